import numpy as np
import pytest
from scipy.integrate import quad

from sealeak import FileFormatError, InputError, PowerSpectrum
from sealeak.physics.spectrum import area_ratio_from_slope
from tests.reference import band_integral, self_affine

H, QL, QR, Q1 = 0.7, 2.0e3, 1.0e4, 1.0e7


def closed_form_moment(n, C0):
    """∫ qⁿ C dq of the self-affine model, by hand."""
    e = n + 1 - 2 * (1 + H)
    plateau = C0 * (QR ** (n + 1) - QL ** (n + 1)) / (n + 1)
    tail = C0 * QR ** (2 * (1 + H)) * (Q1**e - QR**e) / e
    return plateau + tail


@pytest.fixture
def spec():
    return PowerSpectrum.self_affine(hurst=H, q_rolloff=QR, q_cutoff=Q1, q_lowest=QL, C0=1e-20)


@pytest.mark.parametrize("n", [0, 1, 2, 3, 5])
def test_moments_match_closed_form(spec, n):
    assert spec.moment(n) == pytest.approx(closed_form_moment(n, 1e-20), rel=1e-12, abs=0)


def test_rms_quantities_from_moments(spec):
    assert spec.h_rms == pytest.approx(np.sqrt(2 * np.pi * closed_form_moment(1, 1e-20)), rel=1e-12, abs=0)
    assert spec.slope_rms == pytest.approx(np.sqrt(2 * np.pi * closed_form_moment(3, 1e-20)), rel=1e-12, abs=0)
    assert spec.curvature_rms == pytest.approx(np.sqrt(2 * np.pi * closed_form_moment(5, 1e-20)), rel=1e-12)


@pytest.mark.parametrize("h_rms", [1e-7, 1e-6, 44e-6])
def test_h_rms_equals_request(h_rms):
    s = PowerSpectrum.self_affine(hurst=0.8, q_rolloff=9.1e3, q_cutoff=3.14e5, q_lowest=1.2566e3, h_rms=h_rms)
    assert s.h_rms == pytest.approx(h_rms, rel=1e-13, abs=0)
    # independently: quad over the model written out by hand
    C0 = s.C[0]
    m1 = band_integral(lambda q: q * self_affine(q, C0, 1.2566e3, 9.1e3, 3.14e5, 0.8), 1.2566e3, 3.14e5, [9.1e3])
    assert np.sqrt(2 * np.pi * m1) == pytest.approx(h_rms, rel=1e-10, abs=0)


def test_evaluation_matches_model(spec):
    q = np.geomspace(1e3, 2e7, 301)
    assert np.allclose(spec(q), self_affine(q, 1e-20, QL, QR, Q1, H), rtol=1e-12, atol=0)


def test_band_starting_on_the_power_law():
    s = PowerSpectrum.self_affine(hurst=0.8, q_rolloff=1e3, q_cutoff=1e6, q_lowest=1e4, C0=1.0)
    assert s.q_min == 1e4
    assert s(2e4) == pytest.approx((2e4 / 1e3) ** -3.6, rel=1e-12, abs=0)


def test_cumulative_moment_and_inverse(spec):
    q = np.geomspace(QL, Q1, 57)
    m = spec.cumulative_moment(3, q)
    direct = [band_integral(lambda x: x**3 * spec(x), QL, b, [QR]) for b in q[::8]]
    assert np.allclose(m[::8], direct, rtol=1e-10)
    assert np.allclose(spec.inverse_cumulative_moment(3, m), q, rtol=1e-12)


def test_log_log_interpolation_between_table_points():
    s = PowerSpectrum.from_arrays([1e3, 1e5], [1e-16, 1e-22])
    assert s(1e4) == pytest.approx(1e-19, rel=1e-12, abs=0)  # geometric midpoint -> geometric mean
    assert s(5e2) == 0.0 and s(2e5) == 0.0


def test_refined_and_truncated_keep_the_function(spec):
    fine = spec.refined(7)
    q = np.geomspace(QL, Q1, 101)
    assert np.allclose(fine(q), spec(q), rtol=1e-12)
    assert fine.moment(3) == pytest.approx(spec.moment(3), rel=1e-12, abs=0)
    cut = spec.truncated(5e3, 1e5)
    assert cut.moment(1) == pytest.approx(spec.moment(1, 5e3, 1e5), rel=1e-12, abs=0)


def test_area_ratio_closed_form_against_quadrature():
    for slope in (0.1, 0.5, 1.077, 3.0):
        m = slope**2
        ref = quad(lambda x: np.sqrt(1 + x) * np.exp(-x / m) / m, 0, np.inf, epsabs=0, epsrel=1e-12)[0]
        assert area_ratio_from_slope(slope) == pytest.approx(ref, rel=1e-10)
    assert area_ratio_from_slope(0.0) == 1.0


@pytest.mark.parametrize("q, C, field", [
    ([1.0, np.nan, 3.0], [1.0, 1.0, 1.0], "spectrum.q[1]"),
    ([1.0, 2.0, 3.0], [1.0, np.inf, 1.0], "spectrum.C[1]"),
    ([1.0, 3.0, 2.0], [1.0, 1.0, 1.0], "spectrum.q[2]"),
    ([1.0, 1.0, 2.0], [1.0, 1.0, 1.0], "spectrum.q[1]"),
    ([-1.0, 1.0, 2.0], [1.0, 1.0, 1.0], "spectrum.q[0]"),
    ([1.0, 2.0, 3.0], [1.0, 0.0, 1.0], "spectrum.C[1]"),
    ([1.0], [1.0], "spectrum.q"),
])
def test_invalid_spectra_name_the_field(q, C, field):
    with pytest.raises(InputError) as err:
        PowerSpectrum.from_arrays(q, C)
    assert err.value.field == field


@pytest.mark.parametrize("kwargs, field", [
    (dict(hurst=1.2), "hurst"),
    (dict(hurst=0.0), "hurst"),
    (dict(q_cutoff=5e3), "q_cutoff"),
    (dict(h_rms=-1e-6), "h_rms"),
])
def test_invalid_model_parameters(kwargs, field):
    base = dict(hurst=0.8, q_rolloff=1e4, q_cutoff=1e6, h_rms=1e-6)
    base.update(kwargs)
    with pytest.raises(InputError) as err:
        PowerSpectrum.self_affine(**base)
    assert err.value.field == field


def test_spectrum_is_immutable(spec):
    with pytest.raises(ValueError):
        spec.C[0] = 1.0


def test_self_affine_takes_wavelengths_or_wavevectors():
    a = PowerSpectrum.self_affine(hurst=0.8, q_rolloff=9.1e3, q_cutoff=2 * np.pi / 20e-6, q_lowest=2 * np.pi / 5e-3,
                                  h_rms=44e-6)
    b = PowerSpectrum.self_affine(hurst=0.8, rolloff_wavelength=2 * np.pi / 9.1e3, cutoff_wavelength=20e-6,
                                  lowest_wavelength=5e-3, h_rms=44e-6)
    assert np.allclose(a.q, b.q, rtol=1e-14) and np.allclose(a.C, b.C, rtol=1e-12)
    with pytest.raises(InputError, match="not both"):
        PowerSpectrum.self_affine(hurst=0.8, q_rolloff=1e4, rolloff_wavelength=1e-3, q_cutoff=1e6, h_rms=1e-6)
    with pytest.raises(InputError, match="q_cutoff is required"):
        PowerSpectrum.self_affine(hurst=0.8, q_rolloff=1e4, h_rms=1e-6)


def test_spectrum_from_table_file(tmp_path):
    path = tmp_path / "psd.txt"
    # units in the header, space separated: q in 1/um, C in um^4
    path.write_text("# measured\nq (1/um) C (um^4)\n0.001 1e6\n0.01 1e3\n0.1 1\n")
    sp = PowerSpectrum.from_table(path)
    assert np.allclose(sp.q, [1e3, 1e4, 1e5], rtol=1e-12)
    assert np.allclose(sp.C, [1e-18, 1e-21, 1e-24], rtol=1e-12)
    assert sp(np.sqrt(1e3 * 1e4)) == pytest.approx(np.sqrt(1e-18 * 1e-21), rel=1e-12, abs=0)  # log-log interpolation
    assert "psd.txt" in sp.label
    bad = tmp_path / "bad.txt"
    bad.write_text("q (1/m), C (m^4)\n1e3, 1e-18\n1e3, 1e-20\n")
    with pytest.raises(FileFormatError, match="line 3: q = 1000 1/m is not above"):
        PowerSpectrum.from_table(bad)
