"""What the second ``mineburial run`` no longer pays (issue 34 item 1), each with the behaviour kept.

* The NetCDF write imports no dask.distributed (xarray asked it only whether a distributed client is
  the scheduler): checked in a fresh interpreter against ``sys.modules``; the file written is the
  same as one written with dask.distributed imported first (every variable and attribute), and
  dask.distributed is importable again afterwards; with it imported before (a ``--scheduler`` run),
  nothing is blocked.
* The self-check runs beside the Dataset's building (``runner._Beside``): the calling thread's numba
  thread count is the check's, an exception in it is raised in the caller, its value returned.
"""

import subprocess
import sys
import time

import numba
import pytest

from mineburial.ensembles import runner

WRITE = r"""
import sys
import numpy as np
from mineburial.io.dataset import build
from mineburial.io.netcdf import write_netcdf
if sys.argv[2] == "with":
    import dask.distributed  # noqa: F401
ds = build({"status_count": np.arange(11, dtype=np.int64)}, {"status_code": np.arange(11)},
           {"title": "t", "date_created": "x", "history": "x"}, kind="ensemble", version="v")
before = "distributed" in sys.modules
write_netcdf(ds, sys.argv[1])
after = "distributed" in sys.modules
import distributed  # importable again
print(before, after, sys.modules.get("dask.distributed") is not None)
"""


def _write(path, mode):
    out = subprocess.run([sys.executable, "-c", WRITE, str(path), mode], capture_output=True, text=True)
    assert out.returncode == 0, out.stderr
    return out.stdout.split()


def test_the_write_imports_no_dask_distributed_and_writes_the_same_file(tmp_path):
    xr = pytest.importorskip("xarray")
    pytest.importorskip("distributed")
    assert _write(tmp_path / "plain.nc", "without") == ["False", "False", "False"]
    assert _write(tmp_path / "dist.nc", "with") == ["True", "True", "True"]
    with xr.open_dataset(tmp_path / "plain.nc") as a, xr.open_dataset(tmp_path / "dist.nc") as b:
        assert a.identical(b)
        assert a.attrs == b.attrs and a["status_count"].encoding["zlib"] == b["status_count"].encoding["zlib"]


def test_the_check_beside_has_the_callers_numba_threads_and_its_value():
    seen = []
    before = numba.get_num_threads()
    with runner.numba_threads(1):
        beside = runner._Beside(lambda x: (seen.append(numba.get_num_threads()), x * 2)[1], 21)
        assert beside.result() == 42
    assert seen == [1] and numba.get_num_threads() == before


def test_an_error_of_the_check_is_raised_in_the_caller():
    def fails():
        time.sleep(0.05)
        raise ValueError("from the check")

    with pytest.raises(ValueError, match="from the check"):
        runner._Beside(fails).result()
