"""A seal case: everything one prediction needs, as plain SI floats and physics objects.

The case-file loader (:mod:`sealeak.cases.loader`) builds :class:`Case` objects from TOML with
units; :mod:`sealeak.cases.run` runs them. A ``Case`` holds no raw TOML: what the user wrote is
kept by the loader (:class:`~sealeak.cases.loader.CaseFile`) for the report.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ..io.quantities import quantity
from ..lab.rig import DecayRigSetup, RigSetup
from ..physics.capillarity import Wetting
from ..physics.contact import PerssonContact
from ..physics.fluid import Fluid
from ..physics.gas import DEFAULT_RAREFACTION, Gas
from ..physics.oring import ORingContact
from ..physics.profile import PressureProfile
from ..physics.properties import FluidState
from ..physics.seal import Seal
from ..physics.spectrum import PowerSpectrum

__all__ = ["Case", "LifePoint", "MODELS", "FLUID_PRESSURE", "BandSeal", "GasConditions", "RubberPermeation", "STANDARD_TEMPERATURE_CASE"]

#: The temperature of a case whose ``[fluid]`` gives none: 20 °C, in K.
STANDARD_TEMPERATURE_CASE = 293.15

#: The leak-rate theories a case may ask for (``theory.model``).
MODELS = ("critical-junction", "effective-medium", "both")

#: How the fluid's own pressure in the band acts on the contact (``theory.fluid_pressure``, docs/theory.md §13):
#: "coupled" (the effective squeeze pressure p − p_f; the default) or "ignored" (Lorenz & Persson (2009) as printed).
FLUID_PRESSURE = ("coupled", "ignored")


@dataclass(frozen=True, kw_only=True)
class BandSeal:
    """A seal whose nominal contact pressure varies across the band: an O-ring or a pressure-profile file.

    Attributes
    ----------
    kind
        "o-ring" or "profile".
    length
        Ly, the length of the seal line (m): π × the mean diameter of an O-ring's contact line.
    load_name
        What is swept: "compression" (ε = δ/d of an O-ring) or "profile_scale" (a factor on a
        profile file's pressures).
    loads
        The swept values (1), one result row each.
    profiles
        The nominal pressure profile p(x) of each load (docs/theory.md §10).
    q0
        q0 (1/m) of each load: 2π/w with w the load's contact width, unless the case file sets
        ``theory.lowest_wavevector`` or ``theory.square_side`` (docs/theory.md §10.1).
    oring
        The O-ring contact of each compression (force, width, peak pressure, regime), or None.
    faces
        Contact faces in parallel (1: the rough counterface; 2 counts the groove bottom as a
        second, equally rough path).
    q0_fixed
        q0 (1/m) fixed by the case file for every load, or None (q0 = 2π/w per load).
    notes
        Lines for the output: the relations used, their regime and range.
    """

    kind: str
    length: float = quantity("m", "seal line length", key="seal_line_length")
    load_name: str
    loads: NDArray[np.float64] = quantity("1", "a band seal's load, keyed by its name: compression ε or profile scale",
                                          key="<load>")
    profiles: tuple[PressureProfile, ...]
    q0: NDArray[np.float64]
    oring: ORingContact | None = None
    faces: int = quantity("1", "contact faces in parallel", default=1)
    notes: tuple[str, ...] = ()
    cross_section_diameter: float | None = None
    mean_diameter: float | None = None
    profile_source: str = ""
    q0_fixed: float | None = None

    @property
    def spectrum_start(self) -> float:
        """Where the roughness spectrum starts by default (1/m), independent of the listed loads.

        2π/d for an O-ring (every contact width is below the cross-section d), 2π/w of the profile
        file, or the case's fixed q0; the loads' own q0 = 2π/w lie above it (docs/theory.md §10.1).
        """
        if self.q0_fixed is not None:
            return self.q0_fixed
        if self.kind == "o-ring" and self.cross_section_diameter is not None:
            return 2.0 * np.pi / self.cross_section_diameter
        return float(np.min(self.q0))

    @property
    def load_unit(self) -> str:
        """How front ends label a load: compression in %, a scale factor as is."""
        return "%" if self.load_name == "compression" else "1"


@dataclass(frozen=True)
class LifePoint:
    """Where in its life a case is (``[conditions] time`` and ``temperature``; docs/theory.md §16.7)."""

    time: float = quantity("s", "time since assembly of the seal over its life")
    temperature: float = quantity("K", "temperature of the seal over its life (rubber and fluid)")
    modulus: float = quantity("Pa", "the rubber's modulus used at that time and temperature: E(t/a_T) of an O-ring, "
                                    "1/J(t/a_T) of a seal under a squeeze pressure, else the elastic E")
    compression_set: float | None = quantity(
        "1", "the O-ring's compression set c(t, T) fitted to rubber.compression_set, a fraction of its squeeze: its "
             "compression is ε (1 − c) (only where rubber.compression_set is given)")


@dataclass(frozen=True)
class GasConditions:
    """The gas of a gas case, between two absolute pressures (docs/theory.md §11).

    Attributes
    ----------
    gas
        The ideal gas (name, T in K, μ in Pa·s, M in kg/mol) the leak rates use; μ is the case's
        ``fluid.viscosity`` when given, else the property library's.
    upstream_pressure, downstream_pressure
        P_a > P_b >= 0, absolute (Pa); ΔP = P_a − P_b is the case's ``pressure_difference``.
    rarefaction
        The slip model f(Kn) (``theory.rarefaction``; :data:`sealeak.physics.gas.RAREFACTION_MODELS`).
    state
        The property library's state of the gas at T and P_a (viscosity, density, source).
    """

    gas: Gas
    upstream_pressure: float
    downstream_pressure: float
    rarefaction: str
    state: FluidState

    @property
    def temperature(self) -> float:
        """T in K."""
        return self.gas.temperature

    @property
    def mean_pressure(self) -> float:
        """(P_a + P_b)/2 in Pa: where the Knudsen number of the result tables is taken."""
        return 0.5 * (self.upstream_pressure + self.downstream_pressure)


@dataclass(frozen=True)
class RubberPermeation:
    """The gas's transport through the rubber (``[rubber] permeability``, ``diffusivity``; docs/theory.md §11.11).

    Attributes
    ----------
    permeability
        P, the pV permeability (m²/s): Pa·m³/s of the gas at its temperature through 1 m² of a 1 m
        thick layer per Pa of pressure difference.
    diffusivity
        D (m²/s), or None (no breakthrough time).
    height
        H (m), ``seal.height`` of a flat ring or rectangle seal: the rubber face the gas enters by (the slab H × w
        of docs/theory.md §11.11); None for an O-ring (its squeezed cord is the path).
    """

    permeability: float
    diffusivity: float | None = None
    height: float | None = None


@dataclass(frozen=True, kw_only=True)
class Case:
    """One seal case (SI units).

    Attributes
    ----------
    title
        The case's title (``title``).
    spectrum
        The roughness power spectrum C(q) (m⁴ against 1/m; docs/theory.md §1).
    spectrum_note
        One line describing where the spectrum comes from.
    youngs_modulus, poisson_ratio
        E of the rubber (Pa) and its Poisson ratio ν (1).
    e_star
        The contact modulus E* (Pa), combining rubber and substrate (docs/theory.md §2.1).
    seal
        The nominal contact Lx × Ly (m).
    fluid
        The fluid's viscosity (Pa·s) and density (kg/m³).
    squeeze_pressure
        The nominal squeeze pressures P0 (Pa), one prediction each.
    pressure_difference
        ΔP = P_a − P_b across the seal (Pa).
    alpha
        The critical junction's shape factor α (1; docs/theory.md §3.5).
    percolation_threshold
        p_c (1; docs/theory.md §3.2).
    gamma
        γ of the separation bracket (1; docs/theory.md §2.7).
    q0, q0_note
        q0 = 2π/L (1/m) with L the side of the squares the nominal contact is divided into
        (docs/theory.md §2.2), and where it came from.
    model
        The leak-rate theory asked for, one of :data:`MODELS`.
    surface_model
        The ``[surface] model`` the spectrum was built from ("self-affine", "table",
        "topography", or a registered model).
    rig
        The water-column rig of the ``[rig]`` section, or None.
    simulation
        ``[simulation]`` defaults given in the file (grid: an integer, or a tuple of them for a convergence study; realizations, seed).
    label
        The variant's name within a parameter study ('' otherwise).
    source
        The case file's path ('' for text).
    band
        For an O-ring or a pressure-profile seal, its profiles and loads (docs/theory.md §10);
        ``seal`` is then the widest band and ``squeeze_pressure`` each load's mean pressure.
    input_warnings
        Warnings the builders found in the inputs (e.g. a Shore A hardness outside the range of
        the modulus relation), shown with the result's warnings.
    gas
        For a gas (``fluid.name`` a gas at the case's temperature and upstream pressure): the gas,
        both absolute pressures and the rarefaction model (docs/theory.md §11); None for a liquid.
    temperature
        T of the fluid (K; ``fluid.temperature``, default 20 °C).
    absolute_pressures
        (P_a, P_b) in Pa when the case file gives them (gas or liquid), else None.
    fluid_state
        The property library's state of a named fluid (None when nothing was looked up: a liquid
        whose viscosity the case file gives and that has no absolute pressures).
    helium_equivalent
        Whether results carry the helium-equivalent leak rate (always for a gas;
        ``conditions.helium_equivalent`` for a liquid; docs/theory.md §11.9).
    rarefaction
        The slip model of gas flow (``theory.rarefaction``), also used by the helium equivalent.
    permeation
        The gas's permeability (and diffusivity) in the rubber of a gas case (an O-ring, or a ring or rectangle with
        ``seal.height``), or None: the
        results then carry the permeation leak beside the interface leak (docs/theory.md §11.11).
    capillarity
        A liquid's surface tension and contact angles (``fluid.contact_angle`` etc.), or None: no
        capillarity (docs/theory.md §12).
    life
        The time (s) and temperature (K) of a case of the seal over its life, and the modulus (Pa) used
        (:mod:`sealeak.cases.life`), or None.
    fluid_pressure
        ``theory.fluid_pressure``, one of :data:`FLUID_PRESSURE`: whether the fluid pressure in the band
        lowers the effective squeeze pressure (docs/theory.md §13).
    """

    title: str
    spectrum: PowerSpectrum
    spectrum_note: str
    youngs_modulus: float
    poisson_ratio: float
    e_star: float
    seal: Seal
    fluid: Fluid
    squeeze_pressure: NDArray[np.float64]
    pressure_difference: float
    alpha: float = 1.0
    percolation_threshold: float = 0.6
    gamma: float = 1.0
    q0: float = 0.0
    q0_note: str = ""
    model: str = "critical-junction"
    surface_model: str = "self-affine"
    rig: RigSetup | DecayRigSetup | None = None
    simulation: dict[str, Any] = field(default_factory=dict)
    label: str = ""
    source: str = ""
    band: BandSeal | None = None
    input_warnings: tuple[str, ...] = ()
    gas: GasConditions | None = None
    temperature: float = STANDARD_TEMPERATURE_CASE
    absolute_pressures: tuple[float, float] | None = None
    fluid_state: FluidState | None = None
    helium_equivalent: bool = False
    rarefaction: str = DEFAULT_RAREFACTION
    permeation: RubberPermeation | None = None
    # capillarity of a liquid (fluid.contact_angle, docs/theory.md §12)
    capillarity: Wetting | None = None
    fluid_pressure: str = "coupled"
    life: LifePoint | None = None

    @property
    def coupled(self) -> bool:
        """Whether the fluid pressure in the band acts on the contact (``theory.fluid_pressure = "coupled"``)."""
        return self.fluid_pressure == "coupled"

    @property
    def square_side(self) -> float:
        """L = 2π/q0 in m."""
        return 2.0 * np.pi / self.q0

    @property
    def spectrum_is_model(self) -> bool:
        """True when C(q) is an analytic model rather than a measurement or a table."""
        return self.surface_model == "self-affine"

    def contact(self) -> PerssonContact:
        """Persson contact mechanics of this case's interface (docs/theory.md §2)."""
        return PerssonContact(self.spectrum, self.e_star, self.q0, self.gamma)
