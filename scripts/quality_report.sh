#!/bin/sh
# A quality report of one database over many inputs: mm simulate on every shipped input script
# (scripts/input/*.json; a script named for a scene, like stairs_up_down_walk, in that scene; the
# moves_* scripts without their scenes, as scripts/metrics_table.sh runs them) and on random input (--random SEED, seeds 1 to 20), SECONDS each, then a contact
# sheet of each run (mm render --contact-sheet). Writes to OUTDIR:
#   report.md    a table of the main metrics per run, then each metric's mean and worst over the
#                seeds and over the scripts, and the wall-clock timings in a table of their own
#   report.json  every metric of every run, and each metric's mean and worst over the seeds and
#                over the scripts
#   sheets/NAME.png  the contact sheet of each run;  runs/NAME.bvh, .json, .log  what mm wrote
#   sheets/NAME_slide.png  the contact sheet of the second of each run whose labelled foot slide adds
#                the most to foot_slide_cm_s (the metrics' "where"), when it slid at all
# Any numeric key of the metrics JSON is taken (docs/metrics.md); nulls are left out of means.
# Worst is the largest value, or the smallest for the keys in larger_is_better below. Keys ending
# in _us are wall-clock time, the only values that differ between two reports of the same runs.
# Runs go in parallel (--jobs, default the number of cores); the output does not depend on it.
# Exits 1 if a run fails, 3 (after writing the report) if a run has frames with a NaN.
# usage: scripts/quality_report.sh DB.mmdb [SECONDS (default 60)] [OUTDIR (default report)]
#            [--scripts all|none|NAME,NAME...] [--seeds N|SEED,SEED...] [--jobs N]
#   --seeds N: seeds 1 to N (default 20; 0: none).  MM: the mm program (default build/mm).
set -eu
root=$(cd "$(dirname "$0")/.." && pwd)
. "$root/scripts/json_get.sh" # pairs FILE
usage="usage: scripts/quality_report.sh DB.mmdb [SECONDS] [OUTDIR] [--scripts all|none|NAME,...] [--seeds N|SEED,...] [--jobs N]"
larger_is_better="head_p2_cm head_p5_cm head_p50_cm contact_share"
# the columns of the per-run table, those that some run has, in this order
main_keys="foot_slide_cm_s traj_err_cm response_s max_pop_cm pop_p99_cm below_ground_cm contact_height_err_cm \
head_p5_cm head_p50_cm crouched_s bent_s lying_s calibration_s arms_out_s hand_raised_s knee_raised_s contact_share transitions_per_s \
nan_frames"

scripts=all
seeds=20
jobs=$(nproc 2>/dev/null || getconf _NPROCESSORS_ONLN 2>/dev/null || echo 1)
db=
seconds=
out=
while [ $# -gt 0 ]; do
    case $1 in
    --scripts | --seeds | --jobs)
        [ $# -ge 2 ] || { echo "$usage" >&2; exit 2; }
        case $1 in --scripts) scripts=$2 ;; --seeds) seeds=$2 ;; --jobs) jobs=$2 ;; esac
        shift 2 ;;
    -*) echo "$usage" >&2; exit 2 ;;
    *)
        if [ -z "$db" ]; then db=$1; elif [ -z "$seconds" ]; then seconds=$1; elif [ -z "$out" ]; then out=$1
        else echo "$usage" >&2; exit 2; fi
        shift ;;
    esac
done
[ -n "$db" ] || { echo "$usage" >&2; exit 2; }
seconds=${seconds:-60}
out=${out:-report}
mm=${MM:-$root/build/mm}
case $jobs in '' | *[!0-9]* | 0) echo "quality_report: --jobs needs a number >= 1" >&2; exit 2 ;; esac
[ -f "$db" ] || { echo "quality_report: $db: no such database" >&2; exit 1; }
export LC_ALL=C # sorting, and numbers printed with a decimal point

# the runs: NAME KIND ARGUMENT, the scripts by name, then random_NN
mkdir -p "$out/runs" "$out/sheets"
list=$out/runs/list
: >"$list"
if [ "$scripts" = all ]; then
    for s in "$root"/scripts/input/*.json; do echo "$(basename "$s" .json) script $s" >>"$list"; done
elif [ "$scripts" != none ]; then
    for name in $(echo "$scripts" | tr ',' ' '); do
        s=$root/scripts/input/$name.json
        [ -f "$s" ] || { echo "quality_report: no input script $s" >&2; exit 2; }
        echo "$name script $s" >>"$list"
    done
fi
case $seeds in
*,*) seed_list=$(echo "$seeds" | tr ',' ' ') ;;
*[!0-9]* | '') echo "quality_report: --seeds needs a count or a list of seeds" >&2; exit 2 ;;
*) seed_list=$(i=1; while [ "$i" -le "$seeds" ]; do echo "$i"; i=$((i + 1)); done) ;;
esac
for seed in $seed_list; do
    case $seed in '' | *[!0-9]*) echo "quality_report: seed '$seed' is not a number" >&2; exit 2 ;; esac
    printf 'random_%02d random %s\n' "$seed" "$seed" >>"$list"
done
sort -u -k2,2r -k1,1 -o "$list" "$list" # the scripts first
runs=$(wc -l <"$list")
[ "$runs" -gt 0 ] || { echo "quality_report: nothing to run" >&2; exit 2; }
[ "$jobs" -le "$runs" ] || jobs=$runs

# the scene a script crosses: scenes/S.json for the longest S that the script's name starts with
# followed by "_" (stairs_up_down_walk: stairs_up_down); none for the moves_* scripts (above)
scene_of() { # NAME
    best=
    case $1 in moves_*) return 0 ;; esac
    for f in "$root"/scenes/*.json; do
        s=$(basename "$f" .json)
        case $1 in "$s"_*) [ ${#s} -gt ${#best} ] && best=$s ;; esac
    done
    [ -z "$best" ] || echo "$root/scenes/$best.json"
}

# one run: the simulation, its metrics and its contact sheet; a failure leaves NAME.failed
run_one() { # NAME KIND ARGUMENT
    base=$out/runs/$1
    rm -f "$base.failed"
    scene=
    [ "$2" = script ] && scene=$(scene_of "$1")
    if [ "$2" = script ]; then set -- "$1" --input "$3"; else set -- "$1" --random "$3"; fi
    if [ -n "$scene" ]; then set -- "$@" --scene "$scene"; fi
    if ! "$mm" simulate "$db" "$2" "$3" ${scene:+"$4"} ${scene:+"$5"} --seconds "$seconds" -o "$base.bvh" \
        --metrics "$base.json" </dev/null >/dev/null 2>"$base.log"; then
        echo "mm simulate failed" >"$base.failed"
    elif ! "$mm" render "$base.bvh" ${scene:+--scene} ${scene:+"$scene"} --contact-sheet "$out/sheets/$1.png" \
        </dev/null >/dev/null 2>>"$base.log"; then
        echo "mm render --contact-sheet failed" >"$base.failed"
    else
        worst=$(worst_slide "$base.json")
        rm -f "$out/sheets/$1_slide.png"
        if [ -n "$worst" ] && ! "$mm" render "$base.bvh" ${scene:+--scene} ${scene:+"$scene"} \
            --contact-sheet "$out/sheets/$1_slide.png" --from "$(echo "$worst" | cut -d' ' -f1)" \
            --seconds "$(echo "$worst" | cut -d' ' -f2)" </dev/null >/dev/null 2>>"$base.log"; then
            echo "mm render --contact-sheet of the worst second failed" >"$base.failed"
        fi
    fi
}

# the worst second of foot slide in a metrics JSON ("where"): "START SECONDS CM_S", or nothing
worst_slide() { # FILE
    sed -n 's/^    "foot_slide": {"t_s": \([-0-9.e+]*\), "frame": [0-9]*, "seconds": \([-0-9.e+]*\), "cm_s": \([-0-9.e+]*\).*/\1 \2 \3/p' "$1"
}

# lanes: run k goes to lane k mod jobs; each lane runs its share in order
lane=0
pids=
while [ "$lane" -lt "$jobs" ]; do
    (
        k=0
        while read -r name kind arg; do
            [ $((k % jobs)) -eq "$lane" ] && run_one "$name" "$kind" "$arg"
            k=$((k + 1))
        done <"$list"
    ) &
    pids="$pids $!"
    lane=$((lane + 1))
done
for pid in $pids; do wait "$pid"; done
failed=0
while read -r name kind arg; do
    if [ -f "$out/runs/$name.failed" ]; then
        echo "quality_report: $name: $(cat "$out/runs/$name.failed"):" >&2
        cat "$out/runs/$name.log" >&2
        failed=1
    fi
done <"$list"
[ "$failed" -eq 0 ] || exit 1

# every metric of every run: NAME KEY VALUE, in run order and each file's key order; and the worst
# second of slide of each run that slid: NAME START SECONDS CM_S
table=$out/runs/metrics.txt
where=$out/runs/where.txt
: >"$table"
: >"$where"
while read -r name kind arg; do
    pairs "$out/runs/$name.json" | sed "s/^/$name /" >>"$table"
    worst=$(worst_slide "$out/runs/$name.json")
    [ -z "$worst" ] || echo "$name $worst" >>"$where"
done <"$list"

awk -v db="$db" -v seconds="$seconds" -v better="$larger_is_better" -v main="$main_keys" \
    -v md="$out/report.md" -v json="$out/report.json" -v root="$root/" '
function jstr(s) { gsub(/\\/, "\\\\", s); gsub(/"/, "\\\"", s); return "\"" s "\"" }
# a value of key k for a table: whole numbers for the keys whose values all are, else 2 decimals
function cell(k, v) {
    if (v == "" || v == "null") return "-"
    if (!(k in fractional) && v == int(v)) return sprintf("%d", v)
    return sprintf("%.2f", v)
}
function timing(k) { return k ~ /_us$/ }
# the mean and worst of key k over the runs of kind g: sets n, mean, worst, worst_run
function stats(g, k,    i, r, v) {
    n = 0; sum = 0; worst = ""; worst_run = ""
    for (i = 1; i <= nruns; ++i) {
        r = run[i]
        if (kind[r] != g || !((r, k) in value) || value[r, k] == "null") continue
        v = value[r, k] + 0
        ++n; sum += v
        if (worst_run == "" || ((k in is_better) ? (v < worst) : (v > worst))) { worst = v; worst_run = r }
    }
    mean = n ? sum / n : ""
}
BEGIN { split(better, b, " "); for (i in b) is_better[b[i]] = 1 }
# the list of runs (NAME KIND ARGUMENT), then the metrics (NAME KEY VALUE)
FILENAME == ARGV[1] { run[++nruns] = $1; kind[$1] = $2; arg[$1] = substr($0, length($1) + length($2) + 3); next }
FILENAME == ARGV[2] { slide_from[$1] = $2; slide_seconds[$1] = $3; slide_cm_s[$1] = $4; next }
{
    if (!($2 in known)) { known[$2] = 1; key[++nkeys] = $2 }
    value[$1, $2] = $3
    if ($3 != "null" && $3 != int($3)) fractional[$2] = 1
}
END {
    for (g = 1; g <= 2; ++g) { grp = g == 1 ? "random" : "script"; count[grp] = 0 }
    for (i = 1; i <= nruns; ++i) count[kind[run[i]]]++
    # report.json
    print "{" > json
    print "  \"database\": " jstr(db) "," > json
    print "  \"seconds\": " seconds "," > json
    nb = split(better, bl, " "); s = ""
    for (i = 1; i <= nb; ++i) s = s (i > 1 ? ", " : "") jstr(bl[i])
    print "  \"larger_is_better\": [" s "]," > json
    print "  \"runs\": {" > json
    for (i = 1; i <= nruns; ++i) {
        r = run[i]
        print "    " jstr(r) ": {" > json
        print "      \"kind\": " jstr(kind[r]) "," > json
        if (kind[r] == "script") {
            a = arg[r]; if (index(a, root) == 1) a = substr(a, length(root) + 1)
            print "      \"input\": " jstr(a) "," > json
        } else {
            print "      \"seed\": " arg[r] "," > json
        }
        print "      \"sheet\": " jstr("sheets/" r ".png") "," > json
        if (r in slide_from)
            print "      \"worst_slide\": {\"t_s\": " slide_from[r] ", \"seconds\": " slide_seconds[r] \
                ", \"cm_s\": " slide_cm_s[r] ", \"sheet\": " jstr("sheets/" r "_slide.png") "}," > json
        print "      \"metrics\": {" > json
        for (j = 1; j <= nkeys; ++j) if ((r, key[j]) in value) last[r] = key[j]
        for (j = 1; j <= nkeys; ++j)
            if ((r, key[j]) in value)
                print "        " jstr(key[j]) ": " value[r, key[j]] (key[j] == last[r] ? "" : ",") > json
        print "      }" > json
        print "    }" (i < nruns ? "," : "") > json
    }
    print "  }," > json
    print "  \"summary\": {" > json
    for (g = 1; g <= 2; ++g) {
        grp = g == 1 ? "random" : "script"
        print "    " jstr(g == 1 ? "seeds" : "scripts") ": {" > json
        print "      \"runs\": " count[grp] (nkeys ? "," : "") > json
        for (j = 1; j <= nkeys; ++j) {
            stats(grp, key[j])
            line = "      " jstr(key[j]) ": {\"count\": " n ", \"mean\": " (n ? sprintf("%.6g", mean) : "null")
            line = line ", \"worst\": " (n ? sprintf("%.6g", worst) : "null") ", \"worst_run\": "
            line = line (n ? jstr(worst_run) : "null") "}" (j < nkeys ? "," : "")
            print line > json
        }
        print "    }" (g == 1 ? "," : "") > json
    }
    print "  }" > json
    print "}" > json

    # report.md
    print "# Quality report" > md
    print "" > md
    printf "`%s`, %s s per run: %d input scripts from scripts/input/ and %d random-input seeds " \
        "(`mm simulate --random SEED`). The metrics are those of docs/metrics.md; `-` is null. Each run has " \
        "a contact sheet in sheets/, and one of its worst second of foot slide (the mean ground speed of the labelled feet " \
        "over that second: the `where` of the metrics).\n", db, seconds, count["script"], count["random"] > md
    print "" > md
    print "## Runs" > md
    print "" > md
    nm = split(main, mk, " "); cols = 0
    for (j = 1; j <= nm; ++j) if (mk[j] in known) col[++cols] = mk[j]
    s = "| run |"; t = "|---|"
    for (j = 1; j <= cols; ++j) { s = s " " col[j] " |"; t = t "---|" }
    print s " worst second of slide | sheet |" > md
    print t "---|---|" > md
    for (i = 1; i <= nruns; ++i) {
        r = run[i]; s = "| " r " |"
        for (j = 1; j <= cols; ++j) s = s " " cell(col[j], (r, col[j]) in value ? value[r, col[j]] : "") " |"
        w = r in slide_from ? sprintf("[%.2f s: %.1f cm/s](sheets/%s_slide.png)", slide_from[r], slide_cm_s[r], r) : "-"
        print s " " w " | [sheet](sheets/" r ".png) |" > md
    }
    for (g = 1; g <= 2; ++g) {
        grp = g == 1 ? "random" : "script"
        if (!count[grp]) continue
        print "" > md
        if (g == 1) print "## Over the " count[grp] " random seeds" > md
        else print "## Over the " count[grp] " scripts" > md
        print "" > md
        print "Worst: the largest value, the smallest for " better "." > md
        print "" > md
        print "| metric | runs | mean | worst | worst run |" > md
        print "|---|---|---|---|---|" > md
        for (j = 1; j <= nkeys; ++j) {
            if (timing(key[j])) continue
            stats(grp, key[j])
            print "| " key[j] " | " n " | " cell(key[j], mean) " | " cell(key[j], worst) " | " (n ? worst_run : "-") " |" > md
        }
    }
    print "" > md
    print "## Wall-clock timing (differs between runs)" > md
    print "" > md
    print "| metric | mean (seeds) | worst (seeds) | mean (scripts) | worst (scripts) |" > md
    print "|---|---|---|---|---|" > md
    for (j = 1; j <= nkeys; ++j) {
        if (!timing(key[j])) continue
        stats("random", key[j]); s = "| " key[j] " | " cell(key[j], mean) " | " cell(key[j], worst)
        stats("script", key[j]); print s " | " cell(key[j], mean) " | " cell(key[j], worst) " |" > md
    }
}' "$list" "$where" "$table"

nan=$(awk '$2 == "nan_frames" && $3 != "null" && $3 > 0 { printf " %s (%s)", $1, $3 }' "$table")
echo "quality_report: $runs runs, $out/report.md, $out/report.json, $out/sheets/"
if [ -n "$nan" ]; then
    echo "quality_report: frames with a NaN:$nan" >&2
    exit 3
fi
