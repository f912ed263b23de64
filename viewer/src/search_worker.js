// The search off the page's thread: this Web Worker owns the core (WebAssembly) and its Session,
// runs the anytime planner in slices of the user's budget (thesis §5.1, §6.1.2: a slice of work at
// a time, the best pose always available) and posts the best pose whenever the search moved. The
// page only draws, so neither a big mesh's setup (seconds at a million triangles) nor a candidate
// that overruns its slice can freeze it; between slices the worker reads the page's messages, so
// a drag reaches the planner within one slice (§6.5.6's restart rule then applies).
//
// Messages from the page: {type: 'open', hand, object, movement, seed, search},
// {type: 'shoulder', position}, {type: 'budget', ms}, {type: 'pause'}.
// To the page: 'ready', 'opened', 'shoulder', 'result' and 'error' (see each post below).
import init, { Session, builtin_hands, builtin_objects } from '../pkg/prehensile_wasm.js';
import wasmBytes from '../pkg/prehensile_wasm_bg.wasm';

let session = null;
let status = 'idle';
let budget = 4;
let lastProgress = '';
// Yields to the worker's message queue between slices without timers' 4 ms clamp.
const tick = new MessageChannel();
let scheduled = false;

function schedule() {
  if (!scheduled && session && status === 'searching') {
    scheduled = true;
    tick.port2.postMessage(null);
  }
}

// One slice of the search, then the result if the search moved (steps or evaluations; a
// restart's slices change neither until its start is evaluated) or stopped.
tick.port1.onmessage = () => {
  scheduled = false;
  if (!session || status !== 'searching') return;
  const t0 = performance.now();
  try {
    status = session.run_for(budget);
  } catch (e) {
    fail(e);
    return;
  }
  const sliceMs = performance.now() - t0;
  const progress = session.progress();
  if (progress !== lastProgress || status !== 'searching') {
    lastProgress = progress;
    try {
      post({ type: 'result', status, sliceMs, json: session.result_json() });
    } catch (e) {
      fail(e);
      return;
    }
  } else {
    post({ type: 'slice', sliceMs });
  }
  schedule();
};

function post(message, transfer = []) {
  self.postMessage(message, transfer);
}

// The search stops on an error the core threw; the page shows it.
function fail(e) {
  status = 'error';
  post({ type: 'error', message: String(e?.message ?? e) });
}

// Opens a hand and an object; on failure the search before it goes on (the page keeps showing it).
function open({ hand, object, movement, seed, search }) {
  let next;
  try {
    const includes = hand.includes ?? [];
    const joined = new Uint8Array(includes.reduce((n, f) => n + f.bytes.length, 0));
    includes.reduce((at, f) => { joined.set(f.bytes, at); return at + f.bytes.length; }, 0);
    const none = new Uint8Array();
    next = Session.open(hand.name, hand.bytes ?? none,
      includes.map((f) => f.name).join('\n'), joined, new Uint32Array(includes.map((f) => f.bytes.length)),
      object.name, object.bytes ?? none, movement, BigInt(seed));
  } catch (e) {
    post({ type: 'error', message: String(e?.message ?? e), during: 'open' });
    return;
  }
  session?.free();
  session = next;
  lastProgress = '';
  status = search ? 'searching' : 'paused';
  const arrays = {
    objectPositions: session.object_positions(),
    objectIndices: session.object_indices(),
    skinPositions: session.skin_positions(),
    skinJoints: session.skin_joints(),
    skinWeights: session.skin_weights(),
    skinIndices: session.skin_indices(),
    restInverses: session.rest_inverses(),
  };
  post({
    type: 'opened',
    status,
    movements: session.hand_movements(),
    movement: session.movement(),
    handName: session.hand_name(),
    shoulder: session.shoulder(),
    ...arrays,
  }, Object.values(arrays).map((a) => a.buffer));
  schedule();
}

// Moves the shoulder (object frame); the answer says whether the planner restarted.
function moveShoulder([x, y, z]) {
  if (!session) return;
  try {
    const restarted = session.set_shoulder(x, y, z);
    status = 'searching';
    lastProgress = '';
    post({ type: 'shoulder', restarted });
    schedule();
  } catch (e) {
    post({ type: 'error', message: String(e?.message ?? e) });
  }
}

self.onmessage = ({ data }) => {
  if (data.type === 'open') open(data);
  else if (data.type === 'shoulder') moveShoulder(data.position);
  else if (data.type === 'budget') budget = data.ms;
  else if (data.type === 'pause') status = 'paused';
};

init({ module_or_path: wasmBytes })
  .then(() => post({ type: 'ready', hands: builtin_hands(), objects: builtin_objects() }))
  .catch((e) => post({ type: 'error', message: `the core did not start: ${e?.message ?? e}` }));
