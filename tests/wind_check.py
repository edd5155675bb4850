#!/usr/bin/env python3
"""wind_check.py — the wind vsv-convert stores (wind_east, wind_north,
wind_up) against the model's own, computed here independently of Vesuvius:
an MM5 v3 file read from ../shared/docs/INPUT-FORMATS.md alone (U and V on
dot points averaged from the four corners of each cross point, W on full
sigma levels averaged to the half levels, rotated by the Lambert cone: the
angle cone * (LONGICRS - lon0) with the cone factor bhr(4,1) of the big
header), or a WRF wrfout through python3-netcdf4 (U, V, W the mean of the
two faces around a mass point, rotated by the Lambert cone of TRUELAT1/2
from STAND_LON at each XLONG, which must agree with the file's own SINALPHA
within 1e-4 (geogrid's finite differences), or not at all on a Mercator
grid, MAP_PROJ 3).
   wind_check.py MMOUT|WRFOUT VSV
Native levels, the .vsv's times the model's. Every stored value must be
within its species' quantisation bound (vsv-info's max error) plus 2e-5 m/s
(the longitudes and the rotation are float32 on one side, float64 here).
Prints "PASS name ..." / "FAIL name: why" lines with the largest differences;
exit 1 on a failure."""
import struct
import sys

import numpy

import vesuvius
from mm5_records import mm5_records

SLACK = 2e-5


def bhr(big, i, j):
    at = 4000 + 4 * ((j - 1) * 20 + (i - 1))
    return struct.unpack('>f', big[at:at + 4])[0]


def mm5_winds(path):
    """Per output period: (u, v, w) earth-relative, float64 [k bottom-up, I, J]."""
    cone = lon0 = None
    out, cur = [], {}
    for rec in mm5_records(path):
        if rec[0] == 0:
            cone, lon0 = bhr(rec[1], 4, 1), bhr(rec[1], 3, 1)
        elif rec[0] == 1:
            sub, field = rec[1], rec[2]
            end = struct.unpack('>4i', sub[20:36])
            stagger, order = sub[40:44].decode().strip(), sub[44:48].decode().strip()
            name = sub[72:81].decode().strip()
            if name not in ('U', 'V', 'W', 'LONGICRS'):
                continue
            nk = end[2] if order in ('YXS', 'YXW') else 1
            a = numpy.frombuffer(field, '>f4').reshape(nk, end[1], end[0]).astype(numpy.float64)
            if stagger == 'D':
                a = 0.25 * (a[:, :-1, :-1] + a[:, 1:, :-1] + a[:, :-1, 1:] + a[:, 1:, 1:])
            else:
                a = a[:, :-1, :-1]
            if order == 'YXW':
                a = 0.5 * (a[:-1] + a[1:])
            cur[name] = a.transpose(0, 2, 1)[::-1]  # [k, J, I] top-down -> [k, I, J] bottom-up
        elif rec[0] == 2:
            if 'U' in cur:
                alpha = numpy.radians(cone * (cur['LONGICRS'][0] - lon0))
                c, s = numpy.cos(alpha), numpy.sin(alpha)
                u, v = cur['U'], cur['V']
                out.append((u * c + v * s, -u * s + v * c, cur['W']))
            cur = {}
    return out


def wrf_winds(path):
    import netCDF4
    d = netCDF4.Dataset(path)
    out = []
    for t in range(d.dimensions['Time'].size):
        u = numpy.asarray(d['U'][t], numpy.float64)
        v = numpy.asarray(d['V'][t], numpy.float64)
        w = numpy.asarray(d['W'][t], numpy.float64)
        u, v, w = 0.5 * (u[:, :, :-1] + u[:, :, 1:]), 0.5 * (v[:, :-1] + v[:, 1:]), 0.5 * (w[:-1] + w[1:])
        if d.MAP_PROJ == 3:
            c, s = 1.0, 0.0
        else:
            lon = numpy.asarray(d['XLONG'][t] if d['XLONG'].ndim == 3 else d['XLONG'][:], numpy.float64)
            alpha = numpy.radians(lambert_cone(d.TRUELAT1, d.TRUELAT2) * (lon - d.STAND_LON))
            c, s = numpy.cos(alpha), numpy.sin(alpha)
            if 'SINALPHA' in d.variables:  # WRF's own angle (geogrid's, by finite differences): -alpha
                sa = numpy.asarray(d['SINALPHA'][t] if d['SINALPHA'].ndim == 3 else d['SINALPHA'][:])
                if numpy.abs(sa + s).max() > 1e-4:
                    raise SystemExit("FAIL wind: the cone's angle is not the file's SINALPHA (%g)" %
                                     numpy.abs(sa + s).max())
        out.append((u * c + v * s, -u * s + v * c, w))
    return out


def lambert_cone(t1, t2):
    """The cone factor of a Lambert conformal projection true at t1 and t2 (degrees, northern)."""
    t1, t2 = numpy.radians(t1), numpy.radians(t2)
    if abs(t1 - t2) < 1e-9:
        return numpy.sin(t1)
    return ((numpy.log(numpy.cos(t1)) - numpy.log(numpy.cos(t2))) /
            (numpy.log(numpy.tan(numpy.pi / 4 + t2 / 2)) - numpy.log(numpy.tan(numpy.pi / 4 + t1 / 2))))


def main():
    path, vsv = sys.argv[1], sys.argv[2]
    head = open(path, 'rb').read(4)
    ref = wrf_winds(path) if head[:3] in (b'CDF', b'\x89HD') else mm5_winds(path)
    f = vesuvius.open(vsv)
    sp = {s.name: s for s in f.species}
    status = 0
    if len(f.times) != len(ref):
        print("FAIL wind: %d times in %s, %d in the model file" % (len(f.times), vsv, len(ref)))
        return 1
    for c, name in enumerate(('wind_east', 'wind_north', 'wind_up')):
        if name not in sp:
            print("FAIL %s: not in %s" % (name, vsv))
            status = 1
            continue
        bound, worst, ok = sp[name].max_abs_error, 0.0, True
        for t in range(len(f.times)):
            got = f.read(name, t).astype(numpy.float64)
            want = ref[t][c]
            if got.shape != want.shape:
                print("FAIL %s: shape %s, by hand %s" % (name, got.shape, want.shape))
                ok = False
                break
            diff = numpy.abs(got - want)
            if numpy.isnan(got).any() or (diff > bound * (1 + 1e-6) + SLACK).any():
                k = numpy.unravel_index(numpy.nanargmax(diff), diff.shape)
                print("FAIL %s at step %d, cell (z, y, x) %s: %r, by hand %r, bound %g" %
                      (name, t, tuple(int(i) for i in k), got[k], want[k], bound))
                ok = False
                break
            worst = max(worst, diff.max())
        if ok:
            print("PASS %s: %d steps of %s within the bound %.3g + %g m/s of the model's (largest difference %.3g)"
                  % (name, len(f.times), vsv.split('/')[-1], bound, SLACK, worst))
        status |= not ok
    return status


if __name__ == '__main__':
    sys.exit(main())
