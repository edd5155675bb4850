#!/bin/sh
# bench_plot.sh — vsv-plot's plots on the real MM5 run (issue 35, item 6): a
# cross-section across the domain, a time series and a profile, each read
# from the .vsv and drawn as SVG, PNG and PDF (bench_plot.c: the library's
# two calls timed apart), then each whole vsv-plot command as a user runs it
# (starting the program, opening the file, reading, drawing, writing).
set -eu
B=${B:-build}
SHARED=${SHARED:-../shared}
MM5="$SHARED/data/mm5/run1/MMOUT_DOMAIN1"
if [ ! -f "$MM5" ]; then
    echo "(plot benchmark skipped: $MM5 absent)"
    exit 0
fi
W=$(mktemp -d "${TMPDIR:-/tmp}/vsv-bench-plot.XXXXXX")
trap 'rm -rf "$W"' EXIT
R=${ROUNDS:-5}
"$B/vsv-convert" -q "$MM5" --vars Q,CLW,RNW,ICE,SNOW -o "$W/run.vsv"
"$B/vsv-convert" -q --time-res 5m "$MM5" --vars CLW,SNOW -o "$W/run5m.vsv"
printf 'data: MMOUT_DOMAIN1 (207x142x15, native levels), 4 hourly steps; the series on 5-minute steps (37)\n'
printf '%s cores, load %s; %s; cairo %s\n' "$(nproc)" "$(cut -d' ' -f1-3 /proc/loadavg)" "$(date -u '+%Y-%m-%d %H:%M UTC')" \
    "$(pkg-config --modversion cairo 2> /dev/null || echo '?')"
"$B/bench/bench_plot" "$W/run.vsv" "$W/run5m.vsv" "$W" "$R"
# whole commands: the median wall time of R runs each
whole() { # NAME CMD...: prints NAME and the median ms
    name=$1
    shift
    for i in $(seq "$R"); do
        t0=$(date +%s%N)
        "$@" > /dev/null
        t1=$(date +%s%N)
        echo $(((t1 - t0) / 1000))
    done | sort -n | awk -v n="$name" '{ a[NR] = $1 } END { printf "  %-44s %7.1f ms\n", n, a[int((NR + 1) / 2)] / 1000 }'
}
echo "whole commands (vsv-plot ... -o OUT), median of $R, wall:"
whole "--section (SNOW, last step, --top 10000) svg" "$B/vsv-plot" "$W/run.vsv" --section 45.2,-123.4:41.5,-58 \
    --species SNOW --top 10000 -o "$W/s.svg"
whole "--section ... png" "$B/vsv-plot" "$W/run.vsv" --section 45.2,-123.4:41.5,-58 --species SNOW --top 10000 -o "$W/s.png"
whole "--series (CLW,SNOW, 37 steps) svg" "$B/vsv-plot" "$W/run5m.vsv" --series 48.54,-87.38,3800 --species CLW,SNOW \
    -o "$W/t.svg"
whole "--profile (Q,CLW,SNOW, last step) svg" "$B/vsv-plot" "$W/run.vsv" --profile 48.54,-87.38 --species Q,CLW,SNOW \
    -o "$W/p.svg"
whole "vsv-query --profile (the same numbers, CSV)" "$B/vsv-query" "$W/run.vsv" --profile 48.54,-87.38 \
    --species Q,CLW,SNOW --time 3 --csv
