"""Applied forces of seed 004's restraining system (Liu, Hearn, Chen et al.), planar.

Small numba kernels, one per force law, each returning the resultant at a body's
centroid as ``(Fx, Fz, My)`` in the inertial frame of docs/multibody.md (x along the
ship's initial heading and the current, z up, seabed at z = 0, angles counter-clockwise
from +x toward +z) and, where the force has a potential, that potential. Equation
numbers are seed 004's unless another seed is named; docs/restraint.md lists every
deviation from the printed equations and every assumed value.

* :func:`current_speed` -- tidal current profile, eq. (38), the 1/7 power law.
* :func:`element_fluid_force` -- tangential and normal drag of a rotating cable or chain
  element, eqs. (43)-(47); the normal drag is the exact integral of seed 001
  eqs. (31)-(47) (:func:`mineburial.kernels.crossflow.quadratic_drag_integrals`), the
  tangential drag :func:`tangential_drag` in the form the case selects (seed 001 eq. (4),
  default, or seed 004 eq. (45) as printed). The added mass of eq. (46) is in the element's
  mass matrix, not here.
* :func:`element_foundation` -- the elastic seabed foundation of eq. (41) with the lost
  buoyancy of eq. (42): upward force ``(k_z - rho g) V^S`` at the centroid of the embedded
  volume, i.e. Archimedes in a heavy fluid of specific weight ``k_z - rho g``, which has
  an exact potential (the elastic energy of the foundation).
* :func:`anchor_drag` -- eq. (39); :func:`ship_resistance` -- eqs. (59)-(62);
  :func:`ship_hydrostatics` -- eqs. (55)-(58) (heave and pitch restoring);
  :func:`current_added_mass_correction` -- the velocity terms of an element's added mass
  taken with its velocity relative to the current.
* :func:`solve_with_friction` -- the accelerations with the anchor's Coulomb friction of
  eqs. (36)-(37), regularised by the generic seabed-contact law
  (:func:`mineburial.kernels.seabed_contact.regularised_friction`).
"""

import math

import numpy as np

from mineburial._numba import kernel
from mineburial.kernels.core import System
from mineburial.kernels.crossflow import quadratic_drag_integrals
from mineburial.kernels.multibody import (
    accelerations,
    accelerations_assembled,
    body_states,
    inertia_velocity_terms,
    inertial_mass,
    joint_forces,
    kinetic_energy,
    rotating_mass_velocity_terms,
)
from mineburial.kernels.seabed_contact import regularised_friction

#: 4-point Gauss-Legendre nodes and weights on [-1, 1] (Abramowitz & Stegun 25.4.30)
_GL_X = (-0.8611363115940526, -0.3399810435848563, 0.3399810435848563, 0.8611363115940526)
_GL_W = (0.3478548451374538, 0.6521451548625461, 0.6521451548625461, 0.3478548451374538)

#: Reynolds number below which the ITTC-1957 line (eq. (60)) is held at its value at
#: RE_MIN (the line is singular at Re = 100 and is not meant for Re < 1e5)
RE_MIN = 1.0e5


@kernel
def current_speed(height, surface_speed, depth):
    """Eq. (38): ``U(h) = U_s (h / d)^(1/7)`` at ``height`` above the seabed; 0 at and
    below the seabed, ``U_s`` at and above the free surface (``depth`` = d)."""
    if surface_speed == 0.0 or height <= 0.0:
        return 0.0
    if height >= depth:
        return surface_speed
    return surface_speed * (height / depth) ** (1.0 / 7.0)


#: values of the tangential-drag form (params[1][P_TANGENTIAL], ``water.tangential_drag_form``)
TANGENTIAL_DIAMETER = 0.0  # seed 001 eq. (4): C = C_T rho d / 2 per unit length (default)
TANGENTIAL_PERIMETER = 1.0  # seed 004 eqs. (44)-(45) as printed: pi rho D C_F / 2 per unit length


@kernel
def tangential_drag(wt, length, diameter, rho, cf, form):
    """Tangential (skin-friction) drag of a cylindrical element along its axis, ``w_t`` the
    axial water velocity relative to the element (uniform along it: the rotation adds only
    normal velocity, seed 001 eqs. (48)-(51), so the moment about the centroid is zero).

    * ``form = TANGENTIAL_DIAMETER``: ``C_T rho d L |w_t| w_t / 2`` -- seed 001 (Huston &
      Kamman 1980) eqs. (1), (4), (50): the force per unit length is ``C |V_T| V_T`` with
      ``C = C_T rho (d/2)``, the coefficient referred to the diameter d as C_N is in
      eq. (3); its eq. (7) gives ``C_T = 0.062`` for Re_T > 100.55 (after Webster 1976),
      the value seed 004 §3.2.2 takes for C_F (citing Huston 1981, the journal version).
    * ``form = TANGENTIAL_PERIMETER``: ``pi rho D L C_F |w_t| w_t / 2`` -- seed 004
      eqs. (44)-(45) as printed, the same coefficient referred to the wetted perimeter
      pi D, i.e. pi times the force of the coefficient's own definition.

    docs/restraint.md section 6 gives the choice (the default is seed 001's form).
    """
    width = math.pi * diameter if form == TANGENTIAL_PERIMETER else diameter
    return 0.5 * rho * width * length * cf * abs(wt) * wt


@kernel
def element_fluid_force(theta, vx, vz, om, length, diameter, rho, cd, cf, current, tangential_form):
    """Drag of a straight cylindrical element (eqs. (43)-(47)), resultant at its centroid.

    ``theta``: attitude; ``(vx, vz, om)``: centroid velocity and angular velocity;
    ``current``: horizontal water velocity at the centroid (eq. (38)). The water velocity
    relative to the element (eq. (43)) has the tangential part ``w_t`` and, at axial
    station s, the normal part ``w_n(s) = w_n(0) - om s``.

    * tangential drag along the axis, :func:`tangential_drag` in the form
      ``tangential_form`` (seed 001 eq. (4) or seed 004 eq. (45));
    * normal drag, eqs. (44), (47): ``rho D C_D / 2 int |w_n| w_n ds`` along the normal
      and its moment ``rho D C_D / 2 int s |w_n| w_n ds`` -- evaluated exactly for any
      ratio of rotation to translation (seed 001 eqs. (31)-(47), re-derived in
      kernels/crossflow.py) instead of the two printed branches of eq. (47).

    Returns ``(Fx, Fz, My)``.
    """
    c = math.cos(theta)
    s = math.sin(theta)
    rx = current - vx
    rz = -vz
    wt = rx * c + rz * s
    wn = -rx * s + rz * c
    half = 0.5 * length
    _, fn_int, _, mn_int = quadratic_drag_integrals(-half, half, 0.0, wn, 0.0, -om)
    kn = 0.5 * rho * diameter * cd
    fn = kn * fn_int
    ft = tangential_drag(wt, length, diameter, rho, cf, tangential_form)
    fx = ft * c - fn * s
    fz = ft * s + fn * c
    return fx, fz, kn * mn_int


@kernel
def segment_area_below(zc, radius):
    """Area of a disc of ``radius`` centred at height ``zc`` that lies below z = 0."""
    if zc >= radius:
        return 0.0
    if zc <= -radius:
        return math.pi * radius * radius
    r2 = radius * radius
    return r2 * math.acos(zc / radius) - zc * math.sqrt(r2 - zc * zc)


@kernel
def _segment_potential(zc, radius):
    """``int_zc^inf A(z) dz``: the potential per unit length and unit specific weight of
    the disc's embedding (A = :func:`segment_area_below`, so that -d/dzc = A)."""
    r = radius
    if zc >= r:
        return 0.0
    if zc <= -r:
        return math.pi * r * r * r + math.pi * r * r * (-r - zc)
    q = r * r - zc * zc
    g = r * r * zc * math.acos(zc / r) - r * r * math.sqrt(q) + math.sqrt(q) * q / 3.0
    return -g


@kernel
def element_foundation(zc, theta, length, radius, specific_weight):
    """Elastic foundation of eqs. (41)-(42) on a cylindrical element, resultant at its
    centroid.

    The element is cut into cross-sections normal to its axis at the 4 Gauss-Legendre
    stations ``s_i``; the section at ``s_i`` has its centre at height
    ``z_i = zc + s_i sin(theta)`` and sinks ``A(z_i)`` of area into the seabed (a
    horizontal cut of the disc: exact for an element lying flat, which is the only
    case where it touches the seabed). The upward force is
    ``specific_weight * sum w_i A(z_i)`` (eq. (41), ``F^S = k_z V^S``, with the
    buoyancy ``rho g V^S`` lost by eq. (42): ``specific_weight = k_z - rho g``), acting
    at the sections, so that it is minus the gradient of the returned potential
    ``specific_weight * sum w_i P(z_i)`` exactly (conservative foundation).

    Returns ``(Fz, My, potential, embedded_volume)``.
    """
    half = 0.5 * length
    s = math.sin(theta)
    c = math.cos(theta)
    fz = 0.0
    my = 0.0
    pot = 0.0
    vol = 0.0
    for i in range(4):
        si = half * _GL_X[i]
        zi = zc + si * s
        if zi >= radius:
            continue
        wi = half * _GL_W[i]
        a = segment_area_below(zi, radius)
        vol += wi * a
        fz += wi * a
        my += wi * a * si * c
        pot += wi * _segment_potential(zi, radius)
    return specific_weight * fz, specific_weight * my, specific_weight * pot, vol


@kernel
def anchor_drag(v_anchor, current, rho, cd, width, height):
    """Eq. (39): ``F = C_D rho w h U |U| / 2`` with ``U = current - v_anchor``; x force."""
    u = current - v_anchor
    return 0.5 * cd * rho * width * height * u * abs(u)


@kernel
def ittc_friction(reynolds):
    """Eq. (60), the ITTC-1957 line ``C_f = 0.075 / (log10 Re - 2)^2`` (held at RE_MIN
    below RE_MIN)."""
    re = max(reynolds, RE_MIN)
    d = math.log10(re) - 2.0
    return 0.075 / (d * d)


@kernel
def roughness_allowance(roughness, length):
    """Eq. (61): ``C_sf = [105 (k_s / L)^(1/3) - 0.64] 1e-3``."""
    return (105.0 * (roughness / length) ** (1.0 / 3.0) - 0.64) * 1.0e-3


@kernel
def ship_resistance(v_ship, current, length, wetted_area, roughness, rho, nu, half_factor):
    """Eqs. (59)-(62): the ship's longitudinal water force, x component.

    ``v_wx = v_ship - current`` (eq. (59)'s relative velocity); ``Re = |v_wx| L / nu``;
    ``F = -(C_f + C_sf) * half_factor * rho S_w v_wx |v_wx|`` -- a resistance, opposing
    ``v_wx``. Eq. (62) as printed has no 1/2 (``half_factor = 1``); the textbook ITTC form
    has it (``half_factor = 0.5``), see docs/restraint.md.
    """
    vw = v_ship - current
    if vw == 0.0:
        return 0.0
    re = abs(vw) * length / nu
    ct = ittc_friction(re) + roughness_allowance(roughness, length)
    return -ct * half_factor * rho * wetted_area * vw * abs(vw)


@kernel
def ship_hydrostatics(heave, pitch, rho, g, waterplane_area, volume, gm_long):
    """Eq. (58) with eq. (56)'s pitch stiffness: ``F_z = -rho g A_W x3`` and
    ``M = -rho g V GM_L x5`` (the net of the ship's weight, eq. (53), and buoyancy,
    eq. (54), about hydrostatic equilibrium), and their potential, eq. (66).
    Returns ``(Fz, My, potential)``."""
    kz = rho * g * waterplane_area
    kp = rho * g * volume * gm_long
    return -kz * heave, -kp * pitch, 0.5 * (kz * heave * heave + kp * pitch * pitch)


@kernel
def current_added_mass_correction(theta, vx, vz, om, added_mass, length, current):
    """Force (Fx, Fz, My) that turns the core's added-mass velocity terms of a cable or chain
    element, taken with its absolute velocity, into the same terms taken with its velocity
    relative to the water ``w = (vx - current, vz, om)``.

    In a steady uniform current the flow around the element, seen from a frame drifting with
    the water, is the still-water problem with the body velocity ``w``; the added-mass force
    is Galilean-invariant, so it is Kirchhoff's force of ``w``: ``-(M_a dw/dt + g_a(w))``
    with ``dw/dt = dv/dt`` (Newman 1977, *Marine Hydrodynamics*, sec. 4.13; ``g_a`` the
    velocity terms of :func:`mineburial.kernels.multibody.rotating_mass_velocity_terms`,
    including the Munk moment). The core puts ``-(M_a dv/dt + g_a(v))`` in the equations
    (added mass in the mass matrix), so the correction is ``g_a(v) - g_a(w)``. The added
    mass is seed 004 eq. (46)'s: ``added_mass`` = rho pi r^2 L C_M on the element's normal,
    ``added_mass L^2 / 12`` in rotation. The 1/7-power current of eq. (38) is sheared: it
    is taken as uniform at its value at the centroid (the gradient term, of order
    ``m_a vz dU/dz``, is left out; docs/restraint.md)."""
    if current == 0.0 or added_mass == 0.0:
        return 0.0, 0.0, 0.0
    mb = np.zeros((3, 3))
    mb[1, 1] = added_mass
    mb[2, 2] = added_mass * length * length / 12.0
    mi = inertial_mass(mb, theta)
    a0, a1, a2 = rotating_mass_velocity_terms(mi, vx, vz, om)
    b0, b1, b2 = rotating_mass_velocity_terms(mi, vx - current, vz, om)
    return a0 - b0, a1 - b1, a2 - b2


# ---------------------------------------------------------------------------
# the system: applied forces of every body, right-hand side, stop event
# ---------------------------------------------------------------------------
#: body kinds (params[2])
ANCHOR = 0
ELEMENT = 1  # chain link or cable element, in the water
ROD = 2  # the auxiliary rod, in the air (§3.2.2)
SHIP = 3

#: the scalar parameter vector (params[1]), one name a slot, declared once: a case field's path
#: (``mineburial.systems.restraint.model.FIELDS``) where the slot carries that field's value as it is,
#: else a quantity the system derives from the case (``derived.*``, SI units) or the code of a
#: choice or switch (``code.*``), both computed by ``systems.restraint.build_system``. The
#: kernels' ``P_*`` indices below are looked up by these names, so the vector's order is this
#: tuple's and nothing else numbers it.
PARAM_NAMES = (
    "water.gravity",
    "water.density",
    "water.kinematic_viscosity",
    "anchor.friction",
    "anchor.friction_velocity_scale",
    "anchor.drag_coefficient",
    "anchor.width",
    "anchor.height",
    "water.normal_drag",
    "water.tangential_drag",
    "seabed.foundation_stiffness",
    "water.current_speed",
    "derived.water_depth",  # the ship's water plane above the seabed at t = 0 (eq. (38)'s d)
    "ship.length",
    "derived.ship_wetted_area",  # S_W of eq. (61): L B + 2 (L + B) T
    "ship.roughness",
    "code.resistance_half",  # 1 (eq. (62) as printed) or 1/2 (the ITTC line's own definition)
    "derived.waterplane_area",  # A_W = L B
    "derived.displaced_volume",  # m / rho
    "derived.gm_longitudinal",  # GM_L, eq. (57)
    "water.added_mass",
    "code.friction",  # model.friction: 1 on, 0 off
    "code.drag",  # model.drag: 1 on, 0 off
    "code.morison",  # water.added_mass_form: 1 Morison, 0 the printed form
    "code.solver",  # numerics.solver: SOLVER_KANE or SOLVER_RECURSIVE
    "code.tangential_form",  # water.tangential_drag_form: TANGENTIAL_PERIMETER or _DIAMETER
)
PARAM_INDEX = {name: i for i, name in enumerate(PARAM_NAMES)}
N_PARAMS = len(PARAM_NAMES)
P_G = PARAM_INDEX["water.gravity"]
P_RHO = PARAM_INDEX["water.density"]
P_NU = PARAM_INDEX["water.kinematic_viscosity"]
P_MU = PARAM_INDEX["anchor.friction"]
P_VSCALE = PARAM_INDEX["anchor.friction_velocity_scale"]
P_CD_ANCHOR = PARAM_INDEX["anchor.drag_coefficient"]
P_ANCHOR_W = PARAM_INDEX["anchor.width"]
P_ANCHOR_H = PARAM_INDEX["anchor.height"]
P_CD = PARAM_INDEX["water.normal_drag"]
P_CF = PARAM_INDEX["water.tangential_drag"]
P_KZ = PARAM_INDEX["seabed.foundation_stiffness"]
P_USURF = PARAM_INDEX["water.current_speed"]
P_DEPTH = PARAM_INDEX["derived.water_depth"]
P_SHIP_L = PARAM_INDEX["ship.length"]
P_SHIP_SW = PARAM_INDEX["derived.ship_wetted_area"]
P_SHIP_KS = PARAM_INDEX["ship.roughness"]
P_HALF = PARAM_INDEX["code.resistance_half"]
P_AW = PARAM_INDEX["derived.waterplane_area"]
P_VOL = PARAM_INDEX["derived.displaced_volume"]
P_GML = PARAM_INDEX["derived.gm_longitudinal"]
P_CM = PARAM_INDEX["water.added_mass"]
P_FRICTION = PARAM_INDEX["code.friction"]
P_DRAG = PARAM_INDEX["code.drag"]
P_MORISON = PARAM_INDEX["code.morison"]
P_SOLVER = PARAM_INDEX["code.solver"]
P_TANGENTIAL = PARAM_INDEX["code.tangential_form"]

#: values of params[1][P_SOLVER]: how the Kane equations are solved (numerics.solver)
SOLVER_RECURSIVE = 0.0  # kernels.multibody.accelerations, O(N) tree recursion
SOLVER_KANE = 1.0  # kernels.multibody.accelerations_assembled: A du/dt = f assembled, Cholesky

#: codes of the anchor's seabed contact in :func:`solve_with_friction`
CONTACT_ON_SEABED = 0  # normal reaction > 0 and the friction solved (or switched off, or v = 0)
CONTACT_LIFTED = 1  # the solved normal reaction is <= 0: the anchor would leave the seabed
CONTACT_UNSOLVABLE = 2  # 1 + mu s dN/df <= 0: eq. (37) has no solution at this instant
#: indices of the contact counters (params[7]): right-hand-side evaluations with each code
N_CONTACT_CODES = 3


@kernel
def applied_forces(q, u, params):
    """Applied forces (Fx, Fz, My)[N, 3] at every centroid, except the anchor's friction.

    ``params = (desc, p, kind, length, diameter, weight, buoyancy, contact_counts)``: the
    multibody description, the scalar parameters (``P_*``), per body its kind, length,
    diameter, weight ``m g`` and full buoyancy ``rho V g``, and the counters of
    :func:`solve_with_friction`. Returns ``(forces, pos, vel, water_power,
    potential_g, potential_s, potential_e)``: the power of the water forces (eqs. (39),
    (45)-(47), (62), and in a current :func:`current_added_mass_correction`) and the
    potentials of gravity with buoyancy (eq. (65)), of the seabed
    foundation (eqs. (41), (68)) and of the ship's hydrostatic restoring (eq. (66)).
    """
    desc = params[0]
    p = params[1]
    kind = params[2]
    length = params[3]
    diameter = params[4]
    weight = params[5]
    buoy = params[6]
    pos, vel = body_states(q, u, desc)
    n = pos.shape[0]
    forces = np.zeros((n, 3))
    rho = p[P_RHO]
    g = p[P_G]
    drag_on = p[P_DRAG] != 0.0
    k_eff = p[P_KZ] - rho * g
    power = 0.0
    eg = 0.0
    es = 0.0
    ee = 0.0
    for k in range(n):
        z, th = pos[k, 1], pos[k, 2]
        vx, vz, om = vel[k, 0], vel[k, 1], vel[k, 2]
        kk = kind[k]
        if kk == SHIP:
            fz, my, pot = ship_hydrostatics(z - p[P_DEPTH], th, rho, g, p[P_AW], p[P_VOL], p[P_GML])
            forces[k, 1] += fz
            forces[k, 2] += my
            ee += pot
            if drag_on:
                fx = ship_resistance(
                    vx, p[P_USURF], p[P_SHIP_L], p[P_SHIP_SW], p[P_SHIP_KS], rho, p[P_NU], p[P_HALF]
                )
                forces[k, 0] += fx
                power += fx * vx
            continue
        net = weight[k] - buoy[k]
        forces[k, 1] -= net
        eg += net * z
        if kk == ANCHOR:
            if drag_on:
                cur = current_speed(z, p[P_USURF], p[P_DEPTH])
                fx = anchor_drag(vx, cur, rho, p[P_CD_ANCHOR], p[P_ANCHOR_W], p[P_ANCHOR_H])
                forces[k, 0] += fx
                power += fx * vx
        elif kk == ELEMENT:
            r = 0.5 * diameter[k]
            fz, my, pot, _ = element_foundation(z, th, length[k], r, k_eff)
            forces[k, 1] += fz
            forces[k, 2] += my
            es += pot
            cur = current_speed(z, p[P_USURF], p[P_DEPTH])
            if cur != 0.0 and p[P_MORISON] == 0.0:
                ma = rho * math.pi * r * r * length[k] * p[P_CM]
                fx, fz, my = current_added_mass_correction(th, vx, vz, om, ma, length[k], cur)
                forces[k, 0] += fx
                forces[k, 1] += fz
                forces[k, 2] += my
                power += fx * vx + fz * vz + my * om
            if drag_on:
                fx, fz, my = element_fluid_force(
                    th, vx, vz, om, length[k], diameter[k], rho, p[P_CD], p[P_CF], cur, p[P_TANGENTIAL]
                )
                forces[k, 0] += fx
                forces[k, 1] += fz
                forces[k, 2] += my
                power += fx * vx + fz * vz + my * om
    if p[P_MORISON] != 0.0:
        # seed 004 eq. (46) as printed (Morison type, -m_a n (n . a) only): cancel the core's
        # velocity terms of the rotating added mass; their power is counted as the water's
        gv = inertia_velocity_terms(q, u, desc)
        for k in range(n):
            for i in range(3):
                forces[k, i] += gv[k, i]
                power += gv[k, i] * vel[k, i]
    return forces, pos, vel, power, eg, es, ee


@kernel
def _kane_accelerations(q, u, forces, desc, solver):
    """du/dt of the core by the selected solver (P_SOLVER): the O(N) recursion or the assembled
    Kane equations A du/dt = f; both solve the same equations."""
    if solver == SOLVER_KANE:
        return accelerations_assembled(q, u, forces, desc)
    return accelerations(q, u, forces, desc)


@kernel
def solve_with_friction(q, u, params):
    """Accelerations with the anchor's Coulomb friction of eqs. (36)-(37).

    The normal force ``N`` of eq. (37) is the seabed's reaction on the anchor, i.e. the
    reaction of its locked vertical coordinate (row 0 of the core's joint forces), which
    contains the chain's pull ``F_2^H sin(beta_2)`` at the same instant. The friction is the
    generic regularised Coulomb law of :mod:`mineburial.kernels.seabed_contact`,
    ``f = -mu N s``, ``s = v / sqrt(v^2 + v_reg^2)`` (``v``: the anchor's velocity,
    ``v_reg``: anchor.friction_velocity_scale). Accelerations and reactions are affine in
    ``f``, so ``f = -mu s N(f)`` is solved exactly from two evaluations (seed 004 takes the
    previous step's tension instead).

    Where eq. (37) has no solution at the instant (``1 + mu s dN/df <= 0``) or the solved
    normal reaction is not positive (the chain would lift the anchor, which the model's
    locked anchor height cannot follow), the friction is set to zero and the instant is
    counted in ``params[7]`` (CONTACT_UNSOLVABLE, CONTACT_LIFTED); the run reports the counts.

    Returns ``(du, forces, hf, normal, friction, water_power, eg, es, ee, pos, vel, code)``.
    """
    desc = params[0]
    p = params[1]
    counts = params[7]
    solver = p[P_SOLVER]
    forces, pos, vel, power, eg, es, ee = applied_forces(q, u, params)
    du = _kane_accelerations(q, u, forces, desc, solver)
    hf = joint_forces(q, u, du, forces, desc)
    normal = hf[0, 1]
    friction = 0.0
    code = CONTACT_ON_SEABED
    if p[P_FRICTION] != 0.0 and p[P_MU] > 0.0:
        s = -regularised_friction(vel[0, 0], 1.0, 1.0, p[P_VSCALE])
        if s != 0.0:
            # a probe force of the friction's own size keeps the differences well conditioned
            probe = max(1.0, p[P_MU] * abs(normal))
            forces[0, 0] -= probe * s
            du1 = _kane_accelerations(q, u, forces, desc, solver)
            hf1 = joint_forces(q, u, du1, forces, desc)
            forces[0, 0] += probe * s
            dn = (hf1[0, 1] - normal) / (-probe * s)  # dN/df
            denom = 1.0 + p[P_MU] * s * dn
            if denom > 0.0:
                f = -p[P_MU] * s * normal / denom
                if normal + f * dn > 0.0:
                    friction = f
                else:
                    code = CONTACT_LIFTED
            else:
                code = CONTACT_UNSOLVABLE
            if friction != 0.0:
                w = friction / (-probe * s)
                for i in range(du.shape[0]):
                    du[i] += w * (du1[i] - du[i])
                for k in range(hf.shape[0]):
                    for i in range(2):
                        hf[k, i] += w * (hf1[k, i] - hf[k, i])
                forces[0, 0] += friction
            normal = normal + friction * dn
    if code == CONTACT_ON_SEABED and normal <= 0.0:
        code = CONTACT_LIFTED
    counts[code] += 1
    return du, forces, hf, normal, friction, power, eg, es, ee, pos, vel, code


@kernel
def restraint_rhs(t, y, params, dy):
    """dy/dt of the state ``y = (q, u, W^F, W^W)``: the generalised coordinates and speeds
    of the core and the work done on the system by the anchor friction (eq. (67)) and by
    the water (eq. (69)), integrated with the motion."""
    nd = (y.shape[0] - 2) // 2
    q = y[:nd]
    u = y[nd : 2 * nd]
    du, forces, hf, normal, friction, power, eg, es, ee, pos, vel, code = solve_with_friction(q, u, params)
    for i in range(nd):
        dy[i] = u[i]
        dy[nd + i] = du[i]
    dy[2 * nd] = friction * vel[0, 0]
    dy[2 * nd + 1] = power


@kernel
def restraint_event(t, y, params):
    """The stop event: the ship's surge speed (x velocity of the last body's centroid);
    the run ends where it first reaches zero from above."""
    nd = (y.shape[0] - 2) // 2
    pos, vel = body_states(y[:nd], y[nd : 2 * nd], params[0])
    return vel[vel.shape[0] - 1, 0]


@kernel
def record_diagnostics(states, params):
    """Per recorded state: centroid poses and velocities, pin forces, the anchor's normal
    and friction forces, the energy terms (E^K, E^G, E^E, E^S) and the anchor's contact code
    (CONTACT_*). Adds to the contact counters of params[7]; reset them after a run's counts
    are read."""
    n_rec = states.shape[0]
    nd = (states.shape[1] - 2) // 2
    n = params[2].shape[0]
    pos_all = np.empty((n_rec, n, 3))
    vel_all = np.empty((n_rec, n, 3))
    hf_all = np.empty((n_rec, n, 2))
    scal = np.empty((n_rec, 7))
    for r in range(n_rec):
        q = states[r, :nd].copy()
        u = states[r, nd : 2 * nd].copy()
        du, forces, hf, normal, friction, power, eg, es, ee, pos, vel, code = solve_with_friction(
            q, u, params
        )
        pos_all[r] = pos
        vel_all[r] = vel
        hf_all[r] = hf
        scal[r, 0] = kinetic_energy(q, u, params[0])
        scal[r, 1] = eg
        scal[r, 2] = ee
        scal[r, 3] = es
        scal[r, 4] = normal
        scal[r, 5] = friction
        scal[r, 6] = code
    return pos_all, vel_all, hf_all, scal


#: the restraining system of the integration core (:func:`mineburial.multibody.integrate`)
RESTRAINT = System("restraint", restraint_rhs, restraint_event)
