# json_get.sh - sourced by the table scripts (scripts/metrics_table.sh, compare_controllers.sh,
# quality_report.sh).
# get KEY FILE: the number (or null) after "KEY": in a metrics JSON written by mm; the files are
# flat and one key a line, so sed is enough.
get() { sed -n "s/.*\"$1\": \(null\|[-0-9.e+][-0-9.e+]*\).*/\1/p" "$2"; }
# pairs FILE: every top-level key of a metrics JSON whose value is a number or null, one
# "KEY VALUE" a line, in the file's order (what any version of mm simulate --metrics writes).
pairs() { sed -n 's/^  "\([A-Za-z0-9_]*\)": \(null\|[-0-9.e+][-0-9.e+]*\),\{0,1\}$/\1 \2/p' "$1"; }
# fmt VALUE [DECIMALS (default 1)]: the number rounded for a table, "-" for null.
fmt() { [ "$1" = null ] && echo "-" || printf "%.${2:-1}f" "$1"; }
