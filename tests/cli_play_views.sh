#!/bin/sh
# cli_play_views.sh — vsv-play's views, lighting and slices (issue 20) in a
# real window under Xvfb: each view preset (plan, south, west, oblique),
# lighting and slices switched on and off by script actions show what
# vsv-render draws with the same options (the bare screenshot compared
# pixel by pixel), and bad views and slices are refused (exit 2, as
# vsv-render refuses them).
B=${B:-build}
T=$(mktemp -d "${TMPDIR:-/tmp}/vsv-play-views.XXXXXX")
trap 'rm -rf "$T"' EXIT
. tests/cli_lib.sh
if [ "${VIEWER:-1}" != 1 ]; then
    echo "(vsv-play not built: viewer tests skipped)"
    exit 0
fi
"$B/vsv-convert" --vertical even -q samples/mm5/MMOUT_DOMAIN1_CROP -o "$T/s.vsv" --vars Q,CLW,SNOW
P="$B/vsv-play $T/s.vsv --size 480x320 --species CLW,SNOW --slice z=2000 --slice-species Q --no-annotate"
expect "vsv-play --view sideways exits 2" 2 $P --view sideways
expect "vsv-play --light=0,95 exits 2" 2 $P --light=0,95
# a slice the file cannot have is misuse in both tools (exit 2), in the same words
R0="$B/vsv-render -q $T/s.vsv -o $T/x.png --species CLW,SNOW --slice-species Q"
for bad in lat=10 z=-5 lon=200 line=40,-90:41 height=3; do
    expect "vsv-play --slice $bad exits 2" 2 $P --slice $bad
    cp "$T/err" "$T/err.play"
    expect "vsv-render --slice $bad exits 2" 2 $R0 --slice $bad
    if [ "$(head -1 "$T/err.play" | sed 's/^vsv-play: //')" = "$(head -1 "$T/err" | sed 's/^vsv-render: //')" ]; then
        pass "--slice $bad: both say the same ($(head -1 "$T/err"))"
    else
        fail "--slice $bad: both say the same" "$(head -1 "$T/err.play") / $(head -1 "$T/err")"
    fi
done
expect "vsv-play --slice lat=10 (outside the grid) exits 2" 2 $P --slice lat=10
has "and names the grid's latitudes" "$T/err" "outside the grid (latitudes"
expect "vsv-play --slice-species NOPE exits 2" 2 $P --slice-species NOPE
expect "vsv-render --slice-species NOPE exits 2" 2 $R0 --slice z=2000 --slice-species NOPE
"$B/vsv-play" --help > "$T/help"
has "vsv-play --help names --view" "$T/help" "--view NAME"
has "vsv-play --help names --slice" "$T/help" "--slice SPEC"
if ! command -v xvfb-run > /dev/null || ! /usr/bin/python3 -c "import numpy, PIL" 2> /dev/null; then
    pass "vsv-play views: skipped (no xvfb-run or numpy/PIL)"
    exit 0
fi
printf '0.2 slices\n0.3 quit\n' > "$T/noslice.script"
expect "the slices action without --slice is an error naming the line" 1 \
    $XVFB -s "-screen 0 1024x768x24" "$B/vsv-play" "$T/s.vsv" --script "$T/noslice.script"
has "and says why" "$T/err" "slices: none given"
cat > "$T/views.script" <<EOS
0.2 seek 3
0.3 view plan
0.4 screenshot $T/p_plan.png
0.5 view south
0.6 screenshot $T/p_south.png
0.7 view west
0.8 screenshot $T/p_west.png
0.9 view oblique
1.0 screenshot $T/p_oblique.png
1.1 light
1.2 screenshot $T/p_lit.png
1.3 slices
1.4 screenshot $T/p_lit_noslice.png
1.5 light off
1.6 screenshot $T/p_noslice.png
1.7 quit
EOS
ASAN_OPTIONS=${ASAN_OPTIONS:+$ASAN_OPTIONS:}detect_leaks=0 \
expect "vsv-play switches views, light and slices by script (Xvfb)" 0 \
    xvfb-run -a -s "-screen 0 1024x768x24" $P -q --script "$T/views.script"
R="$B/vsv-render -q $T/s.vsv -t 3 -r shearwarp --size 480x320 --species CLW,SNOW --no-annotate"
for v in plan south west oblique; do
    $R --view $v --slice z=2000 --slice-species Q -o "$T/r_$v.png"
done
$R --light --slice z=2000 --slice-species Q -o "$T/r_lit.png"
$R --light -o "$T/r_lit_noslice.png"
$R -o "$T/r_noslice.png"
# PSNR over the whole frame
psnr() {
    /usr/bin/python3 - "$1" "$2" << 'EOP'
import sys
import numpy as np
from PIL import Image
a, b = (np.asarray(Image.open(f).convert("RGB"), dtype=float) for f in sys.argv[1:3])
mse = ((a - b) ** 2).mean()
print("%.1f" % (99.0 if mse == 0 else 10 * np.log10(255.0 ** 2 / mse)))
EOP
}
for v in plan south west oblique lit lit_noslice noslice; do
    db=$(psnr "$T/p_$v.png" "$T/r_$v.png")
    if awk "BEGIN { exit !($db >= 40) }"; then
        pass "vsv-play's $v shows what vsv-render draws (PSNR $db dB)"
    else
        fail "vsv-play's $v shows what vsv-render draws" "PSNR $db dB"
    fi
done
for pair in "plan south" "south west" "west oblique" "oblique lit" "lit lit_noslice" "lit_noslice noslice"; do
    set -- $pair
    db=$(psnr "$T/p_$1.png" "$T/p_$2.png")
    if awk "BEGIN { exit !($db < 45) }"; then
        pass "switching $1 to $2 changes the picture (PSNR $db dB)"
    else
        fail "switching $1 to $2 changes the picture" "PSNR $db dB"
    fi
done
