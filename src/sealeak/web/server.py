"""Serving the web app with uvicorn (``sealeak serve``)."""

from __future__ import annotations

import sys

import uvicorn

from .app import WebConfig, create_app

__all__ = ["serve"]


def serve(host: str = "127.0.0.1", port: int = 8765, config: WebConfig | None = None, quiet: bool = False) -> None:
    """Serve the app on ``host:port`` until interrupted (Ctrl-C); prints the address first."""
    app = create_app(config)
    shown = f"[{host}]" if ":" in host else host
    if not quiet:
        print(f"sealeak: serving the web app at http://{shown}:{port}/ (Ctrl-C stops it)", file=sys.stderr, flush=True)
        if host not in ("127.0.0.1", "localhost", "::1"):
            print(f"sealeak: note: listening on {host}: anyone who can reach this machine can use the app "
                  "(there is no login)", file=sys.stderr, flush=True)
    uvicorn.run(app, host=host, port=port, log_level="warning", access_log=False, server_header=False)
