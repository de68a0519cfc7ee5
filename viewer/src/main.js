// The plan viewer (docs/viewer.md): a plan's animated glTF (robot, scene,
// object, path) with its plan JSON (grasp, statistics). Play, pause and
// scrub the trajectory, orbit the camera, see the contacts with their
// normals and friction cones, and what a depth camera or a point cloud saw;
// with a physics verdict, play the simulated lift (the glTF's second
// animation) instead. `hfts-client view PLAN.json -o plan.html`
// embeds everything in one page (window.HFTS_PLAN, window.HFTS_GLB_BASE64);
// without them the page asks for the two files.
import * as THREE from 'three';
import {GLTFLoader} from 'three/examples/jsm/loaders/GLTFLoader.js';
import {OrbitControls} from 'three/examples/jsm/controls/OrbitControls.js';

const FRICTION = 0.5;  // the planner's default (docs/grasp_quality.md)
const CONE_HEIGHT = 0.03;
const POINT_PIXELS = 4;
const VOXEL_OPACITY = 0.3;

/// World (z up, the planner's frame) to the glTF's y up.
function toView([x, y, z]) {
  return new THREE.Vector3(x, z, -y);
}

function base64Bytes(text) {
  const binary = atob(text);
  const bytes = new Uint8Array(binary.length);
  for (let i = 0; i < binary.length; ++i) bytes[i] = binary.charCodeAt(i);
  return bytes.buffer;
}

/// Red spheres on the contacts, arrows along the inward normals and the
/// friction cones (half-angle atan(mu)) opening outwards, where the finger is.
function contactMarkers(grasp) {
  const group = new THREE.Group();
  group.name = 'contact_markers';
  // Drawn over everything: a contact lies where a fingertip touches the
  // object, inside the finger's own geometry.
  const red = new THREE.MeshStandardMaterial({color: 0xe02020, depthTest: false});
  const coneMaterial = new THREE.MeshStandardMaterial(
      {color: 0xffc020, transparent: true, opacity: 0.45, side: THREE.DoubleSide, depthWrite: false});
  const radius = CONE_HEIGHT * FRICTION;
  for (const c of grasp.contacts_world) {
    const p = toView(c.position);
    const inward = toView(c.normal).normalize();
    const dot = new THREE.Mesh(new THREE.SphereGeometry(0.006, 16, 12), red);
    dot.position.copy(p);
    dot.renderOrder = 10;
    group.add(dot);
    group.add(new THREE.ArrowHelper(inward, p.clone().addScaledVector(inward, -0.04), 0.04,
                                    0xe02020, 0.012, 0.006));
    // ConeGeometry points its apex along +y, centred: put the apex on the
    // contact and the base outwards.
    const cone = new THREE.Mesh(new THREE.ConeGeometry(radius, CONE_HEIGHT, 24, 1, true), coneMaterial);
    cone.quaternion.setFromUnitVectors(new THREE.Vector3(0, 1, 0), inward);
    cone.position.copy(p).addScaledVector(inward, -CONE_HEIGHT / 2);
    group.add(cone);
  }
  return group;
}

/// The HFTS nodes the goal sampler visited (plan --explored; the paper's
/// Fig. 5): each node's representative contacts on the object, coloured
/// from blue (lowest Eq. (1) value) to red (highest), top-level nodes larger.
function exploredMarkers(plan) {
  const group = new THREE.Group();
  group.name = 'explored';
  const nodes = plan.explored || [];
  const order = nodes.map((n, i) => [n.value, i]).sort((a, b) => a[0] - b[0]);
  const rank = new Array(nodes.length);
  order.forEach(([, i], r) => { rank[i] = nodes.length > 1 ? r / (nodes.length - 1) : 1; });
  const [px, py, pz] = plan.object_pose.position;
  const [qx, qy, qz, qw] = plan.object_pose.orientation;
  const rotation = new THREE.Quaternion(qx, qy, qz, qw);
  nodes.forEach((node, i) => {
    const colour = new THREE.Color().setHSL(0.66 * (1 - rank[i]), 0.9, 0.5);
    const material = new THREE.MeshBasicMaterial({color: colour});
    const radius = node.level === 1 ? 0.005 : node.level === 2 ? 0.0035 : 0.0025;
    for (const c of node.contacts_object) {
      const world = new THREE.Vector3(...c).applyQuaternion(rotation).add(new THREE.Vector3(px, py, pz));
      const dot = new THREE.Mesh(new THREE.SphereGeometry(radius, 10, 8), material);
      dot.position.copy(toView([world.x, world.y, world.z]));
      group.add(dot);
    }
  });
  return group;
}

/// Sensed obstacles (docs/point_clouds.md): the glTF holds each one's
/// voxels (node "<name>") and the points the sensor saw ("<name>.points",
/// glTF's POINTS, which three.js draws one pixel wide). The points grow to
/// POINT_PIXELS and their voxels, which hold them and would hide them, turn
/// translucent; the points are drawn after them, not tinted by them.
/// Returns the number of points.
function showSensedPoints(root) {
  const clouds = [];
  root.traverse((o) => { if (o.isPoints) clouds.push(o); });
  let count = 0;
  for (const cloud of clouds) {
    Object.assign(cloud.material, {size: POINT_PIXELS, sizeAttenuation: false, transparent: true});
    cloud.renderOrder = 1;
    count += cloud.geometry.attributes.position.count;
    const obstacle = (cloud.userData.name || '').replace(/\.points$/, '');
    root.traverse((o) => {
      if (!o.isMesh || o.userData.name !== obstacle) return;
      o.material = o.material.clone();  // obstacles share one material
      Object.assign(o.material, {transparent: true, opacity: VOXEL_OPACITY, depthWrite: false});
    });
  }
  return count;
}

function statsTable(plan, points) {
  const s = plan.stats, g = plan.grasp, t = plan.trajectory;
  const rows = [
    ['scene', plan.scene], ['object', plan.object], ['algorithm', `${plan.algorithm}, seed ${plan.seed}`],
    ['epsilon', g.epsilon.toPrecision(4)], ['reachability', `${(1000 * g.reachability).toFixed(2)} mm`],
    ['fingertip error', `${(1000 * g.fingertip_error).toFixed(2)} mm`],
    ['planning time', `${s.planning_time.toFixed(3)} s`], ['iterations', s.iterations],
    ['goal sampling', `${s.goal_sampling_calls} calls, ${s.valid_goal_samples} valid`],
    ['HFTS nodes', s.hfts_nodes_explored], ['collision checks', s.collision_checks],
    ['path', `${plan.path.length} waypoints, length ${s.path_length_smoothed.toFixed(3)}`],
    ['trajectory', `${t.duration.toFixed(2)} s, hand closes at ${t.closing_start.toFixed(2)} s`],
    ['friction cones', `mu = ${FRICTION}`],
  ];
  if (plan.explored) rows.push(['explored nodes', `${plan.explored.length} (blue: low, red: high Eq. 1 value)`]);
  if (points) rows.push(['sensed points', `${points} (violet; their voxels translucent)`]);
  const p = plan.physics;
  if (p) {
    const held = p.trials.filter((trial) => trial.held).length;
    rows.push(['physics', `${p.held ? 'held' : 'NOT held'}, in ${held} of ${p.trials.length} trials`]);
    const failed = p.trials.find((trial) => !trial.held);
    if (failed) rows.push(['first failure', `${failed.name}: ${failed.failure}`]);
    rows.push(['lift', p.lift_direction]);
  }
  const place = plan.place;
  if (place) {
    const at = place.object_pose.position.map((v) => v.toFixed(3)).join(', ');
    rows.push(['place', `at (${at}), retreat ${place.retreat_direction}`]);
    rows.push(['phases', `carry ${t.carry_start.toFixed(2)} s, down ${t.place_start.toFixed(2)} s, ` +
                         `open ${t.release_start.toFixed(2)} s, retreat ${t.retreat_start.toFixed(2)} s`]);
  }
  const pp = plan.place_physics;
  if (pp) rows.push(['pick and place in physics', `${pp.held ? 'held' : 'NOT held'}, ${pp.placed ? 'stayed' : 'did NOT stay'}`]);
  return rows.map(([k, v]) => `<tr><th>${k}</th><td>${v}</td></tr>`).join('');
}

/// The phase of the simulated trial at time t (plan.physics.motion).
function phaseAt(plan, t) {
  const samples = (plan.physics && plan.physics.motion) || [];
  let phase = '';
  for (const s of samples) {
    if (s.time > t + 1e-9) break;
    phase = s.phase;
  }
  return phase;
}

function show(plan, glb) {
  const container = document.getElementById('view');
  const renderer = new THREE.WebGLRenderer({antialias: true, preserveDrawingBuffer: true});
  renderer.setPixelRatio(window.devicePixelRatio);
  renderer.setSize(container.clientWidth, container.clientHeight);
  container.appendChild(renderer.domElement);
  const scene = new THREE.Scene();
  scene.background = new THREE.Color(0xf4f4f0);
  scene.add(new THREE.HemisphereLight(0xffffff, 0x606060, 2.0));
  const sun = new THREE.DirectionalLight(0xffffff, 1.5);
  sun.position.set(2, 4, 3);
  scene.add(sun);
  const grid = new THREE.GridHelper(2, 20, 0xa0a0a0, 0xd0d0d0);
  scene.add(grid);
  const camera = new THREE.PerspectiveCamera(45, container.clientWidth / container.clientHeight, 0.01, 50);
  const controls = new OrbitControls(camera, renderer.domElement);

  new GLTFLoader().parse(glb, '', (gltf) => {
    scene.add(gltf.scene);
    const points = showSensedPoints(gltf.scene);
    const markers = contactMarkers(plan.grasp);
    scene.add(markers);
    const explored = exploredMarkers(plan);
    scene.add(explored);
    const toggle = document.getElementById('show-explored');
    toggle.parentElement.hidden = !plan.explored;
    toggle.onchange = () => { explored.visible = toggle.checked; };
    const box = new THREE.Box3().setFromObject(gltf.scene);
    // Look at the object from the robot's side, turned 50 degrees and from
    // above: the approach and the hand on the object are in view.
    // A pick and place: between where the object was and where it goes,
    // from farther away.
    const from = toView(plan.object_pose.position);
    const to = plan.place ? toView(plan.place.object_pose.position) : from;
    const target = from.clone().add(to).multiplyScalar(0.5);
    const distance = 1.3 + 1.5 * from.distanceTo(to);
    const towardsRobot = new THREE.Vector3(-target.x, 0, -target.z);
    if (towardsRobot.lengthSq() < 1e-6) towardsRobot.set(1, 0, 0);
    towardsRobot.normalize().applyAxisAngle(new THREE.Vector3(0, 1, 0), THREE.MathUtils.degToRad(50));
    controls.target.copy(target);
    camera.position.copy(target).addScaledVector(towardsRobot, distance).add(new THREE.Vector3(0, 0.8 * distance / 1.3, 0));
    camera.lookAt(target);
    controls.update();
    grid.position.y = box.min.y;

    const mixer = new THREE.AnimationMixer(gltf.scene);
    // "plan": the trajectory; "simulated": the physics check's nominal
    // trial (close, lift, hold, disturbances), when the plan has one.
    const clips = new Map(gltf.animations.map((c) => [c.name, c]));
    let clip = clips.get('plan') || gltf.animations[0];
    let action = null;
    const slider = document.getElementById('time');
    const label = document.getElementById('clock');
    const button = document.getElementById('play');
    const chooser = document.getElementById('clip');
    chooser.parentElement.hidden = !clips.has('simulated');
    let playing = false;
    let last = performance.now();
    const setTime = (t) => {
      const clamped = Math.min(Math.max(t, 0), clip.duration);
      action.paused = false;
      action.enabled = true;
      mixer.setTime(clamped);
      slider.value = clamped;
      const phase = clip.name === 'simulated' ? ` ${phaseAt(plan, clamped)}` : '';
      label.textContent = `${clamped.toFixed(2)} / ${clip.duration.toFixed(2)} s${phase}`;
      renderer.render(scene, camera);
    };
    const selectClip = (name) => {
      if (!clips.has(name)) return false;
      mixer.stopAllAction();
      clip = clips.get(name);
      action = mixer.clipAction(clip);
      action.setLoop(THREE.LoopOnce);
      action.clampWhenFinished = true;
      action.play();
      slider.max = clip.duration;
      chooser.value = name;
      setTime(0);
      return true;
    };
    selectClip(clip.name);
    const setPlaying = (on) => {
      playing = on;
      button.textContent = on ? 'Pause' : 'Play';
      if (on && mixer.time >= clip.duration) setTime(0);
      last = performance.now();
    };
    button.onclick = () => setPlaying(!playing);
    chooser.onchange = () => {
      setPlaying(false);
      selectClip(chooser.value);
    };
    slider.oninput = () => {
      setPlaying(false);
      setTime(parseFloat(slider.value));
    };
    document.getElementById('stats').innerHTML = statsTable(plan, points);
    const frame = (now) => {
      if (playing) {
        const t = mixer.time + (now - last) / 1000;
        setTime(t);
        if (t >= clip.duration) setPlaying(false);
      }
      last = now;
      controls.update();
      renderer.render(scene, camera);
      requestAnimationFrame(frame);
    };
    setTime(0);
    requestAnimationFrame(frame);
    // For tests and scripts: the state of the page and a way to move in time.
    window.viewer = {
      get duration() { return clip.duration; },
      contacts: plan.grasp.contacts_world.length,
      markers: markers.children.length,
      explored: explored.children.length,
      points,
      get animatedNodes() { return new Set(clip.tracks.map((t) => t.name.split('.')[0])).size; },
      clips: [...clips.keys()],
      selectClip,
      phase: () => (clip.name === 'simulated' ? phaseAt(plan, mixer.time) : ''),
      setTime,
      /// The centre of a node's geometry (a link's or the object's name) in
      /// the view's world (glTF's y up), in metres.
      worldPosition: (name) => {
        const node = gltf.scene.getObjectByName(name);
        if (!node) return null;
        const p = new THREE.Box3().setFromObject(node).getCenter(new THREE.Vector3());
        return {x: p.x, y: p.y, z: p.z};
      },
      /// Where a node (a link's name) is on the canvas now, in CSS pixels.
      screenPosition: (name) => {
        const node = gltf.scene.getObjectByName(name);
        if (!node) return null;
        const p = node.getWorldPosition(new THREE.Vector3()).project(camera);
        const rect = renderer.domElement.getBoundingClientRect();
        return {x: (p.x + 1) / 2 * rect.width, y: (1 - p.y) / 2 * rect.height};
      },
    };
    window.viewerReady = true;
  }, (error) => {
    document.getElementById('stats').textContent = `cannot read the glTF: ${error.message || error}`;
    console.error('cannot read the glTF', error);
  });
}

function askForFiles() {
  const panel = document.getElementById('stats');
  panel.innerHTML = '<p>Open a plan: its .glb and its .json (hfts-client --out PLAN.json plan ... --gltf PLAN.glb).</p>' +
      '<input id="files" type="file" multiple accept=".glb,.json">';
  document.getElementById('files').onchange = async (event) => {
    let plan = null, glb = null;
    for (const file of event.target.files) {
      if (file.name.endsWith('.glb')) glb = await file.arrayBuffer();
      else plan = JSON.parse(await file.text());
    }
    if (plan && !glb && plan.gltf) glb = base64Bytes(plan.gltf);
    if (plan && glb) show(plan, glb);
    else panel.insertAdjacentHTML('beforeend', '<p>Both files are needed.</p>');
  };
}

if (window.HFTS_PLAN && window.HFTS_GLB_BASE64) {
  show(window.HFTS_PLAN, base64Bytes(window.HFTS_GLB_BASE64));
} else {
  askForFiles();
}
