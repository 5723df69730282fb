"""The mine's body behind a small protocol, resolved at compile time on the body's type.

A body is a ``typing.NamedTuple`` of floats (its shape's dimensions in the body frame, M-frame of
``docs/design.md``: axis ``i_M`` through the centre of mass). Its numba type (``NamedUniTuple``)
carries the class (``instance_class``), so each protocol function below is an ``overload`` that
looks the class up in :data:`SHAPES` and compiles that shape's implementation into the caller: no
run-time branch, no first-class function, cached on disk with the caller (not inlined at numba's IR
level: ``inline="always"`` cost ~5 s more CPU of cold compile, docs/design.md "Body protocol"), as
``core.system_rhs`` and ``stepper._fixed_step`` dispatch on types.

The protocol (what a shape module defines, as plain functions of ``body`` that numba compiles;
heights ``z`` are E-frame, ``a_z = i_M . k``, ``level`` a horizontal plane):

* ``cut(body, a_z, z_c, level)`` -> ``(volume, x_c, eta_c, lateral, nose_end, tail_end)``: the part
  below the plane, its centroid ``x_c i_M + eta_c e_down`` about the COM and its wetted areas;
* ``extent(body, a_z, z_c)`` -> ``(z_min, z_max)``;
* ``burial(body, a_z, z_c, level)`` -> ``(pct_volume, pct_height, pct_area, height_proud,
  penetration)`` (the results table's burial measures);
* ``equivalent_part(body, V, x_c, eta)`` -> ``(l, x_a, x_b, eta)``: the equivalent body of a part
  (seed 000 section 4.1) that the strip forces of the fluid integrate over;
* ``volume(body)`` -> ``(volume, x_centroid)``: the whole body's volume and the axial position of
  its centroid about the COM; ``ends(body)`` -> ``(x_tail, x_nose)``, the axial span about the COM;
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
* the fluid forces' strip theory (kernels/dynamics.py, seeds 000 and 001) integrates a body of
  constant section along its axis: ``strip_section(body)`` -> ``(radius, length)`` of that
  section and the reference length, ``finite_added_mass(body)`` -> ``(k_t, k_a, k_r)``, the
  finite body's added-mass factors on the strip values, and ``crossflow_efficiency(body)``, the
  viscous-crossflow model's eta (both from kernels/added_mass.py's tables of the closed cylinder).

Adding a shape: a module here with its NamedTuple class and these functions, which registers
itself (:func:`register`; docs/design.md, "Adding a body shape"). This package imports no shape,
so the sediment package can use the protocol while the cylinder's module uses the sediment rules.
"""

from numba.core import types
from numba.extending import overload

from mineburial._numba import JIT_OPTIONS

#: body class -> the module that implements the protocol for it (filled by :func:`register`)
SHAPES = {}

#: the protocol's functions, in the order of the module docstring
PROTOCOL = (
    "cut",
    "extent",
    "burial",
    "equivalent_part",
    "volume",
    "ends",
    "lowest_offset",
    "deepest_point",
    "sizes",
    "surface_tractions",
    "pore",
    "strip_section",
    "finite_added_mass",
    "crossflow_efficiency",
)

__all__ = ["SHAPES", "PROTOCOL", "register", "by_type", *PROTOCOL]


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


def cut(body, a_z, z_c, level):
    """Protocol function (module docstring); compiled code only."""
    raise NotImplementedError("compiled code only")


@overload(cut, jit_options=JIT_OPTIONS)
def _cut(body, a_z, z_c, level):
    return _impl("cut", body, a_z, z_c, level)


def extent(body, a_z, z_c):
    """Protocol function (module docstring); compiled code only."""
    raise NotImplementedError("compiled code only")


@overload(extent, jit_options=JIT_OPTIONS)
def _extent(body, a_z, z_c):
    return _impl("extent", body, a_z, z_c)


def burial(body, a_z, z_c, level):
    """Protocol function (module docstring); compiled code only."""
    raise NotImplementedError("compiled code only")


@overload(burial, jit_options=JIT_OPTIONS)
def _burial(body, a_z, z_c, level):
    return _impl("burial", body, a_z, z_c, level)


def equivalent_part(body, volume, x_c, eta):
    """Protocol function (module docstring); compiled code only."""
    raise NotImplementedError("compiled code only")


@overload(equivalent_part, jit_options=JIT_OPTIONS)
def _equivalent_part(body, volume, x_c, eta):
    return _impl("equivalent_part", body, volume, x_c, eta)


def volume(body):
    """Protocol function (module docstring); compiled code only."""
    raise NotImplementedError("compiled code only")


@overload(volume, jit_options=JIT_OPTIONS)
def _volume(body):
    return _impl("volume", body)


def ends(body):
    """Protocol function (module docstring); compiled code only."""
    raise NotImplementedError("compiled code only")


@overload(ends, jit_options=JIT_OPTIONS)
def _ends(body):
    return _impl("ends", body)


def lowest_offset(body, k1, k2, k3):
    """Protocol function (module docstring); compiled code only."""
    raise NotImplementedError("compiled code only")


@overload(lowest_offset, jit_options=JIT_OPTIONS)
def _lowest_offset(body, k1, k2, k3):
    return _impl("lowest_offset", body, k1, k2, k3)


def deepest_point(body, k1, k2, k3):
    """Protocol function (module docstring); compiled code only."""
    raise NotImplementedError("compiled code only")


@overload(deepest_point, jit_options=JIT_OPTIONS)
def _deepest_point(body, k1, k2, k3):
    return _impl("deepest_point", body, k1, k2, k3)


def sizes(body):
    """Protocol function (module docstring); compiled code only."""
    raise NotImplementedError("compiled code only")


@overload(sizes, jit_options=JIT_OPTIONS)
def _sizes(body):
    return _impl("sizes", body)


def surface_tractions(body, reference_paths, k1, k2, k3, d0, vbody, law, bank):
    """Protocol function (module docstring); compiled code only."""
    raise NotImplementedError("compiled code only")


@overload(surface_tractions, jit_options=JIT_OPTIONS)
def _surface_tractions(body, reference_paths, k1, k2, k3, d0, vbody, law, bank):
    return _impl("surface_tractions", body, reference_paths, k1, k2, k3, d0, vbody, law, bank)


def pore(body, k1, k2, k3, d0, zeta_tip, w_z, law, bank):
    """Protocol function (module docstring); compiled code only."""
    raise NotImplementedError("compiled code only")


@overload(pore, jit_options=JIT_OPTIONS)
def _pore(body, k1, k2, k3, d0, zeta_tip, w_z, law, bank):
    return _impl("pore", body, k1, k2, k3, d0, zeta_tip, w_z, law, bank)


def strip_section(body):
    """Protocol function (module docstring); compiled code only."""
    raise NotImplementedError("compiled code only")


@overload(strip_section, jit_options=JIT_OPTIONS)
def _strip_section(body):
    return _impl("strip_section", body)


def finite_added_mass(body):
    """Protocol function (module docstring); compiled code only."""
    raise NotImplementedError("compiled code only")


@overload(finite_added_mass, jit_options=JIT_OPTIONS)
def _finite_added_mass(body):
    return _impl("finite_added_mass", body)


def crossflow_efficiency(body):
    """Protocol function (module docstring); compiled code only."""
    raise NotImplementedError("compiled code only")


@overload(crossflow_efficiency, jit_options=JIT_OPTIONS)
def _crossflow_efficiency(body):
    return _impl("crossflow_efficiency", body)
