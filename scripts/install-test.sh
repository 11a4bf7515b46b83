#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Installs vsculpt into a temporary prefix and checks that the installed copy stands on its
# own (issue #16, docs/install.md): every file in its place, no RUNPATH or string pointing into
# the source or build tree, and the installed binary working from an empty folder with no
# config in reach, no LD_LIBRARY_PATH, no display.
#
#   bash scripts/install-test.sh [--no-build] [--move-build] [--deb] [BUILD_DIR]
#
# BUILD_DIR (default build/) is configured (Release) if it has no CMakeCache.txt and the
# installed targets are built, unless --no-build: then what it holds is installed as it is
# (ctest's `install.prefix` test does this; it must not relink binaries other tests run).
# --move-build renames BUILD_DIR aside while the installed copy runs and puts it back after
# (standalone use only: never while anything else uses that build folder).
# --deb also builds the Debian package (cpack -G DEB in BUILD_DIR) and checks its contents.
set -euo pipefail
src=$(cd "$(dirname "$0")/.." && pwd)

build="" do_build=1 move_build=0 deb=0
for arg in "$@"; do
  case $arg in
    --no-build) do_build=0 ;;
    --move-build) move_build=1 ;;
    --deb) deb=1 ;;
    -h | --help) sed -n '3,/^set -euo/p' "$0" | sed '$d; s/^# \{0,1\}//'; exit 0 ;;
    -*) echo "install-test: unknown option $arg" >&2; exit 2 ;;
    *) build=$arg ;;
  esac
done
build=${build:-$src/build}
if [ "$do_build" = 1 ]; then
  if [ ! -f "$build/CMakeCache.txt" ]; then
    generator=()
    if command -v ninja >/dev/null 2>&1; then generator=(-G Ninja); fi
    cmake -S "$src" -B "$build" "${generator[@]}" -DCMAKE_BUILD_TYPE=Release -DVSCULPT_BUILD_BENCH=OFF
  fi
  # vsculpt_man needs vsculpt and its libraries: everything that is installed.
  cmake --build "$build" --target vsculpt_man --parallel "${VSCULPT_JOBS:-$(nproc)}"
fi
[ -f "$build/CMakeCache.txt" ] || { echo "install-test: $build is not a build folder" >&2; exit 2; }
build=$(cd "$build" && pwd)

tmp=$(mktemp -d "${TMPDIR:-/tmp}/vsculpt-install-test.XXXXXX")
aside=""
cleanup() {
  if [ -n "$aside" ] && [ -d "$aside" ] && [ ! -e "$build" ]; then mv "$aside" "$build"; fi
  rm -rf "$tmp"
}
trap cleanup EXIT
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }
pass() { echo "ok: $*"; }

prefix=$tmp/prefix
echo "== cmake --install $build --prefix $prefix"
cmake --install "$build" --prefix "$prefix" >"$tmp/install.log" || { cat "$tmp/install.log"; exit 1; }

echo "== the installed files"
for f in bin/vsculpt share/vsculpt/sculpt.json share/vsculpt/examples/snowman.vsc \
         lib/udev/rules.d/70-vsculpt.rules share/doc/vsculpt/README.md share/doc/vsculpt/LICENSE \
         share/doc/vsculpt/docs/config.md share/doc/vsculpt/docs/install.md \
         share/man/man1/vsculpt.1.gz share/bash-completion/completions/vsculpt \
         share/applications/vsculpt.desktop share/icons/hicolor/scalable/apps/vsculpt.svg; do
  if [ -s "$prefix/$f" ]; then pass "$f"; else fail "$f is missing or empty"; fi
done
[ -x "$prefix/bin/vsculpt" ] || fail "bin/vsculpt is not executable"
cmp -s "$prefix/share/vsculpt/sculpt.json" "$src/configs/sculpt.json" ||
  fail "share/vsculpt/sculpt.json differs from configs/sculpt.json"

echo "== no RUNPATH and no string points into the source or build tree"
elves=()
while IFS= read -r -d '' f; do
  if [ "$(head -c 4 "$f" | od -An -c | tr -d ' ')" = '177ELF' ]; then elves+=("$f"); fi
done < <(find "$prefix" -type f -print0)
[ "${#elves[@]}" -gt 0 ] || fail "no ELF files installed"
for e in "${elves[@]}"; do
  rel=${e#"$prefix"/}
  runpath=$(readelf -d "$e" | sed -n 's/.*(\(RPATH\|RUNPATH\)).*\[\(.*\)\]/\2/p')
  if [ -z "$runpath" ]; then
    pass "$rel: no RUNPATH"
  else
    bad=0
    IFS=: read -ra entries <<<"$runpath"
    for entry in "${entries[@]}"; do
      case $entry in '$ORIGIN' | '$ORIGIN/'*) ;; *) bad=1 ;; esac
    done
    if [ "$bad" = 0 ]; then pass "$rel: RUNPATH $runpath"; else fail "$rel: RUNPATH $runpath"; fi
  fi
done
# The build folder is usually inside the source folder: checking both covers either layout.
for tree in "$src" "$build"; do
  if hits=$(grep -rlaF "$tree" "$prefix"); then
    fail "installed files mention $tree: $(echo "$hits" | sed "s|$prefix/||" | tr '\n' ' ')"
  else
    pass "no installed file mentions $tree"
  fi
done

if [ "$move_build" = 1 ]; then
  aside="$build.aside.$$"
  mv "$build" "$aside"
  echo "== $build moved aside to $aside while the installed copy runs"
fi

echo "== the installed vsculpt from an empty folder: no config, no LD_LIBRARY_PATH, no display"
work=$tmp/work home=$tmp/home
mkdir -p "$work" "$home"
vs=$prefix/bin/vsculpt
# A clean environment: only PATH, HOME and the locale; no VSCULPT_CONFIG, XDG_*, DISPLAY,
# LD_LIBRARY_PATH. Extra VAR=value arguments before the command add to it.
run() {
  local env=(PATH=/usr/local/bin:/usr/bin:/bin "HOME=$home" LANG=C.UTF-8)
  while [[ $1 == *=* ]]; do env+=("$1"); shift; done
  (cd "$work" && env -i "${env[@]}" "$@" >"$tmp/out" 2>"$tmp/err")
}
# expect CODE TEXT -- [VAR=value...] COMMAND...: the exit code, and TEXT in stdout or stderr.
expect() {
  local code=$1 text=$2
  shift 3
  local got=0
  run "$@" || got=$?
  local what="${*#"$prefix"/}"
  if [ "$got" != "$code" ]; then
    fail "$what: exit $got, expected $code"; sed 's/^/  | /' "$tmp/out" "$tmp/err" | tail -20
  elif ! grep -qF -- "$text" "$tmp/out" "$tmp/err"; then
    fail "$what: no '$text' in the output"; sed 's/^/  | /' "$tmp/out" "$tmp/err" | tail -20
  else
    pass "$what: exit $code, '$text'"
  fi
}

if run ldd "$vs" && ! grep -q "not found" "$tmp/out"; then
  pass "ldd: every library found ($(grep -c "$prefix" "$tmp/out" || true) from the prefix)"
else
  fail "ldd $vs:"; sed 's/^/  | /' "$tmp/out" "$tmp/err"
fi
expect 0 "vsculpt 0.1.0" -- "$vs" --version
expect 0 "config: built-in defaults" -- "$vs" info
expect 0 "watertight" -- "$vs" play "$prefix/share/vsculpt/examples/snowman.vsc" --out x.glb --no-progress
if [ "$(head -c 4 "$work/x.glb" 2>/dev/null)" = glTF ]; then
  pass "x.glb written ($(stat -c %s "$work/x.glb") bytes, glTF binary)"
else
  fail "x.glb was not written as glTF binary"
fi
cp "$src/examples/mug.vsc" "$work/"
expect 0 "watertight" -- "$vs" play mug.vsc --out mug.stl --no-progress
# The lookup order (docs/config.md): $VSCULPT_CONFIG, then the per-user file.
expect 2 "$tmp/missing.json: cannot open config file: No such file or directory (named by \$VSCULPT_CONFIG)" -- "VSCULPT_CONFIG=$tmp/missing.json" "$vs" info
mkdir -p "$home/.config/vsculpt"
cp "$prefix/share/vsculpt/sculpt.json" "$home/.config/vsculpt/sculpt.json"
expect 0 "config: $home/.config/vsculpt/sculpt.json" -- "$vs" info
mkdir -p "$tmp/xdg/vsculpt"
echo '{"tools": {"growth": 0.5}}' >"$tmp/xdg/vsculpt/sculpt.json"
expect 2 "$tmp/xdg/vsculpt/sculpt.json: tools.growth" -- "XDG_CONFIG_HOME=$tmp/xdg" "$vs" info
expect 0 "config: $prefix/share/vsculpt/sculpt.json" -- "XDG_CONFIG_HOME=$tmp/xdg" \
  "VSCULPT_CONFIG=$tmp/missing.json" "$vs" --config "$prefix/share/vsculpt/sculpt.json" info
rm -rf "$home/.config"

# Nothing in the source or build tree is opened (where strace can trace).
if command -v strace >/dev/null 2>&1 && strace -o /dev/null true 2>/dev/null; then
  run strace -f -qq -e trace=%file -o "$tmp/trace" "$vs" info || true
  if grep -F -e "$src" -e "$build" "$tmp/trace" >"$tmp/hits"; then
    fail "vsculpt info opened files in the source or build tree:"; head -5 "$tmp/hits"
  else
    pass "strace: vsculpt info touched nothing in $src or $build"
  fi
else
  echo "skip: strace unavailable (the RUNPATH and string checks above still hold)"
fi

echo "== man page, completion, desktop entry"
if zcat "$prefix/share/man/man1/vsculpt.1.gz" >"$tmp/vsculpt.1" &&
   grep -q '^\.TH VSCULPT' "$tmp/vsculpt.1" && grep -q 'VSCULPT_CONFIG' "$tmp/vsculpt.1" &&
   grep -q 'vsculpt play' "$tmp/vsculpt.1"; then
  pass "vsculpt.1.gz: .TH, COMMANDS and ENVIRONMENT"
  if command -v groff >/dev/null 2>&1; then
    if groff -man -Tutf8 -z "$tmp/vsculpt.1" 2>"$tmp/groff"; [ ! -s "$tmp/groff" ]; then
      pass "groff renders vsculpt.1 without warnings"
    else
      fail "groff warnings:"; head -5 "$tmp/groff"
    fi
  fi
else
  fail "vsculpt.1.gz is not the expected man page"
fi
completion=$(cd "$work" && env -i PATH=/usr/bin:/bin "HOME=$home" bash -c '
  source "$1"
  complete_words() { COMP_WORDS=("$@"); COMP_CWORD=$((${#COMP_WORDS[@]} - 1)); COMPREPLY=(); _vsculpt; echo "${COMPREPLY[*]}"; }
  echo "subcommands: $(complete_words "$2" "")"
  echo "play options: $(complete_words "$2" play --ch)"
  echo "stereo: $(complete_words "$2" play --stereo a)"' _ "$prefix/share/bash-completion/completions/vsculpt" "$vs")
if grep -q "subcommands: .*play.*render" <<<"$completion" && grep -q "play options: --check" <<<"$completion" &&
   grep -q "stereo: anaglyph" <<<"$completion"; then
  pass "bash completion: $(tr '\n' ';' <<<"$completion")"
else
  fail "bash completion: $completion"
fi
if command -v desktop-file-validate >/dev/null 2>&1; then
  if desktop-file-validate "$prefix/share/applications/vsculpt.desktop"; then pass "desktop-file-validate"
  else fail "desktop-file-validate"; fi
elif grep -q '^Exec=vsculpt$' "$prefix/share/applications/vsculpt.desktop" &&
     grep -q '^Icon=vsculpt$' "$prefix/share/applications/vsculpt.desktop"; then
  pass "vsculpt.desktop: Exec and Icon (desktop-file-validate not installed)"
else
  fail "vsculpt.desktop"
fi

if [ -n "$aside" ]; then mv "$aside" "$build"; aside=""; echo "== $build is back"; fi

if [ "$deb" = 1 ]; then
  echo "== cpack -G DEB"
  (cd "$build" && cpack -G DEB >"$tmp/cpack.log" 2>&1) || { cat "$tmp/cpack.log"; exit 1; }
  debfile=$(sed -n 's/.*package: \(.*\.deb\) generated.*/\1/p' "$tmp/cpack.log" | tail -1)
  if [ -f "$debfile" ]; then
    pass "$debfile"
    dpkg-deb -f "$debfile" Package Version Section Maintainer Depends | sed 's/^/  | /'
    dpkg-deb -c "$debfile" >"$tmp/deb-contents"
    awk '{print "  | " $1 " " $6 ($7 ? " " $7 " " $8 : "")}' "$tmp/deb-contents"
    for f in ./usr/bin/vsculpt ./usr/share/man/man1/vsculpt.1.gz ./usr/lib/udev/rules.d/70-vsculpt.rules \
             ./usr/share/doc/vsculpt/copyright; do
      grep -q " $f\$" "$tmp/deb-contents" || fail "$f is not in the package"
    done
    # The maintainer script that has udev read the rule (a replug is not needed).
    dpkg-deb -e "$debfile" "$tmp/deb-control"
    grep -q "udevadm trigger" "$tmp/deb-control/postinst" 2>/dev/null || fail "no postinst running udevadm"
    # The packaged files on their own, unpacked (not installed: this changes nothing on the
    # machine).
    dpkg-deb -x "$debfile" "$tmp/deb-root"
    expect 0 "config: built-in defaults" -- "$tmp/deb-root/usr/bin/vsculpt" info
  else
    fail "cpack wrote no .deb"; cat "$tmp/cpack.log"
  fi
fi

if [ "$failures" -gt 0 ]; then
  echo "install-test: $failures check(s) failed"
  exit 1
fi
echo "install-test: the installed vsculpt stands on its own"
