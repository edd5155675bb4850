#!/usr/bin/python3
"""cf_check.py FILE.nc -- the CF rules a Vesuvius export must keep, written
out and checked one by one (a plain CF checker is not packaged in Debian;
the units are checked by UDUNITS itself, Debian's udunits-bin).

Rules (CF-1.8 sections in brackets):
 1. The global Conventions is "CF-1.8" [2.6.1].
 2. Every units attribute is one UDUNITS knows [3.1]; "ppmV" and the like
    are not.
 3. A variable with a standard_name has units that convert to the name's
    canonical units [3.3]: mole and mass fractions and mixing ratios 1,
    altitude and height m, air_temperature and air_potential_temperature K,
    winds and wind_speed m s-1, relative_humidity 1 (% converts), latitude
    degrees_north, longitude degrees_east, projected x/y m, time a
    "seconds since" reference.
 4. The vertical coordinate z: standard_name altitude (above sea level) or
    height (above the ground) with units of length and positive "up", or a
    pressure with positive "down", or model_level_number [4.3]; a file
    whose heights are above the ground (vsv_attr_vertical_datum "ground")
    says height, every other says altitude; a per-column height variable
    has the same standard_name as z.
 5. Every name in a coordinates attribute is a variable of the file whose
    dimensions are among the variable's, and a grid_mapping names a
    variable with grid_mapping_name [5, 5.6].
 6. _FillValue has its variable's type [2.5.1].
Prints "PASS rule ..." / "FAIL rule ...: why" lines; exits 1 on a failure.
"""
import subprocess
import sys

import netCDF4
import numpy as np

CANON = {
    "altitude": "m", "height": "m", "surface_altitude": "m", "air_temperature": "K",
    "x_wind": "m s-1", "y_wind": "m s-1", "upward_air_velocity": "m s-1",
    "eastward_wind": "m s-1", "northward_wind": "m s-1",
    "latitude": "degrees_north", "longitude": "degrees_east",
    "projection_x_coordinate": "m", "projection_y_coordinate": "m",
    "air_pressure": "Pa", "model_level_number": "1",
    "air_potential_temperature": "K", "wind_speed": "m s-1", "relative_humidity": "1",
}


def canonical(name):
    if name in CANON:
        return CANON[name]
    if name.startswith(("mole_fraction_of_", "mass_fraction_of_")) or name.endswith("_mixing_ratio"):
        return "1"
    return None


def udunits(have, want):
    """None when have converts to want (or parses, want None); else why."""
    r = subprocess.run(["udunits2", "-H", have, "-W", want or have], input="\n\n", capture_output=True, text=True)
    out = (r.stdout + r.stderr).strip()
    if "Don't recognize" in out or "not convertible" in out or "udunits2:" in out:
        return out.replace("udunits2: ", "")
    return None


def main(path):
    nc = netCDF4.Dataset(path)
    fails = []

    def check(rule, ok, why=""):
        print(("PASS" if ok else "FAIL") + " rule %s%s" % (rule, "" if ok else ": " + why))
        if not ok:
            fails.append(rule)

    check("1 Conventions CF-1.8", getattr(nc, "Conventions", "") == "CF-1.8", getattr(nc, "Conventions", "(none)"))
    for name, v in nc.variables.items():
        attrs = v.ncattrs()
        if "units" in attrs:
            u = v.units
            if " since " in u:
                why = udunits(u.split(" since ")[0], "s")
            else:
                why = udunits(u, None)
            check("2 %s units '%s' known to UDUNITS" % (name, u), why is None, why or "")
        if "standard_name" in attrs:
            want = canonical(v.standard_name)
            if v.standard_name == "time":
                ok = " since " in getattr(v, "units", "")
                check("3 %s: time in 'seconds since'" % name, ok, getattr(v, "units", "(none)"))
            else:
                check("3 %s: standard_name %s has a canonical unit here" % (name, v.standard_name), want is not None,
                      "not in the test's table")
                if want is not None:
                    why = udunits(getattr(v, "units", "1"), want)
                    check("3 %s: units %s convert to %s" % (name, getattr(v, "units", "(none)"), want), why is None,
                          why or "")
        if "coordinates" in attrs:
            missing = [c for c in v.coordinates.split() if c not in nc.variables]
            check("5 %s: coordinates exist" % name, not missing, " ".join(missing))
            wider = [c for c in v.coordinates.split()
                     if c in nc.variables and not set(nc.variables[c].dimensions) <= set(v.dimensions)]
            check("5 %s: each coordinate's dimensions are the variable's" % name, not wider,
                  " ".join("%s%s" % (c, nc.variables[c].dimensions) for c in wider))
        if "grid_mapping" in attrs:
            gm = nc.variables.get(v.grid_mapping)
            check("5 %s: grid_mapping %s" % (name, v.grid_mapping),
                  gm is not None and "grid_mapping_name" in gm.ncattrs(), "no such variable or no grid_mapping_name")
        if "_FillValue" in attrs:
            check("6 %s: _FillValue of the variable's type" % name,
                  np.asarray(v._FillValue).dtype == v.dtype, "%s vs %s" % (np.asarray(v._FillValue).dtype, v.dtype))
    z = nc.variables.get("z")
    if z is not None:
        sn = getattr(z, "standard_name", "")
        pos = getattr(z, "positive", "")
        ground = getattr(nc, "vsv_attr_vertical_datum", "") == "ground"
        if sn in ("altitude", "height"):
            check("4 z: %s with positive up" % sn, pos == "up", "positive '%s'" % pos)
            want = "height" if ground else "altitude"
            check("4 z: heights %s are %s" % ("above the ground" if ground else "above sea level", want), sn == want,
                  "standard_name %s" % sn)
            h = nc.variables.get("height")
            if h is not None and len(h.dimensions) == 4:
                check("4 per-column heights: standard_name %s like z" % sn, getattr(h, "standard_name", "") == sn,
                      getattr(h, "standard_name", "(none)"))
        elif sn == "air_pressure":
            check("4 z: pressure with positive down", pos == "down", "positive '%s'" % pos)
        else:
            check("4 z: a level number", sn == "model_level_number", "standard_name '%s'" % sn)
    nc.close()
    return 1 if fails else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1]))
