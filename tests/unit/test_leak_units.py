"""Leak-rate units of gas leak tests and temperatures with their unit (docs/theory.md §Leak-rate units)."""

import itertools
import math

import pytest

from sealeak.errors import UnitError
from sealeak.io.units import (
    STANDARD_PRESSURE,
    STANDARD_TEMPERATURE,
    convert_leak_rate,
    leak_rate_unit,
    molar_flow_factor,
    parse_leak_rate,
    parse_quantity,
    parse_temperature,
)

R = 6.02214076e23 * 1.380649e-23  # 8.31446261815324 J/(mol K)
M_HE = 4.002602e-3
T20 = 293.15


# ---------------------------------------------------------------------- units, each against a hand-computed factor
@pytest.mark.parametrize("unit, kind, factor", [
    ("mbar*l/s", "throughput", 100 * 1e-3),              # 1 mbar = 100 Pa, 1 l = 1e-3 m³
    ("mbar l/s", "throughput", 0.1),
    ("mbar·l/s", "throughput", 0.1),
    ("mbar.l/s", "throughput", 0.1),                      # the leak-test spelling with a dot
    ("mbar*L/s", "throughput", 0.1),
    ("Pa*m^3/s", "throughput", 1.0),
    ("Pa·m³/s", "throughput", 1.0),
    ("Torr*l/s", "throughput", 101325 / 760 * 1e-3),      # 1 Torr = 101325/760 Pa
    ("atm*cc/s", "throughput", 101325 * 1e-6),
    ("sccm", "standard_volume_flow", 1e-6 / 60),          # 1 cm³/min at 0 °C and 101325 Pa
    ("SCCM", "standard_volume_flow", 1e-6 / 60),
    ("slm", "standard_volume_flow", 1e-3 / 60),
    ("mol/s", "molar_flow", 1.0),
    ("umol/s", "molar_flow", 1e-6),
    ("kg/s", "mass_flow", 1.0),
    ("g/a", "mass_flow", 1e-3 / (365.25 * 86400)),        # grams per (Julian) year, refrigerant specs
    ("ml/min", "volume_flow", 1e-6 / 60),
])
def test_leak_rate_unit_kind_and_factor(unit, kind, factor):
    k, f = leak_rate_unit("leak_rate", unit)
    assert k == kind and f == pytest.approx(factor, rel=1e-12)


def test_parse_quantity_reads_leak_test_throughputs():
    for text in ("1e-6 mbar*l/s", "1e-6 mbar l/s", "1e-6 mbar·l/s"):
        assert parse_quantity("leak_rate", text, "throughput") == pytest.approx(1e-7, rel=1e-12)


def test_helium_leak_of_one_mbar_litre_per_second_by_hand():
    """1 mbar·l/s = 0.1 Pa·m³/s; at 20 °C ṅ = 0.1/(8.31446261815324·293.15) = 0.1/2437.3847 = 4.10276e-5 mol/s;
    ṁ = ṅ·4.002602e-3 kg/mol = 1.64217e-7 kg/s."""
    n = convert_leak_rate(1.0, "mbar*l/s", "mol/s", temperature=T20, molar_mass=M_HE)
    assert n == pytest.approx(0.1 / 2437.3847, rel=1e-7)
    assert n == pytest.approx(4.10276e-5, rel=1e-5)
    assert convert_leak_rate(1.0, "mbar*l/s", "kg/s", temperature=T20, molar_mass=M_HE) == pytest.approx(1.64217e-7, rel=1e-5)


def test_sccm_by_hand():
    """1 sccm = 1e-6 m³/min at 101325 Pa, 273.15 K: ṅ = 101325·1e-6/60/(8.31446261815324·273.15)
    = 1.68875e-3/2271.0955 = 7.43583e-7 mol/s; as pV at 0 °C 1.68875e-3 Pa·m³/s = 0.0168875 mbar·l/s,
    at 20 °C the same molecules are 0.0168875·293.15/273.15 = 0.0181240 mbar·l/s."""
    assert STANDARD_TEMPERATURE == 273.15 and STANDARD_PRESSURE == 101325.0
    assert molar_flow_factor("q", "sccm", temperature=T20, molar_mass=M_HE) == pytest.approx(7.43583e-7, rel=1e-5)
    assert convert_leak_rate(1.0, "sccm", "mbar*l/s", temperature=273.15, molar_mass=M_HE) == pytest.approx(0.0168875, rel=1e-12)
    assert convert_leak_rate(1.0, "sccm", "mbar*l/s", temperature=T20, molar_mass=M_HE) == pytest.approx(0.0181240, rel=1e-5)


def test_refrigerant_grams_per_year_by_hand():
    """R134a (M = 0.102032 kg/mol), 5 g/a at 20 °C: ṁ = 5e-3/31557600 = 1.58440e-10 kg/s; ṅ = ṁ/M = 1.55285e-9 mol/s;
    Q_pV = ṅ R T = 1.55285e-9·2437.3847 = 3.78489e-6 Pa·m³/s."""
    q = convert_leak_rate(5.0, "g/a", "Pa*m^3/s", temperature=T20, molar_mass=0.102032)
    assert q == pytest.approx(3.78489e-6, rel=1e-5)


def test_volume_flow_of_a_gas_needs_its_pressure():
    """1 ml/min at 2 bar and 20 °C: ṅ = 2e5·1e-6/60/(R·293.15) = 3.33333e-3/2437.3847 = 1.36759e-6 mol/s."""
    assert molar_flow_factor("q", "ml/min", temperature=T20, molar_mass=M_HE, pressure=2e5) == pytest.approx(1.36759e-6, rel=1e-5)
    with pytest.raises(UnitError, match="pressure") as exc:
        molar_flow_factor("leak_rate unit", "ml/min", temperature=T20, molar_mass=M_HE)
    assert exc.value.field == "leak_rate unit"


UNITS = ["Pa*m^3/s", "mbar*l/s", "Torr*l/s", "sccm", "slm", "mol/s", "kg/s", "g/a", "ml/min"]


@pytest.mark.parametrize("a, b", list(itertools.combinations(UNITS, 2)))
def test_conversions_round_trip_to_1e_12(a, b):
    kw = {"temperature": 310.0, "molar_mass": 28.0134e-3, "pressure": 1.5e5}
    for value in (1e-9, 3.7e-3, 42.0):
        there = convert_leak_rate(value, a, b, **kw)
        assert convert_leak_rate(there, b, a, **kw) == pytest.approx(value, rel=1e-12)


def test_parse_leak_rate_gives_a_molar_flow():
    n = parse_leak_rate("rig.leak_rate", "1e-6 mbar.l/s", temperature=T20, molar_mass=M_HE)
    assert n == pytest.approx(1e-7 / (R * T20), rel=1e-12)
    assert parse_leak_rate("q", "2 sccm", temperature=T20, molar_mass=M_HE) == pytest.approx(2 * 7.43583e-7, rel=1e-5)


@pytest.mark.parametrize("unit", ["Pa", "m", "1/s", "mbar", "l/s/s", "", "  ", "sccm/s", "mbar*l/s,", "foo*l/s", None])
def test_a_unit_that_is_no_leak_rate_is_refused_naming_the_field(unit):
    with pytest.raises(UnitError) as exc:
        leak_rate_unit("column 'leak' unit", unit)
    assert exc.value.field == "column 'leak' unit"


@pytest.mark.parametrize("text", ["1e-6", 1e-6, "mbar*l/s", "1,5 mbar*l/s", "1e-6 Pa", "2 x sccm", "nan mbar*l/s", True])
def test_a_bad_leak_rate_is_refused_naming_the_field(text):
    with pytest.raises(UnitError) as exc:
        parse_leak_rate("spec.leak_rate", text, temperature=T20, molar_mass=M_HE)
    assert exc.value.field == "spec.leak_rate"


@pytest.mark.parametrize("field, kwargs", [("temperature", {"temperature": 0.0}), ("temperature", {"temperature": math.nan}),
                                           ("molar_mass", {"molar_mass": -1.0})])
def test_conversion_needs_a_temperature_and_molar_mass(field, kwargs):
    args = {"temperature": T20, "molar_mass": M_HE} | kwargs
    with pytest.raises(UnitError) as exc:
        convert_leak_rate(1.0, "mbar*l/s", "mol/s", **args)
    assert exc.value.field == field


# ---------------------------------------------------------------------- temperatures
@pytest.mark.parametrize("text, kelvin", [("20 degC", 293.15), ("20 °C", 293.15), ("20°C", 293.15), ("293.15 K", 293.15),
                                          ("68 degF", 293.15), ("-40 degC", 233.15), ("-40 degF", 233.15), ("1e3 K", 1000.0)])
def test_temperature_with_its_unit(text, kelvin):
    assert parse_temperature("fluid.temperature", text) == pytest.approx(kelvin, rel=1e-12)


@pytest.mark.parametrize("text, why", [("20", "no unit"), (20, "bare number"), (293.15, "bare number"), ("20 Pa", "not a temperature"),
                                       ("20 C", "degC"), ("20 m", "not a temperature"), ("-300 degC", "absolute zero"),
                                       ("0 K", "absolute zero"), ("2,5 degC", "decimal point"), ("", "temperature"),
                                       ("1/0 K", "unit"), ("nan K", "finite"), (None, "temperature")])
def test_temperature_in_the_wrong_unit_is_refused_naming_the_field(text, why):
    with pytest.raises(UnitError, match=why) as exc:
        parse_temperature("fluid.temperature", text)
    assert exc.value.field == "fluid.temperature"
