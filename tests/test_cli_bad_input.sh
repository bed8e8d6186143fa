#!/bin/sh
# The bad-input matrix of the mm program's arguments: missing, empty, garbage, truncated and folder
# inputs for every command that reads a file; unknown options and options without their value;
# numbers that are not numbers, NaN, Inf, negative or absurd; outputs in folders that do not exist.
# Each must exit 1 or 2 (never 0, never a crash, a hang or a sanitizer report) with a message
# "mm: ..." or "mm COMMAND: ..." naming the file or the option, and leave no output and no
# temporary file behind. Absurd values that are valid must not crash or hang either.
# usage: test_cli_bad_input.sh MM_BINARY SOURCE_DIR
set -u
mm=$1
src=$2
. "$(dirname "$0")/cli_checks.sh"

# run CMD... : CMD with stdout to $tmp/out, stderr to $tmp/err, at most 120 s; sets $got
limit=""
command -v timeout >/dev/null 2>&1 && limit="timeout 120"
run() {
    # shellcheck disable=SC2086
    $limit "$@" >"$tmp/out" 2>"$tmp/err" </dev/null
    got=$?
}
sanitizer_report() { grep -q -e 'Sanitizer' -e 'runtime error' "$tmp/err"; }

# fails NAME CMD... : CMD exits 1 or 2, stderr has a line "mm[ COMMAND]: ..." holding NAME
fails() {
    name=$1
    shift
    run "$@"
    if [ "$got" -ne 1 ] && [ "$got" -ne 2 ]; then
        bad "exit $got (wanted 1 or 2): $*"
        head -n 5 "$tmp/err"
    elif sanitizer_report; then
        bad "sanitizer report: $*"
        head -n 20 "$tmp/err"
    elif ! grep '^mm[a-z ]*: ' "$tmp/err" | grep -q -F -e "$name"; then
        bad "no message 'mm: ...' naming '$name': $*"
        head -n 5 "$tmp/err"
    else
        ok
    fi
    if [ -n "${o:-}" ] && [ -n "$(ls -A "$o")" ]; then
        bad "output left behind ($(find "$o" ! -path "$o" | tr '\n' ' ')): $*"
        rm -rf "${o:?}"/* "${o:?}"/.[!.]*
    fi
}
# succeeds CMD... : CMD exits 0 without a sanitizer report
succeeds() {
    run "$@"
    if [ "$got" -ne 0 ]; then
        bad "exit $got (wanted 0): $*"
        head -n 5 "$tmp/err"
    elif sanitizer_report; then
        bad "sanitizer report: $*"
        head -n 20 "$tmp/err"
    else
        ok
    fi
}
# values OPTION 'VALUE...' CMD... : each value (and no value at all) after CMD OPTION fails naming OPTION
values() {
    option=$1
    list=$2
    shift 2
    for v in $list; do
        fails "$option" "$@" "$option" "$v"
    done
    fails "$option" "$@" "$option" ""
    fails "$option" "$@" "$option"
}
# names OPTION CMD... : OPTION without its value fails naming it; an empty value fails
names() {
    option=$1
    shift
    fails "$option" "$@" "$option"
    fails "" "$@" "$option" ""
}
# hexadecimal is not taken (strtod would), nor a number that a float turns into 0 or infinity
not_numbers="abc nan -inf 1e999 5x 0x10 0X1p3 1e 1e-300 1e39"
not_ints="$not_numbers 1.5 -1 99999999999999999999"

# --- inputs: the built-in motion set, a tiny database of it, its tables ---------------------------
chain=$src/tests/data/bvh/chain2.bvh
script=$src/scripts/input/turn_90.json
if ! "$mm" synth "$tmp/set" >/dev/null; then
    echo "test_cli_bad_input: mm synth failed"
    exit 1
fi
cat >"$tmp/db.json" <<'EOF'
{"interval": 0.1, "scale": 1, "tags": ["Walk"],
 "clips": [{"name": "idle", "file": "idle.bvh", "type": "idle", "loop": true, "ranges": [[0, 24]]},
           {"name": "walk", "file": "walk_1.40.bvh", "mirror": true, "ranges": [[0, 24]],
            "tags": {"Walk": [[0.0, 0.3]]}}]}
EOF
succeeds "$mm" db build "$tmp/db.json" --data "$tmp/set" -o "$tmp/db.mmdb"
db=$tmp/db.mmdb
succeeds "$mm" similarity build "$db" -o "$tmp/db.sim"
sim=$tmp/db.sim
if [ ! -s "$db" ] || [ ! -s "$sim" ]; then
    echo "test_cli_bad_input: cannot make the database"
    exit 1
fi

# outputs that must never appear go to $tmp/o (checked empty at the end); $tmp/no/dir is missing
mkdir "$tmp/o"
o=$tmp/o
nodir=$tmp/no/dir

# --- bad files, for every command that reads one ---------------------------------------------------
: >"$tmp/empty"
printf '\001\377\376GARBAGE\000\033[31m\r\n\200{[<' >"$tmp/garbage"
for ext in bvh json mmdb sim fbx gltf glb dae bin; do cp "$tmp/garbage" "$tmp/garbage.$ext"; done
head -c 1000 "$db" >"$tmp/truncated.mmdb"
head -c 100 "$sim" >"$tmp/truncated.sim"
head -c 200 "$tmp/set/idle.bvh" >"$tmp/truncated.bvh"
printf '{"keys": [{"t": 0.0, "stick": [0, 1' >"$tmp/truncated.json"
mkdir "$tmp/folder"
readers() { # FILE: every command that reads FILE fails naming it
    f=$1
    fails "$f" "$mm" bvh info "$f"
    fails "$f" "$mm" bvh info "$f" --json
    fails "$f" "$mm" bvh fk "$f" --frame 0
    fails "$f" "$mm" bvh spans "$f"
    fails "$f" "$mm" bvh convert "$f" "$o/convert.bvh"
    fails "$f" "$mm" import info "$f"
    fails "$f" "$mm" config check "$f"
    fails "$f" "$mm" config init "$f" -o "$o/init.json"
    fails "$f" "$mm" db build "$f" -o "$o/build.mmdb"
    fails "$f" "$mm" db info "$f"
    fails "$f" "$mm" db dump "$f"
    fails "$f" "$mm" db search "$f" --frame 0
    fails "$f" "$mm" simulate "$f" --random 1 --seconds 1 -o "$o/sim.bvh" --metrics "$o/sim.json"
    fails "$f" "$mm" simulate "$db" --input "$f" --seconds 1 -o "$o/sim.bvh" --metrics "$o/sim.json"
    fails "$f" "$mm" simulate "$db" --path "$f" --seconds 1 -o "$o/sim.bvh"
    fails "$f" "$mm" simulate "$db" --random 1 --seconds 1 -o "$o/sim.bvh" --skeleton "$f"
    fails "$f" "$mm" simulate "$db" --random 1 --seconds 1 -o "$o/sim.bvh" --skeleton "$tmp/set/idle.bvh" \
        --skeleton-map "$f"
    fails "$f" "$mm" similarity "$f" --from idle --to walk -o "$o/audit"
    fails "$f" "$mm" similarity build "$f" -o "$o/build.sim"
    fails "$f" "$mm" similarity info "$f"
    fails "$f" "$mm" similarity info "$sim" --db "$f"
    fails "$f" "$mm" pfnn eval --weights "$tmp/no_weights" --x "$f" --phase 0 -o "$o/y.bin"
    fails "$f" "$mm" render "$f" -o "$o/frames" --seconds 0.1
    fails "$f" "$mm" metrics "$f"
    fails "$f" "$mm" metrics "$tmp/set/idle.bvh" --db "$f"
    fails "$f" "$mm" metrics "$tmp/set/idle.bvh" --scene "$f"
}
for f in "$tmp/missing" "$tmp/empty" "$tmp/garbage" "$tmp/folder"; do readers "$f"; done
# a folder where a file is expected is called one
fails "is a folder" "$mm" bvh info "$tmp/folder"
# garbage named like each format, to the commands that go by the name
for ext in bvh fbx gltf glb dae; do
    fails "$tmp/garbage.$ext" "$mm" import info "$tmp/garbage.$ext"
done
fails "$tmp/garbage.bvh" "$mm" bvh info "$tmp/garbage.bvh"
fails "$tmp/garbage.json" "$mm" db build "$tmp/garbage.json" -o "$o/build.mmdb"
fails "$tmp/garbage.json" "$mm" simulate "$db" --input "$tmp/garbage.json" --seconds 1 -o "$o/sim.bvh"
fails "$tmp/garbage.mmdb" "$mm" db info "$tmp/garbage.mmdb"
fails "$tmp/garbage.sim" "$mm" similarity info "$tmp/garbage.sim"
fails "$tmp/garbage.bin" "$mm" pfnn eval --weights "$tmp/no_weights" --x "$tmp/garbage.bin" --phase 0 -o "$o/y.bin"
for f in "$tmp/truncated.mmdb" "$tmp/truncated.sim" "$tmp/truncated.bvh" "$tmp/truncated.json"; do readers "$f"; done
# a file that does parse, given to the wrong command
fails "$db" "$mm" similarity info "$db"
fails "$sim" "$mm" db info "$sim"
fails "$script" "$mm" db info "$script"
fails "$chain" "$mm" config check "$chain"
fails "$chain" "$mm" simulate "$db" --input "$chain" --seconds 1 -o "$o/sim.bvh"
# the x input of pfnn eval must be whole rows before the weights are read
head -c 1368 /dev/zero >"$tmp/row.bin"
fails "$tmp/no_weights" "$mm" pfnn eval --weights "$tmp/no_weights" --x "$tmp/row.bin" --phase 0 -o "$o/y.bin"
# mm convert reads every BVH of the folder before it runs Blender (here: the mm program itself)
mkdir "$tmp/bvh_in"
cp "$tmp/garbage" "$tmp/bvh_in/a.bvh"
fails "$tmp/bvh_in/a.bvh" "$mm" convert "$tmp/bvh_in" "$o/fbx" --blender "$mm"
fails "$tmp/missing" "$mm" convert "$tmp/missing" "$o/fbx" --blender "$mm"
fails "$tmp/empty" "$mm" convert "$tmp/empty" "$o/fbx" --blender "$mm"
fails "$tmp/no_blender" "$mm" convert "$tmp/bvh_in" "$o/fbx" --blender "$tmp/no_blender"

# --- configs and input scripts with bad numbers ------------------------------------------------------
for v in 0 -0.1 1e999 '"fast"' null; do
    printf '{"interval": %s, "clips": [{"file": "idle.bvh"}]}' "$v" >"$tmp/interval.json"
    fails "$tmp/interval.json" "$mm" config check "$tmp/interval.json"
    fails "$tmp/interval.json" "$mm" db build "$tmp/interval.json" --data "$tmp/set" -o "$o/build.mmdb"
done
printf '{"clips": [{"file": "idle.bvh", "name": "a"}, {"file": "idle.bvh", "name": "a"}]}' >"$tmp/dup.json"
fails "$tmp/dup.json" "$mm" db build "$tmp/dup.json" --data "$tmp/set" -o "$o/build.mmdb"
printf '{"features": {"bones": [{"name": "NoSuchBone"}]}, "clips": [{"file": "idle.bvh"}]}' >"$tmp/bone.json"
fails "$tmp/bone.json" "$mm" db build "$tmp/bone.json" --data "$tmp/set" -o "$o/build.mmdb"
for v in 1e999 -1e999 '"x"' '[1]'; do
    printf '{"keys": [{"t": 0.0, "stick": [0, %s]}]}' "$v" >"$tmp/stick.json"
    fails "$tmp/stick.json" "$mm" simulate "$db" --input "$tmp/stick.json" --seconds 1 -o "$o/sim.bvh"
    printf '{"keys": [{"t": %s, "stick": [0, 1]}]}' "$v" >"$tmp/time.json"
    fails "$tmp/time.json" "$mm" simulate "$db" --input "$tmp/time.json" --seconds 1 -o "$o/sim.bvh"
done

# numbers in hexadecimal: BVH files never hold them and JSON forbids them; each is refused with
# the file, line and column
bvh=$tmp/set/idle.bvh
first_frame=$(($(grep -n '^Frame Time' "$bvh" | cut -d: -f1) + 1))
sed "${first_frame}s/^[^ ]*/0x10/" "$bvh" >"$tmp/hex_motion.bvh"
sed '0,/OFFSET [^ ]*/s//OFFSET 0x10/' "$bvh" >"$tmp/hex_offset.bvh"
sed 's/^Frame Time: .*/Frame Time: 0x1p-5/' "$bvh" >"$tmp/hex_time.bvh"
sed 's/^Frames: .*/Frames: 0x10/' "$bvh" >"$tmp/hex_frames.bvh"
offset_line=$(grep -n 'OFFSET' "$bvh" | head -1 | cut -d: -f1)
fails "$tmp/hex_motion.bvh:$first_frame:1:" "$mm" bvh info "$tmp/hex_motion.bvh"
fails "$tmp/hex_offset.bvh:$offset_line:" "$mm" bvh convert "$tmp/hex_offset.bvh" "$o/c.bvh"
fails "$tmp/hex_time.bvh:$((first_frame - 1)):" "$mm" bvh info "$tmp/hex_time.bvh"
fails "$tmp/hex_frames.bvh:$((first_frame - 2)):" "$mm" bvh fk "$tmp/hex_frames.bvh" --frame 0
cp "$tmp/hex_motion.bvh" "$tmp/set_hex.bvh"
printf '{"clips": [{"file": "%s"}]}' "$tmp/set_hex.bvh" >"$tmp/hex_clip.json"
fails "$tmp/set_hex.bvh:$first_frame:1:" "$mm" db build "$tmp/hex_clip.json" -o "$o/build.mmdb"
printf '{"interval": 0x10, "clips": [{"file": "idle.bvh"}]}' >"$tmp/hex.json"
fails "$tmp/hex.json:1:" "$mm" config check "$tmp/hex.json"
fails "$tmp/hex.json:1:" "$mm" db build "$tmp/hex.json" --data "$tmp/set" -o "$o/build.mmdb"
printf '{"keys": [{"t": 0.0, "stick": [0, 0x1]}]}' >"$tmp/hex_keys.json"
fails "$tmp/hex_keys.json:1:" "$mm" simulate "$db" --input "$tmp/hex_keys.json" --seconds 1 -o "$o/sim.bvh"
# config names: a tag listed twice, a clip tag not declared, a role naming no joint
printf '{"tags": ["Walk", "Walk"], "clips": [{"file": "idle.bvh"}]}' >"$tmp/dup_tag.json"
fails "$tmp/dup_tag.json" "$mm" db build "$tmp/dup_tag.json" --data "$tmp/set" -o "$o/build.mmdb"
printf '{"tags": ["Walk"], "clips": [{"file": "idle.bvh", "tags": {"Run": [[0, 1]]}}]}' >"$tmp/tag.json"
fails "$tmp/tag.json" "$mm" db build "$tmp/tag.json" --data "$tmp/set" -o "$o/build.mmdb"
printf '{"roles": {"hips": "NoHips"}, "clips": [{"file": "idle.bvh"}]}' >"$tmp/role.json"
fails "NoHips" "$mm" db build "$tmp/role.json" --data "$tmp/set" -o "$o/build.mmdb"
# input scripts: times that go back or below 0, an unknown version field
for keys in '{"t": 0.0, "stick": [0, 1]}, {"t": 0.0, "stick": [0, 1]}' '{"t": -1, "stick": [0, 1]}'; do
    printf '{"keys": [%s]}' "$keys" >"$tmp/keys.json"
    fails "$tmp/keys.json" "$mm" simulate "$db" --input "$tmp/keys.json" --seconds 1 -o "$o/sim.bvh"
done
printf '{"version": 99, "keys": [{"t": 0.0, "stick": [0, 1]}]}' >"$tmp/keys.json"
fails "$tmp/keys.json" "$mm" simulate "$db" --input "$tmp/keys.json" --seconds 1 -o "$o/sim.bvh"

# --- commands, subcommands and unknown options -------------------------------------------------------
for c in bvh db config import pfnn simulate synth convert; do fails "$c" "$mm" "$c"; done
for c in bvh db config import pfnn; do fails "nope" "$mm" "$c" nope; done
fails "nope" "$mm" nope
fails "--bogus" "$mm" bvh info "$chain" --bogus
fails "--bogus" "$mm" bvh fk "$chain" --frame 0 --bogus
fails "--bogus" "$mm" bvh convert "$chain" "$o/c.bvh" --bogus
fails "--bogus" "$mm" bvh spans "$chain" --bogus
fails "--bogus" "$mm" import info "$chain" --bogus
fails "--bogus" "$mm" config explain --bogus
fails "--bogus" "$mm" config init "$tmp/set/idle.bvh" -o "$o/init.json" --bogus
fails "--bogus" "$mm" db build "$tmp/db.json" -o "$o/b.mmdb" --bogus
fails "--bogus" "$mm" db info "$db" --bogus
fails "--bogus" "$mm" db search "$db" --frame 0 --bogus
fails "--bogus" "$mm" simulate "$db" --random 1 --seconds 1 -o "$o/s.bvh" --bogus
fails "--bogus" "$mm" synth "$o/synth" --bogus
fails "--bogus" "$mm" similarity "$db" --from idle --to walk -o "$o/audit" --bogus
fails "--bogus" "$mm" similarity build "$db" -o "$o/b.sim" --bogus
fails "--bogus" "$mm" similarity info "$sim" --bogus
fails "--bogus" "$mm" pfnn eval --x "$tmp/row.bin" --phase 0 -o "$o/y.bin" --bogus
fails "--bogus" "$mm" convert "$tmp/bvh_in" "$o/fbx" --bogus
fails "extra" "$mm" bvh info "$chain" extra
fails "extra" "$mm" db search "$db" --frame 0 extra
fails "extra" "$mm" similarity build "$db" extra

# --- options without their value, and values that are not what the option needs ------------------
values --frame "$not_ints" "$mm" bvh fk "$chain"
values --order "XYZW ZZZ 1" "$mm" bvh convert "$chain" "$o/c.bvh"
values --scale "$not_numbers 0 -1 -0.5" "$mm" bvh convert "$chain" "$o/c.bvh"
values --fps "$not_numbers 0 -1 10001 1e300" "$mm" bvh convert "$chain" "$o/c.bvh"
for opt in --scale --low-hips --pad --idle-speed --idle-min; do
    values "$opt" "$not_numbers -1 -1e300" "$mm" bvh spans "$chain"
done
names --hips "$mm" bvh spans "$chain"
names --root-bone "$mm" bvh spans "$chain"
names --write "$mm" bvh spans "$chain"
names --as "$mm" bvh spans "$chain" --write "$tmp/spans.json"
# bvh spans --write: the config must exist and be one; it is not touched when writing fails
for f in "$tmp/missing" "$tmp/garbage.json" "$tmp/folder"; do
    fails "$f" "$mm" bvh spans "$tmp/set/walk_1.40.bvh" --write "$f"
done
printf '{"clips": []}\n' >"$tmp/spans.json"
long=$(printf '%0100d' 0)
fails "$long" "$mm" bvh spans "$tmp/set/walk_1.40.bvh" --write "$tmp/spans.json" --as "$long"
if [ "$(cat "$tmp/spans.json")" = '{"clips": []}' ]; then ok; else bad "bvh spans --write changed the config on failure"; fi
values --scale "$not_numbers 0 -1" "$mm" import info "$chain"
# config init: its options; a skeleton that is no body; an output it cannot write
names -o "$mm" config init "$tmp/set/idle.bvh"
names --name-prefix "$mm" config init "$tmp/set/idle.bvh" -o "$o/init.json"
values --scale "$not_numbers 0 -1 1001" "$mm" config init "$tmp/set/idle.bvh" -o "$o/init.json"
fails "$chain" "$mm" config init "$chain" -o "$o/init.json"
fails "$nodir" "$mm" config init "$tmp/set/idle.bvh" -o "$nodir/init.json"
fails "$tmp/folder" "$mm" config init "$tmp/set/idle.bvh" -o "$tmp/folder" --force
values --fps "$not_numbers 0 -1 10001" "$mm" import info "$chain"
names -o "$mm" db build "$tmp/db.json"
names --data "$mm" db build "$tmp/db.json" -o "$o/b.mmdb"
values --threads "$not_ints 0 65" "$mm" db build "$tmp/db.json" --data "$tmp/set" -o "$o/b.mmdb"
values --frame "$not_ints" "$mm" db search "$db"
values --traj-from "$not_ints" "$mm" db search "$db" --frame 0
values --top "$not_ints 0 1001" "$mm" db search "$db" --frame 0
values --method "slow BRUTE" "$mm" db search "$db" --frame 0
values --type "walk" "$mm" db search "$db" --frame 0
names --require "$mm" db search "$db" --frame 0
names --exclude "$mm" db search "$db" --frame 0
values --seconds "$not_numbers 0 -1 36001 1e300" "$mm" simulate "$db" --random 1 -o "$o/s.bvh"
values --fps "$not_numbers 0 -1 0.5 1001 1e300" "$mm" simulate "$db" --random 1 --seconds 1 -o "$o/s.bvh"
values --random "$not_ints" "$mm" simulate "$db" --seconds 1 -o "$o/s.bvh"
names --input "$mm" simulate "$db" --seconds 1 -o "$o/s.bvh"
names -o "$mm" simulate "$db" --random 1 --seconds 1
names --metrics "$mm" simulate "$db" --random 1 --seconds 1 -o "$o/s.bvh"
names --path "$mm" simulate "$db" --seconds 1 -o "$o/s.bvh"
names --skeleton "$mm" simulate "$db" --random 1 --seconds 1 -o "$o/s.bvh"
names --skeleton-map "$mm" simulate "$db" --random 1 --seconds 1 -o "$o/s.bvh" --skeleton "$tmp/set/idle.bvh"
fails "--skeleton-map" "$mm" simulate "$db" --random 1 --seconds 1 -o "$o/s.bvh" --skeleton-map "$script"
fails "--path" "$mm" simulate "$db" --random 1 --path "$script" --seconds 1 -o "$o/s.bvh"
# a map naming joints neither skeleton has, or of the wrong shape: the map file and the field
printf '{"pairs": {"NoSuchJoint": "Hips"}}' >"$tmp/map_joint.json"
fails "NoSuchJoint" "$mm" simulate "$db" --random 1 --seconds 1 -o "$o/s.bvh" --skeleton "$tmp/set/idle.bvh" \
    --skeleton-map "$tmp/map_joint.json"
printf '{"follow": [{"joint": "Twist"}]}' >"$tmp/map_follow.json"
fails "follow" "$mm" simulate "$db" --random 1 --seconds 1 -o "$o/s.bvh" --skeleton "$tmp/set/idle.bvh" \
    --skeleton-map "$tmp/map_follow.json"
printf '{"root": 1}' >"$tmp/map_root.json"
fails "map_root.json" "$mm" simulate "$db" --random 1 --seconds 1 -o "$o/s.bvh" --skeleton "$tmp/set/idle.bvh" \
    --skeleton-map "$tmp/map_root.json"
values --seed "$not_ints -0" "$mm" synth "$o/synth"
values --fps "$not_numbers 0 -1 9 241 1e300" "$mm" synth "$o/synth"
values --window "$not_ints 0 257 1e9" "$mm" similarity "$db" --from idle --to walk -o "$o/audit"
values --threads "$not_ints 0 65 1e9" "$mm" similarity "$db" --from idle --to walk -o "$o/audit"
values --measure "manhattan COS" "$mm" similarity "$db" --from idle --to walk -o "$o/audit"
values --channels "position pos,,x rot;vel" "$mm" similarity "$db" --from idle --to walk -o "$o/audit"
values --poor "$not_numbers" "$mm" similarity "$db" --from idle --to walk -o "$o/audit"
names --from "$mm" similarity "$db" --to walk -o "$o/audit"
names --to "$mm" similarity "$db" --from idle -o "$o/audit"
names -o "$mm" similarity "$db" --from idle --to walk
values --window "$not_ints 0 257" "$mm" similarity build "$db" -o "$o/b.sim"
values --threads "$not_ints 0 65" "$mm" similarity build "$db" -o "$o/b.sim"
names -o "$mm" similarity build "$db"
names --db "$mm" similarity info "$sim"
values --phase "$not_numbers" "$mm" pfnn eval --weights "$tmp/no_weights" --x "$tmp/row.bin" -o "$o/y.bin"
values --mode "quartic" "$mm" pfnn eval --weights "$tmp/no_weights" --x "$tmp/row.bin" --phase 0 -o "$o/y.bin"
values --batch-size "$not_ints 0" "$mm" convert "$tmp/bvh_in" "$o/fbx" --blender "$mm"
names --blender "$mm" convert "$tmp/bvh_in" "$o/fbx"
# more of a repeated option than the command holds
set -- "$mm" db search "$db" --frame 0
i=0
while [ $i -lt 65 ]; do
    set -- "$@" --require Walk
    i=$((i + 1))
done
fails "--require" "$@"

# --- valid but absurd values: an error naming the option or file, or a result; no crash, no hang --
fails "$chain" "$mm" bvh fk "$chain" --frame 2147483647
fails "$db" "$mm" db search "$db" --frame 2147483647
fails "$db" "$mm" db search "$db" --frame 0 --traj-from 2147483647
succeeds "$mm" db search "$db" --frame 0 --top 1000
fails "--seconds" "$mm" simulate "$db" --random 1 --seconds 36000 --fps 1000 -o "$o/s.bvh" --metrics "$o/s.json"
succeeds "$mm" bvh spans "$tmp/set/walk_1.40.bvh" --low-hips 100 --pad 1e7
fails "--pad" "$mm" bvh spans "$tmp/set/walk_1.40.bvh" --low-hips 100 --pad 1e300
succeeds "$mm" bvh spans "$tmp/set/walk_1.40.bvh" --low-hips 100 --pad 99999999999
succeeds "$mm" bvh spans "$tmp/set/walk_1.40.bvh" --idle-min 1e30 --idle-speed 1e30
succeeds "$mm" db build "$tmp/db.json" --data "$tmp/set" -o "$tmp/db64.mmdb" --threads 64
if cmp -s "$db" "$tmp/db64.mmdb"; then ok; else bad "db build --threads 64 gave other bytes"; fi
succeeds "$mm" similarity build "$db" --window 256 --threads 64 -o "$tmp/big_window.sim"

# --- outputs that cannot be written: nothing is left behind ------------------------------------------
fails "$nodir/c.bvh" "$mm" bvh convert "$chain" "$nodir/c.bvh"
fails "$nodir/b.mmdb" "$mm" db build "$tmp/db.json" --data "$tmp/set" -o "$nodir/b.mmdb"
fails "$nodir/s.bvh" "$mm" simulate "$db" --random 1 --seconds 1 -o "$nodir/s.bvh" --metrics "$o/s.json"
fails "$nodir/s.json" "$mm" simulate "$db" --random 1 --seconds 1 -o "$o/s.bvh" --metrics "$nodir/s.json"
fails "$nodir/audit" "$mm" similarity "$db" --from idle --to walk -o "$nodir/audit"
fails "$nodir/b.sim" "$mm" similarity build "$db" -o "$nodir/b.sim"
fails "$tmp/garbage" "$mm" synth "$tmp/garbage/set"
fails "$tmp/garbage" "$mm" synth "$tmp/garbage"
# several outputs appear together or not at all: the one that cannot be written keeps the others out
if "$mm" render "$chain" -o "$tmp/can_render" --size 32x32 --seconds 0.05 >/dev/null 2>&1; then
    fails "$tmp/folder" "$mm" simulate "$db" --random 1 --seconds 0.5 -o "$tmp/folder" --metrics "$o/s.json" \
        --video "$o/frames" --size 32x32
    fails "$nodir/s.bvh" "$mm" simulate "$db" --random 1 --seconds 0.5 -o "$nodir/s.bvh" --metrics "$o/s.json" \
        --video "$o/v.gif" --size 32x32
    fails "$nodir/v.gif" "$mm" simulate "$db" --random 1 --seconds 0.5 -o "$o/s.bvh" --metrics "$o/s.json" \
        --video "$nodir/v.gif" --size 32x32
fi
mkdir -p "$tmp/audit_out/similarity.png"
fails "similarity.png" "$mm" similarity "$db" --from idle --to walk -o "$tmp/audit_out"
if [ ! -e "$tmp/audit_out/similarity.csv" ] && [ ! -e "$tmp/audit_out/poor.csv" ]; then ok; else bad "audit CSV left beside a failed PNG"; fi
mkdir -p "$tmp/synth_out/clips.json"
fails "clips.json" "$mm" synth "$tmp/synth_out"
if [ -z "$(find "$tmp/synth_out" -name '*.bvh')" ]; then ok; else bad "mm synth left BVH files beside a failed clips.json"; fi
# an output that is a folder
fails "$tmp/folder" "$mm" bvh convert "$chain" "$tmp/folder"
fails "$tmp/folder" "$mm" db build "$tmp/db.json" --data "$tmp/set" -o "$tmp/folder"
fails "$tmp/folder" "$mm" similarity build "$db" -o "$tmp/folder"
fails "$tmp/folder" "$mm" simulate "$db" --random 1 --seconds 1 -o "$tmp/folder" --metrics "$o/s.json"
fails "$tmp/folder" "$mm" simulate "$db" --random 1 --seconds 1 -o "$o/s.bvh" --metrics "$tmp/folder"
# a path longer than any file name
long=$tmp/$(printf '%0300d' 0)/$(printf '%04000d' 0)
fails "the path is too long" "$mm" similarity build "$db" -o "$long/x.sim"
fails "the path is too long" "$mm" similarity "$db" --from idle --to walk -o "$long"

if [ -z "$(ls -A "$o")" ]; then ok; else bad "a failed command left output behind: $(ls -A "$o")"; fi
leftovers=$(find "$tmp" -name '*.tmp*')
if [ -z "$leftovers" ]; then ok; else bad "temporary files left behind: $leftovers"; fi

finish test_cli_bad_input
