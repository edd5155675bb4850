#!/usr/bin/env python3
"""mm5_split.py — cuts an MM5 v3 file into one file per output period:
each gets the big header (flag 0 and its record) and that period's records
(flag 1, sub-header, data, ..., flag 2), as MM5 itself writes a restarted
run, so the tests can convert one real run as a multi-file run.
   mm5_split.py IN OUTPREFIX [N]   writes OUTPREFIX_00, OUTPREFIX_01, ...
with N periods each (default 1; the last may have fewer) and prints the
number of files."""
import struct
import sys


def records(data, name):
    """Each Fortran record with its length markers, as bytes."""
    at = 0
    while at < len(data):
        n = struct.unpack('>i', data[at:at + 4])[0]
        end = at + 8 + n
        if n < 0 or end > len(data) or data[at + 4 + n:end] != data[at:at + 4]:
            sys.exit('mm5_split.py: %s: bad record at byte %d' % (name, at))
        yield data[at:end]
        at = end


def main():
    if len(sys.argv) not in (3, 4):
        sys.exit('usage: mm5_split.py IN OUTPREFIX [N]')
    name = sys.argv[1]
    per = int(sys.argv[3]) if len(sys.argv) == 4 else 1
    recs = records(open(name, 'rb').read(), name)
    big, period, n, k = b'', [], 0, 0
    for r in recs:
        flag = struct.unpack('>i', r[4:8])[0]
        if flag == 0:        # big header: flag, header
            big = r + next(recs)
        elif flag == 1:      # a field: flag, sub-header, data
            period += [r, next(recs), next(recs)]
        elif flag == 2:      # end of the period
            period.append(r)
            k += 1
            if k == per:
                with open('%s_%02d' % (sys.argv[2], n), 'wb') as f:
                    f.write(big + b''.join(period))
                period, n, k = [], n + 1, 0
        else:
            sys.exit('mm5_split.py: %s: flag %d where a flag record belongs' % (name, flag))
    if k:
        with open('%s_%02d' % (sys.argv[2], n), 'wb') as f:
            f.write(big + b''.join(period))
        n += 1
    elif period or not big:
        sys.exit('mm5_split.py: %s: no big header, or a period without its end flag' % name)
    print(n)


if __name__ == '__main__':
    main()
