// Validates one WGSL file with Dawn's shader compiler (tint), as the `tint` command line would:
// `node check.mjs FILE.wgsl` parses and resolves it and prints every error; the exit status is
// 0 when tint accepts it, 1 when it rejects it, 2 when Dawn cannot start. Dawn runs on its
// null backend: the front end (tint) is the whole check, no GPU or driver is involved. One
// file per process: dawn.node 0.6.2 crashes after a few shader modules in one process.
import { readFileSync } from 'node:fs';
import { create, globals } from 'webgpu';

Object.assign(globalThis, globals);

const file = process.argv[2];
if (!file || process.argv.length > 3) {
  console.error('usage: node check.mjs FILE.wgsl');
  process.exit(2);
}
const code = readFileSync(file, 'utf8');
const adapter = await create(['backend=null']).requestAdapter();
if (!adapter) {
  console.error("Dawn's null backend gave no adapter");
  process.exit(2);
}
const device = await adapter.requestDevice();
// Errors arrive through the error scope; nothing may go to the console unasked.
device.addEventListener('uncapturederror', () => {});
device.pushErrorScope('validation');
const module = device.createShaderModule({ code });
const info = await module.getCompilationInfo();
const error = await device.popErrorScope();
const errors = info.messages.filter((m) => m.type === 'error');
if (errors.length > 0 || error) {
  console.error(`${file}: rejected by tint`);
  for (const m of errors) console.error(`  ${m.lineNum}:${m.linePos}: ${m.message}`);
  if (error && errors.length === 0) console.error(`  ${error.message}`);
  process.exit(1);
}
console.log(`${file}: accepted by tint (Dawn, npm webgpu)`);
process.exit(0);
