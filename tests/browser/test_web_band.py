"""The prediction page of a case with uncertain inputs: the leak-rate plot draws the 5–95 % band (issue 24 item 5).

The band must be the command line's percentiles (`sealeak predict --json` with the default samples and seed),
the nominal curve must be the deterministic prediction, and the page is photographed for a person to look at.
"""

from __future__ import annotations

import json

import pytest

from tests.browser.test_web_pages import cli, goto
from tests.casefiles import edit

UNCERTAIN = edit('[conditions]\n', '[conditions]\nmax_leak_rate = "100 ml/min"\n',
                 edit('h_rms = "44 um"', 'h_rms = "44 um ± 15 %"'))


def _upload(page, tmp_path, name: str, text: str) -> None:
    """Upload ``text`` as the case file ``name`` on the case page and wait until it is checked."""
    (tmp_path / name).write_text(text, encoding="utf-8")
    goto(page, "/case")
    page.set_input_files("#case-file", str(tmp_path / name))
    page.wait_for_selector("#status:has-text('the case is valid')", timeout=120_000)


def _leak_traces(page) -> dict[str, dict]:
    """The prediction page's leak-rate traces by name, once its band is drawn: x, y and the colours of marker and line."""
    goto(page, "/prediction")
    page.wait_for_function("(document.getElementById('plot-leak').data || []).some(t => t.fill === 'tonexty')", timeout=120_000)
    return {t["name"]: t for t in page.evaluate(
        "document.getElementById('plot-leak').data.map(t => ({name: t.name, x: t.x, y: t.y, fill: t.fill || '', "
        "colour: (t.marker || {}).color, line: (t.line || {}).color}))")}


def test_prediction_plot_draws_the_band_of_the_cli(page, artifacts, tmp_path, monkeypatch, capsys):
    _upload(page, tmp_path, "band.toml", UNCERTAIN)
    # the list of examples names the uploaded file, not the example last loaded
    assert page.input_value("#example") == ""
    assert page.evaluate("document.querySelector('#example').selectedOptions[0].textContent").startswith("band.toml (uploaded")
    band = {name: t["y"] for name, t in _leak_traces(page).items()}
    assert cli(tmp_path, monkeypatch, capsys, "predict", "band.toml", "--json", "out.json", "-q")[0] == 0
    rows = json.loads((tmp_path / "out.json").read_text())["results"]
    # the page shows m³/s by default
    assert band["5th percentile of the samples"] == pytest.approx([r["leak_rate_p05"] for r in rows], rel=1e-9, abs=0)
    assert band["5–95 % of 256 samples"] == pytest.approx([r["leak_rate_p95"] for r in rows], rel=1e-9, abs=0)
    assert band["median of the samples"] == pytest.approx([r["leak_rate_p50"] for r in rows], rel=1e-9, abs=0)
    assert band["critical junction (nominal inputs)"] == pytest.approx([r["leak_rate"] for r in rows], rel=1e-9, abs=0)
    assert all(lo < q < hi for lo, q, hi in zip(band["5th percentile of the samples"], band["critical junction (nominal inputs)"],
                                                  band["5–95 % of 256 samples"]))
    page.locator("#plot-leak").scroll_into_view_if_needed()
    page.locator("#plot-leak").screenshot(path=str(artifacts / "prediction-band.png"))


def test_a_band_over_a_load_where_most_samples_seal_keeps_its_median_inside_it(page, artifacts, tmp_path):
    """At 1 MPa nearly every sample seals (p05 = p50 = 0) and the 95th percentile is ~1e-40 m³/s, far below the
    axis: every percentile drawn there sits at the axis' foot, so the median never leaves the band between rows."""
    text = edit('squeeze_pressure = ["20 kPa", "60 kPa", "0.1 MPa"]', 'squeeze_pressure = ["20 kPa", "60 kPa", "0.1 MPa", "1 MPa"]',
                edit('h_rms = "44 um"', 'h_rms = "44 um ± 10 %"'))
    _upload(page, tmp_path, "sealing.toml", text)
    traces = _leak_traces(page)
    lo, med, hi = (traces[n]["y"] for n in ("5th percentile of the samples", "median of the samples", "5–95 % of 256 samples"))
    low_end = 10 ** page.evaluate("document.getElementById('plot-leak').layout.yaxis.range[0]")
    assert all(low_end < a <= b <= c for a, b, c in zip(lo, med, hi)), (lo, med, hi)
    assert lo[-1] == med[-1] == hi[-1]  # all at the foot at 1 MPa
    sealed = traces["critical junction (nominal inputs): sealed"]  # the nominal curve has no channel at 1 MPa
    curve = traces["critical junction (nominal inputs)"]
    assert sealed["x"] == [traces["median of the samples"]["x"][-1]] and sealed["colour"] == curve["line"]
    page.locator("#plot-leak").scroll_into_view_if_needed()
    page.locator("#plot-leak").screenshot(path=str(artifacts / "prediction-band-sealing.png"))


def test_a_median_from_samples_outside_the_theory_is_drawn_hollow(page, artifacts, tmp_path):
    """At 850 kPa the ring's critical gap is narrower than a water molecule (valid = NO), yet it percolates: the
    median of the samples there is circled, not a point to rely on; so is the 5th percentile at 700 kPa, a sample
    of the same kind (the command line's table stars both)."""
    text = edit('squeeze_pressure = ["20 kPa", "60 kPa", "0.1 MPa"]', 'squeeze_pressure = ["300 kPa", "700 kPa", "850 kPa"]',
                edit('h_rms = "44 um"', 'h_rms = "44 um ± 10 %"'))
    _upload(page, tmp_path, "narrow.toml", text)
    traces = _leak_traces(page)
    hollow = traces["median from samples outside the theory"]
    median = traces["median of the samples"]
    assert hollow["x"] == [median["x"][-1]] and hollow["y"] == [median["y"][-1]]
    edge = traces["5th percentile from samples outside the theory"]
    low = traces["5th percentile of the samples"]
    assert edge["x"] == [low["x"][1]] and edge["y"] == [low["y"][1]]
    assert "95th percentile from samples outside the theory" not in traces
    page.locator("#plot-leak").scroll_into_view_if_needed()
    page.locator("#plot-leak").screenshot(path=str(artifacts / "prediction-band-outside.png"))
