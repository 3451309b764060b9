"""The prediction page of the seal over its life: Q against the time since assembly and against the temperature drawn
from the rows of the JSON, with the specification line; legends under their axis titles."""

from __future__ import annotations

import re

import pytest

from sealeak.cases import example_text

from .test_web_pages import goto, load_example

#: A time axis' unit in s (the x of the time plot is the time in the unit its title names).
SECONDS = {"s": 1.0, "min": 60.0, "h": 3600.0, "d": 86400.0, "a": 365.25 * 86400.0}

PLOTS = "['plot-life-time', 'plot-life-temperature'].map(id => document.getElementById(id))"


def _data(page, plot_id: str) -> dict:
    return page.evaluate(f"""(() => {{ const el = document.getElementById('{plot_id}');
        return {{ hidden: el.hidden, layout: el.layout || null,
                  data: (el.data || []).map(t => ({{ name: t.name, x: t.x, y: t.y, yaxis: t.yaxis || 'y' }})) }}; }})()""")


def _approx(shown: list, expected: list[float | None]) -> None:
    """Shown values against the rows' (None: no leak, drawn as a gap)."""
    assert len(shown) == len(expected)
    for s, e in zip(shown, expected):
        assert (s is None) == (e is None)
        if e is not None:
            assert s == pytest.approx(e, rel=1e-9, abs=0)


def _boxes_apart(page, plot_id: str) -> None:
    """The legend lies wholly below the x-axis title (their boxes on the screen do not overlap)."""
    legend, title = (page.locator(f"#{plot_id} {sel}").first.bounding_box() for sel in (".legend", ".xtitle"))
    assert legend is not None and title is not None
    assert legend["y"] >= title["y"] + title["height"], (plot_id, legend, title)


def _predicted(page, text: str) -> list[dict]:
    """Type ``text`` into the case page's TOML editor, open the prediction page once it has run, and return the rows
    of its JSON."""
    goto(page, "/case")
    page.fill("#toml-editor", text)
    page.wait_for_selector("#status:has-text('the case is valid')", timeout=60_000)
    goto(page, "/prediction")
    page.wait_for_function("document.querySelector('#leak-rate').dataset.si !== ''")
    return page.evaluate("fetch('/download/results.json').then(r => r.json())")["results"]


def test_life_plots_draw_the_rows_against_time_and_temperature(page, artifacts):
    # the bundled life example with a specification
    rows = _predicted(page, example_text("nbr-o-ring-life").replace(
        'downstream_pressure = "1 bar"', 'downstream_pressure = "1 bar"\nmax_leak_rate = "1e-6 mbar*l/s"'))
    cases: dict[tuple[float, float], list[dict]] = {}  # each (time, temperature): its rows, one per load, in order
    for r in rows:
        cases.setdefault((r["time"], r["temperature"]), []).append(r)
    times = sorted({t for t, _ in cases})
    temps = sorted({T for _, T in cases})
    loads = min(len(c) for c in cases.values())
    assert (len(times), len(temps), loads) == (4, 5, 2)

    def q(t: float, T: float, n: int, key: str = "leak_rate_mbar_l_s") -> float | None:
        v = cases[(t, T)][n][key]
        return v if isinstance(v, float) and v > 0 else None

    by_time = _data(page, "plot-life-time")
    assert not by_time["hidden"] and by_time["layout"]["xaxis"]["type"] == "log"
    unit = by_time["layout"]["xaxis"]["title"]["text"].rsplit("(", 1)[1].rstrip(")")
    assert "mbar·l/s" in by_time["layout"]["yaxis"]["title"]["text"]
    for n, yaxis in enumerate(["y", "y2"]):  # a panel per load
        curves = {c["name"]: c for c in by_time["data"] if c["yaxis"] == yaxis}
        for T in temps:
            c = curves[f"T = {T - 273.15:.4g} °C"]
            assert [x * SECONDS[unit] for x in c["x"]] == pytest.approx(times, rel=1e-9)
            _approx(c["y"], [q(t, T, n) for t in times])
        limit = curves["max_leak_rate = 1e-6 mbar*l/s"]
        assert limit["y"] == pytest.approx([1e-6, 1e-6], rel=1e-9, abs=0)

    by_temp = _data(page, "plot-life-temperature")
    assert not by_temp["hidden"] and by_temp["layout"]["xaxis"]["title"]["text"] == "temperature T (°C)"
    for n, yaxis in enumerate(["y", "y2"]):
        curves = [c for c in by_temp["data"] if c["yaxis"] == yaxis and c["name"].startswith("t = ")
                  and not c["name"].endswith(": below the axis")]
        assert len(curves) == len(times)
        for t, c in zip(times, curves):  # a curve per time, in order
            assert c["x"] == pytest.approx([T - 273.15 for T in temps], rel=1e-9)
            _approx(c["y"], [q(t, T, n) for T in temps])

    # points more than 20 decades under a panel's top (a cold seal) were cut off the axis: open triangles at its foot
    marked = 0
    for n, yaxis in enumerate(["y", "y2"]):
        lo = by_temp["layout"]["yaxis" if n == 0 else "yaxis2"]["range"][0]
        foot = 10 ** (lo + 0.1)
        for c in by_temp["data"]:
            if c["yaxis"] != yaxis or not c["name"].startswith("t = ") or c["name"].endswith("below the axis"):
                continue
            below = [x for x, y in zip(c["x"], c["y"]) if y is not None and y < foot]
            marks = [m for m in by_temp["data"] if m["name"] == f"{c['name']}: below the axis" and m["yaxis"] == yaxis]
            assert [x for m in marks for x in m["x"]] == below
            marked += len(below)
    assert marked > 0  # the example's cold, young seal leaks more than 20 decades under its hot, old one
    page.select_option("#unit-throughput", "Pa·m³/s")  # the unit chosen: the curves follow it
    page.wait_for_function("document.getElementById('plot-life-time').layout.yaxis.title.text.includes('Pa·m³/s')")
    first = _data(page, "plot-life-time")["data"][0]
    _approx(first["y"], [q(t, temps[0], 0, "leak_rate_pv") for t in times])

    for plot_id in ("plot-life-time", "plot-life-temperature", "plot-leak", "plot-gaps"):
        _boxes_apart(page, plot_id)  # plot-leak: 22 entries, one per row
    # the per-case plots of the surface and its gaps are the case as assembled: one spectrum, not one per case
    assert page.evaluate("document.getElementById('plot-psd').data.length") == 1
    page.screenshot(path=str(artifacts / "prediction-life.png"), full_page=True)
    page.locator("#plot-life-time").screenshot(path=str(artifacts / "prediction-life-time.png"))


def test_no_life_plots_without_time(page):
    load_example(page)
    goto(page, "/prediction")
    page.wait_for_function("document.querySelector('#leak-rate').dataset.si !== ''")
    assert page.evaluate(f"{PLOTS}.map(el => [el.hidden, (el.data || []).length])") == [[True, 0], [True, 0]]
    assert page.evaluate("document.getElementById('plot-leak').data.length") >= 1


def test_life_plots_of_a_study_draw_each_variant_on_its_own_curves(page, artifacts):
    """A [study] × life file (h_rms 1.5 and 3 µm, 2 times × 2 temperatures, 2 compressions): each panel has a curve
    per variant and temperature, named after the variant, drawing that variant's rows (not the rows of all variants
    taken as more loads)."""
    text = (example_text("nbr-o-ring-life")
            .replace('time = ["1 h", "30 d", "1 a", "10 a"]', 'time = ["1 h", "1 a"]')
            .replace('temperature = ["-40 degC", "-10 degC", "20 degC", "60 degC", "100 degC"]',
                     'temperature = ["-10 degC", "60 degC"]')
            + '\n[study]\nvary = "surface.h_rms"\nvalues = ["1.5 um", "3 um"]\n'
              'labels = ["h_rms = 1.5 µm", "h_rms = 3 µm"]\n')
    rows = _predicted(page, text)
    cases: dict[tuple[str, float, float], list[dict]] = {}  # each (variant, time, temperature): its rows, by load
    for r in rows:
        cases.setdefault((r["variant"].split("; ")[0], r["time"], r["temperature"]), []).append(r)
    variants = ["h_rms = 1.5 µm", "h_rms = 3 µm"]
    times = sorted({t for _, t, _ in cases})
    temps = sorted({T for _, _, T in cases})
    assert {v for v, _, _ in cases} == set(variants) and {len(c) for c in cases.values()} == {2}

    by_time = _data(page, "plot-life-time")
    assert not by_time["hidden"]
    for n, yaxis in enumerate(["y", "y2"]):  # a panel per load: 2, not 4
        curves = {c["name"]: c for c in by_time["data"] if c["yaxis"] == yaxis}
        for v in variants:
            for T in temps:
                c = curves[f"{v}, T = {T - 273.15:.4g} °C"]
                v_rows = [cases[(v, t, T)][n]["leak_rate_mbar_l_s"] for t in times]
                _approx(c["y"], [q if isinstance(q, float) and q > 0 else None for q in v_rows])
    assert not [c for c in by_time["data"] if c["yaxis"] == "y3"]
    _boxes_apart(page, "plot-life-time")
    page.locator("#plot-life-time").screenshot(path=str(artifacts / "prediction-life-study.png"))


def test_the_leak_plot_of_a_life_file_gives_each_of_its_20_cases_a_colour(page):
    """The life example's 20 (time, temperature) cases drawn against the load: ten colours repeated, so that
    "t = 1 h, T = -40 °C" and "t = 1 a, T = 20 °C" were the same blue."""
    _predicted(page, example_text("nbr-o-ring-life"))
    colours = page.evaluate("document.getElementById('plot-leak').data.filter(t => t.mode && t.mode.includes('lines'))"
                            ".map(t => [t.name, t.line && t.line.color])")
    hue = {name.split(":")[0]: re.sub(r"rgba?\((\d+),(\d+),(\d+).*", r"\1,\2,\3", c) for name, c in colours if c}
    assert len(hue) == 20 and len(set(hue.values())) == 20, hue


def test_a_case_sealed_at_every_load_draws_its_triangles_at_the_foot_of_an_axis_without_numbers(page, artifacts):
    """The water-o-ring example seals at every compression: the axis fitted itself around 10⁻³⁰ with the sealed
    triangles mid-axis, as if the leak rate were 10⁻³⁰ m³/s."""
    rows = _predicted(page, example_text("water-o-ring"))
    assert rows and all(r["leak_rate"] in (0, 0.0, None) for r in rows)
    layout = page.evaluate("document.getElementById('plot-leak').layout.yaxis")
    assert layout["showticklabels"] is False and layout["title"]["text"].endswith(": 0 everywhere")
    marks = page.evaluate("document.getElementById('plot-leak').data.filter(t => (t.name || '').endsWith(': sealed'))"
                          ".map(t => t.y)")
    low = 10 ** layout["range"][0]
    assert marks and all(low < y < 10 ** (layout["range"][0] + 0.5) for m in marks for y in m)  # at the foot
    page.locator("#plot-leak").scroll_into_view_if_needed()
    page.locator("#plot-leak").screenshot(path=str(artifacts / "prediction-all-sealed.png"))
