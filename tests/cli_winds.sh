#!/bin/sh
# cli_winds.sh — the wind in the file (issue 35 item 1): vsv-convert stores
# wind_east, wind_north, wind_up (the vector "wind", SPEC.md §4 Vectors) by
# default, equal to the model's winds averaged to mass points and rotated to
# east and north within their bound (tests/wind_check.py, its own MM5 and WRF
# readers: the bundled crop, the real MM5 run and two WRF files); --no-winds;
# --time-res; --winds FILE; vsv-extract | vsv-pack the same bytes; a
# horizontal wind (GrADS, no W); vsv-info, vsv-query, Python read("wind"),
# netCDF standard names; the default picture without the wind. Prints
# PASS/FAIL/SKIP lines.
B=${B:-build}
SHARED=${SHARED:-../shared}
PY=${PYTHON:-/usr/bin/python3}
T=$(mktemp -d "${TMPDIR:-/tmp}/vsv-cli-winds.XXXXXX")
trap 'rm -rf "$T"' EXIT
. tests/cli_lib.sh
CROP=samples/mm5/MMOUT_DOMAIN1_CROP
have_py=1
PYTHONPATH="$B/python" "$PY" -c 'import numpy, vesuvius' 2> /dev/null || {
    have_py=0
    echo "  (the Python checks skipped: the Python module vesuvius or numpy is missing)"
}
check() {
    if PYTHONPATH="$B/python:tests" "$PY" tests/wind_check.py "$1" "$2" > "$T/check"; then
        sed 's/^PASS /PASS wind_check: /' "$T/check"
    else
        sed 's/^/FAIL wind_check /' "$T/check"
    fi
}

for t in vsv-convert vsv-extract; do
    expect "$t --help exits 0" 0 "$B/$t" --help
    has "$t --help lists --no-winds" "$T/out" "--no-winds"
done

# the crop: the wind stored by default, a vector, format 4.0 (3.1 with --format 3)
expect "crop: vsv-convert stores the wind by default" 0 "$B/vsv-convert" -q "$CROP" -o "$T/w.vsv"
expect "... vsv-info" 0 "$B/vsv-info" "$T/w.vsv"
has "... format 4.0" "$T/out" ".vsv format 4.0"
# the dense wind's bricks take the Rice coding; vsv-info counts them
n=$(sed -n 's/.*payloads stored, \([0-9]*\) of them Rice-coded.*/\1/p' "$T/out")
[ "${n:-0}" -gt 0 ] && pass "... vsv-info counts the Rice-coded payloads ($n)" ||
    fail "... vsv-info counts the Rice-coded payloads" "$(grep payloads "$T/out")"
expect "... --format 3" 0 "$B/vsv-convert" -q --format 3 "$CROP" -o "$T/w3.vsv"
expect "... vsv-info" 0 "$B/vsv-info" "$T/w3.vsv"
has "... format 3.1 (a vector)" "$T/out" ".vsv format 3.1"
grep -q "Rice-coded" "$T/out" && fail "... format 3: no Rice-coded payloads" "$(grep payloads "$T/out")" ||
    pass "... format 3: no Rice-coded payloads"
has "... the vector line" "$T/out" "vector      wind: wind_east wind_north wind_up (east, north, up; earth-relative)"
has "... what the model's winds were" "$T/out" "U, V on dot points (the mean of the 4 around a cross point)"
"$B/vsv-info" --json "$T/w.vsv" > "$T/w.json"
if "$PY" - "$T/w.json" << 'PY'; then
import json, sys
d = json.load(open(sys.argv[1]))
sp = {s["name"]: s for s in d["species"]}
assert d["vectors"] == {"wind": ["wind_east", "wind_north", "wind_up"]}, d["vectors"]
assert [s["name"] for s in d["species"]][-3:] == ["wind_east", "wind_north", "wind_up"]
for n in ("wind_east", "wind_north", "wind_up"):
    s = sp[n]
    assert s["units"] == "m s-1" and "earth-relative" in s["description"], s
    assert s["bits"] == 16 and s["scale"] == "linear" and s["min"] < 0 < s["max"], s
    # linear 16 bits over the data's range: the bound is half a step (plus
    # the rounding of a decoded value to float32, an ulp of the largest)
    step = (s["range_hi"] - s["range_lo"]) / 65535
    ulp = 2.0 ** -23 * max(abs(s["range_lo"]), abs(s["range_hi"]))
    assert step / 2 <= s["max_abs_error"] <= step / 2 + 2 * ulp, (n, s["max_abs_error"], step, ulp)
assert d["attributes"]["vector:wind"] == "wind_east wind_north wind_up"
PY
    pass "... --json: the vector, units m s-1, 16-bit linear over negative and positive winds, bound half a step (+ float32 rounding)"
else
    fail "... --json: the vector, units m s-1, 16-bit linear over negative and positive winds, bound half a step (+ float32 rounding)" \
        "see above"
fi
expect "... --no-winds" 0 "$B/vsv-convert" -q --no-winds "$CROP" -o "$T/n.vsv"
expect "... vsv-info" 0 "$B/vsv-info" --json "$T/n.vsv"
if grep -q wind_ "$T/out" || ! grep -q '"vectors": {}' "$T/out"; then
    fail "... --no-winds: no wind species, no vector" "$(grep wind "$T/out" | head -3)"
else
    pass "... --no-winds: no wind species, no vector"
fi
expect "... --format 3" 0 "$B/vsv-convert" -q --format 3 --no-winds "$CROP" -o "$T/n3.vsv"
expect "... vsv-info (text)" 0 "$B/vsv-info" "$T/n3.vsv"
has "... a file without a vector stays format 3.0" "$T/out" ".vsv format 3.0"
"$B/vsv-extract" "$CROP" 2> /dev/null | "$B/vsv-pack" -q -o "$T/e.vsv" 2> /dev/null
same "vsv-extract | vsv-pack stores the same wind (the same bytes)" "$T/w.vsv" "$T/e.vsv"
expect "--winds FILE (the same file as a companion)" 0 "$B/vsv-convert" -q --winds "$CROP" "$CROP" -o "$T/c.vsv"
same "... the same bytes" "$T/w.vsv" "$T/c.vsv"
expect "vsv-query prints the components as species" 0 "$B/vsv-query" "$T/w.vsv" --cell 5,5,3 --time 2 --csv
has "... wind_east" "$T/out" "wind_east"
has "... wind_up" "$T/out" "wind_up"

# against the model's own winds
if [ $have_py = 1 ]; then
    check "$CROP" "$T/w.vsv"
    if ! absent "real MM5 run" mm5/run1/MMOUT_DOMAIN1; then
        "$B/vsv-convert" -q "$(data mm5/run1/MMOUT_DOMAIN1)" -o "$T/mm5.vsv"
        check "$(data mm5/run1/MMOUT_DOMAIN1)" "$T/mm5.vsv"
    fi
    for f in wrf/wrf_d01_allvars_cropped.nc wrf/katrina_ci_test_file.nc; do
        absent "$f" "$f" && continue
        "$B/vsv-convert" -q "$(data "$f")" -o "$T/wrf.vsv"
        check "$(data "$f")" "$T/wrf.vsv"
    done
    # time interpolation: the wind a species like any other
    "$B/vsv-convert" -q -r 30m "$CROP" -o "$T/r.vsv"
    if PYTHONPATH="$B/python" "$PY" - "$T/w.vsv" "$T/r.vsv" << 'PY'; then
import sys, numpy as np, vesuvius
a, r = vesuvius.open(sys.argv[1]), vesuvius.open(sys.argv[2])
assert len(r.times) == 7, r.times
ea = {s.name: s.max_abs_error for s in a.species}
er = {s.name: s.max_abs_error for s in r.species}
for n in ("wind_east", "wind_north", "wind_up"):
    for k in range(3):  # 00:30, 01:30, 02:30: the mean of the hours around
        want = (a.read(n, k).astype(np.float64) + a.read(n, k + 1)) / 2
        d = np.abs(r.read(n, 2 * k + 1) - want).max()
        assert d <= ea[n] + er[n] + 1e-6, (n, k, d, ea[n], er[n])
PY
        pass "--time-res 30m: the wind interpolated as a species (the mean of the hours around, within both bounds)"
    else
        fail "--time-res 30m: the wind interpolated as a species" "see above"
    fi
    # Python: read("wind") and wind_speed (a rotation keeps the speed)
    "$B/vsv-convert" -q --derive wind_speed "$CROP" -o "$T/s.vsv"
    if PYTHONPATH="$B/python" "$PY" - "$T/s.vsv" << 'PY'; then
import sys, numpy as np, vesuvius
f = vesuvius.open(sys.argv[1])
assert f.vectors == {"wind": ("wind_east", "wind_north", "wind_up")}, f.vectors
w = f.read("wind", time=2)
assert w.shape == (3, 15, 39, 39) and w.dtype == np.float32, (w.shape, w.dtype)
for c, n in enumerate(("wind_east", "wind_north", "wind_up")):
    assert np.array_equal(w[c], f.read(n, 2)), n
e = {s.name: s.max_abs_error for s in f.species}
speed = np.hypot(w[0].astype(np.float64), w[1])
d = np.abs(speed - f.read("wind_speed", 2)).max()
assert d <= e["wind_speed"] + 1.5 * (e["wind_east"] + e["wind_north"]) + 1e-5, (d, e)
print("  (|hypot(east, north) - wind_speed| at most %.3g m/s)" % d)
PY
        pass "Python read(\"wind\") is (3, nz, ny, nx) float32 east, north, up; its speed is --derive wind_speed's"
    else
        fail "Python read(\"wind\") is (3, nz, ny, nx) float32 east, north, up" "see above"
    fi
fi

# a horizontal wind: GrADS model.ctl has U and V, no W
GRADS=$(data grads/model.ctl)
if ! absent "GrADS" grads/model.ctl; then
    expect "GrADS (U, V, no W): converts" 0 "$B/vsv-convert" -q "$GRADS" -o "$T/g.vsv"
    expect "... vsv-info" 0 "$B/vsv-info" "$T/g.vsv"
    has "... a horizontal vector" "$T/out" "vector      wind: wind_east wind_north (east, north: horizontal"
    if grep -q "wind_up" "$T/out"; then fail "... no wind_up stored" "$(grep wind_up "$T/out")"; else pass "... no wind_up stored"; fi
    if [ $have_py = 1 ] && PYTHONPATH="$B/python" "$PY" -c '
import sys, numpy as np, vesuvius
f = vesuvius.open(sys.argv[1])
w = f.read("wind", 0)
assert w.shape == (2, 7, 46, 72), w.shape
assert f.vectors["wind"] == ("wind_east", "wind_north", None)' "$T/g.vsv"; then
        pass "... Python read(\"wind\") is (2, nz, ny, nx)"
    elif [ $have_py = 1 ]; then
        fail "... Python read(\"wind\") is (2, nz, ny, nx)" "see above"
    fi
    # a trajectory through it has no vertical wind: "up" is no data, not 0
    expect "... a trajectory" 0 "$B/vsv-query" "$T/g.vsv" --trajectory 41.88,-87.63,500 --for 6h --csv
    [ "$(sed -n '2s/.*,//p' "$T/out")" = NaN ] && pass "... its up is NaN in CSV (no vertical wind)" ||
        fail "... its up is NaN in CSV (no vertical wind)" "$(sed -n 2p "$T/out")"
    expect "... as JSON" 0 "$B/vsv-query" "$T/g.vsv" --trajectory 41.88,-87.63,500 --for 6h --json
    has "... its up is null" "$T/out" '"up": null'
    if [ $have_py = 1 ] && PYTHONPATH="$B/python" "$PY" -c '
import sys, numpy as np, vesuvius
r = vesuvius.open(sys.argv[1]).trajectory(41.88, -87.63, 500, 0, 1)
assert np.isnan(r["up"]).all() and np.isfinite(r["east"]).all(), r["up"]' "$T/g.vsv"; then
        pass "... Python: up is NaN"
    elif [ $have_py = 1 ]; then
        fail "... Python: up is NaN" "see above"
    fi
fi

# netCDF: CF standard names
if command -v ncdump > /dev/null 2>&1; then
    expect "vsv-export --netcdf" 0 "$B/vsv-export" "$T/w.vsv" --netcdf "$T/w.nc"
    ncdump -h "$T/w.nc" > "$T/nc"
    has "... wind_east: eastward_wind" "$T/nc" 'wind_east:standard_name = "eastward_wind"'
    has "... wind_north: northward_wind" "$T/nc" 'wind_north:standard_name = "northward_wind"'
    has "... wind_up: upward_air_velocity" "$T/nc" 'wind_up:standard_name = "upward_air_velocity"'
    has "... in m s-1" "$T/nc" 'wind_up:units = "m s-1"'
else
    skip "netCDF standard names" "ncdump absent"
fi

# .vdb (drawn as volumes by Blender, Houdini): the wind's grids only when named
mkdir -p "$T/vdb"
if "$B/vsv-export" -q "$T/w.vsv" --vdb "$T/vdb/a_%d.vdb" --time 1 2> "$T/err"; then
    "$B/vsv-extract" --list "$T/vdb/a_0.vdb" > "$T/out" 2>&1
    has "vsv-export --vdb: the species' grids" "$T/out" "SNOW       XYZ"
    if grep -q wind_ "$T/out"; then fail "... but not the wind's" "$(grep wind_ "$T/out")"; else pass "... but not the wind's"; fi
    expect "... --species CLW,wind_up" 0 "$B/vsv-export" -q "$T/w.vsv" --vdb "$T/vdb/b_%d.vdb" --time 1 \
        --species CLW,wind_up
    "$B/vsv-extract" --list "$T/vdb/b_0.vdb" > "$T/out" 2>&1
    has "... writes the wind's component named" "$T/out" "wind_up    XYZ"
else
    skip "vsv-export --vdb" "$(head -c 200 "$T/err")"
fi

# the default picture leaves the wind out: CLW + wind renders as CLW alone
mkdir -p "$T/a" "$T/b"
"$B/vsv-convert" -q --vars CLW "$CROP" -o "$T/a/x.vsv"
"$B/vsv-convert" -q --vars CLW --no-winds "$CROP" -o "$T/b/x.vsv"
(cd "$T/a" && "$OLDPWD/$B/vsv-render" x.vsv -o ../a.png -t 3 --size 200x150 2> /dev/null)
(cd "$T/b" && "$OLDPWD/$B/vsv-render" x.vsv -o ../b.png -t 3 --size 200x150 2> /dev/null)
if [ -s "$T/a.png" ]; then
    same "vsv-render's default picture of CLW + the wind is CLW's alone" "$T/a.png" "$T/b.png"
else
    fail "vsv-render's default picture of CLW + the wind" "no picture"
fi
(cd "$T/a" && "$OLDPWD/$B/vsv-render" x.vsv -o ../n.png -t 3 --size 200x150 --species CLW,wind_east \
    2> /dev/null)
if cmp -s "$T/n.png" "$T/b.png"; then
    fail "... the wind drawn when named (--species CLW,wind_east)" "the same picture"
else
    pass "... the wind drawn when named (--species CLW,wind_east)"
fi
