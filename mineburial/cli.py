"""Command-line interface: ``mineburial {run,drop,example,map}``."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path


def _cmd_drop(args):
    from mineburial.config import Scenario
    from mineburial.drop import simulate_drop
    from mineburial.io.netcdf import write_netcdf

    scenario = Scenario.from_toml(args.scenario)
    ds = simulate_drop(scenario, record_interval=args.record_interval, forces=args.forces)
    write_netcdf(ds, args.output)
    print(f"{scenario.mine.name}: status {ds.attrs['status']}, "
          f"water entry {float(ds.water_entry_time):.3f} s, "
          f"seabed impact {float(ds.impact_time):.3f} s at {float(ds.impact_speed):.2f} m/s, "
          f"penetration {float(ds.penetration_depth):.3f} m, "
          f"burial {float(ds.burial_volume):.1f} % by volume; wrote {args.output}")
    return 0


def _cmd_example(args):
    from mineburial.config import example_names, example_path

    if args.name is None:
        for name in example_names():
            print(name)
        return 0
    source = example_path(args.name)
    target = Path(args.output or f"{args.name}.toml")
    target.write_text(Path(source).read_text())
    print(f"wrote example scenario {args.name!r} to {target}")
    return 0


def _cmd_run(args):
    from mineburial.ensembles.engine import run_ensemble_cli

    return run_ensemble_cli(args)


def _cmd_map(args):
    from mineburial.maps import run_map_cli

    return run_map_cli(args)


def _cmd_compare(args):
    from mineburial.validation.compare import run_compare_cli

    return run_compare_cli(args)


def _cmd_sensitivity(args):
    from mineburial.validation.sensitivity import run_sensitivity_cli

    return run_sensitivity_cli(args)


def _cmd_validate(args):
    from mineburial.validation.report import run_validate_cli

    return run_validate_cli(args)


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="mineburial",
        description="Monte Carlo prediction of the impact burial of naval mines.")
    from mineburial import __version__
    parser.add_argument("--version", action="version", version=f"mineburial {__version__}")
    sub = parser.add_subparsers(dest="command", required=True)

    run = sub.add_parser("run", help="run a Monte Carlo ensemble and write burial statistics "
                                     "(NetCDF); with no scenario, the embedded default")
    run.add_argument("scenario", nargs="?", help="scenario TOML (default: embedded soft-mud case)")
    run.add_argument("-n", "--drops", type=int, default=None, help="number of drops")
    run.add_argument("--seed", type=int, default=None, help="random seed")
    run.add_argument("-o", "--output", default="burial.nc", help="output NetCDF (default burial.nc)")
    run.add_argument("--sampling", choices=("mc", "sobol"), default=None,
                     help="Monte Carlo or scrambled Sobol sampling")
    run.add_argument("--chunk-size", type=int, default=None, help="drops per chunk written to disk")
    run.add_argument("--threads", type=int, default=None, help="numba threads")
    run.add_argument("--per-drop", action="store_true",
                     help="also store per-drop inputs and results along 'realization'")
    run.add_argument("--scheduler", default=None,
                     help="address of a dask.distributed scheduler to spread chunks over")
    run.add_argument("--quiet", action="store_true", help="no progress lines")
    run.set_defaults(func=_cmd_run)

    drop = sub.add_parser("drop", help="simulate one drop and write its trajectory (NetCDF)")
    drop.add_argument("scenario", help="scenario TOML with fixed values")
    drop.add_argument("-o", "--output", default="trajectory.nc")
    drop.add_argument("--record-interval", type=float, default=None, help="output interval, s")
    drop.add_argument("--forces", action="store_true", help="also write forces and torques")
    drop.set_defaults(func=_cmd_drop)

    ex = sub.add_parser("example", help="write an example scenario (no name: list them)")
    ex.add_argument("name", nargs="?")
    ex.add_argument("-o", "--output", default=None)
    ex.set_defaults(func=_cmd_example)

    mp = sub.add_parser("map", help="burial-probability map over an environment grid")
    mp.add_argument("scenario")
    mp.add_argument("--environment", required=True, help="environment grid NetCDF")
    mp.add_argument("-o", "--output", default="burial_map.nc")
    mp.add_argument("-n", "--drops", type=int, default=None, help="drops per cell")
    mp.add_argument("--seed", type=int, default=None)
    mp.add_argument("--plot", default=None, help="also draw the map to this PNG")
    mp.add_argument("--scheduler", default=None)
    mp.add_argument("--quiet", action="store_true")
    mp.set_defaults(func=_cmd_map)

    cmp_ = sub.add_parser("compare", help="the same sampled drops under several values of one "
                                          "scenario field: side-by-side burial statistics")
    cmp_.add_argument("scenario", nargs="?", help="ensemble scenario TOML (default: embedded)")
    cmp_.add_argument("--vary", required=True, metavar="FIELD=A,B,...",
                      help="scenario field and its values, e.g. sediment.resistance=bearing,"
                           "friction,delta or model=mineburial,impact35")
    cmp_.add_argument("-n", "--drops", type=int, default=None, help="number of drops")
    cmp_.add_argument("--seed", type=int, default=None, help="random seed")
    cmp_.add_argument("-o", "--output", default=None, help="write the comparison (NetCDF)")
    cmp_.add_argument("--plot", default=None, help="draw the comparison to this PNG")
    cmp_.add_argument("--threads", type=int, default=None, help="numba threads")
    cmp_.add_argument("--quiet", action="store_true", help="no progress lines")
    cmp_.set_defaults(func=_cmd_compare)

    sens = sub.add_parser("sensitivity", help="first-order and total Sobol' indices of "
                                              "penetration and burial for every random input")
    sens.add_argument("scenario", nargs="?", help="ensemble scenario TOML (default: embedded)")
    sens.add_argument("-n", "--drops", type=int, default=None,
                      help="base sample size (power of two); n (d + 2) drops are run")
    sens.add_argument("--seed", type=int, default=None, help="random seed")
    sens.add_argument("-o", "--output", default=None, help="write the indices (NetCDF)")
    sens.add_argument("--plot", default=None, help="draw the indices to this PNG")
    sens.add_argument("--threads", type=int, default=None, help="numba threads")
    sens.add_argument("--quiet", action="store_true", help="no progress lines")
    sens.set_defaults(func=_cmd_sensitivity)

    val = sub.add_parser("validate", help="run every validation case and write the report "
                                          "(Markdown, PNG, JSON)")
    val.add_argument("-o", "--output", default="validation", help="report folder")
    val.add_argument("--quick", action="store_true", help="only the quick cases (as in CI)")
    val.set_defaults(func=_cmd_validate)
    return parser


def main(argv=None) -> int:
    from mineburial.config import ScenarioError

    parser = build_parser()
    args = parser.parse_args(argv)
    try:
        return args.func(args)
    except (ScenarioError, FileNotFoundError) as exc:
        print(f"mineburial: error: {exc}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
