"""No silent wrong answers (issue 21, items 6 and 7): map grids read by their CF
conventions, conflicting or empty grids refused, no burial numbers for a drop that did not
come to rest, no Sobol' index for a constant output, a warning when drops did not finish.

References: the elevation grids are the negatives of depths written by hand; the Sobol'
indices of y = x0 + 2 x1 (independent uniforms) are S0 = 1/5, S1 = 4/5 in closed form.
"""

import numpy as np
import pytest
import xarray as xr
from conftest import scenario_dict

from mineburial.analyses.maps import CELL_COMPUTED, CELL_LAND, MapError, read_environment, run_map
from mineburial.analyses.synthetic import synthetic_environment
from mineburial.cli import main

DEPTHS = np.array([[12.0, 3.5, np.nan], [20.0, 7.25, 1.0]])  # (0, 2): land


def grid(values=DEPTHS, **attrs):
    """2 x 3 lat/lon grid: water_depth = values with ``attrs``, stiff clay everywhere."""
    env = synthetic_environment(ny=2, nx=3, seed=1).drop_vars(["current_u", "current_v"])
    env["water_depth"] = (("latitude", "longitude"), np.asarray(values, float), {"units": "m", **attrs})
    env["sediment_class"].values[:] = 4
    return env


def refused_line(capsys, argv, *needles):
    rc = main(argv)
    err = capsys.readouterr().err
    assert rc == 2, err
    assert err.count("\n") == 1 and err.startswith("mineburial: error: ") and "Traceback" not in err, err
    for needle in needles:
        assert needle in err, (needle, err)
    return err


# ---------------------------------------------------------------------------
# item 6: grids by their CF conventions
# ---------------------------------------------------------------------------
@pytest.mark.parametrize(
    "attrs",
    [
        {"positive": "up"},
        {"positive": "UP "},
        {"standard_name": "height_above_mean_sea_level"},
        {"standard_name": "altitude"},
        {"standard_name": "height_above_reference_ellipsoid", "positive": "up"},
    ],
)
def test_elevation_grid_is_not_taken_as_depth_land_for_water(attrs):
    """positive = "up" (or an elevation standard_name): the sea is negative. It was read as
    a depth, so the land was computed and the sea skipped."""
    g = read_environment(grid(-DEPTHS, **attrs))
    np.testing.assert_array_equal(g.water_depth, DEPTHS)  # the depths written by hand
    want = np.where(np.isfinite(DEPTHS), CELL_COMPUTED, CELL_LAND)
    np.testing.assert_array_equal(g.cell_status(), want)
    assert g.vertical.startswith("an elevation")


@pytest.mark.parametrize(
    "attrs",
    [
        {},
        {"positive": "down"},
        {"standard_name": "sea_floor_depth_below_sea_surface"},
        {"standard_name": "sea_floor_depth_below_mean_sea_level", "positive": "down"},
        {"standard_name": "depth"},
    ],
)
def test_depth_grid_stays_a_depth(attrs):
    g = read_environment(grid(DEPTHS, **attrs))
    np.testing.assert_array_equal(g.water_depth, DEPTHS)
    assert g.vertical.startswith("a depth")


def test_elevation_grid_runs_the_sea_cells_and_skips_the_land():
    """End to end: the map of an elevation grid computes the two sea cells (their depth
    the negated elevation) and skips the cell above sea level."""
    env = synthetic_environment(ny=1, nx=3, seed=1).drop_vars(["current_u", "current_v"])
    elev = np.array([[-3.0, 2.0, -4.0]])
    env["water_depth"] = (("latitude", "longitude"), elev, {"units": "m", "positive": "up"})
    env["sediment_class"].values[:] = 4
    scen = scenario_dict(environment={"water_depth": 30.0}, release={"position": [0.0, 0.0, 1.0]})
    ds = run_map(scen, env, n=2, seed=5)
    np.testing.assert_array_equal(ds["cell_status"].values, [[CELL_COMPUTED, CELL_LAND, CELL_COMPUTED]])
    np.testing.assert_array_equal(ds["water_depth"].values, [[3.0, np.nan, 4.0]])
    assert ds["status_count"].values[..., 0, 0].sum() == 2 and ds["status_count"].values[..., 0, 1].sum() == 0
    assert "positive = 'up'" in ds["water_depth"].attrs["comment"]


@pytest.mark.parametrize(
    "attrs, message",
    [
        (
            {"positive": "up", "standard_name": "sea_floor_depth_below_sea_surface"},
            "positive = 'up' but its standard_name 'sea_floor_depth_below_sea_surface' is a depth",
        ),
        (
            {"positive": "down", "standard_name": "height_above_mean_sea_level"},
            "positive = 'down' but its standard_name 'height_above_mean_sea_level' is an elevation",
        ),
        ({"positive": "sideways"}, "positive = 'sideways'; CF allows 'up'"),
        ({"standard_name": "surface_altitude"}, "standard_name 'surface_altitude', which is neither"),
    ],
)
def test_contradicting_or_unknown_vertical_attributes_are_refused(attrs, message):
    with pytest.raises(MapError, match="^environment grid: water_depth has ") as exc:
        read_environment(grid(DEPTHS, **attrs))
    assert message in str(exc.value)


def test_all_negative_grid_is_refused_not_0_computed_48_land(tmp_path, capsys):
    """An elevation grid without attributes: every depth <= 0. It said "0 computed, 48
    land" and exited 0."""
    env = synthetic_environment(ny=6, nx=8, seed=0)
    env["water_depth"].values = -np.abs(env["water_depth"].values)
    del env["water_depth"].attrs["standard_name"]
    path = tmp_path / "env.nc"
    env.to_netcdf(path)
    scenario = tmp_path / "s.toml"
    assert main(["example", "default_soft_mud", "-o", str(scenario)]) == 0
    out = tmp_path / "map.nc"
    refused_line(
        capsys,
        ["map", str(scenario), "--environment", str(path), "-o", str(out), "-n", "2", "--quiet"],
        "no cell to compute among its 48: 48 land",
        "give it the attribute positive = 'up'",
    )
    assert not out.exists()


def test_all_land_grid_is_refused():
    with pytest.raises(MapError, match=r"no cell to compute among its 6: 6 land"):
        read_environment(grid(np.full((2, 3), np.nan)))


def test_grid_without_sediment_in_any_water_cell_is_refused():
    env = grid()
    env["sediment_class"].values[:] = -1  # the fill value: no data
    with pytest.raises(MapError, match=r"no cell to compute among its 6: 1 land .* 5 without sediment data"):
        read_environment(env)


@pytest.mark.parametrize("value", [np.inf, -np.inf])
def test_infinite_depth_is_an_error_naming_the_cell_not_land(value):
    d = DEPTHS.copy()
    d[1, 2] = value
    with pytest.raises(MapError) as exc:
        read_environment(grid(d))
    lat = float(synthetic_environment(ny=2, nx=3, seed=1).latitude[1])
    assert f"water_depth is {value} at cell (1, 2) at latitude {lat:.5f}" in str(exc.value)


def test_infinite_current_is_an_error_naming_the_cell_not_missing():
    env = synthetic_environment(ny=2, nx=3, seed=1)
    env["current_v"].values[0, 1] = np.inf
    with pytest.raises(MapError, match=r"current_v is inf at cell \(0, 1\)"):
        read_environment(env)


def test_current_speed_and_current_u_v_together_are_refused_naming_both():
    env = synthetic_environment(ny=2, nx=3, seed=1)
    env["current_speed"] = env["current_u"].assign_attrs(units="m s-1")
    env["current_direction"] = env["current_u"].assign_attrs(units="degree")
    with pytest.raises(
        MapError, match=r"both current_u, current_v and current_speed, current_direction are given"
    ):
        read_environment(env)
    lone = synthetic_environment(ny=2, nx=3, seed=1)
    lone["current_speed"] = lone["current_u"]  # speed alone beside u/v: still two currents
    with pytest.raises(MapError, match=r"both current_u, current_v and current_speed are given"):
        read_environment(lone)


def test_sediment_class_and_linear_sediment_fields_together_are_refused_naming_both():
    env = synthetic_environment(ny=2, nx=3, seed=1)
    for name, units in (("sediment_density", "kg m-3"), ("sediment_strength", "Pa")):
        env[name] = (("latitude", "longitude"), np.full((2, 3), 1.0), {"units": units})
    with pytest.raises(
        MapError, match=r"both sediment_class and sediment_density, sediment_strength are given"
    ):
        read_environment(env)


def test_zero_by_zero_grid_is_one_line_not_a_traceback(tmp_path, capsys):
    env = synthetic_environment(ny=2, nx=3, seed=1).isel(latitude=slice(0, 0), longitude=slice(0, 0))
    path = tmp_path / "empty.nc"
    env.to_netcdf(path)
    scenario = tmp_path / "s.toml"
    assert main(["example", "default_soft_mud", "-o", str(scenario)]) == 0
    refused_line(
        capsys,
        ["map", str(scenario), "--environment", str(path), "-o", str(tmp_path / "m.nc"), "--quiet"],
        "environment grid: water_depth has no cells (shape 0 x 0)",
    )


# ---------------------------------------------------------------------------
# item 7: drop summaries and Sobol' indices
# ---------------------------------------------------------------------------
DROP = """
[mine]
length = 1.0
diameter = 0.25
mass = {mass}
[release]
position = [0.0, 0.0, 1.0]
[environment]
water_depth = 50.0
[sediment]
class = "soft_clay"
[numerics]
t_max = 5.0
t_max_fall = {t_fall}
"""


@pytest.mark.parametrize(
    "mass, t_fall, status",
    [
        (40.0, 60.0, "floated"),  # 40 kg < rho_w V = 50.3 kg: rises back before the seabed
        (120.0, 0.5, "time_limit"),  # still falling through 50 m of water after 0.5 s
    ],
)
def test_drop_that_never_reached_the_seabed_reports_no_penetration_0_m_burial_0(
    tmp_path, capsys, mass, t_fall, status
):
    scen = tmp_path / "d.toml"
    scen.write_text(DROP.format(mass=mass, t_fall=t_fall))
    out = tmp_path / "t.nc"
    assert main(["drop", str(scen), "-o", str(out)]) == 0
    text = capsys.readouterr().out
    assert f"status {status}" in text and "no seabed impact" in text
    assert "no penetration or burial" in text
    assert " m, burial" not in text and "% by volume" not in text and "penetration 0" not in text
    with xr.open_dataset(out) as ds:
        assert ds.attrs["status"] == status
        assert np.isnan(float(ds.impact_time))


def test_sensitivity_of_a_constant_output_is_undefined_not_zero():
    """Output a = x0 + 2 x1 has S0 = 1/5, S1 = 4/5, S2 = 0; output b = 3 is constant: its
    indices are 0 / 0, NaN with index_status 1 (they were printed 0.000 [0.000, 0.000])."""
    from mineburial.analyses.sensitivity import sensitivity_table, sobol_analysis

    class Uniform:
        def ppf(self, u):
            return u

    def model(v):
        return np.stack([v["x0"] + 2 * v["x1"], np.full(v["x0"].shape, 3.0)])

    ds = sobol_analysis(
        model, {k: Uniform() for k in ("x0", "x1", "x2")}, 1024, 7, ("a", "b"), n_resamples=99
    )
    np.testing.assert_array_equal(ds.index_status.values, [0, 1])
    np.testing.assert_allclose(ds.first_order.sel(output="a").values, [0.2, 0.8, 0.0], atol=0.05)
    for name in ("first_order", "total_order", "first_order_lower", "total_order_upper"):
        assert np.all(np.isnan(ds[name].sel(output="b").values)), name
        assert np.all(np.isfinite(ds[name].sel(output="a").values)), name
    table = sensitivity_table(ds)
    b_part = table.split("b (variance")[1]
    assert b_part.count("undefined (output constant)") == 6 and "0.000" not in b_part


def test_sensitivity_warns_when_every_drop_ended_at_its_time_limit(tmp_path, capsys):
    scen = tmp_path / "s.toml"
    scen.write_text(
        "[ensemble]\nn = 4\nseed = 1\n"
        + DROP.format(mass='{distribution = "uniform", low = 110.0, high = 130.0}', t_fall=0.5)
    )
    out = tmp_path / "s.nc"
    assert main(["sensitivity", str(scen), "-n", "2", "--quiet", "-o", str(out)]) == 0
    text = capsys.readouterr().out
    warnings = [line for line in text.splitlines() if line.startswith("warning:")]
    assert warnings == [
        "warning: every drop ended outside the burial statistics (time_limit 6): the indices describe "
        "where unfinished drops stopped, not their burial; lengthen numerics.t_max / t_max_fall or "
        "check the scenario"
    ]
    with xr.open_dataset(out) as ds:
        assert ds.attrs["warning"] == warnings[0]


def test_sensitivity_failure_warning_threshold_is_10_percent():
    from mineburial.analyses.sensitivity import failure_warning
    from mineburial.kernels.mine import status as st

    counts = np.zeros(len(st.NAMES), dtype=int)
    counts[st.AT_REST], counts[st.TIME_LIMIT] = 91, 9
    assert failure_warning(9, 100, counts) is None
    counts[st.AT_REST], counts[st.TIME_LIMIT], counts[st.FLOATED] = 90, 7, 3
    assert failure_warning(10, 100, counts).startswith(
        "warning: 10 of 100 drops (10 %) ended outside the burial statistics (time_limit 7, floated 3)"
    )
