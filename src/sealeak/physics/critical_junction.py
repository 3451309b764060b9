"""Leak rate by the critical-junction theory (Lorenz & Persson, EPL 86 (2009) 44006; docs/theory.md §3).

The nominal contact Lx × Ly is divided into N = Ly/Lx squares of side L (= Lx by default),
q0 = 2π/L. As the magnification ζ grows the apparent contact area A(ζ)/A0 falls; the non-contact
area first percolates at the critical magnification ζc where (site percolation)

    A(ζc)/A0 = 1 - p_c                                 (p_c ≈ 0.6, so A/A0 = 0.4 by default)

i.e. G(ζc) = (P0/(2 erfinv(1 - p_c)))², solved in closed form (§3.2–§3.3). The critical constriction has
lateral size λc = L/ζc = 2π/(ζc q0) and height u_c = u1(ζc) (:meth:`PerssonContact.u1`, §3.4). Poiseuille
flow through it, times the N squares in parallel, gives the leak rate (Lorenz & Persson (2009) eq. 2; §3.5)

    Q = α (Ly/Lx) u_c³ ΔP / (12 η)                      [m³/s]

If A(ζ1)/A0 > 1 - p_c at the roughness cut-off ζ1 = q1/q0, the non-contact area never percolates
within the resolved roughness: the theory predicts no leak channel and no number is returned
(``percolates`` is False, ``leak_rate`` NaN, and a message says why).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy import special

from ..errors import InputError
from ..io.quantities import quantity
from ..io.units import format_quantity
from .contact import PerssonContact
from .gaps import ArrayCache, contact_key
from .validity import no_channel_note, pressures_text

__all__ = ["pressure_difference_large", "CriticalJunctionResult", "critical_junction", "percolation_limit", "poiseuille_leak_rate",
           "pressure_difference_not_small"]

#: E* (Pa) above which a contact modulus is taken for a mistake rather than a material (diamond's E is 1.1e12 Pa).
STIFFEST_MODULUS = 1.2e12

#: ΔP/P0 above which the assumption P0 >> ΔP (the fluid pressure does not alter the contact) is flagged.
LARGE_PRESSURE_RATIO = 0.5


def pressure_difference_not_small(squeeze_pressure: ArrayLike, pressure_difference: ArrayLike) -> NDArray[np.bool_]:
    """Where ΔP > LARGE_PRESSURE_RATIO · P0: the theories' assumption P0 >> ΔP is doubtful (Pa, Pa; docs/theory.md §3.6)."""
    return np.asarray(pressure_difference, dtype=float) > LARGE_PRESSURE_RATIO * np.asarray(squeeze_pressure, dtype=float)


def pressure_difference_large(pressure: ArrayLike, pressure_difference: ArrayLike, coupled: bool) -> NDArray[np.bool_]:
    """Where ΔP is large against the contact pressure that holds the seal shut (Pa: P0, or a band's peak; ΔP in Pa):
    with the fluid pressure coupled, where ΔP reaches it and opens the seal (docs/theory.md §13.4); with it ignored,
    where the theories' assumption p >> ΔP is doubtful (:func:`pressure_difference_not_small`, §3.6)."""
    if coupled:
        return np.asarray(pressure_difference, dtype=float) >= np.asarray(pressure, dtype=float)
    return pressure_difference_not_small(pressure, pressure_difference)

FloatArray = NDArray[np.float64]


def poiseuille_leak_rate(gap: ArrayLike, pressure_difference: ArrayLike, viscosity: float,
                         aspect_ratio: float, alpha: float = 1.0) -> FloatArray:
    """Q = α (Ly/Lx) g³ ΔP/(12 η) in m³/s (Lorenz & Persson (2009) eq. 2; docs/theory.md §3.5, eq. 3.5).

    Gap g in m, ΔP in Pa, η in Pa·s; ``aspect_ratio`` Ly/Lx and ``alpha`` are dimensionless.
    """
    return alpha * aspect_ratio * np.asarray(gap, dtype=float) ** 3 * np.asarray(pressure_difference) / (12.0 * viscosity)


@dataclass(frozen=True, kw_only=True)
class CriticalJunctionResult:
    """Critical-junction prediction over a sweep of squeeze pressures (arrays of equal length, SI units).

    Attributes
    ----------
    squeeze_pressure
        P0 (Pa).
    pressure_difference
        ΔP = P_a - P_b (Pa).
    percolates
        Whether the non-contact area percolates within the resolved roughness.
    critical_magnification
        ζc (NaN where it does not percolate).
    critical_gap
        u_c = u1(ζc) (m).
    critical_wavelength
        λc = L/ζc (m).
    leak_rate
        Q = α (Ly/Lx) u_c³ ΔP/(12η) (m³/s; Lorenz & Persson (2009) eq. 2), NaN where it does not percolate.
    contact_area_at_cutoff
        A(ζ1)/A0 at the roughness cut-off.
    alpha, percolation_threshold, gamma
        The α, p_c and γ used (dimensionless).
    q0
        q0 = 2π/L (1/m).
    aspect_ratio
        Ly/Lx (dimensionless).
    viscosity
        η (Pa·s).
    messages
        Human-readable notes (one per non-percolating pressure, assumption warnings).
    """

    squeeze_pressure: FloatArray = quantity("Pa", "nominal squeeze pressure P0")
    pressure_difference: FloatArray = quantity("Pa", "pressure difference across the seal")
    percolates: NDArray[np.bool_] = quantity("1", "the non-contact area percolates (a leak channel exists)")
    critical_magnification: FloatArray = quantity("1", "magnification ζc at which the non-contact area percolates")
    critical_gap: FloatArray = quantity("m", "gap u_c of the critical junction")
    critical_wavelength: FloatArray = quantity("m", "wavelength λc = L/ζc of the critical junction")
    leak_rate: FloatArray = quantity("m^3/s", "leak rate Q through the seal")
    contact_area_at_cutoff: FloatArray = quantity("1", "relative contact area A(ζ1)/A0 at the cut-off")
    alpha: float
    percolation_threshold: float
    gamma: float
    q0: float
    aspect_ratio: float
    viscosity: float
    messages: tuple[str, ...] = field(default=())

    def __len__(self) -> int:
        return int(self.squeeze_pressure.size)


def _pressures(squeeze_pressure: ArrayLike, pressure_difference: ArrayLike) -> tuple[FloatArray, FloatArray]:
    """Validated P0 (> 0) and ΔP (>= 0) broadcast against each other (fresh float arrays, Pa)."""
    p0 = _positive_array("squeeze_pressure", squeeze_pressure)
    dp = _positive_array("pressure_difference", pressure_difference, allow_zero=True)
    try:
        p0, dp = np.broadcast_arrays(p0, dp)
    except ValueError:
        raise InputError("pressure_difference", dp.tolist(),
                         f"give one value or one per squeeze pressure ({p0.size})") from None
    return p0.astype(float).copy(), dp.astype(float).copy()


def _positive_array(name: str, value: ArrayLike, allow_zero: bool = False) -> FloatArray:
    arr = np.atleast_1d(np.asarray(value, dtype=float))
    if arr.size == 0:
        raise InputError(name, [], "needs at least one value")
    bad = ~np.isfinite(arr) | ((arr < 0) if allow_zero else (arr <= 0))
    if bad.any():
        i = int(np.argmax(bad))
        raise InputError(name if arr.size == 1 else f"{name}[{i}]", float(arr[i]),
                         "must be finite and " + (">= 0" if allow_zero else "> 0"))
    return arr


#: Bytes of critical junctions (ζc, whether it percolates, A(ζ1)/A0, u_c) kept per contact, threshold and squeeze
#: pressure (~230 bytes each): a web update of η, ΔP or α, the second fluid of a study and a band's tables evaluated
#: again at the same pressures compute no u1 again.
KEPT_JUNCTIONS_BYTES = 16 * 2**20

_JUNCTIONS = ArrayCache(lambda: KEPT_JUNCTIONS_BYTES)


def percolation_limit(contact: PerssonContact, percolation_threshold: float) -> float:
    """The squeeze pressure (Pa) above which the non-contact area no longer percolates within the resolved roughness:
    where A(ζ1)/A0 = erf(P0/(2√G(ζ1))) reaches 1 − p_c, P0 = 2 erfinv(1 − p_c) √G(ζ1) (docs/theory.md eq. 3.3 at ζc = ζ1).
    Below it u_c > 0; towards it ζc runs to ζ1 and u_c falls to 0 faster than any power."""
    if not 0.0 < percolation_threshold < 1.0:
        raise InputError("percolation_threshold", percolation_threshold, "must lie in (0, 1)")
    return 2.0 * float(special.erfinv(1.0 - percolation_threshold)) * math.sqrt(float(contact.G(contact.zeta_max)))


def _junctions(contact: PerssonContact, threshold: float, p0: FloatArray,
               ) -> tuple[FloatArray, NDArray[np.bool_], FloatArray, FloatArray]:
    """(ζc (NaN where it does not percolate), percolates, A(ζ1)/A0, u_c (m)) at each squeeze pressure ``p0`` (Pa).

    Each row is a function of its own pressure alone (the vectorised quadrature adds every row's terms in a fixed
    order, whatever the other rows), so rows are kept by a digest of the contact, the threshold and P0, and only the
    new pressures are computed."""
    key = contact_key(contact, threshold)
    values = p0.tolist()
    kept = [_JUNCTIONS.get((key, p)) for p in values]
    new = [i for i, row in enumerate(kept) if row is None]
    if new:
        fresh = _new_junctions(contact, threshold, p0[new])
        for j, i in enumerate(new):
            kept[i] = _JUNCTIONS.put((key, values[i]), (np.array([column[j] for column in fresh], dtype=float),))
    rows = np.array([row[0] for row in kept]).reshape(p0.size, 4)  # type: ignore[index]
    return rows[:, 0], rows[:, 1] > 0, rows[:, 2], rows[:, 3]


def _new_junctions(contact: PerssonContact, threshold: float, p0: FloatArray,
                   ) -> tuple[FloatArray, NDArray[np.bool_], FloatArray, FloatArray]:
    """:func:`_junctions` computed (docs/theory.md §3.3–§3.4)."""
    zeta_c, percolates = contact.zeta_at_area(1.0 - threshold, p0)
    area_cut = contact.area(contact.zeta_max, p0)
    u_c = np.full_like(p0, np.nan)
    if percolates.any():
        u_c[percolates] = contact.u1(zeta_c[percolates], p0[percolates])
    bad = percolates & ~(np.isfinite(u_c) & (u_c > 0))
    # ζc at the end of the resolved band: u1(ζ1) = 0 exactly (the last roughness closes the junction);
    # u_c = 0 and Q = 0 is the theory's limit there, and the validity verdict flags it (docs/theory.md §9.11)
    at_end = bad & (zeta_c > np.sqrt(contact.zeta_max))
    u_c[at_end] = 0.0
    bad &= ~at_end
    if bad.any():  # ζc so close to 1 that A'(ζc) underflows: u1 = ū + ū' A/A' is not computable
        i = int(np.argmax(bad))
        why = (f"P0/E* = {p0[i] / contact.e_star:.3g}: the surfaces barely touch, so the critical magnification "
               f"ζc - 1 = {zeta_c[i] - 1:.3g} is lost in round-off and u_c = u1(ζc) cannot be computed")
        if contact.e_star > STIFFEST_MODULUS:
            raise InputError("e_star", contact.e_star, f"E* is stiffer than any solid (diamond: E ≈ 1.1e12 Pa); {why}; "
                                                       "check the Young's modulus and its unit")
        raise InputError("squeeze_pressure", float(p0[i]), f"{why}; give a larger squeeze pressure (Pa)")
    return np.where(percolates, zeta_c, np.nan), percolates, np.asarray(area_cut, dtype=float), u_c


def critical_junction(
    contact: PerssonContact,
    *,
    squeeze_pressure: ArrayLike,
    pressure_difference: ArrayLike,
    viscosity: float,
    aspect_ratio: float,
    alpha: float = 1.0,
    percolation_threshold: float = 0.6,
    fluid_pressure_neglected: bool = True,
) -> CriticalJunctionResult:
    """Critical-junction leak rate for every squeeze pressure (vectorised; no loop over pressures).

    ζc from A(ζc)/A0 = 1 - p_c, u_c = u1(ζc), λc = 2π/(ζc q0) and Q = α (Ly/Lx) u_c³ ΔP/(12η) in m³/s
    (Lorenz & Persson (2009) eq. 2; docs/theory.md §3.2–§3.5, eqs. 3.2–3.5).

    Parameters
    ----------
    contact:
        Persson contact mechanics of the interface (spectrum, E*, q0 = 2π/L, γ).
    squeeze_pressure:
        Nominal squeeze pressures P0 in Pa (scalar or 1-D array).
    pressure_difference:
        ΔP in Pa, scalar or broadcastable against ``squeeze_pressure``.
    viscosity:
        η in Pa·s.
    aspect_ratio:
        Ly/Lx (number of squares of side L across the seal).
    alpha:
        Shape factor α of the critical constriction (paper: of order one; fitted 0.2).
    percolation_threshold:
        Site-percolation threshold p_c in (0, 1); the junction percolates at A/A0 = 1 - p_c.
    fluid_pressure_neglected:
        The result is used as printed, the fluid pressure's effect on the contact neglected: rows with
        ΔP > P0/2 get a note (§3.6). False where the caller takes the fluid pressure into account (§13).
    """
    p0, dp = _pressures(squeeze_pressure, pressure_difference)
    for name, v in (("viscosity", viscosity), ("aspect_ratio", aspect_ratio), ("alpha", alpha)):
        if not (np.isfinite(v) and v > 0):
            raise InputError(name, v, "must be finite and > 0")
    if not (0.0 < percolation_threshold < 1.0):
        raise InputError("percolation_threshold", percolation_threshold, "must lie in (0, 1)")

    zeta_c, percolates, area_cut, u_c = _junctions(contact, percolation_threshold, p0)
    lam_c = 2.0 * np.pi / (zeta_c * contact.q0)
    q = np.where(percolates, poiseuille_leak_rate(u_c, dp, viscosity, aspect_ratio, alpha), np.nan)

    note = no_channel_note(p0, percolates, area_cut,
                           f", above 1 - p_c = {1 - percolation_threshold:.3f}, so the non-contact area never percolates "
                           f"within the resolved roughness (down to 2π/q1 = "
                           f"{format_quantity(2.0 * np.pi / contact.spectrum.q_max, 'length', 3)}; finer roughness would lower "
                           "the contact area further); the theory predicts no leak channel (no leak-rate number).")
    messages = [note] if note else []
    large = pressure_difference_not_small(p0, dp) & fluid_pressure_neglected
    if large.any():
        messages.append(
            f"{pressures_text(p0, large)}: ΔP is not small against P0 (ΔP > {LARGE_PRESSURE_RATIO:g} P0): the theory "
            "neglects the fluid pressure's effect on the contact (it assumes P0 >> ΔP); the fluid would lift the seal."
        )
    return CriticalJunctionResult(
        squeeze_pressure=p0, pressure_difference=dp, percolates=percolates,
        critical_magnification=zeta_c, critical_gap=u_c, critical_wavelength=lam_c, leak_rate=q,
        contact_area_at_cutoff=area_cut, alpha=float(alpha),
        percolation_threshold=float(percolation_threshold), gamma=contact.gamma, q0=contact.q0,
        aspect_ratio=float(aspect_ratio), viscosity=float(viscosity), messages=tuple(messages),
    )
