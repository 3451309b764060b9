"""Bit-for-bit reproducibility of a band seal's prediction (docs/theory.md §10), and the interpolant behind it.

The effective medium's σ(p) of a band is a polynomial interpolant in ln p through exact values at
Chebyshev–Lobatto points. Evaluated through a BLAS product (as scipy's BarycentricInterpolator does), the
same inputs gave results differing in the last bits from call to call, which the adaptive quadrature then
amplified to ~1e-9 in its error estimate: two identical runs wrote different JSON.
"""

import json

import numpy as np
from scipy.interpolate import BarycentricInterpolator

from sealeak.cases import example_path, load_cases, run_case
from sealeak.cases.band_tables import chebyshev_lobatto_interpolate
from sealeak.physics import coupling
from sealeak.physics._kernels import weighted_sum
from sealeak.physics.gaps import clear_caches


def _lobatto(n, lo=-2.0, hi=3.0):
    k = np.arange(n)
    return (lo + hi) / 2 - (hi - lo) / 2 * np.cos(np.pi * k / (n - 1))


def test_interpolant_reproduces_a_polynomial_of_degree_n_minus_1_and_agrees_with_scipy():
    s = _lobatto(9)
    coef = np.array([0.3, -1.2, 0.5, 0.25, -0.1, 0.04, 0.01, -0.002, 0.0007])
    f = np.polynomial.polynomial.polyval(s, coef)
    x = np.linspace(-2.0, 3.0, 101)
    np.testing.assert_allclose(chebyshev_lobatto_interpolate(s, f, x), np.polynomial.polynomial.polyval(x, coef), rtol=0, atol=1e-12)
    g = np.exp(-s) * np.sin(3 * s)  # not a polynomial: the same interpolant as scipy's, by another route
    np.testing.assert_allclose(chebyshev_lobatto_interpolate(s, g, x), BarycentricInterpolator(s, g)(x), rtol=0, atol=1e-12)
    assert np.array_equal(chebyshev_lobatto_interpolate(s, g, s), g)  # exact at the nodes


def test_interpolant_is_the_sum_term_by_term_whatever_else_is_asked():
    """Each point's value is Σ_k added from k = 0 up, in that order (written out here), the same bits alone, among
    other points, or in a later block of points (more than the block of 512)."""
    s = _lobatto(65)
    g = np.exp(-s) * np.sin(3 * s)
    x = np.random.default_rng(3).uniform(-2.0, 3.0, 1300)
    w = (-1.0) ** np.arange(s.size)
    w[[0, -1]] *= 0.5
    num = den = np.zeros(x.size)
    for k in range(s.size):
        c = w[k] / (x - s[k])
        num, den = num + c * g[k], den + c
    got = chebyshev_lobatto_interpolate(s, g, x)
    assert np.array_equal(got, num / den)
    assert all(np.array_equal(chebyshev_lobatto_interpolate(s, g, x[i:i + 1]), got[i:i + 1]) for i in (0, 700, 1299))


def test_weighted_sum_is_the_sum_in_fixed_order():
    v = np.random.default_rng(5).normal(size=(7, 40))
    w = np.random.default_rng(6).normal(size=7)
    by_hand = v[0] * w[0]
    for j in range(1, 7):
        by_hand = by_hand + v[j] * w[j]
    assert np.array_equal(weighted_sum(v, w, axis=0), by_hand)
    assert np.array_equal(weighted_sum(v.T.copy(), w, axis=-1), by_hand)


def test_a_band_prediction_is_the_same_bits_every_time():
    (case,) = load_cases(example_path("lip-profile"))
    clear_caches()
    first = json.dumps(run_case(case).records())  # NaN written as NaN: equal text, bit-equal numbers (repr)
    for _ in range(2):
        clear_caches()  # P(u) computed again, not taken from where the first run kept it
        assert json.dumps(run_case(case).records()) == first
    assert json.dumps(run_case(case).records()) == first  # and taken from there


def test_a_second_viscosity_reuses_the_coupled_bands_and_gives_the_same_bits(monkeypatch):
    """The coupled bands are solved at η = 1 Pa·s and divided by η (docs/theory.md §13.3): the second fluid of the
    bundled O-ring example solves no band, and its result is bit for bit that of the second fluid run alone."""
    water, oil = load_cases(example_path("o-ring"))
    assert oil.fluid.viscosity != water.fluid.viscosity
    clear_caches()
    alone = run_case(oil).band
    clear_caches()
    run_case(water)
    solve = coupling._solve_band
    solved = []
    monkeypatch.setattr(coupling, "_solve_band", lambda *a: solved.append(1) or solve(*a))
    after = run_case(oil).band
    assert not solved
    for theory in ("critical_junction", "effective_medium"):
        assert np.array_equal(getattr(after, theory).leak_rate, getattr(alone, theory).leak_rate, equal_nan=True)
        ratio = getattr(after, theory).leak_rate / getattr(run_case(water).band, theory).leak_rate
        finite = np.isfinite(ratio)
        assert finite.any()
        np.testing.assert_allclose(ratio[finite], water.fluid.viscosity / oil.fluid.viscosity, rtol=1e-12)
