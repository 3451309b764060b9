"""Hostile spreads: each refusal is one line naming the key and saying what is wrong (cases/spreads.py)."""

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
