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
  eqs. (31)-(47) (:func:`mineburial.kernels.crossflow.quadratic_drag_integrals`). The
  added mass of eq. (46) is in the element's mass matrix, not here.
* :func:`element_foundation` -- the elastic seabed foundation of eq. (41) with the lost
  buoyancy of eq. (42): upward force ``(k_z - rho g) V^S`` at the centroid of the embedded
  volume, i.e. Archimedes in a heavy fluid of specific weight ``k_z - rho g``, which has
  an exact potential (the elastic energy of the foundation).
* :func:`anchor_drag` -- eq. (39); :func:`anchor_friction` -- eqs. (36)-(37) with a
  regularised sign; :func:`ship_resistance` -- eqs. (59)-(62);
  :func:`ship_hydrostatics` -- eqs. (55)-(58) (heave and pitch restoring).
"""

import math

from mineburial._numba import kernel
from mineburial.kernels.crossflow import quadratic_drag_integrals

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


@kernel
def element_fluid_force(theta, vx, vz, om, length, diameter, rho, cd, cf, current):
    """Drag of a straight cylindrical element (eqs. (43)-(47)), resultant at its centroid.

    ``theta``: attitude; ``(vx, vz, om)``: centroid velocity and angular velocity;
    ``current``: horizontal water velocity at the centroid (eq. (38)). The water velocity
    relative to the element (eq. (43)) has the tangential part ``w_t`` and, at axial
    station s, the normal part ``w_n(s) = w_n(0) - om s``.

    * tangential drag, eq. (45): ``pi rho D L C_F |w_t| w_t / 2`` along the axis;
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
    ft = 0.5 * math.pi * rho * diameter * length * cf * abs(wt) * wt
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
def regularised_sign(v, v_scale):
    """``tanh(v / v_scale)``: the sign of the Coulomb friction of eq. (37), smoothed over
    ``v_scale`` so that the anchor's stick phase is an ordinary ODE (``v_scale = 0``:
    the plain sign)."""
    if v_scale <= 0.0:
        if v > 0.0:
            return 1.0
        if v < 0.0:
            return -1.0
        return 0.0
    return math.tanh(v / v_scale)


@kernel
def anchor_friction(normal_force, v_anchor, mu, v_scale):
    """Eq. (37) with eq. (36)'s direction: ``-mu N sign(v)``; ``N`` is the seabed's normal
    reaction ``m g - rho V g - (upward chain pull)``, never negative (a lifted anchor
    has no friction)."""
    if normal_force <= 0.0:
        return 0.0
    return -mu * normal_force * regularised_sign(v_anchor, v_scale)


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
