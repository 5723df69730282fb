"""The one registry of every variable that mineburial writes to its output.

Each output variable is declared exactly once, as a :class:`Variable` (name,
dimensions, dtype, UDUNITS units, CF ``standard_name`` where the CF Standard
Name Table has one, ``long_name``, a description written to the CF ``comment``
attribute, and any further CF attributes such as ``flag_values``). That
declaration

* builds the :class:`xarray.DataArray` objects of the Dataset
  (:meth:`Variable.data_array`), including the CF attributes and the netCDF
  encoding (``_FillValue``),
* is what :func:`mineburial.io.netcdf.write_netcdf` consults for fill values, and
* renders the Markdown tables of ``docs/notes/output.md``
  (:func:`variables_markdown`).

Three families of variables exist:

* **per-drop** variables along the CF ``realization`` dimension: every column
  of :data:`mineburial.kernels.mine.layout.SUMMARY_NAMES`, ``status`` and
  ``burial_class``; the sampled inputs are declared on the fly from their
  scenario path by :func:`input_variable` (``mine.mass`` -> ``input_mine_mass``).
* **statistics** of each summary output ``X``, expanded from templates:
  ``X_mean``, ``X_std``, ``X_stderr``, ``X_quantile``, ``X_bin`` (+ ``X_bin_bounds``),
  ``X_histogram``, ``X_level``, ``X_exceedance``.
* **ensemble-wide** statistics: burial-class probabilities with Wilson
  intervals and the count of every status code.

Those are the variables of a mine ensemble's file. The other files have a family each in
:data:`FAMILIES` (one drop's trajectory, the restraining system's time series and ensemble,
the Sobol' indices, the synthetic environment grid, the burial map and the comparison of
variants, whose statistics are the ensemble's declarations per cell or per variant);
:func:`mineburial.io.dataset.build` makes every file from the family of its kind.

A post-impact process (:mod:`mineburial.systems.mine.processes.registry`) declares its own variables
(:class:`ProcessVariables`, in its own module) and adds them when it registers
(:func:`register_process_variables`): the ensemble's registry gains them and the map's family each
of its statistics per cell. This module names no process.

In the ensemble's family only ``realization`` carries a CF standard name: the CF Standard Name Table
(v93) has no names for burial depths, burial percentages or mine attitude at
rest (``platform_pitch`` and friends describe observation platforms, not the
observed object), so those variables carry a ``long_name`` only.
"""

from __future__ import annotations

import dataclasses
import difflib
import re
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from mineburial._deferred import xarray as xr
from mineburial.kernels.mine import layout
from mineburial.kernels.mine import status as _mine_status

__all__ = [
    "Variable",
    "VARIABLES",
    "SUMMARY_OUTPUTS",
    "BURIAL_OUTPUTS",
    "PERCENT_OUTPUTS",
    "DEPTH_OUTPUTS",
    "BURIAL_CLASS_NAMES",
    "BURIAL_CLASS_MEANINGS",
    "BURIAL_CLASS_EDGES",
    "BURIAL_CLASS_BASES",
    "UNCLASSIFIED",
    "variable",
    "input_variable",
    "input_variable_name",
    "statistic_names",
    "variables_markdown",
]

# ---------------------------------------------------------------------------
# per-drop summary outputs (columns of layout.SUMMARY_NAMES)
# ---------------------------------------------------------------------------


@dataclass(frozen=True)
class _Output:
    units: str
    long_name: str
    description: str
    kind: str  # "percent", "depth" or "other": selects default histogram bins / exceedance levels


SUMMARY_OUTPUTS: dict[str, _Output] = {
    "penetration_depth": _Output(
        "m",
        "penetration depth of the lowest point of the mine",
        "Depth of the lowest point of the mine below the seabed when it came to rest "
        "(0 when it rests on the seabed without penetrating).",
        "depth",
    ),
    "com_depth": _Output(
        "m",
        "depth of the centre of mass below the seabed",
        "Depth of the centre of mass below the seabed at rest; negative when the centre of "
        "mass lies above the seabed.",
        "depth",
    ),
    "burial_volume": _Output(
        "percent",
        "percentage of the mine volume below the seabed",
        "Burial by volume: percentage of the mine volume lying below the seabed plane at rest.",
        "percent",
    ),
    "burial_height": _Output(
        "percent",
        "percentage of the vertical extent of the mine below the seabed",
        "Burial by height: percentage of the vertical extent (lowest to highest point) of the "
        "mine lying below the seabed at rest.",
        "percent",
    ),
    "burial_area": _Output(
        "percent",
        "percentage of the mine surface area below the seabed",
        "Burial by area: percentage of the outer surface area of the mine lying below the "
        "seabed at rest (100 minus the percentage of surface area proud).",
        "percent",
    ),
    "height_proud": _Output(
        "m",
        "height of the highest point of the mine above the seabed",
        "Height of the highest point of the mine above the seabed at rest (0 when fully buried).",
        "depth",
    ),
    "final_pitch": _Output(
        "degree",
        "dip of the mine axis below the horizontal at rest",
        "Pitch angle psi2 at rest: dip of the nose below the horizontal (+90 is nose-down "
        "vertical); docs/design.md.",
        "other",
    ),
    "final_roll": _Output(
        "degree",
        "roll angle of the mine about its axis at rest",
        "Roll angle psi1 about the main axis at rest (Z-Y-X angles, docs/design.md).",
        "other",
    ),
    "final_heading": _Output(
        "degree",
        "heading of the mine nose at rest",
        "Heading psi3 of the nose at rest, counter-clockwise from the E-frame x axis. Its "
        "statistics are linear (not circular) statistics.",
        "other",
    ),
    "final_x": _Output(
        "m",
        "x position of the centre of mass at rest",
        "E-frame x coordinate of the centre of mass at rest (same origin as the release position).",
        "other",
    ),
    "final_y": _Output(
        "m",
        "y position of the centre of mass at rest",
        "E-frame y coordinate of the centre of mass at rest (same origin as the release position).",
        "other",
    ),
    "impact_speed": _Output(
        "m s-1",
        "speed of the centre of mass at first contact with the seabed",
        "Speed of the centre of mass at the first contact of the mine with the seabed.",
        "other",
    ),
    "impact_pitch": _Output(
        "degree",
        "dip of the mine axis below the horizontal at first seabed contact",
        "Pitch angle psi2 at the first contact with the seabed.",
        "other",
    ),
    "impact_angle": _Output(
        "degree",
        "angle of the velocity below the horizontal at first seabed contact",
        "Angle of the centre-of-mass velocity below the horizontal at the first contact with "
        "the seabed (90 is a vertical fall).",
        "other",
    ),
    "impact_time": _Output(
        "s",
        "time of first contact with the seabed",
        "Time from release to the first contact of the mine with the seabed.",
        "other",
    ),
    "water_entry_time": _Output(
        "s",
        "time of first contact with the water surface",
        "Time from release to the first contact of the mine with the water surface.",
        "other",
    ),
    "total_time": _Output(
        "s", "time from release to rest", "Simulated time from release to the end of the drop.", "other"
    ),
    "max_deceleration": _Output(
        "m s-2",
        "largest deceleration in the sediment",
        "Largest magnitude of the deceleration of the centre of mass while in contact with the sediment.",
        "other",
    ),
    "n_steps": _Output(
        "1",
        "number of time steps",
        "Number of integrator time steps taken for the drop (stored as float64 like every summary column).",
        "other",
    ),
}

if tuple(SUMMARY_OUTPUTS) != tuple(layout.SUMMARY_NAMES):  # pragma: no cover - guards the layout
    raise RuntimeError(
        "mineburial.io.variables.SUMMARY_OUTPUTS is out of step with "
        f"layout.SUMMARY_NAMES: {tuple(SUMMARY_OUTPUTS)} != {layout.SUMMARY_NAMES}"
    )

PERCENT_OUTPUTS = tuple(k for k, v in SUMMARY_OUTPUTS.items() if v.kind == "percent")
DEPTH_OUTPUTS = tuple(k for k, v in SUMMARY_OUTPUTS.items() if v.kind == "depth")
#: the burial outputs proper (percentages and depths)
BURIAL_OUTPUTS = tuple(k for k in SUMMARY_OUTPUTS if k in PERCENT_OUTPUTS + DEPTH_OUTPUTS)

# ---------------------------------------------------------------------------
# impact-burial classes (naval symbology: 0 %, 0-10 %, 10-20 %, 20-75 %, > 75 %)
# ---------------------------------------------------------------------------

#: upper class edges in percent; class k (k >= 1) is the half-open interval
#: (EDGES[k-1], EDGES[k]], class 0 is "exactly 0 %" (p <= 0) and class 4 is p > 75.
BURIAL_CLASS_EDGES = (0.0, 10.0, 20.0, 75.0)
BURIAL_CLASS_NAMES = ("0 %", "(0, 10] %", "(10, 20] %", "(20, 75] %", "(75, 100] %")
BURIAL_CLASS_MEANINGS = (
    "not_buried",
    "buried_0_to_10_percent",
    "buried_10_to_20_percent",
    "buried_20_to_75_percent",
    "buried_more_than_75_percent",
)
#: lower/upper percent bounds of each class (class 0 is the single point 0)
BURIAL_CLASS_LOWER = (0.0, 0.0, 10.0, 20.0, 75.0)
BURIAL_CLASS_UPPER = (0.0, 10.0, 20.0, 75.0, 100.0)
#: summary columns a burial class may be based on
BURIAL_CLASS_BASES = PERCENT_OUTPUTS
#: code of a drop that has no burial class (not at rest, or non-finite basis value)
UNCLASSIFIED = -1

# ---------------------------------------------------------------------------
# the Variable declaration
# ---------------------------------------------------------------------------

_NO_FILL = "none"  # sentinel: write no _FillValue


@dataclass(frozen=True)
class Variable:
    """Declaration of one output variable.

    ``fill_value``: the netCDF ``_FillValue``; ``None`` means xarray's default
    (NaN for floats, none for integers), ``"none"`` means "write none" (used for
    coordinates and bounds, which CF forbids to have missing values).
    """

    name: str
    dims: tuple[str, ...]
    dtype: str
    units: str | None
    long_name: str
    description: str
    standard_name: str | None = None
    attrs: Mapping[str, Any] = field(default_factory=dict)
    fill_value: Any = None
    group: str = "per-drop"
    #: a CF boundary variable (7.1): written without attributes, its metadata
    #: (units included) is that of its parent coordinate (xarray drops them anyway)
    is_bounds: bool = False
    #: the kernel-side names of the flags that the writer hands in as ``flag_values``/``flag_meanings``
    #: at run time (the registry does not import the kernel module that owns them)
    runtime_flags: str | None = None
    #: attributes whose text the writer completes at run time (a comparison's varied field, how a
    #: map's grid gives its depth); the declared text says what they hold
    runtime_attrs: tuple[str, ...] = ()
    #: copied with its attributes and dtype from a file the command reads (a map's grid axes and
    #: grid mapping): the declaration names it and its dims, the input its metadata
    from_input: bool = False

    def cf_attrs(self, **extra: Any) -> dict[str, Any]:
        """CF attributes of the variable (``extra`` overrides or adds, ``None`` removes)."""
        out: dict[str, Any] = {}
        if self.is_bounds:  # CF 7.1: inherits units and the rest from its coordinate
            return {k: v for k, v in extra.items() if v is not None}
        if self.standard_name:
            out["standard_name"] = self.standard_name
        out["long_name"] = self.long_name
        if self.units is not None:
            out["units"] = self.units
        out.update(self.attrs)
        if self.description:  # an empty description writes no comment
            out["comment"] = self.description
        for k, v in extra.items():
            if v is None:
                out.pop(k, None)
            else:
                out[k] = v
        return out

    def encoding(self) -> dict[str, Any]:
        """netCDF encoding entries implied by the declaration (``_FillValue``)."""
        if self.fill_value is None:
            return {}
        if isinstance(self.fill_value, str) and self.fill_value == _NO_FILL:
            return {"_FillValue": None}
        return {"_FillValue": np.array(self.fill_value, dtype=self.dtype)[()]}

    def data_array(self, data, coords=None, **extra_attrs: Any):
        """An :class:`xarray.DataArray` holding ``data`` cast to the declared dtype.

        The shape must have one axis per declared dimension.
        """
        arr = np.asarray(data)
        if arr.ndim != len(self.dims):
            raise ValueError(
                f"variable {self.name!r} is declared with dims {self.dims} but got an array "
                f"of shape {arr.shape}"
            )
        if arr.dtype != np.dtype(self.dtype):
            arr = arr.astype(self.dtype)
        da = xr.DataArray(
            arr, dims=self.dims, coords=coords, name=self.name, attrs=self.cf_attrs(**extra_attrs)
        )
        da.encoding.update(self.encoding())
        return da


def _flag_attrs(values, meanings) -> dict[str, Any]:
    return {"flag_values": np.asarray(values, dtype=np.int8), "flag_meanings": " ".join(meanings)}


#: the falling mine's status codes (the registry of mineburial.kernels.status), of the ``status``
#: variables of its drops
_MINE_STATUS = _mine_status.VOCABULARY


def _status_flags(vocabulary) -> dict[str, Any]:
    """The CF ``flag_values``/``flag_meanings`` of a system's status codes (its vocabulary)."""
    return _flag_attrs(vocabulary.codes, vocabulary.names.values())


#: for a process's own declarations (:func:`register_process_variables`): write no ``_FillValue``,
#: and the ``flag_values``/``flag_meanings`` attributes of codes
NO_FILL, flag_attrs = _NO_FILL, _flag_attrs


def _drop_variables() -> list[Variable]:
    """The per-drop variables along ``realization``: the index, every summary output, the
    termination status and the impact-burial class."""
    drop = ("realization",)
    out = [
        Variable(
            "realization",
            drop,
            "int64",
            "1",
            "index of the drop in the ensemble",
            "Index i of the drop in the Monte Carlo ensemble; every random input of drop i is a "
            "pure function of (seed, i), so a single drop can be re-run from it.",
            standard_name="realization",
            fill_value=_NO_FILL,
        )
    ]
    out += [
        Variable(
            name,
            drop,
            "float64",
            o.units,
            o.long_name,
            o.description + " Reported for every drop; only drops with status "
            "at_rest or buried_sinking enter the statistics.",
            attrs={"coverage_content_type": "modelResult"},
        )
        for name, o in SUMMARY_OUTPUTS.items()
    ]
    out.append(
        Variable(
            "status",
            drop,
            "int8",
            None,
            "termination status of the drop",
            "How the drop ended: "
            + "; ".join(
                f"{code} {name}: {_MINE_STATUS.descriptions[code]}"
                for code, name in _MINE_STATUS.names.items()
            )
            + ".",
            attrs={
                **_status_flags(_MINE_STATUS),
                "coverage_content_type": "qualityInformation",
            },
        )
    )
    out.append(
        Variable(
            "burial_class",
            drop,
            "int8",
            None,
            "impact-burial class of the drop",
            "Impact-burial class on the basis named by the attribute burial_class_basis "
            "(burial_volume by default): 0 is exactly 0 %, class k = 1..3 the half-open interval "
            "(lower, upper] of 0-10, 10-20, 20-75 %, class 4 more than 75 %; -1 for drops that "
            "did not come to rest or whose basis value is not finite.",
            attrs={
                **_flag_attrs((UNCLASSIFIED,) + tuple(range(5)), ("unclassified",) + BURIAL_CLASS_MEANINGS),
                "coverage_content_type": "modelResult",
            },
        )
    )
    return out


def _burial_class_variables() -> list[Variable]:
    """The ensemble's impact-burial classes: the class coordinate, its bounds, the count of
    drops at rest in each class and its probability with the Wilson interval."""
    cls = ("impact_burial_class",)
    out = [
        Variable(
            "impact_burial_class",
            cls,
            "int8",
            None,
            "impact-burial class",
            "Impact-burial classes of naval symbology: 0 is exactly 0 %, 1 is (0, 10] %, 2 is "
            "(10, 20] %, 3 is (20, 75] %, 4 is (75, 100] %.",
            attrs=_flag_attrs(range(5), BURIAL_CLASS_MEANINGS),
            fill_value=_NO_FILL,
            group="statistics",
        )
    ]
    bound_descriptions = {
        "lower": "Lower bound of the class (exclusive, except class 0 which is the point 0 %).",
        "upper": "Upper bound of the class (inclusive).",
    }
    out += [
        Variable(
            f"burial_class_{side}_percent",
            cls,
            "float64",
            "percent",
            f"{side} bound of the impact-burial class",
            description,
            fill_value=_NO_FILL,
            group="statistics",
        )
        for side, description in bound_descriptions.items()
    ]
    out.append(
        Variable(
            "burial_class_count",
            cls,
            "int64",
            "1",
            "number of drops at rest in the impact-burial class",
            "Number of drops with status at_rest or buried_sinking and a finite basis value in each class.",
            fill_value=_NO_FILL,
            group="statistics",
        )
    )
    out.append(
        Variable(
            "burial_class_probability",
            cls,
            "float64",
            "1",
            "probability of the impact-burial class",
            "Fraction k/n of the drops at rest (with a finite basis value) falling in the class; "
            "NaN when n = 0.",
            group="statistics",
            attrs={
                "ancillary_variables": "burial_class_probability_lower "
                "burial_class_probability_upper burial_class_count"
            },
        )
    )
    out += [
        Variable(
            f"burial_class_probability_{side}",
            cls,
            "float64",
            "1",
            f"{side} confidence limit of the impact-burial class probability",
            f"{side.capitalize()} limit of the Wilson score interval (Wilson 1927) at the confidence level "
            "given by the attribute confidence_level.",
            group="statistics",
        )
        for side in ("lower", "upper")
    ]
    out += [
        Variable(
            f"burial_class_probability_epistemic_{side}",
            cls,
            "float64",
            "1",
            f"{side} limit of the impact-burial class probability over the calibrated coefficients",
            f"{side.capitalize()} limit of the central band (level in the attribute band_level) of the class "
            "probability across the coefficient sets of the posterior that the drops drew from: the "
            "epistemic uncertainty the measurements leave open (docs/calibration.md). Estimated from "
            "the same drops, grouped by coefficient set (one-way random-effects analysis of variance; "
            "a beta distribution with the between-set variance). Written only when the ensemble draws "
            "its coefficients from a posterior.",
            group="statistics",
        )
        for side in ("lower", "upper")
    ]
    return out


def _ensemble_variables() -> list[Variable]:
    """The ensemble-wide statistics: the ``quantile`` coordinate, the burial classes and the
    count of every status code."""
    quantile = Variable(
        "quantile",
        ("quantile",),
        "float64",
        "1",
        "probability level of the quantile",
        "Probability p of the quantiles X_quantile: P(X <= X_quantile) = p, linear "
        "interpolation between order statistics (Hyndman & Fan 1996 type 7, numpy "
        "method 'linear').",
        fill_value=_NO_FILL,
        group="statistics",
    )
    status_code = Variable(
        "status_code",
        ("status_code",),
        "int8",
        None,
        "termination status code",
        "Status codes of mineburial.kernels.status.",
        attrs=_status_flags(_MINE_STATUS),
        fill_value=_NO_FILL,
        group="statistics",
    )
    status_count = Variable(
        "status_count",
        ("status_code",),
        "int64",
        "1",
        "number of drops with the status",
        "Number of drops of the ensemble that ended with each status code.",
        fill_value=_NO_FILL,
        group="statistics",
    )
    return [quantile, *_burial_class_variables(), status_code, status_count]


def _coverage_content_type(name: str, var: Variable) -> str:
    """ACDD-1.3 coverage_content_type of a variable that does not set its own."""
    if var.dims == (name,):
        return "coordinate"
    if name.startswith("burial_class_") and name.endswith("_percent"):
        return "referenceInformation"
    if name == "status_count":
        return "qualityInformation"
    return "modelResult"


def _with_coverage(var: Variable) -> Variable:
    """``var`` with its ACDD coverage_content_type (:func:`_coverage_content_type`) unless it sets one."""
    if var.is_bounds or "coverage_content_type" in var.attrs:
        return var
    cct = _coverage_content_type(var.name, var)
    return dataclasses.replace(var, attrs={**var.attrs, "coverage_content_type": cct})


def _declare() -> dict[str, Variable]:
    """The mine ensemble's registry: per-drop variables, ensemble-wide statistics and the statistics
    of every summary output (templates), each with its ACDD coverage_content_type. A post-impact
    process adds its own (:func:`register_process_variables`)."""
    stats = [var for name, o in SUMMARY_OUTPUTS.items() for var in _statistics_of(name, o)]
    v: dict[str, Variable] = {}
    for var in [*_drop_variables(), *_ensemble_variables(), *stats]:
        if var.name in v:  # pragma: no cover - guards the registry itself
            raise RuntimeError(f"output variable {var.name!r} declared twice")
        v[var.name] = var
    return {name: _with_coverage(var) for name, var in v.items()}


def _statistics_of(name: str, out: _Output) -> list[Variable]:
    u, ln = out.units, out.long_name
    basis = "over the drops with status at_rest or buried_sinking and a finite value"
    bin_, lev = f"{name}_bin", f"{name}_level"
    return [
        Variable(
            f"{name}_mean",
            (),
            "float64",
            u,
            f"mean of {ln}",
            f"Arithmetic mean of {name} {basis}.",
            attrs={"cell_methods": "realization: mean"},
            group="statistics",
        ),
        Variable(
            f"{name}_std",
            (),
            "float64",
            u,
            f"standard deviation of {ln}",
            f"Sample standard deviation (ddof = 1) of {name} {basis}; NaN for fewer than 2 values.",
            attrs={"cell_methods": "realization: standard_deviation"},
            group="statistics",
        ),
        Variable(
            f"{name}_stderr",
            (),
            "float64",
            u,
            f"standard error of the mean of {ln}",
            f"Standard error of the mean, std / sqrt(n), of {name} {basis}.",
            group="statistics",
        ),
        Variable(
            f"{name}_quantile",
            ("quantile",),
            "float64",
            u,
            f"quantiles of {ln}",
            f"Quantiles of {name} {basis}, computed exactly from the stored per-drop values "
            "(numpy method 'linear', Hyndman & Fan 1996 type 7).",
            group="statistics",
        ),
        Variable(
            bin_,
            (bin_,),
            "float64",
            u,
            f"centre of the histogram bin of {ln}",
            f"Centre of each histogram bin of {name}; the bin edges are in {name}_bin_bounds.",
            attrs={"bounds": f"{name}_bin_bounds"},
            fill_value=_NO_FILL,
            group="statistics",
        ),
        Variable(
            f"{name}_bin_bounds",
            (bin_, "nv"),
            "float64",
            u,
            f"edges of the histogram bin of {ln}",
            "Lower and upper edge of each bin; bins are half-open [lower, upper) except the last, "
            "which is closed [lower, upper] (numpy.histogram).",
            fill_value=_NO_FILL,
            group="statistics",
            is_bounds=True,
        ),
        Variable(
            f"{name}_histogram",
            (bin_,),
            "int64",
            "1",
            f"histogram of {ln}",
            f"Number of values of {name} {basis} in each bin; values outside the outer edges are "
            "not counted (their number is the attribute n_outside_range).",
            fill_value=_NO_FILL,
            group="statistics",
        ),
        Variable(
            lev,
            (lev,),
            "float64",
            u,
            f"threshold of {ln}",
            f"Threshold x of the exceedance probability P({name} >= x).",
            fill_value=_NO_FILL,
            group="statistics",
        ),
        Variable(
            f"{name}_exceedance",
            (lev,),
            "float64",
            "1",
            f"probability that {ln} reaches or exceeds the threshold",
            f"Exceedance probability P({name} >= {name}_level) {basis}: the fraction of values "
            "greater than or equal to the threshold; NaN when there is no value.",
            group="statistics",
        ),
    ]


VARIABLES: dict[str, Variable] = _declare()

_STATISTIC_SUFFIXES = (
    "mean",
    "std",
    "stderr",
    "quantile",
    "bin",
    "bin_bounds",
    "histogram",
    "level",
    "exceedance",
)


def statistic_names(output: str) -> tuple[str, ...]:
    """Names of the statistics variables of the summary output ``output``."""
    if output not in SUMMARY_OUTPUTS:
        raise KeyError(_unknown("summary output", output, SUMMARY_OUTPUTS))
    return tuple(f"{output}_{s}" for s in _STATISTIC_SUFFIXES)


# ---------------------------------------------------------------------------
# sampled inputs
# ---------------------------------------------------------------------------

_NAME_RE = re.compile(r"^[A-Za-z][A-Za-z0-9_]*$")


def input_variable_name(path: str) -> str:
    """netCDF variable name of the sampled scenario field ``path`` ("mine.mass" ->
    "input_mine_mass", "release.velocity[0]" -> "input_release_velocity_0")."""
    name = "input_" + path.replace(".", "_").replace("[", "_").replace("]", "")
    if not _NAME_RE.match(name):
        raise ValueError(
            f"scenario path {path!r} cannot be turned into a CF variable name "
            "(letters, digits, underscores and dots only)"
        )
    return name


def input_variable(path: str, units: str | None, description: str | None = None) -> Variable:
    """Declaration of the per-drop sampled input ``path`` (a dotted scenario path).

    ``units`` must be a UDUNITS string (``"1"`` for dimensionless values and
    integer-coded choices); ``None`` writes no ``units`` attribute and says so in
    the comment.
    """
    name = input_variable_name(path)
    desc = description or f"sampled value of the scenario field {path}"
    if units is None:
        desc += " (units not provided by the caller)"
    return Variable(
        name,
        ("realization",),
        "float64",
        units,
        f"sampled {path}",
        f"Value of the scenario field {path} sampled for each drop: {desc}",
        attrs={"scenario_path": path, "coverage_content_type": "auxiliaryInformation"},
        group="input",
    )


# ---------------------------------------------------------------------------
# the families of the other files: one drop's trajectory, the restraining system's
# time series and ensembles, the Sobol' sensitivity analysis
# ---------------------------------------------------------------------------
# Their names, units and long names are those the files have carried since they were
# written; a declaration with an empty description writes no ``comment``. Flags owned by a
# kernel module (the restraint's status and contact codes, which the registry must not
# import: mineburial.kernels.multibody costs ~0.2 s of start-up) are handed to the
# builder at run time and named in the description.

#: the restraint's per-case results, in the column order of a chunk's ``summary``
#: (:mod:`mineburial.systems.restraint.ensemble`): units, long name, comment
RESTRAINT_OUTPUTS: dict[str, tuple[str, str, str]] = {
    "stopping_time": (
        "s",
        "time at which the ship's surge speed first reaches zero",
        "located on the integrator's continuous extension; missing (NaN) where the case did not stop: "
        "its status says why",
    ),
    "end_time": ("s", "time at which the run ended (the stopping time, or the time limit)", ""),
    "peak_chain_tension": (
        "N",
        "largest force of the pin joining the anchor chain to the anchor",
        "maximum over the records, every numerics.record_interval (a lower bound of the true peak)",
    ),
    "peak_ship_tension": (
        "N",
        "largest force of the pin joining the auxiliary rod to the ship (the restraining force on the ship)",
        "maximum over the records, every numerics.record_interval (a lower bound of the true peak)",
    ),
    "energy_closure": (
        "1",
        "energy balance error: max |E(t) - E(0)| over the initial kinetic and hydrostatic energy",
        "seed 004 §4.2 reports closure within 0.5 %",
    ),
}
#: the derived quantities of a restraint case written as scalars (seed 004's equations)
RESTRAINT_DERIVED: dict[str, tuple[str, str]] = {
    "water_depth": ("m", "water depth d of eq. (38): height of the ship's water plane above the seabed"),
    "ship_draught": ("m", "draught of the cuboid ship, m / (rho L B)"),
    "ship_wetted_area": ("m2", "wetted surface S_W of the cuboid ship, eq. (62)"),
    "ship_gm_longitudinal": ("m", "longitudinal metacentric height G_y^M, eq. (57)"),
    "catenary_b": ("1", "catenary parameter b = x_s / a, eq. (30)"),
    "catenary_a": ("m", "catenary parameter a = T_h / w_c, eq. (31)"),
    "catenary_horizontal_tension": ("N", "horizontal tension T_h of the initial catenary, eq. (31)"),
    "chain_axis_height": ("m", "initial height of the chain's axis above the seabed (equilibrium sinkage)"),
    "cable_axis_height": ("m", "initial height of the cable's axis above the seabed (equilibrium sinkage)"),
}
_RESTRAINT_STATUS = "mineburial.kernels.multibody.STATUS_NAMES"


def _family(vars_: list[Variable], group: str) -> dict[str, Variable]:
    out: dict[str, Variable] = {}
    for var in vars_:
        if var.name in out:  # pragma: no cover - guards the registry itself
            raise RuntimeError(f"output variable {var.name!r} declared twice in {group}")
        out[var.name] = dataclasses.replace(var, group=group)
    return out


# the columns of a recorded trajectory row (layout.TRAJ_COLUMNS) written along ``time``
_TRAJ_COLUMNS: dict[str, tuple[str, str]] = {
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
#: the force columns of a trajectory row, written with ``mineburial drop --forces``
TRAJ_FORCE_COLUMNS: dict[str, tuple[str, str]] = {
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
if set(layout.TRAJ_COLUMNS) != {"time", "phase", *_TRAJ_COLUMNS, *TRAJ_FORCE_COLUMNS}:  # pragma: no cover
    raise RuntimeError(
        "mineburial.io.variables' trajectory columns are out of step with layout.TRAJ_COLUMNS: "
        f"{layout.TRAJ_COLUMNS}"
    )
#: the trajectory's columns written as they are recorded (every TRAJ_COLUMNS entry but
#: ``time``, the coordinate, and ``phase``, an int8 flag variable)
TRAJ_STATE_COLUMNS = tuple(_TRAJ_COLUMNS)
#: the attitude angles derived from the quaternion (seed 000 eq. (4))
TRAJ_ANGLES: dict[str, str] = {
    "psi1": "roll about the mine axis (seed 000 psi1)",
    "psi2": "dip of the nose below the horizontal (seed 000 psi2)",
    "psi3": "heading of the mine axis (seed 000 psi3)",
}


def _trajectory_variables() -> list[Variable]:
    t = ("time",)
    out = [
        Variable(
            "time", t, "float64", "s", "time since release", "", standard_name="time", fill_value=_NO_FILL
        )
    ]
    for name, (units, long_name) in {**_TRAJ_COLUMNS, **TRAJ_FORCE_COLUMNS}.items():
        out.append(Variable(name, t, "float64", units, long_name, ""))
    out += [Variable(name, t, "float64", "degree", ln, "") for name, ln in TRAJ_ANGLES.items()]
    out.append(
        Variable(
            "phase",
            t,
            "int8",
            None,
            "medium the mine is in or crossing",
            "",
            attrs=_flag_attrs(range(len(layout.PHASE_NAMES)), layout.PHASE_NAMES),
        )
    )
    out += [Variable(name, (), "float64", o.units, o.long_name, "") for name, o in SUMMARY_OUTPUTS.items()]
    out.append(
        Variable(
            "status",
            (),
            "int8",
            None,
            "drop status",
            "",
            attrs=_status_flags(_MINE_STATUS),
        )
    )
    return out


def _restraint_run_variables() -> list[Variable]:
    b, t = ("elapsed_time", "body"), ("elapsed_time",)

    def f(name, dims, units, long_name, comment=""):
        return Variable(name, dims, "float64", units, long_name, comment)

    pin = "horizontal force of the pin joining the body to the previous one, on the body"
    return [
        f("elapsed_time", t, "s", "time since the start of the restraint (elapsed time)"),
        Variable("body", ("body",), "int32", None, "body number (seed 004: 1 = anchor, N = ship)", ""),
        Variable("body_name", ("body",), "object", None, "body", ""),
        Variable("body_kind", ("body",), "object", None, "kind of body", ""),
        f("body_length", ("body",), "m", "body length"),
        f("x", b, "m", "horizontal position of the body's centroid"),
        f("z", b, "m", "height of the body's centroid above the seabed"),
        f("theta", b, "rad", "attitude of the body, counter-clockwise from +x toward +z"),
        f("vx", b, "m s-1", "horizontal velocity of the body's centroid"),
        f("vz", b, "m s-1", "vertical velocity of the body's centroid"),
        f("omega", b, "rad s-1", "angular velocity of the body"),
        f(
            "pin_force_x",
            b,
            "N",
            pin,
            "seed 004 eq. (52); body 1 (the anchor): the seabed's reaction on its locked coordinates",
        ),
        f(
            "pin_force_z",
            b,
            "N",
            pin.replace("horizontal", "vertical"),
            "seed 004 eq. (52); body 1 (the anchor): the seabed's normal reaction",
        ),
        f(
            "pin_tension",
            b,
            "N",
            "magnitude of the pin force (joint constraint force); body 1 (the anchor): magnitude of the "
            "seabed's reaction on its locked coordinates",
        ),
        f("ship_x", t, "m", "ship surge position (centroid)"),
        f("ship_speed", t, "m s-1", "ship surge speed"),
        f("ship_heave", t, "m", "ship heave"),
        f("ship_pitch", t, "rad", "ship pitch angle"),
        f("anchor_x", t, "m", "anchor position (centroid)"),
        f("anchor_speed", t, "m s-1", "anchor speed along the seabed"),
        f("anchor_normal_force", t, "N", "seabed normal reaction on the anchor"),
        f("anchor_friction", t, "N", "seabed friction on the anchor", "seed 004 eq. (37)"),
        Variable(
            "anchor_contact",
            t,
            "int8",
            None,
            "state of the anchor's seabed contact",
            "lifted: the solved normal reaction is <= 0; friction_unsolvable: eq. (37) has "
            "no solution (1 + mu s dN/df <= 0); in both the friction is zero (docs/restraint.md)",
            runtime_flags="mineburial.systems.restraint.model.CONTACT_NAMES",
        ),
        f("kinetic_energy", t, "J", "kinetic energy (with the added mass)", "eq. (64)"),
        f(
            "gravitational_energy",
            t,
            "J",
            "potential energy of weight and buoyancy above the seabed",
            "eq. (65)",
        ),
        f("hydrostatic_energy", t, "J", "elastic energy of the ship's heave and pitch restoring", "eq. (66)"),
        f(
            "foundation_energy",
            t,
            "J",
            "elastic energy stored in the seabed foundation",
            "eq. (68): W^S with the opposite sign",
        ),
        f(
            "friction_dissipation",
            t,
            "J",
            "energy dissipated by the anchor's seabed friction",
            "-W^F, eq. (67)",
        ),
        f(
            "water_dissipation",
            t,
            "J",
            "energy taken from the system by the water (drag, ship resistance)",
            "-W^W, eq. (69); negative where a current feeds energy in",
        ),
        f("total_energy", t, "J", "kinetic + potential + dissipated energy (constant)", "eq. (63)"),
        Variable("status", (), "int8", None, "run status", "", runtime_flags=_RESTRAINT_STATUS),
        f("stopping_time", (), "s", "time at which the ship's surge speed first reaches zero"),
    ] + [f(name, (), units, long_name) for name, (units, long_name) in RESTRAINT_DERIVED.items()]


def _restraint_ensemble_variables() -> list[Variable]:
    r = ("realization",)

    def f(name, dims, units, long_name, comment="", **attrs):
        return Variable(name, dims, "float64", units, long_name, comment, attrs=attrs)

    out = [
        Variable(
            "status", ("status",), "int8", None, "run status of a case", "", runtime_flags=_RESTRAINT_STATUS
        ),
        f("quantile", ("quantile",), "1", "probability level"),
        Variable(
            "realization",
            r,
            "int64",
            "1",
            "case index in the ensemble",
            "",
            standard_name="realization",
            fill_value=_NO_FILL,
        ),
        Variable("status_count", ("status",), "int64", "1", "number of cases with each status", ""),
        f(
            "stopped_fraction",
            (),
            "1",
            "share of the cases run whose ship stopped within numerics.t_max",
            "cases with invalid sampled inputs are not run and not counted",
        ),
    ]
    out += [
        f(f"stopped_fraction_{end}", (), "1", f"{end} end of the 95 % Wilson interval of stopped_fraction")
        for end in ("lower", "upper")
    ]
    stats = (("mean", "mean"), ("std", "standard deviation (n - 1)"), ("min", "minimum"), ("max", "maximum"))
    for stat, what in stats:
        method = {"std": "standard_deviation", "min": "minimum", "max": "maximum"}.get(stat, stat)
        out.append(
            f(
                f"stopping_time_{stat}",
                (),
                "s",
                f"{what} of the stopping time over the cases that stopped",
                cell_methods=f"realization: {method} where stopped",
            )
        )
    out.append(
        f(
            "stopping_time_quantile",
            ("quantile",),
            "s",
            "quantiles of the stopping time over the cases that stopped",
            "numpy.quantile method 'linear' (Hyndman & Fan 1996 type 7)",
        )
    )
    for name in ("peak_chain_tension", "peak_ship_tension"):
        units, long_name, _ = RESTRAINT_OUTPUTS[name]
        for stat, what in (("mean", "mean"), ("max", "maximum")):
            out.append(
                f(
                    f"{name}_{stat}",
                    (),
                    units,
                    f"{what} over the cases that stopped of the {long_name}",
                    cell_methods=f"realization: {what} where stopped",
                )
            )
    out += [f(name, r, units, ln, comment) for name, (units, ln, comment) in RESTRAINT_OUTPUTS.items()]
    out.append(
        Variable(
            "case_status", r, "int8", None, "run status of the case", "", runtime_flags=_RESTRAINT_STATUS
        )
    )
    return out


def _sensitivity_variables() -> list[Variable]:
    """The Sobol' indices of :func:`mineburial.analyses.sensitivity.sobol_analysis` (seeds: Saltelli
    et al. 2010 first order, Jansen 1999 total; bootstrap intervals) and the model-form shares."""
    oi = ("output", "input")
    out = [
        Variable("output", ("output",), "object", None, "output analysed", "", fill_value=_NO_FILL),
        Variable("input", ("input",), "object", None, "random input of the design", "", fill_value=_NO_FILL),
    ]
    for key, symbol, estimator in (
        ("first_order", "first-order Sobol' index S_i", "Saltelli et al. 2010"),
        ("total_order", "total Sobol' index S_Ti", "Jansen 1999"),
    ):
        out.append(Variable(key, oi, "float64", None, symbol, "", attrs={"estimator": estimator}))
        out += [
            Variable(f"{key}_{side}", oi, "float64", None, f"{side} confidence limit of the {symbol}", "")
            for side in ("lower", "upper")
        ]
    out += [
        Variable("output_variance", ("output",), "float64", None, "variance of the output over A and B", ""),
        Variable(
            "index_status",
            ("output",),
            "int8",
            None,
            "whether the Sobol' indices of the output are defined",
            "1: the output took one value at every point of the design, its "
            "variance is 0 and every index 0 / 0, written NaN.",
            attrs=_flag_attrs((0, 1), ("defined", "undefined_output_constant")),
        ),
        Variable(
            "model_form_first_order",
            ("output",),
            "float64",
            None,
            "sum of the model-form inputs' first-order indices (<= the group's closed index)",
            "",
        ),
        Variable(
            "model_form_total_order",
            ("output",),
            "float64",
            None,
            "sum of the model-form inputs' total indices (>= the group's total index)",
            "",
        ),
    ]
    return out


#: the label of every value of the synthetic environment grid (:mod:`mineburial.analyses.synthetic`)
SYNTHETIC_NOTE = (
    "SYNTHETIC DATA: invented values to demonstrate mineburial maps; not a survey, "
    "not a chart, not for operational use."
)


def _current_components(dims, long_name_suffix: str, comment: str, attrs) -> list[Variable]:
    """The current's eastward and northward components over ``dims`` (CF standard names
    eastward/northward_sea_water_velocity): an environment grid's and a map's."""
    return [
        Variable(
            f"current_{c}",
            dims,
            "float64",
            "m s-1",
            f"{way} current{long_name_suffix}",
            comment,
            standard_name=f"{way}_sea_water_velocity",
            attrs=attrs,
        )
        for c, way in (("u", "eastward"), ("v", "northward"))
    ]


def _environment_variables() -> list[Variable]:
    """The synthetic environment grid of :mod:`mineburial.analyses.synthetic` (the format the maps read,
    docs/maps.md): depth, sediment class and current on a WGS 84 latitude/longitude grid."""
    g, gm = ("latitude", "longitude"), {"grid_mapping": "crs"}
    out = [
        Variable(
            axis,
            (axis,),
            "float64",
            f"degrees_{'north' if axis == 'latitude' else 'east'}",
            axis,
            "",
            standard_name=axis,
            attrs={"axis": "Y" if axis == "latitude" else "X"},
            fill_value=_NO_FILL,
        )
        for axis in g
    ]
    out += [
        Variable(
            "water_depth",
            g,
            "float64",
            "m",
            "water depth (synthetic)",
            "NaN on land. " + SYNTHETIC_NOTE,
            standard_name="sea_floor_depth_below_sea_surface",
            attrs=gm,
        ),
        Variable(
            "sediment_class",
            g,
            "int8",
            None,
            "seabed sediment class (synthetic)",
            "Index into the mineburial sediment catalogue "
            "(mineburial.systems.mine.sediment_profiles.class_names()); -1 (fill) on land. " + SYNTHETIC_NOTE,
            attrs=gm,
            fill_value=-1,
            runtime_flags="mineburial.systems.mine.sediment_profiles.class_names()",
        ),
    ]
    out += _current_components(g, " (synthetic)", "", gm)
    out.append(
        Variable(
            "crs",
            (),
            "int32",
            None,
            "WGS 84",
            "",
            attrs={
                "grid_mapping_name": "latitude_longitude",
                "longitude_of_prime_meridian": 0.0,
                "semi_major_axis": 6378137.0,
                "inverse_flattening": 298.257223563,
            },
        )
    )
    return out


# ---------------------------------------------------------------------------
# the output variables of the post-impact processes (mineburial.systems.mine.processes.registry)
# ---------------------------------------------------------------------------
@dataclass(frozen=True)
class ProcessVariables:
    """What a post-impact process declares of its output (its ``variables()``; scour's:
    :data:`mineburial.systems.mine.processes.scour_variables.DECLARED`)."""

    #: the variables of a run's file, in order: names beginning ``<section>_``, but for coordinates
    #: that processes may share (``lead_time``, ...; declared alike by each that has them)
    variables: tuple[Variable, ...]
    #: the coordinates of its statistics that a map shares with its cells' template run, in order
    map_coordinates: tuple[str, ...] = ()
    #: appended to the description of each of its statistics on a map (over which drops of a cell)
    map_note: str = ""
    #: its statistics that are quality information on a map (status counts)
    map_quality: tuple[str, ...] = ()
    #: its statistics that only a run's file holds, not a map per cell (none of scour's)
    run_only: tuple[str, ...] = ()
    #: its name prefix (set by :func:`register_process_variables`)
    section: str = ""

    def map_statistics(self) -> tuple[str, ...]:
        """The statistics a map holds per cell (and lead time): every variable ``<section>_*``
        without a ``realization`` axis that is not a dimension coordinate, but :attr:`run_only`."""
        return tuple(
            var.name
            for var in self.variables
            if var.name.startswith(f"{self.section}_")
            and "realization" not in var.dims
            and var.dims != (var.name,)
            and var.name not in self.run_only
        )


#: the declarations of each registered post-impact process (section -> its :class:`ProcessVariables`)
PROCESS_VARIABLES: dict[str, ProcessVariables] = {}
_AS_DECLARED: dict[str, ProcessVariables] = {}  # as the process gave them (a second registration: the same)


def _same(a: Variable, b: Variable) -> bool:
    return repr(a) == repr(b)  # attrs may hold arrays (flag_values): compare their text


def register_process_variables(section: str, declared: ProcessVariables) -> None:
    """Add the output variables ``declared`` by the post-impact process ``section`` to the mine
    ensemble's registry (:data:`VARIABLES`, with their coverage_content_type) and its statistics,
    per cell, to the map's family. Registering the same declarations again does nothing; other
    declarations under a registered section, a name outside the section's prefix that is not a
    coordinate, or a name declared otherwise already are refused (ValueError)."""
    previous = _AS_DECLARED.get(section)
    if previous is not None:
        if previous is declared:
            return
        raise ValueError(
            f"the output variables of the post-impact process [{section}] are registered already"
        )
    new = {}
    for var in declared.variables:
        var = _with_coverage(var)
        coordinate = var.dims in ((var.name,), ())
        if not (var.name.startswith(f"{section}_") or coordinate):
            raise ValueError(f"[{section}]: output variable {var.name!r} must begin with '{section}_'")
        if var.name in VARIABLES and not (coordinate and _same(VARIABLES[var.name], var)):
            raise ValueError(f"[{section}]: output variable {var.name!r} is declared already")
        new[var.name] = var
    VARIABLES.update(new)
    PROCESS_VARIABLES[section] = dataclasses.replace(declared, variables=tuple(new.values()), section=section)
    _AS_DECLARED[section] = declared
    FAMILIES["map"] = _family(_map_variables(), "map")


def unregister_process_variables(section: str) -> None:
    """Remove the output variables of the process ``section`` (a test's toy process), but the
    coordinates another registered process shares."""
    gone = PROCESS_VARIABLES.pop(section, None)
    _AS_DECLARED.pop(section, None)
    if gone is None:
        return
    kept = {var.name for p in PROCESS_VARIABLES.values() for var in p.variables}
    for var in gone.variables:
        if var.name not in kept:
            VARIABLES.pop(var.name, None)
    FAMILIES["map"] = _family(_map_variables(), "map")


def map_process_statistics() -> tuple[str, ...]:
    """The statistics of every registered post-impact process that a map holds per cell."""
    return tuple(name for p in PROCESS_VARIABLES.values() for name in p.map_statistics())


def map_shared_coords() -> tuple[str, ...]:
    """The coordinates of the statistics that a map shares with its cells' template run: the
    impact's (:data:`MAP_SHARED_COORDS`) and every registered process's."""
    out = list(MAP_SHARED_COORDS)
    for p in PROCESS_VARIABLES.values():
        out += [name for name in p.map_coordinates if name not in out]
    return tuple(out)


# ---------------------------------------------------------------------------
# the burial map (mineburial.analyses.maps): ensemble statistics per cell of an environment grid
# ---------------------------------------------------------------------------
#: the coordinates of the impact statistics that a map shares with its cells' template run (with a
#: post-impact process also its own: :func:`map_shared_coords`)
MAP_SHARED_COORDS = ("quantile", "impact_burial_class", "status_code")
#: summary outputs whose mean, standard deviation and quantiles a map holds per cell
MAP_OUTPUTS = ("burial_volume", "penetration_depth")
#: the impact statistics a map holds per cell; with a post-impact process also its own
#: (:func:`map_process_statistics`)
MAP_STATISTICS = (
    "burial_class_count",
    "burial_class_probability",
    "burial_class_probability_lower",
    "burial_class_probability_upper",
    "status_count",
) + tuple(f"{o}_{s}" for o in MAP_OUTPUTS for s in ("mean", "std", "quantile"))
#: the epistemic band of the class probabilities, in a map whose ensembles draw from a posterior
MAP_EPISTEMIC = ("burial_class_probability_epistemic_lower", "burial_class_probability_epistemic_upper")
#: the horizontal dims of a map as declared; a file names them (and its grid mapping variable) as
#: its environment grid does (:func:`mineburial.io.dataset.build`'s ``names``)
MAP_Y, MAP_X = "y", "x"
#: codes of the per-cell variable ``cell_status``
CELL_STATUS_MEANINGS = ("computed", "land_or_no_water_depth", "no_sediment_data")
_PER_CELL_IMPACT = (
    " Per cell, over the drops of the cell's ensemble that came to rest; NaN on land, "
    "where no drop came to rest, or (std) where fewer than 2 did."
)


def _per_cell(name: str, process: ProcessVariables | None = None) -> Variable:
    """The ensemble statistic ``name`` on a map: one value per cell (the grid's axes appended);
    ``process``: the declarations of the post-impact process whose statistic it is."""
    var = VARIABLES[name]
    quality = name == "status_count" or (process is not None and name in process.map_quality)
    note = ""
    if process is not None:
        note = "" if quality else process.map_note
    elif name.endswith(("_mean", "_std", "_quantile")):
        note = _PER_CELL_IMPACT
    cct = "qualityInformation" if quality else "modelResult"
    return dataclasses.replace(
        var,
        dims=var.dims + (MAP_Y, MAP_X),
        description=var.description + note,
        attrs={**var.attrs, "coverage_content_type": cct},
    )


def _map_cell_variables() -> list[Variable]:
    """What a map holds of each cell besides the statistics: its most likely class, its status,
    its ensemble's seed and the water depth it used."""
    yx = (MAP_Y, MAP_X)
    return [
        Variable(
            "most_likely_burial_class",
            yx,
            "int8",
            None,
            "most likely impact-burial class",
            "Class with the highest burial_class_probability in the cell (the lower class on ties); "
            "-1 where the cell was not computed or no drop came to rest.",
            attrs={
                **_flag_attrs(range(-1, 5), ("no_data", *BURIAL_CLASS_MEANINGS)),
                "coverage_content_type": "modelResult",
            },
        ),
        Variable(
            "cell_status",
            yx,
            "int8",
            None,
            "status of the map cell",
            "0: an ensemble was run; 1: land (water depth missing or <= 0), skipped; 2: no sediment "
            "data, skipped.",
            attrs={
                **_flag_attrs(range(3), CELL_STATUS_MEANINGS),
                "coverage_content_type": "qualityInformation",
            },
        ),
        Variable(
            "cell_seed",
            yx,
            "uint64",
            None,
            "random seed of the cell's ensemble",
            "First 8 bytes (little-endian) of SHA-256 of 'mineburial-map-cell:<seed>:<k>' with <seed> "
            "the global attribute random_seed and k = row * n_columns + column; rerun a cell with "
            "mineburial run --seed <cell_seed>. 0 for skipped cells.",
            attrs={"coverage_content_type": "auxiliaryInformation"},
        ),
        Variable(
            "cell_drop_count",
            yx,
            "int64",
            "1",
            "number of drops of the cell's ensemble",
            "Drops the cell's ensemble ran: its first cell_drop_count drops of seed cell_seed, on which "
            "every statistic of the cell rests (the global attribute n_drops_per_cell; fewer where the "
            "map stopped the cell early, the global attribute sequential_stopping); rerun a cell with "
            "mineburial run --seed <cell_seed> -n <cell_drop_count>. 0 for skipped cells.",
            fill_value=_NO_FILL,
            attrs={"coverage_content_type": "auxiliaryInformation"},
        ),
        Variable(
            "water_depth",
            yx,
            "float64",
            "m",
            "water depth",
            "Water depth of the cell used by its ensemble (from the environment grid's water_depth, "
            "read as <how the grid gives it: a depth or an elevation, and by which attribute>).",
            standard_name="sea_floor_depth_below_sea_surface",
            attrs={"coverage_content_type": "referenceInformation"},
            runtime_attrs=("comment",),
        ),
    ]


#: units of a map's linear sediment profile, by key of the environment grid's ``sediment_<key>``
MAP_SEDIMENT_UNITS = {
    "density": "kg m-3",
    "density_gradient": "kg m-4",
    "strength": "Pa",
    "strength_gradient": "Pa m-1",
}


def _map_environment_variables() -> list[Variable]:
    """The environment of each cell as its ensemble used it: the sediment (a catalogue class or a
    linear profile), the current, and the grid's axes and grid mapping as the grid gives them."""
    yx, ref = (MAP_Y, MAP_X), {"coverage_content_type": "referenceInformation"}
    out = [
        Variable(
            "sediment_class",
            yx,
            "int8",
            None,
            "seabed sediment class",
            "Catalogue class of the cell (mineburial.systems.mine.sediment_profiles); -1: none.",
            attrs=ref,
            fill_value=-1,
            runtime_flags="mineburial.systems.mine.sediment_profiles.class_names()",
        )
    ]
    out += [
        Variable(
            f"sediment_{key}",
            yx,
            "float64",
            units,
            f"seabed sediment {key.replace('_', ' ')}" + (" at the seabed" if "_" not in key else ""),
            "",
            attrs=ref,
        )
        for key, units in MAP_SEDIMENT_UNITS.items()
    ]
    out += _current_components(
        yx, "", "Current used by the cell's ensemble (E-frame x = east, y = north).", ref
    )
    grid = "Named as in the environment grid, with its attributes"
    out += [
        Variable("grid_mapping", (), "int32", None, "grid mapping of the environment grid", grid + ".",
                 from_input=True),
        Variable(MAP_Y, (MAP_Y,), "float64", None, "y axis of the environment grid",
                 grid + " (latitude: standard_name, units degrees_north and axis Y added where missing).",
                 from_input=True),
        Variable(MAP_X, (MAP_X,), "float64", None, "x axis of the environment grid",
                 grid + " (longitude: standard_name, units degrees_east and axis X added where missing).",
                 from_input=True),
    ]  # fmt: skip
    out += [
        Variable(
            axis,
            yx,
            "float64",
            f"degrees_{'north' if axis == 'latitude' else 'east'}",
            axis,
            "",
            standard_name=axis,
        )
        for axis in ("latitude", "longitude")  # of each cell of a projected grid (its grid mapping)
    ]
    return out


def _map_variables() -> list[Variable]:
    """The burial map of :mod:`mineburial.analyses.maps`: the ensemble statistics per cell, the class
    bounds and the coordinates of the statistics, each cell's status, seed and environment."""
    own = [_per_cell(name, p) for p in PROCESS_VARIABLES.values() for name in p.map_statistics()]
    return [
        *(_per_cell(name) for name in MAP_STATISTICS),
        *own,
        *(_per_cell(name) for name in MAP_EPISTEMIC),
        VARIABLES["burial_class_lower_percent"],
        VARIABLES["burial_class_upper_percent"],
        *_map_cell_variables(),
        *_map_environment_variables(),
        *(VARIABLES[name] for name in map_shared_coords()),
    ]


# ---------------------------------------------------------------------------
# the comparison of variants (mineburial.analyses.compare): the same drops under each value
# of one field
# ---------------------------------------------------------------------------
#: the burial measures whose statistics a comparison holds per variant
COMPARE_OUTPUTS = ("penetration_depth", "burial_volume", "burial_height", "burial_area", "height_proud")
#: the measures whose paired differences and per-drop values it holds
COMPARE_PER_DROP = ("penetration_depth", "burial_volume")
_COMPARE_CLASS = (
    "burial_class_count",
    "burial_class_probability",
    "burial_class_probability_lower",
    "burial_class_probability_upper",
    "status_count",
)


def _per_variant(name: str) -> Variable:
    """The ensemble statistic ``name`` of each variant (a ``variant`` axis first)."""
    var = VARIABLES[name]
    return dataclasses.replace(var, dims=("variant", *var.dims))


def _paired_variables(name: str) -> list[Variable]:
    """The paired difference of output ``name`` to the first variant over the drops in both
    statistics, its normal bounds at the run's confidence level, and that number of drops."""
    v, units = ("variant",), SUMMARY_OUTPUTS[name].units
    bound = "bound of the paired difference (normal approximation)"
    runtime = ("long_name",)  # the first variant's value, the confidence level
    return [
        Variable(f"{name}_mean_difference", v, "float64", units,
                 f"mean paired difference of {name} to variant <the first> (same drops)", "",
                 runtime_attrs=runtime),
        Variable(f"{name}_mean_difference_lower", v, "float64", units,
                 f"lower <confidence level> {bound}", "", runtime_attrs=runtime),
        Variable(f"{name}_mean_difference_upper", v, "float64", units,
                 f"upper <confidence level> {bound}", "", runtime_attrs=runtime),
        Variable(f"{name}_n_paired", v, "int64", "1",
                 "drops in the statistics of this and the first variant", ""),
    ]  # fmt: skip


def _comparison_variables() -> list[Variable]:
    """A comparison (:func:`mineburial.analyses.compare.run_comparison`): each variant's burial
    statistics (no histograms) with normal bounds of the means, the paired differences to the first
    variant, each drop's values and status per variant, the slots each variant changed; the
    sampled inputs (``input_*``, the same for every variant) once."""
    stats = [f"{o}_{s}" for o in COMPARE_OUTPUTS for s in ("mean", "std", "stderr", "quantile", "exceedance")]
    out = [_per_variant(name) for name in stats]
    out += [VARIABLES["burial_class_lower_percent"], VARIABLES["burial_class_upper_percent"]]
    out += [_per_variant(name) for name in _COMPARE_CLASS + MAP_EPISTEMIC]
    out += [
        Variable(
            f"{o}_mean_{side}",
            ("variant",),
            "float64",
            SUMMARY_OUTPUTS[o].units,
            f"{side} bound of the mean of {o} (normal approximation, mean -/+ z stderr)",
            "",
            attrs={"cell_methods": "realization: mean", "coverage_content_type": "modelResult"},
        )
        for o in COMPARE_OUTPUTS
        for side in ("lower", "upper")
    ]
    out.append(
        Variable("n_in_statistics", ("variant",), "int64", "1", "drops in the statistics of the variant", "")
    )
    out += [var for name in COMPARE_PER_DROP for var in _paired_variables(name)]
    vr = ("variant", "realization")
    out += [
        Variable(f"drop_{o}", vr, "float64", SUMMARY_OUTPUTS[o].units, f"{o} of each drop", "")
        for o in COMPARE_PER_DROP
    ]
    out.append(
        Variable("drop_status", vr, "int8", None, "drop status", "",
                 attrs=_status_flags(_MINE_STATUS))
    )  # fmt: skip
    out.append(
        Variable("changed_parameters", ("variant",), "object", None,
                 "packed parameter slots that differ from the first variant", "")
    )  # fmt: skip
    out += [VARIABLES[name] for name in ("quantile", *(f"{o}_level" for o in COMPARE_OUTPUTS))]
    out += [VARIABLES["impact_burial_class"], VARIABLES["status_code"]]
    out += [
        Variable("variant", ("variant",), "object", None, "value of <the varied field>", "",
                 runtime_attrs=("long_name",)),
        Variable("realization", ("realization",), "int64", None, "drop index", ""),
    ]  # fmt: skip
    return out


#: what a file of each kind is (the default ``history`` line of :func:`mineburial.io.dataset.standard_attrs)
FAMILY_TITLES = {
    "ensemble": "Monte Carlo ensemble of mine drops",
    "trajectory": "trajectory of one mine drop",
    "restraint_run": "time series of one case of the restraining system",
    "restraint_ensemble": "ensemble of cases of the restraining system",
    "sensitivity": "Sobol' sensitivity indices",
    "environment": "synthetic environment grid (invented values)",
    "map": "burial map over an environment grid",
    "comparison": "comparison of variants of an ensemble scenario",
}
#: the variables of each file kind: the mine ensemble's (:data:`VARIABLES`) and one family each for
#: the single drop's trajectory, the restraint's time series, the restraint ensemble, the Sobol'
#: sensitivity analysis, the synthetic environment grid, the burial map and the comparison
FAMILIES: dict[str, dict[str, Variable]] = {
    "ensemble": VARIABLES,
    "trajectory": _family(_trajectory_variables(), "trajectory"),
    "restraint_run": _family(_restraint_run_variables(), "restraint_run"),
    "restraint_ensemble": _family(_restraint_ensemble_variables(), "restraint_ensemble"),
    "sensitivity": _family(_sensitivity_variables(), "sensitivity"),
    "environment": _family(_environment_variables(), "environment"),
    "map": _family(_map_variables(), "map"),
    "comparison": _family(_comparison_variables(), "comparison"),
}


def family(kind: str) -> dict[str, Variable]:
    """The declared variables of a file of ``kind`` (a key of :data:`FAMILIES`)."""
    try:
        return FAMILIES[kind]
    except KeyError:
        raise KeyError(_unknown("dataset kind", kind, FAMILIES)) from None


# ---------------------------------------------------------------------------
# look-up and documentation
# ---------------------------------------------------------------------------


def _unknown(what: str, name: str, known) -> str:
    close = difflib.get_close_matches(name, list(known), n=3)
    hint = f"; did you mean {', '.join(map(repr, close))}?" if close else ""
    return f"unknown {what} {name!r}{hint}"


def variable(name: str) -> Variable:
    """The declaration of the output variable ``name`` (``input_*`` names are not in the registry)."""
    try:
        return VARIABLES[name]
    except KeyError:
        raise KeyError(_unknown("output variable", name, VARIABLES)) from None


def _md_escape(text: str) -> str:
    return text.replace("|", "\\|")


def _md_row(var: Variable, name: str | None = None) -> str:
    dims = ", ".join(var.dims) if var.dims else "(scalar)"
    units = f"(from `{var.dims[0]}`)" if var.is_bounds else (var.units or "")
    if var.from_input:
        units = "(the input's)"
    cf = var.standard_name or ""
    extra = ""
    if "flag_values" in var.attrs:
        pairs = zip(np.asarray(var.attrs["flag_values"]).tolist(), var.attrs["flag_meanings"].split())
        extra = " Flags: " + ", ".join(f"{v} `{m}`" for v, m in pairs) + "."
    elif var.runtime_flags:
        extra = (
            f" Flags: the codes of `{var.runtime_flags}` (flag_values/flag_meanings written by the writer)."
        )
    if var.runtime_attrs:
        extra += f" The writer completes `{'`, `'.join(var.runtime_attrs)}` (<...> above) at run time."
    return (
        f"| `{name or var.name}` | {dims} | {var.dtype} | {units} | {cf} | "
        f"{_md_escape(var.long_name)} | {_md_escape(var.description + extra)} |"
    )


_MD_HEADER = (
    "| name | dims | dtype | units | standard_name | long_name | description |\n|---|---|---|---|---|---|---|"
)


def variables_markdown(expand: bool = False) -> str:
    """Markdown tables of every output variable.

    With ``expand=False`` the statistics of the summary outputs are shown once
    as templates with ``X`` standing for any summary output (using
    ``penetration_depth`` for units); with ``expand=True`` every variable is listed.
    """
    per_drop = [_md_row(v) for v in VARIABLES.values() if v.group == "per-drop"]
    example = input_variable("mine.mass", "kg", "mass of the mine")
    per_drop.append(
        _md_row(
            dataclasses.replace(
                example,
                name="input_<path>",
                units="as given",
                long_name="sampled <path>",
                description="Value of the scenario field <path> (dots become underscores: mine.mass -> "
                "input_mine_mass) sampled for each drop; attribute scenario_path holds the "
                "dotted path, units and description are those handed to build_dataset.",
            )
        )
    )
    stat_vars = [v for v in VARIABLES.values() if v.group == "statistics"]
    if expand:
        stats = [_md_row(v) for v in stat_vars]
    else:
        template = set(statistic_names("penetration_depth"))
        others = set().union(*(statistic_names(o) for o in SUMMARY_OUTPUTS))
        stats = []
        for v in stat_vars:
            if v.name in template:
                tv = dataclasses.replace(
                    v,
                    name=v.name.replace("penetration_depth", "X"),
                    dims=tuple(d.replace("penetration_depth", "X") for d in v.dims),
                    units="units of X" if v.units == "m" else v.units,
                    long_name=v.long_name.replace("penetration depth of the lowest point of the mine", "X"),
                    description=v.description.replace("penetration_depth", "X"),
                )
                stats.append(_md_row(tv))
            elif v.name not in others:
                stats.append(_md_row(v))
    others = "".join(
        f"\n### {heading}\n\n{_MD_HEADER}\n"
        + "\n".join(_md_row(var) for var in FAMILIES[kind].values())
        + "\n"
        for kind, heading in _FAMILY_HEADINGS.items()
    )
    return (
        "### Per-drop variables (dimension `realization`)\n\n"
        + _MD_HEADER
        + "\n"
        + "\n".join(per_drop)
        + "\n\n### Statistics variables\n\n"
        + _MD_HEADER
        + "\n"
        + "\n".join(stats)
        + "\n"
        + others
    )


#: the Markdown headings of the families other than the mine ensemble's
_FAMILY_HEADINGS = {
    "trajectory": "Drop trajectory (`mineburial drop`; the forces and torques with `--forces`)",
    "restraint_run": "Restraining-system time series (`mineburial restrain`)",
    "restraint_ensemble": "Restraining-system ensemble (`mineburial run` of a restraint scenario)",
    "sensitivity": "Sobol' sensitivity indices (`mineburial sensitivity`)",
    "environment": (
        "Synthetic environment grid (`python -m mineburial.analyses.synthetic`, the maps' input format)"
    ),
    "map": "Burial map (`mineburial map`; `y`, `x` and `grid_mapping` named as in the environment grid)",
    "comparison": "Comparison of variants (`mineburial compare`; the sampled inputs `input_<path>` once)",
}
