#!/bin/sh
# bench_traj.sh — trajectories on the real MM5 run (bench_traj.c): its wind
# written on the run's own levels, paths seeded on a slice over its 3 hours.
set -eu
B=${B:-build}
SHARED=${SHARED:-../shared}
W=$(mktemp -d "${TMPDIR:-/tmp}/vsv-bench-traj.XXXXXX")
trap 'rm -rf "$W"' EXIT
MM5="$SHARED/data/mm5/run1/MMOUT_DOMAIN1"
[ -f "$MM5" ] || { echo "(trajectories skipped: $MM5 absent)"; exit 0; }
printf 'data: MMOUT_DOMAIN1, native levels; %s cores, load %s; %s\n' "$(nproc)" \
    "$(cut -d' ' -f1-3 /proc/loadavg)" "$(date -u '+%Y-%m-%d %H:%M UTC')"
"$B/bench/bench_traj" "$MM5" "$W/wind.vsv" 8 1500
