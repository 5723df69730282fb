"""Exact quadratic-drag integrals along a rotating cylinder (cross-flow).

The fluid velocity relative to the mine, normal to its axis, at axial station
``x`` of the body frame is linear in ``x`` (seed 001 eq. (28),
``v_N = v_GN - omega x (x n)``)::

    v(x) = (vy0 + wy x, vz0 + wz x)        (components along j_M, k_M)

With the body angular velocity ``omega = (omega1, omega2, omega3)`` and the
axis ``n = i_M``, ``omega x i_M = (0, omega3, -omega2)``, so ``wy = -omega3`` and
``wz = +omega2``.

Quadratic (cross-flow) drag needs ``int |v| v dx`` and ``int x |v| v dx`` over
the body (seed 001 eqs. (36)-(37)); seed 001 eqs. (31)-(47) give them in closed
form with ``|v|^2 = a + b x + c x^2``. The printed formulas carry OCR damage and
are singular for ``c = 0`` (no rotation) and ``4ac - b^2 = 0`` (``v`` passes
through zero), so they are re-derived here (see ``docs/notes/crossflow.md``):

* lengths are scaled by the half-length ``h`` of ``[a, b]`` about its midpoint
  ``c`` and velocities by ``S = max(|v(c)|, |w| |h|)``, so the work is done on
  ``[-1, 1]`` with O(1) numbers (no overflow, exact ``k^2`` scaling);
* when ``|w| |h| >= LAMBDA_SWITCH |v(c)|`` the shifted variable
  ``t = x - x_min`` (``x_min``: station of minimum ``|v|``) turns
  ``|v|^2 = m^2 + |w|^2 t^2`` and the moments of ``sqrt(m^2 + s^2)`` have the
  asinh antiderivatives below, which stay finite and exact for ``m -> 0`` (the
  degenerate branch ``|v| = |w| |x - x0|`` with the sign change at ``x0``);
* when ``|w| |h| < LAMBDA_SWITCH |v(c)|`` (slow rotation, including ``w = 0``)
  those antiderivatives cancel catastrophically (relative loss ~ lambda^-3),
  and ``|v|`` is expanded instead in its Gegenbauer series about the midpoint,
  ``sqrt(1 - 2 x tau + tau^2) = sum C_n^(-1/2)(x) tau^n``, which converges like
  ``lambda^n`` and is integrated term by term exactly; it is summed to below
  1e-18 relative, i.e. exact to rounding.
"""

import math

from mineburial._numba import kernel

#: ratio |w| |h| / |v(midpoint)| below which the series branch is used.
LAMBDA_SWITCH = 0.25
#: terms of the series branch: LAMBDA_SWITCH**N_SERIES < 1e-18.
N_SERIES = 31


@kernel
def _m2_asinh(s, m):
    """``m^2 asinh(s/m)`` with its limit 0 for ``m -> 0`` (``m >= 0``)."""
    if m == 0.0:
        return 0.0
    r = s / m
    if not math.isfinite(r):
        # m <= |s| / 1.8e308: m^2 asinh(s/m) < s^2 * 1e-613 -- negligible and
        # the product would be 0 * inf.
        return 0.0
    return m * m * math.asinh(r)


@kernel
def _root_moments(sa, sb, m):
    """Exact ``J_k = int_sa^sb s^k sqrt(m^2 + s^2) ds`` for k = 0, 1, 2.

    Antiderivatives (``R = sqrt(m^2 + s^2)``, ``A = m^2 asinh(s/m)``; cf.
    Gradshteyn & Ryzhik 2.271, and seed 001 eqs. (41)-(43) after the shift
    ``s = sqrt(c) (x + b / (2c))``):

    * ``P0 = (s R + A) / 2``
    * ``P1 = R^3 / 3``
    * ``P2 = s R^3 / 4 - m^2 s R / 8 - m^2 A / 8``

    For ``m = 0`` they reduce to ``s|s|/2``, ``|s|^3/3``, ``s^3|s|/4``, the
    integrals of ``|s|``, ``s|s|``, ``s^2|s|`` with their sign change at 0.
    """
    ra = math.hypot(m, sa)
    rb = math.hypot(m, sb)
    aa = _m2_asinh(sa, m)
    ab = _m2_asinh(sb, m)
    m2 = m * m
    j0 = 0.5 * ((sb * rb - sa * ra) + (ab - aa))
    j1 = (rb * rb * rb - ra * ra * ra) / 3.0
    j2 = (
        (sb * rb * rb * rb - sa * ra * ra * ra) * 0.25
        - m2 * (sb * rb - sa * ra) * 0.125
        - m2 * (ab - aa) * 0.125
    )
    return j0, j1, j2


@kernel
def _unit_interval(vy, vz, wy, wz):
    """``int_-1^1 |v| v du`` and ``int_-1^1 u |v| v du`` for ``v = (vy, vz) + (wy, wz) u``.

    Inputs are O(1) (scaled by the caller). Returns ``(Fy, Fz, My, Mz)``.
    """
    return _unit_interval_norms(vy, vz, wy, wz, math.hypot(vy, vz), math.hypot(wy, wz))


@kernel
def _unit_interval_norms(vy, vz, wy, wz, vv, ww):
    """:func:`_unit_interval` given the norms ``vv = |(vy, vz)|`` and ``ww = |(wy, wz)|`` (the
    caller has them from its scaling: :func:`quadratic_drag_integrals`)."""
    if ww == 0.0 and vv == 0.0:
        return 0.0, 0.0, 0.0, 0.0
    if ww < LAMBDA_SWITCH * vv:
        # --- series branch: |v(u)| = V sqrt(1 - 2 x tau + tau^2), tau = W u / V.
        lam = ww / vv
        if ww > 0.0:
            x = -(vy * wy + vz * wz) / (vv * ww)
            x = min(1.0, max(-1.0, x))
        else:
            x = 0.0
        # Gegenbauer C_n^(alpha) with alpha = -1/2:
        # n C_n = 2 x (n + alpha - 1) C_{n-1} - (n + 2 alpha - 2) C_{n-2}
        c_prev = 1.0  # C_0
        c_cur = -x  # C_1 = 2 alpha x
        k0 = 1.0  # n = 0 term of sum_{n even} C_n lam^n / (n + 1)
        k2 = 1.0 / 3.0  # n = 0 term of sum_{n even} C_n lam^n / (n + 3)
        k1 = c_cur * lam / 3.0  # n = 1 term of sum_{n odd} C_n lam^n / (n + 2)
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
        k0 *= 2.0 * vv  # int |v| du
        k1 *= 2.0 * vv  # int u |v| du
        k2 *= 2.0 * vv  # int u^2 |v| du
        return (vy * k0 + wy * k1, vz * k0 + wz * k1, vy * k1 + wy * k2, vz * k1 + wz * k2)
    # --- closed-form branch in the shifted variable s = W (u - u_min).
    w2 = ww * ww
    u_min = -(vy * wy + vz * wz) / w2
    # v(u_min) is perpendicular to w: v_min = q n_hat, n_hat = (wz, -wy) / W.
    q = (vy * wz - vz * wy) / ww
    m = abs(q)
    vmy = q * wz / ww
    vmz = -q * wy / ww
    sa = ww * (-1.0 - u_min)
    sb = ww * (1.0 - u_min)
    j0, j1, j2 = _root_moments(sa, sb, m)
    i0 = j0 / ww  # int |v| dt
    i1 = j1 / w2  # int t |v| dt
    i2 = j2 / (w2 * ww)  # int t^2 |v| dt
    fy = vmy * i0 + wy * i1
    fz = vmz * i0 + wz * i1
    # u = u_min + t, v = v_min + w t
    my = u_min * fy + vmy * i1 + wy * i2
    mz = u_min * fz + vmz * i1 + wz * i2
    return fy, fz, my, mz


@kernel
def quadratic_drag_integrals(a, b, vy0, vz0, wy, wz):
    """Exact ``int_a^b |v| v dx`` and ``int_a^b x |v| v dx`` for ``v(x) = v0 + w x``.

    ``v0 = (vy0, vz0)`` is the relative cross-flow velocity at ``x = 0`` (the
    COM) and ``w = (wy, wz)`` its rate of change along the axis (seed 001
    eq. (28): ``wy = -omega3``, ``wz = omega2`` in the body frame). Returns
    ``(Fy, Fz, My, Mz)`` with ``(Fy, Fz) = int_a^b |v| v dx`` and
    ``(My, Mz) = int_a^b x |v| v dx``. Seed 001 eqs. (31)-(47), re-derived
    (module docstring, ``docs/notes/crossflow.md``). ``a > b`` gives the
    negated integral, ``a == b`` zeros. Units: ``[v]^2 [x]`` and ``[v]^2 [x]^2``.
    """
    h = 0.5 * (b - a)
    if h == 0.0:
        return 0.0, 0.0, 0.0, 0.0
    c = 0.5 * (a + b)
    vcy = vy0 + wy * c
    vcz = vz0 + wz * c
    ah = abs(h)
    vn = math.hypot(vcy, vcz)
    wn = math.hypot(wy, wz)
    s = max(vn, wn * ah)
    if s == 0.0:
        return 0.0, 0.0, 0.0, 0.0
    # scaled problem on u in [-1, 1]: v = S (vc/S + (w h / S) u); the scaled vectors' norms from
    # the norms above (scaled the same way: exact for a power-of-two scaling of the inputs), not
    # two more hypot calls on the scaled components (they agree to rounding)
    fy, fz, my, mz = _unit_interval_norms(vcy / s, vcz / s, wy * (h / s), wz * (h / s), vn / s, wn * (ah / s))
    kf = s * s * h
    km = kf * h
    fy *= kf
    fz *= kf
    return fy, fz, c * fy + km * my, c * fz + km * mz
