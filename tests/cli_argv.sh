#!/bin/sh
# cli_argv.sh — the tools' command lines as hostile input: drawn argument
# vectors (tests/test_argv_props.py, python3-hypothesis), each tool ending by
# itself with 0, 1 or 2 and failing in its own words. make test draws 25 a
# tool with a fixed seed; tests/FUZZING.md has the long runs.
B=${B:-build}
PYTHON=${PYTHON:-/usr/bin/python3}
B="$B" "$PYTHON" tests/test_argv_props.py
rc=$?
[ $rc -le 1 ] || echo "FAIL tests/test_argv_props.py runs to its end: exit status $rc"
exit 0
