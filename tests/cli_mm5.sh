#!/bin/sh
# cli_mm5.sh — the MM5 conversion tools from the command line: vsv-extract,
# vsv-interp, vsv-convert (byte-identical to the pipe), vsv-info on MM5 files,
# messages and exit codes on bad input. Prints PASS/FAIL lines.
B=${B:-build}
SHARED=${SHARED:-../shared}
T=$(mktemp -d "${TMPDIR:-/tmp}/vsv-cli-mm5.XXXXXX")
trap 'rm -rf "$T"' EXIT
. tests/cli_lib.sh
CROP=samples/mm5/MMOUT_DOMAIN1_CROP
MMOUT=$(data mm5/run1/MMOUT_DOMAIN1)

for tool in vsv-interp vsv-convert; do
    expect "$tool --help exits 0" 0 "$B/$tool" --help
    has "$tool --help prints usage" "$T/out" "Usage: $tool"
    expect "$tool --version exits 0" 0 "$B/$tool" --version
    expect "$tool with a bad option exits 2" 2 "$B/$tool" --bogus
done
expect "vsv-interp without --time-res exits 2" 2 "$B/vsv-interp"
expect "vsv-interp --time-res 10x exits 2" 2 "$B/vsv-interp" --time-res 10x
expect "vsv-convert --vertical sideways exits 2" 2 "$B/vsv-convert" --vertical sideways -o "$T/x.vsv" "$CROP"

# the pipe and the one process give the same bytes
"$B/vsv-extract" --vertical even "$CROP" | "$B/vsv-interp" --time-res 10m | "$B/vsv-pack" -q -o "$T/pipe.vsv"
expect "vsv-convert --time-res 10m" 0 "$B/vsv-convert" --vertical even -q --time-res 10m "$CROP" -o "$T/conv.vsv"
same "vsv-convert is byte-identical to extract | interp | pack" "$T/pipe.vsv" "$T/conv.vsv"
"$B/vsv-extract" --vertical native --vars T,CLW,RNW --times 1:3 "$CROP" | "$B/vsv-pack" -q --bits 8 --scale CLW=log -o "$T/pipe2.vsv"
"$B/vsv-convert" -q --vertical native --vars T,CLW,RNW --times 1:3 --bits 8 --scale CLW=log "$CROP" -o "$T/conv2.vsv"
same "identical with native levels, selections and pack options" "$T/pipe2.vsv" "$T/conv2.vsv"
"$B/vsv-info" -f times.1 "$T/conv.vsv" > "$T/out"
has "10-minute frames from 00:00" "$T/out" '1995-10-24T00:10:00Z'
"$B/vsv-info" -f bricks.total "$T/conv.vsv" > "$T/out"
has "19 frames x 8 species (5 and the wind's 3) x 8 bricks" "$T/out" "1216"
"$B/vsv-info" --json "$T/conv.vsv" > "$T/conv.json"
if /usr/bin/python3 - "$T/conv.json" <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
assert [s["name"] for s in d["species"]] == ["Q", "CLW", "RNW", "ICE", "SNOW", "wind_east", "wind_north", "wind_up"]
assert d["projection"]["name"] == "lcc" and d["projection"]["lat1"] == 50 and d["projection"]["lat2"] == 33
assert abs(d["corners"][0]["lat"] - 42.70) < 0.01 and abs(d["corners"][0]["lon"] + 127.32) < 0.01
assert d["grid"]["vertical"]["kind"] == "even" and d["grid"]["terrain"] and d["grid"]["landuse"]
assert d["source"]["model"] == "MM5 v3" and "PTOP" in d["attributes"]
PY
then pass "converted MM5: species, projection, corners, terrain in the JSON"; else fail "converted MM5: species, projection, corners, terrain in the JSON" "see above"; fi
"$B/vsv-info" -f grid.vertical.levels "$T/conv2.vsv" > "$T/out"
has "native file records level heights" "$T/out" "["

# vsv-info on model files
expect "vsv-info on an MM5 file" 0 "$B/vsv-info" "$CROP"
has "MM5 big-header essentials" "$T/out" "Lambert conformal, centre 38, -97, true latitudes 50 / 33"
has "MM5 field list" "$T/out" "CLOUD WATER MIXING RATIO"
has "MM5 base state" "$T/out" "P00 100000 Pa, TS0 290 K, TLP 50 K"
if ! absent "the MM5 TERRAIN file" mm5/TERRAIN_DOMAIN1; then
    expect "vsv-info on the TERRAIN file" 0 "$B/vsv-info" "$SHARED/data/mm5/TERRAIN_DOMAIN1"
    has "TERRAIN written by program 1" "$T/out" "written by program 1 (TERRAIN"
    expect "vsv-extract of a TERRAIN file (no times) exits 1" 1 "$B/vsv-extract" --vertical even "$SHARED/data/mm5/TERRAIN_DOMAIN1"
    has "no output times is named" "$T/err" "no output times"
fi

# selections and bad input
expect "a 2-D field is refused, listing the 3-D ones" 1 "$B/vsv-extract" --vertical even --vars TERRAIN "$CROP"
has "2-D refusal lists 3-D variables" "$T/err" "not a 3-D variable 'TERRAIN'; available: U, V, T, Q, CLW, RNW, ICE, SNOW, W"
expect "an unknown variable is refused" 1 "$B/vsv-extract" --vertical even --vars NOPE "$CROP"
expect "an empty --vars without --derive is misuse" 2 "$B/vsv-convert" -q --vars "" "$CROP" -o "$T/empty.vsv"
has "... saying so" "$T/err" "vsv-convert: --vars '': no variable (with --derive: the derived ones alone)"
expect "a --vars list of an empty name is misuse" 2 "$B/vsv-convert" -q --vars , "$CROP" -o "$T/empty.vsv"
expect "a --vars list ending in a comma is misuse" 2 "$B/vsv-extract" --vars CLW, "$CROP"
has "... saying so" "$T/err" "vsv-extract: --vars 'CLW,': an empty name"
head -c 200000 "$CROP" > "$T/MMOUT_CUT"
expect "a cut file exits 1" 1 "$B/vsv-convert" --vertical even "$T/MMOUT_CUT" -o "$T/cut.vsv"
has "cut file: record and byte offset" "$T/err" "vsv-convert: $T/MMOUT_CUT: record 5 at byte offset 117792: file ends inside the record"
if [ ! -e "$T/cut.vsv" ]; then pass "no output after a failed conversion"; else fail "no output after a failed conversion" "exists"; fi
printf 'not a model file at all, just text\n' > "$T/notes.txt"
expect "a text file exits 1" 1 "$B/vsv-extract" --vertical even "$T/notes.txt"
has "text file: not an MM5 v3 file" "$T/err" "not an MM5 v3 file"
expect "the same file twice overlaps" 1 "$B/vsv-convert" --vertical even "$CROP" "$CROP" -o "$T/twice.vsv"
has "overlap names both files" "$T/err" "overlap in time"

# the real MMOUT through vsv-convert with both byte orders of threads
if ! absent "the real MMOUT" mm5/run1/MMOUT_DOMAIN1; then
    expect "real MMOUT converts" 0 "$B/vsv-convert" --vertical even -q --threads 2 "$MMOUT" -o "$T/mm5-2.vsv"
    expect "real MMOUT converts with one thread" 0 "$B/vsv-convert" --vertical even -q --threads 1 "$MMOUT" -o "$T/mm5-1.vsv"
    same "thread count does not change the file" "$T/mm5-1.vsv" "$T/mm5-2.vsv"
    expect "real MMOUT .vsv checks" 0 "$B/vsv-info" --check "$T/mm5-2.vsv"
fi
exit 0
