"""Gas permeation through the rubber of a seal (a squeezed O-ring, a flat ring or rectangle): the steady leak and its
breakthrough time.

A gas dissolves in the elastomer where the high-pressure side touches it, diffuses through the
cross-section and leaves on the low-pressure side (solution–diffusion with Henry's law). This leak
adds to the interface leak that the roughness theory predicts; for helium and a nitrile O-ring it
often sets the floor of a leak test (docs/theory.md §11.11).

The squeezed cross-section (area π d²/4, rubber incompressible) is taken as a slab of height
h = (1 − ε) d (the gland's gap) and width t = π d / (4 (1 − ε)) along the flow. The steady pV
throughput through a seal line of length L_y is Fick's law over that slab,

    Q_perm = P ΔP L_y h / t = P ΔP L_y (4/π) (1 − ε)²,

with P the pV permeability in m²/s: the pV throughput (Pa·m³/s of the gas at its temperature)
through 1 m² of a 1 m thick layer per Pa of partial-pressure difference (P = D S for a diffusivity D
and a Henry solubility S in m³(pV)/(m³·Pa)). A flat ring or rectangle seal of height H and width w is the slab h = H, t = w itself
(:func:`slab_permeation`): Q_perm = P ΔP L_y H/w. A layer starting free of gas passes its steady flux
after the Daynes–Barrer time lag t_lag = t² / (6 D) (Crank, *The Mathematics of Diffusion*, 2nd ed.
(1975) eq. 4.24a).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..errors import InputError

__all__ = ["OringPermeation", "oring_permeation", "slab_permeation", "permeation_path", "time_lag"]

FloatArray = NDArray[np.float64]


@dataclass(frozen=True)
class OringPermeation:
    """The permeation of an O-ring (one entry per compression) or of a flat seal (one per row), SI units.

    Attributes
    ----------
    throughput
        Q_perm, the steady pV throughput through the rubber (Pa·m³/s).
    breakthrough_time
        t_lag = t²/(6D) (s), NaN where no diffusivity is known.
    path
        t = π d/(4(1 − ε)), the diffusion path across the squeezed cord (m).
    height
        h = (1 − ε) d, the height of the cord the gas enters and leaves through (m).
    """

    throughput: FloatArray
    breakthrough_time: FloatArray
    path: FloatArray
    height: FloatArray


def permeation_path(cross_section_diameter: float, compression: ArrayLike) -> tuple[FloatArray, FloatArray]:
    """(t, h) in m: the slab of the squeezed cord, t = π d/(4(1 − ε)) along the flow, h = (1 − ε) d across it."""
    eps = np.atleast_1d(np.asarray(compression, dtype=float))
    return np.pi * cross_section_diameter / (4.0 * (1.0 - eps)), (1.0 - eps) * cross_section_diameter


def time_lag(path: ArrayLike, diffusivity: float) -> FloatArray:
    """The Daynes–Barrer time lag t_lag = t²/(6 D) in s of a layer t (m) with diffusivity D (m²/s)."""
    return np.asarray(path, dtype=float) ** 2 / (6.0 * diffusivity)


def oring_permeation(permeability: float, diffusivity: float | None, cross_section_diameter: float,
                     compression: ArrayLike, seal_line_length: float, pressure_difference: float) -> OringPermeation:
    """Steady permeation leak and breakthrough time of an O-ring (docs/theory.md §11.11).

    Parameters
    ----------
    permeability
        P, the pV permeability in m²/s (> 0).
    diffusivity
        D in m²/s (> 0), or None (no breakthrough time).
    cross_section_diameter, compression
        d in m and ε (1) per row, 0 <= ε < 1.
    seal_line_length
        L_y in m.
    pressure_difference
        ΔP = P_a − P_b in Pa (the gas's partial-pressure difference across the seal).
    """
    t, h = permeation_path(cross_section_diameter, compression)
    return slab_permeation(permeability, diffusivity, h, t, seal_line_length, pressure_difference)


def slab_permeation(permeability: float, diffusivity: float | None, height: ArrayLike, path: ArrayLike,
                    seal_line_length: float, pressure_difference: float) -> OringPermeation:
    """Steady permeation leak Q = P ΔP L_y h/t (Pa·m³/s) and time lag t²/(6D) (s) of a rubber slab of ``height`` h (m,
    the face the gas enters by) and ``path`` t (m, along the flow), per row (docs/theory.md §11.11, eqs. 11.19–11.21).

    ``permeability`` P and ``diffusivity`` D (or None) in m²/s, ``seal_line_length`` L_y (m), ``pressure_difference``
    ΔP (Pa). A flat ring or rectangle seal is the slab h = ``seal.height``, t = its width w.
    """
    for name, value in (("permeability", permeability), ("diffusivity", diffusivity)):
        if value is not None and not (np.isfinite(value) and value > 0):
            raise InputError(name, value, "must be a finite value > 0 (m²/s)")
    h, t = np.broadcast_arrays(np.atleast_1d(np.asarray(height, dtype=float)), np.atleast_1d(np.asarray(path, dtype=float)))
    q = permeability * pressure_difference * seal_line_length * h / t
    lag = time_lag(t, diffusivity) if diffusivity is not None else np.full(t.size, np.nan)
    return OringPermeation(throughput=q, breakthrough_time=lag, path=t, height=h)
