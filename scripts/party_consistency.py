#!/usr/bin/python3
"""Do neighbours agree on their party walls? Reads a batch's store and, for
every party wall, looks across the parcel boundary beside it: the neighbouring
parcel's model has a party wall there (both agree), an exterior wall (they
disagree), or no wall within 0.5 m (the neighbour's model stands back, or
has no building there); a party wall on a boundary with land outside the
layer has nobody to agree with. Each parcel decides its party walls from its
own scene, so this is a check across parcels no single model can make.

Usage: party_consistency.py OUT/cadastre.gpkg [--list]
Prints metres of party wall (plan length) per answer; --list adds the pairs
of parcels that disagree or have no wall across. Needs python3-gdal (set-up).
"""
import collections
import sys

import numpy as np
from osgeo import ogr

ogr.UseExceptions()
REACH = 0.5  # m: a wall this near in plan is the neighbour's side of the same wall
STEP = 0.25  # m: sampling along each party wall


def walls_in_plan(store):
    """(parcel_id, element_type, a, b) per wall element: its plan segment."""
    parcel_of = {}
    rows = store.ExecuteSQL("SELECT b.fid AS building, s.parcel_id AS parcel FROM building b "
                            "JOIN la_spatialunit s ON s.fid = b.spatialunit_id")
    for row in rows:
        parcel_of[row.GetFID()] = row.GetField("parcel")
    store.ReleaseResultSet(rows)
    walls = []
    layer = store.GetLayerByName("building_element")
    layer.SetAttributeFilter("element_type IN ('wall', 'party_wall')")
    for f in layer:
        geom = f.GetGeometryRef()
        for i in range(geom.GetGeometryCount()):  # each face: a vertical polygon, a segment in plan
            ring = geom.GetGeometryRef(i).GetGeometryRef(0)
            q = np.array([ring.GetPoint_2D(k) for k in range(ring.GetPointCount())])
            centre = q.mean(0)
            _, s, vt = np.linalg.svd(q - centre)
            if s[0] < 1e-6 or s[1] > 0.05 * s[0]:
                continue  # a sliver with no length in plan
            t = (q - centre) @ vt[0]
            walls.append((parcel_of[f.GetField("building_fid")], f.GetField("element_type"),
                          centre + t.min() * vt[0], centre + t.max() * vt[0]))
    return walls


def distance_to_segment(p, a, b):
    ab = b - a
    t = 0.0 if ab @ ab == 0 else np.clip((p - a) @ ab / (ab @ ab), 0, 1)
    return np.linalg.norm(p - (a + t * ab))


def main():
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    store = ogr.Open(sys.argv[1])
    parcels = {f.GetField("parcel_id"): f.GetGeometryRef().Clone() for f in store.GetLayerByName("la_spatialunit")}
    walls = walls_in_plan(store)
    totals, pairs = collections.Counter(), collections.Counter()
    for pid, kind, a, b in walls:
        if kind != "party_wall":
            continue
        length = np.linalg.norm(b - a)
        n = max(1, int(length / STEP))
        for k in range(n):
            p = a + (k + 0.5) / n * (b - a)
            point = ogr.Geometry(ogr.wkbPoint)
            point.AddPoint_2D(*p)
            across = {q for q, g in parcels.items() if q != pid and g.Distance(point) < REACH}
            if not across:
                totals["neighbour outside the layer"] += length / n
                continue
            near = [(distance_to_segment(p, c, e), k2, q) for q, k2, c, e in walls if q in across]
            d, other_kind, other = min(near, default=(np.inf, None, sorted(across)[0]))
            answer = {"party_wall": "party wall across (agree)", "wall": "exterior wall across (disagree)"}.get(
                other_kind, "") if d < REACH else "no wall across within 0.5 m"
            totals[answer] += length / n
            if not answer.endswith("(agree)"):
                pairs[(pid, other, answer)] += length / n
    for answer, metres in totals.most_common():
        print(f"{metres:8.1f} m  {answer}")
    if "--list" in sys.argv:
        for (pid, other, answer), metres in pairs.most_common():
            print(f"{metres:8.1f} m  {pid} -> {other}: {answer}")


if __name__ == "__main__":
    main()
