#!/bin/sh
# The database configs for the motion capture in $MM_DATA_DIR, made from the takes themselves (the
# repository holds no data: only the settings in configs/mocap.json and the tools that read takes):
#   OUTDIR/lafan1.json        locomotion: every walk and multipleActions take, split into
#                             locomotion and idle clips by `mm bvh spans` (docs/database.md)
#   OUTDIR/lafan1_moves.json  lafan1.json plus the jumps, vaults, climbs and drops that
#                             `mm moves detect` finds in the obstacles and multipleActions takes
#                             (docs/moves_data.md)
# Prints nothing to do and exits 0 when $MM_DATA_DIR/lafan1 is not there.
# usage: scripts/data_configs.sh OUTDIR      (MM: the mm program, default build/mm)
set -eu
out=${1:?usage: scripts/data_configs.sh OUTDIR}
src=$(cd "$(dirname "$0")/.." && pwd)
mm=${MM:-$src/build/mm}
data=${MM_DATA_DIR:-}
if [ -z "$data" ] || [ ! -d "$data/lafan1" ]; then
    echo "no \$MM_DATA_DIR/lafan1: no data configs to make"
    exit 0
fi
mkdir -p "$out"
tmp=$out/.data_configs.$$
mkdir -p "$tmp"
trap 'rm -rf "$tmp"' EXIT

printf '{\n  "extends": "%s/configs/mocap.json"\n}\n' "$src" >"$tmp/lafan1.json"
for take in walk4_subject1 multipleActions1_subject1 multipleActions1_subject2 multipleActions1_subject3 \
    multipleActions1_subject4; do
    "$mm" bvh spans "$data/lafan1/$take.bvh" --config "$src/configs/mocap.json" --write "$tmp/lafan1.json" >/dev/null
done

# the tags listed first, so that their order does not depend on which take has which move
printf '{\n  "extends": "lafan1.json",\n  "tags": ["Jump", "VaultLow", "VaultHigh", "Climb", "Drop", "TakeOff", "HandPlant", "Landing"]\n}\n' \
    >"$tmp/lafan1_moves.json"
for take in obstacles1_subject1 obstacles1_subject2 obstacles1_subject5 obstacles3_subject3 obstacles3_subject4 \
    multipleActions1_subject1 multipleActions1_subject2 multipleActions1_subject3 multipleActions1_subject4; do
    "$mm" moves detect "$data/lafan1/$take.bvh" --config "$tmp/lafan1.json" --write "$tmp/lafan1_moves.json" >/dev/null
done
mv "$tmp/lafan1.json" "$tmp/lafan1_moves.json" "$out/"
echo "wrote $out/lafan1.json, $out/lafan1_moves.json"
