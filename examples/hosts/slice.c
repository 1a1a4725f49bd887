/* The slice host and the slab ray caster (see slice.h, slab.h). */
#include "hosts/slice.h"

#include "diag.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

struct halo_slice {
    const halo_glfuncs *f;
    halo_gl *runtime;
    const halo_program *linked;
    halo_gl_frame *frame;
    int slab;
    GLuint program, vertex_array, framebuffer, textures[2]; /* textures[1]: the slab's second ray state */
    GLuint volume_texture, transfer_texture;
    int width, height;
    const float *volume;
    int dims[3];
    float transfer[HALO_RAYCAST_TRANSFER_TEXELS * 4];
    float inverse_view_projection[16];
    float eye[3], view_axis[3], screen_right[3], screen_up[3];
    float step_voxels;
    float background[3];
    int interval_override;
    long draws, pass_draws;
    halo_slice_progress_fn progress;
    void *progress_user;
};

/* ---- Programs ------------------------------------------------------------------------- */

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
    if (log)
        f->GetShaderInfoLog(shader, length, NULL, log);
    halo_diag_error(diag, GL_COMPILE, file, 0, 0, "the driver rejected '%s': %s", file, log ? log : "");
    free(log);
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
    GLint ok = GL_FALSE;
    f->GetProgramiv(program, GL_LINK_STATUS, &ok);
    if (ok)
        return program;
    halo_diag_error(diag, GL_LINK, fragment_file, 0, 0, "the driver could not link '%s'", fragment_file);
    f->DeleteProgram(program);
    return 0;
}

/* The transfer table, as raycast.c builds it (control points linearly interpolated). */
static void fill_transfer(float *table, const halo_render_settings *s)
{
    for (int i = 0; i < HALO_RAYCAST_TRANSFER_TEXELS; ++i) {
        double x = (double)i / (HALO_RAYCAST_TRANSFER_TEXELS - 1);
        double rgba[4] = {x, x, x, x};
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

halo_slice *halo_slice_create_mode(const halo_host_desc *desc, int slab, halo_diagnostics *diag)
{
    if (!desc || !desc->gl || desc->width < 1 || desc->height < 1 || desc->width > 16384 || desc->height > 16384 ||
        (desc->program && !desc->runtime)) {
        halo_diag_error(diag, USAGE, "", 0, 0, "host: gl, a size in 1..16384 and (with a program) a runtime are required");
        return NULL;
    }
    halo_slice *s = calloc(1, sizeof *s);
    if (!s) {
        halo_diag_error(diag, OUT_OF_MEMORY, "", 0, 0, "out of memory");
        return NULL;
    }
    const halo_glfuncs *f = desc->gl;
    s->f = f;
    s->runtime = desc->runtime;
    s->linked = desc->program;
    s->slab = slab;
    s->width = desc->width;
    s->height = desc->height;
    const char *default_fragment = slab ? "slab.frag" : "slice.frag";
    const char *vertex_source = desc->vertex_source ? desc->vertex_source : halo_host_embedded("slice.vert");
    const char *vertex_file = desc->vertex_file ? desc->vertex_file : "slice.vert";
    if (!vertex_source) {
        halo_diag_error(diag, IO_READ, "slice.vert", 0, 0, "no vertex shader: slice.vert is not embedded");
        goto fail;
    }
    if (desc->program) {
        s->program = halo_gl_program_build(desc->runtime, desc->program, vertex_source, vertex_file, diag);
    } else {
        const char *fragment_source = desc->fragment_source ? desc->fragment_source : halo_host_embedded(default_fragment);
        const char *fragment_file = desc->fragment_file ? desc->fragment_file : default_fragment;
        if (!fragment_source) {
            halo_diag_error(diag, IO_READ, default_fragment, 0, 0, "no fragment shader: %s is not embedded",
                            default_fragment);
            goto fail;
        }
        s->program = link_raw(f, vertex_source, vertex_file, fragment_source, fragment_file, diag);
    }
    if (!s->program)
        goto fail;
    f->GenVertexArrays(1, &s->vertex_array);
    f->GenTextures(2, s->textures);
    for (int k = 0; k < (slab ? 2 : 1); ++k) {
        f->BindTexture(GL_TEXTURE_2D, s->textures[k]);
        f->TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
        f->TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
        f->TexImage2D(GL_TEXTURE_2D, 0, GL_RGBA32F, s->width, s->height, 0, GL_RGBA, GL_FLOAT, NULL);
    }
    f->BindTexture(GL_TEXTURE_2D, 0);
    f->GenFramebuffers(1, &s->framebuffer);
    f->BindFramebuffer(GL_FRAMEBUFFER, s->framebuffer);
    f->FramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, s->textures[0], 0);
    GLenum status = f->CheckFramebufferStatus(GL_FRAMEBUFFER);
    f->BindFramebuffer(GL_FRAMEBUFFER, 0);
    GLenum error = f->GetError();
    if (status != GL_FRAMEBUFFER_COMPLETE || error != GL_NO_ERROR) {
        halo_diag_error(diag, GL_LINK, "", 0, 0, "cannot create a %dx%d RGBA32F render target (status 0x%x, GL error 0x%x)",
                        s->width, s->height, status, error);
        goto fail;
    }
    const halo_program *p = desc->program;
    if (p && (halo_program_image_count(p) || halo_program_output_count(p) || halo_program_sampler_count(p))) {
        s->frame = halo_gl_frame_create(desc->runtime, p, s->width, s->height, diag);
        if (!s->frame)
            goto fail;
    }
    f->GenTextures(1, &s->volume_texture);
    f->GenTextures(1, &s->transfer_texture);
    halo_slice_set_render(s, NULL, diag);
    halo_slice_set_camera(s, 30.0, 20.0, 1.0);
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
    if (s->framebuffer)
        f->DeleteFramebuffers(1, &s->framebuffer);
    if (s->textures[0])
        f->DeleteTextures(2, s->textures);
    if (s->volume_texture)
        f->DeleteTextures(1, &s->volume_texture);
    if (s->transfer_texture)
        f->DeleteTextures(1, &s->transfer_texture);
    if (s->vertex_array)
        f->DeleteVertexArrays(1, &s->vertex_array);
    if (s->program)
        f->DeleteProgram(s->program);
    free(s);
}

unsigned halo_slice_gl_program(const halo_slice *s)
{
    return s ? s->program : 0;
}

halo_gl_frame *halo_slice_frame(const halo_slice *s)
{
    return s ? s->frame : NULL;
}

long halo_slice_draws(const halo_slice *s)
{
    return s ? s->draws : 0;
}

long halo_slice_pass_draws(const halo_slice *s)
{
    return s ? s->pass_draws : 0;
}

void halo_slice_set_interval(halo_slice *s, int interval)
{
    if (s)
        s->interval_override = interval > 0 ? interval : 0;
}

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
    const halo_uniform_info *u = s->linked ? halo_program_find_uniform(s->linked, "halo_generate", "interval") : NULL;
    if (u && u->value && u->count > 0 && u->value[0] >= 1.0)
        return (int)u->value[0];
    return 4;
}

halo_status halo_slice_set_volume(halo_slice *s, const float *data, int nx, int ny, int nz, halo_diagnostics *diag)
{
    if (!s || !data || nx < 2 || ny < 2 || nz < 2 || nx > 2048 || ny > 2048 || nz > 2048) {
        halo_diag_error(diag, USAGE, "", 0, 0, "volume of %dx%dx%d voxels: each side must be 2..2048", nx, ny, nz);
        return HALO_ERROR_INPUT;
    }
    const halo_glfuncs *f = s->f;
    f->BindTexture(GL_TEXTURE_3D, s->volume_texture);
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
    s->volume = data;
    s->dims[0] = nx;
    s->dims[1] = ny;
    s->dims[2] = nz;
    return HALO_OK;
}

halo_status halo_slice_set_render(halo_slice *s, const halo_render_settings *settings, halo_diagnostics *diag)
{
    if (!s)
        return HALO_ERROR_INPUT;
    fill_transfer(s->transfer, settings);
    const halo_glfuncs *f = s->f;
    f->BindTexture(GL_TEXTURE_2D, s->transfer_texture);
    f->TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    f->TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    f->TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    f->TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    f->TexImage2D(GL_TEXTURE_2D, 0, GL_RGBA32F, HALO_RAYCAST_TRANSFER_TEXELS, 1, 0, GL_RGBA, GL_FLOAT, s->transfer);
    f->BindTexture(GL_TEXTURE_2D, 0);
    double step = settings && settings->step > 0.0 && isfinite(settings->step) ? settings->step : 0.5;
    s->step_voxels = (float)step;
    for (int c = 0; c < 3; ++c)
        s->background[c] = settings ? (float)settings->background[c] : 0.0f;
    GLenum error = f->GetError();
    if (error != GL_NO_ERROR) {
        halo_diag_error(diag, IO_READ, "", 0, 0, "cannot upload the transfer function (GL error 0x%x)", error);
        return HALO_ERROR_IO;
    }
    return HALO_OK;
}

/* ---- Camera (the ray caster's, raycast.c) ------------------------------------------------ */

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

void halo_slice_set_camera(halo_slice *s, double azimuth, double elevation, double zoom)
{
    if (!s)
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
    double back[3] = {cos(el) * sin(az), sin(el), cos(el) * cos(az)};
    double eye[3] = {centre + distance * back[0], centre + distance * back[1], centre + distance * back[2]};
    double right[3] = {cos(az), 0.0, -sin(az)};
    double up[3] = {back[1] * right[2] - back[2] * right[1], back[2] * right[0] - back[0] * right[2],
                    back[0] * right[1] - back[1] * right[0]};
    double view[16] = {right[0], up[0], back[0], 0.0, right[1], up[1], back[1], 0.0,
                       right[2], up[2], back[2], 0.0, 0.0, 0.0, 0.0, 1.0};
    for (int row = 0; row < 3; ++row)
        view[12 + row] = -(view[row] * eye[0] + view[4 + row] * eye[1] + view[8 + row] * eye[2]);
    double aspect = (double)s->width / s->height;
    double near_plane = distance - radius > 0.01 ? distance - radius : 0.01;
    double far_plane = distance + radius + 1.0;
    double t = tan(half_fov);
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
        s->inverse_view_projection[i] = (float)inverse[i];
    for (int c = 0; c < 3; ++c) {
        s->eye[c] = (float)eye[c];
        s->view_axis[c] = (float)-back[c];
        s->screen_right[c] = (float)right[c];
        s->screen_up[c] = (float)up[c];
    }
}

static int max_dimension(const int dims[3])
{
    int m = dims[0] > dims[1] ? dims[0] : dims[1];
    return m > dims[2] ? m : dims[2];
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
    int voxels = s->volume ? max_dimension(s->dims) : 1;
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

halo_status halo_slice_render(halo_slice *s, float *rgba, halo_diagnostics *diag)
{
    if (!s || !rgba)
        return HALO_ERROR_INPUT;
    if (!s->volume) {
        halo_diag_error(diag, USAGE, "", 0, 0, "slice host: no volume uploaded");
        return HALO_ERROR_INPUT;
    }
    halo_slice_state st;
    halo_slice_get_state(s, &st);
    const halo_glfuncs *f = s->f;
    GLuint program = s->program;
    static const GLfloat zero[4] = {0, 0, 0, 0};
    long pass_draws_before = halo_gl_frame_pass_draws(s->frame);
    s->draws = 0;

    f->BindFramebuffer(GL_FRAMEBUFFER, s->framebuffer);
    f->FramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, s->textures[0], 0);
    GLenum buffer = GL_COLOR_ATTACHMENT0;
    f->DrawBuffers(1, &buffer);
    f->Viewport(0, 0, s->width, s->height);
    f->Disable(GL_DEPTH_TEST);
    f->Disable(GL_SCISSOR_TEST);
    f->ClearBufferfv(GL_COLOR, 0, zero);
    f->UseProgram(program);
    if (s->linked)
        halo_gl_program_upload(s->runtime, s->linked, program);
    f->ActiveTexture(GL_TEXTURE0);
    f->BindTexture(GL_TEXTURE_3D, s->volume_texture);
    f->ActiveTexture(GL_TEXTURE1);
    f->BindTexture(GL_TEXTURE_2D, s->transfer_texture);
    f->ActiveTexture(GL_TEXTURE0);
    f->Uniform1i(f->GetUniformLocation(program, "volume_texture"), 0);
    f->Uniform1i(f->GetUniformLocation(program, "transfer_texture"), 1);
    f->Uniform1i(f->GetUniformLocation(program, "ray_state"), 2);
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
    }
    if (s->slab) {
        f->Disable(GL_BLEND);
    } else {
        /* front to back: dst += (1 - dst.a) * src, src premultiplied */
        f->Enable(GL_BLEND);
        f->BlendEquation(GL_FUNC_ADD);
        f->BlendFunc(GL_ONE_MINUS_DST_ALPHA, GL_ONE);
    }
    int interval = st.interval;
    int generate = s->frame && halo_program_pass_count(s->linked) > 0;
    if (s->frame) {
        halo_gl_frame_begin(s->frame);
        halo_gl_frame_attach(s->frame, s->framebuffer); /* buffer 0 keeps the blend set above */
        halo_gl_frame_bind(s->frame, program, 3);
    }
    f->BindVertexArray(s->vertex_array);
    int current = 0;
    if (!s->slab) {
        GLint distance_location = f->GetUniformLocation(program, "slice_distance");
        for (int k = 0; k < st.slice_count; ++k) {
            f->Uniform1f(distance_location, (float)(st.first_distance + k * st.step_size));
            f->DrawArrays(GL_TRIANGLES, 0, 3);
            s->draws++;
            if (generate && (k + 1) % interval == 0 && k + 1 < st.slice_count)
                halo_gl_frame_generate(s->frame);
            if (s->progress)
                s->progress(k + 1, st.slice_count, s->progress_user);
        }
        f->Disable(GL_BLEND);
    } else {
        GLint first_location = f->GetUniformLocation(program, "first_distance");
        GLint samples_location = f->GetUniformLocation(program, "slab_samples");
        for (int k = 0; k < st.slice_count; k += interval) {
            int samples = st.slice_count - k < interval ? st.slice_count - k : interval;
            f->FramebufferTexture2D(GL_DRAW_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D,
                                    s->textures[1 - current], 0);
            f->ActiveTexture(GL_TEXTURE2);
            f->BindTexture(GL_TEXTURE_2D, s->textures[current]);
            f->ActiveTexture(GL_TEXTURE0);
            f->Uniform1f(first_location, (float)(st.first_distance + k * st.step_size));
            f->Uniform1i(samples_location, samples);
            f->DrawArrays(GL_TRIANGLES, 0, 3);
            s->draws++;
            current = 1 - current;
            if (generate && k + interval < st.slice_count)
                halo_gl_frame_generate(s->frame);
            if (s->progress)
                s->progress((int)s->draws, (st.slice_count + interval - 1) / interval, s->progress_user);
        }
        f->ActiveTexture(GL_TEXTURE2);
        f->BindTexture(GL_TEXTURE_2D, 0);
        f->ActiveTexture(GL_TEXTURE0);
        f->BindFramebuffer(GL_FRAMEBUFFER, s->framebuffer);
        f->FramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, s->textures[current], 0);
    }
    f->BindFramebuffer(GL_READ_FRAMEBUFFER, s->framebuffer);
    f->ReadBuffer(GL_COLOR_ATTACHMENT0);
    f->PixelStorei(GL_PACK_ALIGNMENT, 4);
    f->ReadPixels(0, 0, s->width, s->height, GL_RGBA, GL_FLOAT, rgba);
    f->DrawBuffers(1, &buffer);
    f->FramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, s->textures[0], 0);
    f->BindVertexArray(0);
    f->UseProgram(0);
    f->ActiveTexture(GL_TEXTURE1);
    f->BindTexture(GL_TEXTURE_2D, 0);
    f->ActiveTexture(GL_TEXTURE0);
    f->BindTexture(GL_TEXTURE_3D, 0);
    f->BindFramebuffer(GL_FRAMEBUFFER, 0);
    s->pass_draws = halo_gl_frame_pass_draws(s->frame) - pass_draws_before;
    GLenum error = f->GetError();
    if (error != GL_NO_ERROR) {
        halo_diag_error(diag, GL_LINK, "", 0, 0, "OpenGL error 0x%x while rendering slices", error);
        return HALO_ERROR_IO;
    }
    /* the background, behind what the slices left transparent */
    size_t pixels = (size_t)s->width * (size_t)s->height;
    for (size_t i = 0; i < pixels; ++i) {
        float *px = &rgba[i * 4];
        float a = px[3];
        for (int c = 0; c < 3; ++c)
            px[c] = px[c] + (1.0f - a) * s->background[c];
        px[3] = 1.0f;
    }
    return HALO_OK;
}
