/* The GPU halo buffer of feature halos (Svakhine & Ebert 2003, Sec. 3.3-3.4): a 3D
 * texture holding, per texel, the normalized sum of the halo influences of the
 * qualified voxels around it, built by additive splatting. The texture is rendered one
 * z-layer at a time: the qualified voxels within the splat's reach of the layer (a
 * contiguous range of a vertex buffer sorted by z) are drawn as GL_POINTS of the
 * splat's size, and each covered pixel adds weight(d) h_n(d) with additive blending.
 * The splat texture holds, per offset d from the splat's centre, the unit vector
 * e = d/|d| and the weight (1/|d|^2)/S (S: the sum over the splat), as the paper's
 * Fig. 4. The view-dependent factor of h_n is computed in the fragment shader, so a
 * new view only redraws. Every GL call goes through the runtime's function table.
 *
 * On OpenGL ES 3.x (WebGL 2) the shaders are GLSL ES 3.00, point sizes always come from
 * the shader, and the buffer is R32F where the context can render into it, blend it and
 * filter it (GL_EXT_color_buffer_float before 3.2, GL_EXT_float_blend,
 * GL_OES_texture_float_linear), else R16F (renderable, blendable and filterable there),
 * with a note; it is read back as RGBA floats, the format ES must read. */
#include "diag.h"
#include "gl/glfuncs.h"
#include "gl/runtime.h"
#include "halo_feature.h"
#include "emu/feature_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

struct halo_feature_buffer {
    halo_gl *gl;
    const halo_glfuncs *f;
    halo_diagnostics *diag;
    halo_feature_desc desc; /* effective */
    int dims[3];            /* buffer texels */
    int radius;
    size_t qualified, points_drawn;
    size_t *layer_first; /* dims[2] + 1 offsets into the vertex buffer, by source z */
    GLuint texture, splat_texture, framebuffer, program, vertex_array, vertex_buffer;
    GLint u_layer, u_view, u_k_hpe, u_k_hse, u_radius, u_buffer_size, u_splat_size, u_splat, u_weighted;
    int es;               /* halo_gl_es_version: 0 desktop, 30..32 OpenGL ES */
    GLenum buffer_format; /* GL_R32F, or GL_R16F on an ES context that cannot take R32F */
};

/* What the shaders below start with: their #version line (and, on ES, precisions). */
static const char desktop_header[] = "#version 330 core\n";
static const char es_header[] =
    "#version 300 es\n"
    "precision highp float;\n"
    "precision highp int;\n"
    "precision highp sampler3D;\n";

static const char splat_vertex_source[] =
    "// One qualified voxel: a point of the splat's size centred on its texel.\n"
    "layout(location = 0) in vec3 source; // the voxel's buffer texel (integers)\n"
    "layout(location = 1) in vec3 normal; // its outward gradient -grad f (unnormalized)\n"
    "uniform vec3 buffer_size;\n"
    "uniform float splat_size;\n"
    "flat out vec3 splat_source;\n"
    "flat out vec3 splat_normal;\n"
    "void main()\n"
    "{\n"
    "    splat_source = source;\n"
    "    splat_normal = normal;\n"
    "    gl_Position = vec4((source.xy + 0.5) / buffer_size.xy * 2.0 - 1.0, 0.0, 1.0);\n"
    "    gl_PointSize = splat_size;\n"
    "}\n";

static const char splat_fragment_source[] =
    "// Adds weight(d) h_n to the texel at offset d from the splatting voxel, with\n"
    "// h_n = max(0, n.e)^k_hpe (1 - |n.V|)^k_hse (Ebert & Rheingans 2000, Sec. 5.2, with the\n"
    "// |n.V| of Svakhine & Ebert 2003, Eq. 2). Neighbours facing away add nothing.\n"
    "uniform highp sampler3D splat; // (e, weight) per offset + radius\n"
    "uniform int layer;\n"
    "uniform int radius;\n"
    "uniform vec3 view;             // unit, sample -> eye, voxel space\n"
    "uniform float k_hpe;\n"
    "uniform float k_hse;\n"
    "uniform bool gradient_weighted; // IVIS Eq. 2: h_n times |grad f|^k_hpe\n"
    "flat in vec3 splat_source;\n"
    "flat in vec3 splat_normal;\n"
    "layout(location = 0) out vec4 influence;\n"
    "float guarded_pow(float x, float e)\n"
    "{\n"
    "    if (x <= 0.0)\n"
    "        return e == 0.0 ? 1.0 : 0.0;\n"
    "    return pow(x, e);\n"
    "}\n"
    "void main()\n"
    "{\n"
    "    ivec3 offset = ivec3(ivec2(gl_FragCoord.xy) - ivec2(splat_source.xy), layer - int(splat_source.z));\n"
    "    if (any(greaterThan(abs(offset), ivec3(radius))))\n"
    "        discard;\n"
    "    vec4 texel = texelFetch(splat, offset + ivec3(radius), 0);\n"
    "    float magnitude = length(splat_normal);\n"
    "    vec3 normal = splat_normal / magnitude; // > 1e-10: only such voxels are drawn\n"
    "    float facing = dot(normal, texel.xyz);\n"
    "    if (!(facing > 0.0))\n"
    "        discard;\n"
    "    // 1 - |n.V| as |n x V|^2 / (1 + |n.V|): equal for unit vectors, without the\n"
    "    // cancellation of 1 - |n.V| where n is nearly along V (k_hse < 1 amplifies it)\n"
    "    vec3 across = cross(normal, view);\n"
    "    float in_plane = dot(across, across) / (1.0 + abs(dot(normal, view)));\n"
    "    float h = guarded_pow(min(facing, 1.0), k_hpe) * guarded_pow(min(in_plane, 1.0), k_hse);\n"
    "    if (gradient_weighted)\n"
    "        h *= guarded_pow(magnitude, k_hpe);\n"
    "    influence = vec4(texel.w * h, 0.0, 0.0, 0.0);\n"
    "}\n";

static GLuint compile(halo_feature_buffer *b, GLenum kind, const char *source, const char *name)
{
    const halo_glfuncs *f = b->f;
    GLuint shader = f->CreateShader(kind);
    const char *texts[2] = {b->es ? es_header : desktop_header, source};
    f->ShaderSource(shader, 2, texts, NULL);
    f->CompileShader(shader);
    GLint ok = 0;
    f->GetShaderiv(shader, GL_COMPILE_STATUS, &ok);
    if (!ok) {
        char log[1024] = "";
        f->GetShaderInfoLog(shader, sizeof log, NULL, log);
        halo_diag_error(b->diag, GL_COMPILE, name, 0, 0, "feature halo splat shader: %s", log);
        f->DeleteShader(shader);
        return 0;
    }
    return shader;
}

static int build_program(halo_feature_buffer *b)
{
    const halo_glfuncs *f = b->f;
    GLuint vs = compile(b, GL_VERTEX_SHADER, splat_vertex_source, "feature_splat.vert");
    GLuint fs = vs ? compile(b, GL_FRAGMENT_SHADER, splat_fragment_source, "feature_splat.frag") : 0;
    if (!fs) {
        if (vs)
            f->DeleteShader(vs);
        return 0;
    }
    b->program = f->CreateProgram();
    f->AttachShader(b->program, vs);
    f->AttachShader(b->program, fs);
    f->LinkProgram(b->program);
    f->DeleteShader(vs);
    f->DeleteShader(fs);
    GLint ok = 0;
    f->GetProgramiv(b->program, GL_LINK_STATUS, &ok);
    if (!ok) {
        char log[1024] = "";
        f->GetProgramInfoLog(b->program, sizeof log, NULL, log);
        halo_diag_error(b->diag, GL_LINK, "feature_splat", 0, 0, "feature halo splat program: %s", log);
        return 0;
    }
    b->u_layer = f->GetUniformLocation(b->program, "layer");
    b->u_view = f->GetUniformLocation(b->program, "view");
    b->u_k_hpe = f->GetUniformLocation(b->program, "k_hpe");
    b->u_k_hse = f->GetUniformLocation(b->program, "k_hse");
    b->u_radius = f->GetUniformLocation(b->program, "radius");
    b->u_buffer_size = f->GetUniformLocation(b->program, "buffer_size");
    b->u_splat_size = f->GetUniformLocation(b->program, "splat_size");
    b->u_splat = f->GetUniformLocation(b->program, "splat");
    b->u_weighted = f->GetUniformLocation(b->program, "gradient_weighted");
    return 1;
}

/* The splat texture: per offset d (|d_k| <= radius), (d/|d|, (1/|d|^2)/S); the centre
 * holds 0 (a voxel is not its own neighbour). */
static int build_splat_texture(halo_feature_buffer *b)
{
    const halo_glfuncs *f = b->f;
    int n = 2 * b->radius + 1;
    float *texels = malloc((size_t)n * (size_t)n * (size_t)n * 4 * sizeof *texels);
    if (!texels)
        return 0;
    double sum = halo_feature_weight_sum(n);
    size_t i = 0;
    for (int z = -b->radius; z <= b->radius; ++z)
        for (int y = -b->radius; y <= b->radius; ++y)
            for (int x = -b->radius; x <= b->radius; ++x, i += 4) {
                double d2 = (double)(x * x + y * y + z * z);
                if (d2 == 0.0) {
                    texels[i] = texels[i + 1] = texels[i + 2] = texels[i + 3] = 0.0f;
                    continue;
                }
                double length = sqrt(d2);
                texels[i] = (float)(x / length);
                texels[i + 1] = (float)(y / length);
                texels[i + 2] = (float)(z / length);
                texels[i + 3] = (float)(1.0 / (d2 * sum));
            }
    f->GenTextures(1, &b->splat_texture);
    f->BindTexture(GL_TEXTURE_3D, b->splat_texture);
    f->TexParameteri(GL_TEXTURE_3D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    f->TexParameteri(GL_TEXTURE_3D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    f->PixelStorei(GL_UNPACK_ALIGNMENT, 4);
    f->TexImage3D(GL_TEXTURE_3D, 0, GL_RGBA32F, n, n, n, 0, GL_RGBA, GL_FLOAT, texels);
    f->BindTexture(GL_TEXTURE_3D, 0);
    free(texels);
    return 1;
}

/* The qualified voxels, z-major (so sorted by z), as (texel, normal) vertices. */
static int build_vertices(halo_feature_buffer *b, const float *values, const int volume_dims[3])
{
    const halo_glfuncs *f = b->f;
    size_t count = (size_t)b->dims[0] * (size_t)b->dims[1] * (size_t)b->dims[2];
    double *gradients = malloc(count * 3 * sizeof *gradients);
    b->layer_first = calloc((size_t)b->dims[2] + 1, sizeof *b->layer_first);
    if (!gradients || !b->layer_first) {
        free(gradients);
        return 0;
    }
    halo_feature_buffer_gradients(values, volume_dims, &b->desc, gradients);
    double cutoff = b->desc.threshold < 0.0 ? 1e-10 : b->desc.threshold;
    size_t qualified = 0;
    for (size_t i = 0; i < count; ++i) {
        const double *g = &gradients[i * 3];
        double m = sqrt(g[0] * g[0] + g[1] * g[1] + g[2] * g[2]);
        qualified += m > cutoff && m > 1e-10;
    }
    float *vertices = malloc((qualified ? qualified : 1) * 6 * sizeof *vertices);
    if (!vertices) {
        free(gradients);
        return 0;
    }
    size_t v = 0, i = 0;
    for (int z = 0; z < b->dims[2]; ++z) {
        b->layer_first[z] = v;
        for (int y = 0; y < b->dims[1]; ++y)
            for (int x = 0; x < b->dims[0]; ++x, ++i) {
                const double *g = &gradients[i * 3];
                double m = sqrt(g[0] * g[0] + g[1] * g[1] + g[2] * g[2]);
                if (!(m > cutoff && m > 1e-10))
                    continue;
                float *out = &vertices[v++ * 6];
                out[0] = (float)x, out[1] = (float)y, out[2] = (float)z;
                out[3] = (float)-g[0], out[4] = (float)-g[1], out[5] = (float)-g[2];
            }
    }
    b->layer_first[b->dims[2]] = v;
    b->qualified = qualified;
    free(gradients);
    f->GenVertexArrays(1, &b->vertex_array);
    f->GenBuffers(1, &b->vertex_buffer);
    f->BindVertexArray(b->vertex_array);
    f->BindBuffer(GL_ARRAY_BUFFER, b->vertex_buffer);
    f->BufferData(GL_ARRAY_BUFFER, (GLsizeiptr)((qualified ? qualified : 1) * 6 * sizeof *vertices), vertices,
                  GL_STATIC_DRAW);
    f->EnableVertexAttribArray(0);
    f->VertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 6 * sizeof(float), (const void *)0);
    f->EnableVertexAttribArray(1);
    f->VertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, 6 * sizeof(float), (const void *)(3 * sizeof(float)));
    f->BindVertexArray(0);
    f->BindBuffer(GL_ARRAY_BUFFER, 0);
    free(vertices);
    return 1;
}

/* The buffer's format, and on ES whether the context can draw the splats at all (points
 * of the splat's size; a float format it renders into, blends and filters). 0 after a
 * diagnostic. */
static int choose_format(halo_feature_buffer *b)
{
    const halo_glfuncs *f = b->f;
    b->buffer_format = GL_R32F;
    if (!b->es)
        return 1;
    GLfloat sizes[2] = {0, 0};
    if (f->GetFloatv)
        f->GetFloatv(0x846D /* GL_ALIASED_POINT_SIZE_RANGE */, sizes);
    int splat = 2 * b->radius + 1;
    if (sizes[1] < (GLfloat)splat) {
        halo_diag_error(b->diag, ENGINE_UNSUPPORTED, "", 0, 0,
                        "feature halos: this OpenGL ES context draws points of at most %g pixels, the halo buffer's "
                        "splats are %d (feature_halo.splat_size %d%s): a smaller splat_size, or half_resolution",
                        (double)sizes[1], splat, b->desc.splat_size,
                        b->desc.half_resolution ? ", half resolution" : "");
        return 0;
    }
    int renders_float = b->es >= 32 || halo_gl_has_extension(b->gl, "GL_EXT_color_buffer_float");
    if (renders_float && halo_gl_has_extension(b->gl, "GL_EXT_float_blend") &&
        halo_gl_has_extension(b->gl, "GL_OES_texture_float_linear"))
        return 1;
    if (renders_float || halo_gl_has_extension(b->gl, "GL_EXT_color_buffer_half_float")) {
        b->buffer_format = GL_R16F;
        halo_diagnostics_report(b->diag, HALO_SEVERITY_NOTE, HALO_MSG_ENGINE_UNSUPPORTED, "", 0, 0, NULL,
                                "feature halos: the halo buffer is R16F (half floats): this OpenGL ES context cannot "
                                "render, blend and filter R32F (GL_EXT_color_buffer_float, GL_EXT_float_blend, "
                                "GL_OES_texture_float_linear)");
        return 1;
    }
    halo_diag_error(b->diag, ENGINE_UNSUPPORTED, "", 0, 0,
                    "feature halos: the halo buffer is drawn into a float texture, which this OpenGL ES context "
                    "cannot render into (GL_EXT_color_buffer_float or GL_EXT_color_buffer_half_float)");
    return 0;
}

halo_feature_buffer *halo_feature_buffer_create(halo_gl *gl, const float *values, const int dims[3],
                                                const halo_feature_desc *desc, halo_diagnostics *diag)
{
    HALO_REFUSE_NULL(diag, gl, "gl", NULL);
    HALO_REFUSE_NULL(diag, values, "values", NULL);
    HALO_REFUSE_NULL(diag, dims, "dims", NULL);
    if (dims[0] < 1 || dims[1] < 1 || dims[2] < 1 || dims[0] > 8192 || dims[1] > 8192 || dims[2] > 8192) {
        halo_diag_error(diag, USAGE, "", 0, 0, "halo_feature_buffer_create: dims in 1..8192 are required");
        return NULL;
    }
    halo_feature_buffer *b = halo_diag_calloc(diag, sizeof *b, "a feature buffer");
    if (!b)
        return NULL;
    b->gl = gl;
    b->f = halo_gl_functions(gl);
    b->diag = diag;
    halo_feature_layout layout = halo_feature_desc_layout(desc, dims);
    b->desc = layout.desc;
    memcpy(b->dims, layout.buffer_dims, sizeof b->dims);
    b->radius = halo_feature_splat_radius(&b->desc);
    b->es = halo_gl_es_version(gl);
    const halo_glfuncs *f = b->f;
    if (!f->FramebufferTextureLayer) {
        halo_diag_error(diag, GL_PROC_MISSING, "", 0, 0, "glFramebufferTextureLayer is missing");
        free(b);
        return NULL;
    }
    if (!choose_format(b)) {
        free(b);
        return NULL;
    }
    GLint max_size = 0;
    f->GetIntegerv(GL_MAX_3D_TEXTURE_SIZE, &max_size);
    if (b->dims[0] > max_size || b->dims[1] > max_size || b->dims[2] > max_size) {
        halo_diag_error(diag, USAGE, "", 0, 0, "halo buffer %dx%dx%d exceeds GL_MAX_3D_TEXTURE_SIZE %d", b->dims[0],
                        b->dims[1], b->dims[2], max_size);
        free(b);
        return NULL;
    }
    GLint saved_texture = 0, saved_active = 0;
    f->GetIntegerv(GL_ACTIVE_TEXTURE, &saved_active);
    f->ActiveTexture(GL_TEXTURE0);
    f->GetIntegerv(GL_TEXTURE_BINDING_3D, &saved_texture);
    if (!build_program(b) || !build_splat_texture(b) || !build_vertices(b, values, dims)) {
        if (!halo_diagnostics_describe(diag).errors)
            halo_diag_error(diag, OUT_OF_MEMORY, "", 0, 0, "out of memory");
        f->BindTexture(GL_TEXTURE_3D, (GLuint)saved_texture);
        f->ActiveTexture((GLenum)saved_active);
        halo_feature_buffer_destroy(b);
        return NULL;
    }
    f->GenTextures(1, &b->texture);
    f->BindTexture(GL_TEXTURE_3D, b->texture);
    f->TexParameteri(GL_TEXTURE_3D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    f->TexParameteri(GL_TEXTURE_3D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    f->TexParameteri(GL_TEXTURE_3D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    f->TexParameteri(GL_TEXTURE_3D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    f->TexParameteri(GL_TEXTURE_3D, GL_TEXTURE_WRAP_R, GL_CLAMP_TO_EDGE);
    f->TexImage3D(GL_TEXTURE_3D, 0, (GLint)b->buffer_format, b->dims[0], b->dims[1], b->dims[2], 0, GL_RED, GL_FLOAT,
                  NULL);
    f->BindTexture(GL_TEXTURE_3D, (GLuint)saved_texture);
    f->ActiveTexture((GLenum)saved_active);
    f->GenFramebuffers(1, &b->framebuffer);
    GLenum error = f->GetError();
    if (error != GL_NO_ERROR) {
        halo_diag_error(diag, GL_LINK, "", 0, 0, "OpenGL error 0x%x while creating the halo buffer", error);
        halo_feature_buffer_destroy(b);
        return NULL;
    }
    return b;
}

void halo_feature_buffer_destroy(halo_feature_buffer *b)
{
    if (!b)
        return;
    const halo_glfuncs *f = b->f;
    if (f) { /* glDelete* passes over the names never made (0) */
        const GLuint textures[2] = {b->texture, b->splat_texture};
        f->DeleteTextures(2, textures);
        f->DeleteFramebuffers(1, &b->framebuffer);
        f->DeleteProgram(b->program);
        f->DeleteVertexArrays(1, &b->vertex_array);
        f->DeleteBuffers(1, &b->vertex_buffer);
    }
    free(b->layer_first);
    free(b);
}

/* The host's state around the build (halo_gl_state, made neutral) and what the build sets
 * beyond it: unit 0's 3D texture and point sizes from the shader. */
typedef struct saved_state {
    halo_gl_state state;
    GLint texture_3d;
    GLboolean point_size;
} saved_state;

static void save_state(const halo_glfuncs *f, int es, saved_state *s)
{
    halo_gl_state_save(f, &s->state);
    halo_gl_state_neutral(f, &s->state);
    f->ActiveTexture(GL_TEXTURE0);
    f->GetIntegerv(GL_TEXTURE_BINDING_3D, &s->texture_3d);
    /* ES has no such switch: its point sizes always come from the shader */
    s->point_size = !es && f->IsEnabled && f->IsEnabled(GL_PROGRAM_POINT_SIZE);
}

static void restore_state(const halo_glfuncs *f, int es, const saved_state *s)
{
    f->BindTexture(GL_TEXTURE_3D, (GLuint)s->texture_3d); /* on unit 0, before the saved unit is restored */
    if (!es)
        (s->point_size ? f->Enable : f->Disable)(GL_PROGRAM_POINT_SIZE);
    halo_gl_state_restore(f, &s->state);
}

halo_status halo_feature_buffer_build(halo_feature_buffer *b, const double view[3])
{
    HALO_REFUSE_NULL(NULL, b, "buffer", HALO_ERROR_INPUT);
    HALO_REFUSE_NULL(b->diag, view, "view", HALO_ERROR_INPUT);
    double length = sqrt(view[0] * view[0] + view[1] * view[1] + view[2] * view[2]);
    if (!(length > 1e-10) || !isfinite(length)) {
        halo_diag_error(b->diag, USAGE, "", 0, 0, "halo_feature_buffer_build: the view vector has no direction");
        return HALO_ERROR_INPUT;
    }
    const halo_glfuncs *f = b->f;
    saved_state saved;
    save_state(f, b->es, &saved);
    f->BindFramebuffer(GL_FRAMEBUFFER, b->framebuffer);
    f->Viewport(0, 0, b->dims[0], b->dims[1]);
    if (!b->es)
        f->Enable(GL_PROGRAM_POINT_SIZE);
    f->Enable(GL_BLEND);
    f->BlendEquation(GL_FUNC_ADD);
    f->BlendFunc(GL_ONE, GL_ONE);
    f->UseProgram(b->program);
    f->BindTexture(GL_TEXTURE_3D, b->splat_texture);
    f->Uniform1i(b->u_splat, 0);
    f->Uniform3f(b->u_view, (float)(view[0] / length), (float)(view[1] / length), (float)(view[2] / length));
    f->Uniform1f(b->u_k_hpe, (float)b->desc.k_hpe);
    f->Uniform1f(b->u_k_hse, (float)b->desc.k_hse);
    f->Uniform1i(b->u_weighted, b->desc.gradient_weighted);
    f->Uniform1i(b->u_radius, b->radius);
    f->Uniform3f(b->u_buffer_size, (float)b->dims[0], (float)b->dims[1], (float)b->dims[2]);
    f->Uniform1f(b->u_splat_size, (float)(2 * b->radius + 1));
    f->BindVertexArray(b->vertex_array);
    static const GLfloat zero[4] = {0, 0, 0, 0};
    static const GLenum draw_buffer = GL_COLOR_ATTACHMENT0;
    f->DrawBuffers(1, &draw_buffer);
    b->points_drawn = 0;
    halo_status status = HALO_OK;
    for (int z = 0; z < b->dims[2]; ++z) {
        f->FramebufferTextureLayer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, b->texture, 0, z);
        if (z == 0 && f->CheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
            halo_diag_error(b->diag, GL_LINK, "", 0, 0, "the halo buffer's layer framebuffer is incomplete");
            status = HALO_ERROR_IO;
            break;
        }
        f->ClearBufferfv(GL_COLOR, 0, zero);
        int lo = z - b->radius < 0 ? 0 : z - b->radius;
        int hi = z + b->radius >= b->dims[2] ? b->dims[2] - 1 : z + b->radius;
        size_t first = b->layer_first[lo], count = b->layer_first[hi + 1] - first;
        if (!count)
            continue;
        f->Uniform1i(b->u_layer, z);
        f->DrawArrays(GL_POINTS, (GLint)first, (GLsizei)count);
        b->points_drawn += count;
    }
    f->FramebufferTextureLayer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, 0, 0, 0);
    restore_state(f, b->es, &saved);
    GLenum error = f->GetError();
    if (status == HALO_OK && error != GL_NO_ERROR) {
        halo_diag_error(b->diag, GL_LINK, "", 0, 0, "OpenGL error 0x%x while splatting the halo buffer", error);
        status = HALO_ERROR_IO;
    }
    return status;
}

halo_feature_buffer_info halo_feature_buffer_describe(const halo_feature_buffer *b)
{
    halo_feature_buffer_info info = {0};
    HALO_REFUSE_NULL(NULL, b, "buffer", info);
    info.texture = b->texture;
    for (int k = 0; k < 3; ++k)
        info.dims[k] = b->dims[k];
    info.qualified = b->qualified;
    info.points_drawn = b->points_drawn;
    return info;
}

halo_status halo_feature_buffer_read(halo_feature_buffer *b, float *out)
{
    HALO_REFUSE_NULL(NULL, b, "buffer", HALO_ERROR_INPUT);
    HALO_REFUSE_NULL(b->diag, out, "out", HALO_ERROR_INPUT);
    const halo_glfuncs *f = b->f;
    halo_gl_bindings saved; /* the framebuffers, and tight packing without a pack buffer */
    halo_gl_bindings_save(f, &saved);
    halo_gl_bindings_neutral(f, &saved);
    f->BindFramebuffer(GL_FRAMEBUFFER, b->framebuffer);
    f->ReadBuffer(GL_COLOR_ATTACHMENT0);
    size_t layer = (size_t)b->dims[0] * (size_t)b->dims[1];
    /* ES reads floats as RGBA only: a layer at a time, its red kept */
    float *rgba = b->es ? malloc(layer * 4 * sizeof *rgba) : NULL;
    if (b->es && !rgba) {
        halo_gl_bindings_restore(f, &saved);
        halo_diag_error(b->diag, OUT_OF_MEMORY, "", 0, 0, "out of memory reading the halo buffer");
        return HALO_ERROR_IO;
    }
    for (int z = 0; z < b->dims[2]; ++z) {
        f->FramebufferTextureLayer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, b->texture, 0, z);
        float *to = out + layer * (size_t)z;
        if (!rgba) {
            f->ReadPixels(0, 0, b->dims[0], b->dims[1], GL_RED, GL_FLOAT, to);
            continue;
        }
        f->ReadPixels(0, 0, b->dims[0], b->dims[1], GL_RGBA, GL_FLOAT, rgba);
        for (size_t i = 0; i < layer; ++i)
            to[i] = rgba[i * 4];
    }
    free(rgba);
    f->FramebufferTextureLayer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, 0, 0, 0);
    halo_gl_bindings_restore(f, &saved);
    GLenum error = f->GetError();
    if (error != GL_NO_ERROR) {
        halo_diag_error(b->diag, GL_LINK, "", 0, 0, "OpenGL error 0x%x while reading the halo buffer", error);
        return HALO_ERROR_IO;
    }
    return HALO_OK;
}
