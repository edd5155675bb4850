#!/bin/sh
# cli_play_annotate.sh — vsv-play's screenshots are annotated as vsv-render's
# frames are (issue 20): by default they carry the time (text top left), a
# colour bar per species (bottom right) and the exaggeration (bottom left),
# and equal vsv-render's annotated frame of the same view; --annotate picks
# the parts, --no-annotate gives the bare picture (vsv-render's bare frame);
# neither carries the player's status lines. In a real window under Xvfb.
B=${B:-build}
T=$(mktemp -d "${TMPDIR:-/tmp}/vsv-play-annotate.XXXXXX")
trap 'rm -rf "$T"' EXIT
. tests/cli_lib.sh
if [ "${VIEWER:-1}" != 1 ]; then
    echo "(vsv-play not built: viewer tests skipped)"
    exit 0
fi
"$B/vsv-convert" -q samples/mm5/MMOUT_DOMAIN1_CROP -o "$T/s.vsv" --vars Q,CLW,SNOW
P="$B/vsv-play $T/s.vsv --size 480x320 --species CLW,SNOW"
expect "vsv-play --annotate with an unknown part exits 2" 2 $P --annotate time,compass
has "... naming the parts (as vsv-render)" "$T/err" "time, bars, exaggeration, scale, graticule, outlines"
"$B/vsv-play" --help > "$T/help"
has "vsv-play --help names --no-annotate" "$T/help" "--no-annotate"
has "vsv-play --help names --annotate" "$T/help" "--annotate PARTS"
if ! command -v xvfb-run > /dev/null || ! /usr/bin/python3 -c "import numpy, PIL" 2> /dev/null; then
    pass "vsv-play annotation: skipped (no xvfb-run or numpy/PIL)"
    exit 0
fi
# shot NAME [OPTIONS]: a screenshot of step 3 in the oblique view
shot() {
    name=$1; shift
    printf '0.2 seek 3\n0.3 screenshot %s\n0.4 quit\n' "$T/p_$name.png" > "$T/$name.script"
    ASAN_OPTIONS=${ASAN_OPTIONS:+$ASAN_OPTIONS:}detect_leaks=0 \
    expect "vsv-play screenshot, $name (Xvfb)" 0 \
        xvfb-run -a -s "-screen 0 1024x768x24" $P -q --script "$T/$name.script" "$@"
}
shot ann
shot bare --no-annotate
shot time --annotate time
R="$B/vsv-render -q $T/s.vsv -t 3 -r shearwarp --size 480x320 --species CLW,SNOW"
$R -o "$T/r_ann.png"
$R --no-annotate -o "$T/r_bare.png"
I="/usr/bin/python3 tests/imgregion.py"

# the parts, where vsv-render puts them (boxes in fractions of the frame)
n=$($I text "$T/p_ann.png" "$T/p_bare.png" 0 0 0.6 0.2)
[ "$n" -ge 300 ] && pass "the screenshot carries the time and run (top left: $n text pixels)" ||
    fail "the screenshot carries the time and run" "$n text pixels top left (want >= 300)"
n=$($I bar "$T/p_ann.png" 0.5 0.5 1 1)
[ "$n" -ge 110 ] && pass "the screenshot carries a colour bar (bottom right: a ramp $n pixels long)" ||
    fail "the screenshot carries a colour bar" "longest ramp bottom right $n pixels (want >= 110)"
n=$($I text "$T/p_ann.png" "$T/p_bare.png" 0.5 0.6 1 1)
[ "$n" -ge 100 ] && pass "... labelled: name, units, range ($n text pixels)" ||
    fail "... labelled: name, units, range" "$n text pixels bottom right (want >= 100)"
n=$($I text "$T/p_ann.png" "$T/p_bare.png" 0 0.75 0.35 1)
[ "$n" -ge 100 ] && pass "the screenshot carries the exaggeration and scale (bottom left: $n text pixels)" ||
    fail "the screenshot carries the exaggeration and scale" "$n text pixels bottom left (want >= 100)"
# the same picture as vsv-render's, annotated or bare
set -- $($I diff "$T/p_ann.png" "$T/r_ann.png")
[ "$1" -le 2 ] && pass "the annotated screenshot is vsv-render's annotated frame ($2 pixels differ, by <= $1/255)" ||
    fail "the annotated screenshot is vsv-render's annotated frame" "$2 pixels differ, by up to $1/255"
set -- $($I diff "$T/p_bare.png" "$T/r_bare.png")
[ "$1" -le 2 ] && pass "--no-annotate: the bare picture, vsv-render's bare frame ($2 pixels differ, by <= $1/255)" ||
    fail "--no-annotate: the bare picture, vsv-render's bare frame" "$2 pixels differ, by up to $1/255"
n=$($I bar "$T/p_bare.png" 0.5 0.5 1 1)
[ "$n" -eq 0 ] && pass "--no-annotate: no colour bar" || fail "--no-annotate: no colour bar" "a ramp $n pixels long"
# --annotate time: the time alone
n=$($I text "$T/p_time.png" "$T/p_bare.png" 0 0 0.6 0.2)
[ "$n" -ge 300 ] && pass "--annotate time: the time is there ($n text pixels)" ||
    fail "--annotate time: the time is there" "$n text pixels top left"
n=$($I bar "$T/p_time.png" 0.5 0.5 1 1)
m=$($I text "$T/p_time.png" "$T/p_bare.png" 0 0.75 0.35 1)
[ "$n" -eq 0 ] && [ "$m" -eq 0 ] && pass "--annotate time: no colour bar, exaggeration or scale" ||
    fail "--annotate time: no colour bar, exaggeration or scale" "ramp $n pixels, $m text pixels bottom left"

# the GPU raycaster (issue 31): vsv-play --renderer gl's screenshot is
# vsv-render --renderer gl's frame (the same shader, the window's context
# against a headless one), annotated and bare
shot gl --renderer gl -r gl
shot glbare --renderer gl --no-annotate
$R -r gl -o "$T/r_gl.png" 2> "$T/err" && $R -r gl --no-annotate -o "$T/r_glbare.png" 2>> "$T/err" ||
    fail "vsv-render --renderer gl renders the same view" "$(head -c 300 "$T/err")"
set -- $($I diff "$T/p_gl.png" "$T/r_gl.png")
[ "$1" -le 2 ] && pass "--renderer gl: the screenshot is vsv-render --renderer gl's frame ($2 pixels differ, by <= $1/255)" ||
    fail "--renderer gl: the screenshot is vsv-render --renderer gl's frame" "$2 pixels differ, by up to $1/255"
set -- $($I diff "$T/p_glbare.png" "$T/r_glbare.png")
[ "$1" -le 2 ] && pass "--renderer gl --no-annotate: vsv-render --renderer gl's bare frame ($2 pixels differ, by <= $1/255)" ||
    fail "--renderer gl --no-annotate: vsv-render --renderer gl's bare frame" "$2 pixels differ, by up to $1/255"
