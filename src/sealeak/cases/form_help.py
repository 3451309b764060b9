"""Readable labels and help of every case-file key for the web form, from ``docs/case-files.md``.

Each key has a label (``"Young's modulus E"``), the help text of its row in the reference's tables
(links and code marks removed) and the anchor of its section there (``"rubber-the-rubber"``).
``tests/unit/test_web_form.py`` checks that the help is the documentation's, so the two cannot drift apart.
"""

from __future__ import annotations

__all__ = ["FieldHelp", "FIELD_HELP"]

from dataclasses import dataclass


@dataclass(frozen=True)
class FieldHelp:
    """How a form labels and explains one key: ``label``, ``anchor`` (the section of ``docs/case-files.md``
    that documents it) and ``help`` (the meaning the reference gives it, one or two sentences)."""

    label: str
    anchor: str
    help: str


#: ``section.key`` (or a top-level key) → its :class:`FieldHelp`, in the order of ``docs/case-files.md``.
FIELD_HELP: dict[str, FieldHelp] = {
    "title": FieldHelp("Title", "top-level",
                     "shown on tables, figures and reports"),
    "description": FieldHelp("Description", "top-level",
                     "free text about the case; kept with the inputs (the report's input table lists it), not used in any calculation"),
    "surface.model": FieldHelp("Surface model", "surface-the-rough-surface",
                     "\"self-affine\", \"table\" or \"topography\""),
    "surface.label": FieldHelp("Surface label", "surface-the-rough-surface",
                     "description of the surface, shown on tables and figures"),
    "surface.h_rms": FieldHelp("rms roughness h_rms", "surface-the-rough-surface",
                     "rms roughness over the band [lowest, cutoff]; sets the amplitude"),
    "surface.C0": FieldHelp("PSD plateau C0", "surface-the-rough-surface",
                     "the plateau value of C(q) below the roll-off, instead of surface.h_rms"),
    "surface.hurst": FieldHelp("Hurst exponent H", "surface-the-rough-surface",
                     "Hurst exponent H"),
    "surface.rolloff_wavevector": FieldHelp("Roll-off wavevector q_r", "surface-the-rough-surface",
                     "roll-off q_r = 2π/λ_r"),
    "surface.rolloff_wavelength": FieldHelp("Roll-off wavelength λ_r", "surface-the-rough-surface",
                     "roll-off wavelength λ_r"),
    "surface.cutoff_wavevector": FieldHelp("Cut-off wavevector q1", "surface-the-rough-surface",
                     "short-wavelength cut-off q1"),
    "surface.cutoff_wavelength": FieldHelp("Cut-off wavelength λ1", "surface-the-rough-surface",
                     "cut-off wavelength λ1 = 2π/q1"),
    "surface.lowest_wavevector": FieldHelp("Lowest wavevector q0", "surface-the-rough-surface",
                     "where C(q) starts"),
    "surface.lowest_wavelength": FieldHelp("Longest wavelength 2π/q0", "surface-the-rough-surface",
                     "the same as a wavelength"),
    "surface.file": FieldHelp("File", "surface-the-rough-surface",
                     "a two-column table of q and C (format below)"),
    "surface.files": FieldHelp("Files", "surface-the-rough-surface",
                     "several height files, stitched: files = [\"wide-field.plu\", \"afm.di\"]"),
    "surface.size": FieldHelp("Map size", "surface-the-rough-surface",
                     "physical size of a map without metadata: one length (square) or a list of two [\"1 mm\", \"0.5 mm\"]"),
    "surface.pixel_size": FieldHelp("Pixel size", "surface-the-rough-surface",
                     "grid spacing instead of surface.size: one length or two"),
    "surface.height_unit": FieldHelp("Height unit", "surface-the-rough-surface",
                     "unit of the heights in files without one, e.g. \"um\""),
    "surface.lateral_unit": FieldHelp("Lateral unit", "surface-the-rough-surface",
                     "unit of x (and y) columns in files without one"),
    "surface.periodic": FieldHelp("Periodic map", "surface-the-rough-surface",
                     "the map is periodic: no window, only the mean removed"),
    "surface.channel": FieldHelp("Channel", "surface-the-rough-surface",
                     "channel (index or name) of multi-channel instrument files"),
    "surface.bins_per_decade": FieldHelp("Bins per decade", "surface-the-rough-surface",
                     "log-spaced q bins per decade"),
    "surface.low_cut": FieldHelp("Low cut N", "surface-the-rough-surface",
                     "the reliable range starts at q = N·2π/L, L the shorter side"),
    "surface.resolution": FieldHelp("Resolution", "surface-the-rough-surface",
                     "shortest reliable wavelength (lateral resolution of the instrument)"),
    "surface.resolution_pixels": FieldHelp("Resolution (pixels)", "surface-the-rough-surface",
                     "the reliable range never extends to wavelengths below N pixels"),
    "rubber.youngs_modulus": FieldHelp("Young's modulus E", "rubber-the-rubber",
                     "Young's modulus E"),
    "rubber.poisson_ratio": FieldHelp("Poisson ratio ν", "rubber-the-rubber",
                     "Poisson ratio ν"),
    "rubber.name": FieldHelp("Material", "rubber-the-rubber",
                     "name of the material (e.g. \"PDMS (Sylgard 184)\"); listed in the report's inputs, not used in any calculation"),
    "rubber.shore_a": FieldHelp("Shore A hardness", "rubber-the-rubber",
                     "Shore A hardness S instead of E: E from Gent's relation E = 0.0981 (56 + 7.62336 S)/(0.137505 (254 − 2.54 S)) MPa (theory §10.2); "
                     "uncertain by −20 %…+28 % at 70 Shore A: a measured E is better"),
    "rubber.permeability": FieldHelp("Gas permeability P", "rubber-the-rubber",
                     "gas case: the gas's pV permeability P in the rubber, the pV throughput (Pa·m³/s of the gas at its "
                     "temperature) through 1 m² of a 1 m thick layer per Pa of pressure difference, in m²/s, or as published "
                     "in Barrer (\"3 barrer\") or mol/(m·s·Pa), converted at the gas temperature (P = Π R T); adds the "
                     "permeation leak through the rubber to the results: an O-ring's squeezed cord, or a ring or rectangle "
                     "seal's slab seal.height × width (theory §11.11)"),
    "rubber.diffusivity": FieldHelp("Gas diffusivity D", "rubber-the-rubber",
                     "gas case: the gas's diffusivity D in the rubber; sets the permeation's breakthrough time t_lag = "
                     "t²/(6D), t the path across the rubber (the cord's width, or a flat seal's width)"),
    "substrate.youngs_modulus": FieldHelp("Young's modulus E", "substrate-an-elastic-substrate-optional",
                     "Young's modulus E2 of the substrate"),
    "substrate.poisson_ratio": FieldHelp("Poisson ratio ν", "substrate-an-elastic-substrate-optional",
                     "Poisson ratio ν2 of the substrate"),
    "substrate.name": FieldHelp("Material", "substrate-an-elastic-substrate-optional",
                     "name of the material; listed in the report's inputs, not used in any calculation"),
    "seal.shape": FieldHelp("Seal shape", "seal-the-seal-geometry",
                     "\"ring\" or \"rectangle\" (or \"o-ring\", below)"),
    "seal.inner_diameter": FieldHelp("Inner diameter", "seal-the-seal-geometry",
                     "ring: inner diameter Di"),
    "seal.outer_diameter": FieldHelp("Outer diameter", "seal-the-seal-geometry",
                     "ring: outer diameter Do; Lx = (Do − Di)/2, Ly = π(Do + Di)/2"),
    "seal.width": FieldHelp("Width Lx", "seal-the-seal-geometry",
                     "rectangle: width Lx along the flow"),
    "seal.length": FieldHelp("Length Ly", "seal-the-seal-geometry",
                     "rectangle: length Ly across the flow"),
    "seal.height": FieldHelp("Height", "seal-the-seal-geometry",
                     "height H of a ring or rectangle seal (e.g. \"0.5 cm\" in reference-experiment): the face the gas "
                     "enters the rubber by, for the permeation of a gas case with rubber.permeability (Q = P ΔP Ly H/w, "
                     "theory §11.11); else listed in the report's inputs and not used"),
    "seal.cross_section_diameter": FieldHelp("Cross-section diameter d", "seal-the-seal-geometry",
                     "O-ring: cross-section (cord) diameter d"),
    "seal.mean_diameter": FieldHelp("Mean diameter D", "seal-the-seal-geometry",
                     "O-ring: the seal line's diameter D directly"),
    "seal.faces": FieldHelp("Contact faces", "seal-the-seal-geometry",
                     "contact faces in parallel: 1 (the rough counterface) or 2 (the groove bottom, as rough, too: Q doubles)"),
    "seal.force_factor": FieldHelp("Force factor", "seal-the-seal-geometry",
                     "O-ring: a factor on the force per length f(ε) of the published relations (or of force_table); the contact "
                     "width stays the relations' w(ε) and the pressure profile is scaled so that it carries f"),
    "seal.force_table": FieldHelp("Force table file", "seal-the-seal-geometry",
                     "O-ring: file with columns compression and line_load, each with its unit (compression (%), line_load (N/mm)), "
                     "a measured or handbook force per length used in place of the published f(ε) (monotone interpolation; "
                     "compressions outside the table are refused); relative to the case file"),
    "seal.pressure_profile": FieldHelp("Pressure profile file", "seal-the-seal-geometry",
                     "file with columns x and pressure, each with its unit (x (mm), pressure (MPa)), the nominal contact pressure across the band, e.g. "
                     "from a finite-element model; relative to the case file; no shape"),
    "fluid.name": FieldHelp("Fluid", "fluid-the-fluid",
                     "a fluid of the property library (CoolProp; below), or any name (e.g. \"oil\") with fluid.viscosity, "
                     "which then runs as an incompressible liquid; picks the default fluid.molecular_size"),
    "fluid.viscosity": FieldHelp("Viscosity η", "fluid-the-fluid",
                     "dynamic viscosity η (Newtonian); overrides the library's value"),
    "fluid.density": FieldHelp("Density ρ", "fluid-the-fluid",
                     "density ρ; used by the rig only (ΔP = ρ g H)"),
    "fluid.molecular_size": FieldHelp("Molecular size d", "fluid-the-fluid",
                     "molecular size d of the fluid: a result whose critical gap u_c is narrower is flagged outside the theory (valid = NO; validity)"),
    "fluid.temperature": FieldHelp("Fluid temperature T", "fluid-the-fluid",
                     "the fluid's temperature T: the library's properties and the gas law are taken there"),
    "conditions.squeeze_pressure": FieldHelp("Squeeze pressure P0", "conditions-the-pressures",
                     "nominal squeeze pressure P0: one value, a list, or a range (below)"),
    "conditions.pressure_difference": FieldHelp("Pressure difference ΔP", "conditions-the-pressures",
                     "fluid pressure difference ΔP = P_a − P_b across the seal"),
    "conditions.compression": FieldHelp("Compression ε", "seal-the-seal-geometry",
                     "O-ring: compression ε = δ/d: one value, a list or a range (default spacing linear), e.g. [\"10 %\", \"20 %\"] or 0.15"),
    "conditions.groove_depth": FieldHelp("Groove depth h", "seal-the-seal-geometry",
                     "O-ring: gland depth h, from the groove bottom to the counterface once assembled (including any clearance), from which ε = (d − "
                     "h)/d"),
    "conditions.profile_scale": FieldHelp("Profile scale", "seal-the-seal-geometry",
                     "profile seal: factors on every pressure of the file, one row each"),
    "conditions.upstream_pressure": FieldHelp("Upstream pressure P_a", "conditions-the-pressures",
                     "absolute pressure P_a on the fluid's side"),
    "conditions.downstream_pressure": FieldHelp("Downstream pressure P_b", "conditions-the-pressures",
                     "absolute pressure P_b on the other side (\"0 Pa\": vacuum)"),
    "conditions.helium_equivalent": FieldHelp("Helium equivalent", "conditions-the-pressures",
                     "also give a liquid case's helium-equivalent leak rate (a gas case always has it)"),
    "theory.alpha": FieldHelp("Junction factor α", "theory-the-theorys-settings-optional",
                     "the factor α of the critical-junction leak rate, Q = α (Ly/Lx) u_c³ ΔP/(12η) (eq. (2) of the paper)"),
    "theory.percolation_threshold": FieldHelp("Percolation threshold p_c", "theory-the-theorys-settings-optional",
                     "p_c: ζc is where A/A0 = 1 − p_c"),
    "theory.gamma": FieldHelp("Separation factor γ", "theory-the-theorys-settings-optional",
                     "γ of the separation integral (1 = the formula as printed; 0.42 Yang & Persson)"),
    "theory.lowest_wavevector": FieldHelp("Lowest wavevector q0", "theory-the-theorys-settings-optional",
                     "override q0 = 2π/L, the smallest wavevector of the contact problem"),
    "theory.square_side": FieldHelp("Square side L", "theory-the-theorys-settings-optional",
                     "the same as the side L of the squares (q0 = 2π/L)"),
    "theory.model": FieldHelp("Theory", "theory-the-theorys-settings-optional",
                     "\"critical-junction\", \"effective-medium\" or \"both\""),
    "theory.rarefaction": FieldHelp("Rarefaction model", "theory-the-theorys-settings-optional",
                     "the slip model of gas flow through the gaps: \"kinetic\" (the kinetic theory of a slit, linearized BGK, from "
                     "continuum through slip and transition to free-molecular flow, the slit as long as the critical junction's λ_c; "
                     "theory §11.4), \"beskok-karniadakis\" (an empirical model: 4–37 % less flow than the kinetic one for "
                     "Kn = 0.1–10, and a finite free-molecular limit) or \"no-slip\" (the viscous law at every Knudsen number)"),
    "theory.fluid_pressure": FieldHelp("Fluid pressure in the band", "theory-the-theorys-settings-optional",
                     "whether the fluid pressure p_f(x) in the band is taken off the contact pressure: \"coupled\" (the effective squeeze "
                     "pressure p − p_f; Q grows faster than linearly in ΔP and a row with ΔP at or beyond the lift-off pressure difference "
                     "is marked not valid, theory §13) or \"ignored\" (Lorenz & Persson 2009 as printed, Q = K ΔP)"),
    "study.vary": FieldHelp("Varied key", "study-a-parameter-study-optional",
                     "the key to vary, as \"section.key\", e.g. \"surface.h_rms\"; or a whole section, e.g. \"fluid\", whose values are tables of its keys "
                     "(each replaces the keys it names)"),
    "study.values": FieldHelp("Values", "study-a-parameter-study-optional",
                     "the values, each written as that key would be (tables for a section)"),
    "study.labels": FieldHelp("Labels of the values", "study-a-parameter-study-optional",
                     "a name for each variant"),
    "rig.kind": FieldHelp("Rig kind", "rig-the-water-column-rig-or-the-pressure-decay-test",
                     "\"pressure-decay\""),
    "rig.cylinder_diameter": FieldHelp("Cylinder diameter", "rig-the-water-column-rig-or-the-pressure-decay-test",
                     "inner diameter of the cylinder"),
    "rig.initial_height": FieldHelp("Initial water height", "rig-the-water-column-rig-or-the-pressure-decay-test",
                     "initial water height H0"),
    "rig.final_height": FieldHelp("Final water height", "rig-the-water-column-rig-or-the-pressure-decay-test",
                     "the level whose arrival time is reported"),
    "rig.load": FieldHelp("Load", "rig-the-water-column-rig-or-the-pressure-decay-test",
                     "load on the ring: a mass such as \"3.4 kg\" (times g) or a force such as \"33 N\"; P0 = load / seal area"),
    "rig.density": FieldHelp("Water density ρ", "rig-the-water-column-rig-or-the-pressure-decay-test",
                     "ρ of the fluid in the column"),
    "rig.duration": FieldHelp("Duration", "rig-the-water-column-rig-or-the-pressure-decay-test",
                     "time span drawn"),
    "rig.gravity": FieldHelp("Gravity g", "rig-the-water-column-rig-or-the-pressure-decay-test",
                     "g"),
    "rig.volume": FieldHelp("Test volume", "rig-the-water-column-rig-or-the-pressure-decay-test",
                     "the gas-filled test volume V, e.g. \"0.5 l\", \"250 ml\", \"1e-4 m^3\""),
    "rig.initial_pressure": FieldHelp("Initial pressure", "rig-the-water-column-rig-or-the-pressure-decay-test",
                     "P1, absolute pressure in the volume at the start"),
    "rig.outside_pressure": FieldHelp("Outside pressure", "rig-the-water-column-rig-or-the-pressure-decay-test",
                     "P2, absolute pressure outside the seal (\"0 Pa\": vacuum)"),
    "rig.temperature": FieldHelp("Gas temperature", "rig-the-water-column-rig-or-the-pressure-decay-test",
                     "T of the test (isothermal), e.g. \"20 degC\", \"293.15 K\""),
    "rig.pressure_loss": FieldHelp("Pressure loss", "rig-the-water-column-rig-or-the-pressure-decay-test",
                     "the pressure loss ΔP whose time Δt is reported (the test's standard leak rate is V·ΔP/Δt)"),
    "simulation.grid": FieldHelp("Grid (points per side)", "simulation-defaults-of-sealeak-simulate-optional",
                     "grid points per side N; a list of them (e.g. [64, 128, 256]) runs the convergence study"),
    "simulation.realizations": FieldHelp("Realizations", "simulation-defaults-of-sealeak-simulate-optional",
                     "random surfaces R"),
    "simulation.seed": FieldHelp("Random seed", "simulation-defaults-of-sealeak-simulate-optional",
                     "random seed (realisation r uses numpy.random.default_rng([seed, r]))"),
    "simulation.device": FieldHelp("Device", "simulation-defaults-of-sealeak-simulate-optional",
                     "where the surfaces are synthesized and the contact solved: cpu (NumPy) or cuda (an NVIDIA GPU "
                     "with CuPy, the gpu extra), where the flows' AMG iterations run too (their set-up and "
                     "small fields' direct solves stay on the CPU)"),
}

# capillarity of a liquid ([fluid], docs/case-files.md)
FIELD_HELP |= {
    "fluid.contact_angle": FieldHelp("Contact angle θ", "fluid-the-fluid",
                     "contact angle θ of the liquid on both walls (rubber and surface), in degrees: with it, a non-wetting "
                     "liquid (θ > 90°) is held where ΔP is below the entry pressure of the narrowest gap (capillarity)"),
    "fluid.contact_angle_rubber": FieldHelp("Contact angle on the rubber θ_r", "fluid-the-fluid",
                     "contact angle θ_r on the rubber, with fluid.contact_angle_surface, instead of fluid.contact_angle"),
    "fluid.contact_angle_surface": FieldHelp("Contact angle on the surface θ_s", "fluid-the-fluid",
                     "contact angle θ_s on the rough counter-surface, with fluid.contact_angle_rubber"),
    "fluid.surface_tension": FieldHelp("Surface tension γ", "fluid-the-fluid",
                     "surface tension γ of the liquid, used with a contact angle"),
}

# the seal over its life (docs/case-files.md, "The seal over its life")
FIELD_HELP |= {
    "rubber.relaxation": FieldHelp("Relaxation modulus E(t)", "the-seal-over-its-life-time-and-temperature",
                     "the rubber's relaxation modulus E(t) = E∞ + Σ Ei exp(−t/τi), a Prony series: {equilibrium_modulus = \"4 MPa\", "
                     'moduli = ["2 MPa", "1 MPa"], times = ["10 s", "1e4 s"]}, or a master-curve file: {master_curve = '
                     '"nbr-master.csv"}; measured at rubber.reference_temperature; each time and temperature takes its modulus '
                     'from it instead of youngs_modulus (theory §16.7)'),
    "rubber.reference_temperature": FieldHelp("Reference temperature Tref", "the-seal-over-its-life-time-and-temperature",
                     "the temperature Tref at which rubber.relaxation was measured, the shift law's reference"),
    "rubber.wlf_c1": FieldHelp("WLF constant C1", "the-seal-over-its-life-time-and-temperature",
                     'C1 of the WLF shift log10 a_T = −C1 (T − Tref)/(C2 + T − Tref): the relaxation at T runs a_T times slower than'
                     ' at Tref'),
    "rubber.wlf_c2": FieldHelp("WLF constant C2 (K)", "the-seal-over-its-life-time-and-temperature",
                     'C2 of the WLF shift, in K'),
    "rubber.activation_energy": FieldHelp("Activation energy Ea", "the-seal-over-its-life-time-and-temperature",
                     'activation energy Ea of an Arrhenius shift ln a_T = (Ea/R)(1/T − 1/Tref), instead of the WLF constants'),
    "rubber.glass_transition": FieldHelp("Glass transition Tg", "the-seal-over-its-life-time-and-temperature",
                     "the rubber's glass-transition temperature Tg: each case within 20 K of it or below gets a warning; without it,"
                     ' estimated from the WLF constants as Tg ≈ Tref − C2 + 51.6 K'),
    "rubber.thermal_expansion": FieldHelp("Rubber thermal expansion α_r", "the-seal-over-its-life-time-and-temperature",
                     "O-ring: the rubber's linear thermal expansion coefficient α_r (an NBR compound about 23e-5 1/K): the cord "
                     'diameter d(T) = d0 (1 + α_r (T − Ta))'),
    "rubber.compression_set": FieldHelp("Compression set data", "the-seal-over-its-life-time-and-temperature",
                     "O-ring: measured compression sets (ISO 815) as points {times = [\"1000 h\", ...], temperatures = "
                     '["70 degC", ...], sets = ["15 %", ...]}, fitted by c(t, T) = 1 − exp(−(t/τ(T))^β) with an Arrhenius '
                     "τ(T); each time and temperature takes the compression ε (1 − c) (theory §16.6)"),
    "seal.gland_thermal_expansion": FieldHelp("Gland thermal expansion α_g", "the-seal-over-its-life-time-and-temperature",
                     "O-ring: the gland's linear thermal expansion coefficient α_g (steel about 1.2e-5 1/K): the gland depth h(T) = "
                     'h0 (1 + α_g (T − Ta)), so the compression at T is 1 − h(T)/d(T)'),
    "conditions.time": FieldHelp("Time since assembly t", "the-seal-over-its-life-time-and-temperature",
                     'time since assembly: one case per time (one value, a list or a range {start, stop, num, spacing}), in s, min, '
                     'h, d or a (years)'),
    "conditions.temperature": FieldHelp("Service temperatures T (over the life)", "the-seal-over-its-life-time-and-temperature",
                     'temperature of the rubber and the fluid: one case per temperature (one value, a list or a linear range {start,'
                     ' stop, num})'),
    "conditions.assembly_temperature": FieldHelp("Assembly temperature Ta", "the-seal-over-its-life-time-and-temperature",
                     'O-ring: the temperature Ta at which it was assembled with its compression or groove_depth'),
}
