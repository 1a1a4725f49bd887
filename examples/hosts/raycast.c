/* The C side of the example hosts (see raycast.h). */
#include "raycast.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

/* Generated at build time by build-aux/embed.sh from examples/hosts/. */
struct halo_embedded_file {
    const char *name;
    const char *text;
};
extern const struct halo_embedded_file halo_embedded_hosts[];

/* The library's internal diagnostics entry point is not exported; the examples add
 * their own diagnostics through this wrapper around the public list. */
#include "diag.h"

const char *halo_host_embedded(const char *name)
{
    if (!name)
        return NULL;
    /* Entries are named by their source path ("examples/hosts/raycast.frag"); match
     * that or the file name alone. */
    for (const struct halo_embedded_file *f = halo_embedded_hosts; f->name; ++f) {
        const char *slash = strrchr(f->name, '/');
        if (strcmp(f->name, name) == 0 || (slash && strcmp(slash + 1, name) == 0))
            return f->text;
    }
    return NULL;
}

char *halo_host_load(const char *name, const char *override_path, halo_diagnostics *diag)
{
    if (override_path) {
        FILE *file = fopen(override_path, "rb");
        if (!file) {
            halo_diag_error(diag, IO_READ, override_path, 0, 0, "cannot open host shader '%s'", override_path);
            return NULL;
        }
        size_t cap = 4096, len = 0;
        char *text = malloc(cap);
        while (text) {
            if (len + 1 >= cap) {
                char *grown = realloc(text, cap * 2);
                if (!grown) {
                    free(text);
                    text = NULL;
                    break;
                }
                text = grown;
                cap *= 2;
            }
            size_t got = fread(text + len, 1, cap - len - 1, file);
            len += got;
            if (got == 0)
                break;
        }
        int failed = ferror(file);
        fclose(file);
        if (!text) {
            halo_diag_error(diag, OUT_OF_MEMORY, override_path, 0, 0, "out of memory reading '%s'", override_path);
            return NULL;
        }
        if (failed) {
            free(text);
            halo_diag_error(diag, IO_READ, override_path, 0, 0, "cannot read host shader '%s'", override_path);
            return NULL;
        }
        text[len] = '\0';
        return text;
    }
    const char *embedded = halo_host_embedded(name);
    if (!embedded) {
        halo_diag_error(diag, IO_READ, name ? name : "", 0, 0, "no embedded host shader '%s'", name ? name : "");
        return NULL;
    }
    size_t n = strlen(embedded);
    char *copy = malloc(n + 1);
    if (!copy) {
        halo_diag_error(diag, OUT_OF_MEMORY, name, 0, 0, "out of memory");
        return NULL;
    }
    memcpy(copy, embedded, n + 1);
    return copy;
}

/* ---- Programs and targets ---------------------------------------------------------- */

static void report_log(halo_diagnostics *diag, halo_message_id id, const char *file, const char *log)
{
    /* Raw (unlinked) shaders: the driver's lines already refer to the file itself. */
    const char *p = log;
    while (p && *p) {
        const char *end = strchr(p, '\n');
        size_t n = end ? (size_t)(end - p) : strlen(p);
        int source, line = 0, column = 0, used = 0;
        const char *text = p;
        if (sscanf(p, "%d:%d(%d):%n", &source, &line, &column, &used) == 3 && used > 0 && (size_t)used <= n) {
            text = p + used;
            while (*text == ' ')
                ++text;
            if (strncmp(text, "error:", 6) == 0)
                text += 6;
            while (*text == ' ')
                ++text;
        } else {
            line = column = 0;
        }
        if (n > 0)
            halo_diag_add(diag, HALO_SEVERITY_ERROR, id, file, line, column, NULL, "%.*s", (int)(n - (size_t)(text - p)),
                          text);
        p = end ? end + 1 : NULL;
    }
}

static GLuint compile_raw(const halo_glfuncs *f, GLenum type, const char *source, const char *file,
                          halo_diagnostics *diag)
{
    GLuint shader = f->CreateShader(type);
    f->ShaderSource(shader, 1, &source, NULL);
    f->CompileShader(shader);
    GLint ok = GL_FALSE, length = 0;
    f->GetShaderiv(shader, GL_COMPILE_STATUS, &ok);
    if (ok)
        return shader;
    f->GetShaderiv(shader, GL_INFO_LOG_LENGTH, &length);
    char *log = calloc((size_t)(length > 0 ? length : 1) + 1, 1);
    if (log) {
        f->GetShaderInfoLog(shader, length, NULL, log);
        report_log(diag, HALO_MSG_GL_COMPILE, file, log);
        free(log);
    }
    halo_diag_error(diag, GL_COMPILE, file, 0, 0, "the driver rejected '%s'", file);
    f->DeleteShader(shader);
    return 0;
}

static GLuint link_raw(const halo_glfuncs *f, const char *vertex_source, const char *vertex_file,
                       const char *fragment_source, const char *fragment_file, halo_diagnostics *diag)
{
    GLuint vertex = compile_raw(f, GL_VERTEX_SHADER, vertex_source, vertex_file, diag);
    GLuint fragment = compile_raw(f, GL_FRAGMENT_SHADER, fragment_source, fragment_file, diag);
    if (!vertex || !fragment) {
        if (vertex)
            f->DeleteShader(vertex);
        if (fragment)
            f->DeleteShader(fragment);
        return 0;
    }
    GLuint program = f->CreateProgram();
    f->AttachShader(program, vertex);
    f->AttachShader(program, fragment);
    f->LinkProgram(program);
    f->DeleteShader(vertex);
    f->DeleteShader(fragment);
    GLint ok = GL_FALSE, length = 0;
    f->GetProgramiv(program, GL_LINK_STATUS, &ok);
    if (ok)
        return program;
    f->GetProgramiv(program, GL_INFO_LOG_LENGTH, &length);
    char *log = calloc((size_t)(length > 0 ? length : 1) + 1, 1);
    if (log) {
        f->GetProgramInfoLog(program, length, NULL, log);
        report_log(diag, HALO_MSG_GL_LINK, fragment_file, log);
        free(log);
    }
    halo_diag_error(diag, GL_LINK, fragment_file, 0, 0, "the driver could not link '%s'", fragment_file);
    f->DeleteProgram(program);
    return 0;
}

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
    if (!desc || !desc->gl || desc->width < 1 || desc->height < 1 || desc->width > 16384 || desc->height > 16384 ||
        (desc->program && !desc->runtime)) {
        halo_diag_error(diag, USAGE, "", 0, 0, "host: gl, a size in 1..16384 and (with a program) a runtime are required");
        return 0;
    }
    const halo_glfuncs *f = desc->gl;
    t->f = f;
    t->runtime = desc->runtime;
    t->linked = desc->program;
    t->width = desc->width;
    t->height = desc->height;
    const char *vertex_source = desc->vertex_source ? desc->vertex_source : halo_host_embedded("raycast.vert");
    const char *vertex_file = desc->vertex_file ? desc->vertex_file : "raycast.vert";
    if (!vertex_source) {
        halo_diag_error(diag, IO_READ, "raycast.vert", 0, 0, "no vertex shader: raycast.vert is not embedded");
        return 0;
    }
    if (desc->program) {
        t->program = halo_gl_program_build(desc->runtime, desc->program, vertex_source, vertex_file, diag);
    } else {
        const char *fragment_source = desc->fragment_source ? desc->fragment_source
                                                            : halo_host_embedded(default_fragment);
        const char *fragment_file = desc->fragment_file ? desc->fragment_file : default_fragment;
        if (!fragment_source) {
            halo_diag_error(diag, IO_READ, default_fragment, 0, 0, "no fragment shader: %s is not embedded",
                            default_fragment);
            return 0;
        }
        t->program = link_raw(f, vertex_source, vertex_file, fragment_source, fragment_file, diag);
    }
    if (!t->program)
        return 0;

    f->GenVertexArrays(1, &t->vertex_array);
    f->GenTextures(1, &t->color_texture);
    f->BindTexture(GL_TEXTURE_2D, t->color_texture);
    f->TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    f->TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    f->TexImage2D(GL_TEXTURE_2D, 0, GL_RGBA32F, t->width, t->height, 0, GL_RGBA, GL_FLOAT, NULL);
    f->GenFramebuffers(1, &t->framebuffer);
    f->BindFramebuffer(GL_FRAMEBUFFER, t->framebuffer);
    f->FramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, t->color_texture, 0);
    GLenum status = f->CheckFramebufferStatus(GL_FRAMEBUFFER);
    f->BindFramebuffer(GL_FRAMEBUFFER, 0);
    GLenum error = f->GetError();
    if (status != GL_FRAMEBUFFER_COMPLETE || error != GL_NO_ERROR) {
        halo_diag_error(diag, GL_LINK, "", 0, 0, "cannot create a %dx%d RGBA32F render target (status 0x%x, GL error 0x%x)",
                        t->width, t->height, status, error);
        return 0;
    }
    return 1;
}

static void host_target_release(host_target *t)
{
    const halo_glfuncs *f = t->f;
    if (!f)
        return;
    if (t->framebuffer)
        f->DeleteFramebuffers(1, &t->framebuffer);
    if (t->color_texture)
        f->DeleteTextures(1, &t->color_texture);
    if (t->vertex_array)
        f->DeleteVertexArrays(1, &t->vertex_array);
    if (t->program)
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

static halo_status host_target_draw(host_target *t, float *rgba, halo_diagnostics *diag)
{
    const halo_glfuncs *f = t->f;
    f->BindVertexArray(t->vertex_array);
    f->DrawArrays(GL_TRIANGLES, 0, 3);
    f->ReadBuffer(GL_COLOR_ATTACHMENT0);
    f->PixelStorei(GL_PACK_ALIGNMENT, 4);
    f->ReadPixels(0, 0, t->width, t->height, GL_RGBA, GL_FLOAT, rgba);
    f->BindVertexArray(0);
    f->UseProgram(0);
    f->BindFramebuffer(GL_FRAMEBUFFER, 0);
    GLenum error = f->GetError();
    if (error != GL_NO_ERROR) {
        halo_diag_error(diag, GL_LINK, "", 0, 0, "OpenGL error 0x%x while rendering", error);
        return HALO_ERROR_IO;
    }
    return HALO_OK;
}

/* ---- The ray caster ------------------------------------------------------------------ */

struct halo_raycast {
    host_target target;
    GLuint volume_texture, transfer_texture;
    const float *volume;
    int dims[3];
    float transfer[HALO_RAYCAST_TRANSFER_TEXELS * 4];
    float inverse_view_projection[16];
    float eye[3];
    float step_voxels;
    float background[3];
};

halo_raycast *halo_raycast_create(const halo_host_desc *desc, halo_diagnostics *diag)
{
    halo_raycast *r = calloc(1, sizeof *r);
    if (!r) {
        halo_diag_error(diag, OUT_OF_MEMORY, "", 0, 0, "out of memory");
        return NULL;
    }
    if (!host_target_init(&r->target, desc, "raycast.frag", diag)) {
        host_target_release(&r->target);
        free(r);
        return NULL;
    }
    const halo_glfuncs *f = r->target.f;
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
    if (f) {
        f->DeleteTextures(1, &r->volume_texture);
        f->DeleteTextures(1, &r->transfer_texture);
    }
    host_target_release(&r->target);
    free(r);
}

unsigned halo_raycast_gl_program(const halo_raycast *r)
{
    return r ? r->target.program : 0;
}

halo_status halo_raycast_set_volume(halo_raycast *r, const float *data, int nx, int ny, int nz,
                                    halo_diagnostics *diag)
{
    if (!r || !data || nx < 2 || ny < 2 || nz < 2 || nx > 2048 || ny > 2048 || nz > 2048) {
        halo_diag_error(diag, USAGE, "", 0, 0, "volume of %dx%dx%d voxels: each side must be 2..2048", nx, ny, nz);
        return HALO_ERROR_INPUT;
    }
    const halo_glfuncs *f = r->target.f;
    f->BindTexture(GL_TEXTURE_3D, r->volume_texture);
    f->TexParameteri(GL_TEXTURE_3D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    f->TexParameteri(GL_TEXTURE_3D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    f->TexParameteri(GL_TEXTURE_3D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    f->TexParameteri(GL_TEXTURE_3D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    f->TexParameteri(GL_TEXTURE_3D, GL_TEXTURE_WRAP_R, GL_CLAMP_TO_EDGE);
    f->PixelStorei(GL_UNPACK_ALIGNMENT, 4);
    f->TexImage3D(GL_TEXTURE_3D, 0, GL_R32F, nx, ny, nz, 0, GL_RED, GL_FLOAT, data);
    f->BindTexture(GL_TEXTURE_3D, 0);
    GLenum error = f->GetError();
    if (error != GL_NO_ERROR) {
        halo_diag_error(diag, IO_READ, "", 0, 0, "cannot upload a %dx%dx%d volume (GL error 0x%x)", nx, ny, nz, error);
        return HALO_ERROR_IO;
    }
    r->volume = data;
    r->dims[0] = nx;
    r->dims[1] = ny;
    r->dims[2] = nz;
    return HALO_OK;
}

/* The transfer table: control points (value, r, g, b, opacity) sorted by value,
 * linearly interpolated, constant beyond the first and last. */
static void fill_transfer(float *table, const halo_render_settings *s)
{
    for (int i = 0; i < HALO_RAYCAST_TRANSFER_TEXELS; ++i) {
        double x = (double)i / (HALO_RAYCAST_TRANSFER_TEXELS - 1);
        double rgba[4] = {x, x, x, x}; /* no control points: a grey ramp */
        int n = s ? s->transfer_count : 0;
        if (n > HALO_MAX_TRANSFER_POINTS)
            n = HALO_MAX_TRANSFER_POINTS;
        if (n > 0) {
            const double(*p)[5] = s->transfer;
            int k = 0;
            while (k < n && p[k][0] <= x)
                ++k;
            if (k == 0 || k == n) {
                int j = k == 0 ? 0 : n - 1;
                for (int c = 0; c < 4; ++c)
                    rgba[c] = p[j][c + 1];
            } else {
                double span = p[k][0] - p[k - 1][0];
                double w = span > 0.0 ? (x - p[k - 1][0]) / span : 1.0;
                for (int c = 0; c < 4; ++c)
                    rgba[c] = (1.0 - w) * p[k - 1][c + 1] + w * p[k][c + 1];
            }
        }
        for (int c = 0; c < 4; ++c)
            table[i * 4 + c] = (float)(rgba[c] < 0.0 ? 0.0 : rgba[c] > 1.0 ? 1.0 : rgba[c]);
    }
}

halo_status halo_raycast_set_render(halo_raycast *r, const halo_render_settings *settings, halo_diagnostics *diag)
{
    if (!r)
        return HALO_ERROR_INPUT;
    fill_transfer(r->transfer, settings);
    const halo_glfuncs *f = r->target.f;
    f->BindTexture(GL_TEXTURE_2D, r->transfer_texture);
    f->TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    f->TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    f->TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    f->TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    f->TexImage2D(GL_TEXTURE_2D, 0, GL_RGBA32F, HALO_RAYCAST_TRANSFER_TEXELS, 1, 0, GL_RGBA, GL_FLOAT, r->transfer);
    f->BindTexture(GL_TEXTURE_2D, 0);
    double step = settings && settings->step > 0.0 && isfinite(settings->step) ? settings->step : 0.5;
    r->step_voxels = (float)step;
    for (int c = 0; c < 3; ++c)
        r->background[c] = settings ? (float)settings->background[c] : 0.0f;
    GLenum error = f->GetError();
    if (error != GL_NO_ERROR) {
        halo_diag_error(diag, IO_READ, "", 0, 0, "cannot upload the transfer function (GL error 0x%x)", error);
        return HALO_ERROR_IO;
    }
    return HALO_OK;
}

/* ---- Camera ---------------------------------------------------------------------------- */

/* 4x4 matrices, column-major (m[column * 4 + row]) as OpenGL takes them. */
static void matrix_multiply(const double a[16], const double b[16], double out[16])
{
    double r[16];
    for (int col = 0; col < 4; ++col)
        for (int row = 0; row < 4; ++row) {
            double sum = 0.0;
            for (int k = 0; k < 4; ++k)
                sum += a[k * 4 + row] * b[col * 4 + k];
            r[col * 4 + row] = sum;
        }
    memcpy(out, r, sizeof r);
}

/* Gauss-Jordan with partial pivoting; returns 0 for a singular matrix. */
static int matrix_invert(const double m[16], double out[16])
{
    double a[4][8];
    for (int row = 0; row < 4; ++row)
        for (int col = 0; col < 4; ++col) {
            a[row][col] = m[col * 4 + row];
            a[row][col + 4] = row == col ? 1.0 : 0.0;
        }
    for (int col = 0; col < 4; ++col) {
        int pivot = col;
        for (int row = col + 1; row < 4; ++row)
            if (fabs(a[row][col]) > fabs(a[pivot][col]))
                pivot = row;
        if (fabs(a[pivot][col]) < 1e-300)
            return 0;
        if (pivot != col)
            for (int k = 0; k < 8; ++k) {
                double tmp = a[col][k];
                a[col][k] = a[pivot][k];
                a[pivot][k] = tmp;
            }
        double scale = 1.0 / a[col][col];
        for (int k = 0; k < 8; ++k)
            a[col][k] *= scale;
        for (int row = 0; row < 4; ++row)
            if (row != col) {
                double factor = a[row][col];
                for (int k = 0; k < 8; ++k)
                    a[row][k] -= factor * a[col][k];
            }
    }
    for (int row = 0; row < 4; ++row)
        for (int col = 0; col < 4; ++col)
            out[col * 4 + row] = a[row][col + 4];
    return 1;
}

void halo_raycast_set_camera(halo_raycast *r, double azimuth, double elevation, double zoom)
{
    if (!r)
        return;
    if (!isfinite(azimuth))
        azimuth = 0.0;
    if (!isfinite(elevation))
        elevation = 0.0;
    if (!isfinite(zoom) || zoom <= 0.0)
        zoom = 1.0;
    const double radius = sqrt(3.0) / 2.0, centre = 0.5;
    double az = azimuth * M_PI / 180.0, el = elevation * M_PI / 180.0;
    double half_fov = HALO_RAYCAST_FIELD_OF_VIEW * M_PI / 360.0;
    double distance = radius / sin(half_fov) / zoom;
    double back[3] = {cos(el) * sin(az), sin(el), cos(el) * cos(az)}; /* from the centre to the eye */
    double eye[3] = {centre + distance * back[0], centre + distance * back[1], centre + distance * back[2]};
    /* right stays horizontal at any elevation, so straight up and down are well defined */
    double right[3] = {cos(az), 0.0, -sin(az)};
    double up[3] = {back[1] * right[2] - back[2] * right[1], back[2] * right[0] - back[0] * right[2],
                    back[0] * right[1] - back[1] * right[0]};
    double view[16] = {right[0], up[0], back[0], 0.0, right[1], up[1], back[1], 0.0,
                       right[2], up[2], back[2], 0.0, 0.0, 0.0, 0.0, 1.0};
    for (int row = 0; row < 3; ++row)
        view[12 + row] = -(view[row] * eye[0] + view[4 + row] * eye[1] + view[8 + row] * eye[2]);

    double aspect = (double)r->target.width / r->target.height;
    double near_plane = distance - radius > 0.01 ? distance - radius : 0.01;
    double far_plane = distance + radius + 1.0;
    double t = tan(half_fov);
    /* The field of view spans the smaller image side. */
    double sx = aspect >= 1.0 ? 1.0 / (t * aspect) : 1.0 / t;
    double sy = aspect >= 1.0 ? 1.0 / t : aspect / t;
    double projection[16] = {sx, 0.0, 0.0, 0.0, 0.0, sy, 0.0, 0.0,
                             0.0, 0.0, -(far_plane + near_plane) / (far_plane - near_plane), -1.0,
                             0.0, 0.0, -2.0 * far_plane * near_plane / (far_plane - near_plane), 0.0};
    double view_projection[16], inverse[16];
    matrix_multiply(projection, view, view_projection);
    if (!matrix_invert(view_projection, inverse))
        return;
    for (int i = 0; i < 16; ++i)
        r->inverse_view_projection[i] = (float)inverse[i];
    for (int c = 0; c < 3; ++c)
        r->eye[c] = (float)eye[c];
}

static int max_dimension(const int dims[3])
{
    int m = dims[0] > dims[1] ? dims[0] : dims[1];
    return m > dims[2] ? m : dims[2];
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
    int voxels = r->volume ? max_dimension(r->dims) : 1;
    float unit_step = 1.0f / (float)voxels;
    for (int c = 0; c < 3; ++c) {
        s->eye[c] = r->eye[c];
        s->background[c] = r->background[c];
        s->dims[c] = r->dims[c];
    }
    s->unit_step = unit_step;
    s->step_size = (float)(r->step_voxels * unit_step);
    s->transfer_texels = HALO_RAYCAST_TRANSFER_TEXELS;
    s->transfer = r->transfer;
    s->volume = r->volume;
}

halo_status halo_raycast_render(halo_raycast *r, float *rgba, halo_diagnostics *diag)
{
    if (!r || !rgba)
        return HALO_ERROR_INPUT;
    if (!r->volume) {
        halo_diag_error(diag, USAGE, "", 0, 0, "ray caster: no volume uploaded");
        return HALO_ERROR_INPUT;
    }
    halo_raycast_state s;
    halo_raycast_get_state(r, &s);
    const halo_glfuncs *f = r->target.f;
    GLuint program = r->target.program;
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
    halo_status status = host_target_draw(&r->target, rgba, diag);
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
    halo_probe *p = calloc(1, sizeof *p);
    if (!p) {
        halo_diag_error(diag, OUT_OF_MEMORY, "", 0, 0, "out of memory");
        return NULL;
    }
    if (!host_target_init(&p->target, desc, "probe.frag", diag)) {
        host_target_release(&p->target);
        free(p);
        return NULL;
    }
    p->staging = malloc((size_t)p->target.width * (size_t)p->target.height * 4 * sizeof(float));
    if (!p->staging) {
        halo_diag_error(diag, OUT_OF_MEMORY, "", 0, 0, "out of memory");
        halo_probe_destroy(p);
        return NULL;
    }
    const halo_glfuncs *f = p->target.f;
    f->GenTextures(PROBE_TEXTURES, p->textures);
    for (int i = 0; i < PROBE_TEXTURES; ++i) {
        f->BindTexture(GL_TEXTURE_2D, p->textures[i]);
        f->TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
        f->TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
        f->TexImage2D(GL_TEXTURE_2D, 0, GL_RGBA32F, p->target.width, p->target.height, 0, GL_RGBA, GL_FLOAT, NULL);
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
