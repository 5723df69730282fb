"""The water-column model choice ``numerics.water_column`` (docs/physics.md, "Water-column
model choices"): coefficient tables against their published/computed values, the added-mass
tensor and the Munk moment of ``viscous_crossflow`` against closed forms computed here, energy
conservation, and the default (``munk_factor``) left as it was."""

import math
import re

import numpy as np
import pytest
import tomllib
from conftest import make_scenario
from scipy.spatial.transform import Rotation

from mineburial.analyses import compare
from mineburial.ensembles import engine
from mineburial.errors import ScenarioError
from mineburial.kernels.mine import added_mass, layout
from mineburial.kernels.mine.coefficients import cross_drag_coefficient
from mineburial.systems.mine import ensemble as mine
from mineburial.systems.mine import model_form
from mineburial.systems.mine.drop import simulate_drop

RHO = 1025.0
L, D = 1.0, 0.25  # conftest's mine: L/D = 4, a tabulated aspect ratio
R = D / 2
VOL = math.pi * R * R * L
G = 9.81

# shared/notes/sources.md section 1 [computed]: closed finite cylinder, boundary elements
BEM = {2.0: (0.736, 0.305), 3.0: (0.810, 0.208), 4.0: (0.852, 0.157), 6.0: (0.898, 0.106)}
# rotational added inertia about the centroid, of strip theory's rho pi R^2 L^3 / 12:
# benchmarks/results/water_column_models.txt (capytaine, direct method) [computed]
BEM_ROT = {2.0: 0.4645, 3.0: 0.5686, 4.0: 0.6429, 6.0: 0.7360}
# Digital DATCOM bodyrt.f crossflow efficiency (Jorgensen, NASA TR R-474)
DATCOM_ETA = {2.0: 0.56, 4.0: 0.60, 8.0: 0.66, 12.0: 0.71, 16.0: 0.74, 20.0: 0.76}


def crossflow_scenario(**numerics):
    base = {"water_column": "viscous_crossflow", "drag": False, "integrator": "rk4", "dt": 1e-5}
    return base | numerics


# ---------------------------------------------------------------------------
# tables
# ---------------------------------------------------------------------------
@pytest.mark.parametrize("ld", sorted(BEM))
def test_added_mass_table_matches_the_computed_values_at_the_tabulated_aspect_ratios(ld):
    kt, ka, kr = added_mass.cylinder_added_mass(ld)
    assert (kt, ka) == BEM[ld] and kr == BEM_ROT[ld]


def test_added_mass_interpolation_is_monotone_and_held_outside_the_table():
    lds = np.linspace(0.5, 10.0, 400)
    kt, ka, kr = np.array([added_mass.cylinder_added_mass(x) for x in lds]).T
    assert np.all(np.diff(kt) >= 0.0) and np.all(np.diff(ka) <= 0.0) and np.all(np.diff(kr) >= 0.0)
    assert added_mass.cylinder_added_mass(1.0) == (*BEM[2.0], BEM_ROT[2.0])
    assert added_mass.cylinder_added_mass(9.0) == (*BEM[6.0], BEM_ROT[6.0])
    # midway between 3 and 4: the mean of the two rows (linear)
    kt5, ka5, _ = added_mass.cylinder_added_mass(3.5)
    assert kt5 == pytest.approx(0.5 * (0.810 + 0.852)) and ka5 == pytest.approx(0.5 * (0.208 + 0.157))
    # k_t + k_a stays below the sphere's 2 x 0.5 and k_t below the 2-D circle's 1
    assert np.all(kt < 1.0) and np.all(kt + ka < 1.05) and np.all(kr < kt)


def test_crossflow_efficiency_table_is_datcoms():
    assert dict(zip(added_mass.ETA_LD.tolist(), added_mass.ETA_TABLE.tolist())) == DATCOM_ETA
    assert added_mass.C_DC_SUBCRITICAL == 1.2


@pytest.mark.parametrize("ld", [2.0, 4.0, 8.0, 12.0])
def test_strip_crossflow_drag_of_seed_000_is_datcoms_separated_crossflow(ld):
    """The separated crossflow eta C_dc of the viscous-crossflow method is already in the
    strip drag: seed 000 eq. (44) in its subcritical band is within 4 % of DATCOM's eta x 1.2,
    so the viscous_crossflow model adds no second crossflow force (no double counting)."""
    cd2 = cross_drag_coefficient(5.0e4, ld)
    assert cd2 == pytest.approx(DATCOM_ETA[ld] * 1.2, rel=0.04)


def _eq44_two_dimensional(re):
    """Seed 000 eq. (44) as printed, its branches without L/D (the 2-D cylinder's C_dn)."""
    if re <= 12000.0:
        return 0.84 + 0.00003 * re
    if re <= 350000.0:
        return 1.875 - 0.0000045 * re
    return 1.0 / (641550.0 / re + 1.5)


def _broadside_deceleration(speed, water_column, h=1e-4):
    """dv/dt over the first h seconds of a horizontal body moving broadside (along earth y,
    its axis along x) at ``speed``, deep, drag on: the crossflow force over the transverse mass."""
    sc = make_scenario(
        environment={"gravity": G},
        release={"position": [0, 0, -50.0], "velocity": [0.0, speed, 0.0]},
        numerics={"water_column": water_column, "integrator": "rk4", "dt": h / 20, "t_max_fall": h},
    )
    ds = simulate_drop(sc, record_interval=h)
    assert float(ds.time[-1]) == pytest.approx(h)
    return (float(ds.v[-1]) - speed) / h


@pytest.mark.parametrize("speed", [0.02, 1.0, 4.0])  # Re = 5e3, 2.5e5, 1e6: 2-D branches of eq. (44)
def test_viscous_crossflow_separated_crossflow_carries_eta_outside_the_finite_body_band(speed):
    """Regression: the viscous_crossflow model used seed 000 eq. (44) as its separated crossflow
    eta C_dn at every Reynolds number, but outside 12000 < Re <= 150000 eq. (44) is the 2-D
    cylinder's C_dn (no L/D), so at the default mine's Re ~ 1e6 the crossflow force lacked
    DATCOM's eta (0.60 at L/D 4): 1/eta = 1.67 times too large. Jorgensen (NASA TR R-474):
    F = eta C_dn(Re) (1/2) rho d L v^2; the munk_factor model keeps eq. (44) as printed."""
    m, re = 80.0, speed * D / 1.0e-6
    force = 0.5 * RHO * _eq44_two_dimensional(re) * D * L * speed**2
    crossflow = _broadside_deceleration(speed, "viscous_crossflow")
    expected = -DATCOM_ETA[4.0] * force / (m + BEM[4.0][0] * RHO * VOL)
    assert crossflow == pytest.approx(expected, rel=1e-3)
    munk = _broadside_deceleration(speed, "munk_factor")
    assert munk == pytest.approx(-force / (m + RHO * VOL), rel=1e-3)


def test_viscous_crossflow_separated_crossflow_in_the_finite_body_band_is_eq44():
    """In 12000 < Re <= 150000 eq. (44) already is the finite body's (0.835 - 0.35/delta,
    within 4 % of eta x 1.2): no eta on top (Re = 5e4 here)."""
    m, speed = 80.0, 0.2
    force = 0.5 * RHO * (0.835 - 0.35 / 4.0) * D * L * speed**2
    expected = -force / (m + BEM[4.0][0] * RHO * VOL)
    assert _broadside_deceleration(speed, "viscous_crossflow") == pytest.approx(expected, rel=1e-3)


@pytest.mark.parametrize("alpha_deg", [0.0, 10.0, 45.0, 80.0, 90.0])
def test_incidence_factor_is_cos_half_alpha_folded_for_a_symmetric_body(alpha_deg):
    a = math.radians(alpha_deg)
    u1, u2 = math.cos(a), math.sin(a)
    expected = math.cos(a / 2)
    assert added_mass.munk_incidence_factor(3 * u1, 3 * u2, 0.0) == pytest.approx(expected, rel=1e-14)
    # flow from behind (180 deg - alpha) and about any transverse direction: the same
    assert added_mass.munk_incidence_factor(-u1, 0.6 * u2, -0.8 * u2) == pytest.approx(expected, rel=1e-14)


# ---------------------------------------------------------------------------
# added-mass tensor: initial acceleration of a body released at rest (no drag)
# ---------------------------------------------------------------------------
@pytest.mark.parametrize("factor", [1.0, 0.8, 1.25])
@pytest.mark.parametrize(
    "water_column, pitch_deg, coefficient",
    [
        ("viscous_crossflow", 90.0, BEM[4.0][1]),
        ("viscous_crossflow", 0.0, BEM[4.0][0]),
        ("munk_factor", 0.0, 1.0),  # strip theory: C_M = 1 (seed 001 eqs. (20)-(21))
    ],
)
def test_added_mass_for_axial_and_transverse_acceleration(water_column, pitch_deg, coefficient, factor):
    """Released at rest, deep, drag off: (m + c k rho V) a = (m - rho V) g along the axis
    (pitch 90 deg: k = k_a) or across it (pitch 0: k = k_t), c = numerics.added_mass_factor."""
    m = 120.0
    sc = make_scenario(
        mine={"mass": m},
        environment={"gravity": G},
        release={"position": [0, 0, -50.0], "pitch_deg": pitch_deg},
        numerics=crossflow_scenario(
            t_max_fall=0.02, dt=1e-4, water_column=water_column, added_mass_factor=factor
        ),
    )
    ds = simulate_drop(sc, record_interval=0.01)
    a = float(ds.w[-1]) / float(ds.time[-1])
    expected = -(m - RHO * VOL) * G / (m + factor * coefficient * RHO * VOL)
    assert a == pytest.approx(expected, rel=1e-9)


# ---------------------------------------------------------------------------
# the Munk moment with its incidence factor
# ---------------------------------------------------------------------------
def _spin_up(alpha_deg, h=1e-4, speed=2.0, **numerics):
    """omega3 / h after h seconds from a horizontal body moving at ``speed`` with incidence
    alpha in the horizontal plane (body axis along x): the initial angular acceleration."""
    a = math.radians(alpha_deg)
    sc = make_scenario(
        environment={"gravity": G},
        release={"position": [0, 0, -50.0], "velocity": [speed * math.cos(a), speed * math.sin(a), 0.0]},
        numerics=crossflow_scenario(t_max_fall=h, dt=h / 20, **numerics),
    )
    ds = simulate_drop(sc, record_interval=h)
    p, _, _ = sc.to_params()
    assert float(ds.time[-1]) == pytest.approx(h)
    return float(ds.omega3[-1]) / h, p[layout.P_J2]


@pytest.mark.parametrize("fraction, factor", [(1.0, 1.0), (0.4, 1.0), (0.0, 1.0), (0.7, 1.2)])
@pytest.mark.parametrize("alpha_deg", [15.0, 30.0, 60.0, -30.0])
def test_munk_moment_is_the_viscous_crossflow_closed_form(alpha_deg, fraction, factor):
    """M = f c (k_t - k_a) rho V U^2 sin(alpha) cos(alpha) cos(alpha/2) (Jorgensen TR R-474, DATCOM
    bodyjm.f: potential term; f = numerics.crossflow_munk_fraction, c = numerics.added_mass_factor),
    destabilising: it turns the axis away from the flow, angular acceleration
    M / (J2 + c k_r rho pi R^2 L^3 / 12)."""
    speed = 2.0
    kw = (
        {}
        if fraction == factor == 1.0
        else {"crossflow_munk_fraction": fraction, "added_mass_factor": factor}
    )
    dw3, j2 = _spin_up(alpha_deg, speed=speed, **kw)
    a = math.radians(alpha_deg)
    kt, ka = BEM[4.0]
    moment = (
        fraction
        * factor
        * (kt - ka)
        * RHO
        * VOL
        * speed**2
        * math.sin(a)
        * math.cos(a)
        * math.cos(abs(a) / 2)
    )
    inertia = j2 + factor * BEM_ROT[4.0] * RHO * math.pi * R * R * L**3 / 12.0
    if fraction == 0.0:
        assert abs(dw3) < 1e-9  # no potential moment left: the tuned removal
        return
    # body y is the earth y here: a positive sideways velocity at positive alpha is turned
    # further broadside by a negative omega3 (the Munk moment is destabilising)
    assert dw3 == pytest.approx(-moment / inertia, rel=2e-3)


@pytest.mark.parametrize("alpha_deg", [0.0, 90.0])
def test_munk_moment_vanishes_axially_and_broadside(alpha_deg):
    dw3, _ = _spin_up(alpha_deg)
    assert abs(dw3) < 1e-9


def test_munk_moment_is_odd_in_incidence():
    up, _ = _spin_up(40.0)
    down, _ = _spin_up(-40.0)
    assert up == pytest.approx(-down, rel=1e-12) and abs(up) > 1.0


# ---------------------------------------------------------------------------
# energy: the tensor and the reduced Munk pair do no work (drag off)
# ---------------------------------------------------------------------------
@pytest.mark.parametrize("fraction, factor", [(1.0, 1.0), (0.35, 1.2)])
def test_mechanical_energy_conserved_with_the_viscous_crossflow_added_mass(fraction, factor):
    """Drag off, the tensor (times the added-mass factor c) and the reduced Munk pair do no work,
    whatever fraction f of the potential moment is kept."""
    m, chi = 60.0, 0.05
    sc = make_scenario(
        mine={"mass": m, "com_offset": chi},
        environment={"gravity": G},
        release={
            "position": [0, 0, -50.0],
            "velocity": [0.4, -0.2, 0.3],
            "pitch_deg": 30.0,
            "angular_velocity": [0.5, 1.0, -0.7],
        },
        numerics={
            "water_column": "viscous_crossflow",
            "crossflow_munk_fraction": fraction,
            "added_mass_factor": factor,
            "drag": False,
            "t_max_fall": 2.0,
            "rtol": 1e-10,
            "atol": 1e-12,
        },
    )
    ds = simulate_drop(sc, record_interval=0.05)
    p, _, _ = sc.to_params()
    j1, j2 = p[layout.P_J1], p[layout.P_J2]
    kt, ka = BEM[4.0]
    a = factor * RHO * math.pi * R * R
    i0, i1 = L, -chi * L  # wetted interval [-L/2 - chi, L/2 - chi]
    # rotational: k_r of strip theory about the centroid, plus the transverse mass at -chi
    i2 = BEM_ROT[4.0] * L**3 / 12.0 + kt * chi**2 * L
    energies = []
    for k in range(ds.sizes["time"]):
        q0, q1, q2, q3 = (float(ds[c][k]) for c in ("q0", "q1", "q2", "q3"))
        rot = Rotation.from_quat([q1, q2, q3, q0]).as_matrix()
        u = rot.T @ np.array([float(ds[c][k]) for c in ("u", "v", "w")])
        w = np.array([float(ds[c][k]) for c in ("omega1", "omega2", "omega3")])
        kin = 0.5 * (m * u @ u + j1 * w[0] ** 2 + j2 * (w[1] ** 2 + w[2] ** 2))
        kin += 0.5 * ka * a * i0 * u[0] ** 2
        kin += 0.5 * kt * a * (i0 * (u[1] ** 2 + u[2] ** 2) + 2 * i1 * (u[1] * w[2] - u[2] * w[1]))
        kin += 0.5 * a * i2 * (w[1] ** 2 + w[2] ** 2)
        z_cov = float(ds.z[k]) + rot[2, 0] * (-chi)  # centre of volume at -chi i_M
        energies.append(kin + m * G * float(ds.z[k]) - RHO * VOL * G * z_cov)
    energies = np.array(energies)
    assert np.ptp(energies) / (abs(energies[0]) + m * G * L) < 2e-6
    # the motion did turn: the Munk pair is active in this test
    assert abs(float(ds.omega3[-1]) - (-0.7)) > 0.05


# ---------------------------------------------------------------------------
# the default is the old model; the new one ignores munk_factor; bad names are one line
# ---------------------------------------------------------------------------
def test_default_water_column_is_the_munk_factor_model_unchanged():
    """The default scenario packs code 0 and gives the same trajectory, bit for bit, as the
    old setting written out (munk_factor 0 with the munk_factor model)."""
    rel = {"velocity": [1.0, 0.5, -2.0], "pitch_deg": 35.0, "angular_velocity": [0.2, -0.4, 0.3]}
    default = make_scenario(release=rel, numerics={"t_max_fall": 0.5})
    explicit = make_scenario(
        release=rel, numerics={"t_max_fall": 0.5, "water_column": "munk_factor", "munk_factor": 0.0}
    )
    p, _, _ = default.to_params()
    assert p[layout.INDEX["numerics.water_column"]] == 0.0
    # appended after the last slot of 69fd694 (t_max_fall): old slots keep their index
    assert layout.INDEX["numerics.water_column"] == layout.INDEX["numerics.t_max_fall"] + 1
    a = simulate_drop(default, record_interval=0.05)
    b = simulate_drop(explicit, record_interval=0.05)
    for name in ("x", "y", "z", "u", "v", "w", "q0", "q1", "q2", "q3", "omega1", "omega2", "omega3"):
        assert np.array_equal(a[name].values, b[name].values), name
    c = simulate_drop(
        make_scenario(release=rel, numerics={"t_max_fall": 0.5, "water_column": "viscous_crossflow"}), 0.05
    )
    assert not np.array_equal(a.omega3.values, c.omega3.values)


def test_viscous_crossflow_does_not_read_munk_factor():
    rel = {"velocity": [1.0, 0.5, -2.0], "pitch_deg": 35.0}
    runs = [
        simulate_drop(
            make_scenario(
                release=rel,
                numerics={"t_max_fall": 0.3, "water_column": "viscous_crossflow", "munk_factor": f},
            ),
            record_interval=0.05,
        )
        for f in (0.0, 1.0)
    ]
    assert np.array_equal(runs[0].omega3.values, runs[1].omega3.values)


def test_unknown_water_column_model_is_one_clear_error():
    with pytest.raises(ScenarioError, match="numerics.water_column"):
        make_scenario(numerics={"water_column": "slender"})


def test_compare_vary_knows_water_column_by_its_short_name():
    """`mineburial compare --vary water_column=...` lacked the short name (issue 19 left-over)."""
    field, values = compare.parse_vary("water_column=munk_factor,viscous_crossflow")
    assert field == "numerics.water_column" and values == ["munk_factor", "viscous_crossflow"]


def test_default_ensemble_draws_the_water_column_from_the_posterior_with_bearing_fixed():
    """The default's model form (docs/physics.md, "Model-form uncertainty"; docs/calibration.md):
    the water column drawn from the shipped posterior (50/50 before issue 32), the resistance the
    mineburial model's bearing (Chu & Fan 2007), not written in the file so that a model variant
    still takes its own laws."""
    spec = engine.load_ensemble(mine.DEFAULT_SCENARIO)
    got = model_form.choices(spec)
    text = got["numerics.water_column"]
    assert text.startswith("from the posterior (shipped): ")
    shares = [float(x) for x in re.findall(r"\(([0-9.e-]+)\)", text.split(": ", 1)[1])]
    assert sum(shares) == pytest.approx(1.0, abs=2e-3)
    assert got["sediment.resistance"] == "fixed: bearing"
    assert got["numerics.model"] == "fixed: mineburial"
    with open(mine.DEFAULT_SCENARIO, "rb") as fh:
        assert "resistance" not in tomllib.load(fh)["sediment"]
