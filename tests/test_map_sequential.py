"""Per-cell sequential stopping of burial maps (``run_map(..., target_half_width=...)``).

Independent references: for each cell, ``run_ensemble`` of the cell's scenario written out by
hand (tests/test_maps.py's ``cell_reference``) with the cell seed from its documented SHA-256
definition and ``n`` = the drops the map says the cell used -- the map must hold exactly its
statistics; the stopping rule checked against the Wilson score interval computed here from its
closed form (Wilson 1927; z = scipy's normal quantile) on the classes of that run's first drops;
and the map's invariance under chunk size, thread count and resume.
"""

import math

import numba
import numpy as np
import pytest
import xarray as xr
from scipy.stats import norm
from test_maps import _scenario, cell_reference, expected_seed, uniform_environment

from mineburial.analyses.maps import MapError, check_stopping, run_map
from mineburial.cli import main
from mineburial.ensembles import engine
from mineburial.ensembles.runner import run_ensemble

SEED = 2024
MAX, MIN, STEP, TARGET = 32, 8, 8, 0.2
CLASSES = {(0, 0): "soft_clay", (0, 1): "firm_clay", (1, 1): "stiff_clay"}  # (1, 0) is land
CODES = {"soft_clay": 1, "firm_clay": 3, "stiff_clay": 4}
CURRENT = {"kind": "power_law", "surface_velocity": [0.02, -0.01], "exponent": 0.2}
COMPUTE_CHUNK = engine.compute_chunk


def _varied(d):
    """A wide mass and release height: the burial class varies from drop to drop in firm and stiff
    clay (about 0.1 s a drop), and is nearly always '> 75 %' in soft clay."""
    d["mine"]["mass"] = {"distribution": "uniform", "low": 20.0, "high": 400.0}
    d["release"]["position"] = [0.0, 0.0, {"distribution": "uniform", "low": 0.5, "high": 6.0}]
    return d


def scenario():
    return _varied(_scenario())


def environment():
    env = uniform_environment()
    for (j, i), name in CLASSES.items():
        env["sediment_class"].values[j, i] = CODES[name]
    return env


def reference(j, i, n, per_drop=False):
    """``mineburial run`` of cell (j, i) with its seed and ``n`` drops."""
    d = _varied(cell_reference(3.0, {"class": CLASSES[(j, i)]}, CURRENT))
    return run_ensemble(d, n=n, seed=expected_seed(SEED, j * 2 + i), per_drop=per_drop)


Z95 = norm.ppf(0.975)


def wilson_half_width(k, n, z=Z95):
    """Half the width of the Wilson score interval of k successes in n trials (Wilson 1927)."""
    p = k / n
    return z / (1.0 + z * z / n) * math.sqrt(p * (1.0 - p) / n + z * z / (4.0 * n * n))


def stops_at(classes, m):
    """Whether the rule stops a cell after the drops whose burial classes are ``classes[:m]``."""
    c = classes[:m]
    c = c[c >= 0]
    if c.size == 0:
        return False
    return all(wilson_half_width(int(np.count_nonzero(c == k)), c.size) < TARGET for k in range(5))


@pytest.fixture(scope="module")
def seq_map(tmp_path_factory):
    out = tmp_path_factory.mktemp("seq") / "map.nc"
    ds = run_map(
        scenario(), environment(), n=MAX, seed=SEED, chunk_size=5,
        target_half_width=TARGET, min_drops=MIN, step=STEP, output=out,
    )  # fmt: skip
    return ds, out


def test_a_stopped_cell_is_exactly_the_plain_run_of_its_first_drops_and_the_rule_holds(seq_map):
    ds, _ = seq_map
    used = ds["cell_drop_count"].values
    assert used[1, 0] == 0  # land
    assert sorted(int(used[c]) for c in CLASSES) != [MAX] * 3, "no cell stopped early: a weak test"
    for j, i in CLASSES:
        m = int(used[j, i])
        assert m in range(MIN, MAX + 1, STEP)  # a decision point: 8, 16, 24, 32
        ref = reference(j, i, m, per_drop=True)
        for name in ("burial_class_count", "burial_class_probability", "burial_class_probability_lower",
                     "burial_class_probability_upper", "status_count", "burial_volume_mean",
                     "penetration_depth_quantile"):  # fmt: skip
            assert np.array_equal(ds[name].values[..., j, i], ref[name].values, equal_nan=True), (name, j, i)
        classes = ref["burial_class"].values
        for earlier in range(MIN, m, STEP):  # the cell went on at every earlier decision point
            assert not stops_at(classes, earlier), (j, i, earlier)
        assert m == MAX or stops_at(classes, m), (j, i, m)
        half = (ds["burial_class_probability_upper"] - ds["burial_class_probability_lower"]).values[
            :, j, i
        ] / 2
        assert m == MAX or np.all(half < TARGET)
    assert int(ds.attrs["n_drops_total"]) == int(used.sum())
    assert ds.attrs["n_drops_per_cell"] == MAX
    assert '"target_half_width": 0.2' in ds.attrs["sequential_stopping"]


def test_the_map_does_not_depend_on_the_chunk_size_or_the_threads(seq_map):
    ds, _ = seq_map
    before = numba.get_num_threads()
    numba.set_num_threads(1)
    try:
        other = run_map(
            scenario(), environment(), n=MAX, seed=SEED, chunk_size=3,
            target_half_width=TARGET, min_drops=MIN, step=STEP,
        )  # fmt: skip
    finally:
        numba.set_num_threads(before)
    for name in ds.data_vars:
        assert np.array_equal(ds[name].values, other[name].values, equal_nan=True), name


def test_an_interrupted_sequential_map_resumes_to_the_same_map_computing_only_what_is_missing(
    seq_map, tmp_path, monkeypatch
):
    ds, clean = seq_map
    out = tmp_path / "map.nc"
    calls = []

    def dying(spec, start, stop):
        if len(calls) == 4:
            raise KeyboardInterrupt
        calls.append((start, stop))
        return COMPUTE_CHUNK(spec, start, stop)

    monkeypatch.setattr(engine, "compute_chunk", dying)
    kw = dict(n=MAX, seed=SEED, chunk_size=5, target_half_width=TARGET, min_drops=MIN, step=STEP)
    with pytest.raises(KeyboardInterrupt):
        run_map(scenario(), environment(), output=out, **kw)
    kept = sum(e - s for s, e in calls)
    assert kept == 16  # (0-5, 5-8, 8-13, 13-16) of the first cell: chunks end at the decision points
    redone = []
    monkeypatch.setattr(
        engine, "compute_chunk", lambda spec, s, e: (redone.append(e - s), COMPUTE_CHUNK(spec, s, e))[1]
    )
    resumed = run_map(scenario(), environment(), output=out, **kw)
    assert sum(redone) == int(ds["cell_drop_count"].values.sum()) - kept
    back, ref = xr.load_dataset(out), xr.load_dataset(clean)
    for name in ds.data_vars:
        assert np.array_equal(resumed[name].values, ds[name].values, equal_nan=True), name
        assert np.array_equal(back[name].values, ref[name].values, equal_nan=True), name


def test_a_plain_map_records_n_drops_in_every_computed_cell():
    ds = run_map(_scenario(), uniform_environment(), n=2, seed=1)
    computed = ds["cell_status"].values == 0
    assert np.all(ds["cell_drop_count"].values[computed] == 2)
    assert np.all(ds["cell_drop_count"].values[~computed] == 0)
    assert ds["cell_drop_count"].attrs["units"] == "1"
    assert "sequential_stopping" not in ds.attrs


def test_sobol_cells_stop_only_at_powers_of_two():
    stop = check_stopping(0.1, 3, None, 64, "sobol")
    assert stop.points(64) == [4, 8, 16, 32, 64]
    assert check_stopping(0.1, 10, 5, 40, "mc").points(40) == [10, 15, 20, 25, 30, 35, 40]
    assert check_stopping(0.1, None, None, 40, "mc").points(40) == [40]  # min_drops: 100 capped at n
    assert check_stopping(0.1, None, None, 1000, "mc").points(1000) == list(range(100, 1001, 100))


@pytest.mark.parametrize(
    "target,min_drops,step,needles",
    [
        (0.0, None, None, ["target_half_width (--target-half-width) = 0.0", "(0, 0.5]"]),
        (0.6, None, None, ["= 0.6", "(0, 0.5]"]),
        (float("nan"), None, None, ["= nan", "(0, 0.5]"]),
        ("0.1", None, None, ["= '0.1'"]),
        (0.1, 50, None, ["min_drops (--min-drops) = 50", "[1, 40]"]),
        (0.1, 0, None, ["min_drops (--min-drops) = 0", "[1, 40]"]),
        (0.1, 10, 0, ["step (--step) = 0", "[1, 40]"]),
        (0.1, 10, 2.5, ["step (--step) = 2.5"]),
        (None, 10, None, ["min_drops (--min-drops) = 10", "give target_half_width"]),
        (None, None, 4, ["step (--step) = 4", "give target_half_width"]),
    ],
)
def test_bad_stopping_settings_are_refused_naming_the_field_value_and_range(target, min_drops, step, needles):
    with pytest.raises(MapError) as err:
        check_stopping(target, min_drops, step, 40, "mc")
    for needle in needles:
        assert needle in str(err.value), (needle, str(err.value))


def test_the_cli_refuses_a_bad_target_before_computing_and_reports_the_drops_saved(
    tmp_path, capsys, monkeypatch
):
    env = tmp_path / "env.nc"
    uniform_environment().to_netcdf(env)
    scen = tmp_path / "s.toml"
    scen.write_text(  # nothing random: every drop of a cell is the same drop
        "[mine]\nlength = 1.0\ndiameter = 0.25\nmass = 80.0\n"
        "[release]\nposition = [0.0, 0.0, 1.0]\n[environment]\nwater_depth = 20.0\n"
        '[sediment]\nclass = "sand"\n[numerics]\nt_max = 3.0\n'
    )
    computed = []
    monkeypatch.setattr(
        engine, "compute_chunk", lambda spec, s, e: (computed.append(e - s), COMPUTE_CHUNK(spec, s, e))[1]
    )
    argv = ["map", str(scen), "--environment", str(env), "-o", str(tmp_path / "m.nc"), "-n", "40", "--quiet"]
    assert main(argv + ["--target-half-width", "0.7"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "--target-half-width" in err and "(0, 0.5]" in err
    assert computed == []
    assert main(argv + ["--target-half-width", "0.2", "--min-drops", "4", "--step", "4"]) == 0
    text = capsys.readouterr().out
    ds = xr.load_dataset(tmp_path / "m.nc")
    total = int(ds["cell_drop_count"].sum())
    # a fixed mine, release and bed: every drop in one class, k = n, Wilson half-width z^2 / (2 (n + z^2))
    z2 = norm.ppf(0.975) ** 2
    first = next(m for m in range(4, 41, 4) if z2 / (2 * (m + z2)) < 0.2)
    assert first == 8 and np.all(ds["cell_drop_count"].values[ds["cell_status"].values == 0] == first)
    assert sum(computed) == total == 3 * first
    assert f"{total} drops in all" in text and "3 cells stopped early" in text


def test_a_sequential_map_on_a_dask_cluster_equals_the_local_map():
    distributed = pytest.importorskip("distributed")
    kw = dict(n=12, seed=SEED, chunk_size=3, target_half_width=0.3, min_drops=4, step=4)
    local = run_map(scenario(), environment(), **kw)
    with (
        distributed.LocalCluster(
            n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None, silence_logs=50
        ) as cluster,
        distributed.Client(cluster) as client,
    ):
        dist = run_map(scenario(), environment(), client=client, **kw)
    assert int(local["cell_drop_count"].values.sum()) < 3 * 12  # some cell stopped early
    for name in local.data_vars:
        assert np.array_equal(local[name].values, dist[name].values, equal_nan=True), name
