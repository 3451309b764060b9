"""``sealeak simulate``: numerically exact leak rate and α (BEM contact + Reynolds flow)."""

from __future__ import annotations

import argparse
import sys
from collections.abc import Callable
from pathlib import Path

from ..errors import InputError, SealeakError
from ._common import inputs, load, outputs

__all__ = ["register"]


def _cmd_simulate(args: argparse.Namespace) -> int:
    from tqdm import tqdm

    from ..cases import simulate
    from ..io.files import check_outputs, write_text
    from ..render import SIMULATION_FIGURE_NAMES, save_figures, simulation_figures, simulation_json, simulation_table

    check_outputs(outputs(args, SIMULATION_FIGURE_NAMES, folders=("plots", "fields")), args.force, inputs=inputs(args))
    if args.fields:
        _check_fields_folder(Path(args.fields), args.force)
    cases = load(args)
    if len(cases) != 1:
        raise SealeakError("simulate takes a case without [study] (one surface)")
    case = cases[0]
    # options override the case's [simulation] section, which overrides the built-in defaults
    grid, realizations, seed = (getattr(args, k) if getattr(args, k) is not None else case.simulation.get(k, d)
                                for k, d in (("grid", 256), ("realizations", 4), ("seed", 0)))
    for key, value in (("grid", grid), ("realizations", realizations), ("seed", seed)):  # name the option (or key)
        low = {"grid": 16, "realizations": 1, "seed": 0}[key]
        if isinstance(value, bool) or not isinstance(value, int) or value < low or (key == "grid" and value % 2):
            where = f"--{key}" if getattr(args, key) is not None else f"simulation.{key}"
            raise InputError(where, value, f"must be {'an even integer' if key == 'grid' else 'an integer'} >= {low}")
    total = realizations * len(case.squeeze_pressure)
    with tqdm(total=total, desc="contact + flow", unit="solve", disable=args.quiet or None, file=sys.stderr) as bar:
        res = simulate(case, grid=grid, realizations=realizations, seed=seed,
                       threshold=not args.no_threshold, fields_dir=args.fields, progress=bar.update)
    if not args.quiet:
        sys.stdout.write(simulation_table(case, res))
    if args.json:
        write_text(args.json, simulation_json(case, res))
    if args.plots:
        save_figures(simulation_figures(case, res), args.plots)
    return 0


def _check_fields_folder(folder: Path, force: bool) -> None:
    """Refuse up front a ``--fields`` folder that cannot be one, or that holds field files without ``--force``."""
    existing = next(d for d in (folder, *folder.parents, Path(".")) if d.exists())
    if not existing.is_dir():
        what = "is a file" if existing == folder else f"is inside {existing}, which is a file"
        raise InputError("--fields", str(folder), f"{what}, not a folder: give a folder for the field files "
                                                  "(it is created if missing)")
    if existing == folder and any(folder.glob("r*-p*.npz")) and not force:
        raise SealeakError(f"{folder} already holds field files; pass --force to overwrite, or choose another folder")


def register(sub: argparse._SubParsersAction, add_case_args: Callable[[argparse.ArgumentParser], None]) -> None:
    """Add ``simulate`` to the sub-command parsers."""
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
