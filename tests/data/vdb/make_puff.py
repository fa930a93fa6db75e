#!/usr/bin/python3
"""Writes puff.vdb with OpenVDB's own Python bindings (pyopenvdb, Debian package
python3-openvdb), not with vpm's writer: a VDB as other tools make it. Deterministic.

usage: /usr/bin/python3 tests/data/vdb/make_puff.py [OUT.vdb]

The file: one FloatGrid named "density" (grid class fog volume, OpenVDB's default compression),
a 24^3 index box [-12, 11]^3 holding a smooth puff  d(i, j, k) = max(0, 1 - r/10)^2 * (1 + 0.25 sin(i/2))
with r = |(i, j, k)| in voxels (values below 1e-3 left inactive), and an index-to-world transform
of voxel size 0.05 translated by (0.25, 1.0, -0.5).
"""
import math
import sys

import pyopenvdb as vdb


def density(i, j, k):
    r = math.sqrt(i * i + j * j + k * k)
    return max(0.0, 1.0 - r / 10.0) ** 2 * (1.0 + 0.25 * math.sin(i / 2.0))


def main():
    out = sys.argv[1] if len(sys.argv) > 1 else "puff.vdb"
    grid = vdb.FloatGrid(0.0)   # the Debian bindings have no DoubleGrid
    grid.name = "density"
    grid.gridClass = vdb.GridClass.FOG_VOLUME
    acc = grid.getAccessor()
    for i in range(-12, 12):
        for j in range(-12, 12):
            for k in range(-12, 12):
                d = density(i, j, k)
                if d >= 1e-3:
                    acc.setValueOn((i, j, k), d)
    xf = vdb.createLinearTransform(voxelSize=0.05)
    xf.translate((0.25, 1.0, -0.5))
    grid.transform = xf
    grid["creator"] = "vpm tests/data/vdb/make_puff.py (pyopenvdb)"
    vdb.write(out, grids=[grid])


if __name__ == "__main__":
    main()
