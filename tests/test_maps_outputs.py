"""The map's figure and GeoTIFF go through the one checked, atomic writer (issue 35, items 1
and 3): a hard link at the path is replaced as a name (the user's file it shares is untouched),
a symbolic link planted while the map computes is refused (single panel and lead-time panels),
and a full disk or a file-size limit is one line naming the file, exit 2, with the earlier
file kept.

The map is computed once (a small map with ``[scour]``); the command-line tests replace
``run_map`` by a function that returns it (and plants the link, as a hostile neighbour would
while the map computes), so nothing is computed twice. Independent references: the bytes of
the user's file and of the earlier output before the command, ``os.lstat`` (a link stays a
link, a hard link count), the PNG signature, and rasterio reading the GeoTIFF back.
"""

import errno
import os
import subprocess
import sys
import textwrap

import numpy as np
import pytest
import rasterio
from test_maps import SEED, _scenario, uniform_environment
from test_maps_scour import forcing_csv, scour_section, with_scour

from mineburial.analyses import maps
from mineburial.cli import main
from mineburial.systems.mine.config import dumps_toml

pytest.importorskip("matplotlib")
PNG = b"\x89PNG\r\n\x1a\n"


@pytest.fixture(scope="module")
def computed(tmp_path_factory):
    """A 2 x 2 map with lead times 0, 0.01, 0.5 d (one land cell), its scenario, environment and
    NetCDF file."""
    tmp = tmp_path_factory.mktemp("mapout")
    sec = scour_section(forcing_csv(tmp / "const.csv"))
    scen = tmp / "scour.toml"
    scen.write_text(dumps_toml(with_scour(_scenario(), sec)))
    env = tmp / "env.nc"
    uniform_environment().to_netcdf(env)
    ds = maps.run_map(scen, env, n=2, seed=SEED, output=tmp / "map.nc")
    return tmp, scen, env, ds


@pytest.fixture
def cli(computed, tmp_path, monkeypatch):
    """``main(map ...)`` with ``run_map`` returning the computed map after ``during()``."""
    _, scen, env, ds = computed
    during = []

    def fake_run_map(*args, **kw):
        for act in during:
            act()
        return ds

    monkeypatch.setattr(maps, "run_map", fake_run_map)
    argv = ["map", str(scen), "--environment", str(env), "-o", str(tmp_path / "out.nc"), "-n", "2", "--quiet"]
    return argv, during


def one_line(capsys, *needles):
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.startswith("mineburial: error: "), err
    assert "Traceback" not in err
    for needle in needles:
        assert needle in err, (needle, err)


PANELS = {"single": [], "lead-times": ["--lead-times", "0,0.5"]}


@pytest.mark.parametrize("panels", PANELS)
def test_a_plot_path_that_is_a_hard_link_leaves_the_users_file_untouched(cli, tmp_path, panels):
    """Was: the user's file (the other name of the inode) overwritten with the PNG."""
    argv, _ = cli
    user = tmp_path / "thesis.txt"
    user.write_bytes(b"the user's own file")
    png = tmp_path / "p.png"
    os.link(user, png)
    assert main(argv + ["--plot", str(png)] + PANELS[panels]) == 0
    assert user.read_bytes() == b"the user's own file" and os.stat(user).st_nlink == 1
    assert png.read_bytes()[:8] == PNG and not os.path.samefile(png, user)


@pytest.mark.parametrize("panels", PANELS)
def test_a_symlink_planted_at_the_plot_while_the_map_computes_is_refused(cli, tmp_path, capsys, panels):
    """Was: followed, the link's target overwritten with the PNG."""
    argv, during = cli
    target = tmp_path / "target.txt"
    target.write_bytes(b"precious")
    png = tmp_path / "p.png"
    during.append(lambda: png.symlink_to(target))
    assert main(argv + ["--plot", str(png)] + PANELS[panels]) == 2
    one_line(capsys, str(png), "symbolic link")
    assert png.is_symlink() and os.readlink(png) == str(target) and target.read_bytes() == b"precious"
    assert not list(tmp_path.glob(".p.png.*.tmp"))


def test_a_symlink_planted_at_the_geotiff_while_the_map_computes_is_refused(cli, tmp_path, capsys):
    argv, during = cli
    target = tmp_path / "target.txt"
    target.write_bytes(b"precious")
    tif = tmp_path / "p.tif"
    during.append(lambda: tif.symlink_to(target))
    assert main(argv + ["--geotiff", str(tif)]) == 2
    one_line(capsys, str(tif), "symbolic link")
    assert tif.is_symlink() and target.read_bytes() == b"precious"


@pytest.mark.parametrize("option,name", [("--plot", "p.png"), ("--geotiff", "p.tif")])
def test_a_full_disk_while_writing_the_figure_or_geotiff_names_it_and_keeps_the_earlier_file(
    cli, tmp_path, capsys, monkeypatch, option, name
):
    """Was: a 0-byte PNG and an error naming no file; for the GeoTIFF "wrote p.tif", exit 0,
    0 bytes. ENOSPC injected in the writer's write (as a full disk raises it)."""
    argv, _ = cli
    out = tmp_path / name
    out.write_bytes(b"an earlier good file")
    real_open = open

    class FullDisk:
        def __init__(self, fh):
            self.fh = fh

        def write(self, data):
            self.fh.write(data[: len(data) // 2])
            raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))

        def __getattr__(self, attr):
            return getattr(self.fh, attr)

        def __enter__(self):
            return self

        def __exit__(self, *exc):
            self.fh.close()

    def full_open(file, mode="r", *a, **kw):
        fh = real_open(file, mode, *a, **kw)
        if "w" in mode and os.path.basename(str(file)).startswith(f".{name}."):
            return FullDisk(fh)
        return fh

    import builtins

    import matplotlib.backends.backend_agg  # noqa: F401 -- imported before open is patched

    monkeypatch.setattr(builtins, "open", full_open)
    assert main(argv + [option, str(out)]) == 2
    monkeypatch.undo()
    one_line(capsys, str(out), "No space left on device")
    assert out.read_bytes() == b"an earlier good file"
    assert sorted(p.name for p in tmp_path.iterdir()) == [name]


LIMITED = textwrap.dedent(
    """
    import resource, signal, sys
    import xarray as xr
    from mineburial.analyses import maps
    from mineburial.cli import main

    saved = xr.load_dataset(sys.argv[1])
    maps.run_map = lambda *a, **kw: saved

    def limited(real):
        def write(*a, **kw):  # the file-size limit holds while the figure or GeoTIFF is written
            signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
            resource.setrlimit(resource.RLIMIT_FSIZE, (512, resource.RLIM_INFINITY))
            return real(*a, **kw)
        return write

    maps.plot_map = limited(maps.plot_map)
    maps.write_geotiff = limited(maps.write_geotiff)
    sys.exit(main(sys.argv[2:]))
    """
)


@pytest.mark.parametrize("option,name", [("--plot", "p.png"), ("--geotiff", "p.tif")])
def test_a_file_size_limit_on_the_figure_or_geotiff_is_one_line_exit_2_earlier_file_kept(
    computed, tmp_path, option, name
):
    """RLIMIT_FSIZE (SIGXFSZ ignored: the write fails with EFBIG, as on a full disk) of 512
    bytes, below the size of the file (a 2 x 2 GeoTIFF has about 1 kB, the PNG 50 kB). Was for
    the GeoTIFF: exit 0, "wrote p.tif", a truncated file in place of the good one (GDAL's error
    only on stderr)."""
    pytest.importorskip("resource")
    src, scen, env, _ = computed
    out = tmp_path / name
    out.write_bytes(b"an earlier good file")
    argv = ["map", str(scen), "--environment", str(env), "-o", str(tmp_path / "o.nc"), "--quiet"]
    argv += [option, str(out)]
    proc = subprocess.run(
        [sys.executable, "-c", LIMITED, str(src / "map.nc"), *argv],
        capture_output=True,
        text=True,
        timeout=120,
        env={**os.environ, "PYTHONPATH": os.pathsep.join(sys.path)},
    )
    assert proc.returncode == 2, proc.stderr
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith(f"mineburial: error: {out}: File too large"), proc.stderr
    assert f"wrote {out}" not in proc.stdout
    assert out.read_bytes() == b"an earlier good file"
    assert not list(tmp_path.glob(f".{name}.*.tmp"))


def test_the_geotiff_written_reads_back_as_the_maps_field(cli, computed, tmp_path, capsys):
    """The verified write still writes the field: read back by rasterio, P(> 75 %) of the
    computed cells and NaN on land."""
    argv, _ = cli
    ds = computed[3]
    tif = tmp_path / "p.tif"
    assert main(argv + ["--geotiff", str(tif)]) == 0
    assert f"wrote {tif}" in capsys.readouterr().out
    with rasterio.open(tif) as r:
        band = r.read(1)
    want = ds["burial_class_probability"].values[4][::-1]  # north up
    computed_cells = ds["cell_status"].values[::-1] == maps.CELL_COMPUTED
    np.testing.assert_array_equal(band[computed_cells], want[computed_cells].astype(np.float32))
    assert np.isnan(band[~computed_cells]).all()


def test_the_writer_refuses_an_empty_or_short_file_and_keeps_the_earlier_one(tmp_path):
    """A library that reports a failed write only on stderr (GDAL) leaves an empty or short
    file and returns: the one writer checks it before the rename."""
    from mineburial.io.files import atomic_path

    path = tmp_path / "out.png"
    path.write_bytes(b"earlier")
    with pytest.raises(OSError, match="empty") as caught:
        with atomic_path(path) as tmp:
            tmp.write_bytes(b"")
    assert caught.value.filename == str(path)

    def verify(tmp):
        if tmp.read_bytes()[:8] != PNG:
            raise OSError(errno.EIO, "not a PNG", str(path))

    with pytest.raises(OSError, match="not a PNG"):
        with atomic_path(path, verify=verify) as tmp:
            tmp.write_bytes(PNG[:4])
    assert path.read_bytes() == b"earlier" and sorted(p.name for p in tmp_path.iterdir()) == ["out.png"]


def test_synthetic_help_prints_the_usage_and_writes_no_file(tmp_path):
    """Was: ``python -m mineburial.analyses.synthetic --help`` wrote a grid to a file named ``--help``."""
    proc = subprocess.run(
        [sys.executable, "-m", "mineburial.analyses.synthetic", "--help"],
        capture_output=True,
        text=True,
        timeout=120,
        cwd=tmp_path,
        env={**os.environ, "PYTHONPATH": os.pathsep.join(sys.path)},
    )
    assert proc.returncode == 0 and proc.stdout.startswith("usage: python -m mineburial.analyses.synthetic")
    assert list(tmp_path.iterdir()) == []


@pytest.fixture
def nothing_computed(monkeypatch):
    def fail(*a, **kw):
        raise AssertionError("the map was computed before the check")

    monkeypatch.setattr(maps, "run_map", fail)


def test_geotiff_of_an_unevenly_spaced_grid_is_refused_before_computing(tmp_path, capsys, nothing_computed):
    """Was: refused only after the whole map was computed."""
    from mineburial.analyses.synthetic import synthetic_environment

    env = synthetic_environment(ny=3, nx=2, seed=1)
    env = env.assign_coords(latitude=("latitude", [54.50, 54.51, 54.53], env["latitude"].attrs))
    env.to_netcdf(tmp_path / "env.nc")
    scen = tmp_path / "s.toml"
    scen.write_text(dumps_toml(_scenario()))
    out = tmp_path / "map.nc"
    argv = ["map", str(scen), "--environment", str(tmp_path / "env.nc"), "-o", str(out), "-n", "2"]
    assert main(argv + ["--geotiff", str(tmp_path / "p.tif")]) == 2
    one_line(capsys, "axis 'latitude' is not evenly spaced")
    assert not out.exists() and not (tmp_path / "p.tif").exists()


def test_geotiff_of_a_grid_mapping_pyproj_cannot_read_is_refused_before_computing(
    tmp_path, capsys, nothing_computed
):
    from test_maps import projected_environment

    env = projected_environment()
    env["utm"].attrs["grid_mapping_name"] = "no_such_projection"
    env.to_netcdf(tmp_path / "env.nc")
    scen = tmp_path / "s.toml"
    scen.write_text(dumps_toml(_scenario()))
    out = tmp_path / "map.nc"
    argv = ["map", str(scen), "--environment", str(tmp_path / "env.nc"), "-o", str(out), "-n", "2"]
    assert main(argv + ["--geotiff", str(tmp_path / "p.tif")]) == 2
    one_line(capsys, "grid mapping 'utm' is not a CRS pyproj can read")
    assert not out.exists()


def test_a_land_cells_partly_missing_forcing_does_not_refuse_the_gridded_map(tmp_path):
    """Was: the land cell's series was checked like a water cell's, and its NaN refused the
    whole map. Reference: the same map with the land cell's series missing altogether."""
    import xarray as xr
    from test_maps_scour import LEADS, grid_series

    env = uniform_environment()
    files, grid = grid_series(tmp_path, env)  # the land cell (1, 0) dry: NaN at every time
    with xr.open_dataset(grid) as g:
        patched = g.load()
    hs = patched["hs"].values.copy()
    hs[2:, 1, 0] = 1.0  # the land cell: waves from the third record on, missing before
    patched["hs"].values[:] = hs
    patched.to_netcdf(tmp_path / "land.nc")
    sec = {"forcing_grid": str(tmp_path / "land.nc"), "lead_times_days": LEADS}
    ds = maps.run_map(with_scour(_scenario(), sec), env, n=2, seed=SEED)
    ref = maps.run_map(with_scour(_scenario(), dict(sec, forcing_grid=str(grid))), env, n=2, seed=SEED)
    assert int(ds.attrs["n_cells_computed"]) == 3
    for name in ("scour_burial_volume_mean", "burial_volume_mean"):
        assert np.array_equal(ds[name].values, ref[name].values, equal_nan=True), name
