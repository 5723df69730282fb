"""The standing body's initial burial and measures of the scour stage (kernels/mine/scour_batch.py:
``standing_burial``, ``standing_measures``; docs/scour.md, Standing body), against the closed form of
a frustum standing on its base: the part below a horizontal plane at height ``b`` above the base is a
truncated cone, ``V(b) = pi b (R0^2 + R0 r(b) + r(b)^2) / 3`` with ``r(b) = R0 + (R1 - R0) b / H``,
and its lateral area ``pi (R0 + r(b)) sqrt(b^2 + (R0 - r(b))^2)``; checked also against scipy's
quadrature of ``pi r(z)^2``. (benchmarks/results/frustum_scour_speed.md: these kernels are a few
microseconds a drop; the tests pin what they compute, whatever their cost.)
"""

import math

import pytest
from scipy import integrate, optimize

from mineburial.kernels.mine import scour_batch as sb
from mineburial.kernels.mine.bodies.frustum import Frustum
from mineburial.kernels.mine.bodies.revolution_geometry import burial_profile

H = 0.44  # the Manta-like height [m]
R0 = 0.49  # its base radius [m]
BODIES = [Frustum(H, R0, ratio * R0, chi) for ratio in (0.31, 0.41, 0.51) for chi in (-0.03, 0.0, 0.02)]


def radius(body, z):
    """Radius at height z above the base (base = tail)."""
    return body.radius_tail + (body.radius_nose - body.radius_tail) * z / body.length


def cone_volume(body, b):
    """The truncated cone's volume below height b above the base (closed form)."""
    b = min(max(b, 0.0), body.length)
    r0, r1 = body.radius_tail, radius(body, b)
    return math.pi * b * (r0 * r0 + r0 * r1 + r1 * r1) / 3.0


def base_depth_state(body, d):
    """(a_z, z_c) of the level standing body (axis up, base down) with its base d below the bed."""
    x_tail = -0.5 * body.length - body.com_offset
    return 1.0, -d - x_tail


@pytest.mark.parametrize("body", BODIES)
def test_closed_form_matches_scipy_quadrature(body):
    """The reference itself: the truncated cone against scipy's quadrature of pi r(z)^2."""
    for b in (0.0, 0.01, 0.1, 0.22, 0.37, body.length):
        q, _ = integrate.quad(lambda z: math.pi * radius(body, z) ** 2, 0.0, b, epsabs=0, epsrel=1e-13)
        assert cone_volume(body, b) == pytest.approx(q, rel=1e-12, abs=1e-15)


@pytest.mark.parametrize("body", BODIES)
def test_standing_measures_are_the_truncated_cone(body):
    v_tot = cone_volume(body, body.length)
    s_tot = math.pi * (body.radius_tail**2 + body.radius_nose**2) + math.pi * (
        body.radius_tail + body.radius_nose
    ) * math.hypot(body.length, body.radius_tail - body.radius_nose)
    for b in (0.003, 0.05, 0.1738, 0.3, 0.43):
        pv, ph, pa, proud, pen = sb.standing_measures(body, b)
        assert pv == pytest.approx(100.0 * cone_volume(body, b) / v_tot, rel=1e-12)
        assert ph == pytest.approx(100.0 * b / body.length, rel=1e-12)
        rb = radius(body, b)
        wet = math.pi * body.radius_tail**2 + math.pi * (body.radius_tail + rb) * math.hypot(
            b, body.radius_tail - rb
        )
        assert pa == pytest.approx(100.0 * wet / s_tot, rel=1e-12)
        assert pen == pytest.approx(b, rel=1e-14)
        assert proud == pytest.approx(body.length - b, rel=1e-14)


@pytest.mark.parametrize("body", BODIES)
def test_standing_burial_of_a_level_body_is_its_own_depth(body):
    """A body already standing level maps to its own base depth (to the bisection's last bits)."""
    for d in (0.002, 0.05, 0.2, 0.4):
        a_z, z_c = base_depth_state(body, d)
        assert sb.standing_burial(body, a_z, z_c) == pytest.approx(d, rel=1e-12, abs=1e-15)


@pytest.mark.parametrize("body", BODIES)
def test_standing_burial_inverts_the_truncated_cone(body):
    """From a tilted rest state: the base depth b of the level body with the same volume fraction
    below the bed, against the closed form inverted by scipy's brentq."""
    v_tot = cone_volume(body, body.length)
    checked = 0
    for a_z, z_c in ((0.98, 0.05), (0.9, 0.1), (0.87, 0.0), (-0.95, 0.12), (0.7, 0.02)):
        # the tilted body's volume below the bed (the profile geometry, itself checked against
        # scipy in tests/test_revolution_geometry.py)
        xs = (-0.5 * body.length - body.com_offset, 0.5 * body.length - body.com_offset)
        pct = burial_profile(xs, (body.radius_tail, body.radius_nose), a_z, z_c, 0.0)[0]
        if not 0.0 < pct < 100.0:
            continue
        ref = optimize.brentq(
            lambda b, f=pct / 100.0: cone_volume(body, b) / v_tot - f, 0.0, body.length, xtol=1e-15
        )
        assert sb.standing_burial(body, a_z, z_c) == pytest.approx(ref, rel=1e-11, abs=1e-14)
        checked += 1
    assert checked >= 4  # the states are partly buried (else the test would check nothing)


def test_standing_burial_limits():
    body = BODIES[4]
    # wholly proud: 0; wholly below the bed, the top d deep: the height + d
    a_z, z_c = base_depth_state(body, -0.1)
    assert sb.standing_burial(body, a_z, z_c) == 0.0
    a_z, z_c = base_depth_state(body, body.length + 0.05)
    assert sb.standing_burial(body, a_z, z_c) == pytest.approx(body.length + 0.05, rel=1e-14)
