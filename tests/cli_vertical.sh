#!/bin/sh
# cli_vertical.sh — the default vertical grid keeps the data: converted with
# no vertical option, every species' smallest and largest value is the
# model's within its error bound (read by tests/model_extremes.py, which
# shares no code with Vesuvius), on the bundled MM5 sample always, on the
# real MM5 run and the Katrina WRF file when they are here. The even grid
# (--vertical even) is labelled as resampled in vsv-info and loses the
# MM5 run's cloud-water peak by more than the bound (why it is not the
# default). --nz and --ztop mean the even grid; with --vertical native
# they are refused.
B=${B:-build}
SHARED=${SHARED:-../shared}
PY=${PYTHON:-/usr/bin/python3}
T=$(mktemp -d "${TMPDIR:-/tmp}/vsv-vertical.XXXXXX")
trap 'rm -rf "$T"' EXIT
. tests/cli_lib.sh

if ! "$PY" -c 'import numpy' 2> /dev/null; then
    skip "default vertical grid" "no python3-numpy"
    exit 0
fi

# keeps NAME MODELFILE: the default conversion's extremes are the model's
keeps() {
    what=$1 src=$2
    expect "$what: converts with the defaults" 0 "$B/vsv-convert" -q -o "$T/d.vsv" "$src"
    "$B/vsv-info" --json "$T/d.vsv" > "$T/d.json"
    "$PY" -c "
import json, sys
d = json.load(open(sys.argv[1]))
assert d['grid']['vertical']['kind'] == 'native', d['grid']['vertical']
for s in d['species']:  # (the wind is the model's rotated: tests/cli_winds.sh checks it)
    if not s['name'].startswith('wind_'):
        print(s['name'], repr(s['min']), repr(s['max']), repr(s['max_abs_error']), s['min_max_of'])" "$T/d.json" > "$T/vsv" ||
        { fail "$what: the default grid is the model's levels" "$(head -c 300 "$T/d.json")"; return; }
    pass "$what: the default grid is the model's levels"
    "$PY" tests/model_extremes.py "$src" $(cut -d' ' -f1 "$T/vsv") > "$T/model" 2> "$T/err" ||
        { fail "$what: the model's extremes" "$(cat "$T/err")"; return; }
    if join "$T/vsv" "$T/model" | awk '{ dl = $2 - $6; dh = $3 - $7; if (dl < 0) dl = -dl; if (dh < 0) dh = -dh;
            if (dl > $4 || dh > $4 || $5 != "data") { print; bad = 1 } } END { exit bad }' > "$T/bad"; then
        pass "$what: every species' min and max within its bound of the model's ($(cut -d' ' -f1 "$T/vsv" | tr '\n' ' '))"
    else
        fail "$what: every species' min and max within its bound of the model's" "$(cat "$T/bad")"
    fi
}

keeps "MM5 sample" samples/mm5/MMOUT_DOMAIN1_CROP
absent "MM5 run" mm5/run1/MMOUT_DOMAIN1 || keeps "MM5 run" "$(data mm5/run1/MMOUT_DOMAIN1)"
if "$PY" -c 'import netCDF4' 2> /dev/null && ! absent "WRF Katrina" wrf/katrina_ci_test_file.nc; then
    keeps "WRF Katrina" "$(data wrf/katrina_ci_test_file.nc)"
fi

# the even grid: labelled, and on the MM5 run it loses the peak
expect "--vertical even" 0 "$B/vsv-convert" -q --vertical even -o "$T/e.vsv" samples/mm5/MMOUT_DOMAIN1_CROP
expect "(vsv-info)" 0 "$B/vsv-info" "$T/e.vsv"
has "vsv-info says its min and max are resampled" "$T/out" "min and max are of the values resampled onto even heights, not the model's own"
has "and how" "$T/out" "resampled   from the model's 15 levels onto 40 even heights"
if ! absent "the even grid loses the MM5 run's cloud-water peak" mm5/run1/MMOUT_DOMAIN1; then
    "$B/vsv-convert" -q --vertical even --vars CLW -o "$T/e2.vsv" "$(data mm5/run1/MMOUT_DOMAIN1)"
    "$B/vsv-info" -f species.0.max "$T/e2.vsv" > "$T/emax"
    "$B/vsv-info" -f species.0.max_abs_error "$T/e2.vsv" > "$T/ebound"
    "$PY" tests/model_extremes.py "$(data mm5/run1/MMOUT_DOMAIN1)" CLW > "$T/m"
    if awk -v e="$(cat "$T/emax")" -v b="$(cat "$T/ebound")" '{ exit !($3 - e > 10 * b) }' "$T/m"; then
        pass "the even grid loses the MM5 run's cloud-water peak (even $(cat "$T/emax"), model $(cut -d' ' -f3 "$T/m"))"
    else
        fail "the even grid loses the MM5 run's cloud-water peak" "even $(cat "$T/emax"), model $(cat "$T/m")"
    fi
fi

expect "--nz alone means the even grid" 0 "$B/vsv-convert" -q --nz 20 -o "$T/n.vsv" samples/mm5/MMOUT_DOMAIN1_CROP
"$B/vsv-info" -f grid.nz "$T/n.vsv" > "$T/nz"
has "(20 even levels)" "$T/nz" "20"
expect "--nz with --vertical native is refused" 2 "$B/vsv-convert" -q --vertical native --nz 20 -o "$T/x.vsv" \
    samples/mm5/MMOUT_DOMAIN1_CROP
has "saying why" "$T/err" "--nz and --ztop shape the even grid: not with --vertical native"
