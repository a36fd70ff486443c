#!/usr/bin/python3
"""A mesh level's PLY (as `batch --mesh` and `cadastre3d mesh` write them)
drawn as an SVG from any side, to look at facades the report's pictures (from
above) do not show: orthographic, faces shaded by their normal, far ones
first. docs/meshes.md's facade pictures are made with it.

  render_mesh_view.py MESH.ply OUT.svg [--azimuth DEG] [--elevation DEG]
      [--width PX] [--box XMIN,YMIN,ZMIN,XMAX,YMAX,ZMAX]

--azimuth: the direction the viewer looks from, degrees clockwise from north
(0: from the north, looking south); --elevation: degrees above the horizon;
--box keeps the faces whose centre lies in it (local coordinates).
"""
import argparse
import math
import struct
import sys

import numpy as np


def read_ply(path):
    with open(path, "rb") as f:
        header = []
        while True:
            line = f.readline().decode("ascii", "replace").strip()
            header.append(line)
            if line == "end_header":
                break
        if "format binary_little_endian 1.0" not in header:
            sys.exit(f"{path}: not a binary little-endian PLY")
        nv = next(int(h.split()[2]) for h in header if h.startswith("element vertex"))
        nf = next(int(h.split()[2]) for h in header if h.startswith("element face"))
        vertices = np.frombuffer(f.read(12 * nv), dtype="<f4").reshape(nv, 3).astype(float)
        faces = np.frombuffer(f.read(13 * nf), dtype=np.dtype([("n", "u1"), ("i", "<i4", 3)]))
        return vertices, faces["i"]


def main():
    a = argparse.ArgumentParser()
    a.add_argument("ply")
    a.add_argument("svg")
    a.add_argument("--azimuth", type=float, default=225)
    a.add_argument("--elevation", type=float, default=20)
    a.add_argument("--width", type=int, default=800)
    a.add_argument("--box", default="")
    o = a.parse_args()
    v, f = read_ply(o.ply)
    tri = v[f]  # faces x 3 corners x 3
    if o.box:
        lo_hi = [float(x) for x in o.box.split(",")]
        c = tri.mean(axis=1)
        keep = np.all((c >= lo_hi[:3]) & (c <= lo_hi[3:]), axis=1)
        tri = tri[keep]
    az, el = math.radians(o.azimuth), math.radians(o.elevation)
    toward = np.array([math.sin(az) * math.cos(el), math.cos(az) * math.cos(el), math.sin(el)])  # to the viewer
    right = np.array([-math.cos(az), math.sin(az), 0.0])
    up = np.cross(toward, right)
    x, y = tri @ right, -(tri @ up)
    depth = (tri.mean(axis=1)) @ toward
    n = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    n /= np.maximum(np.linalg.norm(n, axis=1, keepdims=True), 1e-12)
    light = np.array([-0.3, -0.6, 0.75]) / np.linalg.norm([-0.3, -0.6, 0.75])
    shade = 0.35 + 0.65 * np.abs(n @ (0.5 * light + 0.5 * toward))
    lo_x, lo_y = x.min(), y.min()
    scale = (o.width - 20) / max(x.max() - lo_x, 1e-6)
    height = int((y.max() - lo_y) * scale + 40)
    out = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{o.width}" height="{height}">',
           f'<rect width="100%" height="100%" fill="white"/>',
           f'<text x="6" y="14" font-size="12" font-family="sans-serif">{o.ply.split("/")[-1]}, '
           f'{len(tri)} faces</text>']
    for k in np.argsort(depth):
        g = int(255 * min(1.0, shade[k]))
        pts = " ".join(f"{10 + (x[k, i] - lo_x) * scale:.1f},{30 + (y[k, i] - lo_y) * scale:.1f}" for i in range(3))
        out.append(f'<polygon points="{pts}" fill="rgb({g},{g - 8},{g - 24})" stroke="#444" stroke-width="0.2"/>')
    out.append("</svg>")
    with open(o.svg, "w") as s:
        s.write("\n".join(out))


if __name__ == "__main__":
    main()
