// Headless-Chromium test of the pregrasp plan viewer pages.
//
// Usage: node test.mjs PLAN.html NO_PLAN.html SCREENSHOT.png
// The browser is offline and every request other than opening the page file itself is
// refused and counted: the page must draw from what it carries. The plan page is opened a
// second time with WebGL taken away, to see it say so in words and still list the candidates.
// Chromium: $CHROMIUM, else `chromium` on the PATH.
// Prints `browser: N passed, M failed` last and exits 1 when anything failed.

import { chromium } from 'playwright-core';
import { execFileSync } from 'node:child_process';
import { mkdtempSync, readFileSync, rmSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join, resolve } from 'node:path';
import { pathToFileURL } from 'node:url';

const executablePath = process.env.CHROMIUM || execFileSync('sh', ['-c', 'command -v chromium'], { encoding: 'utf8' }).trim();
const [planHtml, noPlanHtml, screenshot, csvDir] = process.argv.slice(2).map((p) => resolve(p));
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

/** The pixel (RGBA) of the WebGL canvas at CSS position [x, y]. */
async function pixelAt(page, xy) {
  return page.evaluate(([x, y]) => {
    const c = document.querySelector('#view canvas');
    const k = c.width / c.clientWidth;
    const off = document.createElement('canvas');
    off.width = 1;
    off.height = 1;
    const ctx = off.getContext('2d');
    ctx.drawImage(c, Math.floor(x * k), Math.floor(y * k), 1, 1, 0, 0, 1, 1);
    return Array.from(ctx.getImageData(0, 0, 1, 1).data);
  }, xy);
}

/** Every request a page makes, beyond loading its own file, is refused and listed here. */
const refused = [];

/**
 * Opens a page with error capture; resolves once the viewer has started and, unless
 * `noWebgl`, drawn its first frame. `noWebgl`: the page's canvases give no WebGL context.
 */
async function open(context, file, { noWebgl = false } = {}) {
  const page = await context.newPage();
  const errors = [];
  page.on('console', (m) => { if (m.type() === 'error') errors.push(m.text()); });
  page.on('pageerror', (e) => errors.push(String(e)));
  if (noWebgl) {
    await page.addInitScript(() => {
      const original = HTMLCanvasElement.prototype.getContext;
      HTMLCanvasElement.prototype.getContext = function (kind, ...rest) {
        return /webgl/i.test(kind) ? null : original.call(this, kind, ...rest);
      };
    });
  }
  const href = pathToFileURL(file).href;
  await page.route('**/*', (route) => {
    const url = route.request().url();
    if (url === href) return route.continue();
    refused.push(url);
    return route.abort('blockedbyclient');
  });
  await page.goto(href);
  let rendered = true;
  try {
    await page.waitForFunction((gl) => window.pregraspViewer && (!gl || window.pregraspViewer.framesRendered > 0), !noWebgl, { timeout: 30000 });
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
  executablePath, headless: true, args, viewport: { width: 1280, height: 800 }, offline: true,
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
    // Each arm is drawn: the pixels at each arm's flange (DH frame 6, inside the wrist_3 disc)
    // and 5 cm above its base origin (inside the base housing) are not the background.
    const bg = await pixelAt(page, [2, 2]);
    const armPixels = await v(() => [0, 1].flatMap((i) => {
      const p = window.pregraspViewer, base = p.armFrame(i, 0);
      return [p.project(p.armFrame(i, 6)), p.project([base[0], base[1], base[2] + 0.05])];
    }));
    const drawn = [];
    for (const xy of armPixels) {
      const px = xy ? await pixelAt(page, xy) : bg;
      drawn.push(Math.max(...[0, 1, 2].map((k) => Math.abs(px[k] - bg[k]))) > 24);
    }
    check('plan page: both arms are drawn (flange and base pixels are not background)', drawn.every(Boolean), drawn.join(','));

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

    // One timeline, two implementations: the page's (timeline.js) against the exporter's
    // (crates/export/src/timeline.rs, `pregrasp export --format csv`), joints and grippers at
    // every 10th row of each arm's CSV.
    if (csvDir) {
      let rows = 0, jointError = 0, gripMismatch = [];
      for (const [i, robot] of plan.robots.entries()) {
        const lines = readFileSync(join(csvDir, `${robot.name}.csv`), 'utf8').trim().split('\n').slice(1);
        const sample = lines.filter((_, k) => k % 10 === 0 || k === lines.length - 1).map((l) => l.split(',').map(Number));
        const seen = await page.evaluate(([arm, times]) => times.map((t) => {
          window.pregraspViewer.setTime(t);
          return [window.pregraspViewer.armJoints(arm), window.pregraspViewer.gripper(arm)];
        }), [i, sample.map((r) => r[0])]);
        sample.forEach((r, k) => {
          const [q, grip] = seen[k];
          jointError = Math.max(jointError, ...q.map((x, j) => Math.abs(x - r[j + 1])));
          if ((grip !== 'open') !== (r[7] === 1)) gripMismatch.push(`${robot.name} t=${r[0]}`);
          rows++;
        });
      }
      check("plan page: the page's timeline is the exporter's (joints and grippers)",
        rows > 0 && jointError < 1e-9 && gripMismatch.length === 0,
        `${rows} rows, max joint difference ${jointError.toExponential(2)} rad, gripper mismatches ${gripMismatch.length} ${gripMismatch.slice(0, 3).join(' ')}`);
    }

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

    // Grippers: open at the start; the supportive arm closed on the support grasp from the end
    // of sup1 until sup2 opens it ('precision'); each arm closed on its power grasp from the
    // end of mas1 / sup2 on ('power').
    const sup = arm, mas = other;
    const grips = await v(() => {
      const p = window.pregraspViewer, out = {};
      const at = (t) => { p.setTime(t); return [p.gripper(0), p.gripper(1)]; };
      out.start = at(0);
      out.sup1 = at(p.segmentEnd('sup1'));
      out.rot = at((p.segmentEnd('sup1') + p.segmentEnd('rot')) / 2);
      out.mas1mid = at((p.segmentEnd('rot') + p.segmentEnd('mas1')) / 2);
      out.mas1 = at(p.segmentEnd('mas1'));
      out.sup2mid = at((p.segmentEnd('mas1') + p.segmentEnd('sup2')) / 2);
      out.sup2 = at(p.segmentEnd('sup2'));
      return out;
    });
    const gripOk = grips.start.every((g) => g === 'open')
      && grips.sup1[sup] === 'precision' && grips.rot[sup] === 'precision' && grips.rot[mas] === 'open'
      && grips.mas1mid[mas] === 'open' && grips.mas1mid[sup] === 'precision' && grips.mas1[mas] === 'power'
      && grips.sup2mid[sup] === 'open' && grips.sup2mid[mas] === 'power' && grips.sup2.every((g) => g === 'power');
    check('plan page: grippers open, hold the support grasp, then close on the power grasps', gripOk, JSON.stringify(grips));
    // The panel names each closing's grip force (segments[].grip_force; sup1 else the pinch's).
    const planShown = embeddedData(planHtml).plan.plans[await page.evaluate(() => window.pregraspViewer.planIndex())];
    const pinch = planShown.physics ? planShown.physics.grip_force_recommended : null;
    const wantForces = 'grip force: ' + planShown.segments.filter((s) => s.kind !== 'rotate').map((s) => {
      const f = s.grip_force ?? (s.grasp === 'support' ? pinch : null);
      return `${s.name} ${s.robot} ${f === null || f === undefined ? '—' : `${f.toFixed(1)} N`}`;
    }).join(' · ');
    const shownForces = await page.evaluate(() => window.pregraspViewer.gripForces());
    check('plan page: the panel gives each closing its grip force', shownForces === wantForces && / N/.test(shownForces), `${shownForces} (want ${wantForces})`);

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
  const rows = await page.evaluate(() => Array.from(document.querySelectorAll('#candidates tbody tr'), (tr) => tr.cells[0].textContent + ' ' + tr.cells[6].textContent));
  const planJson = embeddedData(planHtml).plan;
  check('plan page: the candidate table is filled', rows.length === planJson.candidates.length && rows.length > 0
    && rows.every((r, k) => r === `${planJson.candidates[k].id} ${planJson.candidates[k].outcome}`), `${rows.length} rows`);
  check('plan page: no console errors', errors.length === 0, errors.slice(0, 3).join(' | '));
  await page.close();

  // ---- the plan page without WebGL: says so in words, still lists the candidates ----
  const ng = await open(context, planHtml, { noWebgl: true });
  const note = await ng.page.evaluate(() => (document.querySelector('#view .no-webgl') || {}).textContent || '');
  const ngRows = await ng.page.evaluate(() => document.querySelectorAll('#candidates tbody tr').length);
  const ngFlag = await ng.page.evaluate(() => window.pregraspViewer && window.pregraspViewer.webgl);
  check('no-WebGL page: explains in words that WebGL is missing', ng.rendered && ngFlag === false && /needs WebGL/.test(note), note.slice(0, 80));
  check('no-WebGL page: still fills the candidate table', ngRows === planJson.candidates.length && ngRows > 0, `${ngRows} rows`);
  check('no-WebGL page: no console errors', ng.errors.length === 0, ng.errors.slice(0, 3).join(' | '));
  await ng.page.screenshot({ path: screenshot.replace(/\.png$/, '-no-webgl.png') });
  await ng.page.close();

  // ---- the no-plan page ----
  const np = await open(context, noPlanHtml);
  check('no-plan page: first frame rendered', np.rendered);
  if (np.rendered) {
    const stats = pixelStats(await pixels(np.page));
    check('no-plan page: canvas is not blank', stats.std > 8 && stats.colours > 20, `luminance std ${stats.std.toFixed(1)}, ${stats.colours} colours`);
    const status = await np.page.evaluate(() => document.getElementById('status').textContent);
    const cands = await np.page.evaluate(() => [window.pregraspViewer.candidateCount(), window.pregraspViewer.candidateRows()]);
    check('no-plan page: says "no plan" and still shows and lists the candidates', status.startsWith('no plan') && cands[0] > 0 && cands[1] === cands[0], `${status}; ${cands[0]} axes drawn, ${cands[1]} rows`);
    await np.page.screenshot({ path: screenshot.replace(/\.png$/, '-no-plan.png') });
  }
  check('no-plan page: no console errors', np.errors.length === 0, np.errors.slice(0, 3).join(' | '));
  check('the pages asked for nothing beyond their own file (all refused anyway)', refused.length === 0, refused.slice(0, 3).join(' '));
} catch (e) {
  check('browser test ran to the end', false, String(e));
} finally {
  await context.close();
  rmSync(profile, { recursive: true, force: true });
}

console.log(`browser: ${passed} passed, ${failed} failed`);
process.exit(failed === 0 ? 0 : 1);
