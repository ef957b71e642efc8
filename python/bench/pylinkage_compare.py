"""mechgen against pylinkage (https://pypi.org/project/pylinkage/) the way its users run it: with
numba installed, so that `Linkage.step_fast` and `step_fast_with_kinematics` run its
numba-compiled solver (without numba they fall back to plain Python, about 30x slower). One script,
one machine, versions and load printed.

Two mechanisms, each for N param sets over one crank turn in 360 rows of 1 degree:
- the compiled-in `four_bar` (crank l1, coupler l2, rocker l3, ground l4; l1, l2, l3 within 3 % of
  the file's), mechgen's generated solvers;
- one Strandbeest leg with Jansen's numbers (`strandbeest.toml` beside this script, loaded at run
  time, so mechgen's JIT runs it; every length within 1 % of Jansen's);
- the same leg compiled in, when the package was built with it (its generated solvers, sets in
  SIMD lanes): `cat mechanism.toml python/bench/strandbeest.toml > /tmp/with-leg.toml`, then
  `MECHGEN_MECHANISM=/tmp/with-leg.toml pip install ./python` (the file the package compiles in
  replaces `mechanism.toml`, so it keeps the four-bar).

Timed (best of REPEAT), per mechanism-step:
- pylinkage `step_fast` (positions of every joint) and `step_fast_with_kinematics` (positions,
  velocities, accelerations), one set after another (`set_constraints` per set), one core;
- mechgen `sweep` (one call per set) and `batch` (one call for every set; on one thread and on
  every core; and on one thread into the arrays of its last result, `out=`): positions,
  velocities and accelerations of every unknown and point, the condition estimate and a status
  per row.
Also the largest difference of a joint's position between the two (rocker pin C, foot F) over the
rows both solve.

Run: `python python/bench/pylinkage_compare.py [N]` (default 2000). Needs `pip install pylinkage
numba` beside mechgen."""

import os
import pathlib
import platform
import sys
import time

import numpy as np

try:
    import numba
except ImportError:
    sys.exit("numba is not installed: pylinkage's users run its fast path with it (pip install numba)")
import pylinkage as pl

import mechgen

N = int(sys.argv[1]) if len(sys.argv) > 1 else 2000
ROWS = 360
REPEAT = 3
HERE = pathlib.Path(__file__).resolve().parent


def best(f):
    times = []
    for _ in range(REPEAT):
        t0 = time.perf_counter()
        f()
        times.append(time.perf_counter() - t0)
    return min(times)


def cpu():
    try:
        for line in open("/proc/cpuinfo"):
            if line.startswith("model name"):
                return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor()


def four_bar(rng):
    m = mechgen.mechanisms()["four_bar"]
    sets = {p: m.params[p] * (1 + 0.03 * rng.uniform(-1, 1, N)) for p in ("l1", "l2", "l3")}
    start = m.sweep(start=0.0, stop=0.0, step=1.0)
    A, D = pl.Ground(0.0, 0.0), pl.Ground(m.params["l4"], 0.0)
    crank = pl.Crank(A, radius=sets["l1"][0], angular_velocity=np.deg2rad(1.0), initial_angle=0.0)
    C = pl.RRRDyad(crank, D, distance1=sets["l2"][0], distance2=sets["l3"][0],
                   x=float(start["C_x"][0]), y=float(start["C_y"][0]))
    linkage = pl.Linkage([A, D, crank, C])

    def place(s, cols):
        linkage.set_constraints([sets["l1"][s], sets["l2"][s], sets["l3"][s]])
        crank.set_coord(sets["l1"][s], 0.0)
        C.set_coord(float(cols["C_x"][s][-1]), float(cols["C_y"][s][-1]))

    return m, sets, linkage, crank, place, ("C", 3)


JANSEN = dict(a=38.0, l=7.8, m=15.0, b=41.5, lc=39.3, d=40.1, le=55.8, f=39.4, g=36.7, h=65.7,
              li=49.0, j=50.0, k=61.9)


def strandbeest(rng, compiled=False):
    if compiled:
        m = mechgen.mechanisms()["strandbeest"]
    else:
        m = mechgen.load(str(HERE / "strandbeest.toml"))["strandbeest"]
    sets = {p: v * (1 + 0.01 * rng.uniform(-1, 1, N)) for p, v in JANSEN.items() if p not in ("a", "l")}
    start = m.sweep(start=0.0, stop=0.0, step=1.0)
    at = lambda P: (float(start[f"{P}_x"][0]), float(start[f"{P}_y"][0]))
    O, B = pl.Ground(0.0, 0.0), pl.Ground(-JANSEN["a"], -JANSEN["l"])
    A = pl.Crank(O, radius=sets["m"][0], angular_velocity=np.deg2rad(1.0), initial_angle=0.0)
    C = pl.RRRDyad(A, B, distance1=sets["j"][0], distance2=sets["b"][0], x=at("C")[0], y=at("C")[1])
    L = pl.RRRDyad(A, B, distance1=sets["k"][0], distance2=sets["lc"][0], x=at("L")[0], y=at("L")[1])
    E = pl.RRRDyad(B, C, distance1=sets["d"][0], distance2=sets["le"][0], x=at("E")[0], y=at("E")[1])
    K = pl.RRRDyad(E, L, distance1=sets["f"][0], distance2=sets["g"][0], x=at("K")[0], y=at("K")[1])
    F = pl.RRRDyad(L, K, distance1=sets["li"][0], distance2=sets["h"][0], x=at("F")[0], y=at("F")[1])
    linkage = pl.Linkage([O, B, A, C, L, E, K, F])
    order = [("m",), ("j", "b"), ("k", "lc"), ("d", "le"), ("f", "g"), ("li", "h")]

    def place(s, cols):
        linkage.set_constraints([sets[p][s] for group in order for p in group])
        A.set_coord(sets["m"][s], 0.0)
        for joint, name in [(C, "C"), (L, "L"), (E, "E"), (K, "K"), (F, "F")]:
            joint.set_coord(float(cols[f"{name}_x"][s][-1]), float(cols[f"{name}_y"][s][-1]))

    return m, sets, linkage, A, place, ("F", 7)


def compare(name, build, rng):
    m, sets, linkage, crank, place, (joint, column) = build(rng)
    cols = m.batch(sets, start=1.0, stop=360.0, step=1.0)
    assert cols["status"].shape == (N, ROWS)
    linkage.set_input_velocity(crank, omega=1.0)
    place(0, cols)
    linkage.step_fast(iterations=ROWS)  # numba's compilation, outside the timing
    linkage.step_fast_with_kinematics(iterations=ROWS)

    trajectories = []

    def py_positions():
        trajectories.clear()
        for s in range(N):
            place(s, cols)
            trajectories.append(linkage.step_fast(iterations=ROWS))

    def py_kinematics():
        for s in range(N):
            place(s, cols)
            linkage.step_fast_with_kinematics(iterations=ROWS)

    t_fast = best(py_positions)
    t_kin = best(py_kinematics)
    names = list(sets)
    t_sweep = best(lambda: [m.sweep(start=1.0, stop=360.0, step=1.0,
                                    params={p: float(sets[p][s]) for p in names}) for s in range(N)])
    t_batch1 = best(lambda: m.batch(sets, start=1.0, stop=360.0, step=1.0, threads=1))
    t_batch = best(lambda: m.batch(sets, start=1.0, stop=360.0, step=1.0))
    # Into the arrays of the last result (`out=`): no fresh memory to fault in.
    kept = m.batch(sets, start=1.0, stop=360.0, step=1.0)
    t_reuse = best(lambda: m.batch(sets, start=1.0, stop=360.0, step=1.0, threads=1, out=kept))

    # Sets where the two agree to 1e-6 somewhere but not everywhere follow different branches:
    # pylinkage picks, at each step and each dyad, the intersection nearer the last position, and
    # can pass a dead point onto another assembly; mechgen follows the start's branch and marks the
    # rows past its dead points.
    worst, both, parted = 0.0, 0, 0
    for s, t in enumerate(trajectories):
        good = (cols["status"][s] == "ok") & np.isfinite(t[:, column, 0])
        d = np.hypot(t[:, column, 0] - cols[f"{joint}_x"][s], t[:, column, 1] - cols[f"{joint}_y"][s])[good]
        if d.size and d.max() > 1e-6:
            parted += 1
        elif d.size:
            worst = max(worst, float(d.max()))
            both += int(good.sum())
    steps = N * ROWS
    ns = lambda t: t * 1e9 / steps
    print(f"\n{name} ({m.engine} engine), {N} param sets x {ROWS} rows = {steps} mechanism-steps")
    print(f"  pylinkage step_fast (positions)                 {ns(t_fast):8.1f} ns per step")
    print(f"  pylinkage step_fast_with_kinematics             {ns(t_kin):8.1f} ns per step")
    print(f"  mechgen sweep, one call per set                 {ns(t_sweep):8.1f} ns per step  ({t_sweep / t_fast:.2f}x step_fast)")
    print(f"  mechgen batch, one thread                       {ns(t_batch1):8.1f} ns per step  ({t_batch1 / t_fast:.2f}x step_fast)")
    print(f"  mechgen batch, {os.cpu_count()} threads                        {ns(t_batch):8.1f} ns per step  ({t_batch / t_fast:.2f}x step_fast)")
    print(f"  mechgen batch, one thread, out= the last result {ns(t_reuse):8.1f} ns per step  ({t_reuse / t_fast:.2f}x step_fast)")
    print(f"  largest |{joint}| difference over {both} rows both solve: {worst:.2e}"
          f" ({parted} of {N} sets on different branches)")


def main():
    print(f"python {platform.python_version()}, numpy {np.__version__}, numba {numba.__version__}, "
          f"pylinkage {pl.__version__}")
    print(f"CPU: {cpu()}, {os.cpu_count()} cores, load average {os.getloadavg()[0]:.2f}")
    print("mechgen: positions, velocities, accelerations of every unknown and point, condition, status")
    rng = np.random.default_rng(1)
    compare("four_bar", four_bar, rng)
    compare("strandbeest", strandbeest, rng)
    if "strandbeest" in mechgen.mechanisms():
        compare("strandbeest", lambda rng: strandbeest(rng, compiled=True), rng)


if __name__ == "__main__":
    main()
