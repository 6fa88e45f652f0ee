const renderer = new THREE.WebGLRenderer({ antialias: false });
renderer.setPixelRatio(1);
renderer.setSize(W, H, false);
renderer.shadowMap.enabled = true;
let shaderError = null;
renderer.debug.checkShaderErrors = true;
renderer.debug.onShaderError = (gl, program, vs, fs) => {
  shaderError = 'shader: ' + gl.getShaderInfoLog(fs) + gl.getShaderInfoLog(vs) + gl.getProgramInfoLog(program);
};
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
const volumetric = new VolumetricLightsPass(scene, camera, S, { sigmaT: [{{sigma_t}}], sigmaS: [{{sigma_s}}], g: {{g}}, name: '{{name}}', {{limits}} });
volumetric.add(light);
const target = new THREE.WebGLRenderTarget(W, H, { type: THREE.FloatType, depthBuffer: false });
const read = () => {
  renderer.setRenderTarget(target);
  volumetric.render(renderer);
  if (shaderError) throw new Error(shaderError);
  const px = new Float32Array(W * H * 4);
  renderer.readRenderTargetPixels(target, 0, 0, W, H, px);
  return px;
};
// The fog alone, then the composite, then the scene's colour as the pass drew it
// (its own target, half floats), then the next frame with the light's intensity
// doubled in three.js alone, then one at the first intensity with the light's
// castShadow turned off (a light with shafts glows unshadowed in its slot).
volumetric.fogOnly = true;
const px = read();
volumetric.fogOnly = false;
const pc = read();
const colour = new Float32Array(W * H * 4);
const half = new Uint16Array(W * H * 4);
renderer.readRenderTargetPixels(volumetric.target, 0, 0, W, H, half);
for (let i = 0; i < half.length; i++) colour[i] = THREE.DataUtils.fromHalfFloat(half[i]);
light.intensity *= 2.0;
volumetric.fogOnly = true;
const p2 = read();
light.intensity /= 2.0;
light.castShadow = false;
const p3 = read();
// A flashlight: the light moved to the camera (castShadow still off): the fog
// of each ray from where it leaves the light's core.
light.position.copy(camera.position);
const p4 = read();
const frames = [px, colour, pc, p2, p3, p4].map((f) => new Uint8Array(f.buffer, f.byteOffset, f.byteLength));
const all = new Uint8Array(W * H * 96);
for (let i = 0; i < W * H; i++) frames.forEach((f, k) => all.set(f.subarray(i * 16, i * 16 + 16), i * 96 + k * 16));
const gl = renderer.getContext();
const info = gl.getExtension('WEBGL_debug_renderer_info');
const adapter = 'three.js r' + THREE.REVISION + ', WebGLRenderer, VolumetricLightsPass with ' + volumetric.name + ', ' +
  (info ? gl.getParameter(info.UNMASKED_RENDERER_WEBGL) : gl.getParameter(gl.RENDERER));
return { adapter, rgba: all, bottomUp: true, texel: 96 };
