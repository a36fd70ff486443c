// A 3D Tiles tileset in headless Chromium: a minimal CesiumJS page (npm
// `cesium`, its Build/Cesium) or, with --own, the page the program writes
// beside the tileset (view.html, three.js and 3d-tiles-renderer). Serves the
// page and the tileset over a local HTTP server, waits until every tile in
// view is loaded, takes a screenshot, and counts the pixels drawn in each
// element type's colour (the tiles are drawn unlit for the count, so a pixel
// is its vertices' colour). With --click (--own only) it clicks the roof
// pixel nearest the middle, reads the page's pick panel and counts the
// pixels of the picked element's mark (#ffe066).
// Prints one JSON object: load_ms (page open to all tiles loaded), errors (the
// console's and the page's), pixels per element type, the screenshot's path,
// and with --click the panel's text, parcel and area. With --from-file (--own
// only) the page is opened from the file, not served, and prints its note.
// With --zoom F (--own only) the camera then comes F times closer, and the
// page is read once the tiles of that view are in (zoom_ms).
// Usage: node tileset_view.js TILESET_DIR OUT.png [--lit] [--own [--click | --from-file] [--zoom F]]
const fs = require('fs');
const http = require('http');
const path = require('path');
const puppeteer = require('puppeteer-core');

const [tilesetDir, png] = process.argv.slice(2, 4);
const lit = process.argv.includes('--lit');
const own = process.argv.includes('--own');
const click = process.argv.includes('--click');
const fromFile = process.argv.includes('--from-file');
const zoomAt = process.argv.indexOf('--zoom');
const zoom = zoomAt > 0 ? Number(process.argv[zoomAt + 1]) : 0;
const cesiumDir = path.join(path.dirname(require.resolve('cesium/package.json')), 'Build', 'Cesium');
// tile_content.cpp's element_colour, linear RGB as the glTF holds it.
const colours = { roof: [0.71, 0.33, 0.24], wall: [0.91, 0.89, 0.82], party_wall: [0.79, 0.66, 0.30],
                  ground: [0.5, 0.5, 0.5], outer_ceiling: [0.42, 0.56, 0.75] };

const page = `<!doctype html><html><head><meta charset="utf-8"><title>loading</title>
<link rel="icon" href="data:,"><script src="Cesium/Cesium.js"></script>
<link href="Cesium/Widgets/widgets.css" rel="stylesheet">
<style>html,body,#v{margin:0;width:100%;height:100%;overflow:hidden}</style></head>
<body><div id="v"></div><script>
const viewer = new Cesium.Viewer('v', {baseLayer: false, baseLayerPicker: false, geocoder: false, timeline: false,
  animation: false, homeButton: false, sceneModePicker: false, navigationHelpButton: false, fullscreenButton: false,
  infoBox: false, selectionIndicator: false, skyBox: false, skyAtmosphere: false,
  // No globe (the buildings on white) and frames only when something changes:
  // the globe's own tiles and a render loop cost seconds in software rendering.
  globe: false, requestRenderMode: true,
  contextOptions: {webgl: {preserveDrawingBuffer: true}}});
viewer.scene.backgroundColor = Cesium.Color.WHITE;
Cesium.Cesium3DTileset.fromUrl('tiles/tileset.json').then((ts) => {
  if (!${lit}) ts.customShader = new Cesium.CustomShader({lightingModel: Cesium.LightingModel.UNLIT});
  viewer.scene.primitives.add(ts);
  viewer.zoomTo(ts, new Cesium.HeadingPitchRange(0.5, -0.7, 0));
  // Frames are drawn on request: ready once one is drawn with every tile in.
  ts.allTilesLoaded.addEventListener(() => {
    const stop = viewer.scene.postRender.addEventListener(() => { stop(); document.title = 'ready'; });
    viewer.scene.requestRender();
  });
}).catch((e) => { document.title = 'error ' + e; });
</script></body></html>`;

function serve() {
  const server = http.createServer((req, res) => {
    const url = decodeURIComponent(req.url.split('?')[0]);
    let file = null;
    if (url === '/' || url === '/view.html') return res.end(page);
    if (url.startsWith('/Cesium/')) file = path.join(cesiumDir, url.slice(8));
    if (url.startsWith('/tiles/')) file = path.join(tilesetDir, url.slice(7));
    if (!file || !fs.existsSync(file) || fs.statSync(file).isDirectory()) { res.statusCode = 404; return res.end(); }
    const types = { '.html': 'text/html', '.js': 'text/javascript', '.json': 'application/json', '.css': 'text/css', '.glb': 'model/gltf-binary' };
    res.setHeader('Content-Type', types[path.extname(file)] || 'application/octet-stream');
    fs.createReadStream(file).pipe(res);
  });
  return new Promise((ok) => server.listen(0, '127.0.0.1', () => ok(server)));
}

// sRGB bytes of a linear colour: what an unlit glTF vertex colour is drawn as.
const srgb = (c) => c.map((v) => Math.round(255 * (v <= 0.0031308 ? 12.92 * v : 1.055 * Math.pow(v, 1 / 2.4) - 0.055)));

// Each colour's pixel count on the canvas, and where (page pixels) the roof
// pixel nearest the canvas's middle is drawn.
function countPixels(selector, expected) {
  const c = document.querySelector(selector);
  const two = document.createElement('canvas');
  two.width = c.width, two.height = c.height;
  const g = two.getContext('2d');
  g.drawImage(c, 0, 0);
  const d = g.getImageData(0, 0, c.width, c.height).data;
  const count = Object.fromEntries(Object.keys(expected).map((k) => [k, 0]));
  let roof = null, best = Infinity;
  for (let i = 0; i < d.length; i += 4)
    for (const [k, e] of Object.entries(expected))
      if (Math.abs(d[i] - e[0]) <= 6 && Math.abs(d[i + 1] - e[1]) <= 6 && Math.abs(d[i + 2] - e[2]) <= 6) {
        count[k]++;
        const x = (i / 4) % c.width, y = Math.floor(i / 4 / c.width);
        const far = Math.hypot(x - c.width / 2, y - c.height / 2);
        if (k === 'roof' && far < best) best = far, roof = [x, y];
      }
  const r = c.getBoundingClientRect();
  const at = roof && { x: r.left + (roof[0] + 0.5) * r.width / c.width, y: r.top + (roof[1] + 0.5) * r.height / c.height };
  return { count, roof: at };
}

// Clicks at the point and returns what the page's pick panel then says.
async function pick(tab, at) {
  await tab.mouse.click(at.x, at.y);
  await tab.waitForFunction(() => document.querySelector('.view3d-pick').dataset.parcel, { timeout: 10000 });
  await tab.evaluate(() => document.querySelector('#view').c3d.view.frame());  // the pick drawn
  const marked = (await tab.evaluate(countPixels, '#view canvas', { mark: [0xff, 0xe0, 0x66] })).count.mark;
  return tab.evaluate((marked) => {
    const p = document.querySelector('.view3d-pick');
    return { text: p.innerText, parcel: p.dataset.parcel, area: p.dataset.area, marked };
  }, marked);
}

// The page opened, read and measured: the JSON this script prints.
async function view(tab, base) {
  const t0 = Date.now();
  const ownPage = fromFile ? 'file://' + path.resolve(tilesetDir, 'view.html') : `${base}/tiles/view.html`;
  await tab.goto(own ? `${ownPage}${lit ? '' : '#unlit'}` : `${base}/view.html`);
  if (own) await tab.waitForFunction(() => ['ready', 'unavailable'].includes(document.querySelector('#view').dataset.state), { timeout: 120000 });
  else await tab.waitForFunction(() => document.title !== 'loading', { timeout: 120000 });
  const load_ms = Date.now() - t0;
  const state = own ? await tab.evaluate(() => document.querySelector('#view').dataset.state) : await tab.title();
  await new Promise((r) => setTimeout(r, 300));
  if (own && state === 'unavailable')
    return { state, note: await tab.evaluate(() => document.querySelector('.view3d-note').textContent) };
  let zoom_ms = null;
  if (own && zoom > 0) {
    const t1 = Date.now();
    await tab.evaluate((f) => {
      const div = document.querySelector('#view'), v = div.c3d.view;
      v.camera.position.sub(v.controls.target).multiplyScalar(1 / f).add(v.controls.target);
      div.dataset.state = 'loading';  // until a frame of this view finds every tile in
      v.controls.update();
      v.render();
    }, zoom);
    await tab.waitForFunction(() => document.querySelector('#view').dataset.state === 'ready', { timeout: 120000 });
    zoom_ms = Date.now() - t1;
  }
  const expected = Object.fromEntries(Object.entries(colours).map(([k, c]) => [k, srgb(c)]));
  const seen = await tab.evaluate(countPixels, own ? '#view canvas' : '#v canvas', expected);
  const picked = own && click && seen.roof ? await pick(tab, seen.roof) : null;
  await tab.screenshot({ path: png });
  return { state, load_ms, zoom_ms, pixels: seen.count, picked, screenshot: png };
}

async function main() {
  const server = await serve();
  const browser = await puppeteer.launch({ executablePath: process.env.CHROMIUM || '/usr/bin/chromium', headless: 'new',
    args: ['--no-sandbox', '--use-angle=swiftshader', '--enable-unsafe-swiftshader', '--ignore-gpu-blocklist'] });
  try {
    const tab = await browser.newPage();
    const errors = [];
    tab.on('console', (m) => { if (m.type() === 'error') errors.push(m.text()); });
    tab.on('pageerror', (e) => errors.push(String(e)));
    await tab.setViewport({ width: 1000, height: 700 });
    const result = await view(tab, `http://127.0.0.1:${server.address().port}`);
    console.log(JSON.stringify({ ...result, errors }));
    // Opened from the file, the page is to say it cannot load the tiles.
    const wanted = fromFile ? 'unavailable' : 'ready';
    process.exitCode = result.state === wanted && errors.length === 0 ? 0 : 1;
  } finally {
    await browser.close();
    server.close();
  }
}
main().catch((e) => { console.error(e.stack || e.message); process.exitCode = 2; });
