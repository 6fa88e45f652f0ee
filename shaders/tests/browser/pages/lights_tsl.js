const renderer = new THREE.WebGPURenderer({ antialias: false, forceWebGL: {{webgl}} });
await renderer.init();
const backend = renderer.backend.isWebGPUBackend ? 'WebGPU' : 'WebGL 2';
if (backend !== '{{want}}') throw new Error('asked for {{want}}, got ' + backend);
renderer.shadowMap.enabled = true;
// The drawing buffer is the frame's size, as a canvas would be: the scene pass
// draws at it, and PostProcessing's output target below is read at it (three's
// screenUV divides by the drawing buffer's size where no render target is set).
renderer.setPixelRatio(1);
renderer.setSize(W, H, false);
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
// The scene pass's colour as the composite reads it, then the composite:
// composite = colour · T + fog, T the medium's transmittance to the surface.
const colourMaterial = new THREE.MeshBasicNodeMaterial();
colourMaterial.fragmentNode = scenePass.getTextureNode('output').sample(screenUV);
quad.material = colourMaterial;
renderer.setRenderTarget(target);
renderer.render(fogScene, ortho);
const pcol = await renderer.readRenderTargetPixelsAsync(target, 0, 0, W, H);
const compositeMaterial = new THREE.MeshBasicNodeMaterial();
compositeMaterial.fragmentNode = volumetric.composite(scenePass, camera);
quad.material = compositeMaterial;
renderer.setRenderTarget(target);
renderer.render(fogScene, ortho);
const pc = await renderer.readRenderTargetPixelsAsync(target, 0, 0, W, H);
// The light changed between frames (twice the intensity), nothing rebuilt or
// refreshed by hand: the next frame's fog doubles.
light.intensity *= 2.0;
quad.material = material;
renderer.setRenderTarget(target);
renderer.render(fogScene, ortho);
const p2 = await renderer.readRenderTargetPixelsAsync(target, 0, 0, W, H);
// The README's form: the composite as PostProcessing's output, drawn into the
// renderer's output target (its render target null), at the first intensity;
// the colour transform off, so that it stays linear like the frames above.
light.intensity /= 2.0;
const postProcessing = new THREE.PostProcessing(renderer);
postProcessing.outputColorTransform = false;
postProcessing.outputNode = volumetric.composite(scenePass, camera);
renderer.setRenderTarget(null);
renderer.setOutputRenderTarget(target);
postProcessing.render();
renderer.setOutputRenderTarget(null);
const ppc = await renderer.readRenderTargetPixelsAsync(target, 0, 0, W, H);
// The light's castShadow turned off: a light with shafts glows unshadowed in its slot.
light.castShadow = false;
quad.material = material;
renderer.setRenderTarget(target);
renderer.render(fogScene, ortho);
const p3 = await renderer.readRenderTargetPixelsAsync(target, 0, 0, W, H);
// A flashlight: the light moved to the camera (castShadow still off): the fog
// of each ray from where it leaves the light's core.
light.position.copy(camera.position);
renderer.setRenderTarget(target);
renderer.render(fogScene, ortho);
const p4 = await renderer.readRenderTargetPixelsAsync(target, 0, 0, W, H);
// Per pixel: the fog, the scene's colour, the composite, the next frame's fog,
// the composite through PostProcessing, the fog with castShadow off, the
// flashlight's fog (16 bytes each).
const frames = [px, pcol, pc, p2, ppc, p3, p4].map((f) => new Uint8Array(f.buffer, f.byteOffset, f.byteLength));
const all = new Uint8Array(W * H * 112);
for (let i = 0; i < W * H; i++) frames.forEach((f, k) => all.set(f.subarray(i * 16, i * 16 + 16), i * 112 + k * 16));
let adapter = 'three.js r' + THREE.REVISION + ', WebGPURenderer (' + backend + '), kernel ' + volumetric.name + ', ';
if (renderer.backend.isWebGPUBackend) {
  const i = (await navigator.gpu.requestAdapter()).info;
  adapter += [i.vendor, i.architecture, i.device, i.description].filter((x) => x).join(' ');
} else {
  const gl = renderer.getContext();
  const info = gl.getExtension('WEBGL_debug_renderer_info');
  adapter += info ? gl.getParameter(info.UNMASKED_RENDERER_WEBGL) : gl.getParameter(gl.RENDERER);
}
return { adapter, rgba: all, bottomUp: {{webgl}}, texel: 112 };
