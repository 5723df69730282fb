"""The experiments of the evidence set as runnable drops (issue 32; docs/calibration.md).

Each case builds the packed drop of one variant (an experiment) for given nuisance values,
and measures the evidence quantities on the finished drop. The coefficients of a set are
written into the packed parameter row afterwards (:func:`apply_coefficients`), so every
case is run under every coefficient set with the same code as an ensemble drop.

* ``exp1``: seed 000's Exp-1 pool drops (eqs. (92), (93); the shipped examples
  ``exp1_case92`` and ``exp1_case93``) with the pool depth as a nuisance parameter,
  integrated on a grid: one drop to a floor below the grid reaches every grid depth in turn
  (:func:`exp1_quantities`). The quantities are those of the validation
  (:mod:`mineburial.validation.cases`): travel time from first water contact to the floor,
  "slant-straight", "flip, then spiral".
* ``anchor``: the torpedo anchor of the validation (:func:`cases.anchor_scenario`) with the
  impact speed and s_u / sigma'_v as nuisance parameters; quantity: tip embedment in anchor
  lengths.
* ``scour_bands``: the field bands of the post-impact scour stage (the validation's Oahu and
  Halekulani events, :data:`validation.cases.SCOUR_EVENTS`), the peak wave period a nuisance
  parameter; quantity: B/D at the end of the event series, from the stage kernel an ensemble
  runs, with the set's ``scour.*`` coefficients and under the set's burial law (issue 33: the law
  is a coefficient with a prior, so the posterior weighs the laws).
"""

from __future__ import annotations

import dataclasses

import numpy as np

from mineburial.kernels.mine import layout, status
from mineburial.systems.mine import model_form
from mineburial.systems.mine.config import load_example
from mineburial.systems.mine.drop import run_params
from mineburial.systems.mine.scenario_fields import SCOUR_BURIAL_LAWS
from mineburial.validation import cases as vc

#: record interval of the Exp-1 trajectories (s): the validation's
EXP1_RECORD = 0.002
#: simulated time after the floor contact of an Exp-1 drop: the quantities end at the floor
EXP1_AFTER_FLOOR = 0.01
#: the Exp-1 drop's floor lies this far below the deepest pool depth of the grid (m)
EXP1_FLOOR_MARGIN = 0.05
_COL = {name: k for k, name in enumerate(layout.TRAJ_COLUMNS)}


def _exp1(variant: str, pool_depth: float):
    sc = load_example(variant)
    env = dataclasses.replace(sc.environment, water_depth=float(pool_depth))
    num = dataclasses.replace(sc.numerics, t_max=EXP1_AFTER_FLOOR)
    return dataclasses.replace(sc, environment=env, numerics=num)


def _anchor(variant: str, impact_speed: float, strength_ratio: float):
    if variant != "centrifuge":
        raise ValueError(f"anchor variant {variant!r} unknown")
    k = strength_ratio * (vc.ANCHOR_CLAY_DENSITY - vc.RHO_W) * vc.G
    return vc.anchor_scenario(float(impact_speed), k)


#: case -> (scenario builder (variant, **nuisance), whether its quantities need a trajectory)
CASES = {"exp1": (_exp1, True), "anchor": (_anchor, False)}

#: the independent blocks of the evidence: the cases of a block read only the coefficients of
#: that block (:func:`coefficient_block`), so its rows are conditioned on their own and the
#: posterior is the product of the blocks' (calibrate.condition)
CASE_BLOCK = {"exp1": "impact", "anchor": "impact", "scour_bands": "scour"}


def coefficient_block(path: str) -> str:
    """The block of a coefficient: the scour stage's (``scour.*``) or the impact phase's."""
    return "scour" if path.startswith("scour.") else "impact"


#: the scour stage's coefficients a set may carry: scenario field -> the stage kernel's name
#: (kernels/mine/scour.py ``default_parameters``; the same slots as systems/mine/processes/scour.py's NUMERIC)
SCOUR_COEFFICIENTS = {
    "scour.beq_a": "beq_a",
    "scour.beq_b": "beq_b",
    "scour.theta_exponent": "tstar_p",
    # the scour-and-settle law's (issue 33; docs/scour.md, Scour and settle)
    "scour.wave_a": "wave_a",
    "scour.wave_kc_exponent": "wave_kc_exp",
    "scour.infill_days": "infill_time",
}
#: a field given in days whose kernel slot holds seconds
_SCOUR_TO_KERNEL = {"scour.infill_days": 86400.0}


#: the set's burial law (a model-form coefficient with a prior, priors.toml): the stage runs under it
SCOUR_LAW = "scour.burial_law"


#: the grain density of each scour event's fine sand (validation.cases' assumptions): carbonate
#: off Oahu, quartz at Indian Rocks Beach
SCOUR_GRAINS = {"oahu": vc.SCOUR_CARBONATE, "halekulani": vc.SCOUR_CARBONATE, "irb": vc.SCOUR_QUARTZ}


def scour_burial(variant: str, coefficients: dict, peak_tp: float) -> float:
    """B/D at the end of the validation's scour event ``variant`` (``oahu``, ``halekulani``: fine
    carbonate sand; ``irb``: fine quartz sand, the Indian Rocks Beach fronts; the mine proud, every
    assumption of validation.cases' scour rows) with
    the peak period ``peak_tp`` and the set's ``scour.*`` coefficients (the stage's defaults for
    the others), under the set's own burial law :data:`SCOUR_LAW` (the stage's default
    ``rennie`` when the set carries none). A coefficient the law does not read is unused."""
    event = {**vc.SCOUR_EVENTS[variant], "peak_tp": float(peak_tp)}
    grains = SCOUR_GRAINS[variant]
    params = {
        SCOUR_COEFFICIENTS[k]: float(v) * _SCOUR_TO_KERNEL.get(k, 1.0)
        for k, v in coefficients.items()
        if k in SCOUR_COEFFICIENTS
    }
    law = str(coefficients.get(SCOUR_LAW, "rennie"))
    laws = vc.scour_kernels.BURIAL_RENNIE, vc.scour_kernels.BURIAL_SCOUR_SETTLE
    codes = dict(zip(SCOUR_BURIAL_LAWS, laws))
    if law not in codes:
        raise ValueError(f"{SCOUR_LAW} = {law!r} is not one of {', '.join(SCOUR_BURIAL_LAWS)}")
    params["burial_law"] = float(codes[law])
    burial, _ = vc.scour_final_burial(event, d50=vc.SCOUR_FINE, rho_grain=grains, **params)
    return burial


def apply_coefficients(p: np.ndarray, values: dict) -> np.ndarray:
    """A copy of the packed row ``p`` with each coefficient ``path -> value`` written into its
    slot (a model choice's label as its code); the post-impact stage's (``scour.*``) have no
    slot and are left out."""
    p = p.copy()
    for path, value in values.items():
        if path.startswith("scour."):
            continue
        if path in model_form.CHOICE_FIELDS:
            value = model_form.CHOICE_FIELDS[path].index(value)
        p[layout.INDEX[path]] = float(value)
    return p


def _lowest_point(traj: np.ndarray, p: np.ndarray) -> np.ndarray:
    """Height of the lowest point of the cylinder at every trajectory row: the lower end
    centre (COM -+ (L/2 -+ chi) along the axis) less R times the sine of the axis's tilt
    from the vertical (the rim of that end)."""
    q = traj[:, [_COL["q0"], _COL["q1"], _COL["q2"], _COL["q3"]]]
    q = q / np.linalg.norm(q, axis=1, keepdims=True)
    axis_z = 2.0 * (q[:, 1] * q[:, 3] - q[:, 0] * q[:, 2])  # z of the body axis (rotation_matrix r20)
    half, chi, radius = 0.5 * p[layout.P_LENGTH], p[layout.P_CHI], 0.5 * p[layout.P_DIAMETER]
    z = traj[:, _COL["z"]]
    ends = np.minimum(z + (half - chi) * axis_z, z - (half + chi) * axis_z)
    return ends - radius * np.sqrt(np.maximum(0.0, 1.0 - axis_z**2)), axis_z


def _crossing(t: np.ndarray, f: np.ndarray, level: float):
    """First time at which ``f`` falls to ``level`` (linear between records), or None."""
    below = np.flatnonzero(f <= level)
    if below.size == 0:
        return None
    k = below[0]
    if k == 0:
        return float(t[0])
    return float(t[k - 1] + (t[k] - t[k - 1]) * (f[k - 1] - level) / (f[k - 1] - f[k]))


def _flip_time(t: np.ndarray, psi2: np.ndarray):
    """First time the axis passes the horizontal (psi2 changes sign), linear between records,
    as the validation's Exp-1 rows define it (validation.cases._flip_time); None if never."""
    s = np.sign(psi2)
    idx = np.flatnonzero(s[1:] * s[:-1] < 0)
    if idx.size == 0:
        return None
    k = idx[0]
    return float(t[k] + (t[k + 1] - t[k]) * psi2[k] / (psi2[k] - psi2[k + 1]))


def _straightness(pos: np.ndarray) -> float:
    """Largest distance of the path from its chord, over the chord's length
    (validation.cases._straightness)."""
    chord = pos[-1] - pos[0]
    length = float(np.linalg.norm(chord))
    u = chord / length
    d = pos - pos[0]
    return float(np.linalg.norm(d - np.outer(d @ u, u), axis=1).max() / length)


def _turning_deg(u: np.ndarray, v: np.ndarray) -> float:
    """Angle the horizontal velocity turns through (validation.cases._turning_deg)."""
    ang = np.unwrap(np.arctan2(v, u))
    return float(np.degrees(ang[-1] - ang[0])) if ang.size > 1 else 0.0


def exp1_quantities(traj: np.ndarray, p: np.ndarray, entry_time: float, depths) -> dict:
    """The Exp-1 quantities of one trajectory for a pool floor at each of ``depths`` (m below
    the calm surface): the drop ran to a deeper floor, and until the cylinder's lowest point
    reaches a floor the fall does not depend on where the floor is, so each floor's drop is
    the trajectory cut where the lowest point crosses it. NaN where the cylinder never
    reaches that floor."""
    t = traj[:, _COL["time"]]
    low, axis_z = _lowest_point(traj, p)
    psi2 = np.arcsin(np.clip(-axis_z, -1.0, 1.0))
    pos = traj[:, [_COL["x"], _COL["y"], _COL["z"]]]
    flip_ref = vc.EXP1["exp1_case93"]["flip_time"]
    out = {k: np.full(len(depths), np.nan) for k in ("travel_time", "slant_straight", "flip_then_spiral")}
    for j, depth in enumerate(depths):
        t_floor = _crossing(t, low, -float(depth))
        if t_floor is None:
            continue
        m = (t >= entry_time) & (t <= t_floor)
        out["travel_time"][j] = t_floor - entry_time
        out["slant_straight"][j] = float(_straightness(pos[m]) <= vc.STRAIGHT_TOL)
        flip = _flip_time(t[m], psi2[m])
        spiral = False
        if flip is not None:
            after = m & (t >= flip)
            spiral = _turning_deg(traj[after, _COL["u"]], traj[after, _COL["v"]]) >= vc.SPIRAL_DEG
            flip -= entry_time
        flip_ok = flip is not None and abs(flip - flip_ref) <= vc.FLIP_TOL
        out["flip_then_spiral"][j] = float(flip_ok and spiral)
    return out


def run_case(case: str, variant: str, nuisance: dict, grid: dict, coefficients: dict) -> tuple[int, dict]:
    """Run one evidence drop; returns (status code, {quantity: values}), one value for each
    point of the case's integrated nuisance parameter (``grid``: name -> values; one value
    when it has none). A drop that did not end normally gives no quantities."""
    if case == "scour_bands":  # no drop: the stage kernel on the event series
        return status.AT_REST, {
            "burial_fraction": np.array([scour_burial(variant, coefficients, **nuisance)])
        }
    build, needs_trajectory = CASES[case]
    if needs_trajectory:  # Exp-1: one drop to a floor below every grid depth
        depths = np.asarray(grid["pool_depth"], dtype=np.float64)
        sc = build(variant, pool_depth=float(depths.max()) + EXP1_FLOOR_MARGIN, **nuisance)
    else:
        sc = build(variant, **nuisance)
    p, sed, cur = sc.to_params()
    p = apply_coefficients(p, coefficients)
    if needs_trajectory:
        code, summary, traj = run_params(p, sed, cur, EXP1_RECORD)
        entry = summary[layout.S_ENTRY_TIME]
        if not (np.isfinite(summary[layout.S_IMPACT_TIME]) and np.isfinite(entry)):
            return code, {}
        return code, exp1_quantities(traj, p, float(entry), depths)
    code, summary, _ = run_params(p, sed, cur)
    if code != status.AT_REST:
        return code, {}
    length = p[layout.P_LENGTH]
    return code, {"embedment_lengths": np.array([summary[layout.S_PENETRATION] / length])}
