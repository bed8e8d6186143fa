#!/bin/sh
# The help of the mm program: every command that `mm --help` lists prints its usage on
# `mm COMMAND --help`, `-h` and `mm help COMMAND` and exits 0; the usage names every option the
# command's parser accepts (the option strings in its source) and no option it does not.
# A command's parser: tools/cmd_WORD.c's mm_cmd_WORD, or cmd_SUB for `mm WORD SUB` (mm_cmd_WORD_SUB
# when tools/cmd_WORD_SUB.c exists); the exceptions are listed in parsers() below.
# usage: test_help.sh MM_BINARY SOURCE_DIR
set -u
mm=$1
src=$2
. "$(dirname "$0")/cli_checks.sh"

# the functions that parse COMMAND's arguments, and the file they are in (FILE FUNCTION...)
parsers() {
    word=${1%% *}
    sub=
    [ "$word" = "$1" ] || sub=${1#* }
    case $1 in
    similarity) echo "$src/tools/cmd_similarity.c cmd_audit shared_option" ;;
    "similarity build") echo "$src/tools/cmd_similarity.c cmd_build shared_option" ;;
    *)
        if [ -z "$sub" ]; then
            echo "$src/tools/cmd_$word.c mm_cmd_$word"
        elif [ -f "$src/tools/cmd_${word}_$sub.c" ]; then
            echo "$src/tools/cmd_${word}_$sub.c mm_cmd_${word}_$sub"
        else
            echo "$src/tools/cmd_$word.c cmd_$sub"
        fi
        ;;
    esac
}

# the option strings ("-x", "--name") in the body of FUNCTION of FILE, one a line; nothing (and
# exit 1) when FILE has no such function
options_of() {
    awk -v f="$2" '
        !inside && $0 ~ "^[a-z].*[ *]" f "\\(" && $0 !~ /;[ \t]*$/ { inside = 1; found = 1 }
        inside { print }
        inside && /^}/ { inside = 0 }
        END { exit found ? 0 : 1 }' "$1" >"$tmp/body" || return 1
    grep -o '"--*[a-z][-a-z]*"' "$tmp/body" | tr -d '"' | grep -v -x -e --help -e -h
    return 0
}

# has OPTION FILE: FILE names OPTION as a word of its own
has() { grep -q -E -- "(^|[^-a-zA-Z0-9])$1([^-a-zA-Z0-9]|\$)" "$2"; }

expect_exit 0 "$mm" --help
cp "$tmp/out" "$tmp/list"
expect_exit 0 "$mm" help
if cmp -s "$tmp/out" "$tmp/list"; then ok; else bad "mm help and mm --help differ"; fi
expect_exit 0 "$mm" -h
if cmp -s "$tmp/out" "$tmp/list"; then ok; else bad "mm -h and mm --help differ"; fi
expect_exit 2 "$mm"
if cmp -s "$tmp/err" "$tmp/list"; then ok; else bad "mm alone does not list the commands"; fi
expect_exit 2 "$mm" help no-such-command

sed -n 's/^  \([a-z][a-z]*\( [a-z][a-z]*\)\{0,1\}\)  .*/\1/p' "$tmp/list" >"$tmp/commands"
# every command of the program is listed (the dispatch table of tools/mm.c, each subcommand
# compared for in its file)
for word in $(grep -o '{"[a-z]*", mm_cmd_' "$src/tools/mm.c" | sed 's/{"\([a-z]*\)".*/\1/'); do
    if grep -q -e "^$word\$" -e "^$word " "$tmp/commands"; then ok; else bad "mm --help does not list $word"; fi
done
for sub in $(grep -h -o -E 'strcmp\((argv\[1\]|sub), "[a-z]+"\) == 0' "$src/tools/cmd_"*.c | sed 's/.*"\([a-z]*\)".*/\1/' | sort -u); do
    if grep -q -e " $sub\$" "$tmp/commands"; then ok; else bad "mm --help does not list a subcommand $sub"; fi
done
if [ "$(wc -l <"$tmp/commands")" -ge 20 ]; then ok; else bad "mm --help lists $(wc -l <"$tmp/commands") commands"; fi

while read -r cmd <&3; do
    # shellcheck disable=SC2086 # the command's words
    expect_exit 0 "$mm" $cmd --help
    cp "$tmp/out" "$tmp/usage"
    expect_grep "^usage: mm $cmd" "$tmp/usage"
    # shellcheck disable=SC2086
    expect_exit 0 "$mm" $cmd -h
    if cmp -s "$tmp/out" "$tmp/usage"; then ok; else bad "mm $cmd -h differs from --help"; fi
    # shellcheck disable=SC2086
    expect_exit 0 "$mm" help $cmd
    if cmp -s "$tmp/out" "$tmp/usage"; then ok; else bad "mm help $cmd differs from mm $cmd --help"; fi
    case $cmd in version | help) continue ;; esac
    set -- $(parsers "$cmd")
    file=$1
    shift
    : >"$tmp/accepted"
    for f in "$@"; do
        if options_of "$file" "$f" >>"$tmp/accepted"; then ok; else bad "$cmd: no function $f in $file (tests/test_help.sh: parsers)"; fi
    done
    for opt in $(sort -u "$tmp/accepted"); do
        if has "$opt" "$tmp/usage"; then ok; else bad "mm $cmd --help does not name $opt, which $file accepts"; fi
    done
    # and names no option the parser does not take
    for opt in $(grep -o -E -- '(^|[ [(|,])--?[a-z][-a-z]*' "$tmp/usage" | sed 's/^[^-]*//' | sort -u); do
        case $opt in --help | -h) continue ;; esac
        if grep -q -x -- "$opt" "$tmp/accepted"; then ok; else bad "mm $cmd --help names $opt, which $file does not take"; fi
    done
done 3<"$tmp/commands"

# --help anywhere after the command, even after other arguments or a bad option
expect_exit 0 "$mm" db build no-such-config.json --help
expect_grep "^usage: mm db build" "$tmp/out"
expect_exit 0 "$mm" simulate --bogus --help
expect_grep "^usage: mm simulate" "$tmp/out"
# a command of subcommands: all of them
expect_exit 0 "$mm" db --help
for sub in build info dump search; do expect_grep "^usage: mm db $sub" "$tmp/out"; done

finish test_help
