"""Safe output files (private): never overwrite unasked, never leave half-written files, replace regular files only.

Every writer goes through :func:`atomic_write`: the content is written to a temporary file in the
target's folder and renamed over the target only when complete, so an interrupted run (Ctrl-C, a
crash) leaves either the old file or none, never a truncated one.

What an output may replace: nothing, or a **regular file** (with ``--force``). Anything else at the
output's path is refused, with or without ``--force``, because renaming a file over it would
destroy or silently change it: a folder, a device node (``/dev/null``), a named pipe (FIFO), a
socket, and a **symbolic link** (also one to a regular file: replacing the link by a file would
cut the link, and writing through it would write somewhere the command line does not name; give
the link's target as the output instead). The checks look at the path itself (``lstat``), not at
what a link points to.
"""

from __future__ import annotations

import os
import stat
import tempfile
from collections.abc import Iterable, Iterator
from contextlib import contextmanager
from pathlib import Path

from ..errors import FileFormatError, SealeakError

__all__ = ["OutputExistsError", "OutputWriteError", "check_outputs", "check_replaceable", "atomic_write", "write_text",
           "input_file"]


class OutputExistsError(SealeakError):
    """An output file exists and overwriting it was not asked for (or cannot be replaced)."""


class OutputWriteError(SealeakError):
    """The operating system refused to write an output file."""

    def __init__(self, path: Path, exc: OSError) -> None:
        super().__init__(f"cannot write {path}: {exc.strerror or exc}")


_KINDS = ((stat.S_ISCHR, "a character device"), (stat.S_ISBLK, "a block device"), (stat.S_ISFIFO, "a named pipe (FIFO)"),
          (stat.S_ISSOCK, "a socket"))


def _kind(mode: int) -> str:
    """What a non-regular file is, in words."""
    return next((name for test, name in _KINDS if test(mode)), "not a regular file")


def check_replaceable(path: str | Path) -> bool:
    """Whether ``path`` exists as a regular file (True) or not at all (False).

    Raises :class:`OutputExistsError` (one line naming the path) if anything else is there: a
    folder, a symbolic link (to anything), a device node, a named pipe, a socket. Such a path is
    never replaced, with or without ``--force``.
    """
    p = Path(path)
    try:
        st = os.lstat(p)
    except FileNotFoundError:
        return False
    except NotADirectoryError:
        raise OutputExistsError(f"{p}: a part of the path above it is a file, not a folder") from None
    except OSError as exc:
        raise OutputWriteError(p, exc) from None
    if stat.S_ISREG(st.st_mode):
        return True
    if stat.S_ISDIR(st.st_mode):
        raise OutputExistsError(f"{p} is a folder: give a file name for this output")
    if stat.S_ISLNK(st.st_mode):
        try:
            target = os.readlink(p)
        except OSError:  # pragma: no cover - raced away
            target = "?"
        raise OutputExistsError(f"{p} is a symbolic link (to {target}): outputs replace regular files only, even with "
                                "--force; give the path of a regular file itself, or another name")
    raise OutputExistsError(f"{p} is {_kind(st.st_mode)}, not a regular file: outputs replace regular files only, "
                            "even with --force; give a file name")


def check_outputs(paths: Iterable[str | Path], force: bool) -> None:
    """Refuse up front (before any work) outputs that cannot or may not be written.

    Refused, with or without ``force``: two outputs of one run that are the same file (the second
    would silently replace the first); a path that exists and is not a regular file (a folder, a
    symbolic link, a device such as ``/dev/null``, a named pipe, a socket: see
    :func:`check_replaceable`); a path below a file, or in a folder the user may not write into.
    Refused without ``force``: a path that exists as a regular file.
    """
    targets = [Path(p) for p in paths]
    seen: dict[Path, Path] = {}
    for p in targets:
        key = p.resolve()
        if key in seen:
            raise OutputExistsError(f"{seen[key]} and {p} are the same file: give each output its own name")
        seen[key] = p
    for p in targets:
        _check_folder(p)
    existing = [str(p) for p in targets if check_replaceable(p)]
    if existing and not force:
        shown = ", ".join(existing[:5]) + (f" and {len(existing) - 5} more" if len(existing) > 5 else "")
        raise OutputExistsError(f"{shown} already exist{'s' if len(existing) == 1 else ''}; "
                                "pass --force to overwrite, or choose another name")


def _check_folder(path: Path) -> None:
    """The folder of ``path`` is (or will be created in) a folder the user may write into."""
    parent = path.parent
    try:
        existing = next((d for d in (parent, *parent.parents) if d.exists()), Path("."))
        is_dir = existing.is_dir()
    except OSError as exc:
        raise OutputWriteError(path, exc) from None
    if not is_dir:
        where = "" if existing == parent else f" (it is in the path of {path})"
        raise OutputExistsError(f"cannot write {path}: {existing} is not a folder{where}")
    if not os.access(existing, os.W_OK | os.X_OK):
        raise OutputExistsError(f"cannot write {path}: no permission to write into the folder {existing}")


@contextmanager
def atomic_write(path: str | Path, mode: str = "w") -> Iterator[Path]:
    """Yield a temporary path next to ``path``; on success rename it to ``path``, else delete it.

    ``path`` may be absent or a regular file; anything else (a folder, a symbolic link, a device,
    a named pipe, a socket) raises :class:`OutputExistsError`, checked before writing and again
    just before the rename. Operating-system failures (no permission, no such folder, disk full)
    raise :class:`OutputWriteError` naming the file, never a bare ``OSError``.
    """
    target = Path(path)
    check_replaceable(target)
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
            check_replaceable(target)  # something else may have appeared there meanwhile
            os.replace(tmp_path, target)
        except OSError as exc:
            raise OutputWriteError(target, exc) from None
    except BaseException:
        tmp_path.unlink(missing_ok=True)
        raise


def input_file(path: str | Path, what: str = "file") -> Path:
    """``path`` as an input that can be read: a regular file, or a symbolic link to one.

    Raises :class:`~sealeak.errors.FileFormatError` naming the path otherwise: missing, a folder, or
    a device, named pipe or socket (reading ``/dev/zero`` or a FIFO would never end).
    ``what`` names the input in the messages (``"case file"``, ``"data file"``).
    """
    p = Path(path)
    try:
        st = os.stat(p)  # follows links: a link to a regular file reads like the file
    except FileNotFoundError:
        raise FileFormatError(p, f"{what} not found") from None
    except NotADirectoryError:
        raise FileFormatError(p, f"{what} not found (a part of the path is a file, not a folder)") from None
    except OSError as exc:
        raise FileFormatError(p, f"cannot read it: {exc.strerror or exc}") from None
    if stat.S_ISDIR(st.st_mode):
        raise FileFormatError(p, f"is a folder, not a {what}")
    if not stat.S_ISREG(st.st_mode):
        raise FileFormatError(p, f"is {_kind(st.st_mode)}, not a regular file" + ("" if what == "file" else f": give a {what}"))
    return p


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


def write_text(path: str | Path, text: str) -> None:
    """Write ``text`` to ``path`` atomically (UTF-8)."""
    with atomic_write(path) as tmp:
        tmp.write_text(text, encoding="utf-8")
