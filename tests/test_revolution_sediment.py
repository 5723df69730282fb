"""Tests of the sediment tractions and pore law of a body of revolution
(mineburial.kernels.mine.bodies.revolution_sediment).

References: the cylinder's fast rule itself (bit for bit for two stations of one radius; the
tapered rule at slope 0 to rounding); an independent midpoint rule over the surface, written
here from the geometry alone (points, normals and area elements from the parametrisation's
derivatives, the embedded and advancing elements by indicators) with the traction law of seed 000
section 6 (``laws._traction``), on a Manta-like frustum, a cone and a slender frustum at a few
poses and motions; the pore law's lever arm from the embedded span computed by hand.
"""

import math

import numpy as np
import pytest
from numba import njit
from test_sediment_kernel import params as _kernel_params

from mineburial.kernels.mine.bodies import revolution_sediment as rsed
from mineburial.kernels.mine.sediment import pack_law
from mineburial.kernels.mine.sediment.fast import _lateral, fast_tractions
from mineburial.kernels.mine.sediment.laws import LAW_REFERENCE_PATHS, _traction
from mineburial.kernels.mine.sediment.pore import pore_pressure

EMPTY_BANK = np.full((1, 3, 2), np.nan)


def _law(diameter, **kw):
    p = _kernel_params(**{"P_SED_QUADRATURE": 0, **kw})
    return pack_law(p, diameter)[:LAW_REFERENCE_PATHS]


def _c2(yaw, pitch, roll):
    """The E-frame vertical in the body frame for R = Rz(yaw) Ry(pitch) Rx(roll): the third row of R."""
    cy, sy = math.cos(yaw), math.sin(yaw)
    cp, sp = math.cos(pitch), math.sin(pitch)
    cr, sr = math.cos(roll), math.sin(roll)
    rz = np.array([[cy, -sy, 0], [sy, cy, 0], [0, 0, 1.0]])
    ry = np.array([[cp, 0, sp], [0, 1.0, 0], [-sp, 0, cp]])
    rx = np.array([[1.0, 0, 0], [0, cr, -sr], [0, sr, cr]])
    return tuple(float(v) for v in (rz @ ry @ rx)[2])


LAWS = {
    "delta": dict(P_SED_RESISTANCE=0),
    "friction": dict(P_SED_RESISTANCE=1),
    "bearing": dict(P_SED_RESISTANCE=2, P_SED_RATE_LAW=1),
}


@pytest.mark.parametrize("law_name", list(LAWS))
@pytest.mark.parametrize("seed", range(6))
def test_equal_radii_are_the_cylinders_fast_rule_bit_for_bit(law_name, seed):
    rng = np.random.default_rng(seed)
    L, R, chi = rng.uniform(0.5, 2.5), rng.uniform(0.1, 0.5), rng.uniform(-0.2, 0.2)
    xs = (-0.5 * L - chi, 0.5 * L - chi)
    c2 = _c2(*rng.uniform(-math.pi, math.pi, size=3))
    d0 = rng.uniform(-0.5, 0.5)
    vb = tuple(float(v) for v in np.concatenate([rng.normal(size=3), rng.normal(size=3)]))
    law = _law(2.0 * R, **LAWS[law_name])
    got = rsed.profile_tractions(xs, (R, R), *c2, d0, vb, law, EMPTY_BANK)
    ref = fast_tractions(L, R, chi, *c2, d0, vb, law, EMPTY_BANK)
    assert got == ref


@pytest.mark.parametrize("seed", range(8))
def test_tapered_rule_at_slope_zero_is_the_cylinders_to_rounding(seed):
    rng = np.random.default_rng(50 + seed)
    x0, x1, R = -0.7, 0.9, 0.3
    c2 = _c2(*rng.uniform(-math.pi, math.pi, size=3))
    d0 = rng.uniform(-0.3, 0.5)
    vb = tuple(float(v) for v in np.concatenate([rng.normal(size=3), rng.normal(size=3)]))
    law = _law(2.0 * R, P_SED_RESISTANCE=2, P_SED_RATE_LAW=1)
    got = np.array(rsed.tapered_lateral(x0, x1, R, R, d0, *c2, vb, law, EMPTY_BANK, True))
    ref = np.array(_lateral(R, x0, x1, d0, *c2, vb, law, EMPTY_BANK, True))
    # the same panels, the seabed/delta crossing breakpoints (issue 34 item 3) included; along a generator
    # the cylinder's rule takes 2 Gauss nodes with the ramp's product weights (issue 34 item 4), the
    # tapered rule 3 plain Gauss nodes (the ramp weights cost it 5 % on a cone with the delta law's
    # unramped friction, test_frustum_tractions_match_a_midpoint_rule_of_the_definition), so they agree to
    # their quadrature error: measured 0.013-0.175 % of the largest component (was 2.4e-16 with the
    # same nodes)
    np.testing.assert_allclose(got, ref, rtol=0.0, atol=5e-3 * (np.abs(ref).max() + 1e-300))


@njit(cache=False)
def _add(acc, x, y, z, nx, ny, nz, da, c2, d0, vb, law, bank):
    """Add the element at (x, y, z) with outward normal n and area da if embedded and advancing;
    also accumulates int |t| dA (acc[6]) and int |r||t| dA (acc[7]) for the error scales."""
    v1, v2, v3, w1, w2, w3 = vb
    zeta = d0 - (c2[0] * x + c2[1] * y + c2[2] * z)
    if zeta <= 0.0:
        return
    vn = (v1 + w2 * z - w3 * y) * nx + (v2 + w3 * x - w1 * z) * ny + (v3 + w1 * y - w2 * x) * nz
    if vn < 0.0:
        return
    g1, g2, g3 = _traction(x, y, z, nx, ny, nz, zeta, v1, v2, v3, w1, w2, w3, law, bank)
    acc[0] += da * g1
    acc[1] += da * g2
    acc[2] += da * g3
    acc[3] += da * (y * g3 - z * g2)
    acc[4] += da * (z * g1 - x * g3)
    acc[5] += da * (x * g2 - y * g1)
    t = math.sqrt(g1 * g1 + g2 * g2 + g3 * g3)
    acc[6] += da * t
    acc[7] += da * t * math.sqrt(x * x + y * y + z * z)


@njit(cache=False)
def _midpoint_reference(x0, x1, r0, r1, c2, d0, vb, law, bank, n):
    """Force, torque and the scales by an n x 2n midpoint rule on the lateral surface and n x 2n
    polar midpoint rules on the caps, from the parametrisation alone."""
    acc = np.zeros(8)
    nt = 2 * n
    dt = 2.0 * math.pi / nt
    dx = (x1 - x0) / n
    for i in range(n):
        u = (i + 0.5) / n
        x = x0 + (x1 - x0) * u
        r = r0 + (r1 - r0) * u
        drdx = (r1 - r0) / (x1 - x0)
        for j in range(nt):
            t = (j + 0.5) * dt
            c = math.cos(t)
            s = math.sin(t)
            # p_x = (1, r' c, r' s), p_t = (0, -r s, r c); p_t x p_x points outwards
            ax, ay, az = 1.0, drdx * c, drdx * s
            bx, by, bz = 0.0, -r * s, r * c
            nx = by * az - bz * ay
            ny = bz * ax - bx * az
            nz = bx * ay - by * ax
            norm = math.sqrt(nx * nx + ny * ny + nz * nz)
            if norm == 0.0:
                continue
            _add(acc, x, r * c, r * s, nx / norm, ny / norm, nz / norm, norm * dx * dt, c2, d0, vb, law, bank)
    for xc, rc, sgn in ((x1, r1, 1.0), (x0, r0, -1.0)):
        if rc <= 0.0:
            continue
        dr = rc / n
        for i in range(n):
            rr = (i + 0.5) * dr
            for j in range(nt):
                t = (j + 0.5) * dt
                _add(
                    acc,
                    xc,
                    rr * math.cos(t),
                    rr * math.sin(t),
                    sgn,
                    0.0,
                    0.0,
                    rr * dr * dt,
                    c2,
                    d0,
                    vb,
                    law,
                    bank,
                )
    return acc


#: (x0, x1, r0, r1): a Manta-like frustum (base 0.98 m, top 0.4 m, height 0.44 m, COM low), a cone,
#: a slender frustum
BODIES = {
    "manta": (-0.16, 0.28, 0.49, 0.20),
    "cone": (-0.12, 0.36, 0.45, 0.0),
    "slender": (-1.1, 0.9, 0.15, 0.32),
}
#: (yaw, pitch, roll), d0, (v1, v2, v3, w1, w2, w3): a base-down axial penetration with some tilt,
#: on the flank with a sideways slide and spin, nose down and rotating
POSES = [
    ((0.0, -1.45, 0.0), -0.05, (-0.1, 0.05, 0.0, 0.0, 0.3, 0.1)),
    ((0.3, 0.2, 0.4), 0.12, (0.2, -0.6, 0.4, 1.5, -0.4, 0.8)),
    ((1.0, 1.2, -0.7), -0.02, (0.8, 0.3, -0.2, 0.0, 1.2, -0.6)),
]


@pytest.mark.parametrize("body", list(BODIES))
@pytest.mark.parametrize("pose", range(len(POSES)))
@pytest.mark.parametrize("law_name", ["delta", "bearing"])
def test_frustum_tractions_match_a_midpoint_rule_of_the_definition(body, pose, law_name):
    x0, x1, r0, r1 = BODIES[body]
    angles, d0, vb = POSES[pose]
    c2 = _c2(*angles)
    # the velocity of the COM in the body frame, turned towards the seabed so that the body advances
    v = np.array(vb[:3])
    vb = (*(v - 0.5 * np.array(c2) * (abs(v).max() + 0.2)), *vb[3:])
    vb = tuple(float(a) for a in vb)
    law = _law(2.0 * max(r0, r1), **LAWS[law_name])
    got = np.array(rsed.profile_tractions((x0, x1), (r0, r1), *c2, d0, vb, law, EMPTY_BANK))
    ref = _midpoint_reference(x0, x1, r0, r1, np.array(c2), d0, vb, law, EMPTY_BANK, 600)
    assert ref[6] > 0.0, "the pose must embed part of the body"
    err_f = np.abs(got[:3] - ref[:3]).max() / ref[6]
    err_m = np.abs(got[3:] - ref[3:6]).max() / ref[7]
    # the cylinder's fast rule against its reference: every error below 5 %, the 90th percentile
    # below 1.5 % (docs/notes/sediment_fast.md section 3); the midpoint rule's own error here is
    # ~1e-3 (n = 600 vs 1200 on these poses)
    assert err_f < 0.02, (err_f, got, ref)
    assert err_m < 0.02, (err_m, got, ref)


def test_pore_law_equal_radii_and_the_frustums_lever_arm():
    law = _law(0.6, P_SED_PORE=1.0)
    L, R, chi = 1.6, 0.3, 0.1
    xs = (-0.5 * L - chi, 0.5 * L - chi)
    for c2, d0 in ((_c2(0.2, 0.5, 0.1), 0.3), (_c2(0.0, 0.0, 0.3), -0.1), (_c2(0.0, -0.9, 0.0), -0.2)):
        got = rsed.profile_pore_pressure(xs, (R, R), *c2, d0, 0.2, -0.8, law, EMPTY_BANK)
        ref = pore_pressure(L, R, chi, *c2, d0, 0.2, -0.8, law, EMPTY_BANK)
        np.testing.assert_allclose(got, ref, rtol=1e-13, atol=1e-13 * abs(ref[0]))
    # a frustum tilted nose down (c20 > 0 when the nose dips): the sections reach the seabed
    # where d0 - c20 x + r(x) rp > 0; with r linear that is x < x*, solved by hand
    x0, x1, r0, r1 = -0.2, 0.3, 0.49, 0.2
    c2 = _c2(0.0, -0.6, 0.0)  # nose up: c20 = -sin(0.6)... the sign is the test's own
    c20, c21, c22 = c2
    rp = math.hypot(c21, c22)
    d0 = -0.1
    k = (r1 - r0) / (x1 - x0)
    # f(x) = d0 - c20 x + (r0 + k (x - x0)) rp, linear: f = f0 + slope (x - x0)
    f0 = d0 - c20 * x0 + r0 * rp
    slope = -c20 + k * rp
    xs_root = x0 - f0 / slope
    lo, hi = (x0, min(x1, xs_root)) if slope < 0.0 else (max(x0, xs_root), x1)
    fpw, t2, t3, _ = rsed.profile_pore_pressure((x0, x1), (r0, r1), *c2, d0, 0.2, -0.8, law, EMPTY_BANK)
    xm = 0.5 * (lo + hi)
    assert x0 < xs_root < x1
    assert t2 == pytest.approx(-xm * fpw * c22, rel=1e-12, abs=1e-15)
    assert t3 == pytest.approx(xm * fpw * c21, rel=1e-12)
    # the rupture line is bounded by the largest diameter, the cylinder's 2R
    deep = rsed.profile_pore_pressure((x0, x1), (r0, r1), *c2, d0, 5.0, -0.8, law, EMPTY_BANK)
    deep_cyl = pore_pressure(0.5, r0, 0.0, *c2, d0, 5.0, -0.8, law, EMPTY_BANK)
    assert deep[0] == pytest.approx(deep_cyl[0], rel=1e-14)


def _largest_step(fun, s0, s1, n):
    """Largest change of the force and of the torque (relative to their largest value on the path)
    between neighbours of n + 1 equally spaced samples of s in [s0, s1] (tests/test_sediment_fast.py)."""
    out = np.array([fun(s) for s in np.linspace(s0, s1, n + 1)])
    d1 = np.abs(np.diff(out, axis=0))
    fs = np.max(np.linalg.norm(out[:, :3], axis=1))
    ms = np.max(np.linalg.norm(out[:, 3:], axis=1))
    assert fs > 0.0 and ms > 0.0
    return max(np.max(d1[:, :3]) / fs, np.max(d1[:, 3:]) / ms)


_MANTA = ((-0.16, 0.28), (0.49, 0.20))
#: paths in the state (the fast rule's point: no jumps), on the Manta-like frustum
TAPER_PATHS = {
    # first contact of the base's rim, tilted: the rim crosses the seabed near s = 0
    "seabed contact": (
        lambda s: ((0.9, 0.3, 0.3162), -0.16 * 0.9 - 0.49 * math.hypot(0.3, 0.3162) + s),
        -4e-3,
        6e-3,
    ),
    # on its flank, the seabed line sweeping from the base to the top
    "seabed line along the flank": (lambda s: ((0.3, 0.1, -0.9487), s), -0.2, 0.3),
}


@pytest.mark.parametrize("name", list(TAPER_PATHS))
def test_frustum_force_is_continuous_along_paths(name):
    """As the cylinder's fast rule (tests/test_sediment_fast.py): a tenfold finer sampling divides
    the largest step by 4 at least (by 1 if the force jumped) and no step exceeds 0.5 % of the scale."""
    case, s0, s1 = TAPER_PATHS[name]
    vb = (-0.4, 0.3, -0.6, 0.2, -0.5, 0.3)
    for model in (0, 2):
        law = _law(0.98, P_SED_RESISTANCE=model, P_SED_RATE_LAW=model % 3)

        def fun(s, law=law):
            c2, d0 = case(s)
            return np.array(rsed.profile_tractions(*_MANTA, *c2, d0, vb, law, EMPTY_BANK))

        coarse = _largest_step(fun, s0, s1, 300)
        fine = _largest_step(fun, s0, s1, 3000)
        assert fine < 0.25 * coarse, (name, model, coarse, fine)
        assert fine < 5e-3, (name, model, fine)


# -----------------------------------------------------------------------------
# The tapered rule's seabed / delta-line crossing breakpoints (the cylinder's issue 34 item 3)
# -----------------------------------------------------------------------------
def _trig2(t, c0, ca1, cb1, ca2, cb2):
    return c0 + ca1 * np.cos(t) + cb1 * np.sin(t) + ca2 * np.cos(2 * t) + cb2 * np.sin(2 * t)


def test_trig2_angles_are_the_real_zeros():
    """Every real zero of a random degree-2 trigonometric polynomial (scipy's brentq between sign
    changes on 20,000 samples) is one of the four angles of ``_trig2_angles`` (to 1e-8 rad)."""
    from scipy import optimize

    rng = np.random.default_rng(36)
    t = np.linspace(-np.pi, np.pi, 20001)
    found = 0
    for _ in range(200):
        args = tuple(rng.normal(size=5) * rng.choice([0.1, 1.0, 10.0], size=5))
        got = np.array(rsed._trig2_angles(*args))
        assert np.all(np.isfinite(got))
        f = _trig2(t, *args)
        for i in np.nonzero(np.sign(f[:-1]) * np.sign(f[1:]) < 0)[0]:
            z = optimize.brentq(_trig2, t[i], t[i + 1], args=args, xtol=1e-14)
            gap = np.abs(got - z) % (2 * np.pi)
            assert np.min(np.minimum(gap, 2 * np.pi - gap)) < 1e-8, (args, z, got)
            found += 1
    assert found > 200


def _lines(x, c, s, rho0, k, d0, c2, vb):
    """The depth and the normal velocity (times sqrt(1 + k^2)) at x on the generator (c, s)."""
    p = np.array([x, (rho0 + k * x) * c, (rho0 + k * x) * s])
    n = np.array([-k, c, s])
    v = vb[:3] + np.cross(vb[3:], p)
    return d0 - c2 @ p, v @ n


def test_crossing_coefficients_are_the_generators_a0_b1_minus_a1_b0():
    """The closed-form coefficients against the seabed and delta lines of a generator computed
    here from the geometry (depth d0 - c2 . p, normal velocity (v + w x p) . n sqrt(1 + k^2) with
    p = (x, r c, r s), n = (-k, c, s)/sqrt(1 + k^2)), both linear in x: a0 b1 - a1 b0 at 50 angles."""
    rng = np.random.default_rng(361)
    for _ in range(20):
        rho0, k, d0 = rng.uniform(0.1, 0.5), rng.uniform(-1.5, 1.5), rng.uniform(-0.5, 0.5)
        c2 = np.array(_c2(*rng.uniform(-math.pi, math.pi, size=3)))
        vb = rng.normal(size=6)
        coef = rsed.tapered_crossing_coefficients(rho0, k, d0, *c2, tuple(vb))
        for t in rng.uniform(-math.pi, math.pi, size=50):
            c, s = math.cos(t), math.sin(t)

            (z0, u0), (z1, u1) = (_lines(x, c, s, rho0, k, d0, c2, vb) for x in (0.0, 1.0))
            want = z0 * (u1 - u0) - (z1 - z0) * u0
            assert _trig2(t, *coef) == pytest.approx(want, rel=1e-10, abs=1e-12)


def _frustum_quad(xs, rs, c2, d0, vbody, p):
    """Independent reference (as tests/test_sediment_fast.py's ``quad_force_torque`` for the
    cylinder): scipy's adaptive ``quad_vec`` over the generator's angle (and a cap chord's y), on 16
    sub-intervals, of the exact inner integral over the embedded, advancing part of each line, by
    64-point Gauss pieces split at the line's point of least speed; the frustum's lateral point
    (x, r c, r s), normal (-k, c, s)/sqrt(1 + k^2), area r sqrt(1 + k^2) dx dt.
    Returns (F, M, int |t| dA, int |r||t| dA)."""
    from scipy import integrate
    from test_sediment_fast import _GW, _GX, _bearing_traction

    (x0, x1), (r0, r1) = xs, rs
    k = (r1 - r0) / (x1 - x0)
    rho0 = r0 - k * x0
    stretch = math.sqrt(1.0 + k * k)
    c2 = np.asarray(c2, float)
    vb, om = np.asarray(vbody[:3], float), np.asarray(vbody[3:], float)
    diameter = 2.0 * max(r0, r1)

    def clip_linear(lo, hi, f0, f1):
        if f1 > 0.0:
            return max(lo, -f0 / f1), hi
        if f1 < 0.0:
            return lo, min(hi, -f0 / f1)
        return (lo, hi) if f0 >= 0.0 else (lo, lo)

    def line(lo, hi, base, ax, nrm_of, weight_of):
        out = np.zeros(8)
        if not hi > lo:
            return out
        v0 = vb + np.cross(om, base)
        v1 = np.cross(om, ax)
        cuts = [-(v0 @ v1) / (v1 @ v1)] if v1 @ v1 > 0 else []
        edges = np.unique(np.clip(np.concatenate([[lo, hi], cuts]), lo, hi))
        for a, b in zip(edges[:-1], edges[1:]):
            u = 0.5 * (a + b) + 0.5 * (b - a) * _GX
            w = 0.5 * (b - a) * _GW * weight_of(u)
            r = base[:, None] + ax[:, None] * u[None, :]
            t = _bearing_traction(r, nrm_of(u), d0 - c2 @ r, vb, om, p, diameter)
            tn = np.sqrt(np.sum(t * t, axis=0))
            out += np.concatenate(
                [t @ w, np.cross(r, t, axis=0) @ w, [tn @ w], [(tn * np.sqrt(np.sum(r * r, axis=0))) @ w]]
            )
        return out

    def lateral(t):
        c, s = math.cos(t), math.sin(t)
        base = np.array([0.0, rho0 * c, rho0 * s])
        ax = np.array([1.0, k * c, k * s])
        nrm = np.array([-k, c, s]) / stretch
        lo, hi = clip_linear(x0, x1, d0 - c2 @ base, -(c2 @ ax))
        v0 = vb + np.cross(om, base)
        lo, hi = clip_linear(lo, hi, v0 @ nrm, np.cross(om, ax) @ nrm)
        return line(
            lo,
            hi,
            base,
            ax,
            lambda u: np.broadcast_to(nrm[:, None], (3, u.size)),
            lambda u: (rho0 + k * u) * stretch,
        )

    def cap(y, xc, r, sgn):
        h = math.sqrt(max(r * r - y * y, 0.0))
        base = np.array([xc, y, 0.0])
        ez = np.array([0.0, 0.0, 1.0])
        nrm = np.array([sgn, 0.0, 0.0])
        lo, hi = clip_linear(-h, h, d0 - c2 @ base, -c2[2])
        v0 = vb + np.cross(om, base)
        lo, hi = clip_linear(lo, hi, v0 @ nrm, np.cross(om, ez) @ nrm)
        return line(lo, hi, base, ez, lambda u: np.broadcast_to(nrm[:, None], (3, u.size)), lambda u: 1.0)

    tot = np.zeros(8)
    for i in range(16):
        a, b = 2 * np.pi * i / 16, 2 * np.pi * (i + 1) / 16
        tot += integrate.quad_vec(lateral, a, b, epsabs=1e-9, epsrel=1e-9, limit=400)[0]
    for xc, r, sgn in ((x1, r1, 1.0), (x0, r0, -1.0)):
        if r <= 0.0:
            continue
        for i in range(16):
            a, b = -r + 2 * r * i / 16, -r + 2 * r * (i + 1) / 16
            tot += integrate.quad_vec(
                lambda y, xc=xc, r=r, sgn=sgn: cap(y, xc, r, sgn), a, b, epsabs=1e-9, epsrel=1e-9, limit=400
            )[0]
    return tot[:3], tot[3:6], tot[6], tot[7]


#: frusta at the cylinder's slap poses (tests/test_sediment_fast.py SLAP_POSES): the slap's
#: 2.4 m mine tapered (tail radius 0.265, nose 0.18; the seabed 0.08 m higher, so that the thinner
#: nose still reaches into it) and flared (nose 0.35), slapping as the cylinder: (stations, radii,
#: the seabed's shift)
SLAP_FRUSTA = {
    "taper_to_nose": ((-1.2 + 0.018, 1.2 + 0.018), (0.265, 0.18), 0.08),
    "flare_to_nose": ((-1.2 + 0.018, 1.2 + 0.018), (0.265, 0.35), 0.0),
}


@pytest.mark.parametrize("body", list(SLAP_FRUSTA))
@pytest.mark.parametrize("pose", range(4))
def test_tapered_rotating_slap_matches_independent_quadrature(body, pose):
    """The frustum's fast rule (``profile_tractions``) against scipy's adaptive quadrature at the
    cylinder's slap poses (a thin embedded, advancing sliver between the seabed line and the
    delta line): force and torque within 2.5 % of their scales (int |t| dA, int |r||t| dA), the
    cylinder's fast-rule tolerance (tests/test_sediment_fast.py)."""
    from test_sediment_fast import SLAP_POSES, slap_params

    xs, rs, shift = SLAP_FRUSTA[body]
    c2, d0, vb = SLAP_POSES[pose]
    d0 += shift
    c2 = np.asarray(c2) / np.linalg.norm(c2)
    p = slap_params()
    F, M, sf, sm = _frustum_quad(xs, rs, c2, d0, vb, p)
    assert sf > 0.0
    law = pack_law(p, 2.0 * max(rs))[:LAW_REFERENCE_PATHS]
    got = np.array(rsed.profile_tractions(xs, rs, *(float(v) for v in c2), d0, tuple(vb), law, EMPTY_BANK))
    ef = np.linalg.norm(got[:3] - F) / sf
    em = np.linalg.norm(got[3:] - M) / sm
    assert ef < 0.025 and em < 0.025, (body, pose, ef, em, got, F, M)
