#!/bin/sh
# bench_codec.sh — the brick coding's size beside netCDF-4 deflate and ZFP
# (libzfp-dev) at the same error bound, with its decode speed, one run: the
# real MM5 run (Q, CLW, SNOW), a real WRF file and gen-plume's plume.
set -eu
B=${B:-build}
SHARED=${SHARED:-../shared}
W=$(mktemp -d "${TMPDIR:-/tmp}/vsv-bench-codec.XXXXXX")
trap 'rm -rf "$W"' EXIT
${CC:-cc} -O2 -o "$W/gen_volume" "$SHARED/tools/gen-plume/gen_volume.c" -lm
"$W/gen_volume" "$W" >/dev/null
printf '%s cores; %s; load %s\n\n' "$(nproc)" "$(date -u +%Y-%m-%d)" "$(cut -d' ' -f1-3 /proc/loadavg)"
BENCH_CODEC_KEEP=1 "$B/bench/bench_codec" "$SHARED" "$W" "$W"
# Where the decode's time goes, printed (perf, when installed): the
# format-4 files of the run above decoded alone, one thread, sampled; the
# shares by where the code lives (libzstd: zstd's decoding; bench_codec: the
# library's own decoder, linked in; the kernel: page faults) and the five
# largest functions.
if command -v perf >/dev/null 2>&1; then
    printf '\nWhere the decode time goes (perf record of bench_codec --decode FILE PASSES, one thread; %% of samples):\n\n'
    # passes: about a second of decoding each (the small files' start-up
    # and first page faults would otherwise show)
    for fp in MM5_Q:100 MM5_CLW:1000 MM5_SNOW:500 WRF_Katrina_QVAPOR_QCLOUD:500 gen-plume_plume:100; do
        f=${fp%:*}
        [ -f "$W/$f.vsv" ] || continue
        if ! perf record -q -o "$W/perf.data" "$B/bench/bench_codec" --decode "$W/$f.vsv" "${fp#*:}" >/dev/null 2>&1; then
            echo "$f: perf record failed"
            continue
        fi
        printf '%s: by library: %s\n' "$f" "$(perf report -i "$W/perf.data" --stdio -q --sort dso 2>/dev/null |
            awk 'NF >= 2 && $1 ~ /%$/ { printf "%s%s %s", sep, $2, $1; sep = ", " }')"
        printf '%s: by function: %s\n' "$f" "$(perf report -i "$W/perf.data" --stdio -q --sort sym 2>/dev/null |
            awk 'NF >= 3 && $1 ~ /%$/ && n < 5 { printf "%s%s %s", sep, $NF, $1; sep = ", "; n++ }')"
    done
else
    printf '\n(perf not installed: where the decode time goes not printed)\n'
fi
