"""Uploads streamed to disk: a multipart form read chunk by chunk, each file written into the session's folder.

Nothing of an upload is held in memory beyond one chunk of the request: every file part goes to a
temporary file in the session's ``incoming/`` folder as it arrives and is moved to ``uploads/``
under its upload name once the whole request has been read and checked (a refused or broken
request leaves nothing behind). The session's quota (the sum of the bytes of all its files: uploads and
simulation results) and the server's (the bytes of all sessions) are checked on the bytes written, so a
request over either stops at once with 413.
"""

from __future__ import annotations

import math
import secrets
import threading
import zipfile
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import IO, Any, BinaryIO

from python_multipart import MultipartParser
from python_multipart.exceptions import FormParserError
from python_multipart.multipart import parse_options_header
from starlette.exceptions import HTTPException
from starlette.requests import Request

from ..topography import npy_header
from .casework import upload_name
from .security import BodyTooLarge

__all__ = ["Form", "Quota", "DiskLedger", "read_form", "folder_bytes", "check_expansion"]

#: The most file parts and text fields a form may have, and the most bytes of all its text fields.
MAX_PARTS = 64
MAX_FIELD_BYTES = 64 * 1024


@dataclass
class Form:
    """A parsed form: its text fields (the first value of each name), its files (field, safe upload name,
    temporary path), and the name each file was uploaded as (safe name → given name, for display only)."""

    fields: dict[str, str] = field(default_factory=dict)
    files: list[tuple[str, str, Path]] = field(default_factory=list)
    given: dict[str, str] = field(default_factory=dict)

    def discard(self) -> None:
        """Remove the temporary files (those not moved elsewhere)."""
        for _field, _name, path in self.files:
            path.unlink(missing_ok=True)


def folder_bytes(folder: Path, part: Path | None = None) -> tuple[int, int]:
    """The bytes of the files in ``folder`` and its sub-folders, and of those inside its sub-folder ``part``,
    in one walk ((0, 0) where a folder does not exist)."""
    total = inside = 0
    if folder.is_dir():
        for p in folder.rglob("*"):
            if p.is_file() and not p.is_symlink():
                size = p.stat().st_size
                total += size
                inside += size if part is not None and p.is_relative_to(part) else 0
    return total, inside


@dataclass(frozen=True)
class Quota:
    """A disk limit: at most ``limit`` bytes, ``used`` taken already; ``what`` words it in a refusal
    (``"the session's files would take more than its quota of 1000 MB (sealeak serve --session-quota)"``);
    ``session``: the session whose files it limits (its token), None for the files of all sessions."""

    limit: int
    used: int
    what: str
    session: str | None = None

    def left(self) -> int:
        """Bytes still free (may be negative)."""
        return self.limit - self.used


class DiskLedger:
    """The bytes uploads of one server are writing, so that uploads running at once count each other's bytes.

    A quota's ``used`` is a reading of the disk when its request began; an upload running beside it writes bytes
    that reading does not hold. Each request takes a ticket (:meth:`begin`) before reading the disk and reserves
    every chunk here before writing it (:meth:`reserve`): the chunks of the other requests still running, and of
    those that ended after this one began (their files may be missing from its reading), count against its quotas.
    A file being written can so be counted twice, which refuses early, never late.
    """

    def __init__(self) -> None:
        self._lock = threading.Lock()
        self._clock = 0
        self._live: dict[int, list[Any]] = {}  # ticket → [session, bytes reserved, clock at begin]
        self._ended: list[tuple[int, str, int]] = []  # (clock at end, session, bytes) of requests that ended

    def begin(self, session: str) -> int:
        """A ticket for a request of ``session`` (before its quotas read the disk)."""
        with self._lock:
            self._clock += 1
            self._live[self._clock] = [session, 0, self._clock]
            return self._clock

    def reserve(self, ticket: int, nbytes: int, quotas: Sequence[Quota]) -> Quota | None:
        """Reserve ``nbytes`` more for ``ticket``, or the first of ``quotas`` they would exceed (nothing reserved)."""
        with self._lock:
            session, mine, began = self._live[ticket]
            others = [(s, b) for t, (s, b, _) in self._live.items() if t != ticket]
            others += [(s, b) for end, s, b in self._ended if end > began]
            for q in quotas:
                pending = sum(b for s, b in others if q.session is None or s == q.session)
                if q.used + pending + mine + nbytes > q.limit:
                    return q
            self._live[ticket][1] = mine + nbytes
            return None

    def end(self, ticket: int) -> None:
        """The request of ``ticket`` has ended (its files are on disk, or removed)."""
        with self._lock:
            session, mine, _ = self._live.pop(ticket)
            self._clock += 1
            self._ended.append((self._clock, session, mine))
            oldest = min((began for _, _, began in self._live.values()), default=self._clock + 1)
            self._ended = [e for e in self._ended if e[0] > oldest]  # no request running began before these


async def read_form(request: Request, incoming: Path, *, file_limit: int, quotas: Sequence[Quota],
                    ledger: DiskLedger, ticket: int) -> Form:
    """Parse the multipart body of ``request``, writing each file into ``incoming`` as it streams in.

    ``file_limit``: the most bytes one file may have; ``quotas``: the disk limits the files count
    against (the session's, the server's), each chunk reserved in ``ledger`` under ``ticket`` (its
    :meth:`DiskLedger.begin`). Over any: :class:`BodyTooLarge` (413), the files written
    so far removed. Not a multipart form: 400.
    """
    kind, options = parse_options_header(request.headers.get("content-type", ""))
    if kind != b"multipart/form-data" or b"boundary" not in options:
        raise HTTPException(400, "request: not a multipart form (send the files as multipart/form-data)")
    form = Form()
    part = _Part()
    pending = [b"", b""]  # the header name and value being read
    field_bytes = 0

    def on_part_begin() -> None:
        nonlocal part
        part = _Part()

    def on_header_field(data: bytes, start: int, end: int) -> None:
        pending[0] += data[start:end]

    def on_header_value(data: bytes, start: int, end: int) -> None:
        pending[1] += data[start:end]

    def on_header_end() -> None:
        part.headers.append((pending[0].lower(), pending[1]))
        pending[0] = pending[1] = b""

    def on_headers_finished() -> None:
        disposition = next((v for k, v in part.headers if k == b"content-disposition"), b"")
        _kind, opts = parse_options_header(disposition)
        if len(form.files) + len(form.fields) >= MAX_PARTS:
            raise HTTPException(400, f"request: more than {MAX_PARTS} files and fields in one form")
        part.name = opts.get(b"name", b"").decode("utf-8", "replace")
        if b"filename" in opts:
            given = opts[b"filename"].decode("utf-8", "replace").replace("\\", "/").rsplit("/", 1)[-1]
            name = upload_name(given)
            form.given[name] = given
            incoming.mkdir(parents=True, exist_ok=True)
            path = incoming / f"{secrets.token_hex(8)}.part"
            form.files.append((part.name, name, path))
            part.file = open(path, "wb")  # noqa: SIM115 - closed in on_part_end, or on an error
            opened.append(part.file)

    def on_part_data(data: bytes, start: int, end: int) -> None:
        nonlocal field_bytes
        chunk = data[start:end]
        if part.file is None:
            field_bytes += len(chunk)
            if field_bytes > MAX_FIELD_BYTES:
                raise HTTPException(400, f"request: the form's text fields hold more than {MAX_FIELD_BYTES // 1024} kB")
            part.text += chunk
            return
        part.size += len(chunk)
        if part.size > file_limit:
            raise BodyTooLarge(f"upload: {form.files[-1][1]} is larger than the server's limit of {file_limit / 1e6:.6g} MB "
                               "for this kind of file")
        over = ledger.reserve(ticket, len(chunk), quotas)
        if over is not None:
            raise BodyTooLarge(f"upload: {over.what}")
        part.file.write(chunk)

    def on_part_end() -> None:
        if part.file is not None:
            part.file.close()
        else:
            form.fields.setdefault(part.name, part.text.decode("utf-8", "replace"))

    opened: list[BinaryIO] = []
    parser = MultipartParser(options[b"boundary"], {
        "on_part_begin": on_part_begin, "on_header_field": on_header_field, "on_header_value": on_header_value,
        "on_header_end": on_header_end, "on_headers_finished": on_headers_finished, "on_part_data": on_part_data,
        "on_part_end": on_part_end})
    try:
        async for chunk in request.stream():
            parser.write(chunk)
        parser.finalize()
    except BaseException as exc:
        for f in opened:
            f.close()
        form.discard()
        if isinstance(exc, FormParserError):
            raise HTTPException(400, "request: malformed multipart form") from None
        raise
    return form


@dataclass
class _Part:
    """The part of a form being read: its headers, field name, and its file or text."""

    headers: list[tuple[bytes, bytes]] = field(default_factory=list)
    name: str = ""
    file: BinaryIO | None = None
    size: int = 0
    text: bytearray = field(default_factory=bytearray)


def check_expansion(path: Path, name: str, limit: int) -> None:
    """Refuse (413) an uploaded archive that expands past ``limit`` bytes, before anything reads it.

    A zip archive (``.npz``; instrument formats such as ``.x3p``) counts the sizes its members declare
    (reading a member stops there) and, for each ``.npy`` member, the bytes its header's shape and
    type need; a ``.npy`` file (by its magic bytes) counts its header's. A damaged file is left to the reader's message.
    """
    try:
        if zipfile.is_zipfile(path):
            with zipfile.ZipFile(path) as z:
                members = z.infolist()
                size = sum(m.file_size for m in members)
                for m in members:
                    if m.filename.endswith(".npy") and size <= limit:
                        with z.open(m) as f:
                            size = max(size, _npy_bytes(f))
        else:
            with open(path, "rb") as f:
                if f.read(6) != b"\x93NUMPY":
                    return
                f.seek(0)
                size = _npy_bytes(f)
    except (zipfile.BadZipFile, ValueError, OSError, EOFError, NotImplementedError, RuntimeError):
        return
    if size > limit:
        raise BodyTooLarge(f"upload: {name} expands to {size / 1e6:.6g} MB, more than the server's limit of "
                           f"{limit / 1e6:.6g} MB (sealeak serve --max-upload)")


def _npy_bytes(f: IO[bytes]) -> int:
    """The bytes of the array a ``.npy`` stream's header declares."""
    shape, dtype = npy_header(f)
    return math.prod(shape) * dtype.itemsize
