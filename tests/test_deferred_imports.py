"""Computing drops imports neither xarray nor netCDF4 (``mineburial/_deferred.py``): they
are imported at the first use of a name of theirs, when a file is built, written or read.

Reference: ``sys.modules`` of a fresh interpreter, which lists every module imported.
"""

import subprocess
import sys
import textwrap

import netCDF4
import xarray

from mineburial import _deferred
from mineburial._deferred import DeferredModule

LIBRARIES = ("xarray", "netCDF4", "pandas")


def _imported_after(code: str) -> list[str]:
    report = f"import sys\nprint(' '.join(m for m in {LIBRARIES!r} if m in sys.modules))\n"
    script = textwrap.dedent(code) + "\n" + report
    done = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stderr
    return done.stdout.split()


def test_sampling_a_chunk_of_the_default_ensemble_imports_no_file_library():
    # what a dask worker or the first chunk of `mineburial run` does before its first drop
    found = _imported_after(
        """
        from mineburial.systems.mine.batch import run_batch
        from mineburial.ensembles.engine import load_ensemble
        from mineburial.systems.mine.ensemble import chunk_inputs
        from mineburial.cli import main
        spec = load_ensemble(None)
        P, valid, _ = chunk_inputs(spec, 0, 4)
        """
    )
    assert found == []


def test_building_a_dataset_imports_xarray_at_its_first_use():
    found = _imported_after(
        """
        from mineburial.io import variables as V
        V.variable("quantile").data_array([0.5])
        """
    )
    assert "xarray" in found


def test_a_deferred_module_is_the_module_it_names():
    assert _deferred.xarray.Dataset is xarray.Dataset
    assert _deferred.netCDF4.Dataset is netCDF4.Dataset
    assert DeferredModule("xarray.coding.times").decode_cf_datetime is xarray.coding.times.decode_cf_datetime
    assert "imported at its first use" in repr(_deferred.xarray)
