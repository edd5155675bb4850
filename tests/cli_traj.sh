#!/bin/sh
# cli_traj.sh — vsv-query --trajectory: a path through a known wind (10 m/s
# east on a Lambert grid, tests/wind_file.c) as CSV, table and JSON, forward,
# backward and several at once; its length; the end at the grid's edge; the
# errors (no wind, no projection, seeds outside, times, option clashes).
B=${B:-build}
T=$(mktemp -d "${TMPDIR:-/tmp}/vsv-cli-traj.XXXXXX")
trap 'rm -rf "$T"' EXIT
. tests/cli_lib.sh
Q="$B/vsv-query"
"$B/tests/windfile" "$T/east.vsv" east && "$B/tests/windfile" "$T/flat.vsv" flat &&
    "$B/tests/windfile" "$T/nowind.vsv" nowind || { fail "tests/windfile writes the test files" "$?"; exit 0; }
expect "vsv-query --help names --trajectory" 0 "$Q" --help
has "the help: --trajectory LAT,LON,HEIGHT" "$T/out" "--trajectory LAT,LON,HEIGHT"
has "the help: --every" "$T/out" "--every DURATION"

# two hours east at 10 m/s: 72 km along the parallel, a point every 30 min
expect "a path as CSV" 0 "$Q" "$T/east.vsv" --trajectory 40,-100.5,300 --for 2h --every 30m --csv
cp "$T/out" "$T/path.csv"
[ "$(head -n 1 "$T/path.csv")" = "time,lat,lon,height,x,y,east,north,up" ] && pass "CSV: its header" ||
    fail "CSV: its header" "$(head -n 1 "$T/path.csv")"
[ "$(wc -l < "$T/path.csv")" = 6 ] && pass "CSV: 5 points and the header" || fail "CSV: 5 points" "$(cat "$T/path.csv")"
has "CSV: the seed first, at the first step, with its wind" "$T/path.csv" "2020-01-01T00:00:00Z,40.000000,-100.500000,300,"
has "CSV: the end 2 h later on the same parallel" "$T/path.csv" "2020-01-01T02:00:00Z,40.000000,-99.654601,300,"
python3 - "$T/path.csv" > "$T/err" 2>&1 << 'PY' && pass "CSV: 72 km travelled, 10 m/s for 2 h (1 m)" || fail "CSV: 72 km" "$(cat "$T/err")"
import csv, math, sys
r = list(csv.DictReader(open(sys.argv[1])))
d = sum(6370000 * math.acos(min(1, math.sin(math.radians(float(a["lat"]))) * math.sin(math.radians(float(b["lat"])))
        + math.cos(math.radians(float(a["lat"]))) * math.cos(math.radians(float(b["lat"])))
        * math.cos(math.radians(float(b["lon"]) - float(a["lon"]))))) for a, b in zip(r, r[1:]))
print(d)
assert abs(d - 72000) < 1, d
PY

expect "the same path as JSON" 0 "$Q" "$T/east.vsv" --trajectory 40,-100.5,300 --for 2h --every 30m --json
python3 -c 'import json,sys; d=json.load(open(sys.argv[1])); t=d["trajectories"][0]; assert t["end"] == "time" and len(t["points"]) == 5 and abs(t["points"][4]["lon"] + 99.654601) < 1e-6 and d["height_units"] == "m", t' "$T/out" 2> "$T/err" &&
    pass "JSON: one path, 5 points, ended at the time asked, the same end" || fail "JSON" "$(cat "$T/err")"
expect "backward from step 3 for 20 min" 0 "$Q" "$T/east.vsv" --trajectory 40,-100.5,300 --from 3 --back --for 20m --every 10m --csv
[ "$(sed -n 2p "$T/out" | cut -d, -f1)" = 2020-01-01T03:00:00Z ] && [ "$(sed -n 4p "$T/out" | cut -d, -f1)" = 2020-01-01T02:40:00Z ] &&
    pass "backward: 03:00 back to 02:40" || fail "backward" "$(cat "$T/out")"
has "backward: it came from the west (12 km)" "$T/out" "2020-01-01T02:40:00Z,40.000000,-100.640900,"
expect "--to earlier than --from goes backward too" 0 "$Q" "$T/east.vsv" --trajectory 40,-100.5,300 --from 2020-01-01T03:00 --to 2020-01-01T02:40 --every 10m --csv
has "--to: the same point" "$T/out" "2020-01-01T02:40:00Z,40.000000,-100.640900,"
expect "two paths, a table" 0 "$Q" "$T/east.vsv" --trajectory 40,-100.5,300 --trajectory 40.3,-100,250 --from 2020-01-01T01:30 --for 30m --every 15m
has "table: a path column" "$T/out" "path time"
has "table: the second path's end" "$T/out" "   2 2020-01-01T02:00:00Z        40.3000    -99.7877     250.00"
# from the west edge for 6 h: it leaves the grid after 214 km
expect "a path to the grid's edge exits 0" 0 "$Q" "$T/east.vsv" --trajectory 40,-101.05,300 --every 1h --csv
has "a note says it left the grid" "$T/err" "trajectory 40,-101.05,300 left the grid sideways at 2020-01-01T0"
tail -n 1 "$T/out" | awk -F, '{ exit !($5 > 119999.999 && $5 < 120000.001) }' && pass "it ends at the east edge (x 120 km, 1 mm)" ||
    fail "it ends at the east edge" "$(tail -n 1 "$T/out")"

# a streamline: the wind of the last step (06:00) held still, 2 h of travel
# past the file's end (a trajectory stops there: its times ran out)
expect "a trajectory from the last step stops at once" 0 "$Q" "$T/east.vsv" --trajectory 40,-100.5,300 --from 6 --for 2h --csv
has "... saying the file's times ran out" "$T/err" "trajectory 40,-100.5,300 "
expect "--streamline from the last step for 2 h" 0 "$Q" "$T/east.vsv" --trajectory 40,-100.5,300 --from 6 --for 2h --every 1h --streamline --csv
has "--streamline: 72 km east along the wind of 06:00, its clock counting the travel" "$T/out" "2020-01-01T08:00:00Z,40.000000,-99.654601,300,"
expect "--streamline without --trajectory is misuse" 2 "$Q" "$T/east.vsv" --at 40,-100.5 --streamline
has "... saying so" "$T/err" "--streamline go with --trajectory"

# errors
expect "a file without wind exits 1" 1 "$Q" "$T/nowind.vsv" --trajectory 40,-100,300
has "naming what is missing" "$T/err" "nowind.vsv: no wind stored (convert from a file with U and V, without --no-winds, or with --winds FILE)"
expect "a grid without a projection exits 1" 1 "$Q" "$T/flat.vsv" --trajectory 40,-100,300
has "saying so" "$T/err" "the grid has no map projection"
expect "--at on a grid without a projection exits 1" 1 "$Q" "$T/flat.vsv" --at 40,-100
has "... pointing to --cell" "$T/err" "no latitude/longitude is known (give a cell: --cell I,J[,K])"
expect "vsv-plot --profile on it exits 1" 1 "$B/vsv-plot" "$T/flat.vsv" --profile 40,-100 --species wind_east -o "$T/x.svg"
has "... pointing to --proj, not to a --cell it lacks" "$T/err" "no latitude/longitude is known (vsv-convert --proj gives a CAMx 5 grid its projection)"
expect "a seed outside the grid exits 1" 1 "$Q" "$T/east.vsv" --trajectory 45,-100,300
has "naming the seed" "$T/err" "--trajectory 45,-100,300: seed x"
has "and why" "$T/err" "is outside the grid at 2020-01-01T00:00:00Z"
for f in --csv --json ""; do
    expect "a good seed then one outside the grid${f:+ ($f)} exits 1" 1 "$Q" "$T/east.vsv" --trajectory 40,-100.5,300 --trajectory 45,-100,300 $f
    [ ! -s "$T/out" ] && pass "and writes nothing${f:+ ($f)}" || fail "and writes nothing${f:+ ($f)}" "$(head -c 200 "$T/out")"
done
expect "a seed above the top exits 1" 1 "$Q" "$T/east.vsv" --trajectory 40,-100,900
has "above the grid's top" "$T/err" "above the grid's top"
expect "--from after the file exits 1" 1 "$Q" "$T/east.vsv" --trajectory 40,-100,300 --from 2020-01-02
expect "a malformed --trajectory exits 2" 2 "$Q" "$T/east.vsv" --trajectory 40,-100
expect "--to with --for exits 2" 2 "$Q" "$T/east.vsv" --trajectory 40,-100,300 --to 3 --for 1h
expect "--trajectory with --at exits 2" 2 "$Q" "$T/east.vsv" --trajectory 40,-100,300 --at 40,-100
expect "--from without --trajectory exits 2" 2 "$Q" "$T/east.vsv" --at 40,-100 --from 1
expect "a bad --every exits 2" 2 "$Q" "$T/east.vsv" --trajectory 40,-100,300 --every 10

# Python's File.trajectory: the same path as the CLI's
PYTHON=${PYTHON:-/usr/bin/python3}
if ! PYTHONPATH="$B/python" "$PYTHON" -c 'import numpy, vesuvius' 2> /dev/null; then
    echo "  (the Python module is not built here: File.trajectory's checks are skipped)"
    exit 0
fi
PYTHONPATH="$B/python" "$PYTHON" - "$T/east.vsv" "$T/path.csv" > "$T/err" 2>&1 << 'PY' &&
import csv, sys
import numpy as np
import vesuvius
f = vesuvius.open(sys.argv[1])
r = f.trajectory(40, -100.5, 300, 0, "2020-01-01T02:00:00Z", every=np.timedelta64(30, "m"))
rows = list(csv.DictReader(open(sys.argv[2])))
assert r["end"] == "time" and len(r["lat"]) == len(rows) == 5, r
for k in ("lat", "lon", "height", "x", "y", "east", "north", "up"):
    assert np.allclose(r[k], [float(w[k]) for w in rows], rtol=1e-8, atol=1e-6), k
assert str(r["time"][4]) == "2020-01-01T02:00:00.000" and r["east"].dtype == np.float32, r["time"]
b = f.trajectory(40, -100.5, 300, 3, np.datetime64("2020-01-01T02:40"), every=600)
assert abs(b["lon"][-1] + 100.6409) < 1e-6 and b["seconds"][-1] - b["seconds"][0] == -1200, b
try:
    f.trajectory(45, -100, 300, 0, 1)
    raise SystemExit("no error for a seed outside the grid")
except vesuvius.Error as e:
    assert "is outside the grid" in str(e), e
PY
    pass "Python: File.trajectory gives the CLI's path, backward too, and vesuvius.Error outside the grid" ||
    fail "Python: File.trajectory" "$(tail -n 5 "$T/err")"
