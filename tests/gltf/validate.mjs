// The Khronos glTF validator over .glb files (crates/cli/tests/gltf_validator.rs).
// Usage: node validate.mjs FILE.glb ... — prints each file's messages; exit 1 if any.
import validator from 'gltf-validator';
import fs from 'fs';
let bad = 0;
for (const path of process.argv.slice(2)) {
  const report = await validator.validateBytes(new Uint8Array(fs.readFileSync(path)));
  const msgs = report.issues.messages;
  const n = report.issues;
  console.log(`${path}: ${n.numErrors} errors, ${n.numWarnings} warnings, ${n.numInfos} infos, ${n.numHints} hints`);
  for (const m of msgs) console.log(`  ${m.code} ${m.pointer || ''} ${m.message}`);
  if (msgs.length) bad++;
}
process.exit(bad ? 1 : 0);
