"""A gas permeability written as published (Barrer, mol/(m·s·Pa)) becomes the pV form P = Π R T (docs/case-files.md)."""

import pytest

from sealeak.errors import UnitError
from sealeak.io.leak_units import parse_permeability

FIELD = "rubber.permeability"
R = 8.314462618  # J/(mol·K)
# 1 Barrer = 1e-10 cm³(STP)·cm/(cm²·s·cmHg), by hand: 1 cm³(STP) = 101325 Pa · 1e-6 m³/(R · 273.15 K) mol,
# 1 cmHg = 0.01 m · 13595.1 kg/m³ · 9.80665 m/s² (conventional mercury), cm = 0.01 m, cm² = 1e-4 m².
MOL_PER_CC_STP = 101325 * 1e-6 / (R * 273.15)
CMHG = 0.01 * 13595.1 * 9.80665
BARRER = 1e-10 * MOL_PER_CC_STP * 0.01 / (1e-4 * CMHG)  # mol/(m·s·Pa)


def test_barrer_is_the_published_molar_value():
    assert BARRER == pytest.approx(3.35e-16, rel=2e-3, abs=0)  # the figure usually quoted (e.g. docs/case-files.md)


@pytest.mark.parametrize("t", [273.15, 293.15, 298.15, 353.15])
def test_barrer_becomes_the_pv_throughput_of_the_moles_at_the_gas_temperature(t):
    assert parse_permeability(FIELD, "1 barrer", temperature=t) == pytest.approx(BARRER * R * t, rel=1e-6, abs=0)
    assert parse_permeability(FIELD, "2.5 Barrer", temperature=t) == pytest.approx(2.5 * BARRER * R * t, rel=1e-6, abs=0)


def test_one_barrer_at_0_degc_is_7_6e_13_m2_per_s():
    assert parse_permeability(FIELD, "1 barrer", temperature=273.15) == pytest.approx(7.60e-13, rel=1e-3, abs=0)


@pytest.mark.parametrize("text", ["{x} mol/(m*s*Pa)", "{x} mol*m/(m^2*s*Pa)", "{y} mmol/(m*s*kPa)"])
def test_molar_form_agrees_with_barrer(text):
    x = 3 * BARRER
    value = text.format(x=x, y=x * 1e6)  # 1 mmol/(m·s·kPa) = 1e-6 mol/(m·s·Pa)
    assert parse_permeability(FIELD, value, temperature=300.0) == pytest.approx(
        parse_permeability(FIELD, "3 barrer", temperature=300.0), rel=1e-6, abs=0)


def test_pv_form_is_taken_as_written_and_published_forms_scale_with_temperature():
    for t in (250.0, 400.0):
        assert parse_permeability(FIELD, "2e-12 m^2/s", temperature=t) == pytest.approx(2e-12, rel=1e-12, abs=0)
        assert parse_permeability(FIELD, "2e-8 cm^2/s", temperature=t) == pytest.approx(2e-12, rel=1e-12, abs=0)
    cold, hot = (parse_permeability(FIELD, "1e-16 mol/(m*s*Pa)", temperature=t) for t in (250.0, 400.0))
    assert hot / cold == pytest.approx(400.0 / 250.0, rel=1e-12)


@pytest.mark.parametrize("value, words", [
    ("1e-12 Pa", "area per time"),
    (1e-12, "bare number"),
    ("barrer", "no number"),
    ("1e400 barrer", "too large"),
    ("1,5 barrer", "decimal point"),
    ("3 barrers", "barrer"),
])
def test_bad_permeabilities_name_the_field_and_the_forms(value, words):
    with pytest.raises(UnitError) as err:
        parse_permeability(FIELD, value, temperature=293.15)
    text = str(err.value)
    assert FIELD in text and words in text and "barrer" in text.lower() and "\n" not in text, text


def test_temperature_must_be_absolute():
    with pytest.raises(UnitError, match="temperature"):
        parse_permeability(FIELD, "1 barrer", temperature=0.0)
