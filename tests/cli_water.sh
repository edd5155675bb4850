#!/bin/sh
# cli_water.sh — water on the ground from every field a WRF file may give it
# by (issue 20): the real WRF file with LU_INDEX (and ISWATER), copies of it
# without LU_INDEX (LANDMASK: 0 is water) and without LANDMASK too (XLAND: 2
# is water) draw the same plan view, pixel for pixel; a copy with none of
# the three draws the file's one water cell as land. Needs ../shared and
# nccopy (netcdf-bin).
B=${B:-build}
SHARED=${SHARED:-../shared}
T=$(mktemp -d "${TMPDIR:-/tmp}/vsv-water.XXXXXX")
trap 'rm -rf "$T"' EXIT
. tests/cli_lib.sh
W=$(data wrf/wrf_d01_allvars_cropped.nc)
absent "WRF water fields" wrf/wrf_d01_allvars_cropped.nc && exit 0
if ! command -v nccopy > /dev/null || ! command -v ncdump > /dev/null ||
    ! /usr/bin/python3 -c "import numpy, PIL" 2> /dev/null; then
    pass "WRF water fields: skipped (no nccopy or numpy/PIL)"
    exit 0
fi
vars=$(ncdump -h "$W" | sed -n '/^variables:/,/^\/\/ global/p' | awk '/^\t[a-z]+ [A-Za-z0-9_]+\(/ { sub(/\(.*/, "", $2); print $2 }')
# without NAME...: a copy of the file without those variables
without() { echo "$vars" | grep -v -x $(for v in "$@"; do printf -- '-e %s ' "$v"; done) | paste -sd, -; }
cp "$W" "$T/lu.nc"
nccopy -V "$(without LU_INDEX)" "$W" "$T/lm.nc"
nccopy -V "$(without LU_INDEX LANDMASK)" "$W" "$T/xl.nc"
nccopy -V "$(without LU_INDEX LANDMASK XLAND)" "$W" "$T/none.nc"
for f in lu lm xl none; do
    "$B/vsv-convert" -q "$T/$f.nc" --vars QCLOUD -o "$T/$f.vsv" &&
        "$B/vsv-render" -q "$T/$f.vsv" --view plan --no-annotate --size 200x160 -o "$T/$f.png" ||
        fail "$f: converts and renders" "$(cat "$T/err" 2> /dev/null)"
done
"$B/vsv-info" "$T/lm.vsv" > "$T/lm.txt"
has "without LU_INDEX the land use is LANDMASK" "$T/lm.txt" "LANDMASK"
"$B/vsv-info" "$T/xl.vsv" > "$T/xl.txt"
has "without LANDMASK too it is XLAND" "$T/xl.txt" "XLAND"
I="/usr/bin/python3 tests/imgregion.py"
for f in lm xl; do
    set -- $($I diff "$T/lu.png" "$T/$f.png")
    [ "$1" = 0 ] && pass "$f: the same water as LU_INDEX (pixel for pixel)" ||
        fail "$f: the same water as LU_INDEX" "$2 pixels differ, by up to $1/255"
done
set -- $($I diff "$T/lu.png" "$T/none.png")
[ "$2" -ge 100 ] && pass "without any, the water cell is land ($2 pixels differ)" ||
    fail "without any, the water cell is land" "$2 pixels differ"
