/* Conformance of feature halos: the GPU halo buffer (libhalo/gl/feature_splat.c) against
 * halo_feature_compute's emulated buffer, that emulation against the exact reference
 * (HALO_FEATURE_REFERENCE), and the stage feature_halo drawn through a probe against
 * halo_emu_apply (the buffer value through the emulated frame's host uniform). */
#include "conform_feature.h"

#include "halo_feature.h"
#include "halo_gl_loader.h"
#include "gl/headless.h"
#include "hosts/raycast.h"
#include "volume.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* ---- Tolerances ---------------------------------------------------------------------------
 *
 * Splat rows: the GPU adds, per texel, up to n^3 - 1 terms weight * h_n in float32
 * (weights and unit vectors rounded to float, normals computed in double and rounded,
 * pow in float, additive blending into R32F), where the emulation works in double. The
 * buffer's values lie in [0, 1] (the weights of a splat sum to 1, h_n <= 1); each term
 * carries ~1e-7 relative error and the blended sum ~n^3 float roundings of the partial
 * sum, so 1e-6 absolute bounds them with a margin: measured on llvmpipe (LLVM 15)
 * 8.6e-8 (n = 5), 7.0e-8 (n = 9), 1.2e-7 (no cutoff), 0 where nothing splats. ~8x
 * over the worst measured. The numbers: conform_feature.h. */
/* Emulation against the exact reference: the same sums in double in another order,
 * times S and the gradient factor: only double rounding (measured 7e-15 absolute on sums up to 12). */
/* Application rows: the buffer read with GL_LINEAR (llvmpipe's float weights, ~1e-7
 * relative to the buffer value), |grad f| in float, then c1 h and c2 h with c up to 50
 * amplifying the lookup's error. Measured 8e-8 (defaults), 1.1e-7 (c = 50, clamped
 * mostly). 5e-6 leaves ~40x: a condition margin for other drivers (8-bit filter weights). */

typedef struct feature_context {
    halo_gl *runtime;
    const halo_glfuncs *f;
    halo_diagnostics *diag;
    halo_library *lib;
    int verbose;
    int rows, failed;
} feature_context;

typedef row_stats stats; /* conform_harness.h */

static void add_value(stats *s, double gpu, double reference, double tolerance, size_t index)
{
    s->values++;
    if (!isfinite(gpu)) {
        s->nonfinite++;
        s->over++;
        return;
    }
    double e = fabs(gpu - reference);
    s->sum_squares += e * e;
    if (e > s->max_abs || s->values == 1)
        s->max_abs = e > s->max_abs ? e : s->max_abs, s->worst = index;
    if (e > tolerance)
        s->over++;
}

static void feature_print_row(feature_context *c, const char *row, const stats *s, double tolerance, const char *reason)
{
    char text[32];
    snprintf(text, sizeof text, "%.0e", tolerance);
    int pass = s->over == 0 && s->nonfinite == 0 && s->values > 0;
    print_row_line(row, s, text, pass);
    if (c->verbose)
        fprintf(stderr, "  %s: worst at index %zu of %zu; tolerance: %s\n", row, s->worst, s->values, reason);
    c->rows++;
    if (!pass)
        c->failed++;
}

static void print_error(feature_context *c, const char *row)
{
    print_error_row_line(row, 17, c->diag);
    c->rows++;
    c->failed++;
}

halo_status halo_feature_ensure_module(halo_library *lib, halo_diagnostics *diag)
{
    if (!lib)
        return HALO_ERROR_INPUT;
    if (halo_library_find(lib, "feature_halo"))
        return HALO_OK;
    const char *env = getenv("HALO_FEATURE_MODULE");
    if (env && *env)
        return halo_library_add(lib, env, NULL, HALO_ADD_NEW, diag);
    const char *srcdir = getenv("srcdir");
    char path[4096];
    snprintf(path, sizeof path, "%s/glsl/feature/feature_halo.glsl", srcdir && *srcdir ? srcdir : ".");
    return halo_library_add(lib, path, NULL, HALO_ADD_NEW, diag);
}

/* ---- Test volumes ------------------------------------------------------------------- */

static float *constant_volume(int n, float value)
{
    float *v = malloc((size_t)n * n * n * sizeof *v);
    for (size_t i = 0; v && i < (size_t)n * n * n; ++i)
        v[i] = value;
    return v;
}

static float *single_voxel_volume(int n)
{
    float *v = constant_volume(n, 0.0f);
    if (v)
        v[((size_t)(n / 2) * n + n / 2) * n + n / 2] = 1.0f;
    return v;
}

/* A slab of value 1 against the x = 0 face, 2 voxels thick, smooth over one more: the
 * feature's boundary, its normals and its halo all meet the volume's edge. */
static float *edge_volume(int n)
{
    float *v = malloc((size_t)n * n * n * sizeof *v);
    for (int z = 0; v && z < n; ++z)
        for (int y = 0; y < n; ++y)
            for (int x = 0; x < n; ++x)
                v[((size_t)z * n + y) * n + x] = x < 2 ? 1.0f : x == 2 ? 0.5f : 0.0f;
    return v;
}

/* ---- Splat rows ----------------------------------------------------------------------- */

static void run_splat_row(feature_context *c, const char *row, const float *values, int n,
                          const halo_feature_desc *desc, const double view[3])
{
    int dims[3] = {n, n, n};
    halo_feature_layout layout = halo_feature_desc_layout(desc, dims);
    const int *bd = layout.buffer_dims;
    size_t count = (size_t)bd[0] * bd[1] * bd[2];
    float *gpu = malloc(count * sizeof *gpu);
    double *emu = malloc(count * sizeof *emu);
    halo_feature_buffer *b = values ? halo_feature_buffer_create(c->runtime, values, dims, desc, c->diag) : NULL;
    if (!gpu || !emu || !b || halo_feature_buffer_build(b, view) != HALO_OK ||
        halo_feature_buffer_read(b, gpu) != HALO_OK ||
        halo_feature_compute(HALO_FEATURE_EMULATED_BUFFER, values, dims, desc, view, emu) != HALO_OK) {
        print_error(c, row);
    } else {
        stats s = {0};
        for (size_t i = 0; i < count; ++i)
            add_value(&s, gpu[i], emu[i], FEATURE_SPLAT_TOLERANCE, i);
        feature_print_row(c, row, &s, FEATURE_SPLAT_TOLERANCE, FEATURE_SPLAT_WHY);
    }
    halo_feature_buffer_destroy(b);
    free(gpu);
    free(emu);
}

/* |grad f| at a voxel, the host contract's gradient written out here (not the library's):
 * central differences over +-1 voxel, halved, the neighbours clamped at the faces. */
static double gradient_magnitude_at(const float *values, const int dims[3], int x, int y, int z)
{
    const int at[3] = {x, y, z};
    double sum = 0.0;
    for (int k = 0; k < 3; ++k) {
        int lo[3] = {x, y, z}, hi[3] = {x, y, z};
        lo[k] = at[k] > 0 ? at[k] - 1 : 0;
        hi[k] = at[k] < dims[k] - 1 ? at[k] + 1 : dims[k] - 1;
        double a = values[((size_t)lo[2] * (size_t)dims[1] + (size_t)lo[1]) * (size_t)dims[0] + (size_t)lo[0]];
        double b = values[((size_t)hi[2] * (size_t)dims[1] + (size_t)hi[1]) * (size_t)dims[0] + (size_t)hi[0]];
        double g = 0.5 * (b - a);
        sum += g * g;
    }
    return sqrt(sum);
}

/* The emulated buffer without cutoff, times S and (1 - |grad f|), is the paper's sum. */
static void run_reference_row(feature_context *c, const float *values, int n, const double view[3])
{
    int dims[3] = {n, n, n};
    size_t count = (size_t)n * n * n;
    halo_feature_desc desc = {.splat_size = 5, .threshold = -1};
    double *emu = malloc(count * sizeof *emu), *exact = malloc(count * sizeof *exact);
    if (!emu || !exact ||
        halo_feature_compute(HALO_FEATURE_EMULATED_BUFFER, values, dims, &desc, view, emu) != HALO_OK ||
        halo_feature_compute(HALO_FEATURE_REFERENCE, values, dims, &desc, view, exact) != HALO_OK) {
        print_error(c, "feature_reference");
    } else {
        double sum = halo_feature_desc_layout(&desc, NULL).splat_weight_sum;
        stats s = {0};
        size_t i = 0;
        for (int z = 0; z < n; ++z)
            for (int y = 0; y < n; ++y)
                for (int x = 0; x < n; ++x, ++i) {
                    double factor = 1.0 - gradient_magnitude_at(values, dims, x, y, z);
                    factor = factor < 0.0 ? 0.0 : factor > 1.0 ? 1.0 : factor;
                    add_value(&s, emu[i] * sum * factor, exact[i], FEATURE_REFERENCE_TOLERANCE, i);
                }
        feature_print_row(c, "feature_reference", &s, FEATURE_REFERENCE_TOLERANCE, FEATURE_REFERENCE_WHY);
    }
    free(emu);
    free(exact);
}

/* ---- Application rows ----------------------------------------------------------------- */

static uint64_t random_state;

static double random_uniform(void) /* splitmix64, [0, 1) */ { return conform_random_uniform(&random_state); }

#define PROBE_SIZE 48

static void fill_samples(halo_emu_sample *samples)
{
    random_state = 0x5eed0f3a7u;
    for (int y = 0; y < PROBE_SIZE; ++y)
        for (int x = 0; x < PROBE_SIZE; ++x) {
            halo_emu_sample *s = &samples[y * PROBE_SIZE + x];
            memset(s, 0, sizeof *s);
            for (int k = 0; k < 3; ++k) {
                /* a few positions outside [0,1]: CLAMP_TO_EDGE */
                s->position[k] = random_uniform() * 1.1 - 0.05;
                s->gradient[k] = (random_uniform() - 0.5) * (x % 4 == 0 ? 0.0 : x % 4 == 1 ? 0.2 : 1.0);
                s->color[k] = random_uniform();
            }
            double v[3] = {random_uniform() - 0.5, random_uniform() - 0.5, random_uniform() - 0.5};
            double l = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
            for (int k = 0; k < 3; ++k)
                s->view[k] = l > 0 ? v[k] / l : 0.0;
            s->value = random_uniform();
            s->depth = random_uniform();
            s->opacity = y % 5 == 0 ? 0.0 : random_uniform();
            halo_probe_round_inputs(s, x, y);
        }
}

static const char probe_vertex[] =
    "#version 330 core\n"
    "out vec2 ndc;\n"
    "void main()\n"
    "{\n"
    "    vec2 corner = vec2(float((gl_VertexID & 1) << 2), float((gl_VertexID & 2) << 1)) - 1.0;\n"
    "    ndc = corner;\n"
    "    gl_Position = vec4(corner, 0.0, 1.0);\n"
    "}\n";

/* Draws probe.frag linked with program over the samples with the buffer bound; rgba out. */
static int draw_probe(feature_context *c, const halo_program *program, unsigned buffer_texture,
                      const halo_emu_sample *samples, float *rgba)
{
    const halo_glfuncs *f = c->f;
    GLuint gl_program = halo_gl_program_build(c->runtime, program, probe_vertex, "feature_probe.vert", NULL, c->diag);
    if (!gl_program)
        return 0;
    size_t n = (size_t)PROBE_SIZE * PROBE_SIZE;
    float *staging = malloc(n * 4 * sizeof *staging);
    GLuint inputs[4], color, framebuffer, vertex_array;
    f->GenTextures(4, inputs);
    f->GenTextures(1, &color);
    static const char *const names[4] = {"position_value", "gradient_depth", "view_texture", "color_opacity"};
    for (int t = 0; t < 5; ++t) {
        if (t < 4 && staging)
            for (size_t i = 0; i < n; ++i) {
                const halo_emu_sample *s = &samples[i];
                const double *v = t == 0 ? s->position : t == 1 ? s->gradient : t == 2 ? s->view : s->color;
                double w = t == 0 ? s->value : t == 1 ? s->depth : t == 2 ? 0.0 : s->opacity;
                float *d = &staging[i * 4];
                d[0] = (float)v[0], d[1] = (float)v[1], d[2] = (float)v[2], d[3] = (float)w;
            }
        f->BindTexture(GL_TEXTURE_2D, t < 4 ? inputs[t] : color);
        f->TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
        f->TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
        f->PixelStorei(GL_UNPACK_ALIGNMENT, 4);
        f->TexImage2D(GL_TEXTURE_2D, 0, GL_RGBA32F, PROBE_SIZE, PROBE_SIZE, 0, GL_RGBA, GL_FLOAT,
                      t < 4 ? staging : NULL);
    }
    f->GenFramebuffers(1, &framebuffer);
    f->BindFramebuffer(GL_FRAMEBUFFER, framebuffer);
    f->FramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, color, 0);
    f->Viewport(0, 0, PROBE_SIZE, PROBE_SIZE);
    f->Disable(GL_BLEND);
    f->Disable(GL_DEPTH_TEST);
    f->UseProgram(gl_program);
    halo_gl_program_upload(c->runtime, program, gl_program);
    for (int t = 0; t < 4; ++t) {
        f->ActiveTexture(GL_TEXTURE0 + (GLenum)t);
        f->BindTexture(GL_TEXTURE_2D, inputs[t]);
        f->Uniform1i(f->GetUniformLocation(gl_program, names[t]), t);
    }
    /* the halo buffer on unit 4: a sampler host uniform is set with its unit */
    f->ActiveTexture(GL_TEXTURE4);
    f->BindTexture(GL_TEXTURE_3D, buffer_texture);
    f->Uniform1i(f->GetUniformLocation(gl_program, "halo_host_feature_buffer"), 4);
    f->ActiveTexture(GL_TEXTURE0);
    f->GenVertexArrays(1, &vertex_array);
    f->BindVertexArray(vertex_array);
    f->DrawArrays(GL_TRIANGLES, 0, 3);
    f->ReadBuffer(GL_COLOR_ATTACHMENT0);
    f->PixelStorei(GL_PACK_ALIGNMENT, 4);
    f->ReadPixels(0, 0, PROBE_SIZE, PROBE_SIZE, GL_RGBA, GL_FLOAT, rgba);
    f->BindVertexArray(0);
    f->ActiveTexture(GL_TEXTURE4);
    f->BindTexture(GL_TEXTURE_3D, 0);
    for (int t = 3; t >= 0; --t) {
        f->ActiveTexture(GL_TEXTURE0 + (GLenum)t);
        f->BindTexture(GL_TEXTURE_2D, 0);
    }
    f->UseProgram(0);
    f->BindFramebuffer(GL_FRAMEBUFFER, 0);
    f->DeleteVertexArrays(1, &vertex_array);
    f->DeleteFramebuffers(1, &framebuffer);
    f->DeleteTextures(4, inputs);
    f->DeleteTextures(1, &color);
    f->DeleteProgram(gl_program);
    free(staging);
    GLenum error = f->GetError();
    if (error != GL_NO_ERROR || !staging) {
        fprintf(stderr, "conform: feature probe: OpenGL error 0x%x\n", error);
        return 0;
    }
    return 1;
}

static void run_apply_row(feature_context *c, const char *row, const char *scene_json, int live, double gain,
                          double darkening, const float *volume, int n)
{
    halo_scene *scene = halo_scene_load("(conformance feature scene)", scene_json, c->lib, c->diag);
    halo_program *program = scene ? halo_link(&(halo_link_desc){.library = c->lib,
                                                                .scene = scene,
                                                                .host_source = halo_host_embedded("probe.frag"),
                                                                .host_file = "probe.frag",
                                                                .all_live = live},
                                              c->diag)
                                  : NULL;
    if (program && live) {
        halo_program_set(program, "feature_halo", "opacity_gain", &gain, 1, c->diag);
        halo_program_set(program, "feature_halo", "darkening", &darkening, 1, c->diag);
    }
    int dims[3] = {n, n, n};
    halo_feature_buffer *b =
        program ? halo_feature_buffer_create(c->runtime, volume, dims, &(halo_feature_desc){0}, c->diag) : NULL;
    size_t count = (size_t)PROBE_SIZE * PROBE_SIZE, texels = (size_t)n * n * n;
    halo_emu_sample *samples = malloc(count * sizeof *samples);
    float *rgba = malloc(count * 4 * sizeof *rgba), *buffer = malloc(texels * sizeof *buffer);
    double *buffer_double = malloc(texels * sizeof *buffer_double);
    halo_emu_frame *frame = NULL;
    static const double view[3] = {0.3, 0.5, 0.81};
    if (!b || !samples || !rgba || !buffer || !buffer_double || halo_feature_buffer_build(b, view) != HALO_OK ||
        halo_feature_buffer_read(b, buffer) != HALO_OK) {
        print_error(c, row);
        goto done;
    }
    for (size_t i = 0; i < texels; ++i)
        buffer_double[i] = buffer[i];
    fill_samples(samples);
    if (!draw_probe(c, program, halo_feature_buffer_describe(b).texture, samples, rgba)) {
        print_error(c, row);
        goto done;
    }
    /* the emulated frame holds the halo buffer's value at the sample in the host uniform
     * (it has no 3D textures) */
    frame = halo_emu_frame_create(program, 1, 1, c->diag);
    if (!frame) {
        print_error(c, row);
        goto done;
    }
    stats s = {0};
    for (size_t i = 0; i < count; ++i) {
        halo_emu_sample e = samples[i];
        /* the emulation reads the GPU's own buffer: this row measures the stage alone */
        double value = halo_feature_buffer_lookup(buffer_double, dims, e.position);
        if (halo_emu_frame_set_host_uniform(frame, HALO_HOST_FEATURE_BUFFER, &value, 1) != HALO_OK ||
            halo_emu_apply(program, frame, &e, c->diag) != HALO_OK) {
            print_error(c, row);
            goto done;
        }
        double expect[4] = {e.color[0], e.color[1], e.color[2], e.opacity};
        for (int k = 0; k < 4; ++k)
            add_value(&s, rgba[i * 4 + (size_t)k], expect[k], FEATURE_APPLY_TOLERANCE, i * 4 + (size_t)k);
    }
    feature_print_row(c, row, &s, FEATURE_APPLY_TOLERANCE, FEATURE_APPLY_WHY);
done:
    halo_emu_frame_destroy(frame);
    halo_feature_buffer_destroy(b);
    halo_program_destroy(program);
    halo_scene_destroy(scene);
    free(samples);
    free(rgba);
    free(buffer);
    free(buffer_double);
}

#define WANT(row) (!only || !strcmp(only, row))

/* The rows named only (NULL: all). */
static int run_rows(const char *only, int verbose, int *failed)
{
    feature_context c = {.verbose = verbose};
    halo_headless *context = NULL;
    c.diag = halo_diagnostics_create();
    halo_setup(NULL);
    c.lib = halo_library_create(c.diag);
    char err[512];
    c.runtime = conform_gl_current_or_headless(&context, c.diag, err, sizeof err);
    if (!c.runtime && !context)
        fprintf(stderr, "halo-validate: conform: %s\n", err);
    static const char *const rows[] = {"feature_splat",           "feature_splat@n3",       "feature_splat@n9",
                                       "feature_splat@half",      "feature_splat@weighted", "feature_splat@nocutoff",
                                       "feature_splat@constant",  "feature_splat@voxel",    "feature_splat@edge",
                                       "feature_splat@edge_half", "feature_reference",      "feature_halo",
                                       "feature_halo@live",       "feature_halo@strong"};
    const int n = 32;
    float *volume = halo_volume_create(n);
    if (!c.lib || !c.runtime || !volume || halo_feature_ensure_module(c.lib, c.diag) != HALO_OK) {
        for (size_t i = 0; i < sizeof rows / sizeof rows[0]; ++i)
            if (WANT(rows[i]))
                print_error(&c, rows[i]);
    } else {
        c.f = halo_headless_functions();
        static const double oblique[3] = {0.3, 0.5, 0.81}, axis[3] = {0, 0, 1}, side[3] = {1, 0, 0};
        if (WANT("feature_splat"))
            run_splat_row(&c, "feature_splat", volume, n, &(halo_feature_desc){0}, oblique);
        if (WANT("feature_splat@n3"))
            run_splat_row(&c, "feature_splat@n3", volume, n, &(halo_feature_desc){.splat_size = 3, .k_hse = 0.5}, axis);
        if (WANT("feature_splat@n9"))
            run_splat_row(&c, "feature_splat@n9", volume, n, &(halo_feature_desc){.splat_size = 9, .threshold = 0.2},
                          oblique);
        if (WANT("feature_splat@half"))
            run_splat_row(&c, "feature_splat@half", volume, n, &(halo_feature_desc){.half_resolution = 1}, oblique);
        if (WANT("feature_splat@weighted"))
            run_splat_row(&c, "feature_splat@weighted", volume, n,
                          &(halo_feature_desc){.threshold = 0.05, .gradient_weighted = 1, .k_hpe = 2}, oblique);
        if (WANT("feature_splat@nocutoff"))
            run_splat_row(&c, "feature_splat@nocutoff", volume, n,
                          &(halo_feature_desc){.threshold = -1, .k_hpe = 3, .k_hse = 1}, side);
        float *hard = constant_volume(16, 0.5f);
        if (WANT("feature_splat@constant"))
            run_splat_row(&c, "feature_splat@constant", hard, 16, &(halo_feature_desc){.threshold = -1}, oblique);
        free(hard);
        hard = single_voxel_volume(15);
        if (WANT("feature_splat@voxel"))
            run_splat_row(&c, "feature_splat@voxel", hard, 15, &(halo_feature_desc){.splat_size = 7}, axis);
        free(hard);
        hard = edge_volume(16);
        if (WANT("feature_splat@edge"))
            run_splat_row(&c, "feature_splat@edge", hard, 16, &(halo_feature_desc){0}, oblique);
        if (WANT("feature_splat@edge_half"))
            run_splat_row(&c, "feature_splat@edge_half", hard, 16, &(halo_feature_desc){.half_resolution = 1}, axis);
        free(hard);
        if (WANT("feature_reference"))
            run_reference_row(&c, volume, n, oblique);
        static const char scene[] = "{\"halo_scene\": 1, \"stages\": [{\"feature_halo\": {}}]}";
        if (WANT("feature_halo"))
            run_apply_row(&c, "feature_halo", scene, 0, 0, 0, volume, n);
        if (WANT("feature_halo@live"))
            run_apply_row(&c, "feature_halo@live", scene, 1, 7.5, 0.5, volume, n);
        if (WANT("feature_halo@strong"))
            run_apply_row(
                &c, "feature_halo@strong",
                "{\"halo_scene\": 1, \"stages\": [{\"feature_halo\": {\"opacity_gain\": 50, \"darkening\": 50}}]}", 0,
                0, 0, volume, n);
    }
    free(volume);
    halo_gl_destroy(c.runtime);
    halo_headless_destroy(context);
    halo_library_destroy(c.lib);
    halo_diagnostics_destroy(c.diag);
    halo_shutdown();
    if (failed)
        *failed += c.failed;
    return c.rows;
}

#undef WANT

int halo_conform_feature_rows(int verbose, int *failed) { return run_rows(NULL, verbose, failed); }

void conform_feature_row(conform *c, const conform_row *row)
{
    /* --stage feature... selects the family */
    if (c->only && strncmp(c->only, "feature", 7))
        return;
    if (conform_skip_on_es(c, row->name, "the feature halo runtime (libhalo/gl/feature_splat.c) draws with GLSL 330"))
        return;
    c->rows += run_rows(row->name, c->verbose, &c->failures);
}
