#!/usr/bin/env python3
"""Reference values near the dead points of `rocker_four_bar` and `sixbar_g` (mechanism.toml).

    python3 tests/data/stress/make_dead_points.py          # writes the CSVs next to this script
    python3 tests/data/stress/make_dead_points.py --check  # recomputes and compares with the files

Also `NAME_cli.csv`: the rows 1e-6 degree inside each dead point at the inputs a command line gives
in degrees (`mechgen sweep NAME --from D --to D`), converted to radians as the CLI converts them.

Independent of the mechgen crate and of Newton's method: every configuration is written in closed
form (mpmath, 80 significant digits), on the branch of the file's `start` configuration.

  rocker_four_bar  input q1. B = l1 e(q1), D = (l4, 0); the triangle B C D gives q2 and q3 by the
                   cosine rule, with the sign of the start configuration. The dead points are where
                   |BD| = l2 + l3: q1* = +-acos((l1^2 + l4^2 - (l2 + l3)^2) / (2 l1 l4)).
  sixbar_g         input q6, but parametrised by q1 (its natural parameter: with q1 as the driver the
                   six-bar is a crank-rocker plus a dyad, closed form and nonsingular over the whole
                   turn). The four-bar ABCD gives q2, q3; the coupler point E; the dyad G-F-E gives
                   q6(q1) and q5(q1). A dead point of the q6-driven linkage is an extremum of q6(q1):
                   dq6/dq1 = 0, found by findroot from the start (q1 = 0) in each direction.

Configurations at offsets of 1, 1e-2, 1e-4 and 1e-6 degrees inside the reachable range of each dead
point: for the input x = x* -+ offset, the parameter q1 with q6(q1) = x is found by a bracketing
root finder between the dead point and the start. Time derivatives for input rate 1 rad/s and
input acceleration 0: with everything a function u(p) of the parameter p (p = x for the four-bar,
p = q1 for the six-bar) and x = f(p),
    du/dt = u'/f',   d2u/dt2 = (u'' f' - u' f'') / f'^3
(mpmath `diff`, finite differences at several times the working precision).

The params are the f64 values the generated code uses (0.35 is 0.34999999999999997779...), and every
input is rounded to the nearest f64 before the configuration is computed, so the references are the
exact solutions of the problem the f64 solver is given: the comparison measures the solver alone.

Checks done on every run:
  * the loop equations, written out again below, vanish at every configuration (< 1e-60 relative);
  * det J (the Jacobian of the loops with respect to the unknowns, written out by hand) vanishes at
    each dead point relative to the product of its column norms (< 1e-40), and not at the offsets;
  * the rates agree with central differences of the closed-form positions at a second step size;
  * the start configuration of the file is reproduced (branch signs).
"""

import os
import sys

from mpmath import mp, mpf, nstr

mp.dps = 80
HERE = os.path.dirname(os.path.abspath(__file__))
DIGITS = 30
OFFSETS = ["1", "1e-2", "1e-4", "1e-6"]


def f64(v):
    """The f64 nearest to v, exactly, as an mpf."""
    return mpf(float(v))


def e(t):
    return (mp.cos(t), mp.sin(t))


def wrap_near(a, ref):
    """a + 2 pi k nearest to ref."""
    return a + 2 * mp.pi * mp.nint((ref - a) / (2 * mp.pi))


def triangle(px, py, qx, qy, a, b, sign):
    """Angles (of P->X, of X->Q) of the point X with |PX| = a, |XQ| = b; `sign` picks the side."""
    dx, dy = qx - px, qy - py
    r = mp.sqrt(dx * dx + dy * dy)
    cos_p = (a * a + r * r - b * b) / (2 * a * r)
    # exactly 1 at a dead point (up to the last digits)
    assert abs(cos_p) < 1 + mpf(10) ** (10 - mp.dps), "triangle cannot close"
    cos_p = max(-1, min(1, cos_p))
    t = mp.atan2(dy, dx) + sign * mp.acos(cos_p)
    x, y = px + a * mp.cos(t), py + a * mp.sin(t)
    return t, mp.atan2(qy - y, qx - x)


# ---------------------------------------------------------------------------------------------
# rocker_four_bar

class Rocker:
    name = "rocker_four_bar"
    input = "q1"
    unknowns = ["q2", "q3"]
    points = ["B", "C"]
    l1, l2, l3, l4 = f64(0.3), f64(0.35), f64(0.3), f64(0.4)
    start_x = mpf(0)
    start_q = [mpf("0.91833642947681943695"), mpf("1.1863995522992575362")]

    def __init__(self):
        self.sign = pick_sign(lambda s: self.at_param(self.start_x, s)[0], self.start_q)

    def at_param(self, p, sign=None):
        """(unknowns, points as flat x, y list, input) at parameter p = q1."""
        sign = self.sign if sign is None else sign
        bx, by = self.l1 * mp.cos(p), self.l1 * mp.sin(p)
        # B + l2 e(q2) = C, D + l3 e(q3) = C
        q2, back = triangle(bx, by, self.l4, 0, self.l2, self.l3, sign)
        q3 = back + mp.pi   # C -> D is -e(q3)
        cx, cy = self.l4 + self.l3 * mp.cos(q3), self.l3 * mp.sin(q3)
        return [q2, q3], [bx, by, cx, cy], p

    def residual(self, x, q):
        q2, q3 = q
        return [self.l1 * mp.cos(x) + self.l2 * mp.cos(q2) - self.l4 - self.l3 * mp.cos(q3),
                self.l1 * mp.sin(x) + self.l2 * mp.sin(q2) - self.l3 * mp.sin(q3)]

    def jacobian(self, x, q):
        q2, q3 = q
        return [[-self.l2 * mp.sin(q2), self.l3 * mp.sin(q3)],
                [self.l2 * mp.cos(q2), -self.l3 * mp.cos(q3)]]

    def scale(self):
        return self.l4

    def dead_points(self):
        """(side, input, parameter) of the dead points, upper (reached by increasing input) first."""
        c = (self.l1 ** 2 + self.l4 ** 2 - (self.l2 + self.l3) ** 2) / (2 * self.l1 * self.l4)
        a = mp.acos(c)
        return [("upper", a, a), ("lower", -a, -a)]

    def param_of_input(self, x, side, dead_param):
        return x


# ---------------------------------------------------------------------------------------------
# sixbar_g

class SixbarG:
    name = "sixbar_g"
    input = "q6"
    unknowns = ["q1", "q2", "q3", "q5"]
    points = ["E"]
    l1, l2, l3, l4 = f64(26.5), f64(75.0), f64(59.0), f64(87.5)
    l5, l6, l2e = f64(48.4), f64(39.0), f64(65.0)
    xg, yg = f64(153.5), f64(41.7)
    alpha = f64(1.0471975511965976)   # deg(60) as the generated code has it
    start_x = mpf("4.8986008266097007955")
    start_q = [mpf(0), mpf("0.87501726483303908994"), mpf("1.7916766419569741996"),
               mpf("2.0451582702708414973")]

    def __init__(self):
        self.sign4 = pick_sign(lambda s: self.four_bar(mpf(0), s)[0], self.start_q[1:2])
        self.sign_dyad = pick_sign(lambda s: [self.at_param(mpf(0), s)[2]], [self.start_x])

    def four_bar(self, p, sign):
        bx, by = self.l1 * mp.cos(p), self.l1 * mp.sin(p)
        q2, back = triangle(bx, by, self.l4, 0, self.l2, self.l3, sign)
        return [q2, back + mp.pi], bx, by

    def at_param(self, p, sign_dyad=None):
        sign_dyad = self.sign_dyad if sign_dyad is None else sign_dyad
        (q2, q3), bx, by = self.four_bar(p, self.sign4)
        ex = bx + self.l2 * mp.cos(q2) + self.l2e * mp.cos(q2 - self.alpha)
        ey = by + self.l2 * mp.sin(q2) + self.l2e * mp.sin(q2 - self.alpha)
        # G + l6 e(q6) = F, F + l5 e(q5) = E
        q6, q5 = triangle(self.xg, self.yg, ex, ey, self.l6, self.l5, sign_dyad)
        q6 = wrap_near(q6, self.start_x)
        return [p, q2, q3, q5], [ex, ey], q6

    def residual(self, x, q):
        q1, q2, q3, q5 = q
        return [
            self.l1 * mp.cos(q1) + self.l2 * mp.cos(q2) - self.l4 - self.l3 * mp.cos(q3),
            self.l1 * mp.sin(q1) + self.l2 * mp.sin(q2) - self.l3 * mp.sin(q3),
            self.l1 * mp.cos(q1) + self.l2 * mp.cos(q2) + self.l2e * mp.cos(q2 - self.alpha)
            - self.l5 * mp.cos(q5) - self.l6 * mp.cos(x) - self.xg,
            self.l1 * mp.sin(q1) + self.l2 * mp.sin(q2) + self.l2e * mp.sin(q2 - self.alpha)
            - self.l5 * mp.sin(q5) - self.l6 * mp.sin(x) - self.yg,
        ]

    def jacobian(self, x, q):
        q1, q2, q3, q5 = q
        s1, c1 = mp.sin(q1), mp.cos(q1)
        s2, c2 = mp.sin(q2), mp.cos(q2)
        s2a, c2a = mp.sin(q2 - self.alpha), mp.cos(q2 - self.alpha)
        s3, c3 = mp.sin(q3), mp.cos(q3)
        s5, c5 = mp.sin(q5), mp.cos(q5)
        l1, l2, l3, l5, l2e = self.l1, self.l2, self.l3, self.l5, self.l2e
        return [[-l1 * s1, -l2 * s2, l3 * s3, 0],
                [l1 * c1, l2 * c2, -l3 * c3, 0],
                [-l1 * s1, -l2 * s2 - l2e * s2a, 0, l5 * s5],
                [l1 * c1, l2 * c2 + l2e * c2a, 0, -l5 * c5]]

    def scale(self):
        return self.xg

    def q6(self, p):
        return self.at_param(p)[2]

    def dq6(self, p):
        return mp.diff(self.q6, p)

    def dead_points(self):
        out = []
        rising = mp.sign(self.dq6(mpf(0)))
        for side, direction in [("upper", rising), ("lower", -rising)]:
            # walk q1 from the start in 1-degree steps until q6 stops moving in this direction
            step = direction * mp.pi / 180
            a = mpf(0)
            while mp.sign(self.dq6(a + step)) == mp.sign(self.dq6(a)):
                a += step
                assert abs(a) < 2 * mp.pi, "no dead point"
            p = mp.findroot(self.dq6, (a, a + step), solver="anderson")
            assert min(a, a + step) <= p <= max(a, a + step)
            out.append((side, self.q6(p), p))
        return out

    def param_of_input(self, x, side, dead_param):
        """q1 between the start and the dead point with q6(q1) = x."""
        g = lambda p: self.q6(p) - x
        toward_start = -mp.sign(dead_param)
        width = mpf("1e-6")
        while mp.sign(g(dead_param + toward_start * width)) == mp.sign(g(dead_param)):
            width *= 2
            assert width < 1, "no bracket"
        return mp.findroot(g, (dead_param + toward_start * width, dead_param), solver="anderson")


# ---------------------------------------------------------------------------------------------

def pick_sign(fn, want):
    """The branch sign (+1 or -1) whose values match `want` modulo 2 pi."""
    for s in (1, -1):
        got = fn(s)
        if all(abs(wrap_near(g, w) - w) < mpf(10) ** -15 for g, w in zip(got, want)):
            return s
    raise AssertionError("start configuration matches neither branch")


def values_at_param(m, p):
    """Input, unknowns and point coordinates as one flat list of functions of the parameter."""
    q, pts, x = m.at_param(p)
    return [x] + q + pts


def motion(m, p, h=None):
    """Rates d/dt and d2/dt2 for input rate 1 and input acceleration 0, from parameter derivatives."""
    opts = {} if h is None else {"h": h}
    n = len(values_at_param(m, p))
    d1 = [mp.diff(lambda t, i=i: values_at_param(m, t)[i], p, 1, **opts) for i in range(n)]
    d2 = [mp.diff(lambda t, i=i: values_at_param(m, t)[i], p, 2, **opts) for i in range(n)]
    f1, f2 = d1[0], d2[0]
    vel = [d1[i] / f1 for i in range(1, n)]
    acc = [(d2[i] * f1 - d1[i] * f2) / f1 ** 3 for i in range(1, n)]
    return vel, acc


def det_rel(a):
    """det(a) over the product of its column norms (Hadamard: at most 1 in magnitude)."""
    d = mp.det(mp.matrix(a))
    k = len(a)
    norms = [mp.sqrt(sum(a[i][j] ** 2 for i in range(k))) for j in range(k)]
    prod = mpf(1)
    for v in norms:
        prod *= v
    return d / prod


def header(m):
    u = m.unknowns
    cols = ["side", "offset_deg", m.input] + u + [f"{v}_vel" for v in u] + [f"{v}_acc" for v in u]
    for p in m.points:
        cols += [f"{p}_{s}" for s in ["x", "y", "vx", "vy", "ax", "ay"]]
    return cols


def row_at(m, side, label, x, p_dead):
    """The reference row at input x (an f64) on the branch ending at the dead point p_dead."""
    p = m.param_of_input(x, side, p_dead)
    q, pts, x_back = m.at_param(p)
    assert abs(x_back - x) < mpf(10) ** -60, f"{m.name}: input {x_back} != {x}"
    res = max(abs(v) for v in m.residual(x, q)) / m.scale()
    assert res < mpf(10) ** -60, f"{m.name}: residual {res}"
    assert abs(det_rel(m.jacobian(x, q))) > mpf(10) ** -8, f"{m.name}: singular at {label}"
    vel, acc = motion(m, p)
    # the same rates from central differences at an explicit, different step
    vel2, acc2 = motion(m, p, h=mpf(10) ** -25)
    for a, b in zip(vel + acc, vel2 + acc2):
        assert abs(a - b) <= mpf(10) ** -25 * (1 + abs(a)), f"{m.name}: rates {a} {b}"
    nq = len(q)
    qd, qdd = vel[:nq], acc[:nq]
    cols = [side, label, x] + q + qd + qdd
    for k in range(len(m.points)):
        i = nq + 2 * k
        cols += [pts[2 * k], pts[2 * k + 1], vel[i], vel[i + 1], acc[i], acc[i + 1]]
    return cols


def rows(m):
    deads, out = [], []
    for side, x_dead, p_dead in m.dead_points():
        q, _, _ = m.at_param(p_dead)
        dr = det_rel(m.jacobian(x_dead, q))
        assert abs(dr) < mpf(10) ** -40, f"{m.name}: det J = {dr} at the {side} dead point"
        deads.append((side, x_dead))
        direction = 1 if side == "upper" else -1
        for off in OFFSETS:
            x = f64(x_dead - direction * mpf(off) * mp.pi / 180)
            out.append(row_at(m, side, off, x, p_dead))
    return deads, out


def cli_rows(m):
    """Rows 1e-6 degree inside each dead point at the input the command line reaches from a degree
    value: `offset_deg` holds that value (the f64 nearest to the dead point's input in degrees
    minus or plus 1e-6, printed shortest), the input is its f64 conversion to radians exactly as
    Rust's `f64::to_radians` does it (the value times the f64 nearest to pi/180, rounded)."""
    import math
    out = []
    for side, x_dead, p_dead in m.dead_points():
        direction = 1 if side == "upper" else -1
        deg = float(x_dead * 180 / mp.pi - direction * mpf("1e-6"))
        x = mpf(deg * (math.pi / 180.0))
        out.append(row_at(m, side, repr(deg), x, p_dead))
    return out


def fmt(v):
    return v if isinstance(v, str) else nstr(v, DIGITS, min_fixed=-5, max_fixed=5)


def main():
    check = "--check" in sys.argv[1:]
    dead_lines = ["mechanism,side,input,input_deg"]
    files = {}
    for m in (Rocker(), SixbarG()):
        deads, table = rows(m)
        for side, x in deads:
            dead_lines.append(f"{m.name},{side},{fmt(x)},{fmt(x * 180 / mp.pi)}")
        text = ",".join(header(m)) + "\n"
        text += "".join(",".join(fmt(v) for v in r) + "\n" for r in table)
        files[f"{m.name}.csv"] = text
        cli = ",".join(header(m)) + "\n"
        cli += "".join(",".join(fmt(v) for v in r) + "\n" for r in cli_rows(m))
        files[f"{m.name}_cli.csv"] = cli
        print(f"{m.name}: " + ", ".join(f"{s} {nstr(x * 180 / mp.pi, 12)} deg" for s, x in deads))
    files["dead_points.csv"] = "\n".join(dead_lines) + "\n"
    for name, text in files.items():
        path = os.path.join(HERE, name)
        if check:
            with open(path) as f:
                assert f.read() == text, f"{path} differs from the recomputed values"
        else:
            with open(path, "w") as f:
                f.write(text)
    print("checked" if check else "written")


if __name__ == "__main__":
    main()
