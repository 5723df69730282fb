"""The mine's body on the Python side: what the scenario, the ensembles and the checks need of
the drop's shape without compiling it, and the one place that names that shape.

The compiled protocol (:mod:`mineburial.kernels.mine.bodies`) serves the kernels; this module
serves the Python around them, and stays light: it imports numpy, the parameter layout, the
closed forms of :mod:`mineburial.kernels.mine.geometry` and :class:`mineburial.schema.Rule` (all of
which ``config`` imported before), never a shape's kernel module, which imports the sediment
kernels (~43 ms more on every import of the configuration, ``python -X importtime``,
docs/design.md "Body protocol").

A shape (:class:`Shape`) gives, from its dimensions ``dims`` (a mapping from the scenario field
path to a value: a float, or an array with one value per drop; :meth:`Shape.dims_of_params`
reads them from packed parameter rows):

* ``fields``: the scenario fields of its dimensions (the placement rule reads them), and
  ``inertia_fields``: those its default inertia depends on besides ``mine.mass``;
* ``volume(dims)``, ``centroid(dims)`` (the axial position of the uniform body's centroid about
  the COM, M-frame), ``inertia(mass, dims)`` -> ``(J_axial, J_transverse)`` and
  ``inertia_tensor(mass, dims)`` (M-frame, ``diag(J_axial, J_transverse, J_transverse)`` for a
  body of revolution): the default mass properties;
* ``reference_lengths(dims)`` -> ``(diameter, length)``: the sizes that the laws written for a
  cylinder take (the sediment law's width, the scour laws' D, the drag laws' aspect ratio);
  the compiled protocol's ``reference_lengths(body)`` is the same for the kernels;
* ``lowest_point(dims, a_z, z)``: the height of the lowest point of the body whose COM is at
  height ``z`` and whose axis has E-frame vertical component ``a_z``, by the kernel that the
  stepper's seabed-contact event uses (the placement rule: the mine starts above the seabed);
* ``kernel_module``: the module of its compiled protocol, whose ``from_params(p)`` builds the
  drop's body in the kernels (``dynamics.drop_body``);
* ``rules``: the relations between its own fields (the cylinder's: the COM inside the body,
  ``|chi| < L/2``), which ``config.RULES`` checks per scenario and over parameter rows.

:data:`DROP_SHAPE` is the drop's shape: the one place that names it, on both sides
(``dynamics.drop_body`` is ``DROP_SHAPE.kernel().from_params``). :class:`CylinderShape` is the
cylinder's Python side; :class:`ProfileShape` a body of revolution with a piecewise-linear radius
profile (:mod:`.revolution_geometry`), the Python side a cone will need, not yet a drop's shape (it
has no compiled protocol and no scenario fields; issue 36 item 2).
"""

import importlib
import math

import numpy as np

from mineburial.kernels.mine.geometry import vertical_extent
from mineburial.kernels.mine.layout import INDEX, MINE_SHAPES, N_PARAMS, P_SHAPE
from mineburial.schema import Rule


def _has_shape(v, name):
    """Where ``v["mine.shape"]`` (a name, or the codes of packed rows) is the shape ``name``; a
    rule of one shape holds for the others; without ``mine.shape``, the default shape."""
    code = v.get("mine.shape", DEFAULT_SHAPE.name)
    if isinstance(code, str):
        return np.asarray(code == name)
    return np.asarray(code) == MINE_SHAPES.index(name)


class Shape:
    """A body shape's Python side (the module docstring lists what a shape gives)."""

    name: str = ""
    fields: tuple = ()
    inertia_fields: tuple = ()
    kernel_module: str = ""
    #: the relations between its own fields (:class:`mineburial.schema.Rule`; ``config.RULES`` holds them)
    rules: tuple = ()

    def marker(self):
        """A prototype body of the shape's class, whose numba type selects the shape's compiled
        protocol (``stepper.reference_paths``): the kernel module's ``PROTOTYPE``; None for the
        default shape (its kernels take no prototype, as before)."""
        return None if self is DEFAULT_SHAPE else self.kernel().PROTOTYPE

    def kernel(self):
        """The module of the shape's compiled protocol (imported on first use: it imports the
        sediment kernels, which the configuration does not need)."""
        return importlib.import_module(self.kernel_module)

    def dims_of_params(self, P):
        """The shape's dimensions from packed parameter rows ``P`` (..., N_PARAMS): one array
        per field, by the field's slot (``layout.INDEX``)."""
        P = np.asarray(P)
        return {f: P[..., INDEX[f]] for f in self.fields}

    def inertia_tensor(self, mass, dims):
        """The default inertia tensor about the COM in the M-frame (axis ``i_M`` first): a body of
        revolution's ``diag(J_axial, J_transverse, J_transverse)``, shape ``(..., 3, 3)``."""
        j1, j2 = self.inertia(mass, dims)
        j1, j2 = np.broadcast_arrays(np.asarray(j1, dtype=np.float64), np.asarray(j2, dtype=np.float64))
        out = np.zeros(j1.shape + (3, 3))
        out[..., 0, 0] = j1
        out[..., 1, 1] = j2
        out[..., 2, 2] = j2
        return out

    def lowest_point(self, dims, a_z, z):
        """Height of the lowest point (arrays broadcast), by the shape's ``_extent_row``."""
        args = np.broadcast_arrays(
            *(np.asarray(x, dtype=np.float64) for x in (*(dims[f] for f in self.fields), a_z, z))
        )
        rows = zip(*(x.ravel().tolist() for x in args))
        return np.array([self._extent_row(*row)[0] for row in rows], dtype=np.float64).reshape(args[0].shape)


class CylinderShape(Shape):
    """The solid right circular cylinder of :mod:`mineburial.kernels.mine.bodies.cylinder`:
    length ``mine.length``, diameter ``mine.diameter``, its COM ``mine.com_offset`` (chi, seed
    000 eq. (42)) behind its middle."""

    name = "cylinder"
    fields = ("mine.length", "mine.diameter", "mine.com_offset")
    inertia_fields = ("mine.length", "mine.diameter")
    kernel_module = "mineburial.kernels.mine.bodies.cylinder"
    rules = (
        Rule(
            "|mine.com_offset| < mine.length/2",
            ("mine.com_offset", "mine.length", "mine.shape"),
            lambda v: ~_has_shape(v, "cylinder") | (np.abs(v["mine.com_offset"]) < v["mine.length"] / 2),
            note="|chi| < length/2: the COM lies inside the body",
            bounds=lambda v: (-v["mine.length"] / 2.0, v["mine.length"] / 2.0, None),
        ),
    )

    @staticmethod
    def volume(dims):
        """``pi R^2 L``, R = d/2 (as ``config.Mine.volume`` has always computed it)."""
        r = dims["mine.diameter"] / 2.0
        return math.pi * r**2 * dims["mine.length"]

    @staticmethod
    def centroid(dims):
        """The uniform cylinder's centroid is its middle, ``-chi`` about the COM (seed 000 eq. (42))."""
        return -dims["mine.com_offset"]

    @staticmethod
    def inertia(mass, dims):
        """(J1, J2) of a uniform solid cylinder about its centre: m R^2/2 about the axis and
        m (3 R^2 + L^2)/12 about a transverse axis. Scalars or numpy arrays.

        The default inertia (``config.Mine`` and the ensembles that vary the mass or size; was
        ``config.uniform_cylinder_inertia``, the same arithmetic). ``length ** 2`` is kept as
        written: a Python float squares with ``pow`` and an array with ``x * x``, which is what
        each caller has always computed.
        """
        r = dims["mine.diameter"] / 2.0
        length = dims["mine.length"]
        return mass * r * r / 2.0, mass * (3.0 * r * r + length**2) / 12.0

    @staticmethod
    def reference_lengths(dims):
        """The diameter and the length themselves."""
        return dims["mine.diameter"], dims["mine.length"]

    #: the body's attitude in the scour stage: lying on its side (docs/scour.md, Rest attitude)
    scour_attitude = "lying"

    @staticmethod
    def scour_geometry(dims):
        """``(standing, diameter, height, flank_angle)`` for the scour stage's laws: the lying
        cylinder (``standing`` 0) of its diameter, whose height on the bed is the diameter; no flank."""
        d = dims["mine.diameter"]
        return 0.0, d, d, 0.0

    @staticmethod
    def _extent_row(length, diameter, com_offset, a_z, z):
        """(z_min, z_max) of one cylinder (:func:`.geometry.vertical_extent`, the stepper's event)."""
        return vertical_extent(length, 0.5 * diameter, com_offset, a_z, z)


class ProfileShape(Shape):
    """A solid body of revolution with a piecewise-linear radius profile (issue 36 item 2): its
    dimensions give the stations ``xs`` (about the COM, tail first) and the radii ``rs`` through
    ``profile(dims) -> (xs, rs)``; volume, centroid, inertia and the lowest point are
    :mod:`.revolution_geometry`'s (compiled on first use). Not the drop's shape yet: it has no
    compiled protocol (``kernel_module`` empty) and no scenario fields of its own; a subclass or an
    instance gives ``fields``, ``inertia_fields`` and ``profile``.

    ``reference_lengths``: the largest diameter and the length between the end stations, the sizes
    that the laws written for a cylinder would take for it (a choice to revisit with those laws:
    the sediment law's width, the scour laws' D)."""

    def __init__(self, name, fields, inertia_fields, profile):
        self.name = name
        self.fields = tuple(fields)
        self.inertia_fields = tuple(inertia_fields)
        self.profile = profile

    def _each(self, dims, fn, *extra):
        """``fn(xs, rs, *extra_row)`` for each drop of ``dims`` (arrays broadcast); an array of the
        results (a trailing axis when ``fn`` returns a tuple), a scalar (tuple) for scalar input."""
        args = np.broadcast_arrays(
            *(np.asarray(x, dtype=np.float64) for x in (*(dims[f] for f in self.fields), *extra))
        )
        shape = args[0].shape
        k = len(self.fields)
        out = []
        for row in zip(*(a.ravel().tolist() for a in args)):
            xs, rs = self.profile(dict(zip(self.fields, row[:k])))
            out.append(fn(np.asarray(xs, dtype=np.float64), np.asarray(rs, dtype=np.float64), *row[k:]))
        result = np.array(out, dtype=np.float64)
        if shape == ():
            return tuple(result[0]) if result.ndim > 1 else float(result[0])
        return result.reshape(shape + result.shape[1:])

    def volume(self, dims):
        """The frusta's volumes summed (:func:`.revolution_geometry.volume_profile`)."""
        return self._each(dims, lambda xs, rs: _revolution().volume_profile(xs, rs)[0])

    def centroid(self, dims):
        """The uniform body's centroid on the axis, about the COM."""
        return self._each(dims, lambda xs, rs: _revolution().volume_profile(xs, rs)[1])

    def inertia(self, mass, dims):
        """(J_axial, J_transverse) of the uniform body about its centroid
        (:func:`.revolution_geometry.inertia_profile`)."""
        both = self._each(dims, lambda xs, rs, m: _revolution().inertia_profile(xs, rs, m), mass)
        return (both[0], both[1]) if isinstance(both, tuple) else (both[..., 0], both[..., 1])

    def reference_lengths(self, dims):
        """The largest diameter and the length between the end stations."""
        both = self._each(dims, lambda xs, rs: (2.0 * float(np.max(rs)), float(xs[-1] - xs[0])))
        return (both[0], both[1]) if isinstance(both, tuple) else (both[..., 0], both[..., 1])

    def lowest_point(self, dims, a_z, z):
        """Height of the lowest point (:func:`.revolution_geometry.extent_profile`)."""
        return np.asarray(
            self._each(dims, lambda xs, rs, a, zc: _revolution().extent_profile(xs, rs, a, zc)[0], a_z, z)
        )


def _revolution():
    """:mod:`.revolution_geometry`, imported on first use (the configuration, which imports this
    module, does not need it)."""
    # local import: the profile's kernels, only for a ProfileShape (import cost of config)
    from mineburial.kernels.mine.bodies import revolution_geometry

    return revolution_geometry


def frustum_centroid_offset(length, r_base, r_top):
    """The uniform frustum's centroid about the middle of its length, towards the top:
    ``L (r_t^2 - r_b^2) / (4 (r_b^2 + r_b r_t + r_t^2))`` (the centroid lies ``L (r_b^2 + 2 r_b r_t +
    3 r_t^2) / (4 (r_b^2 + r_b r_t + r_t^2))`` above the base; exactly 0 for equal radii). Scalars or
    numpy arrays; :func:`.frustum.from_params` computes the same expression in compiled code."""
    sum_sq = r_base * r_base + r_base * r_top + r_top * r_top
    return length * (r_top * r_top - r_base * r_base) / (4.0 * sum_sq)


class FrustumShape(ProfileShape):
    """The solid frustum of :mod:`mineburial.kernels.mine.bodies.frustum`: base (the tail)
    diameter ``mine.diameter``, top (the nose) ``mine.top_ratio`` of it, ``mine.length`` apart;
    its COM ``mine.com_offset`` (chi) from the centre of volume towards the top, as the
    cylinder's (chi = 0: the uniform body). The profile's two stations about the COM are the
    kernel body's (``from_params``): the tail at ``-L/2 - chi_m``, the nose at ``L/2 - chi_m``,
    ``chi_m = chi + frustum_centroid_offset`` the COM's offset from the middle of the length.

    ``reference_lengths``: the base diameter and the length (``ProfileShape``'s largest diameter)."""

    kernel_module = "mineburial.kernels.mine.bodies.frustum"
    rules = (
        Rule(
            "the COM inside the frustum: -h_c < mine.com_offset < mine.length - h_c",
            ("mine.com_offset", "mine.length", "mine.diameter", "mine.top_ratio", "mine.shape"),
            lambda v: ~_has_shape(v, "frustum") | (np.abs(_frustum_chi_mid(v)) < v["mine.length"] / 2),
            note="h_c the centroid's height above the base: the COM lies inside the body",
            bounds=lambda v: (
                -v["mine.length"] / 2 - _frustum_chi_mid({**v, "mine.com_offset": 0.0}),
                v["mine.length"] / 2 - _frustum_chi_mid({**v, "mine.com_offset": 0.0}),
                False,
            ),
        ),
    )

    def __init__(self):
        super().__init__(
            "frustum",
            ("mine.length", "mine.diameter", "mine.com_offset", "mine.top_ratio"),
            ("mine.length", "mine.diameter", "mine.top_ratio"),
            self._profile,
        )

    def _as_cylinder(self, dims, profile_value, cylinder_value):
        """``profile_value`` but where the radii are equal (``mine.top_ratio == 1``) the cylinder's
        closed form ``cylinder_value`` (a frustum of equal radii is the cylinder bit for bit, as its
        kernels are)."""
        equal = np.asarray(dims["mine.top_ratio"]) == 1.0
        if not np.any(equal):
            return profile_value
        if np.ndim(equal) == 0:
            return cylinder_value
        return np.where(equal, cylinder_value, profile_value)

    def volume(self, dims):
        """The frustum's volume (the cylinder's ``pi R^2 L`` for equal radii)."""
        return self._as_cylinder(dims, super().volume(dims), CylinderShape.volume(dims))

    def centroid(self, dims):
        """The uniform frustum's centroid about the COM (the cylinder's ``-chi`` for equal radii)."""
        return self._as_cylinder(dims, super().centroid(dims), CylinderShape.centroid(dims))

    def inertia(self, mass, dims):
        """(J_axial, J_transverse) of the uniform frustum about its centroid (the cylinder's closed
        forms for equal radii)."""
        j1, j2 = super().inertia(mass, dims)
        c1, c2 = CylinderShape.inertia(mass, dims)
        return self._as_cylinder(dims, j1, c1), self._as_cylinder(dims, j2, c2)

    #: the body's attitude in the scour stage: standing on its base, axis vertical (docs/scour.md,
    #: Standing body; docs/bodies_revolution.md, "The scour stage and a frustum")
    scour_attitude = "standing"

    @staticmethod
    def scour_geometry(dims):
        """``(standing, diameter, height, flank_angle)`` for the scour stage's laws: a short body
        standing on its base (``standing`` 1) of the base diameter, its height the length, its flank
        inclined ``atan((R_base - R_top) / L)`` from the vertical (the half-angle of the cone)."""
        d = np.asarray(dims["mine.diameter"], dtype=np.float64)
        length = np.asarray(dims["mine.length"], dtype=np.float64)
        flank = np.arctan(0.5 * d * (1.0 - np.asarray(dims["mine.top_ratio"], dtype=np.float64)) / length)
        return 1.0, d, length, flank

    @staticmethod
    def _profile(dims):
        length = dims["mine.length"]
        r_base = 0.5 * dims["mine.diameter"]
        r_top = r_base * dims["mine.top_ratio"]
        chi_m = dims["mine.com_offset"] + frustum_centroid_offset(length, r_base, r_top)
        return (-0.5 * length - chi_m, 0.5 * length - chi_m), (r_base, r_top)


def _frustum_chi_mid(v):
    """The frustum's COM offset from the middle of its length (rows or one scenario)."""
    r_base = 0.5 * np.asarray(v["mine.diameter"], dtype=np.float64)
    shift = frustum_centroid_offset(v["mine.length"], r_base, r_base * v["mine.top_ratio"])
    return v["mine.com_offset"] + shift


CYLINDER = CylinderShape()
FRUSTUM = FrustumShape()

#: the body shapes by name, in the order of ``scenario_fields.MINE_SHAPES`` (``mine.shape``'s codes)
SHAPES = {"cylinder": CYLINDER, "frustum": FRUSTUM}

#: the default shape (``mine.shape``'s default): the cylinder of seed 000
DEFAULT_SHAPE = CYLINDER


def shape_named(name):
    """The shape of ``mine.shape`` = ``name`` (a name or its code)."""
    if not isinstance(name, str):
        name = MINE_SHAPES[int(name)]
    return SHAPES[name]


def shape_of_params(P):
    """The one shape of the packed parameter rows ``P`` (their ``mine.shape`` slot); a batch
    mixes no shapes (the shape is the compiled body's type: one per scenario)."""
    codes = np.unique(np.asarray(P, dtype=np.float64).reshape(-1, N_PARAMS)[:, P_SHAPE])
    if codes.size > 1:
        names = ", ".join(MINE_SHAPES[int(c)] for c in codes)
        raise ValueError(f"mine.shape: one batch of drops mixes the shapes {names}; run one shape at a time")
    return shape_named(codes[0]) if codes.size else DEFAULT_SHAPE


def shapes_of(v):
    """``(shape, mask)`` for each shape of the values ``v`` (``v["mine.shape"]``: a name, or codes
    for rows); ``mask`` where the rows have that shape (a boolean array of ``v``'s rows' shape)."""
    code = v.get("mine.shape", 0.0)
    if isinstance(code, str):
        code = float(MINE_SHAPES.index(code))
    code = np.asarray(code, dtype=np.float64)
    return [(shape, code == i) for i, shape in enumerate(SHAPES.values())]


#: the drop's shape when a scenario names none: kept for the callers that took the one shape
DROP_SHAPE = DEFAULT_SHAPE
