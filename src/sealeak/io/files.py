"""Safe output files (private): never overwrite unasked, never leave half-written files, replace regular files only.

Every writer goes through :func:`atomic_write` or, for the outputs of a command, :func:`write_files`: the content is
written to a temporary file in the target's folder and renamed over the target only when complete (with
:func:`write_files`, only when every output of the run is), so an interrupted run (Ctrl-C, a crash) leaves either the
old file or none, never a truncated one.

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
import sys
import tempfile
from collections.abc import Iterable, Iterator
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path

from ..errors import FileFormatError, InputError, SealeakError, show_value

__all__ = ["Output", "OutputExistsError", "OutputWriteError", "check_outputs", "check_replaceable", "atomic_write", "write_text",
           "write_output", "write_files", "STDOUT", "input_file"]

#: The output path that means standard output (``--json -``).
STDOUT = "-"


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


def check_replaceable(path: str | Path, shown: str = "") -> bool:
    """Whether ``path`` exists as a regular file (True) or not at all (False).

    Raises :class:`OutputExistsError` (one line naming the path, as ``shown`` where given: ``--json y.json``) if anything
    else is there: a folder, a symbolic link (to anything), a device node, a named pipe, a socket. Such a path is
    never replaced, with or without ``--force``.
    """
    p = Path(path)
    name = shown or str(p)
    try:
        st = os.lstat(p)
    except FileNotFoundError:
        return False
    except NotADirectoryError:
        raise OutputExistsError(f"{name}: a part of the path above it is a file, not a folder") from None
    except OSError as exc:
        raise OutputWriteError(p, exc) from None
    if stat.S_ISREG(st.st_mode):
        return True
    if stat.S_ISDIR(st.st_mode):
        raise OutputExistsError(f"{name} is a folder: give a file name for this output")
    if stat.S_ISLNK(st.st_mode):
        try:
            target = os.readlink(p)
        except OSError:  # pragma: no cover - raced away
            target = "?"
        raise OutputExistsError(f"{name} is a symbolic link (to {target}): outputs replace regular files only, even with "
                                "--force; give the path of a regular file itself, or another name")
    raise OutputExistsError(f"{name} is {_kind(st.st_mode)}, not a regular file: outputs replace regular files only, "
                            "even with --force; give a file name")


@dataclass(frozen=True)
class Output:
    """One output of a command, for :func:`check_outputs`.

    ``path`` as the user gave it; ``option`` names it in messages (``"--json"``); ``folder`` marks a
    folder the command writes files into (``--plots``, ``--fields``), as opposed to a file; ``replaces`` (a glob
    pattern) the files in that folder the command would replace when their names are not known up front
    (``--fields``: ``r*-p*.npz``).
    """

    path: str | Path
    option: str = ""
    folder: bool = False
    replaces: str = ""

    def name(self) -> str:
        """``--json y.json``, or the bare path when no option is known."""
        return f"{self.option} {self.path}" if self.option else str(self.path)


def check_outputs(paths: Iterable[str | Path | Output], force: bool, *, inputs: Iterable[str | Path | None] = ()) -> None:
    """Refuse up front (before any work) outputs that cannot or may not be written.

    ``paths`` are the outputs of one run: plain paths of files, or :class:`Output` (a file or a
    folder written into, with the option naming it); ``inputs`` the files the run reads (case file,
    data files, topographies), ``None`` entries ignored.

    Refused, with or without ``force``: an empty path; two outputs of one run that are the same file
    (the second would silently replace the first); an output inside (below) another file output, or
    a file output that is also an output folder of the run (the run would write the file, then fail
    on the folder, or the reverse); an output that is the same file as an input (it would replace
    the data it was computed from); a path that exists and is not a regular file (a folder, a
    symbolic link, a device such as ``/dev/null``, a named pipe, a socket: see
    :func:`check_replaceable`); a path below a file, or in a folder the user may not write into.
    Refused without ``force``: a path that exists as a regular file, and an output folder that holds files its
    ``replaces`` pattern matches.

    The path ``-`` (:data:`STDOUT`) of one file output means standard output: it is not a file and is
    not checked; two outputs to ``-``, or an output folder ``-``, are refused.
    """
    given = [p if isinstance(p, Output) else Output(p) for p in paths]
    for o in given:
        if str(o.path) == "":
            raise InputError(o.option or "output", "", f"is empty: give a {'folder' if o.folder else 'file'} name (or leave the option out)")
        if str(o.path) == STDOUT and o.folder:
            raise InputError(o.option or "output", STDOUT, "'-' (standard output) is for a file output; give a folder name")
        if not o.folder and str(o.path).endswith(("/", os.sep)):  # ("out/new/" was written as a file named "out/new")
            raise InputError(o.option or "output", str(o.path), "names a folder (it ends in '/'): give a file name")
    to_stdout = [o for o in given if str(o.path) == STDOUT]
    if len(to_stdout) > 1:
        raise InputError(to_stdout[1].option or "output", STDOUT,
                         f"only one output may go to standard output ('-'); {to_stdout[0].name()} already does")
    given = [o for o in given if str(o.path) != STDOUT]
    _check_collisions(given)
    _check_inputs(given, [Path(p) for p in inputs if p])
    existing: list[str] = []
    for o in given:
        if o.folder:
            problem = _output_folder_problem(Path(o.path))
            if problem:  # named as simulate names its folders: "--plots = 'afile': exists and is not a folder ..."
                raise OutputExistsError(f"{o.option} = {show_value(str(o.path))}: {problem}" if o.option
                                        else f"{o.path}: {problem}")
            if o.replaces and Path(o.path).is_dir():
                existing += sorted(str(p) for p in Path(o.path).glob(o.replaces))
            continue
        _check_folder(Path(o.path), o.name())  # named with the option: "cannot write --json y/x.json: y is not a folder"
        if check_replaceable(o.path, o.name()):  # "--json y.json is a folder ..."
            existing.append(str(o.path))
    if existing and not force:
        shown = ", ".join(existing[:5]) + (f" and {len(existing) - 5} more" if len(existing) > 5 else "")
        raise OutputExistsError(f"{shown} already exist{'s' if len(existing) == 1 else ''}; "
                                "pass --force to overwrite, or choose another name")


def _check_collisions(outputs: list[Output]) -> None:
    """Two outputs that are the same file, an output below a file output, a file output that is an output folder."""
    seen: dict[Path, Output] = {}
    for o in outputs:
        if o.folder:
            continue
        key = Path(o.path).resolve()
        if key in seen:
            raise OutputExistsError(f"{seen[key].name()} and {o.name()} are the same file: give each output its own name")
        seen[key] = o
    for f_key, f in seen.items():
        for o in outputs:
            key = Path(o.path).resolve()
            if o.folder and key == f_key:
                raise OutputExistsError(f"{f.name()} and {o.name()} are the same path: a file output cannot also be an "
                                        "output folder; give each its own name")
            if f_key in key.parents:
                raise OutputExistsError(f"{o.name()} would be inside {f.name()}, a file this run writes: give each output "
                                        "its own name")


def _check_inputs(outputs: list[Output], inputs: list[Path]) -> None:
    """No output is an input of the same run (same resolved path, or the same file through another name)."""
    for o in outputs:
        out = Path(o.path)
        for inp in inputs:
            try:
                same = out.resolve() == inp.resolve() or os.path.samefile(out, inp)
            except OSError:  # one of them does not exist (yet): not the same file
                same = False
            if same:
                raise OutputExistsError(f"{o.name()} is the input {inp}: a run may not write over what it reads, even "
                                        "with --force; give the output another name")


def _output_folder_problem(folder: Path) -> str:
    """Why ``folder`` cannot be an output folder (a folder, or one that can be made where the user may write), or ""."""
    try:
        if folder.is_dir():
            return "" if os.access(folder, os.W_OK | os.X_OK) else "no permission to write into that folder"
        if folder.exists() or folder.is_symlink():
            return "exists and is not a folder: give a folder name (it is made if missing)"
        existing, why = _writable_from(folder.parent)
    except OSError as exc:
        raise OutputWriteError(folder, exc) from None
    return f"cannot be made: {why}" if why else ""


def _check_folder(path: Path, shown: str = "") -> None:
    """The folder of ``path`` is (or will be created in) a folder the user may write into; ``shown`` names ``path`` in
    the messages (as :func:`check_replaceable`)."""
    try:
        existing, why = _writable_from(path.parent)
    except OSError as exc:
        raise OutputWriteError(path, exc) from None
    if why:
        where = f" (it is in the path of {path})" if existing != path.parent and not existing.is_dir() else ""
        raise OutputExistsError(f"cannot write {shown or path}: {why}{where}")


def _writable_from(folder: Path) -> tuple[Path, str]:
    """(``folder`` or the first of its parents that exists, why files cannot be made in ``folder`` from there: it is not
    a folder, or the user may not write into it; "" where they can)."""
    existing = next((d for d in (folder, *folder.parents) if d.exists()), Path("."))
    if not existing.is_dir():
        return existing, f"{existing} is not a folder"
    if not os.access(existing, os.W_OK | os.X_OK):
        return existing, f"no permission to write into the folder {existing}"
    # os.access answers for the permission bits: a superuser is told yes for /proc or /sys, where no file can be made,
    # and a read-only mount may pass; a file made and removed at once is the answer the run would meet at its end
    try:
        handle, probe = tempfile.mkstemp(prefix=".sealeak-probe-", dir=existing)
    except OSError as exc:
        return existing, f"no file can be made in the folder {existing} ({exc.strerror or exc})"
    os.close(handle)
    os.unlink(probe)
    return existing, ""


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


def write_files(contents: dict[str, str | bytes]) -> list[str]:
    """Write the outputs of one run all or none: ``contents`` maps paths to text (UTF-8) or bytes. Each file is first
    written in full to a temporary file beside it (its folder made where missing); only when every one is written are
    they renamed into place, one rename each. A failure before that (no permission, a full disk, a pseudo-filesystem
    that refuses files) removes the temporary files and the folders it made, and leaves every existing file as it
    was: raises :class:`OutputWriteError` naming the file. Returns the paths written, in order.
    """
    staged: list[tuple[Path, Path]] = []
    made: list[Path] = []
    target = Path(".")
    try:
        try:
            for path, content in contents.items():
                target = Path(path)
                check_replaceable(target)
                missing = [d for d in (target.parent, *target.parent.parents) if not d.exists()]
                target.parent.mkdir(parents=True, exist_ok=True)
                made += missing
                fd, tmp = tempfile.mkstemp(prefix=f".{target.name}.", suffix=".part", dir=target.parent)
                staged.append((Path(tmp), target))
                with os.fdopen(fd, "wb") as fh:
                    fh.write(content.encode("utf-8") if isinstance(content, str) else content)
                os.chmod(tmp, 0o666 & ~_umask())  # mkstemp makes 0600; give the usual permissions
            for tmp_path, target in staged:
                check_replaceable(target)  # something else may have appeared there meanwhile
            for tmp_path, target in staged:
                os.replace(tmp_path, target)
        except OSError as exc:
            raise OutputWriteError(target, exc) from None
    except BaseException:
        for tmp_path, _ in staged:
            tmp_path.unlink(missing_ok=True)
        for folder in sorted(set(made), key=lambda d: len(d.parts), reverse=True):  # deepest first; only what this call
            # made, and only if it stayed empty
            try:
                folder.rmdir()
            except OSError:
                pass
        raise
    return [str(p) for p in contents]


def write_output(path: str | Path, text: str) -> None:
    """An output of a command: ``text`` to standard output when ``path`` is :data:`STDOUT` (``-``), else
    :func:`write_text` (atomically, UTF-8)."""
    if str(path) == STDOUT:
        sys.stdout.write(text)
        sys.stdout.flush()
    else:
        write_text(path, text)
