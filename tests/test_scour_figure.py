"""The lead-time figure of a run with a ``[scour]`` section (issue 20 item 6; ``mineburial run
--plot``): it is checked before computing (a scenario without the section, an image type matplotlib
cannot write: one line, exit 2, nothing computed), it draws what the run's Dataset holds, and the
share of drops flagged mobile by each lead time is the count of the per-drop first mobility times."""

import numpy as np
import pytest
import tomllib
import xarray as xr
from test_scour_run import scenario, scour_section

from mineburial.cli import main
from mineburial.ensembles import engine
from mineburial.systems.mine.config import dumps_toml
from mineburial.systems.mine.figures import lead_time_series
from mineburial.systems.mine.processes import scour

N = 8
LEADS = [0.0, 0.1, 0.25, 0.5, 1.0]  # days
#: a 24 h storm in 2.5-3.5 m of water: the small cylinders lie proud on stiff clay after impact and
#: are flagged mobile as it builds up (at 8 h), so the mobile share changes with lead time
STORM = dict(peak_hs=0.8, peak_tp=8.0, duration_h=12.0, total_h=24.0, current=0.4, background_hs=0.05)


@pytest.fixture
def no_computing(monkeypatch):
    def fail(spec, start, stop):
        raise AssertionError("a drop was computed")

    monkeypatch.setattr(engine, "compute_chunk", fail)


@pytest.fixture(scope="module")
def drawn(tmp_path_factory):
    pytest.importorskip("matplotlib")
    tmp = tmp_path_factory.mktemp("scour_figure")
    # the self-check is tested in tests/test_accuracy_check.py
    path = scenario(tmp, {"storm": STORM, "lead_times_days": LEADS}, accuracy_check=0)
    d = tomllib.loads(path.read_text())
    d["sediment"]["class"] = "stiff_clay"
    path.write_text(dumps_toml(d))
    out, png = tmp / "out.nc", tmp / "lead.png"
    assert main(["run", str(path), "-o", str(out), "--plot", str(png), "--quiet"]) == 0
    with xr.open_dataset(out) as ds:
        return ds.load(), png


def test_run_plot_writes_the_lead_time_figure(drawn):
    import matplotlib.image

    _, png = drawn
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    height, width, _ = matplotlib.image.imread(png).shape
    assert width > height > 200  # two panels side by side


def test_mobile_share_by_lead_time_counts_the_per_drop_first_mobility_times(drawn):
    ds, _ = drawn
    first = ds["scour_mobile_time"].values  # days; inf: never flagged
    want = [np.count_nonzero(first <= lead) / N for lead in LEADS]
    np.testing.assert_array_equal(ds["scour_mobile_fraction_by_lead_time"].values, want)
    assert ds["scour_mobile_fraction_by_lead_time"].values[-1] == float(ds["scour_mobile_fraction"])
    assert want[0] == 0 < want[-1]  # drops are flagged as the storm builds: the count moves


def test_figure_draws_the_datasets_class_probabilities_and_volume_quantiles(drawn):
    ds, _ = drawn
    s = lead_time_series(ds)
    vol = ds["scour_burial_volume"].values  # per drop (n, lead)
    np.testing.assert_allclose(s["volume_median"], np.quantile(vol, 0.5, axis=0), rtol=1e-12)
    np.testing.assert_allclose(s["volume_q95"], np.quantile(vol, 0.95, axis=0), rtol=1e-12)
    np.testing.assert_allclose(s["p"].sum(axis=1), 1.0, rtol=1e-12)
    assert np.all((s["lower"] <= s["p"]) & (s["p"] <= s["upper"]))


def test_mobile_share_without_drops_is_nan_not_zero():
    assert np.isnan(scour.mobile_by_lead_time(np.array([]), [0.0, 1.0])).all()


@pytest.mark.parametrize(
    "with_scour, plot, needle",
    [
        (False, "lead.png", "has none"),
        (True, "lead.nosuchtype", "unsupported image type '.nosuchtype'"),
    ],
)
def test_bad_plot_is_one_line_before_computing(tmp_path, capsys, no_computing, with_scour, plot, needle):
    pytest.importorskip("matplotlib")
    path = scenario(tmp_path, scour_section(tmp_path) if with_scour else None)
    argv = ["run", str(path), "-o", str(tmp_path / "out.nc"), "--plot", str(tmp_path / plot), "--quiet"]
    assert main(argv) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and needle in err, err
    assert not (tmp_path / "out.nc").exists() and not (tmp_path / plot).exists()


def test_forecast_reference_time_is_the_forcing_start_plus_the_common_window_start():
    """Issue 33 item 7a: CF forecast_reference_time, the date of lead time 0, written as seconds
    since 1970-01-01 UTC (reference: datetime arithmetic); none without dates or with windows
    that start at different times."""
    import dataclasses
    import datetime as dt

    from mineburial.io import forcing as fio

    dated = fio.storm_series(
        peak_hs=1.0, peak_tp=8.0, duration_h=12.0, total_h=48.0, start="2003-01-15T00:00Z"
    )
    spec = scour.ScourSpec((0.0,), (0.5,), "whitehouse", False, {}, dated, {})
    assert scour.reference_time(spec) == np.datetime64("2003-01-15T00:00:00")
    windowed = dataclasses.replace(spec, window_days=1.0)
    six_h = [{"scour:window_start": np.full(3, 6 * 3600.0)}]
    assert scour.reference_time(windowed, six_h) == np.datetime64("2003-01-15T06:00:00")
    assert scour.reference_time(windowed, [{"scour:window_start": np.array([0.0, 3600.0])}]) is None
    assert scour.reference_time(windowed) is None  # a map: the windows are not known
    storm = {"peak_hs": 1.0, "peak_tp": 8.0, "duration_h": 12.0}  # no start: its default is no date
    undated = dataclasses.replace(
        spec, forcing=fio.storm_series(**storm), forcing_record={"forcing_storm": storm}
    )
    assert scour.reference_time(undated) is None
    da = scour.reference_time_variable(np.datetime64("2003-01-15T06:00:00"))
    utc = dt.timezone.utc
    want = (dt.datetime(2003, 1, 15, 6, tzinfo=utc) - dt.datetime(1970, 1, 1, tzinfo=utc)).total_seconds()
    assert float(da) == want and da.attrs["standard_name"] == "forecast_reference_time"
    decoded = xr.decode_cf(xr.Dataset(coords={"forecast_reference_time": da}))
    assert decoded["forecast_reference_time"].values == np.datetime64("2003-01-15T06:00:00")
