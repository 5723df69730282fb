"""The forcing reader contract (issue 35, item 4): a CSV row with more (or fewer) fields than
the header is refused naming its line, before any drop runs (was: read shifted, the current
speed 0 and speeds read as directions); and property-based fuzzing of the CSV and NetCDF
readers with hypothesis: whatever the table, the reader returns the values written here or
refuses in a ScenarioError, nothing else.

Independent references: the CSV text and the NetCDF variables written here; the values the
fuzzed reader must return are the numbers the test put in each cell (floats written with
``repr``, read back exactly), in SI units by the exact factors of the header's unit suffix.
"""

import csv
import math

import numpy as np
import pytest
import xarray as xr
from conftest import scenario_dict
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from mineburial.cli import main
from mineburial.ensembles import engine
from mineburial.errors import ScenarioError
from mineburial.io import forcing as F
from mineburial.io.inputs import numbered_csv
from mineburial.systems.mine import batch
from mineburial.systems.mine.config import dumps_toml
from mineburial.systems.mine.sediment_profiles import load_csv as load_core

HEADER = "time_s,hs_m,tp_s,wave_dir_deg,current_speed_m_s,current_dir_deg"


def rows(n=6, extra=None):
    """``n`` hourly rows; with ``extra`` one more field after the first (a quality flag, as in
    the audit's file) in every row from the third on."""
    out = []
    for k in range(n):
        cells = [f"{3600.0 * k}", "1.0", "8.0", "270.0", f"{0.5 + 0.1 * k}", "45.0"]
        if extra is not None and k >= 2:
            cells.insert(1, extra)
        out.append(",".join(cells))
    return out


def test_a_row_with_more_fields_than_the_header_is_refused_naming_its_line(tmp_path):
    path = tmp_path / "f.csv"
    path.write_text("\n".join(["# a comment line", HEADER, *rows(extra="1")]) + "\n")
    with pytest.raises(ScenarioError) as caught:
        F.load_csv(path)
    message = str(caught.value)
    # the third data row is the file's line 5 (after the comment and the header)
    assert "line 5 has 7 fields but the header (line 2) has 6" in message and str(path) in message


def test_a_row_with_fewer_fields_than_the_header_is_refused_naming_its_line(tmp_path):
    path = tmp_path / "f.csv"
    lines = [HEADER, *rows()]
    lines[4] = lines[4].rsplit(",", 1)[0]
    path.write_text("\n".join(lines) + "\n")
    with pytest.raises(ScenarioError, match=r"line 5 has 5 fields but the header \(line 1\) has 6"):
        F.load_csv(path)


def test_a_core_csv_row_wider_than_its_header_is_refused(tmp_path):
    """The same contract for the other table read by header position (a sediment core)."""
    path = tmp_path / "core.csv"
    path.write_text("depth_m,density_kg_m3,strength_pa\n0.0,1500.0,2000.0\n0.5,9,1600.0,4000.0\n")
    with pytest.raises(ScenarioError, match=r"line 3 has 4 fields but the header \(line 1\) has 3"):
        load_core(path)


def test_the_run_refuses_a_shifted_forcing_before_computing(tmp_path, capsys, monkeypatch):
    """End to end: ``run`` of a scenario whose [scour] forcing has shifted rows is one line,
    exit 2, and no drop is computed."""

    def fail(*a, **kw):
        raise AssertionError("a drop was computed before the forcing was checked")

    monkeypatch.setattr(batch, "run_batch", fail)
    monkeypatch.setattr(engine, "compute_chunk", fail)
    forcing = tmp_path / "f.csv"
    forcing.write_text("\n".join([HEADER, *rows(extra="1")]) + "\n")
    d = scenario_dict(
        environment={"water_depth": 3.0},
        release={"position": [0.0, 0.0, 1.0]},
        sediment={"class": "sand"},
        numerics={"t_max": 3.0},
    )
    d["ensemble"] = {"n": 4}
    d["scour"] = {"forcing": str(forcing), "lead_times_days": [0.0, 0.1]}
    scen = tmp_path / "s.toml"
    scen.write_text(dumps_toml(d))
    out = tmp_path / "out.nc"
    assert main(["run", str(scen), "--quiet", "-o", str(out)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "line 4 has 7 fields but the header (line 1) has 6" in err, err
    assert not out.exists()


# --- fuzzing ------------------------------------------------------------------------------------------
COLUMNS = {  # header name -> (quantity key of the Forcing, factor to SI)
    "hs_m": ("hs", 1.0),
    "hs_cm": ("hs", 0.01),
    "tp_s": ("tp", 1.0),
    "wave_dir_deg": ("wave_from", 1.0),
    "current_speed_m_s": ("current_speed", 1.0),
    "current_speed_kn": ("current_speed", 1852.0 / 3600.0),
    "current_dir_deg": ("current_to", 1.0),
    "water_level_m": ("water_level", 1.0),
}
REQUIRED = ("hs", "tp", "wave_from", "current_speed", "current_to")
RANGES = {"hs": (0.0, 5.0), "tp": (2.0, 20.0), "wave_from": (0.0, 359.0), "current_speed": (0.0, 2.0)}
RANGES.update(current_to=(0.0, 359.0), water_level=(-2.0, 2.0))
BAD_CELLS = ["", "nan", "x", "1e400", "-1", '"1,2"', "inf"]


@st.composite
def tables(draw):
    """A header with a column of each required quantity (its unit drawn) and maybe the water
    level, in a drawn order, and 2-8 hourly rows of plausible numbers; with probability 1/2
    one row is spoilt: a field more or fewer, or a cell that is no plausible number."""
    keys = list(REQUIRED) + (["water_level"] if draw(st.booleans()) else [])
    names = [draw(st.sampled_from(sorted(c for c in COLUMNS if COLUMNS[c][0] == k))) for k in keys]
    names = draw(st.permutations(names))
    n = draw(st.integers(2, 8))
    body = []
    for k in range(n):
        cells = [repr(3600.0 * k)]
        for name in names:
            lo, hi = RANGES[COLUMNS[name][0]]
            cells.append(repr(draw(st.floats(lo, hi, allow_nan=False)) / COLUMNS[name][1]))
        body.append(cells)
    spoil = draw(st.sampled_from(["none", "none", "none", "wider", "narrower", "cell"]))
    k = draw(st.integers(0, n - 1))
    if spoil == "wider":
        body[k].insert(draw(st.integers(1, len(body[k]))), repr(draw(st.floats(0.0, 5.0))))
    elif spoil == "narrower":
        del body[k][draw(st.integers(1, len(body[k]) - 1))]
    elif spoil == "cell":
        body[k][draw(st.integers(1, len(body[k]) - 1))] = draw(st.sampled_from(BAD_CELLS))
    return ["time_s", *names], body


def expected(header, body):
    """What the reader must return, computed here: None when it must refuse."""
    if any(len(r) != len(header) for r in body):
        return None
    keys = {COLUMNS[h][0]: (j, COLUMNS[h][1]) for j, h in enumerate(header) if h in COLUMNS}
    if not set(REQUIRED) <= keys.keys():
        return None
    out = {}
    for key, (j, factor) in keys.items():
        try:
            values = [float(r[j]) for r in body]
        except ValueError:
            return None
        out[key] = np.array(values) * factor
    return out


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(table=tables())
def test_fuzzed_csv_forcing_is_read_as_written_or_refused(tmp_path, table):
    header, body = table
    path = tmp_path / "fuzz.csv"
    with open(path, "w", newline="") as fh:
        fh.write(",".join(header) + "\n" + "\n".join(",".join(r) for r in body) + "\n")
    want = expected(header, list(csv.reader(",".join(r) for r in body)))
    try:
        got = F.load_csv(path)
    except ScenarioError as exc:
        assert "Traceback" not in str(exc) and str(path) in str(exc)
        return
    # accepted: the table must have been well formed, and its values read unshifted
    assert want is not None, (header, body)
    for key, values in want.items():
        np.testing.assert_allclose(getattr(got, key), values, rtol=1e-12, atol=0.0, err_msg=key)


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(
    n=st.integers(1, 6),
    hs=st.floats(0.0, 5.0),
    dtype=st.sampled_from(["float64", "float32", "int32", "U3"]),
    units=st.sampled_from(["m", "cm", "furlong", None]),
    time_units=st.sampled_from(["seconds since 2003-01-15", "hours since 2003-01-15 00:00", "days", None]),
)
def test_fuzzed_netcdf_forcing_is_read_as_written_or_refused(tmp_path, n, hs, dtype, units, time_units):
    """Variables of other types, unknown units and time units: read as written or refused."""
    t = np.arange(n, dtype=float)
    hs_values = np.full(n, hs).astype(dtype) if dtype != "U3" else np.full(n, "abc")
    data = {
        "hs": ("time", hs_values, {} if units is None else {"units": units}),
        "tp": ("time", np.full(n, 8.0), {"units": "s"}),
        "wave_dir": ("time", np.full(n, 270.0), {"units": "degree"}),
        "current_speed": ("time", np.full(n, 0.5), {"units": "m s-1"}),
        "current_dir": ("time", np.full(n, 45.0), {"units": "degree"}),
    }
    ds = xr.Dataset(data, coords={"time": ("time", t, {} if time_units is None else {"units": time_units})})
    path = tmp_path / "fuzz.nc"
    ds.to_netcdf(path)
    try:
        got = F.load_netcdf(path)
    except ScenarioError as exc:
        assert str(path) in str(exc)
        return
    factor = {"m": 1.0, "cm": 0.01}[units]  # an accepted file had a known unit
    assert dtype != "U3" and n >= 2
    np.testing.assert_allclose(got.hs, np.asarray(hs_values, dtype=float) * factor, rtol=1e-6)
    step = {"seconds since 2003-01-15": 1.0, "hours since 2003-01-15 00:00": 3600.0}[time_units]
    np.testing.assert_allclose(got.time, t * step, rtol=1e-12)
    assert math.isfinite(float(got.time[-1]))


def test_numbered_csv_contract_counts_fields_after_quoting():
    """A quoted comma is one field: a row as wide as its header passes."""
    text = 'a,b\n1,"2,5"\n'
    assert list(numbered_csv(text, as_wide_as_header=True)) == [(1, ["a", "b"]), (2, ["1", "2,5"])]
    with pytest.raises(csv.Error, match=r"line 2 has 3 fields"):
        list(numbered_csv("a,b\n1,2,5\n", as_wide_as_header=True))


def test_an_unquoted_toml_datetime_as_storm_start_runs_as_the_quoted_text():
    """Was: every drop computed, then ``TypeError: Object of type datetime is not JSON
    serializable`` writing the record (and at every rerun). Reference: the same scenario with
    the start quoted as ISO 8601 text."""
    import datetime as dt
    import json

    from mineburial.ensembles.runner import run_ensemble

    def with_start(start):
        d = scenario_dict(
            environment={"water_depth": 3.0},
            release={"position": [0.0, 0.0, 1.0]},
            sediment={"class": "sand"},
            numerics={"t_max": 3.0, "sediment_quadrature": "fast"},
        )
        storm = {"peak_hs": 2.0, "peak_tp": 9.0, "duration_h": 24.0, "start": start}
        d["scour"] = {"storm": storm, "lead_times_days": [0.0, 0.5]}
        return d

    when = dt.datetime(2003, 1, 15, tzinfo=dt.timezone.utc)  # what tomllib gives for 2003-01-15T00:00:00Z
    unquoted = run_ensemble(with_start(when), n=2, seed=1, per_drop=True)
    quoted = run_ensemble(with_start("2003-01-15T00:00:00+00:00"), n=2, seed=1, per_drop=True)
    assert json.loads(unquoted.attrs["forcing_storm"])["start"] == "2003-01-15T00:00:00+00:00"
    assert unquoted.attrs["forcing_storm"] == quoted.attrs["forcing_storm"]
    for name, var in quoted.data_vars.items():
        assert np.array_equal(unquoted[name].values, var.values, equal_nan=True), name


def netcdf_forcing(path, n, hs=None):
    t = np.arange(n, dtype=float)
    data = {
        "hs": ("time", np.full(n, 1.0) if hs is None else hs, {"units": "m"}),
        "tp": ("time", np.full(n, 8.0), {"units": "s"}),
        "wave_dir": ("time", np.full(n, 270.0), {"units": "degree"}),
        "current_speed": ("time", np.full(n, 0.5), {"units": "m s-1"}),
        "current_dir": ("time", np.full(n, 45.0), {"units": "degree"}),
    }
    xr.Dataset(data, coords={"time": ("time", t, {"units": "hours since 2003-01-15"})}).to_netcdf(path)
    return path


def test_a_netcdf_forcing_with_more_records_than_memory_allows_is_one_line(tmp_path, monkeypatch):
    """Was: 10^7 records read (2.9 GB), then a MemoryError traceback. The count of values is
    checked against the available memory (here made 10 MB) before any is read."""
    from mineburial import resources

    path = netcdf_forcing(tmp_path / "long.nc", 100_000)  # 6 variables: 600,000 values
    monkeypatch.setattr(resources, "available_memory", lambda *a, **kw: 10_000_000)
    with pytest.raises(ScenarioError) as caught:
        F.load_netcdf(path)
    message = str(caught.value)
    assert str(path) in message and "600,000 values" in message and "would need about" in message
    monkeypatch.undo()
    assert len(F.load_netcdf(path)) == 100_000  # with the machine's memory it is read


def test_a_netcdf_forcing_variable_of_text_is_one_line(tmp_path):
    """Was: ValueError: could not convert string to float (a traceback)."""
    path = netcdf_forcing(tmp_path / "text.nc", 4, hs=np.array(["1.0", "2.0", "x", "3"]))
    with pytest.raises(ScenarioError, match=r"variable 'hs' holds text, not numbers"):
        F.load_netcdf(path)


def test_a_csv_forcing_field_over_the_csv_limit_is_one_line_naming_its_line(tmp_path):
    path = tmp_path / "f.csv"
    lines = [HEADER, *rows()]
    lines[3] = lines[3] + "9" * 140_000
    path.write_text("\n".join(lines) + "\n")
    with pytest.raises(ScenarioError, match=r"line 4: field larger than field limit"):
        F.load_csv(path)


@pytest.mark.parametrize("when", ["1500-01-15T00:00:00Z", "2300-01-15T00:00:00Z"])
def test_a_time_beyond_what_datetime64_ns_holds_is_refused_not_wrapped(tmp_path, when):
    """Was: read as another time silently (1500 became 2084): the series' times and the times
    in every message were wrong."""
    path = tmp_path / "f.csv"
    body = [f"{when[:4]}-01-15T0{k}:00:00Z,1.0,8.0,270.0,0.5,45.0" for k in range(4)]
    path.write_text(
        "\n".join(["time,hs_m,tp_s,wave_dir_deg,current_speed_m_s,current_dir_deg", *body]) + "\n"
    )
    with pytest.raises(
        ScenarioError, match=r"data row 1, column 'time': .* is outside the times that can be held"
    ):
        F.load_csv(path)
    with pytest.raises(
        ScenarioError, match=r"start = .*: .* is outside the times that can be held, 1677-09-21"
    ):
        F.storm_series(peak_hs=2.0, peak_tp=9.0, duration_h=24.0, start=when)


def test_lead_times_days_is_documented_as_what_it_is_optional():
    """Was: documented "— (required)" while a scenario without it runs (no lead time reported;
    compare and sensitivity take the end of the forcing window)."""
    import pathlib

    d = scenario_dict(
        environment={"water_depth": 3.0}, release={"position": [0.0, 0.0, 1.0]}, sediment={"class": "sand"}
    )
    d["scour"] = {"storm": {"peak_hs": 2.0, "peak_tp": 9.0, "duration_h": 24.0}}
    assert engine.load_ensemble(d, n=2).process("scour").lead_times_days == ()
    doc = (pathlib.Path(__file__).resolve().parents[1] / "docs" / "scenario.md").read_text(encoding="utf-8")
    (row,) = [line for line in doc.splitlines() if line.startswith("| `lead_times_days` |")]
    assert "required" not in row and "optional" in row
