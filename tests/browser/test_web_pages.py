"""The four pages in headless Chromium: what a user does and sees, checked against the command line."""

from __future__ import annotations

import json
import re
import time
from pathlib import Path

import numpy as np
import pytest

from sealeak.cases import example_text
from sealeak.cli import main


def cli(tmp_path: Path, monkeypatch, capsys, *argv: str) -> tuple[int, str]:
    monkeypatch.chdir(tmp_path)
    capsys.readouterr()
    code = main(list(argv))
    err = capsys.readouterr().err
    return code, next((ln for ln in err.splitlines() if ln.startswith("sealeak: error:")), "")


def goto(page, path: str) -> None:
    """Open a page and wait until it has loaded what it shows."""
    page.goto(path)
    page.wait_for_selector("body[data-ready]", state="attached")


def load_example(page, name: str = "reference-experiment") -> None:
    goto(page, "/case")
    page.select_option("#example", name)
    page.click("#load-example")
    page.wait_for_selector("#status:has-text('the case is valid')")


def test_prediction_page_shows_the_cli_leak_rate(page, artifacts, tmp_path, monkeypatch, capsys):
    load_example(page)
    goto(page, "/prediction")
    page.wait_for_function("document.querySelector('#leak-rate').dataset.si !== ''")
    page.fill('[name="conditions.squeeze_pressure"]', "0.5 MPa")  # re-runs on change, no button
    page.wait_for_function("document.querySelector('#first-pressure').textContent.startsWith('P0 = 500 kPa')")
    shown = float(page.get_attribute("#leak-rate", "data-si"))
    text = page.inner_text("#leak-rate")
    assert page.inner_text("#leak-rate-unit") == "m³/s"

    case = re.sub(r"squeeze_pressure = [^\n]*", 'squeeze_pressure = "0.5 MPa"', example_text("reference-experiment"))
    (tmp_path / "case.toml").write_text(case, encoding="utf-8")
    assert cli(tmp_path, monkeypatch, capsys, "predict", "case.toml", "--json", "out.json", "-q")[0] == 0
    (row,) = json.loads((tmp_path / "out.json").read_text())["results"]
    assert shown == pytest.approx(row["leak_rate"], rel=1e-12, abs=0)
    assert float(text) == pytest.approx(row["leak_rate"], rel=1e-4, abs=0)  # 5 significant digits on the page
    assert page.locator("#results-table tbody tr").count() == 1

    # a sweep: the table has a row per pressure, the plots are interactive, on log axes
    page.fill('[name="conditions.squeeze_pressure"]', '{start = "20 kPa", stop = "1 MPa", num = 12}')
    page.wait_for_function("document.querySelectorAll('#results-table tbody tr').length === 12")
    axes = page.evaluate("['plot-leak','plot-psd','plot-area','plot-gap','plot-gaps'].map(id => "
                         "[document.getElementById(id).layout.xaxis.type, document.getElementById(id).data.length])")
    assert [a[0] for a in axes] == ["log"] * 5 and all(n >= 1 for _, n in axes)
    assert page.evaluate("document.getElementById('plot-leak').layout.yaxis.type") == "log"
    page.locator("#plot-leak").scroll_into_view_if_needed()
    box = page.locator("#plot-leak .nsewdrag").bounding_box()
    page.mouse.move(box["x"] + box["width"] * 0.3, box["y"] + box["height"] * 0.2)
    page.mouse.move(box["x"] + box["width"] * 0.31, box["y"] + box["height"] * 0.2)
    page.wait_for_selector("#plot-leak .hovertext", state="attached", timeout=5000)  # hover shows the values
    page.screenshot(path=str(artifacts / "prediction.png"), full_page=True)

    # the downloads are the command line's files
    with page.expect_download() as dl:
        page.click("text=CSV")
    assert dl.value.suggested_filename == "results.csv"
    assert Path(dl.value.path()).read_text().startswith("squeeze_pressure (Pa),")


def test_a_gas_case_shows_its_leak_rate_in_mbar_l_s(page, artifacts, tmp_path, monkeypatch, capsys):
    """The helium leak test: the page shows the pV throughput in the leak-test unit, as the CLI's records."""
    load_example(page, "helium-test")
    goto(page, "/prediction")
    page.wait_for_function("document.querySelector('#leak-rate').dataset.si !== ''")
    assert page.inner_text("#leak-rate-what") == "Gas leak rate Q_pV"
    assert page.inner_text("#leak-rate-unit") == "mbar·l/s"
    shown, text = float(page.get_attribute("#leak-rate", "data-si")), page.inner_text("#leak-rate")
    (tmp_path / "he.toml").write_text(example_text("helium-test"), encoding="utf-8")
    assert cli(tmp_path, monkeypatch, capsys, "predict", "he.toml", "--json", "out.json", "-q")[0] == 0
    row = json.loads((tmp_path / "out.json").read_text())["results"][0]
    assert shown == pytest.approx(row["leak_rate_pv"], rel=1e-12, abs=0)  # data-si: Pa·m³/s
    assert float(text) == pytest.approx(row["leak_rate_mbar_l_s"], rel=1e-4, abs=0)  # 1 mbar·l/s = 0.1 Pa·m³/s
    assert float(text) == pytest.approx(shown / 0.1, rel=1e-4, abs=0)
    assert "mbar·l/s" in page.evaluate("document.getElementById('plot-leak').layout.yaxis.title.text")
    page.screenshot(path=str(artifacts / "prediction-gas.png"), full_page=False)


def test_bad_value_shows_the_cli_message_next_to_its_field(page, artifacts, tmp_path, monkeypatch, capsys):
    load_example(page)
    page.screenshot(path=str(artifacts / "case.png"), full_page=False)
    page.fill('[name="rubber.poisson_ratio"]', "0.7")
    box = page.locator('[data-field="rubber.poisson_ratio"] .err')
    box.wait_for(state="visible")
    case = example_text("reference-experiment").replace("poisson_ratio = 0.5", "poisson_ratio = 0.7")
    (tmp_path / "case.toml").write_text(case, encoding="utf-8")
    code, line = cli(tmp_path, monkeypatch, capsys, "predict", "case.toml")
    assert code == 2
    assert box.inner_text() == line[len("sealeak: error: "):]
    assert "invalid" in page.get_attribute('[name="rubber.poisson_ratio"]', "class")
    page.locator('[data-field="rubber.poisson_ratio"]').scroll_into_view_if_needed()
    page.screenshot(path=str(artifacts / "case-error.png"), full_page=False)
    page.fill('[name="rubber.poisson_ratio"]', "0.5")
    page.wait_for_selector("#status:has-text('the case is valid')")
    assert box.inner_text() == ""
    with page.expect_download() as dl:
        page.click("#download-toml")
    assert "poisson_ratio = 0.5" in Path(dl.value.path()).read_text()


def test_the_prediction_page_without_a_case_shows_no_empty_results(page, artifacts):
    """With no case yet the page showed "Leak rate Q at :", empty plot frames and download buttons whose files were a
    JSON error; its results appear once a case has run."""
    goto(page, "/prediction")
    assert page.is_hidden("#results") and page.is_hidden("#leak-rate")
    page.screenshot(path=str(artifacts / "prediction-empty.png"), full_page=False)
    load_example(page)
    goto(page, "/prediction")
    page.wait_for_function("document.querySelector('#leak-rate').dataset.si !== ''")
    assert page.is_visible("#results") and page.is_visible("#leak-rate")


def test_uploaded_case_and_the_file_it_names(page, tmp_path):
    (tmp_path / "lip.toml").write_text(example_text("lip-profile"), encoding="utf-8")
    (tmp_path / "lip-profile.csv").write_text(example_text("lip-profile.csv"), encoding="utf-8")
    goto(page, "/case")
    page.set_input_files("#case-file", str(tmp_path / "lip.toml"))
    box = page.locator('[data-field="seal.pressure_profile"] .err')
    page.wait_for_function("document.querySelector('#status').textContent === 'the case has an error (below)'")
    assert page.inner_text("#message") == ""  # the message is by its field, not in the banner
    box.wait_for(state="visible")
    assert box.inner_text().startswith("seal.pressure_profile = 'lip-profile.csv': must name a file uploaded in this session")
    assert page.inner_text("#case-name") == "case: lip.toml"
    page.set_input_files("#data-files", str(tmp_path / "lip-profile.csv"))
    page.wait_for_selector("#status:has-text('the case is valid')", timeout=60_000)
    assert page.inner_text("#uploads") == "lip-profile.csv" and box.inner_text() == ""


def test_the_example_list_names_the_case_in_the_form(page, tmp_path):
    """Coming back to the Case page, the list of examples showed the first one (helium-test) whatever case was loaded."""
    load_example(page, "o-ring")
    goto(page, "/prediction")
    goto(page, "/case")
    assert page.input_value("#example") == "o-ring"
    (tmp_path / "mine.toml").write_text(example_text("reference-experiment"), encoding="utf-8")
    page.set_input_files("#case-file", str(tmp_path / "mine.toml"))
    page.wait_for_selector("#status:has-text('the case is valid')")
    goto(page, "/case")
    assert page.input_value("#example") == ""
    assert page.locator("#example option:checked").inner_text() == "mine.toml (the case in the form)"


def test_surface_upload_shows_the_cli_h_rms(page, artifacts, tmp_path, monkeypatch, capsys):
    rng = np.random.default_rng(7)
    n = 64
    k = np.hypot(*np.meshgrid(np.fft.fftfreq(n) * n, np.fft.fftfreq(n) * n))
    h = np.real(np.fft.ifft2(np.fft.fft2(rng.standard_normal((n, n))) / (1 + k) ** 1.6))
    f = tmp_path / "map.txt"
    np.savetxt(f, 2.0 * h / h.std())  # µm
    load_example(page)
    goto(page, "/surface")
    assert page.is_visible("#surface-waiting")  # the empty half of the page says what will appear there
    page.screenshot(path=str(artifacts / "surface-empty.png"))
    page.set_input_files("#topo-files", str(f))
    page.fill("#opt-size", "0.5 mm")
    page.fill("#opt-height_unit", "um")
    page.click("#analyze")
    page.wait_for_function("document.querySelector('#h-rms').dataset.si")
    shown = float(page.get_attribute("#h-rms", "data-si"))
    assert cli(tmp_path, monkeypatch, capsys, "surface", "analyze", "map.txt", "--size", "0.5 mm", "--height-unit", "um",
               "--json", "an.json")[0] == 0
    assert shown == json.loads((tmp_path / "an.json").read_text())["statistics"]["h_rms"]
    assert 1.0 < float(page.inner_text("#h-rms")) < 3.0  # µm: the map was scaled to 2 µm rms before the tilt removal
    assert not page.is_visible("#surface-waiting")
    page.click("#use-surface")
    page.wait_for_selector("#used:has-text('measured topography')")
    page.screenshot(path=str(artifacts / "surface.png"), full_page=True)
    goto(page, "/case")
    assert page.input_value('[name="surface.model"]') == "topography"


def _running_in_group(pgid: int) -> list[int]:
    """The processes of group ``pgid`` that still run (zombies waiting for their parent to reap them do not)."""
    out = []
    for stat in Path("/proc").glob("[0-9]*/stat"):
        try:
            fields = stat.read_text().rsplit(")", 1)[1].split()
        except OSError:
            continue
        if int(fields[2]) == pgid and fields[0] != "Z":
            out.append(int(stat.parent.name))
    return out


def _job_state(page, job_id: str) -> dict:
    return page.evaluate(f"fetch('/api/jobs/{job_id}').then(r => r.json())")


def test_simulation_runs_and_cancels(page, artifacts, server):
    _base, app = server
    load_example(page)
    goto(page, "/case")
    page.fill('[name="conditions.squeeze_pressure"]', '["0.1 MPa", "0.3 MPa"]')
    page.wait_for_selector("#status:has-text('the case is valid')")
    goto(page, "/simulation")
    # a long one (cancelled while it runs) and a short one (runs to the end) at the same time
    page.fill("#sim-grid", "512")
    page.fill("#sim-realizations", "8")
    page.click("#start-sim")
    page.wait_for_selector("#jobs .cancel")
    page.fill("#sim-grid", "32")
    page.fill("#sim-realizations", "1")
    page.click("#start-sim")
    page.wait_for_selector("#jobs tr:has-text('grid 512') td.state:has-text('running')")
    long_id = page.get_attribute("#jobs tr:has-text('grid 512')", "data-job")
    page.wait_for_selector("#jobs tr:has-text('grid 32') .show", timeout=120_000)
    page.wait_for_selector("#job-figures img")
    assert _job_state(page, long_id)["state"] == "running"  # the short job finished while the long one runs
    page.screenshot(path=str(artifacts / "simulation.png"), full_page=True)
    job = next(j for s in list(app.state.sessions._sessions.values()) for i, j in s.jobs.items() if i == long_id)
    for _ in range(300):  # a 512² run starts a local Dask cluster (the CLI default): the simulation, the resource tracker, workers
        if len(_running_in_group(job._proc.pid)) >= 3:
            break
        time.sleep(0.1)
    assert len(_running_in_group(job._proc.pid)) >= 3, "the long job started no Dask worker process"
    page.click(f"#jobs tr[data-job='{long_id}'] .cancel")
    page.wait_for_selector(f"#jobs tr[data-job='{long_id}'] td.state:has-text('cancelled')")
    for _ in range(50):  # the process group is gone (SIGTERM, then SIGKILL after 3 s)
        if job._proc is not None and job._proc.poll() is not None:
            break
        time.sleep(0.1)
    assert job._proc.poll() is not None
    for _ in range(50):  # and with it every process of its group (the Dask workers a 512² run starts)
        if not _running_in_group(job._proc.pid):
            break
        time.sleep(0.1)
    else:
        pytest.fail(f"processes of the cancelled job are still running: {_running_in_group(job._proc.pid)}")
    assert page.locator("#job-table").inner_text().strip() != ""
    page.screenshot(path=str(artifacts / "simulation-cancelled.png"), full_page=True)
    # Remove deletes the cancelled job and its folder from the session (its disk counts against the quota)
    folder = job.folder
    page.click(f"#jobs tr[data-job='{long_id}'] .remove")
    page.wait_for_selector(f"#jobs tr[data-job='{long_id}']", state="detached")
    assert not folder.exists()
    assert page.locator("#jobs tr:has-text('grid 32') .show").count() == 1  # the finished one stays


def test_the_prediction_plots_fit_their_cells_and_the_page_its_window(page, artifacts):
    """The plots were drawn while the results were hidden, at Plotly's default 700 px, in cells of 451 px: each covered
    the next and the page scrolled sideways (1629 px at a 1400 px window); on a 420 px phone the form and the results
    shared the width, a word per line. Each plot is now as wide as its cell, and no page is wider than its window."""
    load_example(page)
    goto(page, "/prediction")
    page.wait_for_function("document.querySelector('#leak-rate').dataset.si !== ''")
    widths = page.evaluate("['plot-leak','plot-psd','plot-area','plot-gap','plot-gaps'].map(id => "
                           "[document.getElementById(id).clientWidth, document.getElementById(id)._fullLayout.width])")
    assert all(0 < drawn <= cell for cell, drawn in widths), widths
    assert page.evaluate("document.documentElement.scrollWidth") <= 1400
    page.set_viewport_size({"width": 420, "height": 900})
    goto(page, "/prediction")
    page.wait_for_function("document.querySelector('#leak-rate').dataset.si !== ''")
    page.wait_for_timeout(600)  # (the plots are drawn again 250 ms after a resize)
    assert page.evaluate("document.documentElement.scrollWidth") <= 420
    widths = page.evaluate("['plot-leak','plot-psd'].map(id => "
                           "[document.getElementById(id).clientWidth, document.getElementById(id)._fullLayout.width])")
    assert all(0 < drawn <= cell for cell, drawn in widths), widths
    page.screenshot(path=str(artifacts / "prediction-phone.png"), full_page=True)
