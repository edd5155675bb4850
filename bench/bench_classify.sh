#!/bin/sh
# bench_classify.sh — the shear-warp's classification and its frame rate while
# playing beside VolPack (libvolpack1-dev), same volumes, matched opacity, one
# run: the real MM5 run (Q, CLW, SNOW), the real WRF file (QCLOUD) and
# gen-plume's plume and haze.
set -eu
B=${B:-build}
SHARED=${SHARED:-../shared}
W=$(mktemp -d "${TMPDIR:-/tmp}/vsv-bench-classify.XXXXXX")
trap 'rm -rf "$W"' EXIT
"$B/vsv-convert" -q --vertical even "$SHARED/data/mm5/run1/MMOUT_DOMAIN1" -o "$W/mm5.vsv"
${CC:-cc} -O2 -o "$W/gen_volume" "$SHARED/tools/gen-plume/gen_volume.c" -lm
"$W/gen_volume" "$W" >/dev/null
# the real WRF file, picked up by bench_classify as $W/wrf.vsv
"$B/vsv-convert" -q --vertical even "$SHARED/data/wrf/katrina_ci_test_file.nc" -o "$W/wrf.vsv"
printf '%s cores; %s; load %s\n\n' "$(nproc)" "$(date -u +%Y-%m-%d)" "$(cut -d' ' -f1-3 /proc/loadavg)"
"$B/bench/bench_classify" "$W/mm5.vsv" "$W" "${ROUNDS:-5}"
