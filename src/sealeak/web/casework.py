"""Case files in the web app: form fields ↔ TOML, the session's file rule, running a prediction.

No physics here: a case is built by :func:`sealeak.cases.parse_case_bytes` (the command line's own
loader, so the messages are the CLI's) and run by :func:`sealeak.cases.run_case`; the documents
come from :mod:`sealeak.render` (the same functions as ``sealeak predict --json``).

**Files a case may name.** ``surface.file``, ``surface.files`` and ``seal.pressure_profile`` (also
inside a ``[study]``'s values) may name only files uploaded in the same browser session, by their
upload name: never a path on the server (``/etc/passwd``, ``../x``, ``sub/x``).
"""

from __future__ import annotations

import dataclasses
import json
import math
import re
import threading
import tomllib
from collections import OrderedDict
from collections.abc import Iterator
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
import tomli_w

from ..cases import CaseFile, CaseResult, parse_case_bytes, run_case
from ..cases.form import FORM_SECTIONS, field_kind
from ..cases.schema import SURFACE_KEYS
from ..errors import InputError
from ..render import prediction_json
from .security import MAX_NESTING, check_nesting

__all__ = ["FILE_KEYS", "form_schema", "doc_fields", "fields_doc", "value_text", "text_value", "toml_text", "check_files",
           "file_names", "upload_name", "field_of", "load_toml", "Prediction", "PredictionCache", "DEFAULT_CACHE_BYTES"]

#: The most bytes the prediction cache holds (case texts and their results): 256 MB.
DEFAULT_CACHE_BYTES = 256 * 2**20

#: The keys whose values are file names (each must be a file uploaded in the session).
FILE_KEYS = (("surface", "file"), ("surface", "files"), ("seal", "pressure_profile"))

_NAME = re.compile(r"^[A-Za-z0-9][A-Za-z0-9._ +()-]{0,127}$")


def form_schema() -> list[dict[str, Any]]:
    """The sections of the case form, each key with its kind (:mod:`sealeak.cases.form`), as JSON.

    A ``[surface]`` key lists the surface models that read it (``models``): the form hides the
    empty keys of the other models."""
    out = []
    for section, keys in FORM_SECTIONS.items():
        fields = []
        for key in keys:
            k = field_kind(section, key)
            models = [m for m, keys in SURFACE_KEYS.items() if key in keys] if section == "surface" else []
            fields.append({"name": f"{section}.{key}" if section else key, "key": key, "kind": k.kind,
                           "dimension": k.dimension, "choices": list(k.choices), "example": k.example, "models": models})
        out.append({"section": section, "fields": fields})
    return out


def _inline(value: Any) -> str:
    """A TOML value written inline (one line): strings quoted, lists ``[...]``, tables ``{k = v}``."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, str):
        return json.dumps(value, ensure_ascii=False)
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        return ("nan" if math.isnan(value) else ("inf" if value > 0 else "-inf")) if not math.isfinite(value) else repr(value)
    if isinstance(value, list):
        return "[" + ", ".join(_inline(v) for v in value) + "]"
    if isinstance(value, dict):
        return "{" + ", ".join(f"{_key(k)} = {_inline(v)}" for k, v in value.items()) + "}"
    return json.dumps(str(value))  # dates and times of TOML: kept as text


def _key(k: str) -> str:
    return k if re.fullmatch(r"[A-Za-z0-9_-]+", k) else json.dumps(k)


def value_text(value: Any) -> str:
    """What a form field shows for a TOML value: text as it is, anything else in TOML syntax."""
    return value if isinstance(value, str) else _inline(value)


def text_value(name: str, text: str) -> Any:
    """The TOML value of a form field's text.

    Text, choice and file fields keep the text as it is, unless it starts with ``[``, ``{`` or
    ``"`` (a list, a table or a quoted string in TOML syntax). Other fields read TOML literals
    (``0.8``, ``true``, ``["20 kPa", "60 kPa"]``, ``{start = "10 kPa", stop = "1 MPa", num = 20}``)
    and otherwise keep the text (``"2.3 MPa"``). A malformed list or table is refused naming the field.
    """
    section, _, key = name.rpartition(".")
    kind = field_kind(section, key).kind
    t = text.strip()
    literal = t[:1] in "[{\"" if t else False
    if kind in ("text", "choice", "file") and not literal:
        return text
    try:
        return load_toml(f"v = {t}", name)["v"]
    except tomllib.TOMLDecodeError:
        if literal:
            raise InputError(name, text, "is not a valid TOML list, table or quoted text, e.g. [\"20 kPa\", \"60 kPa\"]") from None
        return text


def load_toml(text: str, field: str) -> dict[str, Any]:
    """``tomllib.loads(text)`` of user text, its nesting and dotted keys checked first (:func:`~sealeak.web.security.check_nesting`).

    Too deep, or a key of too many parts: :class:`~sealeak.errors.InputError` naming ``field``;
    malformed TOML: ``tomllib.TOMLDecodeError`` as from tomllib.
    """
    why = check_nesting(text.encode("utf-8", "replace"))
    if why is not None:
        raise InputError(field, None, why)
    try:
        return tomllib.loads(text)
    except RecursionError:  # a structure the scan did not see (it cannot parse TOML exactly)
        raise InputError(field, None, f"is nested too deeply: at most {MAX_NESTING} levels are allowed") from None


def doc_fields(doc: dict[str, Any]) -> dict[str, str]:
    """The form's fields (``section.key`` → text) of a TOML document; keys the form lacks are kept too."""
    out: dict[str, str] = {}
    for name, value in doc.items():
        if isinstance(value, dict) and name in FORM_SECTIONS:
            for key, v in value.items():
                out[f"{name}.{key}"] = value_text(v)
        else:
            out[name] = value_text(value)
    return out


def fields_doc(fields: dict[str, str]) -> dict[str, Any]:
    """A TOML document from the form's fields (empty fields are left out: the key takes its default)."""
    doc: dict[str, Any] = {}
    tables: dict[str, dict[str, Any]] = {}
    for name, text in fields.items():
        if not isinstance(text, str) or not text.strip():
            continue
        section, _, key = name.rpartition(".")
        if section and section in FORM_SECTIONS and key in FORM_SECTIONS[section]:
            tables.setdefault(section, {})[key] = text_value(name, text)
        elif not section and name in FORM_SECTIONS[""]:
            doc[name] = text_value(name, text)
        else:
            raise InputError(name, text, "is not a case-file key")
    return doc | {s: tables[s] for s in FORM_SECTIONS if s in tables}


def toml_text(doc: dict[str, Any]) -> str:
    """The case file of a document, as TOML text."""
    return tomli_w.dumps(doc)


def file_names(doc: dict[str, Any]) -> Iterator[tuple[str, Any]]:
    """Every (field, value) of ``doc`` that names a file, also in a ``[study]``'s values."""
    for section, key in FILE_KEYS:
        table = doc.get(section)
        if isinstance(table, dict) and key in table:
            yield f"{section}.{key}", table[key]
    study = doc.get("study")
    if isinstance(study, dict) and isinstance(study.get("values"), list):
        vary = study.get("vary")
        for i, value in enumerate(study["values"]):
            for section, key in FILE_KEYS:
                if vary == f"{section}.{key}":
                    yield f"study.values[{i}]", value
                elif vary == section and isinstance(value, dict) and key in value:
                    yield f"study.values[{i}].{key}", value[key]


def upload_name(name: str) -> str:
    """``name`` if it can be the name of an uploaded file (a plain file name, no folder, no ``..``), else InputError."""
    if not isinstance(name, str) or not _NAME.match(name) or ".." in name:
        raise InputError("file", name, "must be a plain file name (letters, digits, . _ - + ( ) and spaces; no folder)")
    return name


def check_files(doc: dict[str, Any], uploaded: set[str]) -> None:
    """Refuse a case naming a file that was not uploaded in this session (a server path, ``..``, an unknown name)."""
    for where, value in file_names(doc):
        for name in value if isinstance(value, list) else [value]:
            if isinstance(name, str) and name in uploaded and _NAME.match(name) and ".." not in name:
                continue
            allowed = ", ".join(sorted(uploaded)) if uploaded else "none yet"
            raise InputError(where, name, "must name a file uploaded in this session (on the Surface page, or with "
                                          f"the case); paths on the server are not allowed; uploaded: {allowed}")


_FIELD = re.compile(r"^((?:[a-z_]+\.)?[A-Za-z0-9_]+)")


def field_of(exc: InputError) -> str:
    """The form field an error names: ``conditions.squeeze_pressure[1]`` → ``conditions.squeeze_pressure``."""
    m = _FIELD.match(exc.field)
    return m.group(1) if m else ""


@dataclass(frozen=True)
class Prediction:
    """A case file run as ``sealeak predict`` runs it: the case file and the result of each case."""

    case_file: CaseFile
    results: list[CaseResult]
    rendered: dict[str, str] = field(default_factory=dict, compare=False)  # documents rendered once, by name

    def json(self) -> str:
        """The ``sealeak predict --json`` document (rendered once)."""
        if "json" not in self.rendered:
            self.rendered["json"] = prediction_json(self.results)
        return self.rendered["json"]


class PredictionCache:
    """Predictions by (case text, source name, uploaded files): a case run once answers again at once.

    The key holds the name, size and modification time of each uploaded file the case names, so a
    file uploaded anew under the same name runs the case again; a case that names no file is shared
    by every session. Thread-safe; keeps the ``size`` most recent, and at most ``max_bytes`` bytes
    (the case texts, the arrays and texts of their results, :func:`footprint`, and the documents
    rendered from them, counted when the next case is added). Requests
    for a case being computed wait for that computation instead of repeating it (an error is not
    cached: each of them then computes, and reports, it for itself).
    """

    def __init__(self, size: int = 64, max_bytes: int = DEFAULT_CACHE_BYTES) -> None:
        self.size = size
        self.max_bytes = max_bytes
        self._sizes: dict[tuple[Any, ...], int] = {}  # the case text and results of each entry (bytes)
        self._items: OrderedDict[tuple[Any, ...], Prediction] = OrderedDict()
        self._lock = threading.Lock()
        self._running: dict[tuple[Any, ...], threading.Event] = {}

    def __len__(self) -> int:
        with self._lock:
            return len(self._items)

    @property
    def nbytes(self) -> int:
        """The bytes held: the case texts, their results and the documents rendered from them since."""
        with self._lock:
            return self._bytes()

    def _bytes(self) -> int:
        return sum(self._sizes[k] + sum(len(v) for v in list(p.rendered.values())) for k, p in self._items.items())

    def predict(self, data: bytes, source: str, uploads: Path) -> Prediction:
        """Check the case's file names against ``uploads``, build the case(s) and run them (or take them from the cache)."""
        try:
            doc = load_toml(data.decode("utf-8-sig"), source)
        except (UnicodeDecodeError, tomllib.TOMLDecodeError):
            doc = None  # the loader below refuses it with the command line's message
        uploaded = {p.name for p in uploads.iterdir() if p.is_file()} if uploads.is_dir() else set()
        named = set()
        if doc is not None:
            check_files(doc, uploaded)
            named = {n for _, v in file_names(doc) for n in (v if isinstance(v, list) else [v])}
        # a case that names no file is the same case in every session; one that does depends on the files' contents
        files = tuple(sorted((n, (uploads / n).stat().st_size, (uploads / n).stat().st_mtime_ns) for n in named))
        key = (data, source, str(uploads) if named or doc is None else "", files)
        while True:
            with self._lock:
                hit = self._items.get(key)
                if hit is not None:
                    self._items.move_to_end(key)
                    return hit
                running = self._running.get(key)
                if running is None:  # this thread computes it; the same request arriving meanwhile waits for it
                    running = self._running[key] = threading.Event()
                    break
            running.wait()
        try:
            case_file = parse_case_bytes(data, uploads, source)
            result = Prediction(case_file, [run_case(c) for c in case_file.cases])
            size = len(data) + footprint(result.results)
            with self._lock:
                if size <= self.max_bytes:
                    self._items[key], self._sizes[key] = result, size
                while len(self._items) > self.size or self._bytes() > self.max_bytes:
                    old, _ = self._items.popitem(last=False)
                    del self._sizes[old]
            return result
        finally:
            with self._lock:
                del self._running[key]
            running.set()


def footprint(obj: Any, _seen: set[int] | None = None) -> int:
    """About the bytes ``obj`` holds: its NumPy arrays, texts and bytes, through dataclasses, lists, tuples and dicts."""
    seen = set() if _seen is None else _seen
    if id(obj) in seen:
        return 0
    seen.add(id(obj))
    if isinstance(obj, np.ndarray):
        return int(obj.nbytes)
    if isinstance(obj, (str, bytes, bytearray)):
        return len(obj)
    if isinstance(obj, dict):
        return sum(footprint(k, seen) + footprint(v, seen) for k, v in obj.items())
    if isinstance(obj, (list, tuple, set, frozenset)):
        return 8 * len(obj) + sum(footprint(v, seen) for v in obj)
    if dataclasses.is_dataclass(obj) and not isinstance(obj, type):
        return sum(footprint(getattr(obj, f.name, None), seen) for f in dataclasses.fields(obj))
    return 8
