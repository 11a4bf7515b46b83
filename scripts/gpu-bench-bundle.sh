#!/usr/bin/env bash
# Packs the benchmark executable with every library it loads, Xvfb and Mesa's software GLX
# (which Xvfb needs to offer GLX at all) into one archive, for timing the renderer on a GPU
# machine that has the NVIDIA driver but none of this project's packages. How it is used and
# what it measured: docs/benchmarks.md, "Renderer on a GPU".
#   usage: scripts/gpu-bench-bundle.sh [build-dir] [out-dir]     (default: build .gpu)
set -euo pipefail
build=${1:-build}
out=${2:-.gpu}
stage=$(mktemp -d)
trap 'rm -rf "$stage"' EXIT
b=$stage/b
mkdir -p "$b/bin" "$b/lib" "$b/dri"
libdir=/usr/lib/x86_64-linux-gnu
dri=$libdir/dri/swrast_dri.so
[[ -x $build/tests/vsculpt_bench ]] || { echo "$build/tests/vsculpt_bench: not built" >&2; exit 1; }
[[ -e $dri ]] || { echo "$dri: missing (apt-get install libgl1-mesa-dri)" >&2; exit 1; }
cp "$build/tests/vsculpt_bench" /usr/bin/Xvfb /usr/bin/xkbcomp "$b/bin/"
cp -L "$dri" "$b/dri/"
# The C runtime stays the target's own (a newer glibc and libstdc++ run these binaries); the
# GL dispatch libraries are loaded by name at run time (GLFW, epoxy), so ldd does not list them.
keep='^(libc|libm|libdl|libpthread|librt|libstdc\+\+|libgcc_s|ld-linux-x86-64)\.so'
{
    for f in "$b/bin/"* "$dri"; do ldd "$f"; done | awk '$3 ~ /^\// {print $3}'
    for l in libGL.so.1 libGLX.so.0 libGLdispatch.so.0 libOpenGL.so.0 libEGL.so.1 libGLX_mesa.so.0 libglapi.so.0; do
        echo "$libdir/$l"
        ldd "$libdir/$l" | awk '$3 ~ /^\// {print $3}'
    done
} | sort -u | while read -r lib; do
    name=$(basename "$lib")
    [[ $name =~ $keep ]] || cp -L "$lib" "$b/lib/$name"
done
# Stand-ins to fit the 64 MiB a device call carries: libLLVM links Z3 (23 MB), and through
# libxml2 ICU's data (31 MB); Xvfb only needs the software driver to load and offer GLX
# visuals (the NVIDIA client library renders), so neither is ever called. Each stand-in
# defines the names the loader must resolve and nothing else.
stub() { # soname, C source
    printf '%s\n' "$2" > "$stage/stub.c"
    gcc -shared -fPIC -o "$b/lib/$1" -Wl,-soname,"$1" "$stage/stub.c"
}
z3=$(objdump -T "$libdir/libLLVM-15.so.1" | awk '$NF ~ /^Z3_/ {print "void " $NF "(void) {}"}')
stub libz3.so.4 "$z3"
icu=$(objdump -T "$libdir/libicuuc.so.72" | awk '$NF ~ /^icudt[0-9]+_dat$/ {print "const char " $NF "[16];"}')
stub libicudata.so.72 "$icu"
cp -r /usr/share/X11/xkb "$b/xkb"
mkdir -p "$out"
tar -C "$stage" -cf - b | xz -T0 -6 > "$out/bundle.tar.xz"
du -h "$out/bundle.tar.xz"
