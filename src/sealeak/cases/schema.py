"""The case-file schema: which sections and keys exist, and typed getters that validate values.

Every key a case file may hold is listed here (:data:`SECTIONS`, :data:`SURFACE_KEYS`); the
builders (:mod:`sealeak.cases.builders`) read values only through :class:`Section`, whose errors
name the field as ``section.key`` and its value. The full reference is ``docs/case-files.md``.
"""

from __future__ import annotations

from collections.abc import Iterator
from contextlib import contextmanager
from typing import Any

import numpy as np

from ..errors import InputError, did_you_mean
from ..io.units import parse_quantity

__all__ = ["CAPILLARITY_KEYS", "SECTIONS", "SURFACE_KEYS", "TOP_LEVEL", "REQUIRED", "Section", "CASE_KEYS", "case_keys"]

#: Keys of [surface] that each surface model reads (besides model and label): a key another model
#: reads is an error, not silently ignored (e.g. h_rms with model = "table").
SURFACE_KEYS: dict[str, set[str]] = {
    "self-affine": {"h_rms", "C0", "hurst", "rolloff_wavevector", "rolloff_wavelength", "cutoff_wavevector",
                    "cutoff_wavelength", "lowest_wavevector", "lowest_wavelength"},
    "table": {"file"},
    "topography": {"file", "files", "pixel_size", "size", "height_unit", "lateral_unit", "periodic", "channel",
                   "bins_per_decade", "low_cut", "resolution", "resolution_pixels"},
}
SECTIONS: dict[str, set[str]] = {
    "surface": {"model", "label"}.union(*SURFACE_KEYS.values()),
    "rubber": {"youngs_modulus", "poisson_ratio", "name", "shore_a",
               "permeability", "diffusivity", "relaxation", "reference_temperature", "wlf_c1", "wlf_c2",
               "activation_energy", "glass_transition", "thermal_expansion", "compression_set"},
    "substrate": {"youngs_modulus", "poisson_ratio", "name"},
    "seal": {"shape", "inner_diameter", "outer_diameter", "width", "length", "height", "cross_section_diameter",
             "mean_diameter", "faces", "pressure_profile",
             "force_factor", "force_table", "gland_thermal_expansion"},
    "fluid": {"viscosity", "density", "name", "molecular_size", "temperature"},
    "conditions": {"squeeze_pressure", "pressure_difference", "compression", "groove_depth", "profile_scale",
                   "upstream_pressure", "downstream_pressure", "helium_equivalent", "time", "temperature",
                   "assembly_temperature"},
    "theory": {"alpha", "percolation_threshold", "gamma", "lowest_wavevector", "square_side", "model", "rarefaction",
               "fluid_pressure"},
    "study": {"vary", "values", "labels"},
    "rig": {"cylinder_diameter", "initial_height", "final_height", "load", "density", "duration", "gravity"},
    "simulation": {"grid", "realizations", "seed", "device"},
}
#: [fluid] keys of capillarity (docs/case-files.md): a liquid's contact angles on the two walls, its surface tension.
CAPILLARITY_KEYS = ("contact_angle", "contact_angle_rubber", "contact_angle_surface", "surface_tension")
SECTIONS["fluid"] |= set(CAPILLARITY_KEYS)
TOP_LEVEL = {"title", "description"}
REQUIRED = ("surface", "rubber", "seal", "fluid", "conditions")

class Section:
    """One TOML table, with typed getters whose errors name ``section.key`` and the value."""

    def __init__(self, name: str, data: Any) -> None:
        if not isinstance(data, dict):
            raise InputError(name, data, "must be a TOML table ([" + name + "])")
        self.name = name
        self.data = data
        allowed = SECTIONS[name]
        for key in data:
            if key not in allowed:
                raise InputError(f"{name}.{key}", data[key],
                                 f"unknown key in [{name}]; allowed keys: {', '.join(sorted(allowed))}")

    def field(self, key: str) -> str:
        """The key as the user sees it: ``section.key``."""
        return f"{self.name}.{key}"

    def has(self, key: str) -> bool:
        """Whether the section gives ``key``."""
        return key in self.data

    def raw(self, key: str, default: Any = None) -> Any:
        """The value as written (no validation), or ``default``."""
        return self.data.get(key, default)

    def quantity(self, key: str, dimension: str, default: Any = None, *, positive: bool = True) -> float:
        """A quantity with its unit (e.g. ``"44 um"``) in SI; required unless ``default`` is given; > 0 if ``positive``."""
        if key not in self.data:
            if default is None:
                raise InputError(self.field(key), None, f"is required: give a {dimension.replace('_', ' ')} with its unit")
            return default
        value = parse_quantity(self.field(key), self.data[key], dimension)
        if positive and not value > 0:
            raise InputError(self.field(key), self.data[key], "must be > 0")
        return value

    def number(self, key: str, default: float | None = None, *, low: float | None = None, high: float | None = None,
               low_open: bool = True, high_open: bool = True) -> float:
        """A plain number within (low, high) (bounds open or closed as asked); required unless ``default``."""
        if key not in self.data:
            if default is None:
                raise InputError(self.field(key), None, "is required")
            return default
        value = self.data[key]
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            if isinstance(value, str):
                value = parse_quantity(self.field(key), value, "dimensionless")
            else:
                raise InputError(self.field(key), value, "must be a number")
        try:
            value = float(value)
        except OverflowError:
            raise InputError(self.field(key), self.data[key], "must be a number a float can hold (|x| < 1.8e308)") from None
        rng = (("(" if low_open else "[") + (f"{low:g}" if low is not None else "-inf") + ", "
               + (f"{high:g}" if high is not None else "inf") + (")" if high_open else "]"))
        ok = np.isfinite(value)
        if low is not None:
            ok &= value > low if low_open else value >= low
        if high is not None:
            ok &= value < high if high_open else value <= high
        if not ok:
            raise InputError(self.field(key), self.data[key], f"must lie in {rng}")  # as written (1e-320, not 9.99989e-321)
        return value

    def choice(self, key: str, options: tuple[str, ...], default: str | None = None) -> str:
        """One of ``options``; required unless ``default`` is given."""
        value = self.data.get(key, default)
        if value is None:
            raise InputError(self.field(key), None, f"is required; allowed: {', '.join(options)}")
        if not isinstance(value, str):
            raise InputError(self.field(key), value, f"must be text; allowed: {', '.join(repr(o) for o in options)}")
        if value not in options:
            raise InputError(self.field(key), value,
                             f"allowed: {', '.join(repr(o) for o in options)}{did_you_mean(value, options)}")
        return value

    def one_of(self, keys: tuple[str, str], dims: tuple[str, str], required: bool = True) -> tuple[str, float] | None:
        """Exactly one of two alternative keys (e.g. h_rms or C0): (key given, its SI value), or None."""
        present = [k for k in keys if k in self.data]
        if len(present) > 1:
            raise InputError(self.field(keys[0]), {k: self.data[k] for k in present},
                             f"give either {keys[0]} or {keys[1]}, not both")
        if not present:
            if required:
                raise InputError(self.field(keys[0]), None, f"is required (or give {self.field(keys[1])})")
            return None
        k = present[0]
        return k, self.quantity(k, dims[keys.index(k)])


#: Physics parameter names → the case-file key a user wrote them as (for error messages).
CASE_KEYS: dict[str, str] = {
    "squeeze_pressure": "conditions.squeeze_pressure",
    "pressure_difference": "conditions.pressure_difference",
    "upstream_pressure": "conditions.upstream_pressure",
    "downstream_pressure": "conditions.downstream_pressure",
    "rarefaction_model": "theory.rarefaction",
    "viscosity": "fluid.viscosity",
    "density": "fluid.density",
    "molecular_size": "fluid.molecular_size",
    "alpha": "theory.alpha",
    "percolation_threshold": "theory.percolation_threshold",
    "gamma": "theory.gamma",
    "aspect_ratio": "seal (Ly/Lx)",
    "youngs_modulus": "rubber.youngs_modulus",
    "e_star": "rubber.youngs_modulus (contact modulus E*)",
    "poisson_ratio": "rubber.poisson_ratio",
    "youngs_modulus_2": "substrate.youngs_modulus",
    "poisson_ratio_2": "substrate.poisson_ratio",
    "rolloff_wavelength": "surface.rolloff_wavelength",
    "cutoff_wavelength": "surface.cutoff_wavelength",
    "lowest_wavelength": "surface.lowest_wavelength",
    "q0": "theory.lowest_wavevector (q0)",
    "hurst": "surface.hurst",
    "h_rms": "surface.h_rms",
    "C0": "surface.C0",
    "q_rolloff": "surface.rolloff_wavevector",
    "q_cutoff": "surface.cutoff_wavevector",
    "q_lowest": "surface.lowest_wavevector",
    "inner_diameter": "seal.inner_diameter",
    "outer_diameter": "seal.outer_diameter",
    "width": "seal.width",
    "length": "seal.length",
    "cylinder_diameter": "rig.cylinder_diameter",
    "initial_height": "rig.initial_height",
    "final_height": "rig.final_height",
    "load": "rig.load",
    "gravity": "rig.gravity",
    "duration": "rig.duration",
}


@contextmanager
def case_keys(keys: dict[str, str] | None = None) -> Iterator[None]:
    """Re-label an :class:`~sealeak.errors.InputError` raised by the physics with the case-file key.

    Physics functions name their own parameters (``squeeze_pressure[2]``); a user of a case file
    wants ``conditions.squeeze_pressure[2]``. Fields that are not physics parameter names pass
    unchanged.
    """
    mapping = CASE_KEYS if keys is None else keys
    try:
        yield
    except InputError as exc:
        name, bracket, index = exc.field.partition("[")
        if name in mapping:
            raise type(exc)(mapping[name] + bracket + index, exc.value, exc.allowed) from None
        raise
