// libhalo for the web: the linker, modules, scenes, reflection, live parameters and line
// map of the C library, in WebAssembly (dist/libhalo-core.mjs, built by emscripten from
// the same sources). docs/hosts/web.md.
//
//   import libhalo from '@libhalo/web';
//   const halo = await libhalo();
//   const program = halo.link({ scene: sceneJson, host: fragmentSource });   // GLSL ES 3.00
//   gl.shaderSource(shader, program.source);
//   program.set('tone_shading.k_ta', 0.4);      // a live parameter
//   program.upload(gl, glProgram);              // the live parameters' uniforms
//
// Host contract 3 (oneDraw: volumetric halos in one draw of a single-pass ray caster):
//   const frame = halo.frame(gl, program, { width, height });   // libhalo's GL runtime
//   frame.draw({ program: glProgram, volume: volumeTexture, volumeSize: [nx, ny, nz],
//                inverseViewProjection, step, framebuffer, draw: () => gl.drawArrays(...) });
//
// Errors are HaloError exceptions: message "file:line:col: text", with .diagnostics (every
// one, as {severity, id, file, line, column, message, source}).
import haloCore from './dist/libhalo-core.mjs';

export class HaloError extends Error {
  constructor(diagnostics, fallback) {
    const errors = diagnostics.filter((d) => d.severity === 'error');
    const first = errors[0] || diagnostics[0];
    super(first ? HaloError.format(first) : fallback);
    this.name = 'HaloError';
    this.diagnostics = diagnostics;
    if (first) {
      this.file = first.file;
      this.line = first.line;
      this.column = first.column;
      this.id = first.id;
    }
  }

  // "file:line:col: message" (as the C library prints it), "file:line:", or the message alone.
  static format(d) {
    const where = d.file ? `${d.file}:${d.line ? `${d.line}:${d.column ? `${d.column}:` : ''}` : ''} ` : '';
    return `${where}${d.message}`;
  }
}

const PIECES = { declarations: 0, sample: 1, finish: 2 };

class Program {
  constructor(halo, handle) {
    this._halo = halo;
    this._handle = handle;
    const core = halo._core;
    this.source = core.UTF8ToString(core._halo_web_program_source(handle));
    this.reflection = JSON.parse(core.UTF8ToString(core._halo_web_program_reflect(handle)));
    this.pieces = {};
    for (const [name, index] of Object.entries(PIECES)) {
      const text = core.UTF8ToString(core._halo_web_program_piece(handle, index));
      if (text) this.pieces[name] = text;
    }
    this._values = new Map(); // "stage.param" -> values set since the last upload
    this._current = new Map(); // "stage.param" -> every value set, for a program built again
  }

  _live() {
    if (!this._handle) throw new HaloError([], 'the program was destroyed');
  }

  // A reflected type as GLSL declares it: 'channels' (a halo parameter, one value a halo
  // channel) is float, vec2, vec3 or vec4 by the program's channel count.
  _glslType(type) {
    if (type !== 'channels') return type;
    const n = this.reflection.channels || 1;
    return n === 1 ? 'float' : `vec${n}`;
  }

  // Sets a live parameter ("stage.param", or stage and param): a number, a boolean or an
  // array of numbers (vectors, arrays). Refused parameters throw a HaloError.
  set(name, a, b) {
    this._live();
    let stage, param, value;
    if (b === undefined) {
      const dot = String(name).indexOf('.');
      if (dot < 0) throw new HaloError([], `set: '${name}' is not stage.param`);
      stage = name.slice(0, dot);
      param = name.slice(dot + 1);
      value = a;
    } else {
      [stage, param, value] = [name, a, b];
    }
    const values = (Array.isArray(value) ? value.flat(2) : [value]).map((v) => (typeof v === 'boolean' ? +v : v));
    if (!values.every((v) => typeof v === 'number')) throw new HaloError([], `set ${stage}.${param}: values must be numbers`);
    // the C side counts elements (a vec3 is one): the components from the reflection
    const entry = [...(this.reflection.uniforms || []), ...(this.reflection.constants || [])]
      .find((u) => u.stage === stage && u.param === param);
    const components = entry ? componentsOf(this._glslType(entry.type).replace(/\[\d+\]$/, '')) : 1;
    if (values.length % components)
      throw new HaloError([], `set ${stage}.${param}: ${values.length} numbers are not whole ${this._glslType(entry.type)} elements`);
    const core = this._halo._core;
    const pointer = core._malloc(Math.max(values.length, 1) * 8);
    try {
      core.HEAPF64.set(values, pointer / 8);
      const count = values.length / components;
      const ok = this._halo._withStrings([stage, param], ([s, p]) => core._halo_web_program_set(this._handle, s, p, pointer, count));
      if (!ok) throw this._halo._error(`set ${stage}.${param} failed`);
    } finally {
      core._free(pointer);
    }
    this._values.set(`${stage}.${param}`, values);
    this._current.set(`${stage}.${param}`, values);
  }

  // The uniforms of the live parameters set (all of them on the first call, or with all:
  // an engine's program built again) into the WebGL program, which must be in use:
  // gl.uniform* by the reflection's types.
  upload(gl, glProgram, { all = false } = {}) {
    this._live();
    for (const u of this.reflection.uniforms || []) { // the live parameters
      const key = `${u.stage}.${u.param}`;
      const values = this._values.get(key) || (this._uploaded && !all ? null : this._current.get(key) || u.value);
      if (!values) continue;
      const array = /^(\w+)\[\d+\]$/.exec(u.type);
      const type = this._glslType(array ? array[1] : u.type);
      const location = gl.getUniformLocation(glProgram, u.name);
      if (location !== null) uploadUniform(gl, location, type, values);
      if (array) { // an array parameter's element count: NAME_count
        const count = gl.getUniformLocation(glProgram, `${u.name}_count`);
        if (count !== null) gl.uniform1i(count, Math.floor(values.length / componentsOf(type)));
      }
    }
    this._values.clear();
    this._uploaded = true;
  }

  // The origin of a line of the linked source (or of a piece: 'declarations', 'sample',
  // 'finish'): {file, line}, the module, host or '<libhalo>' text it came from.
  mapLine(line, piece) {
    this._live();
    const core = this._halo._core;
    const index = piece === undefined ? -1 : PIECES[piece];
    if (index === undefined) throw new HaloError([], `mapLine: '${piece}' is not declarations, sample or finish`);
    return JSON.parse(core.UTF8ToString(core._halo_web_map_line(this._handle, index, line)));
  }

  // A WebGL compile log ("ERROR: 0:147: ...") with each line number mapped to its
  // origin: "ERROR: glsl/halo/map.glsl:31: ...".
  mapLog(log, piece) {
    return String(log).replace(/(ERROR|WARNING): (\d+):(\d+):/g, (whole, kind, source, line) => {
      const origin = this.mapLine(Number(line), piece);
      return origin.file ? `${kind}: ${origin.file}:${origin.line}:` : whole;
    });
  }

  destroy() {
    if (this._handle) this._halo._core._halo_web_program_destroy(this._handle);
    this._handle = 0;
  }
}

// A WebGL object's name in emscripten's GL tables (the C runtime's GLuint), given once and
// kept while the page's object lives (sweepNames drops deleted ones). A program the page
// linked gets the bookkeeping emscripten's glCreateProgram and glLinkProgram give their own
// (emscripten 3.1.6: the lazily filled uniform tables; forgetUniforms empties them).
const pageNames = new WeakMap(); // GL (emscripten's) -> Map(id -> [table, isX]) of the page's objects named here
function nameOf(GL, table, object) {
  if (!object) return 0;
  if (object.name && table[object.name] === object) return object.name;
  const id = GL.getNewId(table);
  table[id] = object;
  object.name = id;
  if (table === GL.programs) forgetUniforms(object);
  if (!pageNames.has(GL)) pageNames.set(GL, new Map());
  pageNames.get(GL).set(id, table);
  return id;
}

// Empties emscripten's uniform tables of a page's program: they refill on the next lookup,
// so a program the page linked again gets its new locations.
function forgetUniforms(program) {
  program.maxUniformLength = program.maxAttributeLength = program.maxUniformBlockNameLength = 0;
  program.uniformIdCounter = 1;
  program.uniformLocsById = 0;
  program.uniformSizeAndIdsByName = {};
}

// The page's objects that the page has deleted since they were named: out of the tables.
function sweepNames(GL, gl) {
  const names = pageNames.get(GL);
  if (!names) return;
  for (const [id, table] of names) {
    const object = table[id];
    const alive = object && (table === GL.textures ? gl.isTexture(object) : table === GL.programs ? gl.isProgram(object)
      : table === GL.framebuffers ? gl.isFramebuffer(object) : table === GL.renderbuffers ? gl.isRenderbuffer(object)
        : table === GL.vaos ? gl.isVertexArray(object) : gl.isBuffer(object));
    if (!alive) {
      table[id] = null;
      names.delete(id);
    }
  }
}

// The page's objects bound on gl, named in emscripten's tables before libhalo's C runtime
// runs: it restores the bindings it changes by their names (unnamed ones would come back
// unbound). A texture deleted while bound on a unit that was not active stays bound there,
// deleted (GLES 3.0, 3.8.1); binding it again is an error, so it is unbound here, which is
// what it is in effect.
function nameBindings(GL, gl) {
  sweepNames(GL, gl);
  const unit = gl.getParameter(gl.ACTIVE_TEXTURE);
  const units = gl.getParameter(gl.MAX_COMBINED_TEXTURE_IMAGE_UNITS);
  for (let i = 0; i < units; ++i) {
    gl.activeTexture(gl.TEXTURE0 + i);
    for (const binding of [gl.TEXTURE_BINDING_2D, gl.TEXTURE_BINDING_3D, gl.TEXTURE_BINDING_2D_ARRAY, gl.TEXTURE_BINDING_CUBE_MAP]) {
      const texture = gl.getParameter(binding);
      if (texture && !gl.isTexture(texture)) gl.bindTexture(binding === gl.TEXTURE_BINDING_2D ? gl.TEXTURE_2D
        : binding === gl.TEXTURE_BINDING_3D ? gl.TEXTURE_3D : binding === gl.TEXTURE_BINDING_2D_ARRAY ? gl.TEXTURE_2D_ARRAY
          : gl.TEXTURE_CUBE_MAP, null);
      else nameOf(GL, GL.textures, texture);
    }
  }
  gl.activeTexture(unit);
  for (const binding of [gl.DRAW_FRAMEBUFFER_BINDING, gl.READ_FRAMEBUFFER_BINDING])
    nameOf(GL, GL.framebuffers, gl.getParameter(binding));
  nameOf(GL, GL.renderbuffers, gl.getParameter(gl.RENDERBUFFER_BINDING));
  nameOf(GL, GL.programs, gl.getParameter(gl.CURRENT_PROGRAM));
  nameOf(GL, GL.vaos, gl.getParameter(gl.VERTEX_ARRAY_BINDING));
  for (const binding of [gl.ARRAY_BUFFER_BINDING, gl.PIXEL_PACK_BUFFER_BINDING, gl.PIXEL_UNPACK_BUFFER_BINDING])
    nameOf(GL, GL.buffers, gl.getParameter(binding));
}

// The WebGL extensions libhalo's runtime uses, enabled on the page's context where present
// (float colour targets and their blending, linear filtering of float textures); the
// context's other extensions are left as the page has them.
const RUNTIME_EXTENSIONS = ['EXT_color_buffer_float', 'EXT_color_buffer_half_float', 'EXT_float_blend',
  'OES_texture_float_linear'];

// A renderer on the CPU (SwiftShader, llvmpipe), where reading back where the image passes'
// results are nonzero is cheaper than passes over the whole frame. WebGL masks GL_RENDERER
// from the C runtime's own test; WEBGL_debug_renderer_info tells it where the browser has it.
function softwareRenderer(gl) {
  const info = gl.getExtension('WEBGL_debug_renderer_info');
  const name = info ? String(gl.getParameter(info.UNMASKED_RENDERER_WEBGL)) : '';
  return /SwiftShader|llvmpipe|softpipe|Software/i.test(name);
}

// libhalo's GL runtime on the page's WebGL 2 context with one program's frame: for a
// program linked with oneDraw, the halo field of every depth segment computed before the
// host draws (docs/host-contract.md, host contract 3).
class Frame {
  constructor(halo, gl, program, { width, height, readback } = {}) {
    if (!(program instanceof Program)) throw new HaloError([], 'frame: program must be a Program of halo.link');
    if (!(width > 0 && height > 0)) throw new HaloError([], 'frame: width and height (the host\'s target in pixels) are required');
    this._halo = halo;
    this._gl = gl;
    this._program = program;
    program._live();
    this.width = width;
    this.height = height;
    this._readback = readback;
    this._make();
  }

  // The C frame on the context's runtime (again after a lost context was restored: the
  // field's textures and programs went with it).
  _make() {
    const halo = this._halo, gl = this._gl, readback = this._readback;
    this._runtime = halo._runtime(gl);
    this._handle = halo._core._halo_web_frame_create(this._runtime, this._program._handle, this.width, this.height,
      readback === undefined ? (softwareRenderer(gl) ? 1 : -1) : readback ? 1 : 0);
    if (!this._handle) throw halo._error('frame: halo_gl_frame_create failed');
    halo._contexts.get(gl).frames.add(this);
  }

  // The context was lost and restored: the C frame's GL names are out of emscripten's tables
  // already; its memory goes, and the next draw makes it again.
  _drop() {
    if (this._handle) this._halo._core._halo_web_frame_destroy(this._handle);
    this._handle = 0;
  }

  // Draws one frame: the field (oneDraw), then the host's proxy once through draw(), with
  // glProgram current and libhalo's textures bound from unit firstUnit (8) on. Options:
  // program (the host's WebGLProgram), inverseViewProjection (16 numbers, column-major:
  // clip space -> the ray positions' space), step (the host's sample spacing there),
  // volume (its WebGLTexture, TEXTURE_3D), volumeSize ([nx, ny, nz]), framebuffer (null:
  // the canvas), draw, and optionally boxMin, boxMax, interval (M), firstUnit,
  // gradientTexture, gradientPrecision, volumeVersion (change it with the volume's
  // contents), seedEpsilon, fieldMaxBytes. The bindings and state it finds when called are
  // what it leaves (not those the draw callback made: an engine with a state cache resets
  // it after, as three.js's renderer.resetState()); the field's textures stay bound on
  // their units until the next call.
  draw(options) {
    if (this._destroyed) throw new HaloError([], 'the frame was destroyed');
    this._program._live(); // the C frame reads its program: not after program.destroy()
    const { program, draw } = options;
    if (typeof draw !== 'function') throw new HaloError([], 'frame.draw: draw (a function drawing the host\'s proxy) is required');
    if (typeof WebGLProgram !== 'undefined' && !(program instanceof WebGLProgram))
      throw new HaloError([], 'frame.draw: program (the host\'s WebGLProgram) is required');
    const gl = this._gl;
    if (gl.isContextLost()) throw new HaloError([], 'frame.draw: the WebGL context is lost');
    // the page's own pending errors are the page's: reported here, not blamed on libhalo
    for (let e = gl.getError(), n = 0; e && n < 8; e = gl.getError(), ++n)
      console.warn(`libhalo: frame.draw found WebGL error 0x${e.toString(16)} pending from the page's own calls`);
    const core = this._halo._core, GL = core.GL;
    this._halo._current(gl); // a context restored since the last draw: this frame made again
    if (!this._handle) this._make();
    const list = (v) => (v === undefined || v === null ? undefined : Array.from(v));
    const programName = nameOf(GL, GL.programs, program);
    forgetUniforms(program); // relinked since the last frame: its new locations
    const desc = {
      inverse_view_projection: Array.from(options.inverseViewProjection || []), step: options.step,
      box_min: list(options.boxMin), box_max: list(options.boxMax), interval: options.interval, first_unit: options.firstUnit,
      framebuffer: nameOf(GL, GL.framebuffers, options.framebuffer), volume_texture: nameOf(GL, GL.textures, options.volume),
      gradient_texture: nameOf(GL, GL.textures, options.gradientTexture), gradient_precision: options.gradientPrecision,
      volume_version: options.volumeVersion, volume_size: list(options.volumeSize), seed_epsilon: options.seedEpsilon,
      field_max_bytes: options.fieldMaxBytes,
    };
    let thrown = null;
    const outer = core.haloDraw; // a draw callback may itself draw another frame
    core.haloDraw = () => { try { draw(); } catch (e) { thrown = thrown || e; } };
    try {
      const ok = this._halo._withStrings([JSON.stringify(desc)], ([text]) => core._halo_web_frame_draw(this._handle, programName, text));
      if (thrown) throw thrown;
      if (!ok) throw this._halo._error('frame.draw failed');
    } finally {
      core.haloDraw = outer;
    }
  }

  // The image the passes after the host's draw (outlines: at=post and final) end in, or null
  // for a program without them.
  get postImage() { // the at=post passes run first, then the at=final ones
    const passes = this._program.reflection.passes || [];
    const last = [...passes.filter((p) => p.at === 'post'), ...passes.filter((p) => p.at === 'final')].pop();
    return last ? last.output : null;
  }

  // After draw: the passes after the host's draw (outlines) over colorTexture, the host's
  // image of this frame over its background (a WebGLTexture, RGBA, the frame's size). Returns
  // the WebGLTexture of their result (postImage, RGBA, the frame's size; the host shows it),
  // or null for a program without such passes. The bindings and state it finds are what it
  // leaves.
  post(colorTexture) {
    if (this._destroyed) throw new HaloError([], 'the frame was destroyed');
    this._program._live(); // the frame's images are named by its program
    if (!this.postImage) return null;
    const gl = this._gl;
    if (gl.isContextLost()) throw new HaloError([], 'frame.post: the WebGL context is lost');
    if (!this._handle) throw new HaloError([], 'frame.post: draw the frame first');
    const core = this._halo._core, GL = core.GL;
    const name = core._halo_web_frame_post(this._handle, this._program._handle, nameOf(GL, GL.textures, colorTexture));
    if (!name) throw this._halo._error('frame.post failed');
    return GL.textures[name] || null;
  }

  // One of the frame's images (e.g. postImage after post) as floats: width * height *
  // channels (the reflection's), rows from the bottom.
  read(image) {
    if (this._destroyed) throw new HaloError([], 'the frame was destroyed');
    this._program._live();
    if (!this._handle) throw new HaloError([], 'frame.read: draw the frame first');
    const info = (this._program.reflection.images || []).find((i) => i.name === image);
    if (!info) throw new HaloError([], `frame.read: the program has no image '${image}'`);
    const scale = info.scale || 1;
    const count = Math.ceil(this.width / scale) * Math.ceil(this.height / scale) * info.channels;
    const core = this._halo._core;
    const pointer = core._malloc(count * 4);
    try {
      const ok = this._halo._withStrings([image], ([text]) => core._halo_web_frame_read(this._handle, text, pointer));
      if (!ok) throw this._halo._error('frame.read failed');
      return new Float32Array(core.HEAPF32.buffer, pointer, count).slice();
    } finally {
      core._free(pointer);
    }
  }

  // The host's draws in the last frame.draw (halo_gl_frame_info.segment_count): 1 for a oneDraw
  // program (its field's depth segments are libhalo's own draws).
  get draws() { return this._handle ? this._halo._core._halo_web_frame_segment_count(this._handle) : 0; }

  // The GPU memory the frame holds, in bytes (halo_gl_frame_info.gpu_bytes): its images and,
  // with oneDraw, the halo field (stacks, atlas, derived gradient).
  get gpuBytes() { return this._handle ? this._halo._core._halo_web_frame_gpu_bytes(this._handle) : 0; }

  destroy() {
    if (this._handle) {
      this._halo._current(this._gl);
      this._halo._core._halo_web_frame_destroy(this._handle);
    }
    const entry = this._halo._contexts.get(this._gl);
    if (entry) entry.frames.delete(this);
    this._handle = 0;
    this._destroyed = true;
  }
}

// For engine adapters that show libhalo's images (outlines: the passes after the draw) in
// the engine's framebuffer. The blend the engine set (WebGL 2: one for all draw buffers), and
// setting one back.
export function blendOf(gl) {
  return { on: gl.isEnabled(gl.BLEND), equation: [gl.BLEND_EQUATION_RGB, gl.BLEND_EQUATION_ALPHA].map((p) => gl.getParameter(p)),
    func: [gl.BLEND_SRC_RGB, gl.BLEND_DST_RGB, gl.BLEND_SRC_ALPHA, gl.BLEND_DST_ALPHA].map((p) => gl.getParameter(p)) };
}
export function setBlend(gl, b) {
  (b.on ? gl.enable : gl.disable).call(gl, gl.BLEND);
  gl.blendEquationSeparate(...b.equation);
  gl.blendFuncSeparate(...b.func);
}

// A width x height texture of format (nearest filtering) and a framebuffer with it as its
// colour: { texture, framebuffer }; the bindings it changes given back. deleteColorTarget
// frees one (null: nothing).
export function colorTarget(gl, format, width, height) {
  const texture = gl.createTexture(), boundTexture = gl.getParameter(gl.TEXTURE_BINDING_2D);
  gl.bindTexture(gl.TEXTURE_2D, texture);
  gl.texStorage2D(gl.TEXTURE_2D, 1, format, width, height);
  gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MIN_FILTER, gl.NEAREST);
  gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MAG_FILTER, gl.NEAREST);
  gl.bindTexture(gl.TEXTURE_2D, boundTexture);
  const framebuffer = gl.createFramebuffer(), boundFramebuffer = gl.getParameter(gl.DRAW_FRAMEBUFFER_BINDING);
  gl.bindFramebuffer(gl.DRAW_FRAMEBUFFER, framebuffer);
  gl.framebufferTexture2D(gl.DRAW_FRAMEBUFFER, gl.COLOR_ATTACHMENT0, gl.TEXTURE_2D, texture, 0);
  gl.bindFramebuffer(gl.DRAW_FRAMEBUFFER, boundFramebuffer);
  return { texture, framebuffer };
}
export function deleteColorTarget(gl, target) {
  if (!target) return;
  gl.deleteFramebuffer(target.framebuffer);
  gl.deleteTexture(target.texture);
}

// The program (and its empty vertex array) that showTexture draws with: old when it is still
// one on gl (not after a lost context), else made; keep false: old's objects deleted, null.
export function textureShower(gl, old, keep = true) {
  const alive = old && gl.isProgram(old.program) && gl.isVertexArray(old.vertexArray);
  if (!keep) {
    if (alive) {
      gl.deleteProgram(old.program);
      gl.deleteVertexArray(old.vertexArray);
    }
    return null;
  }
  if (alive) return old;
  // a triangle over the viewport, each pixel the texture's texel
  const shader = (type, text) => {
    const x = gl.createShader(type);
    gl.shaderSource(x, text);
    gl.compileShader(x);
    return x;
  };
  const vertex = shader(gl.VERTEX_SHADER, '#version 300 es\nvoid main() {\n  vec2 p = vec2(gl_VertexID == 1 ? 3.0 : -1.0, ' +
    'gl_VertexID == 2 ? 3.0 : -1.0);\n  gl_Position = vec4(p, 0.0, 1.0);\n}\n');
  const fragment = shader(gl.FRAGMENT_SHADER, '#version 300 es\nprecision highp float;\nuniform highp sampler2D image;\n' +
    'uniform ivec2 origin;\nout vec4 color;\nvoid main() { color = texelFetch(image, ivec2(gl_FragCoord.xy) - origin, 0); }\n');
  const program = gl.createProgram();
  gl.attachShader(program, vertex);
  gl.attachShader(program, fragment);
  gl.linkProgram(program);
  gl.deleteShader(vertex);
  gl.deleteShader(fragment);
  if (!gl.getProgramParameter(program, gl.LINK_STATUS)) {
    const log = gl.getProgramInfoLog(program);
    gl.deleteProgram(program);
    throw new Error(`the program showing libhalo's images did not link: ${log}`);
  }
  return { program, vertexArray: gl.createVertexArray() };
}

// Draws texture (viewport's size) over framebuffer (null: the canvas) in viewport
// ([x, y, width, height]), with blend (or none), through shower (textureShower's); every
// binding and switch it changes given back.
export function showTexture(gl, shower, texture, framebuffer, viewport, blend) {
  const saved = {
    framebuffer: gl.getParameter(gl.DRAW_FRAMEBUFFER_BINDING), program: gl.getParameter(gl.CURRENT_PROGRAM),
    vertexArray: gl.getParameter(gl.VERTEX_ARRAY_BINDING), unit: gl.getParameter(gl.ACTIVE_TEXTURE),
    viewport: gl.getParameter(gl.VIEWPORT), blend: blendOf(gl),
    switches: [gl.DEPTH_TEST, gl.CULL_FACE, gl.STENCIL_TEST, gl.RASTERIZER_DISCARD, gl.SCISSOR_TEST].map((s) => [s, gl.isEnabled(s)]),
  };
  gl.activeTexture(gl.TEXTURE0);
  const bound = gl.getParameter(gl.TEXTURE_BINDING_2D);
  gl.bindFramebuffer(gl.DRAW_FRAMEBUFFER, framebuffer);
  gl.viewport(...viewport);
  gl.useProgram(shower.program);
  gl.bindVertexArray(shower.vertexArray);
  gl.bindTexture(gl.TEXTURE_2D, texture);
  gl.uniform1i(gl.getUniformLocation(shower.program, 'image'), 0);
  gl.uniform2i(gl.getUniformLocation(shower.program, 'origin'), viewport[0], viewport[1]);
  setBlend(gl, blend || { ...saved.blend, on: false });
  for (const [s] of saved.switches) gl.disable(s);
  Object.getPrototypeOf(gl).drawArrays.call(gl, gl.TRIANGLES, 0, 3);
  gl.bindTexture(gl.TEXTURE_2D, bound);
  gl.activeTexture(saved.unit);
  for (const [s, on] of saved.switches) (on ? gl.enable : gl.disable).call(gl, s);
  setBlend(gl, saved.blend);
  gl.viewport(...saved.viewport);
  gl.bindVertexArray(saved.vertexArray);
  gl.useProgram(saved.program);
  gl.bindFramebuffer(gl.DRAW_FRAMEBUFFER, saved.framebuffer);
}

// The host uniform through which the feature_halo stage reads the halo buffer.
export const FEATURE_BUFFER_UNIFORM = 'halo_host_feature_buffer';
// outline_feature's segmentation (a sampler3D), read only for features with a label
// (reflection.reads_labels); unread, an adapter points it at a unit with a 3D texture
export const LABELS_UNIFORM = 'halo_host_labels';

// Feature halos (docs/feature-halos.md): the halo buffer of a program's feature_halo stage
// (its parameters), splatted by libhalo's GL runtime on gl from the volume's values (dims[0]
// x dims[1] x dims[2] numbers, x fastest, in [0, 1]: the volume as the stages read it).
// build(view) splats it for a view direction (sample -> eye, in the volume's voxel space:
// halo.featureView), and returns at once when the buffer already holds that view: call it
// every frame, before bind(glProgram, unit), which binds it on that texture unit and points
// the program's sampler halo_host_feature_buffer there (the program is left current). A
// context lost and restored: the next build makes the buffer again.
class FeatureBuffer {
  constructor(halo, gl, program, { values, dims } = {}) {
    if (!(program instanceof Program)) throw new HaloError([], 'featureBuffer: program must be a Program of halo.link');
    if (!dims || dims.length !== 3 || !dims.every((n) => Number.isInteger(n) && n > 0))
      throw new HaloError([], 'featureBuffer: dims must be three positive integers');
    if (!values || values.length !== dims[0] * dims[1] * dims[2])
      throw new HaloError([], `featureBuffer: values must hold ${dims.join(' x ')} numbers`);
    this._halo = halo;
    this._gl = gl;
    this._program = program;
    program._live();
    this._values = Float32Array.from(values);
    this.dims = Array.from(dims);
    this.view = null; // the view of the last build
    this._make();
  }

  _make() {
    const halo = this._halo, core = halo._core;
    const runtime = halo._runtime(this._gl);
    const pointer = core._malloc(this._values.length * 4);
    if (!pointer) throw new HaloError([], 'featureBuffer: out of memory');
    try {
      core.HEAPF32.set(this._values, pointer / 4);
      this._handle = core._halo_web_feature_create(runtime, this._program._handle, pointer, this.dims[0], this.dims[1],
        this.dims[2]);
    } finally {
      core._free(pointer);
    }
    if (!this._handle) throw halo._error('featureBuffer: halo_feature_buffer_create failed');
    halo._contexts.get(this._gl).frames.add(this);
    this.view = null;
  }

  _drop() {
    if (this._handle) this._halo._core._halo_web_feature_destroy(this._handle);
    this._handle = 0;
    this.view = null; // the next build splats it anew
  }

  build(view) {
    if (this._destroyed) throw new HaloError([], 'the feature buffer was destroyed');
    if (!view || view.length !== 3) throw new HaloError([], 'featureBuffer.build: view must be three numbers');
    if (this._gl.isContextLost()) throw new HaloError([], 'featureBuffer.build: the WebGL context is lost');
    this._program._live();
    this._halo._current(this._gl); // a context restored since: the buffer dropped, made again here
    if (!this._handle) this._make();
    if (this.view && this.view.every((e, k) => e === view[k])) return; // it holds this view
    if (!this._halo._core._halo_web_feature_build(this._handle, view[0], view[1], view[2]))
      throw this._halo._error('featureBuffer.build failed');
    this.view = Array.from(view);
  }

  // The buffer's WebGLTexture (TEXTURE_3D, R32F or R16F), null before the first build.
  get texture() {
    if (!this._handle || !this.view) return null;
    return this._halo._core.GL.textures[this._halo._core._halo_web_feature_texture(this._handle)] || null;
  }

  bind(glProgram, unit) {
    const gl = this._gl;
    this._halo._current(gl); // a context restored since: no texture until the next build
    const texture = this.texture;
    if (!texture) throw new HaloError([], 'featureBuffer.bind: build it first (after a lost context too)');
    gl.useProgram(glProgram);
    gl.uniform1i(gl.getUniformLocation(glProgram, FEATURE_BUFFER_UNIFORM), unit);
    const active = gl.getParameter(gl.ACTIVE_TEXTURE);
    gl.activeTexture(gl.TEXTURE0 + unit);
    gl.bindTexture(gl.TEXTURE_3D, texture);
    gl.activeTexture(active);
  }

  destroy() {
    if (this._handle) {
      this._halo._current(this._gl);
      this._drop();
    }
    const entry = this._halo._contexts.get(this._gl);
    if (entry) entry.frames.delete(this);
    this._destroyed = true;
  }
}

function componentsOf(type) {
  const m = /^(?:vec|ivec|bvec)(\d)$/.exec(type);
  return m ? Number(m[1]) : type === 'mat4' ? 16 : 1;
}

function uploadUniform(gl, location, type, values) {
  const v = Float32Array.from(values);
  switch (type) {
    case 'float': gl.uniform1fv(location, v); break;
    case 'vec2': gl.uniform2fv(location, v); break;
    case 'vec3': gl.uniform3fv(location, v); break;
    case 'vec4': gl.uniform4fv(location, v); break;
    case 'int': case 'bool': gl.uniform1iv(location, Int32Array.from(values, Math.round)); break;
    case 'mat4': gl.uniformMatrix4fv(location, false, v); break;
    default: throw new HaloError([], `upload: uniform type '${type}' is not handled`);
  }
}

class Halo {
  constructor(core) {
    this._core = core;
    if (!core._halo_web_init()) throw this._error('libhalo could not load its modules');
    this.version = core.UTF8ToString(core._halo_web_version());
    // WebGL 2 context -> {handle (emscripten's), runtime (halo_gl), frames, names, probe}
    this._contexts = new Map();
    // The names emscripten's GL layer gives while a context is current (the C runtime's
    // objects, and the page's named here), kept per context: when the context is lost and
    // restored, its objects are gone, and these names leave the tables with them.
    const GL = core.GL, getNewId = GL.getNewId, halo = this;
    GL.getNewId = function (table) {
      const id = getNewId.call(GL, table);
      const entry = halo._naming;
      if (entry && table !== GL.contexts) { // a context's handle is no object of the context
        if (entry.names.length >= entry.compactAt) { // the deleted ones out (names are never reused)
          entry.names = entry.names.filter((v, i, a) => (i % 2 ? a[i - 1][v] : v[a[i + 1]]));
          entry.compactAt = Math.max(8192, 2 * entry.names.length);
        }
        entry.names.push(table, id); // after: its object is put in the table when this returns
      }
      return id;
    };
  }

  // The context made current in emscripten's GL layer (registered on first use; again,
  // with libhalo's objects made anew, after it was lost and restored).
  _current(gl) {
    const GL = this._core.GL;
    let entry = this._contexts.get(gl);
    if (entry && entry.probe && !gl.isContextLost() && !gl.isVertexArray(entry.probe)) entry = this._restored(gl, entry);
    if (!entry) {
      if (typeof WebGL2RenderingContext === 'undefined' || !(gl instanceof WebGL2RenderingContext))
        throw new HaloError([], 'frame: gl must be a WebGL 2 context');
      for (const name of RUNTIME_EXTENSIONS) gl.getExtension(name);
      this._naming = null; // not another context's
      entry = { handle: GL.registerContext(gl, { majorVersion: 2, minorVersion: 0, enableExtensionsByDefault: false }),
        runtime: 0, frames: new Set(), names: [], compactAt: 8192, probe: null };
      // a vertex array made (and bound once) on the context: gone when the context is
      // restored after a loss, which is how a later call knows (no event needed)
      const vao = gl.getParameter(gl.VERTEX_ARRAY_BINDING);
      entry.probe = gl.createVertexArray();
      gl.bindVertexArray(entry.probe);
      gl.bindVertexArray(vao);
      this._contexts.set(gl, entry);
    }
    GL.makeContextCurrent(entry.handle);
    this._naming = entry;
    nameBindings(GL, gl);
    return entry;
  }

  // gl was lost and restored: its names leave emscripten's tables (so that the C runtime's
  // deletes of them do nothing), its frames' C objects and its runtime are freed, and the
  // context is registered again; the frames are made again at their next draw.
  _restored(gl, entry) {
    const core = this._core, GL = core.GL;
    for (let i = 0; i < entry.names.length; i += 2) entry.names[i][entry.names[i + 1]] = null;
    GL.makeContextCurrent(entry.handle);
    this._naming = null;
    for (const frame of entry.frames) frame._drop();
    if (entry.runtime) core._halo_web_gl_destroy(entry.runtime);
    GL.lastError = 0; // glDeleteProgram of a name no longer in the table records INVALID_VALUE
    GL.deleteContext(entry.handle);
    this._contexts.delete(gl);
    const fresh = this._current(gl);
    for (const frame of entry.frames) fresh.frames.add(frame);
    return fresh;
  }

  // libhalo's GL runtime (halo_gl) on gl, made once per context.
  _runtime(gl) {
    const entry = this._current(gl);
    if (!entry.runtime) {
      entry.runtime = this._core._halo_web_gl_create();
      if (!entry.runtime) throw this._error('frame: halo_gl_create failed on this WebGL 2 context');
    }
    return entry.runtime;
  }

  // For an engine adapter: links a scene as pieces (options: scene, sceneFile, allLive,
  // pieces, imageScale), for host contract 3 (oneDraw) when its stages run passes between depth
  // segments or write extra outputs (drawn once, a ray writes them once: unblended on
  // WebGL 2); refuses, naming the stages, what an engine drawn once with libhalo's field
  // cannot serve: extra outputs and passes after the draw (outlines) unless the adapter
  // serves them ({ outlines: true }), host uniforms (but the camera's, the field's, the
  // image-plane axes and those the adapter names in serves, e.g. the feature buffer's).
  // Returns { program, field (it has a halo field), features (it reads the feature buffer),
  // outlines (it has passes after the draw: frame.post) }.
  linkForEngine(options, engine, serves = [], { outlines = false } = {}) {
    const link = (oneDraw) => this.link({
      scene: options.scene, sceneFile: options.sceneFile || 'scene', target: 'es300', allLive: !!options.allLive,
      pieces: options.pieces, oneDraw, ...(options.imageScale ? { imageScale: options.imageScale } : {}),
    });
    let program;
    try {
      program = link(false);
    } catch (e) { // passes between depth segments (volumetric halos): the field before the draw
      if (e.id !== 'HOST_SINGLE_PASS') throw e;
      program = link(true);
    }
    if (outlines && (program.reflection.outputs || []).length && !program.reflection.one_draw) {
      program.destroy(); // drawn once: the outputs written unblended (WebGL 2 has one blend for all buffers)
      program = link(true);
    }
    const r = program.reflection;
    const needs = [['extra outputs', outlines ? [] : r.outputs],
      ['image passes after the draw', outlines ? [] : (r.passes || []).filter((p) => p.at)],
      ['host uniforms', (r.host_uniforms || []).filter((u) => !/^halo_(camera|stack|host_screen)_/.test(u.name) &&
        !serves.includes(u.name) && !(u.name === LABELS_UNIFORM && !r.reads_labels))]]
      .filter(([, list]) => list && list.length);
    if (needs.length) {
      const stages = (r.stages || []).map((s) => (typeof s === 'string' ? s : s.name)).join(', ');
      program.destroy();
      throw new Error(`installHalo: the scene's stages (${stages}) need ${needs.map(([what]) => what).join(', ')}, ` +
        `which the ${engine} adapter does not serve yet (it serves per-sample stages, volumetric halos` +
        `${serves.includes(FEATURE_BUFFER_UNIFORM) ? ', feature halos' : ''}${outlines ? ', outlines' : ''})`);
    }
    // for smallerProgram: the scene as linked now (a caller's object may change after)
    const scene = options.scene === undefined || typeof options.scene === 'string' ? options.scene : JSON.stringify(options.scene);
    program._engine = { options: { ...options, scene }, engine, serves, outlines };
    return { program, field: (r.passes || []).some((p) => !p.at),
      features: (r.host_uniforms || []).some((u) => u.name === FEATURE_BUFFER_UNIFORM),
      outlines: (r.passes || []).some((p) => p.at) };
  }

  // For an engine adapter, after frame.draw threw error: when it is FIELD_MEMORY (the halo
  // field over its cap) for a oneDraw program of linkForEngine linked without an explicit
  // imageScale, the same scene linked again with halo images at twice the scale (1/2, then
  // 1/4 of the frame per side), the live values set on program carried over: { program (the
  // new one; the adapter puts its pieces in and destroys the old), warning (the text for
  // console.warn: the cap's diagnostic and the new scale) }. Otherwise null: the adapter
  // goes on with error. An explicit imageScale is the user's: kept, the frame refused.
  smallerProgram(program, error) {
    const engine = program && program._engine, r = program && program.reflection;
    const scale = (r && r.image_scale) || 1;
    if (!error || error.id !== 'FIELD_MEMORY' || !engine || engine.options.imageScale || !r.one_draw || scale >= 4)
      return null;
    const options = { ...engine.options, imageScale: scale * 2 };
    const { program: smaller } = this.linkForEngine(options, engine.engine, engine.serves, { outlines: engine.outlines });
    smaller._engine.options = { ...engine.options }; // still the library's choice: 1/4 next, if 1/2 is over the cap too
    try {
      for (const [name, values] of program._current) smaller.set(name, values);
    } catch (e) {
      smaller.destroy();
      throw e;
    }
    return { program: smaller, warning: `${error.message}; linked again with halo images at 1/${scale * 2} of the ` +
      'frame per side (imageScale ' + (scale * 2) + '): give imageScale to choose, or raise fieldMaxBytes' };
  }

  // For an engine adapter: a volume's values as the stages read them (raw[i] * slope +
  // intercept, with low..high as 0..1, clamped), an R32F 3D texture of dims (x fastest),
  // linear where the context filters float textures; made on unit, whose binding is put
  // back. Returns { texture, dims, values (the Float32Array uploaded: a feature buffer's
  // input) }.
  valueTexture(gl, raw, dims, { low, high, slope = 1, intercept = 0 }, unit) {
    const range = high - low;
    const values = new Float32Array(dims[0] * dims[1] * dims[2]);
    for (let i = 0; i < values.length; ++i) {
      const v = range > 0 ? (raw[i] * slope + intercept - low) / range : 0;
      values[i] = v > 0 ? (v < 1 ? v : 1) : 0;
    }
    const previousUnit = gl.getParameter(gl.ACTIVE_TEXTURE);
    gl.activeTexture(gl.TEXTURE0 + unit);
    let previous = gl.getParameter(gl.TEXTURE_BINDING_3D);
    if (previous && !gl.isTexture(previous)) previous = null; // deleted while bound there: unbound in effect
    const texture = gl.createTexture();
    gl.bindTexture(gl.TEXTURE_3D, texture);
    // the page's unpack state, set to tightly packed rows from the array and put back (an
    // engine may leave UNPACK_FLIP_Y_WEBGL on, with which a 3D upload is an error)
    const unpack = [[gl.UNPACK_ALIGNMENT, 1], [gl.UNPACK_ROW_LENGTH, 0], [gl.UNPACK_IMAGE_HEIGHT, 0],
      [gl.UNPACK_SKIP_PIXELS, 0], [gl.UNPACK_SKIP_ROWS, 0], [gl.UNPACK_SKIP_IMAGES, 0], [gl.UNPACK_FLIP_Y_WEBGL, false],
      [gl.UNPACK_PREMULTIPLY_ALPHA_WEBGL, false]].map(([name, v]) => [name, gl.getParameter(name), v]);
    const buffer = gl.getParameter(gl.PIXEL_UNPACK_BUFFER_BINDING);
    for (const [name, , v] of unpack) gl.pixelStorei(name, v);
    gl.bindBuffer(gl.PIXEL_UNPACK_BUFFER, null);
    for (let e = gl.getError(), n = 0; e && n < 8; e = gl.getError(), ++n) {} // the page's, not this upload's
    gl.texImage3D(gl.TEXTURE_3D, 0, gl.R32F, dims[0], dims[1], dims[2], 0, gl.RED, gl.FLOAT, values);
    const error = gl.getError();
    for (const [name, was] of unpack) gl.pixelStorei(name, was);
    gl.bindBuffer(gl.PIXEL_UNPACK_BUFFER, buffer);
    const linear = gl.getExtension('OES_texture_float_linear') ? gl.LINEAR : gl.NEAREST;
    for (const [p, v] of [[gl.TEXTURE_MIN_FILTER, linear], [gl.TEXTURE_MAG_FILTER, linear], [gl.TEXTURE_WRAP_S, gl.CLAMP_TO_EDGE],
      [gl.TEXTURE_WRAP_T, gl.CLAMP_TO_EDGE], [gl.TEXTURE_WRAP_R, gl.CLAMP_TO_EDGE]])
      gl.texParameteri(gl.TEXTURE_3D, p, v);
    gl.bindTexture(gl.TEXTURE_3D, previous);
    gl.activeTexture(previousUnit);
    if (error) {
      gl.deleteTexture(texture);
      throw new HaloError([], `valueTexture: WebGL error 0x${error.toString(16)} uploading the ${dims.join('x')} volume`);
    }
    return { texture, dims: Array.from(dims), values };
  }

  // The halo buffer of a program's feature halos (class FeatureBuffer).
  featureBuffer(gl, program, volume) {
    return new FeatureBuffer(this, gl, program, volume);
  }

  // For an engine adapter: the view a feature buffer is built for, the unit vector from the
  // volume's centre to the eye in voxel space, from the camera's clip space -> texture space
  // mapping (16 numbers, column-major) and the volume's dims: the eye is the point clip
  // (0, 0, 1, 0) maps to (a perspective camera; an orthographic one: its direction, whose
  // sign the buffer does not see).
  featureView(inverseViewProjection, dims) {
    const m = inverseViewProjection;
    const eye = [m[8], m[9], m[10], m[11]];
    const v = eye[3] !== 0 ? [0, 1, 2].map((k) => (eye[k] / eye[3] - 0.5) * dims[k]) : [0, 1, 2].map((k) => -eye[k] * dims[k]);
    const length = Math.hypot(...v);
    if (!(length > 0)) throw new HaloError([], 'featureView: the eye is at the volume\'s centre');
    return v.map((e) => e / length);
  }

  // A frame of the GL runtime for a linked program (class Frame).
  frame(gl, program, size) {
    return new Frame(this, gl, program, size);
  }

  // For a frame kept across draws: frame while it is width x height, else it is destroyed
  // and a new one made (null first, so a failure leaves no destroyed frame behind).
  frameOfSize(frame, gl, program, width, height) {
    if (frame && frame.width === width && frame.height === height) return frame;
    if (frame) frame.destroy();
    return this.frame(gl, program, { width, height });
  }

  _diagnostics() {
    return JSON.parse(this._core.UTF8ToString(this._core._halo_web_diagnostics()));
  }

  _error(fallback) {
    return new HaloError(this._diagnostics(), fallback);
  }

  // Calls fn with the strings copied into WebAssembly memory (null stays 0), then frees them.
  _withStrings(strings, fn) {
    const core = this._core;
    const pointers = strings.map((s) => {
      if (s === null || s === undefined) return 0;
      const size = core.lengthBytesUTF8(s) + 1;
      const p = core._malloc(size);
      core.stringToUTF8(s, p, size);
      return p;
    });
    try {
      return fn(pointers);
    } finally {
      pointers.forEach((p) => p && core._free(p));
    }
  }

  // The modules: [{name, file, summary}].
  modules() {
    return JSON.parse(this._core.UTF8ToString(this._core._halo_web_modules()));
  }

  // Links a scene (JSON text or object) into a host shader (host: its text) or, with
  // pieces ({position, value, color, ...}, docs/composers.md), into pieces for an engine's
  // composer. options: scene, sceneFile, host, hostFile, target ('es300' by default: WebGL
  // 2), kind ('fragment'), oneDraw, allLive, imagePrecision, imageScale, version ('target',
  // 'keep', 'none'), engineUniforms. Returns a Program; throws a HaloError.
  link(options = {}) {
    const known = ['scene', 'sceneFile', 'host', 'hostFile', 'target', 'kind', 'oneDraw', 'allLive',
      'imagePrecision', 'imageScale', 'version', 'engineUniforms', 'pieces'];
    for (const key of Object.keys(options))
      if (!known.includes(key)) throw new HaloError([], `link: unknown option '${key}' (known: ${known.join(', ')})`);
    if (options.host === undefined && options.pieces === undefined)
      throw new HaloError([], 'link: give host (the shader text) or pieces (for a composer)');
    const scene = options.scene === undefined || typeof options.scene === 'string' ? options.scene : JSON.stringify(options.scene);
    const desc = {
      scene, scene_file: options.sceneFile, host: options.host, host_file: options.hostFile,
      target: options.target || 'es300', kind: options.kind, one_draw: options.oneDraw ? 1 : 0,
      all_live: options.allLive ? 1 : 0, image_precision: options.imagePrecision, image_scale: options.imageScale,
      version: options.version, engine_uniforms: options.engineUniforms ? 1 : 0, pieces: options.pieces,
    };
    const handle = this._withStrings([JSON.stringify(desc)], ([text]) => this._core._halo_web_link(text));
    if (!handle) throw this._error('link failed');
    return new Program(this, handle);
  }
}

// Loads the WebAssembly module; options go to emscripten's loader (e.g. locateFile,
// wasmBinary). In a browser it fetches dist/libhalo-core.wasm beside this file; under
// node (tests, build tools) it reads that file.
export default async function libhalo(options = {}) {
  const settings = { ...options };
  if (!settings.wasmBinary && typeof process === 'object' && process.versions && process.versions.node) {
    const { readFile } = await import('node:fs/promises');
    settings.wasmBinary = await readFile(new URL('./dist/libhalo-core.wasm', import.meta.url));
  }
  return new Halo(await haloCore(settings));
}
