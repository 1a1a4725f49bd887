// Type declarations of libhalo's vtk.js adapter (vtkjs.mjs; docs/hosts/web.md).
import type { Halo, Program, HaloPieces } from './libhalo';

export const SUPPORTED_VERSIONS: readonly string[];   // vtk.js versions it was tested with
export const VTKJS_NAMES: Readonly<HaloPieces>;

export interface VtkjsInstallOptions {
  view: any;                       // the vtkOpenGLRenderWindow drawing the mapper (rendered once already)
  scene?: string | object;
  sceneFile?: string;
  allLive?: boolean;
  window?: [number, number];       // the volume's values that become 0..1 for the stages (default their range)
  interval?: number;               // volumetric halos: M, planes a depth segment (default the scene's)
  fieldMaxBytes?: number;          // the cap on the halo field (default libhalo's)
  imageScale?: 1 | 2 | 4;          // halo images at 1/S per side; without it a field over the cap is linked at 1/2, then 1/4
}

export interface VtkjsInstalled {
  readonly program: Program;     // the one drawn now (another after a field over its cap)
  set(name: string, value: number | boolean | number[] | number[][]): void;  // on the next render
  remove(): void;                  // vtk.js's own shader again, on the next render
}

export function installHalo(halo: Halo, mapper: any, options: VtkjsInstallOptions): VtkjsInstalled;
