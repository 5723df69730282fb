"""The linear algebra of the Rosenbrock-W step (kernels/integrators.py: w_factor, lu_factor_small,
lu_solve_small, w_solve, j_times; kernels/core.py: ros34pw2_step) against independent references, for
state sizes and column counts on either side of the four- and two-row blocks of the products (issue 34
item 4 rewrote their loops for fewer instructions and the same floating-point operations):

* J v from the columns of J: bit for bit the sum sum_j jc[i, j] z[j] from 0.0 in column order, written
  out in plain Python floats (the claim of the rewrite: the same operations in the same order);
* the LU factors with partial pivoting and their solve against numpy.linalg.solve, with pivots forced;
* the W solve (I - c J) x = b for J non-zero in a few columns against numpy.linalg.solve of the full n x n
  system;
* one ROS34PW2 step of a linear system y' = A y against the step written out by hand in numpy from the
  tableau of Rang & Angermann (2005) (Hairer & Wanner II, sec. IV.7, form (7.4'): the W-method's linear
  systems solved by numpy on the full matrix).
"""

import numpy as np
import pytest
from linear_system import linear_rhs, no_event

from mineburial.kernels import core
from mineburial.kernels import integrators as ig
from mineburial.kernels.core import System

SIZES = [(1, 1), (2, 1), (3, 2), (4, 3), (5, 2), (6, 6), (7, 3), (9, 4), (13, 6), (15, 6), (16, 7)]


def _columns(rng, n, m):
    return np.sort(rng.choice(n, size=m, replace=False)).astype(np.int64)


@pytest.mark.parametrize("n, m", SIZES)
def test_j_times_is_the_ordered_sum_bit_for_bit(n, m):
    rng = np.random.default_rng(100 * n + m)
    jc = rng.normal(size=(n, m)) * 10.0 ** rng.integers(-3, 4, size=(n, m))
    z = rng.normal(size=m) * 10.0 ** rng.integers(-3, 4, size=m)
    out = np.empty(n)
    ig.j_times(jc, z, out)
    for i in range(n):
        acc = 0.0
        for j in range(m):
            acc += float(jc[i, j]) * float(z[j])
        assert out[i] == acc, (i, out[i], acc)


@pytest.mark.parametrize("m", [1, 2, 3, 5, 6, 8])
def test_lu_factor_and_solve_match_numpy_with_pivoting(m):
    rng = np.random.default_rng(7 + m)
    a = rng.normal(size=(m, m))
    a[0, 0] = 0.0  # the first column must pivot
    a += np.diag(np.linspace(0.1, 1.0, m))[::-1]  # large entries off the diagonal for m > 1
    b = rng.normal(size=m)
    lu = a.copy()
    piv = np.empty(m, np.int64)
    assert ig.lu_factor_small(lu, piv)
    if m > 1:
        assert piv[0] != 0
    x = b.copy()
    ig.lu_solve_small(lu, piv, x)
    np.testing.assert_allclose(x, np.linalg.solve(a, b), rtol=1e-11, atol=1e-13)


def test_lu_factor_refuses_a_singular_matrix():
    a = np.array([[1.0, 2.0], [2.0, 4.0]])
    assert not ig.lu_factor_small(a, np.empty(2, np.int64))
    a = np.array([[np.nan, 0.0], [0.0, 1.0]])
    assert not ig.lu_factor_small(a, np.empty(2, np.int64))


@pytest.mark.parametrize("n, m", SIZES)
def test_w_solve_matches_numpy_on_the_full_system(n, m):
    rng = np.random.default_rng(31 * n + m)
    cols = _columns(rng, n, m)
    jc = rng.normal(size=(n, m)) * 3.0
    c = 0.37
    b = rng.normal(size=n)
    jfull = np.zeros((n, n))
    jfull[:, cols] = jc
    expected = np.linalg.solve(np.eye(n) - c * jfull, b)
    wa = np.empty((m, m))
    piv = np.empty(m, np.int64)
    assert ig.w_factor(jc, cols, c, wa, piv)
    x = b.copy()
    ig.w_solve(jc, cols, c, wa, piv, x, np.empty(m))
    np.testing.assert_allclose(x, expected, rtol=1e-10, atol=1e-12)


LINEAR = System("test ros linear algebra", linear_rhs, no_event)


def _ros34pw2_by_hand(a, y, h):
    """One ROS34PW2 step of y' = A y, J = A, in the form (7.4') of Hairer & Wanner II sec. IV.7:
    (I - h gamma J) k_i = h f(y + sum_j alpha_ij k_j) + h J sum_j gamma_ij k_j."""
    n = y.size
    w = np.eye(n) - h * ig.ROS_GAMMA_DIAG * a
    k = np.zeros((4, n))
    for s in range(4):
        ys = y + sum(ig.ROS_ALPHA[s, j] * k[j] for j in range(s))
        g = sum(ig.ROS_GAMMA[s, j] * k[j] for j in range(s)) if s else np.zeros(n)
        k[s] = np.linalg.solve(w, h * (a @ ys) + h * (a @ g))
    ynew = y + ig.ROS_B @ k
    err = (ig.ROS_B - ig.ROS_B_HAT) @ k
    return ynew, err


@pytest.mark.parametrize("n, m", [(3, 2), (7, 3), (15, 6)])
def test_ros34pw2_step_matches_the_step_written_out_in_numpy(n, m):
    rng = np.random.default_rng(5 * n + m)
    cols = _columns(rng, n, m)
    a = np.zeros((n, n))
    a[:, cols] = rng.normal(size=(n, m)) * 4.0  # the Jacobian is non-zero in the columns cols only
    a[cols, cols] -= 20.0  # stiff
    y = rng.normal(size=n)
    h = 0.05
    f0 = a @ y
    jc = np.ascontiguousarray(a[:, cols])
    out, err = np.empty(n), np.empty(n)
    ok = core.ros34pw2_step(
        LINEAR, 0.0, y, h, a, f0, jc, cols, np.empty((m, m)), np.empty(m, np.int64), np.empty((4, n)),
        np.empty(n), np.empty(n), np.empty(m), out, err,
    )  # fmt: skip
    assert ok
    ynew, err_ref = _ros34pw2_by_hand(a, y, h)
    np.testing.assert_allclose(out, ynew, rtol=1e-11, atol=1e-13)
    np.testing.assert_allclose(err, err_ref, rtol=1e-8, atol=1e-13 * np.abs(y).max())
