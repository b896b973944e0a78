#!/usr/bin/env node
// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// Poses a .glb with three.js (GLTFLoader + AnimationMixer) in plain Node and writes the
// world-space vertex positions of every mesh primitive as three.js computes them.
//   node tests/js/three_pose.js FILE.glb OUT.json [--clip I] [--time T]
// (an embedded .gltf, buffers as data: URIs, works too; external files do not). Files with
// KHR_mesh_quantization and EXT_meshopt_compression are read with three's meshopt decoder.
// Without --clip the rest pose is written. The clip plays once and is clamped at its end
// (LoopOnce + clampWhenFinished), so --time past the end gives the last keyframe.
// Output: {"meshes":[{"node":N,"mesh":M,"primitive":P,"positions":[x,y,z,...]}, ...]} sorted by
// node, then primitive. Textures are neutralised (three.js needs DOM image APIs to decode
// them; positions do not depend on them). Exit status 0 = ok, 2 = failure.
'use strict';

const fs = require('fs');

function usage() {
  console.error('usage: node three_pose.js FILE.glb OUT.json [--clip I] [--time T]');
  process.exit(2);
}

function parseArgs(argv) {
  const out = {clip: -1, time: 0};
  const rest = [];
  for (let i = 0; i < argv.length; ++i) {
    if (argv[i] === '--clip' || argv[i] === '--time') {
      if (i + 1 >= argv.length) usage();
      const value = Number(argv[++i]);
      if (!Number.isFinite(value)) usage();
      if (argv[i - 1] === '--clip') out.clip = value; else out.time = value;
    } else {
      rest.push(argv[i]);
    }
  }
  if (rest.length !== 2) usage();
  out.input = rest[0];
  out.output = rest[1];
  return out;
}

// three's FileLoader (used for data: URIs of an embedded .gltf) reports progress with the DOM's
// ProgressEvent, which Node lacks.
if (typeof globalThis.ProgressEvent === 'undefined') {
  globalThis.ProgressEvent = class ProgressEvent extends Event {
    constructor(type, init = {}) {
      super(type);
      this.lengthComputable = !!init.lengthComputable;
      this.loaded = init.loaded || 0;
      this.total = init.total || 0;
    }
  };
}

// A GLTFLoader plugin that resolves every texture to null: no image is decoded.
function noTexturesPlugin() {
  return {name: 'DERMIS_no_textures', loadTexture: () => Promise.resolve(null)};
}

async function main() {
  const args = parseArgs(process.argv.slice(2));
  const THREE = await import('three');
  const {GLTFLoader} = await import('three/addons/loaders/GLTFLoader.js');
  // EXT_meshopt_compression (dermis export --compress), as a web page would set it up.
  const {MeshoptDecoder} = await import('three/addons/libs/meshopt_decoder.module.js');

  const bytes = fs.readFileSync(args.input);
  const buffer = bytes.buffer.slice(bytes.byteOffset, bytes.byteOffset + bytes.byteLength);
  const loader = new GLTFLoader();
  loader.register(noTexturesPlugin);
  loader.setMeshoptDecoder(MeshoptDecoder);
  const gltf = await new Promise((resolve, reject) => loader.parse(buffer, '', resolve, reject));

  const root = gltf.scene;
  if (args.clip >= 0) {
    if (!Number.isInteger(args.clip) || args.clip >= gltf.animations.length) {
      throw new Error(`clip ${args.clip} out of range (${gltf.animations.length} clips)`);
    }
    const mixer = new THREE.AnimationMixer(root);
    const action = mixer.clipAction(gltf.animations[args.clip]);
    action.setLoop(THREE.LoopOnce);
    action.clampWhenFinished = true;
    action.play();
    mixer.setTime(args.time);
  }
  root.updateMatrixWorld(true);

  const associations = gltf.parser.associations;
  const nodeOf = (object) => {
    for (let o = object; o; o = o.parent) {
      const a = associations.get(o);
      if (a && a.nodes !== undefined) return a.nodes;
    }
    return -1;
  };
  const meshes = [];
  const v = new THREE.Vector3();
  root.traverse((object) => {
    if (!object.isMesh) return;
    const a = associations.get(object);
    if (!a || a.meshes === undefined) return;
    if (object.isSkinnedMesh) object.skeleton.update();
    const position = object.geometry.getAttribute('position');
    const positions = new Array(position.count * 3);
    for (let i = 0; i < position.count; ++i) {
      object.getVertexPosition(i, v);  // morph targets, then skinning (mesh space)
      v.applyMatrix4(object.matrixWorld);
      positions[3 * i] = v.x;
      positions[3 * i + 1] = v.y;
      positions[3 * i + 2] = v.z;
    }
    meshes.push({
      node: nodeOf(object),
      mesh: a.meshes,
      primitive: a.primitives === undefined ? 0 : a.primitives,
      positions,
    });
  });
  meshes.sort((x, y) => x.node - y.node || x.primitive - y.primitive);
  fs.writeFileSync(args.output, JSON.stringify({meshes}));
}

main().catch((e) => {
  console.error(`three_pose.js: ${e && e.stack ? e.stack : e}`);
  process.exit(2);
});
