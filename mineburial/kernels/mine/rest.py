"""The end of a drop: can the sediment hold the mine where it is?

A mine in contact with the sediment is at rest when it is slow (seed 000 eq. (89): COM
speed below ``numerics.rest_speed`` and angular speed below ``numerics.rest_spin``)
**and** the sediment can hold it there. The second condition is a rigid-plastic hold
test by the upper-bound theorem of limit analysis (Drucker, Prager & Greenberg 1952;
Chen 1975, *Limit Analysis and Soil Plasticity*, ch. 2): a rigid body on a rigid-plastic
medium stays put unless some collapse mechanism (a virtual rigid motion, a twist
xi = (v, omega)) makes the static load do more work than the medium dissipates,

    W . xi = F . v + M . omega  >  D(xi) = -(R(xi) . v + M_R(xi) . omega),

where (F, M) is the static load wrench about the centre of mass (gravity, buoyancy of
the immersed part, geostatic overburden of the embedded part: everything that does
not depend on the velocity) and (R, M_R) the sediment's resistance to a motion with
twist xi, evaluated by the traction laws themselves at the probe speed.

The resistance is that of the unregularised law (the switch and slip regularisation of
``numerics.slip_speed`` and ``numerics.switch_speed`` is a numerical device to keep the motion continuous, not
strength: a rigid-plastic capacity is fully mobilised by any motion).
The probe speed is the rest speed: with a rate-dependent strength, a mine that passes
the test would creep, if at all, slower than the rest speed, which is what eq. (89)
calls rest. Mechanisms probed (each only where the load drives it, W . xi > 0):

1. translation along the load force F (sinking, sliding);
2. rotation about the centre of mass along the load torque M;
3. the twist along the whole load, v ~ F, omega ~ M / L_c^2 (L_c: half length plus
   the COM offset), scaled to the probe speed at the farthest point;
4. toppling: rotation along M about the deepest point of the body (the pivot of a
   mine standing on its nose or lying on an edge), v = omega x (r_COM - r_pivot).

A mine that fails any of them keeps moving: the integration goes on, and the test is
repeated while it is slow. The force tolerance of the test is
``mass * rest_speed / REST_TIME`` (a load that would change the speed by less than the
rest speed in REST_TIME seconds is no load).
"""

import math

from mineburial._numba import kernel
from mineburial.kernels.mine import bodies
from mineburial.kernels.mine.dynamics import drop_body, vertical_load
from mineburial.kernels.mine.geometry import e_down_body
from mineburial.kernels.mine.layout import (
    P_DEPTH,
    P_GRAVITY,
    P_MASS,
    P_RHO_WATER,
    P_SED_RESISTANCE,
)
from mineburial.kernels.mine.overburden import overburden_force
from mineburial.kernels.mine.sediment import RES_DELTA, sediment_tractions
from mineburial.kernels.mine.sediment.laws import LAW_DEPTH_FACTOR, LAW_REFERENCE_PATHS, LAW_VREG
from mineburial.kernels.rotation import rotation_matrix

#: s: the force tolerance of the hold test is mass * rest_speed / REST_TIME
REST_TIME = 1.0


@kernel
def static_load(y, p, law, bank):
    """Static load wrench on the mine: E-frame force and body-frame torque about the COM
    of gravity, water buoyancy of the immersed part (seed 000 eqs. (34)-(36)) and, for the
    ``friction`` and ``bearing`` laws, the geostatic overburden on the embedded part
    (:mod:`.overburden`). Returns (Fx, Fy, Fz, M1, M2, M3)."""
    body = drop_body(p, law)
    g = p[P_GRAVITY]
    rho_w = p[P_RHO_WATER]
    depth = p[P_DEPTH]
    qn = math.sqrt(y[6] * y[6] + y[7] * y[7] + y[8] * y[8] + y[9] * y[9])
    r = rotation_matrix(y[6] / qn, y[7] / qn, y[8] / qn, y[9] / qn)
    kb1 = r[6]
    kb2 = r[7]
    kb3 = r[8]
    z = y[2]
    z_lo, _ = bodies.extent(body, kb1, z)
    vs, xs, es, _, _, _ = bodies.cut(body, kb1, z, 0.0)
    f = rho_w * g * vs
    fx = f * xs
    fe = f * es
    if z_lo < -depth and int(p[P_SED_RESISTANCE]) != RES_DELTA:
        fo, fox, foe = overburden_force(body, kb1, z, -depth, z_lo, rho_w, g, p, bank, law)
        f += fo
        fx += fox
        fe += foe
    _, dn2, dn3 = e_down_body(kb1, kb2, kb3)
    # torque of the vertical force f with first moments fx (along i_M) and fe (along e_down)
    _, _, _, m1, m2, m3 = vertical_load(f, fx, fe, dn2, dn3, kb1, kb2, kb3)
    return 0.0, 0.0, f - p[P_MASS] * g, m1, m2, m3


@kernel
def _resisted(y, p, law, bank, r, v1, v2, v3, w1, w2, w3, load_power, tol_power):
    """Does the sediment dissipate at least the load's power on the body twist
    (v body-frame, w body-frame)?"""
    vx = r[0] * v1 + r[1] * v2 + r[2] * v3
    vy = r[3] * v1 + r[4] * v2 + r[5] * v3
    vz = r[6] * v1 + r[7] * v2 + r[8] * v3
    fx, fy, fz, m1, m2, m3, _ = sediment_tractions(
        drop_body(p, law), r, (y[0], y[1], y[2]), (vx, vy, vz), (w1, w2, w3), -p[P_DEPTH], law, bank
    )
    dissipated = -(fx * vx + fy * vy + fz * vz + m1 * w1 + m2 * w2 + m3 * w3)
    return dissipated >= load_power - tol_power


@kernel
def held_by_sediment(y, p, law, bank, probe_speed):
    """Rigid-plastic hold test (module docstring): True when no probed mechanism lets the
    static load move the mine against the sediment's resistance at ``probe_speed``."""
    body = drop_body(p, law)
    depth = p[P_DEPTH]
    qn = math.sqrt(y[6] * y[6] + y[7] * y[7] + y[8] * y[8] + y[9] * y[9])
    r = rotation_matrix(y[6] / qn, y[7] / qn, y[8] / qn, y[9] / qn)
    z_lo, _ = bodies.extent(body, r[6], y[2])
    if not (z_lo < -depth):
        return False
    fx, fy, fz, m1, m2, m3 = static_load(y, p, law, bank)
    # the rigid-plastic capacity: the law without its switch and slip regularisation, and
    # without the soil's inertial drag (a dynamic pressure, no capacity)
    law = (
        law[:LAW_VREG]
        + (1e-9 * probe_speed, 1e-9 * probe_speed, law[LAW_DEPTH_FACTOR], 0.0)
        + law[LAW_REFERENCE_PATHS:]
    )
    # load force in the body frame
    f1 = r[0] * fx + r[3] * fy + r[6] * fz
    f2 = r[1] * fx + r[4] * fy + r[7] * fz
    f3 = r[2] * fx + r[5] * fy + r[8] * fz
    tol = p[P_MASS] * probe_speed / REST_TIME
    _, lc = bodies.sizes(body)
    fn = math.sqrt(f1 * f1 + f2 * f2 + f3 * f3)
    mn = math.sqrt(m1 * m1 + m2 * m2 + m3 * m3)
    tol_power = tol * probe_speed
    if fn <= tol and mn <= tol * lc:
        return True
    # 1. translation along the load force
    if fn > tol:
        s = probe_speed / fn
        if not _resisted(
            y, p, law, bank, r, f1 * s, f2 * s, f3 * s, 0.0, 0.0, 0.0, fn * probe_speed, tol_power
        ):
            return False
    if mn > tol * lc:
        # 2. rotation about the COM along the load torque (farthest point at probe speed)
        s = probe_speed / (mn * lc)
        if not _resisted(y, p, law, bank, r, 0.0, 0.0, 0.0, m1 * s, m2 * s, m3 * s, mn * mn * s, tol_power):
            return False
        # 4. toppling about the deepest point of the body: the end of the axis that is
        # lower, on the rim towards e_down
        xp, py, pz = bodies.deepest_point(body, r[6], r[7], r[8])
        w1 = m1 * s
        w2 = m2 * s
        w3 = m3 * s
        # v_COM = w x (r_COM - r_pivot) = w x (-xp, -py, -pz)
        v1 = w2 * (-pz) - w3 * (-py)
        v2 = w3 * (-xp) - w1 * (-pz)
        v3 = w1 * (-py) - w2 * (-xp)
        power = f1 * v1 + f2 * v2 + f3 * v3 + m1 * w1 + m2 * w2 + m3 * w3
        if power > 0.0:
            if not _resisted(y, p, law, bank, r, v1, v2, v3, w1, w2, w3, power, tol_power):
                return False
    # 3. the twist along the whole load
    if fn > tol and mn > tol * lc:
        a1 = f1
        a2 = f2
        a3 = f3
        b1 = m1 / (lc * lc)
        b2 = m2 / (lc * lc)
        b3 = m3 / (lc * lc)
        vmax = math.sqrt(a1 * a1 + a2 * a2 + a3 * a3) + lc * math.sqrt(b1 * b1 + b2 * b2 + b3 * b3)
        s = probe_speed / vmax
        power = (f1 * a1 + f2 * a2 + f3 * a3 + m1 * b1 + m2 * b2 + m3 * b3) * s
        if not _resisted(
            y, p, law, bank, r, a1 * s, a2 * s, a3 * s, b1 * s, b2 * s, b3 * s, power, tol_power
        ):
            return False
    return True
