"""A Ctrl-C while a field file is written is held back until the file is whole (cases/pipeline.py)."""

from __future__ import annotations

import os
import signal
import threading
from types import SimpleNamespace

import numpy as np
import pytest

from sealeak.cases import pipeline


@pytest.fixture
def python_sigint():
    """Python's own SIGINT handler, as in an interactive ``sealeak`` (a background job ignores SIGINT)."""
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    yield
    signal.signal(signal.SIGINT, previous)


def test_a_ctrl_c_during_a_field_write_waits_for_the_whole_file(tmp_path, monkeypatch, python_sigint):
    spec = SimpleNamespace(fields_stage=str(tmp_path), fields_target=None)
    real = np.savez_compressed
    gap = np.arange(4096.0).reshape(64, 64)

    def interrupted(fh, **arrays):
        os.kill(os.getpid(), signal.SIGINT)  # Ctrl-C arrives before the file is written
        real(fh, **arrays)

    monkeypatch.setattr(pipeline.np, "savez_compressed", interrupted)
    with pytest.raises(KeyboardInterrupt):
        pipeline._write_fields(spec, "r0-p0.npz", gap=gap, pressure=-gap)
    with np.load(tmp_path / "r0-p0.npz") as z:  # the whole file, then the interrupt
        assert np.array_equal(z["gap"], gap) and np.array_equal(z["pressure"], -gap)
    assert signal.getsignal(signal.SIGINT) is signal.default_int_handler  # the handler is back


def test_without_a_ctrl_c_nothing_is_raised_and_off_the_main_thread_nothing_changes(tmp_path, python_sigint):
    spec = SimpleNamespace(fields_stage=str(tmp_path), fields_target=None)
    pipeline._write_fields(spec, "a.npz", gap=np.ones(3))
    seen = []

    def in_a_thread():
        with pipeline._interrupt_after():
            seen.append(signal.getsignal(signal.SIGINT))

    t = threading.Thread(target=in_a_thread)
    t.start()
    t.join()
    assert seen == [signal.default_int_handler] and (tmp_path / "a.npz").exists()


def test_a_ctrl_c_held_back_is_not_lost_when_the_write_then_fails(tmp_path, monkeypatch, python_sigint):
    spec = SimpleNamespace(fields_stage=str(tmp_path), fields_target=None)

    def failing(fh, **arrays):
        os.kill(os.getpid(), signal.SIGINT)
        raise OSError(28, "No space left on device")

    monkeypatch.setattr(pipeline.np, "savez_compressed", failing)
    with pytest.raises(KeyboardInterrupt):
        pipeline._write_fields(spec, "r0-p0.npz", gap=np.ones(3))
