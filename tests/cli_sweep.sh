#!/bin/sh
# cli_sweep.sh — a small fixed subset of the damage sweep (tests/sweep/sweep.py,
# tests/FUZZING.md): 40 single-byte changes and 10 truncations of a .vsv made
# from the real WRF file through vsv-info --check, vsv-extract and vsv-render
# (its last step; the sequence case waits for all-or-nothing sequences),
# 20 + 5 of the real CAMx and GrADS files through vsv-convert. Every run must
# end by itself, exit 0 or 1 naming the file, and leave nothing behind (the
# full sweep runs thousands: too slow for make test). Prints PASS/FAIL lines.
B=${B:-build}
SHARED=${SHARED:-../shared}
T=$(mktemp -d "${TMPDIR:-/tmp}/vsv-cli-sweep.XXXXXX")
trap 'rm -rf "$T"' EXIT
. tests/cli_lib.sh
absent "the damage sweep" wrf/wrf_cropped.nc grads/model.ctl camx/test.uamiv && exit 0
TMPDIR=$T B=$B SHARED=$SHARED /usr/bin/python3 tests/sweep/sweep.py --kinds vsv,camx,grads --flips 40 --truncs 10 \
    --model-flips 20 --model-truncs 5 --jobs 1 --seed 7 --render-last > "$T/sweep" 2>&1
rc=$?
grep -E '^(FAIL|[0-9]+ runs)' "$T/sweep"
if [ $rc = 0 ] && grep -q '^200 runs, 0 failed' "$T/sweep"; then
    pass "the fixed damage sweep: 200 runs, no crash, hang, exit > 1, unnamed file or file left behind"
else
    fail "the fixed damage sweep" "$(grep -E '^FAIL' "$T/sweep" | head -n 3 | cut -c1-300)"
fi
# SIGTERM at a random moment (seeded) of vsv-convert (the bundled MM5
# sample), vsv-export --vdb and --netcdf, vsv-render --movie and a PNG
# sequence, 3 tries each: the tool dies of it (or had finished) and its
# output folder holds nothing (or the complete output). Any moment must
# pass, so a slow machine changes which moments are tried, not the verdict.
TMPDIR=$T B=$B SHARED=$SHARED /usr/bin/python3 tests/sweep/sweep.py --kinds sigterm --sigterm 3 --seed 7 \
    --sigterm-input samples/mm5/MMOUT_DOMAIN1_CROP > "$T/sig" 2>&1
rc=$?
grep -E '^(FAIL|[0-9]+ runs)' "$T/sig"
if [ $rc = 0 ] && grep -q '^15 runs, 0 failed' "$T/sig"; then
    pass "SIGTERM at random moments of 5 jobs, 3 each: nothing left behind"
else
    fail "SIGTERM at random moments" "$(grep -E '^FAIL' "$T/sig" | head -n 3 | cut -c1-300)"
fi
