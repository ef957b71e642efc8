"""Reference for examples/simulator: the inverted slider-crank of mechanism.toml in closed form at
40 digits (mpmath), at the simulator's times t = i * 0.01 s, i = 0..100, crank angle q1 = 2 pi t.

The pin r e(q1) seen from the pivot (-d, 0) is s e(th): s = |r e(q1) + (d, 0)|, th its angle; the
tip is L e(th) - (d, 0). Rates and accelerations are t-derivatives (mpmath.diff).
Run: python3 reference/make_reference.py > reference/ticks.csv (from examples/simulator).
"""
from mpmath import mp, mpf, cos, sin, atan2, sqrt, diff, pi

mp.dps = 40
r, d, L = mpf("0.12"), mpf("0.3"), mpf("0.5")
omega = 2 * pi


def q1(t):
    return omega * t


def th(t):
    return atan2(r * sin(q1(t)), r * cos(q1(t)) + d)


def s(t):
    return sqrt((r * cos(q1(t)) + d) ** 2 + (r * sin(q1(t))) ** 2)


def tip_x(t):
    return L * cos(th(t)) - d


def tip_y(t):
    return L * sin(th(t))


print("t,q1,th,s,th_vel,s_vel,th_acc,s_acc,Tip_x,Tip_y,Tip_vx,Tip_vy,Tip_ax,Tip_ay")
for i in range(101):
    t = mpf(i) / 100
    cells = [t, q1(t), th(t), s(t), diff(th, t), diff(s, t), diff(th, t, 2), diff(s, t, 2),
             tip_x(t), tip_y(t), diff(tip_x, t), diff(tip_y, t), diff(tip_x, t, 2), diff(tip_y, t, 2)]
    print(",".join(mp.nstr(c, 25) for c in cells))
