// Independent glTF check with the Khronos validator (npm gltf-validator):
// prints, per file, its errors, warnings and infos and the messages of the
// errors and warnings; exits 1 when any file has an error.
// Usage: node gltf_check.js FILE.glb...
const fs = require('fs');
const validator = require('gltf-validator');

async function main() {
  let failed = false;
  for (const path of process.argv.slice(2)) {
    const report = await validator.validateBytes(new Uint8Array(fs.readFileSync(path)));
    const i = report.issues;
    console.log(`${path}: ${i.numErrors} errors, ${i.numWarnings} warnings, ${i.numInfos} infos`);
    for (const m of i.messages.filter((m) => m.severity <= 1)) console.log(`  ${m.code}: ${m.message} (${m.pointer || ''})`);
    failed = failed || i.numErrors > 0;
  }
  process.exit(failed ? 1 : 0);
}
main().catch((e) => { console.error(e.message); process.exit(2); });
