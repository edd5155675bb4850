#!/bin/sh
# fuzz.sh — runs the libFuzzer targets `make fuzz` built (build-fuzz/fuzz/),
# FUZZ_SECONDS each (default 60), one after another, from a working copy of
# each target's seed corpus (build-fuzz/corpus/NAME: the new inputs libFuzzer
# finds stay there, tests/corpus is left alone). Prints per target the
# executions, their rate, the coverage reached and the crashes, hangs and
# out-of-memory inputs found (saved as build-fuzz/crashes/NAME-*); exit 1
# when any was found. Usage: fuzz.sh [NAME...] (default: every target).
# Extra libFuzzer options: FUZZ_OPTS.
set -u
F=${F:-build-fuzz}
SECONDS_EACH=${FUZZ_SECONDS:-60}
targets=${*:-vsv mm5 uamiv camxmet netcdf grads stream text player argv}
mkdir -p "$F/corpus" "$F/crashes" "$F/logs"
# seeds of each target (tests/corpus/NAME, and the golden .vsv files)
seeds() {
    case $1 in
    vsv) echo tests/golden/small.vsv tests/golden/bad/*.vsv tests/corpus/vsv/* ;;
    *) echo tests/corpus/"$1"/* ;;
    esac
}
# clang 14's AddressSanitizer can die at start (SIGSEGV before any output)
# on a kernel with vm.mmap_rnd_bits = 32, as here (2 starts in about 200):
# the targets run without address randomisation (setarch -R) when it is there
norand=
setarch "$(uname -m)" -R true 2> /dev/null && norand="setarch $(uname -m) -R"
found=0
printf '%-8s %10s %9s %7s %7s %6s  %s\n' target execs exec/s cov ft corpus found
for t in $targets; do
    bin="$F/fuzz/fuzz_$t"
    if [ ! -x "$bin" ]; then
        echo "fuzz.sh: $bin: not built (make fuzz)" >&2
        exit 2
    fi
    c="$F/corpus/$t"
    mkdir -p "$c"
    for s in $(seeds "$t"); do
        case $s in *.md | *.py | */EXPECTED) continue ;; esac
        [ -f "$s" ] && cp "$s" "$c/seed-$(basename "$s")"
    done
    # libnetcdf itself allocates what a damaged header says before reading
    # it (an attribute of 4 GB: malloc succeeds, the read fails, nc_open
    # returns an error): not a failure of the readers, so only the RSS
    # limit holds there
    # argv: a tool's exit() leaves what it allocated, by design (the
    # target's LeakSanitizer is off, tests/FUZZING.md)
    case $t in netcdf) lim=-malloc_limit_mb=65536 ;; argv) lim=-detect_leaks=0 ;; *) lim= ;; esac
    # a target's dictionary (libFuzzer -dict), where it has one
    dict=
    [ -f "tests/fuzz_$t.dict" ] && dict="-dict=tests/fuzz_$t.dict"
    log="$F/logs/$t.log"
    rm -f "$F/crashes/$t-"*
    # -timeout: an input running 10 s is a hang; -rss_limit_mb: 2 GiB is
    # out of memory (the readers bound their allocations by the file)
    $norand "$bin" -max_total_time="$SECONDS_EACH" -timeout=10 -rss_limit_mb=2048 -print_final_stats=1 $lim $dict \
        -artifact_prefix="$F/crashes/$t-" ${FUZZ_OPTS:-} "$c" > "$log" 2>&1
    rc=$?
    execs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -n 1)
    rate=$(sed -n 's/^stat::average_exec_per_sec: *//p' "$log" | tail -n 1)
    cov=$(grep -o 'cov: [0-9]*' "$log" | tail -n 1 | cut -d' ' -f2)
    ft=$(grep -o 'ft: [0-9]*' "$log" | tail -n 1 | cut -d' ' -f2)
    n=$(find "$c" -type f | wc -l)
    bad=$(ls "$F/crashes/$t-"* 2> /dev/null | wc -l)
    printf '%-8s %10s %9s %7s %7s %6s  %s\n' "$t" "${execs:-?}" "${rate:-?}" "${cov:-?}" "${ft:-?}" "$n" "$bad"
    if [ "$bad" -gt 0 ] || [ $rc -ne 0 ]; then
        found=1
        grep -m 3 -E 'ERROR: |runtime error|SUMMARY' "$log" | sed 's/^/    /'
        ls "$F/crashes/$t-"* 2> /dev/null | sed 's/^/    saved: /'
        echo "    log: $log"
    fi
done
if [ $found -ne 0 ]; then
    echo "fuzz.sh: crashes found; reproduce with $F/fuzz/fuzz_NAME FILE, then add FILE to tests/corpus/NAME" >&2
    exit 1
fi
