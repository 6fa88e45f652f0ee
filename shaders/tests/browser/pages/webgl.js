const canvas = document.createElement('canvas');
canvas.width = W; canvas.height = H;
document.body.appendChild(canvas);
const renderer = new THREE.WebGLRenderer({ canvas, antialias: false, alpha: false, preserveDrawingBuffer: true });
renderer.setPixelRatio(1);
renderer.setSize(W, H, false);
let shaderError = null;
renderer.debug.checkShaderErrors = true;
renderer.debug.onShaderError = (gl, program, vs, fs) => {
  shaderError = 'shader: ' + gl.getShaderInfoLog(fs) + gl.getShaderInfoLog(vs) + gl.getProgramInfoLog(program);
};
const material = new THREE.RawShaderMaterial({
  glslVersion: THREE.GLSL3,
  vertexShader: 'in vec3 position;\nvoid main() { gl_Position = vec4(position.xy, 0.0, 1.0); }\n',
  fragmentShader: glsl + {{main}},
});
const mesh = new THREE.Mesh(new THREE.PlaneGeometry(2, 2), material);
mesh.frustumCulled = false;
const scene = new THREE.Scene();
scene.add(mesh);
renderer.render(scene, new THREE.OrthographicCamera(-1, 1, 1, -1, -1, 1));
if (shaderError) throw new Error(shaderError);
const gl = renderer.getContext();
const px = new Uint8Array(W * H * 4);
gl.readPixels(0, 0, W, H, gl.RGBA, gl.UNSIGNED_BYTE, px);
const info = gl.getExtension('WEBGL_debug_renderer_info');
const adapter = 'three.js r' + THREE.REVISION + ', WebGLRenderer, ' + gl.getParameter(gl.VERSION) + ', ' +
  (info ? gl.getParameter(info.UNMASKED_RENDERER_WEBGL) : gl.getParameter(gl.RENDERER));
// readPixels starts at the bottom row.
return { adapter, rgba: px, bottomUp: true };