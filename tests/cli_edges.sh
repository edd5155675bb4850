#!/bin/sh
# cli_edges.sh — conversion edges from the command line on the real files
# in ../shared/data: MM5 REGRID/BDYOUT/LOWBDY, WRF's default fields, and the
# validation of options and model files (errors named, exit 1, nothing
# written). Prints PASS/FAIL lines.
B=${B:-build}
SHARED=${SHARED:-../shared}
T=$(mktemp -d "${TMPDIR:-/tmp}/vsv-cli-edges.XXXXXX")
trap 'rm -rf "$T"' EXIT
. tests/cli_lib.sh
D="$SHARED/data"
R="$D/mm5/run1"

if [ -f "$R/REGRID_DOMAIN1" ]; then
    expect "vsv-extract --list on REGRID" 0 "$B/vsv-extract" --list "$R/REGRID_DOMAIN1"
    has "REGRID T is a default volume on 23 levels" "$T/out" "T          YXP C        23 K                Cross point temperature  [default]"
    has "REGRID 2-D fields say so" "$T/out" "(2-D)"
    expect "REGRID_DOMAIN1 converts" 0 "$B/vsv-convert" -q "$R/REGRID_DOMAIN1" -o "$T/regrid.vsv"
    "$B/vsv-info" --json "$T/regrid.vsv" > "$T/regrid.json"
    if /usr/bin/python3 - "$T/regrid.json" <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
assert [s["name"] for s in d["species"]] == ["T", "U", "V", "RH", "H"], d["species"]
assert d["grid"]["vertical"]["kind"] == "even" and len(d["times"]) == 2
assert 190 < d["species"][0]["min"] < d["species"][0]["max"] < 310
PY
    then pass "REGRID .vsv: T U V RH H on even heights, 2 times"; else fail "REGRID .vsv: T U V RH H on even heights, 2 times" "see above"; fi
    expect "vsv-extract --list on BDYOUT" 0 "$B/vsv-extract" --list "$R/BDYOUT_DOMAIN1"
    has "BDYOUT slabs named as not volumes" "$T/out" "UEB        YSB D        15 kPa m/s          U-component of velocity          east boundary  (boundary slab, not a volume)"
    expect "vsv-info on BDYOUT" 0 "$B/vsv-info" "$R/BDYOUT_DOMAIN1"
    has "vsv-info BDYOUT: program and slabs" "$T/out" "48 boundary-slab records (YSB XSB YWB XWB): lateral boundary values, not volumes"
    expect "BDYOUT does not convert" 1 "$B/vsv-convert" "$R/BDYOUT_DOMAIN1" -o "$T/bdy.vsv"
    has "BDYOUT: why is named" "$T/err" "no field of this MM5 v3 file is a volume on the 3-D grid (boundary slab"
    expect "vsv-info on LOWBDY" 0 "$B/vsv-info" "$R/LOWBDY_DOMAIN1"
    has "vsv-info LOWBDY: its fields" "$T/out" "TSEASFC"
    expect "vsv-extract --list on LOWBDY" 0 "$B/vsv-extract" --list "$R/LOWBDY_DOMAIN1"
    has "LOWBDY 2-D fields say so" "$T/out" "RES TEMP   YX C          0 K                Temperature of the infinite reservoir  (2-D)"
fi
expect "wrf_cropped.nc converts by default" 0 "$B/vsv-convert" -q "$D/wrf/wrf_cropped.nc" -o "$T/wrfc.vsv"
"$B/vsv-info" -f species.0.name "$T/wrfc.vsv" > "$T/out"
has "wrf_cropped.nc: QVAPOR" "$T/out" "QVAPOR"
exit 0
