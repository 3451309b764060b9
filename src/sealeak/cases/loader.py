"""Case files: TOML with quantities in any units, read into :class:`~sealeak.cases.model.Case` objects.

Format (``docs/case-files.md`` lists every key)::

    title = "PDMS ring on sandpaper"

    [surface]
    model = "self-affine"              # or "table" with file = "psd.csv"
    h_rms = "44 um"                    # or C0 = "... m^4"
    hurst = 0.8
    rolloff_wavevector = "9.1e3 1/m"   # or rolloff_wavelength = "0.69 mm"
    cutoff_wavevector = "3.14e5 1/m"   # q1; or cutoff_wavelength = "20 um"
    # lowest_wavevector = "..."        # where C(q) starts (or lowest_wavelength); default: q0

    [rubber]
    youngs_modulus = "2.3 MPa"
    poisson_ratio = 0.5

    [seal]
    shape = "ring"                     # or "rectangle" with width (Lx, along the flow) and length (Ly)
    inner_diameter = "3 cm"
    outer_diameter = "4 cm"

    [fluid]
    viscosity = "1 mPa*s"

    [conditions]
    squeeze_pressure = ["20 kPa", "60 kPa"]   # or {start = "...", stop = "...", num = 50, spacing = "log"}
    pressure_difference = "10 kPa"

    [theory]
    alpha = 0.2
    percolation_threshold = 0.6
    gamma = 1.0
    # lowest_wavevector = "..."        # override q0 = 2π/Lx (or square_side = "...")

    [study]                            # optional: one case per value of one key
    vary = "surface.h_rms"
    values = ["1 um", "2 um", "4 um"]

Every unknown section or key, missing field, wrong unit or out-of-range value raises a
:class:`~sealeak.errors.SealeakError` naming the field (``section.key``) and the value. What a case
may ask for is bounded before any work (:mod:`sealeak.cases.limits`, :mod:`sealeak.io.tomlscan`).
"""

from __future__ import annotations

import copy
import re
from collections.abc import Callable
from dataclasses import dataclass
from importlib import resources
from pathlib import Path
from typing import Any

from ..errors import FileFormatError, InputError, SealeakError, show_value
from ..io.files import input_file
from ..io.tomlscan import parse_toml
from .builders import build_case, check_sections
from .life import life_cases
from .limits import MAX_CASE_FILE_BYTES, MAX_STUDY_VALUES, at_most
from .model import Case
from .schema import SECTIONS, Section
from .spreads import Spreads, split_spreads

__all__ = ["CaseFile", "read_case_file", "parse_case_file", "parse_case_bytes", "load_cases", "load_case", "parse_cases",
           "example_names", "example_text", "example_path", "example_data_names", "example_description", "named_files",
           "FILE_KEYS", "nested_value", "shown_source", "build_cases"]

@dataclass(frozen=True)
class CaseFile:
    """A case file as read: its cases (one, or one per value of a ``[study]``), and the TOML
    document as the user wrote it (quantities with their units; for the report's inputs table)."""

    cases: list[Case]
    inputs: dict[str, Any]
    source: str
    #: The data files the case names (:data:`FILE_KEYS`: ``surface.file``/``files``, ``seal.pressure_profile``, ...), of every
    #: study variant, as paths (relative names joined to the case file's folder): inputs that no output
    #: of a run may replace.
    files: tuple[Path, ...] = ()
    #: The uncertain inputs and the specification (``conditions.max_leak_rate``) the file gives
    #: (:mod:`sealeak.cases.spreads`); ``cases`` are built from the nominal values.
    spreads: Spreads = Spreads()
    #: The nominal document (spreads taken out) the cases were built from: :func:`build_cases` builds the cases of
    #: other values from a copy of it (the uncertainty propagation, :mod:`sealeak.cases.uncertainty`).
    document: dict[str, Any] | None = None
    case_dir: Path = Path(".")


#: The keys whose values name data files, each as its path of keys ((section, key), or deeper in an inline table).
FILE_KEYS = (("surface", "file"), ("surface", "files"), ("seal", "pressure_profile"), ("seal", "force_table"),
             ("rubber", "relaxation", "master_curve"))


def nested_value(table: Any, keys: tuple[str, ...] | list[str]) -> Any:
    """The value at ``keys`` in nested tables (``doc["rubber"]["relaxation"]["master_curve"]``), or None where a
    table on the way is missing or not a table."""
    for key in keys:
        if not isinstance(table, dict):
            return None
        table = table.get(key)
    return table


def named_files(doc: dict[str, Any], case_dir: Path) -> list[Path]:
    """The data files a parsed case document names (relative names joined to ``case_dir``); values
    that are not file names are left to the builders, which refuse them with the key's name."""
    out: list[Path] = []
    for keys in FILE_KEYS:
        value = nested_value(doc, keys)
        for name in value if isinstance(value, list) else [value]:
            if isinstance(name, str) and name and "\x00" not in name:
                out.append(Path(name) if Path(name).is_absolute() else case_dir / name)
    return out


def parse_case_file(text: str, case_dir: Path | str = ".", source: str = "<text>") -> CaseFile:
    """Read TOML text into a :class:`CaseFile` (relative file names are relative to ``case_dir``).

    Text of more than :data:`~sealeak.cases.limits.MAX_CASE_FILE_BYTES` bytes is refused; the rest is
    pre-scanned (:func:`sealeak.io.tomlscan.parse_toml`): keys of too many parts, nesting too deep and
    over-long bare words are refused before tomllib reads it.
    """
    if len(text) > MAX_CASE_FILE_BYTES:  # characters: never more than the bytes they take in UTF-8
        _check_size(source, len(text.encode("utf-8", "surrogatepass")))
    doc = parse_toml(text, source)
    case_dir = Path(case_dir)
    inputs = copy.deepcopy(doc)
    spreads = split_spreads(doc)
    nominal = copy.deepcopy(doc)
    cases, files = build_cases(doc, case_dir, source)
    return CaseFile(cases, inputs, source, files, spreads, nominal, case_dir)


def build_cases(doc: dict[str, Any], case_dir: Path, source: str) -> tuple[list[Case], tuple[Path, ...]]:
    """The cases of a parsed case document without spreads (one, or one per value of its ``[study]``; ``doc`` loses
    its ``[study]``) and the data files they name."""
    study = doc.pop("study", None)

    def build(variant: dict[str, Any], label: str = "") -> list[Case]:  # one case, or one per time and temperature
        check_sections(variant)  # (before the life keys rewrite [conditions] and [rubber])
        life = life_cases(variant, lambda d, lbl: build_case(d, case_dir, source, label=lbl), label, case_dir)
        return [build_case(variant, case_dir, source, label=label)] if life is None else life

    if study is None:
        return build(doc), tuple(named_files(doc, case_dir))
    sec = Section("study", study)
    vary = sec.raw("vary")
    whole = isinstance(vary, str) and vary in SECTIONS and vary not in ("study", "simulation")
    if not whole and (not isinstance(vary, str) or vary.count(".") != 1):
        raise InputError("study.vary", vary, "must name one key as 'section.key', e.g. 'surface.h_rms', or a section "
                                             "such as 'fluid' whose values are tables")
    section, key = (vary, "") if whole else vary.split(".")
    if section not in SECTIONS or section == "study" or not (whole or key in SECTIONS[section]):
        raise InputError("study.vary", vary, "names no known case-file key")
    values = sec.raw("values")
    if not isinstance(values, list) or not values:
        raise InputError("study.values", values, "must be a non-empty list of values for " + vary)
    at_most("study.values", values, MAX_STUDY_VALUES, "values (one case each)")
    if whole:
        for i, v in enumerate(values):
            if not isinstance(v, dict):
                raise InputError(f"study.values[{i}]", v, f"must be a table of [{section}] keys, e.g. "
                                                           "{name = \"oil\", viscosity = \"50 mPa*s\"}")
    labels = sec.raw("labels", [str(v.get("name") or f"{section} {i + 1}") if whole else f"{key} = {v}"
                                for i, v in enumerate(values)])
    if not isinstance(labels, list) or len(labels) != len(values):
        raise InputError("study.labels", labels, f"must be a list of {len(values)} names")
    def variant_of(value: Any) -> dict[str, Any]:
        variant = copy.deepcopy(doc)
        if whole:  # the table's keys replace the section's
            variant[section] = {**variant.get(section, {}), **value}
        else:
            variant.setdefault(section, {})[key] = value
        return variant

    cases, files = [], named_files(doc, case_dir)
    for i, (value, label) in enumerate(zip(values, labels)):
        variant = variant_of(value)
        files += named_files(variant, case_dir)
        try:
            cases += build(variant, str(label))
        except InputError as exc:
            if not _fails_alike(exc, lambda: build(variant_of(values[(i + 1) % len(values)]), "")):
                raise InputError(f"{exc.field} (study value {show_value(value)})", exc.value, exc.allowed) from None
            raise
    _check_shadowed(doc, section, [key] if not whole else list(values[0]), values, build)
    return cases, tuple(dict.fromkeys(files))


def _check_shadowed(doc: dict[str, Any], section: str, keys: list[str], values: list[Any],
                    build: Callable[[dict[str, Any]], object]) -> None:
    """Check the values of ``section`` that every study value replaces (``keys``: the varied key, or a whole section's
    keys of the first value): no case is built with them, yet the file gives them. The first variant is built again
    with them; an error of one of them is raised as it stands ("-5 banana" as the base viscosity passed silently)."""
    base = doc.get(section)
    if not isinstance(base, dict):
        return
    first = values[0]
    shadowed = [k for k in keys if k in base and all(not isinstance(v, dict) or k in v for v in values)
                and base[k] != (first.get(k) if isinstance(first, dict) else first)]  # (as the first value: built already)
    if not shadowed:
        return
    check = copy.deepcopy(doc)
    check[section] = {**base, **({k: v for k, v in first.items() if k not in shadowed} if isinstance(first, dict) else {})}
    try:
        build(check)
    except InputError as exc:
        if exc.field.partition("[")[0] in {f"{section}.{k}" for k in shadowed}:
            raise InputError(exc.field, exc.value, exc.allowed + " (every study value replaces it, but the case file gives "
                                                                 "it: it must be valid too, or left out)") from None


def _fails_alike(exc: InputError, other: Callable[[], object]) -> bool:
    """Whether building another study variant (``other``) fails with the same field, value and message as ``exc``: the
    error then lies in a key the variants share (a negative modulus beside ``vary = "surface.h_rms"``), and naming the
    study value beside it would blame the value for it. One study value alone shares every key."""
    try:
        other()
    except InputError as second:
        return str(second) == str(exc)
    return False


def parse_cases(text: str, case_dir: Path | str = ".", source: str = "<text>") -> list[Case]:
    """Cases from TOML text (one, or one per value of a ``[study]``)."""
    return parse_case_file(text, case_dir, source).cases


def read_case_file(path: str | Path) -> CaseFile:
    """Read a case file into a :class:`CaseFile` (its cases and its inputs as written)."""
    p = input_file(path, "case file")  # missing, a folder, a FIFO or a device: one line naming it
    _check_size(str(p), p.stat().st_size)  # before reading: a file of gigabytes is not read at all
    with p.open("rb") as f:
        data = f.read(MAX_CASE_FILE_BYTES + 1)  # one byte more tells a file that grew since
    return parse_case_bytes(data, p.parent, str(p))


def _check_size(source: str, size: int) -> None:
    """Refuse a case file of more than :data:`~sealeak.cases.limits.MAX_CASE_FILE_BYTES` bytes."""
    if size > MAX_CASE_FILE_BYTES:
        raise FileFormatError(source, f"is {size} bytes: a case file may have at most {MAX_CASE_FILE_BYTES} bytes "
                                      "(1 MB; data such as profiles or tables go in files of their own)")


def parse_case_bytes(data: bytes, case_dir: Path | str = ".", source: str = "<text>") -> CaseFile:
    """A case file's bytes (UTF-8, a BOM allowed) into a :class:`CaseFile`: the command line reads a file
    through this, the web app a request body, so both refuse the same content with the same message.

    More than :data:`~sealeak.cases.limits.MAX_CASE_FILE_BYTES` bytes are refused before anything is parsed
    (data files the case names have their own limits).
    """
    _check_size(source, len(data))
    try:
        text = data.decode("utf-8-sig")
    except UnicodeDecodeError:
        raise FileFormatError(source, "is not UTF-8 text") from None
    if not text.strip():
        raise FileFormatError(source, "is empty")
    return parse_case_file(text, case_dir, source)


def load_cases(path: str | Path) -> list[Case]:
    """Read a case file; a ``[study]`` gives one case per value."""
    return read_case_file(path).cases


def load_case(path: str | Path) -> Case:
    """Read a case file that defines exactly one case."""
    cases = load_cases(path)
    if len(cases) != 1:
        raise SealeakError(f"{path}: defines a study of {len(cases)} cases; use load_cases")
    return cases[0]


# ---------------------------------------------------------------------- bundled examples
def _examples_dir() -> Any:
    return resources.files("sealeak") / "examples"


def shown_source(source: str) -> str:
    """A case's (or its data file's) path as a report shows it: a bundled example as ``--example NAME`` (or its
    file name, for data it reads), never the install path; any other path as given."""
    path = Path(source)
    try:
        bundled = path.resolve().parent == Path(str(_examples_dir())).resolve()
    except OSError:  # pragma: no cover - an unreadable path: show it as given
        bundled = False
    if not bundled:
        return source
    if path.suffix == ".toml":
        return f"--example {path.stem}"
    return f"{path.name} (bundled example data)"


def example_names() -> list[str]:
    """Names of the bundled example cases (``--example NAME``)."""
    return sorted(p.name[:-5] for p in _examples_dir().iterdir() if p.name.endswith(".toml"))


def example_data_names() -> list[str]:
    """File names of the bundled example data files (e.g. ``reference-measured.csv`` for ``sealeak fit``)."""
    return sorted(p.name for p in _examples_dir().iterdir() if p.name.endswith(".csv"))


def example_description(name: str) -> str:
    """What a bundled example is: a case's ``title``; a data file's first sentence of its leading comment
    (which may run over several comment lines), whole."""
    text = example_text(name)
    if name in example_data_names():
        comment = []
        for line in text.splitlines():
            if not line.startswith("#"):
                break
            comment.append(line.lstrip("# ").strip())
        joined = " ".join(comment) or "example data"
        return re.split(r"(?<=\.)\s", joined, maxsplit=1)[0].rstrip(".")
    title = next((ln for ln in text.splitlines() if ln.startswith("title")), "")
    return title.split("=", 1)[1].strip().strip('"') if "=" in title else ""


def example_text(name: str) -> str:
    """The text of a bundled example: a case (TOML) by name, or a data file by its file name."""
    if name in example_data_names():
        return (_examples_dir() / name).read_text(encoding="utf-8")
    if name not in example_names():
        raise InputError("example", name, f"allowed: {', '.join(example_names() + example_data_names())}")
    return (_examples_dir() / f"{name}.toml").read_text(encoding="utf-8")


def example_path(name: str) -> Path:
    """File-system path of a bundled example case (for reading it as a case)."""
    if name in example_data_names():
        raise InputError("example", name, f"is a data file, not a case: print it with `sealeak examples {name}`; "
                                          f"cases: {', '.join(example_names())}")
    if name not in example_names():
        raise InputError("example", name, f"allowed: {', '.join(example_names())}")
    return Path(str(_examples_dir() / f"{name}.toml"))
