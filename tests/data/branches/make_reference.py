#!/usr/bin/env python3
"""Independent branch-identification oracle for `mechgen branches` (issue 13).

    python3 tests/data/branches/make_reference.py            # all mechanisms
    python3 tests/data/branches/make_reference.py sixbar_g   # only the named ones

Written from the mathematics, not from mechgen's code. See README.md (files, columns, checks) and
METHOD.md (the resultant for sixbar_g) next to this script.

Primary method, per input value t (mpmath, 60 significant digits):
  * every loop is a sum of complex exponentials; a loop that closes a triangle (four-bar chain with
    a known diagonal, RRR dyad, slider) reduces to  a cos(th) + b sin(th) = c,  which the half-angle
    substitution x = tan(th/2) turns into the quadratic (c + a) x^2 - 2 b x + (c - a) = 0 whose
    discriminant /4 is a^2 + b^2 - c^2 (negative: no assembly; zero: dead point of that block);
  * sixbar_g (input q6 at G, one 4x4 block): both loops squared give two equations in (q1, q2),
    biquadratic in (x1, x2) = (tan(q1/2), tan(q2/2)); Sylvester's resultant in x2 is a degree-8
    polynomial in x1, divisible by (1 + x1^2) (the two equations share x2 = i at x1 = i); the
    remaining sextic is solved with mpmath.polyroots; x2 follows from the common root of two
    quadratics (linear formula), q3 and q5 from the loops.
Every configuration is substituted into the loop equations as written in mechanism.toml (parsed
with sympy) and must leave a residual < 1e-30.

Second method (completeness): the same configurations are found without polynomials: per block, a
scalar function of one angle (the cut) is sampled on a dense grid, sign changes are bracketed and
refined, every local minimum of |g| without a sign change is minimised (golden section) to catch a
pair of close roots. The counts (and the configurations) must agree with the primary method.
"""

import math
import os
import sys
import time
import tomllib

import mpmath as mp
import sympy as sp

mp.mp.dps = 60
HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.abspath(os.path.join(HERE, '..', '..', '..'))
TOML = os.path.join(ROOT, 'mechanism.toml')

PI = mp.pi
TWO_PI = 2 * mp.pi
RES_TOL = mp.mpf('1e-30')     # loop residual bound for every configuration
OUT_DIGITS = 36                # significant digits in the reference CSVs
CURVE_DIGITS = 10              # significant digits in the plot data


def deg(x):
    return mp.mpf(x) * mp.pi / 180


def wrap(a):
    """principal value in (-pi, pi]"""
    a = mp.fmod(a, TWO_PI)
    if a > PI:
        a -= TWO_PI
    elif a <= -PI:
        a += TWO_PI
    return a


def fmt(x, n=OUT_DIGITS):
    return mp.nstr(mp.mpf(x), n, strip_zeros=False, min_fixed=-4, max_fixed=6)


def log(*a):
    print(*a, flush=True)


# ----------------------------------------------------------------------------------------------
# mechanism.toml: params as exact decimals, loops parsed by sympy for the residual check
# ----------------------------------------------------------------------------------------------

def load_toml():
    with open(TOML, 'rb') as f:
        return tomllib.load(f)['mechanism']


def raw_param_text(name):
    """the param values exactly as written in mechanism.toml (tomllib gives floats)"""
    out, sec = {}, None
    with open(TOML) as f:
        for line in f:
            s = line.split('#')[0].strip()
            if s.startswith('['):
                sec = s
                continue
            if sec == '[mechanism.%s.params]' % name and '=' in s:
                k, v = s.split('=', 1)
                out[k.strip()] = v.strip().strip('"')
    return out


def param_value(text):
    if text.startswith('deg(') and text.endswith(')'):
        return deg(mp.mpf(text[4:-1]))
    return mp.mpf(text)


class Loops:
    """loops of mechanism.toml as sympy expressions; real residuals, Jacobian and det J lambdified"""

    def __init__(self, spec, params):
        self.input = spec['inputs'][0]
        self.unknowns = list(spec['unknowns'])
        self.vars = [sp.Symbol(n, real=True) for n in [self.input] + self.unknowns]
        self.pars = {k: sp.Symbol(k, real=True) for k in params}
        ns = {str(v): v for v in self.vars}
        ns.update({str(k): v for k, v in self.pars.items()})
        ns['e'] = lambda x: sp.exp(sp.I * x)
        ns['c'] = lambda x, y: x + sp.I * y
        ns['deg'] = lambda x: x * sp.pi / 180
        eqs = []
        for s in spec['loops']:
            ex = sp.expand_complex(sp.sympify(eval(s, {'__builtins__': {}}, ns)))
            eqs += [sp.re(ex), sp.im(ex)]
        self.eqs = eqs
        J = sp.Matrix(eqs).jacobian(self.vars[1:])
        self.detJ = J.det(method='berkowitz')
        G = sp.Matrix(eqs + [self.detJ])
        JG = G.jacobian(self.vars)
        args = self.vars + list(self.pars.values())
        self.pvals = [params[k] for k in self.pars]
        self.f_eqs = sp.lambdify(args, eqs, modules='mpmath')
        self.f_det = sp.lambdify(args, self.detJ, modules='mpmath')
        self.f_G = sp.lambdify(args, list(G), modules='mpmath')
        self.f_JG = sp.lambdify(args, JG.tolist(), modules='mpmath')
        # column scale for a relative det J: product of column norms of J
        self.f_J = sp.lambdify(args, J.tolist(), modules='mpmath')

    def residual(self, t, u):
        return max(abs(v) for v in self.f_eqs(t, *u, *self.pvals))

    def det_rel(self, t, u):
        J = self.f_J(t, *u, *self.pvals)
        n = len(J)
        scale = mp.mpf(1)
        for j in range(n):
            scale *= mp.sqrt(sum(J[i][j] ** 2 for i in range(n)))
        return self.f_det(t, *u, *self.pvals) / scale

    def refine_dead_point(self, t0, u0):
        """Newton on loops = 0, det J = 0 in (t, u) (analytic Jacobian of the extended system)"""
        x = mp.matrix([t0] + list(u0))
        for it in range(60):
            G = mp.matrix(self.f_G(*x, *self.pvals))
            JG = mp.matrix(self.f_JG(*x, *self.pvals))
            dx = mp.lu_solve(JG, G)
            x = x - dx
            if mp.norm(dx) < mp.mpf(10) ** (-mp.mp.dps + 5):
                break
        return x[0], [x[i] for i in range(1, len(x))]


# ----------------------------------------------------------------------------------------------
# building blocks
# ----------------------------------------------------------------------------------------------

def half_angle_solve(a, b, c):
    """all th in (-pi, pi] with a cos th + b sin th = c, via x = tan(th/2):
    (c + a) x^2 - 2 b x + (c - a) = 0.  Returns (roots, normalised discriminant (a^2+b^2-c^2)/(a^2+b^2))."""
    A, C = c + a, c - a
    disc = a * a + b * b - c * c
    nd = disc / (a * a + b * b)
    if disc < 0:
        return [], nd
    sq = mp.sqrt(disc)
    out = []
    for s in (1, -1):
        # x = (b + s sq)/A = (c - a)/(b - s sq): use the better conditioned quotient
        num1, den1 = b + s * sq, A
        num2, den2 = C, b - s * sq
        num, den = (num1, den1) if abs(den1) >= abs(den2) else (num2, den2)
        out.append(PI if den == 0 else wrap(2 * mp.atan(num / den)))
    return out, nd


def golden_min(f, a, b, iters=160):
    g = (mp.sqrt(5) - 1) / 2
    c, d = b - g * (b - a), a + g * (b - a)
    fc, fd = f(c), f(d)
    for _ in range(iters):
        if fc < fd:
            b, d, fd = d, c, fc
            c = b - g * (b - a)
            fc = f(c)
        else:
            a, c, fc = c, d, fd
            d = a + g * (b - a)
            fd = f(d)
    return (c, fc) if fc < fd else (d, fd)


def bisect_root(f, a, b, fa=None):
    fa = f(a) if fa is None else fa
    for _ in range(mp.mp.prec + 20):
        m = (a + b) / 2
        if m == a or m == b:
            break
        fm = f(m)
        if fm == 0:
            return m
        if (fm > 0) == (fa > 0):
            a, fa = m, fm
        else:
            b = m
    return (a + b) / 2


def bracket_roots(g, N=720, lo=None):
    """every zero of the 2pi-periodic g on [lo, lo + 2pi): sign changes on an N-point grid, and every
    local minimum of |g| without a sign change minimised by golden section (a pair of close zeros
    shows as a negative minimum of sign*g).  Refinement by bisection to full precision."""
    lo = -PI if lo is None else lo
    ts = [lo + TWO_PI * k / N for k in range(N)]
    gs = [g(t) for t in ts]
    roots = []
    for k in range(N):
        t0, t1 = ts[k], ts[k] + TWO_PI / N
        g0, g1 = gs[k], gs[(k + 1) % N]
        if g0 == 0:
            roots.append(t0)
        elif (g0 > 0) != (g1 > 0) and g1 != 0:
            roots.append(bisect_root(g, t0, t1, g0))
    for k in range(N):
        gm, g0, gp = gs[k - 1], gs[k], gs[(k + 1) % N]
        if (gm > 0) == (g0 > 0) == (gp > 0) and abs(g0) <= abs(gm) and abs(g0) <= abs(gp):
            s = 1 if g0 > 0 else -1
            a, b = ts[k] - TWO_PI / N, ts[k] + TWO_PI / N
            tm, fm = golden_min(lambda t: s * g(t), a, b)
            if fm < 0:
                roots.append(bisect_root(g, a, tm))
                roots.append(bisect_root(g, tm, b))
            elif fm == 0:
                roots.append(tm)
    return sorted(wrap(r) for r in roots)


def poly_mul(p, q):
    """ascending coefficient lists"""
    r = [mp.mpf(0)] * (len(p) + len(q) - 1)
    for i, a in enumerate(p):
        for j, b in enumerate(q):
            r[i + j] += a * b
    return r


def poly_sub(p, q):
    n = max(len(p), len(q))
    return [(p[i] if i < len(p) else 0) - (q[i] if i < len(q) else 0) for i in range(n)]


def poly_div_1px2(p):
    """divide an ascending polynomial by (1 + x^2); returns (quotient, remainder (r0, r1))"""
    p = list(p)
    n = len(p) - 1
    q = [mp.mpf(0)] * (n - 1)
    for k in range(n, 1, -1):
        q[k - 2] = p[k]
        p[k] -= p[k]
        p[k - 2] -= q[k - 2]
    return q, (p[0], p[1])


def biquad_coeffs(K):
    """K0 + K1 cos q1 + K2 sin q1 + K3 cos q2 + K4 sin q2 + K5 cos(q1-q2) + K6 sin(q1-q2), times
    (1+x1^2)(1+x2^2), as coefficients of x2^0, x2^1, x2^2, each an ascending quadratic in x1"""
    K0, K1, K2, K3, K4, K5, K6 = K
    X0 = [K0 + K1 + K3 + K5, 2 * K2 + 2 * K6, K0 - K1 + K3 - K5]
    X1 = [2 * K4 - 2 * K6, 4 * K5, 2 * K4 + 2 * K6]
    X2 = [K0 + K1 - K3 - K5, 2 * K2 - 2 * K6, K0 - K1 - K3 + K5]
    return X0, X1, X2


def resultant_x2(A, B):
    """Sylvester resultant in x2 of A0 + A1 x2 + A2 x2^2 and B0 + B1 x2 + B2 x2^2 (4x4 determinant in
    Bezout form): (A2 B0 - A0 B2)^2 - (A2 B1 - A1 B2)(A1 B0 - A0 B1)"""
    A0, A1, A2 = A
    B0, B1, B2 = B
    p = poly_sub(poly_mul(A2, B0), poly_mul(A0, B2))
    q = poly_sub(poly_mul(A2, B1), poly_mul(A1, B2))
    r = poly_sub(poly_mul(A1, B0), poly_mul(A0, B1))
    return poly_sub(poly_mul(p, p), poly_mul(q, r))


def peval(p, x):
    return mp.polyval(list(reversed(p)), x)


# ----------------------------------------------------------------------------------------------
# mechanisms: primary solver (polynomial), second solver (bracketing), margin for missed folds
# ----------------------------------------------------------------------------------------------

class Mechanism:
    kinds = None          # 'angle' / 'length' per unknown

    def __init__(self, name, spec):
        self.name = name
        self.spec = spec
        self.raw = raw_param_text(name)
        self.p = {k: param_value(v) for k, v in self.raw.items()}
        self.loops = Loops(spec, self.p)
        self.input = spec['inputs'][0]
        self.unknowns = list(spec['unknowns'])
        self.lscale = max(abs(v) for k, v in self.p.items() if k not in ('alpha', 'beta'))

    # subclasses: solve(t) -> (configs, margin); solve2(t) -> configs

    def dist(self, u, v):
        d = 0
        for k, a, b in zip(self.kinds, u, v):
            x = abs(wrap(a - b)) if k == 'angle' else abs(a - b) / self.lscale
            d = max(d, x)
        return d

    def verified(self, t, configs):
        for u in configs:
            r = self.loops.residual(t, u)
            if not r < RES_TOL * max(1, self.lscale):
                raise RuntimeError('%s: residual %s at t=%s u=%s' % (self.name, r, t, u))
        return configs


class FourBar(Mechanism):
    """l1 e(q1) + l2 e(q2) - l4 - l3 e(q3) = 0, input q1, unknowns q2, q3"""
    kinds = ('angle', 'angle')

    def modes(self, q1):
        p = self.p
        d = p['l1'] * mp.expj(q1) - p['l4']           # B - D
        # l2 e(q2) = l3 e(q3) - d  =>  2 l3 (dx cos q3 + dy sin q3) = l3^2 + |d|^2 - l2^2
        q3s, nd = half_angle_solve(2 * p['l3'] * d.real, 2 * p['l3'] * d.imag,
                                   p['l3'] ** 2 + abs(d) ** 2 - p['l2'] ** 2)
        return [(mp.arg(p['l3'] * mp.expj(q3) - d), q3) for q3 in q3s], nd

    def solve(self, t):
        cfg, nd = self.modes(t)
        return self.verified(t, cfg), abs(nd)

    def bracket_modes(self, t):
        p = self.p
        d = p['l1'] * mp.expj(t) - p['l4']
        g = lambda q3: abs(p['l3'] * mp.expj(q3) - d) ** 2 - p['l2'] ** 2
        return [(mp.arg(p['l3'] * mp.expj(q3) - d), q3) for q3 in bracket_roots(g)]

    def solve2(self, t):
        return self.verified(t, FourBar.bracket_modes(self, t))

    def analytic_dead_points(self):
        """law of cosines: the coupler and the rocker in line, |BD| = l2 + l3 or |l2 - l3|"""
        p = self.p
        out = []
        for L in (p['l2'] + p['l3'], abs(p['l2'] - p['l3'])):
            c = (p['l1'] ** 2 + p['l4'] ** 2 - L ** 2) / (2 * p['l1'] * p['l4'])
            if abs(c) <= 1:
                a = mp.acos(c)
                out += [a, -a]
        return sorted(out)


class SixBar(Mechanism):
    """four-bar ABCD (input q1) + dyad E-F-G; unknowns q2, q3, q5, q6"""
    kinds = ('angle',) * 4

    def E(self, q1, q2):
        p = self.p
        return p['l1'] * mp.expj(q1) + p['l2'] * mp.expj(q2) + p['l2e'] * mp.expj(q2 - p['alpha'])

    def G(self):
        return mp.mpc(self.p['xg'], self.p['yg'])

    def solve(self, t):
        p = self.p
        fb, nd = FourBar.modes(self, t)
        margin = abs(nd)
        out = []
        for q2, q3 in fb:
            h = self.E(t, q2) - self.G()
            # l5 e(q5) = h - l6 e(q6)  =>  2 l6 (hx cos q6 + hy sin q6) = |h|^2 + l6^2 - l5^2
            q6s, nd6 = half_angle_solve(2 * p['l6'] * h.real, 2 * p['l6'] * h.imag,
                                        abs(h) ** 2 + p['l6'] ** 2 - p['l5'] ** 2)
            margin = min(margin, abs(nd6))
            for q6 in q6s:
                out.append((q2, q3, mp.arg(h - p['l6'] * mp.expj(q6)), q6))
        return self.verified(t, out), margin

    def solve2(self, t):
        p = self.p
        out = []
        for q2, q3 in FourBar.bracket_modes(self, t):
            h = self.E(t, q2) - self.G()
            g = lambda q6: abs(h - p['l6'] * mp.expj(q6)) ** 2 - p['l5'] ** 2
            for q6 in bracket_roots(g):
                out.append((q2, q3, mp.arg(h - p['l6'] * mp.expj(q6)), q6))
        return self.verified(t, out)

    def resultant_dead_points(self):
        """dyad E-F-G singular: |E - G| = l5 + l6 or |l5 - l6|, E on the four-bar's coupler.
        Same resultant as sixbar_g with F -> G and l5 -> l5 +- l6: sextic in x1 = tan(q1/2)."""
        p = self.p
        out = []
        for L, sgn in ((p['l5'] + p['l6'], 1), (abs(p['l5'] - p['l6']), -1)):
            for q1, q2, q3 in coupler_circle_points(p, self.G(), L):
                h = self.E(q1, q2) - self.G()
                a = mp.arg(h)
                # stretched: q5 = q6 = arg h; folded: the longer link points along h
                if sgn == 1:
                    q5, q6 = a, a
                elif p['l5'] >= p['l6']:
                    q5, q6 = a, wrap(a + PI)
                else:
                    q5, q6 = wrap(a + PI), a
                out.append((q1, (q2, q3, q5, q6)))
        return sorted(out, key=lambda r: r[0])


def sixbar_K(p, F, L5):
    """K coefficients of f1 = |l1 e1 + l2 e2 - l4|^2 - l3^2 and f2 = |l1 e1 + w e2 - F|^2 - L5^2,
    w = l2 + l2e e(-alpha), in the basis 1, cos q1, sin q1, cos q2, sin q2, cos(q1-q2), sin(q1-q2)"""
    l1, l2, l3, l4 = p['l1'], p['l2'], p['l3'], p['l4']
    K1 = (l1 ** 2 + l2 ** 2 + l4 ** 2 - l3 ** 2, -2 * l1 * l4, 0, -2 * l2 * l4, 0, 2 * l1 * l2, 0)
    w = l2 + p['l2e'] * mp.expj(-p['alpha'])
    u = w * mp.conj(F)
    K2 = (l1 ** 2 + abs(w) ** 2 + abs(F) ** 2 - L5 ** 2, -2 * l1 * F.real, -2 * l1 * F.imag,
          -2 * u.real, 2 * u.imag, 2 * l1 * w.real, 2 * l1 * w.imag)
    return K1, K2, w


def coupler_circle_sextic(p, F, L5):
    K1, K2, w = sixbar_K(p, F, L5)
    A, B = biquad_coeffs(K1), biquad_coeffs(K2)
    R = resultant_x2(A, B)                       # degree 8 in x1
    S, rem = poly_div_1px2(R)                    # R = (1 + x1^2) S
    scale = max(abs(c) for c in R)
    assert abs(rem[0]) < scale * mp.mpf('1e-50') and abs(rem[1]) < scale * mp.mpf('1e-50'), rem
    return S, A, B, R


def coupler_circle_points(p, F, L5, want_margin=False):
    """every (q1, q2, q3) with the four-bar closed and |E - F| = L5: the real roots of the sextic"""
    S, A, B, R = coupler_circle_sextic(p, F, L5)
    while abs(S[-1]) < mp.mpf('1e-40') * max(abs(c) for c in S):
        raise RuntimeError('root at x1 = infinity (q1 = pi): choose another input')
    roots, err = mp.polyroots(list(reversed(S)), maxsteps=400, extraprec=400, error=True)
    scale = max(1, max(abs(r) for r in roots))
    out, margin = [], mp.inf
    for i, r in enumerate(roots):
        for s in roots[i + 1:]:
            margin = min(margin, abs(r - s) / (1 + abs(r) + abs(s)))
    for r in roots:
        if abs(mp.im(r)) > mp.mpf('1e-35') * (1 + abs(r)):
            continue
        x1 = mp.re(r)
        q1 = 2 * mp.atan(x1)
        a = [peval(c, x1) for c in A]
        b = [peval(c, x1) for c in B]
        # common root of the two quadratics in x2: (A1 B2 - A2 B1) x2 = A2 B0 - A0 B2
        den = a[1] * b[2] - a[2] * b[1]
        num = a[2] * b[0] - a[0] * b[2]
        cands = []
        if abs(den) > mp.mpf('1e-25') * (abs(num) + abs(den)):
            x2 = num / den
            cands.append(2 * mp.atan(x2))
        else:   # both roots common (degenerate): take the four-bar's two modes
            cands = [q2 for q2, _ in FourBar.modes(_P(p), q1)[0]]
        for q2 in cands:
            C = p['l1'] * mp.expj(q1) + p['l2'] * mp.expj(q2) - p['l4']
            out.append((wrap(q1), wrap(q2), mp.arg(C)))
    if want_margin:
        return out, margin
    return out


class _P:
    def __init__(self, p):
        self.p = p


class SixBarG(SixBar):
    """input q6; unknowns q1, q2, q3, q5; one 4x4 block: resultant in x1"""

    def F(self, q6):
        return self.G() + self.p['l6'] * mp.expj(q6)

    def solve(self, t):
        F = self.F(t)
        pts, margin = coupler_circle_points(self.p, F, self.p['l5'], want_margin=True)
        out = []
        for q1, q2, q3 in pts:
            out.append((q1, q2, q3, mp.arg(self.E(q1, q2) - F)))
        return self.verified(t, sorted(out)), margin

    def fourbar_mode(self, q1, sigma):
        """the four-bar's assembly mode sigma = +-1 by the cosine rule in the triangle B C D
        (continuous in q1 for a crank-rocker: C never on the line BD)"""
        p = self.p
        B = p['l1'] * mp.expj(q1)
        v = p['l4'] - B                         # B -> D
        rho = abs(v)
        beta = mp.acos((p['l2'] ** 2 + rho ** 2 - p['l3'] ** 2) / (2 * p['l2'] * rho))
        q2 = mp.arg(v) + sigma * beta
        q3 = mp.arg(B + p['l2'] * mp.expj(q2) - p['l4'])
        return wrap(q2), q3

    def solve2(self, t):
        F = self.F(t)
        out = []
        for sigma in (1, -1):
            def g(q1):
                q2, _ = self.fourbar_mode(q1, sigma)
                return abs(self.E(q1, q2) - F) ** 2 - self.p['l5'] ** 2
            for q1 in bracket_roots(g):
                q2, q3 = self.fourbar_mode(q1, sigma)
                out.append((q1, q2, q3, mp.arg(self.E(q1, q2) - F)))
        return self.verified(t, sorted(out))

    def q6_of_q1(self, q1, sigma, tau):
        """the analytic parametrisation by the crank angle: four-bar mode sigma, dyad mode tau"""
        p = self.p
        q2, q3 = self.fourbar_mode(q1, sigma)
        h = self.E(q1, q2) - self.G()
        rho = abs(h)
        c = (p['l6'] ** 2 + rho ** 2 - p['l5'] ** 2) / (2 * p['l6'] * rho)
        if abs(c) > 1:
            return None
        return mp.arg(h) + tau * mp.acos(c)


class SliderCrank(Mechanism):
    """r e(q1) + l e(q2) - sC - i off = 0; unknowns q2, sC"""
    kinds = ('angle', 'length')

    def solve(self, t):
        p = self.p
        # imaginary part: l sin q2 = off - r sin q1
        q2s, nd = half_angle_solve(0, p['l'], p['off'] - p['r'] * mp.sin(t))
        out = [(q2, p['r'] * mp.cos(t) + p['l'] * mp.cos(q2)) for q2 in q2s]
        return self.verified(t, out), abs(nd)

    def solve2(self, t):
        p = self.p
        g = lambda q2: p['r'] * mp.sin(t) + p['l'] * mp.sin(q2) - p['off']
        return self.verified(t, [(q2, p['r'] * mp.cos(t) + p['l'] * mp.cos(q2)) for q2 in bracket_roots(g)])


class Shaper(Mechanism):
    """s3 e(q3) = l1 e(q1) + i lAC;  l3 e(q3) + l4 e(q4) = sE + i yE; unknowns s3, q3, q4, sE"""
    kinds = ('length', 'angle', 'angle', 'length')

    def solve(self, t):
        p = self.p
        v = p['l1'] * mp.expj(t) + mp.mpc(0, p['lAC'])
        # Im(v e(-q3)) = 0: vy cos q3 - vx sin q3 = 0 (s3 may be negative: guide bar reversed)
        q3s, nd = half_angle_solve(v.imag, -v.real, 0)
        margin = abs(nd)
        out = []
        for q3 in q3s:
            s3 = mp.re(v * mp.expj(-q3))
            q4s, nd4 = half_angle_solve(0, p['l4'], p['yE'] - p['l3'] * mp.sin(q3))
            margin = min(margin, abs(nd4))
            for q4 in q4s:
                out.append((s3, q3, q4, p['l3'] * mp.cos(q3) + p['l4'] * mp.cos(q4)))
        return self.verified(t, out), margin

    def solve2(self, t):
        p = self.p
        v = p['l1'] * mp.expj(t) + mp.mpc(0, p['lAC'])
        out = []
        for q3 in bracket_roots(lambda q3: mp.im(v * mp.expj(-q3))):
            s3 = mp.re(v * mp.expj(-q3))
            g = lambda q4: p['l3'] * mp.sin(q3) + p['l4'] * mp.sin(q4) - p['yE']
            for q4 in bracket_roots(g):
                out.append((s3, q3, q4, p['l3'] * mp.cos(q3) + p['l4'] * mp.cos(q4)))
        return self.verified(t, out)


# ----------------------------------------------------------------------------------------------
# dead points: count changes on a grid, bisection, Newton on (loops, det J) = 0
# ----------------------------------------------------------------------------------------------

def scan(m, N):
    ts = [-PI + TWO_PI * k / N for k in range(N)]
    counts, margins = [], []
    for t in ts:
        c, mg = m.solve(t)
        counts.append(len(c))
        margins.append(mg)
    return ts, counts, margins


def closest_pair(m, cfgs):
    best = None
    for i in range(len(cfgs)):
        for j in range(i + 1, len(cfgs)):
            d = m.dist(cfgs[i], cfgs[j])
            if best is None or d < best[0]:
                best = (d, cfgs[i], cfgs[j])
    return best


def find_dead_points(m, N=1440):
    """returns dead points [(t, u)], and a report of the completeness checks"""
    ts, counts, margins = scan(m, N)
    h = TWO_PI / N
    dead, notes = [], []
    brackets = []
    for k in range(N):
        c0, c1 = counts[k], counts[(k + 1) % N]
        if c0 != c1:
            if abs(c0 - c1) != 2:
                raise RuntimeError('%s: count jumps by %d in one cell' % (m.name, c1 - c0))
            brackets.append((ts[k], ts[k] + h, c0, c1))
    # local minima of the margin (normalised discriminant / root separation) away from count changes
    hidden = []
    for k in range(N):
        if margins[k] <= margins[k - 1] and margins[k] <= margins[(k + 1) % N]:
            if counts[k - 1] == counts[k] == counts[(k + 1) % N]:
                tm, fm = golden_min(lambda t: m.solve(t)[1], ts[k] - h, ts[k] + h, iters=80)
                cm = len(m.solve(tm)[0])
                hidden.append((tm, fm, cm))
                if cm != counts[k]:
                    raise RuntimeError('%s: hidden pair of dead points near %s' % (m.name, tm))
    for a, b, ca, cb in brackets:
        for _ in range(34):   # bisection on the count to ~1e-12 rad
            mid = (a + b) / 2
            cm = len(m.solve(mid)[0])
            if cm == ca:
                a = mid
            else:
                b = mid
        t_big = a if ca > cb else b
        cfg = m.solve(t_big)[0]
        _, u1, u2 = closest_pair(m, cfg)
        u0 = [x + (wrap(y - x) / 2 if k == 'angle' else (y - x) / 2) for k, x, y in zip(m.kinds, u1, u2)]
        t, u = m.loops.refine_dead_point(t_big, u0)
        t = wrap(t)
        u = [wrap(x) if k == 'angle' else x for k, x in zip(m.kinds, u)]
        res = m.loops.residual(t, u)
        drel = m.loops.det_rel(t, u)
        assert res < RES_TOL and abs(drel) < mp.mpf('1e-40'), (res, drel)
        assert abs(t - (a + b) / 2) < mp.mpf('1e-9')
        # the count changes by 2 across t, and the merging pair is close to u on the big side
        eps = deg('1e-6')
        cl, cr = len(m.solve(t - eps)[0]), len(m.solve(t + eps)[0])
        assert abs(cl - cr) == 2, (cl, cr)
        dead.append((t, u, res, drel, cl, cr))
    dead.sort(key=lambda r: r[0])
    return dead, hidden, counts


# ----------------------------------------------------------------------------------------------
# tracing: circuits and branches
# ----------------------------------------------------------------------------------------------

class Trace:
    def __init__(self, m, dead, extra_inputs, step_deg=1, dmin=mp.mpf('1e-10')):
        self.m = m
        self.solves = 0
        h = deg(step_deg)
        cuts = []
        for t, u, *_ in dead:
            if not cuts or abs(t - cuts[-1][0]) > mp.mpf('1e-30'):
                cuts.append([t, []])
            cuts[-1][1].append(u)
        self.has_dead = bool(cuts)
        if not cuts:
            cuts = [[deg('-177.5'), []]]   # an artificial cut (no dead point): a seam off the grids
        self.cuts = cuts
        n = len(cuts)
        self.intervals = []
        for i in range(n):
            a = cuts[i][0]
            b = cuts[i + 1][0] if i + 1 < n else cuts[0][0] + TWO_PI
            L = b - a
            ts = set()
            k0 = int(mp.ceil((a + PI) / h))
            k = k0
            while True:
                t = -PI + k * h
                if t >= b:
                    break
                if t > a:
                    ts.add(t)
                k += 1
            for x in extra_inputs:
                for s in (x - TWO_PI, x, x + TWO_PI):
                    if a < s < b:
                        ts.add(s)
            D = min(h, L / 4)
            while D > dmin:
                ts.add(a + D)
                ts.add(b - D)
                D /= 2
            ts.add(a + dmin)
            ts.add(b - dmin)
            ts.add(a + L / 2)
            ts0, ts = sorted(ts), []
            for t in ts0:
                if not ts or t - ts[-1] > mp.mpf('1e-40'):
                    ts.append(t)
            tracks = self.track(ts)
            self.intervals.append((a, b, tracks))
        self.link()

    def solve(self, t):
        self.solves += 1
        return self.m.solve(wrap(t))[0]

    def track(self, ts):
        m = self.m
        first = self.solve(ts[0])
        tracks = [[(ts[0], u)] for u in first]
        i = 1
        pending = list(ts[1:])
        while pending:
            t = pending[0]
            cfg = self.solve(t)
            if len(cfg) != len(tracks):
                raise RuntimeError('%s: count changes inside an interval at %s' % (m.name, t))
            ok, assign = self.match(tracks, t, cfg)
            if not ok:
                tp = tracks[0][-1][0]
                pending.insert(0, (tp + t) / 2)
                if t - tp < mp.mpf('1e-25'):
                    raise RuntimeError('cannot match')
                continue
            for tr, k in zip(tracks, assign):
                tr.append((t, cfg[k]))
            pending.pop(0)
        return tracks

    def predict(self, tr, t):
        m = self.m
        if len(tr) < 2:
            return tr[-1][1]
        (t0, u0), (t1, u1) = tr[-2], tr[-1]
        r = (t - t1) / (t1 - t0)
        return [x1 + (wrap(x1 - x0) if k == 'angle' else (x1 - x0)) * r
                for k, x0, x1 in zip(m.kinds, u0, u1)]

    def match(self, tracks, t, cfg):
        m = self.m
        assign = []
        for tr in tracks:
            p = self.predict(tr, t)
            d = sorted((m.dist(p, u), k) for k, u in enumerate(cfg))
            if len(d) > 1 and not d[0][0] < mp.mpf('0.3') * d[1][0]:
                return False, None
            # the step must also be small against the separation from the other tracks
            assign.append(d[0][1])
        if len(set(assign)) != len(assign):
            return False, None
        return True, assign

    def link(self):
        m = self.m
        n = len(self.intervals)
        parent = {}

        def find(x):
            while parent.setdefault(x, x) != x:
                x = parent[x]
            return x

        self.cont = {}       # (i, j) -> (i+1, k) continuation across cut i+1
        self.folds = []      # (cut index, node1, node2, dead config)
        for i in range(n):
            inext = (i + 1) % n
            cut = self.cuts[inext]
            left = [(j, tr[-1][1]) for j, tr in enumerate(self.intervals[i][2])]
            right = [(k, tr[0][1]) for k, tr in enumerate(self.intervals[inext][2])]
            used_l, used_r = set(), set()
            for u in cut[1]:
                near = [('L', j) for j, v in left if m.dist(u, v) < mp.mpf('1e-3')] + \
                       [('R', k) for k, v in right if m.dist(u, v) < mp.mpf('1e-3')]
                if len(near) != 2 or near[0][0] != near[1][0]:
                    raise RuntimeError('%s: dead point at %s is not a simple fold: %s' % (m.name, cut[0], near))
                side = near[0][0]
                nodes = [(i, j) if side == 'L' else (inext, j) for _, j in near]
                (used_l if side == 'L' else used_r).update(j for _, j in near)
                self.folds.append((inext, side, nodes[0], nodes[1], u))
            for j, v in left:
                if j in used_l:
                    continue
                d = sorted((m.dist(v, w), k) for k, w in right if k not in used_r)
                if not d or not d[0][0] < mp.mpf('1e-6') or (len(d) > 1 and not d[1][0] > 1000 * d[0][0]):
                    raise RuntimeError('%s: no continuation across %s' % (m.name, cut[0]))
                used_r.add(d[0][1])
                self.cont[(i, j)] = (inext, d[0][1])
            if len(used_r) != len(right):
                raise RuntimeError('%s: unmatched tracks right of %s' % (m.name, cut[0]))
        nodes = [(i, j) for i in range(n) for j in range(len(self.intervals[i][2]))]
        # branches: continuation only
        for a, b in self.cont.items():
            parent[find(a)] = find(b)
        broot = {x: find(x) for x in nodes}
        # circuits: also the folds
        for _, _, a, b, _ in self.folds:
            parent[find(a)] = find(b)
        croot = {x: find(x) for x in nodes}
        # label branches and circuits by the smallest input along them
        self.branches = []
        starts = {}
        for ci, side, a, b, u in self.folds:
            if side == 'R':        # the fold is the lower end of the branches a and b
                starts[a] = ci
                starts[b] = ci
        seen = set()
        for x in nodes:
            r = broot[x]
            if r in seen:
                continue
            seen.add(r)
            members = [y for y in nodes if broot[y] == r]
            begin = [y for y in members if y in starts]
            if begin:
                y = begin[0]
                chain = [y]
                while chain[-1] in self.cont:
                    chain.append(self.cont[chain[-1]])
                t_from = self.cuts[starts[y]][0]
                t_to = t_from + sum(self.intervals[c[0]][1] - self.intervals[c[0]][0] for c in chain)
                self.branches.append(dict(nodes=chain, t_from=t_from, t_to=t_to, full=False, turns=None))
            else:
                y = min(members)
                chain = [y]
                while self.cont[chain[-1]] != y:
                    chain.append(self.cont[chain[-1]])
                self.branches.append(dict(nodes=chain, t_from=None, t_to=None, full=True,
                                          turns=len(chain) // n))
        # circuits numbered in order of first branch; branches ordered by circuit then input
        circ_ids = {}
        for br in self.branches:
            br['croot'] = croot[br['nodes'][0]]
        def key(br):
            return (0 if br['full'] else 1, br['t_from'] if br['t_from'] is not None else 0,
                    float(self.intervals[br['nodes'][0][0]][2][br['nodes'][0][1]][0][1][0]))
        self.branches.sort(key=key)
        for br in self.branches:
            if br['croot'] not in circ_ids:
                circ_ids[br['croot']] = len(circ_ids)
            br['circuit'] = circ_ids[br['croot']]
        self.branches.sort(key=lambda br: (br['circuit'],) + key(br)[:2])
        self.node_branch = {}
        for bi, br in enumerate(self.branches):
            br['id'] = bi
            for y in br['nodes']:
                self.node_branch[y] = bi
        self.n_circuits = len(circ_ids)

    def samples(self):
        """(principal input, config, branch, circuit, position along the branch)"""
        for br in self.branches:
            pos = 0
            for (i, j) in br['nodes']:
                for t, u in self.intervals[i][2][j]:
                    yield wrap(t), u, br['id'], br['circuit'], pos
                    pos += 1

    def lookup(self, t):
        out = []
        for tt, u, b, c, _ in self.samples():
            if abs(tt - wrap(t)) < mp.mpf('1e-40'):
                out.append((u, b, c))
        return out

    def dead_circuit(self, u):
        for ci, side, a, b, v in self.folds:
            if v is u:
                return self.branches[self.node_branch[a]]['circuit']


# ----------------------------------------------------------------------------------------------
# output
# ----------------------------------------------------------------------------------------------

def write_csv(path, header, rows):
    with open(path, 'w') as f:
        f.write(','.join(header) + '\n')
        for r in rows:
            f.write(','.join(r) + '\n')


def run(name, spec, cls, out_dir, summary):
    t_start = time.time()
    m = cls(name, spec)
    log('== %s: input %s, unknowns %s' % (name, m.input, m.unknowns))
    # dead points
    dead, hidden, counts = find_dead_points(m)
    log('   dead points: %d (%.1f s)' % (len(dead), time.time() - t_start))
    checks = []
    checks.append('configuration counts on the 0.25 deg scan grid: %s' % sorted(set(counts)))
    checks.append('%d local minima of the root-separation margin away from count changes refined '
                  '(golden section): smallest %s, count unchanged at each' %
                  (len(hidden), mp.nstr(min([h[1] for h in hidden] or [mp.inf]), 3)))
    for t, u, res, drel, cl, cr in dead:
        checks.append('dead point %s deg: loop residual %s, det J / (column norms) %s, '
                      'count %d / %d at -/+ 1e-6 deg' % (mp.nstr(t * 180 / PI, 20), mp.nstr(res, 2),
                                                        mp.nstr(drel, 2), cl, cr))
    # analytic / independent dead points
    if isinstance(m, (FourBar, SixBar)):
        checks.append(grashof(m))
    if isinstance(m, FourBar):
        an = m.analytic_dead_points()
        dn = [d[0] for d in dead]
        assert len(an) == len(dn) and all(abs(a - b) < mp.mpf('1e-45') for a, b in zip(an, dn)), (an, dn)
        checks.append('law of cosines (|BD| = l2 + l3, |l2 - l3|): %d dead points %s deg; '
                      'agree with the scan + Newton within %s rad' %
                      (len(an), [mp.nstr(a * 180 / PI, 15) for a in an],
                       mp.nstr(max([abs(a - b) for a, b in zip(an, dn)] or [0]), 2)))
    if type(m) is SixBar:
        an = m.resultant_dead_points()
        assert len(an) == len(dead), (len(an), len(dead))
        err = 0
        for (ta, ua), (t, u, *_) in zip(an, dead):
            err = max(err, abs(ta - t), m.dist(ua, u))
        assert err < mp.mpf('1e-40'), err
        checks.append('resultant (|E - G| = l5 + l6 or |l5 - l6| on the coupler curve, sextic in '
                      'tan(q1/2)): %d dead points, agree with the scan + Newton within %s' %
                      (len(an), mp.nstr(err, 2)))
    if isinstance(m, SixBarG):
        ext = sixbar_g_extrema(m)
        assert len(ext) == len(dead), (ext, dead)
        err = 0
        for (te, ue), (t, u, *_) in zip(ext, dead):
            err = max(err, abs(te - t), m.dist(ue, u))
        assert err < mp.mpf('1e-40'), err
        checks.append('analytic parametrisation by q1 (four-bar mode x dyad mode, extrema of '
                      'q6(q1) where dq6/dq1 = 0): %d dead points, agree within %s' %
                      (len(ext), mp.nstr(err, 2)))
    if isinstance(m, SixBarG):
        checks.append(exact_resultant_check(m))
        checks.append(sextic_root_count_check(m))
    elif type(m) is SixBar:
        checks.append(dyad_reach_check(m))
    # inputs of the at file
    at = [wrap(deg(-180 + 15 * k)) for k in range(24)]
    for t, *_ in dead:
        for o in ('1e-6', '1e-3'):
            at += [wrap(t - deg(o)), wrap(t + deg(o))]
    at = sorted(set(at))
    # second method at every at input
    t1 = time.time()
    worst = 0
    for t in at:
        c1 = m.solve(t)[0]
        c2 = m.solve2(t)
        if len(c1) != len(c2):
            raise RuntimeError('%s: count %d (polynomial) vs %d (bracketing) at %s' % (name, len(c1), len(c2), t))
        for u in c1:
            worst = max(worst, min(m.dist(u, v) for v in c2) if c2 else 0)
    assert worst < mp.mpf('1e-40'), worst
    checks.append('second method (dense bracketing of each block\'s scalar equation + golden-section '
                  'search at every local minimum of |g|) at all %d inputs of %s-at.csv: same count '
                  'everywhere, configurations agree within %s' % (len(at), name, mp.nstr(worst, 2)))
    log('   second method: %.1f s' % (time.time() - t1))
    # trace
    t1 = time.time()
    tr = Trace(m, [(t, u) for t, u, *_ in dead], at)
    log('   trace: %d solves, %.1f s' % (tr.solves, time.time() - t1))
    # every configuration found: verify again
    nres = 0
    for t, u, b, c, _ in tr.samples():
        assert m.loops.residual(t, u) < RES_TOL * max(1, m.lscale)
        nres += 1
    checks.append('%d traced configurations substituted into the loops of mechanism.toml: all '
                  'residuals < 1e-30' % nres)
    if name in ('sixbar', 'shaper'):
        checks.append(seed_reference_check(m, tr))
    start_line = start_branch(m, tr)
    # ---- files
    ang = lambda k, x: wrap(x) if k == 'angle' else x
    rows = []
    for t in at:
        found = tr.lookup(t)
        assert len(found) == len(m.solve(t)[0])
        if not found:
            rows.append([fmt(t)] + [''] * len(m.unknowns) + ['', '', '0'])
        for u, b, c in sorted(found, key=lambda r: (r[2], r[1])):
            rows.append([fmt(t)] + [fmt(ang(k, x)) for k, x in zip(m.kinds, u)] +
                        [str(c), str(b), str(len(found))])
    write_csv(os.path.join(out_dir, '%s-at.csv' % name),
              ['input'] + m.unknowns + ['circuit', 'branch', 'count'], rows)
    rows = []
    for t, u, *_ in dead:
        rows.append([fmt(t)] + [fmt(ang(k, x)) for k, x in zip(m.kinds, u)] +
                    [str(tr.dead_circuit(u)), fmt(t * 180 / PI, 20)])
    write_csv(os.path.join(out_dir, '%s-dead-points.csv' % name),
              ['input'] + m.unknowns + ['circuit', 'input_deg'], rows)
    rows = []
    dead_idx = {}
    for i, (t, *_) in enumerate(dead):
        dead_idx[i] = t
    def dead_number(t):
        for i, (td, *_) in enumerate(dead):
            if abs(wrap(td - t)) < mp.mpf('1e-30'):
                return str(i)
        return ''
    for br in tr.branches:
        if br['full']:
            rows.append([str(br['id']), str(br['circuit']), '', '', 'true', str(br['turns']), '', '', '', ''])
        else:
            rows.append([str(br['id']), str(br['circuit']), fmt(br['t_from']), fmt(br['t_to']), 'false', '',
                         dead_number(br['t_from']), dead_number(br['t_to']),
                         mp.nstr(br['t_from'] * 180 / PI, 12), mp.nstr(br['t_to'] * 180 / PI, 12)])
    write_csv(os.path.join(out_dir, '%s-branches.csv' % name),
              ['branch', 'circuit', 'input_from', 'input_to', 'full_turn', 'turns', 'dead_from', 'dead_to',
               'input_from_deg', 'input_to_deg'], rows)
    rows = []
    grid = set(wrap(deg(k)) for k in range(-180, 180))
    for t, u, b, c, pos in tr.samples():
        keep = any(abs(t - g) < mp.mpf('1e-40') for g in grid) if False else None
        rows.append((b, pos, t, u, c))
    # plot data: the 1-degree grid points and the samples near dead points (within 1 deg)
    outrows = []
    for b, pos, t, u, c in rows:
        on_grid = abs(t * 180 / PI - mp.nint(t * 180 / PI)) < mp.mpf('1e-40')
        near = any(abs(wrap(t - td)) < deg(1) and abs(wrap(t - td)) > deg('1e-5') for td, *_ in dead)
        if on_grid or near:
            outrows.append([str(b), str(c), mp.nstr(t, CURVE_DIGITS)] +
                           [mp.nstr(ang(k, x), CURVE_DIGITS) for k, x in zip(m.kinds, u)])
    # the dead points close each branch's curve
    for ci, side, a, bnode, u in tr.folds:
        t = tr.cuts[ci][0]
        for node in (a, bnode):
            bb = tr.branches[tr.node_branch[node]]
            outrows.append([str(bb['id']), str(bb['circuit']), mp.nstr(wrap(t), CURVE_DIGITS)] +
                           [mp.nstr(ang(k, x), CURVE_DIGITS) for k, x in zip(m.kinds, u)])
    outrows.sort(key=lambda r: (int(r[0]), float(r[2])))
    write_csv(os.path.join(out_dir, '%s-curves.csv' % name),
              ['branch', 'circuit', 'input'] + m.unknowns, outrows)
    # structure
    lines = ['%s: input %s, unknowns %s' % (name, m.input, ', '.join(m.unknowns)),
             'circuits: %d' % tr.n_circuits, 'branches: %d' % len(tr.branches),
             'dead points: %d' % len(dead)]
    for i, (t, u, *_) in enumerate(dead):
        lines.append('  dead point %d: %s = %s deg (%s rad), circuit %d; %s' % (
            i, m.input, mp.nstr(t * 180 / PI, 15), mp.nstr(t, 20), tr.dead_circuit(u),
            ', '.join('%s = %s' % (n, mp.nstr(ang(k, x) * 180 / PI, 10) + ' deg' if k == 'angle' else
                                   mp.nstr(x, 12)) for n, k, x in zip(m.unknowns, m.kinds, u))))
    for br in tr.branches:
        if br['full']:
            lines.append('  branch %d (circuit %d): full turn of %s, no dead point%s' % (
                br['id'], br['circuit'], m.input,
                '' if br['turns'] == 1 else ' (closes after %d turns)' % br['turns']))
        else:
            lines.append('  branch %d (circuit %d): %s from %s deg (dead point %s) up to %s deg (dead point %s)' % (
                br['id'], br['circuit'], m.input, mp.nstr(br['t_from'] * 180 / PI, 12), dead_number(br['t_from']),
                mp.nstr(br['t_to'] * 180 / PI, 12), dead_number(br['t_to'])))
    lines.append(start_line)
    cnt = {}
    for t in at:
        cnt.setdefault(len(m.solve(t)[0]), []).append(t)
    lines.append('configurations per input (at-file inputs): ' +
                 ', '.join('%d at %d inputs' % (k, len(v)) for k, v in sorted(cnt.items())))
    lines.append('')
    lines.append('checks:')
    lines += ['  - ' + c for c in checks]
    elapsed = time.time() - t_start
    lines.append('  - run time %.1f s (%d solves in the trace)' % (elapsed, tr.solves))
    with open(os.path.join(out_dir, '%s-structure.txt' % name), 'w') as f:
        f.write('\n'.join(lines) + '\n')
    log('\n'.join('   ' + l for l in lines))
    summary[name] = (tr, m, dead)
    return tr, m, dead


def sixbar_g_extrema(m):
    """dead points of sixbar_g from the analytic parametrisation by q1: extrema of q6(q1) for each
    four-bar mode sigma and dyad mode tau (sign changes of dq6/dq1 on a 0.5 deg grid, bisection)"""
    out = []
    N = 720
    for sigma in (1, -1):
        for tau in (1, -1):
            f = lambda q1: m.q6_of_q1(q1, sigma, tau)
            df = lambda q1: mp.diff(f, q1)
            ts = [-PI + TWO_PI * k / N for k in range(N + 1)]
            vals = [f(t) for t in ts]
            ds = [df(t) if v is not None else None for t, v in zip(ts, vals)]
            for k in range(N):
                if ds[k] is None or ds[k + 1] is None:
                    continue
                if (ds[k] > 0) != (ds[k + 1] > 0):
                    # the whole cell must be inside the dyad's domain
                    q1 = bisect_root(df, ts[k], ts[k + 1], ds[k])
                    q1 = mp.findroot(df, q1)
                    q6 = wrap(f(q1))
                    q2, q3 = m.fourbar_mode(q1, sigma)
                    q5 = mp.arg(m.E(q1, q2) - m.F(q6))
                    out.append((q6, (wrap(q1), q2, q3, q5)))
    return sorted(out, key=lambda r: r[0])


def grashof(m):
    """Grashof's condition for the four-bar ABCD (l1 input/crank, l2 coupler, l3 rocker, l4 ground)"""
    L = {k: m.p[k] for k in ('l1', 'l2', 'l3', 'l4')}
    s_, l_ = min(L.values()), max(L.values())
    pq = sum(L.values()) - s_ - l_
    shortest = min(L, key=L.get)
    if s_ + l_ < pq:
        kind = 'Grashof; shortest link %s%s' % (shortest, ': crank-rocker, l1 (angle q1) turns fully'
                                               if shortest == 'l1' else '')
    elif s_ + l_ > pq:
        kind = 'non-Grashof (triple rocker): the input link only rocks, two dead points'
    else:
        kind = 'change point (s + l = p + q)'
    return 'Grashof: four-bar ABCD s + l = %s, p + q = %s: %s' % (mp.nstr(s_ + l_, 8), mp.nstr(pq, 8), kind)


def start_branch(m, tr):
    """the branch of the file's [start] configuration: the nearest traced sample"""
    st = m.spec['start']
    val = lambda v: param_value(v) if isinstance(v, str) else mp.mpf(repr(v))
    t = wrap(val(st[m.input]))
    u = [val(st[k]) for k in m.unknowns]
    best = None
    for tt, uu, b, c, _ in tr.samples():
        d = max(abs(wrap(tt - t)), m.dist(uu, u))
        if best is None or d < best[0]:
            best = (d, b, c)
    return ('the [start] configuration of mechanism.toml (%s = %s deg) is on circuit %d, branch %d '
            '(nearest traced sample at distance %s)' % (m.input, mp.nstr(t * 180 / PI, 8), best[2], best[1],
                                                        mp.nstr(best[0], 2)))


def seed_reference_check(m, tr):
    """the seed mechanisms' reference table (tests/data/NAME.csv, 20 digits, the start's branch)"""
    path = os.path.join(ROOT, 'tests', 'data', '%s.csv' % m.name)
    with open(path) as f:
        lines = [l.strip().split(',') for l in f if l.strip()]
    head = lines[0]
    worst, labels, n = 0, set(), 0
    for row in lines[1:]:
        rec = dict(zip(head, row))
        t = mp.mpf(rec[m.input])
        u_ref = [mp.mpf(rec[k]) for k in m.unknowns]
        cfg = m.solve(t)[0]
        d = min(m.dist(u_ref, u) for u in cfg)
        worst = max(worst, d)
        # its branch: the traced sample at the same input (1-degree grid) closest to it
        best = None
        for tt, uu, b, c, _ in tr.samples():
            if abs(wrap(tt - t)) < mp.mpf('1e-15'):
                dd = m.dist(uu, u_ref)
                if best is None or dd < best[0]:
                    best = (dd, b, c)
        if best is not None and best[0] < mp.mpf('1e-15'):
            labels.add((best[2], best[1]))
        n += 1
    assert worst < mp.mpf('1e-17'), worst
    return ('seed reference tests/data/%s.csv (%d rows, the start branch, 20 digits): every row is one '
            'of the configurations found here (max difference %s); (circuit, branch) of its rows: %s' %
            (m.name, n, mp.nstr(worst, 2), sorted(labels)))


def exact_resultant_check(m):
    """the sextic built from scratch with sympy, exactly, from the loop strings of mechanism.toml:
    q3, q5 eliminated by |.|^2, half-angle substitution, sympy's resultant in x2, at the input
    q6 = 2 atan(-3/4) (rational cos and sin); compared with the numeric Bezout-form resultant"""
    spec = m.spec
    P = {}
    for k, v in m.raw.items():
        P[k] = sp.Rational(v[4:-1]) * sp.pi / 180 if v.startswith('deg(') else sp.Rational(v)
    x1, x2, s3 = sp.symbols('x1 x2 s3')
    x6 = sp.Rational(-3, 4)
    q = {n: sp.Symbol(n, real=True) for n in ('q1', 'q2', 'q3', 'q5', 'q6')}
    ns = dict(q, **P)
    ns.update(e=lambda x: sp.exp(sp.I * x), c=lambda a, b: a + sp.I * b, deg=lambda x: x * sp.pi / 180)
    L = [sp.sympify(eval(s, {'__builtins__': {}}, ns)) for s in spec['loops']]
    rest1 = sp.expand(L[0] + P['l3'] * sp.exp(sp.I * q['q3']))    # = l3 e(q3)
    rest2 = sp.expand(L[1] + P['l5'] * sp.exp(sp.I * q['q5']))    # = l5 e(q5)
    assert not rest1.has(q['q3']) and not rest2.has(q['q5'])
    half = {}
    for v, xv in (('q1', x1), ('q2', x2), ('q6', x6)):
        half[sp.cos(q[v])] = (1 - xv ** 2) / (1 + xv ** 2)
        half[sp.sin(q[v])] = 2 * xv / (1 + xv ** 2)

    def squared(expr, l):
        z = sp.expand(expr * sp.conjugate(expr))
        z = sp.expand_trig(sp.expand(sp.expand_complex(sp.expand(z.rewrite(sp.cos)))))
        z = sp.numer(sp.together(z.subs(half) - l ** 2))
        return sp.expand(z).subs(sp.sqrt(3), s3)
    f1, f2 = squared(rest1, P['l3']), squared(rest2, P['l5'])
    degs = [sp.Poly(f, x1, x2).degree(v) for f in (f1, f2) for v in (x1, x2)]
    Rr = sp.resultant(sp.Poly(f1, x2), sp.Poly(f2, x2))
    Rr = Rr.as_expr() if hasattr(Rr, 'as_expr') else Rr
    Rr = sp.rem(sp.Poly(sp.expand(Rr), s3), sp.Poly(s3 ** 2 - 3, s3)).as_expr().subs(s3, sp.sqrt(3))
    Rx = sp.Poly(sp.expand(Rr), x1)
    quo, rem = sp.div(Rx, sp.Poly(1 + x1 ** 2, x1))
    assert sp.simplify(rem.as_expr()) == 0
    S_exact = [mp.mpf(str(sp.N(c, 70))) for c in reversed(quo.all_coeffs())]
    F = mp.mpc(m.p['xg'], m.p['yg']) + m.p['l6'] * mp.expj(2 * mp.atan(mp.mpf(-3) / 4))
    S_num = coupler_circle_sextic(m.p, F, m.p['l5'])[0]
    ratios = [a / b for a, b in zip(S_exact, S_num)]
    spread = max(abs(r / ratios[0] - 1) for r in ratios)
    assert Rx.degree() == 8 and len(S_exact) == 7 and spread < mp.mpf('1e-45'), (Rx.degree(), spread)
    return ('exact resultant (sympy, from the loop strings of mechanism.toml, at q6 = 2 atan(-3/4)): '
            'both squared loops have degrees (x1, x2) = %s; resultant in x2 has degree %d in x1, '
            'exactly divisible by (1 + x1^2); the sextic equals the numeric Bezout-form one up to a '
            'constant factor within %s' % (degs[:2], Rx.degree(), mp.nstr(spread, 2)))


def sextic_root_count_check(m):
    """at 720 inputs (0.5 deg) every root of the sextic: 6 roots, non-real ones in conjugate pairs"""
    counts = {}
    worst = 0
    for k in range(720):
        t = -PI + TWO_PI * (k + mp.mpf(1) / 3) / 720
        F = m.F(t)
        S = coupler_circle_sextic(m.p, F, m.p['l5'])[0]
        roots, err = mp.polyroots(list(reversed(S)), maxsteps=400, extraprec=400, error=True)
        worst = max(worst, err)
        real = [r for r in roots if abs(mp.im(r)) <= mp.mpf('1e-35') * (1 + abs(r))]
        cplx = [r for r in roots if abs(mp.im(r)) > mp.mpf('1e-35') * (1 + abs(r))]
        assert len(roots) == 6
        for r in cplx:
            assert min(abs(r - mp.conj(s)) for s in cplx) < mp.mpf('1e-40') * (1 + abs(r))
        assert len(m.solve(t)[0]) == len(real)
        counts[len(real)] = counts.get(len(real), 0) + 1
    return ('degree count: at 720 inputs (0.5 deg grid, offset) the sextic has exactly 6 roots (polyroots '
            'error estimate <= %s), the non-real ones in conjugate pairs; real roots: %s' %
            (mp.nstr(worst, 2), ', '.join('%d at %d inputs' % kv for kv in sorted(counts.items()))))


def dyad_reach_check(m):
    """range of |E - G| over the full turn for each assembly mode of the four-bar"""
    p = m.p
    out = []
    for sigma in (1, -1):
        f = lambda q1: abs(m.E(q1, SixBarG.fourbar_mode(m, q1, sigma)[0]) - m.G())
        N = 720
        ts = [-PI + TWO_PI * k / N for k in range(N)]
        vs = [f(t) for t in ts]
        lo = min(golden_min(f, ts[k] - TWO_PI / N, ts[k] + TWO_PI / N, 100)[1]
                 for k in range(N) if vs[k] <= vs[k - 1] and vs[k] <= vs[(k + 1) % N])
        hi = -min(golden_min(lambda t: -f(t), ts[k] - TWO_PI / N, ts[k] + TWO_PI / N, 100)[1]
                  for k in range(N) if vs[k] >= vs[k - 1] and vs[k] >= vs[(k + 1) % N])
        out.append('four-bar mode %+d (q2 = arg(BD) %+d * angle DBC): |E - G| in [%s, %s]' %
                   (sigma, sigma, mp.nstr(lo, 10), mp.nstr(hi, 10)))
    return ('dyad reach: the dyad E-F-G assembles iff |l5 - l6| = %s <= |E - G| <= l5 + l6 = %s; ' %
            (mp.nstr(abs(p['l5'] - p['l6']), 6), mp.nstr(p['l5'] + p['l6'], 6)) + '; '.join(out))


CLASSES = {
    'four_bar': FourBar,
    'rocker_four_bar': FourBar,
    'sixbar': SixBar,
    'sixbar_g': SixBarG,
    'slider_crank': SliderCrank,
    'shaper': Shaper,
}


def main():
    mechs = load_toml()
    names = sys.argv[1:] or list(CLASSES)
    summary = {}
    params_rows = []
    for name in CLASSES:
        for k, v in raw_param_text(name).items():
            params_rows.append([name, k, v, fmt(param_value(v), 40), repr(float(param_value(v)))])
    write_csv(os.path.join(HERE, 'params.csv'), ['mechanism', 'param', 'as_written', 'value', 'f64'], params_rows)
    timings = {}
    for name in names:
        t0 = time.time()
        run(name, mechs[name], CLASSES[name], HERE, summary)
        timings[name] = time.time() - t0
    if 'sixbar' in summary and 'sixbar_g' in summary:
        cross_check_sixbar(summary)
    for k, v in timings.items():
        log('%s: %.1f s' % (k, v))


def cross_check_sixbar(summary):
    """sixbar and sixbar_g have the same loops and the same variables: the same real curve, so the
    same circuits. Every traced sixbar_g configuration (on the 1-degree grid) is located on the
    sixbar circuits by solving sixbar at its q1 and matching."""
    trg, mg, _ = summary['sixbar_g']
    trs, ms, deads = summary['sixbar']
    # sixbar circuits by sampling: for each q1 of a sixbar_g sample, find the sixbar configuration
    pairs = set()
    n = 0
    for t, u, b, c, pos in trg.samples():
        if pos % 7:
            continue
        q1, q2, q3, q5 = u
        # trace sixbar once more only at this q1: label via the closest traced sixbar sample
        best = None
        for tt, uu, bb, cc, _ in trs.samples():
            d = max(abs(wrap(tt - q1)), ms.dist(uu, (q2, q3, q5, t)))
            if best is None or d < best[0]:
                best = (d, cc)
        pairs.add((c, best[1]))
        n += 1
    log('   sixbar_g circuit -> sixbar circuit (nearest traced sample): %s' % sorted(pairs))
    with open(os.path.join(HERE, 'sixbar_g-structure.txt'), 'a') as f:
        f.write('  - same curve as sixbar (same loops, the input is only another coordinate): %d sixbar_g '
                'samples located on the traced sixbar curve; circuit pairs (sixbar_g, sixbar) %s\n' %
                (n, sorted(pairs)))


if __name__ == '__main__':
    main()
