#!/bin/sh
# cli_derive.sh — vsv-convert --derive (issue 35 item 4): the built-ins
# against a hand computation from the MM5 file itself (tests/derive_check.py,
# its own MM5 reader) on the bundled crop and the real run, at the model
# times and interpolated with --time-res; inputs read but not written; the
# units and formula in the file; WRF by hand too; vsv-extract and
# vsv-convert-mpi giving the same bytes; bad specs exit 1 naming the
# character or what the file has, writing nothing. Prints PASS/FAIL lines.
B=${B:-build}
SHARED=${SHARED:-../shared}
PY=${PYTHON:-/usr/bin/python3}
T=$(mktemp -d "${TMPDIR:-/tmp}/vsv-cli-derive.XXXXXX")
trap 'rm -rf "$T"' EXIT
. tests/cli_lib.sh
CROP=samples/mm5/MMOUT_DOMAIN1_CROP
check() { PYTHONPATH="$B/python" "$PY" tests/derive_check.py "$@"; }
have_py=1
PYTHONPATH="$B/python" "$PY" -c 'import numpy, vesuvius' 2> /dev/null || {
    have_py=0
    echo "  (the hand computations skipped: the Python module vesuvius or numpy is missing)"
}

for t in vsv-convert vsv-extract; do
    expect "$t --help exits 0" 0 "$B/$t" --help
    has "$t --help lists --derive" "$T/out" "--derive SPEC"
done

# the crop: no PP, so condensate and wind_speed; Q selected, the inputs not
expect "crop: --vars Q --derive condensate --derive wind_speed" 0 "$B/vsv-convert" -q --vars Q \
    --derive condensate --derive wind_speed "$CROP" -o "$T/crop.vsv"
"$B/vsv-info" --json "$T/crop.vsv" > "$T/crop.json"
if "$PY" - "$T/crop.json" << 'PY'; then
import json, sys
d = json.load(open(sys.argv[1]))
sp = {s["name"]: s for s in d["species"]}
assert list(sp) == ["Q", "condensate", "wind_speed", "wind_east", "wind_north", "wind_up"], list(sp)
assert sp["condensate"]["units"] == "kg kg-1" and "CLW+RNW+ICE+SNOW" in sp["condensate"]["description"]
assert sp["wind_speed"]["units"] == "m s-1" and "sqrt(U^2+V^2)" in sp["wind_speed"]["description"]
assert d["attributes"]["derived condensate"] == "total condensate: CLW+RNW+ICE+SNOW", d["attributes"]
PY
    pass "crop: species Q condensate wind_speed and the wind (inputs read, not written), units and formulas in the file"
else
    fail "crop: species Q condensate wind_speed and the wind (inputs read, not written), units and formulas in the file" \
        "see above"
fi
expect "vsv-info shows the formula" 0 "$B/vsv-info" "$T/crop.vsv"
has "... in the species' description" "$T/out" "total condensate: CLW+RNW+ICE+SNOW"
if [ $have_py = 1 ]; then
    check "$CROP" "$T/crop.vsv" condensate wind_speed
    "$B/vsv-convert" -q --vars '' --derive condensate -r 20m "$CROP" -o "$T/crop20.vsv"
    check "$CROP" "$T/crop20.vsv" condensate
fi
expect "crop: a user expression with units" 0 "$B/vsv-convert" -q --vars CLW \
    --derive 'twice=2*CLW + 0*"SNOW":g/kg' "$CROP" -o "$T/expr.vsv"
expect "... vsv-info" 0 "$B/vsv-info" --json "$T/expr.vsv"
has "... its units" "$T/out" '"units": "g/kg"'
has "... its formula" "$T/out" '"derived twice": "2*CLW + 0*\"SNOW\""'
# a derived name in --vars asks for nothing more (it is written anyway)
expect "crop: --vars naming the derived variable" 0 "$B/vsv-convert" -q --vars twice,CLW \
    --derive 'twice=2*CLW' "$CROP" -o "$T/named.vsv"
"$B/vsv-info" -f species.0.name -f species.1.name -f species.2.name "$T/named.vsv" > "$T/out" # (-f repeats)
[ "$(tr '\n' ' ' < "$T/out")" = "CLW twice wind_east " ] && pass "... CLW, then twice, then the wind" ||
    fail "... CLW, then twice, then the wind" "$(tr '\n' ' ' < "$T/out")"
expect "vsv-extract too" 0 sh -c "'$B/vsv-extract' --vars twice --derive 'twice=2*CLW' '$CROP' > '$T/named.fs'"
# an expression no value fits: written, every cell no data, and said
expect "crop: a derived variable with no finite value" 0 "$B/vsv-convert" --vars '' \
    --derive 'bad=log(0-CLW-1)' "$CROP" -o "$T/bad.vsv"
has "... a note says so" "$T/err" "vsv-convert: note: bad: no finite value at any step: every cell is no data"
expect "... vsv-info" 0 "$B/vsv-info" "$T/bad.vsv"
has "... shows no value, not inf and -inf" "$T/out" "    bad                         no value     no value"
if [ $have_py = 1 ] && PYTHONPATH="$B/python" "$PY" -c '
import sys, numpy, vesuvius
f = vesuvius.open(sys.argv[1])
e = {s.name: s.max_abs_error for s in f.species}
for t in range(len(f.times)):
    d = numpy.abs(f.read("twice", t) - 2 * f.read("CLW", t).astype(numpy.float64)).max()
    assert d <= e["twice"] + 2 * e["CLW"], (t, d)' "$T/expr.vsv"; then
    pass "... twice = 2 * CLW within both bounds at every time"
elif [ $have_py = 1 ]; then
    fail "... twice = 2 * CLW within both bounds at every time" "see above"
fi

# one program: vsv-extract | vsv-pack and vsv-convert-mpi give vsv-convert's bytes
"$B/vsv-convert" -q --derive condensate --derive 'r=RNW/(CLW+1e-9)' "$CROP" -o "$T/c1.vsv"
"$B/vsv-extract" --derive condensate --derive 'r=RNW/(CLW+1e-9)' "$CROP" 2> /dev/null |
    "$B/vsv-pack" -q -o "$T/c2.vsv" 2> /dev/null
same "vsv-extract --derive | vsv-pack is vsv-convert --derive" "$T/c1.vsv" "$T/c2.vsv"
if [ -x "$B/vsv-convert-mpi" ] && command -v mpirun > /dev/null 2>&1; then
    mpi_env
    "$PY" tests/mm5_split.py "$CROP" "$T/cut" > /dev/null
    "$B/vsv-convert" -q -r 20m --derive condensate --derive wind_speed "$T"/cut_0? -o "$T/m1.vsv"
    expect "vsv-convert-mpi -np 3 --derive" 0 $MPIRUN -np 3 "$B/vsv-convert-mpi" -q -r 20m --derive condensate \
        --derive wind_speed "$T"/cut_0? -o "$T/m2.vsv"
    same "... byte-identical to vsv-convert" "$T/m1.vsv" "$T/m2.vsv"
else
    echo "  (vsv-convert-mpi not built or no mpirun: its --derive not checked)"
fi

# refusals: exit 1, the reason, nothing written
refuse() {
    what=$1 msg=$2
    shift 2
    rm -f "$T/bad.vsv"
    expect "$what exits 1" 1 "$B/vsv-convert" -q "$@" "$CROP" -o "$T/bad.vsv"
    has "... says: $msg" "$T/err" "$msg"
    [ ! -e "$T/bad.vsv" ] && pass "... writes nothing" || fail "... writes nothing" "$T/bad.vsv exists"
}
refuse "a value missing" "vsv-convert: --derive 'X=CLW+*2': expected a value at character 7" --derive 'X=CLW+*2'
refuse "an unknown name" "--derive 'X=2*CLWW': unknown name 'CLWW' at character 5; the file's 3-D fields: U V T Q CLW" \
    --derive 'X=2*CLWW'
refuse "an unknown function" "unknown function 'cos' (there are sqrt exp log abs min max) at character 3" \
    --derive 'X=cos(T)'
refuse "a missing parenthesis" "--derive 'X=(T+1:K': expected ')' at character 7" --derive 'X=(T+1:K'
refuse "a name of the file's" "--derive 'T=CLW': T is taken" --derive 'T=CLW'
refuse "a name twice" "--derive 'c=RNW': c is taken" --derive 'c=CLW' --derive 'c=RNW'
refuse "a wind name" "wind.u is taken" --derive 'wind.u=U'
refuse "a control byte in the units" "vsv-convert: --derive X: its units hold control byte 0x09 (at character 2)" \
    --derive "$(printf 'X=T:K\ttab')"
refuse "a bad name" "the name must be 1 to 55 letters" --derive '2x=CLW'
refuse "an expression named as a built-in" "--derive 'theta=T': theta is a built-in's name" --derive 'theta=T'
refuse "an unknown built-in" "--derive 'dewpoint': no such built-in (condensate, wind_speed, theta, rh)" \
    --derive dewpoint
refuse "theta without PP" "--derive theta: this MM5 v3 file lacks PP (pressure = PSTARCRS*SIGMAH+PTOP+PP)" \
    --derive theta
refuse "rh without PP" "--derive rh: this MM5 v3 file lacks PP" --derive rh
refuse "pressure without PP" "--derive 'p=pressure': pressure: this MM5 v3 file lacks PP" --derive 'p=pressure'
WRF=$(data wrf/wrf_cropped.nc)
expect "WRF without U and V: wind_speed refused" 1 "$B/vsv-convert" -q --derive wind_speed "$WRF" -o "$T/bad.vsv"
has "... naming them" "$T/err" "--derive wind_speed: this WRF file has no 3-D U and V"
expect "WRF without hydrometeors: condensate refused" 1 "$B/vsv-convert" -q --derive condensate "$WRF" \
    -o "$T/bad.vsv"
has "... naming them" "$T/err" "no hydrometeor mixing ratio (MM5: CLW RNW ICE SNOW GRAUPEL; WRF: QCLOUD"

# WRF: theta is T + 300 (its T is theta - 300); rh and pressure computed
expect "WRF: --derive theta --derive rh --derive p=pressure:Pa" 0 "$B/vsv-convert" -q --vars '' --derive theta \
    --derive rh --derive 'p=pressure:Pa' "$WRF" -o "$T/wrf.vsv"
"$B/vsv-info" --json "$T/wrf.vsv" > "$T/wrf.json"
if [ $have_py = 1 ] && "$PY" tests/model_extremes.py "$WRF" T > "$T/wt" && "$PY" - "$T/wrf.json" "$T/wt" << 'PY'; then
import json, sys
d = json.load(open(sys.argv[1]))
lo, hi = map(float, open(sys.argv[2]).read().split()[1:3])
sp = {s["name"]: s for s in d["species"]}
th = sp["theta"]
assert "WRF's T is theta-300" in th["description"], th
assert abs(th["min"] - (lo + 300)) <= th["max_abs_error"] and abs(th["max"] - (hi + 300)) <= th["max_abs_error"], th
assert sp["p"]["units"] == "Pa" and "pressure = P+PB" in d["attributes"]["derived p"]
assert "QVAPOR*pressure/(0.622+QVAPOR)" in d["attributes"]["derived rh"] and sp["rh"]["units"] == "%"
assert 0 < sp["rh"]["min"] and sp["rh"]["max"] < 110
PY
    pass "WRF: theta spans T's extremes + 300 K, rh 0..110 %, pressure P+PB in Pa"
elif [ $have_py = 1 ]; then
    fail "WRF: theta spans T's extremes + 300 K, rh 0..110 %, pressure P+PB in Pa" "see above"
fi

# WRF by hand: Katrina (staggered U V, QCLOUD QRAIN) and the cropped run
KAT=$(data wrf/katrina_ci_test_file.nc)
if [ $have_py = 1 ] && "$PY" -c 'import netCDF4' 2> /dev/null; then
    expect "WRF Katrina: the four built-ins" 0 "$B/vsv-convert" -q --vars '' --derive condensate \
        --derive wind_speed --derive theta --derive rh "$KAT" -o "$T/kat.vsv"
    check "$KAT" "$T/kat.vsv" condensate wind_speed theta rh
    check "$WRF" "$T/wrf.vsv" theta rh
else
    echo "  (python3-netcdf4 missing: the WRF hand computations skipped)"
fi

# the real MM5 run: every built-in, at the model times and every 30 min
MMOUT=$(data mm5/run1/MMOUT_DOMAIN1)
if ! absent "MM5 run: the built-ins by hand" mm5/run1/MMOUT_DOMAIN1 && [ $have_py = 1 ]; then
    expect "MM5 run: the four built-ins" 0 "$B/vsv-convert" -q --vars CLW --derive condensate --derive wind_speed \
        --derive theta --derive rh "$MMOUT" -o "$T/run.vsv"
    check "$MMOUT" "$T/run.vsv" condensate wind_speed theta rh
    expect "MM5 run: theta and rh every 30 min" 0 "$B/vsv-convert" -q --vars '' -r 30m --derive theta \
        --derive rh "$MMOUT" -o "$T/run30.vsv"
    check "$MMOUT" "$T/run30.vsv" theta rh
    expect "... vsv-info" 0 "$B/vsv-info" "$T/run.vsv"
    has "... theta's formula with MM5's pressure" "$T/out" \
        "potential temperature: T*(100000/pressure)^0.2857; pressure = PSTARCRS*SIGMAH+PTOP+PP (Pa)"
    has "... rh's with Bolton's es" "$T/out" \
        "100*(Q*pressure/(0.622+Q))/(611.2*exp(17.67*(T-273.15)/(T-29.65)))"
    # exported to CF netCDF: the built-ins get their standard names
    if command -v udunits2 > /dev/null && "$PY" -c 'import netCDF4' 2> /dev/null; then
        expect "MM5 run: the built-ins export to CF netCDF" 0 "$B/vsv-export" -q "$T/run.vsv" --netcdf "$T/run.nc"
        "$PY" tests/cf_check.py "$T/run.nc" > "$T/cf" 2>&1
        if ! grep -q '^FAIL' "$T/cf" && grep -q "rule 3 rh: units % convert to 1" "$T/cf"; then
            pass "... every CF rule holds: theta air_potential_temperature, wind_speed, rh relative_humidity"
        else
            fail "... every CF rule holds" "$(grep -v '^PASS' "$T/cf" | head -5)"
        fi
        ncdump -h "$T/run.nc" > "$T/h"
        has "... theta is air_potential_temperature" "$T/h" 'theta:standard_name = "air_potential_temperature"'
        has "... rh is relative_humidity" "$T/h" 'rh:standard_name = "relative_humidity"'
        if grep -q 'condensate:standard_name' "$T/h"; then
            fail "... condensate gets no standard name (CF has none for the total)" "$(grep condensate: "$T/h")"
        else
            pass "... condensate gets no standard name (CF has none for the total)"
        fi
    fi
fi
