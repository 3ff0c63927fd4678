// Golden skinned vertex positions from an independent implementation (three.js GLTFLoader +
// SkinnedMesh.applyBoneTransform), for dermis's tests/anim_golden.rs.
//
// Usage: node make-golden.mjs [external-assets-dir] [out-dir]
//   defaults: ../../../shared/assets-external  ../../tests/data/golden
//
// What is computed (the glTF 2.0 spec's skinning): for the first node that has both a mesh
// and a skin, for clip 0 at several times, the world-space position of sampled vertices:
//     world = Σ_i w_i · jointWorld[j_i] · inverseBind[j_i] · v
// The skinned mesh node's own transform (and its parents') is NOT applied. three.js binds
// glTF skinned meshes with an identity bindMatrix (asserted below) in "attached" bind mode,
// where bindMatrixInverse = inverse(mesh.matrixWorld): applyBoneTransform() returns
// inverse(meshWorld) · Σ w·boneWorld·boneInverse·v (mesh-local, for the GPU path, which then
// multiplies by meshWorld), so multiplying its result by mesh.matrixWorld gives exactly the
// spec's sum. Joint world matrices include every ancestor node (scene roots such as
// CesiumMan's Z_UP node); the three.js scene root itself is an identity Group.
import fs from 'node:fs';
import path from 'node:path';
import { fileURLToPath } from 'node:url';
import * as THREE from 'three';
import { GLTFLoader } from 'three/examples/jsm/loaders/GLTFLoader.js';

const here = path.dirname(fileURLToPath(import.meta.url));
const assets = path.resolve(process.argv[2] ?? path.join(here, '../../../shared/assets-external'));
const outDir = path.resolve(process.argv[3] ?? path.join(here, '../../tests/data/golden'));

const MODELS = [
  'CesiumMan/CesiumMan.glb',
  'Fox/Fox.glb',
  'RiggedFigure/RiggedFigure.glb',
  'RiggedSimple/RiggedSimple.glb',
  'QuaterniusWomanTankTop/WomanTankTop.glb',
];
const TIMES = [0, 0.25, 0.5, 1.0];
const CLIP = 0;
const SAMPLES = 64; // vertices per time, spread evenly over the mesh

// Re-pack a GLB with all textures/images removed (three cannot decode images under node).
function stripTextures(buf) {
  const dv = new DataView(buf.buffer, buf.byteOffset, buf.byteLength);
  if (dv.getUint32(0, true) !== 0x46546c67) throw new Error('not a GLB');
  const jsonLen = dv.getUint32(12, true);
  const json = JSON.parse(new TextDecoder().decode(buf.subarray(20, 20 + jsonLen)));
  const rest = buf.subarray(20 + jsonLen); // BIN chunk (header included), if any
  delete json.textures;
  delete json.images;
  delete json.samplers;
  for (const m of json.materials ?? []) {
    for (const k of ['normalTexture', 'occlusionTexture', 'emissiveTexture']) delete m[k];
    if (m.pbrMetallicRoughness) {
      delete m.pbrMetallicRoughness.baseColorTexture;
      delete m.pbrMetallicRoughness.metallicRoughnessTexture;
    }
    delete m.extensions;
  }
  let text = JSON.stringify(json);
  while (text.length % 4) text += ' ';
  const jsonBytes = new TextEncoder().encode(text);
  const out = new Uint8Array(20 + jsonBytes.length + rest.length);
  const o = new DataView(out.buffer);
  o.setUint32(0, 0x46546c67, true);
  o.setUint32(4, 2, true);
  o.setUint32(8, out.length, true);
  o.setUint32(12, jsonBytes.length, true);
  o.setUint32(16, 0x4e4f534a, true);
  out.set(jsonBytes, 20);
  out.set(rest, 20 + jsonBytes.length);
  return { arrayBuffer: out.buffer, json };
}

function parse(arrayBuffer) {
  return new Promise((resolve, reject) => new GLTFLoader().parse(arrayBuffer, '', resolve, reject));
}

function round(x) {
  return Math.round(x * 1e7) / 1e7;
}

async function golden(name) {
  const file = fs.readFileSync(path.join(assets, name));
  const { arrayBuffer, json } = stripTextures(new Uint8Array(file));
  const gltf = await parse(arrayBuffer);
  const parser = gltf.parser;

  const nodeIndex = json.nodes.findIndex((n) => n.mesh !== undefined && n.skin !== undefined);
  if (nodeIndex < 0) throw new Error(`${name}: no skinned mesh node`);
  const meshIndex = json.nodes[nodeIndex].mesh;

  // The three objects of that node: the SkinnedMesh itself (one primitive) or a Group of them.
  let nodeObject = null;
  gltf.scene.traverse((o) => {
    const a = parser.associations.get(o);
    if (a && a.nodes === nodeIndex) nodeObject = o;
  });
  if (!nodeObject) throw new Error(`${name}: node ${nodeIndex} not in the scene`);
  const prims = [];
  const consider = (o) => {
    const a = parser.associations.get(o);
    if (o.isSkinnedMesh && a && a.meshes === meshIndex) prims.push({ mesh: o, primitive: a.primitives });
  };
  if (nodeObject.isSkinnedMesh) consider(nodeObject);
  else nodeObject.children.forEach(consider);
  prims.sort((a, b) => a.primitive - b.primitive);
  if (prims.length !== json.meshes[meshIndex].primitives.length) {
    throw new Error(`${name}: expected ${json.meshes[meshIndex].primitives.length} primitives, found ${prims.length}`);
  }
  for (const p of prims) {
    if (!p.mesh.bindMatrix.equals(new THREE.Matrix4())) throw new Error(`${name}: non-identity bindMatrix`);
  }
  // Concatenated vertex list (primitive order), as dermis's skin_positions returns it.
  const table = [];
  for (const p of prims) {
    const n = p.mesh.geometry.attributes.position.count;
    for (let i = 0; i < n; i++) table.push([p.mesh, i]);
  }
  const picks = [];
  for (let k = 0; k < SAMPLES; k++) picks.push(Math.floor((k * (table.length - 1)) / (SAMPLES - 1)));

  const clip = gltf.animations[CLIP];
  const bindings = clip.tracks.map((track) => ({
    interpolant: track.createInterpolant(),
    binding: new THREE.PropertyBinding(gltf.scene, track.name),
  }));
  const samples = [];
  for (const t of TIMES) {
    for (const { interpolant, binding } of bindings) binding.setValue(interpolant.evaluate(t), 0);
    gltf.scene.updateMatrixWorld(true);
    const v = new THREE.Vector3();
    const vertices = picks.map((index) => {
      const [mesh, i] = table[index];
      v.fromBufferAttribute(mesh.geometry.attributes.position, i);
      mesh.applyBoneTransform(i, v).applyMatrix4(mesh.matrixWorld);
      return { index, position: [round(v.x), round(v.y), round(v.z)] };
    });
    samples.push({ time: t, vertices });
  }
  return {
    model: name,
    generator: `three.js r${THREE.REVISION} GLTFLoader + SkinnedMesh.applyBoneTransform (tools/skin-golden)`,
    clip: CLIP,
    clip_duration: clip.duration,
    node: nodeIndex,
    mesh: meshIndex,
    vertex_count: table.length,
    samples,
  };
}

fs.mkdirSync(outDir, { recursive: true });
for (const name of MODELS) {
  const result = await golden(name);
  const out = path.join(outDir, path.basename(name, '.glb') + '.json');
  fs.writeFileSync(out, JSON.stringify(result, null, 1) + '\n');
  console.log(`${name}: ${result.vertex_count} vertices, ${result.samples.length} times -> ${path.relative(process.cwd(), out)}`);
}
