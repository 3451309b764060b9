"""The figures of an uncertain prediction (sealeak.render.uncertainty_figures, issue 24 item 5), built from plain arrays.

Each must read right (tests/integration/test_figures_render.py's checks) and draw what it is given: the
band between the percentiles, sealed samples in the strip below the leak rates, the specification line,
the inputs sorted by their total index, the probability of passing counted from the samples.
"""

import numpy as np
import pytest
from matplotlib.collections import PolyCollection

from sealeak.render.figures import figure_png
from sealeak.render.uncertainty_figures import LeakBand, figure_fan_chart, figure_leak_distribution, figure_tornado
from tests.integration.test_figures_render import _build, figure_problems

X = np.linspace(50.0, 400.0, 8)  # kPa
MEDIAN = 1e-9 * np.exp(-X / 40.0)  # m³/s


def _band(sealed_from=None):
    p05, p25, p50 = MEDIAN / 5, MEDIAN / 2, MEDIAN.copy()
    if sealed_from is not None:
        p05[X >= sealed_from] = 0.0
        p25[X >= sealed_from + 50] = 0.0
        p50[X >= sealed_from + 100] = 0.0
    return LeakBand(X, p05, p50, MEDIAN * 5, p25, MEDIAN * 2, MEDIAN * 1.2, "nominal")


def test_fan_chart_draws_band_median_nominal_and_specification():
    fig = _build(lambda: figure_fan_chart([_band()], "squeeze pressure P0 (kPa)", max_leak_rate=1e-11))
    assert not figure_problems(fig)
    ax = fig.axes[0]
    assert ax.get_yscale() == "log"
    bands = [c for c in ax.collections if isinstance(c, PolyCollection)]
    assert len(bands) == 2  # 5–95 % and 25–75 %
    outer = bands[0].get_paths()[0].vertices
    assert outer[:, 1].min() == pytest.approx((MEDIAN / 5).min(), rel=1e-9, abs=0)
    assert outer[:, 1].max() == pytest.approx((MEDIAN * 5).max(), rel=1e-9, abs=0)
    labels = [line.get_label() for line in ax.get_lines()]
    assert "median" in labels and "deterministic (nominal inputs)" in labels
    spec = [line for line in ax.get_lines() if line.get_label().startswith("max_leak_rate = ")]
    assert len(spec) == 1 and spec[0].get_ydata()[0] == 1e-11
    assert "sealed" not in [t.get_text() for t in ax.yaxis.get_ticklabels()]  # nothing sealed: no strip
    assert figure_png(fig).startswith(b"\x89PNG")


def test_fan_chart_puts_sealed_samples_in_a_strip_below_the_leak_rates():
    band = _band(sealed_from=250.0)
    fig = _build(lambda: figure_fan_chart([band], "squeeze pressure P0 (kPa)"))
    assert not figure_problems(fig)
    ax = fig.axes[0]
    # the strip is named by a tick of its own, "sealed", at the height of the sealed medians (not by a text inside
    # the strip, which would lie under their markers)
    strip = [v for v, text in zip(ax.get_yticks(), ax.yaxis.get_ticklabels()) if text.get_text() == "sealed"]
    assert len(strip) == 1 and not ax.texts
    drawn = np.r_[band.p05, band.p25, band.p50, band.p75, band.p95, band.nominal]
    lowest_leak = drawn[drawn > 0].min()
    sealed_marks = [line for line in ax.get_lines() if line.get_label().startswith("median sealed")]
    assert len(sealed_marks) == 1
    # the medians of the rows at or beyond 350 kPa are sealed, drawn below every leak rate
    assert len(sealed_marks[0].get_xdata()) == int((X >= 350).sum())
    assert (np.asarray(sealed_marks[0].get_ydata()) < lowest_leak).all()
    assert strip[0] == pytest.approx(sealed_marks[0].get_ydata()[0], rel=1e-12, abs=0)
    # no leak-rate tick label in the strip: every other labelled tick is a leak rate above the sealed ones
    ticks = [v for v, text in zip(ax.get_yticks(), ax.yaxis.get_ticklabels()) if text.get_text() not in ("", "sealed")]
    assert min(ticks) > sealed_marks[0].get_ydata()[0]


def test_fan_chart_keeps_every_band_inside_its_axes():
    """A load where the median seals but the 75th percentile still leaks, less than any 5th, 50th or 95th percentile
    drawn (as near an O-ring's sealing compression): the 25–75 % band stays above the axis' bottom, its zeros in the
    sealed strip, instead of running out of the axes below the strip."""
    band = _band(sealed_from=250.0)
    p75 = band.p75.copy()
    p75[-1] = 1e-3 * np.r_[band.p05, band.p50, band.p95][np.r_[band.p05, band.p50, band.p95] > 0].min()
    band = LeakBand(X, band.p05, band.p50, band.p95, band.p25, p75, band.nominal)
    fig = _build(lambda: figure_fan_chart([band], "compression ε = δ/d (%)"))
    ax = fig.axes[0]
    bottom, top = ax.get_ylim()
    for collection in (c for c in ax.collections if isinstance(c, PolyCollection)):
        y = collection.get_paths()[0].vertices[:, 1]
        assert y.min() >= bottom and y.max() <= top


def test_fan_chart_of_a_seal_that_never_leaks_says_so():
    zero = np.zeros_like(X)
    fig = _build(lambda: figure_fan_chart([LeakBand(X, zero, zero, zero)], "compression ε = δ/d (%)"))
    assert not figure_problems(fig)
    assert "sealed in every sample" in fig.axes[0].texts[0].get_text()


def test_tornado_sorts_inputs_by_total_index_largest_on_top():
    labels = ["rubber.youngs_modulus", "surface.h_rms", "surface.hurst", "fluid.viscosity"]
    first, total = np.array([0.2, 0.62, 0.08, -0.004]), np.array([0.22, 0.7, 0.1, 0.002])
    fig = _build(lambda: figure_tornado(labels, first, total, first / 10 + 0.01, total / 10 + 0.01,
                                        notes="at P0 = 200 kPa"))
    assert not figure_problems(fig)
    ax = fig.axes[0]
    shown = [text for _, text in sorted(zip(ax.get_yticks(), [t.get_text() for t in ax.get_yticklabels()]))]
    assert shown[::-1] == ["surface.h_rms", "rubber.youngs_modulus", "surface.hurst", "fluid.viscosity"]
    widths = sorted((p.get_y(), p.get_width()) for p in ax.patches)
    assert max(w for _, w in widths) == pytest.approx(0.7) and min(w for _, w in widths) == 0.0  # -0.004 drawn at 0
    assert "at P0 = 200 kPa" in ax.get_title()


def test_tornado_puts_an_inputs_spread_under_its_name_so_the_bars_keep_the_width():
    """Labels as the case file's inputs give them ("key: spread") take two lines, the name above its spread: long
    spreads (a uniform distribution's bounds) leave the bars more than half the figure's width."""
    labels = ["surface.h_rms: 1 um ± 15 %", "theory.alpha: 1.0 (uniform, low = 0.5, high = 1.5)",
              "theory.percolation_threshold: 0.6 (normal, sd = 0.02)"]
    first, total = np.array([0.5, 0.1, 0.2]), np.array([0.6, 0.15, 0.3])
    fig = _build(lambda: figure_tornado(labels, first, total, first / 10, total / 10))
    assert not figure_problems(fig)
    ax = fig.axes[0]
    assert "theory.alpha\n1.0 (uniform, low = 0.5, high = 1.5)" in [t.get_text() for t in ax.get_yticklabels()]
    assert ax.get_position().width > 0.5


def test_distribution_counts_the_probability_of_passing_with_sealed_samples_passing():
    rng = np.random.default_rng(1)
    q = 10.0 ** rng.normal(-11.0, 0.5, 400)
    q[:40] = 0.0  # sealed: pass
    limit = 3e-11
    fig = _build(lambda: figure_leak_distribution(q, max_leak_rate=limit, nominal=1e-11))
    assert not figure_problems(fig)
    ax = fig.axes[0]
    passing = (40 + int(np.sum(q[40:] <= limit))) / 400
    assert f"{100 * passing:.1f} %" in ax.get_title()
    assert "10 % sealed" in ax.get_title()
    heights = sum(p.get_height() for p in ax.patches)
    assert heights == pytest.approx(0.9)  # the histogram holds the leaking share of the samples
    assert ax.get_xscale() == "log"
    assert [line.get_xdata()[0] for line in ax.get_lines() if line.get_label().startswith("max_leak_rate = ")] == [limit]


def test_distribution_of_a_sealed_load_says_so():
    fig = _build(lambda: figure_leak_distribution(np.zeros(64), max_leak_rate=1e-12))
    assert not figure_problems(fig)
    assert "100.0 %" in fig.axes[0].get_title()
    assert "sealed in every sample" in fig.axes[0].texts[0].get_text()



def test_fan_chart_cuts_its_axis_eight_decades_below_the_top_and_keeps_the_legend_off_the_band():
    """A row where nearly every sample seals can have a 95th percentile of 1e-38 m³/s: the axis stops 8 decades below
    the largest leak rate (the bands run along its floor, a median below it is a ▽ there), and the legend covers
    no part of the bands."""
    x = np.array([20.0, 60.0, 100.0, 1000.0])
    p50 = np.array([9e-6, 1.4e-6, 4.6e-7, 1e-36])
    band = LeakBand(x, np.r_[p50[:3] / 3, 0.0], p50, np.r_[p50[:3] * 2, 1.5e-30], p50 / 2, p50 * 1.5, p50)
    fig = _build(lambda: figure_fan_chart([band], "squeeze pressure P0 (kPa)", max_leak_rate=5e-7))
    assert not figure_problems(fig)
    ax = fig.axes[0]
    lo, hi = ax.get_ylim()
    assert 7.5 < np.log10(hi) - np.log10(lo) < 9.5  # 8 decades and the sealed strip, not 25
    assert "axis cut 8 decades below the largest leak rate" in ax.get_title()
    (below,) = [line for line in ax.get_lines() if line.get_label() == "median below the axis"]
    assert below.get_xdata()[0] == 1000.0 and lo < below.get_ydata()[0] < 1e-12
    legend = fig.legends[0] if fig.legends else ax.get_legend()
    box = legend.get_window_extent()
    for coll in (c for c in ax.collections if isinstance(c, PolyCollection)):
        for path in coll.get_paths():
            assert not path.transformed(coll.get_transform()).intersects_bbox(box, filled=True)


def test_fan_chart_draws_a_median_from_samples_outside_the_theory_hollow():
    band = _band()
    outside = X >= 300.0
    flags = np.zeros((3, X.size), dtype=bool)
    flags[1] = outside  # the median only
    fig = _build(lambda: figure_fan_chart([LeakBand(X, band.p05, band.p50, band.p95, band.p25, band.p75, band.nominal,
                                                    outside=flags)], "squeeze pressure P0 (kPa)"))
    assert not figure_problems(fig)
    ax = fig.axes[0]
    (hollow,) = [line for line in ax.get_lines() if line.get_label() == "median from samples outside the theory"]
    assert list(hollow.get_xdata()) == list(X[outside]) and hollow.get_markerfacecolor() in ("white", (1.0, 1.0, 1.0, 1.0))
    assert "hollow: a median taken from samples that leak outside the theory's validity" in ax.get_title().replace("\n", " ")
    plain = _build(lambda: figure_fan_chart([band], "squeeze pressure P0 (kPa)")).axes[0]
    assert not [line for line in plain.get_lines() if "outside the theory" in line.get_label()]


def test_fan_chart_says_the_axis_is_cut_only_where_it_is():
    """A sealed 5th percentile (0) sits in the sealed strip, not below a cut axis: a band spanning a few decades is not
    cut, and its subtitle does not say so, whatever outside flags come with it."""
    band = _band(sealed_from=350.0)  # p05 = 0 at the last load
    for flags in (None, np.zeros((3, X.size), dtype=bool)):
        fig = _build(lambda flags=flags: figure_fan_chart([LeakBand(X, band.p05, band.p50, band.p95, band.p25, band.p75,
                                                                    band.nominal, outside=flags)], "squeeze pressure P0 (kPa)"))
        lo, hi = fig.axes[0].get_ylim()
        assert np.log10(hi / lo) < 8.0 and "axis cut" not in fig.axes[0].get_title()


def test_fan_chart_marks_a_band_edge_from_samples_outside_the_theory():
    """A 5th or 95th percentile taken from samples outside the theory gets a small hollow circle on its edge of the band,
    at that load only, with the subtitle saying so; the median's marker is not drawn where only an edge is outside."""
    band = _band()
    flags = np.zeros((3, X.size), dtype=bool)
    flags[2, -1] = True  # the 95th percentile at the highest load
    flags[0, 0] = True  # the 5th at the lowest
    fig = _build(lambda: figure_fan_chart([LeakBand(X, band.p05, band.p50, band.p95, band.p25, band.p75, band.nominal,
                                                    outside=flags)], "squeeze pressure P0 (kPa)"))
    assert not figure_problems(fig)
    ax = fig.axes[0]
    (marks,) = [line for line in ax.get_lines() if line.get_label() == "5th or 95th percentile from samples outside the theory"]
    assert sorted(zip(marks.get_xdata(), marks.get_ydata())) == [(X[0], band.p05[0]), (X[-1], band.p95[-1])]
    assert not [line for line in ax.get_lines() if line.get_label() == "median from samples outside the theory"]
    assert "a median or (small) a 5th or 95th percentile taken from samples" in ax.get_title().replace("\n", " ")


def test_distribution_over_most_of_a_decade_keeps_its_tick_labels_apart():
    """A log axis spanning 0.8 decades with labels m×10ⁿ: 8×10ⁿ, 9×10ⁿ and 10ⁿ⁺¹ would print over each other."""
    q = np.geomspace(1.8e-7, 1.3e-6, 64)
    fig = _build(lambda: figure_leak_distribution(q, max_leak_rate=1e-6, nominal=3e-7, unit="mbar·l/s"))
    assert not figure_problems(fig)
    labels = [t.get_text() for t in fig.axes[0].xaxis.get_ticklabels() if t.get_text()]
    assert "8×10⁻⁷" not in labels and "2×10⁻⁷" in labels


def test_fan_chart_of_several_variants_names_each_band_once_and_its_elements_once_in_grey():
    """Six variants: one legend entry per band (its colour, its name) and one per element (median, 25–75 %, ...) in
    grey, not every element of every band; the legend below grows the figure instead of squeezing the axes."""
    bands = [LeakBand(X, MEDIAN / 5 * k, MEDIAN * k, MEDIAN * 5 * k, MEDIAN / 2 * k, MEDIAN * 2 * k, MEDIAN * 1.2 * k,
                      f"variant {k}") for k in range(1, 7)]
    fig = _build(lambda: figure_fan_chart(bands, "squeeze pressure P0 (kPa)", max_leak_rate=1e-11))
    assert not figure_problems(fig)
    legend = (fig.axes[0].get_legend() or fig.legends[0]).get_texts()
    labels = [t.get_text() for t in legend]
    assert labels[:6] == [f"variant {k}" for k in range(1, 7)]
    assert sorted(labels[6:]) == sorted(["5–95 % of the samples", "25–75 %", "median", "deterministic (nominal inputs)",
                                         "max_leak_rate = 1e-11 m³/s"])
    assert fig.axes[0].get_window_extent().height > 0.3 * fig.bbox.height


@pytest.mark.parametrize("limit, where", [(1e-3, "above the top"), (1e-30, "below the foot")])
def test_a_specification_far_from_the_leak_rates_is_named_at_the_axis_edge_not_made_its_end(limit, where):
    """A 1e-3 ml/min limit over an O-ring's leak rates near 1e-19 m³/s made the axis's top: cut 8 decades below it,
    every band ran along the floor and every median was a ▽ below the axis. A limit farther than 3 decades above the
    leak rates (or below the cut) is a legend entry saying how far it lies, and the axis holds the leak rates."""
    fig = _build(lambda: figure_fan_chart([_band()], "squeeze pressure P0 (kPa)", max_leak_rate=limit))
    assert not figure_problems(fig)
    ax = fig.axes[0]
    lo, hi = ax.get_ylim()
    assert lo <= (MEDIAN / 5).min() and hi >= (MEDIAN * 5).max() and hi < 1e-7  # every band on the axis
    assert not [line for line in ax.get_lines() if line.get_label() == "median below the axis"]
    (named,) = [line.get_label() for line in ax.get_lines() if line.get_label().startswith("max_leak_rate = ")]
    decades = abs(np.log10(limit) - np.log10(hi if where == "above the top" else lo))
    assert f"{decades:.1f} decades {where} of the axis" in named
    near = _build(lambda: figure_fan_chart([_band()], "squeeze pressure P0 (kPa)", max_leak_rate=1e-7))
    assert near.axes[0].get_ylim()[1] >= 1e-7  # 2 decades above the largest leak rate: the axis reaches it


def test_a_distribution_far_below_the_specification_keeps_its_axis_on_the_samples():
    rng = np.random.default_rng(2)
    q = 10.0 ** rng.normal(-19.0, 1.0, 256)
    fig = _build(lambda: figure_leak_distribution(q, max_leak_rate=1.7e-11, nominal=1e-19))
    assert not figure_problems(fig)
    ax = fig.axes[0]
    lo, hi = ax.get_xlim()
    assert hi < 1e-14 and lo <= q.min()
    assert "100.0 %" in ax.get_title()  # every sample passes, as before
    (named,) = [line.get_label() for line in ax.get_lines() if line.get_label().startswith("max_leak_rate = ")]
    assert "decades beyond the axis' right end" in named
