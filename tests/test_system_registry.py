"""The system registry (issue 18 item 2) and the leaf error module (item 6).

What each test checks against what:

* no system is chosen by an if-chain: the package's sources (read as text, the
  reference) hold no comparison of a system name (``system == ...``, ``system != ...``);
* a system is one registry entry: a toy system (a chunk's summary is the square of the
  realization index, so the mean over ``n`` is the closed form ``(n - 1)(2n - 1)/6``)
  runs through ``engine.load_ensemble``, the run driver, its checks, the chunk store and
  the NetCDF writer, and resumes from its chunk files, without any of them naming it;
* the registered systems: the scenario's ``system`` key picks the spec, an unknown name
  gets a did-you-mean, example names are unique across systems;
* errors.py imports nothing of mineburial (parsed with :mod:`ast`), and the error types and
  helpers keep their old import places as the same objects.
"""

from __future__ import annotations

import ast
import dataclasses
import re
from pathlib import Path
from typing import ClassVar

import numpy as np
import pytest
import xarray as xr

import mineburial
from mineburial import errors
from mineburial.cli import main
from mineburial.ensembles import engine, runner, store
from mineburial.systems import registry
from mineburial.systems.mine import config, sediment_profiles
from mineburial.systems.mine import ensemble as mine
from mineburial.systems.restraint import ensemble as restraint

ROOT = Path(mineburial.__file__).resolve().parent


# ---------------------------------------------------------------------------
# no if-chains
# ---------------------------------------------------------------------------
_CHAIN = re.compile(r"""system\s*[!=]=|[!=]=\s*\w*\.?system\b|[!=]=\s*["'](mine|restraint)["']""")


def test_the_regex_of_the_guard_sees_an_if_chain():
    for line in ('if spec.system == "restraint":', "if system != 'mine':", 'if "mine" == spec.system:'):
        assert _CHAIN.search(line), line
    assert not _CHAIN.search("system = registry.get(name)")


def test_no_module_chooses_a_system_by_comparing_its_name():
    found = []
    for path in sorted(ROOT.rglob("*.py")):
        for k, line in enumerate(path.read_text().splitlines(), 1):
            if _CHAIN.search(line.split("#")[0]):
                found.append(f"{path.relative_to(ROOT.parent)}:{k}: {line.strip()}")
    assert not found, "\n".join(found)


# ---------------------------------------------------------------------------
# a new system is one registry entry
# ---------------------------------------------------------------------------
@dataclasses.dataclass(frozen=True)
class _Base:
    label: str

    def to_dict(self) -> dict:
        return {"label": self.label}


@dataclasses.dataclass(frozen=True)
class ToySpec:
    base: _Base
    n: int
    seed: int
    chunk_size: int
    sampling: str = "mc"
    per_drop: bool = False
    random: dict = dataclasses.field(default_factory=dict)
    input_files: tuple = ()

    system: ClassVar[str] = "toy"
    summary_width: ClassVar[int] = 1
    unit: ClassVar[str] = "toys"

    def identity_items(self) -> list:
        return []


def _toy_system(calls: list) -> registry.System:
    def load(raw, overrides, base_dir=None):
        ens = {"n": 5, "seed": 0, "chunk_size": 2, **raw.get("ensemble", {})}
        ens.update({k: v for k, v in overrides.items() if v is not None and k in ens})
        return ToySpec(_Base(raw["label"]), int(ens["n"]), int(ens["seed"]), int(ens["chunk_size"]))

    def compute_chunk(spec, start, stop):
        calls.append((start, stop))
        k = np.arange(start, stop, dtype=np.float64)
        return {
            "start": np.int64(start),
            "stop": np.int64(stop),
            "summary": (k * k)[:, None],
            "status": np.zeros(stop - start, dtype=np.int8),
            "invalid_inputs": np.array("{}"),
        }

    def dataset(spec, chunks):
        values = np.concatenate([c["summary"][:, 0] for c in chunks])
        return xr.Dataset(
            {"square_mean": ((), values.mean(), {"units": "1"})}, attrs={"title": spec.base.label}
        )

    return registry.System(
        name="toy",
        load=load,
        compute_chunk=compute_chunk,
        dataset=dataset,
        summarize=lambda ds, elapsed=None, output=None: f"toy mean {float(ds['square_mean']):g}",
        bytes_a_realization=lambda spec: 9,
        warn_run=lambda spec: calls.append("warned"),
        example_names=lambda: ("toy_example",),
        example=lambda name: ("toy scenario", 'system = "toy"\nlabel = "x"\n'),
    )


@pytest.fixture
def toy(monkeypatch):
    calls: list = []
    monkeypatch.setitem(registry.SYSTEMS, "toy", _toy_system(calls))
    monkeypatch.setattr(engine, "SYSTEMS", registry.names())
    return calls


def test_a_system_added_to_the_registry_runs_stores_and_resumes_through_the_generic_layer(toy, tmp_path):
    scenario = {"system": "toy", "label": "squares", "ensemble": {"n": 7, "chunk_size": 3}}
    out = tmp_path / "toy.nc"
    ds = runner.run_ensemble(scenario, output=out)
    n = 7
    assert float(ds["square_mean"]) == pytest.approx((n - 1) * (2 * n - 1) / 6)  # mean of k^2, k < n
    assert toy == ["warned", (0, 3), (3, 6), (6, 7)]
    with xr.open_dataset(out) as back:
        assert float(back["square_mean"]) == float(ds["square_mean"])
        assert back.attrs["title"] == "squares"
    # resume: the chunk files of a run interrupted after its first chunk are loaded, not recomputed
    spec = engine.load_ensemble(scenario, systems=engine.SYSTEMS)
    part = store.ChunkStore.for_spec(spec, tmp_path / "parts").open()
    part.save(registry.get("toy").compute_chunk(spec, 0, 3))
    toy.clear()
    ((_, chunks),) = runner.run_jobs([runner.Job(None, spec, part)])
    assert toy == [(3, 6), (6, 7)]
    assert [int(c["start"]) for c in chunks] == [0, 3, 6]
    assert runner.memory_needed(spec) == 4 * 9 * n + runner.CHUNK_OVERHEAD * 3


def test_a_command_that_runs_only_mines_refuses_another_system_naming_it(toy):
    with pytest.raises(errors.ScenarioError, match=r"system = 'toy': this command runs only 'mine'"):
        engine.load_ensemble({"system": "toy", "label": "x"})


def test_the_examples_of_a_new_system_are_listed_and_written(toy, tmp_path, capsys):
    assert main(["example"]) == 0
    assert capsys.readouterr().out.split()[-1] == "toy_example"
    assert main(["example", "toy_example", "-o", str(tmp_path / "t.toml")]) == 0
    assert "wrote example toy scenario 'toy_example'" in capsys.readouterr().out
    assert (tmp_path / "t.toml").read_text() == 'system = "toy"\nlabel = "x"\n'


# ---------------------------------------------------------------------------
# the registered systems
# ---------------------------------------------------------------------------
def test_the_system_key_picks_the_spec_of_its_system():
    assert registry.names() == ("mine", "restraint")
    assert registry.DEFAULT == "mine"
    spec = engine.load_ensemble(None, n=4)
    assert isinstance(spec, mine.EnsembleSpec) and registry.of(spec) is registry.SYSTEMS["mine"]
    raw = restraint.rs.table2_case(1).to_dict()
    spec = engine.load_ensemble({**raw, "system": "restraint"}, n=4, systems=engine.SYSTEMS)
    assert isinstance(spec, restraint.RestraintEnsembleSpec)
    assert registry.of(spec) is registry.SYSTEMS["restraint"]


@pytest.mark.parametrize("name", ["restrant", "Mine", 3])
def test_an_unknown_system_is_one_line_with_the_allowed_names(name):
    with pytest.raises(errors.ScenarioError) as info:
        engine.load_ensemble({"system": name}, systems=engine.SYSTEMS)
    text = str(info.value)
    assert text.startswith(f"unknown system '{name}':") and text.endswith("allowed: mine, restraint")
    if name == "restrant":
        assert "did you mean 'restraint'?" in text


def test_example_names_are_unique_across_systems_and_each_is_written_by_its_own_system():
    names = [n for s in registry.SYSTEMS.values() for n in s.example_names()]
    assert len(names) == len(set(names))
    assert set(config.ensemble_example_names()) <= set(registry.SYSTEMS["mine"].example_names())
    what, text = registry.example("restraint_ensemble")
    assert what == "restraint ensemble" and 'system = "restraint"' in text
    assert registry.example("restraint_case3")[0] == "restraint case"
    assert registry.example("default_mine") == ("scenario", config.example_path("default_mine").read_text())
    with pytest.raises(
        errors.ScenarioError, match=r"unknown example scenario 'restraint_case99': did you mean"
    ):
        registry.example("restraint_case99")


# ---------------------------------------------------------------------------
# the leaf error module
# ---------------------------------------------------------------------------
def test_errors_imports_nothing_of_mineburial():
    tree = ast.parse((ROOT / "errors.py").read_text())
    imported = [a.name for n in ast.walk(tree) if isinstance(n, ast.Import) for a in n.names]
    imported += [n.module or "" for n in ast.walk(tree) if isinstance(n, ast.ImportFrom)]
    assert imported and not [m for m in imported if m.startswith("mineburial")], imported


def test_the_old_import_places_give_the_same_error_types_and_helpers():
    assert sediment_profiles.ScenarioError is errors.ScenarioError is config.ScenarioError
    assert sediment_profiles.unknown_name_message is errors.unknown_name_message
    assert config.unknown_names_message is errors.unknown_names_message
    assert store.RunError is errors.RunError and store.RunLockedError is errors.RunLockedError
    assert engine.EnsembleError is mine.EnsembleError is errors.EnsembleError
    assert issubclass(errors.RunLockedError, errors.RunError)
    assert issubclass(errors.EnsembleError, errors.ScenarioError)
    assert issubclass(errors.ScenarioError, ValueError)
    msg = errors.unknown_names_message("key", ["lenght", "zzz"], ["length", "mass"])
    assert msg == "unknown keys 'lenght' (did you mean 'length'?), 'zzz': allowed: length, mass"
