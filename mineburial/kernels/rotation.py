"""Unit-quaternion orientation kernels (seed 004 Euler parameters, eqs. (2)-(6), (28)).

The orientation of the mine is the unit quaternion ``q = (q0, q1, q2, q3)``
(scalar first) that rotates body (M-frame) vectors into the earth (E-frame):
``v_E = R(q) v_M``. Seed 000 describes the same rotation with the angles of
its eq. (4), ``R = Rz(psi3) Ry(psi2) Rx(psi1)``; those angles are derived from
``q`` for output only, so the integration never meets the gimbal singularity
of eqs. (8)-(10) at psi2 = +-90 deg.
"""

import math

from mineburial._numba import kernel


@kernel
def rotation_matrix(q0, q1, q2, q3):
    """Rotation matrix body->earth of a unit quaternion, row-major 9-tuple.

    Columns are i_M, j_M, k_M expressed in the E-frame (seed 000 eq. (5)).
    Standard Euler-parameter form (seed 004 eq. (3)).
    """
    r00 = 1.0 - 2.0 * (q2 * q2 + q3 * q3)
    r01 = 2.0 * (q1 * q2 - q0 * q3)
    r02 = 2.0 * (q1 * q3 + q0 * q2)
    r10 = 2.0 * (q1 * q2 + q0 * q3)
    r11 = 1.0 - 2.0 * (q1 * q1 + q3 * q3)
    r12 = 2.0 * (q2 * q3 - q0 * q1)
    r20 = 2.0 * (q1 * q3 - q0 * q2)
    r21 = 2.0 * (q2 * q3 + q0 * q1)
    r22 = 1.0 - 2.0 * (q1 * q1 + q2 * q2)
    return (r00, r01, r02, r10, r11, r12, r20, r21, r22)


@kernel
def quaternion_rate(q0, q1, q2, q3, w1, w2, w3):
    """dq/dt = q (x) (0, omega)/2 with omega in the body frame (seed 004 eq. (28))."""
    return (
        0.5 * (-q1 * w1 - q2 * w2 - q3 * w3),
        0.5 * (q0 * w1 + q2 * w3 - q3 * w2),
        0.5 * (q0 * w2 + q3 * w1 - q1 * w3),
        0.5 * (q0 * w3 + q1 * w2 - q2 * w1),
    )


@kernel
def quaternion_multiply(a0, a1, a2, a3, b0, b1, b2, b3):
    """Hamilton product a (x) b."""
    return (
        a0 * b0 - a1 * b1 - a2 * b2 - a3 * b3,
        a0 * b1 + a1 * b0 + a2 * b3 - a3 * b2,
        a0 * b2 - a1 * b3 + a2 * b0 + a3 * b1,
        a0 * b3 + a1 * b2 - a2 * b1 + a3 * b0,
    )


@kernel
def rotation_vector_quaternion(phi1, phi2, phi3):
    """Quaternion of a rotation by the rotation vector (phi1, phi2, phi3)."""
    angle = math.sqrt(phi1 * phi1 + phi2 * phi2 + phi3 * phi3)
    if angle < 1e-12:
        # second-order series of sin(a/2)/a keeps the result unit to rounding
        s = 0.5 - angle * angle / 48.0
        c = 1.0 - angle * angle / 8.0
    else:
        s = math.sin(0.5 * angle) / angle
        c = math.cos(0.5 * angle)
    return (c, s * phi1, s * phi2, s * phi3)


@kernel
def normalize_quaternion(q0, q1, q2, q3):
    n = math.sqrt(q0 * q0 + q1 * q1 + q2 * q2 + q3 * q3)
    return (q0 / n, q1 / n, q2 / n, q3 / n)


#: |sin psi2| above which the nose is taken as vertical (the gimbal lock of the angles)
GIMBAL_LOCK = 1.0 - 1e-12


@kernel
def euler_angles(q0, q1, q2, q3):
    """(psi1, psi2, psi3) in radians: roll about the axis, nose dip, heading.

    Z-Y-X angles of R(q) = Rz(psi3) Ry(psi2) Rx(psi1) (seed 000 eq. (4)), so
    i_M = (cos psi3 cos psi2, sin psi3 cos psi2, -sin psi2); psi2 in [-pi/2, pi/2],
    psi1, psi3 in (-pi, pi]. ``q`` must be a unit quaternion.

    At the gimbal lock (nose vertical, |sin psi2| > :data:`GIMBAL_LOCK`) only psi3 -/+ psi1
    is defined: psi1 is then 0 and psi3 carries the whole rotation about the vertical.
    """
    r = rotation_matrix(q0, q1, q2, q3)
    s2 = -r[6]
    if s2 > 1.0:
        s2 = 1.0
    elif s2 < -1.0:
        s2 = -1.0
    psi2 = math.asin(s2)
    if abs(s2) > GIMBAL_LOCK:
        return 0.0, psi2, math.atan2(-r[1], r[4])
    psi3 = math.atan2(r[3], r[0])
    psi1 = math.atan2(r[7], r[8])
    return psi1, psi2, psi3
