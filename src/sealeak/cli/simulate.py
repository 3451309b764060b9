"""``sealeak simulate``: numerically exact leak rate and α (BEM contact + Reynolds flow)."""

from __future__ import annotations

import argparse
import sys
from collections.abc import Callable
from pathlib import Path
from typing import TYPE_CHECKING, Any

from ..errors import InputError, SealeakError
from ._common import add_output_args, emit, inputs, load, load_case_file, outputs

if TYPE_CHECKING:
    from ..cases import Case
    from ..cases.ensemble import TaskEvent
    from ..cases.options import SimulationOptions

__all__ = ["register"]


def _cmd_simulate(args: argparse.Namespace) -> int:
    from ..cases.options import simulation_options
    from ..io.files import check_outputs
    from ..render import SIMULATION_FIGURE_NAMES, simulation_figures, simulation_json, simulation_table
    from ..render.convergence import CONVERGENCE_FIGURE_NAMES
    from ..render.simulation import (
        BAND_SIMULATION_FIGURE_NAMES,
        SIMULATION_GAS_FIGURE_NAMES,
        band_simulation_figures,
        band_simulation_json,
        band_simulation_table,
    )

    # either route's figures, and a gas case's
    names = tuple(dict.fromkeys(SIMULATION_FIGURE_NAMES + BAND_SIMULATION_FIGURE_NAMES + SIMULATION_GAS_FIGURE_NAMES
                                + CONVERGENCE_FIGURE_NAMES))
    check_outputs(outputs(args, names, folders=("plots", "fields")), args.force, inputs=inputs(args))
    cases = load(args)
    if len(cases) != 1:
        raise SealeakError("simulate takes a case without [study] (one surface)")
    case = cases[0]
    # options override the case's [simulation] section, which overrides the built-in defaults
    opts = simulation_options(grid=args.grid, realizations=args.realizations, seed=args.seed, workers=args.workers,
                              device=args.device, defaults=case.simulation)
    if _map_route(args, case):
        return _simulate_maps(args, case, opts)
    if args.windows is not None:
        raise InputError("--windows", args.windows, "applies to the map route (--surface maps, a topography case)")
    if args.store is not None and args.fields:
        raise InputError("--fields", args.fields, "cannot be combined with --store (a resumed run would lack the field "
                                                  "files of the tasks it takes from the store): use --store-fields to "
                                                  "keep the fields in the store")
    if args.store_fields and args.store is None:
        raise InputError("--store-fields", None, "needs --store DIR: the fields are kept in the store")
    if len(opts.grids) > 1:
        if case.band is not None:
            raise InputError(opts.grid_field, ",".join(map(str, opts.grids)), "a list of grids (a convergence study) "
                                                                             "applies to uniform seals; an O-ring takes "
                                                                             "one grid")
        if args.fields:
            raise InputError("--fields", args.fields, f"cannot be combined with a list of grids ({opts.grid_field}): "
                                                      "write field files one grid at a time")
        return _convergence(args, case, opts)
    table: Callable[[Case, Any], str]
    json_text: Callable[[Case, Any], str]
    figures: Callable[[Case, Any], dict[str, Any]]
    if case.band is not None:
        res: Any = _simulate_band(args, case, opts)
        table, json_text, figures = band_simulation_table, band_simulation_json, band_simulation_figures
    else:
        res = _run_pipeline(args, opts, "simulate", opts.realizations * len(case.squeeze_pressure), case,
                            threshold=not args.no_threshold)
        table, json_text, figures = simulation_table, simulation_json, simulation_figures
    emit(args, table(case, res), {args.json: json_text(case, res)} if args.json else {},
         figures(case, res) if args.plots else {})
    return 0


def _runner(args: argparse.Namespace, workers: int, store: str | Path | None) -> Any:
    """The runner of the tasks (a Dask cluster, a store), or None for the plain loop in this process."""
    from ..cases.ensemble import make_runner

    if args.scheduler is None and workers == 0 and store is None:  # the plain loop, as before Dask
        return None
    return make_runner(workers=workers, scheduler=args.scheduler, store=store,
                       progress=None if args.quiet else _progress_line, note=_note, fields=args.store_fields)


def _run_pipeline(args: argparse.Namespace, opts: SimulationOptions, route: str, solves: int, case: Case,
                  **options: Any) -> Any:
    """``route`` (``simulate`` or ``simulate_band``) on one grid: the plain loop with a progress bar of ``solves``
    contact and flow solves, or the tasks on the runner (``--workers``, ``--scheduler``, ``--store``)."""
    from tqdm import tqdm

    from ..cases import simulation, simulation_band
    from ..cases.ensemble import run_workers

    run = simulation.simulate if route == "simulate" else simulation_band.simulate_band
    common = {"grid": opts.grid, "realizations": opts.realizations, "seed": opts.seed, "fields_dir": args.fields,
              "grid_name": opts.grid_field, "device": opts.device, **options}
    runner = _runner(args, run_workers(opts.workers, opts.grid, opts.device, opts.gpus), args.store)
    if runner is not None:
        return run(case, runner=runner, **common)
    with tqdm(total=solves, desc="contact + flow", unit="solve", disable=args.quiet or None, file=sys.stderr) as bar:
        return run(case, progress=bar.update, **common)


def _convergence(args: argparse.Namespace, case: Case, opts: SimulationOptions) -> int:
    """``simulate`` at several grids: the convergence and validation study (docs/theory.md §6.8)."""
    from tqdm import tqdm

    from ..cases.convergence import convergence_study
    from ..cases.ensemble import run_workers
    from ..render.convergence import convergence_figures, convergence_json, convergence_table

    bars: list[tqdm] = []
    grids = opts.grids

    def runner_for(grid: int) -> Any:
        workers = run_workers(opts.workers, grid, opts.device, opts.gpus)
        if not args.quiet:
            sys.stderr.write(f"simulate: grid {grid}x{grid} ({grids.index(grid) + 1} of {len(grids)})\n")
        return _runner(args, workers, None if args.store is None else Path(args.store) / f"grid-{grid}")

    def progress_for(grid: int) -> Callable[[int], None]:
        for done in bars:  # the previous grid's bar is finished
            done.close()
        bar = tqdm(total=opts.realizations * len(case.squeeze_pressure), desc=f"grid {grid}: contact + flow",
                   unit="solve", disable=args.quiet or None, file=sys.stderr)
        bars.append(bar)
        return bar.update

    try:
        study = convergence_study(case, grids, realizations=opts.realizations, seed=opts.seed,
                                  threshold=not args.no_threshold, runner_for=runner_for, progress_for=progress_for,
                                  device=opts.device)
    finally:
        for bar in bars:
            bar.close()
    emit(args, convergence_table(case, study), {args.json: convergence_json(case, study)} if args.json else {},
         convergence_figures(case, study) if args.plots else {})
    return 0


def _simulate_band(args: argparse.Namespace, case: Case, opts: SimulationOptions) -> Any:
    """``simulate`` on an O-ring case: the cylinder on the rough surface, the flow across its band, α."""
    band = case.band
    assert band is not None
    if band.kind != "o-ring":
        raise InputError("seal.pressure_profile", band.profile_source or "a pressure profile",
                         "simulate solves uniform seals and O-rings; a seal given by its pressure profile has no body "
                         "whose contact could be simulated (use predict)")
    if args.no_threshold and not args.quiet:
        sys.stderr.write("note: --no-threshold does not apply to an O-ring (no percolation-threshold search is made)\n")
    # the plain loop: one smooth check per load, then each realisation's loads; else one task per realisation
    return _run_pipeline(args, opts, "simulate_band", (opts.realizations + 1) * band.loads.size, case)


def _map_route(args: argparse.Namespace, case: Case) -> bool:
    """Whether ``simulate`` runs on the case's measured maps (``--surface maps``, the default of a topography case)."""
    if args.surface == "maps" and case.surface_model != "topography":
        raise InputError("--surface", "maps", "needs a case with surface.model = \"topography\": its files are the maps")
    return args.surface == "maps" or (args.surface is None and case.surface_model == "topography")


def _simulate_maps(args: argparse.Namespace, case: Case, opts: SimulationOptions) -> int:
    """``simulate`` on a topography case's maps: each map (or sub-window) is the surface, one realisation each."""
    from tqdm import tqdm

    from ..cases.ensemble import run_workers
    from ..cases.simulation_map import case_maps, simulate_maps
    from ..render.simulation_map import map_simulation_json, map_simulation_table

    for option, value in (("--store", args.store), ("--plots", args.plots)):
        if value is not None:
            raise InputError(option, value, "does not apply to the map route (measured maps); use --surface random "
                                            "for random surfaces from the maps' C(q)")
    if len(opts.grids) > 1:
        raise InputError(opts.grid_field, ",".join(map(str, opts.grids)), "the map route takes one grid")
    if (args.realizations is not None or args.seed is not None) and not args.quiet:
        sys.stderr.write("note: --realizations and --seed do not apply to measured maps (one realisation per map)\n")
    case_file = load_case_file(args)
    maps = case_maps(case_file.inputs["surface"], Path(case_file.source).parent)
    grid = None if args.grid is None and "grid" not in case.simulation else opts.grid
    windows = 1 if args.windows is None else args.windows
    workers = run_workers(opts.workers, grid or 0, opts.device, opts.gpus)
    runner = _runner(args, workers, None)
    common: dict[str, Any] = {"grid": grid, "windows": windows, "threshold": not args.no_threshold, "device": opts.device,
                              "fields_dir": args.fields, "grid_name": opts.grid_field, "field_name": "surface.file",
                              "windows_name": "--windows"}
    if runner is not None:
        res = simulate_maps(maps, case, runner=runner, **common)
    else:
        total = len(maps) * windows**2 * len(case.squeeze_pressure)
        with tqdm(total=total, desc="contact + flow", unit="solve", disable=args.quiet or None, file=sys.stderr) as bar:
            res = simulate_maps(maps, case, progress=bar.update, **common)
    emit(args, map_simulation_table(case, res), {args.json: map_simulation_json(case, res)} if args.json else {}, {})
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
    add_output_args(p, json="write per-pressure results as JSON", plots="write figures into DIR")
    p.add_argument("--fields", metavar="DIR", help="write DIR/r<r>-p<i>.npz with height, gap, pressure, size")
    p.add_argument("--no-threshold", action="store_true",
                   help="skip the percolation-threshold search (uniform seals; an O-ring makes none)")
    p.add_argument("--workers", type=int, metavar="N",
                   help="run the realisations on a local Dask cluster of N worker processes, one thread each "
                        "(default: all cores from a 512x512 grid up, else 0); 0: no Dask, one after the other in "
                        "this process")
    p.add_argument("--device", metavar="cpu|cuda",
                   help="where the surfaces are synthesized and the contact solved (default: [simulation] device, else "
                        "cpu): cpu, or cuda for an NVIDIA GPU with CuPy (pip install 'sealeak[gpu]'), one Dask worker "
                        "per GPU, where the flows' AMG iterations run too (their set-up and small fields' direct "
                        "solves stay on the CPU)")
    p.add_argument("--scheduler", metavar="ADDRESS",
                   help="run on the Dask cluster whose scheduler is at ADDRESS (e.g. tcp://10.0.0.5:8786) "
                        "instead of a local one")
    p.add_argument("--store", metavar="DIR",
                   help="keep every finished task in DIR; the same command run again computes only what is missing")
    p.add_argument("--store-fields", action="store_true",
                   help="with --store DIR: every task also writes its height, gap and pressure maps into "
                        "DIR/fields.zarr (Zarr; opens in xarray)")
    p.add_argument("--surface", choices=("maps", "random"),
                   help="maps: each measured map of a topography case is the surface (one realisation per map; the "
                        "default for surface.model = \"topography\"); random: random Gaussian surfaces from C(q) "
                        "(the default otherwise)")
    p.add_argument("--windows", type=int, metavar="K",
                   help="with maps: cut each map's central square into K x K sub-windows, one realisation each "
                        "(default 1)")
    p.set_defaults(func=_cmd_simulate)
