#!/bin/sh
# No success on nonsense (issue 25): a run shorter than the two frames a run needs or longer than a
# BVH file mm can read back, a start past the
# end of the clip, a --write to a config that cannot be written (found before anything is
# detected, even when nothing is found), and JSON that is not strict (a key given twice, text
# after the value) are refused: exit 2 (usage) or 1 (bad input), exactly one line on stderr, a
# "mm: ..." or "mm COMMAND: ..." line naming what is wrong (and the file, line and column of a JSON
# error), nothing written. The limits (--seconds at --fps) are the documented ones.
# usage: test_cli_refusals.sh MM_BINARY SOURCE_DIR
set -u
mm=$1
src=$2
. "$(dirname "$0")/cli_checks.sh"

# refused CODE TEXT CMD... : CMD exits CODE with one stderr line, "mm[ COMMAND]: ..." holding TEXT
refused() {
    want=$1
    text=$2
    shift 2
    "$@" >"$tmp/out" 2>"$tmp/err" </dev/null
    got=$?
    # the sanitizer build may add its suppression statistics: mm's own lines are what is counted
    lines=$(grep -v -e '^-*$' -e '^Suppressions used:' -e '^ *count *bytes template' -e '^ *[0-9]* *[0-9]* [a-zA-Z].*\.so' "$tmp/err" | wc -l | tr -d ' ')
    if [ "$got" -ne "$want" ]; then
        bad "exit $got (wanted $want): $*"
        head -n 5 "$tmp/err"
    elif grep -q -e 'ERROR: [A-Za-z]*Sanitizer' -e 'runtime error' "$tmp/err"; then
        bad "sanitizer report: $*"
        head -n 20 "$tmp/err"
    elif [ "$lines" -ne 1 ] || ! grep -q '^mm[a-z ]*: ' "$tmp/err" || ! grep -q -F -e "$text" "$tmp/err"; then
        bad "wanted one line 'mm...: ...$text...' on stderr: $*"
        cat "$tmp/err"
    else
        ok
    fi
}

"$mm" synth "$tmp/set" >/dev/null || { bad "mm synth"; finish test_cli_refusals; exit 1; }
"$mm" db build "$src/configs/synth.json" --data "$tmp/set" -o "$tmp/db.mmdb" >/dev/null 2>&1 ||
    { bad "mm db build"; finish test_cli_refusals; exit 1; }
out="$tmp/outputs"
mkdir -p "$out"

# mm simulate: fewer than 2 frames is not a run (it wrote a 0-frame BVH with a NaN foot slide)
refused 2 "--seconds 0.001 at --fps 60 is less than 2 frames" \
    "$mm" simulate "$tmp/db.mmdb" --random 1 --seconds 0.001 -o "$out/a.bvh"
refused 2 "--seconds 0.03 at --fps 60 is less than 2 frames" \
    "$mm" simulate "$tmp/db.mmdb" --random 1 --seconds 0.03 -o "$out/a.bvh"
refused 2 "--seconds 0.4 at --fps 2 is less than 2 frames" \
    "$mm" simulate "$tmp/db.mmdb" --random 1 --seconds 0.4 --fps 2 -o "$out/a.bvh"
[ -z "$(ls -A "$out")" ] && ok || bad "a refused run left $(ls "$out")"
# a run whose BVH mm could not read back (over 2 GiB) is refused before it starts
refused 1 "more than the 2 GiB mm reads" "$mm" simulate "$tmp/db.mmdb" --random 1 --seconds 36000 -o "$out/a.bvh"
# a run ended by a signal leaves no temporary file (nor an output) behind
"$mm" simulate "$tmp/db.mmdb" --random 1 --seconds 20000 -o "$out/signal.bvh" --metrics "$out/signal.json" \
    >/dev/null 2>&1 &
pid=$!
waited=0 # until its temporary output exists (the run is under way), at most 120 s
while [ -z "$(ls -A "$out")" ] && [ "$waited" -lt 1200 ]; do
    sleep 0.1
    waited=$((waited + 1))
done
[ -n "$(ls -A "$out")" ] && ok || bad "mm simulate made no temporary file"
kill -TERM "$pid"
wait "$pid"
[ -z "$(ls -A "$out")" ] && ok || bad "a run ended by SIGTERM left $(ls "$out")"
# ... nor the video's, which the encoder writes
if command -v ffmpeg >/dev/null 2>&1; then
    "$mm" simulate "$tmp/db.mmdb" --random 1 --seconds 20000 -o "$out/signal.bvh" --video "$out/signal.mp4" \
        --size 64x36 >/dev/null 2>&1 &
    pid=$!
    waited=0
    while ! ls "$out" | grep -q 'signal.mp4.tmp' && [ "$waited" -lt 1200 ]; do
        sleep 0.1
        waited=$((waited + 1))
    done
    ls "$out" | grep -q 'signal.mp4.tmp' && ok || bad "mm simulate --video made no temporary video"
    kill -TERM "$pid"
    wait "$pid"
    sleep 1 # the encoder ends when its input closes
    [ -z "$(ls -A "$out")" ] && ok || bad "a video run ended by SIGTERM left $(ls "$out")"
fi
# two frames is the shortest run, and its foot slide is a number
expect_exit 0 "$mm" simulate "$tmp/db.mmdb" --random 1 --seconds 0.034 -o "$out/two.bvh"
expect_grep "2 frames at 60 fps" "$tmp/out"
if grep -q nan "$tmp/out"; then bad "a NaN in: $(cat "$tmp/out")"; else ok; fi

# mm render: a start past the end (it rendered the last frame)
clip="$tmp/set/walk_1.40.bvh"
[ -f "$clip" ] || clip=$(ls "$tmp/set"/*.bvh | head -n 1)
refused 1 "--from 1e+09 s is past the end of the clip" "$mm" render "$clip" --from 1e9 -o "$out/r.gif"
refused 1 "$clip" "$mm" render "$clip" --from 1e9 --contact-sheet "$out/s.png"
[ -z "$(ls -A "$out" | grep -v two.bvh)" ] && ok || bad "a refused render left $(ls "$out")"

# a video that cannot be written: one line naming it (the encoder named its temporary file)
if command -v ffmpeg >/dev/null 2>&1; then
    refused 1 "/nonexistent/v.gif: cannot create" "$mm" render "$clip" --seconds 0.2 -o /nonexistent/v.gif
    refused 1 "/nonexistent/v.mp4: cannot create" \
        "$mm" simulate "$tmp/db.mmdb" --random 1 --seconds 1 -o "$out/v.bvh" --video /nonexistent/v.mp4
    [ ! -e "$out/v.bvh" ] && ok || bad "a failed video left v.bvh"
fi

# mm moves detect --write: the config must exist and be writable, whatever is found (it exited 0
# when nothing was found)
refused 1 "/nonexistent/c.json" "$mm" moves detect "$out/two.bvh" --write /nonexistent/c.json
refused 1 "$out/none.json" "$mm" moves detect "$out/two.bvh" --write "$out/none.json"
mkdir -p "$out/dir.json"
refused 1 "$out/dir.json" "$mm" moves detect "$out/two.bvh" --write "$out/dir.json"
# a config that can be written and nothing found: says so, leaves it as it was
cp "$src/configs/synth.json" "$out/c.json"
expect_exit 0 "$mm" moves detect "$out/two.bvh" --write "$out/c.json"
expect_grep "unchanged (0 moves found)" "$tmp/out"
cmp -s "$src/configs/synth.json" "$out/c.json" && ok || bad "--write changed the config though nothing was found"

# strict JSON in configs, input scripts and scenes: file, line and column
printf '{"interval": 0.1,\n "interval": 0.5}\n' >"$out/dup.json"
refused 1 "$out/dup.json:2:2: key 'interval' given twice (first at line 1, column 2)" "$mm" config check "$out/dup.json"
printf '{"interval": 0.1} junk\n' >"$out/junk.json"
refused 1 "$out/junk.json:1:19: text after the JSON value" "$mm" config check "$out/junk.json"
printf '[]' >"$out/array.json"
refused 1 "$out/array.json:1:1: the config must be an object" "$mm" config check "$out/array.json"
printf '{"keys": [{"t": 0, "stick": [0, 1]}]}\n{}' >"$out/in.json"
refused 1 "$out/in.json:2:1: text after the JSON value" \
    "$mm" simulate "$tmp/db.mmdb" --input "$out/in.json" --seconds 1 -o "$out/b.bvh"
printf '{"keys": [\n {"t": 0, "stick": [0, 1], "facing": [1e308, 0]}]}' >"$out/in2.json"
refused 1 "$out/in2.json:2:39: keys[0].facing[0]: 1e308 does not fit a float" \
    "$mm" simulate "$tmp/db.mmdb" --input "$out/in2.json" --seconds 1 -o "$out/b.bvh"
printf '{"ground": 0, "boxes": [], "ground": 1}' >"$out/scene.json"
refused 1 "$out/scene.json:1:28: key 'ground' given twice" \
    "$mm" simulate "$tmp/db.mmdb" --random 1 --scene "$out/scene.json" --seconds 1 -o "$out/b.bvh"
[ ! -e "$out/b.bvh" ] && ok || bad "a refused simulate wrote b.bvh"

# a Collada file that crashes assimp (200,000 nested nodes: an unbounded recursion upstream): the
# import runs in a child process, so mm says so instead of going down, in mm import info and in a
# database build that names the file
awk 'BEGIN {
    printf "<?xml version=\"1.0\"?>\n<COLLADA xmlns=\"http://www.collada.org/2005/11/COLLADASchema\" version=\"1.4.1\">\n";
    printf "<library_visual_scenes><visual_scene id=\"s\">";
    for (i = 0; i < 200000; ++i) printf "<node id=\"n\">";
    for (i = 0; i < 200000; ++i) printf "</node>";
    printf "</visual_scene></library_visual_scenes><scene><instance_visual_scene url=\"#s\"/></scene></COLLADA>\n"
}' >"$tmp/deep.dae"
if "$mm" import info "$tmp/deep.dae" 2>&1 | grep -q "built without assimp"; then
    echo "mm was built without assimp: the importer isolation is not checked"
else
    refused 1 "deep.dae: the importer failed" "$mm" import info "$tmp/deep.dae"
    printf '{"clips": [{"file": "%s"}]}\n' "$tmp/deep.dae" >"$out/deep.json"
    refused 1 "deep.dae: the importer failed" "$mm" db build "$out/deep.json" -o "$out/deep.mmdb"
    [ ! -e "$out/deep.mmdb" ] && ok || bad "a failed build wrote deep.mmdb"
fi

# An output that is a pipe or a device (/dev/null) is written in place, not replaced by a renamed
# file: a named pipe read by cat gets the whole BVH and is still a pipe afterwards.
if mkfifo "$tmp/pipe.bvh" 2>/dev/null; then
    cat "$tmp/pipe.bvh" >"$tmp/piped.bvh" &
    reader=$!
    "$mm" simulate "$tmp/db.mmdb" --random 1 --seconds 0.5 -o "$tmp/pipe.bvh" >/dev/null 2>"$tmp/err" ||
        { bad "mm simulate -o PIPE failed"; cat "$tmp/err"; }
    wait "$reader"
    [ -p "$tmp/pipe.bvh" ] && ok || bad "the pipe was replaced by a file"
    head -n 1 "$tmp/piped.bvh" | grep -q '^HIERARCHY' && grep -q '^Frames: 30' "$tmp/piped.bvh" && ok ||
        bad "the pipe's reader did not get the BVH"
    ls "$tmp" | grep -q 'pipe.bvh.tmp' && bad "a temporary file was left beside the pipe" || ok
fi

finish test_cli_refusals
