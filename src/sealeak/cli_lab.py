"""Sub-commands ``fit``, ``rig`` and ``report`` (registered through ``cli.COMMAND_MODULES``).

Thin layers over :mod:`sealeak.fitting`, :mod:`sealeak.rig` and :mod:`sealeak.report`; heavy imports
stay inside the command functions so ``sealeak --help`` stays fast.
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

from .errors import InputError, SealeakError

__all__ = ["register"]


def register(sub, add_case_args) -> None:
    p = sub.add_parser("fit", help="fit α to measured leak rates (or check linearity in ΔP)")
    add_case_args(p)
    p.add_argument("--data", metavar="FILE", required=True,
                   help="measured data: header with units, e.g. 'squeeze_pressure (kPa), leak_rate (ml/min)'")
    p.add_argument("--at-pressure", metavar="PRESSURE", default="1 atm",
                   help="pressure at which leak-test throughputs (mbar*l/s, Pa*m^3/s) become volume flows "
                        "(default: 1 atm, ambient)")
    p.add_argument("--linearity", action="store_true",
                   help="check Q linear in ΔP at fixed P0 (columns pressure_difference, leak_rate)")
    p.add_argument("--squeeze-pressure", metavar="PRESSURE",
                   help="P0 of a linearity data set (default: its squeeze_pressure column, the case's single P0, "
                        "or the [rig] load)")
    p.add_argument("--json", metavar="FILE", help="write the fit as JSON")
    p.add_argument("--plots", metavar="DIR", help="write the figure (fit.png or linearity.png) into DIR")
    p.set_defaults(func=_cmd_fit)

    p = sub.add_parser("rig", help="virtual water-column rig: level against time, or leak rate from readings")
    add_case_args(p)
    p.add_argument("--readings", metavar="FILE", help="measured (time, height) readings, e.g. 'time (min), height (cm)'")
    p.add_argument("--json", metavar="FILE", help="write the results as JSON")
    p.add_argument("--plots", metavar="DIR", help="write rig.png (and readings.png) into DIR")
    p.set_defaults(func=_cmd_rig)

    p = sub.add_parser("report", help="write one self-contained HTML report of a case")
    add_case_args(p)
    p.add_argument("-o", "--output", metavar="REPORT.html", required=True, help="the HTML file to write")
    p.set_defaults(func=_cmd_report)


def _one_case(args):
    from .cli import _load

    cases = _load(args)
    if len(cases) != 1:
        raise SealeakError(f"this command takes a case with one variant; the case file defines a study of {len(cases)}")
    return cases[0]


def _say(args, text: str) -> None:
    if not args.quiet:
        print(text, file=sys.stderr)


def _outputs(args, names: tuple[str, ...]) -> list[str]:
    out = [args.json] if getattr(args, "json", None) else []
    if getattr(args, "plots", None):
        out += [str(Path(args.plots) / n) for n in names]
    return out


def _pressure(field: str, text: str) -> float:
    from .units import parse_quantity

    value = parse_quantity(field, text, "pressure")
    if not value > 0:
        raise InputError(field, text, "must be > 0")
    return value


def _fmt(x: float, spec: str = ".4g") -> str:
    import math

    return "—" if x is None or not math.isfinite(x) else format(x, spec)


# ---------------------------------------------------------------------- fit
def _cmd_fit(args: argparse.Namespace) -> int:
    import numpy as np

    from ._io import check_outputs, write_text

    names = ("linearity.png",) if args.linearity else ("fit.png",)
    check_outputs(_outputs(args, names), args.force)
    reference = _pressure("--at-pressure", args.at_pressure)
    case = _one_case(args)
    if args.linearity:
        return _fit_linearity(args, case, reference)
    from .fitting import fit_models
    from .labdata import read_leak_data
    from .leakage import pressure_difference_not_small
    from .output import json_value

    data = read_leak_data(args.data, reference_pressure=reference)
    fits = fit_models(case, data.squeeze_pressure, data.pressure_difference, data.leak_rate)
    if not any(f.fitted for f in fits.values()):
        reasons = "; ".join(f"line {data.line_of(i)}: {r}" for i, r in fits["effective_medium"].excluded[:3])
        raise SealeakError(f"{data.path}: no data point can be fitted by either model ({reasons})")
    lines = [f"{case.title}", f"fit of {len(data)} measured leak rate{'s' if len(data) != 1 else ''} from "
             f"{data.path} (columns: {', '.join(data.columns.values())})"]
    if data.throughput:
        lines.append(f"leak rates in {data.columns['leak_rate']} are pV throughputs: converted to volume flows at "
                     f"{reference / 1e3:.6g} kPa (--at-pressure)")
    lines += ["least squares in log Q: Q_measured = α × Q_model(α = 1)", ""]
    lines.append(f"{'model':<20} {'α':>10} {'± std':>10} {'rms (decades)':>14} {'points':>7}")
    for name, f in fits.items():
        lines.append(f"{name.replace('_', ' '):<20} {_fmt(f.alpha):>10} {_fmt(f.alpha_std, '.2g'):>10} "
                     f"{_fmt(f.rms_log10_residual, '.3g'):>14} {f.n_used:>7}")
    messages = []
    for name, f in fits.items():
        for i, reason in f.excluded:
            messages.append(f"{name.replace('_', ' ')}: line {data.line_of(i)} (P0 = {data.squeeze_pressure[i]:.6g} Pa) "
                            f"excluded: {reason}")
    if not any(f.n_used > 1 for f in fits.values()):
        messages.append("with one usable point α has no standard error")
    dp_used = np.where(np.isfinite(data.pressure_difference), data.pressure_difference, case.pressure_difference)
    large = pressure_difference_not_small(data.squeeze_pressure, dp_used)
    if large.any():
        i = int(np.argmax(large))
        messages.append(f"line {data.line_of(i)}: ΔP = {dp_used[i]:.6g} Pa is not small against P0 = {data.squeeze_pressure[i]:.6g} "
                        f"Pa ({int(large.sum())} row(s) like it): both theories assume P0 >> ΔP")
    lines += ["note: " + m for m in messages]
    if not args.quiet:
        print("\n".join(lines))
    if args.json:
        doc = {"case": case.title, "data": data.path, "reference_pressure": reference,
               "units": {"alpha": "1", "alpha_std": "1", "rms_log10_residual": "decades (log10)",
                         "reference_pressure": "Pa"},
               "messages": messages}
        for name, f in fits.items():
            doc[name] = {"alpha": json_value(f.alpha), "alpha_std": json_value(f.alpha_std),
                         "log10_alpha_std": json_value(f.log10_alpha_std),
                         "rms_log10_residual": json_value(f.rms_log10_residual), "points_used": f.n_used,
                         "excluded_rows": [i + 1 for i, _ in f.excluded],
                         "excluded_lines": [data.line_of(i) for i, _ in f.excluded]}
        write_text(args.json, json.dumps(doc, indent=2, ensure_ascii=False) + "\n")
        _say(args, f"wrote {args.json}")
    if args.plots:
        from .lab_figures import figure_fit
        from .plotting import save_figures

        save_figures({"fit.png": figure_fit(case, data, fits)}, args.plots)
        _say(args, f"wrote {Path(args.plots) / 'fit.png'}")
    return 0


def _fit_linearity(args, case, reference: float) -> int:
    import numpy as np

    from ._io import write_text
    from .case import predict, predict_effective_medium
    from .fitting import fit_line
    from .labdata import read_leak_data
    from .output import json_value

    data = read_leak_data(args.data, reference_pressure=reference, required=("pressure_difference", "leak_rate"))
    if len(data) < 3:
        raise SealeakError(f"{data.path}: a linearity check needs at least 3 rows, found {len(data)}")
    line = fit_line(data.pressure_difference, data.leak_rate)
    p0, source = None, ""
    if args.squeeze_pressure:
        p0, source = _pressure("--squeeze-pressure", args.squeeze_pressure), "--squeeze-pressure"
    elif np.isfinite(data.squeeze_pressure).all():
        if not np.allclose(data.squeeze_pressure, data.squeeze_pressure[0], rtol=1e-6):
            raise SealeakError(f"{data.path}: a linearity check is at one squeeze pressure; the file has several")
        p0, source = float(data.squeeze_pressure[0]), "the data file"
    elif case.squeeze_pressure.size == 1:
        p0, source = float(case.squeeze_pressure[0]), "the case file"
    elif case.rig is not None:
        p0, source = case.rig.squeeze_pressure(case.seal), "the [rig] load"
    model_lines: dict[str, float] = {}
    messages = []
    unit_slope = None
    if p0 is not None:
        cj = predict(case, squeeze_pressure=np.array([p0]), pressure_difference=1.0)
        if cj.percolates[0]:
            model_lines[f"critical junction (α = {case.alpha:g})"] = float(cj.leak_rate[0])
            unit_slope = float(cj.leak_rate[0]) / case.alpha
        else:
            messages.extend(cj.messages)
        em = predict_effective_medium(case, squeeze_pressure=np.array([p0]), pressure_difference=1.0)
        if em.percolates[0]:
            model_lines["effective medium (Bruggeman)"] = float(em.leak_rate[0])
        else:
            messages.extend(em.messages)
    else:
        messages.append("no squeeze pressure known (give --squeeze-pressure): no comparison with the models")
    z = line.intercept / line.intercept_std if line.intercept_std > 0 else float("nan")
    lines = [case.title, f"linearity of Q in ΔP: {len(data)} points from {data.path}", "",
             f"slope      {line.slope:.4g} ± {line.slope_std:.2g} m³/(s·Pa)",
             f"intercept  {line.intercept:.4g} ± {line.intercept_std:.2g} m³/s  "
             f"({_fmt(abs(z), '.2g')} standard errors from 0{'; consistent with a line through the origin' if abs(z) < 2 else ''})",
             f"R²         {line.r_squared:.5f}, rms residual {line.rms_residual:.3g} m³/s"]
    if p0 is not None:
        lines.append(f"P0         {p0 / 1e3:.4g} kPa (from {source})")
        for name, k in model_lines.items():
            lines.append(f"model      {name}: slope {k:.4g} m³/(s·Pa)")
        if unit_slope:
            lines.append(f"           α implied by the measured slope: {line.slope / unit_slope:.3g}")
    lines += ["note: " + m for m in messages]
    if not args.quiet:
        print("\n".join(lines))
    if args.json:
        doc = {"case": case.title, "data": data.path,
               "linearity": {"slope": json_value(line.slope), "slope_std": json_value(line.slope_std),
                             "intercept": json_value(line.intercept), "intercept_std": json_value(line.intercept_std),
                             "r_squared": json_value(line.r_squared), "points": line.n,
                             "squeeze_pressure": json_value(p0) if p0 is not None else None,
                             "model_slopes": {k: json_value(v) for k, v in model_lines.items()},
                             "alpha_from_slope": json_value(line.slope / unit_slope) if unit_slope else None},
               "units": {"slope": "m^3/(s*Pa)", "slope_std": "m^3/(s*Pa)", "intercept": "m^3/s",
                         "intercept_std": "m^3/s", "squeeze_pressure": "Pa", "model_slopes": "m^3/(s*Pa)"},
               "messages": messages}
        write_text(args.json, json.dumps(doc, indent=2, ensure_ascii=False) + "\n")
        _say(args, f"wrote {args.json}")
    if args.plots:
        from .lab_figures import figure_linearity
        from .plotting import save_figures

        save_figures({"linearity.png": figure_linearity(data.pressure_difference, data.leak_rate, line, model_lines, p0)},
                     args.plots)
        _say(args, f"wrote {Path(args.plots) / 'linearity.png'}")
    return 0


# ---------------------------------------------------------------------- rig
def _cmd_rig(args: argparse.Namespace) -> int:
    import numpy as np

    from ._io import check_outputs, write_text
    from .output import json_value
    from .rig import drain_time, leak_rate_from_readings, rig_prediction

    names = ("rig.png", "readings.png") if args.readings else ("rig.png",)
    check_outputs(_outputs(args, names), args.force)
    case = _one_case(args)
    if case.rig is None:
        raise InputError("rig", None, f"{case.source or 'the case'} has no [rig] section: give cylinder_diameter, "
                                      "initial_height, load (kg or N) and optionally final_height, density")
    rig = case.rig
    pred = rig_prediction(case)
    area = rig.cylinder_area
    lines = [case.title, "virtual water-column rig (Lorenz & Persson, EPL 86 (2009) 44006)", "",
             f"load        {rig.load:.4g} N ({rig.load_note}) -> P0 = {pred.squeeze_pressure / 1e3:.4g} kPa on the "
             f"{case.seal.nominal_area * 1e4:.4g} cm² seal",
             f"cylinder    D = {rig.cylinder_diameter * 100:.4g} cm, A = {area * 1e4:.4g} cm², "
             f"H0 = {rig.initial_height * 100:.4g} cm (ΔP0 = {rig.pressure_difference(rig.initial_height) / 1e3:.4g} kPa), "
             f"ρ = {rig.density:g} kg/m³, g = {rig.gravity:g} m/s²", ""]
    h1 = pred.columns and next(iter(pred.columns.values())).final_height
    lines.append(f"{'model':<32} {'K = Q/ΔP (m³/(s·Pa))':>22} {'Q at H0 (ml/min)':>17} {'τ (min)':>10} "
                 f"{'t to H = ' + format(h1 * 100, '.3g') + ' cm (min)':>26}")
    doc_models = {}
    for name, k in pred.conductance.items():
        col = pred.columns[name]
        tau = area / (k * rig.density * rig.gravity) if k > 0 else float("inf")
        t_exact = drain_time(rig, k, col.final_height)
        lines.append(f"{name:<32} {_fmt(k, '22.4e')} {_fmt(k * rig.pressure_difference(rig.initial_height) * 6e7, '17.4g')} "
                     f"{_fmt(tau / 60, '10.4g')} {_fmt(t_exact / 60, '26.4g')}")
        doc_models[name] = {"conductance": json_value(k), "time_constant": json_value(tau),
                            "time_to_final_height": json_value(t_exact),
                            "time_to_final_height_ode": json_value(col.time_to_final),
                            "time": [json_value(x) for x in col.time[::10]],
                            "height": [json_value(x) for x in col.height[::10]]}
    lines.append("(linear leak Q = K ΔP: H(t) = H0 exp(-t/τ), τ = A/(K ρ g); the ODE solution agrees)")
    doc = {"case": case.title, "squeeze_pressure": pred.squeeze_pressure, "load": rig.load,
           "final_height": h1, "models": doc_models,
           "units": {"squeeze_pressure": "Pa", "load": "N", "final_height": "m", "conductance": "m^3/(s*Pa)",
                     "time_constant": "s", "time_to_final_height": "s", "time": "s", "height": "m",
                     "interval_pressure_difference": "Pa", "interval_leak_rate": "m^3/s"},
           "messages": list(pred.messages)}
    analysis = None
    if args.readings:
        from .labdata import read_rig_readings

        t, h = read_rig_readings(args.readings)
        analysis = leak_rate_from_readings(rig, t, h, source=args.readings)
        lines += ["", f"readings from {args.readings}: {t.size} points over {t[-1] - t[0]:.4g} s", "",
                  f"{'ΔP (kPa)':>10} {'Q (m³/s)':>12} {'Q (ml/min)':>11}"]
        for dpi, qi in zip(analysis.interval_pressure_difference, analysis.interval_leak_rate):
            lines.append(f"{dpi / 1e3:10.4g} {qi:12.4e} {qi * 6e7:11.4g}")
        rising = int(np.count_nonzero(analysis.interval_leak_rate < 0))
        if rising:
            lines.append(f"note: the level rises in {rising} of {analysis.interval_leak_rate.size} intervals "
                         "(reading noise?): those intervals show a negative Q")
        lines.append(f"exponential fit of ln H(t): K = {analysis.conductance:.4g} ± {analysis.conductance_std:.2g} "
                     f"m³/(s·Pa), rms residual {analysis.rms_log_residual:.2g} decades")
        for name, k in pred.conductance.items():
            if k > 0 and name.startswith("critical"):
                lines.append(f"α implied by the readings: {case.alpha * analysis.conductance / k:.3g} "
                             f"(case α = {case.alpha:g})")
        doc["readings"] = {"interval_pressure_difference": [json_value(x) for x in analysis.interval_pressure_difference],
                           "interval_leak_rate": [json_value(x) for x in analysis.interval_leak_rate],
                           "conductance": json_value(analysis.conductance),
                           "conductance_std": json_value(analysis.conductance_std)}
    lines += ["note: " + m for m in pred.messages]
    if not args.quiet:
        print("\n".join(lines))
    if args.json:
        write_text(args.json, json.dumps(doc, indent=2, ensure_ascii=False) + "\n")
        _say(args, f"wrote {args.json}")
    if args.plots:
        from .lab_figures import figure_readings, figure_rig
        from .plotting import save_figures

        figs = {"rig.png": figure_rig(rig, pred.columns, pred.squeeze_pressure)}
        if analysis is not None:
            figs["readings.png"] = figure_readings(rig, analysis, pred.conductance)
        save_figures(figs, args.plots)
        _say(args, f"wrote {len(figs)} figure(s) to {args.plots}/")
    return 0


# ---------------------------------------------------------------------- report
def _cmd_report(args: argparse.Namespace) -> int:
    from ._io import check_outputs, write_text
    from .report import html_report

    check_outputs([args.output], args.force)
    from .cli import _load

    cases = _load(args)
    write_text(args.output, html_report(cases))
    _say(args, f"wrote {args.output}")
    return 0
