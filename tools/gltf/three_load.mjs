// Loads GLB files with three.js's GLTFLoader (as a three.js app would) and prints what it finds;
// exits 1 if a file fails to load or has no animation.
// Usage: node tools/gltf/three_load.mjs FILE.glb...
import { readFile } from "node:fs/promises";
import { GLTFLoader } from "three/examples/jsm/loaders/GLTFLoader.js";

let failed = 0;
for (const file of process.argv.slice(2)) {
  const data = await readFile(file);
  const buffer = data.buffer.slice(data.byteOffset, data.byteOffset + data.byteLength);
  try {
    const gltf = await new Promise((resolve, reject) => new GLTFLoader().parse(buffer, "", resolve, reject));
    let meshes = 0, skinned = 0, bones = 0;
    gltf.scene.traverse((o) => { if (o.isMesh) meshes += 1; if (o.isSkinnedMesh) skinned += 1; if (o.isBone) bones += 1; });
    const clip = gltf.animations[0];
    console.log(`${file}: three.js loaded ${meshes} meshes (${skinned} skinned, ${bones} bones), animation ${clip ? clip.duration.toFixed(2) + " s, " + clip.tracks.length + " tracks" : "none"}`);
    if (!clip) failed += 1;
  } catch (e) {
    console.log(`${file}: three.js failed: ${e}`);
    failed += 1;
  }
}
process.exit(failed > 0 ? 1 : 0);
