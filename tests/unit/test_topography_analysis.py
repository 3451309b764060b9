"""Statistics, stitching, self-affine fit and analyze() on synthesized surfaces with known answers."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from sealeak.errors import InputError
from sealeak.numerics.synthesis import synthesize
from sealeak.physics.spectrum import PowerSpectrum
from sealeak.render import plot_spectra
from sealeak.topography import (
    BinnedSpectrum,
    LineScans,
    Topography,
    analyze,
    fit_self_affine,
    spectrum_2d,
    stitch,
    surface_statistics,
)

L = 1e-3
MODEL = PowerSpectrum.self_affine(hurst=0.7, q_rolloff=10**5.2, q_cutoff=10**6.3, q_lowest=10**4.1, h_rms=2e-6)
SAMPLES = Path(__file__).resolve().parents[3] / "shared" / "topography-samples"


@pytest.fixture(scope="module")
def periodic_map() -> Topography:
    return Topography(heights=synthesize(MODEL, 512, L, seed=7), size=(L, L), periodic=True, source="synthesized")


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
    assert s.h_rms == pytest.approx(np.std(h), rel=1e-12, abs=0)
    assert s.slope_rms == pytest.approx(np.sqrt(slope2), rel=1e-9)
    assert s.curvature_rms == pytest.approx(np.sqrt(curv2), rel=1e-9)
    # a Gaussian random field: skewness ≈ 0, kurtosis ≈ 3, area ratio ≈ Gaussian-slope formula
    assert abs(s.skewness) < 0.15 and s.kurtosis == pytest.approx(3.0, abs=0.3)
    assert s.area_ratio == pytest.approx(s.spectrum_area_ratio, rel=0.02)
    assert s.slope_rms == pytest.approx(MODEL.slope_rms, rel=0.05)
    assert s.spectrum_h_rms == pytest.approx(2e-6, rel=1e-12, abs=0)


def test_skewness_kurtosis_known_distribution():
    rng = np.random.default_rng(2)
    h = rng.exponential(1e-6, size=(300, 300))  # skewness 2, kurtosis 9
    s = surface_statistics(Topography(heights=h, size=(1e-4, 1e-4), periodic=True))
    assert s.skewness == pytest.approx(2.0, abs=0.15)
    assert s.kurtosis == pytest.approx(9.0, abs=1.2)


def test_stitching_two_scales():
    # one surface at two scales: the whole map and a 4× finer map of a quarter-size window
    coarse = Topography(heights=synthesize(MODEL, 512, L, seed=11), size=(L, L), periodic=True, source="coarse")
    fine = Topography(heights=synthesize(MODEL, 512, L / 4, seed=12), size=(L / 4, L / 4), periodic=True, source="fine")
    a, b = spectrum_2d(coarse), spectrum_2d(fine)
    s = stitch([a, b])
    assert s.q_lo[0] == pytest.approx(a.q_lo[a.reliable][0]) and s.q_hi[-1] == pytest.approx(b.q_hi[b.reliable][-1])
    # overlap: mode-weighted geometric mean, checked bin by bin
    for i in np.nonzero(s.modes > 0)[0]:
        parts = [(x.C[j], x.modes[j]) for x in (a, b) for j in np.nonzero(x.reliable)[0]
                 if np.isclose(x.q_lo[j], s.q_lo[i])]
        C = np.exp(sum(m * np.log(c) for c, m in parts) / sum(m for _, m in parts))
        assert s.C[i] == pytest.approx(C, rel=1e-12, abs=0)
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
    assert f.C0 == pytest.approx(1e-30, rel=1e-6, abs=0)
    assert f.rolloff_resolved


def test_fit_of_synthesized_map_within_standard_errors():
    model = PowerSpectrum.self_affine(hurst=0.6, q_rolloff=10**5.0, q_cutoff=10**6.5, q_lowest=10**3.9, h_rms=1e-6)
    t = Topography(heights=synthesize(model, 1024, L, seed=5), size=(L, L), periodic=True)
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
    assert res.statistics.h_rms == pytest.approx(np.std(periodic_map.heights), rel=1e-12, abs=0)
    assert res.fit is not None and res.spectrum.q.size >= 10
    assert any("removed mean" in n for n in res.notes)
    fig = plot_spectra(res, tmp_path / "spectra.png")
    ax = fig.axes[0]
    assert ax.get_xlabel().endswith("q (1/m)") and ax.get_ylabel().endswith("C(q) (m⁴)")
    assert ax.get_xscale() == "log" and ax.get_yscale() == "log"
    assert (tmp_path / "spectra.png").stat().st_size > 1000
    # the faint points outside the reliable range have their own legend entry
    labels = [t.get_text() for t in fig.legends[0].get_texts()]  # below the axes: never on the data
    assert any("outside the reliable range" in t for t in labels)
    top = ax.child_axes[0].get_xlabel()  # secondary axis: the same q as a wavelength
    assert "wavelength" in top and "(µm)" in top


@pytest.mark.skipif(not SAMPLES.is_dir(), reason="shared topography samples not present")
def test_analyze_files_map_and_line_scan(tmp_path):
    pytest.importorskip("SurfaceTopography")
    ST = pytest.importorskip("SurfaceTopography")
    res = analyze([SAMPLES / "plu-1.plu", SAMPLES / "dektak-1.csv"])
    assert len(res.sources) == 2 and res.sources[1].profile_spectrum is not None
    # the stylus tip radius (2.5 µm in the file) ends the reliable range, not the 4-pixel limit
    cutoff = ST.open_topography(str(SAMPLES / "dektak-1.csv")).topography().short_reliability_cutoff() * 1e-6
    assert res.sources[1].spectrum.q_reliable[1] == pytest.approx(2 * np.pi / cutoff)
    assert res.spectrum.q_min < 3e4 and 2 * np.pi / cutoff / 1.3 < res.spectrum.q_max <= 2 * np.pi / cutoff
    assert res.statistics.spectrum_h_rms == pytest.approx(res.spectrum.h_rms, rel=1e-6, abs=0)
    assert any("inverse Abel" in n for n in res.notes) and any("stitched" in n for n in res.notes)
    plot_spectra(res, tmp_path / "s.png")


# ---------------------------------------------------------------------------- slopes of non-periodic maps
def _discrete_moments(model, n, size):
    """slope² and curvature² of a periodic n×n map with exact amplitudes: Σ over its Fourier modes of
    |k|² C (2π/L)² and |k|⁴ C (2π/L)², the Nyquist component of the gradient excepted (it is real)."""
    k = 2 * np.pi * np.fft.fftfreq(n, d=size / n)
    kx, ky = np.meshgrid(k, k, indexing="ij")
    C = model(np.hypot(kx, ky)) * (2 * np.pi / size) ** 2
    nyq = np.abs(k).max()
    kx_d, ky_d = np.where(np.abs(kx) == nyq, 0, kx), np.where(np.abs(ky) == nyq, 0, ky)
    return np.sum((kx_d**2 + ky_d**2) * C), np.sum((kx**2 + ky**2) ** 2 * C)


@pytest.mark.parametrize("hurst", [0.3, 0.8])
def test_nonperiodic_slope_and_curvature_match_the_spectrum(hurst):
    # roughness up to the Nyquist wavevector, where finite differences read 20-35 % low
    n = 1024
    model = PowerSpectrum.self_affine(hurst=hurst, q_rolloff=1e5, q_cutoff=np.pi * n / L, q_lowest=2 * np.pi / L,
                                      h_rms=1e-6)
    h = synthesize(model, n, L, seed=9, amplitudes="phases")
    slope2, curv2 = _discrete_moments(model, n, L)
    crop = Topography(heights=h[100:612, 300:812], size=(L / 2, L / 2), periodic=False)  # not periodic
    st = surface_statistics(crop)
    assert st.slope_rms == pytest.approx(np.sqrt(slope2), rel=0.02)
    assert st.curvature_rms == pytest.approx(np.sqrt(curv2), rel=0.03)
    # Gaussian slopes: <√(1+|∇h|²)> follows from slope_rms (docs/theory.md §1)
    from sealeak.physics.spectrum import area_ratio_from_slope

    assert st.area_ratio - 1 == pytest.approx(area_ratio_from_slope(np.sqrt(slope2)) - 1, rel=0.05)
    # profiles of the crop: <|∇h|²> = 2<h'²>, <(∇²h)²> = (8/3)<h''²> for an isotropic surface
    sl = surface_statistics(LineScans(heights=h[100:612, 300:812], length=L / 2))
    assert sl.slope_rms == pytest.approx(np.sqrt(slope2), rel=0.03)
    assert sl.curvature_rms == pytest.approx(np.sqrt(curv2), rel=0.05)


# ---------------------------------------------------------------------------- fit: clear results or errors
@pytest.mark.filterwarnings("error")
def test_fit_flat_spectrum_and_white_noise_give_clear_errors():
    q = np.geomspace(1e4, 1e7, 30)
    flat = PowerSpectrum.from_arrays(q, np.full(q.size, 1e-30))
    for rolloff in (None, True, False):
        with pytest.raises(InputError, match="H cannot be determined"):
            fit_self_affine(flat, rolloff=rolloff)
    noise = Topography(heights=np.random.default_rng(0).standard_normal((256, 256)) * 1e-6, size=(L, L))
    with pytest.raises(InputError, match="H cannot be determined"):
        fit_self_affine(spectrum_2d(noise))
    res = analyze([noise])  # the analysis goes on without a fit and says why
    assert res.fit is None and any("fit not possible" in n and "white noise" in n for n in res.notes)


@pytest.mark.filterwarnings("error")
@pytest.mark.parametrize("exponent,bound", [(-5.0, 1.0), (-1.6, 0.0)])
def test_fit_flags_hurst_outside_zero_one(exponent, bound):
    # C ∝ q^-5 wants H = 1.5, C ∝ q^-1.6 wants H = -0.2: held at the bound, flagged, never a warning
    q = np.geomspace(1e4, 1e7, 30)
    f = fit_self_affine(PowerSpectrum.from_arrays(q, 1e-30 * (q / 1e4) ** exponent))
    assert f.hurst == bound and not f.hurst_in_range
    assert f.hurst_wanted == pytest.approx(-exponent / 2 - 1, abs=1e-6)
    assert "outside" in f.warning and np.isnan(f.hurst_err)
    assert "nan" not in repr(f) and f"H = {bound:.3f} (H held at a bound)" in repr(f)  # ("H = 1.000 ± nan" in the log)
    inside = fit_self_affine(PowerSpectrum.from_arrays(q, 1e-30 * (q / 1e4) ** -3.0))
    assert inside.hurst_in_range and inside.warning is None and inside.hurst == pytest.approx(0.5, abs=1e-6)


@pytest.mark.filterwarnings("error")
def test_fit_rolloff_near_the_top_of_the_range():
    q = np.geomspace(1e4, 1e7, 31)  # 10 bins per decade
    # plateau up to the third bin from the top: the model spectrum stays within the fitted range
    qr = q[-4] * 1.0001
    f = fit_self_affine(PowerSpectrum.from_arrays(q, np.where(q < qr, 1e-30, 1e-30 * (q / qr) ** -3.6)))
    assert f.q_rolloff == pytest.approx(qr, rel=1e-3) and f.hurst == pytest.approx(0.8, abs=1e-3)
    assert f.spectrum.q_max == pytest.approx(q[-1]) and f.spectrum.q_min == pytest.approx(q[0])
    # plateau to the last bins: no power law left to fit, a clear error (not "q must be strictly increasing")
    qr = q[-2] * 1.0001
    with pytest.raises(InputError, match="no power-law decay"):
        fit_self_affine(PowerSpectrum.from_arrays(q, np.where(q < qr, 1e-30, 1e-30 * (q / qr) ** -3.6)))


# ---------------------------------------------------------------------------- several sources, small maps
def test_several_sources_statistics_from_the_combined_spectrum():
    coarse = Topography(heights=synthesize(MODEL, 256, L, seed=21), size=(L, L), periodic=True, source="coarse.npy")
    fine = Topography(heights=synthesize(MODEL, 256, L / 8, seed=22), size=(L / 8, L / 8), periodic=True,
                      source="fine.npy")
    res = analyze([coarse, fine])
    st, sp = res.statistics, res.spectrum
    # independent integration of the combined C(q) (log-log interpolation between its points)
    qs = np.geomspace(sp.q_min, sp.q_max, 20001)
    Cs = np.exp(np.interp(np.log(qs), np.log(sp.q), np.log(sp.C)))
    for name, n in (("h_rms", 1), ("slope_rms", 3), ("curvature_rms", 5)):
        assert getattr(st, name) == pytest.approx(np.sqrt(2 * np.pi * np.trapezoid(qs**n * Cs, qs)), rel=1e-3)
    assert st.area_ratio > 1 and st.skewness is not None and st.kurtosis is not None
    # skewness and kurtosis of the measurement that reaches the longest wavelengths
    h = coarse.heights - coarse.heights.mean()
    assert st.skewness == pytest.approx(np.mean(h**3) / np.mean(h**2) ** 1.5, rel=1e-9)
    # the combined band covers both; slope over it close to the model's over the same band
    band = MODEL.truncated(sp.q_min, sp.q_max)
    assert st.slope_rms == pytest.approx(band.slope_rms, rel=0.1)
    # each source keeps its own height statistics
    assert res.sources[1].statistics.h_rms == pytest.approx(np.std(fine.heights), rel=1e-12, abs=0)


def test_small_map_keeps_height_statistics_and_names_the_problem(tmp_path):
    p = tmp_path / "tiny.txt"
    rng = np.random.default_rng(3)
    h = rng.standard_normal((10, 10))
    np.savetxt(p, h)
    res = analyze(p, size="1 mm", height_unit="um")
    assert not res.has_spectrum and res.fit is None
    # independent: rms of the heights minus their least-squares plane (rows of the file are y)
    m = h.T * 1e-6
    i, j = np.meshgrid(np.arange(10), np.arange(10), indexing="ij")
    A = np.stack([np.ones(100), i.ravel(), j.ravel()], axis=1)
    resid = m.ravel() - A @ np.linalg.lstsq(A, m.ravel(), rcond=None)[0]
    assert res.statistics.h_rms == pytest.approx(np.sqrt(np.mean(resid**2)), rel=1e-9, abs=0)
    with pytest.raises(InputError, match=r"tiny\.txt.*too small for a reliable C\(q\)"):
        res.spectrum  # noqa: B018
    # next to a large map, the small one is left out of C(q) (said in the notes), not fatal
    big = Topography(heights=synthesize(MODEL, 256, L, seed=1), size=(L, L), periodic=True, source="big")
    both = analyze([big, p], size="1 mm", height_unit="um")
    assert both.has_spectrum and any("left out of C(q): tiny.txt" in n for n in both.notes)
    assert "too small" in both.sources[1].spectrum_problem and both.sources[0].spectrum_problem is None
    assert not both.sources[1].spectrum.reliable.any()


@pytest.mark.filterwarnings("error")
@pytest.mark.parametrize("exponent,ripple,bound", [(-1.98, 0.2, 0.0), (-1.96, 0.4, 0.0), (-4.03, 0.4, 1.0)])
def test_fit_at_a_bound_warns_also_when_the_data_allow_the_bound(exponent, ripple, bound):
    # H just outside [0, 1] but within two standard errors of the bound (scatter of the bins): the
    # fit stops at the bound, H is still "in range", and the fit says H is poorly determined
    q = np.geomspace(1e4, 1e7, 31)
    C = 1e-30 * (q / 1e4) ** exponent * np.exp(ripple * np.sin(3 * np.arange(q.size)))
    f = fit_self_affine(PowerSpectrum.from_arrays(q, C), rolloff=False)
    assert f.hurst == pytest.approx(bound, abs=1e-4) and f.hurst_in_range
    assert len(f.warnings) == 1 and "bound" in f.warnings[0] and f.warning == f.warnings[0]


@pytest.mark.filterwarnings("error")
def test_fit_with_a_large_reduced_chi2_warns():
    # binned C(q) with many modes per bin (small scatter) and a ±factor-2 ripple: far from one power law
    q = np.geomspace(1e4, 1e6, 21)
    C = 1e-30 * (q / 1e4) ** -3.0 * np.exp(0.7 * np.sin(np.arange(q.size)))
    edges = np.sqrt(q[:-1] * q[1:])
    lo, hi = np.concatenate([[q[0] / 1.1], edges]), np.concatenate([edges, [q[-1] * 1.1]])
    b = BinnedSpectrum(q=q, C=C, modes=np.full(q.size, 5000), q_lo=lo, q_hi=hi, reliable=np.ones(q.size, bool),
                       q_reliable=(q[0], q[-1]), dim=2)
    f = fit_self_affine(b)
    assert f.chi2_red > 100 and 0 < f.hurst < 1
    assert [w for w in f.warnings if "χ²" in w] and "compromise" in f.warning
    # the same shape with the scatter of few modes per bin: no warning
    few = fit_self_affine(BinnedSpectrum(q=q, C=C, modes=np.full(q.size, 2), q_lo=lo, q_hi=hi,
                                         reliable=np.ones(q.size, bool), q_reliable=(q[0], q[-1]), dim=2))
    assert few.chi2_red < 100 and not few.warnings
