#!/usr/bin/env bash
# Runs a command and checks its exit code and that its output (stdout + stderr) matches a
# regular expression: `expect_exit.sh CODE REGEX -- COMMAND...`. ctest's own checks only know
# "non-zero", and the exit-code table (0 ok, 1 runtime failure, 2 bad input) needs the number.
set -uo pipefail
want="$1"; regex="$2"; shift 3
out="$("$@" 2>&1)"
got=$?
printf '%s\n' "$out"
if [ "$got" != "$want" ]; then
  echo "expect_exit: exit code $got, expected $want" >&2
  exit 1
fi
if ! printf '%s\n' "$out" | grep -Eq -- "$regex"; then
  echo "expect_exit: output does not match /$regex/" >&2
  exit 1
fi
