#!/bin/sh
# The runtime library stands alone: libmm_runtime.so needs libc, libm and pthreads and nothing
# else (no cJSON, no assimp, no part of mm_build), every symbol it leaves undefined is theirs, and
# examples/embed.c links against it, libm and libpthread alone with every symbol of every library
# resolved (-Wl,--no-undefined,--no-allow-shlib-undefined) and starts with all of them bound
# (LD_BIND_NOW). libmm_pfnn.so likewise needs only libmm_runtime, libc and libm. And no header of
# either library declares a function the library lacks.
# usage: test_runtime_standalone.sh CC RUNTIME_SO PFNN_SO EMBED_C INCLUDE_DIR OUT_DIR [CFLAGS]
#   CFLAGS: the sanitizer flags of a sanitizer build (its libraries then also need their runtimes)
set -u
cc=$1
runtime=$2
pfnn=$3
embed=$4
include=$5
out=$6
flags=${7:-}
failed=0
mkdir -p "$out"
bad() { failed=$((failed + 1)); echo "FAIL: $*"; }

sanitizers='libasan|libubsan|libtsan|liblsan'
system="libc|libm|libpthread|ld-linux[-a-z0-9_.]*|$sanitizers"
# needed LIB ALLOWED: every DT_NEEDED entry of LIB matches ^(ALLOWED)\.so
needed() {
    names=$(readelf -d "$1" | sed -n 's/.*(NEEDED).*\[\(.*\)\]/\1/p')
    [ -n "$names" ] || bad "$1: readelf shows no NEEDED entries"
    for n in $names; do
        if echo "$n" | grep -Eq "^($2)\.so"; then echo "  $(basename "$1") needs $n"; else
            bad "$(basename "$1") needs $n: only libc, libm and pthreads are allowed"
        fi
    done
}
needed "$runtime" "$system"
needed "$pfnn" "libmm_runtime|$system"

# every symbol the runtime leaves undefined (weak hooks aside) is defined by libc, libm or pthreads
# (and in a sanitizer build by its runtime, which intercepts malloc, memcpy and the like)
provided="$out/system_defined.txt"
: >"$provided"
for lib in $(ldd "$runtime" | awk '/=>/ { print $3 }'); do
    if basename "$lib" | grep -Eq "^($system)\.so"; then
        nm -D --defined-only "$lib" | awk '{ print $3 }' | sed 's/@.*//' >>"$provided"
    fi
done
sort -u "$provided" -o "$provided"
nm -D --undefined-only "$runtime" | awk '$1 == "U" { print $2 }' | sed 's/@.*//' | sort -u >"$out/runtime_undefined.txt"
others=$(comm -23 "$out/runtime_undefined.txt" "$provided")
if [ ! -s "$provided" ]; then
    bad "ldd found none of libc, libm, pthreads for $runtime"
elif [ -n "$others" ]; then
    bad "libmm_runtime.so uses symbols from outside libc, libm and pthreads:"
    echo "$others" | head -20
else
    echo "  libmm_runtime.so: $(wc -l <"$out/runtime_undefined.txt" | tr -d ' ') undefined symbols, all from libc, libm, pthreads"
fi

# every function a header of the library declares, the library defines (mm/runtime.h lists the
# runtime's headers; static inline functions aside)
declared() { # HEADER...: the functions declared
    for h in "$@"; do
        grep -E '^[A-Za-z_][A-Za-z0-9_ *]*[ *](mm_[A-Za-z0-9_]+)\(' "$h" | grep -vE '^(static|typedef|#)' |
            sed -E 's/^[A-Za-z_][A-Za-z0-9_ *]*[ *](mm_[A-Za-z0-9_]+)\(.*/\1/'
    done | sort -u
}
defined() { nm -D --defined-only "$1" | awk '{ print $3 }' | sort -u; }
headers=$(sed -n 's|^#include "\(.*\)"|'"$include"'/mm/\1|p' "$include/mm/runtime.h")
# shellcheck disable=SC2086
declared $headers >"$out/runtime_declared.txt"
defined "$runtime" >"$out/runtime_defined.txt"
missing=$(comm -23 "$out/runtime_declared.txt" "$out/runtime_defined.txt")
count=$(wc -l <"$out/runtime_declared.txt" | tr -d ' ')
if [ -n "$missing" ] || [ "$count" -lt 100 ]; then
    bad "functions declared in the runtime's headers but not defined in libmm_runtime.so ($count declared):"
    echo "$missing"
else
    echo "  the runtime's $(echo "$headers" | wc -w | tr -d ' ') headers declare $count functions, all in libmm_runtime.so"
fi
declared "$include/mm/pfnn.h" >"$out/pfnn_declared.txt"
defined "$pfnn" >"$out/pfnn_defined.txt"
missing=$(comm -23 "$out/pfnn_declared.txt" "$out/pfnn_defined.txt")
if [ -n "$missing" ]; then
    bad "functions declared in mm/pfnn.h but not defined in libmm_pfnn.so:"
    echo "$missing"
fi

# a program of the runtime alone
dir=$(dirname "$runtime")
# shellcheck disable=SC2086
if "$cc" -std=c11 $flags -I"$include" "$embed" -o "$out/embed_shared" -L"$dir" -lmm_runtime -lm -lpthread \
    -Wl,--no-undefined -Wl,--no-allow-shlib-undefined -Wl,-rpath,"$dir"; then
    LD_BIND_NOW=1 "$out/embed_shared" >/dev/null 2>"$out/embed_shared.err"
    status=$?
    # exit 2: the usage message, after every symbol was bound at start-up
    if [ "$status" -eq 2 ] && grep -q usage "$out/embed_shared.err"; then
        echo "  embed.c links and starts against libmm_runtime.so, libm and libpthread alone"
    else
        bad "embed_shared exited $status"
        cat "$out/embed_shared.err"
    fi
else
    bad "embed.c does not link against libmm_runtime.so, libm and libpthread alone"
fi

echo "test_runtime_standalone: $failed failed"
[ "$failed" -eq 0 ]
