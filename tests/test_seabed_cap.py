"""The Dormand-Prince step capped at the predicted seabed crossing (kernels/mine/stepper.py,
``_seabed_cap``): the predicted crossing against the closed-form lowest point of a cylinder
(benchmarks/results/error_norm.md)."""

import math

import numpy as np
import pytest
from conftest import scenario_dict

from mineburial.kernels.mine import layout
from mineburial.kernels.mine.dynamics import derivatives
from mineburial.kernels.mine.sediment import pack_law
from mineburial.kernels.mine.stepper import (
    MIN_REDO_STEP,
    N_EVENTS,
    SEABED_CAP_MARGIN,
    _seabed_cap,
    event_values,
    initial_state,
)
from mineburial.kernels.rotation import rotation_matrix
from mineburial.systems.mine.config import Scenario

L, D, DEPTH = 2.0, 0.5, 20.0


def _drop(pitch_deg, velocity, omega, height):
    """(y, f, p, law, g0): a cylinder (no centre-of-mass offset) whose lowest point is ``height`` above the
    seabed, moving at ``velocity`` and turning at ``omega`` (body frame); f = the right-hand side at y."""
    d = scenario_dict(
        mine={"length": L, "diameter": D, "com_offset": 0.0},
        environment={"water_depth": DEPTH},
        release={"position": [0.0, 0.0, -5.0], "pitch_deg": pitch_deg, "velocity": list(velocity)},
    )
    p, sb, cb = Scenario.from_dict(d).to_params()
    law = pack_law(p, p[layout.P_DIAMETER])
    y = np.empty(layout.N_EXT)
    initial_state(p, y)
    y[10:13] = omega
    a_z = _axis_z(y)
    # the closed-form lowest point of the cylinder: z - (L/2)|a_z| - (D/2) sqrt(1 - a_z^2)
    y[layout.Z] = -DEPTH + height + 0.5 * L * abs(a_z) + 0.5 * D * math.sqrt(1.0 - a_z * a_z)
    f = np.empty(layout.N_EXT)
    derivatives(y, p, law, sb, cb, np.empty(layout.N_WORK), f, np.zeros(layout.N_DIAG))
    g0 = np.empty(N_EVENTS)
    event_values(y, p, law, g0)
    return y, f, p, law, g0


def _axis_z(y):
    return np.array(rotation_matrix(y[6], y[7], y[8], y[9])).reshape(3, 3)[2, 0]


def _cap(h, y, f, p, law, g0):
    return _seabed_cap(h, y, f, p, law, g0, np.empty(layout.N_EXT), np.empty(N_EVENTS))


def test_the_cap_of_a_level_cylinder_is_its_height_over_its_sinking_speed():
    height, w = 0.05, -2.0
    y, f, p, law, g0 = _drop(0.0, (1.0, 0.0, w), (0.0, 0.0, 0.0), height)
    assert g0[2] == pytest.approx(height, rel=1e-12)  # the geometry of the test is the kernel's
    expected = height / -w * (1.0 + SEABED_CAP_MARGIN)
    assert _cap(1.0, y, f, p, law, g0) == pytest.approx(expected, rel=1e-8)
    # a step that ends before the crossing, a rising mine, and a crossing at the step's start
    assert _cap(0.01, y, f, p, law, g0) == 0.01
    y2, f2, p2, law2, g2 = _drop(0.0, (1.0, 0.0, 2.0), (0.0, 0.0, 0.0), height)
    assert _cap(1.0, y2, f2, p2, law2, g2) == 1.0
    y3, f3, p3, law3, g3 = _drop(0.0, (1.0, 0.0, w), (0.0, 0.0, 0.0), 1e-14)
    assert _cap(1.0, y3, f3, p3, law3, g3) == MIN_REDO_STEP


@pytest.mark.parametrize("pitch_deg", [30.0, -50.0, 80.0])
def test_the_cap_of_a_turning_cylinder_follows_its_lowest_point(pitch_deg):
    """The sinking rate of the lowest point, z' - (L/2) sign(a_z) a_z' + (D/2) a_z a_z' / sqrt(1 - a_z^2)
    with a' = omega_E x a (a the body axis, omega_E = R omega), against the cap's difference quotient."""
    height, velocity, omega = 0.02, (0.5, 0.2, -1.5), np.array([0.1, 0.8, 0.3])
    y, f, p, law, g0 = _drop(pitch_deg, velocity, omega, height)
    rot = np.array(rotation_matrix(y[6], y[7], y[8], y[9])).reshape(3, 3)
    a, omega_e = rot[:, 0], rot @ omega
    a_z, da_z = a[2], np.cross(omega_e, a)[2]
    rate = velocity[2] - 0.5 * L * math.copysign(1.0, a_z) * da_z
    rate += 0.5 * D * a_z * da_z / math.sqrt(1.0 - a_z * a_z)
    assert rate < 0.0
    expected = height / -rate * (1.0 + SEABED_CAP_MARGIN)
    assert _cap(1.0, y, f, p, law, g0) == pytest.approx(expected, rel=1e-5)
