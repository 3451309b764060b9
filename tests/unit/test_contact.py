import warnings

import numpy as np
import pytest
from scipy import special

from sealeak import InputError, PowerSpectrum
from sealeak.cases import example_text, parse_cases
from sealeak.physics.contact import PerssonContact, contact_modulus
from tests.reference import PerssonReference, loglog_table, self_affine

E_STAR = contact_modulus(2.3e6, 0.5)
Q0 = 2 * np.pi / 5e-3
QR, Q1, H, HRMS = 9.1e3, 3.14e5, 0.8, 44e-6


@pytest.fixture(scope="module")
def model():
    return PowerSpectrum.self_affine(hurst=H, q_rolloff=QR, q_cutoff=Q1, q_lowest=Q0, h_rms=HRMS)


def smooth_table_spectrum():
    """A tabulated spectrum with curvature in log-log (30 points), not a power law."""
    q = np.geomspace(1e3, 3e5, 30)
    c = 1e-17 / (1 + (q / 1e4) ** 2) ** 1.6 * np.exp(-((np.log(q / 3e4)) ** 2) / 8)
    return PowerSpectrum.from_arrays(q, c)


def test_contact_modulus():
    assert contact_modulus(2.3e6, 0.5) == pytest.approx(2.3e6 / 0.75)
    # two elastic bodies in series
    assert contact_modulus(1e6, 0.5, 3e6, 0.0) == pytest.approx(1 / (0.75 / 1e6 + 1 / 3e6))
    with pytest.raises(InputError, match="youngs_modulus"):
        contact_modulus(-1.0, 0.5)
    with pytest.raises(InputError, match="poisson_ratio"):
        contact_modulus(1e6, 0.51)


def test_G_against_quadrature(model):
    c = PerssonContact(model, E_STAR, Q0)
    ref = PerssonReference(model, Q0, Q1, [QR], E_STAR, Q0, 1.0)
    for z in (1.5, 7.2, 100.0):
        assert c.G(z) == pytest.approx(ref.G(z), rel=1e-11)
    assert c.G(1.0) == 0.0
    assert c.area(1.0, 5e4) == 1.0


def test_critical_magnification_solves_the_area_condition(model):
    c = PerssonContact(model, E_STAR, Q0)
    p0 = np.geomspace(1e3, 3e5, 50)
    zc, ok = c.zeta_at_area(0.4, p0)
    assert ok.all()
    assert np.max(np.abs(c.area(zc, p0) - 0.4)) < 1e-10
    # independently: G at ζc equals (P0/(2 erfinv(0.4)))²
    assert np.allclose(c.G(zc), (p0 / (2 * special.erfinv(0.4))) ** 2, rtol=1e-10)
    assert np.all(np.diff(zc) > 0)


def test_no_solution_flagged(model):
    c = PerssonContact(model, E_STAR, Q0)
    zc, ok = c.zeta_at_area(0.4, [1e4, 1e8])
    assert ok.tolist() == [True, False]
    assert c.area(c.zeta_max, 1e8) > 0.4


@pytest.mark.parametrize("gamma", [1.0, 0.42])
def test_mean_gap_limits_and_monotonicity(model, gamma):
    c = PerssonContact(model, E_STAR, Q0, gamma)
    z = np.geomspace(1.0, c.zeta_max, 120)
    for p0 in (2e4, 1e5):
        u = c.mean_gap(z, p0)
        assert u[-1] == 0.0
        assert np.all(np.diff(u) <= 0)
        assert np.all(c.mean_gap_derivative(z[1:-1], p0) < 0)
        u1 = c.u1(z[1:-1], p0)
        assert np.all(u1 >= u[1:-1])


@pytest.mark.parametrize("gamma", [1.0, 0.42])
@pytest.mark.parametrize("zeta, p0", [(1.0, 6e4), (3.3, 2e4), (20.0, 1.5e5)])
def test_mean_gap_against_nested_quadrature(model, gamma, zeta, p0):
    c = PerssonContact(model, E_STAR, Q0, gamma)
    ref = PerssonReference(lambda q: self_affine(q, model.C[0], Q0, QR, Q1, H), Q0, Q1, [QR], E_STAR, Q0, gamma)
    assert c.mean_gap(zeta, p0) == pytest.approx(ref.ubar(zeta, p0), rel=1e-5)


@pytest.mark.slow
@pytest.mark.parametrize("gamma", [1.0, 0.42])
@pytest.mark.parametrize("zeta, p0", [(2.7, 2e4), (8.0, 1e5)])
def test_u1_against_nested_quadrature(model, gamma, zeta, p0):
    c = PerssonContact(model, E_STAR, Q0, gamma)
    ref = PerssonReference(lambda q: self_affine(q, model.C[0], Q0, QR, Q1, H), Q0, Q1, [QR], E_STAR, Q0, gamma)
    assert c.u1(zeta, p0) == pytest.approx(ref.u1(zeta, p0), rel=1e-5)


@pytest.mark.slow
@pytest.mark.parametrize("gamma", [1.0, 0.42])
def test_tabulated_spectrum_against_nested_quadrature(gamma):
    s = smooth_table_spectrum()
    q0 = 1.5e3
    c = PerssonContact(s, E_STAR, q0, gamma)
    # the reference interpolates the raw table itself (log-log), not through PowerSpectrum
    ref = PerssonReference(loglog_table(s.q, s.C), s.q_min, s.q_max, s.q, E_STAR, q0, gamma)
    for zeta, p0 in ((1.0, 3e4), (6.0, 4e4), (0.5 * c.zeta_max, 1.2e5)):
        assert c.mean_gap(zeta, p0) == pytest.approx(ref.ubar(zeta, p0), rel=1e-5, abs=0)
    assert c.u1(6.0, 4e4) == pytest.approx(ref.u1(6.0, 4e4), rel=1e-5)


@pytest.mark.parametrize("gamma", [1.0, 0.42])
def test_quadrature_refinement_changes_nothing(model, gamma):
    z = np.geomspace(1.0, 250.0, 40)[:-1]
    coarse = PerssonContact(model, E_STAR, Q0, gamma)
    fine = PerssonContact(model, E_STAR, Q0, gamma, panel_width=0.25, order=20)
    for p0 in (2e4, 2e5):
        assert np.allclose(coarse.mean_gap(z, p0), fine.mean_gap(z, p0), rtol=1e-7, atol=0)
        assert np.allclose(coarse.u1(z[1:], p0), fine.u1(z[1:], p0), rtol=1e-7, atol=0)


@pytest.mark.parametrize("gamma", [1.0, 0.42])
@pytest.mark.parametrize("which", ["model", "table"])
def test_q_grid_refinement_changes_nothing(model, gamma, which):
    """The same C(q) on a 40x denser node grid gives the same results, end to end (ζc, u_c, λc, Q, A(ζ1))."""
    from sealeak.physics.critical_junction import critical_junction

    spectrum = model if which == "model" else smooth_table_spectrum()
    q0 = Q0 if which == "model" else 1.5e3
    p0 = np.geomspace(2e4, 2e5, 9)
    out = []
    for s in (spectrum, spectrum.refined(40)):
        c = PerssonContact(s, E_STAR, q0, gamma)
        out.append(critical_junction(c, squeeze_pressure=p0, pressure_difference=1e4, viscosity=1e-3,
                                     aspect_ratio=22.0, alpha=0.2))
    a, b = out
    assert a.percolates.all() and b.percolates.all()
    for name in ("critical_magnification", "critical_gap", "critical_wavelength", "leak_rate",
                 "contact_area_at_cutoff"):
        assert np.allclose(getattr(a, name), getattr(b, name), rtol=1e-5, atol=0), name


def test_sampled_table_converges_to_the_model(model):
    """A table sampled from the model (kink at q_r not a node) converges to it under refinement."""
    p0 = np.array([3e4, 1e5])
    exact = PerssonContact(model, E_STAR, Q0)
    zc, _ = exact.zeta_at_area(0.4, p0)
    target = exact.u1(zc, p0)
    errors = []
    for n in (40, 160, 640, 2560):
        q = np.geomspace(Q0, Q1, n)
        t = PerssonContact(PowerSpectrum.from_arrays(q, model(q)), E_STAR, Q0)
        zt, _ = t.zeta_at_area(0.4, p0)
        errors.append(np.max(np.abs(t.u1(zt, p0) / target - 1)))
    assert errors[3] < errors[2] < errors[1] < errors[0]
    assert errors[3] < 2e-6


def test_broadcasting_over_zeta_and_pressure(model):
    c = PerssonContact(model, E_STAR, Q0, 0.42)
    z = np.array([1.5, 4.0, 30.0])[:, None]
    p = np.array([2e4, 8e4])[None, :]
    grid = c.u1(z, p)
    assert grid.shape == (3, 2)
    for i in range(3):
        for j in range(2):
            assert grid[i, j] == pytest.approx(float(c.u1(z[i, 0], p[0, j])), rel=1e-13, abs=0)


@pytest.mark.parametrize("kwargs, field", [
    (dict(gamma=0.0), "gamma"),
    (dict(gamma=1.5), "gamma"),
    (dict(q0=1e9), "q0"),
    (dict(e_star=-1.0), "E*"),
])
def test_invalid_parameters(model, kwargs, field):
    args = dict(spectrum=model, e_star=E_STAR, q0=Q0)
    args.update(kwargs)
    with pytest.raises(InputError, match=field.replace("*", r"\*")):  # the physics names its own parameters
        PerssonContact(**args)


def test_u1_goes_to_infinity_near_zeta_one_without_a_warning():
    """u1 = ū + ū' A/A' -> +inf as A'(ζ) -> 0 near ζ = 1: for a steeper spectrum (H = 0.75, the reference
    ring) A' underflows to 0 at the first ζ above 1 at some squeeze pressures and the quotient overflows.
    That is the limit, not an error: the curve is +inf there, finite and positive further on, and no
    RuntimeWarning (an error under this suite's settings) escapes, at any pressure of the case."""
    case = parse_cases(example_text("reference-experiment").replace("hurst = 0.8", "hurst = 0.75"))[0]
    contact = case.contact()
    z = np.geomspace(1.0, case.spectrum.q_max / case.q0, 200)[1:-1]
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        curves = [contact.u1(z, p0) for p0 in case.squeeze_pressure]
    assert any(np.isposinf(u1[0]) for u1 in curves)  # the overflow happens in this case
    for u1 in curves:  # +inf where A' underflows near ζ = 1, else finite and positive; never NaN
        assert np.all(np.isposinf(u1) | (np.isfinite(u1) & (u1 > 0)))
        assert np.isfinite(u1[-1]) and not np.isposinf(u1[len(u1) // 2:]).any()


class _OtherCPU(PerssonContact):
    """The cumulative moment of an array a last bit lower than of the scalar (another CPU's SIMD kernel), as a
    measured spectrum whose first node lies above q0 gave here: G(ζ = 1) came out −3·10⁻⁹ Pa² instead of 0."""

    def _m3(self, q):
        m = super()._m3(q)
        return np.nextafter(m, -np.inf) if np.ndim(q) > 0 and np.size(q) > 1 else m


def test_round_off_below_zero_in_g_at_zeta_one_is_no_nan(model):
    contact = _OtherCPU(model, E_STAR, Q0)
    zeta = np.array([1.0, 2.0, 10.0])
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # (√ of a negative G warned, then int(NaN) raised in the ū panels)
        g = contact.G(zeta)
        ubar = contact.mean_gap(zeta, 2e4)
        area = contact.area(zeta, 2e4)
    assert g[0] == 0.0 and np.all(g[1:] > 0)
    assert np.all(np.isfinite(ubar)) and area[0] == 1.0
    exact = PerssonContact(model, E_STAR, Q0)
    assert ubar == pytest.approx(exact.mean_gap(zeta, 2e4), rel=1e-12, abs=0)
