"""The session's case: the form's schema, the case as the pages see it, and every way to change it.

Each answer is the case's state (:func:`sealeak.web.state.case_state`): its TOML, its form fields,
whether it is valid (else the loader's error) and, asked for, its prediction. Text that is not TOML
is answered with ``rejected`` (where it stops being TOML) and the case stays as it was.
"""

from __future__ import annotations

from typing import Any

from fastapi import APIRouter, Request

from ...cases import example_names, example_text
from ...cases.loader import example_data_names, example_description
from ...errors import FileFormatError, InputError
from ..casework import check_files, display_units, edit_text, field_of, form_schema, load_toml, syntax_error, toml_text, upload_name
from ..models import ExampleBody, FieldsBody, SurfaceBody, TomlBody, multipart_body
from ..sessions import Session
from ..state import AppState, SessionDep, StateDep, case_state, form_files, receive, upload_list

__all__ = ["router"]

router = APIRouter(tags=["case"])


@router.get("/api/form")
def form() -> dict[str, Any]:
    """The case form: sections, keys, each key's kind, label and help; the display units; the bundled examples."""
    return {"sections": form_schema(), "units": display_units(),
            "examples": [{"name": n, "description": example_description(n)} for n in example_names()]}


@router.get("/api/case")
def get_case(state: StateDep, s: SessionDep, predict: bool = False) -> dict[str, Any]:
    """The session's case: its TOML, its form fields, whether it is valid (and its prediction)."""
    return case_state(state, s, predict=predict)


@router.post("/api/case/example")
def case_example(state: StateDep, s: SessionDep, body: ExampleBody) -> dict[str, Any]:
    """Start from a bundled example (its data files join the session's uploads)."""
    name = body.name
    text = example_text(name) if name not in example_data_names() else None
    if text is None or name not in example_names():
        raise InputError("example", name, f"allowed: {', '.join(example_names())}")
    for data in example_data_names():  # the files an example names are bundled beside it
        if data in text:
            (s.uploads / data).write_text(example_text(data), encoding="utf-8")
    s.case_text, s.case_name = text, f"{name}.toml"
    return case_state(state, s)


def _rejected(state: AppState, s: Session, text: str, source: str) -> dict[str, Any] | None:
    """None if ``text`` is TOML; else the session's case as it is (unchanged) with ``rejected``: where the text
    stops being TOML (``message``, ``line``, ``column``), for the page to show in place."""
    where = syntax_error(text)
    if where is None:
        return None
    msg = f"{source}: {where['message']}"
    return case_state(state, s) | {"rejected": {"message": msg, "field": "toml", "line": where["line"],
                                                "column": where["column"]}}


@router.post("/api/case/upload", openapi_extra=multipart_body("file", many=False))
async def case_upload(request: Request, state: StateDep, s: SessionDep) -> dict[str, Any]:
    """Start from an uploaded case file (form field ``file``; at most ``max_body`` bytes). A file that is not
    TOML is answered with ``rejected`` (where it stops being TOML) and the session's case stays."""
    form = await receive(request, state, s, state.config.max_body)
    try:
        name, path = form_files(form, "file")[0]
        data = path.read_bytes()
    finally:
        form.discard()
    try:
        text = data.decode("utf-8-sig")
    except UnicodeDecodeError:
        raise FileFormatError(name, "is not UTF-8 text") from None
    bad = _rejected(state, s, text, name)  # not TOML, or too deep or too long a key: named in place, the case stays
    if bad is not None:
        return bad
    s.case_text, s.case_name = text, name
    return case_state(state, s)


@router.put("/api/case/fields")
def case_fields(state: StateDep, s: SessionDep, body: FieldsBody) -> dict[str, Any]:
    """Apply the form's fields to the session's case (its comments kept); answer whether it is valid (and its prediction).

    A member of another name or type, or a field that is not text, is refused (422, the case unchanged)."""
    try:
        text = edit_text(s.case_text, body.fields)
    except InputError as exc:
        return {"valid": False, "error": {"message": str(exc), "field": field_of(exc)}, "toml": s.case_text,
                "fields": body.fields, "name": s.case_name, **upload_list(s)}
    s.case_text = text
    return case_state(state, s, predict=body.predict)


@router.put("/api/case/toml")
def case_toml(state: StateDep, s: SessionDep, body: TomlBody) -> dict[str, Any]:
    """Replace the session's case by TOML text (the editor); ``name``: the file's name, for a file that was
    uploaded with a syntax error and fixed in the editor.

    Text that is not TOML is answered with ``rejected`` (its line and column); the case stays as it was."""
    name = upload_name(body.name) if "name" in body.model_fields_set else s.case_name
    bad = _rejected(state, s, body.toml, name)
    if bad is not None:
        return bad
    s.case_text, s.case_name = body.toml, name
    return case_state(state, s, predict=body.predict)


@router.put("/api/case/surface")
def case_surface(state: StateDep, s: SessionDep, body: SurfaceBody) -> dict[str, Any]:
    """Make uploaded topography files (and their unit options) the case's ``[surface]``."""
    if not body.files:
        raise InputError("surface.files", body.files, "give the names of one or more uploaded files")
    doc = load_toml(s.case_text or example_text("reference-experiment"), s.case_name)
    if s.case_text is None:
        s.case_name = "reference-experiment.toml"
    surface: dict[str, Any] = {"model": "topography", "files": list(body.files)}
    options = body.options.model_dump() if body.options is not None else {}
    surface |= {key: value for key, value in options.items() if value not in (None, "", False)}
    check_files({"surface": surface}, s.uploaded())
    doc["surface"] = surface
    s.case_text = toml_text(doc)
    return case_state(state, s)
