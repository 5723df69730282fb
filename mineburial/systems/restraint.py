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
import math
import pathlib
from dataclasses import dataclass
from typing import Any

import numpy as np

try:  # Python >= 3.11
    import tomllib
except ModuleNotFoundError:  # pragma: no cover - Python 3.10
    import tomli as tomllib

from mineburial.sediment_profiles import ScenarioError, unknown_name_message, unknown_names_message

# ---------------------------------------------------------------------------
# the case: fields, units, ranges, sources
# ---------------------------------------------------------------------------


@dataclass(frozen=True)
class FieldSpec:
    """One field of a case file: its default, unit, allowed range and source."""

    section: str
    name: str
    default: Any
    unit: str
    lo: float | None = None
    hi: float | None = None
    lo_open: bool = True
    hi_open: bool = False
    kind: str = "float"  # float, int, bool, or the allowed strings joined by '|'
    source: str = ""
    assumption: bool = False

    @property
    def path(self) -> str:
        return f"{self.section}.{self.name}"

    def range_text(self) -> str:
        if self.kind == "bool":
            return "true or false"
        if "|" in self.kind:
            return " or ".join(repr(v) for v in self.kind.split("|"))
        lo = "-inf" if self.lo is None else f"{self.lo:g}"
        hi = "inf" if self.hi is None else f"{self.hi:g}"
        left = "(" if (self.lo is None or self.lo_open) else "["
        right = ")" if (self.hi is None or self.hi_open) else "]"
        unit = f" {self.unit}" if self.unit and self.unit != "1" else ""
        return f"{left}{lo}, {hi}{right}{unit}"

    def check(self, value):
        """The value converted to the field's type; ScenarioError naming the field, the
        value and the allowed range otherwise."""
        unit = f" {self.unit}" if self.unit and self.unit != "1" else ""
        if self.kind == "bool":
            if not isinstance(value, bool):
                raise ScenarioError(f"{self.path} = {value!r} must be true or false")
            return value
        if "|" in self.kind:
            allowed = self.kind.split("|")
            if value not in allowed:
                raise ScenarioError(unknown_name_message(self.path, value, allowed))
            return value
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            raise ScenarioError(f"{self.path} = {value!r} is not a number; allowed range {self.range_text()}")
        if self.kind == "int":
            if float(value) != int(value):
                raise ScenarioError(f"{self.path} = {value!r} must be a whole number in {self.range_text()}")
            value = int(value)
        else:
            value = float(value)
        ok = math.isfinite(value)
        if ok and self.lo is not None:
            ok = value > self.lo if self.lo_open else value >= self.lo
        if ok and self.hi is not None:
            ok = value < self.hi if self.hi_open else value <= self.hi
        if not ok:
            raise ScenarioError(
                f"{self.path} = {value:g}{unit} is outside the allowed range {self.range_text()}"
            )
        return value


def _f(section, name, default, unit, lo=None, hi=None, source="", assumption=False, **kw):
    return FieldSpec(section, name, default, unit, lo, hi, source=source, assumption=assumption, **kw)


_S41 = "seed 004 §4.1"
#: every field of a case file, in file order
FIELDS: tuple[FieldSpec, ...] = (
    # --- gravity anchor (body 1)
    _f("anchor", "mass", 40000.0, "kg", 0.0, 1e7, source="seed 004 Table 2 (40 t; 50 t and 60 t in cases 4, 5)"),
    _f("anchor", "length", 2.0, "m", 0.0, 100.0, source=f"{_S41}: 2.0, 2.5, 3.0 m for 40, 50, 60 t"),
    _f("anchor", "width", 4.0, "m", 0.0, 100.0, source=f"{_S41}: width 4.0 m"),
    _f("anchor", "height", 2.1, "m", 0.0, 100.0, source=f"{_S41}: height 2.1 m"),
    _f("anchor", "friction", 0.3, "1", 0.0, 2.0, source="seed 004 Table 2 (0.3; 0.5, 0.7 in cases 2, 3)", lo_open=False),
    _f("anchor", "drag_coefficient", 1.05, "1", 0.0, 10.0, source="seed 004 §3.2.1 after eq. (39) (Saleh 2002)", lo_open=False),
    _f(
        "anchor",
        "friction_velocity_scale",
        1.0e-3,
        "m s-1",
        0.0,
        1.0,
        source="ASSUMPTION: the sign of eq. (37) smoothed as tanh(v / scale); 1 mm/s = 0.03 % of the ship "
        "speed (seed 004 switches stick/slip on the previous step's tension instead)",
        assumption=True,
    ),
    # --- anchor chain (bodies 2..16)
    _f("chain", "links", 15, "1", 1, 1000, kind="int", lo_open=False, source=f"{_S41}: 15 links, 1 m each, 15 m"),
    _f("chain", "link_length", 1.0, "m", 0.0, 100.0, source=f"{_S41}: each link 1 m"),
    _f("chain", "radius", 0.0763, "m", 0.0, 1.0, source="seed 004 Tables 1, 2: equivalent radius R_CE (0.0863, 0.0970 in cases 6, 7)"),
    _f("chain", "density", 7850.0, "kg m-3", 0.0, 30000.0, source=f"{_S41}: steel 7850 kg/m3"),
    # --- restraining cable (three stages) and auxiliary rod
    _f("cable", "length", 152.0, "m", 0.0, 10000.0, source="seed 004 Table 2 (152 m; 172, 192 m in cases 8, 9)"),
    _f("cable", "horizontal", 148.0, "m", 0.0, 10000.0, source="seed 004 Table 2 'cable horizontal component' x_L (149, 150 m in cases 10, 11)"),
    _f("cable", "vertical", 6.0, "m", 0.0, 1000.0, source="seed 004 Table 2 'cable vertical component' h_L (8, 10 m in cases 12, 13)"),
    _f("cable", "radius", 0.0237, "m", 0.0, 1.0, source=f"{_S41}: R_RE = sqrt(2 m_RU / (pi rho_s)) = 0.0237 m"),
    _f("cable", "density", 7850.0, "kg m-3", 0.0, 30000.0, source=f"{_S41}: steel (R_RE is defined with rho_s)"),
    _f("cable", "stage1_elements", 3, "1", 0, 10000, kind="int", lo_open=False, source="seed 004 §4.2: elements 17 to 19 (3 x 2 m)"),
    _f("cable", "stage1_element_length", 2.0, "m", 0.0, 1000.0, source=f"{_S41}: 2 m"),
    _f("cable", "stage2_element_length", 10.0, "m", 0.0, 1000.0, source=f"{_S41}: 10 m (12, 14, 16 elements for 152, 172, 192 m, §4.2)"),
    _f("cable", "stage3_elements", 13, "1", 0, 10000, kind="int", lo_open=False, source="seed 004 §4.2: elements 32 to 44 (13 x 2 m)"),
    _f("cable", "stage3_element_length", 2.0, "m", 0.0, 1000.0, source=f"{_S41}: 2 m"),
    _f("cable", "rod_length", 1.0, "m", 0.0, 100.0, source=f"{_S41}: auxiliary rod 1 m (OCR 'Im'), same material and radius as the cable"),
    # --- ship (body N)
    _f("ship", "mass", 500000.0, "kg", 0.0, 1e10, source="seed 004 Table 2 (500 t; 750, 1000 t in cases 16, 17)"),
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
        lo_open=False,
        source="ASSUMPTION: d_x (seed 004 §4.1, Figure 2) is not printed; 0 = the rod hangs from the "
        "ship's midship section (the pitch it drives is negligible, GM_L ~ 200 m)",
        assumption=True,
    ),
    _f(
        "ship",
        "joint_dz",
        1.0,
        "m",
        -500.0,
        500.0,
        lo_open=False,
        source="ASSUMPTION: d_z is not printed; = rod length, so that the rod is just above the free "
        "surface (§3.2.2) and the water depth equals the cable's vertical component (§4.3.3)",
        assumption=True,
    ),
    _f("ship", "roughness", 150e-6, "m", 0.0, 1.0, lo_open=False, source="seed 004 eq. (61): k_s = 150e-6 m (Molland et al. 2011)"),
    _f(
        "ship",
        "resistance_form",
        "printed",
        "",
        kind="printed|ittc",
        source="seed 004 eq. (62) as printed, (C_f + C_sf) rho S_W v|v| ('printed'); 'ittc' adds the "
        "textbook 1/2 (Molland et al. 2011)",
    ),
    # --- water
    _f("water", "density", 1025.0, "kg m-3", 0.0, 2000.0, source=f"{_S41}: 1025 kg/m3"),
    _f("water", "kinematic_viscosity", 1.05e-6, "m2 s-1", 0.0, 1.0, source=f"{_S41}: 1.05e-6 m2/s"),
    _f("water", "gravity", 9.81, "m s-2", 0.0, 100.0, source=f"{_S41}: 9.81 m/s2"),
    _f("water", "current_speed", 0.0, "m s-1", -10.0, 10.0, lo_open=False, source="seed 004 Table 2 seawater velocity U_ST along +x (1, 2 m/s in cases 18, 19), eq. (38)"),
    _f("water", "normal_drag", 1.21, "1", 0.0, 10.0, lo_open=False, source="seed 004 §3.2.2: C_D = 1.21 (Huston 1981)"),
    _f("water", "tangential_drag", 0.062, "1", 0.0, 10.0, lo_open=False, source="seed 004 §3.2.2: C_F = 0.062 (Huston 1981)"),
    _f("water", "added_mass", 1.0, "1", 0.0, 10.0, lo_open=False, source="seed 004 §3.2.2: C_M = 1 (Huston 1981)"),
    # --- seabed
    _f("seabed", "foundation_stiffness", 5.0e6, "N m-3", 0.0, 1e12, source="seed 004 eq. (41): k_z = 5e6 N/m3 for soft soil (Ma et al. 2012)"),
    # --- model switches (for checks; both on in every seed 004 case)
    _f("model", "friction", True, "", kind="bool", source="seabed friction on the anchor, eq. (37)"),
    _f("model", "drag", True, "", kind="bool", source="water drag: ship eq. (62), anchor eq. (39), elements eqs. (45)-(47)"),
    # --- numerics
    _f("numerics", "method", "dopri5", "", kind="dopri5|rk4", source="adaptive Dormand-Prince 5(4) with dense output; 'rk4': seed 004's fixed-step Runge-Kutta"),
    _f("numerics", "rtol", 1e-7, "1", 0.0, 1.0, source="ASSUMPTION: relative tolerance of dopri5", assumption=True),
    _f("numerics", "atol", 1e-9, "1", 0.0, 1.0, source="ASSUMPTION: absolute tolerance of dopri5 (m, rad, m/s, rad/s)", assumption=True),
    _f("numerics", "dt", 0.002, "s", 0.0, 1.0, source=f"{_S41}: Delta t = 0.002 s (the rk4 step; dopri5's first trial step)"),
    _f("numerics", "t_max", 120.0, "s", 0.0, 1e5, source="ASSUMPTION: time limit; a case not stopped by then ends with status time_limit", assumption=True),
    _f("numerics", "record_interval", 0.1, "s", 0.0, 1e4, source="output interval of the time series (not a model value)"),
)

SECTIONS = tuple(dict.fromkeys(f.section for f in FIELDS))
_BY_PATH = {f.path: f for f in FIELDS}


@dataclass(frozen=True)
class RestraintCase:
    """A validated case of the restraining system (SI units). ``values`` maps
    ``section.field`` to its value; read one with ``case['anchor.mass']`` or
    ``case.anchor_mass``. Constructing it checks every field and the relations between
    them (:meth:`_check_relations`)."""

    name: str
    description: str
    values: dict

    def __post_init__(self):
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

    def __getattr__(self, name):
        if "_" in name:
            section, _, key = name.partition("_")
            path = f"{section}.{key}"
            if path in _BY_PATH:
                return self.values[path]
        raise AttributeError(name)

    # -- derived quantities ---------------------------------------------------
    @property
    def stage2_elements(self) -> int:
        """Elements of the cable's second stage: what is left of the length (§4.2)."""
        rest = (
            self["cable.length"]
            - self["cable.stage1_elements"] * self["cable.stage1_element_length"]
            - self["cable.stage3_elements"] * self["cable.stage3_element_length"]
        )
        return int(round(rest / self["cable.stage2_element_length"]))

    @property
    def ship_draught(self) -> float:
        """Draught of the cuboid ship floating at its mass (m / (rho L B))."""
        return self["ship.mass"] / (self["water.density"] * self["ship.length"] * self["ship.beam"])

    def _check_relations(self):
        rest = (
            self["cable.length"]
            - self["cable.stage1_elements"] * self["cable.stage1_element_length"]
            - self["cable.stage3_elements"] * self["cable.stage3_element_length"]
        )
        n2 = rest / self["cable.stage2_element_length"]
        if rest <= 0.0 or abs(n2 - round(n2)) > 1e-9 * max(1.0, n2) or round(n2) < 1:
            raise ScenarioError(
                f"cable.length = {self['cable.length']:g} m must be the first stage "
                f"({self['cable.stage1_elements']} x {self['cable.stage1_element_length']:g} m) plus the third "
                f"({self['cable.stage3_elements']} x {self['cable.stage3_element_length']:g} m) plus a whole "
                f"number (>= 1) of second-stage elements of {self['cable.stage2_element_length']:g} m"
            )
        slack = self["cable.length"] - self["cable.horizontal"]
        if slack <= 0.0:
            raise ScenarioError(
                f"cable.horizontal = {self['cable.horizontal']:g} m must be less than cable.length = "
                f"{self['cable.length']:g} m"
            )
        if self["cable.vertical"] <= slack:
            raise ScenarioError(
                f"cable.vertical = {self['cable.vertical']:g} m must exceed cable.length - cable.horizontal = "
                f"{slack:g} m: only then has the complete catenary of seed 004 eq. (30) a solution"
            )
        if self.ship_draught >= self["ship.depth"]:
            raise ScenarioError(
                f"ship.mass = {self['ship.mass']:g} kg sinks the cuboid ship: its draught "
                f"{self.ship_draught:.3g} m must be less than ship.depth = {self['ship.depth']:g} m, i.e. the mass "
                f"less than {self['water.density'] * self['ship.length'] * self['ship.beam'] * self['ship.depth']:g} kg"
            )
        rho_anchor = self["anchor.mass"] / (self["anchor.length"] * self["anchor.width"] * self["anchor.height"])
        if rho_anchor <= self["water.density"]:
            raise ScenarioError(
                f"anchor.mass = {self['anchor.mass']:g} kg floats: the anchor's density {rho_anchor:.4g} kg/m3 "
                f"(mass / (length width height)) must exceed water.density = {self['water.density']:g} kg/m3"
            )
        for part in ("chain", "cable"):
            if self[f"{part}.density"] <= self["water.density"]:
                raise ScenarioError(
                    f"{part}.density = {self[f'{part}.density']:g} kg/m3 must exceed water.density = "
                    f"{self['water.density']:g} kg/m3 (the {part} must sink)"
                )
        if self["seabed.foundation_stiffness"] <= self["water.density"] * self["water.gravity"]:
            raise ScenarioError(
                f"seabed.foundation_stiffness = {self['seabed.foundation_stiffness']:g} N/m3 must exceed "
                f"rho g = {self['water.density'] * self['water.gravity']:g} N/m3 (the seabed must carry more than "
                f"the buoyancy it takes away, eqs. (41)-(42))"
            )

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
            bad = [k for k in table if k not in allowed]
            if bad:
                raise ScenarioError(unknown_names_message(f"field of [{section}]", bad, allowed))
            for key, value in table.items():
                values[f"{section}.{key}"] = value
        return cls(
            name=str(meta.get("name", name)), description=str(meta.get("description", "")), values=values
        )

    @classmethod
    def from_toml(cls, path) -> RestraintCase:
        path = pathlib.Path(path)
        try:
            with open(path, "rb") as fh:
                d = tomllib.load(fh)
        except OSError as exc:
            raise ScenarioError(f"cannot read case file '{path}': {exc.strerror}") from None
        except tomllib.TOMLDecodeError as exc:
            raise ScenarioError(f"case file '{path}' is not valid TOML: {exc}") from None
        return cls.from_dict(d, name=path.stem)

    @classmethod
    def from_toml_string(cls, text: str, name: str = "case") -> RestraintCase:
        try:
            d = tomllib.loads(text)
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


def _toml_value(value) -> str:
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, str):
        return f'"{value}"'
    if isinstance(value, int):
        return str(value)
    return repr(float(value))


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
        f"# {TABLE3_CHANGE[number - 1]} (against case 1). Seed 004 Table 3 stopping time: {TABLE3[number - 1]} s.",
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
        if spec.path in set_by_table:
            source = f"seed 004 Table 2 case {number}; {spec.source}"
        unit = f" [{spec.unit}]" if spec.unit and spec.unit != "1" else ""
        lines.append(f"{spec.name} = {_toml_value(value)}  #{unit} {source}")
    return "\n".join(lines) + "\n"
