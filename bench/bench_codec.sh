#!/bin/sh
# bench_codec.sh — the brick coding's size beside netCDF-4 deflate and ZFP
# (libzfp-dev) at the same error bound, with its decode speed, one run: the
# real MM5 run (Q, CLW, SNOW), a real WRF file and gen-plume's plume.
set -eu
B=${B:-build}
SHARED=${SHARED:-../shared}
W=$(mktemp -d "${TMPDIR:-/tmp}/vsv-bench-codec.XXXXXX")
trap 'rm -rf "$W"' EXIT
${CC:-cc} -O2 -o "$W/gen_volume" "$SHARED/tools/gen-plume/gen_volume.c" -lm
"$W/gen_volume" "$W" >/dev/null
printf '%s cores; %s; load %s\n\n' "$(nproc)" "$(date -u +%Y-%m-%d)" "$(cut -d' ' -f1-3 /proc/loadavg)"
"$B/bench/bench_codec" "$SHARED" "$W" "$W"
