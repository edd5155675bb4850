#!/bin/sh
# bench_native.sh — native levels at their heights (resample on load) against
# even heights, on the real MM5 run: the same four hydrometeors converted
# both ways, loaded and drawn interleaved (bench_native.c).
set -eu
B=${B:-build}
SHARED=${SHARED:-../shared}
W=$(mktemp -d "${TMPDIR:-/tmp}/vsv-bench-native.XXXXXX")
trap 'rm -rf "$W"' EXIT
MM5="$SHARED/data/mm5/run1/MMOUT_DOMAIN1"
"$B/vsv-convert" -q --vertical even "$MM5" --vars CLW,RNW,ICE,SNOW -o "$W/even.vsv"
"$B/vsv-convert" -q --vertical native "$MM5" --vars CLW,RNW,ICE,SNOW -o "$W/native.vsv"
printf 'data: MMOUT_DOMAIN1, CLW RNW ICE SNOW, 4 steps; %s cores; %s\n' "$(nproc)" "$(date -u +%Y-%m-%d)"
"$B/bench/bench_native" "$W/even.vsv" "$W/native.vsv" "${ROUNDS:-5}"
