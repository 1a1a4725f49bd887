/* What the example hosts' C sides share (see host_common.h). */
#include "host_common.h"
#include "volume.h"

#include "halo.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Generated at build time by build-aux/embed.sh from examples/hosts/. */
struct halo_embedded_file {
    const char *name;
    const char *text;
};
extern const struct halo_embedded_file halo_embedded_hosts[];

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

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

/* ---- Programs ------------------------------------------------------------------ */

int halo_host_desc_check(const halo_host_desc *desc, halo_diagnostics *diag)
{
    if (!desc || !desc->gl || desc->width < 1 || desc->height < 1 || desc->width > 16384 || desc->height > 16384 ||
        (desc->program && !desc->runtime)) {
        HALO_REPORT_ERROR(diag, HALO_MSG_USAGE, "", 0, 0,
                          "host: gl, a size in 1..16384 and (with a program) a runtime are required");
        return 0;
    }
    return 1;
}

/* Driver log lines "0:LINE(COL): error: TEXT", one diagnostic each; through the
 * linked program's origins when there is one (an unlinked shader's lines already
 * refer to the file itself). */
static void report_log(halo_diagnostics *diag, halo_message_id id, const halo_program *program, const char *file,
                       const char *log)
{
    const char *p = log;
    while (p && *p) {
        const char *end = strchr(p, '\n');
        size_t n = end ? (size_t)(end - p) : strlen(p);
        int source, line = 0, column = 0, used = 0;
        const char *text = p, *origin_file = file;
        if (sscanf(p, "%d:%d(%d):%n", &source, &line, &column, &used) == 3 && used > 0 && (size_t)used <= n) {
            text = p + used;
            while (*text == ' ')
                ++text;
            if (strncmp(text, "error:", 6) == 0)
                text += 6;
            while (*text == ' ')
                ++text;
            int origin_line = line;
            if (program && !halo_program_map_line(program, HALO_PIECE_WHOLE, line, &origin_file, &origin_line))
                origin_file = file;
            line = origin_line;
        } else {
            line = column = 0;
        }
        if (n > 0)
            halo_diagnostics_report(diag, HALO_SEVERITY_ERROR, id, origin_file, line, column, NULL, "%.*s",
                                    (int)(n - (size_t)(text - p)), text);
        p = end ? end + 1 : NULL;
    }
}

static GLuint compile_raw(const halo_glfuncs *f, GLenum type, const halo_program *program, const char *source,
                          const char *file, int log_style, halo_diagnostics *diag)
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
    if (log_style == HALO_HOST_LOG_LINES) {
        if (log) {
            f->GetShaderInfoLog(shader, length, NULL, log);
            report_log(diag, HALO_MSG_GL_COMPILE, program, file, log);
            free(log);
        }
        HALO_REPORT_ERROR(diag, HALO_MSG_GL_COMPILE, file, 0, 0, "the driver rejected '%s'", file);
    } else {
        if (log)
            f->GetShaderInfoLog(shader, length, NULL, log);
        HALO_REPORT_ERROR(diag, HALO_MSG_GL_COMPILE, file, 0, 0, "the driver rejected '%s': %s", file, log ? log : "");
        free(log);
    }
    f->DeleteShader(shader);
    return 0;
}

GLuint halo_host_link_raw(const halo_glfuncs *f, const char *vertex_source, const char *vertex_file,
                          const char *fragment_source, const char *fragment_file, int log_style, halo_diagnostics *diag)
{
    return halo_host_link_mapped(f, NULL, vertex_source, vertex_file, NULL, fragment_source, fragment_file, log_style,
                                 diag);
}

GLuint halo_host_link_mapped(const halo_glfuncs *f, const halo_program *vertex_program, const char *vertex_source,
                             const char *vertex_file, const halo_program *fragment_program, const char *fragment_source,
                             const char *fragment_file, int log_style, halo_diagnostics *diag)
{
    GLuint vertex = compile_raw(f, GL_VERTEX_SHADER, vertex_program, vertex_source, vertex_file, log_style, diag);
    GLuint fragment =
        compile_raw(f, GL_FRAGMENT_SHADER, fragment_program, fragment_source, fragment_file, log_style, diag);
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
    if (log_style == HALO_HOST_LOG_LINES) {
        f->GetProgramiv(program, GL_INFO_LOG_LENGTH, &length);
        char *log = calloc((size_t)(length > 0 ? length : 1) + 1, 1);
        if (log) {
            f->GetProgramInfoLog(program, length, NULL, log);
            report_log(diag, HALO_MSG_GL_LINK, NULL, fragment_file, log);
            free(log);
        }
    }
    HALO_REPORT_ERROR(diag, HALO_MSG_GL_LINK, fragment_file, 0, 0, "the driver could not link '%s'", fragment_file);
    f->DeleteProgram(program);
    return 0;
}

GLuint halo_host_program_build(const halo_host_desc *desc, const char *default_vertex, const char *default_fragment,
                               int log_style, halo_diagnostics *diag)
{
    const char *vertex_source = desc->vertex_source ? desc->vertex_source : halo_host_embedded(default_vertex);
    const char *vertex_file = desc->vertex_file ? desc->vertex_file : default_vertex;
    if (!vertex_source) {
        HALO_REPORT_ERROR(diag, HALO_MSG_IO_READ, default_vertex, 0, 0, "no vertex shader: %s is not embedded",
                          default_vertex);
        return 0;
    }
    if (desc->program && halo_program_reflection(desc->program).target == HALO_TARGET_ES300 &&
        !strncmp(vertex_source, "#version 330 core\n", 18)) {
        /* the example vertex shaders are in the common subset of GLSL 330 and ES 300 */
        size_t length = strlen(vertex_source) + 64;
        char *es = malloc(length);
        if (!es) {
            HALO_REPORT_ERROR(diag, HALO_MSG_OUT_OF_MEMORY, "", 0, 0, "out of memory");
            return 0;
        }
        snprintf(es, length, "#version 300 es\nprecision highp float;\n%s", vertex_source + 18);
        GLuint program = halo_gl_program_build(desc->runtime, desc->program, es, vertex_file, NULL, diag);
        free(es);
        return program;
    }
    if (desc->program)
        return halo_gl_program_build(desc->runtime, desc->program, vertex_source, vertex_file, NULL, diag);
    const char *fragment_source = desc->fragment_source ? desc->fragment_source : halo_host_embedded(default_fragment);
    const char *fragment_file = desc->fragment_file ? desc->fragment_file : default_fragment;
    if (!fragment_source) {
        HALO_REPORT_ERROR(diag, HALO_MSG_IO_READ, default_fragment, 0, 0, "no fragment shader: %s is not embedded",
                          default_fragment);
        return 0;
    }
    return halo_host_link_raw(desc->gl, vertex_source, vertex_file, fragment_source, fragment_file, log_style, diag);
}

/* ---- Targets and textures ------------------------------------------------------- */

void halo_host_image_texture(const halo_glfuncs *f, GLuint texture, GLint internal_format, int width, int height,
                             GLenum format, GLenum type)
{
    f->BindTexture(GL_TEXTURE_2D, texture);
    f->TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    f->TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    f->TexImage2D(GL_TEXTURE_2D, 0, internal_format, width, height, 0, format, type, NULL);
}

void *halo_host_calloc(size_t size, halo_diagnostics *diag)
{
    void *p = calloc(1, size);
    if (!p)
        HALO_REPORT_ERROR(diag, HALO_MSG_OUT_OF_MEMORY, "", 0, 0, "out of memory");
    return p;
}

halo_status halo_host_gl_check(const halo_glfuncs *f, halo_message_id id, const char *failed, halo_diagnostics *diag)
{
    GLenum error = f->GetError();
    if (error == GL_NO_ERROR)
        return HALO_OK;
    halo_diagnostics_report(diag, HALO_SEVERITY_ERROR, id, "", 0, 0, NULL, "%s (GL error 0x%x)", failed, error);
    return HALO_ERROR_IO;
}

int halo_host_framebuffer(const halo_glfuncs *f, GLuint *framebuffer, GLuint color_texture, int width, int height,
                          halo_diagnostics *diag)
{
    f->GenFramebuffers(1, framebuffer);
    f->BindFramebuffer(GL_FRAMEBUFFER, *framebuffer);
    f->FramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, color_texture, 0);
    GLenum status = f->CheckFramebufferStatus(GL_FRAMEBUFFER);
    f->BindFramebuffer(GL_FRAMEBUFFER, 0);
    GLenum error = f->GetError();
    if (status != GL_FRAMEBUFFER_COMPLETE || error != GL_NO_ERROR) {
        HALO_REPORT_ERROR(diag, HALO_MSG_GL_LINK, "", 0, 0,
                          "cannot create a %dx%d RGBA32F render target (status 0x%x, GL error 0x%x)", width, height,
                          status, error);
        return 0;
    }
    return 1;
}

/* internal_format GL_R32F, or a gradient format (RGB, data NULL: the storage only). */
static halo_status upload_volume(const halo_glfuncs *f, GLuint texture, const float *data, int nx, int ny, int nz,
                                 GLint filter, GLint internal_format, const char *what, halo_diagnostics *diag);

halo_status halo_host_upload_volume(const halo_glfuncs *f, GLuint texture, const float *data, int nx, int ny, int nz,
                                    halo_diagnostics *diag)
{
    return upload_volume(f, texture, data, nx, ny, nz, GL_LINEAR, GL_R32F, "volume", diag);
}

halo_status halo_host_upload_classified(const halo_glfuncs *f, GLuint texture, const float *rgba, int nx, int ny,
                                        int nz, halo_diagnostics *diag)
{
    return upload_volume(f, texture, rgba, nx, ny, nz, GL_LINEAR, GL_RGBA8, "classified volume", diag);
}

halo_status halo_host_upload_labels(const halo_glfuncs *f, GLuint texture, const float *labels, int nx, int ny, int nz,
                                    halo_diagnostics *diag)
{
    return upload_volume(f, texture, labels, nx, ny, nz, GL_NEAREST, GL_R32F, "label volume", diag);
}

/* Calls fn on every slab of at most HALO_HOST_GRADIENT_SLAB_BYTES of gradients. */
static int each_gradient_slab(const float *volume, const int dims[3], float *gradients, int slab,
                              void (*fn)(const float *gradients, int z, int count, void *user), void *user)
{
    for (int z = 0; z < dims[2]; z += slab) {
        int count = dims[2] - z < slab ? dims[2] - z : slab;
        halo_volume_gradients_slab(volume, dims, z, count, gradients);
        fn(gradients, z, count, user);
    }
    return 1;
}

typedef struct gradient_upload {
    const halo_glfuncs *f;
    int nx, ny;
    float inverse_scale;
} gradient_upload;

static void gradient_store(const float *gradients, int z, int count, void *user)
{
    gradient_upload *u = user;
    if (u->inverse_scale != 1.0f) {
        /* g / scale in [-1, 1]: GL converts floats to snorm as round(127 c) */
        float *g = (float *)gradients;
        size_t n = (size_t)u->nx * (size_t)u->ny * (size_t)count * 3;
        for (size_t i = 0; i < n; ++i)
            g[i] *= u->inverse_scale;
    }
    u->f->TexSubImage3D(GL_TEXTURE_3D, 0, 0, 0, z, u->nx, u->ny, count, GL_RGB, GL_FLOAT, gradients);
}

static int gradient_format_known(GLint internal_format)
{
    return internal_format == GL_RGB32F || internal_format == GL_RGB16F || internal_format == GL_RGB8_SNORM;
}

/* The packed formats (halo_host_build_packed): the value and the gradient in one texture. */
static int packed_format(GLint internal_format)
{
    return internal_format == GL_RGBA16_SNORM || internal_format == GL_RGBA32F;
}

/* The gradient texture's storage (no data); usable 0 or an unknown format: USAGE with
 * refusal named. */
static halo_status gradient_storage(const halo_glfuncs *f, GLuint texture, int nx, int ny, int nz,
                                    GLint internal_format, int usable, const char *refusal, halo_diagnostics *diag)
{
    if (!usable || !(gradient_format_known(internal_format) || packed_format(internal_format))) {
        HALO_REPORT_ERROR(diag, HALO_MSG_USAGE, "", 0, 0,
                          "gradient volume: %s or not RGB32F, RGB16F, RGB8_SNORM, RGBA16_SNORM, RGBA32F", refusal);
        return HALO_ERROR_INPUT;
    }
    return upload_volume(f, texture, NULL, nx, ny, nz, GL_LINEAR, internal_format, "gradient volume", diag);
}

float halo_host_gradient_scale(const float *volume, const int dims[3], GLint internal_format)
{
    if (internal_format == GL_RGB32F || internal_format == GL_RGBA32F)
        return 1.0f;
    /* snorm: the 8 bits span the volume's own range; half: only values beyond the
     * contract's [0,1] (|g| > 1) are scaled, before they reach half's 65504 */
    float largest = halo_volume_largest_gradient(volume, dims);
    int normalised = internal_format == GL_RGB8_SNORM || internal_format == GL_RGBA16_SNORM;
    return largest > (normalised ? 0.0f : 1.0f) && isfinite(largest) ? largest : 1.0f;
}

halo_status halo_host_upload_gradients(const halo_glfuncs *f, GLuint texture, const float *volume, int nx, int ny,
                                       int nz, GLint internal_format, float *scale, halo_diagnostics *diag)
{
    /* the texture's storage first (no data), then slab by slab */
    halo_status status =
        gradient_storage(f, texture, nx, ny, nz, internal_format, volume && scale, "no volume, no scale", diag);
    if (status != HALO_OK)
        return status;
    size_t slice_bytes = (size_t)nx * (size_t)ny * 3 * sizeof(float);
    int slab = (int)(HALO_HOST_GRADIENT_SLAB_BYTES / slice_bytes);
    slab = slab < 1 ? 1 : slab > nz ? nz : slab;
    float *gradients = malloc(slice_bytes * (size_t)slab);
    if (!gradients) {
        HALO_REPORT_ERROR(diag, HALO_MSG_OUT_OF_MEMORY, "", 0, 0,
                          "out of memory for the gradients of %d slices of %dx%d voxels", slab, nx, ny);
        return HALO_ERROR_IO;
    }
    const int dims[3] = {nx, ny, nz};
    *scale = halo_host_gradient_scale(volume, dims, internal_format);
    gradient_upload u = {.f = f, .nx = nx, .ny = ny, .inverse_scale = 1.0f / *scale};
    f->BindTexture(GL_TEXTURE_3D, texture);
    f->PixelStorei(GL_UNPACK_ALIGNMENT, 4);
    each_gradient_slab(volume, dims, gradients, slab, gradient_store, &u);
    f->BindTexture(GL_TEXTURE_3D, 0);
    free(gradients);
    GLenum error = f->GetError();
    if (error != GL_NO_ERROR) {
        HALO_REPORT_ERROR(diag, HALO_MSG_IO_READ, "", 0, 0,
                          "cannot upload the gradients of a %dx%dx%d volume (GL error 0x%x)", nx, ny, nz, error);
        return HALO_ERROR_IO;
    }
    return HALO_OK;
}

/* A framebuffer with layer 0 of texture attached: complete or not. Leaves framebuffer 0
 * bound and the framebuffer deleted. */
static int layer_renderable(const halo_glfuncs *f, GLuint texture)
{
    GLuint framebuffer = 0;
    f->GenFramebuffers(1, &framebuffer);
    f->BindFramebuffer(GL_FRAMEBUFFER, framebuffer);
    f->FramebufferTextureLayer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, texture, 0, 0);
    int complete = f->CheckFramebufferStatus(GL_FRAMEBUFFER) == GL_FRAMEBUFFER_COMPLETE;
    f->BindFramebuffer(GL_FRAMEBUFFER, 0);
    f->DeleteFramebuffers(1, &framebuffer);
    return complete;
}

int halo_host_gradients_renderable(const halo_glfuncs *f, GLint internal_format)
{
    if (!f || !f->FramebufferTextureLayer ||
        !(gradient_format_known(internal_format) || packed_format(internal_format)))
        return 0;
    /* a probe of 2^3 texels: the real texture's storage comes when it is built */
    GLuint probe = 0;
    f->GenTextures(1, &probe);
    f->BindTexture(GL_TEXTURE_3D, probe);
    f->TexImage3D(GL_TEXTURE_3D, 0, internal_format, 2, 2, 2, 0, GL_RGB, GL_FLOAT, NULL);
    f->BindTexture(GL_TEXTURE_3D, 0);
    int renderable = f->GetError() == GL_NO_ERROR && layer_renderable(f, probe);
    f->DeleteTextures(1, &probe);
    while (f->GetError() != GL_NO_ERROR)
        ; /* an incomplete probe is an answer, not an error for the caller */
    return renderable;
}

static halo_status build_on_gpu(const halo_glfuncs *f, GLuint texture, GLuint volume_texture, int nx, int ny, int nz,
                                GLint internal_format, float scale, const float value_encode[2],
                                halo_diagnostics *diag);

halo_status halo_host_build_gradients(const halo_glfuncs *f, GLuint texture, GLuint volume_texture, int nx, int ny,
                                      int nz, GLint internal_format, float scale, halo_diagnostics *diag)
{
    if (packed_format(internal_format)) {
        HALO_REPORT_ERROR(diag, HALO_MSG_USAGE, "", 0, 0,
                          "gradient volume: RGBA holds the value too: halo_host_build_packed");
        return HALO_ERROR_INPUT;
    }
    return build_on_gpu(f, texture, volume_texture, nx, ny, nz, internal_format, scale, NULL, diag);
}

void halo_host_value_range(const float *volume, const int dims[3], float range[2])
{
    float lo = INFINITY, hi = -INFINITY;
    size_t n = (size_t)dims[0] * (size_t)dims[1] * (size_t)dims[2];
    for (size_t i = 0; volume && i < n; ++i)
        if (isfinite(volume[i])) {
            lo = volume[i] < lo ? volume[i] : lo;
            hi = volume[i] > hi ? volume[i] : hi;
        }
    range[0] = lo <= hi ? lo : 0.0f;
    range[1] = lo < hi && isfinite(hi - lo) ? hi - lo : 1.0f;
}

halo_status halo_host_build_packed(const halo_glfuncs *f, GLuint texture, GLuint volume_texture, int nx, int ny, int nz,
                                   GLint internal_format, float scale, const float value_range[2],
                                   halo_diagnostics *diag)
{
    if (!packed_format(internal_format)) {
        HALO_REPORT_ERROR(diag, HALO_MSG_USAGE, "", 0, 0, "packed volume: RGBA16_SNORM or RGBA32F");
        return HALO_ERROR_INPUT;
    }
    const float encode[2] = {value_range[0], 1.0f / value_range[1]};
    return build_on_gpu(f, texture, volume_texture, nx, ny, nz, internal_format, scale, encode, diag);
}

static halo_status build_on_gpu(const halo_glfuncs *f, GLuint texture, GLuint volume_texture, int nx, int ny, int nz,
                                GLint internal_format, float scale, const float value_encode[2], halo_diagnostics *diag)
{
    halo_status status =
        gradient_storage(f, texture, nx, ny, nz, internal_format, f && f->FramebufferTextureLayer && scale > 0.0f,
                         "on the GPU: no glFramebufferTextureLayer, no scale", diag);
    if (status != HALO_OK)
        return status;
    GLuint program =
        halo_host_link_raw(f, halo_host_embedded("slice.vert"), "slice.vert", halo_host_embedded("gradient.frag"),
                           "gradient.frag", HALO_HOST_LOG_APPENDED, diag);
    if (!program)
        return HALO_ERROR_IO;
    GLuint framebuffer = 0, vertex_array = 0;
    f->GenFramebuffers(1, &framebuffer);
    f->GenVertexArrays(1, &vertex_array);
    f->BindFramebuffer(GL_FRAMEBUFFER, framebuffer);
    static const GLenum draw_buffer = GL_COLOR_ATTACHMENT0;
    f->DrawBuffers(1, &draw_buffer);
    f->Viewport(0, 0, nx, ny);
    f->Disable(GL_BLEND);
    f->Disable(GL_DEPTH_TEST);
    f->Disable(GL_SCISSOR_TEST);
    f->UseProgram(program);
    f->ActiveTexture(GL_TEXTURE0);
    f->BindTexture(GL_TEXTURE_3D, volume_texture);
    f->Uniform1i(f->GetUniformLocation(program, "volume_texture"), 0);
    f->Uniform1f(f->GetUniformLocation(program, "inverse_scale"), 1.0f / scale);
    f->Uniform1i(f->GetUniformLocation(program, "to_half"), internal_format == GL_RGB16F);
    f->Uniform1i(f->GetUniformLocation(program, "pack_value"), value_encode != NULL);
    if (value_encode)
        f->Uniform2f(f->GetUniformLocation(program, "value_encode"), value_encode[0], value_encode[1]);
    GLint layer = f->GetUniformLocation(program, "layer");
    f->BindVertexArray(vertex_array);
    for (int z = 0; z < nz && status == HALO_OK; ++z) {
        f->FramebufferTextureLayer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, texture, 0, z);
        if (z == 0 && f->CheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
            HALO_REPORT_ERROR(diag, HALO_MSG_GL_LINK, "", 0, 0, "the gradient texture's layers are not renderable");
            status = HALO_ERROR_IO;
            break;
        }
        f->Uniform1i(layer, z);
        f->DrawArrays(GL_TRIANGLES, 0, 3);
    }
    f->FramebufferTextureLayer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, 0, 0, 0);
    f->BindVertexArray(0);
    f->BindTexture(GL_TEXTURE_3D, 0);
    f->UseProgram(0);
    f->BindFramebuffer(GL_FRAMEBUFFER, 0);
    f->DeleteVertexArrays(1, &vertex_array);
    f->DeleteFramebuffers(1, &framebuffer);
    f->DeleteProgram(program);
    GLenum error = f->GetError();
    if (status == HALO_OK && error != GL_NO_ERROR) {
        HALO_REPORT_ERROR(diag, HALO_MSG_GL_LINK, "", 0, 0,
                          "OpenGL error 0x%x while building the gradients of a %dx%dx%d volume", error, nx, ny, nz);
        status = HALO_ERROR_IO;
    }
    return status;
}

/* data NULL: the storage only (halo_host_upload_gradients fills it slab by slab). */
static halo_status upload_volume(const halo_glfuncs *f, GLuint texture, const float *data, int nx, int ny, int nz,
                                 GLint filter, GLint internal_format, const char *what, halo_diagnostics *diag)
{
    int rgb = internal_format != GL_R32F,
        rgba = internal_format == GL_RGBA16_SNORM || internal_format == GL_RGBA32F || internal_format == GL_RGBA8;
    if (!f || (!data && !rgb) || nx < 2 || ny < 2 || nz < 2 || nx > 2048 || ny > 2048 || nz > 2048) {
        HALO_REPORT_ERROR(diag, HALO_MSG_USAGE, "", 0, 0, "%s of %dx%dx%d voxels: each side must be 2..2048", what, nx,
                          ny, nz);
        return HALO_ERROR_INPUT;
    }
    f->BindTexture(GL_TEXTURE_3D, texture);
    f->TexParameteri(GL_TEXTURE_3D, GL_TEXTURE_MIN_FILTER, filter);
    f->TexParameteri(GL_TEXTURE_3D, GL_TEXTURE_MAG_FILTER, filter);
    f->TexParameteri(GL_TEXTURE_3D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    f->TexParameteri(GL_TEXTURE_3D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    f->TexParameteri(GL_TEXTURE_3D, GL_TEXTURE_WRAP_R, GL_CLAMP_TO_EDGE);
    f->PixelStorei(GL_UNPACK_ALIGNMENT, 4);
    f->TexImage3D(GL_TEXTURE_3D, 0, internal_format, nx, ny, nz, 0,
                  rgba  ? GL_RGBA
                  : rgb ? GL_RGB
                        : GL_RED,
                  GL_FLOAT, data);
    f->BindTexture(GL_TEXTURE_3D, 0);
    char failed[96];
    snprintf(failed, sizeof failed, "cannot upload a %dx%dx%d %s", nx, ny, nz, what);
    return halo_host_gl_check(f, HALO_MSG_IO_READ, failed, diag);
}

void halo_host_fill_transfer(float *table, const halo_render_settings *s)
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

halo_status halo_host_upload_transfer(const halo_glfuncs *f, GLuint texture, float *table,
                                      const halo_render_settings *settings, float *step_voxels, float background[3],
                                      halo_diagnostics *diag)
{
    halo_host_fill_transfer(table, settings);
    f->BindTexture(GL_TEXTURE_2D, texture);
    f->TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    f->TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    f->TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    f->TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    f->TexImage2D(GL_TEXTURE_2D, 0, GL_RGBA32F, HALO_RAYCAST_TRANSFER_TEXELS, 1, 0, GL_RGBA, GL_FLOAT, table);
    f->BindTexture(GL_TEXTURE_2D, 0);
    double step = settings && settings->step > 0.0 && isfinite(settings->step) ? settings->step : 0.5;
    *step_voxels = (float)step;
    for (int c = 0; c < 3; ++c)
        background[c] = settings ? (float)settings->background[c] : 0.0f;
    return halo_host_gl_check(f, HALO_MSG_IO_READ, "cannot upload the transfer function", diag);
}

int halo_host_max_dimension(const int dims[3])
{
    int m = dims[0] > dims[1] ? dims[0] : dims[1];
    return m > dims[2] ? m : dims[2];
}

/* ---- Camera ---------------------------------------------------------------------- */

void halo_host_matrix_multiply(const double a[16], const double b[16], double out[16])
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

/* The inverse as the adjugate over the determinant, from the 2x2 minors of the upper
 * and the lower two rows (Laplace expansion); 0 for a singular matrix. */
int halo_host_matrix_invert(const double m[16], double out[16])
{
    /* a[row][col] of the column-major m */
#define A(row, col) m[(col)*4 + (row)]
    double s0 = A(0, 0) * A(1, 1) - A(1, 0) * A(0, 1), s1 = A(0, 0) * A(1, 2) - A(1, 0) * A(0, 2);
    double s2 = A(0, 0) * A(1, 3) - A(1, 0) * A(0, 3), s3 = A(0, 1) * A(1, 2) - A(1, 1) * A(0, 2);
    double s4 = A(0, 1) * A(1, 3) - A(1, 1) * A(0, 3), s5 = A(0, 2) * A(1, 3) - A(1, 2) * A(0, 3);
    double c5 = A(2, 2) * A(3, 3) - A(3, 2) * A(2, 3), c4 = A(2, 1) * A(3, 3) - A(3, 1) * A(2, 3);
    double c3 = A(2, 1) * A(3, 2) - A(3, 1) * A(2, 2), c2 = A(2, 0) * A(3, 3) - A(3, 0) * A(2, 3);
    double c1 = A(2, 0) * A(3, 2) - A(3, 0) * A(2, 2), c0 = A(2, 0) * A(3, 1) - A(3, 0) * A(2, 1);
    double det = s0 * c5 - s1 * c4 + s2 * c3 + s3 * c2 - s4 * c1 + s5 * c0;
    if (!(fabs(det) >= 1e-300) || !isfinite(det))
        return 0;
    double k = 1.0 / det, r[4][4];
    r[0][0] = (A(1, 1) * c5 - A(1, 2) * c4 + A(1, 3) * c3) * k;
    r[0][1] = (-A(0, 1) * c5 + A(0, 2) * c4 - A(0, 3) * c3) * k;
    r[0][2] = (A(3, 1) * s5 - A(3, 2) * s4 + A(3, 3) * s3) * k;
    r[0][3] = (-A(2, 1) * s5 + A(2, 2) * s4 - A(2, 3) * s3) * k;
    r[1][0] = (-A(1, 0) * c5 + A(1, 2) * c2 - A(1, 3) * c1) * k;
    r[1][1] = (A(0, 0) * c5 - A(0, 2) * c2 + A(0, 3) * c1) * k;
    r[1][2] = (-A(3, 0) * s5 + A(3, 2) * s2 - A(3, 3) * s1) * k;
    r[1][3] = (A(2, 0) * s5 - A(2, 2) * s2 + A(2, 3) * s1) * k;
    r[2][0] = (A(1, 0) * c4 - A(1, 1) * c2 + A(1, 3) * c0) * k;
    r[2][1] = (-A(0, 0) * c4 + A(0, 1) * c2 - A(0, 3) * c0) * k;
    r[2][2] = (A(3, 0) * s4 - A(3, 1) * s2 + A(3, 3) * s0) * k;
    r[2][3] = (-A(2, 0) * s4 + A(2, 1) * s2 - A(2, 3) * s0) * k;
    r[3][0] = (-A(1, 0) * c3 + A(1, 1) * c1 - A(1, 2) * c0) * k;
    r[3][1] = (A(0, 0) * c3 - A(0, 1) * c1 + A(0, 2) * c0) * k;
    r[3][2] = (-A(3, 0) * s3 + A(3, 1) * s1 - A(3, 2) * s0) * k;
    r[3][3] = (A(2, 0) * s3 - A(2, 1) * s1 + A(2, 2) * s0) * k;
#undef A
    for (int row = 0; row < 4; ++row)
        for (int col = 0; col < 4; ++col)
            out[col * 4 + row] = r[row][col];
    return 1;
}

void halo_host_perspective(double half_fov, double aspect, double near_plane, double far_plane, double out[16])
{
    double t = tan(half_fov);
    /* The field of view spans the smaller image side. */
    double sx = aspect >= 1.0 ? 1.0 / (t * aspect) : 1.0 / t;
    double sy = aspect >= 1.0 ? 1.0 / t : aspect / t;
    double projection[16] = {sx,
                             0.0,
                             0.0,
                             0.0,
                             0.0,
                             sy,
                             0.0,
                             0.0,
                             0.0,
                             0.0,
                             -(far_plane + near_plane) / (far_plane - near_plane),
                             -1.0,
                             0.0,
                             0.0,
                             -2.0 * far_plane * near_plane / (far_plane - near_plane),
                             0.0};
    memcpy(out, projection, sizeof projection);
}

int halo_host_orbit_camera(double azimuth, double elevation, double zoom, int width, int height,
                           halo_host_camera *camera)
{
    return halo_host_orbit_camera_projection(azimuth, elevation, zoom, width, height, 0, camera);
}

int halo_host_orbit_camera_projection(double azimuth, double elevation, double zoom, int width, int height,
                                      int orthographic, halo_host_camera *camera)
{
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
    double *back = camera->back, *eye = camera->eye, *right = camera->right, *up = camera->up;
    back[0] = cos(el) * sin(az);
    back[1] = sin(el);
    back[2] = cos(el) * cos(az);
    for (int c = 0; c < 3; ++c)
        eye[c] = centre + distance * back[c];
    /* right stays horizontal at any elevation, so straight up and down are well defined */
    right[0] = cos(az);
    right[1] = 0.0;
    right[2] = -sin(az);
    up[0] = back[1] * right[2] - back[2] * right[1];
    up[1] = back[2] * right[0] - back[0] * right[2];
    up[2] = back[0] * right[1] - back[1] * right[0];
    double view[16] = {right[0], up[0], back[0], 0.0, right[1], up[1], back[1], 0.0,
                       right[2], up[2], back[2], 0.0, 0.0,      0.0,   0.0,     1.0};
    for (int row = 0; row < 3; ++row)
        view[12 + row] = -(view[row] * eye[0] + view[4 + row] * eye[1] + view[8 + row] * eye[2]);

    double aspect = (double)width / height;
    double near_plane = distance - radius > 0.01 ? distance - radius : 0.01;
    double far_plane = distance + radius + 1.0;
    double projection[16];
    halo_host_perspective(half_fov, aspect, near_plane, far_plane, projection);
    if (orthographic) {
        /* the same view of the bounding sphere: half the smaller side spans its radius / zoom */
        double half = radius / zoom;
        double ox = aspect >= 1.0 ? 1.0 / (half * aspect) : 1.0 / half;
        double oy = aspect >= 1.0 ? 1.0 / half : aspect / half;
        double ortho[16] = {ox,
                            0.0,
                            0.0,
                            0.0,
                            0.0,
                            oy,
                            0.0,
                            0.0,
                            0.0,
                            0.0,
                            -2.0 / (far_plane - near_plane),
                            0.0,
                            0.0,
                            0.0,
                            -(far_plane + near_plane) / (far_plane - near_plane),
                            1.0};
        memcpy(projection, ortho, sizeof projection);
    }
    double view_projection[16], inverse[16];
    halo_host_matrix_multiply(projection, view, view_projection);
    if (!halo_host_matrix_invert(view_projection, inverse))
        return 0;
    for (int i = 0; i < 16; ++i) {
        camera->inverse_view_projection[i] = (float)inverse[i];
        camera->view_projection[i] = view_projection[i];
    }
    return 1;
}

void halo_host_camera_keep(const halo_host_camera *camera, float inverse_view_projection[16], float eye[3],
                           float screen_right[3], float screen_up[3])
{
    for (int i = 0; i < 16; ++i)
        inverse_view_projection[i] = camera->inverse_view_projection[i];
    for (int c = 0; c < 3; ++c) {
        eye[c] = (float)camera->eye[c];
        screen_right[c] = (float)camera->right[c];
        screen_up[c] = (float)camera->up[c];
    }
}

/* ---- Post passes ------------------------------------------------------------------------ */

const halo_image_info *halo_host_post_image(const halo_program *p)
{
    const char *name = NULL;
    for (size_t i = 0; p && i < halo_program_reflection(p).pass_count; ++i)
        if (halo_program_reflection(p).passes[i].at)
            name = halo_program_reflection(p).passes[i].output;
    for (size_t i = 0; name && i < halo_program_reflection(p).image_count; ++i)
        if (!strcmp(halo_program_reflection(p).images[i].name, name))
            return &halo_program_reflection(p).images[i];
    return NULL;
}

halo_status halo_host_post_passes(halo_gl_frame *frame, const halo_program *p, unsigned color_texture, int width,
                                  int height, float *rgba, halo_diagnostics *diag)
{
    const halo_image_info *info = halo_host_post_image(p);
    if (!info || !frame)
        return HALO_OK;
    halo_gl_frame_post(frame, color_texture);
    size_t pixels = (size_t)width * (size_t)height;
    int channels = info->channels;
    float *image = malloc(pixels * (size_t)channels * sizeof *image);
    if (!image) {
        HALO_REPORT_ERROR(diag, HALO_MSG_OUT_OF_MEMORY, "", 0, 0, "out of memory for the post passes");
        return HALO_ERROR_IO;
    }
    halo_status status = halo_gl_frame_read(frame, info->name, image);
    for (size_t k = 0; k < pixels && status == HALO_OK; ++k) {
        const float *px = &image[k * (size_t)channels];
        float grey = 0.0f;
        for (int c = 0; c < channels; ++c)
            grey = px[c] > grey ? px[c] : grey;
        for (int c = 0; c < 3; ++c)
            rgba[k * 4 + (size_t)c] = channels >= 3 ? px[c] : grey;
        rgba[k * 4 + 3] = 1.0f;
    }
    free(image);
    if (status != HALO_OK)
        HALO_REPORT_ERROR(diag, HALO_MSG_GL_LINK, "", 0, 0, "the post passes failed (image %s)", info->name);
    return status;
}
