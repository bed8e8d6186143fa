#!/bin/sh
# End-to-end tests of mm simulate --trace on the built-in set: every line is JSON, the header says
# how the run was made, one search line per search the run reports, candidates winner first and
# then by cost, their terms add up to their cost, the winner is where playback went, the tick
# lines follow the ticks, the same run gives the same bytes, and the options are checked.
# usage: test_trace_cli.sh MM_BINARY SOURCE_DIR
set -u
mm=$1
src=$2
. "$(dirname "$0")/cli_checks.sh"

if ! command -v python3 >/dev/null 2>&1; then
    echo "test_trace_cli: python3 is needed to read the JSON lines (skipped)"
    exit 77
fi

expect_exit 0 "$mm" synth "$tmp/synth"
expect_exit 0 "$mm" db build "$src/configs/synth.json" --data "$tmp/synth" -o "$tmp/s.mmdb"

# a run with turns, stops and runs: the trace with tick lines, and its summary line
expect_exit 0 "$mm" simulate "$tmp/s.mmdb" --input "$src/scripts/input/demo.json" --seconds 8 -o "$tmp/a.bvh" \
    --trace "$tmp/a.jsonl" --trace-ticks --trace-k 6
searches=$(sed -n 's/.* \([0-9]*\) searches, \([0-9]*\) transitions.*/\1/p' "$tmp/out")
transitions=$(sed -n 's/.* \([0-9]*\) searches, \([0-9]*\) transitions.*/\2/p' "$tmp/out")
if [ -n "$searches" ] && [ "$searches" -gt 10 ]; then ok; else bad "searches '$searches'"; fi

# the lines, checked one by one
if python3 - "$tmp/a.jsonl" "$searches" "$transitions" "$src/scripts/input/demo.json" >"$tmp/check" 2>&1 <<'PY'
import json, sys
path, searches, transitions, script = sys.argv[1], int(sys.argv[2]), int(sys.argv[3]), sys.argv[4]
lines = open(path).read().split("\n")
assert lines[-1] == "", "the file ends with a newline"
rows = [json.loads(l) for l in lines[:-1]]          # every line parses on its own
h = rows[0]
assert h["type"] == "header" and h["format"] == "mm-trace" and h["version"] == 1, h
assert h["fps"] == 60 and h["ticks"] == 480 and h["top_k"] == 6 and h["tick_lines"] is True
assert h["input"]["kind"] == "script" and h["input"]["text"] == open(script).read(), "the script verbatim"
assert len(h["database"]["checksum"]) == 16 and h["database"]["frames"] > 1000
names = h["terms"]
assert len(names) >= 5 and names[:5] == ["pose_position", "pose_velocity", "root_velocity",
                                          "traj_position", "traj_direction"], names
s = [r for r in rows[1:] if r["type"] == "search"]
ticks = [r for r in rows[1:] if r["type"] == "tick"]
assert len(s) == searches, (len(s), searches)
assert sum(1 for r in s if r["transition"]) == transitions, "one transition per jump the run counted"
assert [t["tick"] for t in ticks] == list(range(480)), "one tick line per tick, in order"
by_tick = {t["tick"]: t for t in ticks}
for r in s:
    c = r["candidates"]
    assert 1 <= len(c) <= 6 and len(r["query"]) == h["database"]["dims"]
    assert abs(r["t"] - (r["tick"] + 1) / 60.0) < 1e-9
    # winner first (within the search's tie tolerance of the lowest), then by cost then frame
    assert c[0]["cost"] <= min(x["cost"] for x in c) + 1e-6 * abs(c[0]["cost"]) + 1e-9, r["tick"]
    for a, b in zip(c[1:], c[2:]):
        assert (a["cost"], a["frame"]) <= (b["cost"], b["frame"]), (r["tick"], a, b)
    for x in c:
        assert set(x["terms"]) == set(names)
        total = sum(x["terms"].values())
        assert abs(total - x["cost"]) <= 1e-4 * (1 + abs(x["cost"])), (r["tick"], total, x["cost"])
        assert all(x["terms"][n] >= 0 for n in names[:5])
    # the winner is where playback went: the best candidate after a jump, else the frame playing on
    t = by_tick[r["tick"]]
    assert r["winner"] == t["frame"], (r["tick"], r["winner"], t["frame"])
    # a jump goes to the candidate chosen: the winner, or one that plants no swinging foot (at
    # most a quarter of the winner's cost dearer); playing on to let a foot land chooses -1
    if r["transition"]:
        assert r["winner"] == r["choice"], r["tick"]
        chosen = [x for x in c if x["frame"] == r["choice"]]
        assert not chosen or chosen[0]["cost"] <= 1.25 * c[0]["cost"] + 1e-6, r["tick"]
    elif r["choice"] == -1:
        assert r["winner"] == t["frame"]
for t in ticks:
    assert len(t["feet"]) == 2 and all(set(f) >= {"heel", "toe", "locked"} for f in t["feet"])
    assert len(t["root"]["position"]) == 3 and len(t["root"]["facing"]) == 4
print("lines", len(rows), "searches", len(s), "transitions", sum(1 for r in s if r["transition"]))
PY
then ok; else bad "the trace's lines:"; cat "$tmp/check"; fi

# the same run, the same bytes (another output name; searches only, the default k)
expect_exit 0 "$mm" simulate "$tmp/s.mmdb" --input "$src/scripts/input/demo.json" --seconds 8 -o "$tmp/b.bvh" \
    --trace "$tmp/b.jsonl" --trace-ticks --trace-k 6
if cmp -s "$tmp/a.jsonl" "$tmp/b.jsonl"; then ok; else bad "a second run wrote other bytes"; fi
if cmp -s "$tmp/a.bvh" "$tmp/b.bvh"; then ok; else bad "the motion differs between the runs"; fi
# tracing changes nothing of the motion
expect_exit 0 "$mm" simulate "$tmp/s.mmdb" --input "$src/scripts/input/demo.json" --seconds 8 -o "$tmp/c.bvh"
if cmp -s "$tmp/a.bvh" "$tmp/c.bvh"; then ok; else bad "the motion with a trace differs from the motion without"; fi

# random input: the header has the seed; the default k is 5 and there are no tick lines
expect_exit 0 "$mm" simulate "$tmp/s.mmdb" --random 3 --seconds 2 -o "$tmp/r.bvh" --trace "$tmp/r.jsonl"
if python3 -c '
import json, sys
rows = [json.loads(l) for l in open(sys.argv[1])]
h = rows[0]
assert h["input"] == {"kind": "random", "seed": 3, "seconds": 2}, h["input"]
assert h["top_k"] == 5 and h["tick_lines"] is False
assert all(r["type"] == "search" and len(r["candidates"]) <= 5 for r in rows[1:]) and len(rows) > 2
' "$tmp/r.jsonl" 2>"$tmp/check"; then ok; else bad "the random run's trace:"; cat "$tmp/check"; fi

# refusals: options without --trace, a k out of range, a trace that cannot be written (no output left)
expect_exit 2 "$mm" simulate "$tmp/s.mmdb" --random 3 --seconds 1 -o "$tmp/x.bvh" --trace-ticks
expect_grep "need --trace" "$tmp/err"
expect_exit 2 "$mm" simulate "$tmp/s.mmdb" --random 3 --seconds 1 -o "$tmp/x.bvh" --trace "$tmp/x.jsonl" --trace-k 0
expect_grep "trace-k" "$tmp/err"
expect_exit 1 "$mm" simulate "$tmp/s.mmdb" --random 3 --seconds 1 -o "$tmp/x.bvh" --trace "$tmp/no/such/x.jsonl"
if [ ! -e "$tmp/x.bvh" ]; then ok; else bad "a failed trace left the motion behind"; fi

finish test_trace_cli
