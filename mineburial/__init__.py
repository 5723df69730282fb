"""mineburial: a JIT-compiled Monte Carlo engine for the impact burial of naval mines.

Main entry points: :func:`simulate_drop` (one drop, full trajectory) and
:func:`run_ensemble` (many sampled drops, burial statistics in NetCDF).
"""

from importlib.metadata import PackageNotFoundError, version as _version

try:
    __version__ = _version("mineburial")
except PackageNotFoundError:  # running from a source tree that is not installed
    __version__ = "0+unknown"


def simulate_drop(*args, **kwargs):
    from mineburial.drop import simulate_drop as _simulate_drop

    return _simulate_drop(*args, **kwargs)


simulate_drop.__doc__ = "Simulate one drop; see :func:`mineburial.drop.simulate_drop`."

__all__ = ["simulate_drop", "__version__"]
