"""Tests of the sediment traction kernel (mineburial/kernels/mine/sediment.py).

The references are independent of the kernel's quadrature:

* ``reference_force_torque``: plain numpy, the traction laws written out again
  (vectorised), integrated by a uniform midpoint rule in the outer variable
  (theta on the lateral surface, u with y = R sin u on the caps; cells where the
  integrand jumps or kinks are re-integrated on 64 sub-cells) with exact inner
  limits from the linear switch conditions and a 16-point Gauss-Legendre rule
  inside (split where the circumferential slip reverses). It has none of the
  kernel's breakpoint machinery. Against a 16384 x 32 version of itself it is
  within 3e-4 of the force scale on 240 random cases (docs/notes/sediment.md).
* ``midpoint_force_torque``: a plain 2-D midpoint rule with indicator functions,
  which validates the reference itself.
* closed forms (axial penetration of a vertical cylinder; Archimedes for a slowly
  settling cylinder in a zero-strength sediment), rigid-body symmetry and frame
  invariance, and the rate laws, bearing factor, profiles and pore pressure at
  hand-computed points.
"""

import math

import numpy as np
import pytest
from scipy import integrate

from mineburial.kernels.mine import layout as lay
from mineburial.kernels.mine.bodies.cylinder import Cylinder
from mineburial.kernels.mine.sediment import rate_factor, sediment_force_torque, sediment_properties

# the regularisation speeds these tests pin (the defaults of version 0.1.0: slip 1 mm/s,
# advancing switch 0.1 mm/s), independent of numerics.slip_speed / switch_speed defaults
V_REG = 1.0e-3
V_REG_N = 1.0e-4
G = 9.81
RHO_W = 1025.0
SEABED = -20.0
EMPTY_BANK = np.full((1, 3, 2), np.nan)
TOL = 1e-3  # quadrature error allowed, relative to int |t| dA (and int |r||t| dA)


# -----------------------------------------------------------------------------
# helpers
# -----------------------------------------------------------------------------
def params(**kw):
    p = np.zeros(lay.N_PARAMS)
    p[lay.P_GRAVITY] = G
    p[lay.P_RHO_WATER] = RHO_W
    p[lay.P_SED_PROFILE] = -1
    p[lay.P_SED_RHO] = 1600.0
    p[lay.P_SED_RHO_GRAD] = 300.0
    p[lay.P_SED_S] = 2000.0
    p[lay.P_SED_S_GRAD] = 4000.0
    p[lay.P_SED_RESISTANCE] = 0
    p[lay.P_SED_RATE_LAW] = 0
    p[lay.P_SED_A] = 10.0
    p[lay.P_SED_VREST] = 0.04
    p[lay.P_SED_BETA] = 0.1
    p[lay.P_SED_RATE_REF] = 0.01 / 3600.0
    p[lay.P_SED_MU] = 0.3
    p[lay.P_SED_NC] = math.pi + 2.0
    p[lay.P_SED_DEPTH_FACTOR] = 0.4  # Brinch Hansen's (1970), the law these tests write out
    p[lay.P_SED_PORE] = 0.0
    p[lay.P_SED_B] = 0.1
    p[lay.P_SED_KP] = 1e-4
    p[lay.P_SED_EV] = 0.5
    # these tests guard the reference quadrature (tight tolerances); the fast rule is
    # tested against it in tests/test_sediment_fast.py
    p[lay.P_SED_QUADRATURE] = 1
    p[lay.P_SLIP_SPEED] = V_REG  # the regularisation these tests were written for
    p[lay.P_SWITCH_SPEED] = V_REG_N
    for key, value in kw.items():
        p[getattr(lay, key)] = value
    return p


def quat_matrix(q):
    q0, q1, q2, q3 = q / np.linalg.norm(q)
    return np.array(
        [
            [1 - 2 * (q2 * q2 + q3 * q3), 2 * (q1 * q2 - q0 * q3), 2 * (q1 * q3 + q0 * q2)],
            [2 * (q1 * q2 + q0 * q3), 1 - 2 * (q1 * q1 + q3 * q3), 2 * (q2 * q3 - q0 * q1)],
            [2 * (q1 * q3 - q0 * q2), 2 * (q2 * q3 + q0 * q1), 1 - 2 * (q1 * q1 + q2 * q2)],
        ]
    )


def ypr_matrix(yaw, pitch, roll):
    """R = Rz(yaw) Ry(pitch) Rx(roll) (docs/design.md: pitch = dip of the nose)."""
    cy, sy = math.cos(yaw), math.sin(yaw)
    cp, sp = math.cos(pitch), math.sin(pitch)
    cr, sr = math.cos(roll), math.sin(roll)
    rz = np.array([[cy, -sy, 0], [sy, cy, 0], [0, 0, 1.0]])
    ry = np.array([[cp, 0, sp], [0, 1.0, 0], [-sp, 0, cp]])
    rx = np.array([[1.0, 0, 0], [0, cr, -sr], [0, sr, cr]])
    return rz @ ry @ rx


def kernel_call(L, R, chi, C, com, vel, omega, p, bank=EMPTY_BANK):
    """(force E-frame, torque body-frame, added mass) from the kernel."""
    out = sediment_force_torque(
        Cylinder(L, R, chi),
        tuple(float(v) for v in C.ravel()),
        tuple(float(v) for v in com),
        tuple(float(v) for v in vel),
        tuple(float(v) for v in omega),
        SEABED,
        RHO_W,
        G,
        p,
        bank,
    )
    return np.array(out[:3]), np.array(out[3:6]), out[6]


# -----------------------------------------------------------------------------
# independent numpy implementation of the traction laws
# -----------------------------------------------------------------------------
def ref_profile(zeta, p, bank):
    """(rho_s, S, sigma') by np.interp and a fine cumulative trapezoid (bank) or closed form."""
    zeta = np.maximum(zeta, 0.0)
    row = int(p[lay.P_SED_PROFILE])
    if row < 0:
        rho = p[lay.P_SED_RHO] + p[lay.P_SED_RHO_GRAD] * zeta
        s = np.maximum(p[lay.P_SED_S] + p[lay.P_SED_S_GRAD] * zeta, 0.0)
        sig = G * ((p[lay.P_SED_RHO] - RHO_W) * zeta + 0.5 * p[lay.P_SED_RHO_GRAD] * zeta**2)
        return rho, s, sig
    d, r, st = bank[row]
    ok = ~np.isnan(d)
    d, r, st = d[ok], r[ok], st[ok]
    rho = np.interp(zeta, d, r)
    s = np.interp(zeta, d, st)
    # sigma' on a fine grid (cumulative trapezoid of the interpolated density) down to
    # the last tabulated depth, constant density below it
    fine = np.unique(np.concatenate([np.linspace(0.0, d[-1], 40001), d]))
    cum = integrate.cumulative_trapezoid(np.interp(fine, d, r) - RHO_W, fine, initial=0.0)
    sig = G * np.where(zeta <= d[-1], np.interp(zeta, fine, cum), cum[-1] + (r[-1] - RHO_W) * (zeta - d[-1]))
    return rho, s, sig


def ref_rate(speed, p, diameter):
    law = int(p[lay.P_SED_RATE_LAW])
    if law == 0:  # seed 000 eq. (70)
        a, vr = p[lay.P_SED_A], p[lay.P_SED_VREST]
        return a * (1.0 - (1.0 - 1.0 / a) * np.exp(-speed / vr))
    if law == 1:  # semi-log law, strain rate speed / diameter
        rate = speed / diameter
        return 1.0 + p[lay.P_SED_BETA] * np.log10(np.maximum(rate / p[lay.P_SED_RATE_REF], 1.0))
    return np.ones_like(speed)


def ref_traction(r, n, zeta, vb, om, p, bank, diameter):
    """Traction (body frame) on points r (3, ...) with normals n, where v.n >= 0."""
    v = vb.reshape(3, *([1] * (r.ndim - 1))) + np.stack(
        [om[1] * r[2] - om[2] * r[1], om[2] * r[0] - om[0] * r[2], om[0] * r[1] - om[1] * r[0]]
    )
    vn = np.sum(v * n, axis=0)
    vt = v - vn * n
    speed = np.sqrt(np.sum(v * v, axis=0))
    _, s, sig = ref_profile(zeta, p, bank)
    gf = ref_rate(speed, p, diameter)
    mu = p[lay.P_SED_MU]
    model = int(p[lay.P_SED_RESISTANCE])
    hn = np.where(vn > 0, vn / np.sqrt(vn * vn + V_REG_N**2), 0.0)  # regularised delta
    if model == 0:  # seed 000 eq. (74), effective overburden
        pn, ft = sig * hn, mu * gf * s
    elif model == 1:  # strength part of the normal traction, Coulomb friction
        pn = p[lay.P_SED_NC] * s * gf * hn
        ft = mu * pn
    else:  # bearing: N_c(zeta) with Brinch Hansen depth factor, adhesion mu S G
        nc = p[lay.P_SED_NC] * (1.0 + 0.4 * np.arctan(zeta / diameter))
        pn = nc * s * gf * hn
        ft = mu * s * gf
    k = ft / np.sqrt(np.sum(vt * vt, axis=0) + V_REG**2)
    return -pn * n - k * vt


def _moments(r, t, w):
    """Per outer point: weighted sums of force, torque, |t| and |r||t| (8 rows)."""
    tn = np.sqrt(np.sum(t * t, axis=0))
    rn = np.sqrt(np.sum(r * r, axis=0))
    return np.concatenate(
        [
            np.sum(t * w, axis=-1),
            np.sum(np.cross(r, t, axis=0) * w, axis=-1),
            np.sum(tn * w, axis=-1)[None],
            np.sum(rn * tn * w, axis=-1)[None],
        ]
    )


def _split_pieces(lo, hi, xt):
    """The two inner pieces [lo, xt], [xt, hi] (xt clipped; an empty piece has length 0)."""
    hi = np.maximum(hi, lo)
    xt = np.clip(xt, lo, hi)
    return ((lo, xt), (xt, hi))


def _lateral_integrand(th, geo, plist, bank, gx, gw):
    """Integral over x of the lateral-surface moments on generators th: (8 m, n)."""
    R, xa, xb, d0, k, vb, om = geo
    c, s = np.cos(th), np.sin(th)
    lo = np.full(th.shape, xa)
    hi = np.full(th.shape, xb)
    e0 = d0 - R * (k[1] * c + k[2] * s)  # zeta = e0 - k0 x
    if k[0] > 0:
        hi = np.minimum(hi, e0 / k[0])
    elif k[0] < 0:
        lo = np.maximum(lo, e0 / k[0])
    else:
        hi = np.where(e0 > 0, hi, lo)
    a0 = vb[1] * c + vb[2] * s  # v.n = a0 + a1 x
    a1 = om[2] * c - om[1] * s
    with np.errstate(divide="ignore", invalid="ignore"):
        xd = -a0 / a1
        lo = np.where(a1 > 0, np.maximum(lo, xd), lo)
        hi = np.where(a1 < 0, np.minimum(hi, xd), hi)
        hi = np.where((a1 == 0) & (a0 < 0), lo, hi)
        t0 = om[0] * R + vb[2] * c - vb[1] * s  # circumferential slip = t0 + t1 x
        t1 = -(om[1] * c + om[2] * s)
        xt = np.where(t1 != 0, -t0 / t1, hi)
    out = np.zeros((8 * len(plist), th.size))
    for a, b in _split_pieces(lo, hi, xt):
        x = 0.5 * (a + b)[:, None] + 0.5 * (b - a)[:, None] * gx[None, :]
        w = (0.5 * (b - a))[:, None] * gw[None, :] * R
        r = np.stack([x, np.broadcast_to(R * c[:, None], x.shape), np.broadcast_to(R * s[:, None], x.shape)])
        n = np.stack(
            [np.zeros_like(x), np.broadcast_to(c[:, None], x.shape), np.broadcast_to(s[:, None], x.shape)]
        )
        for i, p in enumerate(plist):
            t = ref_traction(r, n, e0[:, None] - k[0] * x, vb, om, p, bank, 2 * R)
            out[8 * i : 8 * i + 8] += _moments(r, t, w)
    return out


def _cap_integrand(u, geo, xc, sgn, plist, bank, gx, gw):
    """Integral over z of the cap moments on the lines y = R sin(u), times dy/du: (8 m, n)."""
    R, _, _, d0, k, vb, om = geo
    y = R * np.sin(u)
    dydu = R * np.cos(u)
    zlo = -R * np.cos(u)
    zhi = R * np.cos(u)
    ec = d0 - k[0] * xc - k[1] * y  # zeta = ec - k2 z
    if k[2] > 0:
        zhi = np.minimum(zhi, ec / k[2])
    elif k[2] < 0:
        zlo = np.maximum(zlo, ec / k[2])
    else:
        zhi = np.where(ec > 0, zhi, zlo)
    q0 = sgn * (vb[0] - om[2] * y)  # v.n = q0 + q1 z
    q1 = sgn * om[1]
    if q1 > 0:
        zlo = np.maximum(zlo, -q0 / q1)
    elif q1 < 0:
        zhi = np.minimum(zhi, -q0 / q1)
    else:
        zhi = np.where(q0 >= 0, zhi, zlo)
    zs = np.full_like(y, (vb[1] + om[2] * xc) / om[0]) if om[0] != 0 else zhi
    out = np.zeros((8 * len(plist), u.size))
    for a, b in _split_pieces(zlo, zhi, zs):  # split at the stagnation of the in-plane slip
        z = 0.5 * (a + b)[:, None] + 0.5 * (b - a)[:, None] * gx[None, :]
        w = (0.5 * (b - a) * dydu)[:, None] * gw[None, :]
        r = np.stack([np.full_like(z, xc), np.broadcast_to(y[:, None], z.shape), z])
        n = np.stack([np.full_like(z, sgn), np.zeros_like(z), np.zeros_like(z)])
        for i, p in enumerate(plist):
            t = ref_traction(r, n, ec[:, None] - k[2] * z, vb, om, p, bank, 2 * R)
            out[8 * i : 8 * i + 8] += _moments(r, t, w)
    return out


def refined_midpoint(fun, a, b, n0, nsub=32, max_frac=0.05, periodic=False):
    """Midpoint rule on n0 cells over the support of the integrand; the cells where it
    jumps or kinks (second difference above 1e-5 of the largest force or torque value
    of any of the stacked 8-row integrands; at most max_frac of the cells, largest
    first) and their neighbours are re-integrated with nsub sub-cells. The support is
    found on a first n0-cell pass (for a periodic integrand: the complement of the
    largest gap where it vanishes)."""
    h = (b - a) / n0
    mids = a + (np.arange(n0) + 0.5) * h
    vals = fun(mids)
    on = np.any(vals != 0.0, axis=0)
    if not on.any():
        return np.zeros(vals.shape[0])
    if periodic:
        off = ~on
        if off.any():
            # start the window after the longest run of empty cells (circularly)
            first = np.argmax(on)  # scan from an occupied cell
            best, best_end, cur = 0, 0, 0
            for k in range(1, n0 + 1):
                j = (first + k) % n0
                cur = cur + 1 if off[j] else 0
                if cur > best:
                    best, best_end = cur, j
            a = mids[best_end] + 0.5 * h
            b = a + (n0 - best + 2) * h
            a -= h
    else:
        idx = np.nonzero(on)[0]
        a, b = max(a, mids[idx[0]] - 1.5 * h), min(b, mids[idx[-1]] + 1.5 * h)
    h = (b - a) / n0
    mids = a + (np.arange(n0) + 0.5) * h
    vals = fun(mids)
    total = vals.sum(axis=1) * h
    d2 = np.abs(vals[:, :] * 0.0)
    d2[:, 1:-1] = np.abs(vals[:, :-2] - 2 * vals[:, 1:-1] + vals[:, 2:])
    d2[:, 0] = np.abs(vals[:, 1] - 2 * vals[:, 0])
    d2[:, -1] = np.abs(vals[:, -2] - 2 * vals[:, -1])
    d2n = np.zeros(n0)
    for g in range(vals.shape[0] // 8):
        for rows in (slice(8 * g, 8 * g + 3), slice(8 * g + 3, 8 * g + 6)):
            scale = np.max(np.abs(vals[rows])) + 1e-300
            d2n = np.maximum(d2n, np.max(d2[rows], axis=0) / scale)
    order = np.argsort(d2n)[::-1][: int(max_frac * n0)]
    flag = np.zeros(n0, bool)
    flag[order[d2n[order] > 1e-5]] = True
    flag[1:] |= flag[:-1].copy()
    flag[:-1] |= flag[1:].copy()
    idx = np.nonzero(flag)[0]
    if idx.size:
        sub = (mids[idx, None] - 0.5 * h + (np.arange(nsub)[None, :] + 0.5) * h / nsub).ravel()
        fine = fun(sub).reshape(vals.shape[0], idx.size, nsub).sum(axis=2) * (h / nsub)
        total += fine.sum(axis=1) - vals[:, idx].sum(axis=1) * h
    return total


def reference_force_torque(L, R, chi, C, com, vel, omega, plist, bank=EMPTY_BANK, n_outer=512, n_inner=16):
    """For each parameter vector of plist: force (E-frame), torque (body, about the COM)
    and the scales int |t| dA, int |r||t| dA."""
    xa, xb = -0.5 * L - chi, 0.5 * L - chi
    geo = (R, xa, xb, SEABED - com[2], C[2], C.T @ np.asarray(vel, float), np.asarray(omega, float))
    gx, gw = np.polynomial.legendre.leggauss(n_inner)
    tot = refined_midpoint(
        lambda th: _lateral_integrand(th, geo, plist, bank, gx, gw), 0.0, 2 * np.pi, n_outer, periodic=True
    )
    for xc, sgn in ((xb, 1.0), (xa, -1.0)):
        tot += refined_midpoint(
            lambda u, xc=xc, sgn=sgn: _cap_integrand(u, geo, xc, sgn, plist, bank, gx, gw),
            -0.5 * np.pi,
            0.5 * np.pi,
            n_outer,
        )
    return [
        (C @ tot[8 * i : 8 * i + 3], tot[8 * i + 3 : 8 * i + 6], tot[8 * i + 6], tot[8 * i + 7])
        for i in range(len(plist))
    ]


def midpoint_force_torque(L, R, chi, C, com, vel, omega, p, bank=EMPTY_BANK, n=800):
    """Plain n x n midpoint rules with indicator functions (lateral: x-theta; caps: y-z)."""
    xa, xb = -0.5 * L - chi, 0.5 * L - chi
    d0 = SEABED - com[2]
    vb = C.T @ np.asarray(vel, float)
    om = np.asarray(omega, float)
    k = C[2]
    F = np.zeros(3)
    M = np.zeros(3)

    def add(r, nrm, dA):
        zeta = d0 - (k[0] * r[0] + k[1] * r[1] + k[2] * r[2])
        v = vb.reshape(3, 1, 1) + np.cross(om.reshape(3, 1, 1), r, axis=0)
        on = (zeta > 0) & (np.sum(v * nrm, axis=0) >= 0)
        t = ref_traction(r, nrm, zeta, vb, om, p, bank, 2 * R) * on
        return ((t * dA).reshape(3, -1).sum(axis=1), (np.cross(r, t, axis=0) * dA).reshape(3, -1).sum(axis=1))

    x = xa + (np.arange(n) + 0.5) * L / n
    th = (np.arange(n) + 0.5) * 2 * np.pi / n
    X, TH = np.meshgrid(x, th, indexing="ij")
    r = np.stack([X, R * np.cos(TH), R * np.sin(TH)])
    nrm = np.stack([np.zeros_like(X), np.cos(TH), np.sin(TH)])
    f, m = add(r, nrm, np.full(X.shape, R * (L / n) * (2 * np.pi / n)))
    F += f
    M += m
    yy = -R + (np.arange(n) + 0.5) * 2 * R / n
    Y, Z = np.meshgrid(yy, yy, indexing="ij")
    inside = (Y * Y + Z * Z < R * R).astype(float)
    for xc, sgn in ((xb, 1.0), (xa, -1.0)):
        r = np.stack([np.full_like(Y, xc), Y, Z])
        nrm = np.stack([np.full_like(Y, sgn), np.zeros_like(Y), np.zeros_like(Y)])
        f, m = add(r, nrm, inside * (2 * R / n) ** 2)
        F += f
        M += m
    return C @ F, M


# -----------------------------------------------------------------------------
# random poses
# -----------------------------------------------------------------------------
def random_case(rng):
    """A random cylinder, orientation, immersion (seabed between its lowest and highest
    point) and motion: pure translation, rotation-dominated, nearly broadside (sharp
    reversal of the circumferential slip) or general, one in four each."""
    L = rng.uniform(0.3, 2.5)
    R = rng.uniform(0.05, 0.4)
    chi = rng.uniform(-0.15, 0.15) * L
    C = quat_matrix(rng.normal(size=4))
    k = C[2]
    xa, xb = -0.5 * L - chi, 0.5 * L - chi
    rperp = math.hypot(k[1], k[2])
    zlow = min(k[0] * xa, k[0] * xb) - R * rperp
    zhigh = max(k[0] * xa, k[0] * xb) + R * rperp
    level = rng.uniform(zlow, zhigh)
    com = np.array([rng.normal(), rng.normal(), SEABED - level])
    kind = rng.integers(4)
    vel = rng.normal(size=3) * rng.uniform(0.05, 4.0)
    omega = rng.normal(size=3) * rng.uniform(0.1, 6.0)
    if kind == 0:
        omega = np.zeros(3)
    elif kind == 1:
        vel = vel * 0.05
    elif kind == 2:
        vb = np.array([rng.normal() * 0.02, rng.normal(), rng.normal()])
        vel = C @ vb * rng.uniform(0.2, 4.0)
        omega = omega * 0.01
    return L, R, chi, C, com, vel, omega


BANK = np.full((2, 3, 8), np.nan)
BANK[0, :, :5] = [
    [0.0, 0.05, 0.15, 0.4, 1.2],
    [1300.0, 1450.0, 1600.0, 1700.0, 1800.0],
    [300.0, 900.0, 2500.0, 4000.0, 9000.0],
]
BANK[1, :, :3] = [[0.02, 0.3, 0.9], [1500.0, 1650.0, 1750.0], [1000.0, 3000.0, 6000.0]]


def _case_params(i):
    """Rate law, friction and profile cycled over the cases, for the three models."""
    common = dict(
        P_SED_RATE_LAW=i % 3, P_SED_MU=0.3 if i % 4 else 0.0, P_SED_PROFILE=-1 if i % 5 else (i // 5) % 2
    )
    return [params(P_SED_RESISTANCE=m, **common) for m in range(3)]


# -----------------------------------------------------------------------------
# (1) quadrature against the brute-force reference
# -----------------------------------------------------------------------------
def test_quadrature_matches_reference_on_random_poses():
    """50 random poses, immersions and motions, each with the three resistance models:
    force and torque within 0.1 % of the force scale int|t| dA (torque scale
    int |r||t| dA) of the reference."""
    rng = np.random.default_rng(20240601)
    n_checked = np.zeros(3, int)
    for i in range(50):
        case = random_case(rng)
        plist = _case_params(i)
        refs = reference_force_torque(*case, plist, BANK)
        for m, (p, (Fr, Mr, sf, sm)) in enumerate(zip(plist, refs)):
            F, M, _ = kernel_call(*case, p, BANK)
            if sf == 0.0:
                assert np.all(F == 0.0) and np.all(M == 0.0)
                continue
            ef = np.linalg.norm(F - Fr) / sf
            em = np.linalg.norm(M - Mr) / sm
            assert ef < TOL and em < TOL, (i, m, ef, em)
            n_checked[m] += 1
    assert np.all(n_checked >= 45), n_checked


def test_reference_matches_plain_midpoint_rule():
    """The reference itself against an 800 x 800 midpoint rule with indicator
    functions, whose error is first order in the cell size at the switch lines."""
    rng = np.random.default_rng(7)
    for i in range(2):
        case = random_case(rng)
        p = _case_params(i + 1)[i]
        Fr, Mr, sf, sm = reference_force_torque(*case, [p])[0]
        Fm, Mm = midpoint_force_torque(*case, p)
        assert np.linalg.norm(Fm - Fr) / sf < 3e-3
        assert np.linalg.norm(Mm - Mr) / sm < 3e-3


# -----------------------------------------------------------------------------
# (2) closed forms
# -----------------------------------------------------------------------------
@pytest.mark.parametrize("model", [0, 1, 2])
def test_axial_penetration_of_vertical_cylinder(model):
    """Nose-down vertical cylinder, fully embedded, moving straight down at V in a
    uniform sediment: the nose cap carries its normal traction at the nose depth
    D times pi R^2; the lateral surface (v.n = 0, regularised switch 0) carries no
    normal traction and, for delta and bearing, the side traction mu G S along the
    whole length; the tail cap recedes; no horizontal force, no torque."""
    L, R, chi, V, D = 1.2, 0.2, 0.1, 1.5, 2.0
    rho0, s0, mu, a, vrest = 1600.0, 3000.0, 0.3, 10.0, 0.04
    C = ypr_matrix(0.3, math.pi / 2, 0.7)  # i_M = -k
    xb = 0.5 * L - chi
    com = np.array([0.0, 0.0, SEABED - D + xb])  # nose at depth D
    p = params(
        P_SED_RESISTANCE=model,
        P_SED_RHO=rho0,
        P_SED_RHO_GRAD=0.0,
        P_SED_S=s0,
        P_SED_S_GRAD=0.0,
        P_SED_MU=mu,
        P_SED_A=a,
        P_SED_VREST=vrest,
    )
    F, M, _ = kernel_call(L, R, chi, C, com, (0.0, 0.0, -V), (0.0, 0.0, 0.0), p)
    g_v = a * (1 - (1 - 1 / a) * math.exp(-V / vrest))  # seed 000 eq. (70)
    h_n = V / math.sqrt(V * V + V_REG_N**2)  # advancing switch
    slip = V / math.sqrt(V * V + V_REG**2)  # regularised slip direction
    nc0 = math.pi + 2.0
    if model == 0:
        cap = (rho0 - RHO_W) * G * D * h_n
        side = mu * g_v * s0 * slip
    elif model == 1:
        cap = nc0 * s0 * g_v * h_n
        side = 0.0
    else:
        cap = nc0 * (1 + 0.4 * math.atan(D / (2 * R))) * s0 * g_v * h_n
        side = mu * s0 * g_v * slip
    fz = math.pi * R * R * cap + 2 * math.pi * R * L * side
    assert F[2] == pytest.approx(fz, rel=1e-9)
    assert abs(F[0]) + abs(F[1]) < 1e-9 * fz
    assert np.all(np.abs(M) < 1e-9 * fz * L)


def test_slow_settling_in_zero_strength_sediment_is_archimedes():
    """delta model, zero strength: a horizontal cylinder half embedded and sinking
    slowly (V = 0.05 m/s) carries sigma' h_n on its lower half only (which is all of
    its embedded part): the vertical force is the 1-D integral of that, and within
    2e-4 of Archimedes' (rho_s - rho_w) g pi R^2 L / 2; the torque about the COM is
    that of a force through the centre of volume (x = -chi)."""
    L, R, V = 1.4, 0.25, 0.05
    rho0 = 1650.0
    p = params(P_SED_RHO=rho0, P_SED_RHO_GRAD=0.0, P_SED_S=0.0, P_SED_S_GRAD=0.0)
    for chi, roll in ((0.0, 0.4), (0.12, -1.1)):
        C = ypr_matrix(0.8, 0.0, roll)
        com = np.array([0.0, 0.0, SEABED])
        F, M, _ = kernel_call(L, R, chi, C, com, (0.0, 0.0, -V), (0.0, 0.0, 0.0), p)
        # phi: angle from the lowest generator; depth R cos(phi), v.n = V cos(phi)

        def f(phi):
            vn = V * math.cos(phi)
            return (
                (rho0 - RHO_W) * G * R * math.cos(phi) * vn / math.hypot(vn, V_REG_N) * math.cos(phi) * R * L
            )

        fz = integrate.quad(f, -math.pi / 2, math.pi / 2, epsabs=0, epsrel=1e-12)[0]
        archimedes = (rho0 - RHO_W) * G * math.pi * R * R * L / 2
        assert F[2] == pytest.approx(fz, rel=1e-6)
        assert F[2] == pytest.approx(archimedes, rel=2e-4)
        assert abs(F[0]) + abs(F[1]) < 1e-6 * fz
        fb = C.T @ F
        assert np.allclose(M, np.cross([-chi, 0.0, 0.0], fb), atol=1e-9 * fz * L)


# -----------------------------------------------------------------------------
# (3) rigid-body consistency
# -----------------------------------------------------------------------------
@pytest.mark.parametrize("model", [0, 1, 2])
def test_symmetric_translation_torque_is_r_cross_f(model):
    """Horizontal cylinder (any roll) translating vertically: the pose and motion are
    symmetric about the mid-plane x = -chi and about the vertical plane through the
    axis, so the resultant is vertical through the centre of volume and the torque
    about the COM is (-chi i_M) x F."""
    L, R, chi = 1.1, 0.2, 0.17
    for roll, depth, w in ((0.3, 0.05, -2.0), (1.2, 0.3, -0.4), (2.5, 0.5, 0.7)):
        C = ypr_matrix(0.6, 0.0, roll)
        com = np.array([0.3, -0.2, SEABED - depth])
        p = params(P_SED_RESISTANCE=model)
        F, M, _ = kernel_call(L, R, chi, C, com, (0.0, 0.0, w), (0.0, 0.0, 0.0), p)
        scale = np.linalg.norm(F) + 1e-30
        # exact up to the quadrature error (its panels are not mirror-symmetric)
        assert abs(F[0]) + abs(F[1]) < 1e-5 * scale
        fb = C.T @ F
        assert np.allclose(M, np.cross([-chi, 0.0, 0.0], fb), atol=1e-4 * scale * R)


def test_rotation_about_the_vertical_rotates_the_force_only():
    """Turning pose and velocity about the vertical turns the E-frame force with them
    and leaves the body-frame torque unchanged (the sediment is horizontally uniform)."""
    rng = np.random.default_rng(3)
    for i in range(6):
        L, R, chi, C, com, vel, omega = random_case(rng)
        a = rng.uniform(0, 2 * np.pi)
        Rz = np.array([[math.cos(a), -math.sin(a), 0], [math.sin(a), math.cos(a), 0], [0, 0, 1.0]])
        p = _case_params(i)[i % 3]
        F1, M1, _ = kernel_call(L, R, chi, C, com, vel, omega, p, BANK)
        F2, M2, _ = kernel_call(L, R, chi, Rz @ C, Rz @ com, Rz @ vel, omega, p, BANK)
        scale = np.linalg.norm(F1) + 1e-30
        assert np.allclose(F2, Rz @ F1, atol=1e-6 * scale)
        assert np.allclose(M2, M1, atol=1e-6 * scale * L)


# -----------------------------------------------------------------------------
# (4) rate laws, bearing factor, profiles
# -----------------------------------------------------------------------------
def test_impact35_rate_law():
    """Seed 000 eq. (70): G(0) = 1, G -> A (eq. (71)), G(V_rest) = A - (A - 1)/e."""
    p = params(P_SED_RATE_LAW=0, P_SED_A=10.0, P_SED_VREST=0.04)
    assert rate_factor(0.0, 0.5, p) == pytest.approx(1.0, abs=1e-15)
    assert rate_factor(0.04, 0.5, p) == pytest.approx(10.0 - 9.0 / math.e, rel=1e-14)
    assert rate_factor(0.1, 0.5, p) == pytest.approx(9.26, abs=0.005)  # 10 - 9 exp(-2.5), by hand
    assert rate_factor(50.0, 0.5, p) == pytest.approx(10.0, rel=1e-14)


def test_semilog_rate_law():
    """G = 1 + beta log10(rate / rate_ref) above the reference rate, 1 below; rate = V/d."""
    p = params(P_SED_RATE_LAW=1, P_SED_BETA=0.15, P_SED_RATE_REF=1e-3)
    d = 0.5
    assert rate_factor(0.0, d, p) == 1.0
    assert rate_factor(0.5 * d * 1e-3, d, p) == 1.0
    assert rate_factor(d * 1e-3 * 1e4, d, p) == pytest.approx(1.6, rel=1e-14)
    assert rate_factor(2.0, d, p) == pytest.approx(1 + 0.15 * math.log10(4000.0), rel=1e-14)


def test_no_rate_law():
    p = params(P_SED_RATE_LAW=2)
    assert rate_factor(0.0, 0.3, p) == 1.0
    assert rate_factor(7.0, 0.3, p) == 1.0


def test_linear_profile():
    p = params(P_SED_RHO=1500.0, P_SED_RHO_GRAD=200.0, P_SED_S=1000.0, P_SED_S_GRAD=3000.0)
    rho, s, sig = sediment_properties(0.5, p, EMPTY_BANK)
    assert rho == pytest.approx(1600.0)
    assert s == pytest.approx(2500.0)
    # int_0^0.5 (1500 + 200 z - 1025) g dz = (475 * 0.5 + 100 * 0.25) g
    assert sig == pytest.approx((475 * 0.5 + 100 * 0.25) * G)
    assert sediment_properties(0.0, p, EMPTY_BANK) == pytest.approx((1500.0, 1000.0, 0.0))


def test_tabulated_profile():
    """Piecewise-linear interpolation, constant above the first and below the last point,
    sigma' exact (trapezoids of the linear density)."""
    bank = np.full((1, 3, 4), np.nan)
    bank[0, :, :3] = [[0.1, 0.3, 0.5], [1400.0, 1600.0, 1700.0], [500.0, 1500.0, 4000.0]]
    p = params(P_SED_PROFILE=0)
    rho, s, sig = sediment_properties(0.05, p, bank)
    assert (rho, s) == (1400.0, 500.0)
    assert sig == pytest.approx((1400 - RHO_W) * 0.05 * G)
    rho, s, sig = sediment_properties(0.2, p, bank)
    assert rho == pytest.approx(1500.0) and s == pytest.approx(1000.0)
    # 0.1 m at 1400, then 0.1 m from 1400 to 1500 (mean 1450)
    assert sig == pytest.approx(((1400 - RHO_W) * 0.1 + (1450 - RHO_W) * 0.1) * G)
    rho, s, sig = sediment_properties(0.9, p, bank)
    assert (rho, s) == (1700.0, 4000.0)
    expect = (1400 - RHO_W) * 0.1 + (1500 - RHO_W) * 0.2 + (1650 - RHO_W) * 0.2 + (1700 - RHO_W) * 0.4
    assert sig == pytest.approx(expect * G)


# -----------------------------------------------------------------------------
# pore pressure and degenerate inputs
# -----------------------------------------------------------------------------
def test_pore_pressure_force_and_added_mass():
    """Seed 000 eq. (73) with the sign that resists the vertical motion: F_z =
    -pi/8 rho_s(zeta_tip) g w / k_p B^3 and added mass pi/8 rho_s (1 + e)/e B^3, with
    B = min(B_set, tip depth, diameter)."""
    L, R, chi = 1.0, 0.15, 0.0
    C = ypr_matrix(0.0, math.pi / 2, 0.0)  # nose down
    rho0, krho, kp, ev = 1500.0, 400.0, 1e-4, 0.6
    for b_set, tip in ((0.1, 0.05), (0.1, 0.25), (5.0, 0.6)):
        com = np.array([0.0, 0.0, SEABED - tip + 0.5 * L])
        base = dict(
            P_SED_RHO=rho0,
            P_SED_RHO_GRAD=krho,
            P_SED_S=0.0,
            P_SED_S_GRAD=0.0,
            P_SED_KP=kp,
            P_SED_EV=ev,
            P_SED_B=b_set,
            P_SED_MU=0.0,
        )
        w = -0.7
        F_on, M_on, m_on = kernel_call(
            L, R, chi, C, com, (0, 0, w), (0, 0, 0), params(P_SED_PORE=1.0, **base)
        )
        F_off, M_off, m_off = kernel_call(
            L, R, chi, C, com, (0, 0, w), (0, 0, 0), params(P_SED_PORE=0.0, **base)
        )
        b = min(b_set, tip, 2 * R)
        rho_tip = rho0 + krho * tip
        assert m_off == 0.0
        assert m_on == pytest.approx(math.pi / 8 * rho_tip * (1 + ev) / ev * b**3, rel=1e-12)
        fpw = -math.pi / 8 * rho_tip * G * w / kp * b**3
        assert fpw > 0  # resists penetration
        assert F_on - F_off == pytest.approx([0.0, 0.0, fpw], rel=1e-12, abs=1e-9 * fpw)
        assert np.allclose(M_on, M_off, atol=1e-9 * fpw * L)  # vertical axis: no arm


def test_degenerate_poses_are_finite():
    """Exactly vertical and horizontal bodies, rest, pure spin, fully buried and fully
    above the seabed: finite results, zero when out of the sediment or at rest."""
    L, R, chi = 1.0, 0.2, 0.05
    p = params(P_SED_RESISTANCE=2, P_SED_RATE_LAW=1)
    poses = [
        ypr_matrix(0, math.pi / 2, 0),
        ypr_matrix(0, -math.pi / 2, 0.3),
        ypr_matrix(0.4, 0.0, 0.0),
        ypr_matrix(0, 0.0, math.pi / 2),
        np.eye(3),
    ]
    motions = [
        ((0, 0, 0), (0, 0, 0)),
        ((0, 0, -1.0), (0, 0, 0)),
        ((0, 0, 0), (3.0, 0, 0)),
        ((0.2, 0, -1.0), (0, 0.5, 0)),
        ((0, 1e-12, -1e-9), (0, 0, 1e-10)),
    ]
    for C in poses:
        for depth in (-1.0, 0.0, 0.1, 0.3, 5.0):
            com = np.array([0.0, 0.0, SEABED - depth])
            for vel, om in motions:
                F, M, m = kernel_call(L, R, chi, C, com, vel, om, p, BANK)
                assert np.all(np.isfinite(F)) and np.all(np.isfinite(M)) and np.isfinite(m)
                if depth == -1.0 or (not np.any(vel) and not np.any(om)):
                    assert np.all(F == 0.0) and np.all(M == 0.0)
