"""Seabed contact of a planar body: elastic foundation with damping plus regularised Coulomb friction.

Seed 004 treats the seabed as an elastic foundation (sec. 2.2; eq. (41): a supporting force
F^S = k_z V^S proportional to the embedded volume, k_z = 5e6 N m^-3 for a soft soil) and drags its gravity
anchor on it with Coulomb friction (eq. (37): F^F = mu N, with a stick test, the anchor held while the pull
is below mu N). These kernels give the generic pieces, for any body of a multibody description, as
(Fx, Fz, My) at the body's centroid (planar conventions of :mod:`mineburial.kernels.multibody`:
x horizontal, z up, My = rx Fz - rz Fx):

* :func:`point_contact` -- a point of the body (a corner, the bottom of an anchor): where the penetration
  d = z_seabed - z_point is positive, the normal force N = max(0, k d - c vz_point) and the friction
  -mu N v / sqrt(v^2 + v_reg^2) against the point's horizontal velocity v.
* :func:`segment_contact` -- a straight segment of the body (a chain link, a cable element, the flat bottom
  of a block) on a Winkler foundation: per unit length n(s) = max(0, k' d(s) - c' vz(s)) and friction
  -mu n(s) v(s) / sqrt(v(s)^2 + v_reg^2), integrated along the embedded part of the segment by Gauss-Legendre
  (8 points: the elastic part, linear in s, is integrated exactly). With k' = k_z D (a flat-bottomed section
  of width D) this is eq. (41) for an embedding of depth d: F^S = k_z D d per unit length.

Regularised friction (a smooth sign of the sliding velocity) replaces the stick/slip switch of seed 004
sec. 3.2.1: above a few v_reg it is Coulomb friction mu N; a body pulled by less than mu N creeps instead of
sticking, at about v_reg F / (mu N). Choose v_reg small against the speeds of interest (the error of a
stopping time is of order v_reg / deceleration); smaller v_reg stiffens the equations near rest.
Energies: :func:`point_foundation_energy`, :func:`segment_foundation_energy` (the elastic energy stored
in the foundation; the damping and friction work is what a system integrates as dissipation, seed 004
eqs. (67)-(68)).
"""

import math

import numpy as np

from mineburial._numba import kernel

#: 8-point Gauss-Legendre nodes and weights on [-1, 1]
GL_NODES, GL_WEIGHTS = np.polynomial.legendre.leggauss(8)


@kernel
def regularised_friction(v, normal_force, mu, v_reg):
    """Friction force -mu N v / sqrt(v^2 + v_reg^2) against the sliding velocity v (v_reg > 0)."""
    return -mu * normal_force * v / math.sqrt(v * v + v_reg * v_reg)


@kernel
def point_contact(x, z, th, vx, vz, om, a, b, seabed_z, stiffness, damping, mu, v_reg):
    """Contact force of a point at body-frame (a, b) of a body with centroid state (x, z, th, vx, vz, om):
    returns (Fx, Fz, My) at the centroid. stiffness in N/m, damping in N s/m; the damping only pushes
    (the normal force is never negative: no adhesion)."""
    c = math.cos(th)
    s = math.sin(th)
    rx = c * a - s * b
    rz = s * a + c * b
    pz = z + rz
    d = seabed_z - pz
    if d <= 0.0:
        return 0.0, 0.0, 0.0
    pvx = vx - om * rz
    pvz = vz + om * rx
    n = stiffness * d - damping * pvz
    if n <= 0.0:
        return 0.0, 0.0, 0.0
    fx = regularised_friction(pvx, n, mu, v_reg)
    fz = n
    return fx, fz, rx * fz - rz * fx


@kernel
def _embedded_interval(z, s_th, half_length, seabed_z):
    """Interval [s0, s1] of the axial coordinate s in [-h, h] where z + s sin(th) < seabed_z; s0 >= s1
    when none."""
    if s_th == 0.0:
        if z < seabed_z:
            return -half_length, half_length
        return 0.0, 0.0
    sc = (seabed_z - z) / s_th
    if s_th > 0.0:
        return -half_length, min(half_length, sc)
    return max(-half_length, sc), half_length


@kernel
def segment_contact(x, z, th, vx, vz, om, half_length, seabed_z, stiffness, damping, mu, v_reg):
    """Contact force of the segment s in [-h, h] along the body's a axis through its centroid, on a Winkler
    foundation: stiffness per unit length in N/m^2 (force per length per depth), damping in N s/m^2.
    Returns (Fx, Fz, My) at the centroid."""
    c = math.cos(th)
    s = math.sin(th)
    s0, s1 = _embedded_interval(z, s, half_length, seabed_z)
    if s1 <= s0:
        return 0.0, 0.0, 0.0
    mid = 0.5 * (s0 + s1)
    rad = 0.5 * (s1 - s0)
    fx = 0.0
    fz = 0.0
    my = 0.0
    for i in range(GL_NODES.shape[0]):
        si = mid + rad * GL_NODES[i]
        wi = rad * GL_WEIGHTS[i]
        rx = si * c
        rz = si * s
        d = seabed_z - z - rz
        n = stiffness * d - damping * (vz + om * rx)
        if n <= 0.0:
            continue
        ft = regularised_friction(vx - om * rz, n, mu, v_reg)
        fx += wi * ft
        fz += wi * n
        my += wi * (rx * n - rz * ft)
    return fx, fz, my


@kernel
def point_foundation_energy(z, th, a, b, seabed_z, stiffness):
    """Elastic energy 1/2 k d^2 stored under a contact point (d: penetration)."""
    d = seabed_z - (z + math.sin(th) * a + math.cos(th) * b)
    if d <= 0.0:
        return 0.0
    return 0.5 * stiffness * d * d


@kernel
def segment_foundation_energy(z, th, half_length, seabed_z, stiffness):
    """Elastic energy int 1/2 k' d(s)^2 ds stored under the embedded part of a segment (exact: d is linear
    in s)."""
    s = math.sin(th)
    s0, s1 = _embedded_interval(z, s, half_length, seabed_z)
    if s1 <= s0:
        return 0.0
    d0 = seabed_z - z - s0 * s
    d1 = seabed_z - z - s1 * s
    return 0.5 * stiffness * (s1 - s0) * (d0 * d0 + d0 * d1 + d1 * d1) / 3.0
