// tests/browser/viewer_test.mjs — opens replay viewer pages (`unison view`) in Debian's chromium, headless, through
// puppeteer-core, and checks what a person would: the page loads with no console error and no request leaving
// the file (no network), the canvas is not blank, `#tick=N` shows tick N and its state hash in the panel, the
// scrubber changes the frame and the address, play and pause work, and a desync report marks its tick and draws
// the flagged body.
// Prints one JSON line per page with its load time (ms from navigation start to the first drawn frame).
//
// Usage: node viewer_test.mjs CASES.json [--screenshot OUT.png]
//   CASES.json: [{"page": "/abs/path.html", "tick": N, "hash": "16 hex digits", "other_tick": M,
//                 "report_tick": R (optional), "screenshot": true (optional)}]
// Exit code 0 when every check passes, 1 otherwise. CHROMIUM overrides the browser path (default /usr/bin/chromium).
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import puppeteer from 'puppeteer-core';

const args = process.argv.slice(2);
const cases = JSON.parse(fs.readFileSync(args[0], 'utf8'));
const shotAt = args.indexOf('--screenshot');
const screenshotPath = shotAt >= 0 ? args[shotAt + 1] : null;
const failures = [];
const check = (ok, what) => { if (!ok) failures.push(what); return ok; };

const profile = fs.mkdtempSync(path.join(os.tmpdir(), 'unison-chromium-'));
const browser = await puppeteer.launch({
  executablePath: process.env.CHROMIUM || '/usr/bin/chromium',
  headless: true,
  userDataDir: profile,
  args: ['--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run', '--disable-background-networking',
         '--disable-component-update', '--disable-sync', '--disable-extensions'],
});

/// Pixels of the view canvas that differ from the background, and a checksum of all of them.
async function canvasSummary(page) {
  return page.evaluate(() => {
    const c = document.getElementById('view');
    const data = c.getContext('2d').getImageData(0, 0, c.width, c.height).data;
    let drawn = 0, red = 0, sum = 0;
    for (let i = 0; i < data.length; i += 4) {
      const r = data[i], g = data[i + 1], b = data[i + 2];
      if (Math.abs(r - 0x14) + Math.abs(g - 0x16) + Math.abs(b - 0x1a) > 12) ++drawn;
      if (r === 0xff && g === 0x5c && b === 0x5c) ++red;
      sum = (sum * 31 + r + 7 * g + 13 * b) >>> 0;
    }
    return { drawn, total: data.length / 4, red, sum };
  });
}

try {
  for (const c of cases) {
    const name = path.basename(c.page);
    const page = await browser.newPage();
    await page.setViewport({ width: 1280, height: 720 });
    const errors = [];
    page.on('console', (m) => { if (m.type() === 'error') errors.push('console: ' + m.text()); });
    page.on('pageerror', (e) => errors.push('page error: ' + e.message));
    page.on('request', (r) => { if (!/^(file|data|blob):/.test(r.url())) errors.push('network request: ' + r.url()); });
    const started = Date.now();
    const url = 'file://' + c.page + (c.tick !== undefined ? '#tick=' + c.tick : '');
    await page.goto(url, { waitUntil: 'load', timeout: 60000 });
    await page.waitForFunction('window.unisonViewer && window.unisonViewer.ready', { timeout: 60000 });
    const wallMs = Date.now() - started;
    const readyMs = await page.evaluate('window.unisonViewer.readyMs');
    const text = (id) => page.$eval('#' + id, (e) => e.textContent);

    const first = await canvasSummary(page);
    check(first.drawn > first.total / 200, `${name}: the canvas is blank (${first.drawn} drawn pixels)`);
    const expectedTick = c.tick !== undefined ? c.tick : (c.report_tick !== undefined ? c.report_tick : 0);
    check(await text('tick') === String(expectedTick), `${name}: the panel shows tick ${await text('tick')}, not ${expectedTick}`);
    if (c.hash) check(await text('hash') === c.hash, `${name}: tick ${expectedTick} shows hash ${await text('hash')}, not ${c.hash}`);
    check((await text('verdict')).includes('matches'), `${name}: the replay does not match the recording at tick ${expectedTick}`);
    if (c.report_tick !== undefined) {
      check(await page.$eval('#report-box', (e) => !e.hidden), `${name}: the desync report is not shown`);
      check(await text('report-tick') === String(c.report_tick), `${name}: the report shows tick ${await text('report-tick')}`);
      check(first.red > 20, `${name}: the flagged body is not drawn in red (${first.red} red pixels)`);
    }

    // The scrubber: another tick, another frame, another address.
    await page.$eval('#scrub', (e, t) => { e.value = t; e.dispatchEvent(new Event('input')); }, c.other_tick);
    const second = await canvasSummary(page);
    check(await text('tick') === String(c.other_tick), `${name}: the scrubber did not move to tick ${c.other_tick}`);
    check(second.sum !== first.sum, `${name}: the frame did not change when scrubbing to tick ${c.other_tick}`);
    check(await page.evaluate('location.hash') === '#tick=' + c.other_tick, `${name}: the address did not follow the scrubber`);
    // Play runs the ticks forward; pause stops them.
    await page.$eval('#scrub', (e) => { e.value = 0; e.dispatchEvent(new Event('input')); });
    await page.click('#play');
    await page.waitForFunction(() => Number(document.getElementById('tick').textContent) > 3, { timeout: 10000 })
      .catch(() => check(false, `${name}: play did not advance the ticks`));
    await page.click('#play');
    const paused = await text('tick');
    await new Promise((r) => setTimeout(r, 200));
    check(await text('tick') === paused, `${name}: pause did not stop the ticks`);
    // The address: a new #tick=N moves the view there.
    await page.evaluate((t) => { location.hash = '#tick=' + t; }, expectedTick);
    await page.waitForFunction((t) => document.getElementById('tick').textContent === String(t), { timeout: 5000 }, expectedTick);
    if (c.hash) check(await text('hash') === c.hash, `${name}: back at tick ${expectedTick} the hash is ${await text('hash')}`);

    if (screenshotPath && c.screenshot) {
      await page.$eval('#scrub', (e, t) => { e.value = t; e.dispatchEvent(new Event('input')); }, expectedTick);
      await page.screenshot({ path: screenshotPath });
    }
    for (const e of errors) check(false, `${name}: ${e}`);
    console.log(JSON.stringify({ page: name, load_ms: Math.round(readyMs), wall_ms: wallMs, errors: errors.length,
                                 drawn_pixels: first.drawn }));
    await page.close();
  }
} finally {
  await browser.close();
  fs.rmSync(profile, { recursive: true, force: true });
}
for (const f of failures) console.error('FAIL ' + f);
process.exit(failures.length ? 1 : 0);
