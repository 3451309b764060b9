"""The O-ring's force correction: ``force_factor`` and a force table (docs/theory.md §10.2, eq. 10.2e)."""

import numpy as np
import pytest
from scipy import integrate

from sealeak.errors import InputError
from sealeak.physics.oring import ForceTable, oring_contact

D = 2.62e-3  # m
E = 5.5e6  # Pa
EPS = np.array([0.005, 0.05, 0.1, 0.2, 0.3])


def test_factor_one_is_the_published_relation_bit_for_bit():
    plain, one = oring_contact(D, E, 0.5, EPS), oring_contact(D, E, 0.5, EPS, force_factor=1.0)
    for name in ("force_per_length", "contact_width", "max_pressure", "mean_pressure"):
        assert np.array_equal(getattr(plain, name), getattr(one, name)), name
    assert plain.source == one.source and plain.regime == one.regime


@pytest.mark.parametrize("factor", [0.5, 2.0, 3.7])
def test_factor_scales_force_and_pressure_not_the_width(factor):
    plain, scaled = oring_contact(D, E, 0.5, EPS), oring_contact(D, E, 0.5, EPS, force_factor=factor)
    np.testing.assert_allclose(scaled.force_per_length, factor * plain.force_per_length, rtol=1e-14)
    np.testing.assert_allclose(scaled.mean_pressure, factor * plain.mean_pressure, rtol=1e-14)
    np.testing.assert_allclose(scaled.max_pressure, factor * plain.max_pressure, rtol=1e-14)
    np.testing.assert_array_equal(scaled.contact_width, plain.contact_width)
    assert "force_factor" in scaled.source


@pytest.mark.parametrize("factor", [0.5, 2.0])
def test_scaled_profile_carries_the_given_force(factor):
    c = oring_contact(D, E, 0.5, 0.15, force_factor=factor)
    prof, w = c.profile(0), float(c.contact_width[0])
    carried, _ = integrate.quad(lambda x: float(prof.at(x)), 0.0, w, epsabs=0.0, epsrel=1e-11, limit=200)
    assert carried == pytest.approx(float(c.force_per_length[0]), rel=1e-8)


def test_a_table_of_lindleys_values_reproduces_lindley():
    # Lindley's f = E d (1.25 ε^1.5 + 50 ε^6) tabulated every 2.5 % over its range (10 % to 35 %)
    grid = np.linspace(0.10, 0.35, 11)
    table = ForceTable(grid, E * D * (1.25 * grid**1.5 + 50 * grid**6), name="lindley.csv")
    eps = np.array([0.10, 0.113, 0.15, 0.2217, 0.29, 0.35])
    model, tabled = oring_contact(D, E, 0.5, eps), oring_contact(D, E, 0.5, eps, force_table=table)
    np.testing.assert_allclose(tabled.force_per_length, model.force_per_length, rtol=2e-3)
    np.testing.assert_array_equal(tabled.contact_width, model.contact_width)
    assert "lindley.csv" in tabled.source


def test_table_interpolation_is_monotone_and_hits_its_points():
    eps = np.array([0.0, 0.1, 0.12, 0.3])
    f = np.array([0.0, 1000.0, 4000.0, 4100.0])  # a steep step, then almost flat: a spline would overshoot
    table = ForceTable(eps, f)
    fine = np.linspace(1e-4, 0.3, 2001)
    values = table(fine)
    assert np.all(np.diff(values) >= 0)
    assert values.max() <= f.max() * (1 + 1e-12)
    np.testing.assert_allclose(table(eps[1:]), f[1:], rtol=1e-12)


def test_table_and_factor_multiply():
    grid = np.array([0.05, 0.2, 0.4])
    table = ForceTable(grid, np.array([500.0, 2000.0, 6000.0]))
    one, two = (oring_contact(D, E, 0.5, 0.2, force_table=table, force_factor=k) for k in (1.0, 2.0))
    assert float(one.force_per_length[0]) == pytest.approx(2000.0, rel=1e-12)
    assert float(two.force_per_length[0]) == pytest.approx(4000.0, rel=1e-12)


@pytest.mark.parametrize("eps", [0.04, 0.45])
def test_compression_outside_the_table_is_refused(eps):
    table = ForceTable(np.array([0.05, 0.2, 0.4]), np.array([500.0, 2000.0, 6000.0]), name="t.csv")
    with pytest.raises(InputError, match="compression.*t.csv"):
        oring_contact(D, E, 0.5, eps, force_table=table)


@pytest.mark.parametrize("eps, f, words", [
    ([0.1], [100.0], "two rows"),
    ([0.1, 0.05], [100.0, 200.0], "monotone"),
    ([0.1, 0.2], [300.0, 200.0], "monotone"),
    ([-0.1, 0.2], [0.0, 200.0], ">= 0"),
    ([0.1, 0.2], [np.nan, 200.0], "finite"),
])
def test_bad_table_is_refused(eps, f, words):
    with pytest.raises(InputError, match=words):
        ForceTable(np.array(eps), np.array(f))


@pytest.mark.parametrize("bad", [0, -1, float("nan"), float("inf"), 1e6, True, "2"])
def test_bad_factor_is_refused_naming_it(bad):
    with pytest.raises(InputError, match="force_factor"):
        oring_contact(D, E, 0.5, 0.2, force_factor=bad)
