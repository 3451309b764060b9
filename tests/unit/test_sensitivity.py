"""Sobol' sensitivity indices (sealeak.cases.sensitivity, issue 24 item 3).

The estimates are checked against indices known in closed form or published, never against the code's
own output: an additive function of the unit cube, y = Σ a_i u_i (S1_i = ST_i = a_i²/Σ a_j², no
interactions), and the Ishigami function (Ishigami & Homma 1990; indices as tabulated by Saltelli et al.
2008, "Global Sensitivity Analysis: The Primer", and Sobol' & Levitan 1999). The module analyses log10 Q,
so the test models return Q = 10^y.
"""

import numpy as np
import pytest

from sealeak.cases import parse_case_file, run_case
from sealeak.cases.sensitivity import sobol_indices, sobol_points
from sealeak.cases.sobol import MAX_BASE_SAMPLES, check_base_samples, log_leak_rate, sensitivity_summary
from sealeak.cases.uncertainty import leak_rates, parse_uncertain_case
from sealeak.errors import InputError
from tests.casefiles import BASE

A = np.array([1.0, 2.0, 0.5, 0.0, 3.0])
NAMES = ["a", "b", "c", "d", "e"]
EXACT = A**2 / np.sum(A**2)

# Ishigami, a = 7, b = 0.1, on [-π, π]³: V = a²/8 + b π⁴/5 + b² π⁸/18 + 1/2
_V1 = 0.5 * (1 + 0.1 * np.pi**4 / 5) ** 2
_V2 = 7**2 / 8
_V13 = 0.1**2 * np.pi**8 * (1 / 18 - 1 / 50)
_V = _V1 + _V2 + _V13
ISHIGAMI_S1 = np.array([_V1 / _V, _V2 / _V, 0.0])  # 0.3139, 0.4424, 0
ISHIGAMI_ST = np.array([(_V1 + _V13) / _V, _V2 / _V, _V13 / _V])  # 0.5576, 0.4424, 0.2437


def additive(u):
    return 10.0 ** (u @ A - 12.0)  # m³/s: log10 Q = Σ a_i u_i - 12


def ishigami(u):
    x = -np.pi + 2 * np.pi * u
    y = np.sin(x[:, 0]) + 7 * np.sin(x[:, 1]) ** 2 + 0.1 * x[:, 2] ** 4 * np.sin(x[:, 0])
    return 10.0**y


def test_additive_function_indices_equal_their_closed_form():
    s = sobol_indices(additive, NAMES, 1024, seed=3)
    assert s.first.shape == s.total.shape == (1, 5)
    # tolerance: 0.01 absolute (the estimator's error at N = 1024 is a few 1e-3, its 95 % interval about 0.02)
    assert s.first[0] == pytest.approx(EXACT, abs=0.01)
    assert s.total[0] == pytest.approx(EXACT, abs=0.01)
    assert s.evaluations == 1024 * 7 and s.base_samples == 1024
    assert (s.first_conf > 0).any() and (s.first_conf < 0.1).all() and (s.total_conf < 0.1).all()
    assert s.sealed_fraction[0] == 0.0
    assert s.variance[0] == pytest.approx(np.sum(A**2) / 12, rel=0.02)  # Var Σ a_i u_i = Σ a_i²/12


def test_ishigami_indices_match_the_published_values():
    # the closed forms above against the published table (Saltelli et al. 2008), then the estimates against them
    assert ISHIGAMI_S1 == pytest.approx([0.3139, 0.4424, 0.0], abs=1e-4)
    assert ISHIGAMI_ST == pytest.approx([0.5576, 0.4424, 0.2437], abs=1e-4)
    s = sobol_indices(ishigami, ["x1", "x2", "x3"], 4096, seed=11)
    # tolerance 0.03 absolute: about the 95 % bootstrap half-width at N = 4096
    assert s.first[0] == pytest.approx(ISHIGAMI_S1, abs=0.03)
    assert s.total[0] == pytest.approx(ISHIGAMI_ST, abs=0.03)
    # the interaction x1·x3 shows as ST > S1 for x1 and x3, not for x2
    assert s.total[0, 0] - s.first[0, 0] > 0.15 and s.total[0, 2] - s.first[0, 2] > 0.15
    assert abs(s.total[0, 1] - s.first[0, 1]) < 0.05


def test_same_seed_same_bytes_other_seed_other_points():
    one = sobol_indices(additive, NAMES, 64, seed=5)
    two = sobol_indices(additive, NAMES, 64, seed=5)
    for name in ("first", "first_conf", "total", "total_conf"):
        assert getattr(one, name).tobytes() == getattr(two, name).tobytes()
    assert sobol_points(5, 64, 5).tobytes() == sobol_points(5, 64, 5).tobytes()
    assert not np.array_equal(sobol_points(5, 64, 5), sobol_points(5, 64, 6))
    # seed 0 is a seed like any other (SALib's bootstrap would take 0 as "unseeded")
    zero = [sobol_indices(additive, NAMES, 64, seed=0) for _ in range(2)]
    assert zero[0].first_conf.tobytes() == zero[1].first_conf.tobytes()


def test_points_are_saltelli_design_on_the_unit_cube():
    p = sobol_points(3, 32, 1)
    assert p.shape == (32 * 5, 3) and (p >= 0).all() and (p < 1).all()
    a, b = p[0::5], p[4::5]
    # A_B^(i) is A with column i from B
    for i in range(3):
        abi = p[1 + i::5]
        assert np.array_equal(np.delete(abi, i, axis=1), np.delete(a, i, axis=1))
        assert np.array_equal(abi[:, i], b[:, i])


def test_each_row_is_analysed_on_its_own():
    def two_rows(u):
        return np.column_stack([10.0 ** (3 * u[:, 0] + 0.2 * u[:, 1]), 10.0 ** (0.2 * u[:, 0] + 3 * u[:, 1])])
    s = sobol_indices(two_rows, ["h_rms", "E"], 256, seed=2)
    assert s.ranking(0) == [0, 1] and s.ranking(1) == [1, 0]
    assert s.total[0, 0] == pytest.approx(9 / 9.04, abs=0.02) and s.total[1, 1] == pytest.approx(9 / 9.04, abs=0.02)


def test_sealed_samples_count_one_decade_below_the_smallest_leak():
    y, floor, sealed = log_leak_rate(np.array([0.0, 1e-12, np.nan, 1e-10]))
    assert floor == pytest.approx(1e-13, rel=1e-12, abs=0) and sealed == 0.5
    assert y == pytest.approx([-13, -12, -13, -10], abs=1e-12)
    y, floor, sealed = log_leak_rate(np.zeros(4))
    assert np.isnan(floor) and sealed == 1.0 and np.isnan(y).all()
    with pytest.raises(InputError, match="leak rate"):
        log_leak_rate(np.array([1e-12, -1.0]))


def test_an_input_that_decides_sealing_leads_and_the_sealed_share_is_reported():
    def seals_below(u):  # sealed when u0 < 0.3; else log10 Q = -10 + 0.5 u1
        return np.where(u[:, 0] < 0.3, 0.0, 10.0 ** (-10 + 0.5 * u[:, 1]))[:, None]
    s = sobol_indices(seals_below, ["compression", "viscosity"], 512, seed=4)
    assert s.sealed_fraction[0] == pytest.approx(0.3, abs=0.02)
    assert s.floor[0] < 1e-10
    assert s.ranking(0) == [0, 1]
    text = sensitivity_summary(s, 0)
    assert text.startswith("compression explains") and "sealed" in text


def test_a_row_without_variance_has_no_indices():
    def rows(u):
        return np.column_stack([np.zeros(len(u)), np.full(len(u), 1e-11), 10.0 ** u[:, 0]])
    s = sobol_indices(rows, ["x", "y"], 16, seed=1)
    assert np.isnan(s.first[:2]).all() and np.isnan(s.total[:2]).all()
    assert np.isfinite(s.total[2]).all()
    assert sensitivity_summary(s, 0) == "No sensitivity: every sample sealed; no input changes log Q."
    assert "same leak rate in every sample" in sensitivity_summary(s, 1)


def test_summary_in_plain_words_names_the_measurement_to_improve():
    s = sobol_indices(additive, NAMES, 1024, seed=3)
    text = sensitivity_summary(s, 0, labels=["h_rms", "E", "H", "ν", "q_r"])
    lead = round(100 * EXACT[4])  # 63 %, from the closed form
    assert text.startswith("q_r explains ")
    shown = int(text.split("explains ")[1].split(" %")[0])
    assert abs(shown - lead) <= 1
    assert "measure it better first" in text and "Next: E (" in text


@pytest.mark.parametrize("bad", [0, 15, 100, 2 * MAX_BASE_SAMPLES, 64.0, True, "64", None])
def test_base_samples_must_be_a_power_of_two_in_range(bad):
    with pytest.raises(InputError, match=r"^--sensitivity( = .*)?: must be a power of two"):
        check_base_samples(bad, "--sensitivity")


def test_the_design_is_bounded():
    with pytest.raises(InputError, match="sensitivity"):
        sobol_points(32, MAX_BASE_SAMPLES, 1)
    with pytest.raises(InputError, match="at least one uncertain input"):
        sobol_points(0, 16, 1)


GAS = BASE.replace('[fluid]\nviscosity = "1 mPa*s"', '[fluid]\nname = "helium"\ntemperature = "20 degC"').replace(
    'pressure_difference = "10 kPa"', 'upstream_pressure = "2 bar"\ndownstream_pressure = "1 bar"')


def test_a_gas_is_analysed_on_the_pv_throughput_its_band_shows():
    # The slip model changes a gas's pV throughput but not the no-slip volume flow: analysed on the latter, a spread
    # of theory.rarefaction alone would look like no sensitivity at all.
    models = ["no-slip", "kinetic"]
    def with_model(model):
        return GAS.replace("alpha = 0.2", f'alpha = 0.2\nrarefaction = "{model}"')

    text = with_model("kinetic") + '[uncertainty]\n"theory.rarefaction" = { distribution = "choice", values = ["no-slip", "kinetic"] }\n'
    sampled = leak_rates(parse_uncertain_case(text), np.array([[0.25], [0.75]]))
    alone = [[rec["leak_rate_pv"] for c in parse_case_file(with_model(m)).cases for rec in run_case(c).records()]
             for m in models]
    np.testing.assert_allclose(sorted(sampled.tolist()), sorted(alone), rtol=1e-12)
    assert (np.array(alone[1]) > 1.001 * np.array(alone[0])).all()  # slip: the kinetic flow is larger


def test_a_design_whose_answers_do_not_fit_the_bound_is_refused_before_any_prediction(monkeypatch):
    import sealeak.cases.sensitivity as sensitivity

    study = parse_uncertain_case(BASE.replace('h_rms = "44 um"', 'h_rms = "44 um ± 10 %"'))
    calls = []
    monkeypatch.setattr(sensitivity, "leak_rates", lambda *a: calls.append(a))
    # 16 base samples, 1 input: 48 points; BASE has 3 rows, so 144 answers
    monkeypatch.setattr(sensitivity, "MAX_EVALUATIONS", 143)
    with pytest.raises(InputError, match=r"--sensitivity = 16: with 1 uncertain inputs and 3 rows holds 144 numbers"):
        sensitivity.study_sensitivity(study, 16, 0)
    assert not calls
