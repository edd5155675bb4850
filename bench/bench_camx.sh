#!/bin/sh
# bench_camx.sh — CAMx conversion throughput: a synthetic continental UAM-IV
# run (200x200 cells, 25 layers, 40 species; HOURS hours, default 24) through
# vsv-convert with 1 and 2 threads beside zstd -3 of the same input, and the
# .vsv size beside the netCDF-4 deflate equivalent (nccopy -d4 of an IOAPI-like
# classic file of the same values).
set -eu
B=${B:-build}
HOURS=${HOURS:-24}
W=$(mktemp -d "${TMPDIR:-/tmp}/vsv-bench-camx.XXXXXX")
trap 'rm -rf "$W"' EXIT
"$B/bench/bench_camx" "$W/run.avrg" "$HOURS"
bytes=$(stat -c %s "$W/run.avrg")
cat "$W/run.avrg" > /dev/null
secs() { s=$(date +%s.%N); "$@" > /dev/null 2>&1; e=$(date +%s.%N); echo "$e - $s" | bc -l; }
mbps() { echo "$bytes / $1 / 1000000" | bc -l; }
printf 'input: synthetic CAMx AVERAGE, 200x200x25, 40 species, %s hours: %.1f MB; %s cores; %s\n\n' "$HOURS" \
    "$(echo "$bytes / 1000000" | bc -l)" "$(nproc)" "$(date -u +%Y-%m-%d)"
printf '| command | seconds | MB/s of input | output MB |\n|---|---|---|---|\n'
for th in 1 2; do
    t=$(secs "$B/vsv-convert" -q --threads $th --vertical native "$W/run.avrg" -o "$W/run.vsv")
    printf '| vsv-convert --threads %s (all 40 species, layers kept) | %.2f | %.0f | %.1f |\n' $th "$t" "$(mbps "$t")" \
        "$(echo "$(stat -c %s "$W/run.vsv") / 1000000" | bc -l)"
    eval "t$th=\$t"
done
vsv=$(stat -c %s "$W/run.vsv")
t=$(secs sh -c "zstd -3 -T1 -q -c '$W/run.avrg' > '$W/run.zst'")
tz=$t
zst=$(stat -c %s "$W/run.zst")
printf '| zstd -3 (one thread) | %.2f | %.0f | %.1f |\n' "$t" "$(mbps "$t")" "$(echo "$(stat -c %s "$W/run.zst") / 1000000" | bc -l)"
t=$(secs sh -c "zstd -3 -T2 -q -c '$W/run.avrg' > '$W/run2.zst'")
printf '| zstd -3 -T2 | %.2f | %.0f | %.1f |\n' "$t" "$(mbps "$t")" "$(echo "$(stat -c %s "$W/run2.zst") / 1000000" | bc -l)"
rm -f "$W/run.zst" "$W/run2.zst"
"$B/bench/bench_camx_nc" "$W/run.avrg" "$W/run.nc"
t=$(secs nccopy -d4 "$W/run.nc" "$W/run.d4.nc")
printf '| netCDF-4 deflate 4 (nccopy -d4 of the same floats) | %.2f | %.0f | %.1f |\n' "$t" "$(mbps "$t")" \
    "$(echo "$(stat -c %s "$W/run.d4.nc") / 1000000" | bc -l)"
nc4=$(stat -c %s "$W/run.d4.nc")
echo
printf -- '- .vsv size / netCDF-4 deflate 4: %.3f; / zstd -3: %.3f\n' "$(echo "$vsv / $nc4" | bc -l)" "$(echo "$vsv / $zst" | bc -l)"
printf -- '- vsv-convert 2 threads / 1 thread: %.2fx faster; vsv-convert 2 threads / zstd -3 one thread: %.2fx the time\n' \
    "$(echo "$t1 / $t2" | bc -l)" "$(echo "$t2 / $tz" | bc -l)"
