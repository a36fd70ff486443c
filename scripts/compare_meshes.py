#!/usr/bin/python3
"""The mesh ladder's methods side by side, as seeds 002 and 003 compare them
(docs/meshes.md): the dense methods (advancing front, ball pivoting, screened
Poisson, alpha shapes) per level with the boundary-aware simplification, and
the simplifications (boundary-aware, plain Lindstrom-Turk, Garland-Heckbert,
vertex clustering) at equal face budgets on the default dense method.

  compare_meshes.py BINARY OUT batch ARGS...   a batch --mesh per variant
  compare_meshes.py BINARY OUT cloud FILE      cadastre3d mesh per variant

Prints a Markdown table per level: the medians over the buildings of faces,
cloud-to-mesh mean and p95, far share (holes), planar regions lost, their
largest extent change, and how far level 4's region borders (ridges, frames)
lie from the level; and the CPU seconds summed.
"""
import glob
import json
import os
import statistics
import subprocess
import sys

DENSE = [("front", "boundary"), ("pivot", "boundary"), ("poisson", "boundary"), ("alpha", "boundary")]
SIMPLIFY = [("front", "qem"), ("front", "garland"), ("front", "clustering")]


def run_variant(binary, out, mode, args, method, simplify):
    where = os.path.join(out, f"{method}-{simplify}")
    if mode == "batch":
        config = where + ".toml"
        shipped = open(os.path.join(os.path.dirname(__file__), "..", "config", "cadastre3d.toml")).read()
        with open(config, "w") as f:
            f.write(shipped.replace('ladder = false', 'ladder = true')
                    .replace('method = "front"', f'method = "{method}"')
                    .replace('simplify = "boundary"', f'simplify = "{simplify}"'))
        cmd = [binary, "batch", *args, "--out", where, "--config", config, "--quiet", "--jobs", "1"]
        ladders = os.path.join(where, "mesh", "*_ladder.json")
    else:
        cmd = [binary, "mesh", "--cloud", args[0], "--out", where, "--method", method, "--simplify", simplify]
        ladders = os.path.join(where, "*_ladder.json")
    # A batch whose parcels partly failed or are suspect exits 3: its other buildings count.
    done = subprocess.run(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    if done.returncode not in ((0, 3) if mode == "batch" else (0,)):
        sys.exit(f"compare_meshes: {' '.join(cmd)} exited {done.returncode}")
    return [json.load(open(p)) for p in sorted(glob.glob(ladders))]


def median(values):
    values = [v for v in values if v is not None]
    return statistics.median(values) if values else float("nan")


def level_row(name, ladders, k):
    levels = [l["levels"][k - 1] for l in ladders]
    change = [lv.get("planar_change", {}) for lv in levels]
    lost = [c["lost"] / c["regions"] for c in change if c.get("regions")]
    return (f"| {name} | {median([lv['faces'] for lv in levels]):.0f} "
            f"| {median([lv['cloud_to_mesh']['mean'] for lv in levels]):.4f} "
            f"| {median([lv['cloud_to_mesh']['p95'] for lv in levels]):.4f} "
            f"| {100 * median([lv['far_share'] for lv in levels]):.1f} % "
            + (f"| {100 * median(lost):.0f} % | {median([c['extent_change'] for c in change]):.3f} "
               f"| {median([c['border_shift']['mean'] for c in change]):.3f} / "
               f"{median([c['border_shift']['p95'] for c in change]):.3f} "
               if k in (2, 3) else "| | | ")
            + f"| {sum(lv['seconds'] for lv in levels):.1f} |")


def main():
    binary, out, mode, args = sys.argv[1], sys.argv[2], sys.argv[3], sys.argv[4:]
    os.makedirs(out, exist_ok=True)
    runs = {}
    for method, simplify in DENSE + SIMPLIFY:
        runs[(method, simplify)] = run_variant(binary, out, mode, args, method, simplify)
    n = len(runs[DENSE[0]])
    print(f"{n} buildings; medians over them, CPU seconds summed\n")
    head = ("| variant | faces | c2m mean (m) | c2m p95 (m) | far | planar regions lost "
            "| extent change (m) | borders' distance mean / p95 (m) | CPU s |\n|---|---|---|---|---|---|---|---|---|")
    for k in (4, 3, 2, 1):
        print(f"Level {k}\n\n{head}")
        variants = DENSE if k in (4, 1) else DENSE + SIMPLIFY
        for key in variants:
            print(level_row(f"{key[0]} + {key[1]}", runs[key], k))
        print()


if __name__ == "__main__":
    main()
