#!/bin/sh
# End-to-end tests of `mm pfnn eval` on the released PFNN weights ($MM_DATA_DIR/pfnn).
# Skipped (exit 77) when MM_DATA_DIR is unset. usage: test_pfnn_cli.sh MM_BINARY
set -u
mm=$1
if [ -z "${MM_DATA_DIR:-}" ] || [ ! -d "$MM_DATA_DIR/pfnn/network" ]; then
    echo "MM_DATA_DIR/pfnn not available: skipped"
    exit 77
fi
w=$MM_DATA_DIR/pfnn
ref=$w/reference
. "$(dirname "$0")/cli_checks.sh"

# expect_close A.bin B.bin TOL : same number of float32 values, all within TOL
expect_close() {
    od -An -v -t f4 -w4 "$1" | tr -d ' ' >"$tmp/a.txt"
    od -An -v -t f4 -w4 "$2" | tr -d ' ' >"$tmp/b.txt"
    if paste "$tmp/a.txt" "$tmp/b.txt" | awk -v tol="$3" '
        function abs(v) { return v < 0 ? -v : v }
        NF != 2 { bad = 1 } abs($1 - $2) > tol { bad = 1 } END { exit bad || NR == 0 }'; then
        ok
    else
        bad "$1 and $2 differ by more than $3"
    fi
}

for p in 0.00 1.00 2.50 4.00; do
    for m in constant linear; do
        for x in C_reset A_xmean; do
            [ -f "$ref/Y_${x}_${m}_p$p.bin" ] || continue
            expect_exit 0 "$mm" pfnn eval --weights "$w" --x "$ref/X_$x.bin" --phase $p --mode $m -o "$tmp/y.bin"
            expect_close "$tmp/y.bin" "$ref/Y_${x}_${m}_p$p.bin" 0.001
        done
    done
done

# several rows; the phase wraps (1 + 2 pi); cubic mode; default weights from $MM_DATA_DIR
cat "$ref/X_C_reset.bin" "$ref/X_A_xmean.bin" >"$tmp/x2.bin"
expect_exit 0 "$mm" pfnn eval --x "$tmp/x2.bin" --phase 7.283185307 --mode constant -o "$tmp/y2.bin"
cat "$ref/Y_C_reset_constant_p1.00.bin" "$ref/Y_A_xmean_constant_p1.00.bin" >"$tmp/r2.bin"
expect_close "$tmp/y2.bin" "$tmp/r2.bin" 0.001
expect_exit 0 "$mm" pfnn eval --weights "$w" --x "$tmp/x2.bin" --phase -5.283185307 --mode constant -o "$tmp/y3.bin"
expect_close "$tmp/y3.bin" "$tmp/r2.bin" 0.001
expect_exit 0 "$mm" pfnn eval --weights "$w" --x "$tmp/x2.bin" --phase 1 --mode cubic -o "$tmp/yc.bin"
[ "$(wc -c <"$tmp/yc.bin")" -eq 2488 ] && ok || bad "cubic output is not 2 x 311 float32"

# errors
expect_exit 2 "$mm" pfnn eval --weights "$w" --x "$ref/X_C_reset.bin" --phase 1 --mode quadratic -o "$tmp/y.bin"
expect_grep "constant, linear or cubic" "$tmp/err"
expect_exit 2 "$mm" pfnn eval --weights "$w" --x "$ref/X_C_reset.bin" -o "$tmp/y.bin"
expect_exit 2 "$mm" pfnn eval --weights "$w" --x "$ref/X_C_reset.bin" --phase abc -o "$tmp/y.bin"
expect_exit 2 "$mm" pfnn
head -c 1000 "$ref/X_C_reset.bin" >"$tmp/short.bin"
expect_exit 1 "$mm" pfnn eval --weights "$w" --x "$tmp/short.bin" --phase 1 -o "$tmp/y.bin"
expect_grep "short.bin: 1000 bytes is not a whole number of rows of 342" "$tmp/err"
expect_exit 1 "$mm" pfnn eval --weights "$tmp/nowhere" --x "$ref/X_C_reset.bin" --phase 1 -o "$tmp/y.bin"
expect_grep "nowhere/network/Xmean.bin" "$tmp/err"
mkdir -p "$tmp/w/network"
for f in "$w"/network/*.bin; do ln -s "$f" "$tmp/w/network/"; done
rm "$tmp/w/network/b2_ctrl3.bin"
head -c 1000 "$w/network/b2_ctrl3.bin" >"$tmp/w/network/b2_ctrl3.bin"
expect_exit 1 "$mm" pfnn eval --weights "$tmp/w" --x "$ref/X_C_reset.bin" --phase 1 -o "$tmp/y.bin"
expect_grep "b2_ctrl3.bin.*short file: 1000 bytes, expected 1244" "$tmp/err"
rm "$tmp/w/network/W0_ctrl1.bin"
expect_exit 1 "$mm" pfnn eval --weights "$tmp/w" --x "$ref/X_C_reset.bin" --phase 1 -o "$tmp/y.bin"
expect_grep "W0_ctrl1.bin: cannot open" "$tmp/err"

# mm pfnn run: a straight walk on a shipped input script, measured like mm simulate
scripts=$(cd "$(dirname "$0")/../scripts/input" && pwd)
expect_exit 0 "$mm" pfnn run --weights "$w" --input "$scripts/straight_walk.json" --seconds 5 --mode linear \
    -o "$tmp/walk.bvh" --metrics "$tmp/walk.json"
expect_grep "walk.bvh: 300 frames at 60 fps (linear)" "$tmp/out"
expect_grep "Frames: 300" "$tmp/walk.bvh"
for key in foot_slide_cm_s traj_err_cm heading_err_deg response_s max_pop_cm frame_median_us memory_mb; do
    expect_grep "\"$key\"" "$tmp/walk.json"
done
expect_grep '"nan_frames": 0,' "$tmp/walk.json"
# the root walked forward (+Z) between 3.5 and 9 m in the 4 s of stick (the demo walks 1.5 m/s at most)
z=$("$mm" bvh fk "$tmp/walk.bvh" --frame 299 | awk 'NR == 1 {print $4}')
awk -v z="$z" 'BEGIN {exit !(z > 3.5 && z < 9)}' && ok || bad "walked to z = $z m"
# ... and straight: the hips within 15 cm of x = 0 (the network as released drifts right, to -x)
x=$("$mm" bvh fk "$tmp/walk.bvh" --frame 299 | awk 'NR == 1 {print $2}')
awk -v x="$x" 'BEGIN {exit !(x > -0.15 && x < 0.15)}' && ok || bad "walked sideways to x = $x m"
expect_exit 0 "$mm" pfnn run --weights "$w" --input "$scripts/straight_walk.json" --seconds 5 --mode linear \
    --symmetry none -o "$tmp/raw.bvh"
x=$("$mm" bvh fk "$tmp/raw.bvh" --frame 299 | awk 'NR == 1 {print $2}')
awk -v x="$x" 'BEGIN {exit !(x < -0.15)}' && ok || bad "the released network walked to x = $x m"
expect_exit 2 "$mm" pfnn run --weights "$w" --random 1 --seconds 1 --symmetry left -o "$tmp/x.bvh"
expect_grep "symmetry must be mirror or none" "$tmp/err"
# the same run twice gives the same bytes
"$mm" pfnn run --weights "$w" --input "$scripts/straight_walk.json" --seconds 5 --mode linear -o "$tmp/walk2.bvh" >/dev/null
cmp -s "$tmp/walk.bvh" "$tmp/walk2.bvh" && ok || bad "two runs differ"
# on a scene: a flat one changes nothing; on the shipped slope the terrain metrics are measured
printf '{"ground": 0, "boxes": []}\n' >"$tmp/flat.json"
"$mm" pfnn run --weights "$w" --input "$scripts/straight_walk.json" --seconds 5 --mode linear --scene "$tmp/flat.json" \
    -o "$tmp/walk3.bvh" >/dev/null
cmp -s "$tmp/walk.bvh" "$tmp/walk3.bvh" && ok || bad "a flat scene changed the motion"
scenes=$(cd "$(dirname "$0")/../scenes" && pwd)
expect_exit 0 "$mm" pfnn run --weights "$w" --input "$scripts/slope_21_walk.json" --seconds 5 --mode linear \
    --scene "$scenes/slope_21.json" -o "$tmp/slope.bvh" --metrics "$tmp/slope.json"
for key in below_ground_cm contact_height_err_cm foot_float_cm penetration_max_cm; do
    grep -q "\"$key\": [0-9]" "$tmp/slope.json" && ok || bad "$key not measured on the slope"
done
# half way up the ramp (0.5 m at z = 4.4 m) the hips are that much higher than on flat ground (1 m)
y=$("$mm" bvh fk "$tmp/slope.bvh" --frame 299 | awk 'NR == 1 {print $3}')
awk -v y="$y" 'BEGIN {exit !(y > 1.2)}' && ok || bad "the hips at y = $y m on the slope"
expect_exit 1 "$mm" pfnn run --weights "$w" --input "$scripts/straight_walk.json" --seconds 1 --scene "$tmp/none.json" \
    -o "$tmp/x.bvh"
expect_grep "none.json" "$tmp/err"
expect_exit 2 "$mm" pfnn run --weights "$w" --input "$scripts/straight_walk.json" -o "$tmp/x.bvh"
expect_exit 2 "$mm" pfnn run --weights "$w" --random 1 --input "$scripts/straight_walk.json" --seconds 1 -o "$tmp/x.bvh"
expect_exit 2 "$mm" pfnn run --weights "$w" --random 1 --seconds 1 --mode quadratic -o "$tmp/x.bvh"
expect_exit 1 "$mm" pfnn run --weights "$w" --input "$tmp/none.json" --seconds 1 -o "$tmp/x.bvh"
expect_grep "none.json" "$tmp/err"
[ ! -e "$tmp/x.bvh" ] && ok || bad "x.bvh written by a failed run"

finish test_pfnn_cli
