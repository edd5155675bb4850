#!/bin/sh
# cli_heights.sh — native model levels drawn at their heights: the same data
# converted with --vertical native and with even heights, seen from the side
# with the terrain off, covers the same pixels (>= 75 % of those either
# covers are covered by both) with a PSNR >= 18 dB over them. On the bundled
# MM5 sample always; on the real MM5 run and a WRF file when ../shared is here.
B=${B:-build}
SHARED=${SHARED:-../shared}
T=$(mktemp -d "${TMPDIR:-/tmp}/vsv-heights.XXXXXX")
trap 'rm -rf "$T"' EXIT
. tests/cli_lib.sh

# side NAME MODELFILE VARS [STEP]: converts both ways, renders both, compares
side() {
    name=$1 src=$2 vars=$3 step=${4:-}
    "$B/vsv-convert" -q "$src" -o "$T/nat.vsv" --vertical native --vars "$vars" &&
        "$B/vsv-convert" -q "$src" -o "$T/even.vsv" --vars "$vars" || { fail "$name: converts" "$(cat "$T/err" 2> /dev/null)"; return; }
    for r in raycast shearwarp; do
        for f in nat even; do
            "$B/vsv-render" -q "$T/$f.vsv" -o "$T/$f.png" --no-terrain --no-annotate --camera 180,5 --exaggerate 60 \
                --size 400x300 -r $r ${step:+--time $step} 2> "$T/err"
        done
        got=$(/usr/bin/python3 tests/imgcmp.py "$T/nat.png" "$T/even.png")
        if echo "$got" | awk '{ exit !($1 >= 75 && $2 >= 18) }'; then
            pass "$name, $r: native and even clouds agree ($got: % covered by both, PSNR dB)"
        else
            fail "$name, $r: native and even clouds agree" "covered by both / either $(echo "$got" | cut -d' ' -f1) % (want >= 75), PSNR $(echo "$got" | cut -d' ' -f2) dB (want >= 18)"
        fi
    done
}

if ! /usr/bin/python3 -c 'import numpy, PIL' 2> /dev/null; then
    pass "native heights: skipped (no python3-numpy / python3-pil)"
    exit 0
fi
side "MM5 sample (CLW, ICE, SNOW at 3 h)" samples/mm5/MMOUT_DOMAIN1_CROP CLW,ICE,SNOW 3
absent "native heights on the real MM5 run" mm5/run1/MMOUT_DOMAIN1 ||
    side "MM5 run (CLW, SNOW, ICE at 3 h)" "$(data mm5/run1/MMOUT_DOMAIN1)" CLW,SNOW,ICE 3
side "WRF Katrina (QCLOUD, QRAIN)" "$(data wrf/katrina_ci_test_file.nc)" QCLOUD,QRAIN
side "WRF allvars (QCLOUD, QICE, QSNOW)" "$(data wrf/wrf_d01_allvars_cropped.nc)" QCLOUD,QICE,QSNOW
# the file says where its levels are
"$B/vsv-convert" -q samples/mm5/MMOUT_DOMAIN1_CROP -o "$T/nat.vsv" --vertical native --vars CLW
expect "vsv-info on a file with per-column heights" 0 "$B/vsv-info" "$T/nat.vsv"
has "vsv-info says the format is 4.0 (its terrain and land use coded, the wind a vector, Rice-coded bricks)" "$T/out" "format 4.0"
has "vsv-info names the heights" "$T/out" "per-column heights"
