#!/usr/bin/python3
"""Writes a LAS file's points in another order (same records, same bytes per
point), to see whether a batch depends on point order.

Usage: reorder_las.py IN.las OUT.las shuffle SEED | cells METRES
  shuffle SEED   a random permutation
  cells METRES   rows of square cells, then x, y, z within a cell
Needs numpy (Debian's python3-numpy); not a project dependency.
"""
import struct
import sys

import numpy as np


def main():
    src, dst, how, arg = sys.argv[1], sys.argv[2], sys.argv[3], sys.argv[4]
    data = open(src, "rb").read()
    off = struct.unpack("<I", data[96:100])[0]
    reclen = struct.unpack("<H", data[105:107])[0]
    n = struct.unpack("<I", data[107:111])[0] or struct.unpack("<Q", data[247:255])[0]
    scale = np.array(struct.unpack("<3d", data[131:155]))
    offset = np.array(struct.unpack("<3d", data[155:179]))
    rec = np.frombuffer(data, dtype=np.uint8, count=n * reclen, offset=off).reshape(n, reclen)
    xyz = rec[:, 0:12].copy().view("<i4").reshape(n, 3) * scale + offset
    if how == "shuffle":
        order = np.random.default_rng(int(arg)).permutation(n)
    elif how == "cells":
        cell = float(arg)
        order = np.lexsort((xyz[:, 2], xyz[:, 1], xyz[:, 0],
                            np.floor(xyz[:, 0] / cell), np.floor(xyz[:, 1] / cell)))
    else:
        sys.exit("reorder_las.py: the order is 'shuffle SEED' or 'cells METRES'")
    open(dst, "wb").write(data[:off] + rec[order].tobytes())


if __name__ == "__main__":
    main()
