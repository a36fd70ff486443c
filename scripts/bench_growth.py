#!/usr/bin/python3
"""How each stage's CPU time grows with what it works on (issue 53): a stage
superlinear in its input shows as an exponent well above 1 (n log n over a
doubling gives about 1.1).

  bench_growth.py densify CLOUD.las PARCELS DTM [--factors 1 2 4 8] [--c3d BIN]
  bench_growth.py towns [--sizes 1000 4000 16000] [--c3d BIN]
  bench_growth.py pieces [--grids 0 1 2 4] [--c3d BIN]
  bench_growth.py layer [--sizes 1000 10000 100000] [--c3d BIN]

`densify`: the one building (or few) of CLOUD, its points repeated k times,
each copy after the first moved by a random offset within a quarter of the
point spacing in plan and 5 mm in height (seeded): the same roof, k times
the points. `pieces`: one 32 x 32 m building whose roof is a k x k field of
pyramids (4k² planes; k = 0: one shed plane), at 20 points/m² with 3 cm
noise, so the points stay the same and the roof's pieces grow. `layer`: a
sample town of 24 parcels and its points, its parcel layer grown to N
parcels by 10 x 20 m lots of open land beside it (no points): what grows is
only the layer. `towns`: sample towns of growing parcel counts (`sample
--parcels N`). Each size is batched once, one thread (--jobs 1), CityJSON
only; the table gives every stage's CPU seconds (summary.json's stages_cpu)
per size and the exponent between consecutive sizes, log(t2/t1)/log(n2/n1),
with the whole process's user+sys CPU beside them. Stages under 0.05 s are
too short to read an exponent from and show "-".
"""
import argparse
import json
import math
import os
import resource
import struct
import subprocess
import sys
import tempfile

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
DEFAULT_C3D = os.path.join(HERE, "..", "build", "cli", "cadastre3d")


def densify_las(src, dst, k, seed=1):
    """Writes src's points k times to dst (see the module's docstring)."""
    with open(src, "rb") as f:
        raw = f.read()
    if raw[:4] != b"LASF":
        raise SystemExit(f"{src}: not a LAS file")
    if raw[104] & 0xC0:
        raise SystemExit(f"{src}: compressed (LAZ); give an uncompressed LAS")
    minor = raw[25]
    offset = struct.unpack_from("<I", raw, 96)[0]
    rec = struct.unpack_from("<H", raw, 105)[0]
    count = struct.unpack_from("<I", raw, 107)[0]
    if minor >= 4:
        count = struct.unpack_from("<Q", raw, 247)[0] or count
        if struct.unpack_from("<I", raw, 240)[0]:
            raise SystemExit(f"{src}: has extended VLRs after the points; not handled")
    scale = struct.unpack_from("<3d", raw, 131)
    hi = np.array(struct.unpack_from("<6d", raw, 179)[0::2])  # max x, y, z
    lo = np.array(struct.unpack_from("<6d", raw, 179)[1::2])
    off = np.array(struct.unpack_from("<3d", raw, 155))
    points = np.frombuffer(raw, dtype=np.uint8, count=count * rec, offset=offset).reshape(count, rec)
    spacing = math.sqrt(max((hi[0] - lo[0]) * (hi[1] - lo[1]), 1e-9) / max(count, 1))
    rng = np.random.default_rng(seed)
    copies = [points]
    ilo = np.round((lo - off) / scale).astype(np.int64)
    ihi = np.round((hi - off) / scale).astype(np.int64)
    for _ in range(1, k):
        c = points.copy()
        xyz = c[:, :12].copy().view("<i4").reshape(count, 3).astype(np.int64)
        jitter = np.stack([rng.uniform(-spacing / 4, spacing / 4, count) / scale[0],
                           rng.uniform(-spacing / 4, spacing / 4, count) / scale[1],
                           rng.uniform(-0.005, 0.005, count) / scale[2]], axis=1)
        xyz = np.clip(xyz + np.round(jitter).astype(np.int64), ilo, ihi)
        c[:, :12] = xyz.astype("<i4").view(np.uint8).reshape(count, 12)
        copies.append(c)
    head = bytearray(raw[:offset])
    total = count * k
    struct.pack_into("<I", head, 107, total if total < 2**32 and (minor < 4 or (raw[104] & 0x3F) < 6) else 0)
    legacy = struct.unpack_from("<5I", head, 111)
    struct.pack_into("<5I", head, 111, *[v * k if total < 2**32 else 0 for v in legacy])
    if minor >= 4:
        struct.pack_into("<Q", head, 247, total)
        struct.pack_into("<15Q", head, 255, *[v * k for v in struct.unpack_from("<15Q", head, 255)])
    with open(dst, "wb") as f:
        f.write(head)
        for c in copies:
            f.write(c.tobytes())
    return total


SIDE_M = 32.0          # the pieces building's side
EAVE_M = 6.0           # its eaves above the flat terrain
PIECES_DENSITY = 20.0  # roof points per m²
EPSG = 32748
ORIGIN = (781000.0, 9240000.0)


def pyramid_roof_z(x, y, k):
    """Height above the eaves of a k x k field of pyramids (pitch 35°) over
    the building's square; k = 0 gives one shed plane rising 3 m."""
    if k == 0:
        return 3.0 * y / SIDE_M
    cell = SIDE_M / k
    u, v = np.mod(x, cell), np.mod(y, cell)
    to_edge = np.minimum(np.minimum(u, cell - u), np.minimum(v, cell - v))
    return math.tan(math.radians(35)) * to_edge


def write_las(path, xyz, classes):
    """LAS 1.2, point format 0, mm scale, offset at the origin."""
    scale, off = 0.001, np.array([ORIGIN[0], ORIGIN[1], 0.0])
    q = np.round((xyz - off) / scale).astype("<i4")
    rec = np.zeros(len(xyz), dtype=[("xyz", "<i4", 3), ("i", "<u2"), ("f", "u1"), ("c", "u1"),
                                    ("a", "i1"), ("u", "u1"), ("s", "<u2")])
    rec["xyz"], rec["f"], rec["c"] = q, 0x09, classes  # return 1 of 1
    head = bytearray(227)
    head[0:4] = b"LASF"
    head[24], head[25] = 1, 2
    head[26:58] = b"cadastre3d bench_growth".ljust(32, b"\0")
    struct.pack_into("<HIIBHI", head, 94, 227, 227, 0, 0, 20, len(xyz))
    struct.pack_into("<5I", head, 111, len(xyz), 0, 0, 0, 0)
    struct.pack_into("<3d3d", head, 131, scale, scale, scale, *off)
    hi, lo = xyz.max(axis=0), xyz.min(axis=0)
    struct.pack_into("<6d", head, 179, hi[0], lo[0], hi[1], lo[1], hi[2], lo[2])
    with open(path, "wb") as f:
        f.write(head)
        f.write(rec.tobytes())


def pieces_scene(folder, k, seed=1):
    """The pieces building (see the module's docstring) with ground round it:
    cloud.las, parcels.gpkg (one parcel), dtm.tif (flat, z = 0)."""
    from osgeo import gdal, ogr, osr
    rng = np.random.default_rng(seed)
    x0, y0 = ORIGIN[0] + 10, ORIGIN[1] + 10
    n_roof = int(PIECES_DENSITY * SIDE_M * SIDE_M)
    x, y = rng.uniform(0, SIDE_M, n_roof), rng.uniform(0, SIDE_M, n_roof)
    z = EAVE_M + pyramid_roof_z(x, y, k) + rng.normal(0, 0.03, n_roof)
    roof = np.stack([x0 + x, y0 + y, z], axis=1)
    ground = []
    while len(ground) < 4 * n_roof // 5:  # 10 points/m² on the open ground of the 52 m square
        g = rng.uniform(-10, SIDE_M + 10, (4096, 2))
        ground.extend(g[~((g >= 0) & (g <= SIDE_M)).all(axis=1)])
    ground = np.array(ground)
    ground = np.column_stack([x0 + ground[:, 0], y0 + ground[:, 1], rng.normal(0, 0.03, len(ground))])
    write_las(os.path.join(folder, "cloud.las"), np.vstack([roof, ground]),
              np.concatenate([np.full(len(roof), 6), np.full(len(ground), 2)]).astype("u1"))
    srs = osr.SpatialReference()
    srs.ImportFromEPSG(EPSG)
    ds = ogr.GetDriverByName("GPKG").CreateDataSource(os.path.join(folder, "parcels.gpkg"))
    layer = ds.CreateLayer("parcels", srs, ogr.wkbPolygon)
    layer.CreateField(ogr.FieldDefn("NIB", ogr.OFTString))
    f = ogr.Feature(layer.GetLayerDefn())
    f.SetField("NIB", f"pieces{k}")
    f.SetGeometry(ogr.CreateGeometryFromWkt(
        f"POLYGON(({x0 - 5} {y0 - 5},{x0 + SIDE_M + 5} {y0 - 5},{x0 + SIDE_M + 5} {y0 + SIDE_M + 5},"
        f"{x0 - 5} {y0 + SIDE_M + 5},{x0 - 5} {y0 - 5}))"))
    layer.CreateFeature(f)
    ds = None
    size = int(SIDE_M + 20)
    dtm = gdal.GetDriverByName("GTiff").Create(os.path.join(folder, "dtm.tif"), size, size, 1, gdal.GDT_Float32)
    dtm.SetGeoTransform((x0 - 10, 1, 0, y0 + SIDE_M + 10, 0, -1))
    dtm.SetProjection(srs.ExportToWkt())
    dtm.GetRasterBand(1).Fill(0.0)
    dtm = None


def layer_with_lots(src, dst, total):
    """src's parcels and, beside them to the east, 10 x 20 m lots of open land
    up to `total` parcels in all, in rows of 100."""
    from osgeo import ogr
    ds = ogr.Open(src)
    layer = ds.GetLayer(0)
    x0, x1, y0, _ = layer.GetExtent()
    out = ogr.GetDriverByName("GPKG").CreateDataSource(dst)
    lots = out.CopyLayer(layer, "parcels")
    field = lots.GetLayerDefn().GetFieldIndex("NIB")
    lots.StartTransaction()
    for k in range(total - layer.GetFeatureCount()):
        col, row = k % 100, k // 100
        ox, oy = x1 + 50 + 10 * col, y0 + 20 * row
        f = ogr.Feature(lots.GetLayerDefn())
        if field >= 0:
            f.SetField(field, f"lot{k}")
        f.SetGeometry(ogr.CreateGeometryFromWkt(
            f"POLYGON(({ox} {oy},{ox + 10} {oy},{ox + 10} {oy + 20},{ox} {oy + 20},{ox} {oy}))"))
        lots.CreateFeature(f)
    lots.CommitTransaction()
    out = None


def batch(c3d, cloud, parcels, dtm, out, formats="cityjson"):
    """Stages' CPU seconds and the whole process's user+sys of one batch,
    one thread; `formats` None: the default outputs."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    cmd = [c3d, "batch", "--quiet", "--jobs", "1", "--cloud", cloud, "--parcels", parcels, "--out", out]
    if formats:
        cmd += ["--formats", formats]
    if dtm:
        cmd += ["--dtm", dtm]
    r = subprocess.run(cmd, capture_output=True, text=True, env=dict(os.environ, OMP_NUM_THREADS="1"))
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if r.returncode not in (0, 3):  # 3: some parcels failed (the layer's lots lie outside the cloud)
        raise SystemExit(f"bench_growth: batch on {cloud} failed: {r.stderr.strip()[-400:]}")
    with open(os.path.join(out, "summary.json")) as f:
        stages = json.load(f)["timings_s"].get("stages_cpu", {})
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return stages, cpu


def exponent(n1, t1, n2, t2):
    if t1 < 0.05 or t2 < 0.05:
        return "-"
    return f"{math.log(t2 / t1) / math.log(n2 / n1):.2f}"


def print_table(label, sizes, runs):
    """runs: [(stages, cpu)] per size."""
    stages = sorted({s for st, _ in runs for s in st}, key=lambda s: -runs[-1][0].get(s, 0))
    rows = stages + ["whole process"]
    head = f"{'stage':24}" + "".join(f"{label + ' ' + str(n):>14}" for n in sizes)
    head += "".join(f"{'exp ' + str(a) + '>' + str(b):>14}" for a, b in zip(sizes, sizes[1:]))
    print(head)
    for s in rows:
        t = [cpu if s == "whole process" else st.get(s, 0.0) for st, cpu in runs]
        line = f"{s:24}" + "".join(f"{v:14.2f}" for v in t)
        line += "".join(f"{exponent(a, ta, b, tb):>14}" for a, b, ta, tb in zip(sizes, sizes[1:], t, t[1:]))
        print(line)
    sys.stdout.flush()


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = ap.add_subparsers(dest="what", required=True)
    d = sub.add_parser("densify")
    d.add_argument("cloud")
    d.add_argument("parcels")
    d.add_argument("dtm")
    d.add_argument("--factors", type=int, nargs="+", default=[1, 2, 4, 8])
    t = sub.add_parser("towns")
    t.add_argument("--sizes", type=int, nargs="+", default=[1000, 4000, 16000])
    g = sub.add_parser("pieces")
    g.add_argument("--grids", type=int, nargs="+", default=[0, 1, 2, 4])
    y = sub.add_parser("layer")
    y.add_argument("--sizes", type=int, nargs="+", default=[1000, 10000, 100000])
    for p in (d, t, g, y):
        p.add_argument("--c3d", default=DEFAULT_C3D)
    a = ap.parse_args()
    with tempfile.TemporaryDirectory() as work:
        runs = []
        if a.what == "densify":
            sizes = a.factors
            for k in sizes:
                cloud = os.path.join(work, f"x{k}.las")
                points = densify_las(a.cloud, cloud, k)
                runs.append(batch(a.c3d, cloud, a.parcels, a.dtm, os.path.join(work, f"out{k}")))
                os.remove(cloud)
                print(f"x{k}: {points} points, {runs[-1][1]:.1f} CPU s", file=sys.stderr)
            print_table("x", sizes, runs)
        elif a.what == "pieces":
            sizes = [max(1, 4 * k * k) for k in a.grids]
            for k, n in zip(a.grids, sizes):
                folder = os.path.join(work, f"pieces{n}")
                os.makedirs(folder)
                pieces_scene(folder, k)
                runs.append(batch(a.c3d, os.path.join(folder, "cloud.las"), os.path.join(folder, "parcels.gpkg"),
                                  os.path.join(folder, "dtm.tif"), os.path.join(work, f"out{n}")))
                print(f"{n} pieces: {runs[-1][1]:.1f} CPU s", file=sys.stderr)
            print_table("pieces", sizes, runs)
        elif a.what == "layer":
            sizes = a.sizes
            town = os.path.join(work, "town")
            subprocess.run([a.c3d, "sample", "--out", town, "--parcels", "24", "--seed", "1"],
                           check=True, capture_output=True)
            for n in sizes:
                parcels = os.path.join(work, f"layer{n}.gpkg")
                layer_with_lots(os.path.join(town, "parcels.gpkg"), parcels, n)
                runs.append(batch(a.c3d, os.path.join(town, "cloud.las"), parcels, os.path.join(town, "dtm.tif"),
                                  os.path.join(work, f"out{n}")))
                print(f"{n} parcels: {runs[-1][1]:.1f} CPU s", file=sys.stderr)
            print_table("n", sizes, runs)
        else:
            sizes = a.sizes
            for n in sizes:
                town = os.path.join(work, f"town{n}")
                subprocess.run([a.c3d, "sample", "--out", town, "--parcels", str(n), "--seed", "1"],
                               check=True, capture_output=True)
                runs.append(batch(a.c3d, os.path.join(town, "cloud.las"), os.path.join(town, "parcels.gpkg"),
                                  os.path.join(town, "dtm.tif"), os.path.join(work, f"out{n}")))
                print(f"{n} parcels: {runs[-1][1]:.1f} CPU s", file=sys.stderr)
            print_table("n", sizes, runs)


if __name__ == "__main__":
    main()
