"""Sediment resistance on the embedded part of the mine (seed 000 section 6).

A small package with methods chosen by name:

* :mod:`.laws` — profiles, strain-rate laws, the traction at one surface point, and
  :func:`~.laws.pack_law`, which packs the law of a drop once into a tuple;
* :mod:`.reference` — the accurate adaptive quadrature over the embedded surface
  (``numerics.sediment_quadrature = "reference"``), the guard in the tests;
* :mod:`.fast` — the fixed-cost rule (``"fast"``, the default), smooth in the state;
* :mod:`.pore` — the pore-water pressure of eq. (73).

:func:`sediment_tractions` is what the equations of motion call;
:func:`sediment_force_torque` is the same with the law packed from a parameter vector.
"""

import math

from mineburial._numba import kernel
from mineburial.kernels.mine import bodies
from mineburial.kernels.mine.sediment.laws import (
    LAW_G,
    LAW_PORE,
    LAW_REFERENCE_PATHS,
    LAW_RHO_W,
    RATE_IMPACT35,
    RATE_NONE,
    RATE_SEMILOG,
    RES_BEARING,
    RES_DELTA,
    RES_FRICTION,
    V_REG,
    V_REG_N,
    pack_law,
    rate_factor,
    sediment_properties,
)

#: the law's slots after the water density and gravity (a constant: numba slices a tuple by constants)
_AFTER_G = LAW_G + 1
assert LAW_G == LAW_RHO_W + 1
QUADRATURE_FAST = 0
QUADRATURE_REFERENCE = 1

__all__ = [
    "sediment_tractions",
    "sediment_force_torque",
    "pack_law",
    "sediment_properties",
    "rate_factor",
    "RES_DELTA",
    "RES_FRICTION",
    "RES_BEARING",
    "RATE_IMPACT35",
    "RATE_SEMILOG",
    "RATE_NONE",
    "V_REG",
    "V_REG_N",
    "QUADRATURE_FAST",
    "QUADRATURE_REFERENCE",
]


@kernel
def sediment_tractions(body, rot, com, vel, omega, seabed_z, law, bank):
    """Resistance of the sediment on the embedded part of the mine.

    body: the mine's body (:mod:`mineburial.kernels.mine.bodies`: its embedded surface, the rule
    that integrates the tractions over it, its pore pressure); rot: 9 floats, row-major
    rotation matrix body->earth; com, vel: COM position and velocity (E-frame, z up);
    omega: angular velocity (body frame); seabed_z: height of the seabed; law:
    :func:`pack_law`; bank: sediment profile bank (``layout``).

    Returns ``(Fx, Fy, Fz, Mx, My, Mz, added_mass_z)``: the force in the E-frame, the
    torque about the COM in the body frame, and the vertical added mass (kg) of the
    dw/dt term of the pore-pressure law eq. (73) (0 when pore pressure is off), which
    the caller puts on the left-hand side: its force is -added_mass_z * dw/dt.
    """
    c20 = rot[6]
    c21 = rot[7]
    c22 = rot[8]
    d0 = seabed_z - com[2]
    zeta_tip = d0 - bodies.lowest_offset(body, c20, c21, c22)
    if not (zeta_tip > 0.0):
        return 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0
    # COM velocity in the body frame (C^T vel)
    v1 = rot[0] * vel[0] + rot[3] * vel[1] + rot[6] * vel[2]
    v2 = rot[1] * vel[0] + rot[4] * vel[1] + rot[7] * vel[2]
    v3 = rot[2] * vel[0] + rot[5] * vel[1] + rot[8] * vel[2]
    w1 = omega[0]
    w2 = omega[1]
    w3 = omega[2]
    # velocity components at the rounding level of the others are zero (an axial motion
    # stays exactly tangential to the lateral surface, so delta = 1 holds there)
    scale, _ = bodies.sizes(body)
    vtiny = 1e-13 * (math.sqrt(v1 * v1 + v2 * v2 + v3 * v3) + math.sqrt(w1 * w1 + w2 * w2 + w3 * w3) * scale)
    if abs(v1) < vtiny:
        v1 = 0.0
    if abs(v2) < vtiny:
        v2 = 0.0
    if abs(v3) < vtiny:
        v3 = 0.0
    if abs(w1) * scale < vtiny:
        w1 = 0.0
    if abs(w2) * scale < vtiny:
        w2 = 0.0
    if abs(w3) * scale < vtiny:
        w3 = 0.0
    vbody = (v1, v2, v3, w1, w2, w3)
    # the rules and the pore law get the law without its last slot, whose type selects what
    # is compiled (pack_law): their compiled code is then one for the default and the
    # reference paths, not compiled again when a drop first needs the reference paths
    # (docs/design.md, compile time)
    rule_law = law[:LAW_REFERENCE_PATHS]
    f1, f2, f3, m1, m2, m3 = bodies.surface_tractions(
        body, law[LAW_REFERENCE_PATHS], c20, c21, c22, d0, vbody, rule_law, bank
    )
    fx = rot[0] * f1 + rot[1] * f2 + rot[2] * f3
    fy = rot[3] * f1 + rot[4] * f2 + rot[5] * f3
    fz = rot[6] * f1 + rot[7] * f2 + rot[8] * f3
    added = 0.0
    if law[LAW_PORE]:
        fpw, t2, t3, added = bodies.pore(body, c20, c21, c22, d0, zeta_tip, vel[2], rule_law, bank)
        fz += fpw
        m2 += t2
        m3 += t3
    return fx, fy, fz, m1, m2, m3, added


@kernel
def sediment_force_torque(body, rot, com, vel, omega, seabed_z, water_density, gravity, p, sediment_bank):
    """:func:`sediment_tractions` with the law packed from the parameter vector ``p``
    (``water_density`` and ``gravity`` as given, for tests that vary them)."""
    radius, _ = bodies.strip_section(body)
    law = pack_law(p, 2.0 * radius)
    law = law[:LAW_RHO_W] + (water_density, gravity) + law[_AFTER_G:]
    return sediment_tractions(body, rot, com, vel, omega, seabed_z, law, sediment_bank)
