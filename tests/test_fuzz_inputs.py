"""Fuzz suite of malformed inputs (issue 21): every command, every input kind.

Each case builds a small folder (a valid scenario of the command and the files it
refers to), breaks ONE thing in it, runs the command in-process in that folder and
asserts the promises of a user error:

* exit status 2 and exactly one line on stderr, ``mineburial: error: ...``;
* that line names the file or the field at fault (a regular expression per case);
* no traceback (any exception other than SystemExit fails the case);
* no file in the folder created, changed or removed (bytes, mtime and symlink targets
  are compared before and after);
* nothing computed: the drop, restraint and validation kernels are replaced by a
  function that fails the case if it is called, so every check is made first.

The reference: the same inputs before the one change reach the computing
(:func:`test_the_unbroken_inputs_reach_the_computing`), so the refusal is the change's.

The cases are generated from tables: TOML syntax damage x every command that reads a
scenario, every field of the embedded example scenarios (``mineburial example``) set
to a wrong type, NaN or an out-of-range value, every distribution of the default
ensemble broken in each way, and damaged profile CSV, empirical CSV, NetCDF core and
environment grid files, and bad command-line options. Cases that fail today are in
:data:`XFAIL` (one table, by owner) with ``strict=True``, so a fix turns them into a
failure that says: remove the mark.
"""

from __future__ import annotations

import copy
import dataclasses
import os
import re
import signal
import threading
from collections.abc import Callable
from pathlib import Path

import netCDF4
import numpy as np
import pytest
from test_bad_input import NORMAL, U, ensemble, setting, single, toml_text

from mineburial import cli
from mineburial.analyses.synthetic import synthetic_environment
from mineburial.systems.mine.config import example_path, tomllib
from mineburial.systems.restraint import ensemble as restraint_ensemble
from mineburial.systems.restraint import model as restraint


# ---------------------------------------------------------------------------
# the case: files to write, the command line, what the error line must name
# ---------------------------------------------------------------------------
@dataclasses.dataclass(frozen=True)
class Case:
    argv: tuple[str, ...]
    files: dict  # name -> bytes, str, or a function(path) that writes the file
    names: str  # regular expression: the file or field the error line must name
    not_in_line: str | None = None  # text the line must not contain (file content)


def _b(text: str | bytes) -> bytes:
    return text.encode() if isinstance(text, str) else text


def _example_dict(name: str) -> dict:
    if name == restraint_ensemble.EXAMPLE_NAME:
        text = restraint_ensemble.example_text()
    elif name.startswith(restraint.EXAMPLE_PREFIX):
        text = restraint.example_text(name)
    else:
        text = Path(example_path(name)).read_text()
    return tomllib.loads(text)


def _small(d: dict) -> dict:
    """An example scenario with its ensemble cut to 4 drops (nothing is computed anyway)."""
    d = copy.deepcopy(d)
    if "ensemble" in d:
        d["ensemble"].update(n=4, chunk_size=2)
    return d


GRID = "env.nc"


def _write_grid(change: Callable = lambda env: env) -> Callable:
    def write(path):
        change(synthetic_environment(ny=3, nx=4, seed=2)).to_netcdf(path)

    return write


#: the command line of each command on its valid scenario ``s.toml``
COMMANDS = {
    "run": ("run", "s.toml", "-o", "out.nc", "--quiet"),
    "drop": ("drop", "s.toml", "-o", "t.nc"),
    "map": ("map", "s.toml", "--environment", GRID, "-o", "map.nc", "--quiet"),
    "compare": ("compare", "s.toml", "--vary", "sediment.resistance=bearing,delta", "--quiet"),
    "sensitivity": ("sensitivity", "s.toml", "-n", "4", "--quiet"),
    "restrain": ("restrain", "s.toml", "-o", "r.nc"),
}


def _base_files(command: str) -> dict:
    """The valid input files of ``command``."""
    if command == "restrain":
        return {"s.toml": toml_text(_example_dict("restraint_case1"))}
    files = {"s.toml": toml_text(single() if command == "drop" else ensemble())}
    if command == "map":
        files[GRID] = _write_grid()
    return files


def command_case(command, names, *, scenario=None, files=None, extra=(), argv=None):
    """A case of ``command`` with its valid files, ``s.toml`` replaced by ``scenario``
    (a dict or raw text/bytes), further ``files`` and ``extra`` options."""
    all_files = _base_files(command)
    if scenario is not None:
        all_files["s.toml"] = toml_text(scenario) if isinstance(scenario, dict) else scenario
    all_files.update(files or {})
    return Case(tuple(argv if argv is not None else COMMANDS[command]) + tuple(extra), all_files, names)


CASES: dict[str, Case] = {}


def add(name: str, case: Case) -> None:
    assert name not in CASES, name
    CASES[name] = case


# ---------------------------------------------------------------------------
# 1. scenario TOML: syntax damage, for every command that reads one
# ---------------------------------------------------------------------------
def _last_key_line(text: str) -> str:
    return [line for line in text.splitlines() if re.match(r"^\w+ = ", line)][-1]


def _first_table_line(text: str) -> str:
    return [line for line in text.splitlines() if line.startswith("[")][0]


SYNTAX = {
    "unterminated_string": lambda t: t + 'name2 = "abc\n',
    "missing_value": lambda t: t + "q = \n",
    "duplicate_key": lambda t: t + _last_key_line(t) + "\n",
    "duplicate_table": lambda t: t + _first_table_line(t) + "\n",
    "unclosed_array": lambda t: t + "q = [1, 2\n",
    "trailing_comma_inline_table": lambda t: t + "q = {a = 1,}\n",
    "invalid_escape": lambda t: t + 'q = "\\x"\n',
    "unclosed_table_header": lambda t: "[mine\n" + t,
    "bare_words": lambda t: t + "this is not toml\n",
    "nul_byte": lambda t: t + "q = 1\x00\n",
    "bom_then_missing_value": lambda t: "\ufeff" + t + "q =\n",
    "latin1_comment": lambda t: _b(t) + b"# caf\xe9 au lait\n",
    "binary_garbage": lambda t: bytes(range(256)) * 4,
    "nested_100000_deep": lambda t: t + "q = " + "[" * 100_000 + "]" * 100_000 + "\n",
}

for _cmd in COMMANDS:
    _valid = _base_files(_cmd)["s.toml"]
    for _kind, _damage in SYNTAX.items():
        add(f"toml_{_kind}-{_cmd}", command_case(_cmd, r"s\.toml", scenario=_damage(_valid)))
    if _cmd != "restrain":  # every field of a restraint case has a default: an empty case is valid
        add(f"toml_empty_file-{_cmd}", command_case(_cmd, r"s\.toml|mine|required", scenario=""))
    add(
        f"toml_unknown_section-{_cmd}",
        command_case(_cmd, r"bogus_section", scenario=_valid + "[bogus_section]\nx = 1\n"),
    )


# ---------------------------------------------------------------------------
# 2. every field of the example scenarios: wrong type, NaN, out of range, unknown keys
# ---------------------------------------------------------------------------
def leaves(d: dict, prefix: str = ""):
    """(dotted path, value) of every fixed value and distribution table in ``d``."""
    for key, value in d.items():
        path = f"{prefix}{key}"
        if isinstance(value, dict) and "distribution" not in value:
            yield from leaves(value, path + ".")
        elif isinstance(value, list):
            for i, item in enumerate(value):
                yield f"{path}[{i}]", item
        else:
            yield path, value


def sections(d: dict, prefix: str = ""):
    for key, value in d.items():
        if isinstance(value, dict) and "distribution" not in value:
            yield prefix + key
            yield from sections(value, prefix + key + ".")


def _set(d: dict, path: str, value) -> dict:
    return setting(lambda: copy.deepcopy(d), path, value)()


def _field_regex(path: str) -> str:
    """The field as the error line names it: ``release.velocity[0]`` or the list."""
    return re.escape(path.split("[")[0])


#: fields that must be > 0 (or >= 0): a negative value is out of range
POSITIVE = re.compile(
    r"(^|\.)(length|diameter|mass|\w*density|\w*viscosity|water_depth|gravity|dt|t_max|t_max_fall|"
    r"rest_speed|rest_spin|radius|width|height|links|beam|depth|\w+_length|\w+_elements|rtol|atol|"
    r"record_interval|foundation_stiffness|drag_coefficient|normal_drag|tangential_drag|added_mass|"
    r"friction_velocity_scale|roughness|speed|n|chunk_size)$"
)

#: (example, command) pairs whose every field is mutated
MUTATED = {
    "default_mine": "drop",
    "default_soft_mud": "run",
    "restraint_case1": "restrain",
    "restraint_ensemble": "run",
}

for _example, _cmd in MUTATED.items():
    _d = _small(_example_dict(_example))
    _tag = f"{_example}-{_cmd}"
    for _path, _value in leaves(_d):
        if isinstance(_value, dict):  # distributions: section 3
            continue
        if isinstance(_value, bool):
            add(
                f"field_bool_as_text-{_path}-{_tag}",
                command_case(_cmd, _field_regex(_path), scenario=_set(_d, _path, "yes")),
            )
            continue
        if isinstance(_value, str):
            if _path.split(".")[-1] in ("name", "description"):
                add(
                    f"field_text_as_list-{_path}-{_tag}",
                    command_case(_cmd, _field_regex(_path), scenario=_set(_d, _path, [1, 2])),
                )
            else:
                add(
                    f"field_unknown_name-{_path}-{_tag}",
                    command_case(_cmd, _field_regex(_path), scenario=_set(_d, _path, "no_such_thing")),
                )
                add(
                    f"field_name_as_number-{_path}-{_tag}",
                    command_case(_cmd, _field_regex(_path), scenario=_set(_d, _path, 5)),
                )
            continue
        add(
            f"field_text-{_path}-{_tag}",
            command_case(_cmd, _field_regex(_path), scenario=_set(_d, _path, "abc")),
        )
        add(
            f"field_nan-{_path}-{_tag}",
            command_case(_cmd, _field_regex(_path), scenario=_set(_d, _path, float("nan"))),
        )
        if "[" not in _path:
            add(
                f"field_list-{_path}-{_tag}",
                command_case(_cmd, _field_regex(_path), scenario=_set(_d, _path, [1.0])),
            )
        if POSITIVE.search(_path):
            add(
                f"field_negative-{_path}-{_tag}",
                command_case(_cmd, _field_regex(_path), scenario=_set(_d, _path, -1)),
            )
    for _section in sections(_d):
        add(
            f"section_unknown_key-{_section}-{_tag}",
            command_case(
                _cmd, re.escape(_section) + r".*colour", scenario=_set(_d, f"{_section}.colour", 1.0)
            ),
        )


# ---------------------------------------------------------------------------
# 3. distributions: every distribution of the example ensembles broken in each way
# ---------------------------------------------------------------------------
def _numeric_params(d: dict) -> list[str]:
    return [k for k, v in d.items() if k != "distribution" and isinstance(v, (int, float))]


def _spread(d: dict) -> dict | None:
    """The distribution with a negative spread or reversed bounds (None: it has neither)."""
    if "std" in d:
        return {**d, "std": -1.0}
    if "sigma" in d:
        return {**d, "sigma": -1.0}
    if "low" in d and "high" in d:
        return {**d, "low": d["high"], "high": d["low"]}
    return None


def _first_numeric(d: dict, value=None, drop=False) -> dict | None:
    """The distribution with its first numeric parameter set to ``value`` or removed (None: it has
    none, as a model-form ``choice`` among labels)."""
    keys = _numeric_params(d)
    if not keys:
        return None
    return {k: v for k, v in d.items() if k != keys[0]} if drop else {**d, keys[0]: value}


DIST_DAMAGE = {
    "unknown_family": lambda d: {**d, "distribution": "gaussian"},
    "family_as_number": lambda d: {**d, "distribution": 5},
    "nan_parameter": lambda d: _first_numeric(d, float("nan")),
    # the first parameter (mean, low, median) is required and finite in every family; a
    # truncated normal's bounds may be infinite or left out (one-sided truncation)
    "inf_parameter": lambda d: _first_numeric(d, float("inf")),
    "text_parameter": lambda d: _first_numeric(d, "abc"),
    "missing_parameter": lambda d: _first_numeric(d, drop=True),
    "extra_parameter": lambda d: {**d, "shape": 1.0},
    "negative_spread_or_reversed_bounds": _spread,
}

for _example in ("default_soft_mud", "restraint_ensemble"):
    _d = _small(_example_dict(_example))
    for _path, _value in leaves(_d):
        if not isinstance(_value, dict):
            continue
        for _kind, _damage in DIST_DAMAGE.items():
            _bad = _damage(_value)
            if _bad is not None:
                add(
                    f"distribution_{_kind}-{_path}-{_example}-run",
                    command_case("run", _field_regex(_path), scenario=_set(_d, _path, _bad)),
                )

for _cmd in ("map", "compare", "sensitivity"):
    for _kind in ("unknown_family", "nan_parameter", "negative_spread_or_reversed_bounds"):
        add(
            f"distribution_{_kind}-mine.mass-{_cmd}",
            command_case(
                _cmd,
                r"mine\.mass",
                scenario=_set(ensemble(), "mine.mass", DIST_DAMAGE[_kind](NORMAL(80.0, 2.0))),
            ),
        )
    add(
        f"distribution_uniform_outside_range-release.pitch_deg-{_cmd}",
        command_case(
            _cmd, r"release\.pitch_deg", scenario=_set(ensemble(), "release.pitch_deg", U(-180.0, 180.0))
        ),
    )


# ---------------------------------------------------------------------------
# 4. referenced files that are missing or not files
# ---------------------------------------------------------------------------
def _core_scenario(command: str, file: str) -> dict:
    return _set(single() if command == "drop" else ensemble(), "sediment", {"file": file})


def _empirical_scenario(file: str) -> dict:
    return _set(ensemble(), "mine.mass", {"distribution": "empirical", "file": file, "column": "m"})


def _folder(path):
    os.mkdir(path)


def _dangling_link(path):
    os.symlink("nowhere.csv", path)


def _fifo(path):
    os.mkfifo(path)


REFERENCED = {
    "missing_csv": ("none.csv", {}),
    "missing_netcdf": ("none.nc", {}),
    "missing_in_subfolder": ("sub/none.csv", {"sub": _folder}),
    "unknown_extension": ("core.txt", {"core.txt": "depth_m,density_kg_m3,strength_pa\n0,1500,1000\n"}),
    "a_folder": ("core.csv", {"core.csv": _folder}),
    "dangling_symlink": ("core.csv", {"core.csv": _dangling_link}),
    "fifo": ("core.csv", {"core.csv": _fifo}),
}

for _cmd in ("drop", "run", "compare", "sensitivity", "map"):
    for _kind, (_file, _files) in REFERENCED.items():
        add(
            f"sediment_file_{_kind}-{_cmd}",
            command_case(_cmd, re.escape(_file), scenario=_core_scenario(_cmd, _file), files=_files),
        )
for _cmd in ("run", "compare", "sensitivity", "map"):
    for _kind in ("missing_in_subfolder", "a_folder", "dangling_symlink", "fifo"):
        _file, _files = REFERENCED[_kind]
        _file = _file.replace("core", "dist")
        _files = {k.replace("core", "dist"): v for k, v in _files.items()}
        add(
            f"empirical_file_{_kind}-{_cmd}",
            command_case(_cmd, re.escape(_file), scenario=_empirical_scenario(_file), files=_files),
        )


# ---------------------------------------------------------------------------
# 5. tabulated profile CSV (sediment.file = "core.csv") and 6. empirical CSV
# ---------------------------------------------------------------------------
CORE = "depth_m,density_kg_m3,strength_pa\n0.0,1500,1000\n0.5,1550,2000\n1.0,1600,3000\n2.0,1650,5000\n"
DIST = "m\n78.0\n80.0\n82.0\n"

CORE_DAMAGE = {
    "header_typo": CORE.replace("strength_pa", "strenght_pa"),
    "no_header": CORE.split("\n", 1)[1],
    "non_numeric_cell": CORE.replace("1550", "soft"),
    "nan_cell": CORE.replace("1550", "nan"),
    "inf_cell": CORE.replace("3000", "inf"),
    "negative_density": CORE.replace("1550", "-1550"),
    "negative_strength": CORE.replace("2000", "-2000"),
    "non_monotonic_depth": CORE.replace("0.5,1550", "1.5,1550"),
    "repeated_depth": CORE.replace("1.0,1600", "0.5,1600"),
    "negative_depth": CORE.replace("0.0,1500", "-0.5,1500"),
    "empty": "",
    "comments_only": "# nothing here\n",
    "header_only": CORE.split("\n", 1)[0] + "\n",
    "short_row": CORE.replace("1.0,1600,3000", "1.0,1600"),
    "huge_cell": CORE.replace("1550", "1" * 200_000),
    "latin1_comment": b"# carott\xe9 du 12 mai\n" + CORE.encode(),
    "bom_then_non_numeric_cell": "\ufeff" + CORE.replace("1550", "soft"),
    "binary_garbage": bytes(range(256)) * 4,
    "nul_byte": CORE.replace("1550", "15\x0050"),
}

DIST_CSV_DAMAGE = {
    "column_missing": DIST.replace("m\n", "mass\n"),
    "no_header": DIST.split("\n", 1)[1],
    "non_numeric_cell": DIST.replace("80.0", "heavy"),
    "nan_cell": DIST.replace("80.0", "nan"),
    "inf_cell": DIST.replace("80.0", "inf"),
    "empty": "",
    "header_only": "m\n",
    "huge_cell": DIST.replace("80.0", "8" * 200_000),
    "latin1_comment": b"# pes\xe9es\n" + DIST.encode(),
    "bom_then_non_numeric_cell": "\ufeff" + DIST.replace("80.0", "heavy"),
    "binary_garbage": bytes(range(256)) * 4,
    "nul_byte": DIST.replace("80.0", "8\x000"),
}

for _cmd in ("drop", "run", "compare"):
    for _kind, _text in CORE_DAMAGE.items():
        if _cmd == "compare" and _kind not in ("non_numeric_cell", "latin1_comment", "huge_cell", "empty"):
            continue
        add(
            f"core_csv_{_kind}-{_cmd}",
            command_case(
                _cmd, r"core\.csv", scenario=_core_scenario(_cmd, "core.csv"), files={"core.csv": _text}
            ),
        )
for _cmd in ("run", "compare", "sensitivity"):
    for _kind, _text in DIST_CSV_DAMAGE.items():
        add(
            f"empirical_csv_{_kind}-{_cmd}",
            command_case(
                _cmd, r"dist\.csv", scenario=_empirical_scenario("dist.csv"), files={"dist.csv": _text}
            ),
        )
    add(
        f"empirical_csv_negative_value-{_cmd}",
        command_case(
            _cmd,
            r"mine\.mass",
            scenario=_empirical_scenario("dist.csv"),
            files={"dist.csv": DIST.replace("80.0", "-80.0")},
        ),
    )
    _passwd = "m\nroot:x:0:0:root:/root:/bin/bash\ndaemon:x:1:1:daemon:/usr/sbin:/usr/sbin/nologin\n"
    add(
        f"empirical_csv_content_not_printed-{_cmd}",
        dataclasses.replace(
            command_case(
                _cmd, r"dist\.csv", scenario=_empirical_scenario("dist.csv"), files={"dist.csv": _passwd}
            ),
            not_in_line="root:x",
        ),
    )


# ---------------------------------------------------------------------------
# 7. NetCDF sediment core (sediment.file = "core.nc")
# ---------------------------------------------------------------------------
def _core_variables() -> dict:
    return {
        "depth": (("z",), np.array([0.0, 0.5, 1.0, 2.0]), {"units": "m", "positive": "down"}),
        "density": (("z",), np.array([1500.0, 1550.0, 1600.0, 1650.0]), {"units": "kg m-3"}),
        "strength": (("z",), np.array([1000.0, 2000.0, 3000.0, 5000.0]), {"units": "Pa"}),
    }


def _write_core(change: Callable) -> Callable:
    def write(path):
        variables = change(_core_variables())
        with netCDF4.Dataset(path, "w") as ds:
            for dims, data, _attrs in variables.values():
                for dim, size in zip(dims, np.shape(data)):
                    if dim not in ds.dimensions:
                        ds.createDimension(dim, size)
            for name, (dims, data, attrs) in variables.items():
                data = np.asarray(data)
                dtype = str if data.dtype.kind == "U" else data.dtype
                v = ds.createVariable(name, dtype, dims)
                if data.dtype.kind == "U":
                    for i, item in enumerate(data):
                        v[i] = item
                else:
                    v[...] = data
                v.setncatts(attrs)

    return write


def _replace(name, dims=None, data=None, attrs=None):
    def change(vs):
        old = vs[name]
        vs[name] = (
            old[0] if dims is None else dims,
            old[1] if data is None else data,
            old[2] if attrs is None else attrs,
        )
        return vs

    return change


def _without(name):
    def change(vs):
        del vs[name]
        return vs

    return change


NC_CORE_DAMAGE = {
    "missing_depth": _write_core(_without("depth")),
    "missing_density": _write_core(_without("density")),
    "missing_strength": _write_core(_without("strength")),
    "depth_2d": _write_core(_replace("depth", ("a", "b"), np.array([[0.0, 0.5], [1.0, 2.0]]))),
    "density_on_other_dimension": _write_core(
        _replace("density", ("w",), np.array([1500.0, 1600.0, 1650.0]))
    ),
    "string_density": _write_core(_replace("density", data=np.array(["soft", "soft", "firm", "firm"]))),
    "char_density": _write_core(
        _replace("density", ("z", "c"), np.array([[b"a"], [b"b"], [b"c"], [b"d"]], dtype="S1"))
    ),
    "nan_density": _write_core(_replace("density", data=np.array([1500.0, np.nan, 1600.0, 1650.0]))),
    "nan_depth": _write_core(_replace("depth", data=np.array([0.0, np.nan, 1.0, 2.0]))),
    "inf_strength": _write_core(_replace("strength", data=np.array([1000.0, 2000.0, np.inf, 5000.0]))),
    "strength_without_units": _write_core(_replace("strength", attrs={})),
    "strength_in_psi": _write_core(_replace("strength", attrs={"units": "psi"})),
    "depth_positive_up": _write_core(_replace("depth", attrs={"units": "m", "positive": "up"})),
    "scalar_depth": _write_core(_replace("depth", (), np.array(0.0))),
    "empty_variables": _write_core(
        lambda vs: {k: (("z",), np.zeros(0), attrs) for k, (_d, _x, attrs) in vs.items()}
    ),
    "not_netcdf": b"depth,density\n0,1500\n",
    "empty_file": b"",
}

for _cmd in ("drop", "run"):
    for _kind, _write in NC_CORE_DAMAGE.items():
        add(
            f"core_netcdf_{_kind}-{_cmd}",
            command_case(
                _cmd, r"core\.nc", scenario=_core_scenario(_cmd, "core.nc"), files={"core.nc": _write}
            ),
        )


# ---------------------------------------------------------------------------
# 8. environment grid (map --environment env.nc)
# ---------------------------------------------------------------------------
def _assign(**arrays):
    def change(env):
        return env.assign(**{k: (("latitude", "longitude"), v(env), a) for k, (v, a) in arrays.items()})

    return change


def _zero_by_zero(env):
    return env.isel(latitude=slice(0, 0), longitude=slice(0, 0))


GRID_DAMAGE = {
    "current_speed_and_current_uv": (
        "current",
        _assign(
            current_speed=(lambda e: np.full((3, 4), 0.3), {"units": "m s-1"}),
            current_direction=(lambda e: np.full((3, 4), 90.0), {"units": "degree"}),
        ),
    ),
    "sediment_class_and_linear_fields": (
        "sediment",
        _assign(
            sediment_density=(lambda e: np.full((3, 4), 1500.0), {"units": "kg m-3"}),
            sediment_strength=(lambda e: np.full((3, 4), 2000.0), {"units": "Pa"}),
            sediment_strength_gradient=(lambda e: np.full((3, 4), 1000.0), {"units": "Pa m-1"}),
        ),
    ),
    "zero_by_zero": ("env\\.nc|water_depth|empty|0 ?x ?0|no cells", _zero_by_zero),
    "all_nan_depth": ("water_depth", lambda e: e.assign(water_depth=e["water_depth"] * np.nan)),
    "string_depth": (
        "water_depth",
        lambda e: e.assign(water_depth=(("latitude", "longitude"), np.full((3, 4), "deep"), {"units": "m"})),
    ),
    "depth_1d": ("water_depth", lambda e: e.assign(water_depth=e["water_depth"].isel(latitude=0))),
    "depth_with_two_times": (
        "water_depth",
        lambda e: e.assign(water_depth=e["water_depth"].expand_dims(time=2)),
    ),
    "depth_without_units": (
        "water_depth",
        lambda e: e.assign(water_depth=e["water_depth"].assign_attrs(units="")),
    ),
    "only_current_u": ("current", lambda e: e.drop_vars("current_v")),
    "only_current_speed": (
        "current",
        lambda e: e.drop_vars(["current_u", "current_v"]).assign(
            current_speed=(("latitude", "longitude"), np.full((3, 4), 0.3), {"units": "m s-1"})
        ),
    ),
    "current_in_knots": (
        "current_u",
        lambda e: e.assign(current_u=e["current_u"].assign_attrs(units="knots")),
    ),
    "no_sediment": ("sediment", lambda e: e.drop_vars("sediment_class")),
    "missing_grid_mapping": ("grid_mapping|crs", lambda e: e.drop_vars("crs")),
    "unnamed_axes": (
        "axes|latitude|longitude|a\\b",
        lambda e: e.rename(latitude="a", longitude="b").assign_coords(
            a=("a", [0.0, 1.0, 2.0]), b=("b", [0.0, 1.0, 2.0, 3.0])
        ),
    ),
    "infinite_longitude": (
        "longitude",
        lambda e: e.assign_coords(
            longitude=("longitude", [10.3, 10.31, 10.32, np.inf], e["longitude"].attrs)
        ),
    ),
    "unknown_sediment_code": (
        "sediment_class",
        lambda e: e.assign(sediment_class=e["sediment_class"].where(e["sediment_class"] != 1, 99)),
    ),
}

for _kind, (_names, _change) in GRID_DAMAGE.items():
    add(f"grid_{_kind}-map", command_case("map", _names, files={GRID: _write_grid(_change)}))
for _kind, _content in (
    ("not_netcdf", b"water_depth = 30\n"),
    ("empty_file", b""),
    ("a_folder", _folder),
    ("fifo", _fifo),
):
    add(f"grid_{_kind}-map", command_case("map", r"env\.nc", files={GRID: _content}))


# ---------------------------------------------------------------------------
# 9. the command line: numbers, options, --vary, --plot, -o
# ---------------------------------------------------------------------------
OPTIONS = {
    "run": [
        ("n_text", ["-n", "many"], "-n"),
        ("n_negative", ["-n", "-5"], "-n|ensemble\\.n"),
        ("n_float", ["-n", "1e3"], "-n"),
        ("seed_text", ["--seed", "x"], "--seed"),
        ("threads_zero", ["--threads", "0"], "threads"),
        ("threads_negative", ["--threads", "-2"], "threads"),
        ("threads_text", ["--threads", "all"], "--threads"),
        ("chunk_size_negative", ["--chunk-size", "-1"], "chunk"),
        ("per_drop_with_value", ["--per-drop=yes"], "--per-drop"),
        ("unknown_option", ["--turbo"], "--turbo"),
        ("output_folder_missing", ["-o", "no/out.nc"], "no/out\\.nc|-o"),
        ("output_is_a_folder", ["-o", "."], "-o|\\."),
    ],
    "drop": [
        ("unknown_option", ["--trace"], "--trace"),
        ("forces_with_value", ["--forces=yes"], "--forces"),
        ("record_interval_empty", ["--record-interval", ""], "--record-interval"),
    ],
    "map": [
        ("n_text", ["-n", "x"], "-n"),
        ("n_negative", ["-n", "-1"], "-n|ensemble\\.n"),
        ("seed_negative", ["--seed", "-1"], "seed"),
        ("plot_unknown_format", ["--plot", "p.xyz"], "p\\.xyz"),
        ("plot_folder_missing", ["--plot", "no/p.png"], "no/p\\.png"),
        ("plot_is_the_scenario", ["--plot", "s.toml"], "s\\.toml"),
        ("output_is_the_grid", ["-o", GRID], "env\\.nc"),
        ("output_is_the_scenario", ["-o", "s.toml"], "s\\.toml"),
        ("environment_is_a_folder", ["--environment", "."], "\\.|environment"),
        ("unknown_option", ["--fast"], "--fast"),
    ],
    "compare": [
        ("vary_without_equals", ["--vary", "sediment.resistance"], "--vary"),
        ("vary_empty_field", ["--vary", "=bearing,delta"], "--vary"),
        ("vary_no_values", ["--vary", "sediment.resistance="], "--vary"),
        ("vary_one_value", ["--vary", "sediment.resistance=bearing"], "--vary"),
        ("vary_repeated_value", ["--vary", "sediment.resistance=bearing,bearing"], "--vary"),
        ("vary_unknown_field", ["--vary", "mine.colour=red,blue"], "mine\\.colour"),
        (
            "vary_unknown_value",
            ["--vary", "sediment.resistance=bearing,magic"],
            "sediment\\.resistance|magic",
        ),
        ("vary_text_for_number", ["--vary", "mine.com_offset=a,b"], "mine\\.com_offset"),
        ("vary_out_of_range", ["--vary", "mine.com_offset=0.0,9.0"], "mine\\.com_offset"),
        ("n_negative", ["-n", "-4"], "-n|ensemble\\.n"),
        ("n_text", ["-n", "four"], "-n"),
        ("threads_zero", ["--threads", "0"], "threads"),
        ("plot_unknown_format", ["--plot", "p.xyz"], "p\\.xyz"),
        ("plot_folder_missing", ["--plot", "no/p.png"], "no/p\\.png"),
        ("output_is_the_scenario", ["-o", "s.toml"], "s\\.toml"),
        ("output_folder_missing", ["-o", "no/c.nc"], "no/c\\.nc"),
        ("output_is_a_folder", ["-o", "."], "-o"),
    ],
    "sensitivity": [
        ("n_not_power_of_two", ["-n", "3"], "-n"),
        ("n_zero", ["-n", "0"], "-n"),
        ("n_negative", ["-n", "-4"], "-n"),
        ("n_text", ["-n", "x"], "-n"),
        ("threads_zero", ["--threads", "0"], "threads"),
        ("seed_negative", ["--seed", "-1"], "seed"),
        ("plot_unknown_format", ["--plot", "p.xyz"], "p\\.xyz"),
        ("output_is_the_scenario", ["-o", "s.toml"], "s\\.toml"),
        ("output_folder_missing", ["-o", "no/s.nc"], "no/s\\.nc"),
        ("unknown_option", ["--vary", "a=1,2"], "--vary"),
    ],
    "restrain": [
        ("output_is_a_folder", ["-o", "."], "-o"),
        ("output_folder_missing", ["-o", "no/r.nc"], "no"),
        ("output_is_the_case", ["-o", "s.toml"], "s\\.toml"),
        ("unknown_option", ["-n", "4"], "-n"),
    ],
}

for _cmd, _options in OPTIONS.items():
    for _kind, _extra, _names in _options:
        add(f"option_{_kind}-{_cmd}", command_case(_cmd, _names, extra=_extra))

# outputs onto the files a command reads (issue 21 item 1)
add(
    "output_is_the_core_csv-drop",
    command_case(
        "drop",
        r"core\.csv",
        scenario=_core_scenario("drop", "core.csv"),
        files={"core.csv": CORE},
        argv=("drop", "s.toml", "-o", "core.csv"),
    ),
)
add(
    "output_is_the_core_csv-compare",
    command_case(
        "compare",
        r"core\.csv",
        scenario=_core_scenario("compare", "core.csv"),
        files={"core.csv": CORE},
        extra=("-o", "core.csv"),
    ),
)
add(
    "output_is_the_empirical_csv-sensitivity",
    command_case(
        "sensitivity",
        r"dist\.csv",
        scenario=_empirical_scenario("dist.csv"),
        files={"dist.csv": DIST},
        extra=("-o", "dist.csv"),
    ),
)
add(
    "output_is_the_empirical_csv-run",
    command_case(
        "run",
        r"dist\.csv",
        scenario=_empirical_scenario("dist.csv"),
        files={"dist.csv": DIST},
        extra=("-o", "dist.csv"),
    ),
)

# example and validate, which read no scenario
_EDITED = "# my edited scenario\n"
for _kind, _argv, _files, _names in (
    ("example_name_empty", ["example", ""], {}, "''|example"),
    ("example_name_with_path", ["example", "../default_mine"], {}, "default_mine"),
    (
        "example_overwrites_edited_file",
        ["example", "default_mine"],
        {"default_mine.toml": _EDITED},
        "default_mine\\.toml",
    ),
    (
        "example_output_exists",
        ["example", "default_mine", "-o", "mine.toml"],
        {"mine.toml": _EDITED},
        "mine\\.toml",
    ),
    (
        "example_output_is_a_symlink",
        ["example", "default_mine", "-o", "link.toml"],
        {"mine.toml": _EDITED, "link.toml": lambda p: os.symlink("mine.toml", p)},
        "link\\.toml",
    ),
    ("example_unknown_option", ["example", "default_mine", "--clobber"], {}, "--clobber"),
    (
        "validate_output_is_a_file",
        ["validate", "--quick", "-o", "report.txt"],
        {"report.txt": "notes\n"},
        "report\\.txt",
    ),
    (
        "validate_output_under_a_file",
        ["validate", "--quick", "-o", "report.txt/sub"],
        {"report.txt": "notes\n"},
        "report\\.txt",
    ),
    ("validate_unknown_option", ["validate", "--full"], {}, "--full"),
    ("no_scenario_for_restrain", ["restrain"], {}, "case"),
    ("map_without_environment", ["map", "s.toml"], {"s.toml": toml_text(ensemble())}, "--environment"),
    ("compare_without_vary", ["compare", "s.toml"], {"s.toml": toml_text(ensemble())}, "--vary"),
):
    add(f"cli_{_kind}", Case(tuple(_argv), _files, _names))


# ---------------------------------------------------------------------------
# THE XFAIL TABLE: cases that fail on this branch today, by the helper who owns the fix.
# strict=True: a fix makes the case pass and the run fail until its line here is removed.
# ---------------------------------------------------------------------------
def _each(case: str, commands: str, reason: str) -> dict[str, str]:
    return {f"{case}-{c}": reason for c in commands.split()}


TOML_COMMANDS = "run drop map compare sensitivity restrain"
XFAIL: dict[str, str] = {}


# ---------------------------------------------------------------------------
# the test
# ---------------------------------------------------------------------------
@pytest.fixture
def nothing_computed(monkeypatch):
    """Any drop, restraint case or validation case computed fails the test."""
    from mineburial.systems.mine import batch
    from mineburial.systems.mine import drop as drop_module
    from mineburial.validation import report
    from mineburial.validation.cases import VERIFICATION, Case

    def computed(*args, **kw):
        raise AssertionError("computing started before the bad input was refused")

    monkeypatch.setattr(batch, "run_batch", computed)
    monkeypatch.setattr(drop_module, "run_params", computed)
    monkeypatch.setattr(restraint, "simulate", computed)
    monkeypatch.setattr(report, "CASES", [Case("computed", "computed", computed, VERIFICATION)])


def snapshot(root: Path) -> dict:
    """Every entry under ``root``: its kind and, for a file, its bytes and mtime."""
    out = {}
    for path in sorted(root.rglob("*")):
        st = path.lstat()
        rel = str(path.relative_to(root))
        if path.is_symlink():
            out[rel] = ("symlink", os.readlink(path), st.st_mtime_ns)
        elif path.is_dir():
            out[rel] = ("folder",)
        elif path.is_file():
            out[rel] = ("file", st.st_mtime_ns, path.read_bytes())
        else:
            out[rel] = ("special", st.st_mode, st.st_mtime_ns)
    return out


def _write(folder: Path, files: dict) -> None:
    for name, content in files.items():
        path = folder / name
        if callable(content):
            content(path)
        else:
            path.write_bytes(_b(content))


class _Timeout(Exception):
    pass


def _alarm(signum, frame):
    raise _Timeout("the command hung for 20 s")


def _unblock_fifos(folder: Path, hung: list, done: threading.Event) -> None:
    """A reader blocked in C on a FIFO (netCDF, xarray) is out of SIGALRM's reach: after
    2 s, open the writing end of every FIFO and close it, again and again until the
    command ends, so that each read sees the end of the file; record the hang."""
    if done.wait(2.0):
        return
    while not done.wait(0.2):
        for path in folder.rglob("*"):
            if path.is_fifo():
                try:
                    os.close(os.open(path, os.O_WRONLY | os.O_NONBLOCK))
                    hung.append(path.name)
                except OSError:  # no reader waiting on it
                    pass


def _params():
    for name in CASES:
        marks = [pytest.mark.xfail(strict=True, reason=XFAIL[name])] if name in XFAIL else []
        yield pytest.param(name, marks=marks, id=name)


@pytest.mark.parametrize("name", list(_params()))
def test_malformed_input_is_refused_in_one_line_and_changes_nothing(
    name, tmp_path, capsys, monkeypatch, nothing_computed
):
    case = CASES[name]
    _write(tmp_path, case.files)
    monkeypatch.chdir(tmp_path)
    before = snapshot(tmp_path)
    hung: list[str] = []  # a FIFO read must not hang the suite: unblocked after 2 s
    done = threading.Event()
    unblock = threading.Thread(target=_unblock_fifos, args=(tmp_path, hung, done), daemon=True)
    unblock.start()
    old = signal.signal(signal.SIGALRM, _alarm)
    signal.alarm(20)
    try:
        rc = cli.main(list(case.argv))
    except SystemExit as exc:  # argparse's own exit
        rc = exc.code
    finally:
        signal.alarm(0)
        signal.signal(signal.SIGALRM, old)
        done.set()
        unblock.join()
    out, err = capsys.readouterr()
    assert not hung, f"the command hung reading the FIFO {hung[0]}"
    assert "Traceback" not in err + out
    assert rc == 2, (rc, err)
    lines = err.splitlines()
    assert len(lines) == 1, err
    assert lines[0].startswith("mineburial: error: "), lines[0]
    assert re.search(case.names, lines[0]), (case.names, lines[0])
    if case.not_in_line:
        assert case.not_in_line not in lines[0], lines[0]
    assert snapshot(tmp_path) == before, "a file in the folder was created, changed or removed"


def test_there_are_at_least_150_cases_over_every_command():
    assert len(CASES) >= 150
    commands = {case.argv[0] for case in CASES.values() if case.argv}
    assert commands >= {"run", "drop", "map", "compare", "sensitivity", "restrain", "example", "validate"}


def test_every_xfail_names_a_case():
    assert set(XFAIL) <= set(CASES)


#: the unbroken inputs each family of cases starts from: (files, command line)
UNBROKEN = {
    **{f"{cmd}-base": (_base_files(cmd), COMMANDS[cmd]) for cmd in COMMANDS},
    **{
        f"{cmd}-example-{ex}": (
            {**_base_files(cmd), "s.toml": toml_text(_small(_example_dict(ex)))},
            COMMANDS[cmd],
        )
        for ex, cmd in MUTATED.items()
    },
    "drop-core-csv": (
        {"s.toml": toml_text(_core_scenario("drop", "core.csv")), "core.csv": CORE},
        COMMANDS["drop"],
    ),
    "drop-core-netcdf": (
        {"s.toml": toml_text(_core_scenario("drop", "core.nc")), "core.nc": _write_core(lambda vs: vs)},
        COMMANDS["drop"],
    ),
    "sensitivity-empirical-csv": (
        {"s.toml": toml_text(_empirical_scenario("dist.csv")), "dist.csv": DIST},
        COMMANDS["sensitivity"],
    ),
    "validate-quick": ({}, ("validate", "--quick", "-o", "report")),
}


@pytest.mark.parametrize("name", list(UNBROKEN))
def test_the_unbroken_inputs_reach_the_computing(name, tmp_path, monkeypatch, nothing_computed):
    """The reference of every case: its inputs before the one change are accepted, so the
    change is what the error line is about."""
    files, argv = UNBROKEN[name]
    _write(tmp_path, files)
    monkeypatch.chdir(tmp_path)
    with pytest.raises(AssertionError, match="computing started"):
        cli.main(list(argv))
