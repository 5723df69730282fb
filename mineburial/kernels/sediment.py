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
#: Gauss-Legendre points per theta-panel of the lateral surface / per x-interval.
N_THETA = 6
N_X = 4
#: Gauss-Legendre points per phi-panel / per rho-interval of an end cap.
N_PHI = 6
N_RHO = 4
#: Largest angular width of one panel (rad); wider panels are split evenly.
MAX_PANEL = 0.5 * math.pi
#: Samples of a degree-2 trigonometric polynomial when bracketing its roots.
N_SAMPLE = 32

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
            for _ in range(6):
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
                if abs(tn - t) < 1e-13:
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
def _next_break(bps, cur):
    nxt = _TWO_PI
    for k in range(len(bps)):
        b = bps[k]
        if b > cur and b < nxt:
            nxt = b
    return nxt


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
def _lateral(R, xa, xb, fe, fd, ft, v1, v2, v3, w1, w2, w3, law, bank, tangential, nt, nxg):
    """Force and torque (body frame, about the COM) on the lateral surface.

    Families (k0, kc, ks, l0, lc, ls) of linear-in-x switch functions along a
    generator at angle t (point (x, R cos t, R sin t), normal (0, cos t, sin t)):
    fe: depth zeta; fd: normal velocity v.n; ft: circumferential slip v_theta.
    """
    # breakpoints in theta: switch lines reaching the ends, crossing each other,
    # and the zeros of the axial slip v_x = v1 - w3 R cos t + w2 R sin t.
    e_a = _end_roots(fe, xa)
    e_b = _end_roots(fe, xb)
    d_a = _end_roots(fd, xa)
    d_b = _end_roots(fd, xb)
    ed = _crossing_roots(fe, fd, xa, xb)
    if tangential:
        t_a = _end_roots(ft, xa)
        t_b = _end_roots(ft, xb)
        x_0 = _roots_lin(v1, -w3 * R, w2 * R)
        et = _crossing_roots(fe, ft, xa, xb)
        dt = _crossing_roots(fd, ft, xa, xb)
    else:
        t_a = (_NAN, _NAN)
        t_b = (_NAN, _NAN)
        x_0 = (_NAN, _NAN)
        et = (_NAN, _NAN, _NAN, _NAN)
        dt = (_NAN, _NAN, _NAN, _NAN)
    bps = (e_a[0], e_a[1], e_b[0], e_b[1], d_a[0], d_a[1], d_b[0], d_b[1],
           ed[0], ed[1], ed[2], ed[3], t_a[0], t_a[1], t_b[0], t_b[1], x_0[0], x_0[1],
           et[0], et[1], et[2], et[3], dt[0], dt[1], dt[2], dt[3])

    f1 = 0.0
    f2 = 0.0
    f3 = 0.0
    m1 = 0.0
    m2 = 0.0
    m3 = 0.0
    cur = 0.0
    while cur < _TWO_PI:
        nxt = _next_break(bps, cur)
        width = nxt - cur
        nsub = int(math.ceil(width / MAX_PANEL - 1e-9))
        if nsub < 1:
            nsub = 1
        hw = 0.5 * width / nsub
        for isub in range(nsub):
            tmid = cur + (2 * isub + 1) * hw
            lo, hi, e0, e1 = _generator_interval(math.cos(tmid), math.sin(tmid), xa, xb, fe, fd)
            if not (hi > lo):
                continue
            for i in range(nt):
                t = tmid + hw * _GL_NODES[nt, i]
                c = math.cos(t)
                s = math.sin(t)
                lo, hi, e0, e1 = _generator_interval(c, s, xa, xb, fe, fd)
                if not (hi > lo):
                    continue
                wt = hw * _GL_WEIGHTS[nt, i] * R
                y = R * c
                z = R * s
                # split at the reversal of the circumferential slip v_theta = T0 + T1 x
                xs = hi
                if tangential:
                    t1 = ft[4] * c + ft[5] * s
                    if t1 != 0.0:
                        xq = -(ft[0] + ft[1] * c + ft[2] * s) / t1
                        if xq > lo and xq < hi:
                            xs = xq
                a = lo
                b = xs
                for part in range(2):
                    if part == 1:
                        if xs >= hi:
                            break
                        a = xs
                        b = hi
                    hx = 0.5 * (b - a)
                    mx = 0.5 * (b + a)
                    for j in range(nxg):
                        x = mx + hx * _GL_NODES[nxg, j]
                        zeta = e0 + e1 * x
                        q1, q2, q3 = _traction(x, y, z, 0.0, c, s, zeta, v1, v2, v3,
                                               w1, w2, w3, law, bank)
                        wgt = wt * hx * _GL_WEIGHTS[nxg, j]
                        f1 += wgt * q1
                        f2 += wgt * q2
                        f3 += wgt * q3
                        m1 += wgt * (y * q3 - z * q2)
                        m2 += wgt * (z * q1 - x * q3)
                        m3 += wgt * (x * q2 - y * q1)
        cur = nxt
    return f1, f2, f3, m1, m2, m3


# =============================================================================
# end caps
# =============================================================================
@kernel
def _ray_interval(ca, sa, oy, oz, o2, R, e0, ey, ez, q0, qy, qz):
    """rho-interval of the ray O + rho (ca, sa) inside disk, zeta > 0 and delta = 1."""
    od = oy * ca + oz * sa
    hi = -od + math.sqrt(max(od * od + R * R - o2, 0.0))
    lo = 0.0
    # zeta = (e0 + e.O) + rho (e.d) > 0
    a0 = e0 + ey * oy + ez * oz
    a1 = ey * ca + ez * sa
    if a1 > 0.0:
        lo = max(lo, -a0 / a1)
    elif a1 < 0.0:
        hi = min(hi, -a0 / a1)
    elif not (a0 > 0.0):
        return 1.0, 0.0
    b0 = q0 + qy * oy + qz * oz
    b1 = qy * ca + qz * sa
    if b1 > 0.0:
        lo = max(lo, -b0 / b1)
    elif b1 < 0.0:
        hi = min(hi, -b0 / b1)
    elif b0 < 0.0:
        return 1.0, 0.0
    return lo, hi


@kernel
def _chord_corners(k, a, b, R, oy, oz):
    """Directions (about O) of the points where the line k + a y + b z = 0 meets the rim."""
    r0, r1 = _roots_lin(k, a * R, b * R)
    d0 = _NAN
    d1 = _NAN
    if r0 == r0:
        d0 = _wrap(math.atan2(R * math.sin(r0) - oz, R * math.cos(r0) - oy))
        d1 = _wrap(math.atan2(R * math.sin(r1) - oz, R * math.cos(r1) - oy))
    return d0, d1


@kernel
def _cap(xc, sgn, R, D0, c20, c21, c22, v1, v2, v3, w1, w2, w3, law, bank, tangential, nph, nr):
    """Force and torque (body frame) on the end cap x = xc with outward normal sgn * i_M."""
    # zeta = e0 + ey y + ez z; delta: q0 + qy y + qz z >= 0 (v.n = sgn (v_x))
    e0 = D0 - c20 * xc
    ey = -c21
    ez = -c22
    q0 = sgn * v1
    qy = -sgn * w3
    qz = sgn * w2
    # polar origin: the stagnation point of the in-plane slip, when it is on the cap
    oy = 0.0
    oz = 0.0
    if tangential and w1 != 0.0:
        sy = -(v3 - w2 * xc) / w1
        sz = (v2 + w3 * xc) / w1
        if sy * sy + sz * sz < 0.81 * R * R:
            oy = sy
            oz = sz
    o2 = oy * oy + oz * oz
    ce0, ce1 = _chord_corners(e0, ey, ez, R, oy, oz)
    cd0, cd1 = _chord_corners(q0, qy, qz, R, oy, oz)
    # intersection of the two chord lines
    cx = _NAN
    det = ey * qz - ez * qy
    if det != 0.0:
        py = (-e0 * qz + ez * q0) / det
        pz = (-ey * q0 + e0 * qy) / det
        if py * py + pz * pz < R * R:
            cx = _wrap(math.atan2(pz - oz, py - oy))
    bps = (ce0, ce1, cd0, cd1, cx)

    f1 = 0.0
    f2 = 0.0
    f3 = 0.0
    m1 = 0.0
    m2 = 0.0
    m3 = 0.0
    cur = 0.0
    while cur < _TWO_PI:
        nxt = _next_break(bps, cur)
        width = nxt - cur
        nsub = int(math.ceil(width / MAX_PANEL - 1e-9))
        if nsub < 1:
            nsub = 1
        hw = 0.5 * width / nsub
        for isub in range(nsub):
            tmid = cur + (2 * isub + 1) * hw
            lo, hi = _ray_interval(math.cos(tmid), math.sin(tmid), oy, oz, o2, R,
                                   e0, ey, ez, q0, qy, qz)
            if not (hi > lo):
                continue
            for i in range(nph):
                t = tmid + hw * _GL_NODES[nph, i]
                ca = math.cos(t)
                sa = math.sin(t)
                lo, hi = _ray_interval(ca, sa, oy, oz, o2, R, e0, ey, ez, q0, qy, qz)
                if not (hi > lo):
                    continue
                wt = hw * _GL_WEIGHTS[nph, i]
                hr = 0.5 * (hi - lo)
                mr = 0.5 * (hi + lo)
                for j in range(nr):
                    rho = mr + hr * _GL_NODES[nr, j]
                    y = oy + rho * ca
                    z = oz + rho * sa
                    zeta = e0 + ey * y + ez * z
                    q1, q2, q3 = _traction(xc, y, z, sgn, 0.0, 0.0, zeta, v1, v2, v3,
                                           w1, w2, w3, law, bank)
                    wgt = wt * hr * _GL_WEIGHTS[nr, j] * rho
                    f1 += wgt * q1
                    f2 += wgt * q2
                    f3 += wgt * q3
                    m1 += wgt * (y * q3 - z * q2)
                    m2 += wgt * (z * q1 - xc * q3)
                    m3 += wgt * (xc * q2 - y * q1)
        cur = nxt
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
    w1 = omega[0]
    w2 = omega[1]
    w3 = omega[2]
    diameter = 2.0 * R

    model = int(p[P_SED_RESISTANCE])
    if model < 0 or model > 2:
        model = RES_DELTA
    n0 = p[P_SED_NC]
    if not (n0 > 0.0):
        n0 = math.pi + 2.0  # Prandtl (1920)
    mu = p[P_SED_MU]
    law = (model, int(p[P_SED_RATE_LAW]), p[P_SED_A], p[P_SED_VREST], p[P_SED_BETA],
           p[P_SED_RATE_REF], mu, n0, diameter, water_density, gravity,
           p[P_SED_RHO], p[P_SED_RHO_GRAD], p[P_SED_S], p[P_SED_S_GRAD], int(p[P_SED_PROFILE]))
    tangential = mu != 0.0

    # switch families (k0, kc, ks, l0, lc, ls) along a lateral generator
    fe = (d0, -R * c21, -R * c22, -c20, 0.0, 0.0)        # zeta
    fd = (0.0, v2, v3, 0.0, w3, -w2)                      # v.n
    ft = (w1 * R, v3, -v2, 0.0, -w2, -w3)                 # v_theta
    f1, f2, f3, m1, m2, m3 = _lateral(R, xa, xb, fe, fd, ft, v1, v2, v3, w1, w2, w3, law,
                                      sediment_bank, tangential, N_THETA, N_X)
    # end caps (embedded when their lowest rim point is below the seabed)
    if d0 - c20 * xb + R * rperp > 0.0:
        g1, g2, g3, h1, h2, h3 = _cap(xb, 1.0, R, d0, c20, c21, c22, v1, v2, v3, w1, w2, w3, law,
                                      sediment_bank, tangential, N_PHI, N_RHO)
        f1 += g1
        f2 += g2
        f3 += g3
        m1 += h1
        m2 += h2
        m3 += h3
    if d0 - c20 * xa + R * rperp > 0.0:
        g1, g2, g3, h1, h2, h3 = _cap(xa, -1.0, R, d0, c20, c21, c22, v1, v2, v3, w1, w2, w3,
                                      law, sediment_bank, tangential, N_PHI, N_RHO)
        f1 += g1
        f2 += g2
        f3 += g3
        m1 += h1
        m2 += h2
        m3 += h3

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
