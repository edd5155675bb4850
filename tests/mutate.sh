#!/bin/sh
# mutate.sh — the mutation harness (`make mutate`): each patch under
# tests/mutants/ is one deliberate bug. In a scratch copy of the tree (the
# checkout is never changed), every patch is applied alone, the tree
# rebuilt, and the tests its header names run; the mutant is killed when
# one of them reports a FAIL, crashes or exits non-zero. Prints a line per
# mutant, the score and the survivors; exits 1 when the score is under
# MUTATE_MIN percent (default 90).
#
# A patch: header lines, then a unified diff from the repository root:
#   # What: the change, in words
#   # Tests: test_format cli_http.sh   (build/tests programs, tests/ scripts)
#   # Killed by: the check that catches it
# or, for a change no test can observe, "# Equivalent: why" (it then counts
# out of the score when it survives). MUTANTS="a b": only those patches.
B=${B:-build}
SHARED=${SHARED:-../shared}
MIN=${MUTATE_MIN:-90}
LIMIT=${MUTATE_TIMEOUT:-600}
top=$(pwd)
W=$(mktemp -d "${TMPDIR:-/tmp}/vsv-mutate.XXXXXX")
trap 'rm -rf "$W"' EXIT INT TERM
case $SHARED in /*) ;; *) SHARED=$top/$SHARED ;; esac

header() { sed -n "s/^# $1: *//p" "$2" | head -n 1; }

# the scratch tree: the checkout's files (tracked and new, not ignored) and
# its build, made newer than every source so that only what a patch
# touches is rebuilt
git ls-files -z --cached --others --exclude-standard | xargs -0 cp --parents -t "$W" 2> /dev/null
if [ -d "$B" ]; then
    cp -a "$B" "$W/build"
    find "$W/build" -type f -exec touch {} +
fi
cd "$W" || exit 1
export SHARED B=build PYTHON=${PYTHON:-/usr/bin/python3}
[ -d build/python/vesuvius ] && export PYMOD=build/python/vesuvius
make_quiet() { make -s --no-print-directory -j"${JOBS:-2}" "$@" > build.log 2>&1; }

# targets and commands for a test name
target() {
    case $1 in
    cli_*.sh) echo all build/tests/mm5crop build/tests/ncsplit build/tests/libcutmap.so build/tests/libholdtmp.so ;;
    *) echo "build/tests/$1" ;;
    esac
}
runone() {
    case $1 in
    cli_*.sh) timeout -k 5 "$LIMIT" sh "tests/$1" ;;
    *) timeout -k 5 "$LIMIT" "build/tests/$1" ;;
    esac
}
# runs the tests named; prints the first failure ("" when all pass)
verdict() {
    for t in "$@"; do
        runone "$t" < /dev/null > run.log 2>&1
        rc=$?
        f=$(grep -a -m 1 '^FAIL ' run.log | cut -c 1-160)
        if [ -n "$f" ]; then echo "$t: $f"; return; fi
        if [ $rc -ne 0 ]; then echo "$t: exit $rc"; return; fi
    done
}

list=${MUTANTS:-$(ls tests/mutants/*.patch 2> /dev/null | sed 's|.*/||; s|\.patch$||')}
[ -n "$list" ] || { echo "mutate: no patches in tests/mutants/" >&2; exit 1; }

# the tests must pass on the tree as it is, or nothing is measured
all_tests=$(for m in $list; do header Tests "tests/mutants/$m.patch"; done | tr ' ' '\n' | sort -u | tr '\n' ' ')
echo "building the tree and running the $(echo $all_tests | wc -w) tests the mutants name, unchanged"
make_quiet all $(for t in $all_tests; do target "$t"; done | sort -u) ||
    { echo "mutate: the unchanged tree does not build:"; tail -n 20 build.log; exit 1; }
base=$(verdict $all_tests)
[ -z "$base" ] || { echo "mutate: a test fails on the unchanged tree: $base"; exit 1; }

killed=0 survived=0 equiv=0 broken=0 surv=""
for m in $list; do
    p=tests/mutants/$m.patch
    tests=$(header Tests "$p")
    if [ -z "$tests" ] || ! git apply "$p" 2> apply.log; then
        echo "$m: BROKEN (no '# Tests:' line, or the patch does not apply: $(head -c 200 apply.log))"
        broken=$((broken + 1))
        continue
    fi
    if ! make_quiet all $(for t in $tests; do target "$t"; done | sort -u); then
        echo "$m: BROKEN (does not build: $(grep -m 1 error build.log | cut -c 1-160))"
        broken=$((broken + 1))
    else
        v=$(verdict $tests)
        if [ -n "$v" ]; then
            echo "$m: killed by $v"
            killed=$((killed + 1))
        elif [ -n "$(header Equivalent "$p")" ]; then
            echo "$m: survived, equivalent: $(header Equivalent "$p")"
            equiv=$((equiv + 1))
        else
            echo "$m: SURVIVED ($(header What "$p"))"
            survived=$((survived + 1))
            surv="$surv $m"
        fi
    fi
    git apply -R "$p" || { echo "mutate: $p does not reverse; stopping"; exit 1; }
done
counted=$((killed + survived))
score=$([ $counted -gt 0 ] && echo $((100 * killed / counted)) || echo 0)
echo "$killed killed, $survived survived, $equiv equivalent, $broken broken: $score % killed"
[ -z "$surv" ] || echo "survivors:$surv"
[ $broken -eq 0 ] && [ "$score" -ge "$MIN" ]
