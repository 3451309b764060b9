"""The ``sealeak`` command line: a thin layer over :mod:`sealeak.cases` and :mod:`sealeak.render`.

User mistakes (bad case files, units, existing outputs) are SealeakError: the CLI prints
``sealeak: error: <message>`` to stderr and exits with status 2, without a traceback.
Figures are written with matplotlib's non-interactive Agg backend, which :func:`main` selects for
the command line only (``import sealeak`` never touches the backend).
"""

from __future__ import annotations

import argparse
import shutil
import sys
import textwrap
from collections.abc import Sequence

from .._version import __version__
from ..errors import SealeakError
from . import lab, serve, simulate, surface
from ._common import (
    EXIT_INTERRUPTED,
    EXIT_USER_ERROR,
    Parser,
    add_case_args,
    add_output_args,
    add_sensitivity_arg,
    add_uncertainty_args,
    check_sensitivity,
    emit,
    inputs,
    load_case_file,
    outputs,
    propagation,
    sobol_sensitivity,
    usage_message,
)

__all__ = ["main", "build_parser"]


def _cmd_predict(args: argparse.Namespace) -> int:
    from ..cases import run_case
    from ..io.files import check_outputs
    from ..render import prediction_csv, prediction_figures, prediction_json, prediction_table, render_figures
    from ..render.figures import prediction_figure_names
    from ..render.life import volume_limit
    from ..render.uncertainty_figures import uncertainty_figure_names, uncertainty_figures

    case_file = load_case_file(args)  # read first: the figures of an O-ring or profile seal are other files
    cases = case_file.cases
    uncertain = case_file.spreads.active and bool(case_file.spreads.inputs)  # max_leak_rate alone draws no band
    check_sensitivity(args, case_file)  # before any sample runs
    names = prediction_figure_names(cases) + (uncertainty_figure_names(args.sensitivity is not None) if uncertain else ())
    check_outputs(outputs(args, names, files=("table", "json", "csv")), args.force, inputs=inputs(args))
    uncertainty = propagation(args, case_file)  # None without uncertain inputs
    results = uncertainty.nominal if uncertainty is not None else [run_case(c) for c in cases]
    sensitivity = sobol_sensitivity(args, uncertainty)
    # render everything first, then write: a failure while rendering leaves no file behind
    table = prediction_table(results, uncertainty, sensitivity)
    texts = {path: render(results, uncertainty, sensitivity) for path, render in ((args.json, prediction_json), (args.csv, prediction_csv))
             if path}
    figures = {}
    if args.plots:
        figures = prediction_figures(results, limit=volume_limit(uncertainty))
        figures |= uncertainty_figures(uncertainty, sensitivity) if uncertainty is not None else {}
    emit(args, table, ({args.table: table} if args.table else {}) | texts, render_figures(figures) if figures else {})
    return 0


def _cmd_examples(args: argparse.Namespace) -> int:
    from ..cases import example_names, example_text
    from ..cases.loader import example_data_names, example_description

    if args.name:
        sys.stdout.write(example_text(args.name))
        return 0
    width = max(60, shutil.get_terminal_size((100, 24)).columns - 1)

    def show(name: str) -> None:  # the whole description, wrapped under its name
        print(textwrap.fill(example_description(name), width, initial_indent=f"  {name:24s} ",
                            subsequent_indent=" " * 27, break_on_hyphens=False))

    print("Bundled example cases (print one with `sealeak examples NAME`, run it with "
          "`sealeak predict --example NAME`):")
    for name in example_names():
        show(name)
    data = example_data_names()
    if data:
        print("Bundled example data (save one with `sealeak examples NAME > NAME`, then e.g. "
              "`sealeak fit --example reference-experiment --data NAME`):")
        for name in data:
            show(name)
    return 0


def build_parser() -> argparse.ArgumentParser:
    """The argument parser of every sub-command (``docs/cli.md`` documents each option)."""
    parser = Parser(prog="sealeak", description="Leak rate of rubber seals from surface roughness "
                    "(Persson contact mechanics + percolation + Poiseuille flow).")
    parser.add_argument("--version", action="version", version=f"sealeak {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=Parser)

    p = sub.add_parser("predict", help="critical-junction leak rate for a case file")
    add_case_args(p)
    p.add_argument("--table", metavar="FILE", help="also write the printed table to FILE (text)")
    p.add_argument("--csv", metavar="FILE", help="write the results as CSV (units in the header)")
    add_uncertainty_args(p)
    add_sensitivity_arg(p)
    add_output_args(p, json="write the results as JSON", plots="write the figures (PNG) into DIR")
    p.set_defaults(func=_cmd_predict)

    p = sub.add_parser("examples", help="list the bundled example cases, or print one")
    p.add_argument("name", nargs="?", help="example to print")
    p.set_defaults(func=_cmd_examples)

    for module in (surface, simulate, lab, serve):
        module.register(sub, add_case_args)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    """Run the command line; returns the exit status (0, 2 for a user error or a case too large for the memory, 130 when
    interrupted)."""
    parser = build_parser()
    args, extra = parser.parse_known_args(argv)
    if extra:  # named with the command whose options they are not
        prog = " ".join(["sealeak"] + [str(v) for v in (getattr(args, "command", None), getattr(args, "surface_command", None)) if v])
        print(f"sealeak: error: {usage_message('unrecognized arguments: ' + ' '.join(extra), prog)}", file=sys.stderr)
        raise SystemExit(EXIT_USER_ERROR)
    if not getattr(args, "command", None):
        parser.print_help()
        return EXIT_USER_ERROR
    import matplotlib  # lazily: only commands that draw need it, and --help stays fast

    matplotlib.use("Agg")  # the command line draws into files: a non-interactive backend, chosen here only
    try:
        return int(args.func(args) or 0)
    except SealeakError as exc:
        print(f"sealeak: error: {exc}", file=sys.stderr)
        return EXIT_USER_ERROR
    except BrokenPipeError:  # output piped into a program that stopped reading (e.g. head)
        return 0
    except OSError as exc:  # the file system refused (permissions, a folder in the way, disk full)
        where = f"{exc.filename}: " if exc.filename else ""
        print(f"sealeak: error: {where}{exc.strerror or exc}", file=sys.stderr)
        return EXIT_USER_ERROR
    except MemoryError as exc:  # NumPy's "Unable to allocate …", or CuPy's out-of-memory error on a GPU
        what = str(exc).strip().splitlines()[0] if str(exc).strip() else "an allocation failed"
        print(f"sealeak: error: out of memory ({what}); no output was left half-written. Ask for less at once: a "
              "smaller grid (simulation.grid), fewer samples, fewer workers, or --device cpu", file=sys.stderr)
        return EXIT_USER_ERROR
    except KeyboardInterrupt:
        print("sealeak: interrupted; no output was left half-written (outputs completed before the interruption remain)", file=sys.stderr)
        return EXIT_INTERRUPTED


if __name__ == "__main__":  # pragma: no cover
    raise SystemExit(main())
