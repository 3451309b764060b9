"""Uploads and surface analysis: files a case may name, and ``surface analyze --json`` of topography files."""

from __future__ import annotations

from collections.abc import Callable
from contextlib import AbstractContextManager
from typing import Any

from fastapi import APIRouter, Request
from fastapi.responses import Response
from starlette.concurrency import run_in_threadpool

from ...errors import InputError
from ...render import analysis_json
from ...topography import analysis_options, analyze, cli_option_names
from ..models import multipart_body
from ..sessions import Session
from ..state import SessionDep, StateDep, receive, save_uploads, scrub, upload_list

__all__ = ["router", "ANALYSIS_FIELDS"]

#: The form fields of ``POST /api/surface/analyze`` beside its files: ``surface analyze``'s unit and range options.
ANALYSIS_FIELDS = ("size", "pixel_size", "height_unit", "lateral_unit", "periodic", "channel", "bins_per_decade",
                   "low_cut", "resolution", "resolution_pixels")

router = APIRouter(tags=["surface"])


@router.post("/api/uploads", openapi_extra=multipart_body("files", many=True))
async def upload_files(request: Request, state: StateDep, s: SessionDep) -> dict[str, Any]:
    """Upload files a case may name (form field ``files``): a C(q) table, a pressure profile, topographies."""
    names = save_uploads(state, s, await receive(request, state, s, state.config.max_upload), "files")
    return {"uploaded": names, **upload_list(s)}


@router.get("/api/uploads")
def list_uploads(s: SessionDep) -> dict[str, Any]:
    """The names of the files uploaded in this session."""
    return {"uploads": sorted(s.uploaded())}


def _number(opts: dict[str, str], key: str, default: float) -> float:
    """The form field ``key`` as a number (empty: ``default``); else refused naming its option."""
    text = opts.get(key, "").strip()
    if not text:
        return default
    try:
        return float(text)
    except ValueError:
        raise InputError(f"--{key.replace('_', '-')}", text, "must be a number") from None


def _flag(opts: dict[str, str], key: str) -> bool:
    """The form field ``key`` as a switch (empty: off); anything but 1/0, true/false, on/off, yes/no refused naming
    its option."""
    text = opts.get(key, "").strip().lower()
    if text in ("", "0", "false", "off", "no"):
        return False
    if text in ("1", "true", "on", "yes"):
        return True
    raise InputError(f"--{key.replace('_', '-')}", opts[key], "must be true or false (1/0, on/off, yes/no)")


def _analysis(s: Session, names: list[str], opts: dict[str, str], slot: Callable[[], AbstractContextManager[None]]) -> str:
    """``surface analyze --json`` of the session's files ``names`` with the form's options (text)."""
    with cli_option_names():  # the messages name --height-unit, --size, ... as the command line's do
        kwargs = analysis_options(
            size=opts.get("size") or None, pixel_size=opts.get("pixel_size") or None,
            height_unit=opts.get("height_unit") or None, lateral_unit=opts.get("lateral_unit") or None,
            periodic=_flag(opts, "periodic"),
            channel=opts.get("channel") or None, bins_per_decade=_number(opts, "bins_per_decade", 10.0),
            low_cut=_number(opts, "low_cut", 3.0), resolution=opts.get("resolution") or None,
            resolution_pixels=_number(opts, "resolution_pixels", 4.0))
        with slot():  # one of the server's computing slots, as a prediction
            an = analyze([s.uploads / n for n in names], **kwargs)
    return analysis_json(an)


@router.post("/api/surface/analyze", openapi_extra=multipart_body("files", many=True, fields=ANALYSIS_FIELDS))
async def api_analyze(request: Request, state: StateDep, s: SessionDep) -> Response:
    """Uploaded topography files (form field ``files``) and the unit options as form fields → ``surface analyze --json``."""
    form = await receive(request, state, s, state.config.max_upload)
    names = save_uploads(state, s, form, "files")
    text = await run_in_threadpool(_analysis, s, names, form.fields, state.cache.slot)
    return Response(scrub(text, s, state.root), media_type="application/json")
