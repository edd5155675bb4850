#!/bin/sh
# cli_python.sh — the Python module: its unittest suite (tests/test_python.py,
# PASS/FAIL lines counted with the rest) against the built module, and
# `make install PREFIX=...` giving a module python3 imports with only
# PYTHONPATH set, as the README says. Skipped with a note when the module is
# not built (python3-dev or python3-numpy missing, or SAN=1).
B=${B:-build}
PYTHON=${PYTHON:-/usr/bin/python3}
if [ ! -f "$B/python/vesuvius/__init__.py" ] || [ -n "$(echo "${PY_MISSING:-}" | tr -d ' ')" ]; then
    echo "  (the Python module is not built here: ${PY_MISSING:-not found}; its tests are skipped)"
    exit 0
fi
T=$(mktemp -d "${TMPDIR:-/tmp}/vsv-cli-python.XXXXXX")
trap 'rm -rf "$T"' EXIT
. tests/cli_lib.sh
PYTHONPATH="$B/python" B="$B" "$PYTHON" tests/test_python.py
P="$T/x"
if make -s --no-print-directory B="$B" install PREFIX="$P" > "$T/log" 2>&1; then
    pass "make install PREFIX=$P"
else
    fail "make install PREFIX=$P" "$(tail -c 400 "$T/log")"
    exit 0
fi
expect "python3 imports the installed module with only PYTHONPATH=\$PREFIX/lib/python3/dist-packages" 0 \
    env -i PATH=/usr/bin:/bin PYTHONPATH="$P/lib/python3/dist-packages" "$PYTHON" -c \
    'import vesuvius, sys; f = vesuvius.open(sys.argv[1]); print(vesuvius.__file__, f.read(0, 3).shape)' \
    "$(pwd)/tests/golden/small.vsv"
has "from the install, not the build tree" "$T/out" "$P/lib/python3/dist-packages/vesuvius/__init__.py"
