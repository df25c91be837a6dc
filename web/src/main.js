// Entry point of the reach viewer. Reads the view report (JSON) from
// `<script id="reach-view-data" type="application/json">` when present, builds the page, and
// exposes the test and integration hook `window.reachViewer`:
//   ready            true once a report is drawn
//   load(report)     draws another view report (e.g. fed live by `reach serve`)
//   setTime(t)       shows the last state at or before t seconds (clamped to the motion)
//   time()           the time shown
//   startTime(), duration()   the motion's first time and length, seconds
//   state()          the state shown (t_s, q_deg, frames, tool, axes), as in the report
//   toolPosition()   world position [x, y, z] (metres) of the drawn tool point
//   linkCount()      number of link objects of the arm (one per link segment; for a URDF robot
//                    drawn with its meshes, the links of its document that hold a mesh)
//   cspace()         with a C-space section: { cells, forbidden, pathPoints } as drawn (cells whose
//                    centre shows a forbidden class's colour)
//   meshCounts()     URDF robots drawn with their meshes: per link name, its mesh objects
//   play() / pause()
//   armPixels()      the canvas pixels the arm covers at the state shown (the arm alone drawn for
//                    one frame): { width, height, x0, x1, y0, y1, count } (pixels, y down)
//   frameBox()       the world box the camera is fitted to, the camera's position, near, far
//   ghosts()         per IK ghost: branch, colour drawn, collides (the library's verdict in the
//                    scene), the label listed beside the view
//   contact()        a motion not proven clear in the scene: { t_s, end_s, link_name, text,
//                    marker (world position of the contact ball), markerVisible, timelineMarks };
//                    null otherwise
//   legend()         the joint plot's legend entries: text, full name, box in canvas pixels
//   live             on the page `reach serve` serves at `/`: received(), latencies() (ms from
//                    the service's send to the page's receipt of each joint state), lastState()
import * as THREE from 'three';
import { OrbitControls } from 'three/addons/controls/OrbitControls.js';
import { Arm, extent, polyline, shapeMesh, toolPath, ghostArms, ghostCollides, ghostVerdict, contactMarker, fitCamera, cornerPoints, boxCorners } from './scene.js';
import { JointPlot } from './plot.js';
import { el } from './dom.js';
import { startLive } from './live.js';
import { UrdfArm } from './urdf.js';
import { CspacePanel } from './cspace.js';

const CSS = `
html, body { margin: 0; height: 100%; font: 13px sans-serif; }
#reach { display: flex; height: 100%; }
#reach-main { flex: 1; display: flex; flex-direction: column; min-width: 0; }
#reach-3d { flex: 1; position: relative; min-height: 0; }
#reach-3d canvas { display: block; }
#reach-title { position: absolute; left: 8px; top: 6px; background: rgba(255,255,255,.8); padding: 2px 6px; }
#reach-timeline { padding: 6px 10px; border-top: 1px solid #ccc; display: flex; align-items: center; gap: 8px; }
#reach-track { flex: 1; position: relative; padding-top: 10px; }
#reach-slider { width: 100%; margin: 0; }
.reach-mark { position: absolute; top: 0; height: 9px; background: #d32f2f; min-width: 2px; opacity: .8; }
.reach-mark.motion { background: #555; }
.reach-mark.infeasible { background: #f9a825; }
#reach-side { width: 340px; border-left: 1px solid #ccc; padding: 8px; overflow: auto; }
#reach-q { font-family: monospace; white-space: pre; }
#reach-events { font-size: 12px; }
#reach-cspace-caption { font-size: 11px; margin-bottom: 6px; }
.reach-mark.contact { background: #b71c1c; height: 12px; top: -2px; opacity: 1; }
#reach-contact { color: #b71c1c; font-weight: bold; margin: 6px 0; cursor: pointer; }
#reach-ghosts { font-size: 12px; margin: 6px 0; }
.reach-ghost.collides { color: #d32f2f; }
`;

class Viewer {
  constructor(root) {
    el('style', { textContent: CSS }, document.head);
    this.root = el('div', { id: 'reach' }, root);
    const main = el('div', { id: 'reach-main' }, this.root);
    this.view = el('div', { id: 'reach-3d' }, main);
    this.title = el('div', { id: 'reach-title' }, this.view);
    const bar = el('div', { id: 'reach-timeline' }, main);
    this.playButton = el('button', { id: 'reach-play', textContent: '▶' }, bar);
    this.track = el('div', { id: 'reach-track' }, bar);
    this.slider = el('input', { id: 'reach-slider', type: 'range', min: 0, max: 1000, value: 0 }, this.track);
    this.clock = el('span', { id: 'reach-clock' }, bar);
    const side = el('div', { id: 'reach-side' }, this.root);
    this.side = side;
    this.plotCanvas = el('canvas', { id: 'reach-plot', width: 320, height: 200 }, side);
    this.qText = el('div', { id: 'reach-q' }, side);
    this.cspaceCanvas = el('canvas', { id: 'reach-cspace', width: 320, height: 280 }, side);
    this.cspaceCaption = el('div', { id: 'reach-cspace-caption' }, side);
    this.contactBox = el('div', { id: 'reach-contact' }, side);
    this.ghostList = el('div', { id: 'reach-ghosts' }, side);
    this.eventList = el('div', { id: 'reach-events' }, side);

    this.renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
    this.renderer.setPixelRatio(window.devicePixelRatio || 1);
    this.view.appendChild(this.renderer.domElement);
    this.camera = new THREE.PerspectiveCamera(45, 1, 0.01, 1000);
    this.camera.up.set(0, 0, 1);
    this.controls = new OrbitControls(this.camera, this.renderer.domElement);
    this.controls.addEventListener('change', () => this.render());
    this.playing = false;
    this.t = 0;
    this.ready = false;

    this.slider.addEventListener('input', () => {
      this.pause();
      this.setTime(this.t0 + (this.slider.value / 1000) * this.duration);
    });
    this.playButton.addEventListener('click', () => (this.playing ? this.pause() : this.play()));
    window.addEventListener('resize', () => this.resize());
  }

  load(report) {
    this.report = report;
    this.scene = new THREE.Scene();
    this.scene.background = new THREE.Color(0xf4f4f4);
    this.scene.add(new THREE.HemisphereLight(0xffffff, 0x888888, 2.0));
    const sun = new THREE.DirectionalLight(0xffffff, 1.5);
    sun.position.set(3, -4, 6);
    this.scene.add(sun);
    const size = extent(report);
    const grid = new THREE.GridHelper(4 * size, 20, 0xaaaaaa, 0xdddddd);
    grid.rotation.x = Math.PI / 2;
    grid.position.set(report.base.xyz_m[0], report.base.xyz_m[1], 0);
    this.scene.add(grid);
    this.scene.add(new THREE.AxesHelper(0.25 * size));

    this.shapeMeshes = report.shapes.map((s) => shapeMesh(s, size));
    this.shapeMeshes.forEach((m) => this.scene.add(m));
    if (report.states.length > 1) this.scene.add(toolPath(report));
    this.ghosts = ghostArms(report, size);
    this.ghosts.forEach((g) => this.scene.add(g.group));
    if (report.ik_target) {
      const target = new THREE.AxesHelper(0.15 * size);
      target.position.set(...report.ik_target.xyz_m);
      const q = report.ik_target.quat_wxyz;
      target.quaternion.set(q[1], q[2], q[3], q[0]);
      this.scene.add(target);
    }
    // A URDF robot with its document: its meshes; the capsules otherwise.
    this.urdfArm = report.urdf ? new UrdfArm(report) : null;
    if (this.urdfArm) this.scene.add(this.urdfArm.group);
    this.arm = new Arm(report, { scale: size, links: !this.urdfArm });
    this.arm.group.name = 'arm';
    this.scene.add(this.arm.group);

    this.contactMarker = report.contact ? contactMarker(report, size) : null;
    if (this.contactMarker) this.scene.add(this.contactMarker);

    this.t0 = report.states[0].t_s;
    this.duration = report.duration_s;
    this.title.textContent = `${report.robot}` + (report.ik_status ? ` — IK: ${report.ik_status}, ${report.ghosts.length} solution(s)` : '');
    this.plot = new JointPlot(this.plotCanvas, report);
    this.plotCanvas.style.display = report.states.length > 1 ? '' : 'none';
    this.cspace = report.cspace ? new CspacePanel(this.cspaceCanvas, this.cspaceCaption, report) : null;
    this.cspaceCanvas.style.display = this.cspace ? '' : 'none';
    if (!this.cspace) this.cspaceCaption.textContent = '';
    this.drawGhostList();
    this.drawContact();
    this.drawTimeline();
    this.resize();
    this.fitView();
    this.setTime(this.t0);
    this.ready = true;
  }

  /** The points the camera frames (world, metres): the corners of every link's box over the
   * motion (at most 25 states, evenly spaced, first and last included), of its IK ghosts and
   * contact marker, on the live page the box of the ball the arm can reach, and the scene's
   * obstacles where they are near all that (a floor or a wall is not framed as a whole). */
  framePoints() {
    const report = this.report;
    const states = report.states;
    const points = [];
    const drawn = this.urdfArm ? this.urdfArm.group : this.arm.group;
    const n = Math.min(states.length, 25);
    for (let k = 0; k < n; k++) {
      const s = states[n > 1 ? Math.round((k * (states.length - 1)) / (n - 1)) : 0];
      this.arm.set(s);
      if (this.urdfArm) this.urdfArm.set(s);
      // cornerPoints updates the world matrices after posing (the renderer would only at the
      // next frame): read before, they would be the previous pose's.
      cornerPoints(drawn, points);
      this.arm.group.updateMatrixWorld(true);
      points.push(this.arm.tip.getWorldPosition(new THREE.Vector3()));
    }
    for (const g of this.ghosts) cornerPoints(g.group, points);
    if (this.contactMarker) cornerPoints(this.contactMarker, points);
    if (this.liveMode) {
      // Live, the arm goes wherever the service moves it: frame the ball it can reach, around
      // the base, of radius the length of its polyline (base, frame origins, tool).
      const line = polyline(report, states[0]);
      let radius = Math.max(0, ...report.link_radii_m);
      for (let k = 1; k < line.length; k++) radius += line[k].distanceTo(line[k - 1]);
      boxCorners(new THREE.Box3().setFromCenterAndSize(line[0], new THREE.Vector3(2, 2, 2).multiplyScalar(radius)), points);
    }
    const arm = new THREE.Box3().setFromPoints(points);
    const reach = arm.getSize(new THREE.Vector3());
    const near = arm.clone().expandByScalar(0.5 * Math.max(reach.x, reach.y, reach.z));
    report.shapes.forEach((shape, i) => {
      if (shape.shape === 'half_space' || shape.role !== 'obstacle') return;
      const mesh = this.shapeMeshes[i];
      mesh.updateMatrixWorld(true);
      boxCorners(new THREE.Box3().setFromObject(mesh).intersect(near), points);
    });
    return points;
  }

  /** Fits the camera to `framePoints()` for the canvas's aspect, the orbit target at their
   * middle. An arm that moves in the base's x–y plane (seed 000's planar arms) is seen from
   * above. */
  fitView() {
    const report = this.report;
    const b = report.base.xyz_m;
    const planar = report.states.every((st) => [...st.frames, st.tool].every((f) => Math.abs(f.xyz_m[2] - b[2]) < 1e-9));
    const direction = planar ? new THREE.Vector3(0.15, -0.6, 1.9) : new THREE.Vector3(1.2, -1.7, 1.1);
    const points = this.framePoints();
    this.box = new THREE.Box3().setFromPoints(points);
    const centre = fitCamera(this.camera, points, direction, this.camera.aspect);
    this.controls.target.copy(centre);
    this.controls.update();
  }

  /** The IK solutions beside the view: the branch, and "in collision" (the library's verdict
   * in the scene) for those drawn red. */
  drawGhostList() {
    this.ghostList.textContent = '';
    for (const g of this.report.ghosts) {
      const collides = ghostCollides(g);
      const item = el('div', { className: `reach-ghost${collides ? ' collides' : ''}` }, this.ghostList);
      item.dataset.branch = g.branch;
      item.textContent =
        `${g.chosen ? '● ' : '○ '}${g.branch}` +
        (g.within_limits ? '' : ' (outside limits)') +
        (collides ? ` — ${ghostVerdict(g)} (${g.check.verdict_text})` : g.check ? ' — free' : '');
    }
  }

  /** The contact of the motion (`report.contact`): a line naming the link, what it touches and
   * when, and a click that shows that instant. */
  drawContact() {
    const c = this.report.contact;
    this.contactBox.textContent = '';
    this.contactBox.style.display = c ? '' : 'none';
    if (!c) return;
    const when = c.end_s != null ? `${c.t_s.toFixed(3)} s … ${c.end_s.toFixed(3)} s` : `${c.t_s.toFixed(3)} s`;
    this.contactBox.textContent = `contact: ${c.pair_text} at ${when} (not proven clear)`;
    this.contactBox.title = 'show the first contact';
    this.contactBox.onclick = () => this.setTime(c.t_s);
  }

  drawTimeline() {
    this.track.querySelectorAll('.reach-mark').forEach((m) => m.remove());
    this.eventList.textContent = '';
    const span = this.duration || 1;
    for (const e of this.report.events) {
      const left = ((e.t_s - this.t0) / span) * 100;
      const width = e.end_s != null ? ((e.end_s - e.t_s) / span) * 100 : 0;
      const mark = el('div', { className: `reach-mark ${e.code}`, title: `${e.t_s.toFixed(3)} s ${e.code}: ${e.message}` }, this.track);
      mark.style.left = `${left}%`;
      mark.style.width = `${width}%`;
      const item = el('div', { textContent: `${e.t_s.toFixed(3)} s  ${e.code}  ${e.message}` }, this.eventList);
      item.style.cursor = 'pointer';
      item.addEventListener('click', () => this.setTime(e.t_s));
    }
    const c = this.report.contact;
    if (c) {
      const end = c.end_s != null ? c.end_s : c.t_s;
      const mark = el('div', { className: 'reach-mark contact', title: `${c.t_s.toFixed(3)} s contact: ${c.pair_text}` }, this.track);
      mark.style.left = `${((c.t_s - this.t0) / span) * 100}%`;
      mark.style.width = `${((end - c.t_s) / span) * 100}%`;
    }
    this.slider.disabled = this.report.states.length < 2;
    this.playButton.disabled = this.slider.disabled;
  }

  resize() {
    const w = this.view.clientWidth || 800;
    const h = this.view.clientHeight || 600;
    this.renderer.setSize(w, h);
    this.camera.aspect = w / h;
    this.camera.updateProjectionMatrix();
    this.render();
  }

  stateAt(t) {
    const states = this.report.states;
    let lo = 0;
    let hi = states.length - 1;
    if (t >= states[hi].t_s) return hi;
    while (lo < hi) {
      const mid = (lo + hi + 1) >> 1;
      if (states[mid].t_s <= t + 1e-12) lo = mid;
      else hi = mid - 1;
    }
    return lo;
  }

  setTime(t) {
    if (!Number.isFinite(t)) throw new Error(`setTime: not a finite time: ${t}`);
    this.t = Math.min(Math.max(t, this.t0), this.t0 + this.duration);
    this.index = this.stateAt(this.t);
    const s = this.report.states[this.index];
    this.slider.value = this.duration > 0 ? Math.round(((this.t - this.t0) / this.duration) * 1000) : 0;
    this.clock.textContent = `${this.t.toFixed(3)} / ${(this.t0 + this.duration).toFixed(3)} s`;
    this.liveState = null;
    this.draw(s);
    this.plot.draw(s.t_s);
    if (this.cspace) this.cspace.draw(this.index);
  }

  render() {
    if (this.scene) this.renderer.render(this.scene, this.camera);
  }

  // The arm at a state sent by the service (live mode): drawn at once, the timeline left as is.
  showLive(s) {
    this.liveState = s;
    this.draw(s);
  }

  // The arm at state `s`, its joint values and tool position beside it.
  draw(s) {
    this.arm.set(s);
    if (this.urdfArm) this.urdfArm.set(s);
    const lines = this.report.joint_names.map((n, j) => {
      const unit = this.report.prismatic[j] ? 'm' : '°';
      // A long (URDF) name is cut to keep the value on the panel; the plot's tooltip has it whole.
      const name = n.length > 20 ? `${n.slice(0, 19)}…` : n;
      return `${name.padEnd(12)} ${s.q_deg[j].toFixed(3).padStart(10)} ${unit}`;
    });
    lines.push(`tool xyz (m)  ${s.tool.xyz_m.map((v) => v.toFixed(4)).join(' ')}`);
    this.qText.textContent = lines.join('\n');
    this.render();
  }

  /** The pixels the arm covers on the canvas (the arm alone drawn over the background, at the
   * state shown; everything else hidden for that one frame): their bounding box in pixels,
   * the canvas size and the count. */
  armPixels() {
    const shown = this.scene.children.map((c) => c.visible);
    const drawn = this.urdfArm ? this.urdfArm.group : this.arm.group;
    this.scene.children.forEach((c) => {
      if (!c.isLight) c.visible = c === drawn;
    });
    const extras = [...this.arm.axisLines, ...this.arm.frameHelpers];
    extras.forEach((o) => (o.visible = false));
    this.renderer.render(this.scene, this.camera);
    const gl = this.renderer.getContext();
    const w = gl.drawingBufferWidth;
    const h = gl.drawingBufferHeight;
    const px = new Uint8Array(w * h * 4);
    gl.readPixels(0, 0, w, h, gl.RGBA, gl.UNSIGNED_BYTE, px);
    const hex = this.scene.background.getHex(); // sRGB, as the canvas shows it
    const ref = [(hex >> 16) & 255, (hex >> 8) & 255, hex & 255];
    let [x0, x1, y0, y1, count] = [w, -1, h, -1, 0];
    for (let y = 0; y < h; y++) {
      for (let x = 0; x < w; x++) {
        const i = 4 * (y * w + x);
        if (Math.abs(px[i] - ref[0]) + Math.abs(px[i + 1] - ref[1]) + Math.abs(px[i + 2] - ref[2]) <= 12) continue;
        count++;
        x0 = Math.min(x0, x);
        x1 = Math.max(x1, x);
        // readPixels rows run bottom up.
        y0 = Math.min(y0, h - 1 - y);
        y1 = Math.max(y1, h - 1 - y);
      }
    }
    this.scene.children.forEach((c, i) => (c.visible = shown[i]));
    extras.forEach((o) => (o.visible = true));
    this.render();
    return { width: w, height: h, x0, x1, y0, y1, count };
  }

  play() {
    if (this.duration <= 0) return;
    if (this.t >= this.t0 + this.duration) this.setTime(this.t0);
    this.playing = true;
    this.playButton.textContent = '⏸';
    let last = performance.now();
    const step = (now) => {
      if (!this.playing) return;
      const dt = (now - last) / 1000;
      last = now;
      this.setTime(this.t + dt);
      if (this.t >= this.t0 + this.duration) this.pause();
      else requestAnimationFrame(step);
    };
    requestAnimationFrame(step);
  }

  pause() {
    this.playing = false;
    this.playButton.textContent = '▶';
  }
}

function start() {
  const viewer = new Viewer(document.body);
  window.reachViewer = {
    get ready() {
      return viewer.ready;
    },
    load: (report) => viewer.load(report),
    setTime: (t) => viewer.setTime(t),
    time: () => viewer.t,
    startTime: () => viewer.t0,
    duration: () => viewer.duration,
    state: () => viewer.liveState || viewer.report.states[viewer.index],
    toolPosition: () => (viewer.urdfArm ? viewer.urdfArm.toolPosition() : viewer.arm.tip.position.toArray()),
    linkCount: () =>
      viewer.urdfArm
        ? Object.values(viewer.urdfArm.meshCounts()).filter((n) => n > 0).length
        : viewer.arm.group.children.filter((c) => c.userData.link !== undefined).length,
    cspace: () => (viewer.cspace ? viewer.cspace.summary() : null),
    meshCounts: () => (viewer.urdfArm ? viewer.urdfArm.meshCounts() : {}),
    play: () => viewer.play(),
    pause: () => viewer.pause(),
    armPixels: () => viewer.armPixels(),
    frameBox: () => ({ min: viewer.box.min.toArray(), max: viewer.box.max.toArray(), camera: viewer.camera.position.toArray(), near: viewer.camera.near, far: viewer.camera.far }),
    ghosts: () =>
      viewer.ghosts.map((g, k) => ({
        branch: viewer.report.ghosts[k].branch,
        color: g.color,
        collides: g.group.userData.collides,
        label: viewer.ghostList.children[k].textContent,
      })),
    contact: () => {
      const c = viewer.report.contact;
      if (!c || !viewer.contactMarker) return null;
      const ball = viewer.contactMarker.getObjectByName('contact point');
      return {
        t_s: c.t_s,
        end_s: c.end_s,
        link_name: c.link_name,
        text: viewer.contactBox.textContent,
        marker: ball.getWorldPosition(new THREE.Vector3()).toArray(),
        markerVisible: ball.visible && viewer.contactMarker.visible,
        timelineMarks: viewer.track.querySelectorAll('.reach-mark.contact').length,
      };
    },
    legend: () => viewer.plot.legendBoxes(),
  };
  const data = document.getElementById('reach-view-data');
  viewer.liveMode = Boolean(data && data.dataset.live === '1');
  if (data) viewer.load(JSON.parse(data.textContent));
  if (data && data.dataset.live === '1') window.reachViewer.live = startLive(viewer, viewer.side);
}

if (document.readyState === 'loading') document.addEventListener('DOMContentLoaded', start);
else start();
