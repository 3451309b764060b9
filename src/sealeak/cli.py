"""The ``sealeak`` command line: a thin layer over the library.

User mistakes (bad case files, units, existing outputs) are SealeakError: the CLI prints
``sealeak: error: <message>`` to stderr and exits with status 2, without a traceback.
"""

from __future__ import annotations

import argparse
import importlib
import sys
from pathlib import Path
from typing import Sequence

from . import __version__
from .errors import SealeakError

__all__ = ["main"]

EXIT_USER_ERROR = 2
EXIT_INTERRUPTED = 130


class _Parser(argparse.ArgumentParser):
    def error(self, message: str) -> None:  # argparse's own errors: usage + exit 2, no traceback
        self.print_usage(sys.stderr)
        print(f"sealeak: error: {message}", file=sys.stderr)
        raise SystemExit(EXIT_USER_ERROR)


def _load(args: argparse.Namespace):
    from .casefile import example_path, load_cases

    if args.example and args.case:
        raise SealeakError("give a case file or --example NAME, not both")
    if args.example:
        return load_cases(example_path(args.example))
    if not args.case:
        raise SealeakError("give a case file (CASE.toml) or --example NAME; `sealeak examples` lists the examples")
    return load_cases(args.case)


def _cmd_predict(args: argparse.Namespace) -> int:
    from ._io import check_outputs, write_text
    from .case import predict, predict_effective_medium
    from .output import prediction_csv, prediction_json, prediction_table

    outputs = [p for p in (args.table, args.json, args.csv) if p]
    if args.plots:
        from .plotting import PREDICTION_FIGURE_NAMES

        outputs += [str(Path(args.plots) / n) for n in PREDICTION_FIGURE_NAMES]
    check_outputs(outputs, args.force)
    cases = _load(args)
    results = [predict(c) for c in cases]
    effective = [predict_effective_medium(c) if c.model != "critical-junction" else None for c in cases]
    if all(em is None for em in effective):
        effective = None
    table = prediction_table(cases, results, effective)
    if not args.quiet:
        sys.stdout.write(table)
    if args.table:
        write_text(args.table, table)
        _say(args, f"wrote {args.table}")
    if args.json:
        write_text(args.json, prediction_json(cases, results, effective))
        _say(args, f"wrote {args.json}")
    if args.csv:
        write_text(args.csv, prediction_csv(cases, results, effective))
        _say(args, f"wrote {args.csv}")
    if args.plots:
        from .plotting import prediction_figures, save_figures

        written = save_figures(prediction_figures(cases, results, effective), args.plots)
        _say(args, f"wrote {len(written)} figures to {args.plots}/")
    return 0


def _cmd_examples(args: argparse.Namespace) -> int:
    from .casefile import example_names, example_text

    if args.name:
        sys.stdout.write(example_text(args.name))
        return 0
    print("Bundled example cases (print one with `sealeak examples NAME`, run it with "
          "`sealeak predict --example NAME`):")
    for name in example_names():
        first = next((ln for ln in example_text(name).splitlines() if ln.startswith("title")), "")
        title = first.split("=", 1)[1].strip().strip('"') if "=" in first else ""
        print(f"  {name:24s} {title}")
    return 0


def _say(args: argparse.Namespace, text: str) -> None:
    if not args.quiet:
        print(text, file=sys.stderr)


def _add_case_args(p: argparse.ArgumentParser) -> None:
    p.add_argument("case", nargs="?", help="case file (TOML)")
    p.add_argument("--example", metavar="NAME", help="use a bundled example case instead of a file")
    p.add_argument("--force", action="store_true", help="overwrite existing output files")
    p.add_argument("-q", "--quiet", action="store_true", help="print nothing but errors")


def build_parser() -> argparse.ArgumentParser:
    parser = _Parser(prog="sealeak", description="Leak rate of rubber seals from surface roughness "
                     "(Persson contact mechanics + percolation + Poiseuille flow).")
    parser.add_argument("--version", action="version", version=f"sealeak {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=_Parser)

    p = sub.add_parser("predict", help="critical-junction leak rate for a case file")
    _add_case_args(p)
    p.add_argument("--table", metavar="FILE", help="also write the printed table to FILE (text)")
    p.add_argument("--json", metavar="FILE", help="write the results as JSON")
    p.add_argument("--csv", metavar="FILE", help="write the results as CSV (units in the header)")
    p.add_argument("--plots", metavar="DIR", help="write the figures (PNG) into DIR")
    p.set_defaults(func=_cmd_predict)

    p = sub.add_parser("examples", help="list the bundled example cases, or print one")
    p.add_argument("name", nargs="?", help="example to print")
    p.set_defaults(func=_cmd_examples)

    for name in COMMAND_MODULES:
        importlib.import_module(name).register(sub, _add_case_args)
    return parser


#: Modules that add sub-commands: each has ``register(subparsers, add_case_args)`` and keeps its
#: heavy imports inside the command functions, so ``sealeak --help`` stays fast.
COMMAND_MODULES: tuple[str, ...] = ("sealeak.cli_surface", "sealeak.cli_simulate", "sealeak.cli_lab")


def main(argv: Sequence[str] | None = None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    if not getattr(args, "command", None):
        parser.print_help()
        return EXIT_USER_ERROR
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
    except KeyboardInterrupt:
        print("sealeak: interrupted; no partial output files were left", file=sys.stderr)
        return EXIT_INTERRUPTED


if __name__ == "__main__":  # pragma: no cover
    raise SystemExit(main())
