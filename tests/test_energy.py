"""Energy and work against forces computed independently of the engine (issue 12 item 17).

The engine's own work outputs integrate the power of the forces it applies, so an energy
balance built from them closes whatever those forces are. These tests instead compute each
force from the printed law along the recorded trajectory and check

* the work-energy theorem with those independent works (it fails when a force is wrong:
  checked by hand with 5x the cross-flow drag and 3x the sediment force), and
* the recorded sediment force and the engine's work outputs against the independent ones.
"""

import math

import numpy as np
from conftest import make_scenario, scenario_dict
from printed_laws import AREA, RHO, VOL, D, G, L, broadside_drag
from scipy.integrate import cumulative_trapezoid

from mineburial.systems.mine.config import Scenario
from mineburial.systems.mine.drop import simulate_drop


def test_water_column_energy_balance_with_the_drag_of_the_printed_law():
    """A mine falling broadside from rest in still water: with the strip-theory added mass
    m_a = rho pi R^2 L (C_M = 1, seed 001) the effective energy
    E = (m + m_a) w^2 / 2 + (m - rho V) g z changes by the work of the drag of seed 000
    eq. (44), 0.5 rho C_d2(Re) d L |w| w, integrated along the recorded trajectory; and the
    engine's work of the fluid forces equals buoyancy + drag + added-mass work."""
    m = 60.0
    m_a = RHO * VOL
    sc = make_scenario(
        mine={"mass": m},
        environment={"gravity": G, "water_density": RHO},
        release={"position": [0, 0, -5.0], "pitch_deg": 0.0},
        numerics={"t_max_fall": 8.0, "rtol": 1e-10, "atol": 1e-12},
    )
    ds = simulate_drop(sc, record_interval=0.002)
    t, z, w = ds.time.values, ds.z.values, ds.w.values
    drag = np.array([broadside_drag(x) for x in w])
    w_drag = cumulative_trapezoid(drag * w, t, initial=0.0)
    energy = 0.5 * (m + m_a) * w**2 + (m - RHO * VOL) * G * z
    scale = abs(w_drag[-1])
    assert scale > 10.0  # drag did real work (J)
    np.testing.assert_allclose(energy - energy[0], w_drag, rtol=0, atol=2e-3 * scale)
    # the engine's fluid work: buoyancy rho V g dz, drag, and the added mass -m_a w^2 / 2
    fluid = RHO * VOL * G * (z - z[0]) + w_drag - 0.5 * m_a * w**2
    np.testing.assert_allclose(ds.work_fluid.values, fluid, rtol=0, atol=2e-3 * scale)
    np.testing.assert_allclose(ds.work_sediment.values, 0.0, atol=1e-12)


def test_sediment_force_and_work_of_a_vertical_penetration_follow_the_bearing_law():
    """A nose-down cylinder driven into a bearing-law sediment (no drag, no side adhesion):
    along the recorded trajectory the sediment force is the geostatic overburden
    (rho_s - rho_w) g pi R^2 zeta plus the bearing N_c S(zeta) G(v) pi R^2 h(v) on the nose
    (N_c = N_c0 (1 + 0.4 arctan(zeta/d)), semi-log rate law G, the advancing switch
    h = v / sqrt(v^2 + v_s^2)); the engine's work of the sediment forces is its integral,
    and the work-energy theorem closes with the independent works."""
    mass, depth = 150.0, 10.0
    s0, ks, rho_s = 3000.0, 2000.0, 1500.0
    nc0, beta, rate_ref, v_switch = math.pi + 2.0, 0.1, 2.78e-6, 5e-3
    d = scenario_dict(
        mine={"mass": mass},
        environment={"water_depth": depth, "gravity": G, "water_density": RHO},
        release={
            "position": [0.0, 0.0, -depth + L / 2 + 0.05],
            "pitch_deg": 90.0,
            "velocity": [0.0, 0.0, -3.0],
        },
        numerics={
            "t_max": 3.0,
            "drag": False,
            "switch_speed": v_switch,
            "munk_factor": 0.0,
            "rtol": 1e-9,
            "atol": 1e-12,
        },
    )
    d["sediment"] = {
        "density": rho_s,
        "density_gradient": 0.0,
        "strength": s0,
        "strength_gradient": ks,
        "resistance": "bearing",
        "rate_law": "semilog",
        "rate_coefficient": beta,
        "reference_rate": rate_ref,
        "friction": 0.0,
        "bearing_factor": nc0,
    }
    ds = simulate_drop(Scenario.from_dict(d), record_interval=2e-4, forces=True)
    t, z, w = ds.time.values, ds.z.values, ds.w.values
    zeta = -depth - (z - L / 2)  # depth of the nose below the seabed
    emb = np.clip(zeta, 0.0, L)
    v = -w  # downward speed
    ratio = np.maximum(np.abs(v) / (D * rate_ref), 1.0)
    rate = 1.0 + beta * np.log10(ratio)
    switch = np.where(v > 0, v / np.sqrt(v * v + v_switch**2), 0.0)
    nc = nc0 * (1.0 + 0.4 * np.arctan(np.maximum(zeta, 0.0) / D))
    bearing = np.where(zeta > 0, nc * (s0 + ks * zeta) * rate * AREA * switch, 0.0)
    force = (rho_s - RHO) * G * AREA * emb + bearing  # upwards
    assert zeta.max() > 0.2 and ds.attrs["status"] == "at_rest"
    inside = zeta > 1e-3
    np.testing.assert_allclose(ds.sediment_force_z.values[inside], force[inside], rtol=2e-3)
    np.testing.assert_allclose(ds.sediment_force_x.values, 0.0, atol=1e-9 * force.max())
    np.testing.assert_allclose(ds.sediment_force_y.values, 0.0, atol=1e-9 * force.max())
    # work of the sediment, independent, against the engine's
    w_sed = cumulative_trapezoid(force * w, t, initial=0.0)
    scale = abs(w_sed[-1])
    assert scale > 100.0
    np.testing.assert_allclose(ds.work_sediment.values, w_sed, rtol=0, atol=3e-3 * scale)
    # work-energy theorem for the body: kinetic + potential energy change = work of the
    # water's buoyancy (fully submerged throughout), of the sediment, and of the added-mass
    # reaction -m_a dw/dt of the water part (isotropic added mass, munk_factor 0: axial
    # m_a = rho pi R^2 times the length still in the water), -int m_a d(w^2/2)
    m_a = RHO * AREA * (L - emb)
    w_added = -cumulative_trapezoid(m_a, 0.5 * w**2, initial=0.0)
    w_buoy = RHO * G * VOL * (z - z[0])
    energy = 0.5 * mass * w**2 + mass * G * z
    np.testing.assert_allclose(energy - energy[0], w_buoy + w_added + w_sed, rtol=0, atol=3e-3 * scale)
