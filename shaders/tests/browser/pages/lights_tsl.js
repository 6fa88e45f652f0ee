const renderer = new THREE.WebGPURenderer({ antialias: false, forceWebGL: {{webgl}} });
await renderer.init();
const backend = renderer.backend.isWebGPUBackend ? 'WebGPU' : 'WebGL 2';
if (backend !== '{{want}}') throw new Error('asked for {{want}}, got ' + backend);
renderer.shadowMap.enabled = true;
{{scene}}
// The light as the stage has it, in three's units (candela × colour).
light.intensity = {{intensity}};
light.color.setRGB({{colour}}, THREE.LinearSRGBColorSpace);
{{spot_penumbra}}
// The stage's camera: its field of view and aim.
camera.fov = {{fov_deg}};
camera.aspect = W / H;
camera.near = 0.05;
camera.far = 100.0;
camera.position.set({{camera}});
camera.lookAt({{target_pos}});
camera.updateProjectionMatrix();
camera.updateMatrixWorld();
const volumetric = new VolumetricLights(renderer, K, { sigmaT: [{{sigma_t}}], sigmaS: [{{sigma_s}}], g: {{g}}, name: '{{name}}', {{limits}} });
volumetric.add(light);
const scenePass = pass(scene, camera);
const material = new THREE.MeshBasicNodeMaterial();
material.fragmentNode = volumetric.fog(scenePass.getTextureNode('depth'), camera);
const quad = new THREE.Mesh(new THREE.PlaneGeometry(2, 2), material);
quad.frustumCulled = false;
const fogScene = new THREE.Scene();
fogScene.add(quad);
const target = new THREE.RenderTarget(W, H, { type: THREE.FloatType, depthBuffer: false });
const ortho = new THREE.OrthographicCamera(-1, 1, 1, -1, -1, 1);
renderer.setRenderTarget(target);
renderer.render(fogScene, ortho);
const px = await renderer.readRenderTargetPixelsAsync(target, 0, 0, W, H);
let adapter = 'three.js r' + THREE.REVISION + ', WebGPURenderer (' + backend + '), kernel ' + volumetric.name + ', ';
if (renderer.backend.isWebGPUBackend) {
  const i = (await navigator.gpu.requestAdapter()).info;
  adapter += [i.vendor, i.architecture, i.device, i.description].filter((x) => x).join(' ');
} else {
  const gl = renderer.getContext();
  const info = gl.getExtension('WEBGL_debug_renderer_info');
  adapter += info ? gl.getParameter(info.UNMASKED_RENDERER_WEBGL) : gl.getParameter(gl.RENDERER);
}
return { adapter, rgba: new Uint8Array(px.buffer, px.byteOffset, px.byteLength), bottomUp: {{webgl}}, texel: 16 };
