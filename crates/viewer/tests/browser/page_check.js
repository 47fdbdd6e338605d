// Issue 30: `flexmbd animate`'s web page in headless Chromium, opened from a file with the
// network off: at each of two times (page.html#t=…, which opens paused there) no console
// error, and the page draws link2 of the double pendulum where the run's CSV puts its tip
// (the CSV's tip, projected with the page's camera, falls on link2's colour within 3 px),
// and not where the CSV puts it at the other time (a probe that can fail).
//
// node page_check.js PAGE.html RUN.csv T1 T2   (NODE_PATH: playwright-core; /usr/bin/chromium)
'use strict';
const fs = require('fs'), os = require('os'), path = require('path');
const { chromium } = require('playwright-core');
const { readPng } = require('./png.js');

const [pagePath, csvPath, ...times] = process.argv.slice(2);
const LINK2 = [0.85, 0.35, 0.05]; // glb.rs PALETTE[1], linear RGB

function csvRow(t) {
  const [header, ...rows] = fs.readFileSync(csvPath, 'utf8').trim().split('\n').map(l => l.split(','));
  const row = rows.map(r => r.map(Number)).find(r => Math.abs(r[0] - t) < 1e-9);
  if (!row) throw new Error(`${csvPath}: no row at t = ${t}`);
  return name => row[header.indexOf(name)];
}

// link2's colour as drawn, lit: red well above green above blue; the background is grey.
const isLink2 = ([r, g, b]) => r > g + 40 && g > b + 20;

function near(png, [x, y], radius) {
  for (let dy = -radius; dy <= radius; dy++)
    for (let dx = -radius; dx <= radius; dx++) {
      const px = Math.round(x) + dx, py = Math.round(y) + dy;
      if (px >= 0 && py >= 0 && px < png.width && py < png.height && isLink2(png.pixel(px, py))) return true;
    }
  return false;
}

(async () => {
  const profile = fs.mkdtempSync(path.join(os.tmpdir(), 'flexmbd-chromium-'));
  const context = await chromium.launchPersistentContext(profile, {
    executablePath: '/usr/bin/chromium',
    headless: true,
    offline: true,
    viewport: { width: 900, height: 700 },
    args: ['--no-sandbox', '--disable-gpu', '--disable-background-networking', '--disable-component-update',
           '--disable-sync', '--no-first-run'],
  });
  const failures = [];
  const tips = times.map(t => { const at = csvRow(Number(t)); return ['tip_x', 'tip_y', 'tip_z'].map(at); });
  try {
    await context.route('**/*', route => route.request().url().startsWith('file:') ? route.continue() : route.abort());
    for (const [k, t] of times.entries()) {
      const page = await context.newPage();
      const errors = [];
      page.on('console', m => { if (m.type() === 'error') errors.push(m.text()); });
      page.on('pageerror', e => errors.push(e.message));
      await page.goto('file://' + path.resolve(pagePath) + '#t=' + t);
      await page.waitForFunction(() => window.flexmbd && window.flexmbd.ready, null, { timeout: 20000 });
      const shown = await page.evaluate(() => window.flexmbd.time);
      const [here, other] = await page.evaluate(ps => ps.map(p => window.flexmbd.project(p)), [tips[k], tips[1 - k]]);
      const png = readPng(await page.screenshot());
      const apart = Math.hypot(here[0] - other[0], here[1] - other[1]);
      console.log(`t = ${t} s: shown at ${shown} s, tip drawn at (${here.map(v => v.toFixed(1))}), ` +
                  `the other time's tip ${apart.toFixed(0)} px away`);
      if (Math.abs(shown - Number(t)) > 1e-9) failures.push(`#t=${t} shows t = ${shown}`);
      if (errors.length) failures.push(`t = ${t}: console errors: ${errors.join(' | ')}`);
      if (!near(png, here, 3)) failures.push(`t = ${t}: no link2 pixel within 3 px of the CSV's tip`);
      if (apart < 30) failures.push(`t = ${t}: the two times' tips are only ${apart} px apart`);
      else if (near(png, other, 3)) failures.push(`t = ${t}: link2 drawn where the CSV puts the tip at the other time`);
      await page.close();
    }
  } finally {
    await context.close();
    fs.rmSync(profile, { recursive: true, force: true });
  }
  for (const f of failures) console.log('FAILED: ' + f);
  console.log(`${times.length * 3 - failures.length} passed, ${failures.length} failed`);
  process.exit(failures.length ? 1 : 0);
})().catch(e => { console.error(e); process.exit(1); });
