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

Before xarray, pyproj is imported where both it and cfgrib are installed (the extras
``geotiff`` and ``grib``): xarray imports every installed backend when it first opens a file,
cfgrib's loads ecCodes, and with the wheels of eccodeslib 2.50 and pyproj 3.7 a process that
loads ecCodes before PROJ aborts at exit (``python -c "import eccodes, pyproj"`` exits 134,
the other order 0), after its work is done but with a failed exit status (docs/scour.md, GRIB).
"""

from __future__ import annotations

import importlib
import importlib.util
import sys

__all__ = ["DeferredModule", "netCDF4", "proj_before_eccodes", "xarray"]


class DeferredModule:
    """Stands for the module ``name``, imported at the first attribute read."""

    __slots__ = ("_name",)

    def __init__(self, name: str):
        self._name = name

    def __getattr__(self, attribute: str):
        if self._name == "xarray" and "xarray" not in sys.modules:
            proj_before_eccodes()
        return getattr(importlib.import_module(self._name), attribute)

    def __repr__(self) -> str:
        return f"<module {self._name!r}, imported at its first use>"


def proj_before_eccodes() -> None:
    """Import pyproj first where cfgrib is installed too (module docstring)."""
    if "pyproj" in sys.modules or "eccodes" in sys.modules:
        return
    if importlib.util.find_spec("cfgrib") is not None and importlib.util.find_spec("pyproj") is not None:
        importlib.import_module("pyproj")


xarray = DeferredModule("xarray")
netCDF4 = DeferredModule("netCDF4")
