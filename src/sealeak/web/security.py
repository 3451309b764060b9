"""The web server's guard: request-body limits, Host and Origin checks, security headers, orphan folders.

:class:`Guard` is ASGI middleware in front of the whole app (``docs/web.md``, "Safety"):

* **Host.** A request whose ``Host`` is not a name the server answers to (:func:`allowed_hosts`:
  127.0.0.1, localhost, [::1] and the ``--host`` given, at the server's port) gets 421: a page of
  another site whose name was made to point at 127.0.0.1 (DNS rebinding) cannot reach the app.
* **Origin.** A state-changing request (POST, PUT, PATCH, DELETE) whose ``Origin`` (or, without
  one, ``Referer``) is not the server's own gets 403. Programs (curl, scripts) send neither and
  are served; browsers send ``Origin`` with every such request.
* **Bodies** are counted on the bytes actually read, never on ``Content-Length`` alone:
  ``Content-Length`` together with ``Transfer-Encoding`` gets 400, a body over its limit 413. A
  JSON or case body (anything but a multipart upload) may hold ``max_body`` bytes and is checked
  for nesting (:func:`check_nesting`) before any parser sees it; an upload may hold ``max_upload``
  bytes and streams through (:mod:`sealeak.web.uploads` writes it to disk as it arrives).
* **Headers.** Every answer carries ``X-Content-Type-Options: nosniff``, ``X-Frame-Options: DENY``,
  ``Referrer-Policy: same-origin`` and a ``Content-Security-Policy`` allowing only the app's own
  scripts, styles, images and requests (the pages' inline event handlers by their hashes).

:func:`remove_orphans` removes the temporary folders of servers that are no longer running.
"""

from __future__ import annotations

import asyncio
import base64
import hashlib
import ipaddress
import json
import os
import re
import shutil
import socket
import threading
from collections.abc import Iterable
from concurrent.futures import ThreadPoolExecutor
from importlib import resources
from pathlib import Path

import numpy as np
from starlette.datastructures import Headers
from starlette.exceptions import HTTPException
from starlette.responses import JSONResponse
from starlette.types import ASGIApp, Message, Receive, Scope, Send

from ..cases.cancel import cancellable
from ..io.tomlscan import MAX_DEPTH, MAX_KEY_PARTS

__all__ = ["Guard", "BodyTooLarge", "BodyStalled", "BODY_IDLE", "DEFAULT_MAX_BODY", "MAX_NESTING", "MAX_KEY_PARTS", "check_nesting",
           "check_text", "allowed_hosts", "content_security_policy", "remove_orphans", "write_pid", "PID_FILE", "ROOT_PREFIX"]

#: The largest JSON or case-file request body (bytes): 2 MB.
DEFAULT_MAX_BODY = 2 * 10**6
#: The deepest nesting of ``[ ]`` and ``{ }`` a JSON or TOML text may have, and the most parts of a dotted TOML
#: key: the case loader's limits (:mod:`sealeak.io.tomlscan`), so a body is refused here as a file is there.
MAX_NESTING = MAX_DEPTH
#: The prefix of a server's temporary folder, and the file in it that names the server's process.
ROOT_PREFIX = "sealeak-web-"
PID_FILE = "server.pid"

#: Seconds a request body may pause between two of its parts before it is refused (408): a body shorter than its
#: Content-Length, or sent a few bytes a minute, would hold its connection and request open for ever.
BODY_IDLE = 30.0
#: The threads that check bodies' nesting (:func:`check_nesting`).
_SCANS = ThreadPoolExecutor(max_workers=2, thread_name_prefix="sealeak-scan")
_UNSAFE = frozenset({"POST", "PUT", "PATCH", "DELETE"})
_LOOPBACK = ("127.0.0.1", "localhost", "::1")
_WILDCARD = ("0.0.0.0", "::", "")
#: Quoted strings (TOML's multi-line ones first: they may hold brackets and newlines) and comments, blanked before counting.
_STRINGS = re.compile(rb'"""(?:[^\\]|\\[\s\S])*?"""|\'\'\'[\s\S]*?\'\'\'|"(?:[^"\\\n]|\\.)*"|\'[^\'\n]*\'|#[^\n]*')
_DOTTED = re.compile(rb'(?<![\w-])(?:(?:[\w-]++|"")[ \t]*+\.[ \t]*+){%d}' % MAX_KEY_PARTS)
_HANDLER = re.compile(r'\son[a-z]+="([^"]*)"')
_INLINE_SCRIPT = re.compile(r"<script>(.*?)</script>", re.S)


class BodyTooLarge(HTTPException):
    """A request body (or a session's uploads) over the server's limit: status 413, its message names the limit."""

    def __init__(self, message: str, field: str = "upload") -> None:
        super().__init__(413, message)
        self.field = field


def _refusal(status: int, message: str, field: str = "") -> JSONResponse:
    return JSONResponse({"error": message, "field": field, "message": f"sealeak: error: {message}"}, status_code=status)


def check_nesting(data: bytes) -> str | None:
    """Why ``data`` (JSON or TOML text) is refused before parsing (``"is nested 40 levels deep ..."``), or None.

    ``[ ]`` and ``{ }`` may nest :data:`MAX_NESTING` deep and a dotted key have :data:`MAX_KEY_PARTS`
    parts (outside quoted strings and comments): deeper structures make Python's parsers recurse
    (RecursionError) and long dotted keys cost TOML parsing time and memory growing with their square.
    """
    bare = _STRINGS.sub(b'""', data)
    codes = np.frombuffer(bare, dtype=np.uint8)
    step = np.isin(codes, (ord("["), ord("{"))).astype(np.int32) - np.isin(codes, (ord("]"), ord("}")))
    depth = int(np.cumsum(step).max()) if step.size else 0
    if depth > MAX_NESTING:
        return f"is nested {depth} levels deep ([ ] and {{ }}): at most {MAX_NESTING} levels are allowed"
    if _DOTTED.search(bare):
        return f"has a dotted key of more than {MAX_KEY_PARTS} parts: at most {MAX_KEY_PARTS} are allowed"
    return None


def check_text(data: bytes) -> str | None:
    """Why a request body is refused before any parser sees it (:func:`check_nesting`, then a JSON text holding a lone
    surrogate escape such as ``"\\ud800"``), or None.

    JSON may write half of a UTF-16 surrogate pair as an escape; the string it gives is no Unicode text, and every
    answer that later held it (the case's TOML, an error message) failed to encode: a session answered 500 to every
    request until it expired. A body that is not JSON is left to its parser.
    """
    why = check_nesting(data)
    if why is not None or b"\\u" not in data:
        return why
    try:
        doc = json.loads(data)
    except ValueError:  # not JSON (a case file), or malformed: its parser answers
        return None
    stack = [doc]
    while stack:  # (nested MAX_NESTING deep at most, checked above)
        item = stack.pop()
        if isinstance(item, str):
            try:
                item.encode("utf-8")
            except UnicodeEncodeError as exc:
                return (f"holds a lone surrogate escape (\\u{ord(item[exc.start]):04x}), which is no character: send the "
                        "text as UTF-8, or a character outside the BMP as a pair of escapes")
        elif isinstance(item, dict):
            stack += [*item.keys(), *item.values()]
        elif isinstance(item, list):
            stack += item
    return None


def allowed_hosts(host: str, extra: Iterable[str] = ()) -> frozenset[str]:
    """The host names (lower case, IPv6 without brackets) a server listening on ``host`` answers to.

    Always the loopback names (127.0.0.1, localhost, ::1), ``host`` itself and the ``extra`` names;
    listening on every interface (0.0.0.0, ::) adds this machine's name and fully qualified name
    (an address typed as such is accepted there too: see :class:`Guard`).
    """
    names = {*_LOOPBACK, host, *extra}
    if host in _WILDCARD:
        names |= {socket.gethostname(), socket.getfqdn()}
    return frozenset(n.strip("[]").rstrip(".").lower() for n in names if n not in _WILDCARD)


def _split_host(value: str) -> tuple[str, int | None] | None:
    """``"name:port"`` or ``"[::1]:port"`` → (name in lower case, port or None); None when malformed."""
    m = re.fullmatch(r"(\[[0-9A-Fa-f:.]+\]|[^\[\]:/@\s]+)(?::(\d{1,5}))?", value)
    if m is None:
        return None
    return m.group(1).strip("[]").rstrip(".").lower(), int(m.group(2)) if m.group(2) else None


def _origin_of(url: str) -> str:
    """``scheme://host[:port]`` of a URL in lower case ('' when it has none, e.g. ``null``)."""
    m = re.match(r"[A-Za-z][A-Za-z0-9+.-]*://[^/?#]*", url)
    return m.group(0).lower() if m else ""


def _is_address(name: str) -> bool:
    try:
        ipaddress.ip_address(name)
    except ValueError:
        return False
    return True


def content_security_policy() -> str:
    """The pages' Content-Security-Policy: everything from the app itself; inline event handlers by hash."""
    static = resources.files("sealeak") / "web" / "static"
    inline = set()
    for page in static.iterdir():
        if page.name.endswith(".html"):
            text = page.read_text(encoding="utf-8")
            inline |= set(_HANDLER.findall(text)) | set(_INLINE_SCRIPT.findall(text))
    hashes = " ".join(sorted(f"'sha256-{base64.b64encode(hashlib.sha256(s.encode()).digest()).decode()}'" for s in inline))
    script = f"script-src 'self' 'unsafe-hashes' {hashes}" if hashes else "script-src 'self'"
    return (f"default-src 'self'; {script}; style-src 'self' 'unsafe-inline'; img-src 'self' data: blob:; "
            "connect-src 'self'; font-src 'self' data:; object-src 'none'; base-uri 'none'; form-action 'self'; "
            "frame-ancestors 'none'")


class Guard:
    """ASGI middleware: Host and Origin checks, body limits counted on the bytes read, security headers.

    ``hosts``: the names the server answers to (:func:`allowed_hosts`); ``any_address``: an IP
    address as Host is accepted too (a server listening on every interface); ``port``: the port Host
    must name (None: any, for an app not yet bound to a socket). ``max_body``: the limit of a JSON
    or case body (bytes); ``max_upload``: the limit of a multipart upload to one of ``upload_paths``
    (any other body is a JSON or case body).
    """

    def __init__(self, app: ASGIApp, *, hosts: frozenset[str], port: int | None, any_address: bool,
                 max_body: int, max_upload: int, upload_paths: Iterable[str]) -> None:
        self.app = app
        self.hosts = hosts
        self.port = port
        self.any_address = any_address
        self.max_body = max_body
        self.max_upload = max_upload
        self.upload_paths = frozenset(upload_paths)
        self.headers = [(b"x-content-type-options", b"nosniff"), (b"x-frame-options", b"DENY"),
                        (b"referrer-policy", b"same-origin"), (b"cross-origin-resource-policy", b"same-origin"),
                        (b"content-security-policy", content_security_policy().encode())]

    async def __call__(self, scope: Scope, receive: Receive, send: Send) -> None:
        """Check the request, then run the app with its body counted and the security headers added."""
        if scope["type"] != "http":
            await self.app(scope, receive, send)
            return

        started = False

        async def send_headers(message: Message) -> None:
            nonlocal started
            if message["type"] == "http.response.start":
                started = True
                present = {k.lower() for k, _ in message.get("headers", [])}
                message["headers"] = [*message.get("headers", []), *[h for h in self.headers if h[0] not in present]]
            await send(message)

        headers = Headers(scope=scope)
        refusal = self._refusal(scope, headers)
        if refusal is not None:
            await refusal(scope, receive, send_headers)
            return
        multipart = scope["path"] in self.upload_paths and headers.get("content-type", "").lower().startswith("multipart/")
        limit = self.max_upload if multipart else min(self.max_body, self.max_upload)
        length = headers.get("content-length")
        if length is not None and (len(length) > 15 or int(length) > limit):
            await _refusal(413, _limit_message(limit, multipart), "upload" if multipart else "body")(scope, receive, send_headers)
            return
        if multipart:  # streamed on: the app's parser writes it to disk as it comes
            counted = _Counted(receive, limit, multipart)
            try:
                await self.app(scope, counted, send_headers)
            except BaseException:  # the limit, raised inside the app's task groups, comes back wrapped
                if counted.over is None or started:
                    raise
                await _refusal(counted.over.status_code, str(counted.over.detail), counted.over.field)(scope, receive, send_headers)
            return
        buffer = bytearray()  # a JSON or case body: read here (it is small), checked, handed on
        counted = _Counted(receive, limit, multipart)
        while True:
            try:
                message = await counted()
            except (BodyTooLarge, BodyStalled) as exc:
                await _refusal(exc.status_code, str(exc.detail), exc.field)(scope, receive, send_headers)
                return
            if message["type"] != "http.request":
                break
            buffer += message.get("body", b"")
            if not message.get("more_body", False):
                break
        body = bytes(buffer)
        # ~0.2 s for 2 MB: off the event loop, and on threads of its own (not those computing predictions)
        why = await asyncio.get_running_loop().run_in_executor(_SCANS, check_text, body) if body else None
        if why is not None:
            await _refusal(400, f"request body {why}", "body")(scope, receive, send_headers)
            return
        sent = False
        # after the body the server has only one message left to give, http.disconnect: awaited from the start, it
        # tells the request's computations that their client has gone (sealeak.cases.cancel), and is the answer to
        # every later receive of the app's
        left = threading.Event()

        async def watch() -> Message:
            message = await receive()
            left.set()
            return message

        watcher = asyncio.ensure_future(watch())

        async def replay() -> Message:
            nonlocal sent
            if not sent:
                sent = True
                return {"type": "http.request", "body": body, "more_body": False}
            return await asyncio.shield(watcher)

        try:
            with cancellable(left.is_set):
                await self.app(scope, replay, send_headers)
        finally:
            watcher.cancel()

    def _refusal(self, scope: Scope, headers: Headers) -> JSONResponse | None:
        """The answer to a request refused by its headers (Host, Origin, lengths), or None."""
        raw_host = headers.get("host", "")
        host = _split_host(raw_host)
        if host is None:
            return _refusal(400, f"Host '{raw_host}': not a host name", "host")
        name, port = host
        if (name not in self.hosts and not (self.any_address and _is_address(name))) or \
                (self.port is not None and (port or 80) != self.port):
            return _refusal(421, f"Host '{raw_host}': this server answers only to {', '.join(sorted(self.hosts))} "
                                 "at its own port (sealeak serve --allow-host NAME adds a name)", "host")
        if scope["method"] in _UNSAFE:
            for name in ("origin", "referer"):  # (a second one would go unchecked: the first alone is read)
                if len(headers.getlist(name)) > 1:
                    return _refusal(400, f"{name.capitalize()} given {len(headers.getlist(name))} times: send it once",
                                    "origin")
            own = f"{scope.get('scheme', 'http')}://{raw_host}".lower()
            origin, referer = headers.get("origin"), headers.get("referer")
            given = origin if origin is not None else referer
            if given is not None and _origin_of(given) != own:
                return _refusal(403, f"{'Origin' if origin is not None else 'Referer'} '{given}': a request that "
                                     "changes a session must come from the app's own pages", "origin")
        if "transfer-encoding" in headers and "content-length" in headers:
            return _refusal(400, "Content-Length and Transfer-Encoding together: send one of them", "body")
        length = headers.get("content-length")
        if length is not None and not length.isdigit():
            return _refusal(400, f"Content-Length '{length}': not a number of bytes", "body")
        return None


def _limit_message(limit: int, multipart: bool) -> str:
    if multipart:
        return f"upload: larger than the server's limit of {limit / 1e6:.6g} MB (sealeak serve --max-upload)"
    return f"request body: larger than the server's limit of {limit / 1e6:.6g} MB for a case file or a JSON request"


class BodyStalled(HTTPException):
    """A request body whose next bytes did not come within :data:`BODY_IDLE` seconds: status 408."""

    def __init__(self) -> None:
        super().__init__(408, f"request body: no bytes for {BODY_IDLE:.0f} s (a body shorter than its Content-Length, "
                              "or a stalled connection): send it again")
        self.field = "body"


class _Counted:
    """``receive`` that raises :class:`BodyTooLarge` (kept as ``over``) as soon as the bytes read pass ``limit``, and
    :class:`BodyStalled` (kept as ``over`` too) when the next part of the body takes more than :data:`BODY_IDLE` s."""

    def __init__(self, receive: Receive, limit: int, multipart: bool) -> None:
        self.receive = receive
        self.limit = limit
        self.multipart = multipart
        self.seen = 0
        self.over: BodyTooLarge | BodyStalled | None = None

    async def __call__(self) -> Message:
        """The next message of the request, its body counted."""
        try:
            message = await asyncio.wait_for(self.receive(), BODY_IDLE)
        except TimeoutError:
            self.over = BodyStalled()
            raise self.over from None
        if message["type"] == "http.request":
            self.seen += len(message.get("body", b""))
            if self.seen > self.limit:
                self.over = BodyTooLarge(_limit_message(self.limit, self.multipart), "upload" if self.multipart else "body")
                raise self.over
        return message


def write_pid(root: Path) -> None:
    """Name this process in ``root`` (a server's temporary folder), so that a later server knows whether it still runs."""
    (root / PID_FILE).write_text(f"{os.getpid()}\n", encoding="ascii")


def _alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:  # a process of another user
        return True
    return True


def remove_orphans(parent: Path) -> list[Path]:
    """Remove the ``sealeak-web-*`` folders in ``parent`` left by servers that no longer run; return them.

    A folder goes when the process its :data:`PID_FILE` names is gone. A folder without that file
    (a server of an older version, which may still run) and the folders of other users are left alone.
    """
    gone = []
    for folder in parent.glob(f"{ROOT_PREFIX}*"):
        try:
            if not folder.is_dir() or folder.is_symlink() or folder.stat().st_uid != os.getuid():
                continue
            text = (folder / PID_FILE).read_text(encoding="ascii").strip() if (folder / PID_FILE).is_file() else ""
        except OSError:
            continue
        if text.isdigit() and not _alive(int(text)):
            shutil.rmtree(folder, ignore_errors=True)
            gone.append(folder)
    return gone
