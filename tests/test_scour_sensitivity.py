"""``mineburial sensitivity`` of the burial after the scour stage at one lead time (issue 20).

Independent references: closed forms of the Sobol' indices (an output of one sampled input
has S_1 = S_T1 = 1; an input the output does not depend on has S_i = S_Ti = 0 exactly, since
its AB_i points give f(A) bit for bit), the burial law (a scour input cannot change the burial
at lead time 0, docs/scour.md), and the same analysis on 1 and 2 threads and resumed after an
interrupt (bit for bit).
"""

import numpy as np
import pytest
import xarray as xr
from conftest import scenario_dict
from test_compare_driver import _count_chunks
from test_scour_run import LEADS, scour_section
from test_sensitivity_driver import assert_same_indices

from mineburial.analyses.sensitivity import CLASS_OUTPUTS, run_sensitivity
from mineburial.cli import main
from mineburial.ensembles import engine
from mineburial.systems.mine.config import dumps_toml

N = 8
BEQ_A = {"distribution": "uniform", "low": 1.1, "high": 1.5}
PITCH = {"distribution": "uniform", "low": 0.0, "high": 60.0}


def scenario(tmp_path, pitch=30.0, beq_a=BEQ_A, with_scour=True, **scour):
    """A short drop of the test cylinder onto soft clay in 3 m of water, then the constant
    0.7 m/s current of tests/test_scour_run.py over fine sand (the burial grows towards
    B_eq = a theta^b D within the last lead time, 0.5 d); only ``beq_a`` (and ``pitch``
    when given a distribution) sampled."""
    d = scenario_dict(
        environment={"water_depth": 3.0},
        release={"position": [0.0, 0.0, 1.0], "pitch_deg": pitch},
        sediment={"class": "soft_clay"},
        numerics={"t_max": 3.0, "sediment_quadrature": "fast"},
    )
    d["mine"]["mass"] = 80.0
    d["ensemble"] = {"n": N, "chunk_size": 8, "seed": 3}
    if with_scour:
        d["scour"] = scour_section(tmp_path, beq_a=beq_a, **scour)
    path = tmp_path / "scenario.toml"
    path.write_text(dumps_toml(d))
    return path


def test_one_sampled_input_has_first_and_total_index_one(tmp_path):
    """Closed form: with beq_a the only random input, all of the burial's variance is its own."""
    ds = run_sensitivity(scenario(tmp_path), n=32, seed=1)
    assert ds.attrs["lead_time_days"] == LEADS[-1]  # the default: the section's last lead time
    assert ds.attrs["scour_status_counts"] == f"ok {32 * 3}"
    for out in ("penetration_depth", "burial_volume"):
        r = ds.sel(output=out, input="scour.beq_a")
        assert float(ds.output_variance.sel(output=out)) > 0.0
        assert abs(float(r.first_order) - 1.0) < 0.15, out
        assert abs(float(r.total_order) - 1.0) < 0.15, out
        assert float(r.total_order_lower) <= 1.0 <= float(r.total_order_upper), out


@pytest.fixture(scope="module")
def two_inputs(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("scour_sobol")
    path = scenario(tmp, pitch=PITCH)
    return tmp, path, run_sensitivity(path, n=N, seed=1, lead_time=0.0)


def test_a_scour_input_has_no_share_of_the_burial_at_lead_time_zero(two_inputs):
    """At lead time 0 the stage has not run on the forcing: the burial is the impact's, so
    beq_a's AB points give f(A) exactly and both its indices are 0; the impact input (pitch)
    takes all of the variance."""
    _, _, ds = two_inputs
    assert ds.attrs["lead_time_days"] == 0.0
    for out in ("penetration_depth", "burial_volume"):
        scour_input = ds.sel(output=out, input="scour.beq_a")
        assert float(scour_input.first_order) == 0.0 and float(scour_input.total_order) == 0.0, out
        assert float(ds.total_order.sel(output=out, input="release.pitch_deg")) > 0.5, out


def test_at_lead_time_zero_the_burial_indices_are_the_impacts(tmp_path):
    """Invariance (docs/scour.md: at lead time 0 the burial by volume is the impact's): with no
    scour input sampled the design is the impact-only one, and the indices of the burial by
    volume and of its classes are those of the same analysis without [scour]."""
    with_stage = run_sensitivity(scenario(tmp_path, pitch=PITCH, beq_a=1.3), n=N, seed=1, lead_time=0.0)
    impact = run_sensitivity(scenario(tmp_path, pitch=PITCH, with_scour=False), n=N, seed=1)
    outputs = ["burial_volume", *CLASS_OUTPUTS]
    for key in ("first_order", "total_order", "output_variance"):
        a, b = with_stage[key].sel(output=outputs).values, impact[key].sel(output=outputs).values
        np.testing.assert_allclose(a, b, rtol=1e-6, atol=1e-9, err_msg=key)
    assert float(impact.output_variance.sel(output="burial_volume")) > 0.0


def test_two_threads_and_an_interrupted_run_give_the_same_bits(two_inputs, monkeypatch, capsys):
    tmp, path, reference = two_inputs
    assert_same_indices(run_sensitivity(path, n=N, seed=1, lead_time=0.0, threads=2), reference)
    assert_same_indices(run_sensitivity(path, n=N, seed=1, lead_time=0.0, threads=1), reference)
    out = tmp / "s.nc"
    argv = ["sensitivity", str(path), "-n", str(N), "--seed", "1", "--lead-time", "0", "--quiet"]
    argv += ["-o", str(out), "--threads", "1"]
    drops = N * (2 + 2)
    _count_chunks(monkeypatch, interrupt_at=3)
    assert main(argv) == 130
    assert len(list((tmp / "s.nc.parts").glob("chunk-*.npz"))) == 2
    monkeypatch.undo()
    calls = _count_chunks(monkeypatch)
    assert main(argv) == 0
    assert len(calls) == len(engine.chunk_bounds(drops, 8)) - 2
    capsys.readouterr()
    with xr.open_dataset(out) as written:
        ds = written.load()
    for name in reference.data_vars:
        np.testing.assert_array_equal(ds[name].values, reference[name].values, err_msg=name)


def test_the_stage_changes_the_indices_at_a_later_lead_time(two_inputs):
    """At the last lead time (0.5 d, many time scales) the burial has relaxed towards
    B_eq = a theta^b D, which beq_a scales: it takes a share of the variance it could not
    have at lead time 0."""
    _, path, _ = two_inputs
    ds = run_sensitivity(path, n=N, seed=1)
    assert ds.attrs["lead_time_days"] == LEADS[-1]
    assert float(ds.total_order.sel(output="burial_volume", input="scour.beq_a")) > 0.5


@pytest.mark.parametrize(
    ("lead", "message"),
    [
        ("2", "--lead-time 2 is outside the allowed range [0, 1] days (the forcing's span)"),
        ("-0.5", "--lead-time -0.5 is outside the allowed range [0, 1] days (the forcing's span)"),
        ("nan", "--lead-time nan is outside the allowed range [0, 1] days (the forcing's span)"),
    ],
)
def test_a_lead_time_outside_the_forcing_is_one_line(tmp_path, capsys, lead, message):
    out = tmp_path / "s.nc"
    argv = ["sensitivity", str(scenario(tmp_path)), "-n", "4", "--lead-time", lead, "-o", str(out)]
    assert main(argv) == 2
    assert capsys.readouterr().err.splitlines() == [f"mineburial: error: {message}"]
    assert not out.exists() and not (tmp_path / "s.nc.parts").exists()


def test_a_lead_time_beyond_the_window_is_one_line(tmp_path, capsys):
    path = scenario(tmp_path, lead_times_days=[0.0, 0.25], window_days=0.5)
    assert main(["sensitivity", str(path), "-n", "4", "--lead-time", "0.75"]) == 2
    assert capsys.readouterr().err.splitlines() == [
        "mineburial: error: --lead-time 0.75 is outside the allowed range [0, 0.5] days (scour.window_days)"
    ]


def test_a_lead_time_without_a_scour_section_is_one_line(tmp_path, capsys):
    d = scenario_dict(release={"pitch_deg": PITCH})
    d["ensemble"] = {"n": N}
    path = tmp_path / "plain.toml"
    path.write_text(dumps_toml(d))
    assert main(["sensitivity", str(path), "-n", "4", "--lead-time", "1"]) == 2
    (line,) = capsys.readouterr().err.splitlines()
    assert line.startswith("mineburial: error: --lead-time 1: the scenario has no [scour] section")
