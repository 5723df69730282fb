"""Tests of the geometry of a body of revolution with a piecewise-linear radius profile cut by a
horizontal plane (mineburial.kernels.mine.bodies.revolution_geometry, issue 36 item 2).

References: the cylinder's own closed forms (:func:`mineburial.kernels.mine.geometry.cut_cylinder`,
an independent derivation in the segment parameter kappa) for the special case of two stations of
one radius; for frusta and a chain of them ending in a cone, scipy.integrate of the definitions
(the volume below the plane as the integral over the axis of the chord-width integral over the
section, ``int 2 sqrt(r^2 - s^2) ds`` from the plane's chord to the rim, its first moments the same
with ``x`` and ``s``; the wetted lateral area as ``int r sqrt(1 + r'^2) dphi dx`` over the arc whose
points lie below the plane), and closed forms of the whole frustum (volume ``pi h (r0^2 + r0 r1 +
r1^2)/3``, lateral area ``pi (r0 + r1)`` times the slant height) and of a vertical one cut at a
height.
"""

import math

import numpy as np
import pytest
from scipy import integrate

from mineburial.kernels.mine.bodies.revolution_geometry import (
    burial_profile,
    cut_profile,
    extent_profile,
    inertia_profile,
    lowest_profile_point,
    volume_profile,
)
from mineburial.kernels.mine.geometry import burial_measures, cut_cylinder, vertical_extent

#: a Manta-like truncated cone on its base (base radius 0.49 m, top 0.2 m, height 0.38 m; COM low)
FRUSTUM = (np.array([-0.15, 0.23]), np.array([0.49, 0.2]))
#: a cylinder with a conical nose and a tapered tail: three frusta, a pointed nose
CHAIN = (np.array([-1.0, -0.2, 0.5, 0.8]), np.array([0.25, 0.35, 0.35, 0.0]))


def _radius(xs, rs, x):
    return float(np.interp(x, xs, rs))


def _reference_cut(xs, rs, a_z, z_c, level):
    """(V, x_c, eta_c, lateral, nose cap, tail cap) by scipy.integrate of the definitions."""
    b = math.sqrt(1.0 - a_z * a_z)
    c = z_c - level

    def s_low(x):  # the plane's chord in the section at x, clipped to the disc
        r = _radius(xs, rs, x)
        return min(max((c + a_z * x) / b, -r), r)

    def section(x, weight):
        r = _radius(xs, rs, x)
        value, _ = integrate.quad(
            lambda s: weight(x, s) * 2.0 * math.sqrt(max(r * r - s * s, 0.0)),
            s_low(x),
            r,
            epsabs=1e-14,
            epsrel=1e-12,
        )
        return value

    def arc(x):  # lateral surface below the plane: points r cos(phi) >= (c + a_z x)/b
        r = _radius(xs, rs, x)
        if r <= 0.0:
            return 0.0
        phi_max = math.acos(s_low(x) / r)
        return 2.0 * phi_max * r

    # the stations and the points where a section turns full or empty ((c + a_z x)/b = +-r(x), linear
    # on each frustum): the outer integrands' kinks, given to quad as break points
    kinks = list(xs[1:-1])
    for x0, x1, r0, r1 in zip(xs[:-1], xs[1:], rs[:-1], rs[1:]):
        m = (r1 - r0) / (x1 - x0)
        for sign in (1.0, -1.0):
            den = a_z / b - sign * m
            if den != 0.0:
                k = (sign * (r0 - m * x0) - c / b) / den
                if x0 < k < x1:
                    kinks.append(k)

    def over_axis(f):
        value, _ = integrate.quad(
            f, xs[0], xs[-1], points=kinks or None, limit=400, epsabs=1e-14, epsrel=1e-12
        )
        return value

    V = over_axis(lambda x: section(x, lambda x, s: 1.0))
    Mx = over_axis(lambda x: section(x, lambda x, s: x))
    Ms = over_axis(lambda x: section(x, lambda x, s: s))
    lateral = 0.0
    for x0, x1, r0, r1 in zip(xs[:-1], xs[1:], rs[:-1], rs[1:]):
        stretch = math.sqrt(1.0 + ((r1 - r0) / (x1 - x0)) ** 2)
        inside = [k for k in kinks if x0 < k < x1]
        value, _ = integrate.quad(arc, x0, x1, points=inside or None, limit=400, epsabs=1e-14, epsrel=1e-12)
        lateral += stretch * value
    caps = []
    for x in (xs[-1], xs[0]):
        rr = _radius(xs, rs, x)
        caps.append(section(x, lambda x, s: 1.0) if rr > 0.0 else 0.0)
    return V, Mx / V, Ms / V, lateral, caps[0], caps[1]


@pytest.mark.parametrize("seed", range(4))
def test_two_stations_of_one_radius_are_the_cylinder(seed):
    L, R, chi = 2.0, 0.3, 0.1
    xs, rs = np.array([-0.5 * L - chi, 0.5 * L - chi]), np.array([R, R])
    rng = np.random.default_rng(seed)
    scale = np.array([math.pi * R * R * L, L, R, 2.0 * math.pi * R * L, math.pi * R * R, math.pi * R * R])
    for _ in range(300):
        a_z = rng.uniform(-1.0, 1.0)
        u = rng.random()
        if u < 0.1:
            a_z = float(rng.choice([-1.0, 0.0, 1.0]))
        elif u < 0.3:  # nearly horizontal: kappa nearly constant along the axis
            a_z = float(rng.choice([-1.0, 1.0]) * rng.uniform(0.0, 1e-3))
        z_c = rng.uniform(-1.5, 1.5)
        got = np.array(cut_profile(xs, rs, a_z, z_c, 0.0))
        ref = np.array(cut_cylinder(L, R, chi, a_z, z_c, 0.0))
        np.testing.assert_allclose(got / scale, ref / scale, rtol=0, atol=2e-14)
        assert extent_profile(xs, rs, a_z, z_c) == pytest.approx(
            vertical_extent(L, R, chi, a_z, z_c), abs=1e-15
        )


@pytest.mark.parametrize(
    "body, a_z, z_c",
    [
        (FRUSTUM, 0.0, 0.1),  # on its side, the plane through the middle
        (FRUSTUM, 0.6, 0.05),  # tilted: the plane cuts the base and the top's rim
        (FRUSTUM, -0.93, 0.2),  # nearly upside down
        (FRUSTUM, 0.99, 0.0),  # nearly on its base, the plane through the COM
        (CHAIN, 0.0, 0.0),
        (CHAIN, 0.3, 0.1),
        (CHAIN, -0.75, -0.25),
        (CHAIN, 0.999, 0.45),  # nose up, the plane near the cone's base
    ],
)
def test_cut_of_frusta_is_the_integral_of_the_definitions(body, a_z, z_c):
    xs, rs = body
    got = cut_profile(xs, rs, a_z, z_c, 0.0)
    ref = _reference_cut(xs, rs, a_z, z_c, 0.0)
    assert got[0] > 0.0
    assert got == pytest.approx(ref, rel=1e-9, abs=1e-12)


@pytest.mark.parametrize("body", [FRUSTUM, CHAIN])
def test_whole_body_below_is_the_frusta_closed_forms(body):
    xs, rs = body
    V = sum(
        math.pi * (x1 - x0) * (r0 * r0 + r0 * r1 + r1 * r1) / 3.0
        for x0, x1, r0, r1 in zip(xs[:-1], xs[1:], rs[:-1], rs[1:])
    )
    lateral = sum(
        math.pi * (r0 + r1) * math.hypot(x1 - x0, r1 - r0)
        for x0, x1, r0, r1 in zip(xs[:-1], xs[1:], rs[:-1], rs[1:])
    )
    centroid = (
        integrate.quad(lambda x: x * math.pi * _radius(xs, rs, x) ** 2, xs[0], xs[-1], points=list(xs))[0] / V
    )
    for a_z in (-0.7, 0.0, 0.4, 1.0):
        v, x_c, eta_c, lat, nose, tail = cut_profile(xs, rs, a_z, -10.0, 0.0)
        assert (v, x_c, eta_c, lat) == pytest.approx((V, centroid, 0.0, lateral), rel=1e-12, abs=1e-15)
        assert (nose, tail) == pytest.approx((math.pi * rs[-1] ** 2, math.pi * rs[0] ** 2), rel=1e-14)
        assert cut_profile(xs, rs, a_z, 10.0, 0.0)[0] == 0.0  # wholly above
    vol, x_vol, area = volume_profile(xs, rs)
    assert (vol, x_vol, area) == pytest.approx(
        (V, centroid, lateral + math.pi * (rs[0] ** 2 + rs[-1] ** 2)), rel=1e-12
    )


@pytest.mark.parametrize("h", [0.05, 0.19, 0.31])
def test_upright_frustum_cut_at_height_h_is_the_lower_frustum(h):
    (x0, x1), (r0, r1) = FRUSTUM
    z_c = 1.0  # axis up (a_z = 1): the base at z_c + x0
    r_h = r0 + (r1 - r0) * h / (x1 - x0)
    v, x_c, eta_c, lat, nose, tail = cut_profile(*FRUSTUM, 1.0, z_c, z_c + x0 + h)
    assert v == pytest.approx(math.pi * h * (r0 * r0 + r0 * r_h + r_h * r_h) / 3.0, rel=1e-13)
    centroid = x0 + h * (r0 * r0 + 2.0 * r0 * r_h + 3.0 * r_h * r_h) / (
        4.0 * (r0 * r0 + r0 * r_h + r_h * r_h)
    )
    assert x_c == pytest.approx(centroid, rel=1e-13)
    assert eta_c == 0.0
    assert lat == pytest.approx(math.pi * (r0 + r_h) * math.hypot(h, r0 - r_h), rel=1e-13)
    assert (nose, tail) == (0.0, pytest.approx(math.pi * r0 * r0, rel=1e-14))


@pytest.mark.parametrize("body", [FRUSTUM, CHAIN])
@pytest.mark.parametrize("a_z", [-1.0, -0.4, 0.0, 0.7, 1.0])
def test_extent_is_the_lowest_and_highest_surface_points(body, a_z):
    xs, rs = body
    b = math.sqrt(1.0 - a_z * a_z)
    x = np.union1d(np.linspace(xs[0], xs[-1], 100001), xs)  # the stations themselves among the points
    r = np.interp(x, xs, rs)
    z_c = 0.3
    lo, hi = extent_profile(xs, rs, a_z, z_c)
    assert lo == pytest.approx(z_c + np.min(a_z * x - b * r), abs=1e-12)
    assert hi == pytest.approx(z_c + np.max(a_z * x + b * r), abs=1e-12)


@pytest.mark.parametrize("body", [FRUSTUM, CHAIN])
def test_inertia_of_the_uniform_body_is_the_integral_over_it(body):
    xs, rs = body
    mass = 700.0

    def over_body(f):  # int f(x, r, phi) r dr dphi dx over the solid, scipy's tplquad
        total = 0.0
        for x0, x1 in zip(xs[:-1], xs[1:]):
            total += integrate.tplquad(
                lambda r, phi, x: f(x, r, phi) * r,
                x0,
                x1,
                0.0,
                2.0 * math.pi,
                0.0,
                lambda x, phi: _radius(xs, rs, x),
                epsabs=1e-13,
                epsrel=1e-11,
            )[0]
        return total

    rho = mass / over_body(lambda x, r, phi: 1.0)
    x_c = over_body(lambda x, r, phi: x) * rho / mass
    j_axial = rho * over_body(lambda x, r, phi: r * r)
    j_transverse = rho * over_body(lambda x, r, phi: (x - x_c) ** 2 + (r * math.sin(phi)) ** 2)
    assert inertia_profile(xs, rs, mass) == pytest.approx((j_axial, j_transverse), rel=1e-10)
    assert volume_profile(xs, rs)[1] == pytest.approx(x_c, rel=1e-10)


def test_inertia_of_two_stations_of_one_radius_is_the_cylinders():
    L, R, chi, m = 2.0, 0.3, 0.1, 700.0
    j1, j2 = inertia_profile(np.array([-0.5 * L - chi, 0.5 * L - chi]), np.array([R, R]), m)
    assert (j1, j2) == pytest.approx((m * R * R / 2.0, m * (3.0 * R * R + L * L) / 12.0), rel=1e-14)


@pytest.mark.parametrize("a_z", [-1.0, -0.5, 0.0, 0.3, 1.0])
def test_burial_and_lowest_point_of_two_stations_of_one_radius_are_the_cylinders(a_z):
    L, R, chi = 2.0, 0.3, 0.1
    xs, rs = np.array([-0.5 * L - chi, 0.5 * L - chi]), np.array([R, R])
    for z_c in (-0.9, -0.2, 0.0, 0.45, 1.3):
        got = burial_profile(xs, rs, a_z, z_c, 0.0)
        assert got == pytest.approx(burial_measures(L, R, chi, a_z, z_c, 0.0), rel=1e-12, abs=1e-12)
    k = (a_z, 0.0, math.sqrt(1.0 - a_z * a_z))  # k in the body's x-z plane
    x, y, z, height = lowest_profile_point(xs, rs, *k)
    assert height == pytest.approx(vertical_extent(L, R, chi, a_z, 0.0)[0], abs=1e-15)
    assert k[0] * x + k[1] * y + k[2] * z == pytest.approx(height, abs=1e-15)  # the point is that low


def test_burial_of_an_upright_frustum_half_in():
    (x0, x1), (r0, r1) = FRUSTUM
    h = 0.5 * (x1 - x0)  # the plane half way up: base and lower half of the side below
    r_h = 0.5 * (r0 + r1)
    pct_v, pct_h, pct_a, proud, pen = burial_profile(*FRUSTUM, 1.0, 0.0, x0 + h)
    v_tot = math.pi * (x1 - x0) * (r0 * r0 + r0 * r1 + r1 * r1) / 3.0
    s_tot = math.pi * (r0 * r0 + r1 * r1) + math.pi * (r0 + r1) * math.hypot(x1 - x0, r1 - r0)
    v = math.pi * h * (r0 * r0 + r0 * r_h + r_h * r_h) / 3.0
    area = math.pi * r0 * r0 + math.pi * (r0 + r_h) * math.hypot(h, r_h - r0)
    assert (pct_v, pct_h, pct_a) == pytest.approx((100.0 * v / v_tot, 50.0, 100.0 * area / s_tot), rel=1e-13)
    assert (proud, pen) == pytest.approx((h, h), rel=1e-13)


def test_tuples_of_stations_give_what_arrays_give():
    xs, rs = CHAIN
    for a_z, z_c in ((0.3, 0.1), (-0.75, -0.25), (0.0, 0.0)):
        as_tuples = (tuple(xs.tolist()), tuple(rs.tolist()))
        assert cut_profile(*as_tuples, a_z, z_c, 0.0) == cut_profile(xs, rs, a_z, z_c, 0.0)
        assert burial_profile(*as_tuples, a_z, z_c, 0.0) == burial_profile(xs, rs, a_z, z_c, 0.0)
    assert inertia_profile(*as_tuples, 5.0) == inertia_profile(xs, rs, 5.0)
