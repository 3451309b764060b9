"""Simulation jobs: ``sealeak simulate`` on the session's case in a process of its own, its progress and results."""

from __future__ import annotations

import re
from typing import Any

from fastapi import APIRouter
from fastapi.responses import PlainTextResponse, Response
from starlette.exceptions import HTTPException as StarletteHTTPException

from ...cases import Case, simulation_options
from ...errors import InputError, ResourceError, SealeakError
from ...numerics import check_memory
from ..casework import file_names, load_toml, resolve_files, toml_text
from ..jobs import Job, start_job
from ..models import JobBody
from ..sessions import Session
from ..state import AppState, SessionDep, StateDep, WebConfig, current, disk_quotas, scrub

__all__ = ["router"]

router = APIRouter(tags=["jobs"])


def _options(body: JobBody, case: Case, config: WebConfig) -> dict[str, int | None]:
    """The job's options as given (None: the case's value), each read as ``sealeak simulate`` reads its option and
    checked, with the case's ``[simulation]`` values, by the one validator of the simulation options
    (:func:`sealeak.cases.simulation_options`) within this server's limits."""
    opts: dict[str, int | None] = {}
    for key in ("grid", "realizations", "seed", "workers"):
        value = getattr(body, key)
        if value in (None, ""):
            opts[key] = None
            continue
        text = str(value).strip()
        # the digits 0-9 only, as the command line and the case files read them: int() takes "٦٤" for 64
        if isinstance(value, bool) or not (isinstance(value, int) or (text.isascii() and text.lstrip("+-").isdigit())):
            raise InputError(f"--{key}", value, "must be an integer" + ("" if text.isascii() else ", written with the digits 0-9"))
        opts[key] = int(text)
    chosen = simulation_options(grid=opts["grid"], realizations=opts["realizations"], seed=opts["seed"], workers=opts["workers"],
                       defaults=case.simulation, max_realizations=config.max_realizations,
                       max_workers=config.max_workers, limit_note=" (this server's limit)")
    try:  # before a process starts: a grid of 2^20 points a side was accepted (200) and failed in its job
        check_memory(max(chosen.grids), "contact")
    except ResourceError as exc:
        raise InputError(chosen.grid_field, max(chosen.grids), str(exc)) from None
    return opts  # the given values: a case's own grid list still runs its convergence study


def _simulations(n: int) -> str:
    """``1 simulation is``, ``2 simulations are``."""
    return f"{n} simulation is" if n == 1 else f"{n} simulations are"


def _launch(state: AppState, s: Session, title: str, opts: dict[str, int | None]) -> Job:
    """Start the job if the session's and the server's caps allow (429 otherwise); the caller holds the locks."""
    cfg = state.config
    running = sum(1 for j in s.jobs.values() if j.state in ("starting", "running"))
    if running >= cfg.max_jobs:
        raise StarletteHTTPException(429, f"{_simulations(running)} running in this session already (at most "
                                          f"{cfg.max_jobs}): wait for one to finish or cancel one")
    everywhere = state.sessions.running_jobs()
    if everywhere >= cfg.max_running:
        raise StarletteHTTPException(429, f"{_simulations(everywhere)} running on this server already (at most "
                                          f"{cfg.max_running} at once): try again when one has finished")
    full = next((q for q in disk_quotas(state, s) if q.left() <= 0), None)
    if full is not None:  # a job writes its results into the session's folder
        raise StarletteHTTPException(507, "simulate: " + full.what.replace("would take", "take", 1) +
                                     "; remove a finished simulation first (DELETE /api/jobs/ID)")
    doc = load_toml(s.case_text or "", s.case_name)
    resolved = resolve_files(doc, s.uploaded())  # the files as they are stored, the case naming them so
    names = {n for _, v in file_names(resolved) for n in (v if isinstance(v, list) else [v])}
    return start_job(s.jobs_folder, (s.case_text or "") if resolved is doc else toml_text(resolved), s.case_name,
                     [s.uploads / n for n in sorted(names)], title, opts["grid"], opts["realizations"], opts["seed"],
                     opts["workers"])


@router.post("/api/jobs")
def start(state: StateDep, s: SessionDep, body: JobBody) -> dict[str, Any]:
    """Start ``simulate`` on the session's case (options: grid, realizations, seed, workers)."""
    cfg = state.config
    pred = current(state, s)  # refused here, with the loader's message, before any process starts
    if len(pred.case_file.cases) != 1:
        raise SealeakError("simulate takes a case without [study] (one surface)")
    opts = _options(body, pred.case_file.cases[0], cfg)
    with state.starting, s.lock:
        job = _launch(state, s, pred.case_file.cases[0].title, opts)
        s.jobs[job.id] = job
    return job.info()


def _job(s: Session, job_id: str) -> Job:
    job = s.jobs.get(job_id)
    if job is None:
        raise StarletteHTTPException(404, f"job {job_id}: no such job in this session")
    return job  # type: ignore[no-any-return]


@router.get("/api/jobs")
def jobs(s: SessionDep) -> list[dict[str, Any]]:
    """This session's jobs, newest first."""
    return [j.info() for j in sorted(s.jobs.values(), key=lambda j: -j.started)]


@router.get("/api/jobs/{job_id}")
def job(s: SessionDep, job_id: str) -> dict[str, Any]:
    """One job's state and progress."""
    return _job(s, job_id).info()


@router.post("/api/jobs/{job_id}/cancel")
def cancel(s: SessionDep, job_id: str) -> dict[str, Any]:
    """Cancel a running job (its process group is killed)."""
    j = _job(s, job_id)
    j.cancel()
    return j.info()


@router.delete("/api/jobs/{job_id}")
def remove(s: SessionDep, job_id: str) -> dict[str, Any]:
    """Remove a job and its results from the session (a running one is cancelled first): frees its disk."""
    j = _job(s, job_id)
    with s.lock:
        j.remove()
        s.jobs.pop(job_id, None)
    return {"removed": job_id}


@router.get("/api/jobs/{job_id}/result.json")
def job_json(state: StateDep, s: SessionDep, job_id: str) -> Response:
    """``simulate --json`` of a finished job."""
    j = _job(s, job_id)
    p = j.folder / "result.json"
    if j.state != "done" or not p.is_file():
        raise StarletteHTTPException(409, f"job {job_id}: not finished ({j.state})")
    return Response(scrub(p.read_text(encoding="utf-8"), s, state.root), media_type="application/json")


@router.get("/api/jobs/{job_id}/table.txt")
def job_table(state: StateDep, s: SessionDep, job_id: str) -> PlainTextResponse:
    """The table ``simulate`` printed."""
    p = _job(s, job_id).folder / "table.txt"
    return PlainTextResponse(scrub(p.read_text(encoding="utf-8", errors="replace") if p.is_file() else "", s, state.root))


@router.get("/api/jobs/{job_id}/figures/{name}")
def job_figure(s: SessionDep, job_id: str, name: str) -> Response:
    """One figure of a finished job (PNG)."""
    j = _job(s, job_id)
    if not re.fullmatch(r"[A-Za-z0-9_.-]+\.png", name) or not (j.folder / "figures" / name).is_file():
        raise StarletteHTTPException(404, f"{name}: no such figure")
    return Response((j.folder / "figures" / name).read_bytes(), media_type="image/png")
