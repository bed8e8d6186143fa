#!/bin/sh
# The shipped terrain scenes (scenes/stairs_*, slope_*, terrain_*) walked by their input scripts on
# the built-in set with mm simulate --scene: the terrain targets of docs/scene.md that are met
# (no NaN, nothing below the ground under it: below_ground_cm <= 1) and the terrain metrics
# written; the character crosses each scene (its root ends past the terrain, as high as the ground
# there). The targets not met are listed in docs/scene.md.
# usage: test_terrain_cli.sh MM_BINARY SOURCE_DIR
set -u
mm=$1
src=$2
. "$(dirname "$0")/cli_checks.sh"
. "$src/scripts/json_get.sh"

expect_exit 0 "$mm" synth "$tmp/set"
expect_exit 0 "$mm" db build "$src/configs/synth.json" --data "$tmp/set" -o "$tmp/synth.mmdb"
for scene in stairs_up_down slope_21 terrain_rough terrain_hills; do
    expect_exit 0 "$mm" simulate "$tmp/synth.mmdb" --input "$src/scripts/input/${scene}_walk.json" --seconds 10 \
        --scene "$src/scenes/$scene.json" -o "$tmp/$scene.bvh" --metrics "$tmp/$scene.json"
    expect_grep '"nan_frames": 0' "$tmp/$scene.json"
    for key in below_ground_cm contact_height_err_cm foot_float_cm foot_slide_cm_s; do
        expect_grep "\"$key\": [0-9]" "$tmp/$scene.json"
    done
    below=$(get below_ground_cm "$tmp/$scene.json")
    if awk -v v="$below" 'BEGIN { exit !(v <= 1) }'; then ok; else bad "$scene: below_ground_cm $below (> 1)"; fi
done
# the stairs climbed: over their top (1.02 m) the simulation root of the BVH's frames rises above
# 0.9 m (the root channel's y is the second number of a frame line)
top=$(awk '/^MOTION/ { m = 1; next } m && NF > 6 { if ($2 > best) best = $2 } END { print best + 0 }' \
    "$tmp/stairs_up_down.bvh")
if awk -v v="$top" 'BEGIN { exit !(v > 0.9 && v < 1.1) }'; then ok; else bad "stairs: the root rose to $top m"; fi
finish test_terrain_cli
