#!/bin/sh
# bench_vtk.sh — the raycaster beside VTK's vtkFixedPointVolumeRayCastMapper on
# the suite of bench_peers.py (MM5 Q, CLW, SNOW, WRF QCLOUD, gen-plume's plume and
# haze; matched settings, interleaved rounds, PSNR and ratios printed), then
# beside OpenVDB's vdb_render on MM5 Q. Needs python3-vtk9 and xvfb (Debian); says
# so when they are missing. vdb_render (libopenvdb-tools) runs when it and
# python3-openvdb are installed.
set -eu
B=${B:-build}
SHARED=${SHARED:-../shared}
SPECIES=${SPECIES:-Q}
if ! /usr/bin/python3 -c 'import vtk' 2>/dev/null || ! command -v xvfb-run >/dev/null; then
    echo "bench_vtk: needs python3-vtk9 and xvfb: apt-get install -y python3-vtk9 xvfb" >&2
    exit 1
fi
W=$(mktemp -d "${TMPDIR:-/tmp}/vsv-bench-vtk.XXXXXX")
trap 'rm -rf "$W"' EXIT
# the suite: Vesuvius beside VTK on six volumes at matched settings (bench_peers.py)
xvfb-run -a /usr/bin/python3 bench/bench_peers.py --build "$B" --shared "$SHARED"
if command -v vdb_render >/dev/null && /usr/bin/python3 -c 'import pyopenvdb' 2>/dev/null; then
    # OpenVDB's vdb_render on Q alone: bench_render writes the decoded volume and the camera
    "$B/vsv-convert" -q "$SHARED/data/mm5/run1/MMOUT_DOMAIN1" -o "$W/mm5.vsv"
    VSV_BENCH_NO_TERRAIN=1 "$B/bench/bench_render" "$W/mm5.vsv" 3 "$SPECIES" > "$W/ours.txt"
    # one process per frame: the time is the one vdb_render reports for ray-tracing
    # (reading the file and writing the image are outside it); one shadow-ray
    # sample per primary sample (-shadowstep far beyond the volume), no density or
    # transmittance cutoff (as the other two: Q never becomes opaque)
    printf '\nOpenVDB vdb_render (volume ray-marcher, cubic voxels of 32 km, step 0.5 voxel), 512x512, 8 orbiting views:\n\n'
    GEO=$(grep '^geometry' "$W/ours.txt")
    /usr/bin/python3 bench/vdb_uniform.py "$W/mm5.vsv.raw" "$GEO" "$W/q.vdb" "$SPECIES"
    set -- $GEO
    CX=$(awk "BEGIN{print $5 + $8 * ($2 - 1) / 2}") CY=$(awk "BEGIN{print $6 + $9 * ($3 - 1) / 2}")
    CZ=$(awk "BEGIN{print $7 + 0.3 * $8 * ($4 - 1)}")
    R=$(awk "BEGIN{print sqrt((${11} - $CX)^2 + (${12} - $CY)^2 + (${13} - $CZ)^2)}")
    printf '| image | threads | frames/s | ms/frame |\n|---|---|---|---|\n'
    for cpus in 1 2; do
        total=0
        for k in 0 1 2 3 4 5 6 7; do
            EYE=$(awk "BEGIN{a = (225 + 45 * $k) * 3.14159265358979 / 180; e = 30 * 3.14159265358979 / 180;
                printf \"%.2f,%.2f,%.2f\", $CX + $R * sin(a) * cos(e), $CY + $R * cos(a) * cos(e), $CZ + $R * sin(e)}")
            s=$(vdb_render "$W/q.vdb" "$W/v.png" -res 512x512 -v -cpus $cpus -cutoff 1e-12 -shadowstep 1000 \
                -step 0.5 -fov 35 -translate "$EYE" -lookat "$CX,$CY,$CZ" -up 0,0,1 -absorb 20,20,20 \
                -scatter 20,20,20 2>&1 | grep 'completed in' | tail -1 | sed 's/.*completed in \([0-9.e+-]*\) sec.*/\1/')
            total=$(awk "BEGIN{print $total + $s}")
        done
        awk "BEGIN{t = $total / 8; printf \"| 512x512 | %d | %.2f | %.0f |\\n\", $cpus, 1 / t, 1000 * t}"
    done
fi
