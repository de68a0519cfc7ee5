#!/usr/bin/env node
// Runs the Khronos glTF validator (npm gltf-validator) on each file given:
//   node viewer/tools/validate_gltf.js PLAN.glb [MORE.glb ...]
// Prints one line per file (errors, warnings, infos, animations, nodes)
// and the error and warning messages; exits 1 when a file has an error or
// cannot be read, 2 on wrong usage.
'use strict';
const fs = require('fs');
const path = require('path');
let validator;
try {
  validator = require('gltf-validator');
} catch (e) {
  console.error('validate_gltf: gltf-validator is not installed; run scripts/setup.sh');
  process.exit(2);
}

async function validate(file) {
  const bytes = new Uint8Array(fs.readFileSync(file));
  const report = await validator.validateBytes(bytes, {maxIssues: 100});
  const issues = report.issues;
  const info = report.info || {};
  console.log(`${path.basename(file)}: ${issues.numErrors} errors, ${issues.numWarnings} warnings, ` +
              `${issues.numInfos} infos, ${info.animationCount || 0} animations, ` +
              `${info.drawCallCount || 0} draw calls, ${info.totalTriangleCount || 0} triangles`);
  for (const m of issues.messages)
    if (m.severity <= 1) console.log(`  ${m.severity === 0 ? 'error' : 'warning'} ${m.code} at ${m.pointer}: ${m.message}`);
  return issues.numErrors === 0;
}

(async () => {
  const files = process.argv.slice(2);
  if (files.length === 0) {
    console.error('usage: validate_gltf.js FILE.glb [...]');
    process.exit(2);
  }
  let ok = true;
  for (const file of files) {
    try {
      ok = (await validate(file)) && ok;
    } catch (e) {
      console.log(`${path.basename(file)}: cannot be validated: ${e.message || e}`);
      ok = false;
    }
  }
  process.exit(ok ? 0 : 1);
})();
