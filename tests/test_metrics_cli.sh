#!/bin/sh
# End-to-end tests of mm metrics on hand-built BVH files with known answers: a pop, a toe under the
# floor, the head's height, the height-weighted slide; units, the output file, errors.
# usage: test_metrics_cli.sh MM_BINARY SOURCE_DIR
set -u
mm=$1
src=$2
. "$(dirname "$0")/cli_checks.sh"
. "$src/scripts/json_get.sh"

# expect_key FILE KEY VALUE : the metrics JSON gives KEY within 1e-3 of VALUE, or null for null
expect_key() {
    got=$(get "$2" "$1")
    if [ "$3" = null ]; then
        if [ "$got" = null ]; then ok; else bad "$2 is '$got', wanted null"; fi
    elif [ -n "$got" ] && [ "$got" != null ] &&
        awk -v a="$got" -v b="$3" 'BEGIN { d = a - b; exit !(d < 1e-3 && d > -1e-3) }'; then
        ok
    else
        bad "$2 is '$got', wanted $3"
    fi
}

# A body in unit U (1: metres, 100: centimetres), nine frames at 30 fps: the hips 1 m up, the head
# 0.6 m above them, the left toe 2 cm under the floor (1 - 0.95 - 0.07); on frame 6 the whole body
# is 5 cm to the side: second differences 0, 0, 0, 0, 5, -10, 5 cm on frames 2 to 8.
body() {
    awk -v u="$1" 'function p(x) { return x * u }
    BEGIN {
        print "HIERARCHY"
        print "ROOT Hips\n{\n  OFFSET 0 0 0"
        print "  CHANNELS 6 Xposition Yposition Zposition Zrotation Yrotation Xrotation"
        print "  JOINT Head\n  {\n    OFFSET 0 " p(0.6) " 0\n    CHANNELS 3 Zrotation Yrotation Xrotation"
        print "    End Site\n    {\n      OFFSET 0 " p(0.1) " 0\n    }\n  }"
        print "  JOINT LeftFoot\n  {\n    OFFSET " p(-0.1) " " p(-0.95) " 0\n    CHANNELS 3 Zrotation Yrotation Xrotation"
        print "    JOINT LeftToe\n    {\n      OFFSET 0 " p(-0.07) " " p(0.1) "\n      CHANNELS 3 Zrotation Yrotation Xrotation"
        print "      End Site\n      {\n        OFFSET 0 0 " p(0.05) "\n      }\n    }\n  }"
        print "  JOINT RightFoot\n  {\n    OFFSET " p(0.1) " " p(-0.92) " 0\n    CHANNELS 3 Zrotation Yrotation Xrotation"
        print "    JOINT RightToe\n    {\n      OFFSET 0 " p(-0.05) " " p(0.1) "\n      CHANNELS 3 Zrotation Yrotation Xrotation"
        print "      End Site\n      {\n        OFFSET 0 0 " p(0.05) "\n      }\n    }\n  }\n}"
        print "MOTION\nFrames: 9\nFrame Time: 0.0333333333"
        for (f = 0; f < 9; ++f) {
            line = p(f == 6 ? 0.05 : 0) " " p(1) " 0 0 0 0"
            for (j = 0; j < 5; ++j) line = line " 0 0 0"
            print line
        }
    }'
}
body 1 >"$tmp/m.bvh"
body 100 >"$tmp/cm.bvh"

expect_exit 0 "$mm" metrics "$tmp/m.bvh" --scale 1
cp "$tmp/out" "$tmp/m.json"
expect_key "$tmp/m.json" max_pop_cm 10
expect_key "$tmp/m.json" pop_p99_cm 5 # of 0, 0, 0, 0, 5, 5, 10: rank floor(0.99 x 6) = 5
expect_key "$tmp/m.json" below_ground_cm 2
expect_key "$tmp/m.json" head_p2_cm 160
expect_key "$tmp/m.json" head_p50_cm 160
expect_key "$tmp/m.json" nan_frames 0
# every foot and toe stays at its own 5th percentile height (h = 0, w = 1), counted from its fourth
# step near the ground (after 0.1 s: steps 4 to 8), and moves 5 cm in a 1/30 s frame on two of
# those five steps: 60 cm/s
expect_key "$tmp/m.json" foot_slide_height_cm_s 60
# against its own head height (no database): upright throughout; no hands, no arms measures
for key in crouched_s bent_s lying_s calibration_s arms_spread_s hand_raised_s knee_raised_s; do expect_key "$tmp/m.json" $key 0; done
for key in arms_out_s hands_apart_max_cm; do expect_key "$tmp/m.json" $key null; done
# no controller, no labels, no database, no scene: null
for key in foot_slide_cm_s foot_slide_raw_cm_s traj_err_cm heading_err_deg response_s db_max_pop_cm searches \
    transitions_per_s search_median_us search_p99_us frame_median_us memory_mb penetration_max_cm \
    contact_height_err_cm contact_share db_pop_p99_cm db_head_p5_cm db_head_p50_cm db_foot_slide_height_cm_s; do
    expect_key "$tmp/m.json" $key null
done
expect_grep '"moves": \[\]' "$tmp/m.json"

# the same body in centimetres, with its scale given or detected, and written to a file
expect_exit 0 "$mm" metrics "$tmp/cm.bvh" --scale 0.01 -o "$tmp/cm.json"
if [ ! -s "$tmp/out" ]; then ok; else bad "-o printed the metrics"; fi
if cmp -s "$tmp/m.json" "$tmp/cm.json"; then ok; else bad "centimetres measure differently:"; diff "$tmp/m.json" "$tmp/cm.json"; fi
expect_exit 0 "$mm" metrics "$tmp/cm.bvh" -o "$tmp/auto.json"
if cmp -s "$tmp/m.json" "$tmp/auto.json"; then ok; else bad "--scale auto measures differently"; fi
if [ -z "$(ls "$tmp" | grep '\.tmp')" ]; then ok; else bad "temporary file left behind"; fi

# a scene whose ground is 0.5 m down: nothing is below it, the head is 2.1 m above it
printf '{"ground": -0.5, "boxes": []}\n' >"$tmp/scene.json"
expect_exit 0 "$mm" metrics "$tmp/m.bvh" --scale 1 --scene "$tmp/scene.json"
expect_key "$tmp/out" below_ground_cm 0
expect_key "$tmp/out" head_p50_cm 210
expect_key "$tmp/out" penetration_max_cm 0

# errors
expect_exit 2 "$mm" metrics
expect_exit 2 "$mm" metrics "$tmp/m.bvh" --scale -1
expect_exit 2 "$mm" metrics "$tmp/m.bvh" --bogus
expect_exit 1 "$mm" metrics "$tmp/missing.bvh"
expect_grep "missing.bvh" "$tmp/err"
expect_exit 1 "$mm" metrics "$tmp/m.bvh" --db "$tmp/missing.mmdb"
expect_exit 1 "$mm" metrics "$tmp/m.bvh" --scene "$tmp/missing.json"
expect_exit 1 "$mm" metrics "$tmp/m.bvh" -o "$tmp/no/such/dir/x.json"
expect_exit 0 "$mm" help
expect_grep "^  metrics  " "$tmp/out"
expect_exit 0 "$mm" metrics --help
expect_grep "^usage: mm metrics FILE.bvh" "$tmp/out"

finish test_metrics_cli
