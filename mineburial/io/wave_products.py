"""Wave-model products as scour forcing (issue 33, item 6): ERA5, Copernicus Marine (CMEMS) and
WAVEWATCH III output on their own latitude/longitude grid, read by CF ``standard_name`` first and by
each product's documented variable names after, interpolated onto points (a map's environment cells,
or ``scour.forcing_location``) and onto the stage's time steps.

Methods (docs/scour.md, "Wave-model products"):

* **space**: bilinear in (longitude, latitude) between the four product grid nodes around the
  point, longitudes compared modulo 360 (a product on 0..360 serves a point at -10 and the reverse;
  a global grid wraps between its last and first column). Where any of the four nodes is land or
  missing at some time (a NaN, as a ``_FillValue`` decodes), the point takes the series of the
  nearest of those four that has a value at every time (distance on the sphere's tangent plane:
  dlat, dlon cos(lat)); with none of the four, it is refused, the cell named. A point outside the
  product's grid is refused (no extrapolation).
* **time**: linear between records onto the stage's steps: the product's own times when none of its
  steps exceeds ``step_s`` (default 3600 s), else every ``step_s`` from the first record, and the
  last record. The stage then holds each step's value until the next (as every forcing).
* directions are interpolated as unit vectors (sin, cos), in space and time, never as angles (350
  and 10 degrees average to 0, not 180); periods are interpolated as periods (a peak frequency
  ``fp`` becomes Tp = 1/fp at the nodes first); mean periods become the peak period with
  :data:`mineburial.io.forcing.PERIOD_RATIOS` as in every forcing.

Wave products hold no current: the series get current 0 m/s and water level 0 m unless the file
has them (CF ``eastward_/northward_sea_water_velocity``, ``sea_water_speed`` with
``direction_of_sea_water_velocity``, ``sea_surface_height_above_mean_sea_level``; WW3 ``ucur``,
``vcur``, ``wlv``), which are interpolated the same way.
"""

from __future__ import annotations

import math
import pathlib

import numpy as np

from mineburial import resources
from mineburial._deferred import proj_before_eccodes
from mineburial._deferred import xarray as xr
from mineburial.errors import ScenarioError
from mineburial.io import forcing as fio

__all__ = [
    "PRODUCT_NAMES",
    "STEP_S",
    "bilinear_plan",
    "interpolate_time",
    "load_wave_point",
    "load_wave_points",
    "load_wave_grid",
    "is_lat_lon_grid",
]

#: the methods, as recorded in a map's attributes (``forcing_grid_interpolation``)
METHOD = (
    "bilinear in longitude/latitude from the product's grid (longitudes modulo 360; a node "
    "missing at some time: the nearest sea node of the four around the cell); linear in time to "
    "1 h steps where the product's are longer; directions as unit vectors"
)

#: file types a wave product may have (GRIB through cfgrib only)
GRIB_SUFFIXES = (".grib", ".grib2", ".grb", ".grb2")
SUFFIXES = (".nc", ".nc4", ".cdf", ".netcdf") + GRIB_SUFFIXES

#: the stage's time step for a product with longer steps [s]: records are interpolated linearly to it
STEP_S = 3600.0

#: documented variable names of each product, read after the CF standard names (in this order):
#: ERA5 (ECMWF parameter short names: swh 140229, pp1d 140231, mwp 140232 = Tm-1,0, mp1 140220,
#: mp2 140221, mwd 140230), Copernicus Marine global/regional wave products (VHM0, VTPK, VTM10,
#: VTM02, VMDR, VPED) and WAVEWATCH III ww3_ounf (hs, tp, fp, t01, t02, t0m1, dir, dp); in GRIB,
#: as cfgrib names them by ecCodes' short names: ERA5's as above, NCEP's WAVEWATCH III GRIB2 swh
#: (HTSGW, 10-0-3), perpw (PERPW, 10-0-11, "primary wave mean period", read as the peak period: NCEP's
#: products derive it from the spectral peak, as recalled, unverified) and dirpw (DIRPW, 10-0-10)
PRODUCT_NAMES = {  # then this project's own names (docs/scour.md, Formats)
    "hs": ("swh", "VHM0", "hs"),
    "tp": ("pp1d", "VTPK", "tp", "perpw"),
    "fp": ("fp",),
    "tm01": ("mp1", "t01", "tm01"),
    "tm02": ("mp2", "VTM02", "t02", "tm02"),
    "tm_10": ("mwp", "VTM10", "t0m1", "tm_10"),
    "wave_dir": ("mwd", "VMDR", "dir", "VPED", "dp", "wave_dir", "dirpw"),
}
#: standard names searched first, in this order (the first found wins). WAVEWATCH III labels its
#: total-sea mean periods sea_surface_wind_wave_..., which CF reserves for the wind-sea partition:
#: they are read by name (t01, t02, t0m1), not by those standard names; its 'sea_surface_wave_peak_period'
#: (tp) and 'sea_surface_wave_peak_direction' (dp) are not CF names but read as theirs
_STANDARD_NAMES = {
    "hs": fio.QUANTITIES["hs"].standard_names,
    "tp": fio.QUANTITIES["tp"].standard_names + ("sea_surface_wave_peak_period",),
    "fp": (),
    "tm01": fio.QUANTITIES["tm01"].standard_names,
    "tm02": fio.QUANTITIES["tm02"].standard_names,
    "tm_10": fio.QUANTITIES["tm_10"].standard_names,
    "wave_dir": fio.QUANTITIES["wave_dir"].standard_names + ("sea_surface_wave_peak_direction",),
}
_OPTIONAL = ("current_speed", "current_dir", "current_u", "current_v", "water_level")
_OPTIONAL_NAMES = {"current_u": ("ucur",), "current_v": ("vcur",), "water_level": ("wlv",)}
#: accepted units of a frequency -> factor to Hz
_FREQUENCY = {"s-1": 1.0, "hz": 1.0, "1/s": 1.0, "s^-1": 1.0}
#: the largest peak frequency accepted [Hz] (a period of 0.5 s), and the smallest (40 s)
_FP_RANGE = (1.0 / 40.0, 2.0)


def _units_text(units) -> str:
    return " ".join(str(units).split()).lower()


def _find(ds, where):
    """{key: variable name} of Hs, one period (tp, fp, tm01, tm02, tm_10 in this order), the wave
    direction, and the optional current and water level: CF standard names first, then the
    products' names; ScenarioError naming what is missing."""
    found = {}
    for key in ("hs", "tp", "fp", "tm01", "tm02", "tm_10", "wave_dir"):
        name = None
        for sn in _STANDARD_NAMES[key]:
            hits = [v for v in ds.data_vars if ds[v].attrs.get("standard_name") == sn]
            if len(hits) > 1:
                raise ScenarioError(
                    f"{where}: variables {', '.join(map(repr, hits))} have the same standard_name '{sn}'"
                )
            if hits:
                name = hits[0]
                break
        if name is None:
            name = next((v for v in PRODUCT_NAMES[key] if v in ds.data_vars), None)
        if name is not None and name not in found.values():
            found[key] = name
    period = next((k for k in ("tp", "fp", "tm01", "tm02", "tm_10") if k in found), None)
    missing = []
    if "hs" not in found:
        missing.append("significant wave height (sea_surface_wave_significant_height; swh, VHM0, hs)")
    if period is None:
        missing.append(
            "a wave period (sea_surface_wave_period_at_variance_spectral_density_maximum or a mean "
            "period's standard name; pp1d, mwp, mp1, mp2, VTPK, VTM10, VTM02, tp, fp, t01, t02, t0m1)"
        )
    if "wave_dir" not in found:
        missing.append("wave direction (sea_surface_wave_from_direction; mwd, VMDR, dir, VPED, dp)")
    if missing:
        raise ScenarioError(f"{where}: not a wave product this reader knows: missing {'; '.join(missing)}")
    out = {"hs": found["hs"], period: found[period], "wave_dir": found["wave_dir"]}
    for key in _OPTIONAL:
        q = fio.QUANTITIES[key]
        hits = [v for v in ds.data_vars if ds[v].attrs.get("standard_name") in q.standard_names]
        hits = hits or [v for v in q.names + _OPTIONAL_NAMES.get(key, ()) if v in ds.data_vars]
        if hits:
            out[key] = hits[0]
    has_uv = "current_u" in out and "current_v" in out
    has_sd = "current_speed" in out and "current_dir" in out
    for key in ("current_speed", "current_dir", "current_u", "current_v"):
        keep = (key in ("current_u", "current_v") and has_uv and not has_sd) or (
            key in ("current_speed", "current_dir") and has_sd
        )
        if not keep:
            out.pop(key, None)
    return out


def _is_axis(da, kind) -> bool:
    sn = str(da.attrs.get("standard_name", "")).lower()
    u = _units_text(da.attrs.get("units", ""))
    name = str(da.name).lower()
    if kind == "lat":
        return (
            sn == "latitude"
            or u in ("degrees_north", "degree_north", "degree_n", "degrees_n")
            or (name in ("lat", "latitude"))
        )
    return (
        sn == "longitude"
        or u in ("degrees_east", "degree_east", "degree_e", "degrees_e")
        or (name in ("lon", "longitude"))
    )


def _axes(ds, var, tdim, where):
    """(lat dim, lon dim, lat values, lon values) of variable ``var``: two horizontal dimensions
    with 1-D latitude and longitude coordinates (a rectilinear grid)."""
    da = ds[var]
    extra = [d for d in da.dims if d != tdim]
    lat = next((d for d in extra if d in ds.variables and ds[d].ndim == 1 and _is_axis(ds[d], "lat")), None)
    lon = next((d for d in extra if d in ds.variables and ds[d].ndim == 1 and _is_axis(ds[d], "lon")), None)
    if lat is None or lon is None:
        two_d = [
            v for v in ds.variables if ds[v].ndim == 2 and (_is_axis(ds[v], "lat") or _is_axis(ds[v], "lon"))
        ]
        what = (
            f"a curvilinear grid (2-D coordinates {', '.join(map(repr, two_d))})"
            if two_d
            else f"dimensions {da.dims} without 1-D latitude and longitude coordinates (an unstructured "
            "or projected grid)"
        )
        raise ScenarioError(
            f"{where}: variable '{var}' is on {what}; this reader takes a regular or rectilinear "
            "latitude/longitude grid (time, latitude, longitude)"
        )
    others = [d for d in extra if d not in (lat, lon)]
    return lat, lon, others


# --- space ---------------------------------------------------------------------------------------------


def _axis_values(values, name, where, kind):
    v = np.asarray(values, dtype=np.float64)
    if v.size < 2 or not np.all(np.isfinite(v)):
        raise ScenarioError(f"{where}: coordinate '{name}' needs at least 2 finite values")
    d = np.diff(v)
    if not (np.all(d > 0) or np.all(d < 0)):
        raise ScenarioError(f"{where}: coordinate '{name}' is not strictly monotonic")
    if kind == "lat" and (v.min() < -90.0 or v.max() > 90.0):
        raise ScenarioError(f"{where}: coordinate '{name}' leaves [-90, 90] degrees_north")
    return v


def bilinear_plan(lat_axis, lon_axis, lat, lon, *, where="wave product", label=None):
    """For points (``lat``, ``lon`` [deg], 1-D) on the rectilinear grid (``lat_axis``,
    ``lon_axis``, each strictly monotonic, either direction): (jj, ii, w), each (npoints, 4): the
    indices into the axes of the four nodes around each point, in the order (j0, i0), (j0, i1),
    (j1, i0), (j1, i1), and their bilinear weights. Longitudes are compared modulo 360; a grid
    whose last column lies within 1.5 steps of its first + 360 wraps. A point outside the grid is
    refused, ``label(k)`` naming point k."""
    label = label or (lambda k: f"point {k}")
    lat_axis = np.asarray(lat_axis, dtype=np.float64)
    lon_axis = np.asarray(lon_axis, dtype=np.float64)
    lat = np.atleast_1d(np.asarray(lat, dtype=np.float64))
    lon = np.atleast_1d(np.asarray(lon, dtype=np.float64))
    # latitude: ascending view
    ylat = lat_axis if lat_axis[-1] > lat_axis[0] else lat_axis[::-1]
    ny = ylat.size
    # longitude: ascending view, relative to its first value
    asc = lon_axis[-1] > lon_axis[0]
    xl = lon_axis if asc else lon_axis[::-1]
    nx = xl.size
    g = xl - xl[0]
    span = g[-1]
    if span > 360.0 + 1e-9:
        raise ScenarioError(f"{where}: longitudes span {span:g} degrees, more than 360")
    step = float(np.median(np.diff(g)))
    wraps = 360.0 - span <= 1.5 * step + 1e-9
    jj = np.empty((lat.size, 4), dtype=np.int64)
    ii = np.empty((lat.size, 4), dtype=np.int64)
    w = np.empty((lat.size, 4))
    for k, (y, x) in enumerate(zip(lat, lon)):
        if not (math.isfinite(y) and math.isfinite(x) and -90.0 <= y <= 90.0):
            raise ScenarioError(
                f"{where}: {label(k)} has latitude {y!r}, longitude {x!r}; allowed: finite, |lat| <= 90"
            )
        if not (ylat[0] - 1e-9 <= y <= ylat[-1] + 1e-9):
            raise ScenarioError(
                f"{where}: {label(k)} at latitude {y:g} lies outside the product's grid (latitude "
                f"{ylat[0]:g} to {ylat[-1]:g}); allowed: points inside the grid (no extrapolation)"
            )
        j = int(min(max(np.searchsorted(ylat, y, side="right") - 1, 0), ny - 2))
        wy = min(max((y - ylat[j]) / (ylat[j + 1] - ylat[j]), 0.0), 1.0)
        xr_ = (x - xl[0]) % 360.0
        if xr_ > 360.0 - 1e-9:  # (a tiny negative) % 360 rounds to 360
            xr_ = 0.0
        if xr_ <= span + 1e-9:
            i = int(min(max(np.searchsorted(g, xr_, side="right") - 1, 0), nx - 2))
            i0, i1 = i, i + 1
            wx = min(max((xr_ - g[i]) / (g[i + 1] - g[i]), 0.0), 1.0)
        elif wraps:
            i0, i1 = nx - 1, 0
            wx = (xr_ - span) / (360.0 - span)
        else:
            raise ScenarioError(
                f"{where}: {label(k)} at longitude {x:g} lies outside the product's grid (longitude "
                f"{xl[0]:g} to {xl[-1]:g}, compared modulo 360); allowed: points inside the grid "
                "(no extrapolation)"
            )
        j0, j1 = j, j + 1
        if not (lat_axis[-1] > lat_axis[0]):  # back to the file's order
            j0, j1 = ny - 1 - j0, ny - 1 - j1
        if not asc:
            i0, i1 = nx - 1 - i0, nx - 1 - i1
        jj[k] = (j0, j0, j1, j1)
        ii[k] = (i0, i1, i0, i1)
        w[k] = ((1 - wy) * (1 - wx), (1 - wy) * wx, wy * (1 - wx), wy * wx)
    return jj, ii, w


def _fallback(jj, ii, w, valid, lat_axis, lon_axis, lat, lon, where, label, steps):
    """The weights with land: where a node with weight > 0 has no value at some time, the point
    takes the nearest valid one of its four nodes (weight 1); none valid: refused."""
    w = w.copy()
    lat_axis = np.asarray(lat_axis, dtype=np.float64)
    lon_axis = np.asarray(lon_axis, dtype=np.float64)
    for k in range(w.shape[0]):
        ok = valid[jj[k], ii[k]]
        if np.all(ok | (w[k] == 0.0)):
            w[k] = np.where(ok, w[k], 0.0)
            continue
        if not ok.any():
            raise ScenarioError(
                f"{where}: {label(k)} has no sea node of the wave product among the four around it "
                f"(grid steps {steps[0]:g} x {steps[1]:g} degrees): all are land or missing at some "
                "time; allowed: a point with a sea node within one grid step"
            )
        dy = lat_axis[jj[k]] - lat[k]
        dx = ((lon_axis[ii[k]] - lon[k] + 180.0) % 360.0 - 180.0) * math.cos(math.radians(lat[k]))
        d = np.where(ok, np.hypot(dy, dx), np.inf)
        w[k] = 0.0
        w[k, int(np.argmin(d))] = 1.0
    return w


# --- time ----------------------------------------------------------------------------------------------


def stage_times(seconds, step_s=STEP_S):
    """The stage's times [s] for a product's record times ``seconds`` (from 0): those times when no
    step exceeds ``step_s``, else every ``step_s`` from 0 and the last record's time."""
    seconds = np.asarray(seconds, dtype=np.float64)
    if not (math.isfinite(step_s) and step_s > 0.0):
        raise ScenarioError(f"wave product: time step = {step_s!r} s; allowed: > 0 s")
    if np.all(np.diff(seconds) <= step_s):
        return seconds.copy()
    end = float(seconds[-1])
    t = np.arange(0.0, end, step_s)
    return np.r_[t, end] if end - t[-1] > 1e-6 * step_s else np.r_[t[:-1], end]


def interpolate_time(seconds, values, times):
    """``values`` (nt, ...) at record times ``seconds`` linearly interpolated to ``times`` (inside
    [seconds[0], seconds[-1]]); exact at the records."""
    seconds = np.asarray(seconds, dtype=np.float64)
    values = np.asarray(values, dtype=np.float64)
    k = np.clip(np.searchsorted(seconds, times, side="right") - 1, 0, seconds.size - 2)
    f = (times - seconds[k]) / (seconds[k + 1] - seconds[k])
    f = f.reshape((-1,) + (1,) * (values.ndim - 1))
    out = values[k] * (1.0 - f) + values[k + 1] * f
    at = f.reshape(-1) == 0.0
    out[at] = values[k[at]]  # a record's own value, bit for bit
    return out


# --- reading -------------------------------------------------------------------------------------------


def grib_reader():
    """Import the optional GRIB reader cfgrib (ImportError without it), after pyproj where both
    are installed (:func:`mineburial._deferred.proj_before_eccodes`: ecCodes loaded before PROJ
    aborts the process at exit)."""
    proj_before_eccodes()
    import cfgrib  # local import: the optional GRIB reader

    return cfgrib


def _open(path, where, max_bytes):
    fio._regular_file(path, where, max_bytes)
    suffix = path.suffix.lower()
    if suffix in GRIB_SUFFIXES:
        try:
            grib_reader()
        except ImportError:
            raise ScenarioError(
                f"{where}: a GRIB file needs the optional reader cfgrib with ecCodes "
                "(pip install cfgrib eccodes), not installed here; or convert it to NetCDF "
                "(e.g. ecCodes' grib_to_netcdf, or the Climate Data Store's NetCDF download)"
            ) from None
        try:  # indexpath "": cfgrib writes no index file beside the user's file
            ds = xr.open_dataset(
                path,
                engine="cfgrib",
                decode_times=False,
                decode_timedelta=False,
                backend_kwargs={"indexpath": ""},
            )
        except Exception as exc:  # noqa: BLE001  # cfgrib/ecCodes raise their own types on a bad file
            first = str(exc).splitlines()[0] if str(exc) else ""
            raise ScenarioError(
                f"{where}: cannot open as GRIB ({type(exc).__name__}: {first[:120]})"
            ) from None
        return _grib_valid_time(ds, where)
    try:
        return xr.open_dataset(path, decode_times=False, decode_timedelta=False)
    except (OSError, ValueError, RuntimeError, TypeError, KeyError) as exc:
        first = str(exc).splitlines()[0] if str(exc) else ""
        raise ScenarioError(f"{where}: cannot open as NetCDF ({type(exc).__name__}: {first[:120]})") from None


def _grib_valid_time(ds, where):
    """cfgrib's layout with the valid time as the ``time`` axis. cfgrib names the forecast's
    reference time ``time`` (standard_name forecast_reference_time), its lead ``step`` and their
    sum ``valid_time``: an analysis series (ERA5) has ``time`` as its axis (step 0), a forecast
    (WAVEWATCH III's GRIB2) ``step`` (one reference time). The stage needs the time each field is
    valid at, so ``valid_time`` replaces whichever axis it runs along; a file with several
    reference times *and* several steps is refused (select one of them first)."""
    vt = ds.variables.get("valid_time")
    if vt is None:
        return ds
    if vt.ndim == 0:
        ds.close()
        raise ScenarioError(
            f"{where}: the GRIB file holds fields valid at one time only; allowed: a series of at "
            "least two times"
        )
    if vt.ndim != 1:
        ds.close()
        raise ScenarioError(
            f"{where}: a GRIB file with several reference times and several forecast steps "
            f"(valid_time of dimensions {vt.dims}); allowed: one of them (select one reference time "
            "or one step first, e.g. with grib_copy)"
        )
    axis = vt.dims[0]
    drop = [c for c in ("time", "step") if c in ds.variables and c != axis]
    out = ds.swap_dims({axis: "valid_time"}).drop_vars(drop + [axis]).rename({"valid_time": "time"})
    return out


def _si(key, name, values, units, where):
    """Values of quantity ``key`` in SI (periods for a frequency); the finite ones checked
    against the quantity's range (NaN are land or missing, handled by the interpolation)."""
    if key == "fp":
        if units is None or _units_text(units) not in _FREQUENCY:
            raise ScenarioError(
                f"{where}: variable '{name}' (peak frequency) has units {units!r}; accepted: "
                f"{', '.join(_FREQUENCY)}"
            )
        f = values * _FREQUENCY[_units_text(units)]
        bad = np.isfinite(f) & ~((f >= _FP_RANGE[0]) & (f <= _FP_RANGE[1]))
        if bad.any():
            raise ScenarioError(
                f"{where}: variable '{name}' = {f[bad][0]:g} Hz; allowed: [{_FP_RANGE[0]:g}, "
                f"{_FP_RANGE[1]:g}] Hz (periods of 0.5 to 40 s)"
            )
        return 1.0 / f  # Tp = 1 / fp [s]
    q = fio.QUANTITIES["tp" if key in fio._PERIODS else key]
    spelled = None if units is None else _units_text(units)
    factor = fio._factor(where, name, key, spelled)
    v = values * factor
    bad = np.isfinite(v) & ~((v <= q.hi) & ((v > q.lo) if q.lo_open else (v >= q.lo)))
    if bad.any():
        raise ScenarioError(
            f"{where}: variable '{name}' = {values[bad][0]:g} {units}; allowed: {fio._range_text(q)}"
        )
    return v


def load_wave_points(
    path,
    lat,
    lon,
    *,
    labels=None,
    step_s=STEP_S,
    gap_factor=fio.GAP_FACTOR,
    max_gap_s=None,
    max_bytes=fio.MAX_NETCDF_BYTES,
):
    """Read a wave product (NetCDF, or GRIB with cfgrib) and interpolate it onto the points
    (``lat``, ``lon`` [deg], 1-D) and the stage's times (module docstring). Returns (times [s]
    from the first record, start (UTC datetime64 or None), fields: {Forcing field name: (nt,
    npoints) float64}, what: a dict describing the reading (product variables, methods)).
    ``labels(k)`` names point k in messages."""
    path = pathlib.Path(path)
    where = f"forcing file '{path}'"
    lat = np.atleast_1d(np.asarray(lat, dtype=np.float64))
    lon = np.atleast_1d(np.asarray(lon, dtype=np.float64))
    label = labels or (lambda k: f"location (latitude {lat[k]:g}, longitude {lon[k]:g})")
    with _open(path, where, max_bytes) as ds:
        tname, seconds, start = fio._netcdf_times(ds, where)
        fio._check_times(where, tname, seconds, start, gap_factor, max_gap_s)
        tdim = ds[tname].dims[0]
        names = _find(ds, where)
        latdim, londim, others = _axes(ds, names["hs"], tdim, where)
        lat_axis = _axis_values(ds[latdim].values, latdim, where, "lat")
        lon_axis = _axis_values(ds[londim].values, londim, where, "lon")
        jj, ii, w = bilinear_plan(lat_axis, lon_axis, lat, lon, where=where, label=label)
        # read only the nodes the points need (a global file is not read whole)
        uj, jpos = np.unique(jj, return_inverse=True)
        ui, ipos = np.unique(ii, return_inverse=True)
        jpos, ipos = jpos.reshape(jj.shape), ipos.reshape(ii.shape)
        need = 8.0 * fio.READ_COPIES * len(names) * seconds.size * (uj.size * ui.size + lat.size)
        refusal = resources.memory_refusal(
            need,
            f"{where}: reading {len(names)} variables at {uj.size} x {ui.size} nodes, {seconds.size} times",
            "give a shorter series or fewer cells",
        )
        if refusal:
            raise ScenarioError(refusal)
        raw = {}
        for key, name in names.items():
            da = ds[name]
            if set(da.dims) - {tdim, latdim, londim} - set(others) or {tdim, latdim, londim} - set(da.dims):
                expected = f"({tdim}, {latdim}, {londim})"
                raise ScenarioError(
                    f"{where}: variable '{name}' has dimensions {da.dims}; expected {expected}"
                )
            sub = da.isel({latdim: uj, londim: ui})
            for d in [d for d in da.dims if d not in (tdim, latdim, londim)]:
                if d == "expver":  # ERA5 with ERA5T (old CDS files): per record the first with a value
                    sub = sub.load()
                    sub = sub.isel(expver=0).combine_first(sub.isel(expver=slice(1, None)).max("expver"))
                elif da.sizes[d] == 1:
                    sub = sub.isel({d: 0})
                else:
                    raise ScenarioError(
                        f"{where}: variable '{name}' has the extra dimension '{d}' of size {da.sizes[d]}; "
                        "only size 1 (or ERA5's expver) is accepted: select one member or level first"
                    )
            values = fio._numbers(sub.transpose(tdim, latdim, londim), name, where)
            raw[key] = _si(key, name, values, da.attrs.get("units"), where)
    period = next(k for k in ("tp", "fp", "tm01", "tm02", "tm_10") if k in raw)
    valid = np.ones((uj.size, ui.size), dtype=bool)
    for v in raw.values():
        valid &= np.all(np.isfinite(v), axis=0)
    steps = tuple(float(np.median(np.abs(np.diff(a)))) for a in (lat_axis, lon_axis))
    w = _fallback(jpos, ipos, w, valid, lat_axis[uj], lon_axis[ui], lat, lon, where, label, steps)

    def at_points(v):  # (nt, nj, ni) -> (nt, npoints), NaN nodes of weight 0 left out
        nodes = v[:, jpos, ipos]  # (nt, npoints, 4)
        return np.sum(np.where(w > 0.0, nodes, 0.0) * w, axis=-1)

    times = stage_times(seconds, step_s)
    series = {}
    for key, v in raw.items():
        if key == "wave_dir" or key == "current_dir":
            rad = np.radians(v)
            s = interpolate_time(seconds, at_points(np.sin(rad)), times)
            c = interpolate_time(seconds, at_points(np.cos(rad)), times)
            series[key] = np.mod(np.degrees(np.arctan2(s, c)), 360.0)
        else:
            series[key] = interpolate_time(seconds, at_points(v), times)
    n = series["hs"].shape
    if "current_u" in series:
        speed = np.hypot(series["current_u"], series["current_v"])
        to = np.mod(np.degrees(np.arctan2(series["current_u"], series["current_v"])), 360.0)
    elif "current_speed" in series:
        speed, to = series["current_speed"], series["current_dir"]
    else:
        speed, to = np.zeros(n), np.zeros(n)
    tp_key = "tp" if period == "fp" else period
    fields = {
        "hs": series["hs"],
        "tp": series[period] / fio.PERIOD_RATIOS[tp_key],
        "wave_from": series["wave_dir"],
        "current_speed": speed,
        "current_to": to,
        "water_level": series.get("water_level", np.zeros(n)),
    }
    for field, key in (
        ("hs", "hs"),
        ("tp", "tp"),
        ("wave_from", "wave_dir"),
        ("current_speed", "current_speed"),
    ):
        fio._check_values(
            where,
            names.get(key, field) if key != "tp" else names[period],
            key,
            fields[field],
            lambda i: fio._iso(start, times[i]),
            cell=lambda idx: f" at {label(int(idx[0]))}",
        )
    what = {
        "variables": {k: names[k] for k in names},
        "period": period,
        "space": "bilinear in longitude/latitude; land: nearest sea node of the four",
        "time": "linear" if times.size != seconds.size else "the product's records",
        "current": "from the file" if "current_u" in names or "current_speed" in names else "none: 0 m/s",
    }
    return times, start, fields, what


def load_wave_point(path, lat, lon, **kwargs) -> fio.Forcing:
    """The :class:`~mineburial.io.forcing.Forcing` of a wave product at one location (``lat``,
    ``lon`` [deg]): :func:`load_wave_points` at a single point (``scour.forcing_location``)."""
    times, start, fields, what = load_wave_points(path, [lat], [lon], **kwargs)
    return fio.Forcing(
        time=times,
        start=start,
        source=f"forcing file '{path}' at latitude {lat:g}, longitude {lon:g}",
        **{k: v[:, 0] for k, v in fields.items()},
    )


def is_lat_lon_grid(path) -> tuple | None:
    """(latitude values, longitude values) of a NetCDF file's first variable on (time, lat, lon)
    with 1-D latitude/longitude coordinates, or None (not such a file, or unreadable: the reader
    that follows then says why)."""
    try:
        with xr.open_dataset(path, decode_times=False, decode_timedelta=False) as ds:
            for v in ds.data_vars:
                dims = ds[v].dims
                lat = next(
                    (d for d in dims if d in ds.variables and ds[d].ndim == 1 and _is_axis(ds[d], "lat")),
                    None,
                )
                lon = next(
                    (d for d in dims if d in ds.variables and ds[d].ndim == 1 and _is_axis(ds[d], "lon")),
                    None,
                )
                if lat and lon:
                    return np.asarray(ds[lat].values, dtype=np.float64), np.asarray(
                        ds[lon].values, dtype=np.float64
                    )
    except (OSError, ValueError, RuntimeError, TypeError, KeyError):
        return None
    return None


def load_wave_grid(path, lat, lon, mask, dims, *, labels=None, **kwargs) -> fio.GriddedForcing:
    """A wave product interpolated onto a map's cells: ``lat`` (ny,), ``lon`` (nx,) the
    environment grid's axes [deg], ``mask`` (ny, nx) the cells to fill (the others dry), ``dims``
    its (y, x) dimension names. ``labels(j, i)`` names a cell in messages."""
    mask = np.asarray(mask, dtype=bool)
    jj, ii = np.nonzero(mask)
    lat = np.asarray(lat, dtype=np.float64)
    lon = np.asarray(lon, dtype=np.float64)
    name = (lambda k: labels(int(jj[k]), int(ii[k]))) if labels else (lambda k: f"cell ({jj[k]}, {ii[k]})")
    times, start, fields, _ = load_wave_points(path, lat[jj], lon[ii], labels=name, **kwargs)
    full = {}
    for k, v in fields.items():
        a = np.full((times.size,) + mask.shape, np.nan)
        a[:, mask] = v
        a.flags.writeable = False
        full[k] = a
    return fio.GriddedForcing(
        time=fio._ro(times),
        start=start,
        dims=tuple(dims),
        y=lat,
        x=lon,
        wet=mask,
        fields=full,
        source=f"forcing file '{path}'",
    )
