"""The optional ``[scour]`` section of an ensemble scenario: the post-impact scour stage of every
drop (issue 20; docs/scour.md, docs/scenario.md).

:func:`parse` reads the section (the forcing from a file or an inline storm, lead times, burial
levels, sediment and law choices) into a :class:`ScourSpec`; its numeric fields are ordinary
fields of :data:`mineburial.systems.mine.config.FIELDS` (``scour.*``), so they are checked, sampled (Philox
streams keyed by the field name: no other input's draws change) and validated per drop like
every other input. :func:`run_chunk` runs the compiled stage over the drops of a chunk after
their impact phase; :func:`dataset` adds the statistics and per-drop variables of the stage to a
run's Dataset; :func:`summary_lines` the class probabilities per lead time to the run summary.
:data:`PROCESS` puts them behind the post-impact process protocol
(:class:`mineburial.systems.mine.processes.registry.Process`), through which the mine's ensemble, maps,
``compare``, ``sensitivity`` and the lead-time figure reach the stage.
A scenario without the section runs exactly as before: nothing here is called.
"""

from __future__ import annotations

import dataclasses
import datetime as _dt
import functools
import hashlib
import inspect
import json
import math
import pathlib
from collections.abc import Mapping

import numba
import numpy as np

from mineburial._deferred import xarray as xr
from mineburial.ensembles.threads import run_blocks
from mineburial.io import forcing as fio
from mineburial.io import variables as V
from mineburial.io import wave_products
from mineburial.kernels.mine import layout
from mineburial.kernels.mine import scour as sc
from mineburial.kernels.mine import status as status_codes
from mineburial.kernels.mine.bodies.shapes import shape_named, shape_of_params
from mineburial.kernels.mine.scour_batch import MEASURE_NAMES, N_REST, R_AZ, R_ZC, scour_drops_ends
from mineburial.systems.mine import config as cfg
from mineburial.systems.mine.processes import scour_figure, scour_map, scour_variables
from mineburial.systems.mine.processes.scour_map import CellForcing
from mineburial.systems.mine.processes.scour_variables import SCOUR_MEASURES, SCOUR_STATUS_NAMES
from mineburial.systems.mine.scenario_fields import SCOUR_BURIAL_LAWS, SCOUR_LAW_FROM_POSTERIOR
from mineburial.systems.mine.sediment_profiles import CATALOGUE, catalogue_profile
from mineburial.systems.mine.statistics import scour_statistics

#: the section's fields that fill a slot of the stage's parameter vector, by the kernel's names
#: (kernels/mine/scour.py ``PARAM_NAMES``): field name -> slot, in slot order
FIELD_SLOTS = {path.split(".", 1)[1]: k for k, path in enumerate(sc.PARAM_NAMES) if path.startswith("scour.")}
#: the bed's cohesion: a flag of the section and of the sediment class, not a sampled number
_FLAGS = ("cohesive",)
#: the conventions of the section (cfg.SCHEMA choices ``scour.<name>``) and the stage slot each fills
CHOICES = {name: k for name, k in FIELD_SLOTS.items() if cfg.SCHEMA[f"scour.{name}"].choices}
#: numeric fields of the section (cfg.FIELDS ``scour.<name>``) and the stage slot each fills; the
#: two that act on the forcing, not the stage, have none
NUMERIC = {name: k for name, k in FIELD_SLOTS.items() if name not in CHOICES and name not in _FLAGS}
NUMERIC.update(
    hs_scale=None,  # scales the forcing, not a stage parameter
    window_position=None,  # where the drop's window starts in the forcing, not a stage parameter
)
#: ``burial_law = "posterior"``: each drop's law is the sampled input LAW_INPUT (its posterior set's
#: law, as the kernel's code), drawn with its coefficient set (systems/mine/calibration/posterior.py)
LAW_FROM_POSTERIOR = SCOUR_LAW_FROM_POSTERIOR
LAW_INPUT = "scour.burial_law"
#: the fields only the scour-and-settle law reads (left out of the resolved section under rennie)
SETTLE_ONLY = ("wave_a", "wave_kc_exponent", "infill_days", "bed_lowering_rate")
#: the section's fields given in days that the stage reads in seconds: factor to its slot's unit
TO_SECONDS = {"infill_days": 86400.0, "bed_lowering_rate": 1.0 / 86400.0}
#: the keys of the section, declared in mineburial/systems/mine/scenario_fields.py
KEYS = tuple(f.name for f in cfg.SCHEMA.values() if f.section == "scour")
#: the scour sediment a scenario's sediment class gives where the section does not (docs/scour.md, Sediment)
SEDIMENT = ("d50", "grain_density", "cohesive")
SLOT = dict(NUMERIC, cohesive=FIELD_SLOTS["cohesive"])
DEFAULT_LEVELS = cfg.SCHEMA["scour.burial_levels"].default
DAY = 86400.0
#: the forcing files shipped with the package, named without extension in ``scour.forcing``
SHIPPED = pathlib.Path(__file__).resolve().parent.parent.parent.parent / "data" / "forcing"
assert MEASURE_NAMES == SCOUR_MEASURES
assert cfg.SCHEMA["scour.orbital"].choices[sc.ORBITAL_HRMS] == "hrms"
assert cfg.SCHEMA["scour.orbital"].choices[sc.ORBITAL_HS] == "hs"
assert cfg.SCHEMA["scour.friction"].choices[sc.FRICTION_SOULSBY] == "soulsby"
assert cfg.SCHEMA["scour.tstar_law"].choices == tuple(sc.TSTAR_LAWS)
assert cfg.SCHEMA["scour.burial_law"].choices[sc.BURIAL_SCOUR_SETTLE] == "scour_settle"
assert SCOUR_BURIAL_LAWS[sc.BURIAL_RENNIE] == "rennie"  # a posterior's law column holds these codes
assert SCOUR_BURIAL_LAWS[sc.BURIAL_SCOUR_SETTLE] == "scour_settle"
assert cfg.SCHEMA["scour.mobility"].choices[sc.MOBILITY_POCKET] == "pocket"
assert cfg.SCHEMA["scour.rest_attitude"].choices[sc.REST_IMPACT] == "impact"
assert {*NUMERIC, *CHOICES} <= set(KEYS)


@dataclasses.dataclass(frozen=True)
class ScourSpec:
    """The resolved ``[scour]`` section: what every drop's stage needs beside its own inputs."""

    lead_times_days: tuple
    burial_levels: tuple
    tstar_law: str
    cohesive: bool
    values: dict  # scour.<name> -> fixed value (representative for a sampled one; mobile_layer inf: none)
    forcing: fio.Forcing
    forcing_record: dict  # file path + sha256, or the storm's parameters
    window_days: float | None = None  # each drop's window of the forcing (None: the whole series)
    conventions: dict = dataclasses.field(default_factory=dict)  # orbital, friction -> name
    # scour sediment taken from the scenario's sediment class: key -> one value, or (sampled class)
    # a value per label of the sediment.class choice, in bank order
    from_class: dict = dataclasses.field(default_factory=dict)

    def resolved(self) -> dict:
        out = {
            "lead_times_days": list(self.lead_times_days),
            "burial_levels": list(self.burial_levels),
            "tstar_law": self.tstar_law,
            "cohesive": self.cohesive,
        }
        out.update(self.conventions)
        if out.get("rest_attitude") == "flat":  # the default: a flat section resolves as before it existed
            del out["rest_attitude"]
        unused = set()  # the coefficients of a law or criterion the section does not use
        if self.conventions.get("burial_law", "rennie") not in ("scour_settle", LAW_FROM_POSTERIOR):
            unused.update(SETTLE_ONLY)  # a law per drop from the posterior: some drops read them
        if self.conventions.get("mobility", "proud") != "pocket":
            unused.add("mobility_drag")
        out.update({k: v for k, v in self.values.items() if math.isfinite(v) and k not in unused})
        for key, value in self.from_class.items():  # one value per label of a sampled class: a list
            out[key] = list(value) if isinstance(value, tuple) else value
        if self.from_class:
            out["sediment_from_class"] = sorted(self.from_class)
        if self.window_days is not None:
            out["window_days"] = self.window_days
        out.update(self.forcing_record)
        return out

    def identity(self) -> bytes:
        arrays = (self.forcing.time, self.forcing.hs, self.forcing.tp, self.forcing.wave_from)
        arrays += (self.forcing.current_speed, self.forcing.current_to, self.forcing.water_level)
        return repr(sorted(self.resolved().items())).encode() + b"".join(a.tobytes() for a in arrays)


def _shown(value: float, *bounds: float) -> str:
    """``value`` as ``:g`` text, or in full (``repr``) when that text equals a bound's: was
    "lead time 4 is outside the allowed range [0, 4]" for 4.0000001 (issue 35)."""
    text = f"{value:g}"
    return repr(float(value)) if any(text == f"{b:g}" for b in bounds) else text


def _numbers(value, location, *, low, high, default):
    if value is None:
        return tuple(default)
    if isinstance(value, (str, bytes, Mapping)) or not hasattr(value, "__len__") or not len(value):
        raise cfg.ScenarioError(f"{location} = {value!r} must be a non-empty list of numbers")
    out = tuple(cfg._number(v, f"{location}[{i}]") for i, v in enumerate(value))
    for i, v in enumerate(out):
        if not (low <= v <= high):
            raise cfg.ScenarioError(
                f"{location}[{i}] = {_shown(v, low, high)} is outside the allowed range [{low:g}, {high:g}]"
            )
    if any(b <= a for a, b in zip(out, out[1:])):
        raise cfg.ScenarioError(f"{location} = {list(out)} must be strictly increasing")
    return out


def _location(value, path):
    """(lat, lon) of ``scour.forcing_location`` for a wave product's file, or None when absent."""
    if value is None:
        return None
    where = f"scour.forcing_location = {value!r}"
    if isinstance(value, (str, bytes, Mapping)) or not hasattr(value, "__len__") or len(value) != 2:
        raise cfg.ScenarioError(f"{where} must be [latitude, longitude] in degrees")
    lat = cfg._number(value[0], "scour.forcing_location[0]")
    lon = cfg._number(value[1], "scour.forcing_location[1]")
    if not (-90.0 <= lat <= 90.0 and -360.0 <= lon <= 360.0):
        raise cfg.ScenarioError(f"{where}: allowed latitude [-90, 90], longitude [-360, 360] degrees")
    if pathlib.Path(path).suffix.lower() not in wave_products.SUFFIXES:
        raise cfg.ScenarioError(
            f"{where} picks a point of a gridded wave product (.nc or .grib); '{path}' is not one"
        )
    return float(lat), float(lon)


def _forcing(sec, base_dir):
    """The forcing of the section and what identifies it (file path and sha256, or the storm)."""
    if sum(k in sec for k in ("forcing", "storm", "forcing_grid")) != 1:
        raise cfg.ScenarioError(
            "[scour]: give exactly one of forcing = '<file .csv or .nc>', storm = {peak_hs = ..., ...} "
            "or (maps only) forcing_grid = '<file .nc>'"
        )
    if "forcing_location" in sec and "forcing" not in sec:
        raise cfg.ScenarioError(
            "scour.forcing_location picks a point of the wave product given as scour.forcing = '<file .nc>'; "
            "give that file"
        )
    if "forcing_grid" in sec:
        cell = sec["forcing_grid"]
        if isinstance(cell, CellForcing):
            return cell.forcing, dict(cell.record)
        raise cfg.ScenarioError(
            f"scour.forcing_grid = {cell!r}: a gridded forcing (time, y, x) is read by `mineburial map` "
            "only, each cell its own series; other commands take forcing = '<file>' or storm = {...}"
        )
    if "forcing" in sec:
        path = sec["forcing"]
        if not isinstance(path, str):
            raise cfg.ScenarioError(f"scour.forcing = {path!r} must be a file path (.csv or .nc)")
        p = pathlib.Path(path)
        if not p.suffix:  # the name of a shipped forcing (mineburial/data/forcing/<name>.csv)
            shipped = sorted(q.stem for q in SHIPPED.glob("*.csv"))
            if path not in shipped:
                raise cfg.ScenarioError(
                    "scour.forcing: " + cfg.unknown_names_message("shipped forcing", [path], shipped)
                )
            p = SHIPPED / f"{path}.csv"
        elif not p.is_absolute() and base_dir is not None:
            p = pathlib.Path(base_dir) / p
        location = _location(sec.get("forcing_location"), p)
        f = fio.load_forcing(p) if location is None else wave_products.load_wave_point(p, *location)
        digest = hashlib.sha256(p.read_bytes()).hexdigest()
        record = {"forcing_file": str(p), "forcing_sha256": digest}
        if location is not None:
            record.update(forcing_location=list(location), forcing_interpolation=wave_products.METHOD)
        return f, record
    storm = sec["storm"]
    allowed = tuple(inspect.signature(fio.storm_series).parameters)
    if not isinstance(storm, Mapping):
        raise cfg.ScenarioError(f"scour.storm = {storm!r} must be a table of {', '.join(allowed)}")
    unknown = [k for k in storm if k not in allowed]
    if unknown:
        raise cfg.ScenarioError("scour.storm: " + cfg.unknown_names_message("key", unknown, allowed))
    missing = [k for k in ("peak_hs", "peak_tp", "duration_h") if k not in storm]
    if missing:
        raise cfg.ScenarioError(
            f"scour.storm: {', '.join(missing)} missing (required: peak_hs, peak_tp, duration_h)"
        )
    for k, v in storm.items():
        if k not in ("ramp", "start"):
            cfg._number(v, f"scour.storm.{k}")
    # the record is written as JSON in the output's attributes: an unquoted TOML datetime as
    # start is kept as its ISO 8601 text (was: a traceback after every drop was computed, issue 35)
    record = {k: v.isoformat() if isinstance(v, (_dt.date, _dt.time)) else v for k, v in storm.items()}
    return fio.storm_series(**storm), {"forcing_storm": record}


def sediment_classes(sediment, choice) -> tuple:
    """The catalogue classes (:class:`~mineburial.systems.mine.sediment_profiles.SedimentClass`) of a
    scenario's ``[sediment]`` table: the labels of a sampled ``sediment.class`` (``choice``, bank order), its
    fixed class, or none (a profile, a file, a linear table)."""
    if choice is not None:
        names = choice.values
    elif isinstance(sediment, Mapping) and isinstance(sediment.get("class"), str):
        names = (sediment["class"],)
    else:
        return ()
    for name in names:
        catalogue_profile(name)  # an unknown class: its one ScenarioError line
    return tuple(CATALOGUE[name] for name in names)


def _from_class(sec, classes) -> dict:
    """The scour sediment keys the section does not give, from ``classes`` (docs/scour.md, Sediment):
    one value when every class agrees, else a tuple with one per class. A cohesive class has no d50:
    the stage, which does not scour it, keeps the field's default there (mobility roughness only)."""
    out = {}
    for key in SEDIMENT:
        if key in sec or not classes:
            continue
        values = tuple(
            cfg.FIELDS["scour.d50"].default if key == "d50" and c.d50 is None else getattr(c, key)
            for c in classes
        )
        out[key] = values[0] if len(set(values)) == 1 else values
    return out


def parse(sec, base_dir=None, depth=None, classes=()) -> ScourSpec:
    """The :class:`ScourSpec` of a ``[scour]`` table whose sampled fields hold a representative
    value; every problem is one :class:`~mineburial.systems.mine.config.ScenarioError` line naming the field.
    ``depth``: the scenario's water depth when it is fixed (a forcing water level that dries the
    bed is then refused here; with a sampled depth such drops get scour status invalid_forcing).
    ``classes``: the scenario's sediment classes (:func:`sediment_classes`), whose d50, grain
    density and cohesion fill the keys the section does not give."""
    if not isinstance(sec, Mapping):
        raise cfg.ScenarioError(f"scour = {sec!r} must be a table: [scour]")
    unknown = [k for k in sec if k not in KEYS]
    if unknown:
        raise cfg.ScenarioError("[scour]: " + cfg.unknown_names_message("key", unknown, KEYS))
    forcing, record = _forcing(sec, base_dir)
    window = _window_days(sec, forcing.duration_s / DAY)
    high = longest_lead_days(forcing, window)
    leads = _numbers(sec.get("lead_times_days"), "scour.lead_times_days", low=0.0, high=high, default=())
    levels = _numbers(
        sec.get("burial_levels"), "scour.burial_levels", low=0.0, high=1.0, default=DEFAULT_LEVELS
    )
    law = sec.get("tstar_law", cfg.SCHEMA["scour.tstar_law"].default)
    if not isinstance(law, str):
        raise cfg.ScenarioError(f"scour.tstar_law = {law!r} must be a name: {', '.join(sc.TSTAR_LAWS)}")
    if law not in sc.TSTAR_LAWS:
        raise cfg.ScenarioError("scour.tstar_law: " + cfg.unknown_names_message("name", [law], sc.TSTAR_LAWS))
    from_class = _from_class(sec, classes)
    first = {key: v[0] if isinstance(v, tuple) else v for key, v in from_class.items()}
    cohesive = sec.get("cohesive", first.get("cohesive", False))
    if not isinstance(cohesive, bool):
        raise cfg.ScenarioError(f"scour.cohesive = {cohesive!r} must be true or false")
    values = {}
    for name in NUMERIC:
        spec = cfg.FIELDS[f"scour.{name}"]
        default = sc.TSTAR_LAWS[law][2] if name == "theta_exponent" else first.get(name, spec.default)
        given = sec.get(name)
        values[name] = (
            math.inf
            if given is None and default is None
            else cfg._check(spec.path, given if given is not None else default)
        )
    conventions = {
        name: cfg._check(f"scour.{name}", sec.get(name, cfg.SCHEMA[f"scour.{name}"].default))
        for name in CHOICES
    }
    if conventions["rest_attitude"] == "impact" and conventions["burial_law"] != "scour_settle":
        raise cfg.ScenarioError(
            f'scour.rest_attitude = "impact" needs scour.burial_law = "scour_settle" (the tilt settles '
            f'into a scour pit, a state of its own; got burial_law = "{conventions["burial_law"]}")'
        )
    if depth is not None:  # the one-line error of a bed that falls dry or below the stage's floor
        forcing.kernel_arrays(depth, values["d50"])
    return ScourSpec(leads, levels, law, cohesive, values, forcing, record, window, conventions, from_class)


def longest_lead_days(forcing, window_days) -> float:
    """The longest lead time [d] a section allows: each drop's window (``window_days``), or the
    forcing's span without one."""
    return forcing.duration_s / DAY if window_days is None else window_days


def at_lead_time(spec, lead_time: float | None):
    """``spec`` whose scour stage gives its burial measures at the one lead time [d] analysed:
    ``lead_time``, or the section's last lead time (the end of each drop's window of the
    forcing when the section names none). Without a ``[scour]`` section the outputs are the
    impact's and ``lead_time`` must be None. One :class:`ScenarioError` line for a lead time
    outside [0, the forcing's span or ``scour.window_days``]."""
    stage = spec.process(PROCESS.section)
    if stage is None:
        if lead_time is not None:
            raise cfg.ScenarioError(
                f"--lead-time {lead_time:g}: the scenario has no [scour] section; its burial is the "
                "impact's (give a [scour] section, or leave --lead-time out)"
            )
        return spec
    return spec.with_process(PROCESS.section, stage_at_lead_time(stage, lead_time))


def stage_at_lead_time(stage: ScourSpec, lead_time: float | None) -> ScourSpec:
    """``stage`` reporting the one lead time [d] analysed (:func:`at_lead_time`)."""
    longest = longest_lead_days(stage.forcing, stage.window_days)
    if lead_time is None:
        lead_time = stage.lead_times_days[-1] if stage.lead_times_days else longest
    elif not (0.0 <= lead_time <= longest):
        what = "scour.window_days" if stage.window_days is not None else "the forcing's span"
        raise cfg.ScenarioError(
            f"--lead-time {_shown(lead_time, 0.0, longest)} is outside the allowed range [0, {longest:g}] "
            f"days ({what})"
        )
    return dataclasses.replace(stage, lead_times_days=(float(lead_time),))


def after_scour(summary: np.ndarray, measures: np.ndarray, *, missing: str = "nan") -> np.ndarray:
    """``summary`` with its burial measures replaced by the scour stage's at its one lead time
    (``measures``: drops x :data:`~mineburial.systems.mine.processes.scour_variables.SCOUR_MEASURES` x 1): the
    outputs of ``compare`` and ``sensitivity`` at ``--lead-time``.

    A drop without a stage value (scour status not ok) gets NaN (``missing="nan"``): the
    burial statistics then leave it out, as ``run``'s statistics after scour do (was: counted
    with its impact burial, P(> 75 %) 0.25 against ``run``'s 1.00 on the same drops, issue 35).
    ``missing="impact"`` keeps its impact measures instead, for a Sobol' analysis, which needs
    a value at every point of its design (``sensitivity`` then warns, naming how many)."""
    if missing not in ("nan", "impact"):
        raise ValueError(f"missing must be 'nan' or 'impact', got {missing!r}")
    out = summary.copy()
    for k, name in enumerate(SCOUR_MEASURES):
        column = layout.SUMMARY_INDEX[name]
        value = measures[:, k, 0]
        otherwise = out[:, column] if missing == "impact" else np.nan
        out[:, column] = np.where(np.isfinite(value), value, otherwise)
    return out


def _window_days(sec, span_days):
    """The length [d] of each drop's window of the forcing (``window_days``), or None (the whole
    series); ``window_position`` (where in the series the window starts) needs it."""
    window = sec.get("window_days")
    if window is None:
        if "window_position" in sec:
            raise cfg.ScenarioError(
                "scour.window_position needs scour.window_days (the length of each drop's window "
                "of the forcing, days)"
            )
        return None
    window = cfg._number(window, "scour.window_days", "d")
    if not (0.0 < window <= span_days):
        raise cfg.ScenarioError(
            f"scour.window_days = {_shown(window, 0.0, span_days)} is outside the allowed range "
            f"(0, {span_days:g}] "
            "(the forcing's span, days)"
        )
    return window


@functools.lru_cache(maxsize=1)
def _orbital_table():
    return sc.build_orbital_table()


def _column(spec, inputs, name, n):
    path = f"scour.{name}"
    if path in inputs:
        return np.asarray(inputs[path], dtype=np.float64)
    return np.full(n, spec.values[name])


#: the tilt state is a lying body's (its two ends); a body that stands on its base in the stage has none
#: (docs/scour.md, Standing body; docs/bodies_revolution.md "The scour stage and a frustum")
NOT_FOR_STANDING = (
    "scour.rest_attitude = 'impact' with mine.shape = '{shape}': the tilt state levels a lying "
    "body's two ends; a {shape} stands on its base in the scour stage (docs/scour.md, Standing "
    "body); remove rest_attitude or give rest_attitude = 'flat'"
)


def stage_parameters(spec: ScourSpec, P, inputs):
    """(S, hs_scale): the stage parameters of each drop (the mine, the water and gravity from its
    packed impact parameters ``P``; the sediment and the laws from the section and its sampled
    inputs) and its factor on Hs."""
    n = P.shape[0]
    c, m, _, kc_min = sc.TSTAR_LAWS[spec.tstar_law]
    S = np.tile(
        sc.default_parameters(tstar_c=c, tstar_m=m, tstar_kc_min=kc_min, cohesive=float(spec.cohesive)),
        (n, 1),
    )
    shape = shape_of_params(P)  # the drop's body (kernels/mine/bodies/shapes.py)
    dims = shape.dims_of_params(P)
    volume = shape.volume(dims)
    S[:, sc.S_DIAMETER] = shape.reference_lengths(dims)[0]
    if shape.scour_attitude == "standing":  # a short body on its base: the pile laws (docs/scour.md)
        standing, diameter, height, flank = shape.scour_geometry(dims)
        S[:, sc.S_STANDING] = standing
        S[:, sc.S_DIAMETER] = diameter
        S[:, sc.S_HEIGHT] = height
        S[:, sc.S_FLANK_ANGLE] = flank
    S[:, sc.S_RHO_WATER] = P[:, layout.P_RHO_WATER]
    S[:, sc.S_MINE_SG] = P[:, layout.P_MASS] / (volume * P[:, layout.P_RHO_WATER])
    S[:, sc.S_NU] = P[:, layout.P_NU_WATER]
    S[:, sc.S_G] = P[:, layout.P_GRAVITY]
    for name, slot in NUMERIC.items():
        if slot is not None:
            S[:, slot] = _column(spec, inputs, name, n) * TO_SECONDS.get(name, 1.0)
    for name, value in spec.conventions.items():
        if name == "burial_law" and value == LAW_FROM_POSTERIOR:
            continue  # not a law: each drop's, below
        S[:, CHOICES[name]] = cfg.SCHEMA[f"scour.{name}"].pack(value)
    if (
        LAW_INPUT in inputs
    ):  # each drop's law, drawn with its coefficient set (systems/mine/calibration/posterior.py)
        S[:, CHOICES["burial_law"]] = np.asarray(inputs[LAW_INPUT], dtype=np.float64)
    elif spec.conventions.get("burial_law") == LAW_FROM_POSTERIOR:
        raise cfg.ScenarioError(
            f"scour.burial_law = {LAW_FROM_POSTERIOR!r} draws each drop's law from a posterior: give "
            "ensemble.coefficients = 'posterior' or a posterior file whose sets carry a law"
        )
    for name, per_class in spec.from_class.items():  # a sampled class: each drop its class's value
        if isinstance(per_class, tuple):
            S[:, SLOT[name]] = np.asarray(per_class, dtype=np.float64)[
                inputs["sediment.class"].astype(np.intp)
            ]
    return S, _column(spec, inputs, "hs_scale", n)


def window_starts(spec: ScourSpec, inputs, n):
    """(start [s] after the forcing's first record of each drop's window, its length [s]):
    ``window_position`` p in [0, 1] puts the start at p (span - length), so the window never
    leaves the series; without ``window_days`` every drop sees the whole series from its start."""
    span = spec.forcing.duration_s
    if spec.window_days is None:
        return np.zeros(n), span
    length = spec.window_days * DAY
    return _column(spec, inputs, "window_position", n) * (span - length), length


def run_chunk(spec: ScourSpec, P, summary, status, inputs) -> dict:
    """The stage's per-drop results of a chunk (keys ``scour:*``, stored with the chunk)."""
    n = P.shape[0]
    S, scale = stage_parameters(spec, P, inputs)
    run = np.isin(status, status_codes.IN_STATISTICS) & np.isfinite(summary[:, layout.S_PENETRATION])
    rest = np.empty((n, N_REST))  # the attitude and height at rest; the body is P's (drop_body)
    rest[:, R_AZ] = -np.sin(np.radians(summary[:, layout.S_FINAL_PITCH]))  # i_M . k, docs/scour.md
    rest[:, R_ZC] = -summary[:, layout.S_COM_DEPTH]
    P = np.ascontiguousarray(P, dtype=np.float64)
    f = spec.forcing
    # directions as Forcing.kernel_arrays gives them (radians towards); the depth is the drop's own
    wdir = np.radians(np.mod(f.wave_from + 180.0, 360.0))
    cdir = np.radians(np.mod(f.current_to, 360.0))
    t, hs, tp, uc = (np.array(a) for a in (f.time, f.hs, f.tp, f.current_speed))
    leads = np.asarray(spec.lead_times_days, dtype=np.float64) * DAY
    levels = np.asarray(spec.burial_levels, dtype=np.float64)
    measures = np.empty((n, len(MEASURE_NAMES), leads.size))
    time_to = np.empty((n, levels.size))
    mobile = np.empty(n)
    codes = np.empty(n, dtype=np.int8)
    pit = np.empty((n, leads.size))
    mobile_lead = np.empty((n, leads.size))
    tilt = np.empty((n, leads.size))
    depth = np.ascontiguousarray(P[:, layout.P_DEPTH])
    run = run.astype(np.uint8)
    level, table = np.array(f.water_level), _orbital_table()
    start, length = window_starts(spec, inputs, n)
    marker = shape_of_params(P).marker()  # None for the default shape: its kernels as before
    shape = () if marker is None else (marker,)

    def stage(a, b):  # rows [a, b): each drop's stage reads and writes only its own rows
        scour_drops_ends(
            S[a:b], scale[a:b], depth[a:b], run[a:b], P[a:b], rest[a:b], t, hs, tp, wdir, uc, cdir,
            level, start[a:b], length, table, leads, levels, measures[a:b], time_to[a:b], mobile[a:b],
            codes[a:b], pit[a:b], mobile_lead[a:b], tilt[a:b], *shape,
        )  # fmt: skip

    # in blocks on the drops' runner: Ctrl-C ends the stage within about a block, as the
    # impact phase (the chunk is then not kept), and the stage uses every thread
    run_blocks(n, stage, numba.get_num_threads())
    out = {
        "scour:measures": measures,
        "scour:time_to": time_to / DAY,
        "scour:mobile": mobile / DAY,
        "scour:status": codes,
        # the scour pit's depth [m] and whether the mine would move, at each lead time (issue 33)
        "scour:pit": pit,
        "scour:mobile_lead": mobile_lead,
        # of those that would move, the ones lying in an open pit (docs/scour.md, Mobility: what follows)
        "scour:mobile_in_pit": mobile_in_pit(mobile_lead, pit, S[:, sc.S_DIAMETER]),
        # where no post-impact process is modelled: a cohesive bed (B_eq = 0, docs/scour.md)
        "scour:cohesive": (S[:, sc.S_COHESIVE] != 0.0).astype(np.uint8),
        # each drop's lead time 0 [s after the forcing's first record] (forecast_reference_time)
        "scour:window_start": np.asarray(start, dtype=np.float64),
    }
    if spec.conventions.get("rest_attitude") == "impact":
        out["scour:tilt"] = tilt  # the tilt [deg] at each lead time (docs/scour.md, Tilt)
    return out


def bytes_a_drop(spec: ScourSpec) -> int:
    """Bytes of the stage's per-drop values of a ``[scour]`` section ``spec``."""
    n_lead = len(spec.lead_times_days)
    tilt = 1 if spec.conventions.get("rest_attitude") == "impact" else 0
    return 8 * ((len(MEASURE_NAMES) + 3 + tilt) * n_lead + len(spec.burial_levels) + 2) + 2


def _per_drop(spec: ScourSpec, chunks):
    """(measures, time_to, mobile, status) of the chunks' drops in order (empty arrays of the
    right shapes without chunks)."""
    if not chunks:
        n_lead, n_lev = len(spec.lead_times_days), len(spec.burial_levels)
        return (
            np.empty((0, len(MEASURE_NAMES), n_lead)),
            np.empty((0, n_lev)),
            np.empty(0),
            np.empty(0, np.int8),
        )
    keys = ("scour:measures", "scour:time_to", "scour:mobile", "scour:status")
    return tuple(np.concatenate([r[key] for r in chunks]) for key in keys)


def _per_drop_states(spec: ScourSpec, chunks):
    """(pit depth [m], mobile 1/0, mobile in an open pit 1/0) of the chunks' drops at each lead
    time (drops x lead times); NaN for chunks stored before these states existed."""
    n_lead = len(spec.lead_times_days)
    out = []
    for key in ("scour:pit", "scour:mobile_lead", "scour:mobile_in_pit"):
        parts = [
            r[key] if key in r else np.full((len(r["scour:status"]), n_lead), np.nan) for r in chunks or ()
        ]
        out.append(np.concatenate(parts) if parts else np.empty((0, n_lead)))
    return tuple(out)


#: the pit depth, in diameters, from which a mine that would move lies in an open pit it rolls back
#: into rather than on a flat bed it may leave: the `proud` criterion's B/D = 0.1 (our choice,
#: docs/scour.md, Mobility)
PIT_OPEN = 0.1


def mobile_in_pit(mobile_lead, pit, diameter) -> np.ndarray:
    """1 where the mine would move at a lead time and lies in an open scour pit (pit depth >=
    :data:`PIT_OPEN` diameters), else 0; NaN where ``mobile_lead`` is (the stage did not run)."""
    mobile_lead = np.asarray(mobile_lead, dtype=np.float64)
    deep = np.asarray(pit, dtype=np.float64) >= PIT_OPEN * np.asarray(diameter, dtype=np.float64)[:, None]
    return np.where(np.isfinite(mobile_lead), (mobile_lead > 0.0) & deep, np.nan)


def mobile_probability(mobile_lead, codes) -> np.ndarray:
    """Share of the drops whose stage ran (status ok) that would move at each lead time (the
    criterion of ``scour.mobility``); NaN at a lead time without such a drop."""
    m = np.asarray(mobile_lead, dtype=np.float64)[np.asarray(codes) == 0]
    finite = np.isfinite(m)
    count = finite.sum(axis=0)
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.where(count > 0, np.where(finite, m, 0.0).sum(axis=0) / count, np.nan)


def statistics(spec: ScourSpec, chunks, class_basis: str) -> xr.Dataset:
    """The stage's statistics of an ensemble's chunks (a map cell's; none: the empty template),
    with the share of its drops on a bed where no post-impact process is modelled."""
    per_drop = _per_drop(spec, chunks)
    stats = scour_statistics(*per_drop, spec.lead_times_days, spec.burial_levels, class_basis=class_basis)
    stats = stats.assign(scour_not_modelled_fraction=_not_modelled(chunks, per_drop[3]))
    when = reference_time(spec)  # every drop (every map cell) sees the series from its first record
    if when is not None:
        stats = stats.assign_coords(forecast_reference_time=reference_time_variable(when))
    return stats


def _not_modelled(chunks, codes) -> xr.DataArray:
    """``scour_not_modelled_fraction``: the share of the drops whose stage ran (status ok) that lie
    on a cohesive bed, where the stage models no post-impact process and keeps the impact burial
    (docs/scour.md, Sediment); NaN without such drops (a cell where nothing came to rest)."""
    ok = np.asarray(codes) == 0
    if chunks and all("scour:cohesive" in r for r in chunks) and ok.any():
        cohesive = np.concatenate([r["scour:cohesive"] for r in chunks]).astype(bool)
        value = float(cohesive[ok].mean())
    else:
        value = math.nan
    return V.variable("scour_not_modelled_fraction").data_array(np.float64(value))


def reference_time(spec: ScourSpec, chunks=None):
    """The calendar date of lead time 0 (CF ``forecast_reference_time``) as numpy datetime64[s]
    (UTC): the forcing's first record plus the drops' common window start (from ``chunks``;
    without them: the first record when the drops see the whole series); None when the forcing
    has no dates (relative seconds, a storm without ``start``) or the drops' windows start at
    different times (a sampled ``window_position``: each drop its own lead time 0)."""
    storm = spec.forcing_record.get("forcing_storm")
    if spec.forcing.start is None or (isinstance(storm, Mapping) and "start" not in storm):
        return None  # a storm's default start (2000-01-01) is no date of the forcing
    offset = 0.0
    if spec.window_days is not None:
        starts = [r["scour:window_start"] for r in (chunks or ()) if "scour:window_start" in r]
        s = np.concatenate(starts) if starts else np.empty(0)
        if not s.size or not np.all(s == s[0]):
            return None
        offset = float(s[0])
    when = spec.forcing.start + np.timedelta64(int(round(offset * 1e9)), "ns")
    return when.astype("datetime64[s]")


def reference_time_variable(when) -> xr.DataArray:
    """The scalar coordinate ``forecast_reference_time`` (seconds since 1970-01-01 UTC) of ``when``."""
    seconds = (np.datetime64(when, "s") - np.datetime64("1970-01-01T00:00:00", "s")) / np.timedelta64(1, "s")
    return V.variable("forecast_reference_time").data_array(np.float64(seconds))


def lead_time_states(spec: ScourSpec, chunks, codes) -> dict:
    """Per lead time, over the drops whose stage ran: the share that would move, split into those
    lying in an open pit (they roll back into it) and those on a flat bed (they may migrate away),
    and the mean pit depth."""
    pit, mobile_lead, in_pit = _per_drop_states(spec, chunks)
    moving = mobile_probability(mobile_lead, codes)
    into_pit = mobile_probability(in_pit, codes)
    with np.errstate(invalid="ignore"):
        pit_mean = np.array(
            [np.mean(c[np.isfinite(c)]) if np.isfinite(c).any() else np.nan for c in pit[codes == 0].T],
            dtype=np.float64,
        )
    return {
        "scour_mobile_probability": V.variable("scour_mobile_probability").data_array(moving),
        "scour_mobile_into_pit_probability": V.variable("scour_mobile_into_pit_probability").data_array(
            into_pit
        ),
        "scour_mobile_away_probability": V.variable("scour_mobile_away_probability").data_array(
            moving - into_pit
        ),
        "scour_pit_depth_mean": V.variable("scour_pit_depth_mean").data_array(pit_mean),
    }


def dataset(spec: ScourSpec, chunks, ds: xr.Dataset, *, per_drop: bool, class_basis: str) -> xr.Dataset:
    """``ds`` with the stage's statistics (and per-drop variables with ``per_drop``) and the
    forcing's record in the global attributes."""
    measures, time_to, mobile, codes = _per_drop(spec, chunks)
    stats = scour_statistics(
        measures, time_to, mobile, codes, spec.lead_times_days, spec.burial_levels, class_basis=class_basis
    )
    stats["scour_not_modelled_fraction"] = _not_modelled(chunks, codes)
    when = reference_time(spec, chunks)
    if when is not None:
        stats = stats.assign_coords(forecast_reference_time=reference_time_variable(when))
    ok = codes == 0
    stats["scour_mobile_fraction_by_lead_time"] = V.variable("scour_mobile_fraction_by_lead_time").data_array(
        mobile_by_lead_time(mobile[ok], spec.lead_times_days)
    )
    stats = stats.assign(lead_time_states(spec, chunks, codes))
    tilt = _per_drop_tilt(chunks)
    if tilt is not None:  # rest_attitude = "impact": the tilt state's statistics (docs/scour.md, Tilt)
        stats = stats.assign(tilt_statistics(tilt[ok], stats["quantile"].values))
    parts = [ds, stats]
    if per_drop:
        pit, mobile_lead, _ = _per_drop_states(spec, chunks)
        data = {
            f"scour_{name}": V.variable(f"scour_{name}").data_array(measures[:, k])
            for k, name in enumerate(MEASURE_NAMES)
        }
        data["scour_time_to_level"] = V.variable("scour_time_to_level").data_array(time_to)
        data["scour_mobile_time"] = V.variable("scour_mobile_time").data_array(mobile)
        data["scour_status"] = V.variable("scour_status").data_array(codes)
        data["scour_pit_depth"] = V.variable("scour_pit_depth").data_array(pit)
        data["scour_mobile_at_lead_time"] = V.variable("scour_mobile_at_lead_time").data_array(mobile_lead)
        if tilt is not None:
            data["scour_tilt"] = V.variable("scour_tilt").data_array(tilt)
        parts.append(
            xr.Dataset(data, coords={"realization": ds["realization"], "lead_time": stats["lead_time"]})
        )
    out = xr.merge(parts, combine_attrs="override", compat="no_conflicts", join="exact")
    for part in parts:
        for name, da in part.variables.items():
            out[name].encoding.update(da.encoding)
    attrs = dict(ds.attrs)
    attrs["scour_n_in_statistics"] = stats.attrs["scour_n_in_statistics"]
    for key, value in spec.forcing_record.items():
        attrs[key] = value if isinstance(value, str) else json.dumps(value, sort_keys=True)
    out.attrs = attrs
    return out


def _per_drop_tilt(chunks):
    """The tilt [deg] of the chunks' drops at each lead time (drops x lead times), or None when the
    section lays the mine flat (``rest_attitude = "flat"``: no tilt state)."""
    if not chunks or not all("scour:tilt" in r for r in chunks):
        return None
    return np.concatenate([r["scour:tilt"] for r in chunks])


def tilt_statistics(tilt, quantiles) -> dict:
    """``scour_tilt_mean`` and ``scour_tilt_quantile`` (type 7) of ``tilt`` (drops x lead times,
    the drops whose stage ran) over its finite values at each lead time; NaN where there are none."""
    q = np.asarray(quantiles, dtype=np.float64)
    n_lead = tilt.shape[1]
    mean = np.full(n_lead, np.nan)
    quant = np.full((n_lead, q.size), np.nan)
    for j in range(n_lead):
        col = tilt[:, j][np.isfinite(tilt[:, j])]
        if col.size:
            mean[j] = np.mean(col)
            quant[j] = np.quantile(col, q, method="linear")
    return {
        "scour_tilt_mean": V.variable("scour_tilt_mean").data_array(mean),
        "scour_tilt_quantile": V.variable("scour_tilt_quantile").data_array(quant),
    }


def mobile_by_lead_time(mobile_days, lead_days) -> np.ndarray:
    """Share of the drops (``mobile_days``: each one's first time flagged mobile [d], inf never)
    flagged mobile by each lead time [d] (the figure's mobile line); NaN without drops."""
    m = np.asarray(mobile_days, dtype=np.float64)
    if not m.size:
        return np.full(len(lead_days), np.nan)
    return (m[:, None] <= np.asarray(lead_days, dtype=np.float64)[None, :]).mean(axis=0)


def _stands(ds) -> bool:
    """Whether the run's body stands on its base in the stage (its shape's ``scour_attitude``; the
    resolved scenario's ``mine.shape``): its burial levels are then fractions of its height h."""
    try:
        resolved = json.loads(ds.attrs["scenario"])
        name = resolved.get("scenario", resolved)["mine"]["shape"]
        return shape_named(name).scour_attitude == "standing"
    except (KeyError, TypeError, ValueError, AttributeError):
        return False


def summary_lines(ds) -> list[str]:
    """The class probabilities per lead time as a small table, the times to reach the levels and
    the share of drops flagged mobile."""
    if "scour_burial_class_probability" not in ds:
        return []
    p = ds["scour_burial_class_probability"].values
    labels = V.BURIAL_CLASS_NAMES
    n = int(ds.attrs.get("scour_n_in_statistics", 0))
    basis = ds["scour_burial_class_probability"].attrs.get("burial_class_basis", "burial_volume")
    lines = [
        f"scour: burial-class probabilities (by {basis}) of the {n} drops whose stage ran, per lead time:"
    ]
    lines.append("  lead [d] " + " ".join(f"{lab:>11}" for lab in labels))
    for j, lead in enumerate(ds["lead_time"].values):
        lines.append(f"  {lead:8.3g} " + " ".join(f"{v:11.3f}" for v in p[j]))
    tq = ds["scour_time_to_level_quantile"].sel(quantile=0.5).values
    unit = "B/h" if _stands(ds) else "B/D"  # the levels are fractions of the body's height on the bed
    for level, med, frac in zip(ds["burial_level"].values, tq, ds["scour_level_reached_fraction"].values):
        lines.append(f"  {unit} >= {level:g}: reached by {frac:.3f} of the drops, median time {med:.3g} d")
    counts = ds["scour_status_count"].values
    left = [f"{SCOUR_STATUS_NAMES[k]} {int(c)}" for k, c in enumerate(counts) if c and k != 0]
    if left:
        lines.append(
            "  left out of the scour statistics: "
            + ", ".join(left)
            + " (scour_status; docs/scour.md, status codes)"
        )
    lines.append(
        f"  flagged mobile (may roll or migrate; burial unchanged): {float(ds['scour_mobile_fraction']):.3f}"
    )
    if "scour_mobile_probability" in ds:
        values = " ".join(f"{v:.3f}" for v in ds["scour_mobile_probability"].values)
        lines.append(f"  would move at each lead time (scour_mobile_probability): {values}")
        if "scour_mobile_into_pit_probability" in ds:
            into = " ".join(f"{v:.3f}" for v in ds["scour_mobile_into_pit_probability"].values)
            lines.append(f"    of those, into their open pit (scour_mobile_into_pit_probability): {into}")
    if "scour_tilt_mean" in ds:  # rest_attitude = "impact"
        values = " ".join(f"{v:.1f}" for v in ds["scour_tilt_mean"].values)
        lines.append(f"  mean tilt [deg] at each lead time (scour_tilt_mean): {values}")
    return lines


class ScourProcess:
    """The scour stage as a post-impact process (:class:`mineburial.systems.mine.processes.registry.Process`):
    the functions above behind the protocol the mine's ensemble calls. Each method looks its
    function up when called (a test may replace one, e.g. :func:`run_chunk`)."""

    section = "scour"

    def load(self, section, *, base_dir, base, template, random) -> ScourSpec:
        standing = shape_named(base.mine.shape).scour_attitude == "standing"
        if standing and section.get("rest_attitude") == "impact":  # the tilt state is a lying body's
            raise cfg.ScenarioError(NOT_FOR_STANDING.format(shape=base.mine.shape))
        depth = None if "environment.water_depth" in random else base.environment.water_depth
        classes = sediment_classes(template.get("sediment"), random.get("sediment.class"))
        return parse(section, base_dir, depth, classes)

    def identity(self, spec: ScourSpec) -> bytes:
        return spec.identity()

    def resolved(self, spec: ScourSpec) -> dict:
        return spec.resolved()

    def input_files(self, spec: ScourSpec) -> tuple:
        rec = spec.forcing_record
        return ((rec["forcing_file"], rec["forcing_sha256"]),) if "forcing_file" in rec else ()

    def run_chunk(self, spec: ScourSpec, P, summary, status, inputs) -> dict:
        return run_chunk(spec, P, summary, status, inputs)

    def bytes_per_drop(self, spec: ScourSpec) -> int:
        return bytes_a_drop(spec)

    def variables(self) -> V.ProcessVariables:
        return scour_variables.DECLARED

    def statistics(self, spec: ScourSpec, chunks, class_basis: str) -> xr.Dataset:
        """A map cell's statistics: :func:`statistics` and, per lead time, the share flagged mobile
        by then, the share that would move and the mean pit depth, as :func:`dataset` gives them."""
        stats = statistics(spec, chunks, class_basis)
        _, _, mobile, codes = _per_drop(spec, chunks)
        ok = codes == 0
        return stats.assign(
            scour_mobile_fraction_by_lead_time=V.variable("scour_mobile_fraction_by_lead_time").data_array(
                mobile_by_lead_time(mobile[ok], spec.lead_times_days)
            ),
            **lead_time_states(spec, chunks, codes),
        )

    def cell_inputs(self, section, *, base_dir, cells):
        return scour_map.cell_inputs(section, base_dir, cells)

    def figure_panels(self, ds) -> list:
        return scour_figure.panels(ds, self.section)

    def dataset(self, spec: ScourSpec, chunks, ds, *, per_drop: bool, class_basis: str) -> xr.Dataset:
        return dataset(spec, chunks, ds, per_drop=per_drop, class_basis=class_basis)

    def summary_lines(self, ds) -> list[str]:
        return summary_lines(ds)

    def lead_times(self, spec: ScourSpec) -> tuple:
        return tuple(spec.lead_times_days)

    def map_attributes(self, spec: ScourSpec) -> tuple[str, dict]:
        text = (
            " With the post-impact scour stage ([scour], docs/scour.md), per cell and lead time: the "
            "scour-burial class probabilities with Wilson intervals, statistics of the burial measures, "
            "the times to reach the burial levels and the share of drops flagged mobile."
        )
        record = spec.forcing_record.items()
        return text, {k: v if isinstance(v, str) else json.dumps(v, sort_keys=True) for k, v in record}

    # the process changes the burial: compare and sensitivity analyse it at one lead time
    def at_lead_time(self, spec: ScourSpec, lead_time: float | None) -> ScourSpec:
        return stage_at_lead_time(spec, lead_time)

    def burial_after(self, spec: ScourSpec, summary, chunks, *, missing: str = "nan"):
        return after_scour(summary, np.concatenate([r["scour:measures"] for r in chunks]), missing=missing)

    def lacks_value(self, spec: ScourSpec, chunks):
        measures = np.concatenate([r["scour:measures"] for r in chunks])
        return ~np.isfinite(measures[:, :, 0]).all(axis=1)

    def status_text(self, chunks) -> str:
        codes = np.bincount(np.concatenate([r["scour:status"] for r in chunks]).astype(np.int64))
        return ", ".join(f"{SCOUR_STATUS_NAMES[k]} {int(n)}" for k, n in enumerate(codes) if n)


#: the stage's post-impact process, registered in :data:`mineburial.systems.mine.processes.registry.PROCESSES`
PROCESS = ScourProcess()
