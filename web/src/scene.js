// The 3-D scene of a view report (`reach::jobs::view::ViewReport`): arm capsules between the
// precomputed frame origins, joint axes, frames, tool path, scene shapes, IK ghost arms.
// No kinematics here: every pose comes from the report.
import * as THREE from 'three';

const COLORS = {
  link: 0xf28c28,
  joint: 0x444444,
  axis: 0x1565c0,
  path: 0x6a1b9a,
  obstacle: 0xd32f2f,
  zone: 0x2e7d32,
  ghost: 0x00838f,
  ghostChosen: 0x1565c0,
  collides: 0xd32f2f,
};

const Y = new THREE.Vector3(0, 1, 0);

/** The polyline of a state: base origin, every frame origin, tool point (`dof + 2` points). */
export function polyline(report, state) {
  return [report.base.xyz_m, ...state.frames.map((f) => f.xyz_m), state.tool.xyz_m].map(
    (p) => new THREE.Vector3(p[0], p[1], p[2]),
  );
}

/** Places a unit cylinder (height 1 along y) between points a and b. */
function placeSegment(mesh, a, b) {
  const d = new THREE.Vector3().subVectors(b, a);
  const len = d.length();
  mesh.visible = len > 1e-9;
  if (!mesh.visible) return;
  mesh.position.copy(a).addScaledVector(d, 0.5);
  mesh.quaternion.setFromUnitVectors(Y, d.divideScalar(len));
  mesh.scale.set(1, len, 1);
}

function quat(q) {
  return new THREE.Quaternion(q[1], q[2], q[3], q[0]);
}

/** Size of the scene: the largest distance of any drawn point from the base. */
export function extent(report) {
  const base = new THREE.Vector3(...report.base.xyz_m);
  let r = 0.2;
  for (const s of [...report.states, ...report.ghosts.map((g) => g.state)]) {
    for (const p of polyline(report, s)) r = Math.max(r, p.distanceTo(base));
  }
  return r;
}

/** An arm: one capsule per link segment, a sphere per joint (`links: false`: neither, when the
 * links are drawn otherwise), axis lines, frames, the tool point. */
export class Arm {
  constructor(report, { color = COLORS.link, opacity = 1, axes = true, frames = true, links = true, scale = 1 }) {
    this.report = report;
    this.group = new THREE.Group();
    const n = report.link_radii_m.length;
    const visual = 0.015 * scale;
    const material = new THREE.MeshStandardMaterial({
      color,
      transparent: opacity < 1,
      opacity,
      depthWrite: opacity >= 1,
    });
    const jointMaterial = new THREE.MeshStandardMaterial({ color: COLORS.joint, transparent: opacity < 1, opacity });
    this.links = [];
    this.joints = [];
    for (let k = 0; k < (links ? n : 0); k++) {
      const r = report.link_radii_m[k] > 0 ? report.link_radii_m[k] : visual;
      const mesh = new THREE.Mesh(new THREE.CylinderGeometry(r, r, 1, 20), material);
      mesh.name = k < n - 1 ? report.joint_names[k] : 'tool';
      mesh.userData.link = k + 1;
      this.links.push(mesh);
      this.group.add(mesh);
      const ball = new THREE.Mesh(new THREE.SphereGeometry(r * 1.15, 20, 12), jointMaterial);
      this.joints.push(ball);
      this.group.add(ball);
    }
    this.tip = new THREE.Mesh(new THREE.SphereGeometry(visual * 1.2, 16, 10), jointMaterial);
    this.group.add(this.tip);
    this.axisLines = [];
    if (axes) {
      const m = new THREE.LineBasicMaterial({ color: COLORS.axis });
      for (let i = 0; i < report.joint_names.length; i++) {
        const g = new THREE.BufferGeometry().setFromPoints([new THREE.Vector3(), new THREE.Vector3()]);
        const line = new THREE.Line(g, m);
        this.axisLines.push(line);
        this.group.add(line);
      }
    }
    this.axisLength = 0.12 * scale;
    this.frameHelpers = [];
    if (frames) {
      for (let i = 0; i <= report.joint_names.length; i++) {
        const h = new THREE.AxesHelper(i === report.joint_names.length ? 0.1 * scale : 0.05 * scale);
        this.frameHelpers.push(h);
        this.group.add(h);
      }
    }
  }

  /** Poses the arm at a state of the report. */
  set(state) {
    const pts = polyline(this.report, state);
    this.links.forEach((mesh, k) => placeSegment(mesh, pts[k], pts[k + 1]));
    this.joints.forEach((ball, k) => ball.position.copy(pts[k]));
    this.tip.position.copy(pts[pts.length - 1]);
    this.axisLines.forEach((line, i) => {
      const a = state.axes[i];
      const p = new THREE.Vector3(...a.point_m);
      const d = new THREE.Vector3(...a.direction).multiplyScalar(this.axisLength);
      line.geometry.setFromPoints([p.clone().sub(d), p.clone().add(d)]);
    });
    const poses = [...state.frames, state.tool];
    this.frameHelpers.forEach((h, i) => {
      h.position.set(...poses[i].xyz_m);
      h.quaternion.copy(quat(poses[i].quat_wxyz));
    });
  }
}

/** A scene shape as a mesh (half-spaces as a square patch of their boundary plane). */
export function shapeMesh(shape, size) {
  const zone = shape.role === 'tool_zone';
  const material = new THREE.MeshStandardMaterial({
    color: zone ? COLORS.zone : COLORS.obstacle,
    transparent: true,
    opacity: zone ? 0.15 : shape.shape === 'half_space' ? 0.18 : 0.45,
    side: THREE.DoubleSide,
    depthWrite: false,
  });
  let mesh;
  switch (shape.shape) {
    case 'point':
      mesh = new THREE.Mesh(new THREE.SphereGeometry(0.02 * size, 12, 8), material);
      mesh.position.set(...shape.at_m);
      break;
    case 'sphere':
      mesh = new THREE.Mesh(new THREE.SphereGeometry(shape.radius_m, 32, 16), material);
      mesh.position.set(...shape.center_m);
      break;
    case 'box': {
      const h = shape.half_extents_m.map((v) => Math.max(2 * v, 1e-4));
      mesh = new THREE.Mesh(new THREE.BoxGeometry(h[0], h[1], h[2]), material);
      mesh.position.set(...shape.center_m);
      mesh.quaternion.copy(quat(shape.quat_wxyz));
      break;
    }
    case 'capsule': {
      const a = new THREE.Vector3(...shape.a_m);
      const b = new THREE.Vector3(...shape.b_m);
      mesh = new THREE.Mesh(new THREE.CapsuleGeometry(shape.radius_m, 1, 8, 20), material);
      placeSegment(mesh, a, b);
      mesh.scale.set(1, 1, 1);
      mesh.geometry = new THREE.CapsuleGeometry(shape.radius_m, a.distanceTo(b), 8, 20);
      mesh.visible = true;
      break;
    }
    case 'half_space': {
      const n = new THREE.Vector3(...shape.normal);
      mesh = new THREE.Mesh(new THREE.PlaneGeometry(2 * size, 2 * size), material);
      mesh.position.copy(n.clone().multiplyScalar(shape.offset_m));
      mesh.quaternion.setFromUnitVectors(new THREE.Vector3(0, 0, 1), n);
      break;
    }
    default:
      throw new Error(`unknown shape ${shape.shape}`);
  }
  mesh.name = shape.name;
  return mesh;
}

/** The tool path through every state. */
export function toolPath(report) {
  const pts = report.states.map((s) => new THREE.Vector3(...s.tool.xyz_m));
  return new THREE.Line(
    new THREE.BufferGeometry().setFromPoints(pts),
    new THREE.LineBasicMaterial({ color: COLORS.path }),
  );
}

/** Whether the library's check in the report's scene found ghost `g` in collision (or its tool
 * outside the zone): `g.check` is absent without a scene. */
export function ghostCollides(g) {
  return g.check != null && !g.check.free;
}

/** What the library's check holds against ghost `g` (one that `ghostCollides`), in words:
 * "in collision" (an obstacle or two links) or "tool outside the zone". */
export function ghostVerdict(g) {
  return g.check.verdict.verdict === 'outside_zone' ? 'tool outside the zone' : 'in collision';
}

/** Ghost arms of the IK solutions: red when the library's check finds them in collision. */
export function ghostArms(report, scale) {
  return report.ghosts.map((g) => {
    const collides = ghostCollides(g);
    const arm = new Arm(report, {
      color: collides ? COLORS.collides : g.chosen ? COLORS.ghostChosen : COLORS.ghost,
      opacity: collides ? 0.35 : g.within_limits ? 0.3 : 0.12,
      axes: false,
      frames: false,
      scale,
    });
    arm.set(g.state);
    arm.group.name = `ghost ${g.branch}`;
    arm.group.userData.collides = collides;
    arm.color = collides ? COLORS.collides : g.chosen ? COLORS.ghostChosen : COLORS.ghost;
    return arm;
  });
}

/** The contact of a motion that the library's swept check does not prove clear
 * (`report.contact`): a red ball at the contact point and the arm at that instant, drawn red
 * and translucent. */
export function contactMarker(report, scale) {
  const c = report.contact;
  const group = new THREE.Group();
  group.name = 'contact';
  const ball = new THREE.Mesh(
    new THREE.SphereGeometry(0.03 * scale, 20, 12),
    new THREE.MeshStandardMaterial({ color: COLORS.collides, depthTest: false, transparent: true, opacity: 0.9 }),
  );
  ball.name = 'contact point';
  ball.renderOrder = 10;
  ball.position.set(...c.xyz_m);
  group.add(ball);
  const arm = new Arm(report, { color: COLORS.collides, opacity: 0.3, axes: false, frames: false, scale });
  arm.set(c.state);
  arm.group.name = 'contact arm';
  group.add(arm.group);
  return group;
}

/** Pushes the 8 corners of `box`, mapped by `matrix` when given, onto `points`. */
export function boxCorners(box, points, matrix = null) {
  if (box.isEmpty()) return points;
  for (let i = 0; i < 8; i++) {
    const p = new THREE.Vector3(i & 1 ? box.max.x : box.min.x, i & 2 ? box.max.y : box.min.y, i & 4 ? box.max.z : box.min.z);
    points.push(matrix ? p.applyMatrix4(matrix) : p);
  }
  return points;
}

/** Pushes the world-space corners of the bounding box of every visible mesh under
 * `object` onto `points` (updates the world matrices first). */
export function cornerPoints(object, points) {
  object.updateMatrixWorld(true);
  object.traverseVisible((o) => {
    if (!o.isMesh || !o.geometry) return;
    if (!o.geometry.boundingBox) o.geometry.computeBoundingBox();
    boxCorners(o.geometry.boundingBox, points, o.matrixWorld);
  });
  return points;
}

/**
 * Puts `camera` looking along −`direction` (unit vector towards the camera) at the points,
 * as close as it can be with every point inside the view with `margin` (a fraction of the
 * half-angles) to spare, for the camera's vertical field of view and `aspect` (width /
 * height): the target is the middle of the points' extents across the view, and the distance
 * the smallest that keeps each point, at its depth, within the half-angles. Sets near and far
 * around the points. Returns the target (the orbit centre).
 */
export function fitCamera(camera, points, direction, aspect, margin = 0.9) {
  const back = direction.clone().normalize();
  const up = camera.up.clone().sub(back.clone().multiplyScalar(camera.up.dot(back)));
  if (up.lengthSq() < 1e-12) up.set(0, 1, 0).sub(back.clone().multiplyScalar(back.y));
  up.normalize();
  const right = new THREE.Vector3().crossVectors(up, back).normalize();
  const lo = [Infinity, Infinity, Infinity];
  const hi = [-Infinity, -Infinity, -Infinity];
  for (const p of points) {
    [p.dot(right), p.dot(up), p.dot(back)].forEach((v, i) => {
      lo[i] = Math.min(lo[i], v);
      hi[i] = Math.max(hi[i], v);
    });
  }
  if (!points.length) [0, 1, 2].forEach((i) => ((lo[i] = -1), (hi[i] = 1)));
  const mid = [0, 1, 2].map((i) => (lo[i] + hi[i]) / 2);
  const centre = new THREE.Vector3()
    .addScaledVector(right, mid[0])
    .addScaledVector(up, mid[1])
    .addScaledVector(back, mid[2]);
  const tanV = Math.tan(THREE.MathUtils.degToRad(camera.fov) / 2) * margin;
  const tanH = tanV * aspect;
  // A point at depth z towards the camera and offsets x, y from the target is inside the view
  // from distance D when |x| ≤ (D − z)·tanH and |y| ≤ (D − z)·tanV.
  let distance = 1e-3;
  for (const p of points) {
    const d = p.clone().sub(centre);
    const z = d.dot(back);
    distance = Math.max(distance, z + Math.abs(d.dot(right)) / tanH, z + Math.abs(d.dot(up)) / tanV);
  }
  const radius = Math.hypot(hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]) / 2 || 1;
  camera.position.copy(centre).addScaledVector(back, distance);
  camera.near = Math.max(distance - 2 * radius, distance / 1000);
  camera.far = distance + 20 * radius;
  camera.lookAt(centre);
  camera.updateProjectionMatrix();
  return centre;
}
