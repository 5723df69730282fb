"""A System's declared sizes (kernels/core.py, ``System(..., sizes=(n, m))``, issue 34 item 4): the
Rosenbrock-W step compiles with the state length n and the Jacobian column count m as constants, and
must give the same step bit for bit as the same system without them; arrays of other sizes are refused
(a failed step, never a read or write outside them); sizes that cannot be are an error."""

import numpy as np
import pytest
from linear_system import linear_rhs, no_event

from mineburial.kernels import core
from mineburial.kernels.core import System

SIZES = [(1, 1), (3, 2), (7, 3), (15, 6), (16, 7)]
PLAIN = System("test core sizes", linear_rhs, no_event)
SIZED = {nm: System("test core sizes", linear_rhs, no_event, sizes=nm) for nm in SIZES}


def _problem(n, m, seed):
    rng = np.random.default_rng(seed)
    cols = np.sort(rng.choice(n, size=m, replace=False)).astype(np.int64)
    a = rng.normal(size=(n, n))
    a[:, cols] += rng.normal(size=(n, m)) * 4.0
    a[cols, cols] -= 20.0  # stiff in the Jacobian's columns
    y = rng.normal(size=n)
    # the Jacobian's columns of another (older) state: a W-method takes any J
    jc = np.ascontiguousarray(a[:, cols] * (1.0 + 0.01 * rng.normal(size=(n, m))))
    return a, y, cols, jc


def _step(system, a, y, cols, jc, h, n_rows=None, m_rows=None):
    n = y.shape[0] if n_rows is None else n_rows
    m = cols.shape[0] if m_rows is None else m_rows
    out, err = np.full(n, -1.0), np.full(n, -1.0)
    kr = np.empty((4, n))
    ok = core.ros34pw2_step(
        system, 0.0, y, h, a, a @ y, jc, cols, np.empty((m, m)), np.empty(m, np.int64), kr,
        np.empty(n), np.empty(n), np.empty(m), out, err,
    )  # fmt: skip
    return ok, out, err, kr


@pytest.mark.parametrize("n, m", SIZES)
def test_declared_sizes_give_the_same_step_bit_for_bit(n, m):
    a, y, cols, jc = _problem(n, m, 11 * n + m)
    for h in (1e-3, 0.05, 0.4):
        ok_plain, out_plain, err_plain, kr_plain = _step(PLAIN, a, y, cols, jc, h)
        ok_sized, out_sized, err_sized, kr_sized = _step(SIZED[(n, m)], a, y, cols, jc, h)
        assert ok_plain and ok_sized
        assert np.array_equal(out_sized, out_plain)
        assert np.array_equal(err_sized, err_plain)
        assert np.array_equal(kr_sized, kr_plain)


def test_arrays_of_other_sizes_are_refused():
    n, m = 7, 3
    a, y, cols, jc = _problem(n, m, 5)
    system = SIZED[(n, m)]
    assert _step(system, a, y, cols, jc, 0.05)[0]
    # a longer state, more columns, a Jacobian of another shape: a failed step, the outputs untouched
    a2, y2, cols2, jc2 = _problem(n + 1, m, 6)
    ok, out, err, _ = _step(system, a2, y2, cols2, jc2, 0.05)
    assert not ok and np.all(out == -1.0) and np.all(err == -1.0)
    a3, y3, cols3, jc3 = _problem(n, m + 1, 7)
    ok, out, err, _ = _step(system, a3, y3, cols3, jc3, 0.05)
    assert not ok and np.all(out == -1.0)
    ok, out, _, _ = _step(system, a, y, cols, np.zeros((n, m + 1)), 0.05)
    assert not ok and np.all(out == -1.0)
    ok, out, _, _ = _step(system, a, y, cols, jc, 0.05, m_rows=m + 1)  # W of another size
    assert not ok and np.all(out == -1.0)


@pytest.mark.parametrize("sizes", [(0, 0), (3, 0), (3, 4), (3,), (3, 2, 1)])
def test_sizes_that_cannot_be_are_an_error(sizes):
    with pytest.raises(ValueError, match="sizes of a System"):
        System("test core sizes bad", linear_rhs, no_event, sizes=sizes)


def test_sizes_are_part_of_the_systems_type():
    assert PLAIN.sizes is None and SIZED[(7, 3)].sizes == (7, 3)
    assert PLAIN.numba_type != SIZED[(7, 3)].numba_type != SIZED[(15, 6)].numba_type
