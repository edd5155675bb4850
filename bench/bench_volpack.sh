#!/bin/sh
# bench_volpack.sh — the shear-warp renderer beside VolPack (libvolpack1-dev) on
# the same 8-bit volumes from the converted real MM5 run (CLW sparse, Q dense),
# set up alike (bench/vp_match.h); each run prints the PSNR between the two
# pictures (a comparison counts at 35 dB or more) and the machine's load.
set -eu
B=${B:-build}
SHARED=${SHARED:-../shared}
W=$(mktemp -d "${TMPDIR:-/tmp}/vsv-bench-volpack.XXXXXX")
trap 'rm -rf "$W"' EXIT
"$B/vsv-convert" -q "$SHARED/data/mm5/run1/MMOUT_DOMAIN1" -o "$W/mm5.vsv"
printf '%s cores; %s; load average %s at the start\n\n' "$(nproc)" "$(date -u '+%Y-%m-%d %H:%M UTC')" \
    "$(cut -d' ' -f1 /proc/loadavg)"
"$B/bench/bench_volpack" "$W/mm5.vsv" CLW 3
echo
"$B/bench/bench_volpack" "$W/mm5.vsv" Q 3
printf '\nload average %s at the end\n' "$(cut -d' ' -f1 /proc/loadavg)"
