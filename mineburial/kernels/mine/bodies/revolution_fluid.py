"""Fluid strips of a body of revolution with a piecewise-linear radius profile (issue 36 item 2):
the cylinder's strip theory (:func:`mineburial.kernels.mine.dynamics.strip_forces`, seeds 000 and
001) with a section radius ``r(x)`` that is linear on each segment of the profile.

The body's stations ``xs`` (tail to nose, about the COM) and radii ``rs`` are those of
:mod:`.revolution_geometry`. Along the axis the relative normal velocity is linear in ``x`` (seed
001 eq. (28)), ``v(x) = v0 + w x`` with ``w = (-omega3, omega2)``, and the crossflow drag per unit
length is ``(1/2) rho C_D 2 r(x) |v| v`` (seed 000 eq. (42) with the local diameter). On a
segment ``r`` is linear too, so with ``u = (x - c)/h`` (``c``, ``h`` the midpoint and half-length)
and ``r = r_m + dr u``,

    int r |v| v dx   = S^2 h (r_m M_0 + dr M_1),
    int x r |v| v dx = c int r |v| v dx + S^2 h^2 (r_m M_1 + dr M_2),
    M_k = int_-1^1 u^k |v~| v~ du,

``S`` the velocity scale of :func:`mineburial.kernels.crossflow.quadratic_drag_integrals` and
``v~ = v/S``. ``M_0, M_1`` are that module's integrals (seed 001 eqs. (31)-(47) re-derived); the
taper adds ``M_2``, which needs one more moment of ``|v|``, ``int u^3 |v| du``: in the closed-form
branch the antiderivative ``int s^3 sqrt(m^2 + s^2) ds = R^3 (3 s^2 - 2 m^2)/15`` (``R =
sqrt(m^2 + s^2)``; differentiate: ``s^3 R``), in the series branch the odd Gegenbauer terms over
``n + 4``. Both branches are exact to rounding, as the cylinder's (``docs/notes/crossflow.md``).

:func:`profile_strip_forces` is :func:`~.dynamics.strip_forces` for the profile, term by term
(docs/bodies_revolution.md):

* crossflow drag: the integrals above with the local diameter ``2 r(x)``; the coefficient of seed
  000 eq. (44) at the strip's Reynolds number ``Re = v_rms d_m / nu`` (``d_m = 2 int r dx /
  ell``, the strip's mean diameter) and the body's aspect ratio ``L / d_mean`` (``d_mean`` the
  whole body's mean diameter);
* Magnus lift: per unit length ``(1/2) rho 2 r C_l |v| (v x e1)``, ``C_l`` at the spin ratio
  ``omega1 (d_m/2) / v_rms`` (the cylinder's with the strip's mean radius);
* axial drag: seed 000 eqs. (38)-(40) on the body's largest section ``pi r_max^2`` (its frontal
  area), at the aspect ratio ``L / d_mean``, scaled by the wetted length fraction as the
  cylinder's; a frustum's fore-aft asymmetry (base first or top first) is not in eq. (40) and is
  left to the drag laws of cones (docs/notes/manta_research.md section 2);
* roll damping, seed 000 eq. (53): ``pi rho nu omega1 int (2 r)^2 dx``.

For a strip on one segment of constant radius the cylinder's own :func:`~.dynamics.strip_forces`
is called: a frustum of equal radii gives the cylinder's forces bit for bit
(tests/test_revolution_fluid.py); otherwise a constant profile agrees to rounding.
:func:`profile_strip_added_mass` gives strip theory's added-mass moments ``int pi r^2 x^k dx``
(seed 001 eqs. (20)-(21) with the local section), which the finite body's factors of
:mod:`mineburial.kernels.mine.added_mass` scale.
"""

import math

import numpy as np

from mineburial._numba import kernel, small_kernel
from mineburial.kernels.crossflow import LAMBDA_SWITCH, N_SERIES, _root_moments
from mineburial.kernels.mine.added_mass import finite_body_cross_drag
from mineburial.kernels.mine.coefficients import (
    axial_drag_coefficient,
    cross_drag_coefficient,
    lift_coefficient,
    roughness_scaled,
)

# the cylinder's strips: dynamics loads no shape module at its import (a frustum's module is
# imported by the Python side that makes its body, shapes.FrustumShape.marker), so no cycle
from mineburial.kernels.mine.dynamics import strip_forces as _cylinder_strip


@kernel
def unit_moments(vy, vz, wy, wz):
    """``M_k = int_-1^1 u^k |v| v du`` for ``k = 0, 1, 2`` and ``v = (vy, vz) + (wy, wz) u``
    (O(1) inputs; :func:`mineburial.kernels.crossflow._unit_interval` with one moment more).
    Returns ``(M0y, M0z, M1y, M1z, M2y, M2z)``."""
    vv = math.hypot(vy, vz)
    ww = math.hypot(wy, wz)
    if ww == 0.0 and vv == 0.0:
        return 0.0, 0.0, 0.0, 0.0, 0.0, 0.0
    if ww < LAMBDA_SWITCH * vv:
        # series branch: |v(u)| = V sqrt(1 - 2 x tau + tau^2), tau = (W/V) u, Gegenbauer C_n^(-1/2)
        lam = ww / vv
        if ww > 0.0:
            x = -(vy * wy + vz * wz) / (vv * ww)
            x = min(1.0, max(-1.0, x))
        else:
            x = 0.0
        c_prev = 1.0
        c_cur = -x
        k0 = 1.0  # sum_{n even} C_n lam^n / (n + 1)
        k2 = 1.0 / 3.0  # sum_{n even} C_n lam^n / (n + 3)
        k1 = c_cur * lam / 3.0  # sum_{n odd} C_n lam^n / (n + 2)
        k3 = c_cur * lam / 5.0  # sum_{n odd} C_n lam^n / (n + 4)
        lam_n = lam
        for n in range(2, N_SERIES + 1):
            lam_n *= lam
            if lam_n < 1e-19:
                break
            c_next = (2.0 * x * (n - 1.5) * c_cur - (n - 3.0) * c_prev) / n
            c_prev = c_cur
            c_cur = c_next
            t = c_cur * lam_n
            if n % 2 == 0:
                k0 += t / (n + 1.0)
                k2 += t / (n + 3.0)
            else:
                k1 += t / (n + 2.0)
                k3 += t / (n + 4.0)
        f = 2.0 * vv
        k0 *= f
        k1 *= f
        k2 *= f
        k3 *= f
        return (
            vy * k0 + wy * k1,
            vz * k0 + wz * k1,
            vy * k1 + wy * k2,
            vz * k1 + wz * k2,
            vy * k2 + wy * k3,
            vz * k2 + wz * k3,
        )
    # closed-form branch in the shifted variable s = W (u - u_min), |v| = sqrt(m^2 + s^2)
    w2 = ww * ww
    u_min = -(vy * wy + vz * wz) / w2
    q = (vy * wz - vz * wy) / ww
    m = abs(q)
    vmy = q * wz / ww
    vmz = -q * wy / ww
    sa = ww * (-1.0 - u_min)
    sb = ww * (1.0 - u_min)
    j0, j1, j2 = _root_moments(sa, sb, m)
    ra = math.hypot(m, sa)
    rb = math.hypot(m, sb)
    m2 = m * m
    j3 = (rb * rb * rb * (3.0 * sb * sb - 2.0 * m2) - ra * ra * ra * (3.0 * sa * sa - 2.0 * m2)) / 15.0
    i0 = j0 / ww  # int |v| dt, t = u - u_min
    i1 = j1 / w2  # int t |v| dt
    i2 = j2 / (w2 * ww)  # int t^2 |v| dt
    i3 = j3 / (w2 * w2)  # int t^3 |v| dt
    f0y = vmy * i0 + wy * i1
    f0z = vmz * i0 + wz * i1
    g1y = vmy * i1 + wy * i2
    g1z = vmz * i1 + wz * i2
    f1y = u_min * f0y + g1y
    f1z = u_min * f0z + g1z
    # u^2 = u_min^2 + 2 u_min t + t^2
    f2y = u_min * f1y + u_min * g1y + vmy * i2 + wy * i3
    f2z = u_min * f1z + u_min * g1z + vmz * i2 + wz * i3
    return f0y, f0z, f1y, f1z, f2y, f2z


@kernel
def tapered_drag_integrals(a, b, ra, rb, vy0, vz0, wy, wz):
    """Exact ``int_a^b r |v| v dx`` and ``int_a^b x r |v| v dx`` for ``v(x) = v0 + w x`` and the
    radius ``r`` linear from ``ra`` at ``a`` to ``rb`` at ``b`` (module docstring). Returns ``(Fy,
    Fz, My, Mz)``; ``a == b`` gives zeros. Units ``[r][v]^2[x]``, ``[r][v]^2[x]^2``."""
    h = 0.5 * (b - a)
    if h == 0.0:
        return 0.0, 0.0, 0.0, 0.0
    c = 0.5 * (a + b)
    vcy = vy0 + wy * c
    vcz = vz0 + wz * c
    s = max(math.hypot(vcy, vcz), math.hypot(wy, wz) * abs(h))
    if s == 0.0:
        return 0.0, 0.0, 0.0, 0.0
    m0y, m0z, m1y, m1z, m2y, m2z = unit_moments(vcy / s, vcz / s, wy * (h / s), wz * (h / s))
    rm = 0.5 * (ra + rb)
    dr = 0.5 * (rb - ra)
    kf = s * s * h
    fy = kf * (rm * m0y + dr * m1y)
    fz = kf * (rm * m0z + dr * m1z)
    km = kf * h
    return fy, fz, c * fy + km * (rm * m1y + dr * m2y), c * fz + km * (rm * m1z + dr * m2z)


@small_kernel
def _radius_at(xs, rs, i, x):
    """r(x) on segment i of the profile (linear between its stations)."""
    x0 = xs[i]
    x1 = xs[i + 1]
    return rs[i] + (rs[i + 1] - rs[i]) * ((x - x0) / (x1 - x0))


@kernel
def profile_means(xs, rs):
    """``(length, mean diameter 2 int r dx / L, largest radius)`` of the profile."""
    length = xs[len(xs) - 1] - xs[0]
    area = 0.0
    r_max = 0.0
    for i in range(len(xs) - 1):
        area += 0.5 * (rs[i] + rs[i + 1]) * (xs[i + 1] - xs[i])
        r_max = max(r_max, rs[i], rs[i + 1])
    return length, 2.0 * area / length, r_max


@kernel
def profile_drag_integrals(xs, rs, a, b, vy0, vz0, wy, wz):
    """Over the strip ``[a, b]`` of the profile: ``(int 2r|v|v dx, int x 2r|v|v dx)`` (y and z),
    ``int r dx`` and ``int r^2 dx`` (each segment's part by :func:`tapered_drag_integrals` and the
    closed forms of a linear ``r``). Returns ``(Dy, Dz, DMy, DMz, int_r, int_r2)``."""
    dy = 0.0
    dz = 0.0
    my = 0.0
    mz = 0.0
    ir = 0.0
    ir2 = 0.0
    for i in range(len(xs) - 1):
        lo = max(a, xs[i])
        hi = min(b, xs[i + 1])
        if hi <= lo:
            continue
        r_lo = _radius_at(xs, rs, i, lo)
        r_hi = _radius_at(xs, rs, i, hi)
        fy, fz, gy, gz = tapered_drag_integrals(lo, hi, r_lo, r_hi, vy0, vz0, wy, wz)
        dy += 2.0 * fy
        dz += 2.0 * fz
        my += 2.0 * gy
        mz += 2.0 * gz
        ir += 0.5 * (r_lo + r_hi) * (hi - lo)
        ir2 += (r_lo * r_lo + r_lo * r_hi + r_hi * r_hi) * (hi - lo) / 3.0
    return dy, dz, my, mz, ir, ir2


@kernel
def profile_strip_forces(rho, nu, xs, rs, L, a, b, ur1, ur2, ur3, w1, w2, w3, drag_on, eta, roughness):
    """Fluid force and torque (body frame, about the COM) on the axial strip ``[a, b]`` of the body
    of revolution (stations ``xs``, radii ``rs``, length ``L``): :func:`~.dynamics.strip_forces`
    with the local section (module docstring); the same arguments but ``R`` (the profile instead).
    A strip on one segment of constant radius is the cylinder's, by that function itself."""
    if drag_on == 0 or rho <= 0.0 or b <= a:
        return 0.0, 0.0, 0.0, 0.0, 0.0, 0.0
    n = len(xs)
    for i in range(n - 1):
        if xs[i] <= a and b <= xs[i + 1] and rs[i] == rs[i + 1]:
            return _cylinder_strip(
                rho, nu, rs[i], L, a, b, ur1, ur2, ur3, w1, w2, w3, drag_on, eta, roughness
            )
    ell = b - a
    _, d_mean, r_max = profile_means(xs, rs)
    aspect = L / d_mean
    # axial drag, seed 000 eqs. (38)-(40), on the frontal area pi r_max^2
    cd1 = axial_drag_coefficient(aspect)
    f1 = 0.5 * rho * cd1 * math.pi * r_max * r_max * abs(ur1) * ur1 * (ell / L)
    dy, dz, jy, jz, ir, ir2 = profile_drag_integrals(xs, rs, a, b, ur2, ur3, -w3, w2)
    d_m = 2.0 * ir / ell
    # representative cross-flow speed: rms of |v| over the strip (closed form), as the cylinder's
    m1 = 0.5 * (a + b)
    m2 = (a * a + a * b + b * b) / 3.0
    v2sq = (ur2 * ur2 + ur3 * ur3) + 2.0 * m1 * (-ur2 * w3 + ur3 * w2) + m2 * (w3 * w3 + w2 * w2)
    vrms = math.sqrt(max(v2sq, 0.0))
    re = vrms * d_m / nu
    cd2 = finite_body_cross_drag(roughness_scaled(cross_drag_coefficient(re, aspect), re, roughness), re, eta)
    k = 0.5 * rho * cd2
    f2 = k * dy
    f3 = k * dz
    m2_ = -k * jz
    m3_ = k * jy
    if vrms > 1e-12:
        cl = lift_coefficient(w1 * (0.5 * d_m) / vrms)
        kl = 0.5 * rho * cl
        f2 += kl * dz
        f3 -= kl * dy
        m2_ += kl * jy
        m3_ += kl * jz
    # viscous roll damping, seed 000 eq. (53), with the local diameter: pi mu int (2r)^2 dx
    m1_ = -math.pi * rho * nu * 4.0 * ir2 * w1
    return f1, f2, f3, m1_, m2_, m3_


#: three Gauss-Legendre nodes on [0, 1]: exact for the degree-4 integrands of the added-mass moments
_GL3_U = np.array([0.5 - 0.5 * math.sqrt(0.6), 0.5, 0.5 + 0.5 * math.sqrt(0.6)])
_GL3_W = np.array([5.0 / 18.0, 8.0 / 18.0, 5.0 / 18.0])


@kernel
def profile_strip_added_mass(xs, rs, a, b):
    """Strip theory's added-mass moments over ``[a, b]`` per unit ``C_M rho`` (seed 001 eqs.
    (20)-(21), section ``pi r(x)^2``): ``(int pi r^2 dx, int pi r^2 x dx, int pi r^2 x^2 dx)``,
    exact (degree-4 polynomials on each segment, a 3-node Gauss rule)."""
    a0 = 0.0
    a1 = 0.0
    a2 = 0.0
    for i in range(len(xs) - 1):
        lo = max(a, xs[i])
        hi = min(b, xs[i + 1])
        if hi <= lo:
            continue
        r_lo = _radius_at(xs, rs, i, lo)
        r_hi = _radius_at(xs, rs, i, hi)
        h = hi - lo
        for k in range(3):
            x = lo + h * _GL3_U[k]
            r = r_lo + (r_hi - r_lo) * _GL3_U[k]
            w = _GL3_W[k] * h * math.pi * r * r
            a0 += w
            a1 += w * x
            a2 += w * x * x
    return a0, a1, a2
