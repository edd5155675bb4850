#!/bin/sh
# cli_flow.sh — the wind drawn by vsv-render (issue 35): wind arrows on a
# plane (--barbs) of a uniform eastward wind point east in a plan view, as
# long as the scale says; a trajectory in it (--trajectory) is drawn along
# its row of pixels from the seed to where the air has gone by the frame's
# time, growing frame by frame; a file without wind and bad arguments are
# refused. Prints PASS/FAIL lines.
B=${B:-build}
PYTHON=${PYTHON:-/usr/bin/python3}
T=$(mktemp -d "${TMPDIR:-/tmp}/vsv-cli-flow.XXXXXX")
trap 'rm -rf "$T"' EXIT
. tests/cli_lib.sh

# 40 x 30 columns of 2 km centred on 40N 100W, a wind of 5 (w10: 10) m/s east, 4 hourly steps
"$B/tests/windfile" "$T/w.vsv" uniform 5 0 0 && "$B/tests/windfile" "$T/n.vsv" uniform 5 0 0 novector &&
    "$B/tests/windfile" "$T/w10.vsv" uniform 10 0 0 ||
    { fail "make the wind files" "exit $?"; exit 0; }
R="-q -s CLW --view plan --size 400x300 --no-annotate"

expect "--help names --trajectory and --barbs" 0 "$B/vsv-render" --help
has "--help: --trajectory" "$T/out" "--trajectory LAT,LON,HEIGHT[:COLOUR]"
has "--help: --barbs" "$T/out" "--barbs HEIGHT[:EVERY]"
expect "a file without wind: exit 1" 1 "$B/vsv-render" "$T/n.vsv" -o "$T/x.png" --trajectory 40,-100,3000
has "... vsv-render: FILE: no wind stored" "$T/err" "vsv-render: $T/n.vsv: no wind stored"
expect "--barbs on it too" 1 "$B/vsv-render" "$T/n.vsv" -o "$T/x.png" --barbs 2000
expect "--trajectory 40,-100: exit 2" 2 "$B/vsv-render" "$T/w.vsv" -o "$T/x.png" --trajectory 40,-100
has "... says what it expects" "$T/err" "--trajectory 40,-100: expected LAT,LON,HEIGHT[:COLOUR]"
expect "--seed-line with N 1: exit 2" 2 "$B/vsv-render" "$T/w.vsv" -o "$T/x.png" --seed-line 40,-100,1000:40,-99,1000:1
expect "--traj-for 3: exit 2 (no unit)" 2 "$B/vsv-render" "$T/w.vsv" -o "$T/x.png" --trajectory 40,-100,3000 --traj-for 3
expect "--trajectory outside the grid: exit 1" 1 "$B/vsv-render" "$T/w.vsv" -o "$T/x.png" --trajectory 50,-100,3000
has "... says so" "$T/err" "--trajectory 50,-100,3000: outside the grid"
[ -e "$T/x.png" ] && fail "no image after an error" "x.png" || pass "no image after an error"

expect "the bare plan view" 0 "$B/vsv-render" "$T/w.vsv" -o "$T/bare.png" $R -t 2
expect "--barbs 2000:4" 0 "$B/vsv-render" "$T/w10.vsv" -o "$T/barbs.png" $R -t 2 --barbs 2000:4
expect "--barbs above the grid's top: exit 1" 1 "$B/vsv-render" "$T/w10.vsv" -o "$T/x.png" $R -t 2 --barbs 2000:4 --barbs 90000
has "... naming the plane" "$T/err" "--barbs 90000: no column drawn has air at that height (above the grid's top or under the ground)"
[ -e "$T/x.png" ] && fail "... and no image" "x.png" || pass "... and no image"
expect "--tube-radius 0: exit 2" 2 "$B/vsv-render" "$T/w10.vsv" -o "$T/x.png" $R -t 2 --barbs 2000:4 --tube-radius 0
expect "--tube-radius wider than a tenth of the domain: exit 1" 1 "$B/vsv-render" "$T/w10.vsv" -o "$T/x.png" $R -t 2 --barbs 2000:4 --tube-radius 1e9
has "... saying so" "$T/err" "--tube-radius 1e+09: more than a tenth of the domain's larger side"
expect "--tube-radius 2000 draws" 0 "$B/vsv-render" "$T/w10.vsv" -o "$T/fat.png" $R -t 2 --barbs 2000:4 --tube-radius 2000
for s in 1 2; do
    expect "--trajectory from step 0, step $s" 0 "$B/vsv-render" "$T/w.vsv" -o "$T/t$s.png" $R -t $s \
        --trajectory 40,-100,3000 --traj-from 0 --traj-for 3h
done
# streamlines: the wind of the frame's step held still, the whole path drawn
# from the first frame on (a trajectory from step 0 shows nothing there)
expect "--streamlines at step 0 for 2 h of travel" 0 "$B/vsv-render" "$T/w.vsv" -o "$T/st0.png" $R -t 0 \
    --trajectory 40,-100,3000 --streamlines --traj-for 2h
expect "--seed-slice 3000:10" 0 "$B/vsv-render" "$T/w.vsv" -o "$T/ss.png" $R -t 1 --seed-slice 3000:10:cyan
expect "--seed-line 3 seeds" 0 "$B/vsv-render" "$T/w.vsv" -o "$T/sl.png" $R -t 1 \
    --seed-line 39.9,-100.1,3000:40.1,-100.1,3000:3
# the GPU raycaster stops at the same tubes (the surfaces are the CPU's)
expect "--renderer gl: paths lit, from the south-west" 0 "$B/vsv-render" "$T/w.vsv" -o "$T/gl.png" -q -s CLW \
    --size 320x240 --no-annotate --light -t 3 --seed-slice 3000:8 -r gl
expect "... and the raycaster's" 0 "$B/vsv-render" "$T/w.vsv" -o "$T/rc.png" -q -s CLW \
    --size 320x240 --no-annotate --light -t 3 --seed-slice 3000:8
d=$("$PYTHON" tests/imgregion.py diff "$T/gl.png" "$T/rc.png" 2>&1)
[ "$d" = "0 0" ] && pass "the GPU raycaster's picture is the raycaster's, pixel for pixel" ||
    fail "the GPU raycaster's picture is the raycaster's, pixel for pixel" "$d (largest difference, pixels)"
expect "--traj-from 2: nothing at step 1" 0 "$B/vsv-render" "$T/w.vsv" -o "$T/t0.png" $R -t 1 \
    --trajectory 40,-100,3000 --traj-from 2

# a plan view of the box -41..39 km x -31..29 km in 400 x 300 pixels: 204 m a
# pixel (1.02 times the tighter fit), the box's centre (-1, -1) km in the middle
if "$PYTHON" - "$T" > "$T/py" 2>&1 <<'PY'
import sys
import numpy as np
from PIL import Image
d = sys.argv[1]
img = lambda n: np.asarray(Image.open(f"{d}/{n}.png").convert("RGB"), dtype=np.int32)
bare = img("bare")
px = lambda x: (x + 1000) / 204 + 199.5
py = lambda y: 149.5 - (y + 1000) / 204
def drawn(n):
    return (np.abs(img(n) - bare).max(axis=2) > 8)
# the arrows: tails at columns 0, 4, ... (x = -40 km + 2 km i), rows j = 0, 4, ...;
# 10 m/s of the 20 m/s that spans 8 km: 4 km (19.6 pixels) east, the head's
# base (its widest) 4.7 pixels before the tip (6 radii of 0.6 x 1/300 of 80 km)
D = drawn("barbs")
bad, n = [], 0
for j in range(0, 30, 4):
    for i in range(0, 40, 4):
        tx, ty = px(-40000 + 2000 * i), py(-30000 + 2000 * j)
        x0, y0 = int(round(tx)), int(round(ty))
        if x0 < 6 or x0 + 26 >= 400 or y0 < 4 or y0 + 4 >= 300:
            continue
        win = D[y0 - 4:y0 + 5, x0 - 5:x0 + 26]
        cols = np.nonzero(win.any(axis=0))[0] + x0 - 5
        if not len(cols):
            bad.append((i, j, "none")); continue
        n += 1
        widest = x0 - 5 + int(np.argmax(win.sum(axis=0)))
        if not (-3 <= cols.max() - (tx + 19.6) <= 1 and abs(cols.min() - tx) <= 2 and widest > tx + 12):
            bad.append((i, j, tx, cols.min(), cols.max(), widest))
assert n >= 50 and not bad, ("arrows", n, bad[:4])
print(f"arrows: {n} point east, 19.6 pixels long")
# the trajectory: seeded at (0, 0) from step 0; 5 m/s for 1 h is 18 km (88.2 pixels), 2 h 36 km
for s, km in ((1, 18), (2, 36)):
    D = drawn(f"t{s}")
    ys, xs = np.nonzero(D)
    sx, sy, ex = px(0), py(0), px(km * 1000)
    # (the head's tip is a point: the last pixel whose centre it covers is up to 2 short of it)
    assert len(xs) and abs(xs.min() - sx) <= 2.5 and -2.5 <= xs.max() - ex <= 1, ("ends", s, xs.min(), xs.max(), sx, ex)
    assert np.abs(ys - sy).max() <= 4.5, ("off its row", s, np.abs(ys - sy).max())
    row = D[int(np.floor(sy)):int(np.ceil(sy)) + 1].any(axis=0)
    assert row[int(np.ceil(sx)) + 1:int(ex) - 1].all(), ("a gap along it", s)
    print(f"step {s}: from pixel {xs.min()} to {xs.max()} (want {sx:.1f} to {ex:.1f}), rows {ys.min()}..{ys.max()}")
assert not drawn("t0").any(), "a trajectory drawn before its start"
D = drawn("st0")
ys, xs = np.nonzero(D)
sx, sy, ex = px(0), py(0), px(36000)
assert len(xs) and abs(xs.min() - sx) <= 2.5 and -2.5 <= xs.max() - ex <= 1, ("streamline", xs.min(), xs.max(), sx, ex)
print(f"streamline at step 0: from pixel {xs.min()} to {xs.max()} (want {sx:.1f} to {ex:.1f})")
# seeds every 10th column from the 5th: 4 x 3 paths, each on its row from its seed
D = drawn("ss")
ys, xs = np.nonzero(D)
rows = [py(-30000 + 2000 * j) for j in (5, 15, 25)]
assert all(min(abs(y - r) for r in rows) <= 4.5 for y in ys), "a pixel off the seeds' rows"
for r in rows:
    for i in (5, 15, 25, 35):
        sx = px(-40000 + 2000 * i)
        near = D[int(r) - 1:int(r) + 3, int(sx) - 1:int(sx) + 4]
        assert near.any() and not D[int(r) - 4:int(r) + 5, int(sx) - 6:int(sx) - 2].any(), ("seed", i, r)
# three seeds along a meridian 0.2 degrees long: three rows, about 11 km apart
ys = np.nonzero(drawn("sl").any(axis=1))[0]
groups = np.split(ys, np.nonzero(np.diff(ys) > 1)[0] + 1)
mid = [g.mean() for g in groups]
assert len(groups) == 3 and all(abs((mid[k + 1] - mid[k]) * 204 - 11120) < 400 for k in range(2)), mid
print(f"seed-slice: 12 paths on 3 rows; seed-line: rows at {[round(m, 1) for m in mid]}")
PY
then pass "arrows east along the wind; the path on its row, growing with the frame ($(tr '\n' ';' < "$T/py"))"
else fail "arrows and paths where the wind takes them" "$(tail -c 600 "$T/py")"; fi
