"""The rigid-plastic hold test of kernels/mine/rest.py against a hand-computed case.

A nose-down vertical cylinder at rest with its flat nose zeta below the seabed, in a
sediment with the ``bearing`` law, no side adhesion and no rate effect. The only static
load is vertical: weight minus water buoyancy of the whole (submerged) body minus the
geostatic overburden of the embedded part, (rho_s - rho_w) g pi R^2 zeta for a uniform
density. The only mechanism it drives is sinking, which the sediment resists with the
bearing capacity of the nose, N_c S(zeta) pi R^2, N_c = N_c0 (1 + 0.4 arctan(zeta / d))
(Brinch Hansen 1970). So the mine is held exactly when

    m g <= rho_w g V + (rho_s - rho_w) g pi R^2 zeta + N_c S(zeta) pi R^2,

which fixes a threshold mass m*. The kernel forgives a load below its force tolerance
m v_probe / REST_TIME (REST_TIME = 1 s), so it holds up to m g - m v_probe / 1 s = m* g:
the mass at which it lets go is m* g / (g - v_probe / 1 s), to rounding.
"""

import math

import numpy as np
import pytest
from conftest import scenario_dict

from mineburial.kernels.mine import layout
from mineburial.kernels.mine.rest import REST_TIME, held_by_sediment
from mineburial.kernels.mine.sediment import pack_law
from mineburial.kernels.mine.stepper import initial_state
from mineburial.systems.mine.config import Scenario

G = 9.81
RHO_W = 1025.0
L, D = 1.0, 0.25
R = D / 2
AREA = math.pi * R * R
DEPTH = 10.0
RHO_S, S0, KS = 1500.0, 3000.0, 2000.0
NC0 = math.pi + 2.0
PROBE = 0.01  # m/s, the probe speed (the rest speed)


def _state(mass, zeta, pitch_deg=90.0, velocity=(0.0, 0.0, 0.0)):
    d = scenario_dict(
        mine={"mass": mass},
        environment={"water_depth": DEPTH, "gravity": G, "water_density": RHO_W},
        release={"position": [0.0, 0.0, -5.0], "pitch_deg": pitch_deg, "velocity": list(velocity)},
    )
    d["sediment"] = {
        "density": RHO_S,
        "density_gradient": 0.0,
        "strength": S0,
        "strength_gradient": KS,
        "resistance": "bearing",
        "rate_law": "none",
        "friction": 0.0,
        "bearing_factor": NC0,
    }
    p, sb, _ = Scenario.from_dict(d).to_params()
    y = np.empty(layout.N_EXT)
    initial_state(p, y)
    y[layout.Z] = -DEPTH + L / 2 - zeta  # the nose zeta below the seabed
    return y, p, pack_law(p, p[layout.P_DIAMETER]), sb


def threshold_mass(zeta):
    nc = NC0 * (1.0 + 0.4 * math.atan(zeta / D))
    capacity = nc * (S0 + KS * zeta) * AREA
    return (RHO_W * G * AREA * L + (RHO_S - RHO_W) * G * AREA * zeta + capacity) / G


@pytest.mark.parametrize("zeta", [0.05, 0.3, 0.8])
def test_hold_threshold_of_a_vertical_cylinder(zeta):
    assert REST_TIME == 1.0
    m_flip = threshold_mass(zeta) * G / (G - PROBE / REST_TIME)
    for factor, held in ((0.9, True), (1 - 1e-6, True), (1 + 1e-6, False), (1.1, False)):
        y, p, law, bank = _state(m_flip * factor, zeta)
        assert held_by_sediment(y, p, law, bank, PROBE) is held, (zeta, factor, m_flip)


def test_a_mine_lighter_than_its_displaced_sediment_and_water_is_not_held():
    """Net load upwards: the mine would rise; the nose does not resist that, nothing holds it."""
    zeta = 0.5
    buoyant = (RHO_W * AREA * L + (RHO_S - RHO_W) * AREA * zeta) * 0.9
    y, p, law, bank = _state(buoyant, zeta)
    assert held_by_sediment(y, p, law, bank, PROBE) is False


def test_a_mine_above_the_seabed_is_not_held():
    y, p, law, bank = _state(threshold_mass(0.3) * 0.5, -0.1)
    assert held_by_sediment(y, p, law, bank, PROBE) is False
