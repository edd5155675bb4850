"""vesuvius — read and write Vesuvius .vsv volume files from Python.

    import vesuvius
    f = vesuvius.open("storm.vsv")
    f.times                      # numpy datetime64[s], one per step
    f.species                    # [Species(name, units, description, max_abs_error, ...)]
    clw = f.read("CLW", time=3)  # float32 (nz, ny, nx), decoded straight into the array
    uvw = f.read("wind", time=3) # a vector: float32 (3, nz, ny, nx), east, north, up (m/s)
    f.query(41.88, -87.63)       # the values at a point, every step
    f.trajectory(41.88, -87.63, 1500, 0, 3)   # the air's path through the stored wind
    ds = f.to_xarray()           # an xarray.Dataset (when xarray is installed)
    vesuvius.write("x.vsv", grid=..., projection=..., times=..., fields={...})

A thin layer over the C library (libvesuvius): the same decoder, the same
point location and sampling as the vsv-* tools. Errors are vesuvius.Error
carrying the library's message.
"""
import os
from collections import namedtuple

import numpy as np

from . import _vesuvius
from ._vesuvius import Error

__all__ = ["open", "write", "Error", "File", "Species", "Point", "version"]
version = _vesuvius.version

Species = namedtuple("Species", "name units description max_abs_error data_min data_max threshold bits scale empty")
Species.__doc__ = """One species: its name and units, the quantisation's bound on |decoded - model value|
(max_abs_error), the finite range the writer saw (data_min, data_max: None when it saw no
finite value), bits (8/16), scale (linear/log) and what
an empty cell decodes to ("zero", or "nan" for no data)."""
Point = namedtuple("Point", "cell lat lon height position times values")
Point.__doc__ = """A point query: the nearest cell (i, j, k) and its centre's lat/lon/height, the
point's fractional cell position (i, j, k), the times, and {species: float32 array over times}."""

_VERT = {"even": 0, "native": 1, "index": 2, "coord": 3}


class File:
    """An open .vsv file (memory-mapped; opening reads only the header and index), or one
    on a web server: an http:// or https:// URL, read by range requests, the parts read
    kept in cache_dir (default $VSV_CACHE_DIR, else ~/.cache/vesuvius; "off": none)."""

    def __init__(self, path, cache_dir=None):
        self.path = path
        self._f = _vesuvius.open(path, cache_dir)

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

    def __repr__(self):
        g = self.grid
        return "<vesuvius.File %r: %d x %d x %d, %d steps, species %s>" % (
            self.path, g["nx"], g["ny"], g["nz"], len(self.times), ",".join(s.name for s in self.species))

    def close(self):
        """Releases the mapping; further calls raise vesuvius.Error."""
        self._f.close()

    @property
    def times(self):
        """The time of each step: numpy datetime64[s] (UTC); in a file of another
        calendar (grid["calendar"]: noleap, all_leap, 360_day), cftime dates of it."""
        cal = self._f.grid["calendar"]
        if cal == "standard":
            return self._f._times.astype("datetime64[s]")
        import cftime
        return np.asarray(cftime.num2date(self._f._times, "seconds since 1970-01-01 00:00:00", calendar=cal))

    @property
    def species(self):
        """The species, in file order: a list of Species."""
        return [Species(*t) for t in self._f._species]

    @property
    def names(self):
        return [s.name for s in self.species]

    grid = property(lambda self: self._f.grid,
                    doc="nx, ny, nz, origin, spacing (projected units, metres); vertical (even, native, index, "
                        "coord), vert_units (m for heights, the coordinate's unit, '' for an index), datum "
                        "('sea level' or 'ground': what heights count from), levels, column_heights (native "
                        "levels with per-column heights), model, run, brick, nbricks, moves (a moving nest's "
                        "later placements: (time, x, y of column (0, 0)) each; origin is its first)")
    projection = property(lambda self: self._f.projection, doc="kind (lcc, pstereo, ...) and parameters (degrees, metres)")
    lat = property(lambda self: self._f.lat,
                   doc="latitude of every column's centre, float64 (ny, nx) (a moving nest: at its first place)")
    lon = property(lambda self: self._f.lon,
                   doc="longitude of every column's centre, float64 (ny, nx) (a moving nest: at its first place)")
    height = property(lambda self: self._f.height,
                      doc="height of every level's centre, float64 (nz,) (native levels: the mean; see heights())")
    terrain = property(lambda self: self._f.terrain, doc="terrain height, float32 (ny, nx), or None")
    attrs = property(lambda self: self._f.attrs, doc="run metadata (key: value)")

    def _step(self, time):
        if isinstance(time, (np.datetime64,)):
            time = str(time.astype("datetime64[s]")) + "Z"
        elif hasattr(time, "strftime"):  # datetime.datetime, or a cftime date
            if getattr(time, "tzinfo", None) is not None and time.utcoffset() is not None:
                time = (time - time.utcoffset()).replace(tzinfo=None)  # an aware datetime: its UTC time
            time = time.strftime("%Y-%m-%dT%H:%M:%SZ")
        elif isinstance(time, (np.integer,)):
            time = int(time)
        return time

    @property
    def vectors(self):
        """The vectors (vsv(5) "Vectors"; the wind, "wind"): {name: (east, north, up)
        species names, up None for a horizontal vector}."""
        names, out = set(self.names), {}
        for k, v in self.attrs.items():
            c = v.split()
            if k.startswith("vector:") and len(c) in (2, 3) and all(n in names for n in c):
                out[k[len("vector:"):]] = tuple(c) + ((None,) if len(c) == 2 else ())
        return out

    def read(self, species, time=0):
        """The decoded volume of species (name or index) at time (a step index, an
        ISO time string, a numpy datetime64 or a datetime: the nearest step):
        float32 (nz, ny, nx), decoded straight into the array; NaN where there is no
        data, among them every cell below the ground (even heights over a terrain).
        A vector's name ("wind") instead reads its components: float32
        (3, nz, ny, nx), eastward, northward and upward (earth-relative; the wind in
        m/s), or (2, nz, ny, nx) for a horizontal vector (a model without W)."""
        if isinstance(species, str) and species not in self.names:
            vec = self.vectors.get(species)
            if vec:
                t = self._step(time)
                return np.stack([self._f.read(c, t) for c in vec if c is not None])
        return self._f.read(species, self._step(time))

    def read_brick(self, species, time, brick):
        """One brick: (float32 (ez, ey, ex) of the cells inside the grid, (k0, j0, i0)
        of its first cell). Bricks are numbered x fastest; grid["nbricks"] of them."""
        a, org, ext = self._f._read_brick(species, self._step(time), brick)
        return a[: ext[0], : ext[1], : ext[2]], org

    def bricks(self, species, time):
        """Streams the non-empty bricks of (species, time): yields ((k0, j0, i0), array)
        without ever holding the whole volume."""
        t = self._step(time)
        for b in range(self.grid["nbricks"]):
            if self._f.brick_empty(species, t, b):  # every cell code 0, whatever the brick's kind
                continue
            a, org = self.read_brick(species, t, b)
            yield org, a

    def heights(self, time=0):
        """Every cell's height at a step, float64 (nz, ny, nx): the file's per-column
        heights of native levels where it has them (they move in time), else each
        level's height (f.height) in every column."""
        return self._f.heights(self._step(time))

    def query(self, lat=None, lon=None, height=None, cell=None, interp=False):
        """The values of every species at a point, every step: lat/lon (degrees) and an
        optional height (metres; None = the lowest level above the ground), or
        cell=(i, j[, k]). interp=True blends the eight cells around the point
        trilinearly (cells without data left out, the others' weights scaled to one;
        NaN where the nearest cell has none); the default is the nearest cell's
        decoded value. Returns a Point
        (its cell, lat, lon and height those of the first step; on native levels with
        per-column heights a height's level is found again at every step)."""
        if cell is not None:
            c, la, lo, h, vals, pos = self._f._query(cell=tuple(cell), interp=interp)
        else:
            if lat is None or lon is None:
                raise TypeError("query: lat and lon, or cell=(i, j[, k])")
            lat, lon = float(lat), float(lon)
            # vsv-query's limits, in its words
            if not -90 <= lat <= 90:
                raise ValueError("query: latitude %r: a number within -90..90" % lat)
            if not -360 <= lon <= 360:
                raise ValueError("query: longitude %r: a number within -360..360" % lon)
            if height is not None and not np.isfinite(float(height)):
                raise ValueError("query: height %r: a finite number of metres (None: the lowest level above "
                                 "the ground)" % height)
            c, la, lo, h, vals, pos = self._f._query(lat, lon, height, interp=interp)
        return Point(c, la, lo, h, pos, self.times, vals)

    def trajectory(self, lat, lon, height, start, end, every=None):
        """The path of the air at lat, lon (degrees) and height (as the file's heights)
        at time start through the stored wind (vector species "wind") until end
        (earlier: backward in time); start and end are step indices, ISO times (between
        steps too), numpy datetime64 or datetimes. every: a point every so many seconds
        of model time (a number or a numpy timedelta64; None: every step of the scheme)
        and at the end. The scheme and its step rule are vsv-query(1)'s (RK4, Courant
        0.5). Returns a dict of arrays, the seed first: time (datetime64[ms]; in a file
        of another calendar, cftime dates), seconds (since 1970 in the file's calendar),
        lat, lon, height, x, y (projected), east, north, up (float32, m/s; up NaN for a
        horizontal wind), and "end":
        why it stopped ("time", "edge", "ground", "top", "data")."""
        if isinstance(every, np.timedelta64):
            every = every / np.timedelta64(1, "s")
        r = self._f._trajectory(float(lat), float(lon), float(height), self._step(start), self._step(end),
                                float(every or 0))
        if isinstance(r, str):
            raise Error(r)
        cols, end_ = r
        out = {k: np.asarray(v, dtype=np.float32 if k in ("east", "north", "up") else np.float64)
               for k, v in cols.items()}
        if self.vectors.get("wind", (None, None, None))[2] is None:
            out["up"][:] = np.nan  # a horizontal wind has no vertical component (0 would claim a calm)
        cal = self._f.grid["calendar"]
        if cal == "standard":
            out["time"] = np.round(out["seconds"] * 1000).astype(np.int64).astype("datetime64[ms]")
        else:
            import cftime
            out["time"] = np.asarray(cftime.num2date(out["seconds"], "seconds since 1970-01-01 00:00:00",
                                                     calendar=cal))
        out["end"] = end_
        return out

    def to_xarray(self, species=None):
        """An xarray.Dataset of every (or the named) species over (time, z, y, x), as
        `vsv-export --netcdf` writes it and xarray.open_dataset reads that file: x/y in
        projected metres (degrees on lat/lon grids), z the levels' heights (CF altitude
        above sea level, or height above the ground where the file's heights count
        from it) or their coordinate, 2-D lat/lon, terrain (surface_altitude), the
        per-column heights of native levels at every step (height), and per species
        its units as UDUNITS spells them, its CF standard_name where it has one and
        vsv_max_abs_error (also max_abs_error). The grid mapping itself is not built
        here (vsv-export writes it as crs); the projection is in attrs. Needs xarray
        (Debian: python3-xarray). Reads every step into memory."""
        try:
            import xarray as xr
        except ImportError as e:
            raise ImportError("to_xarray needs xarray (apt-get install python3-xarray)") from e
        g = self.grid
        if g["moves"]:
            raise Error("the grid moves (a moving nest, grid['moves']): a Dataset holds one placement; "
                        "read() the steps of each placement apart")
        if isinstance(species, str):
            species = [species]
        names = self.names if species is None else list(species)
        if not names:
            raise ValueError("to_xarray: no species named (None: every species)")
        sp = {s.name: s for s in self.species}
        for n in names:
            if n not in sp:
                raise KeyError("to_xarray: no species %r (the file has %s)" % (n, ", ".join(self.names)))
        nt = len(self.times)
        data = {}
        for n in names:
            a = np.empty((nt, g["nz"], g["ny"], g["nx"]), np.float32)
            for t in range(nt):
                a[t] = self.read(n, t)
            s = sp[n]
            units, standard_name, comment = _vesuvius._cf(g["model"], n, s.units)
            attrs = {"long_name": s.description or s.name, "units": units, "vsv_max_abs_error": s.max_abs_error,
                     "max_abs_error": s.max_abs_error}
            if standard_name:
                attrs["standard_name"] = standard_name
            if comment:
                attrs["comment"] = comment
            if units != s.units:
                attrs["vsv_units_original"] = s.units
            data[n] = (("time", "z", "y", "x"), a, attrs)
        latlon = self.projection["kind"] == "latlon"
        x = g["origin"][0] + g["spacing"][0] * np.arange(g["nx"])
        y = g["origin"][1] + g["spacing"][1] * np.arange(g["ny"])
        if latlon:
            xa = {"standard_name": "longitude", "units": "degrees_east", "axis": "X"}
            ya = {"standard_name": "latitude", "units": "degrees_north", "axis": "Y"}
        else:
            xa = {"standard_name": "projection_x_coordinate", "units": "m", "axis": "X"}
            ya = {"standard_name": "projection_y_coordinate", "units": "m", "axis": "Y"}
        ground = g["datum"] == "ground"
        if g["vertical"] in ("even", "native"):
            za = {"standard_name": "height" if ground else "altitude", "units": "m", "positive": "up", "axis": "Z",
                  "long_name": "%sheight above %s%s" % ("mean " if g["vertical"] == "native" else "",
                                                       "the ground" if ground else "sea level",
                                                       " of the model level" if g["vertical"] == "native" else "")}
        elif g["vertical"] == "coord":
            za = {"units": g["vert_units"], "long_name": "model level coordinate", "axis": "Z"}
            if g["vert_units"] in ("hPa", "Pa"):
                za.update(standard_name="air_pressure", positive="down")
        else:
            za = {"standard_name": "model_level_number", "units": "1", "positive": "up", "axis": "Z"}
        times = self.times
        coords = {"time": ("time", times.astype("datetime64[ns]") if times.dtype.kind == "M" else times,
                           {"standard_name": "time", "long_name": "time", "axis": "T"}), "x": ("x", x, xa), "y": ("y", y, ya),
                  "z": ("z", self.height, za)}
        if not latlon and self.projection["kind"] != "none":
            coords["lat"] = (("y", "x"), self.lat, {"standard_name": "latitude", "units": "degrees_north"})
            coords["lon"] = (("y", "x"), self.lon, {"standard_name": "longitude", "units": "degrees_east"})
        if g["vertical"] == "native" and g["column_heights"]:
            h = np.stack([self.heights(t).astype(np.float32) for t in range(nt)])
            coords["height"] = (("time", "z", "y", "x"), h,
                                {"standard_name": za["standard_name"], "units": "m", "positive": "up"})
        if self.terrain is not None:
            data["terrain"] = (("y", "x"), self.terrain,
                               {"standard_name": "surface_altitude", "long_name": "terrain height", "units": "m"})
        attrs = {"Conventions": "CF-1.8", "source": "vesuvius", "model": g["model"], "run": g["run"],
                 "projection": self.projection["kind"]}
        return xr.Dataset(data, coords=coords, attrs=attrs)


def open(path, cache_dir=None):
    """Opens a .vsv file or http(s):// URL: a File (use `with vesuvius.open(p) as f:` to close it)."""
    return File(path, cache_dir)


def write(path, grid, times, fields, projection=None, units=None, descriptions=None, terrain=None,
          levels=None, heights=None, bits=16, scale="linear"):
    """Writes a .vsv with the library's writer (quantised, bricked, compressed; the file
    appears only when complete).

    grid: {"nx", "ny", "nz", "origin": (x0, y0, z0), "spacing": (dx, dy, dz),
           "vertical": "even" (default) | "native" | "index"} — or a File's grid
    projection: {"kind": "lcc"|"pstereo"|"mercator"|"tmerc"|"albers"|"latlon"|"none",
                 "lat0", "lon0", "lat1", "lat2", "radius"} (default: none)
    times: datetime64 values, ISO strings or integer seconds since 1970, increasing
    fields: {name: array (ntimes, nz, ny, nx)}, non-finite = no data
    units, descriptions: {name: text}; terrain: (ny, nx) metres (on even heights, cells
    whose centre lies below it hold no data: they read back NaN, whatever was written);
    levels: (nz,) heights for vertical="native"; heights: (ntimes, nz, ny, nx) every
    cell's height at each step, for native levels that vary by column (as File.heights(t)
    gives them: a File's grid with column_heights needs them, or its levels would stand
    at their mean height in every column); bits 8 or 16; scale "linear" or "log".
    """
    if not fields:
        raise Error("write: no fields")
    t = np.asarray(times)
    if t.dtype.kind in "UO":
        t = np.array([np.datetime64(str(s).rstrip("Z"), "s") for s in t])
    if t.dtype.kind == "M":
        t = t.astype("datetime64[s]").astype(np.int64)
    t = np.ascontiguousarray(t, dtype=np.int64)
    vk = _VERT.get(grid.get("vertical", "even"))
    if vk is None:
        raise Error("write: vertical must be even, native or index")
    g = (int(grid["nx"]), int(grid["ny"]), int(grid["nz"]), tuple(float(v) for v in grid["origin"]),
         tuple(float(v) for v in grid["spacing"]), vk)
    p = projection or {"kind": "none"}
    kind = _vesuvius._proj_kind(p.get("kind", "none"))
    if kind < 0:
        raise Error("unknown projection '%s' (none, latlon, lcc, pstereo, mercator, tmerc, albers)" % p.get("kind"))
    pj = (kind, float(p.get("lat0", 0)), float(p.get("lon0", 0)),
          float(p.get("lat1", 0)), float(p.get("lat2", p.get("lat1", 0))), float(p.get("radius", 0)))
    if levels is None and vk in (1, 3):
        levels = grid.get("levels")
    hts = []
    if heights is not None:
        h = np.asarray(heights, dtype=np.float32)
        if vk != 1 or h.shape != (len(t), g[2], g[1], g[0]):
            raise Error("write: heights: (%d, %d, %d, %d) (times, nz, ny, nx), with vertical native"
                        % (len(t), g[2], g[1], g[0]))
        for i in range(len(t)):  # a record where they change (valid from its time on)
            if i == 0 or not np.array_equal(h[i], h[i - 1]):
                hts.append((int(t[i]), np.ascontiguousarray(h[i]).tobytes()))
    elif grid.get("column_heights"):
        raise Error("write: the grid has per-column heights (grid['column_heights']): give heights= "
                    "(np.stack([f.heights(t) for t in range(len(f.times))])), or a grid without them")
    names = list(fields)
    arrays = [np.ascontiguousarray(fields[n], dtype=np.float32) for n in names]
    arrays = [a[np.newaxis] if a.ndim == 3 and len(t) == 1 else a for a in arrays]
    units = units or {}
    descriptions = descriptions or {}
    if scale not in ("linear", "log"):
        raise Error("write: scale must be linear or log")
    where = os.fsdecode(path)
    for i in range(1, len(t)):
        if t[i] <= t[i - 1]:
            iso = [str(np.datetime64(int(v), "s")) + "Z" for v in (t[i - 1], t[i])]
            raise Error("write: %s: times: step %d (%s) does not come after step %d (%s)"
                        % (where, i, iso[1], i - 1, iso[0]))
    try:
        _vesuvius._write(path, g, pj, t, names, [units.get(n, "") for n in names],
                         [descriptions.get(n, "") for n in names], arrays, terrain, levels, hts, int(bits),
                         1 if scale == "log" else 0)
    except Error as e:  # the writer's words, with the file they are about
        if str(e).startswith(where):
            raise
        raise Error("write: %s: %s" % (where, e)) from None
