"""fieldstream.py — read a Vesuvius field stream (format/SPEC.md §13) into
numpy: the grid, the variable names and the frames. Used by the advection
benchmarks (bench/advect_motion.py, bench/advect_track.py)."""
import struct

import numpy as np


def _str(b, o):
    n = struct.unpack_from('<I', b, o)[0]
    return b[o + 4:o + 4 + n].decode(), o + 4 + n


def read(path):
    """(nx, ny, nz, spacing, names, [(time, array[nvars, nz, ny, nx])])."""
    b = open(path, 'rb').read()
    if b[:8] != b'\x89VSF\r\n\x1a\n':
        raise ValueError('%s: not a field stream' % path)
    n = struct.unpack_from('<I', b, 12)[0]
    o, end = 16, 16 + n
    names, grid = [], None
    while o < end:
        tag, ln = b[o:o + 4], struct.unpack_from('<I', b, o + 4)[0]
        p = o + 8
        if tag == b'GRID':
            nx, ny, nz = struct.unpack_from('<III', b, p)
            spacing = struct.unpack_from('<3d', b, p + 16 + 24)
            grid = (nx, ny, nz, spacing)
        elif tag == b'VAR ':
            names.append(_str(b, p)[0])
        o = p + ((ln + 7) // 8) * 8
    nx, ny, nz, spacing = grid
    cells, frames, o = nx * ny * nz, [], end
    while b[o:o + 4] == b'FRAM':
        t = struct.unpack_from('<q', b, o + 8)[0]
        a = np.frombuffer(b, '<f4', len(names) * cells, o + 16).reshape(len(names), nz, ny, nx)
        frames.append((t, a))
        o += 16 + len(names) * cells * 4
    return nx, ny, nz, spacing, names, frames
