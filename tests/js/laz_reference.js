// The reference for LAZ decoding speed: laz-perf (the LAZ decoder PDAL and
// browsers use, here its WebAssembly build) decodes each file on one core.
// Prints points per second of CPU time (best of 5 after a first pass) and the
// SHA-256 of the decoded records, to hold against ../shared/data/laz/README.md.
// Usage: node laz_reference.js FILE.laz ...
const fs = require('fs');
const crypto = require('crypto');
const { createLazPerf } = require('laz-perf');

function decode(L, buf, hash) {
  const data = L._malloc(buf.length);
  L.HEAPU8.set(buf, data);
  const laz = new L.LASZip();
  laz.open(data, buf.length);
  const n = laz.getCount(), len = laz.getPointLength();
  const point = L._malloc(len);
  const t0 = process.cpuUsage();
  for (let i = 0; i < n; i++) {
    laz.getPoint(point);
    if (hash) hash.update(L.HEAPU8.subarray(point, point + len));
  }
  const cpu = process.cpuUsage(t0);
  laz.delete();
  L._free(point);
  L._free(data);
  return { n, seconds: (cpu.user + cpu.system) / 1e6 };
}

(async () => {
  const L = await createLazPerf();
  for (const file of process.argv.slice(2)) {
    const buf = fs.readFileSync(file);
    const hash = crypto.createHash('sha256');
    const { n } = decode(L, buf, hash);
    let best = Infinity;
    for (let rep = 0; rep < 5; rep++) best = Math.min(best, decode(L, buf, null).seconds);
    console.log(`laz-perf ${file.split('/').pop()}: ${n} points, ${(n / best / 1e6).toFixed(2)} M points/s ` +
                `per core, records sha256 ${hash.digest('hex')}`);
  }
})();
