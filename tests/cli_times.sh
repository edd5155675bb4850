#!/bin/sh
# cli_times.sh — the one time grammar (an index, an ISO time, a range A:B of
# either where ISO times hold colons) in every tool that takes times, and
# --time-res: a unit required, regular steps t0 + k*res, coarser keeps every
# k-th step. Prints PASS/FAIL lines.
B=${B:-build}
SHARED=${SHARED:-../shared}
T=$(mktemp -d "${TMPDIR:-/tmp}/vsv-cli-times.XXXXXX")
trap 'rm -rf "$T"' EXIT
. tests/cli_lib.sh
CROP=samples/mm5/MMOUT_DOMAIN1_CROP # hourly, 1995-10-24 00..03 UTC

# --times with ISO ends that hold colons (was split at the first colon)
"$B/vsv-extract" --times 1995-10-24T01:00:00Z:1995-10-24T02:00:00Z "$CROP" | "$B/vsv-pack" -q -o "$T/r.vsv"
"$B/vsv-info" -f times "$T/r.vsv" > "$T/out"
has "vsv-extract --times ISO:ISO with colons" "$T/out" '["1995-10-24T01:00:00Z", "1995-10-24T02:00:00Z"]'
expect "vsv-convert --times T01:30Z:" 0 "$B/vsv-convert" -q --times 1995-10-24T01:30Z: "$CROP" -o "$T/c.vsv"
"$B/vsv-info" -f times "$T/c.vsv" > "$T/out"
has "a range from between two steps starts at the next" "$T/out" '["1995-10-24T02:00:00Z", "1995-10-24T03:00:00Z"]'
expect "--times ending after the last step exits 1" 1 "$B/vsv-extract" --times 1995-10-24T01:00Z:1995-10-24T05:00Z "$CROP"
has "out-of-range end names the valid range" "$T/err" "is after the last step (steps 0..3, 1995-10-24T00:00:00Z .. 1995-10-24T03:00:00Z)"
expect "--times 2:9 exits 1" 1 "$B/vsv-extract" --times 2:9 "$CROP"
has "an index out of range is named" "$T/err" "step 9 is out of range (steps 0..3"
expect "--times of mixed kinds exits 2" 2 "$B/vsv-extract" --times 1:1995-10-24T02:00Z "$CROP"
expect "--times nonsense exits 2" 2 "$B/vsv-extract" --times yesterday "$CROP"
has "a malformed time names the grammar" "$T/err" "neither a step index, an ISO time"

# --time-res: a unit, regular steps, coarser keeps every k-th step
expect "--time-res 15 (no unit) exits 2" 2 "$B/vsv-convert" --time-res 15 "$CROP" -o "$T/x.vsv"
has "--time-res without a unit is named" "$T/err" "expected a duration with its unit"
if [ ! -e "$T/x.vsv" ]; then pass "nothing written after --time-res 15"; else fail "nothing written after --time-res 15" "exists"; fi
expect "vsv-interp --time-res 90 exits 2" 2 "$B/vsv-interp" --time-res 90
for d in 0m -10m -1h30m; do
    expect "--time-res $d exits 2" 2 "$B/vsv-interp" --time-res "$d"
done
has "a negative step is named" "$T/err" "--time-res -1h30m: a negative duration"
expect "--time-res 0s exits 2" 2 "$B/vsv-interp" --time-res 0s
has "a zero step is named" "$T/err" "--time-res 0s: a duration of zero"
expect "--time-res 9223372036854775807s exits 2" 2 "$B/vsv-interp" --time-res 9223372036854775807s
has "... longer than any file spans (it overflowed the interpolation)" "$T/err" "longer than 10000 years"
expect "--time-res P1M exits 2" 2 "$B/vsv-interp" --time-res P1M
has "ISO months are named" "$T/err" "years and months have no fixed length"
for d in 30m1h 1h1h 1hm PT P1H 1h30 10ms; do
    expect "--time-res $d exits 2" 2 "$B/vsv-interp" --time-res "$d"
    has "--time-res $d names the grammar" "$T/err" "largest first: 30s, 10m, 1h30m, 1d, or ISO 8601 PT1H30M"
done
expect "--time-res 1h30m converts" 0 "$B/vsv-convert" -q --vars T --time-res 1h30m "$CROP" -o "$T/c90.vsv"
"$B/vsv-info" -f time_step "$T/c90.vsv" > "$T/out"
has "1h30m is 5400 s" "$T/out" "5400"
"$B/vsv-info" -f times "$T/c90.vsv" > "$T/out"
has "1h30m: 00:00, 01:30, 03:00" "$T/out" '["1995-10-24T00:00:00Z", "1995-10-24T01:30:00Z", "1995-10-24T03:00:00Z"]'
for d in PT1H30M 90min 5400s PT90M P0DT1H30M 1h30min 1h29m60s; do
    "$B/vsv-convert" -q --vars T --time-res "$d" "$CROP" -o "$T/c90b.vsv"
    same "--time-res $d is 1h30m" "$T/c90.vsv" "$T/c90b.vsv"
    rm -f "$T/c90b.vsv"
done
# a range ending at the run's last time, which is off the 2h grid (00:00,
# 02:00; the run ends 03:00), ends at the last step (it was "after the last
# step"); a time past the run, an index past the steps or a start there fail
expect "--time-res 2h --times to the run's end converts" 0 "$B/vsv-convert" -q --vars T --time-res 2h \
    --times 1995-10-24T01:00Z:1995-10-24T03:00Z "$CROP" -o "$T/end.vsv"
"$B/vsv-info" -f times "$T/end.vsv" > "$T/out"
has "... to the 02:00 step" "$T/out" '["1995-10-24T02:00:00Z"]'
for t in 1995-10-24T01:00Z:1995-10-24T03:00:01Z 0:2 1995-10-24T03:00Z: 1995-10-24T03:00Z; do
    expect "--time-res 2h --times $t exits 1" 1 "$B/vsv-convert" -q --vars T --time-res 2h --times "$t" "$CROP" -o "$T/past.vsv"
done
expect "--time-res 7m converts" 0 "$B/vsv-convert" --time-res 7m "$CROP" -o "$T/r7.vsv"
has "model times off the 7m grid are reported" "$T/err" "3 of 4 model times lie between the steps every 7m"
"$B/vsv-info" "$T/r7.vsv" > "$T/out"
has "vsv-info: 7m steps all 420 s apart" "$T/out" "26 steps, 1995-10-24T00:00:00Z .. 1995-10-24T02:55:00Z, every 420 s (7m)"
"$B/vsv-info" -f time_step "$T/r7.vsv" > "$T/out"
has "vsv-info --json time_step" "$T/out" "420"
expect "--time-res 2h on hourly data" 0 "$B/vsv-convert" -q --time-res 2h "$CROP" -o "$T/r2h.vsv"
"$B/vsv-info" -f times "$T/r2h.vsv" > "$T/out"
has "2h keeps every second hour" "$T/out" '["1995-10-24T00:00:00Z", "1995-10-24T02:00:00Z"]'
"$B/vsv-extract" --vars T --times 2:2 "$CROP" | "$B/vsv-pack" -q -o "$T/h2.vsv"
"$B/vsv-extract" --vars T --times 2 "$CROP" | "$B/vsv-pack" -q -o "$T/h2b.vsv"
same "--times 2 is --times 2:2" "$T/h2.vsv" "$T/h2b.vsv"
expect "vsv-convert --times of one time between steps" 0 "$B/vsv-convert" -q --vars T --times 1995-10-24T01:40Z "$CROP" -o "$T/n.vsv"
has "vsv-convert says which step it took" "$T/err" "--times 1995-10-24T01:40Z: no step at that time; the nearest is step 2, 1995-10-24T02:00:00Z"

# with --time-res, --times picks among the output steps (every 10m from
# 00:00), and the model frames around them bound the interpolation
printf '#!/bin/sh\nexec "%s/vsv-convert" -q --vars T --range 150:350 --time-res 10m "$@" "%s" -o "%s/w.vsv"\n' \
    "$B" "$CROP" "$T" > "$T/w"
chmod +x "$T/w"
expect "--time-res 10m --times 00:40..01:10" 0 "$T/w" --times 1995-10-24T00:40:00Z:1995-10-24T01:10:00Z
"$B/vsv-info" -f times "$T/w.vsv" > "$T/out"
has "four output steps 00:40..01:10" "$T/out" \
    '["1995-10-24T00:40:00Z", "1995-10-24T00:50:00Z", "1995-10-24T01:00:00Z", "1995-10-24T01:10:00Z"]'
"$T/w"
"$B/vsv-query" "$T/w.vsv" --cell 10,10,3 --times 1995-10-24T00:40Z:1995-10-24T01:10Z --csv > "$T/full"
"$T/w" --times 1995-10-24T00:40:00Z:1995-10-24T01:10:00Z
"$B/vsv-query" "$T/w.vsv" --cell 10,10,3 --csv > "$T/part"
same "the window's values are the full conversion's (same range)" "$T/full" "$T/part"
has "... interpolated between the hours (00:50)" "$T/part" "1995-10-24T00:50:00Z,10,10,3"
expect "--times 00:45..00:55 converts" 0 "$T/w" --times 1995-10-24T00:45Z:1995-10-24T00:55Z
"$B/vsv-info" -f times "$T/w.vsv" > "$T/out"
has "00:45..00:55 selects the 00:50 step" "$T/out" '["1995-10-24T00:50:00Z"]'
expect "--times 4:7 are output steps" 0 "$T/w" --times 4:7
"$B/vsv-info" -f times "$T/w.vsv" > "$T/out"
has "steps 4..7 are 00:40..01:10" "$T/out" '["1995-10-24T00:40:00Z", "1995-10-24T00:50:00Z", "1995-10-24T01:00:00Z", "1995-10-24T01:10:00Z"]'
expect "--times of one time between output steps" 0 "$T/w" --times 1995-10-24T00:44Z
has "... says which output step it took" "$T/err" "no output step at that time; the nearest is step 4, 1995-10-24T00:40:00Z"
rm -f "$T/w.vsv"
expect "--times 19 with 19 steps of 10m exits 1" 1 "$T/w" --times 19
has "... naming the output steps" "$T/err" "(among the output steps every 10m): step 19 is out of range (steps 0..18"
if [ ! -e "$T/w.vsv" ]; then pass "nothing written after a window out of range"; else fail "nothing written after a window out of range" "exists"; fi

# the model's outputs are recorded, so interpolated frames can say so
"$B/vsv-info" "$T/c90.vsv" > "$T/out"
has "the file records when the model wrote its outputs" "$T/out" "model_outputs every 3600 s from 1995-10-24T00:00:00Z"

# vsv-render / vsv-export --time: the nearest step, said when not exact
"$B/vsv-convert" -q --time-res 10m --vars CLW "$CROP" -o "$T/s.vsv"
expect "vsv-render --time between steps" 0 "$B/vsv-render" -q "$T/s.vsv" --time 1995-10-24T00:01 -o "$T/a.png" --size 32x24
has "vsv-render says which step it took" "$T/err" "no step at that time; the nearest is step 0, 1995-10-24T00:00:00Z"
expect "vsv-render --time after the end exits 1" 1 "$B/vsv-render" -q "$T/s.vsv" --time 1995-10-24T04:00 -o "$T/b.png"
has "vsv-render names the valid range" "$T/err" "after the last step (steps 0..18"
if [ ! -e "$T/b.png" ]; then pass "no image after a time out of range"; else fail "no image after a time out of range" "exists"; fi
expect "vsv-render --times ISO:ISO" 0 "$B/vsv-render" -q "$T/s.vsv" --times 1995-10-24T00:10:00Z:1995-10-24T00:30:00Z -o "$T/f%02d.png" --size 32x24
if [ -f "$T/f02.png" ] && [ ! -e "$T/f03.png" ]; then pass "three frames for 00:10..00:30"; else fail "three frames for 00:10..00:30" "$(ls "$T")"; fi
expect "vsv-render --time with a range exits 2" 2 "$B/vsv-render" "$T/s.vsv" --time 0:3 -o "$T/c.png"
if "$B/vsv-export" --help > /dev/null 2>&1 && "$B/vsv-export" --help | grep -q vdb; then
    expect "vsv-export --times after the end exits 1" 1 "$B/vsv-export" -q "$T/s.vsv" --vdb "$T/v%02d.vdb" --times 1995-10-24T02:00Z:1995-10-25T00:00Z
    has "vsv-export names the valid range" "$T/err" "is after the last step"
fi

# CF calendars other than the standard one (issue 32): a 360-day file (days
# 28, 29, 30 of February) and a noleap one (28 February, then 1 March a day
# later) keep their dates and intervals through the tools and back
if /usr/bin/python3 -c "import netCDF4" 2> /dev/null; then
    /usr/bin/python3 - "$T" << 'EOP'
import sys, numpy as np, netCDF4
for cal, since, n in (("360_day", "days since 2001-02-28", 3), ("noleap", "days since 2000-02-28", 2)):
    d = netCDF4.Dataset("%s/%s.nc" % (sys.argv[1], cal), "w")
    d.Conventions = "CF-1.8"
    for name, size in (("time", n), ("z", 2), ("y", 3), ("x", 4)):
        d.createDimension(name, size)
    t = d.createVariable("time", "f8", ("time",)); t.units = since; t.calendar = cal; t[:] = np.arange(n)
    z = d.createVariable("z", "f8", ("z",)); z.units = "m"; z.positive = "up"; z.standard_name = "altitude"; z[:] = [500, 1500]
    y = d.createVariable("y", "f8", ("y",)); y.units = "m"; y.standard_name = "projection_y_coordinate"; y[:] = [0, 1000, 2000]
    x = d.createVariable("x", "f8", ("x",)); x.units = "m"; x.standard_name = "projection_x_coordinate"; x[:] = [0, 1000, 2000, 3000]
    v = d.createVariable("O3", "f4", ("time", "z", "y", "x")); v.units = "ppm"
    v[:] = np.arange(n * 24, dtype="f4").reshape(n, 2, 3, 4) * 0.01
    d.close()
EOP
    expect "a 360_day CF file converts" 0 "$B/vsv-convert" -q "$T/360_day.nc" -o "$T/c360.vsv"
    "$B/vsv-info" "$T/c360.vsv" > "$T/out"
    has "... its times are its dates, a day apart" "$T/out" "3 steps, 2001-02-28T00:00:00Z .. 2001-02-30T00:00:00Z, every 86400 s (1d)"
    has "... and the file says its calendar" "$T/out" "calendar    360_day"
    expect "vsv-query --time 2001-02-30 (a 360-day date)" 0 "$B/vsv-query" "$T/c360.vsv" --cell 1,1,0 --time 2001-02-30 --csv
    has "... finds the third step" "$T/out" "2001-02-30T00:00:00Z,1,1,0"
    expect "vsv-query --time 2001-02-29T20:00 (between 360-day steps)" 0 "$B/vsv-query" "$T/c360.vsv" --cell 1,1,0 \
        --time 2001-02-29T20:00Z --csv
    has "... the note names the nearest step by its 360-day date, 2001-02-30" "$T/err" \
        "no step at that time; the nearest is step 2, 2001-02-30T00:00:00Z"
    expect "--time 2001-02-31 exits 2 (no such day)" 2 "$B/vsv-query" "$T/c360.vsv" --cell 1,1,0 --time 2001-02-31
    expect "--time-res 12h on 360-day days" 0 "$B/vsv-convert" -q --time-res 12h "$T/360_day.nc" -o "$T/c360h.vsv"
    "$B/vsv-info" -f times "$T/c360h.vsv" > "$T/out"
    has "... five steps, 29 February 12:00 among them" "$T/out" '"2001-02-29T12:00:00Z", "2001-02-30T00:00:00Z"]'
    expect "the 360_day file exports to netCDF" 0 "$B/vsv-export" -q "$T/c360.vsv" --netcdf "$T/back360.nc"
    ncdump -h "$T/back360.nc" > "$T/out"
    has "... with its calendar" "$T/out" 'time:calendar = "360_day"'
    has "... and its dates" "$T/out" 'time:units = "seconds since 2001-02-28 00:00:00"'
    expect "... which converts back" 0 "$B/vsv-convert" -q "$T/back360.nc" -o "$T/again360.vsv"
    "$B/vsv-info" -f times "$T/again360.vsv" > "$T/out2"
    "$B/vsv-info" -f times "$T/c360.vsv" > "$T/out"
    same "... to the same times" "$T/out" "$T/out2"
    expect "a noleap CF file converts" 0 "$B/vsv-convert" -q "$T/noleap.nc" -o "$T/cnl.vsv"
    "$B/vsv-info" "$T/cnl.vsv" > "$T/out"
    has "... 28 February then 1 March, a day apart (no 29th)" "$T/out" "2 steps, 2000-02-28T00:00:00Z .. 2000-03-01T00:00:00Z, every 86400 s (1d)"
else
    echo "SKIP the calendars: python3-netcdf4 is missing"
fi
exit 0
