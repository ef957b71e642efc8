"""Reference solutions of the closed-form kernels near their dead points, for
tests/closed_form_dead_points.rs. The kernels' inputs are built here in float (IEEE f64, like
Rust), written with repr (round-trips exactly), and each is solved exactly for those very
doubles with mpmath at 60 digits: the reference is the exact answer of the f64 data, so the
difference measures the kernel's own error. Both modes are written, the `+` mode first (RRP:
A.u >= 0; RPR: s + a >= 0; one angle: w_perp . e >= 0).

    pip install mpmath && python3 make_dead_points.py > dead_points.txt
"""
import math
from mpmath import mp, mpf, sqrt, atan2, acos

mp.dps = 60
DELTAS = [10.0 ** -k for k in range(2, 15)]


def out(kind, delta, inputs, modes):
    vals = " ".join(repr(float(x)) for x in inputs)
    sols = " ".join(mp.nstr(x, 25) for m in modes for x in m)
    print(f"{kind} {mp.nstr(delta, 6)} {vals} {sols}")


def rrp(nominal):
    # K + M e(q) + s u = 0; link 0.7 at the offset 0.4, line along 1.3 e(1.1) at distance
    # (1 - nominal) 0.7 from the centre.
    p, r = 0.7 * math.cos(0.4), 0.7 * math.sin(0.4)
    u = (1.3 * math.cos(1.1), 1.3 * math.sin(1.1))
    ul = math.hypot(*u)
    n = (-u[1] / ul, u[0] / ul)
    dist = 0.7 * (1.0 - nominal)
    d = (n[0] * dist + 0.37 * u[0], n[1] * dist + 0.37 * u[1])
    k = (-d[0], -d[1])
    P, R, U0, U1, D0, D1 = map(mpf, (p, r, u[0], u[1], d[0], d[1]))
    L = sqrt(P * P + R * R)
    uu = U0 * U0 + U1 * U1
    cross = U0 * D1 - U1 * D0
    h2 = L * L - cross * cross / uu
    s0 = (D0 * U0 + D1 * U1) / uu
    w = sqrt(h2 / uu)
    modes = []
    for s in (s0 - w, s0 + w):  # A.u = (s0 - s)|u|^2
        a0, a1 = D0 - s * U0, D1 - s * U1
        # e = M^-1 A, angle = arg(A) - arg(M)
        modes.append((atan2(a1, a0) - atan2(R, P), s))
    delta = 1 - sqrt(cross * cross / uu) / L
    out("rrp", delta, (k[0], k[1], p, r, u[0], u[1]), modes)


def rpr(nominal):
    # K + (M + s N) e(q) = 0; N = 1.2 e(0.3), M / N = 0.15 + 0.4 i, |g| = 0.4 (1 + nominal).
    nx, ny = 1.2 * math.cos(0.3), 1.2 * math.sin(0.3)
    a, b = 0.15, 0.4
    mx, my = nx * a - ny * b, nx * b + ny * a
    x = b * math.sqrt((1.0 + nominal) ** 2 - 1.0)
    q0 = 0.9
    # d = N (x + i b) e^{i q0}
    zx, zy = x * math.cos(q0) - b * math.sin(q0), x * math.sin(q0) + b * math.cos(q0)
    d = (nx * zx - ny * zy, nx * zy + ny * zx)
    k = (-d[0], -d[1])
    NX, NY, MX, MY, D0, D1 = map(mpf, (nx, ny, mx, my, d[0], d[1]))
    nn = NX * NX + NY * NY
    g = ((D0 * NX + D1 * NY) / nn, (D1 * NX - D0 * NY) / nn)
    A, B = (MX * NX + MY * NY) / nn, (MY * NX - MX * NY) / nn
    R2 = g[0] ** 2 + g[1] ** 2
    t = sqrt(R2 - B * B)
    modes = []
    for xx in (t, -t):
        # e^{iq} = g / (x + i b)
        modes.append((atan2(g[1], g[0]) - atan2(B, xx), xx - A))
    delta = sqrt(R2) / abs(B) - 1
    out("rpr", delta, (k[0], k[1], mx, my, nx, ny), modes)


def angle1(nominal):
    # K + P cos q + Q sin q = 0, w = 0.8 e(2.0), -K = |w| (1 - nominal).
    P, Q = 0.8 * math.cos(2.0), 0.8 * math.sin(2.0)
    k = -0.8 * (1.0 - nominal)
    MP, MQ, MK = map(mpf, (P, Q, k))
    R = sqrt(MP * MP + MQ * MQ)
    phi = atan2(MQ, MP)
    gam = acos(-MK / R)
    modes = [(phi + gam, mpf(0)), (phi - gam, mpf(0))]
    delta = 1 + MK / R
    out("angle1", delta, (k, P, Q), modes)


for nominal in DELTAS:
    rrp(nominal)
    rpr(nominal)
    angle1(nominal)
