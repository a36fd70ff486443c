#!/usr/bin/python3
"""Renders a parcel OBJ (groups per element) to a PNG: plan view with the roof
points over it, and an axonometric view. A developer's eye on the models.

Usage: render_parcel.py MODEL.obj OUT.png [CLOUD.las]
Needs Debian's python3-matplotlib (not a project dependency).
"""
import re
import struct
import sys

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
from mpl_toolkits.mplot3d.art3d import Poly3DCollection

COLOURS = {"roof": "#b5533c", "wall": "#d9d9d9", "party_wall": "#f0a030", "ground": "#555555",
           "outer_ceiling": "#5b8fd9"}


def read_obj(path):
    verts, faces, origin = [], [], np.zeros(3)
    group = "roof"
    for line in open(path):
        if line.startswith("# coordinates local"):
            m = re.search(r"\(([-\d.]+), ([-\d.]+), ([-\d.]+)\)", line)
            origin = np.array([float(v) for v in m.groups()])
        elif line.startswith("v "):
            verts.append([float(v) for v in line.split()[1:4]])
        elif line.startswith("g "):
            name = line.split()[1]
            group = next((k for k in ["party_wall", "outer_ceiling", "roof", "wall", "ground"] if f"_{k}_" in name), "roof")
            gid = name
        elif line.startswith("f "):
            idx = [int(t.split("/")[0]) - 1 for t in line.split()[1:]]
            faces.append((group, gid, idx))
    return np.array(verts), faces, origin


def read_las(path, bbox, origin):
    data = open(path, "rb").read()
    off = struct.unpack("<I", data[96:100])[0]
    fmt = data[104] & 0x3F
    reclen = struct.unpack("<H", data[105:107])[0]
    n = struct.unpack("<I", data[107:111])[0] or struct.unpack("<Q", data[247:255])[0]
    sc = np.array(struct.unpack("<3d", data[131:155]))
    of = np.array(struct.unpack("<3d", data[155:179]))
    rec = np.frombuffer(data, dtype=np.uint8, count=n * reclen, offset=off).reshape(n, reclen)
    xyz = rec[:, 0:12].copy().view("<i4").reshape(n, 3) * sc + of - origin
    cls = rec[:, 16] if fmt >= 6 else rec[:, 15] & 31
    keep = (xyz[:, 0] > bbox[0]) & (xyz[:, 0] < bbox[2]) & (xyz[:, 1] > bbox[1]) & (xyz[:, 1] < bbox[3])
    return xyz[keep], cls[keep]


def main():
    verts, faces, origin = read_obj(sys.argv[1])
    lo, hi = verts.min(0), verts.max(0)
    fig = plt.figure(figsize=(14, 7))
    ax = fig.add_subplot(1, 2, 1)
    if len(sys.argv) > 3:
        pts, cls = read_las(sys.argv[3], (lo[0] - 3, lo[1] - 3, hi[0] + 3, hi[1] + 3), origin)
        roof = np.isin(cls, [6])
        ax.scatter(pts[roof, 0], pts[roof, 1], s=0.3, c=pts[roof, 2], cmap="viridis")
        ax.scatter(pts[~roof, 0], pts[~roof, 1], s=0.3, c="k")
    groups = sorted({g for _, g, _ in faces})
    cmap = plt.get_cmap("tab10")
    for group, gid, idx in faces:
        if group == "roof":
            p = verts[idx]
            k = groups.index(gid)
            ax.fill(p[:, 0], p[:, 1], alpha=0.35, color=cmap(k % 10), lw=0)
        if group in ("wall", "party_wall"):
            p = verts[idx]
            ax.plot(p[:, 0], p[:, 1], color="orange" if group == "party_wall" else "r", lw=1.5)
    ax.set_aspect("equal")
    ax3 = fig.add_subplot(1, 2, 2, projection="3d")
    polys = [verts[idx] for g, _, idx in faces if g != "outer_ceiling"]
    cols = [COLOURS[g] for g, _, _ in faces if g != "outer_ceiling"]
    ax3.add_collection3d(Poly3DCollection(polys, facecolors=cols, edgecolors="k", linewidths=0.2))
    ax3.set_xlim(lo[0], hi[0]); ax3.set_ylim(lo[1], hi[1]); ax3.set_zlim(lo[2], lo[2] + max(hi[0] - lo[0], hi[1] - lo[1]))
    ax3.view_init(elev=35, azim=-60)
    fig.suptitle(sys.argv[1].split("/")[-1])
    fig.tight_layout()
    fig.savefig(sys.argv[2], dpi=90)


if __name__ == "__main__":
    main()
