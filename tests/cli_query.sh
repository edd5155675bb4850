#!/bin/sh
# cli_query.sh — vsv-query: options, errors naming the valid range, the three
# output forms agreeing, profiles and time series on the real MM5 sample and
# the full MM5 run (../shared), and the Chicago series of the issue.
B=${B:-build}
SHARED=${SHARED:-../shared}
T=$(mktemp -d "${TMPDIR:-/tmp}/vsv-cli-query.XXXXXX")
trap 'rm -rf "$T"' EXIT
. tests/cli_lib.sh
Q="$B/vsv-query"
"$B/vsv-convert" --vertical even -q samples/mm5/MMOUT_DOMAIN1_CROP -o "$T/crop.vsv"
expect "vsv-query --help exits 0" 0 "$Q" --help
has "the help names --profile" "$T/out" "--profile LAT,LON"
expect "no point exits 2" 2 "$Q" "$T/crop.vsv"
expect "two points exit 2" 2 "$Q" "$T/crop.vsv" --at 46,-116 --cell 1,2
expect "a malformed --at exits 2" 2 "$Q" "$T/crop.vsv" --at 46
expect "a fractional --cell exits 2" 2 "$Q" "$T/crop.vsv" --cell 1.5,2
expect "--csv with --json exits 2" 2 "$Q" "$T/crop.vsv" --cell 1,2 --csv --json
has "and says one format at a time" "$T/err" "--csv and --json: one output format at a time"
expect "--json twice is one format" 0 "$Q" "$T/crop.vsv" --cell 1,2 --json --json
expect "--for 0h exits 2" 2 "$Q" "$T/crop.vsv" --trajectory 46,-116,1000 --for 0h
has "and says a length must be more than zero (not 'the step')" "$T/err" "--for 0h: a duration of zero: it must be more than zero"
expect "an unknown species exits 2" 2 "$Q" "$T/crop.vsv" --at 46,-116 -s NOPE
expect "a point outside the grid exits 1" 1 "$Q" "$T/crop.vsv" --at 41.88,-87.63
has "naming the grid's range" "$T/err" "41.88,-87.63 is outside the grid (39 x 39 cells spanning latitude 42.515..56.454, longitude -133.825..-112.199;"
has "... and, its edges no parallels, its corners" "$T/err" "the lcc grid's edges are not parallels or meridians; corner cells SW 42.702,-127.319 SE 45.612,-112.440 NW 52.871,-133.512 NE 56.287,-115.867)"
expect "a height above the grid exits 1" 1 "$Q" "$T/crop.vsv" --at 46,-116,30000
has "naming the levels" "$T/err" "height 30000 m is outside the grid's levels"
expect "a time after the run exits 1" 1 "$Q" "$T/crop.vsv" --at 46,-116 --time 1995-10-25T00:00:00Z
has "naming the run" "$T/err" "is after the last step (steps 0..3, 1995-10-24T00:00:00Z .. 1995-10-24T03:00:00Z)"
expect "a time before the run exits 1" 1 "$Q" "$T/crop.vsv" --at 46,-116 --time 1995-10-23T12:00:00Z
expect "a step past the end exits 1" 1 "$Q" "$T/crop.vsv" --at 46,-116 --time 9
expect "a cell outside the grid exits 1" 1 "$Q" "$T/crop.vsv" --cell 39,0
has "naming the cells" "$T/err" "i 0..38, j 0..38, k 0..39"
expect "a damaged .vsv exits 1" 1 "$Q" tests/golden/bad/payload.vsv --cell 0,0

# a time series: one row per step, the nearest cell and its centre
expect "a series at 46N 116W, 3000 m" 0 "$Q" "$T/crop.vsv" --at 46,-116,3000 -s CLW,SNOW --csv
cp "$T/out" "$T/series.csv"
has "a header with units" "$T/series.csv" "time,i,j,k,lat,lon,height (m),CLW (kg/kg),SNOW (kg/kg)"
# a species without units is its bare name (it was "bare ()")
"$B/vsv-convert" -q samples/mm5/MMOUT_DOMAIN1_CROP -v CLW --no-winds --derive 'bare=CLW*2' -o "$T/bare.vsv"
expect "a species without units, --csv" 0 "$Q" "$T/bare.vsv" --cell 1,1,1 -t 0 --csv
if head -n 1 "$T/out" | grep -q ',CLW (kg/kg),bare$'; then pass "... its column the bare name"; else fail "... its column the bare name" "$(head -n 1 "$T/out")"; fi
expect "... and as a table" 0 "$Q" "$T/bare.vsv" --cell 1,1,1 -t 0
if grep -qF "()" "$T/out"; then fail "... no empty units" "$(head -1 "$T/out")"; else pass "... no empty units"; fi
# a column name holding a comma or a quote (units from the file) is quoted
# as RFC 4180 has it (vsv-plot's CSV: cli_plot.sh)
"$B/vsv-convert" -q samples/mm5/MMOUT_DOMAIN1_CROP -v CLW --no-winds --derive 'dbl=CLW*2:g,"kg"' -o "$T/odd.vsv"
expect "--csv of a species whose units hold a comma and quotes" 0 "$Q" "$T/odd.vsv" --cell 1,1,1 -t 0 --csv
has "... quotes that column" "$T/out" 'time,i,j,k,lat,lon,height (m),CLW (kg/kg),"dbl (g,""kg"")"'
[ "$(wc -l < "$T/series.csv")" = 5 ] && pass "one row per step (4 + header)" || fail "one row per step" "$(cat "$T/series.csv")"
has "the nearest cell, its centre 46.0054N 115.9526W at 3017.5 m" "$T/series.csv" "1995-10-24T02:00:00Z,30,3,8,46.005"
# MM5 writes its hydrometeors before the first step: all zero in period 0
has "no snow in the first period" "$T/series.csv" "1995-10-24T00:00:00Z,30,3,8,46.005392,-115.952608,3017.5,0,0"
snow2=$(awk -F, 'NR == 4 { print $9 }' "$T/series.csv")
awk -v v="$snow2" "BEGIN { exit !(v + 0 > 0) }" && pass "snow at 02:00 (${snow2})" || fail "snow at 02:00" "$snow2"
expect "the same series as JSON" 0 "$Q" "$T/crop.vsv" --at 46,-116,3000 -s CLW,SNOW --json
has "JSON: the same snow value" "$T/out" "\"SNOW\": $snow2"
has "JSON: the method" "$T/out" '"interp": "nearest"'
has "JSON: the species' bound" "$T/out" '"max_abs_error"'
python3 -c 'import json,sys; d=json.load(open(sys.argv[1])); assert len(d["rows"]) == 4' "$T/out" 2> "$T/err" &&
    pass "JSON parses, 4 rows" || fail "JSON parses" "$(cat "$T/err")"
expect "the same as a table" 0 "$Q" "$T/crop.vsv" --at 46,-116,3000 -s CLW,SNOW
has "table: aligned columns, the same value" "$T/out" "1995-10-24T02:00:00Z    30     3    8    46.0054   -115.9526       3017.5             0   7.00689e-09"
expect "one time by ISO" 0 "$Q" "$T/crop.vsv" --at 46,-116,3000 -s SNOW --csv --time 1995-10-24T02:00:00Z
[ "$(sed -n 2p "$T/out" | cut -d, -f8)" = "$snow2" ] && [ "$(wc -l < "$T/out")" = 2 ] && pass "--time picks that step" || fail "--time" "$(cat "$T/out")"
expect "--cell gives the same cell" 0 "$Q" "$T/crop.vsv" --cell 30,3,8 -s CLW,SNOW --csv
same "--cell 30,3,8 = --at 46,-116,3000" "$T/out" "$T/series.csv"
# trilinear: between the nearest values of its neighbours, and differs
expect "--interp" 0 "$Q" "$T/crop.vsv" --at 46,-116,3000 -s SNOW --csv --interp --time 3
snow_i=$(sed -n 2p "$T/out" | cut -d, -f8)
awk -v v="$snow_i" "BEGIN { exit !(v + 0 > 0) }" && pass "trilinear snow at 03:00 is non-zero where the nearest cell is 0 ($snow_i)" || fail "trilinear" "$snow_i"
# a profile: every level, heights 177.5 m apart by 355 m
expect "--profile" 0 "$Q" "$T/crop.vsv" --profile 46,-116 -s SNOW --csv --time 2
[ "$(wc -l < "$T/out")" = 41 ] && pass "40 levels + header" || fail "40 levels" "$(wc -l < "$T/out")"
has "level 0 at 177.5 m" "$T/out" ",30,3,0,46.005392,-115.952608,177.5,"
has "level 39 at 14022.5 m" "$T/out" ",30,3,39,46.005392,-115.952608,14022.5,"
has "level 8 the series' value" "$T/out" ",30,3,8,46.005392,-115.952608,3017.5,$snow2"

# the issue's example on the full run: Chicago, one row per step
if ! absent "Chicago on the full MM5 run" mm5/run1/MMOUT_DOMAIN1; then
    "$B/vsv-convert" --vertical even -q "$(data mm5/run1/MMOUT_DOMAIN1)" -o "$T/run.vsv"
    expect "Chicago on the full MM5 run" 0 "$Q" --at 41.88,-87.63 --species CLW,SNOW --csv "$T/run.vsv"
    [ "$(wc -l < "$T/out")" = 5 ] && pass "one row per step" || fail "one row per step" "$(cat "$T/out")"
    has "Chicago is cell 127,85 (41.8363N 87.6066W)" "$T/out" "1995-10-24T03:00:00Z,127,85,"
fi

# the query API from the installed tree: <vesuvius/vsv_format.h> and pkg-config alone
if make -s --no-print-directory B="$B" install PREFIX="$T/inst" > "$T/log" 2>&1; then
    cat > "$T/q.c" <<'EOC'
#include <vesuvius/vsv_format.h>
#include <stdio.h>
int main(int argc, char **argv)
{
    vsv_file *f = NULL;
    vsv_query *q = NULL;
    vsv_point p;
    char msg[256];
    float v = -1;
    if (argc < 2 || vsv_file_open(argv[1], &f))
        return 1;
    const vsv_meta *m = vsv_file_meta(f);
    if (vsv_point_locate(m, 46, -116, 3000, &p, msg, sizeof msg) || vsv_query_create(f, &q) ||
        vsv_query_sample(q, 2, vsv_meta_find_var(m, "SNOW"), p.pos, VSV_INTERP_NEAREST, &v))
        return 1;
    printf("%d,%d,%d,%.9g\n", p.cell[0], p.cell[1], p.cell[2], v);
    vsv_query_free(q);
    vsv_file_free(f);
    return 0;
}
EOC
    if PKG_CONFIG_PATH="$T/inst/lib/pkgconfig" cc $SANFLAGS -o "$T/q" "$T/q.c" \
        $(PKG_CONFIG_PATH="$T/inst/lib/pkgconfig" pkg-config --cflags --libs vesuvius) > "$T/cc" 2>&1; then
        pass "a program using the query API builds against the installed tree with pkg-config alone"
        expect "and runs" 0 env LD_LIBRARY_PATH="$T/inst/lib" "$T/q" "$T/crop.vsv"
        has "giving vsv-query's cell and value" "$T/out" "30,3,8,$snow2"
    else
        fail "a program using the query API builds against the installed tree" "$(head -c 400 "$T/cc")"
    fi
    [ -f "$T/inst/include/vesuvius/vsv_cf.h" ] && pass "the netCDF export's header is installed" || fail "vsv_cf.h installed" "missing"
else
    fail "make install PREFIX=$T/inst" "$(tail -c 300 "$T/log")"
fi
