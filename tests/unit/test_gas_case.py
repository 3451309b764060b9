"""Gas and named-fluid case files (issue 13): what a case holds, and that old liquid cases need no property library."""

import subprocess
import sys

import pytest

from sealeak.cases.loader import parse_cases
from sealeak.cases.run import run_case
from sealeak.physics.properties import fluid_state
from sealeak.render.notes import worded
from tests.casefiles import edit

ABSOLUTE = 'upstream_pressure = "3 bar"\ndownstream_pressure = "1 bar"'


@pytest.mark.parametrize("fluid", ['viscosity = "1 mPa*s"', 'name = "oil"\nviscosity = "30 mPa*s"',
                                   'name = "water"\nviscosity = "1 mPa*s"', 'name = "my coolant"\nviscosity = "2 mPa*s"'])
def test_a_liquid_with_its_viscosity_does_not_import_the_property_library(fluid):
    text = edit('viscosity = "1 mPa*s"', fluid)
    code = ("import sys; from sealeak.cases.loader import parse_cases; from sealeak.cases.run import run_case; "
            f"c = parse_cases({text!r})[0]; run_case(c); "
            "print(c.gas is None, c.fluid_state is None, 'CoolProp' in sys.modules)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout.split()
    assert out == ["True", "True", "False"]


@pytest.mark.parametrize("name, canonical", [("helium", "helium"), ("He", "helium"), ("n2", "nitrogen"),
                                             ("CO2", "carbon dioxide"), ("R-134a", "R134a")])
def test_a_named_gas_takes_the_library_properties_at_the_case_temperature(name, canonical):
    text = edit('viscosity = "1 mPa*s"', f'name = "{name}"\ntemperature = "40 degC"',
                edit('pressure_difference = "10 kPa"', ABSOLUTE))
    case = parse_cases(text)[0]
    state = fluid_state(canonical, 313.15, 3e5)
    assert case.gas is not None and case.gas.gas.name == canonical
    assert case.gas.temperature == pytest.approx(313.15, rel=1e-12)
    assert case.fluid.viscosity == pytest.approx(state.viscosity, rel=1e-12, abs=0)
    assert case.gas.gas.molar_mass == pytest.approx(state.molar_mass, rel=1e-12, abs=0)
    assert case.pressure_difference == pytest.approx(2e5, rel=1e-12)
    assert case.helium_equivalent


def test_a_given_viscosity_overrides_the_library_for_a_gas():
    text = edit('viscosity = "1 mPa*s"', 'name = "air"\nviscosity = "20 uPa*s"', edit('pressure_difference = "10 kPa"', ABSOLUTE))
    case = parse_cases(text)[0]
    assert case.gas is not None and case.gas.gas.viscosity == pytest.approx(20e-6, rel=1e-12, abs=0)


def test_default_temperature_is_20_degC_and_matching_pressure_difference_is_accepted():
    text = edit('viscosity = "1 mPa*s"', 'name = "argon"', edit('pressure_difference = "10 kPa"', ABSOLUTE + '\npressure_difference = "2 bar"'))
    case = parse_cases(text)[0]
    assert case.temperature == pytest.approx(293.15) and case.absolute_pressures == (3e5, 1e5)


def test_a_named_liquid_with_absolute_pressures_takes_library_viscosity_and_density():
    text = edit('viscosity = "1 mPa*s"', 'name = "water"\ntemperature = "60 degC"', edit('pressure_difference = "10 kPa"', ABSOLUTE))
    case = parse_cases(text)[0]
    state = fluid_state("water", 333.15, 3e5)
    assert case.gas is None and case.fluid_state is not None and case.fluid_state.phase == "liquid"
    assert case.fluid.viscosity == pytest.approx(state.viscosity, rel=1e-12, abs=0)
    assert case.fluid.density == pytest.approx(state.density, rel=1e-12)
    assert case.fluid.viscosity < 0.6e-3  # water at 60 °C is about half as viscous as at 20 °C
    assert not case.input_warnings


@pytest.mark.parametrize("coupled, model", [(True, "critical-junction"), (False, "critical-junction"),
                                            (True, "effective-medium")])
def test_a_helium_test_that_opens_the_seal_is_noted_at_its_rows(coupled, model):
    """He-eq is helium at 1 bar against vacuum: where P0 <= 100 kPa that ΔP reaches the contact pressure and the test
    lifts the seal (docs/theory.md §13.4); those rows' He-eq (a limit, or a contact the gas does not touch) were shown
    without a word."""
    text = edit('squeeze_pressure = ["20 kPa", "60 kPa", "0.1 MPa"]', 'squeeze_pressure = ["60 kPa", "99.9 kPa", "100.1 kPa", "200 kPa"]',
                edit('viscosity = "1 mPa*s"', 'name = "air"', edit('pressure_difference = "10 kPa"',
                                                                   'upstream_pressure = "1.1 bar"\ndownstream_pressure = "1 bar"\n'
                                                                   'helium_equivalent = true')))
    if not coupled:
        text = edit("[theory]", '[theory]\nfluid_pressure = "ignored"', text)
    text = edit("[theory]", f'[theory]\nmodel = "{model}"', text)
    result = run_case(parse_cases(text)[0])
    notes = [n for n in worded(result.messages) if n.startswith("He-eq at")]
    shown = result.critical_junction if model == "critical-junction" else result.effective_medium  # (its notes printed)
    assert notes == [n for n in worded(shown.messages) if n.startswith("He-eq at")]
    (note,) = notes
    assert note.startswith("He-eq at P0 = 60, 99.9 kPa: the helium test's ΔP = 100 kPa")  # not 100.1 or 200 kPa
    assert ("a lower bound" in note) == coupled and ("ignored" in note) == (not coupled)
    quiet = run_case(parse_cases(text.replace('"60 kPa", "99.9 kPa", ', ""))[0])
    assert not [n for n in worded(quiet.messages) if n.startswith("He-eq at")]
