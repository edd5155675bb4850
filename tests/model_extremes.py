#!/usr/bin/env python3
"""model_extremes.py — the smallest and largest value of each 3-D field of a
model file, read independently of Vesuvius (from ../shared/docs/
INPUT-FORMATS.md alone): MM5 v3 (big-endian Fortran records; cross-point
fields on the IX-1 x JX-1 cross points) or WRF (netCDF, via python3-netcdf4).
   model_extremes.py FILE NAME...   prints "NAME MIN MAX" per field."""
import struct
import sys

import numpy

from mm5_records import mm5_records


def mm5(path, names):
    lo, hi = {}, {}
    for rec in mm5_records(path):
        if rec[0] == 1:
            sub, field = rec[1], rec[2]
            ndim = struct.unpack('>i', sub[0:4])[0]
            end = struct.unpack('>4i', sub[20:36])
            stagger = sub[40:44].decode().strip()
            name = sub[72:81].decode().strip()
            if ndim != 3 or name not in names:
                continue
            ix, jx, kx = end[0], end[1], end[2]
            a = numpy.frombuffer(field, '>f4').reshape(kx, jx, ix)
            if stagger == 'C':            # cross points: the last row and column are not
                a = a[:, :-1, :-1]
            lo[name] = min(lo.get(name, numpy.inf), float(a.min()))
            hi[name] = max(hi.get(name, -numpy.inf), float(a.max()))
    return lo, hi


def wrf(path, names):
    import netCDF4
    d = netCDF4.Dataset(path)
    lo, hi = {}, {}
    for n in names:
        a = numpy.asarray(d[n][:], numpy.float32)
        lo[n], hi[n] = float(a.min()), float(a.max())
    return lo, hi


def main():
    path, names = sys.argv[1], sys.argv[2:]
    head = open(path, 'rb').read(4)
    lo, hi = wrf(path, names) if head[:3] in (b'CDF', b'\x89HD') else mm5(path, names)
    for n in names:
        if n not in lo:
            sys.exit('model_extremes.py: %s: no 3-D field %s' % (path, n))
        print(n, repr(lo[n]), repr(hi[n]))


if __name__ == '__main__':
    main()
