#!/bin/sh
# bench_advect.sh — time interpolation along the winds (--interp advect)
# against linear interpolation on real model output: fidelity (hold out an
# output, rebuild it from its neighbours, errors per species and centroid
# errors of the main cloud objects; bench_advect.c), conversion time of the
# two paths measured interleaved in the same run, and the MM5 run as
# 10-minute movies both ways. Results: bench/RESULTS.md.
#   sh bench/bench_advect.sh            (B=build SHARED=../shared ROUNDS=3 OUT=dir)
set -eu
B=${B:-build}
SHARED=${SHARED:-../shared}
ROUNDS=${ROUNDS:-3}
MM5="$SHARED/data/mm5/run1/MMOUT_DOMAIN1"
W=$(mktemp -d "${TMPDIR:-/tmp}/vsv-bench-advect.XXXXXX")
OUT=${OUT:-$W}
trap 'rm -f "$W"/*.vsv' EXIT
mkdir -p "$OUT"
printf 'machine: %s cores, load %s; %s\n\n' "$(nproc)" "$(cut -d' ' -f1-3 /proc/loadavg)" "$(date -u +%Y-%m-%dT%H:%MZ)"

echo "### Fidelity: a held-out output rebuilt from its neighbours"
echo
"$B/bench/bench_advect" "$MM5" 2
for f in katrina_ci_test_file.nc wrf_d01_allvars_cropped.nc; do
    for h in 1 2; do
        echo
        "$B/bench/bench_advect" "$SHARED/data/wrf/$f" $h
    done
done

echo
echo "### Diagnostic: the MM5 hold-out with the winds scaled (how fast do the clouds move?)"
for sc in 0.25 0.5; do
    echo
    "$B/bench/bench_advect" "$MM5" 2 "" $sc | sed -n '/scaled by/p;/^| [A-Z]/p'
done
echo
echo "### Diagnostic: one wind component's sign turned, or W off (would a reader's sign error explain it?)"
for sc in -1,1,1 1,-1,1 1,1,-1 1,1,0; do
    echo
    "$B/bench/bench_advect" "$MM5" 2 "" $sc | sed -n '/scaled by/p;/^| [A-Z]/p'
done
echo
echo "### Diagnostic: how far the vapour pattern moved, against how far the air moved (01:00 to 03:00)"
"$B/bench/bench_advect" "$MM5" 2 Q 1 shift | sed -n '/best shift/,$p'

echo
echo "### Speed: vsv-convert --time-res 10m of the MM5 run (19 frames, 5 species), $ROUNDS rounds interleaved"
echo
best() { sort -n | head -n 1; }
: > "$W/lin.t"
: > "$W/adv.t"
for r in $(seq "$ROUNDS"); do
    /usr/bin/time -f '%e %U %S' -o "$W/t" "$B/vsv-convert" -q --time-res 10m "$MM5" -o "$W/lin.vsv"
    cat "$W/t" >> "$W/lin.t"
    /usr/bin/time -f '%e %U %S' -o "$W/t" "$B/vsv-convert" -q --time-res 10m --interp advect "$MM5" -o "$W/adv.vsv"
    cat "$W/t" >> "$W/adv.t"
done
lw=$(cut -d' ' -f1 "$W/lin.t" | best); aw=$(cut -d' ' -f1 "$W/adv.t" | best)
lc=$(awk '{print $2 + $3}' "$W/lin.t" | best); ac=$(awk '{print $2 + $3}' "$W/adv.t" | best)
printf '| path | wall s (best of %s) | CPU s (best) |\n|---|---|---|\n' "$ROUNDS"
printf '| linear | %s | %s |\n| advect | %s | %s |\n' "$lw" "$lc" "$aw" "$ac"
printf '| advect / linear | %.2f | %.2f |\n' "$(echo "$aw / $lw" | bc -l)" "$(echo "$ac / $lc" | bc -l)"

# the Pacific Northwest, where the jet carries the clouds fastest: from
# 1400 km south of them, 12 km up (projection metres; heights exaggerated)
VIEW=--look-at=-1900000,-100000,12000,-1900000,1300000,2000
echo
echo "### Movies and frames: the MM5 run every 10 minutes, cloud water, snow and ice"
for m in linear advect; do
    "$B/vsv-convert" -q --time-res 10m --interp $m --vars CLW,SNOW,ICE "$MM5" -o "$W/$m.vsv"
    if command -v ffmpeg > /dev/null; then
        "$B/vsv-render" -q "$W/$m.vsv" --movie "$OUT/mm5-$m.mp4" --fps 4 --species CLW:3,SNOW:2,ICE:2 "$VIEW" --size 560x400
    fi
    "$B/vsv-render" -q "$W/$m.vsv" --times 12:18 --species CLW:3,SNOW:2,ICE:2 "$VIEW" --size 560x400 \
        -o "$OUT/mm5-$m-%04d.png"
done
echo "$OUT/mm5-linear.mp4 and mm5-advect.mp4 (with ffmpeg); 02:00..03:00 as $OUT/mm5-{linear,advect}-000N.png, N = 0..6"
