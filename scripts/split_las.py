#!/usr/bin/env python3
"""Cut a LAS file into an N x N grid of LAS tiles (the header's bounds and
counts set per tile, VLRs copied), to feed `cadastre3d batch --cloud DIR`.

  split_las.py cloud.las OUT_DIR [--grid 4]
"""
import argparse
import os
import struct

import numpy as np


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("las")
    ap.add_argument("out")
    ap.add_argument("--grid", type=int, default=4)
    a = ap.parse_args()
    with open(a.las, "rb") as f:
        head = bytearray(f.read(375))
    if head[:4] != b"LASF":
        raise SystemExit(f"{a.las}: not a LAS file")
    minor, fmt = head[25], head[104] & 0x3F
    if head[104] & 0xC0:
        raise SystemExit(f"{a.las}: compressed (LAZ); give an uncompressed LAS")
    offset = struct.unpack_from("<I", head, 96)[0]
    rec = struct.unpack_from("<H", head, 105)[0]
    count = struct.unpack_from("<I", head, 107)[0]
    if minor >= 4:
        count = struct.unpack_from("<Q", head, 247)[0] or count
    scale = struct.unpack_from("<3d", head, 131)
    off = struct.unpack_from("<3d", head, 155)
    with open(a.las, "rb") as f:
        prefix = bytearray(f.read(offset))
    data = np.memmap(a.las, dtype=np.uint8, mode="r", offset=offset, shape=(count, rec))
    xyz = data[:, :12].copy().view("<i4").reshape(count, 3)
    x = xyz[:, 0] * scale[0] + off[0]
    y = xyz[:, 1] * scale[1] + off[1]
    z = xyz[:, 2] * scale[2] + off[2]
    gx = np.minimum(((x - x.min()) / (x.max() - x.min() + 1e-9) * a.grid).astype(int), a.grid - 1)
    gy = np.minimum(((y - y.min()) / (y.max() - y.min() + 1e-9) * a.grid).astype(int), a.grid - 1)
    os.makedirs(a.out, exist_ok=True)
    for i in range(a.grid):
        for j in range(a.grid):
            sel = np.nonzero((gx == i) & (gy == j))[0]
            if sel.size == 0:
                continue
            h = bytearray(prefix)
            n = int(sel.size)
            struct.pack_into("<I", h, 107, n if fmt < 6 and n < 2**32 else 0)
            if minor >= 4 and len(h) >= 255:
                struct.pack_into("<Q", h, 247, n)
            struct.pack_into("<6d", h, 179, x[sel].max(), x[sel].min(), y[sel].max(), y[sel].min(),
                             z[sel].max(), z[sel].min())
            if minor >= 4 and len(h) >= 243:  # no EVLRs in a tile
                struct.pack_into("<QI", h, 235, 0, 0)
            path = os.path.join(a.out, f"tile_{i}_{j}.las")
            with open(path, "wb") as f:
                f.write(h)
                for k in range(0, n, 1 << 20):
                    f.write(np.ascontiguousarray(data[sel[k:k + (1 << 20)]]).tobytes())
            print(path, n)


if __name__ == "__main__":
    main()
