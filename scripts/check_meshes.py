#!/usr/bin/python3
"""A batch's mesh ladders (`batch --mesh`) judged by others: val3dity on every
level 1 (read as an OBJ solid), the Khronos glTF validator on every .glb,
and each file's SHA-256 against the store's `building_mesh_level`.

  check_meshes.py OUT [--shared ../shared]

Prints one line per check and a summary; exits 1 when any check fails.
"""
import argparse
import hashlib
import json
import os
import re
import sqlite3
import struct
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))


def ply_as_obj(ply, obj):
    """A binary PLY as the ladder writes it (float32 vertices, uchar + 3 int32 faces) as OBJ text."""
    with open(ply, "rb") as f:
        data = f.read()
    body = data.index(b"end_header\n") + 11
    header = data[:body].decode("ascii").split("\n")
    nv = next(int(h.split()[2]) for h in header if h.startswith("element vertex"))
    nf = next(int(h.split()[2]) for h in header if h.startswith("element face"))
    with open(obj, "w") as out:
        for i in range(nv):
            out.write("v %.6f %.6f %.6f\n" % struct.unpack_from("<3f", data, body + 12 * i))
        out.write("o hull\n")
        at = body + 12 * nv
        for i in range(nf):
            a, b, c = struct.unpack_from("<3i", data, at + 13 * i + 1)
            out.write(f"f {a + 1} {b + 1} {c + 1}\n")


def sha256(path):
    with open(path, "rb") as f:
        return hashlib.sha256(f.read()).hexdigest()


def main():
    a = argparse.ArgumentParser()
    a.add_argument("out")
    a.add_argument("--shared", default=os.path.join(HERE, "..", "..", "shared"))
    o = a.parse_args()
    db = sqlite3.connect(os.path.join(o.out, "cadastre.gpkg"))
    rows = db.execute("SELECT level, ply, ply_sha256, glb, glb_sha256 FROM building_mesh_level").fetchall()
    failed = []
    hashes = [(p, h) for _, ply, ph, glb, gh in rows for p, h in ((ply, ph), (glb, gh)) if p]
    wrong = [p for p, h in hashes if sha256(os.path.join(o.out, p)) != h]
    print(f"sha256: {len(hashes) - len(wrong)}/{len(hashes)} files as the store says {wrong[:3]}")
    failed += wrong

    val3dity = os.path.join(o.shared, "tools", "val3dity", "val3dity")
    hulls = [ply for level, ply, *_ in rows if level == 1]
    invalid = []
    with tempfile.TemporaryDirectory() as tmp:
        for ply in hulls:
            obj, report = os.path.join(tmp, "hull.obj"), os.path.join(tmp, "report.json")
            ply_as_obj(os.path.join(o.out, ply), obj)
            subprocess.run([val3dity, "--report", report, obj], capture_output=True)
            if not json.load(open(report)).get("validity"):
                invalid.append(ply)
    print(f"val3dity: {len(hulls) - len(invalid)}/{len(hulls)} level-1 hulls valid {invalid[:3]}")
    failed += invalid

    glbs = [os.path.join(o.out, glb) for _, _, _, glb, _ in rows if glb]
    judged, with_errors, warnings = 0, 0, 0
    for k in range(0, len(glbs), 200):
        r = subprocess.run(["node", os.path.join(HERE, "..", "tests", "js", "gltf_check.js"), *glbs[k:k + 200]],
                           capture_output=True, text=True)
        if r.returncode not in (0, 1):
            print(f"gltf-validator: {r.stderr.strip()}")
        for line in r.stdout.splitlines():
            m = re.match(r".*: (\d+) errors, (\d+) warnings", line)
            if m:
                judged += 1
                with_errors += int(m.group(1)) > 0
                warnings += int(m.group(2))
    print(f"gltf-validator: {judged - with_errors}/{len(glbs)} .glb files without errors ({warnings} warnings)")
    if with_errors or judged != len(glbs):
        failed.append("glb")
    sys.exit(1 if failed else 0)


if __name__ == "__main__":
    main()
