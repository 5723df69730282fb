"""The package's import graph has no cycle (issue 12 item 14).

Every ``import mineburial...`` and ``from mineburial... import ...`` anywhere in a module
counts, function-local imports included: a module that imports another which imports
it back (directly or through others) is a cycle. ``from package import name`` is an edge
to the submodule ``package.name`` when there is one, else to the package itself.
Reference: the source files, parsed with :mod:`ast` (no module is imported here).
"""

import ast
from pathlib import Path

import mineburial

ROOT = Path(mineburial.__file__).resolve().parent


def module_name(path: Path) -> str:
    parts = list(path.relative_to(ROOT.parent).with_suffix("").parts)
    if parts[-1] == "__init__":
        parts.pop()
    return ".".join(parts)


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
        graph[name] = edges
    return graph


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
    assert {"mineburial.drop", "mineburial.ensembles.runner"} <= graph["mineburial"]
    assert "mineburial.config" in graph["mineburial.drop"]  # imported inside simulate_drop only


def test_no_import_cycles():
    cycle = find_cycle(import_graph())
    assert cycle is None, " -> ".join(cycle)


def test_the_netcdf_writer_does_not_import_the_ensemble_layer():
    graph = import_graph()
    for module in ("mineburial.io.netcdf", "mineburial.io.variables"):
        assert not {m for m in graph[module] if m.startswith("mineburial.ensembles")}, module
