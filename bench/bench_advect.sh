#!/bin/sh
# bench_advect.sh — time interpolation along the winds (--interp advect)
# against linear interpolation on real model output: fidelity (hold out an
# output, rebuild it from its neighbours, errors per species and centroid
# errors of the main cloud objects; bench_advect.c) with linear, advect
# (the wind's displacement scaled as fitted per species and band) and wind
# (the air's own displacement); how far the patterns really moved
# (advect_motion.py); conversion time of the three, interleaved in the same
# run; and the MM5 run as 10-minute movies, linear and advect, with one ice
# cloud followed through the frames (advect_track.py). Results:
# bench/RESULTS.md. Needs /usr/bin/python3 with numpy and scipy.
#   sh bench/bench_advect.sh            (B=build SHARED=../shared ROUNDS=3 OUT=dir)
set -eu
B=${B:-build}
SHARED=${SHARED:-../shared}
ROUNDS=${ROUNDS:-3}
MM5="$SHARED/data/mm5/run1/MMOUT_DOMAIN1"
W=$(mktemp -d "${TMPDIR:-/tmp}/vsv-bench-advect.XXXXXX")
OUT=${OUT:-$W}
trap 'rm -f "$W"/*.vsv "$W"/*.fs "$W"/*.t "$W"/t; rmdir "$W" 2> /dev/null' EXIT
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
echo "### Diagnostic: the MM5 hold-out with the winds scaled (the wind column moves that far)"
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
echo "### Diagnostic: how far the patterns moved, against how far the air moved (01:00 to 03:00), and a free motion field"
echo
"$B/vsv-extract" --add-winds --vertical even "$MM5" > "$W/mm5.fs"
/usr/bin/python3 bench/advect_motion.py "$W/mm5.fs" 2
rm -f "$W/mm5.fs"

echo
echo "### Speed: vsv-convert --time-res 10m of the MM5 run (19 frames, 5 species), $ROUNDS rounds interleaved"
echo
best() { sort -n | head -n 1; }
for m in linear advect wind; do : > "$W/$m.t"; done
for r in $(seq "$ROUNDS"); do
    for m in linear advect wind; do
        /usr/bin/time -f '%e %U %S' -o "$W/t" "$B/vsv-convert" -q --vertical even --time-res 10m --interp $m "$MM5" -o "$W/$m.vsv"
        cat "$W/t" >> "$W/$m.t"
    done
done
printf '| path | wall s (best of %s) | CPU s (best) | wall / linear | CPU / linear |\n|---|---|---|---|---|\n' "$ROUNDS"
lw=$(cut -d' ' -f1 "$W/linear.t" | best); lc=$(awk '{print $2 + $3}' "$W/linear.t" | best)
for m in linear advect wind; do
    w=$(cut -d' ' -f1 "$W/$m.t" | best); c=$(awk '{print $2 + $3}' "$W/$m.t" | best)
    printf '| %s | %s | %s | %.2f | %.2f |\n' "$m" "$w" "$c" "$(echo "$w / $lw" | bc -l)" "$(echo "$c / $lc" | bc -l)"
done
printf 'load after: %s\n' "$(cut -d' ' -f1-3 /proc/loadavg)"

echo
echo "### Movies and frames: the MM5 run every 10 minutes, cloud ice (a map of the domain)"
echo
for m in linear advect; do
    "$B/vsv-extract" --add-winds --vertical even -v ICE,SNOW,CLW "$MM5" | "$B/vsv-interp" --time-res 10m --interp $m > "$W/$m.fs"
    "$B/vsv-pack" -q -o "$W/$m.vsv" < "$W/$m.fs"
    if command -v ffmpeg > /dev/null; then
        "$B/vsv-render" -q "$W/$m.vsv" --movie "$OUT/mm5-$m.mp4" --fps 4 --species ICE:3 --view plan --size 828x568
    fi
    "$B/vsv-render" -q "$W/$m.vsv" --times 12:18 --species ICE:3 --view plan --size 828x568 -o "$OUT/mm5-$m-%04d.png"
done
echo "$OUT/mm5-linear.mp4 and mm5-advect.mp4 (with ffmpeg); 02:00..03:00 as $OUT/mm5-{linear,advect}-000N.png, N = 0..6"
echo
# the upper-level ice north-east of the domain's centre (cells ~122..129, 108..110)
/usr/bin/python3 bench/advect_track.py "$W/linear.fs" "$W/advect.fs" ICE 32 36 12 18
rm -f "$W"/*.fs
