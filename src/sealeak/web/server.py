"""Serving the web app with uvicorn (``sealeak serve``)."""

from __future__ import annotations

import asyncio
import errno
import socket
import sys
from dataclasses import replace

import uvicorn
from uvicorn.protocols.http.h11_impl import H11Protocol

from ..errors import InputError
from .app import WebConfig, create_app

__all__ = ["serve", "listen", "HEAD_TIMEOUT", "SHUTDOWN_WAIT"]

#: Seconds a new connection may take to send the head (request line and headers) of its first request.
HEAD_TIMEOUT = 30.0
#: Seconds Ctrl-C waits for requests being answered before it stops the server anyway.
SHUTDOWN_WAIT = 5


class _Protocol(H11Protocol):
    """uvicorn's HTTP/1.1 protocol with a deadline for a connection's first request head: a connection that sends
    its headers a byte at a time, or nothing (slowloris), is closed after :data:`HEAD_TIMEOUT` s, where uvicorn
    would keep it, and its file descriptor, for ever. (Later requests on a kept-alive connection have uvicorn's own
    keep-alive timeout; a body that stalls, :data:`~sealeak.web.security.BODY_IDLE`.)"""

    def connection_made(self, transport: asyncio.Transport) -> None:  # type: ignore[override]
        super().connection_made(transport)
        self._head_deadline = self.loop.call_later(HEAD_TIMEOUT, self._head_late)

    def _head_late(self) -> None:
        if self.cycle is None and not self.transport.is_closing():  # no request head came
            self.transport.close()

    def connection_lost(self, exc: Exception | None) -> None:
        self._head_deadline.cancel()
        super().connection_lost(exc)


def listen(host: str, port: int) -> socket.socket:
    """A socket bound to ``host:port`` (port 0: a free one), or an InputError naming ``--host`` or ``--port``."""
    try:
        infos = socket.getaddrinfo(host, port, type=socket.SOCK_STREAM, flags=socket.AI_PASSIVE)
    except socket.gaierror:
        raise InputError("--host", host, "is not a name or address this machine can listen on") from None
    family, kind, proto, _name, address = infos[0]
    sock = socket.socket(family, kind, proto)
    sock.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
    try:
        sock.bind(address)
    except OSError as exc:
        sock.close()
        if exc.errno == errno.EADDRINUSE:
            raise InputError("--port", port, f"is in use on {host} (another server?): choose another port") from None
        if exc.errno == errno.EACCES:
            raise InputError("--port", port, "needs privileges on this machine: choose a port above 1023") from None
        raise InputError("--host", host, f"cannot listen there: {exc.strerror or exc}") from None
    sock.listen(2048)  # connections wait in the backlog until uvicorn serves them: the printed address answers at once
    return sock


def serve(host: str = "127.0.0.1", port: int = 8765, config: WebConfig | None = None, quiet: bool = False) -> None:
    """Serve the app on ``host:port`` until interrupted (Ctrl-C); prints the address first.

    The socket is bound before anything is printed, so a port in use is one line naming ``--port``.
    The app answers only to requests naming ``host`` (or a loopback name) at this port in their Host
    header (``config.allow_hosts`` adds names; :mod:`sealeak.web.security`).
    """
    sock = listen(host, port)
    port = sock.getsockname()[1]
    app = create_app(replace(config or WebConfig(), host=host, port=port))  # the Host names it answers to
    shown = f"[{host}]" if ":" in host else host
    if not quiet:
        print(f"sealeak: serving the web app at http://{shown}:{port}/ (Ctrl-C stops it)", file=sys.stderr, flush=True)
        if host not in ("127.0.0.1", "localhost", "::1"):
            print(f"sealeak: note: listening on {host}: anyone who can reach this machine can use the app "
                  "(there is no login)", file=sys.stderr, flush=True)
    server = uvicorn.Server(uvicorn.Config(app, log_level="warning", access_log=False, server_header=False, http=_Protocol,
                                           timeout_graceful_shutdown=SHUTDOWN_WAIT))
    try:
        server.run(sockets=[sock])
    except KeyboardInterrupt:  # uvicorn has shut down (sessions ended, files removed) and re-raises the Ctrl-C
        pass
    finally:
        sock.close()
    if not quiet:
        print("sealeak: stopped; the sessions' files were removed", file=sys.stderr, flush=True)
