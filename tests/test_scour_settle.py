"""The scour-and-settle burial law, the wave-aware pit equilibrium and the burial-aware mobility
(issue 33 items 2, 3 and 5; docs/scour.md, Scour and settle, Mobility).

Every check is against an independent reference: the closed-form solutions of the pit and burial
ODEs under constant forcing (and scipy's ODE integrator), published numbers (Sumer & Fredsoe 1990
S/D = 0.1 KC^0.5; Rennie et al. 2017 at B = 0), the limits (zero at the threshold of motion,
monotone in theta and KC) and a moment balance evaluated by hand.
"""

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from mineburial.kernels.mine import scour as S

DAY = 86400.0
TABLE = S.build_orbital_table()
D = 0.53


def settle_params(**kw):
    base = dict(diameter=D, d50=2.0e-4, burial_law=S.BURIAL_SCOUR_SETTLE)
    base.update(kw)
    return S.default_parameters(**base)


def constant_forcing(hours, hs=1.5, tp=9.0, uc=0.0, depth=12.0, step=1.0):
    t = np.arange(0.0, hours + step / 2, step) * 3600.0
    one = np.ones_like(t)
    return t, hs * one, tp * one, 0.0 * one, uc * one, 0.0 * one, depth * one


def run(p, forcing, leads, fractions=(0.25, 0.5)):
    n = len(leads)
    ob, op, om = np.empty(n), np.empty(n), np.empty(n)
    ot = np.empty(len(fractions))
    code, t_mob, theta_max = S.scour_stage_states(
        p, *forcing, TABLE, np.asarray(leads, dtype=float), np.asarray(fractions, dtype=float), ob, ot, op, om
    )
    return code, ob, op, om, ot, t_mob, theta_max


def theta_cr(p):
    s = p[S.S_RHO_GRAIN] / p[S.S_RHO_WATER]
    return S.shields_threshold(S.grain_size_number(p[S.S_D50], s, p[S.S_G], p[S.S_NU]))


# --- the equilibrium ------------------------------------------------------------------------------


def test_pit_equilibrium_is_zero_at_the_threshold_and_continuous():
    """No jump at the threshold of motion: 0 at and below theta_cr, O(epsilon) just above it."""
    tc = 0.055
    for ucw in (0.0, 0.5, 1.0):
        args = (8.0, ucw, D, 1.3, 0.36, 0.1, 0.5)
        assert S.pit_equilibrium(tc, tc, *args) == 0.0
        assert S.pit_equilibrium(0.5 * tc, tc, *args) == 0.0
        eps = 1e-6
        assert 0.0 < S.pit_equilibrium(tc * (1 + eps), tc, *args) < 2e-6 * D


def test_pit_equilibrium_reaches_the_published_live_bed_laws():
    """Far above the threshold the onset factor -> 1: waves give Sumer & Fredsoe (1990)
    S/D = 0.1 KC^0.5 (0.4 at KC = 16), a current gives Rennie et al. (2017) 1.3 theta^0.36; the
    factor is exactly 1 - theta_cr/theta."""
    tc = 0.05
    theta = 2.0
    factor = 1.0 - tc / theta
    s_w = S.pit_equilibrium(theta, tc, 16.0, 0.0, D, 1.3, 0.36, 0.1, 0.5)
    assert s_w / (D * factor) == pytest.approx(0.4, rel=1e-12)
    s_c = S.pit_equilibrium(theta, tc, 16.0, 1.0, D, 1.3, 0.36, 0.1, 0.5)
    assert s_c / (D * factor) == pytest.approx(1.3 * 2.0**0.36, rel=1e-12)
    # combined: the U_cw-weighted mean of the two
    s_m = S.pit_equilibrium(theta, tc, 16.0, 0.25, D, 1.3, 0.36, 0.1, 0.5)
    assert s_m == pytest.approx(0.75 * s_w + 0.25 * s_c, rel=1e-12)
    assert S.current_ratio(0.3, 0.9) == pytest.approx(0.25, rel=1e-15)
    assert S.current_ratio(0.0, 0.0) == 0.0


def test_pit_equilibrium_is_monotone_in_theta_and_kc():
    tc = 0.05
    thetas = np.linspace(0.0, 3.0, 301)
    for ucw in (0.0, 0.3, 1.0):
        s = [S.pit_equilibrium(th, tc, 8.0, ucw, D, 1.3, 0.36, 0.1, 0.5) for th in thetas]
        assert np.all(np.diff(s) >= 0.0)
    kcs = np.linspace(0.0, 40.0, 81)
    s = [S.pit_equilibrium(0.3, tc, kc, 0.0, D, 1.3, 0.36, 0.1, 0.5) for kc in kcs]
    assert np.all(np.diff(s) >= 0.0) and s[-1] > s[1] > 0.0


# --- the pit ODE and the mine under constant forcing -------------------------------------------


@pytest.mark.parametrize("s0,s_eq", [(0.0, 0.3), (0.1, 0.3), (0.4, 0.1), (0.4, 0.0)])
def test_relax_pit_against_scipy(s0, s_eq):
    """dS/dt = (S_eq - S)/T, T the growth scale while S < S_eq and the infill scale above it,
    integrated by scipy (RK45, tight tolerances) against the kernel's exact step."""
    t_grow, t_fill, dt = 3600.0, 5 * 3600.0, 7200.0

    def rhs(_, y):
        return [(s_eq - y[0]) / (t_grow if y[0] < s_eq else t_fill)]

    ref = solve_ivp(rhs, (0.0, dt), [s0], rtol=1e-11, atol=1e-13).y[0, -1]
    assert S.relax_pit(s0, s_eq, dt, t_grow, t_fill) == pytest.approx(ref, rel=1e-8, abs=1e-12)
    # the exact step composes: two half steps are one step (constant forcing)
    half = S.relax_pit(S.relax_pit(s0, s_eq, dt / 2, t_grow, t_fill), s_eq, dt / 2, t_grow, t_fill)
    assert half == pytest.approx(S.relax_pit(s0, s_eq, dt, t_grow, t_fill), rel=1e-13)


def test_stage_under_constant_waves_follows_the_closed_form():
    """Constant waves from a pit-free start: S(t) = S_eq (1 - exp(-t/T)) and the mine's burial
    max(B0, S(t)); S_eq and T evaluated by hand from the closures (bed_forcing's theta, u_br,
    T_br) with the published law, independently of pit_target."""
    b0 = 0.02
    p = settle_params(b0=b0, wave_a=0.3)
    forcing = constant_forcing(24.0, hs=1.5, tp=9.0)
    theta, ub, tb, _ = S.bed_forcing(p, 1.5, 9.0, 0.0, 0.0, 0.0, 12.0, TABLE)
    tc = theta_cr(p)
    kc = ub * tb / D
    s_eq = D * (1.0 - tc / theta) * 0.3 * kc**0.5
    s = p[S.S_RHO_GRAIN] / p[S.S_RHO_WATER]
    t_scale = 0.014 * theta**-1.29 * D**2 / math.sqrt(9.81 * (s - 1.0) * 2.0e-4**3)
    leads = np.array([0.0, 0.1, 0.5, 1.0, 3.0, 10.0, 24.0]) * 3600.0
    code, ob, op, _, ot, _, _ = run(p, forcing, leads)
    assert code == S.SCOUR_OK
    pit = s_eq * (1.0 - np.exp(-leads / t_scale))
    np.testing.assert_allclose(op, pit, rtol=1e-9, atol=1e-15)
    np.testing.assert_allclose(ob, np.maximum(b0, pit), rtol=1e-9)
    # time to B/D = 0.25: T ln(S_eq / (S_eq - 0.25 D))
    assert s_eq > 0.25 * D
    assert ot[0] == pytest.approx(t_scale * math.log(s_eq / (s_eq - 0.25 * D)), rel=1e-9)


def test_calm_infill_lowers_the_pit_but_never_lifts_the_mine():
    """A storm digs the pit and the mine settles; in the calm after it (below the threshold) the pit
    infills as exp(-t/T_infill) toward the ambient bed while the burial stays."""
    storm = constant_forcing(24.0, hs=1.8, tp=10.0)
    calm = constant_forcing(240.0, hs=0.2, tp=6.0)
    # the storm's records over [0, 24 h), the calm's from 24 h
    t = np.concatenate([storm[0][:-1], storm[0][-1] + calm[0]])
    forcing = (t,) + tuple(np.concatenate([a[:-1], b]) for a, b in zip(storm[1:], calm[1:]))
    t_fill = 3.0 * DAY
    p = settle_params(infill_time=t_fill, wave_a=0.3)
    theta_calm, *_ = S.bed_forcing(p, 0.2, 6.0, 0.0, 0.0, 0.0, 12.0, TABLE)
    assert theta_calm < theta_cr(p)
    leads = 24.0 * 3600.0 + np.array([0.0, 1.0, 2.0, 5.0, 10.0]) * DAY
    code, ob, op, _, _, _, _ = run(p, forcing, leads)
    assert code == S.SCOUR_OK
    s_end = op[0]
    assert s_end > 0.1 * D
    np.testing.assert_allclose(op, s_end * np.exp(-(leads - leads[0]) / t_fill), rtol=1e-9)
    np.testing.assert_array_equal(ob, np.full(leads.size, ob[0]))  # the burial stays
    assert ob[0] == pytest.approx(s_end, rel=1e-12)  # the mine settled to the pit's depth


def test_far_field_lowering_re_exposes_the_mine():
    """Calm water (no scour) and a far-field bed lowering at r: B(t) = max(B0 - r t, 0)."""
    b0 = 0.2
    rate = 0.05 / DAY  # 5 cm a day
    p = settle_params(b0=b0, bed_rate=rate)
    forcing = constant_forcing(240.0, hs=0.2, tp=6.0)
    leads = np.array([0.0, 1.0, 2.0, 3.9, 4.0, 6.0, 10.0]) * DAY
    code, ob, op, _, _, _, _ = run(p, forcing, leads)
    assert code == S.SCOUR_OK
    np.testing.assert_allclose(ob, np.maximum(b0 - rate * leads, 0.0), rtol=1e-12, atol=1e-15)
    np.testing.assert_array_equal(op, 0.0)


def test_two_similar_storms_bury_in_steps_not_at_once():
    """The shipped two-storm forcing: the first storm raises the burial to a level well below D,
    the calm keeps it while the pit infills, the second (similar, 0.2 m higher) storm adds a step."""
    from mineburial.io import forcing as fio
    from mineburial.systems.mine.processes.scour import SHIPPED

    f = fio.load_forcing(SHIPPED / "two_storms.csv")
    arrays = f.kernel_arrays(12.0, 2.0e-4)
    p = settle_params(b0=0.03, wave_a=0.2)
    leads = np.array([0.0, 2.0, 6.0, 9.5, 16.0, 20.0]) * DAY
    code, ob, op, _, _, _, _ = run(p, arrays, leads)
    assert code == S.SCOUR_OK
    bd = ob / D
    assert bd[0] == pytest.approx(0.03 / D)
    assert bd[0] < bd[2] < 0.6  # one step, not full burial
    assert bd[2] == bd[3]  # calm: the burial stays
    assert op[3] < 0.8 * op[2]  # while the pit infills
    assert bd[4] > bd[3] + 0.05 and bd[5] == bd[4] and bd[5] < 1.0  # the second step


def test_rennie_law_unchanged_and_its_pit_is_the_burial():
    """The default law is the first version's: scour_stage_states with BURIAL_RENNIE gives the
    burial of the closed form B_eq - (B_eq - B0) exp(-t/T) and reports it as the pit too."""
    p = S.default_parameters(diameter=D, b0=0.01)
    assert p[S.S_BURIAL_LAW] == S.BURIAL_RENNIE and p[S.S_MOBILITY] == S.MOBILITY_PROUD
    forcing = constant_forcing(12.0, hs=1.2, tp=8.0)
    theta, *_ = S.bed_forcing(p, 1.2, 8.0, 0.0, 0.0, 0.0, 12.0, TABLE)
    b_eq = min(D * 1.3 * theta**0.36, D)
    s = p[S.S_RHO_GRAIN] / p[S.S_RHO_WATER]
    t_scale = 0.014 * theta**-1.29 * D**2 / math.sqrt(9.81 * (s - 1.0) * 2.0e-4**3)
    leads = np.array([0.0, 0.5, 2.0, 12.0]) * 3600.0
    code, ob, op, _, _, _, _ = run(p, forcing, leads)
    assert code == S.SCOUR_OK
    np.testing.assert_allclose(ob, b_eq - (b_eq - 0.01) * np.exp(-leads / t_scale), rtol=1e-9)
    np.testing.assert_array_equal(op, ob)


def test_invalid_new_parameters_are_refused():
    for key, value in (
        ("burial_law", 2.0),
        ("wave_a", 0.0),
        ("wave_kc_exp", -0.1),
        ("infill_time", 0.0),
        ("bed_rate", math.nan),
        ("bed_rate", -1e-6),
        ("mobility", 3.0),
        ("mob_cd", 0.0),
    ):
        p = settle_params(**{key: value})
        assert not S.parameters_valid(p), key
        code, *_ = run(p, constant_forcing(2.0), [0.0])
        assert code == S.SCOUR_INVALID_PARAMETER


# --- mobility -------------------------------------------------------------------------------------


def test_pocket_tangent_is_the_lip_geometry():
    """B = R (1 - cos alpha): B/D = 1/4 puts the lip at alpha = 60 deg (tan = sqrt 3); B/D = (1 -
    cos 30 deg)/2 at 30 deg."""
    assert S.pocket_tangent(0.25) == pytest.approx(math.sqrt(3.0), rel=1e-14)
    f30 = (1.0 - math.cos(math.radians(30.0))) / 2.0
    assert S.pocket_tangent(f30) == pytest.approx(math.tan(math.radians(30.0)), rel=1e-12)
    assert S.pocket_tangent(0.0) == 0.0 and S.pocket_tangent(0.5) == math.inf


def test_pocket_threshold_is_the_moment_balance():
    """At the threshold the drag's moment about the lip equals the submerged weight's: F R cos a =
    W' R sin a, with F = 1/2 rho C_D U^2 (D - B) L and W' = (rho_m - rho) g pi D^2/4 L (per unit
    length here); and it is Rennie et al.'s rigid-bottom value at B = 0, monotone in B."""
    rho, g, sg, cd, f = 1027.0, 9.81, 1.6, 1.2, 0.1
    theta_rigid = S.mobility_threshold(D, 2.5 * 2e-4, 1.6, -0.72)
    theta_c = S.mobility_threshold_pocket(theta_rigid, f, cd)
    u2 = theta_c * g * D * (sg - 1.0)  # U^2 at the threshold
    drag = 0.5 * rho * cd * u2 * (D - f * D)
    weight = (sg - 1.0) * rho * g * math.pi * D**2 / 4.0
    cos_a = 1.0 - 2.0 * f
    sin_a = math.sqrt(1.0 - cos_a**2)
    assert drag * cos_a == pytest.approx(weight * sin_a, rel=1e-12)
    assert S.mobility_threshold_pocket(theta_rigid, 0.0, cd) == theta_rigid
    values = [S.mobility_threshold_pocket(theta_rigid, x, cd) for x in np.linspace(0.0, 0.49, 50)]
    assert np.all(np.diff(values) >= 0.0)
    assert S.mobility_threshold_pocket(theta_rigid, 0.5, cd) == math.inf


def test_mobility_per_lead_time_in_calm_water():
    """Calm seas (Hs 0.6 m, Tp 8 s, 0.1 m/s current) over a mine 3 cm in: the first version's
    proud flag says mobile (B/D 0.057 <= 0.1, Theta_U above the rigid-bottom threshold), the
    burial-aware criterion says it stays; a mine lying on the bed (B = 0) moves under both."""
    forcing = constant_forcing(24.0, hs=0.6, tp=8.0, uc=0.1)
    leads = [0.0, 12.0 * 3600.0, 24.0 * 3600.0]
    _, _, _, om, _, t_mob, _ = run(settle_params(b0=0.03, mobility=S.MOBILITY_PROUD), forcing, leads)
    assert np.all(om == 1.0) and t_mob == 0.0
    _, _, _, om, _, t_mob, _ = run(settle_params(b0=0.03, mobility=S.MOBILITY_POCKET), forcing, leads)
    assert np.all(om == 0.0) and t_mob == math.inf
    _, _, _, om, _, _, _ = run(settle_params(b0=0.0, mobility=S.MOBILITY_POCKET), forcing, leads)
    assert np.all(om == 1.0)
    # by hand: Theta_U = (u_c + u_br)^2 / (g D (s_obj - 1)) against the pocket value at 3 cm
    _, ub, _, u = S.bed_forcing(settle_params(), 0.6, 8.0, 0.0, 0.1, 0.0, 12.0, TABLE)
    theta_u = u * u / (9.81 * D * 0.5)
    rigid = S.mobility_threshold(D, 5e-4, 1.6, -0.72)
    assert rigid < theta_u < S.mobility_threshold_pocket(rigid, 0.03 / D, 1.2)
