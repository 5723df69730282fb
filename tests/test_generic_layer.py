"""The generic layer names no system (issue 36 item 5): the ensemble engine, the run driver, the chunk
store, the dask layer, the CF dataset builder and the command line import none of the falling mine's
modules, and export none of its names; they reach a system only through the system registry
(:mod:`mineburial.systems.registry`).

**A mine module** is a module that exists for the falling mine alone: since the layout of issue 36
item 6 (docs/design.md, "Layout") its folder says so, every module inside one of
:data:`MINE_PACKAGES`. The generic layer is every module of ``mineburial/ensembles/`` (a mine module
put there fails here) and :data:`GENERIC_MODULES`. Other modules that serve every system (the
registry, the variable registry ``io/variables.py``, the errors) are not mine modules either; they
may import a mine module themselves (the registry imports every system by design), so the check is of
each generic module's own imports: every ``import``/``from ... import`` anywhere in its source,
function-local ones included (the import graph of ``tests/test_imports.py``).

``mineburial/systems/mine/dataset.py`` is the mine's Dataset (its burial statistics, summary columns and
burial classes; docs/design.md): it is a mine module here, and the generic dataset builder is
``mineburial/io/dataset.py`` (the one CF builder of every file).

Reference: the source files parsed with :mod:`ast`, and the module objects' attributes.
"""

from __future__ import annotations

import dataclasses
import importlib
import sys

import pytest
import tomllib
from test_imports import import_graph
from test_system_registry import _toy_system

from mineburial import cli
from mineburial.ensembles import engine
from mineburial.systems import registry

#: the packages whose every module is the falling mine's (docs/design.md, "Layout"): its kernels, its
#: Python side (scenario, ensemble, Dataset, statistics, processes, calibration, commands), the
#: analyses over its ensembles and the validation cases
MINE_PACKAGES = (
    "mineburial.kernels.mine",
    "mineburial.systems.mine",
    "mineburial.analyses",
    "mineburial.validation",
)
#: the generic layer: every module of the ensemble engine's package (engine, run driver, chunk store,
#: dask layer, thread pool, sampling, settings, ...), the CF dataset builder and the command line
GENERIC_PACKAGES = ("mineburial.ensembles",)
GENERIC_MODULES = ("mineburial.io.dataset", "mineburial.cli", "mineburial.commands")


def _within(module: str, package: str) -> bool:
    return module == package or module.startswith(package + ".")


def is_mine(module: str) -> bool:
    """Whether ``module`` is one of the falling mine's (module docstring)."""
    return any(_within(module, p) for p in MINE_PACKAGES)


def generic(graph) -> tuple:
    """The generic layer's modules: :data:`GENERIC_MODULES` and every module in :data:`GENERIC_PACKAGES`."""
    inside = sorted(m for m in graph if any(_within(m, p) for p in GENERIC_PACKAGES))
    return tuple(inside) + GENERIC_MODULES


def mine_imports(graph, modules=None) -> dict:
    """``module -> sorted mine modules it imports`` for each of ``modules`` (default: the generic
    layer) that imports one."""
    modules = generic(graph) if modules is None else modules
    return {
        m: sorted(t for t in graph[m] if is_mine(t)) for m in modules if any(is_mine(t) for t in graph[m])
    }


def test_the_check_sees_a_generic_module_that_imports_the_mine():
    graph = {
        "mineburial.ensembles.engine": {"mineburial.systems.registry", "mineburial.systems.mine.ensemble"},
        "mineburial.ensembles.runner": {"mineburial.kernels.mine.layout", "mineburial.ensembles.settings"},
        "mineburial.cli": {"mineburial.commands"},
    }
    got = mine_imports(
        graph, ("mineburial.ensembles.engine", "mineburial.ensembles.runner", "mineburial.cli")
    )
    assert got == {
        "mineburial.ensembles.engine": ["mineburial.systems.mine.ensemble"],
        "mineburial.ensembles.runner": ["mineburial.kernels.mine.layout"],
    }
    # a module beside the mine's with a shared prefix is not the mine's
    assert not is_mine("mineburial.systems.mine_like") and is_mine("mineburial.kernels.mine.status")


def test_every_named_module_exists():
    """A renamed module must not make the check pass by naming nothing."""
    graph = import_graph()
    for module in GENERIC_MODULES + GENERIC_PACKAGES + MINE_PACKAGES:
        assert module in graph, module
    # the engine's package holds the generic layer's core, and the mine's package its ensemble
    layer = generic(graph)
    for module in ("engine", "runner", "store", "distributed", "threads", "sampling", "settings"):
        assert f"mineburial.ensembles.{module}" in layer, module
    assert is_mine("mineburial.systems.mine.ensemble") and "mineburial.systems.mine.ensemble" in graph


def test_the_generic_layer_imports_no_mine_module():
    assert mine_imports(import_graph()) == {}


def test_the_generic_layer_exports_none_of_the_mine_s_names():
    """No attribute of a generic module is a class or function defined in a mine module (a
    re-export such as engine's former ``EnsembleSpec`` or the runner's ``summarize``)."""
    found = {}
    for name in generic(import_graph()):
        module = importlib.import_module(name)
        for attr, value in vars(module).items():
            origin = getattr(value, "__module__", None)
            if isinstance(origin, str) and is_mine(origin) and not isinstance(value, type(sys)):
                found.setdefault(name, []).append(attr)
    assert found == {}


# ---------------------------------------------------------------------------
# what the engine and the driver took from the mine now comes from the system's registry entry
# ---------------------------------------------------------------------------
@pytest.fixture
def toy(monkeypatch, tmp_path):
    """The toy system of test_system_registry, with a default scenario and a figure of its own."""
    calls: list = []
    default = tmp_path / "toy_default.toml"
    default.write_text('system = "toy"\nlabel = "default toy"\n[ensemble]\nn = 3\n')

    def check_plot(path, spec, output, inputs):
        calls.append(("check_plot", str(path), spec.n))

    def plot(ds, path, *, scenario):
        calls.append(("plot", str(path), float(ds["square_mean"]), scenario))

    system = dataclasses.replace(
        _toy_system(calls), default_scenario=default, check_plot=check_plot, plot=plot
    )
    monkeypatch.setitem(registry.SYSTEMS, "toy", system)
    monkeypatch.setattr(engine, "SYSTEMS", registry.names())
    return calls


def test_the_default_scenario_is_the_default_system_s(toy, monkeypatch):
    assert engine.load_ensemble(None, n=4).system == registry.DEFAULT  # the mine's, unchanged
    monkeypatch.setattr(registry, "DEFAULT", "toy")
    spec = engine.load_ensemble(None, systems=("toy",))
    assert (spec.system, spec.base.label, spec.n) == ("toy", "default toy", 3)


def test_a_spec_of_any_registered_system_is_read_back_as_its_system():
    spec = engine.load_ensemble(
        {"system": "restraint", **restraint_ensemble_raw()}, n=3, systems=engine.SYSTEMS
    )
    again = engine.load_ensemble(spec, n=3, systems=engine.SYSTEMS)
    assert type(again) is type(spec) and again.base == spec.base and again.random.keys() == spec.random.keys()
    assert registry.is_spec(spec) and not registry.is_spec(spec.raw) and not registry.is_spec(None)


def restraint_ensemble_raw() -> dict:
    from mineburial.systems.restraint import ensemble as restraint

    _, text = restraint.example("restraint_ensemble")
    raw = tomllib.loads(text)
    raw.pop("system")
    return raw


def test_run_plot_goes_to_the_system_s_figure(toy, tmp_path, capsys):
    scenario = tmp_path / "toy.toml"
    scenario.write_text('system = "toy"\nlabel = "squares"\n[ensemble]\nn = 4\nchunk_size = 2\n')
    png = tmp_path / "toy.png"
    assert cli.main(["run", str(scenario), "--plot", str(png), "--quiet"]) == 0
    checks = [c for c in toy if isinstance(c, tuple) and c[0] in ("check_plot", "plot")]
    assert checks == [("check_plot", str(png), 4), ("plot", str(png), (0 + 1 + 4 + 9) / 4, "toy")]
    assert toy.index(checks[0]) < toy.index((0, 2))  # checked before the first chunk is computed
    assert f"wrote {png}" in capsys.readouterr().out


def test_a_system_without_a_figure_refuses_run_plot_before_computing(toy, monkeypatch, tmp_path, capsys):
    system = registry.SYSTEMS["toy"]
    monkeypatch.setitem(registry.SYSTEMS, "toy", dataclasses.replace(system, check_plot=None, plot=None))
    scenario = tmp_path / "toy.toml"
    scenario.write_text('system = "toy"\nlabel = "squares"\n')
    assert cli.main(["run", str(scenario), "--plot", str(tmp_path / "t.png")]) == cli.EXIT_USAGE
    assert capsys.readouterr().err.strip() == (
        f"mineburial: error: --plot '{tmp_path / 't.png'}': a 'toy' ensemble draws no figure"
    )
    assert not [c for c in toy if isinstance(c, tuple) and isinstance(c[0], int)]  # nothing computed
