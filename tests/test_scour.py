"""Post-impact scour kernels (mineburial/kernels/mine/scour.py) against independent references.

References: the exact root of the dispersion relation by scipy's brentq; the printed formulas of
Swart (1974), Soulsby (1997), Soulsby & Whitehouse (1997), Wiberg & Harris (1994) and Rennie et al.
(2017) evaluated by hand here; the JONSWAP near-bed velocity of Wiberg & Sherwood (2008) integrated
with scipy.integrate.quad; the check values of /work/shared/notes/sources.md §3 [computed]; and the
closed-form exponential relaxation of the burial computed here from the inputs.
"""

import math

import numpy as np
import pytest
from scipy.integrate import quad
from scipy.optimize import brentq

from mineburial.kernels.mine import scour as S

G = 9.81
RHO = 1027.0  # sea water, Soulsby 1997 Table 2 (10 C, 35 ppt)
NU = 1.36e-6
RHO_S = 2650.0
SG = RHO_S / RHO
KAPPA = 0.40


@pytest.fixture(scope="module")
def table():
    return S.build_orbital_table()


def kh_brentq(omega, h):
    xi = omega * omega * h / G
    return brentq(lambda y: y * math.tanh(y) - xi, 1e-12, max(10.0, 2.0 * xi), xtol=1e-15, rtol=1e-15)


# --- dispersion ----------------------------------------------------------------------------------


@pytest.mark.parametrize(
    "period, kh", [(5.0, 1.717028), (8.0, 0.886224), (10.0, 0.680191), (12.0, 0.554567), (15.0, 0.435944)]
)
def test_dispersion_check_values_at_10m(period, kh):
    # sources.md §3: kh at h = 10 m (Soulsby 2006 qkhfs, equal to the exact root to 6 decimals)
    omega = 2 * math.pi / period
    assert S.kh_exact(omega, 10.0, G) == pytest.approx(kh, abs=1e-6)
    assert kh_brentq(omega, 10.0) == pytest.approx(kh, abs=1e-6)


def test_dispersion_exact_root_matches_brentq():
    for h in (0.5, 3.0, 10.0, 50.0, 400.0):
        for period in (1.0, 4.0, 10.0, 20.0):
            omega = 2 * math.pi / period
            assert S.kh_exact(omega, h, G) == pytest.approx(kh_brentq(omega, h), rel=1e-13)


def test_dispersion_soulsby_explicit_within_one_percent():
    # Soulsby (1997) states about 1 % for the explicit approximation
    worst = 0.0
    for xi in np.geomspace(1e-4, 100.0, 400):
        exact = brentq(lambda y, xi=xi: y * math.tanh(y) - xi, 1e-12, 200.0, xtol=1e-15)
        worst = max(worst, abs(S.kh_soulsby(math.sqrt(xi), 1.0, 1.0) / exact - 1.0))
    assert worst < 0.01
    assert S.kh_soulsby(2 * math.pi / 10, 10.0, G) == pytest.approx(0.680191, rel=0.01)


# --- near-bed orbital velocity -----------------------------------------------------------------------


def test_monochromatic_orbital_check_values():
    # sources.md §3 [computed]: h = 12 m, Hs = 1.25 m, Tp = 10 s: U(Hs) = 0.473, U(Hrms) = 0.334 m/s
    assert S.orbital_monochromatic(1.25, 10.0, 12.0, G) == pytest.approx(0.473, abs=5e-4)
    assert S.orbital_monochromatic(1.25 / math.sqrt(2), 10.0, 12.0, G) == pytest.approx(0.334, abs=5e-4)
    for height, period, h in ((0.4, 5.0, 3.0), (2.0, 14.0, 25.0)):
        ref = math.pi * height / (period * math.sinh(kh_brentq(2 * math.pi / period, h)))
        assert S.orbital_monochromatic(height, period, h, G) == pytest.approx(ref, rel=1e-12)


def jonswap_bed_quad(hs, tp, h, lo=0.2, hi=5.0):
    """u_br and T_br of Wiberg & Sherwood (2008) eqs. 5-7 with a JONSWAP spectrum (gamma 3.3,
    sigma 0.07/0.09) scaled to m0 = Hs^2/16, integrated by scipy's quad on f/fp in [lo, hi]."""
    fp = 1.0 / tp

    def shape(x):
        sig = 0.07 if x <= 1.0 else 0.09
        return x**-5 * math.exp(-1.25 * x**-4) * 3.3 ** math.exp(-((x - 1) ** 2) / (2 * sig**2))

    def su(x):  # bed-velocity spectrum per unit x (m0 normalisation below)
        w = 2 * math.pi * x * fp
        kh = kh_brentq(w, h)
        return shape(x) * ((w / math.sinh(kh)) ** 2 if kh < 700 else 0.0)

    i0 = quad(shape, lo, hi, points=[1.0], limit=200)[0]
    a = hs**2 / 16 / i0 * quad(su, lo, hi, points=[1.0], limit=200)[0]
    b = hs**2 / 16 / i0 * quad(lambda x: x * fp * su(x), lo, hi, points=[1.0], limit=200)[0]
    return math.sqrt(2 * a), a / b


def test_spectral_orbital_check_value(table):
    # sources.md §3 [computed]: h = 12 m, Hs = 1.25 m, Tp = 10 s: u_br = 0.310 m/s, T_br = 9.35 s
    ub, tb = S.orbital_spectral(1.25, 10.0, 12.0, G, table)
    assert ub == pytest.approx(0.310, abs=5e-4)
    assert tb == pytest.approx(9.35, abs=5e-3)


@pytest.mark.parametrize(
    "hs, tp, h", [(1.25, 10.0, 12.0), (2.0, 8.0, 20.0), (0.5, 6.0, 5.0), (3.0, 14.0, 30.0), (1.0, 12.0, 3.0)]
)
def test_spectral_orbital_against_quad(table, hs, tp, h):
    ub, tb = S.orbital_spectral(hs, tp, h, G, table)
    ref_u, ref_t = jonswap_bed_quad(hs, tp, h)
    assert ub == pytest.approx(ref_u, rel=1e-5)
    assert tb == pytest.approx(ref_t, rel=1e-5)
    # W&S's truncation of the spectrum at 0.2 and 5 fp costs < 0.1 % against a wider integral
    wide_u, _ = jonswap_bed_quad(hs, tp, h, lo=0.05, hi=30.0)
    assert ub == pytest.approx(wide_u, rel=1e-3)


def test_spectral_orbital_shallow_limit_and_deep_cut(table):
    # shallow water: u = eta sqrt(g/h), so u_br = sqrt(2) (Hs/4) sqrt(g/h) (F(0) = sqrt(2)/4)
    assert table[0, 0] == pytest.approx(math.sqrt(2) / 4, rel=1e-12)
    # beyond the table (Tn/Tp > TAU_MAX) the bed does not feel the waves
    assert S.orbital_spectral(1.0, 2.0, 100.0, G, table)[0] == 0.0
    assert S.orbital_spectral(1.0, 3.0, 50.0, G, table)[0] < 1e-5


# --- friction and stresses ------------------------------------------------------------------------------


def test_swart_branch_point():
    # Swart (1974): 0.3 up to A/ks = 1.57, then 0.00251 exp(5.21 (A/ks)^-0.19); the branches meet
    assert S.friction_swart(1.0) == 0.3
    assert S.friction_swart(1.57) == 0.3
    above = S.friction_swart(1.57 * (1 + 1e-12))
    assert above == pytest.approx(0.00251 * math.exp(5.21 * 1.57**-0.19), rel=1e-12)
    assert above == pytest.approx(0.29957, abs=5e-6)  # 0.14 % below the 0.3 branch
    assert S.friction_swart(1000.0) == pytest.approx(0.00251 * math.exp(5.21 * 1000.0**-0.19), rel=1e-12)


def test_soulsby_friction_and_wave_stress():
    assert S.friction_soulsby(500.0) == pytest.approx(1.39 * 500.0**-0.52, rel=1e-12)
    ub, tb, d50 = 0.4, 9.0, 2e-4
    a = ub * tb / (2 * math.pi)
    fw_swart = 0.00251 * math.exp(5.21 * (a / (2.5 * d50)) ** -0.19)
    fw_soulsby = 1.39 * (a / (2.5 * d50 / 30)) ** -0.52
    assert S.wave_stress(ub, tb, d50, RHO, S.FRICTION_SWART) == pytest.approx(
        0.5 * RHO * fw_swart * ub**2, rel=1e-12
    )
    assert S.wave_stress(ub, tb, d50, RHO, S.FRICTION_SOULSBY) == pytest.approx(
        0.5 * RHO * fw_soulsby * ub**2, rel=1e-12
    )
    assert S.wave_stress(0.0, tb, d50, RHO, S.FRICTION_SWART) == 0.0


def test_current_stress_log_profile():
    u, h, d50 = 0.5, 12.0, 2e-4
    z0 = d50 / 12
    # a speed at height z: u* = kappa u / ln(z/z0)
    assert S.current_stress(u, 1.0, h, d50, RHO) == pytest.approx(
        RHO * (KAPPA * u / math.log(1.0 / z0)) ** 2, rel=1e-12
    )
    # a depth mean: the mean of the log profile over the depth, integrated by quad, gives the same u*
    ustar = math.sqrt(S.current_stress(u, 0.0, h, d50, RHO) / RHO)
    mean = quad(lambda z: ustar / KAPPA * math.log(z / z0), z0, h, limit=200)[0] / h
    assert mean == pytest.approx(u, rel=1e-4)  # Soulsby's C_D drops a z0/h term (~1e-6)
    # invariance: the depth mean of a log profile is its value at h/e
    assert S.current_stress(u, 0.0, h, d50, RHO) == pytest.approx(
        S.current_stress(u, h / math.e, h, d50, RHO), rel=1e-12
    )


def test_combined_stress_limits():
    # pure current: tau_m = tau_max = tau_c; pure waves: tau_m = 0, tau_max = tau_w (Soulsby 1997)
    assert S.combined_stress(0.7, 0.0, 0.3) == pytest.approx((0.7, 0.7), rel=1e-15)
    assert S.combined_stress(0.0, 0.9, 1.1) == pytest.approx((0.0, 0.9), rel=1e-15)
    assert S.combined_stress(0.0, 0.0, 0.0) == (0.0, 0.0)
    tc, tw = 0.4, 0.6
    tm = tc * (1 + 1.2 * (tw / (tc + tw)) ** 3.2)
    assert S.combined_stress(tc, tw, 0.0) == pytest.approx((tm, tm + tw), rel=1e-14)
    assert S.combined_stress(tc, tw, math.pi / 2)[1] == pytest.approx(math.hypot(tm, tw), rel=1e-14)
    # the wave stress reverses each half period: waves against the current give the same peak
    phi = 0.4
    assert S.combined_stress(tc, tw, phi + math.pi)[1] == pytest.approx(
        S.combined_stress(tc, tw, phi)[1], rel=1e-14
    )


# --- threshold, ripples --------------------------------------------------------------------------------


@pytest.mark.parametrize("d50, expected", [(2e-4, 0.0553), (6e-4, 0.0311)])
def test_shields_threshold_quartz_in_sea_water(d50, expected):
    # Soulsby & Whitehouse (1997), written out here; sources.md §3 [computed] values
    dstar = d50 * (G * (SG - 1) / NU**2) ** (1 / 3)
    printed = 0.30 / (1 + 1.2 * dstar) + 0.055 * (1 - math.exp(-0.020 * dstar))
    got = S.shields_threshold(S.grain_size_number(d50, SG, G, NU))
    assert got == pytest.approx(printed, rel=1e-12)
    assert got == pytest.approx(expected, abs=1e-4)
    assert S.shields(1.0, RHO, SG, G, d50) == pytest.approx(1.0 / (RHO * (SG - 1) * G * d50), rel=1e-14)


def wh_steepness(d0, eta):
    """Wiberg & Harris (1994) eq. 13: eta/lambda as a function of ln(d0/eta)."""
    ln = math.log(d0 / eta)
    return math.exp(-0.095 * ln**2 + 0.442 * ln - 2.28)


def wh_height(d0, lam):
    """The ripple height of wavelength lam: the root of eta/lam = steepness(d0, eta) with
    ln(d0/eta) below the vertex 1.442/0.19 of the law (the larger, physical height), by brentq."""
    return brentq(lambda e: e / lam - wh_steepness(d0, e), d0 * math.exp(-1.442 / 0.19), d0, xtol=1e-15)


def wh_ripple(d0, d50):
    """(eta, regime) after Wiberg & Harris (1994): lambda_orb = 0.62 d0, lambda_ano = 535 d50, regime
    by d0/eta_ano (< 20 orbital, > 100 anorbital, log-interpolated lambda between)."""
    lam_orb, lam_ano = 0.62 * d0, 535 * d50
    ratio = d0 / wh_height(d0, lam_ano)
    if ratio < 20:
        return wh_height(d0, lam_orb), "orbital"
    if ratio > 100:
        return wh_height(d0, lam_ano), "anorbital"
    w = (math.log(ratio) - math.log(100)) / (math.log(20) - math.log(100))
    return wh_height(d0, math.exp(w * math.log(lam_orb / lam_ano) + math.log(lam_ano))), "suborbital"


@pytest.mark.parametrize(
    "d0, d50, regime", [(0.3, 1e-3, "orbital"), (1.0, 4e-4, "suborbital"), (1.5, 2e-4, "anorbital")]
)
def test_ripple_height_wiberg_harris(d0, d50, regime):
    eta, got_regime = wh_ripple(d0, d50)
    assert got_regime == regime
    assert S.ripple_height(d0, d50) == pytest.approx(eta, rel=1e-9)


def test_orbital_ripple_steepness():
    # W&H (1994): orbital ripples have lambda = 0.62 d0 and a steepness of about 0.17
    d0 = 0.3
    assert S.ripple_height(d0, 1e-3) / (0.62 * d0) == pytest.approx(0.17, abs=0.002)
    # no real root of the steepness law: the ripples are washed out
    assert math.isnan(S.ripple_height(30.0, 1e-3))


# --- the burial law and the stage ---------------------------------------------------------------------

HOUR = 3600.0
DAY = 86400.0


def series(n, dt=HOUR, hs=0.0, tp=10.0, wdir=0.0, uc=0.0, cdir=0.0, h=12.0):
    t = np.arange(n) * dt
    return [t] + [np.full(n, v, dtype=float) for v in (hs, tp, wdir, uc, cdir, h)]


def run(p, forcing, table, leads, fractions=(0.5,)):
    leads = np.asarray(leads, dtype=float)
    fractions = np.asarray(fractions, dtype=float)
    out_b = np.empty(leads.shape[0])
    out_t = np.empty(fractions.shape[0])
    status, t_mob, theta_max = S.scour_stage(p, *forcing, table, leads, fractions, out_b, out_t)
    return status, out_b, out_t, t_mob, theta_max


def current_theta(u, h, d50):
    """Shields parameter of a depth-mean current, Soulsby 1997 eqs. 37 and 74 written out."""
    cd = (KAPPA / (math.log(h / (d50 / 12)) - 1)) ** 2
    return cd * u * u / ((SG - 1) * G * d50)


def whitehouse_t(theta, diameter, d50):
    return 0.014 * theta**-1.29 * diameter**2 / math.sqrt(G * (SG - 1) * d50**3)


def test_closed_form_exponential_relaxation_under_a_steady_current(table):
    d, d50, b0, u, h = 0.53, 2e-4, 0.04, 0.6, 12.0
    theta = current_theta(u, h, d50)
    assert theta > 0.0553  # above the threshold of motion
    b_eq = d * 1.3 * theta**0.36
    big_t = whitehouse_t(theta, d, d50)
    p = S.default_parameters(b0=b0, diameter=d, d50=d50, mine_sg=4.0)
    leads = np.array([0.0, 0.1, 0.5, 1.0, 2.0, 3.7, 10.0]) * big_t
    forcing = series(int(12 * big_t / HOUR) + 2, uc=u, h=h)
    status, out_b, out_t, _, theta_max = run(p, forcing, table, leads, (0.2, 0.5, 0.99 * b_eq / d, 1.0))
    assert status == S.SCOUR_OK
    assert theta_max == pytest.approx(theta, rel=1e-12)
    expected = b_eq - (b_eq - b0) * np.exp(-leads / big_t)
    np.testing.assert_allclose(out_b, expected, rtol=1e-11)
    # times to reach 20 % and 50 % and 99 % of B_eq: T ln((B_eq - B0)/(B_eq - f D)); 100 % never
    for k, frac in enumerate((0.2, 0.5, 0.99 * b_eq / d)):
        assert out_t[k] == pytest.approx(big_t * math.log((b_eq - b0) / (b_eq - frac * d)), rel=1e-11)
    assert out_t[3] == math.inf


def test_closed_form_under_waves_and_current_with_kc_time_law(table):
    # monochromatic H_rms waves (Swart friction) plus a current at 60 degrees, the pile-in-waves
    # time law T* = 1e-6 (KC/theta)^3 (KC = 10.5, inside its quoted range 7-34): every quantity
    # evaluated here from the printed formulas
    d, d50, b0, h, hs, tp, u, phi = 0.3, 3e-4, 0.0, 10.0, 1.2, 9.0, 0.2, math.radians(60)
    ub = math.pi * hs / math.sqrt(2) / (tp * math.sinh(kh_brentq(2 * math.pi / tp, h)))
    a = ub * tp / (2 * math.pi)
    tau_w = 0.5 * RHO * 0.00251 * math.exp(5.21 * (a / (2.5 * d50)) ** -0.19) * ub**2
    tau_c = RHO * (KAPPA / (math.log(h / (d50 / 12)) - 1)) ** 2 * u * u
    tau_m = tau_c * (1 + 1.2 * (tau_w / (tau_c + tau_w)) ** 3.2)
    tau_max = math.hypot(tau_m + tau_w * math.cos(phi), tau_w * math.sin(phi))
    theta = tau_max / (RHO * (SG - 1) * G * d50)
    b_eq = d * 1.3 * theta**0.36
    kc = ub * tp / d
    assert 7 <= kc <= 34
    big_t = 1e-6 * (kc / theta) ** 3 * d**2 / math.sqrt(G * (SG - 1) * d50**3)
    c, m, pexp, kc_min = S.TSTAR_LAWS["pile_waves"]
    p = S.default_parameters(
        b0=b0,
        diameter=d,
        d50=d50,
        orbital=S.ORBITAL_HRMS,
        tstar_c=c,
        tstar_m=m,
        tstar_p=pexp,
        tstar_kc_min=kc_min,
    )
    leads = np.array([0.3, 1.0, 2.5]) * big_t
    forcing = series(int(3 * big_t / HOUR) + 2, hs=hs, tp=tp, wdir=phi, uc=u, h=h)
    status, out_b, _, _, theta_max = run(p, forcing, table, leads)
    assert status == S.SCOUR_OK
    assert theta_max == pytest.approx(theta, rel=1e-10)
    np.testing.assert_allclose(out_b, b_eq - (b_eq - b0) * np.exp(-leads / big_t), rtol=1e-9)


def law_parameters(name, **overrides):
    c, m, pexp, kc_min = S.TSTAR_LAWS[name]
    return S.default_parameters(tstar_c=c, tstar_m=m, tstar_p=pexp, tstar_kc_min=kc_min, **overrides)


def test_kc_time_law_without_waves_gives_no_growth_not_instant_burial(table):
    # review: a KC law (m > 0) had T* = 0 at KC = 0, so a current alone buried the mine to B_eq
    # within the first second. Now a wave law without waves (or below its KC range) gives T = inf
    u, h, d50, b0 = 0.6, 12.0, 2e-4, 0.01
    assert current_theta(u, h, d50) > 0.0553  # the current alone moves the sand
    p = law_parameters("pile_waves", b0=b0, d50=d50)
    leads = [1.0, HOUR, 10 * DAY]
    # a pure current; short waves that do not reach the bed (Tp = 1 s in 12 m: u_br = 0); and
    # waves whose KC lies below the law's range (KC < 7): the burial stays where the impact left it
    for hs, tp in ((0.0, 10.0), (0.3, 1.0), (0.3, 6.0)):
        ub, tb = S.orbital_spectral(hs, tp, h, G, table) if hs > 0 else (0.0, tp)
        assert ub * tb / 0.53 < 7.0
        status, out_b, out_t, _, theta_max = run(p, series(24 * 11, hs=hs, tp=tp, uc=u, h=h), table, leads)
        assert status == S.SCOUR_OK and theta_max > 0.0553
        np.testing.assert_array_equal(out_b, [b0, b0, b0])
        assert out_t[0] == math.inf
    # the time-scale kernel itself: inf below kc_min (KC = 0 included), the printed law from kc_min on
    for kc in (0.0, 6.999):
        assert S.scour_time_scale(0.1, kc, 0.53, d50, SG, G, 1e-6, 3.0, -3.0, 7.0) == math.inf
    scale = 0.53**2 / math.sqrt(G * (SG - 1) * d50**3)
    assert S.scour_time_scale(0.1, 7.0, 0.53, d50, SG, G, 1e-6, 3.0, -3.0, 7.0) == pytest.approx(
        1e-6 * (7.0 / 0.1) ** 3 * scale, rel=1e-12
    )


def test_pipeline_law_under_a_current_grows_on_its_time_scale_not_instantly(table):
    # review reproduction: the pipeline preset (then with KC^1.5) and a 0.6 m/s current gave
    # B = 0.32 m after 1 s. The law is T* = (1/50) theta^-5/3 (Fredsoe, Sumer & Arnskov 1992):
    # closed form B(t) = B_eq (1 - exp(-t/T)) with T evaluated here
    u, h, d, d50 = 0.6, 12.0, 0.53, 2e-4
    theta = current_theta(u, h, d50)
    big_t = theta ** (-5 / 3) / 50 * d**2 / math.sqrt(G * (SG - 1) * d50**3)
    b_eq = d * 1.3 * theta**0.36
    leads = np.array([1.0, HOUR, 0.5 * big_t, 2 * big_t])
    status, out_b, _, _, _ = run(
        law_parameters("pipeline"), series(int(2 * big_t / HOUR) + 2, uc=u, h=h), table, leads
    )
    assert status == S.SCOUR_OK
    np.testing.assert_allclose(out_b, b_eq * (1 - np.exp(-leads / big_t)), rtol=1e-10)
    assert out_b[0] < 1e-3  # not 0.32 m after one second


def test_two_forcing_levels_chain_the_exponentials(table):
    # a weaker current, then a stronger one: the second relaxation starts where the first ended
    d, d50, h = 0.53, 2e-4, 12.0
    p = S.default_parameters(diameter=d, d50=d50, mine_sg=4.0)
    forcing = series(3, dt=20 * HOUR, uc=0.45, h=h)
    forcing[4][1:] = 0.8
    th1, th2 = current_theta(0.45, h, d50), current_theta(0.8, h, d50)
    b1 = d * 1.3 * th1**0.36 * (1 - math.exp(-20 * HOUR / whitehouse_t(th1, d, d50)))
    beq2 = d * 1.3 * th2**0.36
    b2 = beq2 - (beq2 - b1) * math.exp(-10 * HOUR / whitehouse_t(th2, d, d50))
    status, out_b, _, _, _ = run(p, forcing, table, [20 * HOUR, 30 * HOUR])
    assert status == S.SCOUR_OK
    np.testing.assert_allclose(out_b, [b1, b2], rtol=1e-11)


def storm_forcing(seed, n=24 * 40):
    rng = np.random.default_rng(seed)
    t, hs, tp, wdir, uc, cdir, h = series(n)
    hs[:] = np.clip(1.0 + 0.8 * np.sin(np.arange(n) / 30.0) + 0.3 * rng.standard_normal(n), 0.0, None)
    tp[:] = 6.0 + 6.0 * rng.random(n)
    wdir[:] = rng.uniform(-math.pi, math.pi, n)
    uc[:] = 0.4 * rng.random(n)
    cdir[:] = rng.uniform(-math.pi, math.pi, n)
    h[:] = 12.0 + 0.5 * np.sin(np.arange(n) * 2 * math.pi / 12.42)
    return [t, hs, tp, wdir, uc, cdir, h]


@pytest.mark.parametrize("seed", [1, 2, 3])
def test_burial_never_decreases(table, seed):
    forcing = storm_forcing(seed)
    p = S.default_parameters(b0=0.02)
    leads = np.linspace(0.0, forcing[0][-1], 3001)
    status, out_b, _, _, _ = run(p, forcing, table, leads)
    assert status == S.SCOUR_OK
    assert out_b[0] == 0.02
    assert np.all(np.diff(out_b) >= 0.0)
    assert out_b[-1] > 0.02  # the storm does bury
    assert np.all(out_b <= p[S.S_DIAMETER])


def test_no_growth_below_threshold(table):
    d50, h = 2e-4, 12.0
    u = 0.15
    assert current_theta(u, h, d50) < 0.0553
    p = S.default_parameters(b0=0.1, d50=d50)
    status, out_b, out_t, _, _ = run(
        p, series(200, uc=u, h=h), table, [0.0, 50 * HOUR, 199 * HOUR], (0.1, 0.5)
    )
    assert status == S.SCOUR_OK
    np.testing.assert_array_equal(out_b, [0.1, 0.1, 0.1])
    assert out_t[0] == 0.0  # 0.1 * 0.53 m is below the initial burial
    assert out_t[1] == math.inf


def test_caps_mobile_layer_full_burial_and_cohesive_bed(table):
    forcing = series(24 * 60, uc=0.8)
    leads = [59 * DAY]
    # mobile layer 0.12 m: the burial tends to it and never passes it
    status, out_b, _, _, _ = run(S.default_parameters(mobile_layer=0.12), forcing, table, leads)
    assert status == S.SCOUR_OK and out_b[0] == pytest.approx(0.12, rel=1e-9) and out_b[0] <= 0.12
    # an impact burial already deeper than the layer stays as it is
    _, out_b, _, _, _ = run(S.default_parameters(mobile_layer=0.12, b0=0.2), forcing, table, leads)
    assert out_b[0] == 0.2
    # the small-object law (a ~ 15, b ~ 1.1) would pass full burial: capped at D
    _, out_b, _, _, _ = run(S.default_parameters(beq_a=15.0, beq_b=1.1), forcing, table, leads)
    assert out_b[0] == pytest.approx(0.53, rel=1e-9) and out_b[0] <= 0.53
    # a cohesive bed does not scour in this model
    _, out_b, _, _, _ = run(S.default_parameters(cohesive=1.0, b0=0.05), forcing, table, leads)
    assert out_b[0] == 0.05


def mono_ub(hs, tp, h):
    """Near-bed orbital amplitude of a monochromatic wave of height hs (linear theory, brentq root)."""
    return math.pi * hs / (tp * math.sinh(kh_brentq(2 * math.pi / tp, h)))


def smoothstep_weight(d50, d_mid=5e-4, half_phi=0.5):
    """The documented blend (docs/scour.md, Coarse sand) written out: 3x^2 - 2x^3 of the position x
    in log2(d50) across [d_mid 2^-half_phi, d_mid 2^half_phi], 0 below, 1 above."""
    x = (math.log2(d50) - math.log2(d_mid) + half_phi) / (2 * half_phi)
    x = min(max(x, 0.0), 1.0)
    return x * x * (3 - 2 * x)


#: coarse-sand waves of the exposure tests: orbital ripples of ~0.1 m (MVCO coarse sand: 0.1-0.2 m,
#: Traykovski et al. 2007), a Rennie B_eq well above the exposure limit
COARSE_WAVES = dict(hs=1.5, tp=8.0, h=10.0)


@pytest.mark.parametrize("exposure", [1.0, 1.5, 2.0])
def test_exposure_limit_in_coarse_sand(table, exposure):
    # coarse sand (1 mm, weight 1) under monochromatic waves: burial stops where the mine's top stands
    # `exposure` ripple heights above the crests, the crests eta/2 above the mean bed:
    # B = D - (exposure + 1/2) eta, eta the Wiberg-Harris height (brentq)
    d50, d = 1e-3, 0.53
    hs, tp, h = COARSE_WAVES.values()
    p = S.default_parameters(d50=d50, orbital=S.ORBITAL_HS, ripple_exposure=exposure)
    eta, regime = wh_ripple(mono_ub(hs, tp, h) * tp / math.pi, d50)
    assert regime == "orbital" and 0.05 < eta < 0.2
    status, out_b, _, _, _ = run(p, series(24 * 30, hs=hs, tp=tp, h=h), table, [29 * DAY])
    assert status == S.SCOUR_OK
    limit = d - (exposure + 0.5) * eta
    assert out_b[0] == pytest.approx(limit, rel=1e-8) and out_b[0] <= limit * (1 + 1e-12)
    # Traykovski et al. (2007): height above the crests = exposure x ripple height
    assert (d - out_b[0]) - 0.5 * eta == pytest.approx(exposure * eta, rel=1e-7)
    # the same waves over fine sand (weight 0) are not limited by ripples: the Rennie B_eq, capped at D
    _, out_fine, _, _, _ = run(
        S.default_parameters(d50=2e-4, orbital=S.ORBITAL_HS),
        series(24 * 30, hs=hs, tp=tp, h=h),
        table,
        [29 * DAY],
    )
    assert out_fine[0] > limit


def test_exposure_limit_closed_form():
    d, eta = 0.53, 0.12
    assert S.exposure_limit(d, eta, 1.0, 1.0) == pytest.approx(d - 1.5 * eta, rel=1e-15)
    assert S.exposure_limit(d, eta, 1.0, 0.5) == pytest.approx(d - 0.75 * eta, rel=1e-15)
    assert S.exposure_limit(d, eta, 1.0, 0.0) == d
    assert S.exposure_limit(0.1, eta, 1.0, 1.0) == 0.0  # a small mine in big ripples: never below the bed


def test_coarse_weight_is_a_smooth_blend_over_one_phi_unit():
    for d50 in np.geomspace(2e-4, 1.5e-3, 97):
        assert S.coarse_weight(d50, 5e-4) == pytest.approx(smoothstep_weight(d50), abs=1e-14)
    assert S.coarse_weight(5e-4 / math.sqrt(2), 5e-4) == pytest.approx(0.0, abs=1e-14)
    assert S.coarse_weight(5e-4, 5e-4) == pytest.approx(0.5, rel=1e-14)
    assert S.coarse_weight(5e-4 * 2**0.25, 5e-4) == pytest.approx(0.84375, rel=1e-13)
    assert S.coarse_weight(5e-4 * math.sqrt(2), 5e-4) == pytest.approx(1.0, abs=1e-14)
    w = [S.coarse_weight(d50, 5e-4) for d50 in np.geomspace(1e-4, 2e-3, 500)]
    assert np.all(np.diff(w) >= 0.0)
    # the largest slope of 3x^2 - 2x^3 is 1.5 (at x = 1/2), x spans one phi unit: between 0.49 and
    # 0.50 mm (log2(50/49) = 0.029 phi) the weight moves by at most 0.044
    assert S.coarse_weight(5e-4, 5e-4) - S.coarse_weight(4.9e-4, 5e-4) <= 1.5 * math.log2(5 / 4.9) + 1e-12


def test_burial_is_continuous_and_monotone_across_grain_size(table):
    # the exposure limit blends in with d50: no jump between 0.49 and 0.50 mm (was x4.6 with the
    # switch at 0.5 mm), and the 30-day burial does not grow with d50 (coarser grains: smaller
    # theta, a larger limit weight)
    hs, tp, h = COARSE_WAVES.values()
    forcing = series(24 * 30, hs=hs, tp=tp, h=h)
    grid = np.round(np.arange(3.0e-4, 8.01e-4, 1e-5), 10)
    out = []
    for d50 in grid:
        status, b, _, _, _ = run(
            S.default_parameters(d50=d50, orbital=S.ORBITAL_HS), forcing, table, [29 * DAY]
        )
        assert status == S.SCOUR_OK
        out.append(b[0])
    out = np.array(out)
    assert np.all(np.diff(out) <= 1e-12)
    rel = -np.diff(out) / out[1:]
    assert rel.max() < 0.03
    b49, b50 = out[np.isclose(grid, 4.9e-4)][0], out[np.isclose(grid, 5.0e-4)][0]
    assert abs(b49 - b50) / b50 < 0.03
    # inside the blend, at d50 = 0.6 mm (weight 0.79), the limit binds: B = D - w (1 + 1/2) eta
    d50 = 6e-4
    eta, _ = wh_ripple(mono_ub(hs, tp, h) * tp / math.pi, d50)
    b60 = out[np.isclose(grid, d50)][0]
    assert b60 == pytest.approx(0.53 - smoothstep_weight(d50) * 1.5 * eta, rel=1e-8)


def mobility_u_crit(d, d50, sg):
    """Speed at the mobility threshold of Rennie et al. (2017), U^2/(g D (s_obj - 1)) = 1.6 (D/k)^-0.72,
    k = 2.5 d50, written out."""
    return math.sqrt(1.6 * (d / (2.5 * d50)) ** -0.72 * G * d * (sg - 1))


def test_mobility_flag_time_for_a_proud_mine(table):
    # a proud mine (B0 = 0) on the criterion's rigid-bottom roughness: flagged in the first
    # interval whose speed passes the threshold, not flagged at 0.9 of it
    d, d50, sg = 0.53, 2e-4, 2.0
    u_crit = mobility_u_crit(d, d50, sg)
    forcing = series(10, uc=0.5 * u_crit)
    forcing[4][6:] = 1.1 * u_crit
    p = S.default_parameters(diameter=d, d50=d50, mine_sg=sg)
    _, _, _, t_mob, _ = run(p, forcing, table, [HOUR])
    assert t_mob == 6 * HOUR
    forcing[4][6:] = 0.9 * u_crit
    _, _, _, t_mob, _ = run(p, forcing, table, [HOUR])
    assert t_mob == math.inf


def test_buried_mine_is_not_flagged_mobile(table):
    # review: the rigid-bottom criterion flagged nearly every drop, buried or not. A mine buried
    # beyond S_MOB_BURIAL_MAX (0.1 D) is not flagged, whatever the speed
    d, d50, sg = 0.53, 2e-4, 2.0
    forcing = series(10, uc=2.0 * mobility_u_crit(d, d50, sg))
    for b0, flagged in ((0.3 * d, False), (0.11 * d, False), (0.09 * d, True), (0.0, True)):
        _, _, _, t_mob, _ = run(
            S.default_parameters(b0=b0, diameter=d, d50=d50, mine_sg=sg), forcing, table, [HOUR]
        )
        assert (t_mob == 0.0) if flagged else (t_mob == math.inf), b0


def test_mine_scoured_below_the_proud_limit_before_the_flow_peaks_is_not_flagged(table):
    # a heavy proud mine scours under 0.45 m/s for 10 h (closed form: B/D > 0.1), then the flow
    # passes its mobility threshold: by then it is no longer proud, so it is not flagged; with
    # the flow peaking in the first hour instead it is
    d, d50, sg, h, u1 = 0.53, 2e-4, 6.0, 12.0, 0.45
    u_crit = mobility_u_crit(d, d50, sg)
    assert u1 < u_crit and current_theta(u1, h, d50) > 0.0553
    th = current_theta(u1, h, d50)
    b10 = d * 1.3 * th**0.36 * (1 - math.exp(-10 * HOUR / whitehouse_t(th, d, d50)))
    assert b10 > 0.1 * d
    forcing = series(14, uc=u1, h=h)
    forcing[4][10:] = 1.2 * u_crit
    p = S.default_parameters(diameter=d, d50=d50, mine_sg=sg)
    status, out_b, _, t_mob, _ = run(p, forcing, table, [10 * HOUR])
    assert status == S.SCOUR_OK and out_b[0] == pytest.approx(b10, rel=1e-11)
    assert t_mob == math.inf
    forcing[4][:] = 1.2 * u_crit
    assert run(p, forcing, table, [HOUR])[3] == 0.0


def test_current_height_within_the_roughness_or_above_the_water_is_rejected(table):
    # review: a current height in (0, z0] gave ln(z/z0) <= 0, theta = inf and full burial with
    # status OK; a depth below e z0 broke the depth-mean drag; a height above the water passed
    d50, h = 2e-4, 12.0
    ks = 2.5 * d50
    good = series(10, uc=0.5, h=h)
    for z in (d50 / 12, 0.5 * d50 / 12, 0.5 * ks, -math.inf, math.inf):
        status, out_b, _, _, _ = run(S.default_parameters(d50=d50, current_z=z), good, table, [HOUR])
        assert status == S.SCOUR_INVALID_PARAMETER and math.isnan(out_b[0]), z
    # from ks up the log law holds: theta as written out (Soulsby 1997 eq. 30 with z0 = d50/12)
    for z in (ks, 1.0):
        status, _, _, _, theta_max = run(S.default_parameters(d50=d50, current_z=z), good, table, [HOUR])
        ustar = KAPPA * 0.5 / math.log(z / (d50 / 12))
        assert status == S.SCOUR_OK and theta_max == pytest.approx(ustar**2 / ((SG - 1) * G * d50), rel=1e-12)
    # a current height above the water surface at some time: invalid forcing
    p = S.default_parameters(d50=d50, current_z=2.0)
    tide = [a.copy() for a in good]
    tide[6][4] = 1.9
    assert run(p, tide, table, [HOUR])[0] == S.SCOUR_INVALID_FORCING
    tide[6][4] = 2.1
    assert run(p, tide, table, [HOUR])[0] == S.SCOUR_OK
    # the depth floor: 10 ks (h/z0 = 300, ln(h/z0) - 1 = 4.7); e z0 would make C_D infinite
    assert S.depth_floor(d50) == pytest.approx(10 * ks, rel=1e-15)
    assert math.log(10 * ks / (d50 / 12)) - 1 == pytest.approx(math.log(300) - 1, rel=1e-12)
    for depth, expected in (
        (math.e * d50 / 12, S.SCOUR_INVALID_FORCING),
        (0.99 * 10 * ks, S.SCOUR_INVALID_FORCING),
        (1.01 * 10 * ks, S.SCOUR_OK),
    ):
        shallow = [a.copy() for a in good]
        shallow[6][3] = depth
        assert run(S.default_parameters(d50=d50), shallow, table, [HOUR])[0] == expected


@pytest.mark.parametrize(
    "key, value",
    [
        ("beq_b", 0.0),
        ("beq_b", -0.36),
        ("tstar_p", 0.0),
        ("tstar_p", 0.5),
        ("tstar_m", -1.0),
        ("tstar_kc_min", -1.0),
        ("tstar_kc_min", math.inf),
        ("mob_p", 0.0),
        ("mob_burial_max", -0.1),
        ("mob_burial_max", 1.5),
        ("ripple_exposure", -0.5),
        ("ripple_exposure", math.inf),
        ("ripple_d50", 0.0),
    ],
)
def test_parameters_outside_their_documented_ranges_are_invalid(table, key, value):
    # b > 0, p < 0, m >= 0, 0 <= kc_min < inf, mobility exponent < 0, proud limit in [0, 1],
    # a finite ripple exposure >= 0, a positive blend grain size
    status, out_b, _, _, _ = run(S.default_parameters(**{key: value}), series(10, uc=0.5), table, [HOUR])
    assert status == S.SCOUR_INVALID_PARAMETER and math.isnan(out_b[0])


def test_kc_law_needs_a_positive_kc_floor(table):
    forcing = series(10, uc=0.5)
    assert run(S.default_parameters(tstar_m=1.5), forcing, table, [HOUR])[0] == S.SCOUR_INVALID_PARAMETER
    assert run(S.default_parameters(tstar_m=1.5, tstar_kc_min=2.0), forcing, table, [HOUR])[0] == S.SCOUR_OK


def test_lead_times_in_any_order_match_the_closed_form(table):
    # the lead times are visited in sorted order with one pointer; any order, repeats, zero,
    # the last sample, negative, beyond and NaN give each its own answer
    d, d50, u, h, b0 = 0.53, 2e-4, 0.6, 12.0, 0.03
    th = current_theta(u, h, d50)
    b_eq, big_t = d * 1.3 * th**0.36, whitehouse_t(th, d, d50)
    forcing = series(25, uc=u, h=h)
    span = forcing[0][-1]
    leads = np.array(
        [5.5 * HOUR, 0.0, span, -1.0, 2 * HOUR, math.nan, 5.5 * HOUR, span + 1.0, 0.25 * HOUR, HOUR]
    )
    status, out_b, _, _, _ = run(S.default_parameters(b0=b0, diameter=d, d50=d50), forcing, table, leads)
    assert status == S.SCOUR_BEYOND_FORCING
    inside = np.array([0, 1, 2, 4, 6, 8, 9])
    expected = b_eq - (b_eq - b0) * np.exp(-leads[inside] / big_t)
    np.testing.assert_allclose(out_b[inside], expected, rtol=1e-11)
    assert np.isnan(out_b[[3, 5, 7]]).all()


def test_status_codes(table):
    good = series(10, uc=0.5)
    p = S.default_parameters()
    bad_p = S.default_parameters(d50=math.nan)
    status, out_b, _, _, _ = run(bad_p, good, table, [HOUR])
    assert status == S.SCOUR_INVALID_PARAMETER and math.isnan(out_b[0])
    assert run(S.default_parameters(mine_sg=0.9), good, table, [HOUR])[0] == S.SCOUR_INVALID_PARAMETER
    for field, index, value in ((0, 5, 3 * HOUR), (1, 2, -0.1), (1, 3, math.nan), (2, 0, 0.0), (6, 1, 0.0)):
        forcing = [a.copy() for a in good]
        forcing[field][index] = value
        status, out_b, _, _, _ = run(p, forcing, table, [HOUR])
        assert status == S.SCOUR_INVALID_FORCING, (field, index, value)
        assert math.isnan(out_b[0])
    assert run(p, [a[:1] for a in good], table, [0.0])[0] == S.SCOUR_INVALID_FORCING
    # a lead time beyond the forcing: NaN there, the others valid
    status, out_b, _, _, _ = run(p, good, table, [HOUR, 9 * HOUR, 9.5 * HOUR, -1.0])
    assert status == S.SCOUR_BEYOND_FORCING
    assert np.isfinite(out_b[:2]).all() and np.isnan(out_b[2:]).all()
    assert run(p, good, table, [HOUR], (math.nan,))[0] == S.SCOUR_INVALID_PARAMETER
    assert run(S.default_parameters(tstar_p=math.nan), good, table, [HOUR])[0] == S.SCOUR_INVALID_PARAMETER
