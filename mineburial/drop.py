"""Single drops: run the compiled stepper on one scenario and return its trajectory."""

from __future__ import annotations

import json
import math

import numpy as np
import xarray as xr

from mineburial.kernels import layout, status
from mineburial.kernels.rotation import euler_angles
from mineburial.kernels.stepper import N_TRAJ, TRAJ_COLUMNS, run_drop

PHASE_NAMES = ("air", "crossing_water_surface", "water", "crossing_seabed", "embedded")

_TRAJ_ATTRS = {
    "x": ("m", "x coordinate of the centre of mass (E-frame)"),
    "y": ("m", "y coordinate of the centre of mass (E-frame)"),
    "z": ("m", "height of the centre of mass above the calm water surface (E-frame, z up)"),
    "u": ("m s-1", "x component of the centre-of-mass velocity"),
    "v": ("m s-1", "y component of the centre-of-mass velocity"),
    "w": ("m s-1", "vertical component of the centre-of-mass velocity (up positive)"),
    "q0": ("1", "orientation quaternion, scalar part (body to earth)"),
    "q1": ("1", "orientation quaternion, first vector component"),
    "q2": ("1", "orientation quaternion, second vector component"),
    "q3": ("1", "orientation quaternion, third vector component"),
    "omega1": ("rad s-1", "angular velocity about the mine axis i_M (body frame)"),
    "omega2": ("rad s-1", "angular velocity about j_M (body frame)"),
    "omega3": ("rad s-1", "angular velocity about k_M (body frame)"),
    "work_fluid": ("J", "work done on the mine by fluid forces (buoyancy, drag, lift, added mass)"),
    "work_sediment": ("J", "work done on the mine by sediment forces"),
}
_FORCE_ATTRS = {
    "fluid_force_x": ("N", "fluid force on the mine, x component (E-frame)"),
    "fluid_force_y": ("N", "fluid force on the mine, y component (E-frame)"),
    "fluid_force_z": ("N", "fluid force on the mine, z component (E-frame)"),
    "sediment_force_x": ("N", "sediment force on the mine, x component (E-frame)"),
    "sediment_force_y": ("N", "sediment force on the mine, y component (E-frame)"),
    "sediment_force_z": ("N", "sediment force on the mine, z component (E-frame)"),
    "torque_1": ("N m", "total torque about the centre of mass, i_M component (body frame)"),
    "torque_2": ("N m", "total torque about the centre of mass, j_M component (body frame)"),
    "torque_3": ("N m", "total torque about the centre of mass, k_M component (body frame)"),
}

SUMMARY_ATTRS = {
    "penetration_depth": ("m", "depth of the lowest point of the mine below the seabed"),
    "com_depth": ("m", "depth of the centre of mass below the seabed (negative: above)"),
    "burial_volume": ("percent", "percent of the mine volume below the seabed"),
    "burial_height": ("percent", "percent of the mine's vertical extent below the seabed"),
    "burial_area": ("percent", "percent of the mine's surface area below the seabed"),
    "height_proud": ("m", "height of the highest point of the mine above the seabed"),
    "final_pitch": ("degree", "final nose dip below the horizontal, psi2"),
    "final_roll": ("degree", "final roll about the mine axis, psi1"),
    "final_heading": ("degree", "final heading of the mine axis, psi3"),
    "final_x": ("m", "final x of the centre of mass"),
    "final_y": ("m", "final y of the centre of mass"),
    "impact_speed": ("m s-1", "speed of the centre of mass at first contact with the seabed"),
    "impact_pitch": ("degree", "nose dip psi2 at first contact with the seabed"),
    "impact_angle": ("degree", "angle of the velocity below the horizontal at first contact"),
    "impact_time": ("s", "time of first contact with the seabed"),
    "water_entry_time": ("s", "time of first contact with the water surface"),
    "total_time": ("s", "simulated time of the drop"),
    "max_deceleration": ("m s-2", "largest acceleration magnitude while in contact with the sediment"),
    "n_steps": ("1", "number of time steps taken"),
}


def run_params(params, sediment_bank, current_bank, record_interval=None):
    """Run one drop on packed inputs; returns (status, summary, trajectory or None)."""
    params = np.ascontiguousarray(params, dtype=np.float64)
    summary = np.empty(layout.N_SUMMARY)
    if record_interval is None:
        traj = np.empty((0, N_TRAJ))
        dt_rec = 1.0
    else:
        dt_rec = float(record_interval)
        n = int(math.ceil(params[layout.P_TMAX] / dt_rec)) + 3
        traj = np.empty((n, N_TRAJ))
    code, rows = run_drop(params, np.ascontiguousarray(sediment_bank, dtype=np.float64),
                          np.ascontiguousarray(current_bank, dtype=np.float64), summary, traj,
                          dt_rec)
    return int(code), summary, (traj[:rows] if record_interval is not None else None)


def simulate_drop(scenario, record_interval: float | None = None, forces: bool = False,
                  params=None) -> xr.Dataset:
    """Simulate one drop and return its trajectory as an :class:`xarray.Dataset`.

    Parameters
    ----------
    scenario : mineburial.config.Scenario, dict or path to a TOML file
        A fully specified (deterministic) scenario.
    record_interval : float, optional
        Output interval in seconds (default: every 10 time steps).
    forces : bool
        Also return the fluid and sediment forces and the torque.
    params : tuple, optional
        Pre-packed ``(p, sediment_bank, current_bank)``; overrides ``scenario`` packing
        (the ensemble uses this to re-run a single sampled drop).

    The dataset has a ``time`` dimension with position, velocity, orientation
    (quaternion and the angles psi1, psi2, psi3 of seed 000 eq. (4)), angular
    velocity, phase (medium) and work of fluid and sediment forces; the per-drop
    burial summary as scalar variables; the status code and the resolved scenario
    in the attributes.
    """
    from mineburial._version import __version__
    from mineburial.config import Scenario

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
    code, summary, traj = run_params(p, sed_bank, cur_bank, record_interval)
    cols = {name: traj[:, i] for i, name in enumerate(TRAJ_COLUMNS)}
    time = cols["time"]
    data = {}
    for name, (units, desc) in _TRAJ_ATTRS.items():
        data[name] = ("time", cols[name], {"units": units, "long_name": desc})
    angles = np.array([euler_angles(*row) for row in traj[:, 7:11]]).reshape(-1, 3)
    for k, (name, desc) in enumerate((("psi1", "roll about the mine axis (seed 000 psi1)"),
                                      ("psi2", "dip of the nose below the horizontal (seed 000 psi2)"),
                                      ("psi3", "heading of the mine axis (seed 000 psi3)"))):
        data[name] = ("time", np.degrees(angles[:, k]), {"units": "degree", "long_name": desc})
    data["phase"] = ("time", cols["phase"].astype(np.int8),
                     {"long_name": "medium the mine is in or crossing",
                      "flag_values": np.arange(len(PHASE_NAMES), dtype=np.int8),
                      "flag_meanings": " ".join(PHASE_NAMES)})
    if forces:
        for name, (units, desc) in _FORCE_ATTRS.items():
            data[name] = ("time", cols[name], {"units": units, "long_name": desc})
    for i, name in enumerate(layout.SUMMARY_NAMES):
        units, desc = SUMMARY_ATTRS[name]
        data[name] = ((), summary[i], {"units": units, "long_name": desc})
    data["status"] = ((), np.int8(code), {
        "long_name": "drop status",
        "flag_values": np.arange(len(status.NAMES), dtype=np.int8),
        "flag_meanings": " ".join(status.NAMES)})
    ds = xr.Dataset(data, coords={"time": ("time", time, {"units": "s", "standard_name": "time",
                                                             "long_name": "time since release"})})
    ds.attrs.update({
        "title": f"mineburial drop trajectory: {scenario.mine.name}",
        "status": status.NAMES[code],
        "status_description": status.DESCRIPTIONS[code],
        "scenario": json.dumps(scenario.to_dict()),
        "mineburial_version": __version__,
        "model": layout.MODEL_NAMES[int(p[layout.P_MODEL])],
        "integrator": layout.INTEGRATOR_NAMES[int(p[layout.P_INTEGRATOR])],
    })
    return ds
