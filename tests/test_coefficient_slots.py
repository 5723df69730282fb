"""Three constants of the kernels made scenario fields (issue 32), so that a calibration can sample
them per drop: ``sediment.bearing_depth_factor`` (Brinch Hansen's 0.4), ``numerics.crossflow_drag_factor``
(a factor on seed 000 eq. (44) above Re = 150 000) and ``sediment.inertial_drag`` (the soil's
inertial drag ½ C_D ρ_s v_n², none by default).

References, each independent of the kernels: the printed laws written out here (the bearing law
with the literal 0.4, eq. (44)'s branches, the strip drag ½ ρ C_d2 d ℓ V²), the closed-form
terminal speed of a cylinder sinking broadside, and the 1-D ``solve_ivp`` solution of an axial
penetration (mineburial/validation/references.py, which writes the force law itself).
"""

import math

import numpy as np
import pytest
from scipy.optimize import brentq

from mineburial.errors import ScenarioError
from mineburial.kernels.mine import layout, status
from mineburial.kernels.mine.coefficients import roughness_scaled
from mineburial.kernels.mine.dynamics import impact35_strip_forces, strip_forces
from mineburial.kernels.mine.sediment.laws import LAW_REFERENCE_PATHS, _traction, pack_law
from mineburial.systems.mine.config import SCHEMA, Scenario, check_params
from mineburial.systems.mine.drop import run_params
from mineburial.validation import cases

G = 9.81
RHO_W = 1025.0
NU = 1.0e-6
NC0 = math.pi + 2.0
EMPTY_BANK = np.full((1, 3, 2), np.nan)


def _scenario(sediment=None, numerics=None, **sections):
    d = {
        "mine": {"length": 2.0, "diameter": 0.5, "mass": 700.0},
        "environment": {"water_depth": 30.0, "water_density": RHO_W, "gravity": G, "water_viscosity": NU},
        "sediment": {
            "density": 1500.0,
            "density_gradient": 40.0,
            "strength": 2000.0,
            "strength_gradient": 0.0,
            "resistance": "bearing",
            "rate_law": "none",
            "friction": 0.0,
            **(sediment or {}),
        },
        "numerics": numerics or {},
        **sections,
    }
    return Scenario.from_dict(d)


def _nose_traction(p, zeta, vn, vt=0.0):
    """Traction (body frame) of the packed law at a point of the nose cap (outward normal +i_M)
    at depth ``zeta``, the mine moving at ``vn`` along its axis and ``vt`` across it."""
    law = pack_law(p, p[layout.P_DIAMETER])[:LAW_REFERENCE_PATHS]  # as the rules receive it
    return _traction(1.0, 0.1, 0.0, 1.0, 0.0, 0.0, zeta, vn, vt, 0.0, 0.0, 0.0, 0.0, law, EMPTY_BANK)


# ---------------------------------------------------------------------------
# (a) the defaults are the constants the kernels held
# ---------------------------------------------------------------------------
def test_defaults_are_the_constants_of_the_printed_laws():
    p, _, _ = _scenario().to_params()
    assert p[layout.P_SED_DEPTH_FACTOR] == 0.4  # Brinch Hansen (1970)
    assert p[layout.P_CROSSFLOW_FACTOR] == 1.0  # eq. (44) as printed
    assert p[layout.P_SED_CD] == 0.0  # seed 000 has no inertial drag
    # appended after the last slot of the layout before issue 32 (numba's cache is keyed per file);
    # later slots (issue 34's water column, issue 36's shape) come after them
    k = layout.INDEX["numerics.overburden_quadrature"] + 1
    assert layout.PARAM_NAMES[k : k + 3] == (
        "sediment.bearing_depth_factor",
        "numerics.crossflow_drag_factor",
        "sediment.inertial_drag",
    )


@pytest.mark.parametrize("zeta", [0.0, 0.013, 0.37, 1.9, 11.0])
@pytest.mark.parametrize("vn", [2e-3, 0.8, 7.5])
def test_default_bearing_pressure_is_the_printed_law_bit_for_bit(zeta, vn):
    """With the defaults the normal pressure is N_c0 (1 + 0.4 arctan(ζ/d)) S h_n, written here
    with the literal 0.4 and no drag term, to the last bit (the same operations in the same
    order; rate law none)."""
    sc = _scenario(sediment={"strength_gradient": 1500.0})
    p, _, _ = sc.to_params()
    d = p[layout.P_DIAMETER]
    s = 2000.0 + 1500.0 * zeta
    vreg = sc.numerics.switch_speed
    hn = vn / math.sqrt(vn * vn + vreg * vreg)
    expected = NC0 * (1.0 + 0.4 * math.atan(zeta / d)) * s * 1.0 * hn
    t = _nose_traction(p, zeta, vn)
    assert t[0] == -expected
    assert t[1] == 0.0 and t[2] == 0.0


def test_unit_factor_leaves_every_cross_drag_coefficient_bit_for_bit():
    rng = np.random.default_rng(32)
    for re in np.concatenate([10.0 ** rng.uniform(-8, 8, 2000), [150000.0, 150000.0000001, 2e6, 0.0]]):
        cd = rng.uniform(0.0, 3.0)
        assert roughness_scaled(cd, re, 1.0) == cd
    assert math.isnan(roughness_scaled(math.nan, 2e6, 1.0))


def test_explicit_defaults_give_the_same_drops_as_absent_fields():
    """The same drop with the three fields written at their defaults and left out: every summary
    value equal (what a calibration that draws the defaults gets), and the axial drop at its
    1-D reference (mineburial validate's row)."""
    sc = _scenario(
        release={"position": [0.0, 0.0, -20.0], "pitch_deg": 35.0, "velocity": [1.0, 0.0, -4.0]},
        numerics={"t_max": 10.0},
    )
    given = _scenario(
        sediment={"bearing_depth_factor": 0.4, "inertial_drag": 0.0},
        release={"position": [0.0, 0.0, -20.0], "pitch_deg": 35.0, "velocity": [1.0, 0.0, -4.0]},
        numerics={"t_max": 10.0, "crossflow_drag_factor": 1.0},
    )
    code_a, sa, _ = run_params(*sc.to_params())
    code_b, sb, _ = run_params(*given.to_params())
    assert code_a == code_b == status.AT_REST
    assert np.array_equal(sa, sb)
    (row,) = cases.axial_penetration()
    assert row.passed and abs(row.model - row.reference) < 0.01 * row.reference, row


# ---------------------------------------------------------------------------
# (b) the deep bearing factor N_c0 (1 + f π/2)
# ---------------------------------------------------------------------------
@pytest.mark.parametrize("f", [0.4, 0.85])
def test_bearing_factor_at_the_seabed_and_deep(f):
    sc = _scenario(sediment={"bearing_depth_factor": f})
    p, _, _ = sc.to_params()
    d = p[layout.P_DIAMETER]
    vn, vreg = 1.5, sc.numerics.switch_speed
    scale = 2000.0 * vn / math.sqrt(vn * vn + vreg * vreg)  # S h_n (G = 1)
    assert -_nose_traction(p, 0.0, vn)[0] / scale == pytest.approx(NC0, rel=1e-15)
    deep = -_nose_traction(p, 1e12 * d, vn)[0] / scale
    assert deep == pytest.approx(NC0 * (1.0 + f * math.pi / 2.0), rel=1e-11)
    # one diameter down: arctan(1) = π/4
    assert -_nose_traction(p, d, vn)[0] / scale == pytest.approx(NC0 * (1.0 + f * math.pi / 4.0), rel=1e-14)


def test_the_described_deep_values():
    """The field's description quotes the deep value of the defaults and the f of a deep 12."""
    text = SCHEMA["sediment.bearing_depth_factor"].description
    assert f"{NC0 * (1 + 0.4 * math.pi / 2):.1f}" == "8.4" and "8.4" in text
    assert f"{(12.0 / NC0 - 1.0) / (math.pi / 2):.2f}" == "0.85" and "0.85" in text


# ---------------------------------------------------------------------------
# (c) the cross-flow drag factor above Re = 150 000
# ---------------------------------------------------------------------------
def _eq44(re, aspect):
    """Seed 000 eq. (44), the two branches used here, as printed."""
    if 12000.0 < re <= 150000.0 and 2.0 <= aspect < 10.0:
        return 0.835 - 0.35 / aspect
    if re > 350000.0:
        return 1.0 / (641550.0 / re + 1.5)
    raise ValueError(re)


@pytest.mark.parametrize("eta", [1.0, 0.6])  # munk_factor model; viscous_crossflow's η(L/D = 4)
@pytest.mark.parametrize("impact35", [False, True])
def test_cross_drag_scales_by_the_factor_above_re_150000_only(eta, impact35):
    rho, R, L = 1025.0, 0.25, 2.0
    a, b = -0.6, 0.9  # a strip of the body
    d = 2 * R
    for re in (4e4, 2e6):
        v = re * NU / d  # uniform cross-flow, no rotation: Re = v d / ν exactly as the kernel forms it

        def force(factor, re=re, v=v):
            if impact35:
                return impact35_strip_forces(rho, NU, R, L, a, b, 0.3, v, 0.0, 0.0, 0.0, 0.0, 1, factor)
            return strip_forces(rho, NU, R, L, a, b, 0.3, v, 0.0, 0.0, 0.0, 0.0, 1, eta, factor)

        base = force(1.0)
        e = 1.0 if (impact35 or re <= 150000.0) else eta  # η multiplies eq. (44) outside its L/D band
        closed = 0.5 * rho * e * _eq44(re, L / d) * d * (b - a) * v * v
        assert base[1] == pytest.approx(closed, rel=1e-12)
        for factor in (0.6, 2.2):
            out = force(factor)
            assert out[0] == base[0] and out[3] == base[3]  # axial drag, roll damping: untouched
            if re <= 150000.0:
                assert out == base  # below the super-critical range: bit for bit
            else:
                assert out[1] == pytest.approx(factor * closed, rel=1e-12)
                assert out[2] == pytest.approx(factor * base[2], abs=1e-12 * closed)


def _broadside_speed(mass, length, diameter, factor):
    """Terminal speed of a cylinder sinking broadside, weight in water = ½ ρ f C_d2(Re) d L v²
    (Re > 350 000 branch of eq. (44)), by brentq."""
    weight = (mass - RHO_W * math.pi * diameter**2 / 4 * length) * G

    def excess(v):
        return weight - 0.5 * RHO_W * factor * _eq44(v * diameter / NU, 4.0) * diameter * length * v * v

    v = brentq(excess, 0.8, 50.0, xtol=1e-14, rtol=1e-14)
    assert v * diameter / NU > 350000.0
    return v


@pytest.mark.parametrize("factor", [1.0, 1.6])
def test_a_broadside_sinker_reaches_the_terminal_speed_of_the_scaled_drag(factor):
    """A heavy cylinder (2 m x 0.5 m, 1400 kg) released at rest broadside 1 m under the surface of
    90 m of water: at the seabed it sinks at the closed-form terminal speed (Re ≈ 2e6), the
    factor times eq. (44)'s drag; τ = v_t/g' ≈ 0.8 s, the fall ≈ 20 τ."""
    mass, length, diameter = 1400.0, 2.0, 0.5
    sc = _scenario(
        mine={"length": length, "diameter": diameter, "mass": mass},
        environment={"water_depth": 90.0, "water_density": RHO_W, "gravity": G, "water_viscosity": NU},
        release={"position": [0.0, 0.0, -1.0], "pitch_deg": 0.0},
        numerics={"crossflow_drag_factor": factor, "t_max": 0.5},
    )
    p, sb, cb = sc.to_params()
    _, summary, _ = run_params(p, sb, cb)
    v_t = _broadside_speed(mass, length, diameter, factor)
    assert summary[layout.S_IMPACT_SPEED] == pytest.approx(v_t, rel=1e-4)
    assert abs(summary[layout.S_IMPACT_PITCH]) < 1e-6


# ---------------------------------------------------------------------------
# (d) the soil's inertial drag ½ C_D ρ_s v_n²
# ---------------------------------------------------------------------------
@pytest.mark.parametrize("resistance", ["bearing", "friction", "delta"])
def test_inertial_drag_adds_the_dynamic_pressure_on_advancing_elements(resistance):
    sc = _scenario(sediment={"resistance": resistance, "friction": 0.3, "rate_law": "semilog"})
    p, _, _ = sc.to_params()
    q = p.copy()
    q[layout.P_SED_CD] = 0.7
    zeta, vn, vt = 0.8, 3.0, 0.4
    rho_s = 1500.0 + 40.0 * zeta  # the linear profile at the point
    t0 = np.array(_nose_traction(p, zeta, vn, vt))
    t1 = np.array(_nose_traction(q, zeta, vn, vt))
    assert t0[0] - t1[0] == pytest.approx(0.5 * 0.7 * rho_s * vn * vn, rel=1e-12)
    assert t1[1] == t0[1] and t1[2] == t0[2]  # no friction follows from it
    # a receding element (v_n < 0) feels none
    assert _nose_traction(q, zeta, -vn, vt) == _nose_traction(p, zeta, -vn, vt)


def _axial(depth_factor, inertial_drag, quadrature):
    """The axial-penetration case of ``mineburial validate`` (validation/cases.py) with the two
    sediment coefficients, and its 1-D solve_ivp reference."""
    sc, zeta = cases.axial_case(depth_factor, inertial_drag, quadrature)
    code, summary, _ = run_params(*sc.to_params())
    assert code == status.AT_REST
    return summary[layout.S_PENETRATION], zeta


@pytest.mark.parametrize("quadrature", ["fast", "reference"])
def test_axial_drop_with_the_coefficients_matches_the_one_dimensional_solution(quadrature):
    """A deep N_c of 12 (f = 0.85) and an inertial drag C_D = 0.7 each shorten the penetration
    of the vertical drop, which stays within 1 % of the 1-D solution of the same force law."""
    pen = {}
    for f, cd in ((0.4, 0.0), (0.85, 0.0), (0.4, 0.7)):
        model, reference = _axial(f, cd, quadrature)
        assert model == pytest.approx(reference, rel=0.01), (f, cd)
        pen[f, cd] = model
    assert pen[0.85, 0.0] < pen[0.4, 0.0] and pen[0.4, 0.7] < pen[0.4, 0.0], pen


# ---------------------------------------------------------------------------
# (e) bad values refused, naming the field and its range
# ---------------------------------------------------------------------------
def test_values_outside_the_ranges_are_refused():
    with pytest.raises(
        ScenarioError, match=r"sediment\.inertial_drag = 3\.0 is outside the allowed range \[0, 2\]"
    ):
        _scenario(sediment={"inertial_drag": 3.0})
    with pytest.raises(ScenarioError, match=r"numerics\.crossflow_drag_factor = 0\.0 .*\(0, 5\]"):
        _scenario(numerics={"crossflow_drag_factor": 0.0})
    with pytest.raises(ScenarioError, match=r"sediment\.bearing_depth_factor = -0\.1 .*\[0, 5\]"):
        _scenario(sediment={"bearing_depth_factor": -0.1})
    p, _, _ = _scenario().to_params()
    rows = np.tile(p, (3, 1))
    rows[1, layout.P_CROSSFLOW_FACTOR] = 0.0
    rows[2, layout.P_SED_DEPTH_FACTOR] = 6.0
    ok = check_params(rows)
    assert ok.tolist() == [True, False, False]
