// Type declarations of libhalo's JavaScript API (libhalo.mjs; docs/hosts/web.md).

export interface HaloDiagnostic {
  severity: 'error' | 'warning';
  id: string;        // "SCENE_JSON", "LINK_MISSING_PROVIDER", ...
  file: string;      // module, host or scene file ("" when none)
  line: number;      // 1-based; 0 when unknown
  column: number;    // 1-based; 0 when unknown
  message: string;
  source?: string;   // the line it points at
}

export class HaloError extends Error {
  diagnostics: HaloDiagnostic[];
  file?: string;
  line?: number;
  column?: number;
  id?: string;
  static format(d: HaloDiagnostic): string;
}

// Expressions of the composer's shader for the sample piece (docs/composers.md).
export interface HaloPieces {
  position?: string; value?: string; gradient?: string; view?: string; depth?: string;
  fragcoord?: string; color?: string; volume?: string; gradient_texture?: string;
  segmented?: boolean | number; first_output_location?: number;
}

export interface LinkOptions {
  scene?: string | object;   // a scene file's JSON (docs/scenes.md); none: no stage
  sceneFile?: string;        // its name in diagnostics
  host?: string;             // the host shader's text, or pieces:
  pieces?: HaloPieces;
  hostFile?: string;
  target?: '330' | '450' | 'es300' | '150'; // default 'es300' (WebGL 2)
  kind?: 'fragment' | 'vertex';
  oneDraw?: boolean;         // host contract 3
  allLive?: boolean;         // every parameter a uniform
  imagePrecision?: 32 | 16 | 8;
  imageScale?: 1 | 2 | 4;
  version?: 'target' | 'keep' | 'none'; // 'none': the engine writes #version (three.js ShaderMaterial)
  engineUniforms?: boolean;
}

export interface Program {
  readonly source: string;                 // the linked shader ("" for pieces)
  readonly pieces: { declarations?: string; sample?: string; finish?: string };
  readonly reflection: any;                // halo_program_reflect_json: uniforms, constants, samplers, ...
  set(name: string, value: number | boolean | number[] | number[][]): void;      // "stage.param"
  set(stage: string, param: string, value: number | boolean | number[] | number[][]): void;
  /** all: every live parameter's current value (a program the engine built again), not only those set since the last upload */
  upload(gl: WebGL2RenderingContext, program: WebGLProgram, options?: { all?: boolean }): void;
  mapLine(line: number, piece?: 'declarations' | 'sample' | 'finish'): { file: string; line: number };
  mapLog(log: string, piece?: 'declarations' | 'sample' | 'finish'): string;
  destroy(): void;
}

// Host contract 3 (a program linked with oneDraw): what frame.draw needs of the host.
export interface FrameDrawOptions {
  program: WebGLProgram;              // the host's program, linked from program.source
  draw: () => void;                   // draws the host's proxy geometry once (the program is current)
  inverseViewProjection: ArrayLike<number>; // 16, column-major: clip space -> the ray positions' space
  step: number;                       // the host's sample spacing in that space
  volume: WebGLTexture;               // TEXTURE_3D: the value at a position, in its red channel
  volumeSize: [number, number, number]; // its voxels per axis
  framebuffer?: WebGLFramebuffer | null; // null: the canvas
  boxMin?: [number, number, number]; boxMax?: [number, number, number]; // default the unit cube
  interval?: number;                  // M, planes per depth segment; default the scene's
  firstUnit?: number;                 // libhalo's textures from this unit on (default 8)
  gradientTexture?: WebGLTexture;     // the host's gradient, if it has one
  gradientPrecision?: 16 | 32;
  volumeVersion?: number;             // change it when the volume's contents change
  seedEpsilon?: number;
  fieldMaxBytes?: number;
}

// libhalo's GL runtime (WebAssembly) on the page's WebGL 2 context, for one program.
export interface Frame {
  readonly width: number;
  readonly height: number;
  draw(options: FrameDrawOptions): void; // the field, then the host once; leaves the state it found
                                         // (the field's textures stay bound on their units)
  readonly draws: number;             // host draws in the last frame: 1 with oneDraw
  readonly gpuBytes: number;          // GPU memory the frame holds (its images; with oneDraw the halo field)
  readonly postImage: string | null;  // the image the passes after the draw (outlines) end in
  // after draw: those passes over the host's image (RGBA, the frame's size, over its
  // background); their result's texture, or null without such passes
  post(colorTexture: WebGLTexture): WebGLTexture | null;
  read(image: string): Float32Array;  // width * height * channels floats, rows from the bottom
  destroy(): void;
}

// Feature halos: the halo buffer of a program's feature_halo stage, splatted on the context.
// For engine adapters that show libhalo's images in the engine's framebuffer (outlines).
export interface Blend { on: boolean; equation: number[]; func: number[] }
export function blendOf(gl: WebGL2RenderingContext): Blend;
export function setBlend(gl: WebGL2RenderingContext, blend: Blend): void;
// a width x height texture of format and a framebuffer with it as its colour; deleteColorTarget frees them
export interface ColorTarget { texture: WebGLTexture; framebuffer: WebGLFramebuffer }
export function colorTarget(gl: WebGL2RenderingContext, format: number, width: number, height: number): ColorTarget;
export function deleteColorTarget(gl: WebGL2RenderingContext, target: ColorTarget | null): void;
export interface TextureShower { program: WebGLProgram; vertexArray: WebGLVertexArrayObject }
// old when still alive on gl, else made; keep false: old's objects deleted, null returned
export function textureShower(gl: WebGL2RenderingContext, old?: TextureShower | null, keep?: boolean): TextureShower | null;
// texture drawn over framebuffer (null: the canvas) in viewport [x, y, width, height], with blend or none
export function showTexture(gl: WebGL2RenderingContext, shower: TextureShower, texture: WebGLTexture,
  framebuffer: WebGLFramebuffer | null, viewport: ArrayLike<number>, blend: Blend | null): void;
export const FEATURE_BUFFER_UNIFORM: 'halo_host_feature_buffer';
export const LABELS_UNIFORM: 'halo_host_labels'; // outline_feature's segmentation (reflection.reads_labels)
export interface FeatureBuffer {
  readonly dims: number[];
  readonly view: number[] | null;          // the view of the last build
  readonly texture: WebGLTexture | null;   // TEXTURE_3D, null before the first build
  build(view: ArrayLike<number>): void;    // sample -> eye, voxel space; at once when it holds this view
  bind(glProgram: WebGLProgram, unit: number): void; // the texture on unit, the sampler pointed there
  destroy(): void;
}

export interface Halo {
  readonly version: string;
  modules(): { name: string; file: string; summary: string }[];
  link(options: LinkOptions): Program;
  frame(gl: WebGL2RenderingContext, program: Program, size: { width: number; height: number; readback?: boolean }): Frame;
  featureBuffer(gl: WebGL2RenderingContext, program: Program,
    volume: { values: ArrayLike<number>; dims: ArrayLike<number> }): FeatureBuffer;
  // for an engine adapter: the view to build a feature buffer for, from clip -> texture space
  featureView(inverseViewProjection: ArrayLike<number>, dims: ArrayLike<number>): number[];
  // frame while it has this size, else destroyed and a new one
  /** for an engine adapter: raw values (raw * slope + intercept, low..high as 0..1) as an R32F 3D texture, made on unit */
  valueTexture(gl: WebGL2RenderingContext, raw: ArrayLike<number>, dims: ArrayLike<number>,
    window: { low: number; high: number; slope?: number; intercept?: number }, unit: number): { texture: WebGLTexture; dims: number[]; values: Float32Array };
  frameOfSize(frame: Frame | null, gl: WebGL2RenderingContext, program: Program, width: number, height: number): Frame;
  // for an engine adapter: pieces, with oneDraw when the stages need a halo field or write
  // outputs; what an engine drawn once cannot serve refused by name (outlines unless served)
  linkForEngine(options: { scene?: string | object; sceneFile?: string; allLive?: boolean; pieces: HaloPieces;
    imageScale?: 1 | 2 | 4 }, engine: string, serves?: string[], what?: { outlines?: boolean }):
    { program: Program; field: boolean; features: boolean; outlines: boolean };
  // for an engine adapter, after frame.draw threw error: for FIELD_MEMORY (a oneDraw program of
  // linkForEngine, no explicit imageScale, under 1/4) the scene linked at twice the halo
  // scale with the live values carried over, and the warning to print; otherwise null
  smallerProgram(program: Program, error: unknown): { program: Program; warning: string } | null;
}

export default function libhalo(options?: object): Promise<Halo>;
