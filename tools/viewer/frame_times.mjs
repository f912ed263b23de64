// Search time per slice of the wasm session on your meshes, as the viewer's worker runs it:
// `Session.open` (the object's setup, timed apart), then `run_for(4)` once a slice until the
// search stops.
// Usage (after `bash tools/viewer/build.sh`): node tools/viewer/frame_times.mjs MESH... [--hand H]
import fs from 'node:fs';
import init, { Session } from '../../viewer/pkg/prehensile_wasm.js';

await init({ module_or_path: fs.readFileSync(new URL('../../viewer/pkg/prehensile_wasm_bg.wasm', import.meta.url)) });
const args = process.argv.slice(2);
const at = args.indexOf('--hand');
const hand = at >= 0 ? args.splice(at, 2)[1] : 'human';
for (const file of args) {
  const bytes = fs.readFileSync(file);
  const began = performance.now();
  const none = new Uint8Array();
  const session = Session.open(hand, none, '', none, new Uint32Array(), file.split('/').pop(), bytes, '', 1n);
  const setup = performance.now() - began;
  const times = [];
  let status = 'searching';
  while (status === 'searching' && times.length < 2000) {
    const t0 = performance.now();
    status = session.run_for(4);
    times.push(performance.now() - t0);
  }
  const sorted = [...times].sort((a, b) => a - b);
  const q = (f) => sorted[Math.min(sorted.length - 1, Math.floor(sorted.length * f))].toFixed(1);
  console.log(`${file}: setup ${setup.toFixed(0)} ms; ${times.length} frames to ${status}: median ${q(0.5)} ms, 90% ${q(0.9)} ms, most ${q(1)} ms`);
  session.free();
}
