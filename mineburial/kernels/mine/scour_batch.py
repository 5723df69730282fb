"""The post-impact scour stage over the drops of an ensemble chunk (issue 20, items 1 and 6).

One compiled loop over drops: each drop that came to rest runs :func:`mineburial.kernels.mine.scour.
scour_stage` over the run's forcing (Hs scaled by the drop's factor, the water depth the drop's
own plus the forcing's water level). The scour laws are those of a cylinder **lying** on or in the
bed (Rennie, Brandt & Friedrichs 2017: B/D = 1 puts the top of the horizontal cylinder level with
the bed), so the stage's mine lies down: it starts from the burial ``B0`` of the horizontal
cylinder that has the same fraction of its volume below the bed as the mine at its impact rest
attitude (:func:`lying_burial`), and the burial measures of the impact phase
(the body protocol's ``burial``, :mod:`mineburial.kernels.mine.bodies`) are evaluated at each lead
time for that lying mine with its lowest point ``B`` below the bed (docs/scour.md, Rest
attitude). A plain loop rather than ``prange`` (the stage costs about 1 ms a drop, a few percent
of the impact phase; docs/design.md, batch driver); the caller runs blocks of drops on the run's
threads (:func:`mineburial.ensembles.threads.run_blocks`; the kernel releases the GIL).
"""

import math

import numpy as np

from mineburial._numba import kernel
from mineburial.kernels.mine import bodies
from mineburial.kernels.mine import scour as sc
from mineburial.kernels.mine.dynamics import body_of
from mineburial.kernels.mine.geometry import segment_area_unit

#: the drop did not come to rest (its impact status is not in the statistics): not run
SCOUR_NOT_RUN = 4
STATUS_NAMES = sc.STATUS_NAMES + ("not_run",)
STATUS_DESCRIPTIONS = sc.STATUS_DESCRIPTIONS + (
    "the impact phase did not leave the mine at rest (its status is not at_rest or "
    "buried_sinking): there is no initial burial and the stage was not run",
)

#: columns of ``rest``: the axis' vertical component a_z and the COM height z_c above the seabed
#: (= -com_depth) of the drop at rest; its body comes from its parameter row (``dynamics.drop_body``)
R_AZ, R_ZC = range(2)
N_REST = 2
#: measures at each lead time (``out_measures[i, k, j]``): as layout.SUMMARY_NAMES's columns
MEASURE_NAMES = ("penetration_depth", "burial_volume", "burial_height", "burial_area", "height_proud")


@kernel
def lying_burial(body, a_z, z_c):
    """Initial burial [m] of the stage's lying mine from the impact's rest state (bed at z = 0):
    the depth of the lowest point of the horizontal cylinder with the same fraction ``f`` of its
    volume below the bed, ``R (1 - cos t)`` with ``(t - sin t cos t)/pi = f`` (the circular
    segment of half-angle ``t``, seed 000 eq. (25a)), solved by bisection to the last bit. A mine
    whose top lies below the bed (f = 1) lies with its top as deep: ``2R`` + that depth, so the
    map is continuous and never unburies a buried mine. A lying mine maps to its own burial.
    ``body`` is the drop's body (``dynamics.drop_body``); the scour laws are a lying cylinder's, of
    the body's reference diameter (docs/scour.md)."""
    R = 0.5 * bodies.reference_lengths(body)[0]
    _, z_max = bodies.extent(body, a_z, z_c)
    if z_max <= 0.0:
        return 2.0 * R - z_max
    pct_v, _, _, _, _ = bodies.burial(body, a_z, z_c, 0.0)
    f = pct_v / 100.0
    if f >= 1.0:
        return 2.0 * R
    if f <= 0.0:
        return 0.0
    lo = 0.0
    hi = math.pi
    target = math.pi * f
    for _ in range(80):
        mid = 0.5 * (lo + hi)
        if mid <= lo or mid >= hi:
            break
        if segment_area_unit(mid) < target:
            lo = mid
        else:
            hi = mid
    return R * (1.0 - math.cos(0.5 * (lo + hi)))


@kernel
def standing_burial(body, a_z, z_c):
    """Initial burial [m] of the stage's standing body (a frustum on its base, axis vertical, base
    down; docs/scour.md, Standing body) from the impact's rest state (bed at z = 0): the depth of the
    base below the bed of the level standing body with the same fraction of its volume below the
    bed as at the impact's attitude (as :func:`lying_burial` for the lying one: the lead-0 burial by
    volume is the impact's), by bisection on the body's own ``bodies.burial`` to the last bit. A
    body wholly below the bed stands with its top as deep (its height + that depth)."""
    x_tail, x_nose = bodies.ends(body)
    height = x_nose - x_tail
    _, z_max = bodies.extent(body, a_z, z_c)
    if z_max <= 0.0:
        return height - z_max
    pct_v, _, _, _, _ = bodies.burial(body, a_z, z_c, 0.0)
    if pct_v >= 100.0:
        return height
    if pct_v <= 0.0:
        return 0.0
    z_low = bodies.lowest_offset(body, 1.0, 0.0, 0.0)  # the base below the COM, axis up
    lo = 0.0
    hi = height
    for _ in range(80):
        mid = 0.5 * (lo + hi)
        if mid <= lo or mid >= hi:
            break
        if bodies.burial(body, 1.0, 0.0, mid + z_low)[0] < pct_v:
            lo = mid
        else:
            hi = mid
    return 0.5 * (lo + hi)


@kernel
def standing_measures(body, b):
    """The burial measures (``bodies.burial``) of the standing body (axis vertical, base down) with
    its base ``b`` below the bed."""
    return bodies.burial(body, 1.0, 0.0, b + bodies.lowest_offset(body, 1.0, 0.0, 0.0))


@kernel
def forcing_window(t, offset, length, idx, tw):
    """The records of the window from ``offset`` to ``offset + length`` [s after t[0]], cut as
    :func:`mineburial.io.forcing.window` cuts them (record k holds over [t_k, t_k+1)): the record
    in effect at the offset first (timed at the offset), those that start inside, and the one in
    effect at the end last (timed at the end). Writes their indices into ``idx`` and their times
    from the window's start into ``tw`` (both at least len(t) + 1 long); returns how many."""
    a = t[0] + offset
    e = a + length
    i0 = np.searchsorted(t, a, side="right") - 1
    i1 = np.searchsorted(t, e, side="left")
    idx[0] = i0
    tw[0] = 0.0
    m = 1
    for k in range(i0 + 1, i1):
        if t[k] - a >= length:  # within rounding of the end
            break
        idx[m] = k
        tw[m] = t[k] - a
        m += 1
    idx[m] = np.searchsorted(t, e, side="right") - 1
    tw[m] = length  # exactly: a lead time equal to the length is inside the window
    return m + 1


@kernel
def scour_drops(
    S, hs_scale, depth, run, P, rest, t, hs, tp, wdir, uc, cdir, level, start, length, table, lead_times,
    fractions, out_measures, out_time_to, out_mobile, out_status, out_pit, out_mobile_lead, shape=None,
):  # fmt: skip
    """:func:`scour_drops_ends` without the tilt output (same arguments otherwise)."""
    scour_drops_ends(
        S, hs_scale, depth, run, P, rest, t, hs, tp, wdir, uc, cdir, level, start, length, table, lead_times,
        fractions, out_measures, out_time_to, out_mobile, out_status, out_pit, out_mobile_lead,
        np.empty((S.shape[0], lead_times.shape[0])), shape,
    )  # fmt: skip


@kernel
def impact_ends(body, a_z, z_c):
    """(B, H, L) of the impact's rest attitude for ``rest_attitude = "impact"``: the depth B [m] of
    the lowest point below the bed (z = 0), the depth H of the higher end's lowest point (of the
    reference cylinder: B - L |a_z|; < 0 where that end stands proud) and the axial span L [m] (tail
    to nose, ``bodies.ends``). The tilt is asin((B - H)/L) = asin(|a_z|) (docs/scour.md, Tilt)."""
    x_tail, x_nose = bodies.ends(body)
    span = x_nose - x_tail
    z_min, _ = bodies.extent(body, a_z, z_c)
    b = -z_min
    return b, b - span * abs(a_z), span


@kernel
def tilted_measures(body, a_z_sign, b, h, span):
    """The burial measures (``bodies.burial``) of the mine tilted at sin(beta) = (B - H)/L, its
    lower end on the side of ``a_z_sign`` (the impact's: the nose down for a_z < 0), with its lowest
    point ``b`` below the bed; with H = B the level mine of the flat choice."""
    sb = sc.tilt_sine(b, h, span)
    a_z = -sb if a_z_sign < 0.0 else sb
    k3 = math.sqrt(1.0 - a_z * a_z)
    return bodies.burial(body, a_z, 0.0, b + bodies.lowest_offset(body, a_z, 0.0, k3))


@kernel
def scour_drops_ends(
    S,
    hs_scale,
    depth,
    run,
    P,
    rest,
    t,
    hs,
    tp,
    wdir,
    uc,
    cdir,
    level,
    start,
    length,
    table,
    lead_times,
    fractions,
    out_measures,
    out_time_to,
    out_mobile,
    out_status,
    out_pit,
    out_mobile_lead,
    out_tilt,
    shape=None,
):
    """Run the stage for each drop ``i`` with ``run[i]``: ``S[i]`` its stage parameters (S_* layout
    of kernels/mine/scour.py), ``hs_scale[i]`` its factor on Hs, ``depth[i]`` its water depth [m] (the
    forcing's water ``level`` is added), ``P[i]`` its parameter row (its body, ``dynamics.drop_body``)
    and ``rest[i]`` its attitude and height at rest (R_* columns); the stage's initial burial
    ``S[i, S_B0]`` is set here from them (:func:`lying_burial`). The drop
    sees the forcing window from ``start[i]`` [s after t[0]] of ``length`` [s]
    (:func:`forcing_window`; the caller keeps it inside the series), lead times counted from its
    start; ``start[i] = 0`` with ``length`` >= the series' span is the whole series as given.

    Writes ``out_measures[i, k, j]`` (measure k of MEASURE_NAMES at lead time j),
    ``out_time_to[i, k]`` (s after the forcing's start at which B/D reaches ``fractions[k]``;
    inf never), ``out_mobile[i]`` (s, first time the mobility threshold is passed; inf never),
    ``out_status[i]`` (sc.SCOUR_* or SCOUR_NOT_RUN; NaN results only with a status that is not ok),
    ``out_pit[i, j]`` (the scour pit's depth [m] below the far-field bed at lead time j) and
    ``out_mobile_lead[i, j]`` (1.0 where the mine would move at lead time j, else 0.0;
    :func:`mineburial.kernels.mine.scour.scour_stage_states`) and ``out_tilt[i, j]`` (the tilt of
    the axis to the horizontal [degrees] at lead time j: 0 under the flat rest attitude; under
    ``S_REST_ATTITUDE = REST_IMPACT`` the stage starts from the impact's attitude, :func:`impact_ends`,
    and the measures are those of the tilted mine, :func:`tilted_measures`).
    """
    n = S.shape[0]
    nt = t.shape[0]
    burial = np.empty(lead_times.shape[0])
    high = np.empty(lead_times.shape[0])
    nb = nt + 1  # a window has at most one record more than the series (both ends cut)
    hs_i = np.empty(nb)
    h_i = np.empty(nb)
    idx = np.empty(nb, dtype=np.int64)
    t_w = np.empty(nb)
    tp_w = np.empty(nb)
    wdir_w = np.empty(nb)
    uc_w = np.empty(nb)
    cdir_w = np.empty(nb)
    span = t[nt - 1] - t[0]
    for i in range(n):
        out_measures[i, :, :] = math.nan
        out_time_to[i, :] = math.nan
        out_mobile[i] = math.nan
        out_pit[i, :] = math.nan
        out_mobile_lead[i, :] = math.nan
        out_tilt[i, :] = math.nan
        if not run[i]:
            out_status[i] = SCOUR_NOT_RUN
            continue
        if start[i] == 0.0 and length >= span:  # the whole series, as given
            nw = nt
            for m in range(nt):
                idx[m] = m
                t_w[m] = t[m]
        else:
            nw = forcing_window(t, start[i], length, idx, t_w)
        for m in range(nw):
            k = idx[m]
            hs_i[m] = hs[k] * hs_scale[i]
            h_i[m] = depth[i] + level[k]
            tp_w[m] = tp[k]
            wdir_w[m] = wdir[k]
            uc_w[m] = uc[k]
            cdir_w[m] = cdir[k]
        body = body_of(P[i], shape)  # the drop's body: ``shape`` the prototype of a non-default shape
        tilted = S[i, sc.S_REST_ATTITUDE] == sc.REST_IMPACT
        standing = S[i, sc.S_STANDING] == 1.0
        if standing:  # a short body on its base (a frustum; the stage refuses a tilt state for it)
            S[i, sc.S_B0] = standing_burial(body, rest[i, R_AZ], rest[i, R_ZC])
        elif tilted:
            b0, h0, span = impact_ends(body, rest[i, R_AZ], rest[i, R_ZC])
            S[i, sc.S_B0] = b0
            S[i, sc.S_B0_HIGH] = h0
            S[i, sc.S_AXIS_SPAN] = span
        else:
            S[i, sc.S_B0] = lying_burial(body, rest[i, R_AZ], rest[i, R_ZC])
        code, t_mobile, _ = sc.scour_stage_ends(
            S[i], t_w[:nw], hs_i[:nw], tp_w[:nw], wdir_w[:nw], uc_w[:nw], cdir_w[:nw], h_i[:nw], table,
            lead_times, fractions, burial, out_time_to[i], out_pit[i], out_mobile_lead[i], high,
        )  # fmt: skip
        out_status[i] = code
        if code == sc.SCOUR_INVALID_PARAMETER or code == sc.SCOUR_INVALID_FORCING:
            out_time_to[i, :] = math.nan
            out_pit[i, :] = math.nan
            out_mobile_lead[i, :] = math.nan
            continue
        out_mobile[i] = t_mobile
        for j in range(lead_times.shape[0]):
            b = burial[j]
            if not math.isfinite(b):
                continue
            if tilted:
                span = S[i, sc.S_AXIS_SPAN]
                out_tilt[i, j] = math.degrees(math.asin(sc.tilt_sine(b, high[j], span)))
                pv, ph, pa, proud, pen = tilted_measures(body, rest[i, R_AZ], b, high[j], span)
                out_measures[i, 0, j] = pen
                out_measures[i, 1, j] = pv
                out_measures[i, 2, j] = ph
                out_measures[i, 3, j] = pa
                out_measures[i, 4, j] = proud
                continue
            out_tilt[i, j] = 0.0
            if standing:  # the base level (no tilt output: "impact" is refused for a standing body)
                pv, ph, pa, proud, pen = standing_measures(body, b)
                out_measures[i, 0, j] = pen
                out_measures[i, 1, j] = pv
                out_measures[i, 2, j] = ph
                out_measures[i, 3, j] = pa
                out_measures[i, 4, j] = proud
                continue
            # the lying mine (a_z = 0, COM at z = 0, lowest point at -R) with the bed B above it
            pv, ph, pa, proud, pen = bodies.burial(
                body, 0.0, 0.0, b + bodies.lowest_offset(body, 0.0, 0.0, 1.0)
            )
            out_measures[i, 0, j] = pen
            out_measures[i, 1, j] = pv
            out_measures[i, 2, j] = ph
            out_measures[i, 3, j] = pa
            out_measures[i, 4, j] = proud
