/* Conformance rows of feature halos (docs/feature-halos.md): the GPU halo buffer
 * against its double-precision emulation, the emulation against the exact reference,
 * and the per-sample stage feature_halo against its emulation. */
#ifndef HALO_CONFORM_FEATURE_H
#define HALO_CONFORM_FEATURE_H

#include "halo.h"

/* Tolerances of the rows (the measurements behind them: conform_feature.c). */
#define FEATURE_SPLAT_TOLERANCE     1e-6
#define FEATURE_SPLAT_WHY           "float32 weights, unit vectors, pow and R32F additive blending of <= n^3 terms in [0,1]"
#define FEATURE_REFERENCE_TOLERANCE 1e-12
#define FEATURE_REFERENCE_WHY       "the same double sums, scaled by S and (1 - |grad f|): double rounding only"
#define FEATURE_APPLY_TOLERANCE     5e-6
#define FEATURE_APPLY_WHY           "GL_LINEAR lookup of the buffer in float, |grad f| in float, scaled by c1 and c2 up to 50"

/* Prints one row per test in halo-validate conform's format (stage max_abs rmse
 * over_tol nonfinite tolerance PASS|FAIL) to stdout; with verbose, the worst texel and
 * the tolerance's reason on stderr. Uses the current OpenGL context when there is one,
 * else creates a headless one. Returns the rows printed and adds the failed ones to
 * *failed (may be NULL). */
int halo_conform_feature_rows(int verbose, int *failed);

#include "conform_harness.h"

/* The row row->name of the rows above when --stage selects the family (no --stage, or
 * one that begins with "feature"), in halo-validate conform's context. */
void conform_feature_row(conform *c, const conform_row *row);

/* Makes sure lib holds the stage feature_halo: a no-op once the module is embedded;
 * otherwise adds $HALO_FEATURE_MODULE, else glsl/feature/feature_halo.glsl under
 * $srcdir (the test harness's), else under the current directory. */
halo_status halo_feature_ensure_module(halo_library *lib, halo_diagnostics *diag);

#endif
