#!/bin/sh
# The metrics of mm simulate (docs/metrics.md) for every shipped input script on one database, as
# a Markdown table: foot slide (final and before IK), trajectory error, response, the largest pop
# against the database's own, transitions per second.
# usage: scripts/metrics_table.sh DB.mmdb [SECONDS (default 30)] [OUTDIR (default out/metrics)]
set -eu
cd "$(dirname "$0")/.."
db=${1:?usage: scripts/metrics_table.sh DB.mmdb [SECONDS] [OUTDIR]}
seconds=${2:-30}
out=${3:-out/metrics}
mm=${MM:-build/mm}
mkdir -p "$out"
. scripts/json_get.sh # get KEY FILE, fmt VALUE [DECIMALS]
echo "| script | foot slide cm/s | raw cm/s | traj err cm | response s | max pop cm | db pop cm | transitions/s |"
echo "|---|---|---|---|---|---|---|---|"
for script in scripts/input/*.json; do
    name=$(basename "$script" .json)
    j=$out/$name.json
    "$mm" simulate "$db" --input "$script" --seconds "$seconds" -o "$out/$name.bvh" --metrics "$j" >/dev/null
    printf '| %s | %s | %s | %s | %s | %s | %s | %s |\n' "$name" \
        "$(fmt "$(get foot_slide_cm_s "$j")")" "$(fmt "$(get foot_slide_raw_cm_s "$j")")" \
        "$(fmt "$(get traj_err_cm "$j")")" "$(fmt "$(get response_s "$j")" 2)" \
        "$(fmt "$(get max_pop_cm "$j")")" "$(fmt "$(get db_max_pop_cm "$j")")" \
        "$(fmt "$(get transitions_per_s "$j")")"
done
