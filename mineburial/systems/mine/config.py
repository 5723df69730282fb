"""Scenario configuration: frozen dataclasses, TOML loading, validation, packing for the kernels.

A scenario file (TOML, SI units, angles named ``*_deg``) has the sections
``[mine]``, ``[release]``, ``[environment]`` (with ``[environment.current]``),
``[sediment]`` and ``[numerics]``; ``docs/scenario.md`` documents every field.

* :class:`Scenario` (and its parts :class:`Mine`, :class:`Release`, :class:`Environment`,
  :class:`Current`, :class:`Sediment`, :class:`Numerics`) are frozen dataclasses that
  validate themselves on construction, so ``dataclasses.replace`` re-validates.
  Numeric fields are Python floats, vectors are tuples of floats.
* :meth:`Scenario.from_dict` / :meth:`Scenario.from_toml` read a scenario;
  :meth:`Scenario.to_dict` writes it back fully resolved (defaults filled, a catalogue
  class or a core file expanded into its values), so ``from_dict(to_dict())`` is equal.
* Every field is declared once, in :data:`mineburial.systems.mine.scenario_fields.TABLE` (the schema
  mechanism is :mod:`mineburial.schema`); :data:`SCHEMA` holds it by path, :data:`RULES`
  the relations between fields, checked per scenario and over packed rows alike.
  :data:`FIELDS` is its numeric part (units, range, default, description), used by
  validation and by the ensemble engine
  (:func:`check_range`, :func:`check_params`): a distribution is checked against its
  field's range when an ensemble is loaded (:func:`check_distribution`), sampled values
  per drop (:func:`check_samples`, counted per field by :func:`invalid_samples`).
* :meth:`Scenario.to_params` packs a scenario into the flat parameter vector and the
  profile banks of :mod:`mineburial.kernels.mine.layout`.

Invalid input raises :class:`ScenarioError` (a ``ValueError``) whose message names the
field path, the value and the allowed range with its units, e.g.
``mine.length = -1.0 m is outside the allowed range (0, 50] m``.
"""

from __future__ import annotations

import dataclasses
import json
import math
import pathlib
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np

try:  # Python >= 3.11
    import tomllib
except ModuleNotFoundError:  # pragma: no cover - Python 3.10
    import tomli as tomllib

from mineburial.errors import ScenarioError, unknown_name_message, unknown_names_message
from mineburial.io.files import atomic_write_text
from mineburial.io.inputs import parse_toml, read_toml
from mineburial.kernels.mine import layout
from mineburial.kernels.mine.bodies.shapes import SHAPES, shape_named, shapes_of
from mineburial.kernels.rotation import euler_angles, normalize_quaternion
from mineburial.schema import (
    SUPPORT_TOLERANCE,
    Rule,
    check_rules,
    dumps_toml,
    generated_block,
    markdown_table,
    replace_generated,
)
from mineburial.schema import Field as FieldSpec
from mineburial.schema import check_distribution as schema_check_distribution
from mineburial.schema import number as _number
from mineburial.systems.mine.scenario_fields import CURRENT_KINDS, MINE_SHAPES, MODEL_NAMES, TABLE
from mineburial.systems.mine.sediment_profiles import (
    CATALOGUE,
    SedimentProfile,
    catalogue_profile,
    load_file,
    pack_banks,
)

__all__ = [
    "ScenarioError",
    "FieldSpec",
    "SCHEMA",
    "RULES",
    "FIELDS",
    "ALIASES",
    "check_range",
    "check_params",
    "explain_params",
    "Mine",
    "Release",
    "Current",
    "Environment",
    "Sediment",
    "Numerics",
    "Scenario",
    "quaternion_from_angles",
    "pack_banks",
    "example_names",
    "example_path",
    "load_example",
    "MODEL_DEFAULTS",
    "SUPPORT_TOLERANCE",
    "check_distribution",
    "check_samples",
    "InvalidSamples",
    "invalid_samples",
    "unknown_names_message",
    "ensemble_example_names",
]

_EPS = np.finfo(np.float64).eps


# ===========================================================================
# Field table: declared once in mineburial/systems/mine/scenario_fields.py (the schema mechanism:
# mineburial/schema.py); everything below derives from it
# ===========================================================================
#: every field of a scenario, by path (numbers, choices, switches, kernel codes)
SCHEMA: dict[str, FieldSpec] = {f.path: f for f in TABLE}

#: dotted path -> FieldSpec for every numeric scalar field of a scenario that an ensemble may
#: sample (``scour.window_days``, a number the stage's reader checks, is not one).
FIELDS: dict[str, FieldSpec] = {f.path: f for f in TABLE if f.kind == "float" and f.sampled}

#: alternative spellings accepted by :func:`check_range`: the scenario-file locations
#: (``release.position[2]``) and ``environment.current.*`` for ``current.*``.
ALIASES: dict[str, str] = {}
for _s in FIELDS.values():
    if _s.location != _s.path:
        ALIASES[_s.location] = _s.path
    if _s.path.startswith("current."):
        ALIASES["environment." + _s.path] = _s.path
ALIASES["environment.current.surface_velocity[0]"] = "current.u"
ALIASES["environment.current.surface_velocity[1]"] = "current.v"


def _spec_for(path: str) -> FieldSpec:
    key = ALIASES.get(path, path)
    try:
        return FIELDS[key]
    except KeyError:
        raise ScenarioError(unknown_name_message("field", path, FIELDS)) from None


def check_range(path: str, values) -> np.ndarray:
    """Boolean mask of ``values`` (any shape) that are finite and inside the static range
    of field ``path`` (:data:`FIELDS`; aliases accepted). The rules between fields
    (:data:`RULES`) are checked by :func:`check_params`."""
    return _spec_for(path).contains(values)


# ===========================================================================
# Distributions and sampled values against the field table (ensembles)
# ===========================================================================
# (SUPPORT_TOLERANCE, the tolerance of the distributions, is the schema's: mineburial.schema)


def _field_for(path: str) -> FieldSpec | None:
    return FIELDS.get(ALIASES.get(path, path))


def _label(location: str, spec: FieldSpec) -> str:
    return location if location == spec.path else f"{location} ({spec.path})"


def check_distribution(path: str, distribution) -> None:
    """Check the distribution of the scenario field ``path`` against the field's allowed range
    (:func:`mineburial.schema.check_distribution`, the one rule of every system). A
    categorical distribution, or a path without a range (labels, or names that are not
    fields), is left to the caller."""
    spec = _field_for(path)
    if spec is None or getattr(distribution, "categorical", False):
        return
    schema_check_distribution(spec, distribution, _label(path, spec))


def check_samples(inputs: Mapping[str, Any], n: int | None = None) -> np.ndarray:
    """Boolean mask over ``n`` drops: True where every sampled value in ``inputs`` (field
    path -> array of per-drop values, the ``inputs`` of an ensemble chunk) lies inside its
    field's allowed range. Paths that are not numeric fields (a sediment-class index) are
    skipped. This is the one check that also covers the release angles, which the packed
    parameter rows of :func:`check_params` hold only as a quaternion. ``n`` (default: the
    length of the first array) sizes the mask when nothing is sampled."""
    ok = None
    for path, values in inputs.items():
        spec = _field_for(path)
        if spec is None:
            continue
        mask = spec.contains(values)
        ok = mask if ok is None else ok & mask
    if ok is None:
        if n is None:
            n = len(next(iter(inputs.values()))) if inputs else 0
        ok = np.ones(n, dtype=bool)
    return ok


@dataclass(frozen=True)
class InvalidSamples:
    """Sampled values of one field that lie outside its allowed range (see
    :func:`invalid_samples`); ``str()`` is the sentence for a warning line."""

    path: str
    count: int
    total: int
    example: float  #: the offending value farthest outside the range
    allowed: str  #: the allowed range with units, as in error messages

    def __str__(self) -> str:
        return (
            f"{self.path}: {self.count} of {self.total} sampled values are outside the "
            f"allowed range {self.allowed} (e.g. {self.example:g}); those drops are "
            f"invalid_input"
        )


def invalid_samples(inputs: Mapping[str, Any]) -> list[InvalidSamples]:
    """The fields of ``inputs`` (path -> per-drop sampled values) with values outside their
    allowed range, one :class:`InvalidSamples` per such field, in the order of ``inputs``.

    After :func:`check_distribution` has passed at load time, what can remain is a draw
    in the tolerated tail (at most :data:`SUPPORT_TOLERANCE` per drop and field); such a
    drop is marked ``invalid_input`` (:func:`check_samples`) and the run should say so
    (``mineburial run`` prints ``str()`` of each item as a warning). Combinations that
    break a cross-field constraint (|chi| < L/2, the mine above the seabed, ...) are
    counted by :func:`check_params`/:func:`explain_params`, not here."""
    out = []
    for path, values in inputs.items():
        spec = _field_for(path)
        if spec is None:
            continue
        v = np.asarray(values, dtype=np.float64).reshape(-1)
        bad = v[~spec.contains(v)]
        if bad.size == 0:
            continue
        distance = np.maximum(spec.low - bad, bad - spec.high)  # NaN for a NaN value
        example = float(bad[np.argmax(np.where(np.isnan(distance), np.inf, distance))])
        out.append(InvalidSamples(path, int(bad.size), int(v.size), example, spec.range_text()))
    return out


# ===========================================================================
# Value checking helpers (scalar, raising)
# ===========================================================================
def _check(path: str, value, location: str | None = None):
    """``value`` of field ``path`` checked against the table (:meth:`FieldSpec.check`)."""
    return SCHEMA[path].check(value, location)


def _names(section: str, kinds=("float", "int", "bool", "choice")) -> tuple[str, ...]:
    """Names of the fields of ``section`` in the table (of the given kinds), in table order."""
    return tuple(f.name for f in TABLE if f.section == section and f.kind in kinds)


def _check_section(obj, section: str, skip=()) -> None:
    """Check (and convert) every field of ``section`` that ``obj`` holds and is set, then
    the rules among them. ``None`` is left to the caller (a default taken elsewhere)."""
    values = {}
    for name in _names(section):
        if name in skip or not hasattr(obj, name) or getattr(obj, name) is None:
            continue
        value = _check(f"{section}.{name}", getattr(obj, name))
        _set(obj, name, value)
        values[f"{section}.{name}"] = value
    _check_rules(values)


#: the linear sediment profile's fields (sediment.density, ...): not options of the model
_SED_LINEAR = ("density", "density_gradient", "strength", "strength_gradient")
_SED_LINEAR_PATHS = tuple(f"sediment.{f}" for f in _SED_LINEAR)

#: each field's declared default, by path (the dataclasses' defaults)
_D = {f.path: f.default for f in TABLE}


def _required_names(section: str) -> tuple[str, ...]:
    """The fields of ``section`` a file must give: no declared default, none computed."""
    return tuple(f.name for f in TABLE if f.section == section and f.default is None and not f.default_text)


def _file_key(f: FieldSpec) -> str:
    """The key of the file table that holds field ``f`` (``release.position[2]`` -> ``position``)."""
    return f.location.rpartition(".")[2].partition("[")[0]


def _list_paths(location: str) -> tuple[str, ...]:
    """The fields a list of a file holds, in order (``release.position`` -> release.x, .y, .z)."""
    return tuple(f.path for f in TABLE if f.location and f.location.startswith(location + "["))


def _table_defaults(section: str):
    """Class decorator, under ``@dataclass``: each annotated field of ``section`` that the class
    does not give a default gets its declared one (:data:`_D`), so that a default is written
    once, in mineburial/systems/mine/scenario_fields.py. A field declared without a default (a required
    one, or one computed when None) keeps what the class says."""

    def decorate(cls):
        for name in cls.__annotations__:
            if name not in cls.__dict__ and _D.get(f"{section}.{name}") is not None:
                setattr(cls, name, _D[f"{section}.{name}"])
        return cls

    return decorate


def _vector(value, n: int, location: str) -> tuple[float, ...]:
    if isinstance(value, (str, bytes)) or not hasattr(value, "__len__") or len(value) != n:
        raise ScenarioError(f"{location} = {value!r} must be a list of {n} numbers")
    return tuple(_number(x, f"{location}[{i}]") for i, x in enumerate(value))


def _set(obj, name, value):
    object.__setattr__(obj, name, value)


# ===========================================================================
# Mass properties: the mine's shape's (``mine.shape``: mineburial.kernels.mine.bodies.shapes.SHAPES)
# ===========================================================================
def _mine_dims(mine) -> dict:
    """The shape's dimensions of a :class:`Mine` (field path -> value)."""
    return {f: getattr(mine, f.split(".", 1)[1]) for f in shape_named(mine.shape).fields}


# ===========================================================================
# Orientation: angles -> quaternion (vectorised, for the sampled release angles).
# The way back, the rotation matrix and the gimbal-lock rule are the kernels'
# (mineburial.kernels.rotation: euler_angles, rotation_matrix).
# ===========================================================================
def quaternion_from_angles(psi1, psi2, psi3) -> np.ndarray:
    """Unit quaternion (q0, q1, q2, q3), scalar first, of R = Rz(psi3) Ry(psi2) Rx(psi1).

    Angles in radians (roll psi1, nose dip psi2, heading psi3; docs/design.md, seed 000
    eq. (4)); arrays broadcast, the result has shape ``broadcast + (4,)``. The body main
    axis is then i_M = R e_x = (cos psi3 cos psi2, sin psi3 cos psi2, -sin psi2). The
    inverse is :func:`mineburial.kernels.rotation.euler_angles`.
    """
    h1, h2, h3 = (np.asarray(a, dtype=np.float64) / 2.0 for a in (psi1, psi2, psi3))
    c1, s1, c2, s2, c3, s3 = np.cos(h1), np.sin(h1), np.cos(h2), np.sin(h2), np.cos(h3), np.sin(h3)
    # q = qz(psi3) * qy(psi2) * qx(psi1) (Hamilton product)
    return np.stack(
        np.broadcast_arrays(
            c1 * c2 * c3 + s1 * s2 * s3,
            s1 * c2 * c3 - c1 * s2 * s3,
            c1 * s2 * c3 + s1 * c2 * s3,
            c1 * c2 * s3 - s1 * s2 * c3,
        ),
        axis=-1,
    )


def _lowest_point(dims, q, z) -> np.ndarray:
    """Height of the lowest point of the drop's body (dimensions ``dims``, field path -> value)
    whose COM is at height ``z`` with attitude ``q`` (..., 4), by the kernel the stepper's
    seabed-contact event uses (the shape's ``lowest_point``); arrays broadcast."""
    q = np.asarray(q, dtype=np.float64)
    q0, q1, q2, q3 = np.moveaxis(q, -1, 0)
    a_z = 2.0 * (q1 * q3 - q0 * q2) / (q0 * q0 + q1 * q1 + q2 * q2 + q3 * q3)  # i_M . k
    z = np.asarray(z, dtype=np.float64)
    out = np.full(np.broadcast_shapes(np.shape(a_z), z.shape, *(np.shape(v) for v in dims.values())), np.nan)
    for shape, where in shapes_of(dims):
        where = np.broadcast_to(where, out.shape)
        if np.any(where):
            rows = {k: np.broadcast_to(np.asarray(dims[k], float), out.shape)[where] for k in shape.fields}
            a, zz = (np.broadcast_to(x, out.shape)[where] for x in (a_z, z))
            out[where] = shape.lowest_point(rows, a, zz)
    return out if out.shape else float(out)


# ===========================================================================
# Cross-field rules, declared once: checked per scenario (the dataclasses below, through
# _check_rules) and over packed parameter rows (check_params, _param_checks)
# ===========================================================================
_Q = _list_paths("release.quaternion")
#: the body's fields of every shape (the placement rule reads them), ``mine.shape`` first
_BODY = ("mine.shape", *dict.fromkeys(f for shape in SHAPES.values() for f in shape.fields))


def _is(v, path, names, name) -> np.ndarray:
    """Where the choice ``v[path]`` (a name, or the codes of packed rows) is ``name`` of ``names``."""
    code = v[path]
    if isinstance(code, str):
        return np.asarray(code == name)
    return np.asarray(code) == names.index(name)


def _shape_is(v, name) -> np.ndarray:
    """Where ``v["mine.shape"]`` is the shape ``name``."""
    return _is(v, "mine.shape", MINE_SHAPES, name)


def _starts_above_seabed(v) -> np.ndarray:
    """The whole mine starts above the seabed, unless ``release.embedded`` allows it in."""
    embedded = np.asarray(v["release.embedded"], dtype=bool)
    if np.all(embedded):
        return embedded
    q = np.stack(np.broadcast_arrays(*(np.asarray(v[k], dtype=np.float64) for k in _Q)), axis=-1)
    lowest = _lowest_point({k: v[k] for k in _BODY if k in v}, q, v["release.z"])
    return embedded | (lowest >= -np.asarray(v["environment.water_depth"]))


def _inside_seabed_message(v) -> str:
    z, depth = v["release.z"], v["environment.water_depth"]
    lowest = float(_lowest_point({k: v[k] for k in _BODY if k in v}, [v[k] for k in _Q], z))
    return (
        f"release.position[2] = {z!r} m starts the mine {-depth - lowest:.3g} m inside "
        f"the seabed (its lowest point at z = {lowest:.6g} m, the seabed at "
        f"-environment.water_depth = {-depth:g} m), so it has no impact: release it "
        f"at least that much higher, or set release.embedded = true for a mine placed "
        f"in the sediment"
    )


def _dt_rule(limit: str) -> Rule:
    return Rule(
        f"numerics.dt <= {limit}",
        ("numerics.dt", limit),
        lambda v: v["numerics.dt"] <= v[limit],
        note=f"dt <= {limit}",
        bounds=lambda v: (None, min(1.0, v[limit]), None),
    )


#: the relations between fields (docs/scenario.md lists them with the fields they bound)
RULES: tuple[Rule, ...] = (
    Rule(
        "current.table_index >= 0 exactly when current.kind is 'table'",
        ("current.kind", "current.table_index"),
        lambda v: (v["current.table_index"] >= 0) == (v["current.kind"] == CURRENT_KINDS.index("table")),
    ),
    # the relations between the body's own fields (the COM inside the body), each shape's
    *(rule for shape in SHAPES.values() for rule in shape.rules),
    Rule(
        "mine.top_ratio = 1 unless mine.shape is 'frustum'",
        ("mine.top_ratio", "mine.shape"),
        lambda v: _shape_is(v, "frustum") | (np.asarray(v["mine.top_ratio"]) == 1.0),
        note="a cylinder's ends are equal: mine.top_ratio is a frustum's (mine.shape = 'frustum')",
        bounds=lambda v: (1.0, 1.0, True),
    ),
    Rule(
        "numerics.model is 'mineburial' when mine.shape is 'frustum'",
        ("numerics.model", "mine.shape"),
        lambda v: ~_shape_is(v, "frustum") | _is(v, "numerics.model", MODEL_NAMES, "mineburial"),
        message=lambda v: (
            "numerics.model = 'impact35' with mine.shape = 'frustum': the printed IMPACT35 model is a "
            "cylinder's (seed 000); use numerics.model = 'mineburial' for a frustum"
        ),
    ),
    Rule(
        "mine.inertia_axial <= 2 mine.inertia_transverse",
        ("mine.inertia_axial", "mine.inertia_transverse"),
        lambda v: v["mine.inertia_axial"] <= 2 * v["mine.inertia_transverse"],
        note="J1 <= 2 J2 = 2 * mine.inertia_transverse, triangle inequality of a rigid body",
        bounds=lambda v: (None, 2.0 * v["mine.inertia_transverse"], None),
    ),
    Rule(
        "release.z > -environment.water_depth",
        ("release.z", "environment.water_depth"),
        lambda v: v["release.z"] > -v["environment.water_depth"],
        note="the COM must start above the seabed, z > -environment.water_depth",
        bounds=lambda v: (-v["environment.water_depth"], None, False),
    ),
    Rule(
        "the mine starts entirely above the seabed (release.embedded = false)",
        ("release.z", "environment.water_depth", *_BODY, *_Q, "release.embedded"),
        _starts_above_seabed,
        message=_inside_seabed_message,
    ),
    Rule(
        "the release quaternion has unit norm (within 1e-9)",
        _Q,
        lambda v: np.abs(np.sqrt(sum(v[k] ** 2 for k in _Q)) - 1) <= 1e-9,
    ),
    _dt_rule("numerics.t_max"),
    _dt_rule("numerics.t_max_fall"),
)


def _check_rules(values: Mapping) -> None:
    """Raise on the first rule of :data:`RULES` that ``values`` (one scenario's fields by
    path) break; a rule whose fields are not all in ``values`` is left to another part."""
    check_rules(RULES, values, SCHEMA)


# ===========================================================================
# The field tables of docs/scenario.md, generated from the table and the rules
# ===========================================================================
def _doc_paths(section: str, keep=lambda f: True) -> tuple[str, ...]:
    return tuple(f.path for f in TABLE if f.section == section and f.kind != "code" and keep(f))


#: each generated table of docs/scenario.md and the fields it lists
DOC_TABLES: dict[str, tuple[str, ...]] = {
    "mine": _doc_paths("mine"),
    "release": _doc_paths("release"),
    "environment": _doc_paths("environment"),
    "current": _doc_paths("current"),
    "sediment-profile": _doc_paths("sediment", lambda f: f.name in _SED_LINEAR),
    "sediment-options": _doc_paths("sediment", lambda f: f.name not in _SED_LINEAR),
    "numerics": _doc_paths("numerics"),
    "scour": _doc_paths("scour"),
}
_DOC_WRITER = "mineburial.systems.mine.config.write_field_tables"


def fields_markdown(name: str) -> str:
    """The Markdown table ``name`` of :data:`DOC_TABLES` (the rules between fields a user
    sets shown with the field they bound)."""
    rules = [r for r in RULES if all(SCHEMA[p].kind != "code" for p in r.paths)]
    return markdown_table((SCHEMA[p] for p in DOC_TABLES[name]), rules)


def _model_defaults_markdown() -> str:
    """The table of the choices that follow ``numerics.model`` (:data:`MODEL_DEFAULTS`)."""
    cols = ("resistance", "rate_law", "integrator")
    rows = ["| `numerics.model` | " + " | ".join(f"`{c}`" for c in cols) + " |", "|" + "---|" * 4]
    for model, chosen in MODEL_DEFAULTS.items():
        label = f'`"{model}"`' + (" (default)" if model == _D["numerics.model"] else "")
        rows.append(f"| {label} | " + " | ".join(f'`"{chosen[c]}"`' for c in cols) + " |")
    return "\n".join(rows) + "\n"


#: every generated table of docs/scenario.md: the field tables (:data:`DOC_TABLES`) and the
#: model-dependent defaults
DOC_BLOCKS = (*DOC_TABLES, "model-defaults")


def _doc_block(name: str) -> str:
    return _model_defaults_markdown() if name == "model-defaults" else fields_markdown(name)


def field_table_block(name: str) -> str:
    """Table ``name`` of :data:`DOC_BLOCKS` as docs/scenario.md holds it, between its markers."""
    return generated_block(name, _doc_block(name), _DOC_WRITER)


def write_field_tables(path="docs/scenario.md") -> None:
    """Regenerate every table of :data:`DOC_BLOCKS` in ``path`` (run from the repository
    root after changing mineburial/systems/mine/scenario_fields.py; tests/test_schema.py fails until then)."""
    path = pathlib.Path(path)
    text = path.read_text(encoding="utf-8")
    for name in DOC_BLOCKS:
        text = replace_generated(text, name, _doc_block(name), _DOC_WRITER)
    atomic_write_text(path, text)  # the one writer (docs/design.md, "Outputs")


# ===========================================================================
# Dataclasses
# ===========================================================================
@dataclass(frozen=True, kw_only=True)
@_table_defaults("mine")
class Mine:
    """The rigid mine, of the shape ``shape`` (``bodies.shapes.SHAPES``: the cylinder of seed
    000 sec. 2, Table 2, or a frustum whose top diameter is ``top_ratio`` of ``diameter``). SI units.

    ``inertia_axial`` / ``inertia_transverse`` left as ``None`` are replaced on
    construction by those of the uniform body (the shape's ``inertia``: the cylinder's
    m R^2/2, m (3R^2 + L^2)/12); pass
    ``None`` again through ``dataclasses.replace`` to recompute them after changing the
    mass or size.
    """

    length: float
    diameter: float
    mass: float
    com_offset: float  # the declared default (_table_defaults), as every unassigned field below
    inertia_axial: float | None = None
    inertia_transverse: float | None = None
    shape: str  # the declared defaults: "cylinder", 1.0
    top_ratio: float
    name: str = "mine"

    def __post_init__(self):
        if not isinstance(self.name, str):
            raise ScenarioError(f"mine.name = {self.name!r} must be a string")
        for f in ("length", "diameter", "mass", "com_offset"):  # the default inertia needs them
            _set(self, f, _check(f"mine.{f}", getattr(self, f)))
        _set(self, "shape", _check("mine.shape", self.shape))
        _set(self, "top_ratio", _check("mine.top_ratio", self.top_ratio))  # a frustum's inertia needs it
        j1, j2 = shape_named(self.shape).inertia(self.mass, _mine_dims(self))
        if self.inertia_axial is None:
            _set(self, "inertia_axial", j1)
        if self.inertia_transverse is None:
            _set(self, "inertia_transverse", j2)
        _check_section(self, "mine")

    @property
    def radius(self) -> float:
        return self.diameter / 2.0

    @property
    def volume(self) -> float:
        """The body's volume (the drop's shape's, ``bodies.shapes``) [m3]."""
        return shape_named(self.shape).volume(_mine_dims(self))

    @property
    def density(self) -> float:
        """Mean density m / volume [kg m-3]."""
        return self.mass / self.volume

    def to_dict(self) -> dict:
        return _file_table(self, "mine")


_ANGLES = ("roll_deg", "pitch_deg", "heading_deg")
#: the release's lists of numbers and the fields each holds (position -> release.x, .y, .z)
_RELEASE_VECTORS = {
    key: _list_paths(f"release.{key}") for key in ("position", "velocity", "angular_velocity")
}


@dataclass(frozen=True, kw_only=True)
@_table_defaults("release")
class Release:
    """Initial state of the drop.

    ``position`` is the COM in the E-frame (z = height above the calm surface),
    ``velocity`` the COM velocity, ``angular_velocity`` is in the **body** frame
    (seed 000 eq. (7)). The orientation is given either by the angles
    (``roll_deg``, ``pitch_deg``, ``heading_deg``; missing ones are 0) or by a
    ``quaternion`` (scalar first, body -> earth, normalised on construction), not both.
    If neither is given the mine is horizontal, nose towards +x.

    ``embedded`` (default false) allows the mine to start partly inside the seabed (a
    mine placed on or pressed into the sediment); without it such a release is refused
    (:class:`Scenario`), since a drop that starts in contact has no impact to report.
    """

    position: tuple = (0.0, 0.0, 0.0)
    velocity: tuple = (0.0, 0.0, 0.0)
    angular_velocity: tuple = (0.0, 0.0, 0.0)
    roll_deg: float | None = None
    pitch_deg: float | None = None
    heading_deg: float | None = None
    quaternion: tuple | None = None
    embedded: bool  # the declared default (_table_defaults)

    def __post_init__(self):
        _set(self, "embedded", _check("release.embedded", self.embedded))
        for name, paths in _RELEASE_VECTORS.items():
            vec = _vector(getattr(self, name), 3, f"release.{name}")
            _set(self, name, tuple(_check(p, x) for p, x in zip(paths, vec)))
        given = [a for a in _ANGLES if getattr(self, a) is not None]
        if self.quaternion is not None:
            if given:
                raise ScenarioError(
                    f"release: give either the angles (roll_deg, pitch_deg, heading_deg) or "
                    f"quaternion, not both (got quaternion and {', '.join(given)}); with "
                    f"dataclasses.replace, set the other form to None"
                )
            q = np.array(_vector(self.quaternion, 4, "release.quaternion"))
            norm = float(np.linalg.norm(q))
            if not (np.isfinite(norm) and norm > 1e-6):
                raise ScenarioError(
                    f"release.quaternion = {list(self.quaternion)!r} has norm "
                    f"{norm:g} ~ 0 and cannot be normalised"
                )
            # idempotent: a quaternion that is already unit (to rounding) is kept as is
            if abs(norm - 1.0) > 4 * _EPS or np.any(np.abs(q) > 1.0):
                q = np.clip(q / norm, -1.0, 1.0)
            _set(self, "quaternion", tuple(_check(f"release.q{i}", float(x)) for i, x in enumerate(q)))
        else:
            for a in _ANGLES:
                value = getattr(self, a)
                _set(self, a, _check(f"release.{a}", 0.0 if value is None else value))

    @property
    def q(self) -> tuple[float, float, float, float]:
        """Unit quaternion body -> earth, scalar first."""
        if self.quaternion is not None:
            return self.quaternion
        return tuple(
            float(x)
            for x in quaternion_from_angles(
                math.radians(self.roll_deg), math.radians(self.pitch_deg), math.radians(self.heading_deg)
            )
        )

    @property
    def angles_deg(self) -> tuple[float, float, float]:
        """(roll, pitch, heading) in degrees, as given or derived from the quaternion."""
        if self.quaternion is None:
            return self.roll_deg, self.pitch_deg, self.heading_deg
        return tuple(math.degrees(a) for a in euler_angles(*normalize_quaternion(*self.quaternion)))

    def to_dict(self) -> dict:
        return _file_table(self, "release")


_CURRENT_KEYS = {
    "none": ("kind",),
    "uniform": ("kind", "velocity"),
    "power_law": ("kind", "surface_velocity", "exponent"),
    "table": ("kind", "depth", "u", "v"),
}


@dataclass(frozen=True, kw_only=True)
@_table_defaults("current")
class Current:
    """Horizontal water current (E-frame x, y components).

    * ``none``: still water;
    * ``uniform``: (u, v) at every depth;
    * ``power_law``: U(h) = U_s (h/d)^exponent with h the height above the seabed and d
      the water depth (seed 004 eq. (38), exponent 1/7); (u, v) is the surface value U_s;
    * ``table``: piecewise-linear (u, v) against ``depth`` below the surface [m]
      (``table_u``, ``table_v``), strictly increasing depths >= 0.

    Fields not used by the kind must keep their defaults (so a Current has one meaning).
    """

    kind: str  # the declared defaults (_table_defaults)
    u: float
    v: float
    exponent: float
    depth: tuple = ()
    table_u: tuple = ()
    table_v: tuple = ()

    def __post_init__(self):
        kind = _check("current.kind", self.kind)
        vel = "surface_velocity" if kind == "power_law" else "velocity"
        for i, f in enumerate(("u", "v")):
            _set(self, f, _check(f"current.{f}", getattr(self, f), f"environment.current.{vel}[{i}]"))
        _set(self, "exponent", _check("current.exponent", self.exponent))
        for f in ("depth", "table_u", "table_v"):
            value = getattr(self, f)
            if isinstance(value, (str, bytes)) or not hasattr(value, "__len__"):
                raise ScenarioError(
                    f"environment.current.{f.replace('table_', '')} = {value!r} must be a list of numbers"
                )
            _set(
                self,
                f,
                tuple(
                    _number(x, f"environment.current.{f.replace('table_', '')}[{i}]")
                    for i, x in enumerate(value)
                ),
            )
        if kind in ("none", "table") and (self.u, self.v) != (0.0, 0.0):
            raise ScenarioError(
                f"environment.current: u, v = ({self.u!r}, {self.v!r}) are only "
                f"used by kind 'uniform' or 'power_law', not '{kind}'"
            )
        if kind != "power_law" and self.exponent != _D["current.exponent"]:
            raise ScenarioError(
                f"environment.current.exponent = {self.exponent!r} is only used "
                f"by kind 'power_law', not '{kind}'"
            )
        if kind != "table":
            if self.depth or self.table_u or self.table_v:
                raise ScenarioError(
                    f"environment.current: depth/u/v tables are only used by kind 'table', not '{kind}'"
                )
            return
        n = len(self.depth)
        if n == 0 or len(self.table_u) != n or len(self.table_v) != n:
            raise ScenarioError(
                f"environment.current: kind 'table' needs depth, u and v lists of the same "
                f"non-zero length, got {n}, {len(self.table_u)}, {len(self.table_v)}"
            )
        d = np.array(self.depth)
        if d[0] < 0 or not np.all(np.diff(d) > 0):
            raise ScenarioError(
                f"environment.current.depth = {list(self.depth)!r} m must be "
                f">= 0 and strictly increasing (depth below the surface)"
            )
        for f, comp in (("table_u", "u"), ("table_v", "v")):
            for i, x in enumerate(getattr(self, f)):
                _check(f"current.{comp}", x, f"environment.current.{comp}[{i}]")

    def as_array(self) -> np.ndarray:
        """(3, n) bank row: depth below the surface, u, v (kind 'table' only)."""
        if self.kind != "table":
            raise ScenarioError(f"environment.current.kind = '{self.kind}' has no table")
        return np.array([self.depth, self.table_u, self.table_v], dtype=np.float64)

    def to_dict(self) -> dict:
        """The ``[environment.current]`` table: the keys of the kind (:data:`_CURRENT_KEYS`)."""
        lists = {"velocity": (self.u, self.v), "surface_velocity": (self.u, self.v)}
        lists.update(u=self.table_u, v=self.table_v)
        keys = _CURRENT_KEYS[self.kind]
        return {k: _file_value(lists[k] if k in lists else getattr(self, k)) for k in keys}


@dataclass(frozen=True, kw_only=True)
@_table_defaults("environment")
class Environment:
    """Fluids, gravity, water depth (the seabed is at z = -water_depth) and current."""

    water_depth: float
    gravity: float  # the declared defaults (_table_defaults)
    air_density: float
    air_viscosity: float
    water_density: float
    water_viscosity: float
    current: Current = field(default_factory=Current)

    def __post_init__(self):
        _check_section(self, "environment")
        if not isinstance(self.current, Current):
            raise ScenarioError(f"environment.current = {self.current!r} must be a Current")

    def to_dict(self) -> dict:
        return _file_table(self, "environment")


#: Defaults that depend on ``numerics.model`` (used where the field is None / absent).
#: impact35 reproduces seed 000's force laws: "delta" tractions (eq. (74)) and the impact
#: function (70); mineburial uses the bearing-factor method (Chu & Fan 2007, IEEE J. Oceanic
#: Eng. 32(1):34, lower bias and RMSE of burial volume on Baltic drops) with a
#: semi-logarithmic rate law (docs/physics.md). mineburial integrates with dopri5 in air and
#: water and the Rosenbrock-W step in the sediment (3x the drops/s of dopri5 on the default
#: ensemble); impact35 with dopri5 throughout, because on its delta law the Rosenbrock-W step
#: is slower (small-cylinder family: 32 against 54 drops/s of CPU at the same tolerance and
#: accuracy; docs/design.md), and at its previous tolerances: rtol 3e-4 (the mineburial default)
#: leaves 9 % on a small-cylinder drop whose converged answer 1e-5 reproduces within 0.3 %. The
#: seed's local-linearisation step (83)-(87) stays selectable as ``integrator = "local_linear"``
#: (docs/design.md, "Time stepping").
MODEL_DEFAULTS = {
    "mineburial": {
        "resistance": "bearing",
        "rate_law": "semilog",
        "integrator": "dopri5_ros34pw2",
        "rtol": 3e-4,
        "atol": 3e-5,
    },
    "impact35": {
        "resistance": "delta",
        "rate_law": "impact35",
        "integrator": "dopri5",
        "rtol": 1e-5,
        "atol": 1e-6,
    },
}


@dataclass(frozen=True, kw_only=True)
@_table_defaults("sediment")
class Sediment:
    """Seabed sediment: a profile and the resistance-model options.

    The profile is either tabulated (``profile``: a :class:`SedimentProfile` from the
    catalogue, a core file or an inline table) or linear (``density``,
    ``density_gradient``, ``strength``, ``strength_gradient``: rho = rho0 + k_rho z,
    S = S0 + k_S z with z the depth below the seabed), never both.

    ``resistance`` and ``rate_law`` left as ``None`` take the defaults of
    ``numerics.model`` (:data:`MODEL_DEFAULTS`) when the :class:`Scenario` is built.
    Option defaults and sources: :data:`FIELDS` and docs/scenario.md.
    """

    profile: SedimentProfile | None = None
    density: float | None = None
    density_gradient: float | None = None
    strength: float | None = None
    strength_gradient: float | None = None
    resistance: str | None = None
    rate_law: str | None = None
    impact_factor: float  # the declared defaults (_table_defaults)
    rest_speed: float
    rate_coefficient: float
    reference_rate: float
    friction: float
    bearing_factor: float
    pore_pressure: bool
    rupture_length: float
    permeability: float
    void_ratio: float
    bearing_depth_factor: float
    inertial_drag: float

    def __post_init__(self):
        linear_given = [f for f in _SED_LINEAR if getattr(self, f) is not None]
        if self.profile is not None:
            if not isinstance(self.profile, SedimentProfile):
                raise ScenarioError(f"sediment.profile = {self.profile!r} must be a SedimentProfile")
            if linear_given:
                raise ScenarioError(
                    f"sediment: give either a tabulated profile (class, profile or file) or a "
                    f"linear one (density, strength, gradients), not both (got a profile and "
                    f"{', '.join(linear_given)})"
                )
        else:
            for f in ("density", "strength"):
                if getattr(self, f) is None:
                    raise ScenarioError(
                        f"sediment.{f} is required for a linear profile; or give the profile "
                        f"as class = one of {', '.join(CATALOGUE)}, profile = {{depth, "
                        f"density, strength}} or file = 'core.csv'"
                    )
            for f in _SED_LINEAR:
                value = getattr(self, f)
                _set(self, f, _check(f"sediment.{f}", 0.0 if value is None else value))
        _check_section(self, "sediment", skip=_SED_LINEAR)

    @classmethod
    def from_class(cls, name: str, **options) -> Sediment:
        """Sediment with the profile of catalogue class ``name`` and ``options``."""
        return cls(profile=catalogue_profile(name), **options)

    @property
    def is_linear(self) -> bool:
        return self.profile is None

    def evaluate(self, depth):
        """(density [kg m-3], strength [Pa]) at ``depth`` [m] below the seabed."""
        if self.profile is not None:
            return self.profile.evaluate(depth)
        z = np.maximum(np.asarray(depth, dtype=np.float64), 0.0)
        return (self.density + self.density_gradient * z, self.strength + self.strength_gradient * z)

    def resolved(self, model: str) -> Sediment:
        """Copy with ``resistance``/``rate_law`` set from :data:`MODEL_DEFAULTS` if None."""
        d = MODEL_DEFAULTS[model]
        return dataclasses.replace(
            self, resistance=self.resistance or d["resistance"], rate_law=self.rate_law or d["rate_law"]
        )

    def to_dict(self) -> dict:
        return _file_table(self, "sediment")


@dataclass(frozen=True, kw_only=True)
@_table_defaults("numerics")
class Numerics:
    """Model choice, integrator and stopping criteria.

    ``integrator``, ``rtol`` and ``atol`` left as ``None`` take the defaults of ``model``
    (:data:`MODEL_DEFAULTS`: ``dopri5_ros34pw2`` at rtol 3e-4, atol 3e-5 for mineburial,
    ``dopri5`` at 1e-5, 1e-6 for impact35; ``dopri5``, the fixed-step ``rk4`` at ``dt`` and
    the seed's ``local_linear`` stay selectable as references). ``dt`` is the step of the
    fixed-step integrators and the first trial step of the adaptive ones; ``rtol``/``atol``
    are the tolerances of the adaptive ones.
    ``sediment_quadrature``: ``fast`` (fixed-cost rule, default) or ``reference``
    (the accurate adaptive quadrature).
    ``water_column``: ``munk_factor`` (default: strip added mass with the axial added mass
    set by ``munk_factor``) or ``viscous_crossflow`` (added-mass tensor of the finite
    cylinder and the Munk moment with its incidence factor; docs/physics.md, "Water-column
    model choices"; ``munk_factor`` is then unused).
    ``overburden_quadrature``: ``fast`` (default: cost bounded whatever a tabulated
    profile's rows) or ``reference`` (the body sliced at every table depth inside it;
    kernels/mine/overburden.py).
    The time limits are two, one for each phase of a drop: ``t_max_fall`` bounds the fall
    through air and water (release to the first seabed contact), ``t_max`` the time after
    that contact. A fall ends by itself at the seabed (or when a mine lighter than the water
    floats), however slowly the mine sinks, so the fall has its own, generous limit, and
    ``t_max`` guards only the motion in the sediment (docs/design.md, "The end of a drop").
    """

    model: str  # the declared defaults (_table_defaults) where no default is written
    integrator: str | None = None
    dt: float
    t_max: float
    t_max_fall: float
    rest_speed: float
    rest_spin: float
    drag: bool
    munk_factor: float
    rtol: float | None = None
    atol: float | None = None
    sediment_quadrature: str
    slip_speed: float
    switch_speed: float
    water_column: str
    overburden_quadrature: str
    crossflow_drag_factor: float
    crossflow_munk_fraction: float
    added_mass_factor: float

    def __post_init__(self):
        _set(self, "model", _check("numerics.model", self.model))
        for f in ("integrator", "rtol", "atol"):
            if getattr(self, f) is None:
                _set(self, f, MODEL_DEFAULTS[self.model][f])
        _check_section(self, "numerics")

    def to_dict(self) -> dict:
        return _file_table(self, "numerics")


# ===========================================================================
# Scenario
# ===========================================================================
_SECTIONS = ("description", "mine", "release", "environment", "sediment", "numerics")
_MINE_KEYS = ("name",) + _names("mine")
_RELEASE_KEYS = tuple(dict.fromkeys(_file_key(f) for f in TABLE if f.section == "release"))
_ENV_KEYS = _names("environment") + ("current",)
_SED_SOURCES = ("class", "profile", "file")
_SED_KEYS = _SED_SOURCES + _names("sediment")
_NUM_KEYS = tuple(f.name for f in dataclasses.fields(Numerics))
#: the keys of each section's file table, in the order ``to_dict`` writes them: the keys its
#: reader accepts, from the declared locations (scenario_fields.TABLE)
_FILE_KEYS = {
    "mine": _MINE_KEYS,
    "release": _RELEASE_KEYS,
    "environment": _ENV_KEYS,
    "sediment": _SED_KEYS,
    "numerics": _NUM_KEYS,
}
#: the sections of the field table that a Scenario holds, and the kinds of field with a value
_PARTS = ("mine", "release", "environment", "current", "sediment", "numerics")
_VALUE_KINDS = ("float", "int", "bool", "choice", "code")


def _file_value(value):
    """``value`` as a file table holds it: a tuple as a list, a profile or current as its table."""
    if hasattr(value, "to_dict"):
        return value.to_dict()
    return list(value) if isinstance(value, tuple) else value


def _file_table(obj, section: str) -> dict:
    """The file table of ``section`` that ``obj`` (its dataclass) holds: each key its reader
    accepts (:data:`_FILE_KEYS`) that ``obj`` has set; ``None`` (the other form of the
    orientation or of the profile, given instead) is left out, so that ``from_dict`` reads
    the table back to an equal object."""
    values = {key: getattr(obj, key, None) for key in _FILE_KEYS[section]}
    return {key: _file_value(value) for key, value in values.items() if value is not None}


def _held_value(obj, f: FieldSpec):
    """The value of field ``f`` that its section's dataclass ``obj`` holds: the attribute of
    the field's name, else the element of the list at its file location (``release.x`` is
    ``release.position[0]``)."""
    if hasattr(obj, f.name):
        return getattr(obj, f.name)
    return getattr(obj, _file_key(f))[int(f.location.partition("[")[2].rstrip("]"))]


def _section(d: Mapping, name: str, allowed, required: bool = False) -> dict:
    if name not in d:
        if required:
            raise ScenarioError(f"[{name}] section is required")
        return {}
    sec = d[name]
    if not isinstance(sec, Mapping):
        raise ScenarioError(f"{name} must be a table ([{name}]), got {sec!r}")
    unknown = [key for key in sec if key not in allowed]
    if unknown:
        raise ScenarioError(f"[{name}]: " + unknown_names_message("key", unknown, allowed))
    return dict(sec)


def _distribution_paths(node, path: str = "") -> list[str]:
    """Paths of the distribution tables (inline tables with a ``distribution`` key)."""
    if isinstance(node, Mapping):
        if "distribution" in node:
            return [path]
        return [
            p
            for key, value in node.items()
            for p in _distribution_paths(value, f"{path}.{key}" if path else str(key))
        ]
    if isinstance(node, (list, tuple)):
        return [p for k, value in enumerate(node) for p in _distribution_paths(value, f"{path}[{k}]")]
    return []


def _check_fixed(d: Mapping) -> None:
    """A :class:`Scenario` is one drop: refuse an ensemble scenario with a message that
    says so (not 'unknown section' or 'must be a number')."""
    random = _distribution_paths(d)
    if random:
        listed = ", ".join(random[:5]) + (f" and {len(random) - 5} more" if len(random) > 5 else "")
        raise ScenarioError(
            f"{listed} {'is a distribution' if len(random) == 1 else 'are distributions'}: "
            f"this is an ensemble scenario, but a single drop needs fixed values; run the "
            f"ensemble with `mineburial run` (run_ensemble), or give fixed values"
        )
    if "ensemble" in d:
        raise ScenarioError(
            "the [ensemble] table belongs to an ensemble scenario (`mineburial "
            "run`, run_ensemble); a single drop does not use it: remove it"
        )


def _required(sec: dict, section: str, keys):
    for key in keys:
        if key not in sec:
            spec = FIELDS.get(f"{section}.{key}")
            units = f" [{spec.units}]" if spec and spec.units != "1" else ""
            raise ScenarioError(f"{section}.{key}{units} is required")


@dataclass(frozen=True, kw_only=True)
class Scenario:
    """A complete, validated drop scenario (see module docstring and docs/scenario.md)."""

    mine: Mine
    environment: Environment
    sediment: Sediment
    release: Release = field(default_factory=Release)
    numerics: Numerics = field(default_factory=Numerics)
    description: str = ""

    def __post_init__(self):
        for name, cls in (
            ("mine", Mine),
            ("environment", Environment),
            ("sediment", Sediment),
            ("release", Release),
            ("numerics", Numerics),
        ):
            if not isinstance(getattr(self, name), cls):
                raise ScenarioError(f"{name} = {getattr(self, name)!r} must be a {cls.__name__}")
        if not isinstance(self.description, str):
            raise ScenarioError(f"description = {self.description!r} must be a string")
        _set(self, "sediment", self.sediment.resolved(self.numerics.model))
        _check_rules(self.field_values())

    def field_values(self) -> dict[str, float]:
        """Every field of the scenario declared in scenario_fields.TABLE, by path, packed as
        a kernel slot holds it (a choice's index, a switch's 0/1, the bank rows' codes): what
        the rules (:data:`RULES`) read here, as they read the packed rows of an ensemble, and
        what :meth:`to_params` packs. The quaternion is the release's orientation whichever
        form gave it; an angle not given (the quaternion given instead) is NaN; a tabulated
        profile gives its seabed values and first-segment gradients as the linear fields."""
        r, s, c = self.release, self.sediment, self.environment.current
        linear = (
            s.profile.surface_gradients() if s.profile is not None else [getattr(s, f) for f in _SED_LINEAR]
        )
        values = {
            **dict(zip(_Q, r.q)),
            **dict(zip(_SED_LINEAR_PATHS, linear)),
            **{f"release.{a}": math.nan for a in _ANGLES if getattr(r, a) is None},
            "current.table_index": 0 if c.kind == "table" else -1,
            "sediment.profile_index": -1 if s.profile is None else 0,
        }
        parts = dict(zip(_PARTS, (self.mine, r, self.environment, c, s, self.numerics)))
        for f in TABLE:
            if f.path not in values and f.section in parts and f.kind in _VALUE_KINDS:
                values[f.path] = f.pack(_held_value(parts[f.section], f))
        return values

    # -- reading -------------------------------------------------------------
    @classmethod
    def from_dict(cls, d: Mapping, base_dir=None) -> Scenario:
        """Build from a nested dict (the parsed TOML). ``base_dir`` resolves a relative
        ``sediment.file`` (default: the current directory)."""
        if not isinstance(d, Mapping):
            raise ScenarioError(f"a scenario must be a table, got {type(d).__name__}")
        _check_fixed(d)
        unknown = [key for key in d if key not in _SECTIONS]
        if unknown:
            raise ScenarioError(unknown_names_message("section", unknown, _SECTIONS))
        mine = _section(d, "mine", _MINE_KEYS, required=True)
        _required(mine, "mine", _required_names("mine"))
        release = _section(d, "release", _RELEASE_KEYS)
        env = _section(d, "environment", _ENV_KEYS, required=True)
        _required(env, "environment", _required_names("environment"))
        current = env.pop("current", {"kind": "none"})
        sed = _section(d, "sediment", _SED_KEYS, required=True)
        num = _section(d, "numerics", _NUM_KEYS)
        return cls(
            mine=Mine(**mine),
            release=Release(**release),
            environment=Environment(**env, current=_current_from_dict(current)),
            sediment=_sediment_from_dict(sed, base_dir),
            numerics=Numerics(**num),
            description=d.get("description", ""),
        )

    @classmethod
    def from_toml(cls, path) -> Scenario:
        """Read a TOML scenario file; a relative ``sediment.file`` is resolved against
        the file's folder."""
        path = pathlib.Path(path)
        try:
            d = read_toml(path)
        except OSError as exc:
            raise ScenarioError(f"cannot read scenario file '{path}': {exc.strerror}") from None
        except tomllib.TOMLDecodeError as exc:
            raise ScenarioError(f"scenario file '{path}' is not valid TOML: {exc}") from None
        return cls.from_dict(d, base_dir=path.resolve().parent)

    @classmethod
    def from_toml_string(cls, text: str, base_dir=None) -> Scenario:
        try:
            d = parse_toml(text)
        except tomllib.TOMLDecodeError as exc:
            raise ScenarioError(f"scenario is not valid TOML: {exc}") from None
        return cls.from_dict(d, base_dir=base_dir)

    # -- writing -------------------------------------------------------------
    def to_dict(self) -> dict:
        """Fully resolved nested dict (floats, strings, bools, lists; no None), JSON and
        TOML serialisable; ``Scenario.from_dict(s.to_dict()) == s``."""
        return {
            "description": self.description,
            "mine": self.mine.to_dict(),
            "release": self.release.to_dict(),
            "environment": self.environment.to_dict(),
            "sediment": self.sediment.to_dict(),
            "numerics": self.numerics.to_dict(),
        }

    def to_json(self) -> str:
        """``to_dict`` as a JSON string (e.g. for a NetCDF global attribute)."""
        return json.dumps(self.to_dict())

    def to_toml(self) -> str:
        """``to_dict`` as TOML text (reads back to an equal Scenario)."""
        return dumps_toml(self.to_dict())

    # -- packing for the kernels ---------------------------------------------
    def to_params(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """``(p, sediment_bank, current_bank)`` for the kernels (kernels/mine/layout.py).

        ``p`` has every slot of ``PARAM_NAMES`` filled; codes are indices into the name
        tuples of layout.py. A tabulated sediment profile is row 0 of a one-row bank
        (``sediment.profile_index = 0``; the linear slots then hold its seabed values and
        first-segment gradients, for information); a linear profile gives an empty bank and
        index -1. Likewise a ``table`` current is row 0 of ``current_bank``.
        """
        values = self.field_values()
        p = np.array([values[name] for name in layout.PARAM_NAMES], dtype=np.float64)
        profiles = [] if self.sediment.profile is None else [self.sediment.profile]
        currents = [self.environment.current] if self.environment.current.kind == "table" else []
        return p, pack_banks(profiles), pack_banks(currents)


def _current_from_dict(cur) -> Current:
    if not isinstance(cur, Mapping):
        raise ScenarioError(f"environment.current must be a table, got {cur!r}")
    kind = cur.get("kind", "none")
    kind = _check("current.kind", kind)
    allowed = _CURRENT_KEYS[kind]
    all_keys = sorted({k for ks in _CURRENT_KEYS.values() for k in ks})
    unknown = [key for key in cur if key not in all_keys]
    if unknown:
        raise ScenarioError("[environment.current]: " + unknown_names_message("key", unknown, all_keys))
    unused = [key for key in cur if key not in allowed]
    if unused:
        raise ScenarioError(
            f"[environment.current]: {'key' if len(unused) == 1 else 'keys'} "
            f"{', '.join(repr(k) for k in unused)} "
            f"{'is' if len(unused) == 1 else 'are'} not used by kind "
            f"'{kind}'; keys of this kind: {', '.join(allowed)}"
        )
    if kind in ("uniform", "power_law"):
        key = "velocity" if kind == "uniform" else "surface_velocity"
        if key not in cur:
            raise ScenarioError(f"environment.current.{key} = [u, v] (m s-1) is required for kind '{kind}'")
        u, v = _vector(cur[key], 2, f"environment.current.{key}")
        return Current(kind=kind, u=u, v=v, exponent=cur.get("exponent", _D["current.exponent"]))
    if kind == "table":
        for key in ("depth", "u", "v"):
            if key not in cur:
                raise ScenarioError(f"environment.current.{key} (list) is required for kind 'table'")
        return Current(kind="table", depth=cur["depth"], table_u=cur["u"], table_v=cur["v"])
    return Current(kind="none")


def _sediment_from_dict(sed: dict, base_dir) -> Sediment:
    sources = [k for k in _SED_SOURCES if k in sed]
    linear = [k for k in _SED_LINEAR if k in sed]
    if len(sources) + (1 if linear else 0) != 1:
        given = sources + (["density/strength"] if linear else [])
        raise ScenarioError(
            "sediment: give exactly one profile: class = one of "
            f"{', '.join(CATALOGUE)} | density/density_gradient/strength/strength_gradient | "
            f"profile = {{depth, density, strength}} | file = 'core.csv' or 'core.nc' "
            f"(got {', '.join(given) if given else 'none'})"
        )
    kw = {k: v for k, v in sed.items() if k not in _SED_SOURCES}
    if "class" in sed:
        kw["profile"] = catalogue_profile(sed["class"])
    elif "profile" in sed:
        kw["profile"] = SedimentProfile.from_dict(sed["profile"])
    elif "file" in sed:
        if not isinstance(sed["file"], str):
            raise ScenarioError(f"sediment.file = {sed['file']!r} must be a path string")
        kw["profile"] = load_file(sed["file"], base_dir)
    return Sediment(**kw)


# ===========================================================================
# Vectorised validation of packed parameter rows (for ensembles)
# ===========================================================================
#: the slots by what their check is: ranges of numbers, codes of choices and switches, bank rows
_SLOT_GROUPS = tuple(
    tuple(name for name in layout.PARAM_NAMES if SCHEMA[name].kind in kinds)
    for kinds in (("float",), ("choice", "bool"), ("code",))
)


def _param_checks(P: np.ndarray, n_sediment, n_current, embedded=False):
    """List of (text, slot names involved, ok mask) over rows of P: each slot against its
    field, then every rule of :data:`RULES`."""
    P = np.atleast_2d(np.asarray(P, dtype=np.float64))
    if P.ndim != 2 or P.shape[-1] != layout.N_PARAMS:
        raise ScenarioError(f"parameter rows must have {layout.N_PARAMS} columns, got shape {P.shape}")
    col = {name: P[:, i] for i, name in enumerate(layout.PARAM_NAMES)}
    col["release.embedded"] = np.full(P.shape[0], bool(embedded))
    numbers, codes, rows = _SLOT_GROUPS
    checks = []
    tabulated = col["sediment.profile_index"] != -1
    for name in numbers:
        spec = SCHEMA[name]
        ok = spec.contains(col[name])
        if name in _SED_LINEAR_PATHS:
            ok |= tabulated & np.isfinite(col[name])  # informational for tables
        checks.append((f"{name} in {spec.range_text()}", (name,), ok))
    for name in codes:
        v, n = col[name], int(SCHEMA[name].high) + 1
        checks.append(
            (f"{name} is an integer code in [0, {n - 1}]", (name,), (v == np.floor(v)) & (v >= 0) & (v < n))
        )
    banks = {"sediment.profile_index": n_sediment, "current.table_index": n_current}
    for name in rows:
        v, n = col[name], banks[name]
        ok = (v == np.floor(v)) & (v >= -1)
        if n is not None:
            ok &= v < n
        bound = f" < {n}" if n is not None else ""
        checks.append((f"{name} is -1 or a bank row{bound}", (name,), ok))
    for rule in RULES:
        checks.append((rule.text, tuple(p for p in rule.paths if p in layout.INDEX), rule.holds(col)))
    return checks


def check_params(
    P, n_sediment: int | None = None, n_current: int | None = None, *, embedded: bool = False
) -> np.ndarray:
    """Boolean mask over packed parameter rows ``P`` (shape (n, N_PARAMS) or (N_PARAMS,)):
    True where every slot is inside its :data:`FIELDS` range, codes are valid, bank
    indices are in range (when the bank sizes are given) and every rule of :data:`RULES`
    holds (``embedded`` is ``release.embedded``, which no slot holds). The ensemble
    marks the failing drops ``invalid_input`` (kernels/status.py); :func:`explain_params`
    says why."""
    checks = _param_checks(P, n_sediment, n_current, embedded)
    ok = np.ones_like(checks[0][2], dtype=bool)
    for _, _, mask in checks:
        ok &= mask
    return ok


def explain_params(
    p, n_sediment: int | None = None, n_current: int | None = None, *, embedded: bool = False
) -> list[str]:
    """The constraints that one parameter row ``p`` violates, with the offending values
    (empty list when the row is valid)."""
    p = np.asarray(p, dtype=np.float64).reshape(-1)
    return [
        f"{text} (got " + ", ".join(f"{n} = {float(p[layout.INDEX[n]])!r}" for n in names) + ")"
        for text, names, mask in _param_checks(p, n_sediment, n_current, embedded)
        if not mask[0]
    ]


# ===========================================================================
# Shipped example scenarios
# ===========================================================================
_DATA = pathlib.Path(__file__).resolve().parent.parent.parent / "data"


def example_names() -> tuple[str, ...]:
    """Names of the example (single-drop) scenarios shipped in ``mineburial/data``."""
    return tuple(sorted(p.stem for p in _DATA.glob("*.toml")))


def ensemble_example_names() -> tuple[str, ...]:
    """Names of the example ensemble scenarios shipped in ``mineburial/data/ensembles``
    (for ``mineburial run`` and ``mineburial map``; ``default_soft_mud`` is the one
    ``mineburial run`` uses without a scenario)."""
    return tuple(sorted(p.stem for p in (_DATA / "ensembles").glob("*.toml")))


def example_path(name: str) -> pathlib.Path:
    """Path of example scenario ``name``, single-drop or ensemble (ScenarioError with a
    suggestion if unknown)."""
    if name in ensemble_example_names():
        return _DATA / "ensembles" / f"{name}.toml"
    names = example_names()
    if name not in names:
        raise ScenarioError(unknown_name_message("example scenario", name, names + ensemble_example_names()))
    return _DATA / f"{name}.toml"


def load_example(name: str) -> Scenario:
    """Load example scenario ``name`` (see :func:`example_names`)."""
    return Scenario.from_toml(example_path(name))
