"""Single drops: run the compiled stepper on one scenario and return its trajectory."""

from __future__ import annotations

import json
import math

import numpy as np

from mineburial import resources
from mineburial._deferred import xarray as xr
from mineburial.errors import ScenarioError
from mineburial.io import variables as V
from mineburial.io.dataset import build
from mineburial.kernels.mine import layout, status
from mineburial.kernels.mine.layout import N_TRAJ, TRAJ_COLUMNS
from mineburial.kernels.mine.overburden import with_long_tables
from mineburial.kernels.mine.stepper import reference_paths, run_drop
from mineburial.kernels.rotation import euler_angles
from mineburial.systems.mine.config import Scenario


def memory_shortfall(need: float) -> float | None:
    """The memory available to this process in bytes (:func:`mineburial.resources.
    available_memory`: free memory and the cgroup limit; 0 where nothing says) when ``need``
    bytes of records would take more than half of it (or are not finite); None when they
    fit. The one memory check of recorded trajectories and time series (drops, multibody
    runs)."""
    memory = resources.available_memory()
    if not math.isfinite(need) or (memory is not None and need > memory / 2):
        return float(memory or 0)
    return None


def trajectory_rows(record_interval, duration: float, name: str = "record_interval") -> int:
    """Rows of the trajectory recorded every ``record_interval`` seconds over ``duration``
    seconds of simulated time.

    Raises :class:`~mineburial.systems.mine.config.ScenarioError` naming ``name`` (the argument or
    command-line option) when the interval is not a finite number > 0, or when the
    trajectory would take more than half of the available memory.
    """
    if isinstance(record_interval, bool) or not isinstance(
        record_interval, (int, float, np.integer, np.floating)
    ):
        raise ScenarioError(f"{name} = {record_interval!r} must be a number of seconds")
    dt_rec = float(record_interval)
    if not (math.isfinite(dt_rec) and dt_rec > 0.0):
        raise ScenarioError(
            f"{name} = {dt_rec!r} s must be a finite number > 0 (seconds between trajectory records)"
        )
    rows = duration / dt_rec + 3.0  # float: may overflow to inf for a tiny interval
    need = rows * N_TRAJ * 8.0
    memory = memory_shortfall(need)
    if memory is not None:
        raise ScenarioError(
            f"{name} = {dt_rec!r} s would record {rows:.3g} trajectory rows over {duration:g} s "
            f"of simulated time, {need / 2**30:.3g} GiB, more than half of the memory "
            f"available ({memory / 2**30:.3g} GiB): give a larger {name}"
        )
    return math.ceil(duration / dt_rec) + 3


def first_trajectory_span(t_max: float, t_max_fall: float) -> float:
    """Simulated time the first trajectory buffer of a drop covers: ``numerics.t_max``, or
    the whole ``t_max_fall + t_max`` if shorter. A drop that runs longer (a long fall, at
    most ``t_max_fall + t_max``) is run again with a buffer sized for its end
    (:func:`run_params`), so the buffer is never sized for a bound it does not reach."""
    return min(t_max_fall + t_max, t_max)


def run_params(params, sediment_bank, current_bank, record_interval=None, name="record_interval"):
    """Run one drop on packed inputs; returns (status, summary, trajectory or None).

    The trajectory buffer first covers :func:`first_trajectory_span`; when the drop runs
    past it, the drop is run again with a buffer sized for its end time (the recorder only
    samples the continuous extension, so both runs integrate the same steps). ``name``
    names the record interval in errors (:func:`trajectory_rows`)."""
    params = np.ascontiguousarray(params, dtype=np.float64)
    summary = np.empty(layout.N_SUMMARY)
    if record_interval is None:
        traj = None
        dt_rec = 1.0
    else:
        dt_rec = float(record_interval)
        span = first_trajectory_span(float(params[layout.P_TMAX]), float(params[layout.P_TMAX_FALL]))
        traj = np.empty((trajectory_rows(dt_rec, span, name), N_TRAJ))
    banks = (
        np.ascontiguousarray(sediment_bank, dtype=np.float64),
        np.ascontiguousarray(current_bank, dtype=np.float64),
    )
    paths = with_long_tables(reference_paths(params), params, banks[0])
    code, rows = run_drop(params, *banks, summary, traj, dt_rec, paths)
    end = summary[layout.S_TOTAL_TIME]
    if traj is not None and rows == traj.shape[0] and traj[rows - 1, 0] < end:
        # the drop ran past the buffer: again, with a buffer that reaches its end
        traj = np.empty((trajectory_rows(dt_rec, end, name), N_TRAJ))
        code, rows = run_drop(params, *banks, summary, traj, dt_rec, paths)
    return int(code), summary, (traj[:rows] if record_interval is not None else None)


def simulate_drop(
    scenario,
    record_interval: float | None = None,
    forces: bool = False,
    params=None,
    record_name: str = "record_interval",
) -> xr.Dataset:
    """Simulate one drop and return its trajectory as an :class:`xarray.Dataset`.

    Parameters
    ----------
    scenario : mineburial.systems.mine.config.Scenario, dict or path to a TOML file
        A fully specified (deterministic) scenario.
    record_interval : float, optional
        Output interval in seconds (default: every 10 time steps); a finite number > 0
        whose trajectory fits in memory (:func:`trajectory_rows`).
    forces : bool
        Also return the fluid and sediment forces and the torque.
    params : tuple, optional
        Pre-packed ``(p, sediment_bank, current_bank)``; overrides ``scenario`` packing
        (the ensemble uses this to re-run a single sampled drop).
    record_name : str
        How errors about the record interval name it (the CLI: ``--record-interval``).

    The dataset has a ``time`` dimension with position, velocity, orientation
    (quaternion and the angles psi1, psi2, psi3 of seed 000 eq. (4)), angular
    velocity, phase (medium) and work of fluid and sediment forces; the per-drop
    burial summary as scalar variables; the status code and the resolved scenario
    in the attributes.
    """
    if not isinstance(scenario, Scenario):
        if isinstance(scenario, dict):
            scenario = Scenario.from_dict(scenario)
        else:
            scenario = Scenario.from_toml(scenario)
    if params is None:
        params = scenario.to_params()
    p, sed_bank, cur_bank = params
    if record_interval is None:
        record_interval = 10.0 * p[layout.P_DT]
    code, summary, traj = run_params(p, sed_bank, cur_bank, record_interval, record_name)
    cols = {name: traj[:, i] for i, name in enumerate(TRAJ_COLUMNS)}
    data = {name: cols[name] for name in V.TRAJ_STATE_COLUMNS}
    quaternion = np.stack([cols[q] for q in ("q0", "q1", "q2", "q3")], axis=1)
    angles = np.degrees(np.array([euler_angles(*row) for row in quaternion]).reshape(-1, 3))
    data.update({name: angles[:, k] for k, name in enumerate(V.TRAJ_ANGLES)})
    data["phase"] = cols["phase"]
    if forces:
        data.update({name: cols[name] for name in V.TRAJ_FORCE_COLUMNS})
    data.update({name: summary[i] for i, name in enumerate(layout.SUMMARY_NAMES)})
    data["status"] = np.int8(code)
    attrs = {
        "title": f"mineburial drop trajectory: {scenario.mine.name}",
        "status": status.NAMES[code],
        "status_description": status.DESCRIPTIONS[code],
        "scenario": json.dumps(scenario.to_dict()),
        "model": layout.MODEL_NAMES[int(p[layout.P_MODEL])],
        "integrator": layout.INTEGRATOR_NAMES[int(p[layout.P_INTEGRATOR])],
    }
    return build(data, {"time": cols["time"]}, attrs, kind="trajectory")


def drop_summary(ds: xr.Dataset, name: str, output) -> str:
    """The line ``mineburial drop`` prints for a drop of :func:`simulate_drop`.

    Burial numbers are printed only for a drop whose burial enters the statistics
    (:data:`mineburial.kernels.mine.status.IN_STATISTICS`: at rest, or buried and still
    sinking, whose penetration is a lower bound). A drop that floated, never reached the
    seabed, or ended at a time limit or in a failure gets its status and why, and no
    penetration or burial: its last state is not a burial. The file keeps the status
    (variable ``status``, attributes ``status``/``status_description``)."""
    code = int(ds["status"])
    impact = float(ds.impact_time)
    text = f"{name}: status {ds.attrs['status']}, water entry {float(ds.water_entry_time):.3f} s, "
    if math.isfinite(impact):
        text += f"seabed impact {impact:.3f} s at {float(ds.impact_speed):.2f} m/s, "
    else:
        text += "no seabed impact, "
    if code in status.IN_STATISTICS:
        bound = " (a lower bound)" if code == status.BURIED_SINKING else ""
        return (
            text + f"penetration {float(ds.penetration_depth):.3f} m{bound}, "
            f"burial {float(ds.burial_volume):.1f} % by volume; wrote {output}"
        )
    return text + f"no penetration or burial: {status.DESCRIPTIONS[code]}; wrote {output} (status recorded)"
