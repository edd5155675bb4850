#!/usr/bin/env python3
"""vdb_uniform.py — the volume bench_render wrote (float32, x fastest) as an
OpenVDB FloatGrid with cubic voxels, for vdb_render (whose ray intersector
takes uniform voxels only): the horizontal cell edge for all three axes, so
the exaggerated levels are squeezed by dx/dz (3 % for the MM5 run).
Usage: vdb_uniform.py RAW 'geometry ...' OUT.vdb NAME  (needs python3-openvdb)"""
import sys

import numpy as np
import pyopenvdb as vdb

raw, geo, out, name = sys.argv[1], sys.argv[2].split()[1:], sys.argv[3], sys.argv[4]
nx, ny, nz = (int(v) for v in geo[:3])
ox, oy, oz, dx = (float(v) for v in geo[3:7])
a = np.fromfile(raw, dtype=np.float32).reshape(nz, ny, nx)
grid = vdb.FloatGrid()
grid.copyFromArray(np.ascontiguousarray(a.transpose(2, 1, 0)))  # index (i, j, k)
grid.transform = vdb.createLinearTransform(voxelSize=dx)
grid.transform.translate((ox, oy, oz))
grid.name = name
vdb.write(out, grids=[grid])
