// cdp.js — opens a page in headless Chromium in real time (no virtual time:
// requestAnimationFrame runs at the browser's own pace, as for a user), evaluates a
// JavaScript expression in it (a promise is awaited) and prints its string value. Talks
// to Chromium over --remote-debugging-pipe (fd 3 in, fd 4 out, NUL-terminated JSON), so
// it needs nothing beyond Node.
// Usage: node cdp.js PAGE.html FRAGMENT EXPRESSION
'use strict';
const { spawn } = require('child_process');
const fs = require('fs'), os = require('os'), path = require('path');

const page = path.resolve(process.argv[2]);
const [fragment, expression] = [process.argv[3], process.argv[4]];
const profile = fs.mkdtempSync(path.join(os.tmpdir(), 'mbfx-fps-'));
const chrome = spawn('/usr/bin/chromium-headless-shell', [
  '--headless', '--no-sandbox', '--use-angle=swiftshader', '--enable-unsafe-swiftshader',
  '--disable-background-networking', '--disable-component-update', '--disable-sync', '--no-first-run',
  '--user-data-dir=' + profile, '--window-size=800,600', '--remote-debugging-pipe',
  'file://' + page + '#' + fragment,
], { stdio: ['ignore', 'ignore', 'ignore', 'pipe', 'pipe'] });

let next = 1, buffer = '';
const waiting = new Map();
chrome.stdio[4].on('data', chunk => {
  buffer += chunk.toString();
  let end;
  while ((end = buffer.indexOf('\0')) >= 0) {
    const msg = JSON.parse(buffer.slice(0, end));
    buffer = buffer.slice(end + 1);
    if (msg.id && waiting.has(msg.id)) { waiting.get(msg.id)(msg); waiting.delete(msg.id); }
  }
});
function send(method, params = {}, sessionId) {
  const id = next++;
  chrome.stdio[3].write(JSON.stringify({ id, method, params, sessionId }) + '\0');
  return new Promise(resolve => waiting.set(id, resolve));
}
const sleep = ms => new Promise(r => setTimeout(r, ms));

async function main() {
  let target = null;
  for (let k = 0; k < 50 && !target; k++) {
    const r = await send('Target.getTargets');
    target = (r.result.targetInfos || []).find(t => t.type === 'page');
    if (!target) await sleep(100);
  }
  if (!target) throw new Error('no page target');
  const { result } = await send('Target.attachToTarget', { targetId: target.targetId, flatten: true });
  // Wait for the page itself (the target starts on about:blank) to finish loading.
  for (let k = 0; k < 100; k++) {
    const q = await send('Runtime.evaluate', { expression: 'location.protocol + document.readyState', returnByValue: true }, result.sessionId);
    if (q.result && q.result.result && q.result.result.value === 'file:complete') break;
    await sleep(50);
  }
  // An evaluation may still meet a context being replaced: try again.
  let r = null;
  for (let k = 0; k < 20 && !(r && r.result && r.result.result && r.result.result.type === 'string'); k++) {
    if (r) await sleep(200);
    r = await send('Runtime.evaluate', { expression, awaitPromise: true, returnByValue: true }, result.sessionId);
  }
  if (!r.result || !r.result.result || r.result.result.type !== 'string') throw new Error(JSON.stringify(r));
  console.log(r.result.result.value);
}
const timer = setTimeout(() => {
  console.error('timed out');
  chrome.kill();
  setTimeout(() => { fs.rmSync(profile, { recursive: true, force: true, maxRetries: 5 }); process.exit(1); }, 1000);
}, 30000);
main().then(() => 0, e => { console.error(e.message); return 1; }).then(async code => {
  clearTimeout(timer);
  // Close the browser and wait for it, so that no child still writes into the profile.
  const closed = new Promise(r => chrome.on('exit', r));
  send('Browser.close');
  await Promise.race([closed, sleep(3000)]);
  if (chrome.exitCode === null) { chrome.kill(); await Promise.race([closed, sleep(2000)]); }
  fs.rmSync(profile, { recursive: true, force: true, maxRetries: 5, retryDelay: 100 });
  process.exit(code);
});
