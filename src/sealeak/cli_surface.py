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


def _analysis_text(an) -> str:
    lines = []
    for src in an.sources:
        s = src.surface
        lines.append(f"source  {src.label}")
        shape = "x".join(str(n) for n in np.shape(s.heights))
        lines.append(f"        {type(s).__name__} {shape} points")
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
        lines.append("  [stitched C(q)]")
        for name, unit, _, b in _stat_rows(an.statistics):
            if b is not None:
                lines.append(f"  {name:15s} {unit:6s} {_fmt(b, unit):>13s}")
    sp = an.spectrum
    lines.append("")
    lines.append(f"C(q): {sp.q.size} points, reliable range q = {sp.q_min:.4g} .. {sp.q_max:.4g} 1/m "
                 f"(λ = {2 * np.pi / sp.q_max * 1e6:.4g} .. {2 * np.pi / sp.q_min * 1e6:.4g} µm)")
    if an.fit is not None:
        f = an.fit
        qr = (f"q_r = {f.q_rolloff:.4g} ± {f.q_rolloff_err:.2g} 1/m" if f.rolloff_resolved
              else "no roll-off resolved")
        lines.append(f"self-affine fit: H = {f.hurst:.3f} ± {f.hurst_err:.3f}, {qr}, "
                     f"h_rms = {f.h_rms * 1e6:.4g} ± {f.h_rms_err * 1e6:.2g} µm, reduced χ² = {f.chi2_red:.3g}")
    if an.notes:
        lines.append("")
        lines.append("what was done:")
        lines.extend(f"  - {n}" for n in an.notes)
    return "\n".join(lines) + "\n"


def _json_value(x):
    from .output import json_value

    return json_value(x)


def _analysis_json(an) -> str:
    st = an.statistics
    stats = {k: _json_value(getattr(st, k)) for k in (
        "h_rms", "slope_rms", "curvature_rms", "area_ratio", "skewness", "kurtosis",
        "spectrum_h_rms", "spectrum_slope_rms", "spectrum_curvature_rms", "spectrum_area_ratio")}
    doc: dict[str, Any] = {
        "units": {"h_rms": "m", "slope_rms": "1", "curvature_rms": "1/m", "area_ratio": "1", "skewness": "1",
                  "kurtosis": "1", "q": "1/m", "C": "m^4"},
        "statistics": stats,
        "psd": {"q": an.spectrum.q.tolist(), "C": an.spectrum.C.tolist()},
        "sources": [{"label": s.label, "statistics": {k: _json_value(getattr(s.statistics, k)) for k in (
            "h_rms", "slope_rms", "curvature_rms", "area_ratio", "skewness", "kurtosis")},
            "notes": list(s.notes)} for s in an.sources],
        "notes": list(an.notes),
    }
    if an.fit is not None:
        f = an.fit
        doc["fit"] = {k: _json_value(getattr(f, k)) for k in (
            "hurst", "hurst_err", "q_rolloff", "q_rolloff_err", "rolloff_resolved", "C0", "C0_err",
            "h_rms", "h_rms_err", "chi2_red")}
    return json.dumps(doc, indent=2, ensure_ascii=False) + "\n"


def _psd_csv(spectrum) -> str:
    rows = ["q (1/m), C (m^4)"] + [f"{q:.10g}, {c:.10g}" for q, c in zip(spectrum.q, spectrum.C)]
    return "\n".join(rows) + "\n"


def _cmd_analyze(args: argparse.Namespace) -> int:
    from ._io import atomic_write, check_outputs, write_text
    from .topography import analyze, plot_spectra

    check_outputs([p for p in (args.psd_out, args.plot, args.json) if p], args.force)
    an = analyze(args.files, **unit_options(args), bins_per_decade=args.bins_per_decade)
    sys.stdout.write(_analysis_text(an))
    if args.psd_out:
        write_text(args.psd_out, _psd_csv(an.spectrum))
        print(f"wrote {args.psd_out}", file=sys.stderr)
    if args.json:
        write_text(args.json, _analysis_json(an))
        print(f"wrote {args.json}", file=sys.stderr)
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
    from ._io import atomic_write, check_outputs
    from .synthesis import synthesize
    from .units import parse_quantity

    out = Path(args.output)
    if out.suffix not in (".npy", ".txt", ".csv"):
        raise InputError("--output", str(out), "must end in .npy, .txt or .csv")
    check_outputs([out], args.force)
    spectrum, width = _spectrum_for_synthesis(args)
    if args.size:
        size = parse_quantity("--size", args.size, "length")
    elif width is not None:
        size = width
    else:
        raise InputError("--size", None, "is required with --psd (side of the square map, e.g. '5 mm')")
    if size <= 0:
        raise InputError("--size", args.size, "must be > 0")
    q_nyquist = np.pi * args.grid / size
    h = synthesize(spectrum, args.grid, size, seed=args.seed, amplitudes=args.amplitudes)
    with atomic_write(out) as tmp:
        if out.suffix == ".npy":
            with open(tmp, "wb") as fh:
                np.save(fh, h)
        else:
            header = (f"sealeak synthesized surface: {args.grid} x {args.grid} points, size {size:.10g} m x "
                      f"{size:.10g} m, heights in m, periodic, seed {args.seed}")
            np.savetxt(tmp, h, fmt="%.10e", header=header, delimiter=" " if out.suffix == ".txt" else ",")
    print(f"wrote {out}: {args.grid} x {args.grid} heights (m), side {size:.6g} m, periodic; "
          f"h_rms = {h.std() * 1e6:.4g} µm (spectrum: {spectrum.h_rms * 1e6:.4g} µm)", file=sys.stderr)
    if spectrum.q_max > q_nyquist:
        print(f"note: the grid resolves q up to {q_nyquist:.4g} 1/m; C(q) above that (to {spectrum.q_max:.4g} 1/m) "
              "is left out of the map", file=sys.stderr)
    print(f"analyze it with: sealeak surface analyze {out} --size '{size:.6g} m' --height-unit m --periodic",
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
    p.add_argument("-o", "--output", required=True, help="output file: .npy, or .txt/.csv (matrix of heights in m)")
    p.set_defaults(func=_cmd_synthesize)
