/* The C side of the example line host (see lines.h). */
#include "lines.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "host_common.h" /* halo_host_embedded, halo_host_matrix_multiply */

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

/* Field of view across the smaller image side, degrees. */
#define LINES_FIELD_OF_VIEW 30.0

void halo_lines_scene_keep_hook(halo_scene *scene, const halo_library *lib, halo_hook hook)
{
    if (!scene || !lib)
        return;
    /* disabling a stage keeps it in the scene's list: info stays valid */
    halo_scene_info info = halo_scene_describe(scene);
    for (size_t i = info.stage_count; i-- > 0;) {
        const char *name = info.stages[i];
        const halo_module *m = halo_library_find(lib, name);
        if (m && halo_module_describe(m).hook != hook)
            halo_scene_enable(scene, name, 0, NULL);
    }
}

static halo_scene *scene_for_hook(const halo_library *lib, const char *path, const char *text, halo_hook hook,
                                  halo_diagnostics *diag)
{
    halo_scene *scene = path   ? halo_scene_load(path, NULL, lib, diag)
                        : text ? halo_scene_load("scene", text, lib, diag)
                               : halo_scene_create(lib);
    halo_lines_scene_keep_hook(scene, lib, hook);
    return scene;
}

halo_status halo_lines_link_scenes(const halo_library *lib, const halo_scene *vertex_scene,
                                   const halo_scene *fragment_scene, const char *vertex_source,
                                   const char *fragment_source, halo_program **vertex, halo_program **fragment,
                                   halo_diagnostics *diag)
{
    *vertex = *fragment = NULL;
    if (!lib) {
        HALO_REPORT_ERROR(diag, HALO_MSG_USAGE, "", 0, 0, "halo_lines_link: a library is required");
        return HALO_ERROR_INPUT;
    }
    const char *vs = vertex_source ? vertex_source : halo_host_embedded("line.vert");
    const char *fs = fragment_source ? fragment_source : halo_host_embedded("line.frag");
    if (!vs || !fs) {
        HALO_REPORT_ERROR(diag, HALO_MSG_IO_READ, "line.vert", 0, 0, "the line host shaders are not embedded");
        return HALO_ERROR_IO;
    }
    *vertex = halo_link(&(halo_link_desc){.library = lib,
                                          .scene = vertex_scene,
                                          .host_source = vs,
                                          .host_file = "line.vert",
                                          .kind = HALO_SHADER_VERTEX},
                        diag);
    *fragment = halo_link(&(halo_link_desc){.library = lib,
                                            .scene = fragment_scene,
                                            .host_source = fs,
                                            .host_file = "line.frag",
                                            .kind = HALO_SHADER_FRAGMENT},
                          diag);
    if (!*vertex || !*fragment) {
        halo_program_destroy(*vertex);
        halo_program_destroy(*fragment);
        *vertex = *fragment = NULL;
        return HALO_ERROR_INPUT;
    }
    return HALO_OK;
}

halo_status halo_lines_link(const halo_library *lib, const char *scene_path, const char *scene_text,
                            const char *vertex_source, const char *fragment_source, halo_program **vertex,
                            halo_program **fragment, halo_diagnostics *diag)
{
    *vertex = *fragment = NULL;
    if (!lib) {
        HALO_REPORT_ERROR(diag, HALO_MSG_USAGE, "", 0, 0, "halo_lines_link: a library is required");
        return HALO_ERROR_INPUT;
    }
    halo_scene *vertex_scene = scene_for_hook(lib, scene_path, scene_text, HALO_HOOK_LINE_VERTEX, diag);
    if (!vertex_scene)
        return HALO_ERROR_INPUT;
    halo_scene *fragment_scene = scene_for_hook(lib, scene_path, scene_text, HALO_HOOK_LINE_FRAGMENT, NULL);
    halo_status status = fragment_scene ? halo_lines_link_scenes(lib, vertex_scene, fragment_scene, vertex_source,
                                                                 fragment_source, vertex, fragment, diag)
                                        : HALO_ERROR_INPUT;
    halo_scene_destroy(vertex_scene);
    halo_scene_destroy(fragment_scene);
    return status;
}

/* ---- Programs ------------------------------------------------------------------------ */

unsigned halo_lines_build_program(const halo_glfuncs *f, const halo_program *vertex_program, const char *vertex_source,
                                  const char *vertex_file, const halo_program *fragment_program,
                                  const char *fragment_source, const char *fragment_file, halo_diagnostics *diag)
{
    if (!f) {
        HALO_REPORT_ERROR(diag, HALO_MSG_USAGE, "", 0, 0, "halo_lines_build_program: no GL functions");
        return 0;
    }
    vertex_file = vertex_file ? vertex_file : "vertex shader";
    fragment_file = fragment_file ? fragment_file : "fragment shader";
    if (vertex_program)
        vertex_source = halo_program_source(vertex_program, HALO_PIECE_WHOLE);
    if (fragment_program)
        fragment_source = halo_program_source(fragment_program, HALO_PIECE_WHOLE);
    if (!vertex_source || !fragment_source) {
        const char *file = vertex_source ? fragment_file : vertex_file;
        HALO_REPORT_ERROR(diag, HALO_MSG_GL_COMPILE, file, 0, 0, "no shader text for '%s'", file);
        return 0;
    }
    return halo_host_link_mapped(f, vertex_program, vertex_source, vertex_file, fragment_program, fragment_source,
                                 fragment_file, HALO_HOST_LOG_LINES, diag);
}

/* ---- Strip geometry --------------------------------------------------------------------- */

/* Unit vector from a to b, or 0 for coincident points. */
static int unit_between(const double *a, const double *b, double out[3])
{
    double d[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
    double n = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    if (!(n > 0.0)) {
        out[0] = out[1] = out[2] = 0.0;
        return 0;
    }
    for (int i = 0; i < 3; ++i)
        out[i] = d[i] / n;
    return 1;
}

void halo_lines_strip_attributes(const halo_polylines *lines, double *direction, double *u)
{
    for (size_t i = 0; i < lines->line_count; ++i) {
        size_t first = lines->first[i], last = lines->first[i + 1]; /* [first, last) */
        size_t n = last - first;
        double total = 0.0;
        for (size_t k = first + 1; k < last; ++k) {
            const double *a = &lines->points[3 * (k - 1)], *b = &lines->points[3 * k];
            total +=
                sqrt((b[0] - a[0]) * (b[0] - a[0]) + (b[1] - a[1]) * (b[1] - a[1]) + (b[2] - a[2]) * (b[2] - a[2]));
        }
        double run = 0.0;
        for (size_t k = first; k < last; ++k) {
            const double *p = &lines->points[3 * k];
            if (k > first) {
                const double *a = &lines->points[3 * (k - 1)];
                run +=
                    sqrt((p[0] - a[0]) * (p[0] - a[0]) + (p[1] - a[1]) * (p[1] - a[1]) + (p[2] - a[2]) * (p[2] - a[2]));
            }
            u[k] = total > 0.0 ? run / total : (n > 1 ? (double)(k - first) / (double)(n - 1) : 0.0);
            /* Nearest distinct neighbours on either side (zero-length segments skipped). */
            double in[3] = {0, 0, 0}, out[3] = {0, 0, 0};
            int has_in = 0, has_out = 0;
            for (size_t j = k; j-- > first && !has_in;)
                has_in = unit_between(&lines->points[3 * j], p, in);
            for (size_t j = k + 1; j < last && !has_out; ++j)
                has_out = unit_between(p, &lines->points[3 * j], out);
            double sum[3] = {in[0] + out[0], in[1] + out[1], in[2] + out[2]};
            double length = sqrt(sum[0] * sum[0] + sum[1] * sum[1] + sum[2] * sum[2]);
            double *d = &direction[3 * k];
            if (length > 1e-6) {
                for (int c = 0; c < 3; ++c)
                    d[c] = sum[c] / length;
            } else { /* a hairpin (directions cancel) or no extent at all */
                const double *keep = has_out ? out : in;
                for (int c = 0; c < 3; ++c)
                    d[c] = keep[c];
            }
        }
    }
}

/* ---- The renderer ------------------------------------------------------------------------ */

struct halo_lines {
    const halo_glfuncs *f;
    GLuint program, vertex_array, buffer, index_buffer, framebuffer, color_texture, depth_buffer;
    int width, height;
    size_t vertex_count, index_count;
    double centre[3], radius; /* the data's bounding sphere */
    halo_lines_state state;
};

halo_lines *halo_lines_create(const halo_lines_desc *desc, halo_diagnostics *diag)
{
    if (!desc || !desc->gl || desc->width < 1 || desc->height < 1 || desc->width > 16384 || desc->height > 16384) {
        HALO_REPORT_ERROR(diag, HALO_MSG_USAGE, "", 0, 0, "lines: gl and a size in 1..16384 are required");
        return NULL;
    }
    halo_lines *l = halo_host_calloc(sizeof *l, diag);
    if (!l)
        return NULL;
    const halo_glfuncs *f = desc->gl;
    l->f = f;
    l->width = desc->width;
    l->height = desc->height;
    l->radius = 1.0;
    const char *vs = desc->vertex_source ? desc->vertex_source : halo_host_embedded("line.vert");
    const char *fs = desc->fragment_source ? desc->fragment_source : halo_host_embedded("line.frag");
    l->program = halo_lines_build_program(f, desc->vertex_program, vs, "line.vert", desc->fragment_program, fs,
                                          "line.frag", diag);
    if (!l->program) {
        halo_lines_destroy(l);
        return NULL;
    }
    f->GenVertexArrays(1, &l->vertex_array);
    f->GenBuffers(1, &l->buffer);
    f->GenBuffers(1, &l->index_buffer);
    f->GenTextures(1, &l->color_texture);
    halo_host_image_texture(f, l->color_texture, GL_RGBA8, l->width, l->height, GL_RGBA, GL_UNSIGNED_BYTE);
    f->BindTexture(GL_TEXTURE_2D, 0);
    f->GenRenderbuffers(1, &l->depth_buffer);
    f->BindRenderbuffer(GL_RENDERBUFFER, l->depth_buffer);
    f->RenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT32F, l->width, l->height);
    f->BindRenderbuffer(GL_RENDERBUFFER, 0);
    f->GenFramebuffers(1, &l->framebuffer);
    f->BindFramebuffer(GL_FRAMEBUFFER, l->framebuffer);
    f->FramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, l->color_texture, 0);
    f->FramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, l->depth_buffer);
    GLenum status = f->CheckFramebufferStatus(GL_FRAMEBUFFER);
    f->BindFramebuffer(GL_FRAMEBUFFER, 0);
    GLenum error = f->GetError();
    if (status != GL_FRAMEBUFFER_COMPLETE || error != GL_NO_ERROR) {
        HALO_REPORT_ERROR(diag, HALO_MSG_GL_LINK, "", 0, 0,
                          "cannot create a %dx%d RGBA8 + DEPTH32F render target (status 0x%x, GL error 0x%x)", l->width,
                          l->height, status, error);
        halo_lines_destroy(l);
        return NULL;
    }
    return l;
}

void halo_lines_destroy(halo_lines *l)
{
    if (!l)
        return;
    const halo_glfuncs *f = l->f;
    if (f) { /* glDelete* passes over the names never made (0) */
        f->DeleteFramebuffers(1, &l->framebuffer);
        f->DeleteRenderbuffers(1, &l->depth_buffer);
        f->DeleteTextures(1, &l->color_texture);
        const GLuint buffers[2] = {l->buffer, l->index_buffer};
        f->DeleteBuffers(2, buffers);
        f->DeleteVertexArrays(1, &l->vertex_array);
        f->DeleteProgram(l->program);
    }
    free(l);
}

size_t halo_lines_vertex_count(const halo_lines *l) { return l ? l->vertex_count : 0; }

halo_status halo_lines_set_data(halo_lines *l, const halo_polylines *lines, halo_diagnostics *diag)
{
    if (!l || !lines || lines->point_count == 0 || lines->point_count > ((size_t)1 << 28)) {
        HALO_REPORT_ERROR(diag, HALO_MSG_USAGE, "", 0, 0, "lines: 1..2^28 points are required");
        return HALO_ERROR_INPUT;
    }
    size_t points = lines->point_count, segments = 0;
    for (size_t i = 0; i < lines->line_count; ++i)
        if (lines->first[i + 1] > lines->first[i])
            segments += lines->first[i + 1] - lines->first[i] - 1;
    double *direction = malloc(points * 3 * sizeof *direction), *u = malloc(points * sizeof *u);
    float *vertices = malloc(points * 2 * 8 * sizeof *vertices);
    uint32_t *indices = malloc((segments ? segments : 1) * 6 * sizeof *indices);
    if (!direction || !u || !vertices || !indices) {
        free(direction), free(u), free(vertices), free(indices);
        HALO_REPORT_ERROR(diag, HALO_MSG_OUT_OF_MEMORY, "", 0, 0, "out of memory building a strip of %zu points",
                          points);
        return HALO_ERROR_IO;
    }
    halo_lines_strip_attributes(lines, direction, u);
    /* Bounding sphere: the box's centre and the farthest point from it. */
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (size_t k = 0; k < points; ++k)
        for (int c = 0; c < 3; ++c) {
            lo[c] = fmin(lo[c], lines->points[3 * k + c]);
            hi[c] = fmax(hi[c], lines->points[3 * k + c]);
        }
    double radius = 0.0;
    for (int c = 0; c < 3; ++c)
        l->centre[c] = 0.5 * (lo[c] + hi[c]);
    for (size_t k = 0; k < points; ++k) {
        const double *p = &lines->points[3 * k];
        double d = sqrt((p[0] - l->centre[0]) * (p[0] - l->centre[0]) + (p[1] - l->centre[1]) * (p[1] - l->centre[1]) +
                        (p[2] - l->centre[2]) * (p[2] - l->centre[2]));
        radius = fmax(radius, d);
    }
    l->radius = radius > 0.0 ? radius : 1.0;
    for (size_t k = 0; k < points; ++k)
        for (int side = 0; side < 2; ++side) {
            float *v = &vertices[(2 * k + (size_t)side) * 8];
            for (int c = 0; c < 3; ++c) {
                v[c] = (float)lines->points[3 * k + c];
                v[3 + c] = (float)direction[3 * k + c];
            }
            v[6] = (float)u[k];
            v[7] = (float)side;
        }
    size_t n = 0;
    for (size_t i = 0; i < lines->line_count; ++i)
        for (size_t k = lines->first[i]; k + 1 < lines->first[i + 1]; ++k) {
            uint32_t a = (uint32_t)(2 * k);
            uint32_t quad[6] = {a, a + 1, a + 2, a + 1, a + 3, a + 2};
            memcpy(&indices[n], quad, sizeof quad);
            n += 6;
        }
    const halo_glfuncs *f = l->f;
    f->BindVertexArray(l->vertex_array);
    f->BindBuffer(GL_ARRAY_BUFFER, l->buffer);
    f->BufferData(GL_ARRAY_BUFFER, (GLsizeiptr)(points * 2 * 8 * sizeof *vertices), vertices, GL_STATIC_DRAW);
    f->BindBuffer(GL_ELEMENT_ARRAY_BUFFER, l->index_buffer);
    f->BufferData(GL_ELEMENT_ARRAY_BUFFER, (GLsizeiptr)(n * sizeof *indices), indices, GL_STATIC_DRAW);
    const GLsizei stride = 8 * sizeof(float);
    f->EnableVertexAttribArray(0);
    f->VertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, stride, (const void *)0);
    f->EnableVertexAttribArray(1);
    f->VertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, stride, (const void *)(3 * sizeof(float)));
    f->EnableVertexAttribArray(2);
    f->VertexAttribPointer(2, 2, GL_FLOAT, GL_FALSE, stride, (const void *)(6 * sizeof(float)));
    f->BindVertexArray(0);
    f->BindBuffer(GL_ARRAY_BUFFER, 0);
    free(direction), free(u), free(vertices), free(indices);
    GLenum error = f->GetError();
    if (error != GL_NO_ERROR) {
        HALO_REPORT_ERROR(diag, HALO_MSG_IO_READ, "", 0, 0, "cannot upload %zu strip vertices (GL error 0x%x)",
                          2 * points, error);
        return HALO_ERROR_IO;
    }
    l->vertex_count = 2 * points;
    l->index_count = n;
    return HALO_OK;
}

/* ---- Camera ---------------------------------------------------------------------------- */

static void cross3(const double a[3], const double b[3], double out[3])
{
    double r[3] = {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
    memcpy(out, r, sizeof r);
}

static void normalize3(double v[3])
{
    double n = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    if (n > 0.0)
        v[0] /= n, v[1] /= n, v[2] /= n;
}

/* Rounds to float, as uploaded. */
static double f32(double x) { return (double)(float)x; }

void halo_lines_get_state(const halo_lines *l, const halo_lines_view *view, halo_lines_state *s)
{
    if (!view) {
        *s = l->state;
        return;
    }
    memset(s, 0, sizeof *s);
    double centre[3], radius = view->radius > 0.0 && isfinite(view->radius) ? view->radius : l->radius;
    for (int c = 0; c < 3; ++c)
        centre[c] = view->radius > 0.0 ? view->centre[c] : l->centre[c];
    double zoom = view->zoom > 0.0 && isfinite(view->zoom) ? view->zoom : 1.0;
    double az = (isfinite(view->azimuth) ? view->azimuth : 0.0) * M_PI / 180.0;
    double el = (isfinite(view->elevation) ? view->elevation : 0.0) * M_PI / 180.0;
    double half_fov = LINES_FIELD_OF_VIEW * M_PI / 360.0;
    double distance = radius / sin(half_fov) / zoom;
    double back[3] = {cos(el) * sin(az), sin(el), cos(el) * cos(az)};
    double right[3] = {cos(az), 0.0, -sin(az)};
    double eye[3];
    double shift = isfinite(view->eye_shift) ? view->eye_shift * distance : 0.0;
    for (int c = 0; c < 3; ++c)
        eye[c] = centre[c] + distance * back[c] + shift * right[c];
    /* look at the centre from the (shifted) eye */
    double forward[3] = {centre[0] - eye[0], centre[1] - eye[1], centre[2] - eye[2]};
    normalize3(forward);
    /* the orbit's up (perpendicular to back and the horizontal right) is never parallel
     * to forward, even looking straight down */
    double orbit_up[3];
    cross3(back, right, orbit_up);
    cross3(forward, orbit_up, right);
    normalize3(right);
    double up[3];
    cross3(right, forward, up);
    double viewm[16] = {right[0], up[0], -forward[0], 0.0, right[1], up[1], -forward[1], 0.0,
                        right[2], up[2], -forward[2], 0.0, 0.0,      0.0,   0.0,         1.0};
    for (int row = 0; row < 3; ++row)
        viewm[12 + row] = -(viewm[row] * eye[0] + viewm[4 + row] * eye[1] + viewm[8 + row] * eye[2]);
    double aspect = (double)l->width / l->height;
    double reach = distance + radius * 1.5;
    double near_plane = fmax(distance - radius * 1.5, distance * 1e-3);
    double projection[16];
    halo_host_perspective(half_fov, aspect, near_plane, reach, projection);
    halo_host_matrix_multiply(projection, viewm, s->view_projection);
    for (int i = 0; i < 16; ++i)
        s->view_projection[i] = f32(s->view_projection[i]);
    /* depth along forward of the sphere's front and back: the eye is `distance` from the
     * centre (approximately, when shifted) */
    double along =
        (centre[0] - eye[0]) * forward[0] + (centre[1] - eye[1]) * forward[1] + (centre[2] - eye[2]) * forward[2];
    for (int c = 0; c < 3; ++c) {
        s->eye[c] = f32(eye[c]);
        s->forward[c] = f32(forward[c]);
    }
    s->depth_range[0] = f32(along - radius);
    s->depth_range[1] = f32(along + radius);
    s->distance_range[0] = f32(fmax(0.0, along - radius));
    s->distance_range[1] = f32(along + radius);
    s->width_unit = f32(radius);
}

void halo_lines_project(const halo_lines *l, const halo_lines_state *s, const double p[3], double pixel[2])
{
    const double *m = s->view_projection;
    double clip[4];
    for (int row = 0; row < 4; ++row)
        clip[row] = m[row] * p[0] + m[4 + row] * p[1] + m[8 + row] * p[2] + m[12 + row];
    double w = clip[3] != 0.0 ? clip[3] : 1e-30;
    pixel[0] = (clip[0] / w * 0.5 + 0.5) * l->width;
    pixel[1] = (clip[1] / w * 0.5 + 0.5) * l->height;
}

halo_status halo_lines_draw(halo_lines *l, const halo_lines_view *view, halo_diagnostics *diag)
{
    if (!l || !view) {
        HALO_REPORT_ERROR(diag, HALO_MSG_USAGE, "", 0, 0, "halo_lines_draw: lines and view are required");
        return HALO_ERROR_INPUT;
    }
    if (!l->vertex_count) {
        HALO_REPORT_ERROR(diag, HALO_MSG_USAGE, "", 0, 0, "lines: no data uploaded");
        return HALO_ERROR_INPUT;
    }
    halo_lines_get_state(l, view, &l->state);
    const halo_lines_state *s = &l->state;
    const halo_glfuncs *f = l->f;
    GLuint program = l->program;
    f->BindFramebuffer(GL_FRAMEBUFFER, l->framebuffer);
    f->Viewport(0, 0, l->width, l->height);
    int mask = view->mask_channels ? view->mask_channels : 7;
    f->ColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    if (!view->keep_color) {
        f->ClearColor((float)view->background[0], (float)view->background[1], (float)view->background[2], 1.0f);
        f->Clear(GL_COLOR_BUFFER_BIT);
    }
    const float far_depth = 1.0f;
    f->ClearBufferfv(GL_DEPTH, 0, &far_depth);
    f->ColorMask((mask & 1) ? GL_TRUE : GL_FALSE, (mask & 2) ? GL_TRUE : GL_FALSE, (mask & 4) ? GL_TRUE : GL_FALSE,
                 GL_TRUE);
    f->Enable(GL_DEPTH_TEST);
    f->DepthFunc(GL_LESS);
    f->DepthMask(GL_TRUE);
    f->Disable(GL_BLEND);
    f->Disable(GL_CULL_FACE);
    f->UseProgram(program);
    float m[16];
    for (int i = 0; i < 16; ++i)
        m[i] = (float)s->view_projection[i];
    f->UniformMatrix4fv(f->GetUniformLocation(program, "view_projection"), 1, GL_FALSE, m);
    f->Uniform3f(f->GetUniformLocation(program, "eye"), (float)s->eye[0], (float)s->eye[1], (float)s->eye[2]);
    f->Uniform3f(f->GetUniformLocation(program, "forward"), (float)s->forward[0], (float)s->forward[1],
                 (float)s->forward[2]);
    f->Uniform2f(f->GetUniformLocation(program, "depth_range"), (float)s->depth_range[0], (float)s->depth_range[1]);
    f->Uniform1f(f->GetUniformLocation(program, "width_unit"), (float)s->width_unit);
    f->Uniform3f(f->GetUniformLocation(program, "line_color"), (float)view->line_color[0], (float)view->line_color[1],
                 (float)view->line_color[2]);
    f->Uniform3f(f->GetUniformLocation(program, "background"), (float)view->background[0], (float)view->background[1],
                 (float)view->background[2]);
    /* the line_strip stage's host uniform (absent when the stage is not linked) */
    f->Uniform2f(f->GetUniformLocation(program, "halo_host_depth_range"), (float)s->distance_range[0],
                 (float)s->distance_range[1]);
    f->BindVertexArray(l->vertex_array);
    f->DrawElements(GL_TRIANGLES, (GLsizei)l->index_count, GL_UNSIGNED_INT, (const void *)0);
    f->BindVertexArray(0);
    f->UseProgram(0);
    f->ColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    f->Disable(GL_DEPTH_TEST);
    f->BindFramebuffer(GL_FRAMEBUFFER, 0);
    return halo_host_gl_check(f, HALO_MSG_GL_LINK, "drawing the lines failed", diag);
}

void halo_lines_finish(halo_lines *l)
{
    if (l)
        l->f->Finish();
}

halo_status halo_lines_read(halo_lines *l, float *rgba, halo_diagnostics *diag)
{
    if (!l || !rgba)
        return HALO_ERROR_INPUT;
    const halo_glfuncs *f = l->f;
    f->BindFramebuffer(GL_FRAMEBUFFER, l->framebuffer);
    f->ReadBuffer(GL_COLOR_ATTACHMENT0);
    f->PixelStorei(GL_PACK_ALIGNMENT, 4);
    f->ReadPixels(0, 0, l->width, l->height, GL_RGBA, GL_FLOAT, rgba);
    f->BindFramebuffer(GL_FRAMEBUFFER, 0);
    return halo_host_gl_check(f, HALO_MSG_IO_READ, "reading the line image failed", diag);
}
