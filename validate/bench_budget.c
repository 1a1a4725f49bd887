/* The error budget (bench_budget.h). */
#include "bench_budget.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

halo_status halo_bench_budget_pick(const halo_bench_case *cases, size_t count, double max_error, size_t *chosen,
                                   halo_diagnostics *diag)
{
    halo_budget_row *rows = calloc(count ? count : 1, sizeof *rows);
    if (!rows)
        return HALO_ERROR_IO;
    for (size_t i = 0; i < count; ++i) {
        rows[i].seconds = cases[i].seconds;
        /* renders without halos, or without generation, are no configuration of the scene */
        rows[i].error =
            cases[i].config.halos && !cases[i].config.no_generation && cases[i].nonfinite == 0 ? cases[i].max_abs : NAN;
    }
    halo_status status = halo_budget_choose(rows, count, max_error, chosen, diag);
    free(rows);
    return status;
}

int halo_bench_budget_verify(const halo_bench_env *env, const float *reference_image, const halo_bench_config *k,
                             double max_error, halo_bench_case *out, int *verified)
{
    memset(out, 0, sizeof *out);
    out->config = *k;
    out->axis = "verify";
    *verified = 0;
    if (!halo_bench_run(env, out, 1))
        return 0;
    size_t pixels = (size_t)env->width * (size_t)env->height;
    halo_bench_image_error(out->image, reference_image, pixels, &out->max_abs, &out->rmse, &out->share_over);
    *verified = out->nonfinite == 0 && out->max_abs <= max_error;
    return 1;
}

halo_status halo_bench_budget(const halo_bench_env *env, int scene_passes, double max_error, halo_bench_config *choice,
                              FILE *report)
{
    halo_bench_case cases[48];
    size_t count = halo_bench_sweep(cases, sizeof cases / sizeof cases[0], scene_passes, 0.25);
    halo_status status = HALO_ERROR_IO;
    if (!halo_bench_run(env, cases, count))
        goto done;
    halo_bench_errors(env, cases, count, 0);
    size_t chosen = 0;
    status = halo_bench_budget_pick(cases, count, max_error, &chosen, env->diag);
    if (status != HALO_OK)
        goto done;
    halo_bench_case check;
    int verified = 0;
    if (!halo_bench_budget_verify(env, cases[0].image, &cases[chosen].config, max_error, &check, &verified)) {
        status = HALO_ERROR_IO;
        halo_bench_cases_free(&check, 1);
        goto done;
    }
    const halo_bench_config *k = &cases[chosen].config;
    if (report)
        fprintf(report,
                "budget: max error %g: %s, M = %d, N = %d, %d-bit halo images at %s resolution, step %g voxel, %s "
                "gradients: %.1f "
                "ms/frame, max abs "
                "error %.3e (sweep) / %.1f ms, %.3e (verified: %s); the exact reference %.1f ms\n",
                max_error, k->slab ? "slab" : "slice", k->interval, k->passes, k->precision, halo_bench_resolution(k),
                k->step, halo_bench_gradient(k), cases[chosen].seconds * 1e3, cases[chosen].max_abs,
                check.seconds * 1e3, check.max_abs, verified ? "within" : "NOT within", cases[0].seconds * 1e3);
    *choice = *k;
    status = verified ? HALO_OK : HALO_ERROR_INPUT;
    halo_bench_cases_free(&check, 1);
done:
    halo_bench_cases_free(cases, count);
    return status;
}
