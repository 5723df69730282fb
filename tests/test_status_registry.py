"""Each system contributes its status names to the registry of ``kernels/status.py`` (issue 36 item
5): the shared codes mean the same in every system, a system names its own end and adds its own
codes, and the files keep the codes, names and order they had.

Independent references: the code tables of docs/design.md ("Status codes of a drop") and
docs/restraint.md (section 5), which the NetCDF files' ``flag_values``/``flag_meanings`` follow.
"""

from __future__ import annotations

import pathlib
import re
import subprocess
import sys

import numpy as np
import pytest

from mineburial.io import variables as V
from mineburial.kernels import status
from mineburial.kernels.mine import layout
from mineburial.kernels.mine import status as mine_status
from mineburial.systems.mine import ensemble as mine
from mineburial.systems.mine.dataset import build_dataset
from mineburial.systems.restraint import ensemble as restraint

DOCS = pathlib.Path(__file__).resolve().parents[1] / "docs"


def _design_table() -> dict:
    text = (DOCS / "design.md").read_text(encoding="utf-8")
    return {int(c): n for c, n in re.findall(r"^\| (\d) \| `(\w+)` \|", text, flags=re.M)}


def test_the_mine_s_vocabulary_is_its_documented_table():
    vocab = status.vocabulary(mine.SYSTEM)
    assert vocab is mine_status.VOCABULARY
    assert vocab.names == _design_table() and vocab.codes == tuple(range(7))
    # "In the statistics": at_rest and buried_sinking (docs/design.md)
    assert {vocab.name(c) for c in vocab.in_statistics} == {"at_rest", "buried_sinking"}
    # the kernels' constants are the vocabulary's codes
    for name in ("AT_REST", "LEFT_DOMAIN", "FLOATED", "BURIED_SINKING", "TIME_LIMIT", "INVALID_INPUT"):
        code = getattr(mine_status, name)
        assert type(code) is int and vocab.name(code) == name.lower(), name


def test_the_restraint_s_vocabulary_is_its_documented_codes():
    text = (DOCS / "restraint.md").read_text(encoding="utf-8")
    said = re.search(
        r"flag values 0, 1, 3, 4\): 0 `stopped`;\s+1 `time_limit`.*?3 `numerical_failure`", text, re.S
    )
    assert said and "4 `invalid_input`" in text
    vocab = status.vocabulary(restraint.SYSTEM)
    assert vocab.names == {0: "stopped", 1: "time_limit", 3: "numerical_failure", 4: "invalid_input"}
    attrs = restraint._status_attrs()
    assert attrs["flag_values"].dtype == np.int8 and attrs["flag_values"].tolist() == [0, 1, 3, 4]
    assert attrs["flag_meanings"] == "stopped time_limit numerical_failure invalid_input"


def test_the_shared_codes_carry_one_name_in_every_registered_system():
    assert set(status.VOCABULARIES) >= {"mine", "restraint"}
    for vocab in status.VOCABULARIES.values():
        for code, name in {1: "time_limit", 3: "numerical_failure", 4: "invalid_input"}.items():
            assert vocab.name(code) == name, vocab.system
        assert status.END in vocab.codes


def test_a_written_ensemble_file_holds_the_documented_flags():
    n = 7
    summary = np.zeros((n, layout.N_SUMMARY))
    ds = build_dataset(summary, np.arange(n, dtype=np.int8), version="0.1.0")
    table = _design_table()
    for name in ("status", "status_code"):
        assert ds[name].attrs["flag_values"].tolist() == sorted(table), name
        assert ds[name].attrs["flag_meanings"].split() == [table[c] for c in sorted(table)], name
    assert V.VARIABLES["status"].attrs["flag_values"].dtype == np.int8


def _vocab(names, **kw):
    return status.Vocabulary("toy", names, {c: f"code {c}" for c in names}, **kw)


SHARED = {0: "done", 1: "time_limit", 3: "numerical_failure", 4: "invalid_input"}


@pytest.mark.parametrize(
    "names, said",
    [
        ({**SHARED, 1: "timeout"}, "the shared code 1 is named 'timeout', not 'time_limit'"),
        ({k: v for k, v in SHARED.items() if k != 4}, "the shared code 4 is missing"),
        ({k: v for k, v in SHARED.items() if k != 0}, "the shared code 0 is missing"),
        ({**SHARED, 5: "done"}, "name 'done' is not a unique single word"),
        ({**SHARED, 5: "two words"}, "name 'two words' is not a unique single word"),
        ({**SHARED, 200: "big"}, "code 200 is not an integer in 0..127"),
    ],
)
def test_a_vocabulary_that_breaks_the_shared_codes_is_refused(names, said):
    with pytest.raises(ValueError, match=re.escape(said)):
        _vocab(names)


def test_in_statistics_must_name_codes_of_the_system():
    with pytest.raises(ValueError, match=r"in_statistics \(7,\)"):
        _vocab(SHARED, in_statistics=(7,))


def test_registering_is_idempotent_and_refuses_a_second_vocabulary_under_a_name():
    toy = _vocab({**SHARED, 5: "sank"}, in_statistics=(0,))
    try:
        assert status.register(toy) is toy
        assert status.register(_vocab({**SHARED, 5: "sank"}, in_statistics=(0,))) is toy
        with pytest.raises(ValueError, match="a different status vocabulary of 'toy'"):
            status.register(_vocab({**SHARED, 5: "floated"}))
        assert (
            status.vocabulary("toy").flag_meanings == "done time_limit numerical_failure invalid_input sank"
        )
    finally:
        status.VOCABULARIES.pop("toy", None)
    with pytest.raises(KeyError, match="no status vocabulary of system 'toy'; registered: mine"):
        status.vocabulary("toy")


def test_the_status_modules_import_no_numba_and_nothing_else_of_mineburial():
    """kernels/status.py and the mine's kernels/mine/status.py are read by the variable registry and
    the command line without numba: in a fresh interpreter they load only each other and the package
    folders above them."""
    code = (
        "import sys\n"
        "import mineburial.kernels.mine.status as m\n"
        "print(sorted(k for k in sys.modules if k.startswith('mineburial') or k in ('numba', 'numpy')))\n"
        "print(m.VOCABULARY.flag_meanings)\n"
    )
    done = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, timeout=120, check=True
    )
    loaded, meanings = done.stdout.splitlines()
    assert loaded == str(
        ["mineburial", "mineburial._version", "mineburial.kernels", "mineburial.kernels.mine",
         "mineburial.kernels.mine.status", "mineburial.kernels.status"]
    )  # fmt: skip
    assert meanings.split() == [_design_table()[c] for c in sorted(_design_table())]
