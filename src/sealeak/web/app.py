"""The web app: five pages (case, surface, prediction, simulation, help on every case-file key) and a JSON API, on FastAPI.

Pages are static HTML with a small script (``static/app.js``) and Plotly.js served from the
``plotly`` package (no network needed). The API runs cases through :mod:`sealeak.cases` and renders
with :mod:`sealeak.render`, the functions the command line uses, so ``POST /api/predict`` answers
with the bytes ``sealeak predict --json`` writes and ``POST /api/surface/analyze`` with those of
``sealeak surface analyze --json``.

Errors are JSON: ``{"error": message, "field": "section.key", "message": "sealeak: error: ..."}``,
status 400 (the request is not a case or file at all), 413 (an upload over the limit) or 422 (a
value refused, with the command line's message). No traceback or server path is ever sent: an
unexpected error is logged on the server and answered with a generic message. The limits and checks
in front of every request (Host, Origin, body sizes, headers) are :mod:`sealeak.web.security`'s.
"""

from __future__ import annotations

import asyncio
import contextlib
import io
import json
import logging
import os
import re
import shutil
import tempfile
import threading
import tomllib
import zipfile
from collections.abc import AsyncIterator, Awaitable, Callable
from dataclasses import dataclass, field
from importlib import resources
from pathlib import Path
from typing import Any

import plotly
from fastapi import FastAPI, Request
from fastapi.exceptions import RequestValidationError
from fastapi.responses import FileResponse, JSONResponse, PlainTextResponse, RedirectResponse, Response
from starlette.exceptions import HTTPException as StarletteHTTPException
from starlette.middleware.base import BaseHTTPMiddleware
from starlette.types import ASGIApp

from ..cases import example_names, example_text
from ..cases.loader import example_data_names, example_description
from ..errors import FileFormatError, InputError, SealeakError
from ..render import analysis_json, html_report, prediction_csv, prediction_figures, render_figures
from ..render.interactive import prediction_plot_data
from ..topography import analysis_options, analyze, cli_option_names
from .casework import (
    DEFAULT_CACHE_BYTES,
    PredictionCache,
    check_files,
    display_units,
    doc_fields,
    edit_text,
    field_of,
    file_names,
    form_schema,
    load_toml,
    resolve_files,
    syntax_error,
    toml_text,
    upload_name,
)
from .jobs import Job, start_job
from .security import DEFAULT_MAX_BODY, ROOT_PREFIX, Guard, allowed_hosts, remove_orphans, write_pid
from .sessions import COOKIE, DEFAULT_MAX_SESSIONS, Session, SessionsFull, SessionStore
from .uploads import Form, check_expansion, folder_bytes, read_form

__all__ = ["WebConfig", "create_app", "DEFAULT_MAX_UPLOAD"]

log = logging.getLogger("sealeak.web")

#: The default upload limit (bytes): 200 MB.
DEFAULT_MAX_UPLOAD = 200 * 10**6
_STATIC = resources.files("sealeak") / "web" / "static"
_PAGES = {"case": "case.html", "surface": "surface.html", "prediction": "prediction.html", "simulation": "simulation.html",
          "help": "help.html"}


#: The default disk quota of a session (bytes of its uploaded files): 1 GB.
DEFAULT_SESSION_QUOTA = 10**9
#: The default most realizations of one simulation job.
DEFAULT_MAX_REALIZATIONS = 1000
#: The paths that take multipart uploads (up to ``max_upload``); every other body is a case or JSON (``max_body``).
UPLOAD_PATHS = ("/api/uploads", "/api/surface/analyze", "/api/case/upload")


def _cores() -> int:
    return os.cpu_count() or 1


@dataclass(frozen=True)
class WebConfig:
    """Settings of one server (``docs/web.md``, "Safety").

    ``max_upload``: the largest upload (bytes; also the most a compressed file may expand to);
    ``max_body``: the largest case file or JSON request (bytes); ``session_idle``: the idle time after
    which a session ends (s); ``root``: the folder for session folders (None: a new temporary folder,
    removed at shutdown); ``max_jobs``: simulations running at once per session; ``max_running``:
    per server (default half the cores, at least 1); ``max_workers``, ``max_realizations``: the most a
    job may ask for; ``session_quota``: the bytes of the files a session may hold; ``max_sessions``:
    sessions at once; ``cache_bytes``: the prediction cache's size; ``host``, ``port``,
    ``allow_hosts``: the address the server listens on and further names it answers to (``port``
    None: any port, for an app not bound to a socket yet).
    """

    max_upload: int = DEFAULT_MAX_UPLOAD
    session_idle: float = 4 * 3600.0
    root: Path | None = None
    max_jobs: int = 4
    max_body: int = DEFAULT_MAX_BODY
    max_running: int = field(default_factory=lambda: max(1, _cores() // 2))
    max_workers: int = field(default_factory=_cores)
    max_realizations: int = DEFAULT_MAX_REALIZATIONS
    session_quota: int = DEFAULT_SESSION_QUOTA
    max_sessions: int = DEFAULT_MAX_SESSIONS
    cache_bytes: int = DEFAULT_CACHE_BYTES
    host: str = "127.0.0.1"
    port: int | None = None
    allow_hosts: tuple[str, ...] = ()


class _Sessions(BaseHTTPMiddleware):
    """Attach the request's :class:`Session` (a new one, with its cookie, when it has none)."""

    def __init__(self, app: ASGIApp, store: SessionStore) -> None:
        super().__init__(app)
        self.store = store

    async def dispatch(self, request: Request, call_next: Callable[[Request], Awaitable[Response]]) -> Response:
        """Find or create the session, run the request, set the cookie of a new session."""
        session = self.store.get(request.cookies.get(COOKIE))
        new = session is None
        if session is None:
            try:
                session = self.store.create()
            except SessionsFull as exc:
                msg = str(exc)
                return JSONResponse({"error": msg, "field": "", "message": f"sealeak: error: {msg}"}, status_code=503)
        request.state.session = session
        response = await call_next(request)
        if new:
            response.set_cookie(COOKIE, session.token, httponly=True, samesite="strict", path="/")
        return response


def _error(exc: SealeakError, status: int, session: Session | None, root: Path) -> JSONResponse:
    msg = _scrub(str(exc), session, root)
    field = field_of(exc) if isinstance(exc, InputError) else ""
    return JSONResponse({"error": msg, "field": field, "message": f"sealeak: error: {msg}"}, status_code=status)


def _scrub(text: str, session: Session | None, root: Path) -> str:
    """``text`` without the server's folders: a session file is named by its upload name only."""
    for folder in ([session.uploads_path, session.folder] if session is not None else []) + [root]:
        text = text.replace(f"{folder}/", "").replace(str(folder), "")
    return text


def _status(exc: SealeakError) -> int:
    return 400 if isinstance(exc, FileFormatError) and not isinstance(exc, InputError) and \
        exc.problem.startswith(("is empty", "is not UTF-8", "malformed TOML")) else 422


def create_app(config: WebConfig | None = None) -> FastAPI:
    """The web app (an ASGI application; ``uvicorn`` serves it, ``sealeak serve`` starts that)."""
    cfg = config or WebConfig()
    own_root = cfg.root is None
    if own_root:  # the folders of servers that crashed go first
        for orphan in remove_orphans(Path(tempfile.gettempdir())):
            log.info("removed %s, the folder of a server that no longer runs", orphan)
    root = Path(tempfile.mkdtemp(prefix=ROOT_PREFIX)) if cfg.root is None else cfg.root
    root.mkdir(parents=True, exist_ok=True)
    if own_root:
        write_pid(root)
    store = SessionStore(root, cfg.session_idle, cfg.max_sessions)
    cache = PredictionCache(max_bytes=cfg.cache_bytes)
    stop = threading.Event()
    starting = threading.Lock()  # one job start at a time: the server's cap is checked and taken together

    def reaper() -> None:
        while not stop.wait(min(60.0, max(cfg.session_idle / 4, 0.05))):
            store.expire()

    @contextlib.asynccontextmanager
    async def lifespan(_app: FastAPI) -> AsyncIterator[None]:
        thread = threading.Thread(target=reaper, name="sealeak-sessions", daemon=True)
        thread.start()
        try:
            yield
        finally:
            stop.set()
            store.close()
            if own_root:
                shutil.rmtree(root, ignore_errors=True)

    app = FastAPI(title="sealeak", lifespan=lifespan, docs_url=None, redoc_url=None, openapi_url=None)
    app.state.sessions = store
    app.state.root = root
    app.add_middleware(_Sessions, store=store)
    app.add_middleware(Guard, hosts=allowed_hosts(cfg.host, cfg.allow_hosts), port=cfg.port,
                       any_address=cfg.host in ("0.0.0.0", "::", ""), max_body=cfg.max_body, max_upload=cfg.max_upload,
                       upload_paths=UPLOAD_PATHS)

    def session_of(request: Request) -> Session:
        return request.state.session  # type: ignore[no-any-return]

    @app.exception_handler(SealeakError)
    async def _sealeak_error(request: Request, exc: SealeakError) -> JSONResponse:
        return _error(exc, _status(exc), getattr(request.state, "session", None), root)

    @app.exception_handler(RequestValidationError)
    async def _bad_request(request: Request, exc: RequestValidationError) -> JSONResponse:
        first = exc.errors()[0] if exc.errors() else {}
        where = ".".join(str(x) for x in first.get("loc", ())[1:]) or "request"
        msg = f"{where}: {first.get('msg', 'malformed request')}"
        return JSONResponse({"error": msg, "field": where, "message": f"sealeak: error: {msg}"}, status_code=400)

    @app.exception_handler(StarletteHTTPException)
    async def _http_error(request: Request, exc: StarletteHTTPException) -> JSONResponse:
        msg = str(exc.detail)
        return JSONResponse({"error": msg, "field": getattr(exc, "field", ""), "message": f"sealeak: error: {msg}"},
                            status_code=exc.status_code)

    @app.exception_handler(Exception)
    async def _unexpected(request: Request, exc: Exception) -> JSONResponse:
        log.exception("unexpected error in %s %s", request.method, request.url.path)
        msg = "internal error: the server could not answer this request (its log has the details)"
        return JSONResponse({"error": msg, "field": "", "message": f"sealeak: error: {msg}"}, status_code=500)

    # ------------------------------------------------------------------ pages and static files
    @app.get("/", include_in_schema=False)
    def index() -> RedirectResponse:
        return RedirectResponse("/case")

    for page, filename in _PAGES.items():
        def serve_page(filename: str = filename) -> Response:
            return Response((_STATIC / filename).read_bytes(), media_type="text/html; charset=utf-8")
        app.get(f"/{page}", include_in_schema=False)(serve_page)

    @app.get("/static/{name}", include_in_schema=False)
    def static(name: str) -> Response:
        if name == "plotly.min.js":
            return FileResponse(Path(plotly.__file__).parent / "package_data" / "plotly.min.js", media_type="text/javascript")
        if not re.fullmatch(r"[a-z]+\.(js|css)", name) or not (_STATIC / name).is_file():
            raise StarletteHTTPException(404, f"{name}: no such file")
        kind = "text/javascript" if name.endswith(".js") else "text/css"
        return Response((_STATIC / name).read_bytes(), media_type=kind)

    # ------------------------------------------------------------------ the case of the session
    def case_state(s: Session, predict: bool = False) -> dict[str, Any]:
        """The session's case for the pages: TOML, form fields, valid or the loader's error, and its prediction."""
        uploads = sorted(s.uploaded())
        out: dict[str, Any] = {"name": s.case_name, "toml": s.case_text, "fields": {}, "valid": False, "error": None,
                               "uploads": uploads, "upload_names": {n: s.upload_names.get(n, n) for n in uploads}}
        if s.case_text is None:
            return out
        try:
            out["fields"] = doc_fields(load_toml(s.case_text, s.case_name))
        except (tomllib.TOMLDecodeError, InputError):  # reported below by the loader, with the CLI's message
            pass
        try:
            pred = cache.predict(s.case_text.encode("utf-8"), s.case_name, s.uploads_path)
        except SealeakError as exc:
            out["error"] = {"message": _scrub(str(exc), s, root), "field": field_of(exc) if isinstance(exc, InputError) else ""}
            return out
        out["valid"] = True
        if predict:
            if "plots" not in pred.rendered:
                pred.rendered["plots"] = json.dumps(prediction_plot_data(pred.results))
            out["prediction"] = {"json": json.loads(_scrub(pred.json(), s, root)), "plots": json.loads(pred.rendered["plots"])}
        return out

    @app.get("/api/form")
    def form() -> dict[str, Any]:
        """The case form: sections, keys, each key's kind, label and help; the display units; the bundled examples."""
        return {"sections": form_schema(), "units": display_units(),
                "examples": [{"name": n, "description": example_description(n)} for n in example_names()]}

    @app.get("/api/case")
    def get_case(request: Request, predict: bool = False) -> dict[str, Any]:
        """The session's case: its TOML, its form fields, whether it is valid (and its prediction)."""
        return case_state(session_of(request), predict=predict)

    @app.post("/api/case/example")
    def case_example(request: Request, body: dict[str, str]) -> dict[str, Any]:
        """Start from a bundled example (its data files join the session's uploads)."""
        s = session_of(request)
        name = body.get("name", "")
        text = example_text(name) if name not in example_data_names() else None
        if text is None or name not in example_names():
            raise InputError("example", name, f"allowed: {', '.join(example_names())}")
        for data in example_data_names():  # the files an example names are bundled beside it
            if data in text:
                (s.uploads / data).write_text(example_text(data), encoding="utf-8")
        s.case_text, s.case_name = text, f"{name}.toml"
        return case_state(s)

    def _rejected(s: Session, text: str, source: str) -> dict[str, Any] | None:
        """None if ``text`` is TOML; else the session's case as it is (unchanged) with ``rejected``: where the text
        stops being TOML (``message``, ``line``, ``column``), for the page to show in place."""
        where = syntax_error(text)
        if where is None:
            return None
        msg = f"{source}: {where['message']}"
        return case_state(s) | {"rejected": {"message": msg, "field": "toml", "line": where["line"], "column": where["column"]}}

    @app.post("/api/case/upload")
    async def case_upload(request: Request) -> dict[str, Any]:
        """Start from an uploaded case file (form field ``file``; at most ``max_body`` bytes). A file that is not
        TOML is answered with ``rejected`` (where it stops being TOML) and the session's case stays."""
        s = session_of(request)
        form = await _receive(request, s, cfg.max_body)
        try:
            name, path = _files(form, "file")[0]
            data = path.read_bytes()
        finally:
            form.discard()
        try:
            text = data.decode("utf-8-sig")
        except UnicodeDecodeError:
            raise FileFormatError(name, "is not UTF-8 text") from None
        bad = _rejected(s, text, name)  # not TOML, or too deep or too long a key: named in place, the case stays
        if bad is not None:
            return bad
        s.case_text, s.case_name = text, name
        return case_state(s)

    def _body(body: dict[str, Any], allowed: dict[str, type]) -> None:
        """Refuse (400) a request body with a member it does not take, or one of the wrong type, naming it."""
        for key, value in body.items():
            want = allowed.get(key)
            if want is None:
                raise InputError(str(key), value, "is not a member of this request; it takes " +
                                 ", ".join(f"'{k}'" for k in allowed))
            if not isinstance(value, want):
                raise InputError(str(key), value, f"must be {'an object' if want is dict else want.__name__}")

    @app.put("/api/case/fields")
    def case_fields(request: Request, body: dict[str, Any]) -> dict[str, Any]:
        """Apply the form's fields to the session's case (its comments kept); answer whether it is valid (and its prediction).

        The body is ``{"fields": {"section.key": "text", ...}, "predict": false}``; a member of another
        name or type, or a field that is not text, is refused (400, the case unchanged)."""
        s = session_of(request)
        _body(body, {"fields": dict, "predict": bool})
        fields = body.get("fields", {})
        for name, value in fields.items():
            if not isinstance(value, str):
                raise InputError(str(name), value, "must be text: every form field is sent as text, e.g. \"0.8\" or "
                                                   "\"2.3 MPa\"")
        try:
            text = edit_text(s.case_text, fields)
        except InputError as exc:
            return {"valid": False, "error": {"message": str(exc), "field": field_of(exc)}, "toml": s.case_text,
                    "fields": fields, "name": s.case_name, "uploads": sorted(s.uploaded()),
                    "upload_names": {n: s.upload_names.get(n, n) for n in s.uploaded()}}
        s.case_text = text
        return case_state(s, predict=bool(body.get("predict")))

    @app.put("/api/case/toml")
    def case_toml(request: Request, body: dict[str, Any]) -> dict[str, Any]:
        """Replace the session's case by TOML text (the editor): ``{"toml": "...", "predict": false}``, and
        ``"name"`` (the file's name) for a file that was uploaded with a syntax error and fixed in the editor.

        Text that is not TOML is answered with ``rejected`` (its line and column); the case stays as it was."""
        s = session_of(request)
        _body(body, {"toml": str, "predict": bool, "name": str})
        text = body.get("toml", "")
        name = upload_name(body["name"]) if "name" in body else s.case_name
        bad = _rejected(s, text, name)
        if bad is not None:
            return bad
        s.case_text, s.case_name = text, name
        return case_state(s, predict=bool(body.get("predict")))

    @app.put("/api/case/surface")
    def case_surface(request: Request, body: dict[str, Any]) -> dict[str, Any]:
        """Make uploaded topography files (and their unit options) the case's ``[surface]``."""
        s = session_of(request)
        files = body.get("files")
        if not isinstance(files, list) or not files:
            raise InputError("surface.files", files, "give the names of one or more uploaded files")
        doc = load_toml(s.case_text or example_text("reference-experiment"), s.case_name)
        if s.case_text is None:
            s.case_name = "reference-experiment.toml"
        surface: dict[str, Any] = {"model": "topography", "files": [str(f) for f in files]}
        for key, value in (body.get("options") or {}).items():
            if value not in (None, "", False) and key in ("size", "pixel_size", "height_unit", "lateral_unit", "periodic",
                                                          "channel", "bins_per_decade", "low_cut", "resolution",
                                                          "resolution_pixels"):
                surface[key] = value
        check_files({"surface": surface}, s.uploaded())
        doc["surface"] = surface
        s.case_text = toml_text(doc)
        return case_state(s)

    def _current(s: Session) -> Any:
        if s.case_text is None:
            raise SealeakError("no case yet: choose an example or upload a case file on the Case page")
        return cache.predict(s.case_text.encode("utf-8"), s.case_name, s.uploads_path)

    def _download(content: bytes | str, filename: str, media: str) -> Response:
        return Response(content, media_type=media, headers={"Content-Disposition": f'attachment; filename="{filename}"'})

    @app.get("/download/case.toml")
    def download_case(request: Request) -> Response:
        """The session's case file as TOML."""
        s = session_of(request)
        if s.case_text is None:
            raise SealeakError("no case yet: choose an example or upload a case file on the Case page")
        return _download(s.case_text, s.case_name, "application/toml")

    @app.get("/download/bundle.zip")
    def download_bundle(request: Request) -> Response:
        """The case file and the uploaded files it names, zipped: ``sealeak predict`` runs it as it is unzipped."""
        s = session_of(request)
        if s.case_text is None:
            raise SealeakError("no case yet: choose an example or upload a case file on the Case page")
        stem = s.case_name[:-5] if s.case_name.endswith(".toml") else s.case_name
        try:
            doc = tomllib.loads(s.case_text)
        except tomllib.TOMLDecodeError:
            doc = {}
        uploaded = s.uploaded()
        check_files(doc, uploaded)  # a case naming a file not uploaded here cannot be bundled (the loader says which)
        resolved = resolve_files(doc, uploaded)
        text = s.case_text if resolved is doc else toml_text(resolved)  # names the files as they are in the zip
        buf = io.BytesIO()
        with zipfile.ZipFile(buf, "w", zipfile.ZIP_DEFLATED) as z:
            z.writestr(f"{stem}/{s.case_name}", text)
            for name in sorted({n for _, v in file_names(resolved) for n in (v if isinstance(v, list) else [v])}):
                z.write(s.uploads_path / name, f"{stem}/{name}")
        return _download(buf.getvalue(), f"{stem}.zip", "application/zip")

    @app.get("/download/results.json")
    def download_json(request: Request) -> Response:
        """``predict --json`` of the session's case."""
        s = session_of(request)
        return _download(_scrub(_current(s).json(), s, root), "results.json", "application/json")

    @app.get("/download/results.csv")
    def download_csv(request: Request) -> Response:
        """``predict --csv`` of the session's case."""
        s = session_of(request)
        return _download(_scrub(prediction_csv(_current(s).results), s, root), "results.csv", "text/csv")

    @app.get("/download/figures.zip")
    def download_figures(request: Request) -> Response:
        """The PNG figures of ``predict --plots``, zipped."""
        pngs = render_figures(prediction_figures(_current(session_of(request)).results))
        buf = io.BytesIO()
        with zipfile.ZipFile(buf, "w", zipfile.ZIP_STORED) as z:
            for name, data in pngs.items():
                z.writestr(name, data)
        return _download(buf.getvalue(), "figures.zip", "application/zip")

    @app.get("/download/report.html")
    def download_report(request: Request) -> Response:
        """The HTML report of ``sealeak report``."""
        s = session_of(request)
        pred = _current(s)
        return _download(_scrub(html_report(pred.results, pred.case_file.inputs), s, root), "report.html",
                         "text/html; charset=utf-8")

    # ------------------------------------------------------------------ the JSON API of scripts
    @app.post("/api/predict")
    async def api_predict(request: Request, name: str = "case.toml") -> Response:
        """The body is a case file (TOML); the answer is what ``sealeak predict --json`` writes for it."""
        s = session_of(request)
        source = upload_name(name)
        data = await request.body()
        pred = await asyncio.to_thread(cache.predict, data, source, s.uploads_path)
        return Response(_scrub(pred.json(), s, root), media_type="application/json")

    async def _receive(request: Request, s: Session, file_limit: int) -> Form:
        """The request's form, its files streamed into the session's folder (within the session's quota)."""
        return await read_form(request, s.folder / "incoming", file_limit=file_limit, quota=cfg.session_quota,
                               used=folder_bytes(s.uploads_path))

    def _files(form: Form, name: str) -> list[tuple[str, Path]]:
        files = [(upload, path) for f, upload, path in form.files if f == name]
        if not files:
            raise FileFormatError(name, f"no file uploaded: send one or more files in the form field '{name}'")
        return files

    def _save_uploads(s: Session, form: Form, name: str) -> list[str]:
        """Keep the files of the form field ``name`` as the session's uploads, under their safe names (the name
        the user gave is kept for display); a compressed file that expands too far: 413."""
        try:
            files = _files(form, name)
            for upload, path in files:
                check_expansion(path, upload, cfg.max_upload)
            s.uploads.mkdir(parents=True, exist_ok=True)
            for upload, path in files:
                os.replace(path, s.uploads / upload)
                s.upload_names[upload] = form.given.get(upload, upload)
            return [upload for upload, _ in files]
        finally:
            form.discard()

    @app.post("/api/uploads")
    async def upload_files(request: Request) -> dict[str, Any]:
        """Upload files a case may name (form field ``files``): a C(q) table, a pressure profile, topographies."""
        s = session_of(request)
        names = _save_uploads(s, await _receive(request, s, cfg.max_upload), "files")
        return {"uploaded": names, "uploads": sorted(s.uploaded()),
                "upload_names": {n: s.upload_names.get(n, n) for n in s.uploaded()}}

    @app.get("/api/uploads")
    def list_uploads(request: Request) -> dict[str, Any]:
        """The names of the files uploaded in this session."""
        return {"uploads": sorted(session_of(request).uploaded())}

    @app.post("/api/surface/analyze")
    async def api_analyze(request: Request) -> Response:
        """Uploaded topography files (form field ``files``) and the unit options as form fields → ``surface analyze --json``."""
        s = session_of(request)
        form = await _receive(request, s, cfg.max_upload)
        names = _save_uploads(s, form, "files")
        opts = form.fields

        def number(key: str, default: float) -> float:
            text = opts.get(key, "").strip()
            if not text:
                return default
            try:
                return float(text)
            except ValueError:
                raise SealeakError(f"--{key.replace('_', '-')} = '{text}': must be a number") from None

        def work() -> str:
            with cli_option_names():  # the messages name --height-unit, --size, ... as the command line's do
                kwargs = analysis_options(
                    size=opts.get("size") or None, pixel_size=opts.get("pixel_size") or None,
                    height_unit=opts.get("height_unit") or None, lateral_unit=opts.get("lateral_unit") or None,
                    periodic=opts.get("periodic", "").lower() in ("1", "true", "on", "yes"),
                    channel=opts.get("channel") or None, bins_per_decade=number("bins_per_decade", 10.0),
                    low_cut=number("low_cut", 3.0), resolution=opts.get("resolution") or None,
                    resolution_pixels=number("resolution_pixels", 4.0))
                an = analyze([s.uploads / n for n in names], **kwargs)
            return analysis_json(an)

        text = await asyncio.to_thread(work)
        return Response(_scrub(text, s, root), media_type="application/json")

    # ------------------------------------------------------------------ simulation jobs
    @app.post("/api/jobs")
    def start(request: Request, body: dict[str, Any]) -> dict[str, Any]:
        """Start ``simulate`` on the session's case (options: grid, realizations, seed, workers)."""
        s = session_of(request)
        pred = _current(s)  # refused here, with the loader's message, before any process starts
        if len(pred.case_file.cases) != 1:
            raise SealeakError("simulate takes a case without [study] (one surface)")
        opts: dict[str, int | None] = {}
        high = {"realizations": cfg.max_realizations, "workers": cfg.max_workers}
        for key, low in (("grid", 16), ("realizations", 1), ("seed", 0), ("workers", 0)):
            value = body.get(key)
            if value in (None, ""):
                opts[key] = None
                continue
            try:
                number = int(str(value).strip())
            except ValueError:
                raise InputError(f"--{key}", value, "must be an integer") from None
            if number < low or (key == "grid" and number % 2):
                raise InputError(f"--{key}", value, f"must be {'an even integer' if key == 'grid' else 'an integer'} >= {low}")
            if key in high and number > high[key]:
                raise InputError(f"--{key}", value, f"must be an integer from {low} to {high[key]} (this server's limit)")
            opts[key] = number
        given = pred.case_file.cases[0].simulation.get("realizations")
        if opts["realizations"] is None and isinstance(given, int) and given > cfg.max_realizations:
            raise InputError("simulation.realizations", given,
                             f"must be at most {cfg.max_realizations} in the web app (this server's limit)")
        with starting, s.lock:
            running = sum(1 for j in s.jobs.values() if j.state in ("starting", "running"))
            if running >= cfg.max_jobs:
                raise StarletteHTTPException(429, f"{running} simulations are running in this session already (at most "
                                                  f"{cfg.max_jobs}): wait for one to finish or cancel one")
            everywhere = store.running_jobs()
            if everywhere >= cfg.max_running:
                raise StarletteHTTPException(429, f"{everywhere} simulations are running on this server already (at most "
                                                  f"{cfg.max_running} at once): try again when one has finished")
            doc = load_toml(s.case_text or "", s.case_name)
            resolved = resolve_files(doc, s.uploaded())  # the files as they are stored, the case naming them so
            names = {n for _, v in file_names(resolved) for n in (v if isinstance(v, list) else [v])}
            job = start_job(s.jobs_folder, (s.case_text or "") if resolved is doc else toml_text(resolved), s.case_name,
                            [s.uploads / n for n in sorted(names)],
                            pred.case_file.cases[0].title, opts["grid"], opts["realizations"], opts["seed"],
                            opts["workers"])
            s.jobs[job.id] = job
        return job.info()

    def _job(s: Session, job_id: str) -> Job:
        job = s.jobs.get(job_id)
        if job is None:
            raise StarletteHTTPException(404, f"job {job_id}: no such job in this session")
        return job  # type: ignore[no-any-return]

    @app.get("/api/jobs")
    def jobs(request: Request) -> list[dict[str, Any]]:
        """This session's jobs, newest first."""
        return [j.info() for j in sorted(session_of(request).jobs.values(), key=lambda j: -j.started)]

    @app.get("/api/jobs/{job_id}")
    def job(request: Request, job_id: str) -> dict[str, Any]:
        """One job's state and progress."""
        return _job(session_of(request), job_id).info()

    @app.post("/api/jobs/{job_id}/cancel")
    def cancel(request: Request, job_id: str) -> dict[str, Any]:
        """Cancel a running job (its process group is killed)."""
        j = _job(session_of(request), job_id)
        j.cancel()
        return j.info()

    @app.get("/api/jobs/{job_id}/result.json")
    def job_json(request: Request, job_id: str) -> Response:
        """``simulate --json`` of a finished job."""
        j = _job(session_of(request), job_id)
        p = j.folder / "result.json"
        if j.state != "done" or not p.is_file():
            raise StarletteHTTPException(409, f"job {job_id}: not finished ({j.state})")
        return Response(_scrub(p.read_text(encoding="utf-8"), session_of(request), root), media_type="application/json")

    @app.get("/api/jobs/{job_id}/table.txt")
    def job_table(request: Request, job_id: str) -> PlainTextResponse:
        """The table ``simulate`` printed."""
        j = _job(session_of(request), job_id)
        p = j.folder / "table.txt"
        return PlainTextResponse(_scrub(p.read_text(encoding="utf-8", errors="replace") if p.is_file() else "",
                                        session_of(request), root))

    @app.get("/api/jobs/{job_id}/figures/{name}")
    def job_figure(request: Request, job_id: str, name: str) -> Response:
        """One figure of a finished job (PNG)."""
        j = _job(session_of(request), job_id)
        if not re.fullmatch(r"[A-Za-z0-9_.-]+\.png", name) or not (j.folder / "figures" / name).is_file():
            raise StarletteHTTPException(404, f"{name}: no such figure")
        return Response((j.folder / "figures" / name).read_bytes(), media_type="image/png")

    return app
