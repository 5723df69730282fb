"""GeoTIFF export of a map's probability field (issue 20): written from small synthetic map
datasets (no kernels) and read back with rasterio. Independent references: the values placed
by hand, the affine transform computed here from the cell edges (midpoints of the coordinates),
and the CRS by pyproj from its EPSG code (a UTM grid) or the WGS 84 ellipsoid (a lat/lon grid).
"""

import sys

import numpy as np
import pyproj
import pytest
import rasterio
import xarray as xr

from mineburial.analyses.maps import MapError, write_geotiff
from mineburial.analyses.synthetic import write_synthetic_environment
from mineburial.cli import main
from mineburial.systems.mine.config import example_path


def synthetic_map(y, x, ydim, xdim, mapping, leads=None):
    """A map dataset as run_map writes it, reduced to what the export reads: P(class k) at
    cell (j, i) = 0.1 k + 0.01 (j * nx + i) (impact) or + 0.001 lead index (after scour)."""
    ny, nx = len(y), len(x)
    cell = np.arange(ny * nx).reshape(ny, nx)
    prob = 0.1 * np.arange(5)[:, None, None] + 0.01 * cell
    status = np.zeros((ny, nx), dtype=np.int8)
    status[0, -1] = 1  # land
    gm = {"grid_mapping": "crs"}
    data = {
        "cell_status": ((ydim, xdim), status, gm),
        "burial_class_probability": (("impact_burial_class", ydim, xdim), prob, gm),
        "crs": ((), np.int32(0), mapping),
    }
    coords = {ydim: (ydim, np.asarray(y, float)), xdim: (xdim, np.asarray(x, float))}
    if ydim == "latitude":
        coords[ydim] = (ydim, np.asarray(y, float), {"units": "degrees_north", "standard_name": "latitude"})
        coords[xdim] = (xdim, np.asarray(x, float), {"units": "degrees_east", "standard_name": "longitude"})
    if leads is not None:
        scour = prob[None] + 0.001 * np.arange(len(leads))[:, None, None, None]
        data["scour_burial_class_probability"] = (("lead_time", "impact_burial_class", ydim, xdim), scour, gm)
        coords["lead_time"] = ("lead_time", np.asarray(leads, float))
    return xr.Dataset(data, coords=coords, attrs={"random_seed": "1", "n_drops_per_cell": 4})


WGS84 = {
    "grid_mapping_name": "latitude_longitude",
    "semi_major_axis": 6378137.0,
    "inverse_flattening": 298.257223563,
    "longitude_of_prime_meridian": 0.0,
}


def test_lat_lon_map_round_trips_values_transform_and_crs(tmp_path):
    lat, lon = [54.50, 54.51, 54.52], [10.30, 10.315, 10.33, 10.345]  # south to north
    ds = synthetic_map(lat, lon, "latitude", "longitude", WGS84, leads=[0.0, 7.0])
    path = write_geotiff(ds, tmp_path / "p.tif", burial_class=3)
    with rasterio.open(path) as r:
        band = r.read(1)
        t, crs = r.transform, r.crs
    expected = ds["burial_class_probability"].values[3][::-1].copy()  # first row: the northernmost
    expected[-1, -1] = np.nan  # the land cell (0, -1), now in the last row
    assert band.dtype == np.float32 and band.shape == (3, 4)
    np.testing.assert_allclose(band, expected, rtol=1e-6)
    assert np.isnan(band[-1, -1]) and np.isfinite(band).sum() == 11
    # edges: half a step beyond the first and last centres
    assert t.a == pytest.approx(0.015) and t.c == pytest.approx(10.30 - 0.0075)
    assert t.e == pytest.approx(-0.01) and t.f == pytest.approx(54.52 + 0.005)
    assert t.b == 0 and t.d == 0
    c = pyproj.CRS.from_wkt(crs.to_wkt())
    assert c.is_geographic and c.ellipsoid.semi_major_metre == 6378137.0
    assert c.ellipsoid.inverse_flattening == pytest.approx(298.257223563)
    # issue 33: the CF latitude_longitude mapping on the WGS 84 ellipsoid is written as EPSG:4326,
    # not as a geographic CRS with an undefined datum (what pyproj.CRS.from_cf reads it as)
    assert pyproj.CRS.from_cf(WGS84).datum.name == "undefined"
    assert crs.to_epsg() == 4326 and c.datum.name.startswith("World Geodetic System 1984")
    # after scour at a lead time: that lead time's field
    path = write_geotiff(ds, tmp_path / "s.tif", lead_time=7.0, burial_class=4)
    with rasterio.open(path) as r:
        band = r.read(1)
    np.testing.assert_allclose(band[0, 0], ds["scour_burial_class_probability"].values[1, 4, 2, 0], rtol=1e-6)
    with pytest.raises(
        MapError, match=r"--lead-time: 3 d is not a lead time of the map; choose among 0, 7 d"
    ):
        write_geotiff(ds, tmp_path / "x.tif", lead_time=3.0)


def test_lat_lon_map_read_back_with_rioxarray_is_epsg_4326(tmp_path):
    rioxarray = pytest.importorskip("rioxarray")
    ds = synthetic_map([54.5, 54.51], [10.3, 10.31, 10.32], "latitude", "longitude", WGS84)
    da = rioxarray.open_rasterio(write_geotiff(ds, tmp_path / "p.tif"))
    assert da.rio.crs.to_epsg() == 4326
    # another ellipsoid (GRS 80 differs in the inverse flattening's 9th digit) keeps its own CRS
    grs80 = {**WGS84, "inverse_flattening": 298.257222101}
    with rasterio.open(
        write_geotiff(
            synthetic_map([1.0, 2.0], [3.0, 4.0], "latitude", "longitude", grs80), tmp_path / "g.tif"
        )
    ) as r:
        assert r.crs.to_epsg() != 4326
        assert pyproj.CRS.from_wkt(r.crs.to_wkt()).ellipsoid.inverse_flattening == pytest.approx(
            298.257222101
        )


def test_projected_north_to_south_map_keeps_its_utm_crs(tmp_path):
    y = [6_050_000.0, 6_049_000.0]  # decreasing: already north up
    x = [560_000.0, 561_000.0, 562_000.0]
    mapping = {"grid_mapping_name": "transverse_mercator", "crs_wkt": pyproj.CRS.from_epsg(32632).to_wkt()}
    ds = synthetic_map(y, x, "y", "x", mapping)
    ds["y"].attrs["standard_name"] = "projection_y_coordinate"
    ds["x"].attrs["standard_name"] = "projection_x_coordinate"
    path = write_geotiff(ds, tmp_path / "utm.tif", burial_class=0)
    with rasterio.open(path) as r:
        band, t, epsg = r.read(1), r.transform, r.crs.to_epsg()
    assert epsg == 32632
    assert (t.a, t.c, t.e, t.f) == (1000.0, 559_500.0, -1000.0, 6_050_500.0)
    np.testing.assert_allclose(band[1], [0.03, 0.04, 0.05], rtol=1e-6)
    assert np.isnan(band[0, 2])


def test_unevenly_spaced_axis_is_refused(tmp_path):
    ds = synthetic_map([54.5, 54.51, 54.53], [10.3, 10.31], "latitude", "longitude", WGS84)
    with pytest.raises(MapError, match="axis 'latitude' is not evenly spaced"):
        write_geotiff(ds, tmp_path / "p.tif")
    assert not (tmp_path / "p.tif").exists()


def test_without_rioxarray_the_map_stops_before_computing_naming_the_extra(tmp_path, monkeypatch, capsys):
    xr.backends.list_engines()  # xarray caches its engines: not while rioxarray is hidden
    monkeypatch.setitem(sys.modules, "rioxarray", None)  # import rioxarray raises ImportError
    env = write_synthetic_environment(tmp_path / "env.nc")
    out = tmp_path / "map.nc"
    args = ["map", str(example_path("default_soft_mud")), "--environment", str(env), "-o", str(out)]
    assert main(args + ["-n", "2", "--geotiff", str(tmp_path / "m.tif")]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "pip install 'mineburial[geotiff]'" in err
    assert not out.exists() and not (tmp_path / "m.tif").exists()
    ds = synthetic_map([1.0, 2.0], [1.0, 2.0], "latitude", "longitude", WGS84)
    with pytest.raises(MapError, match=r"mineburial\[geotiff\]"):
        write_geotiff(ds, tmp_path / "m.tif")
