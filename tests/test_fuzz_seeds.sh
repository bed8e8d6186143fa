#!/bin/sh
# The committed seeds of fuzz_mmdb and fuzz_sim (made by fuzz/make_seeds.sh from the built-in
# motion set) still load with this mm, each tables file belongs to its database, and each seed fits
# in the 32768 bytes scripts/fuzz.sh lets the fuzzers use. When the .mmdb or tables format changes,
# re-make them: fuzz/make_seeds.sh BUILD/mm
# usage: test_fuzz_seeds.sh MM_BINARY SOURCE_DIR
set -u
mm=$1
corpus=$2/fuzz/corpus
passed=0
failed=0

ok() { passed=$((passed + 1)); }
bad() { failed=$((failed + 1)); echo "FAIL: $*"; }
loads() { # CMD... : exits 0
    if "$@" >/dev/null 2>"${TMPDIR:-/tmp}/mm_seeds.$$"; then ok; else
        bad "$* (re-make the seeds: fuzz/make_seeds.sh MM_BINARY)"
        cat "${TMPDIR:-/tmp}/mm_seeds.$$"
    fi
    rm -f "${TMPDIR:-/tmp}/mm_seeds.$$"
}

for f in "$corpus"/mmdb/small.mmdb "$corpus"/mmdb/rich.mmdb "$corpus"/mmdb/rich_compressed.mmdb "$corpus"/sim/small.sim "$corpus"/sim/rich_cos_w2.sim \
    "$corpus"/sim/rich_euclid_all.sim; do
    if [ -f "$f" ] && [ "$(wc -c <"$f")" -lt 32768 ]; then ok; else bad "$f is missing or not under 32768 bytes"; fi
done
loads "$mm" db dump "$corpus/mmdb/small.mmdb"
loads "$mm" db dump "$corpus/mmdb/rich.mmdb"
loads "$mm" db dump "$corpus/mmdb/rich_compressed.mmdb"
loads "$mm" similarity info "$corpus/sim/small.sim" --db "$corpus/mmdb/small.mmdb"
loads "$mm" similarity info "$corpus/sim/rich_cos_w2.sim" --db "$corpus/mmdb/rich.mmdb"
loads "$mm" similarity info "$corpus/sim/rich_euclid_all.sim" --db "$corpus/mmdb/rich.mmdb"

echo "test_fuzz_seeds: $passed passed, $failed failed"
[ "$failed" -eq 0 ]
