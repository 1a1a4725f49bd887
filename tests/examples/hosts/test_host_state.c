/* libhalo's runtime in a host's hostile GL state (issue 26), beside test_segments' case 5
 * (halo_gl_frame_draw on desktop OpenGL). Hostile state is tests/hostile.h's: culling,
 * depth and stencil tests that pass nothing, blending to zero, a one-pixel scissor and
 * viewport, colour writes off, lines, rasterizer discard, sRGB, odd packing, bindings and
 * per-buffer blending.
 *   1. The slice and slab hosts: each halo_gl_frame call they make that must neither
 *      depend on the host's state nor change it (begin, begin_group, generate, end_group,
 *      read_region: halo_slice_set_untidy) is made in hostile state, and the host's own
 *      state is put back after it: the image equals the tidy host's (max abs 0) and every
 *      call gave the hostile state back. Halos (generations between the slices) and
 *      outlines (feature groups and their passes).
 *   2. halo_gl_frame_read in hostile state reads the tidy image and gives the state back.
 *   3. The feature halo buffer: halo_feature_buffer_build and _read in hostile state.
 *   4. The ray caster, hostile between its draws, in one draw and in segments, on every
 *      context: on OpenGL ES (--backend egl-es3.0 or egl-es3.2, tests/examples/hosts/
 *      host_state_es.sh) this is the only case (1 and 3 need desktop OpenGL).
 * Exit 77 without OpenGL. */
#include "../../gl_fixture.h"
#include "../../hostile.h"
#include "gl/runtime.h"
#include "halo_feature.h"
#include "hosts/raycast.h"
#include "hosts/slab.h"
#include "hosts/slice.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define SIZE   48
#define VOLUME 24

static int failures;

#define CHECK(cond, ...)                                \
    do {                                                \
        if (!(cond)) {                                  \
            printf("FAIL %s:%d: ", __FILE__, __LINE__); \
            printf(__VA_ARGS__);                        \
            printf("\n");                               \
            failures++;                                 \
        }                                               \
    } while (0)

typedef struct env {
    gl_fixture g;
    const char *srcdir;
    int es;             /* halo_headless_es of the context */
    hostile h;          /* the hostile state and its counts */
    halo_gl_state host; /* the host's state while a runtime call is made in hostile state */
} env;

static double max_abs_difference(const float *a, const float *b, size_t n)
{
    double m = 0.0;
    for (size_t i = 0; i < n; ++i) {
        double d = fabs((double)a[i] - (double)b[i]);
        m = d > m || d != d ? d : m;
    }
    return m;
}

/* scene_file (examples/scenes/) linked into the embedded host host_name, for GLSL ES 300 on
 * an ES context; NULL after printing the diagnostics. */
static halo_program *link_file(env *e, const char *scene_file, const char *host_name, int one_draw,
                               halo_scene **scene_out)
{
    char path[1024];
    snprintf(path, sizeof path, "%s/examples/scenes/%s", e->srcdir, scene_file);
    char *host = halo_host_load(host_name, NULL, e->g.diag);
    halo_scene *scene = host ? halo_scene_load(path, NULL, e->g.lib, e->g.diag) : NULL;
    halo_program *p = scene ? halo_link(&(halo_link_desc){.library = e->g.lib,
                                                          .scene = scene,
                                                          .host_source = host,
                                                          .host_file = host_name,
                                                          .one_draw = one_draw,
                                                          .target = e->es ? HALO_TARGET_ES300 : HALO_TARGET_DEFAULT},
                                        e->g.diag)
                            : NULL;
    free(host);
    if (!p) {
        halo_diagnostics_print(e->g.diag, stdout);
        halo_scene_destroy(scene);
        return NULL;
    }
    *scene_out = scene;
    return p;
}

/* Hostile state for a runtime call; the host's state saved first. */
static void untidy_begin(env *e)
{
    halo_gl_state_save(e->g.gl, &e->host);
    hostile_set(&e->h);
}

/* After the call: is the hostile state still there? Then the host's state again. */
static void untidy_end(env *e, int bindings, const char *what)
{
    hostile_check(&e->h, bindings, what);
    halo_gl_state_restore(e->g.gl, &e->host);
}

/* ---- 1, 2: the slice and slab hosts ---- */

/* halo_slice_set_untidy's hook: hostile state for the call, the host's back after it. */
static void slice_untidy(void *user, int returned)
{
    env *e = user;
    if (!returned)
        untidy_begin(e);
    else
        untidy_end(e, 1, "a halo_gl_frame call of the slice host");
}

/* Renders scene_file through the slice (slab 0) or slab host, untidy or not; the image of
 * the frame named `image` (when not NULL) read into *read (in hostile state when untidy). */
static float *render_slice(env *e, const char *scene_file, int slab, int untidy, const char *image, float **read,
                           size_t *read_count)
{
    halo_scene *scene = NULL;
    halo_program *p = link_file(e, scene_file, slab ? "slab.frag" : "slice.frag", 0, &scene);
    float *rgba = malloc((size_t)SIZE * SIZE * 4 * sizeof *rgba);
    const halo_host_desc desc = {.gl = e->g.gl, .runtime = e->g.runtime, .program = p, .width = SIZE, .height = SIZE};
    halo_slice *s = !p ? NULL : slab ? halo_slab_create(&desc, e->g.diag) : halo_slice_create(&desc, e->g.diag);
    int ok = s && rgba;
    if (ok) {
        const halo_render_settings *settings = halo_scene_describe(scene).render;
        ok = halo_slice_set_volume(s, e->g.volume, VOLUME, VOLUME, VOLUME, e->g.diag) == HALO_OK &&
             halo_slice_set_render(s, settings, e->g.diag) == HALO_OK;
        halo_slice_set_camera(s, settings->azimuth, settings->elevation, settings->zoom);
        if (untidy)
            halo_slice_set_untidy(s, slice_untidy, e);
        ok = ok && halo_slice_render(s, rgba, e->g.diag) == HALO_OK;
    }
    if (ok && image && halo_slice_frame(s)) {
        const halo_image_info *info = NULL;
        for (size_t i = 0; i < halo_program_reflection(p).image_count; ++i)
            if (!strcmp(halo_program_reflection(p).images[i].name, image))
                info = &halo_program_reflection(p).images[i];
        CHECK(info, "%s has no image %s", scene_file, image);
        *read_count = info ? (size_t)((SIZE + info->scale - 1) / info->scale) *
                                 (size_t)((SIZE + info->scale - 1) / info->scale) * (size_t)info->channels
                           : 0;
        *read = info ? malloc(*read_count * sizeof **read) : NULL;
        if (*read) {
            if (untidy)
                untidy_begin(e);
            ok = halo_gl_frame_read(halo_slice_frame(s), image, *read) == HALO_OK;
            if (untidy)
                untidy_end(e, 1, "halo_gl_frame_read");
        }
    }
    if (!ok) {
        halo_diagnostics_print(e->g.diag, stdout);
        free(rgba);
        rgba = NULL;
    }
    halo_slice_destroy(s);
    halo_program_destroy(p);
    halo_scene_destroy(scene);
    halo_diagnostics_clear(e->g.diag);
    return rgba;
}

static void test_slice_hosts(env *e)
{
    static const struct {
        const char *scene, *image;
    } cases[] = {{"default.json", "field"}, {"outline-occluded-dashed.json", NULL}};
    for (int slab = 0; slab < 2; ++slab)
        for (size_t c = 0; c < sizeof cases / sizeof cases[0]; ++c) {
            float *tidy_read = NULL, *untidy_read = NULL;
            size_t tidy_count = 0, untidy_count = 0;
            float *tidy = render_slice(e, cases[c].scene, slab, 0, cases[c].image, &tidy_read, &tidy_count);
            e->h.checks = e->h.mismatches = 0;
            float *untidy = render_slice(e, cases[c].scene, slab, 1, cases[c].image, &untidy_read, &untidy_count);
            const char *host = slab ? "slab host" : "slice host";
            CHECK(tidy && untidy, "%s, %s: both renders", host, cases[c].scene);
            if (tidy && untidy) {
                double m = max_abs_difference(tidy, untidy, (size_t)SIZE * SIZE * 4);
                printf(
                    "hostile host state, %s, %s: against a tidy host max abs %.3g; %d halo_gl_frame calls in "
                    "hostile state, %d changes to it\n",
                    host, cases[c].scene, m, e->h.checks, e->h.mismatches);
                CHECK(m == 0.0, "%s, %s: a host's hostile state changes the image by %.3g", host, cases[c].scene, m);
                CHECK(e->h.checks > 1 && e->h.mismatches == 0,
                      "%s, %s: libhalo changed the host's state %d times (listed above)", host, cases[c].scene,
                      e->h.mismatches);
            }
            if (cases[c].image) {
                CHECK(tidy_read && untidy_read && tidy_count == untidy_count &&
                          max_abs_difference(tidy_read, untidy_read, tidy_count) == 0.0,
                      "%s, %s: halo_gl_frame_read of %s in hostile state differs from a tidy host's", host,
                      cases[c].scene, cases[c].image);
            }
            free(tidy);
            free(untidy);
            free(tidy_read);
            free(untidy_read);
        }
}

/* ---- 3: the feature halo buffer ---- */

static float *feature_buffer(env *e, int untidy, size_t *count)
{
    const int dims[3] = {VOLUME, VOLUME, VOLUME};
    halo_feature_buffer *b = halo_feature_buffer_create(e->g.runtime, e->g.volume, dims, NULL, e->g.diag);
    halo_feature_buffer_info info = {0};
    if (b)
        info = halo_feature_buffer_describe(b);
    *count = (size_t)info.dims[0] * (size_t)info.dims[1] * (size_t)info.dims[2];
    float *values = b ? malloc(*count * sizeof *values) : NULL;
    const double view[3] = {0.3, 0.5, 0.8};
    if (untidy)
        untidy_begin(e);
    int ok = values && halo_feature_buffer_build(b, view) == HALO_OK;
    if (untidy)
        hostile_check(&e->h, 1, "halo_feature_buffer_build");
    ok = ok && halo_feature_buffer_read(b, values) == HALO_OK;
    if (untidy)
        untidy_end(e, 1, "halo_feature_buffer_read");
    if (!ok) {
        halo_diagnostics_print(e->g.diag, stdout);
        free(values);
        values = NULL;
    }
    halo_feature_buffer_destroy(b);
    halo_diagnostics_clear(e->g.diag);
    return values;
}

static void test_feature_buffer(env *e)
{
    size_t tidy_count = 0, untidy_count = 0;
    float *tidy = feature_buffer(e, 0, &tidy_count);
    e->h.checks = e->h.mismatches = 0;
    float *untidy = feature_buffer(e, 1, &untidy_count);
    CHECK(tidy && untidy && tidy_count == untidy_count, "the feature buffer: both builds");
    if (tidy && untidy && tidy_count == untidy_count) {
        double sum = 0.0;
        for (size_t i = 0; i < tidy_count; ++i)
            sum += tidy[i];
        double m = max_abs_difference(tidy, untidy, tidy_count);
        printf(
            "hostile host state, feature buffer (%zu values, sum %.4g): against a tidy host max abs %.3g; %d "
            "checks, %d changes\n",
            tidy_count, sum, m, e->h.checks, e->h.mismatches);
        CHECK(sum > 0.0, "the feature buffer is empty: the test would show nothing");
        CHECK(m == 0.0, "the feature buffer: a host's hostile state changes it by %.3g", m);
        CHECK(e->h.checks == 2 && e->h.mismatches == 0, "the feature buffer: libhalo changed the host's state");
    }
    free(tidy);
    free(untidy);
}

/* ---- 4: the ray caster ---- */

/* halo_raycast_set_untidy's hook: hostile state after each of the host's draws; before
 * each (switches) and when halo_gl_frame_draw returns (all of it) libhalo must have given
 * it back. */
static void ray_untidy(void *user, int before_draw)
{
    env *e = user;
    if (before_draw)
        hostile_check(&e->h, before_draw == 2, "halo_gl_frame_draw");
    else
        hostile_set(&e->h);
}

static float *render_ray(env *e, const char *scene_file, int one_draw, int untidy)
{
    halo_scene *scene = NULL;
    halo_program *p = link_file(e, scene_file, "raycast.frag", one_draw, &scene);
    float *rgba = malloc((size_t)SIZE * SIZE * 4 * sizeof *rgba);
    const halo_host_desc desc = {.gl = e->g.gl, .runtime = e->g.runtime, .program = p, .width = SIZE, .height = SIZE};
    halo_raycast *r = p ? halo_raycast_create(&desc, e->g.diag) : NULL;
    int ok = r && rgba;
    if (ok) {
        const halo_render_settings *settings = halo_scene_describe(scene).render;
        ok = halo_raycast_set_volume(r, e->g.volume, VOLUME, VOLUME, VOLUME, e->g.diag) == HALO_OK &&
             halo_raycast_set_render(r, settings, e->g.diag) == HALO_OK;
        halo_raycast_set_camera(r, settings->azimuth, settings->elevation, settings->zoom);
        halo_raycast_set_segments(r, 4, 0);
        if (untidy) {
            halo_raycast_set_untidy(r, ray_untidy, e);
            halo_gl_state_save(e->g.gl, &e->host); /* given back below */
        }
        ok = ok && halo_raycast_render(r, rgba, e->g.diag) == HALO_OK;
        if (untidy)
            halo_gl_state_restore(e->g.gl, &e->host);
    }
    if (!ok) {
        halo_diagnostics_print(e->g.diag, stdout);
        free(rgba);
        rgba = NULL;
    }
    halo_raycast_destroy(r);
    halo_program_destroy(p);
    halo_scene_destroy(scene);
    halo_diagnostics_clear(e->g.diag);
    return rgba;
}

static void test_ray_caster(env *e)
{
    const char *context = e->es == 30 ? "OpenGL ES 3.0" : e->es ? "OpenGL ES 3.2" : "OpenGL";
    /* segments need per-buffer blending for the seed output: OpenGL ES 3.0 has none */
    for (int one_draw = 1; one_draw >= (e->es == 30 ? 1 : 0); --one_draw) {
        const char *how = one_draw ? "one draw" : "segments";
        float *tidy = render_ray(e, "default.json", one_draw, 0);
        e->h.checks = e->h.mismatches = 0;
        float *untidy = render_ray(e, "default.json", one_draw, 1);
        CHECK(tidy && untidy, "ray caster, %s, %s: both renders", context, how);
        if (tidy && untidy) {
            double m = max_abs_difference(tidy, untidy, (size_t)SIZE * SIZE * 4);
            printf(
                "hostile host state, ray caster, %s, %s: against a tidy host max abs %.3g; %d checks, %d "
                "changes\n",
                context, how, m, e->h.checks, e->h.mismatches);
            CHECK(m == 0.0, "ray caster, %s, %s: a host's hostile state changes the image by %.3g", context, how, m);
            CHECK(e->h.checks > 1 && e->h.mismatches == 0, "ray caster, %s, %s: libhalo changed the host's state",
                  context, how);
        }
        free(tidy);
        free(untidy);
    }
}

int main(int argc, char **argv)
{
    halo_headless_allow_es(1);
    if (!halo_headless_take_backend_option(&argc, argv, "test_host_state"))
        return 99;
    env e = {0};
    int status = gl_fixture_open(&e.g, SIZE, VOLUME);
    if (status)
        return status;
    e.srcdir = getenv("top_srcdir") ? getenv("top_srcdir") : getenv("srcdir") ? getenv("srcdir") : ".";
    e.es = halo_headless_es(e.g.context);
    e.h = (hostile){.f = e.g.gl, .es = e.es};
    const char *only = getenv("HALO_HOST_STATE_ONLY"); /* "slice", "feature" or "ray": one case */
    if (e.es)
        printf("OpenGL ES: the slice and slab hosts and the feature buffer need desktop OpenGL (not run)\n");
    if (!e.es && (!only || !strcmp(only, "slice")))
        test_slice_hosts(&e);
    if (!e.es && (!only || !strcmp(only, "feature")))
        test_feature_buffer(&e);
    if (!only || !strcmp(only, "ray"))
        test_ray_caster(&e);
    gl_fixture_close(&e.g);
    printf("%d failed\n", failures);
    return failures ? 1 : 0;
}
