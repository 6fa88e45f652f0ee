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
renderer.render(pass, new THREE.OrthographicCamera(-1, 1, 1, -1, -1, 1));
const px = await renderer.readRenderTargetPixelsAsync(target, 0, 0, W, H);
const timing = {{timing}};
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