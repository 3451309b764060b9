"""``sealeak simulate``: numerically exact leak rate and α (BEM contact + Reynolds flow)."""

from __future__ import annotations

import argparse
import sys
from collections.abc import Callable
from pathlib import Path
from typing import TYPE_CHECKING, Any

from ..errors import InputError, SealeakError
from ._common import inputs, load, outputs

if TYPE_CHECKING:
    from ..cases import Case
    from ..cases.ensemble import TaskEvent

__all__ = ["register"]


def _cmd_simulate(args: argparse.Namespace) -> int:
    from tqdm import tqdm

    from ..cases import simulate
    from ..cases.ensemble import default_workers, make_runner
    from ..cases.limits import MAX_REALIZATIONS, whole_number
    from ..io.files import check_outputs, write_text
    from ..render import SIMULATION_FIGURE_NAMES, save_figures, simulation_figures, simulation_json, simulation_table
    from ..render.convergence import CONVERGENCE_FIGURE_NAMES
    from ..render.simulation import BAND_SIMULATION_FIGURE_NAMES, SIMULATION_GAS_FIGURE_NAMES

    # either route's figures, and a gas case's
    names = tuple(dict.fromkeys(SIMULATION_FIGURE_NAMES + BAND_SIMULATION_FIGURE_NAMES + SIMULATION_GAS_FIGURE_NAMES
                                + CONVERGENCE_FIGURE_NAMES))
    check_outputs(outputs(args, names, folders=("plots", "fields")), args.force, inputs=inputs(args))
    if args.fields:
        _check_fields_folder(Path(args.fields), args.force)
    cases = load(args)
    if len(cases) != 1:
        raise SealeakError("simulate takes a case without [study] (one surface)")
    case = cases[0]
    # options override the case's [simulation] section, which overrides the built-in defaults
    grids = _grids(args, case)
    grid = grids[0]
    realizations, seed = (getattr(args, k) if getattr(args, k) is not None else case.simulation.get(k, d)
                          for k, d in (("realizations", 4), ("seed", 0)))
    def where(key: str) -> str:  # name the option (or the case file's key)
        return f"--{key}" if getattr(args, key) is not None else f"simulation.{key}"

    whole_number(where("realizations"), realizations, 1, MAX_REALIZATIONS)
    for key, value, low in (("grid", grid, 16), ("seed", seed, 0)):
        if isinstance(value, bool) or not isinstance(value, int) or value < low or (key == "grid" and value % 2):
            raise InputError(where(key), value, f"must be {'an even integer' if key == 'grid' else 'an integer'} >= {low}")
    if args.store is not None and args.fields:
        raise InputError("--fields", args.fields, "cannot be combined with --store (a resumed run would lack the field "
                                                  "files of the tasks it takes from the store): use --store-fields to "
                                                  "keep the fields in the store")
    if args.store_fields and args.store is None:
        raise InputError("--store-fields", None, "needs --store DIR: the fields are kept in the store")
    grid_name = "simulation.grid" if args.grid is None and "grid" in case.simulation else "--grid"
    if len(grids) > 1:
        if case.band is not None:
            raise InputError(grid_name, ",".join(map(str, grids)), "a list of grids (a convergence study) applies to "
                                                                   "uniform seals; an O-ring takes one grid")
        if args.fields:
            raise InputError("--fields", args.fields, f"cannot be combined with a list of grids ({grid_name}): "
                                                      "write field files one grid at a time")
        return _convergence(args, case, grids, realizations, seed)
    if case.band is not None:
        return _simulate_band(args, case, grid, realizations, seed, grid_name)
    workers = default_workers(grid) if args.workers is None else args.workers
    if args.scheduler is None and workers == 0 and args.store is None:  # the plain loop, as before Dask
        total = realizations * len(case.squeeze_pressure)
        with tqdm(total=total, desc="contact + flow", unit="solve", disable=args.quiet or None, file=sys.stderr) as bar:
            res = simulate(case, grid=grid, realizations=realizations, seed=seed,
                           threshold=not args.no_threshold, fields_dir=args.fields, progress=bar.update)
    else:
        runner = make_runner(workers=workers, scheduler=args.scheduler, store=args.store,
                             progress=None if args.quiet else _progress_line, note=_note, fields=args.store_fields)
        res = simulate(case, grid=grid, realizations=realizations, seed=seed,
                       threshold=not args.no_threshold, fields_dir=args.fields, runner=runner)
    if not args.quiet:
        sys.stdout.write(simulation_table(case, res))
    if args.json:
        write_text(args.json, simulation_json(case, res))
    if args.plots:
        save_figures(simulation_figures(case, res), args.plots)
    return 0


def _grids(args: argparse.Namespace, case: Case) -> tuple[int, ...]:
    """The grid(s) N: ``--grid`` (one, or a comma-separated list), else ``[simulation] grid``, else 256."""
    from ..cases.builders import parse_grid_list

    if args.grid is not None:
        return parse_grid_list(args.grid, "--grid")
    value = case.simulation.get("grid", 256)
    return tuple(value) if isinstance(value, tuple) else (value,)


def _convergence(args: argparse.Namespace, case: Case, grids: tuple[int, ...], realizations: int, seed: int) -> int:
    """``simulate`` at several grids: the convergence and validation study (docs/theory.md §6.8)."""
    from tqdm import tqdm

    from ..cases.convergence import convergence_study
    from ..cases.ensemble import default_workers, make_runner
    from ..io.files import write_text
    from ..render import save_figures
    from ..render.convergence import convergence_figures, convergence_json, convergence_table

    bars: list[tqdm] = []

    def runner_for(grid: int) -> Any:
        workers = default_workers(grid) if args.workers is None else args.workers
        if not args.quiet:
            sys.stderr.write(f"simulate: grid {grid}x{grid} ({grids.index(grid) + 1} of {len(grids)})\n")
        if args.scheduler is None and workers == 0 and args.store is None:
            return None
        store = None if args.store is None else Path(args.store) / f"grid-{grid}"
        return make_runner(workers=workers, scheduler=args.scheduler, store=store,
                           progress=None if args.quiet else _progress_line, note=_note, fields=args.store_fields)

    def progress_for(grid: int) -> Callable[[int], None]:
        for done in bars:  # the previous grid's bar is finished
            done.close()
        bar = tqdm(total=realizations * len(case.squeeze_pressure), desc=f"grid {grid}: contact + flow", unit="solve",
                   disable=args.quiet or None, file=sys.stderr)
        bars.append(bar)
        return bar.update

    try:
        study = convergence_study(case, grids, realizations=realizations, seed=seed, threshold=not args.no_threshold,
                                  runner_for=runner_for, progress_for=progress_for)
    finally:
        for bar in bars:
            bar.close()
    if not args.quiet:
        sys.stdout.write(convergence_table(case, study))
    if args.json:
        write_text(args.json, convergence_json(case, study))
    if args.plots:
        save_figures(convergence_figures(case, study), args.plots)
    return 0


def _simulate_band(args: argparse.Namespace, case: Case, grid: int, realizations: int, seed: int, grid_name: str) -> int:
    """``simulate`` on an O-ring case: the cylinder on the rough surface, the flow across its band, α."""
    from tqdm import tqdm

    from ..cases.ensemble import default_workers, make_runner
    from ..cases.simulation_band import run_band_task, simulate_band
    from ..io.files import write_text
    from ..render import save_figures
    from ..render.simulation import band_simulation_figures, band_simulation_json, band_simulation_table

    band = case.band
    assert band is not None
    if band.kind != "o-ring":
        raise InputError("seal.pressure_profile", band.profile_source or "a pressure profile",
                         "simulate solves uniform seals and O-rings; a seal given by its pressure profile has no body "
                         "whose contact could be simulated (use predict)")
    if args.no_threshold and not args.quiet:
        sys.stderr.write("note: --no-threshold does not apply to an O-ring (no percolation-threshold search is made)\n")
    workers = default_workers(grid) if args.workers is None else args.workers
    if args.scheduler is None and workers == 0 and args.store is None:  # the plain loop
        total = (realizations + 1) * band.loads.size
        with tqdm(total=total, desc="contact + flow", unit="solve", disable=args.quiet or None, file=sys.stderr) as bar:
            res = simulate_band(case, grid=grid, realizations=realizations, seed=seed,
                                fields_dir=args.fields, progress=bar.update, grid_name=grid_name)
    else:  # one task per realisation (after the smooth checks, made here)
        runner = make_runner(workers=workers, scheduler=args.scheduler, store=args.store,
                             progress=None if args.quiet else _progress_line, note=_note, fields=args.store_fields,
                             task_function=run_band_task)  # type: ignore[arg-type]
        res = simulate_band(case, grid=grid, realizations=realizations, seed=seed, fields_dir=args.fields,
                            grid_name=grid_name, runner=runner)  # type: ignore[arg-type]
    if not args.quiet:
        sys.stdout.write(band_simulation_table(case, res))
    if args.json:
        write_text(args.json, band_simulation_json(case, res))
    if args.plots:
        save_figures(band_simulation_figures(case, res), args.plots)
    return 0


def _clock(seconds: float) -> str:
    """``m:ss`` (or ``h:mm:ss``) of a duration in seconds."""
    m, sec = divmod(int(round(seconds)), 60)
    h, m = divmod(m, 60)
    return f"{h}:{m:02d}:{sec:02d}" if h else f"{m}:{sec:02d}"


def _progress_line(event: TaskEvent) -> None:
    """One line on stderr per finished task (with the time left), and one when nothing finished for a while."""
    if event.dashboard is not None:
        line = f"simulate: the Dask dashboard shows the tasks at {event.dashboard}"
    elif event.task is None:
        line = f"simulate: working, {event.done} of {event.total} tasks finished, {_clock(event.elapsed)} elapsed"
    else:
        left = "" if event.left is None else f", about {_clock(event.left)} left"
        line = (f"simulate: {event.task} finished ({event.done} of {event.total} tasks, {_clock(event.elapsed)} "
                f"elapsed{left})")
    sys.stderr.write(line + "\n")
    sys.stderr.flush()


def _note(message: str) -> None:
    sys.stderr.write(f"note: {message}\n")


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
                                        "Reynolds flow (an O-ring: the cylinder on the rough surface, flow across "
                                        "its band)")
    add_case_args(p)
    p.add_argument("--grid", metavar="N[,N...]",
                   help="grid points per side N (even; default: [simulation] grid, else 256); a comma-separated list "
                        "(e.g. 64,128,256) runs a convergence study: the ensemble at each grid, α and the percolation "
                        "threshold against grid size, extrapolated to the continuum")
    p.add_argument("--realizations", type=int,
                   help="random surfaces R (default: [simulation] realizations, else 4)")
    p.add_argument("--seed", type=int, help="random seed (default: [simulation] seed, else 0)")
    p.add_argument("--json", metavar="FILE", help="write per-pressure results as JSON")
    p.add_argument("--fields", metavar="DIR", help="write DIR/r<r>-p<i>.npz with height, gap, pressure, size")
    p.add_argument("--plots", metavar="DIR", help="write figures into DIR")
    p.add_argument("--no-threshold", action="store_true",
                   help="skip the percolation-threshold search (uniform seals; an O-ring makes none)")
    p.add_argument("--workers", type=int, metavar="N",
                   help="run the realisations on a local Dask cluster of N worker processes, one thread each "
                        "(default: all cores from a 512x512 grid up, else 0); 0: no Dask, one after the other in "
                        "this process")
    p.add_argument("--scheduler", metavar="ADDRESS",
                   help="run on the Dask cluster whose scheduler is at ADDRESS (e.g. tcp://10.0.0.5:8786) "
                        "instead of a local one")
    p.add_argument("--store", metavar="DIR",
                   help="keep every finished task in DIR; the same command run again computes only what is missing")
    p.add_argument("--store-fields", action="store_true",
                   help="with --store DIR: every task also writes its height, gap and pressure maps into "
                        "DIR/fields.zarr (Zarr; opens in xarray)")
    p.set_defaults(func=_cmd_simulate)
