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
import { execFileSync, spawnSync } from 'node:child_process';
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

/** The view report inlined in an exported page. */
function pageReport(html) {
  const text = readFileSync(html, 'utf8');
  const m = text.match(/<script id="reach-view-data" type="application\/json"[^>]*>([\s\S]*?)<\/script>/);
  return JSON.parse(m[1]);
}

/** `reach ARGS…` that may exit non-zero (3: not clear): its standard output and status. */
function reachStatus(...args) {
  const r = spawnSync(REACH, args, { cwd: ROOT, encoding: 'utf8', maxBuffer: 64 << 20 });
  return { stdout: r.stdout, status: r.status, stderr: r.stderr };
}

/** The arm's pixels (the arm alone drawn) at fractions `at` of the motion: per fraction the
 * pixel box, and their union. */
async function armCoverage(page, at) {
  return page.evaluate((fractions) => {
    const v = window.reachViewer;
    const boxes = fractions.map((f) => {
      v.setTime(v.startTime() + f * v.duration());
      return v.armPixels();
    });
    const union = boxes.reduce((u, b) => ({
      x0: Math.min(u.x0, b.x0),
      x1: Math.max(u.x1, b.x1),
      y0: Math.min(u.y0, b.y0),
      y1: Math.max(u.y1, b.y1),
    }));
    return { boxes, union, width: boxes[0].width, height: boxes[0].height };
  }, at);
}

/** Every box holds arm pixels and lies inside the canvas, off its border. */
function assertInside(cover, what) {
  for (const b of cover.boxes) {
    assert.ok(b.count > 0, `${what}: the arm is drawn`);
    assert.ok(b.x0 > 0 && b.y0 > 0 && b.x1 < b.width - 1 && b.y1 < b.height - 1, `${what}: arm pixels ${JSON.stringify(b)} touch the canvas border`);
  }
}

/** The fraction of the canvas's width and of its height a pixel box spans. */
function spans(b, cover) {
  return [(b.x1 - b.x0 + 1) / cover.width, (b.y1 - b.y0 + 1) / cover.height];
}

test('issue 35 point 10, camera fit: the weld arm over its motion fills the canvas and stays inside it', async () => {
  const html = join(dir, 'fit_weld.html');
  reach('view', 'welder6r', '--plan', 'examples/seed003_welding.toml', '-o', html);
  const { page, errors } = await open(html);
  const cover = await armCoverage(page, [0, 0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9, 1]);
  assertInside(cover, 'welder6r');
  const [w, h] = spans(cover.union, cover);
  console.log(`welder6r over its motion: arm pixels span ${(100 * w).toFixed(0)} % of the width, ${(100 * h).toFixed(0)} % of the height`);
  assert.ok(Math.max(w, h) >= 0.5, `the weld arm spans ${w.toFixed(2)} × ${h.toFixed(2)} of the canvas`);
  // At every instant the arm is a sizeable part of the view, not a speck.
  for (const b of cover.boxes) assert.ok(Math.max(...spans(b, cover)) >= 0.25, `arm pixels ${JSON.stringify(b)}`);
  assert.deepEqual(errors, []);
  await page.close();
});

test('issue 35 point 10, camera fit: a small arm (PUMA 560 preset) and a large one (KR 16-2 URDF) fill at least 40 % of the canvas', async () => {
  const cases = [
    { name: 'puma560', args: ['puma560', '0', '45', '-60', '0', '-30', '0'] },
    { name: 'kr16', args: [KR16, '--tip', 'tool0', '0', '-90', '90', '0', '45', '0'] },
    { name: 'kr16_capsules', args: [KR16, '--tip', 'tool0', '--no-meshes', '30', '-60', '60', '0', '45', '0'] },
  ];
  for (const c of cases) {
    const html = join(dir, `fit_${c.name}.html`);
    reach('view', ...c.args, '-o', html);
    for (const size of [
      { width: 1100, height: 650 },
      { width: 700, height: 900 },
    ]) {
      const { page, errors } = await open(html, size);
      const cover = await armCoverage(page, [0]);
      assertInside(cover, c.name);
      const [w, h] = spans(cover.union, cover);
      console.log(`${c.name} at ${size.width}×${size.height}: arm pixels span ${(100 * w).toFixed(0)} % × ${(100 * h).toFixed(0)} %`);
      assert.ok(Math.max(w, h) >= 0.4, `${c.name}: the arm spans ${w.toFixed(2)} × ${h.toFixed(2)} of the canvas`);
      assert.deepEqual(errors, []);
      await page.close();
    }
  }
});

test('issue 35 point 10, plot legend: long URDF joint names never overlap', async () => {
  // The KR 16-2 with joint names of 40-odd characters (drawn as capsules: the copy has no meshes beside it).
  const long = (k) => `kuka_kr16_2_${k}_axis_joint_with_a_very_long_name`;
  const text = readFileSync(join(ROOT, KR16), 'utf8').replace(/joint_a([1-6])\b(?!-)/g, (_, k) => long(k));
  const urdf = join(dir, 'kr16_long_names.urdf');
  writeFileSync(urdf, text);
  const motion = join(dir, 'kr16_long_motion.json');
  writeFileSync(
    motion,
    reach('move', urdf, '--tip', 'tool0', '--from', '0,-90,90,0,45,0', '--to', '60,-50,40,90,-60,120', '--duration', '2', '--dt', '0.1', '--json'),
  );
  const html = join(dir, 'kr16_long_names.html');
  reach('view', urdf, '--tip', 'tool0', '--no-meshes', '--motion', motion, '-o', html);
  const { page, errors } = await open(html);
  const legend = await page.evaluate(() => window.reachViewer.legend());
  const canvas = await page.evaluate(() => {
    const c = document.getElementById('reach-plot');
    return { width: c.width, height: c.height, title: c.title };
  });
  assert.equal(legend.length, 6);
  for (let k = 1; k <= 6; k++) {
    assert.equal(legend[k - 1].name, long(k));
    assert.ok(canvas.title.includes(long(k)), 'the tooltip names every joint in full');
  }
  for (const [i, a] of legend.entries()) {
    assert.ok(a.x >= 0 && a.x + a.width <= canvas.width && a.y >= 0 && a.y + a.height <= canvas.height, `entry ${a.text} is inside the canvas`);
    for (const b of legend.slice(i + 1)) {
      const apart = a.x + a.width <= b.x || b.x + b.width <= a.x || a.y + a.height <= b.y || b.y + b.height <= a.y;
      assert.ok(apart, `legend entries ${JSON.stringify(a)} and ${JSON.stringify(b)} overlap`);
    }
  }
  assert.deepEqual(errors, []);
  await page.close();
});

test('issue 35 point 10, IK ghosts inside an obstacle are drawn red and labelled "in collision", as reach check finds them', async () => {
  const ik = ['ur5', '--ik-xyz', '0.4,0.2,0.3', '--ik-rpy', '180,0,0'];
  const plain = join(dir, 'ghosts_plain.html');
  reach('view', ...ik, '-o', plain);
  const ghosts = pageReport(plain).ghosts;
  assert.ok(ghosts.length >= 4);
  assert.ok(ghosts.every((g) => g.check === undefined), 'without a scene no ghost is checked');
  // A ball around the elbow of the first solution.
  const elbow = ghosts[0].state.frames[2].xyz_m;
  const scene = join(dir, 'ghost_ball.toml');
  writeFileSync(scene, `length_unit = "m"\nangle_unit = "deg"\n\n[[obstacles]]\nname = "ball"\nshape = "sphere"\ncenter = [${elbow.join(', ')}]\nradius = 0.05\n`);
  const html = join(dir, 'ghosts_ball.html');
  reach('view', ...ik, '--scene', scene, '-o', html);
  const { page, errors } = await open(html);
  const drawn = await page.evaluate(() => window.reachViewer.ghosts());
  assert.equal(drawn.length, ghosts.length);
  let collide = 0;
  for (const [k, g] of drawn.entries()) {
    const check = reachStatus('check', 'ur5', scene, '--json', ...ghosts[k].state.q_deg.map(String));
    const verdict = JSON.parse(check.stdout);
    const free = verdict.verdict.verdict === 'free';
    assert.equal(check.status, free ? 0 : 3);
    assert.equal(g.collides, !free, `ghost ${g.branch}: reach check says ${verdict.verdict_text}`);
    if (free) {
      assert.notEqual(g.color, 0xd32f2f);
      assert.ok(!g.label.includes('in collision'), g.label);
    } else {
      collide += 1;
      assert.equal(g.color, 0xd32f2f, `ghost ${g.branch} is red`);
      assert.ok(g.label.includes(`in collision (${verdict.verdict_text})`), g.label);
    }
  }
  assert.ok(collide >= 1 && collide < drawn.length, `${collide} of ${drawn.length} ghosts collide: the ball must catch some, not all`);
  assert.deepEqual(errors, []);
  await page.close();
});

test('issue 35 point 10, collision marker: a colliding motion marks the contact (link, time, point) where reach check --motion finds it', async () => {
  const from = '60,-90,0,-90,0,0';
  const motion = join(dir, 'ur5_through_ball.json');
  writeFileSync(motion, reach('move', 'ur5', '--from', from, '--to', '-60,-90,0,-90,0,0', '--duration', '2', '--dt', '0.1', '--json'));
  const scene = 'examples/ur5_ball.toml';
  const check = reachStatus('check', 'ur5', scene, '--motion', motion, '--json', ...from.split(','));
  assert.equal(check.status, 3, 'reach check: the motion is not proven clear');
  const swept = JSON.parse(check.stdout).samples;
  assert.equal(swept.clear, false);
  // The same check run backwards (t → T − t) finds the last contact.
  const samples = JSON.parse(readFileSync(motion, 'utf8')).samples;
  const T = samples[samples.length - 1].t_s;
  const reversed = motionFile('ur5_through_ball_reversed', samples.map((s) => ({ t_s: T - s.t_s, q_deg: s.q_deg })).reverse());
  const last = samples[samples.length - 1].q_deg.map(String);
  const back = JSON.parse(reachStatus('check', 'ur5', scene, '--motion', reversed, '--json', ...last).stdout).samples;

  const html = join(dir, 'ur5_through_ball.html');
  reach('view', 'ur5', '--motion', motion, '--scene', scene, '-o', html);
  const { page, errors } = await open(html);
  const contact = await page.evaluate(() => window.reachViewer.contact());
  assert.ok(contact, 'the page shows a contact');
  assert.ok(Math.abs(contact.t_s - swept.t_s) < 1e-9, `contact at ${contact.t_s} s, reach check: ${swept.t_s} s`);
  assert.ok(Math.abs(contact.end_s - (T - back.t_s)) < 1e-9, `contact ends at ${contact.end_s} s, reach check backwards: ${T - back.t_s} s`);
  assert.ok(contact.end_s > contact.t_s);
  assert.equal(contact.link_name, 'upper_arm_link');
  assert.ok(contact.text.includes(swept.pair_text), contact.text);
  assert.ok(contact.text.includes(`${swept.t_s.toFixed(3)} s`), contact.text);
  assert.ok(contact.markerVisible);
  assert.equal(contact.timelineMarks, 1);
  // The marker is on the ball's surface (centre (0, −0.136, 0.3), radius 0.02), on the arm's side.
  const d = Math.hypot(contact.marker[0], contact.marker[1] + 0.136, contact.marker[2] - 0.3);
  assert.ok(Math.abs(d - 0.02) < 1e-4, `marker ${contact.marker} is ${d} m from the ball's centre`);
  assert.ok(contact.marker[1] > -0.136, 'the marker faces the arm (the upper arm runs along the base z axis)');
  // A click on the contact line shows its instant.
  await page.click('#reach-contact');
  assert.equal(await page.evaluate(() => window.reachViewer.time()), contact.t_s);
  assert.deepEqual(errors, []);
  await page.close();

  // The same motion past a ball out of its way: proven clear, no marker.
  const clearScene = join(dir, 'ball_away.toml');
  writeFileSync(clearScene, readFileSync(join(ROOT, scene), 'utf8').replace('center = [0, -0.136, 0.3]', 'center = [1.5, -0.136, 0.3]'));
  assert.equal(reachStatus('check', 'ur5', clearScene, '--motion', motion, ...from.split(',')).status, 0);
  const clearHtml = join(dir, 'ur5_past_ball.html');
  reach('view', 'ur5', '--motion', motion, '--scene', clearScene, '-o', clearHtml);
  assert.equal(pageReport(clearHtml).swept.clear, true);
  const opened = await open(clearHtml);
  assert.equal(await opened.page.evaluate(() => window.reachViewer.contact()), null);
  assert.equal(await opened.page.evaluate(() => document.querySelectorAll('.reach-mark.contact').length), 0);
  assert.deepEqual(opened.errors, []);
  await opened.page.close();
});
