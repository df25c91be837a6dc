// Browser tests of `reach view`: a real Chromium (Debian's /usr/bin/chromium, or
// $CHROMIUM) driven by playwright-core loads the exported HTML from a file:// URL.
//
//   REACH_BIN   the reach binary (default: ../target/debug/reach)
//   CHROMIUM    the browser (default: /usr/bin/chromium)
//   REACH_SCREENSHOTS=1   also rewrite the screenshots in docs/images/
//
// Run from web/: `node --test tests/` (scripts/test builds the binary first).
import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import { execFileSync } from 'node:child_process';
import { mkdtempSync, writeFileSync, mkdirSync, statSync, readFileSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join, dirname, resolve } from 'node:path';
import { fileURLToPath, pathToFileURL } from 'node:url';
import { chromium } from 'playwright-core';

const WEB = resolve(dirname(fileURLToPath(import.meta.url)), '..');
const ROOT = resolve(WEB, '..');
const REACH = process.env.REACH_BIN || join(ROOT, 'target', 'debug', 'reach');
const BROWSER = process.env.CHROMIUM || '/usr/bin/chromium';
const SHOTS = join(ROOT, 'docs', 'images');
const dir = mkdtempSync(join(tmpdir(), 'reach-view-'));

function reach(...args) {
  return execFileSync(REACH, args, { cwd: ROOT, encoding: 'utf8', maxBuffer: 64 << 20 });
}

let browser;
before(async () => {
  browser = await chromium.launch({
    executablePath: BROWSER,
    args: ['--no-sandbox', '--use-angle=swiftshader', '--enable-unsafe-swiftshader', '--allow-file-access-from-files'],
  });
});
after(async () => {
  await browser?.close();
});

/** Opens an exported HTML file; returns the page and the console errors collected. */
async function open(html, size = { width: 1100, height: 650 }) {
  const page = await browser.newPage({ viewport: size });
  const errors = [];
  page.on('console', (m) => {
    if (m.type() === 'error') errors.push(m.text());
  });
  page.on('pageerror', (e) => errors.push(String(e)));
  page.on('request', (r) => {
    if (!r.url().startsWith('file:') && !r.url().startsWith('data:')) errors.push(`network request: ${r.url()}`);
  });
  await page.goto(pathToFileURL(html).href);
  await page.waitForFunction(() => window.reachViewer && window.reachViewer.ready, null, { timeout: 20000 });
  return { page, errors };
}

test('a UR5 motion: no console error, one object per link, tool where reach fk puts it', async () => {
  const motion = join(dir, 'ur5_motion.json');
  writeFileSync(
    motion,
    reach('move', 'ur5', '--from', '0,-90,90,0,90,0', '--to', '45,-60,60,30,60,20', '--profile', 'quintic', '--duration', '2', '--dt', '0.1', '--json'),
  );
  const report = JSON.parse(reach('move', 'ur5', '--from', '0,-90,90,0,90,0', '--to', '45,-60,60,30,60,20', '--profile', 'quintic', '--duration', '2', '--dt', '0.1', '--json'));
  const html = join(dir, 'ur5.html');
  reach('view', 'ur5', '--motion', motion, '-o', html);
  const { page, errors } = await open(html);

  // UR5: 6 joints, so 6 link segments + the last frame → tool segment.
  assert.equal(await page.evaluate(() => window.reachViewer.linkCount()), 7);

  for (const k of [0, 7, 13, report.samples.length - 1]) {
    const sample = report.samples[k];
    const shown = await page.evaluate((t) => {
      window.reachViewer.setTime(t);
      return { tool: window.reachViewer.toolPosition(), q: window.reachViewer.state().q_deg };
    }, sample.t_s);
    assert.deepEqual(shown.q.map((v) => +v.toFixed(9)), sample.q_deg.map((v) => +v.toFixed(9)));
    const fk = JSON.parse(reach('fk', 'ur5', ...sample.q_deg.map(String), '--json'));
    const expected = fk.pose.xyz_m;
    for (let i = 0; i < 3; i++) {
      assert.ok(Math.abs(shown.tool[i] - expected[i]) < 1e-6, `t=${sample.t_s}: tool ${shown.tool} vs fk ${expected}`);
    }
  }
  // Between samples the last sample at or before t is shown.
  const between = await page.evaluate((t) => {
    window.reachViewer.setTime(t);
    return window.reachViewer.state().t_s;
  }, (report.samples[3].t_s + report.samples[4].t_s) / 2);
  assert.equal(between, report.samples[3].t_s);
  assert.deepEqual(errors, []);
  await page.close();
});

const KR16 = 'examples/urdf/kuka_kr16_support/urdf/kr16_2.urdf';

test('the KUKA KR 16-2 from its URDF: meshes on every link, tool where reach fk puts it', async () => {
  const move = ['move', KR16, '--tip', 'tool0', '--from', '0,-90,90,0,45,0', '--to', '60,-50,40,90,-60,120', '--profile', 'quintic', '--duration', '2', '--dt', '0.1', '--json'];
  const text = reach(...move);
  const report = JSON.parse(text);
  const motion = join(dir, 'kr16_motion.json');
  writeFileSync(motion, text);
  const html = join(dir, 'kr16.html');
  reach('view', KR16, '--tip', 'tool0', '--motion', motion, '-o', html);
  const started = Date.now();
  const { page, errors } = await open(html);
  console.log(`KR16 page: ${(statSync(html).size / 1e6).toFixed(2)} MB, ready in ${Date.now() - started} ms`);

  // Every link with a <visual> in the document holds mesh objects; the others none.
  const counts = await page.evaluate(() => window.reachViewer.meshCounts());
  for (const link of ['base_link', 'link_1', 'link_2', 'link_3', 'link_4', 'link_5', 'link_6']) {
    assert.ok(counts[link] > 0, `link ${link}: ${counts[link]} meshes`);
  }
  assert.equal(counts.tool0, 0);
  assert.equal(await page.evaluate(() => window.reachViewer.linkCount()), 7);

  // The slider: the state shown is a sample of the motion, and urdf-loader's tip link (posed
  // by joint name from that sample's q) is where `reach fk` puts the tool.
  for (const v of [0, 180, 500, 730, 1000]) {
    const shown = await page.evaluate((value) => {
      const slider = document.getElementById('reach-slider');
      slider.value = String(value);
      slider.dispatchEvent(new Event('input'));
      const s = window.reachViewer.state();
      return { t: s.t_s, q: s.q_deg, tool: window.reachViewer.toolPosition() };
    }, v);
    const sample = report.samples.find((s) => Math.abs(s.t_s - shown.t) < 1e-9);
    assert.ok(sample, `slider ${v}: t = ${shown.t} is a sample time`);
    assert.deepEqual(shown.q.map((q) => +q.toFixed(9)), sample.q_deg.map((q) => +q.toFixed(9)));
    const fk = JSON.parse(reach('fk', KR16, '--tip', 'tool0', ...sample.q_deg.map(String), '--json')).pose.xyz_m;
    for (let i = 0; i < 3; i++) {
      assert.ok(Math.abs(shown.tool[i] - fk[i]) < 1e-6, `slider ${v}, t=${shown.t}: tool ${shown.tool} vs fk ${fk}`);
    }
  }
  if (process.env.REACH_SCREENSHOTS) {
    await page.evaluate(() => {
      const v = window.reachViewer;
      v.setTime(v.startTime() + 0.6 * v.duration());
    });
    mkdirSync(SHOTS, { recursive: true });
    await page.screenshot({ path: join(SHOTS, 'view_kr16.png') });
  }
  assert.deepEqual(errors, []);
  await page.close();
});

/** A motion file of samples (t_s, q_deg); returns its path. */
function motionFile(name, samples) {
  const file = join(dir, `${name}.json`);
  writeFileSync(file, JSON.stringify({ samples }));
  return file;
}

/** Configurations one after the other, `dt` seconds apart, as a motion file. */
function stepsFile(name, configurations, dt) {
  return motionFile(name, configurations.map((q, k) => ({ t_s: k * dt, q_deg: q })));
}

// Motions built from the seed workflows' reports.
const motions = {
  // `reach path` gives waypoints and segment durations: shown as a motion through them.
  path: () => {
    const path = JSON.parse(
      reach('path', 'planar3', 'examples/path_planar3_post.toml', '--from', '60,-40,-30', '--to', '0,-30,-30', '--duration', '10', '--json'),
    );
    let t = 0;
    return motionFile(
      'path',
      path.waypoints_deg.map((q, k) => {
        if (k > 0) t += path.segment_durations_s[k - 1];
        return { t_s: t, q_deg: q };
      }),
    );
  },
  // Seed 000: `reach avoid`'s detour legs (start → K2 → K3 → target, each a joint-space
  // straight line, as the detour checks them), each played by `reach move`, 1 s per 30° of S.
  detour: () => {
    const avoid = JSON.parse(reach('avoid', 'planar3', '--from', '60,-40,-30', '--to-xy', '2.4,0.2', '--obstacle', '2.0,0.7', '--json'));
    assert.equal(avoid.outcome.outcome, 'detour');
    const stops = [avoid.start_deg, ...avoid.configurations_deg];
    const samples = [];
    let offset = 0;
    for (let k = 0; k + 1 < stops.length; k++) {
      const duration = Math.max(0.5, avoid.leg_s_deg[k] / 30);
      const leg = JSON.parse(
        reach('move', 'planar3', '--from', stops[k].join(','), '--to', stops[k + 1].join(','), '--duration', String(duration), '--dt', '0.05', '--json'),
      );
      for (const s of leg.samples.slice(k ? 1 : 0)) samples.push({ t_s: offset + s.t_s, q_deg: s.q_deg });
      offset += leg.samples[leg.samples.length - 1].t_s;
    }
    return motionFile('detour', samples);
  },
  // Seed 004: `reach approach`'s increments to a joint goal next to the ceiling (q1, q4 stay 0).
  approach: () => {
    const approach = JSON.parse(
      reach('approach', 'varan4', 'examples/seed004_ceiling.toml', '--from', '0,30,0,0', '--to', '0,90,-100,0', '--json'),
    );
    assert.equal(approach.outcome, 'reached');
    return stepsFile('approach', approach.motion_deg, 0.1);
  },
};

const scenarios = [
  {
    name: 'seed003_weld',
    args: ['welder6r', '--plan', 'examples/seed003_welding.toml'],
    at: 0.4,
  },
  {
    name: 'seed004_zones',
    args: ['varan4', '0', '30', '-45', '10', '--scene', 'examples/seed004_two_planes.toml'],
  },
  {
    name: 'planar3_post_path',
    args: ['planar3', '--motion', '@path', '--scene', 'examples/path_planar3_post.toml'],
    at: 0.5,
  },
  {
    name: 'seed000_detour',
    args: ['planar3', '--motion', '@detour', '--scene', 'examples/seed000_obstacle.toml'],
    at: 0.45,
  },
  {
    name: 'ur5_ik_ghosts',
    args: ['ur5', '--ik-xyz', '0.4,0.2,0.3', '--ik-rpy', '180,0,0'],
  },
  {
    name: 'puma560_urdf',
    args: ['examples/urdf/unimation_puma560_description/urdf/puma560_robot.urdf', '0', '45', '-60', '0', '-30', '0'],
    // Inch meshes scaled by the document's <mesh scale="0.0254 …">; the tool is reach fk's.
    fk: true,
  },
];

for (const s of scenarios) {
  test(`scenario ${s.name} loads without console errors`, async () => {
    const args = s.args.map((a) => (a.startsWith('@') ? motions[a.slice(1)]() : a));
    const html = join(dir, `${s.name}.html`);
    reach('view', ...args, '-o', html);
    const { page, errors } = await open(html);
    if (s.at !== undefined) {
      await page.evaluate((f) => {
        const v = window.reachViewer;
        v.setTime(v.duration() * f + v.startTime());
      }, s.at);
    }
    assert.ok((await page.evaluate(() => window.reachViewer.linkCount())) > 0);
    if (s.fk) {
      const shown = await page.evaluate(() => ({ q: window.reachViewer.state().q_deg, tool: window.reachViewer.toolPosition() }));
      const fk = JSON.parse(reach('fk', s.args[0], ...shown.q.map(String), '--json')).pose.xyz_m;
      shown.tool.forEach((v, i) => assert.ok(Math.abs(v - fk[i]) < 1e-6, `tool ${shown.tool} vs fk ${fk}`));
    }
    if (process.env.REACH_SCREENSHOTS) {
      mkdirSync(SHOTS, { recursive: true });
      await page.screenshot({ path: join(SHOTS, `view_${s.name}.png`) });
    }
    assert.deepEqual(errors, []);
    await page.close();
  });
}

test('seed 004: the C-space section q2 × q3 shows the forbidden cells of reach cspace and the approach path', async () => {
  const motion = motions.approach();
  const html = join(dir, 'seed004_cspace.html');
  const scene = 'examples/seed004_ceiling.toml';
  reach('view', 'varan4', '--motion', motion, '--scene', scene, '--cspace', '2,3', '--cspace-step', '5', '-o', html);
  // The same section by `reach cspace`: q1 and q4 fixed where the motion starts (and stays).
  const grid = JSON.parse(reach('cspace', 'varan4', scene, '--fix', 'q1=0', '--fix', 'q4=0', '--step', '5', '--json'));
  assert.ok(grid.allowed > 0 && grid.allowed < grid.nodes);
  const samples = JSON.parse(readFileSync(motion, 'utf8')).samples;
  const { page, errors } = await open(html, { width: 1200, height: 720 });
  await page.evaluate(() => {
    const v = window.reachViewer;
    v.setTime(v.startTime() + 0.6 * v.duration());
  });
  const drawn = await page.evaluate(() => window.reachViewer.cspace());
  assert.equal(drawn.cells, grid.nodes);
  assert.equal(drawn.forbidden, grid.nodes - grid.allowed);
  assert.equal(drawn.pathPoints, samples.length);
  assert.equal(drawn.pathDrawn, samples.length, 'every path vertex is drawn over the grid');
  if (process.env.REACH_SCREENSHOTS) {
    mkdirSync(SHOTS, { recursive: true });
    await page.screenshot({ path: join(SHOTS, 'view_seed004_cspace.png') });
  }
  assert.deepEqual(errors, []);
  await page.close();
});
