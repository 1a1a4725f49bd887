/* The GL runtime: builds linked programs in the host's context and uploads live
 * parameters. Every GL call goes through the halo_glfuncs table loaded from the host's
 * get-proc-address callback; libhalo never links against libGL. */
#include "halo.h"
#include "internal.h"
#include "diag.h"
#include "gl/frame.h"
#include "gl/glfuncs.h"

#include <ctype.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

struct halo_gl {
    halo_glfuncs f;
    /* The creator's reference (halo_gl_destroy) and one per frame made with it. */
    _Atomic long refs;
};

const halo_glfuncs *halo_gl_functions(const halo_gl *gl)
{
    return gl ? &gl->f : NULL;
}

halo_gl *halo_gl_create(const halo_gl_desc *desc, halo_diagnostics *diag)
{
    if (!desc || !desc->get_proc_address) {
        halo_diag_error(diag, USAGE, "", 0, 0, "halo_gl_create: desc.get_proc_address is required");
        return NULL;
    }
    halo_gl *gl = calloc(1, sizeof *gl);
    if (!gl) {
        halo_diag_error(diag, OUT_OF_MEMORY, "", 0, 0, "out of memory creating the GL runtime");
        return NULL;
    }
    const char *missing = NULL;
    if (!halo_glfuncs_load(&gl->f, desc->get_proc_address, &missing)) {
        halo_diag_error(diag, GL_PROC_MISSING, "", 0, 0,
                        "OpenGL entry point '%s' not found: an OpenGL 3.3 core context must be current",
                        missing ? missing : "?");
        free(gl);
        return NULL;
    }
    atomic_init(&gl->refs, 1);
    return gl;
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
    int line, column;      /* 0 when absent */
    halo_severity severity;
    const char *text;      /* points into the (modified) log line */
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
    static const struct { const char *word; halo_severity severity; } words[] = {
        {"error", HALO_SEVERITY_ERROR}, {"warning", HALO_SEVERITY_WARNING}, {"info", HALO_SEVERITY_NOTE},
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
                              const halo_line_origin *origins, int origin_count, const char *source,
                              const char *file)
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
                mapped = halo_program_map_line(p, m.line, &mapped_file, &mapped_line);
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
        halo_diag_add(diag, m.severity, id, origin_file ? origin_file : "", origin_line, m.column, text_line,
                      "%s", m.text);
        free(text_line);
        if (m.severity == HALO_SEVERITY_ERROR)
            ++reported;
    }
    if (reported == 0 && id != HALO_MSG_GL_LINK)
        halo_diag_add(diag, HALO_SEVERITY_ERROR, id, file ? file : "", 0, 0, NULL,
                      "the driver rejected the shader without an error message");
}

static void report_log(halo_diagnostics *diag, halo_message_id id, char *log, const halo_program *p,
                       const char *source, const char *file)
{
    report_log_mapped(diag, id, log, p, NULL, 0, source, file);
}

static char *shader_log(const halo_glfuncs *f, GLuint shader)
{
    GLint length = 0;
    f->GetShaderiv(shader, GL_INFO_LOG_LENGTH, &length);
    if (length < 1)
        length = 1;
    char *log = calloc((size_t)length + 1, 1);
    if (log)
        f->GetShaderInfoLog(shader, length, NULL, log);
    return log;
}

static char *program_log(const halo_glfuncs *f, GLuint program)
{
    GLint length = 0;
    f->GetProgramiv(program, GL_INFO_LOG_LENGTH, &length);
    if (length < 1)
        length = 1;
    char *log = calloc((size_t)length + 1, 1);
    if (log)
        f->GetProgramInfoLog(program, length, NULL, log);
    return log;
}

/* Compiles one shader; returns its name or 0 after reporting the driver's messages.
 * Lines are mapped through p's line map, or through origins (an image pass). */
static GLuint compile_mapped(const halo_glfuncs *f, GLenum type, const char *source, const halo_program *p,
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

static GLuint compile(const halo_glfuncs *f, GLenum type, const char *source, const halo_program *p,
                      const char *file, halo_diagnostics *diag)
{
    return compile_mapped(f, type, source, p, NULL, 0, file, diag);
}

unsigned halo_gl_program_build(halo_gl *gl, const halo_program *p, const char *vertex_source,
                               const char *vertex_file, halo_diagnostics *diag)
{
    HALO_REFUSE_NULL(diag, gl, "gl", 0);
    HALO_REFUSE_NULL(diag, p, "program", 0);
    HALO_REFUSE_NULL(diag, vertex_source, "vertex_source", 0);
    const halo_glfuncs *f = &gl->f;
    if (!vertex_file)
        vertex_file = "vertex";
    const char *fragment_source = halo_program_source(p);
    GLuint vertex = compile(f, GL_VERTEX_SHADER, vertex_source, NULL, vertex_file, diag);
    GLuint fragment = fragment_source ? compile(f, GL_FRAGMENT_SHADER, fragment_source, p, "(linked source)", diag)
                                      : 0;
    if (!fragment_source)
        halo_diag_error(diag, USAGE, "", 0, 0, "halo_gl_program_build: the program has no source");
    if (!vertex || !fragment) {
        if (vertex)
            f->DeleteShader(vertex);
        if (fragment)
            f->DeleteShader(fragment);
        return 0;
    }
    GLuint program = f->CreateProgram();
    if (!program) {
        halo_diag_error(diag, GL_LINK, "", 0, 0, "glCreateProgram failed (GL error 0x%x)", f->GetError());
        f->DeleteShader(vertex);
        f->DeleteShader(fragment);
        return 0;
    }
    f->AttachShader(program, vertex);
    f->AttachShader(program, fragment);
    if (p->unlocated_outputs) { /* GLSL 150: the outputs are bound by name */
        for (size_t o = 0; o < p->output_count; o++)
            f->BindFragDataLocation(program, (GLuint)p->outputs[o].location, p->outputs[o].name);
        if (p->segment_location > 0)
            f->BindFragDataLocation(program, (GLuint)p->segment_location, "halo_segment_state_out");
    }
    f->LinkProgram(program);
    f->DetachShader(program, vertex);
    f->DetachShader(program, fragment);
    f->DeleteShader(vertex);
    f->DeleteShader(fragment);
    GLint ok = GL_FALSE;
    f->GetProgramiv(program, GL_LINK_STATUS, &ok);
    if (!ok) {
        char *log = program_log(f, program);
        if (!log) {
            halo_diag_error(diag, OUT_OF_MEMORY, "", 0, 0, "out of memory reading the driver's log");
        } else {
            size_t errors_before = halo_diagnostics_errors(diag);
            report_log(diag, HALO_MSG_GL_LINK, log, NULL, NULL, "");
            if (!diag || halo_diagnostics_errors(diag) == errors_before)
                halo_diag_error(diag, GL_LINK, "", 0, 0, "the driver could not link the program");
        }
        free(log);
        f->DeleteProgram(program);
        return 0;
    }
    return program;
}

/* ---- Live parameters --------------------------------------------------------- */

void halo_gl_program_upload(halo_gl *gl, const halo_program *p, unsigned gl_program)
{
    HALO_REFUSE_NULL_VOID(NULL, gl, "gl");
    HALO_REFUSE_NULL_VOID(NULL, p, "program");
    if (!gl_program)
        return;
    const halo_glfuncs *f = &gl->f;
    size_t n = halo_program_uniform_count(p);
    for (size_t i = 0; i < n; ++i) {
        const halo_uniform_info *u = halo_program_uniform(p, i);
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
            int channels = halo_program_channel_count(p);
            GLfloat values[4] = {0, 0, 0, 0};
            for (int k = 0; k < channels && u->count > 0; ++k)
                values[k] = (GLfloat)u->value[k < u->count ? k : u->count - 1];
            if (location >= 0) {
                switch (channels) {
                case 1: f->Uniform1fv(location, 1, values); break;
                case 2: f->Uniform2fv(location, 1, values); break;
                case 3: f->Uniform3fv(location, 1, values); break;
                default: f->Uniform4fv(location, 1, values); break;
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
                case 1: f->Uniform1fv(location, count, values); break;
                case 2: f->Uniform2fv(location, count, values); break;
                case 3: f->Uniform3fv(location, count, values); break;
                default: f->Uniform4fv(location, count, values); break;
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
        case GL_SAMPLER_1D: case GL_SAMPLER_2D: case GL_SAMPLER_3D: case GL_SAMPLER_CUBE:
        case GL_SAMPLER_2D_ARRAY: case GL_SAMPLER_2D_SHADOW: case GL_INT_SAMPLER_2D: case GL_INT_SAMPLER_3D:
        case GL_UNSIGNED_INT_SAMPLER_2D: case GL_UNSIGNED_INT_SAMPLER_3D:
            return 1;
        default:
            return 0;
        }
    }
    return 0;
}

halo_status halo_gl_set_host_uniform(halo_gl *gl, unsigned gl_program, const char *name, const float *values,
                                     int count)
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
    case 1: f->Uniform1fv(location, 1, values); break;
    case 2: f->Uniform2fv(location, 1, values); break;
    case 3: f->Uniform3fv(location, 1, values); break;
    default: f->Uniform4fv(location, 1, values); break;
    }
    return HALO_OK;
}

/* ---- Frames: images, pass programs and the schedule (docs/image-passes.md) ------- */

#define FRAME_MAX_BUFFERS 8 /* draw buffers whose blend enable is saved */

typedef struct frame_image {
    const char *name;
    int channels;
    halo_image_reset reset;
    GLfloat clear;
    int host;          /* host_color: texture[0] is the host's, set by halo_gl_frame_post */
    int width, height; /* ceil(frame / scale) */
    GLuint texture[2]; /* double-buffered: a pass reads texture[current], writes the other */
    int current;
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
    int groups_ended; /* halo_gl_frame_end_group calls since halo_gl_frame_begin */
    int attached;  /* outputs attached to attached_framebuffer by halo_gl_frame_attach */
    GLuint attached_framebuffer;
    int bound;     /* samplers bound by halo_gl_frame_bind from bound_first_unit */
    int bound_first_unit;
    GLuint state[2];   /* host contract 2: the rays' state between segments (RGBA32F), ping-ponged */
    int state_current; /* state[state_current] holds the state after the last segment drawn */
    int segments_drawn;
};

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
void halo_gl_frame_segments_reset(halo_gl_frame *fr)
{
    fr->segments_drawn = 0;
}
int halo_gl_frame_segment_count(const halo_gl_frame *fr)
{
    HALO_REFUSE_NULL(NULL, fr, "frame", 0);
    return fr->segments_drawn;
}

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

/* The GL state the frame functions change, saved and restored around them. */
typedef struct frame_saved {
    GLint draw_framebuffer, read_framebuffer, viewport[4], program, vertex_array, active_texture;
    GLboolean scissor, blend[FRAME_MAX_BUFFERS];
    int blend_count;
    int first_unit, unit_count;
    GLint textures[HALO_MAX_PASS_INPUTS];
} frame_saved;

static void frame_save(const halo_glfuncs *f, frame_saved *s, int units)
{
    memset(s, 0, sizeof *s);
    f->GetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &s->draw_framebuffer);
    f->GetIntegerv(GL_READ_FRAMEBUFFER_BINDING, &s->read_framebuffer);
    f->GetIntegerv(GL_VIEWPORT, s->viewport);
    f->GetIntegerv(GL_CURRENT_PROGRAM, &s->program);
    f->GetIntegerv(GL_VERTEX_ARRAY_BINDING, &s->vertex_array);
    f->GetIntegerv(GL_ACTIVE_TEXTURE, &s->active_texture);
    if (f->IsEnabled)
        s->scissor = f->IsEnabled(GL_SCISSOR_TEST);
    GLint max_buffers = 1;
    f->GetIntegerv(GL_MAX_DRAW_BUFFERS, &max_buffers);
    s->blend_count = max_buffers < 1 ? 1 : max_buffers > FRAME_MAX_BUFFERS ? FRAME_MAX_BUFFERS : max_buffers;
    for (int i = 0; i < s->blend_count; ++i)
        s->blend[i] = f->IsEnabledi ? f->IsEnabledi(GL_BLEND, (GLuint)i) : f->IsEnabled ? f->IsEnabled(GL_BLEND) : 0;
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
    f->ActiveTexture((GLenum)s->active_texture);
    f->BindFramebuffer(GL_DRAW_FRAMEBUFFER, (GLuint)s->draw_framebuffer);
    f->BindFramebuffer(GL_READ_FRAMEBUFFER, (GLuint)s->read_framebuffer);
    f->Viewport(s->viewport[0], s->viewport[1], s->viewport[2], s->viewport[3]);
    f->UseProgram((GLuint)s->program);
    f->BindVertexArray((GLuint)s->vertex_array);
    if (s->scissor)
        f->Enable(GL_SCISSOR_TEST);
    for (int i = 0; i < s->blend_count; ++i) {
        if (f->Enablei && f->Disablei)
            (s->blend[i] ? f->Enablei : f->Disablei)(GL_BLEND, (GLuint)i);
        else if (i == 0)
            (s->blend[0] ? f->Enable : f->Disable)(GL_BLEND);
    }
}

/* Clears the current texture of image i through the frame's framebuffer (bound as draw). */
static void frame_clear_image(halo_gl_frame *fr, int i)
{
    const halo_glfuncs *f = &fr->gl->f;
    frame_image *image = &fr->images[i];
    if (image->host)
        return;
    const GLfloat value[4] = {image->clear, image->clear, image->clear, image->clear};
    f->FramebufferTexture2D(GL_DRAW_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D,
                            image->texture[image->current], 0);
    f->ClearBufferfv(GL_COLOR, 0, value);
}

static GLuint frame_build_pass(const halo_glfuncs *f, const halo_program *p, size_t index, halo_diagnostics *diag)
{
    const halo_pass_info *pass = halo_program_pass(p, index);
    char file[256];
    snprintf(file, sizeof file, "(image pass '%s' of %s)", pass->name ? pass->name : "?",
             pass->stage ? pass->stage : "?");
    const halo_line_origin *origins = p->pass_origins ? p->pass_origins[index] : NULL;
    int origin_count = origins && p->pass_origin_counts ? p->pass_origin_counts[index] : 0;
    GLuint vertex = compile_mapped(f, GL_VERTEX_SHADER, pass->vertex_source, NULL, NULL, 0, file, diag);
    GLuint fragment = compile_mapped(f, GL_FRAGMENT_SHADER, pass->fragment_source, NULL, origins, origin_count,
                                     file, diag);
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
    if (p->unlocated_outputs || p->target == HALO_TARGET_GLSL150)
        f->BindFragDataLocation(program, 0, "halo_pass_output");
    f->LinkProgram(program);
    f->DetachShader(program, vertex);
    f->DetachShader(program, fragment);
    f->DeleteShader(vertex);
    f->DeleteShader(fragment);
    GLint ok = GL_FALSE;
    f->GetProgramiv(program, GL_LINK_STATUS, &ok);
    if (!ok) {
        char *log = program_log(f, program);
        size_t errors_before = halo_diagnostics_errors(diag);
        if (log)
            report_log(diag, HALO_MSG_GL_LINK, log, NULL, NULL, file);
        if (!diag || halo_diagnostics_errors(diag) == errors_before)
            halo_diag_error(diag, GL_LINK, file, 0, 0, "the driver could not link the image pass");
        free(log);
        f->DeleteProgram(program);
        return 0;
    }
    return program;
}

halo_gl_frame *halo_gl_frame_create(halo_gl *gl, const halo_program *p, int width, int height,
                                    halo_diagnostics *diag)
{
    HALO_REFUSE_NULL(diag, gl, "gl", NULL);
    HALO_REFUSE_NULL(diag, p, "program", NULL);
    if (width < 1 || height < 1 || width > 16384 || height > 16384) {
        halo_diag_error(diag, USAGE, "", 0, 0, "halo_gl_frame_create: a size in 1..16384 is required");
        return NULL;
    }
    const halo_glfuncs *f = &gl->f;
    if (halo_program_output_count(p) > 0) {
        GLint major = 0;
        f->GetIntegerv(GL_MAJOR_VERSION, &major);
        if (major < 4 || !f->Enablei || !f->Disablei || !f->BlendEquationi || !f->BlendFunci || !f->IsEnabledi) {
            halo_diag_error(diag, GL_PROC_MISSING, "", 0, 0,
                            "the program writes extra outputs, which need per-draw-buffer blending "
                            "(glBlendFunci, glBlendEquationi: OpenGL 4.0); this context is OpenGL %d.x", major);
            return NULL;
        }
    }
    halo_gl_frame *fr = calloc(1, sizeof *fr);
    if (!fr) {
        halo_diag_error(diag, OUT_OF_MEMORY, "", 0, 0, "out of memory creating a frame");
        return NULL;
    }
    fr->gl = gl;
    fr->program = p;
    atomic_fetch_add(&gl->refs, 1);
    halo_program_retain(p);
    fr->width = width;
    fr->height = height;
    fr->image_count = halo_program_image_count(p);
    fr->pass_count = halo_program_pass_count(p);
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
    int precision = halo_program_image_precision(p);
    int failed = 0;
    f->GenFramebuffers(1, &fr->framebuffer);
    f->GenVertexArrays(1, &fr->vertex_array);
    f->BindFramebuffer(GL_FRAMEBUFFER, fr->framebuffer);
    GLenum attachment0 = GL_COLOR_ATTACHMENT0;
    f->DrawBuffers(1, &attachment0);
    f->ReadBuffer(GL_COLOR_ATTACHMENT0);
    for (size_t i = 0; i < fr->image_count && !failed; ++i) {
        const halo_image_info *info = halo_program_image(p, i);
        frame_image *image = &fr->images[i];
        image->name = info->name;
        image->channels = info->channels;
        image->reset = info->reset;
        image->clear = (GLfloat)info->clear;
        image->host = info->host;
        int scale = info->scale > 1 ? info->scale : 1;
        image->width = (width + scale - 1) / scale;
        image->height = (height + scale - 1) / scale;
        if (image->host)
            continue;
        GLint internal;
        GLenum format;
        image_formats(image->channels, precision, &internal, &format);
        f->GenTextures(2, image->texture);
        for (int k = 0; k < 2; ++k) {
            f->BindTexture(GL_TEXTURE_2D, image->texture[k]);
            f->TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
            f->TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
            f->TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
            f->TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
            f->TexImage2D(GL_TEXTURE_2D, 0, internal, image->width, image->height, 0, format, GL_FLOAT, NULL);
            f->FramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, image->texture[k], 0);
            GLenum status = f->CheckFramebufferStatus(GL_FRAMEBUFFER);
            if (status != GL_FRAMEBUFFER_COMPLETE) {
                halo_diag_error(diag, GL_LINK, "", 0, 0,
                                "image '%s': a %dx%d texture of %d channels at precision %d cannot be rendered to "
                                "(framebuffer status 0x%x)", image->name, image->width, image->height, image->channels, precision,
                                status);
                failed = 1;
                break;
            }
        }
    }
    if (!failed && halo_program_segment_location(p) > 0) {
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
    for (size_t i = 0; i < fr->pass_count && !failed; ++i) {
        const halo_pass_info *info = halo_program_pass(p, i);
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
        pass->program = frame_build_pass(f, p, i, diag);
        if (!pass->program) {
            failed = 1;
            break;
        }
        f->UseProgram(pass->program);
        for (int k = 0; k < info->input_count; ++k) {
            char name[32];
            snprintf(name, sizeof name, "halo_input_%d", k);
            f->Uniform1i(f->GetUniformLocation(pass->program, name), k);
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
    halo_gl_frame_begin(fr);
    return fr;
}

void halo_gl_frame_destroy(halo_gl_frame *fr)
{
    if (!fr)
        return;
    const halo_glfuncs *f = &fr->gl->f;
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
    free(fr->images);
    free(fr->passes);
    halo_program_destroy((halo_program *)fr->program); /* the frame's references */
    halo_gl_destroy(fr->gl);
    free(fr);
}

static void frame_clear(halo_gl_frame *fr, int group);
static void frame_run(halo_gl_frame *fr, int post);

void halo_gl_frame_begin(halo_gl_frame *fr)
{
    HALO_REFUSE_NULL_VOID(NULL, fr, "frame");
    fr->groups_ended = 0;
    frame_clear(fr, 0);
}

void halo_gl_frame_begin_group(halo_gl_frame *fr)
{
    HALO_REFUSE_NULL_VOID(NULL, fr, "frame");
    frame_clear(fr, 1);
}

void halo_gl_frame_end_group(halo_gl_frame *fr)
{
    HALO_REFUSE_NULL_VOID(NULL, fr, "frame");
    frame_run(fr, 1);
    fr->groups_ended++;
}

/* Clears every image (group: all but the frame's accumulators, reset=frame-only). */
static void frame_clear(halo_gl_frame *fr, int group)
{
    if (!fr || fr->image_count == 0)
        return;
    const halo_glfuncs *f = &fr->gl->f;
    GLint draw_framebuffer = 0;
    GLboolean scissor = f->IsEnabled ? f->IsEnabled(GL_SCISSOR_TEST) : GL_FALSE;
    f->GetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &draw_framebuffer);
    f->BindFramebuffer(GL_DRAW_FRAMEBUFFER, fr->framebuffer);
    if (scissor)
        f->Disable(GL_SCISSOR_TEST);
    for (size_t i = 0; i < fr->image_count; ++i)
        if (!group || fr->images[i].reset != HALO_RESET_FRAME_ONLY)
            frame_clear_image(fr, (int)i);
    f->FramebufferTexture2D(GL_DRAW_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, 0, 0);
    if (scissor)
        f->Enable(GL_SCISSOR_TEST);

    f->BindFramebuffer(GL_DRAW_FRAMEBUFFER, (GLuint)draw_framebuffer);
}

/* Attaches the outputs' current textures to the framebuffer bound as GL_DRAW_FRAMEBUFFER. */
static void frame_attach_textures(halo_gl_frame *fr)
{
    const halo_glfuncs *f = &fr->gl->f;
    size_t n = halo_program_output_count(fr->program);
    for (size_t i = 0; i < n; ++i) {
        const halo_output_info *o = halo_program_output(fr->program, i);
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
    size_t n = halo_program_output_count(fr->program);
    if (n == 0)
        return;
    const halo_glfuncs *f = &fr->gl->f;
    f->BindFramebuffer(GL_DRAW_FRAMEBUFFER, host_framebuffer);
    frame_attach_textures(fr);
    GLenum buffers[FRAME_MAX_BUFFERS * 4];
    int max_location = 0;
    for (size_t i = 0; i < n; ++i) {
        int location = halo_program_output(fr->program, i)->location;
        if (location > max_location && location < (int)(sizeof buffers / sizeof buffers[0]))
            max_location = location;
    }
    buffers[0] = GL_COLOR_ATTACHMENT0;
    for (int k = 1; k <= max_location; ++k)
        buffers[k] = GL_NONE;
    for (size_t i = 0; i < n; ++i) {
        const halo_output_info *o = halo_program_output(fr->program, i);
        if (o->location < 1 || o->location > max_location)
            continue;
        buffers[o->location] = GL_COLOR_ATTACHMENT0 + (GLenum)o->location;
        if (!f->Enablei || !f->BlendEquationi || !f->BlendFunci)
            continue; /* reported by halo_gl_frame_create */
        if (o->blend == HALO_BLEND_NONE) {
            f->Disablei(GL_BLEND, (GLuint)o->location);
            continue;
        }
        f->Enablei(GL_BLEND, (GLuint)o->location);
        f->BlendEquationi((GLuint)o->location, o->blend == HALO_BLEND_MAX   ? GL_MAX
                                               : o->blend == HALO_BLEND_MIN ? GL_MIN
                                                                            : GL_FUNC_ADD);
        if (o->blend == HALO_BLEND_FIRST) /* front to back by coverage: the first hit stays */
            f->BlendFunci((GLuint)o->location, GL_ONE_MINUS_DST_ALPHA, GL_ONE);
        else
            f->BlendFunci((GLuint)o->location, GL_ONE, GL_ONE);
    }
    f->DrawBuffers(max_location + 1, buffers);
    fr->attached = 1;
    fr->attached_framebuffer = host_framebuffer;
}

/* Binds the samplers' current textures to their units (from first_unit on). */
static void frame_bind_textures(halo_gl_frame *fr, int first_unit)
{
    const halo_glfuncs *f = &fr->gl->f;
    size_t n = halo_program_sampler_count(fr->program);
    for (size_t i = 0; i < n; ++i) {
        int image = frame_find_image(fr, halo_program_sampler(fr->program, i)->image);
        if (image < 0)
            continue;
        const frame_image *im = &fr->images[image];
        f->ActiveTexture(GL_TEXTURE0 + (GLenum)(first_unit + (int)i));
        f->BindTexture(GL_TEXTURE_2D, im->texture[im->current]);
    }
}

void halo_gl_frame_bind(halo_gl_frame *fr, unsigned gl_program, int first_unit)
{
    HALO_REFUSE_NULL_VOID(NULL, fr, "frame");
    if (first_unit < 0)
        return;
    size_t n = halo_program_sampler_count(fr->program);
    if (n == 0)
        return;
    const halo_glfuncs *f = &fr->gl->f;
    GLint active = GL_TEXTURE0;
    f->GetIntegerv(GL_ACTIVE_TEXTURE, &active);
    frame_bind_textures(fr, first_unit);
    for (size_t i = 0; i < n; ++i)
        f->Uniform1i(f->GetUniformLocation(gl_program, halo_program_sampler(fr->program, i)->name),
                     first_unit + (GLint)i);
    f->ActiveTexture((GLenum)active);
    fr->bound = 1;
    fr->bound_first_unit = first_unit;
}

static void frame_run(halo_gl_frame *fr, int post);

void halo_gl_frame_generate(halo_gl_frame *fr)
{
    HALO_REFUSE_NULL_VOID(NULL, fr, "frame");
    frame_run(fr, 0);
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
        frame_run(fr, 1);
    frame_run(fr, 2);
}

unsigned halo_gl_frame_texture(const halo_gl_frame *fr, const char *image)
{
    HALO_REFUSE_NULL(NULL, fr, "frame", 0);
    HALO_REFUSE_NULL(NULL, image, "image", 0);
    int i = frame_find_image(fr, image);
    return i < 0 ? 0 : fr->images[i].texture[fr->images[i].current];
}

static void frame_run(halo_gl_frame *fr, int post)
{
    if (!fr || (fr->pass_count == 0 && fr->image_count == 0))
        return;
    halo_gl *gl = fr->gl;
    const halo_glfuncs *f = &gl->f;
    frame_saved saved;
    frame_save(f, &saved, fr->max_inputs);
    f->BindFramebuffer(GL_FRAMEBUFFER, fr->framebuffer);
    f->Viewport(0, 0, fr->width, fr->height);
    f->Disable(GL_BLEND);
    f->Disable(GL_SCISSOR_TEST);
    f->BindVertexArray(fr->vertex_array);
    for (size_t i = 0; i < fr->pass_count; ++i) {
        frame_pass *pass = &fr->passes[i];
        frame_image *out = &fr->images[pass->output];
        if (pass->info->post != post || out->host)
            continue;
        f->UseProgram(pass->program);
        halo_gl_program_upload(gl, fr->program, pass->program);
        f->Viewport(0, 0, out->width, out->height);
        for (int rep = pass->start; rep <= pass->repeat; ++rep) {
            for (int k = 0; k < pass->info->input_count; ++k) {
                const frame_image *in = pass->inputs[k] >= 0 ? &fr->images[pass->inputs[k]]
                                        : rep == pass->start && pass->first >= 0 ? &fr->images[pass->first]
                                                                        : out;
                f->ActiveTexture(GL_TEXTURE0 + (GLenum)k);
                f->BindTexture(GL_TEXTURE_2D, in->texture[in->current]);
            }
            if (pass->index_location >= 0)
                f->Uniform1i(pass->index_location, rep);
            if (pass->count_location >= 0)
                f->Uniform1i(pass->count_location, pass->repeat);
            f->FramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D,
                                    out->texture[1 - out->current], 0);
            f->DrawArrays(GL_TRIANGLES, 0, 3);
            out->current = 1 - out->current;
            fr->pass_draws++;
        }
    }
    for (size_t i = 0; i < fr->image_count && !post; ++i)
        if (fr->images[i].reset == HALO_RESET_GENERATION)
            frame_clear_image(fr, (int)i);
    f->FramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, 0, 0);
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
        f->ActiveTexture((GLenum)saved.active_texture);
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
    GLint read_framebuffer = 0, pack = 4;
    f->GetIntegerv(GL_READ_FRAMEBUFFER_BINDING, &read_framebuffer);
    f->GetIntegerv(GL_PACK_ALIGNMENT, &pack);
    f->BindFramebuffer(GL_READ_FRAMEBUFFER, fr->framebuffer);
    f->FramebufferTexture2D(GL_READ_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, im->texture[im->current], 0);
    f->ReadBuffer(GL_COLOR_ATTACHMENT0);
    f->PixelStorei(GL_PACK_ALIGNMENT, 4);
    static const GLenum formats[4] = {GL_RED, GL_RG, GL_RGB, GL_RGBA};
    f->ReadPixels(0, 0, im->width, im->height, formats[im->channels - 1], GL_FLOAT, out);
    f->FramebufferTexture2D(GL_READ_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, 0, 0);
    f->PixelStorei(GL_PACK_ALIGNMENT, pack);
    f->BindFramebuffer(GL_READ_FRAMEBUFFER, (GLuint)read_framebuffer);
    return f->GetError() == GL_NO_ERROR ? HALO_OK : HALO_ERROR_IO;
}

long halo_gl_frame_pass_draws(const halo_gl_frame *fr)
{
    HALO_REFUSE_NULL(NULL, fr, "frame", 0);
    return fr->pass_draws;
}
