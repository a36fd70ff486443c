#!/usr/bin/env python3
"""Compares batch summaries with the sample town's truth, per building.

Usage: compare_truth.py [--density 40] [--noise 0.03] [--quiet]
                        truth.json summary.json [truth.json summary.json ...]
Prints the relative error of every element area and the volume per building
(unless --quiet), the worst error per metric and layout over all pairs given,
how well each area's sigma describes its error, and the outer ceiling against
the least error any method could reach from the roof points (--density and
--noise: those the town was generated with). Buildings are matched per parcel
by order.
"""
import argparse
import json
import math

METRICS = ["roof_area_m2", "roof_plan_area_m2", "wall_area_m2", "party_wall_area_m2",
           "ground_area_m2", "outer_ceiling_area_m2", "volume_m3"]
SIGMA_METRICS = ["roof_area_m2", "wall_area_m2", "party_wall_area_m2", "ground_area_m2",
                 "outer_ceiling_area_m2"]
FISHER = 0.90  # integral of phi^2 / Phi: information on an edge per point and noise sigma


def ring_edges(ring):
    return [(ring[i], ring[(i + 1) % len(ring)]) for i in range(len(ring))]


def same_edge(e, f, tol=0.01):
    return ((math.dist(e[0], f[0]) < tol and math.dist(e[1], f[1]) < tol) or
            (math.dist(e[0], f[1]) < tol and math.dist(e[1], f[0]) < tol))


def eave_length(building, footprints):
    """Length of the roof outline edges the roof points place (not on a party
    wall) for a rectilinear footprint with one overhang o: each free footprint
    edge runs on by o at a convex corner with another free edge and stops o short
    at a concave one; at a party wall the roof ends on the wall line."""
    ring = [p[:2] for p in building["footprint"]]
    o = building["overhang_m"]
    shared = [f for other in building["attached_to"] for f in ring_edges(footprints.get(other, []))]
    edges = ring_edges(ring)
    free = [not any(same_edge(e, f) for f in shared) for e in edges]
    ccw = sum(a[0] * b[1] - b[0] * a[1] for a, b in edges) > 0
    n, total = len(edges), 0.0
    for i, (a, b) in enumerate(edges):
        if not free[i]:
            continue
        length = math.dist(a, b)
        for j, corner in ((i - 1, a), (i + 1, b)):
            if not free[j % n]:
                continue
            p, q = edges[j % n]
            u = (b[0] - a[0], b[1] - a[1]) if j > i else (q[0] - p[0], q[1] - p[1])
            v = (q[0] - p[0], q[1] - p[1]) if j > i else (b[0] - a[0], b[1] - a[1])
            convex = (u[0] * v[1] - u[1] * v[0] > 0) == ccw
            length += o if convex else -o
        total += length
    return total


def relative_error(true, modelled):
    """Error in % of the truth; a truth of zero is 0 % while the model stays
    under half a square metre, else infinite."""
    if true > 1e-6:
        return (modelled - true) / true * 100
    return 0.0 if abs(modelled) < 0.5 else float("inf")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--density", type=float, default=40.0, help="roof points per m2 of the town")
    ap.add_argument("--noise", type=float, default=0.03, help="roof point noise sigma of the town, m")
    ap.add_argument("--quiet", action="store_true", help="only the summaries")
    ap.add_argument("files", nargs="+", help="truth.json summary.json pairs")
    a = ap.parse_args()
    if len(a.files) % 2:
        ap.error("give truth.json and summary.json in pairs")
    worst, z = {}, {m: [] for m in SIGMA_METRICS}
    ceilings = []  # (error m2, true m2, bound m2)
    for k in range(0, len(a.files), 2):
        truth, summary = json.load(open(a.files[k])), json.load(open(a.files[k + 1]))
        footprints = {b["building_id"]: [p[:2] for p in b["footprint"]]
                      for tp in truth["parcels"] for b in tp["buildings"]}
        for tp, sp in zip(truth["parcels"], summary["parcels"]):
            tb, sb = tp["buildings"], sp["buildings"]
            if len(tb) != len(sb):
                print(f"{tp['parcel_id']} {tp['layout']}: {len(tb)} true buildings, {len(sb)} modelled "
                      f"({sp['status']} {sp['reason']})")
                continue
            for t, s in zip(tb, sb):
                row = []
                for m in METRICS:
                    tv, sv = t[m], s[m]
                    err = relative_error(tv, sv)
                    row.append(f"{m.split('_m')[0][:10]}={sv:8.2f}/{tv:8.2f} ({err:+5.1f}%)")
                    key = (tp["layout"], m)
                    worst[key] = max(worst.get(key, 0), abs(err))
                for m in SIGMA_METRICS:
                    sigma = s.get("sigma", {}).get(m, 0)
                    if t[m] > 1e-6 and sigma > 0:
                        z[m].append((s[m] - t[m]) / sigma)
                if t["outer_ceiling_area_m2"] > 1e-6:
                    bound = math.sqrt(eave_length(t, footprints) * a.noise / (FISHER * a.density))
                    ceilings.append((s["outer_ceiling_area_m2"] - t["outer_ceiling_area_m2"],
                                     t["outer_ceiling_area_m2"], bound))
                if not a.quiet:
                    print(tp["parcel_id"][-3:], tp["layout"][:11].ljust(11),
                          "valid" if s["solid_valid"] else "INVALID", " ".join(row))

    print("\nworst |error| % per layout:")
    layouts = sorted({k[0] for k in worst})
    print("layout".ljust(12) + "".join(m.split("_m")[0][:10].rjust(12) for m in METRICS))
    for lay in layouts:
        print(lay.ljust(12) + "".join(f"{worst.get((lay, m), 0):12.2f}" for m in METRICS))

    print("\nsigma of each area against its error (a calibrated sigma: rms 1, 68 % within 1 sigma):")
    for m, v in z.items():
        if v:
            rms = math.sqrt(sum(x * x for x in v) / len(v))
            within = sum(abs(x) <= 1 for x in v) / len(v) * 100
            print(f"  {m:24s} n {len(v):4d}  rms(error/sigma) {rms:5.2f}  within 1 sigma {within:5.1f} %")

    if ceilings:
        over = sum(abs(e) > 0.02 * c for e, c, _ in ceilings)
        expected = sum(math.erfc(0.02 * c / b / math.sqrt(2)) for _, c, b in ceilings)
        ratio = math.sqrt(sum((e / b) ** 2 for e, _, b in ceilings) / len(ceilings))
        print(f"\nouter ceiling: {over} of {len(ceilings)} buildings off by more than 2 %; error / "
              f"information bound: rms {ratio:.2f}")
        print(f"  the bound: each roof edge placed from points at {a.density:g}/m2 blurred by "
              f"{a.noise:g} m has sigma^2 >= noise / ({FISHER} density length) (Cramer-Rao), so the "
              f"area sigma >= sqrt(eave length x noise / ({FISHER} density));")
        print(f"  an estimator at the bound would leave {expected:.1f} buildings beyond 2 % "
              f"(chance that none is: {math.exp(-expected) * 100:.1f} %)")


if __name__ == "__main__":
    main()
