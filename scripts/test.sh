#!/usr/bin/env bash
# Every test in one command: install dependencies, build, run the whole ctest suite.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
bash scripts/build.sh
cd "${VSCULPT_BUILD_DIR:-build}"
ctest --output-on-failure --parallel "$(nproc)" --timeout 900
