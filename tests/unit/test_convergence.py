"""The convergence study's statistics: standard errors, the continuum extrapolation, the study's bookkeeping and flags."""

from dataclasses import replace

import numpy as np
import pytest

from sealeak.cases import example_path, load_cases, simulate
from sealeak.cases.convergence import (
    PUBLISHED_THRESHOLDS,
    _fit_flags,
    _spectrum_shape,
    analyse_convergence,
    convergence_study,
    extrapolate,
    parse_grid_list,
    standard_error,
)
from sealeak.errors import InputError
from sealeak.render.notes import worded

L = 5e-3
GRIDS = np.array([32, 64, 128, 256])
A = L / GRIDS


# ---------------------------------------------------------------- standard error
def test_standard_error_is_sd_over_root_n_of_the_finite_values():
    rng = np.random.default_rng(1)
    x = rng.normal(0.4, 0.03, 7)
    mean, se, n = standard_error(np.concatenate([x, [np.nan, np.inf]]))
    assert n == 7 and mean == pytest.approx(np.mean(x), rel=1e-14, abs=0)
    assert se == pytest.approx(np.std(x, ddof=1) / np.sqrt(7), rel=1e-14, abs=0)
    assert np.isnan(standard_error([0.3])[1]) and standard_error([])[2] == 0


# ---------------------------------------------------------------- extrapolation, closed forms
@pytest.mark.parametrize("points", [2, 3])
def test_exact_line_in_a_is_recovered(points):
    x_inf, c = 0.418, -37.5  # X(a) = X∞ + c a, a in m
    x = x_inf + c * A[:points]
    fit = extrapolate(A[:points], x, np.full(points, 0.01))
    assert fit.value == pytest.approx(x_inf, rel=1e-12, abs=0)
    assert fit.slope == pytest.approx(c, rel=1e-12)
    assert fit.exponent == 1.0 and not fit.exponent_fitted and fit.dof == points - 2
    assert fit.chi2 == pytest.approx(0.0, abs=1e-20)
    # two points: X∞ = (a2 x1 − a1 x2)/(a2 − a1), and its standard error by propagating s1 = s2 = s
    if points == 2:
        a1, a2 = A[:2]
        assert fit.stderr == pytest.approx(0.01 * np.hypot(a2, a1) / abs(a2 - a1), rel=1e-12, abs=0)


def test_exponent_is_fitted_from_four_grids():
    x_inf, c, p = 0.42, 2.0e3, 1.6
    fit = extrapolate(A, x_inf + c * A**p, np.full(4, 1e-3))
    assert fit.exponent_fitted and fit.dof == 1
    assert fit.exponent == pytest.approx(p, rel=1e-8)
    assert fit.value == pytest.approx(x_inf, rel=1e-10)
    assert fit.slope == pytest.approx(c, rel=1e-7)
    # a fixed exponent is honoured with four grids too
    fixed = extrapolate(A, x_inf + c * A**p, np.full(4, 1e-3), exponent=1.0)
    assert not fixed.exponent_fitted and fixed.exponent == 1.0


def test_standard_error_matches_the_monte_carlo_spread():
    """Noise of known sd on an exact line: the spread of X∞ over many draws is the fit's standard error."""
    rng = np.random.default_rng(2024)
    a = A[:3]
    se = np.array([0.02, 0.012, 0.006])
    draws = 4000
    values, reported, unscaled = np.empty(draws), np.empty(draws), np.empty(draws)
    for k in range(draws):
        fit = extrapolate(a, 0.42 + 20.0 * a + rng.normal(0.0, se), se)
        values[k], reported[k], unscaled[k] = fit.value, fit.stderr, fit.stderr_unscaled
    assert np.ptp(unscaled) < 1e-12 * unscaled[0]  # it depends on a and s only
    assert np.std(values, ddof=1) == pytest.approx(unscaled[0], rel=0.05)
    assert np.mean(values) == pytest.approx(0.42, abs=3 * unscaled[0] / np.sqrt(draws))
    # scaled by sqrt(chi2/dof) only when that exceeds 1: never smaller, larger in about a third of the draws (dof = 1)
    assert np.all(reported >= unscaled * (1 - 1e-12))
    assert 0.25 < np.mean(reported > unscaled * (1 + 1e-9)) < 0.40


def test_unweighted_fit_without_standard_errors_uses_the_scatter():
    x = np.array([0.40, 0.43, 0.41])
    fit = extrapolate(A[:3], x, [np.nan] * 3)
    assert not fit.weighted and np.isnan(fit.stderr_unscaled)
    design = np.column_stack([np.ones(3), A[:3]])
    beta, res, *_ = np.linalg.lstsq(design, x, rcond=None)
    cov = np.linalg.inv(design.T @ design) * res[0] / 1
    assert fit.value == pytest.approx(beta[0], rel=1e-12, abs=0)
    assert fit.stderr == pytest.approx(np.sqrt(cov[0, 0]), rel=1e-10)
    assert not fit.monotonic


# ---------------------------------------------------------------- the grid list
@pytest.mark.parametrize("text, grids", [("64", (64,)), ("128,64", (64, 128)), (" 32, 64 ,256", (32, 64, 256))])
def test_grid_list_parses(text, grids):
    assert parse_grid_list(text, "--grid") == grids


@pytest.mark.parametrize("bad", ["32,63", "32,,64", "abc", "32,32", "8,32", "", "32,-64", [32, 32], [32, True], []])
def test_grid_list_refuses(bad):
    with pytest.raises(InputError, match="--grid"):
        parse_grid_list(bad, "--grid")


# ---------------------------------------------------------------- the study
@pytest.fixture(scope="module")
def case():
    (c,) = load_cases(example_path("reference-experiment"))
    return replace(c, squeeze_pressure=np.array([2.5e4, 4e4]))


@pytest.fixture(scope="module")
def study(case):
    return convergence_study(case, [64, 32], realizations=2, seed=7)


def test_study_reproduces_single_grid_runs(case, study):
    assert study.grids == (32, 64)
    for n, res in zip(study.grids, study.results, strict=True):
        single = simulate(case, grid=n, realizations=2, seed=7)
        for key, value in single.per_realization.items():
            np.testing.assert_array_equal(res.per_realization[key], value)
        np.testing.assert_array_equal(res.alpha, single.alpha)
        assert res.percolation_threshold == single.percolation_threshold


def test_study_statistics_are_means_and_standard_errors(study):
    for g, res in zip(study.statistics, study.results, strict=True):
        assert g.spacing == pytest.approx(res.size / res.grid, rel=1e-15, abs=0)
        th = res.per_realization["percolation_threshold"]
        assert g.threshold == pytest.approx(np.mean(th), rel=1e-14, abs=0)
        assert g.threshold_stderr == pytest.approx(np.std(th, ddof=1) / np.sqrt(th.size), rel=1e-12, abs=0)
        alpha = res.per_realization["alpha"]
        for i in range(alpha.shape[1]):
            ok = np.isfinite(alpha[:, i])
            if ok.sum() >= 2:
                assert g.alpha_stderr[i] == pytest.approx(np.std(alpha[ok, i], ddof=1) / np.sqrt(ok.sum()), rel=1e-12, abs=0)
    fit = study.threshold_extrapolation
    a = [g.spacing for g in study.statistics]
    x = [g.threshold for g in study.statistics]
    assert fit.value == pytest.approx(x[0] - (x[1] - x[0]) / (a[1] - a[0]) * a[0], rel=1e-12, abs=0)  # line through two points


def test_threshold_is_compared_with_the_published_values(study):
    fine = study.statistics[-1]
    first = study.comparison[0]
    assert (first.ours, first.published) == (fine.threshold, PUBLISHED_THRESHOLDS[0][1])
    assert first.difference == pytest.approx((fine.threshold - 0.42) / fine.threshold_stderr, rel=1e-12)
    assert {c.published for c in study.comparison} == {0.42, 0.415}


def test_flags_say_too_few_realisations_and_two_grids(study, case):
    flags = " ".join(worded(study.flags))
    assert "only 2 realisations per grid" in flags
    assert "the threshold: the extrapolation rests on 2 grids" in flags
    one = analyse_convergence(case, [simulate(case, grid=n, realizations=1, seed=7, threshold=False) for n in (32, 48)])
    text = " ".join(worded(one.flags))
    assert "only 1 realisation per grid: there is no standard error at all" in text
    assert one.threshold_extrapolation is None and not one.comparison
    assert "no percolation threshold at any grid (the search was skipped with --no-threshold" in text
    # the spectrum is not resolved by 48 points: said so
    assert "even the finest grid (48x48) resolves q only up to" in text


def test_study_needs_two_grids(case):
    with pytest.raises(InputError, match="at least two grids"):
        convergence_study(case, [32], realizations=1, seed=0)


# ---------------------------------------------------------------- flags of a fit, the spectrum's shape
def test_fit_flags_name_what_is_wrong():
    se = [0.01, 0.01, 0.01]
    zigzag = [0.40, 0.46, 0.41]  # not monotonic, and far off any line: χ²/dof = 18 with dof = 1 (p ≈ 2e-5)
    text = " ".join(worded(_fit_flags("X", extrapolate(A[:3], zigzag, se), zigzag, se)))
    assert "do not change in one direction" in text and "does not fit the grids" in text
    flat = [0.420, 0.425, 0.428]  # a change of 0.008 against a standard error of 0.014
    assert "smaller than its standard error" in " ".join(worded(_fit_flags("X", extrapolate(A[:3], flat, se), flat, se)))
    clean = [0.50, 0.45, 0.425]  # an exact line in a, resolved: nothing to say
    assert _fit_flags("X", extrapolate(A[:3], clean, se), clean, se) == []


def test_spectrum_shape_of_the_reference_case(case):
    hurst, rolloffs = _spectrum_shape(case, case.spectrum.q_max)
    assert hurst == pytest.approx(0.8, abs=0.01)  # the case's self-affine H
    assert rolloffs == pytest.approx(case.square_side * 9.1e3 / (2 * np.pi), rel=0.05)  # L/λ_r, q_r = 9.1e3 1/m
