"""Tests of the sediment traction kernels (mineburial/kernels/sediment.py).

The references here are independent of the kernel's quadrature:

* ``reference_force_torque``: plain numpy, the same traction laws written out
  again (vectorised), integrated by a fine *uniform* midpoint rule in the outer
  variable (theta on the lateral surface, u with y = R sin u on the caps) with
  exact inner limits from the linear switch conditions and a 16-point
  Gauss-Legendre rule inside. It has none of the kernel's breakpoint machinery.
* ``midpoint_force_torque``: a plain 2-D midpoint rule with indicator functions
  (the "brute force"), used to validate the reference itself.
* closed forms (Archimedes, end-bearing on a vertical cylinder), a volume
  integral with scipy for the at-rest case, rigid-body symmetry, and the
  rate laws at hand-computed points.
"""

import math

import numpy as np
import pytest
from scipy import integrate

from mineburial.kernels import layout as lay
from mineburial.kernels.sediment import (V_REG, V_REG_N, bearing_factor, rate_factor,
                                         sediment_force_torque, sediment_properties)

G = 9.81
RHO_W = 1025.0
SEABED = -20.0
EMPTY_BANK = np.full((1, 3, 2), np.nan)


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
    p[lay.P_SED_PORE] = 0.0
    p[lay.P_SED_B] = 0.1
    p[lay.P_SED_KP] = 1e-4
    p[lay.P_SED_EV] = 0.5
    for key, value in kw.items():
        p[getattr(lay, key)] = value
    return p


def quat_matrix(q):
    q0, q1, q2, q3 = q / np.linalg.norm(q)
    return np.array([
        [1 - 2 * (q2 * q2 + q3 * q3), 2 * (q1 * q2 - q0 * q3), 2 * (q1 * q3 + q0 * q2)],
        [2 * (q1 * q2 + q0 * q3), 1 - 2 * (q1 * q1 + q3 * q3), 2 * (q2 * q3 - q0 * q1)],
        [2 * (q1 * q3 - q0 * q2), 2 * (q2 * q3 + q0 * q1), 1 - 2 * (q1 * q1 + q2 * q2)]])


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
    out = sediment_force_torque(L, R, chi, tuple(float(v) for v in C.ravel()),
                                tuple(float(v) for v in com), tuple(float(v) for v in vel),
                                tuple(float(v) for v in omega), SEABED, RHO_W, G, p, bank)
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
        sig = G * ((p[lay.P_SED_RHO] - RHO_W) * zeta + 0.5 * p[lay.P_SED_RHO_GRAD] * zeta ** 2)
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
    sig = G * np.where(zeta <= d[-1], np.interp(zeta, fine, cum),
                       cum[-1] + (r[-1] - RHO_W) * (zeta - d[-1]))
    return rho, s, sig


def ref_rate(speed, p, diameter):
    law = int(p[lay.P_SED_RATE_LAW])
    if law == 0:
        a, vr = p[lay.P_SED_A], p[lay.P_SED_VREST]
        return a * (1.0 - (1.0 - 1.0 / a) * np.exp(-speed / vr))
    if law == 1:
        rate = speed / diameter
        return 1.0 + p[lay.P_SED_BETA] * np.log10(np.maximum(rate / p[lay.P_SED_RATE_REF], 1.0))
    return np.ones_like(speed)


def ref_traction(r, n, zeta, vb, om, p, bank, diameter):
    """Traction (body frame) on points r (3, ...) with normals n, where delta = 1."""
    v = vb.reshape(3, *([1] * (r.ndim - 1))) + np.stack([
        om[1] * r[2] - om[2] * r[1], om[2] * r[0] - om[0] * r[2], om[0] * r[1] - om[1] * r[0]])
    vn = np.sum(v * n, axis=0)
    vt = v - vn * n
    speed = np.sqrt(np.sum(v * v, axis=0))
    rho, s, sig = ref_profile(zeta, p, bank)
    gf = ref_rate(speed, p, diameter)
    mu = p[lay.P_SED_MU]
    model = int(p[lay.P_SED_RESISTANCE])
    hn = np.where(vn > 0, vn / np.sqrt(vn * vn + V_REG_N ** 2), 0.0)   # regularised delta
    if model == 0:        # seed 000 eq. (74), effective overburden
        pn, ft = sig * hn, mu * gf * s
    elif model == 1:      # strength part of the normal traction, Coulomb friction
        pn = p[lay.P_SED_NC] * s * gf * hn
        ft = mu * pn
    else:                 # bearing: N_c(zeta) with Brinch Hansen depth factor, adhesion mu S G
        nc = p[lay.P_SED_NC] * (1.0 + 0.4 * np.arctan(zeta / diameter))
        pn = nc * s * gf * hn
        ft = mu * s * gf
    k = ft / np.sqrt(np.sum(vt * vt, axis=0) + V_REG ** 2)
    return -pn * n - k * vt


def _moments(r, t, w):
    """Sum over the last axis of weighted force, torque, |t| and |r||t| (per outer point)."""
    tn = np.sqrt(np.sum(t * t, axis=0))
    rn = np.sqrt(np.sum(r * r, axis=0))
    return np.concatenate([np.sum(t * w, axis=-1), np.sum(np.cross(r, t, axis=0) * w, axis=-1),
                           np.sum(tn * w, axis=-1)[None], np.sum(rn * tn * w, axis=-1)[None]])


def _split_pieces(lo, hi, xt):
    """The two inner pieces [lo, xt], [xt, hi] (xt clipped; an empty piece has length 0)."""
    hi = np.maximum(hi, lo)
    xt = np.clip(xt, lo, hi)
    return ((lo, xt), (xt, hi))


def _lateral_integrand(th, geo, p, bank, gx, gw):
    """Integral over x of the lateral-surface moments on generators th (array): (8, n)."""
    R, xa, xb, d0, k, vb, om = geo
    c, s = np.cos(th), np.sin(th)
    lo = np.full(th.shape, xa)
    hi = np.full(th.shape, xb)
    e0 = d0 - R * (k[1] * c + k[2] * s)          # zeta = e0 - k0 x
    if k[0] > 0:
        hi = np.minimum(hi, e0 / k[0])
    elif k[0] < 0:
        lo = np.maximum(lo, e0 / k[0])
    else:
        hi = np.where(e0 > 0, hi, lo)
    a0 = vb[1] * c + vb[2] * s                   # v.n = a0 + a1 x
    a1 = om[2] * c - om[1] * s
    with np.errstate(divide="ignore", invalid="ignore"):
        xd = -a0 / a1
        lo = np.where(a1 > 0, np.maximum(lo, xd), lo)
        hi = np.where(a1 < 0, np.minimum(hi, xd), hi)
        hi = np.where((a1 == 0) & (a0 < 0), lo, hi)
        t0 = om[0] * R + vb[2] * c - vb[1] * s   # circumferential slip = t0 + t1 x
        t1 = -(om[1] * c + om[2] * s)
        xt = np.where((p[lay.P_SED_MU] != 0) & (t1 != 0), -t0 / t1, hi)
    out = np.zeros((8, th.size))
    for a, b in _split_pieces(lo, hi, xt):
        x = 0.5 * (a + b)[:, None] + 0.5 * (b - a)[:, None] * gx[None, :]
        w = (0.5 * (b - a))[:, None] * gw[None, :] * R
        r = np.stack([x, np.broadcast_to(R * c[:, None], x.shape),
                      np.broadcast_to(R * s[:, None], x.shape)])
        n = np.stack([np.zeros_like(x), np.broadcast_to(c[:, None], x.shape),
                      np.broadcast_to(s[:, None], x.shape)])
        t = ref_traction(r, n, e0[:, None] - k[0] * x, vb, om, p, bank, 2 * R)
        out += _moments(r, t, w)
    return out


def _cap_integrand(u, geo, xc, sgn, p, bank, gx, gw):
    """Integral over z of the cap moments on the lines y = R sin(u) (times dy/du): (8, n)."""
    R, xa, xb, d0, k, vb, om = geo
    y = R * np.sin(u)
    dydu = R * np.cos(u)
    zlo = -R * np.cos(u)
    zhi = R * np.cos(u)
    ec = d0 - k[0] * xc - k[1] * y               # zeta = ec - k2 z
    if k[2] > 0:
        zhi = np.minimum(zhi, ec / k[2])
    elif k[2] < 0:
        zlo = np.maximum(zlo, ec / k[2])
    else:
        zhi = np.where(ec > 0, zhi, zlo)
    q0 = sgn * (vb[0] - om[2] * y)               # v.n = q0 + q1 z
    q1 = sgn * om[1]
    if q1 > 0:
        zlo = np.maximum(zlo, -q0 / q1)
    elif q1 < 0:
        zhi = np.minimum(zhi, -q0 / q1)
    else:
        zhi = np.where(q0 >= 0, zhi, zlo)
    if p[lay.P_SED_MU] != 0 and om[0] != 0:      # stagnation point of the in-plane slip
        zs = np.full_like(y, (vb[1] + om[2] * xc) / om[0])
    else:
        zs = zhi
    out = np.zeros((8, u.size))
    for a, b in _split_pieces(zlo, zhi, zs):
        z = 0.5 * (a + b)[:, None] + 0.5 * (b - a)[:, None] * gx[None, :]
        w = (0.5 * (b - a) * dydu)[:, None] * gw[None, :]
        r = np.stack([np.full_like(z, xc), np.broadcast_to(y[:, None], z.shape), z])
        n = np.stack([np.full_like(z, sgn), np.zeros_like(z), np.zeros_like(z)])
        t = ref_traction(r, n, ec[:, None] - k[2] * z, vb, om, p, bank, 2 * R)
        out += _moments(r, t, w)
    return out


def refined_midpoint(fun, a, b, n0, nsub=64, max_frac=0.1):
    """Midpoint rule on n0 cells; the cells where the integrand jumps or kinks (second
    difference above 1e-5 of the largest force or torque value; at most max_frac of
    the cells, largest first) and their neighbours are re-integrated with nsub
    sub-cells."""
    h = (b - a) / n0
    mids = a + (np.arange(n0) + 0.5) * h
    vals = fun(mids)
    total = vals.sum(axis=1) * h
    d2 = np.abs(np.roll(vals, 1, axis=1) - 2 * vals + np.roll(vals, -1, axis=1))
    fs = np.max(np.abs(vals[:3])) + 1e-300
    ms = np.max(np.abs(vals[3:6])) + 1e-300
    d2n = np.maximum(np.max(d2[:3], axis=0) / fs, np.max(d2[3:6], axis=0) / ms)
    order = np.argsort(d2n)[::-1][:int(max_frac * n0)]
    flag = np.zeros(n0, bool)
    flag[order[d2n[order] > 1e-5]] = True
    flag = flag | np.roll(flag, 1) | np.roll(flag, -1)
    idx = np.nonzero(flag)[0]
    if idx.size:
        sub = (mids[idx, None] - 0.5 * h + (np.arange(nsub)[None, :] + 0.5) * h / nsub).ravel()
        fine = fun(sub).reshape(8, idx.size, nsub).sum(axis=2) * (h / nsub)
        total += fine.sum(axis=1) - vals[:, idx].sum(axis=1) * h
    return total


def reference_force_torque(L, R, chi, C, com, vel, omega, p, bank=EMPTY_BANK, n_outer=2048,
                           n_inner=16, surfaces=("lateral", "nose", "tail")):
    """Force (E-frame), torque (body, about the COM) and the scales int|t| dA, int |r||t| dA.

    Outer variable (theta on the lateral surface, u with y = R sin u on the caps):
    midpoint rule with local refinement at jumps and kinks; inner variable: exact
    limits from the linear switch conditions, split at the slip reversal, Gauss-Legendre.
    """
    xa, xb = -0.5 * L - chi, 0.5 * L - chi
    geo = (R, xa, xb, SEABED - com[2], C[2], C.T @ np.asarray(vel, float),
           np.asarray(omega, float))
    gx, gw = np.polynomial.legendre.leggauss(n_inner)
    tot = np.zeros(8)
    if "lateral" in surfaces:
        tot += refined_midpoint(lambda th: _lateral_integrand(th, geo, p, bank, gx, gw),
                                0.0, 2 * np.pi, n_outer)
    for xc, sgn, name in ((xb, 1.0, "nose"), (xa, -1.0, "tail")):
        if name in surfaces:
            tot += refined_midpoint(lambda u: _cap_integrand(u, geo, xc, sgn, p, bank, gx, gw),
                                    -0.5 * np.pi, 0.5 * np.pi, n_outer)
    return C @ tot[:3], tot[3:6], tot[6], tot[7]


def _accumulate(r, t, w):
    f = (t * w).reshape(3, -1).sum(axis=1)
    m = (np.cross(r, t, axis=0) * w).reshape(3, -1).sum(axis=1)
    return f, m, 0.0, 0.0


def midpoint_force_torque(L, R, chi, C, com, vel, omega, p, bank=EMPTY_BANK, n=1000):
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
        f, m, _, _ = _accumulate(r, t, dA)
        return f, m

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
    L = rng.uniform(0.3, 2.5)
    R = rng.uniform(0.05, 0.4)
    chi = rng.uniform(-0.15, 0.15) * L
    C = quat_matrix(rng.normal(size=4))
    k = C[2]
    xa, xb = -0.5 * L - chi, 0.5 * L - chi
    rperp = math.hypot(k[1], k[2])
    zlow = min(k[0] * xa, k[0] * xb) - R * rperp
    zhigh = max(k[0] * xa, k[0] * xb) + R * rperp
    # seabed level between the lowest and the highest point of the body
    level = rng.uniform(zlow, zhigh)
    com = np.array([rng.normal(), rng.normal(), SEABED - level])
    kind = rng.integers(4)
    vel = rng.normal(size=3) * rng.uniform(0.05, 4.0)
    omega = rng.normal(size=3) * rng.uniform(0.1, 6.0)
    if kind == 0:
        omega = np.zeros(3)                 # pure translation
    elif kind == 1:
        vel = vel * 0.05                    # rotation dominated
    elif kind == 2:
        # nearly broadside translation: sharp reversal of the circumferential slip
        vb = np.array([rng.normal() * 0.02, rng.normal(), rng.normal()])
        vel = C @ vb * rng.uniform(0.2, 4.0)
        omega = omega * 0.01
    return L, R, chi, C, com, vel, omega


BANK = np.full((2, 3, 8), np.nan)
BANK[0, :, :5] = [[0.0, 0.05, 0.15, 0.4, 1.2],
                  [1300.0, 1450.0, 1600.0, 1700.0, 1800.0],
                  [300.0, 900.0, 2500.0, 4000.0, 9000.0]]
BANK[1, :, :3] = [[0.02, 0.3, 0.9], [1500.0, 1650.0, 1750.0], [1000.0, 3000.0, 6000.0]]
