"""Every figure sealeak draws reads right at the size it is written (issue 11 §3).

The figures of every bundled case and study, of degenerate sweeps (no leak channel anywhere, all
pressures in full contact, a single percolating pressure, ΔP = 0 reaching the figure code) and the
fit, linearity and rig figures are built, drawn at a low dpi with every warning an error, and
checked from the figure objects in display coordinates:

* nothing is drawn outside the figure (axes with their labels, titles, second axes, legends);
* no legend covers plotted data, tick labels or text;
* no offset or multiplier text ("1e-6"): the scale is in the unit label; tick labels are distinct;
* a log axis has at least two labelled ticks in view;
* on a linear axis no curve lies flat on zero (its maximum is at least 5 % of the axis top): curves
  whose values differ by decades need a log axis;
* an axes with nothing drawn says why, in a text inside the axes.
"""

import warnings
from dataclasses import replace

import numpy as np
import pytest
from matplotlib.figure import Figure

from sealeak.cases import (
    FitResult,
    example_names,
    example_path,
    linearity,
    prediction_curves,
    read_case_file,
    rig_prediction,
    rig_readings,
    run_case,
)
from sealeak.lab.data import read_leak_data
from sealeak.lab.fitting import fit_scale
from sealeak.lab.rig import exponential_height
from sealeak.render import (
    figure_fit,
    figure_linearity,
    figure_readings,
    figure_rig,
    prediction_figures,
)
from sealeak.render.figures import (
    Series,
    color,
    draw_series,
    figure_critical_junction,
    figure_critical_magnification,
    figure_leak_rate,
    figure_pressure_difference,
    log_axis,
    new_figure,
    prediction_figure_names,
)
from sealeak.render.interactive import prediction_plot_data
from tests.casefiles import BASE, edit

# The figures are checked at the dpi they are written with: text extents do not scale with the dpi
# (glyphs are hinted to whole pixels), so a legend that fits at 150 dpi can be wider at 40. Drawing
# without rendering lays everything out without rasterizing, which is what costs time.
PRESSURES = 'squeeze_pressure = ["20 kPa", "60 kPa", "0.1 MPa"]'


# ---------------------------------------------------------------------- the checks
def _axes(fig):
    """Every axes of a figure, second (ml/min) axes included."""
    out = []
    for ax in fig.axes:
        out.append(ax)
        out.extend(ax.child_axes)
    return out


def _data_lines(ax):
    """Lines in data coordinates with at least one finite point (not axhline/axvline, not empty legend proxies)."""
    out = []
    for line in ax.get_lines():
        if not line.get_visible() or line.get_transform() != ax.transData:
            continue
        xy = np.asarray(line.get_xydata(), dtype=float)
        if len(xy) and np.isfinite(xy).all(axis=1).any():
            out.append(line)
    return out


def _drawn_points(ax):
    """Display coordinates of every line's vertices and of points 1 px apart along its segments, inside the axes."""
    pts = [np.zeros((0, 2))]
    for line in ax.get_lines():
        if not line.get_visible():
            continue
        xy = np.asarray(line.get_xydata(), dtype=float)
        if not len(xy):
            continue
        d = line.get_transform().transform(xy)
        pts.append(d[np.isfinite(d).all(axis=1)])
        if line.get_linestyle() in ("None", "none", "", " ") or len(d) < 2:
            continue
        for a, b in zip(d[:-1], d[1:]):
            if np.isfinite(a).all() and np.isfinite(b).all():
                n = int(min(max(np.hypot(*(b - a)), 1), 3000))
                pts.append(a + (b - a) * np.linspace(0, 1, n + 1)[:, None])
    p = np.concatenate(pts)
    box = ax.bbox
    return p[(p[:, 0] >= box.x0) & (p[:, 0] <= box.x1) & (p[:, 1] >= box.y0) & (p[:, 1] <= box.y1)]


def _tick_labels(axis):
    """(text, bbox) of the visible tick labels in view, major and minor."""
    lo, hi = sorted(axis.get_view_interval())
    out = []
    for tick in axis.get_major_ticks() + axis.get_minor_ticks():
        loc = tick.get_loc()
        if loc is None or not (lo - 1e-12 * abs(hi - lo) <= loc <= hi + 1e-12 * abs(hi - lo)):
            continue
        for label in (tick.label1, tick.label2):
            if label.get_visible() and label.get_text():
                out.append((label.get_text(), label.get_window_extent()))
    return out


def _inside(box, outer, tol=1.0):
    return box.x0 >= outer.x0 - tol and box.y0 >= outer.y0 - tol and box.x1 <= outer.x1 + tol and box.y1 <= outer.y1 + tol


def figure_problems(fig: Figure) -> list[str]:
    """What reads badly in a figure (empty: nothing); drawing it with every warning an error."""
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        fig.draw_without_rendering()
    problems = []
    figbox = fig.bbox
    legends = [ax.get_legend() for ax in fig.axes if ax.get_legend() is not None] + list(fig.legends)
    for ax in _axes(fig):
        if not _inside(ax.get_tightbbox(), figbox):
            problems.append(f"'{ax.get_title()[:40]}': drawn outside the figure")
        for name, axis in (("x", ax.xaxis), ("y", ax.yaxis)):
            if axis.get_offset_text().get_visible() and axis.get_offset_text().get_text():
                problems.append(f"{name} axis shows an offset text {axis.get_offset_text().get_text()!r}")
            ticks = _tick_labels(axis)
            labels = [t for t, _ in ticks]
            if len(labels) != len(set(labels)):
                problems.append(f"{name} axis repeats tick labels {labels}")
            boxes = [b for _, b in ticks]
            if any(a.overlaps(b) for i, a in enumerate(boxes) for b in boxes[i + 1:]):
                problems.append(f"{name} axis prints tick labels over each other: {labels}")
            if axis.get_scale() == "log" and len(labels) < 2 and _data_lines(ax):
                problems.append(f"log {name} axis with {len(labels)} labelled tick(s): {labels}")
    for ax in fig.axes:
        lines = _data_lines(ax)
        texts = [t for t in ax.texts if t.get_visible() and t.get_text()]
        for t in texts:
            if not _inside(t.get_window_extent(), ax.bbox):
                problems.append(f"text {t.get_text()[:30]!r} leaves the axes")
        if not lines and not texts and not ax.get_images():  # an image (a contact map) is drawn too
            problems.append(f"'{ax.get_title()[:40]}': nothing drawn and nothing said")
        if ax.get_yscale() == "linear" and not ax.get_yticks().size == 0:
            lo, hi = ax.get_ylim()
            for line in lines:
                if line.get_linestyle() in ("None", "none", "", " "):
                    continue  # markers (measurements, hollow invalid points) are not curves
                y = np.asarray(line.get_ydata(), dtype=float)
                y = y[np.isfinite(y)]
                if y.size > 1 and hi > 0 and min(y.max(), hi) - max(lo, 0) < 0.05 * (hi - max(lo, 0)):
                    problems.append(f"'{ax.get_title()[:40]}': curve {line.get_label()!r} lies flat on zero (needs a log axis)")
        for leg in legends:
            box = leg.get_window_extent()
            pts = _drawn_points(ax)
            hit = (pts[:, 0] > box.x0) & (pts[:, 0] < box.x1) & (pts[:, 1] > box.y0) & (pts[:, 1] < box.y1)
            if hit.any():
                problems.append(f"legend covers {int(hit.sum())} data point(s) of '{ax.get_title()[:40]}'")
            for t in texts:
                if box.overlaps(t.get_window_extent()):
                    problems.append(f"legend covers the text {t.get_text()[:30]!r}")
    for leg in legends:
        box = leg.get_window_extent()
        if not _inside(box, figbox):
            problems.append("legend outside the figure")
        for ax in _axes(fig):
            for axis in (ax.xaxis, ax.yaxis):
                for text, tb in _tick_labels(axis):
                    if box.overlaps(tb):
                        problems.append(f"legend covers the tick label {text!r}")
            label = ax.yaxis.label
            if label.get_text() and box.overlaps(label.get_window_extent()):
                problems.append("legend covers an axis label")
    return problems


def _build(make):
    """Build figures with every warning an error (NumPy's and matplotlib's included)."""
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        return make()


def _results(text_or_path, tmp_path=None):
    if tmp_path is not None:
        path = tmp_path / "case.toml"
        path.write_text(text_or_path)
        text_or_path = path
    return [run_case(c) for c in read_case_file(text_or_path).cases]


def _assert_reads_right(figures):
    bad = {name: p for name, fig in figures.items() if (p := figure_problems(fig))}
    assert not bad, bad


# ---------------------------------------------------------------------- the bundled cases and studies
#: Figures whose y axis is linear whatever its values span (the other figures are log where a curve spans > 2 decades).
LINEAR_BY_NATURE = {
    "contact_area.png": "A(ζ)/A0 is a fraction of the nominal area, from 0 to 1",
    "gap_distribution.png": "u·P(u) is a probability density",
    "leak_rate.png": "the paper's Fig. 6, linear, beside its log twin leak_rate_log.png (log when the curves differ by decades)",
}

@pytest.fixture(scope="module")
def example_figures():
    cache = {}

    def get(name):
        if name not in cache:
            results = [run_case(c) for c in read_case_file(example_path(name)).cases]
            cache[name] = (results, _build(lambda: prediction_figures(results)))
        return cache[name]
    return get


@pytest.mark.parametrize("name", example_names())
def test_every_figure_of_a_bundled_example_reads_right(name, example_figures):
    results, figures = example_figures(name)
    assert set(figures) == set(prediction_figure_names([r.case for r in results]))
    _assert_reads_right(figures)
    for name, fig in figures.items():
        if name in LINEAR_BY_NATURE:
            continue
        for ax in fig.axes:
            for line in _data_lines(ax):
                y = np.asarray(line.get_ydata(), dtype=float)
                y = y[np.isfinite(y) & (y > 0)]
                if y.size > 1 and y.max() > 100 * y.min():
                    assert ax.get_yscale() == "log", (name, ax.get_title())


def test_a_study_whose_variants_differ_by_decades_is_drawn_on_log_axes(example_figures):
    """hrms-study: the variants' leak rates differ by decades; on a linear axis three of four lay flat at zero."""
    results, figures = example_figures("hrms-study")
    peaks = [np.nanmax(np.where(r.valid, r.critical_junction.leak_rate, np.nan)) for r in results]
    assert max(peaks) > 100 * min(peaks)  # the premise
    for name in ("leak_rate.png", "leak_rate_log.png", "leak_rate_vs_pressure_difference.png"):
        assert figures[name].axes[0].get_yscale() == "log", name
    zc = np.concatenate([np.where(r.valid, r.critical_junction.critical_magnification, np.nan) for r in results])
    assert np.nanmax(zc) > 100 * np.nanmin(zc)
    assert figures["critical_magnification.png"].axes[0].get_yscale() == "log"


def _power(label):
    """The power of ten in a unit label such as 'leak rate Q (10⁻⁶ m³/s)' (1 when there is none)."""
    inner = label.rsplit("(", 1)[1]
    if not inner.startswith("10"):
        return 1.0
    return 10.0 ** int(inner[2:].split(" ")[0].translate(str.maketrans("⁻⁰¹²³⁴⁵⁶⁷⁸⁹", "-0123456789")))


@pytest.mark.parametrize("name", ["leak_rate.png", "leak_rate_log.png", "leak_rate_vs_pressure_difference.png"])
def test_leak_rates_have_a_second_axis_in_ml_per_min(name, example_figures):
    fig = example_figures("reference-experiment")[1][name]
    fig.draw_without_rendering()
    ax = fig.axes[0]
    (sec,) = ax.child_axes
    assert "ml/min" in sec.get_ylabel() and "m³/s" in ax.get_ylabel()
    # both axes show the same leak rate: 1 m³/s = 6e7 ml/min, whatever power of ten each label carries
    for q, m in zip(ax.get_ylim(), sec.get_ylim()):
        assert m * _power(sec.get_ylabel()) == pytest.approx(q * _power(ax.get_ylabel()) * 6e7, rel=1e-9, abs=1e-300)


def test_results_outside_the_theory_are_hollow_and_do_not_set_the_axis(example_figures):
    """hrms-study at high P0: u_c below the molecular size, Q down to ~1e-71 m³/s."""
    results, figures = example_figures("hrms-study")
    q_valid = np.concatenate([r.critical_junction.leak_rate[r.valid & r.critical_junction.percolates] for r in results])
    q_invalid = np.concatenate([r.critical_junction.leak_rate[~r.valid] for r in results])
    assert q_invalid.size and q_invalid.min() < 1e-60  # the premise: one cliff far below every valid point
    ax = figures["leak_rate_log.png"].axes[0]
    lo, hi = ax.get_ylim()
    assert lo > 1e-3 * q_valid.min() and lo < q_valid.min() and hi > q_valid.max()
    hollow = [ln for ln in ax.get_lines() if ln.get_markerfacecolor() == "none" and len(ln.get_xdata())]
    assert sum(len(ln.get_xdata()) for ln in hollow) == q_invalid.size
    for ln in hollow:  # every hollow marker is visible, not clipped away
        y = np.asarray(ln.get_ydata(), dtype=float)
        assert ((y >= lo) & (y <= hi)).all()
    labels = ax.get_legend_handles_labels()[1] + [t.get_text() for leg in figures["leak_rate_log.png"].legends
                                                  for t in leg.get_texts()]
    assert any("below molecular size" in s and "continuum" in s for s in labels)
    # no solid curve passes through an invalid point
    for ln in ax.get_lines():
        if ln.get_linestyle() == "-":
            y = np.asarray(ln.get_ydata(), dtype=float)
            assert not np.isin(y[np.isfinite(y)], q_invalid).any()


# ---------------------------------------------------------------------- degenerate sweeps, the other models
DEGENERATE = {
    "a single pressure, no leak channel": edit(PRESSURES, 'squeeze_pressure = ["100 MPa"]'),
    "both models, every pressure in full contact": edit("[theory]", '[theory]\nmodel = "both"', edit(
        PRESSURES, 'squeeze_pressure = ["40 MPa", "70 MPa", "100 MPa"]')),
    "one pressure of two has a leak channel": edit(PRESSURES, 'squeeze_pressure = ["60 kPa", "100 MPa"]'),
    "both models": edit("[theory]", '[theory]\nmodel = "both"'),
    "the effective medium alone": edit("[theory]", '[theory]\nmodel = "effective-medium"'),
}


@pytest.mark.parametrize("text", list(DEGENERATE.values()), ids=list(DEGENERATE))
def test_degenerate_sweeps_and_the_other_models_draw_without_warnings(text, tmp_path):
    results = _results(text, tmp_path)
    figures = _build(lambda: prediction_figures(results))
    _assert_reads_right(figures)
    if not any(r.critical_junction.percolates.any() for r in results):
        for name in ("leak_rate.png", "leak_rate_log.png", "critical_junction.png", "critical_magnification.png"):
            said = " ".join(t.get_text() for t in figures[name].axes[0].texts)
            assert "no leak channel at any squeeze pressure" in said, name
            assert "100 MPa" in said  # which pressures


def test_a_zero_pressure_difference_reaching_the_figures_says_so(tmp_path):
    """The case loader refuses ΔP = 0; a case built in Python can still carry it to the leak-rate figures."""
    (result,) = _results(BASE, tmp_path)
    results = [run_case(replace(result.case, pressure_difference=0.0))]
    assert results[0].critical_junction.percolates.any()
    figures = _build(lambda: {"leak_rate.png": figure_leak_rate(results, log=False),
                              "leak_rate_log.png": figure_leak_rate(results, log=True),
                              "leak_rate_vs_pressure_difference.png": figure_pressure_difference(prediction_curves(results))})
    _assert_reads_right(figures)
    for name in ("leak_rate.png", "leak_rate_log.png"):
        assert "zero at every squeeze pressure" in " ".join(t.get_text() for t in figures[name].axes[0].texts)


# ---------------------------------------------------------------------- fit, linearity, rig
def test_laboratory_figures_read_right(case, sweep, tmp_path):
    p0, cj, em = sweep  # both models at α = 1 over 20..400 kPa
    rng = np.random.default_rng(11)
    data = tmp_path / "measured.csv"
    q = 0.2 * cj * np.exp(0.15 * rng.standard_normal(cj.size))
    data.write_text("squeeze_pressure (kPa), leak_rate (ml/min)\n"
                    + "\n".join(f"{p / 1e3:.6g}, {x * 6e7:.6g}" for p, x in zip(p0, q)) + "\n")
    # what run_fit returns, from the fixture's curves (run_fit computes them again, on a finer grid)
    fits = {"critical_junction": fit_scale(q, cj, "critical_junction"),
            "effective_medium": fit_scale(q, em, "effective_medium")}
    fit = FitResult(case=case, data=read_leak_data(data), fits=fits,
                    reference_pressure_difference=case.pressure_difference, same_pressure_difference=True,
                    measured=q, grid=p0, curves={"critical_junction": cj, "effective_medium": em}, messages=())
    dp = np.array([2e3, 4e3, 6e3, 8e3, 1e4])
    q_dp = 1.2e-10 * dp * (1 + 0.01 * rng.standard_normal(dp.size))
    check = linearity(case, dp, q_dp)
    pred = rig_prediction(case)
    k = next(iter(pred.conductance.values()))
    t = np.linspace(0, 600, 11)
    readings = rig_readings(case, t, exponential_height(case.rig, 1.3 * k, t))
    figures = _build(lambda: {
        "fit.png": figure_fit(fit), "linearity.png": figure_linearity(dp, q_dp, check),
        "rig.png": figure_rig(case.rig, pred.columns, pred.squeeze_pressure),
        "readings.png": figure_readings(readings, pred.conductance),
    })
    _assert_reads_right(figures)
    assert figures["fit.png"].axes[0].get_yscale() == "log"
    for name in ("fit.png", "linearity.png", "readings.png"):
        assert any("ml/min" in sec.get_ylabel() for sec in figures[name].axes[0].child_axes), name


def test_an_invalid_zero_on_a_log_axis_is_a_triangle_below_it():
    """u_c = 0 (the junction at the end of the resolved band) gives Q = 0, flagged invalid: drawn below the axis."""
    fig, ax = new_figure("test")
    x = np.arange(1.0, 6.0)
    series = [Series(x, np.array([1e-6, 1e-7, 1e-8, 1e-9, 0.0]), np.array([True] * 4 + [False]), color(0), "-", "Q",
                     ("",) * 4 + ("u_c = 0 nm is below the fluid's molecular size 0.3 nm",))]
    assert _build(lambda: draw_series(ax, series, logy=True))
    lo, hi = ax.get_ylim()
    (below,) = [ln for ln in ax.get_lines() if ln.get_marker() == "v"]
    assert list(below.get_xdata()) == [5.0] and lo < below.get_ydata()[0] < 1e-9
    assert not figure_problems(fig)


@pytest.mark.parametrize("fluid_pressure", ["coupled", "ignored"])
def test_the_pressure_difference_figure_says_whether_q_is_linear_in_it(tmp_path, fluid_pressure):
    """The title's claim matches the curve drawn: Q/ΔP constant with the fluid pressure ignored, rising with it
    coupled (the fluid pressure opens the contact, docs/theory.md §13.2)."""
    text = edit("alpha = 0.2", f'alpha = 0.2\nfluid_pressure = "{fluid_pressure}"')
    results = _results(text, tmp_path)
    fig = _build(lambda: figure_pressure_difference(prediction_curves(results)))
    title = fig.axes[0].get_title()
    (line, *_) = _data_lines(fig.axes[0])
    dp, q = (np.asarray(v, dtype=float) for v in line.get_data())
    ratio = q[dp > 0] / dp[dp > 0]
    if fluid_pressure == "ignored":
        assert "linear in ΔP at fixed P0" in title and "faster" not in title
        assert np.ptp(ratio) < 1e-9 * ratio.max()
    else:
        assert "grows faster than ΔP" in title and "linear in ΔP at fixed" not in title
        assert ratio[-1] > 1.01 * ratio[0]


@pytest.mark.parametrize("factor, drawn", [(0.3, (True, True)), (30.0, (False, True)), (1e6, (False, False))])
def test_the_leak_rate_figures_draw_the_specification(tmp_path, factor, drawn):
    """conditions.max_leak_rate as a dash-dotted line at its value (m³/s), on the linear and the log figure; a limit
    above every leak rate widens a log axis (up to LIMIT_DECADES), not a linear one (the curves would lie flat); where
    it is not drawn the subtitle says where it lies."""
    results = _results(BASE, tmp_path)
    q = results[0].critical_junction.leak_rate
    limit = (factor * float(np.nanmax(q)), "the specification")
    for log, shown in zip((False, True), drawn, strict=True):
        ax = _build(lambda log=log: figure_leak_rate(results, log=log, limit=limit)).axes[0]
        lines = [line for line in ax.get_lines() if line.get_label() == "max_leak_rate = the specification"]
        scale = _power(ax.get_ylabel())
        if shown:
            assert len(lines) == 1 and lines[0].get_ydata()[0] * scale == pytest.approx(limit[0], rel=1e-12, abs=0)
            lo, hi = ax.get_ylim()
            assert lo * scale <= limit[0] <= hi * scale
            # on a linear axis the chords between rows cross the line elsewhere than Q does: said, with where to read it
            linear = ax.get_yscale() == "linear"
            assert ("straight lines join the rows" in " ".join(ax.get_title().split())) == linear, ax.get_title()
        else:
            assert not lines and "max_leak_rate = the specification lies above every leak rate drawn" in ax.get_title()


def test_variants_with_one_contact_draw_their_curves_once_named_after_all(example_figures):
    """The o-ring example studies two fluids on one surface: its spectrum is drawn once, labelled with both (two lines
    one over another would show only the last while the legend listed both colours); so are the web page's spectrum
    and its curves at a pressure."""
    results, figures = example_figures("o-ring")
    a, b = (r.case.spectrum.sample(50) for r in results)
    assert len(results) == 2 and all(np.array_equal(x, y) for x, y in zip(a, b, strict=True))  # the premise
    (line,) = _data_lines(figures["spectrum.png"].axes[0])
    assert line.get_label() == ", ".join(r.case.label for r in results)
    plots = prediction_plot_data(results)
    assert [s["label"] for s in plots["spectra"]] == [", ".join(r.case.label for r in results)]
    labels = [s["label"] for s in plots["sets"]]
    assert len(labels) == len(set(labels)) and all(", ".join(r.case.label for r in results) in t for t in labels)
    assert len(plots["gaps"]["density"]) == len(plots["sets"])


def test_critical_junction_figures_say_why_a_pressure_has_no_point(tmp_path):
    """The axis spans every squeeze pressure of the sweep; one without a leak channel has nothing to draw, and the
    subtitle says so (as the leak-rate figures do)."""
    results = _results(edit('["20 kPa", "60 kPa", "0.1 MPa"]', '["20 kPa", "60 kPa", "0.1 MPa", "1 MPa"]'), tmp_path)
    assert not results[0].critical_junction.percolates[-1] and results[0].critical_junction.percolates[:-1].all()
    for make in (figure_critical_junction, figure_critical_magnification):
        ax = _build(lambda make=make: make(results)).axes[0]
        assert "missing points: no leak channel" in ax.get_title()
        assert ax.get_xlim()[1] >= 1000.0  # the axis still spans the sealed pressure (kPa)
    ax = _build(lambda: figure_critical_junction(_results(BASE, tmp_path))).axes[0]
    assert "missing points" not in ax.get_title()


def test_a_log_axis_over_a_small_part_of_a_decade_labels_each_tick_apart():
    """2.2 to 2.6 ×10⁻⁹ is ticked every 0.05 ×10⁻⁹: two digits labelled "2.2×10⁻⁹" and "2.5×10⁻⁹" twice each."""
    fig, ax = new_figure("test")
    ax.set_yscale("log")
    ax.plot([1.0, 2.0], [2.2e-9, 2.6e-9])
    ax.set_ylim(2.18e-9, 2.62e-9)
    log_axis(ax.yaxis)
    fig.canvas.draw()
    labels = [t.get_text() for t in ax.yaxis.get_ticklabels() if t.get_text()]
    assert len(labels) >= 3 and len(set(labels)) == len(labels), labels
    wide, wax = new_figure("test")
    wax.set_yscale("log")
    wax.set_ylim(1e-9, 1e-6)
    log_axis(wax.yaxis)
    wide.canvas.draw()
    assert "2×10⁻⁹" in [t.get_text() for t in wax.yaxis.get_ticklabels()]  # over decades: two digits, as before
