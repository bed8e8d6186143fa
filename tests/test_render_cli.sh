#!/bin/sh
# End-to-end tests of what draws: mm render (headless), mm simulate --video, and mm view in a
# virtual X display (Xvfb) when xvfb-run is installed (otherwise those cases are left out).
# usage: test_render_cli.sh MM_BINARY SOURCE_DIR
set -u
mm=$1
src=$2
. "$(dirname "$0")/cli_checks.sh"
# the width and height of a PNG, from its IHDR chunk
png_size() { od -An -tu1 -j16 -N8 "$1" | awk '{printf "%dx%d", $3 * 256 + $4, $7 * 256 + $8}'; }
expect_png() { # FILE WxH
    if [ -f "$1" ] && [ "$(png_size "$1")" = "$2" ]; then ok; else bad "$1 is not a $2 PNG"; fi
}

expect_exit 0 "$mm" synth "$tmp/synth"
expect_exit 0 "$mm" db build "$src/configs/synth.json" --data "$tmp/synth" -o "$tmp/s.mmdb"

# mm render: 0.2 s at 30 fps is frames 0..6
expect_exit 0 "$mm" render "$tmp/synth/walk_1.40.bvh" -o "$tmp/frames" --size 160x90 --seconds 0.2
expect_grep "7 frames, 160 x 90 at 30 fps" "$tmp/out"
expect_png "$tmp/frames/frame_00006.png" 160x90
[ ! -e "$tmp/frames/frame_00007.png" ] && ok || bad "an 8th frame"
expect_exit 2 "$mm" render "$tmp/synth/walk_1.40.bvh" -o "$tmp/x" --size 10x10
expect_exit 2 "$mm" render "$tmp/synth/walk_1.40.bvh"
expect_exit 1 "$mm" render "$tmp/missing.bvh" -o "$tmp/x"
expect_grep "missing.bvh" "$tmp/err"
: >"$tmp/file"
expect_exit 1 "$mm" render "$tmp/synth/walk_1.40.bvh" -o "$tmp/file" --seconds 0.1
expect_grep "not a folder" "$tmp/err"

# mm render --contact-sheet: one PNG of the size asked for (tiles: tests/test_render.c); the grid
# and the tiles it makes are checked before anything is drawn
expect_exit 0 "$mm" render "$tmp/synth/walk_1.40.bvh" --contact-sheet "$tmp/sheet.png" --grid 3x2 --size 480x360
expect_grep "6 frames (3 x 2)" "$tmp/out"
expect_png "$tmp/sheet.png" 480x360
expect_exit 0 "$mm" render "$tmp/synth/walk_1.40.bvh" --contact-sheet "$tmp/sheet_default.png" --seconds 1
expect_grep "24 frames (6 x 4) from 0.00 to 1.00 s" "$tmp/out"
expect_png "$tmp/sheet_default.png" 1920x1080
expect_exit 2 "$mm" render "$tmp/synth/walk_1.40.bvh" --contact-sheet "$tmp/x.png" --grid 6
expect_grep "grid needs COLUMNSxROWS" "$tmp/err"
expect_exit 2 "$mm" render "$tmp/synth/walk_1.40.bvh" --contact-sheet "$tmp/x.png" --grid 0x4
expect_exit 2 "$mm" render "$tmp/synth/walk_1.40.bvh" --contact-sheet "$tmp/x.png" --grid 20x4 --size 640x360
expect_grep "tiles of 32 x 90" "$tmp/err"
expect_exit 2 "$mm" render "$tmp/synth/walk_1.40.bvh" --contact-sheet "$tmp/x.png" -o "$tmp/frames2"
[ ! -e "$tmp/x.png" ] && ok || bad "a refused contact sheet left x.png"
expect_exit 2 "$mm" render "$tmp/synth/walk_1.40.bvh" -o "$tmp/frames2" --grid 2x2
expect_grep "grid goes with --contact-sheet" "$tmp/err"

# mm simulate --video: frames every 1/30 s of the 1 s simulated, and the motion beside them
expect_exit 0 "$mm" simulate "$tmp/s.mmdb" --input "$src/scripts/input/turn_90.json" --seconds 1 \
    -o "$tmp/sim.bvh" --metrics "$tmp/sim.json" --video "$tmp/simframes" --size 128x72
expect_grep "31 video frames" "$tmp/out"
expect_png "$tmp/simframes/frame_00030.png" 128x72
if command -v ffmpeg >/dev/null 2>&1; then
    expect_exit 0 "$mm" simulate "$tmp/s.mmdb" --random 3 --seconds 1 -o "$tmp/sim.bvh" --video "$tmp/sim.mp4" \
        --size 128x72
    [ -s "$tmp/sim.mp4" ] && ok || bad "no sim.mp4"
    expect_exit 0 "$mm" render "$tmp/synth/idle.bvh" -o "$tmp/idle.gif" --size 64x64 --seconds 0.3 --fps 10
    [ "$(head -c 6 "$tmp/idle.gif")" = "GIF89a" ] && ok || bad "idle.gif is not a GIF"
    # an odd size cannot be an MP4: refused before anything is written, nothing left behind
    expect_exit 1 "$mm" simulate "$tmp/s.mmdb" --random 3 --seconds 1 -o "$tmp/odd.bvh" --video "$tmp/odd.mp4" \
        --size 127x72
    [ ! -e "$tmp/odd.mp4" ] && [ ! -e "$tmp/odd.bvh" ] && ok || bad "output left behind after a refused video"
fi

# mm view in a virtual display: a scripted drive and a clip preview, each saving its last frame.
# (In the sanitizer build, leak reports are off for these two: the X server's GL driver is loaded
# and unloaded at run time and leaves a few allocations LeakSanitizer cannot attribute.)
if command -v xvfb-run >/dev/null 2>&1; then
    expect_exit 0 env ASAN_OPTIONS=detect_leaks=0 xvfb-run -a -s "-screen 0 640x480x24" "$mm" view "$tmp/s.mmdb" \
        --input "$src/scripts/input/turn_90.json" --frames 40 --size 320x240 --screenshot "$tmp/view.png"
    expect_png "$tmp/view.png" 320x240
    expect_exit 0 env ASAN_OPTIONS=detect_leaks=0 xvfb-run -a -s "-screen 0 640x480x24" "$mm" view --clip "$tmp/synth/walk_1.40.bvh" \
        --config "$src/configs/synth.json" --frames 10 --size 320x240 --screenshot "$tmp/clip.png"
    expect_png "$tmp/clip.png" 320x240
fi
expect_exit 2 "$mm" view
expect_exit 2 "$mm" view "$tmp/s.mmdb" --screenshot "$tmp/x.png"
expect_exit 1 "$mm" view --clip "$tmp/synth/walk_1.40.bvh" --config "$src/configs/synth.json" --clip-name nosuch
expect_grep "no clip named nosuch" "$tmp/err"

finish test_render_cli
