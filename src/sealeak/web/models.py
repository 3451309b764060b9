"""The JSON request bodies of the web app's API, as pydantic models (served in ``/openapi.json``).

Every model refuses a member it does not declare (``extra="forbid"``) and takes its members'
types strictly (``"predict": "yes"`` is not true, ``"toml": 5`` is not text). A refused member is
answered like any refused value, 422 with the error JSON naming it (:func:`refusal` words it as
:class:`~sealeak.errors.InputError` does): ``nmae = 'x.toml': is not a member of this request; it
takes 'toml', 'predict', 'name'``.
"""

from __future__ import annotations

import functools
import typing
from collections.abc import Callable, Mapping, Sequence
from typing import Annotated, Any, get_args

from pydantic import BaseModel, ConfigDict, Field, WithJsonSchema

from ..errors import InputError

__all__ = ["ExampleBody", "FieldsBody", "TomlBody", "SurfaceBody", "SurfaceOptions", "JobBody", "refusal", "body_model", "multipart_body", "TOML_BODY"]


class _Body(BaseModel):
    model_config = ConfigDict(extra="forbid", strict=True)


class ExampleBody(_Body):
    """``POST /api/case/example``: start from a bundled example (``sealeak examples`` lists them)."""

    name: str = Field("", description="the example's name, e.g. reference-experiment")


class FieldsBody(_Body):
    """``PUT /api/case/fields``: the form's fields applied to the session's case."""

    fields: dict[str, str] = Field(default_factory=dict, description="section.key → the field's text, e.g. "
                                   "{\"rubber.youngs_modulus\": \"2.3 MPa\"}; a key left out or empty is removed")
    predict: bool = Field(False, description="answer the case's prediction too")


class TomlBody(_Body):
    """``PUT /api/case/toml``: the session's case replaced by TOML text (the editor)."""

    toml: str = Field("", description="the case file's text")
    predict: bool = Field(False, description="answer the case's prediction too")
    name: str = Field("", description="the case file's name (a file uploaded with a syntax error and fixed); "
                      "left out: the case keeps its name")


#: A unit option as a form sends it: text (``"0.5 mm"``, ``"um"``), a number, or true/false (``periodic``);
#: kept as sent (an integer stays an integer in the case file).
_Option = str | bool | int | float | None


class SurfaceOptions(_Body):
    """The unit and range options of ``[surface]`` with ``model = "topography"`` (empty or false: left out)."""

    size: _Option = None
    pixel_size: _Option = None
    height_unit: _Option = None
    lateral_unit: _Option = None
    periodic: _Option = None
    channel: _Option = None
    bins_per_decade: _Option = None
    low_cut: _Option = None
    resolution: _Option = None
    resolution_pixels: _Option = None


class SurfaceBody(_Body):
    """``PUT /api/case/surface``: uploaded topography files (and their unit options) become the case's ``[surface]``."""

    files: list[str] | None = Field(None, description="the stored names of one or more uploaded files")
    options: SurfaceOptions | None = None


#: A simulation option as the page sends it: an integer, its text, or empty/null (the case's value).
#: The job route checks it (``--grid = '33': must be an even integer >= 16``), as ``sealeak simulate`` does.
_JobOption = Annotated[Any, WithJsonSchema({"anyOf": [{"type": "integer"}, {"type": "string"}, {"type": "null"}]})]


class JobBody(_Body):
    """``POST /api/jobs``: ``simulate`` on the session's case; each option overrides the case's ``[simulation]``."""

    grid: _JobOption = Field(None, description="grid points per side (an even integer >= 16)")
    realizations: _JobOption = Field(None, description="realizations (>= 1, at most the server's limit)")
    seed: _JobOption = Field(None, description="the random seed (>= 0)")
    workers: _JobOption = Field(None, description="--workers: 0 for one process, no Dask (at most the server's limit)")


#: The request body of ``POST /api/predict`` in ``/openapi.json``: a case file.
TOML_BODY: dict[str, Any] = {"requestBody": {"required": True, "description": "a case file (TOML, UTF-8)", "content": {
    "application/toml": {"schema": {"type": "string"}}}}}


def multipart_body(files: str, many: bool, fields: Sequence[str] = ()) -> dict[str, Any]:
    """The ``openapi_extra`` of an upload route: a multipart form with the file field ``files`` (several if
    ``many``) and the text ``fields``. The route reads the form itself (:mod:`sealeak.web.uploads`, streamed
    to disk), so FastAPI would not know it."""
    file = {"type": "string", "format": "binary"}
    props = {files: {"type": "array", "items": file} if many else file} | {f: {"type": "string"} for f in fields}
    schema = {"type": "object", "properties": props, "required": [files]}
    return {"requestBody": {"required": True, "content": {"multipart/form-data": {"schema": schema}}}}


#: What a member of a type error must be, by pydantic's error type.
_MUST = {"string_type": "must be text", "bool_type": "must be true or false", "dict_type": "must be an object",
         "model_type": "must be an object", "list_type": "must be a list", "int_type": "must be an integer",
         "float_type": "must be a number"}
#: The names pydantic gives the members of a union in an error's location (not members of the request).
_UNION_TAGS = ("str", "float", "bool", "int", "list", "dict", "none")
#: The message of a form field that is not text (the page's own fields are always sent as text).
_FIELD_TEXT = "must be text: every form field is sent as text, e.g. \"0.8\" or \"2.3 MPa\""


@functools.cache
def body_model(endpoint: Callable[..., Any]) -> type[BaseModel] | None:
    """The request model of a route's function (the type of its parameter that is one of these models), or None."""
    hints = typing.get_type_hints(endpoint)
    return next((t for t in hints.values() if isinstance(t, type) and issubclass(t, _Body)), None)


def _members(model: type[BaseModel], path: Sequence[str]) -> list[str]:
    """The members of the model at ``path`` inside ``model`` (a nested object's own members)."""
    for part in path:
        info = model.model_fields.get(part)
        inner = [t for t in get_args(info.annotation) if isinstance(t, type) and issubclass(t, BaseModel)] if info else []
        if not inner:
            break
        model = inner[0]
    return list(model.model_fields)


def refusal(errors: Sequence[Mapping[str, Any]], model: type[BaseModel]) -> InputError | None:
    """The InputError of pydantic's first error in a JSON body of ``model`` (``errors`` as
    ``RequestValidationError.errors()``); None if it is not about a member (the body is no JSON
    object at all, or malformed JSON).

    A form field of ``PUT /api/case/fields`` is named by its own key (``rubber.youngs_modulus``), the
    members of a nested object by their path (``options.size``); a member that may be one of several
    types (a union) is named once, with every type it may be."""
    error = errors[0] if errors else {}
    loc = [str(x) for x in error.get("loc", ())]
    kind = error.get("type", "")
    if len(loc) < 2 or loc[0] != "body" or (kind != "extra_forbidden" and kind not in _MUST):
        return None
    path, value = loc[1:], error.get("input")
    if path[0] == "fields" and len(path) > 1 and model is FieldsBody:  # a form field: named by its case-file key
        return InputError(path[1], value, _FIELD_TEXT if kind == "string_type" else _MUST.get(kind, "must be text"))
    if kind == "extra_forbidden":
        takes = ", ".join(f"'{m}'" for m in _members(model, path[:-1]))
        return InputError(".".join(path), value, f"is not a member of this request; it takes {takes}")

    def name(e: Mapping[str, Any]) -> str:
        return ".".join(str(p) for p in e.get("loc", ())[1:] if str(p).isidentifier() and p not in _UNION_TAGS)

    member = name(error) or path[0]
    kinds = list(dict.fromkeys(_MUST[e["type"]].removeprefix("must be ") for e in errors
                               if e.get("type") in _MUST and (name(e) or path[0]) == member))
    return InputError(member, value, "must be " + (" or ".join(kinds) if len(kinds) < 3 else
                                                   ", ".join(kinds[:-1]) + " or " + kinds[-1]))
