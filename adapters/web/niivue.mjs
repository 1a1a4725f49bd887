// libhalo in NiiVue (docs/hosts/web.md): NiiVue's volume renderer has no public shader hook,
// so installHalo wraps the render shader NiiVue builds. It reads the shader's text back from
// WebGL, puts a scene's stages into its ray loop (linked as pieces, docs/composers.md),
// builds it as a NiiVue Shader, and wraps the instance's drawImage3D so that libhalo's GL
// runtime (WebAssembly) draws NiiVue's volume: for per-sample stages it sets their camera
// and lets NiiVue draw; for volumetric halos (host contract 3) it computes the frame's
// halo field first, over a float copy of the background volume in NiiVue's RAS texture
// space, and then lets NiiVue draw once.
//
//   import { Niivue } from '@niivue/niivue';
//   import libhalo from '@libhalo/web';
//   import { installHalo } from '@libhalo/web/niivue';
//   const nv = new Niivue(); await nv.attachToCanvas(canvas);
//   await nv.loadVolumes([{ url: 'head.nii.gz' }]); nv.setSliceType(nv.sliceTypeRender);
//   const stages = installHalo(await libhalo(), nv, { scene: sceneJson });
//   nv.drawScene();                          // NiiVue draws as always
//   stages.remove();                         // NiiVue's own shader again
//
// Supported: NiiVue 0.69 (SUPPORTED_VERSIONS), its default volume shader (no gradient
// shading: with nv.setVolumeRenderIllumination(>0) NiiVue draws through another shader and
// the stages are off, with a warning once). What the stages see: the sample's position in
// NiiVue's texture space (samplePos), the background volume's value (cal_min..cal_max to
// 0..1, read from the adapter's float copy), its gradient (central differences of that
// value), and NiiVue's colour (colormap and opacity per voxel step). For halo scenes the
// adapter turns off NiiVue's fast empty-space pass (halos land in empty space). Feature
// halos: libhalo's runtime splats the halo buffer from the float copy (again when it is made
// anew), for the view from the volume's centre to the eye in voxel space (again when it
// turns), bound two units below firstUnit. Outlines (the stages' extra outputs and the
// passes after the draw): NiiVue's volume is drawn into libhalo's target (its colour, RGBA32F,
// and the outputs, unblended; NiiVue's rays run to their end, the outputs need hidden samples
// too), put over NiiVue's framebuffer with the blend NiiVue set for it, and the passes after
// the draw run over a copy of the 3D view's image, whose result replaces it; what NiiVue
// draws after its volume (crosshairs, meshes, the orientation cube) comes over that.

import { blendOf, colorTarget, deleteColorTarget, setBlend, showTexture, textureShower } from './libhalo.mjs';

export const SUPPORTED_VERSIONS = Object.freeze(['0.69.0']);

// Where the pieces go in NiiVue's render shader (fragRenderShader of its shader-srcs.ts)
const ANCHORS = Object.freeze({
  declarations: 'out vec4 fColor;\n',
  sample: 'vec4 colorSample = texture(volume, samplePos.xyz);\n',
  finish: '\tif (firstHit.a < len)\n\t\tbackNearest = firstHit.a;',
  fastPass: 'float val = texture(volume, samplePos.xyz).a;',
});
// With outlines: the fragment output declared at location 0 (the outputs take 1 on), and the
// ray's early termination waits for HALO_RAY_MAY_END (docs/host-contract.md)
const OUTPUT = 'out vec4 fColor;\n';
const TERMINATION = 'if ( colAcc.a > earlyTermination )\n';
const MAIN = 'void main() {';

const VALUE_SAMPLER = 'halo_niivue_value';
const FEATURE_BUFFER = 'halo_host_feature_buffer'; // the feature_halo stage's host uniform
const ORIGIN = 'halo_niivue_origin'; // the 3D view's lower left corner in the canvas (gl.VIEWPORT)
const INSTALLED = Symbol('libhalo');

// A program of the adapter's (a NiiVue Shader's, built with the stages) and its shaders,
// which NiiVue's Shader leaves attached.
function deleteStaged(gl, program) {
  for (const shader of gl.getAttachedShaders(program) || []) gl.deleteShader(shader);
  gl.deleteProgram(program);
}

// NiiVue's names for the sample piece; view and depth come from the camera libhalo sets.
export const NIIVUE_NAMES = Object.freeze({
  position: 'samplePos.xyz',
  value: `texture(${VALUE_SAMPLER}, samplePos.xyz).r`,
  volume: VALUE_SAMPLER,
  fragcoord: `(gl_FragCoord.xy - ${ORIGIN})`,
  color: 'colorSample',
});

// The values NiiVue gave its shader's uniforms (its samplers' units are set once, when it
// builds the shader), copied to the same names in the staged shader.
function copyUniforms(gl, from, to) {
  const current = gl.getParameter(gl.CURRENT_PROGRAM);
  gl.useProgram(to);
  const count = gl.getProgramParameter(from, gl.ACTIVE_UNIFORMS);
  for (let i = 0; i < count; ++i) {
    const u = gl.getActiveUniform(from, i);
    const base = u.name.replace(/\[0\]$/, '');
    for (let e = 0; e < u.size; ++e) {
      const name = u.size > 1 ? `${base}[${e}]` : u.name;
      const source = gl.getUniformLocation(from, name), target = gl.getUniformLocation(to, name);
      if (!source || !target) continue;
      const v = gl.getUniform(from, source);
      switch (u.type) {
        case gl.FLOAT: gl.uniform1f(target, v); break;
        case gl.FLOAT_VEC2: gl.uniform2fv(target, v); break;
        case gl.FLOAT_VEC3: gl.uniform3fv(target, v); break;
        case gl.FLOAT_VEC4: gl.uniform4fv(target, v); break;
        case gl.FLOAT_MAT4: gl.uniformMatrix4fv(target, false, v); break;
        case gl.FLOAT_MAT3: gl.uniformMatrix3fv(target, false, v); break;
        case gl.INT_VEC2: case gl.BOOL_VEC2: gl.uniform2iv(target, Int32Array.from(v, Number)); break;
        case gl.INT_VEC3: case gl.BOOL_VEC3: gl.uniform3iv(target, Int32Array.from(v, Number)); break;
        case gl.INT_VEC4: case gl.BOOL_VEC4: gl.uniform4iv(target, Int32Array.from(v, Number)); break;
        default: gl.uniform1i(target, Number(v)); // int, bool and the samplers
      }
    }
  }
  gl.useProgram(current);
}

function sourcesOf(gl, program) {
  const shaders = gl.getAttachedShaders(program) || [];
  const source = (type) => {
    const s = shaders.find((x) => gl.getShaderParameter(x, gl.SHADER_TYPE) === type);
    return s ? gl.getShaderSource(s) : null;
  };
  return { vertex: source(gl.VERTEX_SHADER), fragment: source(gl.FRAGMENT_SHADER) };
}

// a 4x4 column-major product and inverse (gl-matrix's layout)
function multiply(a, b) {
  const out = new Float64Array(16);
  for (let c = 0; c < 4; ++c)
    for (let r = 0; r < 4; ++r) {
      let sum = 0;
      for (let k = 0; k < 4; ++k) sum += a[k * 4 + r] * b[c * 4 + k];
      out[c * 4 + r] = sum;
    }
  return out;
}

function invert(m) {
  // Gauss-Jordan on the rows of the column-major matrix's transpose, in double precision
  const a = [];
  for (let r = 0; r < 4; ++r) a.push([m[r], m[4 + r], m[8 + r], m[12 + r], r === 0 ? 1 : 0, r === 1 ? 1 : 0, r === 2 ? 1 : 0, r === 3 ? 1 : 0]);
  for (let c = 0; c < 4; ++c) {
    let pivot = c;
    for (let r = c + 1; r < 4; ++r) if (Math.abs(a[r][c]) > Math.abs(a[pivot][c])) pivot = r;
    if (!(Math.abs(a[pivot][c]) > 0)) throw new Error('installHalo: NiiVue\'s view matrix is singular');
    [a[c], a[pivot]] = [a[pivot], a[c]];
    const p = a[c][c];
    for (let k = 0; k < 8; ++k) a[c][k] /= p;
    for (let r = 0; r < 4; ++r)
      if (r !== c) {
        const f = a[r][c];
        for (let k = 0; k < 8; ++k) a[r][k] -= f * a[c][k];
      }
  }
  const out = new Float64Array(16);
  for (let r = 0; r < 4; ++r) for (let c = 0; c < 4; ++c) out[c * 4 + r] = a[r][4 + c];
  return out;
}

// The background volume in NiiVue's RAS texture order, cal_min..cal_max to 0..1 (R32F).
function valueTexture(halo, gl, image, unit) {
  const hdr = image.hdr || {};
  return halo.valueTexture(gl, image.img2RAS(image.frame4D || 0), image.dimsRAS.slice(1, 4),
    { low: image.cal_min, high: image.cal_max, slope: hdr.scl_slope || 1, intercept: hdr.scl_inter || 0 }, unit);
}

// NiiVue's ray step in texture space: one voxel along the ray, 1 / |dims (x) d| for the
// unit direction d (its sliceSize); for the field, the view axis's (the centre's ray).
function niivueStep(inverse, dims) {
  const at = (z) => {
    const p = [0, 1, 2, 3].map((r) => inverse[8 + r] * z + inverse[12 + r]);
    return [p[0] / p[3], p[1] / p[3], p[2] / p[3]];
  };
  const near = at(-1), far = at(1);
  const d = [far[0] - near[0], far[1] - near[1], far[2] - near[2]];
  const length = Math.hypot(d[0], d[1], d[2]);
  const voxels = Math.hypot(d[0] * dims[0], d[1] * dims[1], d[2] * dims[2]) / length;
  return 1 / voxels;
}

// NiiVue's texture space -> its mm space (the render cube's vertices), column-major.
function textureToMm(image) {
  const dims = image.dimsRAS;
  const at = (t) => image.vox2mm([t[0] * dims[1] - 0.5, t[1] * dims[2] - 0.5, t[2] * dims[3] - 0.5], image.matRAS);
  const o = at([0, 0, 0]), x = at([1, 0, 0]), y = at([0, 1, 0]), z = at([0, 0, 1]);
  return Float64Array.of(x[0] - o[0], x[1] - o[1], x[2] - o[2], 0, y[0] - o[0], y[1] - o[1], y[2] - o[2], 0,
    z[0] - o[0], z[1] - o[1], z[2] - o[2], 0, o[0], o[1], o[2], 1);
}

// Outlines' GL objects for a width x height 3D view drawn into target (null: the canvas),
// made again over old when they differ (0 x 0: old's freed, null): volume, the target NiiVue's
// volume is drawn into (its colour RGBA32F, as its shader writes it; libhalo attaches the
// outputs); view, the 3D view's image copied in target's format (RGBA8, or RGBA32F for a float
// target), which the passes after the draw read (whole: copyView's); shower, the program that
// shows a texture.
function outlineTargets(gl, old, width, height, target) {
  let float = false;
  if (width && target) {
    const reading = gl.getParameter(gl.READ_FRAMEBUFFER_BINDING);
    gl.bindFramebuffer(gl.READ_FRAMEBUFFER, target);
    float = gl.getFramebufferAttachmentParameter(gl.READ_FRAMEBUFFER, gl.COLOR_ATTACHMENT0,
      gl.FRAMEBUFFER_ATTACHMENT_COMPONENT_TYPE) === gl.FLOAT;
    gl.bindFramebuffer(gl.READ_FRAMEBUFFER, reading);
  }
  if (old && old.width === width && old.height === height && old.float === float && gl.isTexture(old.volume.texture))
    return old;
  if (old) {
    deleteColorTarget(gl, old.volume);
    deleteColorTarget(gl, old.view);
    deleteColorTarget(gl, old.whole);
    if (!width) textureShower(gl, old.shower, false);
  }
  if (!width) return null;
  if (!gl.getExtension('EXT_color_buffer_float'))
    throw new Error('outlines: this WebGL 2 context cannot render into float textures (EXT_color_buffer_float)');
  return { width, height, float, volume: colorTarget(gl, gl.RGBA32F, width, height),
    view: colorTarget(gl, float ? gl.RGBA32F : gl.RGBA8, width, height), shower: textureShower(gl, old && old.shower) };
}

// The 3D view [x, y, width, height] of target (null: the canvas) copied into own.view; a
// multisampled canvas (NiiVue's antialias) is resolved only by a blit of the same rectangle,
// so a view off the origin goes through own.whole, the size of the view's top right corner.
// Returns the WebGL error, 0 when copied; the bindings it changes given back.
function copyView(gl, own, target, [x, y, width, height]) {
  const reading = gl.getParameter(gl.READ_FRAMEBUFFER_BINDING), drawing = gl.getParameter(gl.DRAW_FRAMEBUFFER_BINDING);
  for (let e = gl.getError(), n = 0; e && n < 8; e = gl.getError(), ++n) // not ours: said, not taken for ours
    console.warn(`libhalo: found WebGL error 0x${e.toString(16)} pending from NiiVue's own calls`);
  gl.bindFramebuffer(gl.READ_FRAMEBUFFER, target);
  if (x || y) {
    if (!own.whole || own.wholeWidth !== x + width || own.wholeHeight !== y + height) {
      deleteColorTarget(gl, own.whole);
      own.whole = colorTarget(gl, own.float ? gl.RGBA32F : gl.RGBA8, x + width, y + height);
      own.wholeWidth = x + width;
      own.wholeHeight = y + height;
    }
    gl.bindFramebuffer(gl.DRAW_FRAMEBUFFER, own.whole.framebuffer);
    gl.blitFramebuffer(0, 0, x + width, y + height, 0, 0, x + width, y + height, gl.COLOR_BUFFER_BIT, gl.NEAREST);
    gl.bindFramebuffer(gl.READ_FRAMEBUFFER, own.whole.framebuffer);
  }
  gl.bindFramebuffer(gl.DRAW_FRAMEBUFFER, own.view.framebuffer);
  gl.blitFramebuffer(x, y, x + width, y + height, 0, 0, width, height, gl.COLOR_BUFFER_BIT, gl.NEAREST);
  gl.bindFramebuffer(gl.READ_FRAMEBUFFER, reading);
  gl.bindFramebuffer(gl.DRAW_FRAMEBUFFER, drawing);
  return gl.getError();
}

// Puts the scene's stages into nv's volume render shader. options: scene (JSON text or
// object), sceneFile, interval (M for halos; default the scene's), firstUnit (libhalo's
// textures from this unit on: 20; the value copy is one below, the feature buffer two), allLive,
// fieldMaxBytes (the cap on the halo field; libhalo's default) and imageScale (the halo
// images at 1/2 or 1/4 of the frame per side; without it a field over the cap is linked
// again at 1/2, then 1/4, and the frame drawn with it, with a warning). Returns { program
// (the one drawn now), set(name, value), remove() }; throws a HaloError or an Error that says why.
export function installHalo(halo, nv, options = {}) {
  const gl = nv.gl;
  if (!gl || !nv.renderVolumeShader || !nv.back)
    throw new Error('installHalo: attach NiiVue to a canvas and load a volume first (nv.renderVolumeShader, nv.back)');
  const shader = nv.renderVolumeShader;
  const { vertex, fragment } = sourcesOf(gl, shader.program);
  for (const [what, anchor] of Object.entries(ANCHORS))
    if (!fragment || !fragment.includes(anchor))
      throw new Error(`installHalo: NiiVue's render shader has no '${anchor.trim()}' (the ${what} anchor): a NiiVue ` +
        `version this adapter does not know (supported: ${SUPPORTED_VERSIONS.join(', ')})`);
  if (nv[INSTALLED]) throw new Error('installHalo: this NiiVue already has libhalo\'s stages: remove() them first');
  let { program, field, features, outlines } = halo.linkForEngine({ scene: options.scene, sceneFile: options.sceneFile,
    allLive: options.allLive, imageScale: options.imageScale, pieces: NIIVUE_NAMES }, 'NiiVue', [FEATURE_BUFFER],
  { outlines: true });
  const missing = [OUTPUT, TERMINATION, MAIN].find((anchor) => !fragment.includes(anchor));
  if (outlines && missing) {
    program.destroy();
    throw new Error(`installHalo: NiiVue's render shader has no '${missing.trim()}' ` +
      `(where outlines change it): a NiiVue version this adapter does not know (supported: ${SUPPORTED_VERSIONS.join(', ')})`);
  }
  // NiiVue's shader with the program's pieces, NiiVue's uniform values copied from its
  // program from, the live parameters' values (all that were set) uploaded
  const stage = (from) => {
    let text = fragment
      .replace(ANCHORS.declarations, `${ANCHORS.declarations}uniform highp sampler3D ${VALUE_SAMPLER};\n` +
        `uniform vec2 ${ORIGIN};\n${program.pieces.declarations || ''}\n`)
      .replace(ANCHORS.sample, `${ANCHORS.sample}${program.pieces.sample || ''}\n`)
      .replace(ANCHORS.finish, `${program.pieces.finish || ''}\n${ANCHORS.finish}`);
    if (field) // halos land in empty space: no fast pass to the first opaque sample
      text = text.replace(ANCHORS.fastPass, 'float val = 1.0; // libhalo: halos land in empty space');
    if (outlines) { // the outputs at locations 1 on; they need every sample of a ray, hidden ones too
      text = text.replace(OUTPUT, `layout(location = 0) ${OUTPUT}`)
        .replace(TERMINATION, 'if ( colAcc.a > earlyTermination && HALO_RAY_MAY_END != 0 ) // libhalo\n');
      // a ray NiiVue ends before its loop (too short, nothing to sample) writes the outputs too
      // (as none: unwritten, a draw buffer's value is undefined, and a feature appeared there)
      const main = text.indexOf(MAIN), end = text.indexOf(ANCHORS.finish, main);
      text = text.slice(0, main) + text.slice(main, end).replace(/\breturn;/g, `{ ${(program.pieces.finish || '').trim()} return; }`) +
        text.slice(end);
    }
    let made;
    try {
      made = new shader.constructor(gl, vertex, text);
    } catch (e) {
      throw new Error(`installHalo: NiiVue could not build its shader with the stages (${e.message}; the compile log ` +
        'on the console: program.mapLog maps its lines to the modules)');
    }
    const current = gl.getParameter(gl.CURRENT_PROGRAM);
    try {
      copyUniforms(gl, from, made.program);
      gl.useProgram(made.program);
      program.upload(gl, made.program, { all: true });
    } catch (e) {
      deleteStaged(gl, made.program);
      throw e;
    } finally {
      gl.useProgram(gl.isProgram(current) ? current : null);
    }
    return made;
  };
  // everything that can fail, before NiiVue is touched; undone on failure
  let staged = null, value = null;
  const firstUnit = options.firstUnit || 20;
  try {
    if (firstUnit + 4 > gl.getParameter(gl.MAX_COMBINED_TEXTURE_IMAGE_UNITS))
      throw new Error(`installHalo: firstUnit ${firstUnit} leaves too few of this context's texture units for libhalo's`);
    staged = stage(shader.program);
    value = valueTexture(halo, gl, nv.back, firstUnit - 1);
  } catch (e) {
    if (value) gl.deleteTexture(value.texture);
    if (staged) deleteStaged(gl, staged.program);
    program.destroy();
    throw e;
  }
  const original = nv.renderVolumeShader;
  const ownDraw = Object.prototype.hasOwnProperty.call(nv, 'drawImage3D') ? nv.drawImage3D : null;
  const niivueDraw = ownDraw || Object.getPrototypeOf(nv).drawImage3D;
  let frame = null, feature = null, warned = new Set(), version = 0;
  let lastView = null; // the camera of the last frame drawn with the stages (the view getter)
  let own = null; // outlines: libhalo's target for NiiVue's volume, the copy of the 3D view, the shower
  let relinkFailed = false; // a field over its cap could not be linked again: no more tries
  let volumeKey = [nv.back, nv.back.cal_min, nv.back.cal_max, nv.back.frame4D];
  let mmFromTexture = textureToMm(nv.back);
  const warnOnce = (why) => {
    if (!warned.has(why)) console.warn(`libhalo: ${why}`);
    warned.add(why);
  };
  nv.renderVolumeShader = staged;
  if (nv.renderShader === original) nv.renderShader = staged;
  nv[INSTALLED] = true;
  nv.drawImage3D = function (mvpMatrix, azimuth, elevation) {
    const draw = () => niivueDraw.call(nv, mvpMatrix, azimuth, elevation);
    if (nv.renderShader !== staged || nv.uiData?.mouseDepthPicker) {
      if (nv.renderShader !== staged) warnOnce('NiiVue draws with another shader (illumination or slices in the render): the stages are off');
      return draw();
    }
    // the background volume changed (another volume, its window, its 4D frame), or the
    // context was lost and restored (the copy went with it): a new copy
    const key = [nv.back, nv.back.cal_min, nv.back.cal_max, nv.back.frame4D];
    if (key.some((k, i) => k !== volumeKey[i]) || !gl.isTexture(value.texture)) {
      const fresh = valueTexture(halo, gl, nv.back, firstUnit - 1);
      if (gl.isTexture(value.texture)) gl.deleteTexture(value.texture);
      value = fresh;
      mmFromTexture = textureToMm(nv.back);
      volumeKey = key;
      ++version;
    }
    // the 3D view's rectangle of the canvas (a quadrant in NiiVue's multiplanar layout):
    // the field is made at its size and read at the fragment's place in it
    const [x, y, width, height] = gl.getParameter(gl.VIEWPORT);
    let redraw = null; // the scene linked at a smaller halo scale: its field fits the cap
    try {
      const kept = frame;
      frame = null;
      frame = halo.frameOfSize(kept, gl, program, width, height);
    } catch (e) {
      warnOnce(`the stages are off: ${e.message}`);
      return drawAlone(draw);
    }
    // the value copy on its unit (NiiVue binds its own textures on 0-10 itself)
    const previousUnit = gl.getParameter(gl.ACTIVE_TEXTURE);
    gl.activeTexture(gl.TEXTURE0 + firstUnit - 1);
    const previous = gl.getParameter(gl.TEXTURE_BINDING_3D);
    gl.bindTexture(gl.TEXTURE_3D, value.texture);
    const current = gl.getParameter(gl.CURRENT_PROGRAM);
    gl.useProgram(staged.program);
    gl.uniform1i(gl.getUniformLocation(staged.program, VALUE_SAMPLER), firstUnit - 1);
    // with outlines NiiVue's volume is drawn at the origin of libhalo's target
    gl.uniform2f(gl.getUniformLocation(staged.program, ORIGIN), outlines ? 0 : x, outlines ? 0 : y);
    gl.useProgram(current);
    gl.activeTexture(previousUnit);
    const dims = value.dims;
    const inverse = invert(multiply(mvpMatrix, mmFromTexture));
    const featureUnit = firstUnit - 2;
    gl.activeTexture(gl.TEXTURE0 + featureUnit);
    const previousFeature = gl.getParameter(gl.TEXTURE_BINDING_3D);
    gl.activeTexture(previousUnit);
    try {
      if (features) { // the halo buffer of this copy, for the view from its centre to the eye
        if (feature && feature.volumeVersion !== version) {
          feature.destroy();
          feature = null;
        }
        if (!feature) {
          feature = halo.featureBuffer(gl, program, { values: value.values, dims });
          feature.volumeVersion = version;
        }
        const view = halo.featureView(inverse, dims);
        feature.build(view); // at once when it holds this view
        feature.bind(staged.program, featureUnit);
        gl.useProgram(current);
      }
      const target = gl.getParameter(gl.DRAW_FRAMEBUFFER_BINDING);
      if (outlines) {
        own = outlineTargets(gl, own, width, height, target);
        if ((nv.meshes && nv.meshes.length) || nv.opts.show3Dcrosshair)
          warnOnce('outlines: NiiVue\'s volume is drawn into libhalo\'s target, which keeps no depth: its meshes and 3D ' +
            'crosshair are not hidden behind the volume\'s surface in these frames');
      }
      let blend = null; // the blend NiiVue set for its volume (outlines)
      const drawOutlined = () => { // NiiVue's volume into libhalo's target, unblended, over transparent black
        gl.clearBufferfv(gl.COLOR, 0, [0, 0, 0, 0]);
        const viewport = gl.getParameter(gl.VIEWPORT);
        const ownDrawElements = Object.prototype.hasOwnProperty.call(gl, 'drawElements') ? gl.drawElements : null;
        gl.drawElements = function drawElements(...args) { // NiiVue turns its blend on just before
          blend = blendOf(gl);
          gl.disable(gl.BLEND); // one blend for all draw buffers: the outputs are written as they are
          try {
            return (ownDrawElements || Object.getPrototypeOf(gl).drawElements).apply(gl, args);
          } finally {
            setBlend(gl, blend);
          }
        };
        gl.viewport(0, 0, width, height);
        try {
          draw();
        } finally {
          if (ownDrawElements) gl.drawElements = ownDrawElements;
          else delete gl.drawElements;
          gl.viewport(...viewport);
        }
      };
      const camera = Object.freeze({ inverseViewProjection: Float64Array.from(inverse), step: niivueStep(inverse, dims),
        width, height });
      frame.draw({
        program: staged.program, volume: value.texture, volumeSize: dims, volumeVersion: version,
        framebuffer: outlines ? own.volume.framebuffer : target, inverseViewProjection: Float32Array.from(inverse),
        step: camera.step, interval: options.interval, fieldMaxBytes: options.fieldMaxBytes, firstUnit,
        draw: outlines ? drawOutlined : draw,
      });
      lastView = camera;
      if (outlines && blend) { // NiiVue drew: its volume as it would have blended it, then the passes over the view
        const view = [x, y, width, height];
        showTexture(gl, own.shower, own.volume.texture, target, view, blend);
        const error = copyView(gl, own, target, view);
        if (error) // the volume is drawn: this frame goes on without its outlines, said once
          warnOnce(`outlines are left out: NiiVue's image could not be copied for the passes after the draw (WebGL error 0x${error.toString(16)})`);
        else
          showTexture(gl, own.shower, frame.post(own.view.texture), target, view, null);
      }
    } catch (e) {
      let smaller = null;
      try { // not again after a relink that failed: the stages stay off with their one warning
        smaller = relinkFailed ? null : halo.smallerProgram(program, e);
      } catch (again) {
        relinkFailed = true;
        e = again;
      }
      if (smaller) // the field over its cap: the scene at a smaller halo scale
        redraw = smaller;
      else { // NiiVue keeps drawing: without the stages, and a warning
        warnOnce(`the stages are off: ${e.message}`);
        drawAlone(draw);
      }
    } finally {
      gl.activeTexture(gl.TEXTURE0 + firstUnit - 1);
      gl.bindTexture(gl.TEXTURE_3D, previous);
      gl.activeTexture(gl.TEXTURE0 + featureUnit);
      gl.bindTexture(gl.TEXTURE_3D, previousFeature);
      gl.activeTexture(previousUnit);
    }
    if (redraw) { // NiiVue's shader built again with the smaller scale's pieces; this frame drawn with it
      const old = program, oldStaged = staged;
      program = redraw.program;
      try {
        staged = stage(oldStaged.program);
      } catch (e) {
        program.destroy();
        program = old;
        relinkFailed = true;
        warnOnce(`the stages are off: ${redraw.warning}; but NiiVue's shader with the new pieces: ${e.message}`);
        return drawAlone(draw);
      }
      console.warn(`libhalo: ${redraw.warning}`);
      if (nv.renderShader === oldStaged) nv.renderShader = staged;
      nv.renderVolumeShader = staged;
      if (gl.getParameter(gl.CURRENT_PROGRAM) === oldStaged.program) gl.useProgram(staged.program);
      deleteStaged(gl, oldStaged.program);
      old.destroy();
      if (feature) feature.destroy();
      feature = null;
      frame.destroy();
      frame = null;
      return nv.drawImage3D(mvpMatrix, azimuth, elevation);
    }
  };
  // one frame with NiiVue's own shader (its uniforms as NiiVue last set them on the staged one)
  function drawAlone(draw) {
    copyUniforms(gl, staged.program, original.program);
    nv.renderShader = original;
    try {
      draw();
    } finally {
      nv.renderShader = staged;
    }
  }
  return {
    get program() { return program; }, // another after a field over its cap (linked at a smaller scale)
    // the camera libhalo's runtime drew the last frame with: { inverseViewProjection (clip
    // space -> NiiVue's texture space, column-major), step (texture units), width, height (the
    // 3D view's) }, null before the first; to draw the same view elsewhere
    get view() { return lastView; },
    // a live parameter ("stage.param"): the uniform's new value on the next draw
    set(name, v) {
      program.set(name, v);
      const current = gl.getParameter(gl.CURRENT_PROGRAM);
      gl.useProgram(staged.program);
      program.upload(gl, staged.program);
      gl.useProgram(current);
    },
    // NiiVue's own shader and drawImage3D again, with the uniform values NiiVue set meanwhile
    remove() {
      if (!nv[INSTALLED]) return;
      copyUniforms(gl, staged.program, original.program);
      if (ownDraw) nv.drawImage3D = ownDraw;
      else delete nv.drawImage3D;
      if (nv.renderShader === staged) nv.renderShader = original;
      nv.renderVolumeShader = original;
      delete nv[INSTALLED];
      if (feature) feature.destroy();
      feature = null;
      if (frame) frame.destroy();
      frame = null;
      if (own) outlineTargets(gl, own, 0, 0, null);
      own = null;
      gl.deleteTexture(value.texture);
      if (gl.getParameter(gl.CURRENT_PROGRAM) === staged.program) gl.useProgram(original.program);
      deleteStaged(gl, staged.program);
      program.destroy();
    },
  };
}
