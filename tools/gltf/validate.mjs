// The Khronos glTF validator on every file named: prints each file's counts and first
// messages; exits 1 if any file has an error or a warning.
// Usage: node tools/gltf/validate.mjs FILE.glb... (after `npm ci` in tools/gltf).
import validator from 'gltf-validator';
import fs from 'fs';
let bad = 0;
for (const f of process.argv.slice(2)) {
  const data = new Uint8Array(fs.readFileSync(f));
  const report = await validator.validateBytes(data, { maxIssues: 50 });
  const i = report.issues;
  console.log(`${f}: ${i.numErrors} errors, ${i.numWarnings} warnings, ${i.numInfos} infos, ${i.numHints} hints`);
  for (const m of i.messages.slice(0, 10)) console.log(`  ${m.severity} ${m.code} ${m.pointer ?? ''}: ${m.message}`);
  if (i.numErrors + i.numWarnings > 0) bad++;
}
process.exit(bad ? 1 : 0);
