"""The mine's body behind a small protocol, resolved at compile time on the body's type.

A body is a ``typing.NamedTuple`` of floats (its shape's dimensions in the body frame, M-frame of
``docs/design.md``: axis ``i_M`` through the centre of mass). Its numba type (``NamedUniTuple``)
carries the class (``instance_class``), so each protocol function below is an ``overload`` that
looks the class up in :data:`SHAPES` and compiles that shape's implementation into the caller: no
run-time branch, no first-class function, cached on disk with the caller (not inlined at numba's IR
level: ``inline="always"`` cost ~5 s more CPU of cold compile, docs/design.md "Body protocol"), as
``core.system_rhs`` and ``core.fixed_trial`` dispatch on types.

The protocol (what a shape module defines, as plain functions of ``body`` that numba compiles;
heights ``z`` are E-frame, ``a_z = i_M . k``, ``level`` a horizontal plane):

* ``cut(body, a_z, z_c, level)`` -> ``(volume, x_c, eta_c, lateral, nose_end, tail_end)``: the part
  below the plane, its centroid ``x_c i_M + eta_c e_down`` about the COM and its wetted areas;
* ``cut_sliver(body, a_z, z_c, level)`` -> ``(kind, bound, x_empty, reach_x, reach_e)``: the part
  below a plane at or near the body's lowest point as far as it is known without cutting: kind 0
  empty (``cut`` would give ``(0, x_empty, 0, ...)``), kind 1 a sliver of volume at most ``bound``
  with ``|x_c| <= reach_x / 2`` and ``|eta_c| <= reach_e / 2``, kind 2 unknown (cut it); the
  overburden leaves out a cut that cannot change a bit (kernels/mine/overburden.py);
* ``extent(body, a_z, z_c)`` -> ``(z_min, z_max)``;
* ``burial(body, a_z, z_c, level)`` -> ``(pct_volume, pct_height, pct_area, height_proud,
  penetration)`` (the results table's burial measures);
* ``equivalent_part(body, V, x_c, eta)`` -> ``(l, x_a, x_b, eta)``: the equivalent body of a part
  (seed 000 section 4.1) that the strip forces of the fluid integrate over;
* ``volume(body)`` -> ``(volume, x_centroid)``: the whole body's volume and the axial position of
  its centroid about the COM (the stepper's test of a mine lighter than the water uses it);
  ``ends(body)`` -> ``(x_tail, x_nose)``, the axial span about the COM;
* ``reference_lengths(body)`` -> ``(diameter, length)``: the sizes that the laws written for a
  cylinder take (the sediment law's width D, ``sediment.pack_law``); the Python side's
  ``shapes.Shape.reference_lengths`` gives the same from the scenario's fields;
* ``lowest_offset(body, k1, k2, k3)``: height of the lowest point above the COM for the E-frame
  vertical ``k`` in body components; ``deepest_point(body, k1, k2, k3)``: a lowest point (body
  frame) about which the body topples; ``sizes(body)`` -> ``(extent_scale, reach)``: the length
  that scales a rotation's speed to a surface speed, and a bound on the distance of any body point
  from the COM;
* ``surface_tractions(body, reference_paths, k1, k2, k3, d0, vbody, law, bank)``: the sediment's
  force (body frame) and torque on the embedded surface by the rule the law names (the fast rule,
  or the reference quadrature when ``reference_paths`` is not None), ``d0`` the seabed's height
  above the COM; ``pore(body, k1, k2, k3, d0, zeta_tip, w_z, law, bank)``: the pore-water
  pressure of seed 000 eq. (73);
* the fluid forces' strip theory (kernels/mine/dynamics.py, seeds 000 and 001) integrates a body of
  constant section along its axis: ``strip_section(body)`` -> ``(radius, length)`` of that
  section and the reference length, ``finite_added_mass(body)`` -> ``(k_t, k_a, k_r)``, the
  finite body's added-mass factors on the strip values, and ``crossflow_efficiency(body)``, the
  viscous-crossflow model's eta (both from kernels/mine/added_mass.py's tables of the closed cylinder).

Adding a shape: a module here with its NamedTuple class, ``from_params(p)`` and these functions,
which registers itself (:func:`register`), and its Python side in :mod:`.shapes` (volume, mass
properties, reference lengths, placement), where ``DROP_SHAPE`` names the drop's shape
(docs/design.md, "Adding a body shape"). This package imports no shape, so the sediment package
can use the protocol while the cylinder's module uses the sediment rules.
"""

import inspect

from numba.core import types
from numba.extending import overload

from mineburial._numba import JIT_OPTIONS

#: body class -> the module that implements the protocol for it (filled by :func:`register`)
SHAPES = {}

#: protocol function name -> its argument names (a shape's implementation takes the same names:
#: numba checks them when it compiles the implementation into a caller), filled by :func:`_declare`
SIGNATURES = {}


def register(cls, module):
    """Make the NamedTuple class ``cls`` a body whose protocol ``module`` implements (each
    shape module calls this for itself; the kernels that build a body import that module)."""
    missing = [name for name in PROTOCOL if not callable(getattr(module, name, None))]
    if missing:
        raise TypeError(f"body module {module.__name__} lacks protocol functions {missing}")
    SHAPES[cls] = module


def by_type(chooser):
    """Mark a shape's protocol function as a chooser: called with the numba types of the
    arguments, it returns the implementation (as an ``overload`` template does), so that a shape
    picks among compiled paths without a compile unit of its own between them and the caller."""
    chooser.by_type = True
    return chooser


def _impl(name, body, *args):
    """The shape's implementation of protocol function ``name`` for the numba types ``body,
    *args`` (None, so that numba reports no match, when ``body`` is not a registered body)."""
    if isinstance(body, (types.NamedUniTuple, types.NamedTuple)) and body.instance_class in SHAPES:
        fn = getattr(SHAPES[body.instance_class], name)
        return fn(body, *args) if getattr(fn, "by_type", False) else fn
    return None


def _declare(name, arguments):
    """Protocol function ``name(arguments)`` (comma-separated names, ``body`` first): a stub for
    compiled code, resolved by an ``overload`` on the body's type (:func:`_impl`).

    The stub and the overload's typing function take ``*args`` but carry the explicit signature
    (``__signature__``), which numba reads to match the implementation's argument names; this
    is the overload that was written out by hand for each function before (the same template,
    the same compiled code)."""
    signature = inspect.Signature(
        [inspect.Parameter(arg, inspect.Parameter.POSITIONAL_OR_KEYWORD) for arg in arguments.split(", ")]
    )

    def stub(*args, **kws):
        raise NotImplementedError(f"bodies.{name} is for compiled code only")

    def typer(*args, **kws):
        return _impl(name, *signature.bind(*args, **kws).args)

    for fn, prefix in ((stub, ""), (typer, "_overload_")):
        fn.__name__ = fn.__qualname__ = prefix + name
        fn.__signature__ = signature
    stub.__doc__ = f"Protocol function {name}({arguments}) (module docstring); compiled code only."
    overload(stub, jit_options=JIT_OPTIONS)(typer)
    SIGNATURES[name] = arguments
    return stub


cut = _declare("cut", "body, a_z, z_c, level")
cut_sliver = _declare("cut_sliver", "body, a_z, z_c, level")
extent = _declare("extent", "body, a_z, z_c")
burial = _declare("burial", "body, a_z, z_c, level")
equivalent_part = _declare("equivalent_part", "body, volume, x_c, eta")
volume = _declare("volume", "body")
ends = _declare("ends", "body")
reference_lengths = _declare("reference_lengths", "body")
lowest_offset = _declare("lowest_offset", "body, k1, k2, k3")
deepest_point = _declare("deepest_point", "body, k1, k2, k3")
sizes = _declare("sizes", "body")
surface_tractions = _declare("surface_tractions", "body, reference_paths, k1, k2, k3, d0, vbody, law, bank")
pore = _declare("pore", "body, k1, k2, k3, d0, zeta_tip, w_z, law, bank")
strip_section = _declare("strip_section", "body")
finite_added_mass = _declare("finite_added_mass", "body")
crossflow_efficiency = _declare("crossflow_efficiency", "body")

#: the protocol's functions, in the order of the module docstring
PROTOCOL = tuple(SIGNATURES)

__all__ = ["SHAPES", "PROTOCOL", "SIGNATURES", "register", "by_type", *PROTOCOL]
