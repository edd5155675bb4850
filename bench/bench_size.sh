#!/bin/sh
# bench_size.sh — the .vsv's size against CF int16-packed netCDF-4, float32
# netCDF-4 rounded to the bound, and ZFP at and calibrated to the bound
# (libzfp-dev), per species and in total: the real MM5 run, the WRF files,
# gen-plume's plume and haze.
set -eu
B=${B:-build}
SHARED=${SHARED:-../shared}
W=$(mktemp -d "${TMPDIR:-/tmp}/vsv-bench-size.XXXXXX")
trap 'rm -rf "$W"' EXIT
${CC:-cc} -O2 -o "$W/gen_volume" "$SHARED/tools/gen-plume/gen_volume.c" -lm
"$W/gen_volume" "$W" >/dev/null
printf '%s cores; %s; load %s\n\n' "$(nproc)" "$(date -u +%Y-%m-%d)" "$(cut -d' ' -f1-3 /proc/loadavg)"
"$B/bench/bench_size" "$SHARED" "$W" "$W"
