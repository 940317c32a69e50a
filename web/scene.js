// juggle's three.js scene (docs/replay_and_export.md, docs/play.md), shared by the replay page
// (web/replay.js) and the live page (web/play.js): MuJoCo's z-up world drawn from a model's
// geoms (export/replay.cc: ReplayScene), one group per moving body, a checker ground, lights,
// and a camera that orbits (OrbitControls) and can follow the character's root.
//   const view = JuggleScene.create(element, {bodies, geoms, follow}, {targetZ, offset});
//   view.bodies[b].position / .quaternion   set per frame, then view.draw(follow)
window.JuggleScene = (function () {
  'use strict';

  function groundTexture() {
    const canvas = document.createElement('canvas');
    canvas.width = canvas.height = 64;
    const ctx = canvas.getContext('2d');
    for (let i = 0; i < 2; ++i) {
      for (let j = 0; j < 2; ++j) {
        ctx.fillStyle = (i + j) % 2 ? '#5f7f55' : '#6b8c60';
        ctx.fillRect(i * 32, j * 32, 32, 32);
      }
    }
    const texture = new THREE.CanvasTexture(canvas);
    texture.wrapS = texture.wrapT = THREE.RepeatWrapping;
    texture.repeat.set(20, 20);
    return texture;
  }

  const quat = (q) => new THREE.Quaternion(q[1], q[2], q[3], q[0]);  // MuJoCo w x y z

  function geomMesh(g, ground) {
    const color = new THREE.Color(g.rgba[0], g.rgba[1], g.rgba[2]);
    const material = new THREE.MeshLambertMaterial({
      color: color, transparent: g.rgba[3] < 1, opacity: g.rgba[3],
    });
    const s = g.size;
    const zAxis = (geometry) => geometry.rotateX(Math.PI / 2);  // three's cylinders lie along y
    let object;
    switch (g.type) {
      case 'plane':
        object = new THREE.Mesh(new THREE.PlaneBufferGeometry(40, 40),
                                new THREE.MeshLambertMaterial({ map: ground }));
        break;
      case 'sphere':
        object = new THREE.Mesh(new THREE.SphereBufferGeometry(s[0], 24, 16), material);
        break;
      case 'ellipsoid':
        object = new THREE.Mesh(new THREE.SphereBufferGeometry(1, 24, 16), material);
        object.scale.set(s[0], s[1], s[2]);
        break;
      case 'cylinder':
        object = new THREE.Mesh(zAxis(new THREE.CylinderBufferGeometry(s[0], s[0], 2 * s[1], 20)),
                                material);
        break;
      case 'capsule': {
        object = new THREE.Group();
        object.add(new THREE.Mesh(
            zAxis(new THREE.CylinderBufferGeometry(s[0], s[0], 2 * s[1], 20, 1, true)), material));
        for (const z of [-s[1], s[1]]) {
          const cap = new THREE.Mesh(new THREE.SphereBufferGeometry(s[0], 20, 12), material);
          cap.position.z = z;
          object.add(cap);
        }
        break;
      }
      case 'box':
        object = new THREE.Mesh(new THREE.BoxBufferGeometry(2 * s[0], 2 * s[1], 2 * s[2]), material);
        break;
      case 'mesh': {  // a convex hull: flat faces, so every triangle gets its own vertices
        const geometry = new THREE.BufferGeometry();
        geometry.setAttribute('position', new THREE.Float32BufferAttribute(g.vertices, 3));
        geometry.setIndex(g.faces);
        const flat = geometry.toNonIndexed();
        flat.computeVertexNormals();
        object = new THREE.Mesh(flat, material);
        break;
      }
      default:
        return null;
    }
    object.position.set(g.pos[0], g.pos[1], g.pos[2]);
    object.quaternion.copy(quat(g.quat));
    object.name = g.name;
    return object;
  }

  // `camera`: the height the camera looks at (m) and its offset from there (default: 0.8 m,
  // front-right 3.2 m away).
  function create(view, data, camera_options) {
    const targetZ = (camera_options && camera_options.targetZ) || 0.8;
    const offset = (camera_options && camera_options.offset) || [1.5, -2.7, 0.55];
    const renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
    renderer.setPixelRatio(window.devicePixelRatio || 1);
    view.appendChild(renderer.domElement);
    const scene = new THREE.Scene();
    scene.background = new THREE.Color(0xe6e6e6);
    const camera = new THREE.PerspectiveCamera(40, 1, 0.05, 200);
    camera.up.set(0, 0, 1);
    scene.add(new THREE.HemisphereLight(0xffffff, 0x667766, 0.75));
    const sun = new THREE.DirectionalLight(0xffffff, 0.55);
    sun.position.set(2, -3, 6);
    scene.add(sun);
    const ground = groundTexture();

    const bodies = data.bodies.map((name) => {
      const group = new THREE.Group();
      group.name = name;
      scene.add(group);
      return group;
    });
    let hasGround = false;
    for (const g of data.geoms) {
      const mesh = geomMesh(g, ground);
      if (!mesh) continue;
      hasGround = hasGround || g.type === 'plane';
      (g.body >= 0 ? bodies[g.body] : scene).add(mesh);
    }
    if (!hasGround) {  // families without a floor still get one to stand on
      scene.add(geomMesh({ type: 'plane', size: [0, 0, 0], pos: [0, 0, 0], quat: [1, 0, 0, 0],
                           rgba: [1, 1, 1, 1], name: 'ground' }, ground));
    }

    // Camera: front-right of the character, orbiting its root.
    const controls = new THREE.OrbitControls(camera, renderer.domElement);
    controls.enableDamping = false;
    function rootTarget(out) {
      const root = bodies[data.follow] || bodies[0];
      return out.set(root.position.x, root.position.y, targetZ);
    }
    function placeCamera() {
      rootTarget(controls.target);
      camera.position.copy(controls.target).add(new THREE.Vector3(offset[0], offset[1], offset[2]));
      controls.update();
    }
    function resize() {
      const w = view.clientWidth, h = view.clientHeight;
      renderer.setSize(w, h);
      camera.aspect = w / Math.max(1, h);
      camera.updateProjectionMatrix();
    }
    window.addEventListener('resize', resize);
    resize();

    const followTarget = new THREE.Vector3(), delta = new THREE.Vector3();
    // Renders; with `follow` the camera moves with the character's root first.
    function draw(follow) {
      if (follow) {
        rootTarget(followTarget);
        delta.subVectors(followTarget, controls.target);
        camera.position.add(delta);
        controls.target.copy(followTarget);
      }
      controls.update();
      renderer.render(scene, camera);
    }
    return { renderer, scene, camera, controls, bodies, draw, placeCamera, resize };
  }

  return { create };
})();
