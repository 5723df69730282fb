"""The crossing quartic's roots from Ferrari's closed form polished by Durand-Kerner sweeps
(``fast._quartic_roots``, issue 34 item 4), against independent references: numpy's companion-matrix
roots, the closed-form zeros of a product of two trigonometric factors (simple, nearly double, double
and complex pairs), brentq on sign changes, and the closed form's own roots against numpy's."""

import math

import numpy as np
from scipy.optimize import brentq

from mineburial.kernels.mine.sediment.fast import _quartic_angles, _quartic_roots, _quartic_starts


def _numpy_roots(c0, ca1, cb1, ca2, cb2):
    """The roots of w^2 p(t), w = exp(i t), from the FFT of p at 16 angles (not the kernel's algebra)."""
    tk = 2 * np.pi * np.arange(16) / 16
    p = c0 + ca1 * np.cos(tk) + cb1 * np.sin(tk) + ca2 * np.cos(2 * tk) + cb2 * np.sin(2 * tk)
    c = np.fft.fft(p) / 16
    return np.roots([c[2], c[1], c[0], c[-1], c[-2]])


def _angle_error(got, want):
    """Largest distance on the circle from an angle of ``want`` to the nearest of ``got``."""
    got = np.asarray(got)
    return max(np.min(np.abs(np.angle(np.exp(1j * (got - w))))) for w in want)


def _product_coefficients(a, cb, big_a, big_b, g):
    """Coefficients of (cos(t - a) - cb)(A + B cos(t - g)) as c0 + ca1 cos t + cb1 sin t + ca2 cos 2t
    + cb2 sin 2t (cos(t - a) cos(t - g) = cos(a - g) / 2 + cos(2t - a - g) / 2)."""
    return (
        -cb * big_a + 0.5 * big_b * math.cos(a - g),
        big_a * math.cos(a) - cb * big_b * math.cos(g),
        big_a * math.sin(a) - cb * big_b * math.sin(g),
        0.5 * big_b * math.cos(a + g),
        0.5 * big_b * math.sin(a + g),
    )


def _lead_below(c, tol):
    """The quartic's leading coefficient below ``tol`` of the largest (all zero included)."""
    big = max(abs(c[0]), math.hypot(c[1], c[2]), math.hypot(c[3], c[4]))
    return not (0.5 * math.hypot(c[3], c[4]) > tol * big)


def _separation(roots):
    """The smallest distance between two of the roots."""
    return np.min(np.abs(roots[:, None] - roots[None, :]) + np.eye(len(roots)) * 9)


def _random_coefficients(rng, n):
    """General coefficients over three decades, and sparse ones (zeros as a drop in one vertical plane
    gives: c0 = -ca2, ca1 = cb2 = 0)."""
    out = [tuple(rng.normal(size=5) * rng.choice([0.1, 1.0, 10.0], size=5)) for _ in range(n)]
    out += [tuple(rng.normal(size=5) * (rng.random(5) < 0.6)) for _ in range(n)]
    for _ in range(n // 4):
        ca2, cb1 = rng.normal(size=2) * 10.0 ** rng.uniform(-4, 1, size=2)
        out.append((-ca2, 0.0, cb1, ca2, 1e-23 * rng.normal()))
    return [tuple(float(x) for x in c) for c in out]


def test_closed_form_starts_are_numpys_roots():
    """Ferrari's roots (the sweeps' starts) are numpy's to 1e-4 relative at well separated roots
    (a start only has to lie in the sweeps' basin; on the contact states they are within ~1e-12)."""
    rng = np.random.default_rng(341)
    checked = 0
    for c in _random_coefficients(rng, 400):
        if _lead_below(c, 1e-6):
            continue
        want = _numpy_roots(*c)
        if _separation(want) < 1e-2:
            continue
        st = np.array(_quartic_starts(*c)).reshape(4, 2) @ np.array([1.0, 1j])
        for w in want:
            assert np.min(np.abs(st - w)) < 1e-4 * abs(w), (c, w, st)
        checked += 1
    assert checked > 600


def test_roots_are_numpys_on_sparse_and_general_coefficients():
    """The polished roots against numpy's: within 1e-9 of their modulus where the roots are 1e-3
    apart, on general coefficients and on sparse ones with exact zeros (the in-plane drops' quartics,
    whose complex pairs lie far from the unit circle, |w| up to ~1e4)."""
    rng = np.random.default_rng(342)
    checked = 0
    for c in _random_coefficients(rng, 400):
        if _lead_below(c, 1e-9):
            assert all(math.isnan(x.real) for x in _quartic_roots(*c))  # degenerate: NaN, as before
            continue
        want = _numpy_roots(*c)
        if _separation(want) < 1e-3:
            continue
        got = np.array(_quartic_roots(*c))
        for w in want:
            assert np.min(np.abs(got - w)) < 1e-9 * abs(w), (c, w, got)
        checked += 1
    assert checked > 700


def test_real_zeros_are_brentqs():
    """Each sign change of p on a fine grid brackets a zero that brentq finds (to 1e-15); it is one of
    the four angles to 1e-12 (simple zeros: the quartic's roots 1e-3 apart; the grid's cells 2 pi /
    720)."""
    rng = np.random.default_rng(343)
    tg = np.linspace(-np.pi, np.pi, 721)
    found = 0
    for c in _random_coefficients(rng, 100):
        c0, ca1, cb1, ca2, cb2 = c
        if _lead_below(c, 1e-3) or _separation(_numpy_roots(*c)) < 1e-3:
            continue

        def p(t, c0=c0, ca1=ca1, cb1=cb1, ca2=ca2, cb2=cb2):
            return c0 + ca1 * math.cos(t) + cb1 * math.sin(t) + ca2 * math.cos(2 * t) + cb2 * math.sin(2 * t)

        pv = np.array([p(t) for t in tg])
        got = _quartic_angles(*c)
        for k in np.nonzero(pv[:-1] * pv[1:] < 0)[0]:
            z = brentq(p, tg[k], tg[k + 1], xtol=1e-15)
            assert _angle_error(got, [z]) < 1e-12, (c, z, got)
            found += 1
    assert found > 150


def test_nearly_double_and_complex_pairs_are_the_closed_forms():
    """p = (cos(t - a) - cos b)(A + B cos(t - g)), |A| > |B|: two zeros a -+ b; with cosh b for cos b,
    the pair exp(i a +- b), of argument a. The angles within 2e-13 / b of them (a root's error near a
    double root grows as eps / separation, for any method) for b from 1e-1 down to 1e-8: the pair's
    argument runs continuously into the double zero where the pair is born."""
    rng = np.random.default_rng(344)
    for _ in range(600):
        a, g = rng.uniform(-np.pi, np.pi, 2)
        b = 10.0 ** rng.uniform(-8, -1)
        big_a, big_b = rng.normal(size=2)
        if abs(big_a) < 1.2 * abs(big_b):
            big_a = math.copysign(1.2 * abs(big_b) + 0.1, big_a)
        for complex_pair in (False, True):
            cb = math.cosh(b) if complex_pair else math.cos(b)
            got = _quartic_angles(*_product_coefficients(a, cb, big_a, big_b, g))
            want = [a, a] if complex_pair else [a - b, a + b]
            assert _angle_error(got, want) < 2e-13 / b, (a, b, complex_pair, got)
            # the two angles near a: both of them (the pair's argument is the same for w, 1/conj(w))
            near = sorted(abs(math.remainder(t - a, 2 * math.pi)) for t in got)[:2]
            assert near[1] < (b if not complex_pair else 0.0) + 2e-13 / b


def test_exact_multiple_roots_are_found():
    """Exact double and quadruple zeros (the closed form's starts coincide there, and the sweeps
    restart from the fixed starts): no NaN, the angles at the zero (to eps^(1/2), eps^(1/4))."""
    for a in (0.0, 0.5 * math.pi, 1.0, -2.5):
        got = _quartic_angles(*_product_coefficients(a, 1.0, 2.0, 1.0, 0.3))
        assert not any(math.isnan(x) for x in got)
        assert sorted(abs(math.remainder(t - a, 2 * math.pi)) for t in got)[1] < 1e-7
    # (1 - cos t)^2 = 3/2 - 2 cos t + cos(2t) / 2: a quadruple zero at 0
    got = _quartic_angles(1.5, -2.0, 0.0, 0.5, 0.0)
    assert max(abs(x) for x in got) < 1e-3
    # sin 2t: the four zeros k pi / 2, where |p| is small at 4 of the 8 angles the closed form samples
    got = sorted(_quartic_angles(0.0, 0.0, 0.0, 0.0, 1.0))
    assert _angle_error(got, [-0.5 * math.pi, 0.0, 0.5 * math.pi, math.pi]) < 1e-15
