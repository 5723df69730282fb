"""Exact cross-flow drag integrals (seed 001 eqs. (31)-(47)) against scipy quadrature.

Reference: ``scipy.integrate.quad`` of ``|v| v`` and ``x |v| v`` component by
component, with breakpoints at the station of minimum ``|v|`` (the zero crossing
in the degenerate case) and around it on the curvature scale ``m / |w|``.
Tolerance: ``|err| <= 1e-9 |ref| + 1e-12 * scale`` with ``scale`` the magnitude
of the integrand integrated (``S^2 |b - a|``, times ``max(|a|, |b|)`` for the
moments, ``S`` the largest speed on the interval).
"""

import math
import warnings

import numpy as np
import pytest
from scipy.integrate import IntegrationWarning, quad

from mineburial.kernels.crossflow import quadratic_drag_integrals

REL = 1e-9
ABS = 1e-12


def _breakpoints(a, b, vy, vz, wy, wz):
    w2 = wy * wy + wz * wz
    if w2 == 0.0:
        return []
    xm = -(vy * wy + vz * wz) / w2
    m = abs(vy * wz - vz * wy) / math.sqrt(w2)
    ell = m / math.sqrt(w2)  # width of the rounded kink of |v|
    pts = {xm}
    for k in (1.0, 10.0, 1e2, 1e4):
        pts.add(xm - k * ell)
        pts.add(xm + k * ell)
    return sorted(p for p in pts if a < p < b)


def quad_reference(a, b, vy, vz, wy, wz):
    """(Fy, Fz, My, Mz) by adaptive quadrature, reversed limits negated."""
    lo, hi, sign = (a, b, 1.0) if a <= b else (b, a, -1.0)
    if lo == hi:
        return np.zeros(4)
    pts = _breakpoints(lo, hi, vy, vz, wy, wz)

    def integrand(x, k):
        ey = vy + wy * x
        ez = vz + wz * x
        n = math.hypot(ey, ez)
        comp = ey if k % 2 == 0 else ez
        return n * comp * (x if k >= 2 else 1.0)

    out = np.empty(4)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", IntegrationWarning)
        for k in range(4):
            out[k] = quad(
                integrand, lo, hi, args=(k,), points=pts or None, epsabs=1e-300, epsrel=1e-13, limit=1000
            )[0]
    return sign * out


def _scales(a, b, vy, vz, wy, wz):
    s = max(math.hypot(vy + wy * a, vz + wz * a), math.hypot(vy + wy * b, vz + wz * b))
    sf = s * s * abs(b - a)
    sm = sf * max(abs(a), abs(b))
    return np.array([sf, sf, sm, sm])


def _check(args, got=None, ref=None):
    if got is None:
        got = np.array(quadratic_drag_integrals(*args))
    if ref is None:
        ref = quad_reference(*args)
    tol = REL * np.abs(ref) + ABS * _scales(*args)
    assert np.all(np.abs(got - ref) <= tol), (args, got, ref, got - ref, tol)


def _random_cases(rng, n):
    """Generic, degenerate, nearly degenerate and non-rotating cases."""
    cases = []
    for i in range(n):
        a, b = rng.uniform(-3.0, 3.0, 2)
        kind = i % 6
        vy, vz = rng.normal(size=2) * 10.0 ** rng.uniform(-1, 1)
        wy, wz = rng.normal(size=2) * 10.0 ** rng.uniform(-2, 1.5)
        if kind == 1:  # no rotation: C = 0
            wy = wz = 0.0
        elif kind == 2:  # parallel, zero crossing x0 inside [a, b]: v = w (x - x0)
            x0 = rng.uniform(min(a, b), max(a, b))
            vy, vz = -wy * x0, -wz * x0
        elif kind == 3:  # nearly parallel: |v_min| tiny relative to |w| L
            x0 = rng.uniform(min(a, b), max(a, b))
            eps = 10.0 ** rng.uniform(-12, -4) * math.hypot(wy, wz) * abs(b - a)
            ny, nz = wz, -wy
            nn = math.hypot(ny, nz)
            vy, vz = -wy * x0 + eps * ny / nn, -wz * x0 + eps * nz / nn
        elif kind == 4:  # slow rotation near the series/closed-form switch
            vc = math.hypot(vy, vz)
            lam = rng.uniform(0.05, 0.6)
            wscale = lam * vc / (0.5 * abs(b - a)) / math.hypot(wy, wz)
            wy, wz = wy * wscale, wz * wscale
            c = 0.5 * (a + b)
            vy, vz = vy - wy * c, vz - wz * c
        elif kind == 5:  # zero crossing outside [a, b]
            x0 = max(a, b) + rng.uniform(0.01, 2.0)
            vy, vz = -wy * x0, -wz * x0
        cases.append((a, b, vy, vz, wy, wz))
    return cases


def test_random_sweep_against_quad():
    rng = np.random.default_rng(20240601)
    for args in _random_cases(rng, 180):
        _check(args)


@pytest.mark.parametrize(
    "args",
    [
        # exactly parallel (exact floats): v = (2, -1) (x - 0.3), crossing inside
        (-1.0, 1.0, -0.6, 0.3, 2.0, -1.0),
        # crossing exactly at an end point and at the midpoint
        (-0.5, 1.5, 1.0, 0.0, 2.0, 0.0),
        (-2.0, 1.0, 0.0, 3.0, 0.0, 2.0),
        (-1.0, 1.0, 0.0, 0.0, 1.5, -2.5),
        # axis-aligned rotation with a perpendicular offset (m > 0, no sign change)
        (-1.2, 0.8, 0.7, 0.0, 0.0, 3.0),
        # nearly degenerate: v_min = 1e-13 / 1e-9 off a zero crossing
        (-1.0, 1.0, -0.3, 1e-13, 1.0, 0.0),
        (-1.0, 2.0, 1e-9, 0.45, 0.0, -1.5),
        # tiny rotation, long offset interval
        (10.0, 12.0, 1.0, -2.0, 1e-9, 3e-9),
        # reversed interval
        (1.0, -1.0, 0.4, 0.2, -1.0, 2.0),
    ],
)
def test_special_cases_against_quad(args):
    _check(args)


def test_equal_limits_give_zero():
    for args in [(0.7, 0.7, 1.0, 2.0, 3.0, 4.0), (0.0, 0.0, 0.0, 0.0, 0.0, 0.0)]:
        assert quadratic_drag_integrals(*args) == (0.0, 0.0, 0.0, 0.0)


def test_zero_velocity_gives_zero():
    assert quadratic_drag_integrals(-1.0, 2.0, 0.0, 0.0, 0.0, 0.0) == (0.0, 0.0, 0.0, 0.0)


def test_uniform_flow_closed_form():
    # w = 0: |v| v L and |v| v (b^2 - a^2) / 2 (elementary)
    a, b, vy, vz = -0.7, 1.9, 1.3, -0.4
    sp = math.hypot(vy, vz)
    ref = np.array(
        [sp * vy * (b - a), sp * vz * (b - a), sp * vy * (b * b - a * a) / 2, sp * vz * (b * b - a * a) / 2]
    )
    _check((a, b, vy, vz, 0.0, 0.0), ref=ref)


def test_pure_rotation_closed_form():
    # v = w x on [-l, l]: F = 0, M = |w| w int x^2 |x| dx = |w| w l^4 / 2
    l, wy, wz = 1.3, 0.6, -2.2
    ww = math.hypot(wy, wz)
    ref = np.array([0.0, 0.0, ww * wy * l**4 / 2, ww * wz * l**4 / 2])
    _check((-l, l, 0.0, 0.0, wy, wz), ref=ref)


def test_reversing_the_interval_negates():
    rng = np.random.default_rng(7)
    for a, b, vy, vz, wy, wz in _random_cases(rng, 60):
        f = np.array(quadratic_drag_integrals(a, b, vy, vz, wy, wz))
        r = np.array(quadratic_drag_integrals(b, a, vy, vz, wy, wz))
        sc = _scales(a, b, vy, vz, wy, wz)
        assert np.all(np.abs(f + r) <= 1e-14 * sc)


def test_velocity_scaling_is_quadratic():
    # v -> k v multiplies both integrals by k^2 (checked against the quad
    # reference of the unscaled problem, so extreme magnitudes are covered)
    rng = np.random.default_rng(11)
    for a, b, vy, vz, wy, wz in _random_cases(rng, 24):
        ref = quad_reference(a, b, vy, vz, wy, wz)
        sc = _scales(a, b, vy, vz, wy, wz)
        for k in (1e-150, 1e-7, 3.7, 1e120):
            got = np.array(quadratic_drag_integrals(a, b, k * vy, k * vz, k * wy, k * wz))
            tol = REL * np.abs(ref) + ABS * sc
            assert np.all(np.abs(got / k**2 - ref) <= tol), (k, got / k**2, ref)


def test_length_scaling():
    # x -> L x with the same velocity field (w -> w / L): F scales by L, M by L^2
    rng = np.random.default_rng(13)
    for a, b, vy, vz, wy, wz in _random_cases(rng, 24):
        ref = quad_reference(a, b, vy, vz, wy, wz)
        sc = _scales(a, b, vy, vz, wy, wz)
        for ell in (1e-100, 1e-3, 1e80):
            got = np.array(quadratic_drag_integrals(a * ell, b * ell, vy, vz, wy / ell, wz / ell))
            got /= np.array([ell, ell, ell * ell, ell * ell])
            assert np.all(np.abs(got - ref) <= REL * np.abs(ref) + ABS * sc), (ell, got, ref)


def test_nan_propagates():
    got = quadratic_drag_integrals(-1.0, 1.0, math.nan, 0.0, 1.0, 0.0)
    assert all(math.isnan(g) for g in got)
