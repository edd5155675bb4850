#!/bin/sh
# cli_netcdf.sh — vsv-export --netcdf (CF-1.8 netCDF-4) and the CF reader:
# options, the file's structure as ncdump sees it (no warnings), atomic output
# that never destroys what was there, and the round trip back through
# vsv-extract / vsv-convert on the real MM5 sample.
B=${B:-build}
T=$(mktemp -d "${TMPDIR:-/tmp}/vsv-cli-netcdf.XXXXXX")
trap 'rm -rf "$T"' EXIT
. tests/cli_lib.sh
"$B/vsv-convert" --vertical even -q samples/mm5/MMOUT_DOMAIN1_CROP -o "$T/crop.vsv"
expect "vsv-export --help names --netcdf" 0 "$B/vsv-export" --help
has "--netcdf OUT.nc" "$T/out" "--netcdf OUT.nc"
expect "--vdb and --netcdf together exit 2" 2 "$B/vsv-export" "$T/crop.vsv" --vdb "$T/a%d.vdb" --netcdf "$T/a.nc"
ln "$T/crop.vsv" "$T/same.nc"
expect "--netcdf onto the input exits 2" 2 "$B/vsv-export" "$T/crop.vsv" --netcdf "$T/same.nc"
has "naming it" "$T/err" "is the input"
# an output named as another kind of file: refused before anything is read
expect "--netcdf with a .vsv name exits 2" 2 "$B/vsv-export" "$T/crop.vsv" --netcdf "$T/out.vsv"
has "... saying whose name it is" "$T/err" "vsv-export: --netcdf $T/out.vsv: the name of a Vesuvius file (.vsv); --netcdf writes netCDF-4 (.nc)"
expect "--vdb with a .nc name exits 2" 2 "$B/vsv-export" "$T/crop.vsv" --vdb "$T/v_%d.NC"
has "... any case" "$T/err" "--vdb $T/v_%d.NC: the name of a netCDF file (.nc); --vdb writes OpenVDB (.vdb)"
expect "--gltf with a .ply name exits 2" 2 "$B/vsv-export" "$T/crop.vsv" --iso CLW:5e-5 --gltf "$T/c.ply"
has "... naming both" "$T/err" "--gltf $T/c.ply: the name of a PLY mesh (.ply); --gltf writes glTF 2.0 (.gltf)"
[ ! -e "$T/out.vsv" ] && [ ! -e "$T/c.ply" ] && pass "... and nothing written" || fail "... and nothing written" "$(ls "$T")"
expect "vsv-convert -o x.nc exits 2" 2 "$B/vsv-convert" samples/mm5/MMOUT_DOMAIN1_CROP -o "$T/conv.nc"
has "... as vsv-export says it" "$T/err" "vsv-convert: -o $T/conv.nc: the name of a netCDF file (.nc); -o writes a .vsv file"
expect "vsv-pack -o x.PNG exits 2" 2 "$B/vsv-pack" -o "$T/pack.PNG" /dev/null
has "... in any case" "$T/err" "vsv-pack: -o $T/pack.PNG: the name of a PNG image (.png); -o writes a .vsv file"
[ ! -e "$T/conv.nc" ] && [ ! -e "$T/pack.PNG" ] && pass "... and nothing written" || fail "... and nothing written" "$(ls "$T")"
expect "--netcdf with a name of no known kind is the user's" 0 "$B/vsv-export" -q "$T/crop.vsv" --netcdf "$T/any.cdf" --time 0
expect "into a missing folder exits 1" 1 "$B/vsv-export" "$T/crop.vsv" --netcdf "$T/nope/x.nc"
has "saying why" "$T/err" "cannot create a temporary file beside it"
echo "keep me" > "$T/old.nc"
expect "a damaged .vsv exits 1" 1 "$B/vsv-export" tests/golden/bad/payload.vsv --netcdf "$T/old.nc"
has "the old file is untouched" "$T/old.nc" "keep me"
[ "$(ls "$T" | grep -c tmp)" = 0 ] && pass "no temporary left behind" || fail "no temporary left behind" "$(ls "$T")"

expect "every step and species" 0 "$B/vsv-export" -q "$T/crop.vsv" --netcdf "$T/crop.nc"
timeout 120 ncdump -hs "$T/crop.nc" > "$T/h" 2> "$T/herr"
[ $? = 0 ] && [ ! -s "$T/herr" ] && pass "ncdump -h reads it without a warning" || fail "ncdump -h" "$(cat "$T/herr")"
has "netCDF-4" "$T/h" '_Format = "netCDF-4"'
has "CF-1.8" "$T/h" ':Conventions = "CF-1.8"'
has "time in seconds since the first step" "$T/h" 'time:units = "seconds since 1995-10-24 00:00:00"'
has "the projection as a grid_mapping" "$T/h" 'crs:grid_mapping_name = "lambert_conformal_conic"'
has "with its parallels" "$T/h" 'crs:standard_parallel = 50., 33.'
has "2-D latitude" "$T/h" "double lat(y, x)"
has "heights as altitude" "$T/h" 'z:standard_name = "altitude"'
has "a species on (time, z, y, x)" "$T/h" "float SNOW(time, z, y, x)"
has "its units" "$T/h" 'SNOW:units = "kg/kg"'
has "its long_name" "$T/h" 'SNOW:long_name = "SNOW MIXING RATIO"'
has "its auxiliary coordinates" "$T/h" 'SNOW:coordinates = "lat lon"'
has "the quantisation bound" "$T/h" "SNOW:vsv_max_abs_error = 1.77909152"
has "chunked by step" "$T/h" "SNOW:_ChunkSizes = 1, 40, 39, 39"
has "deflated" "$T/h" "SNOW:_DeflateLevel = 4"
has "no data as NaN where the species has it" "$T/h" "Q:_FillValue = NaNf"
has "terrain" "$T/h" 'terrain:standard_name = "surface_altitude"'
timeout 120 ncdump "$T/crop.nc" > /dev/null 2> "$T/herr"
[ $? = 0 ] && [ ! -s "$T/herr" ] && pass "ncdump reads all the data without a warning" || fail "ncdump" "$(cat "$T/herr")"
mode=$(stat -c %a "$T/crop.nc")
[ "$mode" = "$(printf '%o' $(( 0666 & ~$(umask) )))" ] && pass "the file has the umask's mode ($mode)" || fail "mode" "$mode"

# back through the CF reader: the same values
expect "vsv-info describes it" 0 "$B/vsv-info" "$T/crop.nc"
has "as CF netCDF, projection restored" "$T/out" "projection  lcc, lat0 38, lon0 -97, lat1 50, lat2 33"
expect "vsv-extract --list reads it" 0 "$B/vsv-extract" --list "$T/crop.nc"
has "its variables" "$T/out" "SNOW       CF           40 kg/kg"
timeout 120 "$B/vsv-extract" --vertical even "$T/crop.nc" | timeout 120 "$B/vsv-pack" -q -o "$T/back.vsv"
expect "packs back into a .vsv" 0 "$B/vsv-info" "$T/back.vsv"
has "same grid" "$T/out" "grid        39 x 39 x 40 cells"
has "same projection" "$T/out" "projection  lcc (lat0 38, lon0 -97, true lat 50/33, R 6370000 m)"
has "same times" "$T/out" "4 steps, 1995-10-24T00:00:00Z .. 1995-10-24T03:00:00Z"
for at in 46,-116,3000 50,-125,1000 48,-120,6000; do
    "$B/vsv-query" "$T/crop.vsv" --at $at --csv > "$T/a" 2>&1
    "$B/vsv-query" "$T/back.vsv" --at $at --csv > "$T/b" 2>&1
    same "vsv-query at $at: the round trip's values equal the original's" "$T/a" "$T/b"
done
"$B/vsv-info" --stats "$T/crop.vsv" | sed -n '/statistics/,$p' > "$T/s1"
"$B/vsv-info" --stats "$T/back.vsv" | sed -n '/statistics/,$p' > "$T/s2"
same "and every species' min/max/mean at every step" "$T/s1" "$T/s2"
# a copy cut short (a download that did not finish): named with both lengths
head -c 300000 "$T/crop.nc" > "$T/cut.nc"
full=$(stat -c %s "$T/crop.nc")
expect "a netCDF-4 file cut short exits 1" 1 "$B/vsv-convert" -q "$T/cut.nc" -o "$T/x.vsv"
has "... saying so, with both lengths" "$T/err" "cut.nc: cut short: 300000 bytes of the $full its HDF5 superblock declares"
expect "vsv-info on it exits 1" 1 "$B/vsv-info" "$T/cut.nc"
has "... the same words" "$T/err" "cut short: 300000 bytes of the $full"
head -c 30 "$T/crop.nc" > "$T/cut30.nc"
expect "cut inside its superblock (30 bytes) exits 1" 1 "$B/vsv-convert" -q "$T/cut30.nc" -o "$T/x.vsv"
has "... saying so" "$T/err" "cut30.nc: cut short: 30 bytes, inside its HDF5 superblock"
# the wind is the wind again: its vector and source restored, a trajectory the same
expect "the round trip's vsv-info" 0 "$B/vsv-info" "$T/back.vsv"
has "... names the wind vector" "$T/out" "vector      wind: wind_east wind_north wind_up (east, north, up; earth-relative)"
has "... and its source" "$T/out" "wind source U V W (MM5 v3"
"$B/vsv-query" "$T/crop.vsv" --trajectory 50,-120,3000 --for 1h --csv > "$T/a" 2>&1
"$B/vsv-query" "$T/back.vsv" --trajectory 50,-120,3000 --for 1h --csv > "$T/b" 2>&1
same "... a trajectory through it equals the original's" "$T/a" "$T/b"
expect "one step, two species" 0 "$B/vsv-export" -q "$T/crop.vsv" --netcdf "$T/one.nc" --time 2 --species SNOW,CLW
timeout 120 ncdump -h "$T/one.nc" > "$T/h"
has "time = 1" "$T/h" "time = 1 ;"
has "from that step" "$T/h" 'time:units = "seconds since 1995-10-24 02:00:00"'
grep -q "float Q(" "$T/h" && fail "only the species asked for" "Q is there" || pass "only the species asked for"
# a later run of steps: times counted from its own first step (1:00), an hour apart
expect "steps 1..3" 0 "$B/vsv-export" -q "$T/crop.vsv" --netcdf "$T/late.nc" --times 1:3 --species SNOW
timeout 120 ncdump -v time "$T/late.nc" > "$T/h"
has "... since 01:00" "$T/h" 'time:units = "seconds since 1995-10-24 01:00:00"'
has "... at 0, 3600 and 7200 s" "$T/h" "time = 0, 3600, 7200 ;"
