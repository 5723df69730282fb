"""Burial-probability maps over an environment grid.

Independent references: for each cell, the single-scenario ensemble
``run_ensemble`` of a scenario written out by hand with that cell's environment and
the cell seed computed here from its documented definition (SHA-256 of
``"mineburial-map-cell:<seed>:<index>"``); the map must hold exactly its statistics.
The IOOS compliance checker (``compliance-checker -t cf:1.11 -c lenient`` exits 0)
judges the file; pyproj's inverse UTM gives the latitude/longitude of a projected grid.
"""

import hashlib
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import xarray as xr
from conftest import scenario_dict

from mineburial.analyses.maps import MAP_OUTPUTS, MapError, plot_map, read_environment, run_map
from mineburial.analyses.synthetic import synthetic_environment, write_synthetic_environment
from mineburial.cli import main
from mineburial.ensembles import engine
from mineburial.ensembles.runner import run_ensemble
from mineburial.io.dataset import registry_mismatches

N, SEED = 5, 424242
#: the names the synthetic (lat/lon) grid gives the map family's y, x and grid mapping
GRID_NAMES = {"y": "latitude", "x": "longitude", "grid_mapping": "crs"}
STAT_NAMES = (
    "burial_class_count",
    "burial_class_probability",
    "burial_class_probability_lower",
    "burial_class_probability_upper",
    "status_count",
) + tuple(f"{o}_{s}" for o in MAP_OUTPUTS for s in ("mean", "std", "quantile"))


def _scenario():
    """Cheap drops: 1 m above the water, 3 s limit, random mass and pitch; the water depth,
    the sediment (a soft_clay distribution here) and the current are replaced per cell."""
    d = scenario_dict(
        environment={
            "water_depth": 30.0,
            "current": {"kind": "power_law", "surface_velocity": [0.1, 0.0], "exponent": 0.2},
        },
        release={
            "position": [0.0, 0.0, 1.0],
            "pitch_deg": {"distribution": "uniform", "low": 0.0, "high": 60.0},
        },
        numerics={"t_max": 3.0},
    )
    d["mine"]["mass"] = {"distribution": "normal", "mean": 80.0, "std": 5.0}
    d["sediment"] = {"class": {"distribution": "choice", "values": ["soft_clay", "sand"]}, "friction": 0.4}
    return d


def expected_seed(seed, index):
    digest = hashlib.sha256(f"mineburial-map-cell:{seed}:{index}".encode()).digest()
    return int.from_bytes(digest[:8], "little")


def uniform_environment(depth=3.0, u=0.02, v=-0.01):
    """2 x 2 lat/lon grid, every water cell the same (stiff clay); cell (1, 0) is land."""
    env = synthetic_environment(ny=2, nx=2, seed=1)
    wet = np.isfinite(env["water_depth"].values)
    assert wet.sum() == 3
    env["water_depth"].values[wet] = depth
    env["sediment_class"].values[wet] = 4  # stiff_clay
    env["current_u"].values[wet] = u
    env["current_v"].values[wet] = v
    return env


def cell_reference(depth, sediment, current):
    """The cell's scenario written out by hand (not with maps.cell_scenario)."""
    d = _scenario()
    d["environment"]["water_depth"] = depth
    d["environment"]["current"] = current
    d["sediment"] = dict(sediment, friction=0.4)
    return d


@pytest.fixture(scope="module")
def uniform_map(tmp_path_factory):
    out = tmp_path_factory.mktemp("map") / "map.nc"
    ds = run_map(_scenario(), uniform_environment(), n=N, seed=SEED, output=out)
    return ds, out


def test_uniform_map_holds_the_single_scenario_statistics_of_every_cell(uniform_map):
    ds, _ = uniform_map
    ny, nx = ds["cell_status"].shape
    ref_scen = cell_reference(
        3.0,
        {"class": "stiff_clay"},
        {"kind": "power_law", "surface_velocity": [0.02, -0.01], "exponent": 0.2},
    )
    computed = 0
    for j in range(ny):
        for i in range(nx):
            if ds["cell_status"].values[j, i] != 0:
                continue
            computed += 1
            seed = expected_seed(SEED, j * nx + i)
            assert int(ds["cell_seed"].values[j, i]) == seed
            ref = run_ensemble(ref_scen, n=N, seed=seed)
            for name in STAT_NAMES:
                got = ds[name].values[..., j, i]
                assert np.array_equal(got, ref[name].values, equal_nan=True), (name, j, i)
    assert computed == 3
    # different seeds: the cells are not copies of one another
    assert len({int(s) for s in ds["cell_seed"].values.ravel() if s}) == 3
    assert int(ds["status_count"].sum()) == 3 * N
    assert np.all(ds["status_count"].values[0][ds["cell_status"].values == 0] > 0)  # some at rest


def test_land_cells_are_skipped(uniform_map):
    ds, _ = uniform_map
    land = ds["cell_status"].values == 1
    assert land.sum() == 1 and land[1, 0]
    for name in STAT_NAMES:
        v = ds[name].values[..., 1, 0]
        if np.issubdtype(v.dtype, np.floating):
            assert np.all(np.isnan(v)), name
        else:
            assert np.all(v == 0), name
    assert ds["most_likely_burial_class"].values[1, 0] == -1
    assert np.isnan(ds["water_depth"].values[1, 0])
    assert ds.attrs["n_cells_land"] == 1 and ds.attrs["n_cells_computed"] == 3


def test_a_map_has_only_its_registry_familys_variables_and_the_text_map_files_had(uniform_map):
    ds, _ = uniform_map
    assert registry_mismatches(ds, "map", names=GRID_NAMES) == []
    assert registry_mismatches(ds, "map") != []  # the grid's own names are not the declared y, x
    # as the maps wrote them by hand before the family (mineburial/analyses/maps.py at ee0fb46)
    assert ds["cell_status"].attrs["flag_meanings"] == "computed land_or_no_water_depth no_sediment_data"
    assert ds["most_likely_burial_class"].attrs["flag_values"].tolist() == [-1, 0, 1, 2, 3, 4]
    assert ds["most_likely_burial_class"].attrs["flag_meanings"].split()[:2] == ["no_data", "not_buried"]
    comment = ds["burial_volume_mean"].attrs["comment"]
    assert comment.endswith(
        "Per cell, over the drops of the cell's ensemble that came to rest; NaN on land, "
        "where no drop came to rest, or (std) where fewer than 2 did."
    )
    assert "sample_size" not in ds["burial_volume_mean"].attrs  # the template run's, not a cell's
    assert ds["burial_class_probability"].attrs["burial_class_basis"] == "burial_volume"
    depth = "Water depth of the cell used by its ensemble (from the environment grid's water_depth, read as a"
    assert ds["water_depth"].attrs["comment"].startswith(depth + " depth")
    assert ds["sediment_class"].attrs["flag_meanings"].split()[4] == "stiff_clay"
    assert ds["latitude"].attrs["axis"] == "Y" and ds["crs"].attrs["long_name"] == "WGS 84"  # the grid's


def test_map_file_metadata_and_round_trip(uniform_map):
    ds, out = uniform_map
    back = xr.load_dataset(out)
    for name in STAT_NAMES:
        assert np.array_equal(back[name].values, ds[name].values, equal_nan=True), name
    assert back["latitude"].attrs["units"] == "degrees_north"
    assert back["burial_class_probability"].attrs["grid_mapping"] == "crs"
    assert back["crs"].attrs["grid_mapping_name"] == "latitude_longitude"
    assert back.attrs["random_seed"] == SEED and back.attrs["n_drops_per_cell"] == N
    import json

    scen = json.loads(back.attrs["scenario"])
    assert scen["map"]["drops_per_cell"] == N
    assert "environment.water_depth" in scen["map"]["overridden_per_cell"]
    assert back.attrs["mineburial_version"]
    assert not Path(str(out) + ".parts").exists()


def _checker():
    exe = Path(sys.executable).with_name("compliance-checker")
    return str(exe) if exe.exists() else shutil.which("compliance-checker")


def test_cf_1_11_compliance(uniform_map, tmp_path):
    _, out = uniform_map
    run_map(_scenario(), projected_environment(), n=2, seed=1, output=tmp_path / "utm.nc")
    files = [out, tmp_path / "utm.nc"]
    exe = _checker()
    assert exe, "compliance-checker is not installed"
    for path in files:
        res = subprocess.run(
            [exe, "-t", "cf:1.11", "-c", "lenient", str(path)], capture_output=True, text=True, timeout=120
        )
        assert res.returncode == 0, res.stdout + res.stderr
        assert "Errors" not in res.stdout, res.stdout


def projected_environment():
    """2 x 1 UTM zone 32N grid with linear-profile sediment and speed/direction current."""
    x = np.array([580000.0])
    y = np.array([6040000.0, 6040500.0])
    dims = ("y", "x")
    return xr.Dataset(
        {
            "water_depth": (dims, np.array([[3.0], [3.5]]), {"units": "m", "grid_mapping": "utm"}),
            "sediment_density": (dims, np.array([[1900.0], [1950.0]]), {"units": "kg m-3"}),
            "sediment_strength": (dims, np.array([[40000.0], [60000.0]]), {"units": "Pa"}),
            "sediment_strength_gradient": (dims, np.array([[2000.0], [1000.0]]), {"units": "Pa m-1"}),
            "current_speed": (dims, np.array([[0.4], [0.0]]), {"units": "m s-1"}),
            "current_direction": (dims, np.array([[0.0], [0.0]]), {"units": "degree"}),
            "utm": (
                (),
                0,
                {
                    "grid_mapping_name": "transverse_mercator",
                    "longitude_of_central_meridian": 9.0,
                    "latitude_of_projection_origin": 0.0,
                    "scale_factor_at_central_meridian": 0.9996,
                    "false_easting": 500000.0,
                    "false_northing": 0.0,
                    "semi_major_axis": 6378137.0,
                    "inverse_flattening": 298.257223563,
                },
            ),
        },
        coords={
            "y": ("y", y, {"standard_name": "projection_y_coordinate", "units": "m", "axis": "Y"}),
            "x": ("x", x, {"standard_name": "projection_x_coordinate", "units": "m", "axis": "X"}),
        },
    )


def test_projected_grid_with_profile_values_and_speed_direction_current():
    ds = run_map(_scenario(), projected_environment(), n=3, seed=77)
    assert ds["burial_volume_mean"].dims == ("y", "x")
    assert ds["burial_volume_mean"].attrs["grid_mapping"] == "utm"
    assert "utm" in ds and ds["utm"].attrs["grid_mapping_name"] == "transverse_mercator"
    assert registry_mismatches(ds, "map", names={"y": "y", "x": "x", "grid_mapping": "utm"}) == []
    # UTM 32N: easting 580 km, northing 6040 km lies near 54.5 N, 10.2 E
    assert abs(float(ds["latitude"][0, 0]) - 54.5) < 0.1
    assert abs(float(ds["longitude"][0, 0]) - 10.23) < 0.1
    for j, (depth, rho, s0, ks, v) in enumerate(
        ((3.0, 1900.0, 40000.0, 2000.0, 0.4), (3.5, 1950.0, 60000.0, 1000.0, 0.0))
    ):
        # direction 0 = towards north = +y; a fixed linear density_gradient is absent -> 0
        ref = run_ensemble(
            cell_reference(
                depth,
                {"density": rho, "density_gradient": 0.0, "strength": s0, "strength_gradient": ks},
                {"kind": "power_law", "surface_velocity": [0.0, v], "exponent": 0.2},
            ),
            n=3,
            seed=expected_seed(77, j),
        )
        for name in STAT_NAMES:
            assert np.array_equal(ds[name].values[..., j, 0], ref[name].values, equal_nan=True), (name, j)


def test_interrupted_map_resumes_without_recomputing(tmp_path, monkeypatch):
    env = uniform_environment()
    out = tmp_path / "m.nc"
    real = engine.compute_chunk
    calls = []

    def failing(spec, start, stop):
        if len(calls) == 4:
            raise KeyboardInterrupt
        calls.append((spec.seed, start, stop))
        return real(spec, start, stop)

    monkeypatch.setattr(engine, "compute_chunk", failing)
    with pytest.raises(KeyboardInterrupt):
        run_map(_scenario(), env, n=4, seed=3, chunk_size=2, output=out)
    assert len(list(Path(str(out) + ".parts").glob("*/chunk-*.npz"))) == 4
    first = list(calls)
    calls.clear()
    monkeypatch.setattr(
        engine, "compute_chunk", lambda spec, s, e: (calls.append((spec.seed, s, e)), real(spec, s, e))[1]
    )
    ds = run_map(_scenario(), env, n=4, seed=3, chunk_size=2, output=out)
    assert len(calls) == 2 and not set(calls) & set(first)  # 6 chunks in all, 4 reused
    monkeypatch.setattr(engine, "compute_chunk", real)
    fresh = run_map(_scenario(), env, n=4, seed=3, chunk_size=2)
    for name in STAT_NAMES:
        assert np.array_equal(ds[name].values, fresh[name].values, equal_nan=True), name


def test_plot_is_drawn_when_matplotlib_is_available(uniform_map, tmp_path):
    ds, _ = uniform_map
    try:
        import matplotlib  # noqa: F401
    except ImportError:
        with pytest.raises(MapError, match="matplotlib"):
            plot_map(ds, tmp_path / "map.png")
        return
    path = plot_map(ds, tmp_path / "map.png")
    data = path.read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n" and len(data) > 20_000


def test_cli_map_writes_netcdf_and_png(tmp_path, capsys):
    env = tmp_path / "env.nc"
    write_synthetic_environment(env, ny=2, nx=2, seed=1)
    ds_env = xr.load_dataset(env)
    assert "SYNTHETIC" in ds_env.attrs["title"] and "SYNTHETIC" in ds_env.attrs["comment"]
    scen = tmp_path / "scen.toml"
    scen.write_text("""
[ensemble]
n = 100
seed = 5
[mine]
length = 1.0
diameter = 0.25
mass = {distribution = "normal", mean = 80.0, std = 5.0}
[release]
position = [0.0, 0.0, 1.0]
pitch_deg = {distribution = "uniform", low = 0.0, high = 60.0}
[environment]
water_depth = 20.0
[sediment]
class = "sand"
[numerics]
t_max = 0.5
""")
    out, png = tmp_path / "map.nc", tmp_path / "map.png"
    rc = main(
        [
            "map",
            str(scen),
            "--environment",
            str(env),
            "-o",
            str(out),
            "-n",
            "2",
            "--plot",
            str(png),
            "--quiet",
        ]
    )
    assert rc == 0
    text = capsys.readouterr().out
    assert "3 computed, 1 land" in text and f"wrote {out}" in text
    ds = xr.load_dataset(out)
    assert ds.attrs["n_drops_per_cell"] == 2 and ds.attrs["random_seed"] == 5
    assert png.exists() == _has_matplotlib()


def _has_matplotlib():
    try:
        import matplotlib  # noqa: F401
    except ImportError:
        return False
    return True


def test_bad_grids_are_rejected_with_clear_messages():
    env = uniform_environment()
    with pytest.raises(MapError, match="water_depth"):
        read_environment(env.drop_vars("water_depth"))
    bad = env.copy()
    bad["sediment_class"].attrs["flag_meanings"] = (
        "very_soft_clay soft_clay silty_mud firm_clay stiff_clayy sandy_silt sand"
    )
    with pytest.raises(MapError, match="did you mean 'stiff_clay'"):
        read_environment(bad)
    nosed = env.drop_vars("sediment_class")
    with pytest.raises(MapError, match="sediment_strength"):
        read_environment(nosed)
    feet = env.copy()
    feet["water_depth"].attrs["units"] = "ft"
    with pytest.raises(MapError, match="units 'ft'"):
        read_environment(feet)
    deep = env.copy()  # a release position below the seabed names the cell
    deep["water_depth"].values[0, 0] = 0.5
    scen = _scenario()
    scen["release"]["position"] = [0.0, 0.0, -1.0]
    with pytest.raises(MapError, match=r"cell \(0, 0\) at latitude"):
        run_map(scen, deep, n=2, seed=1)


def test_a_map_drawing_from_the_posterior_holds_each_cells_epistemic_band(tmp_path):
    """Issue 32: with ensemble.coefficients = "posterior" every cell draws its coefficients from the
    shipped posterior like a run does, and the map holds the run's epistemic band per cell."""
    n = 40
    scen = _scenario()
    scen["ensemble"] = {"coefficients": "posterior"}
    ds = run_map(scen, uniform_environment(), n=n, seed=SEED, output=tmp_path / "m.nc")
    ref_scen = cell_reference(
        3.0,
        {"class": "stiff_clay"},
        {"kind": "power_law", "surface_velocity": [0.02, -0.01], "exponent": 0.2},
    )
    ref_scen["ensemble"] = {"coefficients": "posterior"}
    nx = ds["cell_status"].shape[1]
    j, i = np.argwhere(ds["cell_status"].values == 0)[0]
    ref = run_ensemble(ref_scen, n=n, seed=expected_seed(SEED, j * nx + i))
    band = tuple(f"burial_class_probability_epistemic_{side}" for side in ("lower", "upper"))
    for name in ("burial_class_probability", *band):
        assert np.array_equal(ds[name].values[..., j, i], ref[name].values, equal_nan=True), name
    # the figure draws the band: a second row of panels (the height of a 2-row figure at dpi 50)
    png = plot_map(ds, tmp_path / "band.png", dpi=50).read_bytes()
    plain = plot_map(ds.drop_vars(list(band)), tmp_path / "plain.png", dpi=50).read_bytes()
    height = lambda data: int.from_bytes(data[20:24], "big")  # noqa: E731 -- PNG IHDR
    assert height(png) > 1.7 * height(plain), (height(png), height(plain))
