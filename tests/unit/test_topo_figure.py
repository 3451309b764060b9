"""The C(q) figure of `sealeak surface analyze --plot`: gaps between measurements are not bridged, the
legend covers no data, log axes carry enough labels, nothing is drawn outside the figure, no warning."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from sealeak.numerics.synthesis import synthesize
from sealeak.physics.spectrum import PowerSpectrum
from sealeak.render import plot_spectra
from sealeak.topography import LineScans, Topography, analyze

pytestmark = pytest.mark.filterwarnings("error")

SAMPLES = Path(__file__).resolve().parents[3] / "shared" / "topography-samples"
MODEL = PowerSpectrum.self_affine(hurst=0.8, q_rolloff=2e3, q_cutoff=1e7, q_lowest=3e2, h_rms=5e-6)


def _map(n, size, seed, name):
    return Topography(heights=synthesize(MODEL, n, size, seed=seed), size=(size, size), periodic=True, source=name)


def _stitched_with_a_gap():
    # coarse: reliable up to 4-pixel wavelengths of 8 mm/64 (q ≈ 1.3e4 1/m); fine: from 3·2π/0.1 mm (≈ 1.9e5)
    return analyze([_map(64, 8e-3, 1, "coarse.npz"), _map(128, 1e-4, 2, "fine.npz")])


def _three_scales():
    return analyze([_map(64, 8e-3, 1, "wide.npz"), _map(64, 5e-4, 2, "mid.npz"), _map(128, 2e-5, 3, "afm.npz")])


def _profile():
    h = synthesize(MODEL, 512, 2e-3, seed=4)
    return analyze([LineScans(heights=h[:, :8].T, length=2e-3, periodic=True, source="profiles.txt")])


def _single():
    return analyze([_map(256, 2e-3, 5, "one.npz")])


CASES = {"stitched with a gap": _stitched_with_a_gap, "three scales": _three_scales, "profiles": _profile,
         "one map": _single}


def _segments(line):
    xy = np.asarray(line.get_xydata(), dtype=float)
    ok = np.isfinite(xy).all(axis=1)
    return [(xy[i, 0], xy[i + 1, 0]) for i in range(len(xy) - 1) if ok[i] and ok[i + 1]]


def _uncovered(an):
    """q intervals no source's reliable range covers, between the lowest and the highest (from the sources)."""
    ranges = sorted(s.spectrum.q_reliable for s in an.sources if s.spectrum_problem is None)
    out, reach = [], ranges[0][1]
    for lo, hi in ranges[1:]:
        if lo > reach:
            out.append((reach, lo))
        reach = max(reach, hi)
    return out


def _check_reads_right(fig):
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    renderer = FigureCanvasAgg(fig).get_renderer()
    fig.draw(renderer)
    ax = fig.axes[0]
    # the legend lies outside the axes (and their tick labels): it covers no data
    assert not ax.get_legend() and len(fig.legends) == 1
    legend = fig.legends[0].get_window_extent(renderer)
    assert not legend.overlaps(ax.get_tightbbox(renderer))
    # nothing outside the figure
    whole = fig.bbox
    for artist in (ax, fig.legends[0]):
        box = artist.get_tightbbox(renderer)
        assert box.x0 >= whole.x0 - 1 and box.y0 >= whole.y0 - 1 and box.x1 <= whole.x1 + 1 and box.y1 <= whole.y1 + 1
    # every log axis (q, C, wavelength) has at least three labelled ticks in view
    axes = [ax.xaxis, ax.yaxis] + [c.xaxis for c in ax.child_axes]
    assert len(axes) == 3
    for axis in axes:
        lo, hi = sorted(axis.get_view_interval())
        shown = [t for t in axis.get_major_ticks()
                 if t.label1.get_visible() and t.label1.get_text() or t.label2.get_visible() and t.label2.get_text()]
        inside = [t for t in shown if lo * (1 - 1e-9) <= t.get_loc() <= hi * (1 + 1e-9)]
        assert len(inside) >= 3, (axis, [t.label1.get_text() for t in inside])
    # labels in the unit, no floating offset text
    assert ax.xaxis.get_offset_text().get_text() == "" and ax.yaxis.get_offset_text().get_text() == ""
    assert ax.get_xlabel() == "wavevector q (1/m)" and ax.get_ylabel() == "power spectrum C(q) (m⁴)"


@pytest.mark.parametrize("name", sorted(CASES))
def test_spectra_figure_reads_right(tmp_path, name):
    an = CASES[name]()
    fig = plot_spectra(an, tmp_path / "c.png")
    _check_reads_right(fig)
    ax = fig.axes[0]
    (line,) = [ln for ln in ax.get_lines() if ln.get_label() in ("combined C(q)", "C(q), reliable range")]
    # no segment of the combined C(q) spans a band without data
    for a, b in _uncovered(an):
        assert not any(x0 < a * 1.0001 and x1 > b / 1.0001 for x0, x1 in _segments(line)), (a, b)
    # every bin of the combined C(q) is on the line
    q = np.asarray(line.get_xdata(), dtype=float)
    np.testing.assert_allclose(np.sort(q[np.isfinite(q)]), an.spectrum.q)


def test_gaps_between_measurements_are_shaded_and_not_bridged(tmp_path):
    an = _stitched_with_a_gap()
    (gap,) = _uncovered(an)
    assert gap[1] / gap[0] > 5  # a real gap of more than half a decade
    fig = plot_spectra(an)
    ax = fig.axes[0]
    shades = [p for p in ax.patches if p.get_label().startswith("no reliable C(q)")]
    assert len(shades) == 1
    x0, x1 = shades[0].get_x(), shades[0].get_x() + shades[0].get_width()  # data coordinates along q
    # the shade spans the gap between the sources' reliable ranges (to within a bin: it ends at bin edges)
    assert x0 < np.sqrt(gap[0] * gap[1]) < x1 and gap[0] / 1.3 < x0 and x1 < gap[1] * 1.3
    (line,) = [ln for ln in ax.get_lines() if ln.get_label() == "combined C(q)"]
    assert all(not (a <= gap[0] * 1.0001 and b >= gap[1] / 1.0001) for a, b in _segments(line))
    # the spectrum used for predictions still spans the gap (log-log interpolation, said in the notes)
    assert an.spectrum.q_min < gap[0] and an.spectrum.q_max > gap[1]
    assert any("no measurement covers" in n for n in an.notes)


def test_a_questionable_fit_says_so_in_the_figure():
    q = np.geomspace(2e4, 2e6, 41)
    steep = PowerSpectrum.from_arrays(q, 1e-30 * (q / q[0]) ** -5.0)  # wants H = 1.5
    an = analyze([Topography(heights=synthesize(steep, 512, 1e-3, seed=3, amplitudes="phases"), size=(1e-3, 1e-3),
                             periodic=True)])
    assert an.fit.warnings
    fig = plot_spectra(an)
    labels = [t.get_text() for t in fig.legends[0].get_texts()]
    (fit,) = [t for t in labels if t.startswith("self-affine fit")]
    assert "H at its bound" in fit and "reduced χ²" in fit
    good = plot_spectra(_single())
    (fit,) = [t.get_text() for t in good.legends[0].get_texts() if t.get_text().startswith("self-affine fit")]
    assert "(" not in fit


@pytest.mark.skipif(not SAMPLES.is_dir(), reason="../shared/topography-samples not present")
@pytest.mark.parametrize("files", [("di-1.di", "plu-1.plu", "frt-2.frt"), ("sur-2.sur",), ("dektak-1.csv",),
                                   ("x3p-2.x3p", "mi-1.mi")])
def test_spectra_figure_of_instrument_files(tmp_path, files):
    pytest.importorskip("SurfaceTopography")
    an = analyze([SAMPLES / f for f in files])
    fig = plot_spectra(an, tmp_path / "c.png")
    _check_reads_right(fig)
    (line,) = [ln for ln in fig.axes[0].get_lines() if ln.get_label() in ("combined C(q)", "C(q), reliable range")]
    for a, b in _uncovered(an):
        assert not any(x0 < a * 1.0001 and x1 > b / 1.0001 for x0, x1 in _segments(line))
