"""Reference inverse dynamics of mechanism.toml's `slider_crank` (bodies and gravity as in the
file), computed independently of mechgen: the closed form of the offset slider-crank in the crank
angle t (rod angle q2 = asin((off - r sin t)/l), slider sC = r cos t + l cos q2), the bodies'
positions as mpmath functions of t, their derivatives by mpmath's numerical differentiation at 40
digits, and the effort from Lagrange's equation of the one-degree-of-freedom system:

    Q = M(t) t'' + 1/2 M'(t) t'^2 + V'(t) - F . dP/dt,   M = sum m |dG/dt|^2 + I (dphi/dt)^2

(mechgen sums virtual work over the bodies' accelerations instead). Shaking force and moment from
the bodies' accelerations a_G = G'' w^2 + G' alpha. Writes slider_crank.csv beside this script:
rows at every 15 degrees, for (rate, acc) = (12.5, 0) and (12.5, -40), no load and a load of
(-150, 40) N at the slider C. And slider_crank_flywheel.csv: the flywheel over one turn from 0 at
12.5 rad/s with that load acting over [60, 200] degrees of crank angle, for a speed fluctuation of
0.04: mean effort -F.(P(B) - P(A))/(2 pi) (the energy terms of Q are derivatives of periodic
functions), the work excess W(t) = mean t - (T(t) - T(0) + V(t) - V(0)) + F.(P(min(t, B)) - P(A))
in closed form, its extremes where Q = mean (bisection at 40 digits) or at the load's ends.

Run: python3 make_slider_crank.py  (needs mpmath)
"""

import csv
import os

from mpmath import mp, mpf, sin, cos, asin, sqrt, diff, pi

mp.dps = 40

r, l, off = mpf("0.05"), mpf("0.2"), mpf("0.02")
g = (mpf(0), mpf("-9.81"))
# name: (mass, inertia, com(t) -> (x, y), angle(t))


def q2(t):
    return asin((off - r * sin(t)) / l)


def sC(t):
    return r * cos(t) + l * cos(q2(t))


bodies = [
    (mpf("0.1"), mpf("2e-5"), lambda t: (r / 2 * cos(t), r / 2 * sin(t)), lambda t: t),
    (
        mpf("0.3"),
        mpf("1e-3"),
        lambda t: (r * cos(t) + l / 2 * cos(q2(t)), r * sin(t) + l / 2 * sin(q2(t))),
        q2,
    ),
    (mpf("0.5"), mpf(0), lambda t: (sC(t), off), lambda t: mpf(0)),
]
slider = lambda t: (sC(t), off)


def comp(f, i):
    return lambda t: f(t)[i]


def row(t, w, alpha, force):
    M = mpf(0)
    dM = mpf(0)
    dV = mpf(0)
    T = mpf(0)
    V = mpf(0)
    fx = fy = mom = mpf(0)
    for m, I, G, phi in bodies:
        c = [diff(comp(G, i), t) for i in range(2)]
        cc = [diff(comp(G, i), t, 2) for i in range(2)]
        ccc = [diff(comp(G, i), t, 3) for i in range(2)]
        p1, p2, p3 = diff(phi, t), diff(phi, t, 2), diff(phi, t, 3)
        M += m * (c[0] ** 2 + c[1] ** 2) + I * p1**2
        dM += 2 * m * (c[0] * cc[0] + c[1] * cc[1]) + 2 * I * p1 * p2
        pos = G(t)
        V -= m * (g[0] * pos[0] + g[1] * pos[1])
        dV -= m * (g[0] * c[0] + g[1] * c[1])
        T += (m * (c[0] ** 2 + c[1] ** 2) + I * p1**2) * w**2 / 2
        a = [cc[i] * w**2 + c[i] * alpha for i in range(2)]
        phidd = p2 * w**2 + p1 * alpha
        fx -= m * a[0]
        fy -= m * a[1]
        mom -= pos[0] * m * a[1] - pos[1] * m * a[0] + I * phidd
    cp = [diff(comp(slider, i), t) for i in range(2)]
    Q = M * alpha + dM * w**2 / 2 + dV - (force[0] * cp[0] + force[1] * cp[1])
    return [Q, M, T, V, fx, fy, mom]


here = os.path.dirname(os.path.abspath(__file__))
with open(os.path.join(here, "slider_crank.csv"), "w", newline="") as f:
    out = csv.writer(f)
    out.writerow(
        ["q1_deg", "rate", "acc", "load_x", "load_y", "effort_q1", "inertia_q1_q1",
         "kinetic_energy", "potential_energy", "shaking_fx", "shaking_fy", "shaking_moment"]
    )
    for rate, acc in [(mpf("12.5"), mpf(0)), (mpf("12.5"), mpf(-40))]:
        for force in [(mpf(0), mpf(0)), (mpf(-150), mpf(40))]:
            for deg in range(0, 360, 15):
                t = mpf(deg) * pi / 180
                vals = row(t, rate, acc, force)
                out.writerow(
                    [deg, mp.nstr(rate, 6), mp.nstr(acc, 6), mp.nstr(force[0], 6), mp.nstr(force[1], 6)]
                    + [mp.nstr(v, 30) for v in vals]
                )




def bisect(f, a, b):
    fa = f(a)
    for _ in range(110):
        m = (a + b) / 2
        fm = f(m)
        if (fm < 0) == (fa < 0):
            a, fa = m, fm
        else:
            b = m
    return (a + b) / 2

w = mpf("12.5")
A, B = mpf(60) * pi / 180, mpf(200) * pi / 180
F = (mpf(-150), mpf(40))
delta = mpf("0.04")


def energy(t):
    T = V = mpf(0)
    for m, I, G, phi in bodies:
        c = [diff(comp(G, i), t) for i in range(2)]
        T += (m * (c[0] ** 2 + c[1] ** 2) + I * diff(phi, t) ** 2) * w**2 / 2
        pos = G(t)
        V -= m * (g[0] * pos[0] + g[1] * pos[1])
    return T + V


def load_work(t):
    # F . (P(clamp(t)) - P(A)) for the load acting on [A, B].
    if t <= A:
        return mpf(0)
    e = min(t, B)
    p, pa = slider(e), slider(A)
    return F[0] * (p[0] - pa[0]) + F[1] * (p[1] - pa[1])


mean = -load_work(2 * pi) / (2 * pi)
E0 = energy(mpf(0))


def W(t):
    return mean * t - (energy(t) - E0) + load_work(t)


def effort(t):
    acting = A < t < B
    return row(t, w, mpf(0), F if acting else (mpf(0), mpf(0)))[0]


candidates = [mpf(0), A, B, 2 * pi]
grid = [2 * pi * k / 720 for k in range(721)]
for a, b in zip(grid, grid[1:]):
    fa, fb = mean - effort(a), mean - effort(b)
    if fa * fb < 0 and not (a < A < b) and not (a < B < b):
        candidates.append(bisect(lambda t: mean - effort(t), a, b))
values = [W(t) for t in candidates]
swing = max(values) - min(values)
with open(os.path.join(here, "slider_crank_flywheel.csv"), "w", newline="") as f:
    out = csv.writer(f)
    out.writerow(["mean_effort", "max_energy_fluctuation", "flywheel_inertia"])
    out.writerow([mp.nstr(v, 30) for v in (mean, swing, swing / (delta * w**2))])
