"""Reproducible per-drop uniforms and input samples (Monte Carlo and scrambled Sobol').

The uniform number that drives field *k* of drop *i* is a **pure function of
(seed, i, k)** for ``method="mc"`` and of (seed, i, the set of random fields)
for ``method="sobol"``. It does not depend on how the drops are chunked, on the
thread count or on the machine, so any chunk ``[start, stop)`` can be drawn on
any worker and any single drop can be re-run on its own.

Monte Carlo (``"mc"``): counter-based Philox4x64-10 (Salmon, Moraes, Dror &
Shaw 2011, "Parallel random numbers: as easy as 1, 2, 3", SC'11), keyed by
``(seed, field_id)``. Draw *i* of a field is 64-bit word ``i % 4`` of the block
``Philox4x64-10(counter=(i // 4 + 1, 0, 0, 0), key=(seed, field_id))``, which is
exactly raw output *i* of ``numpy.random.Philox(key=[seed, field_id])``. The
64-bit word ``x`` becomes ``u = ((x >> 12) + 0.5) * 2**-52``: the 2**52 odd
multiples of 2**-53, equally likely, strictly inside (0, 1) and symmetric about
1/2 (``u01_open_open_64_53`` of Zhou's vSMC/MCKL ``u01.h``).

Scrambled Sobol' (``"sobol"``): ``scipy.stats.qmc.Sobol(d, scramble=True,
bits=32, rng=seed)`` (Joe & Kuo 2008 direction numbers; LMS + digital-shift
scrambling, Owen 1997 / Matousek 1998), one dimension per random field, the
dimensions given to the fields in increasing order of their field ids;
``fast_forward(start)`` positions a chunk. The 32-bit point ``q / 2**32`` is
completed below its last digit by an independent uniform of the Philox stream
(counter word 1 = 1, so disjoint from the ``"mc"`` draws):
``u = (q + v) / 2**32``. This is Owen's convention that digits beyond the
precision of the net are i.i.d. uniform; it keeps every point inside its
2**-32 cell (so all stratification properties of the net hold) while making
each marginal exactly uniform with double resolution.

Field ids: :func:`field_id` hashes the field's dotted name (BLAKE2b, 8 bytes),
never its position, so adding a random field to a scenario does not change the
Monte Carlo draws of the other fields (for Sobol' it does: the dimension count
changes the point set).
"""

from __future__ import annotations

import hashlib
import warnings
from collections.abc import Iterable, Mapping, Sequence
from typing import Any

import numpy as np

from mineburial._numba import kernel
from mineburial.ensembles.distributions import Distribution, parse_value

__all__ = [
    "METHODS",
    "SobolBalanceWarning",
    "SampleTable",
    "field_id",
    "uniforms",
    "sample_fields",
    "check_drop_count",
]

#: Sampling methods accepted by :func:`uniforms` and :func:`sample_fields`.
METHODS = ("mc", "sobol")

#: Bits of the Sobol' net (scipy's fast_forward supports at most 32); at most
#: 2**32 drops per run.
SOBOL_BITS = 32
_SOBOL_SCALE = 2.0**-SOBOL_BITS

_MASK32 = np.uint64(0xFFFFFFFF)
_SH32 = np.uint64(32)
_SH12 = np.uint64(12)
# Philox4x64 constants (Salmon et al. 2011; Random123 philox.h)
_PHILOX_M0 = np.uint64(0xD2E7470EE14C6C93)
_PHILOX_M1 = np.uint64(0xCA5A826395121157)
_PHILOX_W0 = np.uint64(0x9E3779B97F4A7C15)  # golden ratio
_PHILOX_W1 = np.uint64(0xBB67AE8584CAA73B)  # sqrt(3) - 1
_ZERO = np.uint64(0)
_ONE = np.uint64(1)


class SobolBalanceWarning(UserWarning):
    """The number of drops of a Sobol' run is not a power of two."""


# ---------------------------------------------------------------------------
# numba kernels: Philox4x64-10 and the conversion to open (0, 1)
# ---------------------------------------------------------------------------


@kernel
def _mulhilo64(a, b):
    """(hi, lo) words of the 128-bit product of two uint64 (schoolbook, 32-bit halves)."""
    a_lo = a & _MASK32
    a_hi = a >> _SH32
    b_lo = b & _MASK32
    b_hi = b >> _SH32
    p0 = a_lo * b_lo
    p1 = a_lo * b_hi
    p2 = a_hi * b_lo
    p3 = a_hi * b_hi
    mid = (p0 >> _SH32) + (p1 & _MASK32) + (p2 & _MASK32)
    hi = p3 + (p1 >> _SH32) + (p2 >> _SH32) + (mid >> _SH32)
    return hi, a * b


@kernel
def _philox4x64_10(c0, c1, c2, c3, k0, k1):
    """One Philox4x64-10 block (Salmon et al. 2011, Random123 ``philox4x64_R`` with R = 10)."""
    for r in range(10):
        if r > 0:  # key schedule: bump before rounds 1..9
            k0 = k0 + _PHILOX_W0
            k1 = k1 + _PHILOX_W1
        hi0, lo0 = _mulhilo64(_PHILOX_M0, c0)
        hi1, lo1 = _mulhilo64(_PHILOX_M1, c2)
        c0, c1, c2, c3 = hi1 ^ c1 ^ k0, lo1, hi0 ^ c3 ^ k1, lo0
    return c0, c1, c2, c3


@kernel
def _open_unit(x):
    """uint64 -> double in (0, 1): ((x >> 12) + 1/2) 2**-52 (vSMC ``u01_open_open_64_53``)."""
    return (np.float64(x >> _SH12) + 0.5) * 2.220446049250313e-16


@kernel
def _philox_fill(seed, fids, ctr1, start, out):
    """out[j, c] = uniform of draw ``start + j`` of the stream with key (seed, fids[c]).

    Draw i is word ``i % 4`` of Philox4x64-10(counter=(i//4 + 1, ctr1, 0, 0), key).
    ``out`` is a C-contiguous (n, n_fields) float64 array.
    """
    n = out.shape[0]
    if n == 0:
        return
    stop = start + n
    b_first = start // 4
    b_last = (stop - 1) // 4
    for c in range(fids.shape[0]):
        k1 = fids[c]
        for b in range(b_first, b_last + 1):
            w0, w1, w2, w3 = _philox4x64_10(np.uint64(b) + _ONE, ctr1, _ZERO, _ZERO, seed, k1)
            i0 = b * 4
            if i0 >= start and i0 + 3 < stop:
                j = i0 - start
                out[j, c] = _open_unit(w0)
                out[j + 1, c] = _open_unit(w1)
                out[j + 2, c] = _open_unit(w2)
                out[j + 3, c] = _open_unit(w3)
            else:
                for w in range(4):
                    i = i0 + w
                    if i >= start and i < stop:
                        if w == 0:
                            x = w0
                        elif w == 1:
                            x = w1
                        elif w == 2:
                            x = w2
                        else:
                            x = w3
                        out[i - start, c] = _open_unit(x)


# ---------------------------------------------------------------------------
# public API
# ---------------------------------------------------------------------------


def field_id(name: str) -> int:
    """Stable 64-bit id of a field: the first 8 bytes (little-endian) of BLAKE2b(name).

    Derived from the dotted name only (e.g. ``"mine.mass"``), never from the
    field's position, so it is the same in every scenario, process and version.
    """
    if not isinstance(name, str) or not name:
        raise TypeError(f"a field name must be a non-empty string, got {name!r}")
    digest = hashlib.blake2b(name.encode("utf-8"), digest_size=8).digest()
    return int.from_bytes(digest, "little")


def _check_seed(seed) -> int:
    if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)):
        raise TypeError(f"seed = {seed!r} must be an integer in [0, 2**64)")
    seed = int(seed)
    if not 0 <= seed < 2**64:
        raise ValueError(f"seed = {seed} must be in [0, 2**64)")
    return seed


def _check_range(start, stop) -> tuple[int, int]:
    for name, v in (("start", start), ("stop", stop)):
        if isinstance(v, bool) or not isinstance(v, (int, np.integer)):
            raise TypeError(f"{name} = {v!r} must be an integer")
    start, stop = int(start), int(stop)
    if not 0 <= start <= stop:
        raise ValueError(f"drop range [start, stop) = [{start}, {stop}) needs 0 <= start <= stop")
    if stop > 2**62:
        raise ValueError(f"stop = {stop} must be <= 2**62")
    return start, stop


def _ids(field_ids: Iterable[int | str]) -> np.ndarray:
    ids = []
    for f in field_ids:
        if isinstance(f, str):
            ids.append(field_id(f))
        elif isinstance(f, (int, np.integer)) and not isinstance(f, bool) and 0 <= int(f) < 2**64:
            ids.append(int(f))
        else:
            raise TypeError(f"field id {f!r} must be a field name or an integer in [0, 2**64)")
    arr = np.array(ids, dtype=np.uint64)
    if np.unique(arr).size != arr.size:
        raise ValueError("field ids must be distinct (a field listed twice?)")
    return arr


def _philox(seed: int, ids: np.ndarray, start: int, stop: int, ctr1: int) -> np.ndarray:
    out = np.empty((stop - start, ids.size), dtype=np.float64)
    _philox_fill(np.uint64(seed), ids, np.uint64(ctr1), np.int64(start), out)
    return out


def _sobol_engine(d: int, seed: int):
    # local import: start-up, scipy.stats adds 1.3 s CPU to importing the runner (2.2 -> 3.6 s,
    # median of 5), paid only by Sobol' sampling
    from scipy.stats import qmc

    rng = np.random.default_rng(seed)
    try:
        return qmc.Sobol(d, scramble=True, bits=SOBOL_BITS, rng=rng)
    except TypeError:  # scipy < 1.15 names the argument ``seed``
        return qmc.Sobol(d, scramble=True, bits=SOBOL_BITS, seed=rng)


def _sobol(seed: int, ids: np.ndarray, start: int, stop: int) -> np.ndarray:
    n, d = stop - start, ids.size
    if stop > 2**SOBOL_BITS:
        raise ValueError(f"a Sobol' run has at most 2**{SOBOL_BITS} drops; stop = {stop}")
    if n == 0 or d == 0:
        return np.empty((n, d), dtype=np.float64)
    engine = _sobol_engine(d, seed)
    if start > 0:
        engine.fast_forward(start)
        pts = engine.random(n)
    else:
        # draw the first point alone: scipy warns on a first call with n not a
        # power of two, which is meaningless for one chunk of a larger run
        first = engine.random(1)
        pts = np.concatenate([first, engine.random(n - 1)]) if n > 1 else first
    # dimension j belongs to the field with the j-th smallest id
    order = np.argsort(ids, kind="stable")
    rank = np.empty_like(order)
    rank[order] = np.arange(d)
    q = pts[:, rank] * 2.0**SOBOL_BITS  # exact integers
    jitter = _philox(seed, ids, start, stop, ctr1=1)  # digits below 2**-32
    u = (q + jitter) * _SOBOL_SCALE
    # q + v may round up to q + 1: keep the point strictly inside its cell
    # [q, q + 1) 2**-32 (this also keeps u < 1)
    np.minimum(u, np.nextafter((q + 1.0) * _SOBOL_SCALE, 0.0), out=u)
    return u


def uniforms(
    seed: int, field_ids: Sequence[int | str], start: int, stop: int, method: str = "mc"
) -> np.ndarray:
    """Uniforms in (0, 1) for drops ``start..stop-1`` and the given fields.

    Returns a C-contiguous float64 array of shape ``(stop - start, len(field_ids))``;
    column c belongs to ``field_ids[c]`` (a field name, hashed with
    :func:`field_id`, or an integer id). Row j is drop ``start + j``.

    ``"mc"``: entry (i, k) is a pure function of (seed, i, k).
    ``"sobol"``: a pure function of (seed, i, the set of field ids); the order
    of ``field_ids`` only orders the columns.
    """
    seed = _check_seed(seed)
    start, stop = _check_range(start, stop)
    ids = _ids(field_ids)
    if method == "mc":
        return _philox(seed, ids, start, stop, ctr1=0)
    if method == "sobol":
        return _sobol(seed, ids, start, stop)
    raise ValueError(f"unknown sampling method {method!r}; available methods are {', '.join(METHODS)}")


def check_drop_count(n_drops: int, method: str) -> None:
    """Warn (:class:`SobolBalanceWarning`) when a Sobol' run is not a power of two.

    The balance (stratification) properties of a Sobol' net hold for the first
    2**m points; call this once per run, before drawing chunks.
    """
    if method not in METHODS:
        raise ValueError(f"unknown sampling method {method!r}; available methods are {', '.join(METHODS)}")
    if method == "sobol":
        n = int(n_drops)
        if n > 2**SOBOL_BITS:
            raise ValueError(f"a Sobol' run has at most 2**{SOBOL_BITS} drops; got {n}")
        if n < 1 or n & (n - 1):
            lo = 1 << max(n.bit_length() - 1, 0)
            warnings.warn(
                f"n_drops = {n} is not a power of two: the Sobol' points lose their "
                f"balance properties (use {lo} or {lo * 2})",
                SobolBalanceWarning,
                stacklevel=2,
            )


class SampleTable(dict):
    """``dict[field -> ndarray]`` of sampled inputs, plus labels of categorical fields.

    Numeric fields map to float64 arrays. Categorical fields (a ``choice`` among
    strings, or a fixed string) map to int64 arrays of indices into
    ``labels[field]``; :meth:`decoded` returns the strings.
    """

    def __init__(self, *args, labels: Mapping[str, tuple[str, ...]] | None = None, **kw):
        super().__init__(*args, **kw)
        self.labels: dict[str, tuple[str, ...]] = dict(labels or {})

    def decoded(self, field: str) -> np.ndarray:
        """The string values of a categorical field (a numpy str array)."""
        return np.asarray(self.labels[field])[self[field]]


def sample_fields(
    spec: Mapping[str, Any], seed: int, start: int, stop: int, method: str = "mc"
) -> SampleTable:
    """Draw every field of ``spec`` for drops ``start..stop-1``.

    ``spec`` maps dotted field names to fixed values (number or string),
    :class:`Distribution` objects or raw inline tables (parsed with
    :func:`parse_value`). Each random field gets the uniforms of its own
    :func:`field_id` (see :func:`uniforms`) mapped through its ``ppf``; fixed
    values are broadcast. Categorical fields return indices + labels (see
    :class:`SampleTable`).
    """
    n = _check_range(start, stop)[1] - int(start)
    parsed = {name: parse_value(v, name) for name, v in spec.items()}
    random_names = [name for name, v in parsed.items() if isinstance(v, Distribution)]
    u = uniforms(seed, random_names, start, stop, method)
    out = SampleTable()
    col = {name: c for c, name in enumerate(random_names)}
    for name, v in parsed.items():
        if isinstance(v, Distribution):
            uc = np.ascontiguousarray(u[:, col[name]])
            if v.categorical:
                out[name] = v.index(uc)
                out.labels[name] = tuple(v.values)
            else:
                out[name] = np.ascontiguousarray(v.ppf(uc), dtype=np.float64)
        elif isinstance(v, str):
            out[name] = np.zeros(n, dtype=np.int64)
            out.labels[name] = (v,)
        else:
            out[name] = np.full(n, v, dtype=np.float64)
    return out
