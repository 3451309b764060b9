"""``sealeak surface analyze|synthesize``: measured topographies to C(q), and random surfaces from C(q)."""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path
from typing import Any, Callable

import numpy as np

from .errors import InputError, SealeakError

__all__ = ["register", "unit_options"]


def _lengths(text: str | None, field: str) -> float | tuple[float, float] | None:
    """'1 mm' -> 1e-3; '1 mm, 0.5 mm' -> (1e-3, 5e-4)."""
    from .units import parse_quantity

    if text is None:
        return None
    parts = [p.strip() for p in text.split(",") if p.strip()]
    if not 1 <= len(parts) <= 2:
        raise InputError(field, text, "one length (square) or two separated by a comma, e.g. '1 mm, 0.5 mm'")
    values = [parse_quantity(field, p, "length") for p in parts]
    for v, p in zip(values, parts):
        if v <= 0:
            raise InputError(field, p, "must be a length > 0")
    return values[0] if len(values) == 1 else (values[0], values[1])


def unit_options(args: argparse.Namespace) -> dict[str, Any]:
    """The unit keyword arguments of :func:`sealeak.topography.analyze` from CLI options."""
    if args.size and args.pixel_size:
        raise InputError("--size", args.size, "give either --size or --pixel-size, not both")
    return dict(size=_lengths(args.size, "--size"), pixel_size=_lengths(args.pixel_size, "--pixel-size"),
                height_unit=args.height_unit, lateral_unit=args.lateral_unit, periodic=args.periodic,
                channel=args.channel)


def range_options(args: argparse.Namespace) -> dict[str, Any]:
    """The reliable-range keyword arguments of :func:`sealeak.topography.analyze` from CLI options."""
    from .units import parse_quantity

    out: dict[str, Any] = dict(bins_per_decade=args.bins_per_decade, low_cut=args.low_cut,
                               resolution_pixels=args.resolution_pixels)
    if args.resolution is not None:
        value = parse_quantity("--resolution", args.resolution, "length")
        if not value > 0:
            raise InputError("--resolution", args.resolution, "must be a length > 0, e.g. '2 um'")
        out["resolution"] = value
    return out


def _stat_rows(stats) -> list[tuple[str, str, float | None, float | None]]:
    return [
        ("h_rms", "µm", stats.h_rms, stats.spectrum_h_rms),
        ("slope_rms", "1", stats.slope_rms, stats.spectrum_slope_rms),
        ("curvature_rms", "1/mm", stats.curvature_rms, stats.spectrum_curvature_rms),
        ("area_ratio", "1", stats.area_ratio, stats.spectrum_area_ratio),
        ("skewness", "1", stats.skewness, None),
        ("kurtosis", "1", stats.kurtosis, None),
    ]


_SCALE = {"µm": 1e6, "1/mm": 1e-3, "1": 1.0}


def _fmt(v: float | None, unit: str) -> str:
    return "—" if v is None or not np.isfinite(v) else f"{v * _SCALE[unit]:.4g}"


def _source_size(surface) -> list[float]:
    return list(surface.size) if hasattr(surface, "size") else [surface.length]


def _analysis_text(an) -> str:
    lines = []
    for src in an.sources:
        s = src.surface
        lines.append(f"source  {src.label}")
        shape = "x".join(str(n) for n in np.shape(s.heights))
        extent = " x ".join(f"{v * 1e6:.4g}" for v in _source_size(s))
        lines.append(f"        {type(s).__name__} {shape} points, {extent} µm")
        if src.spectrum_problem is None:
            lo, hi = src.spectrum.q_reliable
            lines.append(f"        reliable range q = {lo:.4g} .. {hi:.4g} 1/m")
        elif len(an.sources) > 1:
            lines.append(f"        no C(q): {src.spectrum_problem}")
    lines.append("")
    header = "statistics of the single measurement" if len(an.sources) == 1 else "statistics of each measurement"
    lines.append(header)
    if len(an.sources) == 1:
        lines.append(f"  {'quantity':15s} {'unit':6s} {'from heights':>13s} {'from C(q)':>11s}")
        for name, unit, a, b in _stat_rows(an.statistics):
            lines.append(f"  {name:15s} {unit:6s} {_fmt(a, unit):>13s} {_fmt(b, unit):>11s}")
    else:
        for src in an.sources:
            lines.append(f"  [{src.label}]")
            for name, unit, a, _ in _stat_rows(src.statistics):
                lines.append(f"  {name:15s} {unit:6s} {_fmt(a, unit):>13s}")
        if an.has_spectrum:
            lines.append("  [stitched C(q)]")
            for name, unit, _, b in _stat_rows(an.statistics):
                if b is not None:
                    lines.append(f"  {name:15s} {unit:6s} {_fmt(b, unit):>13s}")
            lines.append(f"  (JSON statistics: {an.statistics.method})")
    lines.append("")
    if an.has_spectrum:
        sp = an.spectrum
        lines.append(f"C(q): {sp.q.size} points, reliable range q = {sp.q_min:.4g} .. {sp.q_max:.4g} 1/m "
                     f"(λ = {2 * np.pi / sp.q_max * 1e6:.4g} .. {2 * np.pi / sp.q_min * 1e6:.4g} µm)")
    elif len(an.sources) > 1:
        lines.append("C(q): none: no measurement gives a reliable C(q) (reasons above)")
    else:
        lines.append(f"C(q): none: {an.spectrum_problem}")
    if an.fit is not None:
        f = an.fit
        qr = (f"q_r = {f.q_rolloff:.4g} ± {f.q_rolloff_err:.2g} 1/m" if f.rolloff_resolved
              else "no roll-off resolved")
        herr = f"± {f.hurst_err:.3f}" if np.isfinite(f.hurst_err) else "(at the bound of 0 < H < 1)"
        herr_h = f" ± {f.h_rms_err * 1e6:.2g}" if np.isfinite(f.h_rms_err) else ""
        lines.append(f"self-affine fit: H = {f.hurst:.3f} {herr}, {qr}, "
                     f"h_rms = {f.h_rms * 1e6:.4g}{herr_h} µm, reduced χ² = {f.chi2_red:.3g}")
        if f.warning:
            lines.append(f"  warning: {f.warning}")
    if an.notes:
        lines.append("")
        lines.append("what was done:")
        lines.extend(f"  - {n}" for n in an.notes)
    return "\n".join(lines) + "\n"


def _json_value(x):
    from .output import json_value

    return json_value(x)


_STAT_KEYS = ("h_rms", "slope_rms", "curvature_rms", "area_ratio", "skewness", "kurtosis")
_SPECTRAL_KEYS = ("spectrum_h_rms", "spectrum_slope_rms", "spectrum_curvature_rms", "spectrum_area_ratio")


def _analysis_json(an) -> str:
    st = an.statistics
    stats = {k: _json_value(getattr(st, k)) for k in _STAT_KEYS + _SPECTRAL_KEYS}
    stats["method"] = st.method
    doc: dict[str, Any] = {
        "units": {"h_rms": "m", "slope_rms": "1", "curvature_rms": "1/m", "area_ratio": "1", "skewness": "1",
                  "kurtosis": "1", "q": "1/m", "C": "m^4", "size": "m", "reliable_range": "1/m"},
        "statistics": stats,
        "psd": ({"q": an.spectrum.q.tolist(), "C": an.spectrum.C.tolist()} if an.has_spectrum else None),
        "sources": [{
            "label": s.label,
            "kind": "map" if hasattr(s.surface, "size") else "line scans",
            "grid": list(np.shape(s.surface.heights)),
            "size": _source_size(s.surface),
            "periodic": bool(s.surface.periodic),
            "reliable_range": list((s.spectrum or s.profile_spectrum).q_reliable),
            "spectrum_problem": s.spectrum_problem,
            "statistics": {**{k: _json_value(getattr(s.statistics, k)) for k in _STAT_KEYS + _SPECTRAL_KEYS},
                           "method": s.statistics.method},
            "notes": list(s.notes)} for s in an.sources],
        "notes": list(an.notes),
    }
    if not an.has_spectrum:
        doc["psd_problem"] = an.spectrum_problem
    if an.fit is not None:
        f = an.fit
        doc["fit"] = {k: _json_value(getattr(f, k)) for k in (
            "hurst", "hurst_err", "q_rolloff", "q_rolloff_err", "rolloff_resolved", "C0", "C0_err",
            "h_rms", "h_rms_err", "chi2_red", "hurst_in_range", "hurst_wanted", "warning")}
    return json.dumps(doc, indent=2, ensure_ascii=False) + "\n"


def _psd_csv(spectrum) -> str:
    rows = ["q (1/m), C (m^4)"] + [f"{q:.10g}, {c:.10g}" for q, c in zip(spectrum.q, spectrum.C)]
    return "\n".join(rows) + "\n"


def _cmd_analyze(args: argparse.Namespace) -> int:
    from ._io import atomic_write, check_outputs, write_text
    from .topography import analyze, cli_option_names, plot_spectra

    check_outputs([p for p in (args.psd_out, args.plot, args.json) if p], args.force)
    with cli_option_names():  # messages name --height-unit, --size, ... instead of keyword arguments
        an = analyze(args.files, **unit_options(args), **range_options(args))
    sys.stdout.write(_analysis_text(an))
    sys.stdout.flush()
    if args.json:
        write_text(args.json, _analysis_json(an))
        print(f"wrote {args.json}", file=sys.stderr)
    if not an.has_spectrum and (args.psd_out or args.plot):
        wanted = " and ".join(o for o, v in (("--psd-out", args.psd_out), ("--plot", args.plot)) if v)
        raise SealeakError(f"{wanted}: no C(q) to write: {an.spectrum_problem}")
    if args.psd_out:
        write_text(args.psd_out, _psd_csv(an.spectrum))
        print(f"wrote {args.psd_out}", file=sys.stderr)
    if args.plot:
        import matplotlib.pyplot as plt

        fig = plot_spectra(an)
        with atomic_write(args.plot) as tmp:
            fig.savefig(tmp, format="png", bbox_inches="tight", dpi=150)
        plt.close(fig)
        print(f"wrote {args.plot}", file=sys.stderr)
    return 0


def _spectrum_for_synthesis(args: argparse.Namespace):
    from .casefile import example_path, load_cases
    from .roughness import PowerSpectrum

    given = [x for x in (args.case, args.example, args.psd) if x]
    if len(given) != 1:
        raise SealeakError("give exactly one source of C(q): a case file, --example NAME or --psd TABLE.csv")
    if args.psd:
        return PowerSpectrum.from_table(args.psd, label=Path(args.psd).name), None
    cases = load_cases(example_path(args.example) if args.example else args.case)
    return cases[0].spectrum, cases[0].seal.width


def _cmd_synthesize(args: argparse.Namespace) -> int:
    from ._io import check_outputs
    from .numerics._memory import require_memory
    from .synthesis import synthesis_memory_bytes, synthesize
    from .topography import write_height_map
    from .topography._writers import HEIGHT_MAP_SUFFIXES, height_map_outputs
    from .units import parse_quantity

    out = Path(args.output)
    if out.suffix.lower() not in HEIGHT_MAP_SUFFIXES:
        raise InputError("--output", str(out), f"must end in {', '.join(HEIGHT_MAP_SUFFIXES)}")
    if args.grid < 4 or args.grid % 2:
        raise InputError("--grid", args.grid, "must be an even number of points per side, >= 4")
    if args.seed < 0:
        raise InputError("--seed", args.seed, "must be a non-negative integer (0, 1, 2, ...)")
    n = args.grid
    # refuse before any work: the synthesis peak, then the map kept while the file is written
    require_memory(synthesis_memory_bytes(n), f"--grid {n}: synthesizing a {n}x{n} map")
    check_outputs(height_map_outputs(out), args.force)
    spectrum, width = _spectrum_for_synthesis(args)
    if args.size:
        size = parse_quantity("--size", args.size, "length")
    elif width is not None:
        size = width
    else:
        raise InputError("--size", None, "is required with --psd (side of the square map, e.g. '5 mm')")
    if size <= 0:
        raise InputError("--size", args.size, "must be > 0")
    q_nyquist = np.pi * n / size
    h = synthesize(spectrum, n, size, seed=args.seed, amplitudes=args.amplitudes)
    source = f"--psd {Path(args.psd).name}" if args.psd else (f"--example {args.example}" if args.example
                                                               else f"case {Path(args.case).name}")
    written = write_height_map(out, h, (size, size), periodic=True, comments=[
        f"synthesized by sealeak surface synthesize: C(q) of {source}, seed {args.seed}, {args.amplitudes} amplitudes"])
    h_rms = float(np.linalg.norm(h.ravel())) / n  # the map has mean zero; no full-size temporary
    also = f" (+ {written[1].name}: size and units)" if len(written) > 1 else ""
    print(f"wrote {out}{also}: {n} x {n} heights (m), side {size:.6g} m, periodic; "
          f"h_rms = {h_rms * 1e6:.4g} µm (spectrum: {spectrum.h_rms * 1e6:.4g} µm)", file=sys.stderr)
    if spectrum.q_max > q_nyquist:
        print(f"note: the grid resolves q up to {q_nyquist:.4g} 1/m; C(q) above that (to {spectrum.q_max:.4g} 1/m) "
              "is left out of the map", file=sys.stderr)
    if out.suffix.lower() in (".txt", ".csv") and n * n * 25 > 512 * 2**20:
        print("note: text maps larger than 512 MiB are refused by the reader; use .npz or .npy", file=sys.stderr)
    print(f"analyze it with: sealeak surface analyze {out} (the file states its size, unit and periodicity)",
          file=sys.stderr)
    return 0


def _add_unit_args(p: argparse.ArgumentParser) -> None:
    p.add_argument("--size", metavar="LEN[,LEN]", help="physical size of a map without metadata: '1 mm' (square) "
                   "or '1 mm, 0.5 mm'")
    p.add_argument("--pixel-size", metavar="LEN[,LEN]", help="grid spacing instead of --size, e.g. '2 um'")
    p.add_argument("--height-unit", metavar="UNIT", help="unit of the heights in files without one, e.g. um")
    p.add_argument("--lateral-unit", metavar="UNIT", help="unit of x (and y) columns in files without one")
    p.add_argument("--periodic", action="store_true", help="the map is periodic: no window, only the mean removed")
    p.add_argument("--channel", help="channel (index or name) of multi-channel instrument files")


def register(sub: argparse._SubParsersAction, add_case_args: Callable[[argparse.ArgumentParser], None]) -> None:
    parent = sub.add_parser("surface", help="measured topographies: analyze files into C(q); synthesize surfaces")
    ssub = parent.add_subparsers(dest="surface_command", metavar="ACTION", parser_class=type(parent))
    parent.set_defaults(func=lambda a: (parent.print_help(), 2)[1])

    p = ssub.add_parser("analyze", help="statistics and C(q) of one or more topography files (stitched)")
    p.add_argument("files", nargs="+", metavar="FILE", help="height maps or line scans (instrument or text files)")
    _add_unit_args(p)
    p.add_argument("--bins-per-decade", type=float, default=10.0, help="log-spaced q bins per decade (default 10)")
    p.add_argument("--low-cut", type=float, default=3.0, metavar="N",
                   help="the reliable range starts at q = N·2π/L, L the shorter side (default 3)")
    p.add_argument("--resolution", metavar="LEN",
                   help="shortest reliable wavelength (lateral resolution of the instrument), e.g. '2 um'; "
                        "default: what the file states (e.g. a stylus tip radius), if anything")
    p.add_argument("--resolution-pixels", type=float, default=4.0, metavar="N",
                   help="the reliable range never extends to wavelengths below N pixels (default 4; 2 = Nyquist)")
    p.add_argument("--psd-out", metavar="FILE.csv", help="write C(q) as a two-column table (q in 1/m, C in m^4)")
    p.add_argument("--plot", metavar="FILE.png", help="draw C(q) of each source and the stitched result")
    p.add_argument("--json", metavar="FILE", help="write statistics and C(q) as JSON")
    p.add_argument("--force", action="store_true", help="overwrite existing output files")
    p.set_defaults(func=_cmd_analyze)

    p = ssub.add_parser("synthesize", help="a periodic random height map with the C(q) of a case or table")
    add_case_args(p)
    p.add_argument("--psd", metavar="TABLE.csv", help="take C(q) from a two-column table instead of a case")
    p.add_argument("--grid", type=int, default=512, help="points per side (even; default 512)")
    p.add_argument("--size", help="side of the square map (default: the case's seal width Lx)")
    p.add_argument("--seed", type=int, default=0, help="random seed (default 0); the same seed gives the same map")
    p.add_argument("--amplitudes", choices=("gaussian", "phases"), default="gaussian",
                   help="Gaussian random amplitudes, or exact amplitudes with random phases")
    p.add_argument("-o", "--output", required=True,
                   help="output file: .npz (heights and size), .npy (+ NAME.npy.json with the size) or .txt/.csv "
                        "(one row per y, heights in m, size in the header); `surface analyze` reads each back "
                        "without unit options")
    p.set_defaults(func=_cmd_synthesize)
