"""The tilt state of the scour stage (issue 33 items 2 and 5; docs/scour.md, Tilt): ``scour.rest_attitude``.

Every check is against an independent reference (the flat choice's bit-identity with the engine
before the choice existed was measured at the merge, 248 and 251 variables of 30-drop runs of the two
shipped scour examples, and is not a test: a stored output would be the code's own answer): the two ends'
relaxation against scipy's ODE integrator of the pit with the printed laws and the geometry written
out, the lead-0 burial measures against the impact phase's own, closed forms for a vertical and a level
mine, and the tilted moment balance against a dimensional evaluation with scipy's quadrature.
"""

import math
import pathlib

import numpy as np
import pytest
from scipy.integrate import quad, solve_ivp
from test_scour_run import scenario, scour_section
from test_scour_settle import constant_forcing

from mineburial.ensembles import runner
from mineburial.kernels.mine import layout
from mineburial.kernels.mine import scour as S
from mineburial.kernels.mine.scour_batch import MEASURE_NAMES, N_REST, R_AZ, R_ZC, scour_drops_ends

DAY = 86400.0
TABLE = S.build_orbital_table()
D = 0.53
L = 2.0
R = 0.5 * D
CHI = 0.05
SHIPPED = pathlib.Path(__file__).resolve().parent.parent / "mineburial" / "data" / "ensembles"


def tilt_params(b0, h0, **kw):
    base = dict(
        diameter=D, d50=2.0e-4, burial_law=S.BURIAL_SCOUR_SETTLE, rest_attitude=S.REST_IMPACT, b0=b0,
        b0_high=h0, axis_span=L,
    )  # fmt: skip
    base.update(kw)
    return S.default_parameters(**base)


def run(p, forcing, leads, fractions=(0.25, 0.5)):
    n = len(leads)
    ob, op, om, oh = np.empty(n), np.empty(n), np.empty(n), np.empty(n)
    ot = np.empty(len(fractions))
    leads, fractions = np.asarray(leads, dtype=float), np.asarray(fractions, dtype=float)
    code, t_mob, _ = S.scour_stage_ends(p, *forcing, TABLE, leads, fractions, ob, ot, op, om, oh)
    return code, ob, oh, op, om, ot, t_mob


def pit_by_scipy(p, hs, tp, hours):
    """S(t) of the pit under constant waves: dS/dt = (S_eq - S)/T integrated by scipy, S_eq and T
    written out from the printed laws (Sumer & Fredsoe 1990 wave pit with the onset factor,
    Whitehouse 1998 T*) with theta, u_br, T_br of bed_forcing."""
    theta, ub, tb, _ = S.bed_forcing(p, hs, tp, 0.0, 0.0, 0.0, 12.0, TABLE)
    s = p[S.S_RHO_GRAIN] / p[S.S_RHO_WATER]
    dstar = p[S.S_D50] * (p[S.S_G] * (s - 1.0) / p[S.S_NU] ** 2) ** (1.0 / 3.0)
    tc = 0.30 / (1.0 + 1.2 * dstar) + 0.055 * (1.0 - math.exp(-0.020 * dstar))
    kc = ub * tb / D
    s_eq = D * (1.0 - tc / theta) * p[S.S_WAVE_A] * kc ** p[S.S_WAVE_KC_EXP]
    t_scale = 0.014 * theta**-1.29 * D**2 / math.sqrt(9.81 * (s - 1.0) * 2.0e-4**3)
    sol = solve_ivp(
        lambda _, y: [(s_eq - y[0]) / t_scale], (0.0, hours * 3600.0), [0.0], rtol=1e-11, atol=1e-14,
        dense_output=True,
    )  # fmt: skip
    return s_eq, (lambda t_s: sol.sol(t_s)[0])


# --- the two ends under constant forcing -----------------------------------------------------------


def test_the_higher_end_settles_into_the_pit_and_the_mine_levels():
    """Both ends in the sand (B0 = 0.30 m, H0 = 0.05 m): the pit S(t) (scipy) passes the higher end,
    which follows it, max(H0, S); the lower end waits, max(B0, S); the tilt asin((B - H)/L) falls
    and is 0 once S passes B0, when the mine lies level in its pit."""
    b0, h0 = 0.30, 0.05
    p = tilt_params(b0, h0, wave_a=0.45)
    s_eq, pit = pit_by_scipy(p, 1.5, 9.0, 48.0)
    assert s_eq > b0  # the pit passes both ends
    leads = np.array([0.0, 0.05, 0.2, 0.5, 1.0, 2.0, 4.0, 8.0, 24.0, 48.0]) * 3600.0
    code, ob, oh, op, om, _, _ = run(p, constant_forcing(48.0), leads)
    assert code == S.SCOUR_OK
    s = pit(leads)
    np.testing.assert_allclose(op, s, rtol=1e-8, atol=1e-12)
    np.testing.assert_allclose(oh, np.maximum(h0, s), rtol=1e-8, atol=1e-12)
    np.testing.assert_allclose(ob, np.maximum(b0, s), rtol=1e-8, atol=1e-12)
    tilt = np.degrees(np.arcsin((np.maximum(b0, s) - np.maximum(h0, s)) / L))
    got = np.degrees(np.arcsin([S.tilt_sine(b, h, L) for b, h in zip(ob, oh)]))
    np.testing.assert_allclose(got, tilt, rtol=1e-7, atol=1e-9)
    assert got[0] == pytest.approx(math.degrees(math.asin(0.25 / L)), rel=1e-12)
    assert np.all(np.diff(got) <= 1e-12) and got[-1] == 0.0 and 0.0 < got[3] < got[0]


def test_a_proud_end_is_held_until_the_pit_reaches_the_lower_end():
    """A nose-down mine (B0 = 0.30 m, its tail 0.6 m above the bed, H0 = -0.6 m): the proud end does
    not follow the pit; when the pit reaches the lower end the mine lies in it (B = H = S)."""
    b0, h0 = 0.30, -0.60
    p = tilt_params(b0, h0, wave_a=0.45)
    _, pit = pit_by_scipy(p, 1.5, 9.0, 48.0)
    leads = np.array([0.0, 0.2, 1.0, 4.0, 24.0, 48.0]) * 3600.0
    code, ob, oh, op, _, _, _ = run(p, constant_forcing(48.0), leads)
    assert code == S.SCOUR_OK
    s = pit(leads)
    before = s < b0
    assert before[:2].all() and not before[-1]
    np.testing.assert_allclose(oh[before], h0, rtol=0, atol=1e-15)
    np.testing.assert_allclose(oh[~before], s[~before], rtol=1e-8)
    np.testing.assert_allclose(ob, np.maximum(b0, s), rtol=1e-8)


def test_infill_never_lifts_an_end_and_a_lowering_bed_keeps_the_tilt():
    """Calm water (no scour): the pit stays 0, the ends stay; a far-field bed lowering at r lowers
    both ends, B = max(B0 - r t, 0), the tilt kept (H = B - (B0 - H0)) while the lower end is
    embedded; once the bed reaches it (B = 0) nothing holds the tilt and the mine lies on the bed."""
    b0, h0, r = 0.2, 0.05, 0.05 / DAY
    calm = constant_forcing(24.0 * 10, hs=0.2, tp=6.0)
    leads = np.array([0.0, 1.0, 3.0, 5.0, 9.0]) * DAY
    code, ob, oh, op, _, _, _ = run(tilt_params(b0, h0), calm, leads)
    assert code == S.SCOUR_OK and np.all(op == 0.0)
    np.testing.assert_array_equal(ob, b0)
    np.testing.assert_array_equal(oh, h0)
    code, ob, oh, _, _, _, _ = run(tilt_params(b0, h0, bed_rate=r), calm, leads)
    want_b = np.maximum(b0 - r * leads, 0.0)
    np.testing.assert_allclose(ob, want_b, rtol=1e-12, atol=1e-15)
    embedded = want_b > 0.0
    assert embedded[:3].all() and not embedded[3:].any()
    np.testing.assert_allclose((ob - oh)[embedded], b0 - h0, rtol=1e-12)
    np.testing.assert_array_equal(oh[~embedded], 0.0)


def test_a_level_mine_under_the_impact_choice_is_the_flat_choice():
    """H0 = B0: every output of the stage (burial, pit, times to the levels, mobility) bit for bit
    as under REST_FLAT with the same B0; the higher end is the burial throughout."""
    forcing = constant_forcing(48.0, hs=1.6, tp=9.0, uc=0.3)
    leads = np.array([0.0, 0.5, 2.0, 6.0, 24.0, 48.0]) * 3600.0
    for b0 in (0.0, 0.03, 0.2):
        kw = dict(wave_a=0.3, mobility=S.MOBILITY_POCKET)
        flat = run(
            S.default_parameters(diameter=D, burial_law=S.BURIAL_SCOUR_SETTLE, b0=b0, **kw), forcing, leads
        )
        tilted = run(tilt_params(b0, b0, **kw), forcing, leads)
        for k in (0, 1, 3, 4, 5, 6):
            np.testing.assert_array_equal(flat[k], tilted[k])
        np.testing.assert_array_equal(tilted[2], tilted[1])


def test_impact_needs_scour_settle_and_a_possible_tilt():
    forcing = constant_forcing(2.0)
    assert (
        run(tilt_params(0.2, 0.1, burial_law=S.BURIAL_RENNIE), forcing, [0.0])[0] == S.SCOUR_INVALID_PARAMETER
    )
    assert run(tilt_params(0.2, 0.3), forcing, [0.0])[0] == S.SCOUR_INVALID_PARAMETER  # H > B
    assert run(tilt_params(0.2, 0.2 - 1.01 * L), forcing, [0.0])[0] == S.SCOUR_INVALID_PARAMETER  # sin > 1
    assert run(tilt_params(0.2, 0.1, rest_attitude=2.0), forcing, [0.0])[0] == S.SCOUR_INVALID_PARAMETER


# --- mobility of a tilted mine ----------------------------------------------------------------------


@pytest.mark.parametrize("b", [0.0, 0.01, 0.05, 0.1, 0.2, 0.26, 0.3])
def test_tilted_criterion_at_zero_tilt_is_the_level_one(b):
    rigid = 0.011
    assert S.mobility_threshold_tilted(rigid, b, b, D, L, 1.2) == S.mobility_threshold_pocket(
        rigid, b / D, 1.2
    )


@pytest.mark.parametrize("b,h", [(0.10, 0.02), (0.12, -0.3), (0.1, -1.0)])
def test_tilted_criterion_is_the_moment_balance_by_quadrature(b, h):
    """The critical U^2/(g D (s - 1)) at which the drag moment about the lip line equals the
    weight's: drag 1/2 rho C_D U^2 (D - b_n(x))+ per length (b_n = d(x)/cos beta, d linear from H to
    B), arm R cos(alpha); weight (rho_m - rho) g pi D^2/4 L cos(beta), arm R sin(alpha),
    cos(alpha) = 1 - 2 B/(D cos beta); integrated by scipy's quad, in dimensional form."""
    rho, rho_m, g, cd = 1027.0, 1540.0, 9.81, 1.2
    sin_b = (b - h) / L
    cos_b = math.sqrt(1.0 - sin_b**2)
    cos_a = 1.0 - 2.0 * b / (D * cos_b)
    sin_a = math.sqrt(1.0 - cos_a**2)
    exposed, _ = quad(lambda x: min(max(D - (h + (b - h) * x / L) / cos_b, 0.0), D), 0.0, L, limit=200)
    weight_moment = (rho_m - rho) * g * math.pi * D * D / 4.0 * L * cos_b * R * sin_a
    u2 = weight_moment / (0.5 * rho * cd * R * cos_a * exposed)
    want = u2 / (g * D * (rho_m / rho - 1.0))
    got = S.mobility_threshold_tilted(1e-6, b, h, D, L, cd)
    assert got == pytest.approx(want, rel=1e-9)
    # a level mine buried as deep as the lower end shows less of itself to the flow: a higher threshold
    assert 0.0 < got < S.mobility_threshold_pocket(1e-6, b / D, cd)


def test_a_deep_nose_cannot_roll_out():
    """The lower end's section buried past its centre: no rolling (infinite threshold)."""
    assert S.mobility_threshold_tilted(0.011, 0.4, 0.4 - 1.5, D, L, 1.2) == math.inf
    assert S.mobility_threshold_tilted(0.011, 0.3, 0.3 - L, D, L, 1.2) == math.inf  # vertical


def test_mean_clipped_linear_against_quadrature():
    for y0, y1 in ((-0.5, 2.0), (0.2, 0.7), (1.5, -3.0), (-1.0, -0.5), (1.2, 3.0), (0.3, 0.3)):
        kinks = (
            [x for x in ((0.0 - y0) / (y1 - y0), (1.0 - y0) / (y1 - y0)) if 0.0 < x < 1.0] if y1 != y0 else []
        )
        want, _ = quad(
            lambda x, y0=y0, y1=y1: min(max(y0 + (y1 - y0) * x, 0.0), 1.0), 0.0, 1.0, points=kinks or None
        )
        assert S.mean_clipped_linear(y0, y1) == pytest.approx(want, rel=1e-10, abs=1e-14)


# --- the batch: measures of the tilted mine ---------------------------------------------------------


def batch(a_z, pens, rest_attitude, forcing_hours=24.0, hs=0.0, leads=(0.0, 0.5)):
    n = len(a_z)
    P = np.zeros((n, layout.N_PARAMS))  # the drops' bodies: the L x 2R cylinder, COM offset CHI
    P[:, layout.P_LENGTH], P[:, layout.P_DIAMETER], P[:, layout.P_CHI] = L, 2 * R, CHI
    rest = np.empty((n, N_REST))
    rest[:, R_AZ] = a_z
    for i in range(n):  # COM height that puts the lowest point at -pens[i]
        lo = min(a_z[i] * (-0.5 * L - CHI), a_z[i] * (0.5 * L - CHI)) - R * math.sqrt(1 - a_z[i] ** 2)
        rest[i, R_ZC] = -pens[i] - lo
    S_ = np.tile(
        S.default_parameters(diameter=D, burial_law=S.BURIAL_SCOUR_SETTLE, rest_attitude=rest_attitude),
        (n, 1),
    )
    t = np.arange(forcing_hours + 1.0) * 3600.0
    zero = np.zeros_like(t)
    leads = np.asarray(leads) * DAY
    measures = np.empty((n, len(MEASURE_NAMES), leads.size))
    time_to, mobile, codes = np.empty((n, 1)), np.empty(n), np.empty(n, dtype=np.int8)
    tilt = np.empty((n, leads.size))
    scour_drops_ends(
        S_, np.ones(n), np.full(n, 12.0), np.ones(n, dtype=np.uint8), P, rest, t, zero + hs, zero + 8.0,
        zero, zero, zero, zero, np.zeros(n), t[-1], TABLE, leads, np.array([0.5]),
        measures, time_to, mobile, codes, np.empty((n, leads.size)), np.empty((n, leads.size)), tilt,
    )  # fmt: skip
    return S_, measures, tilt, codes


def test_impact_attitude_keeps_the_impact_measures_in_calm():
    """Calm sea: the vertical mine nose down 0.6 m in: burial by volume and height 0.6/L, height
    proud L - 0.6, tilt 90 degrees; the level mine: the segment's closed form, tilt 0; a 30-degree
    mine: its lowest point and tilt kept at every lead time."""
    a_z = -np.sin(np.radians([90.0, 0.0, 30.0]))
    pens = np.array([0.6, 0.1, 0.25])
    S_, m, tilt, codes = batch(a_z, pens, S.REST_IMPACT)
    assert np.all(codes == S.SCOUR_OK)
    for j in range(2):
        pen, vol, height, _, proud = m[0, :, j]
        assert pen == pytest.approx(0.6, rel=1e-12) and vol == pytest.approx(30.0, rel=1e-9)
        assert height == pytest.approx(30.0, rel=1e-9) and proud == pytest.approx(L - 0.6, rel=1e-12)
        assert tilt[0, j] == pytest.approx(90.0, rel=1e-9)
        pen, vol, height, _, proud = m[1, :, j]
        a = 2 * math.acos(1 - 0.1 / R)
        assert vol == pytest.approx(100 * (a - math.sin(a)) / (2 * math.pi), rel=1e-9)
        assert proud == pytest.approx(D - 0.1, rel=1e-12) and tilt[1, j] == 0.0
        assert m[2, 0, j] == pytest.approx(0.25, rel=1e-12) and tilt[2, j] == pytest.approx(30.0, rel=1e-9)
    assert S_[0, S.S_B0] == pytest.approx(0.6, rel=1e-12) and S_[0, S.S_B0_HIGH] == pytest.approx(
        0.6 - L, rel=1e-12
    )
    # the flat choice lays them down: the vertical mine's height proud is then that of the lying cylinder
    _, flat, flat_tilt, _ = batch(a_z, pens, S.REST_FLAT)
    assert np.all(flat_tilt == 0.0) and flat[0, 4, 0] < D < m[0, 4, 0]
    np.testing.assert_allclose(flat[:, 1], m[:, 1], rtol=1e-9)  # the buried volume is the same


# --- in a run -----------------------------------------------------------------------------------------


@pytest.fixture(scope="module")
def impact_run(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("scour_tilt_run")
    sec = scour_section(tmp, burial_law="scour_settle", mobility="pocket", rest_attitude="impact")
    return runner.run_ensemble(scenario(tmp, sec))


def test_lead_zero_measures_are_the_impacts_own(impact_run):
    """The point of the choice: at lead time 0 every burial measure of every drop is the impact
    phase's (no lay-flat step), and the tilt is the impact's pitch."""
    ds = impact_run
    ok = ds["scour_status"].values == 0
    assert ok.sum() >= 4
    j0 = list(ds["lead_time"].values).index(0.0)
    for name in MEASURE_NAMES:
        np.testing.assert_allclose(
            ds[f"scour_{name}"].values[ok, j0], ds[name].values[ok], rtol=1e-9, atol=1e-9, err_msg=name
        )
    pitch = np.abs(ds["final_pitch"].values[ok])
    np.testing.assert_allclose(ds["scour_tilt"].values[ok, j0], np.minimum(pitch, 180.0 - pitch), rtol=1e-9)
    assert ds["scour_tilt"].values[ok, j0].max() > 1.0  # these light mines come to rest nearly level
    assert np.all(np.diff(ds["scour_tilt"].values[ok], axis=1) <= 1e-9)  # the tilt never grows
    np.testing.assert_allclose(ds["scour_tilt_mean"].values, ds["scour_tilt"].values[ok].mean(axis=0))
    assert ds["scour_tilt"].attrs["units"] == "degree" and ds.attrs  # declared (units from the registry)


@pytest.fixture(scope="module")
def two_storms_impact(tmp_path_factory):
    """The shipped two-storm example (its mines rest 45-80 degrees nose down in sand) with
    rest_attitude = "impact", 8 drops."""
    import xarray as xr

    from mineburial.cli import main

    tmp = tmp_path_factory.mktemp("scour_tilt_two")
    text = (SHIPPED / "scour_two_storms.toml").read_text()
    assert 'mobility = "pocket"' in text
    path = tmp / "two_impact.toml"
    path.write_text(text.replace('mobility = "pocket"', 'mobility = "pocket"\nrest_attitude = "impact"', 1))
    out = tmp / "out.nc"
    assert (
        main(["run", str(path), "-n", "8", "--seed", "5", "--per-drop", "--threads", "1", "-o", str(out)])
        == 0
    )
    with xr.open_dataset(out) as ds:
        return ds.load()


def test_steep_mines_keep_their_attitude_and_impact_measures_at_lead_zero(two_storms_impact):
    ds = two_storms_impact
    ok = ds["scour_status"].values == 0
    assert ok.sum() >= 6
    tilt0 = ds["scour_tilt"].values[ok, 0]
    assert tilt0.min() > 30.0  # nose down in sand, the lay-flat step would be large
    np.testing.assert_allclose(tilt0, np.abs(ds["final_pitch"].values[ok]), rtol=1e-9)
    for name in MEASURE_NAMES:
        np.testing.assert_allclose(
            ds[f"scour_{name}"].values[ok, 0], ds[name].values[ok], rtol=1e-9, atol=1e-9, err_msg=name
        )
    # the lower end settles into the pit and stays as it infills: B >= max(B0, S), never falling;
    # the tilt never grows
    b = ds["scour_penetration_depth"].values[ok]
    assert np.all(b >= np.maximum(b[:, :1], ds["scour_pit_depth"].values[ok]) - 1e-12)
    assert np.all(np.diff(b, axis=1) >= 0.0)
    from mineburial.systems.mine.processes.scour import summary_lines

    assert any(line.startswith("  mean tilt [deg]") for line in summary_lines(ds))
    assert np.all(np.diff(ds["scour_tilt"].values[ok], axis=1) <= 1e-9)


def test_impact_attitude_with_rennie_is_one_line_naming_the_field(tmp_path, capsys):
    from mineburial.cli import main

    path = scenario(tmp_path, scour_section(tmp_path, rest_attitude="impact"))
    assert main(["run", str(path), "-o", str(tmp_path / "out.nc"), "--quiet"]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "scour.rest_attitude" in err and "scour_settle" in err, err
