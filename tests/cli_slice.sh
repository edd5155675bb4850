#!/bin/sh
# cli_slice.sh — vsv-render's lighting and slices (issue 20): --light shades
# the clouds (off by default), the same in both renderers; --slice draws
# sections in a species' colours; bad lights and slices exit 2 saying why.
B=${B:-build}
T=$(mktemp -d "${TMPDIR:-/tmp}/vsv-slice.XXXXXX")
trap 'rm -rf "$T"' EXIT
. tests/cli_lib.sh

"$B/vsv-convert" -q samples/mm5/MMOUT_DOMAIN1_CROP -o "$T/s.vsv" --vars Q,CLW,SNOW
R="$B/vsv-render -q $T/s.vsv --time 3 --size 160x120"
expect "a default render" 0 $R -o "$T/default.png"
expect "--no-light" 0 $R -o "$T/nolight.png" --no-light
same "lighting is off by default" "$T/default.png" "$T/nolight.png"
expect "--light" 0 $R -o "$T/light.png" --light
if cmp -s "$T/light.png" "$T/default.png"; then fail "--light shades the clouds" "same image"; else pass "--light shades the clouds"; fi
expect "--light=90,30" 0 $R -o "$T/east.png" --light=90,30
if cmp -s "$T/light.png" "$T/east.png"; then fail "--light=AZ,EL moves the sun" "same image"; else pass "--light=AZ,EL moves the sun"; fi
expect "--light=1,100 exits 2" 2 $R -o "$T/x.png" --light=1,100
has "--light=1,100 says why" "$T/err" "expected AZ,EL in degrees"
expect "--light=north exits 2" 2 $R -o "$T/x.png" --light=north

expect "--slice z=1500" 0 $R -o "$T/z.png" --slice z=1500 --slice-species Q
if cmp -s "$T/z.png" "$T/default.png"; then fail "--slice z=1500 draws a section" "same image"; else pass "--slice z=1500 draws a section"; fi
expect "--slice lat=48 (the crop spans 42.5-56.5 N)" 0 $R -o "$T/lat.png" --slice lat=48
expect "--slice lon=-120" 0 $R -o "$T/lon.png" --slice lon=-120
expect "--slice line=45,-125:52,-115 --renderer shearwarp" 0 $R -o "$T/line.png" --slice line=45,-125:52,-115 -r shearwarp
expect "--slice lat=10 (outside the grid) exits 2" 2 $R -o "$T/x.png" --slice lat=10
has "--slice lat=10 names the grid's latitudes" "$T/err" "outside the grid (latitudes 42.52 to 56.45)"
expect "--slice z=50000 exits 2" 2 $R -o "$T/x.png" --slice z=50000
has "--slice z=50000 names the grid's heights" "$T/err" "outside the grid's heights"
expect "--slice depth=3 exits 2" 2 $R -o "$T/x.png" --slice depth=3
expect "--slice line=45,-125 (one point) exits 2" 2 $R -o "$T/x.png" --slice line=45,-125
expect "--slice line with both ends at one point exits 2" 2 $R -o "$T/x.png" --slice line=46,-116:46,-116
has "... saying the line is too short" "$T/err" "--slice line=46,-116:46,-116: the line is shorter than half a cell"
expect "--slice-species NOPE exits 2" 2 $R -o "$T/x.png" --slice z=1500 --slice-species NOPE
expect "--slice-colormap nope exits 2" 2 $R -o "$T/x.png" --slice z=1500 --slice-colormap nope
expect "--slice-colormap magma" 0 $R -o "$T/magma.png" --slice z=1500 --slice-species Q --slice-colormap magma
if cmp -s "$T/z.png" "$T/magma.png"; then fail "--slice-colormap changes the colours" "same image"; else pass "--slice-colormap changes the colours"; fi
"$B/vsv-render" --help > "$T/help"
has "--help names --slice" "$T/help" "--slice SPEC"
has "--help names --light" "$T/help" "--light[=AZ,EL]"

# the real run: the lit clouds drawn alike by both renderers (clouds only)
MM=$(data mm5/run1/MMOUT_DOMAIN1)
if ! absent "MM5 lit renderers" mm5/run1/MMOUT_DOMAIN1 && /usr/bin/python3 -c "import numpy, PIL" 2> /dev/null; then
    "$B/vsv-convert" -q "$MM" -o "$T/m.vsv" --vars CLW,RNW,ICE,SNOW
    for r in raycast shearwarp; do
        expect "MM5 lit by the $r renderer" 0 "$B/vsv-render" -q "$T/m.vsv" --time 3 --size 400x300 --no-terrain \
            --light -r $r -o "$T/lit_$r.png"
    done
    set -- $(/usr/bin/python3 tests/imgcmp.py "$T/lit_raycast.png" "$T/lit_shearwarp.png")
    if awk "BEGIN { exit !($1 >= 90 && $2 >= 30) }"; then
        pass "MM5 lit: raycaster and shear-warp agree ($1 % covered by both, PSNR $2 dB)"
    else
        fail "MM5 lit: raycaster and shear-warp agree" "$1 % covered by both, PSNR $2 dB"
    fi
else
    pass "MM5 lit renderers: skipped (no numpy/PIL)"
fi
# --slice-range: LO < HI, or a usage error
expect "--slice-range 2:1 exits 2" 2 "$B/vsv-render" samples/mm5/MMOUT_DOMAIN1_CROP --slice z=3000 --slice-range 2:1 -o "$T/r.png"
has "... saying what it expects" "$T/err" "--slice-range 2:1: expected LO:HI with LO < HI"
