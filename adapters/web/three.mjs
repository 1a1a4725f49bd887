// libhalo in three.js (docs/hosts/web.md): a compositing ray caster in the style of the
// three.js examples (a box mesh with a ShaderMaterial, GLSL 3, the ray from
// cameraPosition through the box), and installHalo, which links a scene's per-sample
// stages as pieces (docs/composers.md) and puts them into a material's fragment shader at
// three comment markers:
//   //halo:declarations   at global scope, after the material's samplers
//   //halo:sample         in the ray loop, after classification: P (vec3, volume texture
//                         space), value (float), color (vec4, not premultiplied) in scope
//   //halo:finish         after the loop
// three's own VolumeShader (examples/jsm/shaders/VolumeShader.js) has only maximum
// intensity projection and isosurfaces, which composite no samples: installHalo refuses
// a material without the markers. Volumetric halos come through host contract 3: the
// stages are linked with oneDraw, and stages.render(renderer, scene, camera) computes
// the frame's halo field with libhalo's GL runtime (WebAssembly, on three's WebGL 2
// context) and then lets three draw once. Feature halos: stages.render splats the halo
// buffer with libhalo's runtime from the volume texture's data (again when the view
// direction changes) and binds it on the context's last texture unit. Outlines (the
// stages' extra outputs and the passes after the draw; installHalo's options.three, the
// THREE module, makes their render targets): stages.render draws the scene without the
// caster, then the caster alone, once, into a render target of its image and the stages'
// outputs, puts its image over the frame (as three would have drawn it), and replaces the
// frame's image with the passes' result over it. The objects with a greater renderOrder than
// the caster's (overlays) are drawn over that; the rest of the scene under the caster. The
// caster's render target holds
// a float texture for each attachment, three's own from 1 on unused (libhalo attaches its
// images there): about 33 MB each at 1920x1080.
//
//   import * as THREE from 'three';
//   import libhalo from '@libhalo/web';
//   import { createVolumeCaster, installHalo } from '@libhalo/web/three';
//   const caster = createVolumeCaster(THREE, { volume, dims, transfer, step: 1 / 256 });
//   scene.add(caster.mesh);
//   const halo = await libhalo();
//   const stages = installHalo(halo, caster.material, { scene: sceneJson });
//   stages.set('tone_shading.k_ta', 0.4);   // a live parameter: a uniform, no rebuild
//   stages.render(renderer, scene, camera); // instead of renderer.render (halos: the field first)
//
// The caster's conventions are libhalo's host contract's (docs/host-contract.md): the
// mesh spans the volume's texture space [0, 1]^3 in world units (a perspective camera: the
// stages' view and depth are the eye's); the value in the red
// channel is already normalized to [0, 1]; the transfer function is N x 1 RGBA (linear
// colour, opacity per unit step); depth is 0 at the front of the volume's bounding sphere
// and 1 at its back, as in examples/hosts/raycast.frag, with which it is compared in the
// browser tests (tests/adapters/web/browser.mjs).

import { showTexture, textureShower } from './libhalo.mjs';

export const MARKERS = Object.freeze({
  declarations: '//halo:declarations',
  sample: '//halo:sample',
  finish: '//halo:finish',
});

// The caster's names for the sample piece (HaloPieces): what the markers have in scope.
export const CASTER_NAMES = Object.freeze({
  position: 'P',
  value: 'value',
  volume: 'u_volume', // the gradient: central differences of the value, halved (the contract's)
  view: 'normalize(cameraPosition - P)',
  depth: 'clamp((distance(cameraPosition, P) - front_distance) / 1.7320508075688772, 0.0, 1.0)',
  fragcoord: 'gl_FragCoord.xy',
  color: 'color',
});

const vertexShader = `
out vec3 v_position; // the box's point in world space: the volume's texture space
void main() {
    vec4 world = modelMatrix * vec4(position, 1.0);
    v_position = world.xyz;
    gl_Position = projectionMatrix * viewMatrix * world;
}
`;

const fragmentShader = `
precision highp sampler3D;
uniform highp sampler3D u_volume;   // R: the value, normalized to [0, 1]
uniform highp sampler2D u_transfer; // N x 1 RGBA: linear colour and opacity per unit step
uniform float u_step;               // the ray step, in texture units
uniform float u_unit_step;          // the step the transfer function's opacities are for
uniform vec3 u_background;
uniform mat4 u_inverse_view_projection; // clip space -> world: each pixel's ray (mesh.onBeforeRender)
uniform vec2 u_viewport;                // the target's size in pixels
in vec3 v_position;
layout(location = 0) out highp vec4 frag_color;
${MARKERS.declarations}
#ifndef HALO_RAY_MAY_END
#define HALO_RAY_MAY_END 1
#endif
vec4 classify(float value) {
    float texels = float(textureSize(u_transfer, 0).x);
    float u = ((value > 0.0 ? min(value, 1.0) : 0.0) * (texels - 1.0) + 0.5) / texels;
    return texture(u_transfer, vec2(u, 0.5));
}
void main() {
    // the pixel's ray through the near and far planes (exact for every pixel, perspective or
    // orthographic; the box's back faces only say which pixels to march)
    vec2 ndc = gl_FragCoord.xy / u_viewport * 2.0 - 1.0;
    vec4 near_point = u_inverse_view_projection * vec4(ndc, -1.0, 1.0);
    vec4 far_point = u_inverse_view_projection * vec4(ndc, 1.0, 1.0);
    vec3 origin = near_point.xyz / near_point.w;
    vec3 direction = normalize(far_point.xyz / far_point.w - origin);
    vec3 inverse_direction = 1.0 / direction;
    vec3 t_low = (vec3(0.0) - origin) * inverse_direction, t_high = (vec3(1.0) - origin) * inverse_direction;
    vec3 t_min3 = min(t_low, t_high), t_max3 = max(t_low, t_high);
    float t_enter = max(max(max(t_min3.x, t_min3.y), t_min3.z), 0.0);
    float t_exit = min(min(t_max3.x, t_max3.y), t_max3.z);
    float front_distance = distance(cameraPosition, vec3(0.5)) - 0.8660254037844386;
    float exponent = u_step / u_unit_step;
    vec4 accumulated = vec4(0.0); // premultiplied
    for (int i = 0; i < 4096; ++i) {
        float t = t_enter + float(i) * u_step;
        if (t > t_exit)
            break;
        vec3 P = origin + t * direction;
        float value = texture(u_volume, P).r;
        vec4 color = classify(value);
        ${MARKERS.sample}
        float alpha = clamp(color.a, 0.0, 1.0);
        if (alpha > 0.0) {
            alpha = 1.0 - pow(1.0 - alpha, exponent);
            accumulated.rgb += (1.0 - accumulated.a) * alpha * color.rgb;
            accumulated.a += (1.0 - accumulated.a) * alpha;
            if (accumulated.a >= 0.99 && HALO_RAY_MAY_END != 0)
                break;
        }
    }
    ${MARKERS.finish}
    frag_color = vec4(accumulated.rgb + (1.0 - accumulated.a) * u_background, 1.0);
}
`;

// The caster: { mesh, material, volumeTexture, transferTexture }. options: volume
// (Float32Array, x fastest), dims [nx, ny, nz], transfer (Float32Array, N RGBA texels),
// step (texture units), unitStep (default step), background ([r, g, b], default white).
export function createVolumeCaster(THREE, options) {
  const { volume, dims, transfer } = options;
  if (!volume || !dims || dims.length !== 3 || volume.length !== dims[0] * dims[1] * dims[2])
    throw new Error('createVolumeCaster: volume must hold dims[0] * dims[1] * dims[2] values');
  if (!transfer || transfer.length < 8 || transfer.length % 4)
    throw new Error('createVolumeCaster: transfer must hold N >= 2 RGBA texels');
  if (!(options.step > 0)) throw new Error('createVolumeCaster: step must be > 0 (texture units)');
  const volumeTexture = new THREE.Data3DTexture(volume, dims[0], dims[1], dims[2]);
  volumeTexture.format = THREE.RedFormat;
  volumeTexture.type = THREE.FloatType;
  const transferTexture = new THREE.DataTexture(transfer, transfer.length / 4, 1, THREE.RGBAFormat, THREE.FloatType);
  for (const texture of [volumeTexture, transferTexture]) {
    texture.minFilter = texture.magFilter = THREE.LinearFilter;
    texture.wrapS = texture.wrapT = texture.wrapR = THREE.ClampToEdgeWrapping;
    texture.generateMipmaps = false;
    texture.unpackAlignment = 1;
    texture.needsUpdate = true;
  }
  const background = options.background || [1, 1, 1];
  const material = new THREE.ShaderMaterial({
    glslVersion: THREE.GLSL3,
    uniforms: {
      u_volume: { value: volumeTexture },
      u_transfer: { value: transferTexture },
      u_step: { value: options.step },
      u_unit_step: { value: options.unitStep || options.step },
      u_background: { value: new THREE.Vector3(background[0], background[1], background[2]) },
      u_inverse_view_projection: { value: new THREE.Matrix4() },
      u_viewport: { value: new THREE.Vector2(1, 1) },
    },
    vertexShader,
    fragmentShader,
    side: THREE.BackSide, // the far faces: the ray starts at the box or at the eye inside it
    depthTest: false,
    depthWrite: false,
  });
  const geometry = new THREE.BoxGeometry(1, 1, 1);
  geometry.translate(0.5, 0.5, 0.5);
  const mesh = new THREE.Mesh(geometry, material);
  const size = new THREE.Vector2();
  mesh.onBeforeRender = (renderer, scene, camera) => {
    if (!renderer.extensions.has('OES_texture_float_linear')) // float textures would not filter: wrong image
      throw new Error('createVolumeCaster: this WebGL 2 context lacks OES_texture_float_linear (linear filtering ' +
        'of the float volume and transfer textures)');
    const u = material.uniforms;
    u.u_inverse_view_projection.value.multiplyMatrices(camera.projectionMatrix, camera.matrixWorldInverse).invert();
    const target = renderer.getRenderTarget();
    if (target) u.u_viewport.value.set(target.width, target.height);
    else u.u_viewport.value.copy(renderer.getDrawingBufferSize(size));
  };
  return { mesh, material, volumeTexture, transferTexture };
}

// A live parameter's value as three.js uploads it.
function uniformValue(type, values) {
  const array = /\[\d+\]$/.test(type);
  const base = type.replace(/\[\d+\]$/, '');
  if (!array && (base === 'float' || base === 'int' || base === 'bool' || (base === 'channels' && values.length === 1)))
    return values[0];
  return base === 'int' || base === 'bool' ? Int32Array.from(values, Math.round) : Float32Array.from(values);
}

// Links the scene's per-sample stages as pieces and puts them into material's fragment
// shader at MARKERS; the live parameters become material uniforms. options: scene (JSON
// text or object), sceneFile (its name in diagnostics), names (overrides of CASTER_NAMES
// for another caster's variables), allLive; for volumetric halos volume and step (the
// material's uniforms of the volume texture and the ray step: 'u_volume', 'u_step') and
// interval (M, planes a depth segment; default the scene's), fieldMaxBytes (the cap on the
// halo field; libhalo's default) and imageScale (the halo images at 1/2 or 1/4 of the frame
// per side; without it a field over the cap is linked again at 1/2, then 1/4, with a
// warning); three (the THREE module) for a scene with outlines. Returns { program (the one
// drawn now), set(name, value), render(renderer,
// scene, camera), remove() }; throws a HaloError with file:line:col on a scene error or a
// refused scene.
export function installHalo(halo, material, options = {}) {
  const original = material.fragmentShader;
  for (const [piece, marker] of Object.entries(MARKERS))
    if (!original.includes(marker))
      throw new Error(`installHalo: the material's fragment shader has no '${marker}' marker (where the ${piece} ` +
        'piece goes): a compositing ray caster marks its declarations, its sample after classification and the ' +
        "end of its ray loop (three's VolumeShader, MIP and isosurfaces only, composites no samples)");
  if (material.glslVersion !== '300 es')
    throw new Error('installHalo: the material must be GLSL 3 (glslVersion: THREE.GLSL3): the pieces are GLSL ES 300');
  let { program, field, features, outlines } = halo.linkForEngine({ scene: options.scene, sceneFile: options.sceneFile,
    allLive: options.allLive, imageScale: options.imageScale, pieces: { ...CASTER_NAMES, ...(options.names || {}) } },
  'three.js', ['halo_host_feature_buffer'], { outlines: true });
  const THREE = options.three;
  if (outlines && !(THREE && typeof THREE.WebGLRenderTarget === 'function')) {
    const stages = (program.reflection.stages || []).map((s) => (typeof s === 'string' ? s : s.name)).join(', ');
    program.destroy();
    throw new Error(`installHalo: the scene's stages (${stages}) draw outlines, which need render targets of their own: ` +
      'pass options.three, the THREE module (import * as THREE from \'three\')');
  }
  const uniforms = [];
  // the program's pieces into the material's shader, its live parameters' values (those set
  // since the install: the program's) into the material's uniforms
  const put = () => {
    for (const name of uniforms) delete material.uniforms[name];
    uniforms.length = 0;
    for (const u of program.reflection.uniforms || []) {
      const values = program._current.get(`${u.stage}.${u.param}`) || u.value;
      material.uniforms[u.name] = { value: uniformValue(u.type, values) };
      uniforms.push(u.name);
      if (/\[\d+\]$/.test(u.type)) {
        const components = /vec(\d)/.exec(u.type) ? Number(/vec(\d)/.exec(u.type)[1]) : 1;
        material.uniforms[`${u.name}_count`] = { value: Math.floor(values.length / components) };
        uniforms.push(`${u.name}_count`);
      }
    }
    material.fragmentShader = original
      .replace(MARKERS.declarations, program.pieces.declarations || '')
      .replace(MARKERS.sample, program.pieces.sample || '')
      .replace(MARKERS.finish, program.pieces.finish || '');
    if (field)
      for (const name of ['halo_host_screen_right', 'halo_host_screen_up']) {
        material.uniforms[name] = { value: new Float32Array(3) };
        uniforms.push(name);
      }
    material.needsUpdate = true;
  };
  put();
  let frame = null; // libhalo's GL runtime for the field, made on the first render
  let own = null; // outlines: three's render targets of the caster's image and outputs, and of the whole image
  let feature = null; // the feature halos' buffer, made on the first render
  let compiledVersion = -1; // the material's version three last compiled for render
  const stages = {
    get program() { return program; }, // another after a field over its cap (linked at a smaller scale)
    // a live parameter ("stage.param"): the uniform's new value, no shader rebuild
    set(name, value) {
      program.set(name, value);
      const dot = name.indexOf('.');
      const u = (program.reflection.uniforms || []).find((e) => e.stage === name.slice(0, dot) &&
        e.param === name.slice(dot + 1));
      if (!u) throw new Error(`set ${name}: a constant in the linked shader: mark it live in the scene or install ` +
        'with allLive');
      const values = (Array.isArray(value) ? value.flat(2) : [value]).map((v) => (typeof v === 'boolean' ? +v : v));
      material.uniforms[u.name].value = uniformValue(u.type, values);
      if (material.uniforms[`${u.name}_count`]) {
        const components = /vec(\d)/.exec(u.type) ? Number(/vec(\d)/.exec(u.type)[1]) : 1;
        material.uniforms[`${u.name}_count`].value = Math.floor(values.length / components);
      }
    },
    // Draws the scene as renderer.render does; with volumetric halos (field) the halo field
    // of this frame first (host contract 3), computed by libhalo on three's context over the
    // caster's volume texture, then three's one draw. The caster's conventions: the mesh
    // spans the volume's texture space in world units; the volume and the step are the
    // material's uniforms named by options.volume ('u_volume') and options.step ('u_step').
    render(renderer, scene, camera) {
      if (!field && !features && !outlines) {
        renderer.render(scene, camera);
        return;
      }
      const gl = renderer.getContext();
      const target = renderer.getRenderTarget();
      const width = target ? target.width : gl.drawingBufferWidth, height = target ? target.height : gl.drawingBufferHeight;
      const volume = material.uniforms[options.volume || 'u_volume'].value;
      const step = material.uniforms[options.step || 'u_step'].value;
      camera.updateMatrixWorld();
      const axes = camera.matrixWorld.elements; // the image plane's axes: the camera's x and y, in world space
      if (field) {
        material.uniforms.halo_host_screen_right.value = Float32Array.of(axes[0], axes[1], axes[2]);
        material.uniforms.halo_host_screen_up.value = Float32Array.of(axes[4], axes[5], axes[6]);
      }
      if (!renderer.properties.get(material).currentProgram || material.version !== compiledVersion) {
        renderer.compile(scene, camera); // the material's program, before libhalo sets its uniforms
        compiledVersion = material.version;
      }
      renderer.initTexture(volume);
      const glProgram = renderer.properties.get(material).currentProgram?.program;
      const glVolume = renderer.properties.get(volume).__webglTexture;
      if (!glProgram || !glVolume) throw new Error('stages.render: three.js has not built the material or the volume');
      if (features) { // the halo buffer for the view from the volume's centre to the eye, in voxels
        const p = camera.getWorldPosition(new camera.position.constructor());
        const size = [volume.image.width, volume.image.height, volume.image.depth];
        const v = [(p.x - 0.5) * size[0], (p.y - 0.5) * size[1], (p.z - 0.5) * size[2]], length = Math.hypot(...v);
        const view = v.map((e) => e / length);
        if (feature && feature.volumeVersion !== volume.version) { // the volume's data changed: splat it anew
          feature.destroy();
          feature = null;
        }
        if (!feature) {
          feature = halo.featureBuffer(gl, program, { values: volume.image.data,
            dims: [volume.image.width, volume.image.height, volume.image.depth] });
          feature.volumeVersion = volume.version;
        }
        feature.build(view); // at once when it holds this view
        // the last unit: three takes its units from 0 on, libhalo's field from 8 on
        feature.bind(glProgram, gl.getParameter(gl.MAX_TEXTURE_IMAGE_UNITS) - 1);
        renderer.resetState(); // three's caches: the program and texture unit changed under them
        renderer.setRenderTarget(target);
      }
      if (!field && !outlines) {
        renderer.render(scene, camera);
        return;
      }
      const framebuffer = target ? renderer.properties.get(target).__webglFramebuffer : null;
      const kept = frame;
      frame = null;
      frame = halo.frameOfSize(kept, gl, program, width, height);
      // outlines: the scene's layers under the caster (drawn as three draws them), the caster
      // alone into a target of its own, its image and the stages' outputs (drawOutlined), put
      // over them, the passes after the draw over that, then the objects over the caster
      const layers = outlines ? outlineLayers(scene, material) : null;
      if (layers) {
        refuseOutlines(THREE, renderer, material, target, width, height);
        const attachments = 1 + Math.max(0, ...(program.reflection.outputs || []).map((o) => o.location));
        own = outlineTargets(THREE, own, width, height, target, attachments);
        drawWithout(renderer, scene, camera, [...layers.casters, ...layers.over], false);
      }
      const drawOutlined = () => { // over transparent black: what the caster leaves undrawn lets the scene through
        gl.clearBufferfv(gl.COLOR, 0, [0, 0, 0, 0]);
        // the caster alone; no clear (three's would clear the stages' outputs too)
        drawWithout(renderer, scene, camera, [...layers.under, ...layers.over], true);
      };
      const inverse = camera.projectionMatrix.clone().multiply(camera.matrixWorldInverse).invert();
      let smaller = null;
      try {
        if (layers) renderer.setRenderTarget(own.caster); // three makes its framebuffer
        frame.draw({
          program: glProgram, volume: glVolume, volumeSize: [volume.image.width, volume.image.height, volume.image.depth],
          volumeVersion: volume.version, framebuffer: layers ? renderer.properties.get(own.caster).__webglFramebuffer : framebuffer,
          inverseViewProjection: inverse.elements, step, interval: options.interval, fieldMaxBytes: options.fieldMaxBytes,
          draw: layers ? drawOutlined : () => renderer.render(scene, camera),
        });
        if (layers) {
          showOutlined(gl, own, frame, renderer, framebuffer, width, height);
          renderer.resetState();
          renderer.setRenderTarget(target);
          if (layers.over.length) drawWithout(renderer, scene, camera, [...layers.under, ...layers.casters], true);
        }
      } catch (e) { // the field over its cap: the scene at a smaller halo scale, drawn at once
        if (!(smaller = halo.smallerProgram(program, e))) throw e;
      } finally {
        // libhalo put back the bindings of before the call, not three's of its draw: three's
        // state cache is told to forget, as after any foreign GL code (resetState also
        // forgets the render target, which is set again)
        renderer.resetState();
        renderer.setRenderTarget(target);
      }
      if (smaller) {
        console.warn(`libhalo: ${smaller.warning}`);
        frame.destroy();
        frame = null;
        if (feature) feature.destroy();
        feature = null;
        program.destroy();
        program = smaller.program;
        put();
        stages.render(renderer, scene, camera);
      }
    },
    // the material's own shader again, without the stages
    remove() {
      material.fragmentShader = original;
      for (const name of uniforms) delete material.uniforms[name];
      material.needsUpdate = true;
      if (frame) frame.destroy();
      frame = null;
      if (feature) feature.destroy();
      feature = null;
      if (own) outlineTargets(THREE, own, 0, 0, null, 0);
      own = null;
      program.destroy();
    },
  };
  return stages;
}

// Outlines' render targets for a width x height frame drawn into target (null: the canvas),
// made again over old when they differ (0 x 0: old's freed, null): caster, the caster's image
// (RGBA32F: its output as it is) and, at attachments 1 to attachments - 1, the stages'
// outputs (libhalo attaches its own textures there for the draw); whole, a copy of the
// frame's whole image in the target's format, which the passes after the draw read; shower,
// the program that shows a texture.
function outlineTargets(THREE, old, width, height, target, attachments) {
  const type = target ? target.texture.type : THREE.UnsignedByteType;
  if (old && old.width === width && old.height === height && old.type === type && old.attachments === attachments)
    return old;
  if (old) {
    old.caster.dispose();
    old.whole.dispose();
    if (!width) textureShower(old.gl, old.shower, false);
  }
  if (!width) return null;
  const options = { depthBuffer: false, minFilter: THREE.NearestFilter, magFilter: THREE.NearestFilter,
    generateMipmaps: false };
  const caster = new THREE.WebGLRenderTarget(width, height, { ...options, type: THREE.FloatType, count: attachments });
  if (!Array.isArray(caster.textures) || caster.textures.length !== attachments) {
    caster.dispose();
    throw new Error(`outlines: this three.js (r${THREE.REVISION}) makes no render target of several textures ` +
      '(WebGLRenderTarget\'s count, three r163 and later)');
  }
  return { width, height, type, attachments, gl: old && old.gl, shower: old && old.shower, caster,
    whole: new THREE.WebGLRenderTarget(width, height, { ...options, type }) };
}

// What outlines do not serve, refused with the reason: a caster that blends (WebGL 2 has one
// blend for all draw buffers: the stages' outputs would blend too; createVolumeCaster's is
// opaque), a multisampled render target (three draws into another framebuffer than the one
// the passes' result goes to), a viewport or scissor smaller than the target (the passes read
// the whole image).
function refuseOutlines(THREE, renderer, material, target, width, height) {
  const why = [];
  if (material.transparent || ![THREE.NormalBlending, THREE.NoBlending].includes(material.blending))
    why.push('the caster\'s material blends (transparent, or a blending of its own): it must be opaque');
  if (target && target.samples > 0) why.push(`the render target is multisampled (samples ${target.samples})`);
  const viewport = renderer.getCurrentViewport(new THREE.Vector4());
  if (viewport.x || viewport.y || viewport.z !== width || viewport.w !== height || renderer.getScissorTest())
    why.push(`the viewport (${viewport.x}, ${viewport.y}, ${viewport.z}, ${viewport.w}) or the scissor is not the whole ` +
      `${width}x${height} target: the passes after the draw read the whole image`);
  if (why.length) throw new Error(`stages.render: outlines: ${why.join('; ')}`);
}

// A scene's layers around the caster (the objects drawn with material): casters; over, the
// objects three draws after them (a greater renderOrder: overlays); under, every other visible
// object, drawn before them.
function outlineLayers(scene, material) {
  const casters = [], over = [], under = [];
  scene.traverseVisible((o) => { if (o.material === material) casters.push(o); });
  const order = Math.max(...casters.map((o) => o.renderOrder));
  scene.traverseVisible((o) => {
    if (o.material !== material && (o.isMesh || o.isLine || o.isPoints || o.isSprite)) (o.renderOrder > order ? over : under).push(o);
  });
  return { casters, over, under };
}

// The scene drawn by three without the objects hidden (their layers' mask 0 for the draw:
// their children are drawn as their own layers say, where visible = false would hide them
// too); onTop: over the target as it is (no clear, no background).
function drawWithout(renderer, scene, camera, hidden, onTop) {
  const { autoClear } = renderer, { background } = scene;
  const masks = hidden.map((o) => o.layers.mask);
  for (const o of hidden) o.layers.mask = 0;
  if (onTop) {
    renderer.autoClear = false;
    scene.background = null; // a colour background clears the target, whatever autoClear says
  }
  try {
    renderer.render(scene, camera);
  } finally {
    hidden.forEach((o, i) => { o.layers.mask = masks[i]; });
    renderer.autoClear = autoClear;
    scene.background = background;
  }
}

// After frame.draw into own.caster: its image over the frame (as three would have drawn the
// caster, opaque where it drew), the frame's whole image copied, the passes after the draw
// over it (frame.post), and their result as the frame's image. Three's state is reset after.
function showOutlined(gl, own, frame, renderer, framebuffer, width, height) {
  const texture = (t) => renderer.properties.get(t).__webglTexture;
  renderer.setRenderTarget(own.whole); // three makes its framebuffer and texture
  renderer.resetState();
  own.gl = gl;
  own.shower = textureShower(gl, own.shower);
  const viewport = [0, 0, width, height];
  const over = { on: true, equation: [gl.FUNC_ADD, gl.FUNC_ADD], func: [gl.ONE, gl.ONE_MINUS_SRC_ALPHA, gl.ONE, gl.ONE_MINUS_SRC_ALPHA] };
  showTexture(gl, own.shower, texture(own.caster.textures[0]), framebuffer, viewport, over);
  const reading = gl.getParameter(gl.READ_FRAMEBUFFER_BINDING), drawing = gl.getParameter(gl.DRAW_FRAMEBUFFER_BINDING);
  gl.bindFramebuffer(gl.READ_FRAMEBUFFER, framebuffer); // the frame's whole image (resolved when multisampled)
  gl.bindFramebuffer(gl.DRAW_FRAMEBUFFER, renderer.properties.get(own.whole).__webglFramebuffer);
  gl.blitFramebuffer(0, 0, width, height, 0, 0, width, height, gl.COLOR_BUFFER_BIT, gl.NEAREST);
  gl.bindFramebuffer(gl.READ_FRAMEBUFFER, reading);
  gl.bindFramebuffer(gl.DRAW_FRAMEBUFFER, drawing);
  const error = gl.getError();
  if (error) throw new Error(`outlines: the frame's image could not be copied for the passes after the draw (WebGL error 0x${error.toString(16)})`);
  showTexture(gl, own.shower, frame.post(texture(own.whole.texture)), framebuffer, viewport, null);
}
