#!/bin/sh
# Motion matching (mm simulate) against the neural controller (mm pfnn run) on every shipped input
# script, with the same metrics; prints a Markdown table (the one in docs/pfnn.md).
# usage: scripts/compare_controllers.sh [SECONDS]     (needs MM_DATA_DIR with lafan1/ and pfnn/)
set -eu
cd "$(dirname "$0")/.."
seconds=${1:-20}
: "${MM_DATA_DIR:?set MM_DATA_DIR to the folder holding lafan1/ and pfnn/}"
mm=build/mm
out=out/compare
mkdir -p "$out"
if [ ! -f "$out/lafan1.mmdb" ]; then
    scripts/data_configs.sh "$out" >/dev/null
    "$mm" db build "$out/lafan1.json" -o "$out/lafan1.mmdb" >/dev/null
fi
. scripts/json_get.sh # get KEY FILE, fmt VALUE [DECIMALS]
echo "| script | controller | foot slide cm/s | traj err cm | heading err deg | response s | max pop cm | frame us (median) | memory MiB |"
echo "|---|---|---|---|---|---|---|---|---|"
for script in scripts/input/*.json; do
    name=$(basename "$script" .json)
    "$mm" simulate "$out/lafan1.mmdb" --input "$script" --seconds "$seconds" -o "$out/$name.mm.bvh" \
        --metrics "$out/$name.mm.json" >/dev/null
    "$mm" pfnn run --input "$script" --seconds "$seconds" -o "$out/$name.pfnn.bvh" \
        --metrics "$out/$name.pfnn.json" >/dev/null
    for kind in mm pfnn; do
        j=$out/$name.$kind.json
        label="motion matching (LAFAN1)"
        [ "$kind" = pfnn ] && label="neural (PFNN, cubic)"
        printf '| %s | %s | %s | %s | %s | %s | %s | %s | %s |\n' "$name" "$label" \
            "$(fmt "$(get foot_slide_cm_s "$j")")" "$(fmt "$(get traj_err_cm "$j")")" \
            "$(fmt "$(get heading_err_deg "$j")")" "$(fmt "$(get response_s "$j")")" \
            "$(fmt "$(get max_pop_cm "$j")")" "$(fmt "$(get frame_median_us "$j")")" "$(fmt "$(get memory_mb "$j")")"
    done
done
