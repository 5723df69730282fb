"""The right-hand side's body cuts taken fewer times at unchanged answers (issue 34 item 4).

* The overburden's first slice starts at the seabed, where the right-hand side has cut the body
  already (``dynamics._immersed_parts``): :func:`overburden.overburden_below` takes that cut.
* Its last slice ends at the body's lowest point, where the cut is empty, or (rounding) a sliver
  of ~1e-37 m^3: :func:`geometry.cut_cylinder_sliver` tells these apart without cutting and bounds
  the sliver, and ``overburden._exact`` leaves the cut out where that cannot change a bit.
* The Gauss rule of the cut's short kappa ranges takes one sine of each angle.

References: the slicing rule written out in Python with a cut at every boundary (the rule before
these changes, float for float), the cut itself (``geometry.cut_cylinder``: the sliver's kinds and
bound), the sliver's exact volume by mpmath at 50 digits, and the segment area's closed form.
"""

import math
import pathlib

import mpmath
import numpy as np
import pytest

from mineburial.kernels.mine import layout
from mineburial.kernels.mine import overburden as ob
from mineburial.kernels.mine.bodies.cylinder import Cylinder
from mineburial.kernels.mine.geometry import (
    cut_cylinder,
    cut_cylinder_sliver,
    segment_area_unit,
    vertical_extent,
)
from mineburial.kernels.mine.sediment.laws import drop_bank, pack_law
from mineburial.systems.mine.config import Scenario

DEFAULT = pathlib.Path(__file__).resolve().parents[1] / "mineburial" / "data" / "default_mine.toml"
RHO_W = 1025.0
G = 9.81
SEABED = -12.3


def _bits(x):
    return np.float64(x).view(np.int64)


def _states(rng, n):
    """Cylinders and attitudes: a_z uniform, exactly vertical, horizontal and near-vertical."""
    out = []
    for i in range(n):
        L = rng.uniform(0.5, 3.0)
        R = rng.uniform(0.1, 0.6)
        chi = rng.uniform(-0.2, 0.2)
        a_z = rng.uniform(-1.0, 1.0)
        if i % 17 == 0:
            a_z = float(rng.choice([-1.0, 1.0, 0.0, -0.0]))
        elif i % 13 == 0:
            a_z = math.copysign(1.0 - 10.0 ** rng.uniform(-16, -6), a_z)
        out.append((L, R, chi, a_z))
    return out


def test_segment_area_against_the_closed_form():
    """theta - sin(theta) cos(theta) = (2 theta - sin 2 theta)/2 at 50 digits (seed 000 eq. (25a))."""
    mpmath.mp.dps = 50
    for theta in np.concatenate([np.geomspace(1e-9, 0.34, 40), np.linspace(0.35, math.pi, 40)]):
        t = mpmath.mpf(float(theta))
        ref = float((2 * t - mpmath.sin(2 * t)) / 2)
        assert segment_area_unit(theta) == pytest.approx(ref, rel=4e-15)


def test_sliver_kinds_and_bound_against_the_cut():
    """Planes at and near the lowest point: kind 0 where the cut is empty (its exact values), kind 1
    a bound on the cut's volume and on its centroid; both kinds met."""
    rng = np.random.default_rng(34)
    seen = {0: 0, 1: 0, 2: 0}
    for L, R, chi, a_z in _states(rng, 400):
        z_c = SEABED + rng.uniform(-2.0, 2.0)
        z_lo, _ = vertical_extent(L, R, chi, a_z, z_c)
        levels = [SEABED - (SEABED - z_lo)]  # the overburden's last boundary
        levels += [z_lo + k * math.ulp(z_lo) for k in range(-3, 4)]
        levels += [z_lo + rng.uniform(0.0, 2.0 * R)]
        for level in levels:
            kind, bound, x_empty = cut_cylinder_sliver(L, R, chi, a_z, z_c, level)
            v, x, e, _, _, _ = cut_cylinder(L, R, chi, a_z, z_c, level)
            seen[kind] += 1
            if kind == 0:
                assert (_bits(v), _bits(x), _bits(e)) == (_bits(0.0), _bits(x_empty), _bits(0.0))
            elif kind == 1:
                assert 0.0 <= v <= bound
                assert abs(x) <= L + abs(chi)
                assert abs(e) <= R * (1.0 + 1e-12)
            else:
                assert bound == math.inf
    assert seen[0] > 100 and seen[1] > 100 and seen[2] > 100


def test_sliver_bound_against_the_exact_volume():
    """The volume below a plane just above the lowest rim, R^2 (w / (1 - k1)) [F0(1) - F0(k1)]
    with F0 = kappa theta - sigma + sigma^3/3 (int of the segment area over kappa, seed 000
    eq. (27b)) at 50 digits: under the bound, and the cut's value within 1e-6 of it."""
    mpmath.mp.dps = 50
    rng = np.random.default_rng(7)
    checked = 0
    for _ in range(300):
        L, R, chi = rng.uniform(0.5, 3.0), rng.uniform(0.1, 0.6), rng.uniform(-0.2, 0.2)
        a_z = rng.uniform(0.05, 0.95) * rng.choice([-1.0, 1.0])
        z_c = SEABED + rng.uniform(-2.0, 2.0)
        z_lo, _ = vertical_extent(L, R, chi, a_z, z_c)
        level = z_lo + 10.0 ** rng.uniform(-12, -4) * R
        kind, bound, _ = cut_cylinder_sliver(L, R, chi, a_z, z_c, level)
        if kind != 1:
            continue
        a = abs(a_z)
        b = math.sqrt((1.0 - a) * (1.0 + a))
        bR = mpmath.mpf(b) * R
        x_low = (-0.5 * L - chi) if a_z > 0 else (0.5 * L - chi)  # the lower end's axis point
        dt = mpmath.mpf(z_c) - mpmath.mpf(level) + mpmath.mpf(a_z) * x_low
        k1 = dt / bR
        w = (bR - dt) / a

        def f0(k):
            th = mpmath.acos(k)
            s = mpmath.sqrt(1 - k * k)
            return k * th - s + s**3 / 3

        exact = float(R * R * w / (1 - k1) * (f0(mpmath.mpf(1)) - f0(k1)))
        v = cut_cylinder(L, R, chi, a_z, z_c, level)[0]
        assert exact <= bound
        assert v == pytest.approx(exact, rel=1e-6)
        checked += 1
    assert checked > 100


def _slicing(L, R, chi, a_z, z_c, seabed, depth_max, p, bank):
    """``overburden._exact`` as it was: a cut at every slice boundary, the seabed's included."""
    c = math.sqrt(max(0.0, 1.0 - a_z * a_z))
    f_tot = mx = me = 0.0
    row = int(p[layout.P_SED_PROFILE])
    top = 0.0
    k = 1
    v1, x1, e1 = cut_cylinder(L, R, chi, a_z, z_c, seabed - top)[:3]
    while top < depth_max:
        bottom = depth_max
        if row >= 0:
            while k < bank.shape[2] and not math.isnan(bank[row, 0, k]):
                if bank[row, 0, k] > top:
                    if bank[row, 0, k] < bottom:
                        bottom = bank[row, 0, k]
                    break
                k += 1
        v2, x2, e2 = cut_cylinder(L, R, chi, a_z, z_c, seabed - bottom)[:3]
        v = v1 - v2
        if v > 0.0:
            xs = (v1 * x1 - v2 * x2) / v
            es = (v1 * e1 - v2 * e2) / v
            z_cent = z_c + a_z * xs - es * c
            rho = ob._density(seabed - z_cent, p, bank)
            f = (rho - RHO_W) * G * v
            f_tot += f
            mx += f * xs
            me += f * es
        top = bottom
        v1, x1, e1 = v2, x2, e2
    return f_tot, mx, me


def _inputs(table):
    d = Scenario.from_toml(DEFAULT).to_dict()
    if table:
        depth = [0.0, 0.15, 0.4, 0.9, 1.6]
        d["sediment"]["profile"] = {
            "name": "layers",
            "depth": depth,
            "density": [1350.0, 1420.0, 1600.0, 1650.0, 1800.0],
            "strength": [2000.0 + 1000.0 * z for z in depth],
        }
    p, sed_bank, _ = Scenario.from_dict(d).to_params()
    p, bank = drop_bank(p, sed_bank)
    if not table:  # the linear profile rho = 1420 + 30 zeta (soft_clay's), no table
        p[layout.P_SED_PROFILE] = -1.0
        p[layout.P_SED_RHO] = 1420.0
        p[layout.P_SED_RHO_GRAD] = 30.0
    return p, bank


@pytest.mark.parametrize("table", [False, True])
def test_overburden_equals_the_slicing_that_cuts_at_every_boundary(table):
    """Bit for bit, on random embedded cylinders, the right-hand side's way (the seabed's cut
    passed in, the last cut left out where it cannot matter) and overburden_force's, against the
    slicing written out with every cut; the sliver's shortcut is taken in most calls."""
    p, bank = _inputs(table)
    law = pack_law(p, p[layout.P_DIAMETER], None)
    rng = np.random.default_rng(11 + table)
    seen = {0: 0, 1: 0, 2: 0, 3: 0}
    for L, R, chi, a_z in _states(rng, 300):
        z_c = SEABED + rng.uniform(-0.5 * L - R, 0.5 * L + R)
        z_lo, _ = vertical_extent(L, R, chi, a_z, z_c)
        if not z_lo < SEABED:
            continue
        body = Cylinder(L, R, chi)
        depth_max = SEABED - z_lo
        ref = _slicing(L, R, chi, a_z, z_c, SEABED, depth_max, p, bank)
        below = cut_cylinder(L, R, chi, a_z, z_c, SEABED)[:3]
        got = ob._exact(body, a_z, z_c, SEABED, depth_max, RHO_W, G, p, bank, below)
        assert [_bits(x) for x in got] == [_bits(x) for x in ref]
        got = ob.overburden_force(body, a_z, z_c, SEABED, z_lo, RHO_W, G, p, bank, law)
        assert [_bits(x) for x in got] == [_bits(x) for x in ref]
        kind, bound, _ = cut_cylinder_sliver(L, R, chi, a_z, z_c, SEABED - depth_max)
        if kind == 1 and ob._negligible_below(bound, 2.0 * (L + abs(chi)), 2.0 * R, *below):
            kind = 3  # a sliver left out
        seen[kind] += 1
    assert sum(seen.values()) > 150 and seen[0] > 50 and seen[3] > 30 and seen[1] > 0
