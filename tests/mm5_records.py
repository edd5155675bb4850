"""mm5_records.py — the Fortran records of an MM5 v3 file, read from
../shared/docs/INPUT-FORMATS.md alone (big-endian 4-byte length markers
around each record), for the test scripts that read MM5 independently of
Vesuvius (model_extremes.py, derive_check.py)."""
import struct


def mm5_records(path):
    """Yields (0, big_header) and (1, sub_header, field) per header flag;
    the end-of-period flag 2 as (2,)."""
    data = open(path, 'rb').read()
    at = 0

    def record():
        nonlocal at
        n = struct.unpack('>i', data[at:at + 4])[0]
        r = data[at + 4:at + 4 + n]
        at += 8 + n
        return r

    while at < len(data):
        flag = struct.unpack('>i', record())[0]
        if flag == 0:
            yield (0, record())
        elif flag == 1:
            sub = record()
            yield (1, sub, record())
        else:
            yield (flag,)
