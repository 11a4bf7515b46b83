#!/usr/bin/env bash
# The sanitizer job (docs/testing.md): builds vsculpt and the test executables with
# AddressSanitizer + UndefinedBehaviorSanitizer (-DVSCULPT_SANITIZE=ON) into build-asan/ and
# runs the core, sketch, studio, devices, app and render tests plus the end-to-end cli.*
# tests there. Fails on a failing test or on any sanitizer report, including one from a test
# whose verdict ignores the exit code (PASS_REGULAR_EXPRESSION, WILL_FAIL).
#
# Environment:
#   VSCULPT_SANITIZE_BUILD_DIR  build folder (default build-asan)
#   VSCULPT_SANITIZE_LABELS     ctest label regex (default core|sketch|studio|devices|app|render|xr;
#                               a regex, so app also selects app-gl, render also render-gl)
#   VSCULPT_SANITIZE_CLI        1 (default): also run the unlabeled cli.* tests; 0: don't
#   VSCULPT_SANITIZE_TARGETS    build targets (default: vsculpt + the test executables below)
#   VSCULPT_JOBS                build and ctest parallelism (default nproc)
# Does not install dependencies: scripts/test.sh does that first.
set -euo pipefail
cd "$(dirname "$0")/.."
ROOT="$PWD"
BUILD_DIR="${VSCULPT_SANITIZE_BUILD_DIR:-build-asan}"
JOBS="${VSCULPT_JOBS:-$(nproc)}"
LABELS="${VSCULPT_SANITIZE_LABELS:-core|sketch|studio|devices|app|render|xr}"
RUN_CLI="${VSCULPT_SANITIZE_CLI:-1}"
# vsculpt itself: app/studio tests spawn it, the cli.* tests run it. Everything with a test
# label the regex above selects; not vsculpt_bench (VSCULPT_SANITIZE turns it off).
default_targets=(
  vsculpt
  vsculpt_core_tests
  vsculpt_studio_tests
  vsculpt_app_tests vsculpt_app_gl_tests vsculpt_app_device_tests
  vsculpt_render_tests vsculpt_render_gl_tests
  vsculpt_devices_tests vsculpt_devices_decoder_tests vsculpt_devices_transport_tests
  vsculpt_devices_imu_tests
  vsculpt_sketch_mesh_tests vsculpt_sketch_cleanup_tests vsculpt_sketch_subdivision_tests
  vsculpt_sketch_teddy_tests vsculpt_sketch_la_tests vsculpt_sketch_solid_tests
  vsculpt_xr_tests vsculpt_xr_test_runtime
)
read -r -a targets <<< "${VSCULPT_SANITIZE_TARGETS:-${default_targets[*]}}"

# verify_asan_link_order=0: the device transport tests run under umockdev-wrapper, which
# LD_PRELOADs libumockdev-preload ahead of the ASan runtime (tests/devices/CMakeLists.txt).
# Known leaks in uninstrumented system libraries (Mesa/llvmpipe, GLFW, X11, ...) are
# suppressed by library name in tests/sanitizers/lsan.supp; never project code.
export ASAN_OPTIONS="detect_leaks=1:verify_asan_link_order=0:halt_on_error=1:abort_on_error=0"
export LSAN_OPTIONS="suppressions=$ROOT/tests/sanitizers/lsan.supp:print_suppressions=0"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"

generator=()
if command -v ninja >/dev/null 2>&1; then generator=(-G Ninja); fi
echo "== sanitize: configure + build $BUILD_DIR (ASan+UBSan, -O1 -g1, $JOBS jobs)"
SECONDS=0
# The build runs the test executables too (gtest_discover_tests lists their tests), so the
# sanitizer options above already apply here.
cmake -S . -B "$BUILD_DIR" "${generator[@]}" -DCMAKE_BUILD_TYPE=Release -DVSCULPT_SANITIZE=ON \
  -DVSCULPT_BUILD_BENCH=OFF -DVSCULPT_BUILD_TESTS=ON >/dev/null
cmake --build "$BUILD_DIR" --parallel "$JOBS" --target "${targets[@]}"
build_s=$SECONDS

# Mesa's GLX dlcloses its DRI driver when the display closes; with the driver unmapped, the
# memory it still holds looks leaked and its stack can be neither named nor suppressed.
# tests/sanitizers/keep_loaded.c makes dlclose keep libraries loaded (docs/testing.md).
cc -shared -fPIC -O2 -o "$BUILD_DIR/libvsculpt_keep_loaded.so" tests/sanitizers/keep_loaded.c
export LD_PRELOAD="$ROOT/$BUILD_DIR/libvsculpt_keep_loaded.so${LD_PRELOAD:+:$LD_PRELOAD}"

# Mesa's shader disk cache runs a writer thread that is torn down at exit, and LeakSanitizer's
# exit-time check crashed more often with it (the GL tests, ctest -L 'app-gl|render-gl' -j3,
# 12 rounds each: 5 crashes with the cache, 0 without; docs/testing.md). The cache only speeds
# up shader compiles across runs; the leak check is unchanged.
export MESA_SHADER_CACHE_DISABLE=true

# ctest judges some tests by their output only (PASS_REGULAR_EXPRESSION ignores the exit
# code, WILL_FAIL inverts it), so a sanitizer report could pass unnoticed: every test's
# output (Testing/Temporary/LastTest.log) is searched for reports after each run.
LOG_DIR="$BUILD_DIR/sanitizer-logs"
rm -rf "$LOG_DIR" && mkdir -p "$LOG_DIR"
report_re='SUMMARY: (AddressSanitizer|LeakSanitizer|UndefinedBehaviorSanitizer)|runtime error:|Sanitizer has encountered a fatal error'
# LeakSanitizer's own crash at exit ("Tracer caught signal 11", then this line): its scan of
# the threads' memory died before it could look for leaks, so the run says nothing about leaks
# either way (docs/testing.md). A test whose only report is this is run again, up to twice;
# it passes if a rerun passes with no report at all. Any other report fails at once.
tracer_re='LeakSanitizer has encountered a fatal error'
runs=0
# "test name<TAB>report line" for every report line in a LastTest.log.
reports_in() {
  awk -v re="$report_re" '
    /^[0-9]+\/[0-9]+ Test: / { name = $0; sub(/^[0-9]+\/[0-9]+ Test: /, "", name) }
    $0 ~ re { print name "\t" $0 }
  ' "$1"
}
run_ctest() {
  runs=$((runs + 1))
  local rc=0 out="$LOG_DIR/run$runs.out"
  ctest --test-dir "$BUILD_DIR" --output-on-failure --parallel "$JOBS" --timeout 900 \
        --no-tests=error "$@" 2>&1 | tee "$out" || rc=1
  cp "$BUILD_DIR/Testing/Temporary/LastTest.log" "$LOG_DIR/run$runs.log"
  reports_in "$LOG_DIR/run$runs.log" > "$LOG_DIR/run$runs.reports"
  if [ -s "$LOG_DIR/run$runs.reports" ]; then
    echo "== sanitize: sanitizer reports (full output in $LOG_DIR/run$runs.log):"
    awk -F '\t' '{ if (!($1 in seen)) { print "  " $1; seen[$1] = 1 } print "      " $2 }' \
      "$LOG_DIR/run$runs.reports"
  fi
  [ $rc = 0 ] && [ ! -s "$LOG_DIR/run$runs.reports" ] && return 0
  # What failed: the tests ctest lists as failed and the tests with a report.
  local failed tracer_only t settled k name_re log rerun_rc
  failed=$( { awk '/^The following tests FAILED:/ { f = 1; next }
                   f && /^[[:space:]]+[0-9]+ - / { sub(/^[[:space:]]+[0-9]+ - /, "");
                                                   sub(/ \([^)]*\)$/, ""); print; next }
                   f { f = 0 }' "$out"
              cut -f1 "$LOG_DIR/run$runs.reports"; } | sort -u)
  [ -n "$failed" ] || return 1  # ctest failed without naming a test: keep its verdict
  # Those whose only report is the tracer crash.
  tracer_only=$(awk -F '\t' -v tre="$tracer_re" '
      { if ($2 ~ tre) crash[$1] = 1; else other[$1] = 1 }
      END { for (t in crash) if (!(t in other)) print t }' "$LOG_DIR/run$runs.reports" | sort)
  rc=0
  while IFS= read -r t; do
    if ! grep -qxF -- "$t" <<< "$tracer_only"; then rc=1; continue; fi
    settled=0
    name_re=$(printf '%s' "$t" | sed 's/[][\.*^$+?(){}|\\/]/\\&/g')
    for k in 1 2; do
      log="$LOG_DIR/run$runs.rerun$k.log"
      echo "== sanitize: $t: LeakSanitizer crashed at exit (no leak report); rerun $k"
      rerun_rc=0
      ctest --test-dir "$BUILD_DIR" --output-on-failure --timeout 900 --no-tests=error \
            -R "^${name_re}\$" || rerun_rc=1
      cp "$BUILD_DIR/Testing/Temporary/LastTest.log" "$log"
      if [ $rerun_rc = 0 ] && [ -z "$(reports_in "$log")" ]; then settled=1; break; fi
      reports_in "$log" | cut -f2 | sed 's/^/      /'
    done
    if [ $settled = 1 ]; then
      echo "== sanitize: $t: rerun $k passed with no report"
    else
      rc=1
    fi
  done <<< "$failed"
  return $rc
}

echo "== sanitize: ctest -L '$LABELS'$([ "$RUN_CLI" = 1 ] && echo " and -R '^cli\\.'")"
SECONDS=0
status=0
run_ctest -L "$LABELS" || status=1
if [ "$RUN_CLI" = 1 ]; then
  run_ctest -R '^cli\.' || status=1
fi
test_s=$SECONDS

echo "== sanitize: build ${build_s} s, tests ${test_s} s, $([ $status = 0 ] && echo passed || echo FAILED)"
exit $status
