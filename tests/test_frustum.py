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
(
    _cut,
    _extent,
    _burial,
    _volume,
    _ends,
    _reference_lengths,
    _lowest_offset,
    _deepest_point,
    _sizes,
    _cut_sliver,
) = (njit(cache=False)(getattr(frustum, name)) for name in frustum.GEOMETRY)


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


def test_the_protocol_is_complete_and_the_frustum_is_registered():
    # every protocol function is here and the module registers itself (issue 36: mine.shape), with
    # the fluid hooks that dynamics calls for it (strip_loads, added_mass) and its prototype body
    assert set(frustum.GEOMETRY + frustum.PHYSICS) == set(bodies.PROTOCOL)
    for name in frustum.PHYSICS:
        assert list(inspect.signature(getattr(frustum, name)).parameters) == bodies.SIGNATURES[name].split(
            ", "
        )
    assert bodies.SHAPES[Frustum] is frustum
    assert all(callable(getattr(frustum, name)) for name in frustum.FLUID_HOOKS)
    assert type(frustum.PROTOTYPE) is Frustum


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


# ---------------------------------------------------------------------------------------------
# the physics (issue 36 item 2)
# ---------------------------------------------------------------------------------------------
_equivalent_part, _surface_tractions, _pore, _strip_section, _finite_added_mass, _crossflow_efficiency = (
    njit(cache=False)(getattr(frustum, name)) for name in frustum.PHYSICS
)


@njit(cache=False)
def _frustum_physics(body, k1, k2, k3, d0, vbody, law, bank, volume, x_c):
    return (
        _equivalent_part(body, volume, x_c, 0.1),
        _surface_tractions(body, None, k1, k2, k3, d0, vbody, law, bank),
        _pore(body, k1, k2, k3, d0, 0.15, -0.7, law, bank),
        _strip_section(body),
        _finite_added_mass(body),
        _crossflow_efficiency(body),
    )


@njit(cache=False)
def _cylinder_physics(body, k1, k2, k3, d0, vbody, law, bank, volume, x_c):
    return (
        bodies.equivalent_part(body, volume, x_c, 0.1),
        bodies.surface_tractions(body, None, k1, k2, k3, d0, vbody, law, bank),
        bodies.pore(body, k1, k2, k3, d0, 0.15, -0.7, law, bank),
        bodies.strip_section(body),
        bodies.finite_added_mass(body),
        bodies.crossflow_efficiency(body),
    )


def _law(diameter):
    from test_sediment_kernel import params

    from mineburial.kernels.mine.sediment import pack_law
    from mineburial.kernels.mine.sediment.laws import LAW_REFERENCE_PATHS

    p = params(P_SED_QUADRATURE=0, P_SED_RESISTANCE=2, P_SED_RATE_LAW=1, P_SED_PORE=1.0)
    return pack_law(p, diameter)[:LAW_REFERENCE_PATHS]


@pytest.mark.parametrize("seed", range(4))
def test_equal_radii_physics_is_the_cylinders_bit_for_bit(seed):
    rng = np.random.default_rng(seed)
    length, radius, chi = rng.uniform(0.8, 2.5), rng.uniform(0.15, 0.5), rng.uniform(-0.2, 0.2)
    k = rng.normal(size=3)
    k /= np.linalg.norm(k)
    vbody = tuple(float(v) for v in rng.normal(size=6))
    bank = np.full((1, 3, 2), np.nan)
    law = _law(2.0 * radius)
    v_part = rng.uniform(0.1, 0.9) * math.pi * radius * radius * length
    x_c = rng.uniform(-0.4, 0.4) * length
    args = (*k, rng.uniform(-0.3, 0.3), vbody, law, bank, v_part, x_c)
    got = _frustum_physics(Frustum(length, radius, radius, chi), *args)
    ref = _cylinder_physics(Cylinder(length, radius, chi), *args)
    assert got == ref


@pytest.mark.parametrize("fraction", [0.05, 0.3, 0.7, 0.97])
def test_equivalent_part_has_the_parts_volume_and_centroid(fraction):
    from scipy.integrate import quad

    length, rt, rn, chi = MANTA
    xs = (-0.5 * length - chi, 0.5 * length - chi)
    area = lambda x: math.pi * np.interp(x, xs, (rt, rn)) ** 2  # noqa: E731
    v_all = quad(area, *xs)[0]
    # the part below a horizontal plane of an upright frustum: [xs[0], x_top], its own centroid
    x_top = xs[0] + fraction * length
    v = quad(area, xs[0], x_top)[0]
    x_c = quad(lambda x: x * area(x), xs[0], x_top)[0] / v
    ell, xa, xb, eta = _equivalent_part(MANTA, v, x_c, 0.25)
    assert (ell, xa, xb, eta) == pytest.approx((x_top - xs[0], xs[0], x_top, 0.25), rel=1e-11, abs=1e-12)
    # a slice in the middle: any interval [p, q] is found back from its volume and centroid
    p, q = xs[0] + 0.2 * fraction * length, xs[0] + (0.2 + 0.75 * fraction) * length
    v = quad(area, p, q)[0]
    x_c = quad(lambda x: x * area(x), p, q)[0] / v
    ell, xa, xb, _ = _equivalent_part(MANTA, v, x_c, 0.0)
    assert (xa, xb) == pytest.approx((p, q), rel=1e-10, abs=1e-11)
    # a centroid too close to an end: shifted to end there, the volume kept
    ell, xa, xb, _ = _equivalent_part(MANTA, 0.5 * v_all, xs[1] - 0.01, 0.0)
    assert xb == xs[1] and quad(area, xa, xb)[0] == pytest.approx(0.5 * v_all, rel=1e-12)


def test_added_mass_of_the_whole_frustum_is_the_bem_tables():
    from mineburial.kernels.mine.added_mass import frustum_added_mass

    length, rt, rn, chi = MANTA
    xs = (-0.5 * length - chi, 0.5 * length - chi)
    v, x_v = _volume(MANTA)
    m_a, m_t, m_c, m_r = frustum_added_mass(rt, rn, length)  # the top (smaller) is the nose: +x
    a0, a1, a2, a11 = frustum.added_mass_moments(MANTA, xs[0], xs[1])
    assert a0 == pytest.approx(m_t, rel=1e-13)
    assert a11 == pytest.approx(m_a, rel=1e-13)
    # coupling about the COM: m_c about the centroid plus m_t times the centroid's position
    assert a1 == pytest.approx(m_c + m_t * x_v, rel=1e-12)
    # rotation about the COM by parallel axes from the centroid's
    assert a2 == pytest.approx(m_r + 2.0 * x_v * m_c + m_t * x_v * x_v, rel=1e-12)
    # the same frustum turned round (nose the larger end) has its centre of added mass mirrored
    flipped = Frustum(length, rn, rt, -chi)
    b0, b1, b2, b11 = frustum.added_mass_moments(flipped, -xs[1], -xs[0])
    assert (b0, b1, b2, b11) == pytest.approx((a0, -a1, a2, a11), rel=1e-12)
    # the protocol's factors: fractions of rho V, k_r about the centre of added mass
    k_t, k_a, k_r = _finite_added_mass(MANTA)
    assert (k_t * v, k_a * v) == pytest.approx((m_t, m_a), rel=1e-13)
