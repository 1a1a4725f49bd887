/* Conformance rows of the slice host and the slab ray caster (examples/hosts/slice.h):
 * a whole small render with volumetric halos against a C emulation of the renderer. */
#ifndef HALO_CONFORM_SLICE_H
#define HALO_CONFORM_SLICE_H

#include "conform_harness.h"

/* A slice row's set-up: the scene with two halos (else none), the slab ray caster (else
 * the slice host) at interval M (0: the program's), the halo images at 1/scale. */
typedef struct conform_slice_params {
    int halos, slab, interval, scale;
    int one_draw; /* host contract 3: the slices drawn at once over the field libhalo computes first */
} conform_slice_params;

/* A whole small render (size x size) against the C emulation of the renderer, within
 * row->tolerance_abs per channel; verbose: the worst pixel and the reason on stderr.
 * --stage slice or slab selects every row of the family. */
void conform_slice_row(conform *c, const conform_row *row);

#endif
