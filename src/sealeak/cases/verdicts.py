"""The validity verdicts of a case's results and the warnings about its inputs (docs/theory.md §9.11).

A verdict per row judges the narrowest gap against the fluid's molecular size (continuum flow) and
ΔP against the contact pressure; :func:`case_warnings` names inputs far outside what the theory
assumes. Used by :func:`~sealeak.cases.run.run_case` and the fits.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from ..physics.critical_junction import CriticalJunctionResult, pressure_difference_large
from ..physics.effective_medium import EffectiveMediumResult
from ..physics.validity import assumption_warnings, continuum_verdict
from .band import BandResult
from .model import Case
from .prediction import _band_effective_gap

__all__ = ["Verdicts", "case_warnings"]

#: Verdicts per row: (valid, reasons) of the critical junction, and of the effective medium (None, None if not run).
Verdicts = tuple[NDArray[np.bool_], tuple[str, ...], NDArray[np.bool_] | None, tuple[str, ...] | None]


def _uniform_verdicts(case: Case, res: CriticalJunctionResult, em: EffectiveMediumResult | None,
                      pressure_difference: bool = True) -> Verdicts:
    """The validity verdicts of a uniform seal per squeeze pressure (docs/theory.md §9.11): u_c against the fluid's
    molecular size and λc, u_e against the molecular size and the seal width Lx; with ``pressure_difference`` also
    ΔP against P0/2 (the fit notes that one on its own)."""
    d = case.fluid.molecular_length
    valid, validity = continuum_verdict(res.critical_gap, d, "u_c", res.critical_wavelength, "λc")
    valid_em = validity_em = None
    if em is not None:
        valid_em, validity_em = continuum_verdict(np.where(em.percolates, em.effective_gap, np.nan), d, "u_e",
                                                  case.seal.width, "Lx (seal width)")
    if not pressure_difference:
        return valid, validity, valid_em, validity_em
    # ΔP not small against P0: the fluid pressure would change the contact (docs/theory.md §3.6, §9.2); coupled:
    # the fluid pressure reaches P0 and opens the seal (§13.4)
    p0, dp = res.squeeze_pressure, res.pressure_difference
    lifted = pressure_difference_large(p0, dp, case.coupled)
    if case.coupled:
        cause = [_opens(float(dp[i]), "P0", float(p0[i])) for i in range(p0.size)]
    else:
        cause = [f"ΔP = {dp[i]:.4g} Pa is not small against P0 = {p0[i]:.4g} Pa: the fluid pressure would lift the seal, "
                 "which the theory (P0 >> ΔP) does not model" for i in range(p0.size)]
    valid, validity = _lifted(valid, validity, lifted, res.percolates, cause, case.coupled)
    if em is not None and valid_em is not None and validity_em is not None:
        valid_em, validity_em = _lifted(valid_em, validity_em, lifted, em.percolates, cause, case.coupled)
    return valid, validity, valid_em, validity_em


#: Added to an O-ring's lift-off verdict: what the contact model leaves out (docs/theory.md §13.4).
ENERGISED = ("; an O-ring in a groove is also pushed by the fluid against the groove's wall (pressure energisation), "
             "which this model of a ring squeezed between two plates leaves out: in a gland its contact pressure rises "
             "with ΔP, and it holds more")


def _opens(dp: float, name: str, lift_off: float) -> str:
    """Why a row whose ΔP reaches the lift-off pressure difference is not valid (docs/theory.md §13.4): the cause, which
    :func:`_lifted` completes with what the row's number is."""
    return (f"ΔP = {dp:.4g} Pa reaches the lift-off pressure difference ({name} = {lift_off:.4g} Pa): the fluid pressure "
            "opens the seal")


#: What a lifted row's number is: with a leak channel, coupled, the limit at lift-off (docs/theory.md §13.4); without
#: one, none (the theory's "sealed" is opened by the fluid).
_AT_LIMIT = "; the leak rate shown is the limit ΔP → lift-off, the open seal leaks more"
_SHUT = ("; the theory's answer, sealed (no leak channel without the fluid's pressure), does not hold: the open seal leaks, "
         "by how much the theory does not say")


def _band_verdicts(case: Case, band: BandResult, pressure_difference: bool = True) -> Verdicts:
    """The validity verdicts of a band seal per load (docs/theory.md §9.11, §10.1): (valid, reasons) of the critical
    junction, and of the effective medium (None, None when it was not run).

    Each judges the band's narrowest constriction: u_c and λc at the peak contact pressure (critical junction),
    or u_e = (12 μ σ_min)^(1/3) against the contact width w (effective medium), against the fluid's molecular
    size; and, with ``pressure_difference``, ΔP against the peak contact pressure p_max (coupled: the fluid opens the
    seal there), or p_max/2 with the fluid pressure ignored (the fit notes that one on its own). A load without a leak
    channel is valid.
    """
    d = case.fluid.molecular_length
    dp, p_max = case.pressure_difference, band.max_contact_pressure
    lifted = pressure_difference_large(p_max, dp, case.coupled) & pressure_difference
    if case.coupled:  # the fluid pressure reaches the peak and opens the seal (docs/theory.md §13.4)
        cause = [_opens(dp, "the peak contact pressure", float(p)) for p in p_max]
    else:
        cause = [f"ΔP = {dp:.4g} Pa is not small against the peak contact pressure {p:.4g} Pa: the fluid pressure would "
                 "open the seal, which the theory (p >> ΔP) does not model" for p in p_max]
    energised = ENERGISED if case.coupled and band.band.oring is not None else ""

    def judged(valid: NDArray[np.bool_], reasons: tuple[str, ...], percolates: NDArray[np.bool_]
               ) -> tuple[NDArray[np.bool_], tuple[str, ...]]:
        return _lifted(valid, reasons, lifted, percolates, cause, case.coupled, energised)

    cj = band.critical_junction
    valid, validity = judged(*continuum_verdict(band.critical_gap_at_max_pressure, d, "u_c at the peak pressure",
                                                band.critical_wavelength_at_max_pressure, "λc"), cj.percolates)
    em = band.effective_medium
    if em is None:
        return valid, validity, None, None
    valid_em, validity_em = judged(*continuum_verdict(_band_effective_gap(case, em), d, "u_e at the peak pressure",
                                                      band.contact_width, "w (contact width)"), em.percolates)
    return valid, validity, valid_em, validity_em


def _lifted(valid: NDArray[np.bool_], reasons: tuple[str, ...], lifted: NDArray[np.bool_], percolates: NDArray[np.bool_],
            cause: list[str], coupled: bool, suffix: str = "") -> tuple[NDArray[np.bool_], tuple[str, ...]]:
    """Add the verdict ``cause[i]`` (ΔP not small against P0, or the seal opens), completed with what the row's number is
    and ``suffix``, to the rows ``lifted``, before any other reason (it explains the number shown: the limit at
    lift-off). A lifted row without a leak channel is not valid either: the theory's seal, shut without the fluid's
    pressure, is opened by it (an O-ring at 50 bar against a 10 bar peak was "sealed", valid)."""
    def why(i: int) -> str:
        said = cause[i] + ((_AT_LIMIT if coupled else "") if percolates[i] else _SHUT) + suffix
        return said if valid[i] else f"{said}; also {reasons[i]}"
    return valid & ~lifted, tuple(why(i) if lifted[i] else r for i, r in enumerate(reasons))


def case_warnings(case: Case, result: CriticalJunctionResult) -> list[str]:
    """Warnings about the case's inputs (docs/theory.md §9.11): slopes, sizes, cut-off, strain, full contact."""
    spectrum = case.spectrum
    return assumption_warnings(
        slope_rms=spectrum.slope_rms, h_rms=spectrum.h_rms, seal_width=case.seal.width, cutoff_wavevector=spectrum.q_max,
        squeeze_pressure=result.squeeze_pressure, youngs_modulus=case.youngs_modulus,
        contact_area_at_cutoff=result.contact_area_at_cutoff, alpha=case.alpha,
    )
