"""Memory this process may still use: the one source of every memory check before computing.

:func:`available_memory` is the smallest of

* ``MemAvailable`` of ``/proc/meminfo`` (Linux >= 3.14: the kernel's estimate of the memory
  that can be given to new work without swapping, page cache and reclaimable slab
  included; ``Documentation/filesystems/proc.rst``), or the total RAM
  (``sysconf(SC_PHYS_PAGES)``) where that file or field is absent;
* for every memory cgroup this process is in, and each of its ancestors, the limit minus
  the usage: cgroup v2 ``memory.max`` - ``memory.current`` (``max``: no limit), cgroup v1
  ``memory.limit_in_bytes`` - ``memory.usage_in_bytes``
  (``Documentation/admin-guide/cgroup-v2.rst`` and ``cgroup-v1/memory.rst``). In a
  container the cgroup limit, not the machine's RAM, is what the out-of-memory killer
  enforces.

A leaf module (standard library only), so that the drop, the run driver, ``compare``,
``sensitivity`` and ``map`` share it. The paths are arguments so tests can give fake
files.
"""

from __future__ import annotations

import math
import os
import pathlib

__all__ = ["available_memory", "memory_refusal", "format_bytes"]

PROC = pathlib.Path("/proc")
CGROUP = pathlib.Path("/sys/fs/cgroup")
#: cgroup v1 writes a "no limit" as the largest page-aligned signed 64-bit value; anything
#: from 2**60 bytes (1 EiB) up is taken as no limit
_NO_LIMIT = 2**60


def _read_int(path: pathlib.Path) -> int | None:
    try:
        text = path.read_text().strip()
    except (OSError, UnicodeDecodeError):
        return None
    try:
        return int(text)
    except ValueError:  # "max" (cgroup v2: no limit) or garbage
        return None


def _mem_available(proc: pathlib.Path) -> int | None:
    try:
        lines = (proc / "meminfo").read_text().splitlines()
    except (OSError, UnicodeDecodeError):
        return None
    for line in lines:
        key, _, rest = line.partition(":")
        if key.strip() == "MemAvailable":
            parts = rest.split()
            if parts and parts[0].isdigit():
                scale = 1024 if len(parts) > 1 and parts[1].lower() == "kb" else 1
                return int(parts[0]) * scale
    return None


def _total_ram() -> int | None:
    try:
        return int(os.sysconf("SC_PAGE_SIZE")) * int(os.sysconf("SC_PHYS_PAGES"))
    except (AttributeError, ValueError, OSError):  # pragma: no cover - not POSIX
        return None


def _cgroup_dirs(proc: pathlib.Path, cgroup: pathlib.Path) -> list[tuple[pathlib.Path, str, str]]:
    """(folder, limit file, usage file) of this process's memory cgroups and their
    ancestors, from ``/proc/self/cgroup`` (lines ``id:controllers:path``)."""
    try:
        lines = (proc / "self" / "cgroup").read_text().splitlines()
    except (OSError, UnicodeDecodeError):
        lines = []
    found = []
    for line in lines:
        parts = line.split(":", 2)
        if len(parts) != 3:
            continue
        _, controllers, rel = parts
        if controllers == "":  # v2: the unified hierarchy (under unified/ on a hybrid system)
            v2_root = cgroup if (cgroup / "cgroup.controllers").exists() else cgroup / "unified"
            mount, files = v2_root, ("memory.max", "memory.current")
        elif "memory" in controllers.split(","):
            mount, files = cgroup / "memory", ("memory.limit_in_bytes", "memory.usage_in_bytes")
        else:
            continue
        rel_parts = [p for p in pathlib.PurePosixPath(rel).parts if p not in ("/", "..", ".")]
        for k in range(len(rel_parts), -1, -1):  # the cgroup, then each ancestor up to the root
            found.append((mount.joinpath(*rel_parts[:k]), *files))
    return found


def available_memory(proc=PROC, cgroup=CGROUP) -> int | None:
    """Bytes this process may still allocate (see the module docstring); None only where
    neither ``/proc/meminfo``, the total RAM nor a cgroup limit is known."""
    proc, cgroup = pathlib.Path(proc), pathlib.Path(cgroup)
    avail = _mem_available(proc)
    candidates = [avail if avail is not None else _total_ram()]
    for folder, limit_file, usage_file in _cgroup_dirs(proc, cgroup):
        limit = _read_int(folder / limit_file)
        if limit is None or limit >= _NO_LIMIT:
            continue
        usage = _read_int(folder / usage_file) or 0
        candidates.append(max(limit - usage, 0))
    known = [c for c in candidates if c is not None]
    return min(known) if known else None


def format_bytes(n: float) -> str:
    """``n`` bytes in the largest binary unit below it, 3 significant digits."""
    for unit in ("bytes", "KiB", "MiB", "GiB", "TiB", "PiB"):
        if abs(n) < 1024 or unit == "PiB":
            return f"{n:.3g} {unit}"
        n /= 1024
    return f"{n:.3g} PiB"  # pragma: no cover


def memory_refusal(need: float, asked: str, advice: str, *, share: float = 1.0, have=None) -> str | None:
    """The one line refusing ``asked`` when it would need ``need`` bytes, more than
    ``share`` of the available memory (or a ``need`` that is not finite); None when it
    fits. ``have`` overrides :func:`available_memory` (tests)."""
    have = available_memory() if have is None else have
    if math.isfinite(need) and (have is None or need <= share * have):
        return None
    amount = f"about {format_bytes(need)}" if math.isfinite(need) else "an unbounded amount"
    part = "half of " if share == 0.5 else ("" if share == 1.0 else f"{share:.0%} of ")
    return (
        f"{asked} would need {amount} of memory, more than {part}the {format_bytes(have or 0)} "
        f"available (free memory and the cgroup limit); {advice}"
    )
