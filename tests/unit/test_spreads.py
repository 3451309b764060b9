"""Hostile spreads: each refusal is one line naming the key and saying what is wrong (cases/spreads.py)."""

import math

import numpy as np
import pytest

from sealeak.cases import parse_case_file
from sealeak.cases.uncertainty import parse_uncertain_case
from sealeak.errors import InputError
from sealeak.io.leak_units import parse_permeability
from tests.casefiles import BASE, ORING


@pytest.mark.parametrize("value", ["nan um ± 10 %", "inf um ± 10 %", "-inf um ± 10 %", "NaN ± 0.1 um"])
def test_a_value_that_is_no_finite_number_is_refused_as_such_not_as_text(value):
    with pytest.raises(InputError) as exc:
        parse_uncertain_case(BASE.replace('h_rms = "44 um"', f'h_rms = "{value}"'))
    assert exc.value.field == "surface.h_rms" and "\n" not in str(exc.value)
    assert "finite" in str(exc.value) and "is text" not in str(exc.value)


def test_a_word_with_a_spread_is_refused_as_text():
    """A choice is text as written: "ring ± 1" is no shape (a spread needs a number where a key takes one)."""
    with pytest.raises(InputError) as exc:
        parse_uncertain_case(BASE.replace('shape = "ring"', 'shape = "ring ± 1"'))
    assert exc.value.field == "seal.shape" and "allowed: 'ring', 'rectangle', 'o-ring'" in str(exc.value)
    with pytest.raises(InputError) as exc:
        parse_uncertain_case(BASE.replace("hurst = 0.8", 'hurst = "high ± 1"'))
    assert exc.value.field == "surface.hurst" and "is text" in str(exc.value)


@pytest.mark.parametrize("entry", ['{ distribution = ["normal"], sd = "1 %" }', '{ distribution = { a = 1 }, sd = "1 %" }'])
def test_a_distribution_that_is_no_name_is_one_line_naming_it(entry):
    with pytest.raises(InputError) as exc:
        parse_uncertain_case(BASE + f'[uncertainty]\n"surface.h_rms" = {entry}\n')
    assert exc.value.field == "uncertainty.surface.h_rms.distribution" and "normal" in exc.value.allowed


@pytest.mark.parametrize("sd", ["1e300 %", "1e308 um"])
def test_a_huge_lognormal_spread_gives_a_finite_log_sd_not_an_overflow(sd):
    """sd/median of 1e300 overflows its square; σ² = ln x with x(x − 1) = r² is still about ln r."""
    # (the spread itself, as read: a case file with it is refused, its ends being no h_rms)
    inp = parse_case_file(BASE + f'[uncertainty]\n"surface.h_rms" = {{ distribution = "lognormal", sd = "{sd}" }}\n').spreads.inputs[0]
    ratio = inp.parameters["sd"] / inp.parameters["median"]
    assert inp.parameters["sigma"] == pytest.approx(math.sqrt(math.log(ratio)), rel=1e-6)


@pytest.mark.parametrize("sd", ["1 %", "25 %", "100 %", "300 %", "5 um"])
def test_a_lognormal_spread_is_the_standard_deviation_of_the_value_around_its_median(sd):
    """The value written is the median m and ``sd`` the standard deviation of the sampled values: a lognormal's is
    m e^(σ²/2) √(e^(σ²) − 1) (its mean m e^(σ²/2) times the coefficient of variation), checked in closed form and
    for a small spread against the spread of the values at evenly spaced probabilities."""
    study = parse_uncertain_case(BASE + f'[uncertainty]\n"surface.h_rms" = {{ distribution = "lognormal", sd = "{sd}" }}\n')
    inp = study.inputs[0]
    m, sigma, want = inp.parameters["median"], inp.parameters["sigma"], inp.parameters["sd"]
    assert m * math.exp(sigma**2 / 2) * math.sqrt(math.expm1(sigma**2)) == pytest.approx(want, rel=1e-12, abs=0)
    u = (np.arange(200_000) + 0.5) / 200_000  # the distribution's values (in SI) at evenly spaced probabilities
    x = inp.ppf(u)
    assert np.median(x) == pytest.approx(44e-6, rel=1e-4, abs=0)  # the value written
    if sigma < 0.3:  # the samples' z is cut at ±3 (TRUNCATION): 1.3 % less spread for a small σ, more for a wide one
        assert np.std(x) / np.median(x) == pytest.approx(want / m, rel=3e-2, abs=0)


#: A gas case (a flat seal of height 2 mm, helium against vacuum) whose rubber has a permeability in Barrer.
PERMEATION = BASE.replace("poisson_ratio = 0.5", 'poisson_ratio = 0.5\npermeability = "3 barrer"').replace(
    'outer_diameter = "4 cm"', 'outer_diameter = "4 cm"\nheight = "2 mm"').replace(
    'viscosity = "1 mPa*s"', 'name = "helium"\ntemperature = "20 degC"').replace(
    'pressure_difference = "10 kPa"', 'upstream_pressure = "1 bar"\ndownstream_pressure = "0 Pa"')


@pytest.mark.parametrize("written", ["3 barrer ± 10 %", "3 Barrer ± 0.3 barrer", "3 barrer ± 1.0039e-16 mol/(m*s*Pa)"])
def test_a_permeability_in_barrer_takes_a_spread(written):
    """Barrer is no pint unit: the spread is carried in mol/(m·s·Pa), the same permeability (1 Barrer = 3.346e-16)."""
    study = parse_uncertain_case(PERMEATION.replace('permeability = "3 barrer"', f'permeability = "{written}"'))
    inp = study.inputs[0]
    assert inp.key == "rubber.permeability" and written in inp.label
    median, upper = (parse_permeability("p", w, temperature=293.15) for w in inp.written(np.array([0.5, 0.8413])))
    nominal = parse_permeability("p", "3 barrer", temperature=293.15)
    assert median == pytest.approx(nominal, rel=1e-12, abs=0)
    assert upper == pytest.approx(1.1 * nominal, rel=1e-3, abs=0)  # one standard deviation (10 %) above


@pytest.mark.parametrize("written", ["44 um ± 10", "44 um ± 3 s", "44 um +/- 10 kelvin"])
def test_a_spread_in_the_wrong_unit_is_refused_quoting_what_was_written(written):
    with pytest.raises(InputError) as exc:
        parse_uncertain_case(BASE.replace('h_rms = "44 um"', f'h_rms = "{written}"'))
    assert exc.value.field == "surface.h_rms" and exc.value.value == written.replace("+/-", "±") and "\n" not in str(exc.value)
    assert "does not convert to the value's unit 'um'" in str(exc.value)


def test_a_plus_minus_in_text_is_no_spread():
    """A rubber named "PDMS 2.3 ± 0.2 MPa batch" made every command refuse the case (a spread needs a number), and a
    label "5 ± 0.1" was sampled as a number; names, labels, files and choices are text as written."""
    text = (BASE.replace('youngs_modulus = "2.3 MPa"', 'name = "PDMS 2.3 ± 0.2 MPa batch"\nyoungs_modulus = "2.3 MPa"')
            .replace('model = "self-affine"', 'model = "self-affine"\nlabel = "5 ± 0.1"'))
    assert "± 0.2 MPa batch" in text and 'label = "5 ± 0.1"' in text
    case_file = parse_case_file(text)
    assert not case_file.spreads.inputs
    assert case_file.document["rubber"]["name"] == "PDMS 2.3 ± 0.2 MPa batch"
    assert case_file.document["surface"]["label"] == "5 ± 0.1"
    spread = parse_case_file(text.replace('h_rms = "44 um"', 'h_rms = "44 um ± 10 %"'))  # a quantity's still is
    assert [i.key for i in spread.spreads.inputs] == ["surface.h_rms"]


@pytest.mark.parametrize("where", ["inline", "table"])
def test_the_specification_takes_no_spread(where):
    """max_leak_rate with a spread was refused as an unknown key of [conditions] (whose list of keys left it out), and
    in [uncertainty] as naming no case-file key."""
    spec = 'max_leak_rate = "1 ml/min ± 10 %"' if where == "inline" else 'max_leak_rate = "1 ml/min"'
    text = BASE.replace('pressure_difference = "10 kPa"', f'pressure_difference = "10 kPa"\n{spec}')
    if where == "table":
        text += '[uncertainty]\n"conditions.max_leak_rate" = { distribution = "normal", sd = "10 %" }\n'
    with pytest.raises(InputError, match="is the specification the samples are compared with: it takes no spread") as exc:
        parse_uncertain_case(text)
    assert exc.value.field == ("conditions.max_leak_rate" if where == "inline" else "uncertainty.conditions.max_leak_rate")


def test_a_choice_of_theory_is_between_single_theories():
    """["critical-junction", "both"] gave three equal percentiles (both's rows show the critical junction) without a word."""
    text = (BASE.replace("[theory]", '[theory]\nmodel = "critical-junction"')
            + '[uncertainty]\n"theory.model" = { distribution = "choice", values = ["critical-junction", "both"] }\n')
    with pytest.raises(InputError, match="choose between single theories") as exc:
        parse_uncertain_case(text)
    assert exc.value.field == "uncertainty.theory.model.values"
    fine = parse_uncertain_case(text.replace('"both"', '"effective-medium"'))
    assert fine.inputs[0].choices == ("critical-junction", "effective-medium")


@pytest.mark.parametrize("written", ['"1.2 ± 10 %"', '"1.2"', '"120 %"'])
def test_an_o_ring_force_factor_takes_a_spread_and_a_number_written_as_text(written):
    """force_factor = "1.2 ± 10 %" was refused as 'must be a number from 0.001 to 1000' (1.2 is), as was "1.2"."""
    text = ORING.replace('inner_diameter = "20 mm"', f'inner_diameter = "20 mm"\nforce_factor = {written}')
    study = parse_uncertain_case(text)
    (case,) = study.cases
    plain = parse_uncertain_case(ORING.replace('inner_diameter = "20 mm"', 'inner_diameter = "20 mm"\nforce_factor = 1.2'))
    assert case.band.profiles[0].force_per_length == pytest.approx(plain.cases[0].band.profiles[0].force_per_length,
                                                                    rel=1e-12, abs=0)
    assert [i.key for i in study.inputs] == (["seal.force_factor"] if "±" in written else [])


@pytest.mark.parametrize("written, refused", [('"20 degC ± 7 K"', False), ('"0 degC ± 5 K"', False),
                                              ('"293.15 K ± 10 %"', False), ('"20 degC ± 10 %"', True),
                                              ('"0 degC ± 10 %"', True), ('"20 degC ± 200 K"', True)])
def test_a_temperature_in_celsius_is_spread_on_the_absolute_scale(written, refused):
    """20 °C ± 7 K was refused as 'above 1/3 of the value (20 degC)' while 293.15 K ± 7 K ran, and '± 10 %' of a value
    in °C was 10 % of the number in °C (0 at 0 °C, 2 K at 20 °C against 29 K for 293.15 K)."""
    text = BASE.replace('viscosity = "1 mPa*s"', f'viscosity = "1 mPa*s"\ntemperature = {written}')
    if not refused:
        (inp,) = parse_uncertain_case(text).inputs
        assert inp.key == "fluid.temperature" and inp.parameters["sd"] > 0
        return
    with pytest.raises(InputError) as exc:
        parse_uncertain_case(text)
    assert exc.value.field == "fluid.temperature"
    assert ("arbitrary zero" in str(exc.value)) == ("%" in written), str(exc.value)


def test_a_plus_minus_in_a_list_of_text_is_no_spread_and_an_end_on_an_open_bound_builds():
    """Study labels "40 ± 2 um" were refused as a spread on a list item; a uniform h_rms from 0 (an end no sample
    reaches, on the open bound h_rms > 0) was refused by the check of the spread's ends."""
    study = BASE.replace('h_rms = "44 um"', 'h_rms = "44 um"') + (
        '[study]\nvary = "surface.h_rms"\nvalues = ["40 um", "44 um"]\nlabels = ["40 ± 2 um", "44 ± 2 um"]\n')
    assert parse_case_file(study).document["study"]["labels"] == ["40 ± 2 um", "44 ± 2 um"]
    uniform = BASE + '[uncertainty]\n"surface.h_rms" = { distribution = "uniform", low = "0 um", high = "50 um" }\n'
    (inp,) = parse_uncertain_case(uniform).inputs
    assert inp.parameters["low"] == 0.0


def test_a_temperature_in_fahrenheit_is_spread_in_kelvin_against_the_absolute_temperature():
    """68 °F ± 100 °F (± 55.6 K around 293 K) was refused: °F degrees were compared with kelvin."""
    text = BASE.replace('viscosity = "1 mPa*s"', 'viscosity = "1 mPa*s"\ntemperature = "68 degF ± 100 degF"')
    (inp,) = parse_uncertain_case(text).inputs
    assert inp.key == "fluid.temperature"
    with pytest.raises(InputError, match=r"below 1/3 of the value \(293\.15 K\)"):
        parse_uncertain_case(text.replace("± 100 degF", "± 200 degF"))


@pytest.mark.parametrize(("written", "sd"), [("20 degC ± 5 delta_degC", 5.0), ("20 degC ± 9 delta_degF", 5.0),
                                             ("68 degF ± 9 delta_degF", 9.0), ("20 degC ± 5 K", 5.0)])
def test_a_temperature_spread_in_a_difference_unit_is_read_as_the_difference_it_is(written, sd):
    """"± 5 delta_degC" (pint's name for a temperature difference in °C) was refused as not converting to °C, while
    "± 5 degC" and "± 5 K" were read as differences; 9 °F of difference are 5 K."""
    text = BASE.replace('viscosity = "1 mPa*s"', f'viscosity = "1 mPa*s"\ntemperature = "{written}"')
    (inp,) = parse_uncertain_case(text).inputs
    assert inp.key == "fluid.temperature"
    assert inp.parameters["sd"] == pytest.approx(sd, rel=1e-12, abs=0.0)
