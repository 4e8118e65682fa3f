// Drives `gslift view` in headless Chromium over the DevTools protocol (--remote-debugging-pipe:
// NUL-terminated JSON on file descriptors 3 and 4), with node's standard library alone, so no npm
// package is needed. It does what a person would: loads the page, orbits with the mouse, clicks a
// known object of the capture's first view, moves the threshold slider, types a text query,
// exports the selection and the view, and writes screenshots. It prints one JSON line of what it
// measured; tests/viewer/viewer_browser_test.cpp judges it.
//
//   node drive_viewer.mjs --gslift BIN --run RUN_FOLDER --chromium EXE --out DIR
//                         --class "anesthesia machine" --query ventilator [--tau T]
import {spawn} from 'node:child_process';
import fs from 'node:fs';
import path from 'node:path';

const args = {};
for (let i = 2; i + 1 < process.argv.length; i += 2) args[process.argv[i].slice(2)] = process.argv[i + 1];
const out = args.out;
fs.mkdirSync(out, {recursive: true});
const result = {steps: []};
function step(name) { result.steps.push(name); }
// Whatever hangs (a browser that never answers), the script ends and says where it was.
const children = [];
setTimeout(() => {
  result.ok = false;
  result.error = 'watchdog: no progress after ' + (result.steps.at(-1) || 'the start');
  console.log(JSON.stringify(result));
  for (const c of children) c.kill('SIGKILL');
  process.exit(1);
}, Number(args.timeout_ms || 90000)).unref();

// The viewer, on a free port; its first stdout line names the URL.
const viewer = spawn(args.gslift, ['view', args.run, '--port', '0', '--threads', '2'],
                     {stdio: ['ignore', 'pipe', 'pipe']});
children.push(viewer);
let viewerErr = '';
viewer.stderr.on('data', d => { viewerErr += d; });
const url = await new Promise((resolve, reject) => {
  let text = '';
  viewer.stdout.on('data', d => {
    text += d;
    const m = text.match(/http:\/\/127\.0\.0\.1:\d+\//);
    if (m) resolve(m[0]);
  });
  viewer.on('exit', code => reject(new Error('gslift view exited with ' + code + ': ' + viewerErr)));
});
step('served ' + url);

const profile = fs.mkdtempSync(path.join(out, 'profile-'));
const chrome = spawn(args.chromium, ['--headless', '--disable-gpu', '--no-sandbox', '--disable-dev-shm-usage',
  '--no-first-run', '--remote-debugging-pipe', '--user-data-dir=' + profile, '--window-size=1400,1800',
  'about:blank'], {stdio: ['ignore', 'ignore', 'ignore', 'pipe', 'pipe']});
children.push(chrome);
const toChrome = chrome.stdio[3], fromChrome = chrome.stdio[4];
let buffer = Buffer.alloc(0), nextId = 1;
const pending = new Map(), consoleMessages = [];
fromChrome.on('data', chunk => {
  buffer = Buffer.concat([buffer, chunk]);
  for (let end; (end = buffer.indexOf(0)) >= 0;) {
    const msg = JSON.parse(buffer.subarray(0, end).toString());
    buffer = buffer.subarray(end + 1);
    if (msg.id && pending.has(msg.id)) {
      const {resolve, reject} = pending.get(msg.id);
      pending.delete(msg.id);
      if (msg.error) reject(new Error(JSON.stringify(msg.error))); else resolve(msg.result);
    } else if (msg.method === 'Runtime.exceptionThrown') {
      consoleMessages.push('exception: ' + JSON.stringify(msg.params.exceptionDetails).slice(0, 300));
    } else if (msg.method === 'Runtime.consoleAPICalled' || msg.method === 'Log.entryAdded') {
      consoleMessages.push(JSON.stringify(msg.params).slice(0, 300));
    }
  }
});
function send(method, params = {}, sessionId = undefined) {
  const id = nextId++;
  toChrome.write(JSON.stringify({id, method, params, sessionId}) + '\0');
  return new Promise((resolve, reject) => pending.set(id, {resolve, reject}));
}

let session;
const page = (method, params) => send(method, params, session);
async function evaluate(expression) {
  const r = await page('Runtime.evaluate', {expression, returnByValue: true, awaitPromise: true});
  if (r.exceptionDetails) throw new Error(expression.slice(0, 80) + ': ' + JSON.stringify(r.exceptionDetails).slice(0, 400));
  return r.result.value;
}
// Waits for a condition of the page (polled; the page offers no event for "frame drawn").
async function until(expression, what, ms = 20000) {
  const t0 = Date.now();
  while (Date.now() - t0 < ms) {
    if (await evaluate(expression)) return;
    await new Promise(r => setTimeout(r, 25));
  }
  throw new Error('timed out waiting for ' + what);
}
async function mouse(type, x, y, modifiers = 0) {
  await page('Input.dispatchMouseEvent', {type, x, y, button: 'left', buttons: type === 'mouseReleased' ? 0 : 1,
                                         clickCount: 1, modifiers});
}
async function screenshot(name, clip) {
  const r = await page('Page.captureScreenshot', clip ? {format: 'png', clip: {...clip, scale: 1}} : {format: 'png', captureBeyondViewport: true});
  const file = path.join(out, name);
  fs.writeFileSync(file, Buffer.from(r.data, 'base64'));
  return file;
}

// Page-side helpers: statistics of the frame canvas, and the IoU of the selection with a class's
// ground truth in a capture view, both from the server's PNG masks.
const helpers = `
window.testing = {
  canvasStats() {
    const c = document.getElementById('frame'), d = c.getContext('2d').getImageData(0, 0, c.width, c.height).data;
    let s = 0, s2 = 0; const colours = new Set();
    for (let i = 0; i < d.length; i += 4) {
      const l = 0.299 * d[i] + 0.587 * d[i + 1] + 0.114 * d[i + 2];
      s += l; s2 += l * l; colours.add((d[i] >> 3) << 10 | (d[i + 1] >> 3) << 5 | (d[i + 2] >> 3));
    }
    const n = d.length / 4;
    return {mean: s / n, std: Math.sqrt(Math.max(0, s2 / n - (s / n) ** 2)), colours: colours.size};
  },
  snapshot() { const c = document.getElementById('frame'); this.saved = c.getContext('2d').getImageData(0, 0, c.width, c.height).data; },
  changedSinceSnapshot() {
    const c = document.getElementById('frame'), d = c.getContext('2d').getImageData(0, 0, c.width, c.height).data;
    let diff = 0; for (let i = 0; i < d.length; i++) diff += Math.abs(d[i] - this.saved[i]);
    return diff / d.length;
  },
  async maskOf(url) {
    const bitmap = await createImageBitmap(await (await fetch(url)).blob());
    const c = new OffscreenCanvas(bitmap.width, bitmap.height), g = c.getContext('2d');
    g.drawImage(bitmap, 0, 0);
    const d = g.getImageData(0, 0, bitmap.width, bitmap.height).data, m = new Uint8Array(bitmap.width * bitmap.height);
    for (let i = 0; i < m.length; i++) m[i] = d[4 * i] > 127 ? 1 : 0;
    return {w: bitmap.width, h: bitmap.height, m};
  },
  async gt(view, cls) { return this.maskOf('/api/gt/mask?view=' + view + '&class=' + encodeURIComponent(cls)); },
  // The pixel of the mask farthest from its outside along rows and columns (an object's inside).
  async innermost(view, cls) {
    const {w, h, m} = await this.gt(view, cls);
    const run = (i0, step, n) => { const r = new Int32Array(n); let k = 0;
      for (let j = 0; j < n; j++) { k = m[i0 + j * step] ? k + 1 : 0; r[j] = k; } return r; };
    const left = new Int32Array(w * h), right = new Int32Array(w * h), up = new Int32Array(w * h), down = new Int32Array(w * h);
    for (let y = 0; y < h; y++) {
      const a = run(y * w, 1, w), b = run(y * w + w - 1, -1, w);
      for (let x = 0; x < w; x++) { left[y * w + x] = a[x]; right[y * w + w - 1 - x] = b[x]; }
    }
    for (let x = 0; x < w; x++) {
      const a = run(x, w, h), b = run((h - 1) * w + x, -w, h);
      for (let y = 0; y < h; y++) { up[y * w + x] = a[y]; down[(h - 1 - y) * w + x] = b[y]; }
    }
    let best = -1, at = [0, 0];
    for (let i = 0; i < w * h; i++) {
      const v = Math.min(left[i], right[i], up[i], down[i]);
      if (v > best) { best = v; at = [i % w, Math.floor(i / w)]; }
    }
    return {x: at[0], y: at[1], depth: best, w};
  },
  async iou(view, cls) {
    const a = await this.maskOf('/api/selection/mask?view=' + view), b = await this.gt(view, cls);
    let inter = 0, uni = 0;
    for (let i = 0; i < a.m.length; i++) { inter += a.m[i] & b.m[i]; uni += a.m[i] | b.m[i]; }
    return uni ? inter / uni : 0;
  },
  async plyHeader() {
    const r = await fetch('/api/selection.ply');
    const bytes = new Uint8Array(await r.arrayBuffer());
    const head = new TextDecoder().decode(bytes.slice(0, 400));
    const m = head.match(/element vertex (\\d+)/);
    return {status: r.status, ply: head.startsWith('ply'), vertices: m ? Number(m[1]) : 0, bytes: bytes.length};
  }
};`;

try {
  const {targetId} = await send('Target.createTarget', {url: 'about:blank'});
  session = (await send('Target.attachToTarget', {targetId, flatten: true})).sessionId;
  await page('Runtime.enable');
  await page('Log.enable');
  await page('Page.enable');
  await page('Emulation.setDeviceMetricsOverride', {width: 1400, height: 1800, deviceScaleFactor: 1, mobile: false});
  await send('Browser.setDownloadBehavior', {behavior: 'allow', downloadPath: path.resolve(out)});
  const t0 = Date.now();
  await page('Page.navigate', {url});
  await until('window.viewer && viewer.frames >= 1 && viewer.idle()', 'the first frame');
  result.first_frame_ms = Date.now() - t0;
  await evaluate(helpers);
  const info = await evaluate('({views: viewer.info.views.length, instances: viewer.info.instances.length, legend: document.querySelectorAll("#legendItems input").length, heldout: document.querySelectorAll("#heldout img").length})');
  result.info = info;
  // The held-out pictures have loaded and decoded.
  await until('Array.from(document.querySelectorAll("#heldout img")).every(i => !i.src || (i.complete && i.naturalWidth > 0))', 'the held-out pictures');
  result.start_canvas = await evaluate('testing.canvasStats()');
  const stage = await evaluate('(() => { const r = document.getElementById("overlay").getBoundingClientRect(); return {x: r.left, y: r.top, width: r.width, height: r.height}; })()');
  await screenshot('viewer_start.png', stage);
  step('loaded');

  // Orbit: a drag across the frame.
  await evaluate('testing.snapshot()');
  const framesBefore = await evaluate('viewer.frames');
  const cx = stage.x + 320, cy = stage.y + 240;
  await mouse('mousePressed', cx, cy);
  for (let k = 1; k <= 8; k++) await mouse('mouseMoved', cx + 15 * k, cy + 4 * k);
  await mouse('mouseReleased', cx + 120, cy + 32);
  await until('viewer.idle()', 'the orbit frames');
  result.orbit = {frames: (await evaluate('viewer.frames')) - framesBefore,
                  mean_abs_change: await evaluate('testing.changedSinceSnapshot()'),
                  canvas: await evaluate('testing.canvasStats()')};
  await screenshot('viewer_orbit.png', stage);
  step('orbited');

  // Back to the first camera; click the known object at its innermost ground-truth pixel.
  await evaluate('viewer.setView(0)');
  await until('viewer.idle()', 'the first camera');
  const tau = String(args.tau || '0.5');
  await evaluate(`(() => { const s = document.getElementById("tau"); s.value = "${tau}"; s.dispatchEvent(new Event("input")); })()`);
  const target = await evaluate(`testing.innermost(0, ${JSON.stringify(args.class)})`);
  const scale = 640 / target.w;
  const px = stage.x + target.x * scale, py = stage.y + target.y * scale;
  const t1 = Date.now();
  await mouse('mousePressed', px, py);
  await mouse('mouseReleased', px, py);
  await until('viewer.selection && viewer.idle()', 'the click\'s selection');
  result.click = {pixel: [target.x, target.y], depth: target.depth, round_trip_ms: Date.now() - t1,
                  selection: await evaluate('viewer.selection'),
                  iou: await evaluate(`testing.iou(0, ${JSON.stringify(args.class)})`)};
  await screenshot('viewer_click.png', stage);
  step('clicked');

  // The threshold slider: a higher threshold keeps fewer Gaussians.
  await evaluate('(() => { const s = document.getElementById("tau"); s.value = "0.95"; s.dispatchEvent(new Event("input")); })()');
  await until('viewer.idle()', 'the slider\'s selection');
  result.slider = {selected_at_095: await evaluate('viewer.selection.selected')};
  await evaluate(`(() => { const s = document.getElementById("tau"); s.value = "${tau}"; s.dispatchEvent(new Event("input")); })()`);
  await until('viewer.idle()', 'the slider\'s selection');
  result.slider.selected_back = await evaluate('viewer.selection.selected');

  // A text query typed into the box, submitted with Enter.
  await evaluate('document.getElementById("query").focus()');
  await page('Input.insertText', {text: args.query});
  for (const type of ['keyDown', 'keyUp'])
    await page('Input.dispatchKeyEvent', {type, key: 'Enter', code: 'Enter', windowsVirtualKeyCode: 13, text: type === 'keyDown' ? '\r' : undefined});
  await until('viewer.selection && viewer.selection.query_class !== "" && viewer.idle()', 'the query\'s selection');
  result.query = {selection: await evaluate('viewer.selection'),
                  iou: await evaluate(`testing.iou(0, ${JSON.stringify(args.class)})`)};
  step('queried');

  // Exports: the PLY through the page's button (a download) and its header, the view as PNG.
  result.ply = await evaluate('testing.plyHeader()');
  await evaluate('document.getElementById("exportPly").click()');
  await evaluate('document.getElementById("savePng").click()');
  const t2 = Date.now();
  while (Date.now() - t2 < 10000 && !(fs.existsSync(path.join(out, 'selection.ply')) && fs.existsSync(path.join(out, 'view.png'))))
    await new Promise(r => setTimeout(r, 50));
  result.downloads = {ply: fs.existsSync(path.join(out, 'selection.ply')) ? fs.statSync(path.join(out, 'selection.ply')).size : 0,
                      png: fs.existsSync(path.join(out, 'view.png')) ? fs.statSync(path.join(out, 'view.png')).size : 0};
  step('exported');
  const whole = await screenshot('viewer_page.png');
  result.screenshots = Object.fromEntries(['viewer_start.png', 'viewer_orbit.png', 'viewer_click.png', 'viewer_page.png']
    .map(n => [n, fs.statSync(path.join(out, n)).size]));
  result.page_errors = await evaluate('viewer.errors');
  result.console = consoleMessages;
  result.ok = true;
} catch (e) {
  result.ok = false;
  result.error = String(e.stack || e);
  result.console = consoleMessages;
} finally {
  const chromeExited = chrome.exitCode !== null || chrome.signalCode !== null ? Promise.resolve()
    : new Promise(r => chrome.on('exit', r));
  chrome.kill('SIGTERM');
  await chromeExited;
  const exited = viewer.exitCode !== null || viewer.signalCode !== null ? Promise.resolve([viewer.exitCode, viewer.signalCode])
    : new Promise(r => viewer.on('exit', (code, signal) => r([code, signal])));
  viewer.kill('SIGINT');
  const [code, signal] = await exited;
  result.viewer_exit = code === null ? signal : code;
  fs.rmSync(profile, {recursive: true, force: true, maxRetries: 5});
  console.log(JSON.stringify(result));
}
