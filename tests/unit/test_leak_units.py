"""Leak-rate units of gas leak tests and temperatures with their unit (docs/theory.md §Leak-rate units)."""

import ast
import itertools
import math
from pathlib import Path

import numpy as np
import pytest

from sealeak.errors import UnitError
from sealeak.io.leak_units import (
    ATMOSPHERE,
    M3_PER_S_PER_ML_PER_MIN,
    MBAR_L_PER_PA_M3,
    ML_PER_MIN_PER_M3_PER_S,
    MOL_PER_STANDARD_M3,
    MOLAR_GAS_CONSTANT,
    PA_M3_PER_MBAR_L,
    STANDARD_PRESSURE,
    STANDARD_TEMPERATURE,
    ZERO_CELSIUS,
    celsius,
    convert_leak_rate,
    leak_rate_unit,
    molar_flow_factor,
    parse_leak_rate,
    pv_throughput,
    to_mbar_l_per_s,
    to_ml_per_min,
    to_sccm,
)
from sealeak.io.units import parse_quantity, parse_temperature, registry

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
    assert k == kind and f == pytest.approx(factor, rel=1e-12, abs=0)


def test_parse_quantity_reads_leak_test_throughputs():
    for text in ("1e-6 mbar*l/s", "1e-6 mbar l/s", "1e-6 mbar·l/s"):
        assert parse_quantity("leak_rate", text, "throughput") == pytest.approx(1e-7, rel=1e-12, abs=0)


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
    assert convert_leak_rate(1.0, "sccm", "mbar*l/s", temperature=273.15, molar_mass=M_HE) == pytest.approx(0.0168875, rel=1e-12, abs=0)
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
        assert convert_leak_rate(there, b, a, **kw) == pytest.approx(value, rel=1e-12, abs=0)


def test_parse_leak_rate_gives_a_molar_flow():
    n = parse_leak_rate("rig.leak_rate", "1e-6 mbar.l/s", temperature=T20, molar_mass=M_HE)
    assert n == pytest.approx(1e-7 / (R * T20), rel=1e-12, abs=0)
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


# ---------------------------------------------------------------------- the one leak-rate unit module
def test_named_factors_agree_with_pint():
    """The factors front ends print with, against pint's own conversion (an independent path)."""
    q = registry().Quantity
    assert M3_PER_S_PER_ML_PER_MIN == pytest.approx(q(1.0, "ml/min").to("m**3/s").magnitude, rel=1e-14, abs=0)
    assert ML_PER_MIN_PER_M3_PER_S == pytest.approx(q(1.0, "m**3/s").to("ml/min").magnitude, rel=1e-14)
    assert PA_M3_PER_MBAR_L == pytest.approx(q(1.0, "mbar*l/s").to("Pa*m**3/s").magnitude, rel=1e-14, abs=0)
    assert MBAR_L_PER_PA_M3 == pytest.approx(q(1.0, "Pa*m**3/s").to("mbar*l/s").magnitude, rel=1e-14, abs=0)
    assert ATMOSPHERE == pytest.approx(q(1.0, "atm").to("Pa").magnitude, rel=1e-14)
    assert ZERO_CELSIUS == pytest.approx(q(0.0, "degC").to("K").magnitude, rel=1e-14)


def test_constants_are_the_si_definitions():
    """R = N_A k_B exactly (2019 SI), 0 °C = 273.15 K, 1 atm = 101325 Pa: the standard conditions of sccm."""
    assert MOLAR_GAS_CONSTANT == pytest.approx(6.02214076e23 * 1.380649e-23, rel=1e-15, abs=0)
    assert (STANDARD_TEMPERATURE, STANDARD_PRESSURE) == (ZERO_CELSIUS, ATMOSPHERE)
    assert MOL_PER_STANDARD_M3 == pytest.approx(101325.0 / (8.31446261815324 * 273.15), rel=1e-14, abs=0)  # 44.6150 mol/m³
    assert MOL_PER_STANDARD_M3 == pytest.approx(44.6150, rel=1e-5)


def test_display_conversions_by_hand():
    assert to_ml_per_min(1e-6 / 60) == pytest.approx(1.0, rel=1e-14, abs=0)
    assert to_mbar_l_per_s(0.1) == pytest.approx(1.0, rel=1e-14, abs=0)
    assert to_sccm(7.43583e-7) == pytest.approx(1.0, rel=1e-5)       # test_sccm_by_hand
    assert celsius(293.15) == pytest.approx(20.0, rel=1e-12)
    assert np.allclose(to_mbar_l_per_s(np.array([0.1, 1.0])), [1.0, 10.0], rtol=1e-14)


@pytest.mark.parametrize("unit", ["Pa*m^3/s", "mbar*l/s", "sccm", "slm", "mol/s", "kg/s", "g/a", "ml/min"])
def test_pv_throughput_of_every_kind_is_the_converted_leak_rate(unit):
    """pv_throughput (a data file's leak rates in their kind's SI unit → Pa·m³/s) against convert_leak_rate."""
    kw = {"temperature": 310.0, "molar_mass": 28.0134e-3, "pressure": 1.5e5}
    kind, factor = leak_rate_unit("leak_rate", unit)
    values = np.array([1e-9, 3.7e-3, 42.0])
    expected = [convert_leak_rate(v, unit, "Pa*m^3/s", **kw) for v in values]
    assert np.allclose(pv_throughput(values * factor, kind, **kw), expected, rtol=1e-12, atol=0)




def test_no_module_but_the_unit_module_writes_the_unit_constants():
    """273.15, 101325, R and ml/min per m³/s live in sealeak.io.leak_units alone (docstrings and comments aside)."""
    src = Path(__file__).resolve().parents[2] / "src" / "sealeak"
    banned = {273.15, 101325.0, 6e7, 6.02214076e23, 8.31446261815324, 8.314}
    found = []
    for path in sorted(src.rglob("*.py")):
        rel = path.relative_to(src).as_posix()
        if rel == "io/leak_units.py":
            continue
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.Constant) and type(node.value) in (int, float) and float(node.value) in banned:
                found.append(f"{rel}:{node.lineno}: {node.value!r}")
    assert not found, found
