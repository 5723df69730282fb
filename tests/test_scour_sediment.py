"""The scour stage's sediment from the scenario's sediment class (issue 20 item 2; docs/scour.md,
Sediment): a key the ``[scour]`` section gives wins, a key it does not give comes from the class
(a map cell's own class), a profile keeps the defaults, and a cohesive class does not scour.

Independent references: the catalogue's classes against the published grain-size classes
(Wentworth 1922: sand is 0.0625-2 mm, fine sand 0.125-0.25 mm); a cohesive bed's burial at every
lead time equal to its impact burial (no growth, the law's statement); a run whose sand comes from
the class equal, drop by drop, to the same run with the class's values written in the section;
each map cell equal to the single run of its own scenario written out by hand.
"""

import json
import pathlib
import types

import numpy as np
import pytest
from test_maps import SEED, _scenario, cell_reference, expected_seed
from test_maps_scour import CURRENT, N, forcing_csv, with_scour
from test_scour_run import scenario

from mineburial.analyses.maps import run_map
from mineburial.analyses.synthetic import synthetic_environment
from mineburial.ensembles import runner
from mineburial.io.inputs import read_toml
from mineburial.kernels.mine import layout
from mineburial.kernels.mine import scour as sc
from mineburial.systems.mine import sediment_profiles as sp
from mineburial.systems.mine.processes import scour

LEADS = [0.0, 0.01, 0.5]  # days
SAND_RANGE = (6.25e-5, 2.0e-3)  # m, Wentworth (1922) sand
FINE_SAND = (1.25e-4, 2.5e-4)  # m, Wentworth (1922) fine sand


def section(tmp_path, **over):
    """A constant 0.9 m/s current over 12 h (above the threshold for 0.2 mm sand), no sediment keys."""
    return {"forcing": str(forcing_csv(tmp_path / "const.csv", u=0.9)), "lead_times_days": LEADS, **over}


def test_catalogue_clays_and_silt_are_cohesive_and_sand_is_fine_quartz_sand():
    for c in sp.CATALOGUE.values():
        assert "scour:" in c.source and ("cohesive" in c.source), c.name  # each states its source
        assert 2600.0 <= c.grain_density <= 2800.0  # quartz and the clay minerals
        assert (c.d50 is None) == c.cohesive, c.name
    assert [c.name for c in sp.CATALOGUE.values() if not c.cohesive] == ["sand"]
    sand = sp.CATALOGUE["sand"]
    assert SAND_RANGE[0] <= sand.d50 <= SAND_RANGE[1] and FINE_SAND[0] <= sand.d50 <= FINE_SAND[1]
    assert sand.d50 == 2.0e-4 and sand.grain_density == 2650.0


def test_a_key_the_section_gives_wins_over_the_class_and_a_profile_keeps_the_defaults(tmp_path):
    clay = scour.sediment_classes({"class": "soft_clay"}, None)
    assert scour.parse(section(tmp_path), classes=clay).cohesive is True
    given = scour.parse(section(tmp_path, cohesive=False, d50=3e-4, grain_density=2700.0), classes=clay)
    assert (given.cohesive, given.values["d50"], given.values["grain_density"]) == (False, 3e-4, 2700.0)
    assert given.from_class == {}
    sand = scour.parse(section(tmp_path), classes=scour.sediment_classes({"class": "sand"}, None))
    assert (sand.cohesive, sand.values["d50"], sand.values["grain_density"]) == (False, 2.0e-4, 2650.0)
    assert sand.resolved()["sediment_from_class"] == ["cohesive", "d50", "grain_density"]
    profile = {"density": 1500.0, "strength": 1000.0}
    assert scour.sediment_classes(profile, None) == ()
    default = scour.parse(section(tmp_path), classes=())
    fields = (default.cohesive, default.values["d50"], default.values["grain_density"])
    assert fields == (False, 2.0e-4, 2650.0) and "sediment_from_class" not in default.resolved()


def test_a_sampled_class_gives_each_drop_its_own_class_sediment(tmp_path):
    choice = types.SimpleNamespace(values=["soft_clay", "sand", "soft_clay"])
    spec = scour.parse(section(tmp_path), classes=scour.sediment_classes({}, choice))
    P = np.zeros((4, layout.N_PARAMS))
    P[:, [layout.P_DIAMETER, layout.P_LENGTH, layout.P_MASS]] = 0.5, 2.0, 600.0
    P[:, [layout.P_RHO_WATER, layout.P_NU_WATER, layout.P_GRAVITY]] = 1025.0, 1.05e-6, 9.81
    label = np.array([1.0, 0.0, 2.0, 1.0])  # index into the choice's labels, as the sampler gives
    S, _ = scour.stage_parameters(spec, P, {"sediment.class": label})
    assert S[:, sc.S_COHESIVE].tolist() == [0.0, 1.0, 1.0, 0.0]
    assert np.all(S[:, sc.S_D50] == 2.0e-4) and np.all(S[:, sc.S_RHO_GRAIN] == 2650.0)


def burial(ds):
    return ds["scour_burial_volume"].values  # drops x lead_time


def test_soft_clay_without_cohesive_in_the_section_does_not_scour(tmp_path):
    ds = runner.run_ensemble(scenario(tmp_path, section(tmp_path), n=4))
    b = burial(ds)
    ok = ds["scour_status"].values == 0
    assert ok.sum() >= 2
    assert np.array_equal(b[ok], np.repeat(b[ok, :1], len(LEADS), axis=1))  # no growth after impact
    assert json.loads(ds.attrs["scenario"])["scour"]["cohesive"] is True


def test_sand_without_d50_in_the_section_scours_with_the_class_sand(tmp_path):
    d = read_toml(scenario(tmp_path, section(tmp_path), n=4))
    d["sediment"]["class"] = "sand"
    from_class = runner.run_ensemble(d)
    resolved = json.loads(from_class.attrs["scenario"])["scour"]
    assert (resolved["d50"], resolved["grain_density"], resolved["cohesive"]) == (2.0e-4, 2650.0, False)
    d["scour"].update(d50=2.0e-4, grain_density=2650.0, cohesive=False)  # the class's values, written
    written = runner.run_ensemble(d)
    assert "sediment_from_class" not in json.loads(written.attrs["scenario"])["scour"]
    assert np.array_equal(burial(from_class), burial(written), equal_nan=True)
    b = burial(from_class)
    assert np.nanmax(b[:, -1] - b[:, 0]) > 0.0  # the sand scours


@pytest.fixture(scope="module")
def clay_and_sand_map(tmp_path_factory):
    """A 1 x 2 grid: a soft_clay cell and a sand cell, same depth and current; [scour] without
    d50, grain density or cohesive."""
    tmp = tmp_path_factory.mktemp("scoursed")
    env = synthetic_environment(ny=1, nx=2, seed=1)
    env["water_depth"].values[:] = 3.0
    names = sp.class_names()
    env["sediment_class"].values[0] = [names.index("soft_clay"), names.index("sand")]
    env["current_u"].values[:] = CURRENT["surface_velocity"][0]
    env["current_v"].values[:] = CURRENT["surface_velocity"][1]
    sec = section(tmp)
    return sec, run_map(with_scour(_scenario(), sec), env, n=N, seed=SEED)


def test_each_map_cell_scours_with_its_own_class_as_its_single_run(clay_and_sand_map):
    sec, ds = clay_and_sand_map
    mean = ds["scour_burial_volume_mean"].values[:, 0, :]  # lead_time x cell
    for i, name in enumerate(("soft_clay", "sand")):
        ref = runner.run_ensemble(
            with_scour(cell_reference(3.0, {"class": name}, CURRENT), sec), n=N, seed=expected_seed(SEED, i)
        )
        assert np.array_equal(mean[:, i], ref["scour_burial_volume_mean"].values, equal_nan=True), name
    assert np.all(np.isfinite(mean))
    assert np.all(mean[:, 0] == mean[0, 0])  # the clay cell: no growth after impact
    assert mean[-1, 1] > mean[0, 1]  # the sand cell scours


def test_the_class_table_of_docs_scenario_shows_the_catalogue_scour_sediment():
    text = (pathlib.Path(__file__).resolve().parent.parent / "docs" / "scenario.md").read_text(
        encoding="utf-8"
    )
    rows = {}
    for line in text.splitlines():
        cells = [c.strip() for c in line.strip("|").split("|")]
        if len(cells) == 9 and cells[0].strip("`") in sp.CATALOGUE:
            rows[cells[0].strip("`")] = cells[6:]
    assert set(rows) == set(sp.CATALOGUE)
    for name, (cohesive, d50, grain) in rows.items():
        c = sp.CATALOGUE[name]
        assert cohesive == ("yes" if c.cohesive else "no"), name
        assert (d50 == "—") if c.d50 is None else float(d50) * 1e-3 == pytest.approx(c.d50), name
        assert float(grain) == c.grain_density, name


def test_cohesive_cells_are_marked_not_modelled_and_hatched_on_the_map(clay_and_sand_map, tmp_path):
    """Issue 33 item 7b: where no post-impact process runs (the soft-clay cell: cohesive, the stage
    keeps the impact burial) the map says so, per cell, instead of a confident 'stays unburied':
    scour_not_modelled_fraction is the share of the cell's drops on a cohesive bed (catalogue:
    soft_clay cohesive, sand not), and the lead-time panels hatch such cells."""
    pytest.importorskip("matplotlib")
    from mineburial.analyses.maps import hatched_cells, not_modelled_cells, plot_lead_times

    _, ds = clay_and_sand_map
    share = ds["scour_not_modelled_fraction"].values
    assert share.shape == (1, 2)
    assert share[0, 0] == 1.0 and share[0, 1] == 0.0
    assert sp.CATALOGUE["soft_clay"].cohesive and not sp.CATALOGUE["sand"].cohesive
    np.testing.assert_array_equal(not_modelled_cells(ds), [[True, False]])
    lead = ds["lead_time"].values
    assert lead[0] == 0.0 and lead[1] > 0.0
    np.testing.assert_array_equal(hatched_cells(ds, 0), [[False, False]])  # the impact: modelled
    np.testing.assert_array_equal(hatched_cells(ds, 1), [[True, False]])
    png = plot_lead_times(ds, tmp_path / "lead.png", list(ds["lead_time"].values[:2]))
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
