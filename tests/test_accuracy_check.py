"""The numerical self-check of every ``mineburial run`` (issue 19 item 6).

Independent reference: the same drops run by the test as a second ensemble whose scenario
asks for the reference numerics in its own ``[numerics]`` table (rtol 3e-5, atol 3e-6, the
reference sediment and overburden quadratures: the same sampled inputs, since a fixed field
changes no draw), the differences recomputed here with numpy from the two runs' per-drop
outputs; and the main results compared bit for bit with a run without the check.
"""

import threading
import time
import types

import numba
import numpy as np
import pytest
import xarray as xr
from conftest import scenario_dict

from mineburial.cli import main
from mineburial.ensembles import engine
from mineburial.ensembles.runner import run_ensemble
from mineburial.errors import ScenarioError
from mineburial.kernels.mine import layout
from mineburial.systems.mine import accuracy, batch
from mineburial.systems.mine import ensemble as mine
from mineburial.systems.mine.config import dumps_toml
from mineburial.systems.mine.ensemble import summarize

N, SEED, SIZE = 6, 3, 3  # 9 reference drops in all (~3 s each): the suite's budget
REFERENCE = {
    "rtol": 3e-5,
    "atol": 3e-6,
    "sediment_quadrature": "reference",
    "overburden_quadrature": "reference",
}


def steep(numerics=None, **ensemble):
    """A 120 kg cylinder thrown nose-down at 6 m/s through 3 m of water into soft clay
    (penetrations of decimetres: a loose tolerance moves them by more than the 5 mm floor)."""
    d = scenario_dict(
        environment={"water_depth": 3.0},
        release={
            "position": [0.0, 0.0, 1.0],
            "velocity": [0.0, 0.0, -6.0],
            "pitch_deg": {"distribution": "uniform", "low": 60.0, "high": 90.0},
        },
        sediment={"class": "soft_clay"},
        numerics={"t_max": 3.0, "sediment_quadrature": "fast", **(numerics or {})},
    )
    d["mine"]["mass"] = {"distribution": "normal", "mean": 120.0, "std": 10.0}
    d["ensemble"] = {"accuracy_check": SIZE, **ensemble}
    return d


def relative_changes(pen, pen_ref):
    d = np.abs(pen - pen_ref)
    return np.where(d <= 0.005, 0.0, d / np.maximum(np.abs(pen_ref), 0.5))


@pytest.fixture(scope="module")
def runs():
    checked = run_ensemble(steep(), n=N, seed=SEED, per_drop=True, self_check=True)
    plain = run_ensemble(steep(), n=N, seed=SEED, per_drop=True)
    reference = run_ensemble(steep(REFERENCE), n=N, seed=SEED, per_drop=True)
    return checked, plain, reference


def test_the_self_check_leaves_every_result_bit_identical(runs):
    checked, plain, _ = runs
    assert set(checked.variables) == set(plain.variables)
    for name, var in plain.variables.items():
        assert np.array_equal(var.values, checked[name].values, equal_nan=var.dtype.kind == "f"), name
    assert not [k for k in plain.attrs if k.startswith("numerical_check")]


def test_the_self_check_attributes_equal_the_subsample_recomputed_on_the_reference_numerics(runs):
    checked, _, reference = runs
    a = checked.attrs
    idx = np.asarray(a["numerical_check_drop_indices"])
    assert a["numerical_check"] == "done" and int(a["numerical_check_drops"]) == SIZE == idx.size
    assert np.all(np.diff(idx) > 0) and 0 <= idx[0] and idx[-1] < N
    for name in ("random_seed",):
        assert checked.attrs[name] == reference.attrs[name]
    for var in [v for v in checked.data_vars if str(v).startswith("input_")]:  # the same drops
        assert np.array_equal(checked[var].values, reference[var].values), var
    pen, pen_ref = checked.penetration_depth.values[idx], reference.penetration_depth.values[idx]
    rel = 100.0 * relative_changes(pen, pen_ref)
    assert float(a["numerical_check_penetration_p95_percent"]) == pytest.approx(
        np.percentile(rel, 95), abs=1e-12
    )
    assert float(a["numerical_check_penetration_max_percent"]) == pytest.approx(rel.max(), abs=1e-12)
    cls = checked.burial_class.values[idx] != reference.burial_class.values[idx]
    assert int(a["numerical_check_class_changes"]) == int(cls.sum())
    status = checked.status.values[idx] != reference.status.values[idx]
    assert int(a["numerical_check_status_changes"]) == int(status.sum())
    assert float(a["numerical_check_wall_time_s"]) > 0.0


def test_a_resumed_run_checks_the_same_drops_with_the_same_differences(runs, tmp_path, monkeypatch):
    checked, _, _ = runs
    out, real, calls = tmp_path / "resumed.nc", engine.compute_chunk, []

    def dying(spec, start, stop):  # Ctrl-C after two chunks of 2 drops
        if len(calls) == 2:
            raise KeyboardInterrupt
        calls.append(start)
        return real(spec, start, stop)

    monkeypatch.setattr(engine, "compute_chunk", dying)
    with pytest.raises(KeyboardInterrupt):
        run_ensemble(steep(), n=N, seed=SEED, chunk_size=2, output=out, self_check=True)
    monkeypatch.undo()
    resumed = run_ensemble(steep(), n=N, seed=SEED, chunk_size=2, output=out, self_check=True)
    for ds in (resumed, xr.load_dataset(out)):
        for key, value in checked.attrs.items():
            if key.startswith("numerical_check") and key != "numerical_check_wall_time_s":
                assert np.array_equal(np.asarray(ds.attrs[key]), np.asarray(value)), key


def test_a_loose_tolerance_warns_and_the_defaults_do_not(runs, tmp_path, capsys):
    checked, _, _ = runs
    assert int(checked.attrs["numerical_check_exceeds_targets"]) == 0
    assert "WARNING" not in summarize(checked) and f"numerical self-check ({SIZE} drops" in summarize(checked)
    scen = tmp_path / "loose.toml"
    scen.write_text(dumps_toml(steep({"rtol": 5e-2, "atol": 5e-3}, n=N, seed=SEED)))
    out = tmp_path / "loose.nc"
    assert main(["run", str(scen), "-o", str(out), "--quiet"]) == 0
    printed = capsys.readouterr().out
    assert "WARNING: the numerical error exceeds its targets" in printed, printed
    with xr.open_dataset(out) as ds:  # written into the output file
        assert int(ds.attrs["numerical_check_exceeds_targets"]) == 1
        p95, mx = (
            ds.attrs["numerical_check_penetration_p95_percent"],
            ds.attrs["numerical_check_penetration_max_percent"],
        )
        assert p95 > 1.0 or mx > 5.0


def test_the_check_is_skipped_and_says_so_when_switched_off_or_when_no_drop_ran():
    off = run_ensemble(steep(accuracy_check=0), n=2, seed=SEED, self_check=True)
    assert off.attrs["numerical_check"] == "skipped (ensemble.accuracy_check = 0)"
    assert "numerical self-check: skipped (ensemble.accuracy_check = 0)" in summarize(off)
    # every drop starts below the seabed (released 5 m down in 2 m of water; the choice's
    # first value, 30 m, weight 0, only validates the scenario): none is run
    none_run = steep()
    none_run["release"]["position"] = [0.0, 0.0, -5.0]
    none_run["environment"]["water_depth"] = {
        "distribution": "choice",
        "values": [30.0, 2.0],
        "weights": [0, 1],
    }
    ds = run_ensemble(none_run, n=2, seed=SEED, self_check=True)
    assert int(ds.status_count.sum()) == 2 and "numerical_check_drops" not in ds.attrs
    assert ds.attrs["numerical_check"].startswith("skipped (no drop was run")


@pytest.mark.parametrize("value", [-1, 1.5, True, "32"])
def test_a_bad_accuracy_check_is_one_line(value):
    with pytest.raises(
        ScenarioError, match=r"ensemble.accuracy_check = .* outside the allowed range \[0, inf\)"
    ):
        engine.load_ensemble(steep(accuracy_check=value))


def test_max_drop_named_the_first_drop_when_no_penetration_changed():
    """Regression: with every difference 0 (or within the 5 mm floor) ``argmax`` of the
    zeros named drop 0 as the worst; now -1 (no drop) and the summary line says so."""
    summary = np.zeros((4, layout.N_SUMMARY))
    summary[:, layout.S_PENETRATION] = [0.3, 1.2, 0.8, 2.0]
    status = np.zeros(4, np.int8)
    near = summary.copy()
    near[2, layout.S_PENETRATION] += 0.004  # within the floor: counts as 0
    assert accuracy.differences(summary, status, near, status)["argmax"] == -1
    moved = summary.copy()
    moved[1, layout.S_PENETRATION] += 0.1  # 0.1 / 1.2 relative: the largest change, drop 1
    assert accuracy.differences(summary, status, moved, status)["argmax"] == 1
    attrs = {
        "numerical_check": "done",
        "numerical_check_drops": 4,
        "numerical_check_penetration_p95_percent": 0.0,
        "numerical_check_penetration_max_percent": 0.0,
        "numerical_check_penetration_max_drop": -1,
        "numerical_check_class_changes": 0,
        "numerical_check_status_changes": 0,
        "numerical_check_wall_time_s": 1.0,
        "numerical_check_exceeds_targets": 0,
    }
    line = accuracy.summary_lines(xr.Dataset(attrs=attrs))[0]
    assert "(no drop changed)" in line and "drop -1" not in line


def test_the_check_is_inconclusive_not_a_pass_when_every_drop_timed_out():
    """Was: "done", p95 and max NaN and no warning (read as a pass) when none of the drops
    re-run ended: here every drop is still falling at numerics.t_max_fall = 0.05 s."""
    ds = run_ensemble(steep({"t_max": 0.01, "t_max_fall": 0.05}), n=3, seed=SEED, self_check=True)
    assert int(ds.status_count.sum()) == int(ds.status_count[1]) == 3  # status 1: time_limit
    state = ds.attrs["numerical_check"]
    assert state.startswith("INCONCLUSIVE: none of the 3 drops re-run ended") and "time_limit" in state
    assert "numerical_check_exceeds_targets" not in ds.attrs
    assert "numerical_check_penetration_p95_percent" not in ds.attrs
    assert f"numerical self-check: {state}" in summarize(ds)


def test_the_sizing_rule_is_the_binomial_chance_of_seeing_one_failing_drop():
    # 1 - (1 - q)^n >= 0.9: at q = 1 % the least n is 230 (1 - 0.99^229 = 0.8999, 0.99^230 = 0.0991)
    assert accuracy.drops_needed(0.01) == 230
    assert 1.0 - 0.99**229 < 0.9 <= 1.0 - 0.99**230
    for n in (1, 3, 8, 230, 1000):
        q = accuracy.detectable_rate(n)
        assert 1.0 - (1.0 - q) ** n == pytest.approx(0.9, rel=1e-12)  # the chance, recomputed
        assert accuracy.drops_needed(q * (1.0 + 1e-9)) <= n < accuracy.drops_needed(q * (1.0 - 1e-6)) + 1
    assert accuracy.detectable_rate(8) == pytest.approx(1.0 - 0.1**0.125)  # 25.0 %


def test_the_check_states_its_detectable_failure_rate_and_prints_progress(runs, capsys):
    checked, _, _ = runs
    rate = float(checked.attrs["numerical_check_detectable_failure_percent"])
    assert rate == pytest.approx(100.0 * (1.0 - 0.1 ** (1.0 / SIZE)), abs=1e-3)  # 3 drops: 53.6 %
    assert f"catch a defect of {rate:.3g} % of drops with 90% probability (230 drops for 1 %)" in summarize(
        checked
    )
    attrs = run_ensemble(steep(), n=N, seed=SEED, self_check=True, progress=True).attrs
    printed = capsys.readouterr().err
    assert f"self-check drops {SIZE}/{SIZE} (100.0 %)" in printed, printed
    for key, value in checked.attrs.items():  # the blocks of the progress lines change nothing
        if key.startswith("numerical_check") and key != "numerical_check_wall_time_s":
            assert np.array_equal(np.asarray(attrs[key]), np.asarray(value)), key


def test_the_reference_keeps_an_adaptive_integrator_and_replaces_a_fixed_step():
    names = layout.INTEGRATOR_NAMES
    P = np.zeros((len(names), layout.N_PARAMS))
    P[:, layout.P_INTEGRATOR] = np.arange(len(names))
    got = [names[int(i)] for i in accuracy.reference_params(P)[:, layout.P_INTEGRATOR]]
    fixed = {"rk4": "dopri5", "local_linear": "dopri5"}  # a tolerance does not tighten a fixed step
    assert got == [fixed.get(name, name) for name in names]


def test_the_check_reference_agrees_with_the_accurate_one_far_inside_the_floor():
    """The self-check's reference (rtol 3e-5) against the accurate one (rtol 1e-5, selectable by
    name) and a tighter solution of the same equations (rtol 3e-6, the reference quadratures): on
    these drops the two references' penetrations agree within 1 mm (the check counts changes
    within 5 mm as 0) and both lie within 1 mm of rtol 3e-6's."""
    spec = engine.load_ensemble(steep(), n=N, seed=SEED)
    P = np.concatenate([mine.chunk_inputs(spec, i, i + 1)[0] for i in (0, 1)])
    valid = np.ones(len(P), bool)
    run = lambda Q: batch.run_batch(Q, valid, spec.sediment_bank, spec.current_bank)  # noqa: E731
    check, accurate = accuracy.reference_params(P), accuracy.reference_params(P, "accurate")
    assert np.all(check[:, layout.P_RTOL] == 3e-5) and np.all(accurate[:, layout.P_RTOL] == 1e-5)
    tight = accurate.copy()
    tight[:, layout.P_RTOL], tight[:, layout.P_ATOL] = 3e-6, 3e-7
    (s_check, c_check), (s_acc, c_acc), (s_tight, _) = run(check), run(accurate), run(tight)
    assert np.all(c_check == c_acc)
    pen = [s[:, layout.S_PENETRATION] for s in (s_check, s_acc, s_tight)]
    assert np.all(np.isfinite(pen[2])) and np.all(pen[2] > 0.05)  # decimetres: a real test
    assert np.max(np.abs(pen[0] - pen[1])) < 1e-3
    assert np.max(np.abs(pen[0] - pen[2])) < 1e-3 and np.max(np.abs(pen[1] - pen[2])) < 1e-3
    with pytest.raises(ValueError, match="reference = 'loose': not one of 'check', 'accurate'"):
        accuracy.reference_params(P, "loose")


def test_the_check_runs_its_drops_one_a_block_on_every_thread(monkeypatch):
    """Regression: with progress lines the drops ran in batches of one drop a thread, each batch
    on one thread (the pool takes two drops a block), so the check ran serially. Here each drop
    sleeps 0.2 s (the GIL released, as the compiled drops do): on 2 threads two drops are in
    flight at once, with or without progress lines, one drop a block, each drop's row its own; with
    a cost per drop the costliest start first."""
    if numba.config.NUMBA_NUM_THREADS < 2:
        pytest.skip("needs 2 numba threads")
    lock, active, peak = threading.Lock(), [0], [0]

    def fake(params, valid, sb, cb, summary, codes, paths, start, stop):
        assert stop == start + 1  # one drop a block
        with lock:
            active[0] += 1
            peak[0] = max(peak[0], active[0])
        time.sleep(0.2)
        with lock:
            active[0] -= 1
        summary[start, :] = start
        codes[start] = 0

    def bar(total, unit):
        return types.SimpleNamespace(update=lambda done, final=False: None)

    monkeypatch.setattr(accuracy.batch, "_run_drops", fake)
    spec = types.SimpleNamespace(sediment_bank=np.zeros((1, 3, 2)), current_bank=np.zeros((1, 3, 2)))
    before = numba.get_num_threads()
    numba.set_num_threads(2)
    try:
        for progress in (None, bar):
            peak[0] = 0
            summary, codes = accuracy._rerun(np.zeros((4, layout.N_PARAMS)), spec, progress)
            assert peak[0] == 2  # serially: 1
            assert np.array_equal(summary[:, 0], np.arange(4.0)) and np.all(codes == 0)
        numba.set_num_threads(1)  # one thread: the order the drops start in
        started = []
        monkeypatch.setattr(accuracy.batch, "_run_drops", lambda *a: (started.append(a[-2]), fake(*a)))
        summary, _ = accuracy._rerun(
            np.zeros((4, layout.N_PARAMS)), spec, None, np.array([3.0, np.nan, 9.0, 5.0])
        )
        assert started == [2, 3, 0, 1]  # the costliest first, an unknown cost last
        assert np.array_equal(summary[:, 0], np.arange(4.0))  # each drop in its own row
    finally:
        numba.set_num_threads(before)


def test_a_drop_on_a_long_table_gets_dopri5_in_the_reference():
    """A table of more than 16 depths below the seabed (the reference quadrature samples its rows
    beyond, sediment/reference.py REFERENCE_LEVELS) takes dopri5 in the reference; a 17-point
    table (16 depths below the seabed), a linear profile and the run without a bank keep the
    drop's own adaptive integrator."""
    names = layout.INTEGRATOR_NAMES
    bank = np.full((3, 3, 40), np.nan)
    bank[0, :, :17] = np.linspace(0.0, 6.0, 17)  # the surface and 16 depths below it
    bank[1, :, :18] = np.linspace(0.0, 6.0, 18)  # 17 depths below the surface
    bank[2, :, :2] = [[0.0, 1.0]] * 3
    P = np.zeros((4, layout.N_PARAMS))
    P[:, layout.P_INTEGRATOR] = names.index("dopri5_ros34pw2")
    P[:, layout.P_SED_PROFILE] = [0, 1, 2, -1]
    got = [names[int(i)] for i in accuracy.reference_params(P, sediment_bank=bank)[:, layout.P_INTEGRATOR]]
    assert got == ["dopri5_ros34pw2", "dopri5", "dopri5_ros34pw2", "dopri5_ros34pw2"]
    assert np.all(accuracy.reference_params(P)[:, layout.P_INTEGRATOR] == names.index("dopri5_ros34pw2"))
