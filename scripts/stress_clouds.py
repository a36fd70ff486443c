#!/usr/bin/python3
"""Stress clouds: the same buildings as data from other writers and scanners.

  stress_clouds.py make OUT [--c3d build/cli/cadastre3d]
  stress_clouds.py run OUT TAG [--c3d build/cli/cadastre3d] [--only v1,v2] [--data ahn3,town]
  stress_clouds.py table OUT TAG_BEFORE TAG_AFTER   (a tag may be TAG1,TAG2: runs merged)

`make` writes, from ../shared/data/ahn3/cloud.las (10 pts/m2, RD coordinates
~83500 / 442300) and from a sample town (`cadastre3d sample`, placed at the
same RD coordinates, 40 pts/m2), these variants of each cloud:

  orig      the cloud as it is
  float32   x, y, z stored as float32 (at RD 83000 / 442000: 7.8 mm / 31 mm steps)
  rows      y snapped onto 0.5 m scan rows (z moved along the local roof slope,
            so the points stay on the roof)
(rows, thin5 and dense change only the airborne classes 2 and 6: a sample
town's handheld wall points, class 64, stay as they are)
  stacked   every point 2-4 times, exact duplicates
  jitter    every point 2-4 times, duplicates within 1 mm
  german    float32 + rows + stacked: the German town of issue 34
  thin5     a random half (AHN3) / eighth (town): ~5 pts/m2
  dense     every point 10 times (AHN3) / 3 times (town), spread 0.1 m in plan
            along the local roof plane: ~100 pts/m2

`run` batches every variant with TAG's binary into OUT/runs/TAG/VARIANT, and
records parcels ok / empty / failed, buildings modelled, val3dity's verdict and
(AHN3) score_vs_city3d.py against the ORIGINAL cloud (every point of the
original measured to our model, so all variants share one ruler), (town) the
worst relative error against truth.json. Writes OUT/runs/TAG.json.
`table` prints a markdown table of two tags side by side.

Needs /usr/bin/python3 with numpy and scipy. Times on 2 cores: make 1 min,
run ~15 min (the dense AHN3 cloud is 2.7 M points).
"""
import argparse
import json
import os
import struct
import subprocess
import sys

import numpy as np
from scipy.spatial import cKDTree

HERE = os.path.dirname(os.path.abspath(__file__))
SHARED = os.path.normpath(os.path.join(HERE, "..", "..", "shared"))
AHN3 = os.path.join(SHARED, "data", "ahn3")
VAL3DITY = os.path.join(SHARED, "tools", "val3dity", "val3dity")
SCORER = os.path.join(SHARED, "tools", "score_vs_city3d.py")
sys.path.insert(0, HERE)
import compare_truth  # noqa: E402

VARIANTS = ["orig", "float32", "rows", "stacked", "jitter", "german", "thin5", "dense"]
ROW_STEP = 0.5      # m, the German town's scan rows
SEED = 34           # issue 34


# ---- LAS in and out (any point format: X Y Z are the first 12 bytes) ---------

def read_las(path):
    d = open(path, "rb").read()
    off, reclen, fmt = struct.unpack_from("<I", d, 96)[0], struct.unpack_from("<H", d, 105)[0], d[104] & 0x3F
    n = struct.unpack_from("<I", d, 107)[0]
    if d[25] >= 4 and n == 0:
        n = struct.unpack_from("<Q", d, 247)[0]
    scale = np.array(struct.unpack_from("<3d", d, 131))
    offset = np.array(struct.unpack_from("<3d", d, 155))
    rec = np.frombuffer(d, np.uint8, n * reclen, off).reshape(n, reclen).copy()
    xyz = rec[:, :12].copy().view("<i4").reshape(n, 3) * scale + offset
    return {"head": bytearray(d[:off]), "tail": d[off + n * reclen:], "rec": rec, "fmt": fmt,
            "scale": scale, "offset": offset, "xyz": xyz}


def write_las(las, path, xyz, take):
    """Writes records las["rec"][take] with coordinates xyz (one row per taken record)."""
    rec = las["rec"][take].copy()
    ints = np.round((xyz - las["offset"]) / las["scale"]).astype("<i4")
    rec[:, :12] = ints.view(np.uint8).reshape(len(rec), 12)
    head, n = bytearray(las["head"]), len(rec)
    mask = 0x0F if las["fmt"] >= 6 else 0x07
    returns = np.bincount(rec[:, 14] & mask, minlength=16)[1:16]
    if las["fmt"] < 6:  # formats 6-10 leave the legacy counts at 0
        struct.pack_into("<I", head, 107, n)
        struct.pack_into("<5I", head, 111, *[int(r) for r in returns[:5]])
    if head[25] >= 4:
        struct.pack_into("<Q", head, 247, n)
        struct.pack_into("<15Q", head, 255, *[int(r) for r in returns])
        evlr = struct.unpack_from("<Q", head, 235)[0]
        if evlr:
            struct.pack_into("<Q", head, 235, len(head) + rec.nbytes)
    real = ints * las["scale"] + las["offset"]
    struct.pack_into("<6d", head, 179, real[:, 0].max(), real[:, 0].min(), real[:, 1].max(), real[:, 1].min(),
                     real[:, 2].max(), real[:, 2].min())
    with open(path, "wb") as f:
        f.write(bytes(head) + rec.tobytes() + las["tail"])


# ---- the variants -------------------------------------------------------------

def slope_xy(xyz, k=12, planar_rms=0.05):
    """Per point dz/dx, dz/dy of the least-squares plane through its k nearest
    points in plan, and whether they lie on it within planar_rms (not at a
    roof's edge or ridge). Slope 0 where they do not fix a plane."""
    _, nn = cKDTree(xyz[:, :2]).query(xyz[:, :2], k=min(k, len(xyz)))
    q = xyz[nn] - xyz[nn].mean(axis=1, keepdims=True)
    a = np.einsum("nki,nkj->nij", q[:, :, :2], q[:, :, :2])
    b = np.einsum("nki,nk->ni", q[:, :, :2], q[:, :, 2])
    ok = np.linalg.det(a) > 1e-6
    g = np.zeros((len(xyz), 2))
    g[ok] = np.linalg.solve(a[ok], b[ok][:, :, None])[:, :, 0]
    res = q[:, :, 2] - np.einsum("nki,ni->nk", q[:, :, :2], g)
    planar = ok & (np.sqrt((res ** 2).mean(axis=1)) < planar_rms)
    return np.clip(g, -3.0, 3.0), planar  # no roof steeper than ~72 degrees moves a point further


def to_float32(xyz):
    return xyz.astype(np.float32).astype(np.float64)


def to_rows(xyz, air):
    """The airborne points snapped onto rows; the others (handheld walls) stay."""
    out = xyz.copy()
    g, _ = slope_xy(xyz[air])
    out[air, 1] = np.round(xyz[air, 1] / ROW_STEP) * ROW_STEP
    out[air, 2] += g[:, 1] * (out[air, 1] - xyz[air, 1])
    return out


def stack(n, rng):
    """Each index 2-4 times."""
    return np.repeat(np.arange(n), rng.integers(2, 5, n))


def spread(xyz, air, copies, sigma, rng):
    """The airborne points `copies` times, the copies spread along the local
    plane (within 1 cm where no plane holds: edges, ridges); the others once."""
    g, planar = np.zeros((len(xyz), 2)), np.zeros(len(xyz), bool)
    g[air], planar[air] = slope_xy(xyz[air])
    take = np.repeat(np.arange(len(xyz)), np.where(air, copies, 1))
    d = rng.normal(0, 1, (len(take), 2)) * np.where(planar[take], sigma, 0.01)[:, None]
    d[np.r_[True, take[1:] != take[:-1]]] = 0  # the original point stays
    out = xyz[take].copy()
    out[:, :2] += d
    out[:, 2] += (g[take] * d).sum(axis=1)
    return out, take


def airborne(las):
    """Points of the ground and building classes (a sample town's handheld wall
    points, class 64, are not an airborne scan's)."""
    cls = las["rec"][:, 16] if las["fmt"] >= 6 else las["rec"][:, 15] & 0x1F
    return (cls == 2) | (cls == 6)


def make_variants(src, outdir, thin_keep, dense_copies):
    las = read_las(src)
    xyz, n = las["xyz"], len(las["xyz"])
    rng = np.random.default_rng(SEED)
    os.makedirs(outdir, exist_ok=True)
    everything = np.arange(n)
    write_las(las, os.path.join(outdir, "orig.las"), xyz, everything)
    write_las(las, os.path.join(outdir, "float32.las"), to_float32(xyz), everything)
    air = airborne(las)
    rows = to_rows(xyz, air)
    write_las(las, os.path.join(outdir, "rows.las"), rows, everything)
    s = stack(n, rng)
    write_las(las, os.path.join(outdir, "stacked.las"), xyz[s], s)
    jit = xyz[s] + rng.integers(-1, 2, (len(s), 3)) * 0.001
    write_las(las, os.path.join(outdir, "jitter.las"), jit, s)
    write_las(las, os.path.join(outdir, "german.las"), to_float32(rows)[s], s)
    keep = np.flatnonzero(~air | (rng.random(n) < thin_keep))
    write_las(las, os.path.join(outdir, "thin5.las"), xyz[keep], keep)
    dense, take = spread(xyz, air, dense_copies, 0.1, rng)
    write_las(las, os.path.join(outdir, "dense.las"), dense, take)


def make(a):
    make_variants(os.path.join(AHN3, "cloud.las"), os.path.join(a.out, "ahn3"), 0.5, 10)
    town = os.path.join(a.out, "town_src")
    subprocess.run([a.c3d, "sample", "--out", town, "--seed", "3", "--epsg", "28992", "--easting", "85000",
                    "--northing", "445000"], check=True, capture_output=True)
    make_variants(os.path.join(town, "cloud.las"), os.path.join(a.out, "town"), 0.125, 3)
    print(f"stress: variants in {a.out}/ahn3 and {a.out}/town")


# ---- runs -----------------------------------------------------------------------

def val3dity(cityjson, report):
    subprocess.run([VAL3DITY, "--report", report, cityjson], capture_output=True)
    r = json.load(open(report))
    feats = r.get("features_overview", [])
    prims = {f.get("type"): f for f in feats}
    sol = [f for f in r.get("features", [])]
    valid = sum(1 for f in sol if f.get("validity"))
    return {"valid": bool(r.get("validity")), "features": len(sol), "features_valid": valid,
            "overview": prims}


def batch(c3d, cloud, parcels, dtm, out):
    cmd = [c3d, "batch", "--quiet", "--cloud", cloud, "--parcels", parcels, "--dtm", dtm, "--out", out,
           "--formats", "cityjson"]
    rc = subprocess.run(cmd, capture_output=True, text=True)
    if rc.returncode not in (0, 3):
        return {"error": (rc.stderr or rc.stdout).strip()[-300:]}
    s = json.load(open(os.path.join(out, "summary.json")))
    status = {}
    for p in s["parcels"]:
        status[p["status"]] = status.get(p["status"], 0) + 1
    return {"parcels": status, "buildings": sum(len(p["buildings"]) for p in s["parcels"]),
            "invalid_ours": sum(not b["solid_valid"] for p in s["parcels"] for b in p["buildings"])}


def run_one(a, data, variant):
    out = os.path.join(a.out, "runs", a.tag, f"{data}_{variant}")
    cloud = os.path.join(a.out, data, variant + ".las")
    if data == "ahn3":
        parcels, dtm = os.path.join(AHN3, "parcels.gpkg"), os.path.join(AHN3, "dtm.tif")
    else:
        parcels, dtm = (os.path.join(a.out, "town_src", f) for f in ("parcels.gpkg", "dtm.tif"))
    r = batch(a.c3d, cloud, parcels, dtm, out)
    if "error" in r:
        return r
    cj = os.path.join(out, "buildings.city.json")
    r["val3dity"] = val3dity(cj, os.path.join(out, "val3dity.json"))
    if data == "ahn3":
        s = json.loads(subprocess.run(["/usr/bin/python3", SCORER, AHN3, cj, "--json"], capture_output=True,
                                      text=True, check=True).stdout)
        r["score"] = {k: s["ours"][k] for k in ("modelled", "median", "rmse_within_1m", "share_gt_0.5m")}
        r["score"]["wins"] = s["wins"]
        r["not_modelled"] = s["not_modelled"]
    else:
        truth = json.load(open(os.path.join(a.out, "town_src", "truth.json")))
        summ = json.load(open(os.path.join(out, "summary.json")))
        worst = {}
        for tp, sp in zip(truth["parcels"], summ["parcels"]):
            if len(tp["buildings"]) != len(sp["buildings"]):
                worst["unmatched"] = worst.get("unmatched", 0) + 1
                continue
            for t, s in zip(tp["buildings"], sp["buildings"]):
                for m in compare_truth.METRICS:
                    e = abs(compare_truth.relative_error(t[m], s[m]))
                    worst[m] = round(max(worst.get(m, 0.0), e), 2)
        r["worst_pct"] = worst
    return r


def run(a):
    path = os.path.join(a.out, "runs", a.tag + ".json")
    results = json.load(open(path)) if os.path.exists(path) else {}
    only = a.only.split(",") if a.only else VARIANTS
    for data in a.data.split(","):
        for v in only:
            r = run_one(a, data, v)
            results[f"{data} {v}"] = r
            print(f"{data} {v}: {line(r)}", flush=True)
            json.dump(results, open(path, "w"), indent=1, sort_keys=True)


def line(r):
    if not r:
        return "-"
    if "error" in r:
        return "ERROR " + r["error"]
    p = r["parcels"]
    v = r["val3dity"]
    s = (f"ok {p.get('ok', 0)} empty {p.get('empty', 0)} failed {p.get('failed', 0)}, {r['buildings']} bldg, "
         f"val3dity {v['features_valid']}/{v['features']}")
    if "score" in r:
        sc = r["score"]
        s += (f", median {sc['median']:.3f} rmse<1m {sc['rmse_within_1m'] or float('nan'):.3f}"
              f" >0.5m {100 * sc['share_gt_0.5m']:.1f}%"
              f" wins {sc['wins']['ours']}")
    if "worst_pct" in r:
        w = r["worst_pct"]
        s += ", worst % " + " ".join(f"{k} {w[k]:.1f}" for k in sorted(w))
    return s


def table(a):
    def load(tags):  # several tags (comma-separated) as one run
        merged = {}
        for tag in tags.split(","):
            merged.update(json.load(open(os.path.join(a.out, "runs", tag + ".json"))))
        return merged
    before, after = load(a.before), load(a.after)
    print(f"| variant | {a.before} | {a.after} |\n|---|---|---|")
    for k in sorted(set(before) | set(after), key=lambda k: (k.split()[0], VARIANTS.index(k.split()[1]))):
        print(f"| {k} | {line(before.get(k))} | {line(after.get(k))} |")


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = ap.add_subparsers(dest="cmd", required=True)
    m = sub.add_parser("make")
    m.add_argument("out")
    m.add_argument("--c3d", default=os.path.join(HERE, "..", "build", "cli", "cadastre3d"))
    r = sub.add_parser("run")
    r.add_argument("out")
    r.add_argument("tag")
    r.add_argument("--c3d", default=os.path.join(HERE, "..", "build", "cli", "cadastre3d"))
    r.add_argument("--only", default="")
    r.add_argument("--data", default="ahn3,town")
    t = sub.add_parser("table")
    t.add_argument("out")
    t.add_argument("before")
    t.add_argument("after")
    a = ap.parse_args()
    {"make": make, "run": run, "table": table}[a.cmd](a)


if __name__ == "__main__":
    main()
