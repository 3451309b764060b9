"""What every sub-command shares: the parser class, case loading, output checks, messages.

The sub-command modules import this module, never :mod:`sealeak.cli` itself (no import cycle).
Heavy imports (the case layer, rendering, matplotlib) stay inside the command functions so that
``sealeak --help`` stays fast: these are the project's only deliberate function-level imports.
"""

from __future__ import annotations

import argparse
import os
import re
import sys
from collections.abc import Iterable
from pathlib import Path
from typing import TYPE_CHECKING

from ..errors import InputError, SealeakError
from ..io.files import Output

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.figure import Figure

    from ..cases import Case, CaseFile
    from ..cases.sobol import SobolIndices
    from ..cases.uncertainty import UncertaintyResult

__all__ = ["Parser", "EXIT_USER_ERROR", "EXIT_INTERRUPTED", "add_case_args", "load_case_file", "load",
           "one_case", "say", "emit", "outputs", "inputs", "positive_pressure", "add_uncertainty_args", "propagation",
           "add_sensitivity_arg", "check_sensitivity", "sobol_sensitivity"]

EXIT_USER_ERROR = 2
EXIT_INTERRUPTED = 130


#: argparse's messages about an option's value, and the project's wording of them (option = 'value': what is allowed).
_ARGPARSE_VALUE = re.compile(r"^argument (?P<opt>[^:]+): invalid (?P<kind>int|float) value: (?P<value>'.*')$")
_ARGPARSE_MISSING = re.compile(r"^argument (?P<opt>[^:]+): expected one argument$")


def usage_message(message: str, prog: str) -> str:
    """argparse's ``message`` in the project's wording, with where to read the options (``prog --help``)."""
    m = _ARGPARSE_VALUE.match(message)
    if m:
        allowed = "an integer" if m["kind"] == "int" else "a number"
        message = f"{m['opt']} = {m['value']}: must be {allowed}"
    m = _ARGPARSE_MISSING.match(message)
    if m:
        message = f"{m['opt']}: needs a value"
    return f"{message} (options: {prog} --help)"


class Parser(argparse.ArgumentParser):
    """argparse with the project's error convention: one line, exit status 2, no traceback."""

    def error(self, message: str) -> None:  # type: ignore[override]
        """Print ``sealeak: error: message (options: PROG --help)`` on one line; exit with status 2."""
        print(f"sealeak: error: {usage_message(message, self.prog)}", file=sys.stderr)
        raise SystemExit(EXIT_USER_ERROR)


def add_case_args(p: argparse.ArgumentParser) -> None:
    """The options of every command that reads a case: CASE, --example, --force, --quiet."""
    p.add_argument("case", nargs="?", help="case file (TOML)")
    p.add_argument("--example", metavar="NAME", help="use a bundled example case instead of a file")
    p.add_argument("--force", action="store_true", help="overwrite existing output files")
    p.add_argument("-q", "--quiet", action="store_true", help="print nothing but errors")


def add_output_args(p: argparse.ArgumentParser, *, json: str, plots: str) -> None:
    """The result files of a command that computes: --json FILE (``json``: what it holds) and --plots DIR (``plots``:
    which figures go into DIR)."""
    p.add_argument("--json", metavar="FILE", help=json)
    p.add_argument("--plots", metavar="DIR", help=plots)


def add_uncertainty_args(p: argparse.ArgumentParser) -> None:
    """The options of the uncertainty propagation of a case file with uncertain inputs: --samples, --seed, --sampler."""
    p.add_argument("--samples", type=int, metavar="N",
                   help="samples of the case file's uncertain inputs (default 256; a power of two for Sobol' points); "
                        "each is a full prediction")
    p.add_argument("--seed", type=int, metavar="S", help="seed of the samples (default 0): the same seed gives the same numbers")
    p.add_argument("--sampler", metavar="NAME", help="sobol (scrambled Sobol' points, the default) or lhs (Latin hypercube)")


def propagation(args: argparse.Namespace, case_file: CaseFile) -> UncertaintyResult | None:
    """The propagation of the case file's uncertain inputs (spreads or ``conditions.max_leak_rate``) with the
    options of :func:`add_uncertainty_args`, or None for a case file without them (the options are then refused)."""
    from tqdm import tqdm

    from ..cases.uncertainty import DEFAULT_SAMPLES, check_sampling, propagate, uncertain_study

    options = {"--samples": args.samples, "--seed": args.seed, "--sampler": args.sampler}
    if not case_file.spreads.active:
        for option, value in options.items():
            if value is not None:
                raise InputError(option, value, "the case file has no uncertain inputs: give a value a spread, e.g. "
                                                "h_rms = \"1.5 um ± 10 %\" (docs/case-files.md, Uncertain inputs)")
        return None
    study = uncertain_study(case_file)
    samples, seed, sampler = (DEFAULT_SAMPLES if args.samples is None else args.samples, args.seed or 0,
                              args.sampler or "sobol")
    check_sampling(samples, seed, sampler)
    say(args, f"sampling {len(study.inputs)} uncertain input{'s' if len(study.inputs) != 1 else ''} with {samples} samples "
              "..." if study.inputs else
              "no uncertain inputs: conditions.max_leak_rate is judged on the deterministic leak rates")
    # a bar for the samples that run a prediction each (the fast paths take all at once and never move it); tqdm
    # draws it on a terminal only, and a bar never moved is not drawn
    with tqdm(total=samples, desc="samples", unit="sample", disable=None if not getattr(args, "quiet", False) else True,
              file=sys.stderr, delay=2.0, leave=False) as bar:
        return propagate(study, samples, seed, sampler, progress=bar.update)


def add_sensitivity_arg(p: argparse.ArgumentParser) -> None:
    """``--sensitivity N``: Sobol' indices of the case file's uncertain inputs (docs/cli.md)."""
    p.add_argument("--sensitivity", type=int, metavar="N",
                   help="Sobol' indices of log10 Q per uncertain input with N base samples (a power of two from 16; "
                        "N·(inputs + 2) more predictions): which measurement narrows the band most")


def check_sensitivity(args: argparse.Namespace, case_file: CaseFile) -> None:
    """``--sensitivity N``: a case file with uncertain inputs and an N the design allows; checked before any sample runs."""
    from ..cases.sobol import check_design

    if args.sensitivity is None:
        return
    if not case_file.spreads.active or not case_file.spreads.inputs:
        raise InputError("--sensitivity", args.sensitivity, "the case file has no uncertain inputs: give a value a spread, e.g. "
                                                            "h_rms = \"1.5 um ± 10 %\" (docs/case-files.md, Uncertain inputs)")
    check_design(len(case_file.spreads.inputs), args.sensitivity)


def sobol_sensitivity(args: argparse.Namespace, uncertainty: UncertaintyResult | None) -> SobolIndices | None:
    """The Sobol' indices of ``--sensitivity N`` (with the propagation's seed), or None without the option."""
    if uncertainty is None or args.sensitivity is None:
        return None
    from ..cases.sensitivity import study_sensitivity  # SALib (about 1 s to import) only when asked for

    say(args, f"Sobol' sensitivity: {args.sensitivity} base samples, "
              f"{args.sensitivity * (len(uncertainty.study.inputs) + 2)} predictions ...")
    return study_sensitivity(uncertainty.study, args.sensitivity, uncertainty.seed, uncertainty.nominal)


def load_case_file(args: argparse.Namespace) -> CaseFile:
    """The case file named by ``args.case`` or ``--example`` (exactly one of them), read once per run
    (:func:`inputs` reads it for the files it names, the command for its cases)."""
    from ..cases import example_path, read_case_file

    cached = vars(args).get("_case_file")
    if cached is not None:
        return cached
    if args.example and args.case:
        raise SealeakError("give a case file or --example NAME, not both")
    if args.example:
        case_file = read_case_file(example_path(args.example))
    elif not args.case:
        raise SealeakError("give a case file (CASE.toml) or --example NAME; `sealeak examples` lists the examples")
    else:  # read_case_file reads regular files only (a FIFO or /dev/zero as the case would never end)
        case_file = read_case_file(args.case)
    args._case_file = case_file
    return case_file


def load(args: argparse.Namespace) -> list[Case]:
    """The cases of the case file named by the arguments (one, or one per study value)."""
    return load_case_file(args).cases


def one_case(args: argparse.Namespace) -> Case:
    """The single case of a command that takes no ``[study]``."""
    cases = load(args)
    if len(cases) != 1:
        raise SealeakError(f"this command takes a case with one variant; the case file defines a study of {len(cases)}")
    return cases[0]


def say(args: argparse.Namespace, text: str) -> None:
    """A progress line on stderr, unless ``--quiet``."""
    if not getattr(args, "quiet", False):
        print(text, file=sys.stderr)


def emit(args: argparse.Namespace, text: str, files: dict[str, str],
         pngs: dict[str, bytes] | dict[str, Figure]) -> None:
    """The end of every command that writes results: print ``text`` (unless ``--quiet``), then write the
    text ``files`` ({path: content}) and the figures ``pngs`` (PNG bytes, or figures rendered here before any file is
    written) into ``args.plots``, saying what was written.

    Everything is rendered before a file is written, and the files are written all or none
    (:func:`~sealeak.io.files.write_files`): a failure leaves no new file behind and every existing one as it was. A
    file given as ``-`` goes to standard output instead, and then ``text`` is not printed (standard output holds that
    file alone).
    """
    from ..io.files import STDOUT, write_files
    from ..render import render_figures

    if not getattr(args, "quiet", False) and STDOUT not in files:
        sys.stdout.write(text)
    rendered = render_figures({n: f for n, f in pngs.items() if not isinstance(f, bytes)})
    plots = Path(args.plots) if pngs else Path(".")
    contents: dict[str, str | bytes] = {path: content for path, content in files.items() if path != STDOUT}
    contents |= {str(plots / n): f if isinstance(f, bytes) else rendered[n] for n, f in pngs.items()}
    write_files(contents)
    if STDOUT in files:
        sys.stdout.write(files[STDOUT])
        sys.stdout.flush()
    for path in files:
        if path != STDOUT:
            say(args, f"wrote {path}")
    if pngs:
        say(args, f"wrote {plots / next(iter(pngs))}" if len(pngs) == 1 else f"wrote {len(pngs)} figures to {plots}{os.sep}")


#: The files a folder option writes under names not known up front (a glob pattern), refused without ``--force``.
_FOLDER_FILES = {"fields": "r*-p*.npz"}


def outputs(args: argparse.Namespace, figure_names: Iterable[str] = (), files: Iterable[str] = ("json",),
            folders: Iterable[str] = ("plots",)) -> list[Output]:
    """The outputs a command will write, for :func:`sealeak.io.files.check_outputs`.

    ``files`` and ``folders`` are the attribute names of the file options (``--json``) and of the
    folder options (``--plots``, ``--fields``) of ``args``; ``figure_names`` the files written into
    ``--plots`` (``--fields`` writes ``r<r>-p<i>.npz``). An option given as an empty string is kept, so that it is
    refused, not ignored.
    """
    out: list[Output] = []
    for attr in files:
        if getattr(args, attr, None) is not None:
            out.append(Output(getattr(args, attr), _option(attr)))
    for attr in folders:
        folder = getattr(args, attr, None)
        if folder is not None:
            out.append(Output(folder, _option(attr), folder=True, replaces=_FOLDER_FILES.get(attr, "")))
            if attr == "plots" and folder:
                out += [Output(str(Path(folder) / n), "--plots") for n in figure_names]
    return out


def inputs(args: argparse.Namespace, *attrs: str) -> list[str]:
    """The files a command reads, for ``check_outputs(inputs=...)``: the case file, every data file it
    names (a C(q) table, topographies, a pressure profile: reading the case for them), and the files of
    the options ``attrs``."""
    out: list[str] = []
    for attr in ("case", *attrs):
        value = getattr(args, attr, None)
        out += value if isinstance(value, list) else [value] if value else []
    if getattr(args, "case", None) or getattr(args, "example", None):
        out += [str(p) for p in load_case_file(args).files]
    return out


def _option(attr: str) -> str:
    """``psd_out`` -> ``--psd-out``."""
    return "--" + attr.replace("_", "-")


def positive_pressure(field: str, text: str) -> float:
    """A pressure option such as ``--at-pressure "1 atm"`` in Pa (> 0)."""
    from ..io.units import parse_quantity

    value = parse_quantity(field, text, "pressure")
    if not value > 0:
        raise InputError(field, text, "must be > 0")
    return value
