"""``sealeak serve``: start the local web app (``docs/web.md``); needs the ``web`` extra."""

from __future__ import annotations

import argparse
from collections.abc import Callable

from ..errors import InputError, SealeakError

__all__ = ["register"]


def _size(text: str, option: str = "--max-upload") -> int:
    """``"200 MB"`` → 200000000 bytes (B, kB, MB, GB; kiB, MiB, GiB; a bare number is bytes)."""
    units = {"": 1, "b": 1, "kb": 10**3, "mb": 10**6, "gb": 10**9, "kib": 2**10, "mib": 2**20, "gib": 2**30}
    t = text.strip().lower().replace(" ", "")
    number = t.rstrip("bgikm")
    unit = t[len(number):]
    try:
        value = float(number)
    except ValueError:
        value = float("nan")
    if unit not in units or not value > 0 or value * units[unit] > 2**50:
        raise InputError(option, text, "must be a size > 0 such as '200 MB', '1 GB' or '500 kB'")
    return int(value * units[unit])


def _cmd_serve(args: argparse.Namespace) -> int:
    try:
        from ..web import WebConfig, serve
    except ImportError as exc:  # the web extra is not installed
        raise SealeakError(f"serve needs the web extra ({exc.name} is missing): pip install 'sealeak[web]'") from None

    if not 0 <= args.port <= 65535:
        raise InputError("--port", args.port, "must be a port number 0..65535")
    if not args.session_timeout > 0:
        shown = int(args.session_timeout) if args.session_timeout.is_integer() else args.session_timeout  # as typed: 0, not 0.0
        raise InputError("--session-timeout", shown, "must be > 0 (minutes)")
    for name in args.allow_host:
        if not name or any(c in name for c in "/:@ \t") and not name.startswith("["):
            raise InputError("--allow-host", name, "must be a host name or address, without port or path (e.g. myhost.lab)")
    config = WebConfig(max_upload=_size(args.max_upload), session_idle=60.0 * args.session_timeout,
                       session_quota=_size(args.session_quota, "--session-quota"),
                       server_quota=_size(args.server_quota, "--server-quota"), allow_hosts=tuple(args.allow_host))
    serve(args.host, args.port, config, quiet=args.quiet)
    return 0


def register(sub: argparse._SubParsersAction, add_case_args: Callable[[argparse.ArgumentParser], None]) -> None:
    """Add ``serve`` to the sub-command parsers."""
    p = sub.add_parser("serve", help="start the local web app (case form, surfaces, prediction, simulation) and its JSON API",
                       description="Start the local web app and its JSON API (docs/web.md) at http://HOST:PORT/; Ctrl-C "
                                   "stops it and removes every uploaded file. Needs the web extra: pip install 'sealeak[web]'.")
    p.add_argument("--host", default="127.0.0.1",
                   help="address to listen on (default 127.0.0.1: this machine only; 0.0.0.0: every network interface)")
    p.add_argument("--port", type=int, default=8765, help="port to listen on (default 8765)")
    p.add_argument("--max-upload", default="200 MB", metavar="SIZE",
                   help="largest request body, e.g. an uploaded topography file (default '200 MB')")
    p.add_argument("--session-quota", default="1 GB", metavar="SIZE",
                   help="most disk a browser session's files (uploads and simulation results) may take (default '1 GB')")
    p.add_argument("--server-quota", default="10 GB", metavar="SIZE",
                   help="most disk the files of all sessions together may take (default '10 GB')")
    p.add_argument("--allow-host", action="append", default=[], metavar="NAME",
                   help="a further host name the app answers to (repeatable; the Host header of every request must be "
                        "127.0.0.1, localhost, [::1], the --host or such a name)")
    p.add_argument("--session-timeout", type=float, default=240.0, metavar="MINUTES",
                   help="a browser session idle this long ends and its files are removed (default 240)")
    p.add_argument("-q", "--quiet", action="store_true", help="print nothing but errors")
    p.set_defaults(func=_cmd_serve)
