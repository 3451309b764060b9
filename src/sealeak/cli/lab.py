"""Sub-commands ``fit``, ``rig`` and ``report``.

Thin layers over :mod:`sealeak.cases` (which runs the fit, the linearity check and the rig) and
:mod:`sealeak.render` (which formats them); heavy imports stay inside the command functions so
``sealeak --help`` stays fast.
"""

from __future__ import annotations

import argparse
from collections.abc import Callable

from ..errors import InputError, SealeakError
from ._common import (
    add_output_args,
    add_sensitivity_arg,
    add_uncertainty_args,
    check_sensitivity,
    emit,
    inputs,
    load,
    load_case_file,
    outputs,
    positive_pressure,
    propagation,
    say,
    sobol_sensitivity,
)

__all__ = ["register"]


def register(sub: argparse._SubParsersAction, add_case_args: Callable[[argparse.ArgumentParser], None]) -> None:
    """Add ``fit``, ``rig`` and ``report`` to the sub-command parsers."""
    p = sub.add_parser("fit", help="fit α to measured leak rates (or check linearity in ΔP)",
                       description="Fit α of both theories to measured leak rates. For an O-ring or pressure-profile "
                                   "seal the data give each row's compression or profile_scale; the effective medium "
                                   "then takes about 1-2 s per distinct value.")
    add_case_args(p)
    _add_variant(p)
    p.add_argument("--data", metavar="FILE", required=True,
                   help="measured data: header with units, e.g. 'squeeze_pressure (kPa), leak_rate (ml/min)'; "
                        "for an O-ring 'compression (%%), leak_rate (ml/min)', for a pressure profile "
                        "'profile_scale, leak_rate (ml/min)'")
    p.add_argument("--at-pressure", metavar="PRESSURE", default="1 atm",
                   help="pressure at which leak-test throughputs (mbar*l/s, Pa*m^3/s) become volume flows "
                        "(default: 1 atm, ambient)")
    p.add_argument("--linearity", action="store_true",
                   help="check Q linear in ΔP at fixed P0 (columns pressure_difference, leak_rate)")
    p.add_argument("--squeeze-pressure", metavar="PRESSURE",
                   help="P0 of a linearity data set (default: its squeeze_pressure column, the case's single P0, "
                        "or the [rig] load); not for an O-ring or profile seal, whose compression or profile_scale "
                        "(a data column, or the case's single value) sets the contact")
    add_output_args(p, json="write the fit as JSON", plots="write the figure (fit.png or linearity.png) into DIR")
    p.set_defaults(func=_cmd_fit)

    p = sub.add_parser("rig", help="virtual leak-test rig (water column or pressure decay): against time, or from readings",
                       description="The virtual rig of the case's [rig] section: the water column (kind = "
                                   "\"water-column\", the default) or the pressure-decay test of a gas (kind = "
                                   "\"pressure-decay\"). An O-ring or pressure-profile seal runs at the case's one "
                                   "compression or profile_scale (the [rig] then has no load).")
    add_case_args(p)
    _add_variant(p)
    p.add_argument("--readings", metavar="FILE", help="measured readings: (time, height) of a water column, e.g. 'time (min), "
                                                      "height (cm)', or (time, absolute pressure) of a pressure-decay test, "
                                                      "e.g. 'time (min), pressure (mbar)'")
    add_output_args(p, json="write the results as JSON", plots="write rig.png (and readings.png) into DIR")
    p.set_defaults(func=_cmd_rig)

    p = sub.add_parser("report", help="write one self-contained HTML report of a case")
    add_case_args(p)
    p.add_argument("-o", "--output", metavar="REPORT.html", required=True, help="the HTML file to write")
    add_uncertainty_args(p)
    add_sensitivity_arg(p)
    p.set_defaults(func=_cmd_report)


def _add_variant(p: argparse.ArgumentParser) -> None:
    p.add_argument("--variant", metavar="NAME", help="the variant of a [study] case file to use (its label, or the "
                                                       "start of it), e.g. --variant water for the o-ring example")


def _one_case(args: argparse.Namespace):  # type: ignore[no-untyped-def]
    """The case of a command that takes one variant: the file's only one, or the study's ``--variant``."""
    cases = load(args)
    labels = [c.label for c in cases]
    if args.variant is not None:
        if len(cases) == 1 and not cases[0].label:
            raise InputError("--variant", args.variant, "the case file defines no [study]: leave --variant out")
        chosen = [c for c in cases if c.label == args.variant]
        chosen = chosen or [c for c in cases if c.label.lower().startswith(args.variant.lower())]
        if len(chosen) != 1:
            raise InputError("--variant", args.variant, f"{'is ambiguous' if chosen else 'is not a variant'}: one of "
                                                        + ", ".join(repr(x) for x in labels))
        return chosen[0]
    if len(cases) != 1:
        raise SealeakError(f"this command takes a case with one variant; the case file defines a study of {len(cases)}: "
                           "choose one with --variant (one of " + ", ".join(repr(x) for x in labels) + ")")
    return cases[0]


# ---------------------------------------------------------------------- fit
def _cmd_fit(args: argparse.Namespace) -> int:
    from ..cases import run_fit
    from ..io.files import check_outputs
    from ..lab import read_leak_data
    from ..render import figure_fit, fit_json, fit_text, render_figures

    names = ("linearity.png",) if args.linearity else ("fit.png",)
    check_outputs(outputs(args, names), args.force, inputs=inputs(args, "data"))
    reference = positive_pressure("--at-pressure", args.at_pressure)
    case = _one_case(args)
    if args.linearity:
        return _fit_linearity(args, case, reference)
    data = read_leak_data(args.data, reference_pressure=reference,
                          load_column=case.band.load_name if case.band is not None else "squeeze_pressure")
    result = run_fit(case, data)
    # render everything first, then write: a failure while rendering leaves no file behind
    text, doc = fit_text(result), fit_json(result) if args.json else ""
    pngs = render_figures({"fit.png": figure_fit(result)}) if args.plots else {}
    emit(args, text, {args.json: doc} if args.json else {}, pngs)
    return 0


def _fit_linearity(args: argparse.Namespace, case, reference: float) -> int:  # type: ignore[no-untyped-def]
    from ..cases.fitting import seal_description
    from ..cases.linearity_check import run_linearity
    from ..lab import read_leak_data
    from ..physics.contact import MIN_SQUEEZE_PRESSURE
    from ..render import figure_linearity, linearity_json, linearity_text, render_figures

    p0, source = None, ""
    if args.squeeze_pressure is not None:
        if case.band is not None:
            raise InputError("--squeeze-pressure", args.squeeze_pressure,
                             f"is for a seal pressed uniformly; this case's seal is {seal_description(case)}: leave the "
                             f"option out (the data file's {case.band.load_name} column or the case's single value sets it)")
        p0, source = positive_pressure("--squeeze-pressure", args.squeeze_pressure), "--squeeze-pressure"
        if p0 < MIN_SQUEEZE_PRESSURE:  # the case file's floor (0.0001 Pa was taken)
            raise InputError("--squeeze-pressure", args.squeeze_pressure,
                             f"must be at least {MIN_SQUEEZE_PRESSURE * 1e3:g} mPa: a seal's squeeze pressure is some kPa to MPa")
    data = read_leak_data(args.data, reference_pressure=reference, required=("pressure_difference", "leak_rate"))
    if len(data) < 3:
        raise SealeakError(f"{data.path}: a linearity check needs at least 3 rows, found {len(data)}")
    if p0 is not None and data.load_name == "squeeze_pressure" and \
            any(abs(v - p0) > 1e-6 * p0 for v in data.load.tolist()):
        raise InputError("--squeeze-pressure", args.squeeze_pressure,
                         f"differs from the data file's squeeze_pressure column ({data.load[0]:.6g} Pa): give one of "
                         "them (the option replaced the file's value without a word)")
    check = run_linearity(case, data, p0, source)
    text, doc = linearity_text(case, data, check), linearity_json(case, data, check) if args.json else ""
    pngs = render_figures({"linearity.png": figure_linearity(data.pressure_difference, data.leak_rate, check)}) if args.plots else {}
    emit(args, text, {args.json: doc} if args.json else {}, pngs)
    return 0


# ---------------------------------------------------------------------- rig
def _cmd_rig(args: argparse.Namespace) -> int:
    from ..cases import RigPrediction, rig_prediction, rig_readings
    from ..io.files import check_outputs
    from ..lab import read_rig_readings
    from ..render import figure_readings, figure_rig, render_figures, rig_json, rig_text
    from ..render.lab import rig_condition

    names = ("rig.png", "readings.png") if args.readings else ("rig.png",)
    check_outputs(outputs(args, names), args.force, inputs=inputs(args, "readings"))
    case = _one_case(args)
    if case.rig is None:
        load = "" if case.band is not None else ", load (kg or N)"  # a band seal's compression or scale sets the contact
        raise InputError("rig", None, f"{case.source or 'the case'} has no [rig] section: give cylinder_diameter, "
                                      f"initial_height{load} and optionally final_height, density")
    if case.rig.kind == "pressure-decay":
        return _decay_rig(args, case)
    analysis = None
    if args.readings:  # read and checked before the model runs: bad readings are refused at once
        t, h = read_rig_readings(args.readings)
        analysis = rig_readings(case, t, h, source=args.readings)
    pred = rig_prediction(case)
    assert isinstance(pred, RigPrediction)  # a pressure-decay [rig] went to _decay_rig above
    text, doc = rig_text(case, pred, analysis, args.readings or ""), rig_json(case, pred, analysis) if args.json else ""
    pngs = {}
    if args.plots:  # rendered before anything is written: a failure leaves no file behind
        figs = {"rig.png": figure_rig(case.rig, pred.columns, pred.squeeze_pressure, rig_condition(case, pred, short=True))}
        if analysis is not None:
            figs["readings.png"] = figure_readings(analysis, pred.conductance)
        pngs = render_figures(figs)
    emit(args, text, {args.json: doc} if args.json else {}, pngs)
    return 0


def _decay_rig(args: argparse.Namespace, case) -> int:  # type: ignore[no-untyped-def]
    """``sealeak rig`` on a ``[rig] kind = "pressure-decay"`` case: P(t), Δt, V·ΔP/Δt; readings give the leak rate and α."""
    from ..cases.leak_tests import decay_prediction, decay_readings
    from ..lab import read_decay_readings
    from ..render import render_figures
    from ..render.lab import decay_condition, decay_json, decay_text
    from ..render.lab_figures import figure_decay, figure_decay_readings

    # the readings are read and checked against the rig's test before the model runs: bad ones are refused at once
    t, p = read_decay_readings(args.readings, case.rig.test) if args.readings else (None, None)
    pred = decay_prediction(case)
    readings = None
    if t is not None and p is not None:
        readings = decay_readings(case, pred, t, p, source=args.readings)
    text, doc = decay_text(case, pred, readings, args.readings or ""), decay_json(case, pred, readings) if args.json else ""
    pngs = {}
    if args.plots:  # rendered before anything is written: a failure leaves no file behind
        figs = {"rig.png": figure_decay(case.rig, pred, decay_condition(case, pred, short=True))}
        if readings is not None:
            figs["readings.png"] = figure_decay_readings(case.rig, readings)
        pngs = render_figures(figs)
    emit(args, text, {args.json: doc} if args.json else {}, pngs)
    return 0


# ---------------------------------------------------------------------- report
def _cmd_report(args: argparse.Namespace) -> int:
    from ..cases import run_case
    from ..io.files import STDOUT, check_outputs, write_output
    from ..render import html_report

    check_outputs(outputs(args, files=("output",), folders=()), args.force, inputs=inputs(args))
    case_file = load_case_file(args)
    check_sensitivity(args, case_file)
    single = len(case_file.cases) == 1  # the report shows the rig of a single case
    uncertainty = propagation(args, case_file)  # None without uncertain inputs
    sensitivity = sobol_sensitivity(args, uncertainty)
    write_output(args.output, html_report([run_case(c, rig=single) for c in case_file.cases], case_file.inputs,
                                          uncertainty, sensitivity))
    if args.output != STDOUT:
        say(args, f"wrote {args.output}")
    return 0
