"""mechgen's `simulate` against MuJoCo (https://pypi.org/project/mujoco/), the simulator most
authors would reach for, on the same four-bar: mechanism.toml's `four_bar` (crank 0.1 m, coupler
0.35 m, rocker 0.3 m, ground 0.4 m; steel bars of 2.4 kg/m and a 0.7 kg coupler), released from
rest at its start configuration under gravity, 10 s. One script, one machine, versions printed.

MuJoCo has no closed loops in its kinematic tree: the crank and the coupler are a chain from the
ground pivot A, the rocker a second chain from D, and the loop is closed at C by an equality
constraint (`connect`), which MuJoCo enforces softly (its default solref/solimp), so the loop can
open. mechgen solves the loop equations at every stage of its integrator (Dormand–Prince 5(4)
with error control, rtol = atol = 1e-12).

Printed per run: wall time per 1 ms of simulated time (a MuJoCo step at timestep 1 ms, one row of
mechgen's at dt = 1 ms), the largest relative drift of the total energy over the 10 s, the largest
loop-closure error (distance between the coupler's C and the rocker's C), and the largest
difference of the crank angle from mechgen's. MuJoCo is run with its default integrator (Euler,
semi-implicit) and with RK4, at timesteps 1 ms and 0.1 ms, with its default (soft) loop and with a
stiff one (time constant twice the timestep, impedance 0.9999: then its first acceleration is
mechgen's to 2e-5).

Run: `python python/bench/mujoco_compare.py`. Needs `pip install mujoco` beside mechgen."""

import math
import os
import platform
import sys
import time

import numpy as np

try:
    import mujoco
except ImportError:
    sys.exit("mujoco is not installed (pip install mujoco)")

import mechgen

T_END = 10.0
# A stiffer loop than MuJoCo's default: the constraint's time constant at twice the timestep (its
# documented lower limit) and an impedance of 0.9999 (default solref 0.02 1, solimp 0.9 0.95).
STIFF = ' solref="{!r} 1" solimp="0.9999 0.9999 0.001"'


def cpu():
    try:
        for line in open("/proc/cpuinfo"):
            if line.startswith("model name"):
                return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or "unknown CPU"


m = mechgen.mechanisms()["four_bar"]
p = m.params
l1, l2, l3, l4 = p["l1"], p["l2"], p["l3"], p["l4"]
q2, q3 = 0.9479697413828936, 1.8959394827657874  # the file's start (crank at 0)
mass = {"crank": 2.4 * l1, "coupler": 0.7, "rocker": 2.4 * l3}
inertia = {"crank": 2.4 * l1**3 / 12, "coupler": 0.0075, "rocker": 2.4 * l3**3 / 12}


def model_xml(integrator, timestep, stiff=False):
    # The mechanism's plane is MuJoCo's x-z plane (gravity along -z); an angle from x towards z
    # is a rotation about -y, so every hinge has axis (0, -1, 0) and a body turned by a about -y
    # has euler (0, -a, 0). The model's zero configuration is the file's start configuration.
    def inertial(name, com):
        i = inertia[name]
        return (f'<inertial pos="{com} 0 0" mass="{mass[name]!r}" '
                f'diaginertia="{i / 100!r} {i!r} {i!r}"/>')

    return f"""
<mujoco model="four_bar">
  <compiler angle="radian"/>
  <option timestep="{timestep!r}" gravity="0 0 -9.81" integrator="{integrator}">
    <flag energy="enable"/>
  </option>
  <worldbody>
    <body name="crank" pos="0 0 0">
      <joint name="q1" type="hinge" axis="0 -1 0"/>
      {inertial("crank", l1 / 2)}
      <body name="coupler" pos="{l1!r} 0 0" euler="0 {-q2!r} 0">
        <joint name="j2" type="hinge" axis="0 -1 0"/>
        {inertial("coupler", l2 / 2)}
      </body>
    </body>
    <body name="rocker" pos="{l4!r} 0 0" euler="0 {-q3!r} 0">
      <joint name="j3" type="hinge" axis="0 -1 0"/>
      {inertial("rocker", l3 / 2)}
    </body>
  </worldbody>
  <equality>
    <connect body1="coupler" body2="rocker" anchor="{l2!r} 0 0"{STIFF.format(2 * timestep) if stiff else ""}/>
  </equality>
</mujoco>"""


def run_mujoco(integrator, timestep, stiff):
    model = mujoco.MjModel.from_xml_string(model_xml(integrator, timestep, stiff))
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    coupler = model.body("coupler").id
    rocker = model.body("rocker").id
    steps = int(round(T_END / timestep))
    every = max(1, int(round(1e-3 / timestep)))
    e0 = data.energy.sum()
    drift = closure = 0.0
    crank = np.empty(steps // every + 1)
    crank[0] = data.qpos[0]
    t0 = time.perf_counter()
    for k in range(1, steps + 1):
        mujoco.mj_step(model, data)
        if k % every == 0:
            crank[k // every] = data.qpos[0]
    wall = time.perf_counter() - t0
    # A second pass for the measurements (so that they do not slow the timed loop).
    mujoco.mj_resetData(model, data)
    mujoco.mj_forward(model, data)
    for k in range(1, steps + 1):
        mujoco.mj_step(model, data)
        drift = max(drift, abs(data.energy.sum() - e0) / abs(e0))
        c1 = data.xpos[coupler] + data.xmat[coupler].reshape(3, 3) @ np.array([l2, 0, 0])
        c2 = data.xpos[rocker] + data.xmat[rocker].reshape(3, 3) @ np.array([l3, 0, 0])
        closure = max(closure, float(np.linalg.norm(c1 - c2)))
    return wall / (T_END / 1e-3), drift, closure, crank


def run_mechgen():
    best = math.inf
    for _ in range(3):
        t0 = time.perf_counter()
        cols = m.simulate(time=T_END, dt=1e-3)
        best = min(best, time.perf_counter() - t0)
    assert (cols["status"] == "ok").all()
    e = cols["kinetic_energy"] + cols["potential_energy"]
    drift = float(np.abs(e - e[0]).max() / abs(e[0]))
    # The loop residual of every row: C from the crank side and from the rocker side.
    q1, q2s, q3s = cols["q1"], cols["q2"], cols["q3"]
    cx = l1 * np.cos(q1) + l2 * np.cos(q2s) - (l4 + l3 * np.cos(q3s))
    cy = l1 * np.sin(q1) + l2 * np.sin(q2s) - l3 * np.sin(q3s)
    closure = float(np.hypot(cx, cy).max())
    return best / len(cols["t"]), drift, closure, cols["q1"]


def main():
    print(f"mechgen {mechgen.__version__ if hasattr(mechgen, '__version__') else '(this checkout)'}, "
          f"mujoco {mujoco.__version__}, numpy {np.__version__}, Python {platform.python_version()}")
    print(f"{cpu()}, {os.cpu_count()} CPUs, load {os.getloadavg()[0]:.2f}")
    print(f"four_bar released from rest under gravity, {T_END:g} s")
    per_ms, drift, closure, ref = run_mechgen()
    rows = [("mechgen simulate (Dormand–Prince 5(4), rtol 1e-12), dt 1 ms", per_ms, drift, closure, 0.0)]
    for integrator, timestep, stiff in [
        ("Euler", 1e-3, False),
        ("RK4", 1e-3, False),
        ("RK4", 1e-4, False),
        ("Euler", 1e-4, True),
        ("RK4", 1e-4, True),
    ]:
        t, d, c, crank = run_mujoco(integrator, timestep, stiff)
        n = min(len(crank), len(ref))
        diff = float(np.abs(crank[:n] - ref[:n]).max())
        loop = "stiff loop" if stiff else "default loop"
        rows.append((f"MuJoCo {integrator}, timestep {timestep * 1e3:g} ms, {loop}", t, d, c, diff))
    print(f"{'':62} {'per 1 ms':>10} {'energy drift':>13} {'loop gap [m]':>13} {'crank vs mechgen [rad]':>23}")
    for name, t, d, c, diff in rows:
        print(f"{name:62} {t * 1e6:>8.2f} us {d:>13.2e} {c:>13.2e} {diff:>23.2e}")


if __name__ == "__main__":
    main()
