#!/bin/sh
# bench_vtk.sh — the raycaster beside VTK's vtkFixedPointVolumeRayCastMapper on the
# same volume (one species of the converted real MM5 run), same camera, same sizes.
# Needs python3-vtk9 and xvfb (Debian); says so when they are missing.
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
"$B/vsv-convert" -q "$SHARED/data/mm5/run1/MMOUT_DOMAIN1" -o "$W/mm5.vsv"
printf 'data: MMOUT_DOMAIN1 at 3 h, species %s alone, 207x142x40; %s cores; %s\n\n' \
    "$SPECIES" "$(nproc)" "$(date -u +%Y-%m-%d)"
printf 'Vesuvius, no terrain (the work VTK does: the volume alone):\n\n'
VSV_BENCH_NO_TERRAIN=1 "$B/bench/bench_render" "$W/mm5.vsv" 3 "$SPECIES" | grep -v '^geometry'
printf '\nVesuvius with the terrain (its default picture; the ground is found again every frame as the camera moves):\n\n'
"$B/bench/bench_render" "$W/mm5.vsv" 3 "$SPECIES" > "$W/ours.txt"
grep -v '^geometry' "$W/ours.txt"
printf '\nVTK vtkFixedPointVolumeRayCastMapper (offscreen, Xvfb):\n\n'
xvfb-run -a /usr/bin/python3 bench/bench_vtk.py "$W/mm5.vsv.raw" "$(grep '^geometry' "$W/ours.txt")" 2>/dev/null
