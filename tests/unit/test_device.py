"""``device = "cuda"`` where it cannot run, and the choices made for a GPU run, checked without a GPU.

CuPy is replaced in ``sys.modules``: by None (not installed: the import fails) or by a stand-in whose CUDA
runtime reports no GPU or little free memory. Every refusal is one line naming the option, before any work.
"""

from __future__ import annotations

import sys
from dataclasses import replace
from types import SimpleNamespace

import numpy as np
import pytest

from sealeak.cases import example_path, load_cases, simulate
from sealeak.cases.ensemble import default_workers, gpu_of_worker, run_workers
from sealeak.cases.options import simulation_options
from sealeak.cli import main
from sealeak.errors import InputError, ResourceError
from sealeak.numerics import (
    array_namespace_for,
    contact_memory_bytes,
    device_count,
    device_memory_bytes,
    flow_memory_bytes,
    require_device_memory,
    solve_flow,
    synthesis_memory_bytes,
)
from tests.cli_errors import one_line_error


def _fake_cupy(gpus: int, free: float = 80e9, pooled: int | None = None) -> SimpleNamespace:
    """A stand-in for CuPy: ``gpus`` GPUs, ``free`` bytes free by the driver, ``pooled`` unused in its pool (None: no pool)."""
    runtime = SimpleNamespace(getDeviceCount=lambda: gpus, memGetInfo=lambda: (int(free), int(2 * free)))
    fake = SimpleNamespace(cuda=SimpleNamespace(runtime=runtime))
    if pooled is not None:
        fake.get_default_memory_pool = lambda: SimpleNamespace(free_bytes=lambda: pooled)
    return fake


@pytest.fixture
def no_cupy(monkeypatch):
    monkeypatch.setitem(sys.modules, "cupy", None)  # `import cupy` raises ImportError


@pytest.fixture
def case():
    (c,) = load_cases(example_path("reference-experiment"))
    return replace(c, squeeze_pressure=np.array([1e5]))


def test_cpu_needs_nothing_and_is_numpy(no_cupy):
    assert array_namespace_for("cpu").asarray([1.0]).__class__ is np.ndarray
    assert device_count("cpu") == 0
    require_device_memory(10**18, "anything", "cpu")  # the host's memory is checked elsewhere


@pytest.mark.parametrize("value", ["gpu", "CUDA", 1, None])
def test_an_unknown_device_is_refused_naming_the_field(value):
    with pytest.raises(InputError) as err:
        array_namespace_for(value, "--device")  # type: ignore[arg-type]
    assert err.value.field == "--device" and "'cpu', 'cuda'" in str(err.value)


def test_cuda_without_cupy_names_the_option_and_the_missing_library(no_cupy):
    with pytest.raises(InputError) as err:
        simulation_options(device="cuda")
    assert err.value.field == "--device" and err.value.value == "cuda" and "CuPy" in str(err.value)
    with pytest.raises(InputError) as err:
        simulation_options(defaults={"device": "cuda"})
    assert err.value.field == "simulation.device"


def test_cuda_with_cupy_but_no_gpu_says_so(monkeypatch):
    monkeypatch.setitem(sys.modules, "cupy", _fake_cupy(0))
    with pytest.raises(InputError, match="sees none") as err:
        simulation_options(device="cuda")
    assert err.value.field == "--device"
    monkeypatch.setitem(sys.modules, "cupy", _fake_cupy(3))
    assert simulation_options(device="cuda").gpus == 3


def test_the_python_api_refuses_before_any_work(case, no_cupy, tmp_path):
    with pytest.raises(InputError) as err:
        simulate(case, grid=32, realizations=1, seed=0, threshold=False, device="cuda", fields_dir=tmp_path / "f")
    assert err.value.field == "device"
    assert not (tmp_path / "f").exists()


def test_gpu_memory_is_checked_against_the_free_memory_before_any_work(case, monkeypatch, tmp_path):
    need = device_memory_bytes(64)
    monkeypatch.setitem(sys.modules, "cupy", _fake_cupy(1, free=need - 1))
    with pytest.raises(ResourceError, match="GPU memory"):
        simulate(case, grid=64, realizations=1, seed=0, threshold=False, device="cuda", fields_dir=tmp_path / "f")
    assert not (tmp_path / "f").exists()
    monkeypatch.setitem(sys.modules, "cupy", _fake_cupy(1, free=need))
    require_device_memory(need, "the 64x64 synthesis and contact", "cuda")


def test_a_run_whose_flow_would_not_fit_is_refused_before_its_first_contact(case, monkeypatch, tmp_path):
    contact, flow = device_memory_bytes(64), flow_memory_bytes(64, "amg")
    assert flow > contact  # at this grid the flow needs more than the synthesis and contact
    monkeypatch.setitem(sys.modules, "cupy", _fake_cupy(1, free=(contact + flow) // 2))
    with pytest.raises(ResourceError, match="synthesis, contact and flow"):
        simulate(case, grid=64, realizations=1, seed=0, threshold=False, device="cuda", fields_dir=tmp_path / "f")
    assert not (tmp_path / "f").exists()


def test_a_flow_on_the_gpu_checks_its_memory_before_any_work(monkeypatch):
    gap = np.full((64, 64), 1e-6)
    monkeypatch.setitem(sys.modules, "cupy", _fake_cupy(1, free=flow_memory_bytes(64, "amg") - 1))
    with pytest.raises(ResourceError, match=r"64x64 flow problem \(amg\) needs about .* GiB of GPU memory"):
        solve_flow(gap, 1e-3, 1e-3, 1e5, method="amg", device="cuda")
    monkeypatch.setitem(sys.modules, "cupy", None)
    with pytest.raises(InputError, match="CuPy") as err:
        solve_flow(gap, 1e-3, 1e-3, 1e5, method="amg", device="cuda")
    assert err.value.field == "device"


def test_the_pools_unused_blocks_count_as_free(monkeypatch):
    monkeypatch.setitem(sys.modules, "cupy", _fake_cupy(1, free=1000, pooled=500))
    require_device_memory(1500, "the test", "cuda")
    with pytest.raises(ResourceError, match="GPU memory"):
        require_device_memory(1501, "the test", "cuda")


def test_the_gpu_estimate_holds_a_contact_solve_and_grows_as_the_cells():
    for n in (256, 1024):
        assert device_memory_bytes(n) > contact_memory_bytes(n) > synthesis_memory_bytes(n)
    assert device_memory_bytes(2048) / device_memory_bytes(1024) == pytest.approx(4.0, rel=0.01)


@pytest.mark.parametrize("how", ["missing", "no-gpu"])
def test_simulate_device_cuda_is_one_line_exit_2_nothing_written(how, monkeypatch, tmp_path, capsys):
    monkeypatch.setitem(sys.modules, "cupy", None if how == "missing" else _fake_cupy(0))
    out = tmp_path / "r.json"
    code = main(["simulate", "--example", "reference-experiment", "--grid", "32", "--realizations", "1",
                 "--json", str(out), "--fields", str(tmp_path / "f"), "--device", "cuda", "-q"])
    assert code == 2
    one_line_error(capsys, "--device", "cuda", "CuPy")
    assert not out.exists() and not (tmp_path / "f").exists()


def test_a_case_file_names_its_device_key(tmp_path, capsys, no_cupy):
    text = example_path("reference-experiment").read_text()
    (tmp_path / "bad.toml").write_text(text + '\n[simulation]\ndevice = "gpu"\n')
    assert main(["simulate", str(tmp_path / "bad.toml"), "-q"]) == 2
    one_line_error(capsys, "simulation.device", "gpu")
    (tmp_path / "gpu.toml").write_text(text + '\n[simulation]\ndevice = "cuda"\n')
    (case,) = load_cases(tmp_path / "gpu.toml")  # a case may name a GPU the machine reading it lacks
    assert case.simulation == {"device": "cuda"}
    assert main(["simulate", str(tmp_path / "gpu.toml"), "--json", str(tmp_path / "r.json"), "-q"]) == 2
    one_line_error(capsys, "simulation.device", "CuPy")
    assert not (tmp_path / "r.json").exists()


def test_workers_one_per_gpu():
    assert run_workers(None, 1024, "cpu", 0) == default_workers(1024)
    assert run_workers(3, 64, "cpu", 0) == 3
    assert run_workers(None, 64, "cuda", 4) == 4  # one per GPU whatever the grid
    assert run_workers(2, 4096, "cuda", 4) == 2  # --workers may lower it
    assert run_workers(8, 4096, "cuda", 4) == 4  # never two workers on one GPU
    assert run_workers(None, 4096, "cuda", 1) == 0  # one GPU: this process, no cluster
    assert [gpu_of_worker(i, 2, None) for i in range(2)] == ["0", "1"]
    assert [gpu_of_worker(i, 2, "3, 5") for i in range(3)] == ["3", "5", "3"]  # the cards this process was given
