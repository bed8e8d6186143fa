#!/bin/sh
# Makes the seed corpora of fuzz_mmdb and fuzz_sim from the project's own procedural motion (mm
# synth), nothing else: two tiny motion databases built from short cuts of a few built-in clips
# (fuzz/seed_configs/small.json: one clip, 2 frames; rich.json: idle, loop, mirrored, ranged, tagged
# and blended clips, 20 frames; and rich_compressed: its poses compressed) and similarity tables of each (cosine and Euclidean, windows 1 and 2,
# every channel).
#
#   fuzz/make_seeds.sh MM_BINARY [OUTDIR]     writes OUTDIR/mmdb/*.mmdb and OUTDIR/sim/*.sim
#                                             (default OUTDIR: fuzz/corpus, the committed seeds)
#
# Each seed stays well under the 32768 bytes scripts/fuzz.sh lets the fuzzers use (-max_len).
# Re-run it when the .mmdb or tables format changes: tests/test_fuzz_seeds.sh fails then.
set -eu

if [ $# -lt 1 ] || [ $# -gt 2 ]; then
    echo "usage: $0 MM_BINARY [OUTDIR]" >&2
    exit 2
fi
mm=$1
here=$(cd "$(dirname "$0")" && pwd)
out=${2:-$here/corpus}
limit=32768

tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
"$mm" synth "$tmp/set" >/dev/null
mkdir -p "$out/mmdb" "$out/sim"
for c in small rich; do
    "$mm" db build "$here/seed_configs/$c.json" --data "$tmp/set" -o "$out/mmdb/$c.mmdb" >/dev/null
done
# the same poses compressed (segments of 8 frames: several per clip)
"$mm" db compress "$out/mmdb/rich.mmdb" --segment-frames 8 --threads 1 -o "$out/mmdb/rich_compressed.mmdb" >/dev/null
"$mm" similarity build "$out/mmdb/small.mmdb" --threads 1 -o "$out/sim/small.sim" >/dev/null
"$mm" similarity build "$out/mmdb/rich.mmdb" --threads 1 --window 2 -o "$out/sim/rich_cos_w2.sim" >/dev/null
"$mm" similarity build "$out/mmdb/rich.mmdb" --threads 1 --measure euclid --channels pos,rot,vel \
    -o "$out/sim/rich_euclid_all.sim" >/dev/null

status=0
for f in "$out"/mmdb/*.mmdb "$out"/sim/*.sim; do
    size=$(wc -c <"$f" | tr -d ' ')
    if [ "$size" -ge "$limit" ]; then
        echo "$0: $f is $size bytes, not under $limit" >&2
        status=1
    fi
    echo "$f: $size bytes"
done
exit $status
