"""The case as the web app edits it: titles that look like TOML, syntax errors, wrong request types,
messages in the user's notation, file names from instruments, the case bundle."""

from __future__ import annotations

import io
import json
import re
import sys
import tomllib
import warnings
import zipfile
from pathlib import Path

import pytest

pytest.importorskip("fastapi", reason="the web extra (sealeak[web]) is not installed")
with warnings.catch_warnings():  # starlette's TestClient on httpx 0.28 warns that httpx2 exists
    warnings.simplefilter("ignore")
    from fastapi.testclient import TestClient

from sealeak.cases import example_text
from sealeak.cli import main
from sealeak.web import create_app

REF = example_text("reference-experiment")


@pytest.fixture
def client():
    with TestClient(create_app(), base_url="http://127.0.0.1:8765") as c:  # a Host the server answers to
        yield c


def leak_rates(doc: dict) -> list:
    """The leak rate of each row (None where sealed), for comparing with a relative tolerance."""
    return [pytest.approx(r["leak_rate"], rel=1e-12, abs=0) if r["leak_rate"] is not None else None for r in doc["results"]]


def cli_json(tmp_path: Path, monkeypatch, capsys, case: str) -> dict:
    monkeypatch.chdir(tmp_path)
    assert main(["predict", case, "--json", "cli.json", "-q"]) == 0
    capsys.readouterr()
    return json.loads((tmp_path / "cli.json").read_text(encoding="utf-8"))


@pytest.mark.parametrize("title", ["[Rev B] my ring", "{draft} ring", '"quoted" ring', "[1, 2]", "true"])
def test_a_title_that_looks_like_toml_stays_text_through_every_edit(client, title):
    state = client.post("/api/case/example", json={"name": "reference-experiment"}).json()
    fields = dict(state["fields"], title=title)
    first = client.put("/api/case/fields", json={"fields": fields}).json()
    assert first["valid"], first["error"]
    assert first["fields"]["title"] == title
    # the next edit (another field) sends the title back as the form shows it: it stays the same text
    again = client.put("/api/case/fields", json={"fields": dict(first["fields"], **{"surface.hurst": "0.7"})}).json()
    assert again["valid"], again["error"]
    assert again["fields"]["title"] == title and again["fields"]["surface.hurst"] == "0.7"
    assert client.post("/api/predict", content=client.get("/download/case.toml").content).json()["cases"][0]["title"] == title


def test_an_uploaded_case_whose_title_looks_like_toml_survives_a_form_edit(client):
    text = REF.replace('title = ', 'title = "[Rev B] my ring"\nold_title = ', 1)
    text = re.sub(r"\nold_title = [^\n]*", "", text)
    state = client.post("/api/case/upload", files={"file": ("rev-b.toml", text.encode())}).json()
    assert state["valid"] and state["fields"]["title"] == "[Rev B] my ring"
    edited = client.put("/api/case/fields", json={"fields": dict(state["fields"], **{"rubber.poisson_ratio": "0.49"})}).json()
    assert edited["valid"] and edited["fields"]["title"] == "[Rev B] my ring"


def test_a_form_edit_keeps_the_comments_and_the_other_lines_of_the_case(client):
    text = "# measured on rig 2, 2024-03-01\n" + REF.replace("[rubber]", "[rubber]  # batch 17")
    state = client.post("/api/case/upload", files={"file": ("c.toml", text.encode())}).json()
    edited = client.put("/api/case/fields", json={"fields": dict(state["fields"], **{"rubber.youngs_modulus": "2.5 MPa"})})
    toml = edited.json()["toml"]
    assert "# measured on rig 2, 2024-03-01" in toml and "[rubber]  # batch 17" in toml
    assert toml.replace('"2.5 MPa"', '"2.3 MPa"') == text  # only the edited value changed


def test_a_form_list_is_written_whole_and_a_list_over_the_limit_is_refused_before_it_is_built(client):
    """A list edited in the form reaches the case text as one TOML array, its tables inline (it was built item by
    item in tomlkit, whose time grows with the square of the length: 40 000 pressures took 150 s, no limit checked);
    more items than any case-file list may hold are refused naming the field."""
    state = client.post("/api/case/example", json={"name": "reference-experiment"}).json()
    pressures = [f"{k} kPa" for k in range(1, 2001)]
    fields = dict(state["fields"], **{"conditions.squeeze_pressure": json.dumps(pressures)})
    edited = client.put("/api/case/fields", json={"fields": fields}).json()
    assert edited["valid"] and tomllib.loads(edited["toml"])["conditions"]["squeeze_pressure"] == pressures
    fields["conditions.squeeze_pressure"] = '{start = "10 kPa", stop = "1 MPa", num = 5}'
    fields["title"] = 'a "quoted" [title]'
    edited = client.put("/api/case/fields", json={"fields": fields}).json()
    doc = tomllib.loads(edited["toml"])
    assert doc["conditions"]["squeeze_pressure"] == {"start": "10 kPa", "stop": "1 MPa", "num": 5}
    assert doc["title"] == 'a "quoted" [title]'
    fields["conditions.squeeze_pressure"] = json.dumps(["1 kPa"] * 10_001)
    refused = client.put("/api/case/fields", json={"fields": fields}).json()
    assert not refused["valid"] and refused["error"]["field"] == "conditions.squeeze_pressure"
    assert refused["error"]["message"].endswith("10001 items: at most 10000 (docs/case-files.md, Limits)")


def test_a_case_with_a_syntax_error_keeps_the_current_case_and_names_the_line(client):
    before = client.post("/api/case/example", json={"name": "reference-experiment"}).json()
    bad = REF.replace("hurst = 0.8", "hurst = 0.8 0.9")
    line = bad.splitlines().index("hurst = 0.8 0.9") + 1
    r = client.post("/api/case/upload", files={"file": ("broken.toml", bad.encode())})
    assert r.status_code == 200
    body = r.json()["rejected"]
    assert body["field"] == "toml" and body["line"] == line and body["column"] == len("hurst = 0.8 ") + 1
    assert body["message"].startswith("broken.toml: malformed TOML") and f"line {line}" in body["message"]
    assert r.json()["toml"] == before["toml"]  # the answer is the case as it stays
    after = client.get("/api/case").json()
    assert after["toml"] == before["toml"] and after["fields"] == before["fields"] and after["valid"]


def test_the_toml_editor_replaces_the_case_or_names_the_line_of_its_error(client):
    client.post("/api/case/example", json={"name": "reference-experiment"})
    text = "# my notes\n" + REF.replace("poisson_ratio = 0.5", "poisson_ratio = 0.49")
    r = client.put("/api/case/toml", json={"toml": text, "predict": True})
    assert r.status_code == 200 and r.json()["valid"] and r.json()["fields"]["rubber.poisson_ratio"] == "0.49"
    assert r.json()["toml"] == text and r.json()["prediction"]["json"]["results"]
    bad = client.put("/api/case/toml", json={"toml": "title = \n"})
    assert bad.status_code == 200 and bad.json()["rejected"]["line"] == 1 and bad.json()["toml"] == text
    assert client.get("/api/case").json()["toml"] == text
    assert client.put("/api/case/toml", json={"toml": 5}).status_code == 422
    assert client.put("/api/case/toml", json={"toml": text, "nmae": "x.toml"}).json()["field"] == "nmae"
    fixed = client.put("/api/case/toml", json={"toml": text, "name": "Prüfung Ø5.toml"}).json()  # a fixed upload, named
    assert fixed["name"] == "Prufung O5.toml" and fixed["toml"] == text


@pytest.mark.parametrize("body, field", [
    ({"title": 5}, "title"),  # not wrapped in "fields": it would have emptied the case
    ({"fields": {"title": 5}}, "title"),
    ({"fields": {"rubber.youngs_modulus": ["2 MPa"]}}, "rubber.youngs_modulus"),
    ({"fields": ["title"]}, "fields"),
    ({"fields": {}, "predict": "yes"}, "predict"),
])
def test_a_wrong_type_in_the_fields_request_is_refused_and_the_case_stays(client, body, field):
    before = client.post("/api/case/example", json={"name": "reference-experiment"}).json()
    r = client.put("/api/case/fields", json=body)
    assert r.status_code in (400, 422)
    assert r.json()["field"] == field and r.json()["error"].startswith(field)
    after = client.get("/api/case").json()
    assert after["toml"] == before["toml"] and after["valid"]


@pytest.mark.parametrize("change, shown, python", [
    (("title = ", "title = 1979-05-27T07:32:00\nold = "), "title = 1979-05-27T07:32:00", "datetime"),
    (("poisson_ratio = 0.5", "poisson_ratio = {foo = 1}"), "rubber.poisson_ratio = {foo = 1}", "{'foo'"),
    (("poisson_ratio = 0.5", "poisson_ratio = [true, 'a']"), "rubber.poisson_ratio = [true, 'a']", "True"),
    (("[conditions]", "[simulation]\ngrid = 64.0\n\n[conditions]"), "simulation.grid = 64.0", "= 64:"),
])
def test_messages_show_values_as_written_in_the_case_file(client, change, shown, python):
    text = REF.replace(*change, 1)
    text = re.sub(r"\nold = [^\n]*", "", text)
    r = client.post("/api/predict", content=text.encode())
    assert r.status_code == 422, r.text
    msg = r.json()["error"]
    assert shown in msg and python not in msg


INSTRUMENT_NAME = "Lippe Ø5 µm #3;Prüfung.csv"


def test_an_instrument_file_name_is_stored_safely_and_the_case_finds_it(client, tmp_path, monkeypatch, capsys):
    profile = example_text("lip-profile.csv")
    case = example_text("lip-profile").replace('"lip-profile.csv"', json.dumps(INSTRUMENT_NAME, ensure_ascii=False))
    (tmp_path / INSTRUMENT_NAME).write_text(profile, encoding="utf-8")
    (tmp_path / "lip.toml").write_text(case, encoding="utf-8")
    expected = cli_json(tmp_path, monkeypatch, capsys, "lip.toml")

    up = client.post("/api/uploads", files=[("files", (INSTRUMENT_NAME, profile.encode()))]).json()
    (stored,) = up["uploaded"]
    assert re.fullmatch(r"[A-Za-z0-9._ +()-]+", stored) and "Pr" in stored and "ufung" in stored
    assert up["upload_names"] == {stored: INSTRUMENT_NAME}  # the user's name is shown beside the stored one
    state = client.post("/api/case/upload", files={"file": ("lip.toml", case.encode())}).json()
    assert state["valid"], state["error"]
    assert state["fields"]["seal.pressure_profile"] == INSTRUMENT_NAME  # the case as the user wrote it
    got = client.get("/api/case?predict=1").json()["prediction"]["json"]
    assert [r["leak_rate"] for r in got["results"]] == leak_rates(expected)

    # the bundle: the case and its file, which the command line runs as unzipped
    r = client.get("/download/bundle.zip")
    assert r.status_code == 200 and r.headers["content-disposition"] == 'attachment; filename="lip.zip"'
    z = zipfile.ZipFile(io.BytesIO(r.content))
    assert sorted(z.namelist()) == sorted(["lip/lip.toml", f"lip/{stored}"])
    (tmp_path / "out").mkdir()
    z.extractall(tmp_path / "out")
    again = cli_json(tmp_path / "out" / "lip", monkeypatch, capsys, "lip.toml")
    assert [r["leak_rate"] for r in again["results"]] == leak_rates(expected)


def test_a_bundle_of_a_case_without_files_is_its_toml(client):
    assert client.get("/download/bundle.zip").status_code == 422  # no case yet
    client.post("/api/case/example", json={"name": "reference-experiment"})
    z = zipfile.ZipFile(io.BytesIO(client.get("/download/bundle.zip").content))
    assert z.namelist() == ["reference-experiment/reference-experiment.toml"]
    assert z.read("reference-experiment/reference-experiment.toml").decode() == REF


def test_a_simulation_option_given_as_a_float_is_named_as_given(client):
    client.post("/api/case/example", json={"name": "reference-experiment"})
    r = client.post("/api/jobs", json={"grid": 64.0})
    assert r.status_code == 422 and r.json()["error"] == "--grid = 64.0: must be an integer"
    assert client.get("/api/jobs").json() == []  # refused before any process started


@pytest.mark.parametrize("grid", ["1048576", "1180591620717411303424"])
def test_a_grid_no_memory_holds_is_refused_before_its_job_starts(client, grid):
    """A grid of 2^20 points a side (or 2^70) was accepted (200), its process started, and failed there."""
    client.post("/api/case/example", json={"name": "reference-experiment"})
    r = client.post("/api/jobs", json={"grid": grid})
    assert r.status_code == 422, r.text
    assert f"--grid = {grid}: the {grid}x{grid} contact problem needs about" in r.json()["error"]
    assert client.get("/api/jobs").json() == []  # refused before any process started


def test_a_gpu_case_on_a_server_without_cupy_is_refused_naming_its_key(client, monkeypatch):
    monkeypatch.setitem(sys.modules, "cupy", None)  # `import cupy` fails, as on a server without the gpu extra
    up = client.post("/api/case/upload", files={"file": ("g.toml", (REF + '\n[simulation]\ndevice = "cuda"\n').encode())})
    assert up.json()["valid"], up.json()["error"]
    r = client.post("/api/jobs", json={"grid": "32"})
    assert r.status_code == 422 and r.json()["error"].startswith("simulation.device = 'cuda': needs CuPy")
    assert client.get("/api/jobs").json() == []  # refused before any process started


def test_toml_the_form_could_not_edit_is_rejected_with_its_line(client):
    client.post("/api/case/example", json={"name": "reference-experiment"})
    deep = 'title = "x"\n[conditions]\nsqueeze_pressure = ' + "[" * 150 + "]" * 150 + "\n"
    r = client.put("/api/case/toml", json={"toml": deep})
    assert r.status_code == 200 and r.json()["rejected"]["line"] == 3
    assert r.json()["toml"] == REF
