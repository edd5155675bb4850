#!/bin/sh
# run.sh — runs every test program and the CLI tests, tallies the PASS/FAIL
# lines, and ends with "N passed, N failed". Exit status 1 if anything failed.
B=${B:-build}
SHARED=${SHARED:-../shared}
export SHARED B
TMPDIR=$(mktemp -d "${TMPDIR:-/tmp}/vsv-run.XXXXXX")
export TMPDIR
log="$TMPDIR/all.log"
: > "$log"
status=0
for t in "$B"/tests/test_*; do
    [ -x "$t" ] || continue
    echo "== $(basename "$t")"
    "$t" > "$TMPDIR/one.log" 2>&1
    rc=$?
    grep -v '^PASS ' "$TMPDIR/one.log"
    cat "$TMPDIR/one.log" >> "$log"
    if [ $rc -ne 0 ] && ! grep -q '^FAIL ' "$TMPDIR/one.log"; then
        echo "FAIL $(basename "$t"): exited $rc without reporting a failure (crash?)" | tee -a "$log"
    fi
done
for s in tests/cli_*.sh; do
    [ "$s" = tests/cli_lib.sh ] && continue # sourced by the others
    echo "== $(basename "$s")"
    sh "$s" > "$TMPDIR/one.log" 2>&1
    rc=$?
    grep -v '^PASS ' "$TMPDIR/one.log"
    cat "$TMPDIR/one.log" >> "$log"
    if [ $rc -ne 0 ] && ! grep -q '^FAIL ' "$TMPDIR/one.log"; then
        echo "FAIL $(basename "$s"): exited $rc without reporting a failure" | tee -a "$log"
    fi
done
pass=$(grep -c '^PASS ' "$log")
fail=$(grep -c '^FAIL ' "$log")
rm -rf "$TMPDIR"
echo "$pass passed, $fail failed"
[ "$fail" -eq 0 ]
