"""Tests of the body protocol (mineburial.kernels.mine.bodies) with the cylinder as its body.

Every value reached through the protocol is checked against a closed form of the solid right
circular cylinder (volume pi R^2 h of a vertical one cut at height h, half the body and the
half-disc centroid 4R/(3 pi) of a horizontal one cut at its axis, the end sections' heights and
the rim's drop R sqrt(1 - a_z^2) for the vertical extent). The geometry's own quadrature-checked
tests are tests/test_geometry.py; here the question is whether the protocol reaches the cylinder
with the right arguments. One small compiled probe calls every geometric protocol function.
"""

import inspect
import math
import types
from typing import NamedTuple

import numpy as np
import pytest
from numba import njit
from numba.core import types as nbtypes

from mineburial.kernels.mine import bodies, layout
from mineburial.kernels.mine.bodies import cylinder
from mineburial.kernels.mine.bodies.cylinder import Cylinder

L, R, CHI = 2.0, 0.3, 0.1
BODY = Cylinder(L, R, CHI)
REL = 1e-12


@njit(cache=False)
def _probe(body, k1, k2, k3, z_c, level):
    """Every geometric protocol function at one attitude (k: E-frame vertical in body
    components, a_z = k1), COM height z_c and plane ``level``."""
    return (
        bodies.cut(body, k1, z_c, level),
        bodies.extent(body, k1, z_c),
        bodies.burial(body, k1, z_c, level),
        bodies.volume(body),
        bodies.ends(body),
        bodies.sizes(body),
        bodies.lowest_offset(body, k1, k2, k3),
        bodies.deepest_point(body, k1, k2, k3),
        bodies.strip_section(body),
    )


def _attitude(a_z):
    """Body components of k for an axis with vertical component a_z (k in the x-z plane)."""
    return a_z, 0.0, math.sqrt((1.0 - a_z) * (1.0 + a_z))


def test_horizontal_cylinder_cut_at_its_axis_is_half_below():
    cut, _, burial, vol, *_ = _probe(BODY, *_attitude(0.0), 0.0, 0.0)
    v, x_c, eta_c, lateral, nose, tail = cut
    assert v == pytest.approx(0.5 * math.pi * R * R * L, rel=REL)
    assert x_c == pytest.approx(-CHI, rel=REL)  # the middle of the body, chi behind the COM
    assert eta_c == pytest.approx(4.0 * R / (3.0 * math.pi), rel=REL)  # half-disc centroid
    assert lateral == pytest.approx(math.pi * R * L, rel=REL)
    assert nose == pytest.approx(0.5 * math.pi * R * R, rel=REL)
    assert tail == pytest.approx(0.5 * math.pi * R * R, rel=REL)
    assert vol == pytest.approx((math.pi * R * R * L, -CHI), rel=REL)
    pct_v, pct_h, pct_a, proud, pen = burial
    assert (pct_v, pct_h, pct_a) == pytest.approx((50.0, 50.0, 50.0), rel=REL)
    assert proud == pytest.approx(R, rel=REL)
    assert pen == pytest.approx(R, rel=REL)


@pytest.mark.parametrize("h", [0.05, 0.7, 1.9])
def test_vertical_cylinder_cut_at_height_h_holds_pi_r2_h(h):
    z_c = 0.4
    bottom = z_c - 0.5 * L - CHI  # nose up (a_z = 1): the tail is the lowest section
    cut, (z_min, z_max), burial, *_ = _probe(BODY, *_attitude(1.0), z_c, bottom + h)
    v, x_c, eta_c, lateral, nose, tail = cut
    assert v == pytest.approx(math.pi * R * R * h, rel=REL)
    assert x_c == pytest.approx(-0.5 * L - CHI + 0.5 * h, rel=REL)
    assert eta_c == 0.0
    assert lateral == pytest.approx(2.0 * math.pi * R * h, rel=REL)
    assert (nose, tail) == pytest.approx((0.0, math.pi * R * R), rel=REL)
    assert (z_min, z_max) == pytest.approx((bottom, bottom + L), rel=REL)
    pct_v, pct_h, pct_a, proud, pen = burial
    assert pct_v == pytest.approx(100.0 * h / L, rel=REL)
    assert pct_h == pytest.approx(100.0 * h / L, rel=REL)
    assert pct_a == pytest.approx(100.0 * (2.0 * h + R) / (2.0 * (L + R)), rel=REL)
    assert (proud, pen) == pytest.approx((L - h, h), rel=REL)


@pytest.mark.parametrize("a_z", [-0.6, 0.0, 0.35, 1.0])
def test_fully_buried_body_is_wholly_below_with_nothing_proud(a_z):
    z_c = -5.0
    cut, (z_min, z_max), burial, vol, *_ = _probe(BODY, *_attitude(a_z), z_c, 0.0)
    # the whole body below: the cut's volume and centroid are the whole body's
    assert cut[:3] == pytest.approx((vol[0], vol[1], 0.0), rel=REL, abs=1e-15)
    assert burial[:3] == pytest.approx((100.0, 100.0, 100.0), rel=REL)
    assert burial[3] == 0.0
    assert burial[4] == pytest.approx(0.0 - z_min, rel=REL)


@pytest.mark.parametrize("a_z", [-0.8, -0.2, 0.0, 0.5, 1.0])
def test_extent_lowest_point_and_sizes_match_the_cylinders_closed_forms(a_z):
    k = _attitude(a_z)
    z_c = 1.5
    _, (z_min, z_max), _, _, ends, sizes, lowest, deepest, section = _probe(BODY, *k, z_c, 0.0)
    xa, xb = -0.5 * L - CHI, 0.5 * L - CHI
    assert ends == pytest.approx((xa, xb), rel=REL)
    drop = R * math.sqrt(1.0 - a_z * a_z)  # the rim below an end section's centre
    assert z_min == pytest.approx(z_c + min(a_z * xa, a_z * xb) - drop, rel=REL, abs=1e-15)
    assert z_max == pytest.approx(z_c + max(a_z * xa, a_z * xb) + drop, rel=REL, abs=1e-15)
    assert lowest == pytest.approx(z_min - z_c, rel=REL, abs=1e-15)
    # the toppling pivot is a lowest point: its height above the COM is the lowest offset
    height = k[0] * deepest[0] + k[1] * deepest[1] + k[2] * deepest[2]
    assert height == pytest.approx(lowest, rel=1e-12, abs=1e-15)
    assert sizes == pytest.approx((L + R, 0.5 * L + abs(CHI) + R), rel=REL)
    assert section == (R, L)  # the strip theory's constant section and reference length


def test_equivalent_part_of_a_third_has_a_third_of_the_length():
    x_c = 0.2
    l, xa, xb, eta = njit(cache=False)(
        lambda b: bodies.equivalent_part(b, math.pi * R * R * L / 3, x_c, 0.0)
    )(BODY)
    assert l == pytest.approx(L / 3.0, rel=REL)
    assert (xa, xb) == pytest.approx((x_c - L / 6.0, x_c + L / 6.0), rel=REL)
    assert eta == 0.0


def test_the_body_is_built_from_the_parameter_vector_slots():
    p = np.zeros(layout.N_PARAMS)
    p[layout.P_LENGTH], p[layout.P_DIAMETER], p[layout.P_CHI] = L, 2.0 * R, CHI
    assert cylinder.from_params(p) == BODY


def test_a_shape_module_lacking_a_protocol_function_is_refused():
    shape = types.SimpleNamespace(**{name: (lambda body: 0.0) for name in bodies.PROTOCOL if name != "pore"})
    shape.__name__ = "half_a_shape"
    with pytest.raises(TypeError, match="pore"):
        bodies.register(tuple, shape)
    assert tuple not in bodies.SHAPES
    assert bodies.SHAPES[Cylinder] is cylinder


class _Cube(NamedTuple):
    side: float


def test_a_registered_shape_is_reached_by_its_type_and_a_chooser_sees_the_argument_types():
    shape = types.SimpleNamespace(**{name: (lambda body: 0.0) for name in bodies.PROTOCOL})
    shape.__name__ = "cube"
    shape.volume = lambda body: (body.side**3, 0.0)

    @bodies.by_type
    def extent(body, a_z, z_c):
        if isinstance(a_z, nbtypes.Integer):
            return lambda body, a_z, z_c: (-1.0, -1.0)
        return lambda body, a_z, z_c: (z_c - body.side, z_c + body.side)

    shape.extent = extent
    bodies.register(_Cube, shape)
    try:
        probe = njit(cache=False)(lambda b, a: (bodies.volume(b), bodies.extent(b, a, 5.0)))
        assert probe(_Cube(2.0), 0.5) == ((8.0, 0.0), (3.0, 7.0))
        assert probe(_Cube(2.0), 1) == ((8.0, 0.0), (-1.0, -1.0))
        assert probe(BODY, 0.0)[0] == pytest.approx(
            (math.pi * R * R * L, -CHI), rel=REL
        )  # still the cylinder
    finally:
        del bodies.SHAPES[_Cube]


def test_each_protocol_function_carries_its_declared_arguments_and_binds_keywords():
    for name in bodies.PROTOCOL:
        params = list(inspect.signature(getattr(bodies, name)).parameters)
        assert params == bodies.SIGNATURES[name].split(", ") and params[0] == "body"
        # the cylinder implements each under the same argument names (numba checks them)
        assert list(inspect.signature(getattr(cylinder, name)).parameters) == params
    probe = njit(cache=False)(lambda b, a: bodies.extent(b, z_c=5.0, a_z=a))
    z_lo, z_hi = probe(BODY, 0.0)  # horizontal axis: the rim R below and above the COM
    assert (z_lo, z_hi) == pytest.approx((5.0 - R, 5.0 + R), rel=REL)
    with pytest.raises(NotImplementedError, match="compiled code only"):
        bodies.extent(BODY, 0.0, 5.0)


class _Ball(NamedTuple):  # a class of its own: numba keeps each overload's implementations by type
    radius: float


def test_a_shape_whose_implementation_names_other_arguments_does_not_compile():
    shape = types.SimpleNamespace(**{name: (lambda body: 0.0) for name in bodies.PROTOCOL})
    shape.__name__ = "misnamed"
    shape.extent = lambda body, tilt, z_c: (z_c - 1.0, z_c + 1.0)  # protocol: (body, a_z, z_c)
    bodies.register(_Ball, shape)
    try:
        probe = njit(cache=False)(lambda b: bodies.extent(b, 0.5, 5.0))
        with pytest.raises(Exception, match="argument names"):
            probe(_Ball(1.0))
    finally:
        del bodies.SHAPES[_Ball]
