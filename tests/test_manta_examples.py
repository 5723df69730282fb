"""The Manta-like examples (issue 36 item 3) as scenarios, without running a drop: they load, sample
the dimensions and mass their comments source (docs/notes/manta_research.md), give each drop a
frustum's closed-form mass properties; ``manta_scour`` adds a ``[scour]`` section, whose stage stands
the frustum on its base (docs/scour.md, Standing body) and refuses only the lying body's tilt state,
with a one-line error naming ``scour.rest_attitude``."""

import math

import numpy as np
import pytest

from mineburial.ensembles import engine
from mineburial.errors import ScenarioError
from mineburial.io.inputs import read_toml
from mineburial.kernels.mine import layout
from mineburial.systems.mine import config
from mineburial.systems.mine import ensemble as em

EXAMPLES = ("manta_ship_laid", "manta_air_laid", "manta_scour")


@pytest.mark.parametrize("name", EXAMPLES)
def test_manta_example_samples_a_sourced_frustum(name):
    assert name in config.ensemble_example_names()
    spec = engine.load_ensemble(config.example_path(name), n=300, chunk_size=300)
    P, valid = em.chunk_inputs(spec, 0, 300)[:2]
    assert np.all(valid)
    assert np.all(P[:, layout.P_SHAPE] == layout.MINE_SHAPES.index("frustum"))
    # base 0.98 m [T], height 0.44 m [M], top 0.30-0.50 m, mass 220-240 kg [M]
    assert np.all(P[:, layout.P_DIAMETER] == 0.98) and np.all(P[:, layout.P_LENGTH] == 0.44)
    top = P[:, layout.P_TOP_RATIO] * 0.98
    assert 0.30 <= top.min() and top.max() <= 0.50 and np.ptp(top) > 0.15
    m = P[:, layout.P_MASS]
    assert 220.0 <= m.min() and m.max() <= 240.0
    # each drop's default inertia: the uniform frustum's axial (3 m/10)(R^5 - r^5)/(R^3 - r^3)
    R, r = 0.49, 0.49 * P[:, layout.P_TOP_RATIO]
    np.testing.assert_allclose(P[:, layout.P_J1], 0.3 * m * (R**5 - r**5) / (R**3 - r**3), rtol=1e-12)
    # denser than the water, 1.1-1.55 x (research notes section 1.3)
    volume = math.pi * 0.44 * (R * R + R * r + r * r) / 3.0
    density = m / volume
    assert 1100.0 < density.min() and density.max() < 1550.0
    assert "no primary source" in read_toml(config.example_path(name))["description"]


def test_manta_scour_is_manta_ship_laid_over_sand_with_a_scour_section():
    """The same body and release as manta_ship_laid (the sampled mass, top and release of a drop
    are the same: the same seed and fields), over sand, with the storm's [scour] section."""
    ship = read_toml(config.example_path("manta_ship_laid"))
    scour = read_toml(config.example_path("manta_scour"))
    assert scour["mine"] == ship["mine"] and scour["release"] == ship["release"]
    assert scour["ensemble"]["seed"] == ship["ensemble"]["seed"]
    assert scour["sediment"]["class"] == "sand" and scour["scour"]["forcing"] == "storm_example"
    a = engine.load_ensemble(config.example_path("manta_ship_laid"), n=50, chunk_size=50)
    b = engine.load_ensemble(config.example_path("manta_scour"), n=50, chunk_size=50)
    Pa, Pb = em.chunk_inputs(a, 0, 50)[0], em.chunk_inputs(b, 0, 50)[0]
    for slot in (layout.P_MASS, layout.P_TOP_RATIO, layout.P_CHI, layout.P_J1, layout.P_J2):
        np.testing.assert_array_equal(Pa[:, slot], Pb[:, slot])


def test_scour_stage_stands_a_frustum_and_refuses_its_tilt_state_naming_the_field():
    raw = read_toml(config.example_path("scour_storm"))
    raw["mine"].update(shape="frustum", top_ratio=0.4)
    base_dir = config.example_path("scour_storm").parent
    engine.load_ensemble(raw, n=4, chunk_size=4, base_dir=base_dir)  # a frustum with [scour] loads
    raw["scour"].update(rest_attitude="impact", burial_law="scour_settle")
    with pytest.raises(
        ScenarioError, match=r"scour\.rest_attitude = 'impact' with mine\.shape = 'frustum'"
    ) as err:
        engine.load_ensemble(raw, n=4, chunk_size=4, base_dir=base_dir)
    assert "\n" not in str(err.value)
