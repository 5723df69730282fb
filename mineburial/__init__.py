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

def run_ensemble(*args, **kwargs):
    from mineburial.ensembles.engine import run_ensemble as _run_ensemble

    return _run_ensemble(*args, **kwargs)


run_ensemble.__doc__ = "Run a Monte Carlo ensemble; see :func:`mineburial.ensembles.engine.run_ensemble`."

__all__ = ["simulate_drop", "run_ensemble", "__version__"]
