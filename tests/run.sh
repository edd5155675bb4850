#!/bin/sh
# run.sh — runs every test program and the CLI tests, tallies the PASS/FAIL
# lines, and ends with "N passed, N failed" (and ", K skipped" when checks
# said SKIP: they need the large files of ../shared/data, absent). Exit
# status 1 if anything failed.
# Each test has a time limit (TEST_TIMEOUT seconds, default 900): a test that
# hangs is a FAIL that shows its last output and the processes it left
# running, never a stuck run. TESTS="test_a test_b": only those programs.
B=${B:-build}
SHARED=${SHARED:-../shared}
LIMIT=${TEST_TIMEOUT:-900}
export SHARED B
TMPDIR=$(mktemp -d "${TMPDIR:-/tmp}/vsv-run.XXXXXX")
export TMPDIR
log="$TMPDIR/all.log"
: > "$log"

# one NAME CMD... : runs a test with its output in one.log, stdin closed
one() {
    name=$1; shift
    echo "== $name"
    # a snapshot of the processes just before the limit, for the report
    ( trap 'kill $z 2> /dev/null; exit 0' TERM
      sleep "$LIMIT" & z=$!
      wait $z && ps -eo pid,ppid,etime,args > "$TMPDIR/ps.log" ) > /dev/null 2>&1 &
    watch=$!
    t0=$(date +%s)
    timeout -k 10 $((LIMIT + 5)) "$@" < /dev/null > "$TMPDIR/one.log" 2>&1
    rc=$?
    echo "   ($(( $(date +%s) - t0 )) s)"
    kill "$watch" 2> /dev/null
    wait "$watch" 2> /dev/null
    grep -v '^PASS ' "$TMPDIR/one.log"
    cat "$TMPDIR/one.log" >> "$log"
    if [ $rc = 124 ] || [ $rc = 137 ]; then
        echo "  (last lines: $(tail -n 3 "$TMPDIR/one.log" | tr '\n' '|'))"
        echo "FAIL $name: still running after $LIMIT s, stopped; processes then:" | tee -a "$log"
        # the test's own processes: descendants of the timeout, not the watcher
        awk -v top=$$ 'NR > 1 { pp[$1] = $2; line[$1] = $0; n[NR] = $1 }
            END { for (i in n) { p = n[i]; q = pp[p]; d = 0
                      while (q != "" && q != 1) { if (pp[q] == top && line[q] ~ / timeout /) d = 1; q = pp[q] }
                      if (d) print substr(line[p], 1, 300) } }' "$TMPDIR/ps.log" 2> /dev/null | sort -n | head -n 25
    elif [ $rc -ne 0 ] && ! grep -q '^FAIL ' "$TMPDIR/one.log"; then
        echo "FAIL $name: exited $rc without reporting a failure (crash?)" | tee -a "$log"
    fi
    rm -f "$TMPDIR/ps.log"
}

# NOASLR=1 (make test TSAN=1): GCC 12's ThreadSanitizer finds "unexpected
# memory mapping" where a kernel with vm.mmap_rnd_bits above 28 places a
# program, so the tests (and the tools they start) run without address
# randomisation where the kernel lets setarch turn it off
pre=
if [ "${NOASLR:-}" = 1 ] && setarch "$(uname -m)" -R true 2> /dev/null; then
    pre="setarch $(uname -m) -R"
fi

if [ -n "${TESTS:-}" ]; then
    # only these test programs (make test TSAN=1)
    for t in $TESTS; do
        one "$t" $pre "$B/tests/$t"
    done
else
    for t in "$B"/tests/test_*; do
        [ -x "$t" ] || continue
        one "$(basename "$t")" "$t"
    done
    for s in tests/cli_*.sh; do
        [ "$s" = tests/cli_lib.sh ] && continue # sourced by the others
        # installs and purges packages as root: `make test-deb` (CI) alone
        [ "$s" = tests/cli_deb.sh ] && continue
        one "$(basename "$s")" sh "$s"
    done
fi
pass=$(grep -c '^PASS ' "$log")
fail=$(grep -c '^FAIL ' "$log")
skip=$(grep -c '^SKIP ' "$log")
rm -rf "$TMPDIR"
if [ "$skip" -eq 0 ]; then
    echo "$pass passed, $fail failed"
elif [ -d "$SHARED/data" ]; then
    echo "$pass passed, $fail failed, $skip skipped"
else
    echo "$pass passed, $fail failed, $skip skipped ($SHARED/data absent)"
fi
[ "$fail" -eq 0 ]
