"""The geostatic (overburden) force of a long tabulated profile (issue 21, item 11).

The reference rule (``numerics.overburden_quadrature = "reference"``) slices the embedded
body at every table depth inside it, so its cost grew with the table's rows (~5,000 slices
for a centimetre core over the penetration). The default ``fast`` rule keeps it while at
most ``EXACT_DEPTHS`` depths lie inside the embedded span and uses ``SLICES`` equal slices
beyond (kernels/mine/overburden.py). Independent references: scipy's dblquad of the volume
integral over the embedded cylinder, ``numpy`` counts, and the reference rule itself for
the bounded rule's error.
"""

import math
import pathlib
import time

import numba
import numpy as np
import pytest
from numba import types
from scipy import integrate

from mineburial._numba import JIT_OPTIONS
from mineburial.errors import ScenarioError
from mineburial.kernels.mine import layout
from mineburial.kernels.mine import overburden as ob
from mineburial.kernels.mine.bodies.cylinder import Cylinder
from mineburial.kernels.mine.geometry import cut_cylinder, vertical_extent
from mineburial.kernels.mine.sediment.laws import drop_bank, pack_law
from mineburial.systems.mine.config import Scenario
from mineburial.systems.mine.drop import run_params

DEFAULT = pathlib.Path(__file__).resolve().parents[1] / "mineburial" / "data" / "default_mine.toml"
RHO_W = 1025.0
G = 9.81


def smooth(z):
    """A curved, non-monotone density (kg m-3) against depth (m)."""
    return 1350.0 + 400.0 * (1.0 - np.exp(-z / 0.7)) + 20.0 * np.sin(6.0 * z)


def scenario(depth, density, quadrature="fast", pitch=0.0, resistance=None):
    d = Scenario.from_toml(DEFAULT).to_dict()
    d["sediment"]["profile"] = {
        "name": f"{len(depth)} rows",
        "depth": list(map(float, depth)),
        "density": list(map(float, density)),
        "strength": list(map(float, 2000.0 + 1010.0 * np.asarray(depth))),
    }
    d["release"]["pitch_deg"] = pitch
    d["numerics"]["overburden_quadrature"] = quadrature
    if resistance:
        d["sediment"]["resistance"] = resistance
    return Scenario.from_dict(d)


def drop_inputs(depth, density, quadrature="fast"):
    p, sed_bank, _ = scenario(depth, density, quadrature).to_params()
    p[layout.P_RHO_WATER] = RHO_W
    p[layout.P_GRAVITY] = G
    return drop_bank(p, sed_bank)


def force(p, bank, a_z, penetration, quadrature, paths=True):
    """(F, F x, F eta) of the body whose lowest point is ``penetration`` below the seabed (z = 0),
    with the law's ``reference_paths`` slot ``paths`` (True: both rules compiled)."""
    q = p.copy()
    q[layout.P_OB_QUADRATURE] = layout.OVERBURDEN_QUADRATURE_NAMES.index(quadrature)
    L, R, chi = q[layout.P_LENGTH], 0.5 * q[layout.P_DIAMETER], q[layout.P_CHI]
    z_lo, _ = vertical_extent(L, R, chi, a_z, 0.0)
    z_c = -penetration - z_lo
    law = pack_law(q, q[layout.P_DIAMETER], paths)
    return np.array(
        ob.overburden_force(Cylinder(L, R, chi), a_z, z_c, 0.0, -penetration, RHO_W, G, q, bank, law)
    )


def exact(p, bank, a_z, penetration):
    """(F, F x, F eta) by the slice-at-every-table-depth rule (``_exact``: the reference rule of
    before issue 34, whatever the table's length), independent of the quadrature code."""
    L, R, chi = p[layout.P_LENGTH], 0.5 * p[layout.P_DIAMETER], p[layout.P_CHI]
    z_lo, _ = vertical_extent(L, R, chi, a_z, 0.0)
    z_c = -penetration - z_lo
    below = cut_cylinder(L, R, chi, a_z, z_c, 0.0)[:3]  # the part below the seabed, its top cut
    return np.array(ob._exact(Cylinder(L, R, chi), a_z, z_c, 0.0, penetration, RHO_W, G, p, bank, below))


def geometry(p):
    return p[layout.P_LENGTH], 0.5 * p[layout.P_DIAMETER], p[layout.P_CHI]


def scipy_force(p, a_z, penetration, rho):
    """F = g int_emb (rho(zeta) - rho_w) dV and its first moments along the axis (x) and
    e_down (u), by scipy's dblquad over x and u: a point x i_M + u e_down + v e_perp is at
    height z_c + a_z x - u sqrt(1 - a_z^2), and the chord in v is 2 sqrt(R^2 - u^2)."""
    L, R, chi = geometry(p)
    c = math.sqrt(1.0 - a_z * a_z)
    z_lo, _ = vertical_extent(L, R, chi, a_z, 0.0)
    z_c = -penetration - z_lo

    def u_low(x):  # below the seabed: z_c + a_z x - c u < 0
        return min(R, max(-R, (z_c + a_z * x) / c))

    def part(weight):
        def f(u, x):
            zeta = -(z_c + a_z * x - c * u)
            return weight(x, u) * 2.0 * math.sqrt(max(0.0, R * R - u * u)) * (rho(zeta) - RHO_W) * G

        val, _ = integrate.dblquad(f, -0.5 * L - chi, 0.5 * L - chi, u_low, R, epsabs=0.0, epsrel=1e-10)
        return val

    return np.array([part(lambda x, u: 1.0), part(lambda x, u: x), part(lambda x, u: u)])


def relative(a, ref, p):
    """Force difference over |F|, moment differences over |F| L/2 and |F| R."""
    L, R, _ = geometry(p)
    scale = abs(ref[0]) * np.array([1.0, 0.5 * L, R])
    return np.abs(a - ref) / scale


ATTITUDES = (0.0, 0.2, 0.6, -0.5, 0.95, 1.0)  # a_z, the axis' vertical component
PENETRATIONS = (0.3, 0.8, 1.5, 2.5, 4.0)  # m, lowest point below the seabed


def test_depths_inside_counts_the_table_depths_strictly_inside_the_span():
    rng = np.random.default_rng(3)
    for n in (1, 2, 3, 40, 3000):
        d = np.concatenate([[0.0], np.sort(rng.choice(np.arange(1, 20000), size=n, replace=False)) * 5e-4])
        p, bank = drop_inputs(d, np.full(d.size, 1500.0))
        for depth_max in np.concatenate([d, d + 1e-9, d - 1e-9, rng.uniform(-1.0, 11.0, 50)]):
            expected = int(np.sum((d > 0.0) & (d < depth_max)))
            assert ob.depths_inside(bank, 0, depth_max) == expected, (n, depth_max)


def test_bounded_rule_against_the_exact_slicing_on_a_30000_row_smooth_profile():
    z = np.linspace(0.0, 10.0, 30000)
    p, bank = drop_inputs(z, smooth(z))
    worst = np.zeros(3)
    for a_z in ATTITUDES:
        for pen in PENETRATIONS:
            fast = force(p, bank, a_z, pen, "fast")
            assert ob.depths_inside(bank, 0, pen) > ob.EXACT_DEPTHS  # the bounded rule ran
            worst = np.maximum(worst, relative(fast, exact(p, bank, a_z, pen), p))
    # measured: 3.5e-6 (force), 8.8e-6 (x moment), 3.9e-5 (e_down moment)
    assert worst[0] < 1e-5 and worst[1] < 1e-4 and worst[2] < 1e-4, worst


def test_bounded_and_exact_rules_against_scipy_dblquad():
    z = np.linspace(0.0, 10.0, 30000)
    p, bank = drop_inputs(z, smooth(z))

    def rho(zeta):
        return smooth(zeta) if zeta > 0.0 else smooth(0.0)

    for a_z, pen in ((0.0, 0.8), (0.3, 1.5), (-0.6, 2.5)):
        ref = scipy_force(p, a_z, pen, rho)
        # the slicing at every depth: exact for the table's piecewise-linear density (the
        # table differs from the smooth curve by ~2e-5 kg m-3); its torque treats each 1/3 mm
        # slice as uniform. The reference rule: REFERENCE_SLICES slices beyond
        # REFERENCE_DEPTHS depths (measured 3e-11, 3e-8, 5e-8 from the former)
        assert np.all(relative(exact(p, bank, a_z, pen), ref, p) < 1e-6)
        assert np.all(relative(force(p, bank, a_z, pen, "reference"), ref, p) < 1e-6)
        assert np.all(relative(force(p, bank, a_z, pen, "fast"), ref, p) < 1e-4)


def test_linear_profile_force_is_exact_with_the_bounded_rule():
    # density linear within every slice: the slice's depth mean plus the secant slope times
    # the centroid's offset is the density at its centroid, as in the reference rule
    z = np.linspace(0.0, 10.0, 30000)
    p, bank = drop_inputs(z, 1420.0 + 30.0 * z)
    for a_z in ATTITUDES:
        for pen in PENETRATIONS:
            rel = relative(force(p, bank, a_z, pen, "fast"), exact(p, bank, a_z, pen), p)
            assert rel[0] < 1e-12 and rel[1] < 1e-5 and rel[2] < 1e-4, (a_z, pen, rel)


def test_rough_core_is_averaged_not_sampled():
    # a white-noise core (30 kg m-3 at every centimetre): every row counts through the
    # running integral; the bounded rule's error is the noise's correlation with the body's
    # cross-section within a slice (measured ~8e-4 of F)
    z = np.linspace(0.0, 10.0, 1001)
    noise = np.random.default_rng(1).normal(0.0, 30.0, z.size)
    p, bank = drop_inputs(z, 1500.0 + 20.0 * z + noise)
    for a_z in ATTITUDES:
        for pen in PENETRATIONS:
            rel = relative(force(p, bank, a_z, pen, "fast"), exact(p, bank, a_z, pen), p)
            assert np.all(rel < 3e-3), (a_z, pen, rel)


def test_short_table_takes_the_exact_slicing_bit_for_bit():
    # at most EXACT_DEPTHS table depths inside the embedded span: the fast rule is the
    # reference rule, so every existing short table keeps its answers
    z = np.concatenate([[0.0], np.sort(np.random.default_rng(2).uniform(0.0, 10.0, 60))])
    p, bank = drop_inputs(z, smooth(z))
    seen = 0
    for a_z in ATTITUDES:
        for pen in np.linspace(0.05, 9.0, 40):
            inside = ob.depths_inside(bank, 0, pen)
            fast = force(p, bank, a_z, pen, "fast")
            exact = force(p, bank, a_z, pen, "reference")
            if inside <= ob.EXACT_DEPTHS:
                seen += 1
                assert np.array_equal(fast, exact), (a_z, pen)
            else:
                assert not np.array_equal(fast, exact)
    assert seen > 20


def test_short_table_drops_are_bit_identical_with_either_rule():
    # 0.5 m rows: at most EXACT_DEPTHS inside down to 6.5 m (with 0.2 m rows the
    # integrator's trial states below 2.6 m already take the bounded rule)
    z = np.linspace(0.0, 10.0, 21)
    rho = 1450.0 + 30.0 * z + np.random.default_rng(4).normal(0.0, 15.0, z.size)
    for pitch in (0.0, 30.0):
        out = [run_params(*scenario(z, rho, q, pitch).to_params())[:2] for q in ("fast", "reference")]
        assert out[0][0] == out[1][0] and np.array_equal(out[0][1], out[1][1])


def test_bounded_rule_compiled_only_for_a_batch_with_a_long_table():
    # with_long_tables decides before the batch; a table of EXACT_DEPTHS depths below the
    # seabed can never put more inside the body (depths_inside checked at every depth)
    def paths(depth, quadrature="fast", given=None):
        p, bank, _ = scenario(depth, np.full(len(depth), 1500.0), quadrature).to_params()
        return ob.with_long_tables(given, np.stack([p, p]), bank), p, bank

    short = np.linspace(0.0, 6.0, ob.EXACT_DEPTHS + 1)  # EXACT_DEPTHS depths below the seabed
    decided, p, bank = paths(short)
    q, own = drop_bank(p, bank)
    assert decided is None
    assert max(ob.depths_inside(own, 0, d) for d in np.linspace(-1.0, 20.0, 400)) == ob.EXACT_DEPTHS
    longer = np.linspace(0.0, 6.0, ob.EXACT_DEPTHS + 2)
    assert paths(longer)[0] is True
    assert paths(longer, "reference")[0] is None  # the reference rule slices at its depths
    many = np.linspace(0.0, 6.0, ob.REFERENCE_DEPTHS + 2)
    assert paths(many, "reference")[0] is True  # ... up to REFERENCE_DEPTHS of them
    assert paths(short, given=True)[0] is True  # a batch with reference paths keeps them
    p, bank, _ = Scenario.from_toml(DEFAULT).to_params()  # a linear profile
    assert ob.with_long_tables(None, p, bank) is None


def test_without_long_tables_the_bounded_rule_is_not_compiled():
    # the law's reference_paths slot None: the reference rule even for a long table (never
    # reached in a run: with_long_tables), and no code of the bounded rule in the kernel
    z = np.linspace(0.0, 10.0, 3000)
    p, bank = drop_inputs(z, smooth(z))
    for a_z, pen in ((0.0, 0.8), (0.6, 2.5)):
        every = exact(p, bank, a_z, pen)
        assert np.array_equal(force(p, bank, a_z, pen, "fast", None), every)
        assert np.array_equal(force(p, bank, a_z, pen, "reference", None), every)
        assert not np.array_equal(force(p, bank, a_z, pen, "fast"), every)
    # the IR of a fresh, uncached compile of the same signatures: numba returns no IR for a
    # kernel loaded from the on-disk cache (the suite's controller warms it: tests/conftest.py)
    fresh = numba.njit(**JIT_OPTIONS)(ob.overburden_force.py_func)
    laws = {}
    for sig in ob.overburden_force.signatures:
        fresh.compile(sig)
        laws[sig[-1].types[-1]] = fresh.inspect_llvm(sig)
    assert "_bounded" not in laws[types.none] and "_bounded" in laws[types.boolean]


def test_long_table_penetration_within_a_millimetre_of_the_exact_rule():
    z = np.linspace(0.0, 10.0, 3000)
    pen = [
        run_params(*scenario(z, 1420.0 + 30.0 * z, q, 20.0).to_params())[1][layout.S_PENETRATION]
        for q in ("fast", "reference")
    ]
    assert pen[0] == pytest.approx(pen[1], abs=1e-3) and pen[0] > 1.0


def test_overburden_cost_does_not_grow_with_the_rows():
    # the reference rule at 300,000 rows cuts the body ~45,000 times per call (~5 ms);
    # the fast rule at most EXACT_DEPTHS + 1 or SLICES + 1 times
    timings = {}
    for n in (3, 300_000):
        z = np.linspace(0.0, 10.0, n)
        p, bank = drop_inputs(z, 1420.0 + 30.0 * z)
        force(p, bank, 0.3, 1.5, "fast")
        t0 = time.perf_counter()
        for pen in np.linspace(1.0, 2.0, 200):
            force(p, bank, 0.3, pen, "fast")
        timings[n] = time.perf_counter() - t0
    assert timings[300_000] < 5 * timings[3] + 0.05, timings


def test_unknown_overburden_quadrature_is_refused_naming_the_field():
    with pytest.raises(ScenarioError, match=r"numerics\.overburden_quadrature.*'exact'"):
        scenario([0.0, 10.0], [1500.0, 1600.0], quadrature="exact")
    p, _, _ = scenario([0.0, 10.0], [1500.0, 1600.0], quadrature="reference").to_params()
    assert p[layout.P_OB_QUADRATURE] == 1
    assert layout.PARAM_NAMES[layout.P_OB_QUADRATURE] == "numerics.overburden_quadrature"


def cpt(rows):
    """A rough cone-penetration-like core on [0, 6] m (benchmarks/bench_self_check.py)."""
    z = np.linspace(0.0, 6.0, rows)
    wave = 0.5 * np.sin(2 * np.pi * z / 0.7) + 0.3 * np.sin(2 * np.pi * z / 0.13 + 1.0)
    noise = np.random.default_rng(34).standard_normal(rows)
    return z, (1420.0 + 30.0 * z) * (1.0 + 0.01 * (0.6 * wave + 0.4 * noise) / 1.5)


def test_reference_rule_equals_the_slicing_at_every_depth_on_a_20000_row_core():
    # issue 34: beyond REFERENCE_DEPTHS depths inside, the reference rule takes REFERENCE_SLICES
    # equal slices (the bounded rule's averaging of the running integral); against the former
    # reference, the slicing at every one of the ~700-5,300 depths inside (measured worst
    # 8.0e-7 force, 1.7e-6 and 2.3e-6 moments; the fast rule's 12 slices: 1.6e-4, 1.8e-4, 8.9e-5)
    z, rho = cpt(20000)
    p, bank = drop_inputs(z, rho)
    worst = np.zeros(3)
    for a_z in ATTITUDES:
        for pen in (0.3, 0.8, 1.5, 2.5, 4.0):
            assert ob.depths_inside(bank, 0, pen) > ob.REFERENCE_DEPTHS
            worst = np.maximum(
                worst, relative(force(p, bank, a_z, pen, "reference"), exact(p, bank, a_z, pen), p)
            )
    assert worst[0] < 4e-6 and worst[1] < 1e-5 and worst[2] < 1e-5, worst


def test_reference_rule_slices_at_every_depth_up_to_its_limit_bit_for_bit():
    z, rho = cpt(2000)  # 3 rows a centimetre
    p, bank = drop_inputs(z, rho)
    seen = 0
    for a_z in (0.0, 0.6):
        for pen in np.linspace(0.05, 1.5, 12):
            if ob.depths_inside(bank, 0, pen) <= ob.REFERENCE_DEPTHS:
                seen += 1
                assert np.array_equal(force(p, bank, a_z, pen, "reference"), exact(p, bank, a_z, pen))
    assert seen >= 6


def test_reference_overburden_cost_does_not_grow_with_the_rows():
    # the slicing at every depth at 300,000 rows cuts the body ~45,000 times per call; the
    # reference rule at most REFERENCE_DEPTHS + 1 or REFERENCE_SLICES + 1 times
    timings = {}
    for n in (3, 300_000):
        z = np.linspace(0.0, 10.0, n)
        p, bank = drop_inputs(z, 1420.0 + 30.0 * z)
        force(p, bank, 0.3, 1.5, "reference")
        t0 = time.perf_counter()
        for pen in np.linspace(1.0, 2.0, 100):
            force(p, bank, 0.3, pen, "reference")
        timings[n] = time.perf_counter() - t0
    t0 = time.perf_counter()
    for pen in np.linspace(1.0, 2.0, 100):
        exact(p, bank, 0.3, pen)
    every = time.perf_counter() - t0
    assert timings[300_000] < every / 20, (timings, every)
