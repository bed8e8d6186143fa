#!/bin/sh
# No joint name is written as a string literal in src/ or tools/ outside the defaults: the runtime,
# the build, the renderer and the tools take their joints from the config's bone roles (docs/runtime.md, "Bone
# roles"). A literal is a joint name when a word of it (letters and digits) is one of the common
# names: Hips, Hip, Pelvis, Spine, Spine1.., Chest, Neck, Head, Foot, Toe, ToeBase, Hand, Ankle,
# Wrist, HEAD, HIPS; Left* / Right* followed by a capital (LeftFoot, RightUpLeg); or LeftFoot,
# RightHand ... in any case. Comments are left out. The files allowed to hold them:
#   src/db/roles.c            mm_role_default_name: the roles' default joint names, the one table
#   src/config.c              mm_config_defaults: the root bone's default (no role of the runtime's)
#   src/io/config_json.c      the documented defaults of the config's fields (docs/config.md)
#   src/synth/synth_skeleton.c the built-in skeleton: its joints' own names, not a lookup
#   tools/help.c              the commands' help text, which documents defaults
#   tools/cmd_bvh_spans.c     mm bvh spans's own name search for a take without a config
#                             (its --config roles come first)
# usage: test_no_joint_names.sh SOURCE_DIR
cd "$1" || exit 1
allowed="src/db/roles.c src/config.c src/io/config_json.c src/synth/synth_skeleton.c tools/help.c tools/cmd_bvh_spans.c"

# literals FILE...: "file:line: literal" for every string literal outside comments
literals() {
    awk '
    FNR == 1 { state = "code" }
    {
        line = $0; n = length(line); i = 1
        if (state == "line") state = "code"
        while (i <= n) {
            c = substr(line, i, 1); two = substr(line, i, 2)
            if (state == "block") {
                if (two == "*/") { state = "code"; i += 2 } else i++
                continue
            }
            if (state == "string") {
                if (c == "\\") { lit = lit two; i += 2; continue }
                if (c == "\"") { print FILENAME ":" FNR ": " lit; state = "code"; i++; continue }
                lit = lit c; i++; continue
            }
            if (state == "char") {
                if (c == "\\") { i += 2; continue }
                if (c == "\047") state = "code"
                i++; continue
            }
            if (two == "/*") { state = "block"; i += 2; continue }
            if (two == "//") { state = "line"; break }
            if (c == "\"") { state = "string"; lit = ""; i++; continue }
            if (c == "\047") { state = "char"; i++; continue }
            i++
        }
        if (state == "string") state = "code" # an unterminated literal ends with its line
    }' "$@"
}

# names: the lines of literals (on stdin) that hold a joint name
names() {
    awk '{
        text = $0; sub(/^[^:]*:[0-9]*: /, "", text)
        count = split(text, words, /[^A-Za-z0-9]+/)
        for (k = 1; k <= count; ++k) {
            w = words[k]; lw = tolower(w)
            if (w ~ /^(Hips?|Pelvis|Spine[0-9]*|Chest|Neck|Head|Foot|Toe|ToeBase|Hand|Ankle|Wrist|HEAD|HIPS)$/ ||
                w ~ /^(Left|Right)[A-Z][A-Za-z0-9]*$/ ||
                lw ~ /^(left|right)(foot|toe|toebase|hand|upleg|leg|arm|forearm|shoulder|ankle|wrist)$/) {
                print; next
            }
        }
    }'
}

# the check itself must see a name in a literal, and none in a comment or a character constant
probe=$(mktemp "${TMPDIR:-/tmp}/mm_names.XXXXXX") || exit 1
trap 'rm -f "$probe"' EXIT
cat >"$probe" <<'EOF'
/* "LeftFoot" in a comment */ const char *a = "a \" quote", *b = "Spine2"; // "Head"
char c = '"'; const char *d = "lefthand"; const char *e = "HandPlant"; /* "Hips"
   "Neck" */ const char *f = "roles.head";
EOF
got=$(literals "$probe" | names | sed 's/^[^:]*:/L/')
want='L1: Spine2
L2: lefthand'
if [ "$got" != "$want" ]; then
    echo "test_no_joint_names: the check itself is wrong; on its probe it found:"
    echo "$got"
    exit 1
fi

files=$(find src tools -name '*.[ch]' | sort)
found=$(for f in $files; do
    case " $allowed " in *" $f "*) continue ;; esac
    literals "$f"
done | names)
if [ -n "$found" ]; then
    echo "test_no_joint_names: joint names written as literals (take the joint from its role:"
    echo "mm_database_role_joint, the config's roles; a default name: mm_role_default_name):"
    echo "$found"
    exit 1
fi
for f in $allowed; do [ -f "$f" ] || { echo "test_no_joint_names: $f is gone: update the allowed list"; exit 1; }; done
echo "test_no_joint_names: $(echo "$files" | wc -l) files of src/ and tools/ hold no joint name outside the defaults"
