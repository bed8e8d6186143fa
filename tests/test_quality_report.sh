#!/bin/sh
# scripts/quality_report.sh on a tiny setup: the built-in set, one script and two seeds of 2 s.
# The report's files are there and well formed, and a second report of the same runs (on another
# number of parallel jobs) has the same report.json but for the wall-clock timings (keys *_us).
# usage: test_quality_report.sh MM_BINARY SOURCE_DIR
set -u
mm=$1
src=$2
. "$(dirname "$0")/cli_checks.sh"
png_size() { od -An -tu1 -j16 -N8 "$1" | awk '{printf "%dx%d", $3 * 256 + $4, $7 * 256 + $8}'; }
report() { env MM="$mm" sh "$src/scripts/quality_report.sh" "$@"; }

expect_exit 0 "$mm" synth "$tmp/synth"
expect_exit 0 "$mm" db build "$src/configs/synth.json" --data "$tmp/synth" -o "$tmp/s.mmdb"

expect_exit 0 report "$tmp/s.mmdb" 2 "$tmp/a" --scripts straight_walk --seeds 2 --jobs 2
expect_grep "3 runs" "$tmp/out"
for name in straight_walk random_01 random_02; do
    expect_grep "^| $name | .* | \[sheet\](sheets/$name.png) |$" "$tmp/a/report.md"
    [ "$(png_size "$tmp/a/sheets/$name.png")" = 1920x1080 ] && ok || bad "no 1920x1080 sheets/$name.png"
    # the worst second of slide, where the run slid: its sheet and its link
    if grep -q '^    "foot_slide": {' "$tmp/a/runs/$name.json"; then
        expect_grep "^| $name | .* | \[[0-9.]* s: [0-9.]* cm/s\](sheets/${name}_slide.png) | \[sheet\]" "$tmp/a/report.md"
        [ "$(png_size "$tmp/a/sheets/${name}_slide.png")" = 1920x1080 ] && ok || bad "no sheets/${name}_slide.png"
        slid=1
    fi
done
[ -n "${slid:-}" ] && ok || bad "no run slid: the worst second's sheet is not tested"
expect_grep "^## Over the 2 random seeds" "$tmp/a/report.md"
expect_grep "^| foot_slide_cm_s | 2 | " "$tmp/a/report.md"
expect_grep "^## Wall-clock timing" "$tmp/a/report.md"
json=$tmp/a/report.json
if command -v python3 >/dev/null 2>&1; then
    expect_exit 0 python3 -m json.tool "$json"
else # balanced braces and brackets, an object from the first line to the last
    opened=$(tr -cd '{[' <"$json" | wc -c)
    closed=$(tr -cd '}]' <"$json" | wc -c)
    [ "$opened" -eq "$closed" ] && [ "$(head -n 1 "$json")" = "{" ] && [ "$(tail -n 1 "$json")" = "}" ] && ok ||
        bad "report.json is not well formed"
fi
expect_grep '^    "straight_walk": {$' "$json"
expect_grep '^      "input": "scripts/input/straight_walk.json",$' "$json"
expect_grep '^      "seed": 2,$' "$json"
expect_grep '^      "nan_frames": {"count": 2, "mean": 0, "worst": 0, "worst_run": "random_01"},$' "$json"

# the same runs again, one at a time: the same report but for the timings (report.md's last table)
expect_exit 0 report "$tmp/s.mmdb" 2 "$tmp/b" --scripts straight_walk --seeds 2 --jobs 1
grep -v '_us"' "$tmp/a/report.json" >"$tmp/a.txt"
grep -v '_us"' "$tmp/b/report.json" >"$tmp/b.txt"
if cmp -s "$tmp/a.txt" "$tmp/b.txt"; then ok; else bad "report.json differs between two reports"; diff "$tmp/a.txt" "$tmp/b.txt"; fi
[ "$(grep -c '_us"' "$tmp/a/report.json")" -gt 0 ] && ok || bad "no timing keys in report.json"
sed '/^## Wall-clock timing/,$d' "$tmp/a/report.md" >"$tmp/a.md"
sed '/^## Wall-clock timing/,$d' "$tmp/b/report.md" >"$tmp/b.md"
if cmp -s "$tmp/a.md" "$tmp/b.md"; then ok; else bad "report.md differs before its timings"; diff "$tmp/a.md" "$tmp/b.md"; fi

# usage errors
expect_exit 2 report
expect_exit 2 report "$tmp/s.mmdb" 2 "$tmp/c" --scripts no_such_script
expect_exit 2 report "$tmp/s.mmdb" 2 "$tmp/c" --seeds x
expect_exit 2 report "$tmp/s.mmdb" 2 "$tmp/c" --bogus

finish test_quality_report
