/* Conformance rows of feature halos (docs/feature-halos.md): the GPU halo buffer
 * against its double-precision emulation, the emulation against the exact reference,
 * and the per-sample stage feature_halo against its emulation. */
#ifndef HALO_CONFORM_FEATURE_H
#define HALO_CONFORM_FEATURE_H

#include "halo.h"

/* Prints one row per test in halo-validate conform's format (stage max_abs rmse
 * over_tol nonfinite tolerance PASS|FAIL) to stdout; with verbose, the worst texel and
 * the tolerance's reason on stderr. Uses the current OpenGL context when there is one,
 * else creates a headless one. Returns the rows printed and adds the failed ones to
 * *failed (may be NULL). */
int halo_conform_feature_rows(int verbose, int *failed);

/* Makes sure lib holds the stage feature_halo: a no-op once the module is embedded;
 * otherwise adds $HALO_FEATURE_MODULE, else glsl/feature/feature_halo.glsl under
 * $srcdir (the test harness's), else under the current directory. */
halo_status halo_feature_ensure_module(halo_library *lib, halo_diagnostics *diag);

#endif
