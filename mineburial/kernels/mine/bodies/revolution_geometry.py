"""Geometry of a solid body of revolution with a piecewise-linear radius profile, cut by a
horizontal plane (issue 36 item 2, first step: the geometry; not yet a registered shape).

The body (M-frame, axis ``i_M`` through the COM, as :mod:`mineburial.kernels.mine.geometry`'s
cylinder) spans the stations ``xs[0] < xs[1] < ... < xs[n-1]`` (``xs[0]`` the tail, ``xs[-1]``
the nose, about the COM) with radii ``rs[i] >= 0`` at them and ``r(x)`` linear between: a chain of
frusta (the cylinder two stations of one radius, a cone a zero radius at one end), closed by flat
end caps of radii ``rs[0]`` and ``rs[-1]``. ``xs`` and ``rs`` are arrays or tuples of floats (a
shape's NamedTuple fields: no allocation in the kernels); the results are the same.

Derivation (the cylinder's of seed 000 section 4, eqs. (25)-(33), with a radius that varies
along the axis). With ``b = sqrt(1 - a_z^2)`` and ``e_down = (a_z i_M - k)/b``, the body point
``x i_M + s e_down + t e_perp`` (``s^2 + t^2 <= r(x)^2``) is at height ``z_c + a_z x - b s``, so
section ``x`` lies below the plane ``z = level`` where ``s >= d(x)/b``, ``d(x) = z_c - level +
a_z x``: full when ``d <= -b r``, empty when ``d >= b r``, else cut at ``kappa = d/(b r) =
cos(theta)``, and then (unit radius) its area below is ``A = theta - sin(theta) cos(theta)``
(eq. (25a)), the area's first moment along ``e_down`` ``(2/3) sin^3(theta)`` and the wetted arc
``2 theta``. So, over the body,

    V = int r^2 A dx,   M_x = int x r^2 A dx,   M_s = int r^3 (2/3) sin^3(theta) dx,
    lateral = int 2 theta r sqrt(1 + r'^2) dx

(the lateral surface's element is ``r sqrt(1 + r'^2) dphi dx``; its point at angle ``phi`` from
``e_down`` is below where ``cos(phi) >= kappa``, the same arc as the section's). ``d`` and ``b r``
are linear on a frustum, so the sections turn full or empty where ``d = -b r`` or ``d = b r``:
each frustum is split there (closed forms for the split points), its full parts take the
frustum's closed forms, and each half of a partial part a Gauss-Legendre rule in ``t`` with ``x
= s +- t^2``, ``s`` the nearest split point beyond the half's outer end (a tangency at the end,
or one just outside it): near ``s`` the integrands go as ``(x - s)^{1/2}`` (the arc) and ``(x -
s)^{3/2}`` (the area), analytic in ``t``, so the rule converges geometrically where a rule in
``x`` would not (a split point just outside the piece, 1e-9 of the lateral area off at 24 nodes).
``a_z`` of either sign
needs no axis reversal (``d`` is linear in ``x`` for any sign); a vertical axis (``b = 0``) has no
partial sections.

The cylinder's closed forms (:func:`.geometry.cut_cylinder`) are the reference for the special
case (tests/test_revolution_geometry.py), and scipy.integrate of the definitions for frusta.
"""

import math

import numpy as np

from mineburial._numba import kernel, small_kernel

#: Gauss-Legendre nodes per half of a partial piece (the substituted integrands are analytic: 24
#: nodes give rounding-level results on the tests' frusta, tests/test_revolution_geometry.py)
N_NODES = 24
_T, _W = np.polynomial.legendre.leggauss(N_NODES)
GL_U = np.ascontiguousarray(0.5 * (_T + 1.0), dtype=np.float64)  # nodes on [0, 1]
GL_W = np.ascontiguousarray(0.5 * _W, dtype=np.float64)


@small_kernel
def _segment_cap(d, br, r):
    """Area of the disc of radius ``r`` (its centre ``d`` above the plane, its rim reaching
    ``br = b r`` above and below) that lies below the plane; a disc lying in the plane (``b = 0, d =
    0``) counts as not below, as the cylinder's caps (:func:`.geometry._cap_area`)."""
    if d >= br:
        return 0.0
    if d <= -br:
        return math.pi * r * r
    kappa = d / br
    theta = math.acos(kappa)
    return r * r * (theta - math.sqrt((1.0 - kappa) * (1.0 + kappa)) * kappa)


@small_kernel
def _full_frustum(x0, x1, r0, r1):
    """Volume, axial first moment and lateral area of the whole frustum [x0, x1] with radii r0, r1."""
    h = x1 - x0
    v = math.pi * h * (r0 * r0 + r0 * r1 + r1 * r1) / 3.0
    # first moment about x0 (the frustum's centroid h (r0^2 + 2 r0 r1 + 3 r1^2) / (4 (r0^2 + r0 r1 + r1^2)))
    mx = v * x0 + math.pi * h * h * (r0 * r0 + 2.0 * r0 * r1 + 3.0 * r1 * r1) / 12.0
    lat = math.pi * (r0 + r1) * math.sqrt(h * h + (r1 - r0) * (r1 - r0))
    return v, mx, lat


@small_kernel
def _add_sections(x, w, x0, r0, slope, stretch, c, a_z, b, acc):
    """Add the partial section at ``x`` with weight ``w`` (of a quadrature over x) to ``acc``."""
    V, Mx, Ms, lat = acc
    r = r0 + slope * (x - x0)
    if r <= 0.0:
        return acc
    kappa = (c + a_z * x) / (b * r)
    if kappa > 1.0:
        kappa = 1.0
    elif kappa < -1.0:
        kappa = -1.0
    theta = math.acos(kappa)
    sigma = math.sqrt((1.0 - kappa) * (1.0 + kappa))
    area = r * r * (theta - sigma * kappa)
    V += w * area
    Mx += w * x * area
    Ms += w * r * r * r * (2.0 / 3.0) * sigma * sigma * sigma
    lat += w * 2.0 * theta * r * stretch
    return V, Mx, Ms, lat


@small_kernel
def _partial_piece(xa, xb, x0, r0, slope, c, a_z, b, s1, s2, acc):
    """Add the partial sections of [xa, xb] (on the frustum whose radius is ``r0 + slope (x - x0)``)
    to ``acc = (V, M_x, M_s, lateral)``: each half by a Gauss-Legendre rule in ``t`` with ``x = s +-
    t^2`` about the nearest point ``s`` beyond its outer end where a section turns full or empty
    (``s1``, ``s2``; there the integrands go as ``(x - s)^{1/2}``, ``(x - s)^{3/2}``, analytic in
    ``t``), or in ``x`` when there is none within four half-lengths (module docstring)."""
    stretch = math.sqrt(1.0 + slope * slope)
    xm = 0.5 * (xa + xb)
    half = xm - xa
    for side in range(2):
        lo = xa if side == 0 else xm
        hi = xm if side == 0 else xb
        # the nearest split point beyond this half's outer end (nan compares false)
        s = math.nan
        if side == 0:
            for q in (s1, s2):
                if q <= xa and xa - q <= 4.0 * half and not (s >= q):
                    s = q
        else:
            for q in (s1, s2):
                if q >= xb and q - xb <= 4.0 * half and not (s <= q):
                    s = q
        if s == s:
            # x = s + sgn t^2, t from |lo - s|^(1/2) to |hi - s|^(1/2) (in either order), dx = 2 t |dt|
            ta = math.sqrt(abs(lo - s))
            tb = math.sqrt(abs(hi - s))
            sgn = 1.0 if side == 0 else -1.0
            for i in range(N_NODES):
                t = ta + (tb - ta) * GL_U[i]
                w = GL_W[i] * abs(tb - ta) * 2.0 * t
                acc = _add_sections(s + sgn * t * t, w, x0, r0, slope, stretch, c, a_z, b, acc)
        else:
            for i in range(N_NODES):
                acc = _add_sections(
                    lo + (hi - lo) * GL_U[i], GL_W[i] * (hi - lo), x0, r0, slope, stretch, c, a_z, b, acc
                )
    return acc


@small_kernel
def _frustum_below(x0, x1, r0, r1, c, a_z, b, acc):
    """Add the part of the frustum [x0, x1] (radii r0, r1) below the plane to ``acc``: split where
    its sections turn full or empty (``d = -b r``, ``d = b r``), each piece full, empty or partial."""
    slope = (r1 - r0) / (x1 - x0)
    # d(x) -+ b r(x) = 0, both linear in x: (c + a_z x) -+ b (r0 + slope (x - x0)) = 0
    s1 = math.nan
    s2 = math.nan
    den = a_z - b * slope
    if den != 0.0:
        s1 = (b * (r0 - slope * x0) - c) / den
    den = a_z + b * slope
    if den != 0.0:
        s2 = (-b * (r0 - slope * x0) - c) / den
    # the split points inside (x0, x1), sorted; inf where there is none (nan compares false)
    q1 = s1 if x0 < s1 < x1 else math.inf
    q2 = s2 if x0 < s2 < x1 else math.inf
    p1 = min(q1, q2)
    p2 = max(q1, q2)
    V, Mx, Ms, lat = acc
    xa = x0
    for k in range(3):
        xb = p1 if k == 0 else (p2 if k == 1 else x1)
        if xb > x1:
            xb = x1
        if xb <= xa:
            continue
        xm = 0.5 * (xa + xb)
        rm = r0 + slope * (xm - x0)
        dm = c + a_z * xm
        if dm <= -b * rm:  # full sections
            v, mx, dl = _full_frustum(xa, xb, r0 + slope * (xa - x0), r0 + slope * (xb - x0))
            V += v
            Mx += mx
            lat += dl
        elif dm < b * rm:  # partial sections (else: empty)
            V, Mx, Ms, lat = _partial_piece(xa, xb, x0, r0, slope, c, a_z, b, s1, s2, (V, Mx, Ms, lat))
        xa = xb
    return V, Mx, Ms, lat


@kernel
def cut_profile(xs, rs, a_z, z_c, level):
    """Part of the body of revolution (stations ``xs``, radii ``rs``) below the plane ``z = level``:
    ``(volume, x_c, eta_c, lateral_area, nose_cap_area, tail_cap_area)``, the centroid ``x_c i_M +
    eta_c e_down`` about the COM, as :func:`.geometry.cut_cylinder` returns them (for an empty part
    ``x_c`` is the station that gets wet first, ``eta_c`` 0)."""
    a = min(max(a_z, -1.0), 1.0)
    b = math.sqrt((1.0 - a) * (1.0 + a))
    c = z_c - level
    n = len(xs)
    acc = (0.0, 0.0, 0.0, 0.0)
    for i in range(n - 1):
        acc = _frustum_below(xs[i], xs[i + 1], rs[i], rs[i + 1], c, a, b, acc)
    V, Mx, Ms, lat = acc
    nose = _segment_cap(c + a * xs[n - 1], b * rs[n - 1], rs[n - 1])
    tail = _segment_cap(c + a * xs[0], b * rs[0], rs[0])
    if V > 0.0:
        return V, Mx / V, Ms / V, lat, nose, tail
    # empty: the station whose lowest point is lowest gets wet first (the middle of the first and
    # the last such station on a tie: a horizontal cylinder's middle, as the cylinder's kernel)
    lowest = math.inf
    for i in range(n):
        lowest = min(lowest, a * xs[i] - b * rs[i])
    first = math.inf
    last = -math.inf
    for i in range(n):
        if a * xs[i] - b * rs[i] == lowest:
            first = min(first, xs[i])
            last = max(last, xs[i])
    return 0.0, 0.5 * (first + last), 0.0, lat, nose, tail


@kernel
def extent_profile(xs, rs, a_z, z_c):
    """Lowest and highest heights ``(z_min, z_max)``: a section's lowest and highest points are at
    ``z_c + a_z x -+ b r(x)``, linear on each frustum, so the extremes are at stations."""
    a = min(max(a_z, -1.0), 1.0)
    b = math.sqrt((1.0 - a) * (1.0 + a))
    lo = math.inf
    hi = -math.inf
    for i in range(len(xs)):
        lo = min(lo, a * xs[i] - b * rs[i])
        hi = max(hi, a * xs[i] + b * rs[i])
    return z_c + lo, z_c + hi


@kernel
def volume_profile(xs, rs):
    """The whole body's volume, the axial position of its centroid about the COM and its
    surface area (lateral and both end caps), by the frusta's closed forms."""
    V = 0.0
    Mx = 0.0
    area = math.pi * (rs[0] * rs[0] + rs[-1] * rs[-1])
    for i in range(len(xs) - 1):
        v, mx, lat = _full_frustum(xs[i], xs[i + 1], rs[i], rs[i + 1])
        V += v
        Mx += mx
        area += lat
    return V, Mx / V, area


@kernel
def burial_profile(xs, rs, a_z, z_c, level):
    """The results table's burial measures of the body below the plane ``z = level``, as
    :func:`.geometry.burial_measures` gives the cylinder's: ``(pct_volume, pct_height, pct_area,
    height_proud, penetration)`` (percent of the volume, of the vertical extent and of the whole
    surface, lateral and both end caps, below the plane; ``max(z_max - level, 0)``, ``max(level -
    z_min, 0)``)."""
    v, _, _, lat, nose, tail = cut_profile(xs, rs, a_z, z_c, level)
    v_tot, _, s_tot = volume_profile(xs, rs)
    z_min, z_max = extent_profile(xs, rs, a_z, z_c)
    ext = z_max - z_min
    below = min(max(level - z_min, 0.0), ext)
    return (
        100.0 * v / v_tot,
        100.0 * below / ext,
        100.0 * (lat + nose + tail) / s_tot,
        max(z_max - level, 0.0),
        max(level - z_min, 0.0),
    )


@kernel
def lowest_profile_point(xs, rs, k1, k2, k3):
    """A lowest point of the body (body frame, about the COM) for the E-frame vertical ``k`` in body
    components (``k1 = a_z``): on the rim of the station whose rim reaches lowest (the last of those
    that tie), towards
    ``e_down = (0, -k2, -k3)/sqrt(k2^2 + k3^2)``; and its height above the COM (the protocol's
    ``deepest_point`` and ``lowest_offset`` of a profile)."""
    b = math.sqrt(k2 * k2 + k3 * k3)
    best = 0
    lowest = math.inf
    for i in range(len(xs)):
        zi = k1 * xs[i] - b * rs[i]
        if zi <= lowest:  # on a tie the station nearer the nose, as the cylinder's deepest_point
            lowest = zi
            best = i
    dn2 = 0.0
    dn3 = 0.0
    if b > 0.0:
        dn2 = -k2 / b
        dn3 = -k3 / b
    return xs[best], rs[best] * dn2, rs[best] * dn3, lowest


#: three Gauss-Legendre nodes on [0, 1]: exact for the polynomials of degree <= 5 of the mass properties
_GL3_U = np.array([0.5 - 0.5 * math.sqrt(0.6), 0.5, 0.5 + 0.5 * math.sqrt(0.6)])
_GL3_W = np.array([5.0 / 18.0, 8.0 / 18.0, 5.0 / 18.0])


@kernel
def inertia_profile(xs, rs, mass):
    """``(J_axial, J_transverse)`` of the uniform body of mass ``mass`` about its centroid: ``rho int
    pi r^4/2 dx`` about the axis, ``rho int (pi r^4/4 + pi r^2 (x - x_c)^2) dx`` about a transverse axis
    through the centroid (each disc's own moment plus its parallel-axis term), ``rho = mass / V``;
    the integrands are polynomials of degree 4 on each frustum, so a 3-node Gauss rule is exact."""
    v, x_c, _ = volume_profile(xs, rs)
    rho = mass / v
    j1 = 0.0
    j2 = 0.0
    for i in range(len(xs) - 1):
        h = xs[i + 1] - xs[i]
        for k in range(3):
            x = xs[i] + h * _GL3_U[k]
            r = rs[i] + (rs[i + 1] - rs[i]) * _GL3_U[k]
            w = _GL3_W[k] * h
            r2 = r * r
            j1 += w * 0.5 * math.pi * r2 * r2
            j2 += w * math.pi * (0.25 * r2 * r2 + r2 * (x - x_c) * (x - x_c))
    return rho * j1, rho * j2


@small_kernel
def _cumulative(xs, rs, x):
    """``(W, M, A)``: the volume ``int pi r^2`` and its first moment ``int pi r^2 x`` from the tail to
    ``x`` (clamped to the body), and the section area ``pi r(x)^2`` there (closed forms of a linear
    ``r`` on each segment)."""
    n = len(xs)
    x = min(max(x, xs[0]), xs[n - 1])
    w = 0.0
    m = 0.0
    area = 0.0
    for i in range(n - 1):
        x0 = xs[i]
        if x <= x0:
            break
        h = xs[i + 1] - x0
        k = (rs[i + 1] - rs[i]) / h
        t = min(x, xs[i + 1]) - x0
        r0 = rs[i]
        wi = math.pi * t * (r0 * r0 + r0 * k * t + k * k * t * t / 3.0)
        w += wi
        m += x0 * wi + math.pi * t * t * (0.5 * r0 * r0 + 2.0 * r0 * k * t / 3.0 + 0.25 * k * k * t * t)
        r = r0 + k * t
        area = math.pi * r * r
    return w, m, area


@kernel
def equivalent_interval(xs, rs, volume, x_c):
    """Seed 000 section 4.1's equivalent body of a part, for a profile: ``(l, x_a, x_b)``, the axial
    interval of the body whose volume is ``volume`` and whose centroid is at ``x_c`` (the
    cylinder's: ``l = V / (pi R^2)`` about ``x_c``, :func:`.geometry.equivalent_of_part`), by Newton's
    method on the two conditions (the cumulative volume and moment in closed form); where the
    interval would leave the body it is shifted, not shrunk, to end there (its volume kept, its
    centroid then not ``x_c``), as the cylinder's is."""
    n = len(xs)
    xt = xs[0]
    xn = xs[n - 1]
    w_all, _, _ = _cumulative(xs, rs, xn)
    if volume >= w_all:
        return xn - xt, xt, xn
    _, _, a_c = _cumulative(xs, rs, x_c)
    if a_c > 0.0:
        ell = volume / a_c
    else:
        ell = (xn - xt) * volume / w_all
    xa = max(x_c - 0.5 * ell, xt)
    xb = min(x_c + 0.5 * ell, xn)
    tol = 1e-14 * w_all
    for _ in range(60):
        wa, ma, aa = _cumulative(xs, rs, xa)
        wb, mb, ab = _cumulative(xs, rs, xb)
        f1 = wb - wa - volume
        f2 = mb - ma - x_c * volume
        if abs(f1) <= tol and abs(f2) <= tol * (xn - xt):
            break
        det = aa * ab * (xa - xb)
        if det == 0.0:
            break
        dxa = -(ab * xb * f1 - ab * f2) / det
        dxb = -(aa * xa * f1 - aa * f2) / det
        xa_new = min(max(xa + dxa, xt), xn)
        xb_new = min(max(xb + dxb, xt), xn)
        if not (xb_new > xa_new):
            break
        if xa_new == xa and xb_new == xb:
            break
        xa = xa_new
        xb = xb_new
    # at an end: keep the volume, shift the interval (Newton on the free end alone)
    wa, _, _ = _cumulative(xs, rs, xa)
    wb, _, _ = _cumulative(xs, rs, xb)
    if xa <= xt or xb >= xn or abs(wb - wa - volume) > 1e-12 * w_all:
        if x_c - xt < xn - x_c:  # the tail end
            xa = xt
            target = volume
            x = xb
            for _ in range(60):
                w, _, a = _cumulative(xs, rs, x)
                if a <= 0.0 or abs(w - target) <= tol:
                    break
                x = min(max(x - (w - target) / a, xt), xn)
            xb = x
        else:
            xb = xn
            target = w_all - volume
            x = xa
            for _ in range(60):
                w, _, a = _cumulative(xs, rs, x)
                if a <= 0.0 or abs(w - target) <= tol:
                    break
                x = min(max(x - (w - target) / a, xt), xn)
            xa = x
    return xb - xa, xa, xb
