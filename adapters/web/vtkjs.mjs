// libhalo in vtk.js (docs/hosts/web.md): a scene's stages go into vtk.js's own volume
// mapper through its documented hook, the mapper's view-specific ShaderReplacements: the
// sample piece after vtk.js classifies and lights a sample (getColorAtPos, which its
// composite ray loop calls for every sample), the finish piece at the end of main. For
// volumetric halos (host contract 3) libhalo's GL runtime (WebAssembly) computes the
// frame's halo field on vtk.js's context, over a float copy of the mapper's volume, after
// vtk.js has set its uniforms and before its one draw (taken at the context's drawArrays:
// vtk.js's objects are frozen).
//
//   import libhalo from '@libhalo/web';
//   import { installHalo } from '@libhalo/web/vtkjs';
//   // mapper: a vtkVolumeMapper with its vtkImageData; view: the vtkOpenGLRenderWindow
//   // (genericRenderWindow.getApiSpecificRenderWindow()); rendered once already
//   const stages = installHalo(await libhalo(), mapper, { view, scene: sceneJson });
//   renderWindow.render();                   // vtk.js draws as always, once
//   stages.set('halo_map.opacity[1]', 0.8); renderWindow.render();
//   stages.remove();                         // vtk.js's own shader again
//
// Supported: vtk.js 37 (its vtkVolumeFS; SUPPORTED_VERSIONS are the versions tested), the
// composite blend mode, a single-component volume. What the stages see: the sample's
// position in vtk.js's volume texture space (posIS), the value (the volume's first
// component, options.window or its range to 0..1, read from the adapter's float copy), its
// gradient (central differences of that value) and vtk.js's colour (its transfer functions,
// gradient opacity and lighting), its opacity per unit distance (vtk.js's correction for
// its sample distance undone before the stages, done again after). Other blend modes,
// clipping planes, several components and vtk.js's label outlines are refused with a message
// (at install and at every draw); outlines of segmentation labels are refused, naming the
// stages. Outlines: the adapter draws vtk.js's volume itself into libhalo's target (its
// colour and the stages' outputs), composites it over vtk.js's framebuffer with vtk.js's
// blend and runs the passes after the draw over vtk.js's whole image (frame.post); vtk.js's
// rays then run to their end (the outputs need hidden samples too). Feature halos: libhalo's runtime splats the halo buffer from the
// adapter's float copy of the volume (again when it changes), for the view from the
// volume's centre to vtk.js's eye (in voxel space; again when it turns), bound on a unit of
// its own.

import { blendOf, colorTarget, deleteColorTarget, showTexture, textureShower } from './libhalo.mjs';

export const SUPPORTED_VERSIONS = Object.freeze(['37.3.1']);

const VALUE_SAMPLER = 'halo_vtkjs_value';
const FEATURE_BUFFER = 'halo_host_feature_buffer'; // the feature_halo stage's host uniform
const LABELS_UNIFORM = 'halo_host_labels'; // outline_feature's segmentation (libhalo.mjs's LABELS_UNIFORM)
const EXPONENT = 'halo_vtkjs_opacity_exponent'; // vtk.js's sample distance / its opacity unit distance (> 0)
// the renderer's whole size over vtk.js's render target's: above 1 in its reduced viewport
// while the user interacts ((2, 2) at its interaction scale 4), (1, 1) otherwise and with
// outlines (drawn into libhalo's target at vtk.js's size); the fragment's pixel in the
// frame where the halo field is made
const PIXEL_SCALE = 'halo_vtkjs_pixel_scale';
const COMPOSITE_BLEND = 0; // vtk.js's BlendMode.COMPOSITE_BLEND
const installed = new WeakSet(); // the mappers with libhalo's stages
const INSTALL_MARK = '// libhalo: the stages of install '; // and its id, in the shaders vtk.js builds with them
// an install's id: this module's (two copies of the adapter in a page do not mix) and a count
const MODULE_ID = Math.random().toString(36).slice(2, 10);
let installs = 0;

// vtk.js's texts the replacements are made at (its vtkVolumeFS.glsl)
const SAMPLE_ANCHOR = 'vec4 getColorAtPos(vec3 posVC) {\n' +
  '  vec3 posIS = posVCtoIS(posVC);\n' +
  '  vec4 texValue = getTextureValue(posIS);\n' +
  '  return getColorForValue(texValue, posVC, posIS);\n' +
  '}';
const FINISH_ANCHOR = 'applyBlend(rayOriginVC, rayDirVC, rayStartEndDistancesVC[0], rayStartEndDistancesVC[1]);';
const FINISH_MARK = '// libhalo: the finish piece of install '; // and its id
// vtk.js's composite loop, before its early ray termination (color.a > 0.99)
const LOOP_ANCHOR = '      color = color + vec4(tColor.rgb * tColor.a, tColor.a) * (1.0 - color.a);\n' +
  '      stepsTraveled++;\n' +
  '      posVC += stepVC;\n';

// vtk.js's names for the sample piece; view and depth come from the camera libhalo sets.
export const VTKJS_NAMES = Object.freeze({
  position: 'posIS',
  value: `texture(${VALUE_SAMPLER}, posIS).r`,
  volume: VALUE_SAMPLER,
  fragcoord: `((gl_FragCoord.xy - vec2(vpOffsetX * vpWidth, vpOffsetY * vpHeight)) * ${PIXEL_SCALE})`,
  color: 'haloColor',
});

// vtk.js's substitute() treats a replacement's text as String.replace's: '$' is special
const literal = (text) => text.replace(/\$/g, '$$$$');

function replacements(pieces, id) { // id: the install's
  const sample = `${INSTALL_MARK}${id}\nuniform highp sampler3D ${VALUE_SAMPLER};\nuniform float ${EXPONENT};\n` +
    `uniform vec2 ${PIXEL_SCALE};\n` +
    `${pieces.declarations || ''}\n` +
    'vec4 getColorAtPos(vec3 posVC) {\n' +
    '  vec3 posIS = posVCtoIS(posVC);\n' +
    '  vec4 texValue = getTextureValue(posIS);\n' +
    '  vec4 haloColor = getColorForValue(texValue, posVC, posIS);\n' +
    // vtk.js's opacity is corrected for its sample distance; the stages take and give it
    // per unit distance (the contract's convention): undone before, done again after
    // (0 where libhalo has not prepared the draw: vtk.js's own sample, no stages)
    `  if (${EXPONENT} > 0.0) {\n` +
    `  haloColor.a = 1.0 - pow(clamp(1.0 - haloColor.a, 0.0, 1.0), 1.0 / ${EXPONENT});\n` +
    `${pieces.sample || ''}\n` +
    `  haloColor.a = 1.0 - pow(clamp(1.0 - haloColor.a, 0.0, 1.0), ${EXPONENT});\n` +
    '  }\n' +
    '  return haloColor;\n' +
    '}';
  // the stages' extra outputs (outlines) need every sample of a ray, hidden ones too
  // (HALO_RAY_MAY_END 0): vtk.js's rays then run to their end
  const loop = `${LOOP_ANCHOR}#if defined(HALO_RAY_MAY_END) && !HALO_RAY_MAY_END\n      if (color.a > 0.99) continue;\n#endif\n`;
  return [SAMPLE_ANCHOR, sample, FINISH_ANCHOR, `${FINISH_ANCHOR}\n${FINISH_MARK}${id}\n${pieces.finish || ''}`,
    LOOP_ANCHOR, loop].reduce((list, text, i, all) => {
    if (i % 2 === 0)
      list.push({ shaderType: 'Fragment', originalValue: text, replacementValue: literal(all[i + 1]), replaceFirst: false,
        replaceAll: false, libhalo: true });
    return list;
  }, []);
}

// The volume's first component, window [low, high] (default its range) to 0..1 (R32F).
function valueTexture(halo, gl, imageData, window, unit) {
  const scalars = imageData.getPointData().getScalars();
  const [low, high] = window || scalars.getRange(0);
  return halo.valueTexture(gl, scalars.getData(), imageData.getDimensions(), { low, high }, unit);
}

// vtk.js's camera as libhalo's: clip space -> its texture space (posIS = vecVCToISMatrix *
// (posVC - originVC), posVC = PCVCMatrix * clip), and its step there along the view axis,
// from the uniforms vtk.js has just set on its program.
function cameraOf(gl, handle) {
  const get = (name) => {
    const location = gl.getUniformLocation(handle, name);
    if (location === null) throw new Error(`installHalo: vtk.js's volume shader has no uniform ${name}`);
    return gl.getUniform(handle, location);
  };
  const pcvc = get('PCVCMatrix'), vcis = get('volume.vecVCToISMatrix'), origin = get('volume.originVC');
  const affine = new Float64Array(16); // column-major: [vcis, -vcis * origin; 0 0 0 1]
  for (let c = 0; c < 3; ++c) for (let r = 0; r < 3; ++r) affine[c * 4 + r] = vcis[c * 3 + r];
  for (let r = 0; r < 3; ++r) affine[12 + r] = -(vcis[r] * origin[0] + vcis[3 + r] * origin[1] + vcis[6 + r] * origin[2]);
  affine[15] = 1;
  const inverse = new Float32Array(16);
  for (let c = 0; c < 4; ++c)
    for (let r = 0; r < 4; ++r) {
      let sum = 0;
      for (let k = 0; k < 4; ++k) sum += affine[k * 4 + r] * pcvc[c * 4 + k];
      inverse[c * 4 + r] = sum;
    }
  const axis = [vcis[6], vcis[7], vcis[8]]; // the view axis, VC (0, 0, -1), in texture space (up to sign)
  return {
    inverse, sampleDistance: get('sampleDistance'), step: get('sampleDistance') * Math.hypot(axis[0], axis[1], axis[2]),
    size: gl.getParameter(gl.VIEWPORT).slice(2, 4), // vtk.js's render target (its small one while interacting)
  };
}

// What the adapter cannot serve in the mapper and its vtkVolume as they are now: null, or why.
function refusal(mapper, actor) {
  const image = mapper.getInputData();
  const scalars = image && image.getPointData().getScalars();
  if (!scalars) return 'the mapper has no input image with scalars';
  if (scalars.getNumberOfComponents() !== 1)
    return `the volume has ${scalars.getNumberOfComponents()} components; the stages read one value a sample`;
  if (mapper.getBlendMode() !== COMPOSITE_BLEND) return 'the mapper\'s blend mode is not composite: the stages apply to composited samples';
  if (mapper.getClippingPlanes().length) return 'the mapper has clipping planes, which libhalo\'s halo field does not clip';
  const property = actor.getProperty();
  if (typeof property.getUseLabelOutline === 'function' && property.getUseLabelOutline())
    return 'the volume property draws label outlines, which the stages do not serve';
  if (!(property.getScalarOpacityUnitDistance(0) > 0)) return 'the scalar opacity unit distance is not > 0';
  return null;
}

// The vtkVolumes of the render window that draw mapper.
function volumesOf(view, mapper) {
  return renderersOf(view).flatMap((r) => r.getVolumes().filter((v) => v.getMapper() === mapper));
}
function renderersOf(view) {
  const window = typeof view.getRenderable === 'function' ? view.getRenderable() : null;
  return window && typeof window.getRenderers === 'function' ? window.getRenderers() : [];
}

// The size in pixels of the renderer that draws actor (vtk.js's tiled size: its viewport of
// the canvas), or null.
function rendererSize(view, actor) {
  const renderer = renderersOf(view).find((r) => r.getVolumes().includes(actor));
  const node = renderer && view.getViewNodeFor(renderer);
  if (!node || typeof node.getTiledSizeAndOrigin !== 'function') return null;
  const { usize, vsize } = node.getTiledSizeAndOrigin();
  return usize > 0 && vsize > 0 ? [usize, vsize] : null;
}

// The highest free block of count contiguous texture units in vtk.js's manager, reserved;
// [] when there is none.
function reserveUnits(manager, count) {
  for (let top = manager.getNumberOfTextureUnits() - 1; top - count + 1 >= 0; --top) {
    const block = Array.from({ length: count }, (_, i) => top - count + 1 + i);
    if (block.every((u) => !manager.isAllocated(u))) {
      block.forEach((u) => manager.allocateUnit(u));
      return block;
    }
  }
  return [];
}

// The context's drawArrays, taken once for every install on it: { installs: id -> {
// programs, prepareDraw }, owners: program -> id or 0 (not a program of libhalo's stages) }.
// vtk.js hands out its context behind a Proxy (which caches getParameter and binds each
// method it returns): the wrapper goes on the context itself.
const hooks = new WeakMap();
const underlying = (gl) => (typeof gl.__getUnderlyingContext === 'function' ? gl.__getUnderlyingContext() : gl);
function hookContext(proxy) {
  const gl = underlying(proxy);
  let hook = hooks.get(gl);
  // one whose wrapper is no longer the context's, with no install left: made again over
  // whatever drawArrays the context has now
  if (hook && gl.drawArrays !== hook.wrapper && !hook.installs.size) hook = null;
  if (hook) return hook;
  const own = Object.prototype.hasOwnProperty.call(gl, 'drawArrays') ? gl.drawArrays : null;
  hook = { installs: new Map(), owners: new WeakMap(), own };
  hook.wrapper = function drawArrays(mode, first, count) {
    const handle = hook.installs.size ? gl.getParameter(gl.CURRENT_PROGRAM) : null;
    if (handle) {
      let owner = hook.owners.get(handle);
      if (owner === undefined) { // a program not seen yet: whose stages does vtk.js's shader hold?
        const fragment = (gl.getAttachedShaders(handle) || []).find((x) => gl.getShaderParameter(x, gl.SHADER_TYPE) === gl.FRAGMENT_SHADER);
        const text = fragment ? gl.getShaderSource(fragment) : '';
        const match = new RegExp(`${INSTALL_MARK}(\\w+-\\d+)\n`).exec(text);
        // marked, but without the finish piece (another replacement took its anchor)
        owner = match ? { id: match[1], complete: text.includes(`${FINISH_MARK}${match[1]}\n`) } : null;
        hook.owners.set(handle, owner);
      }
      const install = owner && hook.installs.get(owner.id);
      // the drawArrays the context had (another's wrapper, or its own, looked up now)
      const draw = () => (hook.own || Object.getPrototypeOf(gl).drawArrays).call(gl, mode, first, count);
      if (install) {
        install.programs.add(handle);
        if (install.prepareDraw(handle, owner.complete, draw)) return undefined; // drawn by the install (outlines)
      }
    }
    return (hook.own || Object.getPrototypeOf(gl).drawArrays).call(gl, mode, first, count);
  };
  gl.drawArrays = hook.wrapper;
  hooks.set(gl, hook);
  return hook;
}
// The last install on gl removed: its own drawArrays again (unless another wrapped it since,
// whose wrapper then calls libhalo's, which passes every draw through).
function unhookContext(proxy) {
  const gl = underlying(proxy);
  const hook = hooks.get(gl);
  if (!hook || gl.drawArrays !== hook.wrapper) return;
  if (hook.own) gl.drawArrays = hook.own;
  else delete gl.drawArrays;
  hooks.delete(gl);
}

// Outlines' GL objects for a width x height view (made again over old, whose objects go; 0 x
// 0: only freed): volume, the target vtk.js's volume is drawn into (its colour RGBA32F: vtk.js's
// output as it is), whole, an RGBA8 copy of vtk.js's whole image (a blit's target: the canvas
// is RGBA8), and shower, the program that shows a texture (libhalo.mjs's textureShower).
function outlineTargets(gl, old, width, height) {
  if (old) {
    deleteColorTarget(gl, old.volume);
    deleteColorTarget(gl, old.whole);
    if (!width) textureShower(gl, old.shower, false);
  }
  if (!width) return null;
  if (!gl.getExtension('EXT_color_buffer_float')) throw new Error('outlines: this WebGL 2 context cannot render into float textures (EXT_color_buffer_float)');
  return { width, height, volume: colorTarget(gl, gl.RGBA32F, width, height), whole: colorTarget(gl, gl.RGBA8, width, height),
    shower: textureShower(gl, old && old.shower) }; // not after a lost context: made again
}

// Puts the scene's stages into mapper's volume shader. options: view (the
// vtkOpenGLRenderWindow that draws the mapper; required), scene (JSON text or object),
// sceneFile, window ([low, high] of the volume's values that become 0..1; default their
// range), interval (M for halos; default the scene's), allLive, fieldMaxBytes (the cap on
// the halo field; libhalo's default) and imageScale (the halo images at 1/2 or 1/4 of the
// frame per side; without it a field over the cap is linked again at 1/2, then 1/4, with a
// warning: that frame is drawn without the stages, the next with them). Returns { program
// (the one drawn now), set(name, value), remove() }; throws a HaloError or an Error that says why.
export function installHalo(halo, mapper, options = {}) {
  const view = options.view;
  if (!view || typeof view.getViewNodeFor !== 'function' || typeof view.getTextureUnitManager !== 'function')
    throw new Error('installHalo: options.view must be the vtkOpenGLRenderWindow (genericRenderWindow.getApiSpecificRenderWindow())');
  const glMapper = view.getViewNodeFor(mapper);
  if (!glMapper || typeof glMapper.onEvent !== 'function' || typeof glMapper.getShaderTemplate !== 'function')
    throw new Error('installHalo: vtk.js has not drawn this mapper yet: render once before installing the stages');
  if (installed.has(mapper)) throw new Error('installHalo: this mapper already has libhalo\'s stages: remove() them first');
  const shaders = {};
  glMapper.getShaderTemplate(shaders);
  for (const [what, anchor] of [['sample', SAMPLE_ANCHOR], ['finish', FINISH_ANCHOR], ['ray loop', LOOP_ANCHOR]])
    if (!shaders.Fragment || !shaders.Fragment.includes(anchor))
      throw new Error(`installHalo: vtk.js's volume shader has no '${anchor.split('\n')[0]}' (the ${what} anchor): a vtk.js ` +
        `version this adapter does not know (tested: ${SUPPORTED_VERSIONS.join(', ')})`);
  // the vtkVolume drawing the mapper (its property), found again at every draw
  let actor = null;
  const refused = drawnBy();
  if (refused) throw new Error(`installHalo: ${refused}`);
  // null and actor set, or why the mapper cannot be served as it is drawn now
  function drawnBy() {
    const volumes = volumesOf(view, mapper);
    if (volumes.length !== 1)
      return volumes.length ? 'the mapper is drawn by several vtkVolumes: the stages are prepared for one'
        : 'the mapper is in no vtkVolume of the view\'s renderers';
    actor = volumes[0];
    return refusal(mapper, actor);
  }
  const gl = view.getContext();
  let { program, features, outlines } = halo.linkForEngine({ scene: options.scene, sceneFile: options.sceneFile,
    allLive: options.allLive, imageScale: options.imageScale, pieces: VTKJS_NAMES }, 'vtk.js', [FEATURE_BUFFER],
  { outlines: true });
  // libhalo's texture units, reserved in vtk.js's manager: the value copy, the feature
  // buffer (with feature halos), the field's samplers and the march's volume
  // (halo_gl_frame_draw's first_unit on)
  const manager = view.getTextureUnitManager();
  const count = 2 + (features ? 1 : 0) + (program.reflection.samplers || []).length;
  const units = reserveUnits(manager, count);
  if (!units.length) {
    program.destroy();
    throw new Error(`installHalo: vtk.js's texture unit manager has no ${count} free units in a row for libhalo ` +
      `(of ${manager.getNumberOfTextureUnits()})`);
  }
  const valueUnit = units[0], featureUnit = features ? units[1] : -1, firstUnit = units[features ? 2 : 1];
  let value = null;
  try {
    value = valueTexture(halo, gl, mapper.getInputData(), options.window, valueUnit);
  } catch (e) {
    units.forEach((u) => manager.free(u));
    program.destroy();
    throw e;
  }
  let volumeKey = [mapper.getInputData(), mapper.getInputData().getMTime()];
  let version = 0, frame = null, feature = null, own = null; // own: outlines' targets and program
  const warned = new Set();
  const warnOnce = (why) => {
    if (!warned.has(why)) console.warn(`libhalo: ${why}`);
    warned.add(why);
  };
  const spec = mapper.getViewSpecificProperties();
  const setReplacements = (list) => {
    spec.OpenGL = { ...(spec.OpenGL || {}), ShaderReplacements: list }; // a new list: vtk.js rebuilds its shader
    mapper.modified();
  };
  const withoutOurs = () => ((spec.OpenGL && spec.OpenGL.ShaderReplacements) || []).filter((r) => !r.libhalo);
  let enabled = true, lastHandle = null;
  // vtk.js builds its opacity table with its sample distance over the unit distance when the
  // opacity function changes, and only then (its cache is keyed on the function's MTime): the
  // exponent it applied is the one of that time
  let opacity = { of: null, mtime: -1, exponent: 1 };

  // vtk.js's program is built and in use, its uniforms set, its VAO and textures bound: the
  // stages' uniforms and, for halos, the frame's field, before vtk.js's one draw. With
  // outlines the install draws vtk.js's volume itself (drawVtk) and returns true.
  function prepare(handle, drawVtk) {
    // another of vtk.js's programs (it keeps one per shading, lights, sample count...): every
    // live parameter's current value, not only those set since the last upload
    program.upload(gl, handle, { all: handle !== lastHandle });
    lastHandle = handle;
    const key = [mapper.getInputData(), mapper.getInputData().getMTime()];
    // another volume, new values, or the context lost and restored (the copy gone): a new copy
    if (key.some((k, i) => k !== volumeKey[i]) || !gl.isTexture(value.texture)) {
      const fresh = valueTexture(halo, gl, key[0], options.window, valueUnit);
      if (gl.isTexture(value.texture)) gl.deleteTexture(value.texture);
      value = fresh;
      volumeKey = key;
      ++version;
    }
    const previousUnit = gl.getParameter(gl.ACTIVE_TEXTURE);
    gl.activeTexture(gl.TEXTURE0 + valueUnit);
    gl.bindTexture(gl.TEXTURE_3D, value.texture);
    gl.activeTexture(previousUnit);
    gl.uniform1i(gl.getUniformLocation(handle, VALUE_SAMPLER), valueUnit);
    // outline_feature's segmentation, unread (label outlines are refused): a 3D unit of its own type
    gl.uniform1i(gl.getUniformLocation(handle, LABELS_UNIFORM), valueUnit);
    const camera = cameraOf(gl, handle);
    const property = actor.getProperty(), fn = property.getScalarOpacity(0);
    if (fn !== opacity.of || fn.getMTime() !== opacity.mtime)
      opacity = { of: fn, mtime: fn.getMTime(), exponent: camera.sampleDistance / property.getScalarOpacityUnitDistance(0) };
    gl.uniform1f(gl.getUniformLocation(handle, EXPONENT), opacity.exponent);
    if (features) { // the halo buffer of this volume copy, for the view from its centre to the eye
      if (feature && feature.volumeVersion !== version) {
        feature.destroy();
        feature = null;
      }
      if (!feature) {
        feature = halo.featureBuffer(gl, program, { values: value.values, dims: value.dims });
        feature.volumeVersion = version;
      }
      const view = halo.featureView(camera.inverse, value.dims);
      feature.build(view); // at once when it holds this view
      feature.bind(handle, featureUnit); // vtk.js's program stays current
    }
    // the field at the renderer's whole size, also when vtk.js draws at a reduced one while
    // the user interacts: the halos keep their size on the screen (their reach is in pixels)
    const whole = (!outlines && rendererSize(view, actor)) || camera.size;
    gl.uniform2f(gl.getUniformLocation(handle, PIXEL_SCALE), whole[0] / camera.size[0], whole[1] / camera.size[1]);
    const kept = frame;
    frame = null;
    frame = halo.frameOfSize(kept, gl, program, whole[0], whole[1]);
    const desc = { program: handle, volume: value.texture, volumeSize: value.dims, volumeVersion: version,
      framebuffer: gl.getParameter(gl.DRAW_FRAMEBUFFER_BINDING), inverseViewProjection: camera.inverse,
      step: camera.step, interval: options.interval, fieldMaxBytes: options.fieldMaxBytes, firstUnit, draw: () => {} };
    try {
      if (outlines) {
        drawWithOutlines(desc, drawVtk);
        return true;
      }
      // libhalo's field now; vtk.js draws when this returns (the field stays bound on its units)
      frame.draw(desc);
    } catch (e) {
      const smaller = halo.smallerProgram(program, e); // a field over its cap (FIELD_MEMORY, before any draw)
      if (!smaller) throw e;
      relink(smaller, handle);
    }
    return false;
  }

  // The scene linked again at a smaller halo scale (its field fits the cap): vtk.js draws
  // this frame without the stages (its program holds the full scale's), builds its shader
  // with the new pieces at the next render, and is asked for that render at the next
  // animation frame.
  function relink(smaller, handle) {
    console.warn(`libhalo: ${smaller.warning}; this frame without the stages, the next with them`);
    skipStages(handle);
    program.destroy();
    program = smaller.program;
    lastHandle = null;
    frame.destroy();
    frame = null;
    if (feature) feature.destroy();
    feature = null;
    setReplacements([...withoutOurs(), ...replacements(program.pieces, id)]);
    const renderWindow = view.getRenderable();
    if (typeof requestAnimationFrame === 'function' && renderWindow && typeof renderWindow.render === 'function')
      requestAnimationFrame(() => { if (installed.has(mapper) && enabled) renderWindow.render(); });
  }

  // Outlines: vtk.js's volume drawn once into libhalo's target (its colour, RGBA32F, and the
  // stages' outputs, unblended), composited over vtk.js's framebuffer with the blend vtk.js
  // set for it; then the passes after the draw over a copy of vtk.js's whole image, whose
  // result replaces it. vtk.js's state is given back as found.
  function drawWithOutlines(desc, drawVtk) {
    const raw = underlying(gl);
    const viewport = raw.getParameter(raw.VIEWPORT);
    if (viewport[0] || viewport[1])
      throw new Error(`outlines need vtk.js's renderer at the canvas's origin (its viewport starts at ${viewport[0]}, ` +
        `${viewport[1]}): the passes after the draw read whole images`);
    const [width, height] = [viewport[2], viewport[3]];
    if (!own || own.width !== width || own.height !== height || !raw.isTexture(own.volume.texture)) own = outlineTargets(raw, own, width, height);
    const target = desc.framebuffer;
    // vtk.js's whole image: its renderer covers the canvas (not its reduced viewport while the
    // user interacts, a framebuffer of its own holding the volume alone)
    const whole = width === raw.drawingBufferWidth && height === raw.drawingBufferHeight;
    const blend = blendOf(raw);
    frame.draw({ ...desc, framebuffer: own.volume.framebuffer, draw: () => {
      raw.clearBufferfv(raw.COLOR, 0, [0, 0, 0, 0]); // what vtk.js's draw leaves outside its proxy: blends as nothing
      drawVtk();
    } });
    showTexture(raw, own.shower, own.volume.texture, target, viewport, blend); // the volume, as vtk.js would have blended it
    if (!whole) {
      warnOnce(`outlines are left out of the frames vtk.js draws at ${width}x${height} (its reduced viewport while ` +
        `interacting, or a renderer smaller than the canvas's ${raw.drawingBufferWidth}x${raw.drawingBufferHeight}): ` +
        'the passes after the draw read the whole image');
      return;
    }
    const reading = raw.getParameter(raw.READ_FRAMEBUFFER_BINDING), drawing = raw.getParameter(raw.DRAW_FRAMEBUFFER_BINDING);
    raw.bindFramebuffer(raw.READ_FRAMEBUFFER, target); // vtk.js's whole image (resolved when multisampled)
    raw.bindFramebuffer(raw.DRAW_FRAMEBUFFER, own.whole.framebuffer);
    raw.blitFramebuffer(0, 0, width, height, 0, 0, width, height, raw.COLOR_BUFFER_BIT, raw.NEAREST);
    raw.bindFramebuffer(raw.READ_FRAMEBUFFER, reading);
    raw.bindFramebuffer(raw.DRAW_FRAMEBUFFER, drawing);
    const error = raw.getError();
    if (error) throw new Error(`outlines: vtk.js's image could not be copied for the passes after the draw (WebGL error 0x${error.toString(16)})`);
    showTexture(raw, own.shower, frame.post(own.whole.texture), target, viewport, null);
  }

  function release() { // libhalo's GL objects and units (the stages' uniforms in vtk.js's programs stay)
    if (frame) frame.destroy();
    frame = null;
    if (own) outlineTargets(underlying(gl), own, 0, 0);
    own = null;
    if (feature) feature.destroy();
    feature = null;
    if (value) gl.deleteTexture(value.texture);
    value = null;
    units.forEach((u) => manager.free(u));
    units.length = 0;
  }

  // vtk.js's objects are frozen: no method of its mapper can be wrapped. libhalo takes the
  // context's drawArrays instead (one wrapper a context, for every install on it): a draw
  // whose program vtk.js built with this install's stages (its shader holds the install's
  // mark) is prepared first; every other draw goes through untouched.
  function prepareDraw(handle, complete, drawVtk) {
    if (!enabled) return false;
    let drew = false; // vtk.js's volume drawn by the install: not again when it fails after
    try {
      const why = (complete ? null : 'vtk.js built its shader without the finish piece (another shader replacement ' +
        `took its place: '${FINISH_ANCHOR}')`) || drawnBy();
      if (why) throw new Error(why);
      prepared = true;
      return prepare(handle, () => { drew = true; drawVtk(); });
    } catch (e) { // this frame with vtk.js's own samples (the stages skipped), the next without them
      disable(e.message);
      return drew;
    }
  }
  function disable(why) { // vtk.js keeps drawing: without the stages, and a warning
    warnOnce(`the stages are off: ${why}`);
    enabled = false;
    const current = gl.getParameter(gl.CURRENT_PROGRAM);
    for (const handle of programs) { // the stages skipped in every program built with them
      if (!gl.isProgram(handle)) { // vtk.js deleted it (its graphics resources released)
        programs.delete(handle);
        continue;
      }
      skipStages(handle);
    }
    gl.useProgram(gl.isProgram(current) ? current : null);
    setReplacements(withoutOurs());
    release();
  }
  // vtk.js's program handle draws its own samples: the stages skipped (their exponent 0),
  // the samplers each on a unit of their own (samplers of other types on one unit fail the
  // draw). The program is left current.
  function skipStages(handle) {
    const samplers = [VALUE_SAMPLER, ...(features ? [FEATURE_BUFFER] : []), ...(program.reflection.samplers || []).map((x) => x.name)];
    gl.useProgram(handle);
    gl.uniform1f(gl.getUniformLocation(handle, EXPONENT), 0);
    samplers.forEach((name, k) => gl.uniform1i(gl.getUniformLocation(handle, name), units[k] ?? 0));
    gl.uniform1i(gl.getUniformLocation(handle, LABELS_UNIFORM), units[0] ?? 0); // 3D, as the value's
  }
  const programs = new Set(); // vtk.js's programs built with this install's stages
  const hook = hookContext(gl);
  const id = `${MODULE_ID}-${++installs}`;
  hook.installs.set(id, { programs, prepareDraw });
  // the mapper's node says when vtk.js is about to draw it (EndEvent, then its shader, its
  // uniforms and drawArrays): a volume draw that did not reach libhalo's drawArrays (another
  // library's replaced the context's since) is told at the next render
  let prepared = true;
  const subscription = glMapper.onEvent((event) => {
    if (event.type === 'EndEvent' && enabled && mapper.getInputData()) {
      if (!prepared) disable('vtk.js drew the volume without libhalo\'s drawArrays (the context\'s was replaced after ' +
        'installHalo, or vtk.js did not build its shader with the stages)');
      prepared = false;
    }
  });
  try {
    setReplacements([...withoutOurs(), ...replacements(program.pieces, id)]);
  } catch (e) {
    subscription.unsubscribe();
    hook.installs.delete(id);
    if (!hook.installs.size) unhookContext(gl);
    release();
    program.destroy();
    throw e;
  }
  installed.add(mapper);

  return {
    get program() { return program; }, // another after a field over its cap (linked at a smaller scale)
    // a live parameter ("stage.param"): the uniform's new value on the next render
    set(name, v) {
      program.set(name, v);
    },
    // vtk.js's own shader again (on the next render)
    remove() {
      if (!installed.has(mapper)) return;
      installed.delete(mapper);
      subscription.unsubscribe();
      hook.installs.delete(id);
      if (!hook.installs.size) unhookContext(gl);
      if (enabled) setReplacements(withoutOurs());
      release();
      program.destroy();
    },
  };
}
