"""Sobol' sensitivity (issue 10 item 3): the Ishigami function against its closed forms."""

import math

import numpy as np
import pytest

from mineburial.analyses.sensitivity import ranking, run_sensitivity, sobol_analysis
from mineburial.ensembles.distributions import from_dict
from mineburial.io.dataset import registry_mismatches

A, B = 7.0, 0.1


def ishigami(x):
    return (np.sin(x["x1"]) + A * np.sin(x["x2"]) ** 2 + B * x["x3"] ** 4 * np.sin(x["x1"]))[None, :]


def ishigami_closed_forms(a=A, b=B):
    """Ishigami & Homma (1990); Sobol' & Levitan (1999): variance decomposition of
    f = sin x1 + a sin^2 x2 + b x3^4 sin x1 with x_i ~ U(-pi, pi):
    V1 = (1 + b pi^4/5)^2 / 2, V2 = a^2/8, V13 = 8 b^2 pi^8/225, V3 = 0."""
    v1 = 0.5 * (1.0 + b * math.pi**4 / 5.0) ** 2
    v2 = a * a / 8.0
    v13 = 8.0 * b * b * math.pi**8 / 225.0
    v = a * a / 8.0 + b * math.pi**4 / 5.0 + b * b * math.pi**8 / 18.0 + 0.5
    assert v == pytest.approx(v1 + v2 + v13, rel=1e-14)  # the two forms of V agree
    return np.array([v1, v2, 0.0]) / v, np.array([v1 + v13, v2, v13]) / v


def uniform_pi(name):
    return from_dict({"distribution": "uniform", "low": -math.pi, "high": math.pi}, name)


def test_ishigami_indices_within_0_02_of_closed_forms():
    inputs = {k: uniform_pi(k) for k in ("x1", "x2", "x3")}
    ds = sobol_analysis(ishigami, inputs, 2**14, seed=7, n_resamples=99)
    s1, st = ishigami_closed_forms()
    np.testing.assert_allclose(ds.first_order.sel(output="y"), s1, atol=0.02)
    np.testing.assert_allclose(ds.total_order.sel(output="y"), st, atol=0.02)
    # the intervals are intervals around the estimate
    assert np.all(ds.first_order_lower <= ds.first_order + 1e-12)
    assert np.all(ds.total_order_upper >= ds.total_order - 1e-12)
    assert ranking(ds, "y") == ["x1", "x2", "x3"]


def test_non_uniform_inputs_map_through_their_ppf():
    """y = x1 + x2 with x1 ~ N(0, 1), x2 ~ lognormal(sigma = 0.5): S_i = var_i / sum, the
    same for first and total order (additive)."""
    inputs = {
        "x1": from_dict({"distribution": "normal", "mean": 3.0, "std": 1.0}, "x1"),
        "x2": from_dict({"distribution": "lognormal", "median": 1.0, "sigma": 0.5}, "x2"),
    }
    v2 = (math.exp(0.25) - 1.0) * math.exp(0.25)  # variance of the lognormal
    expected = np.array([1.0, v2]) / (1.0 + v2)
    ds = sobol_analysis(lambda x: (x["x1"] + x["x2"])[None, :], inputs, 2**12, seed=1, n_resamples=99)
    np.testing.assert_allclose(ds.first_order[0], expected, atol=0.02)
    np.testing.assert_allclose(ds.total_order[0], expected, atol=0.02)


def test_same_seed_same_indices_and_intervals():
    inputs = {k: uniform_pi(k) for k in ("x1", "x2", "x3")}
    a = sobol_analysis(ishigami, inputs, 2**8, seed=3, n_resamples=49)
    b = sobol_analysis(ishigami, inputs, 2**8, seed=3, n_resamples=49)
    for name in a.data_vars:
        np.testing.assert_array_equal(a[name], b[name])
    assert registry_mismatches(a, "sensitivity") == []  # every variable as declared, Conventions


def test_bad_sample_size():
    with pytest.raises(ValueError, match="power of two"):
        sobol_analysis(ishigami, {"x1": uniform_pi("x1")}, 100, seed=1)


def test_scenario_sensitivity_runs_every_random_input():
    """Tiny design on a short variant of the default ensemble: every random input gets an
    index, the indices lie near [0, 1] and burial and penetration both appear."""
    from test_compare import short_default

    ds = run_sensitivity(short_default(), n=4, seed=1)
    assert set(ds.input.values) == {
        "mine.mass",
        "release.velocity[0]",
        "release.pitch_deg",
        "release.angular_velocity[1]",
        "environment.water_depth",
        "environment.current.surface_velocity[0]",
        "sediment.density",
        "sediment.strength",
        "sediment.strength_gradient",
        # the default draws its open coefficients from the shipped posterior: one input, the set
        "calibration.posterior_set",
    }
    assert int(ds.attrs["n_evaluations"]) == 4 * (10 + 2)  # n (d + 2), d = 10 inputs
    assert list(ds.output.values)[:2] == ["penetration_depth", "burial_volume"]


def test_cli_writes_netcdf_and_plot(tmp_path, capsys):
    pytest.importorskip("matplotlib")
    import xarray as xr

    from mineburial.cli import main

    out, png = tmp_path / "s.nc", tmp_path / "s.png"
    assert main(["sensitivity", "-n", "2", "--seed", "3", "--quiet", "-o", str(out), "--plot", str(png)]) == 0
    assert "first order S_i" in capsys.readouterr().out
    assert png.stat().st_size > 0
    with xr.open_dataset(out) as ds:
        assert ds.first_order.dims == ("output", "input") and ds.sizes["input"] == 10


def test_cli_bad_sample_size_is_one_line(capsys):
    from mineburial.cli import main

    assert main(["sensitivity", "-n", "100"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "power of two" in err[0]
