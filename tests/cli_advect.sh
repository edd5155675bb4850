#!/bin/sh
# cli_advect.sh — time interpolation along the model's winds from the
# command line (--interp advect): the pipe and vsv-convert give the same
# bytes, originals pass through exactly, frames in between differ from
# linear ones, winds from a companion file, and the errors: no winds (exit 1,
# naming them), bad method or options (exit 2). Prints PASS/FAIL lines.
B=${B:-build}
T=$(mktemp -d "${TMPDIR:-/tmp}/vsv-cli-advect.XXXXXX")
trap 'rm -rf "$T"' EXIT
. tests/cli_lib.sh
CROP=samples/mm5/MMOUT_DOMAIN1_CROP

for tool in vsv-interp vsv-convert; do
    expect "$tool --help" 0 "$B/$tool" --help
    has "$tool --help names --interp advect" "$T/out" "advect"
    expect "$tool --interp cubic exits 2" 2 "$B/$tool" --interp cubic --time-res 10m "$CROP"
done
expect "vsv-extract --help" 0 "$B/vsv-extract" --help
has "vsv-extract --help names --add-winds" "$T/out" "--add-winds"
expect "vsv-convert --interp advect without --time-res exits 2" 2 "$B/vsv-convert" --vertical even --interp advect "$CROP" -o "$T/x.vsv"
expect "vsv-interp --threads 0 exits 2" 2 "$B/vsv-interp" --time-res 10m --threads 0

# the sample carries MM5's U V W: advect works, pipe = one process
expect "vsv-convert --time-res 10m --interp advect" 0 "$B/vsv-convert" --vertical even -q --time-res 10m --interp advect "$CROP" -o "$T/adv.vsv"
"$B/vsv-extract" --vertical even --add-winds "$CROP" | "$B/vsv-interp" --time-res 10m --interp advect | "$B/vsv-pack" -q -o "$T/pipe.vsv"
same "advect: vsv-convert is byte-identical to extract --add-winds | interp | pack" "$T/adv.vsv" "$T/pipe.vsv"
"$B/vsv-info" "$T/adv.vsv" > "$T/info"
has "the file records how it was interpolated" "$T/info" "advect: semi-Lagrangian along U V W of MMOUT_DOMAIN1_CROP (MM5 v3"
has "... with its scales fitted to the outputs" "$T/info" "displacements scaled per species and band of levels"
expect "vsv-convert --interp wind (the air's own displacement)" 0 "$B/vsv-convert" --vertical even -q --time-res 10m --interp wind "$CROP" -o "$T/wind.vsv"
"$B/vsv-info" "$T/wind.vsv" > "$T/info"
has "... recorded as wind" "$T/info" "wind: semi-Lagrangian along U V W of MMOUT_DOMAIN1_CROP"
"$B/vsv-info" -f species "$T/adv.vsv" > "$T/sp"
# the grid-relative winds it used are not written; the stored (earth-relative) wind is
if grep -q '"wind\.' "$T/sp" || ! grep -q '"wind_east"' "$T/sp"; then
    fail "the grid-relative winds are not written to the file, the stored wind is" "$(grep wind "$T/sp")"
else
    pass "the grid-relative winds are not written to the file, the stored wind is"
fi
"$B/vsv-info" -f times.1 "$T/adv.vsv" > "$T/out"
has "advect: 10-minute frames" "$T/out" '1995-10-24T00:10:00Z'

# the stream: originals bit for bit, frames between them moved
"$B/vsv-extract" --vertical even --add-winds "$CROP" | "$B/vsv-interp" --time-res 10m --interp advect > "$T/adv.fs"
"$B/vsv-extract" --vertical even "$CROP" | "$B/vsv-interp" --time-res 10m > "$T/lin.fs"
if /usr/bin/python3 - "$T/adv.fs" "$T/lin.fs" <<'PY'
import sys
# 19 frames of 8 species (5 and the stored wind's 3) on 39 x 39 x 40 cells,
# then the 16-byte end marker
cells, nv, nf = 39 * 39 * 40, 8, 19
size = 16 + nv * cells * 4
a, l = (open(p, "rb").read() for p in sys.argv[1:3])
fa, fl = (x[len(x) - 16 - nf * size:len(x) - 16] for x in (a, l))
for i in range(nf):
    A, L = fa[i * size:(i + 1) * size], fl[i * size:(i + 1) * size]
    assert (A == L) == (i % 6 == 0), "frame %d: identical %s" % (i, A == L)
PY
then pass "advect: hourly outputs bit-exact, the 15 frames between differ from linear"
else fail "advect: hourly outputs bit-exact, the 15 frames between differ from linear" "see above"; fi

# no winds: an error naming what is missing
mkdir -p "$T/a"
"$B/tests/mm5crop" "$CROP" "$T/a/MMOUT_DOMAIN1_CROP" 1 1 40 40 \
    "T,Q,CLW,RNW,ICE,SNOW,PSTARCRS,TERRAIN,LAND USE,LATITCRS,LONGICRS,SIGMAH,RAIN CON,RAIN NON" 2> "$T/err"
expect "advect on a file without winds exits 1" 1 "$B/vsv-convert" --vertical even --time-res 10m --interp advect "$T/a/MMOUT_DOMAIN1_CROP" -o "$T/x.vsv"
has "... naming U and V and --winds" "$T/err" "has no 3-D U and V"
if [ -e "$T/x.vsv" ]; then fail "no output file after the error" "$T/x.vsv exists"; else pass "no output file after the error"; fi
"$B/vsv-extract" --vertical even "$T/a/MMOUT_DOMAIN1_CROP" > "$T/nowind.fs"
expect "vsv-interp --interp advect on a stream without winds exits 1" 1 "$B/vsv-interp" --time-res 10m --interp advect "$T/nowind.fs"
has "... naming wind.u and wind.v" "$T/err" "no wind.u and no wind.v"
expect "vsv-extract --add-winds on a file without winds exits 1" 1 "$B/vsv-extract" --vertical even --add-winds "$T/a/MMOUT_DOMAIN1_CROP"

# the winds from a companion file (same grid and times): the same file
expect "--winds FILE" 0 "$B/vsv-convert" --vertical even -q --time-res 10m --interp advect --winds "$CROP" "$T/a/MMOUT_DOMAIN1_CROP" -o "$T/comp.vsv"
same "advect with --winds: the same bytes as the model's own winds" "$T/comp.vsv" "$T/adv.vsv"
expect "--winds of another grid exits 1" 1 "$B/vsv-convert" --vertical even -q --time-res 10m --interp advect --winds "$(data wrf/wrf_cropped.nc)" "$CROP" -o "$T/x.vsv"
has "... saying the grids differ" "$T/err" "is not the grid of"
expect "--winds with --no-winds and without --interp advect exits 2" 2 "$B/vsv-convert" --vertical even --time-res 10m \
    --no-winds --winds "$CROP" "$CROP" -o "$T/x.vsv"
