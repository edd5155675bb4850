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
D=$TESTDATA
R="$SHARED/data/mm5/run1"

# the real CAMx lateral boundary file is refused as what it is (it was
# refused as a file whose size "does not divide into hours")
if [ -f "$D/camx/test.lateral_boundary" ]; then
    expect "a CAMx BOUNDARY file is refused" 1 "$B/vsv-extract" --list "$D/camx/test.lateral_boundary"
    has "and says why" "$T/err" "test.lateral_boundary: a CAMx lateral boundary file (BOUNDARY): values on the domain's four edges, not a 3-D grid"
fi

# CAMx met, land use and point source files are named as what they are (they
# were "not an MM5 v3 file, nor another format Vesuvius reads")
for f in wind:"a CAMx wind file, with no grid of its own: read beside a CAMx average file (--met DIR)" \
    height_pressure:"a CAMx met file (height/pressure, temperature, humidity or diffusivity), with no grid" \
    cloud_rain:"a CAMx cloud/rain file, with" landuse:"a CAMx land use file, with" \
    point_source:"a CAMx point source file (PTSOURCE): emissions at stacks, not a 3-D grid"; do
    [ -f "$D/camx/test.${f%%:*}" ] || continue
    expect "vsv-info on test.${f%%:*} exits 1" 1 "$B/vsv-info" "$D/camx/test.${f%%:*}"
    has "... naming it" "$T/err" "test.${f%%:*}: not a .vsv file; ${f#*:}"
done

if ! absent "MM5 REGRID, BDYOUT and LOWBDY files" mm5/run1/REGRID_DOMAIN1; then
    expect "vsv-info on REGRID" 0 "$B/vsv-info" "$R/REGRID_DOMAIN1"
    has "... no start clause where the header has none (it said 'start unknown')" "$T/out" "(REGRID output, domain 1, 143 x 208 dot points, 32 km grid); 1 big header"
    expect "vsv-extract --list on REGRID" 0 "$B/vsv-extract" --list "$R/REGRID_DOMAIN1"
    has "REGRID T is a default volume on 23 levels" "$T/out" "T          YXP C        23 K                Cross point temperature  [default]"
    has "REGRID 2-D fields say so" "$T/out" "(2-D)"
    expect "REGRID_DOMAIN1 converts" 0 "$B/vsv-convert" --vertical even -q "$R/REGRID_DOMAIN1" -o "$T/regrid.vsv"
    "$B/vsv-info" --json "$T/regrid.vsv" > "$T/regrid.json"
    if /usr/bin/python3 - "$T/regrid.json" <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
# U and V, and the wind stored from them (horizontal: REGRID has no W)
assert [s["name"] for s in d["species"]] == ["T", "U", "V", "RH", "H", "wind_east", "wind_north"], d["species"]
assert d["grid"]["vertical"]["kind"] == "even" and len(d["times"]) == 2
assert 190 < d["species"][0]["min"] < d["species"][0]["max"] < 310
PY
    then pass "REGRID .vsv: T U V RH H and the wind on even heights, 2 times"; else fail "REGRID .vsv: T U V RH H and the wind on even heights, 2 times" "see above"; fi
    # native levels: each column's own heights (H), the surface level at the
    # ground, the levels under it (1000-825 hPa at Denver) empty, squeezed 1 cm apart
    expect "REGRID on native levels converts" 0 "$B/vsv-convert" -q --vars T "$R/REGRID_DOMAIN1" -o "$T/regrid-n.vsv"
    expect "... vsv-info" 0 "$B/vsv-info" "$T/regrid-n.vsv"
    has "... per-column heights stored" "$T/out" "per-column heights stored, 1 record"
    expect "... a profile at Denver" 0 "$B/vsv-query" "$T/regrid-n.vsv" --profile 40,-105 -t 0 --csv
    if awk -F, 'NR == 2 { ok = $7 > 1720 && $7 < 1730 && $8 > 270 } NR >= 3 && NR <= 9 { ok = ok && $8 == "NaN" && $7 - prev > 0.005 && $7 - prev < 0.015 }
        NR == 10 { ok = ok && $7 > 2020 && $7 < 2026 && $8 > 270 } { prev = $7 } END { exit !ok }' "$T/out"; then
        pass "... the ground at 1727 m, 7 levels under it empty, 2023 m next"
    else
        fail "... the ground at 1727 m, 7 levels under it empty, 2023 m next" "$(sed -n '1,10p' "$T/out" | tr '\n' ' ')"
    fi
    expect "vsv-extract --list on BDYOUT" 0 "$B/vsv-extract" --list "$R/BDYOUT_DOMAIN1"
    has "BDYOUT slabs named as not volumes" "$T/out" "UEB        YSB D        15 kPa m/s          U-component of velocity          east boundary  (boundary slab, not a volume)"
    expect "vsv-info on BDYOUT" 0 "$B/vsv-info" "$R/BDYOUT_DOMAIN1"
    has "vsv-info BDYOUT: program and slabs" "$T/out" "48 boundary-slab records (YSB XSB YWB XWB): lateral boundary values, not volumes"
    expect "BDYOUT does not convert" 1 "$B/vsv-convert" --vertical even "$R/BDYOUT_DOMAIN1" -o "$T/bdy.vsv"
    has "BDYOUT: why is named" "$T/err" "no field of this MM5 v3 file is a volume on the 3-D grid (boundary slab"
    expect "vsv-info on LOWBDY" 0 "$B/vsv-info" "$R/LOWBDY_DOMAIN1"
    has "vsv-info LOWBDY: its fields" "$T/out" "TSEASFC"
    expect "vsv-extract --list on LOWBDY" 0 "$B/vsv-extract" --list "$R/LOWBDY_DOMAIN1"
    has "LOWBDY 2-D fields say so" "$T/out" "RES TEMP   YX C          0 K                Temperature of the infinite reservoir  (2-D)"
fi
expect "wrf_cropped.nc converts by default" 0 "$B/vsv-convert" --vertical even -q "$D/wrf/wrf_cropped.nc" -o "$T/wrfc.vsv"
"$B/vsv-info" -f species.0.name "$T/wrfc.vsv" > "$T/out"
has "wrf_cropped.nc: QVAPOR" "$T/out" "QVAPOR"

# --proj needs its parameters; they need --proj; options for another format
C="$D/camx/test.uamiv"
expect "--proj lcc without parameters exits 2" 2 "$B/vsv-convert" --vertical even --proj lcc "$C" -o "$T/p.vsv"
has "--proj names what it needs" "$T/err" "--proj lcc needs --lat0 --lon0 --lat1"
if [ ! -e "$T/p.vsv" ]; then pass "nothing written after --proj lcc alone"; else fail "nothing written after --proj lcc alone" "exists"; fi
expect "--lat1 without --proj exits 2" 2 "$B/vsv-extract" --vertical even --lat1 33 "$C"
expect "--proj with an unknown name exits 2" 2 "$B/vsv-convert" --proj utm "$C" -o "$T/p.vsv"
has "and lists the projections (not 'a vertical-grid option')" "$T/err" "vsv-convert: --proj utm: expected latlon, lcc, pstereo, mercator, tmerc, albers"
expect "--lat0 with no number exits 2" 2 "$B/vsv-extract" --proj lcc --lat0 north "$C"
has "and names the option" "$T/err" "vsv-extract: --lat0 north: expected a latitude, degrees from -90 to 90"
expect "--nz 0 exits 2" 2 "$B/vsv-convert" --nz 0 "$C" -o "$T/p.vsv"
has "and says the range" "$T/err" "--nz 0: expected a whole number of levels from 1 to 4096"
expect "--proj lcc with its parameters converts" 0 "$B/vsv-convert" --vertical even -q --proj lcc --lat0 40 --lon0 -97 --lat1 33 --lat2 45 "$C" -o "$T/p.vsv"
expect "--heights on an MM5 file exits 1" 1 "$B/vsv-convert" --vertical even --heights "$D/camx/test.height_pressure" samples/mm5/MMOUT_DOMAIN1_CROP -o "$T/h.vsv"
has "--heights is named as CAMx-only" "$T/err" "--heights is for CAMx files; this is a MM5 v3 file"

# vsv-render: the image format is the extension's
"$B/vsv-convert" --vertical even -q --vars CLW samples/mm5/MMOUT_DOMAIN1_CROP -o "$T/s.vsv"
expect "vsv-render -o x.jpg exits 2" 2 "$B/vsv-render" "$T/s.vsv" -o "$T/x.jpg" --size 32x24
has "the extension is named" "$T/err" "the image format comes from the extension: .png or .exr"
if [ ! -e "$T/x.jpg" ]; then pass "no .jpg of PNG bytes"; else fail "no .jpg of PNG bytes" "exists"; fi
expect "vsv-render -o x.EXR works" 0 "$B/vsv-render" -q "$T/s.vsv" -o "$T/x.EXR" --size 32x24
printf 'species CLW\ncolourmap hot\n' > "$T/bad.tf"
expect "an unknown transfer-function key exits 1" 1 "$B/vsv-render" "$T/s.vsv" -o "$T/y.png" --tf "$T/bad.tf"
has "the unknown key is named" "$T/err" "unknown key 'colourmap'"
printf 'specie CLW\ncolormap hot\n' > "$T/bad2.tf"
expect "a line outside any species block exits 1" 1 "$B/vsv-render" "$T/s.vsv" -o "$T/y.png" --tf "$T/bad2.tf"
has "the stray line is named" "$T/err" "line 1: 'specie' before any 'species NAME' line"

# GrADS OPTIONS: byteswapped and 365_day_calendar honoured, unknown refused
G="$D/grads"
if [ -f "$G/model.ctl" ] && /usr/bin/python3 - "$G" "$T" <<'PY'
import sys, numpy as np
g, t = sys.argv[1], sys.argv[2]
np.fromfile(g + "/model.dat", "<f4").astype(">f4").tofile(t + "/swapped.dat")
ctl = open(g + "/model.ctl").read().replace("^model.dat", "^swapped.dat")
open(t + "/swapped.ctl", "w").write(ctl.replace("OPTIONS little_endian", "OPTIONS byteswapped"))
open(t + "/cal.ctl", "w").write(ctl.replace("OPTIONS little_endian", "OPTIONS byteswapped 365_day_calendar").replace("02JAN1987", "27FEB1988"))
open(t + "/unk.ctl", "w").write(ctl.replace("OPTIONS little_endian", "OPTIONS little_endian frobnicate"))
PY
then
    "$B/vsv-extract" --vertical even --vars T "$G/model.ctl" | "$B/vsv-pack" -q --codec none -o "$T/g1.vsv"
    "$B/vsv-extract" --vertical even --vars T "$T/swapped.ctl" | "$B/vsv-pack" -q --codec none -o "$T/g2.vsv"
    "$B/vsv-info" -f species.0.max "$T/g1.vsv" > "$T/m1"
    "$B/vsv-info" -f species.0.max "$T/g2.vsv" > "$T/m2"
    if cmp -s "$T/m1" "$T/m2" && grep -q '^303' "$T/m1"; then pass "OPTIONS byteswapped: a big-endian copy reads the same T"; else fail "OPTIONS byteswapped: a big-endian copy reads the same T" "$(cat "$T/m1") vs $(cat "$T/m2")"; fi
    expect "OPTIONS 365_day_calendar" 0 "$B/vsv-extract" --list "$T/cal.ctl"
    has "no 29 February in a 365-day calendar" "$T/out" "1988-02-28T00:00:00Z 1988-03-01T00:00:00Z"
    expect "an unknown OPTIONS keyword exits 1" 1 "$B/vsv-extract" --list "$T/unk.ctl"
    has "the keyword is named" "$T/err" "OPTIONS frobnicate is unknown"
fi
exit 0
