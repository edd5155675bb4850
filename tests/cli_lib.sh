# cli_lib.sh — what the CLI test scripts share (sourced, not run): PASS/FAIL
# lines, running a command with its exit code checked, text checks.
# Expects $T (a scratch directory).
pass() { echo "PASS $1"; }
fail() { echo "FAIL $1: $2"; }
# expect NAME CODE CMD... : runs CMD (stdin closed, at most CMD_TIMEOUT
# seconds: a command that hangs fails with exit 124 instead of stalling the
# run), checks its exit code; stdout in $T/out, stderr in $T/err
expect() {
    name=$1; code=$2; shift 2
    timeout -k 5 "${CMD_TIMEOUT:-300}" "$@" < /dev/null > "$T/out" 2> "$T/err"
    rc=$?
    if [ "$rc" = "$code" ]; then pass "$name"; else fail "$name" "exit $rc, wanted $code; stderr: $(head -c 300 "$T/err")"; fi
}
# has NAME FILE TEXT : FILE contains TEXT
has() { if grep -qF -- "$3" "$2"; then pass "$1"; else fail "$1" "no '$3' in: $(head -c 300 "$2")"; fi; }
# same NAME A B : the files are identical
same() { if cmp -s "$2" "$3"; then pass "$1"; else fail "$1" "$2 and $3 differ"; fi; }
