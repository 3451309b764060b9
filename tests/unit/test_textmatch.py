"""The cross-machine text comparison of tests/textmatch.py: words exact, numbers within tolerance."""

from tests.textmatch import same_numbers, same_text


def test_last_bit_of_a_repr_matches():
    assert same_text('"leak_rate": 6.376955986710466e-06,', '"leak_rate": 6.376955986710464e-06,')
    assert same_numbers("1.0000000000000002", "1.0")


def test_a_rounded_value_may_round_either_way_by_one_unit():
    assert same_text("Q = 6.37e-06 m³/s", "Q = 6.38e-06 m³/s")
    assert same_text("20 kPa  1.24e-09", "20 kPa  1.23e-09")
    assert same_numbers("0.125", "0.126")


def test_real_differences_are_caught():
    assert not same_text("Q = 6.37e-06 m³/s", "Q = 6.39e-06 m³/s")
    assert not same_text('"leak_rate": 6.376955986710466e-06', '"leak_rate": 6.376955996710466e-06')
    assert not same_text("40 squeeze pressures", "41 squeeze pressures")  # integers exactly
    assert not same_text("alpha = 0.5", "alpha = 0.6")                    # one or two digits exactly
    assert not same_text("Q = 6.37e-06 m³/s", "Q = 6.37e-06 ml/min")      # words exactly
    assert not same_text("a 1 b", "a 1 b 2")                              # as many numbers
    assert not same_text("Q = 6.37e-06", "Q = 6.37e-05")                  # exponents are compared as values
