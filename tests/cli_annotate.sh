#!/bin/sh
# cli_annotate.sh — vsv-render's annotation (issue 20): on by default,
# --no-annotate gives the bare frame that vsv-render drew before annotation
# (tests/golden/bare-160x120.png, written by the tool of commit dc7c091 from
# the same sample; written again when the raycaster's last partial step came
# to count by its length: 322 pixels changed, by at most 6/255, 17 by more
# than 2), --annotate picks parts, a missing font or GSHHG data set
# is a note and not a failure, the GrADS global lat/lon sample gets its
# coastlines, and grids of extreme spacing render.
B=${B:-build}
SHARED=${SHARED:-../shared}
T=$(mktemp -d "${TMPDIR:-/tmp}/vsv-annotate.XXXXXX")
trap 'rm -rf "$T"' EXIT
. tests/cli_lib.sh

# pixels: the largest channel difference of two PNGs, and how many pixels differ
pixdiff() {
    /usr/bin/python3 -c "
import sys, numpy as np
from PIL import Image
a = np.asarray(Image.open(sys.argv[1]).convert('RGB'), dtype=np.int32)
b = np.asarray(Image.open(sys.argv[2]).convert('RGB'), dtype=np.int32)
d = np.abs(a - b).max(axis=2) if a.shape == b.shape else np.full((1, 1), 999)
print(int(d.max()), int((d > 0).sum()))" "$1" "$2"
}

"$B/vsv-convert" --vertical even -q --vars CLW,SNOW,ICE samples/mm5/MMOUT_DOMAIN1_CROP -o "$T/s.vsv"
R="$B/vsv-render -q $T/s.vsv --size 160x120"
expect "--no-annotate renders" 0 $R --no-annotate -o "$T/bare.png"
set -- $(pixdiff "$T/bare.png" tests/golden/bare-160x120.png)
if [ "$1" -le 2 ]; then
    pass "--no-annotate gives the frame of the tool before annotation ($2 pixels differ, by at most $1/255)"
else
    fail "--no-annotate gives the frame of the tool before annotation" "pixels differ by up to $1/255 ($2 pixels)"
fi
expect "annotated by default" 0 $R -o "$T/ann.png"
set -- $(pixdiff "$T/bare.png" "$T/ann.png")
if [ "$2" -gt 1500 ]; then pass "the default frame carries annotation ($2 pixels changed)"; else
    fail "the default frame carries annotation" "$2 pixels changed"; fi
expect "--annotate time,bars" 0 $R --annotate time,bars -o "$T/tb.png"
set -- $(pixdiff "$T/ann.png" "$T/tb.png")
if [ "$2" -gt 0 ]; then pass "--annotate time,bars leaves out the other parts"; else
    fail "--annotate time,bars leaves out the other parts" "same image as all parts"; fi
expect "--annotate with an unknown part exits 2" 2 $R --annotate time,compass -o "$T/x.png"
has "... naming the parts" "$T/err" "time, bars, exaggeration, scale, graticule, outlines"
expect "--annotate '' exits 2" 2 $R --annotate "" -o "$T/x.png"

# no font: frames without text, said once; no GSHHG files: no outlines, said
VSV_FONT=/nonexistent/font.ttf expect "a missing font is a note, not a failure" 0 $R -o "$T/nofont.png"
has "... naming the font" "$T/err" "note: /nonexistent/font.ttf: no such font"
VSV_GSHHG=$T/none expect "missing GSHHG files are a note, not a failure" 0 $R -o "$T/nomap.png"
has "... naming the package" "$T/err" "apt-get install gmt-gshhg-low"
set -- $(pixdiff "$T/nomap.png" "$T/ann.png")
if [ "$2" -gt 0 ]; then pass "without GSHHG the outlines are left out"; else fail "without GSHHG the outlines are left out" "same image"; fi

# every kind of frame carries the time (text top left), a colour bar (a ramp
# bottom right) and the exaggeration (text bottom left), and --no-annotate
# none of them: PNG, a movie's frame (decoded by ffmpeg) and EXR (its colour
# channels, decoded by ffmpeg); tests/imgregion.py finds them
I="/usr/bin/python3 tests/imgregion.py"
# parts KIND ANNOTATED.png BARE.png SLACK
parts() {
    t=$($I text "$2" "$3" 0 0 0.6 0.2) b=$($I bar "$2" 0.5 0.5 1 1 "$4") b0=$($I bar "$3" 0.5 0.5 1 1 "$4")
    x=$($I text "$2" "$3" 0 0.75 0.35 1) t0=$($I text "$3" "$3" 0 0 1 1)
    [ "${t:-0}" -ge 150 ] && pass "$1: the time (top left, $t text pixels)" || fail "$1: the time" "$t text pixels top left (want >= 150)"
    [ "${b:-0}" -ge 90 ] && pass "$1: a colour bar (bottom right, a ramp $b pixels long)" ||
        fail "$1: a colour bar" "longest ramp bottom right ${b:-?} pixels (want >= 90)"
    [ "${x:-0}" -ge 100 ] && pass "$1: the exaggeration (bottom left, $x text pixels)" ||
        fail "$1: the exaggeration" "$x text pixels bottom left (want >= 100)"
    [ "$b0" = 0 ] && [ "$t0" = 0 ] && pass "$1, --no-annotate: no text, no colour bar" ||
        fail "$1, --no-annotate: no text, no colour bar" "${t0:-?} text pixels, a ramp ${b0:-?} long"
}
R4="$B/vsv-render -q $T/s.vsv --size 400x300"
$R4 -o "$T/f.png" && $R4 --no-annotate -o "$T/f0.png"
parts "PNG" "$T/f.png" "$T/f0.png" 1
if command -v ffmpeg > /dev/null; then
    $R4 --times 2:3 --movie "$T/m.mp4" && $R4 --times 2:3 --no-annotate --movie "$T/m0.mp4"
    $R4 -o "$T/f.exr" && $R4 --no-annotate -o "$T/f0.exr"
    for f in m m0; do ffmpeg -v error -y -i "$T/$f.mp4" -vf 'select=eq(n\,1)' -frames:v 1 "$T/$f-1.png"; done
    for f in f f0; do ffmpeg -v error -y -i "$T/$f.exr" "$T/$f-exr.png"; done
    parts "movie, frame 2" "$T/m-1.png" "$T/m0-1.png" 6
    parts "EXR" "$T/f-exr.png" "$T/f0-exr.png" 1
else
    echo "(no ffmpeg: the movie's and EXR's annotation are not checked)"
fi

has "--help names --no-annotate" "$(sh -c "$B/vsv-render --help > $T/help; echo $T/help")" "--no-annotate"

# the GrADS global lat/lon sample: coastlines over the globe
CTL=$(data grads/model.ctl)
if [ -f "$CTL" ] && [ -f /usr/share/gmt-gshhg/binned_GSHHS_c.nc ]; then
    "$B/vsv-convert" --vertical even -q "$CTL" -o "$T/g.vsv"
    G="$B/vsv-render -q $T/g.vsv --view plan --size 400x300"
    expect "model.ctl renders in plan view" 0 $G --no-annotate -o "$T/g-bare.png"
    expect "... with its outlines" 0 $G --annotate outlines -o "$T/g-coast.png"
    set -- $(pixdiff "$T/g-bare.png" "$T/g-coast.png")
    if [ "$2" -gt 1500 ]; then pass "coastlines drawn over the globe ($2 pixels)"; else
        fail "coastlines drawn over the globe" "$2 pixels changed"; fi
    set -- $($I globe "$T/g-bare.png" "$T/g-coast.png")
    if awk "BEGIN { exit !(${1:-0} >= 0.99 && ${2:-1} <= 0.001) }"; then
        pass "the data cover the globe's box, nothing outside it ($1 / $2 of the pixels)"
    else
        fail "the data cover the globe's box, nothing outside it" "$1 of the box, $2 outside"
    fi
    [ "${3:-0}" -ge 3 ] && [ "${4:-1}" = 0 ] &&
        pass "coast pixels at the Cape of Good Hope, New York, Sydney, Cape Horn (>= $3), none at sea" ||
        fail "coast pixels at four coast points, none at sea" "fewest at a coast point ${3:-?}, most at sea ${4:-?}"
else
    echo "(GrADS sample or GSHHG absent: the global coastline check is skipped)"
fi

# grids of extreme spacing, written by the Python module (issue 33 item 9):
# cells of 1 mm by 1000 km once made the outlines sample every coast segment
# 100,000 times (74 s for 160 x 120 pixels), a curtain slice take 10^10
# values, and a curtain across a grid 12 mm wide was "does not cross the
# grid"; now the work is bounded by the image and the cells crossed
# (tests/test_annotate.c and test_light.c count it)
if [ -n "${PYMOD:-}" ] && [ -z "${PY_MISSING:-}" ]; then
    for c in 1e-3,1e6,1e-3:lon=-97 1e6,1e-3,1e-3:lat=20; do
        sp=${c%%:*}
        PYTHONPATH="$B/python" "${PYTHON:-/usr/bin/python3}" - "$T/x.vsv" "$sp" <<'PY'
import sys
import numpy as np
import vesuvius
nx, ny, nz = 16, 12, 4
sp = tuple(float(v) for v in sys.argv[2].split(","))
rs = np.random.RandomState(1)
vesuvius.write(sys.argv[1], {"nx": nx, "ny": ny, "nz": nz, "origin": (0, 0, 0), "spacing": sp}, [0],
               {"O3": rs.rand(1, nz, ny, nx).astype(np.float32)}, terrain=(rs.rand(ny, nx) * 2e-3).astype(np.float32),
               projection={"kind": "lcc", "lat0": 38, "lon0": -97, "lat1": 33, "lat2": 50, "radius": 6370000})
PY
        expect "spacing $sp: an annotated frame with a curtain (${c#*:}) renders" 0 \
            "$B/vsv-render" -q "$T/x.vsv" --size 160x120 --slice "${c#*:}" -o "$T/x.png"
        expect "spacing $sp: the plan view renders" 0 "$B/vsv-render" -q "$T/x.vsv" --size 160x120 --view plan -o "$T/x.png"
    done
fi
