"""Tests of the closed frustum's added-mass table (mineburial.kernels.mine.added_mass, ``FRUSTUM_*``)
and of the BEM run that computed it (benchmarks/added_mass_revolution_bem.py, its output in
benchmarks/results/added_mass_revolution_bem.txt; capytaine is not a project dependency, so the
run's output is checked here, not the run).

References: Lamb's closed forms for the sphere and spheroids (Lamb, Hydrodynamics, 6th ed., section
114: ``k = alpha_0 / (2 - alpha_0)`` along an axis, the ``alpha_0, beta_0`` integrals by scipy);
the cylinder's table of ``added_mass.py`` (an earlier, independent BEM computation, shared/notes/
sources.md section 1) for the frustum of ratio 1; fore-aft symmetry (no coupling for the
cylinder); the table's own rows in the results file.
"""

import math
from pathlib import Path

import numpy as np
import pytest
from scipy.integrate import quad

from mineburial.kernels.mine import added_mass as am

RESULTS = Path(__file__).resolve().parents[1] / "benchmarks" / "results" / "added_mass_revolution_bem.txt"


def _rows(kind):
    return [line.split()[1:] for line in RESULTS.read_text().splitlines() if line.startswith(kind + " ")]


def _lamb(a_axial, b_radial):
    """(k_axial, k_transverse) of the spheroid with semi-axis a along its axis and b across it."""
    a2, b2 = a_axial * a_axial, b_radial * b_radial
    ab2 = a_axial * b2
    alpha0 = ab2 * quad(lambda s: 1.0 / ((a2 + s) ** 1.5 * (b2 + s)), 0.0, np.inf, epsrel=1e-12)[0]
    beta0 = ab2 * quad(lambda s: 1.0 / ((a2 + s) ** 0.5 * (b2 + s) ** 2), 0.0, np.inf, epsrel=1e-12)[0]
    return alpha0 / (2.0 - alpha0), beta0 / (2.0 - beta0)


def test_lamb_closed_forms_of_the_sphere():
    assert _lamb(1.0, 1.0) == pytest.approx((0.5, 0.5), rel=1e-10)


@pytest.mark.parametrize(
    "name, a, b", [("sphere", 1.0, 1.0), ("prolate_2", 2.0, 1.0), ("oblate_0.45", 0.45, 1.0)]
)
def test_bem_checks_against_lamb(name, a, b):
    row = {r[0]: r for r in _rows("check")}[name]
    k_axial, k_transverse = float(row[1]), float(row[2])
    ref = _lamb(a, b)
    # the mesh: 40 panels round, a 0.4 % smaller volume than the surface of revolution's
    assert k_axial == pytest.approx(ref[0], rel=6e-3)
    assert k_transverse == pytest.approx(ref[1], rel=6e-3)


def test_table_holds_the_bem_runs_numbers():
    rows = _rows("frustum")
    assert len(rows) == am.FRUSTUM_RATIO.size * am.FRUSTUM_LD.size
    for r in rows:
        i = int(np.flatnonzero(am.FRUSTUM_RATIO == float(r[0]))[0])
        j = int(np.flatnonzero(am.FRUSTUM_LD == float(r[1]))[0])
        ma, mt, mc, mr = (float(v) for v in r[8:12])
        assert (am.FRUSTUM_MA[i, j], am.FRUSTUM_MT[i, j], am.FRUSTUM_MC[i, j], am.FRUSTUM_MR[i, j]) == (
            ma,
            mt,
            mc,
            mr,
        )
        # the printed fractions are the same numbers: V = pi L (1 + q + q^2)/3 of the base radius 1
        q, ld = float(r[0]), float(r[1])
        v = math.pi * 2.0 * ld * (1.0 + q + q * q) / 3.0
        assert (ma / v, mt / v) == pytest.approx((float(r[2]), float(r[3])), abs=6e-6)  # 5 decimals


@pytest.mark.parametrize("ld", [2.0, 3.0])
def test_the_cylinder_entry_is_the_cylinder_table(ld):
    m_a, m_t, m_c, m_r = am.frustum_added_mass(1.0, 1.0, 2.0 * ld)
    v = math.pi * 2.0 * ld
    k_t, k_a, k_r = am.cylinder_added_mass(ld)
    assert m_t / v == pytest.approx(k_t, rel=3e-3)
    assert m_a / v == pytest.approx(k_a, rel=5e-3)
    # fore-aft symmetric: no coupling about the centroid
    assert abs(m_c) < 1e-4 * m_t * 2.0 * ld
    # k_r: the cylinder table's value was computed on a coarser mesh (benchmarks/added_mass_bem.py,
    # 1,280 panels: 0.4645 at L/D = 2; the same script at 3,136 panels gives 0.4558, this table's
    # mesh 0.4491, a finer meridian 0.4486: docs/bodies_revolution.md), so it is 2-4 % high
    strip = math.pi * (2.0 * ld) ** 3 / 12.0
    assert m_r / strip == pytest.approx(k_r, rel=4e-2)
    assert m_r / strip < k_r


def test_bilinear_lookup_hits_the_nodes_and_holds_the_ends():
    for i, q in enumerate(am.FRUSTUM_RATIO):
        for j, ld in enumerate(am.FRUSTUM_LD):
            assert am.table_lookup2(am.FRUSTUM_RATIO, am.FRUSTUM_LD, am.FRUSTUM_MA, q, ld) == pytest.approx(
                am.FRUSTUM_MA[i, j], rel=1e-15
            )
    t = am.FRUSTUM_MT
    mid = am.table_lookup2(am.FRUSTUM_RATIO, am.FRUSTUM_LD, t, 0.375, 0.625)
    assert mid == pytest.approx(0.25 * (t[1, 1] + t[1, 2] + t[2, 1] + t[2, 2]), rel=1e-14)
    assert am.table_lookup2(am.FRUSTUM_RATIO, am.FRUSTUM_LD, t, -1.0, 99.0) == t[0, -1]


def test_a_manta_like_frustum_against_the_oblate_spheroid_estimate():
    # docs/notes/manta_research.md section 2.4: an oblate spheroid of c/a = 0.45 has k_axial 1.25 and
    # k_broadside 0.285 (Lamb); a flat-based frustum of the same proportions (L/D = 0.45, top/base
    # 0.4) carries more axial added mass per volume (its flat base meets the flow as a disc) and
    # about as little broadside
    m_a, m_t, _, _ = am.frustum_added_mass(1.0, 0.4, 0.9)
    v = math.pi * 0.9 * (1.0 + 0.4 + 0.16) / 3.0
    k_ax, k_tr = _lamb(0.45, 1.0)
    assert k_ax == pytest.approx(1.25, abs=0.01) and k_tr == pytest.approx(0.285, abs=0.005)
    assert 1.0 * k_ax < m_a / v < 1.6 * k_ax
    assert 0.8 * k_tr < m_t / v < 1.6 * k_tr


def test_a_flat_cone_tends_to_the_disc():
    # a cone of vanishing height is a disc moving broadside: (8/3) rho a^3 (Lamb, section 108; DNV-RP-H103
    # table A-2); the table's two flattest cones (L/D = 0.25, 0.5) extrapolated linearly to L/D = 0
    m1, m2 = am.FRUSTUM_MA[0, 0], am.FRUSTUM_MA[0, 1]
    assert am.FRUSTUM_LD[:2].tolist() == [0.25, 0.5]
    assert 2.0 * m1 - m2 == pytest.approx(8.0 / 3.0, rel=0.02)
