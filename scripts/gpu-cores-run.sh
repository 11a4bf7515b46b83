#!/usr/bin/env bash
# The device machine's cores, for docs/benchmarks.md "The mesher on more cores": the mesher's
# benchmarks pinned with taskset to the first 2, 4, 8, ... of its CPUs. oneTBB and the
# asynchronous mesher size their thread pools from the affinity mask, so each run uses as
# many threads as it has CPUs, as on a machine of that size. Unpacks the bundle that
# scripts/gpu-bench-bundle.sh made, as scripts/gpu-bench-run.sh does; needs no display.
#   usage: [CORES="2 4 8 16"] [FILTER=...] [BENCH_ARGS=...] scripts/gpu-cores-run.sh
cd "$(dirname "$0")/.."
OUT=${OUT:-/tmp/out}
mkdir -p "$OUT"
B=${B:-/opt/vb/b}
if [[ ! -x $B/bin/vsculpt_bench ]]; then
    mkdir -p "$(dirname "$B")" && tar -C "$(dirname "$B")" -xJf "${BUNDLE:-.gpu/bundle.tar.xz}"
fi
export LD_LIBRARY_PATH=$B/lib
FILTER=${FILTER:-'BM_EditLatency(OpenVDB)?/skeletons:100000/zoom:(1/level:7|3/level:5|5/level:3)/(per_chunk:0/)?iterations|BM_FrameLoopAsync|BM_FullPolygonize(/threaded:1/inv_tol:0|OpenVDB)'}
echo "CPUs: $(nproc) of $(getconf _NPROCESSORS_ONLN); $(grep -m1 'model name' /proc/cpuinfo)"
lscpu 2>/dev/null | grep -E 'Thread|Core|Socket|MHz' || true
for n in ${CORES:-2 4 8 16}; do
    echo "== $n CPUs"
    VSCULPT_BENCH_PLACEMENT=swept taskset -c "0-$((n - 1))" "$B/bin/vsculpt_bench" \
        --benchmark_filter="$FILTER" ${BENCH_ARGS:-} 2>&1 | tee "$OUT/cores-$n.txt"
done
