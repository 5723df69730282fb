"""Command-line interface: ``mineburial {run,example,drop,map,compare,sensitivity,validate,calibrate,
restrain}``.

The commands come from the registry :mod:`mineburial.commands`: this module registers the generic
ones (``run``, ``example``), each system's light command module its own (the mine's, the
restraining system's); this module names no system (tests/test_cli_commands.py).

Every error a user can cause ends the command with one line on stderr,
``mineburial: error: ...`` naming the field or option, and exit status 2 (bad
options included); an interrupt (Ctrl-C, SIGINT) ends it with one line and status 130.

Each command imports its modules inside its ``run`` function, on purpose (start-up cost), and
``main`` takes :class:`~mineburial.errors.ScenarioError` from the leaf :mod:`mineburial.errors`: CPU
time, median of 5 runs (2026-11-27): ``mineburial --help`` 0.13 s, and 2.7 s with every command's module
imported at the top (numba, xarray, the kernels); ``mineburial run`` of a scenario with a bad value
2.4 s, and 3.4 s so. Before, ``main`` imported the config (and with it numba) for ``--help``: 0.71 s.
"""

from __future__ import annotations

import argparse
import os
import sys
from pathlib import Path

from mineburial import commands
from mineburial._version import __version__
from mineburial.errors import ScenarioError

#: Exit status of a user error (bad scenario, option or file), as argparse uses.
EXIT_USAGE = 2
#: Exit status after an interrupt: 128 + SIGINT, the shell's convention.
EXIT_INTERRUPTED = 130


class _Parser(argparse.ArgumentParser):
    """argparse with the one-line error of every other user error (no usage block)."""

    def error(self, message):
        self.exit(EXIT_USAGE, f"mineburial: error: {message} (see '{self.prog} --help')\n")


def _cmd_example(args):
    # local import: start-up, each command imports only its own modules (module docstring)
    from mineburial.systems import registry

    if args.name is None:
        for system in registry.SYSTEMS.values():
            for name in system.example_names():
                print(name)
        return 0
    what, text = registry.example(args.name)
    target = Path(args.output or f"{args.name}.toml")
    _write_example(target, text, args.force)
    print(f"wrote example {what} {args.name!r} to {target}")
    return 0


def _write_example(target: Path, text: str, force: bool) -> None:
    """Write an example, never over an existing file (or link) unless ``force``; never
    through a link or over a device (:func:`mineburial.io.files.atomic_path`)."""
    # local import: start-up, each command imports only its own modules (module docstring)
    from mineburial.ensembles.store import RunError, check_output_path
    from mineburial.io.files import atomic_write_text

    check_output_path(target, (), "-o/--output")
    if os.path.lexists(target) and not force:
        raise RunError(f"'{target}' exists; it is left as it is: use --force to overwrite it, or -o NAME")
    try:
        atomic_write_text(target, text, replace=force)
    except FileExistsError:  # created meanwhile by another process
        raise RunError(f"'{target}' exists; it is left as it is: use --force to overwrite it") from None


def _cmd_run(args):
    # local import: start-up, each command imports only its own modules (module docstring)
    from mineburial.ensembles.runner import run_ensemble_cli

    return run_ensemble_cli(args)


def build_parser() -> argparse.ArgumentParser:
    parser = _Parser(
        prog="mineburial", description="Monte Carlo prediction of the impact burial of naval mines."
    )
    parser.add_argument("--version", action="version", version=f"mineburial {__version__}")
    sub = parser.add_subparsers(dest="command", required=True)
    for command in commands.load().values():
        command.add_arguments(sub.add_parser(command.name, help=command.help))
    return parser


def _run_arguments(run) -> None:
    """``mineburial run``: an ensemble, its burial statistics (NetCDF)."""
    run.add_argument("scenario", nargs="?", help="scenario TOML (default: embedded soft-mud case)")
    run.add_argument("-n", "--drops", type=int, default=None, help="number of drops")
    run.add_argument("--seed", type=int, default=None, help="random seed")
    run.add_argument("-o", "--output", default="burial.nc", help="output NetCDF (default burial.nc)")
    run.add_argument(
        "--sampling", choices=("mc", "sobol"), default=None, help="Monte Carlo or scrambled Sobol sampling"
    )
    run.add_argument("--chunk-size", type=int, default=None, help="drops per chunk written to disk")
    run.add_argument("--threads", type=int, default=None, help="numba threads (1 to the cores)")
    run.add_argument(
        "--per-drop",
        action=argparse.BooleanOptionalAction,
        default=None,
        help="also store per-drop inputs and results along 'realization' "
        "(default: the scenario's [ensemble] per_drop)",
    )
    run.add_argument(
        "--scheduler", default=None, help="address of a dask.distributed scheduler to spread chunks over"
    )
    run.add_argument("--quiet", action="store_true", help="no progress lines")
    run.add_argument("--plot", default=None, help="with [scour]: draw burial against lead time to this image")


def _example_arguments(ex) -> None:
    """``mineburial example``: write an example scenario."""
    ex.add_argument("name", nargs="?")
    ex.add_argument("-o", "--output", default=None)
    ex.add_argument("--force", action="store_true", help="overwrite an existing file of that name")


commands.register(
    commands.Command(
        "run",
        "run a Monte Carlo ensemble and write burial statistics (NetCDF); with no scenario, the embedded "
        'default; a scenario with system = "restraint" gives the stopping-time statistics of seed 004\'s '
        "restraining system",
        _run_arguments,
        _cmd_run,
        resumable=True,
    )
)
commands.register(
    commands.Command(
        "example",
        "write an example scenario, single-drop or ensemble (no name: list them)",
        _example_arguments,
        _cmd_example,
    )
)


def _one_line(text: str) -> str:
    return " ".join(str(text).split())


def _os_error_text(exc: OSError) -> str:
    if exc.filename is not None and exc.strerror:
        return f"{exc.filename}: {exc.strerror}"
    return str(exc)


def _check_scheduler_option(args) -> None:
    """``--scheduler`` given with a blank address is refused: every command tested
    ``if args.scheduler`` and so ran on this machine without a word (issue 35)."""
    address = getattr(args, "scheduler", None)
    if address is not None and not address.strip():
        raise ScenarioError(
            f"--scheduler {address!r}: give the scheduler's address, e.g. tcp://host:8786, or leave "
            "the option out to run on this machine"
        )


def main(argv=None) -> int:
    """Run the command line ``argv`` (default ``sys.argv[1:]``); returns the exit status.

    User errors (:class:`~mineburial.systems.mine.config.ScenarioError`, which covers bad distribution
    tables and grids too, and files that cannot be read or written) print one line
    ``mineburial: error: ...`` and return 2; an interrupt prints one line and returns 130.
    Anything else is a bug and keeps its traceback.
    """
    parser = build_parser()
    args = parser.parse_args(argv)
    try:
        _check_scheduler_option(args)
        return commands.COMMANDS[args.command].run(args)
    except ScenarioError as exc:
        message = _one_line(exc)
    except OSError as exc:
        message = _one_line(_os_error_text(exc))
    except KeyboardInterrupt:
        # on a terminal the progress line is still open: end it first
        start = "\n" if getattr(sys.stderr, "isatty", lambda: False)() else ""
        then = (
            "rerun the same command to resume"
            if commands.COMMANDS[args.command].resumable and getattr(args, "output", None)
            else "this command cannot resume: rerun it to start again"
        )
        print(f"{start}mineburial: interrupted; {then}", file=sys.stderr)
        return EXIT_INTERRUPTED
    print(f"mineburial: error: {message}", file=sys.stderr)
    return EXIT_USAGE


if __name__ == "__main__":
    sys.exit(main())
