"""The one place that sets numba options for every kernel of mineburial.

Every compiled function in :mod:`mineburial.kernels` and the ensemble driver is
decorated with :func:`kernel` (or :func:`parallel_kernel`), so changing an option
(caching, fastmath, error model) is a one-line change here.

* ``cache=True``: compiled machine code is cached beside the sources, so the
  compile cost (tens of seconds for the whole drop stepper) is paid once per
  installation rather than once per process.
* ``fastmath=False``: results must be bit-identical whatever the thread count or
  chunking; re-association of floating-point sums would break that.
* ``error_model="numpy"``: a division by zero gives inf/nan instead of raising,
  because kernels never raise inside ``prange``; they return status codes.
"""

from numba import njit

_OPTIONS = dict(cache=True, nogil=True, fastmath=False, error_model="numpy")
#: the same options for ``numba.extending.overload`` implementations (compiled into their
#: caller, which caches them)
JIT_OPTIONS = dict(nogil=True, fastmath=False, error_model="numpy")


def kernel(fn):
    """Compile ``fn`` as a serial numba kernel with the project's options."""
    return njit(**_OPTIONS)(fn)


def parallel_kernel(fn):
    """Compile ``fn`` as a numba kernel that may use ``prange``."""
    return njit(parallel=True, **_OPTIONS)(fn)
