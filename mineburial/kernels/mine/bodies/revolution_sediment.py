"""Sediment tractions and pore law on the embedded surface of a body of revolution with a
piecewise-linear radius profile (issue 36 item 2): the cylinder's fast rule
(:mod:`mineburial.kernels.mine.sediment.fast`, seed 000 section 6) on the lateral surface of a
frustum, whose normal tilts by the half-angle.

Each segment ``[x0, x1]`` of the profile (stations ``xs``, radii ``rs``, about the COM, as
:mod:`.revolution_geometry`) is a frustum with ``r(x) = r0 + k (x - x0)`` (``k`` the slope, ``tan``
of the half-angle). Its lateral point at angle ``t`` is ``p = (x, r c, r s)`` (``c, s = cos t,
sin t``), its outward normal ``n = (-k, c, s) / sqrt(1 + k^2)`` and its area element ``r sqrt(1 +
k^2) dx dt``. Along a generator (``t`` fixed) the three conditions of the traction law stay linear
in ``x`` as on the cylinder:

* the depth below the seabed ``zeta = d0 - c2 . p = d0 - c20 x - r(x) (c21 c + c22 s)``;
* the normal velocity ``(v + omega x p) . n sqrt(1 + k^2) = -k v1 + v2 c + v3 s - k r(x) (w2 s -
  w3 c) + x (w3 c - w2 s)`` (the ``w1`` terms cancel);
* the circumferential slip ``w1 r(x) + (v3 - w2 x) c - (v2 + w3 x) s``;

so the embedded, advancing part of a generator is an exact interval (``N_X`` Gauss nodes, the
fast rule's), and in ``t`` the fast rule's panels carry over with each body end's own radius: the
generators embedded somewhere (``|phi| < a_any``) and along their whole length (``|phi| <
a_all``) from the two ends' depths ``e + r rp cos(phi)``; the angles where the delta line ``v.n =
0`` crosses an end (now the roots of ``K + A cos t + B sin t``, ``K = -k v1`` the tilt's share);
with friction the reversal of the circumferential slip at an end; the quarter points. The
advancing generators fill the union of the two ends' arcs ``K + A cos t + B sin t >= 0`` (half
width ``arccos(-K / amp)``, ``pi/2`` on the cylinder), integrated over their hull (a generator in a
gap advances nowhere and adds zero). The end caps are the cylinder's (:func:`.sediment.fast._cap`)
with each end's radius; a cone's apex (radius 0) has none.

A segment of constant radius is the cylinder's lateral rule itself (:func:`.sediment.fast._lateral`
on ``[x0, x1]``), so a body of one constant segment, the frustum of equal radii, gets the
cylinder's tractions bit for bit; the tapered rule at slope 0 agrees with it to rounding
(tests/test_revolution_sediment.py). The reference quadrature (:mod:`.sediment.reference`) is the
cylinder's only: a profile has the fast rule.

:func:`profile_pore_pressure` is seed 000 eq. (73) as :func:`.sediment.pore.pore_pressure` gives it
for the cylinder, with the rupture-line length bounded by the body's largest diameter (the
cylinder's ``2R``) and acting on the axis at the middle of the span whose sections reach below
the seabed (``d0 - c20 x + r(x) rp > 0``, linear on each segment).
"""

import math

from mineburial._numba import kernel
from mineburial.kernels.mine.sediment.fast import (
    N_T,
    N_X,
    _cap,
    _clip1,
    _harmonic_roots,
    _lateral,
    _local,
    _next_break,
    _quartic_angles,
)
from mineburial.kernels.mine.sediment.laws import GL_NODES as _GL_NODES
from mineburial.kernels.mine.sediment.laws import GL_WEIGHTS as _GL_WEIGHTS
from mineburial.kernels.mine.sediment.laws import (
    LAW_B,
    LAW_EV,
    LAW_G,
    LAW_KP,
    LAW_MU,
    _law_properties,
    _traction,
    add_point_traction,
    add_weighted,
)

_PI = math.pi
_TWO_PI = 2.0 * math.pi
_HALF_PI = 0.5 * math.pi


@kernel
def _tapered_generator(c, s, rho0, k, xa, xb, d0, c20, c21, c22, vbody, law, bank):
    """Moments of the tractions along the generator at angle (c, s) of the frustum ``r = rho0 + k x``
    on ``[xa, xb]``, per unit ``dt`` (the area element ``r sqrt(1 + k^2) dx`` inside)."""
    v1, v2, v3, w1, w2, w3 = vbody
    acc = (0.0, 0.0, 0.0, 0.0, 0.0, 0.0)
    stretch = math.sqrt(1.0 + k * k)
    nx = -k / stretch
    ny = c / stretch
    nz = s / stretch
    lo = xa
    hi = xb
    # seabed: zeta = a0 + a1 x > 0
    g = c21 * c + c22 * s
    a0 = d0 - rho0 * g
    a1 = -c20 - k * g
    if a1 > 0.0:
        lo = max(lo, -a0 / a1)
    elif a1 < 0.0:
        hi = min(hi, -a0 / a1)
    elif not (a0 > 0.0):
        return acc
    # advancing: v.n sqrt(1 + k^2) = b0 + b1 x >= 0
    h2 = w2 * s - w3 * c
    b0 = -k * v1 + v2 * c + v3 * s - k * rho0 * h2
    b1 = -(1.0 + k * k) * h2
    if b1 > 0.0:
        lo = max(lo, -b0 / b1)
    elif b1 < 0.0:
        hi = min(hi, -b0 / b1)
    elif b0 < 0.0:
        return acc
    if not (hi > lo):
        return acc
    h = 0.5 * (hi - lo)
    mid = 0.5 * (hi + lo)
    for i in range(N_X):
        x = mid + h * _GL_NODES[N_X, i]
        r = rho0 + k * x
        wgt = h * _GL_WEIGHTS[N_X, i] * r * stretch
        y = r * c
        z = r * s
        g1, g2, g3 = _traction(x, y, z, nx, ny, nz, a0 + a1 * x, v1, v2, v3, w1, w2, w3, law, bank)
        acc = add_point_traction(acc, wgt, x, y, z, g1, g2, g3)
    return acc


@kernel
def _end_arc(kk, a, b):
    """The arc where ``kk + a cos t + b sin t >= 0``: ``(centre, half width)``; half width -1 when
    there is none, pi when it is the whole circle."""
    amp = math.hypot(a, b)
    if amp > 0.0:
        return math.atan2(b, a), math.acos(_clip1(-kk / amp))
    if kk > 0.0:
        return 0.0, _PI
    return 0.0, -1.0


@kernel
def _trig2_angles(c0, ca1, cb1, ca2, cb2):
    """The four angles of the zeros of the degree-2 trigonometric polynomial ``c0 + ca1 cos t + cb1
    sin t + ca2 cos 2t + cb2 sin 2t`` (a tapered generator's has a free constant term, ``c20 k v1``):
    :func:`.sediment.fast._quartic_angles`, the cylinder's root finder (Durand-Kerner sweeps from
    fixed starts until they converge), shared. NaN when the quartic degenerates."""
    return _quartic_angles(c0, ca1, cb1, ca2, cb2)


@kernel
def tapered_crossing_coefficients(rho0, k, d0, c20, c21, c22, vbody):
    """``(c0, ca1, cb1, ca2, cb2)`` of ``P(t) = a0 b1 - a1 b0``, whose zeros are the generators on
    which the seabed line (``zeta = a0 + a1 x = 0``) and the delta line (``v.n = b0 + b1 x = 0``)
    cross (:func:`_tapered_generator`'s ``a0, a1, b0, b1``). With ``g = c21 c + c22 s``, ``h = w2 s -
    w3 c``, ``V = v2 c + v3 s``, ``K = -k v1``: ``a0 = d0 - rho0 g``, ``a1 = -c20 - k g``, ``b0 = K + V
    - k rho0 h``, ``b1 = -(1 + k^2) h``, so ``P = g (rho0 h + k V + k K) + A0 h + c20 V + c20 K``,
    ``A0 = -(1 + k^2) d0 - k rho0 c20`` (for ``k = 0`` the cylinder's polynomial of
    :func:`.sediment.fast._crossing_angles`)."""
    v1, v2, v3, w1, w2, w3 = vbody
    kk = -k * v1
    a0 = -(1.0 + k * k) * d0 - k * rho0 * c20
    hc = -rho0 * w3 + k * v2  # g's partner, rho0 h + k V = hc cos t + hs sin t
    hs = rho0 * w2 + k * v3
    c0 = c20 * kk + 0.5 * (c21 * hc + c22 * hs)
    ca1 = -a0 * w3 + c20 * v2 + k * kk * c21
    cb1 = a0 * w2 + c20 * v3 + k * kk * c22
    ca2 = 0.5 * (c21 * hc - c22 * hs)
    cb2 = 0.5 * (c21 * hs + c22 * hc)
    return c0, ca1, cb1, ca2, cb2


@kernel
def _on_tapered(t, tdeep, a_any, rho0, k, x0, x1, r0, r1, d0, c20, c21, c22, rp):
    """Crossing angle ``t`` as a breakpoint (offset from ``tdeep``, clamped like the others), as
    :func:`.sediment.fast._on_body` makes the cylinder's: where the crossing lies beyond a body end
    (the seabed line's ``x`` at ``t`` outside ``[x0, x1]``), the angle where the seabed line reaches
    that end instead, on the same side of ``tdeep``; so a crossing outside the body adds no panel
    and none jumps."""
    p = _local(t, tdeep, a_any)
    g = c21 * math.cos(t) + c22 * math.sin(t)
    a1 = -c20 - k * g
    if a1 == 0.0 or not (rp > 0.0):
        return p
    xc = -(d0 - rho0 * g) / a1  # the seabed line's x at t
    if xc > x1:
        e = d0 - c20 * x1
        r = r1
    elif xc < x0:
        e = d0 - c20 * x0
        r = r0
    else:
        return p
    if r > 0.0:
        a_end = math.acos(_clip1(-e / (r * rp)))
    else:
        a_end = _PI if e > 0.0 else 0.0
    return min(a_end, a_any) if p >= 0.0 else -min(a_end, a_any)


@kernel
def tapered_lateral(x0, x1, r0, r1, d0, c20, c21, c22, vbody, law, bank, tangential):
    """Moments of the tractions over the lateral surface of the frustum ``[x0, x1]`` with end radii
    ``r0, r1`` (module docstring: the fast rule's panels with each end's radius)."""
    v1, v2, v3, w1, w2, w3 = vbody
    acc = (0.0, 0.0, 0.0, 0.0, 0.0, 0.0)
    k = (r1 - r0) / (x1 - x0)
    rho0 = r0 - k * x0
    rp = math.sqrt(c21 * c21 + c22 * c22)
    e0 = d0 - c20 * x0  # depth of the axis at each end; a section's deepest point is r rp lower
    e1 = d0 - c20 * x1
    if rp > 0.0:
        b0 = math.acos(_clip1(-e0 / (r0 * rp))) if r0 > 0.0 else (_PI if e0 > 0.0 else 0.0)
        b1 = math.acos(_clip1(-e1 / (r1 * rp))) if r1 > 0.0 else (_PI if e1 > 0.0 else 0.0)
        tdeep = math.atan2(-c22, -c21)
    else:
        b0 = _PI if e0 > 0.0 else 0.0
        b1 = _PI if e1 > 0.0 else 0.0
        tdeep = 0.0
    a_any = max(b0, b1)
    a_all = min(b0, b1)
    if not (a_any > 0.0):
        return acc
    # v.n sqrt(1 + k^2) at an end x_e: K + A cos t + B sin t
    kk = -k * v1
    aa0 = v2 + w3 * x0 + k * r0 * w3
    ab0 = v3 - w2 * x0 - k * r0 * w2
    aa1 = v2 + w3 * x1 + k * r1 * w3
    ab1 = v3 - w2 * x1 - k * r1 * w2
    pa0, pa1 = _harmonic_roots(kk, aa0, ab0)
    pb0, pb1 = _harmonic_roots(kk, aa1, ab1)
    q0 = a_any
    q1 = a_any
    q2 = a_any
    q3 = a_any
    if tangential:
        s0, s1 = _harmonic_roots(w1 * r0, v3 - w2 * x0, -(v2 + w3 * x0))
        s2, s3 = _harmonic_roots(w1 * r1, v3 - w2 * x1, -(v2 + w3 * x1))
        q0 = _local(s0, tdeep, a_any)
        q1 = _local(s1, tdeep, a_any)
        q2 = _local(s2, tdeep, a_any)
        q3 = _local(s3, tdeep, a_any)
    # where the seabed line and the delta line cross inside the lateral surface (an embedded,
    # advancing sliver between them, as a rotating slap cuts, ends there: the cylinder's issue 34)
    x0c, x1c, x2c, x3c = _trig2_angles(*tapered_crossing_coefficients(rho0, k, d0, c20, c21, c22, vbody))
    if x0c == x0c:
        x0c = _on_tapered(x0c, tdeep, a_any, rho0, k, x0, x1, r0, r1, d0, c20, c21, c22, rp)
        x1c = _on_tapered(x1c, tdeep, a_any, rho0, k, x0, x1, r0, r1, d0, c20, c21, c22, rp)
        x2c = _on_tapered(x2c, tdeep, a_any, rho0, k, x0, x1, r0, r1, d0, c20, c21, c22, rp)
        x3c = _on_tapered(x3c, tdeep, a_any, rho0, k, x0, x1, r0, r1, d0, c20, c21, c22, rp)
    else:  # none: at the domain's end, where a breakpoint changes nothing
        x0c = a_any
        x1c = a_any
        x2c = a_any
        x3c = a_any
    hq = min(_HALF_PI, a_any)
    bps = (
        x0c,
        x1c,
        x2c,
        x3c,
        -a_all,
        a_all,
        _local(pa0, tdeep, a_any),
        _local(pa1, tdeep, a_any),
        _local(pb0, tdeep, a_any),
        _local(pb1, tdeep, a_any),
        q0,
        q1,
        q2,
        q3,
        -hq,
        hq,
    )
    # advancing generators: the hull of the two ends' arcs
    ca, wa = _end_arc(kk, aa0, ab0)
    cb, wb = _end_arc(kk, aa1, ab1)
    if wa < 0.0 and wb < 0.0:
        return acc
    if wa < 0.0:
        dc = cb
        dw = wb
    elif wb < 0.0:
        dc = ca
        dw = wa
    else:
        dd = cb - ca
        dd -= _TWO_PI * math.floor(dd / _TWO_PI + 0.5)
        lo = min(-wa, dd - wb)
        hi = max(wa, dd + wb)
        dc = ca + 0.5 * (lo + hi)
        dw = min(0.5 * (hi - lo), _PI)
    delta = dc - tdeep
    delta -= _TWO_PI * math.floor(delta / _TWO_PI + 0.5)
    for shift in range(-1, 2):
        lo = max(-a_any, delta + _TWO_PI * shift - dw)
        hi = min(a_any, delta + _TWO_PI * shift + dw)
        cur = lo
        while cur < hi:
            nxt = _next_break(bps, cur, hi)
            h = 0.5 * (nxt - cur)
            mid = 0.5 * (nxt + cur)
            for i in range(N_T):
                t = tdeep + mid + h * _GL_NODES[N_T, i]
                wgt = h * _GL_WEIGHTS[N_T, i]
                part = _tapered_generator(
                    math.cos(t), math.sin(t), rho0, k, x0, x1, d0, c20, c21, c22, vbody, law, bank
                )
                acc = add_weighted(acc, wgt, part)
            cur = nxt
    return acc


@kernel
def profile_tractions(xs, rs, c20, c21, c22, d0, vbody, law, bank):
    """Sediment force and torque (body frame, about the COM) on the body of revolution by the fast
    rule (module docstring); the arguments of :func:`.sediment.fast.fast_tractions` with the profile
    for ``(L, R, chi)``. Summed as that function sums: the lateral surface (segment by segment,
    tail to nose), then the nose cap, then the tail cap."""
    tangential = law[LAW_MU] != 0.0
    n = len(xs)
    acc = (0.0, 0.0, 0.0, 0.0, 0.0, 0.0)
    for i in range(n - 1):
        if rs[i] == rs[i + 1]:
            part = _lateral(rs[i], xs[i], xs[i + 1], d0, c20, c21, c22, vbody, law, bank, tangential)
        else:
            part = tapered_lateral(
                xs[i], xs[i + 1], rs[i], rs[i + 1], d0, c20, c21, c22, vbody, law, bank, tangential
            )
        if i == 0:
            acc = part
        else:
            acc = add_weighted(acc, 1.0, part)
    for j in range(2):
        xc = xs[n - 1] if j == 0 else xs[0]
        rc = rs[n - 1] if j == 0 else rs[0]
        sgn = 1.0 if j == 0 else -1.0
        if rc > 0.0:
            g1, g2, g3, h1, h2, h3 = _cap(xc, sgn, rc, d0, c20, c21, c22, vbody, law, bank)
            f1, f2, f3, m1, m2, m3 = acc
            acc = (f1 + g1, f2 + g2, f3 + g3, m1 + h1, m2 + h2, m3 + h3)
    return acc


@kernel
def profile_pore_pressure(xs, rs, c20, c21, c22, d0, zeta_tip, w_up, law, bank):
    """Seed 000 eq. (73) for the body of revolution (module docstring): ``(force (E-frame vertical),
    torque about i_M's normals (body 2, 3), vertical added mass)`` as
    :func:`.sediment.pore.pore_pressure`."""
    n = len(xs)
    r_max = 0.0
    for i in range(n):
        r_max = max(r_max, rs[i])
    b = min(zeta_tip, 2.0 * r_max)
    if law[LAW_B] > 0.0:
        b = min(b, law[LAW_B])
    rho_tip, _, _ = _law_properties(zeta_tip, law, bank)
    coef = math.pi / 8.0 * rho_tip * b * b * b
    fpw = 0.0
    if law[LAW_KP] > 0.0:
        fpw = -coef * law[LAW_G] * w_up / law[LAW_KP]
    added = 0.0
    if law[LAW_EV] > 0.0:
        added = coef * (1.0 + law[LAW_EV]) / law[LAW_EV]
    # the axial span whose sections reach below the seabed: d0 - c20 x + r(x) rp > 0
    rp = math.sqrt(c21 * c21 + c22 * c22)
    lo = math.inf
    hi = -math.inf
    for i in range(n - 1):
        x0 = xs[i]
        x1 = xs[i + 1]
        f0 = d0 - c20 * x0 + rs[i] * rp
        f1 = d0 - c20 * x1 + rs[i + 1] * rp
        if f0 > 0.0 and f1 > 0.0:
            lo = min(lo, x0)
            hi = max(hi, x1)
        elif f0 > 0.0:
            lo = min(lo, x0)
            hi = max(hi, x0 + (x1 - x0) * f0 / (f0 - f1))
        elif f1 > 0.0:
            lo = min(lo, x0 + (x1 - x0) * f0 / (f0 - f1))
            hi = max(hi, x1)
    if not (hi >= lo):  # nothing reaches below (zeta_tip > 0 says otherwise: rounding)
        lo = xs[0]
        hi = xs[n - 1]
    xm = 0.5 * (lo + hi)
    return fpw, -xm * fpw * c22, xm * fpw * c21, added
