"""Uncertain inputs (issue 24): spreads in the case file, their propagation, percentiles and the probability of passing."""

import json
import warnings

import numpy as np
import pytest

import sealeak.cases.uncertainty as unc
from sealeak.cases import example_text, parse_case_file, run_case
from sealeak.cases.uncertainty import leak_rates, parse_uncertain_case, propagate, unit_points
from sealeak.errors import InputError
from sealeak.render import prediction_csv, prediction_json
from sealeak.render.interactive import prediction_plot_data
from sealeak.render.uncertainty import passing_lines, uncertainty_columns, uncertainty_heading, uncertainty_legend, uncertainty_summary
from sealeak.render.uncertainty_figures import uncertainty_figures
from tests.casefiles import BASE, ORING

#: BASE at two pressures where the seal leaks, h_rms given a spread (the leak rate rises steeply with it).
LEAKS = BASE.replace('squeeze_pressure = ["20 kPa", "60 kPa", "0.1 MPa"]', 'squeeze_pressure = ["20 kPa", "60 kPa"]')


def spread(text: str, old: str = 'h_rms = "44 um"', new: str = 'h_rms = "44 um ± 10 %"') -> str:
    assert old in text
    return text.replace(old, new)


def test_percentiles_of_q_are_q_at_the_input_percentiles():
    """One monotone input: the p-quantile of Q is Q at the input's p-quantile; the scrambled Sobol' points stratify
    the unit interval in cells of 1/N, so the sample quantile lies within two cells of it."""
    study = parse_uncertain_case(spread(LEAKS))
    n = 256
    result = propagate(study, n, seed=3)
    p = result.percentiles()
    for k, level in enumerate((0.05, 0.50, 0.95)):
        lo, hi = leak_rates(study, np.array([[level - 2 / n], [level + 2 / n]]))
        assert np.all((p[k] >= np.minimum(lo, hi)) & (p[k] <= np.maximum(lo, hi)))
    assert np.all(np.diff(p, axis=0) > 0)  # a real spread: p05 < p50 < p95


def test_sampled_input_follows_its_distribution():
    """The h_rms of the samples: a normal of mean 44 µm and sd 4.4 µm (truncated at ±3 sd)."""
    study = parse_uncertain_case(spread(LEAKS))
    h = study.inputs[0].ppf(unit_points(1, 1024, seed=1)[:, 0])
    assert h.mean() == pytest.approx(44e-6, rel=1e-3)
    assert h.std() == pytest.approx(4.4e-6, rel=0.03)
    assert h.min() >= 44e-6 - 3 * 4.4e-6 * (1 + 1e-12) and h.max() <= 44e-6 + 3 * 4.4e-6 * (1 + 1e-12)


def test_zero_spread_is_the_deterministic_result_bit_for_bit():
    plain = [run_case(c) for c in parse_case_file(LEAKS).cases]
    study = parse_uncertain_case(spread(LEAKS, new='h_rms = "44 um ± 0 %"'))
    result = propagate(study, 8, seed=0)
    assert prediction_json(result.nominal) == prediction_json(plain)
    q = plain[0].critical_junction.leak_rate
    for row in result.percentiles():
        assert np.array_equal(row, q)  # every percentile the very float of the deterministic row


def test_same_seed_same_bytes_other_seed_other_numbers():
    text = spread(LEAKS)
    a, b, c = (propagate(parse_uncertain_case(text), 16, seed=s) for s in (7, 7, 8))
    assert prediction_json(a.nominal, a) == prediction_json(b.nominal, b)
    assert prediction_csv(a.nominal, a) == prediction_csv(b.nominal, b)
    assert not np.array_equal(a.percentiles(), c.percentiles())


@pytest.mark.parametrize("limit, exceed", [("1 m^3/s", 0.0), ("1e-30 ml/min", 1.0)])
def test_pass_probability_far_inside_or_outside_the_specification(limit, exceed):
    text = LEAKS.replace('pressure_difference = "10 kPa"', f'pressure_difference = "10 kPa"\nmax_leak_rate = "{limit}"')
    result = propagate(parse_uncertain_case(spread(text)), 16, seed=0)
    assert np.all(result.exceed_probability == exceed)
    (passing,) = result.passing_loads()
    assert np.isnan(passing.passing_load) and passing.note  # passes everywhere, or nowhere: no load to place


def test_passing_load_lies_between_the_rows_it_separates():
    """A limit between the leak rates of the two pressures: the seal fails at 20 kPa and passes at 60 kPa."""
    q = run_case(parse_case_file(LEAKS).cases[0]).critical_junction.leak_rate
    limit = float(np.sqrt(q[0] * q[1]))
    text = LEAKS.replace('pressure_difference = "10 kPa"', f'pressure_difference = "10 kPa"\nmax_leak_rate = "{limit!r} m^3/s"')
    result = propagate(parse_uncertain_case(spread(text, new='h_rms = "44 um ± 1 %"')), 16, seed=0)
    assert list(result.exceed_probability) == [1.0, 0.0]
    (passing,) = result.passing_loads()
    assert 20e3 < passing.passing_load < 60e3
    # the two rows it lies between, their probabilities of passing, and a warning that rows 3x apart place it roughly
    assert passing.between == (20e3, 60e3) and passing.between_passing_probability == (0.0, 1.0)
    (line,) = [a for a in json.loads(prediction_json(result.nominal, result))["uncertainty"]["answers"] if "passes" in a]
    assert "between the rows at P0 = 20 kPa (passes in 0.0 % of the samples) and P0 = 60 kPa (100.0 %)" in line
    assert "place it roughly" in line


def test_passing_load_without_spread_is_where_the_leak_rate_reaches_the_limit():
    """No spread: the probability of passing jumps from 0 to 1, and the passing load is where the deterministic Q
    reaches the limit with ln Q linear between the rows (docs/theory.md eq. 14.4): for the limit Q0^(3/4) Q1^(1/4), a
    quarter of the way from the first row to the second; not 95 % of the way, as P interpolated linearly would put it."""
    q = run_case(parse_case_file(LEAKS).cases[0]).critical_junction.leak_rate
    limit = float(q[0] ** 0.75 * q[1] ** 0.25)
    text = LEAKS.replace('pressure_difference = "10 kPa"', f'pressure_difference = "10 kPa"\nmax_leak_rate = "{limit!r} m^3/s"')
    result = propagate(parse_uncertain_case(spread(text, new='h_rms = "44 um ± 0 %"')), 8, seed=0)
    (passing,) = result.passing_loads()
    assert passing.between_passing_probability == (0.0, 1.0)
    assert passing.passing_load == pytest.approx(20e3 + 0.25 * 40e3, rel=1e-9, abs=0.0)


def test_passing_load_is_not_placed_towards_a_row_that_seals():
    """Where at least 95 % of the samples seal at the first passing row there is no leak rate to interpolate towards:
    no passing load, the two rows named (in the JSON and the sentence)."""
    text = BASE.replace('squeeze_pressure = ["20 kPa", "60 kPa", "0.1 MPa"]', 'squeeze_pressure = ["20 kPa", "1 MPa"]')
    nominal = run_case(parse_case_file(text).cases[0]).critical_junction
    assert np.isfinite(nominal.leak_rate[0]) and not nominal.percolates[1]  # leaks at 20 kPa, sealed at 1 MPa
    text = text.replace('pressure_difference = "10 kPa"', 'pressure_difference = "10 kPa"\nmax_leak_rate = "1e-30 m^3/s"')
    result = propagate(parse_uncertain_case(spread(text, new='h_rms = "44 um ± 1 %"')), 16, seed=0)
    (passing,) = result.passing_loads()
    assert np.isnan(passing.passing_load) and passing.between == (20e3, 1e6) and "seal" in passing.note
    summary = json.loads(prediction_json(result.nominal, result))["uncertainty"]
    assert summary["passing_loads"][0]["between"] == [20e3, 1e6] and summary["passing_loads"][0]["passing_load"] is None
    (line,) = [a for a in summary["answers"] if "passes" in a]
    assert "from somewhere between the rows at P0 = 20 kPa" in line and "P0 = 1000 kPa" in line


def test_passing_at_the_lowest_load_says_how_many_samples_there_are_outside_the_theory():
    """A seal that passes at its lowest load, where samples leak outside the theory (ΔP lifts the seal): the note says
    what share, as it does between two rows."""
    passing = unc._passing("", "squeeze_pressure", np.array([1e3, 2e3]), np.array([1.0, 1.0]), np.array([1e-9, 1e-10]),
                           np.array([1e-6, 1e-6]), np.array([1.0, 0.5]))
    assert np.isnan(passing.passing_load)
    assert "already at the lowest squeeze pressure computed" in passing.note and "100 % of its samples leak outside" in passing.note


def test_model_choice_samples_each_theory():
    """theory.model as a choice: u < 0.5 runs the critical junction, u >= 0.5 the effective medium."""
    both = run_case(parse_case_file(LEAKS.replace("alpha = 0.2", 'alpha = 0.2\nmodel = "both"')).cases[0])
    text = LEAKS + '\n[uncertainty]\n"theory.model" = { distribution = "choice", values = ["critical-junction", "effective-medium"] }\n'
    text = text.replace("alpha = 0.2", 'alpha = 0.2\nmodel = "critical-junction"')
    q = leak_rates(parse_uncertain_case(text), np.array([[0.25], [0.75]]))
    assert np.array_equal(q[0], both.critical_junction.leak_rate)
    assert np.array_equal(q[1], both.effective_medium.leak_rate)


def test_uncertainty_table_gives_other_distributions():
    text = LEAKS + ('\n[uncertainty]\n"theory.alpha" = { distribution = "uniform", low = 0.1, high = 0.3 }\n'
                    '"fluid.viscosity" = { distribution = "triangular", low = "0.5 mPa*s", high = "2 mPa*s" }\n'
                    '"surface.h_rms" = { distribution = "lognormal", sd = "20 %" }\n')
    study = parse_uncertain_case(text)
    assert [i.distribution for i in study.inputs] == ["uniform", "triangular", "lognormal"]
    u = np.array([0.0, 0.5, 1.0])
    assert np.allclose(study.inputs[0].ppf(u), [0.1, 0.2, 0.3])
    assert np.allclose(study.inputs[1].ppf(u)[[0, 2]], [0.5e-3, 2e-3])
    assert study.inputs[2].ppf(np.array([0.5]))[0] == pytest.approx(44e-6)  # the lognormal's median is the value


def test_json_rows_carry_percentiles_and_units():
    result = propagate(parse_uncertain_case(spread(LEAKS)), 8, seed=0)
    doc = json.loads(prediction_json(result.nominal, result))
    row = doc["results"][0]
    assert row["leak_rate_p05"] <= row["leak_rate_p50"] <= row["leak_rate_p95"]
    assert doc["units"]["leak_rate_p95"] == "m^3/s" and doc["units"]["sealed_fraction"] == "1"
    assert doc["uncertainty"]["samples"] == 8 and doc["uncertainty"]["inputs"][0]["key"] == "surface.h_rms"


@pytest.mark.parametrize("written", ["44 um ± 0.0044 mm", "44 um +/- 4.4 um", "44 um ± 10 %", "44um±10%"])
def test_spread_written_absolute_or_relative(written):
    study = parse_uncertain_case(spread(LEAKS, new=f'h_rms = "{written}"'))
    assert study.inputs[0].parameters["sd"] == pytest.approx(4.4)  # in the value's unit, µm
    assert study.cases[0].spectrum.h_rms == pytest.approx(44e-6)  # the deterministic case: the value


@pytest.mark.parametrize("edit, field", [
    (('h_rms = "44 um"', 'h_rms = "44 um ± -10 %"'), "surface.h_rms"),
    (('h_rms = "44 um"', 'h_rms = "44 um ± 40 %"'), "surface.h_rms"),
    (('h_rms = "44 um"', 'h_rms = "44 um ± 1 kPa"'), "surface.h_rms"),
    (('h_rms = "44 um"', 'h_rms = "44 um ± "'), "surface.h_rms"),
    (('shape = "ring"', 'shape = "ring ± 1"'), "seal.shape"),
    (('squeeze_pressure = ["20 kPa", "60 kPa"]', 'squeeze_pressure = ["20 kPa ± 1 %", "60 kPa"]'),
     "conditions.squeeze_pressure"),
    (("alpha = 0.2", 'alpha = 0.2\n[uncertainty]\n"theory.alpha" = { distribution = "gauss", sd = 0.1 }'),
     "uncertainty.theory.alpha.distribution"),
    (("alpha = 0.2", 'alpha = 0.2\n[uncertainty]\n"theory.alpha" = { distribution = "uniform", low = 0.3, high = 0.1 }'),
     "uncertainty.theory.alpha"),
    (("alpha = 0.2", 'alpha = 0.2\n[uncertainty]\n"theory.alfa" = { distribution = "normal", sd = 0.01 }'),
     "uncertainty.theory.alfa"),
    (("alpha = 0.2", 'alpha = 0.2\n[uncertainty]\n"theory.gamma" = { distribution = "normal", sd = 0.01 }'),
     "theory.gamma"),
    (("alpha = 0.2", 'alpha = 0.2\n[uncertainty]\n"theory.alpha" = { distribution = "normal", mean = 0.01 }'),
     "uncertainty.theory.alpha.mean"),
])
def test_bad_spreads_are_one_line_naming_the_key(edit, field):
    with pytest.raises(InputError) as exc:
        parse_uncertain_case(LEAKS.replace(*edit))
    assert exc.value.field.startswith(field) and "\n" not in str(exc.value)


def test_a_spread_that_reaches_out_of_range_is_refused_whatever_the_samples():
    """hurst = 0.95 ± 0.03 reaches H = 1.04 at its end (±3 sd): refused before any sample, naming that end; it used to
    be refused at 256 samples and accepted at 4 (no sample drew H >= 1). So is α beyond its range, whose samples take
    a path that builds no case (the nominal Q scaled), where 0.1 .. 1e7 ran and gave leak rates 10⁷ times the nominal."""
    text = spread(LEAKS, old="hurst = 0.8", new='hurst = "0.95 ± 0.03"')
    with pytest.raises(InputError) as exc:
        parse_uncertain_case(text)
    assert exc.value.field == "surface.hurst (the end of its spread surface.hurst = 1.04)"
    alpha = LEAKS + '[uncertainty]\n"theory.alpha" = { distribution = "uniform", low = 0.1, high = 1e7 }\n'
    with pytest.raises(InputError, match=r"theory\.alpha \(the end of its spread theory\.alpha = 1e\+07\) = 1e\+07: must lie in"):
        parse_uncertain_case(alpha)
    inside = parse_uncertain_case(spread(LEAKS, old="hurst = 0.8", new='hurst = "0.9 ± 0.03"'))  # 0.81 .. 0.99
    assert [propagate(inside, n, seed=0).samples for n in (4, 256)] == [4, 256]


def test_a_sample_far_out_of_range_is_refused_without_a_warning():
    """A Poisson ratio drawn up to 1e308 (a fuzzed [uncertainty] entry) of an O-ring: the sample's case is refused,
    naming it, and the band's scaling factors computed before it (1 − ν² overflows) print no warning beside the
    one-line error."""
    text = ORING + '\n[uncertainty]\n"rubber.poisson_ratio" = { distribution = "triangular", low = 0, high = 1e308 }\n'
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        with pytest.raises(InputError) as exc:
            propagate(parse_uncertain_case(text), 8, seed=0)
    assert "rubber.poisson_ratio" in exc.value.field and "the end of its spread" in exc.value.field


@pytest.mark.parametrize("samples, sampler", [(1, "sobol"), (100, "sobol"), (8, "halton")])
def test_bad_sample_options(samples, sampler):
    with pytest.raises(InputError):
        unit_points(2, samples, 0, sampler)


def test_gas_limit_needs_a_gas_or_the_helium_equivalent():
    text = LEAKS.replace('pressure_difference = "10 kPa"', 'pressure_difference = "10 kPa"\nmax_leak_rate = "1e-6 mbar*l/s"')
    with pytest.raises(InputError, match="helium_equivalent"):
        parse_uncertain_case(spread(text))


@pytest.mark.parametrize("limit", ["1e-12 m^3/s", "1 ml/min"])
def test_a_gas_limit_in_a_plain_volume_flow_is_refused(limit):
    """A gas's plain volume flow was compared with its Q column, the incompressible K ΔP shown for comparison: the
    helium test at 10 % compression passed 1e-12 m³/s while its pV throughput is ~2.8e-11 m³/s at 1 bar."""
    text = example_text("helium-test").replace('[theory]', f'max_leak_rate = "{limit}"\n[theory]', 1)
    assert "max_leak_rate" in text.split("[theory]")[0]
    with pytest.raises(InputError, match="plain volume flow, which for a gas depends on the pressure") as err:
        parse_uncertain_case(text.replace('h_rms = "1.5 um"', 'h_rms = "1.5 um ± 10 %"'))
    assert err.value.field == "conditions.max_leak_rate"


def test_a_limit_that_is_no_leak_rate_is_named_as_written():
    text = LEAKS.replace('pressure_difference = "10 kPa"', 'pressure_difference = "10 kPa"\nmax_leak_rate = "1 kg"')
    with pytest.raises(InputError) as err:
        parse_uncertain_case(spread(text))
    assert err.value.field == "conditions.max_leak_rate" and err.value.value == "1 kg" and "not a leak rate" in str(err.value)


def _alpha_and_viscosity(model):
    text = spread(LEAKS, old='viscosity = "1 mPa*s"', new='viscosity = "1 mPa*s ± 20 %"')
    return text.replace("alpha = 0.2", f'alpha = "0.2 ± 0.05"\nmodel = "{model}"')


@pytest.mark.parametrize("text", [_alpha_and_viscosity("critical-junction"), _alpha_and_viscosity("effective-medium"),
                                  spread(ORING, 'viscosity = "1 mPa*s"', 'viscosity = "1 mPa*s ± 20 %"')
                                  + '[theory]\nalpha = "1.0 ± 0.2"\n'])
def test_alpha_and_viscosity_samples_share_the_contact(text, monkeypatch):
    """Only α and η uncertain: the shared-contact scaling Q ∝ α/η (∝ 1/η for the effective medium) gives what a full
    prediction of each sample gives (a uniform seal, and an O-ring's band)."""
    study = parse_uncertain_case(text)
    points = unit_points(2, 4, seed=2)
    shared = leak_rates(study, points)
    monkeypatch.setattr(unc, "_shares_contact", lambda study: False)
    monkeypatch.setattr(unc, "_scales", lambda study: False)
    monkeypatch.setattr(unc, "_scales_band", lambda study: False)
    full = leak_rates(study, points)
    assert np.allclose(shared, full, rtol=1e-9, atol=0)
    assert np.ptp(shared[:, 0]) > 0


def test_every_value_of_a_choice_is_checked_before_any_sample_runs():
    text = BASE + '[uncertainty]\n"theory.alpha" = { distribution = "choice", values = [0.2, 0.3, 0.4, "zz"] }\n'
    with pytest.raises(InputError, match=r"theory\.alpha \(a value of its choice theory\.alpha = .?zz"):
        parse_uncertain_case(text)


def test_samples_outside_the_theory_are_counted_and_their_percentiles_marked(monkeypatch):
    """At 1 MPa the ring nearly seals: most samples have no leak channel, and those that leak do so through critical
    gaps narrower than a water molecule (valid = NO in their own prediction). The scaled contact's verdicts are the
    full predictions' verdicts, sample by sample; the 95th percentile comes from such samples and is marked."""
    text = spread(LEAKS.replace('["20 kPa", "60 kPa"]', '["20 kPa", "60 kPa", "1 MPa"]'), new='h_rms = "44 um ± 10 %"')
    study = parse_uncertain_case(text)
    fast = propagate(study, 64, seed=0)
    monkeypatch.setattr(unc, "_scales", lambda study: False)  # every sample a full prediction
    full = propagate(study, 64, seed=0)
    assert fast.valid is not None and full.valid is not None
    assert np.array_equal(fast.valid, full.valid)
    np.testing.assert_allclose(fast.values["leak_rate"], full.values["leak_rate"], rtol=1e-6, atol=0)
    outside = fast.outside_fraction
    assert outside[0] == outside[1] == 0.0 and 0.0 < outside[2] <= 1.0 - fast.sealed[:, 2].mean()
    monkeypatch.undo()
    many = propagate(study, 256, seed=0)  # with 256 samples the 95th percentile at 1 MPa is a leaking sample's
    marked = many.outside()
    assert not marked[:, :2].any() and marked[2, 2] and not marked[:2, 2].any()  # (p05 and p50 are 0: sealed)
    (row,) = [r for r in json.loads(prediction_json(many.nominal, many))["results"] if r["squeeze_pressure"] == 1e6]
    assert row["outside_fraction"] == many.outside_fraction[2] > 0


def test_a_median_from_samples_outside_the_theory_reaches_the_web_plot():
    """At 850 kPa the ring's nominal critical gap is 1e-16 m (valid = NO) and still percolates: the median of the
    samples is such a leak, flagged in the table's stars and in the web plot's data; at 300 kPa it is not."""
    text = spread(BASE.replace('squeeze_pressure = ["20 kPa", "60 kPa", "0.1 MPa"]', 'squeeze_pressure = ["300 kPa", "850 kPa"]'))
    result = propagate(parse_uncertain_case(text), 32, seed=0)
    # the premise, from the deterministic prediction: valid at 300 kPa; at 850 kPa a channel whose gap is below a molecule
    (nominal,) = result.nominal
    assert list(nominal.valid) == [True, False] and nominal.critical_junction.percolates.all()
    assert nominal.critical_junction.critical_gap[1] < nominal.case.fluid.molecular_length
    assert result.percentiles()[1, 1] > 0 and result.outside()[1].tolist() == [False, True]
    (leak,) = prediction_plot_data(result.nominal, result)["leak"]
    assert leak["band"]["p50_outside"] == [False, True]
    # with 256 samples and a row at 700 kPa, the 5th percentile there is such a leak as well: the plot circles it too
    text = spread(BASE.replace('squeeze_pressure = ["20 kPa", "60 kPa", "0.1 MPa"]', 'squeeze_pressure = ["300 kPa", "700 kPa", "850 kPa"]'))
    many = propagate(parse_uncertain_case(text), 256, seed=0)
    (leak,) = prediction_plot_data(many.nominal, many)["leak"]
    flags = [leak["band"][f"p{q}_outside"] for q in ("05", "50", "95")]
    assert flags == [[bool(v) for v in row] for row in many.outside()] and flags[0][1]


def test_the_sobol_samples_skip_the_verdicts_they_do_not_use(monkeypatch):
    """sample_values (the leak rates the Sobol' indices need) takes the scaled route without the samples' validity
    verdicts, a critical junction per sample and row; propagate, which reports them, computes them."""
    study = parse_uncertain_case(spread(LEAKS))
    assert unc._scales(study)
    calls = []
    real = unc.scaled_validity
    monkeypatch.setattr(unc, "scaled_validity", lambda *a: calls.append(1) or real(*a))
    values = unc.sample_values(study, unit_points(1, 16, seed=0))
    assert values["leak_rate"].shape[0] == 16 and not calls
    assert propagate(study, 16, seed=0).valid is not None and calls


def test_a_specification_without_spreads_takes_one_sample_and_draws_no_band():
    """max_leak_rate alone: every sample would be the nominal prediction, so one is taken; each probability is 0 or 1,
    the heading says why, and there is no fan chart or distribution to draw. The table is then a verdict per row: the
    deterministic leak rate (not three equal percentiles) and whether it passes, and the line under it places the load
    where the leak rate itself reaches the limit."""
    text = LEAKS.replace('pressure_difference = "10 kPa"', 'pressure_difference = "10 kPa"\nmax_leak_rate = "1 ml/min"')
    result = propagate(parse_uncertain_case(text), 256, seed=0)
    assert result.samples == 1 and set(result.exceed_probability.tolist()) <= {0.0, 1.0}
    assert "no uncertain inputs" in uncertainty_heading(result)
    assert uncertainty_figures(result) == {}
    # nor percentiles in the records or a band in the web plot, which read as sampled; the pass or fail stays
    assert [set(r) for r in result.row_fields()] == [{"exceed_probability"}] * 2
    summary = uncertainty_summary(result)
    assert summary["samples"] == 0 and summary["sampler"] is None and summary["percentiles"] is None
    assert all(curve["band"] is None for curve in prediction_plot_data(result.nominal, result)["leak"])
    headers, rows = uncertainty_columns(result)
    assert headers == ["P0 (kPa)", "Q (ml/min)", "passes"]
    q = result.nominal[0].critical_junction.leak_rate * 6e7
    assert [float(r[1]) for r in rows] == pytest.approx(q, rel=1e-3, abs=0)
    assert [r[2] for r in rows] == ["no" if v > 1.0 else "yes" for v in q]
    assert "passes: the leak rate is at most conditions.max_leak_rate = 1 ml/min" in uncertainty_legend(result)
    # a limit between the two rows' leak rates: placed where log Q, linear in P0, reaches it
    limit = float(np.sqrt(q[0] * q[1]))
    between = propagate(parse_uncertain_case(text.replace('"1 ml/min"', f'"{limit:.6g} ml/min"')), 8, seed=0)
    (line,) = passing_lines(between)
    assert line.startswith(f"passes {limit:.6g} ml/min from about P0 = 40 kPa on, where the leak rate reaches it"), line
    # a limit above both rows' leak rates, and one below both: no load placed, and the line says which
    for spec, words in ((f"{10 * q.max():.6g} ml/min", "already at the lowest squeeze pressure computed: compute lower "
                                                        "loads to find where it starts to pass"),
                        (f"{0.1 * q.min():.6g} ml/min", "at every squeeze pressure computed")):
        (line,) = passing_lines(propagate(parse_uncertain_case(text.replace('"1 ml/min"', f'"{spec}"')), 8, seed=0))
        assert words in line, line


def test_progress_counts_the_samples_that_run_a_prediction_each():
    """A band whose samples each run a prediction reports every one (the CLI's bar); the uniform seal's scaled
    contact takes all samples at once and reports none, yet gives the same percentiles with or without a listener."""
    steps: list[int] = []
    study = parse_uncertain_case(spread(ORING, 'h_rms = "1.5 um"', 'h_rms = "1.5 um ± 10 %"'))
    propagate(study, 4, seed=0, progress=steps.append)
    assert steps == [1, 1, 1, 1]
    steps.clear()
    uniform = parse_uncertain_case(spread(LEAKS))
    quiet = propagate(uniform, 8, seed=0)
    heard = propagate(uniform, 8, seed=0, progress=steps.append)
    assert steps == [] and np.array_equal(quiet.percentiles(), heard.percentiles())


@pytest.mark.parametrize("limit", ["1e300 ml/min", "1e-300 ml/min", "1e101 m^3/s"])
def test_a_limit_beyond_what_a_case_file_holds_is_refused(limit):
    """Every quantity of a case file lies within 1e-100 .. 1e100 in SI; max_leak_rate did not, and 1e300 ml/min
    overflowed in the distribution figure (warnings on stderr, an axis of 300 decades)."""
    text = LEAKS.replace('pressure_difference = "10 kPa"', f'pressure_difference = "10 kPa"\nmax_leak_rate = "{limit}"')
    with pytest.raises(InputError, match=r"must lie within 1e-100 \.\. 1e\+100 in SI units") as exc:
        parse_uncertain_case(spread(text))
    assert exc.value.field == "conditions.max_leak_rate"


def test_samples_times_rows_are_bounded_before_any_work():
    """10 000 squeeze pressures × 8192 samples grew past 2.8 GB: each limit held, their product had none."""
    text = LEAKS.replace('squeeze_pressure = ["20 kPa", "60 kPa"]', 'squeeze_pressure = { start = "20 kPa", stop = "250 kPa", num = 2000 }')
    study = parse_uncertain_case(spread(text))
    with pytest.raises(InputError, match=r"× 2000 rows is 16384000 leak rates per array; at most 10000000") as exc:
        propagate(study, 8192, seed=0)
    assert exc.value.field == "--samples"
