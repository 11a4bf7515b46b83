#!/usr/bin/env bash
# The GPU machine's side of docs/benchmarks.md "Renderer on a GPU": unpacks the bundle that
# scripts/gpu-bench-bundle.sh made, starts Xvfb (GLX from Mesa's software driver), and runs
# the renderer benchmarks with the NVIDIA GLX client library.
cd "$(dirname "$0")/.."
OUT=${OUT:-/tmp/out}; mkdir -p "$OUT"
DPY=${DPY:-:5}
FILTER=${FILTER:-BM_FrameDraw|BM_HeadsetFrame|BM_ChunkUpload|BM_SampleToFrame}
VENDOR=${VENDOR:-nvidia}
nvidia-smi --query-gpu=name,driver_version --format=csv,noheader 2>&1 | head -2
B=${B:-/opt/vb/b}
if [[ ! -x $B/bin/vsculpt_bench ]]; then mkdir -p "$(dirname "$B")" && tar -C "$(dirname "$B")" -xJf "${BUNDLE:-.gpu/bundle.tar.xz}"; fi
[[ -x /usr/bin/xkbcomp ]] || cp "$B/bin/xkbcomp" /usr/bin/xkbcomp
NV=$(dirname "$(find / -xdev -name 'libGLX_nvidia.so.0' 2>/dev/null | head -1)" 2>/dev/null)
[[ -n $NV && $NV != . ]] || NV=$(dirname "$(find /usr/local/nvidia /usr/lib* -name 'libGLX_nvidia.so.0' 2>/dev/null | head -1)")
echo "NVIDIA GLX in: $NV"
export LD_LIBRARY_PATH=$B/lib:$NV
LIBGL_DRIVERS_PATH=$B/dri "$B/bin/Xvfb" "$DPY" -screen 0 1920x1200x24 -nolisten tcp -fp built-ins \
    -xkbdir "$B/xkb" > "$OUT/xvfb.log" 2>&1 &
xpid=$!
sleep 3
export DISPLAY=$DPY __GLX_VENDOR_LIBRARY_NAME=$VENDOR
"$B/bin/vsculpt_bench" --benchmark_filter="$FILTER" ${BENCH_ARGS:-} 2>&1 | tee "$OUT/gpu.txt"
kill $xpid
