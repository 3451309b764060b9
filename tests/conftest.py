"""Shared fixtures: the reference case and a sweep of both models (the laboratory tests use them)."""

import os
import random
import threading
import time
from dataclasses import replace

import numpy as np
import pytest

try:  # (pytest's own module; where a release moves it, the guard below is off and the tests run as before)
    from _pytest.approx import ApproxScalar
except ImportError:  # pragma: no cover
    try:
        from _pytest.python_api import ApproxScalar
    except ImportError:
        ApproxScalar = None

from sealeak.cases import example_path, load_cases, predict, predict_effective_medium


@pytest.fixture(scope="module")
def case():
    return load_cases(example_path("reference-experiment"))[0]


@pytest.fixture(scope="module")
def sweep(case):
    """Unit-α predictions of both models over P0 = 20..400 kPa (Q spans at least three decades in both)."""
    p0 = np.geomspace(2e4, 4e5, 16)
    cj = predict(replace(case, alpha=1.0), squeeze_pressure=p0).leak_rate
    em = predict_effective_medium(case, squeeze_pressure=p0).leak_rate
    return p0, cj, em


def _no_silent_absolute_tolerance(compare):
    """pytest.approx also allows an absolute error of 1e-12 unless ``abs`` is given: more than most SI values here
    (a leak rate of 1e-11 m³/s, C(q) of 1e-30 m⁴), so such a check would pass whatever the relative error. A comparison
    whose default absolute tolerance exceeds its relative one fails instead, asking for ``abs`` (docs/development.md,
    "Tolerances")."""
    def eq(self, actual):
        expected = self.expected
        if (self.abs is None and isinstance(expected, (int, float)) and not isinstance(expected, bool)
                and expected != 0 and 1e-12 > (1e-6 if self.rel is None else self.rel) * abs(expected)):
            raise AssertionError(f"pytest.approx({expected!r}, rel={self.rel}) would pass any value within 1e-12: "
                                 "give abs (abs=0, or the scale below which a difference does not matter)")
        return compare(self, actual)
    return eq


if ApproxScalar is not None:
    ApproxScalar.__eq__ = _no_silent_absolute_tolerance(ApproxScalar.__eq__)


#: Threads a Dask client or cluster runs its event loop in (distributed's LoopRunner names them so).
_LOOP_THREAD = "IO loop"


@pytest.fixture(scope="module", autouse=True)
def _no_event_loop_left_behind():
    """Every Dask client and cluster a test module starts is closed by its end: no event-loop thread of distributed is
    left running (up to 10 s allowed for a closing loop to end; no garbage collection first, which would close a
    forgotten client here and hide it). A leaked loop broke a later
    LocalCluster in the same process once (a refused --scheduler's half-made Client, docs/architecture.md), and which
    test files share a pytest-xdist worker changes from run to run."""
    before = {t for t in threading.enumerate() if t.name == _LOOP_THREAD}
    yield
    deadline = time.monotonic() + 10.0
    left = [t for t in threading.enumerate() if t.name == _LOOP_THREAD and t not in before]
    while left and time.monotonic() < deadline:
        left[0].join(timeout=0.1)
        left = [t for t in left if t.is_alive()]
    assert not left, f"{len(left)} distributed event-loop thread(s) still running after this module: a Client or " \
                     "cluster was not closed"


def pytest_collection_modifyitems(config, items):
    """``SEALEAK_TEST_FILE_ORDER=reverse`` or ``=SEED`` (an integer) runs the test files in reverse or in a shuffled
    order (the tests of a file in their own order), to find a file that leaves state another one depends on
    (docs/development.md, "State left behind"); unset, pytest's order."""
    order = os.environ.get("SEALEAK_TEST_FILE_ORDER", "")
    if not order:
        return
    files: dict[str, list[pytest.Item]] = {}
    for item in items:
        files.setdefault(item.nodeid.split("::")[0], []).append(item)
    names = list(files)
    if order == "reverse":
        names.reverse()
    elif order.isdigit():
        random.Random(int(order)).shuffle(names)
    else:
        raise pytest.UsageError(f"SEALEAK_TEST_FILE_ORDER = {order!r}: must be 'reverse' or a whole number (a seed)")
    items[:] = [item for name in names for item in files[name]]
