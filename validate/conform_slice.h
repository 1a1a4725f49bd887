/* Conformance rows of the slice host and the slab ray caster (examples/hosts/slice.h):
 * a whole small render with volumetric halos against a C emulation of the renderer. */
#ifndef HALO_CONFORM_SLICE_H
#define HALO_CONFORM_SLICE_H

/* Prints the rows slice, slice@nohalo, slab (M = 1) and slab@M4 in halo-validate
 * conform's format (stage max_abs rmse over_tol nonfinite tolerance PASS|FAIL), on a
 * size x size image (25..512). Uses the current OpenGL context when there is one
 * (halo-validate conform's), else creates a headless one. verbose: the worst pixel and
 * the tolerance's reason on stderr. Returns the rows printed; adds the failed ones to
 * *failed (may be NULL). */
int halo_conform_slice_rows(int size, int verbose, int *failed);

#endif
