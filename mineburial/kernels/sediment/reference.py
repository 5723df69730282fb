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

Its cost (60-350 us an evaluation) and its adaptivity (the number of panels and
points changes with the state, so the force is rough on the scale of its error) make
it the guard of the fast rule (:mod:`.fast`) in the tests, not the default.
"""

import math

import numpy as np

from mineburial._numba import kernel
from mineburial.kernels.sediment.laws import GL_NODES as _GL_NODES
from mineburial.kernels.sediment.laws import GL_WEIGHTS as _GL_WEIGHTS
from mineburial.kernels.sediment.laws import (
    LAW_VREG,
    LAW_VREG_N,
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


@kernel
def _inner(kind, c, s, lo, hi, sg, fe, fd, ft, vel, law, bank, tangential, dip, n, nm):
    """Moments of the tractions along the line at angle (c, s) for r in [lo, hi].

    The line is a generator (kind 0: point (x, R c, R s), normal (0, c, s), r = x) or a
    ray of an end cap (kind 1: point (xc, O + rho (c, s)), normal (sgn, 0, 0), r = rho,
    weight rho). It is cut into parts, each integrated by Gauss-Legendre in u with
    r = anchor + side eps sinh(u) (the sinh transformation of Johnston & Elliott 2005,
    Int. J. Numer. Meth. Eng. 62:564, resolving a near-singularity at distance eps from
    r = anchor) or r = u:

    * generator: split where the circumferential slip reverses (v_theta = T0 + T1 x = 0,
      where the slip direction turns over the length sqrt(v_x^2 + V_REG^2)/|T1|) and
      where the speed is least (the rate factor dips over ~max(v_min, floor)/|dv/dx|),
      mapped towards both (nm points on a mapped part, n otherwise; a part with a
      feature at each end is halved);
    * ray: one part, mapped from O when sg[12] > 0 (speed dip at O);
    * with a tabulated profile each part is also split in u where it crosses a
      tabulated depth (a kink of the profile), each piece getting a share of the
      points proportional to its length, at least LEVEL_POINTS.
    """
    v1, v2, v3, w1, w2, w3 = vel
    p1 = _NAN
    q1 = 0.0
    p2 = _NAN
    q2 = 0.0
    # an end set by the delta switch carries the ramp of the regularised switch
    # v_n / sqrt(v_n^2 + V_REG_N^2), over the length V_REG_N/|dv_n/dr|
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
    if kind == 0:
        R = sg[0]
        # point P + r D, normal N, depth z0 + z1 r
        px, py, pz, dx, dy, dz = 0.0, R * c, R * s, 1.0, 0.0, 0.0
        nx, ny, nz = 0.0, c, s
        z0 = fe[0] + fe[1] * c + fe[2] * s
        z1 = fe[3]
        polar = False
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
    else:
        px, py, pz, dx, dy, dz = sg[0], sg[3], sg[4], 0.0, c, s
        nx, ny, nz = sg[1], 0.0, 0.0
        z0 = sg[6] + sg[7] * sg[3] + sg[8] * sg[4]
        z1 = sg[7] * c + sg[8] * s
        polar = True
    row = law[15]
    nlev = bank.shape[2] if (row >= 0 and z1 != 0.0) else 0
    npiece = 1 + (1 if p1 == p1 else 0) + (1 if p2 == p2 else 0)
    f1 = 0.0
    f2 = 0.0
    f3 = 0.0
    m1 = 0.0
    m2 = 0.0
    m3 = 0.0
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
        mid = 0.5 * (a + b)
        for h in range(nh):
            # one part [sa, sb]: map r = anchor + side eps sinh(u)
            sa = a
            sb = b
            anchor = a
            eps = 0.0
            side = 0.0
            npts = n
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
            # the near-singular layer within LAYER_WIDTHS eps of the anchor is sinh-mapped
            # (u <= asinh(LAYER_WIDTHS)); the rest of the part is plain Gauss-Legendre
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
                for jj in range(nlev + 1):
                    u1 = ub
                    kk = npts
                    if jj < nlev:
                        j = jj if up else nlev - 1 - jj
                        dep = bank[row, 0, j]
                        if not (dep > zlo and dep < zhi):
                            continue
                        rl = (dep - z0) / z1
                        u1 = math.asinh(side * (rl - anchor) / eps) if eps > 0.0 else rl
                        if not (u1 > u0 and u1 < ub):
                            continue
                    if nlev > 0:
                        kk = min(npts, max(LEVEL_POINTS, int(npts * (u1 - u0) / total + 0.999)))
                    # kk-point Gauss-Legendre rule on [u0, u1]
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
                        g1, g2, g3 = _traction(
                            x, y, z, nx, ny, nz, z0 + z1 * r, v1, v2, v3, w1, w2, w3, law, bank
                        )
                        wgt = hu * _GL_WEIGHTS[kk, i] * jac
                        if polar:
                            wgt *= r
                        f1, f2, f3, m1, m2, m3 = add_point_traction(
                            (f1, f2, f3, m1, m2, m3), wgt, x, y, z, g1, g2, g3
                        )
                    u0 = u1
    return f1, f2, f3, m1, m2, m3


# =============================================================================
# panels in the angle (theta on the lateral surface, phi on a cap)
# =============================================================================
@kernel
def _surface(kind, sg, fe, fd, ft, vel, law, bank, tangential, dip, rule, bps, eps, epsr, vtol):
    """Moments over one surface (kind 0 lateral, 1 end cap), integrated in the angle.

    Panels run between consecutive breakpoints (and, on the lateral surface with a
    tabulated profile, where a tabulated depth line reaches a body end on the advancing
    side). A panel next to a breakpoint whose near-singularity scale e is below
    rule[5] times its width is graded geometrically towards it (both ends: halved):
    sub-panel widths e, r e, r^2 e, ... (r = rule[4]), each about as far from the
    near-singularity as it is wide, with rule[3] points. Other panels get
    ceil(width rule[0]) points within [rule[1], rule[2]] (wider ones are split).
    At each angle node the embedded advancing part of the line is integrated by _inner.
    """
    inf = math.inf
    f1 = 0.0
    f2 = 0.0
    f3 = 0.0
    m1 = 0.0
    m2 = 0.0
    m3 = 0.0
    cur = 0.0
    e_cur = inf
    er_cur = inf
    trig = rule[5]
    row = law[15] if kind == 0 else -1
    xa = sg[1]
    xb = sg[2]
    zmax = fe[0] + max(fe[3] * xa, fe[3] * xb) + math.sqrt(fe[1] * fe[1] + fe[2] * fe[2])
    scale = sg[0] if kind == 0 else 1.0  # R dtheta on the lateral surface
    nr = rule[6] if (kind == 0 or sg[12] <= 0.0) else rule[7]
    while cur < _TWO_PI:
        nxt, e_nxt, er_nxt = _next_break(bps, eps, epsr, cur)
        if row >= 0:
            # tabulated depth d reaching x = xe: (E0 - d) + E1 xe = 0
            for j in range(bank.shape[2]):
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
        width = nxt - cur
        # feature at each end: mode 1 = geometric grading (a pole-like near-singularity
        # at distance e, or a front/dip of width e), mode 2 = sinh-mapped layer (the ramp
        # of the delta switch, width er, counted where not negligibly thin), 0 = none
        ra = er_cur if er_cur > RAMP_MIN * width else inf
        rb = er_nxt if er_nxt > RAMP_MIN * width else inf
        mode_a = 1 if e_cur < trig * width else (2 if ra < trig * width else 0)
        mode_b = 1 if e_nxt < trig * width else (2 if rb < trig * width else 0)
        sc_a = min(e_cur, ra) if mode_a == 1 else ra
        sc_b = min(e_nxt, rb) if mode_b == 1 else rb
        nh = 2 if (mode_a > 0 and mode_b > 0) else 1
        mid = 0.5 * (cur + nxt)
        for h in range(nh):
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
                # n-point rule in the angle on [pos, pnext] (from tf)
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
                        f1, f2, f3, m1, m2, m3 = add_weighted(
                            (f1, f2, f3, m1, m2, m3), wt, (g1, g2, g3, h1, h2, h3)
                        )
                if last:
                    break
                pos = pnext
                wsub *= rule[4]
        cur = nxt
        e_cur = e_nxt
        er_cur = er_nxt
    return f1, f2, f3, m1, m2, m3


# =============================================================================
# breakpoints of the lateral surface
# =============================================================================
@kernel
def _lateral_breaks(geo, fe, fd, ft, tangential, dip, vreg, vreg_n):
    """Breakpoints in theta of the lateral surface and their near-singularity scales.

    Returned as two 28-tuples (NaN: no breakpoint; inf: no near-singularity), seven
    groups of four:
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
    max(v_min, floor)/(R |omega x e_theta|) of the speed dip.
    """
    R, xa, xb, v1, v2, v3, w1, w2, w3 = geo
    inf = math.inf
    vscale = math.sqrt(v1 * v1 + v2 * v2 + v3 * v3) + math.sqrt(w1 * w1 + w2 * w2 + w3 * w3) * (xb - xa + R)
    ztol = 1e-9 * (xb - xa + R)
    vtol = 1e-9 * vscale
    pd = _roots_lin(fd[3], fd[4], fd[5])  # poles of x_delta
    pt = _roots_lin(ft[3], ft[4], ft[5])  # poles of x_T
    no4 = (_NAN, _NAN, _NAN, _NAN)
    inf4 = (inf, inf, inf, inf)
    g0 = no4
    g1 = no4
    g2 = no4
    g3 = no4
    g4 = no4
    g5 = no4
    g6 = no4
    h0 = inf4
    h1 = inf4
    h2 = inf4
    h3 = inf4
    h4 = inf4
    h5 = inf4
    h6 = inf4
    r1 = inf4
    r3 = inf4
    r5 = inf4
    # screw axis of the motion (speed dip), group 6
    wn2 = w1 * w1 + w2 * w2 + w3 * w3
    for group in range(7):
        if not tangential and (group == 2 or group == 4 or group == 5):
            continue
        f = fe if (group == 0 or group == 3 or group == 4) else (fd if (group == 1 or group == 5) else ft)
        g = fd if group == 3 else ft
        # candidate angles r and, per candidate, the x where the condition is checked
        r = no4
        rx = (xa, xa, xb, xb)
        vmin_dip = inf
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
                        rx = (xa, xa, p1 + lam0 * u1, p1 + lam1 * u1)
        t0 = _NAN
        t1 = _NAN
        t2 = _NAN
        t3 = _NAN
        o0 = inf
        o1 = inf
        o2 = inf
        o3 = inf
        n0 = inf
        n1 = inf
        n2 = inf
        n3 = inf
        for k in range(4):
            t = r[k]
            if not (t == t):
                continue
            c = math.cos(t)
            s = math.sin(t)
            sl = 0.0
            x = rx[k]
            if group >= 3 and group < 6:
                # position and slope dx/dtheta of the switch line x_F = -F0/F1 (or x_G)
                x = _NAN
                for which in range(2):
                    hh = f if which == 0 else g
                    a0 = hh[0] + hh[1] * c + hh[2] * s
                    a1 = hh[3] + hh[4] * c + hh[5] * s
                    if a1 != 0.0:
                        x = -a0 / a1
                        if which == 0:
                            sl = -((-hh[1] * s + hh[2] * c) * a1 - a0 * (-hh[4] * s + hh[5] * c)) / (a1 * a1)
                        break
            e = inf
            er = inf
            if group == 6 and k < 2:
                # zero of the axial slip on a generator that meets the domain
                lo, hi = _line_interval(
                    0, c, s, (R, xa, xb, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0), fe, fd
                )
                if not (hi > lo):
                    continue
                a0 = ft[0] + ft[1] * c + ft[2] * s
                a1 = ft[4] * c + ft[5] * s
                va = a0 + a1 * lo
                vb = a0 + a1 * hi
                vmin = 0.0 if va * vb <= 0.0 else min(abs(va), abs(vb))
                rate = abs(w3 * R * s + w2 * R * c)
                if rate > 0.0:
                    e = math.sqrt(vmin * vmin + vreg * vreg) / rate
            else:
                zeta = fe[0] + fe[1] * c + fe[2] * s + fe[3] * x
                vn = fd[1] * c + fd[2] * s + x * (fd[4] * c + fd[5] * s)
                need_e = not (group == 0 or group == 3 or group == 4)
                need_d = not (group == 1 or group == 3 or group == 5)
                if (need_e and zeta < -ztol) or (need_d and vn < -vtol):
                    continue
                if group == 6:
                    if x < xa - ztol or x > xb + ztol:
                        continue
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
                    front = math.sqrt(vx * vx + vreg * vreg) / rate if rate > 0.0 else inf
                    e = min(e, min(_adist(t, pt), front))
            if k == 0:
                t0 = t
                o0 = e
                n0 = er
            elif k == 1:
                t1 = t
                o1 = e
                n1 = er
            elif k == 2:
                t2 = t
                o2 = e
                n2 = er
            else:
                t3 = t
                o3 = e
                n3 = er
        tt = (t0, t1, t2, t3)
        ee = (o0, o1, o2, o3)
        rr = (n0, n1, n2, n3)
        if group == 0:
            g0 = tt
            h0 = ee
        elif group == 1:
            g1 = tt
            h1 = ee
            r1 = rr
        elif group == 2:
            g2 = tt
            h2 = ee
        elif group == 3:
            g3 = tt
            h3 = ee
            r3 = rr
        elif group == 4:
            g4 = tt
            h4 = ee
        elif group == 5:
            g5 = tt
            h5 = ee
            r5 = rr
        else:
            g6 = tt
            h6 = ee
    bps = (
        g0[0],
        g0[1],
        g0[2],
        g0[3],
        g1[0],
        g1[1],
        g1[2],
        g1[3],
        g2[0],
        g2[1],
        g2[2],
        g2[3],
        g3[0],
        g3[1],
        g3[2],
        g3[3],
        g4[0],
        g4[1],
        g4[2],
        g4[3],
        g5[0],
        g5[1],
        g5[2],
        g5[3],
        g6[0],
        g6[1],
        g6[2],
        g6[3],
    )
    eps = (
        h0[0],
        h0[1],
        h0[2],
        h0[3],
        h1[0],
        h1[1],
        h1[2],
        h1[3],
        h2[0],
        h2[1],
        h2[2],
        h2[3],
        h3[0],
        h3[1],
        h3[2],
        h3[3],
        h4[0],
        h4[1],
        h4[2],
        h4[3],
        h5[0],
        h5[1],
        h5[2],
        h5[3],
        h6[0],
        h6[1],
        h6[2],
        h6[3],
    )
    inf = math.inf
    epsr = (
        inf,
        inf,
        inf,
        inf,
        r1[0],
        r1[1],
        r1[2],
        r1[3],
        inf,
        inf,
        inf,
        inf,
        r3[0],
        r3[1],
        r3[2],
        r3[3],
        inf,
        inf,
        inf,
        inf,
        r5[0],
        r5[1],
        r5[2],
        r5[3],
        inf,
        inf,
        inf,
        inf,
    )
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


@kernel
def _cap_breaks(xc, sgn, R, d0, c20, c21, c22, vel, tangential, dip):
    """Geometry tuple and breakpoints (padded to 28) of the end cap x = xc, outward
    normal sgn i_M.

    Both switches are straight chords of the cap: zeta = e0 + ey y + ez z > 0 and
    v.n = sgn (v1 + w2 z - w3 y) >= 0. Polar origin O: the point of least speed when
    the rate factor dips there (then rho is sinh-mapped), else the stagnation point of
    the in-plane slip (where the slip direction turns round a point) when it lies on the
    cap, else the centre. Breakpoints: directions of the chord/rim corners and of the
    chord/chord intersection, with the angular distance to the nearer direction
    parallel to the chord (pole of the rho-bound) as scale.
    """
    v1, v2, v3, w1, w2, w3 = vel
    inf = math.inf
    e0 = d0 - c20 * xc
    ey = -c21
    ez = -c22
    q0 = sgn * v1
    qy = -sgn * w3
    qz = sgn * w2
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
    sg = (xc, sgn, R, oy, oz, oy * oy + oz * oz, e0, ey, ez, q0, qy, qz, eps_r)
    ce = _chord_corners(e0, ey, ez, R, oy, oz)
    cd = _chord_corners(q0, qy, qz, R, oy, oz)
    cx = _NAN
    ex = inf
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
    n = _NAN
    bps = (
        ce[0],
        ce[1],
        cd[0],
        cd[1],
        cx,
        n,
        n,
        n,
        n,
        n,
        n,
        n,
        n,
        n,
        n,
        n,
        n,
        n,
        n,
        n,
        n,
        n,
        n,
        n,
        n,
        n,
        n,
        n,
    )
    eps = (
        ce[2],
        ce[3],
        cd[2],
        cd[3],
        ex,
        inf,
        inf,
        inf,
        inf,
        inf,
        inf,
        inf,
        inf,
        inf,
        inf,
        inf,
        inf,
        inf,
        inf,
        inf,
        inf,
        inf,
        inf,
        inf,
        inf,
        inf,
        inf,
        inf,
    )
    return (
        sg,
        bps,
        eps,
        (
            inf,
            inf,
            inf,
            inf,
            inf,
            inf,
            inf,
            inf,
            inf,
            inf,
            inf,
            inf,
            inf,
            inf,
            inf,
            inf,
            inf,
            inf,
            inf,
            inf,
            inf,
            inf,
            inf,
            inf,
            inf,
            inf,
            inf,
            inf,
        ),
    )


# =============================================================================


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
    tangential = law[6] != 0.0
    # speed dip of the rate factor: (mode, floor, limit). impact35: G falls from A to 1
    # over |v| ~ V_rest, resolved where v_min < DIP_SPEEDS V_rest, down to V_rest/4;
    # semilog: log singularity at |v| -> 0 (clipped at d rate_ref), resolved where v_min
    # is below 5 % of the rotation speed scale.
    dip = (0, 0.0, 0.0)
    if law[1] == RATE_IMPACT35 and law[3] > 0.0 and law[2] != 1.0:
        dip = (1, 0.25 * law[3], DIP_SPEEDS * law[3])
    elif law[1] == RATE_SEMILOG and law[4] != 0.0 and law[5] > 0.0:
        dip = (2, law[8] * law[5], 0.05 * math.sqrt(w1 * w1 + w2 * w2 + w3 * w3) * (L + R))
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
