/* The slice host's savings that must leave the result exact (issue 16).
 *
 * 1. The gradient texture built on the GPU (examples/hosts/gradient.frag,
 * halo_host_build_gradients) against the CPU's central differences: on a volume of
 * random values in [0,1], one with values up to 40 (half's scale: |g| > 1) and one with a
 * constant face, sides 2, 5x7x3 and 33x17x9 (odd sides, one-voxel faces):
 *   - float (RGB32F): every texel equals halo_volume_gradients' floats, bit for bit;
 *   - half (RGB16F): every texel equals the CPU path's texture (halo_host_upload_gradients),
 *     bit for bit, and the scales are equal;
 *   - snorm8, when the GL renders into it (desktop GL need not): the same;
 *   - packed16 and packed32 (RGBA16_SNORM, RGBA32F, halo_host_build_packed: the value and the
 *     gradient in one texture, GPU only): every component within 0.75 units of 1/32767,
 *     4 units of 2^-24, of the encoded value and central differences computed in double.
 * A format the GL cannot render into is reported, not failed; float and half must render
 * on a GL 3.3 context (color-renderable RGB32F/RGB16F through the layer probe), else the
 * test fails.
 *
 * 2. The skipped work (halo_slice_set_generation_skip): the skipped generations and the
 * scissored passes (the seeds' box grown by each pass's reach). Two volumes: noise, whose
 * seeds reach its back faces, seen along an axis (the bounding sphere's slices beyond
 * the cube leave whole slabs empty at both ends), and a small ball off the centre (the
 * seeds' box far smaller than the image, so that the reach decides), rendered by the
 * slice and the slab host with the skips on and off: the same floats, and fewer pass
 * draws with them on; the same again with halo_generate's approximation wide (its reach
 * 3 * 4^(N-i) per pass) and with its fold (H_0 at the first spreading pass's taps: reach
 * 2^(N-1) + 1), and with halo images at 1/2 and 1/4 of the frame (the reach in their
 * pixels, the seeds' box max-reduced into them).
 *
 * Exit 77 without OpenGL. */
#include "halo.h"
#include "gl/glfuncs.h"
#include "gl/headless.h"
#include "hosts/host_common.h"
#include "hosts/slab.h"
#include "volume.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Reads layer by layer: the first `components` (3: RGB, 4: RGBA) of every texel of a 3D
 * texture, as floats (out: n * components). An snorm texture is read with
 * GL_CLAMP_READ_COLOR off: by default a read clamps a fixed-point buffer to [0, 1]. */
static int read_components_as(const halo_glfuncs *f, GLuint texture, const int dims[3], int components, int snorm,
                              float *out)
{
    PFNGLCLAMPCOLORPROC clamp_color = NULL;
    void *address = halo_headless_get_proc_address("glClampColor");
    memcpy(&clamp_color, &address, sizeof clamp_color);
    GLuint framebuffer = 0;
    f->GenFramebuffers(1, &framebuffer);
    f->BindFramebuffer(GL_FRAMEBUFFER, framebuffer);
    size_t slice = (size_t)dims[0] * (size_t)dims[1];
    float *rgba = malloc(slice * 4 * sizeof *rgba);
    int ok = rgba != NULL;
    for (int z = 0; ok && z < dims[2]; ++z) {
        f->FramebufferTextureLayer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, texture, 0, z);
        if (f->CheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
            ok = 0;
            break;
        }
        f->ReadBuffer(GL_COLOR_ATTACHMENT0);
        f->PixelStorei(GL_PACK_ALIGNMENT, 4);
        if (snorm && clamp_color)
            clamp_color(GL_CLAMP_READ_COLOR, GL_FALSE);
        f->ReadPixels(0, 0, dims[0], dims[1], GL_RGBA, GL_FLOAT, rgba);
        if (snorm && clamp_color)
            clamp_color(GL_CLAMP_READ_COLOR, GL_FIXED_ONLY);
        for (size_t i = 0; i < slice; ++i)
            memcpy(&out[((size_t)z * slice + i) * (size_t)components], &rgba[i * 4], (size_t)components * sizeof *out);
    }
    f->BindFramebuffer(GL_FRAMEBUFFER, 0);
    f->DeleteFramebuffers(1, &framebuffer);
    free(rgba);
    return ok && f->GetError() == GL_NO_ERROR;
}

static int read_components(const halo_glfuncs *f, GLuint texture, const int dims[3], int components, float *out)
{
    return read_components_as(f, texture, dims, components, 0, out);
}

static int read_texture(const halo_glfuncs *f, GLuint texture, const int dims[3], float *out)
{
    return read_components(f, texture, dims, 3, out);
}

/* The packed formats (halo_host_build_packed): every texel against the encoding of the
 * value and the central differences computed here in double: packed16 (snorm) within 0.75
 * units of 1/32767 (rounding: half a unit, and the GPU's float arithmetic a little more),
 * and a zero difference stored as exactly 0 (code 0: a homogeneous region has no normal);
 * packed32 within 4 units of float's 2^-24 (relative beyond 1) of the encoded value. */
static int check_packed(const halo_glfuncs *f, const char *what, const float *volume, const int dims[3],
                        const float *exact, GLuint volume_texture, GLuint texture, halo_diagnostics *diag)
{
    size_t n = (size_t)dims[0] * (size_t)dims[1] * (size_t)dims[2];
    float *gpu = malloc(n * 4 * sizeof *gpu), range[2];
    int failed = 0;
    halo_host_value_range(volume, dims, range);
    for (int wide = 0; wide < 2 && gpu; ++wide) {
        GLint internal_format = wide ? GL_RGBA32F : GL_RGBA16_SNORM;
        const char *name = wide ? "packed32" : "packed16";
        float scale = halo_host_gradient_scale(volume, dims, internal_format);
        if (halo_host_build_packed(f, texture, volume_texture, dims[0], dims[1], dims[2], internal_format, scale, range,
                                   diag) != HALO_OK ||
            !read_components_as(f, texture, dims, 4, !wide, gpu)) {
            halo_diagnostics_print(diag, stdout);
            printf("FAIL %s %s: build or read-back\n", what, name);
            failed++;
            continue;
        }
        double worst = 0.0, unit = wide ? 1.0 / 16777216.0 : 1.0 / 32767.0, limit = wide ? 4.0 : 0.75;
        size_t zeros = 0, nonzero_zeros = 0;
        for (size_t i = 0; i < n; ++i)
            for (int c = 0; c < 4; ++c) {
                double expected =
                    c == 0 ? ((double)volume[i] - range[0]) / range[1] : (double)exact[i * 3 + (size_t)c - 1] / scale;
                if (c > 0 && expected == 0.0) {
                    zeros++;
                    nonzero_zeros += gpu[i * 4 + (size_t)c] != 0.0f;
                }
                double magnitude = wide && fabs(expected) > 1.0 ? fabs(expected) : 1.0; /* float: relative */
                double units = fabs((double)gpu[i * 4 + (size_t)c] - expected) / (unit * magnitude);
                worst = units > worst ? units : worst;
            }
        int ok = worst <= limit && nonzero_zeros == 0;
        printf(
            "%s %s %s: largest difference %.3f units (at most %g), %zu of %zu zero components not 0, scale %.9g, "
            "value range %g + %g\n",
            ok ? "ok  " : "FAIL", what, name, worst, limit, nonzero_zeros, zeros, (double)scale, (double)range[0],
            (double)range[1]);
        failed += !ok;
    }
    if (!gpu)
        failed++;
    free(gpu);
    return failed;
}

/* The texels that differ from expected, bit for bit; prints the first. */
static size_t count_differences(const char *what, const float *got, const float *expected, size_t n)
{
    size_t differing = 0;
    for (size_t i = 0; i < n; ++i)
        if (memcmp(&got[i], &expected[i], sizeof *got) != 0 && !(got[i] == 0.0f && expected[i] == 0.0f)) {
            if (!differing)
                printf("  %s: component %zu (texel %zu) is %.9g, expected %.9g\n", what, i % 3, i / 3, (double)got[i],
                       (double)expected[i]);
            differing++;
        }
    return differing;
}

typedef struct format_case {
    const char *name;
    GLint internal_format;
    int must_render;
} format_case;

static const format_case formats[] = {
    {"float", GL_RGB32F, 1},
    {"half", GL_RGB16F, 1},
    {"snorm8", GL_RGB8_SNORM, 0},
};

static int check_volume(const halo_glfuncs *f, const char *what, const float *volume, const int dims[3])
{
    int failed = 0;
    size_t n = (size_t)dims[0] * (size_t)dims[1] * (size_t)dims[2];
    float *gpu = malloc(n * 3 * sizeof *gpu), *cpu = malloc(n * 3 * sizeof *cpu);
    float *exact = halo_volume_gradients(volume, dims);
    GLuint textures[3];
    f->GenTextures(3, textures);
    halo_diagnostics *diag = halo_diagnostics_create();
    if (!gpu || !cpu || !exact || !diag ||
        halo_host_upload_volume(f, textures[0], volume, dims[0], dims[1], dims[2], diag) != HALO_OK) {
        printf("FAIL %s: setup\n", what);
        failed = 1;
        goto done;
    }
    for (size_t k = 0; k < sizeof formats / sizeof formats[0]; ++k) {
        const format_case *fc = &formats[k];
        if (!halo_host_gradients_renderable(f, fc->internal_format)) {
            printf("%s %s: the GL does not render into %s%s\n", fc->must_render ? "FAIL" : "note", what, fc->name,
                   fc->must_render ? "" : " (the CPU path builds it)");
            failed += fc->must_render;
            continue;
        }
        float gpu_scale = halo_host_gradient_scale(volume, dims, fc->internal_format), cpu_scale = 0.0f;
        if (halo_host_build_gradients(f, textures[1], textures[0], dims[0], dims[1], dims[2], fc->internal_format,
                                      gpu_scale, diag) != HALO_OK ||
            halo_host_upload_gradients(f, textures[2], volume, dims[0], dims[1], dims[2], fc->internal_format,
                                       &cpu_scale, diag) != HALO_OK ||
            !read_texture(f, textures[1], dims, gpu) || !read_texture(f, textures[2], dims, cpu)) {
            halo_diagnostics_print(diag, stdout);
            printf("FAIL %s %s: build or read-back\n", what, fc->name);
            failed++;
            continue;
        }
        char label[160];
        snprintf(label, sizeof label, "%s %s, GPU against CPU path", what, fc->name);
        size_t differing = count_differences(label, gpu, cpu, n * 3);
        if (fc->internal_format == GL_RGB32F) {
            snprintf(label, sizeof label, "%s float, GPU against the central differences", what);
            differing += count_differences(label, gpu, exact, n * 3);
        }
        int ok = differing == 0 && gpu_scale == cpu_scale;
        printf("%s %s %s: %zu components differ, scale %.9g (CPU path %.9g)\n", ok ? "ok  " : "FAIL", what, fc->name,
               differing, (double)gpu_scale, (double)cpu_scale);
        failed += !ok;
    }
    failed += check_packed(f, what, volume, dims, exact, textures[0], textures[1], diag);
done:
    f->DeleteTextures(3, textures);
    halo_diagnostics_destroy(diag);
    free(exact);
    free(cpu);
    free(gpu);
    return failed;
}

/* xorshift: the same values on every machine */
static float next_random(unsigned *state)
{
    *state ^= *state << 13;
    *state ^= *state >> 17;
    *state ^= *state << 5;
    return (float)(*state >> 8) / 16777216.0f;
}

/* %s: halo_generate's parameters (skip_variants) */
static const char skip_scene[] =
    "{\"halo_scene\": 1, \"stages\": [{\"halo_seed\": {}}, {\"halo_generate\": {%s}},"
    " {\"halo_map\": {\"mode\": 0, \"color_near\": [[1, 0.9, 0.4]], \"opacity\": 0.9}}],"
    " \"render\": {\"azimuth\": 0, \"elevation\": 0, \"zoom\": 1.2, \"step\": 0.5,"
    " \"transfer\": [[0, 0, 0, 0, 0], [1, 1, 1, 1, 0.05]]}}";

/* The cameras of the skip checks: face on, filling the image; oblique, with the cube
 * small in it (slices clipped to a fraction of the image, some missing the cube). */
static const double skip_cameras[2][3] = {{0.0, 0.0, 1.2}, {30.0, 20.0, 0.6}};

/* The gradient format of the skip checks' hosts (skip_variants) */
static halo_gradient_format skip_gradient = HALO_GRADIENT_FORMAT_DEFAULT;

/* Renders the skip scene with host `slab` (program p, or none), skips off (0), on (1) or on
 * without read-backs (2: the slice host's declared regions alone), from
 * camera `camera`; NULL on failure. draws: {slices or slabs drawn, pass draws}. */
static float *render_skips(halo_gl *runtime, const halo_program *p, const halo_render_settings *settings,
                           const float *volume, int side, int slab, int skip, int camera, long draws[2],
                           halo_diagnostics *diag)
{
    enum { PIXELS = 48 };
    halo_host_desc desc = {
        .gl = halo_gl_functions(runtime), .runtime = runtime, .program = p, .width = PIXELS, .height = PIXELS};
    halo_slice *s = slab ? halo_slab_create(&desc, diag) : halo_slice_create(&desc, diag);
    float *rgba = malloc((size_t)PIXELS * PIXELS * 4 * sizeof *rgba);
    if (s)
        halo_slice_set_gradient_format(s, skip_gradient);
    int ok = s && rgba && halo_slice_set_volume(s, volume, side, side, side, diag) == HALO_OK &&
             halo_slice_set_render(s, settings, diag) == HALO_OK;
    if (ok) {
        const double *view = skip_cameras[camera];
        halo_slice_set_camera(s, view[0], view[1], view[2]);
        halo_slice_set_interval(s, 2);
        halo_slice_set_generation_skip(s, skip != 0);
        if (skip == 2 && halo_slice_frame(s)) /* as on a GPU: the boxes the host declares, no read-back */
            halo_gl_frame_set_readback_bounds(halo_slice_frame(s), 0);
        ok = halo_slice_render(s, rgba, diag) == HALO_OK;
        draws[0] = halo_slice_draws(s);
        draws[1] = halo_slice_pass_draws(s);
    }
    halo_slice_destroy(s);
    if (!ok) {
        free(rgba);
        return NULL;
    }
    return rgba;
}

/* Skips on against off, every float: the halo scene on the slice and slab hosts and the
 * slice host with no stages (its slices clipped alone), for each camera. A check fails
 * unless the skips spared work: fewer pass draws (halo scene) or fewer slices drawn
 * (no stages; at the oblique camera, where slices miss the cube). */
static int check_skip_case(halo_gl *runtime, const halo_program *p, const halo_scene *scene, const float *volume,
                           int side, int slab, int camera, const char *what, halo_diagnostics *diag)
{
    long draws[3][2] = {{0, 0}, {0, 0}, {0, 0}};
    float *image[3] = {NULL, NULL, NULL};
    int variants = p && !slab ? 3 : 2;
    for (int skip = 0; skip < variants; ++skip)
        image[skip] = render_skips(runtime, p, halo_scene_describe(scene).render, volume, side, slab, skip, camera,
                                   draws[skip], diag);
    size_t differing = 0, n = (size_t)48 * 48 * 4;
    for (int v = 1; v < variants; ++v)
        for (size_t i = 0; image[0] && image[v] && i < n; ++i)
            differing += memcmp(&image[0][i], &image[v][i], sizeof(float)) != 0;
    /* the halo scene: fewer pass draws, and on the slice host fewer slices (clipped); no
     * stages: fewer slices at the oblique camera, where some miss the cube */
    int spared =
        p ? draws[1][1] < draws[0][1] && (slab || draws[1][0] < draws[0][0]) : camera == 0 || draws[1][0] < draws[0][0];
    int ok = image[0] && image[1] && (variants < 3 || image[2]) && differing == 0 && spared;
    printf("%s %s host, %s, camera %d: skips off %ld slices and %ld pass draws, on %ld and %ld", ok ? "ok  " : "FAIL",
           slab ? "slab" : "slice", what, camera, draws[0][0], draws[0][1], draws[1][0], draws[1][1]);
    if (variants == 3)
        printf(", on without read-backs %ld and %ld", draws[2][0], draws[2][1]);
    printf("; %zu of %zu floats differ\n", differing, n * (size_t)(variants - 1));
    if (!image[0] || !image[1] || (variants == 3 && !image[2]))
        halo_diagnostics_print(diag, stdout);
    for (int v = 0; v < variants; ++v)
        free(image[v]);
    return !ok;
}

/* halo_generate's passes in check_skips: exact N = 3 (the gradient pass stores H_0), the
 * approximation wide at N = 2, exact N = 3 with fold; halo images at 1/2 (with the median
 * pass) and 1/4 (wide): their reach in the images' pixels, boxes between scales */
static const struct {
    const char *params, *name;
    int image_scale;
    halo_gradient_format gradient;
} skip_variants[] = {
    {"\"passes\": 3", "", 1, HALO_GRADIENT_FORMAT_DEFAULT},
    {"\"passes\": 2, \"wide\": true", ", wide", 1, HALO_GRADIENT_FORMAT_DEFAULT},
    {"\"passes\": 3, \"fold\": true", ", fold", 1, HALO_GRADIENT_FORMAT_DEFAULT},
    {"\"passes\": 3, \"median\": true", ", median, 1/2", 2, HALO_GRADIENT_FORMAT_DEFAULT},
    {"\"passes\": 2, \"wide\": true", ", wide, 1/4", 4, HALO_GRADIENT_FORMAT_DEFAULT},
    {"\"passes\": 3", ", packed32", 1, HALO_GRADIENT_PACKED32}, /* the shader variants of the packed volume */
};

static int check_skips(halo_gl *runtime, unsigned *state, int variant)
{
    enum { SIDE = 20 };
    int failed = 0;
    halo_diagnostics *diag = halo_diagnostics_create();
    halo_library *lib = halo_library_create(diag);
    char *host[2] = {halo_host_load("slice.frag", NULL, diag), halo_host_load("slab.frag", NULL, diag)};
    char json[sizeof skip_scene + 64];
    snprintf(json, sizeof json, skip_scene, skip_variants[variant].params);
    skip_gradient = skip_variants[variant].gradient;
    halo_scene *scene = lib ? halo_scene_load("(skip scene)", json, lib, diag) : NULL;
    float *volume = malloc((size_t)SIDE * SIDE * SIDE * sizeof *volume);
    for (int ball = 0; ball < 2; ++ball) {
        for (size_t i = 0; volume && i < (size_t)SIDE * SIDE * SIDE; ++i) {
            int x = (int)(i % SIDE), y = (int)(i / SIDE % SIDE), z = (int)(i / SIDE / SIDE);
            double r2 = (x - 13.5) * (x - 13.5) + (y - 6.5) * (y - 6.5) + (z - 9.5) * (z - 9.5);
            volume[i] = ball ? (r2 < 9.0 ? 0.9f : 0.0f) : next_random(state);
        }
        char what[32];
        snprintf(what, sizeof what, "%s%s", ball ? "ball" : "noise", skip_variants[variant].name);
        for (int slab = 0; slab < 2 && scene && volume; ++slab) {
            halo_program *p = host[slab]
                                  ? halo_link(&(halo_link_desc){.library = lib,
                                                                .scene = scene,
                                                                .image_scale = skip_variants[variant].image_scale,
                                                                .host_source = host[slab],
                                                                .host_file = slab ? "slab.frag" : "slice.frag"},
                                              diag)
                                  : NULL;
            for (int camera = 0; camera < 2; ++camera) {
                failed += p ? check_skip_case(runtime, p, scene, volume, SIDE, slab, camera, what, diag) : 1;
                if (!slab && variant == 0)
                    failed += check_skip_case(runtime, NULL, scene, volume, SIDE, 0, camera,
                                              ball ? "ball, no stages" : "noise, no stages", diag);
            }
            halo_program_destroy(p);
        }
    }
    if (!scene || !volume) {
        halo_diagnostics_print(diag, stdout);
        failed++;
    }
    free(volume);
    halo_scene_destroy(scene);
    free(host[0]);
    free(host[1]);
    halo_library_destroy(lib);
    halo_diagnostics_destroy(diag);
    return failed;
}

/* A scene linked into slice.frag, with what it was made from; program NULL (and the
 * reason in diag) when any step failed. */
typedef struct slice_link {
    halo_diagnostics *diag;
    halo_library *lib;
    char *host;
    halo_scene *scene;
    halo_program *program;
} slice_link;

static void slice_link_open(slice_link *l, const char *json, int image_scale)
{
    l->diag = halo_diagnostics_create();
    l->lib = halo_library_create(l->diag);
    l->host = halo_host_load("slice.frag", NULL, l->diag);
    l->scene = l->lib ? halo_scene_load("(scene)", json, l->lib, l->diag) : NULL;
    l->program = l->scene && l->host ? halo_link(&(halo_link_desc){.library = l->lib,
                                                                   .scene = l->scene,
                                                                   .host_source = l->host,
                                                                   .host_file = "slice.frag",
                                                                   .image_scale = image_scale},
                                                 l->diag)
                                     : NULL;
}

static void slice_link_close(slice_link *l)
{
    halo_program_destroy(l->program);
    halo_scene_destroy(l->scene);
    free(l->host);
    halo_library_destroy(l->lib);
    halo_diagnostics_destroy(l->diag);
}

/* Six outline features: two feature groups, the volume drawn once per group. */
static const char group_scene[] =
    "{\"halo_scene\": 1, \"stages\": [{\"tone_shading\": {}},"
    " {\"outline_feature\": {\"value_min\": [0, 0.15, 0.3, 0.5, 0.65, 0.85], \"value_max\": [0.1, 0.25, 0.4, 0.6, 0.75, 1]}},"
    " {\"outlines\": {}}],"
    " \"render\": {\"azimuth\": 30, \"elevation\": 20, \"zoom\": 1.2, \"step\": 0.5,"
    " \"transfer\": [[0, 0, 0, 0, 0], [0.05, 0.8, 0.6, 0.4, 0.1], [1, 1, 1, 1, 0.3]]}}";

/* The slice host with feature groups writes the colour in the first group only: the
 * colour and every output image the same floats as with every group writing it
 * (skips off). */
static int check_groups(halo_gl *runtime)
{
    enum { SIDE = 20, PIXELS = 48 };
    int failed = 0;
    if (!halo_gl_functions(runtime)->ColorMaski) {
        printf("skip slice host, feature groups: no glColorMaski, every group writes the colour\n");
        return 0;
    }
    slice_link link;
    slice_link_open(&link, group_scene, 1);
    halo_diagnostics *diag = link.diag;
    const halo_scene *scene = link.scene;
    const halo_program *p = link.program;
    float *volume = malloc((size_t)SIDE * SIDE * SIDE * sizeof *volume);
    for (size_t i = 0; volume && i < (size_t)SIDE * SIDE * SIDE; ++i) {
        double x = (double)(i % SIDE) - 9.5, y = (double)(i / SIDE % SIDE) - 9.5, z = (double)(i / SIDE / SIDE) - 9.5;
        volume[i] = (float)(1.0 - sqrt(x * x + y * y + z * z) / 16.5); /* 1 at the centre, 0 at the corners */
    }
    size_t pixels = (size_t)PIXELS * PIXELS, floats = 0, differing = 0;
    float *out[2] = {NULL, NULL};
    int groups = p ? halo_program_reflection(p).group_count : 0;
    for (int skip = 0; skip < 2 && p && volume && groups == 2; ++skip) {
        size_t outputs = halo_program_reflection(p).output_count;
        out[skip] = malloc(pixels * 4 * (outputs + 1) * sizeof(float));
        halo_host_desc desc = {
            .gl = halo_gl_functions(runtime), .runtime = runtime, .program = p, .width = PIXELS, .height = PIXELS};
        halo_slice *s = halo_slice_create(&desc, diag);
        const halo_render_settings *settings = halo_scene_describe(scene).render;
        int ok = s && out[skip] && halo_slice_set_volume(s, volume, SIDE, SIDE, SIDE, diag) == HALO_OK &&
                 halo_slice_set_render(s, settings, diag) == HALO_OK;
        if (ok) {
            halo_slice_set_camera(s, settings->azimuth, settings->elevation, settings->zoom);
            halo_slice_set_generation_skip(s, skip);
            ok = halo_slice_render(s, out[skip], diag) == HALO_OK;
        }
        floats = pixels * 4;
        for (size_t o = 0; ok && o < outputs; ++o) { /* each image after the colour, 4 floats a pixel at most */
            const char *image = halo_program_reflection(p).outputs[o].image;
            const halo_image_info *info = NULL;
            for (size_t k = 0; k < halo_program_reflection(p).image_count; ++k)
                if (!strcmp(halo_program_reflection(p).images[k].name, image))
                    info = &halo_program_reflection(p).images[k];
            ok = info && halo_gl_frame_read(halo_slice_frame(s), image, out[skip] + floats) == HALO_OK;
            floats += ok ? pixels * (size_t)info->channels : 0;
        }
        halo_slice_destroy(s);
        if (!ok) {
            free(out[skip]);
            out[skip] = NULL;
        }
    }
    for (size_t i = 0; out[0] && out[1] && i < floats; ++i)
        differing += memcmp(&out[0][i], &out[1][i], sizeof(float)) != 0;
    int ok = out[0] && out[1] && differing == 0;
    printf(
        "%s slice host, %d feature groups: colour written once against every group; %zu of %zu floats (colour and"
        " %zu images) differ\n",
        ok ? "ok  " : "FAIL", groups, differing, floats, p ? halo_program_reflection(p).output_count : 0);
    if (!ok)
        halo_diagnostics_print(diag, stdout);
    failed += !ok;
    free(out[0]);
    free(out[1]);
    free(volume);
    slice_link_close(&link);
    return failed;
}

/* halo_gl_frame_info.read_box of halo images at 1/4 of a narrow frame (9 x 100: 3 x 25
 * texels): after a generation with no read-back and no declared region (the seeds may be
 * anywhere) the images may be nonzero anywhere, and the region is the whole frame in both
 * directions; with the read-back, nothing was drawn, so nothing can be nonzero. The
 * read-back comes from the runtime's policy (halo_gl_desc.readback: AUTO is on for
 * llvmpipe) or, for setter >= 0, from halo_gl_frame_set_readback_bounds. */
static int check_read_region(halo_gl *runtime, const char *policy, int setter, int expect_readback)
{
    char json[sizeof skip_scene + 64];
    snprintf(json, sizeof json, skip_scene, "\"passes\": 2");
    slice_link link;
    slice_link_open(&link, json, 4);
    halo_gl_frame *frame = link.program ? halo_gl_frame_create(runtime, link.program, 9, 100, link.diag) : NULL;
    int before[4] = {-1, -1, -1, -1}, after[4] = {-1, -1, -1, -1}, any[2] = {-1, -1};
    if (frame) {
        if (setter >= 0)
            halo_gl_frame_set_readback_bounds(frame, setter);
        halo_gl_frame_begin(frame);
        halo_gl_frame_info info0 = halo_gl_frame_describe(frame);
        any[0] = info0.read_any;
        memcpy(before, info0.read_box, sizeof before);
        halo_gl_frame_generate(frame);
        halo_gl_frame_info info1 = halo_gl_frame_describe(frame);
        any[1] = info1.read_any;
        memcpy(after, info1.read_box, sizeof after);
    }
    int ok = frame && any[0] == 0 &&
             (expect_readback ? any[1] == 0
                              : any[1] == 1 && after[0] == 0 && after[1] == 0 && after[2] == 9 && after[3] == 100);
    printf(
        "%s read region, halo images at 1/4 of 9 x 100, %s: %d after the frame's clear, %d after a generation: {%d,"
        " %d, %d, %d} (%s)\n",
        ok ? "ok  " : "FAIL", policy, any[0], any[1], after[0], after[1], after[2], after[3],
        expect_readback ? "read back: nothing drawn, nothing nonzero" : "no read-back: the whole frame");
    if (!frame)
        halo_diagnostics_print(link.diag, stdout);
    halo_gl_frame_destroy(frame);
    slice_link_close(&link);
    return !ok;
}

/* The read-back policy of halo_gl_desc, and one frame's setter over it. */
static int check_readback_policies(halo_gl *runtime, halo_diagnostics *diag)
{
    int failed = check_read_region(runtime, "runtime AUTO (llvmpipe), frame set off", 0, 0);
    static const struct {
        halo_gl_readback policy;
        const char *name;
        int on;
    } rows[] = {{HALO_GL_READBACK_OFF, "runtime OFF", 0},
                {HALO_GL_READBACK_ON, "runtime ON", 1},
                {HALO_GL_READBACK_AUTO, "runtime AUTO (llvmpipe)", 1}};
    for (size_t i = 0; i < sizeof rows / sizeof rows[0]; ++i) {
        halo_gl *gl = halo_gl_create(
            &(halo_gl_desc){.get_proc_address = halo_headless_get_proc_address, .readback = rows[i].policy}, diag);
        failed += gl ? check_read_region(gl, rows[i].name, -1, rows[i].on) : 1;
        halo_gl_destroy(gl);
    }
    halo_gl *gl = halo_gl_create(
        &(halo_gl_desc){.get_proc_address = halo_headless_get_proc_address, .readback = (halo_gl_readback)7}, diag);
    int refused = !gl && halo_diagnostics_has(diag, HALO_MSG_USAGE);
    printf("%s halo_gl_desc.readback 7: %s\n", refused ? "ok  " : "FAIL", refused ? "refused (USAGE)" : "accepted");
    halo_gl_destroy(gl);
    halo_diagnostics_clear(diag);
    return failed + !refused;
}

int main(void)
{
    char err[512];
    if (halo_setup(NULL) != HALO_OK)
        return 99;
    halo_headless *headless = halo_headless_create(16, 16, err, sizeof err);
    if (!headless) {
        printf("no OpenGL context (%s): skipping\n", err);
        halo_shutdown();
        return 77;
    }
    halo_diagnostics *diag = halo_diagnostics_create();
    halo_gl *runtime = halo_gl_create(&(halo_gl_desc){.get_proc_address = halo_headless_get_proc_address}, diag);
    if (!runtime) {
        halo_diagnostics_print(diag, stderr);
        return 99;
    }
    const halo_glfuncs *f = halo_gl_functions(runtime);
    static const int sides[][3] = {{2, 2, 2}, {5, 7, 3}, {33, 17, 9}};
    int failed = 0;
    unsigned state = 12345u;
    for (size_t s = 0; s < sizeof sides / sizeof sides[0]; ++s) {
        const int *dims = sides[s];
        size_t n = (size_t)dims[0] * (size_t)dims[1] * (size_t)dims[2];
        float *volume = malloc(n * sizeof *volume);
        if (!volume)
            return 99;
        char what[64];
        for (int kind = 0; kind < 3; ++kind) {
            for (size_t i = 0; i < n; ++i) {
                float r = next_random(&state);
                /* 0: [0,1]; 1: up to 40 (half's scale); 2: a constant face x = 0 */
                volume[i] = kind == 1 ? 40.0f * r * r : kind == 2 && i % (size_t)dims[0] == 0 ? 0.25f : r;
            }
            snprintf(what, sizeof what, "%dx%dx%d %s", dims[0], dims[1], dims[2],
                     kind == 0   ? "[0,1]"
                     : kind == 1 ? "[0,40]"
                                 : "constant face");
            failed += check_volume(f, what, volume, dims);
        }
        free(volume);
    }
    for (int variant = 0; variant < (int)(sizeof skip_variants / sizeof skip_variants[0]); ++variant)
        failed += check_skips(runtime, &state, variant);
    failed += check_groups(runtime);
    failed += check_readback_policies(runtime, diag);
    printf("%d failed\n", failed);
    halo_gl_destroy(runtime);
    halo_headless_destroy(headless);
    halo_diagnostics_destroy(diag);
    halo_shutdown();
    return failed ? 1 : 0;
}
