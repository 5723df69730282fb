"""The command registry (issue 36 item 5: systems contribute their own CLI commands): the command
line names no system, every system's commands come from its own light module, and a command
registered from outside runs through ``mineburial`` with no other edit."""

from __future__ import annotations

import ast
import importlib.util
import pathlib
import subprocess
import sys

import pytest

from mineburial import cli, commands

ROOT = pathlib.Path(__file__).resolve().parent.parent


def test_the_command_line_names_no_system_module():
    """cli.py imports only the registry, the version and the errors at its top, and in its
    functions only generic modules (the run driver, the store, the file writer, the system
    registry): none of a system's own modules."""
    tree = ast.parse((ROOT / "mineburial" / "cli.py").read_text())
    imported = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom) and node.module and node.module.startswith("mineburial"):
            for alias in node.names:  # a submodule imported from its package, else the module
                sub = f"{node.module}.{alias.name}"
                imported.add(
                    sub
                    if importlib.util.find_spec(sub.rpartition(".")[0]) and _is_module(sub)
                    else node.module
                )
        elif isinstance(node, ast.Import):
            imported.update(a.name for a in node.names if a.name.startswith("mineburial"))
    generic = {
        "mineburial.commands",
        "mineburial._version",
        "mineburial.errors",
        "mineburial.systems.registry",
        "mineburial.ensembles.runner",
        "mineburial.ensembles.store",
        "mineburial.io.files",
    }
    assert imported <= generic, imported - generic


def _is_module(name: str) -> bool:
    try:
        return importlib.util.find_spec(name) is not None
    except ModuleNotFoundError:
        return False


def test_help_imports_no_heavy_module_and_lists_every_system_command():
    """``mineburial --help`` in a fresh interpreter: the commands of both systems are listed, and
    neither numba, xarray nor any kernel or system module was imported to list them."""
    code = (
        "import sys\n"
        "from mineburial import cli\n"
        "parser = cli.build_parser()\n"
        "text = parser.format_help()\n"
        "heavy = [m for m in sys.modules if m in ('numba', 'xarray', 'scipy') or m.startswith(("
        "'mineburial.kernels', 'mineburial.ensembles', 'mineburial.systems.mine.config', "
        "'mineburial.analyses.maps'))]\n"
        "print(heavy)\n"
        "print(text)\n"
    )
    done = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, timeout=120, check=True
    )
    heavy, _, text = done.stdout.partition("\n")
    assert heavy == "[]"
    every = ("run", "example", "drop", "map", "compare", "sensitivity", "validate", "calibrate", "restrain")
    assert all(name in text for name in every)
    assert set(commands.load()) == set(every)


@pytest.fixture
def toy_command():
    seen = {}

    def arguments(parser):
        parser.add_argument("value", type=float)
        parser.add_argument("-o", "--output", default=None)

    def run(args):
        if args.value < 0:
            raise commands_error(f"value = {args.value}; allowed: >= 0")
        if args.value == 99:
            raise KeyboardInterrupt
        seen["value"] = args.value
        return 0

    command = commands.register(commands.Command("toy", "a toy command of the tests", arguments, run))
    yield seen
    commands.unregister(command.name)


def commands_error(text):
    from mineburial.errors import ScenarioError

    return ScenarioError(text)


def test_a_registered_command_runs_with_the_cli_s_one_line_errors(toy_command, capsys):
    assert cli.main(["toy", "2.5"]) == 0 and toy_command["value"] == 2.5
    assert cli.main(["toy", "-1"]) == cli.EXIT_USAGE
    assert capsys.readouterr().err.strip() == "mineburial: error: value = -1.0; allowed: >= 0"
    assert cli.main(["toy", "99", "-o", "x.nc"]) == cli.EXIT_INTERRUPTED  # not resumable
    assert "this command cannot resume" in capsys.readouterr().err


def test_a_resumable_command_says_so_when_interrupted(capsys):
    def run(args):
        raise KeyboardInterrupt

    toy = commands.Command(
        "toy2", "resumable", lambda p: p.add_argument("-o", "--output"), run, resumable=True
    )
    commands.register(toy)
    try:
        assert cli.main(["toy2", "-o", "x.nc"]) == cli.EXIT_INTERRUPTED
        assert "rerun the same command to resume" in capsys.readouterr().err
    finally:
        commands.unregister("toy2")


def test_a_name_registered_twice_is_refused():
    first = commands.COMMANDS["drop"]
    with pytest.raises(ValueError, match="registered already"):
        commands.register(commands.Command("drop", "another", first.add_arguments, first.run))
    assert commands.COMMANDS["drop"] is first
