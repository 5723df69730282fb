"""Model-form uncertainty as an input (issue 19 item 2): model choices sampled as weighted
``choice`` distributions under the seed contract, every model choice named in the run's
summary and attributes, and the model-form share of the Sobol' variance."""

import copy
import math
import re

import numpy as np
import pytest
from test_bad_input import toml_text
from test_compare import short_default

from mineburial.analyses.sensitivity import model_form_lines, model_form_share, sobol_analysis
from mineburial.cli import main
from mineburial.ensembles import engine
from mineburial.ensembles.distributions import from_dict
from mineburial.ensembles.runner import run_ensemble
from mineburial.ensembles.sampling import uniforms
from mineburial.kernels.mine import layout
from mineburial.systems.mine import ensemble as mine
from mineburial.systems.mine import model_form
from mineburial.systems.mine.config import example_path
from mineburial.systems.mine.ensemble import summarize

WC = {"distribution": "choice", "values": ["munk_factor", "viscous_crossflow"], "weights": [1.0, 3.0]}
RES = {"distribution": "choice", "values": ["bearing", "friction", "delta"], "weights": [2.0, 1.0, 1.0]}


def with_choices(n=10, **sections):
    raw = short_default(n)
    raw["ensemble"]["coefficients"] = "fixed"  # the model choices given here, none from the posterior
    for path, table in sections.items():
        section, name = path.split("__")
        raw.setdefault(section, {})[name] = copy.deepcopy(table)
    return raw


# ---------------------------------------------------------------------------
# sampling
# ---------------------------------------------------------------------------
def test_adding_a_sampled_model_choice_leaves_every_other_draw_unchanged():
    """Seed contract: the stream of a field is keyed by its name, so adding the sampled
    water-column model and resistance law changes no other input of any drop."""
    raw = short_default(64)
    raw["ensemble"]["coefficients"] = "fixed"  # start from no model choice (none from the posterior)
    plain = engine.load_ensemble(raw)
    mixed = engine.load_ensemble(with_choices(64, numerics__water_column=WC, sediment__resistance=RES))
    _, _, before = mine.chunk_inputs(plain, 0, 64)
    _, _, after = mine.chunk_inputs(mixed, 0, 64)
    assert set(after) - set(before) == {"numerics.water_column", "sediment.resistance"}
    for path, values in before.items():
        np.testing.assert_array_equal(after[path], values, err_msg=path)


def test_sampled_choice_codes_follow_the_weights_through_the_cumulative_weights():
    """The code of drop i is label j for cum[j-1] <= u_i < cum[j], u_i the field's own
    Philox uniform (sampling.uniforms), and the labels' codes are kernels.mine.layout's."""
    n = 4000
    spec = engine.load_ensemble(with_choices(n, sediment__resistance=RES))
    P, valid, inputs = mine.chunk_inputs(spec, 0, n)
    u = uniforms(spec.seed, ["sediment.resistance"], 0, n, "mc")[:, 0]
    label = np.where(u < 0.5, "bearing", np.where(u < 0.75, "friction", "delta"))
    expected = np.array([layout.RESISTANCE_NAMES.index(v) for v in label], dtype=np.float64)
    np.testing.assert_array_equal(P[:, layout.P_SED_RESISTANCE], expected)
    np.testing.assert_array_equal(inputs["sediment.resistance"], expected)
    share = np.mean(expected == layout.RESISTANCE_NAMES.index("bearing"))
    assert abs(share - 0.5) < 4 * math.sqrt(0.25 / n)  # binomial, 4 sigma
    assert valid.all()


def test_each_drop_with_a_sampled_water_column_equals_the_run_with_its_model_fixed():
    """Invariance: a drop drawn with label k gives bit for bit the burial of the same drop
    (same other inputs, by the seed contract) in the run with the model fixed to k."""
    n = 6
    sampled = run_ensemble(with_choices(n, numerics__water_column=WC), seed=4, per_drop=True)
    code = sampled["input_numerics_water_column"].values
    assert 0 < np.count_nonzero(code == 1) < n  # both models drawn (seed 4)
    for k, label in enumerate(layout.WATER_COLUMN_NAMES):
        fixed = run_ensemble(with_choices(n, numerics__water_column=label), seed=4, per_drop=True)
        pick = code == k
        np.testing.assert_array_equal(sampled.burial_volume.values[pick], fixed.burial_volume.values[pick])
        np.testing.assert_array_equal(
            sampled.penetration_depth.values[pick], fixed.penetration_depth.values[pick]
        )


@pytest.mark.parametrize(
    "table, message",
    [
        ({"distribution": "choice", "values": ["munk_factor", "strip"]}, r"'strip' not one of munk_factor"),
        ({"distribution": "choice", "values": [0.0, 1.0]}, r"only vary as a 'choice' among .* of numbers"),
        (
            {"distribution": "uniform", "low": 0.0, "high": 1.0},
            r"only vary as a 'choice' among .* got uniform",
        ),
    ],
)
def test_bad_sampled_water_column_is_one_line_exit_2(tmp_path, capsys, table, message):
    path = tmp_path / "s.toml"
    path.write_text(toml_text(with_choices(4, numerics__water_column=table)))
    assert main(["run", str(path), "-n", "2", "-o", str(tmp_path / "o.nc")]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "Traceback" not in err
    assert re.search(r"numerics\.water_column", err) and re.search(message, err)


def test_munk_factor_can_be_sampled_continuously():
    table = {"distribution": "uniform", "low": 0.0, "high": 1.0}
    spec = engine.load_ensemble(with_choices(200, numerics__munk_factor=table))
    P, valid, _ = mine.chunk_inputs(spec, 0, 200)
    u = uniforms(spec.seed, ["numerics.munk_factor"], 0, 200, "mc")[:, 0]
    np.testing.assert_array_equal(P[:, layout.P_MUNK], u)  # uniform(0, 1): ppf(u) = u
    assert valid.all()


# ---------------------------------------------------------------------------
# reporting
# ---------------------------------------------------------------------------
def test_every_model_choice_is_named_fixed_or_sampled():
    spec = engine.load_ensemble(example_path("default_soft_mud_model_form"))
    got = model_form.choices(spec)
    assert list(got) == list(model_form.REPORTED)
    assert got["numerics.model"] == "fixed: mineburial"
    assert got["numerics.integrator"] == "fixed: dopri5_ros34pw2"
    assert got["numerics.munk_factor"] == "fixed: 0.0"
    assert got["sediment.rate_law"] == "fixed: semilog"
    assert got["numerics.water_column"] == "sampled: choice of munk_factor (0.5), viscous_crossflow (0.5)"
    assert got["sediment.resistance"] == "sampled: choice of bearing (0.5), friction (0.25), delta (0.25)"


def test_run_output_attributes_and_summary_name_the_model_choices(tmp_path):
    ds = run_ensemble(with_choices(4, numerics__water_column=WC), seed=2)
    assert ds.attrs["model_choice_numerics_water_column"] == (
        "sampled: choice of munk_factor (0.25), viscous_crossflow (0.75)"
    )
    assert ds.attrs["model_choice_sediment_resistance"] == "fixed: bearing"  # the model's default
    text = summarize(ds)
    for path in model_form.REPORTED:
        assert f"  {path}: " in text
    assert "  numerics.water_column: sampled: choice of munk_factor (0.25)" in text


# ---------------------------------------------------------------------------
# model-form share of the variance
# ---------------------------------------------------------------------------
def _additive(a, b):
    """y = a * code(water column) + b * x, x ~ U(0, 1), the code a fair 0/1 choice:
    V = a^2/4 + b^2/12 and the model-form share (a^2/4) / V, first and total order alike."""
    inputs = {
        "numerics.water_column": from_dict(
            {"distribution": "choice", "values": list(layout.WATER_COLUMN_NAMES)}, "numerics.water_column"
        ),
        "mine.mass": from_dict({"distribution": "uniform", "low": 0.0, "high": 1.0}, "mine.mass"),
    }
    ds = sobol_analysis(
        lambda v: (a * v["numerics.water_column"] + b * v["mine.mass"])[None, :],
        inputs,
        2**12,
        seed=3,
        n_resamples=19,
    )
    return model_form_share(ds), (a * a / 4) / (a * a / 4 + b * b / 12)


@pytest.mark.parametrize("a, b", [(1.0, 1.0), (1.0, 3.0)])
def test_model_form_share_of_an_additive_model_is_its_closed_form(a, b):
    ds, exact = _additive(a, b)
    assert float(ds.model_form_first_order.sel(output="y")) == pytest.approx(exact, abs=0.02)
    assert float(ds.model_form_total_order.sel(output="y")) == pytest.approx(exact, abs=0.02)
    assert "numerics.water_column" in "\n".join(model_form_lines(ds))


def test_model_form_share_is_one_when_only_the_model_is_uncertain_and_zero_when_fixed():
    only, exact = _additive(1.0, 0.0)
    assert exact == 1.0
    assert float(only.model_form_first_order.sel(output="y")) == pytest.approx(1.0, abs=0.02)
    assert float(only.model_form_total_order.sel(output="y")) == pytest.approx(1.0, abs=0.02)
    inputs = {
        k: from_dict({"distribution": "uniform", "low": 0.0, "high": 1.0}, k)
        for k in ("mine.mass", "mine.length")
    }
    fixed = model_form_share(
        sobol_analysis(lambda v: (v["mine.mass"] + v["mine.length"])[None, :], inputs, 2**6, 1, n_resamples=9)
    )
    assert float(fixed.model_form_first_order.sel(output="y")) == 0.0
    assert float(fixed.model_form_total_order.sel(output="y")) == 0.0
    assert fixed.model_form_first_order.attrs["model_form_inputs"] == "none"


def only_water_column_uncertain(table):
    """The short default with every input fixed at its centre except the water-column model."""
    raw = short_default(10)
    raw["ensemble"]["coefficients"] = "fixed"
    centre = {
        "normal": lambda v: v["mean"],
        "truncated_normal": lambda v: v["mean"],
        "uniform": lambda v: 0.5 * (v["low"] + v["high"]),
        "lognormal": lambda v: v["median"],
    }
    for section in ("mine", "release", "environment", "sediment"):
        for key, value in raw[section].items():
            if isinstance(value, dict) and "distribution" in value:
                raw[section][key] = centre[value["distribution"]](value)
    raw["release"]["velocity"][0] = 3.0
    raw["release"]["angular_velocity"][1] = 0.5
    raw["environment"]["current"]["surface_velocity"][0] = 0.5
    raw["numerics"]["water_column"] = table
    return raw


def test_sensitivity_of_a_scenario_whose_only_uncertainty_is_the_model_gives_it_the_whole_variance():
    from mineburial.analyses.sensitivity import run_sensitivity

    wc = {"distribution": "choice", "values": list(layout.WATER_COLUMN_NAMES)}
    ds = run_sensitivity(only_water_column_uncertain(wc), n=16, seed=1)
    assert list(ds.input.values) == ["numerics.water_column"]
    for out in ("penetration_depth", "burial_volume"):
        assert float(ds.output_variance.sel(output=out)) > 0  # the two models differ here
        assert float(ds.model_form_first_order.sel(output=out)) == pytest.approx(1.0, abs=0.05)
        assert float(ds.model_form_total_order.sel(output=out)) == pytest.approx(1.0, abs=0.05)
    # the same scenario with the model fixed and the mass uncertain: no model-form share
    raw = only_water_column_uncertain("viscous_crossflow")
    raw["mine"]["mass"] = {"distribution": "normal", "mean": 750.0, "std": 15.0}
    raw["release"]["pitch_deg"] = {"distribution": "uniform", "low": 0.0, "high": 30.0}
    fixed = run_sensitivity(raw, n=4, seed=1)
    assert float(fixed.model_form_first_order.sel(output="burial_volume")) == 0.0
    assert fixed.model_form_first_order.attrs["model_form_inputs"] == "none"
