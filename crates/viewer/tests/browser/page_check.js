// Issue 30: `flexmbd animate`'s web page in headless Chromium, opened from a file with the
// network off: at each of two times (page.html#t=…, which opens paused there) no console
// error, and the page draws each probed body where the run's CSV puts a point of it (the
// point, projected with the page's camera, falls on the body's colour within 3 px), and
// not where the CSV puts it at the other time (a probe that can fail). The probes:
//   double-pendulum (default): link2 at its tip (tip_x, tip_y, tip_z);
//   solid-slider-crank (models/solid_slider_crank_gmsh.ron, the solid FE crank and rod
//     drawn by their surfaces): the slider's pin sphere at (slider_x, 0, 0) on the rail,
//     and the solid crank's middle at 0.15 m (cos θ, sin θ, 0), θ = crank_angle.
//
// node page_check.js PAGE.html RUN.csv T1 T2 [PROBES]   (NODE_PATH: playwright-core; /usr/bin/chromium)
'use strict';
const fs = require('fs'), os = require('os'), path = require('path');
const { chromium } = require('playwright-core');
const { readPng } = require('./png.js');

const [pagePath, csvPath, t1, t2, probeSet = 'double-pendulum'] = process.argv.slice(2);
const times = [t1, t2];

function csvRow(t) {
  const [header, ...rows] = fs.readFileSync(csvPath, 'utf8').trim().split('\n').map(l => l.split(','));
  const row = rows.map(r => r.map(Number)).find(r => Math.abs(r[0] - t) < 1e-9);
  if (!row) throw new Error(`${csvPath}: no row at t = ${t}`);
  return name => {
    const k = header.indexOf(name);
    if (k < 0) throw new Error(`${csvPath}: no column ${name}`);
    return row[k];
  };
}

// The palette's colours (glb.rs PALETTE) as drawn, lit; the background is grey.
const ORANGE = ([r, g, b]) => r > g + 40 && g > b + 20; // PALETTE[1]
const BLUE = ([r, g, b]) => b > r + 60 && b > g + 30; // PALETTE[0]
const GREEN = ([r, g, b]) => g > r + 40 && g > b + 30; // PALETTE[2]
const PROBES = {
  'double-pendulum': [
    { what: 'link2', colour: ORANGE, at: row => ['tip_x', 'tip_y', 'tip_z'].map(row) },
  ],
  'solid-slider-crank': [
    { what: 'the slider', colour: GREEN, at: row => [row('slider_x'), 0, 0] },
    { what: 'the solid crank', colour: BLUE,
      at: row => [0.15 * Math.cos(row('crank_angle')), 0.15 * Math.sin(row('crank_angle')), 0] },
  ],
};
const probes = PROBES[probeSet];
if (!probes) throw new Error(`unknown probes ${probeSet} (known: ${Object.keys(PROBES).join(', ')})`);

function near(png, [x, y], radius, colour) {
  for (let dy = -radius; dy <= radius; dy++)
    for (let dx = -radius; dx <= radius; dx++) {
      const px = Math.round(x) + dx, py = Math.round(y) + dy;
      if (px >= 0 && py >= 0 && px < png.width && py < png.height && colour(png.pixel(px, py))) return true;
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
  // points[p][k]: probe p's point at time k
  const points = probes.map(probe => times.map(t => probe.at(csvRow(Number(t)))));
  let checks = 0;
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
      const png = readPng(await page.screenshot());
      checks += 2;
      if (Math.abs(shown - Number(t)) > 1e-9) failures.push(`#t=${t} shows t = ${shown}`);
      if (errors.length) failures.push(`t = ${t}: console errors: ${errors.join(' | ')}`);
      for (const [p, probe] of probes.entries()) {
        const [here, other] = await page.evaluate(ps => ps.map(q => window.flexmbd.project(q)), [points[p][k], points[p][1 - k]]);
        const apart = Math.hypot(here[0] - other[0], here[1] - other[1]);
        console.log(`t = ${t} s: shown at ${shown} s, ${probe.what} drawn at (${here.map(v => v.toFixed(1))}), ` +
                    `the other time's point ${apart.toFixed(0)} px away`);
        checks += 2;
        if (!near(png, here, 3, probe.colour)) failures.push(`t = ${t}: no pixel of ${probe.what} within 3 px of the CSV's point`);
        if (apart < 30) failures.push(`t = ${t}: ${probe.what}'s points at the two times are only ${apart} px apart`);
        else if (near(png, other, 3, probe.colour)) failures.push(`t = ${t}: ${probe.what} drawn where the CSV puts it at the other time`);
      }
      await page.close();
    }
  } finally {
    await context.close();
    fs.rmSync(profile, { recursive: true, force: true });
  }
  for (const f of failures) console.log('FAILED: ' + f);
  console.log(`${checks - failures.length} passed, ${failures.length} failed`);
  process.exit(failures.length ? 1 : 0);
})().catch(e => { console.error(e); process.exit(1); });
