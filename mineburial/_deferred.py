"""Libraries that the engine imports at their first use, not when it is imported.

Computing drops needs numpy, numba and the sampling's scipy.special; it does not need
xarray (with pandas) or netCDF4, which only build, write and read files. Importing them
with the engine took 0.7 of the 1.2-1.9 s of a warm start on the 2-core development
machine (``python -X importtime``; ``benchmarks/bench_startup.py``), so a dask worker, a
resumed chunk or the first drop of ``mineburial run`` waited for libraries it does not
use. A module of mineburial names them here instead::

    from mineburial._deferred import xarray as xr

and ``xr.Dataset`` imports xarray the first time it is read (Python's import system does
it, under its lock, so threads are safe) and is an ordinary attribute lookup after that.
``tests/test_imports.py`` checks that importing the engine and running a drop imports
neither library. Type annotations stay strings (``from __future__ import annotations``).
"""

from __future__ import annotations

import importlib

__all__ = ["DeferredModule", "netCDF4", "xarray"]


class DeferredModule:
    """Stands for the module ``name``, imported at the first attribute read."""

    __slots__ = ("_name",)

    def __init__(self, name: str):
        self._name = name

    def __getattr__(self, attribute: str):
        return getattr(importlib.import_module(self._name), attribute)

    def __repr__(self) -> str:
        return f"<module {self._name!r}, imported at its first use>"


xarray = DeferredModule("xarray")
netCDF4 = DeferredModule("netCDF4")
