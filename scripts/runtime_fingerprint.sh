#!/bin/sh
# Fingerprints of the runtime's output: the SHA-256 of the BVH that mm simulate writes for every
# shipped input script and for random input on a few seeds, on the built-in set and (when
# MM_DATA_DIR holds LAFAN1) on LAFAN1, with the moves scripts on their scenes. A change to the
# runtime that is meant to keep the character the same must print the same lines before and after;
# `diff` the two outputs.
# usage: scripts/runtime_fingerprint.sh [OUTDIR (default out/fingerprint)] [SECONDS (default 20)]
#   MM: the mm program (default build/mm); SEEDS: the random seeds (default "1 2 3 4 5")
set -eu
cd "$(dirname "$0")/.."
out=${1:-out/fingerprint}
seconds=${2:-20}
mm=${MM:-build/mm}
seeds=${SEEDS:-1 2 3 4 5}
mkdir -p "$out"

databases="synth"
if [ ! -f "$out/synth.mmdb" ]; then
    "$mm" synth "$out/synth_clips" >/dev/null
    "$mm" db build configs/synth.json --data "$out/synth_clips" -o "$out/synth.mmdb" >/dev/null
fi
if [ -n "${MM_DATA_DIR:-}" ] && [ -d "$MM_DATA_DIR/lafan1" ]; then
    if [ ! -f "$out/lafan1.mmdb" ]; then
        scripts/data_configs.sh "$out/configs" >/dev/null
        "$mm" db build "$out/configs/lafan1_moves.json" --data "$MM_DATA_DIR" -o "$out/lafan1.mmdb" >/dev/null
    fi
    databases="synth lafan1"
fi

# the moves scripts on their scenes (docs/moves.md, "Scenes")
moves_runs="moves_walk:low_wall_short moves_walk:low_wall_long moves_walk:high_wall_short
moves_walk:high_wall_long moves_walk:drop_auto moves_walk:joined_walls moves_drop_key:drop_key
moves_jump_wall:jump_onto_wall moves_jump_gap:jump_gap moves_stop_ledge:drop_auto"

for db in $databases; do
    for script in scripts/input/*.json; do
        name=$(basename "$script" .json)
        case $name in moves_*) continue ;; esac
        bvh=$out/$db.$name.bvh
        "$mm" simulate "$out/$db.mmdb" --input "$script" --seconds "$seconds" -o "$bvh" \
            --metrics "$out/$db.$name.json" >/dev/null
        echo "$db $name $(sha256sum "$bvh" | cut -c1-16)"
    done
    for run in $moves_runs; do
        name=${run%%:*}.${run#*:}
        bvh=$out/$db.$name.bvh
        "$mm" simulate "$out/$db.mmdb" --input "scripts/input/${run%%:*}.json" --scene "scenes/${run#*:}.json" \
            --seconds "$seconds" -o "$bvh" --metrics "$out/$db.$name.json" >/dev/null
        echo "$db $name $(sha256sum "$bvh" | cut -c1-16)"
    done
    for name in demo zigzag; do # the crossfade mixer
        bvh=$out/$db.$name.crossfade.bvh
        "$mm" simulate "$out/$db.mmdb" --input "scripts/input/$name.json" --transition crossfade \
            --seconds "$seconds" -o "$bvh" --metrics "$out/$db.$name.crossfade.json" >/dev/null
        echo "$db $name.crossfade $(sha256sum "$bvh" | cut -c1-16)"
    done
    for seed in $seeds; do
        bvh=$out/$db.random$seed.bvh
        "$mm" simulate "$out/$db.mmdb" --random "$seed" --seconds "$seconds" -o "$bvh" \
            --metrics "$out/$db.random$seed.json" >/dev/null
        echo "$db random$seed $(sha256sum "$bvh" | cut -c1-16)"
    done
done
