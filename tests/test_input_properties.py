"""Property-based tests of the input readers (issue 21), with ``hypothesis``.

The scenario TOML readers, the two CSV readers (tabulated profile, empirical
distribution) and the environment grid reader are fed random bytes and mutated valid
inputs (lines deleted, duplicated or swapped, cells swapped or replaced by random
numbers and text, random unicode inserted, every numeric field of an example scenario
given a random value). The property, for every input: the reader either returns a
valid object (checked against the reader's documented invariants, not against its own
output) or raises the project's one-line error type, :class:`ScenarioError` (or one of
its family: DistributionError, MapError, ...) -- never another exception, never a
hang (each example has a deadline). ``derandomize=True``: the examples are the same on
every run, so a failure is reproducible and an expected failure stays expected.
"""

from __future__ import annotations

import copy
import math
from pathlib import Path

import numpy as np
import pytest
import xarray as xr
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from test_bad_input import toml_text

from mineburial.analyses.maps import EnvironmentGrid, read_environment
from mineburial.analyses.synthetic import synthetic_environment
from mineburial.ensembles import distributions as dist
from mineburial.ensembles.engine import load_ensemble
from mineburial.errors import ScenarioError
from mineburial.systems.mine.config import Scenario, example_path, tomllib
from mineburial.systems.mine.ensemble import EnsembleSpec
from mineburial.systems.mine.sediment_profiles import SedimentProfile, load_csv
from mineburial.systems.restraint import model as restraint

SETTINGS = settings(
    max_examples=25,
    deadline=10_000,  # ms per example: a reader that hangs fails (generous: a shared 2-core CI)
    derandomize=True,
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large],
    database=None,
)

FOLDER = Path()  # the module's scratch folder, set by the fixture below


@pytest.fixture(scope="module", autouse=True)
def scratch_folder(tmp_path_factory):
    """Files the readers are fed are written here (pytest's temporary folders, not /tmp)."""
    global FOLDER
    FOLDER = tmp_path_factory.mktemp("properties")


SINGLE_TEXT = Path(example_path("default_mine")).read_text()
ENSEMBLE_TEXT = Path(example_path("default_soft_mud")).read_text()
RESTRAINT_TEXT = restraint.example_text("restraint_case1")
CORE = "depth_m,density_kg_m3,strength_pa\n0.0,1500,1000\n0.5,1550,2000\n1.0,1600,3000\n2.0,1650,5000\n"
DIST = "m\n78.0\n80.0\n82.0\n"


def _file(name: str, content: bytes) -> Path:
    path = FOLDER / name
    path.write_bytes(content)
    return path


# ---------------------------------------------------------------------------
# mutations
# ---------------------------------------------------------------------------
NUMBER_TEXT = st.one_of(
    st.floats(allow_nan=True, allow_infinity=True).map(repr),
    st.integers(min_value=-(10**30), max_value=10**30).map(str),
    st.sampled_from(["nan", "inf", "-inf", "1e999", "-0", "0x10", "1_000", "", " ", "+", "."]),
)
CELL = st.one_of(NUMBER_TEXT, st.text(max_size=12))


@st.composite
def mutated_lines(draw, text: str, separator: str | None = None) -> bytes:
    """``text`` with up to four random line edits: delete, duplicate, swap two lines,
    swap two cells, replace a cell (``separator``) or a number by random text, insert
    random unicode."""
    lines = text.splitlines()
    for _ in range(draw(st.integers(1, 4))):
        if not lines:
            break
        i = draw(st.integers(0, len(lines) - 1))
        op = draw(st.sampled_from(["delete", "duplicate", "swap", "cells", "number", "unicode"]))
        if op == "delete":
            del lines[i]
        elif op == "duplicate":
            lines.insert(i, lines[i])
        elif op == "swap":
            j = draw(st.integers(0, len(lines) - 1))
            lines[i], lines[j] = lines[j], lines[i]
        elif op == "cells" and separator:
            cells = lines[i].split(separator)
            j, k = draw(st.integers(0, len(cells) - 1)), draw(st.integers(0, len(cells) - 1))
            cells[j], cells[k] = cells[k], cells[j]
            lines[i] = separator.join(cells)
        elif op == "number":
            cells = lines[i].split(separator or " = ")
            j = draw(st.integers(0, len(cells) - 1))
            cells[j] = draw(CELL)
            lines[i] = (separator or " = ").join(cells)
        else:
            at = draw(st.integers(0, len(lines[i])))
            lines[i] = lines[i][:at] + draw(st.text(min_size=1, max_size=5)) + lines[i][at:]
    return ("\n".join(lines) + "\n").encode("utf-8", "surrogatepass")


RANDOM_BYTES = st.binary(max_size=400)
RANDOM_TEXT = st.text(max_size=400).map(lambda t: t.encode("utf-8", "surrogatepass"))


def _utf8(data: bytes) -> bool:
    try:
        data.decode("utf-8")
    except UnicodeDecodeError:
        return False
    return True


# ---------------------------------------------------------------------------
# the readers and what a valid result is
# ---------------------------------------------------------------------------
def read_single(data: bytes):
    s = Scenario.from_toml(_file("s.toml", data))
    assert isinstance(s, Scenario)
    assert s.mine.length > 0 and s.mine.diameter > 0 and s.mine.mass > 0
    assert all(math.isfinite(x) for x in s.release.position)
    return s


def read_ensemble(data: bytes):
    spec = load_ensemble(_file("e.toml", data))
    assert isinstance(spec, EnsembleSpec)
    assert spec.n >= 1
    return spec


def read_restraint(data: bytes):
    case = restraint.RestraintCase.from_toml(_file("r.toml", data))
    assert isinstance(case, restraint.RestraintCase)
    assert all(math.isfinite(v) for v in case.values.values() if isinstance(v, float))
    return case


def read_core(data: bytes):
    p = load_csv(_file("core.csv", data))
    assert isinstance(p, SedimentProfile)
    assert p.depth[0] == 0.0 and np.all(np.diff(p.depth) > 0)
    assert np.all(np.isfinite(p.density)) and np.all(p.density > 0)
    assert np.all(np.isfinite(p.strength)) and np.all(p.strength >= 0)
    return p


def read_empirical(data: bytes):
    _file("dist.csv", data)
    d = dist.from_dict(
        {"distribution": "empirical", "file": "dist.csv", "column": "m"}, "mine.mass", base_dir=FOLDER
    )
    assert isinstance(d, dist.Empirical)
    assert len(d.values) >= 1 and all(math.isfinite(v) for v in d.values)
    assert list(d.values) == sorted(d.values)
    return d


def read_grid(source):
    g = read_environment(source)
    assert isinstance(g, EnvironmentGrid)
    ny, nx = g.shape
    assert ny >= 1 and nx >= 1, f"a grid of {ny} x {nx} cells"
    assert g.ds.sizes[g.ydim] == ny and g.ds.sizes[g.xdim] == nx
    assert g.water_depth.dtype == np.float64
    return g


def refused_or_valid(reader, data) -> None:
    """The property: a valid object or a ScenarioError with a one-line message."""
    try:
        reader(data)
    except ScenarioError as exc:
        message = " ".join(str(exc).split())
        assert message, "an empty error message"


# ---------------------------------------------------------------------------
# scenario TOML
# ---------------------------------------------------------------------------
TOML_READERS = {
    "single": (read_single, SINGLE_TEXT),
    "ensemble": (read_ensemble, ENSEMBLE_TEXT),
    "restraint": (read_restraint, RESTRAINT_TEXT),
}


@pytest.mark.parametrize("kind", list(TOML_READERS))
@SETTINGS
@given(data=st.data())
def test_toml_reader_on_mutated_valid_files(kind, data):
    reader, text = TOML_READERS[kind]
    refused_or_valid(reader, data.draw(mutated_lines(text)))


@pytest.mark.parametrize("kind", list(TOML_READERS))
@SETTINGS
@given(raw=RANDOM_TEXT)
def test_toml_reader_on_random_text(kind, raw):
    refused_or_valid(TOML_READERS[kind][0], raw)


def _numeric_leaves(d, prefix=()):
    for key, value in d.items():
        if isinstance(value, dict):
            yield from _numeric_leaves(value, prefix + (key,))
        elif isinstance(value, list):
            for i, item in enumerate(value):
                if isinstance(item, (int, float)) and not isinstance(item, bool):
                    yield prefix + (key, i)
        elif isinstance(value, (int, float)) and not isinstance(value, bool):
            yield prefix + (key,)


ANY_VALUE = st.one_of(
    st.floats(allow_nan=True, allow_infinity=True),
    st.integers(min_value=-(2**63), max_value=2**63 - 1),
    st.text(max_size=8),
    st.booleans(),
    st.lists(st.floats(allow_nan=False, allow_infinity=False), max_size=3),
)


@pytest.mark.parametrize("kind", list(TOML_READERS))
@SETTINGS
@given(data=st.data())
def test_toml_reader_with_random_numbers_in_every_numeric_field(kind, data):
    reader, text = TOML_READERS[kind]
    d = tomllib.loads(text)
    leaves = list(_numeric_leaves(d))
    chosen = data.draw(st.lists(st.sampled_from(leaves), min_size=1, max_size=len(leaves), unique=True))
    d = copy.deepcopy(d)
    for path in chosen:
        node = d
        for key in path[:-1]:
            node = node[key]
        node[path[-1]] = data.draw(ANY_VALUE)
    refused_or_valid(reader, toml_text(d).encode())


# ---------------------------------------------------------------------------
# CSV: tabulated profile and empirical distribution
# ---------------------------------------------------------------------------
CSV_READERS = {"profile": (read_core, CORE), "empirical": (read_empirical, DIST)}


@pytest.mark.parametrize("kind", list(CSV_READERS))
@SETTINGS
@given(data=st.data())
def test_csv_reader_on_mutated_valid_files(kind, data):
    reader, text = CSV_READERS[kind]
    refused_or_valid(reader, data.draw(mutated_lines(text, ",")))


@pytest.mark.parametrize("kind", list(CSV_READERS))
@SETTINGS
@given(data=st.data())
def test_csv_reader_with_random_cells(kind, data):
    reader, text = CSV_READERS[kind]
    rows = [line.split(",") for line in text.splitlines()]
    for row in rows[1:]:
        for j in range(len(row)):
            row[j] = data.draw(NUMBER_TEXT)
    body = "\n".join(",".join(row) for row in rows) + "\n"
    refused_or_valid(reader, body.encode())


@pytest.mark.parametrize("kind", list(CSV_READERS))
@SETTINGS
@given(raw=RANDOM_TEXT)
def test_csv_reader_on_random_text(kind, raw):
    refused_or_valid(CSV_READERS[kind][0], raw)


# random bytes are mostly not UTF-8: a reader that decodes them without a
# ScenarioError (UnicodeDecodeError, a traceback on the command line) fails here
ALL_READERS = {
    **{f"toml_{k}": v[0] for k, v in TOML_READERS.items()},
    **{f"csv_{k}": v[0] for k, v in CSV_READERS.items()},
}


@pytest.mark.parametrize("kind", list(ALL_READERS))
@SETTINGS
@given(raw=RANDOM_BYTES)
def test_reader_on_random_bytes(kind, raw):
    refused_or_valid(ALL_READERS[kind], raw)


# ---------------------------------------------------------------------------
# environment grid
# ---------------------------------------------------------------------------
BASE_GRID = synthetic_environment(ny=3, nx=4, seed=2)
GRID_VARIABLES = ["water_depth", "sediment_class", "current_u", "current_v", "crs", "latitude", "longitude"]


@st.composite
def mutated_grid(draw) -> xr.Dataset:
    """The synthetic grid with up to four random edits: a variable dropped, its units
    changed, its values replaced by random numbers, an axis cut (to one cell or more)
    or reversed, a variable renamed, a conflicting variable added."""
    env = BASE_GRID.copy(deep=True)
    for _ in range(draw(st.integers(1, 4))):
        names = [v for v in GRID_VARIABLES if v in env.variables]
        if not names:
            break
        name = draw(st.sampled_from(names))
        op = draw(st.sampled_from(["drop", "units", "values", "cut", "reverse", "rename", "add"]))
        if op == "drop":
            env = env.drop_vars(name)
        elif op == "units":
            env[name].attrs["units"] = draw(
                st.sampled_from(["", "ft", "m", "knots", "degrees", "Pa"]) | st.text(max_size=6)
            )
        elif op == "values" and env[name].ndim:
            shape = env[name].shape
            values = draw(
                st.lists(
                    st.floats(allow_nan=True, allow_infinity=True, width=32),
                    min_size=int(np.prod(shape)),
                    max_size=int(np.prod(shape)),
                )
            )
            arr = np.asarray(values, dtype=np.float64).reshape(shape)
            if name in env.coords:
                env = env.assign_coords({name: (env[name].dims, arr, env[name].attrs)})
            else:
                env[name] = (env[name].dims, arr, env[name].attrs)
        elif op == "cut":
            dim = draw(st.sampled_from(["latitude", "longitude"]))
            if dim in env.dims:
                stop = draw(st.integers(min(1, env.sizes[dim]), env.sizes[dim]))
                env = env.isel({dim: slice(0, stop)})
        elif op == "reverse":
            dim = draw(st.sampled_from(["latitude", "longitude"]))
            if dim in env.dims:
                env = env.isel({dim: slice(None, None, -1)})
        elif op == "rename" and name not in env.dims:
            new = draw(st.sampled_from(["depth", "sediment_density", "current_speed", "x"]))
            if new not in env.variables:
                env = env.rename({name: new})
        elif op == "add" and "latitude" in env.dims and "longitude" in env.dims:
            extra = draw(
                st.sampled_from(
                    [
                        "current_speed",
                        "current_direction",
                        "sediment_density",
                        "sediment_strength",
                        "sediment_strength_gradient",
                    ]
                )
            )
            env[extra] = (
                ("latitude", "longitude"),
                np.full((env.sizes["latitude"], env.sizes["longitude"]), 1.0),
                {"units": "m s-1"},
            )
    return env


@SETTINGS
@given(env=mutated_grid())
def test_grid_reader_on_mutated_grids(env):
    refused_or_valid(read_grid, env)


@SETTINGS
@given(env=mutated_grid(), empty=st.sampled_from([("latitude",), ("longitude",), ("latitude", "longitude")]))
def test_grid_reader_on_mutated_grids_with_empty_axes(env, empty):
    env = env.isel({dim: slice(0, 0) for dim in empty if dim in env.dims})
    refused_or_valid(read_grid, env)


@settings(SETTINGS, max_examples=10)
@given(env=mutated_grid())
def test_grid_reader_on_mutated_grid_files(env):
    path = FOLDER / "env.nc"
    path.unlink(missing_ok=True)
    try:
        env.to_netcdf(path)
    except (ValueError, TypeError):  # a dataset xarray cannot write is no grid file
        return
    refused_or_valid(read_grid, path)


@settings(SETTINGS, max_examples=10)
@given(raw=RANDOM_BYTES)
def test_grid_reader_on_random_bytes(raw):
    refused_or_valid(read_grid, _file("env.nc", raw))
