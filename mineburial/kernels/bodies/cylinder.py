"""The right circular cylinder, the mine's first body (seed 000 section 4).

A solid cylinder of length ``length`` and radius ``radius`` whose centre of mass sits ``com_offset``
(``chi``, seed 000 eq. (42)) behind its middle: in the M-frame it spans
``x in [-L/2 - chi, L/2 - chi]``. The protocol functions (:mod:`mineburial.kernels.bodies`) call the
cylinder's closed forms in :mod:`mineburial.kernels.geometry`, its embedded-surface integrals in
:mod:`mineburial.kernels.sediment` (the fast rule, :mod:`~.sediment.fast`; the reference
quadrature, :mod:`~.sediment.reference`; the pore pressure, :mod:`~.sediment.pore`) and the closed
cylinder's added-mass and crossflow tables (:mod:`mineburial.kernels.added_mass`).
"""

import math
import sys
from typing import NamedTuple

from numba.core import types
from numba.extending import overload

from mineburial._numba import JIT_OPTIONS, kernel
from mineburial.kernels import bodies
from mineburial.kernels.added_mass import crossflow_efficiency as cylinder_crossflow_efficiency
from mineburial.kernels.added_mass import cylinder_added_mass
from mineburial.kernels.geometry import (
    PI,
    burial_measures,
    cut_cylinder,
    e_down_body,
    equivalent_of_part,
    vertical_extent,
)
from mineburial.kernels.layout import P_CHI, P_DIAMETER, P_LENGTH
from mineburial.kernels.sediment import QUADRATURE_REFERENCE
from mineburial.kernels.sediment.fast import fast_tractions
from mineburial.kernels.sediment.laws import LAW_QUADRATURE
from mineburial.kernels.sediment.pore import pore_pressure
from mineburial.kernels.sediment.reference import reference_tractions


class Cylinder(NamedTuple):
    """A solid right circular cylinder: length [m], radius [m], COM offset ``chi`` [m]."""

    length: float
    radius: float
    com_offset: float


@kernel
def from_params(p):
    """The drop's cylinder from its parameter vector (``kernels/layout.py``)."""
    return Cylinder(p[P_LENGTH], 0.5 * p[P_DIAMETER], p[P_CHI])


def cut(body, a_z, z_c, level):
    return cut_cylinder(body.length, body.radius, body.com_offset, a_z, z_c, level)


def extent(body, a_z, z_c):
    return vertical_extent(body.length, body.radius, body.com_offset, a_z, z_c)


def burial(body, a_z, z_c, level):
    return burial_measures(body.length, body.radius, body.com_offset, a_z, z_c, level)


def equivalent_part(body, volume, x_c, eta):
    return equivalent_of_part(body.length, body.radius, body.com_offset, volume, x_c, eta)


def volume(body):
    return PI * body.radius * body.radius * body.length, -body.com_offset


def ends(body):
    return -0.5 * body.length - body.com_offset, 0.5 * body.length - body.com_offset


def lowest_offset(body, k1, k2, k3):
    # the lower end section's centre, then the rim's drop sqrt(1 - a_z^2) R below it
    xa, xb = bodies.ends(body)
    return min(k1 * xa, k1 * xb) - body.radius * math.sqrt(k2 * k2 + k3 * k3)


def deepest_point(body, k1, k2, k3):
    # the end of the axis that is lower, on the rim towards e_down
    xa, xb = bodies.ends(body)
    _, dn2, dn3 = e_down_body(k1, k2, k3)
    return (xa if k1 * xa < k1 * xb else xb), body.radius * dn2, body.radius * dn3


def sizes(body):
    return body.length + body.radius, 0.5 * body.length + abs(body.com_offset) + body.radius


def surface_tractions(body, reference_paths, k1, k2, k3, d0, vbody, law, bank):
    return _rule(reference_paths, body.length, body.radius, body.com_offset, k1, k2, k3, d0, vbody, law, bank)


def pore(body, k1, k2, k3, d0, zeta_tip, w_z, law, bank):
    return pore_pressure(body.length, body.radius, body.com_offset, k1, k2, k3, d0, zeta_tip, w_z, law, bank)


def strip_section(body):
    return body.radius, body.length


def finite_added_mass(body):
    return cylinder_added_mass(body.length / (2.0 * body.radius))


def crossflow_efficiency(body):
    return cylinder_crossflow_efficiency(body.length / (2.0 * body.radius))


def _rule(reference_paths, L, R, chi, c20, c21, c22, d0, vbody, law, bank):
    """The tractions integrated over the embedded surface by the rule the law names.

    Compiled only through the overload below, which looks at the *type* of
    ``reference_paths`` (``law[LAW_REFERENCE_PATHS]``, see :func:`.pack_law`): for
    ``None`` it is the fast rule alone, so that the reference quadrature (a third of the
    engine's compile time) is not compiled at all; otherwise the rule is chosen per drop
    by the quadrature code.
    """
    raise NotImplementedError("compiled code only")


@overload(_rule, jit_options=JIT_OPTIONS)
def _rule_impl(reference_paths, L, R, chi, c20, c21, c22, d0, vbody, law, bank):
    if isinstance(reference_paths, (types.NoneType, types.Omitted)):

        def fast_only(reference_paths, L, R, chi, c20, c21, c22, d0, vbody, law, bank):
            return fast_tractions(L, R, chi, c20, c21, c22, d0, vbody, law, bank)

        return fast_only

    def by_name(reference_paths, L, R, chi, c20, c21, c22, d0, vbody, law, bank):
        if law[LAW_QUADRATURE] == QUADRATURE_REFERENCE:
            return reference_tractions(L, R, chi, c20, c21, c22, d0, vbody, law, bank)
        return fast_tractions(L, R, chi, c20, c21, c22, d0, vbody, law, bank)

    return by_name


bodies.register(Cylinder, sys.modules[__name__])
