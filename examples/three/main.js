// A street at night in fog: two lamp posts (THREE.PointLight) and a spot light on
// a wall (THREE.SpotLight), shadows on, their glow in the fog by airlight-three
// over three.js, an orbit camera, a quality switch (the error budget the kernel is
// picked for) and the frame time. Two renderers, one scene:
//   (default)          WebGPURenderer, VolumetricLights as its PostProcessing output
//   ?renderer=webgl    WebGLRenderer, VolumetricLightsPass in an EffectComposer
// `?w=…&h=…` fixes the canvas size (the repository's browser test uses it).
const query = new URLSearchParams(location.search);
const webgl = query.get('renderer') === 'webgl';
const THREE = await import(webgl ? 'three' : 'three/webgpu');
const { OrbitControls } = await import('three/addons/controls/OrbitControls.js');
const fixed = query.has('w') ? [Number(query.get('w')), Number(query.get('h'))] : null;
const renderer = webgl ? new THREE.WebGLRenderer({ antialias: false }) : new THREE.WebGPURenderer({ antialias: false });
if (!webgl) await renderer.init();
renderer.setPixelRatio(fixed ? 1 : window.devicePixelRatio);
renderer.setSize(...(fixed ?? [window.innerWidth, window.innerHeight]), !fixed);
renderer.shadowMap.enabled = true;
document.body.appendChild(renderer.domElement);
// `?w=…&h=…` on WebGPU also draws into an offscreen target instead of the canvas:
// headless Chromium's WebGPU on SwiftShader loses its device presenting to a canvas.
const offscreen = fixed && !webgl ? new THREE.RenderTarget(fixed[0], fixed[1]) : null;
if (offscreen) renderer.setOutputRenderTarget(offscreen);
document.getElementById('renderer').textContent = webgl ? 'WebGLRenderer' : 'WebGPURenderer';
const shaftsBox = document.getElementById('shafts');
shaftsBox.checked = query.get('shafts') === '1';
shaftsBox.addEventListener('change', () => {
  query.set('shafts', shaftsBox.checked ? '1' : '0');
  location.search = '?' + query;
});

// The street, metres: asphalt between two rows of houses, a railing, a bench, a ball.
export const MEDIUM = { sigmaT: [0.07, 0.075, 0.08], sigmaS: [0.055, 0.06, 0.065], g: 0.6 };
const scene = new THREE.Scene();
const mat = (c) => new THREE.MeshStandardMaterial({ color: c, roughness: 0.9 });
const box = (w, h, d, x, y, z, m) => {
  const b = new THREE.Mesh(new THREE.BoxGeometry(w, h, d), m);
  b.position.set(x, y, z);
  b.castShadow = true;
  b.receiveShadow = true;
  scene.add(b);
  return b;
};
const ground = new THREE.Mesh(new THREE.PlaneGeometry(40, 80), mat(0x2a2a2c));
ground.rotation.x = -Math.PI / 2;
ground.receiveShadow = true;
scene.add(ground);
box(4, 9, 60, -9, 4.5, 0, mat(0x4a4038));
box(4, 12, 60, 9, 6, 0, mat(0x3c4048));
box(2, 0.15, 60, -6, 0.075, 0, mat(0x555555));
box(2, 0.15, 60, 6, 0.075, 0, mat(0x555555));
for (let i = 0; i < 30; i++) box(0.04, 1.1, 0.04, -5.2, 0.55, -6 + 0.25 * i, mat(0x111111));
box(0.06, 0.06, 7.5, -5.2, 1.1, -2.4, mat(0x111111));
box(1.6, 0.08, 0.5, 4.8, 0.5, 3, mat(0x6b4a2e));
const ball = new THREE.Mesh(new THREE.SphereGeometry(0.45, 48, 24), mat(0x777777));
ball.position.set(2.5, 0.45, -2);
ball.castShadow = true;
scene.add(ball);

// The lights as three.js holds them: candela × colour, inverse square (distance 0, decay 2).
const lamps = [[-4.6, 5.2, -7], [4.6, 5.2, 7]].map(([x, y, z]) => {
  box(0.12, y, 0.12, x, y / 2, z, mat(0x222222));
  const l = new THREE.PointLight(0xffc890, 60, 0, 2);
  l.position.set(x, y - 0.3, z);
  l.castShadow = true;
  l.shadow.mapSize.set(1024, 1024);
  scene.add(l);
  return l;
});
const spot = new THREE.SpotLight(0x9cc4ff, 400, 0, 0.45, 0.35, 2);
spot.position.set(6.8, 7.5, -1);
spot.target.position.set(1.5, 0, -1.5);
spot.castShadow = true;
spot.shadow.mapSize.set(1024, 1024);
scene.add(spot, spot.target);
scene.add(new THREE.AmbientLight(0x404860, 0.15));

const camera = new THREE.PerspectiveCamera(55, 1, 0.1, 120);
camera.position.set(-1.5, 1.7, 17);
const controls = new OrbitControls(camera, renderer.domElement);
controls.target.set(0, 2.2, 0);
controls.update();
const resize = () => {
  const [w, h] = fixed ?? [window.innerWidth, window.innerHeight];
  camera.aspect = w / h;
  camera.updateProjectionMatrix();
  if (!fixed) renderer.setSize(w, h);
};
window.addEventListener('resize', resize);
resize();

// The fog over the scene: per quality (the cheapest kernel on airlight-three's
// menu whose declared bound meets it) a VolumetricLights (WebGPU: the composite is
// PostProcessing's output) or a VolumetricLightsPass (WebGL: the composer's pass,
// which draws the scene itself), rebuilt on a switch.
// Shafts (both renderers): each light's glow walked exactly over its own shadow
// map; off by default, a checkbox (SwiftShader, a CPU adapter, walks the three
// maps slowly; this page's reference holds none of the street's occluders).
const shafts = query.get('shafts') === '1';
const limits = shafts ? { maxPointLights: 0, maxSpotLights: 0, shafts: true, maxShadowedLights: 3 } : { maxPointLights: 2, maxSpotLights: 1, shafts: false };
let fog = null;
let draw;
let fogOf;
let scenePass = null;
if (webgl) {
  const { EffectComposer } = await import('three/addons/postprocessing/EffectComposer.js');
  const { VolumetricLightsPass } = await import('airlight-three/webgl.js');
  const composer = new EffectComposer(renderer);
  draw = () => composer.render();
  fogOf = (maxError) => VolumetricLightsPass.create(scene, camera, { ...MEDIUM, maxError, ...limits }).then((next) => {
    if (fog) {
      composer.removePass(fog);
      fog.dispose();
    }
    for (const l of [...lamps, spot]) next.add(l);
    composer.addPass(next);
    return next;
  });
} else {
  // The README's quick start (quickstart.js), with this page's medium and limits.
  const { foggy } = await import('./quickstart.js');
  let post = null;
  draw = () => post.render();
  fogOf = (maxError) => foggy(renderer, scene, camera, [...lamps, spot], { ...MEDIUM, maxError, ...limits }).then((next) => {
    post?.dispose();
    post = next.post;
    scenePass = next.scenePass;
    return next.fog;
  });
}
async function setQuality(maxError) {
  fog = await fogOf(maxError);
  document.getElementById('kernel').textContent = `kernel ${fog.name}`;
}
const select = document.getElementById('quality');
select.addEventListener('change', () => setQuality(Number(select.value)));
await setQuality(Number(select.value));

// The frame time: the median of the last 30 frames, as the page shows it.
const times = [];
let afterFrame = null;
let last = performance.now();
function frameMs() {
  const s = [...times].sort((a, b) => a - b);
  return s.length ? s[s.length >> 1] : NaN;
}
function frame() {
  const now = performance.now();
  times.push(now - last);
  if (times.length > 30) times.shift();
  last = now;
  controls.update();
  draw();
  if (afterFrame) afterFrame();
  document.getElementById('time').textContent = `${frameMs().toFixed(1)} ms/frame`;
}
renderer.setAnimationLoop(frame);

// For checks (the repository's browser test): the fog alone (RGB, distance to the
// first surface) as floats and what the page shows as 8-bit RGBA, rows from the
// top, and what the reference needs. Both are read right after a frame of the
// animation loop.
const flip = (a, w, h) => {
  const row = a.length / h;
  const out = new a.constructor(a.length);
  for (let y = 0; y < h; y++) out.set(a.subarray((h - 1 - y) * row, (h - y) * row), y * row);
  return out;
};
async function readFog() {
  const [w, h] = fixed ?? [renderer.domElement.width, renderer.domElement.height];
  const target = webgl
    ? new THREE.WebGLRenderTarget(w, h, { type: THREE.FloatType, depthBuffer: false })
    : new THREE.RenderTarget(w, h, { type: THREE.FloatType, depthBuffer: false });
  let fogPx;
  let shown = null;
  if (webgl) {
    // The canvas as the frame left it (read before the browser presents it), then
    // the pass again with the fog alone into a float target; WebGL's rows run
    // from the bottom.
    await new Promise((done) => {
      afterFrame = () => {
        afterFrame = null;
        const gl = renderer.getContext();
        const bytes = new Uint8Array(w * h * 4);
        gl.readPixels(0, 0, w, h, gl.RGBA, gl.UNSIGNED_BYTE, bytes);
        shown = flip(bytes, w, h);
        fog.fogOnly = true;
        renderer.setRenderTarget(target);
        fog.render(renderer);
        renderer.setRenderTarget(null);
        fog.fogOnly = false;
        const px = new Float32Array(w * h * 4);
        renderer.readRenderTargetPixels(target, 0, 0, w, h, px);
        fogPx = flip(px, w, h);
        done();
      };
    });
  } else {
    const material = new THREE.MeshBasicNodeMaterial();
    material.fragmentNode = fog.fog(scenePass.getTextureNode('depth'), camera);
    const quad = new THREE.Mesh(new THREE.PlaneGeometry(2, 2), material);
    quad.frustumCulled = false;
    const fogScene = new THREE.Scene();
    fogScene.add(quad);
    // Drawn by the animation loop's next frame, after the scene pass, then read.
    await new Promise((done) => {
      afterFrame = () => {
        afterFrame = null;
        renderer.setRenderTarget(target);
        renderer.render(fogScene, new THREE.OrthographicCamera(-1, 1, 1, -1, -1, 1));
        renderer.setRenderTarget(null);
        done();
      };
    });
    const px = await renderer.readRenderTargetPixelsAsync(target, 0, 0, w, h);
    fogPx = new Float32Array(px.buffer, px.byteOffset, px.byteLength / 4);
    // What the page shows (the offscreen output: 8-bit sRGB, rows from the top).
    shown = offscreen ? await renderer.readRenderTargetPixelsAsync(offscreen, 0, 0, w, h) : null;
  }
  target.dispose();
  const lights = [...lamps, spot].map((l) => ({
    spot: l.isSpotLight === true,
    position: l.getWorldPosition(new THREE.Vector3()).toArray(),
    intensity: [l.color.r * l.intensity, l.color.g * l.intensity, l.color.b * l.intensity],
    target: l.isSpotLight ? l.target.getWorldPosition(new THREE.Vector3()).toArray() : null,
    cos: l.isSpotLight ? [Math.cos(l.angle), Math.cos(l.angle * (1 - l.penumbra))] : null,
  }));
  return {
    fog: fogPx,
    shown,
    width: w,
    height: h,
    kernel: fog.name,
    renderer: webgl ? 'WebGLRenderer' : 'WebGPURenderer',
    camera: { world: camera.matrixWorld.toArray(), projectionInverse: camera.projectionMatrixInverse.toArray() },
    medium: MEDIUM,
    lights,
  };
}
window.airlightExample = { setQuality, frameMs, readFog, renderer };
