"""Tests of mineburial.kernels.mine.geometry (cylinder cut by a horizontal plane).

Every closed form is checked against an independent reference: nested
``scipy.integrate.quad`` over the axial coordinate x and the transverse
coordinate s along e_down (chord width 2 sqrt(R^2 - s^2), arc length
R ds / sqrt(R^2 - s^2) on each side), with the integration limits taken from
the plane; none of the kernel's antiderivatives are used. Tolerance: relative
1e-6 with an absolute floor of 1e-10 of the natural scale of each quantity
(volume pi R^2 L, moments volume * L or volume * R, areas 2 pi R L, pi R^2),
needed only where the exact value is 0.
"""

import math
import warnings

import numpy as np
import pytest
from numba import njit
from scipy.integrate import IntegrationWarning, quad

from mineburial.kernels.mine import geometry as geo

RTOL = 1e-6
FLOOR = 1e-10


# ---------------------------------------------------------------------------
# independent reference by numerical quadrature
# ---------------------------------------------------------------------------
def _sint(kind, lo, hi, R):
    """Integral over s in [lo, hi] (within [-R, R]) of the chord width
    2 sqrt(R^2 - s^2) ('area'), of s times the chord ('mom') or of the wetted
    arc length of both sides, 2 R / sqrt(R^2 - s^2) ('arc'). A square-root end
    behaviour at s = -R or s = R is handed to QUADPACK's algebraic weight
    (QAWS), so the results are accurate to ~1e-13."""
    lo = max(lo, -R)
    hi = min(hi, R)
    if hi <= lo:
        return 0.0
    at_lo = lo <= -R
    at_hi = hi >= R
    sq = math.sqrt
    if kind == "area":
        p, f2 = 0.5, (lambda s: 2.0 * sq((R + s) * (R - s)))
        fl, fh, fb = (lambda s: 2.0 * sq(R - s)), (lambda s: 2.0 * sq(R + s)), (lambda s: 2.0)
    elif kind == "mom":
        p, f2 = 0.5, (lambda s: 2.0 * s * sq((R + s) * (R - s)))
        fl, fh, fb = (lambda s: 2.0 * s * sq(R - s)), (lambda s: 2.0 * s * sq(R + s)), (lambda s: 2.0 * s)
    else:
        p, f2 = -0.5, (lambda s: 2.0 * R / sq((R + s) * (R - s)))
        fl, fh, fb = (lambda s: 2.0 * R / sq(R - s)), (lambda s: 2.0 * R / sq(R + s)), (lambda s: 2.0 * R)
    if at_lo and at_hi:
        f, w = fb, (p, p)
    elif at_lo:
        f, w = fl, (p, 0.0)
    elif at_hi:
        f, w = fh, (0.0, p)
    else:
        f, w = f2, (0.0, 0.0)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", IntegrationWarning)
        if w is None:
            return quad(f, lo, hi, epsabs=0.0, epsrel=1e-12)[0]
        return quad(f, lo, hi, weight="alg", wvar=w, epsabs=0.0, epsrel=1e-12)[0]


def reference(L, R, chi, a, z_c, level, above=False):
    """(V, V x_c, V eta_c, lateral, nose cap, tail cap) of the part below
    (or above) the plane by nested quadrature. A point x i + s e_down of the
    cross-section is at height z_c + a x - b s, b = sqrt(1 - a^2)."""
    c = z_c - level
    b = math.sqrt(max(0.0, (1.0 - a) * (1.0 + a)))
    xt, xn = -0.5 * L - chi, 0.5 * L - chi

    def limits(x):
        d = c + a * x  # height of the axis point above the plane
        if b == 0.0:
            s0 = -math.inf if d < 0.0 else math.inf
        else:
            s0 = d / b  # below the plane  <=>  s > s0
        return (-R, s0) if above else (s0, R)

    pts = []
    if a != 0.0:
        for x in ((b * R - c) / a, (-b * R - c) / a, -c / a):
            if xt < x < xn:
                pts.append(x)

    def q(g):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", IntegrationWarning)
            return quad(g, xt, xn, points=pts or None, limit=400, epsabs=1e-14 * L * R * R, epsrel=1e-10)[0]

    cache = {}

    def area(x):
        if x not in cache:
            cache[x] = _sint("area", *limits(x), R)
        return cache[x]

    V = q(area)
    Mx = q(lambda x: x * area(x))
    Ms = q(lambda x: _sint("mom", *limits(x), R))
    lat = q(lambda x: _sint("arc", *limits(x), R))
    cn = _sint("area", *limits(xn), R)
    ct = _sint("area", *limits(xt), R)
    return V, Mx, Ms, lat, cn, ct


def _moments(res):
    V, xc, eta, lat, cn, ct = res
    return V, V * xc, V * eta, lat, cn, ct


def _assert_close(got, ref, L, R, label=""):
    vt = math.pi * R * R * L
    vmax = max(abs(ref[0]), abs(got[0]))
    floors = (
        vt,
        vmax * L + vt * L * 1e-3,
        vmax * R + vt * R * 1e-3,
        2 * math.pi * R * L,
        math.pi * R * R,
        math.pi * R * R,
    )
    names = ("volume", "x-moment", "eta-moment", "lateral", "nose cap", "tail cap")
    for g, r, fl, n in zip(got, ref, floors, names):
        assert abs(g - r) <= RTOL * abs(r) + FLOOR * fl, (label, n, g, r)


def _cap_cut(L, R, chi, a, z_c, level):
    """Number of end caps the plane crosses (simple geometry, for labelling
    the cut pattern of seed 000 Fig. 3)."""
    bR = R * math.sqrt(max(0.0, 1.0 - a * a))
    n = 0
    for x in (-0.5 * L - chi, 0.5 * L - chi):
        zc = z_c + a * x
        if zc - bR < level < zc + bR:
            n += 1
    return n


# ---------------------------------------------------------------------------
# sweep over orientations and immersions
# ---------------------------------------------------------------------------
A_SWEEP = (-1.0, -(1.0 - 1e-9), -0.9, -0.5, -0.1, -1e-3, 0.0, 1e-3, 0.1, 0.5, 0.9, 1.0 - 1e-9, 1.0)
FRACTIONS = (-0.2, 0.003, 0.3, 0.65, 0.997, 1.2)  # of the vertical extent


@pytest.mark.parametrize("chi", [0.0, 0.21])
@pytest.mark.parametrize("a", A_SWEEP)
def test_cut_against_quadrature_sweep(a, chi):
    L, R, z_c = 1.6, 0.27, -3.0
    z_min, z_max = geo.vertical_extent(L, R, chi, a, z_c)
    for f in FRACTIONS:
        level = z_min + f * (z_max - z_min)
        got = _moments(geo.cut_cylinder(L, R, chi, a, z_c, level))
        ref = reference(L, R, chi, a, z_c, level)
        _assert_close(got, ref, L, R, (a, chi, f))


@pytest.mark.parametrize("pattern", ["a", "b", "c"])
def test_cut_patterns_of_seed_fig3(pattern):
    """(a) plane cuts only the lateral surface, (b) one end cap, (c) both end
    caps (seed 000 Fig. 3, Table 1), for both parts and several poses."""
    L, R = 1.2, 0.25
    n_caps = {"a": 0, "b": 1, "c": 2}[pattern]
    checked = 0
    for a in (-0.97, -0.6, -0.05, 0.02, 0.3, 0.8, 0.999):
        for chi in (0.0, -0.17):
            for f in np.linspace(0.02, 0.98, 13):
                z_min, z_max = geo.vertical_extent(L, R, chi, a, 0.0)
                level = z_min + f * (z_max - z_min)
                if _cap_cut(L, R, chi, a, 0.0, level) != n_caps:
                    continue
                got = _moments(geo.cut_cylinder(L, R, chi, a, 0.0, level))
                _assert_close(got, reference(L, R, chi, a, 0.0, level), L, R)
                checked += 1
                if checked >= 6:
                    return
    assert checked > 0


def test_nearly_horizontal_tangent_plane():
    """Tilts of 1e-9..1e-3 with the plane grazing the bottom or top line, so
    the tangency lies inside the body (hardest case for the closed forms)."""
    L, R, chi = 1.5, 0.25, 0.2
    for a in (1e-9, -1e-7, 1e-5, -1e-3):
        z_min, z_max = geo.vertical_extent(L, R, chi, a, 0.0)
        for level in (z_min + 0.3 * abs(a) * L, z_min + 0.8 * abs(a) * L, z_max - 0.4 * abs(a) * L):
            got = _moments(geo.cut_cylinder(L, R, chi, a, 0.0, level))
            _assert_close(got, reference(L, R, chi, a, 0.0, level), L, R, (a, level))


@njit
def _eval_many(P, out):
    for i in range(P.shape[0]):
        r = geo.cut_cylinder(P[i, 0], P[i, 1], P[i, 2], P[i, 3], P[i, 4], P[i, 5])
        for j in range(6):
            out[i, j] = r[j]


def test_random_poses_against_quadrature():
    rng = np.random.default_rng(20240611)
    n = 60
    P = np.empty((n, 6))
    for i in range(n):
        L = rng.uniform(0.3, 3.0)
        R = rng.uniform(0.03, 0.5)
        chi = rng.uniform(-0.25, 0.25) * L
        kind = i % 4
        if kind == 0:
            a = rng.uniform(-1.0, 1.0)
        elif kind == 1:  # nearly horizontal
            a = rng.choice([-1.0, 1.0]) * 10.0 ** rng.uniform(-12, -1)
        elif kind == 2:  # nearly vertical
            a = rng.choice([-1.0, 1.0]) * (1.0 - 10.0 ** rng.uniform(-14, -1))
        else:
            a = rng.choice([-1.0, 0.0, 1.0])
        z_c = rng.uniform(-20.0, 5.0)
        z_min, z_max = geo.vertical_extent(L, R, chi, a, z_c)
        level = z_min + rng.uniform(-0.1, 1.1) * (z_max - z_min)
        P[i] = (L, R, chi, a, z_c, level)
    out = np.empty((n, 6))
    _eval_many(P, out)
    for i in range(n):
        L, R = P[i, 0], P[i, 1]
        _assert_close(_moments(out[i]), reference(*P[i]), L, R, tuple(P[i]))


# ---------------------------------------------------------------------------
# analytic cases and symmetries
# ---------------------------------------------------------------------------
def test_horizontal_buried_to_axis_is_half():
    L, R, chi = 2.0, 0.3, 0.13
    V, xc, eta, lat, cn, ct = geo.cut_cylinder(L, R, chi, 0.0, -5.0, -5.0)
    assert V == pytest.approx(0.5 * math.pi * R * R * L, rel=1e-13)
    assert xc == pytest.approx(-chi, rel=1e-13)
    assert eta == pytest.approx(4.0 * R / (3.0 * math.pi), rel=1e-13)  # half disk
    assert lat == pytest.approx(math.pi * R * L, rel=1e-13)
    assert cn == pytest.approx(0.5 * math.pi * R * R, rel=1e-13)
    assert ct == pytest.approx(0.5 * math.pi * R * R, rel=1e-13)
    pv, ph, pa, proud, pen = geo.burial_measures(L, R, chi, 0.0, -5.0, -5.0)
    assert (pv, ph, pa) == pytest.approx((50.0, 50.0, 50.0), rel=1e-13)
    assert proud == pytest.approx(R, rel=1e-13)
    assert pen == pytest.approx(R, rel=1e-13)


def test_vertical_cylinder_is_a_shorter_cylinder():
    L, R, chi = 1.0, 0.2, 0.1
    # nose down (a_z = -1): nose at z_c - (L/2 - chi); level 0.3 above it
    z_c = 0.0
    z_nose = z_c - (0.5 * L - chi)
    V, xc, eta, lat, cn, ct = geo.cut_cylinder(L, R, chi, -1.0, z_c, z_nose + 0.3)
    assert V == pytest.approx(math.pi * R * R * 0.3, rel=1e-13)
    assert xc == pytest.approx(0.5 * L - chi - 0.15, rel=1e-13)
    assert eta == 0.0
    assert lat == pytest.approx(2 * math.pi * R * 0.3, rel=1e-13)
    assert (cn, ct) == (pytest.approx(math.pi * R * R, rel=1e-15), 0.0)


@pytest.mark.parametrize("a", [-1.0, -0.7, -1e-6, 0.0, 0.35, 1.0 - 1e-9])
def test_symmetries(a):
    L, R, chi = 1.3, 0.22, 0.09
    vt = math.pi * R * R * L
    z_min, z_max = geo.vertical_extent(L, R, chi, a, 1.0)
    for f in (0.1, 0.45, 0.8):
        lev = z_min + f * (z_max - z_min)
        V, xc, eta, lat, cn, ct = geo.cut_cylinder(L, R, chi, a, 1.0, lev)
        # axis reversal: a -> -a, chi -> -chi mirrors x and swaps the caps
        V2, xc2, eta2, lat2, cn2, ct2 = geo.cut_cylinder(L, R, -chi, -a, 1.0, lev)
        assert V2 == pytest.approx(V, rel=1e-12)
        assert xc2 == pytest.approx(-xc, rel=1e-12, abs=1e-14)
        assert eta2 == pytest.approx(eta, rel=1e-12, abs=1e-14)
        assert (lat2, cn2, ct2) == pytest.approx((lat, ct, cn), rel=1e-12, abs=1e-15)
        # reflection through the plane: a -> -a, z_c -> 2 level - z_c turns
        # the part below into the part above of the original body
        V3, xc3, eta3, lat3, cn3, ct3 = geo.cut_cylinder(L, R, chi, -a, 2 * lev - 1.0, lev)
        assert V + V3 == pytest.approx(vt, rel=1e-12)
        assert V * xc + V3 * xc3 == pytest.approx(-chi * vt, rel=1e-12)
        assert V * eta == pytest.approx(V3 * eta3, rel=1e-12, abs=1e-15)
        assert lat + lat3 == pytest.approx(2 * math.pi * R * L, rel=1e-12)
        assert cn + cn3 == pytest.approx(math.pi * R * R, rel=1e-12)
        # common vertical shift changes nothing
        r4 = geo.cut_cylinder(L, R, chi, a, 1.0 + 7.5, lev + 7.5)
        assert r4 == pytest.approx((V, xc, eta, lat, cn, ct), rel=1e-9, abs=1e-12)


def test_empty_and_full():
    L, R, chi = 1.0, 0.2, 0.05
    for a in (-1.0, -0.3, 0.0, 0.6, 1.0):
        z_min, z_max = geo.vertical_extent(L, R, chi, a, 0.0)
        V, xc, eta, lat, cn, ct = geo.cut_cylinder(L, R, chi, a, 0.0, z_min - 1e-3)
        assert (V, eta, lat, cn, ct) == (0.0, 0.0, 0.0, 0.0, 0.0)
        assert -0.5 * L - chi <= xc <= 0.5 * L - chi
        V, xc, eta, lat, cn, ct = geo.cut_cylinder(L, R, chi, a, 0.0, z_max + 1e-3)
        assert V == pytest.approx(math.pi * R * R * L, rel=1e-14)
        assert xc == pytest.approx(-chi, rel=1e-12)
        assert eta == 0.0
        assert (lat, cn, ct) == pytest.approx(
            (2 * math.pi * R * L, math.pi * R * R, math.pi * R * R), rel=1e-14
        )
        # just touching the plane from above: nothing is below it
        pv, ph, pa, proud, pen = geo.burial_measures(L, R, chi, a, 0.0, z_min)
        assert (pv, ph, pa, pen) == (0.0, 0.0, 0.0, 0.0)
        assert proud == pytest.approx(z_max - z_min, rel=1e-14)


# ---------------------------------------------------------------------------
# vertical extent, burial measures, equivalent cylinder
# ---------------------------------------------------------------------------
def _rim_extent(L, R, chi, a, z_c, n=200001):
    """Brute force: heights of points on both end-cap rims, for an axis in
    the x-z plane with dip psi2 = -asin(a)."""
    psi2 = -math.asin(a)
    i_m = np.array([math.cos(psi2), 0.0, -math.sin(psi2)])
    u = np.array([math.sin(psi2), 0.0, math.cos(psi2)])  # normal to i_m
    v = np.array([0.0, 1.0, 0.0])
    phi = np.linspace(0.0, 2 * math.pi, n)
    zs = []
    for x in (-0.5 * L - chi, 0.5 * L - chi):
        zs.append(z_c + x * i_m[2] + R * (np.cos(phi) * u[2] + np.sin(phi) * v[2]))
    zs = np.concatenate(zs)
    return zs.min(), zs.max()


@pytest.mark.parametrize("a", [-1.0, -0.8, -0.2, 0.0, 0.4, 0.999, 1.0])
def test_vertical_extent_brute_force(a):
    L, R, chi, z_c = 1.7, 0.3, -0.12, -4.0
    lo, hi = geo.vertical_extent(L, R, chi, a, z_c)
    blo, bhi = _rim_extent(L, R, chi, a, z_c)
    assert lo == pytest.approx(blo, abs=1e-9)
    assert hi == pytest.approx(bhi, abs=1e-9)


@pytest.mark.parametrize("a", [-0.95, -0.4, 0.0, 0.15, 0.7, 1.0])
def test_burial_measures(a):
    L, R, chi, z_c = 1.4, 0.26, 0.08, -10.0
    blo, bhi = _rim_extent(L, R, chi, a, z_c)
    for f in (0.05, 0.37, 0.62, 0.93):
        level = blo + f * (bhi - blo)
        pv, ph, pa, proud, pen = geo.burial_measures(L, R, chi, a, z_c, level)
        V, Mx, Ms, lat, cn, ct = reference(L, R, chi, a, z_c, level)
        assert pv == pytest.approx(100 * V / (math.pi * R * R * L), rel=RTOL)
        assert ph == pytest.approx(100 * f, rel=RTOL)
        assert pa == pytest.approx(100 * (lat + cn + ct) / (2 * math.pi * R * (L + R)), rel=RTOL)
        assert proud == pytest.approx(bhi - level, rel=RTOL)
        assert pen == pytest.approx(level - blo, rel=RTOL)


@pytest.mark.parametrize("a", [-1.0, -0.5, 0.0, 0.2, 0.9])
def test_equivalent_cylinder(a):
    """The equivalent cylinder (seed 000 section 4.1) of the part below a plane, as the
    equations of motion build it: cut_cylinder, then equivalent_of_part."""
    L, R, chi = 1.5, 0.25, 0.1
    xt, xn = -0.5 * L - chi, 0.5 * L - chi
    z_min, z_max = geo.vertical_extent(L, R, chi, a, 0.0)
    for f in (0.1, 0.5, 0.9):
        level = z_min + f * (z_max - z_min)
        ref = reference(L, R, chi, a, 0.0, level)
        V, x_c, eta_c, _, _, _ = geo.cut_cylinder(L, R, chi, a, 0.0, level)
        l, xa, xb, eta = geo.equivalent_of_part(L, R, chi, V, x_c, eta_c)
        assert l == pytest.approx(ref[0] / (math.pi * R * R), rel=RTOL)
        assert xb - xa == pytest.approx(l, rel=1e-12, abs=1e-15)
        assert xt - 1e-12 <= xa and xb <= xn + 1e-12
        xc = ref[1] / ref[0]
        if xt + 1e-9 < xc - 0.5 * l and xc + 0.5 * l < xn - 1e-9:
            assert 0.5 * (xa + xb) == pytest.approx(xc, rel=RTOL, abs=1e-12)
        assert eta == pytest.approx(ref[2] / ref[0], rel=RTOL, abs=1e-12)


def test_equivalent_interval_is_shifted_not_shrunk():
    L, R, chi = 1.0, 0.1, 0.0
    l, xa, xb, eta = geo.equivalent_of_part(L, R, chi, math.pi * R * R * 0.6, -0.4, 0.0)
    assert (l, xa, xb) == pytest.approx((0.6, -0.5, 0.1), rel=1e-14)
    l, xa, xb, eta = geo.equivalent_of_part(L, R, chi, math.pi * R * R * 0.6, 0.45, 0.0)
    assert (l, xa, xb) == pytest.approx((0.6, -0.1, 0.5), rel=1e-14)


def test_e_down_body():
    rng = np.random.default_rng(3)
    for _ in range(50):
        q = rng.normal(size=4)
        q /= np.linalg.norm(q)
        q0, q1, q2, q3 = q
        # rotation body -> earth (scalar-first quaternion)
        Rm = np.array(
            [
                [1 - 2 * (q2 * q2 + q3 * q3), 2 * (q1 * q2 - q0 * q3), 2 * (q1 * q3 + q0 * q2)],
                [2 * (q1 * q2 + q0 * q3), 1 - 2 * (q1 * q1 + q3 * q3), 2 * (q2 * q3 - q0 * q1)],
                [2 * (q1 * q3 - q0 * q2), 2 * (q2 * q3 + q0 * q1), 1 - 2 * (q1 * q1 + q2 * q2)],
            ]
        )
        i_m = Rm[:, 0]
        k = np.array([0.0, 0.0, 1.0])
        e = -k + (k @ i_m) * i_m  # projection of -k normal to i_M
        e /= np.linalg.norm(e)
        kb = Rm.T @ k
        eb = np.array(geo.e_down_body(*kb))
        np.testing.assert_allclose(Rm @ eb, e, atol=1e-12)
        # a point s e_down of the cross-section is lower by b s
        assert (Rm @ eb)[2] == pytest.approx(-math.sqrt(1 - i_m[2] ** 2), abs=1e-12)
    assert geo.e_down_body(1.0, 0.0, 0.0) == (0.0, 0.0, 0.0)
