const renderer = new THREE.WebGLRenderer({ antialias: false });
renderer.setPixelRatio(1);
renderer.setSize(W, H, false);
renderer.shadowMap.enabled = true;
renderer.shadowMap.type = THREE.PCFShadowMap;
let shaderError = null;
renderer.debug.checkShaderErrors = true;
renderer.debug.onShaderError = (gl, program, vs, fs) => {
  shaderError = 'shader: ' + gl.getShaderInfoLog(fs) + gl.getShaderInfoLog(vs) + gl.getProgramInfoLog(program);
};
// The room's occluders, casting shadows, its spot light, and three.js's shadow map.
{{scene}}
const material = new THREE.RawShaderMaterial({
  glslVersion: THREE.GLSL3,
  vertexShader: 'in vec3 position;\nvoid main() { gl_Position = vec4(position.xy, 0.0, 1.0); }\n',
  fragmentShader: glsl + {{main}},
  uniforms: { shadowMap: { value: light.shadow.map.depthTexture }, shadowMatrix: { value: light.shadow.matrix } },
});
const quad = new THREE.Mesh(new THREE.PlaneGeometry(2, 2), material);
quad.frustumCulled = false;
const pass = new THREE.Scene();
pass.add(quad);
const target = new THREE.WebGLRenderTarget(W, H, { type: THREE.FloatType, depthBuffer: false });
renderer.setRenderTarget(target);
renderer.render(pass, new THREE.OrthographicCamera(-1, 1, 1, -1, -1, 1));
if (shaderError) throw new Error(shaderError);
const px = new Float32Array(W * H * 4);
renderer.readRenderTargetPixels(target, 0, 0, W, H, px);
const gl = renderer.getContext();
const info = gl.getExtension('WEBGL_debug_renderer_info');
const adapter = 'three.js r' + THREE.REVISION + ', WebGLRenderer, shadow map ' + light.shadow.map.width + '², ' +
  (info ? gl.getParameter(info.UNMASKED_RENDERER_WEBGL) : gl.getParameter(gl.RENDERER));
return { adapter, rgba: new Uint8Array(px.buffer), bottomUp: true, texel: 16 };