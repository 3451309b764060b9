"""What the routes of the web app share: the server's settings, its session store and caches, as one typed object.

:func:`sealeak.web.app.create_app` builds one :class:`AppState` per app and keeps it as
``app.state.sealeak``; a route asks for it, and for the request's :class:`~sealeak.web.sessions.Session`,
through the FastAPI dependencies :data:`StateDep` and :data:`SessionDep` (no closures). The helpers
here are those several routers use: the error JSON, the scrubbing of server folders out of every
text sent, the session's case as the pages see it, and the multipart form of an upload.
"""

from __future__ import annotations

import json
import os
import threading
import tomllib
from dataclasses import dataclass, field
from pathlib import Path
from typing import Annotated, Any

from fastapi import Depends, Request
from fastapi.responses import JSONResponse, Response

from ..errors import FileFormatError, InputError, SealeakError
from ..render.interactive import prediction_plot_data
from .casework import DEFAULT_CACHE_BYTES, Prediction, PredictionCache, doc_fields, field_of, load_toml
from .security import DEFAULT_MAX_BODY
from .sessions import DEFAULT_MAX_SESSIONS, Session, SessionStore
from .uploads import DiskLedger, Form, Quota, check_expansion, folder_bytes, read_form

__all__ = ["WebConfig", "AppState", "StateDep", "SessionDep", "DEFAULT_MAX_UPLOAD", "DEFAULT_SESSION_QUOTA", "DEFAULT_SERVER_QUOTA", "disk_quotas",
           "DEFAULT_MAX_REALIZATIONS", "NO_CASE", "error_json", "error_response", "scrub", "case_state", "current",
           "download", "receive", "form_files", "save_uploads", "upload_list"]

#: The default upload limit (bytes): 200 MB.
DEFAULT_MAX_UPLOAD = 200 * 10**6
#: The default disk quota of a session (bytes of its uploaded files): 1 GB.
DEFAULT_SESSION_QUOTA = 10**9
#: The default disk limit of the whole server (bytes of all sessions' files): 10 GB.
DEFAULT_SERVER_QUOTA = 10 * 10**9
#: The default most realizations of one simulation job.
DEFAULT_MAX_REALIZATIONS = 1000
#: The message of a request that needs a case when the session has none.
NO_CASE = "no case yet: choose an example or upload a case file on the Case page"


def _cores() -> int:
    return os.cpu_count() or 1


@dataclass(frozen=True, kw_only=True)
class WebConfig:
    """Settings of one server (``docs/web.md``, "Safety").

    ``max_upload``: the largest upload (bytes; also the most a compressed file may expand to);
    ``max_body``: the largest case file or JSON request (bytes); ``session_idle``: the idle time after
    which a session ends (s); ``root``: the folder for session folders (None: a new temporary folder,
    removed at shutdown); ``max_jobs``: simulations running at once per session; ``max_running``:
    per server (default half the cores, at least 1); ``max_workers``, ``max_realizations``: the most a
    job may ask for; ``session_quota``: the bytes of the files a session may hold (uploads and simulation
    results); ``server_quota``: the bytes of the files of all sessions together; ``max_sessions``:
    sessions at once; ``cache_bytes``: the prediction cache's size; ``max_predictions``: predictions computed at
    once on the server (default the cores, at least 2; a case with uncertain inputs is hundreds of them); ``host``, ``port``,
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
    server_quota: int = DEFAULT_SERVER_QUOTA
    max_sessions: int = DEFAULT_MAX_SESSIONS
    cache_bytes: int = DEFAULT_CACHE_BYTES
    max_predictions: int = field(default_factory=lambda: max(2, _cores()))
    host: str = "127.0.0.1"
    port: int | None = None
    allow_hosts: tuple[str, ...] = ()


@dataclass
class AppState:
    """One server's shared state: its settings, the folder of its sessions, the sessions, the prediction cache.

    ``starting`` is held while a simulation job starts, so that the server's cap on running jobs is
    checked and taken together."""

    config: WebConfig
    root: Path
    sessions: SessionStore
    cache: PredictionCache
    starting: threading.Lock = field(default_factory=threading.Lock)
    #: the bytes uploads running at once are writing (:class:`~sealeak.web.uploads.DiskLedger`)
    uploads: DiskLedger = field(default_factory=DiskLedger)


async def _app_state(request: Request) -> AppState:
    return request.app.state.sealeak  # type: ignore[no-any-return]


async def _session(request: Request) -> Session:
    return request.state.session  # type: ignore[no-any-return]


#: The server's :class:`AppState` (a route parameter ``state: StateDep``).
StateDep = Annotated[AppState, Depends(_app_state)]
#: The request's session, attached by the session middleware (a route parameter ``s: SessionDep``).
SessionDep = Annotated[Session, Depends(_session)]


def error_json(msg: str, field: str, status: int) -> JSONResponse:
    """The JSON of every error: ``{"error": msg, "field": field, "message": "sealeak: error: msg"}`` (a character that is
    no Unicode text, half a surrogate pair, written as its escape: the answer must encode)."""
    msg, field = (t.encode("utf-8", "backslashreplace").decode("utf-8") for t in (msg, field))
    return JSONResponse({"error": msg, "field": field, "message": f"sealeak: error: {msg}"}, status_code=status)


def error_response(exc: SealeakError, session: Session | None, root: Path) -> JSONResponse:
    """A refused request as JSON: 400 if the body is not a case at all (empty, not UTF-8, malformed TOML), else 422."""
    bad = isinstance(exc, FileFormatError) and not isinstance(exc, InputError) and \
        exc.problem.startswith(("is empty", "is not UTF-8", "malformed TOML"))
    return error_json(scrub(str(exc), session, root), field_of(exc) if isinstance(exc, InputError) else "",
                      400 if bad else 422)


def scrub(text: str, session: Session | None, root: Path) -> str:
    """``text`` without the server's folders: a session file is named by its upload name only."""
    for folder in ([session.uploads_path, session.folder] if session is not None else []) + [root]:
        text = text.replace(f"{folder}/", "").replace(str(folder), "")
    return text


def upload_list(s: Session) -> dict[str, Any]:
    """The session's uploads (stored names, sorted) and the name each was given."""
    uploads = sorted(s.uploaded())
    return {"uploads": uploads, "upload_names": {n: s.upload_names.get(n, n) for n in uploads}}


def case_state(state: AppState, s: Session, predict: bool = False) -> dict[str, Any]:
    """The session's case for the pages: TOML, form fields, valid or the loader's error, and its prediction."""
    out: dict[str, Any] = {"name": s.case_name, "toml": s.case_text, "fields": {}, "valid": False, "error": None,
                           **upload_list(s)}
    if s.case_text is None:
        return out
    try:
        out["fields"] = doc_fields(load_toml(s.case_text, s.case_name))
    except (tomllib.TOMLDecodeError, InputError):  # reported below by the loader, with the CLI's message
        pass
    try:
        pred = state.cache.predict(s.case_text.encode("utf-8"), s.case_name, s.uploads_path)
    except SealeakError as exc:
        out["error"] = {"message": scrub(str(exc), s, state.root),
                        "field": field_of(exc) if isinstance(exc, InputError) else ""}
        return out
    out["valid"] = True
    if predict:
        if "plots" not in pred.rendered:
            pred.rendered["plots"] = json.dumps(prediction_plot_data(pred.results, pred.uncertainty))
        out["prediction"] = {"json": json.loads(scrub(pred.json(), s, state.root)),
                             "plots": json.loads(pred.rendered["plots"])}
    return out


def current(state: AppState, s: Session) -> Prediction:
    """The prediction of the session's case (cached); no case yet: a SealeakError (422)."""
    if s.case_text is None:
        raise SealeakError(NO_CASE)
    return state.cache.predict(s.case_text.encode("utf-8"), s.case_name, s.uploads_path)


def download(content: bytes | str, filename: str, media: str) -> Response:
    """A response the browser saves as ``filename``."""
    return Response(content, media_type=media, headers={"Content-Disposition": f'attachment; filename="{filename}"'})


def disk_quotas(state: AppState, s: Session) -> list[Quota]:
    """The disk limits new files of session ``s`` count against: its own (all its files: uploads, simulation
    results) and the server's (the files of every session)."""
    cfg = state.config
    everything, session = folder_bytes(state.root, s.folder)  # one walk: the session's folder is in the server's
    return [Quota(cfg.session_quota, session,
                  f"the session's files would take more than its quota of {cfg.session_quota / 1e6:.6g} MB "
                  "(sealeak serve --session-quota)", s.token),
            Quota(cfg.server_quota, everything,
                  f"the files of all sessions would take more than the server's limit of {cfg.server_quota / 1e6:.6g} MB "
                  "(sealeak serve --server-quota): try again later")]


async def receive(request: Request, state: AppState, s: Session, file_limit: int) -> Form:
    """The request's form, its files streamed into the session's folder (within the session's and the server's quotas)."""
    ticket = state.uploads.begin(s.token)  # before the disk is read: uploads running beside it count too
    try:
        return await read_form(request, s.folder / "incoming", file_limit=file_limit, quotas=disk_quotas(state, s),
                               ledger=state.uploads, ticket=ticket)
    finally:
        state.uploads.end(ticket)


def form_files(form: Form, name: str) -> list[tuple[str, Path]]:
    """The (safe name, path) of the files of the form field ``name``; none: a FileFormatError naming the field."""
    files = [(upload, path) for f, upload, path in form.files if f == name]
    if not files:
        raise FileFormatError(name, f"no file uploaded: send one or more files in the form field '{name}'")
    return files


def save_uploads(state: AppState, s: Session, form: Form, name: str) -> list[str]:
    """Keep the files of the form field ``name`` as the session's uploads, under their safe names (the name
    the user gave is kept for display); a compressed file that expands too far: 413."""
    try:
        files = form_files(form, name)
        for upload, path in files:
            check_expansion(path, upload, state.config.max_upload)
        s.uploads.mkdir(parents=True, exist_ok=True)
        for upload, path in files:
            os.replace(path, s.uploads / upload)
            s.upload_names[upload] = form.given.get(upload, upload)
        return [upload for upload, _ in files]
    finally:
        form.discard()
