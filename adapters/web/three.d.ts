// Type declarations of libhalo's three.js adapter (three.mjs; docs/hosts/web.md).
import type { Halo, Program, HaloPieces } from './libhalo';

export const MARKERS: { readonly declarations: string; readonly sample: string; readonly finish: string };
export const CASTER_NAMES: Readonly<HaloPieces>;

export interface VolumeCasterOptions {
  volume: Float32Array;            // nx * ny * nz values in [0, 1], x fastest
  dims: [number, number, number];
  transfer: Float32Array;          // N RGBA texels: linear colour, opacity per unit step
  step: number;                    // ray step, texture units
  unitStep?: number;               // the step the opacities are for (default: step)
  background?: [number, number, number];
}

export interface VolumeCaster {
  mesh: any;                       // THREE.Mesh: a box over [0, 1]^3
  material: any;                   // THREE.ShaderMaterial (GLSL 3) with the markers
  volumeTexture: any;              // THREE.Data3DTexture
  transferTexture: any;            // THREE.DataTexture
}

export function createVolumeCaster(THREE: any, options: VolumeCasterOptions): VolumeCaster;

export interface InstallOptions {
  scene?: string | object;
  sceneFile?: string;
  names?: HaloPieces;              // another caster's expressions
  allLive?: boolean;
  volume?: string;                 // volumetric halos: the material's volume texture uniform ('u_volume')
  step?: string;                   // ... and its ray step uniform ('u_step')
  interval?: number;               // ... M, planes a depth segment (default the scene's)
  fieldMaxBytes?: number;          // the cap on the halo field (default libhalo's)
  imageScale?: 1 | 2 | 4;          // halo images at 1/S per side; without it a field over the cap is linked at 1/2, then 1/4
  three?: any;                     // the THREE module: outlines' render targets (required for a scene with outlines)
}

export interface Installed {
  readonly program: Program;     // the one drawn now (another after a field over its cap)
  set(name: string, value: number | boolean | number[] | number[][]): void;
  // renderer.render, with volumetric halos the frame's halo field first (host contract 3); with
  // outlines the scene under the caster, the caster with its outputs, the passes after the draw,
  // then the objects of a greater renderOrder than the caster's over them
  render(renderer: any, scene: any, camera: any): void;
  remove(): void;
}

export function installHalo(halo: Halo, material: any, options?: InstallOptions): Installed;
