"""Gas flow through the constrictions of a seal: compressible, isothermal, viscous, with rarefaction.

Plain SI floats; no property library here (named fluids: :mod:`sealeak.physics.properties`).
docs/theory.md §11:

* ideal gas at the temperature T of the seal: ρ = p/(R_s T), R_s = R/M;
* mean free path λ = (μ/p) √(π R_s T/2) and Knudsen number Kn = λ/h at a gap h (§Mean free path and Knudsen number);
* isothermal viscous flow through a channel of (no-slip) conductance K = σ W/L in m³/(Pa·s): the
  mass flow is ṁ = K (P_a² − P_b²)/(2 R_s T) and the pV throughput Q_pV = K (P_a² − P_b²)/2 (§Compressible isothermal viscous flow);
  a liquid keeps Q = K ΔP;
* rarefaction: the sheet conductance of a slit of height h is h³/(12 μ) · f(Kn) with f from the
  kinetic theory of the slit (linearized BGK, :mod:`sealeak.physics._kinetic_slit`; default) or the unified
  model of Beskok & Karniadakis (1999) (§Rarefaction: the slit conductance); Kn ∝ 1/p varies along the pressure drop, so
  Q_pV = K ∫_{P_b}^{P_a} p f(Kn(p)) dp (§Integration along the pressure drop); for Kn → ∞ this is free-molecular flow,
  Q_pV = (W/L) G_fm ΔP (:func:`free_molecular_coefficient`).

Errors name the functions' own parameters (``upstream_pressure``, ``temperature``, ...).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.integrate import quad

from ..errors import InputError, positive_number
from ..io.leak_units import MOLAR_GAS_CONSTANT  # R = N_A k_B, J/(mol·K); exported here too
from ..io.quantities import quantity
from ._kinetic_slit import capped_rarefaction, poiseuille_flow_rate
from ._kinetic_slit import pressure_integral as kinetic_pressure_integral

__all__ = [
    "MOLAR_GAS_CONSTANT", "RAREFACTION_MODELS", "DEFAULT_RAREFACTION", "check_rarefaction_model", "BK_ALPHA0", "BK_ALPHA1", "BK_BETA", "Gas", "check_pressures",
    "flow_regime", "slip_factor", "kinetic_pressure_integral", "free_molecular_coefficient", "sheet_conductance", "pressure_integral",
    "viscous_throughput", "viscous_mass_flow", "GasLeak", "gas_leak", "with_throughput", "bk_pressure_integrand",
]

FloatArray = NDArray[np.float64]

#: Rarefaction models of :func:`slip_factor`, the default first: the kinetic theory of the slit (linearized
#: BGK, diffuse walls), the unified model of Beskok & Karniadakis (1999), or none (no-slip continuum flow at
#: every Kn, the liquid law with the gas's viscosity).
RAREFACTION_MODELS = ("kinetic", "beskok-karniadakis", "no-slip")
DEFAULT_RAREFACTION = RAREFACTION_MODELS[0]

#: δ Kn = √π/2: Sharipov's rarefaction parameter δ = p h/(μ v0), v0 = √(2 R_s T), against Kn = λ/h with
#: λ = (μ/p) √(π R_s T/2) (docs/theory.md §11.4).
_DELTA_KN = 0.5 * math.sqrt(math.pi)

#: Beskok & Karniadakis (1999) parameters for a channel with diffuse walls (σ_v = 1) and their
#: general slip condition with b = −1: α0 = 64/(3π(1 − 4/b)) = 64/(15π), α1 = 4, β = 0.4.
BK_ALPHA0 = 64.0 / (15.0 * math.pi)
BK_ALPHA1 = 4.0
BK_BETA = 0.4

#: Flow regimes by the Knudsen number (Schaaf & Chambré 1961; Karniadakis, Beskok & Aluru 2005, §1.2).
_REGIMES = ((1e-3, "continuum"), (0.1, "slip"), (10.0, "transition"), (math.inf, "free molecular"))


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
        t = positive_number("temperature", self.temperature)
        if t < 1.0:
            raise InputError("temperature", self.temperature, "must be an absolute temperature in K (> 1 K)")
        positive_number("viscosity", self.viscosity)
        m = positive_number("molar_mass", self.molar_mass)
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
        """λ = (μ/p) √(π R_s T/2) in m at absolute pressure ``pressure`` (Pa; inf at p = 0; docs/theory.md §11.2, eq. 11.1)."""
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


def check_rarefaction_model(model: str) -> None:
    """Refuse a slip model not in :data:`RAREFACTION_MODELS` (InputError naming ``rarefaction_model``)."""
    if model not in RAREFACTION_MODELS:
        raise InputError("rarefaction_model", model, f"must be one of {', '.join(RAREFACTION_MODELS)}")


def _length_ratio(length: float | None, gap: float) -> float | None:
    """ℓ = L/h of a constriction of length ``length`` L (m; None: an infinite slit) and height ``gap`` h (m)."""
    return None if length is None else positive_number("length", length) / gap


def _kinetic_factor(kn: FloatArray, length_ratio: float | None) -> FloatArray:
    """6 G_P(δ_eff)/δ with δ = (√π/2)/Kn and δ_eff = max(δ, δ_ℓ) (docs/theory.md §11.4); 1 at Kn = 0."""
    with np.errstate(divide="ignore", invalid="ignore"):
        delta = _DELTA_KN / kn
        eff = delta if length_ratio is None else np.maximum(delta, capped_rarefaction(length_ratio))
        out = 6.0 * poiseuille_flow_rate(eff) / delta
    return np.where(kn == 0, 1.0, np.where(np.isinf(kn), np.inf, out))


def slip_factor(knudsen: ArrayLike, model: str = DEFAULT_RAREFACTION, length_ratio: float | None = None) -> FloatArray:
    """f(Kn): the slit's flow divided by the no-slip Poiseuille flow h³/(12μ) (docs/theory.md §11.4: the slit conductance, eq. 11.5).

    ``model="kinetic"`` (default): f = 6 G_P(δ)/δ with G_P the Poiseuille flow rate of the slit from the
    linearized BGK equation with diffuse walls (:mod:`sealeak.physics._kinetic_slit`) and δ = (√π/2)/Kn;
    f → 1 + 6 (2σ_P/√π) Kn for Kn → 0 (σ_P = 1.0162). An infinite slit's f grows like Kn ln Kn; a slit of
    finite length ``length_ratio`` ℓ = L/h (dimensionless) is capped at its free-molecular flow: δ is
    replaced by max(δ, δ_ℓ) and f → (12/√π) G_fm(ℓ) Kn.

    ``model="beskok-karniadakis"`` (Beskok & Karniadakis 1999, channel with diffuse walls):
    f = (1 + α(Kn) Kn) (1 + 6 Kn/(1 + Kn)), α(Kn) = α0 (2/π) arctan(α1 Kn^β),
    α0 = 64/(15π), α1 = 4, β = 0.4. f → 1 + 6 Kn (first-order Maxwell slip) for Kn → 0 and
    f → 7 α0 Kn (free-molecular flow, a finite conductance) for Kn → ∞. ``model="no-slip"``: f = 1.
    """
    kn = np.asarray(knudsen, dtype=float)
    check_rarefaction_model(model)
    if model == "no-slip":
        return np.ones_like(kn)
    if np.any(~(kn >= 0)):
        raise InputError("knudsen", knudsen, "must be >= 0")
    if model == "kinetic":
        return _kinetic_factor(kn, length_ratio)
    with np.errstate(over="ignore", invalid="ignore"):
        alpha = BK_ALPHA0 * (2.0 / math.pi) * np.arctan(BK_ALPHA1 * kn**BK_BETA)
        out = (1.0 + alpha * kn) * (1.0 + 6.0 * kn / (1.0 + kn))
    return np.where(np.isinf(kn), np.inf, out)


def free_molecular_coefficient(gap: ArrayLike, gas: Gas, model: str = DEFAULT_RAREFACTION,
                               length_ratio: float | None = None) -> FloatArray:
    """G_fm in m³/s: the limit Kn → ∞ of h³/(12μ) · f(Kn) · p for a slit of height h (m) (docs/theory.md §11.4).

    Per unit width of the slit the free-molecular pV throughput is q = −G_fm dp/dx; it depends on
    neither the pressure nor the viscosity. Beskok–Karniadakis: G_fm = (7 α0/12) h² √(π R_s T/2)
    = (7 α0 π/48) h² v̄ ≈ 0.622 h² v̄. Kinetic: G_fm = G_fm(ℓ) h² v0/2 (v0 = √(2 R_s T)) for a slit of
    length ``length_ratio`` ℓ = L/h, inf for an infinite slit (None). No slip: inf (f = 1).
    """
    h = np.asarray(gap, dtype=float)
    check_rarefaction_model(model)
    scale = math.sqrt(0.5 * math.pi * gas.specific_gas_constant * gas.temperature)
    if model == "beskok-karniadakis":
        return (7.0 * BK_ALPHA0 / 12.0) * h**2 * scale
    if model == "no-slip" or length_ratio is None:
        return np.full(h.shape, np.inf)
    g = float(poiseuille_flow_rate(capped_rarefaction(length_ratio)))
    return (g / math.sqrt(math.pi)) * h**2 * scale


def sheet_conductance(gap: ArrayLike, gas: Gas, pressure: ArrayLike, model: str = DEFAULT_RAREFACTION,
                      length: float | None = None) -> FloatArray:
    """σ(h, p) = h³/(12 μ) f(λ(p)/h) in m³/(Pa·s): the local sheet conductance of a slit of height h (m)
    for a gas at absolute pressure p (Pa) (docs/theory.md §11.4: the slit conductance, eq. 11.5). At Kn → 0 this is the
    liquid's h³/(12μ). ``length`` L (m) of a scalar gap caps the kinetic model's free-molecular flow (None: an
    infinite slit)."""
    h = np.asarray(gap, dtype=float)
    ratio = None if length is None else _length_ratio(length, float(h))
    return h**3 / (12.0 * gas.viscosity) * slip_factor(gas.knudsen_number(h, pressure), model, ratio)


def bk_pressure_integrand(p: float, c: float) -> float:
    """p f(c/p) for the Beskok–Karniadakis f, written so that p = 0 (Kn = ∞) is finite: (p + α c)(1 + 6c/(p + c))."""
    if p <= 0.0:
        alpha = BK_ALPHA0
    else:
        alpha = BK_ALPHA0 * (2.0 / math.pi) * math.atan(BK_ALPHA1 * (c / p) ** BK_BETA)
    return (p + alpha * c) * (1.0 + 6.0 * c / (p + c))


def pressure_integral(gap: float, gas: Gas, upstream: float, downstream: float, model: str = DEFAULT_RAREFACTION,
                      length: float | None = None) -> float:
    """I = ∫_{P_b}^{P_a} p f(Kn(p)) dp in Pa² with Kn(p) = λ(p)/h (docs/theory.md §11.5, eq. 11.6).

    The pV throughput of a channel of no-slip conductance K (m³/(Pa·s)) whose narrowest gap is
    ``gap`` h (m) is Q_pV = K I. Without rarefaction (``model="no-slip"``, or Kn → 0)
    I = (P_a² − P_b²)/2; for Kn → ∞, I = (12/√π) G_fm(ℓ) c ΔP (kinetic, ℓ = ``length``/h) or 7 α0 c ΔP
    (Beskok–Karniadakis) with c = λ p/h. ``length`` L (m): the constriction's length along the flow,
    which caps the kinetic model's free-molecular flow (None: an infinite slit, whose integrand has an
    integrable logarithmic singularity at p = 0). Kinetic: in closed form, (24 c²/π) ∫ G_P dδ over
    δ = (√π/2) p/c (:func:`kinetic_pressure_integral`); Beskok–Karniadakis:
    adaptive quadrature (scipy.integrate.quad, relative tolerance 1e-12).
    """
    pa, pb = check_pressures(upstream, downstream)
    h = positive_number("gap", gap)
    check_rarefaction_model(model)
    ratio = _length_ratio(length, h)
    if pa == pb:
        return 0.0
    if model == "no-slip":
        return 0.5 * (pa - pb) * (pa + pb)
    c = gas.rarefaction_pressure_scale / h
    if model == "kinetic":
        cap = 0.0 if ratio is None else capped_rarefaction(ratio)
        return float(kinetic_pressure_integral(c, pa, pb, cap))
    if c == 0.0:
        return 0.5 * (pa - pb) * (pa + pb)
    value, _err = quad(bk_pressure_integrand, pb, pa, args=(c,), epsabs=0.0, epsrel=1e-12, limit=400)
    return float(value)


def viscous_throughput(conductance: ArrayLike, upstream: float, downstream: float) -> FloatArray:
    """Q_pV = K (P_a² − P_b²)/2 in Pa·m³/s: isothermal no-slip gas flow through a channel of conductance
    K (m³/(Pa·s)) between absolute pressures P_a ≥ P_b (Pa) (docs/theory.md §11.3, eq. 11.4)."""
    pa, pb = check_pressures(upstream, downstream)
    return np.asarray(conductance, dtype=float) * 0.5 * (pa - pb) * (pa + pb)


def viscous_mass_flow(conductance: ArrayLike, upstream: float, downstream: float, gas: Gas) -> FloatArray:
    """ṁ = K (P_a² − P_b²)/(2 R_s T) in kg/s (docs/theory.md §11.3, eq. 11.4)."""
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
             model: str = DEFAULT_RAREFACTION, length: float | None = None) -> GasLeak:
    """The leak of ``gas`` through a channel of no-slip conductance ``conductance`` K (m³/(Pa·s), e.g.
    α (Ly/Lx) u_c³/(12μ) for the critical junction) whose narrowest gap is ``gap`` h (m), between the
    absolute pressures ``upstream`` P_a and ``downstream`` P_b (Pa) (docs/theory.md §11.5, eq. 11.6). ``length``
    (m): the constriction's length along the flow (the critical junction's λ_c), which caps the kinetic
    model's free-molecular flow; None: an infinite slit."""
    pa, pb = check_pressures(upstream, downstream)
    k = positive_number("conductance", conductance, allow_zero=True)
    h = positive_number("gap", gap)
    q = k * pressure_integral(h, gas, pa, pb, model, length) if k > 0 else 0.0
    rt = MOLAR_GAS_CONSTANT * gas.temperature
    kn = [float(gas.knudsen_number(h, p)) for p in (pa, 0.5 * (pa + pb), pb)]
    return GasLeak(throughput=q, throughput_no_slip=k * 0.5 * (pa - pb) * (pa + pb), mass_flow=q * gas.molar_mass / rt,
                   molar_flow=q / rt, knudsen_upstream=kn[0], knudsen_mean=kn[1], knudsen_downstream=kn[2],
                   regime=flow_regime(kn[1]), rarefaction_model=model)


def with_throughput(leak: GasLeak, throughput: float, gas: Gas) -> GasLeak:
    """``leak`` carrying another pV throughput Q_pV (Pa·m³/s; e.g. the exact coupling of docs/theory.md §13.5), its
    mass and molar flow recomputed; the Knudsen numbers and the no-slip throughput stay those of ``leak``."""
    rt = MOLAR_GAS_CONSTANT * gas.temperature
    return replace(leak, throughput=throughput, mass_flow=throughput * gas.molar_mass / rt, molar_flow=throughput / rt)
