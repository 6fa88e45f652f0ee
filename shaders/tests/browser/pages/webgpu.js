const renderer = new THREE.WebGPURenderer({ antialias: false, forceWebGL: {{force}} });
await renderer.init();
const backend = renderer.backend.isWebGPUBackend ? 'WebGPU' : 'WebGL 2';
if (backend !== '{{want}}') throw new Error('asked for {{want}}, got ' + backend);
const material = new THREE.MeshBasicNodeMaterial();
material.colorNode = {{colour}};
const mesh = new THREE.Mesh(new THREE.PlaneGeometry(2, 2), material);
mesh.frustumCulled = false;
const scene = new THREE.Scene();
scene.add(mesh);
const target = new THREE.RenderTarget(W, H, { type: THREE.UnsignedByteType, depthBuffer: false });
renderer.setRenderTarget(target);
renderer.render(scene, new THREE.OrthographicCamera(-1, 1, 1, -1, -1, 1));
const px = await renderer.readRenderTargetPixelsAsync(target, 0, 0, W, H);
let adapter = 'three.js r' + THREE.REVISION + ', WebGPURenderer (' + backend + ')';
if (renderer.backend.isWebGPUBackend) {
  const i = (await navigator.gpu.requestAdapter()).info;
  adapter += ', ' + [i.vendor, i.architecture, i.device, i.description].filter((x) => x).join(' ');
} else {
  const gl = renderer.getContext();
  const info = gl.getExtension('WEBGL_debug_renderer_info');
  adapter += ', ' + (info ? gl.getParameter(info.UNMASKED_RENDERER_WEBGL) : gl.getParameter(gl.RENDERER));
}
return { adapter, rgba: new Uint8Array(px.buffer, px.byteOffset, px.byteLength), bottomUp: !renderer.backend.isWebGPUBackend };