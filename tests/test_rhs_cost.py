"""The right-hand side's own work cut at unchanged physics (issue 34 item 4, throughput).

* The right-hand side's cuts at the water surface and the seabed take the volume and centroid only
  (:func:`geometry.cut_cylinder_moments`, the body's ``cut_moments`` hook): the first three values of
  :func:`geometry.cut_cylinder` bit for bit, without the wetted end caps.
* The cut's Gauss rule (short kappa ranges) takes the sines and cosines of its node angles from one
  sincos per pair of nodes (angle sums) instead of a library sine of every angle: the same rule to
  rounding (against the rule with library sines, written out in Python) and as close to the exact
  moments as before.

References: the cut's moments as integrals over the axis of the circular segment's area and first
moment (seed 000 eqs. (25a), (27)) by mpmath at 30 digits, which uses none of the kernel's
antiderivatives or Gauss rule; and the full cut (bit for bit, the values the right-hand side took
before).
"""

import math

import mpmath
import numpy as np
import pytest

from mineburial.kernels.mine.geometry import N_GL, TAU, _partial_gauss, cut_cylinder, cut_cylinder_moments


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


def _short_range_cuts(rng, n):
    """Nearly horizontal cylinders (the kappa range a_z L / (b R) under geometry.TAU, where the cut
    takes its Gauss rule) cut near the top rim (full sections and a partial part from kappa = -1),
    near the lowest rim (a sliver to kappa = 1) and across the axis (no tangency)."""
    out = []
    for i in range(n):
        L = rng.uniform(0.5, 3.0)
        R = rng.uniform(0.1, 0.6)
        chi = rng.uniform(-0.2, 0.2)
        a_z = math.copysign(10.0 ** rng.uniform(-8, math.log10(0.2 * R / L)), rng.uniform(-1, 1))
        b = math.sqrt(1.0 - a_z * a_z)
        span = abs(a_z) * 0.5 * L  # the axis's height range about its middle
        kind = i % 3
        if kind == 0:  # the plane above the body's lowest top-rim point: tang1
            h = b * R + rng.uniform(-1.0, 1.0) * span
        elif kind == 1:  # near the lowest rim: tang2
            h = -b * R + rng.uniform(-1.0, 1.0) * span
        else:
            h = rng.uniform(-0.8, 0.8) * b * R
        # the plane h above the axis's middle: z_c - level = -(h - a_z chi) ... as the cut sees it
        level = -12.3
        z_c = level - h - a_z * (-chi)
        out.append((L, R, chi, a_z, z_c, level))
    return out


def test_gauss_rule_cuts_against_the_segment_integrals():
    """The cut's Gauss rule (short kappa ranges, nearly horizontal axes), whose node sines and
    cosines come from one sincos per pair of nodes, against mpmath's integrals of the segment: the
    volume within 1e-10 of itself, the centroid within 1e-11 of the body's length and 1e-12 of its
    radius (the rule with a sine of every angle was as far: 3.3e-11, 3.8e-12, 4e-16 on these cuts)."""
    rng = np.random.default_rng(346)
    worst = [0.0, 0.0, 0.0]
    for L, R, chi, a_z, z_c, level in _short_range_cuts(rng, 150):
        v, x, e = cut_cylinder_moments(L, R, chi, a_z, z_c, level)
        rv, rx, re = _reference_moments(L, R, chi, a_z, z_c, level)
        if not rv > 1e-9 * math.pi * R * R * L:
            continue
        worst[0] = max(worst[0], abs(v - rv) / rv)
        worst[1] = max(worst[1], abs(x - rx) / L)
        worst[2] = max(worst[2], abs(e - re) / R)
    assert worst[0] < 1e-10 and worst[1] < 1e-11 and worst[2] < 1e-12, worst


def _series(theta):
    """theta - sin(theta) cos(theta) = (u - sin u)/2, u = 2 theta, by its Taylor series (no
    cancellation; 20 terms, far beyond rounding for theta < 0.35)."""
    u = 2.0 * theta
    term = u**3 / 6.0
    total = term
    for k in range(2, 21):
        term = -term * u * u / ((2.0 * k) * (2.0 * k + 1.0))
        total += term
    return 0.5 * total


def _gauss_direct(R, k1, k2, tang1, tang2, w, dk, pm):
    """geometry._partial_gauss as it was (a sine of every node's angle and of both factors of its
    fraction along x, the cosine by the library), in Python."""
    if tang1:
        dth = math.acos(-k2)
        thm = math.pi - 0.5 * dth
    elif tang2:
        dth = math.acos(k1)
        thm = 0.5 * dth
    else:
        th1 = math.acos(k1)
        th2 = math.acos(k2)
        thm = 0.5 * (th1 + th2)
    sm = math.sin(thm)
    if not (tang1 or tang2):
        dth = 2.0 * math.asin(min(dk / (2.0 * sm), 1.0)) if sm > 0.0 else th1 - th2
    den = sm * math.sin(0.5 * dth)
    nodes, weights = np.polynomial.legendre.leggauss(N_GL)
    sv = sx = ss = sl = 0.0
    for t, wt in zip(nodes, weights):
        thk = thm - 0.5 * dth * t
        sk = math.sin(thk)
        phi = (math.sin(thm + 0.25 * dth * (1.0 - t)) * math.sin(0.25 * dth * (1.0 + t))) / den
        wk = wt * sk * 0.25 * dth / den
        ak = thk - math.sin(thk) * math.cos(thk) if thk >= 0.35 else _series(thk)
        sv += wk * ak
        sx += wk * ak * (phi - 0.5)
        ss += wk * sk**3
        sl += wk * thk
    vp = R * R * w * sv
    return vp, pm * vp + R * R * w * w * sx, R**3 * w * (2.0 / 3.0) * ss, R * w * 2.0 * sl


def test_gauss_rule_against_direct_sines():
    """The rule with the angle-sum sines and cosines against the same rule with a library sine of
    every angle, on 3,000 short kappa ranges of each kind (from kappa = -1, to kappa = 1, inside):
    volume and lateral area within 2e-14 of themselves; the axial moment (within 2e-14 of
    V (|p_m| + w)) and the e_down moment (2e-14 of itself) too, except from kappa = -1 (angles near
    pi, whose sines carry the angle's absolute rounding: there both rules are ~1e-11 from the exact
    moments, and within 3e-11 of each other)."""
    rng = np.random.default_rng(347)
    worst = np.zeros((3, 4))
    for n in range(9000):
        kind = n % 3
        dk = 10.0 ** rng.uniform(-9.0, math.log10(0.999 * TAU))
        if kind == 0:
            k1, k2, tang1, tang2 = -1.0, -1.0 + dk, True, False
        elif kind == 1:
            k1, k2, tang1, tang2 = 1.0 - dk, 1.0, False, True
        else:
            k1 = rng.uniform(-1.0 + 1e-3, 1.0 - dk - 1e-3)
            k2 = k1 + dk
            tang1 = tang2 = False
            dk = k2 - k1
        R = rng.uniform(0.1, 0.6)
        w = rng.uniform(0.1, 3.0)
        pm = rng.uniform(-1.0, 1.0)
        got = _partial_gauss(R, k1, k2, tang1, tang2, w, dk, pm)
        ref = _gauss_direct(R, k1, k2, tang1, tang2, w, dk, pm)
        scale = (abs(ref[0]), abs(ref[0]) * (abs(pm) + w), abs(ref[2]), abs(ref[3]))
        worst[kind] = np.maximum(worst[kind], [abs(a - b) / s for a, b, s in zip(got, ref, scale)])
    assert np.all(worst[1:] < 2e-14), worst
    assert worst[0, 0] < 2e-14 and worst[0, 3] < 2e-14, worst
    assert worst[0, 1] < 3e-11 and worst[0, 2] < 3e-11, worst
