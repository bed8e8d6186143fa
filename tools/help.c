/* The help of the mm program: every command's one-line summary and full usage, in one table that
 * mm.c consults before it runs a command (mm --help, mm help [COMMAND], mm COMMAND [SUB] --help).
 * A command's entry lists every option it accepts with its default; tests/test_help.sh checks
 * that against the command's source. */
#include <stdio.h>
#include <string.h>

#include "cli.h"

typedef struct help_entry {
    const char *command; /* "db build", "simulate" */
    const char *summary; /* one line */
    const char *usage;   /* synopsis, what it does, then its arguments and options with their defaults */
} help_entry;

static const help_entry entries[] = {
    {"bvh info", "joints, frames, fps, duration, channel orders, estimated height and unit",
     "usage: mm bvh info FILE [--json]\n"
     "The skeleton and timing of a BVH file: joints and End Sites, channels, frames, fps, duration, the\n"
     "rotation orders, the estimated height and unit, the hierarchy.\n"
     "  FILE               a BVH file\n"
     "  --json             print JSON (default: text)\n"},
    {"bvh fk", "world position of every joint at one frame",
     "usage: mm bvh fk FILE --frame K\n"
     "One line per joint (End Sites excluded, file order): NAME X Y Z, its world position at frame K\n"
     "in the file's own units.\n"
     "  FILE               a BVH file\n"
     "  --frame K          the frame, 0-based (required)\n"},
    {"bvh convert", "re-write a BVH file: rotation order, scale, frame rate",
     "usage: mm bvh convert IN OUT [--order ZYX] [--scale S|auto] [--fps F]\n"
     "Re-writes a BVH file with another rotation order, rescaled, resampled (C1 splines through the\n"
     "frames, as the database build does).\n"
     "  IN, OUT            the BVH file read and the one written\n"
     "  --order ORDER      XYZ, XZY, YXZ, YZX, ZXY or ZYX for every joint (default: each joint's own)\n"
     "  --scale S|auto     multiply every length by S; auto: detect the unit and convert to metres\n"
     "                     (default 1: the file's units)\n"
     "  --fps F            resample to F frames per second (default: the file's rate)\n"},
    {"bvh spans", "a take's postures, idle and locomotion spans on any skeleton; into a config",
     "usage: mm bvh spans FILE [--config CONFIG.json] [--scale S|auto] [--up AXIS] [--hips NAME]\n"
     "                    [--root-bone NAME] [--head NAME] [--pad 1] [--idle-speed 0.15] [--idle-min 1]\n"
     "                    [--low-hips H] [--write CONFIG.json [--as NAME] [--no-mirror]]\n"
     "The frame spans of a take for a database config, on any skeleton, unit and up axis, as mm config\n"
     "init splits takes (docs/database.md, \"Spans of a take\"): each frame's posture (mm/posture.h)\n"
     "against the take's own upright head height. Calibration poses (T poses, and A poses: the arms\n"
     "straight 15-60 degrees down, held still), lying, getting up or down (2 s around lying) and going\n"
     "down to the ground (2 s around the hips below 0.65 of their upright height), widened by --pad, are\n"
     "left out;\n"
     "in the rest the spans where the root moves slower than --idle-speed for --idle-min seconds are\n"
     "idle, the others locomotion (crouched, bent and arms-spread frames stay: the build tags or cuts\n"
     "them). Prints JSON: the roles used, the spans of each posture, excluded, idle, locomotion.\n"
     "  FILE               a BVH file\n"
     "  --config CONFIG    take the roles (hips, root_bone, head, left_hand, right_hand), the scale and\n"
     "                     the axes from this database config (default: the roles found as mm config\n"
     "                     init finds them, by names and geometry; the up axis from the poses)\n"
     "  --scale S|auto     multiply lengths by S to get metres (default: the config's scale, else auto)\n"
     "  --up AXIS          the take's up: +X, +Y, +Z, -X, -Y or -Z (default: the config's axes.up, else\n"
     "                     the axis the body stands along)\n"
     "  --hips NAME        the hips joint (default: the config's roles.hips, else found)\n"
     "  --root-bone NAME   the joint whose ground projection gives the root's speed (default: the\n"
     "                     config's roles.root_bone, else found: the chest)\n"
     "  --head NAME        the head joint (default: the config's roles.head, else found)\n"
     "  --pad S            seconds left out on each side of a span left out (default 1)\n"
     "  --idle-speed V     m/s under which the root stands (default 0.15)\n"
     "  --idle-min S       seconds it must stand for an idle span (default 1)\n"
     "  --low-hips H       deprecated (postures find lying from the pose): also leave out frames with\n"
     "                     the hips below H m (default: off)\n"
     "  --write CONFIG     add the spans to this config instead of printing them: the locomotion\n"
     "                     spans as clip NAME, the idle ones as NAME_idle\n"
     "  --as NAME          the clips' name (default: the file's name without folder and extension)\n"
     "  --no-mirror        do not mark the written clips to be mirrored (default: mirrored)\n"},
    {"config explain", "what every database config field means",
     "usage: mm config explain [FIELD] [--markdown]\n"
     "Every database config field with its type, unit, default and meaning (docs/config.md).\n"
     "  FIELD              only the fields whose path starts with FIELD (default: all)\n"
     "  --markdown         print a Markdown table (default: text)\n"},
    {"config check", "validate a config and find its clip files",
     "usage: mm config check CONFIG\n"
     "Reads and validates a database config and looks for each of its clip files (beside CONFIG, then\n"
     "in $MM_DATA_DIR); exits 1 when any is missing.\n"
     "  CONFIG             the database config (JSON)\n"},
    {"config init", "a whole database config from the takes: roles, clips, gait speeds",
     "usage: mm config init TAKE... [-o CONFIG.json] [--force] [--name-prefix P] [--scale S|auto] "
     "[--no-tuning] [--up AXIS] [--forward AXIS]\n"
     "Writes a database config from the takes alone and prints what it found and how sure it is: the\n"
     "axes (up and forward: the build turns other axes to +Y up, +Z forward), the bone roles (by names\n"
     "in the common conventions and by the skeleton's geometry), the forward axis, the mirror pairs, the\n"
     "unit, idle and locomotion clips per take with calibration poses, lying and getting up left out,\n"
     "walk and run speeds from the takes (docs/config.md, \"A config from your takes\").\n"
     "  TAKE...            BVH, FBX, glTF or Collada files, of any up axis\n"
     "  -o, --output PATH  the config to write (default: print the report only)\n"
     "  --force            replace an existing config\n"
     "  --name-prefix P    a prefix for the clip names (default: none)\n"
     "  --scale S|auto     metres per file unit (default: auto, from the body's height)\n"
     "  --no-tuning        leave out the runtime tuning of configs/mocap.json (default: carried)\n"
     "  --up AXIS          the takes' up: +X, +Y, +Z, -X, -Y or -Z (default: detected from the poses)\n"
     "  --forward AXIS     the way the character faces in the files, at right angles to up (default:\n"
     "                     +Z; -Y for +Z up, +Y for -Z up)\n"},
    {"convert", "BVH files to FBX through Blender",
     "usage: mm convert BVH_DIR FBX_DIR [--batch-size 10] [--blender PATH] [--verbose]\n"
     "Converts the .bvh files of a folder, sorted by name, to FBX through Blender: batches of\n"
     "--batch-size takes per FBX file, one take per BVH.\n"
     "  BVH_DIR, FBX_DIR   the folder read and the one written\n"
     "  --batch-size N     takes per FBX file, 1 or more (default 10)\n"
     "  --blender PATH     the blender program (default: blender on $PATH)\n"
     "  --verbose          show Blender's output (default: only on failure)\n"},
    {"import info", "the takes of a BVH, FBX, glTF or Collada file",
     "usage: mm import info FILE [--json] [--scale S|auto] [--fps F]\n"
     "The takes of a file as mm imports them: joints, frames, fps, duration, root, height\n"
     "(docs/import.md).\n"
     "  FILE               a BVH, FBX, glTF or Collada file\n"
     "  --json             print JSON (default: text)\n"
     "  --scale S|auto     multiply every length by S; auto: detect the unit (default 1)\n"
     "  --fps F            sample every take at F frames per second (default: each take's own rate)\n"},
    {"db build", "build a motion database from a config; warnings about what it lacks",
     "usage: mm db build CONFIG -o OUT.mmdb [--data DIR] [--threads N] [--compress [--compress-error MM]]\n"
     "Builds a motion database (docs/database.md) and prints what it found: the postures, the\n"
     "standing poses it made when no clip is an idle clip (standing.make), the idle clips it made to\n"
     "loop (idle_loop.make), the runtime's gait speeds against the data, and warnings about what the\n"
     "database lacks (docs/database.md, \"Diagnostics\").\n"
     "  CONFIG             the database config (JSON); clip files are looked for beside it, in DIR,\n"
     "                     then in $MM_DATA_DIR\n"
     "  -o, --output FILE  the database to write (required)\n"
     "  --data DIR         another folder to look for clip files in (default: none)\n"
     "  --threads N        threads, 1 to 64 (default: the online cores, at most 8); the bytes are the\n"
     "                     same for any count\n"
     "  --compress         compress the poses for shipping: every frame's world joint positions within\n"
     "                     the error bound of the floats; features and search data unchanged\n"
     "                     (docs/database.md, \"A smaller database for shipping\")\n"
     "  --compress-error MM  the bound, millimetres in (0, 100] (default 0.5)\n"},
    {"db compress", "the shipping form of a database: its poses compressed within an error bound",
     "usage: mm db compress DB.mmdb -o OUT.mmdb [--error MM] [--segment-frames N] [--threads N]\n"
     "Writes DB.mmdb with its poses compressed, as a compressing build does (docs/database.md, \"A\n"
     "smaller database for shipping\"), and prints the pose bytes per frame and the largest error.\n"
     "  DB.mmdb            a database with its poses as floats\n"
     "  -o, --output FILE  the database to write (required)\n"
     "  --error MM         every frame's world joint positions within MM millimetres, in (0, 100]\n"
     "                     (default 0.5)\n"
     "  --segment-frames N frames per segment, 1 to 256 (default 16)\n"
     "  --threads N        threads, 1 to 64 (default: the online cores, at most 8); the bytes are the\n"
     "                     same for any count\n"},
    {"db info", "what a database holds: clips, features, speeds, settings, warnings",
     "usage: mm db info FILE [--json]\n"
     "What a database holds: frames, joints, clips (and the idle loops the build made), feature\n"
     "groups, distance curves, settings, root speeds per kind of motion, the runtime's gait speeds\n"
     "against them, the speed envelope (what each gait's locomotion covers per direction of travel,\n"
     "docs/runtime.md; JSON: \"speed_envelope\"), tags, every clip, and the warnings of\n"
     "docs/database.md, \"Diagnostics\" (JSON: \"warnings\", each with a code and message).\n"
     "  FILE               a database (.mmdb)\n"
     "  --json             print JSON (default: text)\n"},
    {"db dump", "everything in a database as deterministic text",
     "usage: mm db dump FILE\n"
     "Everything in a database, its settings included, as deterministic text (for diffs and bug\n"
     "reports; docs/format.md).\n"
     "  FILE               a database (.mmdb)\n"},
    {"db search", "the best frames for a query made from database frames, with every cost term",
     "usage: mm db search DB.mmdb --frame I [--traj-from J] [--method fast] [--top 1]\n"
     "                    [--type idle|locomotion|any] [--require TAG]... [--exclude TAG]... [--no-bias]\n"
     "                    [--json]\n"
     "The best frames for the query of frame I's pose and frame J's trajectory, with every term of\n"
     "their cost: \"why this pose\" (docs/search.md).\n"
     "  DB.mmdb            a database\n"
     "  --frame I          the frame whose pose is the query (required)\n"
     "  --traj-from J      the frame whose trajectory is the query (default: I)\n"
     "  --method M         brute, fast or facing (default fast)\n"
     "  --top K            how many results, 1 to 1000 (default 1)\n"
     "  --type T           idle, locomotion or any (default: the type of frame I's clip)\n"
     "  --require TAG      only frames with this tag (repeatable; default: none)\n"
     "  --exclude TAG      no frames with this tag (repeatable; default: none)\n"
     "  --no-bias          no favours for the next pose and loops, no continuing bias (default: the\n"
     "                     search's defaults)\n"
     "  --json             print JSON (default: text)\n"},
    {"metrics", "the metrics a motion gives alone, on any BVH file",
     "usage: mm metrics FILE.bvh [--db DB.mmdb | --config CONFIG.json] [--scale S|auto] [--scene "
     "SCENE.json]\n"
     "                  [-o OUT.json]\n"
     "The metrics of docs/metrics.md that a motion gives alone: pops, joints below the ground, the\n"
     "head's height, posture, arms, a foot slide measure without contact labels.\n"
     "  FILE.bvh           the motion\n"
     "  --db DB.mmdb       take the bone roles and references from this database (default: the\n"
     "                     roles' default joint names and the file itself)\n"
     "  --config CONFIG    instead: take the bone roles from this database config (by name)\n"
     "  --scale S|auto     multiply lengths by S to get metres (default auto)\n"
     "  --scene SCENE.json the ground, boxes and terrain the motion is on (default: flat ground)\n"
     "  -o OUT.json        write the metrics there (default: standard output)\n"},
    {"moves detect", "jumps, vaults, climbs and drops with their events; into a config",
     "usage: mm moves detect FILE.bvh [--config CONFIG.json] [--json] [--write CONFIG.json] [--as NAME]\n"
     "                    [--no-mirror]\n"
     "The jumps, vaults, climbs and drops of a take with their take-off, hand plant and landing\n"
     "(docs/moves_data.md).\n"
     "  FILE.bvh           the take\n"
     "  --config CONFIG    take the roles, scale and move settings from this database config\n"
     "                     (default: the config defaults, the scale detected)\n"
     "  --json             print JSON (default: text)\n"
     "  --write CONFIG     add the moves to this config as clips FILE_KIND_N, tagged by kind and events\n"
     "  --as NAME          the file name the written clips give (default: FILE, relative to\n"
     "                     $MM_DATA_DIR when inside it)\n"
     "  --no-mirror        do not mark the written clips to be mirrored (default: mirrored)\n"},
    {"pfnn eval", "the phase-functioned neural network on raw inputs",
     "usage: mm pfnn eval --weights DIR --x X.bin --phase P [--mode cubic] -o Y.bin\n"
     "Runs the PFNN network on raw inputs, for checking against other implementations (docs/pfnn.md):\n"
     "X.bin holds rows of 342 little-endian float32, Y.bin receives rows of 311.\n"
     "  --weights DIR      the folder holding network/ (default: $MM_DATA_DIR/pfnn)\n"
     "  --x X.bin          the inputs (required)\n"
     "  --phase P          the phase in radians (required)\n"
     "  --mode M           constant, linear or cubic (default cubic)\n"
     "  -o Y.bin           the outputs (required)\n"},
    {"pfnn run", "the neural controller on the same input and metrics as mm simulate",
     "usage: mm pfnn run [--weights DIR] (--input SCRIPT.json | --random SEED) --seconds T [--mode cubic]\n"
     "                   [--symmetry mirror] [--scene SCENE.json] -o OUT.bvh [--metrics OUT.json]\n"
     "The PFNN controller on an input script or random input, measured with mm simulate's metrics\n"
     "(docs/pfnn.md).\n"
     "  --weights DIR      the folder holding network/ (default: $MM_DATA_DIR/pfnn)\n"
     "  --input SCRIPT     an input script (docs/runtime.md); this or --random\n"
     "  --random SEED      seeded random input; this or --input\n"
     "  --seconds T        how long, in (0, 36000] (required)\n"
     "  --mode M           constant, linear or cubic (default cubic)\n"
     "  --symmetry S       mirror or none (default mirror)\n"
     "  --scene SCENE.json the ground the network is fed the heights of, and its walls (default:\n"
     "                     flat ground)\n"
     "  -o OUT.bvh         the motion (required)\n"
     "  --metrics OUT.json the metrics (default: none)\n"},
    {"render", "a BVH clip drawn headless: a video, PNG frames or a contact sheet",
     "usage: mm render FILE.bvh -o OUT.mp4|OUT.gif|FOLDER [--size 1280x720] [--fps 30] [--from 0]\n"
     "                 [--seconds T] [--scale S|auto] [--scene SCENE.json] [--mesh FILE | --capsules]\n"
     "       mm render FILE.bvh --contact-sheet OUT.png [--grid 6x4] [--size 1920x1080] [--from 0]\n"
     "                 [--seconds T] [--scale S|auto] [--scene SCENE.json]\n"
     "A BVH clip drawn without a display (OSMesa), the camera chasing the body from behind and\n"
     "framing it with where it goes next (docs/viewer.md).\n"
     "  FILE.bvh           the clip\n"
     "  -o OUT             an MP4 or GIF (through ffmpeg), or a folder of PNG frames\n"
     "  --contact-sheet P  instead: one PNG of the clip's poses evenly spaced\n"
     "  --grid CxR         the sheet's columns and rows, each 1 to 32 (default 6x4)\n"
     "  --size WxH         pixels (default 1280x720, a sheet 1920x1080)\n"
     "  --fps F            video frames per second, 1 to 240 (default 30)\n"
     "  --from S           start at S seconds (default 0)\n"
     "  --seconds T        draw T seconds (default: to the end)\n"
     "  --scale S|auto     multiply lengths by S to get metres (default auto)\n"
     "  --scene SCENE.json draw a scene's boxes and terrain (default: none)\n"
     "  --mesh FILE        the body: an FBX or glTF mesh skinned to the clip's skeleton (bones named\n"
     "                     as its joints; default: the body mm makes from the skeleton)\n"
     "  --capsules         draw the skeleton as capsules instead of a body\n"},
    {"similarity", "audit how well two clips join: similarity CSV, heat map, poor frames",
     "usage: mm similarity DB.mmdb --from CLIP --to CLIP -o DIR [--window 1] [--measure cos]\n"
     "                     [--channels pos] [--poor S] [--threads 2]\n"
     "Audits how well two clips join (docs/similarity.md): DIR/similarity.csv frame by frame, a\n"
     "heat-map PNG and the poorly matched frames.\n"
     "  DB.mmdb            a database\n"
     "  --from CLIP        the clip left (required)\n"
     "  --to CLIP          the clip joined (required)\n"
     "  -o, --output DIR   the folder written (required)\n"
     "  --window N         frames compared as one, 1 to 256 (default 1)\n"
     "  --measure M        cos or euclid (default cos)\n"
     "  --channels LIST    pos, rot, vel, comma-separated (default pos)\n"
     "  --poor S           the score a poor frame is worse than (default 0.95 for cos, 0.10 euclid)\n"
     "  --threads N        threads, 1 to 64 (default 2)\n"},
    {"similarity build", "the fusion and link tables of one-shot/loop transitions",
     "usage: mm similarity build DB.mmdb [-o TABLES] [--window 1] [--measure cos] [--channels pos]\n"
     "                           [--threads 2]\n"
     "The seed's fusion and link tables for one-shot/loop transitions, saved beside the database\n"
     "(docs/similarity.md).\n"
     "  DB.mmdb            a database\n"
     "  -o, --output FILE  the tables (default: DB.mmdb.sim)\n"
     "  --window N         frames compared as one, 1 to 256 (default 1)\n"
     "  --measure M        cos or euclid (default cos)\n"
     "  --channels LIST    pos, rot, vel, comma-separated (default pos)\n"
     "  --threads N        threads, 1 to 64 (default 2); the tables are the same for any count\n"},
    {"similarity info", "the size of fusion and link tables",
     "usage: mm similarity info TABLES [--db DB.mmdb]\n"
     "The shape and size of fusion and link tables.\n"
     "  TABLES             the tables (.sim)\n"
     "  --db DB.mmdb       check that they belong to this database (default: not checked)\n"},
    {"simulate", "a character on scripted or random input: motion, metrics, video",
     "usage: mm simulate DB.mmdb (--input SCRIPT.json | --random SEED | --path PATH.json) --seconds T\n"
     "                   [--fps 60] -o OUT.bvh\n"
     "                   [--metrics OUT.json] [--scene SCENE.json] [--distance-matching on|off]\n"
     "                   [--warping on|off] [--transition inertialize|crossfade] [--crossfade-time 0.2]\n"
     "                   [--video OUT.mp4|OUT.gif|FOLDER [--size 1280x720] [--video-fps 30] [--mesh FILE]]\n"
     "                   [--skeleton GAME.bvh [--skeleton-map MAP.json]]\n"
     "                   [--trace OUT.jsonl [--trace-ticks] [--trace-k 5]]\n"
     "Runs one character over an input script, random input or a desired path: its motion as BVH,\n"
     "the metrics of docs/metrics.md and a video of it with its debug drawing. With a scene, the moves\n"
     "(jump, vault, climb, drop-down) run around it (docs/moves.md). With a skeleton, the motion is\n"
     "written in the game's joint names and order (docs/embedding.md, \"The game's skeleton\").\n"
     "  DB.mmdb            a database\n"
     "  --input SCRIPT     an input script (scripts/input/); this, --random or --path\n"
     "  --random SEED      seeded random input; this, --input or --path\n"
     "  --path PATH        follow a desired path: {\"points\": [{\"t\": s, \"position\": [x, z],\n"
     "                     \"facing\": [x, z]}, ...]} (metres, seconds, world; linear between points;\n"
     "                     facing optional: along the path); prints the root's distance from it\n"
     "                     (docs/embedding.md, \"Driving a character\"); this, --input or --random\n"
     "  --seconds T        how long, in (0, 36000] (required)\n"
     "  --fps F            ticks per second, 1 to 1000 (default 60)\n"
     "  -o OUT.bvh         the motion (required)\n"
     "  --metrics OUT.json the metrics (default: none)\n"
     "  --scene SCENE.json boxes to move on, terrain to walk on (default: flat ground, no moves)\n"
     "  --distance-matching on|off  (default: the database's settings, else off)\n"
     "  --warping on|off   stride warping (default: the database's settings, else off)\n"
     "  --transition T     inertialize or crossfade (default inertialize)\n"
     "  --crossfade-time S seconds a crossfade takes, 0 to 10 (default 0.2)\n"
     "  --video OUT        an MP4 or GIF (through ffmpeg), or a folder of PNG frames (default: none)\n"
     "  --size WxH         the video's pixels (default 1280x720)\n"
     "  --video-fps F      the video's frames per second, 1 to 240 (default 30)\n"
     "  --mesh FILE        the video's body: an FBX or glTF mesh skinned to the database's skeleton\n"
     "                     (bones named as its joints; default: the body mm makes from the skeleton)\n"
     "  --skeleton GAME    write the motion in this BVH's skeleton: joints matched to the database's\n"
     "                     by name, the others at the game's rest, no simulation root, the game's\n"
     "                     bone lengths (default: the database's skeleton)\n"
     "  --skeleton-map MAP a JSON map for --skeleton: {\"pairs\": {GAME: DATABASE}, \"follow\":\n"
     "                     [{\"joint\", \"follows\", \"weight\", \"twist\"}], \"root\", \"game_lengths\"}\n"
     "  --trace OUT.jsonl  every search as a JSON line: the query, the winner, whether it jumped and\n"
     "                     the best candidates with every cost term, after a header with what a\n"
     "                     replay needs (docs/viewer.md, \"Record, rewind, trace\"; default: none)\n"
     "  --trace-ticks      one more line per tick: clip, frame, root, the feet's contacts and locks\n"
     "  --trace-k N        candidates per search line, 1 to 64 (default 5)\n"},
    {"synth", "write the built-in procedural motion set (BVH files and clips.json)",
     "usage: mm synth OUTDIR [--seed 0] [--fps 60]\n"
     "Writes the built-in procedural motion set: 40 BVH clips and clips.json with their ground truth\n"
     "(docs/synth.md).\n"
     "  OUTDIR             the folder written (made if missing)\n"
     "  --seed N           the random seed, an integer >= 0 (default 0)\n"
     "  --fps F            frames per second, 10 to 240 (default 60)\n"},
    {"view", "the interactive viewer and motion-matching debugger, or a clip's preview and tagging",
     "usage: mm view DB.mmdb [--config CONFIG.json] [--input SCRIPT.json] [--scene SCENE.json]\n"
     "               [--mesh FILE] [--size 1280x720] [--frames N [--screenshot OUT.png]]\n"
     "               [--script KEYS.txt [--screenshot-dir DIR]] [--replay TRACE.jsonl]\n"
     "       mm view --clip FILE.bvh [--config CONFIG.json] [--clip-name NAME] [--scene SCENE.json]\n"
     "               [--size 1280x720] [--frames N [--screenshot OUT.png]]\n"
     "The interactive viewer (docs/viewer.md): drive a character on a database with keyboard or\n"
     "gamepad and debug it in a panel: status and every cost term, the runtime layers as switches,\n"
     "live tuning saved into the config, the search's best candidates as ghosts, and a timeline to\n"
     "pause (space), step (, .), rewind and resume from; or play, scrub and tag a clip.\n"
     "  DB.mmdb            a database to drive a character on\n"
     "  --clip FILE.bvh    instead: preview this clip\n"
     "  --config CONFIG    the config the tuning (or a clip's tags) is saved into (default: none)\n"
     "  --clip-name NAME   the config's clip to edit (default: the clip of the file)\n"
     "  --input SCRIPT     drive by an input script (default: keyboard and gamepad)\n"
     "  --replay TRACE     open a trace that mm simulate wrote on the timeline: its input and\n"
     "                     switches run again, each search set beside the trace's (default: none)\n"
     "  --scene SCENE.json draw a scene's boxes and terrain, and with a database play its moves (J jumps)\n"
     "                     (default: none)\n"
     "  --mesh FILE        the character's body: an FBX or glTF mesh skinned to the database's\n"
     "                     skeleton (bones named as its joints; default: the body mm makes)\n"
     "  --size WxH         the window's pixels (default 1280x720)\n"
     "  --frames N         run N frames and quit (default: until the window closes)\n"
     "  --screenshot PNG   save the last of the N frames\n"
     "  --script KEYS.txt  play a key script, one fixed 1/60 s tick a frame (docs/viewer.md,\n"
     "                     \"Key scripts\"); the run ends at its quit or after its last line\n"
     "  --screenshot-dir DIR  where the script's shots go: NAME.png and NAME.json\n"
     "                     (default: the shots are not saved)\n"},
    {"version", "print the version",
     "usage: mm version   (or mm --version)\n"
     "Prints the program's version, the version of the mm library it runs with (mm_version(),\n"
     "mm/version.h) and the .mmdb format version it reads (docs/embedding.md, \"Versions\").\n"},
    {"help", "this list, or a command's usage and options",
     "usage: mm help [COMMAND [SUBCOMMAND]]\n"
     "       mm COMMAND [SUBCOMMAND] --help   (or -h)\n"
     "The list of commands, or one command's usage with every option and its default.\n"},
};

enum { ENTRY_COUNT = (int)(sizeof entries / sizeof entries[0]) };

/* The length of an entry's first word (its command). */
static size_t first_word(const char *s)
{
    const char *space = strchr(s, ' ');
    return space ? (size_t)(space - s) : strlen(s);
}

/* Entry e is command, or command sub when sub is given. */
static int matches(const help_entry *e, const char *command, const char *sub)
{
    size_t n = first_word(e->command);
    if (strlen(command) != n || strncmp(e->command, command, n) != 0) return 0;
    if (!sub) return e->command[n] == '\0';
    return e->command[n] == ' ' && strcmp(e->command + n + 1, sub) == 0;
}

void cli_help_list(FILE *f)
{
    fputs("usage: mm COMMAND [SUBCOMMAND] [ARGUMENTS]\n"
          "       mm COMMAND [SUBCOMMAND] --help    a command's usage, every option and its default\n"
          "\n"
          "commands:\n",
          f);
    for (int i = 0; i < ENTRY_COUNT; ++i) fprintf(f, "  %-18s %s\n", entries[i].command, entries[i].summary);
}

int cli_help_known(const char *command)
{
    for (int i = 0; i < ENTRY_COUNT; ++i)
        if (strlen(command) == first_word(entries[i].command) &&
            strncmp(entries[i].command, command, strlen(command)) == 0)
            return 1;
    return 0;
}

int cli_help(FILE *f, const char *command, const char *sub)
{
    /* the subcommand's entry; else the command's own (its others named after it); else all of it */
    int shown = 0;
    for (int i = 0; sub && i < ENTRY_COUNT; ++i)
        if (matches(&entries[i], command, sub)) fputs(entries[i].usage, f), ++shown;
    if (shown) return 0;
    for (int i = 0; i < ENTRY_COUNT; ++i)
        if (matches(&entries[i], command, NULL)) fputs(entries[i].usage, f), ++shown;
    int others = 0;
    for (int i = 0; i < ENTRY_COUNT; ++i) {
        size_t n = first_word(entries[i].command);
        if (entries[i].command[n] != ' ' || !matches(&entries[i], command, entries[i].command + n + 1))
            continue;
        if (!shown) {
            fprintf(f, "%s", others ? "\n" : "");
            fputs(entries[i].usage, f);
        } else {
            fprintf(f, "%s mm %s",
                    others ? "," : "\nsubcommands (mm COMMAND SUBCOMMAND --help):", entries[i].command);
        }
        ++others;
    }
    if (shown && others) fputc('\n', f);
    return shown || others ? 0 : 1;
}

int cli_wants_help(int argc, char **argv)
{
    for (int i = 1; i < argc; ++i)
        if (strcmp(argv[i], "--help") == 0 || strcmp(argv[i], "-h") == 0) return 1;
    return 0;
}
