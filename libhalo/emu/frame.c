/* The emulation's frame: screen-sized double images, host uniforms, extra outputs and
 * the image-pass schedule of docs/image-passes.md, the reference for the GL runtime's
 * halo_gl_frame_*. */
#include "diag.h"
#include "emu.h"
#include "internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

struct halo_emu_frame {
    const halo_program *program;
    int width, height, channels;
    double **images;   /* per program image: width * height * channels */
    double *scratch;   /* one image: every pass writes a fresh buffer */
    double (*host)[4]; /* per program host uniform */
    struct {
        const float *data;
        int dims[3];
    } * volumes;      /* per program host uniform: sampler3D data (halo_emu_frame_set_volume) */
    int groups_ended; /* halo_emu_frame_end_group calls since halo_emu_frame_begin */
};

static int image_index(const halo_emu_frame *f, const char *name)
{
    for (size_t i = 0; i < f->program->image_count; i++)
        if (!strcmp(f->program->images[i].name, name))
            return (int)i;
    return -1;
}

static int image_components(const halo_emu_frame *f, size_t i)
{
    int c = f->program->images[i].channels;
    return c < 1 ? 1 : c > 4 ? 4 : c;
}

static int image_scale(const halo_emu_frame *f, size_t i)
{
    int s = f->program->images[i].scale;
    return s > 1 ? s : 1;
}

/* An image's size: ceil(frame / scale) per side. */
static int image_width(const halo_emu_frame *f, size_t i)
{
    return (f->width + image_scale(f, i) - 1) / image_scale(f, i);
}
static int image_height(const halo_emu_frame *f, size_t i)
{
    return (f->height + image_scale(f, i) - 1) / image_scale(f, i);
}

static size_t image_values(const halo_emu_frame *f, size_t i)
{
    return (size_t)image_width(f, i) * (size_t)image_height(f, i) * (size_t)image_components(f, i);
}

static void clear_image(halo_emu_frame *f, size_t i)
{
    size_t n = image_values(f, i);
    for (size_t k = 0; k < n; k++)
        f->images[i][k] = f->program->images[i].clear;
}

halo_emu_frame *halo_emu_frame_create(const halo_program *p, int width, int height, halo_diagnostics *diag)
{
    HALO_REFUSE_NULL(diag, p, "program", NULL);
    if (width < 1 || height < 1 || width > HALO_MAX_FRAME_SIDE || height > HALO_MAX_FRAME_SIDE) {
        /* within it, width * height * 4 fits an int and every index the stages compute */
        halo_diag_error(diag, USAGE, "", 0, 0, "halo_emu_frame_create: the size %dx%d is not within 1..%d per side",
                        width, height, HALO_MAX_FRAME_SIDE);
        return NULL;
    }
    halo_emu_frame *f = calloc(1, sizeof *f);
    if (!f)
        goto oom;
    f->program = p;
    halo_program_retain(p);
    f->width = width;
    f->height = height;
    f->channels = p->channel_count < 1 ? 1 : p->channel_count;
    f->images = calloc(p->image_count + 1, sizeof *f->images);
    f->host = calloc(p->host_uniform_count + 1, sizeof *f->host);
    f->volumes = calloc(p->host_uniform_count + 1, sizeof *f->volumes);
    f->scratch = calloc((size_t)width * (size_t)height * 4, sizeof *f->scratch);
    if (!f->images || !f->host || !f->volumes || !f->scratch)
        goto oom;
    for (size_t i = 0; i < p->image_count; i++)
        /* four components of room: passes swap buffers between images of any size */
        if (!(f->images[i] = calloc((size_t)width * (size_t)height * 4, sizeof **f->images)))
            goto oom;
    halo_emu_frame_begin(f);
    return f;
oom:
    halo_diag_error(diag, OUT_OF_MEMORY, "", 0, 0, "out of memory");
    halo_emu_frame_destroy(f);
    return NULL;
}

void halo_emu_frame_destroy(halo_emu_frame *f)
{
    if (!f)
        return;
    if (f->images)
        for (size_t i = 0; i < f->program->image_count; i++)
            free(f->images[i]);
    free(f->images);
    free(f->scratch);
    free(f->host);
    free(f->volumes);
    halo_program_destroy((halo_program *)f->program); /* the frame's reference */
    free(f);
}

double *halo_emu_frame_image(halo_emu_frame *f, const char *name)
{
    HALO_REFUSE_NULL(NULL, f, "frame", NULL);
    HALO_REFUSE_NULL(NULL, name, "name", NULL);
    int i = image_index(f, name);
    return i < 0 ? NULL : f->images[i];
}

/* "screen_right" or "halo_host_screen_right". */
static int host_index(const halo_program *p, const char *name)
{
    for (size_t i = 0; i < p->host_uniform_count; i++) {
        const char *full = p->host_uniforms[i].name;
        if (!strcmp(full, name) || (!strncmp(full, "halo_host_", 10) && !strcmp(full + 10, name)))
            return (int)i;
    }
    return -1;
}

halo_status halo_emu_frame_set_host_uniform(halo_emu_frame *f, const char *name, const double *values, int count)
{
    HALO_REFUSE_NULL(NULL, f, "frame", HALO_ERROR_INPUT);
    HALO_REFUSE_NULL(NULL, name, "name", HALO_ERROR_INPUT);
    if (count > 0)
        HALO_REFUSE_NULL(NULL, values, "values", HALO_ERROR_INPUT);
    if (count < 0 || count > 4)
        return HALO_ERROR_INPUT;
    int i = host_index(f->program, name);
    if (i < 0)
        return HALO_ERROR_INPUT;
    for (int k = 0; k < 4; k++)
        f->host[i][k] = k < count ? values[k] : 0.0;
    return HALO_OK;
}

void halo_emu_frame_begin(halo_emu_frame *f)
{
    HALO_REFUSE_NULL_VOID(NULL, f, "frame");
    f->groups_ended = 0;
    for (size_t i = 0; i < f->program->image_count; i++)
        if (!f->program->images[i].host)
            clear_image(f, i);
}

void halo_emu_frame_begin_group(halo_emu_frame *f)
{
    HALO_REFUSE_NULL_VOID(NULL, f, "frame");
    for (size_t i = 0; i < f->program->image_count; i++)
        if (!f->program->images[i].host && f->program->images[i].reset != HALO_RESET_FRAME_ONLY)
            clear_image(f, i);
}

halo_status halo_emu_frame_set_volume(halo_emu_frame *f, const char *name, const float *data, int nx, int ny, int nz)
{
    HALO_REFUSE_NULL(NULL, f, "frame", HALO_ERROR_INPUT);
    HALO_REFUSE_NULL(NULL, name, "name", HALO_ERROR_INPUT);
    HALO_REFUSE_NULL(NULL, data, "data", HALO_ERROR_INPUT);
    if (nx < 1 || ny < 1 || nz < 1)
        return HALO_ERROR_INPUT;
    int i = host_index(f->program, name);
    if (i < 0 || strcmp(f->program->host_uniforms[i].type, "sampler3D"))
        return HALO_ERROR_INPUT;
    f->volumes[i].data = data;
    f->volumes[i].dims[0] = nx;
    f->volumes[i].dims[1] = ny;
    f->volumes[i].dims[2] = nz;
    return HALO_OK;
}

const float *halo_emu_host_volume(const halo_emu_params *p, const char *name, int dims[3])
{
    halo_emu_frame *f = p ? p->frame : NULL;
    dims[0] = dims[1] = dims[2] = 0;
    int i = f ? host_index(f->program, name) : -1;
    if (i < 0 || !f->volumes[i].data)
        return NULL;
    memcpy(dims, f->volumes[i].dims, sizeof f->volumes[i].dims);
    return f->volumes[i].data;
}

/* The pixel ivec2(fragcoord) (GLSL's conversion truncates towards zero), as an index of
 * pixels (multiply by the image's components). */
static int pixel_of(const halo_emu_frame *f, const double fragcoord[2], size_t *index)
{
    double fx = fragcoord[0], fy = fragcoord[1];
    if (!(fx > -1.0 && fy > -1.0 && fx < (double)f->width && fy < (double)f->height))
        return 0;
    int x = (int)fx, y = (int)fy; /* truncation: (-1, 0) -> 0 */
    if (x < 0 || y < 0 || x >= f->width || y >= f->height)
        return 0;
    *index = (size_t)y * (size_t)f->width + (size_t)x;
    return 1;
}

/* The accumulator of output o in the sample. */
static double *output_accum(halo_emu_sample *s, size_t o)
{
    return o == 0 ? s->output_accum : o <= 15 ? s->output_accum_next[o - 1] : NULL;
}

/* The emulated sample's storage of an output's field (NULL: not emulated). */
static const double *output_field(const halo_emu_sample *s, const halo_output_info *out)
{
    if (!strcmp(out->field, "seed") && out->channel < 0)
        return s->seed;
    if (!strcmp(out->field, "feature_depth") && out->channel < 0)
        return s->feature_depth;
    if (!strcmp(out->field, "occluder_depth") && out->channel < 0)
        return &s->occluder_depth;
    if (!strcmp(out->field, "feature_normal") && out->channel >= 0 && out->channel < 4)
        return s->feature_normal[out->channel];
    return NULL;
}

halo_status halo_emu_frame_fold(const halo_program *p, halo_emu_sample *s, halo_diagnostics *diag)
{
    for (size_t o = 0; o < p->output_count; o++) {
        const halo_output_info *out = &p->outputs[o];
        const double *v = output_field(s, out);
        double *a = output_accum(s, o);
        if (!v || !a) {
            halo_diag_error(diag, EMU_MISSING, "", 0, 0, "output '%s' has no field in halo_emu_sample", out->name);
            return HALO_ERROR_INPUT;
        }
        int n = out->components < 4 ? out->components : 4;
        if (out->blend == HALO_BLEND_FIRST) {
            if (a[3] <= 0.0)
                memcpy(a, v, 4 * sizeof *a);
            continue;
        }
        for (int c = 0; c < n; c++) {
            if (out->blend == HALO_BLEND_MIN) { /* stored as 1 - accumulator: zero is the GLSL initial 1.0 */
                double acc = 1.0 - a[c];
                a[c] = 1.0 - (v[c] < acc ? v[c] : acc);
            } else if (out->blend == HALO_BLEND_ADD) {
                a[c] += v[c];
            } else {
                a[c] = v[c] > a[c] ? v[c] : a[c];
            }
        }
    }
    return HALO_OK;
}

void halo_emu_frame_finish(halo_emu_frame *f, const halo_emu_sample *s)
{
    HALO_REFUSE_NULL_VOID(NULL, f, "frame");
    HALO_REFUSE_NULL_VOID(NULL, s, "sample");
    size_t at;
    if (!pixel_of(f, s->fragcoord, &at))
        return;
    for (size_t o = 0; o < f->program->output_count; o++) {
        const halo_output_info *out = &f->program->outputs[o];
        int i = image_index(f, out->image);
        const double *a = output_accum((halo_emu_sample *)s, o);
        if (i < 0 || !a)
            continue;
        int n = image_components(f, (size_t)i);
        double *px = f->images[i] + at * (size_t)n;
        double coverage = 1.0 - px[n - 1];
        for (int c = 0; c < n; c++) {
            double v = a[c];
            switch (out->blend) {
            case HALO_BLEND_ADD:
                px[c] += v;
                break;
            case HALO_BLEND_MIN:
                v = 1.0 - v;
                px[c] = v < px[c] ? v : px[c];
                break;
            case HALO_BLEND_FIRST:
                px[c] += coverage * v;
                break; /* GL_ONE_MINUS_DST_ALPHA, GL_ONE */
            default:
                px[c] = v > px[c] ? v : px[c];
                break;
            }
        }
    }
}

static const halo_linked_stage *find_stage(const halo_program *p, const char *name)
{
    for (size_t i = 0; i < p->stage_count; i++)
        if (!strcmp(p->stages[i].module->name, name))
            return &p->stages[i];
    return NULL;
}

static halo_status run_passes(halo_emu_frame *f, halo_pass_at at, halo_diagnostics *diag);

halo_status halo_emu_frame_generate(halo_emu_frame *f, halo_diagnostics *diag)
{
    HALO_REFUSE_NULL(diag, f, "frame", HALO_ERROR_INPUT);
    return run_passes(f, HALO_PASS_AT_GENERATE, diag);
}

halo_status halo_emu_frame_end_group(halo_emu_frame *f, halo_diagnostics *diag)
{
    HALO_REFUSE_NULL(diag, f, "frame", HALO_ERROR_INPUT);
    halo_status st = run_passes(f, HALO_PASS_AT_POST, diag);
    if (st == HALO_OK)
        f->groups_ended++;
    return st;
}

halo_status halo_emu_frame_post(halo_emu_frame *f, halo_diagnostics *diag)
{
    HALO_REFUSE_NULL(diag, f, "frame", HALO_ERROR_INPUT);
    halo_status st = f->groups_ended ? HALO_OK : run_passes(f, HALO_PASS_AT_POST, diag);
    return st == HALO_OK ? run_passes(f, HALO_PASS_AT_FINAL, diag) : st;
}

static halo_status run_passes(halo_emu_frame *f, halo_pass_at at, halo_diagnostics *diag)
{
    if (!f)
        return HALO_ERROR_INPUT;
    const halo_program *p = f->program;
    /* Resolve everything first, so that a missing emulation changes no image. */
    for (size_t i = 0; i < p->pass_count; i++) {
        const halo_pass_info *pi = &p->passes[i];
        int ok = find_stage(p, pi->stage) && halo_emu_lookup_pass(pi->stage, pi->entry) &&
                 image_index(f, pi->output) >= 0 && (!pi->first || image_index(f, pi->first) >= 0);
        for (int k = 0; ok && k < pi->input_count; k++)
            ok = !strcmp(pi->inputs[k], "previous") || image_index(f, pi->inputs[k]) >= 0;
        if (!ok) {
            halo_diag_error(diag, EMU_MISSING, "", 0, 0, "image pass '%s' (%s of stage %s) has no C emulation",
                            pi->name, pi->entry, pi->stage);
            return HALO_ERROR_INPUT;
        }
    }
    for (size_t i = 0; i < p->pass_count; i++) {
        const halo_pass_info *pi = &p->passes[i];
        if (pi->at != at)
            continue;
        halo_emu_params params = {p, find_stage(p, pi->stage), f};
        halo_emu_pass_fn fn = halo_emu_lookup_pass(pi->stage, pi->entry);
        int out = image_index(f, pi->output);
        int out_components = image_components(f, (size_t)out);
        if (p->images[out].host)
            continue;
        int repeat = pi->repeat < 1 ? 1 : pi->repeat;
        int out_scale = image_scale(f, (size_t)out), width = image_width(f, (size_t)out),
            height = image_height(f, (size_t)out);
        int start = pi->start < 1 ? 1 : pi->start;
        for (int r = start; r <= repeat; r++) {
            halo_emu_pass_context c = {&params,
                                       width,
                                       height,
                                       f->channels,
                                       r,
                                       repeat,
                                       pi->input_count,
                                       {0},
                                       {0},
                                       pi->channel < 0 ? 0 : pi->channel,
                                       out_scale,
                                       {0},
                                       {0},
                                       {0},
                                       {0}};
            for (int k = 0; k < pi->input_count; k++) {
                int in = !strcmp(pi->inputs[k], "previous")
                             ? (r == start && pi->first ? image_index(f, pi->first) : out)
                             : image_index(f, pi->inputs[k]);
                int in_scale = image_scale(f, (size_t)in);
                c.inputs[k] = f->images[in];
                c.input_components[k] = image_components(f, (size_t)in);
                c.input_width[k] = image_width(f, (size_t)in);
                c.input_height[k] = image_height(f, (size_t)in);
                c.input_down[k] = in_scale < out_scale ? out_scale / in_scale : 1;
                c.input_up[k] = in_scale > out_scale ? in_scale / out_scale : 1;
            }
            for (int y = 0; y < height; y++)
                for (int x = 0; x < width; x++) {
                    double v[4] = {0, 0, 0, 0};
                    fn(&c, x, y, v);
                    memcpy(f->scratch + ((size_t)y * (size_t)width + (size_t)x) * (size_t)out_components, v,
                           (size_t)out_components * sizeof *v);
                }
            /* Double buffering: the fresh result becomes the image; the old buffer is reused. */
            double *old = f->images[out];
            f->images[out] = f->scratch;
            f->scratch = old;
        }
    }
    for (size_t i = 0; i < p->image_count && at == HALO_PASS_AT_GENERATE; i++)
        if (p->images[i].reset == HALO_RESET_GENERATION)
            clear_image(f, i);
    return HALO_OK;
}

/* ---- What stages and passes read ---- */

void halo_emu_read_image(const halo_emu_params *p, const char *name, const double fragcoord[2], double out[4])
{
    out[0] = out[1] = out[2] = out[3] = 0.0;
    halo_emu_frame *f = p ? p->frame : NULL;
    if (!f)
        return;
    int i = image_index(f, name);
    size_t at;
    if (i < 0 || !pixel_of(f, fragcoord, &at))
        return;
    int n = image_components(f, (size_t)i);
    int s = image_scale(f, (size_t)i);
    if (s == 1) {
        for (int c = 0; c < n; c++)
            out[c] = f->images[i][at * (size_t)n + (size_t)c];
        return;
    }
    /* a 1/s image: bilinear between the four nearest pixel centres, clamped to the image
     * (halo_read_NAME of a scaled image, libhalo/link.c) */
    int w = image_width(f, (size_t)i), h = image_height(f, (size_t)i);
    double ax = fragcoord[0] / s - 0.5, ay = fragcoord[1] / s - 0.5;
    double cx = floor(ax), cy = floor(ay), tx = ax - cx, ty = ay - cy;
    int x0 = (int)cx, y0 = (int)cy, x1 = x0 + 1, y1 = y0 + 1;
    x0 = x0 < 0 ? 0 : x0 > w - 1 ? w - 1 : x0;
    x1 = x1 < 0 ? 0 : x1 > w - 1 ? w - 1 : x1;
    y0 = y0 < 0 ? 0 : y0 > h - 1 ? h - 1 : y0;
    y1 = y1 < 0 ? 0 : y1 > h - 1 ? h - 1 : y1;
    const double *im = f->images[i];
#define TEXEL(x, y, c) im[((size_t)(y) * (size_t)w + (size_t)(x)) * (size_t)n + (size_t)(c)]
    for (int c = 0; c < n; c++) {
        double bottom = TEXEL(x0, y0, c) + (TEXEL(x1, y0, c) - TEXEL(x0, y0, c)) * tx;
        double top = TEXEL(x0, y1, c) + (TEXEL(x1, y1, c) - TEXEL(x0, y1, c)) * tx;
        out[c] = bottom + (top - bottom) * ty;
    }
#undef TEXEL
}

const double *halo_emu_host_uniform(const halo_emu_params *p, const char *name)
{
    static const double zero[4] = {0, 0, 0, 0};
    halo_emu_frame *f = p ? p->frame : NULL;
    if (!f)
        return zero;
    int i = host_index(f->program, name);
    return i < 0 ? zero : f->host[i];
}

/* One texel of input k; 0 outside it. */
static double input_texel(const halo_emu_pass_context *c, int k, int x, int y, int channel, int n)
{
    int w = c->input_width[k] > 0 ? c->input_width[k] : c->width;
    int h = c->input_height[k] > 0 ? c->input_height[k] : c->height;
    if (x < 0 || y < 0 || x >= w || y >= h)
        return 0.0;
    return c->inputs[k][((size_t)y * (size_t)w + (size_t)x) * (size_t)n + (size_t)channel];
}

double halo_emu_input(const halo_emu_pass_context *c, int k, int x, int y, int channel)
{
    if (k < 0 || k >= c->input_count || !c->inputs[k])
        return 0.0;
    int n = c->input_components[k] > 0 ? c->input_components[k] : c->channels;
    /* halo_input gives the program's channels of any image; halo_input4 all of them */
    if (channel < 0 || channel >= n)
        return 0.0;
    int down = c->input_down[k] > 1 ? c->input_down[k] : 1, up = c->input_up[k] > 1 ? c->input_up[k] : 1;
    if (down > 1) {
        double m = input_texel(c, k, x * down, y * down, channel, n);
        for (int i = 1; i < down * down; i++) {
            double v = input_texel(c, k, x * down + i % down, y * down + i / down, channel, n);
            m = v > m ? v : m;
        }
        return m;
    }
    if (up > 1)
        return x < 0 || y < 0 ? 0.0 : input_texel(c, k, x / up, y / up, channel, n);
    return input_texel(c, k, x, y, channel, n);
}
