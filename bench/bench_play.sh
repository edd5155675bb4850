#!/bin/sh
# bench_play.sh — streamed playback (issues #6, #23): the real MM5 run at a
# 5-minute step, then synthetic 256x256x48 x 4-species files of 8 steps
# (~0.17 GB) and 100 steps (>= 2 GB) of the same grid: the first frame should
# not depend on the file's size. Then decoding speed, the earlier path (every
# brick from its keyframe) against incremental decoding, interleaved in one
# run: on the MM5 run, on a noisy series from gen-plume's plume
# ($SHARED/tools/gen-plume), and on the 2.1 GB file.
set -eu
B=${B:-build}
SHARED=${SHARED:-../shared}
W=$(mktemp -d "${TMPDIR:-/tmp}/vsv-bench-play.XXXXXX")
trap 'rm -rf "$W"' EXIT
printf '%s cores; %s\n\n' "$(nproc)" "$(date -u +%Y-%m-%d)"
"$B/vsv-convert" -q --vertical even --time-res 5m "$SHARED/data/mm5/run1/MMOUT_DOMAIN1" -o "$W/mm5.vsv"
if [ -z "${BENCH_COMPARE_ONLY:-}" ]; then
    "$B/bench/bench_play" "$W/mm5.vsv"
    echo
    "$B/bench/bench_play" --make "$W/small.vsv" 8
    "$B/bench/bench_play" "$W/small.vsv"
    rm -f "$W/small.vsv"
    echo
fi
echo "## from keyframe against incremental"
echo
"$B/bench/bench_play" --compare "$W/mm5.vsv" 64 1024
echo
if [ -f "$SHARED/tools/gen-plume/gen_volume.c" ]; then
    cc -O2 -o "$W/gen_volume" "$SHARED/tools/gen-plume/gen_volume.c" -lm
    "$W/gen_volume" "$W" > /dev/null
    "$B/bench/bench_play" --plume "$W/plume.vsv" 32 "$W/plume_t0.f32"
    rm -f "$W"/plume_*.f32 "$W"/plume_*.u8 "$W"/plume_*.u16
    "$B/bench/bench_play" --compare "$W/plume.vsv" 64 1024
    rm -f "$W/plume.vsv"
    echo
else
    echo "(no $SHARED/tools/gen-plume: the plume series is skipped)"
fi
[ -n "${BENCH_SMALL:-}" ] && exit 0
"$B/bench/bench_play" --make "$W/big.vsv" 100
[ -z "${BENCH_COMPARE_ONLY:-}" ] && "$B/bench/bench_play" "$W/big.vsv"
"$B/bench/bench_play" --compare "$W/big.vsv" 1024
