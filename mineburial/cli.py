"""Command-line interface: ``mineburial {run,drop,example,map,compare,sensitivity,validate,restrain,
calibrate}``.

Every error a user can cause ends the command with one line on stderr,
``mineburial: error: ...`` naming the field or option, and exit status 2 (bad
options included); an interrupt (Ctrl-C, SIGINT) ends it with one line and status 130.

Each command imports its module inside its ``_cmd_*`` function, on purpose (start-up cost), and
``main`` takes :class:`~mineburial.errors.ScenarioError` from the leaf :mod:`mineburial.errors`: CPU
time, median of 5 runs (2026-11-27): ``mineburial --help`` 0.13 s, and 2.7 s with every command's module
imported at the top (numba, xarray, the kernels); ``mineburial run`` of a scenario with a bad value
2.4 s, and 3.4 s so. Before, ``main`` imported the config (and with it numba) for ``--help``: 0.71 s.
"""

from __future__ import annotations

import argparse
import math
import os
import sys
from pathlib import Path

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


def _seconds(text: str) -> float:
    """argparse type: a finite number of seconds > 0."""
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a number of seconds") from None
    if not (math.isfinite(value) and value > 0.0):
        raise argparse.ArgumentTypeError(f"{text} must be a finite number of seconds > 0")
    return value


#: the commands that keep their finished work on an interrupt and resume it when rerun
#: (compare and sensitivity with -o: their finished chunks are kept beside it)
_RESUMABLE = ("run", "map", "compare", "sensitivity", "calibrate")


def _cmd_drop(args):
    # local import: start-up, each command imports only its own modules (module docstring)
    from mineburial.config import Scenario
    from mineburial.drop import drop_summary, first_trajectory_span, simulate_drop, trajectory_rows
    from mineburial.ensembles import engine, runner
    from mineburial.ensembles.store import OutputRun

    scenario = Scenario.from_toml(args.scenario)
    if args.record_interval is not None:
        num = scenario.numerics
        trajectory_rows(
            args.record_interval, first_trajectory_span(num.t_max, num.t_max_fall), "--record-interval"
        )
    # the files the scenario reads, as for `run`; the output's lock refuses a second drop
    inputs = runner.input_paths(args.scenario, engine.load_ensemble(args.scenario))
    with OutputRun(args.output, inputs, "-o/--output") as out:
        ds = simulate_drop(
            scenario,
            record_interval=args.record_interval,
            forces=args.forces,
            record_name="--record-interval",
        )
        out.commit(ds)
    print(drop_summary(ds, scenario.mine.name, args.output))
    return 0


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


def _cmd_restrain(args):
    # local import: start-up, each command imports only its own modules (module docstring)
    from mineburial.systems.restraint import run_case_file

    result = run_case_file(args.case, args.output)
    stop = (
        f"stopping time {result.stopping_time:.3f} s"
        if result.stopping_time is not None
        else f"the ship had not stopped at {result.t_end:.3f} s"
    )
    print(
        f"{result.system.case.name}: status {result.status_name}, {stop}, "
        f"energy closure {result.energy_closure():.1e}; wrote {args.output}"
    )
    return 0


def _cmd_run(args):
    # local import: start-up, each command imports only its own modules (module docstring)
    from mineburial.ensembles.runner import run_ensemble_cli

    return run_ensemble_cli(args)


def _cmd_map(args):
    # local import: start-up, each command imports only its own modules (module docstring)
    from mineburial.maps import run_map_cli

    return run_map_cli(args)


def _cmd_compare(args):
    # local import: start-up, each command imports only its own modules (module docstring)
    from mineburial.validation.compare import run_compare_cli

    return run_compare_cli(args)


def _cmd_sensitivity(args):
    # local import: start-up, each command imports only its own modules (module docstring)
    from mineburial.validation.sensitivity import run_sensitivity_cli

    return run_sensitivity_cli(args)


def _cmd_validate(args):
    # local import: start-up, each command imports only its own modules (module docstring)
    from mineburial.validation.report import run_validate_cli

    return run_validate_cli(args)


def build_parser() -> argparse.ArgumentParser:
    parser = _Parser(
        prog="mineburial", description="Monte Carlo prediction of the impact burial of naval mines."
    )
    parser.add_argument("--version", action="version", version=f"mineburial {__version__}")
    sub = parser.add_subparsers(dest="command", required=True)
    _add_run_parser(sub)
    _add_drop_parser(sub)
    _add_example_parser(sub)
    _add_map_parser(sub)
    _add_compare_parser(sub)
    _add_sensitivity_parser(sub)
    _add_restrain_parser(sub)
    _add_validate_parser(sub)
    _add_calibrate_parser(sub)
    return parser


def _add_run_parser(sub) -> None:
    """``mineburial run``: an ensemble, its burial statistics (NetCDF)."""
    run = sub.add_parser(
        "run",
        help="run a Monte Carlo ensemble and write burial statistics "
        "(NetCDF); with no scenario, the embedded default; a scenario with "
        'system = "restraint" gives the stopping-time statistics of seed 004\'s restraining system',
    )
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
    run.set_defaults(func=_cmd_run)


def _add_drop_parser(sub) -> None:
    """``mineburial drop``: one drop's trajectory (NetCDF)."""
    drop = sub.add_parser("drop", help="simulate one drop and write its trajectory (NetCDF)")
    drop.add_argument("scenario", help="scenario TOML with fixed values")
    drop.add_argument("-o", "--output", default="trajectory.nc")
    drop.add_argument(
        "--record-interval", type=_seconds, default=None, help="output interval, s (default: 10 numerics.dt)"
    )
    drop.add_argument("--forces", action="store_true", help="also write forces and torques")
    drop.set_defaults(func=_cmd_drop)


def _add_example_parser(sub) -> None:
    """``mineburial example``: write an example scenario."""
    ex = sub.add_parser(
        "example", help="write an example scenario, single-drop or ensemble (no name: list them)"
    )
    ex.add_argument("name", nargs="?")
    ex.add_argument("-o", "--output", default=None)
    ex.add_argument("--force", action="store_true", help="overwrite an existing file of that name")
    ex.set_defaults(func=_cmd_example)


def _add_map_parser(sub) -> None:
    """``mineburial map``: burial probability over an environment grid."""
    mp = sub.add_parser("map", help="burial-probability map over an environment grid")
    mp.add_argument("scenario")
    mp.add_argument("--environment", required=True, help="environment grid NetCDF")
    mp.add_argument("-o", "--output", default="burial_map.nc")
    mp.add_argument("-n", "--drops", type=int, default=None, help="drops per cell")
    mp.add_argument("--seed", type=int, default=None)
    mp.add_argument(
        "--target-half-width",
        type=float,
        default=None,
        help="stop a cell once every class probability's 95%% interval is narrower than +/- this "
        "(0 to 0.5; -n is then the maximum drops a cell)",
    )
    mp.add_argument(
        "--min-drops", type=int, default=None, help="with --target-half-width: drops a cell at least (100)"
    )
    mp.add_argument(
        "--step",
        type=int,
        default=None,
        help="with --target-half-width: drops between a cell's looks after --min-drops (its value)",
    )
    mp.add_argument("--plot", default=None, help="also draw the map to this image (.png, .pdf, .svg, ...)")
    mp.add_argument(
        "--lead-times",
        default=None,
        help="with [scour] and --plot: one panel per lead time, days (e.g. 0,1,4)",
    )
    mp.add_argument(
        "--geotiff", default=None, help="also write a class probability as GeoTIFF (needs rioxarray)"
    )
    mp.add_argument(
        "--lead-time", type=float, default=None, help="with --geotiff: after scour at this lead time, days"
    )
    mp.add_argument(
        "--class",
        dest="burial_class",
        type=int,
        default=4,
        help="burial class 0..4 of --geotiff/--lead-times",
    )
    mp.add_argument("--scheduler", default=None)
    mp.add_argument("--quiet", action="store_true")
    mp.set_defaults(func=_cmd_map)


def _add_compare_parser(sub) -> None:
    """``mineburial compare``: the same drops under several values of one field."""
    cmp_ = sub.add_parser(
        "compare",
        help="the same sampled drops under several values of one "
        "scenario field: side-by-side burial statistics",
    )
    cmp_.add_argument("scenario", nargs="?", help="ensemble scenario TOML (default: embedded)")
    cmp_.add_argument(
        "--vary",
        required=True,
        metavar="FIELD=A,B,...",
        help="scenario field and its values, e.g. sediment.resistance=bearing,"
        "friction,delta or model=mineburial,impact35",
    )
    cmp_.add_argument("-n", "--drops", type=int, default=None, help="number of drops")
    cmp_.add_argument("--seed", type=int, default=None, help="random seed")
    cmp_.add_argument("-o", "--output", default=None, help="write the comparison (NetCDF)")
    cmp_.add_argument("--plot", default=None, help="draw the comparison to this PNG")
    cmp_.add_argument(
        "--lead-time",
        type=float,
        default=None,
        metavar="DAYS",
        help="with [scour]: lead time of the compared burial (default: the last of scour.lead_times_days)",
    )
    cmp_.add_argument("--threads", type=int, default=None, help="numba threads (1 to the cores)")
    cmp_.add_argument(
        "--scheduler", default=None, help="address of a dask.distributed scheduler to spread chunks over"
    )
    cmp_.add_argument("--quiet", action="store_true", help="no progress lines")
    cmp_.set_defaults(func=_cmd_compare)


def _add_sensitivity_parser(sub) -> None:
    """``mineburial sensitivity``: Sobol' indices of every random input."""
    sens = sub.add_parser(
        "sensitivity",
        help="first-order and total Sobol' indices of penetration and burial for every random input",
    )
    sens.add_argument("scenario", nargs="?", help="ensemble scenario TOML (default: embedded)")
    sens.add_argument(
        "-n",
        "--drops",
        type=int,
        default=None,
        help="base sample size (power of two); n (d + 2) drops are run",
    )
    sens.add_argument("--seed", type=int, default=None, help="random seed")
    sens.add_argument(
        "--lead-time",
        type=float,
        default=None,
        metavar="DAYS",
        help="with [scour]: lead time of the analysed burial (default: the last of scour.lead_times_days)",
    )
    sens.add_argument("-o", "--output", default=None, help="write the indices (NetCDF)")
    sens.add_argument("--plot", default=None, help="draw the indices to this PNG")
    sens.add_argument("--threads", type=int, default=None, help="numba threads (1 to the cores)")
    sens.add_argument(
        "--scheduler", default=None, help="address of a dask.distributed scheduler to spread chunks over"
    )
    sens.add_argument("--quiet", action="store_true", help="no progress lines")
    sens.set_defaults(func=_cmd_sensitivity)


def _add_restrain_parser(sub) -> None:
    """``mineburial restrain``: one case of seed 004's restraining system."""
    rs = sub.add_parser(
        "restrain",
        help="run one case of seed 004's ship restraining system and write its time series (NetCDF)",
    )
    rs.add_argument("case", help="restraint case TOML (e.g. from 'mineburial example restraint_case1')")
    rs.add_argument("-o", "--output", default="restraint.nc", help="output NetCDF (default restraint.nc)")
    rs.set_defaults(func=_cmd_restrain)


def _add_validate_parser(sub) -> None:
    """``mineburial validate``: every validation case and the report."""
    val = sub.add_parser(
        "validate", help="run every validation case and write the report (Markdown, PNG, JSON)"
    )
    val.add_argument("-o", "--output", default="validation", help="report folder")
    val.add_argument("--quick", action="store_true", help="only the quick cases (as in CI)")
    val.set_defaults(func=_cmd_validate)


def _add_calibrate_parser(sub) -> None:
    """``mineburial calibrate``: condition the coefficient priors on the evidence."""
    cal = sub.add_parser(
        "calibrate",
        help="draw coefficient sets from the priors, run every evidence case under each, weight them "
        "by the measurements and write the posterior (JSON) that ensembles draw from",
    )
    cal.add_argument(
        "-n", "--sets", type=int, default=4096, help="coefficient sets drawn from the prior (default 4096)"
    )
    cal.add_argument("--seed", type=int, default=20261128, help="seed of the scrambled Sobol' draws")
    cal.add_argument(
        "-o",
        "--output",
        default="posterior.json",
        help="posterior file (default posterior.json; the shipped "
        "one is mineburial/data/calibration/posterior.json)",
    )
    cal.add_argument("--threads", type=int, default=None, help="threads (1 to the cores)")
    cal.add_argument("--report", default=None, help="also write the calibration report (Markdown) here")
    cal.add_argument("--plot", default=None, help="draw prior against posterior marginals to this image")
    cal.add_argument("--quiet", action="store_true", help="no progress lines")
    cal.set_defaults(func=_cmd_calibrate)


def _cmd_calibrate(args):
    # local import: start-up, each command imports only its own modules (module docstring)
    from mineburial.calibration import calibrate

    return calibrate.run_cli(args)


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

    User errors (:class:`~mineburial.config.ScenarioError`, which covers bad distribution
    tables and grids too, and files that cannot be read or written) print one line
    ``mineburial: error: ...`` and return 2; an interrupt prints one line and returns 130.
    Anything else is a bug and keeps its traceback.
    """
    parser = build_parser()
    args = parser.parse_args(argv)
    try:
        _check_scheduler_option(args)
        return args.func(args)
    except ScenarioError as exc:
        message = _one_line(exc)
    except OSError as exc:
        message = _one_line(_os_error_text(exc))
    except KeyboardInterrupt:
        # on a terminal the progress line is still open: end it first
        start = "\n" if getattr(sys.stderr, "isatty", lambda: False)() else ""
        then = (
            "rerun the same command to resume"
            if args.command in _RESUMABLE and getattr(args, "output", None)
            else "this command cannot resume: rerun it to start again"
        )
        print(f"{start}mineburial: interrupted; {then}", file=sys.stderr)
        return EXIT_INTERRUPTED
    print(f"mineburial: error: {message}", file=sys.stderr)
    return EXIT_USAGE


if __name__ == "__main__":
    sys.exit(main())
