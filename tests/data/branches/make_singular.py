#!/usr/bin/env python3
"""Dead-point configurations of the inclined double slider (double_slider.toml), 50 digits.

    python3 tests/data/branches/make_singular.py          # writes double_slider-dead-points.csv
    python3 tests/data/branches/make_singular.py --check  # recomputes and compares

Independent of mechgen: geometry in mpmath. A = (sA, 0); B's line passes through H = (0, h) along
u = e(theta). A dead point is where AB is perpendicular to that line, i.e. the distance of A from
the line equals l: cross(A - H, u) = sA sin(theta) + h cos(theta) = -+l, so
    sA = (-+l - h cos(theta)) / sin(theta),   sB = (A - H) . u,   B = H + sB u,   q = atan2(B - A).
The params are the f64 values the solver is given (deg(60) is the f64 nearest 60 degrees). Checks:
the loop closes (< 1e-45) and det J = 0 (< 1e-45) at both.
"""

import os
import sys

from mpmath import mp, mpf, nstr

mp.dps = 50
HERE = os.path.dirname(os.path.abspath(__file__))

L, H = mpf(0.5), mpf(0.2)
THETA = mpf(float(mp.pi / 3))


def dead_points():
    out = []
    for sign in (-1, 1):
        s, c = mp.sin(THETA), mp.cos(THETA)
        sa = (sign * L - H * c) / s
        sb = sa * c - H * s
        bx, by = sb * c, H + sb * s
        q = mp.atan2(by, bx - sa)
        # the loop sA + l e(q) - (0, h) - sB e(theta) and J = d/d(q, sB)
        rx = sa + L * mp.cos(q) - sb * c
        ry = L * mp.sin(q) - H - sb * s
        det = (-L * mp.sin(q)) * (-s) - (-c) * (L * mp.cos(q))
        assert max(abs(rx), abs(ry), abs(det)) < mpf(10) ** -45
        out.append((sa, q, sb))
    return sorted(out)


def main():
    text = "input,q,sB\n" + "".join(
        ",".join(nstr(v, 45) for v in row) + "\n" for row in dead_points()
    )
    path = os.path.join(HERE, "double_slider-dead-points.csv")
    if "--check" in sys.argv[1:]:
        with open(path) as f:
            assert f.read() == text, "double_slider-dead-points.csv differs"
        print("checked")
    else:
        with open(path, "w") as f:
            f.write(text)
        print(text, end="")


if __name__ == "__main__":
    main()
