// artemis export --format glb checked by the Khronos glTF validator (npm gltf-validator):
// no errors, and the attributes the viewer and other tools read are there.
// Usage: node gltf.test.mjs ARTEMIS RUN_DIR OUT_DIR
import { execFileSync } from 'node:child_process';
import { mkdirSync, readFileSync, writeFileSync } from 'node:fs';
import path from 'node:path';
import { VIEWER_DIR, check, requireTools } from './harness.mjs';

requireTools({ validator: true });
const validator = await import(path.join(VIEWER_DIR, 'node_modules', 'gltf-validator', 'module.mjs'));
const [artemis, runDir, outDir] = process.argv.slice(2);
mkdirSync(outDir, { recursive: true });
const glb = path.join(outDir, 'living_map.glb');
execFileSync(artemis, ['--log-level', 'warn', 'export', runDir, '--format', 'glb', '-o', glb], { stdio: 'inherit' });
const report = await validator.validateBytes(new Uint8Array(readFileSync(glb)), { uri: glb, maxIssues: 100 });
writeFileSync(path.join(outDir, 'gltf_validator_report.json'), JSON.stringify(report, null, 2));
const issues = report.issues;
console.log(`validator ${report.validatorVersion}: ${issues.numErrors} errors, ${issues.numWarnings} warnings, ` +
            `${issues.numInfos} infos, ${issues.numHints} hints`);
for (const m of issues.messages.slice(0, 10)) console.log(`  ${m.severity} ${m.code} ${m.pointer || ''}: ${m.message}`);
check(issues.numErrors === 0, 'the GLB passes the Khronos glTF validator without errors');
check(issues.numWarnings === 0, 'and without warnings');
const info = report.info;
check(info.totalVertexCount > 1000 && info.drawCallCount === 1, `${info.totalVertexCount} vertices in one draw call`);
// The attributes, from the file's own JSON chunk (GLB: 12-byte header, then chunk length, type, JSON).
const bytes = readFileSync(glb);
const gltf = JSON.parse(bytes.subarray(20, 20 + bytes.readUInt32LE(12)).toString('utf8'));
const attributes = Object.keys(gltf.meshes[0].primitives[0].attributes).sort();
check(JSON.stringify(attributes) === JSON.stringify(['COLOR_0', 'POSITION', '_CLASS', '_CONFIDENCE']),
      `attributes ${attributes.join(', ')}`);
console.log('glTF test passed');
