/* The GL runtime: builds linked programs in the host's context and uploads live
 * parameters. Every GL call goes through the halo_glfuncs table loaded from the host's
 * get-proc-address callback; libhalo never links against libGL. */
#include "halo.h"
#include "internal.h"
#include "diag.h"
#include "gl/glfuncs.h"
#include "gl/runtime.h"

#include <ctype.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

const halo_glfuncs *halo_gl_functions(const halo_gl *gl) { return gl ? &gl->f : NULL; }

static const GLenum pack_names[10] = {
    GL_PACK_ALIGNMENT,    GL_PACK_ROW_LENGTH,     GL_PACK_SKIP_ROWS,   GL_PACK_SKIP_PIXELS,   GL_UNPACK_ALIGNMENT,
    GL_UNPACK_ROW_LENGTH, GL_UNPACK_IMAGE_HEIGHT, GL_UNPACK_SKIP_ROWS, GL_UNPACK_SKIP_PIXELS, GL_UNPACK_SKIP_IMAGES};
static const GLint tight[10] = {4, 0, 0, 0, 4, 0, 0, 0, 0, 0};
/* The switches libhalo's draws need off (GL_FRAMEBUFFER_SRGB last: desktop GL only). */
static const GLenum halo_gl_switches[5] = {GL_CULL_FACE, GL_DEPTH_TEST, GL_STENCIL_TEST, GL_RASTERIZER_DISCARD,
                                           GL_FRAMEBUFFER_SRGB};

void halo_gl_bindings_save(const halo_glfuncs *f, halo_gl_bindings *b)
{
    f->GetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &b->draw_framebuffer);
    f->GetIntegerv(GL_READ_FRAMEBUFFER_BINDING, &b->read_framebuffer);
    f->GetIntegerv(GL_VIEWPORT, b->viewport);
    f->GetIntegerv(GL_CURRENT_PROGRAM, &b->program);
    f->GetIntegerv(GL_VERTEX_ARRAY_BINDING, &b->vertex_array);
    f->GetIntegerv(GL_ACTIVE_TEXTURE, &b->active_texture);
    int desktop = f->PolygonMode != NULL; /* NULL on OpenGL ES (halo_gl_create) */
    for (int i = 0; i < 5; ++i)
        b->switched_on[i] = f->IsEnabled && (desktop || i < 4) && f->IsEnabled(halo_gl_switches[i]);
    GLint modes[2] = {0, 0};
    if (desktop)
        f->GetIntegerv(GL_POLYGON_MODE, modes);
    b->polygon_mode = modes[0];
    for (int i = 0; i < 10; ++i)
        f->GetIntegerv(pack_names[i], &b->pack[i]);
    f->GetIntegerv(GL_PIXEL_PACK_BUFFER_BINDING, &b->pack_buffer);
    f->GetIntegerv(GL_PIXEL_UNPACK_BUFFER_BINDING, &b->unpack_buffer);
}

void halo_gl_bindings_neutral(const halo_glfuncs *f, const halo_gl_bindings *b)
{
    for (int i = 0; i < 5; ++i)
        if (b->switched_on[i])
            f->Disable(halo_gl_switches[i]);
    if (b->polygon_mode && b->polygon_mode != GL_FILL)
        f->PolygonMode(GL_FRONT_AND_BACK, GL_FILL);
    for (int i = 0; i < 10; ++i)
        if (b->pack[i] != tight[i])
            f->PixelStorei(pack_names[i], tight[i]);
    if (b->pack_buffer)
        f->BindBuffer(GL_PIXEL_PACK_BUFFER, 0);
    if (b->unpack_buffer)
        f->BindBuffer(GL_PIXEL_UNPACK_BUFFER, 0);
}

void halo_gl_use_saved_program(const halo_glfuncs *f, GLint program)
{
    f->UseProgram(program && f->IsProgram((GLuint)program) ? (GLuint)program : 0);
}

void halo_gl_bindings_restore(const halo_glfuncs *f, const halo_gl_bindings *b)
{
    f->BindFramebuffer(GL_DRAW_FRAMEBUFFER, (GLuint)b->draw_framebuffer);
    f->BindFramebuffer(GL_READ_FRAMEBUFFER, (GLuint)b->read_framebuffer);
    f->Viewport(b->viewport[0], b->viewport[1], b->viewport[2], b->viewport[3]);
    halo_gl_use_saved_program(f, b->program);
    f->BindVertexArray((GLuint)b->vertex_array);
    f->ActiveTexture((GLenum)b->active_texture);
    int desktop = f->PolygonMode != NULL;
    for (int i = 0; i < 5; ++i)
        if (desktop || i < 4)
            (b->switched_on[i] ? f->Enable : f->Disable)(halo_gl_switches[i]);
    if (b->polygon_mode)
        f->PolygonMode(GL_FRONT_AND_BACK, (GLenum)b->polygon_mode);
    for (int i = 0; i < 10; ++i)
        f->PixelStorei(pack_names[i], b->pack[i]);
    f->BindBuffer(GL_PIXEL_PACK_BUFFER, (GLuint)b->pack_buffer);
    f->BindBuffer(GL_PIXEL_UNPACK_BUFFER, (GLuint)b->unpack_buffer);
}

static const GLenum blend_queries[6] = {GL_BLEND_EQUATION_RGB, GL_BLEND_EQUATION_ALPHA, GL_BLEND_SRC_RGB,
                                        GL_BLEND_DST_RGB,      GL_BLEND_SRC_ALPHA,      GL_BLEND_DST_ALPHA};

static int state_indexed(const halo_glfuncs *f)
{
    return f->IsEnabledi && f->Enablei && f->Disablei && f->GetIntegeri_v && f->GetBooleani_v &&
           f->BlendEquationSeparatei && f->BlendFuncSeparatei && f->ColorMaski;
}

void halo_gl_state_save(const halo_glfuncs *f, halo_gl_state *s)
{
    memset(s, 0, sizeof *s);
    halo_gl_bindings_save(f, &s->bindings);
    s->scissor = f->IsEnabled && f->IsEnabled(GL_SCISSOR_TEST);
    f->GetIntegerv(GL_SCISSOR_BOX, s->scissor_box);
    int indexed = state_indexed(f);
    GLint buffers = 1;
    if (indexed)
        f->GetIntegerv(GL_MAX_DRAW_BUFFERS, &buffers);
    s->buffer_count = buffers < 1 ? 1 : buffers > HALO_GL_STATE_BUFFERS ? HALO_GL_STATE_BUFFERS : buffers;
    for (int i = 0; i < s->buffer_count; ++i) {
        halo_gl_buffer_state *b = &s->buffers[i];
        GLint *values[6] = {&b->equation[0], &b->equation[1], &b->function[0],
                            &b->function[1], &b->function[2], &b->function[3]};
        if (indexed) {
            b->blend = f->IsEnabledi(GL_BLEND, (GLuint)i);
            for (int q = 0; q < 6; ++q)
                f->GetIntegeri_v(blend_queries[q], (GLuint)i, values[q]);
            f->GetBooleani_v(GL_COLOR_WRITEMASK, (GLuint)i, b->mask);
        } else {
            b->blend = f->IsEnabled && f->IsEnabled(GL_BLEND);
            for (int q = 0; q < 6; ++q)
                f->GetIntegerv(blend_queries[q], values[q]);
            b->mask[0] = b->mask[1] = b->mask[2] = b->mask[3] = GL_TRUE;
            if (f->GetBooleanv)
                f->GetBooleanv(GL_COLOR_WRITEMASK, b->mask);
        }
    }
}

void halo_gl_state_neutral(const halo_glfuncs *f, const halo_gl_state *s)
{
    halo_gl_bindings_neutral(f, &s->bindings);
    if (s->scissor)
        f->Disable(GL_SCISSOR_TEST);
    f->Disable(GL_BLEND); /* every draw buffer */
    f->ColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
}

void halo_gl_state_restore(const halo_glfuncs *f, const halo_gl_state *s)
{
    halo_gl_bindings_restore(f, &s->bindings);
    f->Scissor(s->scissor_box[0], s->scissor_box[1], s->scissor_box[2], s->scissor_box[3]);
    (s->scissor ? f->Enable : f->Disable)(GL_SCISSOR_TEST);
    int indexed = state_indexed(f);
    for (int i = 0; i < s->buffer_count; ++i) {
        const halo_gl_buffer_state *b = &s->buffers[i];
        if (indexed) {
            (b->blend ? f->Enablei : f->Disablei)(GL_BLEND, (GLuint)i);
            f->BlendEquationSeparatei((GLuint)i, (GLenum)b->equation[0], (GLenum)b->equation[1]);
            f->BlendFuncSeparatei((GLuint)i, (GLenum)b->function[0], (GLenum)b->function[1], (GLenum)b->function[2],
                                  (GLenum)b->function[3]);
            f->ColorMaski((GLuint)i, b->mask[0], b->mask[1], b->mask[2], b->mask[3]);
        } else {
            (b->blend ? f->Enable : f->Disable)(GL_BLEND);
            f->BlendEquationSeparate((GLenum)b->equation[0], (GLenum)b->equation[1]);
            f->BlendFuncSeparate((GLenum)b->function[0], (GLenum)b->function[1], (GLenum)b->function[2],
                                 (GLenum)b->function[3]);
            f->ColorMask(b->mask[0], b->mask[1], b->mask[2], b->mask[3]);
        }
    }
}

/* The context's kind, and its entry points made to say what it has: a loader such as
 * Mesa's returns a stub for every name it knows, so the per-draw-buffer blending of OpenGL
 * 4.0 and ES 3.2 (and the indexed queries of its state), glGetTexLevelParameteriv (ES
 * 3.1) and glBindFragDataLocation (desktop only) are set to NULL where the version lacks
 * them, and every caller tests them. 0 after a diagnostic (OpenGL ES 2). */
static int runtime_context(halo_gl *gl, halo_diagnostics *diag)
{
    halo_glfuncs *f = &gl->f;
    const char *version = (const char *)f->GetString(GL_VERSION);
    int major = 0, minor = 0;
    if (version && !strncmp(version, "OpenGL ES ", 10) && sscanf(version + 10, "%d.%d", &major, &minor) == 2) {
        if (major < 3) {
            halo_diag_error(diag, GL_PROC_MISSING, "", 0, 0,
                            "the current context is %s: libhalo needs OpenGL ES 3.0 or later (or OpenGL 3.3 core)",
                            version);
            return 0;
        }
        gl->es = major * 10 + (minor > 9 ? 9 : minor);
    } else {
        f->GetIntegerv(GL_MAJOR_VERSION, &major);
    }
    int per_buffer = gl->es ? gl->es >= 32 : major >= 4;
    if (!per_buffer) {
        f->Enablei = NULL;
        f->Disablei = NULL;
        f->IsEnabledi = NULL;
        f->BlendEquationi = NULL;
        f->BlendFunci = NULL;
        f->BlendEquationSeparatei = NULL;
        f->BlendFuncSeparatei = NULL;
        f->ColorMaski = NULL;
        f->GetIntegeri_v = NULL; /* the indexed blend state's (count_fetches needs OpenGL 4.2) */
        f->GetBooleani_v = NULL;
    }
    if (gl->es) {
        f->BindFragDataLocation = NULL;
        f->PolygonMode = NULL;
        if (gl->es < 31)
            f->GetTexLevelParameteriv = NULL;
    }
    return 1;
}

/* A software rasterizer by its GL_RENDERER (as libhalo-headless tells them apart): it
 * waits for each draw before the next reads its result anyway. */
static int renderer_is_software(const char *renderer)
{
    static const char *const software[] = {"llvmpipe", "softpipe", "swrast", "Software Rasterizer", "SwiftShader"};
    for (size_t i = 0; renderer && i < sizeof software / sizeof software[0]; ++i)
        if (strstr(renderer, software[i]))
            return 1;
    return 0;
}

static int fetch_counting_supported(const halo_gl *gl);

halo_gl *halo_gl_create(const halo_gl_desc *desc, halo_diagnostics *diag)
{
    if (!desc || !desc->get_proc_address) {
        halo_diag_error(diag, USAGE, "", 0, 0, "halo_gl_create: desc.get_proc_address is required");
        return NULL;
    }
    halo_gl *gl = halo_diag_calloc(diag, sizeof *gl, "the GL runtime");
    if (!gl)
        return NULL;
    const char *missing = NULL;
    if (!halo_glfuncs_load(&gl->f, sizeof gl->f, desc->get_proc_address, &missing)) {
        halo_diag_error(
            diag, GL_PROC_MISSING, "", 0, 0,
            "OpenGL entry point '%s' not found: an OpenGL 3.3 core or OpenGL ES 3.0 context must be current",
            missing ? missing : "?");
        free(gl);
        return NULL;
    }
    if (!runtime_context(gl, diag)) {
        free(gl);
        return NULL;
    }
    if (desc->readback != HALO_GL_READBACK_AUTO && desc->readback != HALO_GL_READBACK_ON &&
        desc->readback != HALO_GL_READBACK_OFF) {
        halo_diag_error(diag, USAGE, "", 0, 0, "halo_gl_create: desc.readback %d is not a halo_gl_readback",
                        (int)desc->readback);
        free(gl);
        return NULL;
    }
    gl->readback =
        desc->readback == HALO_GL_READBACK_ON ||
        (desc->readback == HALO_GL_READBACK_AUTO && renderer_is_software((const char *)gl->f.GetString(GL_RENDERER)));
    if (desc->count_fetches && !fetch_counting_supported(gl)) {
        halo_diag_error(diag, GL_PROC_MISSING, "", 0, 0,
                        "halo_gl_create: count_fetches needs desktop OpenGL 4.2 or later with "
                        "GL_ARB_shader_atomic_counters; this context is %s",
                        (const char *)gl->f.GetString(GL_VERSION));
        free(gl);
        return NULL;
    }
    gl->count_fetches = desc->count_fetches != 0;
    atomic_init(&gl->refs, 1);
    return gl;
}

/* ---- Counting the image passes' fetches (halo_gl_desc.count_fetches) -------- */

/* After #version: an atomic counter at binding 0, one increment a texelFetch (a
 * function-like macro: the texelFetch inside it is the built-in). */
const char halo_gl_fetch_counting[] =
    "#extension GL_ARB_shader_atomic_counters : enable\n"
    "layout(binding = 0, offset = 0) uniform atomic_uint halo_fetch_count;\n"
    "#define texelFetch(s, p, l) (atomicCounterIncrement(halo_fetch_count), texelFetch(s, p, l))\n";

static int fetch_counting_supported(const halo_gl *gl)
{
    const halo_glfuncs *f = &gl->f;
    int major = 0, minor = 0;
    const char *version = (const char *)f->GetString(GL_VERSION);
    if (gl->es || !version || sscanf(version, "%d.%d", &major, &minor) != 2 || major * 10 + minor < 42 ||
        !f->BindBufferBase || !f->BindBufferRange || !f->GetBufferSubData || !f->GetInteger64i_v || !f->GetIntegeri_v ||
        !f->MemoryBarrier)
        return 0;
    /* the passes' GLSL (330 and up) takes the counter through the extension's directive */
    return halo_gl_has_extension(gl, "GL_ARB_shader_atomic_counters");
}

void halo_gl_fetches_begin(const halo_gl *gl, GLuint counter, halo_gl_fetch_binding *saved)
{
    const halo_glfuncs *f = &gl->f;
    f->GetIntegerv(GL_ATOMIC_COUNTER_BUFFER_BINDING, &saved->buffer);
    f->GetIntegeri_v(GL_ATOMIC_COUNTER_BUFFER_BINDING, 0, &saved->indexed);
    f->GetInteger64i_v(GL_ATOMIC_COUNTER_BUFFER_START, 0, &saved->start);
    f->GetInteger64i_v(GL_ATOMIC_COUNTER_BUFFER_SIZE, 0, &saved->size);
    const GLuint zero = 0;
    f->BindBufferBase(GL_ATOMIC_COUNTER_BUFFER, 0, counter);
    f->BufferSubData(GL_ATOMIC_COUNTER_BUFFER, 0, sizeof zero, &zero);
}

long long halo_gl_fetches_end(const halo_gl *gl, GLuint counter, const halo_gl_fetch_binding *saved)
{
    const halo_glfuncs *f = &gl->f;
    GLuint count = 0;
    f->MemoryBarrier(GL_ATOMIC_COUNTER_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT); /* the shaders' increments */
    f->BindBuffer(GL_ATOMIC_COUNTER_BUFFER, counter);
    f->GetBufferSubData(GL_ATOMIC_COUNTER_BUFFER, 0, sizeof count, &count);
    if (saved->indexed && saved->size > 0)
        f->BindBufferRange(GL_ATOMIC_COUNTER_BUFFER, 0, (GLuint)saved->indexed, (GLintptr)saved->start,
                           (GLsizeiptr)saved->size);
    else
        f->BindBufferBase(GL_ATOMIC_COUNTER_BUFFER, 0, (GLuint)saved->indexed);
    f->BindBuffer(GL_ATOMIC_COUNTER_BUFFER, (GLuint)saved->buffer);
    return (long long)count;
}

int halo_gl_es_version(const halo_gl *gl) { return gl ? gl->es : 0; }

int halo_gl_read_floats(const halo_gl *gl, int x, int y, int width, int height, int channels, float *out)
{
    static const GLenum formats[4] = {GL_RED, GL_RG, GL_RGB, GL_RGBA};
    if (!gl->es || channels == 4) {
        gl->f.ReadPixels(x, y, width, height, formats[channels - 1], GL_FLOAT, out);
        return 1;
    }
    size_t pixels = (size_t)width * (size_t)height;
    float *rgba = malloc(pixels * 4 * sizeof *rgba);
    if (!rgba)
        return 0;
    gl->f.ReadPixels(x, y, width, height, GL_RGBA, GL_FLOAT, rgba);
    for (size_t i = 0; i < pixels; ++i)
        for (int c = 0; c < channels; ++c)
            out[i * (size_t)channels + (size_t)c] = rgba[i * 4 + (size_t)c];
    free(rgba);
    return 1;
}

int halo_gl_has_extension(const halo_gl *gl, const char *name)
{
    GLint count = 0;
    gl->f.GetIntegerv(GL_NUM_EXTENSIONS, &count);
    for (GLint i = 0; i < count; ++i) {
        const char *e = (const char *)gl->f.GetStringi(GL_EXTENSIONS, (GLuint)i);
        if (e && !strcmp(e, name))
            return 1;
    }
    return 0;
}

void halo_gl_destroy(halo_gl *gl)
{
    if (gl && atomic_fetch_sub(&gl->refs, 1) == 1)
        free(gl);
}

/* ---- Driver info logs ------------------------------------------------------ */

/* Copies line `line` (1-based) of text into a new string, or returns NULL. */
static char *source_line_of(const char *text, int line)
{
    if (!text || line < 1)
        return NULL;
    const char *p = text;
    for (int i = 1; i < line; ++i) {
        p = strchr(p, '\n');
        if (!p)
            return NULL;
        ++p;
    }
    size_t n = strcspn(p, "\r\n");
    char *copy = malloc(n + 1);
    if (!copy)
        return NULL;
    memcpy(copy, p, n);
    copy[n] = '\0';
    return copy;
}

/* One message of a driver's info log, with its position when the driver gave one. */
typedef struct log_message {
    int line, column; /* 0 when absent */
    halo_severity severity;
    const char *text; /* points into the (modified) log line */
} log_message;

static int starts_with_nocase(const char *s, const char *word)
{
    for (; *word; ++s, ++word)
        if (tolower((unsigned char)*s) != *word)
            return 0;
    return 1;
}

/* Skips "error: " / "warning: " (any case) at *p and sets the severity. */
static void take_severity(const char **p, log_message *m)
{
    while (**p == ' ')
        ++*p;
    static const struct {
        const char *word;
        halo_severity severity;
    } words[] = {{"error", HALO_SEVERITY_ERROR},
                 {"warning", HALO_SEVERITY_WARNING},
                 {"info", HALO_SEVERITY_NOTE},
                 {"note", HALO_SEVERITY_NOTE}};
    for (size_t i = 0; i < sizeof words / sizeof words[0]; ++i) {
        if (starts_with_nocase(*p, words[i].word)) {
            const char *q = *p + strlen(words[i].word);
            while (*q && *q != ':' && !isspace((unsigned char)*q))
                ++q; /* "error C0000" (NVIDIA) */
            if (*q == ':') {
                m->severity = words[i].severity;
                *p = q + 1;
                while (**p == ' ')
                    ++*p;
                return;
            }
        }
    }
}

/* Parses one log line. Formats: Mesa "0:12(5): error: msg", NVIDIA "0(12) : error C1008: msg",
 * glslang/ANGLE "ERROR: 0:12: msg"; anything else is kept whole without a position. */
static log_message parse_log_line(const char *s)
{
    log_message m = {0, 0, HALO_SEVERITY_ERROR, s};
    int string_index, line, column, used = 0;
    const char *p = s;
    while (*p == ' ' || *p == '\t')
        ++p;
    if (sscanf(p, "%d:%d(%d):%n", &string_index, &line, &column, &used) == 3 && used > 0) {
        m.line = line;
        m.column = column;
        p += used;
        take_severity(&p, &m);
    } else if (used = 0, sscanf(p, "%d(%d) :%n", &string_index, &line, &used) == 2 && used > 0) {
        m.line = line;
        p += used;
        take_severity(&p, &m);
    } else {
        const char *q = p;
        log_message probe = m;
        take_severity(&q, &probe);
        if (q != p && (used = 0, sscanf(q, "%d:%d:%n", &string_index, &line, &used) == 2) && used > 0) {
            m.line = line;
            m.severity = probe.severity;
            p = q + used;
            while (*p == ' ')
                ++p;
        } else {
            take_severity(&p, &m);
        }
    }
    m.text = p;
    return m;
}

/* Reports every message of an info log. Lines of the fragment shader are mapped through
 * the program's line map; others (vertex shader, link log) keep their own file. */
static void report_log_mapped(halo_diagnostics *diag, halo_message_id id, char *log, const halo_program *p,
                              const halo_line_origin *origins, int origin_count, const char *source, const char *file)
{
    int reported = 0;
    char *next = log;
    while (next && *next) {
        char *line = next;
        next = strchr(line, '\n');
        if (next)
            *next++ = '\0';
        size_t n = strlen(line);
        while (n > 0 && (line[n - 1] == '\r' || line[n - 1] == ' '))
            line[--n] = '\0';
        if (n == 0)
            continue;
        log_message m = parse_log_line(line);
        const char *origin_file = file;
        int origin_line = m.line;
        char *text_line = source_line_of(source, m.line);
        if ((p || origins) && m.line > 0) {
            const char *mapped_file = NULL;
            int mapped_line = 0;
            int mapped = 0;
            if (p) {
                mapped = halo_program_map_line(p, HALO_PIECE_WHOLE, m.line, &mapped_file, &mapped_line);
            } else if (m.line <= origin_count && origins[m.line - 1].file != halo_generated_file) {
                mapped_file = origins[m.line - 1].file;
                mapped_line = origins[m.line - 1].line;
                mapped = 1;
            }
            if (mapped && mapped_file) {
                origin_file = mapped_file;
                origin_line = mapped_line;
            } else {
                origin_file = "(linked source)";
            }
        }
        halo_diagnostics_report(diag, m.severity, id, origin_file ? origin_file : "", origin_line, m.column, text_line,
                                "%s", m.text);
        free(text_line);
        if (m.severity == HALO_SEVERITY_ERROR)
            ++reported;
    }
    if (reported == 0 && id != HALO_MSG_GL_LINK)
        halo_diagnostics_report(diag, HALO_SEVERITY_ERROR, id, file ? file : "", 0, 0, NULL,
                                "the driver rejected the shader without an error message");
}

void halo_gl_report_log(halo_diagnostics *diag, halo_message_id id, char *log, const halo_program *p,
                        const char *source, const char *file)
{
    report_log_mapped(diag, id, log, p, NULL, 0, source, file);
}

/* A shader's or program's info log (the two GL queries have the same shapes). */
static char *info_log(GLuint name, PFNGLGETSHADERIVPROC get_iv, PFNGLGETSHADERINFOLOGPROC get_log)
{
    GLint length = 0;
    get_iv(name, GL_INFO_LOG_LENGTH, &length);
    if (length < 1)
        length = 1;
    char *log = calloc((size_t)length + 1, 1);
    if (log)
        get_log(name, length, NULL, log);
    return log;
}

static char *shader_log(const halo_glfuncs *f, GLuint shader)
{
    return info_log(shader, f->GetShaderiv, f->GetShaderInfoLog);
}

char *halo_gl_program_log(const halo_glfuncs *f, GLuint program)
{
    return info_log(program, f->GetProgramiv, f->GetProgramInfoLog);
}

GLuint halo_gl_program_attach(const halo_glfuncs *f, GLuint vertex, GLuint fragment, const char *file,
                              halo_diagnostics *diag)
{
    GLuint program = vertex && fragment ? f->CreateProgram() : 0;
    if (vertex && fragment && !program)
        halo_diag_error(diag, GL_LINK, file, 0, 0, "glCreateProgram failed (GL error 0x%x)", f->GetError());
    if (!program) {
        if (vertex)
            f->DeleteShader(vertex);
        if (fragment)
            f->DeleteShader(fragment);
        return 0;
    }
    f->AttachShader(program, vertex);
    f->AttachShader(program, fragment);
    return program;
}

GLuint halo_gl_link_attached(const halo_glfuncs *f, GLuint program, GLuint vertex, GLuint fragment, const char *file,
                             const char *what, halo_diagnostics *diag)
{
    f->LinkProgram(program);
    f->DetachShader(program, vertex);
    f->DetachShader(program, fragment);
    f->DeleteShader(vertex);
    f->DeleteShader(fragment);
    GLint ok = GL_FALSE;
    f->GetProgramiv(program, GL_LINK_STATUS, &ok);
    if (ok)
        return program;
    char *log = halo_gl_program_log(f, program);
    if (!log) {
        halo_diag_error(diag, OUT_OF_MEMORY, file, 0, 0, "out of memory reading the driver's log");
    } else {
        size_t errors_before = halo_diagnostics_describe(diag).errors;
        halo_gl_report_log(diag, HALO_MSG_GL_LINK, log, NULL, NULL, file);
        if (!diag || halo_diagnostics_describe(diag).errors == errors_before)
            halo_diag_error(diag, GL_LINK, file, 0, 0, "%s", what);
    }
    free(log);
    f->DeleteProgram(program);
    return 0;
}

GLuint halo_gl_compile_mapped(const halo_glfuncs *f, GLenum type, const char *source, const halo_program *p,
                              const halo_line_origin *origins, int origin_count, const char *file,
                              halo_diagnostics *diag)
{
    GLuint shader = f->CreateShader(type);
    if (!shader) {
        halo_diag_error(diag, GL_COMPILE, file, 0, 0, "glCreateShader failed (GL error 0x%x)", f->GetError());
        return 0;
    }
    f->ShaderSource(shader, 1, &source, NULL);
    f->CompileShader(shader);
    GLint ok = GL_FALSE;
    f->GetShaderiv(shader, GL_COMPILE_STATUS, &ok);
    if (!ok) {
        char *log = shader_log(f, shader);
        if (!log)
            halo_diag_error(diag, OUT_OF_MEMORY, file, 0, 0, "out of memory reading the driver's log");
        else
            report_log_mapped(diag, HALO_MSG_GL_COMPILE, log, p, origins, origin_count, source, file);
        free(log);
        f->DeleteShader(shader);
        return 0;
    }
    return shader;
}

static GLuint compile(const halo_glfuncs *f, GLenum type, const char *source, const halo_program *p, const char *file,
                      halo_diagnostics *diag)
{
    return halo_gl_compile_mapped(f, type, source, p, NULL, 0, file, diag);
}

/* The linked source with `defines` after its #version line (the linker writes it first,
 * or none) and a #line that gives the next line its own number again (GLSL 3.30 on:
 * #line L numbers the next line L); NULL when out of memory. */
static char *source_with_defines(const char *source, const char *defines)
{
    const char *at = source + strspn(source, " \t");
    const char *end = strchr(at, '\n');
    int versioned = !strncmp(at, "#version", 8) && end;
    at = versioned ? end + 1 : source;
    size_t head = (size_t)(at - source), n = head + strlen(defines) + 32 + strlen(at);
    char *text = malloc(n);
    if (text)
        snprintf(text, n, "%.*s%s%s#line %d\n%s", (int)head, source, defines,
                 defines[strlen(defines) - 1] != '\n' ? "\n" : "", versioned ? 2 : 1, at);
    return text;
}

unsigned halo_gl_program_build(halo_gl *gl, const halo_program *p, const char *vertex_source, const char *vertex_file,
                               const char *defines, halo_diagnostics *diag)
{
    HALO_REFUSE_NULL(diag, gl, "gl", 0);
    HALO_REFUSE_NULL(diag, p, "program", 0);
    HALO_REFUSE_NULL(diag, vertex_source, "vertex_source", 0);
    const halo_glfuncs *f = &gl->f;
    if (!vertex_file)
        vertex_file = "vertex";
    const char *fragment_source = halo_program_source(p, HALO_PIECE_WHOLE);
    char *variant = fragment_source && defines && *defines ? source_with_defines(fragment_source, defines) : NULL;
    if (fragment_source && defines && *defines && !variant) {
        halo_diag_error(diag, OUT_OF_MEMORY, "", 0, 0, "out of memory building a variant of the program");
        return 0;
    }
    GLuint vertex = compile(f, GL_VERTEX_SHADER, vertex_source, NULL, vertex_file, diag);
    GLuint fragment = fragment_source ? compile(f, GL_FRAGMENT_SHADER, variant ? variant : fragment_source, p,
                                                "(linked source)", diag)
                                      : 0;
    free(variant);
    if (!fragment_source)
        halo_diag_error(diag, USAGE, "", 0, 0, "halo_gl_program_build: the program has no source");
    GLuint program = halo_gl_program_attach(f, vertex, fragment, "", diag);
    if (!program)
        return 0;
    if (p->unlocated_outputs && f->BindFragDataLocation) { /* GLSL 150: the outputs are bound by name */
        for (size_t o = 0; o < p->output_count; o++)
            f->BindFragDataLocation(program, (GLuint)p->outputs[o].location, p->outputs[o].name);
        if (p->segment_location > 0)
            f->BindFragDataLocation(program, (GLuint)p->segment_location, "halo_segment_state_out");
    }
    return halo_gl_link_attached(f, program, vertex, fragment, "", "the driver could not link the program", diag);
}

/* ---- Live parameters --------------------------------------------------------- */

void halo_gl_program_upload(halo_gl *gl, const halo_program *p, unsigned gl_program)
{
    HALO_REFUSE_NULL_VOID(NULL, gl, "gl");
    HALO_REFUSE_NULL_VOID(NULL, p, "program");
    if (!gl_program)
        return;
    const halo_glfuncs *f = &gl->f;
    size_t n = halo_program_reflection(p).uniform_count;
    for (size_t i = 0; i < n; ++i) {
        const halo_uniform_info *u = &halo_program_reflection(p).uniforms[i];
        if (!u || !u->live || !u->info || !u->name || !u->value)
            continue;
        GLint location = f->GetUniformLocation(gl_program, u->name);
        const halo_param_info *info = u->info;
        int components = info->components < 1 ? 1 : info->components > 4 ? 4 : info->components;
        int count = info->array_size > 0 ? u->count : 1;
        if (count < 0)
            count = 0;
        if (count * components > HALO_MAX_COMPONENTS)
            count = HALO_MAX_COMPONENTS / components;
        if (info->type == HALO_PARAM_CHANNELS) {
            /* one float per halo: halo_channels is float, vec2, vec3 or vec4 (docs/image-passes.md);
             * a shorter list repeats its last element */
            int channels = halo_program_reflection(p).channel_count;
            GLfloat values[4] = {0, 0, 0, 0};
            for (int k = 0; k < channels && u->count > 0; ++k)
                values[k] = (GLfloat)u->value[k < u->count ? k : u->count - 1];
            if (location >= 0) {
                switch (channels) {
                case 1:
                    f->Uniform1fv(location, 1, values);
                    break;
                case 2:
                    f->Uniform2fv(location, 1, values);
                    break;
                case 3:
                    f->Uniform3fv(location, 1, values);
                    break;
                default:
                    f->Uniform4fv(location, 1, values);
                    break;
                }
            }
            continue;
        }
        if (location >= 0 && count > 0) {
            if (info->type == HALO_PARAM_INT || info->type == HALO_PARAM_BOOL) {
                GLint values[HALO_MAX_COMPONENTS];
                for (int k = 0; k < count * components; ++k)
                    values[k] = info->type == HALO_PARAM_BOOL ? (u->value[k] != 0.0) : (GLint)u->value[k];
                f->Uniform1iv(location, count, values);
            } else {
                GLfloat values[HALO_MAX_COMPONENTS];
                for (int k = 0; k < count * components; ++k)
                    values[k] = (GLfloat)u->value[k];
                switch (components) {
                case 1:
                    f->Uniform1fv(location, count, values);
                    break;
                case 2:
                    f->Uniform2fv(location, count, values);
                    break;
                case 3:
                    f->Uniform3fv(location, count, values);
                    break;
                default:
                    f->Uniform4fv(location, count, values);
                    break;
                }
            }
        }
        if (info->array_size > 0) {
            /* `<name>_count`: the number of elements set (modules.md) */
            char count_name[256];
            int written = snprintf(count_name, sizeof count_name, "%s_count", u->name);
            if (written > 0 && (size_t)written < sizeof count_name) {
                GLint count_location = f->GetUniformLocation(gl_program, count_name);
                if (count_location >= 0)
                    f->Uniform1i(count_location, count);
            }
        }
    }
}

/* ---- Host uniforms ------------------------------------------------------------ */

/* Whether the active uniform `name` of the program is a sampler (by its GL type). */
static int uniform_is_sampler(const halo_glfuncs *f, GLuint program, const char *name)
{
    GLint active = 0;
    f->GetProgramiv(program, GL_ACTIVE_UNIFORMS, &active);
    for (GLint i = 0; i < active; ++i) {
        char found[256];
        GLsizei length = 0;
        GLint size = 0;
        GLenum type = 0;
        f->GetActiveUniform(program, (GLuint)i, sizeof found, &length, &size, &type, found);
        if (strcmp(found, name) != 0)
            continue;
        switch (type) {
        case GL_SAMPLER_1D:
        case GL_SAMPLER_2D:
        case GL_SAMPLER_3D:
        case GL_SAMPLER_CUBE:
        case GL_SAMPLER_2D_ARRAY:
        case GL_SAMPLER_2D_SHADOW:
        case GL_INT_SAMPLER_2D:
        case GL_INT_SAMPLER_3D:
        case GL_UNSIGNED_INT_SAMPLER_2D:
        case GL_UNSIGNED_INT_SAMPLER_3D:
            return 1;
        default:
            return 0;
        }
    }
    return 0;
}

halo_status halo_gl_set_host_uniform(halo_gl *gl, unsigned gl_program, const char *name, const float *values, int count)
{
    HALO_REFUSE_NULL(NULL, gl, "gl", HALO_ERROR_INPUT);
    HALO_REFUSE_NULL(NULL, name, "name", HALO_ERROR_INPUT);
    HALO_REFUSE_NULL(NULL, values, "values", HALO_ERROR_INPUT);
    if (!gl_program || count < 1 || count > 4)
        return HALO_ERROR_INPUT;
    const halo_glfuncs *f = &gl->f;
    char full[256];
    const char *lookup = name;
    if (strncmp(name, "halo_host_", 10) != 0) {
        int written = snprintf(full, sizeof full, "halo_host_%s", name);
        if (written < 0 || (size_t)written >= sizeof full)
            return HALO_ERROR_INPUT;
        lookup = full;
    }
    GLint location = f->GetUniformLocation(gl_program, lookup);
    if (location < 0)
        return HALO_ERROR_INPUT;
    if (count == 1 && uniform_is_sampler(f, gl_program, lookup)) {
        /* a sampler takes its texture unit as an int (glUniform1f on it is GL_INVALID_OPERATION) */
        if (!(values[0] >= 0.0f && values[0] < 1024.0f))
            return HALO_ERROR_INPUT;
        f->Uniform1i(location, (GLint)values[0]);
        return HALO_OK;
    }
    switch (count) {
    case 1:
        f->Uniform1fv(location, 1, values);
        break;
    case 2:
        f->Uniform2fv(location, 1, values);
        break;
    case 3:
        f->Uniform3fv(location, 1, values);
        break;
    default:
        f->Uniform4fv(location, 1, values);
        break;
    }
    return HALO_OK;
}
