"""core.borrowed / core.keep_alive (issue 34 item 4): a borrowed view is the same memory without its reference
count, so what a kernel reads and writes through it is what it would through the array; the array's owner is
unaffected (its count and its data), and the views cost no atomics, only where the caller holds the owner."""

import sys

import numpy as np
from numba import njit

from mineburial.kernels.core import borrowed, keep_alive


@njit
def _scaled_sum(a, out):
    b = borrowed(a)
    o = borrowed(out)
    s = 0.0
    for i in range(b.shape[0]):
        o[i] = 2.0 * b[i]
        s += b[i]
    return s


@njit
def _owned_then_borrowed(n):
    owner = np.arange(n, dtype=np.float64)
    view = borrowed(owner)
    s = 0.0
    for i in range(view.shape[0]):
        view[i] += 1.0
        s += view[i]
    keep_alive(owner)
    return s


def test_a_borrowed_view_reads_and_writes_the_arrays_memory():
    a = np.linspace(0.0, 1.0, 11)
    out = np.zeros(11)
    assert _scaled_sum(a, out) == _scaled_sum.py_func(a, np.zeros(11))
    np.testing.assert_array_equal(out, 2.0 * a)


def test_borrowing_leaves_the_owners_reference_count_alone():
    a = np.ones(5)
    out = np.zeros(5)
    before = (sys.getrefcount(a), sys.getrefcount(out))
    for _ in range(100):
        _scaled_sum(a, out)
    assert (sys.getrefcount(a), sys.getrefcount(out)) == before


def test_an_array_kept_alive_is_used_through_its_view_to_the_end():
    # the sum of 1..n through the view of an array the kernel owns and keeps alive to the end (a read after a
    # free need not show in the values: this checks the values and that it compiles and runs, not the free)
    for n in (1, 10, 1000):
        assert _owned_then_borrowed(n) == n * (n + 1) / 2
