"""Ensembles of seed 004's restraining system through ``mineburial run`` (system = "restraint").

What each test checks against what:

* bad input: every error names the field (or key), the value and what is allowed, before
  anything is computed; the commands that only run mines refuse a restraint scenario.
* sampling contract: the sampled friction, anchor mass and ship speed are the mine
  ensemble's draws, i.e. ``numpy.random.Philox(key=[seed, field_id])`` raw outputs mapped
  onto (0, 1) and through the uniform's inverse CDF (numpy is the independent reference);
  the anchor length follows the sampled mass as seed 004 §4.1 tabulates it.
* reproducibility: the same scenario and seed give bit-identical per-case values with 1 or 2
  threads, any chunk size, and after an interrupted run resumed from its chunk files.
* degenerate ensembles against single runs: every case of an ensemble whose distributions
  put all their probability on Table 2 case 3 (or case 4, where the anchor length is
  derived) gives exactly the result of ``simulate`` of that Table 2 case.
* the §4.3.1 trend: with only the friction uncertain, the stopping time falls strictly as
  the sampled friction rises, inside seed 004 Table 3's span for friction 0.3-0.7.

Short time limits keep the whole file at a few tens of seconds.
"""

from __future__ import annotations

import copy
import json

import numpy as np
import pytest
import xarray as xr

from mineburial.cli import main
from mineburial.ensembles import engine
from mineburial.ensembles.runner import run_ensemble
from mineburial.ensembles.sampling import field_id
from mineburial.errors import ScenarioError
from mineburial.io.dataset import registry_mismatches
from mineburial.kernels import multibody as kmb
from mineburial.systems.restraint import ensemble as ens
from mineburial.systems.restraint import model as rs


def _scenario(number: int = 1, t_max: float | None = None, **ensemble) -> dict:
    """Table 2 case ``number`` as a restraint ensemble scenario (a dict as read from TOML)."""
    raw = rs.table2_case(number).to_dict()
    raw["system"] = "restraint"
    if t_max is not None:
        raw["numerics"]["t_max"] = t_max
    raw["ensemble"] = {"seed": 7, **ensemble}
    return raw


def _uniform(low, high):
    return {"distribution": "uniform", "low": low, "high": high}


def _per_case(ds) -> dict:
    return {k: ds[k].values for k in ds.data_vars if "realization" in ds[k].dims}


# ---------------------------------------------------------------------------
# bad input
# ---------------------------------------------------------------------------
def _with(section, name, value, drop=None):
    raw = _scenario()
    raw[section][name] = value
    if drop:
        del raw[drop[0]][drop[1]]
    return raw


@pytest.mark.parametrize(
    "raw, words",
    [
        (_with("anchor", "frictionn", _uniform(0.3, 0.7)), ["anchor.frictionn", "friction"]),
        (_with("anchor", "friction", _uniform(0.3, 2.5)), ["anchor.friction", "[0, 2]", "2.5"]),
        (_with("anchor", "friction", _uniform(-0.2, 0.5)), ["anchor.friction", "[0, 2]"]),
        (_with("chain", "links", {"distribution": "choice", "values": [15, 16]}), ["chain.links", "whole"]),
        (
            _with("ship", "resistance_form", {"distribution": "choice", "values": ["printed", "ittc"]}),
            ["ship.resistance_form", "name"],
        ),
        (_with("ship", "speed", {"distribution": "uniform", "low": 3.0}), ["ship.speed", "high"]),
        ({**_scenario(), "system": "restrain"}, ["system", "restraint", "mine"]),
        ({**_scenario(), "ensemble": {"class_basis": "burial_area"}}, ["class_basis", "sampling, seed"]),
        ({**_scenario(), "ensemble": {"chunk_size": 0}}, ["ensemble.chunk_size", "[1, inf)"]),
        (_with("anchor", "mass", 500.0), ["anchor.mass", "floats"]),
        # an ensemble written before issue 18 renamed numerics.method (the mine's name, numerics.integrator)
        (
            _with("numerics", "method", "rk4", drop=("numerics", "integrator")),
            ["numerics.method", "numerics.integrator", "rename method to integrator"],
        ),
    ],
)
def test_bad_input_names_the_field(raw, words):
    with pytest.raises(ScenarioError) as info:
        engine.load_ensemble(raw, systems=engine.SYSTEMS)
    for word in words:
        assert word in str(info.value), (word, str(info.value))


def test_commands_for_mines_refuse_a_restraint_scenario(tmp_path, capsys):
    with pytest.raises(ScenarioError, match="system = 'restraint'.*mineburial run"):
        engine.load_ensemble(_scenario())  # maps, compare, sensitivity: mines only
    path = tmp_path / "bad.toml"
    text = ens.example_text().replace("high = 0.7}", "high = 2.5}")
    path.write_text(text)
    assert main(["run", str(path), "-o", str(tmp_path / "out.nc")]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.startswith("mineburial: error: anchor.friction")
    assert not (tmp_path / "out.nc").exists()


# ---------------------------------------------------------------------------
# sampling contract and reproducibility
# ---------------------------------------------------------------------------
def _philox_uniform(seed, field, n):
    """Draws 0..n-1 of ``field``: numpy's Philox4x64-10 raw outputs mapped onto (0, 1) as
    docs/notes/sampling.md specifies (the reference implementation, not the project's)."""
    bits = np.random.Philox(key=np.array([seed, field_id(field)], dtype=np.uint64)).random_raw(n)
    return ((bits >> np.uint64(12)).astype(np.float64) + 0.5) * 2.0**-52


def test_sampled_inputs_are_the_mine_ensembles_draws():
    raw = _scenario(t_max=0.05, n=5, chunk_size=2)
    del raw["anchor"]["length"]
    raw["anchor"]["friction"] = _uniform(0.3, 0.7)
    raw["anchor"]["mass"] = _uniform(40000.0, 60000.0)
    raw["ship"]["speed"] = _uniform(3.0, 5.0)
    ds = run_ensemble(raw, threads=1)
    for field, (low, high) in {
        "anchor.friction": (0.3, 0.7),
        "anchor.mass": (40000.0, 60000.0),
        "ship.speed": (3.0, 5.0),
    }.items():
        expected = low + (high - low) * _philox_uniform(7, field, 5)
        np.testing.assert_allclose(ds["input_" + field.replace(".", "_")].values, expected, rtol=1e-15)
    # seed 004 §4.1: 2.0, 2.5, 3.0 m for 40, 50, 60 t
    np.testing.assert_allclose(
        ds.input_anchor_length.values, ds.input_anchor_mass.values / 20000.0, rtol=1e-15
    )
    assert list(ds.case_status.values) == [kmb.TIME_LIMIT] * 5
    scen = json.loads(ds.attrs["scenario"])
    assert scen["system"] == "restraint" and set(scen["random_inputs"]) == {
        "anchor.friction",
        "anchor.mass",
        "ship.speed",
    }
    assert (
        ds.attrs["random_seed"] == 7
        and ds.attrs["sampling_method"] == "mc"
        and ds.attrs["mineburial_version"]
    )


def test_same_seed_same_values_any_threads_chunking_and_resume(tmp_path, monkeypatch):
    raw = _scenario(t_max=1.0, n=5)
    raw["anchor"]["friction"] = _uniform(0.3, 0.7)
    raw["ship"]["speed"] = _uniform(3.0, 5.0)
    one = run_ensemble(raw, threads=1, chunk_size=5)
    two = run_ensemble(raw, threads=2, chunk_size=3)
    # an interrupted run on a file, resumed: the finished chunk is read back, not recomputed
    out = tmp_path / "r.nc"
    real = engine.compute_chunk
    calls = []

    def interrupted(spec, start, stop):
        if start >= 2:
            raise KeyboardInterrupt
        return real(spec, start, stop)

    monkeypatch.setattr(engine, "compute_chunk", interrupted)
    with pytest.raises(KeyboardInterrupt):
        run_ensemble(raw, threads=2, chunk_size=2, output=out)
    assert not out.exists() and (tmp_path / "r.nc.parts" / "chunk-000000000000-000000000002.npz").exists()
    monkeypatch.setattr(
        engine, "compute_chunk", lambda spec, s, e: (calls.append((s, e)), real(spec, s, e))[1]
    )
    run_ensemble(raw, threads=2, chunk_size=2, output=out)
    assert calls == [(2, 4), (4, 5)]
    with xr.open_dataset(out) as back:
        three = back.load()
    for name, values in _per_case(one).items():
        for other in (two, three):
            np.testing.assert_array_equal(other[name].values, values, err_msg=name)
    assert np.all(np.isfinite(one.peak_ship_tension.values)) and np.all(one.peak_ship_tension.values > 0)


# ---------------------------------------------------------------------------
# against single runs and seed 004's trend
# ---------------------------------------------------------------------------
def test_degenerate_ensemble_is_table2_case3_exactly():
    """All probability on Table 2 case 3 (friction 0.7): every case is ``simulate``'s case 3."""
    raw = _scenario(3, n=2, chunk_size=1)
    raw["anchor"]["friction"] = {"distribution": "choice", "values": [0.7]}
    ds = run_ensemble(raw, threads=2)
    single = rs.simulate(rs.table2_case(3))
    assert single.status_name == "stopped"
    np.testing.assert_array_equal(ds.stopping_time.values, [single.stopping_time] * 2)
    assert float(ds.stopped_fraction) == 1.0 and float(ds.stopping_time_std) == 0.0
    tension = np.hypot(single.pin_force[..., 0], single.pin_force[..., 1])
    np.testing.assert_array_equal(ds.peak_chain_tension.values, [tension[:, 1].max()] * 2)
    assert abs(float(ds.stopping_time_mean) - 10.054) < 0.05 * 10.054  # Table 3, case 3


def test_sampled_anchor_mass_derives_the_anchor_length_of_table2_case4():
    """Anchor mass fixed at 50 t through a distribution, length not given: case 4 (2.5 m)."""
    raw = _scenario(1, t_max=1.5, n=2)
    del raw["anchor"]["length"]
    raw["anchor"]["mass"] = {"distribution": "choice", "values": [50000.0]}
    ds = run_ensemble(raw, threads=1)
    single = rs.simulate(rs.table2_case(4).replace(**{"numerics.t_max": 1.5}))
    tension = np.hypot(single.pin_force[..., 0], single.pin_force[..., 1])
    np.testing.assert_array_equal(ds.input_anchor_length.values, [2.5, 2.5])
    np.testing.assert_array_equal(ds.peak_ship_tension.values, [tension[:, -1].max()] * 2)
    np.testing.assert_array_equal(ds.energy_closure.values, [single.energy_closure()] * 2)


def test_stopping_time_falls_with_the_sampled_friction():
    """Seed 004 §4.3.1 / Table 3 cases 1-3: 20.010, 13.228, 10.054 s for friction 0.3, 0.5, 0.7."""
    raw = _scenario(1, n=4, chunk_size=2)
    raw["anchor"]["friction"] = _uniform(0.3, 0.7)
    ds = run_ensemble(raw, threads=2)
    assert list(ds.case_status.values) == [kmb.STOPPED] * 4
    order = np.argsort(ds.input_anchor_friction.values)
    times = ds.stopping_time.values[order]
    assert np.all(np.diff(times) < 0), (ds.input_anchor_friction.values[order], times)
    assert np.all((times > 0.95 * 10.054) & (times < 1.05 * 20.010)), times
    t = ds.stopping_time.values
    assert float(ds.stopping_time_mean) == pytest.approx(np.mean(t), rel=1e-14)
    assert float(ds.stopping_time_std) == pytest.approx(np.std(t, ddof=1), rel=1e-12)
    np.testing.assert_allclose(ds.stopping_time_quantile.sel(quantile=0.5), np.median(t), rtol=1e-14)


# ---------------------------------------------------------------------------
# the example and the command line
# ---------------------------------------------------------------------------
def test_example_is_table2_case1_with_the_section_4_3_ranges(tmp_path, capsys):
    assert main(["example", "restraint_ensemble", "-o", str(tmp_path / "e.toml")]) == 0
    spec = engine.load_ensemble(tmp_path / "e.toml", systems=engine.SYSTEMS)
    assert {k: (d.low, d.high) for k, d in spec.random.items()} == {
        "anchor.friction": (0.3, 0.7),
        "anchor.mass": (40000.0, 60000.0),
        "ship.speed": (3.0, 5.0),
    }
    assert spec.anchor_length_follows_mass
    case1 = rs.table2_case(1)
    fixed = [p for p in case1.values if p not in spec.random and p != "anchor.length"]
    assert {p: spec.base[p] for p in fixed} == {p: case1[p] for p in fixed}


def test_run_command_prints_the_stopping_time_statistics(tmp_path, capsys):
    text = ens.example_text().replace("t_max = 120.0", "t_max = 0.5")
    assert "t_max = 0.5" in text
    path = tmp_path / "e.toml"
    path.write_text(text)
    raw_before = copy.deepcopy(text)
    assert main(["run", str(path), "-n", "2", "--threads", "1", "--quiet", "-o", str(tmp_path / "o.nc")]) == 0
    out = capsys.readouterr().out
    assert "cases: 2 (time_limit 2)" in out and "stopped within the time limit: 0.000" in out
    with xr.open_dataset(tmp_path / "o.nc") as ds:
        assert ds.attrs["n_cases"] == 2 and ds.sizes["realization"] == 2
        assert list(ds.status_count.values) == [0, 2, 0, 0]
        assert registry_mismatches(ds, "restraint_ensemble") == []  # as declared, Conventions
        # the core's shared codes (kernels/status.py): 2 and 5+ are a system's own, unused here
        assert list(ds.status.values) == [0, 1, 3, 4]
        assert ds.status.attrs["flag_meanings"] == "stopped time_limit numerical_failure invalid_input"
    assert path.read_text() == raw_before


def test_sobol_cases_stratify_and_do_not_depend_on_the_chunking():
    """The first 4 points of a (scrambled) Sobol' net put one point in each quarter of every
    input's range (the (0, m, s)-net property, Dick & Pillichshammer 2010 Thm 4.10)."""
    raw = _scenario(t_max=0.05, n=4, sampling="sobol")
    raw["anchor"]["friction"] = _uniform(0.3, 0.7)
    raw["ship"]["speed"] = _uniform(3.0, 5.0)
    whole = run_ensemble(raw, threads=1, chunk_size=4)
    split = run_ensemble(raw, threads=2, chunk_size=1)
    for name, values in _per_case(whole).items():
        np.testing.assert_array_equal(split[name].values, values, err_msg=name)
    for name, (low, high) in {"input_anchor_friction": (0.3, 0.7), "input_ship_speed": (3.0, 5.0)}.items():
        quarter = np.floor((whole[name].values - low) / (high - low) * 4).astype(int)
        assert sorted(quarter) == [0, 1, 2, 3], (name, whole[name].values)
    assert whole.attrs["sampling_method"] == "sobol"


def test_a_sampled_anchor_that_floats_is_not_run_and_is_reported():
    """Anchor mass uniform on [10, 30] t at the fixed 2.0 m x 4.0 m x 2.1 m size: the cases
    lighter than the displaced water (1025 kg/m3 x 16.8 m3 = 17.22 t) get invalid_input."""
    raw = _scenario(t_max=0.05, n=6)
    raw["anchor"]["mass"] = _uniform(10000.0, 30000.0)
    ds = run_ensemble(raw, threads=1)
    floats = ds.input_anchor_mass.values <= 1025.0 * 2.0 * 4.0 * 2.1
    assert 0 < floats.sum() < 6, ds.input_anchor_mass.values
    np.testing.assert_array_equal(ds.case_status.values == kmb.INVALID_INPUT, floats)
    assert np.all(np.isnan(ds.end_time.values[floats])) and np.all(ds.end_time.values[~floats] == 0.05)
    assert ds.status_count.sel(status=kmb.INVALID_INPUT) == floats.sum()
    assert ds.attrs["invalid_inputs"].startswith(f"anchor.mass: {floats.sum()} case")
    assert float(ds.stopped_fraction) == 0.0  # of the cases run (all hit the 0.05 s limit)


def test_ctrl_c_stops_a_restraint_chunk_between_cases_not_after_the_whole_chunk(monkeypatch, sigint_handled):
    """Regression (issue 21 item 10): restraint ensembles ran their cases on a thread pool of
    their own that finished the whole chunk before a Ctrl-C was seen. They now take cases in
    blocks like the mines' drops: after the signal no new block starts."""
    import signal
    import threading
    import time

    from mineburial.ensembles.interrupt import Interrupted

    spec = engine.load_ensemble(_scenario(n=40), systems=engine.SYSTEMS)
    started = []

    def run_case(case):  # a stand-in case of 0.1 s: the run driver is under test, not the physics
        started.append(case)
        if len(started) == 3:
            signal.pthread_kill(threading.main_thread().ident, signal.SIGINT)
        time.sleep(0.1)
        return 0, np.zeros(len(ens.OUTPUTS))

    monkeypatch.setattr(ens, "run_case", run_case)
    with pytest.raises(Interrupted):
        ens.compute_chunk(spec, 0, 40, threads=2)
    assert len(started) < 10  # of 40: the blocks in flight when the signal came, no more
    assert signal.getsignal(signal.SIGINT) is signal.default_int_handler


def test_case_rules_over_sampled_rows_match_each_case_built_alone():
    """The restraint's relations are schema rules (rs.RULES): evaluated at once over sampled
    rows they refuse exactly the rows a case built alone refuses, and the ship-sinks rule at the
    closed-form mass rho L B depth (the cuboid's full displacement)."""
    base = rs.table2_case(1)
    rng = np.random.default_rng(3)
    n = 40
    full = base["water.density"] * base["ship.length"] * base["ship.beam"] * base["ship.depth"]
    columns = {
        "ship.mass": rng.uniform(0.5 * full, 1.5 * full, n),
        "ship.joint_dz": rng.uniform(0.0, 8.0, n),  # the keel reaches the seabed near 6 m
        "cable.vertical": rng.uniform(3.0, 12.0, n),  # no catenary below cable.length - horizontal
    }
    values = {**base.values, **columns}
    allowed = np.ones(n, dtype=bool)
    for rule in rs.RULES:
        allowed &= np.broadcast_to(rule.holds(values), (n,))
    alone = np.ones(n, dtype=bool)
    for j in range(n):
        try:
            base.replace(**{k: float(c[j]) for k, c in columns.items()})
        except ScenarioError:
            alone[j] = False
    assert 5 < allowed.sum() < n - 5
    np.testing.assert_array_equal(allowed, alone)
    sinks = next(r for r in rs.RULES if r.paths[0] == "ship.mass")
    np.testing.assert_array_equal(sinks.holds(values), columns["ship.mass"] < full)
