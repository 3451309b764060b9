"""The options of a simulation (grid N, realisations R, seed, workers, device): one validator for every front end.

``sealeak simulate``'s options, a case file's ``[simulation]`` section and the web app's simulation jobs
all go through :func:`simulation_options` (and the case builders through :func:`grid_number`,
:func:`seed_number` and :func:`parse_grid_list`, the rules it is made of), so a grid is "an even integer
>= 16" in one place only. Each refusal is one :class:`~sealeak.errors.InputError` naming the option or
key the value came from. How large a grid may be is the memory's to say: the pipeline checks it
before any work (:mod:`sealeak.cases.pipeline`).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np

from .. import numerics
from ..errors import InputError
from ..numerics import DEVICES
from .limits import MAX_GRIDS, MAX_REALIZATIONS, MAX_WORKERS, at_most, whole_number

__all__ = ["SimulationOptions", "simulation_options", "grid_number", "seed_number", "device_name", "parse_grid_list",
           "MIN_GRID", "GRID_RULE", "DEFAULT_OPTIONS"]

#: The smallest grid N (points per side).
MIN_GRID = 16
#: What a grid must be (the message of every refusal).
GRID_RULE = f"must be an even integer >= {MIN_GRID}"
#: The built-in defaults, below a case's ``[simulation]`` section and the options.
DEFAULT_OPTIONS: Mapping[str, int] = {"grid": 256, "realizations": 4, "seed": 0}
#: What ``workers = 0`` means, said with every refusal of a number of workers.
_WORKERS_NOTE = " (0: no Dask, this process alone)"


def _integer(value: Any) -> bool:
    return isinstance(value, (int, np.integer)) and not isinstance(value, bool)


def grid_number(field: str, value: Any, what: str = "") -> int:
    """``value`` as a grid N (an even integer >= :data:`MIN_GRID`), else an InputError naming ``field``."""
    if not _integer(value) or value < MIN_GRID or value % 2:
        raise InputError(field, value, GRID_RULE + what)
    return int(value)


def seed_number(field: str, value: Any) -> int:
    """``value`` as a random seed (an integer >= 0), else an InputError naming ``field``."""
    if not _integer(value) or value < 0:
        raise InputError(field, value, "must be an integer >= 0")
    return int(value)


def device_name(field: str, value: Any) -> str:
    """``value`` as a device (``"cpu"`` or ``"cuda"``, :data:`sealeak.numerics.DEVICES`), else an InputError naming ``field``.

    Only the word is checked here (a case file may name a GPU the machine reading it lacks);
    :func:`simulation_options` also checks that a GPU is there.
    """
    if not isinstance(value, str) or value not in DEVICES:
        raise InputError(field, value, "allowed: " + ", ".join(map(repr, DEVICES)))
    return value


def parse_grid_list(value: Any, field: str) -> tuple[int, ...]:
    """Grids N from ``--grid`` text (``"64,128,256"``) or a case file's integer or list; sorted increasing.

    Each must be an even integer >= 16 and appear once, at most :data:`~sealeak.cases.limits.MAX_GRIDS` of
    them; anything else raises :class:`~sealeak.errors.InputError` naming ``field``. (How large a grid may
    be is the memory's to say: ``simulate`` checks it before it starts.)
    """
    allowed = f"{GRID_RULE}, or a comma-separated list of distinct ones (e.g. 64,128,256)"
    if isinstance(value, str) and value.strip().lstrip("-").isdigit():
        value = int(value)  # one number is named as a number (--grid = 15), as before lists were allowed
    if isinstance(value, str):
        parts = value.split(",")
        at_most(field, parts, MAX_GRIDS, "grids", shown=value)
        if not all(p.strip().isdigit() for p in parts):
            raise InputError(field, value, allowed)
        grids = [int(p) for p in parts]
    elif isinstance(value, (list, tuple)):
        at_most(field, value, MAX_GRIDS, "grids")
        if not value or not all(_integer(v) for v in value):
            raise InputError(field, value, allowed)
        grids = [int(v) for v in value]
    elif _integer(value):
        grids = [int(value)]
    else:
        raise InputError(field, value, allowed)
    if any(n < MIN_GRID or n % 2 for n in grids) or len(set(grids)) != len(grids):
        raise InputError(field, value, GRID_RULE if len(grids) == 1 else allowed)
    return tuple(sorted(grids))


@dataclass(frozen=True)
class SimulationOptions:
    """The checked options of one simulation run.

    Attributes
    ----------
    grids
        The grids N (points per side), increasing; more than one is a convergence study.
    realizations
        R, random surfaces per grid.
    seed
        The random seed; realisation r draws from the seed sequence (seed, r).
    workers
        Worker processes of a local Dask cluster (0: this process alone; None: not given, the runner's default).
    device
        Where the surfaces are synthesized and the contact solved: ``"cpu"`` or ``"cuda"`` (a GPU CuPy sees).
    gpus
        GPUs CuPy sees for ``"cuda"`` (0 for ``"cpu"``): one Dask worker each (:func:`sealeak.cases.ensemble.run_workers`).
    grid_field
        Where the grid came from (``--grid``, ``simulation.grid``), for later messages about it.
    """

    grids: tuple[int, ...]
    realizations: int
    seed: int
    workers: int | None = None
    grid_field: str = "grid"
    device: str = "cpu"
    gpus: int = 0

    @property
    def grid(self) -> int:
        """The (first) grid N."""
        return self.grids[0]


def simulation_options(*, grid: Any = None, realizations: Any = None, seed: Any = None, workers: Any = None,
                       device: Any = None, defaults: Mapping[str, Any] | None = None, prefix: str = "--",
                       max_realizations: int = MAX_REALIZATIONS, max_workers: int = MAX_WORKERS,
                       limit_note: str = "") -> SimulationOptions:
    """The options of a simulation, checked: the one validator of the command line, the case files and the web app.

    A value given here (not None) overrides the case's ``defaults`` (its ``[simulation]`` section:
    ``Case.simulation``), which override :data:`DEFAULT_OPTIONS`. A refusal names the value's source:
    ``prefix + key`` for a given value or a built-in default (``--grid``), ``simulation.<key>`` for the
    case's. ``grid`` may be one integer, a list of them or ``--grid`` text (``"64,128"``; a convergence
    study); ``max_realizations`` and ``max_workers`` may be lowered (a server's limits, ``limit_note`` then
    says so in the message, e.g. ``" (this server's limit)"``). ``device`` (``"cpu"``, the default, or
    ``"cuda"``) is checked here, before any work: ``"cuda"`` without CuPy, or with CuPy but no GPU, is an
    InputError naming ``--device`` or ``simulation.device`` and what is missing.
    """
    defaults = defaults or {}
    values: dict[str, Any] = {}
    fields: dict[str, str] = {}
    for key, given in (("grid", grid), ("realizations", realizations), ("seed", seed)):
        from_case = given is None and key in defaults
        values[key] = defaults[key] if from_case else DEFAULT_OPTIONS[key] if given is None else given
        fields[key] = f"simulation.{key}" if from_case else f"{prefix}{key}"
    grids = parse_grid_list(values["grid"], fields["grid"])
    count = whole_number(fields["realizations"], values["realizations"], 1, max_realizations, limit_note)
    chosen = seed_number(fields["seed"], values["seed"])
    cores = None if workers is None else whole_number(f"{prefix}workers", workers, 0, max_workers,
                                                      _WORKERS_NOTE + limit_note)
    from_case = device is None and "device" in defaults
    device_field = "simulation.device" if from_case else f"{prefix}device"
    where = device_name(device_field, defaults["device"] if from_case else "cpu" if device is None else device)
    return SimulationOptions(grids=grids, realizations=count, seed=chosen, workers=cores, grid_field=fields["grid"],
                             device=where, gpus=numerics.device_count(where, device_field))
