#!/usr/bin/python3
"""Checks a batch's outputs the way their users' tools read them (issue 36).

    scripts/check_outputs.py OUT [--c3d build/cli/cadastre3d] [--shared ../shared] [--json F]

OUT is a batch output folder (cadastre.gpkg and the exports beside it; run
`cadastre3d export --store OUT/cadastre.gpkg --out OUT` first for formats the
batch did not write). For each export present:
  - the area of every element type summed over the file's geometry (as a GIS
    or BIM user sums it: by semantic class, never by our attributes) equals the
    store's element total within 0.5 %;
  - CityJSON / CityJSONSeq: val3dity finds every building valid, and
    `cadastre3d validate` agrees with it building by building;
  - GeoPackage: every 2D geometry is valid by GEOS (OGR IsValid);
  - report.html prints to PDF in headless Chromium.
Prints one line per check and exits 1 when any fails.
"""
import argparse
import json
import os
import re
import sqlite3
import subprocess
import sys
import tempfile

TYPES = ["roof", "wall", "party_wall", "ground", "outer_ceiling"]
TOLERANCE = 0.005  # relative, the 0.5 %
FLOOR_M2 = 0.01    # absolute, for totals near zero


def polygon_area(rings):
    """Area of a planar 3D polygon (outer ring, then holes) by Newell's normal."""
    def vector_area(ring):
        nx = ny = nz = 0.0
        for i, a in enumerate(ring):
            b = ring[(i + 1) % len(ring)]
            nx += (a[1] - b[1]) * (a[2] + b[2])
            ny += (a[2] - b[2]) * (a[0] + b[0])
            nz += (a[0] - b[0]) * (a[1] + b[1])
        return (nx * 0.5, ny * 0.5, nz * 0.5)
    outer = vector_area(rings[0])
    norm = sum(c * c for c in outer) ** 0.5
    if norm == 0:
        return 0.0
    unit = [c / norm for c in outer]
    area = norm
    for hole in rings[1:]:
        h = vector_area(hole)
        area -= abs(sum(u * c for u, c in zip(unit, h)))
    return area


def store_totals(gpkg):
    db = sqlite3.connect(gpkg)
    rows = db.execute("SELECT element_type, SUM(area) FROM building_element GROUP BY element_type").fetchall()
    lods = dict(db.execute("SELECT building_id, lod FROM building").fetchall())
    return {t: a for t, a in rows}, lods


def surface_type(semantic):
    t = semantic.get("type", "")
    party = semantic.get("is_party_wall") or semantic.get("isPartyWall") or \
        semantic.get("attributes", {}).get("is_party_wall")
    return {"RoofSurface": "roof", "GroundSurface": "ground", "OuterCeilingSurface": "outer_ceiling",
            "WallSurface": "party_wall" if party else "wall"}.get(t)


def same_lod(a, b):
    norm = {"2": "2.2", "1": "1.2"}
    return norm.get(str(a), str(a)) == norm.get(str(b), str(b))


def cityjson_geometry_sums(objects, vertices, scale, lods, sums):
    """Adds to sums each building's surfaces at its own (primary) LoD, parts included."""
    def verts(i):
        v = vertices[i]
        return (v[0] * scale[0], v[1] * scale[1], v[2] * scale[2])

    def surfaces(geom):
        b, sem = geom["boundaries"], geom.get("semantics")
        if geom["type"] == "MultiSurface" or geom["type"] == "CompositeSurface":
            return [(s, None if sem is None else sem["values"][i]) for i, s in enumerate(b)]
        if geom["type"] == "Solid":
            out = []
            for si, shell in enumerate(b):
                for i, s in enumerate(shell):
                    out.append((s, None if sem is None or sem["values"] is None else sem["values"][si][i]))
            return out
        return []

    for oid, obj in objects.items():
        building = oid if obj["type"] == "Building" else (obj.get("parents") or [None])[0]
        lod = lods.get(building)
        for geom in obj.get("geometry", []):
            if lod is None or not same_lod(geom.get("lod"), lod) or "semantics" not in geom:
                continue
            for rings, v in surfaces(geom):
                if v is None:
                    continue
                t = surface_type(geom["semantics"]["surfaces"][v])
                if t:
                    sums[t] = sums.get(t, 0.0) + polygon_area([[verts(i) for i in r] for r in rings])


def cityjson_sums(path, lods):
    doc = json.load(open(path))
    sums = {}
    cityjson_geometry_sums(doc["CityObjects"], doc["vertices"], doc["transform"]["scale"], lods, sums)
    return sums


def cityjsonseq_sums(path, lods):
    sums = {}
    with open(path) as f:
        header = json.loads(f.readline())
        scale = header["transform"]["scale"]
        for line in f:
            if line.strip():
                feat = json.loads(line)
                cityjson_geometry_sums(feat["CityObjects"], feat["vertices"], scale, lods, sums)
    return sums


def citygml_sums(path):
    from lxml import etree
    sums = {}
    kinds = {"RoofSurface": "roof", "GroundSurface": "ground", "OuterCeilingSurface": "outer_ceiling",
             "WallSurface": "wall"}
    for _, el in etree.iterparse(path, events=("end",)):
        local = etree.QName(el).localname
        if local not in kinds:
            continue
        t = kinds[local]
        for a in el.iter():  # CityGML 2.0: <gen:..Attribute name="..">; 3.0: a <gen:name> child
            if not etree.QName(a).localname.endswith("Attribute"):
                continue
            name = a.get("name") or "".join(a.find("{*}name").itertext() if a.find("{*}name") is not None else [])
            value = a.find("{*}value")
            if name == "isPartyWall" and value is not None and "true" in "".join(value.itertext()).lower():
                t = "party_wall"
        area = 0.0
        for poly in el.iter("{*}Polygon"):
            rings = []
            for ring in poly.iter("{*}LinearRing"):
                pos = ring.find("{*}posList")
                vals = [float(x) for x in pos.text.split()]
                pts = [tuple(vals[i:i + 3]) for i in range(0, len(vals), 3)]
                rings.append(pts[:-1] if pts[0] == pts[-1] else pts)
            if rings:
                area += polygon_area(rings)
        sums[t] = sums.get(t, 0.0) + area
        el.clear()
    return sums


def obj_sums(folder):
    sums = {}
    group = re.compile(r"^g .*?_(roof|wall|party_wall|ground|outer_ceiling)_\d+$")
    for name in sorted(os.listdir(folder)):
        if not name.endswith(".obj"):
            continue
        verts, current = [], None
        for line in open(os.path.join(folder, name)):
            if line.startswith("v "):
                verts.append(tuple(float(x) for x in line.split()[1:4]))
            elif line.startswith("g "):
                m = group.match(line.strip())
                current = m.group(1) if m else None
            elif line.startswith("f ") and current:
                idx = [int(x.split("/")[0]) for x in line.split()[1:]]
                pts = [verts[i - 1] if i > 0 else verts[i] for i in idx]
                sums[current] = sums.get(current, 0.0) + polygon_area([pts])
    return sums


def ifc_sums(path, gpkg, repo):
    script = os.path.join(repo, "tests", "js", "ifc_check.js")
    out = subprocess.run(["node", script, path], capture_output=True, text=True, cwd=os.path.dirname(script))
    if out.returncode != 0:
        raise RuntimeError("web-ifc: " + out.stderr.strip()[-300:])
    db = sqlite3.connect(gpkg)
    kind = {}
    for bid, idx, t in db.execute("SELECT b.building_id, e.element_index, e.element_type FROM building_element e "
                                  "JOIN building b ON b.fid = e.building_fid"):
        kind[f"{bid}/e{idx}"] = t
    sums = {}
    for e in json.loads(out.stdout)["elements"]:
        t = kind.get(e["tag"])
        if t:
            sums[t] = sums.get(t, 0.0) + e["mesh_area"]
    return sums


def compare(name, sums, store):
    ok = True
    parts = []
    for t in TYPES:
        want, got = store.get(t, 0.0), sums.get(t, 0.0)
        good = abs(got - want) <= max(TOLERANCE * abs(want), FLOOR_M2)
        ok &= good
        parts.append(f"{t} {got:.2f}/{want:.2f}{'' if good else ' !'}")
    return ok, f"{name}: sum over the file / store (m2): " + ", ".join(parts)


def cityjson_of_seq(path, out):
    """The CityJSONSeq's features gathered into one CityJSON file (val3dity
    2.6.0 reading a sequence from stdin writes no report and crashes)."""
    with open(path) as f:
        doc = json.loads(f.readline())
        doc.setdefault("CityObjects", {})
        doc.setdefault("vertices", [])
        for line in f:
            if not line.strip():
                continue
            feat = json.loads(line)
            offset = len(doc["vertices"])
            shift = lambda b: [shift(x) for x in b] if isinstance(b, list) else b + offset
            for oid, obj in feat["CityObjects"].items():
                for g in obj.get("geometry", []):
                    g["boundaries"] = shift(g["boundaries"])
                doc["CityObjects"][oid] = obj
            doc["vertices"].extend(feat["vertices"])
    json.dump(doc, open(out, "w"))


def val3dity_verdicts(val3dity, path):
    with tempfile.TemporaryDirectory() as tmp:
        report = os.path.join(tmp, "r.json")
        if path.endswith(".jsonl"):
            cityjson_of_seq(path, os.path.join(tmp, "seq.city.json"))
            path = os.path.join(tmp, "seq.city.json")
        subprocess.run([val3dity, "--report", report, path], capture_output=True)
        r = json.load(open(report))
    return {f["id"]: bool(f["validity"]) for f in r.get("features", [])}


def validate_verdicts(c3d, path, ids):
    out = subprocess.run([c3d, "validate", path], capture_output=True, text=True)
    text = out.stdout + out.stderr
    return {i: re.search(r"\b" + re.escape(i) + r"\b", text) is None for i in ids}


def gpkg_2d_validity(gpkg):
    from osgeo import ogr
    ogr.UseExceptions()
    ds = ogr.Open(gpkg)
    bad, checked = [], 0
    for i in range(ds.GetLayerCount()):
        layer = ds.GetLayerByIndex(i)
        gt = layer.GetGeomType()
        if gt == ogr.wkbNone or ogr.GT_HasZ(gt):
            continue
        for feat in layer:
            g = feat.GetGeometryRef()
            if g is None:
                continue
            checked += 1
            if not g.IsValid():
                bad.append(f"{layer.GetName()}:{feat.GetFID()}")
    return checked, bad


def report_prints(html):
    with tempfile.TemporaryDirectory() as tmp:
        pdf = os.path.join(tmp, "r.pdf")
        subprocess.run(["chromium", "--headless", "--no-sandbox", "--disable-gpu", f"--print-to-pdf={pdf}",
                        "file://" + os.path.abspath(html)], capture_output=True, timeout=300)
        if not os.path.exists(pdf):
            return 0, 0
        data = open(pdf, "rb").read()
        return len(re.findall(rb"/Type\s*/Page[^s]", data)), len(data)


def main():
    here = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("out")
    ap.add_argument("--c3d", default=os.path.join(here, "build", "cli", "cadastre3d"))
    ap.add_argument("--shared", default=os.path.join(here, "..", "shared"))
    ap.add_argument("--json", help="write the results here")
    a = ap.parse_args()
    gpkg = os.path.join(a.out, "cadastre.gpkg")
    store, lods = store_totals(gpkg)
    results = []

    def check(ok, line):
        results.append({"ok": bool(ok), "check": line})
        print(("ok    " if ok else "FAIL  ") + line)

    f = lambda name: os.path.join(a.out, name)
    if os.path.exists(f("buildings.city.json")):
        check(*compare("CityJSON", cityjson_sums(f("buildings.city.json"), lods), store))
    if os.path.exists(f("buildings.city.jsonl")):
        check(*compare("CityJSONSeq", cityjsonseq_sums(f("buildings.city.jsonl"), lods), store))
    for gml in ("buildings.gml", "buildings.citygml3.gml"):
        if os.path.exists(f(gml)):
            check(*compare(gml, citygml_sums(f(gml)), store))
    if os.path.isdir(f("obj")):
        check(*compare("OBJ", obj_sums(f("obj")), store))
    if os.path.exists(f("buildings.ifc")):
        check(*compare("IFC (web-ifc meshes)", ifc_sums(f("buildings.ifc"), gpkg, here), store))

    val3dity = os.path.join(a.shared, "tools", "val3dity", "val3dity")
    for name in ("buildings.city.json", "buildings.city.jsonl"):
        if not os.path.exists(f(name)):
            continue
        if not os.path.exists(val3dity):
            print(f"skip  val3dity: {val3dity} is absent")
            break
        v = val3dity_verdicts(val3dity, f(name))
        invalid = sorted(i for i, good in v.items() if not good)
        check(v and not invalid, f"{name}: val3dity {len(v) - len(invalid)}/{len(v)} valid {invalid[:5]}")
        if name.endswith(".json"):
            ours = validate_verdicts(a.c3d, f(name), list(v))
            differ = sorted(i for i in v if v[i] != ours[i])
            check(not differ, f"{name}: cadastre3d validate agrees with val3dity on {len(v) - len(differ)}/{len(v)}"
                              f" buildings {differ[:5]}")

    checked, bad = gpkg_2d_validity(gpkg)
    check(not bad, f"GeoPackage: {checked - len(bad)}/{checked} 2D geometries valid by GEOS {bad[:5]}")
    if os.path.exists(f("report.html")):
        pages, size = report_prints(f("report.html"))
        check(pages > 0, f"report.html prints: {pages} PDF page(s), {size / 1e6:.1f} MB")
    if a.json:
        json.dump(results, open(a.json, "w"), indent=1)
    sys.exit(0 if all(r["ok"] for r in results) else 1)


if __name__ == "__main__":
    main()
