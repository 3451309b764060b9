"""A prediction whose every client has gone stops (it held a computing slot for minutes, for nobody); one that
another request still waits for goes on. Through PredictionCache with stand-in clients, and through a real server
whose client closes its connection."""

from __future__ import annotations

import socket
import threading
import time
import types
import warnings

import pytest

pytest.importorskip("fastapi", reason="the web extra (sealeak[web]) is not installed")
with warnings.catch_warnings():  # starlette's TestClient on httpx 0.28 warns that httpx2 exists
    warnings.simplefilter("ignore")
    import uvicorn

import sealeak.web.casework as casework
import sealeak.web.server as server_module
from sealeak.cases import cancel
from sealeak.cases import run_case as real_run_case
from sealeak.web import WebConfig, create_app
from sealeak.web.casework import PredictionCache
from tests.casefiles import BASE, ORING


@pytest.fixture
def held(monkeypatch):
    """run_case held until ``release`` is set (looking every 10 ms whether to stop): (release, started)."""
    release, started = threading.Event(), threading.Event()

    def slow(case):
        started.set()
        while not release.wait(0.01):
            cancel.check()
        return real_run_case(case)

    monkeypatch.setattr(casework, "run_case", slow)
    return release, started


def _client(cache: PredictionCache, tmp_path, gone: threading.Event, out: dict[str, object], name: str) -> threading.Thread:
    def run() -> None:
        with cancel.cancellable(gone.is_set):
            try:
                out[name] = cache.predict(BASE.encode(), "case.toml", tmp_path)
            except cancel.Cancelled as exc:
                out[name] = exc
    thread = threading.Thread(target=run)
    thread.start()
    return thread


def _until(condition, what: str, timeout: float = 20.0) -> None:
    """Wait until ``condition()`` holds (the threads' order observed, not guessed from a sleep)."""
    deadline = time.monotonic() + timeout
    while not condition():
        assert time.monotonic() < deadline, f"not reached in {timeout} s: {what}"
        time.sleep(0.01)


def _waiting(cache: PredictionCache, n: int) -> bool:
    """Whether ``n`` requests wait for the one computation running."""
    with cache._lock:
        return [len(c) for c in cache._clients.values()] == [n]


def _two_clients(cache: PredictionCache, tmp_path, started: threading.Event):
    """Client a computes the case, then client b asks for the same and waits for a's computation:
    (a's and b's departure, their answers, their threads)."""
    gone_a, gone_b, out = threading.Event(), threading.Event(), {}
    a = _client(cache, tmp_path, gone_a, out, "a")
    assert started.wait(10)
    b = _client(cache, tmp_path, gone_b, out, "b")
    _until(lambda: _waiting(cache, 2), "b waits for a's computation")
    return gone_a, gone_b, out, a, b


def test_a_prediction_goes_on_while_one_of_its_clients_stays(held, tmp_path):
    release, started = held
    cache = PredictionCache(computing=1)
    gone_a, gone_b, out, a, b = _two_clients(cache, tmp_path, started)
    gone_a.set()  # a's client leaves; b's stays
    time.sleep(0.3)  # (a computation looks every 10 ms whether to stop: it must not)
    release.set()
    a.join(30)
    b.join(30)
    assert out["a"] is out["b"]  # one computation, not stopped, answered to both
    assert len(cache) == 1


def test_a_prediction_nobody_waits_for_stops_and_frees_its_slot(held, tmp_path):
    release, started = held
    cache = PredictionCache(computing=1)
    gone_a, gone_b, out, a, b = _two_clients(cache, tmp_path, started)
    gone_a.set()
    gone_b.set()
    a.join(10)
    b.join(10)
    assert not a.is_alive() and not b.is_alive()  # stopped without the release
    assert isinstance(out["a"], cancel.Cancelled) and isinstance(out["b"], cancel.Cancelled)
    assert len(cache) == 0 and not cache._running and not cache._clients
    release.set()
    assert cache.predict(BASE.encode(), "case.toml", tmp_path).results  # the slot is free again


def test_a_request_waiting_for_a_slot_stops_waiting_when_its_client_leaves(held, tmp_path):
    release, started = held
    cache = PredictionCache(computing=1, wait=60.0)
    gone_a, gone_c, out = threading.Event(), threading.Event(), {}
    a = _client(cache, tmp_path, gone_a, out, "a")
    assert started.wait(10)
    other = threading.Thread(target=lambda: out.update(c=_other(cache, tmp_path, gone_c)))
    other.start()
    _until(lambda: cache._waiting == 1, "c waits for a computing slot")
    gone_c.set()
    other.join(5)
    assert not other.is_alive() and isinstance(out["c"], cancel.Cancelled)  # not after the 60 s wait
    release.set()
    a.join(30)


def _other(cache: PredictionCache, tmp_path, gone: threading.Event) -> object:
    with cancel.cancellable(gone.is_set):
        try:
            return cache.predict(BASE.replace('"44 um"', '"45 um"').encode(), "case.toml", tmp_path)
        except cancel.Cancelled as exc:
            return exc


@pytest.fixture
def served():
    """The app served as ``sealeak serve`` serves it, in a thread: (port, app)."""
    sock = server_module.listen("127.0.0.1", 0)
    port = sock.getsockname()[1]
    app = create_app(WebConfig(host="127.0.0.1", port=port))
    server = uvicorn.Server(uvicorn.Config(app, log_level="warning", http=server_module._Protocol))
    thread = threading.Thread(target=server.run, kwargs={"sockets": [sock]}, daemon=True)
    thread.start()
    deadline = time.monotonic() + 20.0
    while not server.started and time.monotonic() < deadline:
        time.sleep(0.02)
    yield port, app
    server.should_exit = True
    thread.join(20.0)
    sock.close()


def test_a_client_that_closes_its_connection_stops_its_prediction(served):
    """An O-ring band with 256 uncertainty samples (tens of seconds): the client leaves after half a second, and the server
    stops the samples within seconds, keeps nothing of them, and answers the next request."""
    port, app = served
    cache = app.state.sealeak.cache
    body = (ORING.replace('h_rms = "1.5 um"', 'h_rms = "1.5 um ± 10 %"')
            .replace('compression = ["10 %", "15 %", "30 %"]', 'compression = { start = "10 %", stop = "30 %", num = 9 }')).encode()
    head = (b"POST /api/predict HTTP/1.1\r\nHost: 127.0.0.1:%d\r\nContent-Type: application/toml\r\n"
            b"Content-Length: %d\r\n\r\n" % (port, len(body)))
    with socket.create_connection(("127.0.0.1", port), timeout=10) as s:
        s.sendall(head + body)
        deadline = time.monotonic() + 20.0
        while not cache._running and time.monotonic() < deadline:
            time.sleep(0.05)
        assert cache._running  # computing
        time.sleep(0.5)
    left = time.monotonic()
    while cache._running and time.monotonic() < left + 15.0:
        time.sleep(0.05)
    assert not cache._running, "the prediction went on after its client had gone"
    assert len(cache) == 0
    with socket.create_connection(("127.0.0.1", port), timeout=30) as s:
        s.sendall(b"GET /api/form HTTP/1.1\r\nHost: 127.0.0.1:%d\r\nConnection: close\r\n\r\n" % port)
        assert s.recv(64).startswith(b"HTTP/1.1 200")


def test_a_waiter_woken_late_after_a_failed_computation_answers_normally(monkeypatch, tmp_path):
    """A's computation fails (nothing cached); B, waiting for it, wakes late, after C has started the next computation
    under the same key: B's leaving A's list removed an entry of C's (ValueError, a 500) or C's own."""
    calls, release, started = {"n": 0}, threading.Event(), threading.Event()

    def run(case):
        calls["n"] += 1
        if calls["n"] == 1:
            started.set()
            release.wait(10)
            raise RuntimeError("A's computation fails")
        time.sleep(1.0)
        return real_run_case(case)

    class LateWake(threading.Event):  # the thread that waited is scheduled late after the set()
        def wait(self, timeout=None):
            woke = super().wait(timeout)
            if woke:
                time.sleep(0.5)
            return woke

    monkeypatch.setattr(casework, "run_case", run)
    shim = types.SimpleNamespace(**{k: getattr(threading, k) for k in dir(threading) if not k.startswith("__")})
    shim.Event = LateWake  # (casework's threading alone: the rest of the process keeps its own Event)
    monkeypatch.setattr(casework, "threading", shim)
    cache, out = PredictionCache(computing=2), {}

    def client(name):
        with cancel.cancellable(lambda: False):
            try:
                out[name] = cache.predict(BASE.encode(), "case.toml", tmp_path)
            except BaseException as exc:  # noqa: BLE001 (what a request would answer)
                out[name] = exc
    a = threading.Thread(target=client, args=("a",))
    a.start()
    assert started.wait(10)
    b = threading.Thread(target=client, args=("b",))
    b.start()
    _until(lambda: _waiting(cache, 2), "b waits for a's computation")
    release.set()
    _until(lambda: not cache._running, "A's computation has ended")  # (B wakes 0.5 s late: C starts the next)
    c = threading.Thread(target=client, args=("c",))
    c.start()
    for t in (a, b, c):
        t.join(60)
    assert isinstance(out["a"], RuntimeError)
    assert out["b"] is out["c"] and out["c"].results  # one computation after A's, answered to both
