"""Case files in the web app: form fields ↔ TOML, the session's file rule, running a prediction.

No physics here: a case is built by :func:`sealeak.cases.parse_case_bytes` (the command line's own
loader, so the messages are the CLI's) and run by :func:`sealeak.cases.run_case`; the documents
come from :mod:`sealeak.render` (the same functions as ``sealeak predict --json``).

**Files a case may name.** ``surface.file``, ``surface.files``, ``seal.pressure_profile``, ``seal.force_table`` and
``rubber.relaxation.master_curve`` (:data:`~sealeak.cases.loader.FILE_KEYS`; also inside a ``[study]``'s values)
may name only files uploaded in the same browser session, by their
upload name: never a path on the server (``/etc/passwd``, ``../x``, ``sub/x``).
"""

from __future__ import annotations

import contextlib
import dataclasses
import json
import math
import re
import threading
import time
import tomllib
import unicodedata
from collections import OrderedDict
from collections.abc import Callable, Iterator
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
import tomli_w
import tomlkit
from starlette.exceptions import HTTPException as StarletteHTTPException
from tomlkit.exceptions import TOMLKitError

from ..cases import CaseFile, CaseResult, cancel, parse_case_bytes, run_case
from ..cases.form import FORM_SECTIONS, field_kind
from ..cases.form_help import FIELD_HELP
from ..cases.limits import MAX_PRESSURES, at_most
from ..cases.loader import FILE_KEYS, nested_value
from ..cases.schema import SURFACE_KEYS
from ..cases.uncertainty import DEFAULT_SAMPLES, UncertaintyResult, propagate, uncertain_study
from ..errors import FileFormatError, InputError
from ..io.leak_units import STANDARD_PRESSURE, leak_rate_unit
from ..io.tomlscan import MAX_DEPTH, scan_toml
from ..io.units import unit_factor
from ..render import prediction_json

__all__ = ["FILE_KEYS", "DISPLAY_UNITS", "display_units", "form_schema", "doc_fields", "fields_doc", "edit_text", "value_text",
           "text_value", "toml_text", "syntax_error", "check_files", "file_names", "upload_name", "resolve_files", "field_of",
           "load_toml", "Prediction", "PredictionCache", "DEFAULT_CACHE_BYTES", "MAX_WEB_SOLUTIONS"]

#: The most bytes the prediction cache holds (case texts and their results): 256 MB.
DEFAULT_CACHE_BYTES = 256 * 2**20
#: How long (s) a prediction waits for one of the server's computing slots before it is refused (status 503).
PREDICTION_WAIT = 60.0
#: Predictions that may wait for a computing slot at once, per slot: beyond, a prediction is refused at once (503)
#: rather than hold a server thread while it waits.
WAITING_PER_SLOT = 4
#: How often (s) a request waiting for a computing slot, or for the same prediction computed by another request, looks
#: whether its client has gone (it then stops waiting; a prediction nobody waits for stops, :mod:`sealeak.cases.cancel`).
CLIENT_POLL = 0.25
#: The most contact solutions one prediction of the web app may ask for: (uncertainty samples, 1 without spreads) ×
#: the loads of its cases (a band seal's compressions or forces, 1 for a uniform seal's whole sweep). The bundled
#: examples ask for at most 40, the O-ring's uncertainty band 4 608 (~20 s); a case asking for more runs on the command
#: line (``sealeak predict``), where the user owns the machine.
MAX_WEB_SOLUTIONS = 20_000

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
            name = f"{section}.{key}" if section else key
            h = FIELD_HELP[name]
            fields.append({"name": name, "key": key, "kind": k.kind, "dimension": k.dimension, "choices": list(k.choices),
                           "example": k.example, "models": models, "label": h.label, "help": h.help, "anchor": h.anchor})
        out.append({"section": section, "fields": fields})
    return out


#: The units a user may show results in, per dimension (the first is SI, the unit of the JSON records).
DISPLAY_UNITS = {
    "pressure": ["Pa", "kPa", "bar", "psi", "MPa"],
    "length": ["m", "mm", "µm", "nm"],
    "volume_flow": ["m³/s", "ml/min", "mm³/s", "l/h"],
    "throughput": ["Pa·m³/s", "mbar·l/s"],
}


def display_units() -> dict[str, list[dict[str, Any]]]:
    """Each dimension's display units with the factor from SI (value shown = value in SI / factor), taken from
    :mod:`sealeak.io.units` (the library's unit tables). A gas's standard volume flow (``sccm``) is listed with
    the throughput: its factor depends on the gas temperature, so the page takes it from the results' own
    ``leak_rate_sccm`` column; its factor here is that of 0 °C."""
    out: dict[str, list[dict[str, Any]]] = {}
    for dimension, names in DISPLAY_UNITS.items():
        out[dimension] = [{"name": n, "factor": unit_factor("unit", n.replace("·", "*").replace("³", "^3").replace("µ", "u"),
                                                            dimension)} for n in names]
    _kind, sccm = leak_rate_unit("unit", "sccm")  # m³/s at 0 °C and 101325 Pa per sccm
    out["throughput"].append({"name": "sccm", "factor": sccm * STANDARD_PRESSURE, "column": "leak_rate_sccm"})
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

    Text, choice and file fields keep the text as it is (a title ``[Rev B] my ring`` is text).
    Other fields read TOML literals (``0.8``, ``true``, ``["20 kPa", "60 kPa"]``,
    ``{start = "10 kPa", stop = "1 MPa", num = 20}``, ``"2.3 MPa"``) and otherwise keep the text
    (``2.3 MPa``). A malformed list, table or quoted text is refused naming the field.
    """
    section, _, key = name.rpartition(".")
    kind = field_kind(section, key).kind
    if kind in ("text", "choice", "file"):
        return text
    t = text.strip()
    literal = t[:1] in "[{\"" if t else False
    try:
        value = load_toml(f"v = {t}", name)["v"]
    except tomllib.TOMLDecodeError:
        if literal:
            raise InputError(name, text, "is not a valid TOML list, table or quoted text, e.g. [\"20 kPa\", \"60 kPa\"]") from None
        return text
    if isinstance(value, list):  # before any tomlkit item is made of it: the longest list a case file may hold
        at_most(name, value, MAX_PRESSURES, "items", shown=text)
    return value


def load_toml(text: str, field: str) -> dict[str, Any]:
    """``tomllib.loads(text)`` of user text, after the case loader's linear pre-scan of its keys, nesting and
    bare words (:func:`sealeak.io.tomlscan.scan_toml`, the same limits as a case file on the command line).

    Too deep, a key of too many parts, too long a bare word: :class:`~sealeak.errors.InputError` naming
    ``field``; malformed TOML: ``tomllib.TOMLDecodeError`` as from tomllib.
    """
    try:
        scan_toml(text, field)
    except FileFormatError as exc:
        raise InputError(field, None, exc.problem) from None
    try:
        return tomllib.loads(text)
    except RecursionError:  # cannot happen after the scan; kept so that no traceback can ever reach a page
        raise InputError(field, None, f"is nested too deeply: at most {MAX_DEPTH} levels are allowed") from None
    except ValueError as exc:
        if isinstance(exc, tomllib.TOMLDecodeError):
            raise
        raise InputError(field, None, f"malformed TOML: {exc}") from None  # e.g. an integer of over 4300 digits


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


def _toml(value: Any) -> str:
    """A value as TOML text: tables inline (``{start = ..., num = 20}``), as a form shows them."""
    if isinstance(value, dict):
        return "{" + ", ".join(f"{tomlkit.key(k).as_string()} = {_toml(v)}" for k, v in value.items()) + "}"
    if isinstance(value, list):
        return "[" + ", ".join(_toml(v) for v in value) + "]"
    return str(tomlkit.item(value).as_string())


def _item(value: Any) -> Any:
    """A value as a tomlkit item, tables inline. Parsed from its text (:func:`_toml`): tomlkit builds an array
    element by element in a time growing with the square of its length (a form's list of 10 000 pressures took
    7 s, 40 000 took 150 s), and reads the same array from text in linear time."""
    return tomlkit.parse("v = " + _toml(value) + "\n")["v"]


def edit_text(text: str | None, fields: dict[str, str]) -> str:
    """The case text ``text`` with the form's ``fields`` applied, its comments and order kept.

    A field whose text is what the form showed for the current value keeps that value exactly (its
    type, its quoting); a changed field takes :func:`text_value`; a field left out or emptied removes
    its key (and a section left empty). An unknown or malformed changed field is an InputError naming it.
    """
    old = tomllib.loads(text) if text else {}
    shown = doc_fields(old)
    given = {k: v for k, v in fields.items() if isinstance(v, str) and v.strip()}
    changed = fields_doc({k: v for k, v in given.items() if shown.get(k) != v})
    doc = tomlkit.parse(text) if text else tomlkit.document()
    for name in shown:
        if name not in given:
            section, _, key = name.rpartition(".")
            if section and section in FORM_SECTIONS:
                del doc[section][key]  # type: ignore[union-attr]
                if not doc[section]:
                    del doc[section]
            else:
                del doc[name]
    for name, value in changed.items():
        if isinstance(value, dict) and name in FORM_SECTIONS and name:
            if name not in doc:
                doc[name] = tomlkit.table()
            for key, v in value.items():
                doc[name][key] = _item(v)  # type: ignore[index]
        else:
            doc[name] = _item(value)
    return tomlkit.dumps(doc)


_AT = re.compile(r"\(at line (\d+), column (\d+)\)")


def syntax_error(text: str) -> dict[str, Any] | None:
    """None if ``text`` is TOML the app can read and edit, else where it is not: ``{"message", "line", "column"}``
    (1-based; 0 if unknown). Text nested too deeply, with too long a dotted key or bare word is named by the
    case loader's pre-scan (:func:`sealeak.io.tomlscan.scan_toml`) before any parser reads it."""
    try:
        scan_toml(text, "case")
    except FileFormatError as exc:
        at = re.match(r"line (\d+): ", exc.problem)
        return {"message": exc.problem, "line": int(at.group(1)) if at else 0, "column": 0}
    try:
        tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        m = _AT.search(str(exc))
        return {"message": f"malformed TOML: {exc}", "line": int(m.group(1)) if m else 0, "column": int(m.group(2)) if m else 0}
    except RecursionError:
        return {"message": "malformed TOML: nested too deeply", "line": 0, "column": 0}
    try:  # what the form's edits go through: it refuses what tomllib reads but nests too deeply
        tomlkit.parse(text)
    except TOMLKitError as exc:
        return {"message": f"malformed TOML: {exc}", "line": getattr(exc, "line", 0), "column": getattr(exc, "col", 0)}
    return None


def _study_paths(vary: Any) -> Iterator[tuple[str, ...]]:
    """For each of :data:`FILE_KEYS` that ``study.vary`` is or holds, its keys below ``vary``: the study's values are
    then the file names (no keys below) or tables holding them (``vary = "seal"``: ``{force_table = …}``)."""
    for keys in FILE_KEYS:
        for n in range(1, len(keys) + 1):
            if vary == ".".join(keys[:n]):
                yield keys[n:]


def file_names(doc: dict[str, Any]) -> Iterator[tuple[str, Any]]:
    """Every (field, value) of ``doc`` that names a file, also in a ``[study]``'s values."""
    for keys in FILE_KEYS:
        value = nested_value(doc, keys)
        if value is not None:
            yield ".".join(keys), value
    study = doc.get("study")
    if isinstance(study, dict) and isinstance(study.get("values"), list):
        for i, value in enumerate(study["values"]):
            for below in _study_paths(study.get("vary")):
                named = nested_value(value, below)
                if named is not None:
                    yield ".".join((f"study.values[{i}]", *below)), named


#: Letters NFKD does not decompose into ASCII, as an engineer would write them in a file name.
_ASCII = str.maketrans({"\u00b5": "u", "\u03bc": "u", "\u00d8": "O", "\u00f8": "o", "\u00df": "ss", "\u00c6": "AE",
                        "\u00e6": "ae", "\u0152": "OE", "\u0153": "oe", "\u0141": "L", "\u0142": "l", "\u00d0": "D",
                        "\u0111": "d", "\u00b0": "deg"})


def upload_name(name: str) -> str:
    """The safe name under which an uploaded file is stored: ``name`` without any folder, its letters
    folded to ASCII (NFKC, then accents dropped: ``ü`` → ``u``, ``µ`` → ``u``, ``Ø`` → ``O``), every
    other character outside ``A-Z a-z 0-9 . _ - + ( )`` and space replaced by ``_``, no leading dot or
    ``..``, at most 128 characters (the suffix kept; a name of no letters before it, ``名前.txt``, is ``file.txt``).
    Never refused: ``Probe Ø5 µm #3;b.csv`` is stored as ``Probe O5 um _3_b.csv``; the user's name is only ever
    shown, never used as a path."""
    base = str(name).replace("\\", "/").rsplit("/", 1)[-1]
    text = unicodedata.normalize("NFKC", base).translate(_ASCII)
    text = "".join(c for c in unicodedata.normalize("NFKD", text) if not unicodedata.combining(c))
    text = re.sub(r"[^A-Za-z0-9._ +()-]+", "_", text)
    text = re.sub(r"\.{2,}", ".", text)
    stem, dot, suffix = text.rpartition(".")
    if stem and not stem.strip(" ._-+()") and suffix.strip(" _"):  # "名前.txt" (now "_.txt") keeps its suffix: "file.txt"
        text = "file." + suffix.strip(" _")
    text = text.strip(" ._")
    stem, dot, suffix = text.rpartition(".")
    if len(text) > 128:
        text = (stem[: 127 - len(suffix)] + dot + suffix) if dot and len(suffix) <= 16 else text[:128]
    if not text or not text[0].isalnum():
        text = "file" + ("" if not text else "_" + text)
    return text


def _plain(name: Any) -> bool:
    """A plain file name (no folder, not hidden, printable): a case may name an upload by it."""
    return isinstance(name, str) and bool(name) and "/" not in name and "\\" not in name and not name.startswith(".") \
        and name.isprintable() and len(name) <= 255


def _stored(name: Any, uploaded: set[str]) -> str | None:
    """The uploaded file a case's file name refers to (the name itself, or its safe stored name), or None."""
    if not _plain(name):
        return None
    if name in uploaded and _NAME.match(name) and ".." not in name:
        return str(name)
    safe = upload_name(name)
    return safe if safe in uploaded else None


def resolve_files(doc: dict[str, Any], uploaded: set[str]) -> dict[str, Any]:
    """``doc`` with each file name replaced by the name the upload is stored under (a copy; ``doc`` if none changes).

    A case may name ``Probe Ø5 µm.csv``: the file uploaded under that name is stored as
    ``Probe O5 um.csv`` (:func:`upload_name`), which the loader then reads."""
    renames = {n: _stored(n, uploaded) for _, v in file_names(doc) for n in (v if isinstance(v, list) else [v])
               if isinstance(n, str)}
    renames = {k: v for k, v in renames.items() if v is not None and v != k}
    if not renames:
        return doc

    def swap(value: Any) -> Any:
        return [renames.get(v, v) if isinstance(v, str) else v for v in value] if isinstance(value, list) \
            else renames.get(value, value) if isinstance(value, str) else value
    out = doc
    for keys in FILE_KEYS:
        out = _swapped(out, keys, swap)
    study = out.get("study")
    if isinstance(study, dict) and isinstance(study.get("values"), list):
        values = list(study["values"])
        for i in range(len(values)):
            for below in _study_paths(study.get("vary")):
                values[i] = _swapped(values[i], below, swap) if below else swap(values[i])
        out = {**out, "study": {**study, "values": values}}
    return out


def _swapped(table: Any, keys: tuple[str, ...], swap: Callable[[Any], Any]) -> Any:
    """``table`` with ``swap`` applied to the value at ``keys`` in its nested tables (the tables on the way copied, the
    others shared), or ``table`` itself where there is no such value."""
    if not isinstance(table, dict) or keys[0] not in table:
        return table
    value = table[keys[0]]
    return {**table, keys[0]: swap(value) if len(keys) == 1 else _swapped(value, keys[1:], swap)}


def check_files(doc: dict[str, Any], uploaded: set[str]) -> None:
    """Refuse a case naming a file that was not uploaded in this session (a server path, ``..``, an unknown name)."""
    for where, value in file_names(doc):
        for name in value if isinstance(value, list) else [value]:
            if _stored(name, uploaded) is not None:
                continue
            allowed = ", ".join(sorted(uploaded)) if uploaded else "none yet"
            raise InputError(where, name, "must name a file uploaded in this session (on the Surface page, or with "
                                          f"the case); paths on the server are not allowed; uploaded: {allowed}")


_FIELD = re.compile(r"^((?:[a-z_]+\.)?[A-Za-z0-9_]+)")
_OPTION = re.compile(r"^--[a-z][a-z0-9-]*$")


def field_of(exc: InputError) -> str:
    """The form field an error names: ``conditions.squeeze_pressure[1]`` → ``conditions.squeeze_pressure``; an option
    of the surface analysis by its command-line name (``--periodic``)."""
    if _OPTION.match(exc.field):
        return exc.field
    m = _FIELD.match(exc.field)
    return m.group(1) if m else ""


@dataclass(frozen=True)
class Prediction:
    """A case file run as ``sealeak predict`` runs it: the case file, the result of each case and, for a case file with
    uncertain inputs, their propagation (``predict``'s default samples and seed)."""

    case_file: CaseFile
    results: list[CaseResult]
    rendered: dict[str, str] = field(default_factory=dict, compare=False)  # documents rendered once, by name
    uncertainty: UncertaintyResult | None = None

    def json(self) -> str:
        """The ``sealeak predict --json`` document (rendered once)."""
        if "json" not in self.rendered:
            self.rendered["json"] = prediction_json(self.results, self.uncertainty)
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

    def __init__(self, size: int = 64, max_bytes: int = DEFAULT_CACHE_BYTES, computing: int = 2,
                 wait: float = PREDICTION_WAIT) -> None:
        self.size = size
        self.max_bytes = max_bytes
        self.computing = computing
        self.wait = wait
        self._slots = threading.BoundedSemaphore(computing)  # predictions computed at once on this server
        self._sizes: dict[tuple[Any, ...], int] = {}  # the case text and results of each entry (bytes)
        self._items: OrderedDict[tuple[Any, ...], Prediction] = OrderedDict()
        self._lock = threading.Lock()
        self._running: dict[tuple[Any, ...], threading.Event] = {}
        self._clients: dict[tuple[Any, ...], list[_Client]] = {}  # per running key: the requests waiting for it
        self._waiting = 0  # predictions waiting for a slot

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
        resolved = doc
        if doc is not None:
            check_files(doc, uploaded)
            resolved = resolve_files(doc, uploaded)
            named = {n for _, v in file_names(resolved) for n in (v if isinstance(v, list) else [v])}
        # a case that names no file is the same case in every session; one that does depends on the files' contents
        files = tuple(sorted((n, (uploads / n).stat().st_size, (uploads / n).stat().st_mtime_ns) for n in named))
        key = (data, source, str(uploads) if named or doc is None else "", files)
        # this request, as one entry of a computation's list of requests (whether its client has gone: the web
        # server's Guard tells; a call from Python never goes): an object of its own, so that it removes itself only
        me = _Client(cancel.current() or _stays)
        while True:
            with self._lock:
                hit = self._items.get(key)
                if hit is not None:
                    self._items.move_to_end(key)
                    return hit
                running = self._running.get(key)
                if running is None:  # this thread computes it; the same request arriving meanwhile waits for it
                    running = self._running[key] = threading.Event()
                    self._clients[key] = [me]
                    break
                clients = self._clients[key]  # (that computation's list: another may follow it under the same key)
                clients.append(me)
            try:
                while not running.wait(CLIENT_POLL):
                    cancel.check()
            finally:
                with self._lock:
                    clients.remove(me)
        try:
            # read and checked before a computing slot is taken: a case the loader refuses needs none
            # (a case naming "Probe Ø5.csv" is read with the name its upload is stored under)
            loaded = data if resolved is doc or resolved is None else toml_text(resolved).encode("utf-8")
            case_file = parse_case_bytes(loaded, uploads, source)
            _check_cost(case_file)
            # stopped (cancel.Cancelled) once every request waiting for it has gone, while it waits for a slot too:
            # nobody would read the result
            with cancel.cancellable(lambda: self._abandoned(key)), self.slot():
                if case_file.spreads.active:  # as `sealeak predict` without options: its default samples and seed
                    unc = propagate(uncertain_study(case_file), DEFAULT_SAMPLES, 0)
                    result = Prediction(case_file, unc.nominal, uncertainty=unc)
                else:
                    result = Prediction(case_file, [run_case(c) for c in case_file.cases])
            size = len(data) + footprint((result.results, result.uncertainty))
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
                del self._clients[key]
            running.set()

    def _abandoned(self, key: tuple[Any, ...]) -> bool:
        """Whether every request that waits for the prediction of ``key`` has lost its client."""
        with self._lock:
            clients = self._clients.get(key, [])
            return bool(clients) and all(c.gone() for c in clients)

    @contextlib.contextmanager
    def slot(self) -> Iterator[None]:
        """Hold one of the server's computing slots (a prediction's computation, a surface analysis)."""
        self._take_slot()
        try:
            yield
        finally:
            self._slots.release()

    def _take_slot(self) -> None:
        """Take one of the server's computing slots, waiting up to ``wait`` s; a 503 when none frees in time, or at
        once when ``WAITING_PER_SLOT`` × ``computing`` predictions wait already (each holds a server thread)."""
        with self._lock:
            if self._waiting >= WAITING_PER_SLOT * self.computing:
                raise StarletteHTTPException(503, f"predict: {self.computing} predictions are running on this server and "
                                                  f"{self._waiting} are waiting (at most {self.computing} and "
                                                  f"{WAITING_PER_SLOT * self.computing}); try again when one has finished")
            self._waiting += 1
        try:
            deadline = time.monotonic() + self.wait
            while not self._slots.acquire(timeout=max(min(CLIENT_POLL, deadline - time.monotonic()), 0.0)):
                cancel.check()  # (a request whose client has gone stops waiting)
                if time.monotonic() < deadline:
                    continue
                # the server's cores are busy with other cases
                raise StarletteHTTPException(503, f"predict: {self.computing} predictions are running on this server "
                                                  f"already (at most {self.computing}); try again when one has finished")
        finally:
            with self._lock:
                self._waiting -= 1


def _stays() -> bool:
    """A request without a client to lose (a call from Python, a test)."""
    return False


@dataclass(eq=False)
class _Client:
    """One request waiting for a prediction: ``gone`` answers whether its client has left (compared by identity)."""

    gone: Callable[[], bool]


def _check_cost(case_file: CaseFile) -> None:
    """Refuse a case whose prediction asks for more than :data:`MAX_WEB_SOLUTIONS` contact solutions (samples ×
    loads), naming what it asks for: one request must not hold a computing slot for hours."""
    loads = sum(len(c.band.loads) if c.band is not None else 1 for c in case_file.cases)
    samples = DEFAULT_SAMPLES if case_file.spreads.active else 1
    if samples * loads > MAX_WEB_SOLUTIONS:
        what = f"{samples} uncertainty samples × {loads} loads" if samples > 1 else f"{loads} loads"
        raise InputError("case", f"{len(case_file.cases)} case(s)",
                         f"asks for {what} ({samples * loads} contact solutions): the web app computes at most "
                         f"{MAX_WEB_SOLUTIONS} per prediction; run it with `sealeak predict` on the command line")


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
