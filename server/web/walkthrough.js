// The walkthrough: a done job's exported model (GET /v1/jobs/{id}/model.glb, docs/export.md)
// drawn with three.js, to orbit and walk through. Surfaces show their vertices' radiosity
// interpolated, the paper's own shading; bumpy ones evaluate their bump function per
// fragment and turn N into N' through the perturbed radiosity map the file carries, so a
// slider changes the image at display rate with no request to the server. Mirrors and
// glossy reflections are the server's render only ("Render here").
import * as THREE from "three";

// ---- The file ----------------------------------------------------------------------------

// A .glb's JSON and its accessors' data as typed arrays (glTF 2.0 section 4.4).
function parseGlb(bytes) {
  const view = new DataView(bytes);
  if (view.getUint32(0, true) !== 0x46546c67) throw new Error("not a glTF binary");
  const jsonLength = view.getUint32(12, true);
  const gltf = JSON.parse(new TextDecoder().decode(new Uint8Array(bytes, 20, jsonLength)));
  const bin = 20 + jsonLength + 8;
  const sizes = { SCALAR: 1, VEC2: 2, VEC3: 3, VEC4: 4 };
  const accessor = (i) => {
    const a = gltf.accessors[i];
    const v = gltf.bufferViews[a.bufferView];
    const Type = a.componentType === 5125 ? Uint32Array : Float32Array;
    return new Type(bytes, bin + (v.byteOffset || 0) + (a.byteOffset || 0), a.count * sizes[a.type]);
  };
  return { gltf, accessor, bytes, bin };
}

// ---- Shading -----------------------------------------------------------------------------

const kMapTexels = 15;     // per vertex: its radiosity, then 14 texels of map coefficients
const kRowVertices = 256;  // vertices per row of the data texture
const kBumpTypes = ["noise", "wrinkles", "bricks", "tiles", "dimples", "cylinder", "image", "normal_map"];

const vertexShader = /* glsl */ `
precision highp float;
uniform mat4 modelViewMatrix, projectionMatrix;
in vec3 position, normal, radiosity, dpdu, dpdv, corners, bary;
in vec2 uv;
out vec3 vNormal, vRadiosity, vDpdu, vDpdv, vBary;
out vec2 vUv;
flat out ivec3 vCorners;
void main() {
  vNormal = normal; vRadiosity = radiosity; vDpdu = dpdu; vDpdv = dpdv; vBary = bary; vUv = uv;
  vCorners = ivec3(corners + 0.5);
  gl_Position = projectionMatrix * modelViewMatrix * vec4(position, 1.0);
}`;

// solver/scene/bump.cpp, solver/radiosity/map_basis.cpp and solver/render/view_pass.cpp in
// GLSL: the same patterns, Blinn's perturbation, the harmonics and B + B'(N') - B'(N).
const fragmentShader = /* glsl */ `
precision highp float;
precision highp int;
precision highp sampler2D;
uniform sampler2D mapTexture;
uniform bool bumpy;         // the mesh's object has a bump function and the file its map
uniform vec4 bumpA;         // type, amplitude, octaves, seed
uniform vec4 bumpB;         // scale u, scale v, offset u, offset v
uniform vec4 bumpC;         // mortar, radius, direction (deg), strength
uniform sampler2D bumpImage;  // image heights, normal maps
uniform vec3 emission;
uniform int colorKind;      // 0: none, 1: checker, 2: image
uniform vec3 checkerA, checkerB, colorMean;
uniform vec4 colorScale;    // scale u, scale v, offset u, offset v
uniform sampler2D colorImage;
uniform float exposure;
in vec3 vNormal, vRadiosity, vDpdu, vDpdv, vBary;
in vec2 vUv;
flat in ivec3 vCorners;
out vec4 color;

const float kPi = 3.14159265358979;

vec2 gradient(ivec2 c, uint seed) {
  uint h = uint(c.x) * 0x8da6b343u ^ uint(c.y) * 0xd8163841u ^ seed * 0xcb1ab31fu;
  h ^= h >> 13u;
  h *= 0x5bd1e995u;
  h ^= h >> 15u;
  float a = 2.0 * kPi * float(h & 0xffffu) / 65536.0;
  return vec2(cos(a), sin(a));
}
float gradientNoise(vec2 p, uint seed) {
  ivec2 c = ivec2(floor(p));
  vec2 f = p - vec2(c);
  vec2 w = f * f * f * (f * (f * 6.0 - 15.0) + 10.0);
  float n00 = dot(gradient(c, seed), f), n10 = dot(gradient(c + ivec2(1, 0), seed), f - vec2(1, 0));
  float n01 = dot(gradient(c + ivec2(0, 1), seed), f - vec2(0, 1));
  float n11 = dot(gradient(c + ivec2(1, 1), seed), f - vec2(1, 1));
  return mix(mix(n00, n10, w.x), mix(n01, n11, w.x), w.y);
}
float across(vec2 p) {
  float a = radians(bumpC.z);
  return dot(p, vec2(cos(a), sin(a)));
}
float pattern(vec2 p) {
  int type = int(bumpA.x);
  if (type == 0) {
    float h = 0.0, a = 1.0;
    for (int o = 0; o < int(bumpA.z); ++o, a *= 0.5, p *= 2.0)
      h += a * gradientNoise(p, uint(bumpA.w) + uint(o));
    return h;
  }
  if (type == 1) return sin(2.0 * kPi * across(p));
  float m = bumpC.x / 2.0, edge = 0.5 * m;
  if (type == 2) {
    float row = floor(p.y);
    float x = fract(p.x / 2.0 + 0.5 * row), y = fract(p.y);
    float g = min(min(x * 2.0, (1.0 - x) * 2.0), min(y, 1.0 - y));
    return smoothstep(m - edge, m + edge, g) - 1.0;
  }
  if (type == 3) {
    vec2 f = fract(p);
    float g = min(min(f.x, 1.0 - f.x), min(f.y, 1.0 - f.y));
    return smoothstep(m - edge, m + edge, g) - 1.0;
  }
  if (type == 4) {
    vec2 c = fract(p) - 0.5;
    float d2 = dot(c, c) / (bumpC.y * bumpC.y);
    return d2 < 1.0 ? -(1.0 - d2) * (1.0 - d2) : 0.0;
  }
  if (type == 5) {
    float t = 2.0 * fract(across(p)) - 1.0;
    return sqrt(max(0.0, 1.0 - t * t));
  }
  if (type == 6) {
    vec3 c = texture(bumpImage, p).rgb;
    return (c.r + c.g + c.b) / 3.0;
  }
  return 0.0;
}
// Blinn's N' from the height's slopes (bump.cpp's evaluate_bump and perturb_normal).
vec3 perturbed(vec3 n) {
  int type = int(bumpA.x);
  vec2 scale = bumpB.xy, p = vUv * scale + bumpB.zw;
  vec2 d;
  if (type == 1 || type == 5) {
    float a = radians(bumpC.z);
    vec2 axis = vec2(cos(a), sin(a));
    float slope;
    if (type == 1) {
      slope = 2.0 * kPi * cos(2.0 * kPi * across(p));
    } else {
      float t = 2.0 * fract(across(p)) - 1.0;
      slope = -2.0 * t / sqrt(max(1e-4, 1.0 - t * t));
    }
    d = slope * axis * scale;
  } else if (type == 7) {
    // A normal map's normal in the frame of N, dP/du and the image's up (bump.cpp).
    vec3 c = texture(bumpImage, p).rgb;
    vec3 local = vec3((2.0 * c.r - 1.0) * bumpC.w, (2.0 * c.g - 1.0) * bumpC.w, max(0.0, 2.0 * c.b - 1.0));
    vec3 t = vDpdu - n * dot(n, vDpdu), s = vDpdv - n * dot(n, vDpdv);
    if (!(length(t) > 0.0) || !(length(s) > 0.0)) return n;
    vec3 tangent = normalize(t), down = normalize(s - tangent * dot(tangent, s));
    vec3 m = local.x * tangent - local.y * down + local.z * n;
    return length(m) > 0.0 ? normalize(m) : n;
  } else {
    // Central differences: a thousandth of a cell, or half a texel of a height map.
    float e = type == 6 ? 0.5 / float(max(textureSize(bumpImage, 0).x, textureSize(bumpImage, 0).y)) : 1e-3;
    d = vec2(pattern(p + vec2(e, 0)) - pattern(p - vec2(e, 0)),
             pattern(p + vec2(0, e)) - pattern(p - vec2(0, e))) / (2.0 * e) * scale;
  }
  d *= bumpA.y;
  if (d == vec2(0)) return n;
  vec3 c = cross(vDpdu, vDpdv);
  float len = length(c);
  if (!(len > 0.0)) return n;
  float s = dot(c, n) < 0.0 ? -1.0 : 1.0;
  return normalize(n + s * (d.x * cross(n, vDpdv) - d.y * cross(n, vDpdu)) / len);
}
// Real spherical harmonics of bands 0, 1, 2 and 4 (map_basis.cpp).
void harmonics(vec3 d, out float y[18]) {
  float x = d.x, yy = d.y, z = d.z, x2 = x * x, y2 = yy * yy, z2 = z * z;
  y[0] = 0.28209479177387814; y[1] = -0.4886025119029199 * yy; y[2] = 0.4886025119029199 * z;
  y[3] = -0.4886025119029199 * x; y[4] = 1.0925484305920792 * x * yy;
  y[5] = -1.0925484305920792 * yy * z; y[6] = 0.31539156525252005 * (3.0 * z2 - 1.0);
  y[7] = -1.0925484305920792 * x * z; y[8] = 0.5462742152960396 * (x2 - y2);
  y[9] = 2.5033429417967046 * x * yy * (x2 - y2);
  y[10] = -1.7701307697799304 * yy * z * (3.0 * x2 - y2);
  y[11] = 0.9461746957575601 * x * yy * (7.0 * z2 - 1.0);
  y[12] = -0.6690465435572892 * yy * z * (7.0 * z2 - 3.0);
  y[13] = 0.10578554691520431 * (35.0 * z2 * z2 - 30.0 * z2 + 3.0);
  y[14] = -0.6690465435572892 * x * z * (7.0 * z2 - 3.0);
  y[15] = 0.47308734787878004 * (x2 - y2) * (7.0 * z2 - 1.0);
  y[16] = -1.7701307697799304 * x * z * (x2 - 3.0 * y2);
  y[17] = 0.6258357354491761 * (x2 * (x2 - 3.0 * y2) - y2 * (3.0 * x2 - y2));
}
vec4 texel(int vertex, int k) {
  return texelFetch(mapTexture, ivec2((vertex % ${kRowVertices}) * ${kMapTexels} + k,
                                      vertex / ${kRowVertices}), 0);
}
// One corner's B + B'(N') - B'(N): its radiosity, then 18 RGB coefficients in 14 texels.
vec3 corner(int vertex, float dy[18]) {
  vec3 b = texel(vertex, 0).rgb;
  float c[56];
  for (int k = 0; k < 14; ++k) {
    vec4 t = texel(vertex, 1 + k);
    c[4 * k] = t.x; c[4 * k + 1] = t.y; c[4 * k + 2] = t.z; c[4 * k + 3] = t.w;
  }
  for (int j = 0; j < 18; ++j) b += vec3(c[3 * j], c[3 * j + 1], c[3 * j + 2]) * dy[j];
  return b;
}
float srgb(float x) {
  x = clamp(x, 0.0, 1.0);
  return x <= 0.0031308 ? 12.92 * x : 1.055 * pow(x, 1.0 / 2.4) - 0.055;
}
void main() {
  vec3 n = normalize(vNormal);
  vec3 b = vRadiosity;
  if (bumpy) {
    vec3 np = perturbed(n);
    // The map's frame: N, dP/du made perpendicular (perturbed_map.cpp's tangent_frame).
    vec3 t = vDpdu - n * dot(n, vDpdu);
    t = length(t) > 1e-12 ? normalize(t) : normalize(abs(n.x) < 0.9 ? cross(n, vec3(1, 0, 0)) : cross(n, vec3(0, 1, 0)));
    vec3 s = cross(n, t);
    float y[18], y0[18], dy[18];
    harmonics(vec3(dot(np, t), dot(np, s), dot(np, n)), y);
    harmonics(vec3(0, 0, 1), y0);
    for (int j = 0; j < 18; ++j) dy[j] = y[j] - y0[j];
    b = vBary.x * corner(vCorners.x, dy) + vBary.y * corner(vCorners.y, dy) +
        vBary.z * corner(vCorners.z, dy);
  }
  b = max(b, vec3(0));
  // A colour texture scales what is reflected by rho(u,v) / its mean (texture.cpp).
  if (colorKind != 0) {
    vec2 p = vUv * colorScale.xy + colorScale.zw;
    int parity = (int(floor(p.x)) + int(floor(p.y))) & 1;
    vec3 rho = colorKind == 2 ? texture(colorImage, p).rgb : parity == 1 ? checkerB : checkerA;
    vec3 mean = colorKind == 2 ? colorMean : (checkerA + checkerB) / 2.0;
    b = emission + max(b - emission, vec3(0)) * rho / max(mean, vec3(1e-6));
  }
  vec3 radiance = b / kPi * exposure;
  color = vec4(srgb(radiance.r), srgb(radiance.g), srgb(radiance.b), 1.0);
}`;

// A bump function's uniforms, set from its parameters (the file's, or a slider's).
function setBumpUniforms(f, u) {
  const pair = (v, d) => (Array.isArray(v) ? v : v === undefined ? d : [v, v]);
  const scale = pair(f.scale, [1, 1]), offset = pair(f.offset, [0, 0]);
  u.bumpA.value.set(kBumpTypes.indexOf(f.type), f.amplitude ?? 0.01, f.octaves ?? 4, f.seed ?? 1);
  u.bumpB.value.set(scale[0], scale[1], offset[0], offset[1]);
  u.bumpC.value.set(f.mortar ?? 0.08, f.radius ?? 0.35, f.direction_deg ?? 0, f.strength ?? 1);
}

// The file's textures (PNG in its buffer) as three.js textures with their samplers' wrap
// modes, bilinear and without mipmaps as the server samples them; colours decoded from sRGB
// by the GPU before filtering, data (heights, normals) as stored.
async function loadTextures(file) {
  const { gltf, bytes, bin } = file;
  const wraps = { 10497: THREE.RepeatWrapping, 33071: THREE.ClampToEdgeWrapping, 33648: THREE.MirroredRepeatWrapping };
  return Promise.all((gltf.textures || []).map(async (t) => {
    const image = gltf.images[t.source], view = gltf.bufferViews[image.bufferView];
    const blob = new Blob([new Uint8Array(bytes, bin + (view.byteOffset || 0), view.byteLength)], { type: image.mimeType });
    const bitmap = await createImageBitmap(blob, { colorSpaceConversion: "none", premultiplyAlpha: "none" });
    const texture = new THREE.Texture(bitmap);
    const sampler = gltf.samplers[t.sampler] || {};
    texture.wrapS = wraps[sampler.wrapS] ?? THREE.RepeatWrapping;
    texture.wrapT = wraps[sampler.wrapT] ?? THREE.RepeatWrapping;
    texture.magFilter = texture.minFilter = THREE.LinearFilter;
    texture.generateMipmaps = false;
    texture.flipY = false;  // row 0 is the image's top, as the server reads it
    texture.needsUpdate = true;
    return texture;
  }));
}

// One mesh per primitive (material) and bump function, non-indexed: each triangle's corners
// carry the three vertex numbers and barycentric weights, so a fragment reads its corners'
// maps.
async function buildScene(file) {
  const { gltf, accessor } = file;
  const prim0 = gltf.meshes[0].primitives[0].attributes;
  const hasMap = prim0._MAP_0 !== undefined;
  const position = accessor(prim0.POSITION), normal = accessor(prim0.NORMAL), uv = accessor(prim0.TEXCOORD_0);
  const radiosity = accessor(prim0._RADIOSITY);
  const vertices = position.length / 3;
  const zeros = new Float32Array(vertices * 3);
  const dpdu = hasMap ? accessor(prim0._DPDU) : zeros, dpdv = hasMap ? accessor(prim0._DPDV) : zeros;
  const bump = hasMap ? accessor(prim0._BUMP) : new Float32Array(vertices).fill(-1);
  const textures = await loadTextures(file);
  const blank = new THREE.DataTexture(new Uint8Array(4), 1, 1);
  blank.needsUpdate = true;

  // The data texture: per vertex its radiosity and its map coefficients.
  const rows = Math.max(1, Math.ceil(vertices / kRowVertices));
  const data = new Float32Array(kRowVertices * kMapTexels * rows * 4);
  const maps = hasMap ? [...Array(14).keys()].map((k) => accessor(prim0[`_MAP_${k}`])) : [];
  for (let v = 0; v < vertices; ++v) {
    const at = v * kMapTexels * 4;  // rows of kRowVertices vertices, one after the other
    data.set(radiosity.subarray(3 * v, 3 * v + 3), at);
    maps.forEach((m, k) => data.set(m.subarray(4 * v, 4 * v + 4), at + 4 * (1 + k)));
  }
  const mapTexture = new THREE.DataTexture(data, kRowVertices * kMapTexels, rows, THREE.RGBAFormat,
                                           THREE.FloatType);
  mapTexture.needsUpdate = true;

  // Per bump function, the uniforms every mesh it covers shares.
  const bumps = (gltf.extras?.bumps || []).map((f) => {
    const u = { bumpA: { value: new THREE.Vector4() }, bumpB: { value: new THREE.Vector4() },
                bumpC: { value: new THREE.Vector4() },
                bumpImage: { value: f.texture !== undefined ? textures[f.texture] : blank } };
    setBumpUniforms(f, u);
    return { params: { ...f }, uniforms: u };
  });
  const smooth = { bumpA: { value: new THREE.Vector4() }, bumpB: { value: new THREE.Vector4() },
                   bumpC: { value: new THREE.Vector4() }, bumpImage: { value: blank } };
  const exposure = { value: gltf.extras?.exposure ?? 1 };

  const scene = new THREE.Scene();
  for (const p of gltf.meshes[0].primitives) {
    const index = accessor(p.indices);
    const groups = new Map();  // bump function -> the primitive's triangles (first index) under it
    for (let i = 0; i < index.length; i += 3) {
      const b = Math.round(bump[index[i]]);
      if (!groups.has(b)) groups.set(b, []);
      groups.get(b).push(i);
    }
    const extras = gltf.materials[p.material].extras || {};
    const t = extras.texture;
    const kind = !t ? 0 : t.type === "checker" ? 1 : t.texture !== undefined ? 2 : 0;
    for (const [b, triangles] of groups) {
      const n = 3 * triangles.length;
      const arrays = {
        position: new Float32Array(3 * n), normal: new Float32Array(3 * n), uv: new Float32Array(2 * n),
        radiosity: new Float32Array(3 * n), dpdu: new Float32Array(3 * n), dpdv: new Float32Array(3 * n),
        corners: new Float32Array(3 * n), bary: new Float32Array(3 * n),
      };
      triangles.forEach((first, k) => {
        for (let c = 0; c < 3; ++c) {
          const v = index[first + c], i = 3 * k + c;
          for (const [name, source] of [["position", position], ["normal", normal], ["radiosity", radiosity],
                                        ["dpdu", dpdu], ["dpdv", dpdv]])
            arrays[name].set(source.subarray(3 * v, 3 * v + 3), 3 * i);
          arrays.uv.set(uv.subarray(2 * v, 2 * v + 2), 2 * i);
          arrays.corners.set([index[first], index[first + 1], index[first + 2]], 3 * i);
          arrays.bary[3 * i + c] = 1;
        }
      });
      const geometry = new THREE.BufferGeometry();
      for (const [name, a] of Object.entries(arrays))
        geometry.setAttribute(name, new THREE.BufferAttribute(a, name === "uv" ? 2 : 3));
      const own = b >= 0 && bumps[b] ? bumps[b].uniforms : smooth;
      const uniforms = {
        ...own, mapTexture: { value: mapTexture }, bumpy: { value: hasMap && b >= 0 && !!bumps[b] }, exposure,
        emission: { value: new THREE.Vector3(...(extras.emission || [0, 0, 0])) },
        colorKind: { value: kind },
        checkerA: { value: new THREE.Vector3(...(kind === 1 ? t.colors[0] : [1, 1, 1])) },
        checkerB: { value: new THREE.Vector3(...(kind === 1 ? t.colors[1] : [1, 1, 1])) },
        colorMean: { value: new THREE.Vector3(...(kind === 2 ? t.mean : [1, 1, 1])) },
        colorScale: { value: new THREE.Vector4(...(t ? [...t.scale, ...t.offset] : [1, 1, 0, 0])) },
        colorImage: { value: kind === 2 ? textures[t.texture] : blank },
      };
      if (kind === 2) textures[t.texture].colorSpace = THREE.SRGBColorSpace;
      const material = new THREE.RawShaderMaterial({ vertexShader, fragmentShader, uniforms, glslVersion: THREE.GLSL3 });
      scene.add(new THREE.Mesh(geometry, material));
    }
  }
  return { scene, bumps };
}

// The file's camera: glTF looks down -z with +y up; `target` is where orbiting turns about.
function fileCamera(gltf, width, height) {
  const node = gltf.nodes.find((n) => n.camera !== undefined);
  const c = gltf.cameras[node.camera].perspective;
  const camera = new THREE.PerspectiveCamera((c.yfov * 180) / Math.PI, width / height, c.znear, 1e4);
  const m = new THREE.Matrix4().fromArray(node.matrix);
  const position = new THREE.Vector3().setFromMatrixPosition(m);
  const forward = new THREE.Vector3(-m.elements[8], -m.elements[9], -m.elements[10]).normalize();
  const up = new THREE.Vector3(m.elements[4], m.elements[5], m.elements[6]);
  camera.position.copy(position);
  camera.up.copy(up);
  const [lo, hi] = [gltf.accessors[gltf.meshes[0].primitives[0].attributes.POSITION].min,
                    gltf.accessors[gltf.meshes[0].primitives[0].attributes.POSITION].max];
  const centre = new THREE.Vector3(...lo).add(new THREE.Vector3(...hi)).multiplyScalar(0.5);
  const target = position.clone().add(forward.multiplyScalar(Math.max(1e-3, centre.distanceTo(position))));
  camera.lookAt(target);
  return { camera, target };
}

// ---- Orbit and walk ----------------------------------------------------------------------

// Drag: orbit about the target. Shift-drag or right-drag: pan. Wheel: closer or further.
// W, A, S, D or the arrow keys: walk (the target comes along).
function controls(canvas, view, redraw) {
  let drag = null;
  canvas.addEventListener("contextmenu", (e) => e.preventDefault());
  canvas.addEventListener("pointerdown", (e) => {
    drag = { x: e.clientX, y: e.clientY, pan: e.shiftKey || e.button === 2 };
    canvas.setPointerCapture(e.pointerId);
  });
  canvas.addEventListener("pointerup", () => (drag = null));
  canvas.addEventListener("pointermove", (e) => {
    if (!drag) return;
    const { camera, target } = view();
    const dx = e.clientX - drag.x, dy = e.clientY - drag.y;
    drag.x = e.clientX;
    drag.y = e.clientY;
    const offset = camera.position.clone().sub(target);
    if (drag.pan) {
      const scale = offset.length() / canvas.clientHeight;
      const right = new THREE.Vector3().setFromMatrixColumn(camera.matrix, 0);
      const up = new THREE.Vector3().setFromMatrixColumn(camera.matrix, 1);
      const move = right.multiplyScalar(-dx * scale).add(up.multiplyScalar(dy * scale));
      camera.position.add(move);
      target.add(move);
    } else {
      const spherical = new THREE.Spherical().setFromVector3(offset.applyQuaternion(
        new THREE.Quaternion().setFromUnitVectors(camera.up, new THREE.Vector3(0, 1, 0))));
      spherical.theta -= (dx / canvas.clientHeight) * Math.PI;
      spherical.phi = Math.min(Math.PI - 1e-3, Math.max(1e-3, spherical.phi - (dy / canvas.clientHeight) * Math.PI));
      offset.setFromSpherical(spherical).applyQuaternion(
        new THREE.Quaternion().setFromUnitVectors(new THREE.Vector3(0, 1, 0), camera.up));
      camera.position.copy(target).add(offset);
    }
    camera.lookAt(target);
    redraw();
  });
  canvas.addEventListener("wheel", (e) => {
    e.preventDefault();
    const { camera, target } = view();
    const offset = camera.position.clone().sub(target).multiplyScalar(Math.exp(e.deltaY * 1e-3));
    camera.position.copy(target).add(offset);
    camera.lookAt(target);
    redraw();
  }, { passive: false });
  canvas.tabIndex = 0;
  canvas.addEventListener("keydown", (e) => {
    const { camera, target } = view();
    const step = camera.position.distanceTo(target) * 0.05;
    const forward = target.clone().sub(camera.position).normalize();
    const right = forward.clone().cross(camera.up).normalize();
    const moves = { w: forward, arrowup: forward, s: forward.clone().negate(), arrowdown: forward.clone().negate(),
                    d: right, arrowright: right, a: right.clone().negate(), arrowleft: right.clone().negate() };
    const move = moves[e.key.toLowerCase()];
    if (!move) return;
    e.preventDefault();
    move.multiplyScalar(step);
    camera.position.add(move);
    target.add(move);
    camera.lookAt(target);
    redraw();
  });
}

// ---- The walkthrough ---------------------------------------------------------------------

class Walkthrough {
  constructor(canvas) {
    this.canvas = canvas;
    this.renderer = new THREE.WebGLRenderer({ canvas, antialias: false, preserveDrawingBuffer: true });
    this.drawn = 0;  // frames drawn
  }

  // Loads the job's model and shows it from the scene's camera at width x height pixels
  // (`ratio` drawing pixels each way per pixel).
  async open(jobId, width, height, ratio = window.devicePixelRatio || 1) {
    const response = await fetch(`/v1/jobs/${jobId}/model.glb`);
    if (response.status !== 200) throw new Error(`the model could not be fetched (${response.status})`);
    const file = parseGlb(await response.arrayBuffer());
    const built = await buildScene(file);
    this.scene = built.scene;
    this.bumps = built.bumps;
    this.gltf = file.gltf;
    this.size = [width, height];
    this.renderer.setPixelRatio(ratio);
    this.renderer.setSize(width, height, true);
    if (!this.controlled) controls(this.canvas, () => this.view, () => this.draw());
    this.controlled = true;
    this.reset();
  }

  // Back to the scene's camera.
  reset() {
    this.view = fileCamera(this.gltf, ...this.size);
    this.draw();
  }

  draw() {
    this.renderer.render(this.scene, this.view.camera);
    this.drawn++;
  }

  // A bump function's new parameters (the re-texture sliders'), by name.
  // A slider's bump function of another type keeps the file's image, which only the image
  // types read.
  setBump(name, params) {
    const bump = this.bumps.find((b) => b.params.name === name);
    if (!bump) return;
    bump.params = { ...bump.params, ...params };
    setBumpUniforms(bump.params, bump.uniforms);
    this.draw();
  }

  // The camera as a re-texture's "camera" block, to have the server render this view.
  cameraChanges() {
    const { camera, target } = this.view;
    const v = (p) => [p.x, p.y, p.z];
    return { position: v(camera.position), look_at: v(target), up: v(camera.up), fov_deg: camera.fov };
  }
}

window.Walkthrough = Walkthrough;
window.dispatchEvent(new Event("walkthrough-ready"));
