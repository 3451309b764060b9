"""``sealeak surface analyze|synthesize``: measured topographies to C(q), and random surfaces from C(q)."""

from __future__ import annotations

import argparse
import math
import sys
from collections.abc import Callable
from pathlib import Path
from typing import Any

from ..errors import InputError, SealeakError
from ._common import emit, inputs, load, outputs, say

#: The file suffixes ``surface analyze --plot`` writes, each in its own format (matplotlib's).
PLOT_FORMATS = (".png", ".pdf", ".svg")

__all__ = ["register", "unit_options"]


def unit_options(args: argparse.Namespace) -> dict[str, Any]:
    """The unit and reliable-range keyword arguments of :func:`sealeak.topography.analyze` from CLI options."""
    from ..topography import analysis_options

    return analysis_options(size=args.size, pixel_size=args.pixel_size, height_unit=args.height_unit,
                            lateral_unit=args.lateral_unit, periodic=args.periodic, channel=args.channel,
                            bins_per_decade=args.bins_per_decade, low_cut=args.low_cut, resolution=args.resolution,
                            resolution_pixels=args.resolution_pixels)


def _cmd_analyze(args: argparse.Namespace) -> int:
    from ..io.files import atomic_write, check_outputs
    from ..render import analysis_json, analysis_text, plot_spectra, spectrum_csv
    from ..topography import analyze, cli_option_names

    check_outputs(outputs(args, files=("psd_out", "plot", "json"), folders=()), args.force, inputs=inputs(args, "files"))
    if args.plot and Path(args.plot).suffix.lower() not in PLOT_FORMATS:
        raise InputError("--plot", args.plot, f"must end in {', '.join(PLOT_FORMATS[:-1])} or {PLOT_FORMATS[-1]} "
                                              "(the file's format follows its name)")
    with cli_option_names():  # messages name --height-unit, --size, ... instead of keyword arguments
        an = analyze(args.files, **unit_options(args))
    if not an.has_spectrum and (args.psd_out or args.plot):  # before any output: nothing is left behind
        wanted = " and ".join(o for o, v in (("--psd-out", args.psd_out), ("--plot", args.plot)) if v)
        raise SealeakError(f"{wanted}: no C(q) to write: {an.spectrum_problem}")
    files = ({args.json: analysis_json(an)} if args.json else {}) | (
        {args.psd_out: spectrum_csv(an.spectrum)} if args.psd_out else {})
    emit(args, analysis_text(an), files, {})
    sys.stdout.flush()
    if args.plot:
        fig = plot_spectra(an)
        with atomic_write(args.plot) as tmp:
            fig.savefig(tmp, format=Path(args.plot).suffix.lower()[1:], bbox_inches="tight", dpi=150)
        print(f"wrote {args.plot}", file=sys.stderr)
    return 0


def _spectrum_for_synthesis(args: argparse.Namespace):
    from ..physics import PowerSpectrum

    given = [x for x in (args.case, args.example, args.psd) if x]
    if len(given) != 1:
        raise SealeakError("give exactly one source of C(q): a case file, --example NAME or --psd TABLE.csv")
    if args.psd:
        return PowerSpectrum.from_table(args.psd, label=Path(args.psd).name), None
    cases = load(args)  # read once: check_outputs has read it for the files it names
    return cases[0].spectrum, cases[0].seal.width


#: Below this share of the spectrum's h_rms² in the map, synthesize warns.
CAPTURED_WARN = 0.1


def _captured_warning(spectrum, n: int, size: float, size_flag: str) -> str | None:  # type: ignore[no-untyped-def]
    """A warning when the map holds less than CAPTURED_WARN of the spectrum's h_rms², saying what is left out."""
    from ..numerics.synthesis import map_variance
    from ..topography import length_text

    share = map_variance(spectrum, n, size) / spectrum.h_rms**2
    if share >= CAPTURED_WARN:
        return None
    q_long, q_short = 2.0 * math.pi / size, math.pi * n / size
    lost = []
    if spectrum.q_min < q_long:
        lost.append(f"the wavelengths longer than the map's side (a larger {size_flag} keeps them)")
    if spectrum.q_max > q_short:
        lost.append("the wavelengths shorter than two pixels (a larger --grid keeps them)")
    return (f"warning: the map holds only {100 * share:.3g} % of the spectrum's h_rms² (C(q) spans wavelengths "
            f"{length_text(2 * math.pi / spectrum.q_max)} .. {length_text(2 * math.pi / spectrum.q_min)}, the map "
            f"{length_text(2 * size / n)} .. {length_text(size)}); left out: {' and '.join(lost)}")


def _cmd_synthesize(args: argparse.Namespace) -> int:
    import numpy as np

    from ..io.files import check_outputs
    from ..io.units import parse_quantity
    from ..numerics import require_memory, synthesis_memory_bytes, synthesize
    from ..numerics.synthesis import band_problem
    from ..topography import HEIGHT_MAP_SUFFIXES, height_map_outputs, length_text, write_height_map

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
    check_outputs(height_map_outputs(out), args.force, inputs=inputs(args, "psd"))
    spectrum, width = _spectrum_for_synthesis(args)
    if args.size:
        size = parse_quantity("--size", args.size, "length")
    elif width is not None:
        size = width
    else:
        raise InputError("--size", None, "is required with --psd (side of the square map, e.g. '5 mm')")
    if size <= 0:
        raise InputError("--size", args.size, "must be > 0")
    size_flag = "--size" if args.size else "--size (not given: the case's seal width)"
    empty = band_problem(spectrum, n, size, size_name="--size", grid_name="--grid")
    if empty is not None:  # the map would be flat: refused before anything is written
        raise InputError(size_flag, args.size or length_text(size), empty)
    warning = _captured_warning(spectrum, n, size, "--size")
    q_nyquist = math.pi * n / size
    h = synthesize(spectrum, n, size, seed=args.seed, amplitudes=args.amplitudes)
    source = f"--psd {Path(args.psd).name}" if args.psd else (f"--example {args.example}" if args.example
                                                               else f"case {Path(args.case).name}")
    written = write_height_map(out, h, (size, size), periodic=True, comments=[
        f"synthesized by sealeak surface synthesize: C(q) of {source}, seed {args.seed}, {args.amplitudes} amplitudes"])
    h_rms = float(np.linalg.norm(h.ravel())) / n  # the map has mean zero; no full-size temporary
    also = f" (+ {written[1].name}: size and units)" if len(written) > 1 else ""
    say(args, f"wrote {out}{also}: {n} x {n} heights (m), side {size:.6g} m, periodic; "
              f"h_rms = {h_rms * 1e6:.4g} µm (spectrum: {spectrum.h_rms * 1e6:.4g} µm)")
    if warning:
        say(args, warning)
    if spectrum.q_max > q_nyquist:
        say(args, f"note: the grid resolves q up to {q_nyquist:.4g} 1/m; C(q) above that (to {spectrum.q_max:.4g} 1/m) "
                  "is left out of the map")
    if out.suffix.lower() in (".txt", ".csv") and n * n * 25 > 512 * 2**20:
        say(args, "note: text maps larger than 512 MiB are refused by the reader; use .npz or .npy")
    say(args, f"analyze it with: sealeak surface analyze {out} (the file states its size, unit and periodicity)")
    return 0


def _add_unit_args(p: argparse.ArgumentParser) -> None:
    p.add_argument("--size", metavar="LEN[,LEN]", help="physical size of a map without metadata: '1 mm' (square) "
                   "or '1 mm, 0.5 mm'")
    p.add_argument("--pixel-size", metavar="LEN[,LEN]", help="grid spacing instead of --size, e.g. '2 um'")
    p.add_argument("--height-unit", metavar="UNIT", help="unit of the heights in files without one, e.g. um, "
                                                                 "or a scaled unit such as '0.3 nm' (heights in counts of 0.3 nm)")
    p.add_argument("--lateral-unit", metavar="UNIT", help="unit of x (and y) columns in files without one")
    p.add_argument("--periodic", action="store_true", help="the map is periodic: no window, only the mean removed")
    p.add_argument("--channel", help="channel (index or name) of multi-channel instrument files")


def register(sub: argparse._SubParsersAction, add_case_args: Callable[[argparse.ArgumentParser], None]) -> None:
    """Add ``surface analyze`` and ``surface synthesize`` to the sub-command parsers."""
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
    p.add_argument("--plot", metavar="FILE.png", help="draw C(q) of each source and the stitched result "
                                                      "(.png, or .pdf / .svg for a vector figure)")
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
