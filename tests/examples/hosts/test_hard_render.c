/* Hard cases of whole renders (docs/hard-cases.md): the slice host and the slab ray
 * caster (the GPU path, OSMesa) against the double-precision emulation of the same
 * renderer (validate/conform_slice.c), on volumes and parameters chosen to reach the
 * numerically fragile spots: NaN and Inf voxels, denormals, huge values with 16-bit
 * and 8-bit halo images, a constant volume (zero gradients), tiny gradients with
 * alpha = 64, n.V = +-1 with beta = 0 and near 0, delta 0 and 1, empty and full seed
 * images, the smallest volume (2^3; 1^3 is refused with a diagnostic), depth cues at
 * depth 0 and 1. Every result must be finite; where the inputs are finite, within
 * the conformance tolerance of the emulation. Exit 77 without OpenGL. */
#include "../../gl_fixture.h"
#include "hosts/slab.h"
#include "hosts/slice.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int halo_conform_slice_emulate(const halo_slice_state *s, const halo_program *p, int interval, double *out,
                               halo_diagnostics *diag);

#define SIZE 24
#define RENDER(AZ, EL)                                       \
    "\"render\": {\"azimuth\": " #AZ ", \"elevation\": " #EL \
    ", \"zoom\": 1.3, \"step\": 0.5,"                        \
    " \"background\": [0.05, 0.08, 0.25],"                   \
    " \"transfer\": [[0, 0, 0, 0, 0], [0.2, 0.6, 0.8, 1, 0.3], [0.5, 1, 0.85, 0.55, 0.5], [1, 1, 1, 0.8, 0.9]]}"
#define MAP " {\"halo_map\": {\"mode\": [0, 1], \"color_near\": [[1, 0.9, 0.4], [0, 0, 0]], \"opacity\": [0.9, 0.7]}}"
#define HALOS(SEED, GENERATE) \
    "{\"halo_scene\": 1, \"stages\": [{\"halo_seed\": " SEED "}, {\"halo_generate\": " GENERATE "}," MAP "], "

typedef enum volume_kind {
    VOLUME_SPHERE,   /* smooth sphere: ordinary gradients */
    VOLUME_NAN,      /* the sphere with NaN and +-Inf voxels */
    VOLUME_DENORMAL, /* the sphere scaled into float denormals (~1e-39) */
    VOLUME_HUGE,     /* the sphere scaled by 1e6 (gradients and values beyond half float's 65504) */
    VOLUME_CONSTANT, /* 0.5 everywhere: zero gradients */
    VOLUME_TINY,     /* 0.5 + 1e-9 x: a gradient too small to seed with alpha = 64 */
    VOLUME_RAMP_Z,   /* a ramp along z: n parallel to the view when looking along z */
    VOLUME_NOISE     /* hash noise: seeds everywhere */
} volume_kind;

typedef struct hard_case {
    const char *name;
    volume_kind volume;
    int side; /* voxels per side */
    const char *scene;
    int precision; /* halo image precision */
    int slab, interval;
    double tolerance; /* against the emulation; < 0: finite only (the inputs are not finite) */
} hard_case;

static const hard_case cases[] = {
    {"nan_inf_volume", VOLUME_NAN, 10, HALOS("{}", "{\"passes\": 3}") RENDER(30, 20) "}", 32, 0, 4, -1},
    {"nan_inf_volume@slab", VOLUME_NAN, 10, HALOS("{}", "{\"passes\": 3}") RENDER(30, 20) "}", 32, 1, 4, -1},
    {"nan_inf_volume@nohalo", VOLUME_NAN, 10, "{\"halo_scene\": 1, \"stages\": [], " RENDER(30, 20) "}", 32, 0, 1, -1},
    {"nan_inf_volume@sample_stages", VOLUME_NAN, 10,
     "{\"halo_scene\": 1, \"stages\": [{\"boundary\": {}}, {\"silhouette\": {}}, {\"tone_shading\": {}},"
     " {\"sketch\": {}}, {\"orientation_fade\": {}}], " RENDER(30, 20) "}",
     32, 0, 1, -1},
    {"denormal_volume", VOLUME_DENORMAL, 10, HALOS("{\"alpha\": 64}", "{}") RENDER(30, 20) "}", 32, 0, 4, 5e-4},
    {"huge_values@16bit", VOLUME_HUGE, 10, HALOS("{\"alpha\": 1, \"gradient_scale\": 1000}", "{}") RENDER(30, 20) "}",
     16, 0, 4, 5e-3},
    {"huge_values@8bit", VOLUME_HUGE, 10, HALOS("{\"alpha\": 1, \"gradient_scale\": 1000}", "{}") RENDER(30, 20) "}", 8,
     1, 4, 2e-2},
    {"constant_volume", VOLUME_CONSTANT, 10, HALOS("{\"alpha\": 0, \"beta\": 0}", "{}") RENDER(30, 20) "}", 32, 0, 4,
     5e-4},
    {"tiny_gradient@alpha64", VOLUME_TINY, 10,
     HALOS("{\"alpha\": 64, \"gradient_scale\": 1000}", "{}") RENDER(30, 20) "}", 32, 0, 4, 5e-4},
    {"n_parallel_v@beta0", VOLUME_RAMP_Z, 10, HALOS("{\"alpha\": 0, \"beta\": 0}", "{}") RENDER(0, 0) "}", 32, 0, 4,
     5e-4},
    {"n_parallel_v@beta1e-3", VOLUME_RAMP_Z, 10, HALOS("{\"alpha\": 0, \"beta\": 0.001}", "{}") RENDER(0, 0) "}", 32, 1,
     2, 5e-4},
    {"delta0", VOLUME_SPHERE, 10, HALOS("{\"alpha\": 1}", "{\"delta\": 0}") RENDER(30, 20) "}", 32, 0, 4, 5e-4},
    {"delta1", VOLUME_SPHERE, 10, HALOS("{\"alpha\": 1}", "{\"delta\": 1, \"passes\": 6}") RENDER(30, 20) "}", 32, 0, 4,
     5e-4},
    {"empty_seed", VOLUME_SPHERE, 10, HALOS("{\"gradient_scale\": 0}", "{}") RENDER(30, 20) "}", 32, 0, 4, 5e-4},
    {"full_seed", VOLUME_NOISE, 10,
     HALOS("{\"alpha\": 0, \"beta\": 0, \"gradient_scale\": 1000}", "{\"median\": true}") RENDER(30, 20) "}", 32, 0, 4,
     5e-4},
    {"volume_2x2x2", VOLUME_SPHERE, 2, HALOS("{\"alpha\": 1}", "{}") RENDER(30, 20) "}", 32, 0, 4, 5e-4},
    {"depth_0_1_cues", VOLUME_SPHERE, 10,
     "{\"halo_scene\": 1, \"stages\": [{\"distance_blend\": {\"k_de\": 0}}, {\"distance_cue\": {}}], " RENDER(30,
                                                                                                              20) "}",
     32, 0, 1, 5e-4},
};

static float hash_noise(unsigned x)
{
    x ^= x >> 16;
    x *= 0x7feb352dU;
    x ^= x >> 15;
    x *= 0x846ca68bU;
    x ^= x >> 16;
    return (float)(x & 0xffffff) / 16777216.0f;
}

static float *make_volume(volume_kind kind, int n)
{
    float *v = malloc((size_t)n * (size_t)n * (size_t)n * sizeof *v);
    if (!v)
        return NULL;
    for (int z = 0; z < n; ++z)
        for (int y = 0; y < n; ++y)
            for (int x = 0; x < n; ++x) {
                size_t i = ((size_t)z * (size_t)n + (size_t)y) * (size_t)n + (size_t)x;
                double p[3] = {(x + 0.5) / n - 0.5, (y + 0.5) / n - 0.5, (z + 0.5) / n - 0.5};
                double r = sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
                float sphere = (float)(r < 0.45 ? 1.0 - r / 0.45 : 0.0);
                switch (kind) {
                case VOLUME_SPHERE:
                    v[i] = sphere;
                    break;
                case VOLUME_NAN:
                    v[i] = i % 7 == 3 ? NAN : i % 11 == 5 ? INFINITY : i % 13 == 2 ? -INFINITY : sphere;
                    break;
                case VOLUME_DENORMAL:
                    v[i] = sphere * 1e-39f;
                    break;
                case VOLUME_HUGE:
                    v[i] = sphere * 1e6f;
                    break;
                case VOLUME_CONSTANT:
                    v[i] = 0.5f;
                    break;
                case VOLUME_TINY:
                    v[i] = 0.5f + 1e-9f * (float)x;
                    break;
                case VOLUME_RAMP_Z:
                    v[i] = (float)(z + 0.5) / (float)n;
                    break;
                case VOLUME_NOISE:
                    v[i] = hash_noise((unsigned)i * 2654435761U + 17U);
                    break;
                }
            }
    return v;
}

static int run_case(halo_library *lib, halo_gl *runtime, const halo_glfuncs *gl, halo_diagnostics *diag,
                    const hard_case *c)
{
    int ok = 0;
    halo_scene *scene = halo_scene_load(c->name, c->scene, lib, diag);
    char *source = halo_host_load(c->slab ? "slab.frag" : "slice.frag", NULL, diag);
    halo_program *program = NULL;
    halo_slice *host = NULL;
    float *volume = make_volume(c->volume, c->side);
    float *gpu = malloc((size_t)SIZE * SIZE * 4 * sizeof *gpu);
    double *emu = malloc((size_t)SIZE * SIZE * 4 * sizeof *emu);
    if (!scene || !source || !volume || !gpu || !emu)
        goto done;
    program = halo_link(
        &(halo_link_desc){.library = lib, .scene = scene, .host_source = source, .image_precision = c->precision},
        diag);
    if (!program)
        goto done;
    halo_host_desc desc = {.gl = gl, .runtime = runtime, .program = program, .width = SIZE, .height = SIZE};
    host = c->slab ? halo_slab_create(&desc, diag) : halo_slice_create(&desc, diag);
    if (!host)
        goto done;
    const halo_render_settings *settings = halo_scene_describe(scene).render;
    if (halo_slice_set_volume(host, volume, c->side, c->side, c->side, diag) != HALO_OK ||
        halo_slice_set_render(host, settings, diag) != HALO_OK)
        goto done;
    halo_slice_set_camera(host, settings->azimuth, settings->elevation, settings->zoom);
    halo_slice_set_interval(host, c->interval);
    if (halo_slice_render(host, gpu, diag) != HALO_OK)
        goto done;
    halo_slice_state state;
    halo_slice_get_state(host, &state);
    /* Both paths on every volume, non-finite ones included: the emulation of the renderer
     * classifies NaN as the hosts do (it used to index the transfer function with a NaN's
     * (int)floor: docs/hard-cases.md, "Found"). On NaN and Inf voxels the two may differ
     * (how a GPU filters Inf next to finite texels is not specified), so those rows ask
     * for finite images on both paths only. */
    if (!halo_conform_slice_emulate(&state, program, state.interval, emu, diag))
        goto done;
    long gpu_nonfinite = 0, emu_nonfinite = 0;
    double max_abs = 0.0;
    for (size_t i = 0; i < (size_t)SIZE * SIZE * 4; ++i) {
        gpu_nonfinite += !isfinite(gpu[i]);
        emu_nonfinite += !isfinite(emu[i]);
        double e = fabs((double)gpu[i] - emu[i]);
        if (isfinite(e) && e > max_abs)
            max_abs = e;
    }
    if (c->tolerance < 0) {
        /* the stages' emulation itself on NaN and Inf inputs (what the renderer's sampling
         * would hand them): colour, opacity and seed must stay finite */
        halo_emu_frame *frame = halo_emu_frame_create(program, SIZE, SIZE, diag);
        static const double bad[] = {NAN, INFINITY, -INFINITY};
        for (int b = 0; b < 3; ++b) {
            halo_emu_sample sample;
            memset(&sample, 0, sizeof sample);
            sample.value = bad[b];
            sample.gradient[0] = bad[b], sample.gradient[1] = 0.1, sample.gradient[2] = bad[(b + 1) % 3];
            sample.view[2] = 1.0;
            sample.depth = 0.5;
            sample.fragcoord[0] = sample.fragcoord[1] = 3.5;
            sample.color[0] = sample.color[1] = sample.color[2] = 0.5;
            sample.opacity = 0.5;
            if (frame)
                halo_emu_frame_begin(frame);
            if ((frame ? halo_emu_apply(program, frame, &sample, diag)
                       : halo_emu_apply(program, NULL, &sample, diag)) != HALO_OK)
                goto done;
            for (int k = 0; k < 3; ++k)
                emu_nonfinite += !isfinite(sample.color[k]);
            emu_nonfinite += !isfinite(sample.opacity) + !isfinite(sample.seed[0]);
        }
        halo_emu_frame_destroy(frame);
    }
    int pass = gpu_nonfinite == 0 && emu_nonfinite == 0 && (c->tolerance < 0 || max_abs <= c->tolerance);
    char tolerance[32] = "finite only", emu_count[24] = "-", error[24] = "-";
    if (c->tolerance >= 0)
        snprintf(tolerance, sizeof tolerance, "%.0e", c->tolerance);
    snprintf(emu_count, sizeof emu_count, "%ld", emu_nonfinite);
    snprintf(error, sizeof error, "%.3e", max_abs);
    printf("%-28s %-5s %2d-bit M=%-2d gpu_nonfinite %4ld emu_nonfinite %4s max_abs %-9s tolerance %-11s %s\n", c->name,
           c->slab ? "slab" : "slice", c->precision, state.interval, gpu_nonfinite, emu_count, error, tolerance,
           pass ? "PASS" : "FAIL");
    ok = pass;
done:
    if (halo_diagnostics_describe(diag).errors) {
        printf("%-30s ERROR\n", c->name);
        halo_diagnostics_print(diag, stdout);
        ok = 0;
    }
    halo_diagnostics_clear(diag);
    halo_slice_destroy(host);
    halo_program_destroy(program);
    halo_scene_destroy(scene);
    free(source);
    free(volume);
    free(gpu);
    free(emu);
    return ok;
}

/* A 1x1x1 volume: refused with a diagnostic (the hosts need 2 voxels per side for a
 * central difference and a trilinear cell), not rendered wrongly. */
static int one_voxel(halo_library *lib, halo_gl *runtime, const halo_glfuncs *gl, halo_diagnostics *diag)
{
    char *source = halo_host_load("slice.frag", NULL, diag);
    halo_program *program = source ? halo_link(&(halo_link_desc){.library = lib, .host_source = source}, diag) : NULL;
    halo_slice *host =
        program
            ? halo_slice_create(
                  &(halo_host_desc){.gl = gl, .runtime = runtime, .program = program, .width = SIZE, .height = SIZE},
                  diag)
            : NULL;
    float voxel = 0.5f;
    int ok = host && halo_slice_set_volume(host, &voxel, 1, 1, 1, diag) == HALO_ERROR_INPUT &&
             halo_diagnostics_has(diag, HALO_MSG_USAGE);
    printf("%-30s %-5s refused with %s: %s\n", "volume_1x1x1", "slice", "USAGE", ok ? "PASS" : "FAIL");
    halo_diagnostics_clear(diag);
    halo_slice_destroy(host);
    halo_program_destroy(program);
    free(source);
    return ok;
}

int main(void)
{
    gl_fixture g;
    int status = gl_fixture_open(&g, SIZE, 0);
    if (status)
        return status;
    halo_library *lib = g.lib;
    halo_gl *runtime = g.runtime;
    const halo_glfuncs *gl = g.gl;
    halo_diagnostics *diag = g.diag;
    int failed = 0;
    const char *only = getenv("HALO_HARD_CASE");
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; ++i)
        if (!only || !strcmp(only, cases[i].name))
            failed += !run_case(lib, runtime, gl, diag, &cases[i]);
    failed += !one_voxel(lib, runtime, gl, diag);
    printf("%d failed\n", failed);
    gl_fixture_close(&g);
    return failed ? 1 : 0;
}
