#!/bin/sh
# bench_render.sh — raycaster frame rates on the converted real MM5 run (all five
# default species, 40 even levels, exaggerated), 512² and 1024², 1 and 2 threads.
set -eu
B=${B:-build}
SHARED=${SHARED:-../shared}
W=$(mktemp -d "${TMPDIR:-/tmp}/vsv-bench-render.XXXXXX")
trap 'rm -rf "$W"' EXIT
"$B/vsv-convert" -q --vertical even "$SHARED/data/mm5/run1/MMOUT_DOMAIN1" -o "$W/mm5.vsv"
printf 'data: MMOUT_DOMAIN1 at 3 h, 207x142x40, 5 species (Q CLW RNW ICE SNOW); %s cores; %s\n\n' "$(nproc)" "$(date -u +%Y-%m-%d)"
"$B/bench/bench_render" "$W/mm5.vsv"
