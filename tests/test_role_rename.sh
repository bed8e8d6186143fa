#!/bin/sh
# Roles reach every layer: the built-in set with every joint renamed (names that match none of the
# default joint names: LeftFoot -> b_toof_sx, Hips -> b_spih) and its config's roles, matched bones
# and mirror pairs renamed the same way, built and simulated, gives motion byte-identical to the
# original's (every number of the BVH's MOTION section), on a moves script with its scene, a
# random seed, and a run with distance matching and warping on. Foot locking must be on in both
# (foot_slide_raw_cm_s > 0: the feet were found). A runtime that looked a joint up by a literal
# name (LeftFoot ...) would lose it on the renamed skeleton and move differently.
# With MM_DATA_DIR (its lafan1/ folder), LAFAN1's walk and run takes are checked the same way.
# usage: test_role_rename.sh MM SOURCE_DIR
mm=$1
. "$2/scripts/json_get.sh"
src=$2
tmp=$(mktemp -d "${TMPDIR:-/tmp}/mm_rename.XXXXXX") || exit 1
trap 'rm -rf "$tmp"' EXIT
fail() {
    echo "test_role_rename: $*"
    exit 1
}

# rename_set CONFIG OUT_CONFIG OUT_DIR BVH...: the BVH files renamed into OUT_DIR and CONFIG's
# joint names renamed into OUT_CONFIG, its mirror pairs set to the new side suffixes.
rename_set() {
    config=$1
    out_config=$2
    out_dir=$3
    shift 3
    mkdir -p "$out_dir" || exit 1
    first=$1
    # every joint: Left/Right become a suffix, the rest is reversed and lowercased
    sed -n 's/^[[:space:]]*\(ROOT\|JOINT\)[[:space:]]\{1,\}\([^[:space:]]*\)[[:space:]]*$/\2/p' "$first" |
        awk '{
            n = $0; side = "";
            if (substr(n, 1, 4) == "Left") { side = "_sx"; n = substr(n, 5) }
            else if (substr(n, 1, 5) == "Right") { side = "_dx"; n = substr(n, 6) }
            r = ""; for (i = length(n); i >= 1; --i) r = r substr(n, i, 1);
            printf "%s b_%s%s\n", $0, tolower(r), side
        }' >"$tmp/names"
    [ -s "$tmp/names" ] || fail "no joints in $first"
    : >"$tmp/bvh.sed"
    : >"$tmp/cfg.sed"
    while read -r old new; do
        printf "%s\n" "s/^\\([[:space:]]*\\)\\(ROOT\\|JOINT\\)\\([[:space:]]\\{1,\\}\\)$old[[:space:]]*\$/\\1\\2\\3$new/" >>"$tmp/bvh.sed"
        echo "s/\"$old\"/\"$new\"/g" >>"$tmp/cfg.sed"
    done <"$tmp/names"
    for f in "$@"; do sed -f "$tmp/bvh.sed" "$f" >"$out_dir/$(basename "$f")" || exit 1; done
    grep -q '"mirror_pairs"' "$config" && fail "$config has mirror pairs: the test sets its own"
    sed -f "$tmp/cfg.sed" "$config" | sed '1s/^{/{ "mirror_pairs": [["_sx", "_dx"]],/' >"$out_config" || exit 1
    grep -q '"mirror_pairs"' "$out_config" || fail "could not set the mirror pairs of $out_config"
    # no old name is left in the skeletons
    awk '{ print $1 }' "$tmp/names" >"$tmp/old"
    for f in "$out_dir"/*.bvh; do
        grep -E '^[[:space:]]*(ROOT|JOINT)' "$f" | grep -qwF -f "$tmp/old" && fail "$f keeps an old joint name"
    done
}

# motion BVH: the lines after MOTION
motion() { sed -n '/^MOTION/,$p' "$1"; }

# same SET NAME ARGS...: simulates SET's two databases ($tmp/SET_a.mmdb, the original, and
# $tmp/SET_b.mmdb, renamed) with ARGS, compares the motion and the foot slide
same() {
    set=$1
    name=$1_$2
    shift 2
    for side in a b; do
        "$mm" simulate "$tmp/${set}_$side.mmdb" "$@" -o "$tmp/$side.bvh" --metrics "$tmp/$side.json" >/dev/null ||
            fail "$name: simulate failed on $tmp/${set}_$side.mmdb"
        motion "$tmp/$side.bvh" >"$tmp/$side.motion"
        slide=$(get foot_slide_raw_cm_s "$tmp/$side.json")
        awk -v s="$slide" 'BEGIN { exit !(s + 0 > 0) }' ||
            fail "$name: foot_slide_raw_cm_s of $side is '$slide' (feet not found: foot locking off)"
    done
    grep -q 'b_toof_sx' "$tmp/b.bvh" || fail "$name: the renamed set's BVH does not have the new names"
    [ "$(wc -l <"$tmp/a.motion")" -gt 10 ] || fail "$name: no motion"
    cmp -s "$tmp/a.motion" "$tmp/b.motion" ||
        fail "$name: the renamed skeleton moves differently ($(cmp "$tmp/a.motion" "$tmp/b.motion" | head -1))"
    echo "test_role_rename: $name: $(wc -l <"$tmp/a.motion") lines of motion identical, foot_slide_raw_cm_s $slide"
}

# build SET CONFIG_A DATA_A CONFIG_B DATA_B: the two databases of SET
build() {
    "$mm" db build "$2" --data "$3" -o "$tmp/$1_a.mmdb" >"$tmp/build.log" 2>&1 ||
        { cat "$tmp/build.log"; fail "db build of $2 failed"; }
    "$mm" db build "$4" --data "$5" -o "$tmp/$1_b.mmdb" >"$tmp/build.log" 2>&1 ||
        { cat "$tmp/build.log"; fail "db build of $4 (renamed) failed"; }
}

# the built-in set: a moves script with its scene (the jump: moves' hands and feet), a random
# seed, and strafing with distance matching and stride and orientation warping on
"$mm" synth "$tmp/set" >/dev/null || fail "mm synth failed"
rename_set "$src/configs/synth.json" "$tmp/renamed.json" "$tmp/renamed" "$tmp/set"/*.bvh
build synth "$src/configs/synth.json" "$tmp/set" "$tmp/renamed.json" "$tmp/renamed"
same synth moves --input "$src/scripts/input/moves_jump_gap.json" --scene "$src/scenes/jump_gap.json" --seconds 12
same synth seed --random 7 --seconds 30
same synth warped --input "$src/scripts/input/strafe.json" --seconds 15 --distance-matching on --warping on
# mm metrics of the motion: the roles from each database, or from the renamed config against the
# original's default names, give the same numbers; without roles the renamed feet are not found
"$mm" metrics "$tmp/a.bvh" --db "$tmp/synth_a.mmdb" -o "$tmp/ma_db.json" || fail "mm metrics --db failed"
"$mm" metrics "$tmp/b.bvh" --db "$tmp/synth_b.mmdb" -o "$tmp/mb_db.json" || fail "mm metrics --db failed (renamed)"
# (the metrics name the joints where the worst happened: the original's names, renamed, are the
# renamed set's)
sed -f "$tmp/cfg.sed" "$tmp/ma_db.json" >"$tmp/ma_db_renamed.json" || fail "renaming the metrics failed"
cmp -s "$tmp/ma_db_renamed.json" "$tmp/mb_db.json" || fail "mm metrics --db: the renamed motion measures differently"
"$mm" metrics "$tmp/a.bvh" --scale 1 -o "$tmp/ma.json" || fail "mm metrics failed"
"$mm" metrics "$tmp/b.bvh" --scale 1 --config "$tmp/renamed.json" -o "$tmp/mb.json" || fail "mm metrics --config failed"
sed -f "$tmp/cfg.sed" "$tmp/ma.json" >"$tmp/ma_renamed.json" || fail "renaming the metrics failed"
cmp -s "$tmp/ma_renamed.json" "$tmp/mb.json" || fail "mm metrics --config: the renamed motion measures differently"
"$mm" metrics "$tmp/b.bvh" --scale 1 -o "$tmp/mb_names.json" || fail "mm metrics failed (renamed, no roles)"
for key in foot_slide_height_cm_s head_p50_cm; do
    [ "$(get $key "$tmp/ma.json")" != null ] || fail "mm metrics: no $key on the original"
    [ "$(get $key "$tmp/mb_names.json")" = null ] || fail "mm metrics: $key of the renamed motion without its roles"
done
if "$mm" metrics "$tmp/a.bvh" --scale 1 --config "$tmp/renamed.json" >/dev/null 2>"$tmp/err"; then
    fail "mm metrics --config took a config whose roles the file does not have"
fi
grep -q "no joint 'b_toof_sx' (roles.left_foot of the config)" "$tmp/err" || fail "mm metrics --config: $(cat "$tmp/err")"
echo "test_role_rename: synth_metrics: the same with --db, and with --config against the default names"

# LAFAN1, when MM_DATA_DIR has it: a walking take and its mirror with configs/mocap.json's
# settings (distance matching and warping on), and the climbs, drops and jumps `mm moves detect`
# finds in an obstacles take (detected on each set with its own config: the same spans); a climb
# plants a hand (moves' hand roles)
walk=${MM_DATA_DIR:-}/lafan1/walk4_subject1.bvh
obstacles=${MM_DATA_DIR:-}/lafan1/obstacles1_subject1.bvh
if [ -n "${MM_DATA_DIR:-}" ] && [ -f "$walk" ] && [ -f "$obstacles" ]; then
    sed '1s/^{$/{ "clips": [{"name": "walk", "file": "walk4_subject1.bvh", "loop": false, "mirror": true}],/' \
        "$src/configs/mocap.json" >"$tmp/lafan1.json"
    rename_set "$tmp/lafan1.json" "$tmp/lafan1_renamed.json" "$tmp/lafan1_renamed" "$walk" "$obstacles"
    for v in lafan1 lafan1_renamed; do
        printf '{"extends": "%s.json", "tags": ["Jump", "VaultLow", "VaultHigh", "Climb", "Drop", "TakeOff", "HandPlant", "Landing"]}\n' \
            "$v" >"$tmp/${v}_moves.json"
        take=$obstacles
        [ "$v" = lafan1 ] || take=$tmp/lafan1_renamed/obstacles1_subject1.bvh
        "$mm" moves detect "$take" --config "$tmp/$v.json" --write "$tmp/${v}_moves.json" >"$tmp/$v.moves" ||
            fail "mm moves detect on $take failed"
        sed 's/^[^:]*: //' "$tmp/$v.moves" >"$tmp/$v.spans"
    done
    cmp -s "$tmp/lafan1.spans" "$tmp/lafan1_renamed.spans" || fail "the renamed take's moves are not the original's"
    grep -q '^climb' "$tmp/lafan1.moves" || fail "no climb detected in $obstacles"
    build lafan1 "$tmp/lafan1_moves.json" "$MM_DATA_DIR/lafan1" "$tmp/lafan1_renamed_moves.json" "$tmp/lafan1_renamed"
    same lafan1 climb --input "$src/scripts/input/moves_walk.json" --scene "$src/scenes/high_wall_short.json" --seconds 10
    grep -q '"kind": "climb"' "$tmp/a.json" || fail "lafan1_climb: no climb played"
    same lafan1 zigzag --input "$src/scripts/input/zigzag.json" --seconds 20
    same lafan1 seed --random 3 --seconds 20
else
    echo "test_role_rename: no \$MM_DATA_DIR/lafan1: the built-in set alone"
fi
echo "test_role_rename: passed"
