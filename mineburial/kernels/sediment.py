"""Sediment resistance: surface tractions on the embedded part of the mine.

Seed 000 section 6 (Chu & Fan 2006, eqs. (63)-(75)) writes the force of the
sediment on a penetrating cylinder as a surface integral over the part of the
surface below the seabed, switched on only where the surface moves towards the
sediment (the step function delta of eq. (65): delta = 1 when v.n >= 0, with
v = V + omega x r the local velocity and n the outward normal), plus the
pore-water pressure force of eq. (73). This module evaluates that integral for
three traction laws and three strain-rate laws; ``docs/notes/sediment.md``
gives the full derivation, the constants and their sources, and the measured
error and cost of the quadrature.

Conventions (``docs/design.md``): body frame with the axis ``x`` towards the
nose, origin at the centre of mass (COM); the body spans
``x in [-L/2 - chi, L/2 - chi]`` (seed 000 eq. (42)), radius ``R``; E-frame z up;
``zeta`` = depth below the seabed.

Traction laws (code ``int(p[P_SED_RESISTANCE])``, ``layout.RESISTANCE_NAMES``).
``sigma'(zeta) = int_0^zeta (rho_s - rho_w) g dzeta'`` is the *effective*
(submerged) overburden; seed 000 eq. (68) uses the total one, but the stepper
already applies the water pressure (Archimedes with rho_w) to the whole
submerged volume, so using the total overburden would count the water twice.
All three laws act only where delta = 1 (on the receding side a water-filled
cavity opens, seed 000 section 6.1, so there is no contact there).

0 ``delta``    seed 000 eq. (74): normal pressure sigma', tangential traction
               mu G S along tau = -v_tau/|v_tau| (eq. (67)).
1 ``friction`` seed 000 section 10 item 4: normal pressure
               q = sigma' + N S G with N = p[P_SED_NC] (default pi + 2, the
               undrained bearing factor of Prandtl 1920), tangential mu q.
2 ``bearing``  in the spirit of Chu & Fan 2007 (IEEE J. Oceanic Eng. 32(1):34):
               q = sigma' + N_c(zeta) S G with the depth factor of Brinch
               Hansen (1970), N_c = p[P_SED_NC] (1 + 0.4 arctan(zeta/d)), i.e.
               5.14 at the seabed and 8.4 deep (Skempton 1951: 7.5 strip,
               9.0 circle); side adhesion alpha S G with alpha = p[P_SED_MU]
               (True 1976; Aubeny & Shi 2006: alpha ~ 1/S_t).

Rate laws G (code ``int(p[P_SED_RATE_LAW])``, ``layout.RATE_LAW_NAMES``), all
evaluated with the LOCAL speed |v| of the surface element (which reduces to the
seed's COM speed V for a pure translation):
0 ``impact35`` seed 000 eq. (70): G = A [1 - (1 - 1/A) exp(-|v|/V_rest)].
1 ``semilog``  G = 1 + beta log10(max(rate/rate_ref, 1)), rate = |v|/d
               (Biscontin & Pestana 2001; Aubeny & Shi 2006).
2 ``none``     G = 1.

Quadrature: the lateral surface is integrated generator by generator (outer
variable theta, inner x); along a generator every switch (seabed, delta,
reversal of the circumferential slip) is a linear function of x, so the inner
limits are exact, and the outer theta-panels are split at every angle where the
inner integrand changes its form (closed forms, plus the roots of degree-2
trigonometric polynomials for crossings of two switch lines). End caps are
integrated in polar coordinates about the centre (or about the stagnation
point of the in-plane slip), split at the corners of the cut disk. Gauss-Legendre
on every panel; no allocation.
"""

import math

import numpy as np

from mineburial._numba import kernel
from mineburial.kernels.layout import (P_GRAVITY, P_RHO_WATER, P_SED_A, P_SED_B, P_SED_BETA,
                                       P_SED_EV, P_SED_KP, P_SED_MU, P_SED_NC, P_SED_PORE,
                                       P_SED_PROFILE, P_SED_RATE_LAW, P_SED_RATE_REF,
                                       P_SED_RESISTANCE, P_SED_RHO, P_SED_RHO_GRAD, P_SED_S,
                                       P_SED_S_GRAD, P_SED_VREST)

# --- model codes (layout.RESISTANCE_NAMES, layout.RATE_LAW_NAMES) -----------
RES_DELTA = 0
RES_FRICTION = 1
RES_BEARING = 2
RATE_IMPACT35 = 0
RATE_SEMILOG = 1
RATE_NONE = 2

#: Regularisation speed of the slip direction, m/s: tau = -v_tau / sqrt(|v_tau|^2 + V_REG^2).
#: Makes the tangential traction continuous at rest (it grows linearly with the
#: slip below ~V_REG); 1 mm/s is the default rest-speed criterion of the
#: stepper (numerics.rest_speed, seed 000 eq. (89)).
V_REG = 1.0e-3

#: Brinch Hansen (1970) depth factor d_c = 1 + DEPTH_FACTOR * arctan(zeta/d).
DEPTH_FACTOR = 0.4

# --- quadrature constants -----------------------------------------------------
#: Lateral surface, per theta-panel: Gauss-Legendre points = ceil(width * NODES_PER_RAD)
#: clipped to [N_MIN, N_MAX] (wider panels are split); N_GRADED points on each
#: sub-panel of a panel graded geometrically (ratio GRADE_RATIO) towards a breakpoint
#: whose near-singularity scale eps is below GRADE_TRIGGER * panel width; along a
#: generator N_X points per piece, N_X_MAPPED on a sinh-mapped piece.
#: Tuple layout: (NODES_PER_RAD, N_MIN, N_MAX, N_GRADED, GRADE_RATIO, GRADE_TRIGGER,
#: N_X, N_X_MAPPED).
LATERAL_RULE = (2.0, 2, 6, 4, 3.0, 0.5, 4, 6)
#: End caps, the same layout with (N_RHO, N_RHO_MAPPED) in the last two slots.
CAP_RULE = (2.0, 2, 6, 4, 3.0, 0.5, 4, 6)
#: At most this many sub-panels when grading towards one breakpoint.
MAX_GRADE = 14
#: Samples of a degree-2 trigonometric polynomial when bracketing its roots.
N_SAMPLE = 32
#: The speed dip of the impact35 rate law (G falls from A to 1 over |v| ~ V_rest) is
#: resolved where the local minimum speed is below DIP_SPEEDS * V_rest.
DIP_SPEEDS = 7.0

_GL_MAX = 12
_GL_NODES = np.zeros((_GL_MAX + 1, _GL_MAX))
_GL_WEIGHTS = np.zeros((_GL_MAX + 1, _GL_MAX))
for _n in range(1, _GL_MAX + 1):
    _xg, _wg = np.polynomial.legendre.leggauss(_n)
    _GL_NODES[_n, :_n] = _xg
    _GL_WEIGHTS[_n, :_n] = _wg
del _n, _xg, _wg

_SAMPLE_T = 2.0 * np.pi * np.arange(N_SAMPLE + 1) / N_SAMPLE
_SAMPLE_C = np.cos(_SAMPLE_T)
_SAMPLE_S = np.sin(_SAMPLE_T)
_SAMPLE_C2 = np.cos(2.0 * _SAMPLE_T)
_SAMPLE_S2 = np.sin(2.0 * _SAMPLE_T)

_TWO_PI = 2.0 * math.pi
_NAN = math.nan


# =============================================================================
# sediment properties
# =============================================================================
@kernel
def _bank_properties(zeta, bank, row, rho_w, g):
    """Piecewise-linear profile of bank row ``row`` at depth ``zeta``.

    Returns (rho_s, S, sigma'_eff) with sigma'_eff = int_0^zeta (rho_s - rho_w) g,
    exact for the piecewise-linear density (trapezoids); constant values above
    the first and below the last tabulated depth.
    """
    d_prev = bank[row, 0, 0]
    r_prev = bank[row, 1, 0]
    s_prev = bank[row, 2, 0]
    if zeta <= d_prev:
        return r_prev, s_prev, (r_prev - rho_w) * g * zeta
    acc = (r_prev - rho_w) * d_prev
    n = bank.shape[2]
    for j in range(1, n):
        d = bank[row, 0, j]
        if not (d == d):  # NaN padding: end of this row
            break
        r = bank[row, 1, j]
        s = bank[row, 2, j]
        if zeta <= d:
            h = d - d_prev
            f = (zeta - d_prev) / h if h > 0.0 else 1.0
            rz = r_prev + f * (r - r_prev)
            sz = s_prev + f * (s - s_prev)
            acc += (0.5 * (r_prev + rz) - rho_w) * (zeta - d_prev)
            return rz, sz, acc * g
        acc += (0.5 * (r_prev + r) - rho_w) * (d - d_prev)
        d_prev = d
        r_prev = r
        s_prev = s
    acc += (r_prev - rho_w) * (zeta - d_prev)
    return r_prev, s_prev, acc * g


@kernel
def _properties(zeta, rho0, krho, s0, ks, row, bank, rho_w, g):
    """(rho_s, S, sigma'_eff) at depth zeta: linear profile when row < 0, else bank row."""
    if zeta < 0.0:
        zeta = 0.0
    if row < 0:
        rho = rho0 + krho * zeta
        s = s0 + ks * zeta
        if s < 0.0:
            s = 0.0
        sig = g * zeta * ((rho0 - rho_w) + 0.5 * krho * zeta)
        return rho, s, sig
    return _bank_properties(zeta, bank, row, rho_w, g)


@kernel
def sediment_properties(zeta, p, bank):
    """Sediment bulk density, undrained shear strength and effective overburden at depth zeta.

    Returns ``(rho_s [kg m-3], S [Pa], sigma'_eff [Pa])`` with
    ``sigma'_eff = int_0^zeta (rho_s - rho_w) g dzeta'`` (the submerged form of seed
    000 eq. (68)). ``p[P_SED_PROFILE] < 0``: linear profile rho0 + k_rho zeta,
    S0 + k_S zeta; otherwise piecewise-linear interpolation of that bank row.
    """
    return _properties(zeta, p[P_SED_RHO], p[P_SED_RHO_GRAD], p[P_SED_S], p[P_SED_S_GRAD],
                       int(p[P_SED_PROFILE]), bank, p[P_RHO_WATER], p[P_GRAVITY])


# =============================================================================
# rate laws and bearing factor
# =============================================================================
@kernel
def _rate(speed, law, a, vrest, beta, rate_ref, diameter):
    if law == RATE_IMPACT35:
        # seed 000 eq. (70), written A - (A - 1) exp(-V/V_rest) (no division by A)
        if vrest > 0.0:
            return a - (a - 1.0) * math.exp(-speed / vrest)
        return a if speed > 0.0 else 1.0
    if law == RATE_SEMILOG:
        # Biscontin & Pestana (2001), Aubeny & Shi (2006): 1 + beta log10(rate/rate_ref)
        if rate_ref > 0.0 and diameter > 0.0:
            ratio = speed / (diameter * rate_ref)
            if ratio > 1.0:
                return 1.0 + beta * math.log10(ratio)
        return 1.0
    return 1.0


@kernel
def rate_factor(speed, diameter, p):
    """Strain-rate factor G of the shear strength at local speed ``speed`` (m/s).

    Law ``int(p[P_SED_RATE_LAW])``: 0 seed 000 eq. (70) (G(0) = 1, G(inf) = A, eq. (71));
    1 semi-log law with strain rate speed/diameter; 2 G = 1.
    """
    return _rate(speed, int(p[P_SED_RATE_LAW]), p[P_SED_A], p[P_SED_VREST], p[P_SED_BETA],
                 p[P_SED_RATE_REF], diameter)


@kernel
def bearing_factor(zeta, diameter, p):
    """Bearing factor N_c of the ``bearing`` law at depth zeta for a body of diameter d.

    N_c = N_c0 (1 + 0.4 arctan(zeta/d)) with N_c0 = p[P_SED_NC] (pi + 2 = 5.14,
    Prandtl 1920, when p[P_SED_NC] <= 0) and the depth factor of Brinch Hansen (1970).
    """
    nc0 = p[P_SED_NC]
    if not (nc0 > 0.0):
        nc0 = math.pi + 2.0
    z = zeta if zeta > 0.0 else 0.0
    return nc0 * (1.0 + DEPTH_FACTOR * math.atan(z / diameter))


# =============================================================================
# traction at one surface point
# =============================================================================
@kernel
def _traction(x, y, z, nx, ny, nz, zeta, v1, v2, v3, w1, w2, w3, law, bank):
    """Traction (body frame) of the sediment on an advancing surface element.

    (x, y, z): body-frame point; (nx, ny, nz): outward normal; (v1, v2, v3): COM
    velocity in the body frame; (w1, w2, w3): angular velocity (body).
    ``law`` = (model, rate_law, A, V_rest, beta, rate_ref, mu, N0, diameter,
    rho_w, g, rho0, k_rho, S0, k_S, row).
    """
    model = law[0]
    vx = v1 + w2 * z - w3 * y
    vy = v2 + w3 * x - w1 * z
    vz = v3 + w1 * y - w2 * x
    vn = vx * nx + vy * ny + vz * nz
    tx = vx - vn * nx
    ty = vy - vn * ny
    tz = vz - vn * nz
    vt2 = tx * tx + ty * ty + tz * tz
    speed = math.sqrt(vx * vx + vy * vy + vz * vz)
    rho, s, sig = _properties(zeta, law[11], law[12], law[13], law[14], law[15], bank,
                              law[9], law[10])
    gfac = _rate(speed, law[1], law[2], law[3], law[4], law[5], law[8])
    mu = law[6]
    if model == RES_DELTA:
        pn = sig
        ft = mu * gfac * s
    elif model == RES_FRICTION:
        pn = sig + law[7] * s * gfac
        ft = mu * pn
    else:
        nc = law[7] * (1.0 + DEPTH_FACTOR * math.atan(zeta / law[8]))
        pn = sig + nc * s * gfac
        ft = mu * s * gfac
    k = ft / math.sqrt(vt2 + V_REG * V_REG)
    return -pn * nx - k * tx, -pn * ny - k * ty, -pn * nz - k * tz


# =============================================================================
# breakpoints
# =============================================================================
@kernel
def _wrap(t):
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
def _prod(a0, a1, a2, b0, b1, b2):
    """(a0 + a1 c + a2 s)(b0 + b1 c + b2 s) as h0 + h1 c + h2 s + h3 cos2t + h4 sin2t."""
    return (a0 * b0 + 0.5 * (a1 * b1 + a2 * b2), a0 * b1 + a1 * b0, a0 * b2 + a2 * b0,
            0.5 * (a1 * b1 - a2 * b2), 0.5 * (a1 * b2 + a2 * b1))


@kernel
def _trig2(h0, h1, h2, h3, h4, t):
    c = math.cos(t)
    s = math.sin(t)
    val = h0 + h1 * c + h2 * s + h3 * (c * c - s * s) + 2.0 * h4 * s * c
    der = -h1 * s + h2 * c - 2.0 * h3 * (2.0 * s * c) + 2.0 * h4 * (c * c - s * s)
    return val, der


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
    p1 = _prod(f[0], f[1], f[2], g[3], g[4], g[5])
    p2 = _prod(g[0], g[1], g[2], f[3], f[4], f[5])
    h0 = p1[0] - p2[0]
    h1 = p1[1] - p2[1]
    h2 = p1[2] - p2[2]
    h3 = p1[3] - p2[3]
    h4 = p1[4] - p2[4]
    scale = ((abs(f[0]) + abs(f[1]) + abs(f[2])) * (abs(g[3]) + abs(g[4]) + abs(g[5]))
             + (abs(g[0]) + abs(g[1]) + abs(g[2])) * (abs(f[3]) + abs(f[4]) + abs(f[5])))
    r0 = _NAN
    r1 = _NAN
    r2 = _NAN
    r3 = _NAN
    if not (abs(h0) + abs(h1) + abs(h2) + abs(h3) + abs(h4) > 1e-12 * scale):
        return r0, r1, r2, r3
    nfound = 0
    prev = h0 + h1 + h3  # t = 0
    for j in range(N_SAMPLE):
        cur = (h0 + h1 * _SAMPLE_C[j + 1] + h2 * _SAMPLE_S[j + 1] + h3 * _SAMPLE_C2[j + 1]
               + h4 * _SAMPLE_S2[j + 1])
        if (prev < 0.0 and cur >= 0.0) or (prev > 0.0 and cur <= 0.0):
            lo = _SAMPLE_T[j]
            hi = _SAMPLE_T[j + 1]
            flo = prev
            t = lo + (hi - lo) * prev / (prev - cur)
            for _ in range(8):
                val, der = _trig2(h0, h1, h2, h3, h4, t)
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
def _end_roots(f, xe):
    """Angles where the switch line of family f reaches the body end x = xe."""
    return _roots_lin(f[0] + f[3] * xe, f[1] + f[4] * xe, f[2] + f[5] * xe)


@kernel
def _fam(f, c, s):
    """Coefficients (F0, F1) of F = F0 + F1 x at angle (c, s) and their theta-derivatives."""
    return (f[0] + f[1] * c + f[2] * s, f[3] + f[4] * c + f[5] * s,
            -f[1] * s + f[2] * c, -f[4] * s + f[5] * c)


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
def _curve(f, c, s):
    """x-position and slope dx/dtheta of the switch line x_F(theta) = -F0/F1."""
    f0, f1, d0, d1 = _fam(f, c, s)
    if f1 == 0.0:
        return _NAN, 0.0
    return -f0 / f1, -(d0 * f1 - f0 * d1) / (f1 * f1)


@kernel
def _front_eps(t, x, slope, ft, R, v1, w2, w3):
    """Angular width of the slip-reversal front (v_theta = 0) where it meets the curve
    x(theta) of slope ``slope`` at (x, t): |v_tau| ~ sqrt(v_x^2 + V_REG^2) there."""
    c = math.cos(t)
    s = math.sin(t)
    vx = v1 - w3 * R * c + w2 * R * s
    t0, t1, dt0, dt1 = _fam(ft, c, s)
    rate = abs(dt0 + dt1 * x + t1 * slope)
    if not (rate > 0.0):
        return math.inf
    return math.sqrt(vx * vx + V_REG * V_REG) / rate


@kernel
def _set4(tup, k, val):
    """Copy of a 4-tuple with entry k replaced."""
    if k == 0:
        return (val, tup[1], tup[2], tup[3])
    if k == 1:
        return (tup[0], val, tup[2], tup[3])
    if k == 2:
        return (tup[0], tup[1], val, tup[3])
    return (tup[0], tup[1], tup[2], val)


@kernel
def _next_break(bps, eps, cur):
    """Smallest breakpoint above cur (2 pi when none) and the smallest scale attached to it."""
    nxt = _TWO_PI
    e = math.inf
    for k in range(len(bps)):
        b = bps[k]
        if b > cur and b < nxt:
            nxt = b
            e = eps[k]
        elif b == nxt and eps[k] < e:
            e = eps[k]
    return nxt, e


# =============================================================================
# lateral surface
# =============================================================================
@kernel
def _generator_interval(c, s, xa, xb, fe, fd):
    """Embedded (zeta > 0) and advancing (v.n >= 0) x-interval of generator (c, s)."""
    lo = xa
    hi = xb
    # seabed: zeta = E0 + E1 x > 0
    e0 = fe[0] + fe[1] * c + fe[2] * s
    e1 = fe[3]
    if e1 > 0.0:
        lo = max(lo, -e0 / e1)
    elif e1 < 0.0:
        hi = min(hi, -e0 / e1)
    elif not (e0 > 0.0):
        return 1.0, 0.0, e0, e1
    # delta: v.n = D0 + D1 x >= 0
    d0 = fd[1] * c + fd[2] * s
    d1 = fd[4] * c + fd[5] * s
    if d1 > 0.0:
        lo = max(lo, -d0 / d1)
    elif d1 < 0.0:
        hi = min(hi, -d0 / d1)
    elif d0 < 0.0:
        return 1.0, 0.0, e0, e1
    return lo, hi, e0, e1


@kernel
def _segment(a, b, eps, side, c, s, e0, e1, geo, law, bank, n):
    """Moments of the tractions on [a, b] of generator (c, s), per unit theta and R.

    With eps > 0 the piece is mapped x = a + eps sinh(u) (side > 0) or b - eps sinh(u)
    (side < 0): the sinh transformation (Johnston & Elliott 2005, Int. J. Numer. Meth.
    Eng. 62:564) that resolves a near-singularity at distance eps from that end.
    """
    R, xa, xb, v1, v2, v3, w1, w2, w3 = geo
    y = R * c
    z = R * s
    if eps > 0.0:
        hu = 0.5 * math.asinh((b - a) / eps)
    else:
        hu = 0.5 * (b - a)
    f1 = 0.0
    f2 = 0.0
    f3 = 0.0
    m1 = 0.0
    m2 = 0.0
    m3 = 0.0
    for j in range(n):
        u = hu * (1.0 + _GL_NODES[n, j])
        if eps > 0.0:
            jac = eps * math.cosh(u)
            x = a + eps * math.sinh(u) if side > 0 else b - eps * math.sinh(u)
        else:
            jac = 1.0
            x = a + u
        q1, q2, q3 = _traction(x, y, z, 0.0, c, s, e0 + e1 * x, v1, v2, v3, w1, w2, w3, law,
                               bank)
        wgt = hu * _GL_WEIGHTS[n, j] * jac
        f1 += wgt * q1
        f2 += wgt * q2
        f3 += wgt * q3
        m1 += wgt * (y * q3 - z * q2)
        m2 += wgt * (z * q1 - x * q3)
        m3 += wgt * (x * q2 - y * q1)
    return f1, f2, f3, m1, m2, m3


@kernel
def _piece(a, b, ea, eb, c, s, e0, e1, geo, law, bank, n, nm):
    """[a, b] with near-singularity scales ea, eb (0: none) at its ends."""
    if not (b > a):
        return 0.0, 0.0, 0.0, 0.0, 0.0, 0.0
    if ea >= b - a:
        ea = 0.0
    if eb >= b - a:
        eb = 0.0
    if ea > 0.0 and eb > 0.0:
        mid = 0.5 * (a + b)
        g1, g2, g3, h1, h2, h3 = _segment(a, mid, ea, 1, c, s, e0, e1, geo, law, bank, nm)
        k1, k2, k3, l1, l2, l3 = _segment(mid, b, eb, -1, c, s, e0, e1, geo, law, bank, nm)
        return g1 + k1, g2 + k2, g3 + k3, h1 + l1, h2 + l2, h3 + l3
    if ea > 0.0:
        return _segment(a, b, ea, 1, c, s, e0, e1, geo, law, bank, nm)
    if eb > 0.0:
        return _segment(a, b, eb, -1, c, s, e0, e1, geo, law, bank, nm)
    return _segment(a, b, 0.0, 0, c, s, e0, e1, geo, law, bank, n)


@kernel
def _generator(c, s, lo, hi, e0, e1, geo, fd, ft, law, bank, tangential, dip, n, nm):
    """Moments on the generator (c, s) over [lo, hi], split where the circumferential slip
    reverses (v_theta = T0 + T1 x = 0: the slip direction turns over the length
    sqrt(v_x^2 + V_REG^2)/|T1|) and where the speed is smallest (the rate factor dips
    there over ~ max(v_min, floor)/|dv/dx|); sinh maps towards both."""
    R, xa, xb, v1, v2, v3, w1, w2, w3 = geo
    vx = v1 - w3 * R * c + w2 * R * s
    t0 = ft[0] + ft[1] * c + ft[2] * s
    t1 = ft[4] * c + ft[5] * s
    p1 = _NAN
    q1 = 0.0
    p2 = _NAN
    q2 = 0.0
    if tangential and t1 != 0.0:
        xq = -t0 / t1
        if xq > lo and xq < hi:
            p1 = xq
            q1 = math.sqrt(vx * vx + V_REG * V_REG) / abs(t1)
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
        if not (p2 == p2):
            return _piece(lo, hi, 0.0, 0.0, c, s, e0, e1, geo, law, bank, n, nm)
        p1 = p2
        q1 = q2
        p2 = _NAN
    elif p2 == p2 and p2 < p1:
        p1, p2 = p2, p1
        q1, q2 = q2, q1
    if not (p2 == p2):
        g1, g2, g3, h1, h2, h3 = _piece(lo, p1, 0.0, q1, c, s, e0, e1, geo, law, bank, n, nm)
        k1, k2, k3, l1, l2, l3 = _piece(p1, hi, q1, 0.0, c, s, e0, e1, geo, law, bank, n, nm)
        return g1 + k1, g2 + k2, g3 + k3, h1 + l1, h2 + l2, h3 + l3
    g1, g2, g3, h1, h2, h3 = _piece(lo, p1, 0.0, q1, c, s, e0, e1, geo, law, bank, n, nm)
    k1, k2, k3, l1, l2, l3 = _piece(p1, p2, q1, q2, c, s, e0, e1, geo, law, bank, n, nm)
    g1 += k1
    g2 += k2
    g3 += k3
    h1 += l1
    h2 += l2
    h3 += l3
    k1, k2, k3, l1, l2, l3 = _piece(p2, hi, q2, 0.0, c, s, e0, e1, geo, law, bank, n, nm)
    return g1 + k1, g2 + k2, g3 + k3, h1 + l1, h2 + l2, h3 + l3


@kernel
def _lateral_panel(ta, tb, n, geo, fe, fd, ft, law, bank, tangential, dip, rule):
    """Lateral-surface moments of the theta-panel [ta, tb] with an n-point rule."""
    R = geo[0]
    xa = geo[1]
    xb = geo[2]
    f1 = 0.0
    f2 = 0.0
    f3 = 0.0
    m1 = 0.0
    m2 = 0.0
    m3 = 0.0
    hw = 0.5 * (tb - ta)
    tmid = 0.5 * (ta + tb)
    lo, hi, e0, e1 = _generator_interval(math.cos(tmid), math.sin(tmid), xa, xb, fe, fd)
    if not (hi > lo):
        return f1, f2, f3, m1, m2, m3
    for i in range(n):
        t = tmid + hw * _GL_NODES[n, i]
        c = math.cos(t)
        s = math.sin(t)
        lo, hi, e0, e1 = _generator_interval(c, s, xa, xb, fe, fd)
        if not (hi > lo):
            continue
        g1, g2, g3, h1, h2, h3 = _generator(c, s, lo, hi, e0, e1, geo, fd, ft, law, bank,
                                            tangential, dip, rule[6], rule[7])
        wt = hw * _GL_WEIGHTS[n, i] * R
        f1 += wt * g1
        f2 += wt * g2
        f3 += wt * g3
        m1 += wt * h1
        m2 += wt * h2
        m3 += wt * h3
    return f1, f2, f3, m1, m2, m3


@kernel
def _plain_count(width, rule):
    """(number of equal sub-panels, points per sub-panel) for an ungraded panel."""
    want = int(math.ceil(width * rule[0] - 1e-9))
    k = 1
    if want > rule[2]:
        k = (want + rule[2] - 1) // rule[2]
        want = rule[2]
    if want < rule[1]:
        want = rule[1]
    return k, want


@kernel
def _lateral_graded(t_from, t_to, eps, geo, fe, fd, ft, law, bank, tangential, dip, rule):
    """Panel [t_from, t_to] (either order), graded geometrically towards t_from where the
    integrand has a near-singularity at distance ~eps: sub-panel widths eps, r eps,
    r^2 eps, ... (r = rule[4]), each about as far from it as it is wide, with rule[3]
    points each. eps <= 0: one ordinary panel."""
    f1 = 0.0
    f2 = 0.0
    f3 = 0.0
    m1 = 0.0
    m2 = 0.0
    m3 = 0.0
    total = abs(t_to - t_from)
    if not (eps > 0.0):
        ta = min(t_from, t_to)
        k, n = _plain_count(total, rule)
        dw = total / k
        for isub in range(k):
            g1, g2, g3, h1, h2, h3 = _lateral_panel(ta + isub * dw, ta + (isub + 1) * dw, n,
                                                    geo, fe, fd, ft, law, bank, tangential,
                                                    dip, rule)
            f1 += g1
            f2 += g2
            f3 += g3
            m1 += h1
            m2 += h2
            m3 += h3
        return f1, f2, f3, m1, m2, m3
    sgn = 1.0 if t_to > t_from else -1.0
    pos = 0.0
    width = eps
    for k in range(MAX_GRADE):
        nxt = pos + width
        if nxt > total or k == MAX_GRADE - 1 or total - nxt < 0.5 * width:
            nxt = total
        ta = t_from + sgn * pos
        tb = t_from + sgn * nxt
        if tb < ta:
            ta, tb = tb, ta
        g1, g2, g3, h1, h2, h3 = _lateral_panel(ta, tb, rule[3], geo, fe, fd, ft, law, bank,
                                                tangential, dip, rule)
        f1 += g1
        f2 += g2
        f3 += g3
        m1 += h1
        m2 += h2
        m3 += h3
        if nxt >= total:
            break
        pos = nxt
        width *= rule[4]
    return f1, f2, f3, m1, m2, m3


@kernel
def _domain_gap(x, c, s, xa, xb, fe, fd):
    """How far (x, theta) is outside the integration domain: max of the violations of
    xa <= x <= xb, zeta >= 0 and v.n >= 0, each made dimensionless."""
    e = fe[0] + fe[1] * c + fe[2] * s + fe[3] * x
    d = fd[1] * c + fd[2] * s + x * (fd[4] * c + fd[5] * s)
    return e, d, max(xa - x, x - xb)


@kernel
def _lateral(geo, fe, fd, ft, law, bank, tangential, dip, rule):
    """Force and torque (body frame, about the COM) on the lateral surface.

    Families (k0, kc, ks, l0, lc, ls) of linear-in-x switch functions along a
    generator at angle t (point (x, R cos t, R sin t), normal (0, cos t, sin t)):
    fe: depth zeta; fd: normal velocity v.n; ft: circumferential slip v_theta.
    Theta-panels end where a switch line reaches a body end, where two switch
    lines cross, where the axial slip vanishes and where the screw axis of the
    motion meets the surface; only breakpoints on the integration domain are kept.
    Each carries the distance eps to the nearest near-singularity of the
    theta-integrand (the pole of a switch line x_F = -F0/F1 at F1 = 0, the width
    of the slip-reversal front, the width of the speed dip), and panels are graded
    geometrically towards breakpoints with small eps.
    """
    R, xa, xb, v1, v2, v3, w1, w2, w3 = geo
    inf = math.inf
    vscale = math.sqrt(v1 * v1 + v2 * v2 + v3 * v3) + math.sqrt(
        w1 * w1 + w2 * w2 + w3 * w3) * (xb - xa + R)
    ztol = 1e-9 * (xb - xa + R)
    vtol = 1e-9 * vscale
    pd = _roots_lin(fd[3], fd[4], fd[5])     # poles of x_delta
    # seabed line reaching the ends (x_E has no pole: E1 = -c20 is constant); kept
    # where delta = 1 there
    e_a = _end_roots(fe, xa)
    e_b = _end_roots(fe, xb)
    ea0 = e_a[0]
    ea1 = e_a[1]
    eb0 = e_b[0]
    eb1 = e_b[1]
    if ea0 == ea0:
        if _domain_gap(xa, math.cos(ea0), math.sin(ea0), xa, xb, fe, fd)[1] < -vtol:
            ea0 = _NAN
        if _domain_gap(xa, math.cos(ea1), math.sin(ea1), xa, xb, fe, fd)[1] < -vtol:
            ea1 = _NAN
    if eb0 == eb0:
        if _domain_gap(xb, math.cos(eb0), math.sin(eb0), xa, xb, fe, fd)[1] < -vtol:
            eb0 = _NAN
        if _domain_gap(xb, math.cos(eb1), math.sin(eb1), xa, xb, fe, fd)[1] < -vtol:
            eb1 = _NAN
    # delta line reaching the ends (kept where embedded), crossing the seabed line
    d_a = _end_roots(fd, xa)
    d_b = _end_roots(fd, xb)
    da0 = d_a[0]
    da1 = d_a[1]
    db0 = d_b[0]
    db1 = d_b[1]
    if da0 == da0:
        if _domain_gap(xa, math.cos(da0), math.sin(da0), xa, xb, fe, fd)[0] < -ztol:
            da0 = _NAN
        if _domain_gap(xa, math.cos(da1), math.sin(da1), xa, xb, fe, fd)[0] < -ztol:
            da1 = _NAN
    if db0 == db0:
        if _domain_gap(xb, math.cos(db0), math.sin(db0), xa, xb, fe, fd)[0] < -ztol:
            db0 = _NAN
        if _domain_gap(xb, math.cos(db1), math.sin(db1), xa, xb, fe, fd)[0] < -ztol:
            db1 = _NAN
    ed = _crossing_roots(fe, fd, xa, xb)

    ta0 = _NAN
    ta1 = _NAN
    tb0 = _NAN
    tb1 = _NAN
    xr0 = _NAN
    xr1 = _NAN
    et = (_NAN, _NAN, _NAN, _NAN)
    dt = (_NAN, _NAN, _NAN, _NAN)
    ta_eps = (inf, inf)
    tb_eps = (inf, inf)
    x0_eps = (inf, inf)
    et_eps = (inf, inf, inf, inf)
    dt_eps = (inf, inf, inf, inf)
    if tangential:
        pt = _roots_lin(ft[3], ft[4], ft[5])  # poles of x_T
        # slip-reversal line reaching the ends, kept on the domain
        t_a = _end_roots(ft, xa)
        t_b = _end_roots(ft, xb)
        ta0 = t_a[0]
        ta1 = t_a[1]
        tb0 = t_b[0]
        tb1 = t_b[1]
        if ta0 == ta0:
            g = _domain_gap(xa, math.cos(ta0), math.sin(ta0), xa, xb, fe, fd)
            if g[0] < -ztol or g[1] < -vtol:
                ta0 = _NAN
            g = _domain_gap(xa, math.cos(ta1), math.sin(ta1), xa, xb, fe, fd)
            if g[0] < -ztol or g[1] < -vtol:
                ta1 = _NAN
        if tb0 == tb0:
            g = _domain_gap(xb, math.cos(tb0), math.sin(tb0), xa, xb, fe, fd)
            if g[0] < -ztol or g[1] < -vtol:
                tb0 = _NAN
            g = _domain_gap(xb, math.cos(tb1), math.sin(tb1), xa, xb, fe, fd)
            if g[0] < -ztol or g[1] < -vtol:
                tb1 = _NAN
        ta_eps = (min(_adist(ta0, pt), _front_eps(ta0, xa, 0.0, ft, R, v1, w2, w3)),
                  min(_adist(ta1, pt), _front_eps(ta1, xa, 0.0, ft, R, v1, w2, w3)))
        tb_eps = (min(_adist(tb0, pt), _front_eps(tb0, xb, 0.0, ft, R, v1, w2, w3)),
                  min(_adist(tb1, pt), _front_eps(tb1, xb, 0.0, ft, R, v1, w2, w3)))
        # slip-reversal line crossing the seabed line (kept where delta = 1) and the
        # delta line (kept where embedded)
        etr = _crossing_roots(fe, ft, xa, xb)
        dtr = _crossing_roots(fd, ft, xa, xb)
        for k in range(4):
            t = etr[k]
            if t == t:
                c = math.cos(t)
                s = math.sin(t)
                x, sl = _curve(fe, c, s)
                if not (x == x):
                    x = _curve(ft, c, s)[0]
                    sl = 0.0
                if _domain_gap(x, c, s, xa, xb, fe, fd)[1] < -vtol:
                    t = _NAN
                e = min(_adist(t, pt), _front_eps(t, x, sl, ft, R, v1, w2, w3))
                et = _set4(et, k, t)
                et_eps = _set4(et_eps, k, e)
            t = dtr[k]
            if t == t:
                c = math.cos(t)
                s = math.sin(t)
                x, sl = _curve(fd, c, s)
                if not (x == x):
                    x = _curve(ft, c, s)[0]
                    sl = 0.0
                if _domain_gap(x, c, s, xa, xb, fe, fd)[0] < -ztol:
                    t = _NAN
                e = min(min(_adist(t, pt), _adist(t, pd)),
                        _front_eps(t, x, sl, ft, R, v1, w2, w3))
                dt = _set4(dt, k, t)
                dt_eps = _set4(dt_eps, k, e)
        # zeros of the axial slip v_x = v1 - w3 R cos t + w2 R sin t: the slip direction
        # turns fast there if the circumferential slip is small too
        x_0 = _roots_lin(v1, -w3 * R, w2 * R)
        for k in range(2):
            t = x_0[k]
            if t == t:
                c = math.cos(t)
                s = math.sin(t)
                lo, hi, e0, e1 = _generator_interval(c, s, xa, xb, fe, fd)
                if hi > lo:
                    t0 = ft[0] + ft[1] * c + ft[2] * s
                    t1 = ft[4] * c + ft[5] * s
                    va = t0 + t1 * lo
                    vb = t0 + t1 * hi
                    vmin = 0.0 if va * vb <= 0.0 else min(abs(va), abs(vb))
                    rate = abs(w3 * R * s + w2 * R * c)
                    e = math.sqrt(vmin * vmin + V_REG * V_REG) / rate if rate > 0.0 else inf
                    if k == 0:
                        xr0 = t
                        x0_eps = (e, x0_eps[1])
                    else:
                        xr1 = t
                        x0_eps = (x0_eps[0], e)

    # speed dip of the rate factor: where the screw axis of the motion meets (or passes
    # closest to) the lateral surface
    sd0 = _NAN
    sd1 = _NAN
    sd_eps = (inf, inf)
    wn2 = w1 * w1 + w2 * w2 + w3 * w3
    if dip[0] > 0 and wn2 > 0.0:
        wn = math.sqrt(wn2)
        u1 = w1 / wn
        u2 = w2 / wn
        u3 = w3 / wn
        pitch = abs(v1 * u1 + v2 * u2 + v3 * u3)
        # a point of the axis: (omega x V)/|omega|^2
        p1 = (w2 * v3 - w3 * v2) / wn2
        p2 = (w3 * v1 - w1 * v3) / wn2
        p3 = (w1 * v2 - w2 * v1) / wn2
        qa = u2 * u2 + u3 * u3
        qb = p2 * u2 + p3 * u3
        qc = p2 * p2 + p3 * p3 - R * R
        if qa > 1e-12:
            disc = qb * qb - qa * qc
            nroot = 2
            if disc >= 0.0:
                sq = math.sqrt(disc)
                lam0 = (-qb - sq) / qa
                lam1 = (-qb + sq) / qa
                vmin = pitch
            else:
                lam0 = -qb / qa
                lam1 = lam0
                nroot = 1
                dist = math.sqrt(max(qc - qb * qb / qa + R * R, 0.0))
                vmin = math.sqrt(pitch * pitch + wn2 * (dist - R) * (dist - R))
            for k in range(nroot):
                lam = lam0 if k == 0 else lam1
                x = p1 + lam * u1
                t = _wrap(math.atan2(p3 + lam * u3, p2 + lam * u2))
                c = math.cos(t)
                s = math.sin(t)
                g = _domain_gap(x, c, s, xa, xb, fe, fd)
                if vmin < dip[2] and g[0] >= -ztol and g[1] >= -vtol and g[2] <= ztol:
                    rate = R * math.sqrt((w2 * c + w3 * s) ** 2 + w1 * w1)
                    e = max(vmin, dip[1]) / rate if rate > 0.0 else inf
                    if k == 0:
                        sd0 = t
                        sd_eps = (e, sd_eps[1])
                    else:
                        sd1 = t
                        sd_eps = (sd_eps[0], e)

    bps = (ea0, ea1, eb0, eb1, da0, da1, db0, db1, ed[0], ed[1], ed[2], ed[3],
           ta0, ta1, tb0, tb1, xr0, xr1, et[0], et[1], et[2], et[3], dt[0], dt[1], dt[2],
           dt[3], sd0, sd1)
    eps = (inf, inf, inf, inf, _adist(da0, pd), _adist(da1, pd), _adist(db0, pd),
           _adist(db1, pd), _adist(ed[0], pd), _adist(ed[1], pd), _adist(ed[2], pd),
           _adist(ed[3], pd), ta_eps[0], ta_eps[1], tb_eps[0], tb_eps[1], x0_eps[0],
           x0_eps[1], et_eps[0], et_eps[1], et_eps[2], et_eps[3], dt_eps[0], dt_eps[1],
           dt_eps[2], dt_eps[3], sd_eps[0], sd_eps[1])

    f1 = 0.0
    f2 = 0.0
    f3 = 0.0
    m1 = 0.0
    m2 = 0.0
    m3 = 0.0
    cur = 0.0
    e_cur = inf
    trig = rule[5]
    while cur < _TWO_PI:
        nxt, e_nxt = _next_break(bps, eps, cur)
        width = nxt - cur
        grade_a = e_cur < trig * width
        grade_b = e_nxt < trig * width
        if grade_a and grade_b:
            mid = 0.5 * (cur + nxt)
            g1, g2, g3, h1, h2, h3 = _lateral_graded(cur, mid, e_cur, geo, fe, fd, ft, law,
                                                     bank, tangential, dip, rule)
            k1, k2, k3, l1, l2, l3 = _lateral_graded(nxt, mid, e_nxt, geo, fe, fd, ft, law,
                                                     bank, tangential, dip, rule)
            g1 += k1
            g2 += k2
            g3 += k3
            h1 += l1
            h2 += l2
            h3 += l3
        elif grade_a:
            g1, g2, g3, h1, h2, h3 = _lateral_graded(cur, nxt, e_cur, geo, fe, fd, ft, law,
                                                     bank, tangential, dip, rule)
        elif grade_b:
            g1, g2, g3, h1, h2, h3 = _lateral_graded(nxt, cur, e_nxt, geo, fe, fd, ft, law,
                                                     bank, tangential, dip, rule)
        else:
            g1, g2, g3, h1, h2, h3 = _lateral_graded(cur, nxt, 0.0, geo, fe, fd, ft, law,
                                                     bank, tangential, dip, rule)
        f1 += g1
        f2 += g2
        f3 += g3
        m1 += h1
        m2 += h2
        m3 += h3
        cur = nxt
        e_cur = e_nxt
    return f1, f2, f3, m1, m2, m3


# =============================================================================
# end caps
# =============================================================================
@kernel
def _ray_interval(ca, sa, cg):
    """rho-interval of the ray O + rho (ca, sa) inside the disk, with zeta > 0 and delta = 1."""
    oy = cg[3]
    oz = cg[4]
    od = oy * ca + oz * sa
    hi = -od + math.sqrt(max(od * od + cg[2] * cg[2] - cg[5], 0.0))
    lo = 0.0
    # zeta = (e0 + e.O) + rho (e.d) > 0
    a0 = cg[6] + cg[7] * oy + cg[8] * oz
    a1 = cg[7] * ca + cg[8] * sa
    if a1 > 0.0:
        lo = max(lo, -a0 / a1)
    elif a1 < 0.0:
        hi = min(hi, -a0 / a1)
    elif not (a0 > 0.0):
        return 1.0, 0.0
    # delta: (q0 + q.O) + rho (q.d) >= 0
    b0 = cg[9] + cg[10] * oy + cg[11] * oz
    b1 = cg[10] * ca + cg[11] * sa
    if b1 > 0.0:
        lo = max(lo, -b0 / b1)
    elif b1 < 0.0:
        hi = min(hi, -b0 / b1)
    elif b0 < 0.0:
        return 1.0, 0.0
    return lo, hi


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
def _cap_panel(ta, tb, n, cg, vel, law, bank, rule):
    """End-cap moments of the phi-panel [ta, tb] (polar about O) with an n-point rule;
    when cg[12] > 0 the radius is mapped rho = eps sinh(u) (speed dip at O)."""
    xc = cg[0]
    sgn = cg[1]
    oy = cg[3]
    oz = cg[4]
    eps = cg[12]
    v1, v2, v3, w1, w2, w3 = vel
    f1 = 0.0
    f2 = 0.0
    f3 = 0.0
    m1 = 0.0
    m2 = 0.0
    m3 = 0.0
    hw = 0.5 * (tb - ta)
    tmid = 0.5 * (ta + tb)
    lo, hi = _ray_interval(math.cos(tmid), math.sin(tmid), cg)
    if not (hi > lo):
        return f1, f2, f3, m1, m2, m3
    nr = rule[6] if eps <= 0.0 else rule[7]
    for i in range(n):
        t = tmid + hw * _GL_NODES[n, i]
        ca = math.cos(t)
        sa = math.sin(t)
        lo, hi = _ray_interval(ca, sa, cg)
        if not (hi > lo):
            continue
        wt = hw * _GL_WEIGHTS[n, i]
        if eps > 0.0:
            ua = math.asinh(lo / eps)
            ub = math.asinh(hi / eps)
        else:
            ua = lo
            ub = hi
        hr = 0.5 * (ub - ua)
        mr = 0.5 * (ub + ua)
        for j in range(nr):
            u = mr + hr * _GL_NODES[nr, j]
            if eps > 0.0:
                rho = eps * math.sinh(u)
                jac = eps * math.cosh(u)
            else:
                rho = u
                jac = 1.0
            y = oy + rho * ca
            z = oz + rho * sa
            zeta = cg[6] + cg[7] * y + cg[8] * z
            q1, q2, q3 = _traction(xc, y, z, sgn, 0.0, 0.0, zeta, v1, v2, v3, w1, w2, w3, law,
                                   bank)
            wgt = wt * hr * _GL_WEIGHTS[nr, j] * rho * jac
            f1 += wgt * q1
            f2 += wgt * q2
            f3 += wgt * q3
            m1 += wgt * (y * q3 - z * q2)
            m2 += wgt * (z * q1 - xc * q3)
            m3 += wgt * (xc * q2 - y * q1)
    return f1, f2, f3, m1, m2, m3


@kernel
def _cap_graded(t_from, t_to, eps, cg, vel, law, bank, rule):
    """Cap panel, graded geometrically towards t_from (see _lateral_graded)."""
    f1 = 0.0
    f2 = 0.0
    f3 = 0.0
    m1 = 0.0
    m2 = 0.0
    m3 = 0.0
    total = abs(t_to - t_from)
    if not (eps > 0.0):
        ta = min(t_from, t_to)
        k, n = _plain_count(total, rule)
        dw = total / k
        for isub in range(k):
            g1, g2, g3, h1, h2, h3 = _cap_panel(ta + isub * dw, ta + (isub + 1) * dw, n, cg,
                                                vel, law, bank, rule)
            f1 += g1
            f2 += g2
            f3 += g3
            m1 += h1
            m2 += h2
            m3 += h3
        return f1, f2, f3, m1, m2, m3
    sgn = 1.0 if t_to > t_from else -1.0
    pos = 0.0
    width = eps
    for k in range(MAX_GRADE):
        nxt = pos + width
        if nxt > total or k == MAX_GRADE - 1 or total - nxt < 0.5 * width:
            nxt = total
        ta = t_from + sgn * pos
        tb = t_from + sgn * nxt
        if tb < ta:
            ta, tb = tb, ta
        g1, g2, g3, h1, h2, h3 = _cap_panel(ta, tb, rule[3], cg, vel, law, bank, rule)
        f1 += g1
        f2 += g2
        f3 += g3
        m1 += h1
        m2 += h2
        m3 += h3
        if nxt >= total:
            break
        pos = nxt
        width *= rule[4]
    return f1, f2, f3, m1, m2, m3


@kernel
def _cap(xc, sgn, R, d0, c20, c21, c22, vel, law, bank, tangential, dip, rule):
    """Force and torque (body frame) on the end cap x = xc with outward normal sgn * i_M.

    Both switches are straight chords of the cap: zeta = e0 + ey y + ez z > 0 and
    v.n = sgn (v1 + w2 z - w3 y) >= 0. Polar coordinates (rho, phi) about O: the
    point of least speed when the rate factor dips there (then rho is sinh-mapped),
    else the stagnation point of the in-plane slip (where the slip direction turns
    round a point) when it lies on the cap, else the centre. phi-panels end at the
    directions of the chord/rim corners and of the chord/chord intersection, graded
    towards them by the angular distance to the nearer direction parallel to the chord.
    """
    v1, v2, v3, w1, w2, w3 = vel
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
    o2 = oy * oy + oz * oz
    cg = (xc, sgn, R, oy, oz, o2, e0, ey, ez, q0, qy, qz, eps_r)
    ce = _chord_corners(e0, ey, ez, R, oy, oz)
    cd = _chord_corners(q0, qy, qz, R, oy, oz)
    # intersection of the two chord lines, when inside the disk
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
            ex = min(_adist(cx, (_wrap(pe), _wrap(pe + math.pi))),
                     _adist(cx, (_wrap(pq), _wrap(pq + math.pi))))
    bps = (ce[0], ce[1], cd[0], cd[1], cx)
    eps = (ce[2], ce[3], cd[2], cd[3], ex)

    f1 = 0.0
    f2 = 0.0
    f3 = 0.0
    m1 = 0.0
    m2 = 0.0
    m3 = 0.0
    cur = 0.0
    e_cur = math.inf
    trig = rule[5]
    while cur < _TWO_PI:
        nxt, e_nxt = _next_break(bps, eps, cur)
        width = nxt - cur
        grade_a = e_cur < trig * width
        grade_b = e_nxt < trig * width
        if grade_a and grade_b:
            mid = 0.5 * (cur + nxt)
            g1, g2, g3, h1, h2, h3 = _cap_graded(cur, mid, e_cur, cg, vel, law, bank, rule)
            k1, k2, k3, l1, l2, l3 = _cap_graded(nxt, mid, e_nxt, cg, vel, law, bank, rule)
            g1 += k1
            g2 += k2
            g3 += k3
            h1 += l1
            h2 += l2
            h3 += l3
        elif grade_a:
            g1, g2, g3, h1, h2, h3 = _cap_graded(cur, nxt, e_cur, cg, vel, law, bank, rule)
        elif grade_b:
            g1, g2, g3, h1, h2, h3 = _cap_graded(nxt, cur, e_nxt, cg, vel, law, bank, rule)
        else:
            g1, g2, g3, h1, h2, h3 = _cap_graded(cur, nxt, 0.0, cg, vel, law, bank, rule)
        f1 += g1
        f2 += g2
        f3 += g3
        m1 += h1
        m2 += h2
        m3 += h3
        cur = nxt
        e_cur = e_nxt
    return f1, f2, f3, m1, m2, m3


@kernel
def _law(p, diameter, water_density, gravity):
    """Tuple of the traction-law constants used by _traction (see its docstring)."""
    model = int(p[P_SED_RESISTANCE])
    if model < 0 or model > 2:
        model = RES_DELTA
    n0 = p[P_SED_NC]
    if not (n0 > 0.0):
        n0 = math.pi + 2.0  # Prandtl (1920)
    return (model, int(p[P_SED_RATE_LAW]), p[P_SED_A], p[P_SED_VREST], p[P_SED_BETA],
            p[P_SED_RATE_REF], p[P_SED_MU], n0, diameter, water_density, gravity,
            p[P_SED_RHO], p[P_SED_RHO_GRAD], p[P_SED_S], p[P_SED_S_GRAD],
            int(p[P_SED_PROFILE]))


@kernel
def _dip_params(law, L, R, w1, w2, w3):
    """(mode, floor, limit) of the speed dip of the rate factor: mode 0 none; 1 impact35
    (G falls from A to 1 over |v| ~ V_rest: resolved where v_min < DIP_SPEEDS V_rest,
    down to |v| ~ V_rest/4); 2 semilog (log singularity at |v| -> 0, clipped at
    |v| = d rate_ref; resolved where v_min is below 5 % of the rotation speed scale)."""
    if law[1] == RATE_IMPACT35 and law[3] > 0.0 and law[2] != 1.0:
        return 1, 0.25 * law[3], DIP_SPEEDS * law[3]
    if law[1] == RATE_SEMILOG and law[4] != 0.0 and law[5] > 0.0:
        wn = math.sqrt(w1 * w1 + w2 * w2 + w3 * w3)
        return 2, law[8] * law[5], 0.05 * wn * (L + R)
    return 0, 0.0, 0.0


@kernel
def _surface_integral(L, R, chi, c20, c21, c22, d0, v1, v2, v3, w1, w2, w3, law, bank,
                      lateral_rule, cap_rule):
    """Force and torque (body frame, about the COM) of the tractions on the embedded,
    advancing part of the lateral surface and of the two end caps."""
    xa = -0.5 * L - chi
    xb = 0.5 * L - chi
    rperp = math.sqrt(c21 * c21 + c22 * c22)
    tangential = law[6] != 0.0
    dip = _dip_params(law, L, R, w1, w2, w3)
    geo = (R, xa, xb, v1, v2, v3, w1, w2, w3)
    vel = (v1, v2, v3, w1, w2, w3)
    # switch families (k0, kc, ks, l0, lc, ls) along a lateral generator
    fe = (d0, -R * c21, -R * c22, -c20, 0.0, 0.0)        # zeta
    fd = (0.0, v2, v3, 0.0, w3, -w2)                      # v.n
    ft = (w1 * R, v3, -v2, 0.0, -w2, -w3)                 # v_theta
    f1, f2, f3, m1, m2, m3 = _lateral(geo, fe, fd, ft, law, bank, tangential, dip,
                                      lateral_rule)
    # end caps (embedded when their lowest rim point is below the seabed)
    for k in range(2):
        xc = xb if k == 0 else xa
        if d0 - c20 * xc + R * rperp > 0.0:
            g1, g2, g3, h1, h2, h3 = _cap(xc, 1.0 if k == 0 else -1.0, R, d0, c20, c21, c22,
                                          vel, law, bank, tangential, dip, cap_rule)
            f1 += g1
            f2 += g2
            f3 += g3
            m1 += h1
            m2 += h2
            m3 += h3
    return f1, f2, f3, m1, m2, m3


# =============================================================================
# public kernel
# =============================================================================
@kernel
def sediment_force_torque(L, R, chi, rot, com, vel, omega, seabed_z, water_density, gravity, p,
                          sediment_bank):
    """Resistance of the sediment on the embedded part of the mine (seed 000 section 6).

    L, R, chi: length, radius, COM offset (body spans x in [-L/2 - chi, L/2 - chi]);
    rot: 9 floats, row-major rotation matrix body->earth; com, vel: COM position and
    velocity (E-frame, z up); omega: angular velocity (body frame); seabed_z: height of
    the seabed; water_density, gravity: rho_w and g; p: parameter vector
    (``layout.P_SED_*``); sediment_bank: profile bank (``layout``).

    Returns ``(Fx, Fy, Fz, Mx, My, Mz, added_mass_z)``: the force in the E-frame, the
    torque about the COM in the body frame, and the vertical added mass (kg) of the
    dw/dt term of the pore-pressure law eq. (73) (0 when pore pressure is off), which
    the caller puts on the left-hand side: its force is -added_mass_z * dw/dt.
    """
    c20 = rot[6]
    c21 = rot[7]
    c22 = rot[8]
    xa = -0.5 * L - chi
    xb = 0.5 * L - chi
    d0 = seabed_z - com[2]
    rperp = math.sqrt(c21 * c21 + c22 * c22)
    zeta_tip = d0 - (min(c20 * xa, c20 * xb) - R * rperp)
    if not (zeta_tip > 0.0):
        return 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0

    # COM velocity in the body frame (C^T vel)
    v1 = rot[0] * vel[0] + rot[3] * vel[1] + rot[6] * vel[2]
    v2 = rot[1] * vel[0] + rot[4] * vel[1] + rot[7] * vel[2]
    v3 = rot[2] * vel[0] + rot[5] * vel[1] + rot[8] * vel[2]
    diameter = 2.0 * R
    law = _law(p, diameter, water_density, gravity)
    f1, f2, f3, m1, m2, m3 = _surface_integral(L, R, chi, c20, c21, c22, d0, v1, v2, v3,
                                               omega[0], omega[1], omega[2], law,
                                               sediment_bank, LATERAL_RULE, CAP_RULE)

    fx = rot[0] * f1 + rot[1] * f2 + rot[2] * f3
    fy = rot[3] * f1 + rot[4] * f2 + rot[5] * f3
    fz = rot[6] * f1 + rot[7] * f2 + rot[8] * f3

    # pore-water pressure, seed 000 eq. (73), sign fixed to oppose the vertical motion
    added = 0.0
    if p[P_SED_PORE] > 0.0:
        b = min(zeta_tip, diameter)
        if p[P_SED_B] > 0.0:
            b = min(b, p[P_SED_B])
        rho_tip, s_tip, sig_tip = _properties(zeta_tip, p[P_SED_RHO], p[P_SED_RHO_GRAD],
                                              p[P_SED_S], p[P_SED_S_GRAD],
                                              int(p[P_SED_PROFILE]), sediment_bank,
                                              water_density, gravity)
        coef = math.pi / 8.0 * rho_tip * b * b * b
        fpw = 0.0
        if p[P_SED_KP] > 0.0:
            fpw = -coef * gravity * vel[2] / p[P_SED_KP]
        if p[P_SED_EV] > 0.0:
            added = coef * (1.0 + p[P_SED_EV]) / p[P_SED_EV]
        fz += fpw
        # acting on the axis at the middle of its embedded length (r_pw of eq. (75))
        lo = xa
        hi = xb
        top = d0 + R * rperp
        if c20 > 0.0:
            hi = min(hi, top / c20)
        elif c20 < 0.0:
            lo = max(lo, top / c20)
        xm = 0.5 * (lo + hi)
        # r_pw x (C^T k fpw) with r_pw = (xm, 0, 0)
        m2 += -xm * fpw * c22
        m3 += xm * fpw * c21
    return fx, fy, fz, m1, m2, m3, added
