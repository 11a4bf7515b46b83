#!/usr/bin/env bash
# Runs a command under a private Xvfb and exits with the command's own exit code:
# `with_xvfb.sh COMMAND...`. The tests' GL and window runs use it in place of `xvfb-run -a`:
# - Debian 12's xvfb-run sometimes fails to remove its temporary folder after the command
#   ("problem while cleaning up temporary directory") and then exits 5 in place of the
#   command's code; run in parallel by ctest, cli.exit.window_expect failed so once in 40
#   runs here (likely the Release test that failed stop 45's CI).
# - Xvfb picks a free display itself (-displayfd), so parallel runs never race for a number.
# Without -auth the server takes local connections only (-nolisten tcp), with no cookie to clean.
set -uo pipefail
dir="$(mktemp -d "${TMPDIR:-/tmp}/vsculpt-xvfb.XXXXXX")" || exit 1
# Made here: the background job below opens it only when it runs, after the first read may.
: >"$dir/display"
Xvfb -displayfd 3 -screen 0 1280x1024x24 -nolisten tcp 3>"$dir/display" 2>"$dir/log" &
xvfb=$!
cleanup() {
  kill "$xvfb" 2>/dev/null
  wait "$xvfb" 2>/dev/null
  rm -rf "$dir"
}
trap cleanup EXIT
trap 'exit 143' TERM
trap 'exit 130' INT
# Xvfb writes the display's number and a newline once it accepts connections (read fails
# until the newline is there).
display=""
for _ in $(seq 1 600); do
  if IFS= read -r display <"$dir/display" 2>/dev/null && [ -n "$display" ]; then break; fi
  display=""
  if ! kill -0 "$xvfb" 2>/dev/null; then
    echo "with_xvfb.sh: Xvfb did not start:" >&2
    cat "$dir/log" >&2
    exit 1
  fi
  sleep 0.05
done
if [ -z "$display" ]; then
  echo "with_xvfb.sh: Xvfb gave no display within 30 s:" >&2
  cat "$dir/log" >&2
  exit 1
fi
DISPLAY=":$display" "$@"
