"""``POST /api/predict``: a case file in, the bytes ``sealeak predict --json`` writes out."""

from __future__ import annotations

from fastapi import APIRouter, Request
from fastapi.responses import Response
from starlette.concurrency import run_in_threadpool

from ..casework import upload_name
from ..models import TOML_BODY
from ..state import SessionDep, StateDep, scrub

__all__ = ["router"]

router = APIRouter(tags=["predict"])


@router.post("/api/predict", openapi_extra=TOML_BODY)
async def api_predict(request: Request, state: StateDep, s: SessionDep, name: str = "case.toml") -> Response:
    """The body is a case file (TOML); the answer is what ``sealeak predict --json`` writes for it (``name``:
    the case file's name as the command line would see it, its ``source``)."""
    source = upload_name(name)
    data = await request.body()
    pred = await run_in_threadpool(state.cache.predict, data, source, s.uploads_path)  # (not asyncio's few threads)
    return Response(scrub(pred.json(), s, state.root), media_type="application/json")
