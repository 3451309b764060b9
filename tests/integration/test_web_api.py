"""The web app's JSON API against the command line: the same bytes, the same refusals, the safety rules."""

from __future__ import annotations

import json
import re
import subprocess
import sys
import time
import warnings
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("fastapi", reason="the web extra (sealeak[web]) is not installed")
with warnings.catch_warnings():  # starlette's TestClient on httpx 0.28 warns that httpx2 exists
    warnings.simplefilter("ignore")
    from fastapi.testclient import TestClient

from sealeak.cases import example_text
from sealeak.cli import main
from sealeak.topography import write_height_map
from sealeak.web import WebConfig, create_app

REF = example_text("reference-experiment")


def web_client(app, **kwargs) -> TestClient:
    """A test client that names the server as a browser on this machine does (Host 127.0.0.1:8765)."""
    return TestClient(app, base_url="http://127.0.0.1:8765", **kwargs)


@pytest.fixture(scope="module")
def client():
    with web_client(create_app()) as c:
        yield c


def cli(tmp_path: Path, monkeypatch, capsys, *argv: str) -> tuple[int, str]:
    """Run the command line in ``tmp_path``; its exit status and its one error line (or '')."""
    monkeypatch.chdir(tmp_path)
    capsys.readouterr()
    try:
        code = main(list(argv))
    except SystemExit as exc:  # argparse refuses an option's type before main's handler
        code = int(exc.code or 0)
    err = capsys.readouterr().err
    lines = [ln for ln in err.splitlines() if ln.startswith("sealeak: error:")]
    return code, lines[-1] if lines else ""


@pytest.mark.parametrize("example", ["reference-experiment", "hrms-study", "helium-test"])
def test_predict_answers_the_bytes_predict_json_writes(client, tmp_path, monkeypatch, capsys, example):
    (tmp_path / "ring.toml").write_text(example_text(example), encoding="utf-8")
    assert cli(tmp_path, monkeypatch, capsys, "predict", "ring.toml", "--json", "cli.json", "-q")[0] == 0
    r = client.post("/api/predict?name=ring.toml", content=(tmp_path / "ring.toml").read_bytes())
    assert r.status_code == 200 and r.headers["content-type"].startswith("application/json")
    assert r.content == (tmp_path / "cli.json").read_bytes()


def test_predict_of_a_case_naming_an_uploaded_file_equals_the_cli(tmp_path, monkeypatch, capsys):
    text = example_text("lip-profile")
    (tmp_path / "lip.toml").write_text(text, encoding="utf-8")
    (tmp_path / "lip-profile.csv").write_text(example_text("lip-profile.csv"), encoding="utf-8")
    assert cli(tmp_path, monkeypatch, capsys, "predict", "lip.toml", "--json", "cli.json", "-q")[0] == 0
    app = create_app()
    with web_client(app) as c:
        refused = c.post("/api/predict?name=lip.toml", content=text.encode())
        assert refused.status_code == 422 and refused.json()["field"] == "seal.pressure_profile"
        up = c.post("/api/uploads", files=[("files", ("lip-profile.csv", (tmp_path / "lip-profile.csv").read_bytes()))])
        assert up.status_code == 200 and up.json()["uploads"] == ["lip-profile.csv"]
        r = c.post("/api/predict?name=lip.toml", content=text.encode())
        # the profile's file is named as uploaded, never by its place on the server, in every view of the case
        c.post("/api/case/upload", files={"file": ("lip.toml", text.encode())})
        views = [c.get("/api/case?predict=1").text, c.get("/download/results.csv").text, r.text]
        assert all(str(app.state.root) not in v for v in views)
        assert '"pressure_profile": "lip-profile.csv"' in r.text
    assert r.status_code == 200, r.text
    assert r.content == (tmp_path / "cli.json").read_bytes()


# every kind of content the command line refuses in a case file, and the status the API gives it
BAD_CASES = {
    "empty": ("", 400),
    "not UTF-8": (b"title = \"\xff\xfe\"\n", 400),
    "malformed TOML": ("[surface\nmodel = 1", 400),
    "unknown section": (REF + "\n[colour]\nred = 1\n", 422),
    "unknown key": (REF.replace("[rubber]", "[rubber]\nstiffness = \"1 MPa\""), 422),
    "missing section": (re.sub(r"\[fluid\][^\[]*", "", REF), 422),
    "wrong unit": (REF.replace('"2.3 MPa"', '"2.3 m"'), 422),
    "negative": (REF.replace('"2.3 MPa"', '"-2.3 MPa"'), 422),
    "not a number": (REF.replace("hurst = 0.8", 'hurst = "steep"'), 422),
    "out of range": (REF.replace("poisson_ratio = 0.5", "poisson_ratio = 0.7"), 422),
    "bad choice": (REF.replace('shape = "ring"', 'shape = "star"'), 422),
    "list element": (REF.replace("[conditions]", "[conditions]\nsqueeze_pressure = [\"1 kPa\", \"-1 kPa\"]")
                     .replace('squeeze_pressure = {', 'old_sweep = {'), 422),
    "study": (REF + '\n[study]\nvary = "surface.color"\nvalues = [1, 2]\n', 422),
}


@pytest.mark.parametrize("kind", list(BAD_CASES))
def test_bad_case_is_refused_with_the_cli_message(client, tmp_path, monkeypatch, capsys, kind):
    text, status = BAD_CASES[kind]
    data = text if isinstance(text, bytes) else text.encode()
    (tmp_path / "case.toml").write_bytes(data)
    code, line = cli(tmp_path, monkeypatch, capsys, "predict", "case.toml")
    assert code == 2 and line, "the command line refuses it"
    r = client.post("/api/predict?name=case.toml", content=data)
    assert r.status_code == status
    body = r.json()
    assert body["message"] == line
    assert body["error"] == line[len("sealeak: error: "):]
    assert "Traceback" not in r.text


@pytest.mark.parametrize("value", ["/etc/passwd", "../psd.csv", "sub/psd.csv", "psd.csv", "/tmp"])
def test_a_case_may_name_only_files_uploaded_in_its_session(client, value):
    text = REF.replace('model = "self-affine"', f'model = "table"\nfile = "{value}"')
    text = re.sub(r"\n(h_rms|hurst|rolloff_wavevector|cutoff_wavelength|label) = [^\n]*", "", text)
    r = client.post("/api/predict", content=text.encode())
    assert r.status_code == 422
    body = r.json()
    assert body["field"] == "surface.file"
    assert "uploaded in this session" in body["error"] and "paths on the server are not allowed" in body["error"]
    assert "root:" not in r.text  # nothing of the file was read


def test_study_values_naming_files_are_checked_too(client):
    text = REF + '\n[study]\nvary = "seal.pressure_profile"\nvalues = ["/etc/hosts"]\n'
    r = client.post("/api/predict", content=text.encode())
    assert r.status_code == 422 and r.json()["field"] == "study.values"


def test_no_server_path_in_messages_about_uploaded_files(tmp_path):
    with web_client(create_app(WebConfig(root=tmp_path / "root"))) as c:
        c.post("/api/uploads", files=[("files", ("psd.csv", b"q (1/m), C (m^4)\n1e3, -1\n"))])
        text = REF.replace('model = "self-affine"', 'model = "table"\nfile = "psd.csv"')
        text = re.sub(r"\n(h_rms|hurst|rolloff_wavevector|cutoff_wavelength|label) = [^\n]*", "", text)
        r = c.post("/api/predict", content=text.encode())
    assert r.status_code == 422
    assert r.json()["error"].startswith("psd.csv")
    assert str(tmp_path) not in r.text and "/tmp" not in r.text


def test_unexpected_errors_send_no_traceback_and_no_path(monkeypatch):
    import sealeak.web.casework as casework

    def boom(case):
        raise RuntimeError("/srv/secret/path went wrong")

    monkeypatch.setattr(casework, "run_case", boom)
    with web_client(create_app(), raise_server_exceptions=False) as c:
        r = c.post("/api/predict", content=REF.replace("44 um", "45 um").encode())
    assert r.status_code == 500
    assert "internal error" in r.json()["error"]
    assert "secret" not in r.text and "Traceback" not in r.text and "RuntimeError" not in r.text


def test_upload_over_the_limit_gets_413():
    with web_client(create_app(WebConfig(max_upload=10_000))) as c:
        big = b"0" * 20_000
        r = c.post("/api/surface/analyze", files=[("files", ("big.txt", big))])
        assert r.status_code == 413 and "limit" in r.json()["error"]
        assert c.post("/api/predict", content=big).status_code == 413

        def chunks():  # no Content-Length: the body is counted while it streams
            for _ in range(20):
                yield b"#" * 1000

        r = c.post("/api/predict", content=chunks())
        assert r.status_code == 413
        assert c.get("/api/uploads").json()["uploads"] == []
        assert c.post("/api/predict", content=REF.encode()).status_code == 200  # under the limit: served


def _height_file(folder: Path) -> Path:
    rng = np.random.default_rng(3)
    h = rng.standard_normal((64, 64)) * 1e-6
    h = np.real(np.fft.ifft2(np.fft.fft2(h) / (1 + np.add.outer(np.arange(64) ** 2, np.arange(64) ** 2) ** 0.6)))
    path = folder / "map.txt"
    np.savetxt(path, h * 1e6)  # heights in µm, no size: the unit options say it
    return path


def test_surface_analyze_answers_the_bytes_of_the_cli(client, tmp_path, monkeypatch, capsys):
    f = _height_file(tmp_path)
    code, _ = cli(tmp_path, monkeypatch, capsys, "surface", "analyze", f.name, "--size", "0.5 mm", "--height-unit", "um",
                  "--json", "cli.json")
    assert code == 0
    r = client.post("/api/surface/analyze", files=[("files", (f.name, f.read_bytes()))],
                    data={"size": "0.5 mm", "height_unit": "um"})
    assert r.status_code == 200, r.text
    assert r.content == (tmp_path / "cli.json").read_bytes()
    doc = r.json()
    # the rms of the heights as written, to 10 % (the analysis removes the tilt first)
    assert doc["statistics"]["h_rms"] == pytest.approx(float(np.std(np.loadtxt(f) * 1e-6)), rel=0.1)


def test_synthesized_map_with_its_own_units_equals_the_cli(client, tmp_path, monkeypatch, capsys):
    rng = np.random.default_rng(0)
    write_height_map(tmp_path / "s.npz", rng.standard_normal((32, 32)) * 1e-7, (1e-4, 1e-4), periodic=True)
    assert cli(tmp_path, monkeypatch, capsys, "surface", "analyze", "s.npz", "--json", "cli.json")[0] == 0
    r = client.post("/api/surface/analyze", files=[("files", ("s.npz", (tmp_path / "s.npz").read_bytes()))])
    assert r.content == (tmp_path / "cli.json").read_bytes()


BAD_OPTIONS = {
    "no unit": {},
    "negative size": {"size": "-1 mm", "height_unit": "um"},
    "both sizes": {"size": "1 mm", "pixel_size": "1 um", "height_unit": "um"},
    "unknown unit": {"size": "1 mm", "height_unit": "bananas"},
    "bad resolution": {"size": "1 mm", "height_unit": "um", "resolution": "0 um"},
    "bad float": {"size": "1 mm", "height_unit": "um", "low_cut": "three"},
}


@pytest.mark.parametrize("kind", list(BAD_OPTIONS))
def test_surface_analyze_refuses_what_the_cli_refuses(client, tmp_path, monkeypatch, capsys, kind):
    f = _height_file(tmp_path)
    opts = BAD_OPTIONS[kind]
    argv = [x for k, v in opts.items() for x in (f"--{k.replace('_', '-')}", v)]
    code, line = cli(tmp_path, monkeypatch, capsys, "surface", "analyze", f.name, *argv)
    assert code == 2
    r = client.post("/api/surface/analyze", files=[("files", (f.name, f.read_bytes()))], data=opts)
    assert r.status_code == 422
    # the same words; the command line adds where to read its options
    assert r.json()["message"] == line.removesuffix(" (options: sealeak surface analyze --help)")
    assert r.json()["field"]  # the field or option at fault (a bad number named none)


def test_surface_analyze_refuses_a_switch_that_is_neither_on_nor_off(client, tmp_path):
    """``periodic`` is a switch: "maybe" was read as off without a word."""
    f = _height_file(tmp_path)
    r = client.post("/api/surface/analyze", files=[("files", (f.name, f.read_bytes()))],
                    data={"size": "1 mm", "height_unit": "um", "periodic": "maybe"})
    assert r.status_code == 422 and r.json()["message"].startswith("sealeak: error: --periodic = 'maybe': must be true or false")
    assert r.json()["field"] == "--periodic"  # the option it names (it was "")
    r = client.post("/api/surface/analyze", files=[("files", (f.name, f.read_bytes()))],
                    data={"size": "1 mm", "height_unit": "um", "periodic": "Yes"})
    assert r.status_code == 200


@pytest.mark.parametrize("body, kind, error", [
    (b'{"name": ', "application/json", "request body: not valid JSON at character 9 (Expecting value)"),
    (b'\xff\xfe{"name": 1}', "application/json", "request body: not JSON that can be read (not UTF-8"),
    (b'{"name": ' + b"9" * 5000 + b"}", "application/json", "request body: not JSON that can be read"),
    (b'{"name": "o-ring"}', "text/plain", "request body: must be a JSON object, sent with Content-Type: application/json"),
    (b"[1, 2]", "application/json", "request body: must be a JSON object"),
])
def test_a_body_that_is_not_a_json_object_is_named_as_such(client, body, kind, error):
    """Malformed JSON was '9: JSON decode error' with field '9' (its position); text sent as another type read 'Input
    should be a valid dictionary'; unreadable bytes 'There was an error parsing the body'."""
    r = client.post("/api/case/example", content=body, headers={"content-type": kind})
    assert r.status_code == 400 and r.json()["field"] == "body" and r.json()["error"].startswith(error), r.text


def test_pages_answer_head_requests(client):
    assert client.head("/case").status_code == 200 and client.head("/static/style.css").status_code == 200


def test_sessions_do_not_see_each_other():
    app = create_app()
    with web_client(app) as a, web_client(app) as b:
        a.post("/api/uploads", files=[("files", ("lip-profile.csv", example_text("lip-profile.csv").encode()))])
        assert a.get("/api/uploads").json()["uploads"] == ["lip-profile.csv"]
        assert b.get("/api/uploads").json()["uploads"] == []
        lip = example_text("lip-profile").encode()
        assert a.post("/api/predict", content=lip).status_code == 200
        assert b.post("/api/predict", content=lip).status_code == 422
        a.post("/api/case/example", json={"name": "reference-experiment"})
        assert a.get("/api/case").json()["name"] == "reference-experiment.toml"
        assert b.get("/api/case").json()["toml"] is None
        assert a.cookies["sealeak_session"] != b.cookies["sealeak_session"]


def test_sessions_expire_and_their_folders_go(tmp_path):
    app = create_app(WebConfig(root=tmp_path / "root", session_idle=3600))
    with web_client(app) as c:
        c.post("/api/uploads", files=[("files", ("a.csv", b"x"))])
        store = app.state.sessions
        (folder,) = [p for p in (tmp_path / "root").iterdir()]
        assert (folder / "uploads" / "a.csv").is_file()
        assert store.expire(now=time.monotonic() + 10) == []  # not idle long enough
        assert len(store.expire(now=time.monotonic() + 7200)) == 1
        assert not folder.exists()
        c.post("/api/uploads", files=[("files", ("b.csv", b"x"))])  # a new session, a new folder
        assert len(list((tmp_path / "root").iterdir())) == 1
    assert list((tmp_path / "root").iterdir()) == []  # the server's shutdown ends every session


def test_the_temporary_root_is_removed_at_shutdown():
    app = create_app()
    with web_client(app) as c:
        c.post("/api/uploads", files=[("files", ("a.csv", b"x"))])
        root = app.state.root
        assert root.is_dir()
    assert not root.exists()


def test_upload_names_cannot_leave_the_session_folder(client):
    r = client.post("/api/uploads", files=[("files", ("../../evil.csv", b"x"))])
    assert r.status_code == 200 and r.json()["uploaded"] == ["evil.csv"]
    r = client.post("/api/uploads", files=[("files", (".hidden", b"x"))])  # stored visibly, not as a dot file
    assert r.status_code == 200 and r.json()["uploaded"] == ["hidden"]


def test_case_form_round_trip_and_field_messages(client):
    state = client.post("/api/case/example", json={"name": "reference-experiment"}).json()
    assert state["valid"] and state["fields"]["rubber.youngs_modulus"] == "2.3 MPa"
    fields = dict(state["fields"], **{"rubber.youngs_modulus": "-1 MPa"})
    bad = client.put("/api/case/fields", json={"fields": fields}).json()
    assert not bad["valid"]
    assert bad["error"] == {"field": "rubber.youngs_modulus", "message": "rubber.youngs_modulus = '-1 MPa': must be > 0"}
    fields["rubber.youngs_modulus"] = "2300 kPa"
    fields["conditions.squeeze_pressure"] = '{start = "10 kPa", stop = "1 MPa", num = 5}'
    good = client.put("/api/case/fields", json={"fields": fields, "predict": True}).json()
    assert good["valid"] and len(good["prediction"]["json"]["results"]) == 5
    toml = client.get("/download/case.toml")
    assert toml.status_code == 200 and 'youngs_modulus = "2300 kPa"' in toml.text
    # the downloaded case gives the CLI's prediction of the page
    r = client.post("/api/predict", content=toml.content)
    assert json.loads(r.content)["results"] == good["prediction"]["json"]["results"]


def test_the_plots_carry_the_specification_in_si(client):
    """conditions.max_leak_rate reaches the page's plots as written and in SI (a liquid: m³/s); none without it."""
    plots = client.put("/api/case/toml", json={"toml": REF, "predict": True}).json()["prediction"]["plots"]
    assert plots["limit"] is None
    spec = REF.replace('pressure_difference = "10 kPa"', 'pressure_difference = "10 kPa"\nmax_leak_rate = "0.5 ml/min"')
    plots = client.put("/api/case/toml", json={"toml": spec, "predict": True}).json()["prediction"]["plots"]
    assert plots["limit"]["text"] == "0.5 ml/min"
    assert plots["limit"]["value"] == pytest.approx(0.5e-6 / 60, rel=1e-12, abs=0)  # 1 ml = 1e-6 m³


@pytest.mark.slow  # every prediction figure drawn twice (~18 s)
def test_downloads_are_the_cli_renderings(client, tmp_path, monkeypatch, capsys):
    client.post("/api/case/example", json={"name": "reference-experiment"})
    (tmp_path / "c.toml").write_bytes(client.get("/download/case.toml").content)
    argv = ["predict", "c.toml", "--json", "c.json", "--csv", "c.csv", "--plots", "figs", "-q"]
    assert cli(tmp_path, monkeypatch, capsys, *argv)[0] == 0
    assert client.get("/download/results.csv").content == (tmp_path / "c.csv").read_bytes()
    import io
    import zipfile
    z = zipfile.ZipFile(io.BytesIO(client.get("/download/figures.zip").content))
    assert sorted(z.namelist()) == sorted(p.name for p in (tmp_path / "figs").iterdir())
    for name in z.namelist():
        assert z.read(name) == (tmp_path / "figs" / name).read_bytes(), name
    report = client.get("/download/report.html")
    assert report.status_code == 200 and report.text.startswith("<!DOCTYPE html>")


def test_predict_does_not_import_the_web_libraries():
    code = "import sys; from sealeak.cli import main; main(['examples']); print(sorted(m for m in ('fastapi', 'uvicorn', 'starlette') if m in sys.modules))"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert out.strip().endswith("[]")


@pytest.mark.parametrize("argv, message", [
    (["serve", "--max-upload", "lots"], "--max-upload = 'lots': must be a size > 0"),
    (["serve", "--port", "70000"], "--port = 70000: must be a port number"),
    (["serve", "--session-timeout", "0"], "--session-timeout = 0: must be > 0"),
    (["serve", "--session-quota", "-1 GB"], "--session-quota = '-1 GB': must be a size > 0"),
    (["serve", "--allow-host", "http://evil.example.com/"], "--allow-host = 'http://evil.example.com/': must be a host name"),
])
def test_serve_refuses_bad_options(capsys, argv, message):
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert err.startswith(f"sealeak: error: {message}") and "Traceback" not in err


def test_simulation_job_gives_the_cli_result(tmp_path, monkeypatch, capsys):
    text = REF.replace('squeeze_pressure = {', 'old = {') if "squeeze_pressure = {" in REF else REF
    text = re.sub(r"squeeze_pressure = [^\n]*", 'squeeze_pressure = ["0.1 MPa", "0.3 MPa"]', REF)
    (tmp_path / "sim.toml").write_text(text, encoding="utf-8")
    argv = ["simulate", "sim.toml", "--grid", "32", "--realizations", "1", "--json", "cli.json", "-q"]
    assert cli(tmp_path, monkeypatch, capsys, *argv)[0] == 0
    app = create_app()
    with web_client(app) as c, web_client(app) as other:
        fields = c.post("/api/case/upload", files={"file": ("sim.toml", text.encode())}).json()
        assert fields["valid"], fields["error"]
        job = c.post("/api/jobs", json={"grid": "32", "realizations": "1"}).json()
        assert job["state"] in ("starting", "running")
        assert other.get("/api/jobs").json() == []  # another session sees none of it
        assert other.get(f"/api/jobs/{job['id']}").status_code == 404
        assert other.post(f"/api/jobs/{job['id']}/cancel").status_code == 404
        bad = c.post("/api/jobs", json={"grid": "33"})
        assert bad.status_code == 422 and bad.json()["error"].startswith("--grid = 33: must be an even integer >= 16")
        for digits in ("٦٤", "６４"):  # Arabic-Indic and full-width digits were read as 64 (int() takes them)
            bad = c.post("/api/jobs", json={"grid": digits})
            assert bad.status_code == 422 and "written with the digits 0-9" in bad.json()["error"], bad.text
        assert c.post("/api/jobs", json={"grid": True}).status_code == 422
        for _ in range(600):
            info = c.get(f"/api/jobs/{job['id']}").json()
            if info["state"] not in ("starting", "running"):
                break
            time.sleep(0.2)
        assert info["state"] == "done", info
        assert info["done"] == info["total"] > 0
        assert "alpha.png" in " ".join(info["figures"]) or info["figures"]
        web = c.get(f"/api/jobs/{job['id']}/result.json").json()
        assert c.get(f"/api/jobs/{job['id']}/figures/{info['figures'][0]}").headers["content-type"] == "image/png"
    ref = json.loads((tmp_path / "cli.json").read_text())
    _same(web, ref)


def _same(a, b, path="$", skip=()):
    """Key for key, numbers to 1e-12 (relative); keys starting with a ``skip`` prefix are not compared."""
    if isinstance(a, dict):
        assert a.keys() == b.keys(), path
        for k in a:
            if not k.startswith(skip or ("\0",)):
                _same(a[k], b[k], f"{path}.{k}", skip)
    elif isinstance(a, list):
        assert len(a) == len(b), path
        for i, (x, y) in enumerate(zip(a, b)):
            _same(x, y, f"{path}[{i}]", skip)
    elif isinstance(a, float) and isinstance(b, float):
        assert a == pytest.approx(b, rel=1e-12, abs=0), path
    else:
        if path.endswith(".elapsed") or path.endswith("seconds"):
            return
        assert a == b, path


def test_serve_refuses_a_port_in_use(capsys):
    import socket

    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        s.listen()
        port = s.getsockname()[1]
        assert main(["serve", "--port", str(port)]) == 2
    err = capsys.readouterr().err
    assert err == f"sealeak: error: --port = {port}: is in use on 127.0.0.1 (another server?): choose another port\n"


def test_serve_prints_its_address_serves_and_stops_on_ctrl_c(tmp_path):
    import os
    import signal
    import urllib.request

    env = dict(os.environ, TMPDIR=str(tmp_path))
    proc = subprocess.Popen([sys.executable, "-c", "import sys; from sealeak.cli import main; sys.exit(main(sys.argv[1:]))",
                             "serve", "--port", "0"], stderr=subprocess.PIPE, text=True, env=env)
    try:
        line = proc.stderr.readline()
        m = re.fullmatch(r"sealeak: serving the web app at (http://127\.0\.0\.1:(\d+)/) \(Ctrl-C stops it\)\n", line)
        assert m, line
        body = REF.encode()
        req = urllib.request.Request(m.group(1) + "api/predict?name=ring.toml", data=body, method="POST")
        answer = json.loads(urllib.request.urlopen(req, timeout=60).read())
        assert answer["cases"][0]["source"] == "ring.toml"
        page = urllib.request.urlopen(m.group(1) + "case", timeout=30).read().decode()
        assert "<title>sealeak — Case</title>" in page
        assert len(list(tmp_path.glob("sealeak-web-*"))) == 1
    finally:
        proc.send_signal(signal.SIGINT)
        rest = proc.communicate(timeout=30)[1]
    assert proc.returncode == 0, rest
    assert "Traceback" not in rest
    assert list(tmp_path.glob("sealeak-web-*")) == []  # the sessions' folders went with the server


def test_sessions_that_stored_nothing_expire_sooner(tmp_path):
    from sealeak.web.sessions import SessionStore

    store = SessionStore(tmp_path, idle=3600)
    idle, busy = store.create(), store.create()
    busy.uploads.joinpath("a.csv").write_text("x")
    gone = store.expire(now=time.monotonic() + 900)
    assert gone == [idle] and store.get(busy.token) is busy
