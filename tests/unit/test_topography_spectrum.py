"""Spectral analysis of maps and line scans: Parseval, round trips, conventions, windows, Abel transforms.

Expected values come from the definitions (docs/theory.md §1), closed forms and independent quadrature,
never from the code under test.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest
from scipy import integrate, special

from sealeak.numerics.synthesis import synthesize, wavevector_grid
from sealeak.physics.spectrum import PowerSpectrum
from sealeak.topography import (
    LineScans,
    Topography,
    abel_forward,
    abel_inverse,
    power_spectrum_map,
    prepare,
    spectrum_1d,
    spectrum_2d,
    spectrum_2d_from_1d,
    surface_statistics,
)

N = 1024
L = 1e-3  # m: lowest mode q0 = 2π/L = 6283 1/m, Nyquist 3.2e6 1/m
# band edges on bin edges 10^(k/10) so that every bin lies wholly inside or outside the band
Q_LOW, Q_ROLL, Q_CUT = 10**4.1, 10**5.6, 10**6.4
MODEL = PowerSpectrum.self_affine(hurst=0.8, q_rolloff=Q_ROLL, q_cutoff=Q_CUT, q_lowest=Q_LOW, h_rms=1e-6)


@pytest.fixture(scope="module")
def gaussian_map() -> Topography:
    h = synthesize(MODEL, N, L, seed=20240611)
    return Topography(heights=h, size=(L, L), periodic=True, source="synthesized")


# ---------------------------------------------------------------------------- Parseval
@pytest.mark.parametrize("shape,size", [((64, 64), (1e-4, 1e-4)), ((96, 50), (3e-4, 1e-4)), ((33, 47), (2e-5, 5e-5))])
def test_parseval_discrete_spectrum_sums_to_variance(shape, size):
    rng = np.random.default_rng(1)
    h = rng.standard_normal(shape) * 1e-6 + 3e-6  # offset: removed by the mean detrend
    prep = prepare(Topography(heights=h, size=size, periodic=True))
    qx, qy, C, w = power_spectrum_map(prep)
    dq2 = (2 * np.pi / size[0]) * (2 * np.pi / size[1])
    h_rms_spectrum = np.sqrt(np.sum(w * C) * dq2)  # 2π∫qC dq as the sum over all modes
    h_rms_heights = np.std(h)
    assert h_rms_spectrum == pytest.approx(h_rms_heights, rel=1e-10, abs=0)


# ---------------------------------------------------------------------------- round trip
def test_round_trip_bins_within_mode_scatter(gaussian_map):
    b = spectrum_2d(gaussian_map, low_cut=1, resolution_pixels=2)
    # expectation of each bin: mean of the model over the very modes in it (full FFT grid)
    q = wavevector_grid(N, L, half=False).ravel()
    q = q[(q > 0) & (q <= np.pi * N / L * (1 + 1e-12))]
    Cq = MODEL(q)
    z = []
    for qc, c, m, lo, hi in zip(b.q, b.C, b.modes, b.q_lo, b.q_hi):
        inside = (q >= lo * (1 - 1e-12)) & (q < hi)
        assert inside.sum() == m  # mode count per bin
        expected = Cq[inside].mean()
        if expected == 0:
            assert c < 1e-20 * MODEL.C.max()
            continue
        # |h_q|² exponential, ± q identical: m/2 independent values ⇒ relative std ≈ 1/√(m/2)
        sigma = np.sqrt(2.0 * np.sum(Cq[inside] ** 2)) / m
        z.append((c - expected) / sigma)
    z = np.asarray(z)
    assert len(z) >= 20
    assert np.max(np.abs(z)) < 5.0
    assert np.mean(z**2) == pytest.approx(1.0, abs=0.6)  # the scatter is the predicted one


def test_round_trip_h_rms_within_one_percent(gaussian_map):
    # predicted realisation scatter of h_rms: ½ √(2 Σ C²)/Σ C over the modes = 0.3 %
    stats = surface_statistics(gaussian_map, spectrum_2d(gaussian_map, bins_per_decade=20, low_cut=1,
                                                          resolution_pixels=2).to_power_spectrum())
    assert stats.h_rms == pytest.approx(MODEL.h_rms, rel=0.01)
    assert stats.spectrum_h_rms == pytest.approx(MODEL.h_rms, rel=0.01)


def test_power_spectrum_matches_model_inside_band(gaussian_map):
    spec = spectrum_2d(gaussian_map).to_power_spectrum()  # default reliable range
    inside = (spec.q > 2 * Q_LOW) & (spec.q < Q_CUT / 1.5)
    ratio = spec.C[inside] / MODEL(spec.q[inside])
    assert np.all(np.abs(np.log(ratio)) < 0.25)


# ---------------------------------------------------------------------------- convention
def test_surfacetopography_psd_is_2pi_squared_times_persson():
    ST = pytest.importorskip("SurfaceTopography")
    h = synthesize(MODEL, 256, L, seed=3)
    sx, sy = L, 0.75 * L
    h = h[:, :192]
    h = h - h.mean()
    ours = power_spectrum_map(prepare(Topography(heights=h, size=(sx, sy), periodic=True)))
    t = ST.Topography(h, (sx, sy), periodic=True)
    _, _, C_st = t.power_spectrum_from_area(window="None", reliable=False, return_map=True)
    C_st = np.asarray(C_st)[:, : ours[2].shape[1]]  # full fft2 layout → rfft2 half plane
    mask = ours[2] > 1e-12 * ours[2].max()
    np.testing.assert_allclose(C_st[mask] / ours[2][mask], (2 * np.pi) ** 2, rtol=1e-10)


# ---------------------------------------------------------------------------- window
def test_window_correction_on_nonperiodic_crop(gaussian_map):
    crop = Topography(heights=gaussian_map.heights[100:612, 300:812], size=(L / 2, L / 2), periodic=False)
    prep = prepare(crop)  # plane removed, Hann window normalised to mean(w²) = 1
    assert any("Hann" in n for n in prep.notes)
    rms_crop = np.std(prep.surface.heights)
    b = spectrum_2d(prep, low_cut=1, resolution_pixels=2)
    qx, qy, C, w = power_spectrum_map(prep)
    h_binned = np.sqrt(np.sum(b.C * b.modes) * (2 * np.pi / (L / 2)) ** 2)
    h_spec = np.sqrt(np.sum(w * C) * (2 * np.pi / (L / 2)) ** 2)
    assert h_spec == pytest.approx(rms_crop, rel=0.03)
    assert h_binned == pytest.approx(rms_crop, rel=0.03)
    # without the normalisation the Hann window keeps only mean(w²) = (3/8)² of the variance
    assert np.sqrt(np.mean((prep.windowed * (3 / 8)) ** 2)) < 0.5 * rms_crop


# ---------------------------------------------------------------------------- Abel transforms
def _c1d_power_law(q, A, H):
    """C1D of C = A q^(-2(1+H)) over all q: A q^(-(1+2H)) √π Γ(H+½)/Γ(1+H)."""
    return A * q ** (-(1 + 2 * H)) * np.sqrt(np.pi) * special.gamma(H + 0.5) / special.gamma(1 + H)


@pytest.mark.parametrize("H", [0.3, 0.8])
def test_inverse_abel_exact_for_power_law(H):
    q = np.geomspace(1e3, 1e7, 21)
    C2 = abel_inverse(q, _c1d_power_law(q, 2.0, H))
    np.testing.assert_allclose(C2, 2.0 * q ** (-2 * (1 + H)), rtol=1e-12)


def test_forward_abel_matches_quadrature():
    qs = np.array([1.2e4, Q_LOW, 1e5, Q_ROLL, 1e6, 2e6])

    def by_quad(q):
        def f(qy):
            return MODEL(np.hypot(q, qy))
        kinks = [np.sqrt(k * k - q * q) for k in (Q_LOW, Q_ROLL) if k > q]
        upper = np.sqrt(Q_CUT**2 - q * q)
        return 2 * integrate.quad(f, 0, upper, points=kinks or None, limit=500, epsabs=0, epsrel=1e-13)[0]

    np.testing.assert_allclose(abel_forward(MODEL, qs), [by_quad(q) for q in qs], rtol=1e-11)


def test_self_affine_forward_then_inverse_round_trip():
    # C1D of the model by quadrature on a log grid, back to 2D: exact where C1D is a power law
    # (q >= q_r, no upper cut-off); first order in the grid spacing below q_r, where C1D' has a
    # 1/√(q_r - q) singularity from the kink (measured: 1.2 % at the node next to q_r, 1.3e-3
    # below q_r/1.5, 2e-4 at q_lowest, at 100 nodes per decade).
    model = PowerSpectrum.self_affine(hurst=0.7, q_rolloff=1e5, q_cutoff=1e12, q_lowest=1e4, h_rms=1e-6)
    errors = {}
    for ppd in (25, 100):
        q = np.geomspace(1e4, 1e8, 4 * ppd + 1)
        c1 = abel_forward(model, q)
        C2 = abel_inverse(q, c1)
        rel = np.abs(C2 / model(q) - 1)
        errors[ppd] = rel[q < 1e5].max()
        assert rel[(q >= 1e5) & (q <= 1e7)].max() < 1e-6
        if ppd == 100:
            assert rel[q < 1e5 / 1.5].max() < 2e-3
    assert errors[100] < 0.02
    assert errors[100] < errors[25] / 3  # converges with the grid


def test_line_scans_to_2d_match_input_within_scatter(gaussian_map):
    scans = LineScans.from_topography(gaussian_map)  # 1024 periodic profiles along x
    b1 = spectrum_1d(scans, low_cut=1, resolution_pixels=2)
    window = (b1.q >= 2 * Q_LOW) & (b1.q <= Q_CUT / 3)
    b1 = replace(b1, reliable=window)
    b2 = spectrum_2d_from_1d(b1)
    # scatter of each 1D bin: the profile average at qx is Σ_qy P(qx, qy) Δq with independent
    # exponential P of mean C(√(qx²+qy²)) ⇒ var = Σ_qy C² Δq²; the bin averages m positive qx.
    dq = 2 * np.pi / L
    qy = dq * np.fft.fftfreq(N, 1.0 / N)
    sig_ln = []
    for lo, hi, c in zip(b1.q_lo[window], b1.q_hi[window], b1.C[window]):
        qx = dq * np.arange(1, N // 2 + 1)
        qx = qx[(qx >= lo * (1 - 1e-12)) & (qx < hi)]
        var = np.sum(MODEL(np.hypot(qx[:, None], qy[None, :])) ** 2) * dq**2 / qx.size**2
        sig_ln.append(np.sqrt(var) / c)
    sig_ln = np.asarray(sig_ln)
    # propagate through the (nonlinear) transform by its Jacobian in ln C1D
    base = abel_inverse(b1.q[window], b1.C[window])
    J = np.empty((base.size, base.size))
    for k in range(base.size):
        c = b1.C[window].copy()
        c[k] *= np.exp(1e-4)
        J[:, k] = (abel_inverse(b1.q[window], c) - base) / 1e-4
    sigma = np.sqrt((J**2) @ sig_ln**2)
    z = (base - MODEL(b1.q[window])) / sigma
    assert np.max(np.abs(z)) < 4.0
    assert np.mean(z**2) < 3.0
    # the public conversion returns the same values, minus nodes the noise made non-positive
    np.testing.assert_allclose(b2.C, base[base > 0], rtol=1e-12)
    # where the conversion is well conditioned (above the roll-off) it is also close in absolute terms
    upper = b2.q > 1.5 * Q_ROLL
    assert np.all(np.abs(np.log(b2.C[upper] / MODEL(b2.q[upper]))) < 0.2)


# ---------------------------------------------------------------------------- Abel transforms with roll-off
# Self-affine model with roll-off: C = C0 on [q_L, q_r), C0 (q/q_r)^(-α) on [q_r, q_1], α = 2(1+H).
# Its profile spectrum C1D(q) = 2 ∫_q^∞ q' C(q') / √(q'² - q²) dq' in closed form (u = q²/q'²):
#   plateau:   2 C0 [√(q_r² - q²) - √(max(q, q_L)² - q²)]                          (q < q_r)
#   power law: C0 q_r^α q^(1-α) B(s, ½) [I(q²/max(q, q_r)²) - I(q²/q_1²)],  s = H + ½
# (I: regularised incomplete beta function I_x(s, ½)). Derivatives follow with dI/dx = x^(s-1)(1-x)^(-½)/B.
RO = dict(H=0.7, qL=1e4, qr=1e5, q1=1e8, C0=1e-30)


def _c1d_rolloff(q, H, qL, qr, q1, C0):
    q = np.asarray(q, dtype=float)
    a, s = 2 * (1 + H), H + 0.5
    B = special.beta(s, 0.5)
    plateau = np.where(q < qr, 2 * C0 * (np.sqrt(np.clip(qr**2 - q**2, 0, None))
                                         - np.sqrt(np.clip(np.maximum(q, qL) ** 2 - q**2, 0, None))), 0.0)
    lower = np.maximum(q, qr)
    power = C0 * qr**a * q ** (1 - a) * B * (special.betainc(s, 0.5, (q / lower) ** 2)
                                             - special.betainc(s, 0.5, (q / q1) ** 2))
    return plateau + power


def _c1d_rolloff_derivative(q, H, qL, qr, q1, C0):
    a, s = 2 * (1 + H), H + 0.5
    B = special.beta(s, 0.5)

    def dI(x):  # derivative of the regularised incomplete beta function
        return x ** (s - 1) * (1 - x) ** -0.5 / B

    x1 = (q / q1) ** 2
    if q < qr:
        xr = (q / qr) ** 2
        d = -2 * C0 * q / np.sqrt(qr**2 - q**2) + (2 * C0 * q / np.sqrt(qL**2 - q**2) if q < qL else 0.0)
        d += C0 * qr**a * B * ((1 - a) * q ** (-a) * (special.betainc(s, 0.5, xr) - special.betainc(s, 0.5, x1))
                               + q ** (1 - a) * (dI(xr) * 2 * q / qr**2 - dI(x1) * 2 * q / q1**2))
        return d
    return C0 * qr**a * B * ((1 - a) * q ** (-a) * (1 - special.betainc(s, 0.5, x1))
                             - q ** (1 - a) * dI(x1) * 2 * q / q1**2)


def test_c1d_closed_form_with_rolloff_matches_forward_abel():
    model = PowerSpectrum.self_affine(hurst=RO["H"], q_rolloff=RO["qr"], q_cutoff=RO["q1"], q_lowest=RO["qL"],
                                      C0=RO["C0"])
    q = np.array([2e3, 9e3, RO["qL"], 3e4, 9.9e4, RO["qr"], 1.01e5, 1e6, 3e7, 9e7])
    np.testing.assert_allclose(abel_forward(model, q), _c1d_rolloff(q, **RO), rtol=1e-10)


def test_inverse_abel_of_rolloff_c1d_by_quadrature_reproduces_the_model():
    # independent reference: -(1/π) ∫_q^{q1} C1D'(q') / √(q'² - q²) dq' by scipy quad of the closed form
    # (beyond q1, C1D = 0); the integrable singularities at q_L, q_r and q1 are split off as breakpoints.
    model = PowerSpectrum.self_affine(hurst=RO["H"], q_rolloff=RO["qr"], q_cutoff=RO["q1"], q_lowest=RO["qL"],
                                      C0=RO["C0"])

    def reference(q):
        f = lambda x: _c1d_rolloff_derivative(x, **RO) / np.sqrt(x + q)  # noqa: E731
        kinks = [k for k in (RO["qL"], RO["qr"]) if k > q * (1 + 1e-9)]
        edges = [q, *kinks, RO["q1"]]
        total = 0.0
        for lo, hi in zip(edges[:-1], edges[1:]):
            if lo == q:  # (x - q)^(-1/2) singularity at the lower end: algebraic weight, over [q, 2q] at most
                mid = min(hi, 2.0 * q)
                total += integrate.quad(f, lo, mid, weight="alg", wvar=(-0.5, 0.0), limit=400)[0]
                lo = mid
            # the rest in pieces of an eighth of a decade (one piece over decades loses the tail's 1e-2 of C0)
            cuts = np.geomspace(lo, hi, max(2, int(8 * np.log10(hi / lo)) + 1)) if hi > lo else []
            for a, b in zip(cuts[:-1], cuts[1:]):
                total += integrate.quad(lambda x: f(x) / np.sqrt(x - q), a, b, limit=400, epsabs=0, epsrel=1e-12)[0]
        return -total / np.pi

    # (1e-13 of C0 or better, but 4.6e-6 at 6e4, below the roll-off's kink at q_r, where C1D' is singular; abs: C = 0
    # below q_L, where the reference gives 1e-13 C0)
    points = (3e3, 2e4, 6e4, 2e5, 1e6)
    for q in points:
        assert reference(q) == pytest.approx(float(model(q)), rel=1e-5, abs=1e-12 * RO["C0"])


def _inverse_abel_of_interpolant(qn, cn, q):
    """-(1/π) ∫_q^∞ C1D'/√(q'²-q²) for C1D the log-log interpolant of (qn, cn), last power law continued."""
    beta = np.log(cn[1:] / cn[:-1]) / np.log(qn[1:] / qn[:-1])
    total = 0.0
    for k in range(qn.size - 1):
        lo, hi = max(qn[k], q), qn[k + 1]
        if hi <= q:
            continue
        d = lambda x, k=k: beta[k] * cn[k] * (x / qn[k]) ** beta[k] / x  # noqa: E731
        if lo == q:
            total += integrate.quad(lambda x: d(x) / np.sqrt(x + q), lo, hi, weight="alg", wvar=(-0.5, 0.0))[0]
        else:
            total += integrate.quad(lambda x: d(x) / np.sqrt(x * x - q * q), lo, hi, epsabs=0, epsrel=1e-13)[0]
    b, c, qe = beta[-1], cn[-1], qn[-1]  # the tail, with q' = qe e^t: ∫_0^∞ b c e^(bt) / √(qe² e^(2t) - q²) dt
    tail = integrate.quad(lambda t: b * c * np.exp(b * t) / np.sqrt(qe * qe * np.exp(2 * t) - q * q), 0, 60,
                          epsabs=0, epsrel=1e-13, limit=200)[0]
    return -(total + tail) / np.pi


def test_inverse_abel_with_rolloff_against_quadrature():
    # sealeak's inverse Abel transform of the roll-off model's C1D (closed form at 10 nodes per decade,
    # q_r among them) against scipy quad of the same integral for the same piecewise power law:
    # this checks the transform itself, free of the interpolation error of the nodes.
    qn = np.union1d(np.geomspace(RO["qL"], 1e7, 31), [RO["qr"]])
    cn = _c1d_rolloff(qn, **RO)
    ours = abel_inverse(qn, cn)
    ref = np.array([_inverse_abel_of_interpolant(qn, cn, q) for q in qn[:-1]])
    np.testing.assert_allclose(ours[:-1], ref, rtol=1e-9)
    # and the result is the model within the node interpolation error: exact above q_r, where C1D is a
    # power law (q1 far above the nodes: its influence there is (q/q1)^(1+2H) < 1e-5)
    model = PowerSpectrum.self_affine(hurst=RO["H"], q_rolloff=RO["qr"], q_cutoff=RO["q1"], q_lowest=RO["qL"],
                                      C0=RO["C0"])
    above = (qn >= RO["qr"]) & (qn <= 1e6)
    np.testing.assert_allclose(ours[above], model(qn[above]), rtol=1e-4)
