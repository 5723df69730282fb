"""The generic layer names no system (issue 36 item 5): the ensemble engine, the run driver, the chunk
store, the dask layer, the CF dataset builder and the command line import none of the falling mine's
modules, and export none of its names; they reach a system only through the system registry
(:mod:`mineburial.systems.registry`).

**A mine module** is a module that exists for the falling mine alone (docs/design.md, "Where things
are", the row ``systems/mine/``): every module inside one of :data:`MINE_PACKAGES` or equal to, or
inside, one of :data:`MINE_MODULES`. Generic modules that serve every system (the registry, the
sampling, the settings, the variable registry ``io/variables.py``, the errors) are not; they may
import a mine module themselves (the registry imports every system by design), so the check is of
each generic module's own imports: every ``import``/``from ... import`` anywhere in its source,
function-local ones included (the import graph of ``tests/test_imports.py``).

``mineburial/ensembles/dataset.py`` is the mine's Dataset (its burial statistics, summary columns and
burial classes; docs/design.md): it is a mine module here, and the generic dataset builder is
``mineburial/io/dataset.py`` (the one CF builder of every file).

Reference: the source files parsed with :mod:`ast`, and the module objects' attributes.
"""

from __future__ import annotations

import importlib
import sys

from test_imports import import_graph

#: packages whose every module is the mine's
MINE_PACKAGES = ("mineburial.kernels.mine", "mineburial.calibration", "mineburial.validation")
#: modules that are the mine's (a package here counts with its submodules)
MINE_MODULES = (
    # its ensemble: the system entry, the drops on the thread pool, its Dataset and statistics,
    # the self-check, model choices, the epistemic band, the post-impact process seam and scour
    "mineburial.ensembles.mine",
    "mineburial.ensembles.batch",
    "mineburial.ensembles.dataset",
    "mineburial.ensembles.statistics",
    "mineburial.ensembles.accuracy",
    "mineburial.ensembles.model_form",
    "mineburial.ensembles.epistemic",
    "mineburial.ensembles.processes",
    "mineburial.ensembles.scour",
    "mineburial.ensembles.scour_variables",
    "mineburial.ensembles.scour_map",
    "mineburial.ensembles.scour_figure",
    # its scenario (the mine's fields and rules), sediment profiles, single drop, maps and figures
    "mineburial.config",
    "mineburial.scenario_fields",
    "mineburial.sediment_profiles",
    "mineburial.drop",
    "mineburial.maps",
    "mineburial.figures",
    # its commands
    "mineburial.systems.mine_commands",
)
#: the generic layer: engine, run driver, chunk store, dask layer, CF dataset builder, command line
GENERIC = (
    "mineburial.ensembles.engine",
    "mineburial.ensembles.runner",
    "mineburial.ensembles.store",
    "mineburial.ensembles.distributed",
    "mineburial.io.dataset",
    "mineburial.cli",
    "mineburial.commands",
)


def _within(module: str, package: str) -> bool:
    return module == package or module.startswith(package + ".")


def is_mine(module: str) -> bool:
    """Whether ``module`` is one of the falling mine's (module docstring)."""
    return any(_within(module, p) for p in MINE_PACKAGES + MINE_MODULES)


def mine_imports(graph, modules=GENERIC) -> dict:
    """``module -> sorted mine modules it imports`` for each of ``modules`` that imports one."""
    return {
        m: sorted(t for t in graph[m] if is_mine(t)) for m in modules if any(is_mine(t) for t in graph[m])
    }


def test_the_check_sees_a_generic_module_that_imports_the_mine():
    graph = {
        "mineburial.ensembles.engine": {"mineburial.systems.registry", "mineburial.ensembles.mine"},
        "mineburial.ensembles.runner": {"mineburial.kernels.mine.layout", "mineburial.ensembles.settings"},
        "mineburial.cli": {"mineburial.commands"},
    }
    got = mine_imports(
        graph, ("mineburial.ensembles.engine", "mineburial.ensembles.runner", "mineburial.cli")
    )
    assert got == {
        "mineburial.ensembles.engine": ["mineburial.ensembles.mine"],
        "mineburial.ensembles.runner": ["mineburial.kernels.mine.layout"],
    }
    # a module beside the mine's with a shared prefix is not the mine's
    assert not is_mine("mineburial.ensembles.mine_like") and is_mine("mineburial.kernels.mine.status")


def test_every_named_module_exists():
    """A renamed module must not make the check pass by naming nothing."""
    graph = import_graph()
    for module in GENERIC + MINE_MODULES + MINE_PACKAGES:
        assert module in graph, module


def test_the_generic_layer_imports_no_mine_module():
    assert mine_imports(import_graph()) == {}


def test_the_generic_layer_exports_none_of_the_mine_s_names():
    """No attribute of a generic module is a class or function defined in a mine module (a
    re-export such as engine's former ``EnsembleSpec`` or the runner's ``summarize``)."""
    found = {}
    for name in GENERIC:
        module = importlib.import_module(name)
        for attr, value in vars(module).items():
            origin = getattr(value, "__module__", None)
            if isinstance(origin, str) and is_mine(origin) and not isinstance(value, type(sys)):
                found.setdefault(name, []).append(attr)
    assert found == {}
