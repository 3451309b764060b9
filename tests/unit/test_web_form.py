"""The case form: every case-file key has a field, the choices are the loader's, fields round-trip to TOML."""

from __future__ import annotations

import re
import tomllib
from pathlib import Path

import pytest

from sealeak.cases import example_names, example_text, parse_case_file
from sealeak.cases.form import FIELD_KINDS, FORM_SECTIONS
from sealeak.cases.form_help import FIELD_HELP
from sealeak.cases.rig_builders import RIG_KEYS
from sealeak.cases.schema import SECTIONS, TOP_LEVEL
from sealeak.errors import InputError
from sealeak.io.tomlscan import MAX_DEPTH

pytest.importorskip("fastapi", reason="the web extra (sealeak[web]) is not installed")
from sealeak.web.casework import check_files, doc_fields, edit_text, fields_doc, resolve_files, text_value, upload_name  # noqa: E402

REF = example_text("reference-experiment")


def test_every_case_file_key_has_exactly_one_field():
    keys = set(TOP_LEVEL) | {f"{s}.{k}" for s, ks in SECTIONS.items() for k in ks}
    keys |= {f"rig.{k}" for ks in RIG_KEYS.values() for k in ks}
    assert set(FIELD_KINDS) == keys
    in_form = [f"{s}.{k}" if s else k for s, ks in FORM_SECTIONS.items() for k in ks]
    assert sorted(in_form) == sorted(keys) and len(in_form) == len(set(in_form))


@pytest.mark.parametrize("name, old", [("surface.model", 'model = "self-affine"'), ("seal.shape", 'shape = "ring"'),
                                       ("theory.model", None), ("theory.rarefaction", None)])
def test_the_choices_are_the_ones_the_loader_allows(name, old):
    section, key = name.split(".")
    text = REF.replace(old, f'{key} = "nonsense"') if old else REF.replace(f"[{section}]", f'[{section}]\n{key} = "nonsense"')
    with pytest.raises(InputError) as err:
        parse_case_file(text)
    assert err.value.field == name
    allowed = re.findall(r"'([^']+)'", err.value.allowed)
    assert allowed == list(FIELD_KINDS[name].choices)


def test_rig_kinds_are_the_rig_builders():
    assert FIELD_KINDS["rig.kind"].choices == tuple(RIG_KEYS)


@pytest.mark.parametrize("example", example_names())
def test_every_bundled_case_round_trips_through_the_form(example):
    doc = tomllib.loads(example_text(example))
    fields = doc_fields(doc)
    assert all(isinstance(v, str) for v in fields.values())
    assert fields_doc(fields) == doc


def test_field_texts_become_toml_values():
    assert text_value("rubber.youngs_modulus", "2.3 MPa") == "2.3 MPa"
    assert text_value("rubber.youngs_modulus", "2.3") == 2.3  # a bare number stays a number: the loader says what it lacks
    assert text_value("surface.hurst", "0.8") == 0.8
    assert text_value("simulation.grid", "64") == 64
    assert text_value("conditions.helium_equivalent", "true") is True
    assert text_value("conditions.squeeze_pressure", '["1 kPa", "2 kPa"]') == ["1 kPa", "2 kPa"]
    assert text_value("conditions.squeeze_pressure", '{start = "1 kPa", stop = "1 MPa", num = 3}') == \
        {"start": "1 kPa", "stop": "1 MPa", "num": 3}
    assert text_value("title", "42") == "42" and text_value("surface.label", "true") == "true"  # text stays text
    assert text_value("surface.files", '["a.txt", "b.txt"]') == ["a.txt", "b.txt"]
    with pytest.raises(InputError) as err:
        text_value("conditions.squeeze_pressure", '["1 kPa", ')
    assert err.value.field == "conditions.squeeze_pressure"


def test_unknown_field_is_refused_naming_it():
    with pytest.raises(InputError) as err:
        fields_doc({"rubber.colour": "red"})
    assert err.value.field == "rubber.colour"


@pytest.mark.parametrize("doc, field", [
    ({"surface": {"file": "/etc/passwd"}}, "surface.file"),
    ({"surface": {"files": ["a.txt", "../a.txt"]}}, "surface.files"),
    ({"surface": {"file": "sub/a.txt"}}, "surface.file"),
    ({"seal": {"pressure_profile": "b.csv"}}, "seal.pressure_profile"),
    ({"study": {"vary": "surface.file", "values": ["a.txt", "/etc/hosts"]}}, "study.values[1]"),
    ({"study": {"vary": "seal", "values": [{"pressure_profile": "/x"}]}}, "study.values[0].pressure_profile"),
])
def test_a_case_may_name_only_uploaded_files(doc, field):
    with pytest.raises(InputError) as err:
        check_files(doc, {"a.txt"})
    assert err.value.field == field and "uploaded in this session" in err.value.allowed


def test_uploaded_names_pass():
    check_files({"surface": {"files": ["a.txt", "b b.txt"]}, "study": {"vary": "surface.file", "values": ["a.txt"]}},
                {"a.txt", "b b.txt"})


@pytest.mark.parametrize("given, stored", [
    ("Probe Ø5 µm #3;b.csv", "Probe O5 um _3_b.csv"), ("Rauheit_ü.txt", "Rauheit_u.txt"), ("../../evil.csv", "evil.csv"),
    ("C:\\data\\scan.plu", "scan.plu"), (".hidden", "hidden"), ("..", "file"), ("ＡＢＣ.csv", "ABC.csv"), ("", "file"),
    ("名前.txt", "file.txt"), ("😀.csv", "file.csv"),  # a name of no letters kept its suffix alone ("txt"): no format to read
])
def test_uploaded_file_names_are_stored_under_a_safe_name(given, stored):
    assert upload_name(given) == stored
    assert upload_name(stored) == stored  # a safe name is kept as it is


def test_long_upload_names_keep_their_suffix():
    name = upload_name("x" * 300 + ".csv")
    assert len(name) == 128 and name.endswith(".csv")


def test_a_case_naming_a_file_by_the_users_name_reads_the_stored_file():
    doc = {"seal": {"pressure_profile": "Lippe Ø5.csv"}, "study": {"vary": "seal.pressure_profile", "values": ["b ü.csv"]}}
    uploaded = {"Lippe O5.csv", "b u.csv"}
    check_files(doc, uploaded)
    resolved = resolve_files(doc, uploaded)
    assert resolved == {"seal": {"pressure_profile": "Lippe O5.csv"}, "study": {"vary": "seal.pressure_profile",
                                                                                "values": ["b u.csv"]}}
    assert doc["seal"]["pressure_profile"] == "Lippe Ø5.csv"  # the user's case is not changed
    with pytest.raises(InputError):
        check_files({"seal": {"pressure_profile": "sub/Lippe Ø5.csv"}}, uploaded)  # a path is never resolved


@pytest.mark.parametrize("title", ["[Rev B] my ring", "{x}", '"quoted"', "true", "42"])
def test_text_fields_keep_text_that_looks_like_toml(title):
    assert text_value("title", title) == title


def test_editing_fields_changes_only_what_changed():
    text = "# notes\ntitle = 'T'  # kept\n\n[rubber]\nyoungs_modulus = \"2 MPa\"\npoisson_ratio = 0.5\n"
    fields = doc_fields(tomllib.loads(text))
    out = edit_text(text, dict(fields, **{"rubber.poisson_ratio": "0.49"}))
    assert out == text.replace("0.5", "0.49")
    removed = edit_text(text, {k: v for k, v in fields.items() if not k.startswith("rubber.")})
    assert "[rubber]" not in removed and "# notes" in removed
    added = edit_text(text, dict(fields, **{"conditions.squeeze_pressure": '{start = "1 kPa", stop = "1 MPa", num = 3}'}))
    assert tomllib.loads(added)["conditions"] == {"squeeze_pressure": {"start": "1 kPa", "stop": "1 MPa", "num": 3}}


def _documented_rows() -> dict[str, tuple[str, str]]:
    """Each key's first row in docs/case-files.md: (its meaning without links and code marks, its section's anchor)."""
    text = (Path(__file__).resolve().parents[2] / "docs" / "case-files.md").read_text(encoding="utf-8")
    rows: dict[str, tuple[str, str]] = {}
    anchor = ""
    for line in text.splitlines():
        if line.startswith("## "):  # MkDocs' anchor of the heading: lower case, no punctuation, words joined by -
            anchor = re.sub(r"[-\s]+", "-", re.sub(r"[^\w\s-]", "", line[3:].replace("`", "").strip().lower())).strip("-")
        m = re.match(r"\| `([A-Za-z0-9_.]+)(?: = [^`]*)?` \| (.*?) \|", line)
        if m and m.group(1) in FIELD_KINDS and m.group(1) not in rows:
            rows[m.group(1)] = (re.sub(r"\[([^\]]+)\]\([^)]+\)", r"\1", m.group(2)).replace("`", ""), anchor)
    return rows


def test_every_key_has_a_label_and_the_help_of_the_reference():
    rows = _documented_rows()
    assert set(FIELD_HELP) == set(FIELD_KINDS) == set(rows)
    for name, h in FIELD_HELP.items():
        assert h.label and h.label[0].isupper() or h.label.startswith("rms"), name
        assert (h.help, h.anchor) == rows[name], f"{name}: its help differs from docs/case-files.md"
    assert len({h.label for n, h in FIELD_HELP.items() if n.startswith("surface.")}) == len(FORM_SECTIONS["surface"])
    # one section's fields beside another's (a rubber's and its substrate's modulus) may share a label; two temperatures
    # of different meaning may not
    assert FIELD_HELP["fluid.temperature"].label != FIELD_HELP["conditions.temperature"].label


@pytest.mark.parametrize("depth", [MAX_DEPTH + 1, 300, 5000])
def test_a_field_nested_too_deeply_is_refused_naming_it(depth):
    with pytest.raises(InputError) as err:
        text_value("conditions.squeeze_pressure", "[" * depth + '"1 kPa"' + "]" * depth)
    assert err.value.field == "conditions.squeeze_pressure" and len(str(err.value)) < 300
