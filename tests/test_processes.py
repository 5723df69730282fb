"""The post-impact process seam (issue 33 item 1, mineburial/systems/mine/processes/registry.py): a second
process registered from a test module alone — no edit of the mine's ensemble, the runner, the
store, the variable catalogue, maps or figures — runs in ``run`` and ``map``: its section is
parsed, its chunk values are stored and reduced, the output variables it declares itself are
written with their declared CF attributes (and the map holds its statistic per cell), its
summary lines reach the output, its memory enters the estimate and its identity the run's, and
it draws a panel of the lead-time figure. Adding it leaves every impact output bit for bit as it
was (invariance), and its per-drop value is the closed form it states (a factor times the drop's
own penetration depth), per map cell that of the cell's own run."""

import dataclasses
import subprocess

import numpy as np
import pytest
import tomllib
import xarray as xr
from conftest import scenario_dict

from mineburial.ensembles import engine, runner
from mineburial.ensembles.store import run_identity
from mineburial.errors import ScenarioError
from mineburial.io import variables as V
from mineburial.io.dataset import registry_mismatches
from mineburial.kernels.mine import layout
from mineburial.systems.mine import ensemble as mine
from mineburial.systems.mine import figures
from mineburial.systems.mine.config import dumps_toml
from mineburial.systems.mine.processes import registry as processes
from mineburial.systems.mine.processes import scour

N = 6

#: the toy's own output variables (ProcessVariables: a per-drop value and its largest)
TOY_VARIABLES = V.ProcessVariables(
    variables=(
        V.Variable(
            "toy_scaled",
            ("realization",),
            "float64",
            "m",
            "scaled penetration depth",
            "The factor toy.factor times the drop's penetration depth at impact.",
        ),
        V.Variable(
            "toy_scaled_max",
            (),
            "float64",
            "m",
            "largest scaled penetration depth",
            "Largest toy_scaled over the drops (NaN without one).",
            group="statistics",
        ),
    ),
    map_note=" Per cell, over the drops of the cell's ensemble.",
)
#: the title of the toy's panel of the lead-time figure
TOY_PANEL = "toy: largest scaled depth"


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

    def variables(self):
        return TOY_VARIABLES

    def statistics(self, spec, chunks, class_basis):
        values = np.concatenate([r["toy:scaled"] for r in chunks]) if chunks else np.empty(0)
        largest = np.nanmax(values) if np.isfinite(values).any() else np.nan
        return xr.Dataset({"toy_scaled_max": V.variable("toy_scaled_max").data_array(largest)})

    def dataset(self, spec, chunks, ds, *, per_drop, class_basis):
        out = ds.merge(self.statistics(spec, chunks, class_basis))
        if per_drop:
            values = np.concatenate([r["toy:scaled"] for r in chunks])
            out["toy_scaled"] = V.variable("toy_scaled").data_array(values)
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

    def cell_inputs(self, section, *, base_dir, cells):
        return None

    def figure_panels(self, ds):
        def draw(ax, lead):
            ax.plot(lead, np.full(len(lead), float(ds["toy_scaled_max"])), label="toy")
            ax.set_title(TOY_PANEL)

        return [draw]


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
        # written with the attributes it declared itself (CF: long_name, units, comment), as every
        # variable of the catalogue is: nothing in the file the registry does not declare
        for var in TOY_VARIABLES.variables:
            for key, value in {"long_name": var.long_name, "units": "m", "comment": var.description}.items():
                assert back[var.name].attrs[key] == value, (var.name, key)
        assert back["toy_scaled"].attrs["coverage_content_type"] == "modelResult"
        assert registry_mismatches(back, "ensemble") == []
    assert "toy: largest scaled depth" in mine.summarize(ran)


def test_a_process_registers_its_own_variables_and_unregisters_them(toy):
    import cf_units  # UDUNITS-2 bindings, installed with compliance-checker

    assert V.variable("toy_scaled").units == "m" and "toy_scaled" in V.FAMILIES["ensemble"]
    assert V.PROCESS_VARIABLES["toy"].map_statistics() == ("toy_scaled_max",)  # not the per-drop one
    only_run = dataclasses.replace(V.PROCESS_VARIABLES["toy"], run_only=("toy_scaled_max",))
    assert only_run.map_statistics() == ()  # a statistic only a run's file holds
    cell = V.family("map")["toy_scaled_max"]
    assert cell.dims == ("y", "x") and cell.description.endswith(
        "Per cell, over the drops of the cell's ensemble."
    )
    assert not cf_units.Unit(cell.units).is_unknown()
    processes.register(toy)  # the same process again: nothing changes
    with pytest.raises(ValueError, match=r"\[toy\] are registered already"):
        V.register_process_variables("toy", dataclasses.replace(TOY_VARIABLES))
    with pytest.raises(ValueError, match="must begin with 'other_'"):
        V.register_process_variables("other", TOY_VARIABLES)
    processes.unregister("toy")
    assert "toy_scaled" not in V.VARIABLES and "toy_scaled_max" not in V.family("map")
    assert "lead_time" in V.VARIABLES  # scour's coordinates stay
    processes.register(toy)


def test_a_process_runs_in_a_map_with_its_statistic_per_cell(tmp_path, toy):
    from test_maps import GRID_NAMES, SEED, _scenario, cell_reference, expected_seed, uniform_environment

    from mineburial.cli import main

    env, scen, out = tmp_path / "env.nc", tmp_path / "toy.toml", tmp_path / "map.nc"
    uniform_environment().to_netcdf(env)  # 2 x 2 cells of stiff clay, cell (1, 0) land
    scen.write_text(dumps_toml(dict(_scenario(), toy={"factor": 2.5})))
    args = ["map", str(scen), "--environment", str(env), "-o", str(out), "-n", "3", "--seed", str(SEED)]
    assert main(args + ["--quiet"]) == 0
    with xr.open_dataset(out) as ds:
        ds = ds.load()
    # declared by the process itself, per cell (the file as read back: decoded fill values aside)
    assert [m for m in registry_mismatches(ds, "map", names=GRID_NAMES) if m.startswith("toy")] == []
    attrs = ds["toy_scaled_max"].attrs
    assert attrs["units"] == "m" and attrs["long_name"] == "largest scaled penetration depth"
    assert attrs["comment"] == TOY_VARIABLES.variables[1].description + TOY_VARIABLES.map_note
    got = ds["toy_scaled_max"].values
    assert np.isnan(got[1, 0])  # land
    current = {"kind": "power_law", "surface_velocity": [0.02, -0.01], "exponent": 0.2}
    ref = dict(cell_reference(3.0, {"class": "stiff_clay"}, current), toy={"factor": 2.5})
    for j, i in ((0, 0), (0, 1), (1, 1)):
        # the cell's own run, its scenario written out by hand (tests/test_maps.py)
        run = runner.run_ensemble(ref, n=3, seed=expected_seed(SEED, j * 2 + i), per_drop=True)
        depth = run["penetration_depth"].values
        assert np.isfinite(depth).any()
        assert got[j, i] == np.nanmax(2.5 * depth), (j, i)


def test_a_process_draws_its_panel_of_the_lead_time_figure(tmp_path, toy, monkeypatch):
    pytest.importorskip("matplotlib")
    from test_scour_run import scenario as scour_scenario
    from test_scour_run import scour_section

    path = scour_scenario(tmp_path, scour_section(tmp_path))
    d = tomllib.loads(path.read_text())
    d["toy"] = {"factor": 3.0}
    path.write_text(dumps_toml(d))
    ds = runner.run_ensemble(path)
    drawn = {}

    def keep(fig, where, **kw):
        drawn["titles"] = [ax.get_title() for ax in fig.axes]
        drawn["lines"] = {ax.get_title(): [line.get_ydata() for line in ax.get_lines()] for ax in fig.axes}

    monkeypatch.setattr(figures, "save_figure", keep)
    figures.plot_lead_time(ds, tmp_path / "lead.png", scenario="toy")
    assert TOY_PANEL in drawn["titles"]
    (line,) = drawn["lines"][TOY_PANEL]
    np.testing.assert_array_equal(line, float(ds["toy_scaled_max"]))
    # above the burial panels: scour's forcing (through the protocol too), then the toy's
    assert drawn["titles"][0].startswith("forcing") and drawn["titles"][1] == TOY_PANEL
    assert "burial classes, 95 % Wilson bands" in drawn["titles"]


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


def test_a_process_s_own_variables_pass_the_cf_compliance_checker(tmp_path, toy):
    from test_netcdf import _checker_executable, synthetic

    from mineburial.io.netcdf import write_netcdf
    from mineburial.systems.mine.dataset import build_dataset

    summary, status, _ = synthetic(12)
    ds = build_dataset(summary, status, version="0.1.0", statistics_options={"outputs": ("burial_area",)})
    scaled = 2.0 * summary[:, layout.S_PENETRATION]
    ds = toy.dataset(ToySpec(2.0), [{"toy:scaled": scaled}], ds, per_drop=True, class_basis="burial_volume")
    path = write_netcdf(ds, tmp_path / "toy.nc")
    exe = _checker_executable()
    assert exe, "compliance-checker is not installed"
    res = subprocess.run(
        [exe, "-t", "cf:1.11", "-c", "lenient", str(path)], capture_output=True, text=True, timeout=120
    )
    assert res.returncode == 0 and "Errors" not in res.stdout, res.stdout + res.stderr
    with xr.open_dataset(path) as back:
        np.testing.assert_array_equal(back["toy_scaled"].values, scaled)
