/* The conformance harness: see conform_harness.h. */
#include "conform_harness.h"

#include "halo.h"
#include "halo_gl_loader.h"
#include "gl/headless.h"
#include "hosts/host_common.h"
#include "hosts/raycast.h"
#include "hosts/slice.h"

#include <errno.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* ---- Rows ------------------------------------------------------------------------------ */

void conform_tolerance_text(const conform_row *row, char *text, size_t size)
{
    snprintf(text, size, row->tolerance, row->tolerance_abs, row->tolerance_rel);
}

int conform_has_row(const conform *c, const char *name)
{
    for (size_t i = 0; i < c->registry_count; ++i)
        if (!strcmp(c->registry[i].name, name))
            return 1;
    return 0;
}

/* ---- Statistics and rows -------------------------------------------------------------- */

/* row_stats and conform: conform_harness.h */

int row_selected(const conform *c, const char *row, const char *stage)
{
    return !c->only || strcmp(c->only, row) == 0 || (stage && strcmp(c->only, stage) == 0);
}

void print_row_line(const char *row, const row_stats *s, const char *tolerance, int pass)
{
    double rmse = s->values ? sqrt(s->sum_squares / (double)s->values) : 0.0;
    printf("%-26s %10.3e %10.3e %8zu %9zu %17s %s\n", row, s->max_abs, rmse, s->over, s->nonfinite, tolerance,
           pass ? "PASS" : "FAIL");
    fflush(stdout);
}

void print_row(conform *c, const char *row, const row_stats *s, const char *tolerance, int pass)
{
    print_row_line(row, s, tolerance, pass);
    c->rows++;
    if (!pass)
        c->failures++;
}

int conform_skip_on_es(conform *c, const char *row, const char *why)
{
    if (!c->es)
        return 0;
    printf("%-26s skipped on OpenGL ES %d.%d: %s\n", row, c->es / 10, c->es % 10, why);
    fflush(stdout);
    c->skipped++;
    return 1;
}

/* A row that could not run (link or compile error): the diagnostics say why. */
void print_error_row_line(const char *row, int tolerance_width, halo_diagnostics *diag)
{
    printf("%-26s %10s %10s %8s %9s %*s FAIL\n", row, "-", "-", "-", "-", tolerance_width, "-");
    halo_diagnostics_print(diag, stderr);
    halo_diagnostics_clear(diag);
    fflush(stdout);
}

void print_error_row(conform *c, const char *row)
{
    if (c->es == 30 && halo_diagnostics_has(c->diag, HALO_MSG_GL_PROC_MISSING)) {
        /* the runtime's own refusal of what this OpenGL ES version lacks (its diagnostic
         * names it: per-buffer blending on ES 3.0) */
        halo_diagnostics_clear(c->diag);
        conform_skip_on_es(c, row,
                           "the runtime refuses it here (GL_PROC_MISSING: the program writes extra "
                           "outputs, which need per-draw-buffer blending, ES 3.2; on ES 3.0 halos take "
                           "host contract 3, the ray@one_draw rows)");
        return;
    }
    print_error_row_line(row, 12, c->diag);
    c->rows++;
    c->failures++;
}

void conform_row_end(conform *c, const char *row, int printed, halo_program *program, halo_scene *scene)
{
    if (!printed)
        print_error_row(c, row);
    halo_diagnostics_clear(c->diag);
    halo_program_destroy(program);
    halo_scene_destroy(scene);
}

halo_gl *conform_gl_current_or_headless(halo_headless **context, halo_diagnostics *diag, char *err, size_t size)
{
    *context = NULL;
    halo_gl *runtime = halo_gl_create(&(halo_gl_desc){.get_proc_address = halo_headless_get_proc_address}, NULL);
    if (runtime && halo_headless_functions()->GetString(GL_VERSION))
        return runtime;
    halo_gl_destroy(runtime);
    *context = halo_headless_create(64, 64, err, size);
    return *context ? halo_gl_create(&(halo_gl_desc){.get_proc_address = halo_headless_get_proc_address}, diag) : NULL;
}

int row_stats_note(row_stats *s, size_t index, double error)
{
    s->sum_squares += error * error;
    s->values++;
    if (!(error > s->max_abs))
        return 0;
    s->max_abs = error;
    s->worst = index;
    return 1;
}

int row_stats_add(row_stats *s, size_t index, const double *gpu, const double *emu, const double *condition, int n,
                  double tolerance_abs, double tolerance_rel)
{
    int over = 0, nonfinite = 0;
    for (int k = 0; k < n; ++k) {
        if (!isfinite(gpu[k]) || !isfinite(emu[k])) {
            nonfinite = 1;
            continue;
        }
        double error = fabs(gpu[k] - emu[k]);
        double allowed = tolerance_abs + tolerance_rel * fabs(emu[k]) + (condition ? condition[k] : 0.0);
        row_stats_note(s, index, error);
        if (error > allowed)
            over = 1;
    }
    s->over += (size_t)over;
    s->nonfinite += (size_t)nonfinite;
    return over;
}

void print_header(void)
{
    printf("%-26s %10s %10s %8s %9s %17s %s\n", "stage", "max_abs", "rmse", "over_tol", "nonfinite", "tolerance",
           "result");
}

void print_plain_row(conform *c, const char *row, const char *tolerance, int pass)
{
    printf("%-26s %10s %10s %8s %9s %17s %s\n", row, "-", "-", "-", "-", tolerance, pass ? "PASS" : "FAIL");
    c->rows++;
    if (!pass)
        c->failures++;
}

/* ---- Probe inputs ---------------------------------------------------------------------- */

double conform_random_uniform(uint64_t *state)
{
    uint64_t z = (*state += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    z ^= z >> 31;
    return (double)(z >> 11) / 9007199254740992.0;
}

static uint64_t random_state;

static double random_uniform(void) /* splitmix64, [0, 1) */ { return conform_random_uniform(&random_state); }

void conform_normalize3(double v[3])
{
    double n = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    if (n > 0.0)
        for (int k = 0; k < 3; ++k)
            v[k] /= n;
}

static void set3(double out[3], double x, double y, double z) { out[0] = x, out[1] = y, out[2] = z; }

/* A (gradient, view) pair of the hard cases. */
typedef struct direction_case {
    double gradient[3];
    double view[3];
} direction_case;

/* Float one ulp above and below 1 (2^-23 and 2^-24 away). */
#define ONE_ULP_UP   (1.0 + 1.0 / 8388608.0)
#define ONE_ULP_DOWN (1.0 - 1.0 / 16777216.0)

static size_t direction_cases(direction_case *out)
{
    size_t n = 0;
    double oblique[3] = {1, 2, 3}, other[3] = {-0.3, 0.5, -0.8};
    conform_normalize3(oblique);
    conform_normalize3(other);
    /* Round the view to float first: the host's V is a float unit vector. */
    for (int k = 0; k < 3; ++k)
        oblique[k] = (float)oblique[k], other[k] = (float)other[k];
    const double *views[] = {(const double[]){0, 0, 1}, (const double[]){0, 0, -1}, (const double[]){1, 0, 0}, oblique,
                             other};
    for (size_t v = 0; v < sizeof views / sizeof views[0]; ++v) {
        const double *V = views[v];
        /* no gradient, and gradients too small to have a direction (|g|^2 < 1e-20) */
        set3(out[n].gradient, 0, 0, 0), memcpy(out[n++].view, V, 3 * sizeof *V);
        set3(out[n].gradient, 1e-12, 0, 0), memcpy(out[n++].view, V, 3 * sizeof *V);
        set3(out[n].gradient, 0, -1e-12, 1e-12), memcpy(out[n++].view, V, 3 * sizeof *V);
        /* tiny but with a direction (|g|^2 = 1e-18, above the guard) */
        for (int k = 0; k < 3; ++k)
            out[n].gradient[k] = -1e-9 * V[k];
        memcpy(out[n++].view, V, 3 * sizeof *V);
        /* n.V = +1 exactly (g = -a V: the normal points to the eye), and -1 */
        for (int k = 0; k < 3; ++k)
            out[n].gradient[k] = -0.3 * V[k];
        memcpy(out[n++].view, V, 3 * sizeof *V);
        for (int k = 0; k < 3; ++k)
            out[n].gradient[k] = 0.25 * V[k];
        memcpy(out[n++].view, V, 3 * sizeof *V);
        /* parallel, but the view one ulp longer / shorter than 1: n.V rounds past +-1 */
        for (int k = 0; k < 3; ++k) {
            out[n].gradient[k] = -0.2 * V[k];
            out[n].view[k] = V[k] * ONE_ULP_UP;
        }
        n++;
        for (int k = 0; k < 3; ++k) {
            out[n].gradient[k] = 0.45 * V[k];
            out[n].view[k] = V[k] * ONE_ULP_DOWN;
        }
        n++;
        /* perpendicular: n.V = 0 (silhouette) */
        double perpendicular[3] = {V[1] - V[2], V[2] - V[0], V[0] - V[1]};
        conform_normalize3(perpendicular);
        for (int k = 0; k < 3; ++k)
            out[n].gradient[k] = 0.4 * perpendicular[k];
        memcpy(out[n++].view, V, 3 * sizeof *V);
        /* the largest gradient the host contract allows (|each component| <= 0.5) */
        set3(out[n].gradient, 0.5, -0.5, 0.5), memcpy(out[n++].view, V, 3 * sizeof *V);
    }
    return n;
}

/* conform_harness.h */
void conform_fill_samples(halo_emu_sample *samples, int width, int height)
{
    static direction_case directions[64];
    size_t direction_count = direction_cases(directions);
    static const double depths[] = {0.0, 1.0, 0.5, 1e-7, 0.9999999};
    static const double opacities[] = {0.0, 1.0, 0.5, 0.02};
    static const double colors[][3] = {{0, 0, 0},       {1, 1, 1}, {1, 0, 0},    {0.2, 0.5, 0.9},
                                       {0.5, 0.5, 0.5}, {1, 1, 0}, {0, 0.3, 0.3}};
    static const double values[] = {0.0, 1.0, 0.5};
    static const double positions[][3] = {{0.5, 0.5, 0.5}, {0, 0, 0}, {1, 1, 1}};
    const size_t depth_count = sizeof depths / sizeof depths[0];
    const size_t opacity_count = sizeof opacities / sizeof opacities[0];
    const size_t hard = direction_count * depth_count * opacity_count;
    const size_t count = (size_t)width * (size_t)height;
    random_state = 0x68616c6f2d636f6eull; /* fixed seed: every run uses the same samples */
    for (size_t i = 0; i < count; ++i) {
        halo_emu_sample *s = &samples[i];
        memset(s, 0, sizeof *s);
        if (i < hard) {
            const direction_case *d = &directions[i % direction_count];
            memcpy(s->gradient, d->gradient, sizeof s->gradient);
            memcpy(s->view, d->view, sizeof s->view);
            s->depth = depths[(i / direction_count) % depth_count];
            s->opacity = opacities[(i / (direction_count * depth_count)) % opacity_count];
            memcpy(s->color, colors[i % (sizeof colors / sizeof colors[0])], sizeof s->color);
            s->value = values[i % 3];
            memcpy(s->position, positions[(i / 3) % 3], sizeof s->position);
        } else {
            for (int k = 0; k < 3; ++k) {
                s->position[k] = random_uniform();
                s->color[k] = random_uniform();
                s->view[k] = random_uniform() * 2.0 - 1.0;
                s->gradient[k] = random_uniform() - 0.5;
            }
            conform_normalize3(s->view);
            /* gradient magnitudes over many scales, 1e-6 .. 0.87 */
            double scale = pow(10.0, -6.0 * random_uniform() * random_uniform());
            for (int k = 0; k < 3; ++k)
                s->gradient[k] *= scale;
            s->value = random_uniform();
            s->depth = random_uniform();
            double o = random_uniform();
            s->opacity = o < 0.05 ? 0.0 : o > 0.95 ? 1.0 : o;
        }
        halo_probe_round_inputs(s, (int)(i % (size_t)width), (int)(i / (size_t)width));
    }
}

/* Linear filtering of the table at texel coordinate u in [0, texels - 1]. */
static void transfer_texels(const float *transfer, int texels, double u, double rgba[4])
{
    double base = floor(u);
    double f = u - base;
    int i0 = (int)base, i1 = i0 + 1 > texels - 1 ? texels - 1 : i0 + 1;
    for (int k = 0; k < 4; ++k)
        rgba[k] = (1.0 - f) * transfer[i0 * 4 + k] + f * transfer[i1 * 4 + k];
}

void conform_transfer_lookup(const float *transfer, int texels, double value, double rgba[4])
{
    double v = value > 0.0 ? (value < 1.0 ? value : 1.0) : 0.0; /* NaN -> 0, as the hosts do */
    transfer_texels(transfer, texels, v * (texels - 1), rgba);  /* ((v (n-1) + 0.5) / n) * n - 0.5 */
}

void conform_transfer_texture(const float *transfer, int texels, double value, double rgba[4])
{
    double v = value > 0.0 ? (value < 1.0 ? value : 1.0) : 0.0;
    double u = v * texels - 0.5; /* clamped to the edge texels */
    transfer_texels(transfer, texels, u < 0.0 ? 0.0 : u > texels - 1 ? texels - 1 : u, rgba);
}

void conform_transform(const double m[16], const double v[4], double out[4])
{
    for (int row = 0; row < 4; ++row)
        out[row] = m[row] * v[0] + m[4 + row] * v[1] + m[8 + row] * v[2] + m[12 + row] * v[3];
}

void conform_pixel_ray(const double inverse_view_projection[16], int width, int height, int x, int y, double origin[3],
                       double direction[3])
{
    double ndc[2] = {(x + 0.5) / width * 2.0 - 1.0, (y + 0.5) / height * 2.0 - 1.0};
    double near_point[4], far_point[4];
    conform_transform(inverse_view_projection, (const double[]){ndc[0], ndc[1], -1.0, 1.0}, near_point);
    conform_transform(inverse_view_projection, (const double[]){ndc[0], ndc[1], 1.0, 1.0}, far_point);
    double length = 0.0;
    for (int k = 0; k < 3; ++k) {
        origin[k] = near_point[k] / near_point[3];
        direction[k] = far_point[k] / far_point[3] - origin[k];
        length += direction[k] * direction[k];
    }
    length = sqrt(length);
    for (int k = 0; k < 3; ++k)
        direction[k] /= length;
}

halo_emu_frame *conform_host_frame(const halo_program *p, int width, int height, const double screen_right[3],
                                   const double screen_up[3], int *ok, halo_diagnostics *diag)
{
    *ok = 1;
    if (!halo_program_reflection(p).image_count && !halo_program_reflection(p).output_count &&
        !halo_program_reflection(p).sampler_count)
        return NULL;
    halo_emu_frame *frame = halo_emu_frame_create(p, width, height, diag);
    if (!frame) {
        *ok = 0;
        return NULL;
    }
    halo_emu_frame_begin(frame);
    halo_emu_frame_set_host_uniform(frame, "screen_right", screen_right, 3);
    halo_emu_frame_set_host_uniform(frame, "screen_up", screen_up, 3);
    return frame;
}

void conform_over_background(double *rgba, size_t pixels, const double background[3])
{
    for (size_t i = 0; i < pixels; ++i) {
        double *px = &rgba[i * 4];
        for (int c = 0; c < 3; ++c)
            px[c] += (1.0 - px[3]) * background[c];
        px[3] = 1.0;
    }
}

void *conform_host_frame_rays(const halo_program *p, int width, int height, const double screen_right[3],
                              const double screen_up[3], size_t ray_size, conform_ray_init *init, void *context,
                              halo_emu_frame **frame, halo_diagnostics *diag)
{
    unsigned char *rays = malloc((size_t)width * (size_t)height * ray_size);
    if (!rays) {
        HALO_REPORT_ERROR(diag, HALO_MSG_OUT_OF_MEMORY, "", 0, 0, "out of memory");
        return NULL;
    }
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x)
            init(context, x, y, rays + ((size_t)y * (size_t)width + (size_t)x) * ray_size);
    int framed = 1;
    *frame = conform_host_frame(p, width, height, screen_right, screen_up, &framed, diag);
    if (!framed) {
        free(rays);
        return NULL;
    }
    return rays;
}

void conform_print_sample(const char *label, const halo_emu_sample *s, const float *gpu, const double *emu)
{
    fprintf(stderr,
            "  %s: position (%.9g %.9g %.9g) value %.9g gradient (%.9g %.9g %.9g) view (%.9g %.9g %.9g)\n"
            "    depth %.9g colour (%.9g %.9g %.9g) opacity %.9g fragcoord (%.1f %.1f)\n"
            "    gpu (%.9g %.9g %.9g %.9g) emulation (%.9g %.9g %.9g %.9g)\n",
            label, s->position[0], s->position[1], s->position[2], s->value, s->gradient[0], s->gradient[1],
            s->gradient[2], s->view[0], s->view[1], s->view[2], s->depth, s->color[0], s->color[1], s->color[2],
            s->opacity, s->fragcoord[0], s->fragcoord[1], gpu[0], gpu[1], gpu[2], gpu[3], emu[0], emu[1], emu[2],
            emu[3]);
}

/* conform_harness.h */
void conform_set_live_arrays(halo_program *p, const halo_module *m, halo_diagnostics *diag)
{
    static const double elements[4][4] = {
        {0.6, -0.8, 0.0, 1.0}, {0.0, 0.0, 0.0, 0.0}, {-0.3, 0.5, 0.8, 0.5}, {1.0, 1.0, -1.0, 0.25}};
    for (size_t i = 0; i < halo_module_describe(m).param_count; ++i) {
        const halo_param_info *info = &halo_module_describe(m).params[i];
        if (info->array_size < 2)
            continue;
        int count = info->array_size < 4 ? info->array_size : 4;
        double values[HALO_MAX_COMPONENTS];
        for (int e = 0; e < count; ++e)
            for (int k = 0; k < info->components; ++k) {
                double v = elements[e][k];
                values[e * info->components + k] = v < info->min ? info->min : v > info->max ? info->max : v;
            }
        halo_program_set(p, halo_module_describe(m).name, info->name, values, count, diag);
    }
}

/* ---- The frame probe -------------------------------------------------------------------
 *
 * Frame rows run through the GL runtime's frame (halo_gl_frame_*: images, attached outputs,
 * bound samplers, the pass schedule) and compare with the emulation's frame
 * (halo_emu_frame_*). The probe host is drawn by conform itself (it needs the output
 * attachments and the image samplers, which halo_probe does not set up). */

/* The image-plane axes the frame rows use (oblique, so that both matter), as floats. */
void host_axes(double right[3], double up[3])
{
    const double a = 0.3, b = 0.4;
    double r[3] = {cos(a), sin(a), 0.0}, u[3] = {-sin(a) * cos(b), cos(a) * cos(b), sin(b)};
    for (int k = 0; k < 3; ++k)
        right[k] = (float)r[k], up[k] = (float)u[k];
}

/* Sampler host uniforms of the frame rows (e.g. outline_feature's "labels"): a small
 * volume of integer labels, the same in GL (unit 15) and in the emulation
 * (halo_emu_frame_set_volume); sampler2D host uniforms get a 1x1 texture on unit 14.
 * GL needs a texture of the sampler's own type on a unit of its own: the default unit 0
 * holds the probe's sampler2D inputs, and two sampler types on one unit are
 * GL_INVALID_OPERATION at draw. */
/* PROBE_VOLUME_*, PROBE_UNIT_*: conform_harness.h */

const float *probe_label_volume(void)
{
    static float labels[PROBE_VOLUME_X * PROBE_VOLUME_Y * PROBE_VOLUME_Z];
    for (int z = 0; z < PROBE_VOLUME_Z; ++z)
        for (int y = 0; y < PROBE_VOLUME_Y; ++y)
            for (int x = 0; x < PROBE_VOLUME_X; ++x)
                labels[(z * PROBE_VOLUME_Y + y) * PROBE_VOLUME_X + x] = (float)((x + 2 * y + 3 * z) % 4);
    return labels;
}

/* frame_probe: conform_harness.h */

void frame_probe_release(frame_probe *fp)
{
    const halo_glfuncs *f = fp->f;
    if (f) { /* glDelete* passes over the names never made (0) */
        f->DeleteFramebuffers(1, &fp->framebuffer);
        f->DeleteTextures(1, &fp->color);
        f->DeleteTextures(4, fp->inputs);
        f->DeleteVertexArrays(1, &fp->vertex_array);
        f->DeleteTextures(2, fp->host_textures);
        f->DeleteProgram(fp->program);
    }
    free(fp->staging);
    halo_gl_frame_destroy(fp->gl_frame);
    halo_emu_frame_destroy(fp->emu_frame);
    memset(fp, 0, sizeof *fp);
}

int frame_probe_open(conform *c, const halo_program *p, int size, frame_probe *fp)
{
    halo_gl_frame *gl_frame = halo_gl_frame_create(c->runtime, p, size, size, c->diag);
    halo_emu_frame *emu_frame = halo_emu_frame_create(p, size, size, c->diag);
    int ok = gl_frame && emu_frame && frame_probe_init(c, p, fp);
    fp->gl_frame = gl_frame;
    fp->emu_frame = emu_frame;
    return ok;
}

int frame_probe_init(conform *c, const halo_program *p, frame_probe *fp)
{
    memset(fp, 0, sizeof *fp);
    const halo_glfuncs *f = c->gl;
    fp->f = f;
    fp->size = c->size;
    /* (the example hosts' program build: raycast.vert in GLSL ES 300 for an ES program) */
    fp->program = halo_host_program_build(&(halo_host_desc){.gl = f, .runtime = c->runtime, .program = p},
                                          "raycast.vert", NULL, 0, c->diag);
    fp->staging = malloc((size_t)c->size * (size_t)c->size * 4 * sizeof *fp->staging);
    if (!fp->program || !fp->staging)
        return 0;
    f->GenVertexArrays(1, &fp->vertex_array);
    f->GenTextures(4, fp->inputs);
    f->GenTextures(1, &fp->color);
    for (int i = 0; i < 5; ++i)
        halo_host_image_texture(f, i < 4 ? fp->inputs[i] : fp->color, GL_RGBA32F, c->size, c->size, GL_RGBA, GL_FLOAT);
    f->BindTexture(GL_TEXTURE_2D, 0);
    f->GenTextures(2, fp->host_textures);
    f->BindTexture(GL_TEXTURE_3D, fp->host_textures[0]);
    f->TexParameteri(GL_TEXTURE_3D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    f->TexParameteri(GL_TEXTURE_3D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    f->PixelStorei(GL_UNPACK_ALIGNMENT, 4);
    f->TexImage3D(GL_TEXTURE_3D, 0, GL_R32F, PROBE_VOLUME_X, PROBE_VOLUME_Y, PROBE_VOLUME_Z, 0, GL_RED, GL_FLOAT,
                  probe_label_volume());
    f->BindTexture(GL_TEXTURE_3D, 0);
    f->BindTexture(GL_TEXTURE_2D, fp->host_textures[1]);
    f->TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    f->TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    f->TexImage2D(GL_TEXTURE_2D, 0, GL_RGBA32F, 1, 1, 0, GL_RGBA, GL_FLOAT, (const float[]){0, 0, 0, 0});
    f->BindTexture(GL_TEXTURE_2D, 0);
    f->GenFramebuffers(1, &fp->framebuffer);
    f->BindFramebuffer(GL_FRAMEBUFFER, fp->framebuffer);
    f->FramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, fp->color, 0);
    GLenum status = f->CheckFramebufferStatus(GL_FRAMEBUFFER);
    f->BindFramebuffer(GL_FRAMEBUFFER, 0);
    if (status != GL_FRAMEBUFFER_COMPLETE) {
        HALO_REPORT_ERROR(c->diag, HALO_MSG_GL_LINK, "", 0, 0, "frame probe: incomplete framebuffer (0x%x)", status);
        return 0;
    }
    return 1;
}

/* Draws probe.frag once over samples (one per pixel) with the frame's outputs attached and
 * images bound; reads colour and opacity back into rgba (may be NULL). */
halo_status frame_probe_draw(conform *c, frame_probe *fp, const halo_program *p, halo_gl_frame *frame,
                             const halo_emu_sample *samples, float *rgba)
{
    const halo_glfuncs *f = fp->f;
    size_t n = (size_t)fp->size * (size_t)fp->size;
    static const char *const names[4] = {"position_value", "gradient_depth", "view_texture", "color_opacity"};
    for (int t = 0; t < 4; ++t) {
        for (size_t i = 0; i < n; ++i) {
            const halo_emu_sample *s = &samples[i];
            float *d = &fp->staging[i * 4];
            const double *v = t == 0 ? s->position : t == 1 ? s->gradient : t == 2 ? s->view : s->color;
            double w = t == 0 ? s->value : t == 1 ? s->depth : t == 2 ? 0.0 : s->opacity;
            d[0] = (float)v[0], d[1] = (float)v[1], d[2] = (float)v[2], d[3] = (float)w;
        }
        f->BindTexture(GL_TEXTURE_2D, fp->inputs[t]);
        f->PixelStorei(GL_UNPACK_ALIGNMENT, 4);
        f->TexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, fp->size, fp->size, GL_RGBA, GL_FLOAT, fp->staging);
    }
    f->BindTexture(GL_TEXTURE_2D, 0);
    f->Disable(GL_BLEND);
    f->Disable(GL_DEPTH_TEST);
    f->Disable(GL_SCISSOR_TEST);
    f->BindFramebuffer(GL_FRAMEBUFFER, fp->framebuffer);
    halo_gl_frame_attach(frame, fp->framebuffer);
    f->Viewport(0, 0, fp->size, fp->size);
    f->UseProgram(fp->program);
    halo_gl_program_upload(c->runtime, p, fp->program);
    for (int t = 0; t < 4; ++t) {
        f->ActiveTexture(GL_TEXTURE0 + (GLenum)t);
        f->BindTexture(GL_TEXTURE_2D, fp->inputs[t]);
        f->Uniform1i(f->GetUniformLocation(fp->program, names[t]), t);
    }
    f->ActiveTexture(GL_TEXTURE0);
    halo_gl_frame_bind(frame, fp->program, 4);
    double right[3], up[3];
    host_axes(right, up);
    float fr[3] = {(float)right[0], (float)right[1], (float)right[2]},
          fu[3] = {(float)up[0], (float)up[1], (float)up[2]};
    for (size_t i = 0; i < halo_program_reflection(p).host_uniform_count; ++i) {
        const char *name = halo_program_reflection(p).host_uniforms[i].name;
        if (strstr(name, "screen_right"))
            halo_gl_set_host_uniform(c->runtime, fp->program, name, fr, 3);
        else if (strstr(name, "screen_up"))
            halo_gl_set_host_uniform(c->runtime, fp->program, name, fu, 3);
        else if (!strcmp(halo_program_reflection(p).host_uniforms[i].type, "sampler3D")) {
            f->ActiveTexture(GL_TEXTURE0 + PROBE_UNIT_3D);
            f->BindTexture(GL_TEXTURE_3D, fp->host_textures[0]);
            halo_gl_set_host_uniform(c->runtime, fp->program, name, (const float[]){PROBE_UNIT_3D}, 1);
        } else if (!strncmp(halo_program_reflection(p).host_uniforms[i].type, "sampler", 7)) {
            f->ActiveTexture(GL_TEXTURE0 + PROBE_UNIT_2D);
            f->BindTexture(GL_TEXTURE_2D, fp->host_textures[1]);
            halo_gl_set_host_uniform(c->runtime, fp->program, name, (const float[]){PROBE_UNIT_2D}, 1);
        }
    }
    f->ActiveTexture(GL_TEXTURE0);
    f->BindVertexArray(fp->vertex_array);
    f->DrawArrays(GL_TRIANGLES, 0, 3);
    f->BindVertexArray(0);
    if (rgba) {
        f->ReadBuffer(GL_COLOR_ATTACHMENT0);
        f->PixelStorei(GL_PACK_ALIGNMENT, 4);
        f->ReadPixels(0, 0, fp->size, fp->size, GL_RGBA, GL_FLOAT, rgba);
    }
    f->ActiveTexture(GL_TEXTURE0 + PROBE_UNIT_3D);
    f->BindTexture(GL_TEXTURE_3D, 0);
    f->ActiveTexture(GL_TEXTURE0 + PROBE_UNIT_2D);
    f->BindTexture(GL_TEXTURE_2D, 0);
    for (int t = 3; t >= 0; --t) {
        f->ActiveTexture(GL_TEXTURE0 + (GLenum)t);
        f->BindTexture(GL_TEXTURE_2D, 0);
    }
    f->UseProgram(0);
    f->Disable(GL_BLEND);
    f->BindFramebuffer(GL_FRAMEBUFFER, 0);
    GLenum error = f->GetError();
    if (error != GL_NO_ERROR) {
        HALO_REPORT_ERROR(c->diag, HALO_MSG_GL_LINK, "", 0, 0, "OpenGL error 0x%x while drawing the frame probe",
                          error);
        return HALO_ERROR_IO;
    }
    return HALO_OK;
}

void emu_set_axes(halo_emu_frame *ef)
{
    double right[3], up[3];
    host_axes(right, up);
    halo_emu_frame_set_host_uniform(ef, "screen_right", right, 3);
    halo_emu_frame_set_host_uniform(ef, "screen_up", up, 3);
}


void emu_set_probe_volumes(const halo_program *p, halo_emu_frame *ef)
{
    for (size_t i = 0; i < halo_program_reflection(p).host_uniform_count; ++i)
        if (!strcmp(halo_program_reflection(p).host_uniforms[i].type, "sampler3D"))
            halo_emu_frame_set_volume(ef, halo_program_reflection(p).host_uniforms[i].name + strlen("halo_host_"),
                                      probe_label_volume(), PROBE_VOLUME_X, PROBE_VOLUME_Y, PROBE_VOLUME_Z);
}


/* ---- Command line and set-up ---------------------------------------------------------------- */

static void conform_usage(FILE *out)
{
    fputs(
        "Usage: halo-validate conform [--stage NAME] [--size N] [-v] [--list] [--backend B]\n"
        "                             [--gradient-format F]\n"
        "Renders every per-sample stage through a headless OpenGL context (EGL or OSMesa) and\n"
        "compares it with the C emulation; one row per test:\n"
        "  empty     the ray caster linked with no stage against the unlinked one (bit for bit)\n"
        "  STAGE     the stage with its default parameters, on a probe of hard and random samples\n"
        "  STAGE@exp0, STAGE@exp64   every exponent parameter set to 0 / 64\n"
        "  STAGE@live                every parameter a uniform, arrays with several elements\n"
        "  halo_seed, halo_map (and @halos2, @halos4, @live)   drawn through a GL frame (outputs,\n"
        "            images, host uniforms) against the emulated frame\n"
        "  pass:*    halo_generate's image passes on chosen seed images (GPU frame vs emulation)\n"
        "  outline:* the outline passes (at=post) on synthetic feature buffers: flat depth, depth 1,\n"
        "            one pixel, border, sigma > image, no-hit normals, occlusion styles, depth effects\n"
        "  raycast   a small whole render against a C emulation of the ray caster\n"
        "  figure3   the paper's Fig. 3 as numbers (emulation): fails unless spreading the seed\n"
        "            gradient keeps small features' halos better than a low-pass of the seeds\n"
        "Columns: max_abs and rmse of the error over colour and opacity, over_tol the samples\n"
        "(pixels) beyond tolerance, nonfinite the NaN/Inf values, the tolerance (absolute +\n"
        "relative; the per-sample conditioning term is explained in docs/accuracy.md).\n"
        "  --stage NAME  only the rows of this stage (or one row: empty, raycast, boundary@exp64)\n"
        "  --size N      probe and image side in pixels, 25..512 (default 64)\n"
        "  -v            print the worst sample of every row and the tolerance's reason\n"
        "  --list        print the rows (name, family, tolerance, its reason) and run none\n"
        "  --backend B   the headless context: egl, osmesa or auto (default: EGL when it has a\n"
        "                hardware renderer, else OSMesa); -v names the one used. egl-es3.0 or\n"
        "                egl-es3.2: OpenGL ES, the rows linked for GLSL ES 300; the rows that need\n"
        "                desktop OpenGL are skipped with their reason\n"
        "  --gradient-format F   the slice and slab rows' gradient texture: float, half,\n"
        "                        snorm8, packed16 or packed32\n"
        "                (default: the hosts' default); the emulation reads the float gradients\n"
        "Exit status: 0 all pass, 1 a row failed, 2 usage or setup failure (no OpenGL context).\n",
        out);
}

int conform_parse_command_line(conform *c, int argc, char **argv)
{
    c->size = 64;
    for (int i = 1; i < argc; ++i) {
        const char *a = argv[i];
        if (!strcmp(a, "--help") || !strcmp(a, "-h")) {
            conform_usage(stdout);
            return 0;
        } else if (!strcmp(a, "-v") || !strcmp(a, "--verbose")) {
            c->verbose = 1;
        } else if (!strcmp(a, "--list")) {
            c->list = 1;
        } else if (!strcmp(a, "--stage") && i + 1 < argc) {
            c->only = argv[++i];
        } else if (!strcmp(a, "--gradient-format") && i + 1 < argc) {
            char err[128];
            halo_gradient_format format;
            if (!halo_gradient_format_option(argv[++i], &format, err, sizeof err)) {
                fprintf(stderr, "halo-validate: conform: %s\n", err);
                return 2;
            }
            c->gradient_format = (int)format;
        } else if (!strcmp(a, "--size") && i + 1 < argc) {
            const char *text = argv[++i];
            char *end = NULL;
            errno = 0;
            long n = strtol(text, &end, 10);
            if (end == text || *end != '\0' || errno == ERANGE || n < 25 || n > 512) {
                fprintf(stderr, "halo-validate: conform: --size: '%s' is not an integer in 25..512\n", text);
                return 2;
            }
            c->size = (int)n;
        } else {
            fprintf(stderr, "halo-validate: conform: unknown or incomplete argument '%s'\n", a);
            conform_usage(stderr);
            return 2;
        }
    }
    return -1;
}

/* --stage NAME names a row, a family's prefix or a per-sample stage of the library. */
static int stage_known(conform *c)
{
    const char *only = c->only;
    if (!only || strcmp(only, "empty") == 0 || strcmp(only, "raycast") == 0 || strcmp(only, "figure3") == 0 ||
        strncmp(only, "pass:", 5) == 0 || strncmp(only, "slice", 5) == 0 || strncmp(only, "slab", 4) == 0 ||
        strncmp(only, "line", 4) == 0 || strncmp(only, "outline", 7) == 0 || strncmp(only, "feature", 7) == 0)
        return 1;
    /* a row of the registry, or a family (every row of it) */
    for (size_t i = 0; i < c->registry_count; ++i)
        if (!strcmp(c->registry[i].name, only) || !strcmp(c->registry[i].family, only))
            return 1;
    char base[128];
    snprintf(base, sizeof base, "%s", only);
    char *at = strchr(base, '@');
    if (at)
        *at = '\0';
    const halo_module *m = halo_library_find(c->lib, base);
    if (m && halo_module_describe(m).hook == HALO_HOOK_IMAGE) {
        fprintf(stderr,
                "halo-validate: conform: --stage: '%s' is an image-pass stage: its rows are 'pass:%s' when it has no "
                "family of its own, else its family's (halo_generate: the pass: rows; outlines: outline); "
                "conform --list names them\n",
                only, base);
        return 0;
    }
    if (!m || halo_module_describe(m).hook != HALO_HOOK_SAMPLE) {
        fprintf(stderr,
                "halo-validate: conform: --stage: no per-sample stage '%s' (rows: empty, raycast, figure3,"
                " pass:NAME, slice, slab, line_strip, line_halo, lines, or a stage of halo-validate list)\n",
                only);
        return 0;
    }
    return 1;
}

int conform_open(conform *c)
{
    c->diag = halo_diagnostics_create();
    if (!c->diag || halo_setup(NULL) != HALO_OK) {
        fprintf(stderr, "halo-validate: conform: cannot initialize libhalo\n");
        halo_diagnostics_destroy(c->diag);
        c->diag = NULL;
        return 0;
    }
    c->lib = halo_library_create(c->diag);
    if (!c->lib || !stage_known(c))
        goto failed;
    c->raycast_source = halo_host_load("raycast.frag", NULL, c->diag);
    c->probe_source = halo_host_load("probe.frag", NULL, c->diag);
    if (!c->raycast_source || !c->probe_source)
        goto failed;
    char err[512];
    c->context = halo_headless_create(c->size, c->size, err, sizeof err);
    if (!c->context) {
        fprintf(stderr, "halo-validate: conform: %s\n", err);
        goto failed;
    }
    c->runtime = halo_gl_create(&(halo_gl_desc){.get_proc_address = halo_headless_get_proc_address}, c->diag);
    if (!c->runtime)
        goto failed;
    c->gl = halo_headless_functions();
    c->es = halo_gl_es_version(c->runtime);
    c->target = c->es ? HALO_TARGET_ES300 : HALO_TARGET_DEFAULT;
    if (c->verbose)
        fprintf(stderr, "conform: %s context, %s\n", halo_headless_backend(c->context),
                halo_headless_renderer(c->context));
    return 1;
failed:
    halo_diagnostics_print(c->diag, stderr);
    return 0;
}

void conform_close(conform *c)
{
    int set_up = c->diag != NULL;
    free(c->raycast_source);
    free(c->probe_source);
    halo_gl_destroy(c->runtime);
    halo_headless_destroy(c->context);
    halo_library_destroy(c->lib);
    halo_diagnostics_destroy(c->diag);
    if (set_up)
        halo_shutdown();
    c->raycast_source = c->probe_source = NULL;
    c->runtime = NULL;
    c->context = NULL;
    c->lib = NULL;
    c->diag = NULL;
}
