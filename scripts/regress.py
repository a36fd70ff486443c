#!/usr/bin/python3
"""The regression runs behind a model change, in one command.

  regress.py run OUT [--c3d build/cli/cadastre3d] [--quick]
  regress.py diff OLD/regress.json NEW/regress.json [--tolerance 0.01]

`run` batches the Cimahi data (../shared/data/cimahi) as it is, over other parcel
layouts (shifted, rotated, shrunk, grown, square grids), with its roof points
alone, and thinned to every k-th point; and sample towns against their truth.
For each batch it records every building's areas, volume and validity, the
pooled deviations and the roof plan area modelled by two parcels at once
(from the CityJSON export), and writes OUT/regress.json plus one line per run.
`--quick`: Cimahi as it is and roof-only, three layouts, two thinnings and
three towns.

`diff` lists what moved between two such files: buildings that appear, vanish
or change validity, areas or volumes off by more than the tolerance (m2, m3),
parcels whose status changes, and every changed summary figure.

Needs python3-gdal (a project dependency). Times on 2 cores: 2 min 20 s
(`--quick` 50 s).
"""
import argparse
import json
import math
import os
import struct
import subprocess
import sys

from osgeo import ogr, osr

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import compare_truth  # noqa: E402  (the sample towns' comparison)

CIMAHI = os.path.normpath(os.path.join(HERE, "..", "..", "shared", "data", "cimahi"))
AREAS = ["roof_area_m2", "wall_area_m2", "party_wall_area_m2", "ground_area_m2",
         "outer_ceiling_area_m2", "volume_m3"]
TOWN_SEEDS = list(range(1, 22))
ORDINAL = {2: "2nd", 3: "3rd", 4: "4th", 5: "5th"}


# ---- inputs ---------------------------------------------------------------

def thin_las(src, dst, keep):
    """Writes the points of src whose index i satisfies keep(i) to dst (same
    header and record format; point and per-return counts updated)."""
    data = open(src, "rb").read()
    off, reclen, fmt = struct.unpack("<I", data[96:100])[0], struct.unpack("<H", data[105:107])[0], data[104] & 0x3F
    legacy = struct.unpack("<I", data[107:111])[0]
    minor = data[25]
    n = legacy or struct.unpack("<Q", data[247:255])[0]
    end = off + n * reclen
    picked = bytearray()
    returns = [0] * 15
    mask = 0x0F if fmt >= 6 else 0x07
    for i in range(n):
        if keep(i):
            rec = data[off + i * reclen: off + (i + 1) * reclen]
            picked += rec
            r = rec[14] & mask
            if 1 <= r <= 15:
                returns[r - 1] += 1
    m = len(picked) // reclen
    head = bytearray(data[:off])
    if legacy:
        struct.pack_into("<I", head, 107, m)
        struct.pack_into("<5I", head, 111, *returns[:5])
    if minor >= 4:
        struct.pack_into("<Q", head, 247, m)
        struct.pack_into("<15Q", head, 255, *returns)
        evlr = struct.unpack("<Q", data[235:243])[0]
        if evlr:
            struct.pack_into("<Q", head, 235, evlr - (end - off - len(picked)))
    open(dst, "wb").write(bytes(head) + bytes(picked) + data[end:])


def read_layer(path):
    ds = ogr.Open(path)
    layer = ds.GetLayer(0)
    return [(f.GetField("NIB") or str(f.GetFID()), f.GetGeometryRef().Clone()) for f in layer]


def write_layer(path, parcels, epsg=32748):
    drv = ogr.GetDriverByName("GeoJSON")
    if os.path.exists(path):
        drv.DeleteDataSource(path)
    srs = osr.SpatialReference()
    srs.ImportFromEPSG(epsg)
    ds = drv.CreateDataSource(path)
    layer = ds.CreateLayer("parcels", srs, ogr.wkbPolygon)
    layer.CreateField(ogr.FieldDefn("NIB", ogr.OFTString))
    for pid, geom in parcels:
        f = ogr.Feature(layer.GetLayerDefn())
        f.SetField("NIB", pid)
        f.SetGeometry(geom)
        layer.CreateFeature(f)
    ds = None
    return path


def extent(parcels):
    """(min x, max x, min y, max y) of the layer."""
    envs = [g.GetEnvelope() for _, g in parcels]
    return (min(e[0] for e in envs), max(e[1] for e in envs), min(e[2] for e in envs), max(e[3] for e in envs))


def moved(parcels, dx=0.0, dy=0.0, degrees=0.0):
    """The parcels shifted by (dx, dy) and turned about the layer's centre."""
    env = extent(parcels)
    cx, cy = (env[0] + env[1]) / 2, (env[2] + env[3]) / 2
    c, s = math.cos(math.radians(degrees)), math.sin(math.radians(degrees))
    out = []
    for pid, g in parcels:
        ring = g.GetGeometryRef(0)
        r = ogr.Geometry(ogr.wkbLinearRing)
        for i in range(ring.GetPointCount()):
            x, y = ring.GetX(i) - cx, ring.GetY(i) - cy
            r.AddPoint_2D(cx + c * x - s * y + dx, cy + s * x + c * y + dy)
        p = ogr.Geometry(ogr.wkbPolygon)
        p.AddGeometry(r)
        out.append((pid, p))
    return out


def buffered(parcels, distance):
    out = []
    for pid, g in parcels:
        b = g.Buffer(distance, 30)
        if b.GetGeometryType() == ogr.wkbMultiPolygon:  # shrunk apart: its largest part
            b = max((b.GetGeometryRef(i).Clone() for i in range(b.GetGeometryCount())), key=lambda q: q.GetArea())
        if not b.IsEmpty():
            out.append((pid, b))
    return out


def grid(parcels, cell):
    """Square parcels of `cell` m over the layer's extent, blind to the houses."""
    env = extent(parcels)
    out = []
    j = 0
    while env[2] + j * cell < env[3]:
        i = 0
        while env[0] + i * cell < env[1]:
            x, y = env[0] + i * cell, env[2] + j * cell
            out.append((f"g{i}_{j}", ogr.CreateGeometryFromWkt(
                f"POLYGON (({x} {y},{x + cell} {y},{x + cell} {y + cell},{x} {y + cell},{x} {y}))")))
            i += 1
        j += 1
    return out


# ---- one batch and what it gives ----------------------------------------------

def roof_overlap(cityjson):
    """Plan area of roof modelled by two parcels at once (m2), from the export."""
    doc = json.load(open(cityjson))
    sc, tr = doc["transform"]["scale"], doc["transform"]["translate"]
    verts = [(v[0] * sc[0] + tr[0], v[1] * sc[1] + tr[1]) for v in doc["vertices"]]
    objs = doc["CityObjects"]
    plan = {}
    for oid, o in objs.items():
        owner = o if not o.get("parents") else objs[o["parents"][0]]
        pid = owner.get("attributes", {}).get("parcel_id", oid)
        geoms = o.get("geometry", [])
        top = max((float(g["lod"]) for g in geoms), default=0)
        for g in geoms:  # the primary LoD: the solid's roof and the overhangs beside it
            if float(g["lod"]) != top or g["type"] not in ("MultiSurface", "Solid") or "semantics" not in g:
                continue
            solid = g["type"] == "Solid"
            bounds = g["boundaries"][0] if solid else g["boundaries"]
            values = g["semantics"]["values"][0] if solid else g["semantics"]["values"]
            kinds = [g["semantics"]["surfaces"][v]["type"] if v is not None else "" for v in values]
            for surface, kind in zip(bounds, kinds):
                if kind != "RoofSurface":
                    continue
                poly = ogr.Geometry(ogr.wkbPolygon)
                for ring in surface:
                    r = ogr.Geometry(ogr.wkbLinearRing)
                    for k in ring + ring[:1]:
                        r.AddPoint_2D(*verts[k])
                    poly.AddGeometry(r)
                if poly.GetArea() > 1e-9:
                    plan[pid] = poly.Buffer(0) if pid not in plan else plan[pid].Union(poly.Buffer(0))
    ids, total = sorted(plan), 0.0
    for a in range(len(ids)):
        for b in range(a + 1, len(ids)):
            if plan[ids[a]].Intersects(plan[ids[b]]):
                total += surface_area(plan[ids[a]].Intersection(plan[ids[b]]))
    return total


def surface_area(geom):
    """Area of the polygons in an overlay result (touching edges give lines)."""
    kind = ogr.GT_Flatten(geom.GetGeometryType())
    if kind in (ogr.wkbPolygon, ogr.wkbMultiPolygon):
        return geom.GetArea()
    if kind == ogr.wkbGeometryCollection:
        return sum(surface_area(geom.GetGeometryRef(i)) for i in range(geom.GetGeometryCount()))
    return 0.0


def batch(c3d, out, cloud, parcels, dtm, walls=None):
    cmd = [c3d, "batch", "--quiet", "--cloud", cloud, "--parcels", parcels, "--out", out, "--formats", "cityjson"]
    if dtm:
        cmd += ["--dtm", dtm]
    if walls:
        cmd += ["--walls", walls]
    rc = subprocess.run(cmd, capture_output=True, text=True)
    if rc.returncode not in (0, 3):
        return {"error": (rc.stderr or rc.stdout).strip()[-400:]}
    s = json.load(open(os.path.join(out, "summary.json")))
    buildings = {b["building_id"]: {**{k: b[k] for k in AREAS}, "valid": b["solid_valid"]}
                 for p in s["parcels"] for b in p["buildings"]}
    return {
        "buildings": buildings,
        "failed": s["parcels_failed"],
        "statuses": {p["parcel_id"]: p["status"] for p in s["parcels"]},
        "invalid": sum(not b["valid"] for b in buildings.values()),
        "roof_std": round(s["pooled_roof_deviation"]["std"], 4),
        "wall_std": round(s["pooled_wall_deviation"]["std"], 4),
        "roof_overlap_m2": round(roof_overlap(os.path.join(out, "buildings.city.json")), 3),
    }


def run(a):
    os.makedirs(a.out, exist_ok=True)
    results = {}

    def record(name, r):
        results[name] = r
        if "error" in r:
            print(f"{name:28s} ERROR {r['error']}")
        else:
            extra = f"  worst {r['worst']}" if "worst" in r else ""
            suspect = sum(v == "suspect" for v in r["statuses"].values())
            print(f"{name:28s} {len(r['buildings']):4d} buildings, {r['invalid']} invalid, {r['failed']} failed, "
                  f"{suspect} suspect, "
                  f"roof std {r['roof_std']:.3f}, wall std {r['wall_std']:.3f}, "
                  f"roof overlap {r['roof_overlap_m2']:.2f} m2{extra}", flush=True)

    work = os.path.join(a.out, "work")
    os.makedirs(work, exist_ok=True)
    if os.path.isdir(CIMAHI):
        las, dtm, shp = (os.path.join(CIMAHI, f) for f in ("cimahi.las", "dtm.tif", "parcels.shp"))
        parcels = read_layer(shp)
        record("cimahi", batch(a.c3d, os.path.join(work, "cimahi"), las, shp, dtm))
        record("cimahi roof only", batch(a.c3d, os.path.join(work, "roofonly"), os.path.join(CIMAHI, "roof.ply"),
                                         shp, dtm))
        layouts = {
            "shift 1.8 E": moved(parcels, dx=1.8), "shift 1.5 E 1 S": moved(parcels, 1.5, -1.0),
            "rotate +7": moved(parcels, degrees=7), "rotate -4": moved(parcels, degrees=-4),
            "shrink 1 m": buffered(parcels, -1.0), "grow 0.7 m": buffered(parcels, 0.7),
            "grid 12 m": grid(parcels, 12), "grid 18 m": grid(parcels, 18), "grid 25 m": grid(parcels, 25),
        }
        if a.quick:
            layouts = {k: layouts[k] for k in ("rotate +7", "grow 0.7 m", "grid 12 m")}
        for name, layer in layouts.items():
            tag = name.replace(" ", "_").replace(".", "")
            path = write_layer(os.path.join(work, tag + ".geojson"), layer)
            record("layout " + name, batch(a.c3d, os.path.join(work, tag), las, path, dtm))
        every = [(2, 0), (3, 1), (4, 2), (5, 0), (5, 3)] if not a.quick else [(2, 0), (5, 3)]
        for k, j in every:
            thin = os.path.join(work, f"every{k}_{j}.las")
            thin_las(las, thin, lambda i, k=k, j=j: i % k == j)
            record(f"every {ORDINAL[k]} point from {j}",
                   batch(a.c3d, os.path.join(work, f"every{k}_{j}"), thin, shp, dtm))
    else:
        print(f"regress: {CIMAHI} not found; Cimahi runs skipped", file=sys.stderr)

    for seed in (TOWN_SEEDS if not a.quick else [1, 5, 11]):
        town = os.path.join(work, f"town{seed}")
        subprocess.run([a.c3d, "sample", "--out", town, "--seed", str(seed)], check=True, capture_output=True)
        r = batch(a.c3d, os.path.join(work, f"town{seed}_out"), os.path.join(town, "cloud.las"),
                  os.path.join(town, "parcels.gpkg"), os.path.join(town, "dtm.tif"))
        if "error" not in r:
            r["worst"] = worst_errors(os.path.join(town, "truth.json"),
                                      os.path.join(work, f"town{seed}_out", "summary.json"))
        record(f"town {seed}", r)

    with open(os.path.join(a.out, "regress.json"), "w") as f:
        json.dump(results, f, indent=1, sort_keys=True)
    print(f"regress: {os.path.join(a.out, 'regress.json')}")


def worst_errors(truth_path, summary_path):
    """Largest |relative error| % per metric over the town's buildings."""
    truth, summary = json.load(open(truth_path)), json.load(open(summary_path))
    worst = {}
    for tp, sp in zip(truth["parcels"], summary["parcels"]):
        if len(tp["buildings"]) != len(sp["buildings"]):
            worst["unmatched"] = worst.get("unmatched", 0) + 1
            continue
        for t, s in zip(tp["buildings"], sp["buildings"]):
            for m in compare_truth.METRICS:
                worst[m] = round(max(worst.get(m, 0.0), abs(compare_truth.relative_error(t[m], s[m]))), 2)
    return worst


# ---- diff -------------------------------------------------------------------

def diff(a):
    old, new = json.load(open(a.old)), json.load(open(a.new))
    moved_any = False
    for name in sorted(set(old) | set(new)):
        o, n = old.get(name), new.get(name)
        lines = []
        if o is None or n is None or "error" in o or "error" in n:
            lines.append(f"only in {'new' if o is None else 'old'}" if o is None or n is None
                         else f"error: old {o.get('error', 'ok')} / new {n.get('error', 'ok')}")
        else:
            for key in ("failed", "invalid", "roof_std", "wall_std", "roof_overlap_m2", "worst"):
                if o.get(key) != n.get(key):
                    lines.append(f"{key}: {o.get(key)} -> {n.get(key)}")
            ob, nb = o["buildings"], n["buildings"]
            for bid in sorted(set(ob) | set(nb)):
                if bid not in ob or bid not in nb:
                    lines.append(f"{bid}: {'new' if bid not in ob else 'gone'}")
                    continue
                changes = [f"{k.replace('_m2', '').replace('_m3', '')} {ob[bid][k]:.2f} -> {nb[bid][k]:.2f}"
                           for k in AREAS if abs(ob[bid][k] - nb[bid][k]) > a.tolerance]
                if ob[bid]["valid"] != nb[bid]["valid"]:
                    changes.append(f"valid {ob[bid]['valid']} -> {nb[bid]['valid']}")
                if changes:
                    lines.append(f"{bid}: " + ", ".join(changes))
            os_, ns = o.get("statuses", {}), n.get("statuses", {})  # files from before statuses have none
            for pid in sorted(set(os_) & set(ns)):
                if os_[pid] != ns[pid]:
                    lines.append(f"parcel {pid}: {os_[pid]} -> {ns[pid]}")
        if lines:
            moved_any = True
            print(name)
            for line in lines:
                print("  " + line)
    if not moved_any:
        print("regress: nothing moved")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    sub = ap.add_subparsers(dest="command", required=True)
    r = sub.add_parser("run", help="run every regression batch into OUT")
    r.add_argument("out")
    r.add_argument("--c3d", default=os.path.join(HERE, "..", "build", "cli", "cadastre3d"))
    r.add_argument("--quick", action="store_true", help="Cimahi, three layouts, two thinnings, three towns")
    d = sub.add_parser("diff", help="what moved between two regress.json files")
    d.add_argument("old")
    d.add_argument("new")
    d.add_argument("--tolerance", type=float, default=0.01, help="m2 / m3")
    a = ap.parse_args()
    run(a) if a.command == "run" else diff(a)


if __name__ == "__main__":
    main()
