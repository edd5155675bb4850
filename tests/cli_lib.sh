# cli_lib.sh — what the CLI test scripts share (sourced, not run): PASS/FAIL
# lines, running a command with its exit code checked, text checks.
# Expects $T (a scratch directory).
pass() { echo "PASS $1"; }
fail() { echo "FAIL $1: $2"; }
skip() { echo "SKIP $1: $2"; }
# data REL: the path of a test data file: tests/data/REL (the small real
# files copied into the repository) if it is there, else $SHARED/data/REL
# (the large ones; CI has ../shared beside the clone, a user may not)
TESTDATA=$(pwd)/tests/data
data() { if [ -e "$TESTDATA/$1" ]; then echo "$TESTDATA/$1"; else echo "$SHARED/data/$1"; fi; }
# absent NAME REL... : 0 (and "SKIP NAME: ... absent") when a data file is
# missing, so that `absent NAME REL && exit 0` or `if ! absent ...` skips
absent() {
    n=$1; shift
    for r in "$@"; do
        [ -e "$(data "$r")" ] || { skip "$n" "$(data "$r") absent"; return 0; }
    done
    return 1
}
# expect NAME CODE CMD... : runs CMD (stdin closed, at most CMD_TIMEOUT
# seconds: a command that hangs fails with exit 124 instead of stalling the
# run), checks its exit code; stdout in $T/out, stderr in $T/err
expect() {
    name=$1; code=$2; shift 2
    timeout -k 5 "${CMD_TIMEOUT:-300}" "$@" < /dev/null > "$T/out" 2> "$T/err"
    rc=$?
    if [ "$rc" = "$code" ]; then pass "$name"; else fail "$name" "exit $rc, wanted $code; stderr: $(head -c 300 "$T/err")"; fi
}
# $XVFB ARGS...: xvfb-run on a free display, its authority file in $T (set
# before this file is sourced; a path without spaces): after a command that
# exits non-zero, xvfb-run's own temporary folder sometimes fails to be
# removed and it exits 5 instead of the command's code (1 run in 10 of
# vsv-play exiting 1 here)
XVFB="xvfb-run -a -f $T/Xauthority"
# has NAME FILE TEXT : FILE contains TEXT
has() { if grep -qF -- "$3" "$2"; then pass "$1"; else fail "$1" "no '$3' in: $(head -c 300 "$2")"; fi; }
# same NAME A B : the files are identical
same() { if cmp -s "$2" "$3"; then pass "$1"; else fail "$1" "$2 and $3 differ"; fi; }
# execs_only NAME CMD... : every child process CMD starts runs a program
# (exec) first: none is a bare fork of a process that may have threads
# (issue 18). Needs strace (tools/deps.sh); at least one child must be seen.
execs_only() {
    name=$1; shift
    if ! command -v strace > /dev/null; then echo "note: $name: strace missing, not checked"; return; fi
    # LeakSanitizer cannot run under ptrace; the trace is what is checked
    ASAN_OPTIONS="${ASAN_OPTIONS:+$ASAN_OPTIONS:}detect_leaks=0" timeout -k 5 "${CMD_TIMEOUT:-300}" \
        strace -f -qq -e trace=execve -o "$T/strace" "$@" < /dev/null > "$T/out" 2> "$T/err"
    r=$(awk '/--- SIGCHLD/ { if (match($0, /si_pid=[0-9]+/)) kid[substr($0, RSTART + 7, RLENGTH - 7)] = 1 }
             / execve\(/ { ex[$1] = 1 }
             END { n = 0; bad = ""; for (k in kid) { n++; if (!(k in ex)) bad = bad " " k }
                   print n, (bad == "" ? "ok" : "never exec:" bad) }' "$T/strace")
    case "$r" in
    0\ *) fail "$name" "no child process seen" ;;
    *\ ok) pass "$name" ;;
    *) fail "$name" "$r" ;;
    esac
}
# mpi_env: $MPIRUN runs N ranks on this machine alone (as root, in a
# container without a network: shared memory between the ranks, no remote
# shell, no single-copy (ptrace) path); under a sanitizer build Open MPI's
# own allocations at exit are not ours (its components stay loaded, and full
# stacks name them, so tests/lsan.supp matches: slow under ASan, so a
# script that runs other tools after the ranks calls it in a subshell)
mpi_env() {
    export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
    export OMPI_MCA_mca_base_component_disable_dlclose=1
    export LSAN_OPTIONS="${LSAN_OPTIONS:+$LSAN_OPTIONS:}suppressions=$(pwd)/tests/lsan.supp:fast_unwind_on_malloc=0:print_suppressions=0"
    MPIRUN="mpirun -q --oversubscribe --mca btl self,vader --mca btl_vader_single_copy_mechanism none --mca plm_rsh_agent false"
}
