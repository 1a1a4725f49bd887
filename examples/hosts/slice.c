/* The slice host and the slab ray caster (see slice.h, slab.h). */
#include "hosts/slice.h"
#include "hosts/host_common.h"
#include "volume.h"


#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

struct halo_slice {
    const halo_glfuncs *f;
    halo_gl *runtime;
    const halo_program *linked;
    halo_gl_frame *frame;
    int slab;
    GLuint program, vertex_array, framebuffer, textures[2]; /* textures[1]: the slab's second ray state */
    GLuint volume_texture, transfer_texture, labels_texture, gradient_texture;
    int width, height;
    const float *volume;
    int dims[3];
    float transfer[HALO_RAYCAST_TRANSFER_TEXELS * 4];
    float inverse_view_projection[16];
    double view_projection[16]; /* volume texture space -> clip space */
    float eye[3], view_axis[3], screen_right[3], screen_up[3];
    float step_voxels;
    float background[3];
    int interval_override;
    size_t field_max_bytes; /* halo_gl_segments_desc.field_max_bytes (drawn over the field) */
    halo_gradient_format gradient_format;
    float gradient_scale;   /* the texture holds gradient / gradient_scale */
    GLint gradient_pending; /* the internal format of gradients still to build on the GPU; 0: none */
    int reads_gradients;    /* the linked stages read the gradient (slice.frag's sample_gradient) */
    /* packed16/32 (halo_host_build_packed): gradient_texture holds the value too and program
     * is the SLICE_PACKED_VOLUME variant of the host shader, built by set_volume */
    int packed;
    float value_range[2];
    GLuint plain_program;   /* the host shader as linked, while program is the packed variant */
    GLuint outside_program; /* the SLICE_OUTSIDE variant (built at the first clipped render with images) */
    GLuint zero_program;    /* the HALO_IMAGES_ZERO variant (of the packed one when packed): the section's
                             * pixels outside the read region */
    char *vertex_source;    /* for building the variant */
    halo_gl *runtime_for_variant;
    int run_every_generation; /* halo_slice_set_generation_skip(s, 0) */
    int volume_version;       /* halo_gl_segments_desc.volume_version: one more at every upload */
    long draws, pass_draws;
    halo_slice_progress_fn progress;
    void *progress_user;
    void (*untidy)(void *user, int returned); /* halo_slice_set_untidy */
    void *untidy_user;
};

halo_slice *halo_slice_create_mode(const halo_host_desc *desc, int slab, halo_diagnostics *diag)
{
    if (!halo_host_desc_check(desc, diag))
        return NULL;
    halo_slice *s = halo_host_calloc(sizeof *s, diag);
    if (!s)
        return NULL;
    const halo_glfuncs *f = desc->gl;
    s->f = f;
    s->runtime = desc->runtime;
    s->linked = desc->program;
    s->slab = slab;
    s->gradient_scale = 1.0f;
    s->width = desc->width;
    s->height = desc->height;
    s->program =
        halo_host_program_build(desc, "slice.vert", slab ? "slab.frag" : "slice.frag", HALO_HOST_LOG_APPENDED, diag);
    if (!s->program)
        goto fail;
    s->reads_gradients = f->GetUniformLocation(s->program, "gradient_texture") >= 0;
    if (desc->program) { /* for the variants */
        const char *vertex = desc->vertex_source ? desc->vertex_source : halo_host_embedded("slice.vert");
        s->vertex_source = vertex ? strdup(vertex) : NULL;
        s->runtime_for_variant = desc->runtime;
    }
    f->GenVertexArrays(1, &s->vertex_array);
    f->GenTextures(2, s->textures);
    for (int k = 0; k < (slab ? 2 : 1); ++k)
        halo_host_image_texture(f, s->textures[k], GL_RGBA32F, s->width, s->height, GL_RGBA, GL_FLOAT);
    f->BindTexture(GL_TEXTURE_2D, 0);
    if (!halo_host_framebuffer(f, &s->framebuffer, s->textures[0], s->width, s->height, diag))
        goto fail;
    const halo_program *p = desc->program;
    if (p && (halo_program_reflection(p).image_count || halo_program_reflection(p).output_count ||
              halo_program_reflection(p).sampler_count)) {
        s->frame = halo_gl_frame_create(desc->runtime, p, s->width, s->height, diag);
        if (!s->frame)
            goto fail;
    }
    f->GenTextures(1, &s->volume_texture);
    f->GenTextures(1, &s->transfer_texture);
    f->GenTextures(1, &s->gradient_texture);
    halo_slice_set_render(s, NULL, diag);
    halo_slice_set_camera(s, 30.0, 20.0, 1.0);
    for (size_t i = 0; p && i < halo_program_reflection(p).host_uniform_count; ++i)
        if (!strcmp(halo_program_reflection(p).host_uniforms[i].name, "halo_host_labels") &&
            halo_slice_set_labels(s, NULL, 0, 0, 0, diag) != HALO_OK)
            goto fail;
    return s;
fail:
    halo_slice_destroy(s);
    return NULL;
}

halo_slice *halo_slice_create(const halo_host_desc *desc, halo_diagnostics *diag)
{
    return halo_slice_create_mode(desc, 0, diag);
}

void halo_slice_destroy(halo_slice *s)
{
    if (!s)
        return;
    const halo_glfuncs *f = s->f;
    halo_gl_frame_destroy(s->frame);
    if (f) { /* glDelete* passes over the names never made (0) */
        f->DeleteFramebuffers(1, &s->framebuffer);
        const GLuint textures[6] = {s->textures[0],      s->textures[1],    s->volume_texture,
                                    s->transfer_texture, s->labels_texture, s->gradient_texture};
        f->DeleteTextures(6, textures);
        f->DeleteVertexArrays(1, &s->vertex_array);
        f->DeleteProgram(s->program);
        f->DeleteProgram(s->plain_program);
        f->DeleteProgram(s->outside_program);
        f->DeleteProgram(s->zero_program);
    }
    free(s->vertex_source);
    free(s);
}

unsigned halo_slice_gl_program(const halo_slice *s) { return s ? s->program : 0; }

halo_gl_frame *halo_slice_frame(const halo_slice *s) { return s ? s->frame : NULL; }

long halo_slice_draws(const halo_slice *s) { return s ? s->draws : 0; }

long halo_slice_pass_draws(const halo_slice *s) { return s ? s->pass_draws : 0; }

void halo_slice_set_interval(halo_slice *s, int interval)
{
    if (s)
        s->interval_override = interval > 0 ? interval : 0;
}

void halo_slice_set_field_max_bytes(halo_slice *s, size_t bytes)
{
    if (s)
        s->field_max_bytes = bytes;
}

void halo_slice_set_untidy(halo_slice *s, void (*untidy)(void *user, int returned), void *user)
{
    if (s) {
        s->untidy = untidy;
        s->untidy_user = user;
    }
}

/* A call of libhalo's runtime that must neither depend on the host's GL state nor change
 * it, between the two calls of the untidy hook (halo_slice_set_untidy). */
#define SLICE_RUNTIME(s, call)                \
    do {                                      \
        if ((s)->untidy)                      \
            (s)->untidy((s)->untidy_user, 0); \
        call;                                 \
        if ((s)->untidy)                      \
            (s)->untidy((s)->untidy_user, 1); \
    } while (0)

void halo_slice_set_progress(halo_slice *s, halo_slice_progress_fn fn, void *user)
{
    if (s) {
        s->progress = fn;
        s->progress_user = user;
    }
}

int halo_slice_interval(const halo_slice *s)
{
    if (!s)
        return 1;
    if (s->interval_override > 0)
        return s->interval_override;
    int m = s->linked ? halo_program_reflection(s->linked).interval : 0;
    return m > 0 ? m : 4;
}

/* Without a segmentation the labels sampler still needs a 3D texture of its own (unit 0
 * holds the volume, whose values could pass for label ids 0 and 1): 2^3 voxels of -1,
 * which no label id (>= 0) matches. */
static const float no_labels[8] = {-1, -1, -1, -1, -1, -1, -1, -1};

halo_status halo_slice_set_labels(halo_slice *s, const float *labels, int nx, int ny, int nz, halo_diagnostics *diag)
{
    if (!s)
        return HALO_ERROR_INPUT;
    if (!labels) {
        labels = no_labels;
        nx = ny = nz = 2;
    }
    if (!s->labels_texture)
        s->f->GenTextures(1, &s->labels_texture);
    halo_status status = halo_host_upload_labels(s->f, s->labels_texture, labels, nx, ny, nz, diag);
    if (status != HALO_OK) {
        s->f->DeleteTextures(1, &s->labels_texture);
        s->labels_texture = 0;
    }
    return status;
}

int halo_slice_reads_gradients(const halo_slice *s) { return s && s->reads_gradients; }

static const char *const gradient_format_names[HALO_GRADIENT_FORMAT_COUNT] = {NULL,     "float",    "half",
                                                                              "snorm8", "packed16", "packed32"};

const char *halo_gradient_format_name(halo_gradient_format format)
{
    return format > HALO_GRADIENT_DEFAULT && format < HALO_GRADIENT_FORMAT_COUNT ? gradient_format_names[format] : NULL;
}

halo_gradient_format halo_gradient_format_from_name(const char *text)
{
    for (int k = HALO_GRADIENT_FLOAT; text && k < HALO_GRADIENT_FORMAT_COUNT; ++k)
        if (!strcmp(text, gradient_format_names[k]))
            return (halo_gradient_format)k;
    return HALO_GRADIENT_FORMAT_COUNT;
}

int halo_gradient_format_option(const char *text, halo_gradient_format *format, char *err, size_t errlen)
{
    halo_gradient_format named = halo_gradient_format_from_name(text);
    if (named == HALO_GRADIENT_FORMAT_COUNT) {
        if (err && errlen)
            snprintf(err, errlen, "--gradient-format: '%s' is not float, half, snorm8, packed16 or packed32",
                     text ? text : "");
        return 0;
    }
    *format = named;
    return 1;
}

void halo_slice_set_generation_skip(halo_slice *s, int on)
{
    if (!s)
        return;
    s->run_every_generation = !on;
    /* off: every pass over the whole image as well (on: the frame's default) */
    if (!on && s->frame)
        halo_gl_frame_set_readback_bounds(s->frame, 0);
}

void halo_slice_set_gradient_format(halo_slice *s, halo_gradient_format format)
{
    if (s)
        s->gradient_format = format;
}

halo_gradient_format halo_slice_gradient_format(const halo_slice *s)
{
    halo_gradient_format format = s ? s->gradient_format : HALO_GRADIENT_DEFAULT;
    return halo_gradient_format_name(format) ? format : HALO_GRADIENT_FORMAT_DEFAULT;
}

/* Switches the host shader to its SLICE_PACKED_VOLUME variant (built once) or back. */
static halo_status use_packed(halo_slice *s, int packed, halo_diagnostics *diag)
{
    if (packed && !s->plain_program) {
        GLuint variant = s->vertex_source ? halo_gl_program_build(s->runtime_for_variant, s->linked, s->vertex_source,
                                                                  "slice.vert", "#define SLICE_PACKED_VOLUME 1\n", diag)
                                          : 0;
        if (!variant)
            return HALO_ERROR_IO;
        s->plain_program = s->program;
        s->program = variant;
    } else if (!packed && s->plain_program) {
        s->f->DeleteProgram(s->program);
        s->program = s->plain_program;
        s->plain_program = 0;
    }
    if (packed != s->packed && s->zero_program) { /* built for the other volume texture */
        s->f->DeleteProgram(s->zero_program);
        s->zero_program = 0;
    }
    s->packed = packed;
    return HALO_OK;
}

halo_status halo_slice_set_volume(halo_slice *s, const float *data, int nx, int ny, int nz, halo_diagnostics *diag)
{
    halo_status status = halo_host_upload_volume(s ? s->f : NULL, s ? s->volume_texture : 0, data, nx, ny, nz, diag);
    if (status != HALO_OK)
        return status;
    s->gradient_pending = 0;
    halo_gradient_format format = halo_slice_gradient_format(s);
    int packed = format == HALO_GRADIENT_PACKED16 || format == HALO_GRADIENT_PACKED32;
    if (use_packed(s, packed && halo_slice_reads_gradients(s), diag) != HALO_OK)
        return HALO_ERROR_IO;
    /* the gradients for the linked stages (slice.frag's sample_gradient) only when one
     * reads them: otherwise the driver drops the unread fetch and with it the sampler
     * (the same image without the texture) */
    if (halo_slice_reads_gradients(s)) {
        static const GLint internal_formats[HALO_GRADIENT_FORMAT_COUNT] = {
            0, GL_RGB32F, GL_RGB16F, GL_RGB8_SNORM, GL_RGBA16_SNORM, GL_RGBA32F};
        GLint internal_format = internal_formats[format];
        if (halo_host_gradients_renderable(s->f, internal_format)) {
            /* built on the GPU from the volume texture at the first render: by then the
             * caller may have freed data, and the peak holds no CPU copy beside the two
             * textures */
            const int dims[3] = {nx, ny, nz};
            s->gradient_scale = halo_host_gradient_scale(data, dims, internal_format);
            s->gradient_pending = internal_format;
            if (s->packed)
                halo_host_value_range(data, dims, s->value_range);
        } else if (s->packed) {
            HALO_REPORT_ERROR(diag, HALO_MSG_GL_LINK, "", 0, 0,
                              "slice host: this GL cannot render into the 3D textures of "
                              "gradient format %s",
                              halo_gradient_format_name(format));
            return HALO_ERROR_IO;
        } else {
            status = halo_host_upload_gradients(s->f, s->gradient_texture, data, nx, ny, nz, internal_format,
                                                &s->gradient_scale, diag);
            if (status != HALO_OK)
                return status;
        }
    }
    s->volume = data;
    s->volume_version++;
    s->dims[0] = nx;
    s->dims[1] = ny;
    s->dims[2] = nz;
    return HALO_OK;
}

halo_status halo_slice_set_render(halo_slice *s, const halo_render_settings *settings, halo_diagnostics *diag)
{
    if (!s)
        return HALO_ERROR_INPUT;
    return halo_host_upload_transfer(s->f, s->transfer_texture, s->transfer, settings, &s->step_voxels, s->background,
                                     diag);
}

void halo_slice_set_camera(halo_slice *s, double azimuth, double elevation, double zoom)
{
    if (!s)
        return;
    halo_host_camera camera;
    if (!halo_host_orbit_camera(azimuth, elevation, zoom, s->width, s->height, &camera))
        return;
    halo_host_camera_keep(&camera, s->inverse_view_projection, s->eye, s->screen_right, s->screen_up);
    memcpy(s->view_projection, camera.view_projection, sizeof s->view_projection);
    for (int c = 0; c < 3; ++c)
        s->view_axis[c] = (float)-camera.back[c];
}

void halo_slice_get_state(const halo_slice *s, halo_slice_state *st)
{
    memset(st, 0, sizeof *st);
    if (!s)
        return;
    st->width = s->width;
    st->height = s->height;
    for (int i = 0; i < 16; ++i)
        st->inverse_view_projection[i] = s->inverse_view_projection[i];
    int voxels = s->volume ? halo_host_max_dimension(s->dims) : 1;
    float unit_step = 1.0f / (float)voxels;
    float step_size = s->step_voxels * unit_step;
    double centre_distance = 0.0;
    for (int c = 0; c < 3; ++c) {
        st->eye[c] = s->eye[c];
        st->view_axis[c] = s->view_axis[c];
        st->screen_right[c] = s->screen_right[c];
        st->screen_up[c] = s->screen_up[c];
        st->background[c] = s->background[c];
        st->dims[c] = s->dims[c];
        centre_distance += ((double)s->eye[c] - 0.5) * ((double)s->eye[c] - 0.5);
    }
    const double radius = 0.8660254037844386;
    st->first_distance = (float)(sqrt(centre_distance) - radius);
    st->step_size = step_size;
    st->unit_step = unit_step;
    st->slice_count = (int)floor(2.0 * radius / step_size) + 1;
    st->interval = halo_slice_interval(s);
    st->slab = s->slab;
    st->transfer_texels = HALO_RAYCAST_TRANSFER_TEXELS;
    st->transfer = s->transfer;
    st->volume = s->volume;
}

/* ---- Rendering ------------------------------------------------------------------------------ */

static halo_status render_pass(halo_slice *s, float *rgba, int group, halo_diagnostics *diag);

/* A program with feature groups (the reflection's group_count > 1, e.g. more than four
 * outline features) renders the volume once per group: the group's values uploaded,
 * its feature images cleared before and reduced after (halo_gl_frame_begin_group,
 * _end_group); the colour is the same every time, so the slice host writes it in the
 * first group only (glColorMaski off for buffer 0 after it: the driver may then skip the
 * colour's blending, and llvmpipe the shader work that only feeds it). */
halo_status halo_slice_render(halo_slice *s, float *rgba, halo_diagnostics *diag)
{
    if (!s || !rgba)
        return HALO_ERROR_INPUT;
    if (!s->volume) {
        HALO_REPORT_ERROR(diag, HALO_MSG_USAGE, "", 0, 0, "slice host: no volume uploaded");
        return HALO_ERROR_INPUT;
    }
    if (s->gradient_pending) {
        halo_status built =
            s->packed ? halo_host_build_packed(s->f, s->gradient_texture, s->volume_texture, s->dims[0], s->dims[1],
                                               s->dims[2], s->gradient_pending, s->gradient_scale, s->value_range, diag)
                      : halo_host_build_gradients(s->f, s->gradient_texture, s->volume_texture, s->dims[0], s->dims[1],
                                                  s->dims[2], s->gradient_pending, s->gradient_scale, diag);
        if (built != HALO_OK)
            return built;
        s->gradient_pending = 0;
        if (s->packed) { /* the packed texture holds the values: the R32F volume's memory goes */
            s->f->BindTexture(GL_TEXTURE_3D, s->volume_texture);
            s->f->TexImage3D(GL_TEXTURE_3D, 0, GL_R32F, 1, 1, 1, 0, GL_RED, GL_FLOAT, NULL);
            s->f->BindTexture(GL_TEXTURE_3D, 0);
        }
    }
    int groups = s->linked && s->frame ? halo_program_reflection(s->linked).group_count : 1;
    if (groups == 1)
        return render_pass(s, rgba, -1, diag);
    long draws = 0, pass_draws = 0;
    halo_status status = HALO_OK;
    /* the host was given the program to render: selecting a group changes its current
     * values, which the next upload sends */
    halo_program *program = (halo_program *)s->linked;
    for (int g = 0; g < groups && status == HALO_OK; ++g) {
        halo_program_select_group(program, g);
        status = render_pass(s, rgba, g, diag);
        draws += s->draws;
        pass_draws += s->pass_draws;
    }
    halo_program_select_group(program, 0);
    s->draws = draws;
    s->pass_draws = pass_draws;
    return status;
}

/* Whether every stage that runs generation passes says they make every image 0 from a
 * seed image of 0 (halo_stage_info.zero_generation: halo_generate's spreading), so that
 * a generation after an empty slab may be skipped. */
static int generation_zero_from_zero(const halo_program *p)
{
    int any = 0;
    halo_reflection r = halo_program_reflection(p);
    for (size_t i = 0; i < r.pass_count; ++i) {
        const halo_pass_info *pass = &r.passes[i];
        if (pass->at)
            continue;
        const halo_stage_info *info = NULL;
        for (size_t k = 0; k < r.stage_count; ++k)
            if (!strcmp(r.stages[k].name, pass->stage))
                info = &r.stages[k];
        if (!info || !info->zero_generation)
            return 0;
        any = 1;
    }
    return any;
}

/* The range of slice distances (dot(P - eye, view_axis)) at which a plane meets the unit
 * cube, widened by a margin far below a slice step (the shader's inside test is in float). */
static void cube_distance_range(const halo_slice_state *st, double range[2])
{
    range[0] = INFINITY;
    range[1] = -INFINITY;
    for (int corner = 0; corner < 8; ++corner) {
        double d = 0.0;
        for (int c = 0; c < 3; ++c)
            d += ((corner >> c & 1) - (double)st->eye[c]) * st->view_axis[c];
        range[0] = d < range[0] ? d : range[0];
        range[1] = d > range[1] ? d : range[1];
    }
    range[0] -= 1e-3;
    range[1] += 1e-3;
}

/* The generations a frame can skip exactly (issue 16, item 1). A slice outside the unit
 * cube samples nothing: its samples have no gradient, and halo_seed seeds nothing
 * without one. When every slice since the last generation is outside and the halo field
 * is still zero (nothing seeded since the frame began, or the last generation ran on an
 * empty seed image), the generation would write zeros over zeros and leave the
 * occlusion image as it is (max with 0): it is skipped. */
typedef struct generation_skip {
    int enabled;
    double range[2];
    int seeded;     /* a slice since the last generation may have sampled the volume */
    int field_zero; /* the halo images hold zeros */
} generation_skip;

static void generation_skip_start(generation_skip *g, const halo_slice *s, const halo_slice_state *st)
{
    g->enabled = !s->run_every_generation && generation_zero_from_zero(s->linked);
    cube_distance_range(st, g->range);
    g->seeded = 0;
    g->field_zero = 1;
}

/* Slices first .. first + count - 1 were drawn. */
static void generation_skip_drawn(generation_skip *g, const halo_slice_state *st, int first, int count)
{
    double near = st->first_distance + first * (double)st->step_size;
    double far = st->first_distance + (first + count - 1) * (double)st->step_size;
    if (far >= g->range[0] && near <= g->range[1])
        g->seeded = 1;
}

/* Runs the generation unless it is skippable. */
static void generation_run(generation_skip *g, const halo_slice *s)
{
    if (g->enabled && !g->seeded && g->field_zero)
        return;
    SLICE_RUNTIME(s, halo_gl_frame_generate(s->frame));
    g->field_zero = !g->seeded;
    g->seeded = 0;
}

/* Slices clipped to the volume (issue 16, item 1). Outside the unit cube slice.frag's
 * sample is empty: value, colour, opacity and gradient 0. A stage that says it keeps
 * such a sample empty and writes 0 to its outputs where the images it reads are 0
 * (halo_stage_info.keeps_empty: gradient, halo_seed, halo_map, halo_generate and
 * boundary do) adds nothing there: with only such stages linked (or none), a slice's
 * pixels outside its plane's section of the cube and outside the images' nonzero box
 * (halo_gl_frame_info.read_box) add nothing to any buffer, so the slice is scissored to
 * the rest, or not drawn when that is empty. Other stages may make an empty sample
 * visible (opacity_power's pow(0, 0), distance cues...): their slices are drawn whole. */
static int slices_clippable(const halo_slice *s)
{
    if (s->slab || s->run_every_generation)
        return 0;
    for (size_t i = 0; s->linked && i < halo_program_reflection(s->linked).stage_count; ++i)
        if (!halo_program_reflection(s->linked).stages[i].keeps_empty)
            return 0;
    return 1;
}

/* The pixels slice.frag may sample the cube in on the plane dot(P - eye, view_axis) =
 * distance: the window box of the plane's section of the cube grown by 1e-3 (the shader's
 * float inside test), plus a pixel each side; the whole image when a point of it is not
 * in front of the eye. Returns 0 when the plane misses the cube. */
static int slice_section_box(const halo_slice *s, double distance, int box[4])
{
    const double lo = -1e-3, hi = 1.0 + 1e-3;
    double x0 = INFINITY, y0 = INFINITY, x1 = -INFINITY, y1 = -INFINITY;
    int points = 0;
    for (int edge = 0; edge < 12; ++edge) {
        int axis = edge / 4; /* the edge runs along axis; the other two coordinates at lo or hi */
        double a[3], b[3];
        for (int c = 0, bit = 0; c < 3; ++c) {
            if (c == axis) {
                a[c] = lo;
                b[c] = hi;
            } else {
                a[c] = b[c] = (edge >> bit++ & 1) ? hi : lo;
            }
        }
        double da = -distance, db = -distance;
        for (int c = 0; c < 3; ++c) {
            da += (a[c] - s->eye[c]) * s->view_axis[c];
            db += (b[c] - s->eye[c]) * s->view_axis[c];
        }
        if ((da > 0.0 && db > 0.0) || (da < 0.0 && db < 0.0) || da == db)
            continue;
        double t = da / (da - db), clip[4];
        for (int r = 0; r < 4; ++r) {
            clip[r] = s->view_projection[12 + r];
            for (int c = 0; c < 3; ++c)
                clip[r] += s->view_projection[4 * c + r] * (a[c] + t * (b[c] - a[c]));
        }
        if (!(clip[3] > 1e-9)) {
            box[0] = box[1] = 0;
            box[2] = s->width;
            box[3] = s->height;
            return 1;
        }
        double x = (clip[0] / clip[3] + 1.0) * 0.5 * s->width, y = (clip[1] / clip[3] + 1.0) * 0.5 * s->height;
        x0 = x < x0 ? x : x0;
        x1 = x > x1 ? x : x1;
        y0 = y < y0 ? y : y0;
        y1 = y > y1 ? y : y1;
        points++;
    }
    if (!points)
        return 0;
    /* within a few pixels of the image before converting (a point just in front of the
     * eye lands far outside it) */
    x0 = fmax(x0, -2.0), y0 = fmax(y0, -2.0);
    x1 = fmin(x1, s->width + 2.0), y1 = fmin(y1, s->height + 2.0);
    box[0] = x0 - 1.0 > 0.0 ? (int)floor(x0) - 1 : 0;
    box[1] = y0 - 1.0 > 0.0 ? (int)floor(y0) - 1 : 0;
    box[2] = x1 + 1.0 < s->width ? (int)ceil(x1) + 1 : s->width;
    box[3] = y1 + 1.0 < s->height ? (int)ceil(y1) + 1 : s->height;
    return box[0] < box[2] && box[1] < box[3];
}

/* Draws a clipped slice (slices_clippable) at `distance`. programs: the host shader and,
 * when it reads images, its HALO_IMAGES_ZERO and SLICE_OUTSIDE variants (else 0); at:
 * their slice_distance locations. The frame plans which pixels each draws
 * (halo_gl_frame_plan_slice: the shader where the images read can be nonzero, the zero
 * variant the rest of the section, the outside variant the rest of the read region; the
 * boxes do not overlap, so their order does not matter): they start with the program in
 * use (*current), and *current is left the last one used. Each box drawn is declared to
 * the frame (halo_gl_frame_drawn_region). Returns 0 when it draws nothing. */
static int draw_clipped_slice(const halo_slice *s, const GLuint programs[3], const GLint at[3], GLuint *current,
                              float distance)
{
    const halo_glfuncs *f = s->f;
    int section[4] = {0, 0, 0, 0};
    if (!slice_section_box(s, distance, section))
        memset(section, 0, sizeof section);
    halo_gl_slice_plan plan;
    memset(&plan, 0, sizeof plan);
    if (s->frame)
        halo_gl_frame_plan_slice(s->frame, section, programs[1] && programs[2], &plan);
    else if (section[0] < section[2] && section[1] < section[3])
        plan = (halo_gl_slice_plan){{1, 0, 0}, {{{section[0], section[1], section[2], section[3]}}}};
    int first = programs[1] == *current ? 1 : programs[2] == *current ? 2 : 0, any = 0;
    for (int i = 0; i < HALO_GL_SLICE_VARIANTS; ++i) {
        int g = (first + i) % HALO_GL_SLICE_VARIANTS;
        if (!plan.count[g])
            continue;
        if (programs[g] != *current)
            f->UseProgram(*current = programs[g]);
        f->Uniform1f(at[g], distance);
        for (int k = 0; k < plan.count[g]; ++k) {
            const int *b = plan.box[g][k];
            f->Scissor(b[0], b[1], b[2] - b[0], b[3] - b[1]);
            f->DrawArrays(GL_TRIANGLES, 0, 3);
            if (s->frame)
                halo_gl_frame_drawn_region(s->frame, b[0], b[1], b[2], b[3]);
        }
        any = 1;
    }
    return any;
}

/* Colour buffer 0 written (on) or not while the slices are drawn, when `masking` (the
 * frame's passes and clears write their images whatever the host's mask). */
static void colour_mask(const halo_slice *s, int masking, int on)
{
    if (masking)
        s->f->ColorMaski(0, on ? GL_TRUE : GL_FALSE, on ? GL_TRUE : GL_FALSE, on ? GL_TRUE : GL_FALSE,
                         on ? GL_TRUE : GL_FALSE);
}

/* The state of program (the host shader or a variant) for this frame: its live
 * parameters, textures and uniforms; it is left in use. */
static void program_state(halo_slice *s, GLuint program, const halo_slice_state *st_in)
{
    const halo_glfuncs *f = s->f;
    const halo_slice_state st = *st_in;
    f->UseProgram(program);
    if (s->linked)
        halo_gl_program_upload(s->runtime, s->linked, program);
    f->ActiveTexture(GL_TEXTURE0);
    f->BindTexture(GL_TEXTURE_3D, s->packed ? s->gradient_texture : s->volume_texture);
    f->ActiveTexture(GL_TEXTURE1);
    f->BindTexture(GL_TEXTURE_2D, s->transfer_texture);
    f->ActiveTexture(GL_TEXTURE0);
    f->Uniform1i(f->GetUniformLocation(program, "volume_texture"), 0);
    f->Uniform1i(f->GetUniformLocation(program, "transfer_texture"), 1);
    f->Uniform1i(f->GetUniformLocation(program, "ray_state"), 2);
    f->ActiveTexture(GL_TEXTURE0 + HALO_SLICE_GRADIENT_UNIT);
    f->BindTexture(GL_TEXTURE_3D, s->gradient_texture);
    f->ActiveTexture(GL_TEXTURE0);
    f->Uniform1i(f->GetUniformLocation(program, "gradient_texture"), HALO_SLICE_GRADIENT_UNIT);
    f->Uniform1f(f->GetUniformLocation(program, "gradient_texture_scale"), s->gradient_scale);
    if (s->packed)
        f->Uniform2fv(f->GetUniformLocation(program, "packed_value"), 1, s->value_range);
    f->UniformMatrix4fv(f->GetUniformLocation(program, "inverse_view_projection"), 1, GL_FALSE,
                        s->inverse_view_projection);
    f->Uniform3fv(f->GetUniformLocation(program, "eye"), 1, s->eye);
    f->Uniform3fv(f->GetUniformLocation(program, "view_axis"), 1, s->view_axis);
    f->Uniform1f(f->GetUniformLocation(program, "step_size"), (float)st.step_size);
    f->Uniform1f(f->GetUniformLocation(program, "unit_step"), (float)st.unit_step);
    if (s->linked) {
        /* ignored (HALO_ERROR_INPUT) when no stage declares them */
        halo_gl_set_host_uniform(s->runtime, program, "screen_right", s->screen_right, 3);
        halo_gl_set_host_uniform(s->runtime, program, "screen_up", s->screen_up, 3);
        if (s->labels_texture) {
            f->ActiveTexture(GL_TEXTURE0 + HALO_SLICE_LABEL_UNIT);
            f->BindTexture(GL_TEXTURE_3D, s->labels_texture);
            f->ActiveTexture(GL_TEXTURE0);
            halo_gl_set_host_uniform(s->runtime, program, "labels", &(float){HALO_SLICE_LABEL_UNIT}, 1);
        }
    }
}

/* A variant of the host shader (slice.frag) with `defines`, built once into *program: 0
 * with a diagnostic when it cannot be built. */
static GLuint shader_variant(halo_slice *s, GLuint *program, const char *defines, halo_diagnostics *diag)
{
    if (!s->vertex_source) {
        HALO_REPORT_ERROR(diag, HALO_MSG_OUT_OF_MEMORY, "", 0, 0, "slice host: out of memory for its shader's variant");
        return 0;
    }
    if (!*program)
        *program =
            halo_gl_program_build(s->runtime_for_variant, s->linked, s->vertex_source, "slice.vert", defines, diag);
    return *program;
}

/* Host contract 3 (a program linked with one_draw): halo_gl_frame_draw computes the halo
 * field of every depth segment with libhalo's march over this host's volume, on the
 * slices' own planes, then calls draw_slices once: every slice, front to back, with no
 * generation between them; each sample reads its segment's layer of the field. */
typedef struct slice_draw {
    halo_slice *s;
    const halo_slice_state *st;
    GLint distance;
} slice_draw;

static void draw_slices(void *user)
{
    const slice_draw *d = user;
    halo_slice *s = d->s;
    for (int k = 0; k < d->st->slice_count; ++k) {
        s->f->Uniform1f(d->distance, (float)(d->st->first_distance + k * d->st->step_size));
        s->f->DrawArrays(GL_TRIANGLES, 0, 3);
        s->draws++;
        if (s->progress)
            s->progress(k + 1, d->st->slice_count, s->progress_user);
    }
}

/* halo_gl_frame_draw calls the host's draw, with the host's state: not in the untidy
 * hook's hostile state (the ray caster's test covers halo_gl_frame_draw in it). The
 * march reads this host's gradient texture where it holds the contract's gradient as
 * floats (format float: scale 1), else derives its own from the volume. */
static halo_status draw_over_field(halo_slice *s, const halo_slice_state *st, GLuint program, halo_diagnostics *diag)
{
    slice_draw d = {s, st, s->f->GetUniformLocation(program, "slice_distance")};
    int own_gradient = s->reads_gradients && halo_slice_gradient_format(s) == HALO_GRADIENT_FLOAT &&
                       s->gradient_scale == 1.0f && !s->gradient_pending;
    const halo_gl_segments_desc desc = {.inverse_view_projection = s->inverse_view_projection,
                                        .step = (float)st->step_size,
                                        .interval = st->interval,
                                        .framebuffer = s->framebuffer,
                                        .first_unit = 3, /* below the gradient's and labels' units */
                                        .volume_texture = s->volume_texture,
                                        .volume_version = s->volume_version,
                                        .volume_size = {s->dims[0], s->dims[1], s->dims[2]},
                                        .gradient_texture = own_gradient ? s->gradient_texture : 0,
                                        .field_max_bytes = s->field_max_bytes,
                                        .draw = draw_slices,
                                        .user = &d};
    return halo_gl_frame_draw(s->frame, program, &desc, diag);
}

/* One pass over the volume; group >= 0: feature group `group` of a grouped program. */
static halo_status render_pass(halo_slice *s, float *rgba, int group, halo_diagnostics *diag)
{
    halo_slice_state st;
    halo_slice_get_state(s, &st);
    const halo_glfuncs *f = s->f;
    GLuint program = s->program;
    static const GLfloat zero[4] = {0, 0, 0, 0};
    long pass_draws_before = halo_gl_frame_describe(s->frame).pass_draws;
    s->draws = 0;
    int one_draw = s->frame && halo_program_reflection(s->linked).one_draw;
    if (one_draw && (s->slab || group >= 0 || s->packed)) {
        HALO_REPORT_ERROR(diag, HALO_MSG_USAGE, "", 0, 0,
                          "slice host: one_draw (the slices drawn once over the halo field) %s",
                          s->slab     ? "is for the slice host, not the slab host"
                          : s->packed ? "needs the R32F volume that libhalo's march reads, which the packed gradient "
                                        "formats free: use float, half or snorm8"
                                      : "takes no feature groups");
        return HALO_ERROR_INPUT;
    }
    /* a group after the first: rgba and colour buffer 0 hold the colour already */
    int colour_written = group > 0 && !s->slab && !s->run_every_generation && f->ColorMaski;
    /* clipped slices with halo images: the pixels of the section where the images read
     * are 0 and those outside the section get variants */
    GLuint outside = 0, zero_variant = 0;
    if (!one_draw && slices_clippable(s) && s->frame && halo_program_reflection(s->linked).sampler_count > 0 &&
        (!(outside = shader_variant(s, &s->outside_program, "#define SLICE_OUTSIDE 1\n", diag)) ||
         !(zero_variant = shader_variant(s, &s->zero_program,
                                         s->packed ? "#define HALO_IMAGES_ZERO 1\n#define SLICE_PACKED_VOLUME 1\n"
                                                   : "#define HALO_IMAGES_ZERO 1\n",
                                         diag))))
        return HALO_ERROR_IO;

    f->BindFramebuffer(GL_FRAMEBUFFER, s->framebuffer);
    f->FramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, s->textures[0], 0);
    GLenum buffer = GL_COLOR_ATTACHMENT0;
    f->DrawBuffers(1, &buffer);
    f->Viewport(0, 0, s->width, s->height);
    f->Disable(GL_DEPTH_TEST);
    f->Disable(GL_SCISSOR_TEST);
    if (!colour_written)
        f->ClearBufferfv(GL_COLOR, 0, zero);
    if (outside) {
        program_state(s, outside, &st);
        program_state(s, zero_variant, &st);
    }
    program_state(s, program, &st);
    if (s->slab) {
        f->Disable(GL_BLEND);
    } else {
        /* front to back: dst += (1 - dst.a) * src, src premultiplied */
        f->Enable(GL_BLEND);
        f->BlendEquation(GL_FUNC_ADD);
        f->BlendFunc(GL_ONE_MINUS_DST_ALPHA, GL_ONE);
    }
    int interval = st.interval;
    int generate = s->frame && halo_program_reflection(s->linked).pass_count > 0;
    if (s->frame && !one_draw) {
        if (group <= 0)
            SLICE_RUNTIME(s, halo_gl_frame_begin(s->frame));
        if (group >= 0)
            SLICE_RUNTIME(s, halo_gl_frame_begin_group(s->frame));
        halo_gl_frame_attach(s->frame, s->framebuffer); /* buffer 0 keeps the blend set above */
        if (outside) {                                  /* sampler uniforms are set on the program in use */
            f->UseProgram(outside);
            halo_gl_frame_bind(s->frame, outside, 3);
            f->UseProgram(zero_variant);
            halo_gl_frame_bind(s->frame, zero_variant, 3);
            f->UseProgram(program);
        }
        halo_gl_frame_bind(s->frame, program, 3);
    }
    f->BindVertexArray(s->vertex_array);
    colour_mask(s, colour_written, 0);
    int current = 0;
    generation_skip skip;
    generation_skip_start(&skip, s, &st);
    halo_status drawn = HALO_OK; /* one_draw: the field and the slices (on failure: no image) */
    if (one_draw) {
        drawn = draw_over_field(s, &st, program, diag);
        f->Disable(GL_BLEND);
    } else if (!s->slab) {
        const GLuint programs[3] = {program, zero_variant, outside};
        const GLint at[3] = {f->GetUniformLocation(program, "slice_distance"),
                             zero_variant ? f->GetUniformLocation(zero_variant, "slice_distance") : -1,
                             outside ? f->GetUniformLocation(outside, "slice_distance") : -1};
        GLuint current = program;
        int clip = slices_clippable(s);
        for (int k = 0; k < st.slice_count; ++k) {
            float distance = (float)(st.first_distance + k * st.step_size);
            if (clip && s->frame && k % interval == 0) /* the slices of this interval draw nowhere else */
                halo_gl_frame_drawn_region(s->frame, 0, 0, 0, 0);
            if (clip) {
                f->Enable(GL_SCISSOR_TEST); /* a generation leaves it off */
                s->draws += draw_clipped_slice(s, programs, at, &current, distance);
            } else {
                f->Uniform1f(at[0], distance);
                f->DrawArrays(GL_TRIANGLES, 0, 3);
                s->draws++;
            }
            generation_skip_drawn(&skip, &st, k, 1);
            if (generate && (k + 1) % interval == 0 && k + 1 < st.slice_count)
                generation_run(&skip, s); /* clipped: the seeds are inside the boxes declared */
            if (s->progress)
                s->progress(k + 1, st.slice_count, s->progress_user);
        }
        f->Disable(GL_BLEND);
        f->Disable(GL_SCISSOR_TEST);
    } else {
        GLint first_location = f->GetUniformLocation(program, "first_distance");
        GLint samples_location = f->GetUniformLocation(program, "slab_samples");
        for (int k = 0; k < st.slice_count; k += interval) {
            int samples = st.slice_count - k < interval ? st.slice_count - k : interval;
            f->FramebufferTexture2D(GL_DRAW_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, s->textures[1 - current],
                                    0);
            f->ActiveTexture(GL_TEXTURE2);
            f->BindTexture(GL_TEXTURE_2D, s->textures[current]);
            f->ActiveTexture(GL_TEXTURE0);
            f->Uniform1f(first_location, (float)(st.first_distance + k * st.step_size));
            f->Uniform1i(samples_location, samples);
            f->DrawArrays(GL_TRIANGLES, 0, 3);
            s->draws++;
            generation_skip_drawn(&skip, &st, k, samples);
            current = 1 - current;
            if (generate && k + interval < st.slice_count)
                generation_run(&skip, s);
            if (s->progress)
                s->progress((int)s->draws, (st.slice_count + interval - 1) / interval, s->progress_user);
        }
        f->ActiveTexture(GL_TEXTURE2);
        f->BindTexture(GL_TEXTURE_2D, 0);
        f->ActiveTexture(GL_TEXTURE0);
        f->BindFramebuffer(GL_FRAMEBUFFER, s->framebuffer);
        f->FramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, s->textures[current], 0);
    }
    colour_mask(s, colour_written, 1);
    if (group >= 0)
        SLICE_RUNTIME(s, halo_gl_frame_end_group(s->frame));
    if (!colour_written && drawn == HALO_OK) {
        f->BindFramebuffer(GL_READ_FRAMEBUFFER, s->framebuffer);
        f->ReadBuffer(GL_COLOR_ATTACHMENT0);
        f->PixelStorei(GL_PACK_ALIGNMENT, 4);
        f->ReadPixels(0, 0, s->width, s->height, GL_RGBA, GL_FLOAT, rgba);
    }
    f->DrawBuffers(1, &buffer);
    f->FramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, s->textures[0], 0);
    f->BindVertexArray(0);
    f->UseProgram(0);
    f->ActiveTexture(GL_TEXTURE1);
    f->BindTexture(GL_TEXTURE_2D, 0);
    if (s->labels_texture) {
        f->ActiveTexture(GL_TEXTURE0 + HALO_SLICE_LABEL_UNIT);
        f->BindTexture(GL_TEXTURE_3D, 0);
    }
    f->ActiveTexture(GL_TEXTURE0 + HALO_SLICE_GRADIENT_UNIT);
    f->BindTexture(GL_TEXTURE_3D, 0);
    f->ActiveTexture(GL_TEXTURE0);
    f->BindTexture(GL_TEXTURE_3D, 0);
    f->BindFramebuffer(GL_FRAMEBUFFER, 0);
    s->pass_draws = halo_gl_frame_describe(s->frame).pass_draws - pass_draws_before;
    if (drawn != HALO_OK)
        return drawn;
    GLenum error = f->GetError();
    if (error != GL_NO_ERROR) {
        HALO_REPORT_ERROR(diag, HALO_MSG_GL_LINK, "", 0, 0, "OpenGL error 0x%x while rendering slices", error);
        return HALO_ERROR_IO;
    }
    /* the background, behind what the slices left transparent */
    size_t pixels = colour_written ? 0 : (size_t)s->width * (size_t)s->height;
    for (size_t i = 0; i < pixels; ++i) {
        float *px = &rgba[i * 4];
        float a = px[3];
        for (int c = 0; c < 3; ++c)
            px[c] = px[c] + (1.0f - a) * s->background[c];
        px[3] = 1.0f;
    }
    return HALO_OK;
}
