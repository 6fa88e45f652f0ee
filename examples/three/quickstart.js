// The README's three.js quick start, run by this example page on WebGPURenderer
// (main.js; its browser test holds the fog to the reference): every
// THREE.PointLight and THREE.SpotLight in `lights` glows in the fog over `scene`.
import * as THREE from 'three/webgpu';
import { pass } from 'three/tsl';
import { VolumetricLights } from 'airlight-three/lights.js';

export async function foggy(renderer, scene, camera, lights, options = {}) {
  const fog = await VolumetricLights.create(renderer, { sigmaT: 0.07, sigmaS: 0.06, g: 0.6, maxError: 1e-2, ...options });
  for (const light of lights) fog.add(light);
  const scenePass = pass(scene, camera);
  const post = new THREE.PostProcessing(renderer);
  post.outputNode = fog.composite(scenePass, camera);
  return { fog, post, scenePass }; // each frame: post.render()
}
