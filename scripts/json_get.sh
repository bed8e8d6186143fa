# json_get.sh - sourced by the table scripts (scripts/metrics_table.sh, compare_controllers.sh).
# get KEY FILE: the number (or null) after "KEY": in a metrics JSON written by mm; the files are
# flat and one key a line, so sed is enough.
get() { sed -n "s/.*\"$1\": \(null\|[-0-9.e+][-0-9.e+]*\).*/\1/p" "$2"; }
# fmt VALUE [DECIMALS (default 1)]: the number rounded for a table, "-" for null.
fmt() { [ "$1" = null ] && echo "-" || printf "%.${2:-1}f" "$1"; }
