// Independent IFC read-back with web-ifc: prints JSON with, per IfcWall / IfcSlab /
// IfcCovering, its Tag, the number of meshes and triangles web-ifc made, the mesh
// area, its lowest point's height (placements applied) and the storey containing it
// (a roof slab: its IfcRoof's); the quantities of these elements and the single-value
// properties of these, of each IfcRoof (by Tag) and IfcBuilding (by Name), attached
// through IfcRelDefinesByProperties; per IfcBuilding its storeys (name, elevation).
// Usage: node ifc_check.js FILE.ifc
const fs = require('fs');
const WebIFC = require('web-ifc');

function triangleArea(v, a, b, c) {
  const ax = v[b * 6] - v[a * 6], ay = v[b * 6 + 1] - v[a * 6 + 1], az = v[b * 6 + 2] - v[a * 6 + 2];
  const bx = v[c * 6] - v[a * 6], by = v[c * 6 + 1] - v[a * 6 + 1], bz = v[c * 6 + 2] - v[a * 6 + 2];
  const x = ay * bz - az * by, y = az * bx - ax * bz, z = ax * by - ay * bx;
  return 0.5 * Math.sqrt(x * x + y * y + z * z);
}

async function main() {
  const api = new WebIFC.IfcAPI();
  await api.Init();
  const model = api.OpenModel(new Uint8Array(fs.readFileSync(process.argv[2])));
  const meshes = new Map();  // expressID -> {meshes, triangles, area}
  api.StreamAllMeshes(model, (mesh) => {
    const m = meshes.get(mesh.expressID) || { meshes: 0, triangles: 0, area: 0, min_z: Infinity };
    m.meshes += 1;
    for (let i = 0; i < mesh.geometries.size(); i++) {
      const placed = mesh.geometries.get(i);
      const g = api.GetGeometry(model, placed.geometryExpressID);
      const v = api.GetVertexArray(g.GetVertexData(), g.GetVertexDataSize());
      const idx = api.GetIndexArray(g.GetIndexData(), g.GetIndexDataSize());
      for (let t = 0; t < idx.length; t += 3) m.area += triangleArea(v, idx[t], idx[t + 1], idx[t + 2]);
      // web-ifc is y-up: the IFC height is the placed vertex's y (column-major matrix).
      const f = placed.flatTransformation;
      for (let k = 0; k < v.length; k += 6)
        m.min_z = Math.min(m.min_z, f[1] * v[k] + f[5] * v[k + 1] + f[9] * v[k + 2] + f[13]);
      m.triangles += idx.length / 3;
      g.delete();
    }
    meshes.set(mesh.expressID, m);
  });
  const out = { elements: [], quantities: [], properties: [], buildings: [] };
  const ids = (type) => { const v = api.GetLineIDsWithType(model, type), a = []; for (let i = 0; i < v.size(); i++) a.push(v.get(i)); return a; };
  // Containment: element or IfcRoof -> storey; storey -> building; roof slab -> IfcRoof.
  const storeyOf = new Map(), parentOf = new Map();
  for (const id of ids(WebIFC.IFCRELCONTAINEDINSPATIALSTRUCTURE)) {
    const rel = api.GetLine(model, id);
    for (const e of rel.RelatedElements) storeyOf.set(e.value, rel.RelatingStructure.value);
  }
  for (const id of ids(WebIFC.IFCRELAGGREGATES)) {
    const rel = api.GetLine(model, id);
    for (const o of rel.RelatedObjects) parentOf.set(o.value, rel.RelatingObject.value);
  }
  const storeyName = (id) => (id === undefined ? null : api.GetLine(model, id).Name.value);
  const types = { IFCWALL: WebIFC.IFCWALL, IFCSLAB: WebIFC.IFCSLAB, IFCCOVERING: WebIFC.IFCCOVERING };
  const tagOf = new Map();
  for (const [name, type] of Object.entries(types)) {
    for (const id of ids(type)) {
      const line = api.GetLine(model, id);
      const tag = line.Tag ? line.Tag.value : null;
      tagOf.set(id, tag);
      const m = meshes.get(id) || { meshes: 0, triangles: 0, area: 0, min_z: null };
      const storey = storeyOf.has(id) ? storeyOf.get(id) : storeyOf.get(parentOf.get(id));
      out.elements.push({ type: name, tag, meshes: m.meshes, triangles: m.triangles, mesh_area: m.area,
                          min_z: m.min_z, storey: storeyName(storey), storey_id: storey === undefined ? null : storey });
    }
  }
  const elementIds = new Set(tagOf.keys());  // quantities: of these only, as before
  for (const id of ids(WebIFC.IFCROOF)) tagOf.set(id, api.GetLine(model, id).Tag.value);
  for (const id of ids(WebIFC.IFCBUILDING)) {
    const name = api.GetLine(model, id).Name.value;
    tagOf.set(id, name);
    const storeys = [];
    for (const [s, parent] of parentOf) {
      if (parent !== id) continue;
      const line = api.GetLine(model, s);
      if (line.type !== WebIFC.IFCBUILDINGSTOREY) continue;
      storeys.push({ id: s, name: line.Name.value, elevation: line.Elevation.value });
    }
    out.buildings.push({ name, storeys });
  }
  for (const id of ids(WebIFC.IFCRELDEFINESBYPROPERTIES)) {
    const rel = api.GetLine(model, id);
    const def = api.GetLine(model, rel.RelatingPropertyDefinition.value, true);
    for (const obj of rel.RelatedObjects) {
      if (!tagOf.has(obj.value)) continue;
      const tag = tagOf.get(obj.value);
      if (def.type === WebIFC.IFCPROPERTYSET) {
        for (const p of def.HasProperties)
          out.properties.push({ tag, pset: def.Name.value, name: p.Name.value, value: p.NominalValue ? p.NominalValue.value : null });
        continue;
      }
      if (def.type !== WebIFC.IFCELEMENTQUANTITY || !elementIds.has(obj.value)) continue;
      for (const q of def.Quantities) {
        const v = [q.AreaValue, q.LengthValue, q.VolumeValue].find((x) => x !== undefined && x !== null);
        if (v === undefined) continue;
        out.quantities.push({ tag, qto: def.Name.value, name: q.Name.value, value: v.value });
      }
    }
  }
  api.CloseModel(model);
  process.stdout.write(JSON.stringify(out) + '\n');
}

main().catch((e) => { console.error(e); process.exit(1); });
