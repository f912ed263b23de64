// The page's frame gaps (one requestAnimationFrame to the next) while the search worker opens and
// searches your meshes, in headless Chromium, served by `prehensile view`; then the same page's
// gaps with the search done (drawing alone) for comparison. The worker's slice times are reported
// beside them. Usage (after `bash tools/viewer/build.sh` and `cargo build --release -p
// prehensile-cli`): node tools/viewer/page_frames.mjs MESH...
import { spawn } from 'node:child_process';
// playwright-core is the viewer's dev dependency (`npm ci` in viewer/, which build.sh runs).
import { chromium } from '../../viewer/node_modules/playwright-core/index.mjs';

const cli = new URL('../../target/release/prehensile', import.meta.url).pathname;
const dist = new URL('../../viewer/dist', import.meta.url).pathname;
const server = spawn(cli, ['view', '--dir', dist, '--port', '0'], { stdio: ['ignore', 'pipe', 'inherit'] });
const url = await new Promise((resolve) => server.stdout.on('data', (d) => {
  const m = /http:\/\/[0-9.:]+\//.exec(String(d));
  if (m) resolve(m[0]);
}));
const browser = await chromium.launch({
  executablePath: process.env.CHROMIUM ?? '/usr/bin/chromium',
  args: ['--no-sandbox', '--enable-unsafe-swiftshader', '--use-angle=swiftshader'],
});
// Gaps between animation frames, recorded into window.gaps until window.stopGaps.
const recordGaps = () => {
  window.gaps = [];
  window.stopGaps = false;
  let last = performance.now();
  const next = () => {
    const now = performance.now();
    window.gaps.push(now - last);
    last = now;
    if (!window.stopGaps) requestAnimationFrame(next);
  };
  requestAnimationFrame(next);
};
const summary = (xs) => {
  const s = [...xs].sort((a, b) => a - b);
  const q = (p) => s[Math.floor(p * (s.length - 1))].toFixed(1);
  return `median ${q(0.5)} ms, 90% ${q(0.9)}, most ${q(1)} over ${s.length}`;
};
try {
  const page = await browser.newPage({ viewport: { width: 800, height: 500 } });
  await page.goto(url);
  await page.waitForFunction(() => window.prehensile?.state?.result?.valid === true, null, { timeout: 120_000 });
  for (const file of process.argv.slice(2)) {
    const name = file.split('/').pop();
    await page.evaluate(recordGaps);
    await page.setInputFiles('#file', file);
    await page.waitForFunction((n) => window.prehensile.state.result?.object === n && window.prehensile.state.status !== 'searching', name, { timeout: 600_000 });
    const busy = await page.evaluate(() => {
      window.stopGaps = true;
      return { gaps: window.gaps, opened: window.prehensile.state.opened, slices: window.prehensile.state.sliceTimes };
    });
    await page.evaluate(recordGaps);
    await page.waitForTimeout(2000);
    const idle = await page.evaluate(() => { window.stopGaps = true; return window.gaps; });
    console.log(`${name}: setup ${busy.opened.ms.toFixed(0)} ms in the worker; page frame gaps while ` +
      `opening and searching: ${summary(busy.gaps)}; with the search done: ${summary(idle)}; ` +
      `the worker's slices: ${summary(busy.slices)}`);
  }
} finally {
  await browser.close();
  server.kill();
}
