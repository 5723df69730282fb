"""Forcing time series of waves, current and water level for the post-impact scour stage (issue 20).

A :class:`Forcing` holds one validated series: times [s] from the first record (and the UTC start
datetime when the source gives absolute times), significant wave height Hs [m], peak period Tp [s],
the direction the waves come from [deg, nautical: clockwise from north], the current speed [m/s],
the direction the current flows towards [deg, clockwise from north] and the water level [m] (0 when
the source has none). :meth:`Forcing.kernel_arrays` turns it into the flat float64 arrays that
:func:`mineburial.kernels.mine.scour.scour_stage` takes. A :class:`GriddedForcing` holds the same
quantities on (time, y, x) for maps and gives each cell's series.

Sources: a CF NetCDF file with a ``time`` coordinate (:func:`load_netcdf`,
:func:`load_gridded_netcdf`; variables found by CF ``standard_name`` or a documented name, units
converted through the ``units`` attribute), a CSV file with a header (:func:`load_csv`), or the
parametrised storm of :func:`storm_series`. Every reader applies the same checks; bad forcing raises
:class:`~mineburial.systems.mine.sediment_profiles.ScenarioError` with one line naming the file, the variable,
the time (ISO 8601, UTC) and the allowed range with its unit, and never quotes the file's content.
docs/scour.md (Forcing) lists the formats, conventions and checks.
"""

from __future__ import annotations

import csv
import datetime as _dt
import math
import os
import pathlib
import stat
from dataclasses import dataclass, replace

import numpy as np

from mineburial import resources
from mineburial._deferred import xarray as xr
from mineburial.errors import ScenarioError
from mineburial.io.files import atomic_path, atomic_write_text
from mineburial.io.inputs import numbered_csv, read_sized
from mineburial.kernels.mine.scour import depth_floor

__all__ = [
    "Forcing",
    "GriddedForcing",
    "load_forcing",
    "load_csv",
    "load_netcdf",
    "load_gridded_netcdf",
    "write_csv",
    "storm_series",
    "scale_hs",
    "window",
    "GAP_FACTOR",
    "PERIOD_RATIOS",
]

#: a time step more than GAP_FACTOR x the median step is a gap: one missing record of a regular
#: series (a step of 2x) passes and holds the previous record (each record holds until the next),
#: two or more in a row (3x) are refused
GAP_FACTOR = 2.5
#: largest file accepted [bytes]: CSV files are read whole; NetCDF files are read lazily
MAX_CSV_BYTES = 64 * 2**20
MAX_NETCDF_BYTES = 4 * 2**30

#: mean period / peak period of the JONSWAP spectrum the scour kernel assumes (gamma = 3.3,
#: sigma = 0.07 / 0.09; scour.jonswap_shape), from its spectral moments m_n = int f^n S(f) df over
#: (0, inf): Tm01 = m0/m1, Tm02 = sqrt(m0/m2), Tm-10 = m-1/m0 (the energy period). Computed by
#: quadrature (tests/test_forcing.py repeats it); the fits of DNV-RP-C205 (2010) sec. 3.5.5,
#: T1 = Tp (0.7303 + 0.04936 g - 0.006556 g^2 + 0.000361 g^3) = 0.8348 Tp and
#: Tz = Tp (0.6673 + 0.05037 g - 0.00623 g^2 + 0.0003341 g^3) = 0.7777 Tp, agree to 0.05 %.
PERIOD_RATIOS = {"tp": 1.0, "tm01": 0.83433, "tm02": 0.77740, "tm_10": 0.90330}

_LENGTH = {"m": 1.0, "meter": 1.0, "meters": 1.0, "metre": 1.0, "metres": 1.0, "cm": 0.01}
_TIME = {"s": 1.0, "sec": 1.0, "second": 1.0, "seconds": 1.0}
_SPEED = {
    "m s-1": 1.0,
    "m/s": 1.0,
    "m s^-1": 1.0,
    "m.s-1": 1.0,
    "cm s-1": 0.01,
    "cm/s": 0.01,
    "knot": 1852.0 / 3600.0,  # the international knot: 1852 m per hour, exactly
    "knots": 1852.0 / 3600.0,
    "kn": 1852.0 / 3600.0,
}
_ANGLE = {
    "degree": 1.0,
    "degrees": 1.0,
    "deg": 1.0,
    "degrees_true": 1.0,
    "degree true": 1.0,  # ERA5's spelling of mwd's units ("Degree true")
    "degrees true": 1.0,
    "rad": 180.0 / math.pi,
    "radian": 180.0 / math.pi,
    "radians": 180.0 / math.pi,
}
#: CSV column suffix -> units spelling
_CSV_UNITS = {
    "m": "m",
    "cm": "cm",
    "s": "s",
    "deg": "deg",
    "rad": "rad",
    "m_s": "m/s",
    "cm_s": "cm/s",
    "kn": "kn",
}


@dataclass(frozen=True)
class _Quantity:
    units: dict  # accepted units spelling -> factor to the unit below
    unit: str  # unit of the stored values (SI, degrees for angles)
    lo: float
    hi: float
    lo_open: bool  # lo excluded (periods)
    standard_names: tuple  # CF standard names, checked against CF Standard Name Table v93
    names: tuple  # documented variable names (NetCDF) = CSV column stems


#: the quantities; allowed ranges are physical (Hs, speeds >= 0, periods > 0) with upper bounds
#: well beyond the ocean's (largest measured Hs ~ 19 m, tidal currents ~ 5 m/s, tides ~ 8 m) that
#: catch a wrong unit
QUANTITIES = {
    "hs": _Quantity(_LENGTH, "m", 0.0, 30.0, False, ("sea_surface_wave_significant_height",), ("hs",)),
    "tp": _Quantity(
        _TIME,
        "s",
        0.0,
        40.0,
        True,
        ("sea_surface_wave_period_at_variance_spectral_density_maximum",),
        ("tp",),
    ),
    "tm01": _Quantity(
        _TIME,
        "s",
        0.0,
        40.0,
        True,
        ("sea_surface_wave_mean_period_from_variance_spectral_density_first_frequency_moment",),
        ("tm01",),
    ),
    "tm02": _Quantity(
        _TIME,
        "s",
        0.0,
        40.0,
        True,
        ("sea_surface_wave_mean_period_from_variance_spectral_density_second_frequency_moment",),
        ("tm02",),
    ),
    "tm_10": _Quantity(
        _TIME,
        "s",
        0.0,
        40.0,
        True,
        ("sea_surface_wave_mean_period_from_variance_spectral_density_inverse_frequency_moment",),
        ("tm_10",),
    ),
    "wave_dir": _Quantity(
        _ANGLE,
        "deg",
        -360.0,
        360.0,
        False,
        (
            "sea_surface_wave_from_direction",
            "sea_surface_wave_from_direction_at_variance_spectral_density_maximum",
        ),
        ("wave_dir",),
    ),
    "current_speed": _Quantity(_SPEED, "m/s", 0.0, 10.0, False, ("sea_water_speed",), ("current_speed",)),
    "current_dir": _Quantity(
        _ANGLE, "deg", -360.0, 360.0, False, ("direction_of_sea_water_velocity",), ("current_dir",)
    ),
    "current_u": _Quantity(
        _SPEED, "m/s", -10.0, 10.0, False, ("eastward_sea_water_velocity",), ("current_u",)
    ),
    "current_v": _Quantity(
        _SPEED, "m/s", -10.0, 10.0, False, ("northward_sea_water_velocity",), ("current_v",)
    ),
    "water_level": _Quantity(
        _LENGTH,
        "m",
        -20.0,
        20.0,
        False,
        ("sea_surface_height_above_mean_sea_level", "sea_surface_height"),
        ("water_level",),
    ),
}
_PERIODS = ("tp", "tm01", "tm02", "tm_10")


def _ro(a) -> np.ndarray:
    a = np.array(a, dtype=np.float64)
    a.flags.writeable = False
    return a


@dataclass(frozen=True, eq=False)
class Forcing:
    """One validated forcing series (read-only float64 arrays of equal length >= 2).

    ``time`` [s] from the first record (``time[0] == 0``), strictly increasing; record i holds over
    [time[i], time[i+1]). ``start``: UTC datetime64 of the first record, or None when the source
    gave relative seconds. ``hs`` [m], ``tp`` [s] (peak period; mean periods converted with
    :data:`PERIOD_RATIOS`), ``wave_from`` [deg] (waves coming from, clockwise from north),
    ``current_speed`` [m/s], ``current_to`` [deg] (flowing towards, clockwise from north, as CF
    ``direction_of_sea_water_velocity``), ``water_level`` [m] above the datum of the scenario's
    water depth. ``source`` names where it came from (for messages and output attributes)."""

    time: np.ndarray
    hs: np.ndarray
    tp: np.ndarray
    wave_from: np.ndarray
    current_speed: np.ndarray
    current_to: np.ndarray
    water_level: np.ndarray
    start: np.datetime64 | None = None
    source: str = "forcing"

    def __post_init__(self):
        for name in ("time", "hs", "tp", "wave_from", "current_speed", "current_to", "water_level"):
            object.__setattr__(self, name, _ro(getattr(self, name)))
        if isinstance(self.start, str):
            object.__setattr__(self, "start", _parse_iso(self.start))
        elif self.start is not None:
            object.__setattr__(self, "start", np.datetime64(self.start, "ns"))
        _validate(self)

    def __len__(self) -> int:
        return self.time.shape[0]

    @property
    def duration_s(self) -> float:
        return float(self.time[-1])

    def iso(self, i: int) -> str:
        """The time of record i as text: ISO 8601 UTC, or ``t = ... s`` without a start."""
        return _iso(self.start, self.time[i])

    def kernel_arrays(self, depth: float, d50: float | None = None):
        """(t, hs, tp, wave_dir, current_speed, current_dir, h): the flat float64 arrays of
        :func:`mineburial.kernels.mine.scour.scour_stage`. Both directions are returned in radians as
        directions *towards* which waves and current travel (the waves' "from" + 180 deg); the
        kernel uses only their difference. h = depth + water level [m] must stay positive and,
        with the grain size ``d50`` [m] given, at least the stage's ``depth_floor(d50)`` (else
        the stage would return invalid_forcing for every drop)."""
        if not (math.isfinite(depth) and depth > 0.0):
            raise ScenarioError(f"{self.source}: water depth = {depth!r} m; allowed: > 0 m")
        h = depth + self.water_level
        floor = 0.0 if d50 is None else float(depth_floor(d50))
        ok = (h > 0.0) & (h >= floor)
        if not np.all(ok):
            i = int(np.argmax(~ok))
            if h[i] > 0.0:
                why, allowed = f"leaves less than depth_floor(d50) = {floor:g} m", f">= {floor - depth:g}"
            else:
                why, allowed = "dries the bed", f"> {-depth:g}"
            raise ScenarioError(
                f"{self.source}: variable 'water_level' = {self.water_level[i]:g} m at {self.iso(i)} "
                f"{why} (depth {depth:g} m); allowed: {allowed} m"
            )
        wave_to = np.radians(np.mod(self.wave_from + 180.0, 360.0))
        cur_to = np.radians(np.mod(self.current_to, 360.0))
        return (
            np.array(self.time),
            np.array(self.hs),
            np.array(self.tp),
            wave_to,
            np.array(self.current_speed),
            cur_to,
            h,
        )


def _iso(start, seconds: float) -> str:
    if start is None:
        return f"t = {seconds:g} s"
    when = start + np.timedelta64(int(round(seconds * 1e9)), "ns")
    return np.datetime_as_string(when, unit="s") + "Z"


def _range_text(q: _Quantity) -> str:
    return f"{'(' if q.lo_open else '['}{q.lo:g}, {q.hi:g}] {q.unit}"


# --- checks -------------------------------------------------------------------------------------------


def _check_values(where, label, key, values, iso_of, raw=None, raw_unit=None, cell=None):
    """ScenarioError for the first record (in time) whose value is NaN/inf or outside the range of
    quantity ``key``; ``values`` in stored units, (time, ...) shaped; ``iso_of(i)`` the time text,
    ``cell(index)`` the text naming a grid cell (gridded forcing)."""
    q = QUANTITIES["tp" if key in _PERIODS else key]
    v = np.asarray(values)
    ok = np.isfinite(v) & (v <= q.hi) & ((v > q.lo) if q.lo_open else (v >= q.lo))
    if ok.all():
        return
    idx = np.unravel_index(int(np.argmax(~ok)), v.shape)
    shown = v[idx] if raw is None else np.asarray(raw)[idx]
    unit = q.unit if raw is None else raw_unit
    what = "is missing (NaN)" if np.isnan(shown) else f"= {shown:g} {unit}"
    at = "" if cell is None else cell(idx[1:])
    raise ScenarioError(
        f"{where}: variable '{label}' {what} at {iso_of(idx[0])}{at}; allowed: {_range_text(q)}"
    )


def _check_times(where, label, seconds, start, gap_factor, max_gap_s):
    """Times (float seconds from an origin) must be >= 2, finite, strictly increasing, no gaps."""
    n = seconds.shape[0]
    if n == 0:
        raise ScenarioError(f"{where}: variable '{label}' is empty: no records; at least 2 are needed")
    if n == 1:
        raise ScenarioError(
            f"{where}: only one record, at {_iso(start, seconds[0])}; at least 2 are needed (time '{label}')"
        )
    bad = ~np.isfinite(seconds)
    if bad.any():
        i = int(np.argmax(bad))
        after = f"after {_iso(start, seconds[i - 1])}" if i > 0 else "at the first record"
        raise ScenarioError(f"{where}: variable '{label}' is missing (NaN/NaT) at record {i + 1}, {after}")
    step = np.diff(seconds)
    if not np.all(step > 0.0):
        i = int(np.argmax(~(step > 0.0)))
        a, b = _iso(start, seconds[i]), _iso(start, seconds[i + 1])
        if step[i] == 0.0:
            raise ScenarioError(
                f"{where}: variable '{label}' repeats {a} (records {i + 1} and {i + 2}); "
                "times must be strictly increasing"
            )
        raise ScenarioError(
            f"{where}: variable '{label}' goes back from {a} to {b} (records {i + 1} and {i + 2}); "
            "times must be strictly increasing"
        )
    median = float(np.median(step))
    limit = gap_factor * median if max_gap_s is None else min(gap_factor * median, max_gap_s)
    if np.any(step > limit):
        i = int(np.argmax(step > limit))
        rule = f"{gap_factor:g} x the median step of {median:g} s"
        if max_gap_s is not None:
            rule += f" or max_gap_s = {max_gap_s:g} s"
        raise ScenarioError(
            f"{where}: variable '{label}' has a gap of {step[i]:g} s from {_iso(start, seconds[i])} "
            f"to {_iso(start, seconds[i + 1])}; allowed: steps up to {rule}"
        )


def _validate(f: Forcing) -> None:
    n = f.time.shape[0]
    for name in ("hs", "tp", "wave_from", "current_speed", "current_to", "water_level"):
        if getattr(f, name).shape != (n,):
            raise ScenarioError(f"{f.source}: '{name}' has shape {getattr(f, name).shape}; expected ({n},)")
    _check_times(f.source, "time", f.time, f.start, math.inf, None)
    if f.time[0] != 0.0:
        raise ScenarioError(f"{f.source}: time must start at 0 s, got {f.time[0]:g} s")
    checks = (("hs", "hs"), ("tp", "tp"), ("wave_from", "wave_dir"), ("current_speed", "current_speed"))
    for name, key in checks + (("current_to", "current_dir"), ("water_level", "water_level")):
        _check_values(f.source, name, key, getattr(f, name), f.iso)


# --- files --------------------------------------------------------------------------------------------


def _regular_file(path: pathlib.Path, where: str, max_bytes: int) -> int:
    """Stat ``path`` (following links): it must be a non-empty regular file of at most
    ``max_bytes`` (a FIFO or device would block or never end). Returns its size."""
    try:
        st = os.stat(path)
    except OSError as exc:
        raise ScenarioError(f"{where}: cannot read the file ({exc.strerror})") from None
    if not stat.S_ISREG(st.st_mode):
        raise ScenarioError(f"{where}: not a regular file (a directory, FIFO or device); give a file")
    if st.st_size == 0:
        raise ScenarioError(f"{where}: the file is empty (0 bytes)")
    if st.st_size > max_bytes:
        raise ScenarioError(f"{where}: the file has {st.st_size} bytes; allowed: at most {max_bytes} bytes")
    return st.st_size


def _read_text(path: pathlib.Path, where: str, max_bytes: int) -> str:
    _regular_file(path, where, max_bytes)
    try:  # O_NONBLOCK: a FIFO swapped in after the stat must not block the open
        fd = os.open(path, os.O_RDONLY | getattr(os, "O_NONBLOCK", 0))
    except OSError as exc:
        raise ScenarioError(f"{where}: cannot read the file ({exc.strerror})") from None
    with os.fdopen(fd, "rb") as fh:
        if not stat.S_ISREG(os.fstat(fd).st_mode):
            raise ScenarioError(f"{where}: not a regular file (a directory, FIFO or device); give a file")
        data = read_sized(fh, max_bytes)
    if len(data) > max_bytes:
        raise ScenarioError(
            f"{where}: the file has more than {max_bytes} bytes; allowed: at most {max_bytes}"
        )
    try:
        return data.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        raise ScenarioError(f"{where}: not UTF-8 text (byte {exc.start}); expected a CSV file") from None


def _factor(where, label, key, units):
    q = QUANTITIES[key]
    if units is None:
        raise ScenarioError(
            f"{where}: variable '{label}' has no units attribute; accepted: {', '.join(q.units)}"
        )
    spelled = " ".join(str(units).split()).lower()
    if spelled not in q.units:
        raise ScenarioError(
            f"{where}: variable '{label}' has units '{units}'; accepted: {', '.join(q.units)}"
        )
    return q.units[spelled]


def _assemble(where, columns, iso_of, cell=None):
    """SI arrays {hs, tp, wave_from, current_speed, current_to, water_level} from ``columns``:
    key -> (label, raw values (time, ...), units). Checks presence, units and ranges."""
    si = {}
    for key, (label, raw, units) in columns.items():
        values = np.asarray(raw, dtype=np.float64) * _factor(where, label, key, units)
        _check_values(where, label, key, values, iso_of, raw=raw, raw_unit=units, cell=cell)
        si[key] = values
    period = next((k for k in _PERIODS if k in si), None)
    missing = []
    if "hs" not in si:
        missing.append("significant wave height (hs, sea_surface_wave_significant_height)")
    if period is None:
        missing.append("a wave period (tp, tm01, tm02 or tm_10, or their CF standard names)")
    if "wave_dir" not in si:
        missing.append("wave direction (wave_dir, sea_surface_wave_from_direction)")
    has_uv = "current_u" in si and "current_v" in si
    if not ("current_speed" in si and "current_dir" in si) and not has_uv:
        missing.append("current (current_speed and current_dir, or current_u and current_v)")
    if missing:
        raise ScenarioError(f"{where}: missing variable(s): {'; '.join(missing)}")
    if "current_speed" in si and "current_dir" in si:
        speed, to = si["current_speed"], si["current_dir"]
    else:  # eastward u, northward v -> speed and direction towards, clockwise from north
        speed = np.hypot(si["current_u"], si["current_v"])
        to = np.degrees(np.arctan2(si["current_u"], si["current_v"]))
    level = si.get("water_level", np.zeros_like(si["hs"]))
    return {
        "hs": si["hs"],
        "tp": si[period] / PERIOD_RATIOS[period],
        "wave_from": si["wave_dir"],
        "current_speed": speed,
        "current_to": to,
        "water_level": level,
    }


# --- CSV ----------------------------------------------------------------------------------------------


def _csv_columns(where, header):
    """{key: (column index, column name, units)} from header names ``<stem>_<unit suffix>``
    (no stem is a prefix of another's column); columns of no known stem are ignored."""
    found = {}
    for j, name in enumerate(header):
        key = next((k for k, q in QUANTITIES.items() if name.startswith(q.names[0] + "_")), None)
        if key is None:
            continue
        q = QUANTITIES[key]
        units = _CSV_UNITS.get(name[len(q.names[0]) + 1 :])
        if units not in q.units:
            ok = [f"{q.names[0]}_{s}" for s, u in _CSV_UNITS.items() if u in q.units]
            raise ScenarioError(f"{where}: column '{name}' has an unknown unit; accepted: {', '.join(ok)}")
        if key in found:
            raise ScenarioError(f"{where}: columns '{found[key][1]}' and '{name}' give the same quantity")
        found[key] = (j, name, units)
    return found


class TimeOutOfRange(ValueError):
    """An ISO 8601 time outside what datetime64[ns] holds (its message says so)."""


#: the first and last whole seconds datetime64[ns] holds (1677-09-21T00:12:44 to 2262-04-11T23:47:16)
_FIRST_NS = _dt.datetime(1677, 9, 21, 0, 12, 44)
_LAST_NS = _dt.datetime(2262, 4, 11, 23, 47, 16)


def _parse_iso(text) -> np.datetime64:
    """ISO 8601 text (or a datetime, as TOML gives an unquoted one) -> UTC datetime64[ns]
    (no zone: UTC). A trailing 'Z' is read as +00:00 (Python 3.10's fromisoformat refuses it)."""
    if isinstance(text, _dt.datetime):
        when = text
    elif isinstance(text, str):
        t = text.strip()
        when = _dt.datetime.fromisoformat(t[:-1] + "+00:00" if t[-1:] in "Zz" and t else t)
    else:
        raise ValueError(f"{text!r} is not an ISO 8601 time")
    if when.tzinfo is not None:
        when = when.astimezone(_dt.timezone.utc).replace(tzinfo=None)
    if not (_FIRST_NS <= when <= _LAST_NS):  # datetime64[ns] would wrap silently (issue 35)
        raise TimeOutOfRange(
            f"{when.isoformat()}Z is outside the times that can be held, {_FIRST_NS.isoformat()}Z to "
            f"{_LAST_NS.isoformat()}Z (nanoseconds from 1970 in 64 bits)"
        )
    return np.datetime64(when, "ns")


def _times_from_datetimes(stamps):
    """(seconds from the first valid stamp, start) from datetime64[ns] (NaT -> NaN)."""
    stamps = np.asarray(stamps, dtype="datetime64[ns]")
    valid = ~np.isnat(stamps)
    if not valid.any():
        return np.full(stamps.shape, np.nan), None
    origin = stamps[valid][0]
    seconds = (stamps - origin).astype("timedelta64[ns]").astype(np.float64) / 1e9
    return np.where(valid, seconds, np.nan), origin


def load_csv(path, *, gap_factor=GAP_FACTOR, max_gap_s=None, max_bytes=MAX_CSV_BYTES) -> Forcing:
    """Read a forcing series from CSV: a header row, one record per row; ``#`` lines are comments.

    Columns: ``time`` (ISO 8601; no zone = UTC) or ``time_s`` (seconds from any origin), and
    ``<quantity>_<unit>`` with quantity hs, tp (or tm01, tm02, tm_10), wave_dir, current_speed,
    current_dir (or current_u, current_v), optional water_level, and unit m or cm (lengths), s
    (periods), deg or rad (directions), m_s, cm_s or kn (speeds): e.g.
    ``time,hs_m,tp_s,wave_dir_deg,current_speed_m_s,current_dir_deg``."""
    path = pathlib.Path(path)
    where = f"forcing file '{path}'"
    try:  # one value per header column on every row (inputs.numbered_csv), before any drop runs
        rows = [r for _, r in numbered_csv(_read_text(path, where, max_bytes), as_wide_as_header=True)]
    except csv.Error as exc:
        raise ScenarioError(f"{where}: not a CSV table of the forcing ({exc})") from None
    if not rows:
        raise ScenarioError(f"{where}: no header row; expected e.g. time,hs_m,tp_s,wave_dir_deg,...")
    header = [h.strip().lower() for h in rows[0]]
    tcol = "time" if "time" in header else "time_s" if "time_s" in header else None
    if tcol is None:
        raise ScenarioError(f"{where}: missing column 'time' (ISO 8601) or 'time_s' (seconds)")
    it = header.index(tcol)
    stamps, raw_s = [], []
    for k, row in enumerate(rows[1:], start=1):
        try:
            if tcol == "time":
                stamps.append(_parse_iso(row[it]))
            else:
                raw_s.append(float(row[it]))
        except TimeOutOfRange as exc:
            raise ScenarioError(f"{where}: data row {k}, column 'time': {exc}") from None
        except (IndexError, ValueError):
            raise ScenarioError(
                f"{where}: data row {k}, column '{tcol}': not "
                + (
                    "an ISO 8601 time (e.g. 2003-01-15T06:00:00Z)"
                    if tcol == "time"
                    else "a number of seconds"
                )
            ) from None
    if tcol == "time":
        seconds, start = _times_from_datetimes(stamps)
    else:
        raw_s = np.array(raw_s, dtype=np.float64)
        seconds, start = (raw_s - raw_s[0] if raw_s.size else raw_s), None
    _check_times(where, tcol, seconds, start, gap_factor, max_gap_s)
    columns = {}
    for key, (j, name, units) in _csv_columns(where, header).items():
        values = np.empty(len(rows) - 1)
        for k, row in enumerate(rows[1:]):
            try:
                values[k] = float(row[j])
            except (IndexError, ValueError):
                raise ScenarioError(
                    f"{where}: column '{name}' at {_iso(start, seconds[k])} (data row {k + 1}): not a number"
                ) from None
        columns[key] = (name, values, units)
    arrays = _assemble(where, columns, lambda i: _iso(start, seconds[i]))
    return Forcing(time=seconds, start=start, source=where, **arrays)


# --- NetCDF -------------------------------------------------------------------------------------------

_CF_CALENDARS = ("standard", "gregorian", "proleptic_gregorian")


#: float64 copies of each value a NetCDF forcing's reading holds at its peak (the file's values,
#: the float64 conversion, the checked and converted series, the kernel's arrays), with margin
READ_COPIES = 8


def _open_netcdf(path: pathlib.Path, where: str, max_bytes: int) -> xr.Dataset:
    _regular_file(path, where, max_bytes)
    try:  # times decoded below, after their units are checked
        ds = xr.open_dataset(path, decode_times=False, decode_timedelta=False)
    except (OSError, ValueError, RuntimeError, TypeError) as exc:
        first = str(exc).splitlines()[0] if str(exc) else ""
        raise ScenarioError(f"{where}: cannot open as NetCDF ({type(exc).__name__}: {first[:120]})") from None
    # the values are read lazily: their count, against the memory, before any is read (issue 35:
    # 10^7 to 5 10^7 records took 2.9 GB, then a MemoryError traceback); the file's size limit
    # does not bound it, compressed values decompress to more
    values = sum(int(v.size) for v in ds.variables.values())
    refusal = resources.memory_refusal(
        8.0 * READ_COPIES * values,
        f"{where}: reading its {values:,} values ({dict(ds.sizes)})",
        "give a shorter or coarser series",
    )
    if refusal:
        ds.close()
        raise ScenarioError(refusal)
    return ds


def _numbers(var, name, where) -> np.ndarray:
    """The values of a NetCDF variable as float64, or one line when it holds text, times or
    other things than numbers (was: a ValueError traceback, issue 35)."""
    kind = var.dtype.kind
    if kind not in "iuf":
        what = {"U": "text", "S": "text (bytes)", "O": "text or objects", "b": "true/false values"}
        raise ScenarioError(
            f"{where}: variable '{name}' holds {what.get(kind, f'values of type {var.dtype}')}, not numbers"
        )
    return np.asarray(var.values, dtype=np.float64)


def _netcdf_times(ds, where):
    """(name, seconds from the first record, start) of the CF time coordinate."""
    name = "time" if "time" in ds.variables else None
    name = name or next((v for v in ds.variables if ds[v].attrs.get("standard_name") == "time"), None)
    if name is None:
        raise ScenarioError(f"{where}: missing variable 'time' (a CF time coordinate, e.g. hours since ...)")
    var = ds[name]
    if var.ndim != 1:
        raise ScenarioError(f"{where}: variable '{name}' has dimensions {var.dims}; expected one")
    units = var.attrs.get("units")
    calendar = str(var.attrs.get("calendar", "standard")).lower()
    if units is None or " since " not in str(units):
        raise ScenarioError(
            f"{where}: variable '{name}' has units {units!r}; expected CF time units '<unit> since <date>'"
        )
    if calendar not in _CF_CALENDARS:
        raise ScenarioError(
            f"{where}: variable '{name}' has calendar '{calendar}'; accepted: {', '.join(_CF_CALENDARS)}"
        )
    raw = _numbers(var, name, where)
    try:
        finite = np.where(np.isfinite(raw), raw, 0.0)
        stamps = xr.coding.times.decode_cf_datetime(finite, str(units), calendar)
    except (ValueError, OverflowError, TypeError):
        raise ScenarioError(
            f"{where}: variable '{name}' has units '{units}' that are not CF time units"
        ) from None
    stamps = np.where(np.isfinite(raw), np.asarray(stamps, dtype="datetime64[ns]"), np.datetime64("NaT"))
    seconds, start = _times_from_datetimes(stamps)
    return name, seconds, start


def _netcdf_columns(ds, where, tdim, ndim, space_dims=None):
    """{key: (name, raw values (time, ...), units)} of the quantities present, found by CF
    standard_name, else by the documented name; each transposed to (time, *space_dims)."""
    columns = {}
    for key, q in QUANTITIES.items():
        names = [v for v in ds.data_vars if ds[v].attrs.get("standard_name") in q.standard_names]
        names = names or [v for v in q.names if v in ds.variables]
        if len(names) > 1:
            raise ScenarioError(
                f"{where}: variables {', '.join(map(repr, names))} give the same quantity {key}"
            )
        if not names:
            continue
        var = ds[names[0]]
        var = var.squeeze([d for d in var.dims if d != tdim and var.sizes[d] == 1])
        if tdim not in var.dims or var.ndim != ndim:
            expected = "(time)" if ndim == 1 else "(time, y, x)"
            hint = ""
            if ndim == 1 and var.ndim == 3:  # a gridded wave product given as one series
                hint = " (a gridded wave product: give its point as scour.forcing_location = [lat, lon])"
            raise ScenarioError(
                f"{where}: variable '{names[0]}' has dimensions {var.dims}; expected {expected}{hint}"
            )
        if space_dims is None:
            space_dims = tuple(d for d in var.dims if d != tdim)
        if set(var.dims) != {tdim, *space_dims}:
            raise ScenarioError(
                f"{where}: variable '{names[0]}' has dimensions {var.dims}; "
                f"expected ({tdim}, {', '.join(space_dims)})"
            )
        values = _numbers(var.transpose(tdim, *space_dims), names[0], where)
        columns[key] = (names[0], values, var.attrs.get("units"))
    return columns, space_dims


def load_netcdf(path, *, gap_factor=GAP_FACTOR, max_gap_s=None, max_bytes=MAX_NETCDF_BYTES) -> Forcing:
    """Read a forcing series from a CF NetCDF file: a ``time`` coordinate with CF units
    (``<seconds|minutes|hours|days> since <date>``, standard calendar) and 1-D variables (size-1
    extra dimensions are dropped) found by ``standard_name`` (:data:`QUANTITIES`) or by name
    (hs, tp, tm01, tm02, tm_10, wave_dir, current_speed, current_dir, current_u, current_v,
    water_level), each with a ``units`` attribute converted to m, s, deg, m/s."""
    path = pathlib.Path(path)
    where = f"forcing file '{path}'"
    with _open_netcdf(path, where, max_bytes) as ds:
        tname, seconds, start = _netcdf_times(ds, where)
        _check_times(where, tname, seconds, start, gap_factor, max_gap_s)
        columns, _ = _netcdf_columns(ds, where, ds[tname].dims[0], 1)
    arrays = _assemble(where, columns, lambda i: _iso(start, seconds[i]))
    return Forcing(time=seconds, start=start, source=where, **arrays)


@dataclass(frozen=True, eq=False)
class GriddedForcing:
    """Forcing on a (time, y, x) grid: the arrays of :class:`Forcing` with shape (nt, ny, nx),
    the horizontal coordinates ``y``, ``x`` (named ``dims``), and ``wet`` (ny, nx): False where
    the wave height is missing at every time (land). :meth:`cell` gives one cell's series."""

    time: np.ndarray
    start: np.datetime64 | None
    dims: tuple
    y: np.ndarray
    x: np.ndarray
    wet: np.ndarray
    fields: dict
    source: str

    @property
    def shape(self):
        return self.wet.shape

    def cell(self, j: int, i: int) -> Forcing:
        """The series of cell (y index j, x index i); ScenarioError for a dry cell."""
        if not self.wet[j, i]:
            raise ScenarioError(
                f"{self.source}: cell ({self.dims[0]}={j}, {self.dims[1]}={i}) is dry (no waves)"
            )
        return Forcing(
            time=self.time,
            start=self.start,
            source=f"{self.source} cell ({self.dims[0]}={j}, {self.dims[1]}={i})",
            **{k: v[:, j, i] for k, v in self.fields.items()},
        )


def load_gridded_netcdf(
    path, *, gap_factor=GAP_FACTOR, max_gap_s=None, max_bytes=MAX_NETCDF_BYTES, only=None
):
    """Read a gridded forcing (time, y, x) from CF NetCDF: the variables of :func:`load_netcdf`
    with two horizontal dimensions (any names, the same for all; coordinates optional). A cell
    whose wave height is missing at every time is dry (``wet`` False) and not checked; every
    other cell is checked as a series, the message naming the cell.

    ``only`` = (mask (ny, nx), its dimension names): only the cells where the mask is true (the
    cells a map computes) are checked and kept, the others taken as dry (was: a land cell whose
    forcing was partly NaN refused the whole map, issue 35). A mask of another shape is ignored
    (the caller refuses the grid)."""
    path = pathlib.Path(path)
    where = f"forcing file '{path}'"
    with _open_netcdf(path, where, max_bytes) as ds:
        tname, seconds, start = _netcdf_times(ds, where)
        _check_times(where, tname, seconds, start, gap_factor, max_gap_s)
        columns, dims = _netcdf_columns(ds, where, ds[tname].dims[0], 3)
        coords = [
            np.asarray(ds[d].values) if d in ds.variables else np.arange(ds.sizes[d]) for d in dims or ()
        ]
    if "hs" not in columns:
        raise ScenarioError(
            f"{where}: missing variable(s): significant wave height (hs, sea_surface_wave_significant_height)"
        )
    wet = ~np.all(np.isnan(columns["hs"][1]), axis=0)
    if not wet.any():
        raise ScenarioError(
            f"{where}: variable '{columns['hs'][0]}' is missing (NaN) in every cell at every time"
        )
    if only is not None:
        mask, mask_dims = np.asarray(only[0], dtype=bool), tuple(only[1])
        if dims is not None and tuple(dims) == mask_dims[::-1] and mask_dims[0] != mask_dims[1]:
            mask = mask.T
        if mask.shape == wet.shape:
            wet = wet & mask
    jj, ii = np.nonzero(wet)
    wet_columns = {k: (name, v[:, wet], units) for k, (name, v, units) in columns.items()}

    def cell(idx):
        return f" in cell ({dims[0]}={jj[idx[0]]}, {dims[1]}={ii[idx[0]]})"

    arrays = _assemble(where, wet_columns, lambda i: _iso(start, seconds[i]), cell=cell)
    fields = {}
    for k, v in arrays.items():
        full = np.full((seconds.shape[0],) + wet.shape, np.nan)
        full[:, wet] = v
        full.flags.writeable = False
        fields[k] = full
    return GriddedForcing(
        time=_ro(seconds),
        start=start,
        dims=dims,
        y=coords[0],
        x=coords[1],
        wet=wet,
        fields=fields,
        source=where,
    )


#: CF attributes of the variables :func:`write_gridded_netcdf` writes: (name, Forcing field, units,
#: standard name)
_GRID_VARIABLES = (
    ("hs", "hs", "m", "sea_surface_wave_significant_height"),
    ("tp", "tp", "s", "sea_surface_wave_period_at_variance_spectral_density_maximum"),
    ("wave_dir", "wave_from", "degree", "sea_surface_wave_from_direction"),
    ("current_speed", "current_speed", "m s-1", "sea_water_speed"),
    ("current_dir", "current_to", "degree", "direction_of_sea_water_velocity"),
    ("water_level", "water_level", "m", "sea_surface_height_above_mean_sea_level"),
)


def write_gridded_netcdf(cells, y, x, path) -> pathlib.Path:
    """Write a gridded forcing (time, y, x) as the CF NetCDF :func:`load_gridded_netcdf` reads:
    ``cells[j][i]`` the :class:`Forcing` of cell (j, i), all on one time axis, or None for a dry
    cell (NaN at every time); ``y``, ``x``: the horizontal coordinates as
    :class:`xarray.DataArray` (their names and attributes are kept, e.g. an environment grid's)."""
    y, x = (c if isinstance(c, xr.DataArray) else xr.DataArray(np.asarray(c), dims=(n,), name=n)
            for c, n in ((y, "y"), (x, "x")))  # fmt: skip
    first = next(f for row in cells for f in row if f is not None)
    shape = (len(first), y.size, x.size)
    data = {}
    for name, field, units, sn in _GRID_VARIABLES:
        values = np.full(shape, np.nan)
        for (j, i), f in np.ndenumerate(np.array(cells, dtype=object).reshape(shape[1:])):
            if f is not None:
                if f.time.shape != first.time.shape or not np.array_equal(f.time, first.time):
                    raise ScenarioError(
                        f"gridded forcing: cell ({j}, {i}) is not on the time axis of the others"
                    )
                values[:, j, i] = getattr(f, field)
        data[name] = xr.DataArray(
            values, dims=("time", y.dims[0], x.dims[0]), attrs={"units": units, "standard_name": sn}
        )
    start = first.start if first.start is not None else np.datetime64("1970-01-01T00:00:00", "ns")
    iso = str(np.datetime_as_string(start, unit="s"))
    time = xr.DataArray(
        np.array(first.time), dims=("time",), attrs={"units": f"seconds since {iso}", "standard_name": "time"}
    )
    ds = xr.Dataset(data, coords={"time": time, y.dims[0]: y, x.dims[0]: x})
    path = pathlib.Path(path)
    with atomic_path(path) as tmp:  # the one writer (docs/design.md, "Outputs")
        ds.to_netcdf(tmp, encoding={"time": {"dtype": "float64"}})
    return path


def load_forcing(path, base_dir=None, **kwargs) -> Forcing:
    """A forcing series by file type (``.csv``; ``.nc``, ``.nc4``, ``.cdf``), a relative ``path``
    resolved against ``base_dir`` (the scenario file's folder); keywords as :func:`load_csv`."""
    p = pathlib.Path(path)
    if not p.is_absolute() and base_dir is not None:
        p = pathlib.Path(base_dir) / p
    suffix = p.suffix.lower()
    if suffix == ".csv":
        return load_csv(p, **kwargs)
    if suffix in (".nc", ".nc4", ".cdf", ".netcdf"):
        return load_netcdf(p, **kwargs)
    raise ScenarioError(f"forcing file '{path}': unknown file type '{p.suffix}'; expected .csv or .nc")


def write_csv(forcing: Forcing, path, comment: str = "") -> pathlib.Path:
    """Write ``forcing`` as the CSV that :func:`load_csv` reads (``time`` ISO 8601 UTC, or ``time_s``
    without a start; 9 significant digits), atomically; ``comment`` lines are prefixed by ``#``."""
    lines = [f"# {c}" for c in comment.splitlines()]
    lines.append(
        ("time" if forcing.start is not None else "time_s")
        + ",hs_m,tp_s,wave_dir_deg,current_speed_m_s,current_dir_deg,water_level_m"
    )
    for i in range(len(forcing)):
        t = forcing.iso(i) if forcing.start is not None else f"{forcing.time[i]:.9g}"
        values = (forcing.hs, forcing.tp, forcing.wave_from, forcing.current_speed, forcing.current_to)
        row = [t] + [f"{v[i]:.9g}" for v in values + (forcing.water_level,)]
        lines.append(",".join(row))
    return atomic_write_text(path, "\n".join(lines) + "\n")


# --- a parametrised storm -----------------------------------------------------------------------------

STORM_RAMPS = ("cos2", "triangular")


def storm_shape(tau, ramp: str = "cos2"):
    """Storm shape in tau = (t - t_peak) / (duration / 2): 1 at the peak, 0 for |tau| >= 1.
    ``triangular``: 1 - |tau|, Boccotti's equivalent triangular storm (Boccotti 2000, *Wave
    Mechanics for Ocean Engineering*, Elsevier, ch. 3); ``cos2``: cos^2(pi tau / 2), the same
    peak, duration and area under the curve (duration / 2) with a smooth build-up and decay
    (an assumption for examples, not a fit)."""
    tau = np.abs(np.asarray(tau, dtype=np.float64))
    if ramp == "triangular":
        return np.clip(1.0 - tau, 0.0, 1.0)
    if ramp == "cos2":
        return np.where(tau < 1.0, np.cos(0.5 * np.pi * np.minimum(tau, 1.0)) ** 2, 0.0)
    raise ScenarioError(f"storm ramp '{ramp}' is unknown; allowed: {', '.join(STORM_RAMPS)}")


#: the most records a parametrised storm may have (ten years hourly)
MAX_STORM_STEPS = 87_661


def storm_series(
    peak_hs,
    peak_tp,
    duration_h,
    *,
    ramp="cos2",
    current=0.0,
    start="2000-01-01T00:00:00Z",
    step_h=1.0,
    peak_h=None,
    total_h=None,
    background_hs=0.3,
    background_current=0.0,
    wave_from=270.0,
    current_to=0.0,
    surge=0.0,
) -> Forcing:
    """A parametrised storm for examples: over ``total_h`` hours (default 2 x duration) from
    ``start`` (ISO 8601 UTC) every ``step_h`` hours, with s = :func:`storm_shape` centred on
    ``peak_h`` (default the middle) and lasting ``duration_h``:

    * Hs = background_hs + (peak_hs - background_hs) s,
    * Tp = peak_tp sqrt(Hs / peak_hs): constant wave steepness Hs / Tp^2, as of a fully developed
      sea (Pierson & Moskowitz 1964: Hs ~ U^2, Tp ~ U); an assumption for examples,
    * current speed = background_current + (current - background_current) s,
    * water level = surge s; constant directions (waves from ``wave_from``, current towards
      ``current_to``, degrees clockwise from north)."""
    where = "storm"
    for name, value, lo in (
        ("peak_hs", peak_hs, 0.0),
        ("peak_tp", peak_tp, 0.0),
        ("duration_h", duration_h, 0.0),
    ):
        if not (math.isfinite(value) and value > lo):
            raise ScenarioError(f"{where}: {name} = {value!r}; allowed: > {lo:g}")
    if not (math.isfinite(step_h) and 0.0 < step_h <= duration_h):
        raise ScenarioError(f"{where}: step_h = {step_h!r} h; allowed: (0, duration_h = {duration_h:g}] h")
    if not (0.0 <= background_hs <= peak_hs):
        raise ScenarioError(
            f"{where}: background_hs = {background_hs!r} m; allowed: [0, peak_hs = {peak_hs:g}] m"
        )
    total_h = 2.0 * duration_h if total_h is None else total_h
    peak_h = 0.5 * total_h if peak_h is None else peak_h
    n = int(round(total_h / step_h)) + 1
    if not (math.isfinite(total_h) and n >= 2 and abs((n - 1) * step_h - total_h) <= 1e-9 * total_h):
        raise ScenarioError(
            f"{where}: total_h = {total_h!r} h must be a whole number of steps of {step_h:g} h"
        )
    if n > MAX_STORM_STEPS:
        raise ScenarioError(
            f"{where}: total_h = {total_h!r} h at step_h = {step_h:g} h gives {n} steps; "
            f"at most {MAX_STORM_STEPS} are accepted"
        )
    try:
        start_time = _parse_iso(start)
    except TimeOutOfRange as exc:
        raise ScenarioError(f"{where}: start = {start}: {exc}") from None
    except ValueError:
        shown = start.isoformat() if isinstance(start, (_dt.date, _dt.time)) else repr(start)
        raise ScenarioError(
            f"{where}: start = {shown} is not an ISO 8601 time (e.g. 2003-01-15T00:00:00Z)"
        ) from None
    hours = np.arange(n) * step_h
    s = storm_shape((hours - peak_h) / (0.5 * duration_h), ramp)
    hs = background_hs + (peak_hs - background_hs) * s
    return Forcing(
        time=hours * 3600.0,
        hs=hs,
        tp=peak_tp * np.sqrt(hs / peak_hs),
        wave_from=np.full(n, float(wave_from)),
        current_speed=background_current + (current - background_current) * s,
        current_to=np.full(n, float(current_to)),
        water_level=surge * s,
        start=start_time,
        source=f"storm (peak Hs {peak_hs:g} m, Tp {peak_tp:g} s, {duration_h:g} h, {ramp})",
    )


# --- forcing uncertainty (pure functions for the sampled inputs; not wired in yet) ---------------------


def scale_hs(forcing: Forcing, factor: float) -> Forcing:
    """The forcing with every wave height multiplied by ``factor`` (> 0): a sampled scale factor
    on Hs. The period is left as it is (the spectral orbital velocity is proportional to Hs)."""
    if not (math.isfinite(factor) and factor > 0.0):
        raise ScenarioError(f"{forcing.source}: Hs scale factor = {factor!r}; allowed: > 0")
    return replace(forcing, hs=forcing.hs * factor, source=f"{forcing.source} (Hs x {factor:g})")


def window(forcing: Forcing, offset_s: float, length_s: float) -> Forcing:
    """The part of ``forcing`` from ``offset_s`` to ``offset_s + length_s`` [s after its first
    record], re-based to start at 0 (``start`` moved by the offset): a start date drawn from a
    long series. Record i holds over [t_i, t_i+1), so the window's first record is the one in
    effect at the offset, its last the one in effect at the end; the series the kernel sees
    is the original's, piece for piece. ScenarioError if the window leaves the series."""
    end = offset_s + length_s
    if not (math.isfinite(offset_s) and offset_s >= 0.0 and math.isfinite(length_s) and length_s > 0.0):
        raise ScenarioError(
            f"{forcing.source}: window offset = {offset_s!r} s, length = {length_s!r} s; "
            "allowed: offset >= 0, length > 0"
        )
    if end > forcing.duration_s:
        raise ScenarioError(
            f"{forcing.source}: window from {_iso(forcing.start, offset_s)} "
            f"of {length_s:g} s ends after the forcing's last record at {forcing.iso(len(forcing) - 1)}; "
            f"allowed: offset + length <= {forcing.duration_s:g} s"
        )
    t = forcing.time
    i0 = int(np.searchsorted(t, offset_s, side="right")) - 1
    i1 = int(np.searchsorted(t, end, side="left"))
    j_end = int(np.searchsorted(t, end, side="right")) - 1
    idx = np.r_[np.arange(i0, i1), j_end]
    time = np.r_[offset_s, t[i0 + 1 : i1], end] - offset_s
    start = (
        None if forcing.start is None else forcing.start + np.timedelta64(int(round(offset_s * 1e9)), "ns")
    )
    return Forcing(
        time=time,
        hs=forcing.hs[idx],
        tp=forcing.tp[idx],
        wave_from=forcing.wave_from[idx],
        current_speed=forcing.current_speed[idx],
        current_to=forcing.current_to[idx],
        water_level=forcing.water_level[idx],
        start=start,
        source=f"{forcing.source} [window from {offset_s:g} s, {length_s:g} s]",
    )
