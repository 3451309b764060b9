"""`sealeak surface analyze` on inputs a fuzzer found: damaged instrument files (copies of the real samples with
one byte changed, made in tmp_path), sizes near the ends of the doubles, an array where a size belongs, and a
map of tiny pixels. Each gives exit status 2 and one line naming the file, or a result without a warning.
"""

import importlib.util
import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

SAMPLES = Path(__file__).resolve().parents[3] / "shared" / "topography-samples"
CLI = "import sys; from sealeak.cli import main; sys.exit(main(sys.argv[1:]))"  # as in test_cli_inputs.py
needs_samples = pytest.mark.skipif(not SAMPLES.is_dir(), reason="../shared/topography-samples not present")
needs_reader = pytest.mark.skipif(importlib.util.find_spec("SurfaceTopography") is None,
                                  reason="SurfaceTopography (sealeak[formats]) not installed")


def sealeak(cwd, *argv):
    return subprocess.run([sys.executable, "-c", CLI, *argv], capture_output=True, text=True, timeout=300, cwd=cwd)


def refused(cwd, *argv):
    run = sealeak(cwd, "surface", "analyze", *argv)
    assert run.returncode == 2, run.stderr[-3000:]
    assert run.stderr.startswith("sealeak: error: ") and run.stderr.count("\n") == 1, run.stderr[-3000:]
    assert "Traceback" not in run.stderr and len(run.stderr) < 600, run.stderr
    return run.stderr


def damaged(tmp_path, sample, offset, byte):
    data = bytearray((SAMPLES / sample).read_bytes())
    data[offset] = byte
    path = tmp_path / sample
    path.write_bytes(bytes(data))
    return path.name


@needs_samples
@needs_reader
@pytest.mark.parametrize(("sample", "offset", "byte", "reason"), [("al3d-1.al3d", 621, 0x7F, "ValueError"),
                                                                  ("nc-1.nc", 27, 0, "TypeError")])
def test_an_instrument_file_with_a_damaged_header_is_refused_in_one_line(tmp_path, sample, offset, byte, reason):
    name = damaged(tmp_path, sample, offset, byte)
    message = refused(tmp_path, name)
    assert message.startswith(f"sealeak: error: {name}: cannot be read") and reason in message, message


def test_an_npz_stating_a_subnormal_size_is_refused_naming_the_entry(tmp_path):
    np.savez(tmp_path / "s.npz", heights=np.random.default_rng(0).random((8, 8)), size=np.array(5e-324),
             height_unit=np.array("m"))
    message = refused(tmp_path, "s.npz")
    assert "s.npz: array 'size'" in message and "1e-100 m and 1e+100 m" in message


def test_an_npz_size_of_a_million_values_is_refused_in_one_short_line(tmp_path):
    np.savez(tmp_path / "big.npz", heights=np.random.default_rng(0).random((8, 8)), size=np.ones((1000, 1000)),
             height_unit=np.array("m"))
    message = refused(tmp_path, "big.npz")
    assert "big.npz: array 'size'" in message and "shape (1000, 1000)" in message


@needs_samples
def test_a_map_of_tiny_pixels_is_analysed_without_a_warning_and_with_its_curvature(tmp_path):
    run = sealeak(tmp_path, "surface", "analyze", str(SAMPLES / "matrix-5.txt"), "--height-unit", "um",
                  "--size", "1e-100 m", "--json", "-")
    assert run.returncode == 0, run.stderr[-3000:]
    assert run.stderr == ""
    ref = sealeak(tmp_path, "surface", "analyze", str(SAMPLES / "matrix-5.txt"), "--height-unit", "um",
                  "--size", "1 mm", "--json", "-")
    tiny, mm = (json.loads(r.stdout) for r in (run, ref))

    def stats(doc):
        found = []

        def walk(node):
            if isinstance(node, dict):
                if "curvature_rms" in node and not isinstance(node["curvature_rms"], str):
                    found.append(node)
                for v in node.values():
                    walk(v)
            elif isinstance(node, list):
                for v in node:
                    walk(v)
        walk(doc)
        assert found
        return found[0]

    assert stats(tiny)["curvature_rms"] == pytest.approx(stats(mm)["curvature_rms"] * 1e194, rel=1e-9)
    assert stats(tiny)["slope_rms"] == pytest.approx(stats(mm)["slope_rms"] * 1e97, rel=1e-9)
