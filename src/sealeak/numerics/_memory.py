"""Up-front memory checks shared by the numerical solvers."""

from __future__ import annotations

import os

from ..errors import ResourceError


def available_memory_bytes() -> int:
    """Memory the OS reports as available (``MemAvailable`` in /proc/meminfo), in bytes.

    Falls back to the physical memory (``os.sysconf``) where /proc is missing.
    """
    try:
        with open("/proc/meminfo", encoding="ascii") as fh:
            for line in fh:
                if line.startswith("MemAvailable:"):
                    return int(line.split()[1]) * 1024
    except OSError:
        pass
    return int(os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES"))


def require_memory(need: int, what: str, available: float | None = None) -> None:
    """Raise :class:`ResourceError` when ``need`` bytes exceed ``available`` (default: what the OS reports)."""
    have = available_memory_bytes() if available is None else float(available)
    if need > have:
        raise ResourceError(
            f"{what} needs about {need / 2**30:.2f} GiB (estimate), "
            f"more than the {have / 2**30:.2f} GiB available; use a smaller grid")
