#!/usr/bin/env bash
# The main job in one command: install dependencies, build, run vsculpt.
# Arguments are passed to vsculpt (try --help).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
bash scripts/build.sh
exec "${VSCULPT_BUILD_DIR:-build}/app/vsculpt" "$@"
