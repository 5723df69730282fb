"""Shared helpers for the tests: build scenarios from small dict overrides; the warm-up of
numba's cache before the xdist workers start (:func:`pytest_configure`)."""

import copy
import os
import pathlib
import signal
import subprocess
import sys
import time

import pytest

from mineburial.systems.mine import ensemble as mine

BASE = {
    "mine": {"name": "test cylinder", "length": 1.0, "diameter": 0.25, "mass": 80.0, "com_offset": 0.0},
    "release": {
        "position": [0.0, 0.0, -5.0],
        "velocity": [0.0, 0.0, 0.0],
        "pitch_deg": 0.0,
        "heading_deg": 0.0,
        "roll_deg": 0.0,
        "angular_velocity": [0.0, 0.0, 0.0],
    },
    "environment": {
        "water_depth": 1000.0,
        "water_density": 1025.0,
        "water_viscosity": 1.0e-6,
        "air_density": 1.225,
    },
    "sediment": {"class": "soft_clay"},
    # the default integrator (dopri5) at its default tolerances (test_water_column.py asks for
    # tight ones), and the reference sediment quadrature (the fast rule is tested against it
    # in test_sediment_fast.py and test_integrators.py); a fall through the 1000 m of water
    # stops at t_max_fall, 5 s after release, and a drop that reaches a shallower seabed
    # stops at most t_max = 5 s after its first contact
    "numerics": {"dt": 1e-3, "t_max": 5.0, "t_max_fall": 5.0, "sediment_quadrature": "reference"},
}


def merge(base, over):
    out = copy.deepcopy(base)
    for key, value in over.items():
        if isinstance(value, dict) and isinstance(out.get(key), dict):
            out[key] = merge(out[key], value)
        else:
            out[key] = value
    return out


def scenario_dict(**sections):
    """The BASE test scenario with sections overridden key by key."""
    return merge(BASE, sections)


def make_scenario(**sections):
    from mineburial.systems.mine.config import Scenario

    return Scenario.from_dict(scenario_dict(**sections))


@pytest.fixture
def scenario_factory():
    return make_scenario


def cheap_ensemble():
    """Cheap drops (~0.05 s): a small cylinder 1 m above 3 m of water onto stiff clay."""
    d = scenario_dict(
        environment={"water_depth": {"distribution": "uniform", "low": 2.5, "high": 3.5}},
        release={
            "position": [0.0, 0.0, 1.0],
            "pitch_deg": {"distribution": "uniform", "low": 0.0, "high": 60.0},
        },
        sediment={"class": "stiff_clay"},
        numerics={"t_max": 3.0},
    )
    d["mine"]["mass"] = {"distribution": "normal", "mean": 80.0, "std": 5.0}
    return d


@pytest.fixture(autouse=True)
def _self_check_off_unless_asked(request, monkeypatch):
    """The numerical self-check of ``mineburial run`` (by default about one reference drop per
    255 drops, at least 8, each ~45 drops' worth) is off in the suite's in-process runs unless a
    scenario sets ``ensemble.accuracy_check`` itself: it is tested in tests/test_accuracy_check.py, and
    paying it in every CLI test would cost minutes of the suite's budget."""
    if request.module.__name__ != "test_accuracy_check":
        monkeypatch.setitem(mine.ENSEMBLE_DEFAULTS, "accuracy_check", 0)


#: one drop of the BASE scenario on the sediment quadrature named by argv[1] (``fast``: the
#: default paths, reference_paths None; ``reference``: reference_paths True), through the batch
#: driver and with a trajectory: the four run_drop specialisations most test files share
WARM_UP_MINE = """
import sys
sys.path.insert(0, sys.argv[2])
from conftest import make_scenario
from mineburial.systems.mine.drop import run_params
from mineburial.systems.mine.batch import run_batch
p, sb, cb = make_scenario(numerics={"sediment_quadrature": sys.argv[1]}).to_params()
run_batch(p[None, :], [1], sb, cb, threads=1)
run_params(p, sb, cb, record_interval=0.5)
"""

#: 0.5 s of seed 004's Table 2 case 1 through the public entry point: the restraining system's
#: driver (one specialisation for every integrator and case) and its record diagnostics, which
#: five test files share (tests/test_restraint.py first paid it: 44 s of its fixture's set-up)
WARM_UP_RESTRAINT = """
from mineburial.systems.restraint import model as restraint
restraint.simulate(restraint.table2_case(1).replace(**{"numerics.t_max": 0.5}))
"""

#: the warm-up processes: script and its arguments
WARM_UPS = {
    "fast": (WARM_UP_MINE, "fast"),
    "reference": (WARM_UP_MINE, "reference"),
    "restraint": (WARM_UP_RESTRAINT,),
}


def _warm_up_wanted(config) -> bool:
    """Whether this process is the xdist controller of a run of the whole suite on workers,
    with numba's on-disk cache on (a run of a few files should not wait for it)."""
    if hasattr(config, "workerinput") or config.getoption("collectonly", False):
        return False
    if not (config.getoption("numprocesses", 0) or 0) or config.getoption("dist", "no") == "no":
        return False
    env = os.environ
    if env.get("NUMBA_DISABLE_JIT", "0") != "0" or env.get("MINEBURIAL_NUMBA_CACHE", "1") in ("0", "false"):
        return False
    here = pathlib.Path(__file__).parent.resolve()
    return all(pathlib.Path(a.split("::")[0]).resolve() in (here, here.parent) for a in config.args)


def pytest_configure(config):
    """Compile the engine's shared paths once, in the xdist controller, before the workers start:
    from an empty cache (CI) both workers otherwise compile the same kernels at the same time
    (one run_drop specialisation is 20-60 s of CPU). Three processes (:data:`WARM_UPS`: the
    mine's default and reference paths and the restraining system) fill numba's on-disk cache
    (``NUMBA_CACHE_DIR`` or the package's ``__pycache__``), from which the workers load. The
    restraint's 70 s of compile share the two cores with the mine's reference paths (the
    longest, ~108 s alone, CPU ~90 s) after the default paths (~70 s): on a 2-core host it
    makes the warm-up ~10 s longer and takes ~45 s of compile off the workers (docs/design.md,
    "Test suite time"); on a warm cache it costs the processes' start-up and cache loads.
    Results are unaffected: a kernel loaded from the cache is the one compiled (docs/design.md,
    "Developing kernels")."""
    config.warm_up_note = None
    if not _warm_up_wanted(config):
        return
    t0 = time.perf_counter()
    here = str(pathlib.Path(__file__).parent.resolve())
    procs = {
        name: subprocess.Popen([sys.executable, "-c", script, *args, here], stdout=subprocess.DEVNULL)
        for name, (script, *args) in WARM_UPS.items()
    }
    codes = {name: proc.wait() for name, proc in procs.items()}
    config.warm_up_note = (
        f"numba cache warmed before the workers started: {time.perf_counter() - t0:.1f} s, exit codes {codes}"
    )


def pytest_report_header(config):
    return getattr(config, "warm_up_note", None)


@pytest.fixture
def sigint_handled():
    """SIGINT at Python's KeyboardInterrupt handler for the test, whatever the runner inherited: a
    test run started in the background of a shell without job control (``bash .ci/run &``) has
    SIGINT ignored, which Python and :func:`mineburial.ensembles.interrupt.sigint_flag` keep (as
    they should), so an in-process test of the flag would see no signal at all."""
    old = signal.signal(signal.SIGINT, signal.default_int_handler)
    try:
        yield
    finally:
        signal.signal(signal.SIGINT, old)
