// A minimal CesiumJS page on a 3D Tiles tileset, in headless Chromium: serves
// the page, CesiumJS (npm `cesium`, its Build/Cesium) and the tileset over a
// local HTTP server, waits until every tile in view is loaded, takes a
// screenshot, and counts the pixels drawn in each element type's colour (the
// tiles are drawn unlit for the count, so a pixel is its vertices' colour).
// Prints one JSON object: load_ms (page open to all tiles loaded), errors (the
// console's and the page's), pixels per element type, the screenshot's path.
// Usage: node tileset_view.js TILESET_DIR OUT.png [--lit]
const fs = require('fs');
const http = require('http');
const path = require('path');
const puppeteer = require('puppeteer-core');

const [tilesetDir, png] = process.argv.slice(2, 4);
const lit = process.argv.includes('--lit');
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
    const types = { '.js': 'text/javascript', '.json': 'application/json', '.css': 'text/css', '.glb': 'model/gltf-binary' };
    res.setHeader('Content-Type', types[path.extname(file)] || 'application/octet-stream');
    fs.createReadStream(file).pipe(res);
  });
  return new Promise((ok) => server.listen(0, '127.0.0.1', () => ok(server)));
}

// sRGB bytes of a linear colour: what an unlit glTF vertex colour is drawn as.
const srgb = (c) => c.map((v) => Math.round(255 * (v <= 0.0031308 ? 12.92 * v : 1.055 * Math.pow(v, 1 / 2.4) - 0.055)));

async function main() {
  const server = await serve();
  const browser = await puppeteer.launch({ executablePath: process.env.CHROMIUM || '/usr/bin/chromium', headless: 'new',
    args: ['--no-sandbox', '--use-angle=swiftshader', '--enable-unsafe-swiftshader', '--ignore-gpu-blocklist'] });
  const tab = await browser.newPage();
  const errors = [];
  tab.on('console', (m) => { if (m.type() === 'error') errors.push(m.text()); });
  tab.on('pageerror', (e) => errors.push(String(e)));
  await tab.setViewport({ width: 1000, height: 700 });
  const t0 = Date.now();
  await tab.goto(`http://127.0.0.1:${server.address().port}/view.html`);
  await tab.waitForFunction(() => document.title !== 'loading', { timeout: 120000 });
  const load_ms = Date.now() - t0;
  const title = await tab.title();
  await new Promise((r) => setTimeout(r, 300));
  const expected = Object.fromEntries(Object.entries(colours).map(([k, c]) => [k, srgb(c)]));
  const pixels = await tab.evaluate((expected) => {
    const c = document.querySelector('#v canvas');
    const two = document.createElement('canvas');
    two.width = c.width, two.height = c.height;
    const g = two.getContext('2d');
    g.drawImage(c, 0, 0);
    const d = g.getImageData(0, 0, c.width, c.height).data;
    const count = Object.fromEntries(Object.keys(expected).map((k) => [k, 0]));
    for (let i = 0; i < d.length; i += 4)
      for (const [k, e] of Object.entries(expected))
        if (Math.abs(d[i] - e[0]) <= 6 && Math.abs(d[i + 1] - e[1]) <= 6 && Math.abs(d[i + 2] - e[2]) <= 6) count[k]++;
    return count;
  }, expected);
  await tab.screenshot({ path: png });
  console.log(JSON.stringify({ title, load_ms, errors, pixels, screenshot: png }));
  await browser.close();
  server.close();
  process.exitCode = title === 'ready' && errors.length === 0 ? 0 : 1;
}
main().catch((e) => { console.error(e.stack || e.message); process.exitCode = 2; });
