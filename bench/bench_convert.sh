#!/bin/sh
# bench_convert.sh — MM5 conversion throughput (MB of MM5 input per second)
# of vsv-convert with 1 and 2 threads, beside zstd -3 and gzip -6 of the same
# input in the same run. Best of 3 wall-clock runs each.
set -eu
B=${B:-build}
SHARED=${SHARED:-../shared}
IN=${1:-$SHARED/data/mm5/run1/MMOUT_DOMAIN1}
W=$(mktemp -d "${TMPDIR:-/tmp}/vsv-bench-conv.XXXXXX")
trap 'rm -rf "$W"' EXIT
[ -f "$IN" ] || { echo "bench_convert: $IN not found" >&2; exit 1; }
bytes=$(stat -c %s "$IN")
cat "$IN" > /dev/null   # warm the page cache for every contender alike
best() { # best wall seconds of 3 runs of "$@"
    b=
    for i in 1 2 3; do
        s=$(date +%s.%N); "$@" > /dev/null 2>&1; e=$(date +%s.%N)
        t=$(echo "$e - $s" | bc -l)
        if [ -z "$b" ] || [ "$(echo "$t < $b" | bc -l)" = 1 ]; then b=$t; fi
    done
    echo "$b"
}
row() { # name seconds output-file
    size=$( [ -f "$3" ] && stat -c %s "$3" || echo 0)
    printf '| %s | %.3f | %.0f | %.2f |\n' "$1" "$2" "$(echo "$bytes / $2 / 1000000" | bc -l)" "$(echo "$size / 1000000" | bc -l)"
}
printf 'input: %s (%.1f MB); machine: %s cores; %s\n\n' "$IN" "$(echo "$bytes / 1000000" | bc -l)" "$(nproc)" "$(date -u +%Y-%m-%d)"
printf '| command | seconds | MB/s of input | output MB |\n|---|---|---|---|\n'
t=$(best "$B/vsv-convert" -q --vertical even --threads 1 "$IN" -o "$W/a.vsv"); row "vsv-convert --threads 1 (CLW RNW ICE SNOW Q, 40 even levels)" "$t" "$W/a.vsv"
t=$(best "$B/vsv-convert" -q --vertical even --threads 2 "$IN" -o "$W/b.vsv"); row "vsv-convert --threads 2" "$t" "$W/b.vsv"
t=$(best "$B/vsv-convert" -q --threads 2 --vertical native "$IN" -o "$W/c.vsv"); row "vsv-convert --threads 2 --vertical native" "$t" "$W/c.vsv"
t=$(best "$B/vsv-convert" -q --vertical even --threads 2 --time-res 10m "$IN" -o "$W/d.vsv"); row "vsv-convert --threads 2 --time-res 10m (19 frames)" "$t" "$W/d.vsv"
t=$(best sh -c "'$B/vsv-extract' '$IN' | '$B/vsv-pack' -q -o '$W/e.vsv'"); row "vsv-extract \\| vsv-pack (the pipe)" "$t" "$W/e.vsv"
t=$(best sh -c "zstd -3 -T1 -q -c '$IN' > '$W/in.zst'"); row "zstd -3 (one thread)" "$t" "$W/in.zst"
t=$(best sh -c "zstd -3 -T2 -q -c '$IN' > '$W/in2.zst'"); row "zstd -3 -T2" "$t" "$W/in2.zst"
t=$(best sh -c "gzip -6 -c '$IN' > '$W/in.gz'"); row "gzip -6" "$t" "$W/in.gz"
