"""Benchmark of the fields a task store keeps (``simulate --store DIR --store-fields``): size and time.

Usage: python benchmarks/bench_fieldstore.py [N]   (default N = 512)

One realisation of the bundled reference-experiment case at three squeeze pressures (20, 80, 300 kPa),
seed 1: the height map and the gap and contact-pressure maps of each pressure, as a sweep task keeps
them. Times, best of 3: writing them as one task's Zarr group (zstd, chunks of one map, renamed in:
``sealeak.io.fieldstore.TaskFields``), checking them against their SHA-256 as a resumed run does
(``fields_intact``), and, for comparison, writing the same maps into one HDF5 file with h5py (gzip level
4, without and with the shuffle filter; skipped if h5py is missing). Sizes are the bytes on disk.
"""

from __future__ import annotations

import os
import shutil
import sys
import tempfile
import time
from dataclasses import replace
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "src"))

from sealeak import numerics  # noqa: E402
from sealeak.cases import example_path, load_cases  # noqa: E402
from sealeak.cases.simulation import resolved_spectrum_cut  # noqa: E402
from sealeak.io.fieldstore import TaskFields, create_field_store, fields_intact  # noqa: E402

PRESSURES = np.array([2e4, 8e4, 3e5])


def size_on_disk(path: Path) -> int:
    if path.is_file():
        return path.stat().st_size
    return sum(p.stat().st_size for p in path.rglob("*") if p.is_file())


def best(fn, repeat: int = 3) -> float:
    times = []
    for _ in range(repeat):
        t = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t)
    return min(times)


def main() -> None:
    n = int(sys.argv[1]) if len(sys.argv) > 1 else 512
    (case,) = load_cases(example_path("reference-experiment"))
    case = replace(case, squeeze_pressure=PRESSURES)
    size = case.square_side
    spectrum = case.spectrum
    if spectrum.q_max > resolved_spectrum_cut(n, size):
        spectrum = spectrum.truncated(None, resolved_spectrum_cut(n, size))
    h = numerics.synthesize(spectrum, n, size, seed=np.random.default_rng([1, 0]))
    results = numerics.solve_contact_sweep(h, size, case.e_star, PRESSURES)
    gap = np.stack([r.gap for r in results])
    pressure = np.stack([r.pressure for r in results])
    raw = h.nbytes + gap.nbytes + pressure.nbytes
    print(f"N = {n}, {PRESSURES.size} pressures: {raw / 1e6:.2f} MB of float64 maps")

    work = Path(tempfile.mkdtemp(prefix="bench-fieldstore-"))
    try:
        create_field_store(work)
        record: dict = {}

        def write_zarr() -> None:
            fields = TaskFields(work, "r0", grid=n, size=size, period=size, load_name="squeeze_pressure",
                                loads=PRESSURES, load_unit="Pa", attributes={"grid": n})
            fields.put_height(h)
            for i in range(PRESSURES.size):
                fields.put(i, gap[i], pressure[i])
            record.update(fields.commit())

        t_write = best(write_zarr)
        t_check = best(lambda: fields_intact(work, record))
        zsize = size_on_disk(work / "fields.zarr" / "r0")
        print(f"zarr (zstd):           {zsize / 1e6:7.2f} MB ({100 * zsize / raw:.0f} %), write {t_write:.3f} s, "
              f"checksum check {t_check:.3f} s")
        try:
            import h5py
        except ImportError:
            print("h5py not installed: no HDF5 comparison")
            return
        for shuffle in (False, True):
            path = work / f"fields-{shuffle}.h5"

            def write_hdf5() -> None:
                with h5py.File(path, "w") as f:
                    f.create_dataset("height", data=h, chunks=(min(n, 1024),) * 2, compression="gzip",
                                     compression_opts=4, shuffle=shuffle)
                    for name, a in (("gap", gap), ("pressure", pressure)):
                        f.create_dataset(name, data=a, chunks=(1,) + (min(n, 1024),) * 2, compression="gzip",
                                         compression_opts=4, shuffle=shuffle)

            t = best(write_hdf5)
            hsize = os.path.getsize(path)
            print(f"hdf5 (gzip 4{', shuffle' if shuffle else ''}):{' ' * (1 if shuffle else 10)}{hsize / 1e6:7.2f} MB "
                  f"({100 * hsize / raw:.0f} %), write {t:.3f} s")
    finally:
        shutil.rmtree(work, ignore_errors=True)


if __name__ == "__main__":
    main()
