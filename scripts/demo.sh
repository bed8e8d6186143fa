#!/bin/sh
# The main job, from a fresh clone: installs what mm needs and builds it (scripts/setup.sh), makes
# the built-in motion set (or uses $MM_DATA_DIR/lafan1 when it is there), builds the motion
# database, drives a character through a scripted demo (walk, run, turns, stops, strafe) and writes
#   out/demo.mp4      the character rendered headless (PNG frames in out/demo_frames/ without ffmpeg)
#   out/demo.bvh      its motion
#   out/metrics.json  its quality metrics (docs/metrics.md)
# then prints a summary.  usage: scripts/demo.sh [--synth]   (--synth: ignore MM_DATA_DIR)
set -e
cd "$(dirname "$0")/.."
scripts/setup.sh --program-only
mkdir -p out
if [ "${1:-}" != "--synth" ] && [ -n "${MM_DATA_DIR:-}" ] && [ -d "$MM_DATA_DIR/lafan1" ]; then
    echo "== motion: LAFAN1 from $MM_DATA_DIR"
    scripts/data_configs.sh out/data_configs
    config=out/data_configs/lafan1.json
    data=$MM_DATA_DIR
else
    echo "== motion: the built-in set (out/synth)"
    build/mm synth out/synth
    config=configs/synth.json
    data=out/synth
fi
echo "== database"
build/mm db build "$config" --data "$data" -o out/demo.mmdb
video=out/demo.mp4
if ! command -v ffmpeg >/dev/null 2>&1; then
    video=out/demo_frames
    echo "ffmpeg is not installed: writing PNG frames to $video/"
fi
echo "== simulation and video"
build/mm simulate out/demo.mmdb --input scripts/input/demo.json --seconds 30 \
    -o out/demo.bvh --metrics out/metrics.json --video "$video"
echo "== metrics (out/metrics.json)"
tr -d '\n' <out/metrics.json | tr -s ' ' && echo
echo "== wrote $video, out/demo.bvh, out/metrics.json"
