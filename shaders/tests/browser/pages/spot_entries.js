// Every named kernel's spot entry from its import-free sources module, on
// WebGLRenderer's ground (a WebGL 2 context, no three.js), every argument a
// uniform as VolumetricLightsPass passes them: one row of W rays per kernel,
// RGBA32F read back (RGB the fog, A the seconds its program took to compile
// and draw). (shaders/tests/browser/pages/spot_entries.js)
const names = {{names}};
const canvas = document.createElement('canvas');
canvas.width = W;
canvas.height = H;
const gl = canvas.getContext('webgl2');
if (!gl) throw new Error('no WebGL 2');
if (!gl.getExtension('EXT_color_buffer_float')) throw new Error('no EXT_color_buffer_float');
const target = gl.createTexture();
gl.bindTexture(gl.TEXTURE_2D, target);
gl.texStorage2D(gl.TEXTURE_2D, 1, gl.RGBA32F, W, H);
const fb = gl.createFramebuffer();
gl.bindFramebuffer(gl.FRAMEBUFFER, fb);
gl.framebufferTexture2D(gl.FRAMEBUFFER, gl.COLOR_ATTACHMENT0, gl.TEXTURE_2D, target, 0);
const shader = (type, src) => {
  const s = gl.createShader(type);
  gl.shaderSource(s, src);
  gl.compileShader(s);
  if (!gl.getShaderParameter(s, gl.COMPILE_STATUS)) throw new Error(gl.getShaderInfoLog(s));
  return s;
};
const vertex = shader(gl.VERTEX_SHADER, '#version 300 es\nin vec2 p;\nvoid main() { gl_Position = vec4(p, 0.0, 1.0); }');
const buffer = gl.createBuffer();
gl.bindBuffer(gl.ARRAY_BUFFER, buffer);
gl.bufferData(gl.ARRAY_BUFFER, new Float32Array([-1, -1, 3, -1, -1, 3]), gl.STATIC_DRAW);
// The entry's arguments by the names its signature gives them.
const ARGS = { origin: 'uOrigin', dir: 'dir', surface: 'surface', light: 'uLight', axis: 'uAxis',
  cos_outer: 'uCone.x', cos_inner: 'uCone.y', intensity: 'uCone.z', sigma_t: 'uSigmaT', sigma_s: 'uSigmaS', g: 'uG' };
const out = new Float32Array(W * H * 4);
for (let y = 0; y < H; y++) {
  const S = await import('./airlight-three/sources/' + names[y] + '.js');
  const sig = new RegExp(S.prefix + 'spot\\(([^)]*)\\)').exec(S.glsl);
  if (!sig) throw new Error(names[y] + ': no spot entry');
  const call = sig[1].split(',').map((a) => {
    const name = a.trim().split(/\s+/).pop();
    if (!(name in ARGS)) throw new Error(names[y] + ': spot argument ' + name);
    return ARGS[name];
  }).join(', ');
  const fragment = '#version 300 es\nprecision highp float;\nprecision highp int;\n' + S.glsl + `
uniform vec3 uOrigin; uniform vec3 uLight; uniform vec3 uAxis; uniform vec3 uCone;
uniform vec3 uSigmaT; uniform vec3 uSigmaS; uniform float uG; uniform vec4 uFan;
out vec4 colour;
void main() {
    float x = floor(gl_FragCoord.x);
    vec3 dir = vec3(uFan.x + uFan.y * (x + 0.5), uFan.z, 1.0);
    float surface = mod(x, 2.0) == 0.0 ? uFan.w : -1.0;
    colour = vec4(${S.prefix}spot(${call}), 0.0);
}`;
  const t0 = performance.now();
  const program = gl.createProgram();
  gl.attachShader(program, vertex);
  gl.attachShader(program, shader(gl.FRAGMENT_SHADER, fragment));
  gl.linkProgram(program);
  if (!gl.getProgramParameter(program, gl.LINK_STATUS)) throw new Error(names[y] + ': ' + gl.getProgramInfoLog(program));
  gl.useProgram(program);
  const u = (n) => gl.getUniformLocation(program, n);
  gl.uniform3f(u('uOrigin'), {{origin}});
  gl.uniform3f(u('uLight'), {{light}});
  gl.uniform3f(u('uAxis'), {{axis}});
  gl.uniform3f(u('uCone'), {{cone}});
  gl.uniform3f(u('uSigmaT'), {{sigma_t}});
  gl.uniform3f(u('uSigmaS'), {{sigma_s}});
  gl.uniform1f(u('uG'), {{g}});
  gl.uniform4f(u('uFan'), {{fan}});
  const at = gl.getAttribLocation(program, 'p');
  gl.enableVertexAttribArray(at);
  gl.vertexAttribPointer(at, 2, gl.FLOAT, false, 0, 0);
  gl.viewport(0, y, W, 1);
  gl.drawArrays(gl.TRIANGLES, 0, 3);
  const row = new Float32Array(W * 4);
  gl.readPixels(0, y, W, 1, gl.RGBA, gl.FLOAT, row);
  const seconds = (performance.now() - t0) / 1000;
  for (let x = 0; x < W; x++) row[4 * x + 3] = seconds;
  out.set(row, y * W * 4);
}
const info = gl.getExtension('WEBGL_debug_renderer_info');
const adapter = info ? gl.getParameter(info.UNMASKED_RENDERER_WEBGL) : gl.getParameter(gl.RENDERER);
return { adapter, rgba: new Uint8Array(out.buffer), bottomUp: false, texel: 16 };
