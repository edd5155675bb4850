#!/usr/bin/env python3
"""test_argv_props.py — the tools' command lines as hostile input (issue 33):
Hypothesis draws argument vectors for each tool from its own options (read
from its --help), values at the edges (huge, negative, NaN, format
directives, long names, bytes that are not UTF-8) and the small files of
the repository, runs the tool in a scratch folder with stdin closed, and
asserts that it ends by itself with 0, 1 (an error) or 2 (misuse), never a
signal, and that a failure says what it is, starting with the tool's name
(or prints its usage). Out of process (a fork and exec per vector: about
100 a second here, against an in-process libFuzzer target's thousands);
tests/FUZZING.md has the long runs. Prints PASS/FAIL lines.
VSV_ARGV_EXAMPLES=N vectors per tool (default 25), VSV_ARGV_SEED (fixed)."""
import os
import re
import shutil
import subprocess
import sys
import tempfile

try:
    from hypothesis import HealthCheck, given, seed, settings, strategies as st
except ImportError:
    print("SKIP tool command lines: python3-hypothesis is not installed")
    sys.exit(0)

B = os.path.abspath(os.environ.get("B", "build"))
TOP = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
EXAMPLES = int(os.environ.get("VSV_ARGV_EXAMPLES", "25"))
SEED = int(os.environ.get("VSV_ARGV_SEED", "20261127"))
TIMEOUT = float(os.environ.get("VSV_ARGV_TIMEOUT", "60"))
TOOLS = ["vsv-info", "vsv-query", "vsv-render", "vsv-export", "vsv-convert", "vsv-extract", "vsv-pack",
         "vsv-interp"]
SCRATCH = tempfile.mkdtemp(prefix="vsv-argv.")
# the files a vector may name: a small .vsv, a model file, a stream, a text file
shutil.copy(os.path.join(TOP, "tests/golden/small.vsv"), os.path.join(SCRATCH, "a.vsv"))
shutil.copy(os.path.join(TOP, "tests/corpus/netcdf/ioapi-cmaq.nc"), os.path.join(SCRATCH, "m.nc"))
with open(os.path.join(SCRATCH, "t.txt"), "w") as f:
    f.write("species X\ncolormap viridis\n")
FILES = ["a.vsv", "m.nc", "t.txt", "missing.vsv", ".", "/dev/null", "out.vsv", "o_%04d.png", "x.png", "x.nc"]
VALUES = ["0", "1", "-1", "3", "1e308", "-1e308", "nan", "inf", "99999999999999999999", "0x10", "",
          "%s%n%s", "%04d", "a" * 300, "1995-10-24T01:00:00Z", "0:", ":", "1:0", "0:1", "-5:5", "10m", "1h30m",
          "PT1H", "-10m", "0m", "1s", "CLW", "X", "Q,CLW", "X:0.5", "X:magma", "X:0:1", "X=0:1", "z=2000",
          "lat=40", "line=40,-100:41,-99", "40,-100", "40,-100,1500", "0,0,0", "800x600", "0x0", "65536x2",
          "plan", "oblique", "south", "raycast", "shearwarp", "gl", "even", "native", "linear", "log", "advect",
          "\u00e9\u00e8", "\x7f", "http://127.0.0.1:9/x.vsv", "-", "--", "-o"]


def options(tool):
    """The tool's long options, from its --help."""
    out = subprocess.run([os.path.join(B, tool), "--help"], capture_output=True, text=True, timeout=30).stdout
    return sorted(set(re.findall(r"(--[a-z][a-z0-9-]+)", out)) - {"--help", "--version"})


def vectors(opts):
    token = st.one_of(st.sampled_from(opts), st.sampled_from(FILES), st.sampled_from(VALUES),
                      st.builds(lambda o, v: o + "=" + v, st.sampled_from(opts), st.sampled_from(VALUES)),
                      st.text(st.characters(blacklist_characters="\x00", blacklist_categories=("Cs",)), max_size=12))
    return st.lists(token, min_size=0, max_size=8)


def check(tool, argv):
    env = dict(os.environ, VSV_CACHE_DIR=os.path.join(SCRATCH, "cache"), LC_ALL="C.UTF-8")
    try:
        p = subprocess.run([os.path.join(B, tool)] + argv, cwd=SCRATCH, stdin=subprocess.DEVNULL,
                           capture_output=True, timeout=TIMEOUT, env=env)
    except subprocess.TimeoutExpired:
        raise AssertionError("%s %r: still running after %g s" % (tool, argv, TIMEOUT))
    err = p.stderr.decode("utf-8", "replace")
    assert p.returncode in (0, 1, 2), "%s %r: exit %d (a signal?): %s" % (tool, argv, p.returncode, err[-300:])
    if p.returncode:
        first = err.lstrip().split("\n")[0]
        assert first.startswith(tool + ":") or first.startswith("Usage") or first.startswith("usage") or \
            "--help" in err, "%s %r: exit %d with no message of its own: %r" % (tool, argv, p.returncode, err[-300:])


failed = 0
for tool in TOOLS:
    if not os.access(os.path.join(B, tool), os.X_OK):
        print("SKIP %s command lines: %s/%s is not built" % (tool, B, tool))
        continue
    opts = options(tool)

    def make(tool):
        @settings(max_examples=EXAMPLES, deadline=None, database=None, suppress_health_check=list(HealthCheck))
        @seed(SEED)
        @given(vectors(opts))
        def prop(argv):
            check(tool, argv)
        return prop

    prop = make(tool)

    name = "%s: %d drawn command lines end by themselves, each failure in its own words" % (tool, EXAMPLES)
    try:
        prop()
        print("PASS " + name)
    except Exception as e:  # Hypothesis reports the shrunk vector
        failed += 1
        print("FAIL %s: %s" % (name, str(e).replace("\n", " | ")[:900]))
shutil.rmtree(SCRATCH, ignore_errors=True)
sys.exit(1 if failed else 0)
