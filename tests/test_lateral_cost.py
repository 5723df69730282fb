"""The fast rule's depth terms of a linear profile without the bank (issue 34 item 4,
:func:`mineburial.kernels.mine.sediment.laws._linear_depth_terms`): the same values, to the bit, as the
general terms that take the bank, so that the rule's loops may take either."""

import math

import numpy as np
import pytest

from mineburial.ensembles.engine import load_ensemble
from mineburial.kernels.mine.layout import P_SED_CD, P_SED_PROFILE, P_SED_RESISTANCE, P_SED_S_GRAD
from mineburial.kernels.mine.sediment.laws import (
    _depth_terms,
    _linear_depth_terms,
    _linear_properties,
    _properties,
    pack_law,
)
from mineburial.systems.mine.ensemble import chunk_inputs

ZETAS = (-1.0, -0.0, 0.0, 1e-300, 0.01, 0.25, 0.7, 3.0, 40.0, math.inf, math.nan)


@pytest.fixture(scope="module")
def default_row():
    """The parameters of the default ensemble's first drop."""
    P, valid, _ = chunk_inputs(load_ensemble(None), 0, 1)
    return P[valid.astype(bool)][0]


@pytest.mark.parametrize("resistance", [0, 1, 2])
@pytest.mark.parametrize("strength_gradient", [1010.0, -5000.0])
def test_linear_depth_terms_are_the_general_ones_to_the_bit(default_row, resistance, strength_gradient):
    """Every resistance law, a strength that grows or is clipped at 0, depths above the seabed, at it,
    inside, infinite and NaN: the terms without the bank equal those with it, bit for bit."""
    p = default_row.copy()
    p[P_SED_PROFILE] = -1.0
    p[P_SED_RESISTANCE] = float(resistance)
    p[P_SED_S_GRAD] = strength_gradient
    p[P_SED_CD] = 1.2
    law = pack_law(p, 0.53, None)
    bank = np.zeros((0, 3, 1))
    for zeta in ZETAS:
        want = np.array(_depth_terms(zeta, law, bank))
        got = np.array(_linear_depth_terms(zeta, law))
        np.testing.assert_array_equal(got.view(np.int64), want.view(np.int64))
        rho0, krho, s0, ks, rho_w, g = 1420.0, 30.0, 2000.0, strength_gradient, 1025.0, 9.81
        want = np.array(_properties(zeta, rho0, krho, s0, ks, -1, bank, rho_w, g))
        got = np.array(_linear_properties(zeta, rho0, krho, s0, ks, rho_w, g))
        np.testing.assert_array_equal(got.view(np.int64), want.view(np.int64))
