#!/bin/sh
# bench_vtk.sh — the raycaster beside VTK's vtkFixedPointVolumeRayCastMapper on
# the suite of bench_peers.py (MM5 Q, CLW, SNOW, WRF QCLOUD, gen-plume's plume and
# haze; matched settings, interleaved rounds, PSNR and ratios printed). Needs
# python3-vtk9 and xvfb (Debian); says so when they are missing. (OpenVDB's
# vdb_render is not compared: bench/RESULTS.md says why.)
set -eu
B=${B:-build}
SHARED=${SHARED:-../shared}
if ! /usr/bin/python3 -c 'import vtk' 2>/dev/null || ! command -v xvfb-run >/dev/null; then
    echo "bench_vtk: needs python3-vtk9 and xvfb: apt-get install -y python3-vtk9 xvfb" >&2
    exit 1
fi
# the suite: Vesuvius beside VTK on six volumes at matched settings (bench_peers.py)
xvfb-run -a /usr/bin/python3 bench/bench_peers.py --build "$B" --shared "$SHARED"
