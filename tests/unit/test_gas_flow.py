"""Gas flow through a gap field (numerics._gas_flow): the p² problem, the slip fixed point, its checks.

Every expected value is computed independently of the solver: closed forms of a straight channel,
the physics layer's own quadrature (``pressure_integral``, scipy ``quad``), or the liquid solver
(``solve_flow``) on a field whose conductance is the limit the gas solve must reach.
"""

import math

import numpy as np
import pytest

from sealeak.errors import ConvergenceError, InputError
from sealeak.numerics import solve_contact, solve_flow, solve_gas_flow
from sealeak.numerics._gas_flow import secant_slip_factor
from sealeak.numerics.synthesis import synthesize
from sealeak.physics.gas import BK_ALPHA0, Gas, pressure_integral, slip_factor
from sealeak.physics.spectrum import PowerSpectrum

# helium at 20 °C (μ, M rounded from the reference data of test_gas.py; any values serve these checks)
HELIUM = Gas("helium", 293.15, 19.6e-6, 4.0026e-3)
AIR = Gas("air", 293.15, 18.2e-6, 28.965e-3)
L = 1e-3  # side of the square (m), W = L

BK = "beskok-karniadakis"


def channel(n=16, gap=0.5e-6):
    return np.full((n, n), gap)


def no_slip_k(gap, gas):
    """K = (W/L) h³/(12μ) of a straight channel of constant gap (W = L)."""
    return gap**3 / (12.0 * gas.viscosity)


def centres(n):
    return (np.arange(n) + 0.5) / n  # x/L of the cell centres


@pytest.fixture(scope="module")
def rough():
    """A 32² contact gap field of a self-affine surface at about 20 % contact, percolating."""
    n, size = 32, 1e-3
    q0 = 2 * math.pi / size
    spec = PowerSpectrum.self_affine(hurst=0.8, q_rolloff=2 * q0, q_cutoff=8 * q0, q_lowest=q0, h_rms=2e-6)
    h = synthesize(spec, n, size, seed=3)
    res = solve_contact(h, size, 2e6, 5e3)
    assert 0.05 < res.contact_area < 0.4
    return res.gap, res.contact, size


# ------------------------------------------------------------------ without slip: the p² problem
@pytest.mark.parametrize("method", ["direct", "amg"])
@pytest.mark.parametrize("pa, pb", [(1e5, 0.0), (2e5, 1e5), (1e5, 99e3), (1e3, 10.0)])
def test_straight_channel_no_slip_closed_form(method, pa, pb):
    """p(x)² = P_a² − (P_a² − P_b²) x/L and ṁ = K (P_a² − P_b²)/(2 R_s T), K = h³/(12μ) (W = L)."""
    n, h = 16, 0.5e-6
    res = solve_gas_flow(channel(n, h), L, HELIUM, pa, pb, model="no-slip", method=method, rtol=1e-10)
    x = centres(n)
    exact_p = np.sqrt(pa**2 - (pa**2 - pb**2) * x)
    assert np.allclose(res.pressure, exact_p[:, None], rtol=1e-8, atol=0)
    rst = 8.314462618 / HELIUM.molar_mass * HELIUM.temperature
    exact_m = no_slip_k(h, HELIUM) * (pa**2 - pb**2) / (2 * rst)
    assert res.mass_flow == pytest.approx(exact_m, rel=1e-8, abs=0)
    assert res.throughput == pytest.approx(exact_m * rst, rel=1e-8, abs=0)
    assert res.iterations == 0 and res.percolates


def test_no_slip_mean_pressure_volume_flow_is_the_liquid_formula(rough):
    """Q_pV/P̄ = K0 ΔP exactly, whatever ΔP (docs/theory.md §11.3): the liquid solve with the gas's viscosity."""
    gap, contact, size = rough
    pa, pb = 3e5, 2e4
    gas = solve_gas_flow(gap, size, AIR, pa, pb, contact=contact, model="no-slip")
    liquid = solve_flow(gap, size, AIR.viscosity, pa - pb, contact=contact)
    assert gas.throughput / (0.5 * (pa + pb)) == pytest.approx(liquid.flux, rel=1e-9, abs=0)


# ------------------------------------------------------------------ with slip: closed forms of a channel
@pytest.mark.parametrize("model", [BK, "kinetic"])
@pytest.mark.parametrize("pa, pb", [(1e5, 0.0), (1e3, 0.0), (10.0, 0.0), (3e5, 1e5), (2e3, 1e3)])
def test_straight_channel_with_slip_integral_falls_linearly(pa, pb, model):
    """∫_{p(x)}^{P_a} p f dp = (x/L) ∫_{P_b}^{P_a} p f dp (mass conservation, docs/theory.md §11.5), and
    Q_pV = K ∫ p f dp, against the physics layer's adaptive quadrature."""
    n, h = 16, 0.5e-6
    res = solve_gas_flow(channel(n, h), L, HELIUM, pa, pb, method="direct", tol=1e-11, rtol=1e-12, model=model)
    total = pressure_integral(h, HELIUM, pa, pb, model)
    assert res.throughput == pytest.approx(no_slip_k(h, HELIUM) * total, rel=1e-8, abs=0)
    x = centres(n)
    along = np.array([pressure_integral(h, HELIUM, pa, p, model) for p in res.pressure[:, 5]])
    assert np.allclose(along, x * total, rtol=1e-8, atol=0)
    assert np.ptp(res.pressure, axis=1).max() <= 1e-12 * pa  # nothing changes across the channel
    # the slip matters in these cases: the no-slip throughput is measurably smaller
    assert res.throughput > (1 + 1e-3) * res.throughput_no_slip


@pytest.mark.parametrize("gas", [HELIUM, AIR], ids=["helium", "air"])
def test_kn_to_zero_slip_solve_tends_to_the_p2_solve(rough, gas):
    """f = 1 + 6 Kn + ...: with gaps a thousand and a million times wider the slip route approaches the
    p² route as O(Kn), in ṁ and in the pressure field."""
    gap, contact, size = rough
    pa, pb = 1e6, 1e5
    excess = []
    for scale in (1e3, 1e6):
        wide = gap * scale
        slip = solve_gas_flow(wide, size, gas, pa, pb, contact=contact, tol=1e-11, rtol=1e-12)
        plain = solve_gas_flow(wide, size, gas, pa, pb, contact=contact, model="no-slip", rtol=1e-12)
        kn_max = float(np.nanmax(slip.knudsen))
        excess.append(slip.mass_flow / plain.mass_flow - 1)
        assert 0 < excess[-1] <= 7 * kn_max
        assert np.nanmax(np.abs(slip.pressure - plain.pressure)) <= 7 * kn_max * pa
    assert kn_max < 1e-3
    assert excess[1] < excess[0] / 500  # linear in Kn ∝ 1/scale


def test_kn_to_infinity_is_free_molecular_flow(rough):
    """f → 7 α0 Kn: the flux of p² becomes (g³/12μ) 7 α0 (c/p) ∇p² = 2 G_fm(g) ∇p/... linear in p with a
    conductance ∝ g² (docs/theory.md §11.4), i.e. the liquid problem on the field g^(2/3):
    Q_pV → (7 α0/12) √(π R_s T/2) K[g²] ΔP. The approach is slow (α(Kn) → α0 as Kn^−0.4)."""
    gap, contact, size = rough
    fm_field = solve_flow(np.where(contact, 0.0, gap) ** (2.0 / 3.0), size, 1.0 / 12.0, 1.0, contact=contact).conductance
    coeff = 7 * BK_ALPHA0 / 12 * math.sqrt(0.5 * math.pi * HELIUM.specific_gas_constant * HELIUM.temperature)
    errors = []
    for pa in (1e-2, 1e-5):  # Kn from ~1e6 to ~1e12 over the gaps
        res = solve_gas_flow(gap, size, HELIUM, pa, 0.0, contact=contact, tol=1e-10, rtol=1e-11, model=BK)
        errors.append(abs(res.throughput / (coeff * fm_field * pa) - 1))
        kn_min = float(np.nanmin(res.knudsen))
        assert errors[-1] <= 0.2 * kn_min**-0.4  # the leading correction of α(Kn): (2/π)/(4 Kn^0.4) = 0.16 Kn^-0.4
    assert errors[1] < errors[0] / 10


def test_small_pressure_drop_tends_to_the_liquid_formula_with_slip(rough):
    """ΔP ≪ P: Q_pV/P̄ → the liquid flow through σ = g³ f(Kn(g, P̄))/(12μ) (docs/theory.md §11.5), to O((ΔP/P)²)."""
    gap, contact, size = rough
    pm, dp = 2e4, 2.0
    res = solve_gas_flow(gap, size, AIR, pm + dp / 2, pm - dp / 2, contact=contact, tol=1e-11, rtol=1e-12)
    f = slip_factor(AIR.knudsen_number(np.where(contact, 1.0, gap), pm))
    liquid = solve_flow(gap * np.cbrt(f), size, AIR.viscosity, dp, contact=contact)
    assert res.throughput / pm == pytest.approx(liquid.flux, rel=3e-6, abs=0)  # (8e-7 here)
    assert res.throughput / pm > (1 + 1e-3) * solve_flow(gap, size, AIR.viscosity, dp, contact=contact).flux


# ------------------------------------------------------------------ rough field: conservation and bounds
@pytest.mark.parametrize("pa, pb", [(1e5, 0.0), (1e5, 5e4), (100.0, 1.0)])
def test_rough_field_conserves_mass_and_lies_between_its_slip_bounds(rough, pa, pb):
    gap, contact, size = rough
    res = solve_gas_flow(gap, size, HELIUM, pa, pb, contact=contact, method="direct")
    assert res.percolates and res.method == "direct"
    assert res.outflow == pytest.approx(res.inflow, rel=1e-8, abs=0)
    assert res.conservation_error <= 1e-8
    # every face's factor F lies between f at the highest and f at the lowest pressure of its cells
    # (Rayleigh monotonicity of a resistor network): the enhancement of ṁ over no-slip is bounded so
    solved = np.isfinite(res.pressure)
    lo = float(np.min(slip_factor(HELIUM.knudsen_number(gap[solved], pa))))
    hi = float(np.max(slip_factor(HELIUM.knudsen_number(gap[solved], pb)))) if pb > 0 else math.inf
    ratio = res.throughput / res.throughput_no_slip
    assert lo <= ratio <= hi and ratio > 1
    # pressures obey the maximum principle and the Knudsen field is λ(p)/g
    assert np.nanmin(res.pressure) >= pb and np.nanmax(res.pressure) <= pa
    assert np.allclose(res.knudsen[solved], HELIUM.knudsen_number(gap[solved], res.pressure[solved]), rtol=1e-12)
    assert np.isnan(res.knudsen[~solved]).all()


def test_direct_and_amg_agree(rough):
    gap, contact, size = rough
    a = solve_gas_flow(gap, size, AIR, 1e5, 0.0, contact=contact, method="direct")
    b = solve_gas_flow(gap, size, AIR, 1e5, 0.0, contact=contact, method="amg")
    assert b.method == "amg" and b.conservation_error <= 1e-8
    assert b.mass_flow == pytest.approx(a.mass_flow, rel=2e-6, abs=0)
    assert np.nanmax(np.abs(b.pressure - a.pressure)) <= 2e-6 * 1e5


# ------------------------------------------------------------------ the fixed point
def test_fixed_point_error_is_within_its_tolerance(rough):
    """The default tolerance's result against a much tighter solve: the accepted error is below tol."""
    gap, contact, size = rough
    loose = solve_gas_flow(gap, size, HELIUM, 1e3, 0.0, contact=contact, tol=1e-5, rtol=1e-8)
    tight = solve_gas_flow(gap, size, HELIUM, 1e3, 0.0, contact=contact, tol=1e-11, rtol=1e-12)
    assert 1 < loose.iterations < tight.iterations
    assert abs(loose.mass_flow / tight.mass_flow - 1) <= 1e-5
    assert np.nanmax(np.abs(loose.pressure - tight.pressure)) <= 1e-5 * 1e3
    assert max(loose.mass_flow_change, loose.pressure_change) <= 1e-5
    assert loose.error_estimate <= 1e-5


@pytest.mark.parametrize("max_iter", [1, 2, 3])
def test_a_fixed_point_that_has_not_converged_is_refused(rough, max_iter):
    gap, contact, size = rough
    with pytest.raises(ConvergenceError, match=f"did not converge in {max_iter} iterations"):
        solve_gas_flow(gap, size, HELIUM, 1e3, 0.0, contact=contact, tol=1e-10, rtol=1e-11, max_iter=max_iter)


# ------------------------------------------------------------------ the secant factor
@pytest.mark.parametrize("kn", [1e-8, 1e-3, 0.05, 1.0, 30.0, 1e4, 1e8])
@pytest.mark.parametrize("ratio", [0.0, 1e-9, 1e-3, 0.2, 0.26, 0.7, 0.999])
@pytest.mark.parametrize("model", [BK, "kinetic"])
def test_secant_factor_against_adaptive_quadrature(kn, ratio, model):
    """F (p1² − p2²)/2 = ∫ p f dp, the physics layer's quad (relative tolerance 1e-12) or the kinetic
    model's closed form; Kn at the higher pressure."""
    h, p1 = 1e-6, 1e4
    c = HELIUM.rarefaction_pressure_scale / h
    gas = Gas("x", HELIUM.temperature, HELIUM.viscosity * kn * p1 / c, HELIUM.molar_mass)  # Kn(p1) = kn
    p2 = ratio * p1
    F = secant_slip_factor(gas.rarefaction_pressure_scale / h, p1, p2, model)
    assert F * 0.5 * (p1**2 - p2**2) == pytest.approx(pressure_integral(h, gas, p1, p2, model), rel=1e-10)
    assert secant_slip_factor(gas.rarefaction_pressure_scale / h, p2, p1, model) == F  # symmetric


def test_secant_factor_of_an_empty_interval_is_the_local_factor():
    c = np.array([10.0, 1e3, 1e5])
    assert np.allclose(secant_slip_factor(c, 1e4, 1e4), slip_factor(c / 1e4), rtol=1e-14)


# ------------------------------------------------------------------ what is refused, and blocked flow
def test_blocked_field_has_no_flow():
    gap = channel(16)
    contact = np.zeros(gap.shape, dtype=bool)
    contact[7, :] = True
    res = solve_gas_flow(gap, L, HELIUM, 1e5, 0.0, contact=contact)
    assert not res.percolates and res.mass_flow == 0.0 and res.throughput == 0.0
    assert np.isnan(res.pressure).all()


@pytest.mark.parametrize("kwargs, field", [
    (dict(upstream_pressure=-1.0), "upstream_pressure"),
    (dict(downstream_pressure=-5.0), "downstream_pressure"),
    (dict(upstream_pressure=1e4, downstream_pressure=1e5), "upstream_pressure"),
    (dict(upstream_pressure=1e5, downstream_pressure=1e5), "upstream_pressure"),
    (dict(upstream_pressure=math.nan), "upstream_pressure"),
    (dict(upstream_pressure=math.inf), "upstream_pressure"),
    (dict(model="maxwell"), "rarefaction_model"),
    (dict(gas="helium"), "gas"),
    (dict(gap=np.ones((4, 5)) * 1e-6), "gap"),
    (dict(gap=np.full((1, 1), 1e-6)), "gap"),
    (dict(gap=np.full((8, 8), np.nan)), "gap"),
    (dict(size=0.0), "size"),
    (dict(tol=0.0), "tol"),
    (dict(tol=0.5), "tol"),
    (dict(rtol=0.0), "rtol"),
    (dict(max_iter=0), "max_iter"),
    (dict(method="lu"), "method"),
])
def test_bad_input_names_the_field(kwargs, field):
    args = dict(gap=channel(8), size=L, gas=HELIUM, upstream_pressure=1e5, downstream_pressure=0.0)
    args.update(kwargs)
    with pytest.raises(InputError) as err:
        solve_gas_flow(**args)
    assert err.value.field == field
