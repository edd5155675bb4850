#!/bin/sh
# cli_moves.sh — a WRF moving nest (the Katrina file, GRID_ID 2, whose SW
# corner moves from 21.80N 91.65W at 12Z to 22.80N 93.00W at 21Z) placed at
# every time: vsv-info lists the placements; a query at WRF's own 21Z
# cloud-water maximum returns WRF's value within the bound; a time series
# there says no data before the nest arrives; frames interpolated across a
# move blend the same place; the nest split into one file per time gives
# the same file; netCDF export and Python's to_xarray refuse to mix
# placements; the renderer and the player draw each step where the nest
# stands.
B=${B:-build}
SHARED=${SHARED:-../shared}
PY=${PYTHON:-/usr/bin/python3}
T=$(mktemp -d "${TMPDIR:-/tmp}/vsv-moves.XXXXXX")
trap 'rm -rf "$T"' EXIT
. tests/cli_lib.sh

absent "moving nest" wrf/katrina_ci_test_file.nc && exit 0
K=$(data wrf/katrina_ci_test_file.nc)
if ! "$PY" -c 'import netCDF4, numpy' 2> /dev/null; then
    skip "moving nest" "no python3-netcdf4"
    exit 0
fi

# WRF's own 21Z maximum of QCLOUD: level, lat, lon and value
"$PY" - "$K" > "$T/wrf" <<'EOF'
import sys, numpy, netCDF4
d = netCDF4.Dataset(sys.argv[1])
q = d["QCLOUD"][3]
k, j, i = numpy.unravel_index(numpy.argmax(q), q.shape)
print(k, float(d["XLAT"][3, j, i]), float(d["XLONG"][3, j, i]), float(q[k, j, i]), i, j)
EOF
read -r WK WLAT WLON WVAL WI WJ < "$T/wrf"

expect "the moving nest converts (native levels)" 0 "$B/vsv-convert" -q --vertical native -o "$T/n.vsv" "$K"
expect "vsv-info" 0 "$B/vsv-info" "$T/n.vsv"
has "it is format 4.0 (heights and terrain coded, the wind a vector, dense bricks Rice-coded)" "$T/out" ".vsv format 4.0"
expect "vsv-info" 0 "$B/vsv-info" "$T/n.vsv"
has "and lists 3 more placements" "$T/out" "moves       a moving nest: 3 more placements"
has "the 21Z one where WRF puts it" "$T/out" "from 2005-08-28T21:00:00Z  SW 22.803N 93.003W  (-15, +12 cells)"
"$B/vsv-info" --json "$T/n.vsv" > "$T/info.json"
BOUND=$("$PY" -c "import json,sys; d=json.load(open(sys.argv[1])); print([s['max_abs_error'] for s in d['species'] if s['name']=='QCLOUD'][0])" "$T/info.json")

expect "a profile at WRF's 21Z maximum" 0 "$B/vsv-query" "$T/n.vsv" --profile "$WLAT,$WLON" --time 3 -s QCLOUD --csv
got=$(awk -F, -v k="$WK" 'NR > 1 && $4 == k { print $2, $3, $8 }' "$T/out")
if echo "$got $WI $WJ $WVAL $BOUND" | awk '{ d = $3 - $6; if (d < 0) d = -d; exit !($1 == $4 && $2 == $5 && d <= $7) }'; then
    pass "is WRF's value in WRF's cell within the bound ($got; WRF $WI $WJ $WVAL, bound $BOUND)"
else
    fail "is WRF's value in WRF's cell within the bound" "got (i j value) $got; WRF $WI $WJ $WVAL, bound $BOUND"
fi
expect "the default (even) grid finds the point at 21Z too" 0 "$B/vsv-convert" -q -o "$T/e.vsv" "$K"
expect "(its query)" 0 "$B/vsv-query" "$T/e.vsv" --profile "$WLAT,$WLON" --time 3 -s QCLOUD
expect "a time series at the point" 0 "$B/vsv-query" "$T/n.vsv" --at "$WLAT,$WLON" -s QCLOUD --csv
if awk -F, 'NR == 2 || NR == 3 { if ($2 != -1 || tolower($8) != "nan") bad = 1 } NR == 5 { if ($2 == -1) bad = 1 } END { exit bad || NR != 5 }' "$T/out"; then
    pass "says no data before the nest reaches it, values after"
else
    fail "says no data before the nest reaches it, values after" "$(cat "$T/out")"
fi

# hourly frames: 19Z and 20Z lie between 18Z and 21Z at the same place
expect "hourly frames across the moves" 0 "$B/vsv-convert" -q --vertical native --time-res 1h -o "$T/h.vsv" "$K"
expect "(their time series)" 0 "$B/vsv-query" "$T/h.vsv" --at "$WLAT,$WLON,1783" -s QCLOUD --times 6:9 --csv
if awk -F, 'NR > 1 { v[NR - 2] = $8 } END { d = v[0] + (v[3] - v[0]) * 2 / 3 - v[2]; if (d < 0) d = -d; exit !(v[0] > 0 && v[3] > v[0] && d < 1e-7) }' "$T/out"; then
    pass "20Z is two thirds of the way from 18Z to 21Z at the same place"
else
    fail "20Z is two thirds of the way from 18Z to 21Z at the same place" "$(cat "$T/out")"
fi

# one file per time: the same placements, the same values
"$PY" - "$K" "$T" <<'EOF'
import sys, netCDF4
src = netCDF4.Dataset(sys.argv[1])
for t in range(len(src.dimensions["Time"])):
    dst = netCDF4.Dataset("%s/wrfout_d02_%d.nc" % (sys.argv[2], t), "w", format="NETCDF3_64BIT_OFFSET")
    dst.setncatts({a: src.getncattr(a) for a in src.ncattrs()})
    for n, dim in src.dimensions.items():
        dst.createDimension(n, None if n == "Time" else len(dim))
    for n, v in src.variables.items():
        o = dst.createVariable(n, v.datatype, v.dimensions)
        o.setncatts({a: v.getncattr(a) for a in v.ncattrs()})
        if v.dimensions and v.dimensions[0] == "Time":
            o[0:1] = v[t:t + 1]
        elif v.dimensions:
            o[:] = v[:]
        else:
            o.assignValue(v.getValue())
    dst.close()
EOF
expect "the nest split into a file per time converts" 0 "$B/vsv-convert" -q --vertical native -o "$T/s.vsv" \
    "$T/wrfout_d02_0.nc" "$T/wrfout_d02_1.nc" "$T/wrfout_d02_2.nc" "$T/wrfout_d02_3.nc"
"$B/vsv-info" "$T/n.vsv" | grep -A3 "^  moves" > "$T/m1"
"$B/vsv-info" "$T/s.vsv" | grep -A3 "^  moves" > "$T/m2"
[ -s "$T/m1" ] && same "with the same placements" "$T/m1" "$T/m2" || fail "with the same placements" "$(cat "$T/m2")"
"$B/vsv-query" "$T/n.vsv" --at "$WLAT,$WLON,1783" --csv > "$T/q1"
"$B/vsv-query" "$T/s.vsv" --at "$WLAT,$WLON,1783" --csv > "$T/q2"
cut -d, -f1-4,7- "$T/q1" > "$T/v1"; cut -d, -f1-4,7- "$T/q2" > "$T/v2"
same "and the same cells, heights and values at the point" "$T/v1" "$T/v2"

# on MPI ranks: the same bytes, hourly frames across the moves included
if [ -x "$B/vsv-convert-mpi" ] && command -v mpirun > /dev/null 2>&1; then (
    mpi_env # in a subshell: its slow unwinding under ASan is for the ranks only
    "$B/vsv-convert" -q --time-res 1h -o "$T/c1.vsv" "$T"/wrfout_d02_?.nc
    expect "the split nest on 2 MPI ranks, hourly" 0 $MPIRUN -np 2 "$B/vsv-convert-mpi" -q --time-res 1h \
        -o "$T/m1.vsv" "$T"/wrfout_d02_?.nc
    same "is byte for byte vsv-convert's" "$T/c1.vsv" "$T/m1.vsv"
) fi

expect "netCDF export of steps at two places is refused" 1 "$B/vsv-export" "$T/n.vsv" --netcdf "$T/all.nc"
has "saying where the grid moves" "$T/err" "the grid moves at 2005-08-28T15:00:00Z (step 1; a moving nest)"
[ -e "$T/all.nc" ] && fail "and writes nothing" "$T/all.nc exists" || pass "and writes nothing"
expect "netCDF export of one placement" 0 "$B/vsv-export" "$T/n.vsv" --netcdf "$T/21z.nc" --time 3
expect "has the 21Z corner" 0 "$PY" -c "
import sys, netCDF4
d = netCDF4.Dataset(sys.argv[1])
sys.exit(0 if abs(d['lat'][0, 0] - 22.80254) < 1e-3 and abs(d['lon'][0, 0] + 93.00261) < 1e-3 else 1)" "$T/21z.nc"

# the picture: the nest's box where it stands (plan view, no annotation):
# the 12Z and 21Z frames share the view, and the box moved west and north
for t in 0 3; do
    "$B/vsv-render" -q "$T/n.vsv" --time $t -s QCLOUD --view plan --no-annotate --size 300x300 -o "$T/r$t.png" 2> "$T/err" ||
        fail "renders step $t" "$(cat "$T/err")"
done
if "$PY" -c 'import PIL' 2> /dev/null; then
    expect "the 21Z box lies west and north of the 12Z box" 0 "$PY" -c "
import sys, numpy
from PIL import Image
def box(p):
    a = numpy.asarray(Image.open(p).convert('RGB')).astype(int)
    bg = a[0, 0]
    ys, xs = numpy.nonzero(numpy.abs(a - bg).sum(axis=2) > 30)
    return xs.min(), ys.min(), xs.max(), ys.max()
b0, b3 = box(sys.argv[1]), box(sys.argv[2])
w0, w3 = b0[2] - b0[0], b3[2] - b3[0]
sys.exit(0 if b3[0] < b0[0] and b3[1] < b0[1] and abs(w0 - w3) <= 2 else 1)" "$T/r0.png" "$T/r3.png"
fi

if [ "${VIEWER:-1}" = 1 ] && [ -x "$B/vsv-play" ] && command -v xvfb-run > /dev/null; then
    for t in 0 3; do
        printf '0.2 seek %s\n0.6 screenshot %s\n0.8 quit\n' $t "$T/p$t.png" > "$T/play$t"
        ASAN_OPTIONS=${ASAN_OPTIONS:+$ASAN_OPTIONS:}detect_leaks=0 \
        expect "vsv-play shows the nest at step $t (Xvfb)" 0 \
            xvfb-run -a -s "-screen 0 800x600x24" "$B/vsv-play" "$T/n.vsv" --size 320x240 --script "$T/play$t"
    done
    [ -s "$T/p0.png" ] && [ -s "$T/p3.png" ] && ! cmp -s "$T/p0.png" "$T/p3.png" &&
        pass "and the two places differ" || fail "and the two places differ" "screenshots missing or equal"
fi
if [ -n "${PYMOD:-}" ] && [ -z "${PY_MISSING:-}" ]; then
    PYTHONPATH="$B/python" expect "Python: the moves, a point reached later, to_xarray refused" 0 "$PY" -c "
import sys, math, vesuvius
f = vesuvius.open(sys.argv[1])
p = f.query(float(sys.argv[2]), float(sys.argv[3]), 1783.0)
v = p.values['QCLOUD']
try:
    f.to_xarray()
    sys.exit('to_xarray mixed placements')
except vesuvius.Error as e:
    assert 'moving nest' in str(e), e
ok = len(f.grid['moves']) == 3 and math.isnan(v[0]) and math.isnan(v[1]) and v[3] > 0
sys.exit(0 if ok else 'moves %s values %s' % (f.grid['moves'], v))" "$T/n.vsv" "$WLAT" "$WLON"
fi
