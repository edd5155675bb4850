#!/bin/sh
# fuzz-campaign.sh — a long libFuzzer campaign, in chunks that survive the
# session: each target's corpus, crashes and an append-only log live under
# CAMPAIGN (default /work/fuzz-campaign, outside the tree), so a new run
# resumes where the last one stopped. Run from the top of the tree.
#
#   make fuzz FUZZ_SECONDS=1                   # builds build-fuzz/fuzz/*
#   STOP=21:40 nice -n 10 sh tests/fuzz-campaign.sh &   # one worker a core
#   STOP=21:40 nice -n 10 sh tests/fuzz-campaign.sh &
#   sh tests/fuzz-campaign.sh --status         # cumulative figures per target
#
# A worker fuzzes one chunk (CHUNK seconds, default 900, cut short at STOP,
# HH:MM UTC, or at GOAL) of a target no other worker holds (flock on CAMPAIGN/NAME/lock),
# then chooses again: first the target that can reach GOAL executions (10^7)
# soonest at its measured rate within the time left, else the one fuzzed
# the fewest seconds so far (a target not yet run first). Targets at GOAL
# are done; FUZZ="a b" limits the choice. Every chunk appends one line to
# CAMPAIGN/log.tsv: target, UTC date, seconds, executions, coverage (edges),
# features, corpus size, crash files. A crash, hang or out-of-memory input is
# saved in CAMPAIGN/NAME/crashes/ and the target skipped while that folder
# holds one (fix the code, add the input to tests/corpus/NAME, then move it
# to CAMPAIGN/NAME/fixed/). `--record NAME` appends the figures of
# CAMPAIGN/NAME/last.log (a chunk whose worker was stopped) to the log.
set -u
F=${F:-build-fuzz}
C=${CAMPAIGN:-/work/fuzz-campaign}
GOAL=${GOAL:-10000000}
CHUNK=${CHUNK:-900}
LOG="$C/log.tsv"
all="uamiv text mm5 stream vsv netcdf player camxmet grads argv"
mkdir -p "$C"
[ -f "$LOG" ] || printf 'target\tdate\tseconds\texecs\tcov\tft\tcorpus\tcrashes\n' > "$LOG"

total() { awk -F'\t' -v t="$1" '$1 == t { s += $4 } END { print s + 0 }' "$LOG"; }
secs_of() { awk -F'\t' -v t="$1" '$1 == t { s += $3 } END { print s + 0 }' "$LOG"; }

# the figures of CAMPAIGN/$1/last.log appended to the log
record() {
    t=$1 d="$C/$1" log="$C/$1/last.log"
    execs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -n 1)
    # stopped before the final statistics: the last progress line
    [ -n "$execs" ] || execs=$(grep -o '^#[0-9]*' "$log" | tail -n 1 | tr -d '#')
    cov=$(grep -o 'cov: [0-9]*' "$log" | tail -n 1 | cut -d' ' -f2)
    ft=$(grep -o 'ft: [0-9]*' "$log" | tail -n 1 | cut -d' ' -f2)
    n=$(find "$d/corpus" -type f | wc -l)
    bad=$(find "$d/crashes" -type f | wc -l)
    used=$(sed -n 's/^Done [0-9]* runs in \([0-9]*\) second.*/\1/p' "$log" | tail -n 1)
    # stopped or crashed: executions over their rate
    rate=$(sed -n 's/^stat::average_exec_per_sec: *//p' "$log" | tail -n 1)
    [ -n "$used" ] || { [ "${rate:-0}" -gt 0 ] && used=$(( ${execs:-0} / rate )); }
    printf '%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\n' "$t" "$(date -u +%FT%TZ)" "${used:-0}" \
        "${execs:-0}" "${cov:-}" "${ft:-}" "$n" "$bad" >> "$LOG"
    cat "$log" >> "$d/fuzz.log"
    echo "$bad"
}

case ${1:-} in
--status)
    printf '%-8s %12s %8s %7s %7s %7s %7s\n' target execs seconds cov ft corpus crashes
    for t in $all; do
        awk -F'\t' -v t="$t" '$1 == t { e += $4; s += $3; c = $5; f = $6; n = $7; k = $8 }
            END { printf "%-8s %12d %8d %7s %7s %7s %7d\n", t, e, s, c, f, n, k }' "$LOG"
    done
    exit 0 ;;
--record)
    record "$2" > /dev/null
    exit 0 ;;
esac
targets=${FUZZ:-$all}

# seconds left before STOP (HH:MM UTC today); a large number without STOP
left() {
    [ -n "${STOP:-}" ] || { echo 999999; return; }
    echo $(( $(date -u -d "$STOP" +%s) - $(date -u +%s) ))
}
seeds() {
    case $1 in
    vsv) echo tests/golden/small.vsv tests/golden/bad/*.vsv tests/corpus/vsv/* ;;
    *) echo tests/corpus/"$1"/* ;;
    esac
}
runnable() { # not at the goal, no crash waiting, not held by another worker
    [ "$(total "$1")" -lt "$GOAL" ] && [ "$(find "$C/$1/crashes" -type f 2> /dev/null | wc -l)" -eq 0 ]
}

# the next target (see the top); empty when none is left
choose() {
    best= how=
    for t in $targets; do
        runnable "$t" || continue
        mkdir -p "$C/$t"
        exec 8> "$C/$t/lock"
        flock -n 8 || { exec 8>&-; continue; }
        exec 8>&-
        e=$(total "$t") s=$(secs_of "$t")
        if [ "$s" -gt 0 ]; then
            need=$(( (GOAL - e) * s / (e > 0 ? e : 1) ))
            [ "$need" -le "$1" ] && key=$need || key=$(( 1000000000 + s ))
        else
            key=1000000000
        fi
        if [ -z "$best" ] || [ "$key" -lt "$how" ]; then best=$t how=$key; fi
    done
    echo "$best"
}

for t in $targets; do
    [ -x "$F/fuzz/fuzz_$t" ] || { echo "fuzz-campaign: $F/fuzz/fuzz_$t: not built (make fuzz)" >&2; exit 2; }
done
# clang 14's AddressSanitizer can die at start (SIGSEGV before any output)
# on a kernel with vm.mmap_rnd_bits = 32, as here (2 starts in about 200):
# the targets run without address randomisation (setarch -R) when it is there
norand=
setarch "$(uname -m)" -R true 2> /dev/null && norand="setarch $(uname -m) -R"
while :; do
    s=$(left)
    [ "$s" -gt 30 ] || exit 0
    t=$(choose "$s")
    [ -n "$t" ] || { echo "fuzz-campaign: no target left to run" >&2; exit 0; }
    d="$C/$t"
    exec 9> "$d/lock"
    flock -n 9 || continue # taken meanwhile
    [ "$s" -lt "$CHUNK" ] && secs=$s || secs=$CHUNK
    echo "fuzz-campaign: $t: $(total "$t") executions so far; $secs s more" >&2
    mkdir -p "$d/corpus" "$d/crashes" "$d/fixed"
    for f in $(seeds "$t"); do
        case $f in *.md | *.py | */EXPECTED) continue ;; esac
        [ -f "$f" ] && [ ! -f "$d/corpus/seed-$(basename "$f")" ] && cp "$f" "$d/corpus/seed-$(basename "$f")"
    done
    # as tests/fuzz.sh: 10 s an input is a hang, 2 GiB is out of memory;
    # libnetcdf may allocate what a header says (the RSS limit holds)
    # argv: a tool's exit() leaves what it allocated, by design (the
    # target's LeakSanitizer is off, tests/FUZZING.md)
    case $t in netcdf) lim=-malloc_limit_mb=65536 ;; argv) lim=-detect_leaks=0 ;; *) lim= ;; esac
    # a target's dictionary (libFuzzer -dict), where it has one
    dict=
    [ -f "tests/fuzz_$t.dict" ] && dict="-dict=tests/fuzz_$t.dict"
    $norand "$F/fuzz/fuzz_$t" -max_total_time="$secs" -runs=$((GOAL - $(total "$t"))) -timeout=10 -rss_limit_mb=2048 -print_final_stats=1 $lim $dict \
        -artifact_prefix="$d/crashes/" "$d/corpus" > "$d/last.log" 2>&1
    bad=$(record "$t")
    [ "$bad" -eq 0 ] || echo "fuzz-campaign: $t: found something: $d/crashes, $d/last.log" >&2
    exec 9>&-
done
