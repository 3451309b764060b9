"""One quantity parser for everything a user types: what it reads, what it refuses, and that it never crashes.

The expected SI values are the units' definitions (1 µm = 1e-6 m, 1 cP = 1 mPa·s, 1 l = 1e-3 m³, ...),
not numbers taken from the parser.
"""

import math
from datetime import timedelta

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from sealeak.errors import FileFormatError, UnitError
from sealeak.io.leak_units import ATMOSPHERE, leak_rate_factor
from sealeak.io.tables import read_spectrum_table, read_unit_table
from sealeak.io.units import (
    DIMENSIONS,
    SI_RANGE,
    comma_advice,
    parse_number,
    parse_quantity,
    split_quantities,
    unit_dimension,
    unit_factor,
)
from sealeak.lab.data import read_leak_data

FIELD = "rubber.youngs_modulus"


# ------------------------------------------------------------------------------------------ what is read
@pytest.mark.parametrize("text, dimension, si", [
    ("44 um", "length", 44e-6),
    ("44 µm", "length", 44e-6),  # micro sign
    ("44 μm", "length", 44e-6),  # Greek mu
    ("0.044 mm", "length", 44e-6),
    ("3 Å", "length", 3e-10),
    ("2.3 MPa", "pressure", 2.3e6),
    ("2300 kPa", "pressure", 2.3e6),
    ("2.3MPa", "pressure", 2.3e6),
    ("2.3e6 Pa", "pressure", 2.3e6),
    (".5 MPa", "pressure", 5e5),
    ("5. kPa", "pressure", 5e3),
    ("-1 MPa", "pressure", -1e6),  # the sign is kept; ranges are the caller's business
    ("2.3 N/mm^2", "pressure", 2.3e6),
    ("2.3 N/mm²", "pressure", 2.3e6),
    ("2 kg/(m*s^2)", "pressure", 2.0),
    ("2 kg m^-1 s⁻²", "pressure", 2.0),
    ("60\u00a0kPa", "pressure", 6e4),  # a non-breaking space
    ("2 bar", "pressure", 2e5),
    ("1 mPa*s", "viscosity", 1e-3),
    ("1 mPa·s", "viscosity", 1e-3),
    ("1 mPa s", "viscosity", 1e-3),
    ("1 cP", "viscosity", 1e-3),
    ("9.1e3 1/m", "wavevector", 9.1e3),
    ("1 1/um", "wavevector", 1e6),
    ("1 m^-1", "wavevector", 1.0),
    ("1e-20 m^4", "psd", 1e-20),
    ("1 um^4", "psd", 1e-24),
    ("1000 kg/m^3", "density", 1000.0),
    ("1 g/cm^3", "density", 1000.0),
    ("1 ml/min", "volume_flow", 1e-6 / 60),
    ("9.81 m/s^2", "acceleration", 9.81),
    ("5 min", "time", 300.0),
    ("0.5", "dimensionless", 0.5),
    ("50 %", "dimensionless", 0.5),
])
def test_quantities_people_write_are_read_in_si(text, dimension, si):
    assert parse_quantity(FIELD, text, dimension) == pytest.approx(si, rel=1e-12, abs=0)


@pytest.mark.parametrize("unit, dimension, si", [
    ("kPa", "pressure", 1e3), ("1/um", "wavevector", 1e6), ("1 / um", "wavevector", 1e6), ("um^4", "psd", 1e-24),
    ("0.5 um", "length", 0.5e-6), ("ml/min", "volume_flow", 1e-6 / 60), ("", "dimensionless", 1.0),
])
def test_units_of_table_columns(unit, dimension, si):
    assert unit_factor("column 'x' unit", unit, dimension) == pytest.approx(si, rel=1e-12, abs=0)


def test_leak_test_throughputs_become_volume_flows_at_the_reference_pressure():
    # 1 mbar·l/s = 100 Pa × 1e-3 m³ / s = 0.1 Pa·m³/s; at 1 atm that is 0.1/101325 m³/s
    assert leak_rate_factor("mbar*l/s") == pytest.approx(0.1 / ATMOSPHERE, rel=1e-12, abs=0)
    assert leak_rate_factor("Pa*m^3/s", reference_pressure=2e5) == pytest.approx(1 / 2e5, rel=1e-12, abs=0)
    assert leak_rate_factor("ml/min") == pytest.approx(1e-6 / 60, rel=1e-12, abs=0)
    assert unit_dimension("q", "mbar*l/s", ("volume_flow", "throughput"))[0] == "throughput"


# ------------------------------------------------------------------------------------------ what is refused
REFUSED = [
    "1/0 MPa", "(2 MPa", "2 MPa)", "2 MPa(", "1e999999 Pa", "1e-999999 Pa", "2**1000**1000 Pa", "2**1000 Pa",
    "3 MPa + 2 kPa", "3 MPa - 2 kPa", "2*MPa", "2 MPa*3", "2 3 MPa", "1 000 Pa", "pi MPa", "e MPa", "MPa",
    "--5 Pa", "+-5 Pa", "nan Pa", "NaN MPa", "inf Pa", "-inf Pa", "infinity Pa", "1_000 Pa", "0x10 Pa", "½ MPa",
    "١ MPa", "２ MPa", "2 Pa^99999", "2 Pa^2^3", "2 ((((Pa))))", "2 Pa^", "2 Pa/", "2 /Pa", "1 MPa MPa",
    "5 %", "1e3", "", "  ", "\n", "1 mPa*s", "2 kpa", "1e300 GPa", "1 degC", "1.2.3 MPa", "1e3e4 Pa",
    "2 MPa # comment", "2 [MPa]", "2 MPa;", "__import__('os') Pa", "2 Pa" + " " * 300 + "Pa",
    "2 " + "(" * 2000 + "Pa" + ")" * 2000,
]


@pytest.mark.parametrize("text", REFUSED)
def test_anything_but_one_number_and_a_unit_is_refused_naming_the_field(text):
    with pytest.raises(UnitError) as err:
        parse_quantity(FIELD, text, "pressure")
    assert err.value.field == FIELD and err.value.value == text
    message = str(err.value)
    assert message.startswith(f"{FIELD} = ") and "\n" not in message.strip()


@pytest.mark.parametrize("value", [True, None, [], {}, ["2 MPa"], float("nan"), float("inf"), 10 ** 400, 2.3])
def test_values_that_are_not_strings(value):
    with pytest.raises(UnitError):
        parse_quantity(FIELD, value, "pressure")
    if not isinstance(value, (bool, type(None), list, dict)) and value != 2.3:
        with pytest.raises(UnitError):  # not finite (or not representable) even where a bare number is allowed
            parse_quantity("theory.alpha", value, "dimensionless")


@pytest.mark.parametrize("text, says", [
    ("1/0 MPa", "arithmetic is not evaluated"),
    ("3 MPa + 2 kPa", "arithmetic is not evaluated"),
    ("MPa", "no number"),
    ("nan Pa", "not a finite number"),
    ("1e999999 Pa", "too large"),
    ("1e-999999 Pa", "too small"),
    ("1e300 GPa", "too large"),
    ("(2 MPa", "does not start with a number"),
    ("2 MPa)", "unbalanced brackets"),
    ("2 kpa", "did you mean 'kPa'"),
    ("1 mPa*s", "is a viscosity, not a pressure"),
    ("5 %", "dimensionless, not a pressure"),
    ("1e3", "no unit"),
    ("½ MPa", "digits 0-9"),
])
def test_the_message_says_what_is_wrong(text, says):
    with pytest.raises(UnitError) as err:
        parse_quantity(FIELD, text, "pressure")
    assert says in str(err.value)
    assert "'60 kPa'" in str(err.value)  # and what is allowed


# ------------------------------------------------------------------------------------------ commas
@pytest.mark.parametrize("text, dimension, advice, meant", [
    ("2,3 MPa", "pressure", "write 2.3 MPa", 2.3e6),
    ("0,5 mm", "length", "write 0.5 mm", 0.5e-3),
    ("12,5e3 Pa", "pressure", "write 12.5e3 Pa", 12.5e3),
    ("-2,3 MPa", "pressure", "write -2.3 MPa", -2.3e6),
    ("0,5", "dimensionless", "write 0.5", 0.5),
    ("1,000 Pa", "pressure", "write 1000 Pa", 1000.0),  # thousands separator (or a decimal comma: both said)
    ("12,345,678 Pa", "pressure", "write 12345678 Pa", 12345678.0),
    ("1,000.5 Pa", "pressure", "write 1000.5 Pa", 1000.5),
])
def test_a_comma_in_a_number_is_refused_with_how_to_write_it(text, dimension, advice, meant):
    with pytest.raises(UnitError) as err:
        parse_quantity(FIELD, text, dimension)
    message = str(err.value)
    assert "',' is not allowed in numbers" in message and advice in message
    written = advice.removeprefix("write ")  # the advice, followed, gives the number the user meant
    assert parse_quantity(FIELD, written, dimension) == pytest.approx(meant, rel=1e-12, abs=0)


def test_an_ambiguous_comma_names_both_readings():
    message = comma_advice("1,000 Pa")
    assert "1000 Pa" in message and "1.000 Pa" in message


@pytest.mark.parametrize("text", ["2,3 mm", "1 mm,2,5 mm", "2,5um"])
def test_lists_of_lengths_refuse_a_decimal_comma(text):
    with pytest.raises(UnitError) as err:
        split_quantities("--size", text)
    assert "use a decimal point" in str(err.value) and err.value.field == "--size"
    assert split_quantities("--size", "1 mm, 0.5 mm") == ["1 mm", "0.5 mm"]


@pytest.mark.parametrize("unit", ["2,5 um", "1/0", "ml/min + 1", "(ml/min", "ml/min**99999", "ml/min^", "2**1000**1000 l/s"])
def test_units_in_headers_use_the_same_parser(unit):
    with pytest.raises(UnitError) as err:
        leak_rate_factor(unit, field_name="column 'leak_rate' unit")
    assert err.value.field == "column 'leak_rate' unit" and err.value.value == unit


@pytest.mark.parametrize("text", ["2,3", "1,000", "1_000", "0x10", "١", "1e999", "1e-999", "", "2 3", "1/2", "--1"])
def test_numbers_are_ascii_decimals(text):
    with pytest.raises(ValueError):
        parse_number(text)
    assert parse_number(" -1.5e-3 ") == -1.5e-3 and math.isnan(parse_number("nan"))


# ------------------------------------------------------------------------------------------ fuzz
PIECES = ["1", "0", "9", "2.3", ".", "e", "E", "e999999", "-", "+", "−", "*", "/", "^", "**", "(", ")", "[", "]", " ",
          "\u00a0", "\t", "\n", ",", "_", "%", "#", "'", "=", "nan", "inf", "Pa", "kPa", "MPa", "mPa", "m", "um", "µ", "μ",
          "1/", "s", "kg", "l", "min", "²", "⁻", "½", "١", "°C", "Å", "x", "pi", "lambda", "__import__", "1000", "9" * 30]


def _outcome(text, dimension):
    try:
        value = parse_quantity("field", text, dimension)
    except UnitError as err:
        assert err.field == "field" and str(err).startswith("field")
        return None
    assert isinstance(value, float) and math.isfinite(value)
    return value


@settings(max_examples=400, deadline=timedelta(seconds=2))
@given(st.lists(st.sampled_from(PIECES), max_size=12).map("".join), st.sampled_from(sorted(DIMENSIONS)))
def test_fuzz_pieces_give_a_finite_float_or_a_unit_error(text, dimension):
    _outcome(text, dimension)
    try:
        factor = unit_factor("unit", text, dimension)
    except UnitError:
        return
    assert math.isfinite(factor) and factor > 0


@settings(max_examples=300, deadline=timedelta(seconds=2))
@given(st.text(max_size=40), st.sampled_from(["pressure", "length", "dimensionless", "wavevector"]))
def test_fuzz_any_text_gives_a_finite_float_or_a_unit_error(text, dimension):
    _outcome(text, dimension)
    try:
        parse_number(text)
    except ValueError:
        pass


@settings(max_examples=200, deadline=timedelta(seconds=2))
@given(st.floats(allow_nan=False, allow_infinity=False, min_value=-1e300, max_value=1e300))
def test_fuzz_every_float_written_with_a_unit_reads_back(x):
    """A float written with a unit reads back exactly where its SI magnitude is 0 or within SI_RANGE (1e-100 to
    1e100: far around any seal's), and is refused naming the field outside it; a bare number reads back always."""
    low, high = SI_RANGE
    if x == 0 or low <= abs(x) <= high:
        assert parse_quantity("field", f"{x!r} Pa", "pressure") == x
    else:
        with pytest.raises(UnitError, match="too small|too large"):
            parse_quantity("field", f"{x!r} Pa", "pressure")
    assert parse_quantity("field", f"{x!r}", "dimensionless") == x


# ------------------------------------------------------------------------------------------ data files
@pytest.mark.parametrize("text, line, advice", [
    ("squeeze_pressure (kPa); leak_rate (ml/min)\n20; 380\n40,5; 120\n", 3, "write 40.5"),
    ("squeeze_pressure (kPa)\tleak_rate (ml/min)\n20\t1,000\n", 2, "write 1000"),
    ("squeeze_pressure (kPa) leak_rate (ml/min)\n20,5 1,5\n", 2, "write 20.5"),
    ("# measured\nsqueeze_pressure (kPa);leak_rate (ml/min)\n20;1\n30;2,5e-1;\n", 4, "write 2.5e-1"),
])
def test_data_files_refuse_decimal_commas_naming_file_and_line(tmp_path, text, line, advice):
    path = tmp_path / "measured.csv"
    path.write_text(text)
    with pytest.raises(FileFormatError) as err:
        read_leak_data(path)
    message = str(err.value)
    assert message.startswith(f"{path}: line {line}: ")
    assert "',' is not allowed in numbers" in message and advice in message


def test_a_first_row_with_decimal_commas_is_not_taken_for_a_header(tmp_path):
    path = tmp_path / "psd.csv"
    path.write_text("1000;1,5e-18\n2000;2,5e-19\n")
    with pytest.raises(FileFormatError) as err:
        read_spectrum_table(path)
    assert "line 1: " in str(err.value) and "write 1.5e-18" in str(err.value)


def test_comma_separated_rows_with_a_glued_comma_get_the_decimal_comma_hint(tmp_path):
    path = tmp_path / "measured.csv"
    path.write_text("squeeze_pressure (kPa), leak_rate (ml/min)\n20,5, 380\n")
    with pytest.raises(FileFormatError) as err:
        read_leak_data(path)
    assert "line 2: 3 values" in str(err.value) and "use a decimal point" in str(err.value)


@pytest.mark.parametrize("cell", ["1_000", "0x10", "١٢", "1e-999"])
def test_table_cells_are_strict_numbers(tmp_path, cell):
    path = tmp_path / "t.csv"
    path.write_text(f"a (m), b (m)\n1, 2\n3, {cell}\n")
    with pytest.raises(FileFormatError) as err:
        read_unit_table(path)
    assert str(err.value).startswith(f"{path}: line 3: ")


@pytest.mark.parametrize("text", [
    "q (1/m), C (m^4)\n1e3, 1e-18\n1e4, 1e-21\n",
    "q (1/m); C (m^4)\n1e3; 1e-18\n1e4; 1e-21;\n",
    "q (1/m)\tC (m^4)\n1e3\t1e-18\n1e4\t1e-21\n",
    "q (1/m) C (m^4)\n1e3 1e-18\n1e4   1e-21\n",
    "1e3 1e-18\n1e4 1e-21\n",
])
def test_tables_with_decimal_points_still_read(tmp_path, text):
    path = tmp_path / "psd.csv"
    path.write_text(text)
    q, c = read_spectrum_table(path)
    assert list(q) == [1e3, 1e4] and list(c) == [1e-18, 1e-21]


@pytest.mark.parametrize("unit", ["1/0 kPa", "(kPa", "2,5 kPa", "kPa + 1", "kPa**99999"])
def test_bad_units_in_a_data_header_name_the_file(tmp_path, unit):
    path = tmp_path / "measured.csv"
    path.write_text(f"squeeze_pressure ({unit}); leak_rate (ml/min)\n20; 380\n")
    with pytest.raises(FileFormatError) as err:
        read_leak_data(path)
    assert str(err.value).startswith(f"{path}: column 'squeeze_pressure' unit = ")
