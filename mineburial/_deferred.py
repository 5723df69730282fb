"""Libraries that the engine imports at their first use, not when it is imported.

Computing drops needs numpy, numba and the sampling's scipy.special; it does not need
xarray (with pandas) or netCDF4, which only build, write and read files. Importing them
with the engine made a dask worker, a resumed chunk or the first drop of ``mineburial run``
wait for libraries it does not use: deferring them took the warm start to the first drop
from 2.03 to 1.48 s (medians, 2-core development machine, ``benchmarks/results/
throughput_and_startup.txt``, session 12). A module of mineburial names them here instead::

    from mineburial._deferred import xarray as xr

and ``xr.Dataset`` imports xarray the first time it is read (Python's import system does
it, under its lock, so threads are safe); after that, each read looks the module up in
``sys.modules`` (``importlib.import_module``: 2.3 us a read on the development machine) and
reads its attribute. ``tests/test_deferred_imports.py`` checks that loading the default
ensemble and sampling a chunk imports neither library. Type annotations stay strings
(``from __future__ import annotations``).
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
