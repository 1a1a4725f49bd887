// Type declarations of libhalo's NiiVue adapter (niivue.mjs; docs/hosts/web.md).
import type { Halo, Program, HaloPieces } from './libhalo';

export const SUPPORTED_VERSIONS: readonly string[];   // NiiVue versions whose render shader it knows
export const NIIVUE_NAMES: Readonly<HaloPieces>;

export interface NiivueInstallOptions {
  scene?: string | object;
  sceneFile?: string;
  allLive?: boolean;
  interval?: number;               // volumetric halos: M, planes a depth segment (default the scene's)
  fieldMaxBytes?: number;          // the cap on the halo field (default libhalo's)
  imageScale?: 1 | 2 | 4;          // halo images at 1/S per side; without it a field over the cap is linked at 1/2, then 1/4
  firstUnit?: number;              // libhalo's textures from this unit on (default 20; the value copy one below)
}

export interface NiivueView {
  readonly inverseViewProjection: Float64Array; // clip space -> NiiVue's texture space, column-major
  readonly step: number;           // the ray step given to libhalo, texture units
  readonly width: number;          // the 3D view's size in pixels
  readonly height: number;
}

export interface NiivueInstalled {
  readonly program: Program;     // the one drawn now (another after a field over its cap)
  readonly view: NiivueView | null; // the camera of the last frame drawn with the stages
  set(name: string, value: number | boolean | number[] | number[][]): void;
  remove(): void;                  // NiiVue's own shader and drawImage3D again
}

export function installHalo(halo: Halo, nv: any, options?: NiivueInstallOptions): NiivueInstalled;
