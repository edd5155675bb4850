"""test_python.py — the Python module `vesuvius` (unittest), on the bundled MM5
sample and, when ../shared is beside the checkout, the full MM5 run: f.read against
vsv-info --stats, vsv-query's CSV/JSON against f.read and f.query, lat/lon, bricks,
the writer's round trip, to_xarray, and errors carrying the library's message.
Prints "PASS name" / "FAIL name: why" lines for tests/run.sh.
Run: PYTHONPATH=build/python B=build python3 tests/test_python.py"""
import atexit
import csv
import io
import json
import math
import os
import shutil
import subprocess
import sys
import tempfile
import unittest

import numpy as np

import vesuvius

B = os.environ.get("B", "build")
SHARED = os.environ.get("SHARED", "../shared")
TMP = tempfile.mkdtemp(prefix="vsv-py-")
atexit.register(shutil.rmtree, TMP, True)
FULL = os.path.join(SHARED, "data/mm5/run1/MMOUT_DOMAIN1")


def data(rel):
    """A test data file: the repository's copy (tests/data), else ../shared's."""
    own = os.path.join("tests/data", rel)
    return own if os.path.exists(own) else os.path.join(SHARED, "data", rel)


def tool(*args):
    return subprocess.run([os.path.join(B, args[0])] + list(args[1:]), check=True, capture_output=True,
                          text=True).stdout


def convert(src, out):
    path = os.path.join(TMP, out)
    if not os.path.exists(path):
        tool("vsv-convert", "-q", "--vertical", "even", src, "-o", path)
    return path


class Sample(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.path = convert("samples/mm5/MMOUT_DOMAIN1_CROP", "crop.vsv")
        cls.f = vesuvius.open(cls.path)

    def test_times_are_datetime64(self):
        t = self.f.times
        self.assertEqual(t.dtype, np.dtype("datetime64[s]"))
        self.assertEqual(list(t.astype(str)), ["1995-10-24T00:00:00", "1995-10-24T01:00:00",
                                               "1995-10-24T02:00:00", "1995-10-24T03:00:00"])

    def test_species_names_units_bounds(self):
        sp = self.f.species
        self.assertEqual([s.name for s in sp], ["Q", "CLW", "RNW", "ICE", "SNOW", "wind_east", "wind_north", "wind_up"])
        self.assertTrue(all(s.units == "kg/kg" and s.bits == 16 and 0 < s.max_abs_error < 1e-6 for s in sp[:5]))
        # the stored wind (vsv-convert's default): m/s, 16 bits, a bound of a few 1e-4 m/s
        self.assertTrue(all(s.units == "m s-1" and s.bits == 16 and 0 < s.max_abs_error < 1e-3 for s in sp[5:]))
        info = json.loads(tool("vsv-info", "--json", self.path))
        for s, j in zip(sp, info["species"]):
            self.assertAlmostEqual(s.max_abs_error, j["max_abs_error"], delta=s.max_abs_error * 1e-8)

    def test_grid_and_projection(self):
        g, p = self.f.grid, self.f.projection
        self.assertEqual((g["nx"], g["ny"], g["nz"], g["vertical"]), (39, 39, 40, "even"))
        self.assertEqual((p["kind"], p["lat0"], p["lon0"], p["lat1"], p["lat2"]), ("lcc", 38, -97, 50, 33))
        self.assertEqual(self.f.height.shape, (40,))
        self.assertAlmostEqual(self.f.height[0], 177.5)
        self.assertAlmostEqual(self.f.height[39], 14022.5)

    def test_read_matches_vsv_info_stats(self):
        """f.read of every species and step: min, max exactly and the mean as vsv-info --stats prints them."""
        stats = json.loads(tool("vsv-info", "--stats", "--json", self.path))["stats"]
        self.assertEqual(len(stats), 32)  # 8 species (5 and the wind's 3) x 4 steps
        for row in stats:
            a = self.f.read(row["species"], time=row["time"])
            self.assertEqual(a.shape, (40, 39, 39))
            self.assertEqual(a.dtype, np.float32)
            fin = a[np.isfinite(a)]
            self.assertEqual(float(np.float32(row["min"])), float(fin.min()), row)
            self.assertEqual(float(np.float32(row["max"])), float(fin.max()), row)
            self.assertAlmostEqual(row["mean"], float(fin.astype(np.float64).mean()), delta=abs(row["mean"]) * 1e-6)

    def test_read_decodes_into_the_array_it_returns(self):
        a = self.f.read("Q", 2)
        self.assertTrue(a.flags["OWNDATA"] and a.flags["C_CONTIGUOUS"] and a.flags["WRITEABLE"])
        self.assertIsNone(a.base)

    def test_read_by_time_kinds(self):
        want = self.f.read("SNOW", 2)
        for t in (2, -2, "1995-10-24T02:00:00Z", np.datetime64("1995-10-24T02:00:00"), "1995-10-24T01:50:00Z"):
            np.testing.assert_array_equal(self.f.read("SNOW", t), want, err_msg=str(t))
        np.testing.assert_array_equal(self.f.read(4, 2), want)
        # numpy integers (np.arange, argmin, a times array's index) are step indices too
        for t in (np.int64(2), np.int32(-2), np.arange(4)[2]):
            np.testing.assert_array_equal(self.f.read("SNOW", t), want, err_msg=repr(t))
        np.testing.assert_array_equal(self.f.heights(np.int64(3)), self.f.heights(3))

    def test_aware_datetimes_are_their_utc_time(self):
        from datetime import datetime, timedelta, timezone
        minus2 = timezone(timedelta(hours=-2))
        # 00:00 at UTC-2 is 02:00Z; 22:00 the day before at UTC-2 is 00:00Z
        np.testing.assert_array_equal(self.f.read("SNOW", datetime(1995, 10, 24, 0, tzinfo=minus2)),
                                      self.f.read("SNOW", 2))
        np.testing.assert_array_equal(self.f.read("SNOW", datetime(1995, 10, 23, 22, tzinfo=minus2)),
                                      self.f.read("SNOW", 0))
        with self.assertRaisesRegex(vesuvius.Error, "after the last step"):
            self.f.read("SNOW", datetime(1995, 10, 24, 2, tzinfo=minus2))  # 04:00Z
        np.testing.assert_array_equal(self.f.read("SNOW", datetime(1995, 10, 24, 2, tzinfo=timezone.utc)),
                                      self.f.read("SNOW", 2))

    def test_write_keeps_per_column_heights(self):
        """A File's grid with per-column heights (native MM5 levels) is written with
        them (heights=, terrain=): every cell's height and the terrain come back, and
        a point's cell is the original's; without heights= it is refused (its levels
        would stand at their mean height in every column)."""
        native = os.path.join(TMP, "crop-native-w.vsv")
        tool("vsv-convert", "-q", "--vars", "CLW", "samples/mm5/MMOUT_DOMAIN1_CROP", "-o", native)
        f = vesuvius.open(native)
        n = len(f.times)
        self.assertTrue(f.grid["column_heights"])
        c = np.stack([f.read("CLW", t) for t in range(n)])
        out = os.path.join(TMP, "w-heights.vsv")
        with self.assertRaisesRegex(vesuvius.Error, "per-column heights"):
            vesuvius.write(out, grid=f.grid, projection=f.projection, times=f.times, fields={"CLW2": 2 * c})
        self.assertFalse(os.path.exists(out))
        h = np.stack([f.heights(t) for t in range(n)])
        vesuvius.write(out, grid=f.grid, projection=f.projection, times=f.times, fields={"CLW2": 2 * c},
                       terrain=f.terrain, heights=h)
        g = vesuvius.open(out)
        np.testing.assert_array_equal(np.stack([g.heights(t) for t in range(n)]), h)
        np.testing.assert_array_equal(g.terrain, f.terrain)
        self.assertEqual(g.query(46, -116, 1200).cell, f.query(46, -116, 1200).cell)
        with self.assertRaisesRegex(vesuvius.Error, "heights: "):
            vesuvius.write(out, grid=f.grid, projection=f.projection, times=f.times, fields={"CLW2": 2 * c},
                           heights=h[:, ::-1])  # decreasing upward

    def test_write_errors_name_the_file(self):
        g = {"nx": 2, "ny": 2, "nz": 2, "origin": (0, 0, 0), "spacing": (1, 1, 1)}
        bad = os.path.join(TMP, "nodir", "x.vsv")
        with self.assertRaisesRegex(vesuvius.Error, "^write: %s: cannot create" % bad):
            vesuvius.write(bad, grid=g, times=[0, 60], fields={"a": np.zeros((2, 2, 2, 2))})
        with self.assertRaisesRegex(vesuvius.Error, r"x2.vsv: times: step 1 \(1970-01-01T00:00:00Z\) does not come "
                                    r"after step 0 \(1970-01-01T00:01:00Z\)"):
            vesuvius.write(os.path.join(TMP, "x2.vsv"), grid=g, times=[60, 0], fields={"a": np.zeros((2, 2, 2, 2))})
        # native levels falling with k were taken (level 0 at 3000 m drawn lowest);
        # none at all was "vertical kind 1 needs levels"
        native = dict(g, vertical="native")
        with self.assertRaisesRegex(vesuvius.Error, r"x3.vsv: native levels: level 1 \(1000\) after level 0 "
                                    r"\(3000\): they must rise with k"):
            vesuvius.write(os.path.join(TMP, "x3.vsv"), grid=native, times=[0], fields={"a": np.zeros((2, 2, 2))},
                           levels=[3000, 1000])
        with self.assertRaisesRegex(vesuvius.Error, "x4.vsv: native levels need their levels"):
            vesuvius.write(os.path.join(TMP, "x4.vsv"), grid=native, times=[0], fields={"a": np.zeros((2, 2, 2))})

    def test_query_refuses_what_vsv_query_refuses(self):
        for lat, lon, h, what in ((float("nan"), 0, None, "latitude nan"), (41.88, -447.63, None, "longitude -447.63"),
                                  (41.88, 632.37, None, "longitude 632.37"), (95, 0, None, "latitude 95"),
                                  (46, -116, float("nan"), "height nan")):
            with self.assertRaisesRegex(ValueError, what):
                self.f.query(lat, lon, h)

    def test_species_index_bounds(self):
        """Species by index: 0..7 of eight (five and the wind's three), the last one
        included; 8 and -1 refused by name."""
        np.testing.assert_array_equal(self.f.read(7, 1), self.f.read("wind_up", 1))
        for s in (8, -1):
            with self.assertRaisesRegex(vesuvius.Error, r"species %d out of range \(0..7\)" % s):
                self.f.read(s, 0)
        with self.assertRaisesRegex(vesuvius.Error, r"species 8 out of range \(0..7\)"):
            self.f.read_brick(8, 0, 0)

    def test_query_csv_equals_read(self):
        """vsv-query --csv at a snowy point: every row equals f.read at the same cell."""
        out = tool("vsv-query", self.path, "--at", "46,-116,3000", "--species", "CLW,SNOW", "--csv")
        rows = list(csv.DictReader(io.StringIO(out)))
        self.assertEqual(len(rows), 4)
        nonzero = 0
        for t, r in enumerate(rows):
            i, j, k = int(r["i"]), int(r["j"]), int(r["k"])
            for s in ("CLW", "SNOW"):
                v = np.float32(float(r["%s (kg/kg)" % s]))
                self.assertEqual(v, self.f.read(s, t)[k, j, i], (t, s))
                nonzero += v != 0
        self.assertGreater(nonzero, 0)

    def test_profile_equals_read_column(self):
        out = tool("vsv-query", self.path, "--profile", "46,-116", "--species", "SNOW", "--csv", "--time", "2")
        rows = list(csv.DictReader(io.StringIO(out)))
        i, j = int(rows[0]["i"]), int(rows[0]["j"])
        col = self.f.read("SNOW", 2)[:, j, i]
        np.testing.assert_array_equal([np.float32(float(r["SNOW (kg/kg)"])) for r in rows], col)
        self.assertEqual([float(r["height (m)"]) for r in rows], list(self.f.height))

    def test_f_query_equals_vsv_query_json(self):
        for interp in (False, True):
            args = ["vsv-query", self.path, "--at", "46,-116,3000", "--json"] + (["--interp"] if interp else [])
            doc = json.loads(tool(*args))
            p = self.f.query(46, -116, 3000, interp=interp)
            r0 = doc["rows"][0]
            self.assertEqual(p.cell, (r0["i"], r0["j"], r0["k"]))
            self.assertAlmostEqual(p.lat, r0["lat"], places=6)
            for t, r in enumerate(doc["rows"]):
                for s, v in r["values"].items():
                    self.assertEqual(np.float32(v), p.values[s][t], (interp, t, s))
        c = self.f.query(cell=(30, 3, 8))
        self.assertEqual(c.cell, (30, 3, 8))
        np.testing.assert_array_equal(c.values["SNOW"], self.f.query(46, -116, 3000).values["SNOW"])

    def test_lat_lon_arrays(self):
        lat, lon = self.f.lat, self.f.lon
        self.assertEqual(lat.shape, (39, 39))
        corners = json.loads(tool("vsv-info", "--json", self.path))["corners"]
        sw = corners[0]
        self.assertAlmostEqual(lat[0, 0], sw["lat"], places=5)
        self.assertAlmostEqual(lon[0, 0], sw["lon"], places=5)
        doc = json.loads(tool("vsv-query", self.path, "--cell", "30,3,8", "--json", "-t", "0"))
        self.assertAlmostEqual(lat[3, 30], doc["rows"][0]["lat"], places=6)
        self.assertAlmostEqual(lon[3, 30], doc["rows"][0]["lon"], places=6)

    def test_bricks_stream_the_volume(self):
        vol = self.f.read("SNOW", 3)
        # an empty brick reads 0, and no data (NaN) under the ground
        got = np.where(np.isnan(vol), np.nan, 0).astype(vol.dtype)
        n = 0
        for (k0, j0, i0), a in self.f.bricks("SNOW", 3):
            got[k0:k0 + a.shape[0], j0:j0 + a.shape[1], i0:i0 + a.shape[2]] = a
            n += 1
            # none all zeros: brick 3 is UNCHANGED from an empty one (it was yielded)
            self.assertGreater(np.nanmax(a), 0, (k0, j0, i0))
        np.testing.assert_array_equal(got, vol)
        self.assertTrue(0 < n < self.f.grid["nbricks"])

    def test_errors_carry_the_library_message(self):
        with self.assertRaisesRegex(vesuvius.Error, "no species 'NOPE'"):
            self.f.read("NOPE")
        with self.assertRaisesRegex(vesuvius.Error, r"time step 9 out of range \(0..3\)"):
            self.f.read("Q", 9)
        with self.assertRaisesRegex(vesuvius.Error, "after the last step"):
            self.f.read("Q", "1996-01-01T00:00:00Z")
        with self.assertRaisesRegex(vesuvius.Error, r"41.88,-87.63 is outside the grid \(39 x 39 cells"):
            self.f.query(41.88, -87.63)
        with self.assertRaisesRegex(vesuvius.Error, "not a .vsv file"):
            vesuvius.open("samples/mm5/MMOUT_DOMAIN1_CROP")
        with self.assertRaisesRegex(vesuvius.Error, "checksum"):
            g = vesuvius.open("tests/golden/bad/payload.vsv")
            for s in range(len(g.species)):
                for t in range(len(g.times)):
                    g.read(s, t)

    def test_to_xarray(self):
        try:
            import xarray  # noqa: F401
        except ImportError:
            self.skipTest("xarray not installed")
        ds = self.f.to_xarray(["CLW", "SNOW"])
        self.assertEqual(dict(ds.sizes), {"time": 4, "z": 40, "y": 39, "x": 39})
        self.assertEqual(list(self.f.to_xarray("CLW").data_vars)[0], "CLW")
        with self.assertRaisesRegex(ValueError, "no species named"):
            self.f.to_xarray([])
        self.assertEqual(ds["SNOW"].attrs["units"], "kg/kg")
        np.testing.assert_array_equal(ds["SNOW"].values[2], self.f.read("SNOW", 2))
        self.assertEqual(ds["lat"].shape, (39, 39))
        self.assertEqual(str(ds["time"].values[3])[:19], "1995-10-24T03:00:00")

    def test_below_ground_is_nan_for_every_species(self):
        """One rule below the ground: every species reads NaN in the cells whose centre
        lies below the terrain (Q, the hydrometeors and the wind alike), in read, query and
        the netCDF export."""
        under = self.f.height[:, None, None] < self.f.terrain[None, :, :]
        self.assertGreater(under.sum(), 1000)
        for s in self.f.species:
            a = self.f.read(s.name, 3)
            self.assertTrue(np.isnan(a[under]).all(), s.name)
        k, j, i = np.argwhere(under)[0]
        row = list(csv.DictReader(io.StringIO(tool("vsv-query", self.path, "--cell", "%d,%d,%d" % (i, j, k), "--csv",
                                                    "--time", "3"))))[0]
        self.assertTrue(all(math.isnan(float(row["%s (%s)" % (s.name, s.units)])) for s in self.f.species), row)

    def test_write_round_trip(self):
        """A file written from numpy with a File's grid and projection reads back within the
        stated bound, with the same lat/lon and times; below its terrain, no data."""
        rng = np.random.default_rng(7)
        g = self.f.grid
        shape = (3, g["nz"], g["ny"], g["nx"])
        a = rng.random(shape, dtype=np.float32) * 1e-3
        a[:, :5] = np.nan
        b = np.zeros(shape, np.float32)
        b[1, 10:20, 5:9, 7:30] = 2.5
        times = np.array(["2020-06-01T00:00", "2020-06-01T00:10", "2020-06-01T00:20"], dtype="datetime64[s]")
        out = os.path.join(TMP, "written.vsv")
        # the terrain as float64, numpy's default (it was refused: a cast not 'safe')
        vesuvius.write(out, grid=g, projection=self.f.projection, times=times, fields={"A": a, "B": b},
                       units={"A": "kg/kg", "B": "ppm"}, terrain=self.f.terrain.astype(np.float64))
        w = vesuvius.open(out)
        np.testing.assert_array_equal(w.times, times)
        self.assertEqual([(s.name, s.units) for s in w.species], [("A", "kg/kg"), ("B", "ppm")])
        np.testing.assert_array_equal(w.lat, self.f.lat)
        np.testing.assert_array_equal(w.lon, self.f.lon)
        under = w.height[:, None, None] < w.terrain[None, :, :]
        for t in range(3):
            ra, rb = w.read("A", t), w.read("B", t)
            self.assertTrue(np.array_equal(np.isnan(ra), np.isnan(a[t]) | under))
            fin = np.isfinite(a[t]) & ~under
            self.assertLessEqual(np.abs(ra[fin] - a[t][fin]).max(), w.species[0].max_abs_error)
            self.assertTrue(np.isnan(rb[under]).all())
            self.assertLessEqual(np.abs(rb[~under] - b[t][~under]).max(), w.species[1].max_abs_error)
        subprocess.run([os.path.join(B, "vsv-info"), "--check", out], check=True, capture_output=True)

    def test_threads_share_a_file(self):
        """Threads reading one File at once get what one thread gets (issue 33: a shared
        decoder without the GIL crashed or said 'Data corruption'), and close() waits
        for the reads in progress; a read after it raises."""
        from concurrent.futures import ThreadPoolExecutor
        f = vesuvius.open(self.path)
        want = {(s, t): f.read(s, t) for s in ("CLW", "Q") for t in range(4)}
        jobs = [(s, t) for _ in range(12) for s in ("CLW", "Q") for t in range(4)]
        with ThreadPoolExecutor(4) as ex:
            got = list(ex.map(lambda j: (j, f.read(j[0], j[1]), f.read_brick(j[0], j[1], 0)[0]), jobs))
        for j, a, _ in got:
            np.testing.assert_array_equal(a, want[j])
        g = vesuvius.open(self.path)
        errors = []

        def reader():
            for t in range(200):
                try:
                    g.read("Q", t % 4)
                except vesuvius.Error as e:
                    errors.append(str(e))
                    return
        with ThreadPoolExecutor(3) as ex:
            futs = [ex.submit(reader) for _ in range(3)]
            g.close()
            for fu in futs:
                fu.result()
        self.assertTrue(all("closed" in e for e in errors), errors[:3])
        with self.assertRaisesRegex(vesuvius.Error, "closed"):
            g.read("Q", 0)

    def test_threads_read_every_species_at_once(self):
        """Four threads reading every species and step of one File, 200 reads in all, get
        what one thread gets: File.read decodes without the GIL but under the File's
        lock (without it the threads share one decoder: a crash, or 'Data corruption').
        Run in a child process, so that a crash fails this test, not the whole suite."""
        code = "\n".join([
            "import sys, numpy as np, vesuvius",
            "from concurrent.futures import ThreadPoolExecutor",
            "f = vesuvius.open(sys.argv[1])",
            "want = {(s, t): f.read(s, t) for s in range(5) for t in range(4)}",
            "jobs = [(s, t) for _ in range(10) for s in range(5) for t in range(4)]",
            "with ThreadPoolExecutor(4) as ex:",
            "    got = list(ex.map(lambda j: f.read(*j), jobs))",
            "print(sum(np.array_equal(a, want[j], equal_nan=True) for j, a in zip(jobs, got)), 'same')"])
        r = subprocess.run([sys.executable, "-c", code, self.path], capture_output=True, text=True, timeout=300)
        self.assertEqual((r.returncode, r.stdout.strip()), (0, "200 same"), r.stderr[-300:])

    def test_write_refuses_names_it_would_cut_or_garble(self):
        """A species name of 64 bytes was cut to 63 silently; a control character made
        vsv-info --json print invalid JSON (issue 33): both refused, nothing written."""
        g = {"nx": 4, "ny": 3, "nz": 2, "origin": (0, 0, 100), "spacing": (1000, 1000, 200)}
        a = np.zeros((1, 2, 3, 4), np.float32)
        out = os.path.join(TMP, "names.vsv")
        with self.assertRaisesRegex(vesuvius.Error, "at most 63 bytes"):
            vesuvius.write(out, grid=g, times=[0], fields={"N" * 64: a})
        with self.assertRaisesRegex(vesuvius.Error, "not UTF-8 text"):
            vesuvius.write(out, grid=g, times=[0], fields={"bad\nname": a})
        self.assertFalse(os.path.exists(out))
        vesuvius.write(out, grid=g, times=[0], fields={"N" * 63: a, "ozone \u00b5g": a})
        self.assertEqual([s.name for s in vesuvius.open(out).species], ["N" * 63, "ozone \u00b5g"])
        json.loads(tool("vsv-info", "--json", out))

    def test_species_without_a_value_has_no_range(self):
        """A species with no finite value anywhere has no range: data_min and data_max are
        None (they were inf and -inf), as vsv-info says "no value" and --json null."""
        g = {"nx": 4, "ny": 3, "nz": 2, "origin": (0, 0, 100), "spacing": (1000, 1000, 200)}
        a = np.full((1, 2, 3, 4), np.nan, np.float32)
        out = os.path.join(TMP, "allnan.vsv")
        vesuvius.write(out, grid=g, times=[0], fields={"E": a, "F": np.ones_like(a)})
        e, f = vesuvius.open(out).species
        self.assertEqual((e.data_min, e.data_max), (None, None))
        self.assertEqual((f.data_min, f.data_max), (1.0, 1.0))
        sp = json.loads(tool("vsv-info", "--json", out))["species"]
        self.assertEqual((sp[0]["min"], sp[0]["max"]), (None, None))

    def test_write_refuses_times_beyond_the_years(self):
        """A time outside the years 1..9999 is refused (INT64_MIN reached netCDF as a
        time axis before, issue 33)."""
        g = {"nx": 4, "ny": 3, "nz": 2, "origin": (0, 0, 100), "spacing": (1000, 1000, 200)}
        a = np.zeros((2, 2, 3, 4), np.float32)
        with self.assertRaisesRegex(vesuvius.Error, "outside the years 1..9999"):
            vesuvius.write(os.path.join(TMP, "t.vsv"), grid=g, times=[-2 ** 63, 0], fields={"A": a})
        self.assertFalse(os.path.exists(os.path.join(TMP, "t.vsv")))

    def test_write_refuses_bad_input(self):
        g = {"nx": 4, "ny": 3, "nz": 2, "origin": (0, 0, 100), "spacing": (1000, 1000, 200)}
        out = os.path.join(TMP, "bad.vsv")
        with self.assertRaisesRegex(vesuvius.Error, r"expected float32 \(2, 2, 3, 4\)"):
            vesuvius.write(out, grid=g, times=[0, 60], fields={"X": np.zeros((2, 2, 4, 3))})
        with self.assertRaisesRegex(vesuvius.Error, "unknown projection 'utm'"):
            vesuvius.write(out, grid=g, times=[0], projection={"kind": "utm"}, fields={"X": np.zeros((1, 2, 3, 4))})
        with self.assertRaisesRegex(vesuvius.Error, "increase|order|time"):
            vesuvius.write(out, grid=g, times=[60, 0], fields={"X": np.zeros((2, 2, 3, 4))})
        self.assertFalse(os.path.exists(out))
        vesuvius.write(out, grid=g, times=["2001-02-03T04:05:06Z"], fields={"X": np.ones((2, 3, 4))})
        self.assertEqual(str(vesuvius.open(out).times[0]), "2001-02-03T04:05:06")


def xarray_open(path):
    """xarray.open_dataset with every warning an error (after a first open that
    lets xarray import its lazy dependencies, whose own deprecation notes are
    not about the file)."""
    import warnings
    import netCDF4  # noqa: F401
    import xarray as xr
    xr.open_dataset(path).close()
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        return xr.open_dataset(path).load()


PROJECTIONS = [dict(kind="lcc", lat0=38, lon0=-97, lat1=50, lat2=33),
               dict(kind="lcc", lat0=29.04, lon0=89.8, lat1=29.04, lat2=29.04),
               dict(kind="pstereo", lat0=60, lon0=-105, lat1=60),
               dict(kind="pstereo", lat0=-71, lon0=0, lat1=-71),
               dict(kind="mercator", lat0=0, lon0=-89, lat1=20),
               dict(kind="tmerc", lat0=0, lon0=-87, lat1=0.9996),
               dict(kind="albers", lat0=23, lon0=-96, lat1=29.5, lat2=45.5),
               dict(kind="latlon")]


class NetCDF(unittest.TestCase):
    """vsv-export --netcdf: xarray reads it without warnings and gets the .vsv's decoded
    values; every projection the format carries survives the round trip through the
    CF reader, and PROJ (pyproj) reads the grid_mapping as the library does."""

    @classmethod
    def setUpClass(cls):
        try:
            import xarray  # noqa: F401
        except ImportError:
            raise unittest.SkipTest("xarray not installed")
        cls.path = convert("samples/mm5/MMOUT_DOMAIN1_CROP", "crop.vsv")
        cls.nc = os.path.join(TMP, "crop.nc")
        tool("vsv-export", "-q", cls.path, "--netcdf", cls.nc)
        cls.f = vesuvius.open(cls.path)

    def agree(self, vsv, variables=None):
        """to_xarray() and xarray.open_dataset of vsv-export's file hold the same
        variables, values and CF attributes."""
        nc = vsv + ".nc"
        tool("vsv-export", "-q", vsv, "--netcdf", nc)
        a = vesuvius.open(vsv).to_xarray()
        b = xarray_open(nc)
        keys = ("units", "standard_name", "positive", "comment", "vsv_units_original")
        names = set(a.variables)
        self.assertEqual(names, set(b.variables) - {"crs"})
        for n in names:
            np.testing.assert_array_equal(a[n].values, b[n].values, err_msg=n)
            for k in keys:
                self.assertEqual(a[n].attrs.get(k), b[n].attrs.get(k), "%s: %s" % (n, k))
        for k in ("long_name",):
            self.assertEqual(a["z"].attrs.get(k), b["z"].attrs.get(k))
        return a

    def test_to_xarray_agrees_with_export(self):
        """The MM5 crop on even heights, on native levels with per-column heights,
        and a CMAQ file whose heights count from the ground."""
        a = self.agree(self.path)
        self.assertEqual(a["CLW"].attrs["standard_name"], "cloud_liquid_water_mixing_ratio")
        self.assertEqual(a["z"].attrs["standard_name"], "altitude")
        self.assertEqual(a["x"].attrs["units"], "m")
        self.assertIn("terrain", a)
        native = os.path.join(TMP, "crop-native.vsv")
        tool("vsv-convert", "-q", "--vertical", "native", "--vars", "CLW,Q", "samples/mm5/MMOUT_DOMAIN1_CROP",
             "-o", native)
        a = self.agree(native)
        self.assertEqual(a["height"].dims, ("time", "z", "y", "x"))
        cmaq = convert("tests/corpus/netcdf/ioapi-cmaq.nc", "cmaq.vsv")
        a = self.agree(cmaq)
        self.assertEqual(a["z"].attrs["standard_name"], "height")
        self.assertEqual(a["O3"].attrs["units"], "ppm")
        self.assertEqual(vesuvius.open(cmaq).grid["datum"], "ground")

    def test_360_day_calendar(self):
        """A 360-day CF file: its steps are cftime dates of that calendar (29 and 30
        February among them), a read by such a date finds its step, and to_xarray
        agrees with the export."""
        import netCDF4
        import cftime
        src = os.path.join(TMP, "c360.nc")
        d = netCDF4.Dataset(src, "w")
        d.Conventions = "CF-1.8"
        for name, size in (("time", 3), ("z", 2), ("y", 3), ("x", 4)):
            d.createDimension(name, size)
        t = d.createVariable("time", "f8", ("time",))
        t.units, t.calendar = "days since 2001-02-28", "360_day"
        t[:] = [0, 1, 2]
        for name, n in (("z", 2), ("y", 3), ("x", 4)):
            c = d.createVariable(name, "f8", (name,))
            c.units = "m"
            c[:] = np.arange(n) * 1000.0 + (500 if name == "z" else 0)
        d["z"].positive = "up"
        v = d.createVariable("O3", "f4", ("time", "z", "y", "x"))
        v.units = "ppm"
        v[:] = np.arange(72, dtype="f4").reshape(3, 2, 3, 4) * 0.01
        d.close()
        out = os.path.join(TMP, "c360.vsv")
        tool("vsv-convert", "-q", src, "-o", out)
        f = vesuvius.open(out)
        self.assertEqual(f.grid["calendar"], "360_day")
        self.assertEqual(list(f.times), [cftime.Datetime360Day(2001, 2, d) for d in (28, 29, 30)])
        self.assertAlmostEqual(float(f.read("O3", f.times[2]).max()), 0.71, places=5)
        self.assertAlmostEqual(float(f.read("O3", "2001-02-29T00:00:00Z").max()), 0.47, places=5)
        self.agree(out)

    def test_vert_units(self):
        """Heights are in m on even and native files alike; an index has none."""
        self.assertEqual(self.f.grid["vert_units"], "m")
        native = convert("tests/corpus/netcdf/wrf-crop.nc", "wrf-crop.vsv")
        self.assertEqual(vesuvius.open(native).grid["vert_units"], "m")

    def test_xarray_values_equal_decoded(self):
        ds = xarray_open(self.nc)
        self.assertEqual(dict(ds.sizes), {"time": 4, "z": 40, "y": 39, "x": 39})
        np.testing.assert_array_equal(ds["time"].values.astype("datetime64[s]"), self.f.times)
        for s in self.f.species:
            self.assertEqual(ds[s.name].attrs["units"], s.units)
            self.assertEqual(ds[s.name].attrs["long_name"], s.description)
            self.assertEqual(ds[s.name].attrs["vsv_max_abs_error"], s.max_abs_error)
            self.assertEqual(ds[s.name].dtype, np.float32)
            for t in range(4):
                np.testing.assert_array_equal(ds[s.name].values[t], self.f.read(s.name, t), err_msg=s.name)
        np.testing.assert_array_equal(ds["lat"].values, self.f.lat)
        np.testing.assert_array_equal(ds["lon"].values, self.f.lon)
        np.testing.assert_array_equal(ds["z"].values, self.f.height)
        np.testing.assert_array_equal(ds["terrain"].values, self.f.terrain)
        self.assertEqual(ds["SNOW"].encoding["chunksizes"], (1, 40, 39, 39))
        self.assertTrue(ds["SNOW"].encoding["zlib"])

    def test_every_projection_round_trips(self):
        rng = np.random.default_rng(1)
        try:
            import pyproj
        except ImportError:
            pyproj = None
            print("  (pyproj not installed: the PROJ cross-check is skipped)")
        for p in PROJECTIONS:
            if p["kind"] == "latlon":
                g = dict(nx=20, ny=15, nz=3, origin=(-100, 30, 100), spacing=(0.25, 0.25, 200))
            else:
                g = dict(nx=20, ny=15, nz=3, origin=(-3e5, -2e5, 100), spacing=(30000, 30000, 200))
            a = rng.random((2, 3, 15, 20), dtype=np.float32)
            a[:, 0, :3] = np.nan
            src, nc, back = (os.path.join(TMP, "p." + e) for e in ("vsv", "nc", "back.vsv"))
            vesuvius.write(src, grid=g, projection=p, times=[0, 3600], fields={"A": a}, units={"A": "1"})
            tool("vsv-export", "-q", src, "--netcdf", nc)
            tool("vsv-convert", "-q", nc, "-o", back)
            f, f2 = vesuvius.open(src), vesuvius.open(back)
            self.assertEqual(f2.projection["kind"], p["kind"])
            np.testing.assert_allclose(f2.lat, f.lat, rtol=0, atol=1e-9, err_msg=p["kind"])
            np.testing.assert_allclose(f2.lon, f.lon, rtol=0, atol=1e-9, err_msg=p["kind"])
            for t in range(2):
                np.testing.assert_array_equal(f2.read("A", t), f.read("A", t), err_msg=p["kind"])
            ds = xarray_open(nc)
            np.testing.assert_array_equal(ds["A"].values[1], f.read("A", 1))
            if pyproj and p["kind"] != "latlon":
                crs = pyproj.CRS.from_cf(ds["crs"].attrs)
                tr = pyproj.Transformer.from_crs(crs, crs.geodetic_crs, always_xy=True)
                X, Y = np.meshgrid(ds["x"].values, ds["y"].values)
                lon, lat = tr.transform(X, Y)
                d = np.hypot((lat - f.lat) * 111195, (lon - f.lon) * 111195 * np.cos(np.radians(lat)))
                self.assertLess(d.max(), 1e-3, p["kind"])

    def test_reads_cf_from_another_writer(self):
        """A CF file written by netCDF4-python the way many tools do: a lat/lon grid stored
        north to south, int16 packed with scale_factor/add_offset and a _FillValue, times
        in hours since a date, pressure levels. vsv-extract reads the same numbers."""
        import netCDF4
        path = os.path.join(TMP, "other.nc")
        d = netCDF4.Dataset(path, "w")
        d.Conventions = "CF-1.6"
        for n, k in (("time", None), ("level", 3), ("lat", 4), ("lon", 5)):
            d.createDimension(n, k)
        t = d.createVariable("time", "f8", ("time",))
        t.units = "hours since 2002-06-03 00:00:00"
        t.calendar = "gregorian"
        t[:] = [0, 1.5, 3]
        lv = d.createVariable("level", "f4", ("level",))
        lv.units = "hPa"
        lv.positive = "down"
        lv[:] = [1000, 850, 700]
        la = d.createVariable("lat", "f4", ("lat",))
        la.units = "degrees_north"
        la[:] = [50, 49, 48, 47]
        lo = d.createVariable("lon", "f4", ("lon",))
        lo.units = "degrees_east"
        lo[:] = [-100, -99, -98, -97, -96]
        v = d.createVariable("O3", "i2", ("time", "level", "lat", "lon"), fill_value=-32767)
        v.units = "ppb"
        v.long_name = "ozone"
        v.scale_factor = 0.01
        v.add_offset = 40.0
        rng = np.random.default_rng(3)
        want = (rng.random((3, 3, 4, 5)) * 50).astype(np.float32)
        want[1, 2, 0, 0] = np.nan
        v[:] = np.ma.masked_invalid(want)
        d.close()
        listed = tool("vsv-extract", "--list", path)
        self.assertIn("O3", listed)
        self.assertIn("2002-06-03T01:30:00Z", listed)
        back = os.path.join(TMP, "other.vsv")
        tool("vsv-convert", "-q", path, "-o", back)
        f = vesuvius.open(back)
        self.assertEqual(f.projection["kind"], "latlon")
        self.assertEqual(f.grid["vertical"], "coord")
        np.testing.assert_array_equal(f.height, [1000, 850, 700])
        self.assertEqual(f.lat[0, 0], 47)   # the south row first
        self.assertEqual(f.lon[0, 0], -100)
        ref = netCDF4.Dataset(path)["O3"][:].filled(np.nan)  # unpacked by netCDF4-python
        for s in range(3):
            got = f.read("O3", s)
            exp = ref[s][:, ::-1, :]
            self.assertTrue(np.array_equal(np.isnan(got), np.isnan(exp)), s)
            fin = np.isfinite(exp)
            self.assertLessEqual(np.abs(got[fin] - exp[fin]).max(), f.species[0].max_abs_error + 1e-5)

    @unittest.skipUnless(os.path.exists(data("wrf")), data("wrf") + " absent")
    def test_wrf_native_levels(self):
        """Real WRF output on its own (native) levels: z holds the levels' mean heights,
        the values come back equal."""
        src = os.path.join(TMP, "wrf.vsv")
        tool("vsv-convert", "-q", "--vertical", "native", "--vars", "QCLOUD,QVAPOR",
             data("wrf/wrf_d01_allvars_cropped.nc"), "-o", src)
        nc = os.path.join(TMP, "wrf.nc")
        tool("vsv-export", "-q", src, "--netcdf", nc)
        f = vesuvius.open(src)
        ds = xarray_open(nc)
        self.assertEqual(ds["z"].attrs["long_name"], "mean height above sea level of the model level")
        np.testing.assert_array_equal(ds["z"].values, f.grid["levels"])
        np.testing.assert_array_equal(ds["QVAPOR"].values[3], f.read("QVAPOR", 3))
        # per-column heights, moving in time: height(time, z, y, x) equals f.heights(t)
        self.assertEqual(ds["height"].dims, ("time", "z", "y", "x"))
        self.assertIn("height", ds["QVAPOR"].attrs.get("coordinates", "") + " ".join(ds["QVAPOR"].coords))
        for t in range(4):
            np.testing.assert_array_equal(ds["height"].values[t], f.heights(t).astype(np.float32))
        self.assertGreater(np.abs(f.heights(3) - f.heights(0)).max(), 1)
        back = os.path.join(TMP, "wrf-back.vsv")
        tool("vsv-convert", "-q", nc, "-o", back, "--vertical", "native")
        f2 = vesuvius.open(back)
        self.assertEqual(f2.grid["vertical"], "native")
        np.testing.assert_array_equal(f2.grid["levels"], f.grid["levels"])
        np.testing.assert_array_equal(f2.read("QVAPOR", 3), f.read("QVAPOR", 3))
        for t in range(4):
            np.testing.assert_array_equal(f2.heights(t), f.heights(t))
        # a height's level found again at every step, as vsv-query does
        p = f.query(30, 87, 6000)
        rows = list(csv.DictReader(io.StringIO(tool("vsv-query", src, "--at", "30,87,6000", "-s", "QVAPOR", "--csv"))))
        for t, r in enumerate(rows):
            self.assertEqual(np.float32(float(r["QVAPOR (kg kg-1)"])), p.values["QVAPOR"][t])
            self.assertAlmostEqual(float(r["height (m)"]), f.heights(t)[int(r["k"]), int(r["j"]), int(r["i"])], places=2)


@unittest.skipUnless(os.path.exists(FULL), FULL + " absent")
class FullRun(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.path = convert(FULL, "run.vsv")
        cls.f = vesuvius.open(cls.path)

    def test_chicago_csv_equals_read(self):
        """The issue's example: one row per step, values equal f.read at the same cell."""
        out = tool("vsv-query", "--at", "41.88,-87.63", "--species", "CLW,SNOW", "--csv", self.path)
        rows = list(csv.DictReader(io.StringIO(out)))
        self.assertEqual(len(rows), 4)
        for t, r in enumerate(rows):
            i, j, k = int(r["i"]), int(r["j"]), int(r["k"])
            self.assertEqual((i, j), (127, 85))
            for s in ("CLW", "SNOW"):
                self.assertEqual(np.float32(float(r["%s (kg/kg)" % s])), self.f.read(s, t)[k, j, i])
            q = float(tool("vsv-query", "--cell", "%d,%d,%d" % (i, j, k), "-s", "Q", "--csv", "-t", str(t),
                           self.path).splitlines()[1].split(",")[-1])
            self.assertEqual(np.float32(q), self.f.read("Q", t)[k, j, i])

    def test_read_matches_vsv_info_stats(self):
        stats = json.loads(tool("vsv-info", "--stats", "--json", self.path))["stats"]
        for row in stats:
            a = self.f.read(row["species"], time=row["time"])
            fin = a[np.isfinite(a)]
            self.assertEqual(float(np.float32(row["min"])), float(fin.min()), row)
            self.assertEqual(float(np.float32(row["max"])), float(fin.max()), row)


class Reporter(unittest.TextTestResult):
    def addSuccess(self, test):
        super().addSuccess(test)
        print("PASS python %s" % test.id().split(".", 1)[1], flush=True)

    def addFailure(self, test, err):
        super().addFailure(test, err)
        print("FAIL python %s: %s" % (test.id().split(".", 1)[1], str(err[1]).splitlines()[0][:300]), flush=True)

    def addError(self, test, err):
        super().addError(test, err)
        print("FAIL python %s: %s: %s" % (test.id().split(".", 1)[1], err[0].__name__, str(err[1])[:300]), flush=True)

    def addSkip(self, test, reason):
        super().addSkip(test, reason)
        # data absent: a SKIP line, counted; a missing Python package: a note
        if reason.endswith(" absent"):
            print("SKIP python %s: %s" % (test.id().split(".", 1)[1], reason), flush=True)
        else:
            print("  (skipped: %s: %s)" % (test.id().split(".", 1)[1], reason), flush=True)


if __name__ == "__main__":
    r = unittest.TextTestRunner(stream=sys.stderr, resultclass=Reporter, verbosity=0).run(
        unittest.defaultTestLoader.loadTestsFromModule(sys.modules[__name__]))
    sys.exit(0 if r.wasSuccessful() else 1)
