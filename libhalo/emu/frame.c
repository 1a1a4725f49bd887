/* The emulation's frame: screen-sized double images, host uniforms, extra outputs and
 * the image-pass schedule of docs/image-passes.md, the reference for the GL runtime's
 * halo_gl_frame_*. */
#include "diag.h"
#include "emu.h"
#include "internal.h"

#include <stdlib.h>
#include <string.h>

struct halo_emu_frame {
    const halo_program *program;
    int width, height, channels;
    double **images;        /* per program image: width * height * channels */
    double *scratch;        /* one image: every pass writes a fresh buffer */
    double (*host)[4];      /* per program host uniform */
};

static int image_index(const halo_emu_frame *f, const char *name) {
    for (size_t i = 0; i < f->program->image_count; i++)
        if (!strcmp(f->program->images[i].name, name)) return (int)i;
    return -1;
}

static size_t image_values(const halo_emu_frame *f) {
    return (size_t)f->width * (size_t)f->height * (size_t)f->channels;
}

halo_emu_frame *halo_emu_frame_create(const halo_program *p, int width, int height, halo_diagnostics *diag) {
    if (!p || width < 1 || height < 1) {
        halo_diag_error(diag, USAGE, "", 0, 0, "halo_emu_frame_create: a program and a positive size are required");
        return NULL;
    }
    halo_emu_frame *f = calloc(1, sizeof *f);
    if (!f) goto oom;
    f->program = p;
    f->width = width;
    f->height = height;
    f->channels = p->channel_count < 1 ? 1 : p->channel_count;
    f->images = calloc(p->image_count + 1, sizeof *f->images);
    f->host = calloc(p->host_uniform_count + 1, sizeof *f->host);
    f->scratch = calloc(image_values(f), sizeof *f->scratch);
    if (!f->images || !f->host || !f->scratch) goto oom;
    for (size_t i = 0; i < p->image_count; i++)
        if (!(f->images[i] = calloc(image_values(f), sizeof **f->images))) goto oom;
    return f;
oom:
    halo_diag_error(diag, OUT_OF_MEMORY, "", 0, 0, "out of memory");
    halo_emu_frame_destroy(f);
    return NULL;
}

void halo_emu_frame_destroy(halo_emu_frame *f) {
    if (!f) return;
    if (f->images)
        for (size_t i = 0; i < f->program->image_count; i++) free(f->images[i]);
    free(f->images);
    free(f->scratch);
    free(f->host);
    free(f);
}

double *halo_emu_frame_image(halo_emu_frame *f, const char *name) {
    if (!f || !name) return NULL;
    int i = image_index(f, name);
    return i < 0 ? NULL : f->images[i];
}

/* "screen_right" or "halo_host_screen_right". */
static int host_index(const halo_program *p, const char *name) {
    for (size_t i = 0; i < p->host_uniform_count; i++) {
        const char *full = p->host_uniforms[i].name;
        if (!strcmp(full, name) || (!strncmp(full, "halo_host_", 10) && !strcmp(full + 10, name))) return (int)i;
    }
    return -1;
}

halo_status halo_emu_frame_set_host_uniform(halo_emu_frame *f, const char *name, const double *values, int count) {
    if (!f || !name || (!values && count > 0) || count < 0 || count > 4) return HALO_ERROR_INPUT;
    int i = host_index(f->program, name);
    if (i < 0) return HALO_ERROR_INPUT;
    for (int k = 0; k < 4; k++) f->host[i][k] = k < count ? values[k] : 0.0;
    return HALO_OK;
}

void halo_emu_frame_begin(halo_emu_frame *f) {
    if (!f) return;
    for (size_t i = 0; i < f->program->image_count; i++) memset(f->images[i], 0, image_values(f) * sizeof(double));
}

/* The pixel ivec2(fragcoord): GLSL's conversion truncates towards zero. */
static int pixel_of(const halo_emu_frame *f, const double fragcoord[2], size_t *index) {
    double fx = fragcoord[0], fy = fragcoord[1];
    if (!(fx > -1.0 && fy > -1.0 && fx < (double)f->width && fy < (double)f->height)) return 0;
    int x = (int)fx, y = (int)fy; /* truncation: (-1, 0) -> 0 */
    if (x < 0 || y < 0 || x >= f->width || y >= f->height) return 0;
    *index = ((size_t)y * (size_t)f->width + (size_t)x) * (size_t)f->channels;
    return 1;
}

void halo_emu_frame_finish(halo_emu_frame *f, const halo_emu_sample *s) {
    if (!f || !s) return;
    size_t at;
    if (!pixel_of(f, s->fragcoord, &at)) return;
    for (size_t o = 0; o < f->program->output_count; o++) {
        const halo_output_info *out = &f->program->outputs[o];
        int i = image_index(f, out->image);
        if (i < 0) continue;
        double *px = f->images[i] + at;
        for (int c = 0; c < f->channels; c++) {
            double v = s->output_accum[c];
            px[c] = out->blend == HALO_BLEND_ADD ? px[c] + v : (v > px[c] ? v : px[c]);
        }
    }
}

static const halo_linked_stage *find_stage(const halo_program *p, const char *name) {
    for (size_t i = 0; i < p->stage_count; i++)
        if (!strcmp(p->stages[i].module->name, name)) return &p->stages[i];
    return NULL;
}

halo_status halo_emu_frame_generate(halo_emu_frame *f, halo_diagnostics *diag) {
    if (!f) return HALO_ERROR_INPUT;
    const halo_program *p = f->program;
    /* Resolve everything first, so that a missing emulation changes no image. */
    for (size_t i = 0; i < p->pass_count; i++) {
        const halo_pass_info *pi = &p->passes[i];
        int ok = find_stage(p, pi->stage) && halo_emu_lookup_pass(pi->stage, pi->entry) && image_index(f, pi->output) >= 0 &&
                 (!pi->first || image_index(f, pi->first) >= 0);
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
        halo_emu_params params = {p, find_stage(p, pi->stage), f};
        halo_emu_pass_fn fn = halo_emu_lookup_pass(pi->stage, pi->entry);
        int out = image_index(f, pi->output);
        int repeat = pi->repeat < 1 ? 1 : pi->repeat;
        for (int r = 1; r <= repeat; r++) {
            halo_emu_pass_context c = {&params, f->width, f->height, f->channels, r, repeat, pi->input_count, {0}};
            for (int k = 0; k < pi->input_count; k++) {
                if (!strcmp(pi->inputs[k], "previous"))
                    c.inputs[k] = r == 1 && pi->first ? f->images[image_index(f, pi->first)] : f->images[out];
                else
                    c.inputs[k] = f->images[image_index(f, pi->inputs[k])];
            }
            for (int y = 0; y < f->height; y++)
                for (int x = 0; x < f->width; x++) {
                    double v[4] = {0, 0, 0, 0};
                    fn(&c, x, y, v);
                    memcpy(f->scratch + ((size_t)y * (size_t)f->width + (size_t)x) * (size_t)f->channels, v,
                           (size_t)f->channels * sizeof *v);
                }
            /* Double buffering: the fresh result becomes the image; the old buffer is reused. */
            double *old = f->images[out];
            f->images[out] = f->scratch;
            f->scratch = old;
        }
    }
    for (size_t i = 0; i < p->image_count; i++)
        if (p->images[i].reset == HALO_RESET_GENERATION) memset(f->images[i], 0, image_values(f) * sizeof(double));
    return HALO_OK;
}

/* ---- What stages and passes read ---- */

void halo_emu_read_image(const halo_emu_params *p, const char *name, const double fragcoord[2], double out[4]) {
    out[0] = out[1] = out[2] = out[3] = 0.0;
    halo_emu_frame *f = p ? p->frame : NULL;
    if (!f) return;
    int i = image_index(f, name);
    size_t at;
    if (i < 0 || !pixel_of(f, fragcoord, &at)) return;
    for (int c = 0; c < f->channels; c++) out[c] = f->images[i][at + (size_t)c];
}

const double *halo_emu_host_uniform(const halo_emu_params *p, const char *name) {
    static const double zero[4] = {0, 0, 0, 0};
    halo_emu_frame *f = p ? p->frame : NULL;
    if (!f) return zero;
    int i = host_index(f->program, name);
    return i < 0 ? zero : f->host[i];
}

double halo_emu_input(const halo_emu_pass_context *c, int k, int x, int y, int channel) {
    if (k < 0 || k >= c->input_count || !c->inputs[k] || x < 0 || y < 0 || x >= c->width || y >= c->height ||
        channel < 0 || channel >= c->channels)
        return 0.0;
    return c->inputs[k][((size_t)y * (size_t)c->width + (size_t)x) * (size_t)c->channels + (size_t)channel];
}
