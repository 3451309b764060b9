"""Safe output files (private): never overwrite unasked, never leave half-written files.

Every writer goes through :func:`atomic_write`: the content is written to a temporary file in the
target's folder and renamed over the target only when complete, so an interrupted run (Ctrl-C, a
crash) leaves either the old file or none, never a truncated one.
"""

from __future__ import annotations

import os
import tempfile
from contextlib import contextmanager
from pathlib import Path
from typing import Iterable, Iterator

from .errors import SealeakError

__all__ = ["OutputExistsError", "check_outputs", "atomic_write", "write_text"]


class OutputExistsError(SealeakError):
    """An output file exists and overwriting it was not asked for."""


def check_outputs(paths: Iterable[str | Path], force: bool) -> None:
    """Refuse up front (before any work) when an output exists and ``force`` is False."""
    existing = [str(p) for p in paths if Path(p).exists()]
    if existing and not force:
        shown = ", ".join(existing[:5]) + (f" and {len(existing) - 5} more" if len(existing) > 5 else "")
        raise OutputExistsError(f"{shown} already exist{'s' if len(existing) == 1 else ''}; "
                                "pass --force to overwrite, or choose another name")
    for p in paths:
        parent = Path(p).parent
        if parent.exists() and not parent.is_dir():
            raise OutputExistsError(f"{parent} is a file, not a folder")


@contextmanager
def atomic_write(path: str | Path, mode: str = "w") -> Iterator[Path]:
    """Yield a temporary path next to ``path``; on success rename it to ``path``, else delete it."""
    target = Path(path)
    target.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(prefix=f".{target.name}.", suffix=".part", dir=target.parent)
    os.close(fd)
    tmp_path = Path(tmp)
    try:
        yield tmp_path
        os.chmod(tmp_path, 0o666 & ~_umask())  # mkstemp makes 0600; give the usual permissions
        os.replace(tmp_path, target)
    except BaseException:
        tmp_path.unlink(missing_ok=True)
        raise


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


def write_text(path: str | Path, text: str) -> None:
    """Write ``text`` to ``path`` atomically (UTF-8)."""
    with atomic_write(path) as tmp:
        tmp.write_text(text, encoding="utf-8")
