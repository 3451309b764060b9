"""Statistics, stitching, self-affine fit and analyze() on synthesized surfaces with known answers."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from sealeak.roughness import PowerSpectrum
from sealeak.synthesis import synthesize
from sealeak.topography import (
    Topography,
    analyze,
    fit_self_affine,
    plot_spectra,
    spectrum_2d,
    stitch,
    surface_statistics,
)

L = 1e-3
MODEL = PowerSpectrum.self_affine(hurst=0.7, q_rolloff=10**5.2, q_cutoff=10**6.3, q_lowest=10**4.1, h_rms=2e-6)
SAMPLES = Path(__file__).parents[2] / "shared" / "topography-samples"


@pytest.fixture(scope="module")
def periodic_map() -> Topography:
    return Topography(synthesize(MODEL, 512, L, seed=7), (L, L), periodic=True, source="synthesized")


def test_statistics_of_periodic_map_agree_with_discrete_moments(periodic_map):
    s = surface_statistics(periodic_map, MODEL)
    h = periodic_map.heights
    # independent: moments of the discrete spectrum Σ qⁿ |h_q|² over all modes of the map
    F = np.fft.fft2(h) / h.size
    k = 2 * np.pi * np.fft.fftfreq(512, d=L / 512)
    kx, ky = np.meshgrid(k, k, indexing="ij")
    P = np.abs(F) ** 2
    # the Nyquist mode of an even grid has no derivative along its own axis (it is real)
    kx_d = np.where(np.abs(kx) == np.abs(k).max(), 0.0, kx)
    ky_d = np.where(np.abs(ky) == np.abs(k).max(), 0.0, ky)
    slope2 = np.sum((kx_d**2 + ky_d**2) * P)
    curv2 = np.sum((kx**2 + ky**2) ** 2 * P)
    assert s.h_rms == pytest.approx(np.std(h), rel=1e-12)
    assert s.slope_rms == pytest.approx(np.sqrt(slope2), rel=1e-9)
    assert s.curvature_rms == pytest.approx(np.sqrt(curv2), rel=1e-9)
    # a Gaussian random field: skewness ≈ 0, kurtosis ≈ 3, area ratio ≈ Gaussian-slope formula
    assert abs(s.skewness) < 0.15 and s.kurtosis == pytest.approx(3.0, abs=0.3)
    assert s.area_ratio == pytest.approx(s.spectrum_area_ratio, rel=0.02)
    assert s.slope_rms == pytest.approx(MODEL.slope_rms, rel=0.05)
    assert s.spectrum_h_rms == pytest.approx(2e-6, rel=1e-12)


def test_skewness_kurtosis_known_distribution():
    rng = np.random.default_rng(2)
    h = rng.exponential(1e-6, size=(300, 300))  # skewness 2, kurtosis 9
    s = surface_statistics(Topography(h, (1e-4, 1e-4), periodic=True))
    assert s.skewness == pytest.approx(2.0, abs=0.15)
    assert s.kurtosis == pytest.approx(9.0, abs=1.2)


def test_stitching_two_scales():
    # one surface at two scales: the whole map and a 4× finer map of a quarter-size window
    coarse = Topography(synthesize(MODEL, 512, L, seed=11), (L, L), periodic=True, source="coarse")
    fine = Topography(synthesize(MODEL, 512, L / 4, seed=12), (L / 4, L / 4), periodic=True, source="fine")
    a, b = spectrum_2d(coarse), spectrum_2d(fine)
    s = stitch([a, b])
    assert s.q_lo[0] == pytest.approx(a.q_lo[a.reliable][0]) and s.q_hi[-1] == pytest.approx(b.q_hi[b.reliable][-1])
    # overlap: mode-weighted geometric mean, checked bin by bin
    for i in np.nonzero(s.modes > 0)[0]:
        parts = [(x.C[j], x.modes[j]) for x in (a, b) for j in np.nonzero(x.reliable)[0]
                 if np.isclose(x.q_lo[j], s.q_lo[i])]
        C = np.exp(sum(m * np.log(c) for c, m in parts) / sum(m for _, m in parts))
        assert s.C[i] == pytest.approx(C, rel=1e-12)
        assert s.modes[i] == sum(m for _, m in parts)
    # against the model: within 4 standard deviations of a bin mean, 1/√(modes/2) (the lowest bins
    # hold few modes); bins away from the band edges and the roll-off kink
    inside = (s.q > 2e4) & (s.q < 10**6.2) & (np.abs(np.log10(s.q) - 5.2) > 0.1)
    z = np.log(s.C[inside] / MODEL(s.q[inside])) * np.sqrt(s.modes[inside] / 2)
    assert np.all(np.abs(z) < 4)


def test_fit_recovers_exact_model():
    # a model spectrum sampled on bins is a self-affine C(q): the fit must return its parameters
    truth = PowerSpectrum.self_affine(hurst=0.65, q_rolloff=3e5, q_cutoff=1e8, q_lowest=1e4, C0=1e-30)
    q = np.geomspace(2e4, 5e7, 40)
    f = fit_self_affine(PowerSpectrum.from_arrays(q, truth(q)))
    assert f.hurst == pytest.approx(0.65, abs=1e-6)
    assert f.q_rolloff == pytest.approx(3e5, rel=1e-4)
    assert f.C0 == pytest.approx(1e-30, rel=1e-6)
    assert f.rolloff_resolved


def test_fit_of_synthesized_map_within_standard_errors():
    model = PowerSpectrum.self_affine(hurst=0.6, q_rolloff=10**5.0, q_cutoff=10**6.5, q_lowest=10**3.9, h_rms=1e-6)
    t = Topography(synthesize(model, 1024, L, seed=5), (L, L), periodic=True)
    b = spectrum_2d(t, resolution_pixels=3)
    f = fit_self_affine(b)
    assert f.rolloff_resolved
    assert abs(f.hurst - 0.6) < 4 * f.hurst_err and f.hurst_err < 0.05
    assert abs(np.log(f.q_rolloff / 1e5)) < 4 * f.q_rolloff_err / f.q_rolloff
    assert f.spectrum.q_min == pytest.approx(b.q[b.reliable][0])
    # pure power law above the roll-off
    g = fit_self_affine(b, q_range=(2e5, 3e6), rolloff=False)
    assert not g.rolloff_resolved and abs(g.hurst - 0.6) < 4 * g.hurst_err


def test_fit_detects_missing_plateau():
    q = np.geomspace(1e5, 1e7, 30)
    f = fit_self_affine(PowerSpectrum.from_arrays(q, 1e-30 * (q / 1e5) ** (-2 * 1.8)))
    assert not f.rolloff_resolved and f.hurst == pytest.approx(0.8, abs=1e-8)


def test_analyze_objects_and_plot(tmp_path, periodic_map):
    res = analyze([periodic_map])
    assert res.statistics.h_rms == pytest.approx(np.std(periodic_map.heights), rel=1e-12)
    assert res.fit is not None and res.spectrum.q.size >= 10
    assert any("removed mean" in n for n in res.notes)
    fig = plot_spectra(res, tmp_path / "spectra.png")
    ax = fig.axes[0]
    assert ax.get_xlabel() == "q (1/m)" and ax.get_ylabel() == "C(q) (m⁴)"
    assert ax.get_xscale() == "log" and ax.get_yscale() == "log"
    assert (tmp_path / "spectra.png").stat().st_size > 1000


@pytest.mark.skipif(not SAMPLES.is_dir(), reason="shared topography samples not present")
def test_analyze_files_map_and_line_scan(tmp_path):
    pytest.importorskip("SurfaceTopography")
    res = analyze([SAMPLES / "plu-1.plu", SAMPLES / "dektak-1.csv"])
    assert len(res.sources) == 2 and res.sources[1].profile_spectrum is not None
    assert res.spectrum.q_min < 3e4 and res.spectrum.q_max > 5e6
    assert res.statistics.spectrum_h_rms == pytest.approx(res.spectrum.h_rms)
    assert any("inverse Abel" in n for n in res.notes) and any("stitched" in n for n in res.notes)
    plot_spectra(res, tmp_path / "s.png")
