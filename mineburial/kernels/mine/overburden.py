"""Geostatic (overburden) force of the sediment on the embedded part of the mine.

The effective overburden pressure sigma'(zeta) = int_0^zeta (rho_s - rho_w) g dzeta'
(seed 000 eq. (68) with the water's share removed: the water pressure is already
in the buoyancy of the whole submerged volume) acting on every embedded surface
element integrates, by the divergence theorem, to a volume integral over the
embedded part (sigma' vanishes on the seabed plane, which closes the surface):

    F = g int_emb (rho_s(zeta) - rho_w) dV  k,

an upward "sediment buoyancy" - Archimedes with the sediment's density. The embedded
part is cut into horizontal slices by planes (the body protocol's ``cut``, :mod:`.bodies`: each slice's
volume and centroid exactly), each slice acting at its centroid. Two rules
(``numerics.overburden_quadrature``, ``layout.OVERBURDEN_QUADRATURE_NAMES``):

``reference`` (:func:`_exact`): a slice boundary at every tabulated depth inside the
  body, so that the density is linear within each slice and int rho dV = V rho(zeta_c)
  with zeta_c the slice's centroid depth: exact for the force (and for the torque when
  the density is uniform within each slice); a linear profile is one slice. Its cost is
  the number of table depths within the penetration (~5,000 for a centimetre core), so
  beyond :data:`REFERENCE_DEPTHS` of them it takes :func:`_bounded` with
  :data:`REFERENCE_SLICES` slices (issue 34: 8e-7 of the force from the slicing at every
  depth on a rough 20,000-row core, docs/notes/sediment.md).
``fast`` (the default): the reference rule while at most :data:`EXACT_DEPTHS` table
  depths lie inside the embedded span (every analytic profile and every short table:
  bit-identical to it), else :func:`_bounded`: :data:`SLICES` equal slices of the
  embedded span whatever the table's length (docs/notes/sediment.md, "The overburden
  of a long table").

:func:`_bounded` is compiled only for a batch that may need it, like the reference paths
(:func:`.stepper.reference_paths`, whose ``None`` or ``True`` rides in the law's
``LAW_REFERENCE_PATHS`` slot): :func:`with_long_tables` makes it ``True`` when some drop has a
table longer than :data:`EXACT_DEPTHS` depths; with ``None`` the reference rule alone is
compiled (docs/design.md, compile time).
"""

import math

import numpy as np
from numba import types
from numba.extending import overload

from mineburial._numba import JIT_OPTIONS, kernel, small_kernel
from mineburial.kernels.mine import bodies
from mineburial.kernels.mine.environment import bracket, interpolate_row, last_point
from mineburial.kernels.mine.layout import (
    N_PARAMS,
    P_OB_QUADRATURE,
    P_SED_PROFILE,
    P_SED_RHO,
    P_SED_RHO_GRAD,
)
from mineburial.kernels.mine.sediment.laws import COLUMN_OVERBURDEN, LAW_REFERENCE_PATHS, sediment_properties

#: codes of ``numerics.overburden_quadrature`` (``layout.OVERBURDEN_QUADRATURE_NAMES``)
OB_FAST = 0
OB_REFERENCE = 1
#: the fast rule slices at the table's depths while at most this many lie inside the
#: embedded span (the reference rule's cost: one cut per depth); beyond, :data:`SLICES`
#: equal slices, so that the cost is bounded by about EXACT_DEPTHS + 1 cuts of the body
EXACT_DEPTHS = 12
#: slices of the bounded rule (:func:`_bounded`)
SLICES = 12
#: the reference rule slices at the table's depths while at most this many lie inside the
#: embedded span, else it takes the bounded rule with :data:`REFERENCE_SLICES` slices: its cost
#: is bounded by about 257 cuts of the body whatever the table's rows (issue 34)
REFERENCE_DEPTHS = 256
REFERENCE_SLICES = 256


@kernel
def _density(zeta, p, bank):
    row = int(p[P_SED_PROFILE])
    if row < 0:
        return p[P_SED_RHO] + p[P_SED_RHO_GRAD] * zeta
    return interpolate_row(bank, row, 1, zeta)


@small_kernel
def _points_below(bank, row, x, last, strict):
    """Number of tabulated depths of bank row ``row`` below ``x`` (``< x`` when
    ``strict``, else ``<= x``): O(1) on a drop's own bank (``environment.bracket``)."""
    d0 = bank[row, 0, 0]
    if d0 > x or (strict and d0 == x) or not (x == x):
        return 0
    dl = bank[row, 0, last]
    if dl < x or (not strict and dl == x):
        return last + 1
    lo, _ = bracket(bank, row, x, last, strict)
    return lo + 1


@kernel
def depths_inside(bank, row, depth_max):
    """Tabulated depths strictly between the seabed and ``depth_max``: the number of
    slices the reference rule adds (its cost), found without scanning the table."""
    last = last_point(bank, row)
    n = _points_below(bank, row, depth_max, last, True) - _points_below(bank, row, 0.0, last, False)
    return max(n, 0)


@kernel
def overburden_force(body, a_z, z_c, seabed_z, z_lo, rho_w, g, p, bank, law):
    """(F, F*x, F*eta): upward force [N] of the effective overburden and its first
    moments about the COM in the body frame (x along the axis, eta along e_down):
    the torque is (F*x i_M + F*eta e_down) x k. The rule: ``p[P_OB_QUADRATURE]``; ``law``
    (:func:`.laws.pack_law`): its ``LAW_REFERENCE_PATHS`` slot decides whether the bounded
    rule is compiled (:func:`with_long_tables`)."""
    if seabed_z - z_lo <= 0.0:  # nothing embedded (overburden_below's test)
        return 0.0, 0.0, 0.0
    v, x, e, _, _, _ = bodies.cut(body, a_z, z_c, seabed_z)
    return overburden_below(body, a_z, z_c, seabed_z, z_lo, rho_w, g, p, bank, law, (v, x, e))


@kernel
def overburden_below(body, a_z, z_c, seabed_z, z_lo, rho_w, g, p, bank, law, below):
    """:func:`overburden_force` given ``below = (V, x_c, eta_c)``, the body's part below the
    seabed (``bodies.cut(body, a_z, z_c, seabed_z)``, which the right-hand side has cut
    already): the top cut of the slices, not cut again (the same values, bit for bit)."""
    depth_max = seabed_z - z_lo  # deepest embedded point below the seabed
    if depth_max <= 0.0:
        return 0.0, 0.0, 0.0
    return _rule(law[LAW_REFERENCE_PATHS], body, a_z, z_c, seabed_z, depth_max, rho_w, g, p, bank, below)


def with_long_tables(paths, params, sediment_bank):
    """``paths`` (:func:`.stepper.reference_paths` of the drops whose parameter vectors are the
    rows of ``params``), or ``True`` when one of them may take the bounded rule: its overburden
    quadrature ``fast`` and its sediment table with more than :data:`EXACT_DEPTHS` depths below
    the seabed (:func:`depths_inside` counts no more), or ``reference`` and more than
    :data:`REFERENCE_DEPTHS`. The bounded rule is then compiled with
    the reference paths: a run's self-check (systems/mine/accuracy.py) compiles those anyway, and a
    third type of ``paths`` would compile the whole drop once more (docs/design.md)."""
    if isinstance(paths, tuple):  # (paths, a shape's prototype body): stepper.reference_paths
        return (with_long_tables(paths[0], params, sediment_bank), paths[1])
    if paths is not None:
        return paths
    params = np.asarray(params, dtype=np.float64).reshape(-1, N_PARAMS)
    bank = np.asarray(sediment_bank, dtype=np.float64)
    reference = params[:, P_OB_QUADRATURE] == OB_REFERENCE
    for chosen, most in ((~reference, EXACT_DEPTHS), (reference, REFERENCE_DEPTHS)):
        rows = params[chosen, P_SED_PROFILE]
        rows = np.unique(rows[(rows >= 0) & (rows < bank.shape[0])]).astype(np.int64)
        if rows.size and np.any(np.sum(bank[rows, 0, :] > 0.0, axis=1) > most):
            return True
    return None


def _rule(paths, body, a_z, z_c, seabed_z, depth_max, rho_w, g, p, bank, below):
    """The overburden of a body embedded down to ``depth_max``: the reference rule, or the
    bounded one for a long table (see the module); compiled through the overload below, which
    leaves the bounded rule out when ``paths`` is ``None``. ``below``: the part below the
    seabed (:func:`overburden_below`)."""
    raise NotImplementedError("compiled code only")


@overload(_rule, jit_options=JIT_OPTIONS)
def _rule_impl(paths, body, a_z, z_c, seabed_z, depth_max, rho_w, g, p, bank, below):
    if isinstance(paths, (types.NoneType, types.Omitted)):

        def reference_only(paths, body, a_z, z_c, seabed_z, depth_max, rho_w, g, p, bank, below):
            # no drop of the batch has a long table (with_long_tables): the fast rule is this
            return _exact(body, a_z, z_c, seabed_z, depth_max, rho_w, g, p, bank, below)

        return reference_only

    def by_table(paths, body, a_z, z_c, seabed_z, depth_max, rho_w, g, p, bank, below):
        row = int(p[P_SED_PROFILE])
        if row >= 0:
            ref = int(p[P_OB_QUADRATURE]) == OB_REFERENCE
            if depths_inside(bank, row, depth_max) > (REFERENCE_DEPTHS if ref else EXACT_DEPTHS):
                # one call site: the bounded rule is compiled (inlined) once
                slices = REFERENCE_SLICES if ref else SLICES
                return _bounded(body, a_z, z_c, seabed_z, depth_max, rho_w, g, p, bank, slices, below)
        return _exact(body, a_z, z_c, seabed_z, depth_max, rho_w, g, p, bank, below)

    return by_table


@kernel
def _exact(body, a_z, z_c, seabed_z, depth_max, rho_w, g, p, bank, below):
    """The reference rule: one slice between consecutive table depths (see the module).
    ``below``: the part below the seabed, the first slice's top cut."""
    c = math.sqrt(max(0.0, 1.0 - a_z * a_z))
    f_tot = 0.0
    mx = 0.0
    me = 0.0
    row = int(p[P_SED_PROFILE])
    top = 0.0
    k = 1
    # the part below each slice boundary; a slice's bottom cut is the next slice's top cut
    # (one cut per boundary: a tabulated profile has one boundary per depth in the body); the
    # first, at the seabed (seabed_z - 0.0 = seabed_z), is the caller's
    v1, x1, e1 = below
    while top < depth_max:
        # next slice boundary: the next table depth, or the bottom of the body
        bottom = depth_max
        if row >= 0:
            while k < bank.shape[2] and not math.isnan(bank[row, 0, k]):
                if bank[row, 0, k] > top:
                    if bank[row, 0, k] < bottom:
                        bottom = bank[row, 0, k]
                    break
                k += 1
        kind = 2
        x_empty = 0.0
        if bottom == depth_max:
            # the last slice ends at the body's lowest point: what the cut there would give may be
            # known, or too small to change a bit of v, xs or es (_negligible_below)
            kind, bound, x_empty, reach_x, reach_e = bodies.cut_sliver(body, a_z, z_c, seabed_z - bottom)
            if kind == 1 and not _negligible_below(bound, reach_x, reach_e, v1, x1, e1):
                kind = 2
        if kind == 0:  # the cut's exact values for an empty part
            v2, x2, e2 = 0.0, x_empty, 0.0
        elif kind == 1:  # a sliver: zeros give the same v, xs, es bit for bit
            v2, x2, e2 = 0.0, 0.0, 0.0
        else:
            v2, x2, e2, _, _, _ = bodies.cut(body, a_z, z_c, seabed_z - bottom)
        v = v1 - v2  # the part between the two planes, its centroid (xs, es)
        if v > 0.0:
            xs = (v1 * x1 - v2 * x2) / v
            es = (v1 * e1 - v2 * e2) / v
            z_cent = z_c + a_z * xs - es * c
            rho = _density(seabed_z - z_cent, p, bank)
            f = (rho - rho_w) * g * v
            f_tot += f
            mx += f * xs
            me += f * es
        top = bottom
        v1, x1, e1 = v2, x2, e2
    return f_tot, mx, me


#: 2**-55: a term below this fraction of a float's magnitude leaves it unchanged when added
#: (under half the spacing of the floats next to it, whatever the float: _negligible_below)
_HALF_SPACING = 2.0**-55
#: the smallest magnitude that _negligible_below takes for a normal float (well above 2**-1022)
_NORMAL = 1e-290


@small_kernel
def _negligible_below(bound, reach_x, reach_e, v1, x1, e1):
    """Whether a cut below the slice (volume v2, centroid x2, e2) whose volume is at most
    ``bound``, ``|x2|`` at most ``reach_x / 2`` and ``|e2|`` at most ``reach_e / 2``
    (``bodies.cut_sliver``) can be left out of the slice above it without changing a bit: v1 - v2 ==
    v1, v1 x1 - v2 x2 == v1 x1 and v1 e1 - v2 e2 == v1 e1 in floating point, each subtracted term
    under 2**-55 of a normal, non-zero float, less than half the spacing of the floats next to
    it, so that the difference rounds back to it; v2, x2, e2 = 0, 0, 0 then give the slice's v,
    xs and es bit for bit."""
    px = abs(v1 * x1)
    pe = abs(v1 * e1)
    return (
        v1 > _NORMAL
        and px > _NORMAL
        and pe > _NORMAL
        and 2.0 * bound < v1 * _HALF_SPACING
        and bound * reach_x < px * _HALF_SPACING
        and bound * reach_e < pe * _HALF_SPACING
    )


@small_kernel
def _profile_at(zeta, p, bank, row, last, rho_w, g):
    """``(rho_s, sigma')`` at depth ``zeta`` of bank row ``row`` (``last``: its last point):
    ``laws.sediment_properties`` without the strength, its segment found by
    ``environment.bracket`` (O(1)) and the integral down to its top read from
    ``laws.COLUMN_OVERBURDEN``. A bank without that column takes the general path."""
    if bank.shape[1] <= COLUMN_OVERBURDEN or not (zeta > bank[row, 0, 0] and zeta <= bank[row, 0, last]):
        r, _, s = sediment_properties(zeta, p, bank)
        return r, s
    lo, hi = bracket(bank, row, zeta, last, True)  # bank[row, 0, lo] < zeta <= bank[row, 0, hi]
    d0 = bank[row, 0, lo]
    r0 = bank[row, 1, lo]
    rz = r0 + (zeta - d0) / (bank[row, 0, hi] - d0) * (bank[row, 1, hi] - r0)
    return rz, (bank[row, COLUMN_OVERBURDEN, lo] + (0.5 * (r0 + rz) - rho_w) * (zeta - d0)) * g


@small_kernel
def _slice(body, a_z, c, z_c, seabed_z, a, b, v1, x1, e1, r1, s1, rho_w, g, p, bank, row, last):
    """The slice between the depths ``a`` and ``b`` (the part below ``a``: ``v1, x1, e1``,
    the profile at ``a``: ``r1, s1``): ``(V, x_s, eta_s, zeta_c, w, w', var)`` with its
    volume, centroid and centroid depth, the force per volume w (:func:`_bounded`), the
    slope w' = g (rho_s(b) - rho_s(a)) / (b - a) and the variance of the depth over the
    slice, h^2/12 - (zeta_c - (a + b)/2)^2 (exact for a cross-section linear in depth);
    then the same at ``b`` for the next slice."""
    v2, x2, e2, _, _, _ = bodies.cut(body, a_z, z_c, seabed_z - b)
    r2, s2 = _profile_at(b, p, bank, row, last, rho_w, g)
    v = v1 - v2
    if not (v > 0.0 and b > a):
        return 0.0, 0.0, 0.0, 0.5 * (a + b), 0.0, 0.0, 0.0, v2, x2, e2, r2, s2
    xs = (v1 * x1 - v2 * x2) / v
    es = (v1 * e1 - v2 * e2) / v
    zeta_c = seabed_z - (z_c + a_z * xs - es * c)
    h = b - a
    off = zeta_c - 0.5 * (a + b)
    slope = g * (r2 - r1) / h
    w = (s2 - s1) / h + slope * off
    var = max(0.0, h * h / 12.0 - off * off)
    return v, xs, es, zeta_c, w, slope, var, v2, x2, e2, r2, s2


@small_kernel
def _rate(x0, t0, x1, t1):
    """d x / d zeta between two slice centroids (0 when they share a depth)."""
    return (x1 - x0) / (t1 - t0) if t1 != t0 else 0.0


@kernel
def _bounded(body, a_z, z_c, seabed_z, depth_max, rho_w, g, p, bank, slices, below):
    """The bounded rule: :data:`SLICES` equal slices from the top of the embedded part
    (the seabed, or the body's top when it is buried) to ``depth_max``. A slice [a, b]
    of volume V and centroid (x_s, eta_s) at depth zeta_c carries

        F_i = w V,   w = (sigma'(b) - sigma'(a)) / (b - a) + w' (zeta_c - (a + b)/2),

    the depth mean of (rho_s - rho_w) g over the slice, read from the running overburden
    integral sigma' (``laws.sediment_properties``: exact for the tabulated profile, O(1)),
    plus the secant slope w' = g (rho_s(b) - rho_s(a)) / (b - a) times the centroid's
    offset from the mid-depth: exact for a density linear within the slice (then F_i =
    (rho_s(zeta_c) - rho_w) g V, the reference rule's slice), and every table row counts
    through the integral, so a rough core is averaged, not sampled. Its moments are
    F_i x_s + w' V var (d x_s / d zeta) (and the same for eta): with w linear in the
    slice, int w x dV = F_i x_s + w' V cov(zeta, x), the covariance taken as the depth's
    variance over the slice times the rate at which the slices' centroids move with
    depth (central differences of the neighbours' centroids). Errors: docs/notes/sediment.md.
    ``below``: the part below the seabed, the first slice's top cut when the body crosses it."""
    c = math.sqrt(max(0.0, 1.0 - a_z * a_z))
    row = int(p[P_SED_PROFILE])
    last = last_point(bank, row)
    _, z_hi = bodies.extent(body, a_z, z_c)
    top = max(0.0, seabed_z - z_hi)
    h = (depth_max - top) / slices
    if top == 0.0:  # the body crosses the seabed: its part below it is the caller's cut
        v1, x1, e1 = below
    else:
        v1, x1, e1, _, _, _ = bodies.cut(body, a_z, z_c, seabed_z - top)
    r1, s1 = _profile_at(top, p, bank, row, last, rho_w, g)
    # slice i is finished once slice i + 1 is known (its centroid's rate with depth); _slice
    # has one call site: it is inlined, and a second copy doubled this compile (docs/design.md)
    vc, xc, ec, tc, wc, sc, qc = 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0
    xp, ep, tp = 0.0, 0.0, 0.0  # the previous slice (at i = 2: the first one)
    f_tot = 0.0
    mx = 0.0
    me = 0.0
    for i in range(1, slices + 2):
        if i <= slices:
            a = top + (i - 1) * h
            b = depth_max if i == slices else top + i * h
            vn, xn, en, tn, wn, sn, qn, v1, x1, e1, r1, s1 = _slice(
                body, a_z, c, z_c, seabed_z, a, b, v1, x1, e1, r1, s1, rho_w, g, p, bank, row, last
            )
        else:  # the last slice: one-sided rate
            vn, xn, en, tn, wn, sn, qn = 0.0, xc, ec, tc, 0.0, 0.0, 0.0
        if i == 1:
            xp, ep, tp = xn, en, tn
        elif vc > 0.0:
            t0 = tp
            t1 = tn
            x0, e0, x2, e2 = xp, ep, xn, en
            if vn <= 0.0:
                t1, x2, e2 = tc, xc, ec
            f = wc * vc
            corr = sc * vc * qc
            f_tot += f
            mx += f * xc + corr * _rate(x0, t0, x2, t1)
            me += f * ec + corr * _rate(e0, t0, e2, t1)
            xp, ep, tp = xc, ec, tc
        vc, xc, ec, tc, wc, sc, qc = vn, xn, en, tn, wn, sn, qn
    return f_tot, mx, me
