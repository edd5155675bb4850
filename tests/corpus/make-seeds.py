#!/usr/bin/python3
"""make-seeds.py — writes the fuzz seed inputs of tests/corpus/ that are
crops of the real model output in ../shared/data (netCDF, GrADS) or files
the project writes (IOAPI). Run from the top of the tree:
    /usr/bin/python3 tests/corpus/make-seeds.py [SHARED]
Each seed stays under 100 KB. The .vsv and field-stream seeds are written by
the project's tools (tests/corpus/README.md says how)."""
import os
import sys

import numpy as np
import netCDF4

SHARED = sys.argv[1] if len(sys.argv) > 1 else "../shared"
D = SHARED + "/data"
OUT = "tests/corpus"

# dimension name -> size kept
WRF_CROP = {"Time": 2, "west_east": 6, "south_north": 6, "west_east_stag": 7, "south_north_stag": 7,
            "bottom_top": 5, "bottom_top_stag": 6, "soil_layers_stag": 2}


def crop_nc(src, dst, crop, keep=None, attrs=None, var_attrs=None):
    """A netCDF classic (64-bit offset) copy of src with each dimension cut to
    crop[name] (the leading part), only the variables in keep (all if None)."""
    with netCDF4.Dataset(src) as a, netCDF4.Dataset(dst, "w", format="NETCDF3_64BIT_OFFSET") as b:
        for n, d in a.dimensions.items():
            size = len(d)
            if n in crop:
                size = min(size, crop[n])
            b.createDimension(n, None if d.isunlimited() else size)
        for k in a.ncattrs():
            v = a.getncattr(k)
            if attrs and k in attrs:
                v = attrs[k]
            b.setncattr(k, v)
        for k, v in (attrs or {}).items():
            b.setncattr(k, v)
        for n, v in a.variables.items():
            if keep is not None and n not in keep:
                continue
            if v.dtype == str or v.dtype.kind in "OU" or v.dtype == np.int64 or v.dtype == np.uint64:
                continue
            fill = v.getncattr("_FillValue") if "_FillValue" in v.ncattrs() else None
            w = b.createVariable(n, v.dtype, v.dimensions, fill_value=fill)
            for k in v.ncattrs():
                if k != "_FillValue":
                    w.setncattr(k, v.getncattr(k))
            for k, x in (var_attrs or {}).get(n, {}).items():
                w.setncattr(k, x)
            idx = tuple(slice(0, min(len(a.dimensions[d]), crop.get(d, len(a.dimensions[d])))) for d in v.dimensions)
            w[idx] = v[idx]
    print(dst, os.path.getsize(dst), "bytes")


def wrf_attrs(nx, ny, nz):
    return {"WEST-EAST_GRID_DIMENSION": np.int32(nx + 1), "SOUTH-NORTH_GRID_DIMENSION": np.int32(ny + 1),
            "BOTTOM-TOP_GRID_DIMENSION": np.int32(nz + 1)}


def ioapi(dst, camx, gdtyp=2, nt=2, nx=6, ny=5, nz=3):
    """An IOAPI file as CMAQ (camx=False) or CAMx 7 (z, topo) writes it, laid
    out as in INPUT-FORMATS.md and tests/test_ioapi.c."""
    with netCDF4.Dataset(dst, "w", format="NETCDF3_CLASSIC") as f:
        f.createDimension("TSTEP", None)
        f.createDimension("DATE-TIME", 2)
        f.createDimension("LAY", nz)
        f.createDimension("VAR", 2)
        f.createDimension("ROW", ny)
        f.createDimension("COL", nx)
        tf = f.createVariable("TFLAG", "i4", ("TSTEP", "VAR", "DATE-TIME"))
        names = ["O3", "PM25"]
        units = ["ppmV            ", "micrograms/m**3 "]
        vs = []
        for i, n in enumerate(names):
            v = f.createVariable(n, "f4", ("TSTEP", "LAY", "ROW", "COL"))
            v.units = units[i]
            v.var_desc = ["ozone", "fine PM"][i].ljust(10)
            vs.append(v)
        if camx:
            z = f.createVariable("z", "f4", ("TSTEP", "LAY", "ROW", "COL"))
            topo = f.createVariable("topo", "f4", ("ROW", "COL"))
            f.CAMx_NAME = "AVERAGE"
        for k, v in [("NCOLS", nx), ("NROWS", ny), ("NLAYS", nz), ("GDTYP", gdtyp), ("SDATE", 2016182),
                     ("STIME", 0), ("TSTEP", 10000), ("VGTYP", 7)]:
            f.setncattr(k, np.int32(v))
        for k, v in [("P_ALP", 30.0), ("P_BET", 60.0), ("P_GAM", -90.0), ("XCENT", -90.0), ("YCENT", 40.0),
                     ("XORIG", -36000.0), ("YORIG", -30000.0), ("XCELL", 12000.0), ("YCELL", 12000.0)]:
            f.setncattr(k, np.float64(v))
        f.VGTOP = np.float32(5000)
        f.VGLVLS = np.array([1.0, 0.995, 0.985, 0.96][: nz + 1], dtype="f4")
        f.FILEDESC = "Vesuvius fuzz seed"
        for t in range(nt):
            tf[t] = [[2016182, t * 10000]] * 2
            for i, v in enumerate(vs):
                v[t] = (np.arange(nz * ny * nx, dtype="f4").reshape(nz, ny, nx) * 0.001 + (i + 1) * 0.01 + t * 0.5)
            if camx:
                z[t] = np.repeat(np.array([40.0 * (k + 1) ** 2 + t for k in range(nz)], dtype="f4"),
                                 nx * ny).reshape(nz, ny, nx)
        if camx:
            topo[:] = (100 + np.arange(nx * ny) % nx).reshape(ny, nx)
    print(dst, os.path.getsize(dst), "bytes")


def grads():
    """model.ctl cut to 8 x 6 cells, 3 levels, 2 days, its data cut alike,
    as one input: the .ctl text, a NUL, the binary (fuzz_grads.c)."""
    nx, ny, nz, nt = 72, 46, 7, 5
    levs = [("PS", 0), ("U", 7), ("V", 7), ("Z", 7), ("T", 7), ("Q", 5), ("TS", 0), ("P", 0)]
    per_t = sum(max(l, 1) for _, l in levs) * nx * ny
    a = np.fromfile(D + "/grads/model.dat", dtype="<f4")
    assert a.size == per_t * nt, a.size
    cx, cy, cz, ct = 8, 6, 3, 2
    out = []
    for t in range(ct):
        at = t * per_t
        for _, l in levs:
            for k in range(max(l, 1)):
                plane = a[at: at + nx * ny].reshape(ny, nx)
                at += nx * ny
                if k < cz:
                    out.append(plane[20: 20 + cy, 30: 30 + cx])
    ctl = open(D + "/grads/model.ctl").read()
    ctl = ctl.replace("XDEF 72 LINEAR  0.0 5.0", "XDEF %d LINEAR  150.0 5.0" % cx)
    ctl = ctl.replace("YDEF 46 LINEAR  -90.0 4.0", "YDEF %d LINEAR  -10.0 4.0" % cy)
    ctl = ctl.replace("ZDEF 7 LEVELS 1000 850 700 500 300 200 100", "ZDEF %d LEVELS 1000 850 700" % cz)
    ctl = ctl.replace("TDEF 5 LINEAR", "TDEF %d LINEAR" % ct)
    for n, l in levs:
        if l:
            ctl = ctl.replace("%-6s %d " % (n, l), "%-6s %d " % (n, min(l, cz)))
    dst = OUT + "/grads/model-crop"
    with open(dst, "wb") as f:
        f.write(ctl.encode() + b"\0" + np.concatenate([p.ravel() for p in out]).astype("<f4").tobytes())
    print(dst, os.path.getsize(dst), "bytes")


def main():
    os.makedirs(OUT + "/netcdf", exist_ok=True)
    os.makedirs(OUT + "/grads", exist_ok=True)
    crop_nc(D + "/wrf/wrf_cropped.nc", OUT + "/netcdf/wrf-crop.nc", WRF_CROP, attrs=wrf_attrs(6, 6, 5))
    crop_nc(D + "/wrf/katrina_ci_test_file.nc", OUT + "/netcdf/katrina-crop.nc", WRF_CROP,
            keep={"Times", "XLAT", "XLONG", "U", "V", "W", "PH", "PHB", "T", "P", "PB", "QVAPOR", "QCLOUD", "HGT",
                  "ZNU", "ZNW", "XLAT_U", "XLONG_U", "XLAT_V", "XLONG_V", "MAPFAC_M"}, attrs=wrf_attrs(6, 6, 5))
    crop_nc(D + "/wrf/wrf_d01_allvars_cropped.nc", OUT + "/netcdf/wrf-allvars-crop.nc", dict(WRF_CROP, Time=1),
            keep={"Times", "XLAT", "XLONG", "PH", "PHB", "T", "P", "PB", "QVAPOR", "QCLOUD", "QRAIN", "QICE", "QSNOW",
                  "QGRAUP", "HGT", "U", "V", "W"}, attrs=wrf_attrs(6, 6, 5))
    crop_nc(D + "/ncl/contour.cdf", OUT + "/netcdf/contour-crop.nc", {"frtime": 2, "level": 4, "lat": 8, "lon": 8},
            attrs={"Conventions": "CF-1.6"}, var_attrs={"frtime": {"units": "hours since 1990-01-01 00:00:00"}})
    ioapi(OUT + "/netcdf/ioapi-cmaq.nc", False)
    ioapi(OUT + "/netcdf/ioapi-camx.nc", True)
    ioapi(OUT + "/netcdf/ioapi-latlon.nc", False, gdtyp=1)
    grads()


main()
