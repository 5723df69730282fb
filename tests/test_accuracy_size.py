"""The numerical self-check's size (issue 34 item 2): ``ensemble.accuracy_check = "auto"`` (the
default) re-runs as many drops as take ~15 % of the run's time, at least 8, at most the size that
catches a defect of 1 % of the drops with 90 % probability; an integer is honoured; anything else
is one line naming the field.

Independent references: the detection probability 1 - (1 - q)^n of n drops drawn at random from a
population in which a fraction q fails (at least one failing drop among them), evaluated by direct
products and a brute-force search over n, not through the logarithm the code uses; the time share
as the inequality that defines it, k K <= s (N + k K) (k reference drops of K ensemble drops' cost
each beside N ensemble drops), checked for k and k + 1; hand-worked values at N = 2,000, 10^4, 10^5.
"""

import dataclasses

import numpy as np
import pytest
from conftest import scenario_dict

from mineburial.cli import main
from mineburial.ensembles import engine
from mineburial.errors import ScenarioError
from mineburial.systems.mine import accuracy
from mineburial.systems.mine import ensemble as mine
from mineburial.systems.mine.config import dumps_toml


def least_drops_brute_force(rate, probability=0.9):
    n, missed = 0, 1.0
    while 1.0 - missed < probability:  # missed = (1 - rate)^n, multiplied out
        n += 1
        missed *= 1.0 - rate
    return n


def test_the_cap_is_the_least_size_that_catches_a_1_percent_defect_9_times_in_10():
    cap = least_drops_brute_force(0.01)
    assert cap == 230  # 1 - 0.99^230 = 0.9009, 1 - 0.99^229 = 0.8999
    assert 1 - 0.99**230 >= 0.9 > 1 - 0.99**229
    assert accuracy.drops_needed(0.01) == cap
    for rate in (0.02, 0.05, 0.25):
        assert accuracy.drops_needed(rate) == least_drops_brute_force(rate)
    assert accuracy.default_size(10**6) == cap == accuracy.default_size(10**9)


@pytest.mark.parametrize("n", [1, 7, 100, 2000, 2294])
def test_the_floor_is_8_drops(n):
    assert accuracy.default_size(n) == 8


@pytest.mark.parametrize(
    ("n", "size"),
    # 0.15 N / (0.85 * 45) = N / 255, rounded down, within [8, 230]
    [(2_000, 8), (2_295, 9), (10_000, 39), (25_500, 100), (58_649, 229), (58_650, 230), (100_000, 230)],
)
def test_the_size_at_hand_worked_points(n, size):
    assert accuracy.default_size(n) == size


@pytest.mark.parametrize("n", [2_295, 5_000, 10_000, 33_333, 58_000])
def test_between_floor_and_cap_the_size_is_the_largest_within_the_time_share(n):
    s, k_cost = accuracy.TIME_SHARE, accuracy.CHECK_COST_RATIO
    k = accuracy.default_size(n)
    assert 8 < k < 230
    assert k * k_cost <= s * (n + k * k_cost) + 1e-9
    assert (k + 1) * k_cost > s * (n + (k + 1) * k_cost)


@pytest.mark.parametrize(("n", "percent"), [(2_000, 25.0), (10_000, 5.7), (100_000, 1.0)])
def test_what_the_default_size_detects(n, percent):
    """The failure rate q caught with 90 % probability by the default size at N drops: the q with
    (1 - q)^k = 0.1, checked by the product itself (docs/design.md states these three)."""
    k = accuracy.default_size(n)
    q = accuracy.detectable_rate(k)
    assert np.prod(np.full(k, 1.0 - q)) == pytest.approx(0.1, rel=1e-9)
    assert 100 * q == pytest.approx(percent, abs=0.05)


def test_an_explicit_size_is_honoured_and_0_is_off():
    for value in (0, 1, 8, 17, 500):
        spec = engine.load_ensemble(scenario_dict(ensemble={"accuracy_check": value}), systems=engine.SYSTEMS)
        assert spec.accuracy_check == value
        assert accuracy.check_size(spec.accuracy_check, 10**6) == value
    spec = engine.load_ensemble(scenario_dict(ensemble={"accuracy_check": "auto"}), systems=engine.SYSTEMS)
    assert spec.accuracy_check == "auto"
    assert accuracy.check_size(spec.accuracy_check, 10_000) == 39
    assert accuracy.check_size(spec.accuracy_check, 3) == 8  # choose_drops then takes the 3 run


def test_the_default_is_auto():
    """The shipped default (the suite's conftest sets 0 for its runs)."""
    default = {f.name: f.default for f in dataclasses.fields(mine.EnsembleSpec)}["accuracy_check"]
    assert default == accuracy.AUTO == "auto"


def test_the_chosen_drops_are_a_function_of_seed_status_and_size():
    status = np.zeros(5000, np.int8)
    a = accuracy.choose_drops(11, status, accuracy.default_size(status.size))
    b = accuracy.choose_drops(11, status.copy(), 19)
    assert np.array_equal(a, b) and a.size == 19 and np.all(np.diff(a) > 0)
    assert not np.array_equal(a, accuracy.choose_drops(12, status, 19))


@pytest.mark.parametrize("value", [-1, 1.5, True, "32", "Auto", "", [8]])
def test_a_bad_size_is_one_line_naming_the_field(value):
    with pytest.raises(ScenarioError) as err:
        engine.load_ensemble(scenario_dict(ensemble={"accuracy_check": value}), systems=engine.SYSTEMS)
    text = str(err.value)
    assert text.startswith("ensemble.accuracy_check = ") and "\n" not in text
    assert "[0, inf)" in text and '"auto"' in text


def test_a_bad_size_ends_mineburial_run_with_one_line(tmp_path, capsys):
    path = tmp_path / "bad.toml"
    path.write_text(dumps_toml(scenario_dict(ensemble={"accuracy_check": "many"})))
    assert main(["run", str(path), "-o", str(tmp_path / "out.nc"), "--quiet"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("mineburial: error: ensemble.accuracy_check = 'many'")
    assert not (tmp_path / "out.nc").exists()
