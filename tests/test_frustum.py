"""Tests of the frustum's geometric protocol functions (mineburial.kernels.mine.bodies.frustum).

References: the cylinder's protocol (bodies.cylinder, geometry.py's closed forms, an independent
derivation) for a frustum of equal radii; the frustum's closed forms (volume ``pi L (r_t^2 + r_t r_n
+ r_n^2)/3`` and its centroid, an upright frustum's extent and a cut at a height); the lowest point's
height from its body-frame coordinates. Each function is compiled as the protocol compiles a
shape's function into its caller (njit of the implementation).
"""

import inspect
import math

import numpy as np
import pytest
from numba import njit

from mineburial.kernels.mine import bodies
from mineburial.kernels.mine.bodies import frustum
from mineburial.kernels.mine.bodies.cylinder import Cylinder
from mineburial.kernels.mine.bodies.frustum import Frustum

L, R, CHI = 2.0, 0.3, 0.1
#: a Manta-like frustum on its side's scale: base radius 0.49 m, top 0.2 m, height 0.38 m, COM low
MANTA = Frustum(0.38, 0.49, 0.2, 0.04)


# the shape's functions compiled (the protocol compiles each into its caller as an overload's implementation)
_cut, _extent, _burial, _volume, _ends, _reference_lengths, _lowest_offset, _deepest_point, _sizes = (
    njit(cache=False)(getattr(frustum, name)) for name in frustum.GEOMETRY
)


@njit(cache=False)
def _frustum_probe(body, k1, k2, k3, z_c, level):
    return (
        _cut(body, k1, z_c, level),
        _extent(body, k1, z_c),
        _burial(body, k1, z_c, level),
        _volume(body),
        _ends(body),
        _sizes(body),
        _lowest_offset(body, k1, k2, k3),
        _deepest_point(body, k1, k2, k3),
        _reference_lengths(body),
    )


@njit(cache=False)
def _cylinder_probe(body, k1, k2, k3, z_c, level):
    return (
        bodies.cut(body, k1, z_c, level),
        bodies.extent(body, k1, z_c),
        bodies.burial(body, k1, z_c, level),
        bodies.volume(body),
        bodies.ends(body),
        bodies.sizes(body),
        bodies.lowest_offset(body, k1, k2, k3),
        bodies.deepest_point(body, k1, k2, k3),
        bodies.reference_lengths(body),
    )


def _k(a_z):
    return a_z, 0.0, math.sqrt((1.0 - a_z) * (1.0 + a_z))


def test_each_function_takes_the_protocols_arguments():
    for name in frustum.GEOMETRY:
        assert list(inspect.signature(getattr(frustum, name)).parameters) == bodies.SIGNATURES[name].split(
            ", "
        )


def test_the_physics_is_missing_so_registration_is_refused():
    with pytest.raises(TypeError, match="surface_tractions"):
        bodies.register(Frustum, frustum)
    assert Frustum not in bodies.SHAPES


@pytest.mark.parametrize("a_z", [-1.0, -0.45, 0.0, 0.3, 0.999, 1.0])
def test_equal_radii_are_the_cylinder(a_z):
    for z_c in (-1.2, -0.3, 0.0, 0.2, 1.4):
        got = _frustum_probe(Frustum(L, R, R, CHI), *_k(a_z), z_c, 0.0)
        ref = _cylinder_probe(Cylinder(L, R, CHI), *_k(a_z), z_c, 0.0)
        for g, r in zip(got, ref):
            assert np.asarray(g, dtype=float) == pytest.approx(
                np.asarray(r, dtype=float), rel=1e-12, abs=1e-14
            )


def test_manta_like_frustum_closed_forms():
    length, rt, rn, chi = MANTA
    cut, (lo, hi), burial, (v, x_c), ends, sizes, lowest, deepest, refs = _frustum_probe(
        MANTA, *_k(1.0), 0.0, -10.0
    )
    v_closed = math.pi * length * (rt * rt + rt * rn + rn * rn) / 3.0
    # centroid of a frustum above its base: L (rt^2 + 2 rt rn + 3 rn^2) / (4 (rt^2 + rt rn + rn^2))
    above_tail = length * (rt * rt + 2.0 * rt * rn + 3.0 * rn * rn) / (4.0 * (rt * rt + rt * rn + rn * rn))
    assert (v, x_c) == pytest.approx((v_closed, -0.5 * length - chi + above_tail), rel=1e-13)
    assert ends == pytest.approx((-0.5 * length - chi, 0.5 * length - chi), rel=1e-15)
    assert (lo, hi) == pytest.approx(ends, rel=1e-15)  # upright: the base lowest, the top highest
    assert refs == (2.0 * rt, length)
    assert cut[0] == 0.0 and burial[:3] == (0.0, 0.0, 0.0)  # the seabed far below
    # on its side (axis horizontal): the base's rim lowest, R_max below the COM, towards e_down = -k
    *_, lowest, deepest, _ = _frustum_probe(MANTA, *_k(0.0), 0.0, -10.0)
    assert lowest == pytest.approx(-rt, rel=1e-15)
    assert deepest == pytest.approx((-0.5 * length - chi, 0.0, -rt), rel=1e-15, abs=1e-15)


@pytest.mark.parametrize("a_z", [-0.9, -0.2, 0.0, 0.6])
def test_the_deepest_point_is_as_low_as_the_lowest_offset_and_within_reach(a_z):
    k = _k(a_z)
    *_, sizes, lowest, deepest, _ = _frustum_probe(MANTA, *k, 0.0, -10.0)
    assert k[0] * deepest[0] + k[1] * deepest[1] + k[2] * deepest[2] == pytest.approx(lowest, abs=1e-15)
    assert math.hypot(*deepest) <= sizes[1]


def test_upright_frustum_half_in_the_seabed():
    length, rt, rn, chi = MANTA
    h = 0.5 * length
    r_h = 0.5 * (rt + rn)
    z_c = 0.0
    level = z_c - 0.5 * length - chi + h  # the plane half way up
    cut, _, burial, *_ = _frustum_probe(MANTA, *_k(1.0), z_c, level)
    assert cut[0] == pytest.approx(math.pi * h * (rt * rt + rt * r_h + r_h * r_h) / 3.0, rel=1e-13)
    assert burial[1] == pytest.approx(50.0, rel=1e-13)
    assert burial[3:] == pytest.approx((h, h), rel=1e-13)
