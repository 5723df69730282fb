"""The one CF dataset builder (issue 18 item 5): every file kind's variables from the registry,
the global attributes every mineburial file carries written in one place.

Independent references: the CF/ACDD convention string and the package version written
literally; ISO 8601 parsed by the standard library; the files' variables (made by the
writers themselves from tiny arrays, no kernels run) compared with the registry's
declarations; xarray's netCDF round trip. The writers that need a kernel run are checked in
the tests that already make those runs (test_restraint, test_restraint_ensemble,
test_sensitivity, test_cli's drop).
"""

import datetime as dt

import numpy as np
import pytest
import xarray as xr
from test_netcdf import synthetic

import mineburial
from mineburial.analyses.synthetic import synthetic_environment
from mineburial.io import variables as V
from mineburial.io.dataset import build, registry_mismatches, standard_attrs
from mineburial.io.netcdf import write_netcdf
from mineburial.kernels.mine import layout
from mineburial.systems.mine.dataset import build_dataset
from mineburial.systems.mine.sediment_profiles import class_names


def _conventions_and_version(attrs):
    assert attrs["Conventions"] == "CF-1.11, ACDD-1.3"
    assert attrs["mineburial_version"] == mineburial.__version__
    created = dt.datetime.strptime(attrs["date_created"], "%Y-%m-%dT%H:%M:%SZ")
    assert abs((dt.datetime.now(dt.timezone.utc).replace(tzinfo=None) - created).total_seconds()) < 3600
    assert attrs["history"].startswith(attrs["date_created"] + " mineburial " + mineburial.__version__)


def test_an_ensemble_file_has_only_registry_variables_and_the_common_attributes(tmp_path):
    summary, status, inputs = synthetic(16)
    units = {p: ("kg" if p == "mine.mass" else "1", "x") for p in inputs}
    ds = build_dataset(
        summary,
        status,
        inputs=inputs,
        input_metadata=units,
        version=mineburial.__version__,
        seed=1,
        statistics_options={"outputs": ("penetration_depth", "burial_volume")},  # two: the suite's time
    )
    assert registry_mismatches(ds, "ensemble") == []
    _conventions_and_version(ds.attrs)
    assert {f"input_{p.replace('.', '_')}" for p in inputs} <= set(ds.data_vars)
    back = xr.open_dataset(write_netcdf(ds, tmp_path / "e.nc"))
    assert back.attrs["Conventions"] == "CF-1.11, ACDD-1.3"
    assert back["status"].attrs["flag_meanings"].split()[0] == "at_rest"


def test_a_trajectory_built_from_tiny_arrays_carries_the_declared_metadata():
    n = 3
    data = {name: np.linspace(0.0, 1.0, n) for name in V.TRAJ_STATE_COLUMNS}
    data.update({name: np.zeros(n) for name in V.TRAJ_ANGLES})
    data["phase"] = np.array([0, 2, 4])
    data.update({name: 1.5 for name in layout.SUMMARY_NAMES})
    data["status"] = 0
    ds = build(data, {"time": np.arange(n, dtype=float)}, {"title": "t"}, kind="trajectory")
    assert registry_mismatches(ds, "trajectory") == []
    _conventions_and_version(ds.attrs)
    # the names, units and long names the files have had since they were written (drop.py, 0534f69)
    assert ds["z"].attrs["units"] == "m" and "comment" not in ds["z"].attrs
    assert ds["omega1"].attrs["units"] == "rad s-1" and ds["time"].attrs["standard_name"] == "time"
    assert ds["phase"].dtype == np.int8 and ds["phase"].attrs["flag_meanings"].split()[-1] == "embedded"
    assert ds["penetration_depth"].dims == () and ds["penetration_depth"].attrs["units"] == "m"
    assert ds["status"].attrs["flag_meanings"].split()[0] == "at_rest"


def test_every_column_of_the_recorded_trajectory_is_declared():
    declared = set(V.FAMILIES["trajectory"])
    assert set(layout.TRAJ_COLUMNS) <= declared  # time, phase, the state, the work and force columns


def test_a_name_outside_the_family_is_refused_with_the_closest_names():
    with pytest.raises(KeyError, match="unknown output variable 'stoping_time'.*'stopping_time"):
        build({"stoping_time": 1.0}, kind="restraint_run")
    with pytest.raises(KeyError, match="unknown dataset kind 'trajectroy'.*'trajectory'"):
        build({}, kind="trajectroy")


def test_flags_owned_by_a_kernel_module_are_required_where_declared():
    ds = build({"status": np.int8(1)}, kind="restraint_run")  # the flags not handed in
    assert any("flags of mineburial.kernels.multibody" in p for p in registry_mismatches(ds, "restraint_run"))


def test_standard_attrs_keep_the_files_own_and_fill_in_the_rest():
    own = {"history": "made by hand", "source": "mine", "date_created": "2001-02-03T04:05:06Z", "x": None}
    a = standard_attrs("sensitivity", {**own, "Conventions": "CF-1.0"})
    assert a["Conventions"] == "CF-1.11, ACDD-1.3"  # the one convention string, never the caller's
    assert (a["history"], a["source"], a["date_created"]) == ("made by hand", "mine", "2001-02-03T04:05:06Z")
    assert "x" not in a and a["mineburial_version"] == mineburial.__version__
    b = standard_attrs("restraint_run", version="9.9")
    assert b["mineburial_version"] == "9.9" and b["source"] == "mineburial 9.9"
    assert b["history"].endswith("mineburial 9.9: time series of one case of the restraining system")


def test_the_restraint_outputs_keep_their_units():
    # units of the per-case results as the restraint ensemble files have carried them (0534f69)
    units = {name: V.FAMILIES["restraint_ensemble"][name].units for name in V.RESTRAINT_OUTPUTS}
    assert units == {
        "stopping_time": "s",
        "end_time": "s",
        "peak_chain_tension": "N",
        "peak_ship_tension": "N",
        "energy_closure": "1",
    }


def test_the_synthetic_environment_grid_is_built_from_its_family(tmp_path):
    ds = synthetic_environment(ny=2, nx=3)
    assert registry_mismatches(ds, "environment") == []
    _conventions_and_version(ds.attrs)
    back = xr.open_dataset(write_netcdf(ds, tmp_path / "env.nc"), mask_and_scale=False)
    assert back["sediment_class"].attrs["_FillValue"] == -1  # land: no sediment
    assert back["sediment_class"].attrs["flag_meanings"].split() == list(class_names())
    assert back["water_depth"].attrs["standard_name"] == "sea_floor_depth_below_sea_surface"


def test_a_plain_tuple_is_values_not_values_and_attributes():
    ds = build({}, {"quantile": (0.05, 0.5)}, kind="restraint_ensemble")
    assert ds["quantile"].values.tolist() == [0.05, 0.5] and ds["quantile"].attrs["units"] == "1"


def test_a_map_takes_its_grids_names_and_copies_the_grids_axes_and_grid_mapping():
    names = {"y": "northing", "x": "easting", "grid_mapping": "utm"}
    axis = {"standard_name": "projection_y_coordinate", "units": "m"}
    ds = build(
        {
            "cell_status": np.zeros((2, 3), dtype=np.int8),
            "water_depth": (np.ones((2, 3)), {"comment": "read as a depth"}),
            "grid_mapping": xr.DataArray(np.int32(0), attrs={"grid_mapping_name": "transverse_mercator"}),
        },
        {
            "y": xr.DataArray([0.0, 1.0], dims=("northing",), attrs=axis),
            "x": xr.DataArray(np.arange(3.0, dtype=np.float32), dims=("easting",)),  # the grid's dtype
        },
        kind="map",
        names=names,
    )
    assert ds["cell_status"].dims == ("northing", "easting") and ds["water_depth"].attrs["units"] == "m"
    assert ds["utm"].attrs == {"grid_mapping_name": "transverse_mercator"} and ds["northing"].attrs == axis
    assert registry_mismatches(ds, "map", names=names) == []
    del ds["water_depth"].attrs["comment"]  # a run-time attribute must still be there
    assert registry_mismatches(ds, "map", names=names) == ["water_depth: attribute comment = None, declared "
        + repr(V.FAMILIES["map"]["water_depth"].description)]  # fmt: skip


def test_the_map_and_comparison_families_derive_their_statistics_from_the_ensembles():
    ens, m, c = V.FAMILIES["ensemble"], V.FAMILIES["map"], V.FAMILIES["comparison"]
    for name in V.MAP_STATISTICS + V.map_process_statistics():
        assert m[name].dims == ens[name].dims + ("y", "x") and m[name].units == ens[name].units, name
        assert m[name].long_name == ens[name].long_name and m[name].description.startswith(
            ens[name].description
        )
    for name in ("burial_volume_mean", "height_proud_exceedance", "status_count"):
        assert c[name].dims == ("variant",) + ens[name].dims and c[name].cf_attrs() == ens[name].cf_attrs()
