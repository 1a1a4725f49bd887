/* halo_gl_desc.count_fetches (the bench's fetches per pixel): the image passes' texelFetch
 * calls, counted by an atomic counter a call, against the count the passes'
 * definitions give (glsl/halo/generate.glsl; a tap outside the image reads nothing). One
 * generation of halo_generate over a W x H frame, unscissored (read-back off, no drawn
 * region: every pixel of every pass drawn):
 *   gradient:        4 taps a pixel at distance 1:       4WH - 2W - 2H
 *   spread, pass i:  9 taps at spacing k = 2^(N-i), and H_0 at the pixel:
 *                    (3W - 2k)(3H - 2k) + WH            (k < W, H)
 *   occlude:         the field and the occlusion at the pixel: 2WH
 *   median:          9 taps at distance 1: (3W - 2)(3H - 2)
 * for N = 1, 2, 3 and the median on. And the counting changes no float: the field of the
 * same random seeds with and without it, max abs 0; without it the count is 0. A context
 * without atomic counters (OpenGL before 4.2) gets GL_PROC_MISSING, and the test exits 77,
 * as it does without OpenGL. */
#include "halo.h"
#include "gl/glfuncs.h"
#include "gl/headless.h"
#include "render_driver.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

enum { W = 20, H = 12 };

static int failures = 0;
#define CHECK(cond, ...)                  \
    do {                                  \
        if (!(cond)) {                    \
            printf("FAIL: " __VA_ARGS__); \
            printf("\n");                 \
            failures++;                   \
        }                                 \
    } while (0)

/* The fetches one generation's passes make by their definitions, or -1 for a pass this
 * test does not know. */
static long long expected_fetches(const halo_program *p)
{
    long long w = W, h = H, total = 0;
    halo_reflection r = halo_program_reflection(p);
    for (size_t i = 0; i < r.pass_count; ++i) {
        const halo_pass_info *pass = &r.passes[i];
        if (pass->at != HALO_PASS_AT_GENERATE)
            continue;
        if (!strcmp(pass->name, "gradient"))
            total += 4 * w * h - 2 * w - 2 * h;
        else if (!strcmp(pass->name, "median"))
            total += (3 * w - 2) * (3 * h - 2);
        else if (!strcmp(pass->name, "occlude"))
            total += 2 * w * h;
        else if (!strcmp(pass->name, "spread"))
            for (int rep = pass->start < 1 ? 1 : pass->start; rep <= pass->repeat; ++rep) {
                long long k = 1LL << (pass->repeat - rep);
                total += (3 * w - 2 * k) * (3 * h - 2 * k) + w * h;
            }
        else
            return -1;
    }
    return total;
}

/* One generation over seeds (W x H x 4 floats) with a runtime counting or not: the field
 * into field (W x H x channels), the fetches into *fetches. 0 on failure. */
static int generate(const halo_program *p, int count, const float *seeds, float *field, long long *fetches,
                    halo_diagnostics *diag)
{
    halo_gl *gl = halo_gl_create(&(halo_gl_desc){.get_proc_address = halo_headless_get_proc_address,
                                                 .readback = HALO_GL_READBACK_OFF,
                                                 .count_fetches = count},
                                 diag);
    halo_gl_frame *fr = gl ? halo_gl_frame_create(gl, p, W, H, diag) : NULL;
    int ok = fr != NULL;
    if (ok) {
        const halo_glfuncs *f = halo_gl_functions(gl);
        halo_gl_frame_begin(fr);
        f->BindTexture(GL_TEXTURE_2D, halo_gl_frame_texture(fr, "seed"));
        f->TexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, W, H, GL_RGBA, GL_FLOAT, seeds);
        f->BindTexture(GL_TEXTURE_2D, 0);
        halo_gl_frame_generate(fr);
        ok = halo_gl_frame_read(fr, "field", field) == HALO_OK;
        *fetches = halo_gl_frame_describe(fr).pass_fetches;
    }
    halo_gl_frame_destroy(fr);
    halo_gl_destroy(gl);
    return ok;
}

int main(void)
{
    char why[256] = "";
    halo_headless *context = halo_headless_create(W, H, why, sizeof why);
    if (!context) {
        printf("SKIP: no OpenGL context (%s)\n", why);
        return 77;
    }
    halo_setup(&(halo_setup_desc){0});
    halo_diagnostics *diag = halo_diagnostics_create();
    halo_gl *probe =
        halo_gl_create(&(halo_gl_desc){.get_proc_address = halo_headless_get_proc_address, .count_fetches = 1}, diag);
    if (!probe) { /* a context without atomic counters: refused with a message, as documented */
        int refused = halo_diagnostics_has(diag, HALO_MSG_GL_PROC_MISSING);
        halo_diagnostics_print(diag, stdout);
        printf(refused ? "SKIP: this context cannot count fetches\n" : "FAIL: not GL_PROC_MISSING\n");
        halo_diagnostics_destroy(diag);
        halo_headless_destroy(context);
        return refused ? 77 : 1;
    }
    halo_gl_destroy(probe);
    halo_library *lib = halo_library_create(diag);
    float seeds[W * H * 4], counted[W * H * 4], plain[W * H * 4];
    unsigned state = 12345;
    for (int i = 0; i < W * H * 4; ++i) {
        state = state * 1664525u + 1013904223u;
        seeds[i] = (i % 7 == 0) ? (float)(state >> 8) / 16777216.0f : 0.0f;
    }
    static const char *const variants[] = {"\"passes\": 1", "\"passes\": 2", "\"passes\": 3",
                                           "\"passes\": 2, \"median\": true"};
    for (size_t v = 0; lib && v < sizeof variants / sizeof variants[0]; ++v) {
        char json[512];
        snprintf(json, sizeof json,
                 "{\"halo_scene\": 1, \"stages\": [{\"halo_seed\": {}}, {\"halo_generate\": {%s}}, "
                 "{\"halo_map\": {\"mode\": 1}}]}",
                 variants[v]);
        halo_scene *scene = halo_scene_load("fetch scene", json, lib, diag);
        halo_link_desc link = {.library = lib, .scene = scene};
        halo_program *p = scene ? halo_driver_link(&link, HALO_DRIVER_SLAB, 0, diag) : NULL;
        long long with = -1, without = -1, expected = p ? expected_fetches(p) : -1;
        int ok = p && generate(p, 1, seeds, counted, &with, diag) && generate(p, 0, seeds, plain, &without, diag);
        CHECK(ok && expected > 0, "halo_generate {%s}: no generation (or a pass the test does not know)", variants[v]);
        if (ok) {
            int channels = 4; /* the field image's */
            for (size_t i = 0; i < halo_program_reflection(p).image_count; ++i)
                if (!strcmp(halo_program_reflection(p).images[i].name, "field"))
                    channels = halo_program_reflection(p).images[i].channels;
            size_t n = (size_t)W * H * (size_t)channels;
            float worst = 0.0f;
            for (size_t i = 0; i < n; ++i) {
                float d = counted[i] > plain[i] ? counted[i] - plain[i] : plain[i] - counted[i];
                worst = d > worst || d != d ? d : worst;
            }
            printf(
                "halo_generate {%s} on %dx%d: %lld fetches counted, %lld by the passes' definitions (%.2f a "
                "pixel); without counting %lld; the field with and without it max abs %g\n",
                variants[v], W, H, with, expected, (double)with / (W * H), without, (double)worst);
            CHECK(with == expected, "{%s}: %lld fetches counted, %lld expected", variants[v], with, expected);
            CHECK(without == 0, "{%s}: %lld fetches counted without count_fetches", variants[v], without);
            CHECK(worst == 0.0f, "{%s}: counting changes the field by %g", variants[v], (double)worst);
        }
        halo_program_destroy(p);
        halo_scene_destroy(scene);
    }
    halo_diagnostics_print(diag, stdout);
    halo_library_destroy(lib);
    halo_diagnostics_destroy(diag);
    halo_headless_destroy(context);
    halo_shutdown();
    printf(failures ? "%d failed\n" : "test_fetch_count: all passed\n", failures);
    return failures ? 1 : 0;
}
