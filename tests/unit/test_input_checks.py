"""The shared checks of numeric arguments (sealeak.errors, sealeak.io.units): one line naming the field and what is allowed."""

from __future__ import annotations

import math

import numpy as np
import pytest

from sealeak.errors import InputError, positive_number, positive_values
from sealeak.io.units import is_number
from sealeak.lab.pressure_decay import PressureDecaySetup
from sealeak.numerics import solve_flow


@pytest.mark.parametrize("value", [0.0, -1.0, math.inf, math.nan])
def test_a_number_not_above_zero_is_refused_with_its_field(value):
    with pytest.raises(InputError, match=r"^volume = .*: must be finite and > 0$"):
        positive_number("volume", value)


def test_zero_passes_where_allowed_and_text_is_not_a_number():
    assert positive_number("outside_pressure", 0, allow_zero=True) == 0.0
    with pytest.raises(InputError, match="must be finite and >= 0"):
        positive_number("outside_pressure", -1, allow_zero=True)
    with pytest.raises(InputError, match="must be a number"):
        positive_number("volume", "a litre")


def test_an_upper_bound_is_named_in_the_message():
    assert positive_number("final_height", 0.2, below=(0.3, "the initial height 0.3 m")) == 0.2
    with pytest.raises(InputError, match="final_height = 0.3: must be below the initial height 0.3 m"):
        positive_number("final_height", 0.3, below=(0.3, "the initial height 0.3 m"))
    with pytest.raises(InputError, match="pressure_loss .*must be below the initial pressure difference"):
        PressureDecaySetup(volume=1e-3, initial_pressure=2e5, outside_pressure=1e5, temperature=293.15,
                           pressure_loss=1e5)


def test_solver_arguments_must_be_numbers_not_text():
    positive_values(("size", np.float32(1e-3), "a length > 0 (m)"), ("grid", np.int64(4), "a count > 0"))
    with pytest.raises(InputError, match=r"^size = .*must be finite, a length > 0 \(m\)$"):
        positive_values(("size", "1e-3", "a length > 0 (m)"))
    with pytest.raises(InputError, match=r"^viscosity = .*must be finite, a viscosity"):
        solve_flow(np.ones((8, 8)) * 1e-6, 1e-3, -1.0, 1e5)


@pytest.mark.parametrize(("text", "parse", "expected"), [("2.5", float, True), ("2,5", float, False),
                                                         ("1e400", float, True), ("abc", float, False)])
def test_is_number_asks_the_parser_it_is_given(text, parse, expected):
    assert is_number(text, parse) is expected


def test_is_number_by_default_reads_as_the_data_files_do():
    assert is_number("1e-3") and not is_number("2,5") and not is_number("1e400")  # too large for a float
