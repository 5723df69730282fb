"""The post-impact scour stage over the drops of an ensemble chunk (issue 20, items 1 and 6).

One compiled loop over drops: each drop that came to rest runs :func:`mineburial.kernels.scour.
scour_stage` from its impact burial over the run's forcing (Hs scaled by the drop's factor, the
water depth the drop's own plus the forcing's water level), and the burial measures of the
impact phase (:func:`mineburial.kernels.geometry.burial_measures`) are evaluated at each lead time
with the mine at its rest attitude and the bed level raised so that the lowest point lies the
scour burial ``B`` below it (docs/scour.md, Integration). A plain loop rather than ``prange``: the
stage costs about 1 ms a drop, a few percent of the impact phase, and a parallel loop's compile
is not worth it (docs/design.md, batch driver).
"""

import math

import numpy as np

from mineburial._numba import kernel
from mineburial.kernels import scour as sc
from mineburial.kernels.geometry import burial_measures, vertical_extent

#: the drop did not come to rest (its impact status is not in the statistics): not run
SCOUR_NOT_RUN = 4
STATUS_NAMES = sc.STATUS_NAMES + ("not_run",)
STATUS_DESCRIPTIONS = sc.STATUS_DESCRIPTIONS + (
    "the impact phase did not leave the mine at rest (its status is not at_rest or "
    "buried_sinking): there is no initial burial and the stage was not run",
)

#: columns of ``geom``: length, radius, COM offset chi, axial vertical component a_z, COM height z_c
#: above the seabed (= -com_depth), all at rest
G_LENGTH, G_RADIUS, G_CHI, G_AZ, G_ZC = range(5)
N_GEOM = 5
#: measures at each lead time (``out_measures[i, k, j]``): as layout.SUMMARY_NAMES's columns
MEASURE_NAMES = ("penetration_depth", "burial_volume", "burial_height", "burial_area", "height_proud")


@kernel
def scour_drops(
    S,
    hs_scale,
    depth,
    run,
    geom,
    t,
    hs,
    tp,
    wdir,
    uc,
    cdir,
    level,
    table,
    lead_times,
    fractions,
    out_measures,
    out_time_to,
    out_mobile,
    out_status,
):
    """Run the stage for each drop ``i`` with ``run[i]``: ``S[i]`` its stage parameters (S_* layout
    of kernels/scour.py), ``hs_scale[i]`` its factor on Hs, ``depth[i]`` its water depth [m] (the
    forcing's water ``level`` is added), ``geom[i]`` its geometry at rest (G_* columns).

    Writes ``out_measures[i, k, j]`` (measure k of MEASURE_NAMES at lead time j),
    ``out_time_to[i, k]`` (s after the forcing's start at which B/D reaches ``fractions[k]``;
    inf never), ``out_mobile[i]`` (s, first time the mobility threshold is passed; inf never) and
    ``out_status[i]`` (sc.SCOUR_* or SCOUR_NOT_RUN; NaN results only with a status that is not ok).
    """
    n = S.shape[0]
    nt = t.shape[0]
    burial = np.empty(lead_times.shape[0])
    hs_i = np.empty(nt)
    h_i = np.empty(nt)
    for i in range(n):
        out_measures[i, :, :] = math.nan
        out_time_to[i, :] = math.nan
        out_mobile[i] = math.nan
        if not run[i]:
            out_status[i] = SCOUR_NOT_RUN
            continue
        for m in range(nt):
            hs_i[m] = hs[m] * hs_scale[i]
            h_i[m] = depth[i] + level[m]
        code, t_mobile, _ = sc.scour_stage(
            S[i], t, hs_i, tp, wdir, uc, cdir, h_i, table, lead_times, fractions, burial, out_time_to[i]
        )
        out_status[i] = code
        if code == sc.SCOUR_INVALID_PARAMETER or code == sc.SCOUR_INVALID_FORCING:
            out_time_to[i, :] = math.nan
            continue
        out_mobile[i] = t_mobile
        L = geom[i, G_LENGTH]
        R = geom[i, G_RADIUS]
        chi = geom[i, G_CHI]
        a_z = geom[i, G_AZ]
        z_c = geom[i, G_ZC]
        z_min, _ = vertical_extent(L, R, chi, a_z, z_c)
        for j in range(lead_times.shape[0]):
            b = burial[j]
            if not math.isfinite(b):
                continue
            pv, ph, pa, proud, pen = burial_measures(L, R, chi, a_z, z_c, z_min + b)
            out_measures[i, 0, j] = pen
            out_measures[i, 1, j] = pv
            out_measures[i, 2, j] = ph
            out_measures[i, 3, j] = pa
            out_measures[i, 4, j] = proud
