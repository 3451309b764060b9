"""``sealeak simulate``: numerically exact leak rate and α (BEM contact + Reynolds flow)."""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path
from typing import Any, Callable

import numpy as np

from .errors import SealeakError

__all__ = ["register"]

UNITS = {
    "squeeze_pressure": "Pa", "relative_contact_area": "1", "relative_contact_area_std": "1",
    "relative_contact_area_theory": "1", "mean_gap": "m", "mean_gap_std": "m", "percolating_fraction": "1",
    "leak_rate": "m^3/s", "leak_rate_std": "m^3/s", "leak_rate_critical_junction": "m^3/s", "alpha": "1",
    "alpha_std": "1", "percolation_threshold": "1", "percolation_threshold_std": "1", "pressure_difference": "Pa",
    "size": "m",
}
FIGURES = ("simulate_leak_rate.png", "simulate_alpha.png", "contact_map.png")


def simulation_json(case, res) -> str:
    from .output import case_summary, json_value

    keys = [k for k in UNITS if k not in ("percolation_threshold", "percolation_threshold_std",
                                          "pressure_difference", "size")]
    rows = [{k: json_value(getattr(res, k)[i]) for k in keys} | {"pressure_difference": res.pressure_difference}
            for i in range(res.squeeze_pressure.size)]
    doc: dict[str, Any] = {
        "units": UNITS,
        "results": rows,
        "percolation_threshold": json_value(res.percolation_threshold),
        "percolation_threshold_std": json_value(res.percolation_threshold_std),
        "settings": {"grid": res.grid, "realizations": res.realizations, "seed": res.seed, "size": res.size,
                     "spectrum_cut_wavevector": res.q_cut, "spectrum": res.spectrum_note},
        "leak_rate_critical_junction_note": "critical-junction prediction with alpha = 1 for the same spectrum; "
                                            "alpha = leak_rate / leak_rate_critical_junction",
        "case": case_summary(case),
        "notes": list(res.notes),
    }
    return json.dumps(doc, indent=2, ensure_ascii=False) + "\n"


def simulation_table(case, res) -> str:
    lines = [f"{case.title}: numerically exact leak rate",
             f"grid {res.grid}x{res.grid} on a square of side {res.size * 1e3:.4g} mm, {res.realizations} "
             f"realisation(s), seed {res.seed}; {res.spectrum_note}", ""]
    lines.append(f"{'P0 (kPa)':>9} {'A/A0 sim':>9} {'A/A0 th':>8} {'ū (µm)':>9} {'perc':>5} "
                 f"{'Q sim (m³/s)':>13} {'± std':>9} {'Q cj α=1':>10} {'α':>7} {'± std':>7}")

    def f(x, fmt):
        return "—".rjust(int(fmt.split(".")[0])) if not np.isfinite(x) else format(x, fmt)

    for i in range(res.squeeze_pressure.size):
        lines.append(f"{res.squeeze_pressure[i] / 1e3:9.4g} {res.relative_contact_area[i]:9.3f} "
                     f"{res.relative_contact_area_theory[i]:8.3f} {res.mean_gap[i] * 1e6:9.4g} "
                     f"{res.percolating_fraction[i]:5.2f} {f(res.leak_rate[i], '13.3e')} {f(res.leak_rate_std[i], '9.2e')} "
                     f"{f(res.leak_rate_critical_junction[i], '10.3e')} {f(res.alpha[i], '7.3f')} "
                     f"{f(res.alpha_std[i], '7.3f')}")
    if np.isfinite(res.percolation_threshold):
        lines.append("")
        lines.append(f"the non-contact area stops percolating at A/A0 = {res.percolation_threshold:.3f} ± "
                     f"{res.percolation_threshold_std:.2g} (critical-junction theory assumes 1 - p_c = "
                     f"{1 - case.percolation_threshold:.3f})")
    for n in res.notes:
        lines.append("note: " + n)
    return "\n".join(lines) + "\n"


def simulation_figures(case, res) -> dict:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.colors import ListedColormap

    from .numerics import spanning_mask
    from .plotting import pressure_axis

    figs = {}
    scale, unit = pressure_axis(res.squeeze_pressure)
    p = res.squeeze_pressure / scale
    fig, ax = plt.subplots(figsize=(6.4, 4.4), dpi=150)
    ok = res.leak_rate > 0
    std = np.nan_to_num(res.leak_rate_std[ok])
    lower = np.minimum(std, 0.9 * res.leak_rate[ok])  # keep the bar above zero on the log axis
    ax.errorbar(p[ok], res.leak_rate[ok], yerr=[lower, std], fmt="o", ms=4, capsize=3,
                label=f"numerical (BEM + Reynolds), {res.realizations} realisation(s)")
    ax.plot(p, res.leak_rate_critical_junction, "-", label="critical junction, α = 1")
    if case.alpha != 1.0:
        ax.plot(p, case.alpha * res.leak_rate_critical_junction, "--", label=f"critical junction, α = {case.alpha:g}")
    ax.set_yscale("log")
    ax.set_xlabel(f"squeeze pressure P0 ({unit})")
    ax.set_ylabel("leak rate Q (m³/s)")
    ax.set_title(f"Numerical against critical-junction leak rate\n{res.grid}² grid, ΔP = "
                 f"{res.pressure_difference / 1e3:.3g} kPa, Ly/Lx = {case.seal.aspect_ratio:.3g}", fontsize=9)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    figs["simulate_leak_rate.png"] = fig

    fig, ax = plt.subplots(figsize=(6.4, 4.4), dpi=150)
    ok = np.isfinite(res.alpha)
    ax.errorbar(p[ok], res.alpha[ok], yerr=np.nan_to_num(res.alpha_std[ok]), fmt="o-", ms=4, capsize=3, label="α = Q_num / Q_cj(α=1)")
    ax.axhline(case.alpha, color="k", ls="--", lw=0.8, label=f"case α = {case.alpha:g}")
    ax.set_xlabel(f"squeeze pressure P0 ({unit})")
    ax.set_ylabel("α (1)")
    ax.set_title("The factor α of the critical-junction theory, computed", fontsize=9)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    figs["simulate_alpha.png"] = fig

    fig, ax = plt.subplots(figsize=(5.6, 5.2), dpi=150)
    if res.contact_maps:
        idx = sorted(res.contact_maps)
        perc_idx = [i for i in idx if res.per_realization["percolates"][0, i]]
        pick = perc_idx[-1] if perc_idx else idx[len(idx) // 2]
        contact = res.contact_maps[pick]
        channel = spanning_mask(~contact)
        img = np.where(contact, 0, np.where(channel, 2, 1))
        cmap = ListedColormap(["#202020", "#d8d8d8", "#1f77b4"])
        # img is indexed [x, y]; transpose so x runs horizontally (flow left to right)
        ax.imshow(img.T, cmap=cmap, vmin=0, vmax=2, extent=(0, res.size * 1e3, 0, res.size * 1e3), origin="lower",
                  interpolation="nearest")
        ax.set_xlabel("x (mm), flow from inlet x = 0 to outlet →")
        ax.set_ylabel("y, periodic (mm)")
        ax.set_title(f"Contact map, realisation 0, P0 = {res.squeeze_pressure[pick] / scale:.3g} {unit}\n"
                     f"black: contact ({contact.mean():.1%}); blue: channels spanning inlet to outlet; "
                     f"grey: trapped fluid", fontsize=8)
    figs["contact_map.png"] = fig
    return figs


def _cmd_simulate(args: argparse.Namespace) -> int:
    from ._io import check_outputs, write_text
    from .cli import _load
    from .simulation import simulate

    outputs = [args.json] if args.json else []
    if args.plots:
        outputs += [str(Path(args.plots) / n) for n in FIGURES]
    check_outputs(outputs, args.force)
    if args.fields and Path(args.fields).exists() and any(Path(args.fields).glob("r*-p*.npz")) and not args.force:
        raise SealeakError(f"{args.fields} already holds field files; pass --force to overwrite, or choose another folder")
    cases = _load(args)
    if len(cases) != 1:
        raise SealeakError("simulate takes a case without [study] (one surface)")
    case = cases[0]
    from tqdm import tqdm

    # options override the case's [simulation] section, which overrides the built-in defaults
    grid, realizations, seed = (getattr(args, k) if getattr(args, k) is not None else case.simulation.get(k, d)
                                for k, d in (("grid", 256), ("realizations", 4), ("seed", 0)))
    total = realizations * len(case.squeeze_pressure)
    with tqdm(total=total, desc="contact + flow", unit="solve", disable=args.quiet or None, file=sys.stderr) as bar:
        res = simulate(case, grid=grid, realizations=realizations, seed=seed,
                       threshold=not args.no_threshold, fields_dir=args.fields, progress=bar.update)
    if not args.quiet:
        sys.stdout.write(simulation_table(case, res))
    if args.json:
        write_text(args.json, simulation_json(case, res))
    if args.plots:
        from .plotting import save_figures

        save_figures(simulation_figures(case, res), args.plots)
    return 0


def register(sub: argparse._SubParsersAction, add_case_args: Callable[[argparse.ArgumentParser], None]) -> None:
    p = sub.add_parser("simulate", help="numerically exact leak rate and α: random surfaces, BEM contact, "
                                        "Reynolds flow")
    add_case_args(p)
    p.add_argument("--grid", type=int, help="grid points per side N (even; default: [simulation] grid, else 256)")
    p.add_argument("--realizations", type=int,
                   help="random surfaces R (default: [simulation] realizations, else 4)")
    p.add_argument("--seed", type=int, help="random seed (default: [simulation] seed, else 0)")
    p.add_argument("--json", metavar="FILE", help="write per-pressure results as JSON")
    p.add_argument("--fields", metavar="DIR", help="write DIR/r<r>-p<i>.npz with height, gap, pressure, size")
    p.add_argument("--plots", metavar="DIR", help="write figures into DIR")
    p.add_argument("--no-threshold", action="store_true", help="skip the percolation-threshold search")
    p.set_defaults(func=_cmd_simulate)
