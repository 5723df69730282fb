"""Wave-model products as scour forcing (issue 33, item 6): ERA5, Copernicus Marine and WAVEWATCH III
files written here in their real layouts (variable names, standard names, units, packing, fill
values, axis order and longitude convention), read by mineburial.io.wave_products and compared
with references computed independently: scipy's RegularGridInterpolator for the bilinear step,
numpy.interp for time, 1/fp for the peak period, the packing undone by hand."""

from __future__ import annotations

import math

import numpy as np
import pytest
import xarray as xr
from scipy.interpolate import RegularGridInterpolator

from mineburial.errors import ScenarioError
from mineburial.io import wave_products as wp
from mineburial.systems.mine.processes import scour

RNG = np.random.default_rng(20260433)
FILL = -32767


def _packed(values, scale, offset=0.0):
    """What a reader must get back from int16 packing: round((v - offset) / scale) * scale + offset,
    the fill value where v is NaN (CF packing, done by hand)."""
    ints = np.where(np.isnan(values), FILL, np.round((values - offset) / scale))
    return np.where(ints == FILL, np.nan, ints * scale + offset)


def _int16(scale, offset=0.0):
    return {"dtype": "int16", "scale_factor": scale, "add_offset": offset, "_FillValue": FILL}


def _field(shape, lo, hi):
    return lo + (hi - lo) * RNG.random(shape)


# --- the three layouts ---------------------------------------------------------------------------------


def era5_new(path, land=()):
    """ERA5 single levels from the Climate Data Store (NetCDF since 2024): (valid_time, latitude,
    longitude), valid_time int64 seconds since 1970, latitude descending 90 -> -90 in part, longitude
    0..359.5 (0.5 degree wave grid), float32 with NaN fill, GRIB_* attributes and standard_name
    'unknown', scalar 'number', 'expver' text along valid_time. Hourly."""
    lat = np.array([56.0, 55.5, 55.0, 54.5, 54.0])
    lon = np.arange(0.0, 360.0, 0.5)
    nt = 7
    shape = (nt, lat.size, lon.size)
    data = {
        "swh": _field(shape, 0.5, 3.0),
        "pp1d": _field(shape, 5.0, 12.0),
        "mwd": _field(shape, 0.0, 360.0),
    }
    for j, i in land:
        for v in data.values():
            v[:, j, i] = np.nan
    t = 1_700_000_000 + 3600 * np.arange(nt, dtype=np.int64)
    attrs = {
        "swh": ("Significant height of combined wind waves and swell", "m", 140229),
        "pp1d": ("Peak wave period", "s", 140231),
        "mwd": ("Mean wave direction", "Degree true", 140230),
    }
    ds = xr.Dataset(
        {
            k: (
                ("valid_time", "latitude", "longitude"),
                v.astype(np.float32),
                {
                    "long_name": attrs[k][0],
                    "units": attrs[k][1],
                    "GRIB_paramId": attrs[k][2],
                    "GRIB_shortName": k,
                    "standard_name": "unknown",
                },
            )
            for k, v in data.items()
        },
        coords={
            "number": 0,
            "valid_time": (
                "valid_time",
                t,
                {
                    "units": "seconds since 1970-01-01",
                    "calendar": "proleptic_gregorian",
                    "standard_name": "time",
                    "long_name": "time",
                },
            ),
            "latitude": ("latitude", lat, {"units": "degrees_north", "standard_name": "latitude"}),
            "longitude": ("longitude", lon, {"units": "degrees_east", "standard_name": "longitude"}),
            "expver": ("valid_time", np.array(["0001"] * nt)),
        },
        attrs={
            "GRIB_centre": "ecmf",
            "Conventions": "CF-1.7",
            "institution": "European Centre for Medium-Range Weather Forecasts",
        },
    )
    enc = {k: {"_FillValue": np.float32(np.nan)} for k in data}
    ds.to_netcdf(path, encoding=enc)
    f32 = {k: v.astype(np.float32).astype(np.float64) for k, v in data.items()}
    return lat, lon, (t - t[0]).astype(float), f32


def era5_old(path, expver=False):
    """ERA5 from the old Climate Data Store: (time, latitude, longitude), time int32 hours since
    1900-01-01 00:00:00.0 (gregorian), int16 packed (scale_factor, add_offset, _FillValue =
    missing_value = -32767); swh, mwp (Tm-1,0), mwd. With ``expver`` the ERA5/ERA5T mix: an expver
    dimension of 2 whose first holds the first records, the second the rest."""
    lat = np.array([55.0, 54.75, 54.5, 54.25])
    lon = np.array([10.0, 10.25, 10.5, 10.75])
    nt = 5
    shape = (nt, lat.size, lon.size)
    raw = {
        "swh": _field(shape, 0.5, 3.0),
        "mwp": _field(shape, 4.0, 10.0),
        "mwd": _field(shape, 200.0, 340.0),
    }
    scale = {"swh": (4.5e-5, 1.6), "mwp": (1.5e-4, 7.0), "mwd": (5.5e-3, 180.0)}
    units = {"swh": "m", "mwp": "s", "mwd": "Degree true"}
    hours = (1_085_000 + np.arange(nt)).astype(np.int32)
    variables = {}
    for k, v in raw.items():
        if expver:
            both = np.full((nt, 2) + shape[1:], np.nan)
            both[:3, 0], both[3:, 1] = v[:3], v[3:]
            variables[k] = (("time", "expver", "latitude", "longitude"), both, {"units": units[k]})
        else:
            variables[k] = (("time", "latitude", "longitude"), v, {"units": units[k]})
    coords = {
        "time": (
            "time",
            hours,
            {"units": "hours since 1900-01-01 00:00:00.0", "calendar": "gregorian", "long_name": "time"},
        ),
        "latitude": ("latitude", lat, {"units": "degrees_north", "long_name": "latitude"}),
        "longitude": ("longitude", lon, {"units": "degrees_east", "long_name": "longitude"}),
    }
    if expver:
        coords["expver"] = ("expver", np.array([1, 5], dtype=np.int32))
    ds = xr.Dataset(variables, coords=coords, attrs={"Conventions": "CF-1.6"})
    enc = {k: dict(_int16(*scale[k]), missing_value=FILL) for k in raw}
    ds.to_netcdf(path, encoding=enc)
    return lat, lon, 3600.0 * np.arange(nt), {k: _packed(v, *scale[k]) for k, v in raw.items()}


def cmems(path, land=(), lat0=54.0, lon0=-5.0):
    """Copernicus Marine GLOBAL_ANALYSISFORECAST_WAV_001_027 (MFWAM), a regional subset of its
    1/12 degree grid: (time, latitude, longitude) ascending, longitudes -180..180, time hours since
    1950-01-01, 3-hourly; VHM0, VTPK, VTM10, VMDR, VPED and a wind-sea partition VHM0_WW with their
    CF standard names; int16 packed (scale 0.01 m, 0.01 s, 0.1 degree), _FillValue -32767 on land."""
    lat = lat0 + np.arange(4) / 12.0
    lon = lon0 + np.arange(5) / 12.0
    nt = 5
    shape = (nt, lat.size, lon.size)
    spec = {  # name: (standard name, units, lo, hi, scale)
        "VHM0": ("sea_surface_wave_significant_height", "m", 0.5, 4.0, 0.01),
        "VTPK": ("sea_surface_wave_period_at_variance_spectral_density_maximum", "s", 5.0, 14.0, 0.01),
        "VTM10": (
            "sea_surface_wave_mean_period_from_variance_spectral_density_inverse_frequency_moment",
            "s",
            4.0,
            11.0,
            0.01,
        ),
        "VMDR": ("sea_surface_wave_from_direction", "degree", 0.0, 360.0, 0.1),
        "VPED": (
            "sea_surface_wave_from_direction_at_variance_spectral_density_maximum",
            "degree",
            0.0,
            360.0,
            0.1,
        ),
        "VHM0_WW": ("sea_surface_wind_wave_significant_height", "m", 0.1, 1.0, 0.01),
    }
    raw = {k: _field(shape, s[2], s[3]) for k, s in spec.items()}
    for j, i in land:
        for v in raw.values():
            v[:, j, i] = np.nan
    ds = xr.Dataset(
        {
            k: (("time", "latitude", "longitude"), v, {"standard_name": spec[k][0], "units": spec[k][1]})
            for k, v in raw.items()
        },
        coords={
            "time": (
                "time",
                648_000.0 + 3.0 * np.arange(nt),
                {"units": "hours since 1950-01-01", "standard_name": "time", "calendar": "gregorian"},
            ),
            "latitude": (
                "latitude",
                lat,
                {"units": "degrees_north", "standard_name": "latitude", "axis": "Y"},
            ),
            "longitude": (
                "longitude",
                lon,
                {"units": "degrees_east", "standard_name": "longitude", "axis": "X"},
            ),
        },
        attrs={"Conventions": "CF-1.6", "source": "MFWAM", "product": "GLOBAL_ANALYSISFORECAST_WAV_001_027"},
    )
    ds.to_netcdf(path, encoding={k: _int16(spec[k][4]) for k in raw})
    return lat, lon, 3.0 * 3600.0 * np.arange(nt), {k: _packed(v, spec[k][4]) for k, v in raw.items()}


def ww3(path):
    """WAVEWATCH III ww3_ounf on a regular grid: (time, latitude, longitude), time days since
    1990-01-01 00:00:00 (double), longitudes 0..360 (a grid at 350-352 E), 3-hourly; hs (int16,
    scale 0.002), fp (peak frequency, s-1, scale 0.001, no standard_name), t02 (labelled with the
    wind-wave standard name, as ww3_ounf does), dir (degree, scale 0.1), dp, MAPSTA."""
    lat = np.array([48.0, 48.5, 49.0])
    lon = np.array([350.0, 350.5, 351.0, 351.5, 352.0])
    nt = 4
    shape = (nt, lat.size, lon.size)
    raw = {
        "hs": _field(shape, 0.5, 5.0),
        "fp": _field(shape, 0.06, 0.2),
        "t02": _field(shape, 4.0, 9.0),
        "dir": _field(shape, 0.0, 360.0),
        "dp": _field(shape, 0.0, 360.0),
    }
    attrs = {
        "hs": {
            "units": "m",
            "standard_name": "sea_surface_wave_significant_height",
            "globwave_name": "significant_wave_height",
            "long_name": "significant height of wind and swell waves",
        },
        "fp": {
            "units": "s-1",
            "long_name": "wave peak frequency",
            "globwave_name": "dominant_wave_frequency",
        },
        "t02": {
            "units": "s",
            "long_name": "mean period T02",
            "standard_name": "sea_surface_wind_wave_mean_period_from_variance_"
            "spectral_density_second_frequency_moment",
        },
        "dir": {
            "units": "degree",
            "standard_name": "sea_surface_wave_from_direction",
            "long_name": "wave mean direction",
        },
        "dp": {
            "units": "degree",
            "standard_name": "sea_surface_wave_peak_direction",
            "long_name": "peak direction",
        },
    }
    scale = {"hs": 0.002, "fp": 0.001, "t02": 0.01, "dir": 0.1, "dp": 1.0}
    ds = xr.Dataset(
        {k: (("time", "latitude", "longitude"), v, attrs[k]) for k, v in raw.items()},
        coords={
            "time": (
                "time",
                12_400.0 + 0.125 * np.arange(nt),
                {"units": "days since 1990-01-01 00:00:00", "standard_name": "time", "calendar": "standard"},
            ),
            "latitude": ("latitude", lat, {"units": "degree_north", "standard_name": "latitude"}),
            "longitude": ("longitude", lon, {"units": "degree_east", "standard_name": "longitude"}),
        },
        attrs={"WAVEWATCH_III_version_number": "7.14", "product_name": "ww3.201312.nc"},
    )
    ds["MAPSTA"] = (("latitude", "longitude"), np.ones((lat.size, lon.size), dtype=np.int16))
    ds.to_netcdf(path, encoding={k: _int16(scale[k]) for k in raw})
    return lat, lon, 3.0 * 3600.0 * np.arange(nt), {k: _packed(v, scale[k]) for k, v in raw.items()}


# --- references ----------------------------------------------------------------------------------------


def bilinear(lat, lon, field, plat, plon):
    """scipy's linear RegularGridInterpolator at (plat, plon) for every time of ``field``
    (nt, nlat, nlon); lat sorted ascending here, and a global grid extended by its first column
    at +360 so that it wraps."""
    order = np.argsort(lat)
    lat, field = lat[order], field[:, order]
    if lon[-1] - lon[0] + (lon[1] - lon[0]) >= 360.0 - 1e-9:  # global
        lon, field = np.r_[lon, lon[0] + 360.0], np.concatenate([field, field[:, :, :1]], axis=2)
    x = (plon - lon[0]) % 360.0 + lon[0]
    return np.array([RegularGridInterpolator((lat, lon), f)([[plat, x]])[0] for f in field])


def bilinear_dir(lat, lon, deg, plat, plon):
    s = bilinear(lat, lon, np.sin(np.radians(deg)), plat, plon)
    c = bilinear(lat, lon, np.cos(np.radians(deg)), plat, plon)
    return np.degrees(np.arctan2(s, c)) % 360.0


def hourly(t, v):
    times = np.arange(0.0, t[-1] + 1.0, 3600.0)
    return times, np.interp(times, t, v)


def angle_close(a, b, tol=1e-9):
    return np.max(np.abs((np.asarray(a) - np.asarray(b) + 180.0) % 360.0 - 180.0)) <= tol


# --- each product at a point ---------------------------------------------------------------------------


def test_era5_new_format_wraps_longitudes_across_the_seam_and_reads_descending_latitudes(tmp_path):
    path = tmp_path / "era5.nc"
    lat, lon, t, f = era5_new(path)
    for plat, plon in ((54.7, -0.2), (55.25, 359.9), (54.0, 10.3), (56.0, 0.0)):
        got = wp.load_wave_point(path, plat, plon)
        assert np.array_equal(got.time, t)  # hourly: the records themselves
        np.testing.assert_allclose(got.hs, bilinear(lat, lon, f["swh"], plat, plon), rtol=1e-12)
        np.testing.assert_allclose(got.tp, bilinear(lat, lon, f["pp1d"], plat, plon), rtol=1e-12)
        assert angle_close(got.wave_from, bilinear_dir(lat, lon, f["mwd"], plat, plon))
        assert np.all(got.current_speed == 0.0) and np.all(got.water_level == 0.0)
    assert str(got.start) == "2023-11-14T22:13:20.000000000"


def test_era5_old_format_packed_int16_and_the_mean_period_becomes_the_peak_period(tmp_path):
    path = tmp_path / "era5_old.nc"
    lat, lon, t, f = era5_old(path)
    plat, plon = 54.6, 10.4
    got = wp.load_wave_point(path, plat, plon)
    np.testing.assert_allclose(got.hs, bilinear(lat, lon, f["swh"], plat, plon), rtol=1e-9)
    # mwp is Tm-1,0 (ECMWF parameter 140232); Tp = Tm-1,0 / 0.90330 for the stage's JONSWAP (docs/scour.md)
    np.testing.assert_allclose(got.tp, bilinear(lat, lon, f["mwp"], plat, plon) / 0.90330, rtol=1e-9)
    assert angle_close(got.wave_from, bilinear_dir(lat, lon, f["mwd"], plat, plon), 1e-7)
    assert str(got.start) == np.datetime_as_string(
        np.datetime64("1900-01-01T00:00") + np.timedelta64(1_085_000, "h"), unit="ns"
    )


def test_era5_expver_mix_takes_each_record_from_the_experiment_that_has_it(tmp_path):
    path = tmp_path / "mix.nc"
    lat, lon, t, f = era5_old(path, expver=True)  # records 0-2 in expver 1 (ERA5), 3-4 in 5 (ERA5T)
    got = wp.load_wave_point(path, 54.6, 10.4)
    np.testing.assert_allclose(got.hs, bilinear(lat, lon, f["swh"], 54.6, 10.4), rtol=1e-9)


def test_cmems_standard_names_linear_in_time_to_hourly_and_the_wind_sea_partition_ignored(tmp_path):
    path = tmp_path / "cmems.nc"
    lat, lon, t, f = cmems(path)
    plat, plon = 54.13, -4.77
    got = wp.load_wave_point(path, plat, plon)
    times, hs = hourly(t, bilinear(lat, lon, f["VHM0"], plat, plon))
    assert np.array_equal(got.time, times) and got.time[-1] == 12 * 3600.0
    np.testing.assert_allclose(got.hs, hs, rtol=1e-12)
    np.testing.assert_allclose(got.tp, hourly(t, bilinear(lat, lon, f["VTPK"], plat, plon))[1], rtol=1e-12)
    # the mean direction VMDR (not the peak direction VPED), as unit vectors in space and time
    rad = np.radians(f["VMDR"])
    s = hourly(t, bilinear(lat, lon, np.sin(rad), plat, plon))[1]
    c = hourly(t, bilinear(lat, lon, np.cos(rad), plat, plon))[1]
    assert angle_close(got.wave_from, np.degrees(np.arctan2(s, c)) % 360.0, 1e-9)


def test_ww3_peak_frequency_becomes_a_period_at_the_nodes_and_0_360_serves_negative_longitudes(tmp_path):
    path = tmp_path / "ww3.nc"
    lat, lon, t, f = ww3(path)
    plat, plon = 48.3, -9.2  # = 350.8 E
    got = wp.load_wave_point(path, plat, plon)
    tp = hourly(t, bilinear(lat, lon, 1.0 / f["fp"], plat, plon))[1]  # Tp = 1/fp, then interpolated
    np.testing.assert_allclose(got.tp, tp, rtol=1e-12)
    np.testing.assert_allclose(got.hs, hourly(t, bilinear(lat, lon, f["hs"], plat, plon))[1], rtol=1e-12)
    rad = np.radians(f["dir"])  # 'dir', the mean direction, before the peak direction 'dp'
    s = hourly(t, bilinear(lat, lon, np.sin(rad), plat, plon))[1]
    c = hourly(t, bilinear(lat, lon, np.cos(rad), plat, plon))[1]
    assert angle_close(got.wave_from, np.degrees(np.arctan2(s, c)) % 360.0)
    assert got.start == np.datetime64("1990-01-01") + np.timedelta64(12_400, "D")


def test_ww3_without_fp_reads_t02_by_name_and_converts_it(tmp_path):
    path = tmp_path / "ww3.nc"
    lat, lon, t, f = ww3(path)
    with xr.open_dataset(path) as ds:
        ds.drop_vars("fp").load().to_netcdf(tmp_path / "nofp.nc")
    got = wp.load_wave_point(tmp_path / "nofp.nc", 48.3, 351.1)
    want = hourly(t, bilinear(lat, lon, f["t02"], 48.3, 351.1))[1] / 0.77740  # Tm02 = 0.77740 Tp
    np.testing.assert_allclose(got.tp, want, rtol=1e-9)


# --- land, edges and refusals --------------------------------------------------------------------------


def test_land_node_the_point_takes_its_nearest_sea_node_of_four_and_all_land_is_refused(tmp_path):
    path = tmp_path / "cmems.nc"
    land = ((1, 1), (1, 2), (2, 1), (2, 2), (0, 1))
    lat, lon, t, f = cmems(path, land=land)
    # cell between nodes (0,0) (0,1) (1,0) (1,1): (0,1) and (1,1) are land; nearer (1,0) than (0,0)
    plat, plon = lat[0] + 0.7 / 12, lon[0] + 0.2 / 12
    got = wp.load_wave_point(path, plat, plon)
    d = {}
    for j, i in ((0, 0), (1, 0)):
        d[(j, i)] = math.hypot(lat[j] - plat, (lon[i] - plon) * math.cos(math.radians(plat)))
    j, i = min(d, key=d.get)
    assert (j, i) == (1, 0)
    np.testing.assert_allclose(got.hs, hourly(t, f["VHM0"][:, j, i])[1], rtol=1e-12)
    # every node around the point is land: refused, the point named
    with pytest.raises(
        ScenarioError,
        match=r"location \(latitude 54\.125, longitude -4\.875\) has no sea node.*steps 0\.0833333 x.*one "
        "grid step",
    ):
        wp.load_wave_point(path, lat[1] + 0.5 / 12, lon[1] + 0.5 / 12)
    # a map's cells take the same rule, the cell named
    with pytest.raises(ScenarioError, match=r"cell \(0, 0\) .*no sea node"):
        wp.load_wave_grid(
            path,
            np.array([lat[1] + 0.5 / 12]),
            np.array([lon[1] + 0.5 / 12]),
            np.ones((1, 1), bool),
            ("latitude", "longitude"),
        )


def test_points_outside_the_grid_are_refused_not_extrapolated(tmp_path):
    path = tmp_path / "ww3.nc"
    ww3(path)
    with pytest.raises(
        ScenarioError, match=r"latitude 50 lies outside the product's grid \(latitude 48 to 49\)"
    ):
        wp.load_wave_point(path, 50.0, 351.0)
    with pytest.raises(
        ScenarioError, match=r"longitude 5 lies outside the product's grid \(longitude 350 to 352"
    ):
        wp.load_wave_point(path, 48.5, 5.0)


def test_bilinear_plan_weights_sum_to_one_and_reproduce_a_bilinear_function_exactly():
    # f = a + b x + c y + d x y is reproduced exactly by bilinear interpolation (descending axes too)
    lat = np.array([60.0, 59.0, 57.5, 57.0])
    lon = np.array([20.0, 18.0, 17.5, 15.0])
    y, x = np.meshgrid(lat, lon, indexing="ij")
    fn = 1.0 + 0.3 * x - 0.7 * y + 0.05 * x * y
    plat, plon = RNG.uniform(57.0, 60.0, 50), RNG.uniform(15.0, 20.0, 50)
    jj, ii, w = wp.bilinear_plan(lat, lon, plat, plon)
    assert np.allclose(w.sum(axis=1), 1.0) and np.all(w >= 0.0)
    np.testing.assert_allclose(
        (fn[jj, ii] * w).sum(axis=1), 1.0 + 0.3 * plon - 0.7 * plat + 0.05 * plon * plat, rtol=1e-12
    )


def test_refusals_name_what_is_missing_or_unreadable(tmp_path):
    lat, lon, t, f = cmems(tmp_path / "cmems.nc")
    with xr.open_dataset(tmp_path / "cmems.nc") as ds:
        ds = ds.load()
    ds[["VHM0"]].to_netcdf(tmp_path / "hs_only.nc")
    with pytest.raises(ScenarioError, match=r"missing a wave period .*; wave direction"):
        wp.load_wave_point(tmp_path / "hs_only.nc", 54.1, -4.8)
    bad = ds.copy()
    bad["VHM0"].attrs["units"] = "ft"
    bad.to_netcdf(tmp_path / "ft.nc")
    with pytest.raises(ScenarioError, match=r"variable 'VHM0' has units 'ft'; accepted: m"):
        wp.load_wave_point(tmp_path / "ft.nc", 54.1, -4.8)
    # a curvilinear grid (2-D latitude/longitude), as of a rotated or tripolar product
    y2, x2 = np.meshgrid(lat, lon, indexing="ij")
    curv = xr.Dataset(
        {k: (("time", "y", "x"), ds[k].values, ds[k].attrs) for k in ("VHM0", "VTPK", "VMDR")},
        coords={
            "time": ds["time"],
            "lat": (("y", "x"), y2, {"standard_name": "latitude"}),
            "lon": (("y", "x"), x2, {"standard_name": "longitude"}),
        },
    )
    curv.to_netcdf(tmp_path / "curv.nc")
    with pytest.raises(ScenarioError, match=r"curvilinear grid .*regular or rectilinear"):
        wp.load_wave_point(tmp_path / "curv.nc", 54.1, -4.8)
    path = tmp_path / "ww3.nc"
    ww3(path)
    with xr.open_dataset(path) as w3:
        w3 = w3.load()
    w3["fp"].attrs["units"] = "s"
    w3.to_netcdf(tmp_path / "fp_s.nc")
    with pytest.raises(ScenarioError, match=r"'fp' \(peak frequency\) has units 's'; accepted: s-1, hz"):
        wp.load_wave_point(tmp_path / "fp_s.nc", 48.3, 351.0)


def test_time_interpolation_keeps_records_and_is_linear_between():
    t = np.array([0.0, 10800.0, 21600.0])
    times = wp.stage_times(t)
    assert np.array_equal(times, np.arange(0.0, 21601.0, 3600.0))
    v = np.array([[1.0], [4.0], [2.5]])
    got = wp.interpolate_time(t, v, times)[:, 0]
    np.testing.assert_allclose(got, np.interp(times, t, v[:, 0]), rtol=1e-15)
    assert got[0] == 1.0 and got[3] == 4.0 and got[6] == 2.5
    assert np.array_equal(wp.stage_times(np.array([0.0, 1800.0, 3600.0])), [0.0, 1800.0, 3600.0])
    assert np.array_equal(wp.stage_times(np.array([0.0, 9000.0])), [0.0, 3600.0, 7200.0, 9000.0])


# --- in a run: scour.forcing_location ------------------------------------------------------------------


def test_scenario_forcing_location_reads_the_point_of_a_wave_product(tmp_path):
    path = tmp_path / "cmems.nc"
    lat, lon, t, f = cmems(path)
    sec = {"forcing": "cmems.nc", "forcing_location": [54.13, -4.77], "lead_times_days": [0.0, 0.25]}
    spec = scour.parse(sec, base_dir=tmp_path)
    np.testing.assert_allclose(
        spec.forcing.hs, hourly(t, bilinear(lat, lon, f["VHM0"], 54.13, -4.77))[1], rtol=1e-12
    )
    assert spec.forcing_record["forcing_location"] == [54.13, -4.77]
    assert spec.forcing_record["forcing_file"] == str(path)
    with pytest.raises(ScenarioError, match=r"scour.forcing_location picks a point .*give that file"):
        scour.parse(
            {"storm": {"peak_hs": 2.0, "peak_tp": 8.0, "duration_h": 12.0}, "forcing_location": [54.0, -4.8]}
        )
    with pytest.raises(ScenarioError, match=r"must be \[latitude, longitude\]"):
        scour.parse(dict(sec, forcing_location=[54.0]), base_dir=tmp_path)
    with pytest.raises(ScenarioError, match=r"allowed latitude \[-90, 90\]"):
        scour.parse(dict(sec, forcing_location=[95.0, 0.0]), base_dir=tmp_path)
    # without a location the gridded file is refused, the way to give one said
    with pytest.raises(ScenarioError, match=r"scour.forcing_location"):
        scour.parse({k: v for k, v in sec.items() if k != "forcing_location"}, base_dir=tmp_path)


# --- in a map: scour.forcing_grid on the product's own grid --------------------------------------------


def test_map_reads_a_wave_product_on_its_own_grid_onto_the_environment_cells(tmp_path):
    from test_maps import SEED, _scenario, uniform_environment
    from test_maps_scour import scour_section, with_scour

    from mineburial.analyses import maps
    from mineburial.systems.mine.processes import scour_map

    env = uniform_environment()  # 2 x 2 cells at 54.50/54.51 N, 10.300/10.315 E; cell (1, 0) land
    path = tmp_path / "cmems.nc"
    lat, lon, t, f = cmems(path, lat0=54.45, lon0=10.25)
    grid = maps.read_environment(env)
    g, record = scour_map.read_forcing_grid(str(path), tmp_path, maps.map_cells(grid))
    assert record["forcing_grid_interpolation"] == wp.METHOD and record["forcing_grid_file"] == str(path)
    assert not g.wet[1, 0] and g.wet.sum() == 3
    for j, i in ((0, 0), (0, 1), (1, 1)):
        plat, plon = float(env["latitude"][j]), float(env["longitude"][i])
        cell = g.cell(j, i)
        np.testing.assert_allclose(
            cell.hs, hourly(t, bilinear(lat, lon, f["VHM0"], plat, plon))[1], rtol=1e-12
        )
        np.testing.assert_allclose(
            cell.tp, hourly(t, bilinear(lat, lon, f["VTPK"], plat, plon))[1], rtol=1e-12
        )
    # end to end: the map runs the stage on every water cell with the product's series
    sec = {k: v for k, v in scour_section(path).items() if k != "forcing"}
    ds = maps.run_map(with_scour(_scenario(), dict(sec, forcing_grid=str(path))), env, n=2, seed=SEED)
    assert ds.attrs["forcing_grid_interpolation"] == wp.METHOD
    counts = ds["scour_status_count"].values.sum(axis=0)
    assert counts[0, 0] == counts[0, 1] == counts[1, 1] == 2 and counts[1, 0] == 0


def test_map_forcing_on_the_environment_cells_is_read_as_before_bit_for_bit(tmp_path):
    from test_maps import uniform_environment

    from mineburial.analyses import maps
    from mineburial.io import forcing as fio
    from mineburial.systems.mine.processes import scour_map

    env = uniform_environment()
    cells = [[fio.storm_series(2.0, 8.0, 6.0, current=0.3), None], [None, fio.storm_series(1.0, 7.0, 6.0)]]
    cells[0][1] = cells[0][0]
    path = fio.write_gridded_netcdf(cells, env["latitude"], env["longitude"], tmp_path / "grid.nc")
    g, record = scour_map.read_forcing_grid(str(path), tmp_path, maps.map_cells(maps.read_environment(env)))
    assert "forcing_grid_interpolation" not in record
    for j, i in ((0, 0), (0, 1), (1, 1)):
        for name in ("hs", "tp", "wave_from", "current_speed", "current_to", "water_level"):
            assert np.array_equal(getattr(g.cell(j, i), name), getattr(cells[j][i], name))
