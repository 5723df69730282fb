"""Tests of the fluid strips of a body of revolution (mineburial.kernels.mine.bodies.revolution_fluid).

References: scipy.integrate.quad of the definitions (``int r |v| v dx`` with ``r`` and ``v`` linear
in ``x``; the strip force per unit length ``(1/2) rho C_D 2 r |v| v`` and its moment), the
cylinder's own strip forces (bit for bit for a frustum of equal radii), a profile split at a
collinear station (the same body), and strip theory's added mass of a frustum in closed form.
"""

import math

import numpy as np
import pytest
from scipy.integrate import quad

from mineburial.kernels.crossflow import quadratic_drag_integrals
from mineburial.kernels.mine.added_mass import finite_body_cross_drag
from mineburial.kernels.mine.bodies import revolution_fluid as rf
from mineburial.kernels.mine.coefficients import (
    axial_drag_coefficient,
    cross_drag_coefficient,
    lift_coefficient,
    roughness_scaled,
)
from mineburial.kernels.mine.dynamics import strip_forces


def _quad(f, a, b, points=None):
    val, _ = quad(f, a, b, epsabs=0.0, epsrel=1e-12, limit=400, points=points)
    return val


def _tapered_reference(a, b, ra, rb, vy0, vz0, wy, wz):
    """int r |v| v dx and int x r |v| v dx by adaptive quadrature, with |v|'s minimum as a breakpoint."""

    def r(x):
        return ra + (rb - ra) * (x - a) / (b - a)

    def v(x):
        return vy0 + wy * x, vz0 + wz * x

    pts = None
    w2 = wy * wy + wz * wz
    if w2 > 0.0:
        xm = -(vy0 * wy + vz0 * wz) / w2
        if a < xm < b:
            pts = [xm]
    out = []
    for k in (0, 1):
        for comp in (0, 1):
            out.append(_quad(lambda x, k=k, c=comp: x**k * r(x) * math.hypot(*v(x)) * v(x)[c], a, b, pts))
    return out[0], out[1], out[2], out[3]


def _states(n, seed):
    rng = np.random.default_rng(seed)
    for _ in range(n):
        a = rng.uniform(-1.5, 0.5)
        b = a + rng.uniform(0.05, 2.0)
        ra, rb = rng.uniform(0.0, 0.6, size=2)
        kind = rng.integers(4)
        vy0, vz0 = rng.normal(size=2) * 2.0
        if kind == 0:  # no rotation
            wy = wz = 0.0
        elif kind == 1:  # slow rotation (series branch)
            wy, wz = rng.normal(size=2) * 0.05
        elif kind == 2:  # |v| through zero inside the strip (degenerate branch)
            x0 = rng.uniform(a, b)
            wy, wz = rng.normal(size=2) * 3.0
            vy0, vz0 = -wy * x0, -wz * x0
        else:  # fast rotation
            wy, wz = rng.normal(size=2) * 4.0
        yield a, b, ra, rb, vy0, vz0, wy, wz


@pytest.mark.parametrize("state", list(_states(40, 7)))
def test_tapered_integrals_match_quadrature(state):
    got = rf.tapered_drag_integrals(*state)
    ref = _tapered_reference(*state)
    scale = max(abs(x) for x in ref) + 1e-300
    np.testing.assert_allclose(got, ref, rtol=0.0, atol=1e-11 * scale)


@pytest.mark.parametrize("state", list(_states(20, 11)))
def test_constant_radius_is_the_cylinders_integral_to_rounding(state):
    a, b, ra, _, vy0, vz0, wy, wz = state
    got = np.array(rf.tapered_drag_integrals(a, b, ra, ra, vy0, vz0, wy, wz))
    ref = ra * np.array(quadratic_drag_integrals(a, b, vy0, vz0, wy, wz))
    np.testing.assert_allclose(got, ref, rtol=0.0, atol=1e-14 * (np.abs(ref).max() + 1e-300))


def _args(rng):
    ur = rng.normal(size=3) * 1.5
    w = rng.normal(size=3) * 2.0
    return (*ur, *w)


@pytest.mark.parametrize("seed", range(8))
def test_equal_radii_give_the_cylinders_strip_forces_bit_for_bit(seed):
    rng = np.random.default_rng(seed)
    L, R, chi = 1.7, 0.26, rng.uniform(-0.3, 0.3)
    xs = (-0.5 * L - chi, 0.5 * L - chi)
    rs = (R, R)
    a = rng.uniform(xs[0], 0.0)
    b = rng.uniform(0.0, xs[1])
    for rho, nu in ((1025.0, 1.05e-6), (1.2, 1.5e-5)):
        for eta, rough in ((1.0, 1.0), (0.6, 1.3)):
            kin = _args(rng)
            got = rf.profile_strip_forces(rho, nu, xs, rs, L, a, b, *kin, 1, eta, rough)
            ref = strip_forces(rho, nu, R, L, a, b, *kin, 1, eta, rough)
            assert got == ref


def _strip_reference(rho, nu, xs, rs, L, a, b, ur1, ur2, ur3, w1, w2, w3, eta, rough):
    """The strip forces of the module docstring from their definitions, by quadrature."""
    r = lambda x: np.interp(x, xs, rs)  # noqa: E731
    vy = lambda x: ur2 - w3 * x  # noqa: E731
    vz = lambda x: ur3 + w2 * x  # noqa: E731
    speed = lambda x: math.hypot(vy(x), vz(x))  # noqa: E731
    pts = [x for x in xs if a < x < b]
    ell = b - a
    d_m = 2.0 * _quad(r, a, b, pts) / ell
    d_mean = 2.0 * _quad(r, xs[0], xs[-1], list(xs[1:-1])) / L
    aspect = L / d_mean
    vrms = math.sqrt(_quad(lambda x: speed(x) ** 2, a, b) / ell)
    re = vrms * d_m / nu
    cd2 = finite_body_cross_drag(roughness_scaled(cross_drag_coefficient(re, aspect), re, rough), re, eta)
    cl = lift_coefficient(w1 * 0.5 * d_m / vrms)
    # force per unit length: drag 0.5 rho cd2 2r |v| v, lift 0.5 rho cl 2r |v| (v x e1) = (vz, -vy)
    fy = lambda x: 0.5 * rho * 2.0 * r(x) * speed(x) * (cd2 * vy(x) + cl * vz(x))  # noqa: E731
    fz = lambda x: 0.5 * rho * 2.0 * r(x) * speed(x) * (cd2 * vz(x) - cl * vy(x))  # noqa: E731
    f2 = _quad(fy, a, b, pts)
    f3 = _quad(fz, a, b, pts)
    # torque of a force (0, fy, fz) at x i_M: x i_M x (0, fy, fz) = (0, -x fz, x fy)
    m2 = -_quad(lambda x: x * fz(x), a, b, pts)
    m3 = _quad(lambda x: x * fy(x), a, b, pts)
    m1 = -math.pi * rho * nu * w1 * _quad(lambda x: (2.0 * r(x)) ** 2, a, b, pts)
    f1 = 0.5 * rho * axial_drag_coefficient(aspect) * math.pi * max(rs) ** 2 * abs(ur1) * ur1 * ell / L
    return f1, f2, f3, m1, m2, m3


@pytest.mark.parametrize("seed", range(10))
def test_frustum_strip_forces_match_their_definition(seed):
    rng = np.random.default_rng(100 + seed)
    L, chi = rng.uniform(0.3, 2.0), rng.uniform(-0.1, 0.1)
    xs = (-0.5 * L - chi, 0.5 * L - chi)
    rs = tuple(rng.uniform(0.05, 0.5, size=2))
    if seed == 0:
        rs = (0.49, 0.0)  # a cone
    a = rng.uniform(xs[0], xs[0] + 0.4 * L)
    b = rng.uniform(xs[1] - 0.4 * L, xs[1])
    rho, nu = 1025.0, 1.05e-6
    kin = _args(rng)
    got = rf.profile_strip_forces(rho, nu, xs, rs, L, a, b, *kin, 1, 0.7, 1.0)
    ref = _strip_reference(rho, nu, xs, rs, L, a, b, *kin, 0.7, 1.0)
    scale = max(abs(x) for x in ref)
    np.testing.assert_allclose(got, ref, rtol=0.0, atol=2e-10 * scale)


def test_a_collinear_station_changes_nothing_but_rounding():
    rng = np.random.default_rng(5)
    xs2 = (-0.3, 0.5)
    rs2 = (0.45, 0.2)
    xm = 0.1
    xs3 = (-0.3, xm, 0.5)
    rs3 = (0.45, float(np.interp(xm, xs2, rs2)), 0.2)
    for _ in range(10):
        kin = _args(rng)
        a, b = sorted(rng.uniform(-0.3, 0.5, size=2))
        f2 = rf.profile_strip_forces(1025.0, 1e-6, xs2, rs2, 0.8, a, b, *kin, 1, 1.0, 1.0)
        f3 = rf.profile_strip_forces(1025.0, 1e-6, xs3, rs3, 0.8, a, b, *kin, 1, 1.0, 1.0)
        np.testing.assert_allclose(f3, f2, rtol=1e-12, atol=1e-12 * max(abs(x) for x in f2))


def test_strip_added_mass_of_a_frustum_in_closed_form():
    # whole frustum: int pi r^2 = V = pi h (r0^2 + r0 r1 + r1^2)/3; first moment about x0 from the
    # centroid h (r0^2 + 2 r0 r1 + 3 r1^2) / (4 (r0^2 + r0 r1 + r1^2)); second moment by sympy-free
    # expansion: int_0^h pi (r0 + s t)^2 t^2 dt with s = (r1 - r0)/h
    x0, h, r0, r1 = -0.2, 0.44, 0.49, 0.15
    xs, rs = (x0, x0 + h), (r0, r1)
    a0, a1, a2 = rf.profile_strip_added_mass(xs, rs, -10.0, 10.0)
    s = (r1 - r0) / h
    v = math.pi * h * (r0 * r0 + r0 * r1 + r1 * r1) / 3.0
    m1_about_x0 = math.pi * h * h * (r0 * r0 + 2.0 * r0 * r1 + 3.0 * r1 * r1) / 12.0
    m2_about_x0 = math.pi * (r0 * r0 * h**3 / 3.0 + 2.0 * r0 * s * h**4 / 4.0 + s * s * h**5 / 5.0)
    assert a0 == pytest.approx(v, rel=1e-14)
    assert a1 == pytest.approx(x0 * v + m1_about_x0, rel=1e-13)
    assert a2 == pytest.approx(x0 * x0 * v + 2.0 * x0 * m1_about_x0 + m2_about_x0, rel=1e-13)
    # part of it: quadrature of the definition
    a, b = -0.1, 0.15
    ref = [_quad(lambda x, k=k: math.pi * np.interp(x, xs, rs) ** 2 * x**k, a, b) for k in range(3)]
    np.testing.assert_allclose(rf.profile_strip_added_mass(xs, rs, a, b), ref, rtol=1e-13)
