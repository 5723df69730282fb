"""Reading inputs safely (issue 21, items 11-14 and the traceback cases of input files).

* every input file (scenario TOML, profile CSV, empirical CSV, NetCDF core, environment
  grid) must be a regular file of sane size: a FIFO, a link to /dev/zero or a folder is
  refused in one line at once (the FIFO and /dev/zero cases run in a subprocess with a
  timeout, so that a regression fails instead of hanging or filling the memory);
* a file that does not parse is named with its line and column, never quoted;
* malformed text (not UTF-8, nested too deeply, a CSV cell over the csv module's limit),
  a NetCDF core of text and a bad MINEBURIAL_NUMBA_CACHE end in one line, exit status 2;
* a tabulated profile is looked up by bisection, bit-identical to a scan of the table
  (a brute-force reference written here) and close to numpy.interp, at a cost that does
  not grow with its rows;
* numba's cache is not loaded from a folder that others can write.
"""

import math
import os
import subprocess
import sys
import time
from pathlib import Path

import netCDF4
import numpy as np
import pytest

from mineburial import _numba, cli
from mineburial.analyses.maps import read_environment
from mineburial.analyses.synthetic import synthetic_environment
from mineburial.ensembles import distributions as dist
from mineburial.errors import ScenarioError
from mineburial.io import inputs
from mineburial.kernels.mine.environment import interpolate_row
from mineburial.kernels.mine.layout import N_PARAMS, P_RHO_WATER, P_SED_PROFILE
from mineburial.kernels.mine.sediment.laws import (
    COLUMN_OVERBURDEN,
    _bank_properties,
    _scan_properties,
    drop_bank,
)
from mineburial.systems.mine.config import Scenario
from mineburial.systems.mine.sediment_profiles import load_csv

ROOT = Path(__file__).resolve().parents[1]
TIMEOUT = 120  # s: a subprocess that hangs on a FIFO fails the test instead of the suite

SCENARIO = """
[mine]
length = 1.0
diameter = 0.25
mass = 80.0
[environment]
water_depth = 10.0
[sediment]
{sediment}
[numerics]
t_max = 5.0
"""
CORE = "depth_m,density_kg_m3,strength_pa\n0,1400,2000\n1,1430,3000\n"


def one_line_error(proc, *needles):
    """Exit status 2, one line on stderr naming each needle, no traceback."""
    err = proc.stderr.strip()
    assert proc.returncode == 2, (proc.returncode, err)
    assert len(err.splitlines()) == 1 and err.startswith("mineburial: error: "), err
    assert "Traceback" not in err
    for needle in needles:
        assert needle in err, (needle, err)
    return err


def run_cli(*args, env=None, cwd=None):
    return subprocess.run(
        [sys.executable, "-m", "mineburial.cli", *map(str, args)],
        capture_output=True,
        text=True,
        timeout=TIMEOUT,
        env={**os.environ, **(env or {})},
        cwd=cwd,
    )


def cli_main(capsys, *args):
    status = cli.main([str(a) for a in args])
    err = capsys.readouterr().err.strip()
    assert status == 2, err
    assert len(err.splitlines()) == 1 and "Traceback" not in err, err
    return err


# ---------------------------------------------------------------------------
# item 12: only regular files of sane size are read
# ---------------------------------------------------------------------------
# each reader, called on the file 'bad' in the working folder (Python source for the subprocess)
READERS = {
    "scenario": "Scenario.from_toml('bad')",
    "profile_csv": "load_csv('bad')",
    "empirical_csv": "dist.from_dict({'distribution': 'empirical', 'file': 'bad'}, 'mine.mass')",
    "netcdf_core": "load_netcdf('bad')",
    "environment_grid": "read_environment('bad')",
}
#: each kind of bad input: how to make it at a path, and the words of its refusal
BAD_INPUTS = {
    "fifo": (os.mkfifo, "FIFO (named pipe), not a regular file"),  # no writer: a read would block forever
    "dev_zero": (lambda path: os.symlink("/dev/zero", path), "character device, not a regular file"),
    "folder": (os.mkdir, "a folder, not a regular file"),
}
#: one interpreter calls every reader on every bad input, in the folder named by each line of stdin, and
#: prints one line per call: the folder, a tab, then REFUSED and the message, or what else happened
READ_EACH = """
import sys, os
from mineburial.systems.mine.config import Scenario
from mineburial.systems.mine.sediment_profiles import load_csv, load_netcdf, ScenarioError
from mineburial.ensembles import distributions as dist
from mineburial.analyses.maps import read_environment
READERS = {readers!r}
for folder in sys.stdin.read().splitlines():
    os.chdir(folder)
    try:
        eval(READERS[os.path.basename(folder).split("-", 1)[1]])
        outcome = "ACCEPTED"
    except ScenarioError as exc:
        outcome = "REFUSED " + " ".join(str(exc).split())
    except Exception as exc:
        outcome = "RAISED " + type(exc).__name__ + ": " + " ".join(str(exc).split())
    print(folder + "\t" + outcome, flush=True)
"""


@pytest.fixture(scope="module")
def refusals(tmp_path_factory):
    """{(kind, reader): what the reader did with that bad input}, all read in ONE subprocess (one
    interpreter start instead of 15: ~2 s each), with a timeout, so that a regression that blocks on
    the FIFO or reads /dev/zero fails the tests (the calls it never reached are missing) instead
    of hanging or filling the memory of the test run."""
    root = tmp_path_factory.mktemp("bad_inputs")
    folders = {}
    for kind, (make, _) in BAD_INPUTS.items():
        for reader in READERS:
            folder = root / f"{kind}-{reader}"
            folder.mkdir()
            make(folder / "bad")
            folders[str(folder)] = (kind, reader)
    try:
        proc = subprocess.run(
            [sys.executable, "-c", READ_EACH.format(readers=READERS)],
            input="\n".join(folders),
            capture_output=True,
            text=True,
            timeout=TIMEOUT,
        )
        out, missing = proc.stdout, f"no answer (exit status {proc.returncode}): {proc.stderr[-2000:]}"
    except subprocess.TimeoutExpired as exc:
        out = exc.stdout.decode() if isinstance(exc.stdout, bytes) else exc.stdout or ""
        missing = f"no answer within {TIMEOUT} s"
    answers = dict(line.split("\t", 1) for line in out.splitlines())
    return {case: answers.get(folder, missing) for folder, case in folders.items()}


def refused(refusals, kind, reader):
    outcome = refusals[kind, reader]
    assert outcome.startswith("REFUSED ") and BAD_INPUTS[kind][1] in outcome, outcome


@pytest.mark.parametrize("reader", list(READERS))
def test_fifo_input_is_refused_instead_of_hanging(refusals, reader):
    refused(refusals, "fifo", reader)


@pytest.mark.parametrize("reader", list(READERS))
def test_link_to_dev_zero_is_refused_instead_of_filling_memory(refusals, reader):
    refused(refusals, "dev_zero", reader)


@pytest.mark.parametrize("reader", list(READERS))
def test_folder_as_input_file_is_refused(refusals, reader):
    refused(refusals, "folder", reader)


def test_fifo_scenario_on_the_command_line_is_one_line(tmp_path):
    os.mkfifo(tmp_path / "s.toml")
    one_line_error(run_cli("drop", tmp_path / "s.toml"), "s.toml", "FIFO")


def test_text_input_over_the_size_limit_is_refused_without_reading_it(tmp_path):
    big = tmp_path / "core.csv"
    with open(big, "wb") as fh:  # sparse: the limit is checked on the size, nothing is read
        fh.truncate(inputs.LIMITS["text"] + 1)
    t0 = time.perf_counter()
    with pytest.raises(ScenarioError, match=r"core\.csv'.*64 MiB limit of a text input"):
        load_csv(big)
    assert time.perf_counter() - t0 < 2.0


# ---------------------------------------------------------------------------
# item 14: name the file, line and column, never the content
# ---------------------------------------------------------------------------
PASSWD = "root:x:0:0:root:/root:/bin/bash\ndaemon:x:1:1:daemon:/usr/sbin:/usr/sbin/nologin\n"


def test_empirical_file_that_is_not_a_table_is_named_not_printed(tmp_path):
    (tmp_path / "passwd").write_text(PASSWD)
    for column in (None, "x"):
        d = {"distribution": "empirical", "file": "passwd"} | ({"column": column} if column else {})
        with pytest.raises(dist.DistributionError) as info:
            dist.from_dict(d, "mine.mass", base_dir=tmp_path)
        message = str(info.value)
        assert "passwd" in message and "line 1" in message
        assert "root:" not in message and "daemon" not in message and "/bin" not in message


def test_etc_passwd_as_empirical_file_prints_none_of_it(tmp_path):
    # the case of the issue, on the real file where there is one
    if not Path("/etc/passwd").is_file():
        pytest.skip("no /etc/passwd on this system")
    first = Path("/etc/passwd").read_text().splitlines()[0]
    with pytest.raises(dist.DistributionError) as info:
        dist.from_dict({"distribution": "empirical", "file": "/etc/passwd"}, "mine.mass")
    assert "/etc/passwd" in str(info.value) and first not in str(info.value)
    assert first.split(":")[0] + ":" not in str(info.value)


def test_bad_cell_of_a_profile_csv_names_line_and_column_not_content(tmp_path):
    core = tmp_path / "core.csv"
    core.write_text("# a comment\n\ndepth_m,density_kg_m3,strength_pa\n0,1400,2000\n1,SECRET-TOKEN,3000\n")
    with pytest.raises(ScenarioError) as info:
        load_csv(core)
    message = str(info.value)
    assert "line 5, column 2 ('density_kg_m3'): not a number" in message  # the file's own line
    assert "SECRET" not in message


def test_bad_cell_of_an_empirical_csv_names_line_and_column_not_content(tmp_path):
    (tmp_path / "v.csv").write_text("mass\n# comment\n80\nSECRET-TOKEN\n")
    with pytest.raises(dist.DistributionError) as info:
        dist.from_dict({"distribution": "empirical", "file": "v.csv"}, "mine.mass", base_dir=tmp_path)
    assert "line 4, column 1 ('mass'): not a number" in str(info.value)
    assert "SECRET" not in str(info.value)


# ---------------------------------------------------------------------------
# tracebacks that become one line
# ---------------------------------------------------------------------------
def test_latin1_scenario_is_one_line_naming_line_and_column(tmp_path, capsys):
    text = SCENARIO.format(sediment='class = "soft_clay"').replace("[mine]", "# Köln\n[mine]")
    (tmp_path / "s.toml").write_bytes(text.encode("latin-1"))
    err = cli_main(capsys, "drop", tmp_path / "s.toml")
    line = text.splitlines().index("# Köln") + 1
    assert f"not UTF-8 text (byte 0xf6 at line {line}, column 4)" in err and "s.toml" in err


def test_latin1_comment_in_core_csv_is_one_line(tmp_path, capsys):
    comment = "# Bohrkern Ostsee, Kühlung"
    (tmp_path / "core.csv").write_bytes((comment + "\n" + CORE).encode("latin-1"))
    (tmp_path / "s.toml").write_text(SCENARIO.format(sediment='file = "core.csv"'))
    err = cli_main(capsys, "drop", tmp_path / "s.toml")
    column = comment.index("ü") + 1
    assert "core.csv" in err and f"not UTF-8 text (byte 0xfc at line 1, column {column})" in err


def test_toml_nested_100000_deep_is_one_line_not_a_recursion_error(tmp_path, capsys):
    (tmp_path / "s.toml").write_text("a = " + "[" * 100_000 + "]" * 100_000 + "\n")
    err = cli_main(capsys, "drop", tmp_path / "s.toml")
    assert "s.toml' is not valid TOML" in err and "nested too deeply" in err
    with pytest.raises(ScenarioError, match="nested too deeply"):
        Scenario.from_toml_string("a = " + "{b = " * 50_000 + "1" + "}" * 50_000)


def test_csv_cell_over_the_csv_field_limit_is_one_line(tmp_path, capsys):
    long_cell = "1" * 131_073  # the csv module's field_size_limit() is 131,072 characters
    (tmp_path / "core.csv").write_text(CORE + f'2,"{long_cell}",3000\n')
    (tmp_path / "s.toml").write_text(SCENARIO.format(sediment='file = "core.csv"'))
    err = cli_main(capsys, "drop", tmp_path / "s.toml")
    assert "core.csv" in err and "line 4" in err and "field larger than field limit" in err
    assert long_cell[:50] not in err
    (tmp_path / "v.csv").write_text(f'mass\n80\n"{long_cell}"\n')
    with pytest.raises(dist.DistributionError, match=r"v\.csv.*line 3.*field larger than field limit"):
        dist.from_dict({"distribution": "empirical", "file": "v.csv"}, "mine.mass", base_dir=tmp_path)


def test_netcdf_core_with_a_string_variable_is_one_line(tmp_path, capsys):
    with netCDF4.Dataset(tmp_path / "core.nc", "w") as ds:
        ds.createDimension("z", 2)
        for name, units in (("depth", "m"), ("density", "kg m-3"), ("strength", "Pa")):
            v = ds.createVariable(name, str if name == "density" else "f8", ("z",))
            v.units = units
            v[:] = np.array(["soft", "firm"], dtype=object) if name == "density" else np.array([0.0, 1.0])
    (tmp_path / "s.toml").write_text(SCENARIO.format(sediment='file = "core.nc"'))
    err = cli_main(capsys, "drop", tmp_path / "s.toml")
    assert "core.nc" in err and "variable 'density' does not hold numbers" in err and "soft" not in err


def test_bad_numba_cache_switch_is_one_line_naming_the_allowed_values():
    proc = run_cli("drop", "s.toml", env={_numba.CACHE_ENV: "maybe"})
    one_line_error(
        proc, "MINEBURIAL_NUMBA_CACHE = 'maybe'", "must be 1 (or true, yes, on", "or 0 (or false, no, off"
    )


# ---------------------------------------------------------------------------
# item 11: the profile lookup, bisection bit-identical to a scan
# ---------------------------------------------------------------------------
def scan_interpolate(xs, ys, x):
    """Brute-force reference of interpolate_row: walk the table to the bracketing pair."""
    if x <= xs[0]:
        return ys[0]
    if x >= xs[-1]:
        return ys[-1]
    k = 0
    while xs[k + 1] <= x:
        k += 1
    f = (x - xs[k]) / (xs[k + 1] - xs[k])
    return ys[k] + f * (ys[k + 1] - ys[k])


def scan_profile(d, r, s, rho_w, g):
    """Brute-force reference of the sediment profile: zeta -> (rho, S, sigma') summing trapezoids
    from the seabed down, in order (the running sums once per table, as a walk down it adds them),
    the bracketing pair found by a scan of the whole table (numpy's, not a bisection)."""
    acc = [(r[0] - rho_w) * d[0]]  # acc[j]: the sum down to knot j
    for j in range(1, len(d)):
        acc.append(acc[-1] + (0.5 * (r[j - 1] + r[j]) - rho_w) * (d[j] - d[j - 1]))

    def at(zeta):
        if zeta <= d[0]:
            return r[0], s[0], (r[0] - rho_w) * g * zeta
        if not zeta <= d[-1]:
            return r[-1], s[-1], (acc[-1] + (r[-1] - rho_w) * (zeta - d[-1])) * g
        j = int(np.argmax(d >= zeta))  # the first knot at or below zeta
        f = (zeta - d[j - 1]) / (d[j] - d[j - 1])
        rz = r[j - 1] + f * (r[j] - r[j - 1])
        sz = s[j - 1] + f * (s[j] - s[j - 1])
        return rz, sz, (acc[j - 1] + (0.5 * (r[j - 1] + rz) - rho_w) * (zeta - d[j - 1])) * g

    return at


def random_bank(rng, sizes):
    """A NaN-padded bank of random increasing tables (depth from 0, density, strength);
    the depth steps span six decades (crowded and sparse parts in one table)."""
    bank = np.full((len(sizes), 3, max(sizes)), np.nan)
    for i, n in enumerate(sizes):
        bank[i, 0, :n] = np.concatenate([[0.0], np.cumsum(10.0 ** rng.uniform(-6.0, 0.0, n - 1))])
        bank[i, 1, :n] = rng.uniform(1000.0, 2700.0, n)
        bank[i, 2, :n] = rng.uniform(0.0, 1e5, n)
    return bank


def probe_points(rng, xs):
    """Exact knots, both ends, points just inside and outside them, and random points."""
    eps = np.spacing(xs)
    return np.concatenate(
        [xs, xs + eps, xs - eps, [xs[0] - 1.0, xs[-1] + 1.0], rng.uniform(xs[0], xs[-1], 300)]
    )


def test_profile_lookup_is_bit_identical_to_a_scan_and_agrees_with_numpy_interp():
    rng = np.random.default_rng(21)
    bank = random_bank(rng, [1, 2, 3, 17, 200, 1001])
    for row in range(bank.shape[0]):
        n = int(np.sum(~np.isnan(bank[row, 0])))
        xs = bank[row, 0, :n]
        for column in (1, 2):
            ys = bank[row, column, :n]
            for x in probe_points(rng, xs):
                got = interpolate_row(bank, row, column, x)
                assert got == scan_interpolate(xs, ys, x), (row, column, x)
                assert got == pytest.approx(np.interp(x, xs, ys), rel=1e-12, abs=1e-9)


def test_drop_bank_lookup_is_bit_identical_to_the_scan_of_the_shared_bank():
    rng = np.random.default_rng(11)
    bank = random_bank(rng, [3, 1, 40, 2500, 7])
    g = 9.81
    for row in range(bank.shape[0]):
        p = np.zeros(N_PARAMS)
        p[P_SED_PROFILE] = row
        p[P_RHO_WATER] = rho_w = rng.uniform(1000.0, 1030.0)
        q, own = drop_bank(p, bank)
        n = int(np.sum(~np.isnan(bank[row, 0])))
        assert q[P_SED_PROFILE] == 0 and p[P_SED_PROFILE] == row and own.shape == (1, 5, n)
        d, r, s = (bank[row, c, :n] for c in range(3))
        scan = scan_profile(d, r, s, rho_w, g)
        # the integral column: cumulative trapezoids of (rho - rho_w), numpy's sequential cumsum
        terms = np.concatenate([[(r[0] - rho_w) * d[0]], (0.5 * (r[:-1] + r[1:]) - rho_w) * np.diff(d)])
        assert np.array_equal(own[0, COLUMN_OVERBURDEN], np.cumsum(terms))
        for zeta in probe_points(rng, d):
            fast = _bank_properties(zeta, own, 0, rho_w, g)
            assert (
                fast
                == _scan_properties(zeta, bank, row, rho_w, g)
                == _bank_properties(zeta, bank, row, rho_w, g)
            )
            assert fast == scan(zeta), (row, zeta)
            # and sigma' is the integral of (rho - rho_w) g (the trapezoid rule is exact here)
            zz = np.unique(np.concatenate([[0.0], d[d < zeta], [max(zeta, 0.0)]]))
            rr = np.interp(zz, d, r)
            ref = g * (np.sum(0.5 * (rr[1:] + rr[:-1]) * np.diff(zz)) - rho_w * zz[-1]) if zeta > 0 else None
            if ref is not None and zeta <= d[-1]:
                assert fast[2] == pytest.approx(ref, rel=1e-9, abs=1e-6)
    assert math.isnan(_bank_properties(math.nan, own, 0, 1025.0, g)[2])


def test_profile_lookup_cost_does_not_grow_with_its_rows():
    # 1,000,000 rows against 3: a scan of the table at each call (the bug) costs ~1 ms per
    # call here, 2,000 calls ~2 s; bisection costs microseconds
    timings = {}
    for n in (3, 1_000_000):
        d = np.linspace(0.0, 10.0, n)
        bank = np.stack([d, 1420.0 + 30.0 * d, 2000.0 + 1010.0 * d])[None]
        p = np.zeros(N_PARAMS)
        p[P_RHO_WATER] = 1025.0
        _, own = drop_bank(p, bank)
        _bank_properties(9.99, own, 0, 1025.0, 9.81)
        interpolate_row(bank, 0, 1, 9.99)
        t0 = time.perf_counter()
        for zeta in np.linspace(9.0, 9.999, 2000):
            _bank_properties(zeta, own, 0, 1025.0, 9.81)
            interpolate_row(bank, 0, 1, zeta)
        timings[n] = time.perf_counter() - t0
    assert timings[1_000_000] < 5 * timings[3] + 0.2, timings


# ---------------------------------------------------------------------------
# item 13: numba's cache only in a folder the user alone can write
# ---------------------------------------------------------------------------
def test_cache_folder_writable_by_every_user_is_refused(tmp_path):
    shared = tmp_path / "shared"
    shared.mkdir()
    shared.chmod(0o777)
    assert _numba.cache_folder_problem(shared) == "is writable by every user"


def test_cache_folder_of_another_user_is_refused(tmp_path):
    assert _numba.cache_folder_problem(tmp_path, uid=os.geteuid() + 1).startswith("is owned by another user")


def test_private_cache_folder_is_accepted(tmp_path):
    private = tmp_path / "private"
    private.mkdir(mode=0o700)
    assert _numba.cache_folder_problem(private) is None
    private.chmod(0o755)  # readable by others is fine: they cannot plant a file
    assert _numba.cache_folder_problem(private) is None


CACHE_KIND = (
    "from mineburial.kernels.mine.environment import interpolate_row\n"
    "print(type(interpolate_row._cache).__name__)\n"
)


def run_with_cache_dir(folder, cwd):
    env = {**os.environ, "NUMBA_CACHE_DIR": str(folder), _numba.CACHE_ENV: "1"}
    return subprocess.run(
        [sys.executable, "-c", CACHE_KIND], capture_output=True, text=True, timeout=TIMEOUT, env=env, cwd=cwd
    )


def test_numba_cache_dir_writable_by_others_is_not_used_and_warned_once(tmp_path):
    shared = tmp_path / "shared"
    shared.mkdir()
    shared.chmod(0o777)
    proc = run_with_cache_dir(shared, ROOT)
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.strip() == "NullCache"  # compiled in memory, nothing loaded from there
    warnings = [line for line in proc.stderr.splitlines() if line.startswith("mineburial: warning:")]
    assert len(warnings) == 1 and str(shared) in warnings[0] and "writable by every user" in warnings[0]


def test_private_numba_cache_dir_is_used_without_warning(tmp_path):
    private = tmp_path / "private"
    private.mkdir(mode=0o700)
    proc = run_with_cache_dir(private, ROOT)
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.strip() == "FunctionCache" and "warning" not in proc.stderr


def test_ordinary_grid_passes_the_input_check(tmp_path):
    env = synthetic_environment(ny=3, nx=4, seed=2)
    env.to_netcdf(tmp_path / "env.nc")
    grid = read_environment(tmp_path / "env.nc")
    depth = env["water_depth"].values
    assert np.array_equal(np.where(depth > 0, depth, np.nan), grid.water_depth, equal_nan=True)


# ---------------------------------------------------------------------------
# issue 35 item 6: choice weights whose sum is beyond float
# ---------------------------------------------------------------------------
def test_choice_weights_summing_beyond_float_keep_their_proportions():
    """Was: ``OverflowError: intermediate overflow in fsum`` (a traceback). Finite weights are
    proportions: 1e308, 1e308, 2e308... give what 1, 1, 2 give."""
    big = dist.from_dict(
        {"distribution": "choice", "values": [1.0, 2.0, 3.0], "weights": [1e308, 1e308, 1.5e308]}, "x"
    )
    small = dist.from_dict({"distribution": "choice", "values": [1.0, 2.0, 3.0], "weights": [2, 2, 3]}, "x")
    assert big.weights == pytest.approx(small.weights, rel=1e-15) and math.fsum(big.weights) == pytest.approx(
        1.0
    )


def test_reading_a_small_input_allocates_about_its_size_not_the_limit(tmp_path):
    """Was: ``read(limit + 1)`` allocated the 64 MiB limit for every scenario file read (a
    MemoryError under a 500 MB address-space limit). Reference: tracemalloc's peak."""
    import tracemalloc

    from mineburial.io import forcing

    path = tmp_path / "s.toml"
    path.write_text("# a small file\n" * 100)
    tracemalloc.start()
    try:
        inputs.read_text(path)
        forcing._read_text(path, "f", forcing.MAX_CSV_BYTES)
        _, peak = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()
    assert peak < 1 << 20, peak
    # the limit still holds for a file that is over it
    big = tmp_path / "big.toml"
    big.write_bytes(b"#" * (inputs.LIMITS["text"] + 10))
    with pytest.raises(inputs.InputFileError, match="limit"):
        inputs.read_text(big)
