"""Serving the web app with uvicorn (``sealeak serve``)."""

from __future__ import annotations

import errno
import socket
import sys
from dataclasses import replace

import uvicorn

from ..errors import InputError
from .app import WebConfig, create_app

__all__ = ["serve", "listen"]


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
    server = uvicorn.Server(uvicorn.Config(app, log_level="warning", access_log=False, server_header=False))
    try:
        server.run(sockets=[sock])
    except KeyboardInterrupt:  # uvicorn has shut down (sessions ended, files removed) and re-raises the Ctrl-C
        pass
    finally:
        sock.close()
    if not quiet:
        print("sealeak: stopped; the sessions' files were removed", file=sys.stderr, flush=True)
