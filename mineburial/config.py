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
* :data:`FIELDS` is the machine-readable table of every numeric scalar field (units,
  range, default, description), used by validation and by the ensemble engine
  (:func:`check_range`, :func:`check_params`): a distribution is checked against its
  field's range when an ensemble is loaded (:func:`check_distribution`), sampled values
  per drop (:func:`check_samples`, counted per field by :func:`invalid_samples`).
* :meth:`Scenario.to_params` packs a scenario into the flat parameter vector and the
  profile banks of :mod:`mineburial.kernels.layout`.

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

from mineburial.io.inputs import parse_toml, read_toml
from mineburial.kernels import layout
from mineburial.kernels.geometry import vertical_extent
from mineburial.kernels.rotation import euler_angles, normalize_quaternion
from mineburial.sediment_profiles import (
    CATALOGUE,
    ScenarioError,
    SedimentProfile,
    catalogue_profile,
    load_file,
    pack_banks,
    unknown_name_message,
    unknown_names_message,
)

__all__ = [
    "ScenarioError",
    "FieldSpec",
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
    "uniform_cylinder_inertia",
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
# Field table
# ===========================================================================
def _fmt(x: float) -> str:
    return "inf" if x == math.inf else "-inf" if x == -math.inf else f"{x:g}"


@dataclass(frozen=True)
class FieldSpec:
    """Units, allowed range and meaning of one numeric scalar scenario field.

    ``path`` is the dotted name (the slot name in :data:`mineburial.kernels.layout.PARAM_NAMES`
    where the field has one); ``location`` is where the value sits in a scenario file
    (``release.position[2]`` for ``release.z``). ``default`` is ``None`` for required
    fields or fields whose default is computed (documented in ``description``).
    """

    path: str
    units: str
    low: float
    high: float
    low_inclusive: bool
    high_inclusive: bool
    description: str
    default: float | None = None
    location: str = ""

    def range_text(
        self,
        low: float | None = None,
        high: float | None = None,
        low_inclusive: bool | None = None,
        high_inclusive: bool | None = None,
    ) -> str:
        """``(0, 50] m`` style text of the allowed range (optionally with other bounds)."""
        lo = self.low if low is None else low
        hi = self.high if high is None else high
        li = self.low_inclusive if low_inclusive is None else low_inclusive
        hi_incl = self.high_inclusive if high_inclusive is None else high_inclusive
        text = ("[" if li else "(") + f"{_fmt(lo)}, {_fmt(hi)}" + ("]" if hi_incl else ")")
        return f"{text} {self.units}" if self.units != "1" else text

    def contains(self, values) -> np.ndarray:
        """Boolean mask: finite and inside the range (vectorised)."""
        v = np.asarray(values, dtype=np.float64)
        ok = np.isfinite(v)
        ok &= (v >= self.low) if self.low_inclusive else (v > self.low)
        ok &= (v <= self.high) if self.high_inclusive else (v < self.high)
        return ok


def _spec(path, units, low, high, description, default=None, *, incl=(True, True), location=None):
    return FieldSpec(
        path,
        units,
        float(low),
        float(high),
        incl[0],
        incl[1],
        description,
        None if default is None else float(default),
        location or path,
    )


_OPEN_LOW = (False, True)
_OPEN = (False, False)

#: 1 %/h, the conventional laboratory (triaxial) shear rate, in s-1.
LAB_STRAIN_RATE = 0.01 / 3600.0

_FIELD_LIST = [
    # --- mine ---------------------------------------------------------------
    _spec("mine.length", "m", 0, 50, "length L of the cylinder", incl=_OPEN_LOW),
    _spec("mine.diameter", "m", 0, 10, "diameter d = 2R of the cylinder", incl=_OPEN_LOW),
    _spec("mine.mass", "kg", 0, 1e5, "mass m", incl=_OPEN_LOW),
    _spec(
        "mine.com_offset",
        "m",
        -25,
        25,
        "chi: COM displacement from the centre of volume towards the nose (seed 000 "
        "Fig. 1); also |chi| < length/2",
        0.0,
        incl=_OPEN,
    ),
    _spec(
        "mine.inertia_axial",
        "kg m2",
        0,
        1e7,
        "J1, moment of inertia about the main axis through the COM; default m R^2/2 "
        "(uniform cylinder); also J1 <= 2 J2",
        incl=_OPEN_LOW,
    ),
    _spec(
        "mine.inertia_transverse",
        "kg m2",
        0,
        1e7,
        "J2 = J3, moment of inertia about a transverse axis through the COM; default "
        "m (3R^2 + L^2)/12 (uniform cylinder)",
        incl=_OPEN_LOW,
    ),
    # --- release ------------------------------------------------------------
    _spec("release.x", "m", -1e5, 1e5, "initial x of the COM", 0.0, location="release.position[0]"),
    _spec("release.y", "m", -1e5, 1e5, "initial y of the COM", 0.0, location="release.position[1]"),
    _spec(
        "release.z",
        "m",
        -11000,
        20000,
        "initial height of the COM above the calm water surface; also > -environment.water_depth",
        0.0,
        location="release.position[2]",
    ),
    _spec("release.u", "m s-1", -500, 500, "initial COM velocity, x", 0.0, location="release.velocity[0]"),
    _spec("release.v", "m s-1", -500, 500, "initial COM velocity, y", 0.0, location="release.velocity[1]"),
    _spec(
        "release.w", "m s-1", -500, 500, "initial COM velocity, z (up)", 0.0, location="release.velocity[2]"
    ),
    _spec("release.roll_deg", "deg", -360, 360, "psi1, roll about the main axis", 0.0),
    _spec(
        "release.pitch_deg",
        "deg",
        -90,
        90,
        "psi2, dip of the nose below the horizontal (+90 = nose down)",
        0.0,
    ),
    _spec("release.heading_deg", "deg", -360, 360, "psi3, heading of the nose from +x towards +y", 0.0),
    _spec("release.q0", "1", -1, 1, "orientation quaternion, scalar part", location="release.quaternion[0]"),
    _spec("release.q1", "1", -1, 1, "orientation quaternion, x part", location="release.quaternion[1]"),
    _spec("release.q2", "1", -1, 1, "orientation quaternion, y part", location="release.quaternion[2]"),
    _spec("release.q3", "1", -1, 1, "orientation quaternion, z part", location="release.quaternion[3]"),
    _spec(
        "release.omega1",
        "rad s-1",
        -1000,
        1000,
        "initial angular velocity, body axis 1",
        0.0,
        location="release.angular_velocity[0]",
    ),
    _spec(
        "release.omega2",
        "rad s-1",
        -1000,
        1000,
        "initial angular velocity, body axis 2",
        0.0,
        location="release.angular_velocity[1]",
    ),
    _spec(
        "release.omega3",
        "rad s-1",
        -1000,
        1000,
        "initial angular velocity, body axis 3",
        0.0,
        location="release.angular_velocity[2]",
    ),
    # --- environment ----------------------------------------------------------
    _spec("environment.gravity", "m s-2", 0, 100, "gravitational acceleration g", 9.81, incl=_OPEN_LOW),
    _spec("environment.air_density", "kg m-3", 0, 10, "air density (ISA sea level 1.225)", 1.225),
    _spec(
        "environment.air_viscosity",
        "m2 s-1",
        0,
        1e-3,
        "kinematic viscosity of air (ISA 15 C: 1.46e-5)",
        1.5e-5,
        incl=_OPEN_LOW,
    ),
    _spec(
        "environment.water_density",
        "kg m-3",
        0,
        1300,
        "water density (sea water 1025, seed 004 sec. 4; fresh 998; 0 = no water, for ballistic checks)",
        1025.0,
    ),
    _spec(
        "environment.water_viscosity",
        "m2 s-1",
        0,
        1e-4,
        "kinematic viscosity of water (sea water 1.05e-6, seed 004 sec. 4)",
        1.05e-6,
        incl=_OPEN_LOW,
    ),
    _spec("environment.water_depth", "m", 0, 11000, "water depth H; the seabed is at z = -H", incl=_OPEN_LOW),
    _spec(
        "current.u",
        "m s-1",
        -10,
        10,
        "current x: uniform value or surface value of the power law",
        0.0,
        location="environment.current.velocity[0]",
    ),
    _spec(
        "current.v",
        "m s-1",
        -10,
        10,
        "current y: uniform value or surface value of the power law",
        0.0,
        location="environment.current.velocity[1]",
    ),
    _spec(
        "current.exponent",
        "1",
        0,
        1,
        "power-law exponent, U(h) = U_s (h/d)^exponent (seed 004 eq. (38))",
        1.0 / 7.0,
        incl=_OPEN_LOW,
        location="environment.current.exponent",
    ),
    # --- sediment -------------------------------------------------------------
    _spec("sediment.density", "kg m-3", 1000, 2700, "linear profile: bulk density at the seabed"),
    _spec("sediment.density_gradient", "kg m-4", 0, 1e4, "linear profile: density gradient", 0.0),
    _spec("sediment.strength", "Pa", 0, 1e6, "linear profile: undrained shear strength at the seabed"),
    _spec("sediment.strength_gradient", "Pa m-1", 0, 1e6, "linear profile: strength gradient", 0.0),
    _spec("sediment.impact_factor", "1", 1, 100, "A of seed 000 eq. (70), (72)", 10.0),
    _spec("sediment.rest_speed", "m s-1", 0, 10, "V_rest of seed 000 eq. (70), (72)", 0.04, incl=_OPEN_LOW),
    _spec(
        "sediment.rate_coefficient",
        "1",
        0,
        2,
        "beta of the semi-logarithmic rate law, per log10 cycle of strain rate (~0.1: Kulhawy & Mayne 1990)",
        0.1,
    ),
    _spec(
        "sediment.reference_rate",
        "s-1",
        0,
        1e6,
        "reference strain rate of the semi-logarithmic law (1 %/h lab rate)",
        LAB_STRAIN_RATE,
        incl=_OPEN_LOW,
    ),
    _spec(
        "sediment.friction",
        "1",
        0,
        5,
        "mu, tangential/normal traction ratio (seed 004 Table 2 case 1: 0.3)",
        0.3,
    ),
    _spec(
        "sediment.bearing_factor",
        "1",
        0,
        50,
        "N_c, bearing-capacity factor (pi + 2, Prandtl 1920)",
        math.pi + 2.0,
        incl=_OPEN_LOW,
    ),
    _spec("sediment.rupture_length", "m", 0, 10, "B of seed 000 eq. (73)", 0.1, incl=_OPEN_LOW),
    _spec(
        "sediment.permeability",
        "m s-1",
        0,
        1,
        "k_p of seed 000 eq. (73) (1e-4, seed 000 ref. [15])",
        1e-4,
        incl=_OPEN_LOW,
    ),
    _spec("sediment.void_ratio", "1", 0, 20, "e_v of seed 000 eq. (73) (~0.5)", 0.5, incl=_OPEN_LOW),
    # --- numerics -------------------------------------------------------------
    _spec("numerics.dt", "s", 0, 1, "time step; also dt <= t_max and dt <= t_max_fall", 1e-3, incl=_OPEN_LOW),
    _spec(
        "numerics.t_max",
        "s",
        0,
        1e6,
        "limit on the simulated time after the mine first touches the seabed (time_limit)",
        60.0,
        incl=_OPEN_LOW,
    ),
    _spec(
        "numerics.t_max_fall",
        "s",
        0,
        1e6,
        "limit on the simulated time of the fall, from release to the first seabed contact",
        600.0,
        incl=_OPEN_LOW,
    ),
    _spec(
        "numerics.rest_speed",
        "m s-1",
        0,
        10,
        "rest criterion on the COM speed (seed 000 eq. (89), epsilon_1); the sediment's "
        "hold is probed at this speed",
        1e-2,
        incl=_OPEN_LOW,
    ),
    _spec(
        "numerics.rest_spin", "rad s-1", 0, 100, "rest criterion on the angular speed", 5e-2, incl=_OPEN_LOW
    ),
    _spec(
        "numerics.munk_factor",
        "1",
        0,
        1,
        "fraction of the potential-flow Munk moment kept by the added-mass tensor "
        "(0: isotropic translational added mass, no Munk moment; 1: slender-body strip "
        "theory); see docs/physics.md",
        0.0,
    ),
    _spec(
        "numerics.rtol",
        "1",
        0,
        0.1,
        "relative tolerance of the adaptive integrators (dopri5, dopri5_ros34pw2), per step on "
        "position, velocity, attitude and angular velocity; default 3e-4 for numerics.model = "
        "'mineburial', 1e-5 for 'impact35'",
        3e-4,
        incl=_OPEN_LOW,
    ),
    _spec(
        "numerics.atol",
        "1",
        0,
        1.0,
        "absolute tolerance of the adaptive integrators, in m, m s-1, 1 (quaternion) and rad s-1; "
        "default 3e-5 for numerics.model = 'mineburial', 1e-6 for 'impact35'",
        3e-5,
        incl=_OPEN_LOW,
    ),
    _spec(
        "numerics.slip_speed",
        "m s-1",
        0,
        0.1,
        "regularisation speed of the slip direction of the sediment's tangential traction "
        "(seed 000 eq. (67)): it ramps up over this slip speed (docs/design.md)",
        5e-3,
        incl=_OPEN_LOW,
    ),
    _spec(
        "numerics.switch_speed",
        "m s-1",
        0,
        0.1,
        "regularisation speed of the advancing switch of seed 000 eq. (65): the normal "
        "traction ramps up over this normal speed (docs/design.md)",
        5e-3,
        incl=_OPEN_LOW,
    ),
    # --- post-impact scour, the optional [scour] section (docs/scour.md): no kernel slot of the
    # impact phase; packed into the stage's own parameters by mineburial/ensembles/scour.py
    _spec(
        "scour.d50",
        "m",
        6.25e-5,
        2e-3,
        "median grain size of the bed's sand (Wentworth's sand, 0.0625-2 mm: the scour laws are of "
        "non-cohesive sand, docs/scour.md)",
        2e-4,
    ),
    _spec("scour.grain_density", "kg m-3", 1200, 8000, "density of the sand grains (quartz 2650)", 2650),
    _spec(
        "scour.mobile_layer",
        "m",
        0,
        100,
        "thickness of the mobile sand layer over a bed scour cannot dig (absent: unlimited)",
        incl=_OPEN_LOW,
    ),
    _spec(
        "scour.beq_a",
        "1",
        0,
        100,
        "a of the equilibrium burial B_eq/D = a theta^b (Rennie, Brandt & Friedrichs 2017: 1.3 for "
        "D > 8 cm, 15 for small or tapered objects)",
        1.3,
        incl=_OPEN_LOW,
    ),
    _spec(
        "scour.beq_b",
        "1",
        0,
        3,
        "b of B_eq/D = a theta^b (Rennie et al. 2017: 0.36; 1.1)",
        0.36,
        incl=_OPEN_LOW,
    ),
    _spec(
        "scour.theta_exponent",
        "1",
        -5,
        0,
        "exponent p of the Shields parameter in the time scale T* = c KC^m theta^p (default: the "
        "T* law's, Whitehouse 1998 -1.29; uncertain between about -1.3 and -2.2)",
    ),
    _spec(
        "scour.hs_scale",
        "1",
        0,
        10,
        "factor on every significant wave height of the forcing (forcing uncertainty)",
        1.0,
        incl=_OPEN_LOW,
    ),
    _spec(
        "scour.window_position",
        "1",
        0,
        1,
        "where each drop's window of scour.window_days starts in the forcing: 0 its first record, "
        "1 the last start that fits (a uniform draw is a start date drawn from a long series)",
        0.0,
    ),
]

#: dotted path -> FieldSpec for every numeric scalar field of a scenario.
FIELDS: dict[str, FieldSpec] = {s.path: s for s in _FIELD_LIST}

#: alternative spellings accepted by :func:`check_range`: the scenario-file locations
#: (``release.position[2]``) and ``environment.current.*`` for ``current.*``.
ALIASES: dict[str, str] = {}
for _s in _FIELD_LIST:
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
    of field ``path`` (:data:`FIELDS`; aliases accepted). Cross-field constraints
    (|chi| < L/2, J1 <= 2 J2, z > -H, dt <= t_max and t_max_fall) are checked by :func:`check_params`."""
    return _spec_for(path).contains(values)


# ===========================================================================
# Distributions and sampled values against the field table (ensembles)
# ===========================================================================
#: The largest probability that a continuous distribution of a numeric field may put
#: outside the field's allowed range (the tails of a normal on a positive field); more is
#: refused when the scenario is loaded (:func:`check_distribution`). A draw in the
#: tolerated tail is still caught: :func:`check_samples` marks its drop invalid and
#: :func:`invalid_samples` counts it.
SUPPORT_TOLERANCE = 1e-6


def _field_for(path: str) -> FieldSpec | None:
    return FIELDS.get(ALIASES.get(path, path))


def _label(location: str, spec: FieldSpec) -> str:
    return location if location == spec.path else f"{location} ({spec.path})"


def _inline(d: Mapping) -> str:
    """A distribution table as the inline TOML a user writes (long lists shortened)."""

    def value(v):
        if isinstance(v, (list, tuple)):
            items = [value(x) for x in v[:6]] + (["..."] if len(v) > 6 else [])
            return "[" + ", ".join(items) + "]"
        return json.dumps(v) if isinstance(v, str) else f"{v:g}"

    return "{" + ", ".join(f"{k} = {value(v)}" for k, v in d.items()) + "}"


def check_distribution(path: str, distribution) -> None:
    """Check the distribution of field ``path`` against the field's allowed range.

    ``distribution`` is a :class:`mineburial.ensembles.distributions.Distribution`.
    A continuous one may put at most :data:`SUPPORT_TOLERANCE` of its probability
    outside the range (a normal(750, 15) on the mass is fine, a uniform(-10, 10) or a
    normal(1, 1) is not); a discrete one (``choice``, ``empirical``) none at all: every
    value it can draw must be allowed. Nothing is truncated on the user's behalf: a
    ``truncated_normal`` or a ``uniform`` with its bounds inside the range is the way to
    say so. Raises :class:`ScenarioError` naming the field, the distribution, the
    probability outside and the allowed range. Fields without a range (labels, or
    names that are not fields) are left to the caller.
    """
    spec = _field_for(path)
    if spec is None or getattr(distribution, "categorical", False):
        return
    p = distribution.probability_outside(spec.low, spec.high, spec.low_inclusive, spec.high_inclusive)
    tolerance = 0.0 if distribution.discrete else SUPPORT_TOLERANCE
    if p <= tolerance:
        return
    label = f"{_label(path, spec)} = {_inline(distribution.to_dict())}"
    if distribution.discrete:
        values = np.asarray(distribution.values, dtype=np.float64)
        bad = values[~spec.contains(values)]
        raise ScenarioError(
            f"{label}: {bad.size} of its {values.size} values lie outside the allowed range "
            f"{spec.range_text()} (probability {p:.3g}), e.g. {float(bad[0]):g}"
        )
    raise ScenarioError(
        f"{label} puts probability {p:.3g} outside the allowed range {spec.range_text()} "
        f"(at most {SUPPORT_TOLERANCE:g} may lie outside): narrow it, or bound it inside the "
        f"range (a uniform's or a truncated_normal's low and high)"
    )


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
def _range_error(
    location: str,
    path: str,
    value: float,
    spec: FieldSpec,
    *,
    low=None,
    high=None,
    low_inclusive=None,
    note: str = "",
) -> ScenarioError:
    label = location if location == path else f"{location} ({path})"
    units = "" if spec.units == "1" else f" {spec.units}"
    extra = f" ({note})" if note else ""
    return ScenarioError(
        f"{label} = {value!r}{units} is outside the allowed range "
        f"{spec.range_text(low, high, low_inclusive)}{extra}"
    )


def _number(value, location: str, units: str = "") -> float:
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, (int, float, np.integer, np.floating)):
        u = f" ({units})" if units and units != "1" else ""
        hint = (
            (': an inline table is a distribution only with distribution = "..." (docs/scenario.md)')
            if isinstance(value, Mapping)
            else ""
        )
        raise ScenarioError(f"{location} = {value!r} must be a number{u}{hint}")
    return float(value)


def _check(path: str, value, location: str | None = None) -> float:
    spec = FIELDS[path]
    loc = location or spec.location
    v = _number(value, loc, spec.units)
    if not spec.contains(v):
        raise _range_error(loc, path, v, spec)
    return v


def _vector(value, n: int, location: str) -> tuple[float, ...]:
    if isinstance(value, (str, bytes)) or not hasattr(value, "__len__") or len(value) != n:
        raise ScenarioError(f"{location} = {value!r} must be a list of {n} numbers")
    return tuple(_number(x, f"{location}[{i}]") for i, x in enumerate(value))


def _choice(value, allowed, location: str) -> str:
    if not isinstance(value, str) or value not in allowed:
        raise ScenarioError(f"{location}: " + unknown_name_message("name", value, allowed))
    return value


def _set(obj, name, value):
    object.__setattr__(obj, name, value)


# ===========================================================================
# Mass properties
# ===========================================================================
def uniform_cylinder_inertia(mass, diameter, length):
    """(J1, J2) of a uniform solid cylinder about its centre: m R^2/2 about the axis and
    m (3 R^2 + L^2)/12 about a transverse axis. Scalars or numpy arrays.

    The one formula of the default inertia (:class:`Mine` and the ensembles that vary the
    mass or size). ``length ** 2`` is kept as written: a Python float squares with ``pow``
    and an array with ``x * x``, which is what each caller has always computed.
    """
    r = diameter / 2.0
    return mass * r * r / 2.0, mass * (3.0 * r * r + length**2) / 12.0


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


def _lowest_point(length, diameter, com_offset, q, z) -> np.ndarray:
    """Height of the lowest point of the cylinder whose COM is at height ``z`` with
    attitude ``q`` (..., 4), by the kernel the stepper's seabed-contact event uses
    (kernels/geometry.py ``vertical_extent``); arrays broadcast."""
    q = np.asarray(q, dtype=np.float64)
    q0, q1, q2, q3 = np.moveaxis(q, -1, 0)
    a_z = 2.0 * (q1 * q3 - q0 * q2) / (q0 * q0 + q1 * q1 + q2 * q2 + q3 * q3)  # i_M . k
    args = np.broadcast_arrays(
        *(np.asarray(x, dtype=np.float64) for x in (length, diameter, com_offset, a_z, z))
    )
    rows = zip(*(x.ravel().tolist() for x in args))
    return np.array(
        [vertical_extent(L, 0.5 * d, chi, a, zc)[0] for L, d, chi, a, zc in rows], dtype=np.float64
    ).reshape(args[0].shape)


# ===========================================================================
# Dataclasses
# ===========================================================================
@dataclass(frozen=True, kw_only=True)
class Mine:
    """The rigid cylinder (seed 000 sec. 2, Table 2). SI units.

    ``inertia_axial`` / ``inertia_transverse`` left as ``None`` are replaced on
    construction by those of a uniform cylinder (m R^2/2, m (3R^2 + L^2)/12); pass
    ``None`` again through ``dataclasses.replace`` to recompute them after changing the
    mass or size.
    """

    length: float
    diameter: float
    mass: float
    com_offset: float = 0.0
    inertia_axial: float | None = None
    inertia_transverse: float | None = None
    name: str = "mine"

    def __post_init__(self):
        if not isinstance(self.name, str):
            raise ScenarioError(f"mine.name = {self.name!r} must be a string")
        for f in ("length", "diameter", "mass", "com_offset"):
            _set(self, f, _check(f"mine.{f}", getattr(self, f)))
        j1, j2 = uniform_cylinder_inertia(self.mass, self.diameter, self.length)
        if self.inertia_axial is None:
            _set(self, "inertia_axial", j1)
        if self.inertia_transverse is None:
            _set(self, "inertia_transverse", j2)
        for f in ("inertia_axial", "inertia_transverse"):
            _set(self, f, _check(f"mine.{f}", getattr(self, f)))
        half = self.length / 2.0
        if not abs(self.com_offset) < half:
            raise _range_error(
                "mine.com_offset",
                "mine.com_offset",
                self.com_offset,
                FIELDS["mine.com_offset"],
                low=-half,
                high=half,
                note="|chi| < length/2: the COM lies inside the body",
            )
        if not self.inertia_axial <= 2.0 * self.inertia_transverse:
            raise _range_error(
                "mine.inertia_axial",
                "mine.inertia_axial",
                self.inertia_axial,
                FIELDS["mine.inertia_axial"],
                high=2.0 * self.inertia_transverse,
                note="J1 <= 2 J2 = 2 * mine.inertia_transverse, triangle inequality of a rigid body",
            )

    @property
    def radius(self) -> float:
        return self.diameter / 2.0

    @property
    def volume(self) -> float:
        return math.pi * self.radius**2 * self.length

    @property
    def density(self) -> float:
        """Mean density m / (pi R^2 L) [kg m-3]."""
        return self.mass / self.volume

    def to_dict(self) -> dict:
        return {
            "name": self.name,
            "length": self.length,
            "diameter": self.diameter,
            "mass": self.mass,
            "com_offset": self.com_offset,
            "inertia_axial": self.inertia_axial,
            "inertia_transverse": self.inertia_transverse,
        }


_ANGLES = ("roll_deg", "pitch_deg", "heading_deg")


@dataclass(frozen=True, kw_only=True)
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
    embedded: bool = False

    def __post_init__(self):
        if not isinstance(self.embedded, (bool, np.bool_)):
            raise ScenarioError(f"release.embedded = {self.embedded!r} must be true or false")
        _set(self, "embedded", bool(self.embedded))
        for name, paths in (
            ("position", ("release.x", "release.y", "release.z")),
            ("velocity", ("release.u", "release.v", "release.w")),
            ("angular_velocity", ("release.omega1", "release.omega2", "release.omega3")),
        ):
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
        d = {"position": list(self.position), "velocity": list(self.velocity)}
        if self.quaternion is not None:
            d["quaternion"] = list(self.quaternion)
        else:
            for a in _ANGLES:
                d[a] = getattr(self, a)
        d["angular_velocity"] = list(self.angular_velocity)
        d["embedded"] = self.embedded
        return d


_CURRENT_KEYS = {
    "none": ("kind",),
    "uniform": ("kind", "velocity"),
    "power_law": ("kind", "surface_velocity", "exponent"),
    "table": ("kind", "depth", "u", "v"),
}


@dataclass(frozen=True, kw_only=True)
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

    kind: str = "none"
    u: float = 0.0
    v: float = 0.0
    exponent: float = 1.0 / 7.0
    depth: tuple = ()
    table_u: tuple = ()
    table_v: tuple = ()

    def __post_init__(self):
        kind = _choice(self.kind, layout.CURRENT_KINDS, "environment.current.kind")
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
        if kind != "power_law" and self.exponent != 1.0 / 7.0:
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
        if self.kind == "none":
            return {"kind": "none"}
        if self.kind == "uniform":
            return {"kind": "uniform", "velocity": [self.u, self.v]}
        if self.kind == "power_law":
            return {"kind": "power_law", "surface_velocity": [self.u, self.v], "exponent": self.exponent}
        return {"kind": "table", "depth": list(self.depth), "u": list(self.table_u), "v": list(self.table_v)}


@dataclass(frozen=True, kw_only=True)
class Environment:
    """Fluids, gravity, water depth (the seabed is at z = -water_depth) and current."""

    water_depth: float
    gravity: float = 9.81
    air_density: float = 1.225
    air_viscosity: float = 1.5e-5
    water_density: float = 1025.0
    water_viscosity: float = 1.05e-6
    current: Current = field(default_factory=Current)

    def __post_init__(self):
        for f in (
            "water_depth",
            "gravity",
            "air_density",
            "air_viscosity",
            "water_density",
            "water_viscosity",
        ):
            _set(self, f, _check(f"environment.{f}", getattr(self, f)))
        if not isinstance(self.current, Current):
            raise ScenarioError(f"environment.current = {self.current!r} must be a Current")

    def to_dict(self) -> dict:
        d = {
            f: getattr(self, f)
            for f in (
                "gravity",
                "air_density",
                "air_viscosity",
                "water_density",
                "water_viscosity",
                "water_depth",
            )
        }
        d["current"] = self.current.to_dict()
        return d


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

_SED_OPTIONS = (
    "impact_factor",
    "rest_speed",
    "rate_coefficient",
    "reference_rate",
    "friction",
    "bearing_factor",
    "rupture_length",
    "permeability",
    "void_ratio",
)
_SED_LINEAR = ("density", "density_gradient", "strength", "strength_gradient")


@dataclass(frozen=True, kw_only=True)
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
    impact_factor: float = 10.0
    rest_speed: float = 0.04
    rate_coefficient: float = 0.1
    reference_rate: float = LAB_STRAIN_RATE
    friction: float = 0.3
    bearing_factor: float = math.pi + 2.0
    pore_pressure: bool = False
    rupture_length: float = 0.1
    permeability: float = 1e-4
    void_ratio: float = 0.5

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
        if self.resistance is not None:
            _choice(self.resistance, layout.RESISTANCE_NAMES, "sediment.resistance")
        if self.rate_law is not None:
            _choice(self.rate_law, layout.RATE_LAW_NAMES, "sediment.rate_law")
        for f in _SED_OPTIONS:
            _set(self, f, _check(f"sediment.{f}", getattr(self, f)))
        if not isinstance(self.pore_pressure, (bool, np.bool_)):
            raise ScenarioError(f"sediment.pore_pressure = {self.pore_pressure!r} must be true or false")
        _set(self, "pore_pressure", bool(self.pore_pressure))

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
        d: dict[str, Any] = {}
        if self.profile is not None:
            d["profile"] = self.profile.to_dict()
        else:
            d.update({f: getattr(self, f) for f in _SED_LINEAR})
        if self.resistance is not None:
            d["resistance"] = self.resistance
        if self.rate_law is not None:
            d["rate_law"] = self.rate_law
        d.update({f: getattr(self, f) for f in _SED_OPTIONS})
        d["pore_pressure"] = self.pore_pressure
        return d


@dataclass(frozen=True, kw_only=True)
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
    kernels/overburden.py).
    The time limits are two, one for each phase of a drop: ``t_max_fall`` bounds the fall
    through air and water (release to the first seabed contact), ``t_max`` the time after
    that contact. A fall ends by itself at the seabed (or when a mine lighter than the water
    floats), however slowly the mine sinks, so the fall has its own, generous limit, and
    ``t_max`` guards only the motion in the sediment (docs/design.md, "The end of a drop").
    """

    model: str = "mineburial"
    integrator: str | None = None
    dt: float = 1e-3
    t_max: float = 60.0
    t_max_fall: float = 600.0
    rest_speed: float = 1e-2
    rest_spin: float = 5e-2
    drag: bool = True
    munk_factor: float = 0.0
    rtol: float | None = None
    atol: float | None = None
    sediment_quadrature: str = "fast"
    slip_speed: float = 5e-3
    switch_speed: float = 5e-3
    water_column: str = "munk_factor"
    overburden_quadrature: str = "fast"

    def __post_init__(self):
        _choice(self.model, layout.MODEL_NAMES, "numerics.model")
        _choice(self.water_column, layout.WATER_COLUMN_NAMES, "numerics.water_column")
        for f in ("integrator", "rtol", "atol"):
            if getattr(self, f) is None:
                _set(self, f, MODEL_DEFAULTS[self.model][f])
        _choice(self.integrator, layout.INTEGRATOR_NAMES, "numerics.integrator")
        _choice(self.sediment_quadrature, layout.SEDIMENT_QUADRATURE_NAMES, "numerics.sediment_quadrature")
        _choice(
            self.overburden_quadrature, layout.OVERBURDEN_QUADRATURE_NAMES, "numerics.overburden_quadrature"
        )
        for f in (
            "dt",
            "t_max",
            "t_max_fall",
            "rest_speed",
            "rest_spin",
            "munk_factor",
            "rtol",
            "atol",
            "slip_speed",
            "switch_speed",
        ):
            _set(self, f, _check(f"numerics.{f}", getattr(self, f)))
        for limit in ("t_max", "t_max_fall"):
            if not self.dt <= getattr(self, limit):
                raise _range_error(
                    "numerics.dt",
                    "numerics.dt",
                    self.dt,
                    FIELDS["numerics.dt"],
                    high=min(1.0, getattr(self, limit)),
                    note=f"dt <= numerics.{limit}",
                )
        if not isinstance(self.drag, (bool, np.bool_)):
            raise ScenarioError(f"numerics.drag = {self.drag!r} must be true or false")
        _set(self, "drag", bool(self.drag))

    def to_dict(self) -> dict:
        return {f.name: getattr(self, f.name) for f in dataclasses.fields(self)}


# ===========================================================================
# Scenario
# ===========================================================================
_SECTIONS = ("description", "mine", "release", "environment", "sediment", "numerics")
_MINE_KEYS = ("name", "length", "diameter", "mass", "com_offset", "inertia_axial", "inertia_transverse")
_RELEASE_KEYS = (
    "position",
    "velocity",
    "angular_velocity",
    "roll_deg",
    "pitch_deg",
    "heading_deg",
    "quaternion",
    "embedded",
)
_ENV_KEYS = (
    "gravity",
    "air_density",
    "air_viscosity",
    "water_density",
    "water_viscosity",
    "water_depth",
    "current",
)
_SED_SOURCES = ("class", "profile", "file")
_SED_KEYS = _SED_SOURCES + _SED_LINEAR + ("resistance", "rate_law", "pore_pressure") + _SED_OPTIONS
_NUM_KEYS = tuple(f.name for f in dataclasses.fields(Numerics))


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
        z, depth = self.release.position[2], self.environment.water_depth
        if not z > -depth:
            raise _range_error(
                "release.position[2]",
                "release.z",
                z,
                FIELDS["release.z"],
                low=-depth,
                low_inclusive=False,
                note="the COM must start above the seabed, z > -environment.water_depth",
            )
        m = self.mine
        lowest = float(_lowest_point(m.length, m.diameter, m.com_offset, self.release.q, z))
        if not self.release.embedded and lowest < -depth:
            raise ScenarioError(
                f"release.position[2] = {z!r} m starts the mine {-depth - lowest:.3g} m inside "
                f"the seabed (its lowest point at z = {lowest:.6g} m, the seabed at "
                f"-environment.water_depth = {-depth:g} m), so it has no impact: release it "
                f"at least that much higher, or set release.embedded = true for a mine placed "
                f"in the sediment"
            )

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
        _required(mine, "mine", ("length", "diameter", "mass"))
        release = _section(d, "release", _RELEASE_KEYS)
        env = _section(d, "environment", _ENV_KEYS, required=True)
        _required(env, "environment", ("water_depth",))
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
        """``(p, sediment_bank, current_bank)`` for the kernels (kernels/layout.py).

        ``p`` has every slot of ``PARAM_NAMES`` filled; codes are indices into the name
        tuples of layout.py. A tabulated sediment profile is row 0 of a one-row bank
        (``sediment.profile_index = 0``; the linear slots then hold its seabed values and
        first-segment gradients, for information); a linear profile gives an empty bank and
        index -1. Likewise a ``table`` current is row 0 of ``current_bank``.
        """
        m, r, e, c, s, n = (
            self.mine,
            self.release,
            self.environment,
            self.environment.current,
            self.sediment,
            self.numerics,
        )
        q = r.q
        if s.profile is not None:
            rho0, krho, s0, ks = s.profile.surface_gradients()
            sed_bank, sed_index = pack_banks([s.profile]), 0
        else:
            rho0, krho, s0, ks = s.density, s.density_gradient, s.strength, s.strength_gradient
            sed_bank, sed_index = pack_banks([]), -1
        if c.kind == "table":
            cur_bank, cur_index = pack_banks([c]), 0
        else:
            cur_bank, cur_index = pack_banks([]), -1
        values = {
            "mine.length": m.length,
            "mine.diameter": m.diameter,
            "mine.mass": m.mass,
            "mine.com_offset": m.com_offset,
            "mine.inertia_axial": m.inertia_axial,
            "mine.inertia_transverse": m.inertia_transverse,
            "release.x": r.position[0],
            "release.y": r.position[1],
            "release.z": r.position[2],
            "release.u": r.velocity[0],
            "release.v": r.velocity[1],
            "release.w": r.velocity[2],
            "release.q0": q[0],
            "release.q1": q[1],
            "release.q2": q[2],
            "release.q3": q[3],
            "release.omega1": r.angular_velocity[0],
            "release.omega2": r.angular_velocity[1],
            "release.omega3": r.angular_velocity[2],
            "environment.gravity": e.gravity,
            "environment.air_density": e.air_density,
            "environment.air_viscosity": e.air_viscosity,
            "environment.water_density": e.water_density,
            "environment.water_viscosity": e.water_viscosity,
            "environment.water_depth": e.water_depth,
            "current.kind": layout.CURRENT_KINDS.index(c.kind),
            "current.u": c.u,
            "current.v": c.v,
            "current.exponent": c.exponent,
            "current.table_index": cur_index,
            "sediment.profile_index": sed_index,
            "sediment.density": rho0,
            "sediment.density_gradient": krho,
            "sediment.strength": s0,
            "sediment.strength_gradient": ks,
            "sediment.resistance": layout.RESISTANCE_NAMES.index(s.resistance),
            "sediment.rate_law": layout.RATE_LAW_NAMES.index(s.rate_law),
            "sediment.pore_pressure": float(s.pore_pressure),
            "numerics.model": layout.MODEL_NAMES.index(n.model),
            "numerics.integrator": layout.INTEGRATOR_NAMES.index(n.integrator),
            "numerics.dt": n.dt,
            "numerics.t_max": n.t_max,
            "numerics.t_max_fall": n.t_max_fall,
            "numerics.rest_speed": n.rest_speed,
            "numerics.rest_spin": n.rest_spin,
            "numerics.drag": float(n.drag),
            "numerics.munk_factor": n.munk_factor,
            "numerics.rtol": n.rtol,
            "numerics.atol": n.atol,
            "numerics.slip_speed": n.slip_speed,
            "numerics.switch_speed": n.switch_speed,
            "numerics.sediment_quadrature": layout.SEDIMENT_QUADRATURE_NAMES.index(n.sediment_quadrature),
            "numerics.water_column": layout.WATER_COLUMN_NAMES.index(n.water_column),
            "numerics.overburden_quadrature": layout.OVERBURDEN_QUADRATURE_NAMES.index(
                n.overburden_quadrature
            ),
        }
        for f in _SED_OPTIONS:
            values[f"sediment.{f}"] = getattr(s, f)
        missing = set(layout.PARAM_NAMES) - set(values)
        extra = set(values) - set(layout.PARAM_NAMES)
        if missing or extra:  # pragma: no cover - guards layout changes
            raise RuntimeError(
                f"to_params is out of step with layout.PARAM_NAMES: missing "
                f"{sorted(missing)}, unknown {sorted(extra)}"
            )
        p = np.empty(layout.N_PARAMS, dtype=np.float64)
        for name, value in values.items():
            p[layout.INDEX[name]] = value
        return p, sed_bank, cur_bank


def _current_from_dict(cur) -> Current:
    if not isinstance(cur, Mapping):
        raise ScenarioError(f"environment.current must be a table, got {cur!r}")
    kind = cur.get("kind", "none")
    kind = _choice(kind, layout.CURRENT_KINDS, "environment.current.kind")
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
        return Current(kind=kind, u=u, v=v, exponent=cur.get("exponent", 1.0 / 7.0))
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
_CODE_LIMITS = {
    "current.kind": len(layout.CURRENT_KINDS),
    "sediment.resistance": len(layout.RESISTANCE_NAMES),
    "sediment.rate_law": len(layout.RATE_LAW_NAMES),
    "numerics.model": len(layout.MODEL_NAMES),
    "numerics.integrator": len(layout.INTEGRATOR_NAMES),
    "numerics.sediment_quadrature": len(layout.SEDIMENT_QUADRATURE_NAMES),
    "numerics.water_column": len(layout.WATER_COLUMN_NAMES),
    "numerics.overburden_quadrature": len(layout.OVERBURDEN_QUADRATURE_NAMES),
    "sediment.pore_pressure": 2,
    "numerics.drag": 2,
}


def _param_checks(P: np.ndarray, n_sediment, n_current, embedded=False):
    """List of (text, slot names involved, ok mask) over rows of P."""
    P = np.atleast_2d(np.asarray(P, dtype=np.float64))
    if P.ndim != 2 or P.shape[-1] != layout.N_PARAMS:
        raise ScenarioError(f"parameter rows must have {layout.N_PARAMS} columns, got shape {P.shape}")
    col = {name: P[:, i] for i, name in enumerate(layout.PARAM_NAMES)}
    checks = []
    tabulated = col["sediment.profile_index"] != -1
    for name in layout.PARAM_NAMES:
        spec = FIELDS.get(name)
        if spec is None:
            continue
        ok = spec.contains(col[name])
        if name in (
            "sediment.density",
            "sediment.density_gradient",
            "sediment.strength",
            "sediment.strength_gradient",
        ):
            ok |= tabulated & np.isfinite(col[name])  # informational for tables
        checks.append((f"{name} in {spec.range_text()}", (name,), ok))
    for name, n in _CODE_LIMITS.items():
        v = col[name]
        checks.append(
            (f"{name} is an integer code in [0, {n - 1}]", (name,), (v == np.floor(v)) & (v >= 0) & (v < n))
        )
    for name, n in (("sediment.profile_index", n_sediment), ("current.table_index", n_current)):
        v = col[name]
        ok = (v == np.floor(v)) & (v >= -1)
        if n is not None:
            ok &= v < n
        bound = f" < {n}" if n is not None else ""
        checks.append((f"{name} is -1 or a bank row{bound}", (name,), ok))
    checks.append(
        (
            "current.table_index >= 0 exactly when current.kind is 'table'",
            ("current.kind", "current.table_index"),
            (col["current.table_index"] >= 0) == (col["current.kind"] == layout.CURRENT_KINDS.index("table")),
        )
    )
    checks.append(
        (
            "|mine.com_offset| < mine.length/2",
            ("mine.com_offset", "mine.length"),
            np.abs(col["mine.com_offset"]) < col["mine.length"] / 2,
        )
    )
    checks.append(
        (
            "mine.inertia_axial <= 2 mine.inertia_transverse",
            ("mine.inertia_axial", "mine.inertia_transverse"),
            col["mine.inertia_axial"] <= 2 * col["mine.inertia_transverse"],
        )
    )
    checks.append(
        (
            "release.z > -environment.water_depth",
            ("release.z", "environment.water_depth"),
            col["release.z"] > -col["environment.water_depth"],
        )
    )
    if not embedded:
        q = np.stack([col[f"release.q{i}"] for i in range(4)], axis=-1)
        with np.errstate(invalid="ignore", divide="ignore"):
            lowest = _lowest_point(
                col["mine.length"], col["mine.diameter"], col["mine.com_offset"], q, col["release.z"]
            )
        checks.append(
            (
                "the mine starts entirely above the seabed (release.embedded = false)",
                (
                    "release.z",
                    "environment.water_depth",
                    "mine.length",
                    "mine.diameter",
                    "mine.com_offset",
                    "release.q0",
                    "release.q1",
                    "release.q2",
                    "release.q3",
                ),
                lowest >= -col["environment.water_depth"],
            )
        )
    qn = np.sqrt(sum(col[f"release.q{i}"] ** 2 for i in range(4)))
    checks.append(
        (
            "the release quaternion has unit norm (within 1e-9)",
            tuple(f"release.q{i}" for i in range(4)),
            np.abs(qn - 1) <= 1e-9,
        )
    )
    for limit in ("numerics.t_max", "numerics.t_max_fall"):
        checks.append((f"numerics.dt <= {limit}", ("numerics.dt", limit), col["numerics.dt"] <= col[limit]))
    return checks


def check_params(
    P, n_sediment: int | None = None, n_current: int | None = None, *, embedded: bool = False
) -> np.ndarray:
    """Boolean mask over packed parameter rows ``P`` (shape (n, N_PARAMS) or (N_PARAMS,)):
    True where every slot is inside its :data:`FIELDS` range, codes are valid, bank
    indices are in range (when the bank sizes are given) and the cross-field constraints
    hold (|chi| < L/2, J1 <= 2 J2, z0 > -H, the whole mine above the seabed unless
    ``embedded`` (``release.embedded``), unit quaternion, dt <= t_max and t_max_fall). The ensemble
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
# Minimal TOML writer for to_dict() output
# ===========================================================================
def _toml_value(v) -> str:
    if isinstance(v, (bool, np.bool_)):
        return "true" if v else "false"
    if isinstance(v, (int, np.integer)):
        return str(int(v))
    if isinstance(v, (float, np.floating)):
        v = float(v)
        if math.isnan(v):
            return "nan"
        if math.isinf(v):
            return "inf" if v > 0 else "-inf"
        return repr(v)
    if isinstance(v, str):
        return json.dumps(v, ensure_ascii=False)
    if isinstance(v, (list, tuple)):
        return "[" + ", ".join(_toml_value(x) for x in v) + "]"
    raise TypeError(f"cannot write {type(v).__name__} to TOML")


def dumps_toml(d: Mapping, _prefix: str = "") -> str:
    """TOML text of a nested dict of scalars, lists and sub-dicts (sub-dicts become
    ``[a.b]`` tables)."""
    lines, tables = [], []
    for key, value in d.items():
        if isinstance(value, Mapping):
            tables.append((key, value))
        else:
            lines.append(f"{key} = {_toml_value(value)}")
    out = []
    if lines:
        if _prefix:
            out.append(f"[{_prefix}]")
        out.extend(lines)
        out.append("")
    for key, value in tables:
        out.append(dumps_toml(value, f"{_prefix}.{key}" if _prefix else key))
    return "\n".join(out)


# ===========================================================================
# Shipped example scenarios
# ===========================================================================
_DATA = pathlib.Path(__file__).resolve().parent / "data"


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
