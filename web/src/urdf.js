// A URDF robot drawn from its own document and visual meshes (`report.urdf`, see
// `reach::jobs::view::ViewUrdf`): urdf-loader builds the links from the document, the meshes
// come from the report (base64, decoded here; the page makes no request), and every state
// poses the document's joints by name with the state's joint values. The chain's base link is
// placed at the report's base pose; the tool point is the origin of the chain's tip link.
import * as THREE from 'three';
import URDFLoader from 'urdf-loader';
import { STLLoader } from 'three/examples/jsm/loaders/STLLoader.js';
import { ColladaLoader } from 'three/examples/jsm/loaders/ColladaLoader.js';

/** The bytes of a base64 string. */
function decode(b64) {
  const s = atob(b64);
  const bytes = new Uint8Array(s.length);
  for (let i = 0; i < s.length; i++) bytes[i] = s.charCodeAt(i);
  return bytes;
}

/** A mesh object from an inlined STL or Collada file (`material`: the URDF's, for STL). */
function meshObject(filename, bytes, material) {
  if (/\.stl$/i.test(filename)) {
    const geometry = new STLLoader().parse(bytes.buffer);
    geometry.computeVertexNormals();
    return new THREE.Mesh(geometry, material || new THREE.MeshPhongMaterial({ color: 0xb0b0b0 }));
  }
  if (/\.dae$/i.test(filename)) return new ColladaLoader().parse(new TextDecoder().decode(bytes), '').scene;
  throw new Error(`mesh ${filename}: only STL and Collada (.dae) meshes are drawn`);
}

export class UrdfArm {
  constructor(report) {
    const doc = report.urdf;
    this.report = report;
    const files = new Map(doc.meshes.map((m) => [m.filename, m.base64]));
    const loader = new URDFLoader();
    // Keep every address as the document writes it: it is the key of the inlined mesh.
    loader.packages = (pkg) => `package://${pkg}`;
    loader.workingPath = '';
    loader.loadMeshCb = (path, manager, material, done) => {
      const b64 = files.get(path);
      if (b64 === undefined) {
        done(null, new Error(`mesh ${path} is not in the page`));
        return;
      }
      try {
        done(meshObject(path, decode(b64), material));
      } catch (e) {
        done(null, e);
      }
    };
    this.robot = loader.parse(doc.text);
    for (const j of Object.values(this.robot.joints)) j.ignoreLimits = true;
    for (const name of report.joint_names) {
      if (!(name in this.robot.joints)) throw new Error(`URDF: no joint named ${name}`);
    }
    for (const name of [doc.base_link, doc.tip_link]) {
      if (!(name in this.robot.links)) throw new Error(`URDF: no link named ${name}`);
    }
    this.robot.matrixAutoUpdate = false;
    this.group = new THREE.Group();
    this.group.name = 'urdf';
    this.group.add(this.robot);
    const b = report.base;
    this.base = new THREE.Matrix4().compose(
      new THREE.Vector3(...b.xyz_m),
      new THREE.Quaternion(b.quat_wxyz[1], b.quat_wxyz[2], b.quat_wxyz[3], b.quat_wxyz[0]),
      new THREE.Vector3(1, 1, 1),
    );
  }

  /** Poses the robot at a state: joint values by name, the base link at the report's base. */
  set(state) {
    this.report.joint_names.forEach((name, j) => {
      const v = state.q_deg[j];
      this.robot.setJointValue(name, this.report.prismatic[j] ? v : (v * Math.PI) / 180);
    });
    // The base link's pose in the robot's root frame, then the root placed to put it at `base`.
    this.robot.matrix.identity();
    this.group.updateMatrixWorld(true);
    const inRoot = this.robot.links[this.report.urdf.base_link].matrixWorld.clone();
    this.robot.matrix.copy(this.base).multiply(inRoot.invert());
    this.group.updateMatrixWorld(true);
  }

  /** World position of the tip link's origin (the tool point). */
  toolPosition() {
    return this.robot.links[this.report.urdf.tip_link].getWorldPosition(new THREE.Vector3()).toArray();
  }

  /** Per link of the document: how many mesh objects its visuals hold. */
  meshCounts() {
    const counts = {};
    for (const [name, link] of Object.entries(this.robot.links)) {
      let n = 0;
      for (const visual of link.children.filter((c) => c.isURDFVisual)) {
        visual.traverse((o) => {
          if (o.isMesh) n += 1;
        });
      }
      counts[name] = n;
    }
    return counts;
  }
}
