#!/bin/sh
# End-to-end tests of the mm program: output format, exit codes, error messages.
# usage: test_cli.sh MM_BINARY TEST_DATA_DIR
set -u
mm=$1
data=$2
. "$(dirname "$0")/cli_checks.sh"
# expect_value FILE JOINT X Y Z : the fk line of JOINT is within 1e-6 of X Y Z (fk is float: 4.5 cos 90 degrees
# prints as -2.2e-08)
expect_value() {
    if awk -v j="$2" -v x="$3" -v y="$4" -v z="$5" '
        function abs(v) { return v < 0 ? -v : v }
        $1 == j { found = 1; if (abs($2 - x) > 1e-6 || abs($3 - y) > 1e-6 || abs($4 - z) > 1e-6) off = 1 }
        END { exit found && !off ? 0 : 1 }' "$1"; then ok; else bad "fk $2 is not ($3 $4 $5):"; cat "$1"; fi
}
# expect_speeds FILE KIND DIRECTION P10 P50 P90 : mm db info's speed line of KIND gives DIRECTION's
# percentiles within 0.011 m/s (printed to 0.01); '*' skips one
expect_speeds() {
    if awk -v k="$2" -v d="$3" -v a="$4" -v b="$5" -v c="$6" '
        function abs(v) { return v < 0 ? -v : v }
        $1 == k && $3 == "frames" { for (i = 1; i <= NF; ++i) if ($i == d) { found = 1
            if ((a != "*" && abs($(i + 1) - a) > 0.011) || (b != "*" && abs($(i + 2) - b) > 0.011) ||
                (c != "*" && abs($(i + 3) - c) > 0.011)) off = 1 } }
        END { exit found && !off ? 0 : 1 }' "$1"; then ok; else bad "speeds of $2 $3 are not $4 $5 $6:"; cat "$1"; fi
}

chain=$data/bvh/chain2.bvh

expect_exit 0 "$mm" version
expect_grep "^mm " "$tmp/out"
expect_exit 2 "$mm"
expect_exit 2 "$mm" no-such-command
expect_grep "unknown command" "$tmp/err"

# info
expect_exit 0 "$mm" bvh info "$chain"
expect_grep "joints: *2 (+ 1 End Sites)" "$tmp/out"
expect_grep "frames: *3" "$tmp/out"
expect_grep "fps: *2 " "$tmp/out"
expect_grep "duration: *1.000 s" "$tmp/out"
if [ -n "${MM_DATA_DIR:-}" ]; then
    # a CMU-skeleton take: the header and first 4 frames of a file of the shared data
    awk 'f >= 4 { exit } /^Frames:/ { print "Frames: 4"; next } { print } f >= 0 { f++ } /^Frame Time:/ { f = 0 }' \
        f=-1 "$MM_DATA_DIR/pfnn/bvh/LocomotionFlat09_000.bvh" >"$tmp/cmu.bvh"
    expect_exit 0 "$mm" bvh info "$tmp/cmu.bvh" --json
    expect_grep '"joints": 31' "$tmp/out"
    expect_grep '"frames": 4' "$tmp/out"
    expect_grep '"orders": {"ZYX": 31}' "$tmp/out"
    expect_grep '"unit": "CMU units"' "$tmp/out"
fi
expect_exit 2 "$mm" bvh info "$chain" --bogus

# fk: one line per joint, End Sites excluded, values in file units
expect_exit 0 "$mm" bvh fk "$chain" --frame 1
if [ "$(wc -l <"$tmp/out")" -eq 2 ]; then ok; else bad "fk printed $(wc -l <"$tmp/out") lines, wanted 2"; fi
expect_value "$tmp/out" Base 10 0 0
expect_value "$tmp/out" Tip 9 0 0
expect_exit 0 "$mm" bvh fk "$chain" --frame 2
expect_value "$tmp/out" Tip 0 6 0
expect_exit 1 "$mm" bvh fk "$chain" --frame 3
expect_grep "out of range" "$tmp/err"
if [ ! -s "$tmp/out" ]; then ok; else bad "fk out of range printed to stdout"; fi
expect_exit 2 "$mm" bvh fk "$chain" --frame -1
expect_exit 2 "$mm" bvh fk "$chain"
expect_exit 1 "$mm" bvh fk "$tmp/missing.bvh" --frame 0
expect_grep "missing.bvh" "$tmp/err"

# the locale of the environment does not change the output
LC_ALL=de_DE.UTF-8 "$mm" bvh fk "$data/bvh/mobu_style.bvh" --frame 0 >"$tmp/de" 2>/dev/null
"$mm" bvh fk "$data/bvh/mobu_style.bvh" --frame 0 >"$tmp/c"
if cmp -s "$tmp/de" "$tmp/c"; then ok; else bad "fk output depends on the locale"; fi

# convert: order, scale, resampling
expect_exit 0 "$mm" bvh convert "$chain" "$tmp/c.bvh" --order XYZ --scale 0.5 --fps 4
expect_exit 0 "$mm" bvh info "$tmp/c.bvh"
expect_grep "frames: *5" "$tmp/out"
expect_grep "XYZ x2" "$tmp/out"
expect_exit 0 "$mm" bvh fk "$tmp/c.bvh" --frame 2
expect_value "$tmp/out" Tip 4.5 0 0
expect_exit 2 "$mm" bvh convert "$chain" "$tmp/x.bvh" --order QQQ
expect_exit 2 "$mm" bvh convert "$chain" "$tmp/x.bvh" --scale -1
printf 'HIERARCHY\nROOT A\n{\n OFFSET 0 0 0\n CHANNELS 3 Zrotation Yrotation Xrotation\n JOINT B\n {\n  OFFSET 0 0.3 0\n  CHANNELS 0\n }\n}\nMOTION\nFrames: 1\nFrame Time: 0.1\n0 0 0\n' >"$tmp/small.bvh"
expect_exit 1 "$mm" bvh convert "$tmp/small.bvh" "$tmp/x.bvh" --scale auto
expect_grep "unit" "$tmp/err"
if [ ! -e "$tmp/x.bvh" ]; then ok; else bad "a failed convert left $tmp/x.bvh behind"; fi
expect_exit 1 "$mm" bvh convert "$chain" "$tmp/no/such/dir/x.bvh"
if [ -z "$(ls "$tmp" | grep '\.tmp')" ]; then ok; else bad "temporary file left behind"; fi

# errors name the file, line and column
printf 'HIERARCHY\nROOT A\n{\n  OFFSET 0 0 0\n  CHANNELS 3 Xrotation Yrotation Zrotation\n}\nMOTION\nFrames: 1\nFrame Time: 0.1\n1 2 nan\n' >"$tmp/nan.bvh"
expect_exit 1 "$mm" bvh info "$tmp/nan.bvh"
expect_grep "nan.bvh:10:5:" "$tmp/err"
expect_grep "not a finite number" "$tmp/err"

# config explain / check
expect_exit 0 "$mm" config explain interval
expect_grep "seed's Interval" "$tmp/out"
expect_exit 1 "$mm" config explain no_such_field
if [ -n "${MM_DATA_DIR:-}" ]; then
    expect_exit 0 "$mm" config check "$data/configs/cmu_style.json"
    expect_grep "1 clips" "$tmp/out"
fi
printf '{"clips": [{"file": "missing.bvh"}]}' >"$tmp/missing.json"
expect_exit 1 "$mm" config check "$tmp/missing.json"
expect_grep "missing.bvh" "$tmp/err"
printf '{"interval": 0.02,\n "clipz": []}' >"$tmp/typo.json"
expect_exit 1 "$mm" config check "$tmp/typo.json"
expect_grep "typo.json:2:11: clipz: unknown field" "$tmp/err"

# db build / info / dump: deterministic bytes, the JSON fields users rely on
if [ -n "${MM_DATA_DIR:-}" ]; then # the config reads a take of the shared data
    expect_exit 0 "$mm" db build "$data/configs/cmu_style.json" -o "$tmp/a.mmdb"
    expect_grep "8 frames, 27 dims, 2 clips" "$tmp/out"
    expect_exit 0 "$mm" db build "$data/configs/cmu_style.json" -o "$tmp/b.mmdb"
    if cmp -s "$tmp/a.mmdb" "$tmp/b.mmdb"; then ok; else bad "two builds of one config differ"; fi
    expect_exit 0 "$mm" db info "$tmp/a.mmdb" --json
    expect_grep '"frames": 8, "dims": 27' "$tmp/out"
    expect_grep '"clips": 2' "$tmp/out"
    expect_grep '"clip_names": \["cmu", "cmu_mirror"\]' "$tmp/out"
    expect_grep '"tags": \["DoNotUse"\]' "$tmp/out"
    expect_grep '"bytes": ' "$tmp/out"
    expect_exit 0 "$mm" db dump "$tmp/a.mmdb"
    cp "$tmp/out" "$tmp/dump1"
    expect_exit 0 "$mm" db dump "$tmp/b.mmdb"
    if cmp -s "$tmp/out" "$tmp/dump1"; then ok; else bad "dumps differ"; fi
    expect_grep "^clip 1 cmu_mirror" "$tmp/out"
    head -c 1000 "$tmp/a.mmdb" >"$tmp/short.mmdb"
    expect_exit 1 "$mm" db info "$tmp/short.mmdb"
    expect_grep "short.mmdb" "$tmp/err"
fi
expect_exit 1 "$mm" db build "$tmp/missing.json" -o "$tmp/c.mmdb"
if [ ! -e "$tmp/c.mmdb" ]; then ok; else bad "a failed build left its output"; fi

# the main job: the built-in motion set and its database config
expect_exit 0 "$mm" synth "$tmp/synth/set"
expect_exit 0 "$mm" db build "$data/../../configs/synth.json" --data "$tmp/synth/set" -o "$tmp/synth.mmdb"
# its diagnostics (docs/database.md, "Diagnostics"): none; the run's sideways and backward speeds are
# the untagged sidesteps' and backward walk's, which both gaits play
expect_grep '^warnings: *0' "$tmp/out"
expect_grep '^  run  side .* covered$' "$tmp/out"
expect_grep '^  run  backward .* covered$' "$tmp/out"
expect_grep '^  walk forward *1.50 m/s default .* covered$' "$tmp/out"
expect_exit 0 "$mm" db info "$tmp/synth.mmdb" --json
expect_grep '"clips": 65' "$tmp/out"
expect_grep '"gait_speeds": \[{"gait": "walk", "direction": "forward", "speed": 1.5, "source": "default", ' "$tmp/out"
expect_grep '"warnings": \[\]' "$tmp/out"
expect_grep '"speeds": \[{"name": "Walk", "frames": [0-9]*, "still": [0-9]*, "forward": {"frames": [1-9][0-9]*, "p10": 1\.0[45]' "$tmp/out"
expect_grep '"tags": \["DoNotUse", "Jump", "Walk", "Run"\]' "$tmp/out"
expect_grep '"distance": {"segments": [0-9]*, "stops": [1-9][0-9]*, "pivots": [0-9]*, "no_stop": [0-9]*, "starts": [1-9]' "$tmp/out"
expect_exit 0 "$mm" db info "$tmp/synth.mmdb"
expect_grep '^distance: .* segments (.* stops, .* pivots, .* without a stop), .* clips start from rest' "$tmp/out"
# speeds by gait tag, against the built-in set's construction (src/synth/synth_set.c): the walk
# loops at 1.05 to 1.75 m/s and the run loops at 3.0, 3.8 and 4.6 m/s hold their speed, so the
# forward p10 and p90 are the slowest and fastest walk loop's and the fastest run loop's (the run
# p10 is lower: the loop of sharp run turns slows to 2.7 m/s in them); the backward walk is a
# loop at 1.0 m/s and the backstep holds 1.0 m/s between its start and stop (untagged: locomotion);
# the idle never moves
expect_speeds "$tmp/out" Walk forward 1.05 '*' 1.75
expect_speeds "$tmp/out" locomotion backward '*' 1.00 1.00
expect_speeds "$tmp/out" Run forward '*' '*' 4.60
expect_grep '^  idle  *480 frames  *480 still  forward  *-  *-  *- (0)' "$tmp/out"
expect_grep '^  clip  35 walk_stop .* 1 stop$' "$tmp/out"
expect_exit 1 "$mm" db build "$data/../../configs/synth.json" -o "$tmp/nosynth.mmdb"

expect_grep "idle.bvh" "$tmp/err"
# mirroring a skeleton with a side's joint and no partner is refused, naming both; unmirrored it builds
mkdir -p "$tmp/onehand"
sed 's/JOINT RightHand/JOINT RightPalm/' "$tmp/synth/set/walk_1.40.bvh" >"$tmp/onehand/walk.bvh"
printf '{"scale": 1, "roles": {"right_hand": "RightPalm"}, "clips": [{"file": "walk.bvh", "mirror": %s}]}\n' true \
    >"$tmp/onehand/mirror.json"
printf '{"scale": 1, "roles": {"right_hand": "RightPalm"}, "clips": [{"file": "walk.bvh", "mirror": %s}]}\n' false \
    >"$tmp/onehand/plain.json"
expect_exit 1 "$mm" db build "$tmp/onehand/mirror.json" -o "$tmp/onehand.mmdb"
expect_grep "cannot mirror: joint 'LeftHand' has no partner: no joint is named 'RightHand'" "$tmp/err"
expect_exit 0 "$mm" db build "$tmp/onehand/plain.json" -o "$tmp/onehand.mmdb"

# db search: the JSON contract, methods agree, filters, errors
expect_exit 0 "$mm" db search "$tmp/synth.mmdb" --frame 500 --traj-from 3000 --top 3 --json
expect_grep '^{"query": {"frame": 500, "traj_from": 3000, "method": "fast"}, "results": \[{"frame": ' "$tmp/out"
expect_grep '"clip": "[a-z_0-9.]*", "clip_index": [0-9]*, "time": ' "$tmp/out"
expect_grep '"terms": {"pose_position": [-0-9.e]*, "pose_velocity": [-0-9.e]*, "root_velocity": [-0-9.e]*, "traj_position": [-0-9.e]*, "traj_direction": [-0-9.e]*}' "$tmp/out"
if [ "$(grep -o '"frame": ' "$tmp/out" | wc -l)" -eq 4 ]; then ok; else bad "--top 3 did not give 3 results"; fi
cp "$tmp/out" "$tmp/fast.json"
expect_exit 0 "$mm" db search "$tmp/synth.mmdb" --frame 500 --traj-from 3000 --top 3 --json --method brute
sed 's/"method": "brute"/"method": "fast"/' "$tmp/out" >"$tmp/brute.json"
if cmp -s "$tmp/fast.json" "$tmp/brute.json"; then ok; else bad "fast and brute give different results"; fi
expect_exit 0 "$mm" db search "$tmp/synth.mmdb" --frame 500 --require Jump --type any
expect_grep "jump" "$tmp/out"
expect_exit 0 "$mm" db search "$tmp/synth.mmdb" --frame 500 --no-bias --exclude Jump
expect_exit 1 "$mm" db search "$tmp/synth.mmdb" --frame 500 --require NoSuchTag
expect_grep "no tag 'NoSuchTag'" "$tmp/err"
expect_exit 1 "$mm" db search "$tmp/synth.mmdb" --frame 99999
expect_grep "out of range" "$tmp/err"
expect_exit 2 "$mm" db search "$tmp/synth.mmdb" --frame 1 --method slow
expect_exit 2 "$mm" db search "$tmp/synth.mmdb"

# bvh spans --write: each take's locomotion and idle spans become two clips of a config, the same
# spans as printed (a walk that stops: walking from frame 0, standing to the end; a start the
# reverse); writing again changes nothing; the config builds
set_dir=$tmp/synth/set
printf '{\n  "clips": []\n}\n' >"$tmp/spans.json"
for take in walk_stop walk_start; do
    expect_exit 0 "$mm" bvh spans "$set_dir/$take.bvh"
    cp "$tmp/out" "$tmp/$take.spans"
    expect_exit 0 "$mm" bvh spans "$set_dir/$take.bvh" --write "$tmp/spans.json"
done
expect_grep '"locomotion": \[\[0, [0-9]*\]\]' "$tmp/walk_stop.spans"
expect_grep '"idle": \[\[[0-9]*, 301\]\]' "$tmp/walk_stop.spans"
expect_grep '"idle": \[\[0, [0-9]*\]\]' "$tmp/walk_start.spans"
expect_grep '"locomotion": \[\[[0-9]*, 301\]\]' "$tmp/walk_start.spans"
# the written clips hold the printed ranges: walk_stop, walk_stop_idle (type idle), walk_start, ...
has() { if grep -qF "$1" "$2"; then ok; else bad "'$1' not in $2:"; cat "$2"; fi; }
tr -d ' \n' <"$tmp/spans.json" >"$tmp/spans.flat"
for take in walk_stop walk_start; do
    loco=$(tr -d ' \n' <"$tmp/$take.spans" | sed 's/.*"locomotion":\(\[[^a-z"{}]*\]\)[,}].*/\1/')
    idle=$(tr -d ' \n' <"$tmp/$take.spans" | sed 's/.*"idle":\(\[[^a-z"{}]*\]\)[,}].*/\1/')
    has "{\"name\":\"$take\",\"file\":\"$set_dir/$take.bvh\",\"ranges\":$loco,\"mirror\":true}" "$tmp/spans.flat"
    has "{\"name\":\"${take}_idle\",\"file\":\"$set_dir/$take.bvh\",\"ranges\":$idle,\"type\":\"idle\",\"mirror\":true}" \
        "$tmp/spans.flat"
done
cp "$tmp/spans.json" "$tmp/spans.before"
expect_exit 0 "$mm" bvh spans "$set_dir/walk_stop.bvh" --write "$tmp/spans.json"
if cmp -s "$tmp/spans.json" "$tmp/spans.before"; then ok; else bad "writing the same spans again changed the config"; fi
expect_exit 0 "$mm" bvh spans "$set_dir/idle.bvh" --write "$tmp/spans.json" --as standing --no-mirror
tr -d ' \n' <"$tmp/spans.json" >"$tmp/spans.flat"
has "{\"name\":\"standing_idle\",\"file\":\"$set_dir/idle.bvh\",\"ranges\":[[0,480]],\"type\":\"idle\"}" "$tmp/spans.flat"
if grep -q '"name":"standing"' "$tmp/spans.flat"; then bad "a take without locomotion got a locomotion clip"; else ok; fi
expect_exit 0 "$mm" db build "$tmp/spans.json" --data "$set_dir" -o "$tmp/spans.mmdb"
expect_exit 0 "$mm" db info "$tmp/spans.mmdb"
# the 9 clips of the spans and the loops the build made of two idle clips' still stretches (one mirrored)
expect_grep "^clips: *12 (8 idle, 3 loop, 5 mirrored" "$tmp/out"
expect_grep "^idle loops: 2 made" "$tmp/out"
# a walk alone: no idle clip, no stop, no start, and the walk's other speeds and the run uncovered
printf '{"clips": [{"file": "walk_1.40.bvh", "loop": true}]}\n' >"$tmp/walk_only.json"
expect_exit 0 "$mm" db build "$tmp/walk_only.json" --data "$set_dir" -o "$tmp/walk_only.mmdb"
for code in no_idle no_stops no_starts speed_not_covered; do expect_grep "^  $code: " "$tmp/out"; done
expect_grep "add an idle clip" "$tmp/out"
expect_exit 0 "$mm" db info "$tmp/walk_only.mmdb"
expect_grep "^  no_idle: " "$tmp/out"
expect_grep "^height: *1.6[0-9] m standing" "$tmp/out"

# bvh spans on any skeleton: the joints renamed (no Hips: the root, whose children are the legs
# and spine; the head and hands by their endings) give the same spans, the roles found as config
# init finds them (mm_skeleton_roles_find); a config's roles are taken as they are; a head with no
# name of a head (Skull) is found by geometry (the highest end); a skeleton without roles (a chain
# of two joints) is an error that lists the joints
sed -e 's/^ROOT Hips/ROOT root_joint/' -e 's/JOINT Head$/JOINT torso_head/' -e 's/JOINT LeftHand$/JOINT lWrist/' \
    -e 's/JOINT RightHand$/JOINT rWrist/' "$set_dir/walk_stop.bvh" >"$tmp/renamed.bvh"
expect_exit 0 "$mm" bvh spans "$tmp/renamed.bvh"
expect_grep '"roles": {"hips": "root_joint", "root_bone": "Spine2", "head": "torso_head", "left_hand": "lWrist", "right_hand": "rWrist"}' "$tmp/out"
sed -n '/"postures"/,$p' "$tmp/out" >"$tmp/renamed.spans"
sed -n '/"postures"/,$p' "$tmp/walk_stop.spans" >"$tmp/walk_stop.tail"
if cmp -s "$tmp/renamed.spans" "$tmp/walk_stop.tail"; then ok; else bad "renamed joints gave other spans"; fi
expect_grep '"calibration": \[\]' "$tmp/out"
expect_exit 0 "$mm" bvh spans "$set_dir/walk_stop.bvh" --config "$data/../../configs/synth.json"
expect_grep '"root_bone": "Spine2"' "$tmp/out"
expect_exit 1 "$mm" bvh spans "$tmp/renamed.bvh" --config "$data/../../configs/synth.json"
expect_grep "no joint named 'Hips' (roles.hips of " "$tmp/err"
expect_grep "its joints: root_joint, LeftUpLeg" "$tmp/err"
sed 's/JOINT torso_head$/JOINT Skull/' "$tmp/renamed.bvh" >"$tmp/nohead.bvh"
expect_exit 0 "$mm" bvh spans "$tmp/nohead.bvh"
expect_grep '"head": "Skull"' "$tmp/out"
expect_exit 1 "$mm" bvh spans "$data/bvh/chain2.bvh"
expect_grep "the roles cannot be found: .*--hips NAME --head NAME" "$tmp/err"
expect_grep "its joints: Base, Tip" "$tmp/err"
expect_exit 0 "$mm" bvh spans "$tmp/nohead.bvh" --head Skull --hips root_joint --root-bone Spine2
expect_grep '"roles": {"hips": "root_joint", "root_bone": "Spine2", "head": "Skull"' "$tmp/out"
expect_exit 0 "$mm" bvh spans "$set_dir/walk_stop.bvh" --low-hips 0.6
expect_grep "deprecated" "$tmp/err"
if [ -n "${MM_DATA_DIR:-}" ]; then
    # the CMU take opens with a T pose: a calibration span from frame 0, left out with a second
    expect_exit 0 "$mm" bvh spans "$MM_DATA_DIR/pfnn/bvh/LocomotionFlat09_000.bvh"
    expect_grep '"calibration": \[\[0, [0-9]*\]\]' "$tmp/out"
    expect_grep '"excluded": \[\[0, [0-9]*\]' "$tmp/out"
fi

# simulate: a character on scripted and random input; the BVH is deterministic, the metrics JSON
# carries every documented key
script_dir=$data/../../scripts/input
expect_exit 0 "$mm" simulate "$tmp/synth.mmdb" --input "$script_dir/turn_90.json" --seconds 5 -o "$tmp/sim1.bvh" --metrics "$tmp/sim1.json"
expect_exit 0 "$mm" simulate "$tmp/synth.mmdb" --input "$script_dir/turn_90.json" --seconds 5 -o "$tmp/sim2.bvh" --metrics "$tmp/sim2.json"
if cmp -s "$tmp/sim1.bvh" "$tmp/sim2.bvh"; then ok; else bad "two simulations of one script differ"; fi
for key in foot_slide_cm_s foot_slide_raw_cm_s traj_err_cm heading_err_deg response_s max_pop_cm db_max_pop_cm searches transitions_per_s nan_frames search_median_us search_p99_us \
    below_ground_cm contact_height_err_cm contact_share foot_slide_height_cm_s db_foot_slide_height_cm_s pop_p99_cm db_pop_p99_cm head_p2_cm \
    head_p5_cm head_p50_cm db_head_p5_cm db_head_p50_cm crouched_s bent_s lying_s calibration_s arms_spread_s hand_raised_s knee_raised_s arms_out_s \
    hands_apart_max_cm; do
    expect_grep "\"$key\": " "$tmp/sim1.json"
done
expect_grep '"nan_frames": 0' "$tmp/sim1.json"
# what the database gives: numbers on the built-in set (its roles name a head, hands, feet and toes)
for key in contact_height_err_cm contact_share foot_slide_height_cm_s db_foot_slide_height_cm_s pop_p99_cm db_pop_p99_cm head_p50_cm \
    db_head_p50_cm crouched_s calibration_s arms_out_s hands_apart_max_cm; do
    expect_grep "\"$key\": [0-9]" "$tmp/sim1.json"
done
# mm metrics on the motion written, against the same database: the same pose measures (the BVH
# holds the motion to 9 digits)
expect_exit 0 "$mm" metrics "$tmp/sim1.bvh" --db "$tmp/synth.mmdb" -o "$tmp/sim1_bvh.json"
for key in max_pop_cm pop_p99_cm below_ground_cm foot_slide_height_cm_s head_p2_cm head_p50_cm db_pop_p99_cm \
    db_head_p5_cm crouched_s bent_s calibration_s arms_out_s hands_apart_max_cm; do
    a=$(sed -n "s/.*\"$key\": \([-0-9.e+]*\).*/\1/p" "$tmp/sim1.json")
    b=$(sed -n "s/.*\"$key\": \([-0-9.e+]*\).*/\1/p" "$tmp/sim1_bvh.json")
    if [ -n "$a" ] && awk -v a="$a" -v b="$b" 'BEGIN { exit !(b != "" && a - b < 1e-3 && b - a < 1e-3) }'; then
        ok
    else
        bad "$key: mm simulate $a, mm metrics on its BVH $b"
    fi
done
expect_grep '"contact_share": null' "$tmp/sim1_bvh.json"
# a file without the database's joints
expect_exit 1 "$mm" metrics "$data/bvh/chain2.bvh" --db "$tmp/synth.mmdb"
expect_grep "no joint 'Hips' (a bone role of the database)" "$tmp/err"
expect_exit 0 "$mm" bvh info "$tmp/sim1.bvh"
expect_grep "frames: *300" "$tmp/out"
expect_exit 0 "$mm" simulate "$tmp/synth.mmdb" --random 5 --seconds 3 --fps 30 -o "$tmp/sim3.bvh" --metrics "$tmp/sim3.json"
expect_exit 2 "$mm" simulate "$tmp/synth.mmdb" --seconds 3 -o "$tmp/sim4.bvh"
expect_exit 1 "$mm" simulate "$tmp/synth.mmdb" --input "$tmp/missing.json" --seconds 3 -o "$tmp/sim4.bvh"
expect_grep "missing.json" "$tmp/err"

finish test_cli
