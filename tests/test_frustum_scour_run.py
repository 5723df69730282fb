"""The scour stage of the Manta-like example (``manta_scour``) over a chunk of drops, from given rest
states (the impact phase is not run here: tests/test_frustum_drop.py covers it): the frustum stands
on its base with the impact's buried volume, and its burial measures at each lead time are the
standing frustum's closed forms (docs/scour.md, Standing body)."""

import math

import numpy as np
import pytest

from mineburial.ensembles import engine
from mineburial.kernels.mine import layout
from mineburial.kernels.mine import scour as sc
from mineburial.kernels.mine import status as status_codes
from mineburial.kernels.mine.bodies.shapes import frustum_centroid_offset
from mineburial.systems.mine import ensemble as em
from mineburial.systems.mine.config import example_path
from mineburial.systems.mine.processes import scour

N = 6


def standing_volume_fraction(b, length, r_base, r_top):
    """Fraction of a frustum standing on its base below a bed ``b`` above the base (closed form)."""
    b = min(max(b, 0.0), length)
    r_b = r_base - (r_base - r_top) * b / length
    part = math.pi * b / 3.0 * (r_base**2 + r_base * r_b + r_b**2)
    whole = math.pi * length / 3.0 * (r_base**2 + r_base * r_top + r_top**2)
    return part / whole


@pytest.fixture(scope="module")
def chunk():
    spec = engine.load_ensemble(example_path("manta_scour"), n=N, chunk_size=N, systems=engine.SYSTEMS)
    P, _, inputs = em.chunk_inputs(spec, 0, N)
    stage = spec.process("scour")
    length, r_base = P[:, layout.P_LENGTH], 0.5 * P[:, layout.P_DIAMETER]
    r_top = r_base * P[:, layout.P_TOP_RATIO]
    chi_m = P[:, layout.P_CHI] + frustum_centroid_offset(length, r_base, r_top)
    base_below_com = 0.5 * length + chi_m  # the base's distance below the COM, axis vertical
    b0 = np.linspace(0.0, 0.2, N)  # the impact left the base b0 below the bed, standing level
    summary = np.full((N, layout.N_SUMMARY), np.nan)
    summary[:, layout.S_FINAL_PITCH] = -90.0  # nose (top) up: a_z = +1
    summary[:, layout.S_COM_DEPTH] = b0 - base_below_com  # COM height above the bed: base_below_com - b0
    summary[:, layout.S_PENETRATION] = b0
    status = np.full(N, status_codes.AT_REST)
    out = scour.run_chunk(stage, P, summary, status, inputs)
    return stage, P, b0, out, (length, r_base, r_top)


def test_the_standing_frustum_starts_from_the_impacts_burial(chunk):
    stage, P, b0, out, (length, r_base, r_top) = chunk
    assert np.all(out["scour:status"] == sc.SCOUR_OK)
    j0 = list(stage.lead_times_days).index(0.0)
    m = out["scour:measures"][:, :, j0]
    np.testing.assert_allclose(m[:, 0], b0, atol=1e-12)  # penetration of the base
    expected = [100.0 * standing_volume_fraction(b, L, R, r) for b, L, R, r in zip(b0, length, r_base, r_top)]
    np.testing.assert_allclose(m[:, 1], expected, rtol=1e-9, atol=1e-9)
    np.testing.assert_allclose(m[:, 2], 100.0 * b0 / length, rtol=1e-9, atol=1e-9)  # by height
    np.testing.assert_allclose(m[:, 4], length - b0, rtol=1e-12)  # height proud


def test_the_storm_buries_it_monotonically_within_its_height(chunk):
    stage, P, b0, out, (length, r_base, r_top) = chunk
    pen = out["scour:measures"][:, 0, :]
    order = np.argsort(stage.lead_times_days)
    assert np.all(np.diff(pen[:, order], axis=1) >= -1e-15)  # burial never decreases
    assert np.all(pen <= length[:, None] + 1e-12)
    # the measures at each lead time are the standing frustum's closed forms of its burial
    vol = np.array(
        [
            [100.0 * standing_volume_fraction(b, L, R, r) for b in row]
            for row, L, R, r in zip(pen, length, r_base, r_top)
        ]
    )
    np.testing.assert_allclose(out["scour:measures"][:, 1, :], vol, rtol=1e-9, atol=1e-9)
    # no rolling criterion for a body on its flat base
    assert np.all(out["scour:mobile_lead"] == 0.0) and np.all(np.isinf(out["scour:mobile"]))
    # the storm (Hs to 2.5 m at 10 s, 0.4 m/s current, 12 m) scours: the burial grows
    assert np.all(pen[:, order[-1]] > pen[:, order[0]])


def test_manta_scour_end_to_end(tmp_path, capsys):
    """Four drops of the example through ``mineburial run``: impact, rest, scour. The stage's lead-0
    burial by volume is the impact's (the standing frustum keeps the buried volume: a conservation
    statement), each lead time's burial by volume is the standing frustum's closed form of its
    penetration, and the summary prints the levels as fractions of the height."""
    from mineburial.cli import main

    out = tmp_path / "manta.nc"
    path = str(example_path("manta_scour"))
    assert main(["run", path, "-n", "4", "--per-drop", "--threads", "1", "-o", str(out), "--quiet"]) == 0
    assert "B/h >= 0.5" in capsys.readouterr().out
    import xarray as xr

    with xr.open_dataset(out) as ds:
        assert np.all(ds["scour_status"].values == sc.SCOUR_OK)
        np.testing.assert_allclose(
            ds["scour_burial_volume"].values[:, 0], ds["burial_volume"].values, atol=1e-9
        )
        top = ds["input_mine_top_ratio"].values
        pen = ds["scour_penetration_depth"].values
        vol = np.array(
            [
                [100.0 * standing_volume_fraction(b, 0.44, 0.49, 0.49 * t) for b in row]
                for row, t in zip(pen, top)
            ]
        )
        np.testing.assert_allclose(ds["scour_burial_volume"].values, vol, rtol=1e-9, atol=1e-9)
        np.testing.assert_allclose(ds["scour_height_proud"].values, 0.44 - pen, atol=1e-12)
        assert np.all(pen[:, -1] > pen[:, 0]) and np.all(pen <= 0.44 + 1e-12)  # the storm scours, within h
