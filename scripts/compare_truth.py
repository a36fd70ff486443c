#!/usr/bin/env python3
"""Compares a batch summary.json with the sample town's truth.json, per building.

Usage: compare_truth.py truth.json summary.json
Prints the relative error of every element area, volume and heights, and the
worst error per metric and layout. Buildings are matched per parcel by order.
"""
import json
import sys

METRICS = ["roof_area_m2", "roof_plan_area_m2", "wall_area_m2", "party_wall_area_m2",
           "ground_area_m2", "outer_ceiling_area_m2", "volume_m3"]


def main():
    truth = json.load(open(sys.argv[1]))
    summary = json.load(open(sys.argv[2]))
    worst = {}
    for tp, sp in zip(truth["parcels"], summary["parcels"]):
        tb, sb = tp["buildings"], sp["buildings"]
        if len(tb) != len(sb):
            print(f"{tp['parcel_id']} {tp['layout']}: {len(tb)} true buildings, {len(sb)} modelled ({sp['status']} {sp['reason']})")
            continue
        for t, s in zip(tb, sb):
            row = []
            for m in METRICS:
                tv, sv = t[m], s[m]
                err = (sv - tv) / tv * 100 if tv > 1e-6 else (0.0 if abs(sv) < 0.5 else float("inf"))
                row.append(f"{m.split('_m')[0][:10]}={sv:8.2f}/{tv:8.2f} ({err:+5.1f}%)")
                key = (tp["layout"], m)
                worst[key] = max(worst.get(key, 0), abs(err))
            print(tp["parcel_id"][-3:], tp["layout"][:11].ljust(11), "valid" if s["solid_valid"] else "INVALID", " ".join(row))
    print("\nworst |error| % per layout:")
    layouts = sorted({k[0] for k in worst})
    print("layout".ljust(12) + "".join(m.split("_m")[0][:10].rjust(12) for m in METRICS))
    for l in layouts:
        print(l.ljust(12) + "".join(f"{worst.get((l, m), 0):12.2f}" for m in METRICS))


if __name__ == "__main__":
    main()
