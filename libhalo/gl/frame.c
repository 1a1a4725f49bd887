/* Frames: a linked program's images, its image passes and their schedule between the
 * host's draws (docs/image-passes.md). Built on the runtime (runtime.c) in the host's
 * context; the host draws through halo_gl_frame_attach / _bind. */
#include "halo.h"
#include "internal.h"
#include "diag.h"
#include "gl/frame.h"
#include "gl/glfuncs.h"
#include "gl/runtime.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define FRAME_MAX_BUFFERS 8 /* halo_gl_frame_attach's draw-buffer list holds 4x this */

/* A box of pixels [x0, x1) x [y0, y1); empty when x0 >= x1 or y0 >= y1. */
typedef struct frame_box {
    int x0, y0, x1, y1;
} frame_box;

static int box_empty(frame_box b) { return b.x0 >= b.x1 || b.y0 >= b.y1; }

static frame_box box_union(frame_box a, frame_box b)
{
    if (box_empty(a))
        return b;
    if (box_empty(b))
        return a;
    return (frame_box){a.x0 < b.x0 ? a.x0 : b.x0, a.y0 < b.y0 ? a.y0 : b.y0, a.x1 > b.x1 ? a.x1 : b.x1,
                       a.y1 > b.y1 ? a.y1 : b.y1};
}

/* The box where a and b overlap (empty when they do not). */
static frame_box box_intersect(frame_box a, frame_box b)
{
    return (frame_box){a.x0 > b.x0 ? a.x0 : b.x0, a.y0 > b.y0 ? a.y0 : b.y0, a.x1 < b.x1 ? a.x1 : b.x1,
                       a.y1 < b.y1 ? a.y1 : b.y1};
}

/* r less b as at most four boxes (below, above, left, right of b) into pieces; returns their count. */
static int box_subtract(frame_box r, frame_box b, int pieces[4][4])
{
    int lo = r.y0 > b.y0 ? r.y0 : b.y0, hi = r.y1 < b.y1 ? r.y1 : b.y1;
    const frame_box candidates[4] = {{r.x0, r.y0, r.x1, b.y0 < r.y1 ? b.y0 : r.y1},
                                     {r.x0, b.y1 > r.y0 ? b.y1 : r.y0, r.x1, r.y1},
                                     {r.x0, lo, b.x0 < r.x1 ? b.x0 : r.x1, hi},
                                     {b.x1 > r.x0 ? b.x1 : r.x0, lo, r.x1, hi}};
    int n = 0;
    for (int k = 0; k < 4; ++k)
        if (!box_empty(candidates[k])) {
            const frame_box c = candidates[k];
            pieces[n][0] = c.x0, pieces[n][1] = c.y0, pieces[n][2] = c.x1, pieces[n][3] = c.y1;
            n++;
        }
    return n;
}

/* b grown by r pixels on each side, within a width x height image. */
static frame_box box_grow(frame_box b, int r, int width, int height)
{
    if (box_empty(b))
        return b;
    b.x0 = b.x0 - r < 0 ? 0 : b.x0 - r;
    b.y0 = b.y0 - r < 0 ? 0 : b.y0 - r;
    b.x1 = b.x1 + r > width ? width : b.x1 + r;
    b.y1 = b.y1 + r > height ? height : b.y1 + r;
    return b;
}

typedef struct frame_image {
    const char *name;
    int channels;
    halo_image_reset reset;
    GLfloat clear;
    int host;          /* host_color: texture[0] is the host's, set by halo_gl_frame_post */
    int scale;         /* halo_image_info.scale: 1, or 1/scale of the frame per side */
    int width, height; /* ceil(frame / scale) */
    GLuint texture[2]; /* double-buffered: a pass reads texture[current], writes the other */
    int current;
    /* Outside support[k], texture[k] holds 0 (kept where generations are scissored:
     * frame_scissored); the whole image while unknown. */
    frame_box support[2];
} frame_image;

typedef struct frame_pass {
    const halo_pass_info *info;
    GLuint program;
    GLint index_location, count_location;
    int inputs[HALO_MAX_PASS_INPUTS]; /* image index; -1: previous */
    int output, first;                /* first: image index for repetition 1's previous, -1: the output */
    int repeat, start;
} frame_pass;

struct halo_gl_frame {
    halo_gl *gl;
    const halo_program *program;
    int width, height;
    frame_image *images;
    size_t image_count;
    frame_pass *passes;
    size_t pass_count;
    int max_inputs;
    GLuint framebuffer, vertex_array;
    long pass_draws;
    /* halo_gl_desc.count_fetches: the atomic counter of the passes' texel fetches, and their sum */
    GLuint fetch_counter;
    long long pass_fetches;
    int groups_ended; /* halo_gl_frame_end_group calls since halo_gl_frame_begin */
    int attached;     /* outputs attached to attached_framebuffer by halo_gl_frame_attach */
    GLuint attached_framebuffer;
    const halo_program *attached_program; /* whose outputs: the program's, or its march's (field.c) */
    /* host contract 3: the stacks of a one_draw program, made by field.c at its first draw */
    halo_gl_field *field;
    void (*field_destroy)(halo_gl_frame *fr, halo_gl_field *field);
    size_t (*field_bytes)(const halo_gl_field *field);
    int bound; /* samplers bound by halo_gl_frame_bind from bound_first_unit */
    int bound_first_unit;
    GLuint state[2];   /* host contract 2: the rays' state between segments (RGBA32F), ping-ponged */
    int state_current; /* state[state_current] holds the state after the last segment drawn */
    int segments_drawn;
    /* The union of halo_gl_frame_drawn_region calls since the host's draws were last taken
     * into the images' support (frame_take_host_draws); without a call (drawn_known 0)
     * the host may have drawn anywhere. */
    int drawn_known;
    frame_box drawn;
    /* Before a scissored generation, the host's outputs are read back (inside the
     * declared region, if any) and their nonzero pixels' box taken
     * (halo_gl_frame_set_readback_bounds). */
    int readback_bounds;
    float *readback;
    /* halo_gl_frame_draw is running (a draw callback that destroys the frame only asks for
     * it: the frame goes when the draw returns) */
    int drawing, destroy_pending;
};

int halo_gl_frame_drawing(halo_gl_frame *fr, int change)
{
    if (change < 0) /* a query: -1 when a destroy was asked for, else 0 */
        return fr->destroy_pending ? -1 : 0;
    fr->drawing += change ? 1 : -1; /* nested halo_gl_frame_draw calls (a callback that draws) */
    return fr->drawing == 0 && fr->destroy_pending;
}

/* For segments.c: the runtime, program, size and ray-state textures of a frame. */
halo_gl *halo_gl_frame_runtime(const halo_gl_frame *fr) { return fr->gl; }
const halo_program *halo_gl_frame_program(const halo_gl_frame *fr) { return fr->program; }
void halo_gl_frame_size(const halo_gl_frame *fr, int *width, int *height)
{
    *width = fr->width;
    *height = fr->height;
}
unsigned halo_gl_frame_state(halo_gl_frame *fr, int next)
{
    return fr->state[next ? 1 - fr->state_current : fr->state_current];
}
void halo_gl_frame_state_flip(halo_gl_frame *fr)
{
    fr->state_current = 1 - fr->state_current;
    fr->segments_drawn++;
}
void halo_gl_frame_segments_reset(halo_gl_frame *fr) { fr->segments_drawn = 0; }

static int frame_find_image(const halo_gl_frame *f, const char *name)
{
    for (size_t i = 0; name && i < f->image_count; ++i)
        if (strcmp(f->images[i].name, name) == 0)
            return (int)i;
    return -1;
}

static void image_formats(int channels, int precision, GLint *internal, GLenum *format)
{
    static const GLint f32[4] = {GL_R32F, GL_RG32F, GL_RGBA32F, GL_RGBA32F};
    static const GLint f16[4] = {GL_R16F, GL_RG16F, GL_RGBA16F, GL_RGBA16F};
    static const GLint u8[4] = {GL_R8, GL_RG8, GL_RGBA8, GL_RGBA8};
    static const GLenum formats[4] = {GL_RED, GL_RG, GL_RGBA, GL_RGBA};
    int c = channels < 1 ? 1 : channels > 4 ? 4 : channels;
    *internal = precision == 16 ? f16[c - 1] : precision == 8 ? u8[c - 1] : f32[c - 1];
    *format = formats[c - 1];
}

void halo_gl_image_upload_format(GLint internal, GLenum *format, GLenum *type)
{
    switch (internal) {
    case GL_R32F:
    case GL_R16F:
    case GL_R8:
        *format = GL_RED;
        break;
    case GL_RG32F:
    case GL_RG16F:
    case GL_RG8:
        *format = GL_RG;
        break;
    default:
        *format = GL_RGBA;
        break;
    }
    /* OpenGL ES takes the normalized 8-bit formats only as bytes */
    *type = internal == GL_R8 || internal == GL_RG8 || internal == GL_RGBA8 ? GL_UNSIGNED_BYTE : GL_FLOAT;
}

size_t halo_gl_image_texel_bytes(GLint internal)
{
    switch (internal) {
    case GL_R8:
        return 1;
    case GL_RG8:
    case GL_R16F:
        return 2;
    case GL_RGBA8:
    case GL_RG16F:
    case GL_R32F:
        return 4;
    case GL_RGBA16F:
    case GL_RG32F:
        return 8;
    default:
        return 16; /* GL_RGBA32F */
    }
}

/* The GL state the frame functions change, saved and restored around them: the host's
 * (halo_gl_state, made neutral for the frame's draws) and the 2D textures of the units
 * its passes bind. */
typedef struct frame_saved {
    halo_gl_state state;
    int unit_count;
    GLint textures[HALO_MAX_PASS_INPUTS];
} frame_saved;

static void frame_save(const halo_glfuncs *f, frame_saved *s, int units)
{
    memset(s, 0, sizeof *s);
    halo_gl_state_save(f, &s->state);
    halo_gl_state_neutral(f, &s->state);
    s->unit_count = units > HALO_MAX_PASS_INPUTS ? HALO_MAX_PASS_INPUTS : units;
    for (int u = 0; u < s->unit_count; ++u) {
        f->ActiveTexture(GL_TEXTURE0 + (GLenum)u);
        f->GetIntegerv(GL_TEXTURE_BINDING_2D, &s->textures[u]);
    }
}

static void frame_restore(const halo_glfuncs *f, const frame_saved *s)
{
    for (int u = 0; u < s->unit_count; ++u) {
        f->ActiveTexture(GL_TEXTURE0 + (GLenum)u);
        f->BindTexture(GL_TEXTURE_2D, (GLuint)s->textures[u]);
    }
    halo_gl_state_restore(f, &s->state);
}

/* Clears the current texture of image i through the frame's framebuffer (bound as draw). */
static void frame_clear_image(halo_gl_frame *fr, int i)
{
    const halo_glfuncs *f = &fr->gl->f;
    frame_image *image = &fr->images[i];
    if (image->host)
        return;
    const GLfloat value[4] = {image->clear, image->clear, image->clear, image->clear};
    f->FramebufferTexture2D(GL_DRAW_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, image->texture[image->current],
                            0);
    f->ClearBufferfv(GL_COLOR, 0, value);
    image->support[image->current] = (frame_box){0, 0, 0, 0};
}

static frame_box image_full(const frame_image *im) { return (frame_box){0, 0, im->width, im->height}; }

/* The box of the pixels of image im's current texture inside `within` that differ from 0
 * (NaN included), read back through the frame's framebuffer (bound as GL_FRAMEBUFFER);
 * `within` when the scratch memory is missing. */
static frame_box frame_nonzero_box(halo_gl_frame *fr, int channels, int image_width, int image_height,
                                   frame_box within);

static frame_box image_nonzero_box(halo_gl_frame *fr, frame_image *im, frame_box within)
{
    fr->gl->f.FramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, im->texture[im->current], 0);
    fr->gl->f.ReadBuffer(GL_COLOR_ATTACHMENT0);
    return frame_nonzero_box(fr, im->channels, im->width, im->height, within);
}

int halo_gl_frame_nonzero_box(halo_gl_frame *fr, int channels, int width, int height, int box[4])
{
    if (!fr->readback_bounds)
        return 0;
    frame_box b = frame_nonzero_box(fr, channels, width, height, (frame_box){box[0], box[1], box[2], box[3]});
    box[0] = b.x0;
    box[1] = b.y0;
    box[2] = b.x1;
    box[3] = b.y1;
    return 1;
}

/* The nonzero box inside `within` of the read framebuffer's colour attachment 0 (an image
 * of width x height, `channels` floats a pixel). */
static frame_box frame_nonzero_box(halo_gl_frame *fr, int channels, int image_width, int image_height, frame_box within)
{
    const halo_glfuncs *f = &fr->gl->f;
    within = box_grow(within, 0, image_width, image_height);
    if (box_empty(within))
        return (frame_box){0, 0, 0, 0};
    if (!fr->readback)
        fr->readback = malloc((size_t)fr->width * (size_t)fr->height * 4 * sizeof(float));
    if (!fr->readback)
        return within;
    int width = within.x1 - within.x0, height = within.y1 - within.y0;
    GLint pack = 4;
    f->GetIntegerv(GL_PACK_ALIGNMENT, &pack);
    f->PixelStorei(GL_PACK_ALIGNMENT, 4);
    int read = halo_gl_read_floats(fr->gl, within.x0, within.y0, width, height, channels, fr->readback);
    f->PixelStorei(GL_PACK_ALIGNMENT, pack);
    if (!read)
        return within;
    frame_box b = {image_width, image_height, 0, 0};
    size_t row = (size_t)width * (size_t)channels;
    for (int y = 0; y < height; ++y) {
        const float *line = fr->readback + (size_t)y * row;
        size_t first = 0, last = row;
        while (first < row && line[first] == 0.0f)
            ++first;
        if (first == row)
            continue;
        while (line[last - 1] == 0.0f)
            --last;
        int x0 = within.x0 + (int)(first / (size_t)channels);
        int x1 = within.x0 + (int)((last - 1) / (size_t)channels) + 1;
        b.x0 = x0 < b.x0 ? x0 : b.x0;
        b.x1 = x1 > b.x1 ? x1 : b.x1;
        b.y0 = within.y0 + y < b.y0 ? within.y0 + y : b.y0;
        b.y1 = within.y0 + y + 1;
    }
    return box_empty(b) ? (frame_box){0, 0, 0, 0} : b;
}

/* Box b of an image at 1/from of the frame in the pixels of one at 1/to, as a pass reads
 * it (link.c, halo_input4): a larger input is max-reduced over the to/from blocks, so an
 * output pixel is nonzero where its block meets b; a smaller one is read at pixel /
 * (from/to). */
static frame_box box_to_scale(frame_box b, int from, int to)
{
    if (box_empty(b) || from == to)
        return b;
    if (to > from) {
        int d = to / from;
        return (frame_box){b.x0 / d, b.y0 / d, (b.x1 + d - 1) / d, (b.y1 + d - 1) / d};
    }
    int u = from / to;
    return (frame_box){b.x0 * u, b.y0 * u, b.x1 * u, b.y1 * u};
}

/* The host's draws since the last call are in the images it writes (the program's
 * outputs): their current textures' support grows by the region the host declared, or
 * becomes the whole image; read_back: by the nonzero pixels read back inside that region,
 * or of the whole image (exact). */
static void frame_take_host_draws(halo_gl_frame *fr, int read_back)
{
    /* with host contract 3, libhalo's march (the program's prepass) writes the seeds */
    const halo_program *writers[2] = {fr->program, fr->program->prepass};
    for (int w = 0; w < 2 && writers[w]; ++w)
        for (size_t i = 0, n = halo_program_reflection(writers[w]).output_count; i < n; ++i) {
            int k = frame_find_image(fr, halo_program_reflection(writers[w]).outputs[i].image);
            if (k < 0 || fr->images[k].host)
                continue;
            frame_image *im = &fr->images[k];
            frame_box *support = &im->support[im->current];
            /* the declared region is in the frame's pixels; a 1/s image (the seeds of host
             * contract 3's march) is written where its pixels' blocks meet it */
            frame_box drawn = box_grow(box_to_scale(box_grow(fr->drawn, 0, fr->width, fr->height), 1, im->scale), 0,
                                       im->width, im->height);
            if (read_back && fr->drawn_known)
                *support = box_union(*support, image_nonzero_box(fr, im, drawn));
            else if (read_back)
                *support = image_nonzero_box(fr, im, image_full(im));
            else
                *support = fr->drawn_known ? box_union(*support, drawn) : image_full(im);
        }
    fr->drawn_known = 0;
}

/* Whether the generation passes may be scissored to where their outputs can be nonzero:
 * each declares its reach (in its output image's pixels, at 1/s of the frame too), and
 * every image they touch is cleared to 0. */
static int frame_scissored(const halo_gl_frame *fr)
{
    int any = 0;
    for (size_t i = 0; i < fr->pass_count; ++i) {
        const frame_pass *pass = &fr->passes[i];
        if (pass->info->at)
            continue;
        if (pass->info->reach < 0)
            return 0;
        any = 1;
        int images[HALO_MAX_PASS_INPUTS + 2], n = 0;
        images[n++] = pass->output;
        if (pass->first >= 0)
            images[n++] = pass->first;
        for (int k = 0; k < pass->info->input_count; ++k)
            if (pass->inputs[k] >= 0)
                images[n++] = pass->inputs[k];
        for (int k = 0; k < n; ++k) {
            const frame_image *im = &fr->images[images[k]];
            if (im->host || im->clear != 0.0f)
                return 0;
        }
    }
    return any;
}


/* Where repetition rep of a pass can write a nonzero pixel: its inputs' support, in the
 * output's pixels, grown by its reach (pixels of the output image, whatever its scale: a
 * module stepping B^(PARAM-i) of its own pixels stays within it, halo_generate's
 * max(1, 2^(N-i) / s) on a 1/s image too). */
static frame_box pass_reach_box(const halo_gl_frame *fr, const frame_pass *pass, int rep, const frame_image *out)
{
    int reach = halo_pass_reach(pass->info, rep);
    if (reach < 0)
        return image_full(out);
    frame_box in = {0, 0, 0, 0};
    for (int k = 0; k < pass->info->input_count; ++k) {
        const frame_image *im =
            &fr->images[halo_gl_pass_input(pass->inputs[k], rep, pass->start, pass->first, pass->output)];
        in = box_union(in, box_to_scale(im->support[im->current], im->scale, out->scale));
    }
    return box_grow(in, reach, out->width, out->height);
}

GLuint halo_gl_pass_build(const halo_gl *gl, const halo_program *p, size_t index, const char *vertex_source,
                          const char *define, halo_diagnostics *diag)
{
    const halo_glfuncs *f = &gl->f;
    const halo_pass_info *pass = &halo_program_reflection(p).passes[index];
    char file[256];
    snprintf(file, sizeof file, "(image pass '%s' of %s)", pass->name ? pass->name : "?",
             pass->stage ? pass->stage : "?");
    const halo_line_origin *origins = p->pass_origins ? p->pass_origins[index] : NULL;
    int origin_count = origins && p->pass_origin_counts ? p->pass_origin_counts[index] : 0;
    /* a define (and the fetch counting) go after the #version line; #line 2 keeps the
     * lines the origins map */
    const char *source = pass->fragment_source, *end = strchr(source, '\n');
    const char *counting = gl->count_fetches ? halo_gl_fetch_counting : "";
    char *defined = NULL;
    if ((define || *counting) && end) {
        size_t size = strlen(source) + (define ? strlen(define) : 0) + strlen(counting) + 32;
        defined = malloc(size);
        if (!defined)
            return 0;
        snprintf(defined, size, "%.*s%s%s%s%s#line 2\n%s", (int)(end - source) + 1, source, define ? "#define " : "",
                 define ? define : "", define ? " 1\n" : "", counting, end + 1);
        source = defined;
    }
    GLuint vertex = halo_gl_compile_mapped(f, GL_VERTEX_SHADER, vertex_source ? vertex_source : pass->vertex_source,
                                           NULL, NULL, 0, file, diag);
    GLuint fragment = halo_gl_compile_mapped(f, GL_FRAGMENT_SHADER, source, NULL, origins, origin_count, file, diag);
    free(defined);
    GLuint program = halo_gl_program_attach(f, vertex, fragment, file, diag);
    if (!program)
        return 0;
    if ((p->unlocated_outputs || p->target == HALO_TARGET_GLSL150) && f->BindFragDataLocation)
        f->BindFragDataLocation(program, 0, "halo_pass_output");
    program =
        halo_gl_link_attached(f, program, vertex, fragment, file, "the driver could not link the image pass", diag);
    if (!program)
        return 0;
    f->UseProgram(program);
    for (int k = 0; k < pass->input_count; ++k) {
        char name[32];
        snprintf(name, sizeof name, "halo_input_%d", k);
        f->Uniform1i(f->GetUniformLocation(program, name), k);
    }
    return program;
}

/* Has the context what the program's images and outputs need? The host's extra outputs
 * blend per draw buffer (OpenGL 4.0, ES 3.2), but for a ray caster drawn once (single_pass):
 * a ray writes its pixel once, and its outputs are written unblended where a context has
 * one blend for all buffers (OpenGL ES 3.0; halo_gl_frame_attach_outputs). libhalo's own march writes
 * only seeds, with one blend for all its buffers. On ES the images must be
 * colour-renderable floats (EXT_color_buffer_float before 3.2), and blending into 32-bit
 * ones needs EXT_float_blend. */
int halo_gl_blend_per_buffer(const halo_glfuncs *f)
{
    return f->Enablei && f->Disablei && f->BlendEquationi && f->BlendFunci && f->IsEnabledi;
}

static int frame_context_fits(halo_gl *gl, const halo_program *p, halo_diagnostics *diag)
{
    const halo_glfuncs *f = &gl->f;
    size_t outputs = halo_program_reflection(p).output_count;
    int per_buffer = halo_gl_blend_per_buffer(f);
    if (outputs > 0 && !per_buffer && !(p->single_pass && halo_program_reflection(p).segment_location <= 0)) {
        const char *version = (const char *)f->GetString(GL_VERSION);
        halo_diag_error(diag, GL_PROC_MISSING, "", 0, 0,
                        "the program writes extra outputs (%s%s), which need per-draw-buffer blending "
                        "(glBlendFunci, glBlendEquationi: OpenGL 4.0 or OpenGL ES 3.2); this context is %s%s",
                        halo_program_reflection(p).outputs[0].image, outputs > 1 ? ", ..." : "",
                        version ? version : "older",
                        gl->es ? ": on OpenGL ES 3.0 (WebGL 2) link a ray caster with host contract 3 "
                                 "(halo_link_desc.one_draw): drawn once, it writes its outputs unblended; a slice "
                                 "host's are not"
                               : "");
        return 0;
    }
    if (!gl->es || halo_program_reflection(p).image_count == 0)
        return 1;
    if (gl->es < 32 && !halo_gl_has_extension(gl, "GL_EXT_color_buffer_float")) {
        halo_diag_error(diag, GL_PROC_MISSING, "", 0, 0,
                        "the program's images are float textures drawn to, which OpenGL ES %d.%d allows with "
                        "GL_EXT_color_buffer_float; this context lacks it",
                        gl->es / 10, gl->es % 10);
        return 0;
    }
    size_t blended = (per_buffer ? outputs : 0) + (p->prepass ? halo_program_reflection(p->prepass).output_count : 0);
    if (blended > 0 && halo_program_reflection(p).image_precision == 32 &&
        !halo_gl_has_extension(gl, "GL_EXT_float_blend")) {
        halo_diag_error(diag, GL_PROC_MISSING, "", 0, 0,
                        "the program's outputs blend into 32-bit float images, which OpenGL ES needs "
                        "GL_EXT_float_blend for; this context lacks it: link with image_precision 16");
        return 0;
    }
    return 1;
}

halo_gl_frame *halo_gl_frame_create(halo_gl *gl, const halo_program *p, int width, int height, halo_diagnostics *diag)
{
    HALO_REFUSE_NULL(diag, gl, "gl", NULL);
    HALO_REFUSE_NULL(diag, p, "program", NULL);
    if (width < 1 || height < 1 || width > 16384 || height > 16384) {
        halo_diag_error(diag, USAGE, "", 0, 0, "halo_gl_frame_create: a size in 1..16384 is required");
        return NULL;
    }
    const halo_glfuncs *f = &gl->f;
    if (!frame_context_fits(gl, p, diag))
        return NULL;
    halo_gl_frame *fr = halo_diag_calloc(diag, sizeof *fr, "a frame");
    if (!fr)
        return NULL;
    fr->gl = gl;
    fr->program = p;
    atomic_fetch_add(&gl->refs, 1);
    halo_program_retain(p);
    fr->width = width;
    fr->height = height;
    fr->image_count = halo_program_reflection(p).image_count;
    fr->pass_count = halo_program_reflection(p).pass_count;
    fr->images = calloc(fr->image_count ? fr->image_count : 1, sizeof *fr->images);
    fr->passes = calloc(fr->pass_count ? fr->pass_count : 1, sizeof *fr->passes);
    if (!fr->images || !fr->passes) {
        halo_diag_error(diag, OUT_OF_MEMORY, "", 0, 0, "out of memory creating a frame");
        halo_gl_frame_destroy(fr);
        return NULL;
    }
    frame_saved saved;
    frame_save(f, &saved, 1);
    f->ActiveTexture(GL_TEXTURE0);
    int precision = halo_program_reflection(p).image_precision;
    int failed = 0;
    f->GenFramebuffers(1, &fr->framebuffer);
    f->GenVertexArrays(1, &fr->vertex_array);
    f->BindFramebuffer(GL_FRAMEBUFFER, fr->framebuffer);
    GLenum attachment0 = GL_COLOR_ATTACHMENT0;
    f->DrawBuffers(1, &attachment0);
    f->ReadBuffer(GL_COLOR_ATTACHMENT0);
    for (size_t i = 0; i < fr->image_count && !failed; ++i) {
        const halo_image_info *info = &halo_program_reflection(p).images[i];
        frame_image *image = &fr->images[i];
        image->name = info->name;
        image->channels = info->channels;
        image->reset = info->reset;
        image->clear = (GLfloat)info->clear;
        image->host = info->host;
        int scale = info->scale > 1 ? info->scale : 1;
        image->scale = scale;
        image->width = (width + scale - 1) / scale;
        image->height = (height + scale - 1) / scale;
        image->support[0] = image->support[1] = image_full(image); /* not initialised */
        if (image->host)
            continue;
        GLint internal;
        GLenum format;
        image_formats(image->channels, precision, &internal, &format);
        /* a 1/s image the samples read through the filter (the passes' texelFetch ignores it) */
        GLint filter = halo_program_image_filtered(p, info) ? GL_LINEAR : GL_NEAREST;
        f->GenTextures(2, image->texture);
        for (int k = 0; k < 2; ++k) {
            f->BindTexture(GL_TEXTURE_2D, image->texture[k]);
            f->TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, filter);
            f->TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, filter);
            f->TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
            f->TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
            GLenum type;
            halo_gl_image_upload_format(internal, &format, &type);
            f->TexImage2D(GL_TEXTURE_2D, 0, internal, image->width, image->height, 0, format, type, NULL);
            f->FramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, image->texture[k], 0);
            GLenum status = f->CheckFramebufferStatus(GL_FRAMEBUFFER);
            if (status != GL_FRAMEBUFFER_COMPLETE) {
                halo_diag_error(diag, GL_LINK, "", 0, 0,
                                "image '%s': a %dx%d texture of %d channels at precision %d cannot be rendered to "
                                "(framebuffer status 0x%x)",
                                image->name, image->width, image->height, image->channels, precision, status);
                failed = 1;
                break;
            }
        }
    }
    if (!failed && halo_program_reflection(p).segment_location > 0) {
        f->GenTextures(2, fr->state);
        for (int k = 0; k < 2; ++k) {
            f->BindTexture(GL_TEXTURE_2D, fr->state[k]);
            f->TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
            f->TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
            f->TexImage2D(GL_TEXTURE_2D, 0, GL_RGBA32F, width, height, 0, GL_RGBA, GL_FLOAT, NULL);
        }
    }
    f->FramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, 0, 0);
    f->BindTexture(GL_TEXTURE_2D, 0);
    if (!failed && gl->count_fetches) { /* the passes' fetch counter: one GLuint */
        GLint bound = 0;
        f->GetIntegerv(GL_ATOMIC_COUNTER_BUFFER_BINDING, &bound);
        f->GenBuffers(1, &fr->fetch_counter);
        f->BindBuffer(GL_ATOMIC_COUNTER_BUFFER, fr->fetch_counter);
        f->BufferData(GL_ATOMIC_COUNTER_BUFFER, sizeof(GLuint), NULL, GL_DYNAMIC_READ);
        f->BindBuffer(GL_ATOMIC_COUNTER_BUFFER, (GLuint)bound);
    }
    for (size_t i = 0; i < fr->pass_count && !failed; ++i) {
        const halo_pass_info *info = &halo_program_reflection(p).passes[i];
        frame_pass *pass = &fr->passes[i];
        pass->info = info;
        pass->repeat = info->repeat < 1 ? 1 : info->repeat;
        pass->start = info->start < 1 ? 1 : info->start;
        pass->output = frame_find_image(fr, info->output);
        pass->first = info->first ? frame_find_image(fr, info->first) : -1;
        if (pass->output < 0 || (info->first && pass->first < 0) || info->input_count > HALO_MAX_PASS_INPUTS) {
            halo_diag_error(diag, PASS_INVALID, "", 0, 0, "image pass '%s': unknown output or first image",
                            info->name ? info->name : "?");
            failed = 1;
            break;
        }
        for (int k = 0; k < info->input_count; ++k) {
            pass->inputs[k] = strcmp(info->inputs[k], "previous") == 0 ? -1 : frame_find_image(fr, info->inputs[k]);
            if (pass->inputs[k] < 0 && strcmp(info->inputs[k], "previous") != 0) {
                halo_diag_error(diag, PASS_INVALID, "", 0, 0, "image pass '%s': unknown input image '%s'",
                                info->name ? info->name : "?", info->inputs[k]);
                failed = 1;
            }
        }
        if (info->input_count > fr->max_inputs)
            fr->max_inputs = info->input_count;
        if (failed)
            break;
        pass->program = halo_gl_pass_build(gl, p, i, NULL, NULL, diag);
        if (!pass->program) {
            failed = 1;
            break;
        }
        pass->index_location = f->GetUniformLocation(pass->program, "halo_pass_index");
        pass->count_location = f->GetUniformLocation(pass->program, "halo_pass_count");
    }
    frame_restore(f, &saved);
    GLenum error = f->GetError();
    if (!failed && error != GL_NO_ERROR) {
        halo_diag_error(diag, GL_LINK, "", 0, 0, "OpenGL error 0x%x creating the frame's images and passes", error);
        failed = 1;
    }
    if (failed) {
        halo_gl_frame_destroy(fr);
        return NULL;
    }
    fr->readback_bounds = gl->readback; /* the runtime's policy (halo_gl_desc.readback) */
    halo_gl_frame_begin(fr);
    return fr;
}

void halo_gl_frame_destroy(halo_gl_frame *fr)
{
    if (!fr)
        return;
    if (fr->drawing > 0) { /* from halo_gl_frame_draw's callback: when the outermost draw returns */
        fr->destroy_pending = 1;
        return;
    }
    const halo_glfuncs *f = &fr->gl->f;
    if (fr->field && fr->field_destroy)
        fr->field_destroy(fr, fr->field);
    for (size_t i = 0; fr->images && i < fr->image_count; ++i)
        if (fr->images[i].texture[0] && !fr->images[i].host)
            f->DeleteTextures(2, fr->images[i].texture);
    for (size_t i = 0; fr->passes && i < fr->pass_count; ++i)
        if (fr->passes[i].program)
            f->DeleteProgram(fr->passes[i].program);
    if (fr->state[0])
        f->DeleteTextures(2, fr->state);
    if (fr->framebuffer)
        f->DeleteFramebuffers(1, &fr->framebuffer);
    if (fr->vertex_array)
        f->DeleteVertexArrays(1, &fr->vertex_array);
    if (fr->fetch_counter)
        f->DeleteBuffers(1, &fr->fetch_counter);
    free(fr->images);
    free(fr->passes);
    free(fr->readback);
    halo_program_destroy((halo_program *)fr->program); /* the frame's references */
    halo_gl_destroy(fr->gl);
    free(fr);
}

/* Which images a clear resets: all; a feature group's (not the frame's accumulators,
 * reset=frame-only); all but a one_draw program's field (read from its stacks). */
typedef enum { FRAME_CLEAR_ALL, FRAME_CLEAR_GROUP, FRAME_CLEAR_HOST } frame_clear_what;
static void frame_clear(halo_gl_frame *fr, frame_clear_what what);
static void frame_run(halo_gl_frame *fr, halo_pass_at at);

void halo_gl_frame_begin(halo_gl_frame *fr)
{
    HALO_REFUSE_NULL_VOID(NULL, fr, "frame");
    fr->groups_ended = 0;
    frame_clear(fr, FRAME_CLEAR_ALL);
}

void halo_gl_frame_begin_host(halo_gl_frame *fr)
{
    fr->groups_ended = 0;
    frame_clear(fr, FRAME_CLEAR_HOST);
}

void halo_gl_frame_begin_group(halo_gl_frame *fr)
{
    HALO_REFUSE_NULL_VOID(NULL, fr, "frame");
    frame_clear(fr, FRAME_CLEAR_GROUP);
}

void halo_gl_frame_end_group(halo_gl_frame *fr)
{
    HALO_REFUSE_NULL_VOID(NULL, fr, "frame");
    frame_run(fr, HALO_PASS_AT_POST);
    fr->groups_ended++;
}

/* Clears the images `what` says. */
static void frame_clear(halo_gl_frame *fr, frame_clear_what what)
{
    if (!fr || fr->image_count == 0)
        return;
    const halo_glfuncs *f = &fr->gl->f;
    frame_take_host_draws(fr, 0); /* for the images not cleared */
    frame_saved saved;
    frame_save(f, &saved, 0); /* a clear obeys the scissor, the colour mask, rasterizer discard */
    f->BindFramebuffer(GL_DRAW_FRAMEBUFFER, fr->framebuffer);
    for (size_t i = 0; i < fr->image_count; ++i)
        if (what == FRAME_CLEAR_ALL || (what == FRAME_CLEAR_GROUP && fr->images[i].reset != HALO_RESET_FRAME_ONLY) ||
            (what == FRAME_CLEAR_HOST && !halo_prepass_image(fr->program, fr->images[i].name)))
            frame_clear_image(fr, (int)i);
    f->FramebufferTexture2D(GL_DRAW_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, 0, 0);
    frame_restore(f, &saved);
}

/* Attaches the outputs' current textures to the framebuffer bound as GL_DRAW_FRAMEBUFFER. */
static void frame_attach_textures(halo_gl_frame *fr)
{
    const halo_glfuncs *f = &fr->gl->f;
    const halo_program *p = fr->attached_program ? fr->attached_program : fr->program;
    size_t n = halo_program_reflection(p).output_count;
    for (size_t i = 0; i < n; ++i) {
        const halo_output_info *o = &halo_program_reflection(p).outputs[i];
        int image = frame_find_image(fr, o->image);
        if (image < 0 || o->location < 1)
            continue;
        const frame_image *im = &fr->images[image];
        f->FramebufferTexture2D(GL_DRAW_FRAMEBUFFER, GL_COLOR_ATTACHMENT0 + (GLenum)o->location, GL_TEXTURE_2D,
                                im->texture[im->current], 0);
    }
}

void halo_gl_frame_attach(halo_gl_frame *fr, unsigned host_framebuffer)
{
    HALO_REFUSE_NULL_VOID(NULL, fr, "frame");
    halo_gl_frame_attach_outputs(fr, fr->program, host_framebuffer, 1);
}

void halo_gl_frame_attach_outputs(halo_gl_frame *fr, const halo_program *p, unsigned host_framebuffer, int colour)
{
    size_t n = halo_program_reflection(p).output_count;
    if (n == 0)
        return;
    const halo_glfuncs *f = &fr->gl->f;
    f->BindFramebuffer(GL_DRAW_FRAMEBUFFER, host_framebuffer);
    fr->attached_program = p;
    frame_attach_textures(fr);
    GLenum buffers[FRAME_MAX_BUFFERS * 4];
    int max_location = 0;
    for (size_t i = 0; i < n; ++i) {
        int location = halo_program_reflection(p).outputs[i].location;
        if (location > max_location && location < (int)(sizeof buffers / sizeof buffers[0]))
            max_location = location;
    }
    buffers[0] = colour ? GL_COLOR_ATTACHMENT0 : GL_NONE;
    for (int k = 1; k <= max_location; ++k)
        buffers[k] = GL_NONE;
    for (size_t i = 0; i < n; ++i) {
        const halo_output_info *o = &halo_program_reflection(p).outputs[i];
        if (o->location < 1 || o->location > max_location)
            continue;
        buffers[o->location] = GL_COLOR_ATTACHMENT0 + (GLenum)o->location;
        GLenum equation = o->blend == HALO_BLEND_MAX ? GL_MAX : o->blend == HALO_BLEND_MIN ? GL_MIN : GL_FUNC_ADD;
        /* first: front to back by coverage, the first hit stays */
        GLenum source = o->blend == HALO_BLEND_FIRST ? GL_ONE_MINUS_DST_ALPHA : GL_ONE;
        if (!halo_gl_blend_per_buffer(f)) {
            /* one blend for every buffer (OpenGL ES 3.0): libhalo's march, whose buffer 0
             * is not drawn and whose outputs are seeds; or a ray caster drawn once, which
             * writes each pixel once (halo_gl_frame_create refuses others' outputs there):
             * unblended, as a blend of the one value into the image's clear value gives */
            if (!colour) {
                (o->blend == HALO_BLEND_NONE ? f->Disable : f->Enable)(GL_BLEND);
                f->BlendEquation(equation);
                f->BlendFunc(source, GL_ONE);
            } else {
                f->Disable(GL_BLEND);
            }
            continue;
        }
        if (o->blend == HALO_BLEND_NONE) {
            f->Disablei(GL_BLEND, (GLuint)o->location);
            continue;
        }
        f->Enablei(GL_BLEND, (GLuint)o->location);
        f->BlendEquationi((GLuint)o->location, equation);
        f->BlendFunci((GLuint)o->location, source, GL_ONE);
    }
    f->DrawBuffers(max_location + 1, buffers);
    fr->attached = 1;
    fr->attached_framebuffer = host_framebuffer;
}

/* Binds the samplers' current textures to their units (from first_unit on). */
static void frame_bind_textures(halo_gl_frame *fr, int first_unit)
{
    const halo_glfuncs *f = &fr->gl->f;
    size_t n = halo_program_reflection(fr->program).sampler_count;
    for (size_t i = 0; i < n; ++i) {
        const char *name = halo_program_reflection(fr->program).samplers[i].image;
        int image = frame_find_image(fr, name);
        if (image < 0)
            continue;
        const frame_image *im = &fr->images[image];
        f->ActiveTexture(GL_TEXTURE0 + (GLenum)(first_unit + (int)i));
        if (!halo_prepass_image(fr->program, name)) /* host contract 3: field.c binds the image's stack */
            f->BindTexture(GL_TEXTURE_2D, im->texture[im->current]);
    }
}

void halo_gl_frame_bind(halo_gl_frame *fr, unsigned gl_program, int first_unit)
{
    HALO_REFUSE_NULL_VOID(NULL, fr, "frame");
    if (first_unit < 0)
        return;
    size_t n = halo_program_reflection(fr->program).sampler_count;
    if (n == 0)
        return;
    const halo_glfuncs *f = &fr->gl->f;
    GLint active = GL_TEXTURE0;
    f->GetIntegerv(GL_ACTIVE_TEXTURE, &active);
    frame_bind_textures(fr, first_unit);
    for (size_t i = 0; i < n; ++i)
        f->Uniform1i(f->GetUniformLocation(gl_program, halo_program_reflection(fr->program).samplers[i].name),
                     first_unit + (GLint)i);
    f->ActiveTexture((GLenum)active);
    fr->bound = 1;
    fr->bound_first_unit = first_unit;
}

static void frame_run(halo_gl_frame *fr, halo_pass_at at);

void halo_gl_frame_generate(halo_gl_frame *fr)
{
    HALO_REFUSE_NULL_VOID(NULL, fr, "frame");
    frame_run(fr, HALO_PASS_AT_GENERATE);
}

void halo_gl_frame_post(halo_gl_frame *fr, unsigned host_color_texture)
{
    HALO_REFUSE_NULL_VOID(NULL, fr, "frame");
    for (size_t i = 0; i < fr->image_count; ++i)
        if (fr->images[i].host) {
            fr->images[i].texture[0] = fr->images[i].texture[1] = host_color_texture;
            fr->images[i].current = 0;
        }
    if (!fr->groups_ended)
        frame_run(fr, HALO_PASS_AT_POST);
    frame_run(fr, HALO_PASS_AT_FINAL);
}

unsigned halo_gl_frame_texture(const halo_gl_frame *fr, const char *image)
{
    HALO_REFUSE_NULL(NULL, fr, "frame", 0);
    HALO_REFUSE_NULL(NULL, image, "image", 0);
    int i = frame_find_image(fr, image);
    if (i < 0)
        return 0;
    /* The caller may write the texture (as the VTK adapter's exchange of seeds does): its
     * support becomes unknown. The frame was created non-const (halo_gl_frame_create). */
    frame_image *im = &((halo_gl_frame *)fr)->images[i];
    im->support[im->current] = image_full(im);
    return im->texture[im->current];
}

int halo_gl_frame_reads_back(const halo_gl_frame *fr) { return fr->readback_bounds; }

void halo_gl_frame_set_readback_bounds(halo_gl_frame *fr, int on)
{
    HALO_REFUSE_NULL_VOID(NULL, fr, "frame");
    fr->readback_bounds = on != 0;
}

void halo_gl_frame_drawn_region(halo_gl_frame *fr, int x0, int y0, int x1, int y1)
{
    HALO_REFUSE_NULL_VOID(NULL, fr, "frame");
    frame_box b = {x0, y0, x1, y1};
    if (box_empty(b))
        b = (frame_box){0, 0, 0, 0};
    fr->drawn = fr->drawn_known ? box_union(fr->drawn, b) : b;
    fr->drawn_known = 1;
}

/* halo_gl_frame_info.read_box and read_any. */
static int frame_read_region(const halo_gl_frame *fr, int box[4])
{
    frame_box all = {0, 0, fr->width, fr->height}, region = {0, 0, 0, 0};
    for (size_t i = 0; i < halo_program_reflection(fr->program).sampler_count; ++i) {
        int k = frame_find_image(fr, halo_program_reflection(fr->program).samplers[i].image);
        const frame_image *im = k >= 0 ? &fr->images[k] : NULL;
        if (!im || im->host || im->clear != 0.0f) { /* support holds for images cleared to 0 */
            region = all;
            break;
        }
        frame_box b = im->support[im->current];
        if (box_empty(b))
            continue;
        /* a 1/s image is read bilinearly between the texel centres around a pixel: texel t
         * reaches the frame pixels [(t - 1) s, (t + 2) s) */
        int s = im->scale;
        b = (frame_box){(b.x0 - 1) * s, (b.y0 - 1) * s, (b.x1 + 1) * s, (b.y1 + 1) * s};
        region = box_union(region, box_grow(b, 0, fr->width, fr->height));
    }
    box[0] = region.x0;
    box[1] = region.y0;
    box[2] = region.x1;
    box[3] = region.y1;
    return !box_empty(region);
}

/* The one box b into plan's list of variant v (when not empty). */
static void plan_add(halo_gl_slice_plan *plan, int v, frame_box b)
{
    if (box_empty(b))
        return;
    int *out = plan->box[v][plan->count[v]++];
    out[0] = b.x0, out[1] = b.y0, out[2] = b.x1, out[3] = b.y1;
}

int halo_gl_frame_plan_slice(const halo_gl_frame *fr, const int section[4], int variants, halo_gl_slice_plan *plan)
{
    HALO_REFUSE_NULL(NULL, fr, "frame", 0);
    HALO_REFUSE_NULL(NULL, section, "section", 0);
    HALO_REFUSE_NULL(NULL, plan, "plan", 0);
    memset(plan, 0, sizeof *plan);
    frame_box cut = {section[0], section[1], section[2], section[3]}, read = {0, 0, 0, 0};
    if (box_empty(cut))
        cut = read;
    if (!variants) {
        plan_add(plan, HALO_GL_SLICE_SHADER, cut);
        return plan->count[HALO_GL_SLICE_SHADER];
    }
    int r[4];
    if (frame_read_region(fr, r))
        read = (frame_box){r[0], r[1], r[2], r[3]};
    frame_box inside = box_intersect(cut, read);
    plan_add(plan, HALO_GL_SLICE_SHADER, inside);
    /* the rest of the section (all of it when no image can be nonzero) */
    if (box_empty(inside))
        plan_add(plan, HALO_GL_SLICE_ZERO, cut);
    else if (!box_empty(cut))
        plan->count[HALO_GL_SLICE_ZERO] = box_subtract(cut, inside, plan->box[HALO_GL_SLICE_ZERO]);
    /* the read region off the section */
    if (box_empty(cut))
        plan_add(plan, HALO_GL_SLICE_OUTSIDE, read);
    else if (!box_empty(read))
        plan->count[HALO_GL_SLICE_OUTSIDE] = box_subtract(read, cut, plan->box[HALO_GL_SLICE_OUTSIDE]);
    return plan->count[0] + plan->count[1] + plan->count[2];
}

static void frame_run(halo_gl_frame *fr, halo_pass_at at)
{
    if (!fr || (fr->pass_count == 0 && fr->image_count == 0))
        return;
    halo_gl *gl = fr->gl;
    const halo_glfuncs *f = &gl->f;
    frame_saved saved;
    frame_save(f, &saved, fr->max_inputs);
    halo_gl_fetch_binding counting;
    halo_gl_frame_fetches_begin(fr, &counting);
    f->BindFramebuffer(GL_FRAMEBUFFER, fr->framebuffer);
    f->Viewport(0, 0, fr->width, fr->height);
    f->Disable(GL_BLEND);
    f->Disable(GL_SCISSOR_TEST);
    f->BindVertexArray(fr->vertex_array);
    int scissored = at == HALO_PASS_AT_GENERATE && frame_scissored(fr);
    frame_take_host_draws(fr, scissored && fr->readback_bounds);
    for (size_t i = 0; i < fr->pass_count; ++i) {
        frame_pass *pass = &fr->passes[i];
        frame_image *out = &fr->images[pass->output];
        if (pass->info->at != at || out->host)
            continue;
        f->UseProgram(pass->program);
        halo_gl_program_upload(gl, fr->program, pass->program);
        f->Viewport(0, 0, out->width, out->height);
        for (int rep = pass->start; rep <= pass->repeat; ++rep) {
            for (int k = 0; k < pass->info->input_count; ++k) {
                const frame_image *in =
                    &fr->images[halo_gl_pass_input(pass->inputs[k], rep, pass->start, pass->first, pass->output)];
                f->ActiveTexture(GL_TEXTURE0 + (GLenum)k);
                f->BindTexture(GL_TEXTURE_2D, in->texture[in->current]);
            }
            halo_gl_pass_repetition(f, pass->index_location, pass->count_location, rep, pass->repeat);
            /* Scissored: the pixels that can be nonzero, and those the target texture
             * holds nonzero from before (they become the pass's zeros); none: no draw. */
            frame_box *target = &out->support[1 - out->current];
            frame_box reach = scissored ? pass_reach_box(fr, pass, rep, out) : image_full(out);
            frame_box write = box_union(reach, *target);
            if (!box_empty(write)) {
                f->FramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D,
                                        out->texture[1 - out->current], 0);
                if (scissored) {
                    f->Enable(GL_SCISSOR_TEST);
                    f->Scissor(write.x0, write.y0, write.x1 - write.x0, write.y1 - write.y0);
                }
                f->DrawArrays(GL_TRIANGLES, 0, 3);
                fr->pass_draws++;
            }
            *target = reach;
            out->current = 1 - out->current;
        }
    }
    for (size_t i = 0; i < fr->image_count && at == HALO_PASS_AT_GENERATE; ++i) {
        frame_image *im = &fr->images[i];
        if (im->reset != HALO_RESET_GENERATION)
            continue;
        frame_box b = scissored ? im->support[im->current] : image_full(im);
        if (box_empty(b))
            continue;
        if (scissored) {
            f->Enable(GL_SCISSOR_TEST);
            f->Scissor(b.x0, b.y0, b.x1 - b.x0, b.y1 - b.y0);
        }
        frame_clear_image(fr, (int)i);
    }
    f->Disable(GL_SCISSOR_TEST);
    f->FramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, 0, 0);
    halo_gl_frame_fetches_end(fr, &counting);
    frame_restore(f, &saved);
    /* Passes flip images: the host framebuffer and the samplers get the new current textures. */
    if (fr->attached) {
        GLint draw_framebuffer = 0;
        f->GetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &draw_framebuffer);
        f->BindFramebuffer(GL_DRAW_FRAMEBUFFER, fr->attached_framebuffer);
        frame_attach_textures(fr);
        f->BindFramebuffer(GL_DRAW_FRAMEBUFFER, (GLuint)draw_framebuffer);
    }
    if (fr->bound) {
        frame_bind_textures(fr, fr->bound_first_unit);
        f->ActiveTexture((GLenum)saved.state.bindings.active_texture);
    }
}

halo_status halo_gl_frame_read(halo_gl_frame *fr, const char *name, float *out)
{
    HALO_REFUSE_NULL(NULL, fr, "frame", HALO_ERROR_INPUT);
    HALO_REFUSE_NULL(NULL, name, "image", HALO_ERROR_INPUT);
    HALO_REFUSE_NULL(NULL, out, "out", HALO_ERROR_INPUT);
    int index = frame_find_image(fr, name);
    if (index < 0)
        return HALO_ERROR_INPUT;
    const halo_glfuncs *f = &fr->gl->f;
    const frame_image *im = &fr->images[index];
    halo_gl_bindings saved;
    halo_gl_bindings_save(f, &saved);
    halo_gl_bindings_neutral(f, &saved); /* tight packing */
    f->BindFramebuffer(GL_READ_FRAMEBUFFER, fr->framebuffer);
    f->FramebufferTexture2D(GL_READ_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, im->texture[im->current], 0);
    f->ReadBuffer(GL_COLOR_ATTACHMENT0);
    int read = halo_gl_read_floats(fr->gl, 0, 0, im->width, im->height, im->channels, out);
    f->FramebufferTexture2D(GL_READ_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, 0, 0);
    halo_gl_bindings_restore(f, &saved);
    return f->GetError() == GL_NO_ERROR && read ? HALO_OK : HALO_ERROR_IO;
}

halo_gl_frame_info halo_gl_frame_describe(const halo_gl_frame *fr)
{
    halo_gl_frame_info info = {0};
    HALO_REFUSE_NULL(NULL, fr, "frame", info);
    info.pass_draws = fr->pass_draws;
    info.pass_fetches = fr->pass_fetches;
    info.segment_count = fr->segments_drawn;
    info.read_any = frame_read_region(fr, info.read_box);
    /* the GPU memory: the images' textures, the rays' state (contract 2), the field */
    for (size_t i = 0; i < fr->image_count; ++i) {
        const frame_image *im = &fr->images[i];
        GLint internal;
        GLenum format;
        image_formats(im->channels, halo_program_reflection(fr->program).image_precision, &internal, &format);
        for (int k = 0; k < 2 && !im->host; ++k)
            info.gpu_bytes +=
                im->texture[k] ? (size_t)im->width * (size_t)im->height * halo_gl_image_texel_bytes(internal) : 0;
    }
    for (int k = 0; k < 2; ++k)
        info.gpu_bytes += fr->state[k] ? (size_t)fr->width * (size_t)fr->height * 16u : 0;
    if (fr->field && fr->field_bytes)
        info.gpu_bytes += fr->field_bytes(fr->field);
    return info;
}

/* For field.c (host contract 3). */
int halo_gl_frame_image_view(const halo_gl_frame *fr, const char *name, halo_gl_frame_image *view)
{
    int i = frame_find_image(fr, name);
    if (i < 0 || fr->images[i].host)
        return 0;
    const frame_image *im = &fr->images[i];
    GLenum format;
    image_formats(im->channels, halo_program_reflection(fr->program).image_precision, &view->internal_format, &format);
    view->texture = im->texture[im->current];
    view->width = im->width;
    view->height = im->height;
    view->box[0] = im->support[im->current].x0;
    view->box[1] = im->support[im->current].y0;
    view->box[2] = im->support[im->current].x1;
    view->box[3] = im->support[im->current].y1;
    return 1;
}

halo_gl_field *halo_gl_frame_field(const halo_gl_frame *fr) { return fr->field; }

int halo_gl_pass_input(int named, int rep, int start, int first, int output)
{
    return named >= 0 ? named : rep == start && first >= 0 ? first : output;
}

void halo_gl_pass_repetition(const halo_glfuncs *f, GLint index_location, GLint count_location, int rep, int repeat)
{
    if (index_location >= 0)
        f->Uniform1i(index_location, rep);
    if (count_location >= 0)
        f->Uniform1i(count_location, repeat);
}

void halo_gl_frame_count_pass_draws(halo_gl_frame *fr, long draws) { fr->pass_draws += draws; }

void halo_gl_frame_fetches_begin(halo_gl_frame *fr, halo_gl_fetch_binding *saved)
{
    if (fr->fetch_counter)
        halo_gl_fetches_begin(fr->gl, fr->fetch_counter, saved);
}

void halo_gl_frame_fetches_end(halo_gl_frame *fr, const halo_gl_fetch_binding *saved)
{
    if (fr->fetch_counter)
        fr->pass_fetches += halo_gl_fetches_end(fr->gl, fr->fetch_counter, saved);
}

void halo_gl_frame_set_field(halo_gl_frame *fr, halo_gl_field *field,
                             void (*destroy)(halo_gl_frame *fr, halo_gl_field *field),
                             size_t (*bytes)(const halo_gl_field *field))
{
    fr->field = field;
    fr->field_destroy = destroy;
    fr->field_bytes = bytes;
}
