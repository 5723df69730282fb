"""The command line, happy paths and exit codes: ``mineburial {run, drop, example}``
(``map`` is exercised in test_maps.py; user errors in test_bad_input.py).

References: the library calls the commands stand for (simulate_drop, the example files)
and numpy statistics over the per-drop values the run wrote.
"""

import os
import subprocess
import sys

import numpy as np
import pytest
import xarray as xr

from mineburial import __version__
from mineburial.cli import main
from mineburial.io.dataset import registry_mismatches
from mineburial.kernels.mine import status
from mineburial.systems.mine.config import Scenario, ensemble_example_names, example_names, example_path
from mineburial.systems.mine.drop import simulate_drop

DROP = """
[mine]
length = 1.0
diameter = 0.25
mass = 120.0
[release]
position = [0.0, 0.0, -3.0]
velocity = [0.0, 0.0, -2.0]
pitch_deg = 40.0
[environment]
water_depth = 4.0
[sediment]
class = "soft_clay"
[numerics]
t_max = 5.0
"""

ENSEMBLE = """
[ensemble]
n = 6
seed = 4
[mine]
length = 1.0
diameter = 0.25
mass = {distribution = "uniform", low = 90.0, high = 150.0}
[release]
position = [0.0, 0.0, -2.0]
pitch_deg = {distribution = "uniform", low = 0.0, high = 60.0}
[environment]
water_depth = 3.0
[sediment]
class = "soft_clay"
[numerics]
t_max = 5.0
"""


def _cli(*args):
    """Run ``python -m mineburial.cli`` in a fresh process: (exit code, stdout, stderr)."""
    env = {**os.environ, "PYTHONPATH": os.pathsep.join(sys.path)}
    out = subprocess.run(
        [sys.executable, "-m", "mineburial.cli", *args], env=env, capture_output=True, text=True, timeout=300
    )
    return out.returncode, out.stdout, out.stderr


def test_process_exit_codes():
    rc, out, err = _cli("--version")
    assert rc == 0 and out.strip() == f"mineburial {__version__}"
    rc, out, err = _cli()  # no command: one error line
    assert rc == 2 and err.startswith("mineburial: error:") and "command" in err
    assert len(err.strip().splitlines()) == 1
    rc, out, err = _cli("example")
    assert rc == 0 and err == ""
    assert set(example_names()) | set(ensemble_example_names()) <= set(out.split())


def test_example_writes_the_embedded_file(tmp_path, capsys):
    target = tmp_path / "case.toml"
    assert main(["example", "exp2_barrel", "-o", str(target)]) == 0
    assert target.read_text() == example_path("exp2_barrel").read_text()
    assert f"to {target}" in capsys.readouterr().out
    Scenario.from_toml(target)  # a valid scenario


def test_drop_writes_the_trajectory_of_simulate_drop(tmp_path, capsys):
    scen = tmp_path / "drop.toml"
    scen.write_text(DROP)
    out = tmp_path / "traj.nc"
    assert main(["drop", str(scen), "-o", str(out), "--record-interval", "0.05", "--forces"]) == 0
    ref = simulate_drop(Scenario.from_toml(scen), record_interval=0.05, forces=True)
    with xr.open_dataset(out) as ds:
        assert ds.attrs["status"] == ref.attrs["status"] == "at_rest"
        np.testing.assert_array_equal(ds.time.values, ref.time.values)
        np.testing.assert_array_equal(ds.z.values, ref.z.values)
        assert "sediment_force_z" in ds
        assert registry_mismatches(ds, "trajectory") == []  # every variable as declared, Conventions
        assert float(ds.penetration_depth) == float(ref.penetration_depth) > 0.0
    text = capsys.readouterr().out
    assert "status at_rest" in text and f"wrote {out}" in text


@pytest.mark.parametrize("sampling", ["mc", "sobol"])
def test_run_writes_statistics_of_its_per_drop_values(tmp_path, capsys, sampling):
    scen = tmp_path / "ens.toml"
    scen.write_text(ENSEMBLE)
    out = tmp_path / "ens.nc"
    rc = main(
        [
            "run",
            str(scen),
            "-n",
            "4",
            "--seed",
            "3",
            "-o",
            str(out),
            "--per-drop",
            "--sampling",
            sampling,
            "--quiet",
        ]
    )
    assert rc == 0
    with xr.open_dataset(out) as ds:
        assert ds.sizes["realization"] == 4 and int(ds.attrs["random_seed"]) == 3
        used = np.isin(ds.status.values, status.IN_STATISTICS)
        assert used.any()
        for name in ("burial_volume", "penetration_depth"):
            assert float(ds[f"{name}_mean"]) == pytest.approx(
                float(np.mean(ds[name].values[used])), rel=1e-12
            )
    assert str(out) in capsys.readouterr().out
