const scene = new THREE.Scene();
const stone = {{material}};
{{shadow_side}}for (const [x0, y0, z0, x1, y1, z1] of [{{boxes}}]) {
  const m = new THREE.Mesh(new THREE.BoxGeometry(x1 - x0, y1 - y0, z1 - z0), stone);
  m.position.set((x0 + x1) / 2, (y0 + y1) / 2, (z0 + z1) / 2);
  m.castShadow = true;
  scene.add(m);
}
const ball = new THREE.Mesh(new THREE.SphereGeometry({{ball_r_dbg}}, 96, 48), stone);
ball.position.set({{bx_dbg}}, {{by_dbg}}, {{bz_dbg}});
ball.castShadow = true;
scene.add(ball);
const floor = new THREE.Mesh(new THREE.PlaneGeometry({{floor_w_dbg}}, {{floor_d_dbg}}), {{floor}});
floor.rotation.x = -Math.PI / 2;
floor.position.set({{floor_x_dbg}}, {{floor_y_dbg}}, {{floor_z_dbg}});
floor.receiveShadow = true;
scene.add(floor);
{{light}}
light.position.set({{lx_dbg}}, {{ly_dbg}}, {{lz_dbg}});
light.castShadow = true;
light.shadow.mapSize.set({{map}}, {{map}});
light.shadow.camera.near = {{near_dbg}};
light.shadow.camera.far = {{far_dbg}};
scene.add(light);
const camera = new THREE.PerspectiveCamera(60, W / H, 0.1, 100);
camera.position.set({{cx_dbg}}, {{cy_dbg}}, {{cz_dbg}});
camera.lookAt({{cx_dbg}}, {{cy_dbg}}, {{cz_dbg}} + 1.0);
// This render draws three.js's shadow map (light.shadow.map, light.shadow.matrix).
const scratch = new THREE.{{target}}(W, H);
renderer.setRenderTarget(scratch);
renderer.render(scene, camera);
if (!light.shadow.map || !light.shadow.map.depthTexture) throw new Error('three.js drew no shadow map');
