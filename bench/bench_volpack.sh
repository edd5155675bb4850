#!/bin/sh
# bench_volpack.sh — the shear-warp renderer beside VolPack (libvolpack1-dev) on
# the same 8-bit volumes from the converted real MM5 run (CLW and SNOW sparse,
# Q dense), the real WRF file (QCLOUD) and gen-plume's plume (sparse) and haze
# (never empty),
# set up alike (bench/vp_match.h), after a closed-form box that checks the
# set-up; each run prints the PSNR between the two pictures (a comparison
# counts at 35 dB or more) and the machine's load.
set -eu
B=${B:-build}
SHARED=${SHARED:-../shared}
W=$(mktemp -d "${TMPDIR:-/tmp}/vsv-bench-volpack.XXXXXX")
trap 'rm -rf "$W"' EXIT
"$B/vsv-convert" -q --vertical even "$SHARED/data/mm5/run1/MMOUT_DOMAIN1" -o "$W/mm5.vsv"
printf '%s cores; %s; load average %s at the start\n\n' "$(nproc)" "$(date -u '+%Y-%m-%d %H:%M UTC')" \
    "$(cut -d' ' -f1 /proc/loadavg)"
# the closed-form case first: a box off the middle of an otherwise empty grid
"$B/bench/bench_volpack" --box "$W/box.vsv"
echo
"$B/bench/bench_volpack" "$W/mm5.vsv" CLW 3
echo
"$B/bench/bench_volpack" "$W/mm5.vsv" Q 3
echo
"$B/bench/bench_volpack" "$W/mm5.vsv" SNOW 3
# the real WRF file: QCLOUD at its fourth time (21 UTC)
"$B/vsv-convert" -q --vertical even "$SHARED/data/wrf/katrina_ci_test_file.nc" -o "$W/wrf.vsv"
echo
"$B/bench/bench_volpack" "$W/wrf.vsv" QCLOUD 3
# gen-plume's synthetic volumes: the sparse plume and the hazy one
${CC:-cc} -O2 -o "$W/gen_volume" "$SHARED/tools/gen-plume/gen_volume.c" -lm
"$W/gen_volume" "$W" >/dev/null
echo
"$B/bench/bench_volpack" --plume "$W"
echo
"$B/bench/bench_volpack" --haze "$W"
printf '\nload average %s at the end\n' "$(cut -d' ' -f1 /proc/loadavg)"
