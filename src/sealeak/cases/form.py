"""What a form needs to edit a case file: each key's kind (its dimension, or the values allowed).

The web app builds its case form from :data:`FORM_SECTIONS` (every section and key the loader
accepts, :data:`~sealeak.cases.schema.SECTIONS` and the rig keys) and shows each field with the
kind listed here: a physical dimension (``"pressure"``: the field takes a quantity with its unit,
e.g. ``"2.3 MPa"``, parsed by :func:`sealeak.io.units.parse_quantity` when the case is built), a
choice among fixed values, a number, text, true/false, a file name, or a list. The values stay as
the user typed them; validating them is the case loader's job (the same messages as the command
line). ``docs/case-files.md`` documents every key.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

from ..numerics import DEVICES
from ..physics.gas import RAREFACTION_MODELS
from .model import FLUID_PRESSURE, MODELS
from .rig_builders import RIG_KEYS
from .schema import SECTIONS, TOP_LEVEL

__all__ = ["FieldKind", "FIELD_KINDS", "FORM_SECTIONS", "field_kind"]


@dataclass(frozen=True)
class FieldKind:
    """How a form shows one key: ``kind`` is ``"quantity"``, ``"number"``, ``"integer"``, ``"choice"``,
    ``"text"``, ``"bool"``, ``"file"``, ``"files"`` or ``"list"``; ``dimension`` the physical dimension of a
    quantity (``"pressure"``), ``choices`` the allowed values of a choice, ``example`` a value to show as
    a placeholder."""

    kind: str
    dimension: str = ""
    choices: tuple[str, ...] = ()
    example: str = ""


def _q(dimension: str, example: str) -> FieldKind:
    return FieldKind("quantity", dimension, (), example)


def _n(example: str = "") -> FieldKind:
    return FieldKind("number", "", (), example)


_TEXT = FieldKind("text")
_LENGTH = _q("length", "44 um")
_WAVEVECTOR = _q("wavevector", "9.1e3 1/m")
_PRESSURE = _q("pressure", "2.3 MPa")

#: ``section.key`` (or a top-level key) → its :class:`FieldKind`.
FIELD_KINDS: dict[str, FieldKind] = {
    "title": _TEXT, "description": _TEXT,
    "surface.model": FieldKind("choice", choices=("self-affine", "table", "topography")),
    "surface.label": _TEXT, "surface.h_rms": _LENGTH, "surface.C0": _q("PSD (m^4)", "1e-20 m^4"),
    "surface.hurst": _n("0.8"), "surface.rolloff_wavevector": _WAVEVECTOR, "surface.rolloff_wavelength": _q("length", "0.69 mm"),
    "surface.cutoff_wavevector": _q("wavevector", "3.14e5 1/m"), "surface.cutoff_wavelength": _q("length", "20 um"),
    "surface.lowest_wavevector": _WAVEVECTOR, "surface.lowest_wavelength": _q("length", "5 mm"),
    "surface.file": FieldKind("file"), "surface.files": FieldKind("files"),
    "surface.size": _q("length(s)", "1 mm"), "surface.pixel_size": _q("length(s)", "2 um"),
    "surface.height_unit": FieldKind("text", example="um"), "surface.lateral_unit": FieldKind("text", example="um"),
    "surface.periodic": FieldKind("bool"), "surface.channel": FieldKind("text", example="0"),
    "surface.bins_per_decade": _n("10"), "surface.low_cut": _n("3"), "surface.resolution": _q("length", "2 um"),
    "surface.resolution_pixels": _n("4"),
    "rubber.youngs_modulus": _PRESSURE, "rubber.poisson_ratio": _n("0.5"), "rubber.name": _TEXT, "rubber.shore_a": _n("70"),
    "rubber.permeability": _q("area_per_time", "1e-12 m^2/s"), "rubber.diffusivity": _q("area_per_time", "1e-10 m^2/s"),
    "substrate.youngs_modulus": _q("pressure", "210 GPa"), "substrate.poisson_ratio": _n("0.3"), "substrate.name": _TEXT,
    "seal.shape": FieldKind("choice", choices=("ring", "rectangle", "o-ring")),
    "seal.inner_diameter": _q("length", "3 cm"), "seal.outer_diameter": _q("length", "4 cm"),
    "seal.width": _q("length", "5 mm"), "seal.length": _q("length", "110 mm"), "seal.height": _q("length", "0.5 cm"),
    "seal.cross_section_diameter": _q("length", "3.53 mm"), "seal.mean_diameter": _q("length", "20 mm"),
    "seal.faces": FieldKind("integer", example="1"), "seal.pressure_profile": FieldKind("file"),
    "seal.force_factor": _n("1"), "seal.force_table": FieldKind("file"),
    "fluid.name": FieldKind("text", example="water"), "fluid.viscosity": _q("viscosity", "1 mPa*s"),
    "fluid.density": _q("density", "1000 kg/m^3"), "fluid.molecular_size": _q("length", "0.3 nm"),
    "fluid.temperature": _q("temperature", "20 degC"),
    "conditions.squeeze_pressure": _q("pressure (one, a list or a range)", '["20 kPa", "0.1 MPa"]'),
    "conditions.pressure_difference": _q("pressure", "10 kPa"), "conditions.compression": _n('["10 %", "20 %"]'),
    "conditions.groove_depth": _q("length", "2.8 mm"), "conditions.profile_scale": _n("1"),
    "conditions.upstream_pressure": _q("pressure", "2 bar"), "conditions.downstream_pressure": _q("pressure", "1 bar"),
    "conditions.helium_equivalent": FieldKind("bool"),
    "theory.alpha": _n("0.2"), "theory.percolation_threshold": _n("0.6"), "theory.gamma": _n("1"),
    "theory.lowest_wavevector": _WAVEVECTOR, "theory.square_side": _q("length", "5 mm"),
    "theory.model": FieldKind("choice", choices=MODELS), "theory.rarefaction": FieldKind("choice", choices=RAREFACTION_MODELS),
    "theory.fluid_pressure": FieldKind("choice", choices=FLUID_PRESSURE),
    "study.vary": FieldKind("text", example="surface.h_rms"), "study.values": FieldKind("list", example='["1 um", "2 um"]'),
    "study.labels": FieldKind("list", example='["smooth", "rough"]'),
    "rig.kind": FieldKind("choice", choices=tuple(RIG_KEYS)), "rig.cylinder_diameter": _q("length", "2.5 cm"),
    "rig.initial_height": _q("length", "1 m"), "rig.final_height": _q("length", "0.5 m"), "rig.load": _q("mass or force", "3.4 kg"),
    "rig.density": _q("density", "1000 kg/m^3"), "rig.duration": _q("time", "2 h"), "rig.gravity": _q("acceleration", "9.81 m/s^2"),
    "rig.volume": _q("volume", "0.5 l"), "rig.initial_pressure": _q("pressure", "3 bar"),
    "rig.outside_pressure": _q("pressure", "1 bar"), "rig.temperature": _q("temperature", "20 degC"),
    "rig.pressure_loss": _q("pressure", "10 mbar"),
    "simulation.grid": FieldKind("integer", example="256"), "simulation.realizations": FieldKind("integer", example="4"),
    "simulation.seed": FieldKind("integer", example="0"),
    "simulation.device": FieldKind("choice", choices=DEVICES),
}
# capillarity of a liquid ([fluid], docs/case-files.md)
FIELD_KINDS |= {
    "fluid.contact_angle": _n("110"), "fluid.contact_angle_rubber": _n("110"), "fluid.contact_angle_surface": _n("100"),
    "fluid.surface_tension": _q("surface tension", "72.8 mN/m"),
}

# the seal over its life (docs/case-files.md, "The seal over its life")
_TEMPERATURE = _q("temperature", "20 degC")
FIELD_KINDS |= {
    "rubber.relaxation": FieldKind("list", example='{equilibrium_modulus = "4 MPa", moduli = ["2 MPa"], times = ["10 s"]}'),
    "rubber.reference_temperature": _TEMPERATURE, "rubber.wlf_c1": _n("8.86"), "rubber.wlf_c2": _n("101.6"),
    "rubber.activation_energy": _q("molar_energy", "80 kJ/mol"), "rubber.glass_transition": _q("temperature", "-30 degC"),
    "rubber.thermal_expansion": _q("thermal_expansion", "23e-5 1/K"),
    "rubber.compression_set": FieldKind("list", example='{times = ["1000 h", "1000 h", "1 a"], temperatures = ["70 degC", '
                                                        '"100 degC", "70 degC"], sets = ["15 %", "35 %", "30 %"]}'),
    "seal.gland_thermal_expansion": _q("thermal_expansion", "1.2e-5 1/K"),
    "conditions.time": _q("time (one, a list or a range)", '["1 h", "1 a", "10 a"]'),
    "conditions.temperature": _q("temperature (one, a list or a range)", '["-20 degC", "80 degC"]'),
    "conditions.assembly_temperature": _TEMPERATURE,
}


def _documented_order(section: str) -> Callable[[str], int]:
    """Sort key of a section's keys: their order in :data:`FIELD_KINDS` (that of ``docs/case-files.md``), others last."""
    order = list(FIELD_KINDS)

    def key(k: str) -> int:
        return order.index(f"{section}.{k}") if f"{section}.{k}" in FIELD_KINDS else 999
    return key


#: The form's sections in the order of ``docs/case-files.md`` ("" holds the top-level keys), each with its keys.
FORM_SECTIONS: dict[str, list[str]] = {
    "": sorted(TOP_LEVEL, reverse=True),
    **{name: sorted(SECTIONS[name] | (set().union(*RIG_KEYS.values()) if name == "rig" else set()),
                    key=_documented_order(name))
       for name in ("surface", "rubber", "substrate", "seal", "fluid", "conditions", "theory", "rig", "simulation", "study")},
}


def field_kind(section: str, key: str) -> FieldKind:
    """The :class:`FieldKind` of ``section.key`` (``section`` empty for a top-level key)."""
    return FIELD_KINDS[f"{section}.{key}" if section else key]
