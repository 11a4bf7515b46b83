#!/usr/bin/env bash
# Every test in one command: install dependencies, build, run the whole ctest suite, then the
# sanitizer job (scripts/sanitize.sh: ASan+UBSan build in build-asan/, core, sketch, studio,
# devices, app, render and cli tests). VSCULPT_SKIP_SANITIZE=1 skips the sanitizer job.
# Fails if either fails; both run even if the first one fails.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
bash scripts/build.sh
BUILD_DIR="${VSCULPT_BUILD_DIR:-build}"
FAILED_LOG="$BUILD_DIR/Testing/Temporary/LastTestsFailed.log"
rm -f "$FAILED_LOG"  # ctest leaves the last failing run's list when every test passes
status=0
release=0
(cd "$BUILD_DIR" && ctest --output-on-failure --parallel "$(nproc)" --timeout 900) || release=$?
status=$release
if [ "${VSCULPT_SKIP_SANITIZE:-0}" = 1 ]; then
  echo "== VSCULPT_SKIP_SANITIZE=1: sanitizer job skipped"
else
  bash scripts/sanitize.sh || status=$((status ? status : $?))
fi
# The sanitizer job prints for half an hour after the Release run, so a log cut to its tail
# would not show which Release test failed: say it again last, with the test's output, and
# whether it fails again run alone.
if [ "$release" != 0 ] && [ -s "$FAILED_LOG" ]; then
  echo "== Release tests that failed (ctest exit $release):"
  cat "$FAILED_LOG"
  cp "$BUILD_DIR/Testing/Temporary/LastTest.log" "$BUILD_DIR/Testing/release-run.log"  # a rerun overwrites it
  failed=$(cat "$FAILED_LOG")
  while IFS=: read -r number name; do
    echo "== $name: its output in the Release run (last 80 lines)"
    awk -v start="Testing: $name" -v stop="\"$name\" end time" \
      'index($0, start) { on = 1 } on { print } on && index($0, stop) { exit }' \
      "$BUILD_DIR/Testing/release-run.log" | tail -n 80
    echo "== $name: run again alone"
    (cd "$BUILD_DIR" && ctest -I "$number,$number" --timeout 900 2>&1 | grep -E "Test +#|tests passed") ||
      true
  done <<< "$failed"
fi
exit "$status"
