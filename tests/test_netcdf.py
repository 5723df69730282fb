"""NetCDF output: round trip, atomic write, CF-1.11 / ACDD-1.3 compliance.

Independent references: the per-drop arrays handed to ``build_dataset`` (the
file must give them back bit for bit), the IOOS compliance checker
(``compliance-checker -t cf:1.11 -c lenient`` must exit with 0), the UDUNITS-2
library through ``cf_units`` for every declared unit, and the file system
(no partial or temporary file after a failed write).

The compliance checker's run time grows with the square of the number of
variables (about 1 min for the full 200-variable default file, which passes
as well), so the checked file describes three outputs, one of each kind
(depth, percent, other): every statistics template is exercised.
"""

import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

import netCDF4
import numpy as np
import pytest
import xarray as xr

from mineburial.io import variables as V
from mineburial.io.netcdf import write_netcdf
from mineburial.kernels.mine import layout
from mineburial.kernels.mine import status as S
from mineburial.systems.mine.dataset import build_dataset
from mineburial.systems.mine.statistics import burial_class

OUTPUTS = ("penetration_depth", "burial_volume", "final_heading")
SCENARIO = {
    "mine": {"mass": np.float64(680.0), "length": 2.0, "shape": "cylinder"},
    "release": {"z": 5.0},
    "ensemble": {"n": np.int64(64), "seed": 7},
    "sediment": {"strength": [1000.0, 2000.0]},
}
INPUT_META = {
    "mine.mass": ("kg", "mass of the mine"),
    "sediment.strength": ("Pa", "undrained shear strength at the seabed"),
    "current.kind": ("1", "code of the current profile"),
}


def synthetic(n=64, seed=11):
    rng = np.random.default_rng(seed)
    summary = rng.normal(2.0, 1.0, size=(n, layout.N_SUMMARY))
    for name in V.PERCENT_OUTPUTS:
        summary[:, layout.SUMMARY_INDEX[name]] = np.where(rng.random(n) < 0.2, 0.0, rng.uniform(0, 100, n))
    status = rng.choice(5, size=n, p=[0.6, 0.1, 0.1, 0.1, 0.1]).astype(np.int8)
    summary[status == S.INVALID_INPUT] = np.nan  # drops that were not run
    inputs = {
        "mine.mass": rng.normal(680.0, 20.0, n),
        "sediment.strength": rng.uniform(500.0, 5000.0, n),
        "current.kind": rng.integers(0, 3, n).astype(np.float64),
    }
    return summary, status, inputs


def make_dataset(n=64, **kw):
    summary, status, inputs = synthetic(n)
    args = dict(
        inputs=inputs,
        input_metadata=INPUT_META,
        scenario=SCENARIO,
        seed=2**70 + 3,
        version="0.1.0",
        sampling_method="latin_hypercube",
        statistics_options={"outputs": OUTPUTS},
        date_created="2024-06-11T10:00:00Z",
        creator={
            "name": "Test Author",
            "email": "test@example.org",
            "type": "person",
            "institution": "Test Institute",
        },
    )
    args.update(kw)
    return build_dataset(summary, status, **args), summary, status, inputs


def test_round_trip_gives_back_identical_values(tmp_path):
    ds, summary, status, inputs = make_dataset()
    path = write_netcdf(ds, tmp_path / "run.nc")
    with xr.open_dataset(path) as back:
        back.load()
    xr.testing.assert_identical(back, ds)
    for name in ds.variables:
        assert back[name].dtype == ds[name].dtype, name
    # against the arrays handed in, not only against the in-memory Dataset
    for j, name in enumerate(layout.SUMMARY_NAMES):
        np.testing.assert_array_equal(back[name].values, summary[:, j])
    np.testing.assert_array_equal(back["status"].values, status)
    for path_, values in inputs.items():
        var = back[V.input_variable_name(path_)]
        np.testing.assert_array_equal(var.values, values)
        assert var.attrs["units"] == INPUT_META[path_][0]
        assert var.attrs["scenario_path"] == path_
    cls = back["burial_class"].values
    vol = summary[:, layout.SUMMARY_INDEX["burial_volume"]]
    at_rest = status == S.AT_REST
    np.testing.assert_array_equal(cls[~at_rest], -1)
    np.testing.assert_array_equal(cls[at_rest], burial_class(vol[at_rest]))
    np.testing.assert_array_equal(back["realization"].values, np.arange(summary.shape[0]))
    assert back["realization"].attrs["standard_name"] == "realization"


def test_file_format_compression_and_global_attributes(tmp_path):
    ds, summary, status, _ = make_dataset()
    path = write_netcdf(ds, tmp_path / "run.nc", complevel=5)
    with netCDF4.Dataset(path) as nc:
        assert nc.data_model == "NETCDF4"
        filters = nc["penetration_depth"].filters()
        assert filters["zlib"] and filters["complevel"] == 5
        assert "_FillValue" not in nc["realization"].ncattrs()
        assert "_FillValue" not in nc["burial_volume_bin_bounds"].ncattrs()
        assert nc["status"].flag_values.dtype == nc["status"].dtype
        attrs = {k: nc.getncattr(k) for k in nc.ncattrs()}
    assert attrs["Conventions"] == "CF-1.11, ACDD-1.3"
    for key in (
        "title",
        "summary",
        "keywords",
        "history",
        "date_created",
        "creator_name",
        "creator_email",
        "product_version",
        "source",
        "id",
        "references",
        "standard_name_vocabulary",
        "sampling_method",
    ):
        assert attrs[key], key
    assert json.loads(attrs["scenario"]) == json.loads(json.dumps(SCENARIO, default=lambda o: o.item()))
    assert attrs["random_seed"] == str(2**70 + 3)  # too large for a 64-bit attribute
    assert attrs["n_drops"] == summary.shape[0]
    assert attrs["n_at_rest"] == np.count_nonzero(status == S.AT_REST)
    assert attrs["date_created"] == "2024-06-11T10:00:00Z"
    assert attrs["history"].startswith("2024-06-11T10:00:00Z mineburial 0.1.0")
    assert attrs["burial_class_basis"] == "burial_volume"
    # the final file gets ordinary permissions (umask), not mkstemp's 0600
    umask = os.umask(0)
    os.umask(umask)
    assert (path.stat().st_mode & 0o777) == (0o666 & ~umask)


def test_small_seed_is_an_integer_and_statistics_only_file(tmp_path):
    ds, *_ = make_dataset(seed=12345, per_drop=False)
    assert "realization" not in ds.dims and "penetration_depth" not in ds
    path = write_netcdf(ds, tmp_path / "stats.nc")
    with xr.open_dataset(path) as back:
        assert back.attrs["random_seed"] == 12345
        assert back.attrs["random_seed"].dtype == np.int64


def _fail_prepare_variable_after(monkeypatch, n_ok):
    """Make the netCDF4 backend raise while it is half-way through defining variables."""
    from xarray.backends import netCDF4_

    original = netCDF4_.NetCDF4DataStore.prepare_variable
    calls = {"n": 0}

    def prepare_variable(self, *args, **kwargs):
        calls["n"] += 1
        if calls["n"] > n_ok:
            raise OSError("simulated disk failure mid-write")
        return original(self, *args, **kwargs)

    monkeypatch.setattr(netCDF4_.NetCDF4DataStore, "prepare_variable", prepare_variable)
    return calls


def _fail_fsync(monkeypatch):
    """Make the flush of the complete temporary file fail (just before the rename)."""

    def fsync(fd):
        raise OSError("simulated fsync failure")

    monkeypatch.setattr(os, "fsync", fsync)


@pytest.mark.parametrize("failure", ["mid_write", "fsync"])
def test_atomic_write_keeps_previous_file_and_leaves_no_temporary(tmp_path, monkeypatch, failure):
    path = tmp_path / "run.nc"
    old, *_ = make_dataset(n=16)
    write_netcdf(old, path)
    before = path.read_bytes()
    new, *_ = make_dataset(n=40)
    if failure == "mid_write":
        calls = _fail_prepare_variable_after(monkeypatch, n_ok=10)
    else:
        _fail_fsync(monkeypatch)
    with pytest.raises(OSError, match="simulated"):
        write_netcdf(new, path)
    if failure == "mid_write":
        assert calls["n"] == 11  # it really failed half-way through the variables
    monkeypatch.undo()
    assert path.read_bytes() == before
    assert sorted(p.name for p in tmp_path.iterdir()) == ["run.nc"]
    with xr.open_dataset(path) as back:
        assert back.sizes["realization"] == 16


def test_failed_first_write_creates_nothing(tmp_path, monkeypatch):
    ds, *_ = make_dataset(n=8)
    _fail_prepare_variable_after(monkeypatch, n_ok=3)
    with pytest.raises(OSError):
        write_netcdf(ds, tmp_path / "new.nc")
    assert list(tmp_path.iterdir()) == []


def test_no_drop_at_rest_builds_and_writes(tmp_path):
    summary, status, _ = synthetic(12)
    status[:] = S.NUMERICAL_FAILURE
    ds = build_dataset(summary, status, version="0.1.0", statistics_options={"outputs": ("burial_volume",)})
    assert "n_at_rest = 0" in ds.attrs["statistics_note"]
    path = write_netcdf(ds, tmp_path / "none.nc")
    with xr.open_dataset(path) as back:
        assert np.isnan(back["burial_volume_mean"].item())
        assert np.all(back["burial_class"].values == -1)
        assert back["status_count"].values[S.NUMERICAL_FAILURE] == 12


def _checker_executable():
    exe = Path(sys.executable).with_name("compliance-checker")
    return str(exe) if exe.exists() else shutil.which("compliance-checker")


def test_cf_1_11_compliance_checker_reports_no_errors(tmp_path):
    ds, *_ = make_dataset()
    full = write_netcdf(ds, tmp_path / "full.nc")
    summary, status, _ = synthetic(10)
    status[:] = S.TIME_LIMIT
    empty = write_netcdf(
        build_dataset(summary, status, version="0.1.0", statistics_options={"outputs": ("burial_area",)}),
        tmp_path / "empty.nc",
    )
    exe = _checker_executable()
    assert exe, "compliance-checker is not installed"
    # both files in one run of the checker (its exit status is 0 only if every file passes; one
    # interpreter start instead of two, ~4 s each)
    res = subprocess.run(
        [exe, "-t", "cf:1.11", "-c", "lenient", str(full), str(empty)],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert res.returncode == 0, res.stdout + res.stderr
    assert res.stdout.count("IOOS Compliance Checker Report") == 2, res.stdout
    assert "Errors" not in res.stdout, res.stdout


@pytest.mark.filterwarnings("ignore::DeprecationWarning")  # the checker's own ioos_sos plugin
def test_acdd_1_3_attributes_present(tmp_path):
    """ACDD-1.3 check via the Python API: the only shortfall allowed is the missing
    standard_name of variables for which the CF table has none."""
    from compliance_checker.runner import CheckSuite, ComplianceChecker

    ds, *_ = make_dataset()
    path = write_netcdf(ds, tmp_path / "run.nc")
    CheckSuite.load_all_available_checkers()
    report = tmp_path / "acdd.json"
    ComplianceChecker.run_checker(
        str(path), ["acdd:1.3"], 0, "lenient", output_filename=str(report), output_format="json"
    )
    res = json.loads(report.read_text())["acdd:1.3"]
    failed = [
        r
        for level in ("high_priorities", "medium_priorities", "low_priorities")
        for r in res[level]
        if r["value"][0] != r["value"][1]
    ]
    messages = [m for r in failed for m in r["msgs"]]
    assert messages and all(m == "standard_name" for m in messages), messages


def test_every_declared_unit_is_valid_udunits():
    import cf_units  # UDUNITS-2 bindings, installed with compliance-checker

    for var in V.VARIABLES.values():
        if var.units is not None:
            assert not cf_units.Unit(var.units).is_unknown(), (var.name, var.units)
    assert cf_units.Unit("percent").convert(50.0, "1") == pytest.approx(0.5)


def test_registry_markdown_and_docs_are_in_step():
    md = V.variables_markdown()
    for name in list(layout.SUMMARY_NAMES) + [
        "status",
        "burial_class",
        "realization",
        "burial_class_probability",
        "status_count",
    ]:
        assert f"`{name}`" in md
    for suffix in (
        "mean",
        "std",
        "stderr",
        "quantile",
        "bin",
        "bin_bounds",
        "histogram",
        "level",
        "exceedance",
    ):
        assert f"`X_{suffix}`" in md
    full = V.variables_markdown(expand=True)
    assert all(f"`{name}`" in full for name in V.VARIABLES)
    doc = Path(__file__).resolve().parents[1] / "docs" / "notes" / "output.md"
    assert md in doc.read_text(), "regenerate the table in docs/notes/output.md"


def test_bad_inputs_have_clear_messages():
    summary, status, inputs = synthetic(8)
    with pytest.raises(ValueError, match="shape"):
        build_dataset(summary, status[:-1])
    with pytest.raises(ValueError, match="sampled input 'mine.mass'"):
        build_dataset(summary, status, inputs={"mine.mass": np.ones(3)})
    with pytest.raises(ValueError, match="cannot be turned into a CF variable name"):
        build_dataset(summary, status, inputs={"mine mass": np.ones(8)})
