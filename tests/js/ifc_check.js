// Independent IFC read-back with web-ifc: prints JSON with, per IfcWall / IfcSlab /
// IfcCovering, its Tag, the number of meshes and triangles web-ifc made, the mesh
// area, and every IfcQuantityArea attached through IfcRelDefinesByProperties.
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
    const m = meshes.get(mesh.expressID) || { meshes: 0, triangles: 0, area: 0 };
    m.meshes += 1;
    for (let i = 0; i < mesh.geometries.size(); i++) {
      const g = api.GetGeometry(model, mesh.geometries.get(i).geometryExpressID);
      const v = api.GetVertexArray(g.GetVertexData(), g.GetVertexDataSize());
      const idx = api.GetIndexArray(g.GetIndexData(), g.GetIndexDataSize());
      for (let t = 0; t < idx.length; t += 3) m.area += triangleArea(v, idx[t], idx[t + 1], idx[t + 2]);
      m.triangles += idx.length / 3;
      g.delete();
    }
    meshes.set(mesh.expressID, m);
  });
  const out = { elements: [], quantities: [] };
  const types = { IFCWALL: WebIFC.IFCWALL, IFCSLAB: WebIFC.IFCSLAB, IFCCOVERING: WebIFC.IFCCOVERING };
  const tagOf = new Map();
  for (const [name, type] of Object.entries(types)) {
    const ids = api.GetLineIDsWithType(model, type);
    for (let i = 0; i < ids.size(); i++) {
      const id = ids.get(i);
      const line = api.GetLine(model, id);
      const tag = line.Tag ? line.Tag.value : null;
      tagOf.set(id, tag);
      const m = meshes.get(id) || { meshes: 0, triangles: 0, area: 0 };
      out.elements.push({ type: name, tag, meshes: m.meshes, triangles: m.triangles, mesh_area: m.area });
    }
  }
  const rels = api.GetLineIDsWithType(model, WebIFC.IFCRELDEFINESBYPROPERTIES);
  for (let i = 0; i < rels.size(); i++) {
    const rel = api.GetLine(model, rels.get(i));
    const def = api.GetLine(model, rel.RelatingPropertyDefinition.value, true);
    if (def.type !== WebIFC.IFCELEMENTQUANTITY) continue;
    for (const obj of rel.RelatedObjects) {
      if (!tagOf.has(obj.value)) continue;
      for (const q of def.Quantities) {
        if (q.AreaValue === undefined) continue;
        out.quantities.push({ tag: tagOf.get(obj.value), qto: def.Name.value, name: q.Name.value, value: q.AreaValue.value });
      }
    }
  }
  api.CloseModel(model);
  process.stdout.write(JSON.stringify(out) + '\n');
}

main().catch((e) => { console.error(e); process.exit(1); });
