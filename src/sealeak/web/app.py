"""The web app: five pages (case, surface, prediction, simulation, help on every case-file key) and a JSON API, on FastAPI.

Pages are static HTML with a small script (``static/app.js``) and Plotly.js served from the
``plotly`` package (no network needed). The API runs cases through :mod:`sealeak.cases` and renders
with :mod:`sealeak.render`, the functions the command line uses, so ``POST /api/predict`` answers
with the bytes ``sealeak predict --json`` writes and ``POST /api/surface/analyze`` with those of
``sealeak surface analyze --json``. The routes are :mod:`sealeak.web.routes`, one router per job;
the schema of the API is served at ``/openapi.json`` (no Swagger page: it would load scripts from
the internet, which the pages' Content-Security-Policy refuses).

Errors are JSON: ``{"error": message, "field": "section.key", "message": "sealeak: error: ..."}``,
status 400 (the request is not a case or file at all), 413 (an upload over the limit) or 422 (a
value refused, with the command line's message; also a JSON member of another name or type). No
traceback or server path is ever sent: an unexpected error is logged on the server and answered
with a generic message. The limits and checks in front of every request (Host, Origin, body sizes,
headers) are :mod:`sealeak.web.security`'s.
"""

from __future__ import annotations

import contextlib
import logging
import shutil
import tempfile
import threading
from collections.abc import AsyncIterator, Awaitable, Callable
from pathlib import Path

from fastapi import FastAPI, Request
from fastapi.exceptions import RequestValidationError
from fastapi.responses import JSONResponse, Response
from fastapi.routing import APIRoute
from starlette.exceptions import HTTPException as StarletteHTTPException
from starlette.middleware.base import BaseHTTPMiddleware
from starlette.types import ASGIApp

from .._version import __version__
from ..cases.cancel import Cancelled
from ..errors import SealeakError
from .casework import PredictionCache
from .models import body_model, refusal
from .routes import ROUTERS
from .security import ROOT_PREFIX, Guard, allowed_hosts, remove_orphans, write_pid
from .sessions import COOKIE, SessionsFull, SessionStore
from .state import DEFAULT_MAX_UPLOAD, AppState, WebConfig, error_json, error_response

__all__ = ["WebConfig", "create_app", "DEFAULT_MAX_UPLOAD", "UPLOAD_PATHS"]

log = logging.getLogger("sealeak.web")

#: The paths that take multipart uploads (up to ``max_upload``); every other body is a case or JSON (``max_body``).
UPLOAD_PATHS = ("/api/uploads", "/api/surface/analyze", "/api/case/upload")


#: The paths whose routes use the session (the API and the downloads); the rest create none.
SESSION_PATHS = ("/api/", "/download/")


class _Sessions(BaseHTTPMiddleware):
    """Attach the request's :class:`Session` (a new one, with its cookie, when it has none)."""

    def __init__(self, app: ASGIApp, store: SessionStore) -> None:
        super().__init__(app)
        self.store = store

    async def dispatch(self, request: Request, call_next: Callable[[Request], Awaitable[Response]]) -> Response:
        """Find or create the session, run the request, set the cookie of a new session. Pages and static files need
        none: they create none (a browser gets its session with its first API call)."""
        session = self.store.get(request.cookies.get(COOKIE))
        if session is None and not request.url.path.startswith(SESSION_PATHS):
            return await call_next(request)
        new = session is None
        if session is None:
            try:
                session = self.store.create()
            except SessionsFull as exc:
                return error_json(str(exc), "", 503)
        request.state.session = session
        response = await call_next(request)
        if new:
            response.set_cookie(COOKIE, session.token, httponly=True, samesite="strict", path="/")
        return response


def _root(cfg: WebConfig) -> Path:
    """The folder of the sessions' folders: ``cfg.root``, or a new temporary one (the folders of servers that
    crashed are removed first, and the new one is marked with this server's process id)."""
    if cfg.root is not None:
        cfg.root.mkdir(parents=True, exist_ok=True)
        return cfg.root
    for orphan in remove_orphans(Path(tempfile.gettempdir())):
        log.info("removed %s, the folder of a server that no longer runs", orphan)
    root = Path(tempfile.mkdtemp(prefix=ROOT_PREFIX))
    write_pid(root)
    return root


def _lifespan(state: AppState, own_root: bool) -> Callable[[FastAPI], contextlib.AbstractAsyncContextManager[None]]:
    """While the app runs, a thread ends idle sessions; at shutdown every session ends (and an own root goes)."""
    stop = threading.Event()

    def reaper() -> None:
        while not stop.wait(min(60.0, max(state.config.session_idle / 4, 0.05))):
            state.sessions.expire()

    @contextlib.asynccontextmanager
    async def lifespan(_app: FastAPI) -> AsyncIterator[None]:
        thread = threading.Thread(target=reaper, name="sealeak-sessions", daemon=True)
        thread.start()
        try:
            yield
        finally:
            stop.set()
            state.sessions.close()
            if own_root:
                shutil.rmtree(state.root, ignore_errors=True)

    return lifespan


async def _sealeak_error(request: Request, exc: Exception) -> JSONResponse:
    assert isinstance(exc, SealeakError)
    return error_response(exc, getattr(request.state, "session", None), request.app.state.sealeak.root)


async def _bad_request(request: Request, exc: Exception) -> JSONResponse:
    """A JSON member of another name or type: 422 naming it (as a refused value); any other malformed request: 400."""
    assert isinstance(exc, RequestValidationError)
    errors = exc.errors()
    first = errors[0] if errors else {}
    route = request.scope.get("route")
    model = body_model(route.endpoint) if isinstance(route, APIRoute) else None
    refused = refusal(errors, model) if model is not None else None
    if refused is not None:
        return await _sealeak_error(request, refused)
    loc = first.get("loc", ())
    if first.get("type") == "json_invalid":  # loc ("body", position): the place in the text, not a field
        at = loc[1] if len(loc) > 1 else "?"
        why = first.get("ctx", {}).get("error", "malformed")
        return error_json(f"request body: not valid JSON at character {at} ({why})", "body", 400)
    if len(loc) == 1 and loc[0] == "body":  # the body as a whole: a list, a number, or text sent as another type
        return error_json("request body: must be a JSON object, sent with Content-Type: application/json (docs/web.md "
                          "lists each request's members)", "body", 400)
    where = ".".join(str(x) for x in loc[1:]) or "request"
    return error_json(f"{where}: {first.get('msg', 'malformed request')}", where, 400)


async def _http_error(request: Request, exc: Exception) -> JSONResponse:
    assert isinstance(exc, StarletteHTTPException)
    if exc.status_code == 400 and exc.detail == "There was an error parsing the body":  # FastAPI's words, without why
        return error_json("request body: not JSON that can be read (not UTF-8, or a number of thousands of digits)",
                          "body", 400)
    return error_json(str(exc.detail), getattr(exc, "field", ""), exc.status_code)


async def _cancelled(request: Request, exc: Exception) -> JSONResponse:
    """A computation stopped because its client has gone (sealeak.cases.cancel): nobody reads this answer."""
    return error_json("request stopped: its client disconnected before the answer was ready", "", 503)


async def _unexpected(request: Request, exc: Exception) -> JSONResponse:
    log.exception("unexpected error in %s %s", request.method, request.url.path)
    return error_json("internal error: the server could not answer this request (its log has the details)", "", 500)


def create_app(config: WebConfig | None = None) -> FastAPI:
    """The web app (an ASGI application; ``uvicorn`` serves it, ``sealeak serve`` starts that)."""
    cfg = config or WebConfig()
    root = _root(cfg)
    state = AppState(cfg, root, SessionStore(root, cfg.session_idle, cfg.max_sessions),
                     PredictionCache(max_bytes=cfg.cache_bytes, computing=cfg.max_predictions))
    app = FastAPI(title="sealeak", version=__version__, lifespan=_lifespan(state, own_root=cfg.root is None),
                  docs_url=None, redoc_url=None, openapi_url="/openapi.json",
                  description="The JSON API of `sealeak serve` (docs/web.md): the answers are the command line's.")
    app.state.sealeak = state
    app.state.sessions = state.sessions
    app.state.root = root
    app.add_middleware(_Sessions, store=state.sessions)
    app.add_middleware(Guard, hosts=allowed_hosts(cfg.host, cfg.allow_hosts), port=cfg.port,
                       any_address=cfg.host in ("0.0.0.0", "::", ""), max_body=cfg.max_body, max_upload=cfg.max_upload,
                       upload_paths=UPLOAD_PATHS)
    app.add_exception_handler(SealeakError, _sealeak_error)
    app.add_exception_handler(RequestValidationError, _bad_request)
    app.add_exception_handler(StarletteHTTPException, _http_error)
    app.add_exception_handler(Cancelled, _cancelled)
    app.add_exception_handler(Exception, _unexpected)
    for router in ROUTERS:
        app.include_router(router)
    return app
