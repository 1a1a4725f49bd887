/* The C side of the example hosts (see raycast.h). */
#include "raycast.h"
#include "host_common.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>


char *halo_host_load(const char *name, const char *override_path, halo_diagnostics *diag)
{
    if (override_path) {
        return halo_read_text_file(override_path, "host shader", NULL, diag);
    }
    const char *embedded = halo_host_embedded(name);
    if (!embedded) {
        HALO_REPORT_ERROR(diag, HALO_MSG_IO_READ, name ? name : "", 0, 0, "no embedded host shader '%s'",
                          name ? name : "");
        return NULL;
    }
    size_t n = strlen(embedded);
    char *copy = malloc(n + 1);
    if (!copy) {
        HALO_REPORT_ERROR(diag, HALO_MSG_OUT_OF_MEMORY, name, 0, 0, "out of memory");
        return NULL;
    }
    memcpy(copy, embedded, n + 1);
    return copy;
}

char *halo_host_mip_variant(const char *source)
{
    static const char off[] = "//#define MIP\n//#pragma halo compositing mip\n";
    const char *at = source ? strstr(source, off) : NULL;
    char *text = at ? malloc(strlen(source) + 1) : NULL;
    if (!text)
        return NULL;
    size_t head = (size_t)(at - source);
    memcpy(text, source, head);
    strcpy(text + head, "#define MIP\n#pragma halo compositing mip\n");
    strcat(text, at + sizeof off - 1);
    return text;
}

/* ---- Programs and targets ---------------------------------------------------------- */

/* The parts both hosts share: program, full-screen triangle, RGBA32F target. */
typedef struct host_target {
    const halo_glfuncs *f;
    halo_gl *runtime;
    const halo_program *linked;
    GLuint program, vertex_array, framebuffer, color_texture;
    int width, height;
} host_target;

static int host_target_init(host_target *t, const halo_host_desc *desc, const char *default_fragment,
                            halo_diagnostics *diag)
{
    memset(t, 0, sizeof *t);
    if (!halo_host_desc_check(desc, diag))
        return 0;
    const halo_glfuncs *f = desc->gl;
    t->f = f;
    t->runtime = desc->runtime;
    t->linked = desc->program;
    t->width = desc->width;
    t->height = desc->height;
    t->program = halo_host_program_build(desc, "raycast.vert", default_fragment, HALO_HOST_LOG_LINES, diag);
    if (!t->program)
        return 0;

    f->GenVertexArrays(1, &t->vertex_array);
    f->GenTextures(1, &t->color_texture);
    halo_host_image_texture(f, t->color_texture, GL_RGBA32F, t->width, t->height, GL_RGBA, GL_FLOAT);
    return halo_host_framebuffer(f, &t->framebuffer, t->color_texture, t->width, t->height, diag);
}

static void host_target_release(host_target *t)
{
    const halo_glfuncs *f = t->f;
    if (!f)
        return;
    /* glDelete* passes over the names never made (0) */
    f->DeleteFramebuffers(1, &t->framebuffer);
    f->DeleteTextures(1, &t->color_texture);
    f->DeleteVertexArrays(1, &t->vertex_array);
    f->DeleteProgram(t->program);
    memset(t, 0, sizeof *t);
}

/* Binds program and target; the caller sets its uniforms and textures, then draws. */
static void host_target_begin(host_target *t)
{
    const halo_glfuncs *f = t->f;
    f->BindFramebuffer(GL_FRAMEBUFFER, t->framebuffer);
    GLenum buffer = GL_COLOR_ATTACHMENT0;
    f->DrawBuffers(1, &buffer);
    f->Viewport(0, 0, t->width, t->height);
    f->Disable(GL_BLEND);
    f->Disable(GL_DEPTH_TEST);
    f->Disable(GL_SCISSOR_TEST);
    f->UseProgram(t->program);
    if (t->linked)
        halo_gl_program_upload(t->runtime, t->linked, t->program);
}

static halo_status host_target_read(host_target *t, float *rgba, halo_diagnostics *diag);

static halo_status host_target_draw(host_target *t, float *rgba, halo_diagnostics *diag)
{
    const halo_glfuncs *f = t->f;
    f->BindVertexArray(t->vertex_array);
    f->DrawArrays(GL_TRIANGLES, 0, 3);
    return host_target_read(t, rgba, diag);
}

/* Reads the target back and unbinds program and target. */
static halo_status host_target_read(host_target *t, float *rgba, halo_diagnostics *diag)
{
    const halo_glfuncs *f = t->f;
    f->BindFramebuffer(GL_FRAMEBUFFER, t->framebuffer);
    f->ReadBuffer(GL_COLOR_ATTACHMENT0);
    f->PixelStorei(GL_PACK_ALIGNMENT, 4);
    f->ReadPixels(0, 0, t->width, t->height, GL_RGBA, GL_FLOAT, rgba);
    f->BindVertexArray(0);
    f->UseProgram(0);
    f->BindFramebuffer(GL_FRAMEBUFFER, 0);
    GLenum error = f->GetError();
    if (error != GL_NO_ERROR) {
        HALO_REPORT_ERROR(diag, HALO_MSG_GL_LINK, "", 0, 0, "OpenGL error 0x%x while rendering", error);
        return HALO_ERROR_IO;
    }
    return HALO_OK;
}

/* ---- The ray caster ------------------------------------------------------------------ */

/* A host of size bytes (a struct whose first member is its host_target), zeroed, with
 * its target set up for default_fragment; NULL (diagnostics in diag) on failure. */
static void *host_create(size_t size, const halo_host_desc *desc, const char *default_fragment, halo_diagnostics *diag)
{
    host_target *t = halo_host_calloc(size, diag);
    if (!t)
        return NULL;
    if (!host_target_init(t, desc, default_fragment, diag)) {
        host_target_release(t);
        free(t);
        return NULL;
    }
    return t;
}

struct halo_raycast {
    host_target target;
    GLuint volume_texture, transfer_texture;
    const float *volume;
    int dims[3];
    int volume_version; /* halo_gl_segments_desc.volume_version: one more at every upload of a volume or a piece */
    float transfer[HALO_RAYCAST_TRANSFER_TEXELS * 4];
    float inverse_view_projection[16];
    float eye[3];
    float screen_right[3], screen_up[3];
    float step_voxels;
    float background[3];
    halo_gl_frame *frame; /* a program with images, outputs or segments (host contract 2) */
    int interval, segments;
    int orthographic;
    float jitter;           /* the uniform `jitter` of hosts that jitter their first sample */
    float seed_epsilon;     /* host contract 3: halo_gl_segments_desc.seed_epsilon */
    int gradient_precision; /* ... and .gradient_precision */
    GLuint piece_texture;   /* ... and a piece (halo_raycast_set_piece), 0: none */
    int piece_dims[3];
    float piece_min[3], piece_max[3];
    void (*exchange)(void *user, float *values, size_t count, halo_blend blend);
    void *exchange_user;
    size_t exchange_max_bytes;
    size_t field_max_bytes;                              /* halo_gl_segments_desc.field_max_bytes */
    GLuint exit_program, exit_texture, exit_framebuffer; /* halo_raycast_set_exit_points */
    GLuint classified_texture;                           /* halo_raycast_set_classified, 0: none */
    float view_step;                                     /* halo_raycast_set_view's step, 0: the settings' */
    void (*untidy)(void *user, int before_draw);         /* halo_raycast_set_untidy */
    void *untidy_user;
};

/* The state the host's draw needs, set before it draws (an untidy host left other). */
static void host_draw_state(const halo_glfuncs *f)
{
    f->Disable(GL_CULL_FACE);
    f->Disable(GL_DEPTH_TEST);
    f->Disable(GL_STENCIL_TEST);
    f->Disable(GL_BLEND);
    f->Disable(GL_SCISSOR_TEST);
    f->Disable(GL_RASTERIZER_DISCARD);
    f->Disable(GL_FRAMEBUFFER_SRGB);
    if (f->PolygonMode)
        f->PolygonMode(GL_FRONT_AND_BACK, GL_FILL);
    f->ColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    f->PixelStorei(GL_PACK_ALIGNMENT, 4);
    f->PixelStorei(GL_PACK_ROW_LENGTH, 0);
    f->PixelStorei(GL_PACK_SKIP_ROWS, 0);
    f->PixelStorei(GL_PACK_SKIP_PIXELS, 0);
}

/* The proxy geometry: one full-screen triangle (halo_gl_segments_desc.draw). */
static void draw_proxy(void *user)
{
    halo_raycast *r = user;
    if (r->untidy) {
        r->untidy(r->untidy_user, 1);
        host_draw_state(r->target.f);
        r->target.f->Viewport(0, 0, r->target.width, r->target.height);
    }
    r->target.f->BindVertexArray(r->target.vertex_array);
    r->target.f->DrawArrays(GL_TRIANGLES, 0, 3);
    if (r->untidy)
        r->untidy(r->untidy_user, 0);
}

halo_raycast *halo_raycast_create(const halo_host_desc *desc, halo_diagnostics *diag)
{
    halo_raycast *r = host_create(sizeof *r, desc, "raycast.frag", diag);
    if (!r)
        return NULL;
    const halo_glfuncs *f = r->target.f;
    const halo_program *p = desc->program;
    if (p && (halo_program_reflection(p).image_count || halo_program_reflection(p).output_count ||
              halo_program_reflection(p).sampler_count || halo_program_reflection(p).segment_location > 0)) {
        r->frame = halo_gl_frame_create(desc->runtime, p, desc->width, desc->height, diag);
        if (!r->frame) {
            halo_raycast_destroy(r);
            return NULL;
        }
    }
    f->GenTextures(1, &r->volume_texture);
    f->GenTextures(1, &r->transfer_texture);
    halo_raycast_set_render(r, NULL, diag);
    halo_raycast_set_camera(r, 30.0, 20.0, 1.0);
    return r;
}

void halo_raycast_destroy(halo_raycast *r)
{
    if (!r)
        return;
    const halo_glfuncs *f = r->target.f;
    halo_gl_frame_destroy(r->frame);
    if (f) {
        f->DeleteTextures(1, &r->volume_texture);
        f->DeleteTextures(1, &r->transfer_texture);
        if (r->piece_texture)
            f->DeleteTextures(1, &r->piece_texture);
        f->DeleteProgram(r->exit_program);
        f->DeleteTextures(1, &r->exit_texture);
        f->DeleteFramebuffers(1, &r->exit_framebuffer);
        if (r->classified_texture)
            f->DeleteTextures(1, &r->classified_texture);
    }
    host_target_release(&r->target);
    free(r);
}

unsigned halo_raycast_gl_program(const halo_raycast *r) { return r ? r->target.program : 0; }

halo_status halo_raycast_set_volume(halo_raycast *r, const float *data, int nx, int ny, int nz, halo_diagnostics *diag)
{
    halo_status status =
        halo_host_upload_volume(r ? r->target.f : NULL, r ? r->volume_texture : 0, data, nx, ny, nz, diag);
    if (status != HALO_OK)
        return status;
    r->volume = data;
    r->volume_version++;
    r->dims[0] = nx;
    r->dims[1] = ny;
    r->dims[2] = nz;
    return HALO_OK;
}

halo_status halo_raycast_set_render(halo_raycast *r, const halo_render_settings *settings, halo_diagnostics *diag)
{
    if (!r)
        return HALO_ERROR_INPUT;
    return halo_host_upload_transfer(r->target.f, r->transfer_texture, r->transfer, settings, &r->step_voxels,
                                     r->background, diag);
}

/* ---- Camera ---------------------------------------------------------------------------- */

void halo_raycast_set_camera(halo_raycast *r, double azimuth, double elevation, double zoom)
{
    if (!r)
        return;
    halo_host_camera camera;
    if (!halo_host_orbit_camera_projection(azimuth, elevation, zoom, r->target.width, r->target.height, r->orthographic,
                                           &camera))
        return;
    halo_host_camera_keep(&camera, r->inverse_view_projection, r->eye, r->screen_right, r->screen_up);
    r->view_step = 0.0f;
}

void halo_raycast_set_view(halo_raycast *r, const double inverse_view_projection[16], double step)
{
    if (!r || !inverse_view_projection)
        return;
    float *axes[2] = {r->screen_right, r->screen_up};
    for (int i = 0; i < 16; ++i)
        r->inverse_view_projection[i] = (float)inverse_view_projection[i];
    for (int a = 0; a < 2; ++a) { /* column a: where clip (1, 0, 0, 0) or (0, 1, 0, 0) goes */
        const double *v = inverse_view_projection + 4 * a;
        double length = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
        for (int c = 0; c < 3; ++c)
            axes[a][c] = (float)(length > 0.0 ? v[c] / length : 0.0);
    }
    /* the eye: where clip (0, 0, 1, 0) maps to for a perspective camera (w != 0); for an
     * orthographic one a point ten units back from the volume's centre against the view */
    const double *e = inverse_view_projection + 8;
    double length = sqrt(e[0] * e[0] + e[1] * e[1] + e[2] * e[2]);
    for (int c = 0; c < 3; ++c)
        r->eye[c] = e[3] != 0.0 ? (float)(e[c] / e[3]) : length > 0.0 ? (float)(0.5 - 10.0 * e[c] / length) : 0.5f;
    r->view_step = step > 0.0 && isfinite(step) ? (float)step : 0.0f;
}

halo_gl_frame *halo_raycast_frame(const halo_raycast *r) { return r ? r->frame : NULL; }

void halo_raycast_set_orthographic(halo_raycast *r, int orthographic)
{
    if (r)
        r->orthographic = orthographic != 0;
}

void halo_raycast_set_segments(halo_raycast *r, int interval, int segments)
{
    if (r) {
        r->interval = interval > 0 ? interval : 0;
        r->segments = segments > 0 ? segments : 0;
    }
}

void halo_raycast_set_untidy(halo_raycast *r, void (*untidy)(void *user, int before_draw), void *user)
{
    if (!r)
        return;
    r->untidy = untidy;
    r->untidy_user = user;
}

void halo_raycast_set_exchange_max_bytes(halo_raycast *r, size_t bytes)
{
    if (r)
        r->exchange_max_bytes = bytes;
}

void halo_raycast_set_field_max_bytes(halo_raycast *r, size_t bytes)
{
    if (r)
        r->field_max_bytes = bytes;
}

halo_status halo_raycast_set_piece(halo_raycast *r, const float *data, int nx, int ny, int nz, const float piece_min[3],
                                   const float piece_max[3],
                                   void (*exchange)(void *user, float *values, size_t count, halo_blend blend),
                                   void *user, halo_diagnostics *diag)
{
    if (!r)
        return HALO_ERROR_INPUT;
    if (!data || !exchange) { /* a piece without the others' seeds would be drawn alone: none */
        r->exchange = NULL;
        memset(r->piece_min, 0, sizeof r->piece_min);
        memset(r->piece_max, 0, sizeof r->piece_max);
        return HALO_OK;
    }
    if (!r->piece_texture)
        r->target.f->GenTextures(1, &r->piece_texture);
    halo_status status = halo_host_upload_volume(r->target.f, r->piece_texture, data, nx, ny, nz, diag);
    r->volume_version++;
    if (status != HALO_OK)
        return status;
    r->piece_dims[0] = nx;
    r->piece_dims[1] = ny;
    r->piece_dims[2] = nz;
    memcpy(r->piece_min, piece_min, sizeof r->piece_min);
    memcpy(r->piece_max, piece_max, sizeof r->piece_max);
    r->exchange = exchange;
    r->exchange_user = user;
    return HALO_OK;
}

void halo_raycast_set_gradient_precision(halo_raycast *r, int bits)
{
    if (r)
        r->gradient_precision = bits;
}

void halo_raycast_set_seed_epsilon(halo_raycast *r, float epsilon)
{
    if (r)
        r->seed_epsilon = epsilon > 0.0f ? epsilon : 0.0f;
}

void halo_raycast_set_jitter(halo_raycast *r, float jitter)
{
    if (r)
        r->jitter = jitter;
}

halo_status halo_raycast_set_exit_points(halo_raycast *r, halo_diagnostics *diag)
{
    if (!r)
        return HALO_ERROR_INPUT;
    const halo_glfuncs *f = r->target.f;
    if (!r->exit_program) {
        r->exit_program =
            halo_host_link_raw(f, halo_host_embedded("exit_points.vert"), "exit_points.vert",
                               halo_host_embedded("exit_points.frag"), "exit_points.frag", HALO_HOST_LOG_LINES, diag);
        if (!r->exit_program)
            return HALO_ERROR_IO;
        f->GenTextures(1, &r->exit_texture);
        halo_host_image_texture(f, r->exit_texture, GL_RGBA32F, r->target.width, r->target.height, GL_RGBA, GL_FLOAT);
        f->BindTexture(GL_TEXTURE_2D, 0);
        if (!halo_host_framebuffer(f, &r->exit_framebuffer, r->exit_texture, r->target.width, r->target.height, diag))
            return HALO_ERROR_IO;
    }
    return HALO_OK;
}

halo_status halo_raycast_set_classified(halo_raycast *r, const float *rgba, int nx, int ny, int nz,
                                        halo_diagnostics *diag)
{
    if (!r || !rgba) {
        HALO_REPORT_ERROR(diag, HALO_MSG_USAGE, "", 0, 0, "classified volume: no ray caster or no texels");
        return HALO_ERROR_INPUT;
    }
    if (!r->classified_texture)
        r->target.f->GenTextures(1, &r->classified_texture);
    return halo_host_upload_classified(r->target.f, r->classified_texture, rgba, nx, ny, nz, diag);
}

/* The first pass of a two-pass caster: the box's back faces into the exit-point
 * texture, which is left bound to unit 2. */
static void draw_exit_points(halo_raycast *r)
{
    const halo_glfuncs *f = r->target.f;
    double inverse[16], view_projection[16];
    float matrix[16];
    for (int i = 0; i < 16; ++i)
        inverse[i] = r->inverse_view_projection[i];
    halo_host_matrix_invert(inverse, view_projection);
    for (int i = 0; i < 16; ++i)
        matrix[i] = (float)view_projection[i];
    f->BindFramebuffer(GL_FRAMEBUFFER, r->exit_framebuffer);
    f->Viewport(0, 0, r->target.width, r->target.height);
    f->ClearColor(0.0f, 0.0f, 0.0f, 0.0f);
    f->Clear(GL_COLOR_BUFFER_BIT);
    f->Enable(GL_CULL_FACE); /* the default GL_BACK: the shader's triangles face inwards */
    f->UseProgram(r->exit_program);
    f->UniformMatrix4fv(f->GetUniformLocation(r->exit_program, "view_projection"), 1, GL_FALSE, matrix);
    f->BindVertexArray(r->target.vertex_array);
    f->DrawArrays(GL_TRIANGLES, 0, 36);
    f->Disable(GL_CULL_FACE);
    f->ActiveTexture(GL_TEXTURE2);
    f->BindTexture(GL_TEXTURE_2D, r->exit_texture);
}

void halo_raycast_get_state(const halo_raycast *r, halo_raycast_state *s)
{
    memset(s, 0, sizeof *s);
    if (!r)
        return;
    s->width = r->target.width;
    s->height = r->target.height;
    for (int i = 0; i < 16; ++i)
        s->inverse_view_projection[i] = r->inverse_view_projection[i];
    int voxels = r->volume ? halo_host_max_dimension(r->dims) : 1;
    float unit_step = 1.0f / (float)voxels;
    for (int c = 0; c < 3; ++c) {
        s->eye[c] = r->eye[c];
        s->screen_right[c] = r->screen_right[c];
        s->screen_up[c] = r->screen_up[c];
        s->background[c] = r->background[c];
        s->dims[c] = r->dims[c];
    }
    s->unit_step = unit_step;
    s->step_size = r->view_step > 0.0f ? r->view_step : (float)(r->step_voxels * unit_step);
    s->transfer_texels = HALO_RAYCAST_TRANSFER_TEXELS;
    s->transfer = r->transfer;
    s->volume = r->volume;
}

halo_status halo_raycast_render(halo_raycast *r, float *rgba, halo_diagnostics *diag)
{
    if (!r || !rgba)
        return HALO_ERROR_INPUT;
    if (!r->volume) {
        HALO_REPORT_ERROR(diag, HALO_MSG_USAGE, "", 0, 0, "ray caster: no volume uploaded");
        return HALO_ERROR_INPUT;
    }
    halo_raycast_state s;
    halo_raycast_get_state(r, &s);
    const halo_glfuncs *f = r->target.f;
    GLuint program = r->target.program;
    if (r->exit_program)
        draw_exit_points(r);
    host_target_begin(&r->target);
    f->ActiveTexture(GL_TEXTURE0);
    f->BindTexture(GL_TEXTURE_3D, r->volume_texture);
    f->ActiveTexture(GL_TEXTURE1);
    f->BindTexture(GL_TEXTURE_2D, r->transfer_texture);
    f->ActiveTexture(GL_TEXTURE0);
    /* Locations of -1 (a uniform the compiler removed) are ignored by glUniform*. */
    f->Uniform1i(f->GetUniformLocation(program, "volume_texture"), 0);
    f->Uniform1i(f->GetUniformLocation(program, "transfer_texture"), 1);
    f->UniformMatrix4fv(f->GetUniformLocation(program, "inverse_view_projection"), 1, GL_FALSE,
                        r->inverse_view_projection);
    f->Uniform3fv(f->GetUniformLocation(program, "eye"), 1, r->eye);
    f->Uniform1f(f->GetUniformLocation(program, "step_size"), (float)s.step_size);
    f->Uniform1f(f->GetUniformLocation(program, "unit_step"), (float)s.unit_step);
    f->Uniform3fv(f->GetUniformLocation(program, "background"), 1, r->background);
    f->Uniform1f(f->GetUniformLocation(program, "jitter"), r->jitter);
    f->Uniform1i(f->GetUniformLocation(program, "exit_points"), 2);
    if (r->classified_texture) {
        f->ActiveTexture(GL_TEXTURE3);
        f->BindTexture(GL_TEXTURE_3D, r->classified_texture);
        f->ActiveTexture(GL_TEXTURE0);
        f->Uniform1i(f->GetUniformLocation(program, "color_volume"), 3);
    }
    halo_status status = HALO_OK;
    halo_gl_segments_desc segments = {.inverse_view_projection = r->inverse_view_projection,
                                      .step = (float)s.step_size,
                                      .interval = r->interval,
                                      .segments = r->segments,
                                      .framebuffer = r->target.framebuffer,
                                      .volume_texture = r->exchange ? r->piece_texture : r->volume_texture,
                                      .volume_version = r->volume_version,
                                      .volume_size = {r->exchange ? r->piece_dims[0] : r->dims[0],
                                                      r->exchange ? r->piece_dims[1] : r->dims[1],
                                                      r->exchange ? r->piece_dims[2] : r->dims[2]},
                                      .piece_min = {r->piece_min[0], r->piece_min[1], r->piece_min[2]},
                                      .piece_max = {r->piece_max[0], r->piece_max[1], r->piece_max[2]},
                                      .exchange = r->exchange,
                                      .exchange_user = r->exchange_user,
                                      .exchange_max_bytes = r->exchange_max_bytes,
                                      .field_max_bytes = r->field_max_bytes,
                                      .seed_epsilon = r->seed_epsilon,
                                      .gradient_precision = r->gradient_precision,
                                      .draw = draw_proxy,
                                      .user = r};
    if (r->frame) {
        /* host contract 2: libhalo draws the proxy, once or once per depth segment */
        halo_gl_set_host_uniform(r->target.runtime, program, "screen_right", r->screen_right, 3);
        halo_gl_set_host_uniform(r->target.runtime, program, "screen_up", r->screen_up, 3);
        if (r->untidy) /* the state an untidy host leaves for libhalo's first call */
            r->untidy(r->untidy_user, 0);
        status = halo_gl_frame_draw(r->frame, program, &segments, diag);
        if (r->untidy) {
            r->untidy(r->untidy_user, 2);
            host_draw_state(f);
        }
        if (status == HALO_OK)
            status = host_target_read(&r->target, rgba, diag);
        if (status == HALO_OK)
            status = halo_host_post_passes(r->frame, r->target.linked, r->target.color_texture, r->target.width,
                                           r->target.height, rgba, diag);
    } else {
        /* the camera of halo_view_at and halo_depth_at (a v2 host drawn once) */
        if (r->target.linked)
            status = halo_gl_set_camera(r->target.runtime, program, &segments, diag);
        if (status == HALO_OK)
            status = host_target_draw(&r->target, rgba, diag);
    }
    f->ActiveTexture(GL_TEXTURE3);
    f->BindTexture(GL_TEXTURE_3D, 0);
    f->ActiveTexture(GL_TEXTURE2);
    f->BindTexture(GL_TEXTURE_2D, 0);
    f->ActiveTexture(GL_TEXTURE1);
    f->BindTexture(GL_TEXTURE_2D, 0);
    f->ActiveTexture(GL_TEXTURE0);
    f->BindTexture(GL_TEXTURE_3D, 0);
    return status;
}

/* ---- The conformance probe ---------------------------------------------------------- */

enum { PROBE_POSITION_VALUE, PROBE_GRADIENT_DEPTH, PROBE_VIEW, PROBE_COLOR_OPACITY, PROBE_TEXTURES };
static const char *const probe_samplers[PROBE_TEXTURES] = {"position_value", "gradient_depth", "view_texture",
                                                           "color_opacity"};

struct halo_probe {
    host_target target;
    GLuint textures[PROBE_TEXTURES];
    float *staging; /* width*height*4 floats */
};

halo_probe *halo_probe_create(const halo_host_desc *desc, halo_diagnostics *diag)
{
    halo_probe *p = host_create(sizeof *p, desc, "probe.frag", diag);
    if (!p)
        return NULL;
    p->staging = malloc((size_t)p->target.width * (size_t)p->target.height * 4 * sizeof(float));
    if (!p->staging) {
        HALO_REPORT_ERROR(diag, HALO_MSG_OUT_OF_MEMORY, "", 0, 0, "out of memory");
        halo_probe_destroy(p);
        return NULL;
    }
    const halo_glfuncs *f = p->target.f;
    f->GenTextures(PROBE_TEXTURES, p->textures);
    for (int i = 0; i < PROBE_TEXTURES; ++i) {
        halo_host_image_texture(f, p->textures[i], GL_RGBA32F, p->target.width, p->target.height, GL_RGBA, GL_FLOAT);
    }
    f->BindTexture(GL_TEXTURE_2D, 0);
    return p;
}

void halo_probe_destroy(halo_probe *p)
{
    if (!p)
        return;
    if (p->target.f && p->textures[0])
        p->target.f->DeleteTextures(PROBE_TEXTURES, p->textures);
    host_target_release(&p->target);
    free(p->staging);
    free(p);
}

void halo_probe_round_inputs(halo_emu_sample *s, int x, int y)
{
    for (int c = 0; c < 3; ++c) {
        s->position[c] = (float)s->position[c];
        s->gradient[c] = (float)s->gradient[c];
        s->view[c] = (float)s->view[c];
        s->color[c] = (float)s->color[c];
    }
    s->value = (float)s->value;
    s->depth = (float)s->depth;
    s->opacity = (float)s->opacity;
    s->fragcoord[0] = x + 0.5;
    s->fragcoord[1] = y + 0.5;
}

halo_status halo_probe_run(halo_probe *p, const halo_emu_sample *samples, float *rgba, halo_diagnostics *diag)
{
    if (!p || !samples || !rgba)
        return HALO_ERROR_INPUT;
    const halo_glfuncs *f = p->target.f;
    size_t n = (size_t)p->target.width * (size_t)p->target.height;
    for (int t = 0; t < PROBE_TEXTURES; ++t) {
        for (size_t i = 0; i < n; ++i) {
            const halo_emu_sample *s = &samples[i];
            float *dst = &p->staging[i * 4];
            switch (t) {
            case PROBE_POSITION_VALUE:
                dst[0] = (float)s->position[0], dst[1] = (float)s->position[1], dst[2] = (float)s->position[2];
                dst[3] = (float)s->value;
                break;
            case PROBE_GRADIENT_DEPTH:
                dst[0] = (float)s->gradient[0], dst[1] = (float)s->gradient[1], dst[2] = (float)s->gradient[2];
                dst[3] = (float)s->depth;
                break;
            case PROBE_VIEW:
                dst[0] = (float)s->view[0], dst[1] = (float)s->view[1], dst[2] = (float)s->view[2];
                dst[3] = 0.0f;
                break;
            default:
                dst[0] = (float)s->color[0], dst[1] = (float)s->color[1], dst[2] = (float)s->color[2];
                dst[3] = (float)s->opacity;
                break;
            }
        }
        f->BindTexture(GL_TEXTURE_2D, p->textures[t]);
        f->PixelStorei(GL_UNPACK_ALIGNMENT, 4);
        f->TexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, p->target.width, p->target.height, GL_RGBA, GL_FLOAT, p->staging);
    }
    host_target_begin(&p->target);
    for (int t = 0; t < PROBE_TEXTURES; ++t) {
        f->ActiveTexture(GL_TEXTURE0 + (GLenum)t);
        f->BindTexture(GL_TEXTURE_2D, p->textures[t]);
        f->Uniform1i(f->GetUniformLocation(p->target.program, probe_samplers[t]), t);
    }
    f->ActiveTexture(GL_TEXTURE0);
    halo_status status = host_target_draw(&p->target, rgba, diag);
    for (int t = PROBE_TEXTURES - 1; t >= 0; --t) {
        f->ActiveTexture(GL_TEXTURE0 + (GLenum)t);
        f->BindTexture(GL_TEXTURE_2D, 0);
    }
    return status;
}
