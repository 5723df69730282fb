"""The package's import graph has no cycle (issue 12 item 14), and a function imports a
module only where the import says why (issue 18: optional dependencies and measured
start-up cost).

Every ``import mineburial...`` and ``from mineburial... import ...`` anywhere in a module
counts, function-local imports included: a module that imports another which imports
it back (directly or through others) is a cycle. ``from package import name`` is an edge
to the submodule ``package.name`` when there is one, else to the package itself.
A function-local import is either of an optional dependency (:data:`OPTIONAL`) or carries
the marker ``# local import:`` and its reason on its line(s) or the line above.
Reference: the source files, parsed with :mod:`ast` (no module is imported here).
"""

import ast
import functools
import types
from pathlib import Path

import mineburial

ROOT = Path(mineburial.__file__).resolve().parent


def module_name(path: Path) -> str:
    parts = list(path.relative_to(ROOT.parent).with_suffix("").parts)
    if parts[-1] == "__init__":
        parts.pop()
    return ".".join(parts)


@functools.cache  # the tree does not change during a run: parse it once (~0.9 s), not in every test
def import_graph() -> dict:
    files = {module_name(p): p for p in ROOT.rglob("*.py")}
    graph = {}
    for name, path in files.items():
        package = name if path.name == "__init__.py" else name.rpartition(".")[0]
        edges = set()
        for node in ast.walk(ast.parse(path.read_text(), str(path))):
            if isinstance(node, ast.Import):
                targets = [alias.name for alias in node.names]
            elif isinstance(node, ast.ImportFrom):
                if node.level:
                    base = package.split(".")[: len(package.split(".")) - node.level + 1]
                    module = ".".join(base + ([node.module] if node.module else []))
                else:
                    module = node.module or ""
                targets = [
                    f"{module}.{a.name}" if f"{module}.{a.name}" in files else module for a in node.names
                ]
            else:
                continue
            for target in targets:
                while target and target not in files:  # import a.b.c of a module a.b
                    target = target.rpartition(".")[0]
                if target.startswith("mineburial") and target != name:
                    edges.add(target)
        graph[name] = frozenset(edges)
    return types.MappingProxyType(graph)  # read-only: every test shares the one cached graph


def find_cycle(graph: dict):
    """A cycle as a list of modules, or None (depth-first search, three colours)."""
    colour, stack = {}, []

    def visit(node):
        colour[node] = "grey"
        stack.append(node)
        for nxt in sorted(graph.get(node, ())):
            if colour.get(nxt) == "grey":
                return stack[stack.index(nxt) :] + [nxt]
            if nxt not in colour:
                found = visit(nxt)
                if found:
                    return found
        stack.pop()
        colour[node] = "black"
        return None

    for node in sorted(graph):
        if node not in colour:
            found = visit(node)
            if found:
                return found
    return None


def test_find_cycle_detects_a_cycle_and_accepts_a_tree():
    assert find_cycle({"a": {"b"}, "b": {"c"}, "c": {"a"}}) == ["a", "b", "c", "a"]
    assert find_cycle({"a": {"b", "c"}, "b": {"c"}, "c": set()}) is None


def test_graph_sees_function_local_imports():
    graph = import_graph()
    # mineburial/__init__.py imports these only inside its wrapper functions
    assert {"mineburial.systems.mine.drop", "mineburial.ensembles.runner"} <= graph["mineburial"]
    assert (
        "mineburial.analyses.maps" in graph["mineburial.systems.mine.commands"]
    )  # inside the map command's run only


def test_no_import_cycles():
    cycle = find_cycle(import_graph())
    assert cycle is None, " -> ".join(cycle)


def test_the_netcdf_writer_does_not_import_the_ensemble_layer():
    graph = import_graph()
    for module in ("mineburial.io.netcdf", "mineburial.io.variables"):
        assert not {m for m in graph[module] if m.startswith("mineburial.ensembles")}, module


#: each system's kernels, a subpackage of mineburial.kernels (docs/design.md, "Layout");
#: the rest of mineburial.kernels is the generic integration core and math, which knows no system
SYSTEM_KERNELS = ("mineburial.kernels.mine", "mineburial.kernels.restraint")


def _within(module: str, package: str) -> bool:
    return module == package or module.startswith(package + ".")


def kernel_layer_violations(graph: dict) -> list:
    """``module -> target`` edges where a generic kernel module imports a system's kernels, or
    one system's kernels import another's."""
    found = []
    for module in sorted(m for m in graph if _within(m, "mineburial.kernels")):
        own = next((p for p in SYSTEM_KERNELS if _within(module, p)), None)
        for target in sorted(graph[module]):
            if any(_within(target, p) for p in SYSTEM_KERNELS if p != own):
                found.append(f"{module} -> {target}")
    return found


def test_kernel_layer_violations_sees_a_core_that_imports_a_system():
    graph = {
        "mineburial.kernels.core": {"mineburial.kernels.mine.layout"},
        "mineburial.kernels.restraint.forces": {"mineburial.kernels.mine.bodies", "mineburial.kernels.core"},
        "mineburial.kernels.mine.stepper": {"mineburial.kernels.core", "mineburial.kernels.mine.layout"},
    }
    assert kernel_layer_violations(graph) == [
        "mineburial.kernels.core -> mineburial.kernels.mine.layout",
        "mineburial.kernels.restraint.forces -> mineburial.kernels.mine.bodies",
    ]


def test_the_generic_kernels_import_no_system_and_the_systems_not_each_other():
    graph = import_graph()
    # the scan sees the generic core and both systems' kernels
    generic = {"mineburial.kernels.core", "mineburial.kernels.multibody", "mineburial.kernels.seabed_contact"}
    assert generic <= set(graph)
    assert {"mineburial.kernels.mine.stepper", "mineburial.kernels.restraint.forces"} <= set(graph)
    assert kernel_layer_violations(graph) == []


#: the run layer's generic modules: each serves every system of the registry, so none imports a
#: system's kernels or modules (docs/design.md, "Layout"); every other module of mineburial.ensembles
#: too (the folder is the generic ensemble engine)
GENERIC_RUN_MODULES = (
    "mineburial.ensembles.threads",
    "mineburial.ensembles.store",
    "mineburial.ensembles.interrupt",
    "mineburial.ensembles.sampling",
    "mineburial.ensembles.settings",
    "mineburial.ensembles.distributed",
    "mineburial.ensembles.distributions",
    "mineburial.ensembles.intervals",
)
#: the systems' packages (kernels and Python side) and the analyses over the mine's ensembles
SYSTEM_MODULES = SYSTEM_KERNELS + (
    "mineburial.systems.mine",
    "mineburial.systems.restraint",
    "mineburial.analyses",
)


def test_the_generic_run_modules_import_no_system():
    graph = import_graph()
    for module in GENERIC_RUN_MODULES:
        assert module in graph, module
    for module in sorted(m for m in graph if _within(m, "mineburial.ensembles")):
        found = sorted(t for t in graph[module] if any(_within(t, p) for p in SYSTEM_MODULES))
        assert found == [], module


#: optional dependencies, imported by the functions that need them: pyproject's extras
#: (matplotlib; rioxarray, with rasterio's affine and pyproj) and dask's distributed scheduler
OPTIONAL = ("matplotlib", "distributed", "dask.distributed", "pyproj", "rioxarray", "affine")
MARKER = "# local import:"


def _import_groups(function):
    """The runs of consecutive import statements in the bodies of ``function`` (nested
    blocks and functions included)."""
    for node in ast.walk(function):
        for name in ("body", "orelse", "finalbody"):
            statements = getattr(node, name, None)
            if not isinstance(statements, list):  # a lambda's body is an expression
                continue
            group = []
            for statement in [*statements, None]:
                if isinstance(statement, (ast.Import, ast.ImportFrom)):
                    group.append(statement)
                elif group:
                    yield group
                    group = []


def _optional(statement) -> bool:
    if isinstance(statement, ast.Import):
        modules = [alias.name for alias in statement.names]
    else:
        modules = ["." * statement.level + (statement.module or "")]
    return all(any(m == o or m.startswith(o + ".") for o in OPTIONAL) for m in modules)


def unexplained_local_imports(text: str) -> list[int]:
    """Lines of the imports inside a function of source ``text`` that import something other
    than an optional dependency, without ``# local import: <reason>`` on the lines of the
    run of imports it belongs to or in the comment lines right above that run."""
    lines = text.splitlines()
    found = set()
    for function in ast.walk(ast.parse(text)):
        if not isinstance(function, (ast.FunctionDef, ast.AsyncFunctionDef)):
            continue
        for group in _import_groups(function):
            above = group[0].lineno - 2
            while above >= 0 and lines[above].lstrip().startswith("#"):
                above -= 1
            said = " ".join(lines[above + 1 : group[-1].end_lineno])
            if len(said.partition(MARKER)[2].split()) >= 2:  # the marker and a reason of 2 words or more
                continue
            found.update(s.lineno for s in group if not _optional(s))
    return sorted(found)


def test_the_local_import_check_tells_explained_from_unexplained_imports():
    text = """
import os


def f():
    import matplotlib.pyplot as plt
    from dask.distributed import Client
    x = 1
    # local import: scipy.stats costs 0.5 s of start-up
    from scipy.stats import qmc
    from mineburial.systems.mine.config import Scenario
    x = 2
    from mineburial.systems.mine.drop import simulate_drop  # local import: an import cycle, test_imports
    from mineburial.analyses.maps import run_map_cli
    x = 3
    from mineburial.systems.mine.drop import simulate_drop
    import json  # local import:
    if x:
        from mineburial.analyses import maps

    def g():
        from mineburial import ensembles
"""
    assert unexplained_local_imports(text) == [16, 17, 19, 22]


def test_every_function_local_import_is_optional_or_says_why():
    unexplained = [
        f"{path.relative_to(ROOT.parent)}:{line}"
        for path in sorted(ROOT.rglob("*.py"))
        for line in unexplained_local_imports(path.read_text())
    ]
    assert not unexplained, f"function-local imports without '{MARKER} <reason>': {unexplained}"
