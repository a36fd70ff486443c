// The page written beside a batch's 3D Tiles (OUT/3dtiles/view.html,
// docs/exports.md "3D Tiles"). esbuild bundles this file with three.js and
// 3d-tiles-renderer into 3dtiles/lib/c3d-tiles.js, one classic script.
//
//   C3DTiles.open(div, url)  the tileset at url, streamed as the camera moves;
//                            a click names the building and element under it
//
// The tiles are fetched, so the page is served over HTTP (a browser refuses
// fetch() from file://); opened from a file it says how to serve it.
import * as THREE from 'three';
import { TilesRenderer } from '3d-tiles-renderer';
import { GLTFExtensionsPlugin } from '3d-tiles-renderer/plugins';
import { frame, makeView, material, num, onClick, panel, say, unlit, webglAvailable } from './view.js';

// The world -> east, north, up metres at the tileset's centre: the view is
// z up, as the report's, whatever frame the tileset is written in.
function localFrame(tiles) {
  const sphere = new THREE.Sphere();
  tiles.getBoundingSphere(sphere);
  const at = tiles.ellipsoid.getPositionToCartographic(sphere.center, {});
  const enu = tiles.ellipsoid.getEastNorthUpFrame(at.lat, at.lon, at.height, new THREE.Matrix4());
  return enu.invert();
}

// The root's bounds in the local frame: its region's corners where it has
// one (an oriented box around a region is loose), else its bounding box.
function rootBox(tiles, toLocal) {
  const box = new THREE.Box3();
  const region = tiles.root.boundingVolume.region;
  if (!region) {
    tiles.getBoundingBox(box);
    return box.applyMatrix4(tiles.group.matrixWorld);
  }
  const [west, south, east, north, low, high] = region;
  for (let k = 0; k < 8; ++k) {
    const p = tiles.ellipsoid.getCartographicToPosition(k & 1 ? north : south, k & 2 ? east : west, k & 4 ? high : low,
                                                        new THREE.Vector3());
    box.expandByPoint(p.applyMatrix4(toLocal));
  }
  return box;
}

// The tiles' glTF materials become the view's (lit or, for tests, unlit)
// with the vertices' element colours.
function ownMaterials(model) {
  model.traverse((o) => {
    if (!o.isMesh) return;
    o.material.dispose();
    o.material = material(null, true);
  });
}

// The building and element under a hit, from the tile's EXT_mesh_features
// ids and EXT_structural_metadata tables, with each one's feature (its
// vertex attribute and id); null where the tile has none.
function featureRows(hit) {
  const { meshFeatures, structuralMetadata } = hit.object.userData;
  if (!meshFeatures || !structuralMetadata) return null;
  const info = meshFeatures.getFeatureInfo();
  const ids = meshFeatures.getFeatures(hit.faceIndex, hit.barycoord);
  const rows = structuralMetadata.getPropertyTableData(info.map((f) => f.propertyTable), ids);
  const found = { features: {} };
  info.forEach((f, k) => {
    if (ids[k] == null) return;
    found[f.label] = rows[k];
    found.features[f.label] = { attribute: f.attribute, id: ids[k] };
  });
  return found.building ? found : null;
}

const AREAS = [['roof_area_m2', 'roof'], ['wall_area_m2', 'wall'], ['party_wall_area_m2', 'party wall'],
               ['ground_area_m2', 'ground'], ['outer_ceiling_area_m2', 'outer ceiling']];

// A parent tile draws a far building as its LoD 1.2 prism, one element per
// type holding the building's totals of that type, marked by a slope of -1.
function elementLines(b, e, money) {
  const type = e.type.replace('_', ' ');
  const area = `Area <span class="area">${num(e.area_m2, 2)}</span> &plusmn; ${num(e.sigma_area_m2, 2)} m&#178; &middot; ` +
               `plan ${num(e.plan_area_m2, 2)} m&#178;`;
  const cost = e.amount >= 0 ? ` &middot; cost amount ${money(e.amount)}` : '';
  if (e.slope_deg < 0)
    return [`<b>${type}</b> of building ${b.building_id}, all its ${type} elements ` +
            '(drawn as its LoD 1.2 prism at this distance; come closer for each element)',
            area, `Points ${e.support_points}${cost}`];
  return [`<b>${type}</b> of building ${b.building_id}`, `${area} &middot; slope ${num(e.slope_deg, 1)}&deg;`,
          `Points ${e.support_points} &middot; RMSE ${e.support_points > 0 ? num(e.rmse_m, 3) + ' m' : '\u2014'}${cost}`];
}

function featureText({ building: b, element: e }) {
  const money = (v) => (v >= 0 ? `${b.currency} ${num(v, 0)}` : '\u2014');
  const lines = e ? elementLines(b, e, money) : [`<b>Building ${b.building_id}</b>`];
  lines.push(`Parcel <span class="parcel">${b.parcel_id}</span> (${b.status}) &middot; LoD ${b.lod} &middot; ` +
             AREAS.filter(([k]) => b[k] > 0).map(([k, name]) => `${name} ${num(b[k], 1)} m&#178;`).join(', ') +
             ` &middot; volume ${num(b.volume_m3, 1)} m&#179;`,
             `Building value ${money(b.building_value)} &middot; NJOP ${money(b.njop)} &middot; tax ${money(b.tax)}`);
  return lines.join('<br>');
}

// The picked feature's triangles (those whose vertices carry its id) drawn
// over it in a light colour, a mesh of the tile's own vertices.
function highlight(hit, feature) {
  const geometry = hit.object.geometry;
  const ids = feature && feature.attribute !== undefined ? geometry.getAttribute(`_feature_id_${feature.attribute}`) : null;
  if (!ids) return null;
  const corners = [];
  const count = geometry.index ? geometry.index.count : ids.count;
  for (let i = 0; i < count; i += 3) {
    const v = [0, 1, 2].map((k) => (geometry.index ? geometry.index.getX(i + k) : i + k));
    if (ids.getX(v[0]) === feature.id) corners.push(...v);
  }
  const mark = new THREE.BufferGeometry();
  mark.setAttribute('position', geometry.getAttribute('position'));
  mark.setIndex(corners);
  const mesh = new THREE.Mesh(mark, new THREE.MeshBasicMaterial({ color: '#ffe066', side: THREE.DoubleSide,
    polygonOffset: true, polygonOffsetFactor: -2, polygonOffsetUnits: -2 }));
  mesh.raycast = () => {};  // clicks go through to the tile
  hit.object.add(mesh);
  mesh.updateMatrixWorld(true);  // the tiles' matrices are not updated each frame: set it once
  return mesh;
}

function onPick(view, tiles, info) {
  let marked = null;
  onClick(view, () => [tiles.group], (hit) => {
    if (marked) marked.removeFromParent(), marked.geometry.dispose(), marked = null;
    const rows = hit && featureRows(hit);
    if (!rows) info.textContent = hit ? 'This tile holds no figures.' : 'Click a building for its figures.';
    else {
      info.innerHTML = featureText(rows);
      info.dataset.parcel = rows.building.parcel_id;
      info.dataset.area = rows.element ? String(rows.element.area_m2) : '';
      marked = highlight(hit, rows.features.element || rows.features.building);
    }
    view.render();
  });
}

// Ready once a frame is drawn with every tile the view wants loaded or
// failed; failures are in the console and named in the panel.
function watchLoading(div, view, tiles, info, t0) {
  let framed = false;  // the root is in and the camera on it
  tiles.addEventListener('load-root-tileset', () => { framed = true; });
  tiles.addEventListener('load-error', ({ tile, url }) => {
    if (tile) return;
    info.textContent = `The tileset ${url} could not be loaded: the browser's console says why.`;
    div.dataset.state = 'unavailable';
  });
  view.listeners.push(() => {
    if (div.dataset.state === 'unavailable') return;
    // From the counts, not isLoading (false again while tiles still come),
    // and processNodeQueue, which readies the tiles' children between frames:
    // until it has, a frame may find nothing to load where they come next.
    const { queued, downloading, parsing } = tiles.stats;
    const done = framed && queued + downloading + parsing === 0 && !tiles.processNodeQueue.running;
    if (done && div.dataset.state !== 'ready') {
      div.dataset.loadMs = String(Math.round(performance.now() - t0));
      if (tiles.stats.failed) info.textContent = `${tiles.stats.failed} tile(s) could not be loaded: the browser's console names them.`;
    }
    div.dataset.state = done ? 'ready' : 'loading';
  });
}

export function open(div, url) {
  if (location.protocol === 'file:')
    return say(div, 'This page fetches the tiles, which a browser does not do for a page opened from a file: ' +
                    'serve this folder over HTTP (for instance "python3 -m http.server" in it) and open view.html there.');
  if (!webglAvailable()) return say(div, 'No WebGL in this browser: open tileset.json in CesiumJS, QGIS or ArcGIS.');
  const t0 = performance.now();
  div.dataset.state = 'loading';
  const view = makeView(div);
  if (unlit()) view.scene.background.set('#ffffff');  // apart from every element colour, for tests that count them
  const tiles = new TilesRenderer(new URL(url, location.href).href);  // tiles resolve against it
  tiles.registerPlugin(new GLTFExtensionsPlugin({ metadata: true, rtc: true }));
  tiles.setCamera(view.camera);  // its resolution is set before each update, as the canvas may resize
  const world = new THREE.Group();  // the tileset's frame -> the view's local one
  world.matrixAutoUpdate = false;
  world.add(tiles.group);
  view.scene.add(world);
  tiles.addEventListener('load-model', ({ scene }) => { ownMaterials(scene); view.render(); });
  tiles.addEventListener('needs-update', view.render);
  const info = panel(div);
  info.textContent = 'Click a building for its figures. Drag to turn, right-drag to pan, wheel to zoom.';
  watchLoading(div, view, tiles, info, t0);
  tiles.addEventListener('load-root-tileset', () => {
    const toLocal = localFrame(tiles);
    world.matrix.copy(toLocal);
    world.updateMatrixWorld(true);
    frame(view, rootBox(tiles, toLocal));
  });
  view.before.push(() => {
    view.scene.updateMatrixWorld();
    view.camera.updateMatrixWorld();
    tiles.setResolutionFromRenderer(view.camera, view.renderer);
    tiles.update();
  });
  onPick(view, tiles, info);
  div.c3d = { view, tiles };
  view.render();
}
