"""A window of the forcing per drop (issue 20, item 3: a start date drawn from a long series):
``scour.window_days`` and the sampled ``scour.window_position``. The compiled window cuts the
series as the tested Python ``forcing.window`` does, each drop's stage over its window is the
stage over that cut series, the new field draws from its own stream (no other input changes),
and bad keys are one line."""

import math

import numpy as np
import pytest
from test_scour_run import N, scenario, scour_section

from mineburial.cli import main
from mineburial.ensembles import runner
from mineburial.io import forcing as fio
from mineburial.kernels.mine import layout
from mineburial.kernels.mine import scour as S
from mineburial.kernels.mine.scour_batch import MEASURE_NAMES, N_REST, R_ZC, forcing_window, scour_drops


def irregular_forcing(n=60, seed=4):
    rng = np.random.default_rng(seed)
    t = np.concatenate([[0.0], np.cumsum(rng.uniform(1800.0, 5400.0, n - 1))])
    return fio.Forcing(
        time=t,
        hs=rng.uniform(0.1, 1.4, n),
        tp=rng.uniform(5.0, 12.0, n),
        wave_from=rng.uniform(0.0, 360.0, n),
        current_speed=rng.uniform(0.0, 0.3, n),
        current_to=rng.uniform(0.0, 360.0, n),
        water_level=rng.uniform(-0.5, 0.5, n),
    )


@pytest.mark.parametrize("offset_frac, length_frac", [(0.0, 0.5), (0.13, 0.31), (0.5, 0.5), (0.37, 0.2)])
def test_compiled_window_cuts_the_series_as_forcing_window_does(offset_frac, length_frac):
    f = irregular_forcing()
    span = f.duration_s
    offset, length = offset_frac * span, length_frac * span
    if offset_frac == 0.37:  # a window that starts and ends exactly on records
        offset, length = float(f.time[11]), float(f.time[30] - f.time[11])
    ref = fio.window(f, offset, length)
    idx = np.empty(len(f) + 1, dtype=np.int64)
    tw = np.empty(len(f) + 1)
    m = forcing_window(np.array(f.time), offset, length, idx, tw)
    assert m == len(ref)
    np.testing.assert_allclose(tw[:m], ref.time, rtol=1e-13, atol=1e-9)
    assert tw[m - 1] == length
    for name in ("hs", "tp", "wave_from", "current_speed", "current_to", "water_level"):
        np.testing.assert_array_equal(getattr(f, name)[idx[:m]], getattr(ref, name), err_msg=name)


def test_each_drop_scours_over_its_own_window():
    f = irregular_forcing()
    span, length = f.duration_s, 0.4 * f.duration_s
    starts = np.array([0.0, 0.2, 0.6]) * (span - length)
    n = starts.size
    table = S.build_orbital_table()
    depth = 12.0
    S_ = np.tile(S.default_parameters(), (n, 1))
    P = np.zeros((n, layout.N_PARAMS))  # the drops' bodies: 2.0 m x 0.53 m cylinders
    P[:, layout.P_LENGTH], P[:, layout.P_DIAMETER] = 2.0, 0.53
    rest = np.zeros((n, N_REST))
    rest[:, R_ZC] = 0.265 - 0.02  # lying, 2 cm in
    leads = np.array([0.0, 0.3, 0.7, 1.0]) * length
    fractions = np.array([0.25, 0.5])
    t, hs, tp, wdir, uc, cdir, _ = f.kernel_arrays(depth)
    measures = np.empty((n, len(MEASURE_NAMES), leads.size))
    time_to, mobile, codes = np.empty((n, 2)), np.empty(n), np.empty(n, dtype=np.int8)
    scour_drops(
        S_, np.ones(n), np.full(n, depth), np.ones(n, dtype=np.uint8), P, rest, t, hs, tp, wdir, uc, cdir,
        np.array(f.water_level), starts, length, table, leads, fractions, measures, time_to, mobile, codes,
        np.empty((n, leads.size)), np.empty((n, leads.size)),
    )  # fmt: skip
    assert np.all(codes == S.SCOUR_OK)
    finals = []
    for i in range(n):
        arrays = fio.window(f, starts[i], length).kernel_arrays(depth)
        burial, want_to = np.empty(leads.size), np.empty(2)
        code, t_mob, _ = S.scour_stage(S_[i], *arrays, table, leads, fractions, burial, want_to)
        assert code == S.SCOUR_OK
        np.testing.assert_allclose(measures[i, 0], burial, rtol=1e-12)
        np.testing.assert_allclose(time_to[i], want_to, rtol=1e-9)
        assert mobile[i] == pytest.approx(t_mob, rel=1e-9) or (math.isinf(mobile[i]) and math.isinf(t_mob))
        finals.append(burial[1])
    assert len(set(np.round(finals, 9))) == n  # the windows differ, so the check is not of a constant


@pytest.fixture(scope="module")
def window_runs(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("scour_window")
    plain = runner.run_ensemble(scenario(tmp, scour_section(tmp, lead_times_days=[0.0, 0.25])))
    window = {"distribution": "uniform", "low": 0.0, "high": 1.0}
    sec = scour_section(tmp, lead_times_days=[0.0, 0.25], window_days=0.5, window_position=window)
    return plain, runner.run_ensemble(scenario(tmp, sec))


def test_window_position_has_its_own_stream_and_no_other_draw_changes(window_runs):
    plain, windowed = window_runs
    pos = windowed["input_scour_window_position"].values
    assert pos.shape == (N,) and np.all((pos >= 0) & (pos <= 1)) and len(set(pos)) == N
    for name, var in plain.variables.items():  # every input and impact output as without windows
        if not str(name).startswith("scour_"):
            assert np.array_equal(var.values, windowed[name].values, equal_nan=var.dtype.kind == "f"), name
    # the forcing is constant, so any window of it gives the whole series' burial (an invariance)
    assert np.all(windowed["scour_status"].values == 0)
    np.testing.assert_allclose(
        windowed["scour_penetration_depth"].values, plain["scour_penetration_depth"].values, rtol=1e-12
    )


@pytest.mark.parametrize(
    "over, needle",
    [
        ({"window_position": 0.5}, "scour.window_position needs scour.window_days"),
        ({"window_days": 2.0}, "scour.window_days = 2 is outside the allowed range (0, 1]"),
        ({"window_days": 0.5, "window_position": 1.5}, "scour.window_position = 1.5 is outside"),
        ({"window_days": 0.01}, "scour.lead_times_days[1] = 0.5 is outside the allowed range [0, 0.01]"),
    ],
)
def test_bad_window_is_one_line(tmp_path, capsys, over, needle):
    path = scenario(tmp_path, scour_section(tmp_path, lead_times_days=[0.0, 0.5], **over))
    assert main(["run", str(path), "-o", str(tmp_path / "out.nc"), "--quiet"]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and needle in err, err
    assert not (tmp_path / "out.nc").exists()
