// Independent check of a 3D Tiles tileset: 3d-tiles-tools (npm, Cesium)
// traverses tileset.json; every glTF content is judged by the Khronos
// gltf-validator, and its EXT_structural_metadata property tables are read
// back with 3d-tiles-tools' own binary metadata reader. Prints one JSON
// object: tiles, contents, glTF errors and warnings, every child region
// inside its parent's, and per content whether it is a leaf, its transform
// composed from the root, its feature counts, its positions' least corner and
// its property tables' rows (objects of property -> value).
// Usage: node tiles_check.js TILESET_DIR
const fs = require('fs');
const path = require('path');
const validator = require('gltf-validator');
const tools = require('3d-tiles-tools');

function glbChunks(bytes) {
  const jsonLength = bytes.readUInt32LE(12);
  const json = JSON.parse(bytes.subarray(20, 20 + jsonLength).toString('utf8'));
  const binStart = 20 + jsonLength + 8;
  return { json, bin: bytes.subarray(binStart, binStart + bytes.readUInt32LE(20 + jsonLength)) };
}

// Every row of every property table, read by 3d-tiles-tools' BinaryPropertyTableModel.
function propertyTables(json, bin) {
  const meta = json.extensions && json.extensions.EXT_structural_metadata;
  if (!meta) return [];
  const viewsData = json.bufferViews.map((v) => bin.subarray(v.byteOffset || 0, (v.byteOffset || 0) + v.byteLength));
  return meta.propertyTables.map((table) => {
    const model = new tools.BinaryPropertyTableModel({
      propertyTable: table,
      binaryMetadata: {
        metadataClass: meta.schema.classes[table.class],
        binaryEnumInfo: { enumValueTypes: {}, enumValueNameValues: {}, enumValueValueNames: {} },
        binaryBufferStructure: { buffers: json.buffers, bufferViews: json.bufferViews },
        binaryBufferData: { bufferViewsData: viewsData, buffersData: [bin] },
      },
    });
    const rows = [];
    for (let i = 0; i < model.getCount(); i++) {
      const entity = model.getMetadataEntityModel(i);
      const row = {};
      for (const name of model.getPropertyNames()) row[name] = entity.getPropertyValue(name);
      rows.push(row);
    }
    return { class: table.class, rows };
  });
}

// Column-major 4 x 4 product a * b (3D Tiles' transforms).
function times(a, b) {
  const m = new Array(16).fill(0);
  for (let c = 0; c < 4; c++)
    for (let r = 0; r < 4; r++)
      for (let k = 0; k < 4; k++) m[c * 4 + r] += a[k * 4 + r] * b[c * 4 + k];
  return m;
}
const identity = [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1];

function inside(child, parent) {
  const eps = 1e-9;
  return child[0] >= parent[0] - eps && child[1] >= parent[1] - eps && child[2] <= parent[2] + eps &&
         child[3] <= parent[3] + eps && child[4] >= parent[4] - 1e-6 && child[5] <= parent[5] + 1e-6;
}

async function main() {
  const dir = process.argv[2];
  const tileset = JSON.parse(fs.readFileSync(path.join(dir, 'tileset.json'), 'utf8'));
  const resolver = tools.ResourceResolvers.createFileResourceResolver(dir);
  const out = { version: tileset.asset.version, tiles: 0, contents: [], glTFErrors: 0, glTFWarnings: 0, regionsNested: true };
  const parents = new Map(), world = new Map();  // a tile's parent; its transform composed down from the root
  const traverser = new tools.TilesetTraverser(dir, resolver, { depthFirst: true, traverseExternalTilesets: true });
  await traverser.traverse(tileset, async (traversed) => {
    out.tiles++;
    const tile = traversed.asRawTile();
    for (const child of tile.children || []) parents.set(child, tile);
    const parent = parents.get(tile);
    world.set(tile, times(parent ? world.get(parent) : identity, tile.transform || identity));
    if (parent && !inside(tile.boundingVolume.region, parent.boundingVolume.region)) out.regionsNested = false;
    for (const content of traversed.getFinalContents()) {
      const bytes = Buffer.from(await resolver.resolveData(content.uri));
      const report = await validator.validateBytes(new Uint8Array(bytes));
      out.glTFErrors += report.issues.numErrors;
      out.glTFWarnings += report.issues.numWarnings;
      const { json, bin } = glbChunks(bytes);
      const prim = json.meshes[0].primitives[0];
      const ids = prim.extensions.EXT_mesh_features.featureIds.map((f) => f.featureCount);
      out.contents.push({ uri: content.uri, leaf: !(tile.children && tile.children.length),
                          transform: world.get(tile), featureCounts: ids,
                          positionMin: json.accessors[prim.attributes.POSITION].min,
                          vertices: report.info.totalVertexCount, tables: propertyTables(json, bin) });
    }
    return true;
  });
  console.log(JSON.stringify(out));
  process.exitCode = out.glTFErrors > 0 ? 1 : 0;  // not exit(): a pipe would lose the tail of the output
}
main().catch((e) => { console.error(e.stack || e.message); process.exitCode = 2; });
