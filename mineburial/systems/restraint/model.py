"""Seed 004's restraining system (Liu, Hearn, Chen et al., Kane method): a powerless ship
stopped by a gravity anchor dragged over the seabed through an anchor chain, a
restraining cable and an auxiliary rod.

Parts (docs/restraint.md explains the model, its sources and its assumptions):

* the case: :class:`RestraintCase`, read from TOML (:meth:`RestraintCase.from_toml`)
  and validated field by field against :data:`FIELDS` (name, unit, allowed range,
  source in seed 004 or the assumption made); :func:`table2_case` gives Table 2's 19
  cases and :func:`example_text` writes one as a commented scenario file;
* the initial configuration: :func:`catenary_parameter` and :func:`initial_configuration`
  (seed 004 §3.1, eqs. (30)-(35));
* the multibody description (anchor, 15 chain links, the three cable stages, the rod,
  the ship: a chain of N bodies is N bodies) and the run (:func:`simulate`), through the
  core's ``integrate`` with the jitted right-hand side and stop event of this module;
* the result as a CF NetCDF dataset (:func:`to_dataset`, written atomically by
  :func:`mineburial.io.netcdf.write_netcdf`).
"""

from __future__ import annotations

import dataclasses
import json
import math
import pathlib
import sys
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np

try:  # Python >= 3.11
    import tomllib
except ModuleNotFoundError:  # pragma: no cover - Python 3.10
    import tomli as tomllib

from mineburial import multibody as mb
from mineburial.ensembles.store import OutputRun
from mineburial.errors import ScenarioError, unknown_name_message, unknown_names_message
from mineburial.io.dataset import build
from mineburial.io.files import atomic_write_text
from mineburial.io.inputs import parse_toml, read_toml
from mineburial.io.variables import RESTRAINT_DERIVED
from mineburial.kernels import multibody as kmb
from mineburial.kernels.methods import METHOD_NAMES
from mineburial.kernels.multibody import NUMERICAL_FAILURE, STATUS_NAMES, STOPPED, body_states
from mineburial.kernels.restraint import forces as rf
from mineburial.kernels.restraint.forces import ANCHOR, ELEMENT, ROD, SHIP, segment_area_below
from mineburial.multibody import record_bytes
from mineburial.resources import memory_refusal
from mineburial.schema import (
    Field,
    Rule,
    check_rules,
    generated_block,
    markdown_table,
    replace_generated,
    toml_value,
)

# ---------------------------------------------------------------------------
# the case: fields, units, ranges, sources
# ---------------------------------------------------------------------------


#: one field of a case file: its default, unit, allowed range and source (the schema
#: mechanism the mine's scenario uses too, mineburial/schema.py)
FieldSpec = Field


def _f(section, name, default, unit, lo=None, hi=None, *, source, low_inclusive=False, kind="float"):
    """A field; ``lo``/``hi`` None are unbounded; the low end is open unless
    ``low_inclusive``, the high end closed; ``kind`` 'a|b' is a choice between a and b."""
    choices = tuple(kind.split("|")) if "|" in kind else ()
    return Field(
        f"{section}.{name}",
        unit,
        -math.inf if lo is None else float(lo),
        math.inf if hi is None else float(hi),
        low_inclusive=low_inclusive,
        default=default,
        source=source,
        kind="choice" if choices else kind,
        choices=choices,
    )


_S41 = "seed 004 §4.1"
#: every field of a case file, in file order
FIELDS: tuple[FieldSpec, ...] = (
    # --- gravity anchor (body 1)
    _f(
        "anchor",
        "mass",
        40000.0,
        "kg",
        0.0,
        1e7,
        source="seed 004 Table 2 (40 t; 50 t and 60 t in cases 4, 5)",
    ),
    _f("anchor", "length", 2.0, "m", 0.0, 100.0, source=f"{_S41}: 2.0, 2.5, 3.0 m for 40, 50, 60 t"),
    _f("anchor", "width", 4.0, "m", 0.0, 100.0, source=f"{_S41}: width 4.0 m"),
    _f("anchor", "height", 2.1, "m", 0.0, 100.0, source=f"{_S41}: height 2.1 m"),
    _f(
        "anchor",
        "friction",
        0.3,
        "1",
        0.0,
        2.0,
        source="seed 004 Table 2 (0.3; 0.5, 0.7 in cases 2, 3)",
        low_inclusive=True,
    ),
    _f(
        "anchor",
        "drag_coefficient",
        1.05,
        "1",
        0.0,
        10.0,
        source="seed 004 §3.2.1 after eq. (39) (Saleh 2002)",
        low_inclusive=True,
    ),
    _f(
        "anchor",
        "friction_velocity_scale",
        1.0e-3,
        "m s-1",
        1.0e-5,
        1.0,
        low_inclusive=True,
        source="ASSUMPTION: the sign of eq. (37) smoothed as v / sqrt(v^2 + scale^2) (the seabed-contact "
        "law of docs/multibody.md); 1 mm/s = 0.03 % of the ship speed (seed 004 switches stick/slip on the "
        "previous step's tension instead). At least 1e-5 m/s: the friction's stiffness mu N / (m scale) "
        "(~2e4 1/s at 1e-5 m/s for case 1) sets the step, and a smaller scale makes the run stiff beyond "
        "any step budget",
    ),
    # --- anchor chain (bodies 2..16)
    _f(
        "chain",
        "links",
        15,
        "1",
        1,
        1000,
        kind="int",
        low_inclusive=True,
        source=f"{_S41}: 15 links, 1 m each, 15 m",
    ),
    _f("chain", "link_length", 1.0, "m", 0.0, 100.0, source=f"{_S41}: each link 1 m"),
    _f(
        "chain",
        "radius",
        0.0763,
        "m",
        0.0,
        1.0,
        source="seed 004 Tables 1, 2: equivalent radius R_CE (0.0863, 0.0970 in cases 6, 7)",
    ),
    _f("chain", "density", 7850.0, "kg m-3", 0.0, 30000.0, source=f"{_S41}: steel 7850 kg/m3"),
    # --- restraining cable (three stages) and auxiliary rod
    _f(
        "cable",
        "length",
        152.0,
        "m",
        0.0,
        10000.0,
        source="seed 004 Table 2 (152 m; 172, 192 m in cases 8, 9)",
    ),
    _f(
        "cable",
        "horizontal",
        148.0,
        "m",
        0.0,
        10000.0,
        source="seed 004 Table 2 'cable horizontal component' x_L (149, 150 m in cases 10, 11)",
    ),
    _f(
        "cable",
        "vertical",
        6.0,
        "m",
        0.0,
        1000.0,
        source="seed 004 Table 2 'cable vertical component' h_L (8, 10 m in cases 12, 13)",
    ),
    _f(
        "cable",
        "radius",
        0.0237,
        "m",
        0.0,
        1.0,
        source=f"{_S41}: R_RE = sqrt(2 m_RU / (pi rho_s)) = 0.0237 m",
    ),
    _f(
        "cable",
        "density",
        7850.0,
        "kg m-3",
        0.0,
        30000.0,
        source=f"{_S41}: steel (R_RE is defined with rho_s)",
    ),
    _f(
        "cable",
        "stage1_elements",
        3,
        "1",
        0,
        10000,
        kind="int",
        low_inclusive=True,
        source="seed 004 §4.2: elements 17 to 19 (3 x 2 m)",
    ),
    _f("cable", "stage1_element_length", 2.0, "m", 0.0, 1000.0, source=f"{_S41}: 2 m"),
    _f(
        "cable",
        "stage2_element_length",
        10.0,
        "m",
        0.0,
        1000.0,
        source=f"{_S41}: 10 m (12, 14, 16 elements for 152, 172, 192 m, §4.2)",
    ),
    _f(
        "cable",
        "stage3_elements",
        13,
        "1",
        0,
        10000,
        kind="int",
        low_inclusive=True,
        source="seed 004 §4.2: elements 32 to 44 (13 x 2 m)",
    ),
    _f("cable", "stage3_element_length", 2.0, "m", 0.0, 1000.0, source=f"{_S41}: 2 m"),
    _f(
        "cable",
        "rod_length",
        1.0,
        "m",
        0.0,
        100.0,
        source=f"{_S41}: auxiliary rod 1 m (OCR 'Im'), same material and radius as the cable",
    ),
    # --- ship (body N)
    _f(
        "ship",
        "mass",
        500000.0,
        "kg",
        0.0,
        1e10,
        source="seed 004 Table 2 (500 t; 750, 1000 t in cases 16, 17)",
    ),
    _f("ship", "length", 50.0, "m", 0.0, 1000.0, source=f"{_S41}: cuboid 50 m x 10 m x 5 m"),
    _f("ship", "beam", 10.0, "m", 0.0, 1000.0, source=f"{_S41}: cuboid 50 m x 10 m x 5 m"),
    _f("ship", "depth", 5.0, "m", 0.0, 1000.0, source=f"{_S41}: cuboid 50 m x 10 m x 5 m"),
    _f("ship", "speed", 3.0, "m s-1", 0.0, 50.0, source="seed 004 Table 2 (3 m/s; 4, 5 m/s in cases 14, 15)"),
    _f(
        "ship",
        "joint_dx",
        0.0,
        "m",
        -500.0,
        500.0,
        low_inclusive=True,
        source="ASSUMPTION: d_x (seed 004 §4.1, Figure 2) is not printed; 0 = the rod hangs from the "
        "ship's midship section (the pitch it drives is negligible, GM_L ~ 200 m)",
    ),
    _f(
        "ship",
        "joint_dz",
        1.0,
        "m",
        -500.0,
        500.0,
        low_inclusive=True,
        source="ASSUMPTION: d_z is not printed; = rod length, so that the rod is just above the free "
        "surface (§3.2.2) and the water depth equals the cable's vertical component (§4.3.3)",
    ),
    _f(
        "ship",
        "roughness",
        150e-6,
        "m",
        0.0,
        1.0,
        low_inclusive=True,
        source="seed 004 eq. (61): k_s = 150e-6 m (Molland et al. 2011)",
    ),
    _f(
        "ship",
        "resistance_form",
        "ittc",
        "",
        kind="printed|ittc",
        source="MODEL CHOICE (docs/restraint.md section 6): 'ittc' = (C_f + C_sf) rho S_W v|v| / 2, the "
        "ITTC-1957 line's own definition R_F = C_F rho S V^2 / 2 (ITTC 1957; Molland et al. 2011, which "
        "seed 004 cites for eq. (61)); 'printed' = seed 004 eq. (62) as printed, without the 1/2",
    ),
    # --- water
    _f("water", "density", 1025.0, "kg m-3", 0.0, 2000.0, source=f"{_S41}: 1025 kg/m3"),
    _f("water", "kinematic_viscosity", 1.05e-6, "m2 s-1", 0.0, 1.0, source=f"{_S41}: 1.05e-6 m2/s"),
    _f("water", "gravity", 9.81, "m s-2", 0.0, 100.0, source=f"{_S41}: 9.81 m/s2"),
    _f(
        "water",
        "current_speed",
        0.0,
        "m s-1",
        -10.0,
        10.0,
        low_inclusive=True,
        source="seed 004 Table 2 seawater velocity U_ST along +x (1, 2 m/s in cases 18, 19), eq. (38)",
    ),
    _f(
        "water",
        "normal_drag",
        1.21,
        "1",
        0.0,
        10.0,
        low_inclusive=True,
        source="seed 004 §3.2.2: C_D = 1.21 (Huston 1981)",
    ),
    _f(
        "water",
        "tangential_drag",
        0.062,
        "1",
        0.0,
        10.0,
        low_inclusive=True,
        source="seed 004 §3.2.2: C_F = 0.062 (Huston 1981) = seed 001 eq. (7): C_T = 0.062 for Re_T > 100.55",
    ),
    _f(
        "water",
        "tangential_drag_form",
        "diameter",
        "",
        kind="diameter|perimeter",
        source="MODEL CHOICE (docs/restraint.md section 6): 'diameter' = C_T rho d L v|v| / 2, seed 001 "
        "eqs. (4), (50), the form in which C_T = 0.062 is defined (referred to the diameter, like C_N in "
        "eq. (3)); 'perimeter' = pi rho D L C_F v|v| / 2, seed 004 eqs. (44)-(45) as printed (pi times it)",
    ),
    _f(
        "water",
        "added_mass",
        1.0,
        "1",
        0.0,
        10.0,
        low_inclusive=True,
        source="seed 004 §3.2.2: C_M = 1 (Huston 1981)",
    ),
    _f(
        "water",
        "added_mass_form",
        "lagrange",
        "",
        kind="lagrange|morison",
        source="seed 004 eq. (46) is Morison's -m_a n (n . a) ('morison'); the default 'lagrange' adds the "
        "velocity terms of a rotating added mass that make the energy of eq. (64) exact (docs/multibody.md)",
    ),
    # --- seabed
    _f(
        "seabed",
        "foundation_stiffness",
        5.0e6,
        "N m-3",
        0.0,
        1e12,
        source="seed 004 eq. (41): k_z = 5e6 N/m3 for soft soil (Ma et al. 2012)",
    ),
    # --- model switches (for checks; both on in every seed 004 case)
    _f(
        "model",
        "friction",
        True,
        "",
        kind="bool",
        source="seed 004 eq. (37): seabed friction on the anchor (on in every case of the seed; "
        "off only for checks)",
    ),
    _f(
        "model",
        "drag",
        True,
        "",
        kind="bool",
        source="seed 004 eqs. (39), (45)-(47), (62): water drag on anchor, elements and ship "
        "(on in every case of the seed)",
    ),
    # --- numerics
    _f(
        "numerics",
        "integrator",
        "dopri5",
        "",
        kind="|".join(METHOD_NAMES),
        source="seed 004 §4.1 integrates by fixed-step Runge-Kutta ('rk4'); the default 'dopri5' is adaptive "
        "Dormand-Prince 5(4) with the stop located on its dense output (a numerical choice); 'ros34pw2' is "
        "the Rosenbrock-W step for the stiff regularised friction (docs/multibody.md)",
    ),
    _f(
        "numerics",
        "rtol",
        1e-7,
        "1",
        0.0,
        1e-3,
        source="ASSUMPTION: relative tolerance of dopri5 (at most 1e-3: a looser run cannot close the "
        "energy balance that every run is checked against, 1e-3 of the initial energy)",
    ),
    _f(
        "numerics",
        "atol",
        1e-9,
        "1",
        0.0,
        1e-3,
        source="ASSUMPTION: absolute tolerance of dopri5 (m, rad, m/s, rad/s; at most 1e-3, as rtol)",
    ),
    _f(
        "numerics",
        "dt",
        0.002,
        "s",
        0.0,
        0.01,
        source=f"{_S41}: Delta t = 0.002 s (the rk4 step; dopri5's first trial step); at most 0.01 s: "
        "rk4 at 0.01 s already misses the energy balance every run is checked against on case 1 "
        "(1.1e-3 over 3 s, against 2.5e-6 at 0.002 s), and at 0.5 s it blows up",
    ),
    _f(
        "numerics",
        "t_max",
        120.0,
        "s",
        0.0,
        1e5,
        source="ASSUMPTION: time limit; a case not stopped by then ends with status time_limit",
    ),
    _f(
        "numerics",
        "record_interval",
        0.1,
        "s",
        0.0,
        1e4,
        source="output interval of the time series (not a model value)",
    ),
    _f(
        "numerics",
        "solver",
        "recursive",
        "",
        kind="recursive|kane",
        source="how Kane's equations (seed 004 eqs. (24)-(27)) are solved: 'kane' assembles A du/dt = f "
        "from the partial velocities and solves it by Cholesky (O(N^2) + O(N^3)); the default "
        "'recursive' solves the same equations by the O(N) tree recursion (docs/multibody.md)",
    ),
)

SECTIONS = tuple(dict.fromkeys(f.section for f in FIELDS))
_BY_PATH = {f.path: f for f in FIELDS}
#: fields renamed since an earlier release -> their name now: a case or ensemble that still uses an old
#: name is refused with one line saying what to rename (numerics.method became numerics.integrator with
#: issue 18, the name the mine's scenarios give the same setting; docs/restraint.md section 10)
RENAMED = {"numerics.method": "numerics.integrator"}


def refuse_renamed(paths) -> None:
    """ScenarioError naming the first of ``paths`` (``section.field``) that is an old name in RENAMED."""
    for path in paths:
        if path in RENAMED:
            section, _, old = path.partition(".")
            new = RENAMED[path].partition(".")[2]
            raise ScenarioError(
                f"{path} is now called {RENAMED[path]} (the mine's name for the same setting): "
                f"rename {old} to {new} in [{section}]"
            )


_DOC_WRITER = "mineburial.systems.restraint.model.write_field_table"


def field_table_block() -> str:
    """The field table of docs/restraint.md (section 10), between its markers."""
    return generated_block("case-fields", markdown_table(FIELDS, RULES), _DOC_WRITER)


def write_field_table(path="docs/restraint.md") -> None:
    """Regenerate the field table in ``path`` (run from the repository root after changing
    :data:`FIELDS`; tests/test_schema.py fails until then)."""
    path = pathlib.Path(path)
    text = path.read_text(encoding="utf-8")
    atomic_write_text(
        path, replace_generated(text, "case-fields", markdown_table(FIELDS, RULES), _DOC_WRITER)
    )


# ---------------------------------------------------------------------------
# the relations between fields: schema rules, per case and over sampled rows
# ---------------------------------------------------------------------------
_STAGES = (
    "cable.length",
    "cable.stage1_elements",
    "cable.stage1_element_length",
    "cable.stage3_elements",
    "cable.stage3_element_length",
    "cable.stage2_element_length",
)


def _stage2_rest(v: Mapping):
    """Cable length left to the second stage (seed 004 §4.2), scalar or per row."""
    return (
        v["cable.length"]
        - v["cable.stage1_elements"] * v["cable.stage1_element_length"]
        - v["cable.stage3_elements"] * v["cable.stage3_element_length"]
    )


def _whole_stage2(v: Mapping):
    rest = _stage2_rest(v)
    n2 = rest / v["cable.stage2_element_length"]
    return (rest > 0.0) & (np.abs(n2 - np.round(n2)) <= 1e-9 * np.maximum(1.0, n2)) & (np.round(n2) >= 1)


def _draught(v: Mapping):
    """Draught of the cuboid ship floating at its mass, m / (rho L B)."""
    return v["ship.mass"] / (v["water.density"] * v["ship.length"] * v["ship.beam"])


class _Values(dict):
    """One case's values with the derived quantities :func:`initial_configuration` reads."""

    @property
    def stage2_elements(self) -> int:
        return int(round(_stage2_rest(self) / self["cable.stage2_element_length"]))

    @property
    def ship_draught(self) -> float:
        return float(_draught(self))


def _water_depth(v: Mapping) -> float:
    """The ``d`` of seed 004 eq. (38) of one case's values (:attr:`RestraintCase.water_depth`)."""
    lay = initial_configuration(_Values(v))
    inner = slice(1, lay.kinds.size - 2)
    rise = float(np.sum(lay.lengths[inner] * np.sin(lay.angles[inner])))
    return lay.chain_height + rise + v["cable.rod_length"] - v["ship.joint_dz"]


def _keel_height(v: Mapping):
    """Height of the ship's keel above the seabed at t = 0 (:attr:`RestraintCase.water_depth`
    less the draught), scalar or per row; NaN where the initial layout itself is refused (its
    own error, :func:`initial_configuration`, then speaks when the case is built)."""
    arrays = {k: np.asarray(x) for k, x in v.items()}
    shape = np.broadcast_shapes(*(a.shape for a in arrays.values()))
    out = np.full(shape, np.nan)
    for idx in np.ndindex(shape):
        row = {k: (a[idx] if a.ndim else a).item() for k, a in arrays.items()}
        try:
            out[idx] = _water_depth(row) - float(_draught(row))
        except ScenarioError:
            pass
    return out if shape else float(out)


def _stages_message(v: Mapping) -> str:
    return (
        f"cable.length = {v['cable.length']:g} m must be the first stage "
        f"({v['cable.stage1_elements']} x {v['cable.stage1_element_length']:g} m) plus the third "
        f"({v['cable.stage3_elements']} x {v['cable.stage3_element_length']:g} m) plus a whole "
        f"number (>= 1) of second-stage elements of {v['cable.stage2_element_length']:g} m"
    )


def _sinks(part: str) -> Rule:
    return Rule(
        f"{part}.density > water.density (the {part} must sink)",
        (f"{part}.density", "water.density"),
        lambda v: v[f"{part}.density"] > v["water.density"],
        message=lambda v: (
            f"{part}.density = {v[f'{part}.density']:g} kg/m3 must exceed water.density = "
            f"{v['water.density']:g} kg/m3 (the {part} must sink)"
        ),
    )


def _keel_message(v: Mapping) -> str:
    depth = _water_depth(v)
    draught = float(_draught(v))
    keel = depth - draught
    return (
        f"ship.joint_dz = {v['ship.joint_dz']:g} m with cable.vertical = "
        f"{v['cable.vertical']:g} m and cable.rod_length = {v['cable.rod_length']:g} m puts "
        f"the water plane {depth:.3g} m above the seabed and the keel (draught "
        f"{draught:.3g} m) at {keel:.3g} m: the water depth must be > 0 and the ship's "
        f"keel above the seabed (ship.joint_dz < {keel + v['ship.joint_dz']:.4g} m)"
    )


#: the relations between a case's fields, declared once as schema rules (mineburial/schema.py):
#: checked in this order when a case is built (:meth:`RestraintCase._check_relations`) and,
#: vectorised, over an ensemble's sampled rows before any of them runs
#: (``mineburial.systems.restraint.ensemble.compute_chunk``). The keel rule needs the initial layout,
#: so it loops over rows (tens of microseconds each).
RULES: tuple[Rule, ...] = (
    Rule(
        "cable.length = stage 1 + stage 3 + a whole number (>= 1) of stage-2 elements (seed 004 §4.2)",
        _STAGES,
        _whole_stage2,
        message=_stages_message,
    ),
    Rule(
        "cable.horizontal < cable.length",
        ("cable.horizontal", "cable.length"),
        lambda v: v["cable.length"] - v["cable.horizontal"] > 0.0,
        message=lambda v: (
            f"cable.horizontal = {v['cable.horizontal']:g} m must be less than cable.length = "
            f"{v['cable.length']:g} m"
        ),
    ),
    Rule(
        "cable.vertical > cable.length - cable.horizontal (seed 004 eq. (30) has a solution)",
        ("cable.vertical", "cable.length", "cable.horizontal"),
        lambda v: v["cable.vertical"] > v["cable.length"] - v["cable.horizontal"],
        message=lambda v: (
            f"cable.vertical = {v['cable.vertical']:g} m must exceed cable.length - cable.horizontal = "
            f"{v['cable.length'] - v['cable.horizontal']:g} m: only then has the complete catenary of "
            f"seed 004 eq. (30) a solution"
        ),
    ),
    Rule(
        "the ship floats: its draught m / (rho L B) < ship.depth",
        ("ship.mass", "water.density", "ship.length", "ship.beam", "ship.depth"),
        lambda v: _draught(v) < v["ship.depth"],
        message=lambda v: (
            f"ship.mass = {v['ship.mass']:g} kg sinks the cuboid ship: its draught "
            f"{float(_draught(v)):.3g} m must be less than ship.depth = {v['ship.depth']:g} m, "
            f"i.e. the mass less than "
            f"{v['water.density'] * v['ship.length'] * v['ship.beam'] * v['ship.depth']:g} kg"
        ),
    ),
    Rule(
        "the anchor sinks: mass / (length width height) > water.density",
        ("anchor.mass", "anchor.length", "anchor.width", "anchor.height", "water.density"),
        lambda v: (
            v["anchor.mass"] / (v["anchor.length"] * v["anchor.width"] * v["anchor.height"])
            > v["water.density"]
        ),
        message=lambda v: (
            f"anchor.mass = {v['anchor.mass']:g} kg floats: the anchor's density "
            f"{v['anchor.mass'] / (v['anchor.length'] * v['anchor.width'] * v['anchor.height']):.4g} "
            f"kg/m3 (mass / (length width height)) must exceed water.density = "
            f"{v['water.density']:g} kg/m3"
        ),
    ),
    _sinks("chain"),
    _sinks("cable"),
    Rule(
        "seabed.foundation_stiffness > water.density water.gravity (seed 004 eqs. (41)-(42))",
        ("seabed.foundation_stiffness", "water.density", "water.gravity"),
        lambda v: v["seabed.foundation_stiffness"] > v["water.density"] * v["water.gravity"],
        message=lambda v: (
            f"seabed.foundation_stiffness = {v['seabed.foundation_stiffness']:g} N/m3 must exceed "
            f"rho g = {v['water.density'] * v['water.gravity']:g} N/m3 (the seabed must carry more "
            f"than the buoyancy it takes away, eqs. (41)-(42))"
        ),
    ),
    Rule(
        "the ship's keel starts above the seabed (the initial layout's water depth > the draught)",
        tuple(f.path for f in FIELDS),
        lambda v: np.logical_not(_keel_height(v) <= 0.0),  # NaN (layout refused): left to the layout
        message=_keel_message,
        field="ship.joint_dz",
    ),
)


@dataclass(frozen=True)
class RestraintCase:
    """A validated case of the restraining system (SI units). ``values`` maps
    ``section.field`` to its value; read one with ``case['anchor.mass']``. Constructing it
    checks every field and the relations between them (:meth:`_check_relations`)."""

    name: str
    description: str
    values: dict

    def __post_init__(self):
        object.__setattr__(self, "values", dict(self.values))  # never change the caller's dict
        refuse_renamed(self.values)
        for spec in FIELDS:
            if spec.path not in self.values:
                self.values[spec.path] = spec.default
            self.values[spec.path] = spec.check(self.values[spec.path])
        unknown = [k for k in self.values if k not in _BY_PATH]
        if unknown:
            raise ScenarioError(unknown_names_message("case field", unknown, _BY_PATH))
        self._check_relations()

    def __getitem__(self, path):
        return self.values[path]

    # -- derived quantities ---------------------------------------------------
    @property
    def stage2_elements(self) -> int:
        """Elements of the cable's second stage: what is left of the length (§4.2)."""
        return _Values(self.values).stage2_elements

    @property
    def ship_draught(self) -> float:
        """Draught of the cuboid ship floating at its mass (m / (rho L B))."""
        return float(_draught(self.values))

    @property
    def water_depth(self) -> float:
        """Height of the ship's water plane above the seabed at t = 0 (the ``d`` of eq. (38)):
        the chain's axis height plus the rise of every chain link and cable element of the
        initial layout (:func:`initial_configuration`) to the rod's lower end, plus the
        (vertical) rod, less ``ship.joint_dz``."""
        return _water_depth(self.values)

    def _check_relations(self):
        """The relations between the fields (:data:`RULES`), in order."""
        check_rules(RULES, self.values, _BY_PATH)

    # -- reading and writing --------------------------------------------------
    @classmethod
    def from_dict(cls, d: dict, name: str = "case") -> RestraintCase:
        if not isinstance(d, dict):
            raise ScenarioError("a restraint case must be a table of sections")
        d = dict(d)
        meta = d.pop("case", {})
        if not isinstance(meta, dict):
            raise ScenarioError("[case] must be a table with 'name' and 'description'")
        unknown_meta = [k for k in meta if k not in ("name", "description")]
        if unknown_meta:
            raise ScenarioError(unknown_names_message("key of [case]", unknown_meta, ("name", "description")))
        unknown = [s for s in d if s not in SECTIONS]
        if unknown:
            raise ScenarioError(unknown_names_message("section", unknown, SECTIONS + ("case",)))
        values = {}
        for section, table in d.items():
            if not isinstance(table, dict):
                raise ScenarioError(f"[{section}] must be a table of fields, not {table!r}")
            allowed = [f.name for f in FIELDS if f.section == section]
            refuse_renamed(f"{section}.{k}" for k in table)
            bad = [k for k in table if k not in allowed]
            if bad:
                raise ScenarioError(unknown_names_message(f"field of [{section}]", bad, allowed))
            for key, value in table.items():
                values[f"{section}.{key}"] = value
        for key in ("name", "description"):
            if key in meta and not isinstance(meta[key], str):
                raise ScenarioError(f"case.{key} = {meta[key]!r} must be text (a quoted string)")
        return cls(name=meta.get("name", name), description=meta.get("description", ""), values=values)

    @classmethod
    def from_toml(cls, path) -> RestraintCase:
        path = pathlib.Path(path)
        try:
            d = read_toml(path)
        except OSError as exc:
            raise ScenarioError(f"cannot read case file '{path}': {exc.strerror}") from None
        except tomllib.TOMLDecodeError as exc:
            raise ScenarioError(f"case file '{path}' is not valid TOML: {exc}") from None
        return cls.from_dict(d, name=path.stem)

    @classmethod
    def from_toml_string(cls, text: str, name: str = "case") -> RestraintCase:
        try:
            d = parse_toml(text)
        except tomllib.TOMLDecodeError as exc:
            raise ScenarioError(f"case is not valid TOML: {exc}") from None
        return cls.from_dict(d, name=name)

    def to_dict(self) -> dict:
        """The fully resolved case as nested sections (defaults filled)."""
        out: dict = {"case": {"name": self.name, "description": self.description}}
        for spec in FIELDS:
            out.setdefault(spec.section, {})[spec.name] = self.values[spec.path]
        return out

    def replace(self, **changes) -> RestraintCase:
        """A copy with ``section.field`` values changed (``replace(**{'anchor.mass': 5e4})``)."""
        values = dict(self.values)
        values.update(changes)
        return RestraintCase(self.name, self.description, values)


# ---------------------------------------------------------------------------
# Table 2 of seed 004
# ---------------------------------------------------------------------------

#: Table 2 columns: friction, anchor mass (t), chain radius (m), cable length, horizontal,
#: vertical (m), ship speed (m/s), ship mass (t), seawater velocity (m/s)
TABLE2 = (
    (0.3, 40, 0.0763, 152, 148, 6, 3, 500, 0),
    (0.5, 40, 0.0763, 152, 148, 6, 3, 500, 0),
    (0.7, 40, 0.0763, 152, 148, 6, 3, 500, 0),
    (0.3, 50, 0.0763, 152, 148, 6, 3, 500, 0),
    (0.3, 60, 0.0763, 152, 148, 6, 3, 500, 0),
    (0.3, 40, 0.0863, 152, 148, 6, 3, 500, 0),
    (0.3, 40, 0.0970, 152, 148, 6, 3, 500, 0),
    (0.3, 40, 0.0763, 172, 168, 6, 3, 500, 0),
    (0.3, 40, 0.0763, 192, 188, 6, 3, 500, 0),
    (0.3, 40, 0.0763, 152, 149, 6, 3, 500, 0),
    (0.3, 40, 0.0763, 152, 150, 6, 3, 500, 0),
    (0.3, 40, 0.0763, 152, 148, 8, 3, 500, 0),
    (0.3, 40, 0.0763, 152, 148, 10, 3, 500, 0),
    (0.3, 40, 0.0763, 152, 148, 6, 4, 500, 0),
    (0.3, 40, 0.0763, 152, 148, 6, 5, 500, 0),
    (0.3, 40, 0.0763, 152, 148, 6, 3, 750, 0),
    (0.3, 40, 0.0763, 152, 148, 6, 3, 1000, 0),
    (0.3, 40, 0.0763, 152, 148, 6, 3, 500, 1),
    (0.3, 40, 0.0763, 152, 148, 6, 3, 500, 2),
)
#: Table 3 of seed 004: stopping time (s) of each case (the case numbers of rows 4-19
#: were lost in the OCR; the rows are in order)
TABLE3 = (
    20.010,
    13.228,
    10.054,
    16.774,
    14.498,
    19.992,
    19.976,
    19.972,
    19.936,
    19.702,
    19.386,
    19.908,
    19.798,
    23.654,
    26.516,
    29.134,
    38.242,
    22.122,
    24.126,
)
#: the parameter each case changes against case 1 (Table 3's last column)
TABLE3_CHANGE = (
    "none",
    "seabed friction increased",
    "seabed friction increased",
    "anchor mass increased",
    "anchor mass increased",
    "anchor chain radius increased",
    "anchor chain radius increased",
    "overall cable length increased",
    "overall cable length increased",
    "horizontal projection of the cable changed",
    "horizontal projection of the cable changed",
    "cable vertical length changed",
    "cable vertical length changed",
    "initial ship speed increased",
    "initial ship speed increased",
    "ship displaced mass increased",
    "ship displaced mass increased",
    "current introduced",
    "current introduced",
)
#: anchor length by anchor mass (seed 004 §4.1)
ANCHOR_LENGTH = {40: 2.0, 50: 2.5, 60: 3.0}
N_CASES = len(TABLE2)
EXAMPLE_PREFIX = "restraint_case"


def table2_values(number: int) -> dict:
    """The ``section.field`` values that Table 2 sets for case ``number`` (1..19)."""
    if not 1 <= number <= N_CASES:
        raise ScenarioError(f"seed 004 Table 2 case = {number} is outside 1..{N_CASES}")
    mu, ma, rc, lc, xl, hl, v0, ms, u = TABLE2[number - 1]
    return {
        "anchor.friction": float(mu),
        "anchor.mass": ma * 1000.0,
        "anchor.length": ANCHOR_LENGTH[ma],
        "chain.radius": float(rc),
        "cable.length": float(lc),
        "cable.horizontal": float(xl),
        "cable.vertical": float(hl),
        "ship.speed": float(v0),
        "ship.mass": ms * 1000.0,
        "water.current_speed": float(u),
    }


def table2_case(number: int) -> RestraintCase:
    """Seed 004 Table 2 case ``number`` (1..19) with every other field at its default."""
    return RestraintCase(
        name=f"{EXAMPLE_PREFIX}{number}",
        description=f"seed 004 Table 2 case {number} ({TABLE3_CHANGE[number - 1]})",
        values=table2_values(number),
    )


def example_names() -> tuple[str, ...]:
    """``restraint_case1`` ... ``restraint_case19``."""
    return tuple(f"{EXAMPLE_PREFIX}{k}" for k in range(1, N_CASES + 1))


def example_text(name: str) -> str:
    """Case file of example ``name`` (``restraint_caseN``): every value with its source in
    seed 004, every value the seed does not print marked ASSUMPTION."""
    if name not in example_names():
        raise ScenarioError(unknown_name_message("restraint example", name, example_names()))
    number = int(name[len(EXAMPLE_PREFIX) :])
    case = table2_case(number)
    set_by_table = table2_values(number)
    lines = [
        f"# Seed 004 (Liu, Hearn, Chen et al., restraining system, Kane method), Table 2 case {number}:",
        f"# {TABLE3_CHANGE[number - 1]} (against case 1). "
        f"Seed 004 Table 3 stopping time: {TABLE3[number - 1]} s.",
        "# Run with: mineburial restrain THIS_FILE.toml -o OUT.nc   (SI units; docs/restraint.md)",
        "# Every value names its source; values seed 004 does not print are marked ASSUMPTION.",
        "",
        "[case]",
        f'name = "{case.name}"',
        f'description = "{case.description}"',
    ]
    section = None
    for spec in FIELDS:
        if spec.section != section:
            section = spec.section
            lines += ["", f"[{section}]"]
        value = case[spec.path]
        source = spec.source
        if spec.path == "anchor.length":
            source = f"seed 004 §4.1: {value:g} m for the {case['anchor.mass'] / 1000:g} t anchor"
        elif spec.path in set_by_table:
            source = f"seed 004 Table 2 case {number} (column: {spec.source})"
        unit = f" [{spec.unit}]" if spec.unit and spec.unit != "1" else ""
        lines.append(f"{spec.name} = {toml_value(value)}  #{unit} {source}")
    return "\n".join(lines) + "\n"


# ---------------------------------------------------------------------------
# initial configuration: seed 004 §3.1, eqs. (30)-(35)
# ---------------------------------------------------------------------------


def catenary_parameter(length: float, horizontal: float, vertical: float) -> tuple[float, float]:
    """``(b, a)`` of the complete catenary, seed 004 eqs. (30)-(31): ``b`` solves
    ``(cosh b - 1)(L_c - x_L) = h_L (sinh b - b)`` and ``a = T_h / w_c = (L_c - x_L) / (sinh b - b)``.

    The ratio ``(cosh b - 1) / (sinh b - b)`` falls from +inf (b -> 0) to 1 (b -> inf), so a
    root exists exactly when ``h_L > L_c - x_L`` (checked by :class:`RestraintCase`); it is
    bracketed and found by bisection on ``log b`` in closed form-free arithmetic.
    """
    slack = length - horizontal
    ratio = vertical / slack
    if not ratio > 1.0:
        raise ScenarioError(
            f"cable.vertical = {vertical:g} m must exceed cable.length - cable.horizontal = {slack:g} m"
        )

    def g(b):
        return (math.cosh(b) - 1.0) - ratio * (math.sinh(b) - b)

    lo, hi = 1e-6, 1.0
    while g(hi) > 0.0:
        hi *= 2.0
        if hi > 700.0:
            raise ScenarioError(f"the catenary of cable.vertical = {vertical:g} m has no solution")
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if g(mid) > 0.0:
            lo = mid
        else:
            hi = mid
        if hi - lo <= 1e-15 * hi:
            break
    b = 0.5 * (lo + hi)
    return b, slack / (math.sinh(b) - b)


def resting_height(radius: float, density: float, case: RestraintCase) -> float:
    """Height of the axis of a long horizontal cylinder resting on the elastic seabed:
    ``(k_z - rho g) A(z) = (rho_s - rho) g pi r^2`` (eqs. (41)-(42); A: the disc's area
    below the seabed), solved by bisection."""
    rho = case["water.density"]
    g = case["water.gravity"]
    need = (density - rho) * g * math.pi * radius**2 / (case["seabed.foundation_stiffness"] - rho * g)
    lo, hi = -radius, radius
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if segment_area_below(mid, radius) > need:
            lo = mid
        else:
            hi = mid
    return 0.5 * (lo + hi)


@dataclass(frozen=True)
class Layout:
    """Bodies of the system in seed 004's order (anchor, chain links, cable stages 1-3,
    rod, ship) with their lengths and radii, and the initial node points of the chain and
    cable (x, z of every pin from the anchor's to the rod's lower end)."""

    kinds: np.ndarray
    names: tuple
    lengths: np.ndarray
    radii: np.ndarray
    angles: np.ndarray
    nodes: np.ndarray
    catenary_b: float
    catenary_a: float
    chain_height: float
    cable_height: float


def initial_configuration(case: RestraintCase) -> Layout:
    """The initial layout of seed 004 §3.1: the anchor on the seabed, the chain straight
    along the seabed (angles 0), the cable continuing it on the seabed and then rising as
    the complete catenary of eqs. (30)-(34) to height ``h_L``, each element the chord
    between the catenary points at its end arc lengths (eq. (35), with its OCR-damaged
    denominator read as ``X_{k+1} - X_k``), the rod vertical.

    Chain and cable axes rest at their equilibrium sinkage in the elastic seabed
    (:func:`resting_height`); the first cable element steps down from the chain's axis
    height to the cable's (a few centimetres over 2 m).
    """
    zc = resting_height(case["chain.radius"], case["chain.density"], case)
    zr = resting_height(case["cable.radius"], case["cable.density"], case)
    b, a = catenary_parameter(case["cable.length"], case["cable.horizontal"], case["cable.vertical"])
    xs = a * b
    flat = case["cable.horizontal"] - xs
    first = case["cable.stage1_element_length"] if case["cable.stage1_elements"] else 0.0
    if flat < first:
        raise ScenarioError(
            f"cable.horizontal = {case['cable.horizontal']:g} m leaves {flat:.3g} m of cable on the seabed "
            f"before the catenary (x_s = {xs:.3g} m, eqs. (30)-(34)); at least one first-stage element "
            f"({first:g} m) must lie on the seabed"
        )
    n_links = case["chain.links"]
    ll = case["chain.link_length"]
    el = (
        [case["cable.stage1_element_length"]] * case["cable.stage1_elements"]
        + [case["cable.stage2_element_length"]] * case.stage2_elements
        + [case["cable.stage3_element_length"]] * case["cable.stage3_elements"]
    )
    x0 = 0.5 * case["anchor.length"]
    nodes = [(x0 + i * ll, zc) for i in range(n_links + 1)]
    xc0 = nodes[-1][0]
    arc = 0.0
    for length in el:
        arc += length
        if arc <= flat:
            nodes.append((xc0 + arc, zr))
        else:
            sk = arc - flat
            xk = a * math.asinh(sk / a)
            nodes.append((xc0 + flat + xk, zr + a * (math.cosh(xk / a) - 1.0)))
    nodes = np.array(nodes)
    d = np.diff(nodes, axis=0)
    angles = np.arctan2(d[:, 1], d[:, 0])
    angles[:n_links] = 0.0
    n_el = len(el)
    kinds = np.array([ANCHOR] + [ELEMENT] * (n_links + n_el) + [ROD, SHIP], dtype=np.int64)
    lengths = np.array(
        [case["anchor.length"]] + [ll] * n_links + el + [case["cable.rod_length"], case["ship.length"]]
    )
    radii = np.array([0.0] + [case["chain.radius"]] * n_links + [case["cable.radius"]] * (n_el + 1) + [0.0])
    names = (
        ("anchor",)
        + tuple(f"chain link {i + 1}" for i in range(n_links))
        + tuple(f"cable element {i + 1}" for i in range(n_el))
        + ("auxiliary rod", "ship")
    )
    angles = np.concatenate([[0.0], angles, [0.5 * math.pi, 0.0]])  # body 0 (anchor) .. N-1 (ship)
    return Layout(kinds, names, lengths, radii, angles, nodes, b, a, zc, zr)


# ---------------------------------------------------------------------------
# the multibody description and the run
# ---------------------------------------------------------------------------


@dataclass(frozen=True)
class System:
    """Everything a run needs: the case, its layout, the core's description, the jitted
    parameters and the initial state."""

    case: RestraintCase
    layout: Layout
    description: Any
    params: tuple
    y0: np.ndarray
    water_depth: float
    derived: dict


#: force parameters (kernels/restraint/forces.py ``P_*``) that are a field of the case as it is
def build_system(case: RestraintCase) -> System:
    """The multibody description of a case (a chain of N bodies is N bodies), the
    parameters of its forces and its initial state (ship at x = 0, speed ``ship.speed``,
    rod turning with it, everything else at rest, seed 004 §2.2 assumption (2))."""
    lay = initial_configuration(case)
    n = lay.kinds.size
    rho = case["water.density"]
    g = case["water.gravity"]
    ca = case["water.added_mass"]
    ma = case["anchor.mass"]
    la, wa, ha = case["anchor.length"], case["anchor.width"], case["anchor.height"]
    ms = case["ship.mass"]
    ls, bs, ds = case["ship.length"], case["ship.beam"], case["ship.depth"]
    draught = case.ship_draught
    d_s = 0.5 * ds - draught  # eq. (18): geometric centre to water plane
    parent = np.arange(-1, n - 1)
    jp = np.zeros((n, 2))
    jb = np.zeros((n, 2))
    mass = np.zeros((n, 3, 3))
    weight = np.zeros(n)
    buoy = np.zeros(n)
    diameter = 2.0 * lay.radii
    mass[0] = mb.rigid_mass_matrix(ma, ma / 12.0 * (la**2 + ha**2))  # eq. (18), k = 1
    weight[0] = ma * g
    buoy[0] = rho * la * wa * ha * g
    for k in range(1, n - 1):
        length = lay.lengths[k]
        r = lay.radii[k]
        dens = case["chain.density"] if k <= case["chain.links"] else case["cable.density"]
        m = dens * math.pi * r**2 * length
        if lay.kinds[k] == rf.ELEMENT:
            mass[k] = mb.segment_mass_matrix(m, length, r, ca, rho)
            buoy[k] = rho * math.pi * r**2 * length * g
        else:
            mass[k] = mb.segment_mass_matrix(m, length)
        weight[k] = m * g
        jb[k] = (-0.5 * length, 0.0)
        jp[k] = (0.5 * lay.lengths[k - 1], 0.0)
    jp[1] = (0.5 * la, lay.chain_height - 0.5 * ha)
    mass[n - 1] = mb.rigid_mass_matrix(ms, ms / 12.0 * (ls**2 + ds**2 + 12.0 * d_s**2))  # eq. (18), k = N
    jp[n - 1] = (0.5 * lay.lengths[n - 2], 0.0)
    jb[n - 1] = (case["ship.joint_dx"], case["ship.joint_dz"])
    root_pose = np.array([0.0, 0.5 * ha, 0.0])
    desc = mb.Description(parent, jp, jb, mass, np.array([1, 0, 0]), root_pose, names=lay.names)
    q0 = desc.coordinates(lay.angles[1:])
    pos, _ = body_states(q0, np.zeros_like(q0), desc.arrays())
    # shift x so that the ship's centroid starts at x = 0 (seed 004's origin o_0)
    root_pose[0] = -pos[n - 1, 0]
    desc = mb.Description(parent, jp, jb, mass, np.array([1, 0, 0]), root_pose, names=lay.names)
    q0 = desc.coordinates(lay.angles[1:])
    u0 = np.zeros_like(q0)
    # generalised speeds: q = (x_anchor, th_1 .. th_{N-1}); the rod is body N-2 (dof N-2)
    u0[n - 2] = -case["ship.speed"] / lay.lengths[n - 2]
    pos, vel = body_states(q0, u0, desc.arrays())
    z_water = float(pos[n - 1, 1])  # the ship floats at its equilibrium at t = 0
    volume = ms / rho
    gm_long = ls**3 * bs / (12.0 * volume) - 0.5 * draught  # eq. (57), z_B = T/2, z_G = T (assumption (8))
    wetted = ls * bs + 2.0 * (ls + bs) * draught
    perimeter = case["water.tangential_drag_form"] == "perimeter"
    derived = {
        "derived.water_depth": z_water,
        "derived.ship_wetted_area": wetted,
        "derived.waterplane_area": ls * bs,
        "derived.displaced_volume": volume,
        "derived.gm_longitudinal": gm_long,
        "code.resistance_half": 1.0 if case["ship.resistance_form"] == "printed" else 0.5,
        "code.friction": 1.0 if case["model.friction"] else 0.0,
        "code.drag": 1.0 if case["model.drag"] else 0.0,
        "code.morison": 1.0 if case["water.added_mass_form"] == "morison" else 0.0,
        "code.solver": rf.SOLVER_KANE if case["numerics.solver"] == "kane" else rf.SOLVER_RECURSIVE,
        "code.tangential_form": rf.TANGENTIAL_PERIMETER if perimeter else rf.TANGENTIAL_DIAMETER,
    }
    # the kernels' parameter vector by its declared names (rf.PARAM_NAMES): a field's value or a
    # derived quantity; a name that is neither is a KeyError here, never a silent zero
    p = np.array([derived[n] if n in derived else float(case[n]) for n in rf.PARAM_NAMES])
    contact_counts = np.zeros(rf.N_CONTACT_CODES, np.int64)
    params = (desc.arrays(), p, lay.kinds, lay.lengths.copy(), diameter, weight, buoy, contact_counts)
    y0 = np.concatenate([q0, u0, [0.0, 0.0]])
    derived = _derived(case, lay, z_water, wetted, gm_long)
    return System(case, lay, desc, params, y0, z_water, derived)


def _derived(case: RestraintCase, lay: Layout, z_water: float, wetted: float, gm_long: float) -> dict:
    """The values a run derives from its case (water depth, ship hydrostatics, catenary), reported
    with its result; the catenary's horizontal tension is a w of the submerged cable weight w."""
    return {
        "water_depth": z_water,
        "ship_draught": case.ship_draught,
        "ship_wetted_area": wetted,
        "ship_gm_longitudinal": gm_long,
        "catenary_b": lay.catenary_b,
        "catenary_a": lay.catenary_a,
        "catenary_horizontal_tension": lay.catenary_a
        * (case["cable.density"] - case["water.density"])
        * case["water.gravity"]
        * math.pi
        * case["cable.radius"] ** 2,
        "n_bodies": lay.kinds.size,
        "cable_stage2_elements": case.stage2_elements,
        "chain_axis_height": lay.chain_height,
        "cable_axis_height": lay.cable_height,
    }


#: the energy balance every run must close, relative to the energy the ship brings
#: (:meth:`RestraintResult.energy_closure`): a run that misses it is a numerical failure. The
#: default settings close it to ~1e-8 (benchmarks/results/restraint_table3.txt) and seed 004
#: §4.2 reports 0.5 %; 1e-3 passes every converged run (the seed's rk4 at 2 ms: ~1e-6) and
#: catches a blown-up or under-resolved one (rk4 at 0.5 s: 1e+247; rtol 0.9: 1.5e+2).
ENERGY_CLOSURE_LIMIT = 1e-3

#: names of the anchor's contact codes (kernels/restraint/forces.py CONTACT_*)
CONTACT_NAMES = ("on_seabed", "lifted", "friction_unsolvable")


@dataclass(frozen=True)
class RestraintResult:
    """A run: the records, the status, the stopping time (NaN-free: the end time when the
    ship did not stop) and the diagnostics of every record. ``failure`` says why a run is a
    numerical failure (empty otherwise); ``contact_counts`` counts the right-hand-side
    evaluations of the run in which the anchor's normal reaction came out <= 0 (``lifted``)
    or eq. (37) had no solution (``friction_unsolvable``): the friction was zero there."""

    system: System
    times: np.ndarray
    states: np.ndarray
    status: int
    status_name: str
    t_end: float
    stopping_time: float | None
    pos: np.ndarray
    vel: np.ndarray
    pin_force: np.ndarray
    scalars: np.ndarray
    failure: str = ""
    contact_counts: tuple = (0, 0, 0)

    @property
    def energy(self) -> dict:
        """Energy terms of eqs. (63)-(69) at every record, J: ``kinetic`` (E^K, eq. (64),
        with the added mass), ``gravity`` (E^G, eq. (65), with buoyancy), ``hydrostatic``
        (E^E, eq. (66)), ``foundation`` (elastic energy of the seabed, the W^S of eq. (68)
        with the opposite sign), ``friction_dissipated`` (-W^F, eq. (67)),
        ``water_dissipated`` (-W^W, eq. (69)) and ``total`` (their sum: constant)."""
        nd = self.system.description.n_dof
        ek, eg, ee, es = (self.scalars[:, i] for i in range(4))
        dfric = -self.states[:, 2 * nd]
        dwater = -self.states[:, 2 * nd + 1]
        total = ek + eg + ee + es + dfric + dwater
        return {
            "kinetic": ek,
            "gravity": eg,
            "hydrostatic": ee,
            "foundation": es,
            "friction_dissipated": dfric,
            "water_dissipated": dwater,
            "total": total,
        }

    def energy_closure(self) -> float:
        """max |E(t) - E(0)| / (E^K(0) + E^E(0)): the energy balance of seed 004 §4.2,
        measured against the energy the ship brings (its initial kinetic energy; the
        gravitational potential, counted from the seabed, would only inflate the
        denominator). inf where a record is not finite or there is none."""
        if self.times.size == 0:
            return math.inf
        e = self.energy["total"]
        ref = self.energy["kinetic"][0] + abs(self.energy["hydrostatic"][0])
        if not (np.all(np.isfinite(e)) and math.isfinite(ref) and ref > 0.0):
            return math.inf
        return float(np.max(np.abs(e - e[0])) / ref)

    @property
    def contact_events(self) -> dict:
        """The counts of :attr:`contact_counts` by name (``lifted``, ``friction_unsolvable``)."""
        return dict(zip(CONTACT_NAMES[1:], (int(c) for c in self.contact_counts[1:])))


def _check_record_memory(case: RestraintCase, dt_rec: float, system: System, name: str) -> None:
    """ScenarioError naming ``name`` when the records of a run (states and the diagnostics
    computed from them) would take more than half of the available memory (the one memory
    check of :mod:`mineburial.resources`, as for the drop's trajectory)."""
    n = system.layout.kinds.size
    # per record: the state, and positions, velocities, pin forces and scalars of every body,
    # held twice while the dataset is built
    values = system.y0.size + 2 * (8 * n + 7)
    t_max = case["numerics.t_max"]
    refusal = memory_refusal(
        record_bytes(t_max, dt_rec, values),
        f"{name} = {dt_rec:g} s ({t_max / dt_rec:.3g} states over numerics.t_max = {t_max:g} s)",
        f"give a larger {name}",
        share=0.5,
    )
    if refusal is not None:
        raise ScenarioError(refusal)


def _last_finite_record(*arrays) -> int:
    """Number of leading records that are finite in every array (records along axis 0)."""
    n = arrays[0].shape[0]
    ok = np.ones(n, bool)
    for a in arrays:
        ok &= np.isfinite(a.reshape(n, -1)).all(axis=1)
    bad = np.flatnonzero(~ok)
    return n if bad.size == 0 else int(bad[0])


def simulate(case: RestraintCase, record_interval: float | None = None) -> RestraintResult:
    """Run a case until the ship's surge speed first reaches zero (the stopping time,
    located on the integrator's continuous extension) or ``numerics.t_max``.

    After the run, every record must be finite and the energy balance must close within
    :data:`ENERGY_CLOSURE_LIMIT`; otherwise the status is ``numerical_failure`` (records cut
    at the first non-finite one), with the reason in ``failure``."""
    system = build_system(case)
    if record_interval is None:
        dt_rec, name = case["numerics.record_interval"], "numerics.record_interval"
    else:
        dt_rec, name = float(record_interval), "record_interval"
        if not (math.isfinite(dt_rec) and dt_rec > 0.0):
            raise ScenarioError(f"record_interval = {record_interval!r} s must be a finite number > 0")
    _check_record_memory(case, dt_rec, system, name)
    counts = system.params[7]
    counts[:] = 0
    res = mb.integrate(
        rf.RESTRAINT,
        system.y0,
        0.0,
        case["numerics.t_max"],
        system.params,
        method=case["numerics.integrator"],
        dt=case["numerics.dt"],
        rtol=case["numerics.rtol"],
        atol=case["numerics.atol"],
        record_dt=dt_rec,
        # the stiffness (regularised friction, seabed contact) is in the speeds u of y = (q, u, W^F, W^W)
        jacobian_columns=np.arange(system.description.n_dof, 2 * system.description.n_dof),
    )
    contact_counts = tuple(int(c) for c in counts)
    pos, vel, hf, scal = rf.record_diagnostics(np.ascontiguousarray(res.states), system.params)
    counts[:] = 0
    status, t_end, failure = res.status, res.t_stop, ""
    if status == NUMERICAL_FAILURE:
        failure = (
            "the integrator failed (a non-finite state or rate, a step-size underflow or the step budget)"
        )
    times, states = res.times, res.states
    keep = _last_finite_record(times, states, pos, vel, hf, scal)
    if keep < times.size:
        times, states, pos, vel, hf, scal = (a[:keep] for a in (times, states, pos, vel, hf, scal))
        status = NUMERICAL_FAILURE
        t_end = float(times[-1]) if keep else 0.0
        failure = "a recorded value is not finite; the records end at the last finite one"
    result = RestraintResult(
        system,
        times,
        states,
        status,
        STATUS_NAMES[status],
        t_end,
        None,
        pos,
        vel,
        hf,
        scal,
        failure,
        contact_counts,
    )
    if status != NUMERICAL_FAILURE and times.size:
        closure = result.energy_closure()
        if not closure <= ENERGY_CLOSURE_LIMIT:
            status = NUMERICAL_FAILURE
            failure = (
                f"the energy balance does not close: {closure:.2g} of the initial energy "
                f"(limit {ENERGY_CLOSURE_LIMIT:g}); the run is not converged "
                f"(numerics.integrator, dt, rtol, atol)"
            )
    return dataclasses.replace(
        result,
        status=status,
        status_name=STATUS_NAMES[status],
        stopping_time=t_end if status == STOPPED else None,
        failure=failure,
    )


# ---------------------------------------------------------------------------
# output: CF NetCDF
# ---------------------------------------------------------------------------


def to_dataset(result: RestraintResult):
    """The time series of a run as a CF-1.11 dataset: every body's centroid position,
    attitude and velocities, the pin forces (eq. (52)), the anchor's normal and friction
    forces (eq. (37)), the energy terms of eqs. (64)-(69); the resolved case and the
    mineburial version in the attributes. Every variable's metadata comes from the
    registry's ``restraint_run`` family (:mod:`mineburial.io.variables`), the file through
    :func:`mineburial.io.dataset.build`. Write it with
    :func:`mineburial.io.netcdf.write_netcdf` (atomic)."""
    sysm = result.system
    lay = sysm.layout
    case = sysm.case
    n = lay.kinds.size
    data = _time_series(result)
    status, status_name, failure = result.status, result.status_name, result.failure
    stopping_time = result.stopping_time
    bad = [name for name, v in data.items() if not np.all(np.isfinite(v[0] if isinstance(v, tuple) else v))]
    if bad:  # never a silent NaN: a non-finite value makes the run a numerical failure
        status = kmb.NUMERICAL_FAILURE
        status_name = kmb.STATUS_NAMES[status]
        failure = f"non-finite values in {', '.join(bad)}"
        stopping_time = None
    data["status"] = (
        np.int8(status),
        {"flag_values": kmb.STATUS_CODES, "flag_meanings": kmb.STATUS_MEANINGS},
    )
    if stopping_time is not None:
        data["stopping_time"] = float(stopping_time)
    data.update({name: float(sysm.derived[name]) for name in RESTRAINT_DERIVED})
    coords = {
        "elapsed_time": result.times,
        "body": np.arange(1, n + 1),
        "body_name": np.array(lay.names, dtype=object),
        "body_kind": np.array(["anchor", "element", "rod", "ship"], dtype=object)[lay.kinds],
        "body_length": lay.lengths,
    }
    attrs = {
        "title": f"mineburial restraining system (seed 004): {case.name}",
        "summary": "Planar Kane-method multibody model of a powerless ship stopped by an overhead "
        "restraining system (Liu, Hearn, Chen et al.): ship, auxiliary rod, restraining cable, "
        "anchor chain and a gravity anchor dragged over the seabed; docs/restraint.md.",
        "status": status_name,
        "status_description": kmb.STATUS_DESCRIPTIONS[status],
        "failure": failure,
        "anchor_lifted_evaluations": int(result.contact_counts[1]),
        "anchor_friction_unsolvable_evaluations": int(result.contact_counts[2]),
        "end_time": float(result.t_end),
        "case": json.dumps(case.to_dict()),
        "energy_closure": result.energy_closure(),
        "n_bodies": int(sysm.derived["n_bodies"]),
        "cable_stage2_elements": int(sysm.derived["cable_stage2_elements"]),
    }
    if stopping_time is not None:
        attrs["stopping_time"] = float(stopping_time)
    return build(data, coords, attrs, kind="restraint_run")


def _time_series(result: RestraintResult) -> dict:
    """The time series of a run by output name: every body's centroid position, attitude and
    velocities, the pin forces (eq. (52)), the ship's and the anchor's motion, the anchor's
    normal and friction forces (eq. (37)) and contact code, the energy terms of eqs. (64)-(69)."""
    ship, e = result.system.layout.kinds.size - 1, result.energy
    pos, vel, pin = result.pos, result.vel, result.pin_force
    data = {
        **{name: pos[:, :, k] for k, name in enumerate(("x", "z", "theta"))},
        **{name: vel[:, :, k] for k, name in enumerate(("vx", "vz", "omega"))},
        "pin_force_x": pin[:, :, 0],
        "pin_force_z": pin[:, :, 1],
        "pin_tension": np.hypot(pin[:, :, 0], pin[:, :, 1]),
        "ship_x": pos[:, ship, 0],
        "ship_speed": vel[:, ship, 0],
        "ship_heave": pos[:, ship, 1] - result.system.water_depth,
        "ship_pitch": pos[:, ship, 2],
        "anchor_x": pos[:, 0, 0],
        "anchor_speed": vel[:, 0, 0],
        "anchor_normal_force": result.scalars[:, 4],
        "anchor_friction": result.scalars[:, 5],
        "anchor_contact": (result.scalars[:, 6].astype(np.int8), _flags(CONTACT_NAMES)),
        "kinetic_energy": e["kinetic"],
        "gravitational_energy": e["gravity"],
        "hydrostatic_energy": e["hydrostatic"],
        "foundation_energy": e["foundation"],
        "friction_dissipation": e["friction_dissipated"],
        "water_dissipation": e["water_dissipated"],
        "total_energy": e["total"],
    }
    return data


def _flags(names) -> dict:
    """CF flag attributes of the codes 0..len(names)-1."""
    return {"flag_values": np.arange(len(names), dtype=np.int8), "flag_meanings": " ".join(names)}


def run_case_file(path, output) -> RestraintResult:
    """``mineburial restrain``: read, run, write atomically; returns the result. The output
    path is checked (not the case file, a regular file or nothing) and locked before the
    run (:class:`~mineburial.ensembles.store.OutputRun`)."""
    case = RestraintCase.from_toml(path)
    with OutputRun(output, (path,), "-o/--output") as out:
        result = simulate(case)
        out.commit(to_dataset(result))
    events = result.contact_events
    if any(events.values()):
        print(
            f"mineburial: warning: the anchor's friction was set to zero in "
            f"{events['lifted']} right-hand-side evaluations where the chain lifted it and "
            f"{events['friction_unsolvable']} where eq. (37) had no solution (docs/restraint.md)",
            file=sys.stderr,
        )
    if result.failure:
        print(f"mineburial: warning: {result.failure}", file=sys.stderr)
    return result
