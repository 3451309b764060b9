"""The downloads of the session's case: its TOML, a bundle with its files, and ``predict``'s documents."""

from __future__ import annotations

import io
import tomllib
import zipfile

from fastapi import APIRouter
from fastapi.responses import Response

from ...errors import SealeakError
from ...render import html_report, prediction_csv, prediction_figures, render_figures
from ...render.life import volume_limit
from ...render.uncertainty_figures import uncertainty_figures
from ..casework import check_files, file_names, resolve_files, toml_text
from ..state import NO_CASE, SessionDep, StateDep, current, download, scrub

__all__ = ["router"]

router = APIRouter(tags=["downloads"])


@router.get("/download/case.toml")
def download_case(s: SessionDep) -> Response:
    """The session's case file as TOML."""
    if s.case_text is None:
        raise SealeakError(NO_CASE)
    return download(s.case_text, s.case_name, "application/toml")


@router.get("/download/bundle.zip")
def download_bundle(s: SessionDep) -> Response:
    """The case file and the uploaded files it names, zipped: ``sealeak predict`` runs it as it is unzipped."""
    if s.case_text is None:
        raise SealeakError(NO_CASE)
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
    return download(buf.getvalue(), f"{stem}.zip", "application/zip")


@router.get("/download/results.json")
def download_json(state: StateDep, s: SessionDep) -> Response:
    """``predict --json`` of the session's case."""
    return download(scrub(current(state, s).json(), s, state.root), "results.json", "application/json")


@router.get("/download/results.csv")
def download_csv(state: StateDep, s: SessionDep) -> Response:
    """``predict --csv`` of the session's case."""
    pred = current(state, s)
    return download(scrub(prediction_csv(pred.results, pred.uncertainty), s, state.root), "results.csv", "text/csv")


@router.get("/download/figures.zip")
def download_figures(state: StateDep, s: SessionDep) -> Response:
    """The PNG figures of ``predict --plots``, zipped (with uncertain inputs the band and the distribution too)."""
    pred = current(state, s)
    figures = prediction_figures(pred.results, limit=volume_limit(pred.uncertainty))
    pngs = render_figures(figures | (uncertainty_figures(pred.uncertainty) if pred.uncertainty else {}))
    buf = io.BytesIO()
    with zipfile.ZipFile(buf, "w", zipfile.ZIP_STORED) as z:
        for name, data in pngs.items():
            z.writestr(name, data)
    return download(buf.getvalue(), "figures.zip", "application/zip")


@router.get("/download/report.html")
def download_report(state: StateDep, s: SessionDep) -> Response:
    """The HTML report of ``sealeak report``."""
    pred = current(state, s)
    return download(scrub(html_report(pred.results, pred.case_file.inputs, pred.uncertainty), s, state.root), "report.html",
                    "text/html; charset=utf-8")
