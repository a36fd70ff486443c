#!/usr/bin/python3
"""How each stage's CPU time grows with what it works on (issue 53): a stage
superlinear in its input shows as an exponent well above 1 (n log n over a
doubling gives about 1.1).

  bench_growth.py densify CLOUD.las PARCELS DTM [--factors 1 2 4 8] [--c3d BIN]
  bench_growth.py towns [--sizes 1000 4000 16000] [--c3d BIN]

`densify`: the one building (or few) of CLOUD, its points repeated k times,
each copy after the first moved by a random offset within a quarter of the
point spacing in plan and 5 mm in height (seeded): the same roof, k times
the points. `towns`: sample towns of growing parcel counts (`sample
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


def batch(c3d, cloud, parcels, dtm, out):
    """Stages' CPU seconds and the whole process's user+sys of one batch."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    cmd = [c3d, "batch", "--quiet", "--jobs", "1", "--formats", "cityjson",
           "--cloud", cloud, "--parcels", parcels, "--out", out]
    if dtm:
        cmd += ["--dtm", dtm]
    r = subprocess.run(cmd, capture_output=True, text=True, env=dict(os.environ, OMP_NUM_THREADS="1"))
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if r.returncode != 0:
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
    for p in (d, t):
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
