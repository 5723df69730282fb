"""The scour stage starts from the mine lying down (issue 20, item 1; docs/scour.md, Rest attitude).

The stage's laws are those of a horizontal cylinder; its initial burial is that of the lying
cylinder with the same fraction of its volume below the bed as the impact's rest state. Before,
the stage started from the depth of the lowest point, so a nose-down mine with most of its body
proud counted B/D >= 0.5 at impact. References: the circular segment's area solved with scipy
(brentq), the buried volume of a vertical cylinder (p/L), and the lying mine's own burial."""

import math

import numpy as np
import pytest
from scipy.optimize import brentq

from mineburial.kernels.mine import layout
from mineburial.kernels.mine import scour as S
from mineburial.kernels.mine.bodies.cylinder import Cylinder
from mineburial.kernels.mine.scour_batch import MEASURE_NAMES, N_REST, R_AZ, R_ZC, lying_burial, scour_drops

L = 2.0
R = 0.265
D = 2 * R
CHI = 0.05


def segment_burial(fraction, radius=R):
    """B of a horizontal cylinder with ``fraction`` of its volume below the bed: the segment of
    central angle a has area R^2 (a - sin a)/2, and depth B = R (1 - cos(a/2))."""
    if fraction <= 0.0:
        return 0.0
    if fraction >= 1.0:
        return 2 * radius
    a = brentq(lambda a: (a - math.sin(a)) / (2 * math.pi) - fraction, 0.0, 2 * math.pi, xtol=1e-15)
    return radius * (1 - math.cos(a / 2))


@pytest.mark.parametrize("pen", [1e-4, 0.02, 0.1, R, 0.4, D - 1e-4])
def test_a_mine_already_lying_keeps_its_burial(pen):
    # horizontal axis (a_z = 0): lowest point at z_c - R = -pen
    assert lying_burial(Cylinder(L, R, CHI), 0.0, R - pen) == pytest.approx(pen, rel=1e-12, abs=1e-15)


@pytest.mark.parametrize("pen", [0.05, 0.4, 1.0, 1.7])
def test_nose_down_mine_lies_with_the_same_buried_volume(pen):
    """The failure this pins: a vertical mine with its nose 1 m into the bed (half its volume
    buried, most of it standing proud) started the stage at B = 1 m > D, fully buried."""
    # vertical, nose down (a_z = -1): the nose end is at z_c - (L/2 - chi) = -pen
    z_c = (0.5 * L - CHI) - pen
    b0 = lying_burial(Cylinder(L, R, CHI), -1.0, z_c)
    assert b0 == pytest.approx(segment_burial(pen / L), rel=1e-12)
    if pen == 1.0:
        assert b0 == pytest.approx(R, rel=1e-12)  # half the volume: lying half buried


def test_a_mine_whose_top_is_below_the_bed_lies_as_deep():
    z_c = -(0.5 * L + CHI) - 0.3  # vertical, nose down, tail end 0.3 m below the bed
    assert lying_burial(Cylinder(L, R, CHI), -1.0, z_c) == pytest.approx(D + 0.3, rel=1e-12)
    # a tilted one: its top is 0.1 m below the bed
    a = -math.sin(math.radians(30.0))
    top = max(a * (-0.5 * L - CHI), a * (0.5 * L - CHI)) + R * math.sqrt(1 - a * a)
    assert lying_burial(Cylinder(L, R, CHI), a, -top - 0.1) == pytest.approx(D + 0.1, rel=1e-12)


def test_stage_measures_are_those_of_the_lying_mine_and_keep_the_volume_class():
    """Under a calm sea (no growth) every lead time shows the lying mine at B0: its burial by
    volume is the impact's, its height burial B0/D and its height proud D - B0."""
    n = 4
    pitch = np.radians([0.0, 20.0, 60.0, 90.0])
    a_z = -np.sin(pitch)
    pens = np.array([0.1, 0.3, 0.6, 1.2])
    P = np.zeros((n, layout.N_PARAMS))  # the drops' bodies: the L x 2R cylinder, COM offset CHI
    P[:, layout.P_LENGTH], P[:, layout.P_DIAMETER], P[:, layout.P_CHI] = L, 2 * R, CHI
    rest = np.empty((n, N_REST))
    rest[:, R_AZ] = a_z
    for i in range(n):  # COM height that puts the lowest point at -pens[i]
        lo = min(a_z[i] * (-0.5 * L - CHI), a_z[i] * (0.5 * L - CHI)) - R * math.sqrt(1 - a_z[i] ** 2)
        rest[i, R_ZC] = -pens[i] - lo
    S_ = np.tile(S.default_parameters(diameter=D), (n, 1))
    t = np.arange(25.0) * 3600.0
    zero = np.zeros_like(t)
    leads = np.array([0.0, 0.5])
    measures = np.empty((n, len(MEASURE_NAMES), leads.size))
    time_to, mobile, codes = np.empty((n, 1)), np.empty(n), np.empty(n, dtype=np.int8)
    scour_drops(
        S_, np.ones(n), np.full(n, 12.0), np.ones(n, dtype=np.uint8), P, rest, t, zero, zero + 8.0,
        zero, zero, zero, zero, np.zeros(n), t[-1], S.build_orbital_table(), leads, np.array([0.5]),
        measures, time_to, mobile, codes, np.empty((n, leads.size)), np.empty((n, leads.size)),
    )  # fmt: skip
    assert np.all(codes == S.SCOUR_OK)
    # the impact's burial by volume of the vertical mine is pen / L; of the horizontal one the segment
    assert measures[3, 1, 0] == pytest.approx(100 * pens[3] / L, rel=1e-9)
    for i in range(n):
        b0 = S_[i, S.S_B0]
        for j in range(leads.size):
            pen, vol, height, _, proud = measures[i, :, j]
            assert pen == pytest.approx(b0, rel=1e-12)
            a = 2 * math.acos(1 - b0 / R)  # central angle of the buried segment
            assert vol == pytest.approx(100 * (a - math.sin(a)) / (2 * math.pi), rel=1e-9)
            assert height == pytest.approx(100 * b0 / D, rel=1e-12)
            assert proud == pytest.approx(D - b0, rel=1e-12)
    assert S_[0, S.S_B0] == pytest.approx(pens[0], rel=1e-12)  # lying: unchanged
    assert S_[3, S.S_B0] == pytest.approx(segment_burial(0.6), rel=1e-12)  # nose 1.2 m in: 60 %
    assert time_to[0, 0] == math.inf and time_to[3, 0] == 0.0  # calm: 0.1/0.53 never; 0.6 > 0.5 at once
