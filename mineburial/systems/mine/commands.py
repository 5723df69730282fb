"""The falling mine's commands (:mod:`mineburial.commands`): ``drop``, ``map``, ``compare``,
``sensitivity``, ``validate`` and ``calibrate``. Light on purpose: each ``run`` imports its own
modules when the command runs (start-up cost, :mod:`mineburial.cli`'s docstring)."""

from __future__ import annotations

import argparse
import math

from mineburial.commands import Command, register

__all__ = ["seconds"]


def seconds(text: str) -> float:
    """argparse type: a finite number of seconds > 0."""
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a number of seconds") from None
    if not (math.isfinite(value) and value > 0.0):
        raise argparse.ArgumentTypeError(f"{text} must be a finite number of seconds > 0")
    return value


def _execution_arguments(parser) -> None:
    """Where and how quietly the drops of compare and sensitivity run (as ``mineburial run``'s)."""
    parser.add_argument("--threads", type=int, default=None, help="numba threads (1 to the cores)")
    parser.add_argument(
        "--scheduler", default=None, help="address of a dask.distributed scheduler to spread chunks over"
    )
    parser.add_argument("--quiet", action="store_true", help="no progress lines")


# --- drop ----------------------------------------------------------------------------------------------


def _drop_arguments(drop) -> None:
    drop.add_argument("scenario", help="scenario TOML with fixed values")
    drop.add_argument("-o", "--output", default="trajectory.nc")
    drop.add_argument(
        "--record-interval", type=seconds, default=None, help="output interval, s (default: 10 numerics.dt)"
    )
    drop.add_argument("--forces", action="store_true", help="also write forces and torques")


def _run_drop(args) -> int:
    # local import: start-up, each command imports only its own modules (module docstring)
    from mineburial.ensembles import engine, runner
    from mineburial.ensembles.store import OutputRun
    from mineburial.systems.mine.config import Scenario
    from mineburial.systems.mine.drop import (
        drop_summary,
        first_trajectory_span,
        simulate_drop,
        trajectory_rows,
    )

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


# --- map -----------------------------------------------------------------------------------------------


def _map_arguments(mp) -> None:
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
    mp.add_argument(
        "--cell-seeds",
        choices=("index", "inputs"),
        default="index",
        help="seed each cell by its index (default: every cell its own ensemble) or by its inputs (cells "
        "with identical inputs share one ensemble, computed once)",
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


def _run_map(args) -> int:
    # local import: start-up, each command imports only its own modules (module docstring)
    from mineburial.analyses.maps import run_map_cli

    return run_map_cli(args)


# --- compare -------------------------------------------------------------------------------------------


def _compare_arguments(cmp_) -> None:
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
    _execution_arguments(cmp_)


def _run_compare(args) -> int:
    # local import: start-up, each command imports only its own modules (module docstring)
    from mineburial.analyses.compare import run_compare_cli

    return run_compare_cli(args)


# --- sensitivity ---------------------------------------------------------------------------------------


def _sensitivity_arguments(sens) -> None:
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
    _execution_arguments(sens)


def _run_sensitivity(args) -> int:
    # local import: start-up, each command imports only its own modules (module docstring)
    from mineburial.analyses.sensitivity import run_sensitivity_cli

    return run_sensitivity_cli(args)


# --- validate ------------------------------------------------------------------------------------------


def _validate_arguments(val) -> None:
    val.add_argument("-o", "--output", default="validation", help="report folder")
    val.add_argument("--quick", action="store_true", help="only the quick cases (as in CI)")


def _run_validate(args) -> int:
    # local import: start-up, each command imports only its own modules (module docstring)
    from mineburial.validation.report import run_validate_cli

    return run_validate_cli(args)


# --- calibrate -----------------------------------------------------------------------------------------


def _calibrate_arguments(cal) -> None:
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


def _run_calibrate(args) -> int:
    # local import: start-up, each command imports only its own modules (module docstring)
    from mineburial.systems.mine.calibration import calibrate

    return calibrate.run_cli(args)


register(Command("drop", "simulate one drop and write its trajectory (NetCDF)", _drop_arguments, _run_drop))
register(
    Command(
        "map", "burial-probability map over an environment grid", _map_arguments, _run_map, resumable=True
    )
)
register(
    Command(
        "compare",
        "the same sampled drops under several values of one scenario field: side-by-side burial statistics",
        _compare_arguments,
        _run_compare,
        resumable=True,
    )
)
register(
    Command(
        "sensitivity",
        "first-order and total Sobol' indices of penetration and burial for every random input",
        _sensitivity_arguments,
        _run_sensitivity,
        resumable=True,
    )
)
register(
    Command(
        "validate",
        "run every validation case and write the report (Markdown, PNG, JSON)",
        _validate_arguments,
        _run_validate,
    )
)
register(
    Command(
        "calibrate",
        "draw coefficient sets from the priors, run every evidence case under each, weight them "
        "by the measurements and write the posterior (JSON) that ensembles draw from",
        _calibrate_arguments,
        _run_calibrate,
        resumable=True,
    )
)
