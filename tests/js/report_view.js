// The report's 3D view (web/report_viewer.js) in headless Chromium, opened
// from file:// as an officer opens the report: waits until the view is ready
// (every cell in view loaded, on the summary), takes a screenshot, counts the
// pixels of given colours, and on a parcel page clicks where an element is
// drawn and reads what the pick panel shows.
// Prints one JSON object: state, load_ms, errors (console and page), pixels
// per colour, pick (building, element, area, text) and the cells loaded.
// Usage: node report_view.js PAGE.html OUT.png [--unlit] [--no-webgl]
//          [--click BUILDING ELEMENT | --click largest TYPE | --click top] [--colours '#rrggbb,...']
//          [--size WxH] [--level K] [--zoom F]
// (--level: show mesh level K of the parcel page's switch before the rest;
// --zoom: bring the camera F times closer to what it looks at, and wait for
// the cells that brings into view.)
// (TYPE: 0 roof, 1 wall, 2 party wall, 3 ground, 4 outer ceiling; top: on the
// summary, the highest roof drawn.)
const path = require('path');
const puppeteer = require('puppeteer-core');

const args = process.argv.slice(2);
const [page, png] = args;
const opt = (name) => { const i = args.indexOf(name); return i < 0 ? null : args.slice(i + 1); };
const unlit = args.includes('--unlit'), noWebgl = args.includes('--no-webgl');
const click = opt('--click'), colours = opt('--colours'), size = opt('--size'), level = opt('--level');
const zoom = opt('--zoom');
const [width, height] = size ? size[0].split('x').map(Number) : [1200, 900];

const hex = (h) => [1, 3, 5].map((i) => parseInt(h.slice(i, i + 2), 16));

async function main() {
  const flags = ['--no-sandbox', '--use-angle=swiftshader', '--enable-unsafe-swiftshader', '--ignore-gpu-blocklist'];
  if (noWebgl) flags.push('--disable-3d-apis', '--disable-webgl');
  const browser = await puppeteer.launch({ executablePath: process.env.CHROMIUM || '/usr/bin/chromium',
                                           headless: 'new', args: flags });
  const tab = await browser.newPage();
  const errors = [];
  tab.on('console', (m) => { if (m.type() === 'error') errors.push(m.text()); });
  tab.on('pageerror', (e) => errors.push(String(e)));
  await tab.setViewport({ width, height });
  const t0 = Date.now();
  await tab.goto('file://' + path.resolve(page) + (unlit ? '#unlit' : ''));
  await tab.waitForFunction(() => {
    const v = document.getElementById('view3d');
    return v && (v.dataset.state === 'ready' || v.dataset.state === 'unavailable');
  }, { timeout: 120000 });
  const load_ms = Date.now() - t0;
  await tab.evaluate(() => document.getElementById('view3d').scrollIntoView());
  await new Promise((r) => setTimeout(r, 300));
  const out = { state: await tab.$eval('#view3d', (v) => v.dataset.state), load_ms, errors };
  out.view_ms = Number(await tab.$eval('#view3d', (v) => v.dataset.loadMs || -1));
  out.note = await tab.$eval('#view3d', (v) => (v.querySelector('.view3d-note') || {}).textContent || '');
  out.pictures = await tab.$$eval('svg', (s) => s.length);
  if (out.state === 'ready') {
    out.cells = await tab.$eval('#view3d', (v) => (v.c3d.cells || []).map((c) => ({ name: c.name, far: !!c.far, near: !!c.near })));
    if (zoom) {
      const t1 = Date.now();
      await tab.$eval('#view3d', (v, f) => {
        const { camera, controls } = v.c3d.view;
        camera.position.lerp(controls.target, 1 - 1 / f);
        controls.update();
        controls.dispatchEvent({ type: 'change' });
      }, Number(zoom[0]));
      await new Promise((r) => setTimeout(r, 200));
      await tab.waitForFunction(() => document.getElementById('view3d').dataset.state === 'ready', { timeout: 120000 });
      out.zoom_ms = Date.now() - t1;
      out.cells = await tab.$eval('#view3d', (v) => v.c3d.cells.map((c) => ({ name: c.name, far: !!c.far, near: !!c.near })));
    }
    if (level) {
      out.levels = await tab.$$eval('#view3d .view3d-levels option', (o) => o.map((x) => x.value));
      await tab.select('#view3d .view3d-levels', level[0]);
      await tab.waitForFunction(() => document.getElementById('view3d').dataset.state === 'ready', { timeout: 120000 });
      await new Promise((r) => setTimeout(r, 300));
    }
    if (click) {
      if (click[0] === 'top') {  // the summary: the highest roof drawn
        const at = await tab.$eval('#view3d', (v) => v.c3d.topOnScreen());
        await tab.mouse.click(at.x, at.y);
        await new Promise((r) => setTimeout(r, 300));
        out.pick = await tab.$eval('#view3d .view3d-pick', (p) => ({ parcel: p.dataset.parcel || null,
          value: p.dataset.value === undefined ? null : Number(p.dataset.value), text: p.textContent }));
      } else {
      const [b, e] = click[0] === 'largest' ? await tab.$eval('#view3d', (v, t) => v.c3d.largest(t), Number(click[1]))
                                            : [Number(click[0]), Number(click[1])];
      out.clicked = { building: b, element: e };
      const at = await tab.$eval('#view3d', (v, b, e) => v.c3d.elementOnScreen(b, e), b, e);
      await tab.mouse.click(at.x, at.y);
      await new Promise((r) => setTimeout(r, 300));
      out.pick = await tab.$eval('#view3d .view3d-pick', (p) => ({
        building: p.dataset.building, element: p.dataset.element === undefined ? null : Number(p.dataset.element),
        area: p.dataset.area === undefined ? null : Number(p.dataset.area),
        shown: (p.querySelector('.area') || {}).textContent || null, text: p.textContent }));
      }
    }
    if (colours) {
      const want = colours[0].split(',').map(hex);
      out.pixels = await tab.$eval('#view3d canvas', (c, want) => {
        const two = document.createElement('canvas');
        two.width = c.width, two.height = c.height;
        const g = two.getContext('2d');
        g.drawImage(c, 0, 0);
        const d = g.getImageData(0, 0, c.width, c.height).data;
        const n = want.map(() => 0);
        for (let i = 0; i < d.length; i += 4)
          want.forEach((w, k) => { if (Math.abs(d[i] - w[0]) <= 3 && Math.abs(d[i + 1] - w[1]) <= 3 && Math.abs(d[i + 2] - w[2]) <= 3) ++n[k]; });
        return n;
      }, want);
    }
  }
  const view = await tab.$('#view3d');
  if (view) await view.screenshot({ path: png });
  await browser.close();
  console.log(JSON.stringify(out));
}

main().catch((e) => { console.error(String(e)); process.exit(1); });
