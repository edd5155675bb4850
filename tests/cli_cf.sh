#!/bin/sh
# cli_cf.sh — vsv-export --netcdf against the CF rules tests/cf_check.py
# writes out (units UDUNITS knows, standard names with their canonical
# units, height above the ground vs altitude above sea level, coordinates
# and grid mappings that exist) on MM5 (bundled), CMAQ and CAMx netCDF
# (the IOAPI files of tests/corpus: no terrain, and terrain from topo),
# and WRF (corpus crop); CAMx UAM-IV heights: tests/test_camx_met.c.
B=${B:-build}
SHARED=${SHARED:-../shared}
T=$(mktemp -d "${TMPDIR:-/tmp}/vsv-cli-cf.XXXXXX")
trap 'rm -rf "$T"' EXIT
. tests/cli_lib.sh
if ! command -v udunits2 > /dev/null; then
    echo "SKIP CF checks: udunits2 (Debian udunits-bin) is not installed"
    exit 0
fi

# NAME: convert ARGS... then export and check
cf() {
    f=$1
    shift
    rm -f "$T/$f.vsv" "$T/$f.nc"
    expect "$f: converts" 0 "$B/vsv-convert" --vertical even -q "$@" -o "$T/$f.vsv"
    expect "$f: exports" 0 "$B/vsv-export" -q "$T/$f.vsv" --netcdf "$T/$f.nc"
    /usr/bin/python3 tests/cf_check.py "$T/$f.nc" > "$T/check" 2>&1
    n=$(grep -c '^PASS' "$T/check")
    if ! grep -q '^FAIL' "$T/check" && [ "$n" -gt 10 ]; then
        pass "$f: every CF rule holds ($n checks)"
    else
        fail "$f: every CF rule holds" "$(grep -v '^PASS' "$T/check" | head -5)"
    fi
    ncdump -h "$T/$f.nc" > "$T/$f.h"
}

cf mm5 --vars T,Q,CLW,RNW,SNOW,ICE samples/mm5/MMOUT_DOMAIN1_CROP
has "MM5 CLW is cloud_liquid_water_mixing_ratio" "$T/mm5.h" 'CLW:standard_name = "cloud_liquid_water_mixing_ratio"'
has "MM5 Q is humidity_mixing_ratio" "$T/mm5.h" 'Q:standard_name = "humidity_mixing_ratio"'
has "MM5 T is air_temperature" "$T/mm5.h" 'T:standard_name = "air_temperature"'
# a species without units (GrADS's, a derived one without :UNITS) has no
# units attribute (it got units = "", which UDUNITS reads as dimensionless)
cf bare --vars CLW --no-winds --derive 'bare=CLW*2' samples/mm5/MMOUT_DOMAIN1_CROP
if grep -q 'bare:units' "$T/bare.h"; then fail "a species without units has no units attribute" "$(grep 'bare:units' "$T/bare.h")"; else pass "a species without units has no units attribute"; fi
has "... the others keep theirs" "$T/bare.h" 'CLW:units = "kg/kg"'
has "MM5 RNW is the mass fraction of rain" "$T/mm5.h" 'RNW:standard_name = "mass_fraction_of_rain_in_air"'
has "... and says it is the model's mixing ratio" "$T/mm5.h" "RNW:comment = \"the model\'s mixing ratio (per kg of dry air)"
has "MM5 heights are altitudes (terrain under them)" "$T/mm5.h" 'z:standard_name = "altitude"'
cf mm5-native --vars CLW --vertical native samples/mm5/MMOUT_DOMAIN1_CROP
has "native levels: per-column altitude" "$T/mm5-native.h" 'height:standard_name = "altitude"'

cf cmaq tests/corpus/netcdf/ioapi-cmaq.nc
has "CMAQ heights are above the ground: height" "$T/cmaq.h" 'z:standard_name = "height"'
has "... said so" "$T/cmaq.h" 'z:long_name = "height above the ground"'
has "ppmV is written ppm" "$T/cmaq.h" 'O3:units = "ppm"'
has "... keeping the model's spelling" "$T/cmaq.h" 'O3:vsv_units_original = "ppmV"'
has "micrograms/m**3 is written ug m-3" "$T/cmaq.h" 'PM25:units = "ug m-3"'
has "ozone is mole_fraction_of_ozone_in_air" "$T/cmaq.h" 'O3:standard_name = "mole_fraction_of_ozone_in_air"'
has "history says the units were respelt" "$T/cmaq.h" "units in the model\'s spelling written as UDUNITS spells them"
if grep -q 'PM25:standard_name' "$T/cmaq.h"; then fail "PM2.5 in ug m-3 gets no mole fraction" "$(grep PM25:standard_name "$T/cmaq.h")"; else pass "PM2.5 in ug m-3 gets no mole fraction"; fi
"$B/vsv-info" "$T/cmaq.vsv" > "$T/info"
has "vsv-info: CMAQ heights count from the ground" "$T/info" "heights count from the ground"
# the round trip keeps the datum
expect "the CMAQ export converts back" 0 "$B/vsv-convert" --vertical even -q "$T/cmaq.nc" -o "$T/back.vsv"
"$B/vsv-info" "$T/back.vsv" > "$T/info"
has "... with its heights above the ground" "$T/info" "heights count from the ground"

# CB05's ethene ETH and ethane ETHA, in ppbV: a standard name is the whole
# word's (ETH is not ETHA, it gets none), ppbV is written ppb
/usr/bin/python3 - "$T/eth-in.nc" << 'EOP'
import shutil, sys, netCDF4
shutil.copy("tests/corpus/netcdf/ioapi-cmaq.nc", sys.argv[1])
d = netCDF4.Dataset(sys.argv[1], "a")
for old, new, desc in (("O3", "ETH", "ethene"), ("PM25", "ETHA", "ethane")):
    d.renameVariable(old, new)
    d[new].units, d[new].var_desc = "ppbV".ljust(16), desc.ljust(10)
d.close()
EOP
cf eth "$T/eth-in.nc"
has "ppbV is written ppb" "$T/eth.h" 'ETH:units = "ppb"'
has "ETHA (ethane) is mole_fraction_of_ethane_in_air" "$T/eth.h" 'ETHA:standard_name = "mole_fraction_of_ethane_in_air"'
if grep -q 'ETH:standard_name' "$T/eth.h"; then fail "ETH (ethene) gets no standard name" "$(grep ETH:standard_name "$T/eth.h")"; else pass "ETH (ethene) gets no standard name"; fi
cf camx-nc tests/corpus/netcdf/ioapi-camx.nc
has "CAMx netCDF with topo: heights lifted onto it, altitude" "$T/camx-nc.h" 'z:standard_name = "altitude"'
"$B/vsv-info" "$T/camx-nc.vsv" > "$T/info"
has "vsv-info: CAMx on topo counts from sea level" "$T/info" "heights count from sea level"

cf wrf --vars QVAPOR,T tests/corpus/netcdf/wrf-crop.nc
has "WRF QVAPOR is humidity_mixing_ratio" "$T/wrf.h" 'QVAPOR:standard_name = "humidity_mixing_ratio"'
if grep -q 'T:standard_name' "$T/wrf.h"; then fail "WRF T (perturbation theta) gets no standard name" "$(grep T:standard_name "$T/wrf.h")"; else pass "WRF T (perturbation theta) gets no standard name"; fi

