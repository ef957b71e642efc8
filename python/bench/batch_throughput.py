"""`Mechanism.batch` against the Rust batch (the `mechgen batch` command, release build, the
same engine and the same threads): 10 000 six-bar param sets (l1, l2, l3, l5 within 2 % of the
file's) over 36 rows (0°, 10°, …, 350°). Checks that both give the same rows (statuses, and values
to the last digit the CSV writes), then times each (best of `REPEAT` runs; the command's time
includes its start and reading the sets, and writes no rows) and prints the ratio.

Run: `python python/bench/batch_throughput.py [MECHGEN_BIN] [N]` (default target/release/mechgen,
10 000 sets); build the command first (`cargo build --release`)."""

import pathlib
import subprocess
import sys
import tempfile
import time

import numpy as np
import pandas as pd

import mechgen

ROOT = pathlib.Path(__file__).resolve().parents[2]
BIN = sys.argv[1] if len(sys.argv) > 1 else str(ROOT / "target" / "release" / "mechgen")
N = int(sys.argv[2]) if len(sys.argv) > 2 else 10_000
REPEAT = 3
RANGE = ["--from", "0", "--to", "350", "--step", "10"]

m = mechgen.mechanisms()["sixbar"]
rng = np.random.default_rng(11)
sets = {p: m.params[p] * (1 + 0.02 * rng.uniform(-1, 1, N)) for p in ("l1", "l2", "l3", "l5")}

with tempfile.TemporaryDirectory() as tmp:
    tmp = pathlib.Path(tmp)
    pd.DataFrame(sets).to_csv(tmp / "sets.csv", index=False, float_format="%.17g")
    read = pd.read_csv(tmp / "sets.csv")
    sets = {p: read[p].to_numpy() for p in read.columns}

    # The same rows.
    subprocess.run([BIN, "batch", "sixbar", "--params", str(tmp / "sets.csv"), *RANGE,
                    "--csv", str(tmp / "rows.csv")], check=True, capture_output=True)
    want = pd.read_csv(tmp / "rows.csv")
    cols = m.batch(sets, start=0.0, stop=350.0, step=10.0)
    assert cols["status"].shape == (N, 36)
    got = pd.DataFrame({c: v.reshape(-1) for c, v in cols.items()})
    want = want.drop(columns="set")
    assert list(got.columns) == list(want.columns)
    assert (got["status"].astype(str).values == want["status"].astype(str).values).all()
    for c in want.columns:
        if c != "status":
            a, b = got[c].to_numpy(dtype=float), want[c].to_numpy(dtype=float)
            assert ((a == b) | (np.isnan(a) & np.isnan(b))).all(), c
    ok = int((got["status"] == "ok").sum())
    print(f"{N} sets x 36 rows: the same {len(got)} rows ({ok} ok) from Python and the command")

    def best(f):
        times = []
        for _ in range(REPEAT):
            t0 = time.perf_counter()
            f()
            times.append(time.perf_counter() - t0)
        return min(times)

    t_rust = best(lambda: subprocess.run([BIN, "batch", "sixbar", "--params", str(tmp / "sets.csv"),
                                          *RANGE], check=True, capture_output=True))
    t_py = best(lambda: m.batch(sets, start=0.0, stop=350.0, step=10.0))

rows = N * 36
print(f"mechgen batch (Rust):  {t_rust:.3f} s, {t_rust * 1e9 / rows:.0f} ns per row")
print(f"Mechanism.batch:       {t_py:.3f} s, {t_py * 1e9 / rows:.0f} ns per row")
print(f"Python / Rust: {t_py / t_rust:.2f}x")
