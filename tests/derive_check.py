#!/usr/bin/env python3
"""derive_check.py — the built-ins of vsv-convert --derive computed by hand
from an MM5 v3 file or a WRF wrfout, read here independently of Vesuvius
(from ../shared/docs/INPUT-FORMATS.md alone; WRF through python3-netcdf4),
against the values of a .vsv read back through the Python module. Native
levels only (the .vsv's levels are the file's).
   derive_check.py MMOUT|WRFOUT VSV NAME...
For each NAME among condensate, wind_speed, theta, rh and each time of the
.vsv, the hand value (at a model time, or interpolated linearly between the
two around it: --time-res interpolates the derived field) must be within the
species' quantisation bound (vsv-info's max error) plus a tolerance:
condensate none (the same float sum), the others 1e-6 of the value (the
pressure and the averaged winds are float32 in the converter, float64 here).
Prints "PASS name" / "FAIL name: why" lines and the largest differences."""
import struct
import sys

import numpy

import vesuvius
from mm5_records import mm5_records

HYDRO = ["CLW", "RNW", "ICE", "SNOW", "GRAUPEL", "QCLOUD", "QRAIN", "QICE", "QSNOW", "QGRAUP"]


def mm5_periods(path):
    """Per output time: its date (datetime64) and the 3-D, 2-D and 1-D fields
    on cross points as [k bottom-up, I south-north, J west-east] (dot-point
    fields averaged from their four corners); PTOP from the big header."""
    ptop, periods, cur = None, [], {}
    for rec in mm5_records(path):
        flag = rec[0]
        if flag == 0:
            big = rec[1]
            ptop = struct.unpack('>f', big[4000 + 4 * (1 * 20 + 1):4000 + 4 * (1 * 20 + 1) + 4])[0]  # bhr(2,2)
        elif flag == 1:
            sub, field = rec[1], rec[2]
            end = struct.unpack('>4i', sub[20:36])
            stagger = sub[40:44].decode().strip()
            order = sub[44:48].decode().strip()
            name = sub[72:81].decode().strip()
            cur['date'] = sub[48:67].decode().replace('_', 'T')
            if order == 'YXS':
                a = numpy.frombuffer(field, '>f4').reshape(end[2], end[1], end[0]).astype(numpy.float64)
            elif order == 'YX':
                a = numpy.frombuffer(field, '>f4').reshape(1, end[1], end[0]).astype(numpy.float64)
            elif order == 'S':
                cur[name] = numpy.frombuffer(field, '>f4').astype(numpy.float64)
                continue
            else:
                continue
            if stagger == 'D':
                a = 0.25 * (a[:, :-1, :-1] + a[:, 1:, :-1] + a[:, :-1, 1:] + a[:, 1:, 1:])
            else:
                a = a[:, :-1, :-1]
            # [k, J, I] top-down → [k, I, J] bottom-up
            cur[name] = numpy.ascontiguousarray(a.transpose(0, 2, 1)[::-1])
        elif flag == 2:
            periods.append(cur)
            cur = {}
    return ptop, periods


def wrf_periods(path):
    """Per time: its date and the fields on mass points, [k, y, x] bottom-up
    as WRF stores them (staggered winds the mean of their two faces)."""
    import netCDF4
    d = netCDF4.Dataset(path)
    want = ["T", "P", "PB", "QVAPOR", "U", "V"] + HYDRO
    periods = []
    for t in range(d.dimensions["Time"].size):
        f = {"wrf": True, "date": b"".join(d["Times"][t]).decode().replace("_", "T")}
        for n in want:
            if n in d.variables:
                a = numpy.asarray(d[n][t], numpy.float64)
                if n == "U":
                    a = 0.5 * (a[:, :, :-1] + a[:, :, 1:])
                elif n == "V":
                    a = 0.5 * (a[:, :-1, :] + a[:, 1:, :])
                f[n] = a
        periods.append(f)
    return None, periods


def hand(ptop, f, name):
    """One built-in at one output time, float64, as vsv-convert(1) defines it."""
    if name == 'condensate':
        return sum(f[q] for q in HYDRO if q in f)
    if name == 'wind_speed':
        return numpy.sqrt(f['U'] ** 2 + f['V'] ** 2)
    if f.get('wrf'):  # T is theta - 300 K; the pressure P + PB
        p, q = f['P'] + f['PB'], f['QVAPOR']
        if name == 'theta':
            return f['T'] + 300
        t = (f['T'] + 300) * (p / 100000.0) ** 0.2857
    else:
        sigma = f['SIGMAH'][::-1]  # bottom-up like the levels
        p = f['PSTARCRS'][0][None, :, :] * sigma[:, None, None] + ptop + f['PP']
        t, q = f['T'], f['Q']
        if name == 'theta':
            return t * (100000.0 / p) ** 0.2857
    e = q * p / (0.622 + q)
    es = 611.2 * numpy.exp(17.67 * (t - 273.15) / (t - 29.65))  # Bolton (1980), Pa
    return 100.0 * e / es


def main():
    path, vsv, names = sys.argv[1], sys.argv[2], sys.argv[3:]
    head = open(path, 'rb').read(4)
    ptop, periods = wrf_periods(path) if head[:3] in (b'CDF', b'\x89HD') else mm5_periods(path)
    # the model times that hold a period (set-up files have none)
    mt = numpy.array([numpy.datetime64(p['date']) for p in periods])
    v = vesuvius.open(vsv)
    species = {s.name: s for s in v.species}
    status = 0
    for name in names:
        if name not in species:
            print("FAIL %s: not in %s" % (name, vsv))
            status = 1
            continue
        bound = species[name].max_abs_error
        ref = [hand(ptop, p, name).astype(numpy.float32).astype(numpy.float64) for p in periods]
        worst, where = 0.0, None
        ok = True
        for ti, t in enumerate(v.times):
            b = int(numpy.searchsorted(mt, t))
            if b < len(mt) and mt[b] == t:
                want = ref[b]
            else:  # between two model times: the derived field interpolated
                a = b - 1
                w = (t - mt[a]) / (mt[b] - mt[a])
                want = ref[a] + (ref[b] - ref[a]) * w
            got = v.read(name, ti).astype(numpy.float64)
            if got.shape != want.shape:
                print("FAIL %s: shape %s, by hand %s" % (name, got.shape, want.shape))
                ok = False
                break
            tol = bound * (1 + 1e-6) + (0 if name == 'condensate' else 1e-6 * numpy.abs(want))
            excess = numpy.abs(got - want) - tol
            if numpy.isnan(got).any() or (excess > 0).any():
                k = numpy.unravel_index(numpy.nanargmax(excess), excess.shape)
                print("FAIL %s at %s: cell (z, y, x) %s: %r, by hand %r, bound %g" %
                      (name, t, tuple(int(i) for i in k), got[k], want[k], bound))
                ok = False
                break
            d = numpy.abs(got - want).max()
            if d >= worst:
                worst, where = d, t
        if ok:
            print("PASS %s: %d times of %s within the bound %.3g%s of the hand value (largest difference %.3g at %s)"
                  % (name, len(v.times), vsv.split('/')[-1], bound, "" if name == 'condensate' else " + 1e-6 of it",
                     worst, where))
        status |= not ok
    return status


if __name__ == '__main__':
    sys.exit(main())
