#!/usr/bin/env bash
# Every GPU check of docs/performance.md#gpu in one run, on a machine with an NVIDIA GPU where sealeak and its gpu
# and test extras import (pip install -e '.[gpu,test]'): the machine, the GPU tests, then bench_gpu.py's tables.
# Each step writes its own file in FOLDER (default out/gpu-checks) as it runs, so a run cut short keeps what it
# finished; a failed step does not stop the next.
#
# Usage: bash benchmarks/gpu_checks.sh [FOLDER] [quick|full]     (PYTHON=... picks the interpreter)
set -u -o pipefail
dir=${1:-out/gpu-checks}
mode=${2:-full}
py=${PYTHON:-python3}
export PYTHONUNBUFFERED=1
mkdir -p "$dir"
step() {  # step NAME COMMAND...: run, keep its output in FOLDER/NAME.txt, say how long it took
    local name=$1 t0=$SECONDS
    shift
    echo "== $name: $*"
    "$@" 2>&1 | tee "$dir/$name.txt"
    echo "== $name: exit ${PIPESTATUS[0]}, $((SECONDS - t0)) s" | tee -a "$dir/$name.txt"
}
step machine bash -c "date -u; nvidia-smi --query-gpu=name,driver_version,memory.total --format=csv; nproc; \
$py -c 'import numpy, scipy, cupy; print(\"numpy\", numpy.__version__, \"scipy\", scipy.__version__, \"cupy\", cupy.__version__)'"
step tests "$py" -m pytest -q -p no:cacheprovider tests/unit/test_gpu.py tests/unit/test_flow_cycle.py \
    tests/unit/test_device.py tests/unit/test_array_api.py
step quick "$py" benchmarks/bench_gpu.py --quick --sections contact,flow
if [ "$mode" = full ]; then
    step contact "$py" benchmarks/bench_gpu.py 2048 4096 8192 --cpu-max 2048 --sections contact
    step flow "$py" benchmarks/bench_gpu.py --sections flow --flow 2048,4096 --jacobi-max 2048
    step simulate "$py" benchmarks/bench_gpu.py 1024 --sections simulate
fi
