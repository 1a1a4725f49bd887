/* The error budget: the cheapest configuration of a scene whose error against the
 * exact reference stays within E, chosen from a measured sweep (bench_run.h) with
 * halo_budget_choose and verified by measuring it again. Used by halo-validate bench
 * --max-error and meant for halo-render --max-error (docs/performance.md). */
#ifndef HALO_BENCH_BUDGET_H
#define HALO_BENCH_BUDGET_H

#include "bench_run.h"

/* Picks among measured cases (halo_bench_run, halo_bench_errors): only halo cases with
 * a measured max_abs qualify. Returns HALO_OK and *chosen, or HALO_ERROR_INPUT. */
halo_status halo_bench_budget_pick(const halo_bench_case *cases, size_t count, double max_error, size_t *chosen,
                                   halo_diagnostics *diag);

/* Renders config k again (env->repeat timed frames) and measures its error against the
 * reference image; *verified = 1 when max_abs <= max_error and the image is finite.
 * out receives the measurement (free with halo_bench_cases_free). Returns 1, or 0 on a
 * render failure. */
int halo_bench_budget_verify(const halo_bench_env *env, const float *reference_image, const halo_bench_config *k,
                             double max_error, halo_bench_case *out, int *verified);

/* All of it for a renderer such as halo-render: runs the standard sweep of env's scene
 * and volume (halo_bench_sweep; the scene's halo_generate.passes as N), picks the
 * cheapest configuration within max_error, verifies it and writes it to *choice; a
 * summary goes to report (may be NULL). HALO_ERROR_INPUT when nothing fits or the
 * verification fails, HALO_ERROR_IO when a render fails. */
halo_status halo_bench_budget(const halo_bench_env *env, int scene_passes, double max_error, halo_bench_config *choice,
                              FILE *report);

#endif
