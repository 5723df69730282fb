"""The right-hand side's own work cut at unchanged physics (issue 34 item 4, throughput).

* The right-hand side's cuts at the water surface and the seabed take the volume and centroid only
  (:func:`geometry.cut_cylinder_moments`, the body's ``cut_moments`` hook): the first three values of
  :func:`geometry.cut_cylinder` bit for bit, without the wetted end caps.

References: the cut's moments as integrals over the axis of the circular segment's area and first
moment (seed 000 eqs. (25a), (27)) by mpmath at 30 digits, which uses none of the kernel's
antiderivatives or Gauss rule; and the full cut (bit for bit, the values the right-hand side took
before).
"""

import math

import mpmath
import numpy as np
import pytest

from mineburial.kernels.mine.geometry import cut_cylinder, cut_cylinder_moments


def _bits(x):
    return np.float64(x).view(np.int64)


def _reference_moments(L, R, chi, a_z, z_c, level):
    """(V, x_c, eta_c) of the part below ``level`` by mpmath quadrature over the axis x of the
    section's segment: kappa(x) = (z_c - level + a_z x)/(b R), theta = acos(kappa), area R^2 (theta
    - sin theta cos theta), first moment along e_down (2/3) R^3 sin^3 theta."""
    mpmath.mp.dps = 30
    a = mpmath.mpf(a_z)
    b = mpmath.sqrt(1 - a * a)
    bR = b * R
    c = mpmath.mpf(z_c) - mpmath.mpf(level)
    xt = mpmath.mpf(-0.5 * L - chi)
    xn = mpmath.mpf(0.5 * L - chi)

    def theta(x):
        k = (c + a * x) / bR
        if k <= -1:
            return mpmath.pi
        if k >= 1:
            return mpmath.mpf(0)
        return mpmath.acos(k)

    def area(x):
        t = theta(x)
        return R * R * (t - mpmath.sin(t) * mpmath.cos(t))

    def mom(x):
        return mpmath.mpf(2) / 3 * R**3 * mpmath.sin(theta(x)) ** 3

    cuts = [xt, xn]
    for k in (-1, 1):  # where a section becomes full / empty
        x = (k * bR - c) / a
        if xt < x < xn:
            cuts.append(x)
    cuts.sort()
    v = mpmath.quad(area, cuts)
    mx = mpmath.quad(lambda x: x * area(x), cuts)
    ms = mpmath.quad(mom, cuts)
    return float(v), float(mx / v) if v > 0 else None, float(ms / v) if v > 0 else None


def _states(rng, n):
    """Cylinders, attitudes and planes: every kind of cut (empty, full, partial with and without full
    sections, short kappa ranges of nearly horizontal axes), exactly vertical and horizontal axes."""
    out = []
    for i in range(n):
        L = rng.uniform(0.5, 3.0)
        R = rng.uniform(0.1, 0.6)
        chi = rng.uniform(-0.2, 0.2)
        a_z = rng.uniform(-1.0, 1.0)
        if i % 5 == 0:
            a_z = math.copysign(10.0 ** rng.uniform(-9, -1), a_z)  # nearly horizontal: Gauss rule
        if i % 23 == 0:
            a_z = float(rng.choice([-1.0, 1.0, 0.0, -0.0]))
        z_c = rng.uniform(-1.0, 1.0) * (0.5 * L * abs(a_z) + R * 1.2)
        out.append((L, R, chi, a_z, z_c, 0.0 if i % 2 else -12.3 + 0.0 * z_c))
    return out


def test_cut_moments_are_the_cut_bit_for_bit():
    """cut_cylinder_moments gives cut_cylinder's volume and centroid with the same bits, on 2,000 cuts
    of every kind."""
    rng = np.random.default_rng(344)
    for L, R, chi, a_z, z_c, level in _states(rng, 2000):
        z = z_c + level  # the plane cuts the body at some height
        full = cut_cylinder(L, R, chi, a_z, z, level)
        part = cut_cylinder_moments(L, R, chi, a_z, z, level)
        assert tuple(map(_bits, part)) == tuple(map(_bits, full[:3])), (L, R, chi, a_z, z, level)


def test_cut_moments_against_the_segment_integrals():
    """Volume and centroid against mpmath's integral of the segment along the axis (1e-12 of the
    whole body's volume, of its length and of its radius)."""
    rng = np.random.default_rng(345)
    n_short = 0
    for L, R, chi, a_z, z_c, level in _states(rng, 200):
        if abs(a_z) >= 1.0 or a_z == 0.0:
            continue  # the reference divides by a_z and by b
        z = z_c + level
        v, x, e = cut_cylinder_moments(L, R, chi, a_z, z, level)
        rv, rx, re = _reference_moments(L, R, chi, a_z, z, level)
        vol = math.pi * R * R * L
        assert v == pytest.approx(rv, abs=1e-12 * vol)
        if rv > 1e-6 * vol:
            assert x == pytest.approx(rx, abs=1e-12 * L)
            assert e == pytest.approx(re, abs=1e-12 * R)
        bR = R * math.sqrt(1.0 - a_z * a_z)
        if 0.0 < abs(a_z) * L < 0.25 * bR and 0.0 < rv < vol:
            n_short += 1
    assert n_short > 10
