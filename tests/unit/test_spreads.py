"""Hostile spreads: each refusal is one line naming the key and saying what is wrong (cases/spreads.py)."""

import math

import pytest

from sealeak.cases.uncertainty import parse_uncertain_case
from sealeak.errors import InputError
from tests.casefiles import BASE


@pytest.mark.parametrize("value", ["nan um ± 10 %", "inf um ± 10 %", "-inf um ± 10 %", "NaN ± 0.1 um"])
def test_a_value_that_is_no_finite_number_is_refused_as_such_not_as_text(value):
    with pytest.raises(InputError) as exc:
        parse_uncertain_case(BASE.replace('h_rms = "44 um"', f'h_rms = "{value}"'))
    assert exc.value.field == "surface.h_rms" and "\n" not in str(exc.value)
    assert "finite" in str(exc.value) and "is text" not in str(exc.value)


def test_a_word_with_a_spread_is_refused_as_text():
    with pytest.raises(InputError) as exc:
        parse_uncertain_case(BASE.replace('shape = "ring"', 'shape = "ring ± 1"'))
    assert exc.value.field == "seal.shape" and "is text" in str(exc.value)


@pytest.mark.parametrize("entry", ['{ distribution = ["normal"], sd = "1 %" }', '{ distribution = { a = 1 }, sd = "1 %" }'])
def test_a_distribution_that_is_no_name_is_one_line_naming_it(entry):
    with pytest.raises(InputError) as exc:
        parse_uncertain_case(BASE + f'[uncertainty]\n"surface.h_rms" = {entry}\n')
    assert exc.value.field == "uncertainty.surface.h_rms.distribution" and "normal" in exc.value.allowed


@pytest.mark.parametrize("sd", ["1e300 %", "1e308 um"])
def test_a_huge_lognormal_spread_gives_a_finite_log_sd_not_an_overflow(sd):
    """sd/median of 1e300 overflows its square; sigma = sqrt(ln(1 + r²)) is still about sqrt(2 ln r)."""
    study = parse_uncertain_case(BASE + f'[uncertainty]\n"surface.h_rms" = {{ distribution = "lognormal", sd = "{sd}" }}\n')
    inp = study.inputs[0]
    ratio = inp.parameters["sd"] / inp.parameters["median"]
    assert inp.parameters["sigma"] == pytest.approx(math.sqrt(2 * math.log(ratio)), rel=1e-6)
