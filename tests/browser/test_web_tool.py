"""The web app as an engineer's tool, in headless Chromium: labels and help, the TOML editor, units,
the busy state, plots with sealed and invalid points, pinned results, the case bundle."""

from __future__ import annotations

import io
import json
import re
import zipfile
from pathlib import Path

import pytest

from sealeak.cases import example_text
from sealeak.cases.form import FIELD_KINDS
from sealeak.cases.form_help import FIELD_HELP
from sealeak.cli import main
from sealeak.io.units import unit_factor

from .test_web_pages import goto, load_example


def cli_json(tmp_path: Path, monkeypatch, capsys, example: str, text: str | None = None) -> dict:
    monkeypatch.chdir(tmp_path)
    (tmp_path / "c.toml").write_text(text or example_text(example), encoding="utf-8")
    assert main(["predict", "c.toml", "--json", "c.json", "-q"]) == 0
    capsys.readouterr()
    return json.loads((tmp_path / "c.json").read_text(encoding="utf-8"))


def test_every_field_has_a_readable_label_its_help_and_a_link_to_it(page, artifacts):
    load_example(page)
    box = page.locator('[data-field="rubber.youngs_modulus"]')
    assert box.locator(".label-text").inner_text() == "Young's modulus E"
    assert box.locator("label code").inner_text() == "youngs_modulus"
    assert box.locator(".hint").inner_text().startswith(FIELD_HELP["rubber.youngs_modulus"].help)
    assert page.locator("#case-form .field .doc-link").count() == len(FIELD_KINDS)
    assert page.locator("#case-form .field .label-text").count() == len(FIELD_KINDS)
    page.screenshot(path=str(artifacts / "case-labels.png"), full_page=False)
    href = box.locator(".doc-link").get_attribute("href")
    assert href == "/help#rubber.youngs_modulus"
    goto(page, href)
    row = page.locator('tr[id="rubber.youngs_modulus"]')
    assert "target" in row.get_attribute("class")
    assert FIELD_HELP["rubber.youngs_modulus"].help in row.inner_text()
    assert page.locator("table.help tbody tr").count() == len(FIELD_KINDS)
    assert "docs/case-files.md#rubber-the-rubber" in page.inner_text("#section-rubber")
    page.screenshot(path=str(artifacts / "help.png"), full_page=False)


def test_the_toml_editor_and_the_form_stay_in_step_and_comments_are_kept(page, artifacts):
    load_example(page)
    editor = page.locator("#toml-editor")
    assert editor.input_value() == example_text("reference-experiment")
    page.fill('[name="rubber.poisson_ratio"]', "0.49")  # the form → the editor, the comments kept
    page.wait_for_function("document.querySelector('#toml-editor').value.includes('poisson_ratio = 0.49')")
    assert editor.input_value() == example_text("reference-experiment").replace("poisson_ratio = 0.5", "poisson_ratio = 0.49")

    text = editor.input_value().replace("hurst = 0.8", "hurst = 0.7  # steeper")  # the editor → the form
    editor.fill(text)
    page.wait_for_function("document.querySelector('[name=\"surface.hurst\"]').value === '0.7'")
    page.wait_for_selector("#status:has-text('the case is valid')")

    broken = text.replace('h_rms = "44 um"', 'h_rms = "44 um" "x"')  # a syntax error: shown in place, the case stays
    line = broken.splitlines().index('h_rms = "44 um" "x"') + 1
    editor.fill(broken)
    err = page.locator("#toml-error")
    err.wait_for(state="visible")
    shown = err.inner_text().splitlines()
    assert shown[0].startswith(f"line {line}, column 17: Expected newline")
    assert shown[1] == f'{line} | h_rms = "44 um" "x"' and shown[2].index("^") == shown[1].index('"x"')
    assert "invalid" in editor.get_attribute("class")
    assert page.input_value('[name="surface.h_rms"]') == "44 um" and page.input_value('[name="surface.hurst"]') == "0.7"
    page.screenshot(path=str(artifacts / "case-toml-error.png"), full_page=False)
    editor.fill(text)
    err.wait_for(state="hidden")
    with page.expect_download() as dl:
        page.click("#download-toml")
    assert Path(dl.value.path()).read_text(encoding="utf-8") == text


def test_an_uploaded_case_with_a_syntax_error_keeps_the_form(page, artifacts, tmp_path):
    load_example(page)
    bad = example_text("reference-experiment").replace("hurst = 0.8", "hurst = 0.8 0.9")
    (tmp_path / "broken.toml").write_text(bad, encoding="utf-8")
    page.set_input_files("#case-file", str(tmp_path / "broken.toml"))
    page.wait_for_selector("#message:has-text('Not loaded: the form keeps the current case')")
    line = bad.splitlines().index("hurst = 0.8 0.9") + 1
    assert f"line {line}" in page.inner_text("#message")
    assert page.input_value('[name="surface.hurst"]') == "0.8"  # the form keeps the current case
    assert page.inner_text("#case-name") == "case: reference-experiment.toml"
    assert page.input_value("#toml-editor") == bad  # the file waits in the editor, its error marked
    assert page.inner_text("#toml-error").startswith(f"line {line}, column")
    page.screenshot(path=str(artifacts / "case-upload-syntax-error.png"), full_page=False)
    page.fill("#toml-editor", bad.replace("hurst = 0.8 0.9", "hurst = 0.9"))  # fixed in the editor: now it is the case
    page.wait_for_function("document.querySelector('[name=\"surface.hurst\"]').value === '0.9'")
    assert page.inner_text("#case-name") == "case: broken.toml"
    assert page.is_hidden("#toml-error")


def test_results_in_the_units_the_user_chooses(page, artifacts, tmp_path, monkeypatch, capsys):
    load_example(page)
    goto(page, "/prediction")
    page.wait_for_function("document.querySelector('#leak-rate').dataset.si !== ''")
    page.select_option("#unit-pressure", "bar")
    page.select_option("#unit-volume_flow", "ml/min")
    page.select_option("#unit-length", "mm")
    row = cli_json(tmp_path, monkeypatch, capsys, "reference-experiment")["results"]
    assert page.inner_text("#leak-rate-unit") == "ml/min"
    ml_min = unit_factor("u", "ml/min", "volume_flow")
    assert float(page.inner_text("#leak-rate")) == pytest.approx(row[0]["leak_rate"] / ml_min, rel=1e-4, abs=0)
    assert page.inner_text("#first-pressure") == f"P0 = {row[0]['squeeze_pressure'] / 1e5:.4g} bar"
    heads = page.locator("#results-table th").all_inner_texts()
    assert "squeeze_pressure (bar)" in heads and "critical_gap (mm)" in heads and "leak_rate (ml/min)" in heads
    gaps = [float(t) for t in page.locator("#results-table td[data-key='critical_gap']").all_inner_texts()]
    assert gaps == pytest.approx([r["critical_gap"] * 1e3 for r in row], rel=1e-4)
    assert "(bar)" in page.evaluate("document.getElementById('plot-leak').layout.xaxis.title.text")
    assert "(ml/min)" in page.evaluate("document.getElementById('plot-leak').layout.yaxis.title.text")
    x = page.evaluate("document.getElementById('plot-leak').data[0].x")
    assert x == pytest.approx([r["squeeze_pressure"] / 1e5 for r in row], rel=1e-9)
    names = page.evaluate("document.getElementById('plot-area').data.map(t => t.name)")
    assert names and all(re.fullmatch(r"P0 = [0-9.e+-]+ bar", n) for n in names), names
    assert "P0 = 0.2 bar" in names  # the first pressure of the sweep, 20 kPa
    page.screenshot(path=str(artifacts / "prediction-units.png"), full_page=False)
    goto(page, "/prediction")  # the choice is kept
    assert page.input_value("#unit-pressure") == "bar"


def test_a_gas_in_sccm_a_compression_in_percent_and_its_sealed_point_marked(page, artifacts, tmp_path, monkeypatch, capsys):
    load_example(page, "helium-test")
    goto(page, "/prediction")
    page.wait_for_function("document.querySelector('#leak-rate').dataset.si !== ''")
    page.select_option("#unit-throughput", "sccm")
    rows = cli_json(tmp_path, monkeypatch, capsys, "helium-test")["results"]
    assert float(page.inner_text("#leak-rate")) == pytest.approx(rows[0]["leak_rate_sccm"], rel=1e-4, abs=0)
    layout = page.evaluate("document.getElementById('plot-leak').layout")
    assert layout["xaxis"]["title"]["text"] == "compression ε (%)" and layout["xaxis"]["type"] == "linear"
    traces = page.evaluate("document.getElementById('plot-leak').data.map(t => ({name: t.name, x: t.x, y: t.y}))")
    assert traces[0]["x"] == pytest.approx([100 * r["compression"] for r in rows], rel=1e-9)
    sealed = [100 * r["compression"] for r in rows if r["leak_rate_pv"] is None]
    assert sealed, "the example has a sealed compression"
    marker = next(t for t in traces if t["name"].endswith(": sealed"))  # the curve's own markers, in its colour
    assert marker["x"] == pytest.approx(sealed)
    lo, hi = layout["yaxis"]["range"]  # fitted: the curve fills the axis, the sealed marker sits at its foot
    finite = [y for y in traces[0]["y"] if y is not None]
    assert 10 ** lo < min(finite) and max(finite) < 10 ** hi < 10 * max(finite)
    assert all(10 ** lo < y < min(finite) for y in marker["y"])
    x_lo, x_hi = layout["xaxis"]["range"]
    assert x_lo < min(traces[0]["x"]) and max(traces[0]["x"]) < x_hi < max(traces[0]["x"]) + 5
    page.locator("#plot-leak").scroll_into_view_if_needed()
    page.screenshot(path=str(artifacts / "prediction-gas-sealed.png"), full_page=False)


def test_points_outside_the_theory_are_marked(page, tmp_path, monkeypatch, capsys):
    """hrms-study reaches critical gaps narrower than a water molecule at its higher pressures (valid = NO)."""
    load_example(page, "hrms-study")
    goto(page, "/prediction")
    page.wait_for_function("document.getElementById('plot-leak').data && document.getElementById('plot-leak').data.length > 0")
    rows = cli_json(tmp_path, monkeypatch, capsys, "hrms-study")["results"]
    invalid = sorted(r["squeeze_pressure"] / 1e3 for r in rows if not r["valid"] and r["leak_rate"])
    assert invalid and len(invalid) < len(rows)
    marked = page.evaluate("(document.getElementById('plot-leak').data.find(t => t.name.startsWith('outside')) || {x: []}).x")
    assert sorted(marked) == pytest.approx(invalid)
    assert page.locator("#results-table tr.invalid-row").count() == sum(not r["valid"] for r in rows)


def test_busy_while_computing_a_superseded_computation_is_aborted_and_the_header_sticks(page, artifacts):
    load_example(page)
    goto(page, "/prediction")
    page.wait_for_function("document.querySelector('#leak-rate').dataset.si !== ''")
    failed: list[str] = []
    page.on("requestfailed", lambda r: failed.append(r.url) if "/api/case/fields" in r.url else None)
    held: list = []  # the first computation is held back (as a slow one would be) until the next edit supersedes it

    def hold(route):
        if held:
            route.continue_()
        else:
            held.append(route)
    page.route("**/api/case/fields", hold)
    with page.expect_request("**/api/case/fields"):
        page.fill('[name="conditions.squeeze_pressure"]', '{start = "20 kPa", stop = "1 MPa", num = 40}')
    page.wait_for_function("document.body.classList.contains('busy')")
    assert float(page.evaluate("getComputedStyle(document.getElementById('results')).opacity")) < 1
    assert page.is_visible("#busy")
    page.fill('[name="conditions.squeeze_pressure"]', "0.5 MPa")  # supersedes the sweep
    page.wait_for_function("document.querySelector('#first-pressure').textContent === 'P0 = 500 kPa'")
    page.wait_for_function("!document.body.classList.contains('busy')")
    assert len(failed) == 1, "the sweep's request was aborted"
    try:
        held[0].continue_()  # too late: the page no longer waits for it
    except Exception:  # noqa: BLE001 - the request is gone
        pass
    assert page.locator("#results-table tbody tr").count() == 1
    page.evaluate("window.scrollTo(0, document.body.scrollHeight)")
    top = page.locator("#result-head").bounding_box()["y"]
    assert 0 <= top < 5, "the result header stays at the top of the window"
    page.screenshot(path=str(artifacts / "prediction-scrolled.png"), full_page=False)


def test_pinned_results_are_overlaid_and_their_inputs_compared(page, artifacts):
    load_example(page)
    goto(page, "/prediction")
    page.wait_for_function("document.querySelector('#leak-rate').dataset.si !== ''")
    page.fill('[name="conditions.squeeze_pressure"]', '{start = "20 kPa", stop = "1 MPa", num = 12}')
    page.wait_for_function("document.querySelectorAll('#results-table tbody tr').length === 12")
    pinned_q = page.evaluate("document.getElementById('plot-leak').data[0].y")
    page.click("#pin")
    page.wait_for_selector("#compare:not([hidden])")
    page.click("details[data-section=rubber] > summary")
    page.fill('[name="rubber.youngs_modulus"]', "5 MPa")
    page.wait_for_function("document.querySelector('#compare-table tr[data-key=\"rubber.youngs_modulus\"]') !== null")
    row = page.locator('#compare-table tr[data-key="rubber.youngs_modulus"]').locator("td").all_inner_texts()
    assert row == ["rubber.youngs_modulus", "5 MPa", "2.3 MPa"]
    assert page.locator("#compare-table tbody tr[data-key]").count() == 1  # only the input that differs
    traces = page.evaluate("document.getElementById('plot-leak').data.map(t => ({name: t.name, y: t.y, dash: t.line && t.line.dash, "
                           "colour: t.line && t.line.color}))")
    pin = next(t for t in traces if t["name"].startswith("#1 "))
    assert pin["dash"] == "dot" and pin["y"] == pinned_q
    assert pin["colour"] and pin["colour"] != traces[0]["colour"]  # a colour of its own, not only a dotted line
    # a stiffer rubber makes less contact at the same squeeze pressure: wider gaps, more leak
    pairs = [(a, b) for a, b in zip(traces[0]["y"], pinned_q) if a and b]
    assert pairs and all(a > b for a, b in pairs)
    page.evaluate("window.scrollTo(0, 0)")
    page.screenshot(path=str(artifacts / "prediction-compare.png"), full_page=False)
    page.click("#compare-table .unpin")
    page.wait_for_selector("#compare", state="hidden")
    assert not any(t.startswith("#1 ") for t in page.evaluate("document.getElementById('plot-leak').data.map(t => t.name)"))


def test_the_case_bundle_holds_the_case_and_its_files(page, tmp_path):
    (tmp_path / "lip.toml").write_text(example_text("lip-profile"), encoding="utf-8")
    (tmp_path / "lip-profile.csv").write_text(example_text("lip-profile.csv"), encoding="utf-8")
    goto(page, "/case")
    page.set_input_files("#case-file", str(tmp_path / "lip.toml"))
    page.set_input_files("#data-files", str(tmp_path / "lip-profile.csv"))
    page.wait_for_selector("#status:has-text('the case is valid')", timeout=60_000)
    with page.expect_download() as dl:
        page.click("#download-bundle")
    assert dl.value.suggested_filename == "lip.zip"
    z = zipfile.ZipFile(io.BytesIO(Path(dl.value.path()).read_bytes()))
    assert sorted(z.namelist()) == ["lip/lip-profile.csv", "lip/lip.toml"]
    assert z.read("lip/lip-profile.csv").decode() == example_text("lip-profile.csv")


def test_an_instrument_file_name_is_accepted_and_shown_with_its_stored_name(page, tmp_path):
    name = "Lippe Ø5 µm #3;Prüfung.csv"
    (tmp_path / name).write_text(example_text("lip-profile.csv"), encoding="utf-8")
    (tmp_path / "lip.toml").write_text(example_text("lip-profile").replace("lip-profile.csv", name), encoding="utf-8")
    goto(page, "/case")
    page.set_input_files("#data-files", str(tmp_path / name))
    page.wait_for_selector("#uploads:has-text('uploaded as')")
    page.set_input_files("#case-file", str(tmp_path / "lip.toml"))
    page.wait_for_selector("#status:has-text('the case is valid')", timeout=60_000)
    assert page.inner_text("#uploads") == f"Lippe O5 um _3_Prufung.csv (uploaded as {name})"
    assert page.input_value('[name="seal.pressure_profile"]') == name


def test_each_curve_marks_its_own_sealed_and_invalid_points_in_its_colour(page, artifacts, tmp_path, monkeypatch, capsys):
    """The o-ring example: two fluids, both theories. A sealed load is marked in the colour of the curve that seals
    there (not one colour for all), and the effective medium's points outside the theory are crossed as the critical
    junction's are."""
    load_example(page, "o-ring")
    goto(page, "/prediction")
    page.wait_for_function("document.querySelector('#leak-rate').dataset.si !== ''", timeout=120_000)
    traces = page.evaluate("document.getElementById('plot-leak').data.map(t => ({name: t.name, x: t.x, y: t.y, "
                           "colour: (t.marker || {}).color, line: (t.line || {}).color}))")
    rows = cli_json(tmp_path, monkeypatch, capsys, "o-ring")["results"]
    by_name = {t["name"]: t for t in traces}
    for study in ("water", "oil"):
        for theory, key in (("critical junction", "leak_rate"), ("effective medium", "leak_rate_effective_medium")):
            curve = next(t for t in traces if t["name"].startswith(study) and t["name"].endswith(theory))
            mine = [r for r in rows if str(r.get("variant", "")).startswith(study)]
            sealed = [100 * r["compression"] for r in mine if r[key] is None]
            marks = by_name.get(f"{curve['name']}: sealed")
            assert (marks["x"] if marks else []) == pytest.approx(sealed)
            if marks:
                assert marks["colour"] == curve["line"]
    invalid_em = sorted(100 * r["compression"] for r in rows
                        if r.get("valid_effective_medium") is False and r["leak_rate_effective_medium"] is not None)
    crossed = sorted(next(t for t in traces if t["name"].startswith("outside"))["x"])
    assert invalid_em and all(any(abs(x - c) < 1e-9 for c in crossed) for x in invalid_em)
    page.locator("#plot-leak").scroll_into_view_if_needed()
    page.locator("#plot-leak").screenshot(path=str(artifacts / "prediction-o-ring-marks.png"))
