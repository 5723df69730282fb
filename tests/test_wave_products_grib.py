"""Wave products in GRIB (issue 33, item 6: "GRIB through cfgrib as an optional extra"), read by
mineburial.io.wave_products through cfgrib. The files are written here with ecCodes in the real
layouts: ERA5's analysis series (GRIB 1, ECMWF parameters swh 140229, pp1d 140231, mwd 140230,
latitudes north to south, longitudes 0..360, one field per parameter and time) and NCEP's
WAVEWATCH III forecast (GRIB 2, discipline 10 category 0 parameters 3 HTSGW, 11 PERPW, 10 DIRPW,
one reference time, hourly steps), with land as GRIB bitmap points. The reference values are the
fields as ecCodes itself decodes them (GRIB packs to 16 bits: the written values are not what a
reader gets back), interpolated with scipy's RegularGridInterpolator and numpy.interp."""

from __future__ import annotations

import datetime as dt
import subprocess
import sys

import numpy as np
import pytest
from scipy.interpolate import RegularGridInterpolator

from mineburial.errors import ScenarioError
from mineburial.io import wave_products as wp

try:  # the reader's import order (pyproj before ecCodes: wave_products.grib_reader), then ecCodes
    wp.grib_reader()
    import eccodes
except ImportError:
    pytest.skip("the optional GRIB extra is not installed (pip install '.[grib]')", allow_module_level=True)

RNG = np.random.default_rng(20261129)
MISSING = 9999.0


def _set(h, **keys):
    for k, v in keys.items():
        eccodes.codes_set(h, k, v)


def _message(f, edition, lat, lon, values, land=(), **keys):
    """Write one field; returns the values as ecCodes decodes them back, as float32 (cfgrib's
    type for GRIB values), NaN at land."""
    h = eccodes.codes_grib_new_from_samples(f"regular_ll_sfc_grib{edition}")
    step = float(abs(lat[1] - lat[0]))
    _set(
        h,
        Ni=lon.size,
        Nj=lat.size,
        latitudeOfFirstGridPointInDegrees=float(lat[0]),
        latitudeOfLastGridPointInDegrees=float(lat[-1]),
        longitudeOfFirstGridPointInDegrees=float(lon[0]),
        longitudeOfLastGridPointInDegrees=float(lon[-1]),
        iDirectionIncrementInDegrees=step,
        jDirectionIncrementInDegrees=step,
        **keys,
    )
    v = values.copy()
    if land:
        _set(h, bitmapPresent=1, missingValue=MISSING)
        for j, i in land:
            v[j, i] = MISSING
    eccodes.codes_set_values(h, v.ravel())
    decoded = eccodes.codes_get_values(h).reshape(v.shape).astype(np.float32).astype(np.float64)
    eccodes.codes_write(h, f)
    eccodes.codes_release(h)
    return np.where(decoded == np.float32(MISSING), np.nan, decoded)


def era5_grib(path, land=()):
    """ERA5 wave parameters, 6-hourly analyses on a 0.5-degree grid (GRIB 1)."""
    lat = np.array([21.5, 21.0, 20.5, 20.0])  # north to south, as ECMWF writes
    lon = np.arange(201.0, 203.01, 0.5)
    nt = 5
    out = {"swh": [], "pp1d": [], "mwd": []}
    ranges = {"swh": (140229, 0.5, 3.0), "pp1d": (140231, 6.0, 14.0), "mwd": (140230, 0.0, 360.0)}
    with open(path, "wb") as f:
        for k in range(nt):
            when = dt.datetime(2008, 1, 10) + dt.timedelta(hours=6 * k)
            for name, (pid, lo, hi) in ranges.items():
                field = lo + (hi - lo) * RNG.random((lat.size, lon.size))
                out[name].append(
                    _message(
                        f,
                        1,
                        lat,
                        lon,
                        field,
                        land,
                        dataDate=int(when.strftime("%Y%m%d")),
                        dataTime=when.hour * 100,
                        paramId=pid,
                    )
                )
    return lat, lon, 6 * 3600.0 * np.arange(nt), {k: np.array(v) for k, v in out.items()}


def ww3_grib2(path, steps=(0, 1, 2, 3, 4), reference_hours=(0,)):
    """NCEP WAVEWATCH III forecast fields (GRIB 2, discipline 10): hourly steps of one run."""
    lat = np.array([30.0, 29.75, 29.5])
    lon = np.arange(235.0, 236.01, 0.25)
    out = {"swh": [], "perpw": [], "dirpw": []}
    ranges = {"swh": (3, 0.5, 4.0), "perpw": (11, 5.0, 16.0), "dirpw": (10, 0.0, 360.0)}
    with open(path, "wb") as f:
        for hour in reference_hours:
            for step in steps:
                for name, (number, lo, hi) in ranges.items():
                    field = lo + (hi - lo) * RNG.random((lat.size, lon.size))
                    out[name].append(
                        _message(
                            f,
                            2,
                            lat,
                            lon,
                            field,
                            centre=7,
                            dataDate=20240301,
                            dataTime=hour * 100,
                            discipline=10,
                            parameterCategory=0,
                            parameterNumber=number,
                            stepUnits=1,
                            forecastTime=step,
                        )
                    )
    return lat, lon, 3600.0 * np.asarray(steps, dtype=float), {k: np.array(v) for k, v in out.items()}


def bilinear(lat, lon, field, plat, plon):
    order = np.argsort(lat)
    x = plon % 360.0
    return np.array([RegularGridInterpolator((lat[order], lon), f[order])([[plat, x]])[0] for f in field])


def bilinear_dir(lat, lon, deg, plat, plon):
    s = bilinear(lat, lon, np.sin(np.radians(deg)), plat, plon)
    c = bilinear(lat, lon, np.cos(np.radians(deg)), plat, plon)
    return np.degrees(np.arctan2(s, c)) % 360.0


def angle_close(a, b, tol):
    return np.max(np.abs((np.asarray(a) - np.asarray(b) + 180.0) % 360.0 - 180.0)) <= tol


def test_era5_grib_analysis_series_is_read_by_valid_time_and_interpolated_like_the_netcdf(tmp_path):
    path = tmp_path / "era5_waves.grib"
    lat, lon, t, f = era5_grib(path)
    plat, plon = 20.8, -158.3  # Oahu's south shore, asked on -180..180 of a 0..360 grid
    got = wp.load_wave_point(path, plat, plon)
    hours, hs = np.arange(0.0, t[-1] + 1.0, 3600.0), bilinear(lat, lon, f["swh"], plat, plon)
    assert np.array_equal(got.time, hours)  # 6-hourly records, linear to the stage's hourly steps
    np.testing.assert_allclose(got.hs, np.interp(hours, t, hs), rtol=1e-12)
    np.testing.assert_allclose(
        got.tp, np.interp(hours, t, bilinear(lat, lon, f["pp1d"], plat, plon)), rtol=1e-12
    )
    assert angle_close(got.wave_from[::6], bilinear_dir(lat, lon, f["mwd"], plat, plon), 1e-9)
    assert str(got.start) == "2008-01-10T00:00:00.000000000"
    assert not list(tmp_path.glob("*.idx"))  # no cfgrib index written beside the user's file


def test_ww3_grib2_forecast_steps_become_the_time_axis_and_perpw_is_the_peak_period(tmp_path):
    path = tmp_path / "gfswave.grib2"
    lat, lon, t, f = ww3_grib2(path)
    plat, plon = 29.6, -124.4
    got = wp.load_wave_point(path, plat, plon)
    assert np.array_equal(got.time, t)  # hourly steps: the records themselves
    np.testing.assert_allclose(got.hs, bilinear(lat, lon, f["swh"], plat, plon), rtol=1e-12)
    np.testing.assert_allclose(got.tp, bilinear(lat, lon, f["perpw"], plat, plon), rtol=1e-12)
    assert angle_close(got.wave_from, bilinear_dir(lat, lon, f["dirpw"], plat, plon), 1e-9)
    assert str(got.start) == "2024-03-01T00:00:00.000000000"  # the reference time + step 0


def test_grib_land_points_from_the_bitmap_take_the_nearest_sea_node(tmp_path):
    path = tmp_path / "era5_land.grib"
    lat, lon, t, f = era5_grib(path, land=[(1, 1)])  # (21.0 N, 201.5 E) is land
    plat, plon = 20.9, 201.4  # among (21.0, 201.0), (21.0, 201.5)=land, (20.5, 201.0), (20.5, 201.5)
    got = wp.load_wave_point(path, plat, plon)
    # the nearest valid node of the four: (21.0, 201.0) at dlat 0.1, dlon 0.4 cos(20.9)
    hours = np.arange(0.0, t[-1] + 1.0, 3600.0)
    np.testing.assert_allclose(got.hs, np.interp(hours, t, f["swh"][:, 1, 0]), rtol=1e-12)


def test_grib_with_several_reference_times_and_steps_is_refused_in_one_line(tmp_path):
    path = tmp_path / "two_runs.grib2"
    ww3_grib2(path, steps=(0, 1, 2), reference_hours=(0, 6))
    with pytest.raises(ScenarioError, match=r"several reference times and several forecast steps"):
        wp.load_wave_point(path, 29.6, -124.4)


def test_a_file_that_is_not_grib_is_refused_naming_it(tmp_path):
    path = tmp_path / "broken.grib"
    path.write_bytes(b"GRIB" + bytes(100))
    with pytest.raises(ScenarioError, match=r"broken.grib'.*cannot open as GRIB"):
        wp.load_wave_point(path, 20.0, 200.0)


def test_without_cfgrib_a_grib_file_is_refused_with_the_extra_to_install(tmp_path, monkeypatch):
    monkeypatch.setitem(sys.modules, "cfgrib", None)  # import cfgrib raises ImportError
    path = tmp_path / "era5.grib"
    path.write_bytes(b"GRIB" + bytes(100))
    with pytest.raises(ScenarioError, match=r"GRIB file needs the optional reader cfgrib"):
        wp.load_wave_point(path, 54.0, 10.0)


def test_a_process_with_cfgrib_and_pyproj_installed_exits_cleanly_after_opening_a_netcdf(tmp_path):
    """xarray imports every backend at its first open (cfgrib's loads ecCodes); mineburial imports
    pyproj before xarray where both are installed, so the process exits 0 (ecCodes first: 134)."""
    pytest.importorskip("pyproj")
    path = tmp_path / "plain.nc"
    code = (
        "import numpy as np, sys\n"
        "from mineburial._deferred import xarray as xr\n"
        f"xr.Dataset({{'a': ('t', np.arange(3.0))}}).to_netcdf({str(path)!r})\n"
        f"assert float(xr.open_dataset({str(path)!r})['a'].sum()) == 3.0\n"
        "assert 'eccodes' in sys.modules and 'pyproj' in sys.modules\n"
    )
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stderr[-2000:]
