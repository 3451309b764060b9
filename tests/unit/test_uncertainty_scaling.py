"""The scaling of Persson's contact (docs/theory.md eq. 14.6) and the uncertainty band it computes (issue 24 item 6).

h_rms × s (the spectrum's shape kept) and E* × k: P(ζ) and ζ_c depend on P0/(k s) alone, the gaps scale as s at
P0/(k s). Each claim is checked by computing the scaled contact directly.
"""

import numpy as np
import pytest

import sealeak.cases.uncertainty as unc
from sealeak.cases import example_text
from sealeak.cases.band import ScaledJunctions, _junction_at_peak, junction_sigma, run_band, scaled_junctions
from sealeak.cases.loader import parse_case_file
from sealeak.cases.scaling import SCALING_TABLE_TOP, sigma_table
from sealeak.cases.uncertainty import leak_rates, parse_uncertain_case, propagate, unit_points
from sealeak.physics.contact import PerssonContact
from sealeak.physics.coupling import effective_pressure_integral
from sealeak.physics.critical_junction import critical_junction, percolation_limit
from sealeak.physics.effective_medium import effective_medium
from sealeak.physics.spectrum import PowerSpectrum
from tests.casefiles import BASE, ORING

S, K = 1.37, 0.71  # h_rms × s, E* × k
SPECTRUM = PowerSpectrum.self_affine(h_rms=1e-6, hurst=0.8, q_rolloff=1e4, q_cutoff=7.8e9)
NOMINAL = PerssonContact(SPECTRUM, 13.3e6, 1e4, 0.42)
SCALED = PerssonContact(SPECTRUM.scaled(S * S), K * 13.3e6, 1e4, 0.42)
P0 = np.geomspace(1e5, 3e6, 7)
FLOW = {"pressure_difference": 1.0, "viscosity": 1e-3, "aspect_ratio": 1.0}

#: The hrms-study example's first seal (40 squeeze pressures, some beyond percolation) with the scaling inputs uncertain.
UNIFORM = (example_text("hrms-study").split("[study]")[0]
           .replace('h_rms = "1 um"', 'h_rms = "1 um ± 10 %"')
           .replace('youngs_modulus = "10 MPa"', 'youngs_modulus = "10 MPa ± 10 %"')
           .replace('viscosity = "1 mPa*s"', 'viscosity = "1 mPa*s ± 10 %"')
           + '\n[uncertainty]\n"theory.alpha" = { distribution = "uniform", low = 0.5, high = 1.5 }\n'
             '"rubber.poisson_ratio" = { distribution = "uniform", low = 0.3, high = 0.5 }\n'
             '"conditions.pressure_difference" = { distribution = "uniform", low = "5 kPa", high = "20 kPa" }\n')


def test_contact_area_and_gaps_scale():
    """A(ζ)/A0 at P0 is the nominal one at P0/(k s); ū and u1 are s times the nominal ones there."""
    zeta = np.array([1.5, 30.0, 1e3])[:, None]
    tau = P0 / (K * S)
    np.testing.assert_allclose(SCALED.area(zeta, P0), NOMINAL.area(zeta, tau), rtol=1e-10, atol=0)
    np.testing.assert_allclose(SCALED.mean_gap(zeta, P0), S * NOMINAL.mean_gap(zeta, tau), rtol=1e-10, atol=0)
    np.testing.assert_allclose(SCALED.u1(zeta, P0), S * NOMINAL.u1(zeta, tau), rtol=1e-10, atol=0)


def test_critical_junction_scales():
    """ζ_c and λ_c are the nominal ones at P0/(k s), u_c s times, the leak rate s³ times (eq. 14.6)."""
    scaled = critical_junction(SCALED, squeeze_pressure=P0, **FLOW)
    nominal = critical_junction(NOMINAL, squeeze_pressure=P0 / (K * S), **FLOW)
    assert np.array_equal(scaled.percolates, nominal.percolates) and nominal.percolates.any()
    np.testing.assert_allclose(scaled.critical_magnification, nominal.critical_magnification, rtol=1e-10, atol=0)
    np.testing.assert_allclose(scaled.critical_wavelength, nominal.critical_wavelength, rtol=1e-10, atol=0)
    np.testing.assert_allclose(scaled.critical_gap, S * nominal.critical_gap, rtol=1e-10, atol=0)
    np.testing.assert_allclose(scaled.leak_rate, S**3 * nominal.leak_rate, rtol=1e-10, atol=0)


def test_effective_medium_scales_to_its_solver_tolerance():
    """σ_eff scales as s³ at P0/(k s) too (Bruggeman's equation is homogeneous in σ(u) ∝ u³); its numerics are not
    scale-free (about 1e-7), which is why the effective medium's samples take the full prediction."""
    scaled = effective_medium(SCALED, squeeze_pressure=P0, **FLOW)
    nominal = effective_medium(NOMINAL, squeeze_pressure=P0 / (K * S), **FLOW)
    assert np.array_equal(scaled.percolates, nominal.percolates) and nominal.percolates.any()
    ok = scaled.percolates
    np.testing.assert_allclose(scaled.leak_rate[ok], S**3 * nominal.leak_rate[ok], rtol=1e-6, atol=0)


def test_coupled_integral_scales():
    """∫σ_s ds over P0 − ΔP .. P0 is k s⁴ times the nominal integral over the scaled pressures (eq. 14.7)."""
    case = parse_case_file(example_text("hrms-study").split("[study]")[0]).cases[0]
    sigma = junction_sigma(case, NOMINAL)
    sigma_s = junction_sigma(case, SCALED)
    dp = np.full(P0.shape, 2e4)
    direct = effective_pressure_integral(sigma_s, P0, dp).value
    via = K * S**4 * effective_pressure_integral(sigma, P0 / (K * S), dp / (K * S)).value
    assert np.all(direct[:3] > 0)
    np.testing.assert_allclose(direct, via, rtol=1e-10, atol=0)


def test_sigma_table_error_bound():
    """The table of σ_nom meets the exact σ within 1e-6 at random scaled pressures below its top, without
    evaluating the exact σ there (it is a table, not the exact function in disguise)."""
    case = parse_case_file(example_text("hrms-study").split("[study]")[0]).cases[0]
    contact = case.contact()
    exact = junction_sigma(case, contact)
    calls: list[int] = []

    def counted(p):
        calls.append(p.size)
        return exact(p)
    table = sigma_table(contact, counted, 1e4, 1e7, case.percolation_threshold)
    top = SCALING_TABLE_TOP * percolation_limit(contact, case.percolation_threshold)
    p = np.exp(np.random.default_rng(1).uniform(np.log(1e4), np.log(top), 3000))
    built = len(calls)
    got = table(p)
    assert len(calls) == built
    assert np.max(np.abs(got / exact(p) - 1.0)) < 1e-6


@pytest.mark.parametrize("fluid_pressure", ["coupled", "ignored"])
def test_scaled_samples_match_full_predictions(fluid_pressure, monkeypatch):
    """h_rms, E, ν, ΔP, α and η uncertain: every sample's leak rate by the scaling is the full prediction's within
    the table's error, the sealed samples the same, and so the percentiles."""
    text = UNIFORM.replace("alpha = 1.0", f'alpha = 1.0\nfluid_pressure = "{fluid_pressure}"')
    study = parse_uncertain_case(text)
    assert unc._scales(study)
    fast = propagate(study, 8, seed=4)
    monkeypatch.setattr(unc, "_scales", lambda study: False)
    full = propagate(study, 8, seed=4)
    a, b = fast.values["leak_rate"], full.values["leak_rate"]
    assert np.array_equal(a > 0, b > 0) and (b > 0).any() and (b == 0).any()
    np.testing.assert_allclose(a, b, rtol=1e-6, atol=0)
    np.testing.assert_allclose(fast.percentiles(), full.percentiles(), rtol=1e-6, atol=0)
    assert np.ptp(a[:, 0]) > 0


def test_nominal_samples_are_the_deterministic_rows_bit_for_bit():
    """Every input with a spread of zero: the scaling path returns the full prediction's rows, not the table's."""
    text = UNIFORM.split("[uncertainty]")[0].replace("± 10 %", "± 0 %")
    study = parse_uncertain_case(text)
    assert unc._scales(study)
    result = propagate(study, 4, seed=0)
    q = np.nan_to_num(result.nominal[0].critical_junction.leak_rate)
    assert all(np.array_equal(row, q) for row in result.values["leak_rate"])


@pytest.mark.parametrize("text", [
    BASE.replace("hurst = 0.8", 'hurst = "0.8 ± 0.02"'),  # the spectrum's shape
    BASE.replace('h_rms = "44 um"', 'h_rms = "44 um ± 10 %"').replace("alpha = 0.2", 'alpha = 0.2\nmodel = "effective-medium"'),
    ORING.replace('viscosity = "1 mPa*s"', 'viscosity = "1 mPa*s ± 20 %"')
    + '[theory]\nalpha = "1.0 ± 0.2"\n',
])
def test_what_does_not_scale_takes_the_full_prediction(text):
    """A spread of the spectrum's shape, the effective medium's rows, a band seal: no scaling path."""
    study = parse_uncertain_case(text)
    assert not unc._scales(study)


def test_substrate_takes_the_full_prediction():
    """A substrate makes E* not proportional to E: no scaling path; every sample is a full prediction."""
    text = BASE.replace('youngs_modulus = "2.3 MPa"', 'youngs_modulus = "2.3 MPa ± 10 %"').replace(
        "[fluid]", '[substrate]\nyoungs_modulus = "5 MPa"\n[fluid]')
    study = parse_uncertain_case(text)
    assert not unc._scales(study)
    points = unit_points(1, 4, seed=0)
    assert np.all(np.isfinite(leak_rates(study, points)))


#: An O-ring on the critical junction with the scaling inputs uncertain (its profile scales with E, Lindley's force).
ORING_BAND = (ORING.replace('h_rms = "1.5 um"', 'h_rms = "1.5 um ± 10 %"')
              .replace('youngs_modulus = "5.5 MPa"', 'youngs_modulus = "5.5 MPa ± 10 %"')
              .replace('viscosity = "1 mPa*s"', 'viscosity = "1 mPa*s ± 10 %"')
              + '[theory]\nmodel = "critical-junction"\nalpha = "1.0 ± 0.2"\n')


def test_band_samples_by_the_nominal_contact_match_full_predictions(monkeypatch):
    """A band seal's samples take σ from the nominal contact's tables at the scaled pressures (docs/theory.md §14.5):
    every sample's coupled leak rate is the full prediction's within the tables' error (1e-7, then the shooting's
    ~1e-8), the sealed ones the same."""
    study = parse_uncertain_case(ORING_BAND)
    assert unc._scales_band(study) and not unc._scales(study)
    used = []
    tables = unc.band_junction_tables
    monkeypatch.setattr(unc, "band_junction_tables", lambda *a: used.append(len(tables(*a))) or tables(*a))
    fast = propagate(study, 8, seed=2)
    assert used and used[0] == 3  # one table per load
    monkeypatch.setattr(unc, "_scales_band", lambda study: False)
    full = propagate(study, 8, seed=2)
    a, b = fast.values["leak_rate"], full.values["leak_rate"]
    assert np.array_equal(a > 0, b > 0) and (b > 0).any()
    np.testing.assert_allclose(a, b, rtol=1e-6, atol=0)
    assert np.ptp(a[:, 0]) > 0


def test_band_nominal_samples_are_the_deterministic_rows_bit_for_bit():
    """A spread of zero on a band seal: the samples are the full prediction's rows, not the tables'."""
    text = ORING_BAND.replace("± 10 %", "± 0 %").replace('"1.0 ± 0.2"', "1.0")
    study = parse_uncertain_case(text)
    assert unc._scales_band(study)
    result = propagate(study, 4, seed=0)
    q = np.nan_to_num(result.nominal[0].band.critical_junction.leak_rate)
    assert all(np.array_equal(row, q) for row in result.values["leak_rate"])


def test_samples_of_both_theories_compute_the_critical_junction_they_show(monkeypatch):
    """With theory.model = "both" the rows show the critical junction, so a sample computes it alone
    (uncertainty._shown_theory): after the nominal run of both theories every prediction is on the critical junction,
    the samples' leak rates are those of the same case on the critical junction bit for bit, and a spread of zero
    gives the deterministic rows of the case with both theories bit for bit."""
    both = ORING_BAND.replace('model = "critical-junction"', 'model = "both"')
    study = parse_uncertain_case(both)
    assert study.cases[0].model == "both" and unc._scales_band(study)
    models = []
    real = unc.run_case
    monkeypatch.setattr(unc, "run_case", lambda case: models.append(case.model) or real(case))
    got = propagate(study, 8, seed=2)
    assert models[0] == "both" and len(models) > 1 and set(models[1:]) == {"critical-junction"}
    assert got.nominal[0].band.effective_medium is not None
    alone = propagate(parse_uncertain_case(ORING_BAND), 8, seed=2)
    assert np.array_equal(got.values["leak_rate"], alone.values["leak_rate"]) and np.ptp(got.values["leak_rate"][:, 0]) > 0
    zero = propagate(parse_uncertain_case(both.replace("± 10 %", "± 0 %").replace('"1.0 ± 0.2"', "1.0")), 4, seed=0)
    q = np.nan_to_num(zero.nominal[0].band.critical_junction.leak_rate)
    assert all(np.array_equal(row, q) for row in zero.values["leak_rate"])


def test_band_samples_take_the_peak_junction_from_their_own_sigma():
    """A band sample's u_c and λc at the peak pressure (the validity verdict's, the capillary and kinetic gap's) come
    from the band's σ (u_c = (12 η σ/α)^(1/3), ζc in closed form) instead of a new junction: the exact junction's within
    the tables' error (1e-7 in σ, a third of it in u_c), NaN where it does not percolate."""
    study = parse_uncertain_case(ORING_BAND)
    points = unit_points(len(study.inputs), 8, seed=5)
    factors = unc._factors(study, points)
    tables = unc._band_tables(study, points, factors["length"])
    assert tables is not None
    for i in range(1, 4):
        values = [inp.written(points[:, j])[i] for j, inp in enumerate(study.inputs)]
        case = unc._sample_cases(study, values)[0]
        with scaled_junctions(ScaledJunctions(tables[0], float(factors["length"][i]), float(factors["modulus"][i]))):
            fast = run_band(case)
        exact = run_band(case)
        assert np.array_equal(np.isnan(fast.critical_gap_at_max_pressure), np.isnan(exact.critical_gap_at_max_pressure))
        np.testing.assert_allclose(fast.critical_gap_at_max_pressure, exact.critical_gap_at_max_pressure, rtol=1e-7)
        np.testing.assert_allclose(fast.critical_wavelength_at_max_pressure, exact.critical_wavelength_at_max_pressure,
                                   rtol=1e-12)
        live = np.isfinite(exact.critical_gap_at_max_pressure)
        assert live.any()  # (and the numbers are the table's, not the exact junction's bits)
        assert not np.array_equal(fast.critical_gap_at_max_pressure[live], exact.critical_gap_at_max_pressure[live])


def test_a_band_samples_peak_junction_closed_at_the_end_of_the_roughness_is_zero_not_missing():
    """Where ζc reaches the end of the resolved roughness the junction percolates with u_c = 0 (σ = 0, docs/theory.md
    §9.11): the sample's peak gap is 0 with its λc, as the exact junction gives, and NaN only where it does not
    percolate."""
    case = parse_case_file(ORING).cases[0]
    contact = PerssonContact(case.spectrum, case.e_star, 3000.0, case.gamma)
    limit = percolation_limit(contact, case.percolation_threshold)
    closed = lambda p: np.zeros_like(p)  # noqa: E731
    with scaled_junctions(ScaledJunctions({contact.q0: closed}, 1.0, 1.0)):
        uc, lc = _junction_at_peak(case, contact, 0.5 * limit, closed)
        assert uc == 0.0
        exact = critical_junction(contact, squeeze_pressure=[0.5 * limit], percolation_threshold=case.percolation_threshold,
                                  **FLOW)
        assert lc == pytest.approx(float(exact.critical_wavelength[0]), rel=1e-12, abs=0)
        assert np.isnan(_junction_at_peak(case, contact, 2.0 * limit, closed)).all()
