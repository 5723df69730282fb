"""Planar multibody descriptions: the data that the Kane core of :mod:`mineburial.kernels.multibody` runs.

A system (the restraining system of seed 004, a moored mine, a test pendulum) is a :class:`Description` --
bodies joined by pins in a tree -- plus its own forces, events and summary. This module builds and
validates the description; the kernels never see a Python object, only the tuple :meth:`Description.arrays`.

* :class:`Description` -- frozen dataclass of the flat arrays (see the kernel module for their meaning),
  validated on construction: a bad value raises :class:`DescriptionError` naming the field, the body, the
  value and what is allowed.
* :func:`rigid_mass_matrix`, :func:`segment_mass_matrix` -- body-frame generalised mass of a rigid body and
  of a slender segment (rod, cable element, chain link) with its added mass (seed 004 eq. (46)).
* :func:`chain` -- N links laid out end to end from a start point, optionally pinned to a fixed point
  (the root is then a fixed, massless *ground* body): the building block of cables, chains and pendulums.
* :func:`integrate` -- the Python face of the kernel driver (method by name, settings checked) for a
  :class:`System` (its right-hand side and event kernels, reached by static dispatch).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from mineburial.kernels import multibody as _mb
from mineburial.kernels.core import System
from mineburial.resources import memory_refusal

__all__ = [
    "DescriptionError",
    "Description",
    "rigid_mass_matrix",
    "segment_mass_matrix",
    "chain",
    "integrate",
    "IntegrationResult",
    "System",
]


class DescriptionError(ValueError):
    """Invalid multibody description or integration setting; the message names the field."""


def _as_float_array(name, value, shape):
    try:
        arr = np.array(value, dtype=np.float64)
    except (TypeError, ValueError) as exc:
        raise DescriptionError(f"{name} must be an array of numbers, got {value!r}") from exc
    if arr.shape != shape:
        raise DescriptionError(f"{name} must have shape {shape}, got {arr.shape}")
    bad = np.argwhere(~np.isfinite(arr))
    if bad.size:
        idx = tuple(int(i) for i in bad[0])
        raise DescriptionError(f"{name}{list(idx)} = {arr[idx]} is not finite")
    return arr


@dataclass(frozen=True, eq=False)
class Description:
    """A planar tree of rigid bodies joined by pins (arrays as in :mod:`mineburial.kernels.multibody`).

    parent:           int[N], -1 for body 0 only, parent[k] < k
    joint_on_parent:  (N, 2) body-frame pin position from the parent's centroid, m (row 0 unused)
    joint_on_body:    (N, 2) body-frame pin position from body k's centroid, m (row 0 unused)
    mass_matrix:      (N, 3, 3) body-frame generalised mass at the centroid (a, b, theta): kg, kg m, kg m^2
    root_free:        3 flags: the root's x, z, theta are free (1) or locked at root_pose (0)
    root_pose:        the root's x, z (m) and theta (rad)
    names:            optional body names, used in messages and output
    """

    parent: np.ndarray
    joint_on_parent: np.ndarray
    joint_on_body: np.ndarray
    mass_matrix: np.ndarray
    root_free: np.ndarray
    root_pose: np.ndarray
    names: tuple = ()

    def __post_init__(self):
        try:
            parent = np.array(self.parent)
        except (TypeError, ValueError) as exc:  # pragma: no cover - numpy accepts almost anything
            raise DescriptionError(f"parent must be an array of integers, got {self.parent!r}") from exc
        if parent.ndim != 1 or parent.size == 0:
            raise DescriptionError(f"parent must be a non-empty 1-D array, got shape {parent.shape}")
        if not (np.issubdtype(parent.dtype, np.integer) or np.all(parent == np.round(parent))):
            raise DescriptionError(f"parent must hold integers, got {parent.tolist()}")
        parent = parent.astype(np.int64)
        n = parent.size
        if parent[0] != -1:
            raise DescriptionError(f"parent[0] = {parent[0]}: body 0 is the root and must have parent -1")
        for k in range(1, n):
            if not 0 <= parent[k] < k:
                raise DescriptionError(
                    f"parent[{k}] = {parent[k]} is out of order: each body's parent must be an earlier body, "
                    f"0 <= parent[k] < k"
                )
        jp = _as_float_array("joint_on_parent", self.joint_on_parent, (n, 2))
        jb = _as_float_array("joint_on_body", self.joint_on_body, (n, 2))
        mm = _as_float_array("mass_matrix", self.mass_matrix, (n, 3, 3))
        rf = np.array(self.root_free)
        if rf.shape != (3,) or not np.all(np.isin(rf, (0, 1))):
            raise DescriptionError(f"root_free must be three flags 0 or 1 (x, z, theta), got {rf.tolist()}")
        rf = rf.astype(np.int64)
        rp = _as_float_array("root_pose", self.root_pose, (3,))
        if n == 1 and not rf.any():
            raise DescriptionError(
                "the description has no degree of freedom: one body with root_free = 0 0 0"
            )
        for k in range(n):
            m = mm[k]
            if not np.allclose(m, m.T, rtol=1e-12, atol=0.0):
                raise DescriptionError(
                    f"mass_matrix[{k}] ({self._name(k)}) must be symmetric, got {m.tolist()}"
                )
            for i, what in enumerate(("mass along a", "mass along b", "moment of inertia")):
                if m[i, i] < 0.0:
                    raise DescriptionError(
                        f"mass_matrix[{k}][{i}][{i}] = {m[i, i]} ({self._name(k)}, {what}) must be >= 0"
                    )
            if np.linalg.eigvalsh(m).min() < -1e-12 * max(1.0, np.abs(m).max()):
                raise DescriptionError(
                    f"mass_matrix[{k}] ({self._name(k)}) must be positive semi-definite, got {m.tolist()}"
                )
        if self.names and len(self.names) != n:
            raise DescriptionError(f"names must name all {n} bodies, got {len(self.names)}")
        for name, value in (
            ("parent", parent),
            ("joint_on_parent", jp),
            ("joint_on_body", jb),
            ("mass_matrix", mm),
            ("root_free", rf),
            ("root_pose", rp),
        ):
            value = np.ascontiguousarray(value)
            value.setflags(write=False)
            object.__setattr__(self, name, value)
        object.__setattr__(self, "names", tuple(self.names))
        # the generalised mass must be positive definite (every degree of freedom carries inertia)
        q = np.zeros(self.n_dof)
        a, _ = _mb.generalised_mass_and_force(q, q, np.zeros((n, 3)), self.arrays())
        if np.linalg.eigvalsh(a).min() <= 1e-14 * max(1.0, np.abs(a).max()):
            raise DescriptionError(
                "the generalised mass matrix is singular: some degree of freedom moves no mass "
                "(a massless free body, or a free root with zero mass or inertia)"
            )

    def _name(self, k):
        return self.names[k] if self.names else f"body {k}"

    @property
    def n_bodies(self) -> int:
        return int(self.parent.size)

    @property
    def n_dof(self) -> int:
        return int(self.root_free.sum()) + self.n_bodies - 1

    def arrays(self) -> tuple:
        """The tuple ``desc`` that every kernel of :mod:`mineburial.kernels.multibody` takes."""
        return (
            self.parent,
            self.joint_on_parent,
            self.joint_on_body,
            self.mass_matrix,
            self.root_free,
            self.root_pose,
        )

    def coordinates(self, angles, root=None) -> np.ndarray:
        """Generalised coordinates q from the absolute angles of bodies 1..N-1 (rad) and, where the root is
        free, its pose (x, z, theta) (default: root_pose)."""
        angles = np.asarray(angles, dtype=np.float64).reshape(-1)
        if angles.size != self.n_bodies - 1:
            raise DescriptionError(
                f"angles must give the {self.n_bodies - 1} angles of bodies 1..N-1, got {angles.size}"
            )
        root = self.root_pose if root is None else _as_float_array("root", root, (3,))
        return np.concatenate([root[self.root_free == 1], angles])

    def initial_state(self, q, u=None) -> np.ndarray:
        """State y = concat(q, u) (u = 0 by default)."""
        q = _as_float_array("q", q, (self.n_dof,))
        u = np.zeros(self.n_dof) if u is None else _as_float_array("u", u, (self.n_dof,))
        return np.concatenate([q, u])


def rigid_mass_matrix(mass, inertia):
    """diag(m, m, I) of a rigid body (kg, kg m^2; both >= 0)."""
    for name, value in (("mass", mass), ("inertia", inertia)):
        if not (math.isfinite(value) and value >= 0.0):
            raise DescriptionError(f"{name} = {value} must be finite and >= 0")
    return np.diag([float(mass), float(mass), float(inertia)])


def segment_mass_matrix(mass, length, radius=0.0, added_mass_coefficient=0.0, water_density=1025.0):
    """Body-frame generalised mass of a slender segment along its a axis (seed 004 eqs. (18), (46)):
    diag(m, m + m_a, m L^2/12 + m_a L^2/12) with the added mass m_a = rho pi r^2 L C_M on the normal only
    (eq. (46): F^A = pi rho D^2 C_M dU/dt L / 4, T^A = -pi rho D^2 C_M d(omega)/dt L^3 / 48). The rod's own
    axial inertia term m R^2/2 of eq. (18) turns about the segment axis, which the plane does not have."""
    for name, value, low in (
        ("mass", mass, 0.0),
        ("length", length, 0.0),
        ("radius", radius, 0.0),
        ("added_mass_coefficient", added_mass_coefficient, 0.0),
        ("water_density", water_density, 0.0),
    ):
        if not (math.isfinite(value) and value >= low):
            raise DescriptionError(f"{name} = {value} must be finite and >= {low}")
    if length == 0.0:
        raise DescriptionError("length = 0 m: a segment must have a positive length")
    ma = water_density * math.pi * radius**2 * length * added_mass_coefficient
    return np.diag([float(mass), mass + ma, (mass + ma) * length**2 / 12.0])


def chain(n_links, link_length, mass_matrix, angles, start=(0.0, 0.0), pinned=True, names=None):
    """A chain of ``n_links`` straight links laid out end to end from ``start``.

    Each link has its pins at its ends (a = -L/2 and +L/2 on its axis); ``link_length`` is one length (m) or
    one per link; link i points along ``angles[i]`` (rad, from +x toward +z; one value: all links).
    ``mass_matrix`` is one link's (3, 3) body-frame mass or one per link.
    ``pinned=True``: body 0 is a fixed massless ground at ``start`` and the first link turns about it
    (N = n_links + 1 bodies); ``pinned=False``: body 0 is the first link, free in x, z, theta.
    Returns (description, q0): the description and the generalised coordinates of the layout.
    """
    if not (isinstance(n_links, (int, np.integer)) and n_links >= 1):
        raise DescriptionError(f"n_links = {n_links!r} must be an integer >= 1")
    lengths = np.asarray(link_length, dtype=np.float64).reshape(-1)
    if lengths.size == 1:
        lengths = np.full(n_links, lengths[0])
    if lengths.size != n_links:
        raise DescriptionError(
            f"link_length must give one length or one per link ({n_links}), got {lengths.size}"
        )
    for i, length in enumerate(lengths):
        if not (math.isfinite(length) and length > 0.0):
            raise DescriptionError(f"link_length[{i}] = {length} m must be finite and > 0")
    angles = np.asarray(angles, dtype=np.float64).reshape(-1)
    if angles.size == 1:
        angles = np.full(n_links, angles[0])
    if angles.size != n_links:
        raise DescriptionError(f"angles must give one angle per link ({n_links}), got {angles.size}")
    if not np.all(np.isfinite(angles)):
        raise DescriptionError(f"angles = {angles.tolist()} must be finite")
    mm = np.asarray(mass_matrix, dtype=np.float64)
    if mm.shape == (3, 3):
        mm = np.broadcast_to(mm, (n_links, 3, 3))
    if mm.shape != (n_links, 3, 3):
        raise DescriptionError(f"mass_matrix must have shape (3, 3) or ({n_links}, 3, 3), got {mm.shape}")
    x0, z0 = (float(v) for v in start)
    half = np.concatenate([[0.0] if pinned else [], 0.5 * lengths])  # half length of each body
    n = n_links + 1 if pinned else n_links
    off = 1 if pinned else 0
    parent = np.arange(-1, n - 1)
    jp = np.zeros((n, 2))
    jb = np.zeros((n, 2))
    masses = np.zeros((n, 3, 3))
    masses[off:] = mm
    for k in range(1, n):
        jp[k] = (half[k - 1], 0.0)
        jb[k] = (-half[k], 0.0)
    if pinned:
        root_free = (0, 0, 0)
        root_pose = (x0, z0, 0.0)
        q0 = angles.copy()
    else:
        root_free = (1, 1, 1)
        c, s = math.cos(angles[0]), math.sin(angles[0])
        root_pose = (x0 + half[0] * c, z0 + half[0] * s, angles[0])
        q0 = np.concatenate([root_pose, angles[1:]])
    if names is None:
        names = (("ground",) if pinned else ()) + tuple(f"link {i + 1}" for i in range(n_links))
    desc = Description(parent, jp, jb, masses, np.array(root_free), np.array(root_pose), names=tuple(names))
    return desc, q0


def record_bytes(duration, record_dt, values_per_record):
    """Bytes of the records :func:`integrate` preallocates: ``duration / record_dt + 2`` rows of
    ``values_per_record`` float64 (inf where the count overflows)."""
    rows = duration / record_dt + 2.0
    return rows * values_per_record * 8.0


@dataclass(frozen=True)
class IntegrationResult:
    """Records of :func:`integrate`: times (n,), states (n, len(y0)), status code and name, end time."""

    times: np.ndarray
    states: np.ndarray
    status: int
    t_stop: float

    @property
    def status_name(self) -> str:
        return _mb.STATUS_NAMES[self.status]


def integrate(
    system,
    y0,
    t0,
    t_end,
    params,
    method="dopri5",
    dt=2e-3,
    rtol=1e-8,
    atol=1e-10,
    record_dt=None,
    max_steps=_mb.MAX_STEPS,
    jacobian_columns=None,
):
    """Integrate a system with :func:`mineburial.kernels.multibody.integrate`, checking the settings first.

    ``system`` is a :class:`System` (its right-hand side ``rhs(t, y, params, dy)`` and event
    ``event(t, y, params) -> float``, numba-compiled functions, reached by static dispatch);
    ``method`` is one of ``"dopri5"`` (adaptive, first step ``dt``), ``"rk4"`` (fixed step ``dt``) or
    ``"ros34pw2"`` (Rosenbrock-W, adaptive, first step ``dt``, for stiff systems; its Jacobian is
    differenced in the state components ``jacobian_columns``, default all: a mechanical system whose
    stiffness is in its speeds names their slots, fewer right-hand sides per Jacobian);
    ``record_dt`` defaults to ``dt``; ``max_steps`` is the step budget (a run that spends it ends as
    numerical_failure). The records are preallocated: a ``record_dt`` whose records would take more than
    half of this machine's memory is refused before the run."""
    if method not in _mb.METHODS:
        raise DescriptionError(f"method = {method!r} is not known; the methods are {', '.join(_mb.METHODS)}")
    record_dt = dt if record_dt is None else record_dt
    for name, value in (("dt", dt), ("rtol", rtol), ("atol", atol), ("record_dt", record_dt)):
        if not (math.isfinite(value) and value > 0.0):
            raise DescriptionError(f"{name} = {value} must be finite and > 0")
    if not (math.isfinite(t0) and math.isfinite(t_end) and t_end > t0):
        raise DescriptionError(f"t_end = {t_end} s must be finite and later than t0 = {t0} s")
    if isinstance(max_steps, bool) or not isinstance(max_steps, (int, np.integer)) or max_steps < 1:
        raise DescriptionError(f"max_steps = {max_steps!r} must be an integer >= 1")
    y0 = np.ascontiguousarray(y0, dtype=np.float64)
    if not np.all(np.isfinite(y0)):
        raise DescriptionError(f"y0 = {y0.tolist()} must be finite")
    refusal = memory_refusal(
        record_bytes(t_end - t0, record_dt, y0.size),
        f"record_dt = {record_dt:g} s ({(t_end - t0) / record_dt:.3g} states over {t_end - t0:g} s)",
        "give a larger record_dt",
        share=0.5,
    )
    if refusal is not None:
        raise DescriptionError(refusal)
    cols = np.arange(y0.size) if jacobian_columns is None else np.asarray(jacobian_columns)
    if cols.ndim != 1 or cols.dtype.kind not in "iu" or not np.all((cols >= 0) & (cols < y0.size)):
        raise DescriptionError(
            f"jacobian_columns = {cols.tolist()} must be indices of the state (0 .. {y0.size - 1})"
        )
    if np.unique(cols).size != cols.size:
        raise DescriptionError(f"jacobian_columns = {cols.tolist()} must not repeat an index")
    cols = np.ascontiguousarray(cols, dtype=np.int64)
    if not isinstance(system, System):
        raise DescriptionError(f"system = {system!r} must be a mineburial.kernels.core.System")
    times, states, status, t_stop = _mb.integrate(
        system,
        y0,
        float(t0),
        float(t_end),
        params,
        method,
        float(dt),
        float(rtol),
        float(atol),
        float(record_dt),
        int(max_steps),
        cols,
    )
    return IntegrationResult(times, states, int(status), float(t_stop))
