// Headless-Chromium test of the pregrasp plan viewer pages.
//
// Usage: node test.mjs PLAN.html NO_PLAN.html SCREENSHOT.png
// The pages load three.js from the CDN; every CDN request is answered from the local
// node_modules/three (same pinned version), every other network request is refused.
// Prints `browser: N passed, M failed` last and exits 1 when anything failed.

import { chromium } from 'playwright-core';
import { mkdtempSync, readFileSync, rmSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { dirname, join, resolve } from 'node:path';
import { fileURLToPath, pathToFileURL } from 'node:url';

const here = dirname(fileURLToPath(import.meta.url));
const THREE_VERSION = JSON.parse(readFileSync(join(here, 'node_modules/three/package.json'), 'utf8')).version;
const CDN = `https://cdn.jsdelivr.net/npm/three@${THREE_VERSION}/`;
const [planHtml, noPlanHtml, screenshot] = process.argv.slice(2).map((p) => resolve(p));
if (!planHtml || !noPlanHtml || !screenshot) {
  console.error('usage: node test.mjs PLAN.html NO_PLAN.html SCREENSHOT.png');
  process.exit(2);
}

let passed = 0;
let failed = 0;
function check(name, ok, detail = '') {
  if (ok) passed++; else failed++;
  console.log(`${ok ? 'ok  ' : 'FAIL'} ${name}${detail ? ` (${detail})` : ''}`);
}

/** The WebGL canvas scaled to 160 px wide, as RGBA bytes (read by the test, not the page). */
async function pixels(page) {
  return page.evaluate(() => {
    const c = document.querySelector('#view canvas');
    const w = 160;
    const h = Math.max(1, Math.round((w * c.height) / c.width));
    const off = document.createElement('canvas');
    off.width = w;
    off.height = h;
    const ctx = off.getContext('2d');
    ctx.drawImage(c, 0, 0, w, h);
    return Array.from(ctx.getImageData(0, 0, w, h).data);
  });
}

/** Luminance standard deviation and the number of distinct (quantised) colours. */
function pixelStats(px) {
  let sum = 0, sum2 = 0, n = 0;
  const colours = new Set();
  for (let i = 0; i < px.length; i += 4) {
    const l = 0.299 * px[i] + 0.587 * px[i + 1] + 0.114 * px[i + 2];
    sum += l; sum2 += l * l; n++;
    colours.add(((px[i] >> 4) << 8) | ((px[i + 1] >> 4) << 4) | (px[i + 2] >> 4));
  }
  const mean = sum / n;
  return { std: Math.sqrt(Math.max(sum2 / n - mean * mean, 0)), colours: colours.size };
}

/** Fraction of pixels whose colour changed by more than 24 in some channel. */
function changedFraction(a, b) {
  let changed = 0;
  for (let i = 0; i < a.length; i += 4) {
    if (Math.abs(a[i] - b[i]) > 24 || Math.abs(a[i + 1] - b[i + 1]) > 24 || Math.abs(a[i + 2] - b[i + 2]) > 24) changed++;
  }
  return changed / (a.length / 4);
}

/** The JSON document a viewer page embeds (escaped JSON text is still JSON). */
function embeddedData(file) {
  const html = readFileSync(file, 'utf8');
  const open = '<script type="application/json" id="pregrasp-data">';
  const start = html.indexOf(open) + open.length;
  return JSON.parse(html.slice(start, html.indexOf('</script>', start)));
}

const dist = (a, b) => Math.hypot(a[0] - b[0], a[1] - b[1], a[2] - b[2]);

/** Opens a page with CDN routing and error capture; resolves once the first frame is drawn. */
async function open(context, file) {
  const page = await context.newPage();
  const errors = [];
  page.on('console', (m) => { if (m.type() === 'error') errors.push(m.text()); });
  page.on('pageerror', (e) => errors.push(String(e)));
  await page.goto(pathToFileURL(file).href);
  let rendered = true;
  try {
    await page.waitForFunction(() => window.pregraspViewer && window.pregraspViewer.framesRendered > 0, null, { timeout: 30000 });
  } catch {
    rendered = false;
  }
  return { page, errors, rendered };
}

const profile = mkdtempSync(join(tmpdir(), 'pregrasp-chromium-'));
const args = ['--headless', '--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run',
  '--disable-background-networking', '--disable-component-update', '--disable-sync',
  '--use-angle=swiftshader', '--enable-unsafe-swiftshader'];
const context = await chromium.launchPersistentContext(profile, {
  executablePath: '/usr/bin/chromium', headless: true, args, viewport: { width: 1280, height: 800 },
});
const refused = [];
await context.route('**/*', async (route) => {
  const url = route.request().url();
  if (url.startsWith('file:')) return route.continue();
  if (url.startsWith(CDN)) {
    const rel = url.slice(CDN.length).split(/[?#]/)[0];
    const body = readFileSync(join(here, 'node_modules/three', rel));
    return route.fulfill({ status: 200, contentType: 'text/javascript', body });
  }
  refused.push(url);
  return route.abort();
});

try {
  // ---- the planned page ----
  const { page, errors, rendered } = await open(context, planHtml);
  check('plan page: first frame rendered', rendered);
  const hasPlan = embeddedData(planHtml).plan.plans.length > 0;
  if (!hasPlan) console.log('note: the plan file has no plan; timeline checks skipped');
  if (rendered && !hasPlan) {
    const stats = pixelStats(await pixels(page));
    check('plan page: canvas is not blank', stats.std > 8 && stats.colours > 20, `luminance std ${stats.std.toFixed(1)}, ${stats.colours} colours`);
    await page.screenshot({ path: screenshot });
  }
  if (rendered && hasPlan) {
    const v = (expr) => page.evaluate(expr);
    const stats = pixelStats(await pixels(page));
    check('plan page: canvas is not blank', stats.std > 8 && stats.colours > 20, `luminance std ${stats.std.toFixed(1)}, ${stats.colours} colours`);
    const fkErr = await v(() => window.pregraspViewer.fkError());
    check('plan page: JS forward kinematics matches Rust FK', fkErr < 1e-9, `max error ${fkErr.toExponential(2)}`);
    const counts = await v(() => [window.pregraspViewer.candidateCount(), window.pregraspViewer.hullEdgeCount()]);
    check('plan page: candidates and hull edges drawn', counts[0] > 0 && counts[1] >= 3, `${counts[0]} candidates, ${counts[1]} hull edges`);

    const T = await v(() => window.pregraspViewer.duration());
    check('plan page: timeline has a duration', T > 0, `${T.toFixed(2)} s`);
    // The timeline against the plan itself (read from the page's embedded JSON by the test).
    const plan = embeddedData(planHtml).plan;
    const chosen = plan.plans[0];
    let t0 = 0;
    const order = [];
    let worst = 0;
    for (const seg of chosen.segments) {
      const dur = seg.points[seg.points.length - 1].t;
      const mid = await page.evaluate((t) => window.pregraspViewer.setTime(t), t0 + dur / 2);
      order.push(mid);
      const r = plan.robots.findIndex((x) => x.name === seg.robot);
      for (const j of [1, Math.floor(seg.points.length / 2), seg.points.length - 2]) {
        if (j < 1 || j >= seg.points.length) continue;
        const q = await page.evaluate(([i, t]) => { window.pregraspViewer.setTime(t); return window.pregraspViewer.armJoints(i); }, [r, t0 + seg.points[j].t]);
        worst = Math.max(worst, ...q.map((x, k) => Math.abs(x - seg.points[j].q[k])));
      }
      t0 += dur;
    }
    check('plan page: timeline duration is the sum of the segments', Math.abs(T - t0) < 1e-9, `${T} vs ${t0}`);
    check('plan page: segments play in order sup1, rot, mas1, sup2', order.join(',') === 'sup1,rot,mas1,sup2', order.join(','));
    check('plan page: arms pass through the plan points', worst < 1e-9, `max joint error ${worst.toExponential(2)} rad`);

    // Move the timeline: the arm that moves first (sup1's robot) and the pixels must change.
    await v(() => window.pregraspViewer.setTime(0));
    const arm = await v(() => window.pregraspViewer.movingArm());
    const tip0 = await page.evaluate((i) => window.pregraspViewer.armTip(i), arm);
    const obj0 = await v(() => window.pregraspViewer.objectPosition());
    const px0 = await pixels(page);
    const tMid = await v(() => window.pregraspViewer.segmentEnd('rot'));
    await page.evaluate((t) => window.pregraspViewer.setTime(t), tMid);
    const tip1 = await page.evaluate((i) => window.pregraspViewer.armTip(i), arm);
    const obj1 = await v(() => window.pregraspViewer.objectPosition());
    const px1 = await pixels(page);
    check('plan page: moving the timeline moves the arm', tip0 && tip1 && dist(tip0, tip1) > 0.05, tip0 && tip1 ? `flange moved ${dist(tip0, tip1).toFixed(3)} m` : 'no arm');
    check('plan page: the part moves with μ_rot', dist(obj0, obj1) > 0.01, `part moved ${dist(obj0, obj1).toFixed(3)} m`);
    const frac = changedFraction(px0, px1);
    check('plan page: moving the timeline changes the pixels', frac > 0.005, `${(100 * frac).toFixed(1)}% of pixels changed`);
    // The master arm holds its start configuration until mas1.
    const other = 1 - arm;
    const q0 = await page.evaluate((i) => { window.pregraspViewer.setTime(0); return window.pregraspViewer.armJoints(i); }, other);
    const q1 = await page.evaluate(([i, t]) => { window.pregraspViewer.setTime(t); return window.pregraspViewer.armJoints(i); }, [other, tMid]);
    check('plan page: the other arm holds still while one moves', q0.every((x, j) => Math.abs(x - q1[j]) < 1e-12));

    const nPlans = await v(() => document.querySelectorAll('#plan-select option').length);
    if (nPlans > 1) {
      const ok = await v(() => { window.pregraspViewer.selectPlan(1); return window.pregraspViewer.planIndex() === 1 && window.pregraspViewer.duration() > 0; });
      check('plan page: the plan selector switches plans', ok);
      await v(() => window.pregraspViewer.selectPlan(0));
    }

    // Storyboard: the 3D view at the end of each segment, beside the screenshot.
    let tEnd = 0;
    for (const seg of chosen.segments) {
      tEnd += seg.points[seg.points.length - 1].t;
      await page.evaluate((t) => window.pregraspViewer.setTime(t), tEnd);
      await page.locator('#view canvas').screenshot({ path: screenshot.replace(/\.png$/, `-${seg.name}.png`) });
    }
    await page.evaluate((t) => window.pregraspViewer.setTime(t), tMid);
    await page.screenshot({ path: screenshot });
    console.log(`screenshot: ${screenshot}`);
  }
  check('plan page: no console errors', errors.length === 0, errors.slice(0, 3).join(' | '));
  await page.close();

  // ---- the no-plan page ----
  const np = await open(context, noPlanHtml);
  check('no-plan page: first frame rendered', np.rendered);
  if (np.rendered) {
    const stats = pixelStats(await pixels(np.page));
    check('no-plan page: canvas is not blank', stats.std > 8 && stats.colours > 20, `luminance std ${stats.std.toFixed(1)}, ${stats.colours} colours`);
    const status = await np.page.evaluate(() => document.getElementById('status').textContent);
    const cands = await np.page.evaluate(() => window.pregraspViewer.candidateCount());
    check('no-plan page: says "no plan" and still lists the candidates', status.startsWith('no plan') && cands > 0, `${status}; ${cands} candidates`);
    await np.page.screenshot({ path: screenshot.replace(/\.png$/, '-no-plan.png') });
  }
  check('no-plan page: no console errors', np.errors.length === 0, np.errors.slice(0, 3).join(' | '));
  check('no request left the machine', refused.length === 0, refused.slice(0, 3).join(' '));
} catch (e) {
  check('browser test ran to the end', false, String(e));
} finally {
  await context.close();
  rmSync(profile, { recursive: true, force: true });
}

console.log(`browser: ${passed} passed, ${failed} failed`);
process.exit(failed === 0 ? 0 : 1);
