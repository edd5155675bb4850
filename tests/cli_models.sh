#!/bin/sh
# cli_models.sh — CAMx, WRF and IOAPI input through the same tools: format
# detected from content, vsv-info on model files, CAMx projection and height
# options, errors. Prints PASS/FAIL lines.
B=${B:-build}
SHARED=${SHARED:-../shared}
T=$(mktemp -d "${TMPDIR:-/tmp}/vsv-cli-models.XXXXXX")
trap 'rm -rf "$T"' EXIT
. tests/cli_lib.sh
D=$TESTDATA

# CAMx UAM-IV: detected by content whatever the name
cp "$D/camx/test.uamiv" "$T/some-name.bin"
expect "vsv-info on a CAMx file" 0 "$B/vsv-info" "$T/some-name.bin"
has "CAMx header shown" "$T/out" "CAMx UAM-IV AVERAGE file (big-endian, v5 header)"
has "CAMx species listed" "$T/out" "NO NO2 O3 SO2"
expect "vsv-extract --list on CAMx" 0 "$B/vsv-extract" --list "$T/some-name.bin"
has "aerosol units" "$T/out" "ug/m3"
expect "CAMx converts with a projection given" 0 "$B/vsv-convert" -q --vars NO2,O3,PSO4 --proj lcc --lat0 40 --lon0 -97 --lat1 33 --lat2 45 "$T/some-name.bin" -o "$T/camx.vsv"
"$B/vsv-info" --json "$T/camx.vsv" > "$T/camx.json"
if /usr/bin/python3 - "$T/camx.json" <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
assert d["projection"]["name"] == "lcc" and d["corners"][0]["lat"] is not None
assert [s["name"] for s in d["species"]] == ["NO2", "O3", "PSO4"] and d["species"][2]["units"] == "ug/m3"
assert d["grid"]["vertical"]["kind"] == "index" and d["grid"]["vertical"]["units"] == "layer index"
assert d["times"] == ["2002-06-03T00:00:00Z"]
assert abs(d["species"][0]["max"] - 1.01672206e-03) < 1e-9
PY
then pass "CAMx .vsv: projection, species, units, layer index, time, NO2 max"; else fail "CAMx .vsv: projection, species, units, layer index, time, NO2 max" "see above"; fi
expect "vsv-info says the vertical axis is layer index" 0 "$B/vsv-info" "$T/camx.vsv"
has "layer index said" "$T/out" "layer index"
# the real height/pressure sample has 3 layers and 2 hours; test.uamiv 1 and
# 1: the surface layer CAMx writes alone, its heights the lowest layer's
expect "a height/pressure file of more layers gives the lowest" 0 "$B/vsv-convert" -q --vertical native --heights "$D/camx/test.height_pressure" --vars O3 "$T/some-name.bin" -o "$T/camx-z.vsv"
"$B/vsv-info" "$T/camx-z.vsv" > "$T/info"
has "... layer 1's middle as its level" "$T/info" "native levels (m): 17.1"
expect "a wrong heights file is refused" 1 "$B/vsv-convert" -q --heights "$D/camx/test.wind" "$T/some-name.bin" -o "$T/x.vsv"
expect "--proj with a bad name exits 2" 2 "$B/vsv-convert" --proj nowhere "$T/some-name.bin" -o "$T/x.vsv"
# a latitude past the pole (it wrote a file whose every latitude was NaN)
expect "--lat0 100 exits 2" 2 "$B/vsv-convert" --proj lcc --lat0 100 --lon0 0 --lat1 30 "$T/some-name.bin" -o "$T/x.vsv"
has "... naming the range" "$T/err" "--lat0 100: expected a latitude, degrees from -90 to 90"
# a lat-lon IOAPI grid placed in metres (XORIG -36000): refused as a map
# that places nothing (it converted, the grid starting at -24000 degrees)
expect "a lat-lon grid south of the pole exits 1" 1 "$B/vsv-info" tests/corpus/netcdf/ioapi-latlon.nc
has "... saying so" "$T/err" "ioapi-latlon.nc: projection latlon: the grid's corner cell at x -30000, y -24000 maps to no latitude and longitude"
head -c 3000 "$D/camx/test.uamiv" > "$T/cut.avrg"
expect "a cut CAMx file exits 1" 1 "$B/vsv-extract" "$T/cut.avrg"
has "cut CAMx names sizes" "$T/err" "does not divide into hours"

# WRF
W="$D/wrf/wrf_d01_allvars_cropped.nc"
expect "vsv-info on a wrfout file" 0 "$B/vsv-info" "$W"
has "WRF summary" "$T/out" "WRF output"
expect "wrfout converts (hydrometeors and vapour by default)" 0 "$B/vsv-convert" -q --time-res 1h "$W" -o "$T/wrf.vsv"
"$B/vsv-info" --json "$T/wrf.vsv" > "$T/wrf.json"
if /usr/bin/python3 - "$T/wrf.json" <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
assert [s["name"] for s in d["species"]] == ["QCLOUD", "QGRAUP", "QICE", "QRAIN", "QSNOW", "QVAPOR", "wind_east",
                                             "wind_north", "wind_up"]
assert len(d["times"]) == 10 and d["times"][1] == "2005-09-21T01:00:00Z"
assert d["projection"]["name"] == "lcc" and d["grid"]["terrain"]
PY
then pass "WRF .vsv: default hydrometeors and QVAPOR, hourly frames, lcc, terrain"; else fail "WRF .vsv: default hydrometeors and QVAPOR, hourly frames, lcc, terrain" "see above"; fi
"$B/vsv-extract" "$W" | "$B/vsv-interp" --time-res 1h | "$B/vsv-pack" -q -o "$T/wrf-pipe.vsv"
if cmp -s "$T/wrf.vsv" "$T/wrf-pipe.vsv"; then pass "WRF: vsv-convert = the pipe, byte for byte"; else fail "WRF: vsv-convert = the pipe, byte for byte" "differ"; fi
expect "any 3-D WRF variable by name" 0 "$B/vsv-convert" -q --vars U,W,T "$W" -o "$T/wrf-uwt.vsv"
expect "contour.cdf (not a model format) exits 1" 1 "$B/vsv-extract" "$D/ncl/contour.cdf"
has "the netCDF kind is named" "$T/err" "none of WRF output"
exit 0
