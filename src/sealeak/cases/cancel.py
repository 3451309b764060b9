"""Stopping a long computation whose result nobody waits for any more (the web app's client has gone).

A caller runs the computation inside :func:`cancellable` with a function that answers whether to stop; the
computation calls :func:`check` between its steps (each load of a band seal, :func:`sealeak.cases.band.run_band`;
each uncertainty sample that runs a prediction of its own, :func:`sealeak.cases.uncertainty.propagate`), which
raises :class:`Cancelled` once that function answers True. Outside :func:`cancellable` :func:`check` never raises,
so the command line and the library run as before. The function is held in a context variable: it follows the
computation into the thread that runs it (anyio's worker threads, which Starlette's ``run_in_threadpool`` and
FastAPI's plain routes use, copy the caller's context; ``loop.run_in_executor`` does not), and two computations on two
threads each see their own.

Nothing a stopped computation has finished is lost: the values kept for reuse (P(u) rows, σ tables, solved bands)
stay kept, each complete; what is abandoned is the result being assembled.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator
from contextlib import contextmanager
from contextvars import ContextVar

__all__ = ["Cancelled", "cancellable", "check", "current"]

_STOP: ContextVar[Callable[[], bool] | None] = ContextVar("sealeak_stop", default=None)


class Cancelled(Exception):
    """The caller stopped the computation: nobody waits for its result (not an error of the input)."""


@contextmanager
def cancellable(stop: Callable[[], bool] | None) -> Iterator[None]:
    """Within the block, :func:`check` raises :class:`Cancelled` once ``stop()`` is True (None: never)."""
    token = _STOP.set(stop)
    try:
        yield
    finally:
        _STOP.reset(token)


def current() -> Callable[[], bool] | None:
    """The ``stop`` function of the innermost :func:`cancellable` block around the caller, or None."""
    return _STOP.get()


def check() -> None:
    """Raise :class:`Cancelled` where the caller has asked to stop (a step boundary of a long computation)."""
    stop = _STOP.get()
    if stop is not None and stop():
        raise Cancelled("the computation was stopped: nobody waits for its result")
