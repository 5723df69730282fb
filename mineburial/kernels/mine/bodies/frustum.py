"""The solid frustum (truncated cone; a cone when one radius is 0, the cylinder when both are equal),
for the Manta-like mine of issue 36 (items 2-3): the body protocol's functions.

Geometry (:mod:`.revolution_geometry` on the two stations, no allocation: the stations are tuples):
``cut``, ``extent``, ``burial``, ``volume``, ``ends``, ``reference_lengths``, ``lowest_offset``,
``deepest_point``, ``sizes`` and ``equivalent_part`` (seed 000 section 4.1's equivalent body: the
axial interval of the part's volume and centroid). Physics: the sediment's ``surface_tractions``
(the fast rule on the tilted lateral surface and the two caps, :mod:`.revolution_sediment`; a
profile has no reference quadrature, so ``reference_paths`` is ignored) and ``pore`` (seed 000 eq.
(73)); the fluid's ``finite_added_mass`` (the closed frustum's BEM table,
:func:`.added_mass.frustum_added_mass`) and ``crossflow_efficiency`` (DATCOM's eta at the aspect
ratio ``L / d_mean``). A frustum of equal radii calls the cylinder's own functions wherever the
profile's arithmetic would differ in the last bits, so it gives the cylinder's answers bit for bit
(tests/test_frustum.py).

Registered (:func:`mineburial.kernels.mine.bodies.register`): a scenario chooses it with ``mine.shape =
"frustum"`` (base diameter ``mine.diameter``, top ``mine.top_ratio`` of it, ``mine.length`` apart;
:func:`from_params`). The fluid strips of the wetted parts are the shape's own hooks that
``dynamics`` calls when a shape module has them: :func:`strip_loads` (the strips of the local
section, :func:`.revolution_fluid.profile_strip_forces`) and :func:`added_mass` (strip theory's
moments of the local section, or the BEM factors, :func:`added_mass_moments`); ``strip_section``
returns the mean radius for the laws that take one radius.

A frustum of length ``length`` whose tail (``x = -L/2 - chi``) has radius ``radius_tail`` and nose
(``x = L/2 - chi``) ``radius_nose``; its COM sits ``com_offset`` (chi) behind its middle, as the
cylinder's (seed 000 eq. (42)).
"""

import math
import sys
from typing import NamedTuple

from mineburial._numba import kernel, small_kernel
from mineburial.kernels.mine import bodies
from mineburial.kernels.mine.added_mass import crossflow_efficiency as _crossflow_efficiency
from mineburial.kernels.mine.added_mass import cylinder_added_mass, frustum_added_mass
from mineburial.kernels.mine.bodies.revolution_fluid import profile_strip_added_mass, profile_strip_forces
from mineburial.kernels.mine.bodies.revolution_geometry import (
    burial_profile,
    cut_profile,
    equivalent_interval,
    extent_profile,
    lowest_profile_point,
    volume_profile,
)
from mineburial.kernels.mine.bodies.revolution_sediment import profile_pore_pressure, profile_tractions
from mineburial.kernels.mine.dynamics import _added_mass as _one_radius_added_mass
from mineburial.kernels.mine.geometry import (
    PI,
    burial_measures,
    cut_cylinder,
    e_down_body,
    equivalent_of_part,
    vertical_extent,
)
from mineburial.kernels.mine.layout import (
    P_ADDED_MASS_FACTOR,
    P_CHI,
    P_DIAMETER,
    P_LENGTH,
    P_MUNK,
    P_RHO_AIR,
    P_RHO_WATER,
    P_TOP_RATIO,
)
from mineburial.kernels.mine.sediment.pore import pore_pressure


class Frustum(NamedTuple):
    """A solid frustum: length [m], tail and nose radii [m], COM offset ``chi`` [m]."""

    length: float
    radius_tail: float
    radius_nose: float
    com_offset: float


#: the transverse added-mass coefficient of a circular section (seed 001 eq. (5), (20)), as dynamics.C_M
C_M = 1.0


@kernel
def from_params(p):
    """The drop's frustum from its parameter vector: base (tail) radius ``mine.diameter / 2``, top
    (nose) ``mine.top_ratio`` of it, length ``mine.length``; ``mine.com_offset`` is the COM's offset
    from the centre of volume towards the top (the scenario field's meaning), so the body's offset
    from the middle of its length adds the uniform frustum's centroid offset
    ``L (r_t^2 - r_b^2) / (4 (r_b^2 + r_b r_t + r_t^2))`` (``shapes.frustum_centroid_offset``;
    exactly 0 for equal radii, so a ratio of 1 is the cylinder's body)."""
    length = p[P_LENGTH]
    r_base = 0.5 * p[P_DIAMETER]
    r_top = r_base * p[P_TOP_RATIO]
    sum_sq = r_base * r_base + r_base * r_top + r_top * r_top
    shift = length * (r_top * r_top - r_base * r_base) / (4.0 * sum_sq)
    return Frustum(length, r_base, r_top, p[P_CHI] + shift)


@small_kernel
def _stations(body):
    """(xs, rs): the tail and the nose about the COM and their radii, as tuples."""
    xt = -0.5 * body.length - body.com_offset
    xn = 0.5 * body.length - body.com_offset
    return (xt, xn), (body.radius_tail, body.radius_nose)


def cut(body, a_z, z_c, level):
    """The part below the plane (:func:`.revolution_geometry.cut_profile`; equal radii: the cylinder's
    closed form, :func:`.geometry.cut_cylinder`, bit for bit, as every geometric function here)."""
    if body.radius_tail == body.radius_nose:
        return cut_cylinder(body.length, body.radius_tail, body.com_offset, a_z, z_c, level)
    xs, rs = _stations(body)
    return cut_profile(xs, rs, a_z, z_c, level)


def cut_sliver(body, a_z, z_c, level):
    """Unknown (kind 2: the overburden cuts the body, kernels/mine/overburden.py): no bound on a
    frustum's sliver is written."""
    return 2, math.inf, 0.0, 0.0, 0.0


def extent(body, a_z, z_c):
    """Lowest and highest heights: at the end sections' rims (:func:`.revolution_geometry.extent_profile`)."""
    if body.radius_tail == body.radius_nose:
        return vertical_extent(body.length, body.radius_tail, body.com_offset, a_z, z_c)
    xs, rs = _stations(body)
    return extent_profile(xs, rs, a_z, z_c)


def burial(body, a_z, z_c, level):
    """The results table's burial measures (:func:`.revolution_geometry.burial_profile`)."""
    if body.radius_tail == body.radius_nose:
        return burial_measures(body.length, body.radius_tail, body.com_offset, a_z, z_c, level)
    xs, rs = _stations(body)
    return burial_profile(xs, rs, a_z, z_c, level)


def volume(body):
    """``pi L (r_t^2 + r_t r_n + r_n^2)/3`` and the axial position of its centroid about the COM."""
    if body.radius_tail == body.radius_nose:
        return PI * body.radius_tail * body.radius_tail * body.length, -body.com_offset
    xs, rs = _stations(body)
    v, x_c, _ = volume_profile(xs, rs)
    return v, x_c


def ends(body):
    """Tail and nose at ``x = -L/2 - chi, L/2 - chi``."""
    xs, _ = _stations(body)
    return xs[0], xs[1]


def reference_lengths(body):
    """The larger diameter and the length (what the laws written for a cylinder would take: a
    choice to revisit with those laws)."""
    return 2.0 * max(body.radius_tail, body.radius_nose), body.length


def lowest_offset(body, k1, k2, k3):
    """Height above the COM of the lower end section's rim towards ``e_down``."""
    if body.radius_tail == body.radius_nose:
        xa, xb = bodies.ends(body)
        return min(k1 * xa, k1 * xb) - body.radius_tail * math.sqrt(k2 * k2 + k3 * k3)
    xs, rs = _stations(body)
    return lowest_profile_point(xs, rs, k1, k2, k3)[3]


def deepest_point(body, k1, k2, k3):
    """A lowest point (body frame): on the rim of the end section that reaches lowest."""
    if body.radius_tail == body.radius_nose:
        xa, xb = bodies.ends(body)
        _, dn2, dn3 = e_down_body(k1, k2, k3)
        return (xa if k1 * xa < k1 * xb else xb), body.radius_tail * dn2, body.radius_tail * dn3
    xs, rs = _stations(body)
    x, y, z, _ = lowest_profile_point(xs, rs, k1, k2, k3)
    return x, y, z


def sizes(body):
    """``L + R_max`` (scales a rotation to a surface speed) and the reach ``L/2 + |chi| + R_max``, a
    bound on any point's distance from the COM (as the cylinder's, with the larger radius)."""
    r = max(body.radius_tail, body.radius_nose)
    return body.length + r, 0.5 * body.length + abs(body.com_offset) + r


def equivalent_part(body, volume, x_c, eta):
    """Seed 000 section 4.1's equivalent body of a part: the axial interval whose volume is the
    part's and whose centroid is the part's (:func:`.revolution_geometry.equivalent_interval`); for
    equal radii the cylinder's (:func:`.geometry.equivalent_of_part`)."""
    if body.radius_tail == body.radius_nose:
        return equivalent_of_part(body.length, body.radius_tail, body.com_offset, volume, x_c, eta)
    xs, rs = _stations(body)
    ell, xa, xb = equivalent_interval(xs, rs, volume, x_c)
    return ell, xa, xb, eta


def surface_tractions(body, reference_paths, k1, k2, k3, d0, vbody, law, bank):
    """Seed 000 section 6 by the fast rule over the tilted lateral surface and the two caps
    (:func:`.revolution_sediment.profile_tractions`; for equal radii the cylinder's fast rule, bit
    for bit). ``reference_paths`` is not used: a profile has no reference quadrature."""
    xs, rs = _stations(body)
    return profile_tractions(xs, rs, k1, k2, k3, d0, vbody, law, bank)


def pore(body, k1, k2, k3, d0, zeta_tip, w_z, law, bank):
    """Seed 000 eq. (73) (:func:`.revolution_sediment.profile_pore_pressure`; for equal radii the
    cylinder's :func:`.sediment.pore.pore_pressure`)."""
    if body.radius_tail == body.radius_nose:
        return pore_pressure(
            body.length, body.radius_tail, body.com_offset, k1, k2, k3, d0, zeta_tip, w_z, law, bank
        )
    xs, rs = _stations(body)
    return profile_pore_pressure(xs, rs, k1, k2, k3, d0, zeta_tip, w_z, law, bank)


def strip_section(body):
    """The mean radius ``(r_t + r_n)/2`` and the length (the cylinder's ``(R, L)`` for equal radii);
    a frustum's strips are :func:`.revolution_fluid.profile_strip_forces` (module docstring)."""
    return 0.5 * (body.radius_tail + body.radius_nose), body.length


@kernel
def _added_mass_parts(body):
    """``(m_axial, m_transverse, x_m, I_m, V, x_v, strip_rot)`` per unit density: the BEM table's
    added masses (:func:`.added_mass.frustum_added_mass`), the centre of added mass ``x_m`` about the
    COM (body axis), the rotational added inertia ``I_m`` about it, the volume, its centroid and
    strip theory's rotational inertia about the centroid ``int pi r^2 (x - x_v)^2 dx``."""
    xs, rs = _stations(body)
    a0, a1, a2 = profile_strip_added_mass(xs, rs, xs[0], xs[1])
    x_v = a1 / a0
    strip_rot = a2 - a1 * x_v
    if body.radius_nose <= body.radius_tail:  # the top (smaller end) is the nose: +x
        m_a, m_t, m_c, m_r = frustum_added_mass(body.radius_tail, body.radius_nose, body.length)
        sgn = 1.0
    else:
        m_a, m_t, m_c, m_r = frustum_added_mass(body.radius_nose, body.radius_tail, body.length)
        sgn = -1.0
    shift = m_c / m_t
    return m_a, m_t, x_v + sgn * shift, m_r - m_c * shift, a0, x_v, strip_rot


def finite_added_mass(body):
    """``(k_t, k_a, k_r)``: the closed frustum's transverse and axial added mass as fractions of
    ``rho V`` and its rotational added inertia about the centre of added mass as a fraction of
    strip theory's about the centroid (the cylinder table's normalisation; for equal radii the
    cylinder's :func:`.added_mass.cylinder_added_mass`, bit for bit); the centre of added mass:
    :func:`added_mass_moments`."""
    if body.radius_tail == body.radius_nose:
        return cylinder_added_mass(body.length / (2.0 * body.radius_tail))
    m_a, m_t, _, i_m, v, _, strip_rot = _added_mass_parts(body)
    return m_t / v, m_a / v, i_m / strip_rot


@kernel
def added_mass_moments(body, a, b):
    """The finite body's added mass of the wetted interval ``[a, b]`` per unit density, as
    ``dynamics._added_mass`` forms the cylinder's: ``(a0, a1, a2, a11)``, the transverse added mass,
    its first and second moments about the COM along the axis and the axial added mass. Strip
    theory's moments of ``[a, b]`` (:func:`.revolution_fluid.profile_strip_added_mass`) scaled by
    the BEM factors of the whole body (``k_t``, ``k_a``; ``k_r`` about the centre of added mass,
    which lies ``x_m - x_v`` from the strip centroid, scaled by the wetted length fraction): the
    whole body's BEM added-mass matrix when ``[a, b]`` is the whole body."""
    xs, rs = _stations(body)
    m_a, m_t, x_m, i_m, v, x_v, strip_rot = _added_mass_parts(body)
    s0, s1, s2 = profile_strip_added_mass(xs, rs, a, b)
    if not (s0 > 0.0):
        return 0.0, 0.0, 0.0, 0.0
    frac = (b - a) / body.length
    centre = s1 / s0 + (x_m - x_v) * frac
    a0 = m_t / v * s0
    rot = i_m / strip_rot * (s2 - s1 * s1 / s0)
    return a0, a0 * centre, rot + a0 * centre * centre, m_a / v * s0


def crossflow_efficiency(body):
    """DATCOM's crossflow efficiency at the aspect ratio ``L / d_mean``, ``d_mean = r_t + r_n`` (for
    equal radii the cylinder's ``L/(2R)``: ``R + R == 2 R`` exactly)."""
    return _crossflow_efficiency(body.length / (body.radius_tail + body.radius_nose))


def strip_loads(body, model, rho, nu, a, b, ur1, ur2, ur3, w1, w2, w3, loads):
    """The fluid strips of ``[a, b]`` added to ``loads``, as ``dynamics.add_strip_forces`` adds the
    cylinder's: :func:`.revolution_fluid.profile_strip_forces` with the local section (``model`` =
    (impact35, R, L, drag_on, eta, roughness); the impact35 model has no frustum version and is
    refused for a frustum by the scenario's rules, R is unused)."""
    _, _, length, drag_on, eta, roughness = model
    xs, rs = _stations(body)
    h1, h2, h3, h4, h5, h6 = profile_strip_forces(
        rho, nu, xs, rs, length, a, b, ur1, ur2, ur3, w1, w2, w3, drag_on, eta, roughness
    )
    f1, f2, f3, m1, m2, m3 = loads
    return f1 + h1, f2 + h2, f3 + h3, m1 + h4, m2 + h5, m3 + h6


def added_mass(body, p, model, crossflow_model, wa, wb, aa, ab):
    """The wetted parts' added mass ``(a0, a1, a2, a11)`` about the COM, as ``dynamics._added_mass``
    forms the cylinder's: strip theory's moments of the local section ``C_M rho pi r(x)^2`` (seed
    001 eqs. (20)-(21)) with the axial ``(1 - munk_factor) a0`` (the ``munk_factor`` model), or the
    BEM factors of the closed frustum (:func:`added_mass_moments`, the ``viscous_crossflow`` model);
    ``numerics.added_mass_factor`` on every coefficient. Equal radii: the cylinder's own
    (``dynamics._added_mass``, whose ``model`` R is ``strip_section``'s mean radius, here the
    radius), bit for bit."""
    if body.radius_tail == body.radius_nose:
        return _one_radius_added_mass(body, p, model, crossflow_model, wa, wb, aa, ab)
    xs, rs = _stations(body)
    a0 = 0.0
    a1 = 0.0
    a2 = 0.0
    a11 = 0.0
    for k in range(2):
        lo = wa if k == 0 else aa
        hi = wb if k == 0 else ab
        rho = C_M * (p[P_RHO_WATER] if k == 0 else p[P_RHO_AIR])
        if hi > lo:
            if crossflow_model:
                f0, f1, f2, f11 = added_mass_moments(body, lo, hi)
                a0 += rho * f0
                a1 += rho * f1
                a2 += rho * f2
                a11 += rho * f11
            else:
                s0, s1, s2 = profile_strip_added_mass(xs, rs, lo, hi)
                a0 += rho * s0
                a1 += rho * s1
                a2 += rho * s2
    if not crossflow_model:
        a11 = (1.0 - p[P_MUNK]) * a0
    c = p[P_ADDED_MASS_FACTOR]
    return c * a0, c * a1, c * a2, c * a11


#: the protocol functions written here (the rest: module docstring)
GEOMETRY = (
    "cut",
    "extent",
    "burial",
    "volume",
    "ends",
    "reference_lengths",
    "lowest_offset",
    "deepest_point",
    "sizes",
    "cut_sliver",
)
#: the physics: with GEOMETRY, every function of the protocol (``bodies.PROTOCOL``)
PHYSICS = (
    "equivalent_part",
    "surface_tractions",
    "pore",
    "strip_section",
    "finite_added_mass",
    "crossflow_efficiency",
)
#: a prototype body of the class: its numba type selects the frustum's kernels (``shapes.Shape.marker``)
PROTOTYPE = Frustum(1.0, 0.5, 0.5, 0.0)

#: the fluid's hooks that dynamics calls when a shape module has them (the cylinder's default otherwise)
FLUID_HOOKS = ("strip_loads", "added_mass")

bodies.register(Frustum, sys.modules[__name__])
