const renderer = new THREE.WebGPURenderer({ antialias: false, forceWebGL: {{webgl}} });
await renderer.init();
const backend = renderer.backend.isWebGPUBackend ? 'WebGPU' : 'WebGL 2';
if (backend !== '{{want}}') throw new Error('asked for {{want}}, got ' + backend);
renderer.shadowMap.enabled = true;
renderer.shadowMap.type = THREE.PCFShadowMap;
{{scene}}
const sceneEnd = {{code_fn}}({{scene_end}}, [{{code}}({{box_entry}})]);
{{fog_setup}}
const material = new THREE.MeshBasicNodeMaterial();
material.fragmentNode = Fn(() => {
  const pos = screenCoordinate.xy;
  const u = pos.x.mul(2.0 / W).sub(1.0);
  const v = float(1.0).sub(pos.y.mul(2.0 / H));
  const t = float({{t_dbg}});
  const d = {{f}}.add({{r}}.mul(u.mul(t).mul({{aspect_dbg}}))).add({{up}}.mul(v.mul(t)));
  const dir = d.div(sqrt(dot(d, d)));
  const end = sceneEnd({ dir });
  const fog = {{fog}};
  return vec4(fog, end);
})();
const quad = new THREE.Mesh(new THREE.PlaneGeometry(2, 2), material);
quad.frustumCulled = false;
const pass = new THREE.Scene();
pass.add(quad);
const target = new THREE.RenderTarget(W, H, { type: THREE.FloatType, depthBuffer: false });
renderer.setRenderTarget(target);
const ortho = new THREE.OrthographicCamera(-1, 1, 1, -1, -1, 1);
renderer.render(pass, ortho);
let px = await renderer.readRenderTargetPixelsAsync(target, 0, 0, W, H);
// Wall-clock of a frame's fog once compiled, with the read-back that waits for
// it (median of 3): the pass alone, and the pass after what a frame redoes first
// (the exact mode's pyramid).
const wall = async (first) => {
  const times = [];
  for (let i = 0; i < 3; i++) {
    const t0 = performance.now();
    if (first) first();
    renderer.setRenderTarget(target);
    renderer.render(pass, ortho);
    px = await renderer.readRenderTargetPixelsAsync(target, 0, 0, W, H);
    times.push(performance.now() - t0);
  }
  return times.sort((a, b) => a - b)[1].toFixed(1);
};
const passMs = await wall(null);
const frameMs = await wall({{per_frame}});
const timing = '; fog pass ' + passMs + ' ms, frame ' + frameMs + ' ms wall (median of 3, read-back included)';
let adapter = 'three.js r' + THREE.REVISION + ', WebGPURenderer (' + backend + '), shadow map ' + light.shadow.mapSize.x + '², ';
if (renderer.backend.isWebGPUBackend) {
  const i = (await navigator.gpu.requestAdapter()).info;
  adapter += [i.vendor, i.architecture, i.device, i.description].filter((x) => x).join(' ');
} else {
  const gl = renderer.getContext();
  const info = gl.getExtension('WEBGL_debug_renderer_info');
  adapter += info ? gl.getParameter(info.UNMASKED_RENDERER_WEBGL) : gl.getParameter(gl.RENDERER);
}
adapter += timing;
return { adapter, rgba: new Uint8Array(px.buffer, px.byteOffset, px.byteLength), bottomUp: {{webgl}}, texel: 16 };