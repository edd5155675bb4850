#!/usr/bin/env python3
"""test_python_props.py — property tests of the Python API (issue 33): for
grids, values, names and arguments that Hypothesis draws, vesuvius.write then
vesuvius.open gives back every value within its stated bound (no data stays no
data), query at a cell equals read, and whatever a caller passes — wrong
shapes, non-finite grids, huge sizes, names that are not text, out-of-range
steps and cells — ends in a Python exception, never a crash or a silent wrong
answer. Prints PASS/FAIL lines. VSV_PROPS_EXAMPLES=N sets the examples per
property (default 60: make test; the long run in tests/FUZZING.md uses more),
VSV_PROPS_SEED a seed (default fixed: the same examples every run)."""
import os
import sys
import tempfile
import traceback

import numpy as np

try:
    from hypothesis import HealthCheck, given, seed, settings, strategies as st
except ImportError:
    print("SKIP python properties: python3-hypothesis is not installed")
    sys.exit(0)

import vesuvius

EXAMPLES = int(os.environ.get("VSV_PROPS_EXAMPLES", "60"))
SEED = int(os.environ.get("VSV_PROPS_SEED", "20261127"))
TMP = tempfile.mkdtemp(prefix="vsv-props.")
RUNS = {"n": 0}
CALLS = {"n": 0}  # examples a property was run on
CFG = settings(max_examples=EXAMPLES, deadline=None, database=None, derandomize=False,
               suppress_health_check=list(HealthCheck))


def path(name):
    RUNS["n"] += 1
    return os.path.join(TMP, "%s-%d.vsv" % (name, RUNS["n"]))


dims = st.tuples(st.integers(1, 40), st.integers(1, 40), st.integers(1, 12))
ntimes = st.integers(1, 3)


@st.composite
def fields(draw):
    nx, ny, nz = draw(dims)
    nt = draw(ntimes)
    kind = draw(st.sampled_from(["smooth", "sparse", "noise", "constant", "nodata"]))
    rng = np.random.default_rng(draw(st.integers(0, 2 ** 32 - 1)))
    scale = draw(st.sampled_from([1e-9, 1e-4, 1.0, 300.0, 1e6]))
    shape = (nt, nz, ny, nx)
    if kind == "smooth":
        z, y, x = np.meshgrid(np.arange(nz), np.arange(ny), np.arange(nx), indexing="ij")
        a = np.stack([np.sin(x / 3.0 + t) * np.cos(y / 4.0) + z / 10.0 for t in range(nt)]) * scale
    elif kind == "sparse":
        a = np.where(rng.random(shape) < 0.05, rng.random(shape) * scale, 0.0)
    elif kind == "noise":
        a = rng.normal(0, scale, shape)
    elif kind == "constant":
        a = np.full(shape, scale)
    else:
        a = rng.random(shape) * scale
        a[rng.random(shape) < 0.3] = np.nan
    return (nx, ny, nz), nt, a.astype(np.float32), draw(st.sampled_from([8, 16]))


def grid(nx, ny, nz):
    return {"nx": nx, "ny": ny, "nz": nz, "origin": (0.0, 0.0, 250.0), "spacing": (1000.0, 1000.0, 500.0)}


@CFG
@seed(SEED)
@given(fields())
def round_trip(case):
    CALLS["n"] += 1
    (nx, ny, nz), nt, a, bits = case
    p = path("rt")
    vesuvius.write(p, grid(nx, ny, nz), np.arange(nt) * 600, {"X": a}, bits=bits)
    with vesuvius.open(p) as f:
        sp = f.species[0]
        assert f.grid["nx"] == nx and f.grid["ny"] == ny and f.grid["nz"] == nz
        assert len(f.times) == nt
        for t in range(nt):
            b = f.read("X", t)
            assert b.shape == (nz, ny, nx)
            nan_a, nan_b = np.isnan(a[t]), np.isnan(b)
            assert (nan_a == nan_b).all(), "no data moved"
            err = np.abs(b[~nan_a].astype(np.float64) - a[t][~nan_a])
            assert err.size == 0 or err.max() <= sp.max_abs_error * (1 + 1e-6) + 1e-30, \
                "error %g over the bound %g" % (err.max(), sp.max_abs_error)
        k, j, i = nz - 1, ny // 2, nx - 1
        q = f.query(cell=(i, j, k))
        v = q.values["X"]
        for t in range(nt):
            want = f.read("X", t)[k, j, i]
            assert (np.isnan(v[t]) and np.isnan(want)) or v[t] == want, "query %r read %r" % (v[t], want)
    os.unlink(p)


bad_value = st.one_of(st.just(float("nan")), st.just(float("inf")), st.just(-1.0), st.just(0.0), st.just(1e308),
                      st.integers(-2 ** 40, 2 ** 40), st.text(max_size=5), st.none())


@CFG
@seed(SEED)
@given(st.dictionaries(st.sampled_from(["nx", "ny", "nz", "origin", "spacing", "vertical"]), bad_value, min_size=1),
       st.sampled_from(["times", "fields", "grid", "bits", "scale", "names"]), st.data())
def bad_arguments(overrides, what, data):
    """Any wrong argument is an exception (never a crash, never a file)."""
    CALLS["n"] += 1
    g = grid(4, 3, 2)
    times, flds, bits, scale = [0], {"X": np.zeros((1, 2, 3, 4), np.float32)}, 16, "linear"
    if what == "grid":
        for k, v in overrides.items():
            g[k] = (v, v, v) if k in ("origin", "spacing") else v
    elif what == "times":
        times = data.draw(st.lists(st.integers(-2 ** 63, 2 ** 63 - 1), max_size=3))
    elif what == "fields":
        shp = data.draw(st.lists(st.integers(0, 5), min_size=0, max_size=5))
        flds = {"X": np.zeros(shp, np.float32)}
    elif what == "bits":
        bits = data.draw(st.integers(-100, 100))
    elif what == "scale":
        scale = data.draw(st.text(max_size=6))
    else:
        name = data.draw(st.text(min_size=0, max_size=80))
        flds = {name: np.zeros((1, 2, 3, 4), np.float32)}
    p = path("bad")
    try:
        vesuvius.write(p, g, times, flds, bits=bits, scale=scale)
    except (vesuvius.Error, ValueError, TypeError, OverflowError, KeyError, UnicodeError):
        assert not os.path.exists(p), "a refused write left a file"
        return
    with vesuvius.open(p) as f:  # taken: it must read back as written
        assert f.read(0, 0).shape == (f.grid["nz"], f.grid["ny"], f.grid["nx"])
    os.unlink(p)


@CFG
@seed(SEED)
@given(st.one_of(st.integers(-2 ** 70, 2 ** 70), st.text(max_size=12), st.floats(allow_nan=True)),
       st.one_of(st.integers(-2 ** 70, 2 ** 70), st.text(max_size=12), st.none()),
       st.tuples(st.integers(-2 ** 40, 2 ** 40), st.integers(-2 ** 40, 2 ** 40), st.integers(-2 ** 40, 2 ** 40)))
def bad_reads(species, time, cell):
    """Out-of-range species, steps and cells: exceptions, never a crash."""
    CALLS["n"] += 1
    with vesuvius.open(GOLDEN) as f:
        try:
            f.read(species, 0 if time is None else time)
        except (vesuvius.Error, ValueError, TypeError, OverflowError, IndexError, KeyError):
            pass
        try:
            f.query(cell=cell)
        except (vesuvius.Error, ValueError, TypeError, OverflowError, IndexError):
            pass


GOLDEN = os.path.join(os.path.dirname(os.path.abspath(__file__)), "golden", "small.vsv")
failed = 0
for prop in (round_trip, bad_arguments, bad_reads):
    name = "python property %s (%d examples asked)" % (prop.__name__, EXAMPLES)
    CALLS["n"] = 0
    try:
        prop()
        print("PASS %s: %d runs" % (name, CALLS["n"]))
    except Exception:  # a falsified property: Hypothesis prints the example
        failed += 1
        print("FAIL %s: %s" % (name, traceback.format_exc(limit=3).replace("\n", " | ")[-900:]))
sys.exit(1 if failed else 0)
