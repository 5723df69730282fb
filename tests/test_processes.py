"""The post-impact process seam (issue 33 item 1, mineburial/ensembles/processes.py): a second
process registered from a test module alone — no edit of the mine's ensemble, the runner or the
store — runs in ``run``: its section is parsed, its chunk values are stored and reduced, its
variables and summary lines reach the output, its memory enters the estimate and its identity
the run's. Adding it leaves every impact output bit for bit as it was (invariance), and its
per-drop value is the closed form it states (twice the drop's own penetration depth)."""

import dataclasses

import numpy as np
import pytest
import xarray as xr
from conftest import scenario_dict

from mineburial.config import ScenarioError, dumps_toml
from mineburial.ensembles import engine, mine, processes, runner, scour
from mineburial.ensembles.store import run_identity
from mineburial.kernels.mine import layout

N = 6


@dataclasses.dataclass(frozen=True)
class ToySpec:
    factor: float


class ToyProcess:
    """A toy process: each drop's ``toy_scaled`` = ``factor`` x its penetration depth at impact."""

    section = "toy"

    def load(self, section, *, base_dir, base, template, random):
        factor = section.get("factor", 2.0)
        if not isinstance(factor, (int, float)) or factor <= 0:
            raise ScenarioError(f"toy.factor = {factor!r} must be a positive number")
        return ToySpec(float(factor))

    def identity(self, spec):
        return repr(spec.factor).encode()

    def resolved(self, spec):
        return {"factor": spec.factor}

    def input_files(self, spec):
        return ()

    def run_chunk(self, spec, P, summary, status, inputs):
        return {"toy:scaled": spec.factor * summary[:, layout.S_PENETRATION]}

    def bytes_per_drop(self, spec):
        return 8

    def statistics(self, spec, chunks, class_basis):
        values = np.concatenate([r["toy:scaled"] for r in chunks]) if chunks else np.empty(0)
        return xr.Dataset({"toy_scaled_max": np.nanmax(values) if values.size else np.nan})

    def dataset(self, spec, chunks, ds, *, per_drop, class_basis):
        out = ds.merge(self.statistics(spec, chunks, class_basis))
        if per_drop:
            out["toy_scaled"] = ("realization", np.concatenate([r["toy:scaled"] for r in chunks]))
        out.attrs = dict(ds.attrs)
        return out

    def summary_lines(self, ds):
        return (
            [f"toy: largest scaled depth {float(ds['toy_scaled_max']):.3g} m"]
            if "toy_scaled_max" in ds
            else []
        )

    def lead_times(self, spec):
        return ()

    def map_attributes(self, spec):
        return "", {}


@pytest.fixture
def toy():
    process = processes.register(ToyProcess())
    yield process
    processes.unregister("toy")


def scenario(tmp_path, **sections):
    d = scenario_dict(
        release={
            "position": [0.0, 0.0, 1.0],
            "pitch_deg": {"distribution": "uniform", "low": 0.0, "high": 60.0},
        },
        sediment={"class": "soft_clay"},
        numerics={"t_max": 3.0, "sediment_quadrature": "fast"},
    )
    d["ensemble"] = {"n": N, "chunk_size": 4, "per_drop": True, "seed": 3}
    d.update(sections)
    path = tmp_path / f"scenario{len(sections)}.toml"
    path.write_text(dumps_toml(d))
    return path


def test_a_process_registered_by_its_own_module_runs_in_run(tmp_path, toy):
    plain = runner.run_ensemble(scenario(tmp_path))
    ran = runner.run_ensemble(scenario(tmp_path, toy={"factor": 3.0}), output=tmp_path / "toy.nc")
    depth = plain["penetration_depth"].values
    assert np.isfinite(depth).any()
    # the impact outputs are those of the run without the process, bit for bit
    for name in plain.data_vars:
        np.testing.assert_array_equal(ran[name].values, plain[name].values, err_msg=name)
    # the process's per-drop value is its closed form of the drop's own impact result
    np.testing.assert_array_equal(ran["toy_scaled"].values, 3.0 * depth)
    assert float(ran["toy_scaled_max"]) == np.nanmax(3.0 * depth)
    assert '"toy": {"factor": 3.0}' in ran.attrs["scenario"]
    with xr.open_dataset(tmp_path / "toy.nc") as back:
        np.testing.assert_array_equal(back["toy_scaled"].values, 3.0 * depth)
    assert "toy: largest scaled depth" in mine.summarize(ran)


def test_a_process_enters_the_memory_estimate_and_the_identity(tmp_path, toy):
    without = engine.load_ensemble(scenario(tmp_path))
    spec = engine.load_ensemble(scenario(tmp_path, toy={"factor": 3.0}))
    assert mine.bytes_a_drop(spec) == mine.bytes_a_drop(without) + 8
    other = engine.load_ensemble(scenario(tmp_path, toy={"factor": 4.0}))
    assert len({run_identity(without), run_identity(spec), run_identity(other)}) == 3
    assert spec.process("toy") == ToySpec(3.0) and without.process("toy") is None
    with pytest.raises(ScenarioError, match="toy.factor"):
        engine.load_ensemble(scenario(tmp_path, toy={"factor": -1.0}))


def test_registering_a_process_leaves_the_identity_of_a_run_without_its_section(tmp_path):
    path = scenario(tmp_path)
    before = run_identity(engine.load_ensemble(path))
    processes.register(ToyProcess())
    try:
        assert run_identity(engine.load_ensemble(path)) == before
    finally:
        processes.unregister("toy")


def test_scour_is_the_first_registered_process_and_the_registry_checks_the_protocol():
    assert list(processes.PROCESSES) == ["scour"] and processes.PROCESSES["scour"] is scour.PROCESS
    assert isinstance(scour.PROCESS, processes.Process)
    assert processes.owns_input("scour.d50") and not processes.owns_input("mine.mass")
    with pytest.raises(TypeError, match="Process protocol"):
        processes.register(object())

    class Other(ToyProcess):
        section = "scour"

    with pytest.raises(ValueError, match=r"\[scour\] is already registered"):
        processes.register(Other())


class ToyBurial(ToyProcess):
    """A toy process that would change the burial too (the BurialProcess methods)."""

    def at_lead_time(self, spec, lead_time):
        return spec

    def burial_after(self, spec, summary, chunks, *, missing="nan"):
        return summary

    def lacks_value(self, spec, chunks):
        return np.zeros(0, bool)

    def status_text(self, chunks):
        return ""


def test_a_lead_time_needs_the_one_process_that_changes_the_burial(tmp_path, toy):
    plain = engine.load_ensemble(scenario(tmp_path, toy={"factor": 3.0}))
    assert isinstance(scour.PROCESS, processes.BurialProcess) and not isinstance(toy, processes.BurialProcess)
    assert processes.burial_process(plain) is None and processes.at_lead_time(plain, None) is plain
    assert plain.lead_time_sections() == ()  # no lead-time figure of the toy process
    with pytest.raises(ScenarioError, match=r"--lead-time 1: the scenario has no \[scour\] section"):
        processes.at_lead_time(plain, 1.0)
    processes.unregister("toy")
    processes.register(ToyBurial())
    two = dataclasses.replace(plain, processes=(("scour", None), ("toy", None)))
    with pytest.raises(
        ScenarioError, match=r"\[scour\], \[toy\]: at most one process that changes the burial"
    ):
        processes.burial_process(two)
