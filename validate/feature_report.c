/* halo_feature_report_main: the tables of docs/feature-halos.md. */
#include "feature_report.h"

#include "conform_feature.h"
#include "conform_harness.h"
#include "halo_feature.h"
#include "halo_gl_loader.h"
#include "gl/headless.h"
#include "volume.h"
#include "volume_io.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#define DEFAULT_MRI "/usr/share/mricron/templates/ch2better.nii.gz"

static double now_ms(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec * 1e3 + (double)t.tv_nsec * 1e-6;
}

static int compare_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

typedef struct report {
    halo_gl *runtime;
    const halo_glfuncs *f;
    halo_diagnostics *diag;
    int splat, repeat;
} report;

/* The view of the measurements: oblique, like the scenes' cameras. */
static const double report_view[3] = {0.42, 0.34, 0.84};

static void gradient_table_row(const char *name, const float *values, int n)
{
    int dims[3] = {n, n, n};
    size_t count = (size_t)n * n * n;
    float *m = malloc(count * sizeof *m);
    if (!m || halo_feature_gradient_magnitudes(values, dims, m) != HALO_OK) {
        free(m);
        return;
    }
    static const double thresholds[] = {0.05, 0.1, 0.2, 0.4};
    size_t above[4] = {0}, nonzero = 0;
    double max = 0.0;
    for (size_t i = 0; i < count; ++i) {
        for (int t = 0; t < 4; ++t)
            above[t] += m[i] > thresholds[t];
        nonzero += m[i] > 1e-10;
        if (m[i] > max)
            max = m[i];
    }
    printf("| %s (%d^3) | %.2f %% | %.2f %% | %.2f %% | %.2f %% | %.2f %% | %.3f |\n", name, n,
           100.0 * (double)nonzero / (double)count, 100.0 * (double)above[0] / (double)count,
           100.0 * (double)above[1] / (double)count, 100.0 * (double)above[2] / (double)count,
           100.0 * (double)above[3] / (double)count, max);
    free(m);
}

/* Build time (median of repeat builds, glFinish included) and error against the exact
 * reference, for one desc. The error is that of the stage's halo effect
 * h/S = buffer(P_i) (1 - |grad f(P_i)|) at every voxel centre, against the exact h_i/S. */
static int measure(report *r, const char *volume, const float *values, int n, const halo_feature_desc *desc,
                   const double *exact, double exact_max, const char *label)
{
    int dims[3] = {n, n, n};
    size_t count = (size_t)n * n * n;
    halo_feature_layout layout = halo_feature_desc_layout(desc, dims);
    const int *bd = layout.buffer_dims;
    size_t texels = (size_t)bd[0] * bd[1] * bd[2];
    double t0 = now_ms();
    halo_feature_buffer *b = halo_feature_buffer_create(r->runtime, values, dims, desc, r->diag);
    double create_ms = now_ms() - t0;
    float *buffer = malloc(texels * sizeof *buffer);
    double *buffer_double = malloc(texels * sizeof *buffer_double);
    double *times = malloc((size_t)r->repeat * sizeof *times);
    if (!b || !buffer || !buffer_double || !times) {
        halo_diagnostics_print(r->diag, stderr);
        halo_feature_buffer_destroy(b);
        free(buffer), free(buffer_double), free(times);
        return 0;
    }
    int ok = 1;
    for (int k = 0; k < r->repeat && ok; ++k) {
        /* a slightly different view each time: a rebuild as after a camera move */
        double view[3] = {report_view[0] + 0.01 * k, report_view[1], report_view[2]};
        r->f->Finish();
        double start = now_ms();
        ok = halo_feature_buffer_build(b, view) == HALO_OK;
        r->f->Finish();
        times[k] = now_ms() - start;
    }
    ok = ok && halo_feature_buffer_build(b, report_view) == HALO_OK && halo_feature_buffer_read(b, buffer) == HALO_OK;
    if (!ok) {
        halo_diagnostics_print(r->diag, stderr);
        halo_feature_buffer_destroy(b);
        free(buffer), free(buffer_double), free(times);
        return 0;
    }
    qsort(times, (size_t)r->repeat, sizeof *times, compare_double);
    for (size_t i = 0; i < texels; ++i)
        buffer_double[i] = buffer[i];
    double sum = halo_feature_desc_layout(desc, NULL).splat_weight_sum;
    double max_abs = 0.0, sum_squares = 0.0;
    size_t i = 0, over = 0;
    float *magnitude = malloc(count * sizeof *magnitude);
    halo_feature_gradient_magnitudes(values, dims, magnitude);
    for (int z = 0; z < n; ++z)
        for (int y = 0; y < n; ++y)
            for (int x = 0; x < n; ++x, ++i) {
                double p[3] = {(x + 0.5) / n, (y + 0.5) / n, (z + 0.5) / n};
                double factor = 1.0 - (double)magnitude[i];
                factor = factor < 0 ? 0 : factor;
                double approx = halo_feature_buffer_lookup(buffer_double, bd, p) * factor;
                double e = fabs(approx - exact[i] / sum);
                max_abs = e > max_abs ? e : max_abs;
                sum_squares += e * e;
                over += e > 0.01;
            }
    free(magnitude);
    printf("| %s | %s | %zu (%.2f %%) | %zu | %.1f | %.1f | %.4f | %.2e | %.3f %% |\n", volume, label,
           halo_feature_buffer_describe(b).qualified,
           100.0 * (double)halo_feature_buffer_describe(b).qualified / (double)texels,
           halo_feature_buffer_describe(b).points_drawn, create_ms, times[r->repeat / 2], max_abs / (exact_max / sum),
           sqrt(sum_squares / (double)count), 100.0 * (double)over / (double)count);
    fflush(stdout);
    halo_feature_buffer_destroy(b);
    free(buffer), free(buffer_double), free(times);
    return 1;
}

typedef struct variant {
    double threshold;
    int half;
    const char *label;
} variant;

static int report_volume(report *r, const char *name, const float *values, int n, int weighted)
{
    int dims[3] = {n, n, n};
    size_t count = (size_t)n * n * n;
    double *exact = malloc(count * sizeof *exact);
    halo_feature_desc reference_desc = {.splat_size = r->splat, .gradient_weighted = weighted};
    double t0 = now_ms();
    if (!exact ||
        halo_feature_compute(HALO_FEATURE_REFERENCE, values, dims, &reference_desc, report_view, exact) != HALO_OK) {
        free(exact);
        return 0;
    }
    double reference_ms = now_ms() - t0;
    double exact_max = 0.0;
    for (size_t i = 0; i < count; ++i)
        exact_max = exact[i] > exact_max ? exact[i] : exact_max;
    double sum = halo_feature_desc_layout(&reference_desc, NULL).splat_weight_sum;
    fprintf(stderr, "%s%s: exact reference (CPU, 1 thread) %.0f ms; max h_i %.4f (= %.4f after / S, S = %.4f)\n", name,
            weighted ? " (gradient-weighted)" : "", reference_ms, exact_max, exact_max / sum, sum);
    static const variant ebert[] = {{-1, 0, "Ebert, no cutoff"},
                                    {0.1, 0, "Ebert, cutoff 0.1"},
                                    {0.2, 0, "Ebert, cutoff 0.2"},
                                    {-1, 1, "Ebert, no cutoff, half res."},
                                    {0.1, 1, "Ebert, cutoff 0.1, half res."}};
    static const variant ivis[] = {{-1, 0, "weighted, no cutoff"},
                                   {0.05, 0, "weighted, cutoff 0.05"},
                                   {0.1, 0, "weighted, cutoff 0.1"},
                                   {0.2, 0, "weighted, cutoff 0.2"},
                                   {0.4, 0, "weighted, cutoff 0.4"},
                                   {-1, 1, "weighted, no cutoff, half res."},
                                   {0.1, 1, "weighted, cutoff 0.1, half res."}};
    const variant *list = weighted ? ivis : ebert;
    size_t list_count = weighted ? sizeof ivis / sizeof *ivis : sizeof ebert / sizeof *ebert;
    int ok = 1;
    for (size_t t = 0; t < list_count && ok; ++t) {
        halo_feature_desc desc = {.splat_size = r->splat,
                                  .threshold = list[t].threshold,
                                  .half_resolution = list[t].half,
                                  .gradient_weighted = weighted};
        ok = measure(r, name, values, n, &desc, exact, exact_max, list[t].label);
    }
    free(exact);
    return ok;
}

int halo_feature_report_main(int argc, char **argv)
{
    int size = HALO_VOLUME_DEFAULT_SIZE, mri_size = 128, splat = 5, repeat = 3;
    const char *mri = DEFAULT_MRI;
    for (int i = 0; i < argc; ++i) {
        const char *a = argv[i];
        int has = i + 1 < argc;
        if (!strcmp(a, "--size") && has)
            size = atoi(argv[++i]);
        else if (!strcmp(a, "--mri") && has)
            mri = argv[++i];
        else if (!strcmp(a, "--mri-size") && has)
            mri_size = atoi(argv[++i]);
        else if (!strcmp(a, "--splat") && has)
            splat = atoi(argv[++i]);
        else if (!strcmp(a, "--repeat") && has)
            repeat = atoi(argv[++i]);
        else {
            fprintf(stderr,
                    "feature report: unknown argument '%s'\n"
                    "usage: [--size N] [--mri PATH] [--mri-size N] [--splat N] [--repeat N]\n",
                    a);
            return 2;
        }
    }
    if (size < HALO_VOLUME_MIN_SIZE || size > HALO_VOLUME_MAX_SIZE || mri_size < 8 || mri_size > 512 ||
        splat < HALO_FEATURE_SPLAT_MIN || splat > HALO_FEATURE_SPLAT_MAX || splat % 2 == 0 || repeat < 1 ||
        repeat > 100) {
        fprintf(stderr, "feature report: --size 8..512, --mri-size 8..512, --splat 3, 5, 7 or 9, --repeat 1..100\n");
        return 2;
    }
    report r = {.splat = splat, .repeat = repeat};
    r.diag = halo_diagnostics_create();
    halo_setup(NULL);
    halo_headless *context = NULL;
    char context_err[512];
    r.runtime = conform_gl_current_or_headless(&context, r.diag, context_err, sizeof context_err);
    if (!r.runtime && !context) {
        fprintf(stderr, "feature report: %s\n", context_err);
        halo_diagnostics_destroy(r.diag);
        halo_shutdown();
        return 77;
    }
    int status = 1;
    float *builtin = NULL, *head = NULL;
    halo_volume_file file = {0};
    if (!r.runtime)
        goto done;
    r.f = halo_headless_functions();
    fprintf(stderr, "feature report: %s\n", (const char *)r.f->GetString(GL_RENDERER));
    builtin = halo_volume_create(size);
    if (!builtin)
        goto done;
    int head_size = 0;
    char err[512] = "";
    FILE *probe = fopen(mri, "rb");
    if (probe) {
        fclose(probe);
        if (halo_volume_read_nifti(mri, &file, err, sizeof err) == HALO_VOLUME_OK) {
            double window[2];
            halo_volume_percentile_window(&file, 1.0, 99.0, window);
            head_size = halo_volume_display_size(&file, mri_size);
            head = halo_volume_to_display(&file, window, head_size);
        } else {
            fprintf(stderr, "feature report: %s (skipped)\n", err);
        }
    } else {
        fprintf(stderr, "feature report: %s not found: the MRI head is skipped\n", mri);
    }
    printf(
        "Share of voxels above gradient thresholds (|grad f| in normalized value per voxel step, central\n"
        "differences / 2; the largest possible is sqrt(3)/2 = 0.866):\n\n");
    printf("| volume | > 0 | > 0.05 | > 0.1 | > 0.2 | > 0.4 | max |\n|---|---|---|---|---|---|---|\n");
    gradient_table_row("built-in", builtin, size);
    if (head)
        gradient_table_row("MRI head", head, head_size);
    printf(
        "\nHalo buffer: %dx%dx%d splat, view (%.2f, %.2f, %.2f), median of %d builds; error of the halo\n"
        "effect h/S at every voxel against the exact reference, max relative to the largest exact value,\n"
        "RMSE absolute, share of voxels off by more than 0.01:\n\n",
        splat, splat, splat, report_view[0], report_view[1], report_view[2], repeat);
    printf(
        "| volume | buffer | qualified | points drawn | preprocess ms | build ms | max error / max h | RMSE | > 0.01 |\n"
        "|---|---|---|---|---|---|---|---|---|\n");
    char name[64];
    snprintf(name, sizeof name, "built-in %d^3", size);
    for (int weighted = 0; weighted < 2; ++weighted) {
        snprintf(name, sizeof name, "built-in %d^3", size);
        if (!report_volume(&r, name, builtin, size, weighted))
            goto done;
        if (head) {
            snprintf(name, sizeof name, "MRI head %d^3", head_size);
            if (!report_volume(&r, name, head, head_size, weighted))
                goto done;
        }
    }
    status = 0;
done:
    if (status)
        halo_diagnostics_print(r.diag, stderr);
    free(builtin);
    free(head);
    halo_volume_file_free(&file);
    halo_gl_destroy(r.runtime);
    halo_headless_destroy(context);
    halo_diagnostics_destroy(r.diag);
    halo_shutdown();
    return status;
}
