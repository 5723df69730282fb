"""The restraining system's command (:mod:`mineburial.commands`): ``restrain``, one case of
seed 004's ship restraining system. Light on purpose: ``run`` imports the system when it runs."""

from __future__ import annotations

from mineburial.commands import Command, register


def _restrain_arguments(rs) -> None:
    rs.add_argument("case", help="restraint case TOML (e.g. from 'mineburial example restraint_case1')")
    rs.add_argument("-o", "--output", default="restraint.nc", help="output NetCDF (default restraint.nc)")


def _run_restrain(args) -> int:
    # local import: start-up, each command imports only its own modules (mineburial.cli's docstring)
    from mineburial.systems.restraint.model import run_case_file

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


register(
    Command(
        "restrain",
        "run one case of seed 004's ship restraining system and write its time series (NetCDF)",
        _restrain_arguments,
        _run_restrain,
    )
)
