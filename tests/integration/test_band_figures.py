"""Figures and report of O-ring and pressure-profile seals (issue 12, "What to build" 3 and 5).

Small variants of the bundled examples: the O-ring study (water and oil) at three compressions with
the critical junction alone, the lip profile at two scales with both theories; each has a load
whose band holds no leak channel. The figures must draw what :class:`~sealeak.cases.band.BandResult`
holds (checked from the figure objects), read right (the checks every figure passes,
tests/integration/test_figures_render.py), and `sealeak predict --plots` must write them instead
of the uniform figures; the report shows the band table, not the uniform one.
"""

import html
import re
from pathlib import Path

import numpy as np
import pytest

from sealeak.cases import example_path, parse_case_file, read_case_file, run_case
from sealeak.cli import main
from sealeak.physics.profile import PressureProfile, resistance_band, series_resistance
from sealeak.render import html_report, prediction_figures
from sealeak.render.band import BAND_FIGURE_NAMES, load_labels, local_gap_curve, profile_curve, resistance_spans
from sealeak.render.figures import PREDICTION_FIGURE_NAMES, prediction_figure_names
from sealeak.render.notes import worded
from sealeak.render.text import prediction_columns, validity_notes
from tests.integration.test_figures_render import _build, figure_problems

BAND_FILES = {"spectrum.png", *BAND_FIGURE_NAMES}
PNG = b"\x89PNG\r\n\x1a\n"


def _oring_text():
    text = Path(example_path("o-ring")).read_text()
    text = re.sub(r"(?m)^compression = .*$", 'compression = ["10 %", "20 %", "30 %"]', text)
    return re.sub(r'(?m)^model = "both"$', 'model = "critical-junction"', text)


def _lip_text():
    return re.sub(r"(?m)^profile_scale = .*$", "profile_scale = [0.5, 2.0]", Path(example_path("lip-profile")).read_text())


@pytest.fixture(scope="module")
def cases_dir(tmp_path_factory):
    folder = tmp_path_factory.mktemp("band")
    (folder / "o-ring.toml").write_text(_oring_text())
    (folder / "lip.toml").write_text(_lip_text())
    (folder / "lip-profile.csv").write_text(Path(example_path("lip-profile")).with_name("lip-profile.csv").read_text())
    return folder


@pytest.fixture(scope="module")
def runs(cases_dir):
    """(results, figures, case file) of each small example."""
    out = {}
    for name in ("o-ring", "lip"):
        case_file = read_case_file(cases_dir / f"{name}.toml")
        results = [run_case(c) for c in case_file.cases]
        out[name] = (results, _build(lambda results=results: prediction_figures(results)), case_file)
    return out


def test_the_small_examples_have_what_the_figures_must_show(runs):
    """The premise: a study of two fluids, both theories in one case, a sealed load and an invalid one."""
    oring, lip = runs["o-ring"][0], runs["lip"][0]
    assert len(oring) == 2 and oring[0].case.fluid.molecular_length != oring[1].case.fluid.molecular_length
    assert lip[0].band.effective_medium is not None
    for results in (oring, lip):
        assert (~results[0].band.critical_junction.percolates).any() and results[0].band.critical_junction.percolates.any()
    assert (~oring[0].valid & oring[0].band.critical_junction.percolates).any()


@pytest.mark.parametrize("name", ["o-ring", "lip"])
def test_band_figures_replace_the_uniform_ones_and_read_right(name, runs):
    results, figures, _ = runs[name]
    assert set(figures) == BAND_FILES == set(prediction_figure_names([r.case for r in results]))
    assert not set(figures) & (set(PREDICTION_FIGURE_NAMES) - {"spectrum.png", "leak_rate.png"})
    bad = {n: p for n, fig in figures.items() if (p := figure_problems(fig))}
    assert not bad, bad


def _lines(ax, style=None):
    out = []
    for line in ax.get_lines():
        if line.get_transform() != ax.transData or not len(line.get_xdata()):
            continue
        if style is None or line.get_linestyle() == style:
            out.append(line)
    return out


def _xy(line):
    return np.asarray(line.get_xdata(), dtype=float), np.asarray(line.get_ydata(), dtype=float)


@pytest.mark.parametrize("name", ["o-ring", "lip"])
def test_pressure_profile_draws_each_load_and_where_its_resistance_sits(name, runs):
    results, figures, _ = runs[name]
    r = results[0]
    b = r.band
    top, bars = figures["pressure_profile.png"].axes[:2]
    sx = 1e-3 if b.contact_width.max() >= 1e-3 else 1e-6
    ps = 1e6 if "MPa" in top.get_ylabel() else 1e3
    lines = _lines(top)
    assert len(lines) == len(b)  # one curve per load (the study's variants share them)
    for i, (profile, line) in enumerate(zip(b.band.profiles, lines)):
        x, p = _xy(line)
        centre = profile.width / 2 if b.band.kind == "o-ring" else 0.0
        x_m = x * sx + centre
        np.testing.assert_allclose(p * ps, profile.at(x_m), rtol=1e-12, atol=1e-9 * b.max_contact_pressure[i])
        assert x_m.min() == pytest.approx(0, abs=1e-12) and x_m.max() == pytest.approx(b.contact_width[i], rel=1e-12, abs=0)
        assert (p * ps).max() == pytest.approx(b.max_contact_pressure[i], rel=1e-9)
    # the bars: per load the intervals of the highest pressures, as wide as the band that holds 90 % of R
    labels = [t.get_text() for t in bars.get_yticklabels()]
    assert labels == load_labels(b.band)
    rows: dict[int, list] = {}
    for line in _lines(bars):
        x, y = _xy(line)
        assert y[0] == y[1]
        rows.setdefault(int(y[0]), []).append((x.min() * sx, x.max() * sx))
    widths = b.critical_junction.resistance_band_width
    for i, profile in enumerate(b.band.profiles):
        if not b.critical_junction.percolates[i]:
            assert i not in rows
            assert any("no leak channel" in t.get_text() and round(t.get_position()[1]) == i for t in bars.texts)
            continue
        spans = rows[i]
        assert sum(hi - lo for lo, hi in spans) == pytest.approx(widths[i], rel=1e-6)
        centre = profile.width / 2 if b.band.kind == "o-ring" else 0.0
        x = np.linspace(0, profile.width, 4001)
        inside = np.zeros(x.size, bool)
        for lo, hi in spans:
            inside |= (x >= lo + centre) & (x <= hi + centre)
        p = profile.at(x)
        assert p[inside].min() >= p[~inside].max() * (1 - 1e-6)  # the resistance sits where the pressure is highest


def test_resistance_spans_hold_the_band_width_at_the_highest_pressures():
    """A step (plateau) profile and a Hertz profile: the spans are the reported width, at the highest pressures."""
    sigma = lambda p: 1e-15 * np.exp(-p / 2e5)  # noqa: E731  falls with p, like both theories
    step = PressureProfile.table([0, 1e-4, 1e-4, 3e-4, 3e-4, 4e-4], [1e5, 1e5, 4e5, 4e5, 2e5, 2e5])
    hertz = PressureProfile.semi_elliptic(1e-3, 1e6)
    for profile in (step, hertz):
        width, _ = resistance_band(series_resistance(profile, sigma))
        spans = resistance_spans(profile, width)
        assert sum(hi - lo for lo, hi in spans) == pytest.approx(width, rel=1e-9, abs=0)
        edges = np.linspace(0, profile.width, 8001)
        x = (edges[1:] + edges[:-1]) / 2  # cell centres: never on a step
        inside = np.zeros(x.size, bool)
        for lo, hi in spans:
            inside |= (x > lo) & (x < hi)
        assert profile.at(x)[inside].min() >= profile.at(x)[~inside].max() - 1e-6
        assert len(spans) == 1  # one piece: the partial plateau lies next to the higher pressures
    assert resistance_spans(hertz, float("nan")) == []


@pytest.mark.parametrize("name", ["o-ring", "lip"])
def test_local_critical_gap_is_the_band_results_and_smallest_where_the_pressure_peaks(name, runs):
    results, figures, _ = runs[name]
    r = results[0]
    b = r.band
    ax = figures["local_critical_gap.png"].axes[0]
    assert ax.get_yscale() == "log"
    us = 1e-9 if "(nm)" in ax.get_ylabel() else 1e-6
    lines = [ln for ln in _lines(ax) if ln.get_linestyle() == "-"]
    open_loads = np.flatnonzero(b.critical_junction.percolates)
    assert len(lines) == open_loads.size  # sealed loads are named in the subtitle, not drawn
    for i, line in zip(open_loads, lines):
        x, u = _xy(line)
        uc = b.local_critical_gap(int(i), r.case.alpha, r.case.fluid.viscosity)
        pos = uc[uc > 0]
        assert (np.abs(u[:, None] * us / pos[None, :] - 1).min(axis=1) < 1e-12).all()  # each drawn value is one of BandResult's
        np.testing.assert_allclose(local_gap_curve(r, int(i))[1], u * us)
        # u_c falls as p rises: its smallest value is at the peak pressure, where the band's verdict is judged
        gap_min = (u * us).min()
        assert gap_min == pytest.approx(b.critical_gap_at_max_pressure[i], rel=0.05)
        assert gap_min >= b.critical_gap_at_max_pressure[i] * (1 - 1e-9)
    sealed = b.band.loads[~b.critical_junction.percolates]
    value = f"{100 * sealed[0]:.3g} %" if b.band.load_name == "compression" else f"scale {sealed[0]:.3g}"
    assert "no leak channel" in ax.get_title() and value in ax.get_title()
    # the molecular size of each fluid, dashed
    sizes = sorted({res.case.fluid.molecular_length for res in results})
    flat = sorted(float(ln.get_ydata()[0]) * us for ln in ax.get_lines()
                  if ln.get_transform() != ax.transData and ln.get_linestyle() != "-")
    np.testing.assert_allclose(flat, sizes, rtol=1e-12)


@pytest.mark.parametrize("name", ["o-ring", "lip"])
def test_leak_rate_figure_shows_each_theory_its_uniform_twin_and_the_sealed_loads(name, runs):
    results, figures, _ = runs[name]
    ax = figures["leak_rate.png"].axes[0]
    assert ax.get_yscale() == "log" and "ml/min" in ax.child_axes[0].get_ylabel()
    solid = [ln for ln in _lines(ax, "-") if np.isfinite(_xy(ln)[1]).any()]
    dashed = _lines(ax, "--")
    theories = [(r, t) for r in results for t in (r.band.critical_junction, r.band.effective_medium)
                if t is not None and (t is r.band.effective_medium or r.shows_critical_junction)]
    assert len(solid) == len(dashed) == len(theories)
    crosses = [ln for ln in ax.get_lines() if ln.get_marker() == "x" and len(ln.get_xdata())]
    lo = min(np.nanmin(_xy(ln)[1]) for ln in solid + dashed)
    for (r, theory), s, d in zip(theories, solid, dashed):
        b = r.band
        x_load = 100 * b.band.loads if b.band.load_name == "compression" else b.band.loads
        x, q = _xy(s)
        np.testing.assert_allclose(x, x_load)
        shown = theory.percolates & (r.valid if theory is b.critical_junction else True)
        np.testing.assert_allclose(q[shown], theory.leak_rate[shown], rtol=1e-12)
        assert not np.isfinite(q[~shown]).any()
        xd, qd = _xy(d)
        np.testing.assert_allclose(qd, theory.uniform_mean_pressure, rtol=1e-12)
        assert s.get_color() == d.get_color()
        # a sealed load is an × at the bottom, in the theory's colour, not dropped
        mine = [c for c in crosses if c.get_color() == s.get_color()]
        n_sealed = int((~theory.percolates).sum())
        assert sum(len(c.get_xdata()) for c in mine) == n_sealed
        for c in mine:
            cx, cy = _xy(c)
            assert np.all(cy < lo) and np.all(cy > ax.get_ylim()[0])
            np.testing.assert_allclose(np.sort(cx), np.sort(x_load[~theory.percolates]), rtol=0.03)
    labels = [t.get_text() for leg in [*figures["leak_rate.png"].legends, ax.get_legend()] if leg for t in leg.get_texts()]
    assert any("no leak channel" in t for t in labels) and any("mean" in t for t in labels)


def test_invalid_loads_are_hollow(runs):
    results, figures, _ = runs["o-ring"]
    ax = figures["leak_rate.png"].axes[0]
    hollow = [ln for ln in ax.get_lines() if ln.get_markerfacecolor() == "none" and len(ln.get_xdata())]
    invalid = sum(int((~r.valid & r.band.critical_junction.percolates).sum()) for r in results)
    assert invalid and sum(len(ln.get_xdata()) for ln in hollow) == invalid


def test_profile_curve_of_a_hertz_profile_is_the_profile():
    prof = PressureProfile.semi_elliptic(2e-3, 1.5e6)
    x, p = profile_curve(prof)
    np.testing.assert_allclose(p, 1.5e6 * np.sqrt(np.clip(1 - (x / 1e-3 - 1) ** 2, 0, None)), rtol=1e-12, atol=1e-6)
    assert np.trapezoid(p, x) == pytest.approx(prof.force_per_length, rel=1e-3)


def test_report_of_a_band_case_has_the_band_table_and_figures_not_the_uniform_ones(runs):
    results, _, case_file = runs["lip"]
    text = html_report(results, case_file.inputs)
    headers, rows = prediction_columns(results[0])
    heads = re.findall(r"<th[^>]*>([^<]*)</th>", text)
    assert all(h in heads for h in headers)
    for uniform_only in ("ζc", "λc (µm)", "A(ζ1)/A0", "P0 (kPa)", "σ_eff (m³/Pa/s)"):
        assert uniform_only not in heads
    figure_ids = re.findall(r'<figure id="fig-([^"]+)"', text)
    assert set(figure_ids) == BAND_FILES
    for name in set(PREDICTION_FIGURE_NAMES) - BAND_FILES:
        assert name not in text
    # the band table's rows as predict prints them; the sealed load's leak rate and verdict read "—"
    table_rows = [re.findall(r"<td[^>]*>([^<]*)</td>", tr) for tr in re.findall(r"<tr[^>]*>(.*?)</tr>", text)]
    for row in rows:
        assert [html.escape(c.strip()) for c in row] in table_rows
    sealed = int(np.flatnonzero(~results[0].band.critical_junction.percolates)[0])
    assert rows[sealed][-1].strip() == "—" and rows[sealed][headers.index("Q_CJ (m³/s)")].strip() == "—"
    assert 'id="seal"' in text and "lip-profile.csv" in text
    for note in [*worded(results[0].messages), *validity_notes(results[0])]:
        assert html.escape(note) in text


def test_predict_plots_writes_the_band_figures(cases_dir, tmp_path, capsys):
    out = tmp_path / "plots"
    assert main(["predict", str(cases_dir / "o-ring.toml"), "--plots", str(out)]) == 0
    written = {p.name for p in out.iterdir()}
    assert written == BAND_FILES
    for p in out.iterdir():
        data = p.read_bytes()
        assert data.startswith(PNG) and len(data) > 10_000
    assert "wrote 4 figures" in capsys.readouterr().err


@pytest.mark.parametrize("existing", sorted(BAND_FIGURE_NAMES))
def test_an_existing_band_figure_is_not_replaced(existing, cases_dir, tmp_path, capsys):
    out = tmp_path / "plots"
    out.mkdir()
    (out / existing).write_bytes(b"mine")
    assert main(["predict", str(cases_dir / "lip.toml"), "--plots", str(out)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and existing in err and "Traceback" not in err
    assert (out / existing).read_bytes() == b"mine" and {p.name for p in out.iterdir()} == {existing}


@pytest.mark.parametrize("edits", [
    {"profile_scale = [0.5, 2.0]": "profile_scale = [3.0, 4.0]"},
    {"profile_scale = [0.5, 2.0]": "profile_scale = [0.5]", 'model = "both"': 'model = "effective-medium"'},
], ids=["every load sealed", "the effective medium alone"])
def test_degenerate_band_runs_draw_and_say_why(edits, cases_dir, tmp_path):
    text = _lip_text()
    for old, new in edits.items():
        assert old in text
        text = text.replace(old, new)
    path = cases_dir / f"lip-{len(edits)}.toml"
    path.write_text(text)
    results = [run_case(c) for c in read_case_file(path).cases]
    figures = _build(lambda: prediction_figures(results))
    bad = {n: p for n, fig in figures.items() if (p := figure_problems(fig))}
    assert not bad, bad
    b = results[0].band
    ax = figures["leak_rate.png"].axes[0]
    labels = [t.get_text() for leg in [*figures["leak_rate.png"].legends, ax.get_legend()] if leg for t in leg.get_texts()]
    if not b.critical_junction.percolates.any():
        gap_ax = figures["local_critical_gap.png"].axes[0]
        said = " ".join(t.get_text() for t in gap_ax.texts)
        assert "no leak channel at any load" in said and "profile scale " in said  # the loads in the notes' words
        crosses = [ln for ln in ax.get_lines() if ln.get_marker() == "x"]
        assert sum(len(ln.get_xdata()) for ln in crosses) == 2 * len(b)  # both theories, every load
        assert "critical junction" in labels and "effective medium" in labels  # the colours are named
    else:
        assert "effective medium" in labels and "critical junction" not in labels
        assert "(effective medium)" in figures["pressure_profile.png"].axes[1].get_title(loc="left")


def test_report_of_a_study_describes_a_shared_seal_once(runs):
    results, _, case_file = runs["o-ring"]
    text = html_report(results, case_file.inputs)
    relation = html.escape(results[0].band.band.notes[0])
    assert text.count(relation) == 1  # water and oil share the O-ring
    for r in results:  # each variant's band table
        assert f"<h3>{html.escape(r.case.label)}</h3>" in text
    assert text.count("force per length f (N/m)") == 1


def test_a_sealed_load_the_fluid_pressure_opens_is_a_hollow_triangle_and_the_legend_says_why():
    """An O-ring at ΔP = 25 bar, above its peaks of 0.64, 1.3 and 2.2 MPa: the 10 % and 20 % loads leak at the lift-off
    limit, the 30 % load has no leak channel at its peak but the fluid opens it too. Its × said "the band seals"; the
    hollow markers' legend said "not a thin film" for the lift-off. The title gave ΔP as 2.5e+03 kPa."""
    text = re.sub(r'(?m)^pressure_difference = .*$', 'pressure_difference = "25 bar"', _oring_text())
    results = [run_case(c) for c in parse_case_file(text).cases]
    r = results[0]
    assert r.band.critical_junction.percolates.tolist()[-1] is False and not r.valid[-1]
    fig = _build(lambda: prediction_figures(results))["leak_rate.png"]
    assert not figure_problems(fig)
    ax = fig.axes[0]
    triangles = [ln for ln in ax.get_lines() if ln.get_marker() == "^" and ln.get_markerfacecolor() == "none"
                 and len(ln.get_xdata())]
    bottom = [ln for ln in triangles if np.all(_xy(ln)[1] < 1.01 * ax.get_ylim()[0] * (ax.get_ylim()[1] / ax.get_ylim()[0]) ** 0.1)]
    assert len(bottom) == 2  # water and oil, side by side at 30 %
    assert all(_xy(ln)[0] == pytest.approx([30.0], rel=0.03) for ln in bottom)
    assert not [ln for ln in ax.get_lines() if ln.get_marker() == "x" and len(ln.get_xdata())]
    labels = [t.get_text() for leg in [*fig.legends, ax.get_legend()] if leg for t in leg.get_texts()]
    assert any("sealed but for ΔP, which opens it: valid = NO" in t for t in labels)
    assert any(t.startswith("ΔP ≥ lift-off (its limit)") for t in labels)
    assert not any(t.startswith("ΔP below") or "not a thin film" in t for t in labels)
    assert "ΔP = 2.5 MPa" in ax.get_title()
