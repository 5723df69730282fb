"""The solid frustum (truncated cone; a cone when one radius is 0, the cylinder when both are equal):
its **geometric** protocol functions, for the Manta-like mine of issue 36 (items 2-3).

Not a registered shape yet: the physics the protocol also asks for (the sediment's
``surface_tractions`` and ``pore`` law, the fluid strips' ``strip_section``, ``finite_added_mass``,
``crossflow_efficiency``, and ``equivalent_part``) are closed forms of the constant-radius cylinder
and have no frustum version, so :func:`mineburial.kernels.mine.bodies.register` would refuse this
module, and the drop's kernels cannot build a frustum. What is here is what the body's geometry
needs, by :mod:`.revolution_geometry` on the two stations (no allocation: the stations are tuples):
``cut``, ``extent``, ``burial``, ``volume``, ``ends``, ``reference_lengths``, ``lowest_offset``,
``deepest_point``, ``sizes``, under the protocol's signatures (tests/test_frustum.py).

A frustum of length ``length`` whose tail (``x = -L/2 - chi``) has radius ``radius_tail`` and nose
(``x = L/2 - chi``) ``radius_nose``; its COM sits ``com_offset`` (chi) behind its middle, as the
cylinder's (seed 000 eq. (42)).
"""

from typing import NamedTuple

from mineburial._numba import small_kernel
from mineburial.kernels.mine.bodies.revolution_geometry import (
    burial_profile,
    cut_profile,
    extent_profile,
    lowest_profile_point,
    volume_profile,
)


class Frustum(NamedTuple):
    """A solid frustum: length [m], tail and nose radii [m], COM offset ``chi`` [m]."""

    length: float
    radius_tail: float
    radius_nose: float
    com_offset: float


@small_kernel
def _stations(body):
    """(xs, rs): the tail and the nose about the COM and their radii, as tuples."""
    xt = -0.5 * body.length - body.com_offset
    xn = 0.5 * body.length - body.com_offset
    return (xt, xn), (body.radius_tail, body.radius_nose)


def cut(body, a_z, z_c, level):
    """The part below the plane (:func:`.revolution_geometry.cut_profile`)."""
    xs, rs = _stations(body)
    return cut_profile(xs, rs, a_z, z_c, level)


def extent(body, a_z, z_c):
    """Lowest and highest heights: at the end sections' rims (:func:`.revolution_geometry.extent_profile`)."""
    xs, rs = _stations(body)
    return extent_profile(xs, rs, a_z, z_c)


def burial(body, a_z, z_c, level):
    """The results table's burial measures (:func:`.revolution_geometry.burial_profile`)."""
    xs, rs = _stations(body)
    return burial_profile(xs, rs, a_z, z_c, level)


def volume(body):
    """``pi L (r_t^2 + r_t r_n + r_n^2)/3`` and the axial position of its centroid about the COM."""
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
    xs, rs = _stations(body)
    return lowest_profile_point(xs, rs, k1, k2, k3)[3]


def deepest_point(body, k1, k2, k3):
    """A lowest point (body frame): on the rim of the end section that reaches lowest."""
    xs, rs = _stations(body)
    x, y, z, _ = lowest_profile_point(xs, rs, k1, k2, k3)
    return x, y, z


def sizes(body):
    """``L + R_max`` (scales a rotation to a surface speed) and the reach ``L/2 + |chi| + R_max``, a
    bound on any point's distance from the COM (as the cylinder's, with the larger radius)."""
    r = max(body.radius_tail, body.radius_nose)
    return body.length + r, 0.5 * body.length + abs(body.com_offset) + r


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
)
