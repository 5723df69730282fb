"""mineburial: a JIT-compiled Monte Carlo engine for the impact burial of naval mines.

Main entry points: :func:`simulate_drop` (one drop, full trajectory) and
:func:`run_ensemble` (many sampled drops, burial statistics in NetCDF).
"""

from mineburial._version import __version__


def simulate_drop(*args, **kwargs):
    # local import: start-up, `import mineburial` (every command's first import) takes 0.11 s CPU,
    # with the drop and the runner 2.4 s (median of 5, docs/design.md "Imports")
    from mineburial.systems.mine.drop import simulate_drop as _simulate_drop

    return _simulate_drop(*args, **kwargs)


simulate_drop.__doc__ = "Simulate one drop; see :func:`mineburial.systems.mine.drop.simulate_drop`."


def run_ensemble(*args, **kwargs):
    # local import: start-up, as simulate_drop's
    from mineburial.ensembles.runner import run_ensemble as _run_ensemble

    return _run_ensemble(*args, **kwargs)


run_ensemble.__doc__ = "Run a Monte Carlo ensemble; see :func:`mineburial.ensembles.runner.run_ensemble`."

__all__ = ["simulate_drop", "run_ensemble", "__version__"]
