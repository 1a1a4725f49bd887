/* Validation with glslang's C interface, in process. Every error glslang reports is
 * rewritten to the origin of its line: the module's or the host's own file:line:col. */
#include "diag.h"
#include "glsl_locate.h"
#include "internal.h"
#include "strbuf.h"

#include <glslang/Include/glslang_c_interface.h>
#include <glslang/Public/resource_limits_c.h>
#include <ctype.h>
#include <stdlib.h>
#include <string.h>

static void report_log(const char *log, const char *source, halo_glsl_spots *spots, const halo_line_origin *origins,
                       int origin_count, const char *fallback, halo_diagnostics *diag, int *errors) {
    char *copy = halo_strdup(log ? log : "");
    if (!copy) return;
    int last_line = 0; /* of the last error: a later one there follows from it */
    const char *last_file = NULL;
    for (char *line = strtok(copy, "\n"); line; line = strtok(NULL, "\n")) {
        halo_severity sev;
        const char *rest;
        if (!strncmp(line, "ERROR: ", 7)) { sev = HALO_SEVERITY_ERROR; rest = line + 7; }
        else if (!strncmp(line, "WARNING: ", 9)) { sev = HALO_SEVERITY_WARNING; rest = line + 9; }
        else continue;
        int string_index, out_line = 0, consumed = 0;
        const char *msg = rest;
        if (sscanf(rest, "%d:%d:%n", &string_index, &out_line, &consumed) == 2 && consumed > 0) msg = rest + consumed;
        while (*msg == ' ') msg++;
        for (size_t n = strlen(msg); n > 0 && (msg[n - 1] == ' ' || msg[n - 1] == '\r'); n--) line[msg - line + n - 1] = '\0';
        if (strstr(msg, "compilation errors.") || strstr(msg, "compilation terminated")) continue;
        int column = 0, at_end = 0; /* glsl_locate.c: the token, or after the one before a missing ';' */
        halo_glsl_place(spots, msg, &out_line, &column, &at_end);
        const char *file = fallback;
        int line_no = 0, col = 0, generated_line = 0;
        const char *text = NULL;
        if (out_line >= 1 && out_line <= origin_count) {
            const halo_line_origin *o = &origins[out_line - 1];
            file = o->file;
            line_no = o->line;
            text = o->text;
            col = halo_glsl_original_column(source, out_line, column, at_end, msg, o->text);
            if (o->file == halo_generated_file) { /* no line of the reader's file: say where it is */
                file = fallback;
                line_no = col = 0;
                text = NULL;
                generated_line = out_line;
            }
        }
        if (sev == HALO_SEVERITY_ERROR && *errors && line_no && line_no == last_line && file == last_file &&
            halo_glsl_follows_earlier_error(msg))
            continue; /* one problem, one message */
        if (sev == HALO_SEVERITY_ERROR) last_line = line_no, last_file = file;
        char *message = halo_glsl_message(msg, text);
        halo_diag_add(diag, sev, sev == HALO_SEVERITY_ERROR ? HALO_MSG_GLSL_ERROR : HALO_MSG_GLSL_WARNING, file,
                      line_no, col, text, generated_line ? "%s (in code libhalo wrote: line %d of the linked shader)" : "%s",
                      message ? message : msg, generated_line);
        free(message);
        if (sev == HALO_SEVERITY_ERROR) (*errors)++;
    }
    free(copy);
}

halo_status halo_glslang_validate(const char *source, halo_shader_kind kind, halo_target target,
                                  const halo_line_origin *origins, int origin_count, const char *fallback_file,
                                  halo_diagnostics *diag) {
    (void)target; /* the #version line in the source selects the language */
    glslang_input_t in = {0};
    in.language = GLSLANG_SOURCE_GLSL;
    in.stage = kind == HALO_SHADER_VERTEX ? GLSLANG_STAGE_VERTEX : GLSLANG_STAGE_FRAGMENT;
    in.client = GLSLANG_CLIENT_NONE;
    in.target_language = GLSLANG_TARGET_NONE;
    in.code = source;
    in.default_version = 100;
    in.default_profile = GLSLANG_NO_PROFILE;
    /* Without cascading errors glslang stops at the first statement with an error; with
     * them it goes on, and report_log drops the errors that follow from an earlier one on
     * the same line (halo_glsl_follows_earlier_error): every problem once. */
    in.messages = GLSLANG_MSG_CASCADING_ERRORS_BIT;
    in.resource = glslang_default_resource();
    glslang_shader_t *sh = glslang_shader_create(&in);
    if (!sh) {
        halo_diag_error(diag, OUT_OF_MEMORY, fallback_file, 0, 0, "glslang could not create a shader");
        return HALO_ERROR_IO;
    }
    int errors = 0;
    int ok = glslang_shader_preprocess(sh, &in);
    if (ok) ok = glslang_shader_parse(sh, &in);
    /* glslang 12 gives no columns: where the text has errors, compile it once more with
     * one token per line to find them (glsl_locate.c). */
    halo_glsl_spots spots = {0};
    if (!ok) halo_glsl_locate(&in, &spots);
    report_log(glslang_shader_get_info_log(sh), source, &spots, origins, origin_count, fallback_file, diag, &errors);
    halo_glsl_spots_free(&spots);
    if (ok) {
        /* Linking catches a missing main and interface errors. */
        glslang_program_t *prog = glslang_program_create();
        glslang_program_add_shader(prog, sh);
        if (!glslang_program_link(prog, GLSLANG_MSG_CASCADING_ERRORS_BIT)) {
            report_log(glslang_program_get_info_log(prog), source, NULL, origins, origin_count, fallback_file, diag,
                       &errors);
            if (!errors) {
                halo_diag_error(diag, GLSL_ERROR, fallback_file, 0, 0, "glslang: link failed");
                errors++;
            }
        }
        glslang_program_delete(prog);
    }
    glslang_shader_delete(sh);
    if (!ok && !errors) {
        halo_diag_error(diag, GLSL_ERROR, fallback_file, 0, 0, "glslang rejected the shader");
        errors++;
    }
    return errors ? HALO_ERROR_INPUT : HALO_OK;
}

halo_status halo_program_validate(const halo_program *p, halo_diagnostics *diag) {
    HALO_REFUSE_NULL(diag, p, "program", HALO_ERROR_INPUT);
    halo_status st = halo_glslang_validate(p->source, p->kind, p->target, p->origins, p->origin_count, p->host_file,
                                           diag);
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
static int mentions_annotation(const char *line, const char *word, int anywhere) {
    size_t n = strlen(word);
    for (const char *h = line; h; h = anywhere && *h ? strchr(h + 1, '#') : NULL) {
        int col = halo_annotation_start(h);
        if (col && !strncmp(h + col - 1, word, n) && !isalnum((unsigned char)h[col - 1 + n]) && h[col - 1 + n] != '_')
            return 1;
    }
    return 0;
}

halo_source_kind halo_source_kind_of(const char *source) {
    HALO_REFUSE_NULL(NULL, source, "source", HALO_SOURCE_SHADER);
    char *copy = source ? halo_strdup(source) : NULL;
    char **lines = NULL;
    int n = copy ? halo_split_lines(copy, &lines) : -1;
    halo_source_kind kind = HALO_SOURCE_SHADER;
    for (int i = 0; i < n && kind != HALO_SOURCE_MODULE; i++) {
        if (mentions_annotation(lines[i], "module", 0)) kind = HALO_SOURCE_MODULE;
        else if (mentions_annotation(lines[i], "declarations", 1)) kind = HALO_SOURCE_HOST;
    }
    free(lines);
    free(copy);
    return kind;
}

halo_status halo_validate_shader(const char *source, const char *file, halo_shader_kind kind, halo_target target,
                                 halo_diagnostics *diag) {
    HALO_REFUSE_NULL(diag, source, "source", HALO_ERROR_INPUT);
    if (!file) file = "shader";
    source = halo_skip_bom(source); /* editors write it; glslang would not take it */
    /* A host (it has the marker): link it with no stage, which also checks the contract. */
    char *copy = halo_strdup(source);
    char **lines = NULL;
    int n = copy ? halo_split_lines(copy, &lines) : -1;
    if (n < 0) {
        free(copy);
        halo_diag_error(diag, OUT_OF_MEMORY, file, 0, 0, "out of memory");
        return HALO_ERROR_IO;
    }
    int is_host = halo_source_kind_of(source) == HALO_SOURCE_HOST, version = 0;
    for (int i = 0; i < n; i++) {
        const char *l = lines[i];
        while (*l == ' ' || *l == '\t') l++;
        if (!version && *l == '#' && strstr(l, "version")) version = i + 1;
    }
    halo_status st;
    if (is_host) {
        halo_library empty = {0};
        halo_program *p = halo_link_host(&(halo_link_desc){.library = &empty, .host_source = source, .host_file = file,
                                                      .target = target, .kind = kind},
                                    diag);
        st = p ? halo_program_validate(p, diag) : HALO_ERROR_INPUT;
        halo_program_destroy(p);
    } else {
        /* A plain shader: set the target's #version and validate as is. */
        halo_target t = target == HALO_TARGET_DEFAULT ? HALO_TARGET_GLSL330 : target;
        halo_strbuf b = {0};
        halo_line_origin *origins = calloc((size_t)n + 8, sizeof *origins);
        int count = 0;
        if (!version) {
            halo_strbuf_printf(&b, "%s\n", halo_target_version_line(t));
            origins[count++] = (halo_line_origin){halo_generated_file, 0, NULL};
        }
        for (int i = 0; i < n && origins; i++) {
            if (i + 1 == version) {
                halo_strbuf_printf(&b, "%s\n", halo_target_version_line(t));
                origins[count++] = (halo_line_origin){file, i + 1, lines[i]};
                if (t == HALO_TARGET_ES300) {
                    halo_strbuf_append(&b, "precision highp float;\n");
                    origins[count++] = (halo_line_origin){file, i + 1, lines[i]};
                }
                continue;
            } else {
                halo_strbuf_printf(&b, "%s\n", lines[i]);
            }
            origins[count++] = (halo_line_origin){file, i + 1, lines[i]};
        }
        char *text = halo_strbuf_take(&b);
        st = text && origins ? halo_glslang_validate(text, kind, t, origins, count, file, diag) : HALO_ERROR_IO;
        free(text);
        free(origins);
    }
    free(lines);
    free(copy);
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
static void point_check_host_at_entry(halo_program *p, const halo_module *m) {
    int line = m->module_line;
    for (size_t i = 0; i < m->declared.count; i++)
        if (!strcmp(m->declared.items[i], "apply")) line = m->declared.lines[i];
    for (int i = 0; i < p->origin_count; i++) {
        halo_line_origin *o = &p->origins[i];
        if (o->file == halo_generated_file || !strcmp(o->file, check_host_file))
            *o = (halo_line_origin){m->file, line, line >= 1 && line <= m->line_count ? m->lines[line - 1] : NULL};
    }
}

halo_status halo_module_validate(const halo_library *lib, const halo_module *m, halo_target target,
                                 halo_diagnostics *diag) {
    HALO_REFUSE_NULL(diag, lib, "library", HALO_ERROR_INPUT);
    HALO_REFUSE_NULL(diag, m, "module", HALO_ERROR_INPUT);
    if (m->is_library) {
        /* Every helper, in file order, in a translation unit of its own. */
        halo_strbuf b = {0};
        halo_line_origin *origins = calloc((size_t)m->line_count + 8, sizeof *origins);
        if (!origins) return HALO_ERROR_IO;
        int count = 0;
        halo_target t = target == HALO_TARGET_DEFAULT ? HALO_TARGET_GLSL330 : target;
        halo_strbuf_printf(&b, "%s\n", halo_target_version_line(t));
        origins[count++] = (halo_line_origin){halo_generated_file, 0, NULL};
        if (t == HALO_TARGET_ES300) {
            halo_strbuf_append(&b, "precision highp float;\n");
            origins[count++] = (halo_line_origin){halo_generated_file, 0, NULL};
        }
        for (int i = 0; i < m->line_count; i++) {
            if (m->is_annotation[i]) continue;
            halo_strbuf_printf(&b, "%s\n", m->lines[i]);
            origins[count++] = (halo_line_origin){m->file, i + 1, m->lines[i]};
        }
        halo_strbuf_append(&b, "void main() {}\n");
        origins[count++] = (halo_line_origin){halo_generated_file, 0, NULL};
        char *text = halo_strbuf_take(&b);
        halo_status st = text ? halo_glslang_validate(text, HALO_SHADER_FRAGMENT, t, origins, count, m->file, diag)
                              : HALO_ERROR_IO;
        free(text);
        free(origins);
        return st;
    }
    if (m->hook != HALO_HOOK_SAMPLE) return HALO_OK; /* other hooks are checked by their own hosts */
    halo_scene *scene = halo_scene_create(lib);
    if (!scene) return HALO_ERROR_IO;
    halo_status st = halo_scene_enable(scene, m->name, 1, diag);
    /* Both variants must compile: parameters as constants, and as uniforms. */
    char host[sizeof check_host_source + 32];
    snprintf(host, sizeof host, check_host_source, target == HALO_TARGET_GLSL150 ? "" : "layout(location = 0) ");
    for (int live = 0; live < 2 && st == HALO_OK; live++) {
        halo_program *p = halo_link_host(&(halo_link_desc){.library = lib, .scene = scene, .host_source = host,
                                                      .host_file = check_host_file, .target = target,
                                                      .all_live = live},
                                    diag);
        if (p) point_check_host_at_entry(p, m);
        st = p ? halo_program_validate(p, diag) : HALO_ERROR_INPUT;
        halo_program_destroy(p);
    }
    halo_scene_destroy(scene);
    return st;
}
