// The WebAssembly build gives the native build's grasps: the same hand, object, movement and
// seed searched to the end by the wasm Session (in Node) and by `prehensile grasp`, compared
// field by field (the search's wall time aside). Every discrete field (validity, movement,
// fingers, step and pose counts) must be equal and every number equal to 1e-9: the two builds
// differ in the last digit of some numbers because the browser's sin, cos and acos are not
// glibc's, and had that sent the search down another path the counts would differ.
import assert from 'node:assert/strict';
import { spawnSync } from 'node:child_process';
import fs from 'node:fs';
import init, { Session } from '../pkg/prehensile_wasm.js';

await init({ module_or_path: fs.readFileSync(new URL('../pkg/prehensile_wasm_bg.wasm', import.meta.url)) });
const cli = new URL('../../target/release/prehensile', import.meta.url).pathname;
// The last case is a mesh file with holes: its inside comes from winding numbers, integrated
// line by line on rayon's threads natively and in turn in wasm (rayon's fallback without
// threads), which must give the same object.
const openCup = new URL('../../crates/prehensile-core/tests/data/winding/open_cup.obj', import.meta.url).pathname;
const cases = [['human', 'mug', 'power', 2], ['human', 'sphere', 'precision', 1], ['robot3', 'torus', 'close', 3], ['cartoon4', 'box', 'close', 1], ['human', openCup, 'power', 1]];
for (const [hand, object, movement, seed] of cases) {
  // Timed from the object's setup on, as the native search's own clock (stats.seconds, which
  // includes the initial approximation) plus its object setup.
  const began = performance.now();
  const session = object.endsWith('.obj')
    ? Session.open(hand, new Uint8Array(), '', new Uint8Array(), new Uint32Array(), object.split('/').pop(), fs.readFileSync(object), movement, BigInt(seed))
    : new Session(hand, object, movement, BigInt(seed));
  session.run_to_end();
  const wasmMs = performance.now() - began;
  const wasm = JSON.parse(session.result_json());
  const run = spawnSync(cli, ['grasp', '--hand', hand, '--object', object, '--movement', movement, '--seed', String(seed), '--threads', '1']);
  assert.ok(run.status === 0 || run.status === 1, `${cli}: ${run.stderr}`);
  const native = JSON.parse(run.stdout.toString());
  const nativeMs = native.stats.seconds * 1e3;
  // A seven-pose step: each search's own clock over its steps (the initial approximation
  // included, a small share over hundreds of steps).
  const stepMs = [wasm, native].map((r) => (r.stats.seconds * 1e3) / Math.max(1, r.stats.steps));
  delete wasm.stats.seconds;
  delete native.stats.seconds;
  if (object.endsWith('.obj')) {
    // The viewer names a dropped object by its file name (its list shows it), the CLI by the
    // file's stem.
    assert.strictEqual(wasm.object, `${native.object}.obj`);
    delete wasm.object;
    delete native.object;
  }
  const label = `${hand} ${object.split('/').pop()} ${movement} seed ${seed}`;
  let worst = 0;
  const same = (a, b, at) => {
    if (typeof a === 'number' && typeof b === 'number') {
      const gap = Math.abs(a - b) / Math.max(1, Math.abs(a));
      // The load ratios are linear programs over nearly degenerate wrench sets: a last-digit
      // difference in the contacts moves them by up to about 1e-4.
      const tolerance = at.includes('.load_ratio.') ? 1e-3 : 1e-9;
      if (tolerance === 1e-9) worst = Math.max(worst, gap);
      assert.ok(gap <= tolerance, `${label}: ${at} is ${a} in wasm, ${b} native`);
    } else if (a && typeof a === 'object') {
      assert.deepStrictEqual(Object.keys(a).sort(), Object.keys(b ?? {}).sort(), `${label}: ${at}`);
      for (const k of Object.keys(a)) same(a[k], b[k], `${at}.${k}`);
    } else {
      assert.strictEqual(a, b, `${label}: ${at}`);
    }
  };
  same(wasm, native, 'result');
  console.log(`${hand} on ${object.split('/').pop()} (${movement}, seed ${seed}): wasm and native agree (${wasm.valid ? 'valid' : 'not valid'}, ${wasm.stats.steps} steps, largest relative difference ${worst.toExponential(1)}); search ${wasmMs.toFixed(1)} ms in wasm, ${nativeMs.toFixed(1)} ms native (${(wasmMs / nativeMs).toFixed(2)}x); per step ${stepMs[0].toFixed(3)} ms in wasm, ${stepMs[1].toFixed(3)} ms native (${(stepMs[0] / stepMs[1]).toFixed(2)}x)`);
}
