"""Stopping a long computation whose client has gone (sealeak.cases.cancel): a band stops between loads, an
uncertainty band between samples, and nothing changes outside a cancellable block or while the caller stays."""

from __future__ import annotations

import contextvars
import threading
from concurrent.futures import ThreadPoolExecutor

import numpy as np
import pytest

import sealeak.cases.band as band_module
from sealeak.cases import parse_case_file, run_case
from sealeak.cases.cancel import Cancelled, cancellable, check, current
from sealeak.cases.uncertainty import parse_uncertain_case, propagate
from tests.casefiles import ORING


class StopAfter:
    """A ``stop`` function that answers True from its ``n``-th call on, and counts its calls."""

    def __init__(self, n: int) -> None:
        self.n = n
        self.calls = 0

    def __call__(self) -> bool:
        self.calls += 1
        return self.calls >= self.n


def test_check_raises_only_inside_a_block_whose_caller_asks_to_stop():
    check()  # no block: never
    with cancellable(lambda: False):
        check()
        with cancellable(lambda: True):
            with pytest.raises(Cancelled):
                check()
        check()  # the inner block's function is gone with it
    assert current() is None


def test_the_stop_function_follows_the_context_into_a_worker_thread():
    """The web app's computations run on worker threads that copy the request's context (as anyio's do)."""
    with cancellable(lambda: True), ThreadPoolExecutor(1) as pool:
        copied = pool.submit(contextvars.copy_context().run, check)
        bare = pool.submit(check)  # a thread started without the context: not stopped
        with pytest.raises(Cancelled):
            copied.result()
        assert bare.result() is None


def test_a_band_stops_between_loads_and_runs_unchanged_while_the_caller_stays(monkeypatch):
    (case,) = parse_case_file(ORING).cases
    loads = len(case.band.loads)
    assert loads == 3
    stays = StopAfter(10**9)
    with cancellable(stays):
        kept = run_case(case)
    assert stays.calls == loads  # one look per load
    plain = run_case(case)
    assert np.array_equal(kept.band.critical_junction.leak_rate, plain.band.critical_junction.leak_rate, equal_nan=True)
    computed: list[int] = []
    contact = band_module.persson_contact
    monkeypatch.setattr(band_module, "persson_contact", lambda c, q0: computed.append(1) or contact(c, q0))
    with cancellable(StopAfter(2)), pytest.raises(Cancelled):
        run_case(case)
    assert len(computed) == 1  # the first load ran, the second was not started


def test_an_uncertainty_band_stops_between_samples():
    study = parse_uncertain_case(ORING.replace('h_rms = "1.5 um"', 'h_rms = "1.5 um ± 10 %"'))
    steps: list[int] = []
    stop = threading.Event()

    def progress(n: int) -> None:
        steps.append(n)
        if len(steps) == 2:
            stop.set()  # the client leaves during the second sample

    with cancellable(stop.is_set), pytest.raises(Cancelled):
        propagate(study, 8, seed=0, progress=progress)
    assert steps == [1, 1]  # the third sample was not started
