"""Memory estimates against the memory AVAILABLE, checked before computing (issue 21, item 9).

The helper :func:`mineburial.resources.available_memory` is tested on fake ``/proc`` and
cgroup folders against values computed by hand; the commands are tested for one line,
exit status 2 and no drop computed.
"""

import os
from pathlib import Path

import numpy as np
import pytest

from mineburial import resources
from mineburial.cli import main

GiB = 2**30
KB = 1024


def fake_proc(tmp_path, meminfo=None, cgroup_lines=()):
    proc = tmp_path / "proc"
    (proc / "self").mkdir(parents=True)
    if meminfo is not None:
        (proc / "meminfo").write_text(meminfo)
    (proc / "self" / "cgroup").write_text("".join(line + "\n" for line in cgroup_lines))
    return proc


def write(folder: Path, **files):
    folder.mkdir(parents=True, exist_ok=True)
    for name, text in files.items():
        (folder / name.replace("_", ".", 1)).write_text(text)


MEMINFO = "MemTotal:       16000000 kB\nMemFree:         1000000 kB\nMemAvailable:    8000000 kB\n"


def test_available_memory_is_meminfo_available_without_a_cgroup(tmp_path):
    proc = fake_proc(tmp_path, MEMINFO, ["0::/"])
    assert resources.available_memory(proc, tmp_path / "none") == 8_000_000 * KB


def test_cgroup_v2_limit_minus_usage_below_meminfo_wins(tmp_path):
    proc = fake_proc(tmp_path, MEMINFO, ["0::/user.slice/job"])
    cg = tmp_path / "cgroup"
    write(cg, cgroup_controllers="memory")
    write(cg / "user.slice", memory_max="max\n", memory_current="123\n")  # no limit
    write(cg / "user.slice" / "job", memory_max=f"{4 * GiB}\n", memory_current=f"{1 * GiB}\n")
    # min(8e6 kB = 7.63 GiB, 4 GiB - 1 GiB)
    assert resources.available_memory(proc, cg) == 3 * GiB


def test_cgroup_v2_parent_limit_counts_too(tmp_path):
    proc = fake_proc(tmp_path, MEMINFO, ["0::/user.slice/job"])
    cg = tmp_path / "cgroup"
    write(cg, cgroup_controllers="memory")
    write(cg / "user.slice", memory_max=f"{2 * GiB}\n", memory_current=f"{3 * GiB // 2}\n")
    write(cg / "user.slice" / "job", memory_max=f"{4 * GiB}\n", memory_current=f"{1 * GiB}\n")
    assert resources.available_memory(proc, cg) == GiB // 2


def test_cgroup_v1_limit_minus_usage_and_its_no_limit_value(tmp_path):
    proc = fake_proc(tmp_path, MEMINFO, ["5:devices:/", "4:memory:/docker/abc", "0::/"])
    cg = tmp_path / "cgroup"
    # the v1 root writes "no limit" as 2**63 - 4096
    write(cg / "memory", memory_limit_in_bytes="9223372036854771712\n", memory_usage_in_bytes="5\n")
    write(
        cg / "memory" / "docker" / "abc",
        memory_limit_in_bytes=f"{2 * GiB}\n",
        memory_usage_in_bytes=f"{GiB // 2}\n",
    )
    assert resources.available_memory(proc, cg) == 3 * GiB // 2


def test_cgroup_usage_over_its_limit_leaves_nothing(tmp_path):
    proc = fake_proc(tmp_path, MEMINFO, ["0::/"])
    cg = tmp_path / "cgroup"
    write(cg, cgroup_controllers="memory", memory_max="1000\n", memory_current="5000\n")
    assert resources.available_memory(proc, cg) == 0


def test_without_meminfo_available_the_total_ram_is_the_fallback(tmp_path):
    """An old kernel (no MemAvailable line) or no /proc at all: the machine's RAM, checked
    against this machine's own /proc/meminfo MemTotal (within 5 %)."""
    total_kb = None
    for line in Path("/proc/meminfo").read_text().splitlines():
        if line.startswith("MemTotal:"):
            total_kb = int(line.split()[1])
    assert total_kb
    for proc in (fake_proc(tmp_path, "MemTotal: 5 kB\nMemFree: 1 kB\n"), tmp_path / "no-proc"):
        got = resources.available_memory(proc, tmp_path / "none")
        assert abs(got - total_kb * KB) < 0.05 * total_kb * KB, (proc, got)


def test_the_real_machine_has_a_positive_available_memory():
    got = resources.available_memory()
    assert got is not None and 0 < got <= os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES")


def test_memory_refusal_line_names_the_request_the_estimate_and_the_available():
    line = resources.memory_refusal(3 * GiB, "-n 7", "run fewer", have=2 * GiB)
    assert line == (
        "-n 7 would need about 3 GiB of memory, more than the 2 GiB available "
        "(free memory and the cgroup limit); run fewer"
    )
    assert resources.memory_refusal(2 * GiB, "x", "y", have=2 * GiB) is None
    assert "more than half of the 2 GiB" in resources.memory_refusal(
        1.5 * GiB, "x", "y", share=0.5, have=2 * GiB
    )
    assert "an unbounded amount" in resources.memory_refusal(float("inf"), "x", "y", have=2 * GiB)


# ---------------------------------------------------------------------------
# the commands
# ---------------------------------------------------------------------------
def refused(capsys, argv, *needles):
    rc = main(argv)
    err = capsys.readouterr().err
    assert rc == 2, err
    assert err.count("\n") == 1 and err.startswith("mineburial: error: "), err
    assert "Traceback" not in err
    for needle in needles:
        assert needle in err, (needle, err)
    return err


@pytest.fixture
def no_drops(monkeypatch):
    from mineburial.ensembles import engine
    from mineburial.systems.mine import batch

    def fail(*args, **kwargs):
        raise AssertionError("a drop was computed before the check")

    monkeypatch.setattr(batch, "run_batch", fail)
    monkeypatch.setattr(engine, "compute_chunk", fail)


def test_compare_with_a_trillion_drops_is_refused_before_growing_to_24_gb(capsys, no_drops, tmp_path):
    out = tmp_path / "c.nc"
    refused(
        capsys,
        ["compare", "--vary", "sediment.resistance=bearing,delta", "-n", "1000000000000", "-o", str(out)],
        "ensemble.n = 1000000000000 drops under 2 variants would need about",
        "available",
    )
    assert not out.exists()


def test_sensitivity_with_2_to_the_30_drops_is_one_line_not_a_traceback(capsys, no_drops):
    refused(
        capsys,
        ["sensitivity", "-n", "1073741824", "--quiet"],
        "-n 1073741824: the Sobol' design of",
        "TiB of memory",
        "available",
    )


def test_sensitivity_threads_0_is_one_line_not_a_traceback(capsys, no_drops):
    refused(
        capsys, ["sensitivity", "--threads", "0", "-n", "2"], "--threads = 0 is outside the allowed range 1.."
    )


def test_compare_threads_0_is_one_line_not_a_traceback(capsys, no_drops):
    refused(
        capsys,
        ["compare", "--vary", "sediment.resistance=bearing,delta", "--threads", "0", "-n", "4"],
        "--threads = 0 is outside the allowed range 1..",
    )


def test_sensitivity_memory_bound_lies_above_a_measured_peak():
    """The estimate is an upper bound of tracemalloc's peak of a small analysis."""
    import tracemalloc

    from mineburial.analyses.sensitivity import memory_needed, sobol_analysis

    class Uniform:
        def ppf(self, u):
            return u

    def model(v):
        return np.stack([v["x0"] + 2 * v["x1"], v["x2"] ** 2])

    n, d = 1024, 3
    inputs = {f"x{i}": Uniform() for i in range(d)}
    sobol_analysis(model, inputs, 4, 1, ("a", "b"), n_resamples=9)  # scipy's first-call imports
    tracemalloc.start()
    sobol_analysis(model, inputs, n, 1, ("a", "b"))
    peak = tracemalloc.get_traced_memory()[1]
    tracemalloc.stop()
    assert peak < memory_needed(n, d) < 3 * peak


def test_run_checks_the_available_memory_not_the_total_ram(capsys, no_drops, monkeypatch, tmp_path):
    """1000 drops need some 400 kB: refused when only 10 KiB are available."""
    monkeypatch.setattr(resources, "available_memory", lambda *a: 10 * KB)
    refused(
        capsys,
        ["run", "-n", "1000", "-o", str(tmp_path / "o.nc"), "--quiet"],
        "ensemble.n = 1000 drops",
        "more than the 10 KiB available",
    )


def test_drop_trajectory_check_takes_half_of_the_available_memory(monkeypatch):
    from mineburial.systems.mine.drop import memory_shortfall

    monkeypatch.setattr(resources, "available_memory", lambda *a: 1_000_000)
    assert memory_shortfall(400_000.0) is None
    assert memory_shortfall(600_000.0) == 1_000_000.0
    assert memory_shortfall(float("inf")) == 1_000_000.0


def test_a_4_million_cell_map_is_refused_before_computing(monkeypatch):
    """A 2000 x 2000 grid used 2.4 GB unchecked: 20 kB a cell to compute needs 80 GB, more than
    the 24 GiB made available here (a machine with more free memory would rightly accept it)."""
    from mineburial.analyses.maps import MAP_BYTES_A_COMPUTED_CELL, MapError, _check_map_memory
    from mineburial.ensembles import engine

    monkeypatch.setattr(resources, "available_memory", lambda *a: 24 * GiB)
    base = engine.load_ensemble(None, n=10)
    status = np.zeros((2000, 2000), dtype=np.int8)
    assert 4_000_000 * MAP_BYTES_A_COMPUTED_CELL > 24 * GiB
    with pytest.raises(MapError, match=r"the map over the 2000 x 2000 environment grid \(4000000 cells"):
        _check_map_memory(base, status)


def test_map_cli_checks_the_available_memory_before_computing(capsys, no_drops, monkeypatch, tmp_path):
    from mineburial.analyses.synthetic import write_synthetic_environment

    env = write_synthetic_environment(tmp_path / "env.nc", ny=3, nx=4)
    scenario = tmp_path / "s.toml"
    assert main(["example", "default_soft_mud", "-o", str(scenario)]) == 0
    monkeypatch.setattr(resources, "available_memory", lambda *a: 100 * KB)
    out = tmp_path / "map.nc"
    refused(
        capsys,
        ["map", str(scenario), "--environment", str(env), "-o", str(out), "-n", "2", "--quiet"],
        "the map over the 3 x 4 environment grid (11 cells to compute)",
        "more than the 100 KiB available",
    )
    assert not out.exists()
