#!/bin/sh
# Builds the libFuzzer targets into build-fuzz (or $MM_FUZZ_BUILD) and runs each for N seconds
# (default 60).
#
#   scripts/fuzz.sh [seconds] [target...]      e.g. scripts/fuzz.sh 300 fuzz_bvh
#   (targets: fuzz_bvh, fuzz_config, fuzz_mmdb, fuzz_input, fuzz_sim, fuzz_scene; each has a dictionary fuzz/<name>.dict if present)
#
# Each target starts from its seed corpus fuzz/corpus/<name>/ (read only; the mmdb and sim seeds
# are made from the built-in motion set by fuzz/make_seeds.sh) plus a working corpus in
# build-fuzz/corpus/<name>/ that grows from run to run. Crashes, leaks and timeouts are written
# to build-fuzz/artifacts/<name>/; add each one to the seed corpus or a test once it is fixed.
# Prints executions per second and coverage per target; exits non-zero when anything was found.
#
# CI budget (.ci/run runs `scripts/fuzz.sh 60`): 60 s per target, the six targets one after the
# other, so 6 minutes of fuzzing per CI run in all (plus the build of build-fuzz). fuzz_mmdb and
# fuzz_sim use a custom mutator that recomputes the checksum (fuzz/fuzz_reseal.h). The executions
# each target reaches in its minute are in docs/reliability.md.
set -eu

root=$(cd "$(dirname "$0")/.." && pwd)
build=${MM_FUZZ_BUILD:-$root/build-fuzz}
seconds=${1:-60}
[ $# -gt 0 ] && shift
targets=${*:-fuzz_bvh fuzz_config fuzz_mmdb fuzz_input fuzz_sim fuzz_scene}

case $seconds in
'' | *[!0-9]*)
    echo "usage: $0 [seconds] [target...]" >&2
    exit 2
    ;;
esac

cmake -S "$root" -B "$build" -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ \
    -DCMAKE_BUILD_TYPE=RelWithDebInfo -DMM_BUILD_FUZZ=ON -DMM_BUILD_TESTS=OFF -DMM_BUILD_BENCH=OFF >/dev/null
# shellcheck disable=SC2086
cmake --build "$build" --target $targets -j "$(nproc 2>/dev/null || echo 2)" >/dev/null


status=0
summary=""
for t in $targets; do
    name=${t#fuzz_}
    seeds="$root/fuzz/corpus/$name"
    work="$build/corpus/$name"
    artifacts="$build/artifacts/$name"
    log="$build/$t.log"
    mkdir -p "$work" "$artifacts"
    [ -d "$seeds" ] || seeds="" # no committed seeds: libFuzzer starts from the dictionary
    stamp="$build/$t.start"
    : >"$stamp"
    echo "== $t: $seconds s (log: $log)"
    rc=0
    dict=""
    [ -f "$root/fuzz/$name.dict" ] && dict="-dict=$root/fuzz/$name.dict"
    # shellcheck disable=SC2086
    "$build/fuzz/$t" "$work" $seeds $dict -max_total_time="$seconds" -max_len=32768 \
        -timeout=10 -rss_limit_mb=2048 -print_final_stats=1 -artifact_prefix="$artifacts/" >"$log" 2>&1 || rc=$?
    # The last status line reads "#RUNS <event> cov: C ft: F corp: N/SIZE ... exec/s: E rss: R".
    last=$(grep -E '^#[0-9]+' "$log" | tail -n 1 || true)
    runs=$(grep -E '^stat::number_of_executed_units:' "$log" | awk '{print $2}' || true)
    speed=$(grep -E '^stat::average_exec_per_sec:' "$log" | awk '{print $2}' || true)
    cov=$(echo "$last" | sed -n 's/.* cov: \([0-9]*\).*/\1/p')
    ft=$(echo "$last" | sed -n 's/.* ft: \([0-9]*\).*/\1/p')
    corp=$(echo "$last" | sed -n 's/.* corp: \([0-9]*\/[0-9a-zA-Z]*\).*/\1/p')
    found=$(find "$artifacts" -type f -newer "$stamp" | wc -l | tr -d ' ')
    line="$t: ${runs:-?} runs, ${speed:-?} exec/s, cov ${cov:-?} edges, ft ${ft:-?} features, corpus ${corp:-?}"
    if [ "$rc" -ne 0 ] || [ "$found" -ne 0 ]; then
        line="$line - FOUND A PROBLEM (exit $rc, $found artifact(s) in $artifacts)"
        grep -E 'ERROR|SUMMARY|runtime error|deadly signal' "$log" | head -n 5 || true
        status=1
    fi
    echo "$line"
    summary="$summary$line
"
done
echo "== summary"
printf '%s' "$summary"
exit $status
