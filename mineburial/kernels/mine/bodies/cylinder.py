"""The right circular cylinder, the mine's first body (seed 000 section 4).

A solid cylinder of length ``length`` and radius ``radius`` whose centre of mass sits ``com_offset``
(``chi``, seed 000 eq. (42)) behind its middle: in the M-frame it spans
``x in [-L/2 - chi, L/2 - chi]``. The protocol functions (:mod:`mineburial.kernels.mine.bodies`) call the
cylinder's closed forms in :mod:`mineburial.kernels.mine.geometry`, its embedded-surface integrals in
:mod:`mineburial.kernels.mine.sediment` (the fast rule, :mod:`~.sediment.fast`; the reference
quadrature, :mod:`~.sediment.reference`; the pore pressure, :mod:`~.sediment.pore`) and the closed
cylinder's added-mass and crossflow tables (:mod:`mineburial.kernels.mine.added_mass`).
"""

import math
import sys
from typing import NamedTuple

from numba.core import types

from mineburial._numba import kernel
from mineburial.kernels.mine import bodies
from mineburial.kernels.mine.added_mass import crossflow_efficiency as cylinder_crossflow_efficiency
from mineburial.kernels.mine.added_mass import cylinder_added_mass
from mineburial.kernels.mine.geometry import (
    PI,
    burial_measures,
    cut_cylinder,
    cut_cylinder_moments,
    cut_cylinder_sliver,
    e_down_body,
    equivalent_of_part,
    vertical_extent,
)
from mineburial.kernels.mine.layout import P_CHI, P_DIAMETER, P_LENGTH
from mineburial.kernels.mine.sediment import QUADRATURE_REFERENCE
from mineburial.kernels.mine.sediment.fast import fast_tractions
from mineburial.kernels.mine.sediment.laws import LAW_QUADRATURE
from mineburial.kernels.mine.sediment.pore import pore_pressure
from mineburial.kernels.mine.sediment.reference import reference_tractions


class Cylinder(NamedTuple):
    """A solid right circular cylinder: length [m], radius [m], COM offset ``chi`` [m]."""

    length: float
    radius: float
    com_offset: float


@kernel
def from_params(p):
    """The drop's cylinder from its parameter vector (``kernels/mine/layout.py``)."""
    return Cylinder(p[P_LENGTH], 0.5 * p[P_DIAMETER], p[P_CHI])


def cut(body, a_z, z_c, level):
    """Seed 000 eqs. (25)-(33), re-derived (:func:`.geometry.cut_cylinder`)."""
    return cut_cylinder(body.length, body.radius, body.com_offset, a_z, z_c, level)


def cut_moments(body, a_z, z_c, level):
    """The first three values of :func:`cut` (volume and centroid), bit for bit, without the
    wetted areas (:func:`.geometry.cut_cylinder_moments`): an optional hook of a shape that the
    right-hand side takes where it has one (kernels/mine/dynamics.py, ``body_cut_moments``)."""
    return cut_cylinder_moments(body.length, body.radius, body.com_offset, a_z, z_c, level)


def cut_sliver(body, a_z, z_c, level):
    """The cut below a plane at or near the lowest point, without cutting
    (:func:`.geometry.cut_cylinder_sliver`), with the reach of its centroid (twice the bounds on
    ``|x_c|``, ``|eta_c|``)."""
    L, R, chi = body.length, body.radius, body.com_offset
    kind, bound, x_empty = cut_cylinder_sliver(L, R, chi, a_z, z_c, level)
    return kind, bound, x_empty, 2.0 * (L + abs(chi)), 2.0 * R


def extent(body, a_z, z_c):
    """End sections at ``z_c + a_z x``, rims ``+- R sqrt(1 - a_z^2)`` (:func:`.geometry.vertical_extent`)."""
    return vertical_extent(body.length, body.radius, body.com_offset, a_z, z_c)


def burial(body, a_z, z_c, level):
    """The results table's burial measures (:func:`.geometry.burial_measures`)."""
    return burial_measures(body.length, body.radius, body.com_offset, a_z, z_c, level)


def equivalent_part(body, volume, x_c, eta):
    """Seed 000 section 4.1's equivalent cylinder (:func:`.geometry.equivalent_of_part`)."""
    return equivalent_of_part(body.length, body.radius, body.com_offset, volume, x_c, eta)


def volume(body):
    """``pi R^2 L``; the centroid of a uniform cylinder is its middle, ``-chi`` (seed 000 eq. (42))."""
    return PI * body.radius * body.radius * body.length, -body.com_offset


def ends(body):
    """Tail and nose at ``x = -L/2 - chi, L/2 - chi`` (seed 000 eq. (42))."""
    return -0.5 * body.length - body.com_offset, 0.5 * body.length - body.com_offset


def reference_lengths(body):
    """The diameter ``2R`` (exactly the parameter's ``mine.diameter``: halved and doubled) and ``L``."""
    return 2.0 * body.radius, body.length


def lowest_offset(body, k1, k2, k3):
    """The lower end section's centre, then its rim ``R sqrt(k2^2 + k3^2) = R sqrt(1 - a_z^2)`` below."""
    xa, xb = bodies.ends(body)
    return min(k1 * xa, k1 * xb) - body.radius * math.sqrt(k2 * k2 + k3 * k3)


def deepest_point(body, k1, k2, k3):
    """The lower end of the axis, on the rim towards ``e_down`` (:func:`.geometry.e_down_body`)."""
    xa, xb = bodies.ends(body)
    _, dn2, dn3 = e_down_body(k1, k2, k3)
    return (xa if k1 * xa < k1 * xb else xb), body.radius * dn2, body.radius * dn3


def sizes(body):
    """``L + R`` (scales a rotation to a surface speed) and the reach ``L/2 + |chi| + R``."""
    return body.length + body.radius, 0.5 * body.length + abs(body.com_offset) + body.radius


def pore(body, k1, k2, k3, d0, zeta_tip, w_z, law, bank):
    """Seed 000 eq. (73) (:func:`.sediment.pore.pore_pressure`)."""
    return pore_pressure(body.length, body.radius, body.com_offset, k1, k2, k3, d0, zeta_tip, w_z, law, bank)


def strip_section(body):
    """A constant circular section of radius R along the length L (seeds 000 and 001 strip theory)."""
    return body.radius, body.length


def finite_added_mass(body):
    """The closed cylinder's BEM factors at aspect ratio L/(2R) (:func:`.added_mass.cylinder_added_mass`)."""
    return cylinder_added_mass(body.length / (2.0 * body.radius))


def crossflow_efficiency(body):
    """DATCOM's crossflow efficiency at aspect ratio L/(2R) (:func:`.added_mass.crossflow_efficiency`)."""
    return cylinder_crossflow_efficiency(body.length / (2.0 * body.radius))


@bodies.by_type
def surface_tractions(body, reference_paths, k1, k2, k3, d0, vbody, law, bank):
    """Seed 000 section 6 over the lateral surface and end caps, by the rule the law names.

    Chosen on the *type* of ``reference_paths`` (``law[LAW_REFERENCE_PATHS]``, see
    :func:`.pack_law`): for ``None`` the fast rule alone (:mod:`.sediment.fast`), so that the
    reference quadrature (:mod:`.sediment.reference`, a third of the engine's compile time) is not
    compiled at all; otherwise the rule is chosen per drop by the quadrature code.
    """
    if isinstance(reference_paths, (types.NoneType, types.Omitted)):

        def fast_only(body, reference_paths, k1, k2, k3, d0, vbody, law, bank):
            L, R, chi = body
            return fast_tractions(L, R, chi, k1, k2, k3, d0, vbody, law, bank)

        return fast_only

    def by_name(body, reference_paths, k1, k2, k3, d0, vbody, law, bank):
        L, R, chi = body
        if law[LAW_QUADRATURE] == QUADRATURE_REFERENCE:
            return reference_tractions(L, R, chi, k1, k2, k3, d0, vbody, law, bank)
        return fast_tractions(L, R, chi, k1, k2, k3, d0, vbody, law, bank)

    return by_name


bodies.register(Cylinder, sys.modules[__name__])
