"""References for tests/odd-files: every mechanism of mechanism.toml and other.toml from closed
forms written here (independently of mechgen), at 40 digits with mpmath.

Inputs move as x(t) = x + xd t + xdd t^2 / 2 (xd, xdd below); positions are the closed forms at
x(t), velocities and accelerations their first and second t-derivatives at t = 0 (mpmath.diff).
Writes reference/NAME.csv: the inputs, then per unknown u: u, u_vel, u_acc; then per point P:
P_x, P_y, P_vx, P_vy, P_ax, P_ay. Run: python3 reference/make_reference.py (from tests/odd-files).
"""
import os
from mpmath import mp, mpf, sin, cos, asin, atan2, sqrt, diff, pi

mp.dps = 40
XD, XDD = mpf("1.3"), mpf("-0.7")


def slider(r, l):
    """r e(q1) + l e(b) - s = 0, branch cos b > 0: (b, s)."""
    def f(q1):
        b = asin(-r * sin(q1) / l)
        return b, r * cos(q1) + l * cos(b)
    return f


def mech_slider(r, l, points=()):
    f = slider(mpf(r), mpf(l))
    def pos(x):
        b, s = f(x[0])
        pts = [p(x, b, s) for p in points]
        return [b, s], pts
    return pos


def sweep(x):
    r, l, k = mpf("0.3"), mpf("1.0"), mpf("0.5")
    a, ad = slider(r, l)(x[0])
    va = k * ad * ad
    add = k * sin(a)
    return [a, ad, add, va], [(ad + l * cos(a), add + l * sin(a))]


def inputs(x):
    r, l = mpf("0.25"), mpf("0.9")
    b, s_rel = slider(r, l)(x[1])
    return [b, x[0] + s_rel], [(x[0] + r * cos(x[1]), r * sin(x[1]))]


def solve(x):
    l = mpf("1.5")
    a, b = l * cos(x[0]), l * sin(x[0]) ** 2
    return [a, b], [(a, b)]


def four_bar(x):
    l1, l2, l3, l4 = mpf("0.1"), mpf("0.35"), mpf("0.3"), mpf("0.4")
    bx, by = l1 * cos(x[0]), l1 * sin(x[0])
    dx, dy = l4 - bx, -by
    d = sqrt(dx * dx + dy * dy)
    a = (l2 * l2 - l3 * l3 + d * d) / (2 * d)
    h = sqrt(l2 * l2 - a * a)
    px, py = bx + a * dx / d, by + a * dy / d
    cx, cy = px - h * dy / d, py + h * dx / d  # C on the left of B→D: the start's branch
    return [atan2(cy - by, cx - bx), atan2(cy, cx - l4)], [(cx, cy)]


def crank_tip(r):
    return lambda x, b, s: (mpf(r) * cos(x[0]), mpf(r) * sin(x[0]))


MECHS = {
    # name: (positions, rows of inputs)
    "tick": (mech_slider("0.2", "0.7"), None),
    "sweep": (sweep, None),
    "params": (mech_slider("1", "2.5"), None),
    "inputs": (inputs, "two"),
    "solve": (solve, None),
    "generic": (four_bar, None),
    "a_rather_long_mechanism_name_that_goes_on_and_on_to_check_long_identifiers_work":
        (mech_slider("0.15", "0.5", [crank_tip("0.15")]), None),
    "t": (mech_slider("0.2", "0.6"), None),
    "mechgen": (mech_slider("0.1", "0.3"), None),
    "core": (mech_slider("0.3", "0.8"), None),
    "v": (mech_slider("0.25", "0.6", [crank_tip("0.25")]), None),
    "x": (mech_slider("0.1", "0.45"), None),
    "points": (mech_slider("0.35", "1.2", [crank_tip("0.35"), lambda x, b, s: (s, mpf(0))]), None),
    "motion": (mech_slider("0.05", "0.2"), None),
    "std": (mech_slider("0.4", "1.1"), None),
}


def rows(kind):
    for i in range(19):  # 0° to 360° in 20° steps
        q1 = mpf(20 * i) * pi / 180
        yield [q1] if kind is None else [mpf("0.1") + mpf("0.05") * i, q1]


def fmt(v):
    return mp.nstr(v, 25, min_fixed=-5, max_fixed=5)


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    for name, (pos, kind) in MECHS.items():
        lines = []
        for x0 in rows(kind):
            at = lambda t: [xi + XD * t + XDD * t * t / 2 for xi in x0]
            q0, p0 = pos(x0)
            cells = [fmt(v) for v in x0]
            for k in range(len(q0)):
                f = lambda t, k=k: pos(at(t))[0][k]
                cells += [fmt(q0[k]), fmt(diff(f, 0)), fmt(diff(f, 0, 2))]
            for j in range(len(p0)):
                fx = lambda t, j=j: pos(at(t))[1][j][0]
                fy = lambda t, j=j: pos(at(t))[1][j][1]
                cells += [fmt(p0[j][0]), fmt(p0[j][1]), fmt(diff(fx, 0)), fmt(diff(fy, 0)),
                          fmt(diff(fx, 0, 2)), fmt(diff(fy, 0, 2))]
            lines.append(",".join(cells))
        with open(os.path.join(here, name + ".csv"), "w") as out:
            out.write("# x…; per unknown: value, rate, acceleration; per point: x, y, vx, vy, ax, ay\n")
            out.write("\n".join(lines) + "\n")


if __name__ == "__main__":
    main()
