"""Maps whose cells are seeded by their inputs (``cell_seeds = "inputs"``): cells with identical inputs
share one ensemble, computed once (issue 34 item 5).

Independent references: each cell's statistics against ``run_ensemble`` of the cell's scenario written
out by hand, run with the seed the map records for it (the map must hold exactly that ensemble's
statistics); the number of distinct ensembles against numpy's count of distinct (depth, sediment,
current) rows of the environment; invariances (a cell's seed does not depend on where the cell lies).
"""

import numpy as np
import pytest
from test_maps import STAT_NAMES, _scenario, cell_reference

from mineburial.analyses.maps import MapError, run_map
from mineburial.analyses.synthetic import synthetic_environment
from mineburial.cli import main
from mineburial.ensembles.runner import run_ensemble
from mineburial.systems.mine.sediment_profiles import class_names

N, SEED = 5, 8675309
CURRENT = {"kind": "power_law", "surface_velocity": [0.02, -0.01], "exponent": 0.2}
#: the two environments the water cells take: (depth, sediment class code, its name)
ENVS = ((3.0, 4, "stiff_clay"), (4.0, 0, class_names()[0]))


def two_environment_grid(pattern):
    """A 3 x 3 lat/lon grid, cell (0, 0) land, each water cell environment ENVS[pattern[j][i]]."""
    env = synthetic_environment(ny=3, nx=3, seed=1)
    env["water_depth"].values[0, 0] = np.nan
    for j in range(3):
        for i in range(3):
            if (j, i) == (0, 0):
                continue
            depth, code, _ = ENVS[pattern[j][i]]
            env["water_depth"].values[j, i] = depth
            env["sediment_class"].values[j, i] = code
            env["current_u"].values[j, i] = 0.02
            env["current_v"].values[j, i] = -0.01
    return env


PATTERN = ((0, 0, 1), (1, 0, 1), (0, 1, 0))


@pytest.fixture(scope="module")
def inputs_map():
    env = two_environment_grid(PATTERN)
    return env, run_map(_scenario(), env, n=N, seed=SEED, cell_seeds="inputs")


def test_cells_with_identical_inputs_share_one_ensemble_computed_once(inputs_map):
    env, ds = inputs_map
    wet = ds["cell_status"].values == 0
    rows = np.stack(
        [
            env[v].values[wet].astype(float)
            for v in ("water_depth", "sediment_class", "current_u", "current_v")
        ],
        axis=1,
    )
    distinct = len(np.unique(rows, axis=0))
    assert distinct == 2
    assert int(ds.attrs["n_cells_distinct"]) == distinct
    assert int(ds.attrs["n_drops_total"]) == distinct * N
    assert ds.attrs["cell_seeds"] == "inputs"
    seeds = ds["cell_seed"].values
    groups = {}
    for j, i in zip(*np.nonzero(wet)):
        groups.setdefault(PATTERN[j][i], set()).add(int(seeds[j, i]))
    assert all(len(s) == 1 for s in groups.values())  # one seed per set of identical inputs
    assert groups[0] != groups[1]
    assert int(ds["cell_drop_count"].values[wet].min()) == N  # every cell holds its ensemble's drops


def test_each_cell_holds_the_single_scenario_statistics_of_its_recorded_seed(inputs_map):
    _, ds = inputs_map
    refs = {}
    for j in range(3):
        for i in range(3):
            if ds["cell_status"].values[j, i] != 0:
                continue
            depth, _, name = ENVS[PATTERN[j][i]]
            seed = int(ds["cell_seed"].values[j, i])
            if seed not in refs:
                refs[seed] = run_ensemble(cell_reference(depth, {"class": name}, CURRENT), n=N, seed=seed)
            for stat in STAT_NAMES:
                got = ds[stat].values[..., j, i]
                assert np.array_equal(got, refs[seed][stat].values, equal_nan=True), (stat, j, i)


def test_a_cells_seed_depends_on_its_inputs_not_on_where_it_lies(inputs_map):
    _, ds = inputs_map
    swapped = tuple(tuple(1 - v for v in row) for row in PATTERN)
    ds2 = run_map(_scenario(), two_environment_grid(swapped), n=2, seed=SEED, cell_seeds="inputs")
    wet = ds["cell_status"].values == 0
    a = {PATTERN[j][i]: int(ds["cell_seed"].values[j, i]) for j, i in zip(*np.nonzero(wet))}
    b = {swapped[j][i]: int(ds2["cell_seed"].values[j, i]) for j, i in zip(*np.nonzero(wet))}
    assert a == b
    for stat in ("burial_class_count", "status_count"):  # same inputs, same seed: the same drops
        j0, i0 = next((j, i) for j, i in zip(*np.nonzero(wet)) if PATTERN[j][i] == 0)
        j1, i1 = next((j, i) for j, i in zip(*np.nonzero(wet)) if swapped[j][i] == 0)
        assert int(ds2[stat].values[..., j1, i1].sum()) == 2
        assert int(ds[stat].values[..., j0, i0].sum()) == N


def test_sequential_stopping_with_inputs_seeds_counts_the_drops_computed(tmp_path):
    env = two_environment_grid(PATTERN)
    ds = run_map(
        _scenario(), env, n=8, seed=SEED, cell_seeds="inputs", target_half_width=0.45, min_drops=2, step=2
    )
    wet = ds["cell_status"].values == 0
    used = {}
    for j, i in zip(*np.nonzero(wet)):
        used.setdefault(int(ds["cell_seed"].values[j, i]), set()).add(int(ds["cell_drop_count"].values[j, i]))
    assert all(len(v) == 1 for v in used.values())
    assert int(ds.attrs["n_drops_total"]) == sum(next(iter(v)) for v in used.values())


def test_bad_cell_seeds_is_refused_in_one_line():
    with pytest.raises(MapError, match=r"cell_seeds \(--cell-seeds\) = 'cell'.*'index', 'inputs'"):
        run_map(_scenario(), two_environment_grid(PATTERN), n=2, seed=SEED, cell_seeds="cell")


def test_cli_prints_the_distinct_cells(tmp_path, capsys):
    scen = tmp_path / "s.toml"
    scen.write_text("""
[mine]
length = 1.0
diameter = 0.25
mass = 80.0
[release]
position = [0.0, 0.0, 1.0]
[environment]
water_depth = 20.0
[sediment]
class = "sand"
[numerics]
t_max = 0.5
""")
    env = tmp_path / "env.nc"
    two_environment_grid(PATTERN).to_netcdf(env)
    rc = main(
        [
            "map",
            str(scen),
            "--environment",
            str(env),
            "-o",
            str(tmp_path / "m.nc"),
            "-n",
            "2",
            "--seed",
            "1",
            "--cell-seeds",
            "inputs",
            "--quiet",
        ]
    )
    assert rc == 0
    out = capsys.readouterr().out
    assert "cells with identical inputs computed once: 2 distinct of 8 (4 drops computed)" in out
