"""Geometry of a right circular cylinder cut by a horizontal plane.

A mine is a solid cylinder of length ``L`` and radius ``R``. In its body frame
(M-frame, ``docs/design.md``) the axis is ``x`` (unit vector ``i_M``, pointing to
the nose), the origin is the centre of mass, and the body spans
``x in [-L/2 - chi, L/2 - chi]`` (seed 000 eq. (42); ``chi`` = COM offset).
The axis has E-frame vertical component ``a_z = i_M . k = -sin(psi2)``; the COM
is at height ``z_c``; the horizontal plane ``z = level`` is the water surface
(``level = 0``) or the seabed (``level = -H``).

The kernels here give the part of the body *below* the plane: volume, centroid,
wetted lateral and end-cap areas, the vertical extent of the body, the burial
measures of the results table and the equivalent cylinder of seed 000 section 4.1
of a part of the body.

Derivation (re-derived from seed 000 section 4, eqs. (25)-(33); see
``docs/notes/geometry.md`` for the full summary and the printed typos):

* ``e_down`` is the unit vector normal to ``i_M`` that points most steeply
  down, ``e_down = (a_z i_M - k)/b`` with ``b = sqrt(1 - a_z^2)``; then
  ``k = a_z i_M - b e_down``. A body point ``x i_M + s e_down + t e_perp``
  (``s^2 + t^2 <= R^2``) is at height ``z_c + a_z x - b s``.
* The axis point of section ``x`` is ``d(x) = z_c - level + a_z x`` above the
  plane. The section is full (entirely below) when ``d <= -bR``, empty when
  ``d >= bR``, and otherwise cut along the chord ``s = kappa R`` with
  ``kappa(x) = d(x)/(bR)``, linear in ``x`` (seed 000 eq. (25b):
  ``kappa = 1 - h/R`` with ``h`` the segment depth, eq. (27a)).
* With ``kappa = cos(theta)`` (``theta`` = half-angle of the wetted arc) the
  circular segment below the plane has (``R = 1``)
  area ``A = theta - sin(theta) cos(theta)`` (eq. (25a)),
  first moment along ``e_down`` ``m = (2/3) sin^3(theta)``,
  wetted arc length ``2 theta``.
* Along the cut part ``dx = dkappa / g`` with ``g = a_z/(bR)``, so every
  integral over ``x`` is an integral over ``kappa`` with the exact
  antiderivatives (``sigma = sin(theta) = sqrt(1 - kappa^2)``)

  ``F0 = kappa theta - sigma + sigma^3/3``                 (int A dkappa, eq. (27b))
  ``F1 = (kappa^2/2 - 1/8) theta - kappa sigma (1 + 2 kappa^2)/8``  (int kappa A)
  ``Fm = (kappa (5 - 2 kappa^2) sigma - 3 theta)/12``      (int m dkappa, cf. eq. (32) mu_z)
  ``Fa = 2 (kappa theta - sigma)``                        (int 2 theta dkappa)

Degeneracies (no division by a tiny number anywhere):

* ``a_z < 0`` is mapped onto ``a_z > 0`` by reversing the body axis
  (``x -> -x``, ``chi -> -chi``, nose <-> tail); ``e_down`` is unchanged.
* Full/partial/empty intervals are found from the signs of ``d +- bR`` at the
  two ends, so the exactly vertical (``b = 0``: no partial sections) and
  exactly horizontal (``a_z = 0``: ``kappa`` constant) bodies need no special
  formula beyond that; their lengths are ``(-bR - d_tail)/a_z`` etc., which are
  only formed when they lie inside ``[0, L]``.
* When the cut part spans a small range of ``kappa`` (``|dkappa| < TAU``, nearly
  horizontal axis) the antiderivative differences cancel, so the same
  integrals are evaluated with an ``N_GL``-point Gauss-Legendre rule in
  ``theta`` (the integrands ``A(theta) sin(theta)`` ... are entire functions
  of ``theta`` and the interval is short, so the rule is exact to rounding);
  the mapping between ``theta`` and ``x`` is written with half-angle products
  so that it keeps full relative precision as ``dkappa -> 0``.
"""

import math

import numpy as np

from mineburial._numba import kernel, small_kernel

PI = math.pi

#: Below this range of kappa over the cut part the closed forms are replaced
#: by Gauss-Legendre quadrature in theta (see module docstring).
TAU = 0.25
#: Number of Gauss-Legendre nodes of that rule.
N_GL = 12
_GL_T, _GL_W = np.polynomial.legendre.leggauss(N_GL)
_GL_T = np.ascontiguousarray(_GL_T, dtype=np.float64)
_GL_W = np.ascontiguousarray(_GL_W, dtype=np.float64)


# ---------------------------------------------------------------------------
# circular segment (unit radius), functions of the half-angle theta
# ---------------------------------------------------------------------------
@kernel
def segment_area_unit(theta):
    """Area ``theta - sin(theta) cos(theta)`` of the unit-circle segment of
    half-angle ``theta`` (seed 000 eq. (25a) with ``R = 1``,
    ``1 - h/R = cos(theta)``); series for small ``theta`` avoids cancellation."""
    if theta < 0.35:
        return _segment_series(theta)
    return theta - math.sin(theta) * math.cos(theta)  # one sincos call (LLVM pairs them)


@small_kernel
def _segment_series(theta):
    """:func:`segment_area_unit` below ``theta = 0.35``: (u - sin u)/2 with u = 2 theta, summed
    as sum_{k>=1} (-1)^(k+1) u^(2k+1)/(2k+1)!."""
    u = 2.0 * theta
    u2 = u * u
    term = u * u2 / 6.0
    total = term
    for k in range(2, 10):
        term = -term * u2 / ((2.0 * k) * (2.0 * k + 1.0))
        total += term
    return 0.5 * total


@small_kernel
def _segment_area_sc(theta, sin_theta, cos_theta):
    """:func:`segment_area_unit` given the sine and cosine of ``theta`` (read only when ``theta >=
    0.35``), where the caller has them (the Gauss rule's nodes, :func:`_partial_gauss`)."""
    if theta < 0.35:
        return _segment_series(theta)
    return theta - sin_theta * cos_theta


@kernel
def _antiderivatives(kappa, theta, sigma):
    """Exact antiderivatives over kappa (unit radius) of the segment area,
    kappa * area, e_down moment and arc length: (F0, F1, Fm, Fa)."""
    k2 = kappa * kappa
    f0 = kappa * theta - sigma + sigma * sigma * sigma / 3.0
    f1 = (0.5 * k2 - 0.125) * theta - kappa * sigma * (1.0 + 2.0 * k2) / 8.0
    fm = (kappa * (5.0 - 2.0 * k2) * sigma - 3.0 * theta) / 12.0
    fa = 2.0 * (kappa * theta - sigma)
    return f0, f1, fm, fa


@kernel
def _cap_area(d, bR, R):
    """Below-plane area of an end cap whose centre is ``d`` above the plane;
    the cap's lowest point is ``bR`` below its centre. A cap lying in the
    plane (``b = 0, d = 0``) counts as not below (strict inequality)."""
    if d >= bR:
        return 0.0
    if d <= -bR:
        return PI * R * R
    kappa = d / bR
    return R * R * segment_area_unit(math.acos(kappa))


# ---------------------------------------------------------------------------
# the part below the plane, raw moments, a_z >= 0
# ---------------------------------------------------------------------------
@small_kernel
def _partial_span(L, a, bR, xt, xn, dt, dn, tang1, tang2, full_len):
    """The sections cut by the plane, kappa from ``k1`` to ``k2`` over x from ``p1`` to
    ``p1 + w``, and the kappa range ``dk`` that the body's length spans (``w <= 0``: none)."""
    p1 = xt + full_len
    if tang1:
        k1 = -1.0
    else:
        k1 = dt / bR
    if tang2:
        k2 = 1.0
    else:
        k2 = dn / bR
    if k1 < -1.0:
        k1 = -1.0
    if k2 > 1.0:
        k2 = 1.0
    if tang1 and tang2:
        w = 2.0 * bR / a
    elif tang1:
        # the rest of the body: keeps full_len + w = L exactly (computing
        # (dn + bR)/a instead would lose ~eps R/a of length when a_z is tiny)
        w = L - full_len
    elif tang2:
        w = (bR - dt) / a
    else:
        w = L
    if w > xn - p1:
        w = xn - p1
    if tang1 or tang2:
        dk = k2 - k1
    else:
        dk = a * L / bR
    return k1, k2, p1, w, dk


@small_kernel
def _partial_closed(R, k1, k2, tang1, tang2, w, dk, pm):
    """Volume, first moments (along ``i_M`` about the COM, along ``e_down``) and wetted
    lateral area of the partial sections by the closed forms: the integral over x is
    (w/dk) times the integral over kappa of :func:`_antiderivatives`."""
    th1 = PI if tang1 else math.acos(k1)
    th2 = 0.0 if tang2 else math.acos(k2)
    s1 = math.sqrt((1.0 - k1) * (1.0 + k1))
    s2 = math.sqrt((1.0 - k2) * (1.0 + k2))
    a1, b1, m1, l1 = _antiderivatives(k1, th1, s1)
    a2, b2, m2, l2 = _antiderivatives(k2, th2, s2)
    jx = w / dk  # dx/dkappa = bR/a
    d0 = a2 - a1
    km = 0.5 * (k1 + k2)
    vp = R * R * jx * d0
    return (
        vp,
        pm * vp + R * R * jx * jx * ((b2 - b1) - km * d0),
        R * R * R * jx * (m2 - m1),
        R * jx * (l2 - l1),
    )


@small_kernel
def _partial_gauss(R, k1, k2, tang1, tang2, w, dk, pm):
    """The same moments as :func:`_partial_closed` by Gauss-Legendre in theta, theta from th1
    (x = p1) down to th2 (x = p1 + w), where the kappa range is too short for the closed
    forms' cancellation.

    The node angles are thk = thm - 2 u t_k with u = dth/4: the rule's nodes come in pairs
    +-t_k, so one sincos of u t_k gives, by the angle-sum formulas, the sine and cosine of both
    nodes' thk (and the two sines of the fraction along x), from those of thm, thm + u and u
    (one sincos each): 9 sincos and a sine a cut instead of 38 to 50 sines and cosines. The sum
    formulas differ from the library's sines by rounding: volume and lateral area within 2e-14
    of themselves; the moments too, except from a tangency at kappa = -1 (angles near pi, whose
    sines carry the angle's absolute rounding either way: ~1e-11 of the partial part's moments,
    as far as the direct sines are from the exact values; tests/test_rhs_cost.py)."""
    if tang1:
        dth = math.acos(-k2)  # pi - acos(k2) without cancellation
        thm = PI - 0.5 * dth
    elif tang2:
        dth = math.acos(k1)
        thm = 0.5 * dth
    else:
        th1 = math.acos(k1)
        th2 = math.acos(k2)
        thm = 0.5 * (th1 + th2)
    sm = math.sin(thm)
    cm = math.cos(thm)
    if not (tang1 or tang2):
        if sm > 0.0:
            r = dk / (2.0 * sm)
            if r > 1.0:
                r = 1.0
            dth = 2.0 * math.asin(r)  # cos th2 - cos th1 = 2 sin(thm) sin(dth/2)
        else:
            dth = th1 - th2
    den = sm * math.sin(0.5 * dth)  # = (k2 - k1)/2
    degenerate = not (den > 1e-280)
    u = 0.25 * dth
    su = math.sin(u)
    cu = math.cos(u)
    sa = math.sin(thm + u)
    ca = math.cos(thm + u)
    sv = 0.0
    sx = 0.0
    ss = 0.0
    sl = 0.0
    for j in range(N_GL // 2):
        # the pair of nodes -t, +t (t > 0): _GL_T[j] = -t, _GL_T[N_GL - 1 - j] = +t
        v = u * _GL_T[N_GL - 1 - j]
        sv_ = math.sin(v)
        cv = math.cos(v)
        s2 = 2.0 * sv_ * cv  # sin(2v)
        c2 = (cv - sv_) * (cv + sv_)  # cos(2v)
        for side in range(2):
            if side == 0:
                i = j
                sg = -1.0
            else:
                i = N_GL - 1 - j
                sg = 1.0
            t = _GL_T[i]
            thk = thm - 0.5 * dth * t
            sk = sm * c2 - cm * (sg * s2)  # sin(thm - 2 v t/|t|)
            ck = cm * c2 + sm * (sg * s2)
            if degenerate:
                phi = 0.5 * (1.0 + t)
                jac = 0.5
            else:
                # fraction along x: (cos th1 - cos thk)/(cos th1 - cos th2)
                #   = sin(thm + u (1 - t)) sin(u (1 + t)) / den
                phi = ((sa * cv - ca * (sg * sv_)) * (su * cv + cu * (sg * sv_))) / den
                # d(phi)/dt = sin(thk) (dth/2)/(cos th2 - cos th1)
                jac = sk * u / den
            wk = _GL_W[i] * jac
            ak = _segment_area_sc(thk, sk, ck)
            sv += wk * ak
            sx += wk * ak * (phi - 0.5)
            ss += wk * sk * sk * sk
            sl += wk * thk
    vp = R * R * w * sv
    return vp, pm * vp + R * R * w * w * sx, R * R * R * w * (2.0 / 3.0) * ss, R * w * 2.0 * sl


@kernel
def _cut_raw_up(L, R, chi, a, c):
    """Part below the plane for ``a = a_z >= 0``; ``c = z_c - level``.

    Returns ``(V, Mx, Ms, lateral, nose_cap, tail_cap)``: volume, first
    moments along ``i_M`` (about the COM) and along ``e_down``, wetted areas:
    the full sections (d <= -bR) in closed form, the partial ones (:func:`_partial_span`)
    by :func:`_partial_closed` or :func:`_partial_gauss` (:func:`_moments_up`), the end caps
    by :func:`_cap_area`.
    """
    V, Mx, Ms, lat, dt, dn, bR = _moments_up(L, R, chi, a, c)
    return V, Mx, Ms, lat, _cap_area(dn, bR, R), _cap_area(dt, bR, R)


@kernel
def _moments_up(L, R, chi, a, c):
    """:func:`_cut_raw_up` without the end caps: ``(V, Mx, Ms, lateral, d_tail, d_nose, bR)``,
    the tail and nose sections' centres above the plane and the rim's depth below them for the
    caps (the right-hand side's cuts need the volume and its centroid only, and each cap that
    the plane crosses costs an acos and a sincos)."""
    if a > 1.0:
        a = 1.0
    b = math.sqrt((1.0 - a) * (1.0 + a))
    bR = b * R
    xt = -0.5 * L - chi
    xn = 0.5 * L - chi
    dt = c + a * xt  # tail section centre above the plane
    dn = c + a * xn  # nose section centre (dn >= dt since a >= 0)
    area = PI * R * R

    if dt >= bR:  # whole body above the plane
        return 0.0, 0.0, 0.0, 0.0, dt, dn, bR
    if dn <= -bR:  # whole body below the plane
        return area * L, area * L * (-chi), 0.0, 2.0 * PI * R * L, dt, dn, bR

    # -- full sections: x in [xt, xt + full_len] (d <= -bR) --------------
    tang1 = dt < -bR  # partial part starts at a tangency (kappa = -1)
    tang2 = dn > bR  # partial part ends at a tangency (kappa = +1)
    full_len = 0.0
    if tang1:
        full_len = -(bR + dt) / a  # a > 0 here since dn > -bR > dt
        if full_len > L:
            full_len = L
    V = area * full_len
    Mx = V * (xt + 0.5 * full_len)
    Ms = 0.0
    lat = 2.0 * PI * R * full_len

    # -- partial sections: kappa from k1 to k2, x from p1 to p1 + w ---------
    if bR <= 0.0:
        return V, Mx, Ms, lat, dt, dn, bR
    k1, k2, p1, w, dk = _partial_span(L, a, bR, xt, xn, dt, dn, tang1, tang2, full_len)
    if w <= 0.0:
        return V, Mx, Ms, lat, dt, dn, bR
    pm = p1 + 0.5 * w
    if dk >= TAU:
        vp, mx, ms, dlat = _partial_closed(R, k1, k2, tang1, tang2, w, dk, pm)
    else:
        vp, mx, ms, dlat = _partial_gauss(R, k1, k2, tang1, tang2, w, dk, pm)
    V += vp
    Mx += mx
    Ms += ms
    lat += dlat
    return V, Mx, Ms, lat, dt, dn, bR


@kernel
def _cut_raw(L, R, chi, a_z, c):
    """Raw moments of the part below the plane for any ``a_z`` (axis reversal
    for ``a_z < 0``): ``(V, Mx, Ms, lateral, nose_cap, tail_cap)``."""
    if a_z < 0.0:
        V, Mx, Ms, lat, cn, ct = _cut_raw_up(L, R, -chi, -a_z, c)
        return V, -Mx, Ms, lat, ct, cn
    return _cut_raw_up(L, R, chi, a_z, c)


@kernel
def _empty_x(L, chi, a_z):
    """Axial position where the part below the plane appears first (its
    centroid in the limit of vanishing volume): the tail end for a nose-up
    axis, the nose end for a nose-down axis, the middle when horizontal."""
    if a_z > 0.0:
        return -0.5 * L - chi
    if a_z < 0.0:
        return 0.5 * L - chi
    return -chi


# ---------------------------------------------------------------------------
# public kernels
# ---------------------------------------------------------------------------
@kernel
def e_down_body(kx, ky, kz):
    """Body-frame components of ``e_down`` given the E-frame vertical ``k``
    in body components ``(kx, ky, kz)`` (``kx = a_z``): ``e_down = (a_z i_M -
    k)/|...| = (0, -ky, -kz)/sqrt(ky^2 + kz^2)``. Returns ``(0, 0, 0)`` for a
    vertical axis, where every ``eta`` is 0 anyway."""
    n = math.sqrt(ky * ky + kz * kz)
    if n > 0.0:
        return 0.0, -ky / n, -kz / n
    return 0.0, 0.0, 0.0


@kernel
def cut_cylinder(L, R, chi, a_z, z_c, level):
    """Part of the cylinder below the plane ``z = level``.

    Returns ``(volume, x_c, eta_c, lateral_area, nose_cap_area,
    tail_cap_area)``; the centroid is ``x_c i_M + eta_c e_down`` relative to
    the COM (seed 000 eqs. (25)-(33), re-derived; eta_c = 0 for an empty part
    or a vertical axis; for an empty part x_c is the point that gets wet first).
    """
    V, Mx, Ms, lat, cn, ct = _cut_raw(L, R, chi, a_z, z_c - level)
    if V > 0.0:
        return V, Mx / V, Ms / V, lat, cn, ct
    return 0.0, _empty_x(L, chi, a_z), 0.0, lat, cn, ct


@kernel
def cut_cylinder_moments(L, R, chi, a_z, z_c, level):
    """The first three values of :func:`cut_cylinder` (``volume, x_c, eta_c``), bit for bit,
    without the wetted end caps (the right-hand side's cuts at the water surface and the seabed
    use no areas)."""
    if a_z < 0.0:  # _cut_raw's axis reversal
        V, Mx, Ms, _, _, _, _ = _moments_up(L, R, -chi, -a_z, z_c - level)
        Mx = -Mx
    else:
        V, Mx, Ms, _, _, _, _ = _moments_up(L, R, chi, a_z, z_c - level)
    if V > 0.0:
        return V, Mx / V, Ms / V
    return 0.0, _empty_x(L, chi, a_z), 0.0


@kernel
def cut_cylinder_sliver(L, R, chi, a_z, z_c, level):
    """What :func:`cut_cylinder` (``L, R, chi, a_z, z_c, level``) returns, where that is known
    without cutting: ``(kind, bound, x_empty)``.

    * ``kind`` 0: the part below the plane is empty: :func:`cut_cylinder` returns volume 0.0,
      ``x_c = x_empty`` and ``eta_c = 0.0`` exactly (the same tests on the same values as its
      own: the whole body above the plane);
    * ``kind`` 1: a sliver at the lowest rim, the plane within a kappa range under :data:`TAU`
      of the tangency (the partial sections that :func:`_partial_gauss` integrates, with no full
      section): its computed volume is at most ``bound`` (>= 0), its ``|x_c|`` at most ``L +
      |chi|`` and its ``|eta_c|`` at most ``R``. The overburden's last slice ends at the body's
      lowest point, where rounding leaves such a sliver of ~1e-37 m^3 in half its calls
      (:func:`.overburden._exact`);
    * ``kind`` 2: anything else (no bound; the caller cuts).

    The bound: with kappa from k1 = d_t/(bR) to 1 over the axial length w = (bR - d_t)/a_z and
    delta = 1 - k1 (< TAU), the Gauss rule's half-angles lie in [0, dth], dth = acos(k1) <=
    (pi/sqrt 2) sqrt(delta); the segment area of half-angle theta is at most (2/3) theta^3
    (its series alternates); the rule's weights times its Jacobian sum to 2 x at most 1.05
    (theta/2 / sin(theta/2) squared at theta = acos(1 - TAU)); so |V| <= R^2 w x 2 x 1.05 x
    (2/3) x 10.97 delta^1.5 = 15.4 R^2 w delta^1.5, and ``bound`` is twice that (rounding). A
    centroid lies in the part: |x_c| <= |x_tail| + w <= L + |chi| and |eta_c| <= R (the
    segment's centroid is inside the circle), each to rounding."""
    c = z_c - level
    a = a_z
    ch = chi
    if a_z < 0.0:  # _cut_raw's axis reversal
        a = -a_z
        ch = -chi
    if a > 1.0:
        a = 1.0
    b = math.sqrt((1.0 - a) * (1.0 + a))
    bR = b * R
    xt = -0.5 * L - ch
    xn = 0.5 * L - ch
    dt = c + a * xt
    dn = c + a * xn
    if dt >= bR:  # _cut_raw_up's "whole body above the plane"
        return 0, 0.0, _empty_x(L, chi, a_z)
    # _cut_raw_up's partial sections from a tangency at kappa = 1 only (tang2, not tang1: no full
    # section), kappa from k1 = dt/bR, the Gauss rule (dk < TAU): _partial_span's values
    if not (dn > -bR and dt >= -bR and dn > bR and bR > 0.0):
        return 2, math.inf, 0.0
    k1 = dt / bR
    if k1 < -1.0:
        k1 = -1.0
    dk = 1.0 - k1
    if not (dk < TAU):
        return 2, math.inf, 0.0
    w = (bR - dt) / a
    if w > xn - xt:
        w = xn - xt
    return 1, 32.0 * R * R * w * dk * math.sqrt(dk), 0.0


@kernel
def vertical_extent(L, R, chi, a_z, z_c):
    """Lowest and highest heights ``(z_min, z_max)`` of the body: the end
    sections are at ``z_c + a_z x`` and reach ``+- R sqrt(1 - a_z^2)``."""
    a = a_z
    if a > 1.0:
        a = 1.0
    elif a < -1.0:
        a = -1.0
    bR = R * math.sqrt((1.0 - a) * (1.0 + a))
    zt = a * (-0.5 * L - chi)
    zn = a * (0.5 * L - chi)
    lo = zt if zt < zn else zn
    hi = zn if zt < zn else zt
    return z_c + lo - bR, z_c + hi + bR


@kernel
def burial_measures(L, R, chi, a_z, z_c, level):
    """Burial of the body below the plane ``z = level``.

    Returns ``(pct_volume, pct_height, pct_area, height_proud, penetration)``:
    percent of volume, of vertical extent and of total surface area
    (lateral + both caps) below the plane; ``height_proud = max(z_max -
    level, 0)``; ``penetration = max(level - z_min, 0)``.
    """
    V, Mx, Ms, lat, cn, ct = _cut_raw(L, R, chi, a_z, z_c - level)
    z_min, z_max = vertical_extent(L, R, chi, a_z, z_c)
    v_tot = PI * R * R * L
    s_tot = 2.0 * PI * R * (L + R)
    below = level - z_min
    ext = z_max - z_min
    if below < 0.0:
        below = 0.0
    if below > ext:
        below = ext
    pct_v = 100.0 * V / v_tot
    pct_h = 100.0 * below / ext
    pct_a = 100.0 * (lat + cn + ct) / s_tot
    proud = z_max - level
    if proud < 0.0:
        proud = 0.0
    pen = level - z_min
    if pen < 0.0:
        pen = 0.0
    return pct_v, pct_h, pct_a, proud, pen


@kernel
def equivalent_of_part(L, R, chi, V, x_c, eta):
    """Equivalent cylinder (seed 000 section 4.1) of a part of volume V whose partial
    centre of volume lies at axial position x_c: ``(l, x_a, x_b, eta)``."""
    l = V / (PI * R * R)
    if l > L:
        l = L
    xa = x_c - 0.5 * l
    xb = x_c + 0.5 * l
    xt = -0.5 * L - chi
    xn = 0.5 * L - chi
    if xa < xt:  # shift, not shrink, to stay inside the body
        xa = xt
        xb = xt + l
    elif xb > xn:
        xb = xn
        xa = xn - l
    return l, xa, xb, eta
