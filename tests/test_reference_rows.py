"""The reference sediment quadrature on a long tabulated profile (issue 34, item 2).

The reference rule split every line of its quadrature at every table depth it crossed, and the
lateral surface's angle panels at every depth line reaching a body end: on a 20,000-row log
(0.3 mm apart) one evaluation took 8-19 s, so the self-check of a run never ended. Beyond
``REFERENCE_LEVELS`` depths in a span the rows are now sampled by a bounded rule. Independent
references: the same linear profile given by 2 rows (no split at all), the cost of the 3-row
table, and the splitting kept bit for bit on short tables (the kernel tests' closed forms).
"""

import math
import time

import numpy as np
from test_sediment_kernel import params

from mineburial.kernels.mine import layout as lay
from mineburial.kernels.mine.sediment import reference as ref
from mineburial.kernels.mine.sediment.laws import LAW_REFERENCE_PATHS, drop_bank, pack_law

L, R, CHI = 2.0, 0.265, 0.05


def bank_of(depth, density, strength):
    b = np.array([[depth, density, strength]], dtype=np.float64)
    p = params()
    p[lay.P_SED_PROFILE] = 0
    p[lay.P_SED_RESISTANCE] = 2  # bearing
    return drop_bank(p, b)


def tractions(p, bank, pitch, d0, vb):
    law = pack_law(p, 2.0 * R)[:LAW_REFERENCE_PATHS]
    c2 = (math.sin(pitch), 0.0, math.cos(pitch))
    return np.array(ref.reference_tractions(L, R, CHI, c2[0], c2[1], c2[2], d0, vb, law, bank))


POSES = [
    (0.3, 0.3, (0.5, 0.0, 0.8, 0.0, 0.3, 0.0)),
    (0.0, 1.0, (0.2, 0.1, 1.5, 0.05, -0.2, 0.1)),
    (1.2, 0.8, (0.0, 0.0, 2.0, 0.0, 0.0, 0.0)),
    (-0.4, 0.5, (1.0, -0.3, 0.4, 0.0, 0.5, -0.2)),
]


def test_long_linear_table_matches_the_two_row_table():
    # the same linear profile as 2 rows (never split) and as 20,000 rows (the bounded rule:
    # LONG_PIECES equal pieces of every part): both integrate a smooth integrand (measured
    # worst 9.1e-6 of the force scale, 2.0e-5 of the torque scale, pitch 1.2 rad)
    z2 = np.array([0.0, 6.0])
    z = np.linspace(0.0, 6.0, 20000)
    short = bank_of(z2, 1420.0 + 30.0 * z2, 2000.0 + 1010.0 * z2)
    long = bank_of(z, 1420.0 + 30.0 * z, 2000.0 + 1010.0 * z)
    for pitch, d0, vb in POSES:
        a = tractions(*short, pitch, d0, vb)
        b = tractions(*long, pitch, d0, vb)
        scale = np.abs(a[:3]).max()
        assert np.all(np.abs(b[:3] - a[:3]) < 3e-5 * scale), (a, b)
        assert np.all(np.abs(b[3:] - a[3:]) < 1e-4 * scale * L), (a, b)


def test_reference_cost_does_not_grow_with_the_rows():
    # before: 0.3 ms at 2 rows, 110-200 ms at 2,000 and 8-19 s at 20,000 (quadratic in the rows)
    timings = {}
    for n in (3, 20000):
        z = np.linspace(0.0, 6.0, n)
        wave = np.sin(2 * np.pi * z / 0.13)
        p, bank = bank_of(z, 1420.0 + 30.0 * z + 10.0 * wave, (2000.0 + 1010.0 * z) * (1.0 + 0.05 * wave))
        tractions(p, bank, *POSES[0])
        t0 = time.perf_counter()
        for pitch, d0, vb in POSES:
            tractions(p, bank, pitch, d0, vb)
        timings[n] = time.perf_counter() - t0
    assert timings[20000] < 10 * timings[3] + 0.01, timings
