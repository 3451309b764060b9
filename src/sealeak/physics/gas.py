"""Gas flow through the constrictions of a seal: compressible, isothermal, viscous, with rarefaction.

Plain SI floats; no property library here (named fluids: :mod:`sealeak.physics.properties`).
docs/theory.md §11:

* ideal gas at the temperature T of the seal: ρ = p/(R_s T), R_s = R/M;
* mean free path λ = (μ/p) √(π R_s T/2) and Knudsen number Kn = λ/h at a gap h (§Mean free path and Knudsen number);
* isothermal viscous flow through a channel of (no-slip) conductance K = σ W/L in m³/(Pa·s): the
  mass flow is ṁ = K (P_a² − P_b²)/(2 R_s T) and the pV throughput Q_pV = K (P_a² − P_b²)/2 (§Compressible isothermal viscous flow);
  a liquid keeps Q = K ΔP;
* rarefaction: the sheet conductance of a slit of height h is h³/(12 μ) · f(Kn) with the unified
  model of Beskok & Karniadakis (1999) for f (§Rarefaction: the slit conductance); Kn ∝ 1/p varies along the pressure drop, so
  Q_pV = K ∫_{P_b}^{P_a} p f(Kn(p)) dp (§Integration along the pressure drop); for Kn → ∞ this is free-molecular flow,
  Q_pV = (W/L) G_fm ΔP with G_fm = (7 α0/12) h² √(π R_s T/2).

Errors name the functions' own parameters (``upstream_pressure``, ``temperature``, ...).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.integrate import quad

from ..errors import InputError
from ..io.leak_units import MOLAR_GAS_CONSTANT  # R = N_A k_B, J/(mol·K); exported here too
from ..io.quantities import quantity

__all__ = [
    "MOLAR_GAS_CONSTANT", "RAREFACTION_MODELS", "BK_ALPHA0", "BK_ALPHA1", "BK_BETA", "Gas", "check_pressures",
    "flow_regime", "slip_factor", "free_molecular_coefficient", "sheet_conductance", "pressure_integral",
    "viscous_throughput", "viscous_mass_flow", "GasLeak", "gas_leak",
]

FloatArray = NDArray[np.float64]

#: Rarefaction models of :func:`slip_factor`: the unified model of Beskok & Karniadakis (1999), or
#: none (no-slip continuum flow at every Kn, the liquid law with the gas's viscosity).
RAREFACTION_MODELS = ("beskok-karniadakis", "no-slip")

#: Beskok & Karniadakis (1999) parameters for a channel with diffuse walls (σ_v = 1) and their
#: general slip condition with b = −1: α0 = 64/(3π(1 − 4/b)) = 64/(15π), α1 = 4, β = 0.4.
BK_ALPHA0 = 64.0 / (15.0 * math.pi)
BK_ALPHA1 = 4.0
BK_BETA = 0.4

#: Flow regimes by the Knudsen number (Schaaf & Chambré 1961; Karniadakis, Beskok & Aluru 2005, §1.2).
_REGIMES = ((1e-3, "continuum"), (0.1, "slip"), (10.0, "transition"), (math.inf, "free molecular"))


def _finite(name: str, value: float, *, positive: bool = True, allow_zero: bool = False) -> float:
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise InputError(name, value, "must be a number") from None
    if not math.isfinite(v) or (positive and (v < 0 or (v == 0 and not allow_zero))):
        raise InputError(name, value, "must be finite and >= 0" if allow_zero else "must be finite and > 0")
    return v


@dataclass(frozen=True)
class Gas:
    """An ideal gas at temperature ``temperature`` (K) with ``viscosity`` μ (Pa·s) and ``molar_mass`` M (kg/mol).

    The viscosity of a dilute gas does not depend on the pressure (Maxwell; docs/theory.md §11.1):
    one μ at the seal's temperature serves the whole pressure drop. ``name`` is for messages.
    """

    name: str
    temperature: float = quantity("K", "temperature of the gas")
    viscosity: float = quantity("Pa*s", "dynamic viscosity μ of the gas")
    molar_mass: float = quantity("kg/mol", "molar mass M of the gas")

    def __post_init__(self) -> None:
        t = _finite("temperature", self.temperature)
        if t < 1.0:
            raise InputError("temperature", self.temperature, "must be an absolute temperature in K (> 1 K)")
        _finite("viscosity", self.viscosity)
        m = _finite("molar_mass", self.molar_mass)
        if not 1e-3 <= m <= 1.0:
            raise InputError("molar_mass", self.molar_mass, "must be a molar mass in kg/mol (e.g. 0.004 for helium)")

    @property
    def specific_gas_constant(self) -> float:
        """R_s = R/M in J/(kg·K)."""
        return MOLAR_GAS_CONSTANT / self.molar_mass

    @property
    def mean_thermal_speed(self) -> float:
        """v̄ = √(8 R_s T/π) in m/s: the mean molecular speed of a Maxwell distribution (docs/theory.md §11.2)."""
        return math.sqrt(8.0 * self.specific_gas_constant * self.temperature / math.pi)

    @property
    def rarefaction_pressure_scale(self) -> float:
        """μ √(π R_s T/2) in Pa·m: λ p, the same at every pressure; Kn = (this)/(p h) (docs/theory.md §11.2)."""
        return self.viscosity * math.sqrt(0.5 * math.pi * self.specific_gas_constant * self.temperature)

    def density(self, pressure: ArrayLike) -> FloatArray:
        """ρ = p/(R_s T) in kg/m³ at absolute pressure ``pressure`` (Pa), ideal gas."""
        return np.asarray(pressure, dtype=float) / (self.specific_gas_constant * self.temperature)

    def mean_free_path(self, pressure: ArrayLike) -> FloatArray:
        """λ = (μ/p) √(π R_s T/2) in m at absolute pressure ``pressure`` (Pa; inf at p = 0; docs/theory.md §11.2)."""
        p = np.asarray(pressure, dtype=float)
        with np.errstate(divide="ignore"):
            return self.rarefaction_pressure_scale / p

    def knudsen_number(self, gap: ArrayLike, pressure: ArrayLike) -> FloatArray:
        """Kn = λ(p)/h for a gap h (m) at absolute pressure p (Pa) (docs/theory.md §11.2)."""
        h = np.asarray(gap, dtype=float)
        with np.errstate(divide="ignore", invalid="ignore"):
            return self.mean_free_path(pressure) / h


def check_pressures(upstream: float, downstream: float) -> tuple[float, float]:
    """The absolute pressures (Pa) of a gas leak, checked: both finite, ``upstream_pressure`` > 0,
    ``downstream_pressure`` >= 0 (vacuum allowed) and not above the upstream one."""
    for name, value in (("upstream_pressure", upstream), ("downstream_pressure", downstream)):
        try:
            v = float(value)
        except (TypeError, ValueError):
            raise InputError(name, value, "must be an absolute pressure (a number, Pa)") from None
        if not math.isfinite(v) or v < 0:
            raise InputError(name, value, "must be an absolute pressure: finite and >= 0 (0 is vacuum)")
    pa, pb = float(upstream), float(downstream)
    if pa <= 0:
        raise InputError("upstream_pressure", upstream, "must be an absolute pressure > 0")
    if pa < pb:
        raise InputError("upstream_pressure", upstream,
                         f"must not be below the downstream pressure {pb:.6g} Pa (the gas flows from upstream to downstream)")
    return pa, pb


def flow_regime(knudsen: float) -> str:
    """"continuum" (Kn < 0.001), "slip" (< 0.1), "transition" (< 10) or "free molecular" (docs/theory.md §11.2)."""
    if not knudsen >= 0:
        raise InputError("knudsen", knudsen, "must be >= 0")
    return next((name for limit, name in _REGIMES if knudsen < limit), _REGIMES[-1][1])


def slip_factor(knudsen: ArrayLike, model: str = "beskok-karniadakis") -> FloatArray:
    """f(Kn): the slit's flow divided by the no-slip Poiseuille flow h³/(12μ) (docs/theory.md §11.4: the slit conductance).

    Beskok & Karniadakis (1999), channel with diffuse walls:
    f = (1 + α(Kn) Kn) (1 + 6 Kn/(1 + Kn)), α(Kn) = α0 (2/π) arctan(α1 Kn^β),
    α0 = 64/(15π), α1 = 4, β = 0.4. f → 1 + 6 Kn (first-order Maxwell slip) for Kn → 0 and
    f → 7 α0 Kn (free-molecular flow, a finite conductance) for Kn → ∞. ``model="no-slip"``: f = 1.
    """
    kn = np.asarray(knudsen, dtype=float)
    if model == "no-slip":
        return np.ones_like(kn)
    if model != "beskok-karniadakis":
        raise InputError("rarefaction_model", model, f"must be one of {', '.join(RAREFACTION_MODELS)}")
    if np.any(~(kn >= 0)):
        raise InputError("knudsen", knudsen, "must be >= 0")
    with np.errstate(over="ignore", invalid="ignore"):
        alpha = BK_ALPHA0 * (2.0 / math.pi) * np.arctan(BK_ALPHA1 * kn**BK_BETA)
        out = (1.0 + alpha * kn) * (1.0 + 6.0 * kn / (1.0 + kn))
    return np.where(np.isinf(kn), np.inf, out)


def free_molecular_coefficient(gap: ArrayLike, gas: Gas) -> FloatArray:
    """G_fm = (7 α0/12) h² √(π R_s T/2) in m³/s: the limit Kn → ∞ of h³/(12μ) · f(Kn) · p (docs/theory.md §11.4: the slit conductance).

    Per unit width of a slit of height h (m), the free-molecular pV throughput is q = −G_fm dp/dx;
    it depends on neither the pressure nor the viscosity. G_fm = (7 α0 π/48) h² v̄ ≈ 0.622 h² v̄.
    """
    h = np.asarray(gap, dtype=float)
    return (7.0 * BK_ALPHA0 / 12.0) * h**2 * math.sqrt(0.5 * math.pi * gas.specific_gas_constant * gas.temperature)


def sheet_conductance(gap: ArrayLike, gas: Gas, pressure: ArrayLike, model: str = "beskok-karniadakis") -> FloatArray:
    """σ(h, p) = h³/(12 μ) f(λ(p)/h) in m³/(Pa·s): the local sheet conductance of a slit of height h (m)
    for a gas at absolute pressure p (Pa) (docs/theory.md §11.4: the slit conductance). At Kn → 0 this is the liquid's h³/(12μ)."""
    h = np.asarray(gap, dtype=float)
    return h**3 / (12.0 * gas.viscosity) * slip_factor(gas.knudsen_number(h, pressure), model)


def _integrand(p: float, c: float) -> float:
    """p f(c/p) for the Beskok–Karniadakis f, written so that p = 0 (Kn = ∞) is finite: (p + α c)(1 + 6c/(p + c))."""
    if p <= 0.0:
        alpha = BK_ALPHA0
    else:
        alpha = BK_ALPHA0 * (2.0 / math.pi) * math.atan(BK_ALPHA1 * (c / p) ** BK_BETA)
    if c == 0.0:
        return p
    return (p + alpha * c) * (1.0 + 6.0 * c / (p + c))


def pressure_integral(gap: float, gas: Gas, upstream: float, downstream: float, model: str = "beskok-karniadakis") -> float:
    """I = ∫_{P_b}^{P_a} p f(Kn(p)) dp in Pa² with Kn(p) = λ(p)/h (docs/theory.md §11.5).

    The pV throughput of a channel of no-slip conductance K (m³/(Pa·s)) whose narrowest gap is
    ``gap`` h (m) is Q_pV = K I. Without rarefaction (``model="no-slip"``, or Kn → 0)
    I = (P_a² − P_b²)/2; for Kn → ∞, I = 7 α0 c ΔP with c = λ p/h. Adaptive quadrature
    (scipy.integrate.quad, relative tolerance 1e-12): the integrand is finite at p = 0 (vacuum).
    """
    pa, pb = check_pressures(upstream, downstream)
    h = _finite("gap", gap)
    if model not in RAREFACTION_MODELS:
        raise InputError("rarefaction_model", model, f"must be one of {', '.join(RAREFACTION_MODELS)}")
    if pa == pb:
        return 0.0
    if model == "no-slip":
        return 0.5 * (pa - pb) * (pa + pb)
    c = gas.rarefaction_pressure_scale / h
    value, _err = quad(_integrand, pb, pa, args=(c,), epsabs=0.0, epsrel=1e-12, limit=400)
    return float(value)


def viscous_throughput(conductance: ArrayLike, upstream: float, downstream: float) -> FloatArray:
    """Q_pV = K (P_a² − P_b²)/2 in Pa·m³/s: isothermal no-slip gas flow through a channel of conductance
    K (m³/(Pa·s)) between absolute pressures P_a ≥ P_b (Pa) (docs/theory.md §11.3)."""
    pa, pb = check_pressures(upstream, downstream)
    return np.asarray(conductance, dtype=float) * 0.5 * (pa - pb) * (pa + pb)


def viscous_mass_flow(conductance: ArrayLike, upstream: float, downstream: float, gas: Gas) -> FloatArray:
    """ṁ = K (P_a² − P_b²)/(2 R_s T) in kg/s (docs/theory.md §11.3)."""
    return viscous_throughput(conductance, upstream, downstream) / (gas.specific_gas_constant * gas.temperature)


@dataclass(frozen=True, kw_only=True)
class GasLeak:
    """A gas leak through a channel of no-slip conductance K whose narrowest gap is h (docs/theory.md §11.5).

    Attributes
    ----------
    throughput
        Q_pV = K ∫ p f dp in Pa·m³/s, counted at the gas temperature T.
    throughput_no_slip
        K (P_a² − P_b²)/2 in Pa·m³/s: the same channel without rarefaction.
    mass_flow, molar_flow
        ṁ = Q_pV/(R_s T) in kg/s and ṅ = Q_pV/(R T) in mol/s.
    knudsen_upstream, knudsen_mean, knudsen_downstream
        Kn = λ/h at P_a, at the mean pressure (P_a + P_b)/2 and at P_b (inf for vacuum).
    regime
        The flow regime at the mean pressure (:func:`flow_regime`).
    rarefaction_model
        The model of f(Kn) used.
    """

    throughput: float
    throughput_no_slip: float
    mass_flow: float
    molar_flow: float
    knudsen_upstream: float
    knudsen_mean: float
    knudsen_downstream: float
    regime: str
    rarefaction_model: str


def gas_leak(conductance: float, gap: float, gas: Gas, upstream: float, downstream: float,
             model: str = "beskok-karniadakis") -> GasLeak:
    """The leak of ``gas`` through a channel of no-slip conductance ``conductance`` K (m³/(Pa·s), e.g.
    α (Ly/Lx) u_c³/(12μ) for the critical junction) whose narrowest gap is ``gap`` h (m), between the
    absolute pressures ``upstream`` P_a and ``downstream`` P_b (Pa) (docs/theory.md §11.5)."""
    pa, pb = check_pressures(upstream, downstream)
    k = _finite("conductance", conductance, allow_zero=True)
    h = _finite("gap", gap)
    q = k * pressure_integral(h, gas, pa, pb, model) if k > 0 else 0.0
    rt = MOLAR_GAS_CONSTANT * gas.temperature
    kn = [float(gas.knudsen_number(h, p)) for p in (pa, 0.5 * (pa + pb), pb)]
    return GasLeak(throughput=q, throughput_no_slip=k * 0.5 * (pa - pb) * (pa + pb), mass_flow=q * gas.molar_mass / rt,
                   molar_flow=q / rt, knudsen_upstream=kn[0], knudsen_mean=kn[1], knudsen_downstream=kn[2],
                   regime=flow_regime(kn[1]), rarefaction_model=model)
