// The grasp search live in the browser: the prehensile core compiled to WebAssembly runs the
// anytime planner in a Web Worker (search_worker.js), a slice of the user's budget at a time
// (thesis §5.1, §6.1.2), and three.js draws the best pose so far on the page's own thread, so the
// page never waits for the search. `window.prehensile` exposes the state for tests and the console.
import * as THREE from 'three';
import { OrbitControls } from 'three/examples/jsm/controls/OrbitControls.js';
import { TransformControls } from 'three/examples/jsm/controls/TransformControls.js';
import { GLTFLoader } from 'three/examples/jsm/loaders/GLTFLoader.js';
// The worker's bundle (the core inlined as bytes) as text, started from a blob: the page then
// runs from a folder opened as file:// as well as from `prehensile view`, with nothing to fetch.
import workerSource from '../build/search_worker.txt';

const $ = (id) => document.getElementById(id);
// sliceTimes: the worker's milliseconds per search slice since the last (re)start; frameTimes:
// the page's own work per animation frame (drawing the newest pose and the scene), which the
// search no longer adds to.
// playback: a saved animation (`grasp --glb`, `simulate --glb`) playing instead of the search;
// run: a simulation report (`simulate --out`) whose state-machine timeline labels it.
const state = { status: 'loading', result: null, sliceTimes: [], frameTimes: [], restarts: 0, error: null, shoulder: null, playback: null, run: null };
// Where the hand and the object come from: a built-in name (bytes null) or a file the user gave.
const sources = { hand: { name: 'human', bytes: null }, object: { name: 'mug', bytes: null } };
window.prehensile = { state };

// Everything runs once the core is compiled (a classic script, for file://: no top-level await).
async function main() {
  const worker = new Worker(URL.createObjectURL(new Blob([workerSource], { type: 'text/javascript' })));
  // The worker's first message: the core started, with its built-in hands and objects.
  const builtins = await new Promise((resolve, reject) => {
    worker.onmessage = ({ data }) => (data.type === 'ready' ? resolve(data) : reject(new Error(data.message)));
    worker.onerror = (e) => reject(new Error(`the search worker did not start: ${e.message}`));
  });
  worker.onerror = (e) => showError(`the search worker: ${e.message}`);
  for (const [id, names] of [['hand', builtins.hands], ['object', builtins.objects]]) {
    for (const name of names.split(',')) $(id).append(new Option(name, name));
  }
  $('object').value = 'mug';
  $('movement').append(new Option('power', 'power'));

  // Scene: the object frame is z-up (the search's default), as is the three.js world here.
  THREE.Object3D.DEFAULT_UP.set(0, 0, 1);
  const renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
  renderer.setPixelRatio(window.devicePixelRatio);
  $('view').append(renderer.domElement);
  const scene = new THREE.Scene();
  scene.background = new THREE.Color(0xf4f4f2);
  const camera = new THREE.PerspectiveCamera(40, 1, 0.005, 20);
  camera.position.set(0.35, -0.45, 0.3);
  const orbit = new OrbitControls(camera, renderer.domElement);
  scene.add(new THREE.HemisphereLight(0xffffff, 0x888877, 2.2));
  const sun = new THREE.DirectionalLight(0xffffff, 1.6);
  sun.position.set(1, -1, 2);
  scene.add(sun);
  const grid = new THREE.GridHelper(1, 20, 0xcccccc, 0xe4e4e4);
  grid.rotation.x = Math.PI / 2;
  grid.position.z = -0.1;
  scene.add(grid);

  // The object group moves when dragged; the hand is drawn in the object's frame inside it.
  const objectGroup = new THREE.Group();
  scene.add(objectGroup);
  const handGroup = new THREE.Group();
  objectGroup.add(handGroup);
  // A skinned hand's bones (glTF hands), posed by the result in the object's frame; its mesh sits
  // at the scene's origin, so that the bones alone place it (as a glTF skin).
  const boneGroup = new THREE.Group();
  objectGroup.add(boneGroup);
  let skinned = null;
  // The result the picture shows (drawn at the animation frame after it came).
  let drawn = null;
  const shoulderBall = new THREE.Mesh(new THREE.SphereGeometry(0.015), new THREE.MeshStandardMaterial({ color: 0xf08c00 }));
  scene.add(shoulderBall);
  const drag = new TransformControls(camera, renderer.domElement);
  drag.addEventListener('dragging-changed', (e) => { orbit.enabled = !e.value; });
  drag.addEventListener('objectChange', () => moved());
  scene.add(drag.getHelper ? drag.getHelper() : drag);
  renderer.domElement.addEventListener('dblclick', () => drag.attach(drag.object === objectGroup ? shoulderBall : objectGroup));

  const skin = new THREE.MeshStandardMaterial({ color: 0xd9a38b, roughness: 0.7 });
  const touching = new THREE.MeshStandardMaterial({ color: 0x3b82f6, roughness: 0.6 });
  const coneMaterial = new THREE.MeshBasicMaterial({ color: 0xd92d20, transparent: true, opacity: 0.25, side: THREE.DoubleSide, depthWrite: false });

  function resize() {
    const { clientWidth: w, clientHeight: h } = $('view');
    renderer.setSize(w, h, false);
    camera.aspect = w / h;
    camera.updateProjectionMatrix();
  }
  window.addEventListener('resize', resize);
  resize();

  function showError(e) {
    state.error = String(e?.message ?? e);
    $('error').textContent = state.error;
  }

  // Opens the hand and object in the worker; `showOpened` shows them once it has. With `saved`
  // (a saved result of built-in hand and object), the session is opened to draw the object, and
  // the saved result is shown instead of a search.
  let pendingSaved = null;
  // An open in progress: when it was asked for and how many frames the page drew since.
  let opening = null;
  function start(movement = $('movement').value, saved = null) {
    pendingSaved = saved;
    opening = { at: performance.now(), frames: 0 };
    $('note').textContent = `opening ${sources.hand.name} and ${sources.object.name}…`;
    worker.postMessage({
      type: 'open', hand: sources.hand, object: sources.object, movement,
      seed: Number($('seed').value) || 1, search: !saved,
    });
  }

  function showOpened(m) {
    state.opened = { ms: performance.now() - opening.at, frames: opening.frames };
    opening = null;
    $('note').textContent = '';
    stopPlayback();
    state.result = null;
    undrawn = false;
    state.restarts = 0;
    state.sliceTimes = [];
    $('error').textContent = '';
    state.error = null;
    $('movement').replaceChildren(...m.movements.split(',').map((name) => new Option(name, name)));
    $('movement').value = m.movement;
    objectGroup.clear();
    objectGroup.add(handGroup, boneGroup);
    buildSkin(m);
    state.handName = m.handName;
    // A skinned hand is drawn as its mesh; its capsules on demand.
    $('capsules').checked = !state.skinned;
    objectGroup.position.set(0, 0, 0);
    const geometry = new THREE.BufferGeometry();
    geometry.setAttribute('position', new THREE.BufferAttribute(m.objectPositions, 3));
    geometry.setIndex(new THREE.BufferAttribute(m.objectIndices, 1));
    geometry.computeVertexNormals();
    objectGroup.add(new THREE.Mesh(geometry, new THREE.MeshStandardMaterial({ color: 0x9aa5b1, roughness: 0.5, metalness: 0.1 })));
    state.shoulder = m.shoulder;
    const [x, y, z] = m.shoulder;
    shoulderBall.position.set(x, y, z);
    drag.attach(objectGroup);
    state.status = m.status;
    if (pendingSaved) showSaved(pendingSaved);
    pendingSaved = null;
  }

  // What the worker says: a session opened, a pose found, a slice done, a drag answered, an error.
  // The newest result is read as it comes, with its status, so that `state` never pairs a
  // search that has stopped with the pose from before its last restart; it is drawn at the next
  // animation frame.
  let undrawn = false;
  worker.onmessage = ({ data: m }) => {
    if (m.type === 'opened') showOpened(m);
    else if (m.type === 'error') {
      showError(m.message);
      if (m.during === 'open') {
        opening = null; // a refused file leaves the search before it running
        $('note').textContent = '';
      } else state.status = 'error';
    } else if (state.status === 'saved result' || state.status === 'playing') {
      // a result or slice of a search the page no longer shows
    } else if (m.type === 'shoulder') {
      if (m.restarted) {
        state.restarts += 1;
        state.sliceTimes = [];
      }
      state.status = 'searching';
    } else if (m.type === 'result' || m.type === 'slice') {
      state.sliceTimes.push(m.sliceMs);
      if (m.type === 'result') {
        try {
          state.result = JSON.parse(m.json);
          undrawn = true;
        } catch (e) {
          showError(e);
        }
        state.status = m.status;
      }
    }
  };
  $('budget').addEventListener('change', () => worker.postMessage({ type: 'budget', ms: Math.max(0.5, Number($('budget').value) || 4) }));

  // Dragging moves the shoulder relative to the object: the planner sees the shoulder in the
  // object's frame, and restarts when the reach direction turned too far.
  function moved() {
    if (!state.shoulder || state.status === 'saved result' || state.status === 'playing') return;
    const p = shoulderBall.position.clone().sub(objectGroup.position);
    state.shoulder = [p.x, p.y, p.z];
    worker.postMessage({ type: 'shoulder', position: state.shoulder });
  }
  // How well the skinned mesh follows the hand: the median distance, metres, from its posed
  // vertices to the surface of the nearest of the drawn result's capsules (object frame), over every
  // 7th vertex; null without a skinned hand.
  window.prehensile.skinDistance = () => {
    // Against the result the picture shows, whose pose the bones hold: `state.result` may be
    // a newer one from the worker, drawn only at the next animation frame.
    if (!skinned?.mesh.visible || !drawn) return null;
    objectGroup.updateMatrixWorld(true);
    const toObject = objectGroup.matrixWorld.clone().invert();
    const geometry = skinned.mesh.geometry;
    const d = [];
    for (let i = 0; i < geometry.attributes.position.count; i += 7) {
      const v = new THREE.Vector3().fromBufferAttribute(geometry.attributes.position, i);
      skinned.mesh.applyBoneTransform(i, v);
      v.applyMatrix4(toObject);
      let best = Infinity;
      for (const c of drawn.capsules) {
        const a = new THREE.Vector3(...c.a);
        const ab = new THREE.Vector3(...c.b).sub(a);
        const t = Math.min(1, Math.max(0, v.clone().sub(a).dot(ab) / Math.max(ab.lengthSq(), 1e-18)));
        best = Math.min(best, Math.abs(a.add(ab.multiplyScalar(t)).distanceTo(v) - c.radius));
      }
      d.push(best);
    }
    d.sort((x, y) => x - y);
    return d[Math.floor(d.length / 2)];
  };
  // What a drag of the object or of the shoulder ball does, callable from the console and tests.
  window.prehensile.moveObject = (dx, dy, dz) => { objectGroup.position.add(new THREE.Vector3(dx, dy, dz)); moved(); };
  window.prehensile.moveShoulder = (x, y, z) => { shoulderBall.position.set(x, y, z); moved(); };

  function capsuleMesh(c) {
    const a = new THREE.Vector3(...c.a);
    const b = new THREE.Vector3(...c.b);
    const length = a.distanceTo(b);
    const mesh = new THREE.Mesh(new THREE.CapsuleGeometry(c.radius, length, 4, 12), c.touching ? touching : skin);
    mesh.position.copy(a).add(b).multiplyScalar(0.5);
    if (length > 1e-9) mesh.quaternion.setFromUnitVectors(new THREE.Vector3(0, 1, 0), b.clone().sub(a).normalize());
    return mesh;
  }

  // The session's skinned mesh, if its hand has one (`m`: the worker's `opened` message): the
  // core's rest vertices, bone weights and inverse rest frames, bound to one three.js bone per
  // hand bone.
  function buildSkin(m) {
    if (skinned) {
      scene.remove(skinned.mesh);
      skinned.mesh.geometry.dispose();
      skinned = null;
    }
    boneGroup.clear();
    const positions = m.skinPositions;
    state.skinned = positions.length > 0;
    if (!state.skinned) return;
    const geometry = new THREE.BufferGeometry();
    geometry.setAttribute('position', new THREE.BufferAttribute(positions, 3));
    geometry.setAttribute('skinIndex', new THREE.Uint16BufferAttribute(m.skinJoints, 4));
    geometry.setAttribute('skinWeight', new THREE.BufferAttribute(m.skinWeights, 4));
    geometry.setIndex(new THREE.BufferAttribute(m.skinIndices, 1));
    geometry.computeVertexNormals();
    const inverses = m.restInverses;
    const bones = [];
    const boneInverses = [];
    for (let k = 0; k < inverses.length / 16; k++) {
      bones.push(new THREE.Bone());
      boneGroup.add(bones[k]);
      boneInverses.push(new THREE.Matrix4().fromArray(inverses, 16 * k));
    }
    const mesh = new THREE.SkinnedMesh(geometry, skin);
    mesh.frustumCulled = false;
    mesh.bind(new THREE.Skeleton(bones, boneInverses), new THREE.Matrix4());
    mesh.visible = false; // until a result poses it
    scene.add(mesh);
    skinned = { mesh, bones };
  }

  function drawResult(r) {
    drawn = r;
    handGroup.traverse((o) => o.geometry?.dispose());
    handGroup.clear();
    // The skin is the current search's hand's: a saved result of another hand shows its capsules.
    const skinFits = skinned && r.bones.length === skinned.bones.length && r.hand === state.handName;
    if (skinned) skinned.mesh.visible = Boolean(skinFits);
    if (skinFits) {
      r.bones.forEach((b, k) => {
        skinned.bones[k].position.set(...b.pose.position);
        skinned.bones[k].quaternion.set(...b.pose.rotation_xyzw);
      });
    }
    if ($('capsules').checked || !skinFits) for (const c of r.capsules) handGroup.add(capsuleMesh(c));
    const dot = new THREE.SphereGeometry(0.003);
    const red = new THREE.MeshBasicMaterial({ color: 0xd92d20 });
    // Each contact's friction cone (half-angle atan μ about its normal), drawn outside the object
    // with its apex at the contact: the directions of force the object can take there.
    const height = 0.015;
    const cone = new THREE.ConeGeometry(height * (r.friction ?? 0), height, 16, 1, true);
    cone.translate(0, -height / 2, 0); // apex at the origin, opening along −y
    for (const c of r.contacts) {
      const m = new THREE.Mesh(dot, red);
      m.position.set(...c.point);
      handGroup.add(m);
      const p = new THREE.Vector3(...c.point);
      const normal = new THREE.Vector3(...c.normal);
      const n = normal.clone().multiplyScalar(0.02);
      handGroup.add(new THREE.Line(new THREE.BufferGeometry().setFromPoints([p, p.clone().add(n)]), new THREE.LineBasicMaterial({ color: 0xd92d20 })));
      const f = new THREE.Mesh(cone, coneMaterial);
      f.position.copy(p);
      f.quaternion.setFromUnitVectors(new THREE.Vector3(0, 1, 0), normal); // opens along −normal: out of the object
      handGroup.add(f);
    }
  }

  function showInfo(r) {
    const rows = [
      ['status', `${state.status}${state.restarts ? `, ${state.restarts} restart(s)` : ''}`],
      ['grasp', r.valid ? '<span class="valid">valid</span>' : `<span class="invalid">not valid</span>: ${r.invalid_reason ?? ''}`],
      ['movement', r.movement],
      ['quality', r.quality?.toFixed(4) ?? '−∞'],
      ['fingers touching', r.fingers_touching.join(', ') || '—'],
      ['force closure', `${r.stability.force_closure ? 'yes' : 'no'} (μ = ${r.friction}; friction cones drawn at the contacts)`],
      ['ε (Ferrari–Canny)', r.stability.epsilon.toFixed(4)],
      ...Object.entries(r.terms).map(([k, v]) => [k, v.toFixed(4)]),
      ['steps / poses', `${r.stats.steps} / ${r.stats.evaluations}`],
      ['setup', `${state.opened.ms.toFixed(0)} ms in the worker, the page drawing ${state.opened.frames} frames meanwhile`],
      ['search per slice', `${median(state.sliceTimes).toFixed(2)} ms median (most ${Math.max(0, ...state.sliceTimes).toFixed(2)} ms over ${state.sliceTimes.length} slices, in a worker)`],
      ['page per frame', `${median(state.frameTimes.slice(-120)).toFixed(2)} ms median over the last ${Math.min(120, state.frameTimes.length)} frames`],
    ];
    $('info').innerHTML = rows.map(([k, v]) => `<tr><td>${k}</td><td>${v}</td></tr>`).join('');
  }

  const median = (xs) => (xs.length ? [...xs].sort((x, y) => x - y)[Math.floor(xs.length / 2)] : 0);

  // Each animation frame: the newest pose from the worker, if one came, then the picture. The
  // page's own time per frame is kept in frameTimes.
  function frame() {
    requestAnimationFrame(frame);
    const t0 = performance.now();
    if (opening) opening.frames += 1;
    if (undrawn) {
      undrawn = false;
      try {
        drawResult(state.result);
        showInfo(state.result);
      } catch (e) {
        showError(e);
      }
    }
    if (state.playback) advancePlayback();
    orbit.update();
    renderer.render(scene, camera);
    state.frameTimes.push(performance.now() - t0);
    if (state.frameTimes.length > 2000) state.frameTimes.splice(0, 1000);
  }

  // Files the user gave, by name: they join the hand and object lists, so that the lists always
  // show what is searched and the user can go back to a file.
  const given = { hand: new Map(), object: new Map() };
  function choose(id, source) {
    if (source.bytes) {
      given[id].set(source.name, source);
      if (![...$(id).options].some((o) => o.value === source.name)) $(id).append(new Option(source.name, source.name));
    }
    $(id).value = source.name;
  }
  $('hand').addEventListener('change', () => { sources.hand = given.hand.get($('hand').value) ?? { name: $('hand').value, bytes: null }; start(''); });
  $('object').addEventListener('change', () => { sources.object = given.object.get($('object').value) ?? { name: $('object').value, bytes: null }; start(); });
  $('movement').addEventListener('change', () => start());
  $('seed').addEventListener('change', () => start());

  // The user's own files, from the file chooser or dropped on the view: meshes replace the
  // object, hand files the hand; saved results (.json) are shown, saved animations (.glb with an
  // animation) played, simulation reports (.json) label the animation's timeline; what cannot be
  // read is reported on the page.
  const MESHES = ['obj', 'stl', 'ply', 'glb'];
  const HANDS = ['toml', 'urdf', 'xml'];
  async function openFiles(files) {
    let handChanged = false;
    let searchInputs = false;
    // MJCF and URDF files: the hand is the one no other includes; the rest are its includes,
    // and so are the mesh files it names (an MJCF's <mesh file="…">, a URDF's collision
    // <mesh filename="…">), which would otherwise replace the object.
    const xml = [];
    for (const file of files) {
      if (/\.(xml|urdf)$/i.test(file.name)) xml.push({ name: file.name, bytes: new Uint8Array(await file.arrayBuffer()) });
    }
    const texts = xml.map((f) => new TextDecoder().decode(f.bytes));
    const included = (f) => texts.some((t) => t.includes(`file="${f.name}"`) || t.includes(`filename="${f.name}"`) || t.includes(`/${f.name}"`));
    const meshAssets = [];
    for (const file of files) {
      const ext = file.name.split('.').pop().toLowerCase();
      if (xml.length > 0 && MESHES.includes(ext) && included(file)) {
        meshAssets.push({ name: file.name, bytes: new Uint8Array(await file.arrayBuffer()) });
      }
    }
    if (xml.length > 1 || meshAssets.length > 0) {
      const main = xml.find((f) => !included(f) && f.name.toLowerCase().endsWith('.urdf')) ?? xml.find((f) => !included(f)) ?? xml[0];
      sources.hand = { name: main.name, bytes: main.bytes, includes: [...xml.filter((f) => f !== main), ...meshAssets] };
      handChanged = true;
      searchInputs = true;
      const taken = new Set([...xml, ...meshAssets].map((f) => f.name));
      files = files.filter((f) => !taken.has(f.name));
    }
    for (const file of files) {
      const ext = file.name.split('.').pop().toLowerCase();
      const bytes = new Uint8Array(await file.arrayBuffer());
      if (ext === 'json') {
        if (!openSaved(file.name, bytes)) return;
      } else if (ext === 'glb' && await playIfAnimated(file.name, bytes)) {
        // played
      } else if (ext === 'glb' && hasSkin(bytes)) {
        sources.hand = { name: file.name, bytes };
        handChanged = true;
        searchInputs = true;
      } else if (MESHES.includes(ext)) {
        sources.object = { name: file.name, bytes };
        searchInputs = true;
      } else if (HANDS.includes(ext)) {
        sources.hand = { name: file.name, bytes };
        handChanged = true;
        searchInputs = true;
      } else {
        showError(`${file.name}: not a mesh (${MESHES.join(', ')}), hand file (${HANDS.join(', ')}, or a skinned .glb), saved result or run (.json) or animation (.glb)`);
        return;
      }
    }
    if (searchInputs) {
      choose('hand', sources.hand);
      choose('object', sources.object);
      start(handChanged ? '' : $('movement').value);
    }
  }

  // A saved grasp result (`prehensile grasp --out`): shown as it was found, the search stopped; a
  // built-in object is loaded to show it with. A simulation report (`simulate --out`): its state
  // timeline is kept for the animation. Returns false after reporting what is wrong.
  function openSaved(name, bytes) {
    let doc;
    try {
      doc = JSON.parse(new TextDecoder().decode(bytes));
    } catch (e) {
      showError(`${name}: not JSON: ${e.message}`);
      return false;
    }
    const schema = String(doc?.schema ?? '');
    if (schema.startsWith('prehensile.grasp/')) {
      if (builtins.objects.split(',').includes(doc.object) && builtins.hands.split(',').includes(doc.hand)) {
        sources.hand = { name: doc.hand, bytes: null };
        sources.object = { name: doc.object, bytes: null };
        $('hand').value = doc.hand;
        $('object').value = doc.object;
        start(doc.movement, doc);
      } else {
        worker.postMessage({ type: 'pause' });
        showSaved(doc);
      }
      return true;
    }
    if (schema.startsWith('prehensile.run/')) {
      state.run = doc;
      showTimeline();
      return true;
    }
    showError(`${name}: schema '${schema}' is neither a grasp result (prehensile.grasp/…) nor a simulation run (prehensile.run/…)`);
    return false;
  }

  // Shows a saved result as it was found, the search stopped.
  function showSaved(doc) {
    undrawn = false;
    state.status = 'saved result';
    state.result = doc;
    drawResult(doc);
    showInfo(doc);
  }

  // Whether a GLB's JSON chunk declares a skin: a rigged hand rather than an object's mesh.
  function hasSkin(bytes) {
    if (bytes.length < 20) return false;
    const view = new DataView(bytes.buffer, bytes.byteOffset, bytes.byteLength);
    const length = view.getUint32(12, true);
    if (view.getUint32(0, true) !== 0x46546c67 || view.getUint32(16, true) !== 0x4e4f534a || 20 + length > bytes.length) return false;
    try {
      return (JSON.parse(new TextDecoder().decode(bytes.subarray(20, 20 + length))).skins ?? []).length > 0;
    } catch {
      return false;
    }
  }

  // Plays a GLB that carries an animation (what `grasp --glb` and `simulate --glb` write) in place
  // of the live search; false for a GLB without one (a mesh).
  async function playIfAnimated(name, bytes) {
    let gltf;
    try {
      gltf = await new GLTFLoader().parseAsync(bytes.buffer.slice(bytes.byteOffset, bytes.byteOffset + bytes.byteLength), '');
    } catch (e) {
      return false; // not readable by three.js: let the core's reader report it as a mesh
    }
    if (!gltf.animations.length) return false;
    stopPlayback();
    worker.postMessage({ type: 'pause' });
    state.status = 'playing';
    objectGroup.visible = false;
    if (skinned) skinned.mesh.visible = false;
    drag.detach();
    const mixer = new THREE.AnimationMixer(gltf.scene);
    for (const clip of gltf.animations) mixer.clipAction(clip).play();
    const duration = Math.max(...gltf.animations.map((c) => c.duration));
    scene.add(gltf.scene);
    state.playback = { name, root: gltf.scene, mixer, duration, time: 0, last: performance.now() };
    $('timeline').hidden = false;
    $('time').max = String(duration);
    showTimeline();
    return true;
  }

  function stopPlayback() {
    if (!state.playback) return;
    scene.remove(state.playback.root);
    state.playback = null;
    objectGroup.visible = true;
    $('timeline').hidden = true;
  }

  // Advances the animation by the frame's time (looping) unless the slider holds it.
  function advancePlayback() {
    const p = state.playback;
    const now = performance.now();
    if (!$('pause').checked) p.time = (p.time + (now - p.last) / 1000) % p.duration;
    else p.time = Number($('time').value);
    p.last = now;
    p.mixer.setTime(p.time);
    $('time').value = String(p.time);
    $('clock').textContent = `${p.time.toFixed(2)} s of ${p.duration.toFixed(2)} s${currentState(p.time)}`;
  }

  // The simulation's state-machine state at time t (the last event at or before it), if a run
  // report was given.
  function currentState(t) {
    const events = state.run?.cases?.flatMap((c) => (c.timeline ?? []).map((e) => ({ ...e, label: c.label }))) ?? [];
    if (!events.length) return '';
    const past = events.filter((e) => e.time <= t + 1e-9);
    if (!past.length) return ` — ${events[0].label}: hand ${events[0].hand} before ${events[0].state}`;
    const e = past[past.length - 1];
    return ` — ${e.label}: hand ${e.hand} ${e.state}`;
  }

  // The run report's timeline, in the panel.
  function showTimeline() {
    if (!state.run) return;
    const rows = [['simulation', `${state.run.scenario}, hand ${state.run.hand}, held: ${state.run.held ? 'yes' : 'no'}`]];
    for (const c of state.run.cases ?? []) {
      rows.push([c.label, `held ${c.held ? 'yes' : 'no'}, slip ${(1000 * c.object_slip_m).toFixed(1)} mm`]);
      for (const e of c.timeline ?? []) rows.push([`  ${e.time.toFixed(3)} s`, `hand ${e.hand}: ${e.state}`]);
    }
    $('info').innerHTML = rows.map(([k, v]) => `<tr><td>${k}</td><td>${v}</td></tr>`).join('');
  }
  $('file').addEventListener('change', () => openFiles([...$('file').files]));
  $('view').addEventListener('dragover', (e) => e.preventDefault());
  $('view').addEventListener('drop', (e) => { e.preventDefault(); openFiles([...e.dataTransfer.files]); });
  $('capsules').addEventListener('change', () => state.result && drawResult(state.result));
  start();
  frame();

  // Files named on `prehensile view`'s command line, opened as if dropped on the page.
  const opened = location.protocol === 'file:' ? null : await fetch('open/list.json').catch(() => null);
  if (opened?.ok) {
    const names = await opened.json();
    const files = await Promise.all(names.map(async (name, k) => new File([await (await fetch(`open/${k}`)).arrayBuffer()], name)));
    if (files.length) await openFiles(files);
  }
}
main().catch((e) => {
  document.getElementById('error').textContent = String(e?.message ?? e);
  throw e;
});
