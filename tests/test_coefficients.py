"""Drag and lift coefficient laws against hand evaluation of the printed formulas.

References are the printed laws evaluated by hand in the test (the arithmetic
is written out): seed 000 eqs. (40), (44), (50).
Tolerance 1e-12 relative (pure floating-point evaluation of the same formula).
"""

import math

import pytest

from mineburial.kernels.mine.coefficients import (
    axial_drag_coefficient,
    cross_drag_coefficient,
    lift_coefficient,
)

R = 1e-12


# --- seed 000 eq. (40) -------------------------------------------------------


@pytest.mark.parametrize(
    "aspect, expected",
    [
        (1e6, 1.0),
        (10.0, 1.0),
        (8.000001, 1.0),
        (8.0, 0.75 + 8 / 32.1934 + 0.09612 / 8**2),
        (3.0, 0.75 + 3 / 32.1934 + 0.09612 / 3**2),
        (1.0, 0.75 + 1 / 32.1934 + 0.09612 / 1**2),
        (0.6, 0.75 + 0.6 / 32.1934 + 0.09612 / 0.6**2),
        (0.5, 1.15),
        (0.2, 1.15),
        (0.0, 1.15),
    ],
)
def test_axial_drag_branches(aspect, expected):
    assert axial_drag_coefficient(aspect) == pytest.approx(expected, rel=R)


def test_axial_drag_limits_join():
    # the middle branch meets the limiting values 1.0 (delta = 8) and 1.15 (delta = 0.5)
    assert axial_drag_coefficient(8.0) == pytest.approx(1.0, abs=1e-6)
    assert axial_drag_coefficient(0.5 + 1e-12) == pytest.approx(1.15, abs=2e-5)
    assert math.isnan(axial_drag_coefficient(math.nan))


# --- seed 000 eq. (44) -------------------------------------------------------


@pytest.mark.parametrize(
    "re, aspect, expected",
    [
        (5.0, 4.0, 1.9276 + 8 / 5),
        (12.0, 4.0, 1.9276 + 8 / 12),
        (100.0, 4.0, 1.261 + 16 / 100),
        (180.0, 4.0, 1.261 + 16 / 180),
        (1000.0, 4.0, 0.855 + 89 / 1000),
        (2000.0, 4.0, 0.855 + 89 / 2000),
        (5000.0, 4.0, 0.84 + 0.00003 * 5000),
        (12000.0, 4.0, 0.84 + 0.00003 * 12000),
        (50000.0, 20.0, 1.2 - 4 / 20),
        (50000.0, 10.0, 1.2 - 4 / 10),
        (50000.0, 5.0, 0.835 - 0.35 / 5),
        (150000.0, 2.0, 0.835 - 0.35 / 2),
        (50000.0, 1.0, 0.7 - 0.08 / 1),
        (200000.0, 4.0, 1.875 - 0.0000045 * 200000),
        (350000.0, 4.0, 1.875 - 0.0000045 * 350000),
        (1e6, 4.0, 1 / (641550 / 1e6 + 1.5)),
        (1e9, 0.5, 1 / (641550 / 1e9 + 1.5)),
    ],
)
def test_cross_drag_branches(re, aspect, expected):
    assert cross_drag_coefficient(re, aspect) == pytest.approx(expected, rel=R)


def test_cross_drag_aspect_only_matters_in_band():
    for re in (5.0, 100.0, 1000.0, 5000.0, 200000.0, 1e6):
        assert cross_drag_coefficient(re, 1.0) == cross_drag_coefficient(re, 30.0)


def test_cross_drag_low_reynolds_guard():
    # Re below 1e-6 is evaluated at 1e-6
    expected = 1.9276 + 8 / 1e-6
    for re in (0.0, 1e-12, 1e-6, -3.0):
        assert cross_drag_coefficient(re, 4.0) == pytest.approx(expected, rel=R)
    assert cross_drag_coefficient(1e-3, 4.0) == pytest.approx(1.9276 + 8 / 1e-3, rel=R)


def test_cross_drag_negative_branch_floored():
    # 0.7 - 0.08 / delta < 0 for delta < 0.1143: floored at zero
    assert cross_drag_coefficient(50000.0, 0.05) == 0.0
    assert cross_drag_coefficient(50000.0, 0.2) == pytest.approx(0.7 - 0.08 / 0.2, rel=R)


def test_cross_drag_documented_jumps():
    # near-continuous breakpoints (jumps below 1e-3)
    for re in (12.0, 180.0, 2000.0, 350000.0):
        below = cross_drag_coefficient(re, 4.0)
        above = cross_drag_coefficient(re * (1 + 1e-12), 4.0)
        assert abs(above - below) < 1e-3
    # the aspect-ratio band jumps at both ends unless delta -> infinity
    assert cross_drag_coefficient(12000.0, 4.0) == pytest.approx(0.84 + 0.00003 * 12000, rel=R)
    assert cross_drag_coefficient(12000.0 + 1e-6, 4.0) == pytest.approx(0.835 - 0.35 / 4, rel=R)
    assert cross_drag_coefficient(150000.0 + 1e-6, 4.0) == pytest.approx(
        1.875 - 0.0000045 * 150000.0, rel=1e-9
    )
    # within the band the three aspect branches of the kernel join at delta = 2 and delta = 10
    for delta in (2.0, 10.0):
        below = cross_drag_coefficient(50000.0, delta * (1 - 1e-12))
        above = cross_drag_coefficient(50000.0, delta * (1 + 1e-12))
        assert above == pytest.approx(below, rel=1e-9)
    assert math.isnan(cross_drag_coefficient(math.nan, 4.0))


# --- seed 000 eq. (50) -------------------------------------------------------


@pytest.mark.parametrize(
    "s, expected",
    [
        (0.0, 0.0),
        (1.0, 2 * 1.0),
        (4.0, 2 * 4.0),
        (6.0, 8 + 0.24 * (6 - 4)),
        (100.0, 8 + 0.24 * (100 - 4)),
        (-1.0, 2 * -1.0),
        (-6.0, -(8 + 0.24 * (6 - 4))),
    ],
)
def test_lift_branches(s, expected):
    assert lift_coefficient(s) == pytest.approx(expected, rel=R, abs=0.0)


def test_lift_is_odd_and_continuous():
    for s in (0.3, 3.9, 4.0, 4.1, 17.0, 1e5):
        assert lift_coefficient(-s) == -lift_coefficient(s)
    assert lift_coefficient(4.0 * (1 + 1e-12)) == pytest.approx(8.0, rel=1e-10)
    assert math.isnan(lift_coefficient(math.nan))
