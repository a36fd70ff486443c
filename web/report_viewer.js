// The report's 3D view (docs/report.md, "3D view"). esbuild bundles this file
// with three.js into report/lib/c3d-viewer.js, one classic script: a page
// opened from file:// may load classic scripts but neither ES modules nor
// fetch(), so the data come as scripts too, each calling C3DViewer.data().
//
//   C3DViewer.parcel(div, scene)  a parcel's buildings by element, picking
//   C3DViewer.summary(div, base)  every parcel by value, cells loaded on demand
//
// Where WebGL is absent the div says so and the page's pictures stay the view.
import * as THREE from 'three';
import { frame, makeView, material, num, onClick, onScreen, panel, say, webglAvailable } from './view.js';

// Data scripts: each calls C3DViewer.data(name, value) once it has run.
const waiting = new Map();
export function data(name, value) {
  const w = waiting.get(name);
  if (w) waiting.delete(name), w.ok(value);
}
function load(url, name) {
  return new Promise((ok, fail) => {
    waiting.set(name, { ok });
    const s = document.createElement('script');
    s.src = url;
    s.onerror = () => { waiting.delete(name); fail(new Error('cannot load ' + url)); };
    s.onload = () => s.remove();
    document.head.appendChild(s);
  });
}

function triangles(flat) {
  const g = new THREE.BufferGeometry();
  g.setAttribute('position', new THREE.Float32BufferAttribute(flat, 3));
  g.computeVertexNormals();  // not indexed: each triangle its own normal
  g.computeBoundingBox();
  return g;
}

// A polygon's rings (flat x,y lists, outer first) as ground triangles at z.
function groundShape(rings, z) {
  const pts = rings.map((r) => { const a = []; for (let i = 0; i + 1 < r.length; i += 2) a.push(new THREE.Vector2(r[i], r[i + 1])); return a; });
  const tris = THREE.ShapeUtils.triangulateShape(pts[0], pts.slice(1));
  const all = pts.flat(), pos = [];
  for (const t of tris) for (const k of t) pos.push(all[k].x, all[k].y, z);
  return pos;
}

// Rings' edges at height z as line segments, appended to pos.
function edges(rings, z, pos) {
  for (const r of rings)
    for (let i = 0; i + 1 < r.length; i += 2) {
      const j = (i + 2) % r.length;
      pos.push(r[i], r[i + 1], z, r[j], r[j + 1], z);
    }
  return pos;
}

function lines(pos, colour) {
  const g = new THREE.BufferGeometry();
  g.setAttribute('position', new THREE.Float32BufferAttribute(pos, 3));
  return new THREE.LineSegments(g, new THREE.LineBasicMaterial({ color: colour }));
}

// ---------------------------------------------------------------- parcel page

function elementText(scene, b, e, ei) {
  const type = scene.types[e.t];
  const lines = [
    `<b>${type.name}</b> of building ${b.id}, element ${ei + 1} (LoD ${b.lod})`,
    `Area <span class="area">${num(e.a, 2)}</span> &plusmn; ${num(e.s, 2)} m&#178; &middot; plan ${num(e.pa, 2)} m&#178; &middot; slope ${num(e.sl, 1)}&deg;`,
    `Points ${e.n} &middot; RMSE ${e.n > 0 ? num(e.r, 3) + ' m' : '\u2014'}` + (e.ev ? ` &middot; evidence: ${e.ev}` : ''),
  ];
  if (e.m >= 0) lines.push(`Cost amount ${scene.currency} ${num(e.m, 0)}`);
  return lines.join('<br>');
}

function legend(div, scene, groups, render) {
  const l = document.createElement('div');
  l.className = 'view3d-legend';
  scene.types.forEach((t, k) => {
    if (!groups[k].children.length) return;
    const label = document.createElement('label');
    const box = document.createElement('input');
    box.type = 'checkbox';
    box.checked = true;
    box.onchange = () => { groups[k].visible = box.checked; render(); };
    const sw = document.createElement('span');
    sw.className = 'swatch';
    sw.style.background = t.colour;
    label.append(box, sw, t.name);
    l.appendChild(label);
  });
  div.appendChild(l);
}

function meshText(scene, m) {
  return `<b>Mesh level ${m.level}</b> of building ${scene.buildings[m.b].id}: ${m.faces.toLocaleString('en-US')} faces` +
         `${m.closed ? ', closed' : ''}<br>Its points to the mesh: mean ${num(m.mean, 3)} m, 95th percentile ${num(m.p95, 3)} m`;
}

// A choice between the element model and each mesh level of the buildings'
// ladders (batch --mesh): a level's meshes are loaded when first chosen.
function meshSwitch(div, scene, view, model, info) {
  const levels = [...new Set(scene.meshes.map((m) => m.level))].sort();
  const bar = document.createElement('div');
  bar.className = 'view3d-legend';
  const select = document.createElement('select');
  select.className = 'view3d-levels';
  select.add(new Option('Element model', '0'));
  for (const k of levels) select.add(new Option(`Mesh level ${k}` + (k === 1 ? ' (closed hull)' : k === 4 ? ' (dense)' : ''), String(k)));
  bar.append('Show: ', select);
  div.insertBefore(bar, info);
  const shown = new Map();  // level -> group
  const meshes = [];
  select.onchange = async () => {
    const k = Number(select.value);
    div.dataset.state = 'loading';
    model.visible = k === 0;
    shown.forEach((g, level) => { g.visible = level === k; });
    if (k && !shown.has(k)) {
      const group = new THREE.Group();
      shown.set(k, group);
      view.scene.add(group);
      for (const m of scene.meshes.filter((m) => m.level === k)) {
        try {
          const d = await load(m.file, m.name);
          const g = new THREE.BufferGeometry();
          g.setAttribute('position', new THREE.Float32BufferAttribute(d.pos, 3));
          g.setIndex(d.idx);
          g.computeVertexNormals();
          const mat = material('#8fb8a8');  // no legend colour: a mesh has no elements
          mat.flatShading = true;
          const mesh = new THREE.Mesh(g, mat);
          mesh.userData = { mesh: m };
          group.add(mesh);
          meshes.push(mesh);
        } catch (e) {
          info.textContent = `Level ${k} of building ${scene.buildings[m.b].id} is not in this report: ` +
                             'the report was written away from the batch\'s mesh/ folder.';
        }
      }
    }
    await view.frame();
    div.dataset.state = 'ready';
  };
  return () => meshes.filter((m) => m.parent.visible);
}

export function parcel(div, scene) {
  if (!webglAvailable()) return say(div, 'No WebGL in this browser: the pictures below show the parcel.');
  const view = makeView(div);
  const box = new THREE.Box3();
  for (const rings of scene.parcel) {
    const ground = new THREE.Mesh(triangles(groundShape(rings, scene.ground - 0.05)), material('#e4e1d6'));
    view.scene.add(ground, lines(edges(rings, scene.ground - 0.04, []), '#444444'));
    box.expandByObject(ground);
  }
  const groups = scene.types.map(() => new THREE.Group());
  const model = new THREE.Group();  // the element model, hidden while a mesh level shows
  groups.forEach((g) => model.add(g));
  view.scene.add(model);
  const pickable = [];
  scene.buildings.forEach((b, bi) => b.elements.forEach((e, ei) => {
    const mesh = new THREE.Mesh(triangles(e.tri), material(scene.types[e.t].colour));
    mesh.userData = { b, e, bi, ei };
    const edges = new THREE.LineSegments(new THREE.EdgesGeometry(mesh.geometry, 10),
                                         new THREE.LineBasicMaterial({ color: '#333333' }));
    groups[e.t].add(mesh, edges);
    pickable.push(mesh);
    box.expandByObject(mesh);
  }));
  legend(div, scene, groups, view.render);
  const info = panel(div);
  const levelMeshes = scene.meshes && scene.meshes.length ? meshSwitch(div, scene, view, model, info) : () => [];
  let picked = null;
  onClick(view, () => (model.visible ? pickable.filter((m) => m.parent.visible) : []).concat(levelMeshes()), (hit) => {
    if (picked) picked.material.emissive?.set('#000000'), picked.material.color.set(scene.types[picked.userData.e.t].colour);
    picked = hit && hit.object.userData.e ? hit.object : null;
    if (hit && hit.object.userData.mesh) info.innerHTML = meshText(scene, hit.object.userData.mesh);
    if (!picked) return view.render();
    picked.material.emissive?.set('#3a3a00');
    if (!picked.material.emissive) picked.material.color.offsetHSL(0, 0, 0.15);
    const { b, e, ei } = picked.userData;
    info.innerHTML = elementText(scene, b, e, ei);
    info.dataset.building = b.id;
    info.dataset.element = String(ei);
    info.dataset.area = String(e.a);
    view.render();
  });
  frame(view, box);
  // For tests: where element ei of building bi is drawn, at its largest triangle's centre.
  div.c3d = {
    view,
    // The building and element of the largest area of type t.
    largest(t) {
      let best = null;
      scene.buildings.forEach((b, bi) => b.elements.forEach((e, ei) => {
        if (e.t === t && (!best || e.a > best.a)) best = { a: e.a, bi, ei };
      }));
      return best && [best.bi, best.ei];
    },
    elementOnScreen(bi, ei) {
      const t = scene.buildings[bi].elements[ei].tri;
      let best = -1, at = 0;
      for (let i = 0; i + 8 < t.length; i += 9) {
        const a = new THREE.Vector3(t[i], t[i + 1], t[i + 2]), b = new THREE.Vector3(t[i + 3], t[i + 4], t[i + 5]);
        const c = new THREE.Vector3(t[i + 6], t[i + 7], t[i + 8]);
        const s = b.clone().sub(a).cross(c.clone().sub(a)).length();
        if (s > best) best = s, at = i;
      }
      const c = new THREE.Vector3();
      for (let k = 0; k < 3; ++k) c.add(new THREE.Vector3(t[at + 3 * k], t[at + 3 * k + 1], t[at + 3 * k + 2]));
      return onScreen(view, c.multiplyScalar(1 / 3));
    },
  };
  view.frame().then(() => { div.dataset.state = 'ready'; });
}

// --------------------------------------------------------------- summary page

// A cell's buildings as one mesh (part: triangles, and how many of them each
// building has, in the cell's order): vertex colours by the parcel's class.
function cellMesh(index, cell, part) {
  const g = triangles(part.pos);
  const colours = new Float32Array(part.pos.length);
  const first = [];  // first triangle of each building
  let tri = 0;
  const c = new THREE.Color();
  part.counts.forEach((n, k) => {
    first.push(tri);
    c.set(index.colours[cell.parcels[cell.buildings[k].p].c]);
    for (let v = 3 * tri; v < 3 * (tri + n); ++v) colours.set([c.r, c.g, c.b], 3 * v);
    tri += n;
  });
  g.setAttribute('color', new THREE.BufferAttribute(colours, 3));
  const mesh = new THREE.Mesh(g, material(null, true));
  mesh.userData = { cell, part, first };
  return mesh;
}

function parcelsMesh(index, cell) {
  const pos = [], col = [], outlines = [];  // the cell's outlines in one draw
  const c = new THREE.Color();
  for (const p of cell.parcels) {
    c.set(index.colours[p.c]).lerp(new THREE.Color('#ffffff'), 0.45);
    for (const rings of p.rings) {
      const tri = groundShape(rings, p.z - 0.1);
      pos.push(...tri);
      for (let i = 0; i < tri.length / 3; ++i) col.push(c.r, c.g, c.b);
      edges(rings, p.z - 0.08, outlines);
    }
  }
  const g = triangles(pos);
  g.setAttribute('color', new THREE.Float32BufferAttribute(col, 3));
  const group = new THREE.Group();
  group.add(new THREE.Mesh(g, material(null, true)), lines(outlines, '#555555'));
  return group;
}

function valueLegend(div, index) {
  const l = document.createElement('div');
  l.className = 'view3d-legend';
  l.innerHTML = `NJOP per m&#178; of land (${index.currency}/m&#178;): ` + index.colours.map((c, k) =>
    `<span class="entry"><span class="swatch" style="background:${c}"></span>${index.labels[k]}</span>`).join('');
  div.appendChild(l);
}

function parcelText(index, cell, b) {
  const p = cell.parcels[b.p];
  return `<b>Parcel <a href="${index.pages}${p.page}">${p.id}</a></b> (${p.status}) &middot; building ${b.id}` +
         `<br>NJOP per m&#178; of land: ${p.v >= 0 ? index.currency + ' ' + num(p.v, 0) : 'not valued'}` +
         ` &middot; class: ${index.labels[p.c]}`;
}

export function summary(div, base) {
  if (!webglAvailable()) return say(div, 'No WebGL in this browser: the overview map below shows the parcels.');
  const view = makeView(div);
  const info = panel(div);
  info.textContent = 'Click a building for its parcel. Drag to turn, right-drag to pan, wheel to zoom.';
  const t0 = performance.now();
  load(base + 'index.js', 'index').then((index) => {
    valueLegend(div, index);
    div.insertBefore(div.lastChild, info);
    const cells = index.cells.map((c) => ({ ...c, box: new THREE.Box3(new THREE.Vector3(...c.box.slice(0, 3)), new THREE.Vector3(...c.box.slice(3))), far: null, near: null, loading: false }));
    const all = new THREE.Box3();
    cells.forEach((c) => all.union(c.box));
    let busy = 0, drawn = 0;
    // After a cell came in: the next ones, and a frame now and then (a frame
    // of a whole town costs more than a cell in software rendering).
    const loaded = () => {
      update(false);
      if (!busy || performance.now() - drawn > 1000) drawn = performance.now(), view.render();
    };
    // Cells in view: far ones as prisms with their parcels, near ones by
    // element. Ready once a frame is drawn with nothing left to load.
    const update = (afterFrame) => {
      const m = new THREE.Matrix4().multiplyMatrices(view.camera.projectionMatrix, view.camera.matrixWorldInverse);
      const frustum = new THREE.Frustum().setFromProjectionMatrix(m);
      const want = [];
      for (const c of cells) {
        const d = c.box.distanceToPoint(view.camera.position);
        const near = d < index.near_m;
        if (c.near && !near && d > 2 * index.near_m) { view.scene.remove(c.near); c.near.geometry.dispose(); c.near = null; }
        if (c.near && c.far) c.far.userData.prisms.visible = false;
        else if (c.far) c.far.userData.prisms.visible = true;
        if (c.failed || !frustum.intersectsBox(c.box)) continue;
        if (!c.far) want.push([d, c, 'far']);
        else if (near && !c.near) want.push([d, c, 'near']);
      }
      want.sort((a, b) => a[0] - b[0]);
      div.dataset.pending = String(want.length + busy);
      if (!want.length && !busy) {
        if (!afterFrame) return;
        if (div.dataset.state !== 'ready') div.dataset.loadMs = String(Math.round(performance.now() - t0));
        div.dataset.state = 'ready';
      } else div.dataset.state = 'loading';
      while (busy < 4 && want.length) {
        const [, c, part] = want.shift();
        if (c.loading) continue;
        c.loading = true, ++busy;
        const name = c.name + (part === 'far' ? '-far' : '');
        load(base + name + '.js', name).then((d) => {
          if (part === 'far') {
            c.far = new THREE.Group();
            c.far.add(parcelsMesh(index, d));
            c.far.userData.prisms = cellMesh(index, d, d.prisms);
            c.far.add(c.far.userData.prisms);
            view.scene.add(c.far);
          } else {
            c.near = cellMesh(index, d, d.elements);
            view.scene.add(c.near);
          }
        }).catch((e) => { console.error(String(e)); c.failed = true; })
          .finally(() => { c.loading = false, --busy; loaded(); });
      }
    };
    view.listeners.push(() => update(true));
    frame(view, all);
    const pickable = () => cells.flatMap((c) => [c.near, c.far && c.far.userData.prisms.visible ? c.far.userData.prisms : null]).filter(Boolean);
    onClick(view, pickable, (hit) => {
      if (!hit) return;
      const { cell, part, first } = hit.object.userData;
      let k = first.length - 1;
      while (k > 0 && first[k] > hit.faceIndex) --k;
      const b = cell.buildings[k];
      info.innerHTML = parcelText(index, cell, b);
      info.dataset.parcel = cell.parcels[b.p].id;
      info.dataset.value = String(cell.parcels[b.p].v);
    });
    div.c3d = {
      view, cells,
      // Where the highest triangle of the buildings drawn is (tests click there).
      topOnScreen() {
        let best = null;
        for (const m of pickable()) {
          const p = m.geometry.getAttribute('position');
          for (let i = 0; i < p.count; i += 3) {
            const z = (p.getZ(i) + p.getZ(i + 1) + p.getZ(i + 2)) / 3;
            if (!best || z > best.z) best = { z, i, p };
          }
        }
        if (!best) return null;
        const c = new THREE.Vector3();
        for (let k = 0; k < 3; ++k) c.add(new THREE.Vector3().fromBufferAttribute(best.p, best.i + k));
        return onScreen(view, c.multiplyScalar(1 / 3));
      },
    };
  }).catch((e) => { console.error(String(e)); say(div, 'The 3D data of this report are missing: ' + e.message); });
}
