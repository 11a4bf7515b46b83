#!/usr/bin/env bash
# Every test in one command: install dependencies, build, run the whole ctest suite, then the
# sanitizer job (scripts/sanitize.sh: ASan+UBSan build in build-asan/, core, sketch, studio,
# devices, app, render and cli tests). VSCULPT_SKIP_SANITIZE=1 skips the sanitizer job.
# Fails if either fails; both run even if the first one fails.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
bash scripts/build.sh
status=0
(cd "${VSCULPT_BUILD_DIR:-build}" && ctest --output-on-failure --parallel "$(nproc)" --timeout 900) ||
  status=$?
if [ "${VSCULPT_SKIP_SANITIZE:-0}" = 1 ]; then
  echo "== VSCULPT_SKIP_SANITIZE=1: sanitizer job skipped"
else
  bash scripts/sanitize.sh || status=$((status ? status : $?))
fi
exit "$status"
