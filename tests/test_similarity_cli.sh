#!/bin/sh
# End-to-end tests of mm similarity: the audit outputs, building and checking the tables, errors.
# usage: test_similarity_cli.sh MM_BINARY SOURCE_DIR
set -u
mm=$1
src=$2
. "$(dirname "$0")/cli_checks.sh"

# a database of the built-in set
expect_exit 0 "$mm" synth "$tmp/synth"
expect_exit 0 "$mm" db build "$src/configs/synth.json" --data "$tmp/synth" -o "$tmp/s.mmdb"
db=$tmp/s.mmdb

# audit: a loop against itself, window 4
expect_exit 0 "$mm" similarity "$db" --from walk_1.40 --to walk_1.40 --window 4 -o "$tmp/a"
expect_grep "walk_1.40 (.* frames) -> walk_1.40" "$tmp/out"
expect_grep "0 of .* frames have a poor best match" "$tmp/out"
frames=$(sed -n 's/^walk_1.40 (\([0-9]*\) frames).*/\1/p' "$tmp/out")
# the CSV: a header and one row per frame, one column per frame (+ the frame number)
if [ "$(wc -l <"$tmp/a/similarity.csv")" -eq $((frames + 1)) ]; then ok; else bad "csv rows"; fi
if [ "$(head -1 "$tmp/a/similarity.csv" | tr ',' '\n' | wc -l)" -eq $((frames + 1)) ]; then ok; else bad "csv columns"; fi
# each frame matches itself best (score 1; the clip holds two gait cycles, so a frame one cycle
# away may tie within rounding)
if awk -F, 'NR > 1 { m = $2; for (i = 3; i <= NF; ++i) if ($i > m) m = $i; d = $($1 + 2);
                     if (d < 0.99999 || m - d > 1e-5) bad = 1 }
            END { exit bad }' "$tmp/a/similarity.csv"; then ok; else bad "best match off the diagonal"; fi
# the PNG: signature and size (IHDR width x height = to x from)
if [ "$(head -c 8 "$tmp/a/similarity.png" | od -An -tx1 | tr -d ' \n')" = 89504e470d0a1a0a ]; then ok; else bad "png signature"; fi
if [ "$(od -An -tu1 -j16 -N8 "$tmp/a/similarity.png" | awk '{ print $3 * 256 + $4, $7 * 256 + $8 }')" = "$frames $frames" ]; then
    ok; else bad "png size"; fi
expect_grep "^frame,best_frame,score$" "$tmp/a/poor.csv"

# audit with the distance: a stop against idle has poor frames (the walking part)
expect_exit 0 "$mm" similarity "$db" --from walk_stop --to idle --measure euclid --poor 0.05 -o "$tmp/b"
expect_grep "euclid, window 1" "$tmp/out"
if [ "$(wc -l <"$tmp/b/poor.csv")" -gt 10 ]; then ok; else bad "walk_stop vs idle: no poor frames"; fi

# tables: build (default name beside the database), info, check against the database
expect_exit 0 "$mm" similarity build "$db" --window 4 --threads 2
expect_grep "wrote $db.sim" "$tmp/out"
expect_grep "memory: .* bytes" "$tmp/out"
expect_grep "fusion: .* one-shot frames x 35 loop clips" "$tmp/out"
expect_exit 0 "$mm" similarity build "$db" --window 4 --threads 1 -o "$tmp/one.sim"
if cmp -s "$db.sim" "$tmp/one.sim"; then ok; else bad "tables differ between 1 and 2 threads"; fi
expect_exit 0 "$mm" similarity info "$db.sim" --db "$db"
expect_grep "window: *4 frames" "$tmp/out"
expect_grep "belongs to: *$db" "$tmp/out"

# tables of another database are refused
expect_exit 0 "$mm" synth "$tmp/synth2" --seed 7
expect_exit 0 "$mm" db build "$src/configs/synth.json" --data "$tmp/synth2" -o "$tmp/s2.mmdb"
expect_exit 1 "$mm" similarity info "$db.sim" --db "$tmp/s2.mmdb"
expect_grep "belong to another database" "$tmp/err"
# a corrupted file
cp "$db.sim" "$tmp/bad.sim"
printf 'X' | dd of="$tmp/bad.sim" bs=1 seek=300 conv=notrunc 2>/dev/null
expect_exit 1 "$mm" similarity info "$tmp/bad.sim"
expect_grep "checksum mismatch" "$tmp/err"
expect_exit 1 "$mm" similarity info "$db"
expect_grep "bad magic" "$tmp/err"

# usage errors
expect_exit 2 "$mm" similarity "$db" --from idle -o "$tmp/c"
expect_exit 2 "$mm" similarity "$db" --from idle --to idle --measure manhattan -o "$tmp/c"
expect_exit 2 "$mm" similarity "$db" --from idle --to idle --window 0 -o "$tmp/c"
expect_exit 2 "$mm" similarity build "$db" --bogus
expect_exit 1 "$mm" similarity "$db" --from nope --to idle -o "$tmp/c"
expect_grep "no clip named 'nope'" "$tmp/err"

finish test_similarity_cli
