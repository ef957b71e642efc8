"""mechgen's `batch` against pylinkage (https://pypi.org/project/pylinkage/) on the same job: the
compiled-in four-bar (crank l1, coupler l2, rocker l3, ground 0.4) for N param sets (l1, l2, l3
drawn around the file's values), each over one crank turn in 360 rows of 1°: pylinkage's
fastest documented path (`Linkage.step_fast`, its numba-compiled solver; `set_constraints` per
set), against `Mechanism.batch` (every core, the GIL released). Prints the time per
mechanism-step of each and the largest difference of the rocker pin C's position.

pylinkage is not a dependency of the package: install it beside it (`pip install pylinkage`).
Run: `python python/bench/pylinkage_compare.py [N]` (default 10 000)."""

import sys
import time

import numpy as np
import pylinkage as pl

import mechgen

N = int(sys.argv[1]) if len(sys.argv) > 1 else 10_000
ROWS = 360

m = mechgen.mechanisms()["four_bar"]
rng = np.random.default_rng(1)
sets = {p: m.params[p] * (1 + 0.03 * rng.uniform(-1, 1, N)) for p in ("l1", "l2", "l3")}
l4 = m.params["l4"]

# mechgen: one call, rows at 1°, 2°, …, 360° (pylinkage's rows).
t0 = time.perf_counter()
cols = m.batch(sets, start=1.0, stop=360.0, step=1.0)
t_mechgen = time.perf_counter() - t0
assert cols["status"].shape == (N, ROWS)

# pylinkage: one linkage, its constraints set per param set, `step_fast` per set.
A, D = pl.Ground(0.0, 0.0), pl.Ground(l4, 0.0)
crank = pl.Crank(A, radius=sets["l1"][0], angular_velocity=np.deg2rad(1.0), initial_angle=0.0)
start = m.sweep(start=0.0, stop=0.0, step=1.0)
C = pl.RRRDyad(crank, D, distance1=sets["l2"][0], distance2=sets["l3"][0],
               x=float(start["C_x"][0]), y=float(start["C_y"][0]))
linkage = pl.Linkage([A, D, crank, C])
linkage.step_fast(iterations=ROWS)  # numba's compilation, outside the timing
worst, ok = 0.0, 0
t0 = time.perf_counter()
trajectories = []
for s in range(N):
    linkage.set_constraints([sets["l1"][s], sets["l2"][s], sets["l3"][s]])
    crank.set_coord(sets["l1"][s], 0.0)
    C.set_coord(float(cols["C_x"][s][-1]), float(cols["C_y"][s][-1]))
    trajectories.append(linkage.step_fast(iterations=ROWS))
t_pylinkage = time.perf_counter() - t0

for s, t in enumerate(trajectories):
    good = cols["status"][s] == "ok"
    d = np.hypot(t[:, 3, 0] - cols["C_x"][s], t[:, 3, 1] - cols["C_y"][s])[good]
    if d.size and np.isfinite(d).all():
        worst = max(worst, float(d.max()))
        ok += 1

steps = N * ROWS
print(f"{N} four-bar param sets x {ROWS} rows ({steps} mechanism-steps)")
print(f"mechgen batch:        {t_mechgen * 1e9 / steps:10.1f} ns per mechanism-step ({t_mechgen:.3f} s)")
print(f"pylinkage step_fast:  {t_pylinkage * 1e9 / steps:10.1f} ns per mechanism-step ({t_pylinkage:.3f} s)")
print(f"largest |C| difference over {ok} sets solved by both: {worst:.3e}")
