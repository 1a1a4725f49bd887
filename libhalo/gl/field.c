/* Host contract 3 in the GL runtime (docs/host-contract.md, "Host contract 3"): for a
 * program linked with one_draw, the images that generation passes make (volumetric halos'
 * field and occlusion) are computed for every depth segment before the host draws, and
 * the host is drawn once.
 *
 * Per segment j, front to back: libhalo's march (the program's prepass, linked from the
 * same scene; prepass.c) draws the seeds of the segment's planes into the frame's seed
 * image, scissored to the segment's footprint; halo_gl_frame_generate runs the passes
 * (scissored to where seeds can reach, as for a slice host); the images the samples read
 * are copied into layer j of their stack (a GL_TEXTURE_2D_ARRAY), inside the box where
 * either the new or the layer's old content can be nonzero. A sample of segment j reads
 * layer j - 1 (halo_stack_layer_at in the linked shader). The segments and the planes are
 * the slice host's and the segmented ray caster's (segments.c), so at equal M the field is
 * theirs; the occlusion image's running maximum is kept by the front-to-back order.
 *
 * With eight draw buffers, where the march is batchable (halo_prepass_batchable: one seed
 * output into an image every generation starts from the blend's identity, no discard) and
 * the batch's seed stack is within a sixteenth of field_max_bytes, the march draws eight
 * segments at once (field_batches): each ray is set up once for the eight, and the seeds
 * of segment j0 + b go to layer b of an eight-layer seed stack; each of the eight
 * generations then starts from a copy of its layer. Every march clips its rays to the
 * volume's box and steps over empty bricks (prepass.c). The samples and the images are the
 * same as one segment a draw (`halo-validate conform --stage segments` prints the same
 * numbers), up to a sample whose rounded position differs from the exact one by more than
 * the margins there. */
#include "halo.h"
#include "internal.h"
#include "diag.h"
#include "gl/field_atlas.h"
#include "gl/frame.h"
#include "gl/glfuncs.h"
#include "gl/runtime.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <stdio.h>
#include <string.h>

#define FIELD_MAX_STACKS         4
#define FIELD_DEFAULT_FIRST_UNIT 8

typedef struct field_stack {
    const char *image;
    GLuint texture;
    GLint internal_format;
    int width, height;
    int (*boxes)[4]; /* per layer: outside it the layer holds 0 */
} field_stack;

/* The gradient the march reads when the host gives none: central differences of the
 * host's volume (halved, per voxel step: the contract's), kept while the volume is. */
typedef struct field_gradient {
    GLuint texture, program;
    GLint volume, layer;
    /* the empty-space skip: per brick of 4^3 voxels, the largest |gradient| a sample in it
     * interpolates (voxels 4b - 1 .. 4b + 4 per axis), of the gradient texture in use */
    GLuint bricks, brick_program;
    GLint brick_gradient, brick_layer;
    unsigned bricks_of;
    int bricks_version, bricks_valid, brick_size[3];
    unsigned of;           /* the volume texture it was derived from */
    GLint internal_format; /* GL_RGBA32F or GL_RGBA16F: halo_gl_segments_desc.gradient_precision */
    int size[3];
    int version; /* halo_gl_segments_desc.volume_version it was derived at */
    int valid;
} field_gradient;

/* A march program's uniform locations (range: march_range, or march_ranges of a batch). */
typedef struct march_locations {
    GLint volume, gradient_sampler, bricks_sampler, skip, matrix, viewport, box_min, box_max, plane, planes, range;
    GLint piece_min, piece_scale, scale;
} march_locations;

#define FIELD_BATCH 8 /* segments a draw of the batched march (prepass.c: HALO_MARCH_BATCH) */

struct halo_gl_field {
    GLuint framebuffer, vertex_array;
    /* the march of one segment a draw, and (0 where it cannot run: a march of
     * another output than the seeds at location 1, fewer than 8 draw buffers) of
     * FIELD_BATCH segments a draw into the seed stacks */
    GLuint march, batch;
    march_locations at, batch_at;
    /* the batched march's generations as atlases, each pass one draw over every segment
     * (field_atlas.c); NULL where they do not suit one */
    halo_gl_field_atlas *atlas;
    int atlas_unsuited; /* the program's generations cannot run on an atlas */
    /* the layers an atlas did not fit for, and did at its last success: a frame with no more
     * than the latter, or half the former, tries again (each try compiles its passes) */
    int atlas_failed, atlas_fit;
    field_gradient gradient;
    field_stack stacks[FIELD_MAX_STACKS];
    int stack_count;
    int layers; /* allocated in each stack */
    /* a piece of a distributed volume (halo_gl_segments_desc.exchange): the seeds of every
     * segment, kept to be combined across the pieces once a frame */
    GLuint seed_stacks[FIELD_MAX_STACKS];
    size_t seed_stack_bytes[FIELD_MAX_STACKS];
    int seed_layers;
    float *exchange_buffer;
    size_t exchange_size;
    /* field_key of the field the stacks hold (valid: they hold one), and how many fields
     * this frame has computed */
    uint64_t key;
    int key_valid, computed;
};

static const char march_vertex_330[] =
    "#version 330 core\n"
    "void main() {\n"
    "    gl_Position = vec4(float((gl_VertexID & 1) << 2) - 1.0, float((gl_VertexID & 2) << 1) - 1.0, 0.0, 1.0);\n"
    "}\n";
static const char march_vertex_es300[] =
    "#version 300 es\n"
    "void main() {\n"
    "    gl_Position = vec4(float((gl_VertexID & 1) << 2) - 1.0, float((gl_VertexID & 2) << 1) - 1.0, 0.0, 1.0);\n"
    "}\n";
/* One layer of the bricks: the largest |gradient| among the voxels whose values a
 * trilinear sample inside the brick reads (the brick's 4 and one more on each side). */
static const char brick_fragment_body[] =
    "uniform highp sampler3D gradient;\n"
    "uniform int layer;\n"
    "layout(location = 0) out vec4 largest;\n"
    "void main() {\n"
    "    ivec3 size = textureSize(gradient, 0), b = ivec3(ivec2(gl_FragCoord.xy), layer) * 4;\n"
    "    float m = 0.0;\n"
    "    for (int z = -1; z <= 4; ++z)\n"
    "        for (int y = -1; y <= 4; ++y)\n"
    "            for (int x = -1; x <= 4; ++x)\n"
    "                m = max(m, length(texelFetch(gradient, clamp(b + ivec3(x, y, z), ivec3(0), size - 1), 0).rgb));\n"
    "    largest = vec4(m, 0.0, 0.0, 0.0);\n"
    "}\n";
/* One layer of the gradient: central differences of the voxel values, clamped at the
 * borders as the volume sampler's CLAMP_TO_EDGE reads them, halved. Trilinear filtering
 * commutes with the shift by one voxel, so that inside the volume the gradient at a
 * position is the one host contract 2 derives there (segment.c). */
static const char gradient_fragment_body[] =
    "uniform highp sampler3D volume;\n"
    "uniform int layer;\n"
    "layout(location = 0) out vec4 gradient;\n"
    "float value_at(ivec3 p) { return texelFetch(volume, clamp(p, ivec3(0), textureSize(volume, 0) - 1), 0).r; }\n"
    "void main() {\n"
    "    ivec3 p = ivec3(ivec2(gl_FragCoord.xy), layer);\n"
    "    gradient = vec4(0.5 * vec3(value_at(p + ivec3(1, 0, 0)) - value_at(p - ivec3(1, 0, 0)),\n"
    "                               value_at(p + ivec3(0, 1, 0)) - value_at(p - ivec3(0, 1, 0)),\n"
    "                               value_at(p + ivec3(0, 0, 1)) - value_at(p - ivec3(0, 0, 1))), 0.0);\n"
    "}\n";

static void field_destroy(halo_gl_frame *fr, halo_gl_field *field);

static march_locations march_locations_of(const halo_glfuncs *f, GLuint march, const char *range)
{
    return (march_locations){
        .volume = f->GetUniformLocation(march, "march_volume"),
        .gradient_sampler = f->GetUniformLocation(march, "march_gradient"),
        .bricks_sampler = f->GetUniformLocation(march, "march_bricks"),
        .skip = f->GetUniformLocation(march, "march_skip"),
        .matrix = f->GetUniformLocation(march, "march_inverse_view_projection"),
        .viewport = f->GetUniformLocation(march, "march_viewport"),
        .scale = f->GetUniformLocation(march, "march_scale"),
        .box_min = f->GetUniformLocation(march, "march_box_min"),
        .box_max = f->GetUniformLocation(march, "march_box_max"),
        .plane = f->GetUniformLocation(march, "march_plane"),
        .planes = f->GetUniformLocation(march, "march_planes"),
        .range = f->GetUniformLocation(march, range),
        .piece_min = f->GetUniformLocation(march, "march_piece_min"),
        .piece_scale = f->GetUniformLocation(march, "march_piece_scale"),
    };
}

/* The field of a one_draw frame: its stacks and libhalo's march; NULL after a diagnostic. */
static halo_gl_field *field_create(halo_gl_frame *fr, halo_diagnostics *diag)
{
    halo_gl *gl = halo_gl_frame_runtime(fr);
    const halo_glfuncs *f = halo_gl_functions(gl);
    const halo_program *p = halo_gl_frame_program(fr);
    halo_gl_field *field = halo_diag_calloc(diag, sizeof *field, "the field of a one-draw frame");
    if (!field)
        return NULL;
    for (size_t i = 0; i < halo_program_reflection(p).sampler_count; ++i) {
        const char *image = halo_program_reflection(p).samplers[i].image;
        halo_gl_frame_image view;
        if (!halo_prepass_image(p, image) || !halo_gl_frame_image_view(fr, image, &view))
            continue;
        if (field->stack_count == FIELD_MAX_STACKS) {
            halo_diag_error(diag, USAGE, "", 0, 0, "a one-draw program reads more than %d images of generation passes",
                            FIELD_MAX_STACKS);
            field_destroy(fr, field);
            return NULL;
        }
        field->stacks[field->stack_count++] =
            (field_stack){image, 0, view.internal_format, view.width, view.height, NULL};
    }
    GLint program = 0;
    f->GetIntegerv(GL_CURRENT_PROGRAM, &program);
    field->march = halo_gl_program_build(
        gl, p->prepass, p->prepass->target == HALO_TARGET_ES300 ? march_vertex_es300 : march_vertex_330,
        "(libhalo's march, vertex shader)", NULL, diag);
    if (!field->march) {
        field_destroy(fr, field);
        return NULL;
    }
    field->at = march_locations_of(f, field->march, "march_range");
    GLint draw_buffers = 0, attachments = 0;
    f->GetIntegerv(GL_MAX_DRAW_BUFFERS, &draw_buffers);
    f->GetIntegerv(GL_MAX_COLOR_ATTACHMENTS, &attachments);
    if (halo_prepass_batchable(p->prepass) && draw_buffers >= FIELD_BATCH && attachments >= FIELD_BATCH) {
        /* (a batch that does not build leaves the march of one segment a draw) */
        int es = p->prepass->target == HALO_TARGET_ES300;
        field->batch = halo_gl_program_build(gl, p->prepass, es ? march_vertex_es300 : march_vertex_330,
                                             "(libhalo's march, vertex shader)", "#define HALO_MARCH_BATCH 1\n", NULL);
        if (field->batch)
            field->batch_at = march_locations_of(f, field->batch, "march_ranges");
    }
    f->GenFramebuffers(1, &field->framebuffer);
    f->GenVertexArrays(1, &field->vertex_array);
    halo_gl_use_saved_program(f, program);
    return field;
}

/* The GPU memory field holds: its stacks, the seeds' stacks, the atlas, the derived
 * gradient and its bricks (halo_gl_frame_info.gpu_bytes). */
static size_t field_bytes(const halo_gl_field *field)
{
    size_t bytes = 0;
    for (int s = 0; s < field->stack_count; ++s)
        bytes += (size_t)field->stacks[s].width * (size_t)field->stacks[s].height * (size_t)field->layers *
                 halo_gl_image_texel_bytes(field->stacks[s].internal_format);
    for (int s = 0; s < FIELD_MAX_STACKS; ++s)
        bytes += field->seed_stacks[s] ? field->seed_stack_bytes[s] : 0;
    const field_gradient *g = &field->gradient;
    if (g->texture)
        bytes += (size_t)g->size[0] * (size_t)g->size[1] * (size_t)g->size[2] *
                 (g->internal_format == GL_RGBA16F ? 8u : 16u);
    if (g->bricks)
        bytes += (size_t)g->brick_size[0] * (size_t)g->brick_size[1] * (size_t)g->brick_size[2] * 4u;
    return bytes + halo_gl_field_atlas_bytes(field->atlas);
}

static void field_destroy(halo_gl_frame *fr, halo_gl_field *field)
{
    if (!field)
        return;
    const halo_glfuncs *f = halo_gl_functions(halo_gl_frame_runtime(fr));
    for (int s = 0; s < field->stack_count; ++s) {
        f->DeleteTextures(1, &field->stacks[s].texture);
        free(field->stacks[s].boxes);
    }
    for (int s = 0; s < FIELD_MAX_STACKS; ++s)
        if (field->seed_stacks[s])
            f->DeleteTextures(1, &field->seed_stacks[s]);
    free(field->exchange_buffer);
    halo_gl_field_atlas_destroy(f, field->atlas);
    f->DeleteProgram(field->march);
    f->DeleteProgram(field->batch);
    f->DeleteProgram(field->gradient.program);
    f->DeleteTextures(1, &field->gradient.texture);
    f->DeleteProgram(field->gradient.brick_program);
    f->DeleteTextures(1, &field->gradient.bricks);
    f->DeleteFramebuffers(1, &field->framebuffer);
    f->DeleteVertexArrays(1, &field->vertex_array);
    free(field);
}

/* Binds the stacks to the host program's samplers of their images, from first_unit on as
 * halo_gl_frame_bind binds the others. */
static void field_bind(const halo_glfuncs *f, const halo_program *p, const halo_gl_field *field, int first_unit)
{
    for (size_t i = 0; i < halo_program_reflection(p).sampler_count; ++i)
        for (int s = 0; s < field->stack_count; ++s)
            if (!strcmp(field->stacks[s].image, halo_program_reflection(p).samplers[i].image)) {
                f->ActiveTexture(GL_TEXTURE0 + (GLenum)(first_unit + (int)i));
                f->BindTexture(GL_TEXTURE_2D_ARRAY, field->stacks[s].texture);
            }
}

/* At least `layers` layers in every stack (a quarter more, so that a moving camera does not
 * reallocate every frame, where the cap on their bytes allows); a new layer's content is
 * unknown: its box is the whole image. 1; 0 out of memory; -1 over max_bytes (FIELD_MEMORY,
 * with what would fit). */
static int field_reserve(const halo_glfuncs *f, const halo_program *p, halo_gl_field *field, int layers, int cap,
                         size_t max_bytes, size_t seed_per_layer, halo_diagnostics *diag)
{
    size_t per_layer = seed_per_layer; /* the exchange's seed stacks, when there is one */
    for (int s = 0; s < field->stack_count; ++s)
        per_layer += (size_t)field->stacks[s].width * (size_t)field->stacks[s].height *
                     halo_gl_image_texel_bytes(field->stacks[s].internal_format);
    if (per_layer > 0 && (size_t)layers > max_bytes / per_layer) {
        int scale = halo_program_reflection(p).image_scale > 1 ? halo_program_reflection(p).image_scale : 1;
        double mib = 1.0 / (1024.0 * 1024.0), need = (double)layers * (double)per_layer;
        char fits[160] = "";
        for (int smaller = scale * 2; smaller <= 4 && !fits[0]; smaller *= 2)
            if (need * scale * scale / ((double)smaller * smaller) <= (double)max_bytes)
                snprintf(fits, sizeof fits, "halo_link_desc.image_scale %d fits (about %.3g MiB); ", smaller,
                         need * mib * scale * scale / ((double)smaller * smaller));
        halo_diag_error(diag, FIELD_MEMORY, "", 0, 0,
                        "halo_gl_frame_draw: the halo field of %d layers (a depth segment each, but the last) needs "
                        "%.3g MiB (%zu bytes a layer: %d image%s at %dx%d%s), over field_max_bytes %.3g MiB; %sa "
                        "larger halo_generate.interval (M) has fewer segments, or raise field_max_bytes",
                        layers, need * mib, per_layer, field->stack_count, field->stack_count == 1 ? "" : "s",
                        field->stacks[0].width, field->stacks[0].height,
                        seed_per_layer ? ", and the exchange's seeds" : "", (double)max_bytes * mib, fits);
        return -1;
    }
    if (layers <= field->layers)
        return 1;
    int count = cap > 0 ? cap : layers + layers / 4;
    if (per_layer > 0 && (size_t)count > max_bytes / per_layer)
        count = (int)(max_bytes / per_layer); /* >= layers (above) */
    for (int s = 0; s < field->stack_count; ++s) {
        field_stack *st = &field->stacks[s];
        int(*boxes)[4] = realloc(st->boxes, (size_t)count * sizeof *boxes);
        if (!boxes) {
            halo_diag_error(diag, OUT_OF_MEMORY, "", 0, 0, "out of memory for the stack of image '%s'", st->image);
            return 0;
        }
        st->boxes = boxes;
        for (int k = 0; k < count; ++k) {
            boxes[k][0] = boxes[k][1] = 0;
            boxes[k][2] = st->width;
            boxes[k][3] = st->height;
        }
        GLenum format, type;
        halo_gl_image_upload_format(st->internal_format, &format, &type);
        if (!st->texture)
            f->GenTextures(1, &st->texture);
        f->BindTexture(GL_TEXTURE_2D_ARRAY, st->texture);
        /* a 1/s image's layers are read through the filter (emit.c), within a layer */
        GLint filter = halo_program_image_filtered(p, halo_program_image_named((halo_program *)p, st->image))
                           ? GL_LINEAR
                           : GL_NEAREST;
        f->TexParameteri(GL_TEXTURE_2D_ARRAY, GL_TEXTURE_MIN_FILTER, filter);
        f->TexParameteri(GL_TEXTURE_2D_ARRAY, GL_TEXTURE_MAG_FILTER, filter);
        f->TexParameteri(GL_TEXTURE_2D_ARRAY, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
        f->TexParameteri(GL_TEXTURE_2D_ARRAY, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
        f->TexImage3D(GL_TEXTURE_2D_ARRAY, 0, st->internal_format, st->width, st->height, count, 0, format, type, NULL);
    }
    if (f->GetError() != GL_NO_ERROR) {
        halo_diag_error(diag, GL_LINK, "", 0, 0, "the stacks of %d depth segments (%dx%d) could not be allocated",
                        count, field->stack_count ? field->stacks[0].width : 0,
                        field->stack_count ? field->stacks[0].height : 0);
        return 0;
    }
    field->layers = count;
    return 1;
}

/* The pixels (x0, y0, x1, y1) where the box's part with lo <= phi <= hi projects, grown by
 * one pixel; the whole frame when a point lies behind the eye; empty (0) when the part is. */
static int segment_footprint(const double view_projection[16], const halo_segment_plan *plan, const double low[3],
                             const double high[3], double lo, double hi, int width, int height, int box[4])
{
    double corners[8][3], phi[8];
    for (int c = 0; c < 8; ++c) {
        phi[c] = plan->plane[3];
        for (int k = 0; k < 3; ++k) {
            corners[c][k] = (c >> k) & 1 ? high[k] : low[k];
            phi[c] += plan->plane[k] * corners[c][k];
        }
    }
    double points[8 + 24][3];
    int n = 0;
    for (int c = 0; c < 8; ++c) {
        if (phi[c] >= lo && phi[c] <= hi)
            memcpy(points[n++], corners[c], sizeof points[0]);
        for (int k = 0; k < 3; ++k) { /* the edge from c along axis k */
            int d = c | (1 << k);
            if (d == c)
                continue;
            const double bounds[2] = {lo, hi};
            for (int b = 0; b < 2; ++b)
                if ((phi[c] - bounds[b]) * (phi[d] - bounds[b]) < 0.0) {
                    double t = (bounds[b] - phi[c]) / (phi[d] - phi[c]);
                    for (int a = 0; a < 3; ++a)
                        points[n][a] = corners[c][a] + t * (corners[d][a] - corners[c][a]);
                    ++n;
                }
        }
    }
    if (n == 0)
        return 0;
    double x0 = INFINITY, y0 = INFINITY, x1 = -INFINITY, y1 = -INFINITY;
    for (int i = 0; i < n; ++i) {
        double clip[4];
        for (int r = 0; r < 4; ++r)
            clip[r] = view_projection[r] * points[i][0] + view_projection[4 + r] * points[i][1] +
                      view_projection[8 + r] * points[i][2] + view_projection[12 + r];
        if (!(clip[3] > 1e-12)) {
            box[0] = box[1] = 0;
            box[2] = width;
            box[3] = height;
            return 1;
        }
        double x = (clip[0] / clip[3] * 0.5 + 0.5) * width, y = (clip[1] / clip[3] * 0.5 + 0.5) * height;
        x0 = x < x0 ? x : x0;
        x1 = x > x1 ? x : x1;
        y0 = y < y0 ? y : y0;
        y1 = y > y1 ? y : y1;
    }
    x0 = floor(x0) - 1.0, y0 = floor(y0) - 1.0, x1 = ceil(x1) + 1.0, y1 = ceil(y1) + 1.0;
    box[0] = x0 < 0.0 ? 0 : x0 > width ? width : (int)x0;
    box[1] = y0 < 0.0 ? 0 : y0 > height ? height : (int)y0;
    box[2] = x1 < 0.0 ? 0 : x1 > width ? width : (int)x1;
    box[3] = y1 < 0.0 ? 0 : y1 > height ? height : (int)y1;
    return box[0] < box[2] && box[1] < box[3];
}

/* A program of libhalo's full-screen vertex shader and a fragment body (its version line
 * that of the march); 0 after a diagnostic. */
static GLuint field_program(const halo_glfuncs *f, const halo_program *march, const char *body, const char *file,
                            halo_diagnostics *diag)
{
    int es = march->target == HALO_TARGET_ES300;
    char source[2048];
    snprintf(source, sizeof source, "%s%s",
             es ? "#version 300 es\nprecision highp float;\nprecision highp int;\nprecision highp sampler3D;\n"
                : "#version 330 core\n",
             body);
    GLuint vertex = halo_gl_compile_mapped(f, GL_VERTEX_SHADER, es ? march_vertex_es300 : march_vertex_330, NULL, NULL,
                                           0, file, diag);
    GLuint fragment = halo_gl_compile_mapped(f, GL_FRAGMENT_SHADER, source, NULL, NULL, 0, file, diag);
    GLuint program = halo_gl_program_attach(f, vertex, fragment, file, diag);
    return program ? halo_gl_link_attached(f, program, vertex, fragment, file, "the driver could not link it", diag)
                   : 0;
}

/* A 3D texture of size[3] (internal format, linear or nearest) written layer by layer by
 * program, whose uniform `layer` (at layer_location) says which. */
static void field_draw_layers(const halo_glfuncs *f, halo_gl_field *field, GLuint *texture, GLint internal,
                              GLenum filter, const int size[3], int allocate, GLuint program, GLint layer_location)
{
    if (allocate) {
        if (!*texture)
            f->GenTextures(1, texture);
        f->BindTexture(GL_TEXTURE_3D, *texture);
        f->TexParameteri(GL_TEXTURE_3D, GL_TEXTURE_MIN_FILTER, (GLint)filter);
        f->TexParameteri(GL_TEXTURE_3D, GL_TEXTURE_MAG_FILTER, (GLint)filter);
        f->TexParameteri(GL_TEXTURE_3D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
        f->TexParameteri(GL_TEXTURE_3D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
        f->TexParameteri(GL_TEXTURE_3D, GL_TEXTURE_WRAP_R, GL_CLAMP_TO_EDGE);
        f->TexImage3D(GL_TEXTURE_3D, 0, internal, size[0], size[1], size[2], 0, internal == GL_R32F ? GL_RED : GL_RGBA,
                      GL_FLOAT, NULL);
    }
    f->UseProgram(program);
    f->BindFramebuffer(GL_DRAW_FRAMEBUFFER, field->framebuffer);
    GLenum buffer = GL_COLOR_ATTACHMENT0;
    f->DrawBuffers(1, &buffer);
    f->Viewport(0, 0, size[0], size[1]);
    f->BindVertexArray(field->vertex_array);
    for (int z = 0; z < size[2]; ++z) {
        f->FramebufferTextureLayer(GL_DRAW_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, *texture, 0, z);
        f->Uniform1i(layer_location, z);
        f->DrawArrays(GL_TRIANGLES, 0, 3);
    }
    f->FramebufferTextureLayer(GL_DRAW_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, 0, 0, 0);
}

/* The bricks of gradient (bound to unit + 1 as march_gradient is), kept while it is. */
static GLuint field_bricks(const halo_glfuncs *f, halo_gl_field *field, const halo_program *march, GLuint gradient,
                           const int size[3], int version, int unit, halo_diagnostics *diag)
{
    field_gradient *g = &field->gradient;
    int bricks[3] = {(size[0] + 3) / 4, (size[1] + 3) / 4, (size[2] + 3) / 4};
    if (g->bricks_valid && g->bricks_of == gradient && g->bricks_version == version &&
        !memcmp(g->brick_size, bricks, sizeof bricks))
        return g->bricks;
    if (!g->brick_program) {
        g->brick_program = field_program(f, march, brick_fragment_body, "(libhalo's empty-space bricks)", diag);
        if (!g->brick_program)
            return 0;
        g->brick_gradient = f->GetUniformLocation(g->brick_program, "gradient");
        g->brick_layer = f->GetUniformLocation(g->brick_program, "layer");
    }
    f->ActiveTexture(GL_TEXTURE0 + (GLenum)unit + 1);
    f->BindTexture(GL_TEXTURE_3D, gradient);
    f->UseProgram(g->brick_program);
    f->Uniform1i(g->brick_gradient, unit + 1);
    f->ActiveTexture(GL_TEXTURE0 + (GLenum)unit + 2);
    field_draw_layers(f, field, &g->bricks, GL_R32F, GL_NEAREST, bricks,
                      !g->bricks || memcmp(g->brick_size, bricks, sizeof bricks), g->brick_program, g->brick_layer);
    g->bricks_of = gradient;
    g->bricks_version = version;
    memcpy(g->brick_size, bricks, sizeof bricks);
    g->bricks_valid = 1;
    return g->bricks;
}

/* The gradient texture the march reads: the host's, or one derived from its volume (bound
 * at unit); 0 after a diagnostic. */
/* The volume's voxels per axis: the desc's, or queried; 0 after a diagnostic. */
static int field_volume_size(const halo_glfuncs *f, const halo_gl_segments_desc *d, int unit, int size[3],
                             halo_diagnostics *diag)
{
    memcpy(size, d->volume_size, 3 * sizeof *size);
    if (size[0] < 1 || size[1] < 1 || size[2] < 1) {
        size[0] = size[1] = size[2] = 0;
        f->ActiveTexture(GL_TEXTURE0 + (GLenum)unit);
        f->BindTexture(GL_TEXTURE_3D, d->volume_texture);
        if (f->GetTexLevelParameteriv) {
            f->GetTexLevelParameteriv(GL_TEXTURE_3D, 0, GL_TEXTURE_WIDTH, &size[0]);
            f->GetTexLevelParameteriv(GL_TEXTURE_3D, 0, GL_TEXTURE_HEIGHT, &size[1]);
            f->GetTexLevelParameteriv(GL_TEXTURE_3D, 0, GL_TEXTURE_DEPTH, &size[2]);
        }
    }
    if (size[0] >= 1 && size[1] >= 1 && size[2] >= 1 && size[0] <= 16384 && size[1] <= 16384 && size[2] <= 16384)
        return 1;
    halo_diag_error(diag, USAGE, "", 0, 0,
                    "halo_gl_frame_draw: the size of desc.volume_texture is unknown (%dx%dx%d): give "
                    "desc.volume_size (a context without glGetTexLevelParameteriv, such as OpenGL ES 3.0)",
                    size[0], size[1], size[2]);
    return 0;
}

static GLuint field_gradient_texture(const halo_glfuncs *f, halo_gl_field *field, const halo_program *march,
                                     const halo_gl_segments_desc *d, const int size[3], int unit, GLint internal,
                                     halo_diagnostics *diag)
{
    if (d->gradient_texture)
        return d->gradient_texture;
    field_gradient *g = &field->gradient;
    f->ActiveTexture(GL_TEXTURE0 + (GLenum)unit);
    f->BindTexture(GL_TEXTURE_3D, d->volume_texture);
    if (g->valid && g->of == d->volume_texture && g->version == d->volume_version && g->internal_format == internal &&
        !memcmp(g->size, size, sizeof g->size))
        return g->texture;
    if (!g->program) {
        g->program = field_program(f, march, gradient_fragment_body, "(libhalo's gradient of the host's volume)", diag);
        if (!g->program)
            return 0;
        g->volume = f->GetUniformLocation(g->program, "volume");
        g->layer = f->GetUniformLocation(g->program, "layer");
    }
    f->UseProgram(g->program);
    f->Uniform1i(g->volume, unit);
    f->ActiveTexture(GL_TEXTURE0 + (GLenum)unit + 1);
    field_draw_layers(f, field, &g->texture, internal, GL_LINEAR, size,
                      !g->texture || g->internal_format != internal || memcmp(g->size, size, sizeof g->size),
                      g->program, g->layer);
    g->internal_format = internal;
    g->bricks_valid = 0; /* the skip's bricks are of the gradient in use */
    f->ActiveTexture(GL_TEXTURE0 + (GLenum)unit);
    g->of = d->volume_texture;
    g->version = d->volume_version;
    memcpy(g->size, size, sizeof g->size);
    g->valid = 1;
    return g->texture;
}

/* The largest |gradient| below which a sample's seed is at most epsilon in every channel:
 * s <= min(1, g gradient_scale)^alpha (h_v, h_d, h_p and the contour term are at most 1,
 * docs/stages/halo_seed.md), so g <= epsilon^(1/alpha) / gradient_scale; with epsilon 0,
 * the gradient stage's own zero (|gradient| <= 1e-10: no normal, no seed), exact. */
static float field_skip_bound(const halo_program *march, float epsilon)
{
    const double exact = 1e-10;
    if (!(epsilon > 0.0f) || !isfinite(epsilon))
        return (float)exact;
    const halo_uniform_info *alpha = halo_program_find_uniform(march, "halo_seed", "alpha");
    const halo_uniform_info *scale = halo_program_find_uniform(march, "halo_seed", "gradient_scale");
    if (!alpha || !scale || !alpha->value || !scale->value || alpha->count < 1 || scale->count < 1)
        return (float)exact;
    double bound = INFINITY;
    for (int h = 0; h < halo_program_reflection(march).channel_count; ++h) {
        double a = alpha->value[h < alpha->count ? h : alpha->count - 1];
        double k = scale->value[h < scale->count ? h : scale->count - 1];
        double g = !(a > 0.0) ? exact : !(k > 0.0) ? INFINITY : pow((double)epsilon, 1.0 / a) / k;
        bound = g < bound ? g : bound;
    }
    return (float)(bound > exact ? bound : exact);
}

/* The march's host uniforms. The seeding stages no longer run in the host's program, so
 * what the host set there (halo_gl_set_host_uniform) is gone with them: the image-plane
 * axes the contract defines (halo_host_screen_right, _up: unit, in the space of the
 * positions) are derived from the camera, the directions clip +x and +y map to; a march
 * with another host uniform is refused at link time (prepass.c). */
static void field_host_uniforms(const halo_glfuncs *f, const halo_gl_segments_desc *d, GLuint march)
{
    static const char *const axes[2] = {"halo_host_screen_right", "halo_host_screen_up"};
    for (int a = 0; a < 2; ++a) {
        double v[3], length = 0.0;
        for (int k = 0; k < 3; ++k) { /* column a of the inverse: clip (1, 0, 0, 0) or (0, 1, 0, 0) */
            v[k] = d->inverse_view_projection[4 * a + k];
            length += v[k] * v[k];
        }
        length = length > 0.0 ? sqrt(length) : 1.0;
        f->Uniform3f(f->GetUniformLocation(march, axes[a]), (float)(v[0] / length), (float)(v[1] / length),
                     (float)(v[2] / length));
    }
}

/* The images the samples read, after segment j's generation, into layer j of their stacks. */
static void field_store(const halo_glfuncs *f, halo_gl_frame *fr, halo_gl_field *field, int layer)
{
    for (int s = 0; s < field->stack_count; ++s) {
        field_stack *st = &field->stacks[s];
        halo_gl_frame_image view;
        if (!halo_gl_frame_image_view(fr, st->image, &view))
            continue;
        int *old = st->boxes[layer], copy[4];
        int fresh = view.box[0] < view.box[2] && view.box[1] < view.box[3];
        int stale = old[0] < old[2] && old[1] < old[3];
        if (!fresh && !stale)
            continue;
        for (int k = 0; k < 4; ++k)
            copy[k] = !stale   ? view.box[k]
                      : !fresh ? old[k]
                      : k < 2  ? (view.box[k] < old[k] ? view.box[k] : old[k])
                               : (view.box[k] > old[k] ? view.box[k] : old[k]);
        f->FramebufferTexture2D(GL_READ_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, view.texture, 0);
        f->ReadBuffer(GL_COLOR_ATTACHMENT0);
        f->BindTexture(GL_TEXTURE_2D_ARRAY, st->texture);
        f->CopyTexSubImage3D(GL_TEXTURE_2D_ARRAY, 0, copy[0], copy[1], layer, copy[0], copy[1], copy[2] - copy[0],
                             copy[3] - copy[1]);
        memcpy(old, view.box, sizeof view.box);
    }
    f->FramebufferTexture2D(GL_READ_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, 0, 0);
}

/* The GL state field_compute changes, saved and restored around it: the host's
 * (halo_gl_state, made neutral for the march) and the textures of the units it binds. */
typedef struct field_saved {
    halo_gl_state state;
    GLint texture_3d[3], texture_array, texture_2d;
} field_saved;

static void field_save(const halo_glfuncs *f, field_saved *s, int unit)
{
    halo_gl_state_save(f, &s->state);
    for (int k = 0; k < 3; ++k) {
        f->ActiveTexture(GL_TEXTURE0 + (GLenum)(unit + k));
        f->GetIntegerv(GL_TEXTURE_BINDING_3D, &s->texture_3d[k]);
    }
    f->ActiveTexture(GL_TEXTURE0 + (GLenum)unit);
    f->GetIntegerv(GL_TEXTURE_BINDING_2D_ARRAY, &s->texture_array);
    f->GetIntegerv(GL_TEXTURE_BINDING_2D, &s->texture_2d); /* the seeds' copies bind there */
    f->ActiveTexture((GLenum)s->state.bindings.active_texture);
    halo_gl_state_neutral(f, &s->state);
}

static void field_restore(const halo_glfuncs *f, const field_saved *s, int unit)
{
    for (int k = 0; k < 3; ++k) {
        f->ActiveTexture(GL_TEXTURE0 + (GLenum)(unit + k));
        f->BindTexture(GL_TEXTURE_3D, (GLuint)s->texture_3d[k]);
    }
    f->ActiveTexture(GL_TEXTURE0 + (GLenum)unit);
    f->BindTexture(GL_TEXTURE_2D_ARRAY, (GLuint)s->texture_array);
    f->BindTexture(GL_TEXTURE_2D, (GLuint)s->texture_2d);
    halo_gl_state_restore(f, &s->state); /* the active unit too */
}

/* The planes of segment j: [first, end) of the plan's planes front + k step. */
static void segment_planes(const halo_segment_plan *plan, double step, int j, int planes, int *first, int *end)
{
    /* segment j holds the planes with phi in [start + j length, start + (j + 1) length),
     * start = front - step / 2 (segments.c) */
    double a = ceil(j * plan->length / step - 0.5 - 1e-9), b = ceil((j + 1) * plan->length / step - 0.5 - 1e-9);
    *first = a < 0.0 ? 0 : a > planes ? planes : (int)a;
    *end = b < 0.0 ? 0 : b > planes ? planes : (int)b;
}

/* The piece's part of the box (halo_gl_segments_desc.piece_min, _max): the map from ray
 * positions to its volume texture, and where its march samples: from its first point's
 * centre to its last's, out to the box where the piece reaches the box's face (pieces
 * share their boundary points, so the pieces' samples cover the box; a sample on a shared
 * face is taken by both, its value the same, its gradient one-sided in each, as no piece
 * has the other's points: the max keeps the larger seed). 0 with USAGE for a bad box. */
static int field_piece(const halo_gl_segments_desc *d, const double low[3], const double high[3], const int voxels[3],
                       double sample_low[3], double sample_high[3], float piece_min[3], float piece_scale[3],
                       halo_diagnostics *diag)
{
    int piece = 0;
    for (int k = 0; k < 3; ++k)
        piece |= d->piece_min[k] != 0.0f || d->piece_max[k] != 0.0f;
    for (int k = 0; k < 3; ++k) {
        piece_min[k] = 0.0f;
        piece_scale[k] = 1.0f;
        sample_low[k] = low[k];
        sample_high[k] = high[k];
        if (!piece)
            continue;
        double a = d->piece_min[k], b = d->piece_max[k];
        if (!(b > a) || !isfinite(a) || !isfinite(b)) {
            halo_diag_error(diag, USAGE, "", 0, 0,
                            "halo_gl_frame_draw: piece_min and piece_max must bound a box (axis %d: %g to %g)", k, a,
                            b);
            return 0;
        }
        double half = (b - a) / (2.0 * voxels[k]), tolerance = 1e-6 * (high[k] - low[k]);
        piece_min[k] = (float)a;
        piece_scale[k] = (float)(1.0 / (b - a));
        sample_low[k] = a > low[k] + tolerance ? a + half : low[k];
        sample_high[k] = b < high[k] - tolerance ? b - half : high[k];
    }
    return 1;
}

/* The seeds of every segment, for the exchange across pieces (exchange 1), or of a batch
 * of segments (field_batches): one array texture a seed image (the march's outputs), with
 * at least `layers` layers. */
static int field_seed_reserve(const halo_glfuncs *f, halo_gl_frame *fr, halo_gl_field *field, const halo_program *march,
                              int layers, int exchange, halo_diagnostics *diag)
{
    size_t n = halo_program_reflection(march).output_count;
    for (size_t i = 0; i < n && i < FIELD_MAX_STACKS; ++i) {
        halo_gl_frame_image view;
        if (!halo_gl_frame_image_view(fr, halo_program_reflection(march).outputs[i].image, &view))
            continue;
        if (exchange && halo_gl_es_version(halo_gl_frame_runtime(fr)) > 0 && view.internal_format != GL_RGBA32F &&
            view.internal_format != GL_RGBA16F) {
            /* the exchange reads and writes RGBA floats: OpenGL ES takes them for RGBA images only */
            halo_diag_error(diag, USAGE, "", 0, 0,
                            "halo_gl_frame_draw: the seeds' exchange on OpenGL ES needs RGBA float seed images, "
                            "not this program's (more halo channels or 32/16-bit images)");
            return 0;
        }
        if (layers <= field->seed_layers)
            continue; /* (a batch's stack, grown for an exchange, or the other way round) */
        GLenum format, type;
        halo_gl_image_upload_format(view.internal_format, &format, &type);
        if (!field->seed_stacks[i])
            f->GenTextures(1, &field->seed_stacks[i]);
        f->BindTexture(GL_TEXTURE_2D_ARRAY, field->seed_stacks[i]);
        f->TexParameteri(GL_TEXTURE_2D_ARRAY, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
        f->TexParameteri(GL_TEXTURE_2D_ARRAY, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
        f->TexImage3D(GL_TEXTURE_2D_ARRAY, 0, view.internal_format, view.width, view.height, layers, 0, format, type,
                      NULL);
        field->seed_stack_bytes[i] =
            (size_t)view.width * (size_t)view.height * (size_t)layers * halo_gl_image_texel_bytes(view.internal_format);
    }
    if (f->GetError() != GL_NO_ERROR) {
        halo_diag_error(diag, GL_LINK, "", 0, 0, "the seeds of %d depth segments could not be allocated", layers);
        return 0;
    }
    if (layers > field->seed_layers)
        field->seed_layers = layers;
    return 1;
}

/* Copies the march's seed images into (to_stack) or out of layer j of their seed stacks:
 * the whole image, or (out of the stack) within box (x0 y0 x1 y1 of the seed image). */
static void field_seed_copy(const halo_glfuncs *f, halo_gl_frame *fr, halo_gl_field *field, const halo_program *march,
                            int j, int to_stack, const int box[4])
{
    size_t n = halo_program_reflection(march).output_count;
    for (size_t i = 0; i < n && i < FIELD_MAX_STACKS; ++i) {
        halo_gl_frame_image view;
        if (!field->seed_stacks[i] ||
            !halo_gl_frame_image_view(fr, halo_program_reflection(march).outputs[i].image, &view))
            continue;
        if (to_stack) {
            f->FramebufferTexture2D(GL_READ_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, view.texture, 0);
            f->ReadBuffer(GL_COLOR_ATTACHMENT0);
            f->BindTexture(GL_TEXTURE_2D_ARRAY, field->seed_stacks[i]);
            f->CopyTexSubImage3D(GL_TEXTURE_2D_ARRAY, 0, 0, 0, j, 0, 0, view.width, view.height);
        } else {
            f->FramebufferTextureLayer(GL_READ_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, field->seed_stacks[i], 0, j);
            f->ReadBuffer(GL_COLOR_ATTACHMENT0);
            f->BindTexture(GL_TEXTURE_2D, view.texture);
            int all[4] = {0, 0, view.width, view.height};
            const int *b = box ? box : all;
            f->CopyTexSubImage2D(GL_TEXTURE_2D, 0, b[0], b[1], b[0], b[1], b[2] - b[0], b[3] - b[1]);
            f->BindTexture(GL_TEXTURE_2D, 0);
        }
    }
    f->FramebufferTexture2D(GL_READ_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, 0, 0);
}

/* The seeds of every segment combined across the pieces: read back, the host's exchange,
 * uploaded again. */
static int field_seed_exchange(const halo_glfuncs *f, halo_gl_frame *fr, halo_gl_field *field,
                               const halo_program *march, const halo_gl_segments_desc *d, int layers,
                               halo_diagnostics *diag)
{
    size_t n = halo_program_reflection(march).output_count;
    for (size_t i = 0; i < n && i < FIELD_MAX_STACKS; ++i) {
        halo_gl_frame_image view;
        if (!field->seed_stacks[i] ||
            !halo_gl_frame_image_view(fr, halo_program_reflection(march).outputs[i].image, &view))
            continue;
        size_t layer = (size_t)view.width * (size_t)view.height * 4;
        /* layers in groups of at most exchange_max_bytes (at least one a call) */
        size_t cap = d->exchange_max_bytes ? d->exchange_max_bytes : HALO_GL_EXCHANGE_MAX_BYTES;
        size_t group = cap / (layer * sizeof(float));
        group = group < 1 ? 1 : group > (size_t)layers ? (size_t)layers : group;
        size_t count = layer * group;
        if (count > field->exchange_size) {
            float *grown = realloc(field->exchange_buffer, count * sizeof *grown);
            if (!grown) {
                halo_diag_error(diag, OUT_OF_MEMORY, "", 0, 0, "out of memory for the seeds of %d segments", layers);
                return 0;
            }
            field->exchange_buffer = grown;
            field->exchange_size = count;
        }
        f->PixelStorei(GL_PACK_ALIGNMENT, 4);
        f->PixelStorei(GL_UNPACK_ALIGNMENT, 4);
        for (int first = 0; first < layers; first += (int)group) {
            int k = layers - first < (int)group ? layers - first : (int)group;
            for (int j = 0; j < k; ++j) {
                f->FramebufferTextureLayer(GL_READ_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, field->seed_stacks[i], 0,
                                           first + j);
                f->ReadBuffer(GL_COLOR_ATTACHMENT0);
                f->ReadPixels(0, 0, view.width, view.height, GL_RGBA, GL_FLOAT,
                              field->exchange_buffer + (size_t)j * layer);
            }
            f->FramebufferTexture2D(GL_READ_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, 0, 0);
            d->exchange(d->exchange_user, field->exchange_buffer, layer * (size_t)k,
                        halo_program_reflection(march).outputs[i].blend);
            f->BindTexture(GL_TEXTURE_2D_ARRAY, field->seed_stacks[i]);
            f->TexSubImage3D(GL_TEXTURE_2D_ARRAY, 0, 0, 0, first, view.width, view.height, k, GL_RGBA, GL_FLOAT,
                             field->exchange_buffer);
        }
    }
    return 1;
}

/* What a march program reads, set on it (which becomes current): the samplers on units
 * unit .. unit + 2, the camera, the box, the planes. */
static void march_setup(halo_gl_frame *fr, const halo_gl_segments_desc *d, const halo_segment_plan *plan, GLuint march,
                        const march_locations *at, int unit, GLuint gradient, GLuint bricks, const double sample_low[3],
                        const double sample_high[3], const float piece_min[3], const float piece_scale[3])
{
    halo_gl *gl = halo_gl_frame_runtime(fr);
    const halo_glfuncs *f = halo_gl_functions(gl);
    const halo_program *p = halo_gl_frame_program(fr);
    int width, height;
    halo_gl_frame_size(fr, &width, &height);
    f->UseProgram(march);
    halo_gl_program_upload(gl, p->prepass, march);
    halo_segment_camera_set(f, march, plan);
    f->ActiveTexture(GL_TEXTURE0 + (GLenum)unit);
    f->BindTexture(GL_TEXTURE_3D, d->volume_texture);
    f->Uniform1i(at->volume, unit);
    f->ActiveTexture(GL_TEXTURE0 + (GLenum)unit + 1);
    f->BindTexture(GL_TEXTURE_3D, gradient);
    f->Uniform1i(at->gradient_sampler, unit + 1);
    f->ActiveTexture(GL_TEXTURE0 + (GLenum)unit + 2);
    f->BindTexture(GL_TEXTURE_3D, bricks);
    f->Uniform1i(at->bricks_sampler, unit + 2);
    f->Uniform1f(at->skip, field_skip_bound(p->prepass, d->seed_epsilon));
    field_host_uniforms(f, d, march);
    f->UniformMatrix4fv(at->matrix, 1, GL_FALSE, d->inverse_view_projection);
    f->Uniform2f(at->viewport, (float)width, (float)height);
    /* the march at the seed images' scale (the halo images', halo_link_desc.image_scale): a
     * ray through the centre of each 1/s pixel */
    int s = halo_program_reflection(p).image_scale > 1 ? halo_program_reflection(p).image_scale : 1;
    f->Uniform1f(at->scale, (float)s);
    f->Uniform3f(at->box_min, (float)sample_low[0], (float)sample_low[1], (float)sample_low[2]);
    f->Uniform3f(at->box_max, (float)sample_high[0], (float)sample_high[1], (float)sample_high[2]);
    f->Uniform3fv(at->piece_min, 1, piece_min);
    f->Uniform3fv(at->piece_scale, 1, piece_scale);
    f->Uniform4f(at->plane, (float)plan->plane[0], (float)plan->plane[1], (float)plan->plane[2], (float)plan->plane[3]);
    f->Uniform2f(at->planes, (float)plan->front, d->step);
}

/* Segment j's planes [first, end) and where its seeds can be nonzero (box: frame pixels,
 * x0 y0 x1 y1; all 0 when nowhere) for a march over [low, high]. */
static void segment_reach(const halo_gl_frame *fr, const halo_gl_segments_desc *d, const halo_segment_plan *plan,
                          const double view_projection[16], const double low[3], const double high[3], int planes,
                          int j, int *first, int *end, int box[4])
{
    int width, height;
    halo_gl_frame_size(fr, &width, &height);
    segment_planes(plan, d->step, j, planes, first, end);
    double lo = plan->front + *first * (double)d->step, hi = plan->front + (*end - 1) * (double)d->step;
    double slack = 1e-6 * (plan->back - plan->front);
    box[0] = box[1] = box[2] = box[3] = 0;
    if (!(*end > *first &&
          segment_footprint(view_projection, plan, low, high, lo - slack, hi + slack, width, height, box)))
        box[0] = box[1] = box[2] = box[3] = 0;
}

/* Generation j of the frame: its seeds (in the frame's seed image), the passes, the stacks. */
static void field_generate(const halo_glfuncs *f, halo_gl_frame *fr, halo_gl_field *field, int unit, int j,
                           const int box[4])
{
    halo_gl_frame_drawn_region(fr, box[0], box[1], box[2], box[3]);
    halo_gl_frame_generate(fr);
    f->BindFramebuffer(GL_READ_FRAMEBUFFER, field->framebuffer);
    f->ActiveTexture(GL_TEXTURE0 + (GLenum)unit);
    field_store(f, fr, field, j);
}

/* The batched march (field->batch): the seeds of FIELD_BATCH segments a draw into the layers
 * of the seed stack (segment b of a draw to draw buffer 0 for b = 0, b + 1 for b = 1 .. 6, and
 * 1 for the last, through the linked seed output: prepass.c),
 * then those segments' generations, each from a copy of its layer; front to back. */
static void field_batches(halo_gl_frame *fr, const halo_gl_segments_desc *d, const halo_segment_plan *plan,
                          const double view_projection[16], const double low[3], const double high[3], int planes,
                          int unit)
{
    halo_gl *gl = halo_gl_frame_runtime(fr);
    const halo_glfuncs *f = halo_gl_functions(gl);
    const halo_program *p = halo_gl_frame_program(fr);
    halo_gl_field *field = halo_gl_frame_field(fr);
    int s = halo_program_reflection(p).image_scale > 1 ? halo_program_reflection(p).image_scale : 1;
    int width, height;
    halo_gl_frame_size(fr, &width, &height);
    for (int j0 = 0; j0 + 1 < plan->segments; j0 += FIELD_BATCH) {
        /* the generations of the previous batch used the framebuffer and changed the state */
        f->UseProgram(field->batch);
        f->BindFramebuffer(GL_DRAW_FRAMEBUFFER, field->framebuffer);
        f->Viewport(0, 0, (width + s - 1) / s, (height + s - 1) / s);
        f->Disable(GL_BLEND); /* each pixel of a layer is written once, by its ray */
        f->BindVertexArray(field->vertex_array);
        GLint ranges[2 * FIELD_BATCH] = {0};
        GLenum buffers[FIELD_BATCH];
        int boxes[FIELD_BATCH][4] = {{0}}, all[4] = {0, 0, 0, 0};
        for (int b = 0; b < FIELD_BATCH; ++b) {
            int j = j0 + b, location = b == FIELD_BATCH - 1 ? 1 : b == 0 ? 0 : b + 1, *box = boxes[b];
            GLenum attachment = GL_COLOR_ATTACHMENT0 + (GLenum)location;
            buffers[location] = GL_NONE;
            if (j + 1 >= plan->segments) {
                f->FramebufferTexture2D(GL_DRAW_FRAMEBUFFER, attachment, GL_TEXTURE_2D, 0, 0);
                continue;
            }
            segment_reach(fr, d, plan, view_projection, low, high, planes, j, &ranges[2 * b], &ranges[2 * b + 1], box);
            f->FramebufferTextureLayer(GL_DRAW_FRAMEBUFFER, attachment, field->seed_stacks[0], 0, b);
            buffers[location] = attachment;
            if (box[0] < box[2] && box[1] < box[3]) {
                int empty = !(all[0] < all[2] && all[1] < all[3]);
                for (int k = 0; k < 4; ++k)
                    all[k] = empty   ? box[k]
                             : k < 2 ? (box[k] < all[k] ? box[k] : all[k])
                                     : (box[k] > all[k] ? box[k] : all[k]);
            }
        }
        if (all[0] < all[2] && all[1] < all[3]) {
            f->DrawBuffers(FIELD_BATCH, buffers);
            f->Uniform2iv(field->batch_at.range, FIELD_BATCH, ranges);
            f->Enable(GL_SCISSOR_TEST);
            /* the 1/s pixels whose blocks meet the footprints */
            int x0 = all[0] / s, y0 = all[1] / s, x1 = (all[2] + s - 1) / s, y1 = (all[3] + s - 1) / s;
            f->Scissor(x0, y0, x1 - x0, y1 - y0);
            f->DrawArrays(GL_TRIANGLES, 0, 3);
            f->Disable(GL_SCISSOR_TEST);
        }
        for (int b = 0; b < FIELD_BATCH; ++b)
            f->FramebufferTexture2D(GL_DRAW_FRAMEBUFFER, GL_COLOR_ATTACHMENT0 + (GLenum)b, GL_TEXTURE_2D, 0, 0);
        for (int b = 0; field->atlas && b < FIELD_BATCH && j0 + b + 1 < plan->segments; ++b) {
            const int *box = boxes[b];
            int seed_box[4] = {box[0] / s, box[1] / s, (box[2] + s - 1) / s, (box[3] + s - 1) / s};
            halo_gl_field_atlas_seed(field->atlas, j0 + b, field->seed_stacks[0], b, seed_box);
        }
        for (int b = 0; !field->atlas && b < FIELD_BATCH && j0 + b + 1 < plan->segments; ++b) {
            const int *box = boxes[b];
            f->BindFramebuffer(GL_READ_FRAMEBUFFER, field->framebuffer);
            f->ActiveTexture(GL_TEXTURE0 + (GLenum)unit);
            if (box[0] < box[2] && box[1] < box[3]) {
                /* the layer's seeds where the segment can have any (the rest of the layer is
                 * stale); the frame's seed image holds 0 elsewhere */
                int seed_box[4] = {box[0] / s, box[1] / s, (box[2] + s - 1) / s, (box[3] + s - 1) / s};
                field_seed_copy(f, fr, field, p->prepass, b, 0, seed_box);
            }
            field_generate(f, fr, field, unit, j0 + b, box);
        }
    }
}

/* The atlas's images after the generations of segments [0, layers) into the stacks, inside
 * the box where either the new or the layer's old content can be nonzero (field_store). */
static void field_store_atlas(const halo_glfuncs *f, halo_gl_field *field, int layers)
{
    f->BindFramebuffer(GL_READ_FRAMEBUFFER, field->framebuffer);
    for (int s = 0; s < field->stack_count; ++s) {
        field_stack *st = &field->stacks[s];
        f->BindTexture(GL_TEXTURE_2D_ARRAY, st->texture);
        GLuint attached = 0;
        for (int j = 0; j < layers; ++j) {
            int origin[2], box[4], copy[4], *old = st->boxes[j];
            GLuint texture = halo_gl_field_atlas_tile(field->atlas, st->image, j, origin, box);
            int fresh = box[0] < box[2] && box[1] < box[3], stale = old[0] < old[2] && old[1] < old[3];
            if (!texture || (!fresh && !stale))
                continue;
            for (int k = 0; k < 4; ++k)
                copy[k] = !stale   ? box[k]
                          : !fresh ? old[k]
                          : k < 2  ? (box[k] < old[k] ? box[k] : old[k])
                                   : (box[k] > old[k] ? box[k] : old[k]);
            if (texture != attached) {
                f->FramebufferTexture2D(GL_READ_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, texture, 0);
                f->ReadBuffer(GL_COLOR_ATTACHMENT0);
                attached = texture;
            }
            f->CopyTexSubImage3D(GL_TEXTURE_2D_ARRAY, 0, copy[0], copy[1], j, origin[0] + copy[0], origin[1] + copy[1],
                                 copy[2] - copy[0], copy[3] - copy[1]);
            memcpy(old, box, sizeof box);
        }
    }
    f->FramebufferTexture2D(GL_READ_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, 0, 0);
}

/* The atlas for the batched march's generations, within a quarter of max_bytes and what the
 * stacks leave of it: NULL where it cannot serve every stack (never again for this
 * program), or not this many layers (tried again with fewer). */
static halo_gl_field_atlas *field_atlas(halo_gl_frame *fr, halo_gl_field *field, int layers, size_t max_bytes)
{
    size_t stacks = 0;
    for (int s = 0; s < field->stack_count; ++s)
        stacks += (size_t)field->stacks[s].width * (size_t)field->stacks[s].height *
                  halo_gl_image_texel_bytes(field->stacks[s].internal_format) * (size_t)field->layers;
    if (field->atlas_unsuited || (field->atlas_failed && layers > field->atlas_fit && layers > field->atlas_failed / 2))
        return NULL;
    /* (reserve destroys an atlas it cannot grow) */
    size_t budget = stacks < max_bytes ? max_bytes - stacks : 0;
    field->atlas = halo_gl_field_atlas_reserve(fr, field->atlas, layers,
                                               budget < max_bytes / 4 ? budget : max_bytes / 4, &field->atlas_unsuited);
    for (int s = 0; field->atlas && s < field->stack_count; ++s) {
        int origin[2], box[4];
        if (!halo_gl_field_atlas_tile(field->atlas, field->stacks[s].image, 0, origin, box)) {
            /* a stacked image the generations do not make */
            halo_gl_field_atlas_destroy(halo_gl_functions(halo_gl_frame_runtime(fr)), field->atlas);
            field->atlas = NULL;
            field->atlas_unsuited = 1;
        }
    }
    field->atlas_failed = field->atlas ? 0 : layers;
    field->atlas_fit = field->atlas ? (layers > field->atlas_fit ? layers : field->atlas_fit) : field->atlas_fit;
    return field->atlas;
}

/* Seeds, generation and the stacks for every segment but the last (whose field no sample reads). */
static halo_status field_compute(halo_gl_frame *fr, const halo_gl_segments_desc *d, const halo_segment_plan *plan,
                                 int unit, halo_diagnostics *diag)
{
    halo_gl *gl = halo_gl_frame_runtime(fr);
    const halo_glfuncs *f = halo_gl_functions(gl);
    const halo_program *p = halo_gl_frame_program(fr);
    halo_gl_field *field = halo_gl_frame_field(fr);
    int width, height;
    halo_gl_frame_size(fr, &width, &height);
    double span = floor((plan->back - plan->front) / d->step) + 1.0;
    GLint max_layers = 256;
    f->GetIntegerv(GL_MAX_ARRAY_TEXTURE_LAYERS, &max_layers);
    if (!(span <= 1 << 20) || plan->segments - 1 > max_layers) {
        halo_diag_error(diag, USAGE, "", 0, 0,
                        "halo_gl_frame_draw: %.0f planes in %d depth segments (step %g): the field of more than %d "
                        "segments (GL_MAX_ARRAY_TEXTURE_LAYERS) or 2^20 planes is not kept; a larger step or "
                        "halo_generate.interval",
                        span, plan->segments, (double)d->step, (int)max_layers);
        return HALO_ERROR_INPUT;
    }
    int planes = (int)span;
    f->ActiveTexture(GL_TEXTURE0 + (GLenum)unit); /* the stacks are bound there to be made and filled */
    int layers = plan->segments > 1 ? plan->segments - 1 : 1;
    size_t max_bytes = d->field_max_bytes ? d->field_max_bytes : HALO_GL_FIELD_MAX_BYTES, seed_per_layer = 0;
    for (size_t i = 0; d->exchange && i < halo_program_reflection(p->prepass).output_count; ++i) {
        halo_gl_frame_image view; /* the seed stacks of the exchange (field_seed_reserve) count too */
        if (halo_gl_frame_image_view(fr, halo_program_reflection(p->prepass).outputs[i].image, &view))
            seed_per_layer +=
                (size_t)view.width * (size_t)view.height * halo_gl_image_texel_bytes(view.internal_format);
    }
    int reserved = field_reserve(f, p, field, layers, layers > max_layers - max_layers / 5 ? max_layers : 0, max_bytes,
                                 seed_per_layer, diag);
    if (reserved <= 0)
        return reserved < 0 ? HALO_ERROR_INPUT : HALO_ERROR_IO;
    double inverse[16], view_projection[16], low[3], high[3];
    for (int i = 0; i < 16; ++i)
        inverse[i] = d->inverse_view_projection[i];
    if (!halo_mat4_invert(inverse, view_projection))
        return HALO_ERROR_INPUT; /* reported by the plan */
    halo_segments_box(d, low, high);

    int voxels[3];
    /* the derived gradient: float (exact) where float textures filter linearly (OpenGL; OpenGL
     * ES with OES_texture_float_linear), else or when asked, half */
    int es = halo_gl_es_version(gl) > 0;
    /* (and, on ES, rendering into RGBA32F: EXT_color_buffer_float) */
    int float_linear = !es || (halo_gl_has_extension(gl, "GL_OES_texture_float_linear") &&
                               halo_gl_has_extension(gl, "GL_EXT_color_buffer_float"));
    if (d->gradient_precision != 0 && d->gradient_precision != 16 && d->gradient_precision != 32) {
        halo_diag_error(diag, USAGE, "", 0, 0, "halo_gl_frame_draw: gradient_precision is 16, 32 or 0, not %d",
                        d->gradient_precision);
        return HALO_ERROR_INPUT;
    }
    if (d->gradient_precision == 32 && !float_linear) {
        halo_diag_error(diag, GL_LINK, "", 0, 0,
                        "halo_gl_frame_draw: gradient_precision 32 needs linear filtering of float textures and "
                        "rendering into them, which this OpenGL ES context lacks (GL_OES_texture_float_linear, "
                        "GL_EXT_color_buffer_float); 16 or 0 (half here)");
        return HALO_ERROR_INPUT;
    }
    GLint internal = d->gradient_precision == 16 || !float_linear ? GL_RGBA16F : GL_RGBA32F;
    GLuint gradient = field_volume_size(f, d, unit, voxels, diag)
                          ? field_gradient_texture(f, field, p->prepass, d, voxels, unit, internal, diag)
                          : 0;
    GLuint bricks = gradient ? field_bricks(f, field, p->prepass, gradient, voxels, d->volume_version, unit, diag) : 0;
    if (!bricks)
        return HALO_ERROR_INPUT;
    double sample_low[3], sample_high[3];
    float piece_min[3], piece_scale[3];
    if (!field_piece(d, low, high, voxels, sample_low, sample_high, piece_min, piece_scale, diag))
        return HALO_ERROR_INPUT;
    /* a piece of a distributed volume: the seeds of every segment first, combined across the
     * pieces once, then the generations */
    int exchanged = d->exchange != NULL;
    f->ActiveTexture(GL_TEXTURE0 + (GLenum)unit); /* the seed stacks are made there too */
    if (exchanged && !field_seed_reserve(f, fr, field, p->prepass, layers, 1, diag))
        return HALO_ERROR_IO;
    halo_gl_frame_begin(fr);
    /* the batches' seed stack, eight layers of the seed image, within a sixteenth of the
     * field's cap (else, or where it cannot be had, one segment a draw) */
    size_t batch_bytes = 0;
    for (size_t i = 0; field->batch && i < halo_program_reflection(p->prepass).output_count; ++i) {
        halo_gl_frame_image view;
        if (halo_gl_frame_image_view(fr, halo_program_reflection(p->prepass).outputs[i].image, &view))
            batch_bytes += FIELD_BATCH * (size_t)view.width * (size_t)view.height *
                           halo_gl_image_texel_bytes(view.internal_format);
    }
    if (!exchanged && field->batch && batch_bytes <= max_bytes / 16) {
        if (field_seed_reserve(f, fr, field, p->prepass, FIELD_BATCH, 0, NULL)) {
            halo_gl_frame_attach_outputs(fr, p->prepass, field->framebuffer, 0);
            if (field_atlas(fr, field, layers, max_bytes)) {
                halo_gl_field_atlas_begin(field->atlas);
                halo_gl_frame_attach_outputs(fr, p->prepass, field->framebuffer, 0);
            }
            march_setup(fr, d, plan, field->batch, &field->batch_at, unit, gradient, bricks, sample_low, sample_high,
                        piece_min, piece_scale);
            field_batches(fr, d, plan, view_projection, sample_low, sample_high, planes, unit);
            if (field->atlas) {
                halo_gl_field_atlas_generate(field->atlas, layers);
                f->ActiveTexture(GL_TEXTURE0 + (GLenum)unit);
                field_store_atlas(f, field, layers);
            }
            return HALO_OK;
        }
        for (int k = 0; k < 8 && f->GetError() != GL_NO_ERROR; ++k) {}
    }
    march_setup(fr, d, plan, field->march, &field->at, unit, gradient, bricks, sample_low, sample_high, piece_min,
                piece_scale);
    halo_gl_frame_attach_outputs(fr, p->prepass, field->framebuffer, 0);
    f->BindFramebuffer(GL_READ_FRAMEBUFFER, field->framebuffer);
    int s = halo_program_reflection(p).image_scale > 1 ? halo_program_reflection(p).image_scale : 1;
    f->Viewport(0, 0, (width + s - 1) / s, (height + s - 1) / s);
    f->BindVertexArray(field->vertex_array);
    for (int j = 0; j + 1 < plan->segments; ++j) {
        int first, end, box[4];
        segment_reach(fr, d, plan, view_projection, sample_low, sample_high, planes, j, &first, &end, box);
        if (exchanged && j > 0) { /* this segment's seeds alone: the frame's images cleared */
            halo_gl_frame_begin(fr);
            halo_gl_frame_attach_outputs(fr, p->prepass, field->framebuffer, 0);
            f->BindFramebuffer(GL_READ_FRAMEBUFFER, field->framebuffer);
        }
        if (box[0] < box[2] && box[1] < box[3]) {
            f->UseProgram(field->march);
            f->BindFramebuffer(GL_DRAW_FRAMEBUFFER, field->framebuffer);
            f->Enable(GL_SCISSOR_TEST);
            /* the 1/s pixels whose blocks meet the footprint */
            int x0 = box[0] / s, y0 = box[1] / s, x1 = (box[2] + s - 1) / s, y1 = (box[3] + s - 1) / s;
            f->Scissor(x0, y0, x1 - x0, y1 - y0);
            f->Uniform2i(field->at.range, first, end);
            f->DrawArrays(GL_TRIANGLES, 0, 3);
            f->Disable(GL_SCISSOR_TEST);
        }
        f->ActiveTexture(GL_TEXTURE0 + (GLenum)unit);
        if (exchanged)
            field_seed_copy(f, fr, field, p->prepass, j, 1, NULL);
        else
            field_generate(f, fr, field, unit, j, box);
    }
    if (!exchanged)
        return HALO_OK;
    if (!field_seed_exchange(f, fr, field, p->prepass, d, layers, diag))
        return HALO_ERROR_IO;
    halo_gl_frame_begin(fr);
    for (int j = 0; j + 1 < plan->segments; ++j) {
        /* segment j's seeds of every piece; they can be nonzero where the segment's part of
         * the whole box projects */
        int first, end, box[4];
        segment_reach(fr, d, plan, view_projection, low, high, planes, j, &first, &end, box);
        f->BindFramebuffer(GL_READ_FRAMEBUFFER, field->framebuffer);
        f->ActiveTexture(GL_TEXTURE0 + (GLenum)unit);
        field_seed_copy(f, fr, field, p->prepass, j, 0, NULL);
        field_generate(f, fr, field, unit, j, box);
    }
    return HALO_OK;
}

static uint64_t key_add(uint64_t h, const void *data, size_t size)
{
    const unsigned char *b = data;
    for (size_t i = 0; i < size; ++i)
        h = (h ^ b[i]) * 1099511628211u; /* FNV-1a */
    return h;
}

/* Does a stage of p feed the field: its samples run in the march (the seeds and what they
 * need), or it has a generation pass (at=generate: it spreads the seeds)? */
static int field_stage(const halo_program *p, const char *stage)
{
    for (size_t s = 0; s < p->stage_count; s++) {
        const halo_module *m = p->stages[s].module;
        if (strcmp(m->name, stage))
            continue;
        if (p->stages[s].prepass)
            return 1;
        for (size_t k = 0; k < m->pass_count; k++)
            if (!m->passes[k].at)
                return 1;
    }
    return 0;
}

/* What a frame's field depends on, hashed: the march's inputs in the desc (the camera, the
 * step, the box, M, the volume and its version, the gradient, the cap), the frame's size,
 * the feature group and the live parameters of the stages that feed it (field_stage). A
 * frame drawn again with the same key reads the field it holds: a host redrawn for its own
 * reasons (a per-sample stage's parameter, halo_map's opacity, a repaint) does not pay for
 * the field again. The volume's contents are known by volume_version, as the derived
 * gradient knows them. */
static uint64_t field_key(const halo_gl_frame *fr, const halo_gl_segments_desc *d)
{
    const halo_program *p = halo_gl_frame_program(fr);
    uint64_t h = 14695981039346656037u;
    h = key_add(h, d->inverse_view_projection, 16 * sizeof *d->inverse_view_projection);
    h = key_add(h, &d->step, sizeof d->step);
    h = key_add(h, d->box_min, sizeof d->box_min);
    h = key_add(h, d->box_max, sizeof d->box_max);
    h = key_add(h, &d->interval, sizeof d->interval);
    h = key_add(h, &d->segments, sizeof d->segments);
    h = key_add(h, &d->volume_texture, sizeof d->volume_texture);
    h = key_add(h, &d->gradient_texture, sizeof d->gradient_texture);
    h = key_add(h, &d->gradient_precision, sizeof d->gradient_precision);
    h = key_add(h, &d->volume_version, sizeof d->volume_version);
    h = key_add(h, d->volume_size, sizeof d->volume_size);
    h = key_add(h, &d->seed_epsilon, sizeof d->seed_epsilon);
    h = key_add(h, d->piece_min, sizeof d->piece_min);
    h = key_add(h, d->piece_max, sizeof d->piece_max);
    h = key_add(h, &d->field_max_bytes, sizeof d->field_max_bytes);
    int size[2];
    halo_gl_frame_size(fr, &size[0], &size[1]);
    h = key_add(h, size, sizeof size);
    h = key_add(h, &p->group, sizeof p->group);
    for (size_t i = 0; i < p->uniform_count; ++i) {
        const halo_uniform_info *u = &p->uniforms[i];
        if (!u->live || !field_stage(p, u->stage))
            continue;
        h = key_add(h, &u->count, sizeof u->count);
        h = key_add(h, u->value, (size_t)u->count * (size_t)u->info->components * sizeof *u->value);
    }
    return h;
}

int halo_gl_field_computed(const halo_gl_frame *fr)
{
    const halo_gl_field *field = halo_gl_frame_field(fr);
    return field ? field->computed : 0;
}

halo_status halo_gl_field_draw(halo_gl_frame *fr, unsigned gl_program, const halo_gl_segments_desc *d,
                               halo_diagnostics *diag)
{
    halo_gl *gl = halo_gl_frame_runtime(fr);
    const halo_glfuncs *f = halo_gl_functions(gl);
    const halo_program *p = halo_gl_frame_program(fr);
    if (!d->volume_texture) {
        halo_diag_error(diag, USAGE, "", 0, 0,
                        "halo_gl_frame_draw: a program linked with one_draw needs desc.volume_texture (the host's "
                        "volume, which libhalo's march samples for the seeds of every depth segment)");
        return HALO_ERROR_INPUT;
    }
    halo_segment_plan plan;
    if (!halo_segment_plan_make(d, p, &plan, diag))
        return HALO_ERROR_INPUT;
    if (!halo_gl_frame_field(fr)) {
        halo_gl_field *made = field_create(fr, diag);
        if (!made)
            return HALO_ERROR_IO;
        halo_gl_frame_set_field(fr, made, field_destroy, field_bytes);
    }
    int first_unit = d->first_unit > 0 ? d->first_unit : FIELD_DEFAULT_FIRST_UNIT;
    int march_unit = first_unit + (int)halo_program_reflection(p).sampler_count;
    field_saved saved;
    halo_gl_field *field = halo_gl_frame_field(fr);
    /* a distributed volume's exchange is a collective: every frame, on every piece */
    uint64_t key = d->exchange ? 0 : field_key(fr, d);
    halo_status status = HALO_OK;
    field_save(f, &saved, march_unit);
    if (d->exchange || !field->key_valid || field->key != key) {
        field->key_valid = 0;
        status = field_compute(fr, d, &plan, march_unit, diag);
        field->key_valid = status == HALO_OK && !d->exchange;
        field->key = key;
        field->computed += status == HALO_OK;
    } else {
        halo_gl_frame_begin_host(fr); /* the host's outputs and the passes after its draw start anew */
    }
    field_restore(f, &saved, march_unit); /* the host draws with its own state */
    if (status == HALO_OK) {
        f->UseProgram(gl_program);
        halo_segment_camera_set(f, gl_program, &plan);
        f->Uniform4f(f->GetUniformLocation(gl_program, "halo_stack_plane"), (float)plan.plane[0], (float)plan.plane[1],
                     (float)plan.plane[2], (float)plan.plane[3]);
        f->Uniform3f(f->GetUniformLocation(gl_program, "halo_stack_slabs"), (float)plan.start,
                     (float)(1.0 / plan.length), (float)plan.segments);
        f->BindFramebuffer(GL_DRAW_FRAMEBUFFER, d->framebuffer);
        /* one blend for all buffers (OpenGL ES 3.0): the outputs' attach turns it off */
        GLboolean blend = f->IsEnabled(GL_BLEND);
        halo_gl_frame_attach(fr, d->framebuffer);
        halo_gl_frame_bind(fr, gl_program, first_unit);
        GLint active = GL_TEXTURE0;
        f->GetIntegerv(GL_ACTIVE_TEXTURE, &active);
        field_bind(f, p, halo_gl_frame_field(fr), first_unit);
        f->ActiveTexture((GLenum)active);
        halo_gl_frame_segments_reset(fr);
        d->draw(d->user);
        halo_gl_frame_state_flip(fr); /* counts the one draw */
        if (!halo_gl_blend_per_buffer(f) && halo_program_reflection(p).output_count > 0)
            (blend ? f->Enable : f->Disable)(GL_BLEND);
        f->BindFramebuffer(GL_DRAW_FRAMEBUFFER, (GLuint)saved.state.bindings.draw_framebuffer);
        halo_gl_use_saved_program(f, saved.state.bindings.program);
    }
    GLenum error = f->GetError();
    if (status == HALO_OK && error != GL_NO_ERROR) {
        halo_diag_error(diag, GL_LINK, "", 0, 0, "OpenGL error 0x%x computing the field of %d depth segments", error,
                        plan.segments);
        return HALO_ERROR_IO;
    }
    return status;
}
