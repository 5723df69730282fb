"""Closed forms and independent numerical references for the validation cases and the tests.

Each function computes a reference value **without** the kernels: from a closed form,
``scipy.optimize.brentq`` or ``scipy.integrate.solve_ivp`` on the same force law written
out for a special case. The validation report (:mod:`mineburial.validation.cases`) and
the tests (``tests/test_water_column.py``, ``tests/test_sediment_drop.py``) both call
them, so a reference is written once.
"""

from __future__ import annotations

import math

import numpy as np
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

__all__ = [
    "broadside_drag_coefficient",
    "axial_drag_coefficient",
    "terminal_velocity_broadside",
    "terminal_velocity_axial",
    "archimedes_penetration",
    "axial_penetration",
    "work_energy_residual",
]


def broadside_drag_coefficient(length: float, diameter: float) -> float:
    """C_d2 of seed 000 eq. (44) on the branch 12 000 < Re <= 150 000, 2 <= L/d < 10:
    0.835 - 0.35 / (L/d)."""
    delta = length / diameter
    if not 2.0 <= delta < 10.0:
        raise ValueError(f"L/d = {delta:g} is outside the branch 2 <= L/d < 10 of eq. (44)")
    return 0.835 - 0.35 / delta


def axial_drag_coefficient(length: float, diameter: float) -> float:
    """C_d1 of seed 000 eq. (40): 0.75 + delta/32.1934 + 0.09612/delta^2, delta = L/d."""
    delta = length / diameter
    return 0.75 + delta / 32.1934 + 0.09612 / delta**2


def terminal_velocity_broadside(mass, length, diameter, water_density, gravity, viscosity):
    """Terminal sinking speed (m/s) of a horizontal cylinder: weight in water = broadside
    drag, 0.5 rho C_d2 d L v^2 (seed 000 eq. (44)). Raises if the Reynolds number
    v d / nu is outside the branch of C_d2 used."""
    vol = math.pi * (diameter / 2) ** 2 * length
    cd2 = broadside_drag_coefficient(length, diameter)
    v = math.sqrt((mass - water_density * vol) * gravity / (0.5 * water_density * cd2 * diameter * length))
    re = v * diameter / viscosity
    if not 12_000 < re <= 150_000:
        raise ValueError(f"Re = {re:.0f} is outside the branch 12 000 < Re <= 150 000 of eq. (44)")
    return v


def terminal_velocity_axial(mass, length, diameter, water_density, gravity):
    """Terminal sinking speed (m/s) of a vertical cylinder: weight in water = axial drag,
    0.5 rho C_d1 pi R^2 v^2 (seed 000 eqs. (38)-(40))."""
    area = math.pi * (diameter / 2) ** 2
    vol = area * length
    cd1 = axial_drag_coefficient(length, diameter)
    return math.sqrt((mass - water_density * vol) * gravity / (0.5 * water_density * cd1 * area))


def archimedes_penetration(length, diameter, mine_density, sediment_density, water_density):
    """Depth h (m) of the lowest line of a horizontal cylinder floating in a zero-strength
    sediment denser than the mine: (rho_s - rho_w) V_emb + rho_w V = rho_m V with V_emb the
    circular-segment volume L (R^2 acos((R-h)/R) - (R-h) sqrt(R^2 - (R-h)^2))."""
    r = diameter / 2
    vol = math.pi * r * r * length
    if not water_density < mine_density < sediment_density:
        raise ValueError("a floating depth needs rho_w < rho_mine < rho_s")
    v_emb = (mine_density - water_density) * vol / (sediment_density - water_density)

    def segment(h):
        return r * r * math.acos((r - h) / r) - (r - h) * math.sqrt(max(r * r - (r - h) ** 2, 0.0))

    return brentq(lambda h: length * segment(h) - v_emb, 0.0, diameter, xtol=1e-14, rtol=1e-14)


def axial_penetration(
    *,
    mass,
    length,
    diameter,
    impact_speed,
    strength,
    strength_gradient,
    sediment_density,
    water_density,
    gravity,
    bearing_factor,
    rate_coefficient,
    reference_rate,
    switch_speed,
    rest_speed,
    depth_factor=0.4,
    inertial_drag=0.0,
):
    """Final penetration (m) of a vertical cylinder entering the seabed nose first at
    ``impact_speed`` (m/s, > 0 downwards), from ``solve_ivp`` on the ``bearing`` law written
    for this case (docs/notes/sediment.md), with no fluid drag and no side friction:

    m_eff dv/dt = W' - (rho_s - rho_w) g A min(zeta, L)
                  - N_c (1 + f atan(zeta/d)) (S0 + k zeta) G(v) A v/sqrt(v^2 + V_n^2)
                  - 0.5 C_D rho_s A v^2,

    W' the weight in water, A = pi R^2, G the semi-logarithmic rate law at strain rate v/d,
    m_eff = m + rho_w A (L - zeta) the isotropic added mass of the part still in water
    (munk_factor 0), f = ``depth_factor`` (Brinch Hansen's 0.4 by default), C_D =
    ``inertial_drag`` (the soil's inertial drag on the flat nose, 0 by default), integrated until
    v falls below ``rest_speed``."""
    d, L = diameter, length
    area = math.pi * (d / 2) ** 2
    weight = (mass - water_density * area * L) * gravity

    def g_rate(v):
        ratio = v / (d * reference_rate)
        return 1.0 + rate_coefficient * math.log10(ratio) if ratio > 1.0 else 1.0

    def rhs(t, y):
        zeta, v = y
        emb = min(max(zeta, 0.0), L)
        nc = bearing_factor * (1.0 + depth_factor * math.atan(zeta / d))  # Brinch Hansen depth factor
        h = v / math.sqrt(v * v + switch_speed**2) if v > 0 else 0.0
        bearing = nc * (strength + strength_gradient * zeta) * g_rate(v) * area * h
        if v > 0 and inertial_drag > 0:
            bearing += 0.5 * inertial_drag * sediment_density * area * v * v
        overburden = (sediment_density - water_density) * gravity * area * emb
        m_eff = mass + water_density * area * (L - emb)
        return [v, (weight - overburden - bearing) / m_eff]

    def stopped(t, y):
        return y[1] - rest_speed

    stopped.terminal = True
    stopped.direction = -1
    sol = solve_ivp(
        rhs, (0.0, 10.0), [0.0, impact_speed], events=stopped, rtol=1e-10, atol=1e-12, max_step=1e-3
    )
    if sol.status != 1:
        raise RuntimeError("the 1-D reference did not come to rest within 10 s")
    return float(sol.y[0, -1])


def work_energy_residual(ds, mass, inertia_axial, inertia_transverse, gravity):
    """Work-energy theorem for a rigid body over a recorded drop: returns
    ``(E1 - E0 - W, scale)`` with E = kinetic + m g z and W the work of the fluid and
    sediment forces recorded by the drop (``work_fluid``, ``work_sediment``); ``scale`` is
    the initial kinetic energy plus the potential energy released."""

    def kinetic(k):
        v = np.array([float(ds[c][k]) for c in ("u", "v", "w")])
        w = np.array([float(ds[c][k]) for c in ("omega1", "omega2", "omega3")])
        return 0.5 * mass * v @ v + 0.5 * (
            inertia_axial * w[0] ** 2 + inertia_transverse * (w[1] ** 2 + w[2] ** 2)
        )

    e0 = kinetic(0) + mass * gravity * float(ds.z[0])
    e1 = kinetic(-1) + mass * gravity * float(ds.z[-1])
    work = float(ds.work_fluid[-1]) + float(ds.work_sediment[-1])
    scale = kinetic(0) + mass * gravity * (float(ds.z[0]) - float(ds.z[-1]))
    return (e1 - e0) - work, scale
