"""The scour stage for a short body standing on its base (issue 36 item 3: a Manta-like frustum;
docs/scour.md, Standing body; docs/bodies_revolution.md, "The scour stage and a frustum").

Every check is against an independent reference: the published laws' own numbers (Sumer & Fredsoe
2001's combined pile law and its waves-only limit of Sumer, Fredsoe & Christiansen 1992, evaluated
here from the printed formula; Al-Awadi 2021's reductions at 10, 16 and 22 deg), the invariances the
sources state (the equilibrium does not depend on the body's height below h/D = 2, Zhao, Cheng &
Zang 2010), the limits (zero at and below the threshold of motion; monotone in KC and theta), the
closed-form relaxation under constant forcing, and the frustum's volume in closed form.
"""

import math

import numpy as np
import pytest

from mineburial.kernels.mine import scour as S

DAY = 86400.0
TABLE = S.build_orbital_table()
D = 0.98  # the Manta-like base [m]
H = 0.44  # its height [m]


def sumer_fredsoe_2001(kc, ucw):
    """S/D = 1.3 {1 - exp[-A (KC - B)]}, A = 0.03 + 0.75 Ucw^2.6, B = 6 exp(-4.7 Ucw), 0 for KC <= B
    (Sumer & Fredsoe 2001, J. Hydraul. Eng. 127(5); as printed in ../shared/notes/sources.md §3)."""
    a = 0.03 + 0.75 * ucw**2.6
    b = 6.0 * math.exp(-4.7 * ucw)
    return 0.0 if kc <= b else 1.3 * (1.0 - math.exp(-a * (kc - b)))


def standing_params(**kw):
    base = dict(diameter=D, height=H, standing=1.0, flank_angle=0.0, d50=2.0e-4)
    base.update(kw)
    return S.default_parameters(**base)


# --- the published laws ------------------------------------------------------------------------------


def test_pile_law_is_the_published_combined_law_and_its_limits():
    # waves only (U_cw = 0): no horseshoe vortex, no scour, up to KC = 6 (Sumer et al. 1992)
    assert S.pile_scour_ratio(6.0, 0.0) == 0.0
    assert S.pile_scour_ratio(5.0, 0.0) == 0.0
    # waves only at KC = 10 and 30: 1.3 (1 - e^-0.12) = 0.147, 1.3 (1 - e^-0.72) = 0.667
    assert S.pile_scour_ratio(10.0, 0.0) == pytest.approx(1.3 * (1.0 - math.exp(-0.12)), rel=1e-14)
    assert S.pile_scour_ratio(30.0, 0.0) == pytest.approx(0.6672, abs=5e-5)
    # the steady-current value 1.3 as KC grows (Sumer et al. 1992; Breusers et al. 1977)
    assert S.pile_scour_ratio(1e4, 1.0) == pytest.approx(1.3, rel=1e-12)
    for kc in (0.5, 3.0, 7.0, 15.0, 40.0):
        for ucw in (0.0, 0.2, 0.45, 0.7, 1.0):
            assert S.pile_scour_ratio(kc, ucw) == pytest.approx(
                sumer_fredsoe_2001(kc, ucw), rel=1e-13, abs=1e-15
            )


def test_flank_factor_reproduces_the_published_reductions():
    """Al-Awadi 2021: piers inclined 10, 16, 22 deg scour about 5, 10, 15 % less; held beyond 22 deg."""
    for deg, factor in ((0.0, 1.0), (10.0, 0.95), (16.0, 0.90), (22.0, 0.85), (35.0, 0.85), (60.0, 0.85)):
        assert S.flank_factor(math.radians(deg)) == pytest.approx(factor, abs=1e-14)
    angles = np.radians(np.linspace(0.0, 30.0, 61))
    values = [S.flank_factor(a) for a in angles]
    assert np.all(np.diff(values) <= 0.0)  # a steeper lean never scours more


# --- the equilibrium: zero at the threshold, monotone, independent of height -------------------------


def test_standing_equilibrium_zero_at_and_below_the_threshold():
    tc = 0.055
    for ucw in (0.0, 0.4, 1.0):
        assert S.standing_equilibrium(tc, tc, 20.0, ucw, tc, D, 0.3) == 0.0
        assert S.standing_equilibrium(0.5 * tc, tc, 20.0, ucw, 0.2 * tc, D, 0.3) == 0.0
        assert 0.0 < S.standing_equilibrium(tc * (1 + 1e-6), tc, 20.0, ucw, 0.0, D, 0.0) < 1e-5 * D


def test_standing_equilibrium_monotone_in_kc_and_theta():
    tc = 0.055
    kcs = np.linspace(0.0, 60.0, 121)
    thetas = np.linspace(0.0, 1.0, 101)
    for ucw in (0.0, 0.3, 0.8):
        by_kc = [S.standing_equilibrium(0.3, tc, kc, ucw, 0.0, D, 0.2) for kc in kcs]
        assert np.all(np.diff(by_kc) >= 0.0) and by_kc[-1] > 0.0
        by_theta = [S.standing_equilibrium(th, tc, 20.0, ucw, 0.0, D, 0.2) for th in thetas]
        assert np.all(np.diff(by_theta) >= 0.0)
    # live bed, waves only, a vertical wall: the published value itself
    assert S.standing_equilibrium(1e9, tc, 20.0, 0.0, 0.0, D, 0.0) == pytest.approx(
        D * sumer_fredsoe_2001(20.0, 0.0)
    )


def test_the_current_alone_scours_at_the_steady_current_value():
    """A strong current under small waves: the current's own horseshoe vortex (S/D = 1.3 in live
    bed), not the combined law at the waves' small KC."""
    tc = 0.055
    theta_c = 1e9  # live bed
    assert S.standing_equilibrium(1e9, tc, 0.5, 0.9, theta_c, D, 0.0) == pytest.approx(1.3 * D, rel=1e-9)
    assert S.standing_equilibrium(1e9, tc, 0.0, 1.0, theta_c, D, 0.0) == pytest.approx(1.3 * D, rel=1e-9)


@pytest.mark.parametrize("ucw_uc", [(0.0, 0.0), (0.5, 0.3)])
def test_equilibrium_independent_of_height_below_two_diameters(ucw_uc):
    """Zhao, Cheng & Zang 2010: the scour at the upstream edge does not depend on h/D for h/D < 2;
    the height only caps the burial (full burial, the top level with the bed)."""
    _, uc = ucw_uc
    tc = 0.0554
    theta, ub, tb = 0.12, 0.6, 9.0
    results = []
    for h_over_d in (0.3, 0.45, 1.0, 1.9):
        p = standing_params(height=h_over_d * D, flank_angle=math.radians(15.0))
        s_eq, t_scale = S.standing_target(p, theta, tc, ub, tb, uc, 0.0)
        expected = S.standing_equilibrium(
            theta, tc, ub * tb / D, S.current_ratio(uc, ub), 0.0, D, math.radians(15.0)
        )
        assert s_eq == min(expected, h_over_d * D)
        results.append((expected, t_scale))
    assert len(set(results)) == 1  # the uncapped equilibrium and the time scale: one value for every height


# --- the stage under constant forcing: the exact relaxation ------------------------------------------


def constant_forcing(hours, hs=2.0, tp=10.0, uc=0.3, depth=12.0):
    t = np.arange(0.0, hours + 0.5, 1.0) * 3600.0
    one = np.ones_like(t)
    return t, hs * one, tp * one, 0.0 * one, uc * one, 0.0 * one, depth * one


@pytest.mark.parametrize("law", [S.BURIAL_RENNIE, S.BURIAL_SCOUR_SETTLE])
def test_stage_relaxes_to_the_pile_equilibrium(law):
    angle = math.radians(25.0)
    p = standing_params(flank_angle=angle, burial_law=law, b0=0.02, height=2.0)  # height: no cap
    forcing = constant_forcing(48.0)
    leads = np.array([0.0, 0.5, 3.0, 24.0]) * 3600.0
    out = np.empty(4)
    ot = np.empty(2)
    pit, mob = np.empty(4), np.empty(4)
    code, t_mob, _ = S.scour_stage_states(p, *forcing, TABLE, leads, np.array([0.5, 0.75]), out, ot, pit, mob)
    assert code == S.SCOUR_OK
    # the hand computation: the bed's forcing (closures tested in test_scour*.py), then the published laws
    theta, ub, tb, _ = S.bed_forcing(p, 2.0, 10.0, 0.0, 0.3, 0.0, 12.0, TABLE)
    s = 2650.0 / 1027.0
    tc = S.shields_threshold(S.grain_size_number(2e-4, s, 9.81, 1.36e-6))
    kappa_term = 0.40 / (math.log(12.0 / (2e-4 / 12.0)) - 1.0)  # Soulsby 1997 depth-mean drag
    theta_c = 1027.0 * kappa_term**2 * 0.3**2 / (1027.0 * (s - 1.0) * 9.81 * 2e-4)
    ucw = 0.3 / (0.3 + ub)
    onset = lambda th: max(0.0, 1.0 - tc / th)  # noqa: E731
    k_flank = 0.85  # 25 deg: held at Al-Awadi's 22 deg value
    s_eq = D * k_flank * max(onset(theta) * sumer_fredsoe_2001(ub * tb / D, ucw), onset(theta_c) * 1.3)
    t_scale = 0.014 * theta**-1.29 * D * D / math.sqrt(9.81 * (s - 1.0) * (2e-4) ** 3)  # Whitehouse 1998
    b_expected = s_eq - (s_eq - 0.02) * np.exp(-leads / t_scale) if law == S.BURIAL_RENNIE else None
    if law == S.BURIAL_SCOUR_SETTLE:  # the pit from 0, the mine at max(own burial, pit)
        b_expected = np.maximum(0.02, s_eq * (1.0 - np.exp(-leads / t_scale)))
    np.testing.assert_allclose(out, b_expected, rtol=1e-12, atol=1e-15)
    # no rolling criterion for a body on its flat base
    assert t_mob == math.inf and np.all(mob == 0.0)
    # the burial levels are fractions of the height (here 2 m: 1 m and 1.5 m)
    for k, frac in enumerate((0.5, 0.75)):
        if s_eq > frac * 2.0:
            assert ot[k] == pytest.approx(
                t_scale * math.log((s_eq - (0.02 if law == S.BURIAL_RENNIE else 0.0)) / (s_eq - frac * 2.0)),
                rel=1e-12,
            )
        else:
            assert ot[k] == math.inf


def test_stage_caps_at_the_height_and_refuses_a_tilt_state():
    p = standing_params(b0=0.0)
    forcing = constant_forcing(96.0, hs=3.0, uc=0.6)
    leads = np.array([96.0 * 3600.0])
    out, ot = np.empty(1), np.empty(1)
    code, _, _ = S.scour_stage(p, *forcing, TABLE, leads, np.array([1.0]), out, ot)
    assert code == S.SCOUR_OK and out[0] == pytest.approx(H, rel=1e-9) and ot[0] < 96 * 3600.0
    bad = standing_params(rest_attitude=S.REST_IMPACT, burial_law=S.BURIAL_SCOUR_SETTLE)
    assert (
        S.scour_stage(bad, *forcing, TABLE, leads, np.array([1.0]), out, ot)[0] == S.SCOUR_INVALID_PARAMETER
    )
    for key, value in (("height", 0.0), ("flank_angle", -0.1), ("flank_angle", 2.0), ("standing", 0.5)):
        assert S.parameters_valid(standing_params(**{key: value})) is False


def test_a_cohesive_bed_does_not_scour_a_standing_body():
    p = standing_params(cohesive=1.0, b0=0.05)
    forcing = constant_forcing(24.0, hs=3.0, uc=0.6)
    out, ot = np.empty(1), np.empty(1)
    S.scour_stage(p, *forcing, TABLE, np.array([24 * 3600.0]), np.array([0.5]), out, ot)
    assert out[0] == 0.05
