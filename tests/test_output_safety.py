"""Files written by the commands: nothing destroyed (issue 21 items 1-5 and 15, and the
output-side tracebacks).

Every command keeps the promises ``run`` keeps: a file it reads is never overwritten
(resolved through links); an output is written only as a regular file in place of a
regular file or nothing; the ``OUT.nc.parts`` working folder is used only if mineburial
created and marked it, and its lock is never followed nor truncated; the output path and
the plot format are checked before computing; a failed final write is one line naming
the path, with the old output and the finished chunks intact.

Independent references: the bytes of every file before the command (a refused command
must leave all of them as they were), the kind of a file from ``os.lstat`` (a device
stays a device), a second command that is refused while the first holds the output, and
a clean run without an output path (a rerun after a failed write must equal it bit for
bit).
"""

import errno
import os
import stat
import subprocess
import sys
import textwrap

import numpy as np
import pytest
import xarray as xr
from conftest import scenario_dict

from mineburial.cli import main
from mineburial.ensembles import engine, store
from mineburial.ensembles.runner import run_ensemble
from mineburial.io.files import OutputPathError, atomic_path, atomic_write_bytes
from mineburial.systems.mine import batch
from mineburial.systems.mine import drop as drop_module
from mineburial.systems.mine.config import dumps_toml
from mineburial.systems.restraint import model as R

VARY = "sediment.resistance=bearing,delta"
CORE = "depth_m,density_kg_m3,strength_pa\n0.0,1500.0,2000.0\n0.5,1600.0,4000.0\n2.0,1700.0,8000.0\n"


def cheap(n=8, chunk=2):
    """Cheap drops (~0.1 s) onto the core ``core.csv``; mass from the empirical file
    ``masses.csv``, pitch and water depth uniform."""
    d = scenario_dict(
        environment={"water_depth": {"distribution": "uniform", "low": 2.5, "high": 3.5}},
        release={
            "position": [0.0, 0.0, 1.0],
            "pitch_deg": {"distribution": "uniform", "low": 0.0, "high": 60.0},
        },
        numerics={"t_max": 3.0, "sediment_quadrature": "fast"},
    )
    d["sediment"] = {"file": "core.csv"}
    d["mine"]["mass"] = {"distribution": "empirical", "file": "masses.csv", "column": "mass"}
    d["ensemble"] = {"n": n, "chunk_size": chunk}
    return d


class Files:
    """A folder with an ensemble scenario, a single-drop scenario, a restraint case, the
    core CSV and the empirical-distribution file they read."""

    def __init__(self, folder):
        self.folder = folder
        self.core = folder / "core.csv"
        self.core.write_text(CORE)
        self.masses = folder / "masses.csv"
        self.masses.write_text("mass\n75.0\n80.0\n85.0\n")
        self.scenario = folder / "s.toml"
        self.scenario.write_text(dumps_toml(cheap()))
        single = scenario_dict(
            environment={"water_depth": 3.0},
            release={"position": [0.0, 0.0, 1.0]},
            numerics={"t_max": 3.0, "sediment_quadrature": "fast"},
        )
        single["sediment"] = {"file": "core.csv"}
        self.single = folder / "single.toml"
        self.single.write_text(dumps_toml(single))
        self.case = folder / "case.toml"
        self.case.write_text(R.example_text("restraint_case1"))

    def argv(self, command, output):
        output = str(output)
        return {
            "run": ["run", str(self.scenario), "--quiet", "-o", output],
            "compare": ["compare", str(self.scenario), "--vary", VARY, "-n", "4", "--quiet", "-o", output],
            "sensitivity": ["sensitivity", str(self.scenario), "-n", "2", "--quiet", "-o", output],
            "drop": ["drop", str(self.single), "-o", output],
            "restrain": ["restrain", str(self.case), "-o", output],
        }[command]


COMMANDS = ("run", "compare", "sensitivity", "drop", "restrain")


@pytest.fixture
def files(tmp_path):
    return Files(tmp_path)


@pytest.fixture
def no_computing(monkeypatch):
    """Any drop, ensemble chunk or restraint run fails the test: refusals come first."""

    def fail(*args, **kw):
        raise AssertionError("something was computed before the check")

    for module, name in (
        (batch, "run_batch"),
        (engine, "compute_chunk"),
        (drop_module, "simulate_drop"),
        (R, "simulate"),
    ):
        monkeypatch.setattr(module, name, fail)


def snapshot(folder):
    """Every entry under ``folder``: its kind and its bytes (a link: its target)."""
    out = {}
    for root, dirs, names in os.walk(folder):
        for name in dirs + names:
            path = os.path.join(root, name)
            st = os.lstat(path)
            if stat.S_ISLNK(st.st_mode):
                out[path] = ("link", os.readlink(path))
            elif stat.S_ISREG(st.st_mode):
                out[path] = ("file", open(path, "rb").read())
            else:
                out[path] = (stat.S_IFMT(st.st_mode), None)
    return out


def refused(capsys, argv, *needles):
    """``argv`` ends with status 2 and one line naming the problem, no traceback."""
    rc = main(argv)
    err = capsys.readouterr().err
    assert rc == 2, err
    assert err.count("\n") == 1 and err.startswith("mineburial: error: "), err
    for needle in needles:
        assert needle in err, (needle, err)
    return err


def refused_unchanged(capsys, folder, argv, *needles):
    before = snapshot(folder)
    refused(capsys, argv, *needles)
    assert snapshot(folder) == before


# ---------------------------------------------------------------------------
# item 1: a file a command reads is never its output
# ---------------------------------------------------------------------------
def test_compare_refuses_to_overwrite_its_scenario(files, capsys, no_computing):
    refused_unchanged(capsys, files.folder, files.argv("compare", files.scenario), "is an input of the run")


def test_compare_refuses_to_overwrite_a_referenced_core_csv(files, capsys, no_computing):
    refused_unchanged(capsys, files.folder, files.argv("compare", files.core), "is an input of the run")


def test_compare_refuses_to_overwrite_a_core_named_by_a_varied_value(files, capsys, no_computing):
    other = files.folder / "core2.csv"
    other.write_text(CORE)
    argv = ["compare", str(files.scenario), "--vary", f"sediment.file={files.core},{other}", "-n", "2"]
    refused_unchanged(capsys, files.folder, argv + ["-o", str(other)], "is an input of the run")


def test_sensitivity_refuses_to_overwrite_its_scenario(files, capsys, no_computing):
    refused_unchanged(capsys, files.folder, files.argv("sensitivity", files.scenario), "is an input")


def test_sensitivity_refuses_to_overwrite_an_empirical_distribution_file(files, capsys, no_computing):
    refused_unchanged(capsys, files.folder, files.argv("sensitivity", files.masses), "is an input")


def test_drop_refuses_to_overwrite_a_referenced_core_csv(files, capsys, no_computing):
    refused_unchanged(capsys, files.folder, files.argv("drop", files.core), "is an input of the run")


@pytest.mark.parametrize("command", COMMANDS)
def test_an_output_linked_to_an_input_is_refused_by_every_command(files, capsys, no_computing, command):
    """The check resolves links: an -o that is a link to the file read is that file."""
    read = {"drop": files.single, "restrain": files.case}.get(command, files.scenario)
    link = files.folder / "out.nc"
    link.symlink_to(read.name)
    refused_unchanged(capsys, files.folder, files.argv(command, link), "is an input of the run")


# ---------------------------------------------------------------------------
# item 2: the working folder and its lock
# ---------------------------------------------------------------------------
@pytest.mark.parametrize("command", ["run", "compare", "drop"])
def test_a_users_folder_named_like_the_parts_folder_is_never_emptied(files, capsys, no_computing, command):
    parts = files.folder / "out.nc.parts"
    parts.mkdir()
    (parts / "notes.txt").write_text("a user's own notes")
    (parts / "chunk-000000000000-000000000002.npz").write_text("not a chunk")
    refused_unchanged(
        capsys, files.folder, files.argv(command, files.folder / "out.nc"), "was not created by mineburial"
    )


def test_a_parts_folder_that_is_a_symlink_is_refused_and_its_target_untouched(files, capsys, no_computing):
    victim = files.folder / "victim"
    victim.mkdir()
    (victim / "thesis.nc").write_text("precious")
    (files.folder / "out.nc.parts").symlink_to(victim)
    refused_unchanged(capsys, files.folder, files.argv("run", files.folder / "out.nc"), "is a symbolic link")


def test_a_lock_that_is_a_symlink_is_neither_followed_nor_truncated(files, capsys, no_computing):
    victim = files.folder / "victim.txt"
    victim.write_text("precious")
    parts = store.own_folder(files.folder / "out.nc.parts")  # a folder mineburial made
    (parts / "lock").symlink_to(victim)
    refused_unchanged(capsys, files.folder, files.argv("run", files.folder / "out.nc"), "lock")


def test_a_stale_lock_is_created_anew_not_truncated_in_place(tmp_path):
    """A lock file left by a dead run is replaced by a new file: a second name of the old
    one (a hard link planted in the folder) keeps its contents."""
    victim = tmp_path / "victim.txt"
    victim.write_text("precious")
    parts = store.own_folder(tmp_path / "out.nc.parts")
    os.link(victim, parts / "lock")
    lock = store.RunLock(parts, tmp_path / "out.nc").acquire()
    try:
        assert victim.read_text() == "precious"
        assert not os.path.samefile(victim, parts / "lock")
        assert f'"pid": {os.getpid()}' in (parts / "lock").read_text()
    finally:
        lock.release()


def test_finishing_removes_links_in_the_parts_folder_not_their_targets(files, capsys):
    victim = files.folder / "victim"
    victim.mkdir()
    (victim / "thesis.nc").write_text("precious")
    parts = store.own_folder(files.folder / "out.nc.parts")  # left by a killed run ...
    (parts / "cell-0").symlink_to(victim)  # ... with a link planted in it
    assert main(files.argv("drop", files.folder / "out.nc")) == 0
    assert (victim / "thesis.nc").read_text() == "precious"
    assert not parts.exists() and (files.folder / "out.nc").is_file()


# ---------------------------------------------------------------------------
# item 3: outputs are regular files in place of a regular file or nothing
# ---------------------------------------------------------------------------
@pytest.mark.parametrize("device", ["/dev/null", "/dev/full"])
@pytest.mark.parametrize("command", COMMANDS)
def test_a_device_as_output_is_refused_and_stays_a_device(files, capsys, no_computing, command, device):
    if not os.path.exists(device):
        pytest.skip(f"{device} does not exist on this system")
    before = os.lstat(device)
    refused(capsys, files.argv(command, device), "is a character device")
    after = os.lstat(device)
    assert stat.S_ISCHR(after.st_mode) and after.st_rdev == before.st_rdev and after.st_ino == before.st_ino


@pytest.mark.parametrize("command", ["compare", "drop", "restrain"])
def test_a_fifo_as_output_is_refused_without_hanging(files, capsys, no_computing, command):
    fifo = files.folder / "out.nc"
    os.mkfifo(fifo)
    refused_unchanged(capsys, files.folder, files.argv(command, fifo), "is a FIFO")


def test_compare_output_dot_is_refused_as_a_folder(files, capsys, no_computing, monkeypatch):
    """Was "Device or resource busy" from the rename, after computing."""
    monkeypatch.chdir(files.folder)
    refused_unchanged(capsys, files.folder, files.argv("compare", "."), "'.' is an existing folder")


@pytest.mark.parametrize("command", COMMANDS)
def test_a_symlink_output_is_refused_and_neither_link_nor_target_change(files, capsys, no_computing, command):
    """The decision of docs/design.md ("Outputs"): a link is neither written through nor replaced."""
    target = files.folder / "older.nc"
    target.write_text("an older result")
    (files.folder / "out.nc").symlink_to(target.name)
    dangling = files.folder / "new.nc"
    dangling.symlink_to("nowhere.nc")
    refused_unchanged(capsys, files.folder, files.argv(command, files.folder / "out.nc"), "symbolic link")
    refused_unchanged(capsys, files.folder, files.argv(command, dangling), "symbolic link")


def test_the_atomic_write_never_renames_over_a_link_made_while_writing(tmp_path):
    """The destination is checked again just before the rename."""
    target = tmp_path / "target.txt"
    target.write_text("precious")
    path = tmp_path / "out.nc"
    with pytest.raises(OutputPathError, match="symbolic link"):
        with atomic_path(path) as tmp:
            tmp.write_text("new")
            path.symlink_to(target)  # someone plants a link meanwhile
    assert path.is_symlink() and target.read_text() == "precious"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out.nc", "target.txt"]


# ---------------------------------------------------------------------------
# item 4: mineburial example never overwrites silently
# ---------------------------------------------------------------------------
def test_example_refuses_to_overwrite_an_edited_file_unless_forced(tmp_path, capsys):
    target = tmp_path / "default_mine.toml"
    assert main(["example", "default_mine", "-o", str(target)]) == 0
    original = target.read_text()
    target.write_text(original + "\n# my edits\n")
    refused_unchanged(capsys, tmp_path, ["example", "default_mine", "-o", str(target)], "--force")
    assert main(["example", "default_mine", "-o", str(target), "--force"]) == 0
    assert target.read_text() == original


def test_example_never_writes_through_a_symlink(tmp_path, capsys):
    victim = tmp_path / "victim.toml"
    victim.write_text("# my scenario\n")
    link = tmp_path / "default_mine.toml"
    link.symlink_to(victim.name)
    dangling = tmp_path / "new.toml"
    dangling.symlink_to("elsewhere.toml")
    for argv in (["-o", str(link)], ["-o", str(link), "--force"], ["-o", str(dangling), "--force"]):
        refused_unchanged(capsys, tmp_path, ["example", "default_mine", *argv])


# ---------------------------------------------------------------------------
# item 5: two commands on one output
# ---------------------------------------------------------------------------
def test_a_second_drop_on_an_output_being_written_is_refused_not_lost(files, capsys, monkeypatch):
    """Was: both drops reported "wrote t.nc" and one result was lost. The second drop
    starts while the first is computing (called from inside the first's simulation)."""
    out = files.folder / "t.nc"
    heavier = files.folder / "heavier.toml"
    heavier.write_text(files.single.read_text().replace("mass = 80.0", "mass = 120.0"))
    real = drop_module.simulate_drop
    second = []

    def first_simulation(*args, **kw):
        if not second:
            second.append(main(["drop", str(heavier), "-o", str(out)]))
        return real(*args, **kw)

    monkeypatch.setattr(drop_module, "simulate_drop", first_simulation)
    assert main(["drop", str(files.single), "-o", str(out)]) == 0
    captured = capsys.readouterr()
    assert second == [2]
    assert "is being written by another mineburial run" in captured.err
    assert captured.out.count("wrote") == 1
    with xr.open_dataset(out) as ds:  # the first drop's result, intact
        assert '"mass": 80.0' in ds.attrs["scenario"]
    assert not (files.folder / "t.nc.parts").exists()


# ---------------------------------------------------------------------------
# item 15: no promise of a resume that cannot happen
# ---------------------------------------------------------------------------
@pytest.mark.parametrize("command", ["drop", "restrain"])  # compare, sensitivity: test_*_driver.py
def test_an_interrupted_command_that_cannot_resume_does_not_promise_it(files, capsys, monkeypatch, command):
    def interrupted(*args, **kw):
        raise KeyboardInterrupt

    for module, name in ((batch, "run_batch"), (drop_module, "simulate_drop"), (R, "simulate")):
        monkeypatch.setattr(module, name, interrupted)
    out = files.folder / "out.nc"
    assert main(files.argv(command, out)) == 130
    err = capsys.readouterr().err
    assert err.splitlines() == [
        "mineburial: interrupted; this command cannot resume: rerun it to start again"
    ]
    assert not out.exists() and not (files.folder / "out.nc.parts").exists()


# ---------------------------------------------------------------------------
# output-side tracebacks: checks before computing, a failed final write
# ---------------------------------------------------------------------------
@pytest.mark.parametrize("command", ["restrain", "compare", "sensitivity"])
@pytest.mark.parametrize(
    ("output", "needle"),
    [("no/out.nc", "does not exist"), (".", "is an existing folder"), ("s.toml/out.nc", "is a file")],
)
def test_the_output_path_is_checked_before_computing(files, capsys, no_computing, command, output, needle):
    refused_unchanged(capsys, files.folder, files.argv(command, files.folder / output), needle)


@pytest.mark.parametrize("command", ["compare", "sensitivity"])
def test_an_unknown_plot_format_is_refused_before_computing(files, capsys, no_computing, command):
    pytest.importorskip("matplotlib")
    argv = files.argv(command, files.folder / "out.nc") + ["--plot", str(files.folder / "p.xyz")]
    refused_unchanged(capsys, files.folder, argv, "unsupported image type '.xyz'")


def test_an_os_error_that_names_no_file_names_the_output(tmp_path):
    """Was "[Errno 28] No space left on device", without the path."""
    path = tmp_path / "out.nc"
    with pytest.raises(OSError) as caught:
        with atomic_path(path):
            raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))
    assert caught.value.errno == errno.ENOSPC and caught.value.filename == str(path)
    assert list(tmp_path.iterdir()) == []


LIMITED = textwrap.dedent(
    """
    import resource, signal, sys
    from mineburial.cli import main
    from mineburial.ensembles import store

    limit = int(sys.argv[1])
    real = store.OutputRun.commit

    def limited_commit(self, ds):  # the file-size limit holds during the final write
        signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
        resource.setrlimit(resource.RLIMIT_FSIZE, (limit, resource.getrlimit(resource.RLIMIT_FSIZE)[1]))
        return real(self, ds)

    store.OutputRun.commit = limited_commit
    sys.exit(main(sys.argv[2:]))
    """
)


def test_a_file_size_limit_during_the_final_write_is_one_line_and_keeps_old_output_and_chunks(
    files, capsys, monkeypatch
):
    """Was ``RuntimeError: NetCDF: HDF error`` with a traceback. A real write failure:
    RLIMIT_FSIZE (SIGXFSZ ignored, so the write fails with EFBIG as on a full disk) below
    the size of the NetCDF file and above that of the chunk files."""
    pytest.importorskip("resource")
    out = files.folder / "out.nc"
    out.write_bytes(b"the output of an earlier run")
    limit = 64 * 1024
    proc = subprocess.run(
        [sys.executable, "-c", LIMITED, str(limit), *files.argv("run", out)],
        capture_output=True,
        text=True,
        timeout=600,
        env={**os.environ, "PYTHONPATH": os.pathsep.join(sys.path)},
    )
    assert proc.returncode == 2, proc.stderr
    lines = proc.stderr.strip().splitlines()
    assert "Traceback" not in proc.stderr and len(lines) == 1, proc.stderr
    assert lines[0].startswith(f"mineburial: error: {out}: writing the NetCDF file failed (NetCDF: HDF")
    assert out.read_bytes() == b"the output of an earlier run"
    chunks = sorted((files.folder / "out.nc.parts").glob("chunk-*.npz"))
    assert len(chunks) == 4 and all(c.stat().st_size < limit for c in chunks)
    assert not list(files.folder.glob(".out.nc.*.tmp"))
    # the rerun completes from the kept chunks and equals a clean run
    calls = []
    real = engine.compute_chunk
    monkeypatch.setattr(engine, "compute_chunk", lambda *a: (calls.append(a[1:]), real(*a))[1])
    assert main(files.argv("run", out)) == 0
    assert calls == [] and "discarding" not in capsys.readouterr().err
    assert not (files.folder / "out.nc.parts").exists()
    clean = run_ensemble(files.scenario)
    with xr.open_dataset(out) as back:
        for name in clean.data_vars:
            assert np.array_equal(back[name].values, clean[name].values, equal_nan=True), name


def test_a_write_beyond_a_file_size_limit_names_the_file(tmp_path):
    """The OS error of a plain write (EFBIG, as ENOSPC on a full disk) names the path."""
    pytest.importorskip("resource")
    code = textwrap.dedent(
        """
        import resource, signal, sys
        from mineburial.io.files import atomic_write_bytes
        signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
        resource.setrlimit(resource.RLIMIT_FSIZE, (1000, resource.getrlimit(resource.RLIMIT_FSIZE)[1]))
        try:
            atomic_write_bytes(sys.argv[1], b"x" * 5000)
        except OSError as exc:
            print(exc.errno, exc.filename)
        """
    )
    path = tmp_path / "big.bin"
    atomic_write_bytes(path, b"old")
    proc = subprocess.run(
        [sys.executable, "-c", code, str(path)],
        capture_output=True,
        text=True,
        timeout=120,
        env={**os.environ, "PYTHONPATH": os.pathsep.join(sys.path)},
    )
    assert proc.stdout.split() == [str(errno.EFBIG), str(path)], proc.stderr
    assert path.read_bytes() == b"old" and sorted(p.name for p in tmp_path.iterdir()) == ["big.bin"]


# ---------------------------------------------------------------------------
# issue 35 item 7: validate -o through the one writer
# ---------------------------------------------------------------------------
@pytest.fixture
def no_cases(monkeypatch):
    """The validation cases replaced by none: the report's files are written at once."""
    from mineburial.validation import report

    monkeypatch.setattr(report, "run_case", lambda case, quick=False, figures=None: [])


def test_validate_refuses_a_symlinked_report_folder(tmp_path, capsys, no_cases):
    """Was: written through the link into its target folder."""
    target = tmp_path / "elsewhere"
    target.mkdir()
    link = tmp_path / "validation"
    link.symlink_to(target)
    refused_unchanged(capsys, tmp_path, ["validate", "-o", str(link)], "symbolic link")


def test_validate_never_replaces_a_users_summary_but_replaces_its_own_report(tmp_path, capsys, no_cases):
    """Was: a user's summary.md in an existing folder replaced without a word."""
    folder = tmp_path / "notes"
    folder.mkdir()
    (folder / "summary.md").write_text("# my own summary\n")
    refused_unchanged(
        capsys, tmp_path, ["validate", "-o", str(folder)], "is not a report of mineburial validate"
    )
    fresh = tmp_path / "report"
    assert main(["validate", "-o", str(fresh)]) == 0
    first = (fresh / "summary.md").read_text()
    assert first.startswith("# Validation summary\n\nGenerated by `mineburial validate")
    assert main(["validate", "-o", str(fresh)]) == 0  # an earlier report is replaced
    assert sorted(p.name for p in fresh.iterdir()) == ["report.md", "results.json", "summary.md"]
