"""Forcing series (mineburial/io/forcing.py) against independent references.

References: the arrays each test constructs and writes itself (CSV text written here, NetCDF
written by xarray with CF time units); exact unit factors (1 knot = 1852/3600 m/s); the spectral
moments of the JONSWAP spectrum integrated here with scipy's quad; the closed forms of the storm
shapes; a direct lookup of the piecewise-constant series for the window; and, end to end, the
Shields parameter at the storm's peak composed here from the printed formulas (Swart 1974,
Soulsby 1997) around the spectral orbital velocity tested in tests/test_scour.py.
"""

import math
import os
from importlib import resources

import numpy as np
import pytest
import xarray as xr
from scipy.integrate import quad

from mineburial.errors import ScenarioError
from mineburial.io import forcing as F
from mineburial.kernels.mine import scour as S

START = np.datetime64("2003-01-15T00:00:00", "ns")
N = 30
HOUR = 3600.0
#: a marker written into every test file: no message may quote the file's content
MARKER = "CONTENT-MARKER-7f3a"


def reference_arrays(n=N):
    """The arrays the round trips must give back (SI units, degrees, hourly from START)."""
    k = np.arange(n, dtype=float)
    return {
        "time": k * HOUR,
        "hs": 0.5 + 1.5 * np.sin(k / 7.0) ** 2,
        "tp": 6.0 + 0.25 * k,
        "wave_from": (200.0 + 5.0 * k) % 360.0,
        "current_speed": 0.05 + 0.01 * k,
        "current_to": (10.0 * k) % 360.0,
        "water_level": 0.4 * np.sin(2 * math.pi * k / 12.42),
    }


def iso(seconds):
    return np.datetime_as_string(START + np.timedelta64(int(seconds), "s"), unit="s") + "Z"


def csv_text(ref, columns=None, time="iso"):
    """CSV text written here (not by the module): ``columns`` maps a header name to a column."""
    cols = columns or {
        "hs_m": ref["hs"],
        "tp_s": ref["tp"],
        "wave_dir_deg": ref["wave_from"],
        "current_speed_m_s": ref["current_speed"],
        "current_dir_deg": ref["current_to"],
        "water_level_m": ref["water_level"],
    }
    tname = "time" if time == "iso" else "time_s"
    lines = [f"# {MARKER}", ",".join([tname, *cols])]
    for i, t in enumerate(ref["time"]):
        stamp = iso(t) if time == "iso" else repr(float(t) + 1000.0)
        lines.append(",".join([stamp] + [repr(float(c[i])) for c in cols.values()]))
    return "\n".join(lines) + "\n"


def write(tmp_path, text, name="series.csv"):
    path = tmp_path / name
    path.write_text(text)
    return path


def dataset(ref, **over):
    """A CF dataset with standard names; xarray encodes time as hours since START."""

    def var(values, std, units):
        return ("time", np.asarray(values, dtype=float), {"standard_name": std, "units": units})

    data = {
        "VHM0": var(ref["hs"], "sea_surface_wave_significant_height", "m"),
        "VTPK": var(ref["tp"], "sea_surface_wave_period_at_variance_spectral_density_maximum", "s"),
        "VMDR": var(ref["wave_from"], "sea_surface_wave_from_direction", "degree"),
        "speed": var(ref["current_speed"], "sea_water_speed", "m s-1"),
        "cdir": var(ref["current_to"], "direction_of_sea_water_velocity", "degree"),
        "zeta": var(ref["water_level"], "sea_surface_height_above_mean_sea_level", "m"),
    }
    data.update(over)
    data = {k: v for k, v in data.items() if v is not None}
    times = START + (ref["time"] * 1e9).astype("timedelta64[ns]")
    ds = xr.Dataset(data, coords={"time": times})
    ds.attrs["comment"] = MARKER
    return ds


def to_nc(ds, tmp_path, name="series.nc"):
    path = tmp_path / name
    enc = {"time": {"units": "hours since 2003-01-15 00:00:00", "calendar": "standard", "dtype": "f8"}}
    if "time" in ds.variables and not np.issubdtype(ds["time"].dtype, np.datetime64):
        enc = {}
    ds.to_netcdf(path, encoding=enc)
    return path


def assert_matches(forcing, ref, rtol=1e-12):
    for name in ("time", "hs", "tp", "current_speed", "water_level"):
        np.testing.assert_allclose(getattr(forcing, name), ref[name], rtol=rtol, atol=1e-12, err_msg=name)
    for name in ("wave_from", "current_to"):  # directions compared on the circle
        diff = np.angle(np.exp(1j * np.radians(getattr(forcing, name) - ref[name])))
        np.testing.assert_allclose(diff, 0.0, atol=1e-9, err_msg=name)


# --- round trips and units -----------------------------------------------------------------------


def test_csv_round_trip_iso_times(tmp_path):
    ref = reference_arrays()
    f = F.load_csv(write(tmp_path, csv_text(ref)))
    assert_matches(f, ref)
    assert f.start == START
    assert f.iso(5) == "2003-01-15T05:00:00Z"


def test_csv_round_trip_seconds_and_units(tmp_path):
    ref = reference_arrays()
    knot = 1852.0 / 3600.0  # the international knot, exactly
    cols = {
        "hs_cm": ref["hs"] * 100.0,
        "tp_s": ref["tp"],
        "wave_dir_rad": np.radians(ref["wave_from"]),
        "current_speed_kn": ref["current_speed"] / knot,
        "current_dir_deg": ref["current_to"],
    }
    f = F.load_csv(write(tmp_path, csv_text(ref, cols, time="seconds")))
    assert f.start is None  # relative seconds: no absolute start
    assert_matches(f, {**ref, "water_level": np.zeros(N)})
    assert f.iso(2) == "t = 7200 s"


def test_netcdf_round_trip_cf_hours_and_standard_names(tmp_path):
    ref = reference_arrays()
    path = to_nc(dataset(ref), tmp_path)
    with xr.open_dataset(path, decode_times=False) as raw:  # the file holds CF hours
        assert raw["time"].attrs["units"].startswith("hours since")
        np.testing.assert_array_equal(raw["time"].values, np.arange(N))
    f = F.load_netcdf(path)
    assert_matches(f, ref)
    assert f.start == START


def test_netcdf_units_cm_s_knots_radians_and_velocity_components(tmp_path):
    ref = reference_arrays()
    to = np.radians(ref["current_to"])
    u, v = ref["current_speed"] * np.sin(to), ref["current_speed"] * np.cos(to)  # east, north
    ds = dataset(
        ref,
        speed=None,
        cdir=None,
        VMDR=(
            "time",
            np.radians(ref["wave_from"]),
            {"standard_name": "sea_surface_wave_from_direction", "units": "rad"},
        ),
        uo=("time", u * 100.0, {"standard_name": "eastward_sea_water_velocity", "units": "cm s-1"}),
        vo=(
            "time",
            v / (1852.0 / 3600.0),
            {"standard_name": "northward_sea_water_velocity", "units": "knots"},
        ),
    )
    assert_matches(F.load_netcdf(to_nc(ds, tmp_path)), ref, rtol=1e-10)


def test_variables_by_documented_names_and_mean_period(tmp_path):
    ref = reference_arrays()
    ds = dataset(ref)
    ds = ds.rename({"VHM0": "hs", "VMDR": "wave_dir", "speed": "current_speed", "cdir": "current_dir"})
    for name in ("hs", "wave_dir", "current_speed", "current_dir"):
        del ds[name].attrs["standard_name"]
    tm02 = ref["tp"] * moment_ratios()["tm02"]
    ds["VTPK"] = ("time", tm02, {"units": "s"})
    ds = ds.rename({"VTPK": "tm02"})
    f = F.load_netcdf(to_nc(ds, tmp_path))
    assert_matches(f, ref, rtol=2e-5)  # PERIOD_RATIOS holds 5 digits


def moment_ratios():
    """Tm01/Tp, Tm02/Tp and Tm-10/Tp of a JONSWAP spectrum (gamma 3.3, sigma 0.07/0.09) from its
    moments m_n = int x^n S(x) dx over (0, inf), x = f/fp, integrated here with quad."""

    def shape(x):
        sig = 0.07 if x <= 1.0 else 0.09
        return x**-5 * math.exp(-1.25 * x**-4) * 3.3 ** math.exp(-((x - 1) ** 2) / (2 * sig**2))

    def m(n):
        return sum(
            quad(lambda x: x**n * shape(x), a, b, limit=200)[0] for a, b in ((0.05, 1), (1, 3), (3, math.inf))
        )

    return {"tp": 1.0, "tm01": m(0) / m(1), "tm02": math.sqrt(m(0) / m(2)), "tm_10": m(-1) / m(0)}


def test_period_ratios_are_the_jonswap_moments():
    ratios = moment_ratios()
    for key, value in F.PERIOD_RATIOS.items():
        assert value == pytest.approx(ratios[key], rel=1e-5), key
    # DNV-RP-C205 (2010) sec. 3.5.5 fits at gamma = 3.3 agree to 0.1 %
    g = 3.3
    assert ratios["tm01"] == pytest.approx(0.7303 + 0.04936 * g - 0.006556 * g**2 + 0.000361 * g**3, rel=1e-3)
    assert ratios["tm02"] == pytest.approx(0.6673 + 0.05037 * g - 0.00623 * g**2 + 0.0003341 * g**3, rel=1e-3)


def test_kernel_arrays_directions_towards_and_depth(tmp_path):
    ref = reference_arrays()
    f = F.load_csv(write(tmp_path, csv_text(ref)))
    t, hs, tp, wdir, uc, cdir, h = f.kernel_arrays(12.0)
    np.testing.assert_allclose(h, 12.0 + ref["water_level"], rtol=1e-14)
    # waves from 200 deg travel towards 20 deg
    assert wdir[0] == pytest.approx(math.radians(20.0), rel=1e-14)
    assert cdir[3] == pytest.approx(math.radians(30.0), rel=1e-14)
    assert all(a.dtype == np.float64 and a.flags.c_contiguous for a in (t, hs, tp, wdir, uc, cdir, h))
    with pytest.raises(ScenarioError, match=r"water_level.*2003-01-15T\d\d:00:00Z.*allowed: > -0.3 m"):
        f.kernel_arrays(0.3)


# --- bad forcing: one line naming the file, the variable, the time and the allowed range --------------


def bad_csv(column, index, value):
    ref = reference_arrays()
    ref[column] = ref[column].copy()
    ref[column][index] = value
    return csv_text(ref)


@pytest.mark.parametrize(
    "column, index, value, variable, allowed",
    [
        ("hs", 5, -0.2, "hs_m", "[0, 30] m"),
        ("hs", 6, math.nan, "hs_m", "[0, 30] m"),
        ("hs", 7, 45.0, "hs_m", "[0, 30] m"),
        ("tp", 8, 0.0, "tp_s", "(0, 40] s"),
        ("tp", 9, -3.0, "tp_s", "(0, 40] s"),
        ("wave_from", 10, 400.0, "wave_dir_deg", "[-360, 360] deg"),
        ("current_speed", 11, math.inf, "current_speed_m_s", "[0, 10] m/s"),
        ("current_to", 12, math.nan, "current_dir_deg", "[-360, 360] deg"),
        ("water_level", 13, 25.0, "water_level_m", "[-20, 20] m"),
    ],
)
def test_bad_values_name_file_variable_time_and_range(tmp_path, column, index, value, variable, allowed):
    path = write(tmp_path, bad_csv(column, index, value), "bad_values.csv")
    with pytest.raises(ScenarioError) as info:
        F.load_csv(path)
    msg = str(info.value)
    assert "bad_values.csv" in msg and f"'{variable}'" in msg and iso(index * HOUR) in msg
    assert allowed in msg
    assert "\n" not in msg and MARKER not in msg


@pytest.mark.parametrize(
    "times, expected",
    [
        ([0, 1, 2, 2, 3, 4], ["repeats 2003-01-15T02:00:00Z", "strictly increasing"]),
        ([0, 1, 3, 2, 4, 5], ["goes back from 2003-01-15T03:00:00Z to 2003-01-15T02:00:00Z"]),
        (
            [0, 1, 2, 3, 6, 7, 8],
            ["gap of 10800 s from 2003-01-15T03:00:00Z", "2.5 x the median step of 3600 s"],
        ),
    ],
)
def test_bad_times_name_the_time(tmp_path, times, expected):
    ref = {k: v[: len(times)] for k, v in reference_arrays().items()}
    ref["time"] = np.array(times, dtype=float) * HOUR
    path = write(tmp_path, csv_text(ref), "bad_times.csv")
    with pytest.raises(ScenarioError) as info:
        F.load_csv(path)
    msg = str(info.value)
    assert "bad_times.csv" in msg and "'time'" in msg and "\n" not in msg
    for part in expected:
        assert part in msg
    # the same times in a CF NetCDF file give the same message
    nc_msg = str(
        pytest.raises(ScenarioError, F.load_netcdf, to_nc(dataset(ref), tmp_path, "bad_times.nc")).value
    )
    for part in expected:
        assert part in nc_msg


def test_one_missing_record_is_not_a_gap_but_max_gap_s_can_refuse_it(tmp_path):
    ref = reference_arrays()
    keep = np.ones(N, bool)
    keep[10] = False  # a step of 2 h in an hourly series
    path = write(tmp_path, csv_text({k: v[keep] for k, v in ref.items()}), "holed.csv")
    f = F.load_csv(path)
    assert len(f) == N - 1 and f.time[10] == 11 * HOUR
    with pytest.raises(
        ScenarioError, match=r"holed\.csv.*'time'.*gap of 7200 s from 2003-01-15T09:00:00Z.*max_gap_s"
    ):
        F.load_csv(path, max_gap_s=5400.0)


def test_empty_and_single_record_series(tmp_path):
    ref = reference_arrays()
    header_only = csv_text(ref).splitlines()[:2]
    with pytest.raises(ScenarioError, match=r"empty\.csv.*'time'.*no records"):
        F.load_csv(write(tmp_path, "\n".join(header_only) + "\n", "empty.csv"))
    one = csv_text({k: v[:1] for k, v in ref.items()})
    with pytest.raises(ScenarioError, match=r"one\.csv.*only one record, at 2003-01-15T00:00:00Z"):
        F.load_csv(write(tmp_path, one, "one.csv"))


def test_missing_variables_and_units(tmp_path):
    ref = reference_arrays()
    cases = [
        (dataset(ref, speed=None), ["missing variable", "current"]),
        (dataset(ref, VTPK=None), ["missing variable", "wave period"]),
        (
            dataset(ref, VHM0=("time", ref["hs"], {"standard_name": "sea_surface_wave_significant_height"})),
            ["'VHM0'", "no units", "accepted: m"],
        ),
        (
            dataset(
                ref,
                VHM0=(
                    "time",
                    ref["hs"],
                    {"standard_name": "sea_surface_wave_significant_height", "units": "ft"},
                ),
            ),
            ["'VHM0'", "units 'ft'", "accepted: m"],
        ),
    ]
    for k, (ds, parts) in enumerate(cases):
        path = to_nc(ds, tmp_path, f"case{k}.nc")
        msg = str(pytest.raises(ScenarioError, F.load_netcdf, path).value)
        assert f"case{k}.nc" in msg and "\n" not in msg and MARKER not in msg
        for part in parts:
            assert part in msg, (k, msg)
    with pytest.raises(ScenarioError, match=r"units\.csv.*column 'hs_ft'.*accepted: hs_m, hs_cm"):
        F.load_csv(write(tmp_path, csv_text(ref).replace("hs_m", "hs_ft"), "units.csv"))
    with pytest.raises(ScenarioError, match=r"nowave\.csv.*missing variable.*wave direction"):
        F.load_csv(write(tmp_path, csv_text(ref).replace("wave_dir_deg", "other"), "nowave.csv"))


def test_netcdf_time_checks(tmp_path):
    ref = reference_arrays()
    ds = dataset(ref).assign_coords(time=("time", np.arange(N, dtype=float), {}))  # numbers, no units
    msg = str(pytest.raises(ScenarioError, F.load_netcdf, to_nc(ds, tmp_path, "nounits.nc")).value)
    assert "nounits.nc" in msg and "'time'" in msg and "since" in msg
    ds = dataset(ref).assign_coords(
        time=("time", np.arange(N, dtype=float), {"units": "hours since 2003-01-15", "calendar": "360_day"})
    )
    with pytest.raises(ScenarioError, match=r"cal\.nc.*'time'.*calendar '360_day'"):
        F.load_netcdf(to_nc(ds, tmp_path, "cal.nc"))
    # a missing value (fill value) in Hs names the time
    hs = ref["hs"].copy()
    hs[4] = np.nan
    ds = dataset(
        ref, VHM0=("time", hs, {"standard_name": "sea_surface_wave_significant_height", "units": "m"})
    )
    with pytest.raises(
        ScenarioError, match=r"fill\.nc.*'VHM0' is missing \(NaN\) at 2003-01-15T04:00:00Z.*\[0, 30\] m"
    ):
        F.load_netcdf(to_nc(ds, tmp_path, "fill.nc"))


def test_not_a_regular_file_size_limit_and_type(tmp_path):
    fifo = tmp_path / "pipe.csv"
    os.mkfifo(fifo)  # opening it for reading would block until a writer came
    with pytest.raises(ScenarioError, match=r"pipe\.csv.*not a regular file"):
        F.load_csv(fifo)
    with pytest.raises(ScenarioError, match=r"dir\.nc.*not a regular file"):
        (tmp_path / "dir.nc").mkdir()
        F.load_netcdf(tmp_path / "dir.nc")
    path = write(tmp_path, csv_text(reference_arrays()), "big.csv")
    with pytest.raises(ScenarioError, match=r"big\.csv.*at most 100 bytes"):
        F.load_csv(path, max_bytes=100)
    with pytest.raises(ScenarioError, match=r"absent\.csv.*cannot read"):
        F.load_forcing(tmp_path / "absent.csv")
    with pytest.raises(ScenarioError, match=r"x\.txt.*unknown file type"):
        F.load_forcing("x.txt")
    notnc = write(tmp_path, "not a netcdf file " + MARKER, "text.nc")
    msg = str(pytest.raises(ScenarioError, F.load_netcdf, notnc).value)
    assert "text.nc" in msg and "cannot open as NetCDF" in msg and MARKER not in msg


# --- gridded forcing ------------------------------------------------------------------------------------


def gridded(ref, ny=2, nx=3):
    """(time, y, x) fields: cell (j, i) holds the reference series scaled by 1 + 0.1 (j + i);
    cell (1, 0) is land (all NaN)."""
    scale = 1.0 + 0.1 * (np.arange(ny)[:, None] + np.arange(nx)[None, :])
    out = {}
    for name in ("hs", "tp", "current_speed"):
        field = ref[name][:, None, None] * scale[None]
        field[:, 1, 0] = np.nan
        out[name] = field
    for name in ("wave_from", "current_to"):
        field = np.repeat(np.repeat(ref[name][:, None, None], ny, 1), nx, 2)
        field[:, 1, 0] = np.nan
        out[name] = field
    return out, scale


def test_gridded_round_trip_cells_and_dry_cell(tmp_path):
    ref = reference_arrays()
    fields, scale = gridded(ref)
    dims = ("time", "y", "x")
    ds = xr.Dataset(
        {
            "hs": (dims, fields["hs"], {"units": "m"}),
            "tp": (dims, fields["tp"], {"units": "s"}),
            "wave_dir": (dims, fields["wave_from"], {"units": "degree"}),
            "current_speed": (dims, fields["current_speed"] * 100.0, {"units": "cm/s"}),
            "current_dir": (dims, fields["current_to"], {"units": "degree"}),
        },
        coords={
            "time": START + (ref["time"] * 1e9).astype("timedelta64[ns]"),
            "y": [10.0, 20.0],
            "x": [1.0, 2.0, 3.0],
        },
    )
    g = F.load_gridded_netcdf(to_nc(ds, tmp_path, "grid.nc"))
    assert g.shape == (2, 3) and g.dims == ("y", "x")
    np.testing.assert_array_equal(g.wet, [[True, True, True], [False, True, True]])
    np.testing.assert_array_equal(g.y, [10.0, 20.0])
    for j, i in ((0, 0), (0, 2), (1, 2)):
        cell = g.cell(j, i)
        expected = {**ref, "water_level": np.zeros(N)}
        for name in ("hs", "tp", "current_speed"):
            expected[name] = ref[name] * scale[j, i]
        assert_matches(cell, expected)
    with pytest.raises(ScenarioError, match=r"grid\.nc.*cell \(y=1, x=0\) is dry"):
        g.cell(1, 0)
    dry = ds.copy(deep=True)
    dry["hs"][:] = np.nan
    with pytest.raises(ScenarioError, match=r"dry\.nc.*'hs' is missing \(NaN\) in every cell"):
        F.load_gridded_netcdf(to_nc(dry, tmp_path, "dry.nc"))
    # a bad value in one wet cell names the variable, the time and the cell
    bad = ds.copy(deep=True)
    bad["tp"][7, 1, 2] = 0.0
    with pytest.raises(
        ScenarioError,
        match=r"badgrid\.nc.*'tp' = 0 s at 2003-01-15T07:00:00Z in cell \(y=1, x=2\).*\(0, 40\] s",
    ):
        F.load_gridded_netcdf(to_nc(bad, tmp_path, "badgrid.nc"))


# --- the parametrised storm ----------------------------------------------------------------------------


@pytest.mark.parametrize("ramp, third", [("cos2", 0.75), ("triangular", 2.0 / 3.0)])
def test_storm_peak_duration_symmetry_and_area(ramp, third):
    hp, hb, tp, dur = 3.0, 0.5, 12.0, 36.0
    f = F.storm_series(
        hp, tp, dur, ramp=ramp, current=0.6, background_hs=hb, step_h=1.0, total_h=96.0, peak_h=40.0
    )
    hours = f.time / HOUR
    assert len(f) == 97 and f.start == np.datetime64("2000-01-01T00:00:00", "ns")
    assert f.hs.max() == hp and hours[np.argmax(f.hs)] == 40.0  # the peak
    outside = np.abs(hours - 40.0) >= dur / 2  # the duration: background outside it, above inside
    assert np.all(f.hs[outside] == hb) and np.all(f.hs[~outside] > hb)
    k = np.arange(1, 40)
    np.testing.assert_allclose(f.hs[40 - k], f.hs[40 + k], rtol=1e-14)  # symmetry about the peak
    # at tau = 1/3 the shape is cos^2(pi/6) = 3/4 (cos2) or 1 - 1/3 (triangle)
    assert f.hs[40 + 6] == pytest.approx(hb + (hp - hb) * third, rel=1e-14)
    # both shapes have the area duration/2 (trapezoid rule, exact for the triangle's grid)
    assert np.trapezoid(f.hs - hb, hours) == pytest.approx((hp - hb) * dur / 2, rel=1e-6)
    np.testing.assert_allclose(f.tp, tp * np.sqrt(f.hs / hp), rtol=1e-14)  # constant steepness
    assert f.current_speed.max() == 0.6 and f.current_speed[0] == 0.0
    with pytest.raises(ScenarioError, match=r"storm ramp 'box'.*cos2, triangular"):
        F.storm_series(hp, tp, dur, ramp="box")
    with pytest.raises(ScenarioError, match=r"background_hs"):
        F.storm_series(1.0, tp, dur, background_hs=2.0)


def example_path():
    return resources.files("mineburial") / "data" / "forcing" / "storm_example.csv"


def test_example_storm_file_is_the_documented_storm():
    f = F.load_csv(example_path())
    assert os.path.getsize(example_path()) < 20_000
    kw = dict(peak_hs=2.5, peak_tp=10.0, duration_h=48.0, current=0.4, background_current=0.05)
    ref = F.storm_series(**kw, background_hs=0.4, start="2003-01-15T00:00:00Z", total_h=96.0, surge=0.3)
    assert len(f) == 97 and f.start == np.datetime64("2003-01-15T00:00:00", "ns")
    assert f.hs.max() == 2.5 and f.iso(int(np.argmax(f.hs))) == "2003-01-17T00:00:00Z"
    for name in ("time", "hs", "tp", "current_speed", "water_level"):
        np.testing.assert_allclose(getattr(f, name), getattr(ref, name), rtol=1e-8, atol=1e-12)
    np.testing.assert_array_equal(f.wave_from, 270.0)
    np.testing.assert_array_equal(f.current_to, 0.0)


# --- forcing uncertainty helpers ----------------------------------------------------------------------


def test_scale_hs():
    f = F.storm_series(2.0, 10.0, 24.0)
    g = F.scale_hs(f, 1.25)
    np.testing.assert_array_equal(g.hs, 1.25 * f.hs)
    np.testing.assert_array_equal(g.tp, f.tp)
    for bad in (0.0, -1.0, math.nan):
        with pytest.raises(ScenarioError, match="scale factor"):
            F.scale_hs(f, bad)
    # the first record (in time) beyond the range is named: 20 x Hs passes 30 m first at 20 h
    first = int(np.argmax(20.0 * f.hs > 30.0))
    assert first == 20
    with pytest.raises(ScenarioError, match=r"'hs' = 31.5 m at 2000-01-01T20:00:00Z; allowed: \[0, 30\] m"):
        F.scale_hs(f, 20.0)


def test_window_is_the_series_piece_for_piece():
    ref = reference_arrays()
    f = F.Forcing(start=START, **ref)
    offset, length = 5.5 * HOUR, 10.25 * HOUR
    w = F.window(f, offset, length)
    assert w.time[0] == 0.0 and w.time[-1] == length
    assert w.start == START + np.timedelta64(int(offset * 1e9), "ns")
    # the record in effect at any time inside the window is the original's at offset + that time
    probe = np.random.default_rng(4).uniform(0.0, length, 500)
    i_w = np.searchsorted(w.time, probe, side="right") - 1
    i_f = np.array([max(i for i in range(N) if ref["time"][i] <= offset + p) for p in probe])
    for name in ("hs", "tp", "wave_from", "current_speed", "current_to", "water_level"):
        np.testing.assert_array_equal(getattr(w, name)[i_w], ref[name][i_f])
    assert len(F.window(f, 3 * HOUR, 2 * HOUR)) == 3  # on record boundaries: records 3, 4 and the end
    with pytest.raises(
        ScenarioError, match=r"window from 2003-01-16T00:00:00Z.*ends after .*2003-01-16T05:00:00Z"
    ):
        F.window(f, 24 * HOUR, 6 * HOUR)
    with pytest.raises(ScenarioError, match="offset >= 0"):
        F.window(f, -1.0, HOUR)


# --- end to end: the example storm through the scour stage ---------------------------------------------


def test_example_storm_through_the_scour_stage():
    depth, d50, diameter = 12.0, 2e-4, 0.53
    g, rho, rho_s, nu = 9.81, 1027.0, 2650.0, 1.36e-6
    f = F.load_csv(example_path())
    arrays = f.kernel_arrays(depth)
    table = S.build_orbital_table()
    p = S.default_parameters(d50=d50, diameter=diameter, b0=0.02)
    leads = np.arange(0.0, f.duration_s + 1.0, 6 * HOUR)
    out_b, out_t = np.empty(leads.size), np.empty(2)
    status, _, theta_max = S.scour_stage(p, *arrays, table, leads, np.array([0.25, 0.5]), out_b, out_t)
    assert status == S.SCOUR_OK
    assert np.all(np.isfinite(out_b)) and out_b[0] == 0.02
    assert np.all(np.diff(out_b) >= 0.0) and np.all(out_b <= diameter)

    # the Shields parameter at the peak composed here: waves from 270 deg, current towards 0 deg
    # cross at 90 deg, so tau_max = sqrt(tau_m^2 + tau_w^2) (Soulsby 1997)
    k = int(np.argmax(f.hs))
    h = depth + f.water_level[k]
    ub, tb = S.orbital_spectral(f.hs[k], f.tp[k], h, g, table)
    a_ks = ub * tb / (2 * math.pi) / (2.5 * d50)
    fw = 0.00251 * math.exp(5.21 * a_ks**-0.19)  # Swart (1974)
    tau_w = 0.5 * rho * fw * ub**2
    tau_c = rho * (0.40 / (math.log(h / (d50 / 12)) - 1)) ** 2 * f.current_speed[k] ** 2
    tau_m = tau_c * (1 + 1.2 * (tau_w / (tau_c + tau_w)) ** 3.2)
    theta_peak = math.hypot(tau_m, tau_w) / (rho * (rho_s / rho - 1) * g * d50)
    dstar = d50 * (g * (rho_s / rho - 1) / nu**2) ** (1 / 3)
    theta_cr = 0.30 / (1 + 1.2 * dstar) + 0.055 * (1 - math.exp(-0.020 * dstar))
    assert theta_peak > 2 * theta_cr
    assert theta_max == pytest.approx(theta_peak, rel=1e-9)  # the peak is the stage's largest theta

    # before the storm (background Hs 0.4 m, Tp 4 s in 12 m) the bed is below threshold: no growth;
    # the storm (24 h to 72 h) buries; after it nothing changes
    hours = leads / HOUR
    assert np.all(out_b[hours <= 24.0] == 0.02)
    assert out_b[hours == 48.0][0] > 0.02 and out_b[hours == 72.0][0] > out_b[hours == 48.0][0]
    assert np.all(out_b[hours >= 72.0] == out_b[hours == 72.0][0])
    assert 24 * HOUR < out_t[0] < 72 * HOUR


def test_kernel_arrays_refuses_a_depth_below_the_stages_floor_not_only_a_dry_bed(tmp_path):
    """Forcing validation checked h > 0 only; a depth above 0 but below depth_floor(d50) = 10 ks
    passed it and then made every drop's stage return invalid_forcing (issue 20, item 3)."""
    ref = reference_arrays()
    f = F.load_csv(write(tmp_path, csv_text(ref)))
    d50 = 2.0e-3  # floor = 10 * 2.5 * d50 = 0.05 m
    low = float(np.min(f.water_level))
    depth = -low + 0.03  # the shallowest record has h = 0.03 m: wet, but below the floor
    with pytest.raises(ScenarioError, match=r"water_level.*depth_floor\(d50\) = 0.05 m.*allowed: >= "):
        f.kernel_arrays(depth, d50)
    f.kernel_arrays(depth)  # without a grain size only a dry bed is refused
    h = f.kernel_arrays(-low + 0.06, d50)[-1]  # 1 cm above the floor
    assert np.min(h) == pytest.approx(0.06, abs=1e-12)
