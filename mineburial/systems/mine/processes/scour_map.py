"""The scour stage's inputs per cell of a map (``scour.forcing_grid``, docs/maps.md): the gridded
forcing read onto the map's cells, each cell's scenario given its own series. Moved from
:mod:`mineburial.analyses.maps`, which reaches it only through the process protocol
(:meth:`mineburial.systems.mine.processes.registry.Process.cell_inputs`, :meth:`ScourProcess.cell_inputs
<mineburial.systems.mine.processes.scour.ScourProcess.cell_inputs>`), with the map's grid described by
:class:`mineburial.analyses.maps.MapCells` (``dims``, ``y``, ``x``, ``geographic``, ``computed``,
``label(j, i)``); every problem is one :class:`~mineburial.systems.mine.config.ScenarioError` line naming the
file, the coordinate or the cell.
"""

from __future__ import annotations

import dataclasses
import pathlib
from collections.abc import Mapping

import numpy as np

from mineburial.ensembles.settings import file_digest
from mineburial.io import forcing as fio
from mineburial.io import wave_products
from mineburial.systems.mine import config as cfg


@dataclasses.dataclass(frozen=True, eq=False)
class CellForcing:
    """A map cell's own series of a gridded forcing (``scour.forcing_grid``, docs/maps.md), put in
    the cell's scenario by :meth:`GriddedForcing.section` in place of the file name (a scenario file
    cannot hold one). Immutable, so copies of a scenario share it."""

    forcing: fio.Forcing
    record: dict  # the grid file, its sha256 (and the cell) for the output's attributes

    def __deepcopy__(self, memo):
        return self


@dataclasses.dataclass(frozen=True)
class GriddedForcing:
    """The gridded forcing of a map (``scour.forcing_grid``) on its cells: what
    :meth:`~mineburial.systems.mine.processes.registry.Process.cell_inputs` gives the map."""

    grid: object  # the forcing on the map's cells (fio.GriddedForcing or a wave product's)
    record: dict  # the grid file, its sha256 (and interpolation) for the output's attributes
    first: tuple  # the first cell the map computes: the base scenario takes its series

    @property
    def files(self) -> tuple:
        """``((path, SHA-256),)`` of the grid file (a map's run is identified by it)."""
        return ((self.record["forcing_grid_file"], self.record["forcing_grid_sha256"]),)

    @property
    def nbytes(self) -> int:
        """Memory of the forcing while the map runs: its fields and each cell's copy."""
        return 2 * sum(v.nbytes for v in self.grid.fields.values())

    def section(self, sec: Mapping, j: int, i: int) -> dict:
        """The ``[scour]`` section ``sec`` of cell (j, i) with its own series."""
        return dict(
            sec, forcing_grid=CellForcing(self.grid.cell(j, i), {**self.record, "forcing_grid_cell": [j, i]})
        )

    def base_section(self, sec: Mapping) -> dict:
        """The section of the map's base scenario: the series of the first cell to compute (every
        cell shares the time axis, which the lead times are checked against), recorded as the grid
        file alone."""
        return dict(sec, forcing_grid=CellForcing(self.grid.cell(*self.first), self.record))


def cell_inputs(sec, base_dir, cells) -> GriddedForcing | None:
    """The gridded forcing of a ``[scour]`` section ``sec`` on a map's cells (``cells()``: the map's
    :class:`~mineburial.analyses.maps.MapCells`, read only here), or None without ``forcing_grid``."""
    if not (isinstance(sec, Mapping) and "forcing_grid" in sec):
        return None
    cells = cells()
    g, record = read_forcing_grid(sec["forcing_grid"], base_dir, cells)
    j, i = (int(v) for v in np.argwhere(cells.computed)[0])
    return GriddedForcing(g, record, (j, i))


def read_forcing_grid(value, base_dir, cells):
    """(gridded forcing on the environment's cells, its record) of ``scour.forcing_grid``:
    a CF NetCDF (time, y, x) (:func:`mineburial.io.forcing.load_gridded_netcdf`) whose axes
    are those of the environment grid (same sizes and coordinate values, either order) and
    whose every water cell of the environment has a forcing; else one line naming the file,
    the coordinate or the cell."""
    if not isinstance(value, str):
        raise cfg.ScenarioError(f"scour.forcing_grid = {value!r} must be a NetCDF file path (time, y, x)")
    path = pathlib.Path(value)
    if not path.is_absolute() and base_dir is not None:
        path = pathlib.Path(base_dir) / path
    where = f"scour.forcing_grid '{path}'"
    if not path.is_file():
        raise cfg.ScenarioError(f"{where}: no such file")
    computed = cells.computed  # land cells' series are neither read nor checked
    ydim, xdim = cells.dims
    product = _wave_product_grid(path, cells)  # a lat/lon grid other than the environment's
    if product is not None:
        return product, {
            "forcing_grid_file": str(path),
            "forcing_grid_sha256": file_digest(path),
            "forcing_grid_interpolation": wave_products.METHOD,
        }
    g = fio.load_gridded_netcdf(path, only=(computed, (ydim, xdim)))
    if tuple(g.dims) == (xdim, ydim):  # stored (time, x, y): the environment's order
        g = dataclasses.replace(
            g,
            dims=(ydim, xdim),
            y=g.x,
            x=g.y,
            wet=g.wet.T,
            fields={k: v.transpose(0, 2, 1) for k, v in g.fields.items()},
        )
    if g.shape != computed.shape:
        raise cfg.ScenarioError(
            f"{where}: its grid ({', '.join(g.dims)}) has {g.shape[0]} x {g.shape[1]} cells, the "
            f"environment grid ({ydim}, {xdim}) {computed.shape[0]} x {computed.shape[1]}; give the "
            "forcing on the environment's cells"
        )
    for name, own, env, ref in ((g.dims[0], g.y, ydim, cells.y), (g.dims[1], g.x, xdim, cells.x)):
        own = np.asarray(own, dtype=np.float64)
        ref = np.asarray(ref, dtype=np.float64)
        bad = np.flatnonzero(~(np.abs(own - ref) <= 1e-9 * max(1.0, float(np.abs(ref).max()))))
        if bad.size:
            k = int(bad[0])
            raise cfg.ScenarioError(
                f"{where}: coordinate '{name}'[{k}] = {own[k]:g} does not match the environment grid's "
                f"'{env}'[{k}] = {ref[k]:g}; the forcing must be on the environment's cells (same "
                "coordinates)"
            )
    dry = np.argwhere(computed & ~g.wet)
    if dry.size:
        j, i = (int(v) for v in dry[0])
        raise cfg.ScenarioError(
            f"{where}: the wave height is missing at every time at {cells.label(j, i)}, a water "
            f"cell of the environment grid ({len(dry)} such cell{'s' * (len(dry) > 1)}); give its "
            "forcing, or make it land in the grid"
        )
    return g, {"forcing_grid_file": str(path), "forcing_grid_sha256": file_digest(path)}


def _wave_product_grid(path, cells):
    """A gridded forcing on its own latitude/longitude grid (a wave product: ERA5, Copernicus
    Marine, WAVEWATCH III), interpolated onto the environment's computed cells
    (:func:`mineburial.io.wave_products.load_wave_grid`: bilinear, land by the nearest sea node,
    linear in time); None for a file on the environment's own cells or not on a lat/lon grid
    (read as before, bit for bit)."""
    axes = wave_products.is_lat_lon_grid(path) if cells.geographic else None
    if axes is None:
        return None
    lat = np.asarray(cells.y, dtype=np.float64)
    lon = np.asarray(cells.x, dtype=np.float64)

    def same(own, ref):
        return own.shape == ref.shape and bool(
            np.all(np.abs(own - ref) <= 1e-9 * max(1.0, float(np.abs(ref).max())))
        )

    if same(axes[0], lat) and same(axes[1], lon):
        return None
    return wave_products.load_wave_grid(path, lat, lon, cells.computed, cells.dims, labels=cells.label)
