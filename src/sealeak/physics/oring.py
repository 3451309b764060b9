"""O-ring contact: force, contact width and pressure profile of a squeezed O-ring; Shore A hardness.

An O-ring of cross-section diameter d is squeezed by δ = ε d between two flat faces, the groove
bottom and the counterface (docs/theory.md §10.2). Both faces carry the same force per unit length
of seal line f (equilibrium) on the same contact width w = 2b; the rough counterface is the one
the leak-rate theory models. The nominal pressure across the band is the Hertz semi-ellipse

    p(x) = p_max sqrt(1 - (2x/w - 1)²),      p_max = 4 f / (π w),      ∫₀^w p dx = f.

f(ε) and w(ε) come from two published relations, with E* = E/(1 - ν²):

* small squeeze (ε <= :data:`HERTZ_UPTO`): Hertz line contact of a cylinder of radius R = d/2
  between two rigid flat plates (Johnson, *Contact Mechanics* (1985) ch. 4-5):
  half-width b = sqrt(4 f R/(π E*)), and the compression of the diameter
  δ = (2 f/(π E*)) (2 ln(4R/b) - 1), solved for f;
* larger squeeze (ε >= :data:`LINDLEY_FROM`): Lindley's relations for a laterally unrestrained
  O-ring (Lindley, J. Inst. Rubber Ind. 1 (1967) 202): f = E d (1.25 ε^1.5 + 50 ε^6),
  w = d sqrt(6 ε/π), for incompressible rubber; for ν < 0.5 E is replaced by (3/4) E*, the
  same plane-strain modulus Hertz uses (equal to E at ν = 0.5);
* in between, ln f and ln w are interpolated with a cubic smoothstep in ln ε, so f, w and p_max
  are continuous and increase with ε.

The force may be corrected (docs/theory.md §10.2, eq. 10.7): measured O-ring forces often lie above
Lindley's relation, and the leak rate depends steeply on the load. ``force_factor`` multiplies f(ε);
a :class:`ForceTable` (compression, line load from a test or a handbook) replaces f(ε) by a
monotone (PCHIP) interpolation of its points, refused outside the table's range. The contact width
w(ε) stays that of the relations above, and the semi-elliptic profile is scaled so that ∫p dx = f.

Compressions from :data:`LINDLEY_CHECKED_UPTO` to :data:`MAX_COMPRESSION` are computed with a
warning; from :data:`MAX_COMPRESSION` on they are refused.

Young's modulus from the Shore A hardness S uses Gent's relation (Trans. IRI 34 (1958) 46), the
durometer's spring force over the indentation of its truncated-cone indenter:
E = 0.0981 (56 + 7.62336 S) / (0.137505 (254 - 2.54 S)) MPa.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.interpolate import PchipInterpolator

from ..errors import InputError
from .contact import contact_modulus
from .profile import PressureProfile

__all__ = [
    "ORingContact", "ForceTable", "oring_contact", "compression_from_groove_depth", "youngs_modulus_from_shore_a", "shore_a_warnings",
    "HERTZ_UPTO", "LINDLEY_FROM", "LINDLEY_CHECKED_UPTO", "MAX_COMPRESSION", "MIN_COMPRESSION",
    "SHORE_A_CHECKED",
]

FloatArray = NDArray[np.float64]

#: Compression ε up to which the Hertz line contact alone is used (contact half-width b < 0.08 R there).
HERTZ_UPTO = 0.01
#: Compression from which Lindley's O-ring relations alone are used.
LINDLEY_FROM = 0.10
#: Compression up to which Lindley's relations have been compared with measurements and finite elements; warned above.
LINDLEY_CHECKED_UPTO = 0.30
#: Compressions from this one on are refused.
MAX_COMPRESSION = 0.5

#: The smallest compression ε accepted: a squeeze of a millionth of the diameter (2.6 nm on a 2.6 mm ring) is
#: below any roughness, and much smaller ones underflow the Hertz and Lindley relations.
MIN_COMPRESSION = 1e-6
#: Shore A range in which Gent's relation is supported (Gent 1958 for >= 40; ASTM D2240 for <= 90); warned outside.
SHORE_A_CHECKED = (40.0, 90.0)

#: The one-line statement of the relations, carried into every result.
SOURCE = ("O-ring contact: Hertz line contact of a cylinder between two plates (Johnson 1985) up to 1 % compression, "
          "Lindley's O-ring relations (J. IRI 1 (1967) 202) from 10 %, interpolated between; semi-elliptic pressure")


@dataclass(frozen=True, kw_only=True)
class ORingContact:
    """Contact of a squeezed O-ring on each flat face, one entry per compression (SI units).

    Attributes
    ----------
    cross_section_diameter
        d in m.
    compression
        ε = δ/d (1), δ the squeeze of the cross-section.
    force_per_length
        f in N per m of seal line (the same on both faces).
    contact_width
        Full contact width w = 2b in m.
    max_pressure
        Peak of the semi-elliptic profile, p_max = 4 f/(π w) in Pa.
    mean_pressure
        f / w in Pa (= π p_max/4).
    regime
        "Hertz", "Hertz-Lindley" (the interpolation) or "Lindley", per compression.
    source
        One line naming the published relations (docs/theory.md §10.2).
    warnings
        Plain-words warnings: compressions beyond the checked range, rubber that is not
        incompressible in Lindley's range.
    """

    cross_section_diameter: float
    compression: FloatArray
    force_per_length: FloatArray
    contact_width: FloatArray
    max_pressure: FloatArray
    mean_pressure: FloatArray
    regime: tuple[str, ...]
    source: str
    warnings: tuple[str, ...] = ()
    force_factor: float = 1.0
    force_table: ForceTable | None = None

    def profile(self, i: int) -> PressureProfile:
        """The semi-elliptic pressure profile of compression ``i``: width w[i] (m), peak p_max[i] (Pa); it carries f[i]."""
        return PressureProfile.semi_elliptic(float(self.contact_width[i]), float(self.max_pressure[i]))


@dataclass(frozen=True)
class ForceTable:
    """A measured or handbook force–compression relation of an O-ring: line load f (N/m) at compressions ε (1).

    Both columns strictly increase, f >= 0, at least two rows (checked here, an
    :class:`~sealeak.errors.InputError` naming ``force_table``). Between the points f is the
    monotone piecewise-cubic (PCHIP, Fritsch-Carlson) interpolant; outside [ε_first, ε_last] it is refused.
    """

    compression: FloatArray
    force_per_length: FloatArray
    name: str = "force table"

    def __post_init__(self) -> None:
        eps = np.asarray(self.compression, dtype=float)
        f = np.asarray(self.force_per_length, dtype=float)
        if eps.ndim != 1 or eps.shape != f.shape or eps.size < 2:
            raise InputError("force_table", self.name, "needs at least two rows of compression and line load")
        if not (np.all(np.isfinite(eps)) and np.all(np.isfinite(f))):
            raise InputError("force_table", self.name, "must hold finite numbers only")
        if eps[0] < 0 or f.min() < 0:
            raise InputError("force_table", self.name, "must hold compressions and line loads >= 0")
        if not (np.all(np.diff(eps) > 0) and np.all(np.diff(f) > 0)):
            raise InputError("force_table", self.name, "must be monotone: compression and line load both increasing row by row")
        object.__setattr__(self, "compression", eps)
        object.__setattr__(self, "force_per_length", f)

    def __call__(self, eps: FloatArray) -> FloatArray:
        """f (N/m) at the compressions ``eps``; an InputError naming ``compression`` for one outside the table."""
        lo, hi = float(self.compression[0]), float(self.compression[-1])
        for i, e in enumerate(eps):
            if not lo <= e <= hi:
                raise InputError(f"compression[{i}]" if eps.size > 1 else "compression", float(e),
                                 f"must lie within the force table {self.name} ({100 * lo:.4g} % to {100 * hi:.4g} %): "
                                 "a measured force curve is not extrapolated")
        return np.asarray(PchipInterpolator(self.compression, self.force_per_length)(eps), dtype=float)


def oring_contact(cross_section_diameter: float, youngs_modulus: float, poisson_ratio: float, compression: ArrayLike,
                  force_factor: float = 1.0, force_table: ForceTable | None = None) -> ORingContact:
    """Force per length, contact width and peak pressure of an O-ring squeezed between two flat faces (docs/theory.md §10.2, eqs. 10.3–10.7).

    Parameters
    ----------
    cross_section_diameter
        d in m.
    youngs_modulus, poisson_ratio
        The rubber's E in Pa and ν in (-1, 0.5]; the faces are rigid.
    compression
        ε = δ/d, one or more values in (0, :data:`MAX_COMPRESSION`).
    force_factor
        A factor (> 0) on the force f(ε); 1 leaves the relations as published.
    force_table
        A measured f(ε) used in place of the relations' force (times ``force_factor``); the
        contact width stays the relations' w(ε).

    Returns
    -------
    ORingContact
        f (N/m), w (m), p_max = 4f/(πw) and f/w (Pa) per compression, with the regime of each:
        Hertz line contact between two plates for ε <= 1 % (Johnson 1985), Lindley's
        f = E d (1.25 ε^1.5 + 50 ε^6) and w = d (6ε/π)^1/2 for ε >= 10 % (Lindley 1967), and a
        smooth interpolation of ln f and ln w in ln ε between them; f scaled by ``force_factor`` or
        taken from ``force_table`` (eq. 10.7).
    """
    d = _diameter(cross_section_diameter)
    e_star = contact_modulus(youngs_modulus, poisson_ratio)
    eps = _compressions(compression)
    factor = _force_factor(force_factor)
    f, w = _force_and_width(eps, d, e_star)
    source = SOURCE
    if force_table is not None:
        f = force_table(eps)
        source += f"; force per length from {force_table.name} (monotone interpolation), contact width from the relations"
    if factor != 1.0:
        f = f * factor
        source += f"; force × {factor:.4g} (seal.force_factor)"
    p_max = 4.0 * f / (np.pi * w)
    regime = tuple("Hertz" if e <= HERTZ_UPTO else "Lindley" if e >= LINDLEY_FROM else "Hertz-Lindley" for e in eps)
    return ORingContact(cross_section_diameter=d, compression=eps, force_per_length=f, contact_width=w, max_pressure=p_max,
                        mean_pressure=f / w, regime=regime, source=source, warnings=_warnings(eps, float(poisson_ratio)),
                        force_factor=factor, force_table=force_table)


def _force_factor(value: float) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float, np.integer, np.floating)):
        raise InputError("force_factor", value, "must be a number > 0 (a factor on the O-ring's force per length)")
    factor = float(value)
    if not (np.isfinite(factor) and 1e-3 <= factor <= 1e3):
        raise InputError("force_factor", value, "must lie between 0.001 and 1000 (a factor on the O-ring's force per length)")
    return factor


def _force_and_width(eps: FloatArray, d: float, e_star: float) -> tuple[FloatArray, FloatArray]:
    """f (N/m) and w (m) of each compression: Hertz, Lindley, and the smoothstep between them in ln ε."""
    f_l, w_l = _lindley(eps, d, e_star)
    f, w = f_l.copy(), w_l.copy()
    low = eps < LINDLEY_FROM
    if np.any(low):
        f_h, w_h = _hertz_two_plates(eps[low], d, e_star)
        t = np.clip(np.log(eps[low] / HERTZ_UPTO) / np.log(LINDLEY_FROM / HERTZ_UPTO), 0.0, 1.0)
        s = t * t * (3.0 - 2.0 * t)
        f[low] = np.exp((1.0 - s) * np.log(f_h) + s * np.log(f_l[low]))
        w[low] = np.exp((1.0 - s) * np.log(w_h) + s * np.log(w_l[low]))
    return f, w


def _lindley(eps: FloatArray, d: float, e_star: float) -> tuple[FloatArray, FloatArray]:
    """Lindley (1967): f = E d (1.25 ε^1.5 + 50 ε^6) with E -> (3/4) E*, and w = d sqrt(6ε/π)."""
    e_lindley = 0.75 * e_star  # = E for incompressible rubber
    return e_lindley * d * (1.25 * eps**1.5 + 50.0 * eps**6), d * np.sqrt(6.0 * eps / np.pi)


def _hertz_two_plates(eps: FloatArray, d: float, e_star: float) -> tuple[FloatArray, FloatArray]:
    """Hertz line contact of a cylinder (R = d/2) between two rigid plates, compressed by δ = ε d.

    With φ = f/(E* d) the half-width is b = d sqrt(2φ/π) and δ = (2f/(πE*))(2 ln(4R/b) - 1)
    becomes ε = (2φ/π)(ln(2π/φ) - 1), solved by the fixed point φ = πε/(2(ln(2π/φ) - 1)), a
    contraction by 1/(ln(2π/φ) - 1) < 0.3 for ε < 0.1. Returns f (N/m) and w = 2b (m).
    """
    phi = eps.copy()
    for _ in range(100):
        new = np.pi * eps / (2.0 * (np.log(2.0 * np.pi / phi) - 1.0))
        done = bool(np.all(np.abs(new - phi) <= 1e-15 * new))
        phi = new
        if done:
            break
    return phi * e_star * d, 2.0 * d * np.sqrt(2.0 * phi / np.pi)


def _warnings(eps: FloatArray, poisson_ratio: float) -> tuple[str, ...]:
    out = []
    beyond = eps[eps > LINDLEY_CHECKED_UPTO]
    if beyond.size:
        shown = ", ".join(f"{100 * e:.3g} %" for e in beyond[:5]) + (" ..." if beyond.size > 5 else "")
        out.append(f"compression {shown} is beyond the {100 * LINDLEY_CHECKED_UPTO:.0f} % to which Lindley's O-ring relation has "
                   f"been checked against measurements: the force and contact width are extrapolated (refused from "
                   f"{100 * MAX_COMPRESSION:.0f} %)")
    if poisson_ratio < 0.45 and np.any(eps > HERTZ_UPTO):
        out.append(f"Lindley's O-ring relation is for incompressible rubber (ν = 0.5); with ν = {poisson_ratio:.3g} its modulus "
                   "is taken as 3/4 E/(1 - ν²), the plane-strain modulus Hertz's contact uses: treat the force as approximate")
    return tuple(out)


def compression_from_groove_depth(cross_section_diameter: float, groove_depth: ArrayLike) -> FloatArray:
    """ε = (d - h)/d for a gland depth h (m): the distance from the groove bottom to the counterface (docs/theory.md §10.2).

    Refuses h <= 0, h >= d (the O-ring is not squeezed) and h <= (1 - :data:`MAX_COMPRESSION`) d,
    each with an :class:`~sealeak.errors.InputError` naming ``groove_depth`` (``groove_depth[i]`` in a list).
    """
    d = _diameter(cross_section_diameter)
    h = np.atleast_1d(np.asarray(groove_depth, dtype=float)).ravel()
    if h.size == 0:
        raise InputError("groove_depth", [], "is empty: give at least one depth")
    for i, v in enumerate(h):
        name = f"groove_depth[{i}]" if h.size > 1 else "groove_depth"
        if not np.isfinite(v) or v <= 0:
            raise InputError(name, float(v), "must be a finite depth > 0 (m)")
        if v >= d:
            raise InputError(name, float(v), f"must be less than the cross-section diameter ({d:.6g} m): at this depth the O-ring is "
                                             "not squeezed")
        if (d - v) / d >= MAX_COMPRESSION:
            raise InputError(name, float(v), f"must exceed {1 - MAX_COMPRESSION:g} × the cross-section diameter "
                                             f"({(1 - MAX_COMPRESSION) * d:.6g} m): a shallower groove squeezes the O-ring by "
                                             f"{100 * MAX_COMPRESSION:.0f} % or more, beyond the published O-ring relations")
    return (d - h) / d


def youngs_modulus_from_shore_a(shore_a: float) -> float:
    """Young's modulus E in Pa from the Shore A hardness S, by Gent's relation (docs/theory.md §10.2, eq. 10.8).

    E = 0.0981 (56 + 7.62336 S) / (0.137505 (254 - 2.54 S)) MPa (Gent, Trans. IRI 34 (1958) 46):
    the durometer's spring force (56 + 7.62336 S) gf over 1.375 mm times the indentation
    2.54 mm (100 - S)/100 of its truncated-cone indenter. Refused outside 0 < S < 100 (an
    InputError naming ``shore_a``); supported for 40 <= S <= 90 (:func:`shore_a_warnings`).
    """
    if isinstance(shore_a, bool) or not isinstance(shore_a, (int, float, np.integer, np.floating)):
        raise InputError("shore_a", shore_a, "must be a number between 0 and 100 (Shore A hardness)")
    s = float(shore_a)
    if not (np.isfinite(s) and 0.0 < s < 100.0):
        raise InputError("shore_a", shore_a, "must lie between 0 and 100 (Shore A hardness; 100 would be a rigid body)")
    return 1e6 * 0.0981 * (56.0 + 7.62336 * s) / (0.137505 * (254.0 - 2.54 * s))


def shore_a_warnings(shore_a: float) -> tuple[str, ...]:
    """A warning when S lies outside :data:`SHORE_A_CHECKED`, where Gent's relation is not supported (docs/theory.md §10.2)."""
    lo, hi = SHORE_A_CHECKED
    s = float(shore_a)
    if s < lo:
        return (f"Shore A {s:.3g} is below {lo:.0f}: Gent's hardness-modulus relation is supported from about {lo:.0f} Shore A; "
                "the Young's modulus it gives is approximate (measure it if it matters)",)
    if s > hi:
        return (f"Shore A {s:.3g} is above {hi:.0f}, where the A durometer loses resolution (ASTM D2240 suggests the D scale): "
                "the Young's modulus from Gent's relation is approximate (measure it if it matters)",)
    return ()


def _diameter(value: float) -> float:
    try:
        d = float(value)
    except (TypeError, ValueError):
        raise InputError("cross_section_diameter", value, "must be a length (m)") from None
    if not (np.isfinite(d) and d > 0):
        raise InputError("cross_section_diameter", value, "must be a finite length > 0 (m)")
    return d


def _compressions(compression: ArrayLike) -> FloatArray:
    try:
        eps = np.atleast_1d(np.asarray(compression, dtype=float)).ravel()
    except (TypeError, ValueError):
        raise InputError("compression", compression, "must be numbers (ε = squeeze/diameter)") from None
    if eps.size == 0:
        raise InputError("compression", [], "is empty: give at least one compression")
    for i, e in enumerate(eps):
        name = f"compression[{i}]" if eps.size > 1 else "compression"
        if not (np.isfinite(e) and e > 0):
            raise InputError(name, float(e), "must be > 0: ε = squeeze/cross-section diameter, and an O-ring that is not squeezed "
                                             "does not seal")
        if e < MIN_COMPRESSION:
            raise InputError(name, float(e), f"must be at least {MIN_COMPRESSION:g} ({100 * MIN_COMPRESSION:g} %): a smaller "
                                             "squeeze is below any roughness, and the O-ring relations underflow there")
        if e >= MAX_COMPRESSION:
            raise InputError(name, float(e), f"must be below {MAX_COMPRESSION:g} ({100 * MAX_COMPRESSION:.0f} %): the published "
                                             f"O-ring relations are checked to about {100 * LINDLEY_CHECKED_UPTO:.0f} %, and a "
                                             "cross-section squeezed to half its diameter is far outside them")
    return eps
