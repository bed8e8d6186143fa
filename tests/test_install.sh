#!/bin/sh
# mm installs like a library (docs/embedding.md): `cmake --install` into a temporary prefix puts
# there the libraries mm_runtime, mm_build, mm_pfnn (static and shared, versioned), only their
# headers (not mm_render's), the mm program, mm.pc (and mm-build.pc, mm-pfnn.pc) and the CMake
# package mm with its version file. Against that tree alone, examples/embed.c, examples/crowd.c and
# examples/build_db.c are built twice, with pkg-config and with find_package(mm) (examples/
# CMakeLists.txt, a project of its own linking mm::runtime and mm::build), and run on a database
# the installed mm program makes from the built-in set: the builds give the same output, build_db
# the same bytes as `mm db build`, and every installed header compiles.
# usage: test_install.sh BUILD_DIR SOURCE_DIR OUT_DIR CC [CFLAGS]
#   CFLAGS: the sanitizer flags of a sanitizer build (the installed libraries need their runtime)
set -u
build=$1
src=$2
out=$3
cc=$4
flags=${5:-}
# shellcheck disable=SC1091
. "$src/tests/cli_checks.sh"
rm -rf "$out"
mkdir -p "$out"
prefix=$out/prefix
run() { # LOG CMD...: runs CMD, its output to $out/LOG; reports a failure with the log
    log=$1
    shift
    if "$@" >"$out/$log" 2>&1; then ok; else
        bad "$*"
        tail -20 "$out/$log"
        return 1
    fi
}

if ! run install.log cmake --install "$build" --prefix "$prefix"; then
    finish test_install
    exit
fi
version=$(sed -n 's/^#define MM_VERSION_\(MAJOR\|MINOR\|PATCH\) \([0-9]*\)$/\2/p' "$src/include/mm/version.h" | paste -sd.)
major_minor=${version%.*}

# the tree: libraries, headers, program, pkg-config files, CMake package
libdir=$prefix/lib
[ -d "$libdir" ] || libdir=$(dirname "$(find "$prefix" -name libmm_runtime.a | head -1)")
for lib in mm_runtime mm_build mm_pfnn; do
    for f in "lib$lib.a" "lib$lib.so" "lib$lib.so.$major_minor" "lib$lib.so.$version"; do
        if [ -e "$libdir/$f" ]; then ok; else bad "not installed: $f"; fi
    done
    soname=$(readelf -d "$libdir/lib$lib.so" | sed -n 's/.*(SONAME).*\[\(.*\)\]/\1/p')
    if [ "$soname" = "lib$lib.so.$major_minor" ]; then ok; else bad "lib$lib.so's SONAME is '$soname'"; fi
done
for f in bin/mm include/mm/runtime.h include/mm/version.h include/mm/mm.h include/mm/database_build.h \
    include/mm/pfnn.h "${libdir#"$prefix"/}/pkgconfig/mm.pc" "${libdir#"$prefix"/}/cmake/mm/mmConfig.cmake" \
    "${libdir#"$prefix"/}/cmake/mm/mmConfigVersion.cmake"; do
    if [ -e "$prefix/$f" ]; then ok; else bad "not installed: $f"; fi
done
for f in render.h view.h; do
    if [ -e "$prefix/include/mm/$f" ]; then bad "installed: mm_render's header $f"; else ok; fi
done
# every installed header compiles, alone and all together, with only the installed tree
for h in "$prefix"/include/mm/*.h; do echo "#include <mm/$(basename "$h")>"; done >"$out/headers.c"
echo "int main(void) { return mm_version() == MM_VERSION_NUMBER ? 0 : 1; }" >>"$out/headers.c"
# shellcheck disable=SC2086
run headers.log "$cc" -std=c11 -Wall -Wextra -Wpedantic -Werror $flags -I"$prefix/include" "$out/headers.c" \
    -o "$out/headers" -L"$libdir" -lmm_runtime -Wl,-rpath,"$libdir" && run headers_run.log "$out/headers"

# the database, made by the installed program
run version.log "$prefix/bin/mm" --version && expect_grep "mm $version (library $version," "$out/version.log"
run synth.log "$prefix/bin/mm" synth "$out/set" &&
    run db.log "$prefix/bin/mm" db build "$src/configs/synth.json" --data "$out/set" -o "$out/synth.mmdb"

# 1. pkg-config
export PKG_CONFIG_PATH="$libdir/pkgconfig"
if [ "$(pkg-config --modversion mm 2>&1)" = "$version" ]; then ok; else bad "pkg-config --modversion mm: $(pkg-config --modversion mm 2>&1)"; fi
pc_libdir=$(pkg-config --variable=libdir mm)
for example in embed crowd build_db; do
    module=mm
    [ "$example" = build_db ] && module=mm-build
    # shellcheck disable=SC2046,SC2086
    run "pc_$example.log" "$cc" -std=c11 -Wall -Wextra -Werror $flags $(pkg-config --cflags $module) \
        "$src/examples/$example.c" -o "$out/pc_$example" $(pkg-config --libs $module) -lm -Wl,-rpath,"$pc_libdir"
done
# they run with the installed libraries (not the build tree's)
if ldd "$out/pc_embed" | grep -q "$prefix.*libmm_runtime"; then ok; else bad "pc_embed does not use the installed libmm_runtime"; fi
run pc_embed.out "$out/pc_embed" "$out/synth.mmdb" && expect_grep "^t = 5 s" "$out/pc_embed.out"
run pc_crowd.out "$out/pc_crowd" "$out/synth.mmdb" 500 0.5 && expect_grep "500 characters, 30 ticks.*every pose finite" "$out/pc_crowd.out"
run pc_build_db.out "$out/pc_build_db" "$src/configs/synth.json" "$out/set" "$out/pc.mmdb"
if cmp -s "$out/pc.mmdb" "$out/synth.mmdb"; then ok; else bad "build_db (pkg-config) and mm db build made different databases"; fi

# 2. find_package(mm) in a project of its own
run cmake_configure.log cmake -S "$src/examples" -B "$out/examples" -DCMAKE_PREFIX_PATH="$prefix" \
    -DCMAKE_C_COMPILER="$cc" -DCMAKE_C_FLAGS="$flags" -DCMAKE_BUILD_TYPE=Release &&
    run cmake_build.log cmake --build "$out/examples"
ex=$out/examples
run cm_embed.out "$ex/embed" "$out/synth.mmdb"
if cmp -s "$out/cm_embed.out" "$out/pc_embed.out"; then ok; else bad "embed's output differs between the pkg-config and the CMake build"; fi
run cm_embed_static.out "$ex/embed_static" "$out/synth.mmdb"
if cmp -s "$out/cm_embed_static.out" "$out/pc_embed.out"; then ok; else bad "embed_static's output differs from embed's"; fi
if readelf -d "$ex/embed_static" | grep -q "libmm_runtime"; then bad "embed_static needs libmm_runtime.so"; else ok; fi
run cm_crowd.out "$ex/crowd" "$out/synth.mmdb" 500 0.5
if cmp -s "$out/cm_crowd.out" "$out/pc_crowd.out"; then ok; else bad "crowd's output differs between the pkg-config and the CMake build"; fi
run cm_build_db.out "$ex/build_db" "$src/configs/synth.json" "$out/set" "$out/cm.mmdb"
if cmp -s "$out/cm.mmdb" "$out/synth.mmdb"; then ok; else bad "build_db (CMake) and mm db build made different databases"; fi
# a version the package is not compatible with is refused
printf 'cmake_minimum_required(VERSION 3.25)\nproject(v LANGUAGES C)\nfind_package(mm 99 QUIET)\nif(mm_FOUND)\n  message(FATAL_ERROR "found")\nendif()\n' >"$out/v.cmake"
mkdir -p "$out/v" && cp "$out/v.cmake" "$out/v/CMakeLists.txt"
run cmake_v99.log cmake -S "$out/v" -B "$out/v/build" -DCMAKE_PREFIX_PATH="$prefix"

finish test_install
