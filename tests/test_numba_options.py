"""The numba options of every kernel: the on-disk cache switch MINEBURIAL_NUMBA_CACHE."""

import os
import subprocess
import sys

import pytest

from mineburial._numba import CACHE_ENV, cache_enabled


@pytest.mark.parametrize(
    "value, expected",
    [
        (None, True),
        ("1", True),
        ("true", True),
        (" ON ", True),
        ("", True),
        ("0", False),
        ("false", False),
        ("No", False),
        ("off", False),
    ],
)
def test_cache_switch_values(value, expected):
    environ = {} if value is None else {CACHE_ENV: value}
    assert cache_enabled(environ) is expected


def test_cache_switch_rejects_other_values():
    with pytest.raises(ValueError, match=r"MINEBURIAL_NUMBA_CACHE = 'maybe' must be 1 .* or 0"):
        cache_enabled({CACHE_ENV: "maybe"})


@pytest.mark.parametrize("value, cache_class", [("0", "NullCache"), ("1", "FunctionCache")])
def test_kernels_follow_the_switch(value, cache_class):
    """In a fresh process, the kernels' numba dispatchers carry numba's null cache when the
    switch is off and its on-disk function cache when it is on (nothing is compiled)."""
    code = (
        "from mineburial.kernels.rotation import rotation_matrix; "
        "print(type(rotation_matrix._cache).__name__)"
    )
    env = {**os.environ, CACHE_ENV: value}
    out = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, check=True)
    assert out.stdout.strip() == cache_class
