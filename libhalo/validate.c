/* Validation with glslang, in process (glslang_parse.cpp). Every error glslang reports is
 * rewritten to the origin of its line: the module's or the host's own file:line:col. */
#include "diag.h"
#include "glsl_locate.h"
#include "glslang_parse.h"
#include "internal.h"
#include "strbuf.h"

#include <ctype.h>
#include <stdlib.h>
#include <string.h>

/* How a shader's lines map back: through origins (line N of the source is origins[N-1]),
 * or, raw, as glslang reports them (a plain shader with '#line': its own numbering). */
typedef struct log_map {
    const halo_line_origin *origins;
    int origin_count;
    int raw;
    const char *fallback;   /* the file, and the name glslang is given for the text */
    const char *source;     /* the text compiled (glslang_run sets it) */
    halo_glsl_spots *spots; /* where its errors are (glsl_locate.c); NULL: none */
    /* the last error's place: a later error there that follows from it is dropped */
    int last_line;
    char last_file[512];
} log_map;

static void report_entry(char *line, log_map *map, halo_diagnostics *diag, int *errors)
{
    halo_severity sev;
    const char *rest;
    if (!strncmp(line, "ERROR: ", 7)) {
        sev = HALO_SEVERITY_ERROR;
        rest = line + 7;
    } else if (!strncmp(line, "WARNING: ", 9)) {
        sev = HALO_SEVERITY_WARNING;
        rest = line + 9;
    } else
        return;
    size_t name_len = 0;
    int out_line = 0, numbered = 0;
    size_t consumed = halo_glsl_log_location(rest, map->fallback, &name_len, &out_line, &numbered);
    char *msg = line + (rest - line) + consumed;
    while (*msg == ' ')
        msg++;
    for (size_t n = strlen(msg); n > 0 && (msg[n - 1] == ' ' || msg[n - 1] == '\r'); n--)
        msg[n - 1] = '\0';
    if (strstr(msg, "compilation errors.") || strstr(msg, "compilation terminated"))
        return;
    int column = 0, at_end = 0; /* glsl_locate.c: the token, or after the one before a missing ';' */
    if (numbered && !map->raw)
        halo_glsl_place(map->spots, msg, &out_line, &column, &at_end);
    char named[512] = "";
    const char *file = map->fallback;
    int line_no = 0, col = 0, generated_line = 0;
    const char *text = NULL;
    if (consumed && !numbered) {
        /* '#line L "name"': the name and line the shader gave itself */
        snprintf(named, sizeof named, "%.*s", (int)name_len, rest);
        file = named;
        line_no = out_line;
    } else if (consumed && map->raw) {
        line_no = out_line;
    } else if (out_line >= 1 && out_line <= map->origin_count) {
        const halo_line_origin *o = &map->origins[out_line - 1];
        file = o->file;
        line_no = o->line;
        text = o->text;
        col = halo_glsl_original_column(map->source, out_line, column, at_end, msg, o->text);
        if (o->file == halo_generated_file) { /* no line of the reader's file: say where it is */
            file = map->fallback;
            line_no = col = 0;
            text = NULL;
            generated_line = out_line;
        }
    }
    if (sev == HALO_SEVERITY_ERROR && *errors && line_no && line_no == map->last_line &&
        !strcmp(file, map->last_file) && halo_glsl_follows_earlier_error(msg))
        return; /* one problem, one message */
    if (sev == HALO_SEVERITY_ERROR) {
        map->last_line = line_no;
        snprintf(map->last_file, sizeof map->last_file, "%s", file);
    }
    char *message = halo_glsl_message(msg, text);
    halo_diagnostics_report(diag, sev, sev == HALO_SEVERITY_ERROR ? HALO_MSG_GLSL_ERROR : HALO_MSG_GLSL_WARNING, file,
                            line_no, col, text,
                            generated_line ? "%s (in code libhalo wrote: line %d of the linked shader)" : "%s",
                            message ? message : msg, generated_line);
    free(message);
    if (sev == HALO_SEVERITY_ERROR)
        (*errors)++;
}

static void report_log(const char *log, log_map *map, halo_diagnostics *diag, int *errors)
{
    char *copy = halo_strdup(log ? log : "");
    if (!copy)
        return;
    map->last_line = 0;
    char *cursor = NULL; /* strtok_r: another thread may be reading its own log */
    for (char *line = strtok_r(copy, "\n", &cursor); line; line = strtok_r(NULL, "\n", &cursor))
        report_entry(line, map, diag, errors);
    free(copy);
}

/* Compiles and links one shader. link_always: link after compile errors too, as
 * glslangValidator -l does (a missing main, interface errors). */
static halo_status glslang_run(const char *source, halo_shader_kind kind, int link_always, const log_map *where,
                               halo_diagnostics *diag)
{
    int vertex = kind == HALO_SHADER_VERTEX;
    halo_glslang_result r;
    /* Without cascading errors glslang stops at the first statement with an error; with
     * them it goes on, and report_log drops the errors that follow from an earlier one on
     * the same line (halo_glsl_follows_earlier_error): every problem once. One parse of
     * the source, the preprocessor inside it, gives the messages in glslangValidator's
     * order: the preprocessor's and the parser's merged, none after where it stops. */
    if (halo_glslang_compile(source, vertex, where->fallback,
                             link_always ? HALO_GLSLANG_LINK_ALWAYS : HALO_GLSLANG_LINK_IF_COMPILED, &r)) {
        halo_diag_error(diag, OUT_OF_MEMORY, where->fallback, 0, 0, "glslang could not compile the shader");
        return HALO_ERROR_IO;
    }
    halo_glsl_spots spots = {0};
    log_map copy = *where, *map = &copy;
    map->source = source;
    map->spots = &spots;
    int errors = 0;
    /* glslang 12 gives no columns: where the text has errors, compile it once more with
     * one token per line to find them (glsl_locate.c). */
    if (!r.compiled)
        halo_glsl_locate(source, vertex, where->fallback, &spots);
    report_log(r.log, map, diag, &errors);
    halo_glsl_spots_free(&spots);
    map->spots = NULL;
    if (!r.linked) {
        /* Linking catches a missing main and interface errors. */
        int before = errors;
        report_log(r.link_log, map, diag, &errors);
        if (errors == before && r.compiled) {
            halo_diag_error(diag, GLSL_ERROR, map->fallback, 0, 0, "glslang: link failed");
            errors++;
        }
    }
    halo_glslang_result_free(&r);
    if (!r.compiled && !errors) {
        halo_diag_error(diag, GLSL_ERROR, map->fallback, 0, 0, "glslang rejected the shader");
        errors++;
    }
    return errors ? HALO_ERROR_INPUT : HALO_OK;
}

static int version_directive_line(const char *source);

halo_status halo_glslang_validate(const char *source, halo_shader_kind kind, halo_target target,
                                  const halo_line_origin *origins, int origin_count, const char *fallback_file,
                                  halo_diagnostics *diag)
{
    log_map map = {.origins = origins, .origin_count = origin_count, .fallback = fallback_file};
    /* The #version line in the source selects the language. A text without one (linked
     * with HALO_VERSION_NONE, or KEEP from a host without one, or composed by an engine
     * that adds its own at compile time, as three.js does) is checked as the target it was
     * linked for: the version the engine adds, not GLSL ES 1.00, which no host of libhalo's
     * targets is. */
    if (version_directive_line(source) || target == HALO_TARGET_DEFAULT || (unsigned)target >= HALO_TARGET_COUNT)
        return glslang_run(source, kind, 0, &map, diag);
    halo_strbuf b = {0};
    halo_strbuf_printf(&b, "%s\n%s", halo_target_version_line(target), source);
    char *text = halo_strbuf_take(&b);
    halo_line_origin *shifted = calloc((size_t)origin_count + 1, sizeof *shifted);
    if (!text || !shifted) {
        free(text);
        free(shifted);
        halo_diag_error(diag, OUT_OF_MEMORY, fallback_file, 0, 0, "out of memory");
        return HALO_ERROR_IO;
    }
    shifted[0] = (halo_line_origin){halo_generated_file, 0, NULL};
    if (origin_count)
        memcpy(shifted + 1, origins, (size_t)origin_count * sizeof *shifted);
    map.origins = shifted;
    map.origin_count = origin_count + 1;
    halo_status st = glslang_run(text, kind, 0, &map, diag);
    free(shifted);
    free(text);
    return st;
}

/* The public validation functions hold glslang while they run (halo_glslang_acquire). */
static halo_status program_validate_held(const halo_program *p, halo_diagnostics *diag)
{
    halo_status st =
        halo_glslang_validate(p->source, p->kind, p->target, p->origins, p->origin_count, p->host_file, diag);
    for (size_t i = 0; i < p->pass_count; i++) {
        const halo_pass_info *pass = &p->passes[i];
        const char *file = pass->stage;
        if (halo_glslang_validate(pass->fragment_source, HALO_SHADER_FRAGMENT, p->target, p->pass_origins[i],
                                  p->pass_origin_counts[i], file, diag) != HALO_OK ||
            halo_glslang_validate(pass->vertex_source, HALO_SHADER_VERTEX, p->target, NULL, 0, "<pass vertex shader>",
                                  diag) != HALO_OK)
            st = HALO_ERROR_INPUT;
    }
    return st;
}

/* Is there a '#pragma halo WORD' at p, or after a '#' later on the line (a commented-out one)? */
static int mentions_annotation(const char *line, const char *word, int anywhere)
{
    size_t n = strlen(word);
    for (const char *h = line; h; h = anywhere && *h ? strchr(h + 1, '#') : NULL) {
        int col = halo_annotation_start(h);
        if (col && !strncmp(h + col - 1, word, n) && !isalnum((unsigned char)h[col - 1 + n]) && h[col - 1 + n] != '_')
            return 1;
    }
    return 0;
}

halo_source_kind halo_source_kind_of(const char *source)
{
    HALO_REFUSE_NULL(NULL, source, "source", HALO_SOURCE_SHADER);
    char *copy = source ? halo_strdup(source) : NULL;
    char **lines = NULL;
    int n = copy ? halo_split_lines(copy, &lines) : -1;
    halo_source_kind kind = HALO_SOURCE_SHADER;
    for (int i = 0; i < n && kind != HALO_SOURCE_MODULE; i++) {
        if (mentions_annotation(lines[i], "module", 0))
            kind = HALO_SOURCE_MODULE;
        else if (mentions_annotation(lines[i], "declarations", 1))
            kind = HALO_SOURCE_HOST;
    }
    free(lines);
    free(copy);
    return kind;
}

/* Skips blanks, line ends and comments, as the preprocessor does before a token;
 * *line counts the line ends ("\n", "\r\n", or a lone "\r"). Stops at a line end when
 * in_line (a directive ends there). */
static const char *skip_blank(const char *p, int *line, int in_line)
{
    for (;;) {
        if (*p == ' ' || *p == '\t' || *p == '\v' || *p == '\f')
            p++;
        else if (!in_line && (*p == '\n' || *p == '\r')) {
            p += p[0] == '\r' && p[1] == '\n' ? 2 : 1;
            (*line)++;
        } else if (p[0] == '/' && p[1] == '/') {
            while (*p && *p != '\n' && *p != '\r')
                p++;
        } else if (p[0] == '/' && p[1] == '*') {
            const char *end = strstr(p + 2, "*/");
            if (!end)
                return p + strlen(p);
            for (p += 2; p < end; p++)
                if (*p == '\n' || (*p == '\r' && p[1] != '\n'))
                    (*line)++;
            p = end + 2;
        } else {
            return p;
        }
    }
}

/* The line of the shader's '#version' (0: none): the preprocessor takes it as the first
 * token of the text, '#' then 'version', never one in a comment or after code. */
static int version_directive_line(const char *source)
{
    int line = 1;
    const char *p = skip_blank(source, &line, 0);
    if (*p != '#')
        return 0;
    p = skip_blank(p + 1, &line, 1);
    return !strncmp(p, "version", 7) && !isalnum((unsigned char)p[7]) && p[7] != '_' ? line : 0;
}

/* Does a line start with the directive '#line'? */
static int is_line_directive(const char *l)
{
    int n = 0;
    l = skip_blank(l, &n, 1);
    if (*l != '#')
        return 0;
    l = skip_blank(l + 1, &n, 1);
    return !strncmp(l, "line", 4) && !isalnum((unsigned char)l[4]) && l[4] != '_';
}

/* A plain shader (no libhalo annotation): validated as is, for its own #version or,
 * else for the target's. Lines are numbered as an editor shows them: an old-Mac
 * "\r" ends a line. */
static halo_status validate_plain(const char *source, const char *file, halo_shader_kind kind, halo_target target,
                                  halo_diagnostics *diag)
{
    char *copy = halo_strdup(source), *text = NULL;
    char **lines = NULL;
    for (char *p = copy; p && *p; p++)
        if (*p == '\r' && p[1] != '\n')
            *p = '\n';
    int n = copy ? halo_split_lines(copy, &lines) : -1;
    halo_line_origin *origins = n >= 0 ? calloc((size_t)n + 2, sizeof *origins) : NULL;
    int raw = 0, version_line = version_directive_line(source), first = 0;
    halo_strbuf b = {0};
    if (origins && target != HALO_TARGET_DEFAULT && !version_line) {
        /* the target's version, on a line of its own before the shader's first */
        halo_strbuf_printf(&b, "%s\n", halo_target_version_line(target));
        origins[first++] = (halo_line_origin){halo_generated_file, 0, NULL};
    }
    for (int i = 0; origins && i < n; i++) {
        origins[first + i] = (halo_line_origin){file, i + 1, lines[i]};
        if (is_line_directive(lines[i]))
            raw = 1;
        const char *hash = strchr(lines[i], '#');
        if (target != HALO_TARGET_DEFAULT && i + 1 == version_line && hash) {
            /* the target's version in place of the shader's own, on the same line */
            halo_strbuf_printf(&b, "%.*s%s\n", (int)(hash - lines[i]), lines[i], halo_target_version_line(target));
        } else {
            halo_strbuf_printf(&b, "%s\n", lines[i]);
        }
    }
    text = halo_strbuf_take(&b);
    halo_status st = HALO_ERROR_IO;
    if (!text || !origins) {
        halo_diag_error(diag, OUT_OF_MEMORY, file, 0, 0, "out of memory");
    } else {
        if (target == HALO_TARGET_DEFAULT && !version_line)
            halo_diagnostics_report(diag, HALO_SEVERITY_NOTE, HALO_MSG_GLSL_VERSION_IMPLIED, file, 0, 0, NULL,
                                    "no '#version': checked as GLSL ES 1.00, GLSL's rule for a shader without one "
                                    "(desktop OpenGL reads it as GLSL 1.10; --target chooses a version)");
        log_map map = {.origins = origins, .origin_count = n + first, .raw = raw, .fallback = file};
        st = glslang_run(text, kind, 1, &map, diag);
    }
    free(text);
    free(origins);
    free(lines);
    free(copy);
    return st;
}

static halo_status validate_shader_held(const char *source, const char *file, halo_shader_kind kind, halo_target target,
                                        halo_diagnostics *diag)
{
    if (!file)
        file = "shader";
    source = halo_skip_bom(source); /* editors write it; glslang would not take it */
    if (halo_source_kind_of(source) != HALO_SOURCE_HOST)
        return validate_plain(source, file, kind, target, diag);
    /* A host (it has the marker): link it with no stage, which also checks the contract. */
    halo_library empty = {.refs = 1}; /* never freed: the link's reference goes again */
    halo_program *p = halo_link_host(
        &(halo_link_desc){.library = &empty, .host_source = source, .host_file = file, .target = target, .kind = kind},
        diag);
    halo_status st = p ? HALO_WITH_GLSLANG(diag, program_validate_held(p, diag)) : HALO_ERROR_INPUT;
    halo_program_destroy(p);
    return st;
}

static const char check_host_file[] = "<check-host>";

/* %s: the output's layout (none under GLSL 150) */
static const char check_host_source[] =
    "#pragma halo declarations\n"
    "%sout vec4 fragment_color;\n"
    "void main() {\n"
    "    halo_sample s = halo_make_sample(vec3(0.5), 0.5, vec3(0.1, 0.2, 0.3), vec3(0.0, 0.0, 1.0), 0.5,\n"
    "                                     gl_FragCoord.xy, vec3(0.8), 0.5);\n"
    "    halo_apply(s);\n"
    "    halo_finish();\n"
    "    fragment_color = vec4(s.color, s.opacity);\n"
    "}\n";

/* The check host and the code the linker writes around the stage are no file of the
 * module's author: an error there (an entry that does not fit libhalo's call) is the
 * entry's, at the module's 'apply'. */
static void point_check_host_at_entry(halo_program *p, const halo_module *m)
{
    int line = m->module_line;
    for (size_t i = 0; i < m->declared.count; i++)
        if (!strcmp(m->declared.items[i], "apply"))
            line = m->declared.lines[i];
    for (int i = 0; i < p->origin_count; i++) {
        halo_line_origin *o = &p->origins[i];
        if (o->file == halo_generated_file || !strcmp(o->file, check_host_file))
            *o = (halo_line_origin){m->file, line, line >= 1 && line <= m->line_count ? m->lines[line - 1] : NULL};
    }
}

static halo_status module_validate_held(const halo_library *lib, const halo_module *m, halo_target target,
                                        halo_diagnostics *diag)
{
    if (m->is_library) {
        /* Every helper, in file order, in a translation unit of its own. */
        halo_strbuf b = {0};
        halo_line_origin *origins = calloc((size_t)m->line_count + 8, sizeof *origins);
        if (!origins)
            return HALO_ERROR_IO;
        int count = 0;
        halo_target t = target == HALO_TARGET_DEFAULT ? HALO_TARGET_GLSL330 : target;
        halo_strbuf_printf(&b, "%s\n", halo_target_version_line(t));
        origins[count++] = (halo_line_origin){halo_generated_file, 0, NULL};
        if (t == HALO_TARGET_ES300) {
            halo_strbuf_append(&b, "precision highp float;\n");
            origins[count++] = (halo_line_origin){halo_generated_file, 0, NULL};
        }
        for (int i = 0; i < m->line_count; i++) {
            if (m->is_annotation[i])
                continue;
            halo_strbuf_printf(&b, "%s\n", m->lines[i]);
            origins[count++] = (halo_line_origin){m->file, i + 1, m->lines[i]};
        }
        halo_strbuf_append(&b, "void main() {}\n");
        origins[count++] = (halo_line_origin){halo_generated_file, 0, NULL};
        char *text = halo_strbuf_take(&b);
        halo_status st =
            text ? halo_glslang_validate(text, HALO_SHADER_FRAGMENT, t, origins, count, m->file, diag) : HALO_ERROR_IO;
        free(text);
        free(origins);
        return st;
    }
    if (m->hook != HALO_HOOK_SAMPLE)
        return HALO_OK; /* other hooks are checked by their own hosts */
    halo_scene *scene = halo_scene_create(lib);
    if (!scene)
        return HALO_ERROR_IO;
    halo_status st = halo_scene_enable(scene, m->name, 1, diag);
    /* Both variants must compile: parameters as constants, and as uniforms. */
    char host[sizeof check_host_source + 32];
    snprintf(host, sizeof host, check_host_source, target == HALO_TARGET_GLSL150 ? "" : "layout(location = 0) ");
    for (int live = 0; live < 2 && st == HALO_OK; live++) {
        halo_program *p = halo_link_host(&(halo_link_desc){.library = lib,
                                                           .scene = scene,
                                                           .host_source = host,
                                                           .host_file = check_host_file,
                                                           .target = target,
                                                           .all_live = live},
                                         diag);
        if (p)
            point_check_host_at_entry(p, m);
        st = p ? HALO_WITH_GLSLANG(diag, program_validate_held(p, diag)) : HALO_ERROR_INPUT;
        halo_program_destroy(p);
    }
    halo_scene_destroy(scene);
    return st;
}

halo_status halo_validate_module(const halo_library *lib, const halo_module *m, halo_target target,
                                 halo_diagnostics *diag)
{
    HALO_REFUSE_NULL(diag, lib, "library", HALO_ERROR_INPUT);
    size_t i = 0;
    while (i < lib->count && lib->modules[i] != m)
        i++;
    if (i == lib->count) {
        /* the check links by name: it would validate lib's module of that name instead */
        halo_diag_error(diag, USAGE, "", 0, 0, "halo_validate: module '%s' is not one of the library's",
                        halo_module_name_of(m));
        return HALO_ERROR_INPUT;
    }
    return HALO_WITH_GLSLANG(diag, module_validate_held(lib, m, target, diag));
}

halo_status halo_validate_program(const halo_program *p, halo_diagnostics *diag)
{
    return HALO_WITH_GLSLANG(diag, program_validate_held(p, diag));
}

halo_status halo_validate_source(const char *source, const char *file, halo_shader_kind kind, halo_target target,
                                 halo_diagnostics *diag)
{
    return HALO_WITH_GLSLANG(diag, validate_shader_held(source, file, kind, target, diag));
}
