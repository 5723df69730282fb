"""``mineburial compare``: the same sampled drops under each variant (issue 10 item 2)."""

import copy

import numpy as np
import pytest
import tomllib
import xarray as xr

from mineburial.analyses.compare import ComparisonError, parse_vary, run_comparison
from mineburial.cli import main
from mineburial.ensembles.runner import run_ensemble
from mineburial.io.dataset import registry_mismatches
from mineburial.systems.mine.ensemble import DEFAULT_SCENARIO


def short_default(n=10):
    """The embedded default ensemble released 2 m above a 5 m deep seabed (short drops);
    every random input of the default is kept."""
    with open(DEFAULT_SCENARIO, "rb") as fh:
        raw = copy.deepcopy(tomllib.load(fh))
    raw["environment"]["water_depth"] = {"distribution": "uniform", "low": 4.5, "high": 5.5}
    raw["release"]["position"] = [0.0, 0.0, -2.0]
    raw["numerics"]["t_max"] = 10.0
    raw["ensemble"].update({"n": n, "chunk_size": 4})
    return raw


@pytest.fixture(scope="module")
def resistances():
    return run_comparison(short_default(), "sediment.resistance", ["bearing", "friction", "delta"], seed=5)


def test_every_variant_equals_its_own_ensemble_run(resistances):
    """Variant k is bit-identical to `mineburial run` on the scenario with the field set to
    value k: the inputs are the run's own draws, and nothing else changed."""
    for k, value in enumerate(["bearing", "friction", "delta"]):
        raw = short_default()
        raw["sediment"]["resistance"] = value
        ref = run_ensemble(raw, seed=5, per_drop=True)
        np.testing.assert_array_equal(resistances.drop_burial_volume[k], ref.burial_volume)
        np.testing.assert_array_equal(resistances.drop_penetration_depth[k], ref.penetration_depth)
        np.testing.assert_array_equal(resistances.drop_status[k], ref.status)
        for name in [v for v in ref.data_vars if v.startswith("input_")]:
            np.testing.assert_array_equal(resistances[name], ref[name])
        np.testing.assert_array_equal(resistances.burial_class_probability[k], ref.burial_class_probability)
        for side in ("lower", "upper"):  # the default draws from the posterior: the run's epistemic band
            name = f"burial_class_probability_epistemic_{side}"
            np.testing.assert_array_equal(resistances[name][k], ref[name])


def test_only_the_varied_field_changes(resistances):
    assert list(resistances.changed_parameters.values) == ["", "sediment.resistance", "sediment.resistance"]
    assert registry_mismatches(resistances, "comparison") == []  # every variable from the registry
    assert resistances.variant.attrs["long_name"] == "value of sediment.resistance"
    assert resistances.penetration_depth_mean_difference_lower.attrs["long_name"] == (
        "lower 95% bound of the paired difference (normal approximation)"
    )
    # the variants do differ in their results
    assert not np.array_equal(resistances.drop_burial_volume[0], resistances.drop_burial_volume[2])


def test_paired_difference_is_the_mean_of_per_drop_differences(resistances):
    d = (resistances.drop_penetration_depth[2] - resistances.drop_penetration_depth[0]).values
    assert resistances.penetration_depth_mean_difference[2] == pytest.approx(d.mean(), rel=1e-12)
    half = 1.959963984540054 * d.std(ddof=1) / np.sqrt(d.size)
    assert resistances.penetration_depth_mean_difference_upper[2] == pytest.approx(d.mean() + half, rel=1e-12)


def test_model_variant_switches_the_model_defaults_only():
    raw = short_default(n=4)
    raw["ensemble"]["coefficients"] = "fixed"  # the models' own defaults, none drawn from the posterior
    ds = run_comparison(raw, "model", ["mineburial", "impact35"], seed=2)
    # the model defaults: resistance, rate law, integrator and tolerances (impact35 keeps dopri5
    # at rtol 1e-5, atol 1e-6)
    assert set(ds.changed_parameters.values[1].split()) == {
        "numerics.model",
        "numerics.integrator",
        "numerics.rtol",
        "numerics.atol",
        "sediment.resistance",
        "sediment.rate_law",
    }


def test_parse_vary():
    assert parse_vary("resistance=bearing,delta") == ("sediment.resistance", ["bearing", "delta"])
    assert parse_vary("sediment.impact_factor=5,10.5") == ("sediment.impact_factor", [5, 10.5])
    for bad in ("resistance", "resistance=bearing", "resistance=a,a"):
        with pytest.raises(ComparisonError):
            parse_vary(bad)


def test_random_field_cannot_be_varied():
    with pytest.raises(ComparisonError, match="random in the scenario"):
        run_comparison(short_default(n=2), "mine.mass", [700.0, 800.0])


def test_cli_writes_table_netcdf_and_plot(tmp_path, capsys):
    pytest.importorskip("matplotlib")
    out, png = tmp_path / "c.nc", tmp_path / "c.png"
    assert (
        main(
            [
                "compare",
                "-n",
                "3",
                "--vary",
                "sediment.impact_factor=5,10",
                "--quiet",
                "-o",
                str(out),
                "--plot",
                str(png),
            ]
        )
        == 0
    )
    text = capsys.readouterr().out
    assert "| sediment.impact_factor | 5 | 10 |" in text
    assert png.stat().st_size > 0
    with xr.open_dataset(out) as ds:
        assert list(ds.variant.values) == ["5", "10"]
        assert ds.burial_class_probability.dims == ("variant", "impact_burial_class")


def test_cli_error_is_one_line(capsys):
    assert main(["compare", "--vary", "mine.mass=1,2", "-n", "2"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("mineburial: error: --vary mine.mass")


def test_plot_with_bounds_equal_to_the_estimate_up_to_rounding(resistances, tmp_path):
    """Regression: on the default ensemble the delta variant buries every drop 100 %; the
    Wilson upper bound of P(> 75 %) = 1 came out 2.2e-16 below it and matplotlib refused the
    negative error bar."""
    pytest.importorskip("matplotlib")
    from mineburial.analyses.compare import plot_comparison

    ds = resistances.copy(deep=True)
    p = ds.burial_class_probability.values
    ds["burial_class_probability_upper"].values[:] = p - 2.220446049250313e-16
    ds["burial_volume_mean_lower"].values[:] = ds.burial_volume_mean.values + 1e-14
    plot_comparison(ds, tmp_path / "c.png")
    assert (tmp_path / "c.png").stat().st_size > 0
