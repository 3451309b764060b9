"""The guard of tests/conftest.py: a pytest.approx whose default absolute tolerance (1e-12) would exceed its relative one
fails, where it would have passed any value (docs/development.md, "Tolerances")."""

import pytest


def test_a_tiny_value_without_abs_is_refused():
    with pytest.raises(AssertionError, match="give abs"):
        assert 3e-15 == pytest.approx(1e-15, rel=1e-9)  # (1e-12 absolutely: it would pass)
    with pytest.raises(AssertionError, match="give abs"):
        assert [1.0, 2e-13] == pytest.approx([1.0, 2e-13])  # (rel 1e-6 by default: 2e-19 < 1e-12)


def test_a_stated_tolerance_is_kept():
    assert 1e-15 == pytest.approx(1e-15 * (1 + 1e-10), rel=1e-9, abs=0)
    assert 3e-15 != pytest.approx(1e-15, rel=1e-9, abs=0)
    assert 1.0 == pytest.approx(1.0 + 1e-7)  # (1e-6 relative: the absolute default is below it)
    assert 1e-13 == pytest.approx(0.0, abs=1e-12)  # (zero, or abs given: as pytest has it)
