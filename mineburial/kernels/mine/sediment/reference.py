"""Reference quadrature of the sediment tractions over the embedded surface.

The accurate rule (``numerics.sediment_quadrature = "reference"``): the lateral surface
is integrated generator by generator (outer variable theta, inner x). Along a
generator every switch (seabed, delta, reversal of the circumferential slip, least
speed) is a linear or quadratic function of x, so the inner limits and split points
are exact; the theta-panels end at every angle where the inner integrand changes its
form (closed forms, plus the roots of degree-2 trigonometric polynomials where two
switch lines cross), and are graded geometrically towards near-singularities (poles
of a switch line, sharp fronts). End caps are integrated in polar coordinates about
the centre, the stagnation point of the in-plane slip or the point of least speed, in
panels between the corners of the cut disk. Gauss-Legendre on every part, sinh
transformations at near-singular ends; no allocation (``docs/notes/sediment.md``
section 3 gives the derivation and the measured error and cost).

A tabulated profile's depths split the lines and panels while at most ``REFERENCE_LEVELS`` lie
in a span; beyond, a long table's rows are sampled by ``LONG_PIECES`` equal pieces, so that the
cost does not grow with the rows (issue 34; ``docs/notes/sediment.md``).

Its cost (60-350 us an evaluation) and its adaptivity (the number of panels and
points changes with the state, so the force is rough on the scale of its error) make
it the guard of the fast rule (:mod:`.fast`) in the tests, not the default.
"""

import math

import numpy as np

from mineburial._numba import kernel, small_kernel
from mineburial.kernels.mine.environment import bracket, last_point
from mineburial.kernels.mine.sediment.laws import GL_NODES as _GL_NODES
from mineburial.kernels.mine.sediment.laws import GL_WEIGHTS as _GL_WEIGHTS
from mineburial.kernels.mine.sediment.laws import (
    LAW_A,
    LAW_BETA,
    LAW_DIAMETER,
    LAW_MU,
    LAW_RATE,
    LAW_RATE_REF,
    LAW_ROW,
    LAW_VREG,
    LAW_VREG_N,
    LAW_VREST,
    RATE_IMPACT35,
    RATE_SEMILOG,
    _traction,
    add_point_traction,
    add_weighted,
)

# --- quadrature constants -----------------------------------------------------
#: Lateral surface, per theta-panel: Gauss-Legendre points = ceil(width * NODES_PER_RAD)
#: clipped to [N_MIN, N_MAX] (wider panels are split); N_GRADED points on each
#: sub-panel of a panel graded geometrically (ratio GRADE_RATIO) towards a breakpoint
#: whose near-singularity scale eps is below GRADE_TRIGGER * panel width; along a
#: generator N_X points per piece, N_X_MAPPED on a sinh-mapped piece.
#: Tuple layout: (NODES_PER_RAD, N_MIN, N_MAX, N_GRADED, GRADE_RATIO, GRADE_TRIGGER,
#: N_X, N_X_MAPPED).
LATERAL_RULE = (3.0, 4, 8, 4, 4.0, 0.25, 4, 5)
#: End caps, the same layout with (N_RHO, N_RHO_MAPPED) in the last two slots.
CAP_RULE = (3.0, 4, 8, 4, 4.0, 0.25, 4, 5)
#: The ramp of the regularised switch across the delta line (width V_REG_N/|dv_n/dr|)
#: is resolved (along a line, or by grading an angle panel) where it is wider than
#: RAMP_MIN times the line or panel; thinner ramps weigh less than the quadrature error.
RAMP_MIN = 1e-3
#: Width of the sinh-mapped layer next to a near-singularity, in units of its scale eps
#: (beyond it the integrand is smooth at the scale of its distance from it).
LAYER_WIDTHS = 16.0
#: Least number of points on each part of a generator piece split at tabulated depths.
LEVEL_POINTS = 3
#: A part (of a line) or a lateral surface is split at the tabulated depths it crosses while at
#: most this many lie inside its depth span; beyond (a long table: a cone-penetration log has a
#: row every few millimetres), the part is cut into LONG_PIECES equal pieces of its full rule
#: and the lateral surface's angle panels are not split at the depth lines, so that the cost is
#: bounded whatever the table's rows (issue 34: a 20,000-row log cost 8-19 s an evaluation).
#: The rows are then sampled (at 4x the fast rule's points), not resolved one by one.
REFERENCE_LEVELS = 16
LONG_PIECES = 4
#: At most this many sub-panels when grading towards one breakpoint.
MAX_GRADE = 14
#: Samples of a degree-2 trigonometric polynomial when bracketing its roots.
N_SAMPLE = 32
#: The speed dip of the impact35 rate law (G falls from A to 1 over |v| ~ V_rest) is
#: resolved where the local minimum speed is below DIP_SPEEDS * V_rest.
DIP_SPEEDS = 7.0


_SAMPLE_T = 2.0 * np.pi * np.arange(N_SAMPLE + 1) / N_SAMPLE
_SAMPLE_C = np.cos(_SAMPLE_T)
_SAMPLE_S = np.sin(_SAMPLE_T)
_SAMPLE_C2 = np.cos(2.0 * _SAMPLE_T)
_SAMPLE_S2 = np.sin(2.0 * _SAMPLE_T)

_TWO_PI = 2.0 * math.pi
_NAN = math.nan


@small_kernel
def _count_below(bank, row, x, last, strict):
    """Number of tabulated depths of bank row ``row`` (last point ``last``) below ``x``
    (``< x`` when ``strict``, else ``<= x``), by ``environment.bracket`` (O(1) on a drop's own
    bank, O(log n) on any): the row is never scanned."""
    if not (x == x) or bank[row, 0, 0] > x or (strict and bank[row, 0, 0] == x):
        return 0
    if bank[row, 0, last] < x or (not strict and bank[row, 0, last] == x):
        return last + 1
    lo, _ = bracket(bank, row, x, last, strict)
    return lo + 1


@small_kernel
def _levels_between(bank, row, lo, hi):
    """``(j0, j1)``: the first and last index of the tabulated depths d of bank row ``row``
    with lo < d < hi (j1 < j0: none), found without scanning the row."""
    last = last_point(bank, row)
    if math.isnan(bank[row, 0, last]):
        return 0, -1
    return _count_below(bank, row, lo, last, False), _count_below(bank, row, hi, last, True) - 1


# =============================================================================
# breakpoints
# =============================================================================
@kernel
def _wrap(t):
    """t mapped into [0, 2 pi) (NaN stays NaN)."""
    if not (t == t):
        return t
    return t - _TWO_PI * math.floor(t / _TWO_PI)


@kernel
def _roots_lin(k, a, b):
    """Roots in [0, 2pi) of k + a cos t + b sin t = 0 (NaN when absent)."""
    amp = math.sqrt(a * a + b * b)
    if not (amp > 0.0) or abs(k) > amp:
        return _NAN, _NAN
    psi = math.atan2(b, a)
    d = math.acos(-k / amp)
    return _wrap(psi + d), _wrap(psi - d)


@kernel
def _crossing_roots(f, g, xa, xb):
    """Angles where the switch lines of two families cross inside the body.

    Family ``f`` = (k0, kc, ks, l0, lc, ls) is the linear-in-x function
    F(x, t) = (k0 + kc cos t + ks sin t) + x (l0 + lc cos t + ls sin t).
    Their zero lines x_F(t) = -F0/F1 and x_G(t) meet where
    F0 G1 - G0 F1 = 0, a degree-2 trigonometric polynomial; its roots are
    bracketed on N_SAMPLE samples and polished by safeguarded Newton steps.
    Up to four roots (NaN when absent), kept only if the crossing lies in (xa, xb).
    """
    # (a0 + a1 c + a2 s)(b0 + b1 c + b2 s) = a0 b0 + (a1 b1 + a2 b2)/2 + (a0 b1 + a1 b0) c
    #   + (a0 b2 + a2 b0) s + (a1 b1 - a2 b2)/2 cos 2t + (a1 b2 + a2 b1)/2 sin 2t
    a0, a1, a2, b0, b1, b2 = f[0], f[1], f[2], g[3], g[4], g[5]
    k0, k1, k2, l0, l1, l2 = g[0], g[1], g[2], f[3], f[4], f[5]
    h0 = a0 * b0 + 0.5 * (a1 * b1 + a2 * b2) - k0 * l0 - 0.5 * (k1 * l1 + k2 * l2)
    h1 = a0 * b1 + a1 * b0 - k0 * l1 - k1 * l0
    h2 = a0 * b2 + a2 * b0 - k0 * l2 - k2 * l0
    h3 = 0.5 * (a1 * b1 - a2 * b2) - 0.5 * (k1 * l1 - k2 * l2)
    h4 = 0.5 * (a1 * b2 + a2 * b1) - 0.5 * (k1 * l2 + k2 * l1)
    scale = (abs(f[0]) + abs(f[1]) + abs(f[2])) * (abs(g[3]) + abs(g[4]) + abs(g[5])) + (
        abs(g[0]) + abs(g[1]) + abs(g[2])
    ) * (abs(f[3]) + abs(f[4]) + abs(f[5]))
    r0 = _NAN
    r1 = _NAN
    r2 = _NAN
    r3 = _NAN
    if not (abs(h0) + abs(h1) + abs(h2) + abs(h3) + abs(h4) > 1e-12 * scale):
        return r0, r1, r2, r3
    nfound = 0
    prev = h0 + h1 + h3  # t = 0
    for j in range(N_SAMPLE):
        cur = (
            h0
            + h1 * _SAMPLE_C[j + 1]
            + h2 * _SAMPLE_S[j + 1]
            + h3 * _SAMPLE_C2[j + 1]
            + h4 * _SAMPLE_S2[j + 1]
        )
        if (prev < 0.0 and cur >= 0.0) or (prev > 0.0 and cur <= 0.0):
            lo = _SAMPLE_T[j]
            hi = _SAMPLE_T[j + 1]
            flo = prev
            t = lo + (hi - lo) * prev / (prev - cur)
            for _ in range(8):
                c = math.cos(t)
                s = math.sin(t)
                c2 = c * c - s * s
                s2 = 2.0 * s * c
                val = h0 + h1 * c + h2 * s + h3 * c2 + h4 * s2
                der = -h1 * s + h2 * c - 2.0 * h3 * s2 + 2.0 * h4 * c2
                if val == 0.0:
                    break
                if (val < 0.0) == (flo < 0.0):
                    lo = t
                    flo = val
                else:
                    hi = t
                tn = t - val / der if der != 0.0 else 0.5 * (lo + hi)
                if not (tn > lo and tn < hi):
                    tn = 0.5 * (lo + hi)
                if abs(tn - t) < 1e-14:
                    t = tn
                    break
                t = tn
            c = math.cos(t)
            s = math.sin(t)
            f1 = f[3] + f[4] * c + f[5] * s
            g1 = g[3] + g[4] * c + g[5] * s
            if abs(f1) >= abs(g1):
                xc = -(f[0] + f[1] * c + f[2] * s) / f1 if f1 != 0.0 else _NAN
            else:
                xc = -(g[0] + g[1] * c + g[2] * s) / g1
            if xc > xa and xc < xb:
                if nfound == 0:
                    r0 = t
                elif nfound == 1:
                    r1 = t
                elif nfound == 2:
                    r2 = t
                elif nfound == 3:
                    r3 = t
                nfound += 1
        prev = cur
    return r0, r1, r2, r3


@kernel
def _adist(t, poles):
    """Angular distance from t to the nearer of two angles (inf when both are NaN)."""
    best = math.inf
    for k in range(2):
        q = poles[k]
        if q == q:
            d = abs(t - q) % _TWO_PI
            d = min(d, _TWO_PI - d)
            best = min(best, d)
    return best


@kernel
def _next_break(bps, eps, epsr, cur):
    """Smallest breakpoint above cur (2 pi when none) and the smallest near-singularity
    scales attached to it (eps: poles, fronts, dips; epsr: ramp of the delta switch)."""
    nxt = _TWO_PI
    e = math.inf
    er = math.inf
    for k in range(len(bps)):
        b = bps[k]
        if b > cur and b < nxt:
            nxt = b
            e = eps[k]
            er = epsr[k]
        elif b == nxt:
            e = min(e, eps[k])
            er = min(er, epsr[k])
    return nxt, e, er


@kernel
def _line_interval(kind, c, s, sg, fe, fd):
    """Part of the line at angle (c, s) that is embedded (zeta > 0) and advancing
    (v.n >= 0): an x-interval of the generator (kind 0) or a rho-interval of the ray
    from O (kind 1); empty when hi <= lo."""
    if kind == 0:
        lo = sg[1]
        hi = sg[2]
        # seabed: zeta = E0 + E1 x > 0
        a0 = fe[0] + fe[1] * c + fe[2] * s
        a1 = fe[3]
        # delta: v.n = D0 + D1 x >= 0
        b0 = fd[1] * c + fd[2] * s
        b1 = fd[4] * c + fd[5] * s
    else:
        oy = sg[3]
        oz = sg[4]
        od = oy * c + oz * s
        lo = 0.0
        hi = -od + math.sqrt(max(od * od + sg[2] * sg[2] - sg[5], 0.0))
        a0 = sg[6] + sg[7] * oy + sg[8] * oz
        a1 = sg[7] * c + sg[8] * s
        b0 = sg[9] + sg[10] * oy + sg[11] * oz
        b1 = sg[10] * c + sg[11] * s
    if a1 > 0.0:
        lo = max(lo, -a0 / a1)
    elif a1 < 0.0:
        hi = min(hi, -a0 / a1)
    elif not (a0 > 0.0):
        return 1.0, 0.0
    if b1 > 0.0:
        lo = max(lo, -b0 / b1)
    elif b1 < 0.0:
        hi = min(hi, -b0 / b1)
    elif b0 < 0.0:
        return 1.0, 0.0
    return lo, hi


@small_kernel
def _delta_ramp_ends(kind, c, s, lo, hi, sg, fd, law):
    """Widths ``(elo, ehi)`` of the ramp of the regularised delta switch
    v_n / sqrt(v_n^2 + V_REG_N^2) at the ends of the line's interval [lo, hi]: an end set by
    the delta switch carries it over the length V_REG_N/|dv_n/dr| (0: no ramp there, or one
    thinner than RAMP_MIN of the interval)."""
    if kind == 0:
        b0 = fd[1] * c + fd[2] * s
        b1 = fd[4] * c + fd[5] * s
    else:
        b0 = sg[9] + sg[10] * sg[3] + sg[11] * sg[4]
        b1 = sg[10] * c + sg[11] * s
    elo = 0.0
    ehi = 0.0
    if b1 != 0.0:
        rd = -b0 / b1
        tol = 1e-12 * (abs(lo) + abs(hi)) + 1e-300
        en = law[LAW_VREG_N] / abs(b1)
        if en > RAMP_MIN * (hi - lo):
            if abs(lo - rd) <= tol:
                elo = en
            elif abs(hi - rd) <= tol:
                ehi = en
    return elo, ehi


@small_kernel
def _generator_features(c, s, lo, hi, R, fd, ft, vel, law, tangential, dip):
    """Split points of a generator inside (lo, hi) and their widths, ``(p1, q1, p2, q2)`` in
    increasing x (NaN: none): where the circumferential slip reverses (v_theta = T0 + T1 x = 0;
    the slip direction turns over sqrt(v_x^2 + V_REG^2)/|T1|) and where the speed is least
    (the rate factor dips over ~max(v_min, floor)/|dv/dx|)."""
    v1, _, _, _, w2, w3 = vel
    p1 = _NAN
    q1 = 0.0
    p2 = _NAN
    q2 = 0.0
    vx = v1 - w3 * R * c + w2 * R * s
    t0 = ft[0] + ft[1] * c + ft[2] * s
    t1 = ft[4] * c + ft[5] * s
    if tangential and t1 != 0.0:
        xq = -t0 / t1
        if xq > lo and xq < hi:
            p1 = xq
            q1 = math.sqrt(vx * vx + law[LAW_VREG] * law[LAW_VREG]) / abs(t1)
    if dip[0] > 0:
        d0 = fd[1] * c + fd[2] * s
        d1 = fd[4] * c + fd[5] * s
        a2 = d1 * d1 + t1 * t1
        if a2 > 0.0:
            xm = -(d0 * d1 + t0 * t1) / a2
            if xm > lo and xm < hi:
                cr = d0 * t1 - t0 * d1
                vmin = math.sqrt(vx * vx + cr * cr / a2)
                if vmin < dip[2]:
                    p2 = xm
                    q2 = max(vmin, dip[1]) / math.sqrt(a2)
    if not (p1 == p1):
        p1 = p2
        q1 = q2
        p2 = _NAN
    elif p2 == p2 and p2 < p1:
        p1, p2 = p2, p1
        q1, q2 = q2, q1
    return p1, q1, p2, q2


@small_kernel
def _part_map(kind, sg, h, nh, a, b, ea, eb, n, nm):
    """The map r = anchor + side eps sinh(u) of part ``h`` (of ``nh``) of the piece [a, b]
    whose ends carry near-singularities of widths ``ea``, ``eb`` (0: none), as
    ``(sa, sb, anchor, eps, side, npts)``: a piece with a feature at each end is halved, each
    half mapped towards its end (eps = 0: plain Gauss-Legendre, r = u); on a cap's ray with
    a speed dip at the polar origin, the whole ray is mapped from it."""
    sa = a
    sb = b
    anchor = a
    eps = 0.0
    side = 0.0
    npts = n
    mid = 0.5 * (a + b)
    if kind == 1 and sg[12] > 0.0:
        # speed dip at the polar origin: rho = eps_r sinh(u) on the whole ray
        anchor = 0.0
        eps = sg[12]
        side = 1.0
        npts = nm
    elif nh == 2:
        npts = nm
        if h == 0:
            sb = mid
            eps = ea
            side = 1.0
        else:
            sa = mid
            anchor = b
            eps = eb
            side = -1.0
    elif ea > 0.0:
        eps = ea
        side = 1.0
        npts = nm
    elif eb > 0.0:
        anchor = b
        eps = eb
        side = -1.0
        npts = nm
    return sa, sb, anchor, eps, side, npts


@small_kernel
def _gauss_piece(u0, u1, kk, anchor, eps, side, line, vel, law, bank, acc):
    """``acc`` plus the kk-point Gauss-Legendre rule on [u0, u1] of the traction moments along
    the line ``line`` = (point, direction, normal, depth z0 + z1 r, polar weight r or not)."""
    px, py, pz, dx, dy, dz, nx, ny, nz, z0, z1, polar = line
    v1, v2, v3, w1, w2, w3 = vel
    hu = 0.5 * (u1 - u0)
    mu = 0.5 * (u1 + u0)
    for i in range(kk):
        u = mu + hu * _GL_NODES[kk, i]
        if eps > 0.0:
            r = anchor + side * eps * math.sinh(u)
            jac = eps * math.cosh(u)
        else:
            r = u
            jac = 1.0
        x = px + r * dx
        y = py + r * dy
        z = pz + r * dz
        g1, g2, g3 = _traction(x, y, z, nx, ny, nz, z0 + z1 * r, v1, v2, v3, w1, w2, w3, law, bank)
        wgt = hu * _GL_WEIGHTS[kk, i] * jac
        if polar:
            wgt *= r
        acc = add_point_traction(acc, wgt, x, y, z, g1, g2, g3)
    return acc


@small_kernel
def _part(sa, sb, anchor, eps, side, npts, n, line, nlev, row, vel, law, bank, acc):
    """``acc`` plus the moments over one part [sa, sb] mapped as :func:`_part_map` says: the
    near-singular layer within LAYER_WIDTHS eps of the anchor sinh-mapped (u <= asinh(
    LAYER_WIDTHS)), the rest plain Gauss-Legendre; each split where it crosses one of the
    tabulated depths of profile ``row`` (``nlev`` > 0: a kink of the profile), each piece getting
    a share of the points proportional to its length, at least LEVEL_POINTS, while at most
    REFERENCE_LEVELS depths lie in its span (found by bisection, not by a scan of the row); else
    LONG_PIECES equal pieces of ``npts`` points (a long table: the rows sampled)."""
    z0 = line[9]
    z1 = line[10]
    sa0 = sa
    sb0 = sb
    edge = 0.0
    nsp = 1
    if eps > 0.0:
        edge = anchor + side * LAYER_WIDTHS * eps
        if (side > 0.0 and edge <= sa0) or (side < 0.0 and edge >= sb0):
            eps = 0.0  # the layer lies outside the part
            side = 0.0
            npts = n
        elif edge > sa0 and edge < sb0:
            nsp = 2
    lay_side = side
    for sp in range(nsp):
        if nsp == 2:
            if sp == 0:  # the layer, mapped
                sa = sa0 if lay_side > 0.0 else edge
                sb = edge if lay_side > 0.0 else sb0
            else:  # the rest, plain
                sa = edge if lay_side > 0.0 else sa0
                sb = sb0 if lay_side > 0.0 else edge
                eps = 0.0
                side = 0.0
                npts = n
        if eps > 0.0:
            ua = math.asinh(side * (sa - anchor) / eps)
            ub = math.asinh(side * (sb - anchor) / eps)
            if ua > ub:
                ua, ub = ub, ua
        else:
            ua = sa
            ub = sb
        za = z0 + z1 * sa
        zb = z0 + z1 * sb
        zlo = min(za, zb)
        zhi = max(za, zb)
        up = (z1 > 0.0) == (side >= 0.0)  # depth increases with u
        total = ub - ua
        u0 = ua
        j0 = 0
        j1 = -1
        if nlev > 0:
            j0, j1 = _levels_between(bank, row, zlo, zhi)
        if j1 - j0 + 1 > REFERENCE_LEVELS:  # a long table: equal pieces, the rows sampled
            for q in range(LONG_PIECES):
                u1 = ub if q == LONG_PIECES - 1 else ua + (q + 1) * total / LONG_PIECES
                acc = _gauss_piece(u0, u1, npts, anchor, eps, side, line, vel, law, bank, acc)
                u0 = u1
            continue
        # the depths inside (zlo, zhi) in the order u meets them (the others were skipped
        # one by one before: the same pieces, found in O(1))
        nin = max(j1 - j0 + 1, 0)
        for jj in range(nin + 1):
            u1 = ub
            kk = npts
            if jj < nin:
                j = j0 + jj if up else j1 - jj
                dep = bank[row, 0, j]
                if not (dep > zlo and dep < zhi):
                    continue
                rl = (dep - z0) / z1
                u1 = math.asinh(side * (rl - anchor) / eps) if eps > 0.0 else rl
                if not (u1 > u0 and u1 < ub):
                    continue
            if nlev > 0:
                kk = min(npts, max(LEVEL_POINTS, int(npts * (u1 - u0) / total + 0.999)))
            acc = _gauss_piece(u0, u1, kk, anchor, eps, side, line, vel, law, bank, acc)
            u0 = u1
    return acc


@kernel
def _inner(kind, c, s, lo, hi, sg, fe, fd, ft, vel, law, bank, tangential, dip, n, nm):
    """Moments of the tractions along the line at angle (c, s) for r in [lo, hi].

    The line is a generator (kind 0: point (x, R c, R s), normal (0, c, s), r = x) or a
    ray of an end cap (kind 1: point (xc, O + rho (c, s)), normal (sgn, 0, 0), r = rho,
    weight rho). It is cut into pieces at its features, and each piece into parts, each
    integrated by Gauss-Legendre in u with r = anchor + side eps sinh(u) (the sinh
    transformation of Johnston & Elliott 2005, Int. J. Numer. Meth. Eng. 62:564, resolving a
    near-singularity at distance eps from r = anchor) or r = u:

    * generator: split where the circumferential slip reverses and where the speed is least
      (:func:`_generator_features`), mapped towards both (nm points on a mapped part, n
      otherwise; a part with a feature at each end is halved, :func:`_part_map`);
    * ray: one part, mapped from O when sg[12] > 0 (speed dip at O);
    * an end set by the delta switch is mapped towards its ramp (:func:`_delta_ramp_ends`);
    * with a tabulated profile each part is also split where it crosses a tabulated depth
      (:func:`_part`).
    """
    elo, ehi = _delta_ramp_ends(kind, c, s, lo, hi, sg, fd, law)
    p1 = _NAN
    q1 = 0.0
    p2 = _NAN
    q2 = 0.0
    if kind == 0:
        R = sg[0]
        # point P + r D, normal N, depth z0 + z1 r
        z0 = fe[0] + fe[1] * c + fe[2] * s
        line = (0.0, R * c, R * s, 1.0, 0.0, 0.0, 0.0, c, s, z0, fe[3], False)
        p1, q1, p2, q2 = _generator_features(c, s, lo, hi, R, fd, ft, vel, law, tangential, dip)
    else:
        z0 = sg[6] + sg[7] * sg[3] + sg[8] * sg[4]
        line = (sg[0], sg[3], sg[4], 0.0, c, s, sg[1], 0.0, 0.0, z0, sg[7] * c + sg[8] * s, True)
    row = law[LAW_ROW]
    nlev = bank.shape[2] if (row >= 0 and line[10] != 0.0) else 0
    npiece = 1 + (1 if p1 == p1 else 0) + (1 if p2 == p2 else 0)
    acc = (0.0, 0.0, 0.0, 0.0, 0.0, 0.0)
    for k in range(npiece):
        a = lo if k == 0 else (p1 if k == 1 else p2)
        ea = elo if k == 0 else (q1 if k == 1 else q2)
        b = hi if k == npiece - 1 else (p1 if k == 0 else p2)
        eb = ehi if k == npiece - 1 else (q1 if k == 0 else q2)
        if not (b > a):
            continue
        if ea >= b - a:
            ea = 0.0
        if eb >= b - a:
            eb = 0.0
        nh = 2 if (ea > 0.0 and eb > 0.0) else 1
        for h in range(nh):
            sa, sb, anchor, eps, side, npts = _part_map(kind, sg, h, nh, a, b, ea, eb, n, nm)
            acc = _part(sa, sb, anchor, eps, side, npts, n, line, nlev, row, vel, law, bank, acc)
    return acc


# =============================================================================
# panels in the angle (theta on the lateral surface, phi on a cap)
# =============================================================================
@small_kernel
def _depth_line_break(cur, nxt, e_nxt, er_nxt, fe, fd, xa, xb, zmax, row, bank, vtol):
    """The next panel end ``(nxt, e, er)`` on the lateral surface with a tabulated profile:
    the first angle after ``cur`` and before ``nxt`` where a tabulated depth line d reaches a
    body end xe, (E0 - d) + E1 xe = 0, on the advancing side (no near-singularity there);
    else ``nxt`` and its scales unchanged. A long table (more than REFERENCE_LEVELS depths above
    ``zmax``) adds no panel ends (its rows are sampled, :func:`_part`)."""
    inf = math.inf
    j0, j1 = _levels_between(bank, row, 0.0, zmax)
    if j1 - j0 + 1 > REFERENCE_LEVELS:  # a long table: no panel ends at its depth lines
        return nxt, e_nxt, er_nxt
    for j in range(j0, j1 + 1):
        d = bank[row, 0, j]
        if not (d < zmax):
            break
        if not (d > 0.0):
            continue
        for k in range(4):
            xe = xa if k < 2 else xb
            rr = _roots_lin(fe[0] - d + fe[3] * xe, fe[1], fe[2])
            t = rr[k % 2]
            if t > cur and t < nxt:
                c = math.cos(t)
                s = math.sin(t)
                if fd[1] * c + fd[2] * s + xe * (fd[4] * c + fd[5] * s) >= -vtol:
                    nxt = t
                    e_nxt = inf
                    er_nxt = inf
    return nxt, e_nxt, er_nxt


@small_kernel
def _panel_modes(cur, nxt, e_cur, er_cur, e_nxt, er_nxt, trig):
    """How the panel [cur, nxt] treats each end: mode 1 = geometric grading (a pole-like
    near-singularity at distance e, or a front/dip of width e), mode 2 = sinh-mapped layer
    (the ramp of the delta switch, width er, counted where not negligibly thin), 0 = none;
    as ``(mode_a, scale_a, mode_b, scale_b)``."""
    inf = math.inf
    width = nxt - cur
    ra = er_cur if er_cur > RAMP_MIN * width else inf
    rb = er_nxt if er_nxt > RAMP_MIN * width else inf
    mode_a = 1 if e_cur < trig * width else (2 if ra < trig * width else 0)
    mode_b = 1 if e_nxt < trig * width else (2 if rb < trig * width else 0)
    sc_a = min(e_cur, ra) if mode_a == 1 else ra
    sc_b = min(e_nxt, rb) if mode_b == 1 else rb
    return mode_a, sc_a, mode_b, sc_b


@small_kernel
def _half_panel(h, nh, cur, nxt, mode_a, sc_a, mode_b, sc_b):
    """Half ``h`` (of ``nh``; a panel with a feature at each end is halved) of the panel
    [cur, nxt] as ``(tf, tt, mode, e)``: from the end ``tf`` that carries the feature (mode,
    scale e) towards ``tt``."""
    mid = 0.5 * (cur + nxt)
    if nh == 2:
        tf = cur if h == 0 else nxt
        tt = mid
        mode = mode_a if h == 0 else mode_b
        e = sc_a if h == 0 else sc_b
    elif mode_a > 0:
        tf = cur
        tt = nxt
        mode = mode_a
        e = sc_a
    elif mode_b > 0:
        tf = nxt
        tt = cur
        mode = mode_b
        e = sc_b
    else:
        tf = cur
        tt = nxt
        mode = 0
        e = 0.0
    return tf, tt, mode, e


@small_kernel
def _angle_rule(
    kind, tf, sgn, pos, pnext, n, mapped, e, sg, fe, fd, ft, vel, law, bank, tangential, dip, rule, acc
):
    """``acc`` plus the n-point Gauss-Legendre rule in the angle on the sub-panel [pos, pnext]
    (measured from ``tf`` in the direction ``sgn``; sinh-mapped with scale ``e`` when
    ``mapped``): at each node the embedded advancing part of the line, by :func:`_inner`."""
    scale = sg[0] if kind == 0 else 1.0  # R dtheta on the lateral surface
    nr = rule[6] if (kind == 0 or sg[12] <= 0.0) else rule[7]
    if mapped:
        hw = 0.5 * math.asinh(pnext / e)
        qmid = hw
    else:
        hw = 0.5 * (pnext - pos)
        qmid = 0.5 * (pnext + pos)
    tm = tf + sgn * (e * math.sinh(qmid) if mapped else qmid)
    lo, hi = _line_interval(kind, math.cos(tm), math.sin(tm), sg, fe, fd)
    if hi > lo:
        for i in range(n):
            q = qmid + hw * _GL_NODES[n, i]
            jac = 1.0
            if mapped:
                jac = e * math.cosh(q)
                q = e * math.sinh(q)
            t = tf + sgn * q
            c = math.cos(t)
            s = math.sin(t)
            lo, hi = _line_interval(kind, c, s, sg, fe, fd)
            if not (hi > lo):
                continue
            g1, g2, g3, h1, h2, h3 = _inner(
                kind, c, s, lo, hi, sg, fe, fd, ft, vel, law, bank, tangential, dip, nr, rule[7]
            )
            wt = hw * _GL_WEIGHTS[n, i] * scale * jac
            acc = add_weighted(acc, wt, (g1, g2, g3, h1, h2, h3))
    return acc


@kernel
def _surface(kind, sg, fe, fd, ft, vel, law, bank, tangential, dip, rule, bps, eps, epsr, vtol):
    """Moments over one surface (kind 0 lateral, 1 end cap), integrated in the angle.

    Panels run between consecutive breakpoints (and, on the lateral surface with a
    tabulated profile, where a tabulated depth line reaches a body end on the advancing
    side, :func:`_depth_line_break`). A panel next to a breakpoint whose near-singularity
    scale e is below rule[5] times its width is graded geometrically towards it (both ends:
    halved; :func:`_panel_modes`, :func:`_half_panel`): sub-panel widths e, r e, r^2 e, ...
    (r = rule[4]), each about as far from the near-singularity as it is wide, with rule[3]
    points. Other panels get ceil(width rule[0]) points within [rule[1], rule[2]] (wider ones
    are split). At each angle node the embedded advancing part of the line is integrated by
    _inner (:func:`_angle_rule`).
    """
    inf = math.inf
    acc = (0.0, 0.0, 0.0, 0.0, 0.0, 0.0)
    cur = 0.0
    e_cur = inf
    er_cur = inf
    row = law[LAW_ROW] if kind == 0 else -1
    xa = sg[1]
    xb = sg[2]
    zmax = fe[0] + max(fe[3] * xa, fe[3] * xb) + math.sqrt(fe[1] * fe[1] + fe[2] * fe[2])
    while cur < _TWO_PI:
        nxt, e_nxt, er_nxt = _next_break(bps, eps, epsr, cur)
        if row >= 0:
            nxt, e_nxt, er_nxt = _depth_line_break(
                cur, nxt, e_nxt, er_nxt, fe, fd, xa, xb, zmax, row, bank, vtol
            )
        mode_a, sc_a, mode_b, sc_b = _panel_modes(cur, nxt, e_cur, er_cur, e_nxt, er_nxt, rule[5])
        nh = 2 if (mode_a > 0 and mode_b > 0) else 1
        for h in range(nh):
            tf, tt, mode, e = _half_panel(h, nh, cur, nxt, mode_a, sc_a, mode_b, sc_b)
            # sub-panels of [tf, tt], measured from tf
            total = abs(tt - tf)
            sgn = 1.0 if tt > tf else -1.0
            nplain = int(math.ceil(total * rule[0] - 1e-9))
            kplain = 1
            if nplain > rule[2]:
                kplain = (nplain + rule[2] - 1) // rule[2]
                nplain = rule[2]
            if nplain < rule[1]:
                nplain = rule[1]
            pos = 0.0
            wsub = e
            for ksub in range(MAX_GRADE + kplain):
                mapped = False
                n = nplain
                if mode == 1:
                    n = rule[3]
                    pnext = pos + wsub
                    last = pnext > total or ksub == MAX_GRADE - 1 or total - pnext < 0.5 * wsub
                    if last:
                        pnext = total
                elif mode == 2 and ksub == 0:
                    # the layer within LAYER_WIDTHS er of tf, sinh-mapped
                    n = rule[3]
                    mapped = True
                    pnext = min(total, LAYER_WIDTHS * e)
                    last = pnext >= total
                else:
                    k0 = 1 if mode == 2 else 0
                    pnext = pos + (total - pos) / (kplain - (ksub - k0))
                    last = ksub - k0 == kplain - 1
                acc = _angle_rule(
                    kind,
                    tf,
                    sgn,
                    pos,
                    pnext,
                    n,
                    mapped,
                    e,
                    sg,
                    fe,
                    fd,
                    ft,
                    vel,
                    law,
                    bank,
                    tangential,
                    dip,
                    rule,
                    acc,
                )
                if last:
                    break
                pos = pnext
                wsub *= rule[4]
        cur = nxt
        e_cur = e_nxt
        er_cur = er_nxt
    return acc


# =============================================================================
# breakpoints of the lateral surface
# =============================================================================
#: no breakpoint (NaN) and no near-singularity (inf), for padding the breakpoint tuples
_NO4 = (_NAN, _NAN, _NAN, _NAN)
_INF4 = (math.inf, math.inf, math.inf, math.inf)
_NO23 = (_NAN,) * 23
_INF23 = (math.inf,) * 23
_INF28 = (math.inf,) * 28


@small_kernel
def _screw_axis_dip(geo, dip, r, rx):
    """Group 6's candidates where the screw axis of the motion meets (or passes closest to)
    the lateral surface, the speed dip of the rate factor: the candidate angles ``r`` and
    their x ``rx`` with slots 2, 3 filled when the least speed there is below the dip's
    limit, and that least speed (inf when none)."""
    R, _, _, v1, v2, v3, w1, w2, w3 = geo
    vmin_dip = math.inf
    wn2 = w1 * w1 + w2 * w2 + w3 * w3
    if dip[0] > 0 and wn2 > 0.0:
        wn = math.sqrt(wn2)
        u1 = w1 / wn
        u2 = w2 / wn
        u3 = w3 / wn
        pitch = abs(v1 * u1 + v2 * u2 + v3 * u3)
        # a point of the axis, (omega x V)/|omega|^2, and its direction u
        p1 = (w2 * v3 - w3 * v2) / wn2
        p2 = (w3 * v1 - w1 * v3) / wn2
        p3 = (w1 * v2 - w2 * v1) / wn2
        qa = u2 * u2 + u3 * u3
        qb = p2 * u2 + p3 * u3
        qc = p2 * p2 + p3 * p3 - R * R
        if qa > 1e-12:
            disc = qb * qb - qa * qc
            if disc >= 0.0:
                sq = math.sqrt(disc)
                lam0 = (-qb - sq) / qa
                lam1 = (-qb + sq) / qa
                vmin_dip = pitch
            else:
                lam0 = -qb / qa
                lam1 = _NAN
                dist = math.sqrt(max(qc - qb * qb / qa + R * R, 0.0))
                vmin_dip = math.sqrt(pitch * pitch + wn2 * (dist - R) * (dist - R))
            if vmin_dip < dip[2]:
                ta = _wrap(math.atan2(p3 + lam0 * u3, p2 + lam0 * u2))
                tb = _wrap(math.atan2(p3 + lam1 * u3, p2 + lam1 * u2))
                r = (r[0], r[1], ta, tb)
                rx = (rx[0], rx[1], p1 + lam0 * u1, p1 + lam1 * u1)
    return r, rx, vmin_dip


@small_kernel
def _candidates(group, geo, f, g, tangential, dip):
    """Candidate angles of breakpoint group ``group`` (see :func:`_lateral_breaks`), the x
    where each is checked, and the least speed of the screw-axis dip (group 6; else inf)."""
    R, xa, xb, v1, _, _, _, w2, w3 = geo
    r = _NO4
    rx = (xa, xa, xb, xb)
    vmin_dip = math.inf
    if group < 3:
        for k in range(2):
            xe = xa if k == 0 else xb
            q = _roots_lin(f[0] + f[3] * xe, f[1] + f[4] * xe, f[2] + f[5] * xe)
            if k == 0:
                r = (q[0], q[1], r[2], r[3])
            else:
                r = (r[0], r[1], q[0], q[1])
    elif group < 6:
        r = _crossing_roots(f, g, xa, xb)
    else:
        if tangential:
            q = _roots_lin(v1, -w3 * R, w2 * R)
            r = (q[0], q[1], r[2], r[3])
        r, rx, vmin_dip = _screw_axis_dip(geo, dip, r, rx)
    return r, rx, vmin_dip


@small_kernel
def _switch_line(f, g, c, s):
    """Position x and slope dx/dtheta (of the first family's line only) at angle (c, s) of the
    line where two switch families cross, x_F = -F0/F1 (or x_G where F1 = 0)."""
    x = _NAN
    sl = 0.0
    for which in range(2):
        hh = f if which == 0 else g
        a0 = hh[0] + hh[1] * c + hh[2] * s
        a1 = hh[3] + hh[4] * c + hh[5] * s
        if a1 != 0.0:
            x = -a0 / a1
            if which == 0:
                sl = -((-hh[1] * s + hh[2] * c) * a1 - a0 * (-hh[4] * s + hh[5] * c)) / (a1 * a1)
            break
    return x, sl


@small_kernel
def _axial_slip_scale(c, s, geo, fe, fd, ft, vreg):
    """Group 6's candidate at a zero of the axial slip v_x, on a generator that meets the
    domain: ``(kept, scale)``, the scale sqrt(v_theta_min^2 + V_REG^2)/|dv_x/dtheta|."""
    R, xa, xb, _, _, _, _, w2, w3 = geo
    e = math.inf
    lo, hi = _line_interval(0, c, s, (R, xa, xb, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0), fe, fd)
    if not (hi > lo):
        return False, e
    a0 = ft[0] + ft[1] * c + ft[2] * s
    a1 = ft[4] * c + ft[5] * s
    va = a0 + a1 * lo
    vb = a0 + a1 * hi
    vmin = 0.0 if va * vb <= 0.0 else min(abs(va), abs(vb))
    rate = abs(w3 * R * s + w2 * R * c)
    if rate > 0.0:
        e = math.sqrt(vmin * vmin + vreg * vreg) / rate
    return True, e


@small_kernel
def _break_scales(group, t, c, s, x, sl, geo, fe, fd, ft, dip, vreg, vreg_n, pd, pt, ztol, vtol, vmin_dip):
    """Whether candidate ``t`` of group ``group`` lies on the integration domain, and its
    near-singularity scales ``(kept, e, er)`` (inf: none): the pole distance of the delta line
    and the ramp of its regularised switch (groups 1, 3, 5), the slip-reversal front
    (2, 4, 5), the screw-axis speed dip (6)."""
    R, xa, xb, v1, _, _, w1, w2, w3 = geo
    e = math.inf
    er = math.inf
    zeta = fe[0] + fe[1] * c + fe[2] * s + fe[3] * x
    vn = fd[1] * c + fd[2] * s + x * (fd[4] * c + fd[5] * s)
    need_e = not (group == 0 or group == 3 or group == 4)
    need_d = not (group == 1 or group == 3 or group == 5)
    if (need_e and zeta < -ztol) or (need_d and vn < -vtol):
        return False, e, er
    if group == 6:
        if x < xa - ztol or x > xb + ztol:
            return False, e, er
        rate = R * math.sqrt((w2 * c + w3 * s) ** 2 + w1 * w1)
        if rate > 0.0:
            e = max(vmin_dip, dip[1]) / rate
    if group == 1 or group == 3 or group == 5:
        e = _adist(t, pd)
        # ramp of the regularised switch across the delta line, along the
        # body end (group 1), the seabed line (3) or at fixed x (5)
        dvn = (-fd[1] * s + fd[2] * c) + x * (-fd[4] * s + fd[5] * c)
        if group == 3:
            dvn += (fd[4] * c + fd[5] * s) * sl
        if dvn != 0.0:
            er = vreg_n / abs(dvn)
    if group == 2 or group == 4 or group == 5:
        # slip-reversal front crossing the curve x(theta) of slope sl:
        # |v_tau| ~ sqrt(v_x^2 + V_REG^2), v_theta changes at |dv_theta/dtheta|
        vx = v1 - w3 * R * c + w2 * R * s
        a1 = ft[3] + ft[4] * c + ft[5] * s
        rate = abs((-ft[1] * s + ft[2] * c) + (-ft[4] * s + ft[5] * c) * x + a1 * sl)
        front = math.sqrt(vx * vx + vreg * vreg) / rate if rate > 0.0 else math.inf
        e = min(e, min(_adist(t, pt), front))
    return True, e, er


@small_kernel
def _set4(q, k, v):
    """The 4-tuple ``q`` with slot ``k`` set to ``v``."""
    return (v if k == 0 else q[0], v if k == 1 else q[1], v if k == 2 else q[2], v if k == 3 else q[3])


@kernel
def _group_breaks(group, geo, fe, fd, ft, tangential, dip, vreg, vreg_n, pd, pt, ztol, vtol):
    """Breakpoint group ``group`` of :func:`_lateral_breaks`: its four angles (NaN: none) and
    their scales ``e`` and ``er`` (inf: none)."""
    if not tangential and (group == 2 or group == 4 or group == 5):
        return _NO4, _INF4, _INF4
    f = fe if (group == 0 or group == 3 or group == 4) else (fd if (group == 1 or group == 5) else ft)
    g = fd if group == 3 else ft
    r, rx, vmin_dip = _candidates(group, geo, f, g, tangential, dip)
    tt = _NO4
    ee = _INF4
    rr = _INF4
    for k in range(4):
        t = r[k]
        if not (t == t):
            continue
        c = math.cos(t)
        s = math.sin(t)
        if group == 6 and k < 2:
            kept, e = _axial_slip_scale(c, s, geo, fe, fd, ft, vreg)
            er = math.inf
        else:
            x, sl = _switch_line(f, g, c, s) if (group >= 3 and group < 6) else (rx[k], 0.0)
            kept, e, er = _break_scales(
                group, t, c, s, x, sl, geo, fe, fd, ft, dip, vreg, vreg_n, pd, pt, ztol, vtol, vmin_dip
            )
        if kept:
            tt = _set4(tt, k, t)
            ee = _set4(ee, k, e)
            rr = _set4(rr, k, er)
    return tt, ee, rr


@kernel
def _lateral_breaks(geo, fe, fd, ft, tangential, dip, vreg, vreg_n):
    """Breakpoints in theta of the lateral surface and their near-singularity scales.

    Returned as three 28-tuples (NaN: no breakpoint; inf: no near-singularity), seven
    groups of four (:func:`_group_breaks`), and the tolerance on v.n:
    0, 1, 2: the seabed line (zeta = 0), the delta line (v.n = 0), the slip-reversal
    line (v_theta = 0) reaching the body ends (two angles per end);
    3, 4, 5: crossings seabed/delta, seabed/slip, delta/slip inside the body (roots of
    a degree-2 trigonometric polynomial, _crossing_roots);
    6: zeros of the axial slip v_x (where the slip direction turns fast if v_theta is
    small too) and where the screw axis of the motion meets (or passes closest to)
    the surface (speed dip of the rate factor).
    A breakpoint is kept only on the integration domain (the seabed line where
    delta = 1, the delta line where embedded, the others where both hold). Scales:
    angular distance to the pole of a switch line x_F = -F0/F1 (F1 = 0); width of the
    slip-reversal front sqrt(v_x^2 + V_REG^2)/|dv_theta/dtheta| along the crossing
    curve; sqrt(v_theta_min^2 + V_REG^2)/|dv_x/dtheta| at a zero of v_x; angular width
    max(v_min, floor)/(R |omega x e_theta|) of the speed dip; the ramp of the delta
    switch (groups 1, 3, 5; inf elsewhere).
    """
    R, xa, xb, v1, v2, v3, w1, w2, w3 = geo
    vscale = math.sqrt(v1 * v1 + v2 * v2 + v3 * v3) + math.sqrt(w1 * w1 + w2 * w2 + w3 * w3) * (xb - xa + R)
    ztol = 1e-9 * (xb - xa + R)
    vtol = 1e-9 * vscale
    pd = _roots_lin(fd[3], fd[4], fd[5])  # poles of x_delta
    pt = _roots_lin(ft[3], ft[4], ft[5])  # poles of x_T
    args = (geo, fe, fd, ft, tangential, dip, vreg, vreg_n, pd, pt, ztol, vtol)
    g0, h0, r0 = _group_breaks(0, *args)
    g1, h1, r1 = _group_breaks(1, *args)
    g2, h2, r2 = _group_breaks(2, *args)
    g3, h3, r3 = _group_breaks(3, *args)
    g4, h4, r4 = _group_breaks(4, *args)
    g5, h5, r5 = _group_breaks(5, *args)
    g6, h6, r6 = _group_breaks(6, *args)
    bps = g0 + g1 + g2 + g3 + g4 + g5 + g6
    eps = h0 + h1 + h2 + h3 + h4 + h5 + h6
    epsr = r0 + r1 + r2 + r3 + r4 + r5 + r6
    return bps, eps, epsr, vtol


# =============================================================================
# end caps
# =============================================================================
@kernel
def _chord_corners(k, a, b, R, oy, oz):
    """Directions (about O) of the points where the line k + a y + b z = 0 meets the rim,
    and the angular distance of each from the nearer pole of the line's rho-bound
    (the directions parallel to the line)."""
    r0, r1 = _roots_lin(k, a * R, b * R)
    d0 = _NAN
    d1 = _NAN
    e0 = math.inf
    e1 = math.inf
    if r0 == r0:
        d0 = _wrap(math.atan2(R * math.sin(r0) - oz, R * math.cos(r0) - oy))
        d1 = _wrap(math.atan2(R * math.sin(r1) - oz, R * math.cos(r1) - oy))
        par = math.atan2(b, a) + 0.5 * math.pi
        poles = (_wrap(par), _wrap(par + math.pi))
        e0 = _adist(d0, poles)
        e1 = _adist(d1, poles)
    return d0, d1, e0, e1


@small_kernel
def _cap_origin(xc, R, vel, tangential, dip):
    """Polar origin O = ``(oy, oz)`` of the end cap x = xc and the sinh map's scale ``eps_r``
    of rho (0: none): the point of least speed when the rate factor dips there, else the
    stagnation point of the in-plane slip (where the slip direction turns round a point) when
    it lies on the cap, else the centre."""
    v1, v2, v3, w1, w2, w3 = vel
    oy = 0.0
    oz = 0.0
    eps_r = 0.0
    placed = False
    if dip[0] > 0 and w1 != 0.0:
        # least speed on the cap plane: v_x = v1 + g.r with g = (-w3, w2); in-plane slip
        # u0 + w1 (-z, y) with u0 = (v2 + w3 xc, v3 - w2 xc):
        # (g g^T + w1^2 I) r = -v1 g - w1 (u0z, -u0y)
        gy = -w3
        gz = w2
        u0y = v2 + w3 * xc
        u0z = v3 - w2 * xc
        by = -v1 * gy - w1 * u0z
        bz = -v1 * gz + w1 * u0y
        a11 = gy * gy + w1 * w1
        a12 = gy * gz
        a22 = gz * gz + w1 * w1
        det = a11 * a22 - a12 * a12
        py = (a22 * by - a12 * bz) / det
        pz = (a11 * bz - a12 * by) / det
        if py * py + pz * pz < 0.81 * R * R:
            vx = v1 + gy * py + gz * pz
            sy = u0y - w1 * pz
            sz = u0z + w1 * py
            vmin = math.sqrt(vx * vx + sy * sy + sz * sz)
            if vmin < dip[2]:
                oy = py
                oz = pz
                placed = True
                eps_r = max(vmin, dip[1]) / math.sqrt(w1 * w1 + 0.5 * (gy * gy + gz * gz))
    if not placed and tangential and w1 != 0.0:
        sy = -(v3 - w2 * xc) / w1
        sz = (v2 + w3 * xc) / w1
        if sy * sy + sz * sz < 0.81 * R * R:
            oy = sy
            oz = sz
    if eps_r >= R:
        eps_r = 0.0
    return oy, oz, eps_r


@small_kernel
def _chords_crossing(e0, ey, ez, q0, qy, qz, R, oy, oz):
    """Direction (about O) of the point where the seabed chord and the delta chord cross on
    the cap (NaN: not on it), and its angular distance from the nearer direction parallel to
    either chord (inf: none)."""
    cx = _NAN
    ex = math.inf
    det = ey * qz - ez * qy
    if det != 0.0:
        py = (-e0 * qz + ez * q0) / det
        pz = (-ey * q0 + e0 * qy) / det
        if py * py + pz * pz < R * R:
            cx = _wrap(math.atan2(pz - oz, py - oy))
            pe = math.atan2(ez, ey) + 0.5 * math.pi
            pq = math.atan2(qz, qy) + 0.5 * math.pi
            ex = min(
                _adist(cx, (_wrap(pe), _wrap(pe + math.pi))), _adist(cx, (_wrap(pq), _wrap(pq + math.pi)))
            )
    return cx, ex


@kernel
def _cap_breaks(xc, sgn, R, d0, c20, c21, c22, vel, tangential, dip):
    """Geometry tuple and breakpoints (padded to 28) of the end cap x = xc, outward
    normal sgn i_M.

    Both switches are straight chords of the cap: zeta = e0 + ey y + ez z > 0 and
    v.n = sgn (v1 + w2 z - w3 y) >= 0. Polar origin O: :func:`_cap_origin`. Breakpoints:
    directions of the chord/rim corners and of the chord/chord intersection, with the
    angular distance to the nearer direction parallel to the chord (pole of the rho-bound)
    as scale.
    """
    v1, _, _, _, w2, w3 = vel
    e0 = d0 - c20 * xc
    ey = -c21
    ez = -c22
    q0 = sgn * v1
    qy = -sgn * w3
    qz = sgn * w2
    oy, oz, eps_r = _cap_origin(xc, R, vel, tangential, dip)
    sg = (xc, sgn, R, oy, oz, oy * oy + oz * oz, e0, ey, ez, q0, qy, qz, eps_r)
    ce = _chord_corners(e0, ey, ez, R, oy, oz)
    cd = _chord_corners(q0, qy, qz, R, oy, oz)
    cx, ex = _chords_crossing(e0, ey, ez, q0, qy, qz, R, oy, oz)
    bps = (ce[0], ce[1], cd[0], cd[1], cx) + _NO23
    eps = (ce[2], ce[3], cd[2], cd[3], ex) + _INF23
    return sg, bps, eps, _INF28


# =============================================================================
# the rule
# =============================================================================
@kernel
def reference_tractions(L, R, chi, c20, c21, c22, d0, vbody, law, bank):
    """Sediment force and torque (body frame, about the COM) by the reference quadrature.

    ``(c20, c21, c22)``: the E-frame vertical in the body frame; ``d0``: height of the
    seabed above the COM; ``vbody`` = (v1, v2, v3, w1, w2, w3): COM velocity and angular
    velocity in the body frame; ``law``: :func:`.laws.pack_law`.
    """
    xa = -0.5 * L - chi
    xb = 0.5 * L - chi
    rperp = math.sqrt(c21 * c21 + c22 * c22)
    v1, v2, v3, w1, w2, w3 = vbody
    tangential = law[LAW_MU] != 0.0
    # speed dip of the rate factor: (mode, floor, limit). impact35: G falls from A to 1
    # over |v| ~ V_rest, resolved where v_min < DIP_SPEEDS V_rest, down to V_rest/4;
    # semilog: log singularity at |v| -> 0 (clipped at d rate_ref), resolved where v_min
    # is below 5 % of the rotation speed scale.
    dip = (0, 0.0, 0.0)
    if law[LAW_RATE] == RATE_IMPACT35 and law[LAW_VREST] > 0.0 and law[LAW_A] != 1.0:
        dip = (1, 0.25 * law[LAW_VREST], DIP_SPEEDS * law[LAW_VREST])
    elif law[LAW_RATE] == RATE_SEMILOG and law[LAW_BETA] != 0.0 and law[LAW_RATE_REF] > 0.0:
        spin = math.sqrt(w1 * w1 + w2 * w2 + w3 * w3)
        dip = (2, law[LAW_DIAMETER] * law[LAW_RATE_REF], 0.05 * spin * (L + R))
    geo = (R, xa, xb, v1, v2, v3, w1, w2, w3)
    # switch families (k0, kc, ks, l0, lc, ls) along a lateral generator, linear in x
    fe = (d0, -R * c21, -R * c22, -c20, 0.0, 0.0)  # zeta
    fd = (0.0, v2, v3, 0.0, w3, -w2)  # v.n
    ft = (w1 * R, v3, -v2, 0.0, -w2, -w3)  # v_theta
    f1 = 0.0
    f2 = 0.0
    f3 = 0.0
    m1 = 0.0
    m2 = 0.0
    m3 = 0.0
    for surf in range(3):
        if surf == 0:
            bps, eps, epsr, vtol = _lateral_breaks(
                geo, fe, fd, ft, tangential, dip, law[LAW_VREG], law[LAW_VREG_N]
            )
            sg = (R, xa, xb, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0)
            kind = 0
            rule = LATERAL_RULE
        else:
            # end caps, when their lowest rim point is below the seabed
            xc = xb if surf == 1 else xa
            if not (d0 - c20 * xc + R * rperp > 0.0):
                continue
            sg, bps, eps, epsr = _cap_breaks(
                xc, 1.0 if surf == 1 else -1.0, R, d0, c20, c21, c22, vbody, tangential, dip
            )
            kind = 1
            rule = CAP_RULE
        g1, g2, g3, h1, h2, h3 = _surface(
            kind, sg, fe, fd, ft, vbody, law, bank, tangential, dip, rule, bps, eps, epsr, vtol
        )
        f1 += g1
        f2 += g2
        f3 += g3
        m1 += h1
        m2 += h2
        m3 += h3
    return f1, f2, f3, m1, m2, m3
