#!/bin/sh
# Builds mm and runs the whole test suite with CTest.
# usage: scripts/test.sh [--sanitize]   (--sanitize: AddressSanitizer + UBSan build in build-asan/)
# Tests on real motion capture run when MM_DATA_DIR points at it and are reported skipped otherwise.
set -e
cd "$(dirname "$0")/.."
if [ "${1:-}" = "--sanitize" ]; then
    scripts/setup.sh >/dev/null
    cmake -S . -B build-asan -DCMAKE_BUILD_TYPE=Debug -DMM_SANITIZE=address,undefined -DMM_BUILD_BENCH=OFF >/dev/null
    cmake --build build-asan -j"$(nproc)"
    dir=build-asan
else
    scripts/setup.sh
    dir=build
fi
ctest --test-dir "$dir" --output-on-failure -j"$(nproc)"
