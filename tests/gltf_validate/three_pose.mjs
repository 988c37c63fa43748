// Usage: node three_pose.mjs FILE.glb CLIP TIME OUT.bin
// Loads FILE.glb with three.js's GLTFLoader (the npm package pinned in package.json), plays the animation
// named CLIP (or none: "-") with an AnimationMixer at TIME seconds (clamped at the clip's end, not wrapped),
// and writes every mesh vertex as three shows it (morph targets applied, then skinning, then the node's world
// transform: Mesh.getVertexPosition and matrixWorld) as float32 x, y, z, the meshes in the glTF's mesh and
// primitive order (a mesh reordered by `export --optimize` put back in its source order by its
// _CAGEWRAP_SOURCE_INDEX attribute): what `cagewrap pose --out` writes for the same frame. Prints one line describing the scene
// (meshes, vertices, skinned, morph targets, the skinned mesh's node name and its bones' names in joint order).
// With a fifth argument "drivers", the morph weights of a mesh carrying pose-driven correctives (its extras'
// cagewrap_pose_correctives, docs/pose-correctives.md) are computed from the posed bones' angles as an engine
// would, replacing the clip's keyed weights: weight_k = full_k * sum_f weights[k][f] * clamp(side_f * angle_f / scale_f, 0, 1).
// Exits 1 on a load error or an unknown clip, 2 when three is not installed.
import fs from 'node:fs';

let THREE, GLTFLoader;
try {
  THREE = await import('three');
  ({ GLTFLoader } = await import('three/examples/jsm/loaders/GLTFLoader.js'));
} catch (e) {
  console.error('three is not installed: run scripts/setup.sh (npm install in tests/gltf_validate)');
  process.exit(2);
}

const [file, clipName, timeText, out, mode] = process.argv.slice(2);
if (!file || !clipName || !timeText || !out) {
  console.error('usage: node three_pose.mjs FILE.glb CLIP|- TIME OUT.bin');
  process.exit(1);
}
const bytes = fs.readFileSync(file);
const buffer = bytes.buffer.slice(bytes.byteOffset, bytes.byteOffset + bytes.byteLength);
const gltf = await new Promise((resolve, reject) => new GLTFLoader().parse(buffer, '', resolve, reject)).catch((e) => {
  console.error(`${file}: three.js cannot load it: ${e && e.message ? e.message : e}`);
  process.exit(1);
});

const scene = gltf.scene;
const time = Number(timeText);
if (clipName !== '-') {
  const clip = gltf.animations.find((a) => a.name === clipName);
  if (!clip) {
    console.error(`${file}: no animation '${clipName}' (it has: ${gltf.animations.map((a) => a.name).join(', ') || 'none'})`);
    process.exit(1);
  }
  const mixer = new THREE.AnimationMixer(scene);
  const action = mixer.clipAction(clip);
  action.setLoop(THREE.LoopOnce, 1);
  action.clampWhenFinished = true;
  action.play();
  mixer.setTime(Math.min(time, clip.duration));
}

// one joint angle (degrees) of a node, relative to its rest rotation (core/cage/keyposes.h, driver_value)
function driverAngle(target, bone) {
  const rest = new THREE.Quaternion(...target.rest_rotation);
  const q = rest.invert().multiply(bone.quaternion).normalize();
  if (q.w < 0) q.set(-q.x, -q.y, -q.z, -q.w);
  const axis = new THREE.Vector3(...target.axis).normalize();
  const v = new THREE.Vector3(q.x, q.y, q.z);
  const deg = 180 / Math.PI;
  if (target.kind === 'rotation') {
    const s = v.length();
    return s < 1e-15 ? 0 : 2 * Math.atan2(s, q.w) * (v.dot(axis) / s) * deg;
  }
  // swing * twist about the axis
  const proj = v.dot(axis);
  const twist = new THREE.Quaternion(axis.x * proj, axis.y * proj, axis.z * proj, q.w);
  const len = twist.length();
  if (len < 1e-12) return target.kind === 'twist' ? 0 : 180;
  twist.normalize();
  if (target.kind === 'twist') return 2 * Math.atan2(proj / len, q.w / len) * deg;
  const swing = q.clone().multiply(twist.clone().invert());
  return 2 * Math.acos(Math.min(1, Math.abs(swing.w))) * deg;
}
let driven = 0;
if (mode === 'drivers') {
  const byNode = new Map();
  scene.traverse((o) => {
    const a = gltf.parser.associations.get(o);
    if (a && a.nodes !== undefined) byNode.set(a.nodes, o);
  });
  scene.traverse((o) => {
    const pc = o.isMesh && o.userData && o.userData.cagewrap_pose_correctives;
    if (!pc) return;
    const features = pc.features.map((f, i) => {
      const bone = byNode.get(f.node);
      if (!bone) throw new Error(`pose-driven feature ${i} names node ${f.node}, which three.js did not load`);
      return Math.min(1, Math.max(0, (f.side * driverAngle(f, bone)) / f.scale));
    });
    pc.weights.forEach((row, k) => {
      let w = 0;
      row.forEach((c, i) => { w += c * features[i]; });
      o.morphTargetInfluences[k] = pc.full[k] * w;
    });
    driven += pc.weights.length;
  });
}
scene.updateMatrixWorld(true);

const meshes = [];
scene.traverse((o) => {
  if (o.isMesh) {
    const a = gltf.parser.associations.get(o) || {};
    meshes.push({ mesh: o, order: [a.meshes ?? 0, a.primitives ?? 0] });
  }
});
meshes.sort((x, y) => x.order[0] - y.order[0] || x.order[1] - y.order[1]);
let total = 0;
for (const { mesh } of meshes) total += mesh.geometry.attributes.position.count;
const values = new Float32Array(total * 3);
const v = new THREE.Vector3();
let at = 0;
let skinned = null;
let reordered = false;
for (const { mesh } of meshes) {
  if (mesh.isSkinnedMesh) {
    mesh.skeleton.update();
    skinned = skinned || mesh;
  }
  const n = mesh.geometry.attributes.position.count;
  // a mesh reordered for the GPU (cagewrap export --optimize) says where each vertex came from
  const source = mesh.geometry.attributes._cagewrap_source_index;
  reordered = reordered || !!source;
  for (let i = 0; i < n; ++i) {
    mesh.getVertexPosition(i, v);
    v.applyMatrix4(mesh.matrixWorld);
    const k = at + 3 * (source ? source.getX(i) : i);
    values[k] = v.x;
    values[k + 1] = v.y;
    values[k + 2] = v.z;
  }
  at += 3 * n;
}
fs.writeFileSync(out, Buffer.from(values.buffer));
const targets = meshes.length ? (meshes[0].mesh.geometry.morphAttributes.position || []).length : 0;
console.log(JSON.stringify({
  meshes: meshes.length,
  vertices: total,
  skinned: meshes.filter((m) => m.mesh.isSkinnedMesh).length,
  morph_targets: targets,
  reordered,
  driven,
  node: skinned ? skinned.name : null,
  bones: skinned ? skinned.skeleton.bones.map((b) => b.name) : [],
}));
