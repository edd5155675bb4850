#!/bin/sh
# bench_play.sh — streamed playback (issue #6): the real MM5 run at a 5-minute
# step, then synthetic 256x256x48 x 4-species files of 8 steps (~0.17 GB) and
# 100 steps (>= 2 GB) of the same grid: the first frame should not depend on
# the file's size.
set -eu
B=${B:-build}
SHARED=${SHARED:-../shared}
W=$(mktemp -d "${TMPDIR:-/tmp}/vsv-bench-play.XXXXXX")
trap 'rm -rf "$W"' EXIT
printf '%s cores; %s\n\n' "$(nproc)" "$(date -u +%Y-%m-%d)"
"$B/vsv-convert" -q --time-res 5m "$SHARED/data/mm5/run1/MMOUT_DOMAIN1" -o "$W/mm5.vsv"
"$B/bench/bench_play" "$W/mm5.vsv"
echo
"$B/bench/bench_play" --make "$W/small.vsv" 8
"$B/bench/bench_play" "$W/small.vsv"
rm -f "$W/small.vsv"
echo
"$B/bench/bench_play" --make "$W/big.vsv" 100
"$B/bench/bench_play" "$W/big.vsv"
