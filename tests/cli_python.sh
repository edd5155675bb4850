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
rc=$?
# 1: a failed test, reported by its FAIL line; anything else (a crash) ends
# the suite without one
[ $rc -le 1 ] || fail "tests/test_python.py runs to its end" "exit status $rc"
# properties of the API over drawn inputs (python3-hypothesis; the long run: tests/FUZZING.md)
PYTHONPATH="$B/python" "$PYTHON" tests/test_python_props.py
rc=$?
[ $rc -le 1 ] || fail "tests/test_python_props.py runs to its end" "exit status $rc"
P="$T/x"
if make -s --no-print-directory B="$B" install PREFIX="$P" > "$T/log" 2>&1; then
    pass "make install PREFIX=$P"
else
    fail "make install PREFIX=$P" "$(tail -c 400 "$T/log")"
    exit 0
fi
V=$("$PYTHON" -c "import sys; print('%d.%d' % sys.version_info[:2])")
# where the interpreter looks for PREFIX (tools/pydir.py asks it): for a
# prefix of no scheme of its own, upstream's PREFIX/lib/python3.X/site-packages
D=$("$PYTHON" tools/pydir.py "$P")
[ "$D" = "$P/lib/python$V/site-packages" ] && pass "PREFIX=$P: the module goes to \$PREFIX/lib/python$V/site-packages" ||
    fail "PREFIX=$P: the module goes to \$PREFIX/lib/python$V/site-packages" "'$D'"
expect "python3 imports the installed module with only PYTHONPATH=$D" 0 \
    env -i PATH=/usr/bin:/bin PYTHONPATH="$D" "$PYTHON" -c \
    'import vesuvius, sys; f = vesuvius.open(sys.argv[1]); print(vesuvius.__file__, f.read(0, 3).shape)' \
    "$(pwd)/tests/golden/small.vsv"
has "from the install, not the build tree" "$T/out" "$D/vesuvius/__init__.py"
# the default prefix installs where Debian's python3 looks without PYTHONPATH
make -s --no-print-directory B="$B" install DESTDIR="$T/root" > "$T/log" 2>&1
if [ -f "$T/root/usr/local/lib/python$V/dist-packages/vesuvius/__init__.py" ] &&
    "$PYTHON" -c "import sys; sys.exit('/usr/local/lib/python$V/dist-packages' not in sys.path)"; then
    pass "make install puts the module in /usr/local/lib/python$V/dist-packages, on python3's path"
else
    fail "make install puts the module on python3's path" "$(find "$T/root" -name __init__.py)"
fi
# PREFIX=/usr (a Debian package's): Debian's own folder for every python3,
# /usr/lib/python3/dist-packages, also on the path
make -s --no-print-directory B="$B" install PREFIX=/usr DESTDIR="$T/usr-root" > "$T/log" 2>&1
D=$("$PYTHON" tools/pydir.py /usr)
if [ -f "$T/usr-root$D/vesuvius/__init__.py" ] &&
    (cd / && "$PYTHON" -c "import sys; sys.exit('$D' not in sys.path)"); then
    pass "make install PREFIX=/usr puts the module in $D, on python3's path"
else
    fail "make install PREFIX=/usr puts the module on python3's path" "$D; $(find "$T/usr-root" -name __init__.py)"
fi
# a folder named vesuvius in the working directory (the checkout, from its
# parent) is not taken for the module: the installed one is imported
mkdir -p "$T/parent/vesuvius"
cp README.md Makefile "$T/parent/vesuvius/"
(cd "$T/parent" && env -i PATH=/usr/bin:/bin PYTHONPATH="$T/root/usr/local/lib/python$V/dist-packages" "$PYTHON" -c \
    'import vesuvius, sys; print(vesuvius.__file__, vesuvius.open(sys.argv[1]).grid["nx"])' \
    "$OLDPWD/tests/golden/small.vsv") > "$T/out" 2> "$T/err"
has "imported from the checkout's parent: the module, not the folder" "$T/out" \
    "$T/root/usr/local/lib/python$V/dist-packages/vesuvius/__init__.py"
