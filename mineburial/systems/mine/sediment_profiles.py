"""Sediment profiles: tabulated bulk density and undrained shear strength against depth.

A :class:`SedimentProfile` holds three 1-D arrays

* ``depth``    depth below the seabed [m], strictly increasing, first point 0,
* ``density``  bulk density rho_s(z) [kg m-3] (seed 000 eq. (68)),
* ``strength`` undrained shear strength S(z) [Pa] (seed 000 eq. (69)),

and evaluates them piecewise linearly. **Below the last point the values are held
constant** (and above the seabed, z < 0, the seabed value is used): a core that
stops at 30 cm says nothing about deeper layers, and a constant is the least
inventive continuation. Give a deeper point if a trend must continue.

Profiles come from

* the :data:`CATALOGUE` of named sediment classes (:func:`catalogue_profile`),
* CSV cores (:func:`load_csv`; columns ``depth_m, density_kg_m3, strength_pa``),
* NetCDF cores (:func:`load_netcdf`; variables ``depth, density, strength`` with
  ``units`` attributes),
* inline tables in a scenario file, or :meth:`SedimentProfile.linear`.

Several profiles are stacked into the NaN-padded bank that the kernels read with
:func:`pack_banks` (layout in :mod:`mineburial.kernels.mine.layout`).

The error type :class:`ScenarioError` and the did-you-mean helpers live in the leaf
module :mod:`mineburial.errors`; they are importable from here too.
"""

from __future__ import annotations

import csv
import difflib
import math
import pathlib
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from mineburial._deferred import netCDF4
from mineburial.errors import ScenarioError, unknown_name_message, unknown_names_message
from mineburial.io import inputs
from mineburial.io.inputs import InputFileError

__all__ = [
    "ScenarioError",
    "SedimentProfile",
    "SedimentClass",
    "CATALOGUE",
    "catalogue_profile",
    "class_names",
    "load_csv",
    "load_netcdf",
    "load_file",
    "pack_banks",
    "DENSITY_RANGE",
    "STRENGTH_RANGE",
    "CATALOGUE_MAX_DEPTH",
    "nc_clay_strength_gradient",
    "bearing_capacity_factors",
    "drained_equivalent_strength",
]


def _rebuild_profile(depth, density, strength, name, description, source):
    return SedimentProfile(depth, density, strength, name=name, description=description, source=source)


#: Allowed bulk density of a sediment [kg m-3]: from (fresh) water to the grain
#: density of quartz/clay minerals (~2650-2700 kg m-3).
DENSITY_RANGE = (1000.0, 2700.0)
#: Allowed undrained shear strength [Pa]: 0 (fluid) to 1 MPa (hard clay).
STRENGTH_RANGE = (0.0, 1.0e6)
#: Depth [m] down to which catalogue classes are tabulated (constant below):
#: far deeper than any mine penetrates (seed 000 Exp-2 burial depths are cm to dm).
CATALOGUE_MAX_DEPTH = 10.0
#: Most points a tabulated profile read from a file may have (docs/scenario.md): a
#: millimetre-resolution core 1 km long.
MAX_PROFILE_POINTS = 1_000_000


def _fmt(x: float) -> str:
    return f"{x:g}"


def _as_vector(values, where: str) -> np.ndarray:
    try:
        a = np.array(values, dtype=np.float64)
    except (TypeError, ValueError):
        raise ScenarioError(f"{where} = {values!r} must be a list of numbers") from None
    if a.ndim != 1 or a.size == 0:
        raise ScenarioError(f"{where} must be a non-empty 1-D list of numbers, got shape {a.shape}")
    if not np.all(np.isfinite(a)):
        raise ScenarioError(f"{where} = {a.tolist()} contains non-finite values")
    return a


class SedimentProfile:
    """Piecewise-linear bulk density and undrained shear strength against depth below the seabed.

    Immutable: the arrays are read-only copies. Two profiles are equal when their arrays
    and labels are equal (so a :class:`mineburial.systems.mine.config.Scenario` holding one compares
    by value).

    Parameters
    ----------
    depth : depth below the seabed [m], strictly increasing, ``depth[0] == 0``.
    density : bulk density [kg m-3] in :data:`DENSITY_RANGE`.
    strength : undrained shear strength [Pa] in :data:`STRENGTH_RANGE`.
    name, description, source : provenance labels (free text).
    where : field path used in error messages (e.g. ``"sediment.profile"``).
    """

    __slots__ = ("depth", "density", "strength", "name", "description", "source")

    def __init__(
        self,
        depth,
        density,
        strength,
        *,
        name: str = "",
        description: str = "",
        source: str = "",
        where: str = "sediment.profile",
    ):
        d = _as_vector(depth, f"{where}.depth")
        rho = _as_vector(density, f"{where}.density")
        s = _as_vector(strength, f"{where}.strength")
        if not (d.size == rho.size == s.size):
            raise ScenarioError(
                f"{where}: depth, density and strength must have the same length, "
                f"got {d.size}, {rho.size}, {s.size}"
            )
        if d[0] != 0.0:
            raise ScenarioError(
                f"{where}.depth[0] = {float(d[0])!r} m: the first point must be at the seabed, "
                f"depth 0 m (add a row at depth 0, e.g. repeating the first slice)"
            )
        if d.size > 1 and not np.all(np.diff(d) > 0):
            i = int(np.argmin(np.diff(d) > 0)) + 1
            raise ScenarioError(
                f"{where}.depth[{i}] = {float(d[i])!r} m: depths must be strictly increasing "
                f"(previous point {float(d[i - 1])!r} m)"
            )
        for arr, key, (lo, hi), units in (
            (rho, "density", DENSITY_RANGE, "kg m-3"),
            (s, "strength", STRENGTH_RANGE, "Pa"),
        ):
            bad = np.flatnonzero((arr < lo) | (arr > hi))
            if bad.size:
                i = int(bad[0])
                raise ScenarioError(
                    f"{where}.{key}[{i}] = {float(arr[i])!r} {units} is outside the allowed range "
                    f"[{_fmt(lo)}, {_fmt(hi)}] {units}"
                )
        for arr in (d, rho, s):
            arr.flags.writeable = False
        set_ = object.__setattr__
        set_(self, "depth", d)
        set_(self, "density", rho)
        set_(self, "strength", s)
        set_(self, "name", str(name))
        set_(self, "description", str(description))
        set_(self, "source", str(source))

    def __reduce__(self):
        # picklable (dask workers) despite __slots__ and the read-only __setattr__
        return (
            _rebuild_profile,
            (
                self.depth.copy(),
                self.density.copy(),
                self.strength.copy(),
                self.name,
                self.description,
                self.source,
            ),
        )

    # -- immutability / value semantics ------------------------------------
    def __setattr__(self, key, value):
        raise AttributeError("SedimentProfile is immutable")

    def __eq__(self, other):
        if not isinstance(other, SedimentProfile):
            return NotImplemented
        return (
            np.array_equal(self.depth, other.depth)
            and np.array_equal(self.density, other.density)
            and np.array_equal(self.strength, other.strength)
            and (self.name, self.description, self.source) == (other.name, other.description, other.source)
        )

    def __hash__(self):
        return hash(
            (
                self.depth.tobytes(),
                self.density.tobytes(),
                self.strength.tobytes(),
                self.name,
                self.description,
                self.source,
            )
        )

    def __repr__(self):
        label = f" {self.name!r}" if self.name else ""
        return (
            f"SedimentProfile{label}({self.n_points} points, depth 0..{self.depth[-1]:g} m, "
            f"density {self.density.min():g}..{self.density.max():g} kg m-3, "
            f"strength {self.strength.min():g}..{self.strength.max():g} Pa)"
        )

    # -- evaluation --------------------------------------------------------
    @property
    def n_points(self) -> int:
        return int(self.depth.size)

    def evaluate(self, depth):
        """Bulk density [kg m-3] and strength [Pa] at ``depth`` [m] below the seabed.

        Piecewise linear between the points; constant beyond the last point and, for
        negative depths (above the seabed), equal to the seabed value (``numpy.interp``
        semantics).
        """
        z = np.asarray(depth, dtype=np.float64)
        return (np.interp(z, self.depth, self.density), np.interp(z, self.depth, self.strength))

    def as_array(self) -> np.ndarray:
        """The profile as a (3, n_points) array: depth, density, strength (one bank row)."""
        return np.stack([self.depth, self.density, self.strength])

    def surface_gradients(self) -> tuple[float, float, float, float]:
        """(density at 0, density gradient, strength at 0, strength gradient) of the first
        segment (zero gradients for a one-point profile): the linear description that is
        exact for catalogue classes."""
        if self.n_points == 1:
            return float(self.density[0]), 0.0, float(self.strength[0]), 0.0
        dz = self.depth[1] - self.depth[0]
        return (
            float(self.density[0]),
            float((self.density[1] - self.density[0]) / dz),
            float(self.strength[0]),
            float((self.strength[1] - self.strength[0]) / dz),
        )

    def to_dict(self) -> dict:
        """Plain dict (lists of floats, strings), the inline ``profile`` table of a scenario."""
        d = {}
        for key in ("name", "description", "source"):
            if getattr(self, key):
                d[key] = getattr(self, key)
        d["depth"] = self.depth.tolist()
        d["density"] = self.density.tolist()
        d["strength"] = self.strength.tolist()
        return d

    @classmethod
    def from_dict(cls, d: dict, where: str = "sediment.profile") -> SedimentProfile:
        allowed = {"depth", "density", "strength", "name", "description", "source"}
        if not isinstance(d, dict):
            raise ScenarioError(f"{where} must be a table with keys depth, density, strength")
        unknown = [key for key in d if key not in allowed]
        if unknown:
            raise ScenarioError(f"{where}: " + unknown_names_message("key", unknown, allowed))
        for key in ("depth", "density", "strength"):
            if key not in d:
                raise ScenarioError(f"{where}.{key} is required (a list of numbers)")
        return cls(
            d["depth"],
            d["density"],
            d["strength"],
            name=d.get("name", ""),
            description=d.get("description", ""),
            source=d.get("source", ""),
            where=where,
        )

    @classmethod
    def linear(
        cls,
        density: float,
        density_gradient: float,
        strength: float,
        strength_gradient: float,
        *,
        max_depth: float = CATALOGUE_MAX_DEPTH,
        **labels,
    ) -> SedimentProfile:
        """Two-point table of rho = rho0 + k_rho z, S = S0 + k_S z on [0, max_depth]
        (exact there, constant below)."""
        return cls(
            [0.0, max_depth],
            [density, density + density_gradient * max_depth],
            [strength, strength + strength_gradient * max_depth],
            **labels,
        )


# ---------------------------------------------------------------------------
# Loaders
# ---------------------------------------------------------------------------
CSV_COLUMNS = ("depth_m", "density_kg_m3", "strength_pa")


def load_csv(path, *, name: str | None = None) -> SedimentProfile:
    """Read a core from CSV: a header row naming ``depth_m, density_kg_m3, strength_pa``
    (any order, extra columns ignored), one row per point; lines starting with ``#`` are
    comments."""
    path = pathlib.Path(path)
    where = f"sediment.file '{path}'"
    try:
        rows = list(inputs.numbered_csv(inputs.read_text(path, "text"), as_wide_as_header=True))
    except OSError as exc:
        raise ScenarioError(f"{where}: cannot read the file ({exc.strerror})") from None
    except csv.Error as exc:
        raise ScenarioError(f"{where}: not a CSV table ({exc})") from None
    if not rows:
        raise ScenarioError(f"{where}: the file is empty")
    header = [h.strip() for h in rows[0][1]]
    cols = {}
    for col in CSV_COLUMNS:
        if col not in header:
            close = difflib.get_close_matches(col, header, n=1, cutoff=0.5)
            hint = f" (found '{close[0]}')" if close and inputs.column_names(close) else ""
            raise ScenarioError(
                f"{where}: missing column '{col}'{hint} in the header row (line {rows[0][0]}); "
                f"required columns: {', '.join(CSV_COLUMNS)}"
            )
        cols[col] = header.index(col)
    if len(rows) - 1 > MAX_PROFILE_POINTS:
        raise ScenarioError(f"{where}: {len(rows) - 1} data rows; at most {MAX_PROFILE_POINTS} are accepted")
    data = {c: [] for c in CSV_COLUMNS}
    for lineno, row in rows[1:]:
        for col, i in cols.items():
            try:
                data[col].append(float(row[i]))
            except (IndexError, ValueError):
                raise ScenarioError(
                    f"{where}: line {lineno}, column {i + 1} ('{col}'): "
                    + ("missing" if i >= len(row) else "not a number")
                ) from None
    return SedimentProfile(
        data["depth_m"],
        data["density_kg_m3"],
        data["strength_pa"],
        name=path.stem if name is None else name,
        source=f"file {path.resolve()}",
        where=where,
    )


# accepted spellings of the units attribute -> factor to SI
_UNITS = {
    "depth": (
        {"m": 1.0, "meter": 1.0, "meters": 1.0, "metre": 1.0, "metres": 1.0, "cm": 0.01, "mm": 1e-3},
        "m",
    ),
    "density": (
        {
            "kg m-3": 1.0,
            "kg/m3": 1.0,
            "kg m^-3": 1.0,
            "kg/m^3": 1.0,
            "kg m**-3": 1.0,
            "kg.m-3": 1.0,
            "g cm-3": 1000.0,
            "g/cm3": 1000.0,
            "g cm^-3": 1000.0,
            "g/cm^3": 1000.0,
        },
        "kg m-3",
    ),
    "strength": ({"pa": 1.0, "kpa": 1000.0, "n m-2": 1.0, "n/m2": 1.0}, "Pa"),
}


def load_netcdf(path, *, name: str | None = None) -> SedimentProfile:
    """Read a core from NetCDF: 1-D variables ``depth`` (below the seabed, positive down),
    ``density`` and ``strength``, each with a ``units`` attribute (m/cm/mm, kg m-3 or
    g cm-3, Pa or kPa; converted to SI)."""
    path = pathlib.Path(path)
    where = f"sediment.file '{path}'"
    try:
        inputs.check_input(path, "core")
        ds = netCDF4.Dataset(str(path), "r")
    except InputFileError as exc:
        raise ScenarioError(f"{where}: cannot read the file ({exc.strerror})") from None
    except OSError as exc:
        raise ScenarioError(f"{where}: cannot open as NetCDF ({exc})") from None
    try:
        arrays = {}
        for var, (table, si) in _UNITS.items():
            if var not in ds.variables:
                raise ScenarioError(
                    f"{where}: missing variable '{var}'; required variables: "
                    f"{', '.join(_UNITS)} (found: {', '.join(ds.variables)})"
                )
            v = ds.variables[var]
            units = getattr(v, "units", None)
            if units is None:
                raise ScenarioError(f"{where}: variable '{var}' has no units attribute (expected {si})")
            key = " ".join(str(units).split()).lower()
            if key not in table:
                raise ScenarioError(
                    f"{where}: variable '{var}' has units '{units}'; accepted: {', '.join(table)}"
                )
            if var == "depth" and str(getattr(v, "positive", "down")).lower() != "down":
                raise ScenarioError(
                    f"{where}: variable 'depth' must be positive down "
                    f"(depth below the seabed), got positive = '{v.positive}'"
                )
            if not (isinstance(v.dtype, np.dtype) and v.dtype.kind in "iuf"):  # str: text
                raise ScenarioError(f"{where}: variable '{var}' does not hold numbers (text or another type)")
            if len(v.dimensions) != 1:  # a core is one profile: a 2-D field is not flattened into one
                raise ScenarioError(
                    f"{where}: variable '{var}' has dimensions {tuple(v.dimensions)}; "
                    "a core's variables are 1-D over one depth dimension"
                )
            if v.size > MAX_PROFILE_POINTS:
                raise ScenarioError(
                    f"{where}: variable '{var}' has {v.size} points; "
                    f"at most {MAX_PROFILE_POINTS} are accepted"
                )
            try:
                data = np.ma.filled(np.ma.asarray(v[:], dtype=np.float64), np.nan).ravel()
            except (OSError, RuntimeError) as exc:  # netCDF4 reports a damaged file so
                raise ScenarioError(f"{where}: cannot read variable '{var}' ({exc})") from None
            arrays[var] = data * table[key]
    finally:
        ds.close()
    return SedimentProfile(
        arrays["depth"],
        arrays["density"],
        arrays["strength"],
        name=path.stem if name is None else name,
        source=f"file {path.resolve()}",
        where=where,
    )


def load_file(path, base_dir=None) -> SedimentProfile:
    """Load a core by extension (``.csv`` or ``.nc``/``.nc4``/``.cdf``), resolving a
    relative ``path`` against ``base_dir`` (the scenario file's folder)."""
    p = pathlib.Path(path)
    if not p.is_absolute() and base_dir is not None:
        p = pathlib.Path(base_dir) / p
    suffix = p.suffix.lower()
    if suffix == ".csv":
        return load_csv(p)
    if suffix in (".nc", ".nc4", ".cdf", ".netcdf"):
        return load_netcdf(p)
    raise ScenarioError(f"sediment.file = '{path}': unknown file type '{p.suffix}', expected .csv or .nc")


# ---------------------------------------------------------------------------
# Catalogue of sediment classes
# ---------------------------------------------------------------------------
RHO_SEAWATER = 1025.0  # kg m-3, reference pore/sea water for effective unit weights
G = 9.81  # m s-2
#: s_u / sigma'_v of normally consolidated clay: Mesri, G. (1975), discussion of
#: "New design procedure for stability of soft clays", J. Geotech. Eng. Div. ASCE
#: 101(GT4), 409-412 (s_u = 0.22 sigma'_p); also Ladd & Foott (1974) SHANSEP, 0.2-0.25.
SU_RATIO_NC = 0.22
#: Width [m] of the loaded body used to turn a drained bearing capacity into an
#: equivalent strength for silts and sands (a ~0.5 m diameter ground mine).
EQUIVALENT_WIDTH = 0.5
#: Bearing-capacity factor used for that conversion: N_c = pi + 2 (Prandtl 1920).
NC_SURFACE = math.pi + 2.0


def nc_clay_strength_gradient(density_mid: float) -> float:
    """Strength gradient [Pa m-1] of a normally consolidated clay,
    dS/dz = (s_u/sigma'_v) (rho - rho_w) g with s_u/sigma'_v = 0.22 (Mesri 1975)."""
    return SU_RATIO_NC * (density_mid - RHO_SEAWATER) * G


def bearing_capacity_factors(phi_deg: float) -> tuple[float, float, float]:
    """Drained bearing-capacity factors (N_c, N_q, N_gamma) for friction angle phi:
    N_q = e^(pi tan phi) tan^2(45 + phi/2) (Prandtl-Reissner), N_c = (N_q - 1) cot phi,
    N_gamma = 2 (N_q + 1) tan phi (Vesic 1973, J. Soil Mech. Found. Div. 99(SM1):45-73)."""
    t = math.tan(math.radians(phi_deg))
    nq = math.exp(math.pi * t) * math.tan(math.radians(45.0 + phi_deg / 2.0)) ** 2
    return (nq - 1.0) / t, nq, 2.0 * (nq + 1.0) * t


def drained_equivalent_strength(
    phi_deg: float, density: float, width: float = EQUIVALENT_WIDTH
) -> tuple[float, float]:
    """Crude undrained-strength proxy (S0 [Pa], dS/dz [Pa m-1]) for a cohesionless bed.

    The drained bearing capacity of a strip of width B embedded at depth z,
    q = 0.5 gamma' B N_gamma + gamma' z N_q (Terzaghi/Vesic), is divided by the
    undrained factor N_c = pi + 2 so that a clay model ``N_c S`` reproduces it:
    S0 = 0.5 gamma' B N_gamma / N_c, dS/dz = gamma' N_q / N_c. It ignores dilation,
    partial drainage and rate effects, which all matter for sand under impact.
    """
    _, nq, ng = bearing_capacity_factors(phi_deg)
    gamma_eff = (density - RHO_SEAWATER) * G
    return 0.5 * gamma_eff * width * ng / NC_SURFACE, gamma_eff * nq / NC_SURFACE


@dataclass(frozen=True)
class SedimentClass:
    """A named sediment class with linear profiles rho = rho0 + k_rho z, S = S0 + k_S z, and the
    sediment the post-impact scour stage needs (docs/scour.md, Sediment): the median grain size
    ``d50`` [m] (None for a cohesive class: the scour laws have no grain size for it), the grain
    density [kg m-3] and whether the bed is cohesive (a cohesive bed does not scour in this model)."""

    name: str
    description: str
    density: float  # kg m-3 at the seabed
    density_gradient: float  # kg m-4
    strength: float  # Pa at the seabed
    strength_gradient: float  # Pa m-1
    source: str
    cohesive: bool
    d50: float | None  # m; None for a cohesive class
    grain_density: float = 2650.0  # kg m-3

    def profile(self) -> SedimentProfile:
        """The class as a two-point table on [0, CATALOGUE_MAX_DEPTH] m (constant below)."""
        return SedimentProfile.linear(
            self.density,
            self.density_gradient,
            self.strength,
            self.strength_gradient,
            name=self.name,
            description=self.description,
            source=f"catalogue class '{self.name}': {self.source}",
            where=f"sediment.class '{self.name}'",
        )


_HB82 = "bulk density after Hamilton & Bachman (1982), J. Acoust. Soc. Am. 72(6):1891-1904"
_MESRI = "gradient = 0.22 (rho(2.5 m) - 1025) g, NC clay s_u/sigma'_v of Mesri (1975)"
#: The scour sediment of a cohesive class (docs/scour.md, Sediment).
_COHESIVE = (
    "scour: cohesive, no scour in this model -- the scour laws (Rennie et al. 2017; Whitehouse 1998; "
    "Sumer & Fredsoe 2002) are fitted to non-cohesive sand, while a mud's erosion is set by its "
    "consolidation-dependent critical erosion stress (Whitehouse, Soulsby, Roberts & Mitchener 2000, "
    "Dynamics of Estuarine Muds, Thomas Telford); no d50; grain density 2650 kg m-3 (clay minerals "
    "2600-2800, Mitchell & Soga 2005, Fundamentals of Soil Behavior)"
)


def _clay(name, description, rho0, k_rho, s0, source):
    k_s = nc_clay_strength_gradient(rho0 + 2.5 * k_rho)
    return SedimentClass(name, description, rho0, k_rho, s0, k_s, f"{source}; {_COHESIVE}", True, None)


def _granular(name, description, rho0, k_rho, phi, source, *, cohesive, d50):
    s0, k = drained_equivalent_strength(phi, rho0)
    return SedimentClass(name, description, rho0, k_rho, s0, k, source, cohesive, d50)


#: Named sediment classes, from very soft clay to sand. Clays: the mudline strength
#: follows the consistency classes of Terzaghi & Peck (1967, Soil Mechanics in
#: Engineering Practice, Table 45: very soft s_u < 12.5 kPa, soft 12.5-25, medium/firm
#: 25-50, stiff 50-100) and the fall-cone range of seed 000 Table 4; the gradient is that
#: of a normally consolidated clay (s_u/sigma'_v = 0.22, Mesri 1975), 0.8-2 kPa/m, the
#: 1-2 kPa/m typical of soft marine clays (e.g. Randolph & Gourvenec 2011, Offshore
#: Geotechnical Engineering). Silt and sand: equivalent strength from the drained bearing
#: capacity (:func:`drained_equivalent_strength`) -- a crude proxy.
CATALOGUE: dict[str, SedimentClass] = {
    c.name: c
    for c in (
        _clay(
            "very_soft_clay",
            "very soft, high-water-content surficial mud (harbour/estuary)",
            1300.0,
            40.0,
            500.0,
            "S0 = 0.5 kPa, low end of 'very soft' (Terzaghi & Peck 1967) and inside the "
            "fall-cone range 0.0063-25 kPa of seed 000 Table 4; rho0 typical of high-porosity "
            f"surficial muds; {_MESRI}",
        ),
        _clay(
            "soft_clay",
            "soft normally consolidated marine (silty) clay",
            1420.0,
            30.0,
            2000.0,
            f"rho0 = 1420 kg m-3 ~ silty clay, {_HB82}; S0 = 2 kPa mudline strength of soft "
            f"marine clays (Randolph & Gourvenec 2011); {_MESRI}",
        ),
        _clay(
            "silty_mud",
            "soft clayey silt / silty mud of shelf basins",
            1490.0,
            30.0,
            3000.0,
            f"rho0 = 1490 kg m-3 ~ clayey silt, {_HB82}; S0 = 3 kPa (soft, Terzaghi & Peck 1967); {_MESRI}",
        ),
        _clay(
            "firm_clay",
            "firm (medium) overconsolidated clay",
            1800.0,
            10.0,
            25000.0,
            "S0 = 25 kPa, lower bound of 'medium' (Terzaghi & Peck 1967); rho0 = 1800 kg m-3 "
            f"typical of overconsolidated clay; {_MESRI}",
        ),
        _clay(
            "stiff_clay",
            "stiff clay or a hard, nearly impenetrable bottom",
            1950.0,
            5.0,
            50000.0,
            "S0 = 50 kPa, lower bound of 'stiff' (Terzaghi & Peck 1967); rho0 = 1950 kg m-3 "
            f"typical of stiff clay; {_MESRI}",
        ),
        _granular(
            "sandy_silt",
            "sandy silt (crude equivalent-strength proxy)",
            1770.0,
            10.0,
            28.0,
            f"rho0 = 1770 kg m-3, {_HB82}; equivalent strength from drained bearing "
            "capacity, phi' = 28 deg, B = 0.5 m, divided by N_c = pi + 2 (Vesic 1973): "
            "a crude proxy; scour: cohesive, no scour in this model -- a silt-dominated bed "
            "(Hamilton & Bachman 1982's sandy silt: mean grain size in the silt range, below "
            "the 0.0625 mm of sand that scour.d50 allows) with more than about 5-10 % clay "
            "erodes as a cohesive bed (van Ledden, van Kesteren & Winterwerp 2004, Cont. Shelf "
            f"Res. 24(1):1-11), outside the sand scour laws; {_COHESIVE.removeprefix('scour: cohesive, ')}",
            cohesive=True,
            d50=None,
        ),
        _granular(
            "sand",
            "fine to medium sand (crude equivalent-strength proxy)",
            1940.0,
            0.0,
            33.0,
            f"rho0 = 1940 kg m-3 ~ fine sand, {_HB82}; equivalent strength from drained "
            "bearing capacity, phi' = 33 deg, B = 0.5 m, divided by N_c = pi + 2 "
            "(Vesic 1973): a crude proxy; scour: non-cohesive, d50 = 0.2 mm (fine sand, "
            "Wentworth 0.125-0.25 mm; the d50 of Soulsby & Whitehouse 1997's threshold check "
            "and of the shipped scour examples), quartz grains 2650 kg m-3 (Soulsby 1997, "
            "Dynamics of Marine Sands)",
            cohesive=False,
            d50=2.0e-4,
        ),
    )
}


def class_names() -> tuple[str, ...]:
    """Names of the catalogue classes, from soft to stiff clays, then silt and sand."""
    return tuple(CATALOGUE)


def catalogue_profile(name: str) -> SedimentProfile:
    """The profile of catalogue class ``name`` (ScenarioError with a suggestion if unknown)."""
    try:
        return CATALOGUE[name].profile()
    except (KeyError, TypeError):
        raise ScenarioError(
            "sediment.class: " + unknown_name_message("sediment class", name, CATALOGUE)
        ) from None


# ---------------------------------------------------------------------------
# Banks
# ---------------------------------------------------------------------------
def _rows(item) -> np.ndarray:
    if isinstance(item, SedimentProfile):
        return item.as_array()
    as_array = getattr(item, "as_array", None)  # e.g. config.Current with kind "table"
    if callable(as_array):
        return np.asarray(as_array(), dtype=np.float64)
    a = np.asarray(item, dtype=np.float64)
    if a.ndim != 2 or a.shape[0] != 3:
        raise ScenarioError(f"a bank row must be a profile or a (3, n) array, got shape {a.shape}")
    return a


def pack_banks(profiles: Sequence) -> np.ndarray:
    """Stack profiles into one bank of shape (n, 3, max_points), padded with NaN after
    each row's last point (layout of :mod:`mineburial.kernels.mine.layout`).

    Items may be :class:`SedimentProfile`, objects with ``as_array()`` returning a
    (3, k) array (a tabulated current), or (3, k) arrays. An empty sequence gives an
    empty (0, 3, 1) bank.
    """
    rows = [_rows(p) for p in profiles]
    if not rows:
        return np.empty((0, 3, 1), dtype=np.float64)
    npts = max(r.shape[1] for r in rows)
    bank = np.full((len(rows), 3, npts), np.nan, dtype=np.float64)
    for i, r in enumerate(rows):
        bank[i, :, : r.shape[1]] = r
    return bank
