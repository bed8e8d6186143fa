#!/bin/sh
# Builds mm and runs the whole test suite with CTest.
# usage: scripts/test.sh [--sanitize | --tsan]
#   --sanitize: AddressSanitizer + UndefinedBehaviorSanitizer build in build-asan/, all tests
#   --tsan:     ThreadSanitizer build in build-tsan/, the tests that run threads (search, batch,
#               the crowd on mm's pool and on a parallel-for of its own threads,
#               the threaded database build)
# Tests on real motion capture run when MM_DATA_DIR points at it and are reported skipped otherwise.
set -e
cd "$(dirname "$0")/.."
if [ "${1:-}" = "--sanitize" ]; then
    scripts/setup.sh >/dev/null
    cmake -S . -B build-asan -DCMAKE_BUILD_TYPE=Debug -DMM_SANITIZE=address,undefined -DMM_BUILD_BENCH=OFF >/dev/null
    cmake --build build-asan -j"$(nproc)"
    dir=build-asan
elif [ "${1:-}" = "--tsan" ]; then
    scripts/setup.sh >/dev/null
    cmake -S . -B build-tsan -DCMAKE_BUILD_TYPE=RelWithDebInfo -DMM_SANITIZE=thread -DMM_BUILD_BENCH=OFF >/dev/null
    cmake --build build-tsan -j"$(nproc)" --target test_search test_database test_crowd
    # the real data and thousands of queries add nothing to what races there are, at TSan's speed
    env -u MM_DATA_DIR MM_TEST_SEARCH_QUERIES=200 ctest --test-dir build-tsan --output-on-failure -R 'test_search|test_database$|test_crowd'
    exit
else
    scripts/setup.sh
    dir=build
fi
ctest --test-dir "$dir" --output-on-failure -j"$(nproc)"
