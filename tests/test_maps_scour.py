"""Maps with the post-impact scour stage (issue 20): a lead-time axis per cell, one forcing for all
cells or a gridded forcing (time, y, x), each cell taking its own series.

Independent references: each cell's statistics are those of ``run_ensemble`` of the cell's
scenario written out by hand, with the cell seed from its documented definition and, for a
gridded forcing, the cell's own series given to ``run`` as a CSV file (the grid file is built
from the same CSV series, so the values are the same float64 numbers); the seed contract is
checked against the map without ``[scour]`` (every impact statistic equal).
"""

import hashlib
import json

import numpy as np
import pytest
import rasterio
import xarray as xr
from test_maps import (
    GRID_NAMES,
    SEED,
    STAT_NAMES,
    _scenario,
    cell_reference,
    expected_seed,
    uniform_environment,
)

from mineburial.analyses.maps import run_map
from mineburial.cli import main
from mineburial.ensembles.runner import run_ensemble
from mineburial.errors import ScenarioError
from mineburial.io import forcing as fio
from mineburial.io import variables as V
from mineburial.io.dataset import registry_mismatches
from mineburial.systems.mine.config import dumps_toml

N = 4
LEADS = [0.0, 0.01, 0.5]  # days
CURRENT = {"kind": "power_law", "surface_velocity": [0.02, -0.01], "exponent": 0.2}


def forcing_csv(path, hours=12, hs=0.0, u=0.7):
    """A constant forcing (relative times), written by hand."""
    rows = ["time_s,hs_m,tp_s,wave_dir_deg,current_speed_m_s,current_dir_deg,water_level_m"]
    rows += [f"{3600.0 * i},{hs},8.0,270.0,{u},0.0,0.0" for i in range(hours + 1)]
    path.write_text("\n".join(rows) + "\n")
    return path


def scour_section(forcing):
    sand = {"d50": 2.0e-4, "grain_density": 2650.0, "cohesive": False}  # on the cells' clay classes
    return {"forcing": str(forcing), "lead_times_days": LEADS, **sand}


def with_scour(d, sec):
    d = dict(d)
    d["scour"] = sec
    return d


def cell_run(sec, seed):
    ref = cell_reference(3.0, {"class": "stiff_clay"}, CURRENT)
    return run_ensemble(with_scour(ref, sec), n=N, seed=seed)


SCOUR_NAMES = (
    "scour_burial_class_probability",
    "scour_burial_class_probability_lower",
    "scour_burial_class_probability_upper",
    "scour_burial_volume_mean",
    "scour_burial_volume_quantile",
    "scour_height_proud_mean",
    "scour_time_to_level_quantile",
    "scour_mobile_fraction",
    "scour_status_count",
    # per lead time, as run's file has them (issue 33 item 5)
    "scour_mobile_fraction_by_lead_time",
    "scour_mobile_probability",
    "scour_mobile_into_pit_probability",
    "scour_mobile_away_probability",
    "scour_pit_depth_mean",
)


@pytest.fixture(scope="module")
def maps(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("scourmap")
    sec = scour_section(forcing_csv(tmp / "const.csv"))
    plain = run_map(_scenario(), uniform_environment(), n=N, seed=SEED)
    # one drop a chunk here; the CLI test's map has the default chunking and must be equal
    scoured = run_map(with_scour(_scenario(), sec), uniform_environment(), n=N, seed=SEED, chunk_size=1)
    return tmp, sec, plain, scoured


def test_map_with_scour_keeps_every_impact_statistic_of_the_map_without(maps):
    _, _, plain, scoured = maps
    for name in STAT_NAMES + ("cell_seed", "most_likely_burial_class"):
        assert np.array_equal(plain[name].values, scoured[name].values, equal_nan=True), name
    assert not [v for v in plain.variables if str(v).startswith("scour_")]


def test_each_cell_holds_the_scour_statistics_of_its_single_run(maps):
    _, sec, _, ds = maps
    assert registry_mismatches(ds, "map", names=GRID_NAMES) == []  # the stage's statistics declared too
    assert set(V.PROCESS_VARIABLES["scour"].map_statistics()) == {
        v for v in ds.data_vars if str(v).startswith("scour_")
    }  # and no more
    assert list(ds["lead_time"].values) == LEADS
    assert ds["lead_time"].attrs["standard_name"] == "forecast_period"
    assert ds["scour_burial_class_probability"].dims == (
        "lead_time",
        "impact_burial_class",
        "latitude",
        "longitude",
    )
    nx = ds.sizes["longitude"]
    for j, i in ((0, 0), (1, 1)):
        ref = cell_run(sec, expected_seed(SEED, j * nx + i))
        for name in SCOUR_NAMES:
            got = ds[name].values[..., j, i]
            assert np.array_equal(got, ref[name].values, equal_nan=True), (name, j, i)
    land = ds["scour_burial_volume_mean"].values[:, 1, 0]
    assert np.all(np.isnan(land)) and ds["scour_status_count"].values[:, 1, 0].sum() == 0
    assert ds.attrs["forcing_file"] == sec["forcing"]
    assert json.loads(ds.attrs["scenario"])["scour"]["lead_times_days"] == LEADS


def grid_series(tmp, env):
    """Per water cell its own constant series (a calm cell, a weak and a strong current), as CSV
    files and as the gridded NetCDF built from the same numbers; the land cell dry."""
    speeds = {(0, 0): 0.0, (0, 1): 0.3, (1, 1): 0.9}
    files = {c: forcing_csv(tmp / f"cell{c[0]}{c[1]}.csv", u=u) for c, u in speeds.items()}
    cells = [[fio.load_csv(files[(j, i)]) if (j, i) in files else None for i in range(2)] for j in range(2)]
    path = fio.write_gridded_netcdf(cells, env["latitude"], env["longitude"], tmp / "grid.nc")
    return files, path


def test_gridded_forcing_gives_each_cell_its_own_series(tmp_path):
    env = uniform_environment()
    files, grid = grid_series(tmp_path, env)
    sec = {k: v for k, v in scour_section(files[(0, 0)]).items() if k != "forcing"}
    scen = with_scour(_scenario(), dict(sec, forcing_grid=str(grid)))
    ds = run_map(scen, env, n=N, seed=SEED, output=tmp_path / "map.nc")  # through the chunk store
    for j, i in ((0, 0), (1, 1)):
        csv = files[(j, i)]
        ref = cell_run(dict(sec, forcing=str(csv)), expected_seed(SEED, j * 2 + i))
        for name in SCOUR_NAMES:
            assert np.array_equal(ds[name].values[..., j, i], ref[name].values, equal_nan=True), (name, j, i)
    # the calm cell keeps its impact burial; the strong current buries deeper by the last lead time
    mean = ds["scour_burial_volume_mean"].values
    assert mean[-1, 0, 0] == mean[0, 0, 0] and mean[-1, 1, 1] > mean[0, 1, 1]
    assert ds.attrs["forcing_grid_file"] == str(grid)
    assert ds.attrs["forcing_grid_sha256"] == hashlib.sha256(grid.read_bytes()).hexdigest()
    assert not (tmp_path / "map.nc.parts").exists()


def test_gridded_forcing_on_another_grid_is_one_line_exit_2(tmp_path, capsys):
    env = uniform_environment()
    env_path = tmp_path / "env.nc"
    env.to_netcdf(env_path)
    files, _ = grid_series(tmp_path, env)
    shifted = env["longitude"] + 0.5
    cells = [[fio.load_csv(files[(0, 0)])] * 2] * 2
    bad = fio.write_gridded_netcdf(cells, env["latitude"], shifted, tmp_path / "shifted.nc")
    sec = {"forcing_grid": str(bad), "lead_times_days": LEADS}
    # a lat/lon grid other than the environment's is interpolated onto it (docs/maps.md); this one
    # misses the cells: refused, the cell named
    with pytest.raises(
        ScenarioError, match=r"cell \(0, 0\) .*lies outside the product's grid \(longitude 10\.8 to"
    ):
        run_map(with_scour(_scenario(), sec), env, n=N, seed=SEED)
    dry = fio.write_gridded_netcdf(
        [[cells[0][0], None], [None, cells[0][0]]], env["latitude"], env["longitude"], tmp_path / "dry.nc"
    )
    scen = tmp_path / "s.toml"
    scen.write_text(dumps_toml(with_scour(_scenario(), dict(sec, forcing_grid=str(dry)))))
    out = tmp_path / "map.nc"
    assert main(["map", str(scen), "--environment", str(env_path), "-o", str(out), "-n", "2"]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "missing at every time at cell (0, 1)" in err and "dry.nc" in err
    assert not out.exists()
    assert main(["run", str(scen), "-o", str(out), "-n", "2"]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "read by `mineburial map` only" in err


def test_cli_map_draws_lead_time_panels_and_writes_the_geotiff_after_scour(maps, capsys):
    tmp, sec, _, ds = maps
    env = tmp / "env.nc"
    uniform_environment().to_netcdf(env)
    scen = tmp / "scour.toml"
    scen.write_text(dumps_toml(with_scour(_scenario(), sec)))
    out, png, tif = tmp / "map.nc", tmp / "map.png", tmp / "map.tif"
    args = ["map", str(scen), "--environment", str(env), "-o", str(out), "-n", str(N), "--seed", str(SEED)]
    # checked before computing: a lead time the map does not have, for the panels and the GeoTIFF
    for bad in (["--plot", str(png), "--lead-times", "0,7"], ["--geotiff", str(tif), "--lead-time", "7"]):
        assert main(args + bad) == 2
        err = capsys.readouterr().err.strip()
        assert (
            len(err.splitlines()) == 1
            and "7 d is not a lead time of the map; choose among 0, 0.01, 0.5" in err
        )
        assert not out.exists()
    extra = ["--plot", str(png), "--lead-times", "0,0.5", "--geotiff", str(tif), "--lead-time", "0.5"]
    assert main(args + extra + ["--class", "0", "--quiet"]) == 0
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    with rasterio.open(tif) as r:
        band = r.read(1)
    want = ds["scour_burial_class_probability"].values[-1, 0][::-1]  # north up
    np.testing.assert_allclose(band[np.isfinite(band)], want[np.isfinite(want)], rtol=1e-6)
    assert np.isnan(band[0, 0])  # the land cell (1, 0) is in the north-west
    with xr.open_dataset(out) as written:  # default chunking: the same cells as one drop a chunk
        for name in SCOUR_NAMES:
            assert np.array_equal(written[name].values, ds[name].values, equal_nan=True), name


def test_memory_check_counts_the_lead_time_arrays(tmp_path, monkeypatch):
    from mineburial.analyses import maps
    from mineburial.ensembles import engine

    needs = []
    monkeypatch.setattr(maps, "memory_refusal", lambda need, *a, **k: needs.append(need))
    status = np.zeros((3, 4), dtype=np.int8)
    sec = scour_section(forcing_csv(tmp_path / "f.csv"))
    for d in (_scenario(), with_scour(_scenario(), sec)):
        maps._check_map_memory(engine.load_ensemble(d, n=N), status)
    # per grid cell and lead time: 5 measures x (mean + 5 quantiles) + 4 class arrays x 5 classes
    # + the mobile share by then, the share that would move (and its split: into an open pit, away)
    # and the mean pit depth (issue 33);
    # per cell: 2 levels x 5 time quantiles + 2 reached fractions + 1 mobile share + 5 status
    # counts + 1 not-modelled share; 8 bytes each, three copies; plus the stage's per-drop values
    # in flight (with the window start and the cohesive flag; issue 33: the pit depth and the mobility
    # at each lead time beside the 5 measures)
    lead_bytes = 8 * (len(LEADS) * (5 * 6 + 4 * 5 + 5) + 2 * 5 + 2 + 1 + 5 + 1)
    per_drop = 8 * ((5 + 3) * len(LEADS) + 2 + 2) + 2
    extra = needs[1] - needs[0]
    assert extra >= 3 * lead_bytes * status.size
    assert extra <= 3 * lead_bytes * status.size + 4 * per_drop * N
