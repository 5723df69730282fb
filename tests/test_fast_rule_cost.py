"""The fast sediment rule's cheaper pieces (issue 34 item 4, benchmarks/results/fast_rule_cost.md):
each against an independent reference (CPython's complex arithmetic, libm's log10 and hypot, the
closed form of the harmonic's roots, numpy's companion-matrix roots)."""

import math

import numpy as np
import pytest

from mineburial.kernels.mine.sediment.fast import (
    _cdiv,
    _cmul,
    _harmonic_roots,
    _nonzero,
    _quartic_roots,
    _sorted16,
    _zero_roots,
)
from mineburial.kernels.mine.sediment.laws import RATE_IMPACT35, RATE_NONE, RATE_SEMILOG, _rate

SPECIAL = (0.0, -0.0, 1e-300, -3e-310, 0.5, -2.0, 1e200, math.inf, -math.inf, math.nan)


def _values(rng, n):
    return list(rng.normal(size=n) * 10.0 ** rng.uniform(-8, 8, size=n))


def test_complex_product_and_quotient_are_cpythons_to_the_bit():
    """The real-arithmetic product and quotient of the Durand-Kerner sweeps give CPython's complex
    product and quotient (the same algorithm numba compiles, ``_Py_c_prod``, ``_Py_c_quot``) to the
    bit, on random operands over 16 decades and on signed zeros, tiny, huge, infinite and NaN parts
    (a zero divisor: NaN, where Python raises)."""
    rng = np.random.default_rng(34)
    vals = _values(rng, 400)
    pairs = [(vals[i], vals[i + 1], vals[i + 2], vals[i + 3]) for i in range(0, 396, 4)]
    finite, divisors = SPECIAL[:7], SPECIAL[2:]
    pairs += [(a, b, c, d) for a in finite for b in (1.5, -0.0) for c in divisors for d in (0.25, -3.0)]
    for ar, ai, br, bi in pairs:
        want = complex(ar, ai) * complex(br, bi)
        got = _cmul(ar, ai, br, bi)
        np.testing.assert_array_equal(np.array(got), np.array([want.real, want.imag]))
        if br == 0.0 and bi == 0.0:
            assert all(math.isnan(x) for x in _cdiv(ar, ai, br, bi))
            continue
        want = complex(ar, ai) / complex(br, bi)
        got = _cdiv(ar, ai, br, bi)
        np.testing.assert_array_equal(np.array(got), np.array([want.real, want.imag]))


def test_quartic_roots_are_numpys():
    """The four roots of the self-inversive quartic of a degree-2 trigonometric polynomial against
    numpy's companion-matrix roots of the same quartic (coefficients from the FFT of the polynomial
    sampled at 16 angles, not the kernel's algebra): each within 1e-9 of its modulus where the
    roots are apart by 1e-3 or more."""
    rng = np.random.default_rng(3434)
    tk = 2 * np.pi * np.arange(16) / 16
    checked = 0
    for _ in range(300):
        c0, ca1, cb1, ca2, cb2 = rng.normal(size=5) * rng.choice([0.1, 1.0, 10.0], size=5)
        p = c0 + ca1 * np.cos(tk) + cb1 * np.sin(tk) + ca2 * np.cos(2 * tk) + cb2 * np.sin(2 * tk)
        c = np.fft.fft(p) / 16
        want = np.roots([c[2], c[1], c[0], c[-1], c[-2]])
        if np.min(np.abs(want[:, None] - want[None, :]) + np.eye(4)) < 1e-3:
            continue
        got = np.array(_quartic_roots(c0, ca1, cb1, ca2, cb2))
        for w in want:
            assert np.min(np.abs(got - w)) < 1e-9 * abs(w), (w, got)
        checked += 1
    assert checked > 250


def test_harmonic_roots_at_zero_offset_are_the_closed_form():
    """k = 0: the roots of a cos t + b sin t are atan2(b, a) -+ pi/2 (the arccos of 0), the same as
    the general routine's to the bit (also where a^2 + b^2 underflows: both take that as a zero
    harmonic); a zero harmonic gives the double root atan2(b, a)."""
    rng = np.random.default_rng(35)
    vals = _values(rng, 200) + [0.0, -0.0, 1e-300]
    for a, b in zip(vals[:-1], vals[1:], strict=True):
        got = _zero_roots(a, b)
        assert got == _harmonic_roots(0.0, a, b)
        if a * a + b * b > 0.0:
            assert got == (math.atan2(b, a) - math.pi / 2, math.atan2(b, a) + math.pi / 2)
        elif a == 0.0 and b == 0.0:
            assert got == (math.atan2(b, a), math.atan2(b, a))


def test_nonzero_is_hypot_positive():
    """``_nonzero(a, b)`` is ``hypot(a, b) > 0`` for every pair of special and random values."""
    rng = np.random.default_rng(36)
    vals = list(SPECIAL) + _values(rng, 50)
    for a in vals:
        for b in vals:
            assert _nonzero(a, b) == (math.hypot(a, b) > 0.0), (a, b)


@pytest.mark.parametrize("law", [RATE_SEMILOG, RATE_IMPACT35, RATE_NONE])
def test_fast_rate_law_is_log10s_to_rounding(law):
    """The fast rule's rate factor (log(ratio)/ln 10) against the semilog law with libm's log10
    (1 + beta log10(rate / rate_ref), Biscontin & Pestana 2001) to 1e-15 relative (a few ulp), from the
    threshold (ratio 1) to 1e12; the other laws are :func:`.laws._rate`'s to the bit."""
    rng = np.random.default_rng(37)
    for _ in range(2000):
        speed = 10.0 ** rng.uniform(-6, 4)
        beta = rng.uniform(0.0, 0.5)
        rate_ref = 10.0 ** rng.uniform(-6, 0)
        diameter = rng.uniform(0.1, 1.0)
        got = _rate(speed, law, 3.0, 0.5, beta, rate_ref, diameter, True)
        if law == RATE_SEMILOG:
            ratio = speed / (diameter * rate_ref)
            want = 1.0 + beta * math.log10(ratio) if ratio > 1.0 else 1.0
            assert abs(got - want) <= 1e-15 * want, (speed, beta, rate_ref, diameter, got, want)
        else:
            assert got == _rate(speed, law, 3.0, 0.5, beta, rate_ref, diameter)
    assert _rate(1.0, RATE_SEMILOG, 3.0, 0.5, 0.1, 0.0, 1.0, True) == 1.0  # no reference rate: G = 1


def test_sorted_breakpoints_are_pythons_sort():
    """The 16 lateral breakpoints sorted by the compare-exchange network are Python's ``sorted`` of them
    (NaN replaced by the fill value first), on random values with ties, signed zeros and NaN, and on
    every 0-1 input of 16 (the 0-1 principle: then every input is sorted)."""
    rng = np.random.default_rng(38)
    for _ in range(3000):
        b = (
            rng.choice([-1.5, -0.0, 0.0, 0.3, 1.2, math.nan], size=16)
            if rng.random() < 0.3
            else rng.normal(size=16)
        )
        b = tuple(float(x) for x in b)
        got = _sorted16(b, 2.0)
        want = sorted(2.0 if math.isnan(x) else x for x in b)
        assert list(got) == want, (b, got)
    for bits in range(1 << 16):
        b = tuple(float((bits >> k) & 1) for k in range(16))
        assert list(_sorted16(b, 0.0)) == sorted(b)
