#!/bin/sh
# bench_gl.sh — the GPU raycaster against the CPU raycaster (issue #31): at
# 1024 x 1024 and 1920 x 1200, on the real MM5 run (its last output, Q CLW
# SNOW) and gen-plume's plume and haze, the same cameras (an orbit: every
# frame renders anew), interleaved (bench/bench_gl.c); frames a second, CPU
# a frame, the ratio, the PSNR and the OpenGL device it ran on. Here the
# device is Mesa's llvmpipe, this machine's CPU; the same script runs
# unchanged where EGL finds a GPU. FRAMES (default 3) a configuration.
set -eu
B=${B:-build}
SHARED=${SHARED:-../shared}
FRAMES=${FRAMES:-3}
W=$(mktemp -d "${TMPDIR:-/tmp}/vsv-bench-gl.XXXXXX")
trap 'rm -rf "$W"' EXIT
[ -x "$B/bench/bench_gl" ] || make -s --no-print-directory "$B/bench/bench_gl" "$B/bench/bench_play"
printf '%s cores; %s; %s\n' "$(nproc)" "$(date -u +%Y-%m-%dT%H:%MZ)" "$(uptime | sed 's/.*load/load/')"
sets=""
if [ -f "$SHARED/data/mm5/run1/MMOUT_DOMAIN1" ]; then
    "$B/vsv-convert" -q --vertical even --times 3 "$SHARED/data/mm5/run1/MMOUT_DOMAIN1" -o "$W/mm5.vsv"
    sets="mm5:Q,CLW,SNOW"
fi
if [ -f "$SHARED/tools/gen-plume/gen_volume.c" ]; then
    ${CC:-cc} -O2 -o "$W/gen_volume" "$SHARED/tools/gen-plume/gen_volume.c" -lm
    "$W/gen_volume" "$W" > /dev/null
    "$B/bench/bench_play" --plume "$W/plume.vsv" 1 "$W/plume_t0.f32" > /dev/null
    "$B/bench/bench_play" --plume "$W/haze.vsv" 1 "$W/plume_haze.f32" > /dev/null
    rm -f "$W"/plume_*.f32 "$W"/plume_*.u8 "$W"/plume_*.u16
    sets="$sets plume:- haze:-"
fi
[ -n "$sets" ] || { echo "(bench_gl: no data: $SHARED/data and $SHARED/tools/gen-plume are missing)"; exit 0; }
for size in 1024x1024 1920x1200; do
    for s in $sets; do
        "$B/bench/bench_gl" "$W/${s%%:*}.vsv" "${s#*:}" "$size" "$FRAMES"
    done
done
