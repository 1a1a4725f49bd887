/* halo-validate bench: Table 1 of Bruckner & Groller 2007 on this machine. The slice
 * host (examples/hosts/slice.h) renders the built-in volume without halos (the
 * reference: the same host and scene with the halo stages off) and with one emissive
 * halo for M = 1, 2, 4, 8 slices between generations; the slab ray caster renders the
 * same with M samples per draw. Each configuration: the median of R frames, glFinish
 * before and after each; all measured in the same run. Each M's image is compared with
 * M = 1's of the same renderer. */
#include "bench.h"

#include "halo.h"
#include "gl/glfuncs.h"
#include "gl/headless.h"
#include "hosts/slab.h"
#include "hosts/slice.h"
#include "volume.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

/* The paper's Table 1: halo frame rate as % of the reference (29.34 fps), GeForce 8800 GTX. */
static const int paper_m[4] = {1, 2, 4, 8};
static const double paper_percent[4] = {15.85, 26.31, 34.97, 42.91};

#define BENCH_RENDER                                                                                  \
    "\"render\": {\"azimuth\": 30, \"elevation\": 20, \"zoom\": 1.3, \"step\": 0.5,"                  \
    " \"background\": [0.05, 0.08, 0.25],"                                                            \
    " \"transfer\": [[0, 0, 0, 0, 0], [0.2, 0.6, 0.8, 1, 0], [0.3, 0.6, 0.8, 1, 0.08],"              \
    "  [0.5, 1, 0.85, 0.55, 0.3], [0.75, 0.95, 0.3, 0.2, 0.7], [1, 1, 1, 0.8, 0.9]]}"

static const char bench_reference_scene[] = "{\"halo_scene\": 1, \"stages\": [], " BENCH_RENDER "}";
/* One emissive halo with the paper's seeding exponents (alpha 32, beta 0.125), N = 4. */
static const char bench_halo_scene[] =
    "{\"halo_scene\": 1, \"stages\": ["
    " {\"halo_seed\": {}}, {\"halo_generate\": {\"passes\": 4, \"delta\": 0.8}},"
    " {\"halo_map\": {\"mode\": 0, \"color_near\": [[1, 0.9, 0.4]], \"color_far\": [[1, 0.3, 0.1]], \"opacity\": 0.9}}], "
    BENCH_RENDER "}";

static double now_seconds(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + (double)t.tv_nsec * 1e-9;
}

static int compare_doubles(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

typedef struct bench {
    halo_library *lib;
    halo_gl *runtime;
    const halo_glfuncs *gl;
    halo_diagnostics *diag;
    int size, volume_size, repeat;
    float *volume;
} bench;

typedef struct bench_result {
    const char *renderer;
    int halos, interval;
    int slices;
    long draws, pass_draws;
    double seconds; /* median */
    float *image;
} bench_result;

/* Renders one configuration repeat times; keeps the last image. Returns 0 on failure. */
static int run_config(bench *b, const char *scene_text, int slab, int interval, bench_result *out)
{
    int ok = 0;
    halo_scene *scene = halo_scene_parse(scene_text, "(bench scene)", b->lib, b->diag);
    char *source = halo_host_load(slab ? "slab.frag" : "slice.frag", NULL, b->diag);
    halo_program *program = NULL;
    halo_slice *host = NULL;
    double *times = calloc((size_t)b->repeat, sizeof *times);
    out->image = malloc((size_t)b->size * (size_t)b->size * 4 * sizeof(float));
    if (!scene || !source || !times || !out->image)
        goto done;
    program = halo_link(&(halo_link_desc){.library = b->lib, .scene = scene, .host_source = source,
                                          .host_file = slab ? "slab.frag" : "slice.frag"},
                        b->diag);
    if (!program)
        goto done;
    halo_host_desc desc = {.gl = b->gl, .runtime = b->runtime, .program = program, .width = b->size,
                           .height = b->size};
    host = slab ? halo_slab_create(&desc, b->diag) : halo_slice_create(&desc, b->diag);
    if (!host)
        goto done;
    const halo_render_settings *settings = halo_scene_render(scene);
    if (halo_slice_set_volume(host, b->volume, b->volume_size, b->volume_size, b->volume_size, b->diag) != HALO_OK ||
        halo_slice_set_render(host, settings, b->diag) != HALO_OK)
        goto done;
    halo_slice_set_camera(host, settings->azimuth, settings->elevation, settings->zoom);
    halo_slice_set_interval(host, interval);
    /* one frame to warm up (shader compilation on first draw, texture residency) */
    if (halo_slice_render(host, out->image, b->diag) != HALO_OK)
        goto done;
    for (int r = 0; r < b->repeat; ++r) {
        b->gl->Finish();
        double start = now_seconds();
        if (halo_slice_render(host, out->image, b->diag) != HALO_OK)
            goto done;
        b->gl->Finish();
        times[r] = now_seconds() - start;
    }
    qsort(times, (size_t)b->repeat, sizeof *times, compare_doubles);
    out->seconds = b->repeat % 2 ? times[b->repeat / 2] : 0.5 * (times[b->repeat / 2 - 1] + times[b->repeat / 2]);
    halo_slice_state state;
    halo_slice_get_state(host, &state);
    out->slices = state.slice_count;
    out->interval = state.interval;
    out->draws = halo_slice_draws(host);
    out->pass_draws = halo_slice_pass_draws(host);
    ok = 1;
done:
    if (!ok)
        halo_diagnostics_print(b->diag, stderr);
    halo_diagnostics_clear(b->diag);
    halo_slice_destroy(host);
    halo_program_destroy(program);
    halo_scene_destroy(scene);
    free(source);
    free(times);
    return ok;
}

/* Error of image against base: max abs, RMSE over colour, share of pixels with a channel off by > 1/255. */
static void image_error(const float *image, const float *base, size_t pixels, double *max_abs, double *rmse,
                        double *share)
{
    double m = 0.0, sum = 0.0;
    size_t over = 0;
    for (size_t i = 0; i < pixels; ++i) {
        int off = 0;
        for (int c = 0; c < 3; ++c) {
            double e = fabs((double)image[i * 4 + (size_t)c] - (double)base[i * 4 + (size_t)c]);
            m = e > m ? e : m;
            sum += e * e;
            off |= e > 1.0 / 255.0;
        }
        over += (size_t)off;
    }
    *max_abs = m;
    *rmse = pixels ? sqrt(sum / (double)(pixels * 3)) : 0.0;
    *share = pixels ? (double)over / (double)pixels : 0.0;
}

static void bench_usage(FILE *out)
{
    fputs("Usage: halo-validate bench [--size N] [--volume-size N] [--repeat R] [--table1]\n"
          "Frame time of the slice host (view-aligned slices, as Bruckner & Groller 2007) without\n"
          "halos and with one emissive halo generated every M = 1, 2, 4, 8 slices, and of the slab\n"
          "ray caster (M samples per draw); the median of R frames each, glFinish around each.\n"
          "  --size N         image side in pixels, 16..2048 (default 512)\n"
          "  --volume-size N  built-in volume side in voxels, 8..512 (default 128)\n"
          "  --repeat R       frames per configuration, 1..101 (default 3)\n"
          "  --table1         also print the paper's Table 1 beside the measured rates\n",
          out);
}

static int parse_int(const char *text, int low, int high, int *out)
{
    char *end = NULL;
    errno = 0;
    long n = strtol(text, &end, 10);
    if (end == text || *end != '\0' || errno == ERANGE || n < low || n > high)
        return 0;
    *out = (int)n;
    return 1;
}

int halo_bench_main(int argc, char **argv)
{
    bench b = {.size = 512, .volume_size = 128, .repeat = 3};
    int table1 = 0;
    for (int i = 1; i < argc; ++i) {
        const char *a = argv[i];
        if (!strcmp(a, "--help") || !strcmp(a, "-h")) {
            bench_usage(stdout);
            return 0;
        } else if (!strcmp(a, "--table1")) {
            table1 = 1;
        } else if (!strcmp(a, "--size") && i + 1 < argc) {
            if (!parse_int(argv[++i], 16, 2048, &b.size)) {
                fprintf(stderr, "halo-validate: bench: --size: '%s' is not an integer in 16..2048\n", argv[i]);
                return 2;
            }
        } else if (!strcmp(a, "--volume-size") && i + 1 < argc) {
            if (!parse_int(argv[++i], HALO_VOLUME_MIN_SIZE, HALO_VOLUME_MAX_SIZE, &b.volume_size)) {
                fprintf(stderr, "halo-validate: bench: --volume-size: '%s' is not an integer in %d..%d\n", argv[i],
                        HALO_VOLUME_MIN_SIZE, HALO_VOLUME_MAX_SIZE);
                return 2;
            }
        } else if (!strcmp(a, "--repeat") && i + 1 < argc) {
            if (!parse_int(argv[++i], 1, 101, &b.repeat)) {
                fprintf(stderr, "halo-validate: bench: --repeat: '%s' is not an integer in 1..101\n", argv[i]);
                return 2;
            }
        } else {
            fprintf(stderr, "halo-validate: bench: unknown or incomplete argument '%s'\n", a);
            bench_usage(stderr);
            return 2;
        }
    }
    int status = 2;
    halo_headless *context = NULL;
    enum { CONFIGS = 12 };
    bench_result results[CONFIGS];
    memset(results, 0, sizeof results);
    b.diag = halo_diagnostics_create();
    if (!b.diag || halo_setup(NULL) != HALO_OK) {
        fprintf(stderr, "halo-validate: bench: cannot initialize libhalo\n");
        halo_diagnostics_destroy(b.diag);
        return 2;
    }
    b.lib = halo_library_create(b.diag);
    b.volume = halo_volume_create(b.volume_size);
    char err[512];
    context = halo_headless_create(b.size, b.size, err, sizeof err);
    if (!context) {
        fprintf(stderr, "halo-validate: bench: %s\n", err);
        goto cleanup;
    }
    b.runtime = halo_gl_create(&(halo_gl_desc){.get_proc_address = halo_headless_get_proc_address}, b.diag);
    if (!b.lib || !b.volume || !b.runtime) {
        halo_diagnostics_print(b.diag, stderr);
        goto cleanup;
    }
    b.gl = halo_gl_functions(b.runtime);
    const char *renderer = (const char *)b.gl->GetString(GL_RENDERER);

    /* The slice reference first (every % is against it); NO_GENERATION: seeding and mapping
     * per sample but no image pass (M beyond the last slice), the paper's "seeding and
     * mapping alone"; the slab reference batches 8 samples per draw. */
    enum { NO_GENERATION = 1 << 20 };
    struct { const char *name; int halos, slab, interval; } configs[] = {
        {"slice", 0, 0, 1}, {"slice", 1, 0, 1}, {"slice", 1, 0, 2}, {"slice", 1, 0, 4}, {"slice", 1, 0, 8},
        {"slice", 1, 0, NO_GENERATION},
        {"slab", 0, 1, 8}, {"slab", 1, 1, 1}, {"slab", 1, 1, 2}, {"slab", 1, 1, 4}, {"slab", 1, 1, 8},
    };
    size_t config_count = sizeof configs / sizeof configs[0];
    for (size_t i = 0; i < config_count; ++i) {
        fprintf(stderr, "bench: %s, %s, M = %d (%zu of %zu)...\n", configs[i].name,
                configs[i].halos ? "one halo" : "no halos", configs[i].interval == NO_GENERATION ? 0 : configs[i].interval,
                i + 1, config_count);
        results[i].renderer = configs[i].name;
        results[i].halos = configs[i].halos;
        if (!run_config(&b, configs[i].halos ? bench_halo_scene : bench_reference_scene, configs[i].slab,
                        configs[i].interval, &results[i]))
            goto cleanup;
        fprintf(stderr, "bench:   %.1f ms\n", results[i].seconds * 1e3);
    }
    printf("# halo-validate bench: %dx%d image, %d^3 built-in volume, %d slices (sample distance 0.5 voxel),\n"
           "# median of %d frames, %s\n", b.size, b.size, b.volume_size, results[0].slices, b.repeat,
           renderer ? renderer : "?");
    printf("# M = -: seeding and mapping per sample, no generation (the halo field stays empty)\n");
    printf("%-6s %-6s %3s %6s %7s %10s %8s %9s %9s %10s %10s %8s\n", "host", "halos", "M", "draws", "passes",
           "ms/frame", "fps", "%ref", table1 ? "paper%" : "", "max_abs", "rmse", ">1/255");
    size_t pixels = (size_t)b.size * (size_t)b.size;
    for (size_t i = 0; i < config_count; ++i) {
        const bench_result *r = &results[i];
        double reference = results[0].seconds;
        char paper[16] = "";
        int is_slice = strcmp(r->renderer, "slice") == 0;
        if (table1 && r->halos && is_slice)
            for (int k = 0; k < 4; ++k)
                if (paper_m[k] == r->interval)
                    snprintf(paper, sizeof paper, "%.2f", paper_percent[k]);
        char errors[64] = "";
        const bench_result *base = NULL; /* M = 1 of the same renderer */
        for (size_t j = 0; j < config_count && r->halos && r->interval != NO_GENERATION; ++j)
            if (results[j].halos && results[j].interval == 1 && strcmp(results[j].renderer, r->renderer) == 0)
                base = &results[j];
        double max_abs = 0, rmse = 0, share = 0;
        if (base && base != r)
            image_error(r->image, base->image, pixels, &max_abs, &rmse, &share);
        if (base && base != r)
            snprintf(errors, sizeof errors, "%10.3e %10.3e %7.2f%%", max_abs, rmse, 100.0 * share);
        else
            snprintf(errors, sizeof errors, "%10s %10s %8s", "-", "-", "-");
        char interval[16];
        snprintf(interval, sizeof interval, "%d", r->interval);
        printf("%-6s %-6s %3s %6ld %7ld %10.1f %8.3f %8.2f%% %9s %s\n", r->renderer, r->halos ? "1" : "0",
               r->interval == NO_GENERATION ? "-" : interval, r->draws, r->pass_draws, r->seconds * 1e3, 1.0 / r->seconds,
               100.0 * reference / r->seconds, paper, errors);
    }
    if (table1)
        printf("# paper (GeForce 8800 GTX, 256^3, 512^2, sample distance 0.5): reference 29.34 fps;"
               " M = 1, 2, 4, 8: 15.85, 26.31, 34.97, 42.91 %% of it\n");
    status = 0;
cleanup:
    for (size_t i = 0; i < CONFIGS; ++i)
        free(results[i].image);
    free(b.volume);
    halo_gl_destroy(b.runtime);
    halo_headless_destroy(context);
    halo_library_destroy(b.lib);
    halo_diagnostics_destroy(b.diag);
    halo_shutdown();
    return status;
}
