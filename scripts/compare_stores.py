#!/usr/bin/python3
"""Compare two Cadastre3D stores: a sharded run against an unsharded one, a
PostGIS store against a GeoPackage (docs/scale.md, "Sharding and Slurm").

    /usr/bin/python3 scripts/compare_stores.py A B [--tol 1e-6]

A and B: a GeoPackage path, PG:... or postgresql://... (read through OGR).
Equal when both hold the same parcels with the same statuses, the same
building elements with areas within --tol m², the same NJOP and tax within
--tol, and neither holds a parcel, building or element twice. Exit 0 when
equal, 1 with the differences listed, 2 when a store cannot be read.
"""
import argparse
import sys
from collections import Counter

from osgeo import gdal, ogr

gdal.UseExceptions()

ELEMENTS = ("SELECT su.parcel_id, b.building_id, e.element_index, e.element_type, e.area "
            "FROM building_element e JOIN building b ON e.building_fid = b.fid "
            "JOIN la_spatialunit su ON b.spatialunit_id = su.fid")
VALUES = ("SELECT u.parcel_id, v.njop, v.tax FROM vm_valuation v "
          "JOIN vm_valuationunit u ON v.valuationunit_id = u.fid")


def open_store(loc):
    name = "PG:" + loc if loc.startswith(("postgresql://", "postgres://")) else loc
    try:
        ds = ogr.Open(name)
    except RuntimeError as e:
        print(f"compare_stores: {loc}: {e}", file=sys.stderr)
        sys.exit(2)
    if ds is None:
        print(f"compare_stores: {loc}: cannot open", file=sys.stderr)
        sys.exit(2)
    return ds


def rows(ds, sql):
    lyr = ds.ExecuteSQL(sql)
    if lyr is None:
        return []
    defn = lyr.GetLayerDefn()
    out = [tuple(f.GetField(i) for i in range(defn.GetFieldCount())) for f in lyr]
    ds.ReleaseResultSet(lyr)
    return out


def read(loc):
    """Everything compared, keyed, with the keys held twice."""
    ds = open_store(loc)
    s = {"dupes": []}
    jobs = rows(ds, "SELECT parcel_id, status FROM parcel_job")
    units = rows(ds, "SELECT parcel_id FROM la_spatialunit")
    elems = rows(ds, ELEMENTS)
    vals = rows(ds, VALUES)
    buildings = rows(ds, "SELECT building_id FROM building")
    for what, keys in (("parcel_job", [j[0] for j in jobs]), ("la_spatialunit", [u[0] for u in units]),
                       ("building", [b[0] for b in buildings]), ("element", [e[:3] for e in elems]),
                       ("valuation", [v[0] for v in vals])):
        s["dupes"] += [f"{what} {k} x{n}" for k, n in Counter(keys).items() if n > 1]
    s["status"] = {p: st for p, st in jobs}
    s["elements"] = {(p, b, int(i)): (t, a) for p, b, i, t, a in elems}
    s["values"] = {p: (njop, tax) for p, njop, tax in vals}
    return s


def differ(x, y, tol):
    if x is None or y is None:
        return x is not y
    return abs(float(x) - float(y)) > tol


def compare(a, b, tol):
    out = [f"A holds {d} times" for d in a["dupes"]] + [f"B holds {d} times" for d in b["dupes"]]
    for name in ("status", "elements", "values"):
        ka, kb = set(a[name]), set(b[name])
        out += [f"{name}: {k} only in A" for k in sorted(ka - kb, key=str)]
        out += [f"{name}: {k} only in B" for k in sorted(kb - ka, key=str)]
        for k in sorted(ka & kb, key=str):
            va, vb = a[name][k], b[name][k]
            if name == "status" and va != vb:
                out.append(f"parcel {k}: status {va} / {vb}")
            if name == "elements" and (va[0] != vb[0] or differ(va[1], vb[1], tol)):
                out.append(f"element {k}: {va} / {vb}")
            if name == "values" and (differ(va[0], vb[0], tol) or differ(va[1], vb[1], tol)):
                out.append(f"parcel {k}: NJOP, tax {va} / {vb}")
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("a")
    ap.add_argument("b")
    ap.add_argument("--tol", type=float, default=1e-6, help="m² for areas, currency for NJOP and tax")
    args = ap.parse_args()
    a, b = read(args.a), read(args.b)
    diffs = compare(a, b, args.tol)
    print(f"A: {len(a['status'])} parcels, {len(a['elements'])} elements; "
          f"B: {len(b['status'])} parcels, {len(b['elements'])} elements")
    for d in diffs[:40]:
        print("  " + d)
    if len(diffs) > 40:
        print(f"  ... {len(diffs) - 40} more")
    print("equal" if not diffs else f"{len(diffs)} difference(s)")
    return 1 if diffs else 0


if __name__ == "__main__":
    sys.exit(main())
