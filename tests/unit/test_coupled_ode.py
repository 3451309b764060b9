"""The coupled band's shooting (physics/coupling.py, docs/theory.md eq. 13.3) against an independent one: the ODE in x
(not θ), solve_ivp's DOP853 at a tolerance 100× tighter, the exact σ(s) (not its spline), at ΔP up to lift-off
(at 0.999 p_max solve_ivp at the code's own tolerance, 1e-10, missed by 15 % on the O-ring example)."""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from scipy import integrate, optimize

import sealeak.physics.coupling as coupling
from sealeak.physics.coupling import coupled_band_flow, gas_sheet
from sealeak.physics.gaps import clear_caches
from sealeak.physics.profile import SIGMA_FLOOR, PressureProfile, series_resistance

W, P_MAX = 1e-3, 2e6
SIGMA0, S0 = 1e-15, P_MAX / 8


def sigma(s):
    """A sheet conductance (m³/(Pa·s)) that closes exponentially with the effective pressure s (Pa), as u_c does."""
    return SIGMA0 * np.exp(-np.asarray(s, dtype=float) / S0)


def reference_flow(dp):
    """q (m²/s) with p_f(w) = 0 for dp_f/dx = −q/σ(p(x) − p_f), p(x) the Hertz profile, σ clipped as the code clips
    it (effective pressures below 1e-6 p_max take σ there)."""
    def p(x):
        return P_MAX * np.sqrt(max(0.0, 1.0 - (2.0 * x / W - 1.0) ** 2))

    def outlet(q):
        rhs = lambda x, u: [-q / sigma(max(p(x) - u[0], 1e-6 * P_MAX))]  # noqa: E731
        with np.errstate(invalid="ignore", divide="ignore"):  # (its step control on a flat stretch: 0/0)
            sol = integrate.solve_ivp(rhs, (0.0, W), [dp], method="DOP853", rtol=1e-12, atol=1e-14 * dp)
        return sol.y[0, -1] / dp

    q0 = dp / integrate.quad(lambda x: 1.0 / sigma(p(x)), 0.0, W, epsabs=0, epsrel=1e-12)[0]
    hi = 2.0 * q0
    while outlet(hi) > 0:
        hi *= 2.0
    return optimize.brentq(outlet, q0, hi, rtol=1e-12)


def reference_flow_in_angle(dp, near):
    """As :func:`reference_flow`, with x = (W/2)(1 − cos θ), which removes the square-root ends of the Hertz profile
    (dp/dx is infinite there, which limits the shooting in x to ~1e-5), at solve_ivp's rtol 1e-13; the root is
    bracketed around ``near`` (m²/s) by a factor of 2."""
    def outlet(q):
        def rhs(theta, u):
            return [-q * (W / 2.0) * np.sin(theta) / sigma(max(P_MAX * np.sin(theta) - u[0], 1e-6 * P_MAX))]
        with np.errstate(invalid="ignore", divide="ignore"):
            sol = integrate.solve_ivp(rhs, (0.0, np.pi), [dp], method="DOP853", rtol=1e-13, atol=1e-14 * dp)
        return sol.y[0, -1] / dp

    return optimize.brentq(outlet, 0.5 * near, 2.0 * near, rtol=1e-13)


@pytest.mark.parametrize("fraction", [0.999, *np.random.default_rng(7).uniform(0.05, 0.95, 1)])
def test_shooting_matches_an_independent_solution(fraction):
    dp = fraction * P_MAX
    got = coupled_band_flow(PressureProfile.semi_elliptic(W, P_MAX), sigma, dp)
    assert got.converged and not got.lifted
    # the shooting in x is good to ~1e-5 (at the middle fraction its rtol 1e-12 and 1e-13 differ by 2e-5)
    assert got.flow == pytest.approx(reference_flow(dp), rel=5e-5, abs=0)
    # in θ the reference is good to ~1e-7, so what is left is the band's spline of ln σ (2.3e-6 in σ for this σ)
    assert got.flow == pytest.approx(reference_flow_in_angle(dp, got.flow), rel=5e-6, abs=0)


@pytest.mark.parametrize("fraction", [0.3, 0.9])
def test_no_flow_is_shot_twice(fraction, monkeypatch):
    """Every ODE solve is for a new trial flow and ``shots`` counts them (Newton's method; where it fails, Brent's
    method starts from the ends of the bracket the doubling has shot already, and those shots are reused)."""
    tried = []
    makers = coupling._liquid_slopes

    def recording(profile, table, **kw):
        def record(make):
            def made(q):
                tried.append(q)
                return make(q)
            return made
        return [record(make) for make in makers(profile, table, **kw)]

    monkeypatch.setattr(coupling, "_liquid_slopes", recording)
    got = coupled_band_flow(PressureProfile.semi_elliptic(W, P_MAX), sigma, fraction * P_MAX)
    assert got.converged and got.shots >= 2
    assert len(tried) == got.shots == len(set(tried))


@pytest.mark.parametrize("fraction", [0.05, 0.5, 0.95])
def test_newtons_method_agrees_with_bracketing(fraction, monkeypatch):
    """Newton's method on the outlet pressure with its derivative from the variational equation (∂p_f/∂ln q carried
    across the band) lands on the root that bracketing and Brent's method find, to the shooting's tolerance, in fewer
    shots; with a wrong derivative it would not converge within the bounds in so few shots."""
    profile = PressureProfile.semi_elliptic(W, P_MAX)
    clear_caches()
    newton = coupled_band_flow(profile, sigma, fraction * P_MAX)
    clear_caches()
    monkeypatch.setattr(coupling, "_newton_shoot", lambda *a: None)
    bracketed = coupled_band_flow(profile, sigma, fraction * P_MAX, rtol=1e-12)  # (Brent's method well below the shots' error)
    assert newton.converged and bracketed.converged
    # (Newton's shots at coupling.SHOT_RTOL, bracketing's at 1e-10: they differ by 2e-10, 1e-8 and 2.5e-8 at 0.05, 0.5 and 0.95 p_max, within
    # the flow's tolerance)
    assert newton.flow == pytest.approx(bracketed.flow, rel=coupling.FLOW_RTOL, abs=0)
    assert newton.shots < bracketed.shots and newton.shots <= 7  # (0.95 p_max: 3 loose shots, then 4 tight ones)


def test_a_loose_shot_does_not_close_the_bracket_on_the_wrong_side(monkeypatch):
    """At 0.75 p_max a loose shot near the root (coupling.LOOSE_RTOL) gives the outlet pressure the wrong sign (−0.025 ΔP
    where a tight shot gives +0.004 ΔP). Were the bracket narrowed to it, Newton's steps would crawl towards that end for
    40 shots without converging and the band be solved the other way round (65 shots in all); as it is, Newton's method
    converges in a few shots, on the root that bracketing with shots at 1e-10 finds."""
    profile = PressureProfile.semi_elliptic(W, P_MAX)
    clear_caches()
    newton = coupled_band_flow(profile, sigma, 0.75 * P_MAX)
    assert newton.converged and newton.shots <= 8
    clear_caches()
    monkeypatch.setattr(coupling, "_newton_shoot", lambda *a: None)
    bracketed = coupled_band_flow(profile, sigma, 0.75 * P_MAX)
    assert newton.flow == pytest.approx(bracketed.flow, rel=coupling.FLOW_RTOL, abs=0)


def test_a_shot_that_fails_at_the_looser_tolerance_is_shot_again_before_it_bounds_the_root(monkeypatch):
    """On a steep band (σ ∝ e^(−24 s/p_max), ΔP = 0.84 p_max) a shot at coupling.SHOT_RTOL just below the root fails
    (DOP853's step shrinks to nothing), where at coupling.STRICT_RTOL it crosses the band. Taken as a flow too large, it
    closed the bracket below the root, and Newton's answer was 1.7e-5 off; shot again at STRICT_RTOL it is within the
    shots' accuracy (~1e-6) of a solve with every shot at 1e-12, in a few shots."""
    got, reference = _steep_band(monkeypatch, 0.84)
    assert got.converged and reference.converged and got.shots <= 6
    assert got.flow == pytest.approx(reference.flow, rel=1e-6, abs=0)


def test_a_loose_step_that_leaves_the_bracket_is_shot_again_tight(monkeypatch):
    """On the steep band at ΔP = 0.94 p_max a loose shot's Newton step leaves the bracket the tight shots have narrowed:
    the same flow is shot again tight (18 shots) rather than bisecting that bracket or taking its false position (23),
    and the answer is within the shots' accuracy of a solve with every shot at 1e-12."""
    got, reference = _steep_band(monkeypatch, 0.94)
    assert got.converged and reference.converged and got.shots <= 20
    assert got.flow == pytest.approx(reference.flow, rel=1e-6, abs=0)


def _steep_band(monkeypatch, fraction):
    """(the flow of the band σ = 1e-15 e^(−24 s/p_max)/(1 + (s/p_max)²) at ΔP = ``fraction`` p_max, the same with every
    shot at 1e-12)."""
    profile = PressureProfile.semi_elliptic(W, P_MAX)

    def steep(s):
        s = np.asarray(s, dtype=float)
        return 1e-15 * np.exp(-24.0 * s / P_MAX) / (1.0 + (s / P_MAX) ** 2)

    clear_caches()
    got = coupled_band_flow(profile, steep, fraction * P_MAX)
    with monkeypatch.context() as m:
        m.setattr(coupling, "SHOT_RTOL", 1e-12)
        m.setattr(coupling, "STRICT_RTOL", 1e-12)
        clear_caches()
        reference = coupled_band_flow(profile, steep, fraction * P_MAX, rtol=1e-11)
    return got, reference


@pytest.mark.parametrize("factor", [1.5, 30.0])
def test_flow_is_inversely_proportional_to_viscosity(factor, monkeypatch):
    """q ∝ σ at fixed ΔP (p_f(x) does not change when σ is multiplied by a constant): a band solved for σ/k, here
    afresh, has the flow q/k of the band solved for σ, within the flow's tolerance (coupling.FLOW_RTOL; 8e-9 here: the
    same shots, scaled, up to rounding, which may tip the last Newton step)."""
    clear_caches()
    profile = PressureProfile.semi_elliptic(W, P_MAX)
    solved = []
    solve = coupling._solve_band
    monkeypatch.setattr(coupling, "_solve_band", lambda *a: solved.append(1) or solve(*a))
    q = coupled_band_flow(profile, sigma, 0.4 * P_MAX).flow
    thicker = coupled_band_flow(profile, lambda s: sigma(s) / factor, 0.4 * P_MAX)
    assert len(solved) == 2  # the second solved, not taken from the first
    assert thicker.flow == pytest.approx(q / factor, rel=coupling.FLOW_RTOL, abs=0)


def test_a_band_solved_once_is_not_solved_again(monkeypatch):
    """The solution depends on the profile, ΔP and σ alone: the same band again is answered without a shot, the same."""
    clear_caches()
    profile = PressureProfile.semi_elliptic(W, P_MAX)
    first = coupled_band_flow(profile, sigma, 0.5 * P_MAX)
    monkeypatch.setattr(coupling, "_solve_band", lambda *a: pytest.fail("solved again"))
    assert coupled_band_flow(profile, sigma, 0.5 * P_MAX) == first




@pytest.mark.parametrize("k", [10, 30, 60, 120])
def test_a_near_sealed_band_matches_the_closed_form_of_a_flat_band(k):
    """A flat band (p = p0 across it) separates eq. 13.3: q w = ∫ σ(s) ds over s from p0 − ΔP to p0. With σ falling by
    e^(0.9 k) over that range the shooting in x cannot follow the band beyond k ≈ 20 (its pressure drops over the last
    1e-8 of the width; it once said it had converged, 1e10 too large): the band is then solved the other way round,
    x(p_f), within the bounds ΔP/R(p) ... ΔP/R(p − ΔP)."""
    p0, s0, dp = P_MAX, P_MAX / k, 0.9 * P_MAX

    def steep(s):
        return SIGMA0 * np.exp(-np.asarray(s, dtype=float) / s0)

    clear_caches()
    got = coupled_band_flow(PressureProfile.table([0.0, W], [p0, p0]), steep, dp)
    exact = SIGMA0 * s0 * (np.exp(-(p0 - dp) / s0) - np.exp(-p0 / s0)) / W
    assert got.converged
    assert got.flow == pytest.approx(exact, rel=1e-4, abs=0)  # the band's spline of ln σ in ln s: ~1e-5 here


@pytest.mark.parametrize("fraction", [0.3, 0.9])
def test_the_two_directions_of_the_band_agree_where_both_follow_it(fraction, monkeypatch):
    """The inverse integration (x of p_f) against the shooting in x on the Hertz band of the other tests."""
    dp = fraction * P_MAX
    profile = PressureProfile.semi_elliptic(W, P_MAX)
    clear_caches()
    inverse_calls = []
    solve_inverse = coupling._solve_inverse
    monkeypatch.setattr(coupling, "_solve_inverse", lambda *a: inverse_calls.append(1) or solve_inverse(*a))
    forward = coupled_band_flow(profile, sigma, dp)
    assert not inverse_calls  # the shooting in x alone
    inverse = solve_inverse(profile, lambda s: float(sigma(max(s, 1e-6 * P_MAX))), dp,
                                      (0.5 * forward.flow, 2.0 * forward.flow), 1e-10)
    assert forward.converged and inverse.converged
    assert inverse.flow == pytest.approx(forward.flow, rel=1e-6, abs=0)


def test_a_trial_flow_far_off_warns_nothing():
    """The inverse integration with a bracket reaching 10^200 times below the flow: at its lower end dx/dτ overflows
    and the integrator's step-size control with it, and nothing of that reaches the user as a NumPy warning (seen on
    the CLI's stderr during an O-ring's uncertainty band); from a bracket of 10^100 the flow is found."""
    profile = PressureProfile.semi_elliptic(W, P_MAX)
    clear_caches()
    forward = coupled_band_flow(profile, sigma, 0.5 * P_MAX)
    for below in (1e-100, 1e-200):
        with warnings.catch_warnings():
            warnings.simplefilter("error")
            got = coupling._solve_inverse(profile, lambda s: float(sigma(max(s, 1e-6 * P_MAX))), 0.5 * P_MAX,
                                          (below * forward.flow, 2.0 * forward.flow), 1e-10)
        assert got.converged == (below == 1e-100)
        if got.converged:
            assert got.flow == pytest.approx(forward.flow, rel=1e-6, abs=0)


@pytest.mark.parametrize("k", [30, 60, 120])
def test_a_steep_hertz_band_against_the_closed_form_of_the_kirchhoff_transform(k):
    """For σ = σ0 exp(−s/s0) the Kirchhoff transform ψ(p_f) = ∫σ ds over [p_max − p_f, p_max] falls along the band as
    dψ/dx = −q exp((p(x) − p_max)/s0), whatever p_f (docs/theory.md eq. 13.8), so q = ψ(ΔP) / ∫exp((p − p_max)/s0) dx,
    a closed form independent of the shooting (the floor at 1e-6 p_max only touches strips where σ is e^k times its
    peak value and carries no pressure drop). With σ falling by e^15 and e^30 over ΔP the shooting meets it (the
    bracketing and Brent's method once answered the upper bound ΔP/R[p − ΔP] here, 30 times too large); at e^60 the
    pressure drops over less of the width than θ resolves, and the band is flagged, with the upper bound as its flow."""
    s0, dp = P_MAX / k, 0.5 * P_MAX

    def steep(s):
        return SIGMA0 * np.exp(-np.asarray(s, dtype=float) / s0)

    psi = SIGMA0 * s0 * (np.exp(-(P_MAX - dp) / s0) - np.exp(-P_MAX / s0))
    weight = integrate.quad(lambda x: np.exp(P_MAX * (np.sqrt(max(0.0, 1.0 - (2.0 * x / W - 1.0) ** 2)) - 1.0) / s0),
                            0.0, W, points=[W / 2], epsabs=0.0, epsrel=1e-13, limit=500)[0]
    clear_caches()
    got = coupled_band_flow(PressureProfile.semi_elliptic(W, P_MAX), steep, dp)
    if k < 100:
        assert got.converged
        assert got.flow == pytest.approx(psi / weight, rel=1e-6, abs=0)
    else:
        open_resistance = integrate.quad(
            lambda x: 1.0 / float(steep(max(P_MAX * np.sqrt(max(0.0, 1.0 - (2.0 * x / W - 1.0) ** 2)) - dp,
                                            1e-6 * P_MAX))), 0.0, W, points=[W / 2], epsabs=0.0, epsrel=1e-10,
            limit=500)[0]
        assert not got.converged
        assert got.flow == pytest.approx(dp / open_resistance, rel=1e-3, abs=0) and got.flow > psi / weight


@pytest.mark.parametrize("fraction", [0.05, 0.5, 0.95])
def test_loose_shots_far_from_the_root_leave_the_root_alone(fraction, monkeypatch):
    """Newton's first shots integrate at coupling.LOOSE_RTOL, those after a step in ln q below LOOSE_STEP at
    coupling.SHOT_RTOL: the flow is that of shots all at SHOT_RTOL within the shooting's tolerance, and the shot that ends
    it is a tight one."""
    profile = PressureProfile.semi_elliptic(W, P_MAX)
    tolerances = []
    real_ode = coupling.ode

    class Recording:
        def __init__(self, f):
            self.solver = real_ode(f)

        def set_integrator(self, name, **kw):
            tolerances.append(kw["rtol"])
            self.solver.set_integrator(name, **kw)
            return self.solver

    monkeypatch.setattr(coupling, "ode", Recording)
    clear_caches()
    mixed = coupled_band_flow(profile, sigma, fraction * P_MAX)
    assert coupling.LOOSE_RTOL in tolerances and tolerances[-1] == coupling.SHOT_RTOL  # (both kinds of shot were taken)
    monkeypatch.setattr(coupling, "LOOSE_RTOL", coupling.SHOT_RTOL)
    clear_caches()
    tight = coupled_band_flow(profile, sigma, fraction * P_MAX)
    assert mixed.converged and tight.converged
    assert mixed.flow == pytest.approx(tight.flow, rel=coupling.FLOW_RTOL, abs=0)  # (3.4e-9 at most on one machine)


def test_a_newton_step_taken_unconfirmed_lands_where_a_confirming_shot_would(monkeypatch):
    """Newton's last step from a shot at coupling.SHOT_RTOL is taken without a shot to confirm it where C δ² (C from the last two
    steps, at least coupling.NEWTON_CURVATURE) is below rtol/10: the flow is that of solving on until a step falls
    below 10 rtol (the criterion alone, NEWTON_CURVATURE infinite), within the ODE's own error, with a shot fewer where
    the criterion holds. Whether it holds for one band may turn on the last bits of its steps, which differ between CPUs
    (a band at 0.95 p_max sits at the border on some), so a shot fewer is asked of the five bands together (here the ones
    at 0.65 and 0.7 p_max save one each)."""
    profile = PressureProfile.semi_elliptic(W, P_MAX)
    early, confirmed = [], []
    curvature = coupling.NEWTON_CURVATURE
    for fraction in (0.05, 0.5, 0.65, 0.7, 0.95):
        monkeypatch.setattr(coupling, "NEWTON_CURVATURE", curvature)
        clear_caches()
        early.append(coupled_band_flow(profile, sigma, fraction * P_MAX))
        monkeypatch.setattr(coupling, "NEWTON_CURVATURE", float("inf"))
        clear_caches()
        confirmed.append(coupled_band_flow(profile, sigma, fraction * P_MAX))
    for a, b in zip(early, confirmed, strict=True):
        assert a.converged and b.converged
        # within the flow's tolerance, FLOW_RTOL = 1e-7: C δ² < rtol/10 estimates the error left, it does not bound it
        # (the answers differ by 4e-9 at most on one machine, by 1.1e-8 at 0.65 p_max on another)
        assert a.flow == pytest.approx(b.flow, rel=coupling.FLOW_RTOL, abs=0)
        assert a.shots <= b.shots
    assert sum(a.shots for a in early) < sum(b.shots for b in confirmed)


def _early(steps, rtol=1e-9):
    """Walk a sequence of Newton steps |δ_k| (in ln q): at every k where coupling._settled takes the step as the answer,
    the steps left after it (the error of that answer) sum to at most rtol. Returns the k where it does so although the
    step is above 10 rtol (a shot early)."""
    settled = [k for k in range(1, steps.size - 1) if coupling._settled(float(steps[k]), float(steps[k - 1]), rtol)]
    assert settled
    for k in settled:
        assert steps[k + 1:].sum() <= rtol
    return [k for k in settled if steps[k] > 10 * rtol]


@pytest.mark.parametrize("rate", [0.01, 0.05, 0.3, 0.6])
def test_the_answer_is_within_rtol_where_newton_converges_only_linearly(rate):
    """Near sealing Newton converges only linearly (δ_k = δ_0 ρ^k, rates 0.4–0.6 on the sweep): the answer is within
    rtol there too (a step below 10 rtol alone would leave up to 10 rtol ρ/(1 − ρ), 1.5e-8 at ρ = 0.6; C δ² alone
    up to 1e-10/ρ)."""
    _early(1e-1 * rate ** np.arange(400.0))


@pytest.mark.parametrize("curvature", [0.5, 10.0, 1e3])
@pytest.mark.parametrize("first", [1e-1, 3e-3, 1e-4])
def test_the_answer_is_within_rtol_where_newton_converges_quadratically(curvature, first):
    """δ_{k+1} = C δ_k²: wherever a step is taken as the answer, early or not, it is within rtol."""
    steps = [first / curvature]
    while steps[-1] > 1e-30:
        steps.append(curvature * steps[-1] ** 2)
    _early(np.array(steps))


def test_a_small_enough_newton_step_is_taken_a_shot_early():
    """C = 1 from δ = 5e-4: the next step, 2.5e-7 (25× above 10 rtol), is the answer (its error 6e-14)."""
    assert _early(np.array([5e-4, 2.5e-7, 6.25e-14, 3.9e-27])) == [1]


def test_a_trial_flow_not_from_a_newton_step_is_not_settled_early():
    """Without the step before (bisection, false position, a failed shot), only a step below 10 rtol ends the solve."""
    assert not coupling._settled(1e-7, None, 1e-9)
    assert coupling._settled(1e-8, None, 1e-9)
    assert not coupling._settled(1e-7, 1e-7, 1e-9)  # (a step that did not shrink)


def test_a_peak_a_hair_from_the_percolation_limit_seals_without_overflow():
    """σ at the peak below the smallest normal double (u_c of ~1e-103 m: a peak within a hair of the percolation
    limit) counts as no leak channel: the band is sealed, R infinite, no gas sheet, and no warning or math error (a
    denormal σ made 1/σ overflow, R infinite and the shooting take ln 0: a traceback). Just above the floor the band
    is solved as any other, its flow ΔP/R(p − ΔP) or less."""
    profile = PressureProfile.semi_elliptic(W, P_MAX)

    def closing(at_peak):
        """σ falling exponentially to ``at_peak`` at p_max (m³/(Pa·s))."""
        scale = np.log(SIGMA0 / at_peak) / P_MAX
        return lambda s: SIGMA0 * np.exp(-np.asarray(s, dtype=float) * scale)

    with warnings.catch_warnings():
        warnings.simplefilter("error")  # (an overflow warning fails the test)
        clear_caches()
        sealed = closing(1.5e-319)
        band = coupled_band_flow(profile, sealed, 0.05 * P_MAX)
        assert band.flow == 0.0 and band.converged
        r = series_resistance(profile, sealed)
        assert r.sealed and r.resistance == np.inf
        assert gas_sheet(lambda s: (sealed(s), np.full(np.size(s), 1e-9), np.full(np.size(s), 1e-8)),
                         1e-6 * P_MAX, P_MAX) is None
        open_band = coupled_band_flow(profile, closing(1e3 * SIGMA_FLOOR), 0.05 * P_MAX)
    assert 0.0 < open_band.flow and not series_resistance(profile, closing(1e3 * SIGMA_FLOOR)).sealed
