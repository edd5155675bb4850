#!/bin/sh
# bench_mpi.sh — vsv-convert-mpi's scaling on this machine: the real MM5 run
# at 10-minute frames (19 steps) on 1 and 2 ranks, with vsv-convert (one
# process, its encoder on every core) as the peer, interleaved in ROUNDS
# rounds (default 5) with the load average before each; the medians and the
# median of the per-round ratios. Then one rank's per-step read, encode and
# write seconds (--stats) on the MM5 run and on a synthetic CAMx run: the
# inputs of the scaling model in bench/RESULTS.md.
set -eu
B=${B:-build}
SHARED=${SHARED:-../shared}
ROUNDS=${ROUNDS:-5}
IN=${1:-$SHARED/data/mm5/run1/MMOUT_DOMAIN1}
[ -x "$B/vsv-convert-mpi" ] || { echo "bench_mpi: $B/vsv-convert-mpi not built (apt-get install libopenmpi-dev openmpi-bin)"; exit 0; }
[ -f "$IN" ] || { echo "bench_mpi: $IN not found" >&2; exit 1; }
W=$(mktemp -d "${TMPDIR:-/tmp}/vsv-bench-mpi.XXXXXX")
trap 'rm -rf "$W"' EXIT
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
MPIRUN="mpirun -q --oversubscribe --mca btl self,vader --mca btl_vader_single_copy_mechanism none --mca plm_rsh_agent false"
cat "$IN" > /dev/null   # the page cache warm for every contender alike
secs() { s=$(date +%s.%N); "$@" > /dev/null 2>&1; e=$(date +%s.%N); echo "$e - $s" | bc -l; }
median() { sort -g | awk '{ v[NR] = $1 } END { print (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2 }'; }
load() { cut -d' ' -f1 /proc/loadavg; }
steps=19
printf 'input: %s, --time-res 10m (%d steps); machine: %s cores; %s\n\n' "$IN" $steps "$(nproc)" "$(date -u +%Y-%m-%dT%H:%MZ)"
printf '| round | load (1 min) | vsv-convert s | np 1 s | np 2 s | np 2 / np 1 | np 2 / vsv-convert |\n|---|---|---|---|---|---|---|\n'
: > "$W/rows"
for r in $(seq 1 "$ROUNDS"); do
    l=$(load)
    c=$(secs "$B/vsv-convert" -q --vertical even --time-res 10m "$IN" -o "$W/c.vsv")
    m1=$(secs $MPIRUN -np 1 "$B/vsv-convert-mpi" -q --vertical even --time-res 10m "$IN" -o "$W/m1.vsv")
    m2=$(secs $MPIRUN -np 2 "$B/vsv-convert-mpi" -q --vertical even --time-res 10m "$IN" -o "$W/m2.vsv")
    cmp -s "$W/c.vsv" "$W/m2.vsv" && cmp -s "$W/c.vsv" "$W/m1.vsv" || { echo "bench_mpi: outputs differ" >&2; exit 1; }
    r21=$(echo "$m1 / $m2" | bc -l)
    r2c=$(echo "$c / $m2" | bc -l)
    printf '| %d | %s | %.2f | %.2f | %.2f | %.2fx | %.2fx |\n' "$r" "$l" "$c" "$m1" "$m2" "$r21" "$r2c"
    echo "$c $m1 $m2 $r21 $r2c" >> "$W/rows"
done
col() { awk -v c="$1" '{ print $c }' "$W/rows" | median; }
printf '| median | %s | %.2f | %.2f | %.2f | %.2fx | %.2fx |\n' "$(load)" "$(col 1)" "$(col 2)" "$(col 3)" "$(col 4)" "$(col 5)"
printf '\nrates (median): vsv-convert %.2f steps/s, np 1 %.2f steps/s, np 2 %.2f steps/s\n' \
    "$(echo "$steps / $(col 1)" | bc -l)" "$(echo "$steps / $(col 2)" | bc -l)" "$(echo "$steps / $(col 3)" | bc -l)"

printf '\nper-step costs on one rank (--stats), load %s:\n\n' "$(load)"
$MPIRUN -np 1 "$B/vsv-convert-mpi" -q --vertical even --stats --time-res 10m "$IN" -o "$W/m1.vsv" | sed 's/^/    /'
HOURS=${HOURS:-6}
if [ -x "$B/bench/bench_camx" ]; then
    "$B/bench/bench_camx" "$W/run.avrg" "$HOURS" > /dev/null
    printf '\nsynthetic CAMx AVERAGE, 200x200x25, 40 species, %s hours (%s MB), --vertical native:\n\n' "$HOURS" \
        "$(echo "$(stat -c %s "$W/run.avrg") / 1000000" | bc)"
    cat "$W/run.avrg" > /dev/null
    $MPIRUN -np 1 "$B/vsv-convert-mpi" -q --stats --vertical native "$W/run.avrg" -o "$W/camx.vsv" | sed 's/^/    /'
fi
