"""Safe output files (private): never overwrite unasked, never leave half-written files.

Every writer goes through :func:`atomic_write`: the content is written to a temporary file in the
target's folder and renamed over the target only when complete, so an interrupted run (Ctrl-C, a
crash) leaves either the old file or none, never a truncated one.
"""

from __future__ import annotations

import os
import tempfile
from collections.abc import Iterable, Iterator
from contextlib import contextmanager
from pathlib import Path

from ..errors import SealeakError

__all__ = ["OutputExistsError", "OutputWriteError", "check_outputs", "atomic_write", "write_text"]


class OutputExistsError(SealeakError):
    """An output file exists and overwriting it was not asked for (or cannot be replaced)."""


class OutputWriteError(SealeakError):
    """The operating system refused to write an output file."""

    def __init__(self, path: Path, exc: OSError) -> None:
        super().__init__(f"cannot write {path}: {exc.strerror or exc}")


def check_outputs(paths: Iterable[str | Path], force: bool) -> None:
    """Refuse up front (before any work) outputs that cannot or may not be written.

    Refused: a path that exists and ``force`` is False; a path that is an existing folder (even
    with ``force``: a folder is never replaced by a file); two outputs of one run that are the
    same file (the second would silently replace the first); a parent that is a file.
    """
    paths = [Path(p) for p in paths]
    seen: dict[Path, Path] = {}
    for p in paths:
        key = p.resolve()
        if key in seen:
            raise OutputExistsError(f"{seen[key]} and {p} are the same file: give each output its own name")
        seen[key] = p
        if p.is_dir():
            raise OutputExistsError(f"{p} is a folder: give a file name for this output")
    existing = [str(p) for p in paths if p.exists()]
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
    """Yield a temporary path next to ``path``; on success rename it to ``path``, else delete it.

    Operating-system failures (no permission, no such folder, disk full, a folder in the way)
    raise :class:`OutputWriteError` naming the file, never a bare ``OSError``.
    """
    target = Path(path)
    try:
        target.parent.mkdir(parents=True, exist_ok=True)
        fd, tmp = tempfile.mkstemp(prefix=f".{target.name}.", suffix=".part", dir=target.parent)
    except OSError as exc:
        raise OutputWriteError(target, exc) from None
    os.close(fd)
    tmp_path = Path(tmp)
    try:
        try:
            yield tmp_path
            os.chmod(tmp_path, 0o666 & ~_umask())  # mkstemp makes 0600; give the usual permissions
            os.replace(tmp_path, target)
        except OSError as exc:
            raise OutputWriteError(target, exc) from None
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
