"""The right-hand side's 6x6 solve by the mass matrix's blocks (issue 34 item 4).

Without pore-pressure added mass the generalised mass matrix (``dynamics._mass_matrix``) couples
only U2 with W3 and U3 with W2; ``dynamics._solve_mass`` is then ``solve6``'s Cholesky with the
products of the factor's zeros left out. References: ``solve6`` itself (the same values, bit for
bit, on random matrices of the right-hand side's structure), ``numpy.linalg.solve``, and the
full solve taken with pore-pressure added mass.
"""

import numpy as np

from mineburial.kernels.mine.dynamics import _mass_matrix, _solve_mass, solve6


def _system(rng, pore):
    m = rng.uniform(50.0, 2000.0)
    J1 = rng.uniform(0.5, 50.0)
    J2 = rng.uniform(5.0, 500.0)
    a0 = rng.uniform(0.0, 1.5) * m
    a1 = rng.uniform(-0.3, 0.3) * a0
    a2 = rng.uniform(0.0, 1.0) * J2 + a1 * a1 / max(a0, 1e-300)
    a11 = rng.uniform(0.0, 0.3) * m
    if rng.uniform() < 0.1:
        a0 = a1 = a2 = a11 = 0.0  # in the air: no added mass
    k = rng.normal(size=3)
    kb = tuple(k / np.linalg.norm(k))
    mass = np.empty(36)
    _mass_matrix(mass, m, J1, J2, (a0, a1, a2, a11), pore, kb)
    rhs = rng.normal(size=6) * np.array([1e3, 1e3, 1e3, 1e2, 1e2, 1e2])
    return mass, rhs


def test_block_solve_equals_solve6_bit_for_bit():
    rng = np.random.default_rng(34)
    for _ in range(2000):
        mass, rhs = _system(rng, 0.0)
        ref = np.empty(6)
        solve6(mass.copy(), rhs, ref)
        got = np.empty(6)
        _solve_mass(mass.copy(), rhs, got, 0.0)
        assert np.array_equal(got.view(np.int64), ref.view(np.int64))
        np.testing.assert_allclose(got, np.linalg.solve(mass.reshape(6, 6), rhs), rtol=1e-12, atol=0.0)


def test_with_pore_added_mass_the_full_solve():
    rng = np.random.default_rng(35)
    for _ in range(200):
        mass, rhs = _system(rng, rng.uniform(1.0, 500.0))
        assert np.any(mass.reshape(6, 6)[:3, :3][np.triu_indices(3, 1)] != 0.0)
        got = np.empty(6)
        _solve_mass(mass.copy(), rhs, got, 1.0)
        np.testing.assert_allclose(got, np.linalg.solve(mass.reshape(6, 6), rhs), rtol=1e-12, atol=0.0)
