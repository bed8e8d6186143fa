# Shared by the end-to-end CLI tests (sourced, not run): a temporary folder removed on exit,
# pass/fail counters and the checks they all use.
#   expect_exit CODE CMD...  runs CMD (stdout to $tmp/out, stderr to $tmp/err), wants exit CODE
#   expect_grep PATTERN FILE FILE contains PATTERN
#   finish NAME              prints the counts; the script's exit status says whether all passed
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
passed=0
failed=0

ok() { passed=$((passed + 1)); }
bad() { failed=$((failed + 1)); echo "FAIL: $*"; }
expect_exit() {
    want=$1; shift
    "$@" >"$tmp/out" 2>"$tmp/err"; got=$?
    if [ "$got" -eq "$want" ]; then ok; else bad "exit $got (wanted $want): $*"; cat "$tmp/err"; fi
}
expect_grep() {
    if grep -q -- "$1" "$2"; then ok; else bad "'$1' not in $2:"; cat "$2"; fi
}
finish() {
    echo "$1: $passed passed, $failed failed"
    [ "$failed" -eq 0 ]
}
