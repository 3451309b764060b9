"""Builders: validated case-file sections → the SI objects of a :class:`~sealeak.cases.model.Case`.

Each builder reads one section through :class:`~sealeak.cases.schema.Section` (so every message
names ``section.key``) and returns physics objects in SI units: the surface models (a self-affine
model, a table, measured topography files), the seal, the squeeze pressures, the rig and the
simulation defaults. Errors raised by the physics constructors with their own parameter names are
re-labelled here with the case-file key (:func:`relabel`).
"""

from __future__ import annotations

import unicodedata
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from ..errors import InputError, UnitError, show_value
from ..io.leak_units import STANDARD_PRESSURE, celsius, parse_permeability
from ..io.units import format_quantity, parse_quantity, parse_temperature
from ..lab.rig import DecayRigSetup, RigSetup
from ..physics.contact import MIN_SQUEEZE_PRESSURE, contact_modulus
from ..physics.fluid import Fluid
from ..physics.gas import RAREFACTION_MODELS, Gas, check_pressures
from ..physics.oring import shore_a_warnings, youngs_modulus_from_shore_a
from ..physics.properties import FluidState, canonical_fluid_name, close_fluid_name, fluid_state, vapour_pressure_note
from ..physics.seal import STANDARD_GRAVITY, Seal
from ..physics.spectrum import PowerSpectrum
from ..topography import Analysis, analyze, case_option_names
from .capillarity import build_wetting
from .limits import MAX_PRESSURES, MAX_REALIZATIONS, MAX_TOPOGRAPHY_FILES, at_most, whole_number
from .model import FLUID_PRESSURE, STANDARD_TEMPERATURE_CASE, BandSeal, Case, GasConditions, RubberPermeation
from .options import device_name, grid_number, parse_grid_list, seed_number
from .rig_builders import RigSection, decay_rig_setup
from .schema import REQUIRED, SECTIONS, SURFACE_KEYS, TOP_LEVEL, Section, case_keys
from .seals import SEAL_SHAPES, build_band, is_band_seal

__all__ = ["build_case", "ALPHA_RANGE", "PERCOLATION_RANGE", "register_surface_model", "SurfaceBuilder", "parse_grid_list", "topography_analysis"]

#: A ``[surface] model = ...`` builder: (section, case folder, q0) -> (spectrum, description, kind).
SurfaceBuilder = Callable[[Section, Path, float], tuple[PowerSpectrum, str]]

#: Extra surface models registered with :func:`register_surface_model`.
_SURFACE_MODELS: dict[str, SurfaceBuilder] = {}


def register_surface_model(name: str, builder: SurfaceBuilder) -> None:
    """Register a ``[surface] model = name`` builder (the measured-topography model is one)."""
    _SURFACE_MODELS[name] = builder


def _wavevector(sec: Section, stem: str, required: bool = True) -> float | None:
    got = sec.one_of((f"{stem}_wavevector", f"{stem}_wavelength"), ("wavevector", "length"), required)
    if got is None:
        return None
    key, value = got
    return value if key.endswith("wavevector") else 2.0 * np.pi / value


def _written(sec: Section, stem: str) -> str:
    """Which of ``stem_wavevector`` / ``stem_wavelength`` the section gives."""
    return f"{stem}_wavevector" if sec.has(f"{stem}_wavevector") else f"{stem}_wavelength"


def _seal(sec: Section) -> Seal:
    for key in ("cross_section_diameter", "mean_diameter", "faces"):
        if sec.has(key):
            raise InputError(sec.field(key), sec.raw(key), "is for an O-ring (shape = \"o-ring\") or a pressure-profile seal")
    for key in ("force_factor", "force_table"):  # (read by an O-ring's line load only: here they were ignored)
        if sec.has(key):
            raise InputError(sec.field(key), sec.raw(key), "is for an O-ring (shape = \"o-ring\")")
    shape = sec.choice("shape", SEAL_SHAPES)
    if sec.has("height"):  # the ring's cross-section height: described, not used by the theory
        sec.quantity("height", "length")
    if shape == "ring":
        for k in ("width", "length"):
            if sec.has(k):
                raise InputError(sec.field(k), sec.raw(k), "a ring seal takes inner_diameter and outer_diameter")
        di = sec.quantity("inner_diameter", "length")
        do = sec.quantity("outer_diameter", "length")
        if not di < do:  # (named as written: Seal.ring names it in metres)
            raise InputError(sec.field("outer_diameter"), sec.raw("outer_diameter"),
                             f"must exceed seal.inner_diameter = {show_value(sec.raw('inner_diameter'))}")
        return Seal.ring(di, do)
    for k in ("inner_diameter", "outer_diameter"):
        if sec.has(k):
            raise InputError(sec.field(k), sec.raw(k), "a rectangular seal takes width (along the flow) and length")
    return Seal.rectangle(sec.quantity("width", "length"), sec.quantity("length", "length"))


#: What a squeeze pressure below :data:`~sealeak.physics.contact.MIN_SQUEEZE_PRESSURE` is told.
def _texts(doc: dict[str, Any], source: str) -> str:
    """The case's title (default: the file's name), its description and labels checked as text the outputs print."""
    title = doc.get("title", Path(source).stem if source else "case")
    if not isinstance(title, str):
        raise InputError("title", title, "must be text")
    _printable("title", title)
    if not isinstance(doc.get("description", ""), str):
        raise InputError("description", doc["description"], "must be text")
    _printable("description", doc.get("description", ""), newlines=True)
    for section in ("rubber", "substrate", "surface"):
        key = "label" if section == "surface" else "name"
        value = doc.get(section, {}).get(key, "") if isinstance(doc.get(section), dict) else ""
        if not isinstance(value, str):
            raise InputError(f"{section}.{key}", value, "must be text")
        _printable(f"{section}.{key}", value)
    return str(title)


def _printable(field: str, text: str, newlines: bool = False) -> None:
    """Refuse a control character in text the outputs print (a title goes to the terminal and into the report: an
    escape sequence recoloured the terminal, a NUL byte reached the HTML); tabs, and line breaks where ``newlines``,
    are text."""
    allowed = "\t\n\r" if newlines else "\t"
    bad = next((c for c in text if unicodedata.category(c) == "Cc" and c not in allowed), None)
    if bad is not None:
        raise InputError(field, text, f"holds the control character U+{ord(bad):04X}: write it as text "
                                      f"without control characters{'' if newlines else ' or line breaks'}")


#: The α (theory.alpha) and p_c (theory.percolation_threshold) a case may give, both ends allowed.
ALPHA_RANGE = (1e-6, 1e6)
PERCOLATION_RANGE = (0.01, 0.99)
_TOO_SMALL = f"must be at least {MIN_SQUEEZE_PRESSURE * 1e3:g} mPa: a seal's squeeze pressure is some kPa to MPa"


def _squeeze(sec: Section) -> np.ndarray:
    key = "squeeze_pressure"
    value = sec.raw(key)
    field = sec.field(key)
    if value is None:
        raise InputError(field, None, "is required: a list such as [\"20 kPa\", \"60 kPa\"] or "
                                      "{start = \"10 kPa\", stop = \"100 kPa\", num = 20, spacing = \"log\"}")
    if isinstance(value, (str, int, float)) and not isinstance(value, bool):
        values = [value]
    elif isinstance(value, list):
        values = value
    elif isinstance(value, dict):
        unknown = set(value) - {"start", "stop", "num", "spacing"}
        if unknown:
            raise InputError(f"{field}.{sorted(unknown)[0]}", value[sorted(unknown)[0]],
                             "unknown key; a range takes start, stop, num, spacing")
        sub = Section.__new__(Section)
        sub.name, sub.data = field, value
        start = sub.quantity("start", "pressure")
        stop = sub.quantity("stop", "pressure")
        num = whole_number(f"{field}.num", value.get("num", 20), 1, MAX_PRESSURES)
        spacing = value.get("spacing", "log")
        if spacing not in ("log", "linear"):
            raise InputError(f"{field}.spacing", spacing, "allowed: 'log', 'linear'")
        if not stop > start:
            raise InputError(f"{field}.stop", value["stop"], f"must exceed start ({value['start']})")
        if not start >= MIN_SQUEEZE_PRESSURE:
            raise InputError(f"{field}.start", value["start"], _TOO_SMALL)
        return np.geomspace(start, stop, num) if spacing == "log" else np.linspace(start, stop, num)
    else:
        raise InputError(field, value, "must be a list of pressures or a {start, stop, num} range")
    if not values:
        raise InputError(field, [], "is empty: give at least one squeeze pressure")
    at_most(field, values, MAX_PRESSURES, "pressures")
    out = np.array([parse_quantity(f"{field}[{i}]", v, "pressure") for i, v in enumerate(values)])
    bad = out <= 0
    if bad.any():
        i = int(np.argmax(bad))
        raise InputError(f"{field}[{i}]", values[i], "must be > 0")
    small = out < MIN_SQUEEZE_PRESSURE
    if small.any():
        i = int(np.argmax(small))
        raise InputError(f"{field}[{i}]" if isinstance(value, list) else field, values[i], _TOO_SMALL)
    return out


def _self_affine(sec: Section, q0: float) -> tuple[PowerSpectrum, str]:
    amp = sec.one_of(("h_rms", "C0"), ("length", "psd"))
    assert amp is not None
    hurst = sec.number("hurst", low=0.0, high=1.0)
    q_r = _wavevector(sec, "rolloff")
    q_1 = _wavevector(sec, "cutoff")
    q_l = _wavevector(sec, "lowest", required=False)
    q_l = q0 if q_l is None else q_l
    kwargs = {"h_rms": amp[1]} if amp[0] == "h_rms" else {"C0": amp[1]}
    label = sec.raw("label", "")
    if not isinstance(label, str):
        raise InputError(sec.field("label"), label, "must be text")
    assert q_r is not None and q_1 is not None
    if not q_r < q_1:  # name the keys as the file wrote them (wavevector or wavelength), both of the pair
        r_key = _written(sec, "rolloff")
        c_key = _written(sec, "cutoff")
        raise InputError(sec.field(r_key), sec.raw(r_key),
                         f"the roll-off (q_r = {q_r:.4g} 1/m) must lie at longer wavelengths than the cut-off "
                         f"{sec.field(c_key)} = {show_value(sec.raw(c_key))} (q1 = {q_1:.4g} 1/m); check both")
    if q_l is not None and not q_l < q_1 and (sec.has("lowest_wavevector") or sec.has("lowest_wavelength")):
        l_key = _written(sec, "lowest")
        raise InputError(sec.field(l_key), sec.raw(l_key),
                         f"the lowest wavevector (q = {q_l:.4g} 1/m) must lie below the cut-off q1 = {q_1:.4g} 1/m")
    spec = PowerSpectrum.self_affine(hurst=hurst, q_rolloff=q_r, q_cutoff=q_1, q_lowest=q_l, label=label, **kwargs)
    note = label or f"self-affine model: H = {hurst:g}, q_r = {q_r:.4g} 1/m, q1 = {q_1:.4g} 1/m"
    return spec, note


def _table(sec: Section, case_dir: Path, q0: float) -> tuple[PowerSpectrum, str]:
    name = sec.raw("file")
    if not isinstance(name, str) or not name:
        raise InputError(sec.field("file"), name, "is required for model = 'table': the path of a q, C table")
    path = Path(name)
    if not path.is_absolute():
        path = case_dir / path
    _check_exists(sec.field("file"), name, path)
    spec = PowerSpectrum.from_table(path, label=sec.raw("label", ""))
    return spec, f"tabulated spectrum from {path.name} ({spec.q.size} points, log-log interpolation)"


def _check_exists(field: str, name: str, path: Path) -> None:
    """A file a case names must exist: else one line naming its key, as written and where it was looked for (a relative
    name is read from the case file's folder)."""
    if not path.exists():
        where = "" if Path(name).is_absolute() else f" (looked for {path.absolute()}: a relative name is read from the case file's folder)"
        raise InputError(field, name, "no such file" + where)


def topography_analysis(sec: Section, case_dir: Path, *, fit: bool = True) -> tuple[Analysis, list[Path]]:
    """The measured files of a ``model = "topography"`` section, analysed (:func:`sealeak.topography.analyze`
    with the section's reading and analysis options), and their paths; errors name ``surface.<key>``."""
    files = sec.raw("files", sec.raw("file"))
    if sec.has("file") and sec.has("files"):
        raise InputError(sec.field("files"), files, "give either file or files, not both")
    names = [files] if isinstance(files, str) else files
    if not isinstance(names, list) or not names or not all(isinstance(n, str) and n for n in names):
        raise InputError(sec.field("file"), files, "is required for model = 'topography': a file name or a list")
    at_most(sec.field("files"), names, MAX_TOPOGRAPHY_FILES, "files")
    paths = [Path(n) if Path(n).is_absolute() else case_dir / n for n in names]
    key = "files" if sec.has("files") else "file"
    for i, (name, path) in enumerate(zip(names, paths, strict=True)):
        _check_exists(sec.field(key) + (f"[{i}]" if isinstance(files, list) else ""), name, path)

    def lengths(key: str) -> float | tuple[float, float] | None:
        if not sec.has(key):
            return None
        raw = sec.raw(key)
        items = raw if isinstance(raw, list) else [raw]
        if not 1 <= len(items) <= 2:
            raise InputError(sec.field(key), raw, "one length or a list of two")
        vals = [parse_quantity(f"{sec.field(key)}", v, "length") for v in items]
        if min(vals) <= 0:
            raise InputError(sec.field(key), raw, "must be > 0")
        return vals[0] if len(vals) == 1 else (vals[0], vals[1])

    for key in ("height_unit", "lateral_unit"):
        if sec.has(key) and not isinstance(sec.raw(key), str):
            raise InputError(sec.field(key), sec.raw(key), "must be a unit name such as 'um'")
    periodic = sec.raw("periodic", False)
    if not isinstance(periodic, bool):
        raise InputError(sec.field("periodic"), periodic, "must be true or false")
    with case_option_names():  # the topography module's messages name surface.<key>
        an = analyze(paths, size=lengths("size"), pixel_size=lengths("pixel_size"),
                     height_unit=sec.raw("height_unit"), lateral_unit=sec.raw("lateral_unit"), periodic=periodic,
                     channel=sec.raw("channel"),
                     bins_per_decade=sec.number("bins_per_decade", 10.0, low=1.0, high=200.0, low_open=False,
                                                high_open=False),
                     low_cut=sec.number("low_cut", 3.0, low=1.0, low_open=False),
                     resolution_pixels=sec.number("resolution_pixels", 4.0, low=2.0, low_open=False),
                     resolution=sec.quantity("resolution", "length") if sec.has("resolution") else None, fit=fit)
    return an, paths


def _topography(sec: Section, case_dir: Path, q0: float) -> tuple[PowerSpectrum, str]:
    """``model = "topography"``: C(q) from measured height maps / line scans (stitched if several)."""
    an, paths = topography_analysis(sec, case_dir)
    with case_option_names():
        spec = an.spectrum
    label = sec.raw("label", "")
    if not isinstance(label, str):
        raise InputError(sec.field("label"), label, "must be text")
    if label:
        spec = PowerSpectrum.from_arrays(spec.q, spec.C, label=label)
    note = (f"measured topography ({', '.join(p.name for p in paths)}): C(q) over q = {spec.q_min:.4g} .. "
            f"{spec.q_max:.4g} 1/m")
    if spec.q_min > q0 * 1.0001:
        note += (f"; the measurement starts at q = {spec.q_min:.4g} 1/m > q0 = {q0:.4g} 1/m, so roughness at "
                 "longer wavelengths is missing (taken as zero)")
    return spec, note


register_surface_model("topography", _topography)


def _elastic(rubber: Section, sub: Any) -> tuple[float, float, float, tuple[str, ...]]:
    """The rubber's E (Pa) and ν, the contact modulus E* (Pa) with the substrate (rigid if None), warnings."""
    input_warnings: tuple[str, ...] = ()
    if rubber.has("shore_a"):
        if rubber.has("youngs_modulus"):
            raise InputError(rubber.field("shore_a"), rubber.raw("shore_a"), "give either youngs_modulus or shore_a, not both")
        shore = rubber.number("shore_a", low=0.0, high=100.0)
        with case_keys({"shore_a": rubber.field("shore_a")}):
            youngs = youngs_modulus_from_shore_a(shore)
            input_warnings += shore_a_warnings(shore)
    elif not rubber.has("youngs_modulus"):
        raise InputError(rubber.field("youngs_modulus"), None, 'is required, or rubber.shore_a instead: give a pressure with '
                                                               'its unit (e.g. "7 MPa") or a Shore A hardness (e.g. 70)')
    else:
        youngs = rubber.quantity("youngs_modulus", "pressure")
    nu = rubber.number("poisson_ratio", 0.5, low=-1.0, high=0.5, high_open=False)
    if sub is not None:
        s = Section("substrate", sub)
        e2 = s.quantity("youngs_modulus", "pressure")
        nu2 = s.number("poisson_ratio", 0.0, low=-1.0, high=0.5, high_open=False)
        with case_keys():
            e_star = contact_modulus(youngs, nu, e2, nu2)
    else:
        with case_keys():
            e_star = contact_modulus(youngs, nu)
    return youngs, nu, e_star, input_warnings


def check_sections(doc: dict[str, Any]) -> None:
    """Every top-level key of a case document is a known section or key, and every required section is there."""
    for key in doc:
        if key not in SECTIONS and key not in TOP_LEVEL:
            raise InputError(key, doc[key], f"unknown section or key; allowed sections: "
                                            f"{', '.join(sorted(SECTIONS))}")
    for name in REQUIRED:
        if name not in doc:
            raise InputError(name, None, f"section [{name}] is missing")


def build_case(doc: dict[str, Any], case_dir: Path, source: str, label: str = "") -> Case:
    """One :class:`Case` from a parsed case file (TOML document without its ``[study]``).

    Errors the physics constructors raise with their own parameter names (``outer_diameter``)
    come out with the case-file key (``seal.outer_diameter``): each constructor is called inside
    :func:`~sealeak.cases.schema.case_keys`.
    """
    check_sections(doc)
    title = _texts(doc, source)
    rubber = Section("rubber", doc["rubber"])
    youngs, nu, e_star, input_warnings = _elastic(rubber, doc.get("substrate"))
    seal_section = Section("seal", doc["seal"])
    band_kind = is_band_seal(seal_section)
    if band_kind is None:
        with case_keys():
            seal = _seal(seal_section)
    cond = Section("conditions", doc["conditions"])
    theory = Section("theory", doc.get("theory", {}))
    fluid_section = Section("fluid", doc["fluid"])
    fl = _fluid(fluid_section, cond, theory)
    fluid = fl.fluid
    input_warnings += fl.warnings
    # capillarity of a liquid (fluid.contact_angle; docs/theory.md §12)
    wetting, wetting_warnings = build_wetting(fluid_section, fluid.name, fl.temperature, gas=fl.gas is not None)
    input_warnings += wetting_warnings
    band = None
    if band_kind is None:
        for key in ("compression", "groove_depth", "profile_scale"):
            if cond.has(key):
                raise InputError(cond.field(key), cond.raw(key), "is for an O-ring (seal.shape = \"o-ring\") or a seal "
                                 "with a pressure_profile; this seal takes squeeze_pressure")
        p0 = _squeeze(cond)
    else:
        q0_fixed = (theory.quantity("lowest_wavevector", "wavevector") if theory.has("lowest_wavevector") else
                    2.0 * np.pi / theory.quantity("square_side", "length") if theory.has("square_side") else None)
        band, seal, p0 = build_band(band_kind, seal_section, cond, rubber, youngs, nu, case_dir, q0_fixed)
        if theory.has("square_side"):
            w = np.array([p.width for p in band.profiles])
            input_warnings += (f"theory.square_side = {theory.raw('square_side')!r}: {'an O-ring' if band_kind == 'o-ring' else 'a band seal'} "
                               f"has no square side; the key sets q0 = 2π/L for every load in place of 2π/w (w, the contact "
                               f"width, is {w.min() * 1e6:.4g} … {w.max() * 1e6:.4g} µm here), the longest roughness wavelength "
                               "the contact sees; remove it unless you mean that (theory.lowest_wavevector sets q0 directly)",)
    dp = fl.pressure_difference
    # α is of order one (0.1 to 2 in the literature); far outside, a leak rate underflows to 0 or overflows. p_c is a
    # contact-area fraction near 0.4 to 0.6; at 1e-320 the area 1 − p_c rounds to 1 and the contact theory refused it
    # without naming the key
    alpha = theory.number("alpha", 1.0, low=ALPHA_RANGE[0], high=ALPHA_RANGE[1], low_open=False, high_open=False)
    pc = theory.number("percolation_threshold", 0.6, low=PERCOLATION_RANGE[0], high=PERCOLATION_RANGE[1],
                       low_open=False, high_open=False)
    gamma = theory.number("gamma", 1.0, low=0.0, high=1.0, high_open=False)
    model = theory.choice("model", ("critical-junction", "effective-medium", "both"), "critical-junction")
    fluid_pressure = theory.choice("fluid_pressure", FLUID_PRESSURE, FLUID_PRESSURE[0])
    if theory.has("lowest_wavevector") and theory.has("square_side"):
        raise InputError("theory.lowest_wavevector", theory.raw("lowest_wavevector"),
                         "give either lowest_wavevector or square_side, not both")
    if theory.has("lowest_wavevector"):
        q0 = theory.quantity("lowest_wavevector", "wavevector")
        q0_note = "q0 set in the case file"
    elif theory.has("square_side"):
        q0 = 2.0 * np.pi / theory.quantity("square_side", "length")
        q0_note = "q0 = 2π/L with L set in the case file"
    elif band is not None:
        q0 = float(band.q0.min())
        q0_note = "q0 = 2π/w per load (w its contact width)"
    else:
        q0 = 2.0 * np.pi / seal.width
        q0_note = "q0 = 2π/Lx (seal width)"
    surf = Section("surface", doc["surface"])
    model_name = surf.raw("model")
    builders: dict[str, Callable[..., tuple[PowerSpectrum, str]]] = {
        "self-affine": lambda s, d, q: _self_affine(s, q),
        "table": _table,
        **_SURFACE_MODELS,
    }
    if not isinstance(model_name, str) or model_name not in builders:
        raise InputError("surface.model", model_name, f"allowed: {', '.join(repr(k) for k in builders)}")
    if model_name in SURFACE_KEYS:
        allowed = SURFACE_KEYS[model_name] | {"model", "label"}
        for key in surf.data:
            if key not in allowed:
                raise InputError(surf.field(key), surf.raw(key),
                                 f"not used by model = {model_name!r}; its keys: {', '.join(sorted(allowed))}")
    q0_given = not surf.has("lowest_wavevector") and not surf.has("lowest_wavelength")
    try:
        with case_keys():
            spectrum, note = builders[model_name](surf, case_dir, q0 if band is None else band.spectrum_start)
    except InputError as exc:  # the spectrum starts at q0 unless the file says otherwise: blame q0's source
        if q0_given and exc.field.startswith("surface.lowest_wave"):
            raise _q0_error(seal_section, theory, seal, q0, exc.allowed) from None
        raise
    if not (q0 if band is None else float(band.q0.max())) < spectrum.q_max:
        raise _q0_error(seal_section, theory, seal, q0 if band is None else float(band.q0.max()),
                        f"must be below the roughness cut-off q1 = {spectrum.q_max:.6g} 1/m")
    permeation = _permeation(rubber, seal_section, fl.gas is not None, band, fl.temperature)
    rig = _rig(doc["rig"], fluid, band, doc) if "rig" in doc else None  # the rig's objects under case_keys, in _rig
    if isinstance(rig, RigSetup) and band is None and rig.squeeze_pressure(seal) < MIN_SQUEEZE_PRESSURE:
        # (named here, not as conditions.squeeze_pressure = 1.78e-86, the value the contact theory was handed)
        raise InputError("rig.load", doc["rig"].get("load"),
                         f"gives a squeeze pressure of {rig.squeeze_pressure(seal):.3g} Pa over the seal's area: "
                         f"{_TOO_SMALL}")
    simulation = _simulation(Section("simulation", doc["simulation"])) if "simulation" in doc else {}
    return Case(
        title=title, spectrum=spectrum, spectrum_note=note, youngs_modulus=youngs, poisson_ratio=nu,
        e_star=e_star, seal=seal, fluid=fluid, squeeze_pressure=p0, pressure_difference=dp, alpha=alpha,
        percolation_threshold=pc, gamma=gamma, q0=q0, q0_note=q0_note, model=model, rig=rig, label=label,
        simulation=simulation, source=source, surface_model=str(model_name), band=band, input_warnings=input_warnings,
        gas=fl.gas, temperature=fl.temperature, absolute_pressures=fl.absolute_pressures, fluid_state=fl.state,
        helium_equivalent=fl.helium_equivalent, rarefaction=fl.rarefaction, permeation=permeation,
        capillarity=wetting,
        fluid_pressure=fluid_pressure,
    )


def _permeation(rubber: Section, seal: Section, is_gas: bool, band: BandSeal | None,
                temperature: float) -> RubberPermeation | None:
    """``[rubber] permeability`` and ``diffusivity`` (m²/s) of a gas case with an O-ring, or a ring or rectangle seal
    with ``seal.height`` (docs/case-files.md), else None; a pressure profile has no rubber path (refused).

    The permeability as written in m²/s (pV form), or published (mol/(m·s·Pa), Barrer) and turned into the pV
    form at the gas temperature (K) by :func:`~sealeak.io.leak_units.parse_permeability`."""
    if not rubber.has("permeability"):
        if rubber.has("diffusivity"):
            raise InputError(rubber.field("diffusivity"), rubber.raw("diffusivity"),
                             "needs rubber.permeability too: the diffusivity only sets the permeation's breakthrough time")
        return None
    if not is_gas:
        raise InputError(rubber.field("permeability"), rubber.raw("permeability"),
                         "is for a gas case (fluid.name a gas, with upstream_pressure and downstream_pressure): "
                         "the permeation through the rubber is a gas leak")
    if band is not None and band.kind != "o-ring":
        raise InputError(rubber.field("permeability"), rubber.raw("permeability"),
                         "is for an O-ring, a ring or a rectangle seal: a pressure profile gives no rubber cross-section "
                         "for the gas to diffuse through")
    if band is None and not seal.has("height"):
        raise InputError(rubber.field("permeability"), rubber.raw("permeability"),
                         f"needs {seal.field('height')} for a {seal.raw('shape', 'flat')} seal: the gas diffuses through "
                         "the rubber slab of that height across the seal's width")
    permeability = parse_permeability(rubber.field("permeability"), rubber.raw("permeability"), temperature=temperature)
    if not permeability > 0:
        raise InputError(rubber.field("permeability"), rubber.raw("permeability"), "must be > 0")
    return RubberPermeation(permeability=permeability,
                            diffusivity=rubber.quantity("diffusivity", "area_per_time") if rubber.has("diffusivity") else None,
                            height=seal.quantity("height", "length") if band is None else None)


#: Known fluids that are liquids at 20 °C and 1 atm: with a viscosity given and no absolute pressures,
#: such a case runs as before named fluids existed, without any property lookup.
_LIQUIDS_AT_ROOM = ("water", "ethanol")


@dataclass(frozen=True, kw_only=True)
class _FluidInputs:
    """What [fluid] and the pressure keys of [conditions] give (SI): the fluid, ΔP, the gas, the warnings."""

    fluid: Fluid
    pressure_difference: float
    temperature: float
    absolute_pressures: tuple[float, float] | None
    state: FluidState | None
    gas: GasConditions | None
    helium_equivalent: bool
    rarefaction: str
    warnings: tuple[str, ...]


def _absolute_pressures(cond: Section) -> tuple[float, float] | None:
    """``conditions.upstream_pressure`` and ``downstream_pressure`` (absolute, Pa), both or neither."""
    keys = ("upstream_pressure", "downstream_pressure")
    given = [cond.has(k) for k in keys]
    if not any(given):
        return None
    if not all(given):
        missing = keys[given.index(False)]
        raise InputError(cond.field(missing), None, "is required with " + cond.field(keys[given.index(True)])
                         + ": give both absolute pressures (e.g. upstream_pressure = \"1 bar\", downstream_pressure = "
                         "\"0 Pa\" for vacuum)")
    pa, pb = (cond.quantity(k, "pressure", positive=False) for k in keys)
    with case_keys():
        pa, pb = check_pressures(pa, pb)
    if pa == pb:
        raise InputError(cond.field("upstream_pressure"), cond.raw("upstream_pressure"),
                         f"equals {cond.field('downstream_pressure')}: with no pressure difference across the seal nothing leaks")
    return pa, pb


def _pressure_difference(cond: Section, absolute: tuple[float, float] | None) -> float:
    """ΔP (Pa): ``conditions.pressure_difference``, or P_a − P_b; both given must agree (to 1e-6)."""
    if absolute is not None:
        dp = absolute[0] - absolute[1]
        if cond.has("pressure_difference"):
            given = cond.quantity("pressure_difference", "pressure", positive=False)
            if not abs(given - dp) <= 1e-6 * dp:
                raise InputError(cond.field("pressure_difference"), cond.raw("pressure_difference"),
                                 f"disagrees with conditions.upstream_pressure − conditions.downstream_pressure = "
                                 f"{cond.raw('upstream_pressure')} − {cond.raw('downstream_pressure')} = {dp:.6g} Pa; "
                                 "give either the pressure difference or the absolute pressures, or make them agree")
        return dp
    if not cond.has("pressure_difference"):
        raise InputError(cond.field("pressure_difference"), None, "is required: give a pressure with its unit (e.g. "
                         "\"10 kPa\"), or the absolute conditions.upstream_pressure and conditions.downstream_pressure")
    dp = cond.quantity("pressure_difference", "pressure", positive=False)
    if not dp > 0:
        raise InputError(cond.field("pressure_difference"), cond.raw("pressure_difference"),
                         "must be > 0: with no pressure difference across the seal nothing leaks")
    return dp


def _fluid(fsec: Section, cond: Section, theory: Section) -> _FluidInputs:
    """[fluid] with the pressures of [conditions]: a liquid (Q = K ΔP) or a gas between two absolute pressures.

    A named fluid's viscosity, density and phase come from the property library
    (:func:`~sealeak.physics.properties.fluid_state`, at ``fluid.temperature`` and the upstream
    pressure); ``fluid.viscosity`` overrides the looked-up value. A liquid whose viscosity is given
    and that has no absolute pressures is not looked up (docs/theory.md §11.9). A gas needs both
    absolute pressures.
    """
    name = fsec.raw("name", "")
    if not isinstance(name, str):
        raise InputError(fsec.field("name"), name, "must be text, e.g. \"water\" or \"helium\"")
    density = fsec.quantity("density", "density") if fsec.has("density") else None
    viscosity = fsec.quantity("viscosity", "viscosity") if fsec.has("viscosity") else None
    molecular = fsec.quantity("molecular_size", "length") if fsec.has("molecular_size") else None
    temperature = parse_temperature(fsec.field("temperature"), fsec.raw("temperature")) if fsec.has("temperature") \
        else STANDARD_TEMPERATURE_CASE
    rarefaction = theory.choice("rarefaction", RAREFACTION_MODELS, RAREFACTION_MODELS[0])
    helium = cond.raw("helium_equivalent", False)
    if not isinstance(helium, bool):
        raise InputError(cond.field("helium_equivalent"), helium, "must be true or false")
    absolute = _absolute_pressures(cond)
    dp = _pressure_difference(cond, absolute)
    keys = {"fluid": fsec.field("name"), "temperature": fsec.field("temperature"), "pressure": cond.field("upstream_pressure")}
    known = None
    warnings: list[str] = []
    if name.strip():
        try:
            with case_keys(keys):
                known = canonical_fluid_name(name)
        except InputError as exc:
            if viscosity is None:
                raise
            warnings += _unknown_fluid(fsec, name, absolute, exc)
    elif viscosity is None:
        raise InputError(fsec.field("viscosity"), None, "is required: give the viscosity with its unit (e.g. \"1 mPa*s\"), "
                                                        "or fluid.name, a fluid of the property library (e.g. \"water\", \"helium\")")
    lookup = known is not None and (viscosity is None or absolute is not None or known not in _LIQUIDS_AT_ROOM)
    given_viscosity, given_density = viscosity, density
    state = gas = None
    if lookup:
        assert known is not None
        with case_keys(keys):
            state = fluid_state(known, temperature, absolute[0] if absolute is not None else STANDARD_PRESSURE)
        if state.phase not in ("gas", "supercritical", "liquid"):
            raise InputError(fsec.field("name"), name, f"is {state.phase} at {celsius(temperature):.4g} °C and "
                             f"{state.pressure:.6g} Pa (on its saturation line): choose a temperature or upstream pressure "
                             "where it is a gas or a liquid")
        if state.is_gas:
            if absolute is None:
                raise InputError(cond.field("upstream_pressure"), None,
                                 f"is required for a gas ({known} is a gas at {celsius(temperature):.4g} °C): give "
                                 "conditions.upstream_pressure and conditions.downstream_pressure (absolute, e.g. \"1 bar\" "
                                 "and \"0 Pa\" for vacuum); a gas's leak rate depends on both, not on ΔP alone")
            mu = viscosity if viscosity is not None else state.viscosity
            with case_keys({"viscosity": fsec.field("viscosity"), "temperature": fsec.field("temperature")}):
                g = Gas(name=known, temperature=temperature, viscosity=mu, molar_mass=state.molar_mass)
            gas = GasConditions(g, absolute[0], absolute[1], rarefaction, state)
            viscosity = mu
        else:
            viscosity = viscosity if viscosity is not None else state.viscosity
            density = density if density is not None else state.density
            if absolute is not None:
                note = vapour_pressure_note(state, *absolute)
                warnings += [note] if note else []
        name = known
    if known is not None:
        warnings += _property_warnings(fsec, known, state, temperature, given_viscosity, given_density)
    assert viscosity is not None
    if gas is None and theory.has("rarefaction") and not helium:
        raise InputError(theory.field("rarefaction"), theory.raw("rarefaction"), "is for gas flow: the fluid is a liquid "
                         "(set conditions.helium_equivalent = true for its helium-equivalent leak rate)")
    with case_keys():
        fluid = Fluid(viscosity, density, name, molecular)
    return _FluidInputs(fluid=fluid, pressure_difference=dp, temperature=temperature, absolute_pressures=absolute,
                        state=state, gas=gas, helium_equivalent=helium or gas is not None, rarefaction=rarefaction,
                        warnings=tuple(warnings))


#: A given fluid.viscosity or fluid.density this many times above or below the property library's value
#: for the named fluid gets a warning (the library's correlations are good to a few percent).
PROPERTY_FACTOR = 2.0


def _property_warnings(fsec: Section, known: str, state: FluidState | None, temperature: float,
                       viscosity: float | None, density: float | None) -> list[str]:
    """Warnings for a given viscosity or density far (:data:`PROPERTY_FACTOR`) from the library's for the named fluid.

    ``state`` is the looked-up state; a liquid of :data:`_LIQUIDS_AT_ROOM` with its viscosity given
    and no absolute pressures is not looked up, and is compared (at 1 atm) only when fluid.temperature
    is given: a liquid's viscosity at 20 °C is then often kept by mistake (water: 1 mPa·s at 20 °C,
    0.13 mPa·s at 200 °C, where at 1 atm it is steam).
    """
    if viscosity is None and density is None:
        return []
    if state is None:
        if not fsec.has("temperature"):
            return []
        try:
            state = fluid_state(known, temperature, STANDARD_PRESSURE)
        except InputError:  # outside the library's range: nothing to compare with
            return []
        if state.is_gas:
            return [f"{fsec.field('temperature')} = {fsec.raw('temperature')!r}: {known} is a gas at "
                    f"{celsius(temperature):.4g} °C and 1 atm, yet the case runs it as a liquid with the given "
                    f"{fsec.field('viscosity')}; give the absolute conditions.upstream_pressure and downstream_pressure "
                    "for the library's phase and properties"]
    where = f"{known} ({state.phase}) at {celsius(temperature):.4g} °C and {format_quantity(state.pressure, 'pressure', 4)}"
    out = []
    for key, given, library, unit, scale in (("viscosity", viscosity, state.viscosity, "mPa·s", 1e3),
                                             ("density", density, state.density, "kg/m³", 1.0)):
        if given is not None and library > 0 and not 1 / PROPERTY_FACTOR <= given / library <= PROPERTY_FACTOR:
            liquid = " (a liquid's?)" if state.is_gas and given > 20 * library else ""
            out.append(f"{fsec.field(key)} = {fsec.raw(key)!r}{liquid} is {given / library:.3g} times the property "
                       f"library's {library * scale:.3g} {unit} for {where}: the given value is used; check it")
    return out


def _unknown_fluid(fsec: Section, name: str, absolute: tuple[float, float] | None, exc: InputError) -> list[str]:
    """A fluid.name outside the property library, with its viscosity given: it runs as an incompressible liquid.

    A near miss of a library name ("helum") is refused when the case gives absolute pressures (a gas
    test, where a typo would silently turn the gas into a liquid), and warned about otherwise; any
    other unknown name with absolute pressures gets a warning that it is taken as a liquid.
    """
    hint = close_fluid_name(name)
    if hint and absolute is not None:
        raise InputError(fsec.field("name"), name, f"unknown fluid{hint}: a fluid outside the property library runs as an "
                         "incompressible liquid with its fluid.viscosity, never as a gas; use the library's name, or another "
                         "name for a liquid of your own")
    if hint:
        return [f"fluid.name = {name!r} is not in the property library{hint}: it runs as an incompressible liquid with the "
                "given fluid.viscosity"]
    if absolute is not None and "oils are not" not in exc.allowed:
        return [f"fluid.name = {name!r} is not in the property library: it runs as an incompressible liquid with the given "
                "fluid.viscosity (no gas flow, no vapour-pressure check); a gas must be one of the library's fluids"]
    return []


def _q0_error(seal_section: Section, theory: Section, seal: Seal, q0: float, why: str) -> InputError:
    """q0 = 2π/L is out of range: name the key it came from (theory.*, else the seal's width)."""
    problem = f"it sets q0 = 2π/L = {q0:.6g} 1/m, which must be {why.removeprefix('must be ')}" if why.startswith("must") else why
    if theory.has("lowest_wavevector"):
        return InputError(theory.field("lowest_wavevector"), theory.raw("lowest_wavevector"), why)
    if theory.has("square_side"):
        return InputError(theory.field("square_side"), theory.raw("square_side"), problem)
    key = {"ring": "outer_diameter", "o-ring": "cross_section_diameter", "profile": "pressure_profile"}.get(seal.shape, "width")
    width = f"{seal.width:.4g} m"
    return InputError(seal_section.field(key), seal_section.raw(key),
                      f"the seal width Lx = {width} is too narrow for the roughness: q0 = 2π/Lx = {q0:.6g} 1/m should be "
                      f"below the roughness cut-off ({why.removeprefix('must be ')}); check the seal's dimensions, or "
                      "set theory.square_side")


def _rig(raw: Any, fluid: Fluid, band: BandSeal | None = None, doc: dict[str, Any] | None = None) -> RigSetup | DecayRigSetup:
    """The [rig] section: the water-column rig of the reference experiment (:class:`~sealeak.lab.rig.RigSetup`),
    or with ``kind = "pressure-decay"`` the pressure-decay test of a gas (:class:`~sealeak.lab.rig.DecayRigSetup`,
    built by :func:`~sealeak.cases.rig_builders.decay_rig_setup`; ``doc`` gives its [fluid] and [theory]).

    For an O-ring or pressure-profile seal (``band``) the compression or profile scale sets the
    contact, so ``load`` is refused; the rig's load is then the band's contact force f·Ly (N) at
    its first load (the rig itself runs at one load only, :func:`sealeak.cases.rig.rig_prediction`).
    """
    sec = RigSection(raw)
    gravity = sec.quantity("gravity", "acceleration") if sec.has("gravity") else STANDARD_GRAVITY
    if sec.kind == "pressure-decay":
        doc = doc or {}
        if band is not None and sec.has("load"):
            raise InputError(sec.field("load"), sec.raw("load"), "is not used here: the seal's compression or profile_scale "
                                                                 "(in [conditions]) sets the contact; remove load")
        if band is None and not sec.has("load"):
            raise InputError(sec.field("load"), None, "is required: the mass (e.g. '3.4 kg') or force (e.g. '33 N') on the seal")
        decay_load = None if band is not None else _rig_load(sec, gravity)
        fluid_doc, theory_doc = doc.get("fluid", {}), doc.get("theory", {})
        return decay_rig_setup(sec, fluid, fluid_doc if isinstance(fluid_doc, dict) else {},
                               theory_doc if isinstance(theory_doc, dict) else {}, band, decay_load)
    if band is not None:
        what = "an O-ring's compression" if band.kind == "o-ring" else "a pressure profile's profile_scale"
        if sec.has("load"):
            raise InputError(sec.field("load"), sec.raw("load"), f"is not used here: {what} (in [conditions]) sets the "
                                                                 "contact; remove load")
        load = band.profiles[0].force_per_length * band.length
        shown = f"compression {100 * band.loads[0]:.4g} %" if band.kind == "o-ring" else f"profile_scale {band.loads[0]:.4g}"
        note = f"the contact force f·Ly at {shown}"
    elif not sec.has("load"):
        raise InputError(sec.field("load"), None, "is required: the mass (e.g. '3.4 kg') or force (e.g. '33 N') on the ring")
    else:
        load, note = _rig_load(sec, gravity)
    if sec.has("density"):
        density = sec.quantity("density", "density")
    elif fluid.density is not None:
        density = fluid.density
    else:
        raise InputError(sec.field("density"), None, "is required (or give [fluid] density): the rig needs ρ for ΔP = ρ g H")
    final = sec.quantity("final_height", "length") if sec.has("final_height") else None
    duration = sec.quantity("duration", "time") if sec.has("duration") else None
    diameter = sec.quantity("cylinder_diameter", "length")
    height = sec.quantity("initial_height", "length")
    if final is not None and final > 0 and not final < height:  # (named as written: RigSetup names it in metres)
        raise InputError(sec.field("final_height"), sec.raw("final_height"),
                         f"must be below rig.initial_height = {show_value(sec.raw('initial_height'))}")
    with case_keys():
        return RigSetup(cylinder_diameter=diameter, initial_height=height, load=load, density=density,
                        final_height=final, gravity=gravity, duration=duration, load_note=note)


def _rig_load(sec: Section, gravity: float) -> tuple[float, str]:
    """[rig] load as a force (N), given as a mass (× g) or a force, and how it was given."""
    try:
        mass = sec.quantity("load", "mass")
        return mass * gravity, f"load {mass:g} kg × g"
    except UnitError:
        try:
            return sec.quantity("load", "force"), "load given as a force"
        except UnitError:
            raise UnitError(sec.field("load"), sec.raw("load"),
                            "a mass (e.g. '3.4 kg') or a force (e.g. '33 N') with its unit") from None


def _simulation(sec: Section) -> dict[str, Any]:
    """The [simulation] section: defaults of ``sealeak simulate`` (its options override them).

    Checked by the simulation options' own rules (:mod:`sealeak.cases.options`). ``grid`` is an integer,
    or a list of them for a convergence study (kept as a sorted tuple; a list of one is that integer).
    """
    out: dict[str, Any] = {}
    if sec.has("realizations"):
        out["realizations"] = whole_number(sec.field("realizations"), sec.raw("realizations"), 1, MAX_REALIZATIONS)
    if sec.has("grid"):
        v = sec.raw("grid")
        grids = parse_grid_list(v, sec.field("grid")) if isinstance(v, list) else (grid_number(sec.field("grid"), v),)
        out["grid"] = grids[0] if len(grids) == 1 else grids
    if sec.has("seed"):
        out["seed"] = seed_number(sec.field("seed"), sec.raw("seed"))
    if sec.has("device"):
        out["device"] = device_name(sec.field("device"), sec.raw("device"))
    return out
