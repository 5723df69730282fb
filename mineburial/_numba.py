"""The one place that sets numba options for every kernel of mineburial.

Every compiled function in :mod:`mineburial.kernels` and the ensemble driver is
decorated with :func:`kernel`, and every ``numba.extending.overload`` takes
:data:`JIT_OPTIONS`, so changing an option (caching, fastmath, error model) is a
one-line change here.

* ``cache``: compiled machine code is cached on disk beside the sources (numba's
  ``__pycache__/*.nbi, *.nbc``), so the compile cost (tens of seconds for the whole
  drop stepper) is paid once per installation rather than once per process. The
  environment variable ``MINEBURIAL_NUMBA_CACHE`` switches it: ``0`` (or ``false``,
  ``no``, ``off``) compiles in memory only, which is what to use while editing a
  kernel (numba checks a cached function against its own source file, not against
  the kernels it calls in other files, so a stale cache can survive an edit) or on
  a read-only installation; ``1`` (``true``, ``yes``, ``on``) or unset caches; any
  other value is an error. It is read once, when mineburial is imported (the same
  kind of switch as sgkit's ``SGKIT_DISABLE_NUMBA_CACHE``).
* ``fastmath=False``: results must be bit-identical whatever the thread count or
  chunking; re-association of floating-point sums would break that.
* ``error_model="numpy"``: a division by zero gives inf/nan instead of raising,
  because kernels never raise (they run on worker threads); they return status codes.
* ``nogil=True``: the batch driver runs compiled drops on several Python threads.
"""

import os

from numba import njit

#: name of the environment variable that switches the on-disk cache of compiled kernels
CACHE_ENV = "MINEBURIAL_NUMBA_CACHE"


_OFF = ("0", "false", "no", "off")
_ON = ("1", "true", "yes", "on", "")


def cache_enabled(environ=os.environ) -> bool:
    """Whether compiled kernels are cached on disk (``MINEBURIAL_NUMBA_CACHE``)."""
    value = environ.get(CACHE_ENV, "1").strip().lower()
    if value in _OFF:
        return False
    if value in _ON:
        return True
    raise ValueError(
        f"environment variable {CACHE_ENV} = {environ[CACHE_ENV]!r} must be "
        f"1 (cache compiled kernels on disk, the default) or 0 (do not)"
    )


_OPTIONS = dict(cache=cache_enabled(), nogil=True, fastmath=False, error_model="numpy")
#: the same options for ``numba.extending.overload`` implementations (compiled into their
#: caller, which caches them)
JIT_OPTIONS = dict(nogil=True, fastmath=False, error_model="numpy")


def kernel(fn):
    """Compile ``fn`` as a serial numba kernel with the project's options."""
    return njit(**_OPTIONS)(fn)


def small_kernel(fn):
    """A kernel inlined into its callers at numba's IR level (``inline="always"``): no
    compile unit of its own. For small helpers (a few loops over a state vector) whose
    separate compile, link and cache cost more than their body (docs/design.md)."""
    return njit(inline="always", **_OPTIONS)(fn)
