// Validates .glb files with the Khronos glTF validator.
// Usage: node tools/gltf-validate/validate.mjs [file.glb ...]   (default: every .glb under assets/)
// Prints error/warning/info/hint counts per file (and the error/warning messages) and exits
// non-zero if any file has an error.
import { readFileSync, readdirSync, statSync } from 'node:fs';
import { join, dirname, resolve, relative } from 'node:path';
import { fileURLToPath } from 'node:url';
import validator from 'gltf-validator';

const repoRoot = resolve(dirname(fileURLToPath(import.meta.url)), '..', '..');

function findGlbs(dir) {
  const out = [];
  for (const name of readdirSync(dir).sort()) {
    const p = join(dir, name);
    if (statSync(p).isDirectory()) out.push(...findGlbs(p));
    else if (name.toLowerCase().endsWith('.glb')) out.push(p);
  }
  return out;
}

const files = process.argv.length > 2 ? process.argv.slice(2) : findGlbs(join(repoRoot, 'assets'));
if (files.length === 0) {
  console.error('no .glb files to validate');
  process.exit(1);
}

let failed = 0;
for (const file of files) {
  const report = await validator.validateBytes(new Uint8Array(readFileSync(file)), {
    uri: file,
    maxIssues: 0,
    // External resources are not used: everything is embedded in the GLB.
    externalResourceFunction: (uri) => Promise.reject(new Error(`external resource ${uri} not allowed`)),
  });
  const i = report.issues;
  const name = relative(process.cwd(), file) || file;
  console.log(`${name}: ${i.numErrors} errors, ${i.numWarnings} warnings, ${i.numInfos} infos, ${i.numHints} hints`);
  for (const m of i.messages) {
    if (m.severity <= 1) {
      const kind = m.severity === 0 ? 'error' : 'warning';
      console.log(`  ${kind} ${m.code}: ${m.message}${m.pointer ? ` (${m.pointer})` : ''}`);
    } else if (process.env.VERBOSE) {
      console.log(`  info ${m.code}: ${m.message}${m.pointer ? ` (${m.pointer})` : ''}`);
    }
  }
  if (i.numErrors > 0) failed++;
}
if (failed > 0) {
  console.error(`${failed} of ${files.length} file(s) failed validation`);
  process.exit(1);
}
console.log(`all ${files.length} file(s) valid`);
