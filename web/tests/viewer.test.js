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
import { mkdtempSync, writeFileSync, mkdirSync, statSync } from 'node:fs';
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
    name: 'ur5_ik_ghosts',
    args: ['ur5', '--ik-xyz', '0.4,0.2,0.3', '--ik-rpy', '180,0,0'],
  },
];

for (const s of scenarios) {
  test(`scenario ${s.name} loads without console errors`, async () => {
    const args = s.args.map((a) => {
      if (a !== '@path') return a;
      // `reach path` gives waypoints and segment durations: shown as a motion through them.
      const path = JSON.parse(
        reach('path', 'planar3', 'examples/path_planar3_post.toml', '--from', '60,-40,-30', '--to', '0,-30,-30', '--duration', '10', '--json'),
      );
      let t = 0;
      const samples = path.waypoints_deg.map((q, k) => {
        if (k > 0) t += path.segment_durations_s[k - 1];
        return { t_s: t, q_deg: q };
      });
      const file = join(dir, 'path.json');
      writeFileSync(file, JSON.stringify({ samples }));
      return file;
    });
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
    if (process.env.REACH_SCREENSHOTS) {
      mkdirSync(SHOTS, { recursive: true });
      await page.screenshot({ path: join(SHOTS, `view_${s.name}.png`) });
    }
    assert.deepEqual(errors, []);
    await page.close();
  });
}
