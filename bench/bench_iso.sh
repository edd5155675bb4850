#!/bin/sh
# bench_iso.sh — isosurfaces on the real MM5 run: extraction per step
# (afresh and kept across steps) and frames with and without the surface
# (bench_iso.c), the run converted with its own levels (per-column heights).
set -eu
B=${B:-build}
SHARED=${SHARED:-../shared}
W=$(mktemp -d "${TMPDIR:-/tmp}/vsv-bench-iso.XXXXXX")
trap 'rm -rf "$W"' EXIT
MM5="$SHARED/data/mm5/run1/MMOUT_DOMAIN1"
"$B/vsv-convert" -q "$MM5" --vars CLW,RNW,ICE,SNOW -o "$W/native.vsv"
printf 'data: MMOUT_DOMAIN1, native levels; %s cores, load %s; %s\n' "$(nproc)" \
    "$(cut -d' ' -f1-3 /proc/loadavg)" "$(date -u '+%Y-%m-%d %H:%M UTC')"
"$B/bench/bench_iso" "$W/native.vsv" CLW 5e-5 "${ROUNDS:-5}"
"$B/bench/bench_iso" "$W/native.vsv" SNOW 2e-5 "${ROUNDS:-5}"
