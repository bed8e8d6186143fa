#!/bin/sh
# Determinism: every command that writes a file writes the same bytes for the same input, run
# after run and whatever its thread count. The built-in motion set always; LAFAN1 and the PFNN
# weights when MM_DATA_DIR holds them. Metrics files are compared without their wall-clock keys
# (docs/metrics.md: search_median_us, search_p99_us, frame_median_us).
# usage: test_determinism.sh MM_BINARY SOURCE_DIR [all|builtin]   (builtin: leave MM_DATA_DIR out)
set -u
mm=$1
src=$2
data=${MM_DATA_DIR:-}
[ "${3:-all}" = builtin ] && data=""
. "$(dirname "$0")/cli_checks.sh"

run() { # CMD... : must exit 0 (stdout to $tmp/out, stderr to $tmp/err)
    if "$@" >"$tmp/out" 2>"$tmp/err"; then ok; else bad "exit $?: $*"; head -n 5 "$tmp/err"; fi
}
same() { # A B : files or folders with the same bytes
    if [ -d "$1" ] && diff -r "$1" "$2" >/dev/null 2>&1; then
        ok
    elif [ -f "$1" ] && cmp -s "$1" "$2"; then
        ok
    else
        bad "$1 and $2 differ"
    fi
}
# metrics JSON without the keys that hold wall time
no_clock() { grep -v -e '"search_median_us"' -e '"search_p99_us"' -e '"frame_median_us"' "$1" >"$2"; }

# mm synth: the built-in set, twice
run "$mm" synth "$tmp/synth"
run "$mm" synth "$tmp/synth2"
same "$tmp/synth" "$tmp/synth2"

# mm db build: 1, 2 and 4 threads, and 2 again
for t in 1 2 4; do
    run "$mm" db build "$src/configs/synth.json" --data "$tmp/synth" -o "$tmp/s$t.mmdb" --threads $t
done
run "$mm" db build "$src/configs/synth.json" --data "$tmp/synth2" -o "$tmp/s2b.mmdb" --threads 2
for f in s2 s4 s2b; do same "$tmp/s1.mmdb" "$tmp/$f.mmdb"; done
db=$tmp/s1.mmdb
run "$mm" db dump "$db"
mv "$tmp/out" "$tmp/dump1"
run "$mm" db dump "$tmp/s4.mmdb"
same "$tmp/dump1" "$tmp/out"

# mm bvh convert (new order, scale, resampled) and mm bvh spans
for k in 1 2; do
    run "$mm" bvh convert "$tmp/synth/walk_1.40.bvh" "$tmp/conv$k.bvh" --order XYZ --scale 0.5 --fps 24
    run "$mm" bvh convert "$tmp/synth/walk_1.40.bvh" "$tmp/auto$k.bvh" --scale auto
    run "$mm" bvh spans "$tmp/synth/idle.bvh"
    mv "$tmp/out" "$tmp/spans$k"
done
same "$tmp/conv1.bvh" "$tmp/conv2.bvh"
same "$tmp/auto1.bvh" "$tmp/auto2.bvh"
same "$tmp/spans1" "$tmp/spans2"

# mm simulate: scripted and random input, twice each, on databases built with 1 and 4 threads
for k in 1 4; do
    run "$mm" simulate "$tmp/s$k.mmdb" --input "$src/scripts/input/turn_90.json" --seconds 8 \
        -o "$tmp/turn$k.bvh" --metrics "$tmp/turn$k.json"
    run "$mm" simulate "$tmp/s$k.mmdb" --random 11 --seconds 8 -o "$tmp/rand$k.bvh" --metrics "$tmp/rand$k.json"
done
same "$tmp/turn1.bvh" "$tmp/turn4.bvh"
same "$tmp/rand1.bvh" "$tmp/rand4.bvh"
for m in turn rand; do
    no_clock "$tmp/${m}1.json" "$tmp/${m}1.m"
    no_clock "$tmp/${m}4.json" "$tmp/${m}4.m"
    same "$tmp/${m}1.m" "$tmp/${m}4.m"
done

# mm similarity: the audit and the tables on 1, 2 and 4 threads
for t in 1 2 4; do
    run "$mm" similarity "$db" --from walk_1.40 --to run_3.00 --window 4 --threads $t -o "$tmp/audit$t"
    run "$mm" similarity build "$db" -o "$tmp/tables$t" --threads $t
done
for t in 2 4; do
    same "$tmp/audit1" "$tmp/audit$t"
    same "$tmp/tables1" "$tmp/tables$t"
done

# mm render and mm simulate --video (PNG frames), when this build draws headless
if "$mm" render "$tmp/synth/walk_1.40.bvh" -o "$tmp/frames1" --size 64x48 --seconds 0.1 >/dev/null 2>&1; then
    run "$mm" render "$tmp/synth/walk_1.40.bvh" -o "$tmp/frames2" --size 64x48 --seconds 0.1
    same "$tmp/frames1" "$tmp/frames2"
    for k in 1 2; do
        run "$mm" simulate "$db" --random 5 --seconds 0.5 -o "$tmp/v$k.bvh" --metrics "$tmp/v$k.json" \
            --video "$tmp/video$k" --size 64x48 --video-fps 10
    done
    same "$tmp/video1" "$tmp/video2"
    same "$tmp/v1.bvh" "$tmp/v2.bvh"
else
    echo "mm render cannot draw here: render and --video left out"
fi

# real data, when it is there
if [ -n "$data" ] && [ -d "$data/lafan1" ]; then
    # its configs, made from the takes twice
    for k in 1 2; do
        run env MM="$mm" MM_DATA_DIR="$data" sh "$src/scripts/data_configs.sh" "$tmp/dc$k"
    done
    same "$tmp/dc1" "$tmp/dc2"
    for t in 1 2 4; do
        run "$mm" db build "$tmp/dc1/lafan1.json" -o "$tmp/l$t.mmdb" --threads $t
    done
    same "$tmp/l1.mmdb" "$tmp/l2.mmdb"
    same "$tmp/l1.mmdb" "$tmp/l4.mmdb"
    for k in 1 2; do
        run "$mm" simulate "$tmp/l$((k * 2)).mmdb" --random 3 --seconds 10 -o "$tmp/lr$k.bvh" \
            --metrics "$tmp/lr$k.json"
        no_clock "$tmp/lr$k.json" "$tmp/lr$k.m"
    done
    same "$tmp/lr1.bvh" "$tmp/lr2.bvh"
    same "$tmp/lr1.m" "$tmp/lr2.m"
else
    echo "MM_DATA_DIR/lafan1 not found: LAFAN1 left out"
fi
if [ -n "$data" ] && [ -d "$data/pfnn/network" ]; then
    for k in 1 2; do
        run "$mm" pfnn run --weights "$data/pfnn" --random 3 --seconds 2 -o "$tmp/p$k.bvh" --metrics "$tmp/p$k.json"
        no_clock "$tmp/p$k.json" "$tmp/p$k.m"
    done
    same "$tmp/p1.bvh" "$tmp/p2.bvh"
    same "$tmp/p1.m" "$tmp/p2.m"
else
    echo "MM_DATA_DIR/pfnn not found: mm pfnn run left out"
fi

finish test_determinism
