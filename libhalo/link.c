/* The linker: scene + modules + host shader → one program, emitting only what the
 * scene needs. A straight pipeline: check the host → resolve and order the stages →
 * gather parameters → emit, each line with its origin. */
#include "diag.h"
#include "host_scan.h"
#include "internal.h"
#include "strbuf.h"

#include <ctype.h>
#include <jansson.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

const char halo_generated_file[] = "<libhalo>";

/* ---- Output with origins ---- */

typedef struct emitter {
    halo_strbuf text;
    halo_line_origin *origins;
    int count, cap;
    int failed;
} emitter;

static void emit(emitter *e, const char *file, int line, const char *original, const char *fmt, ...)
    __attribute__((format(printf, 5, 6)));

static void emit(emitter *e, const char *file, int line, const char *original, const char *fmt, ...) {
    /* fmt may hold several lines: each gets the same origin. */
    halo_strbuf b = {0};
    va_list ap;
    va_start(ap, fmt);
    halo_strbuf_vprintf(&b, fmt, ap);
    va_end(ap);
    if (b.failed || !b.data) { e->failed = 1; halo_strbuf_free(&b); return; }
    for (char *p = b.data;;) {
        char *nl = strchr(p, '\n');
        size_t n = nl ? (size_t)(nl - p) : strlen(p);
        if (e->count == e->cap) {
            int cap = e->cap ? e->cap * 2 : 256;
            halo_line_origin *o = realloc(e->origins, (size_t)cap * sizeof *o);
            if (!o) { e->failed = 1; break; }
            e->origins = o;
            e->cap = cap;
        }
        e->origins[e->count++] = (halo_line_origin){file, line, original};
        halo_strbuf_append_n(&e->text, p, n);
        halo_strbuf_append(&e->text, "\n");
        if (!nl || !nl[1]) break;
        p = nl + 1;
    }
    halo_strbuf_free(&b);
}

#define GEN(e, ...) emit((e), halo_generated_file, 0, NULL, __VA_ARGS__)

/* ---- The host ---- */

static const char *const contract_names[] = {"halo_sample", "halo_make_sample", "halo_apply", "halo_finish",
                                             "halo_line_vertex", "halo_make_line_vertex", "halo_line_fragment",
                                             "halo_make_line_fragment", "HALO_LINKED",
                                             "HALO_CONTRACT_VERSION",
                                             /* host contract 2 */
                                             "halo_segment_begin", "halo_segment_end", "halo_view_at",
                                             "halo_depth_at", "halo_gradient_at", "HALO_RAY_MAY_END", NULL};

typedef struct host_info {
    int version_line; /* 0: none */
    int marker_line;
    int slices;       /* #pragma halo slices: the host draws slices or slabs and runs the passes itself */
    char *volume, *gradient; /* #pragma halo volume NAME / gradient NAME (owned) */
    int volume_line;
    halo_host_scan scan; /* comments, #if branches, #line and macros of the host */
    int compositing_mip; /* #pragma halo compositing mip: the line; the host composites no samples */
} host_info;

/* `#pragma halo volume NAME`, `gradient NAME`, `slices` or `compositing mip`: 1 if the line is one of them
 * (stored in h), 0 if it is another annotation, -1 if it is one of them but malformed. */
static int host_annotation(const char *line, int number, host_info *h) {
    const char *d = line + halo_annotation_start(line) - 1;
    size_t word = strcspn(d, " \t");
    const char *arg = d + word;
    while (*arg == ' ' || *arg == '\t') arg++;
    size_t n = strcspn(arg, " \t");
    int rest = arg[n + strspn(arg + n, " \t")] != '\0';
    if (word == 6 && !strncmp(d, "slices", 6)) {
        if (*arg) return -1;
        h->slices = number;
        return 1;
    }
    if (word == 11 && !strncmp(d, "compositing", 11)) {
        if (n != 3 || strncmp(arg, "mip", 3) || rest) return -1;
        h->compositing_mip = number;
        return 1;
    }
    char **slot = word == 6 && !strncmp(d, "volume", 6) ? &h->volume
                  : word == 8 && !strncmp(d, "gradient", 8) ? &h->gradient : NULL;
    if (!slot) return 0;
    if (!n || rest || !(isalpha((unsigned char)arg[0]) || arg[0] == '_')) return -1;
    for (size_t k = 0; k < n; k++)
        if (!isalnum((unsigned char)arg[k]) && arg[k] != '_') return -1;
    free(*slot);
    *slot = malloc(n + 1);
    if (*slot) { memcpy(*slot, arg, n); (*slot)[n] = '\0'; }
    h->volume_line = number;
    return 1;
}

/* Reports at a host line, where its #line directives say it comes from. */
static void host_diag(const host_info *h, halo_diagnostics *diag, halo_message_id id, const char *host_file,
                      char **lines, int line, int column, const char *fmt, ...) __attribute__((format(printf, 8, 9)));
static void host_diag(const host_info *h, halo_diagnostics *diag, halo_message_id id, const char *host_file,
                      char **lines, int line, int column, const char *fmt, ...) {
    halo_strbuf b = {0};
    va_list ap;
    va_start(ap, fmt);
    halo_strbuf_vprintf(&b, fmt, ap);
    va_end(ap);
    const char *file;
    int origin_line;
    halo_host_scan_origin(&h->scan, host_file, line, &file, &origin_line);
    halo_diag_add(diag, HALO_SEVERITY_ERROR, id, file, origin_line, column, lines[line - 1], "%s",
                  b.data ? b.data : halo_message_name(id));
    halo_strbuf_free(&b);
}

static int is_version_line(const char *l) {
    while (*l == ' ' || *l == '\t') l++;
    if (*l != '#') return 0;
    l++;
    while (*l == ' ' || *l == '\t') l++;
    return !strncmp(l, "version", 7) && !isalnum((unsigned char)l[7]);
}

static int is_marker_line(const char *l) {
    int col = halo_annotation_start(l);
    if (!col) return 0;
    const char *d = l + col - 1;
    if (strncmp(d, "declarations", 12)) return 0;
    for (d += 12; *d; d++)
        if (!isspace((unsigned char)*d)) return 0;
    return 1;
}

/* Marker lines that a compiler never sees: commented out, or in an #if branch not taken. */
static int report_inactive_markers(const host_info *h, const char *file, char **lines, int count,
                                   halo_target target, halo_diagnostics *diag) {
    int errors = 0;
    for (int i = 0; i < count; i++) {
        const halo_host_line_info *l = &h->scan.lines[i];
        if (is_marker_line(h->scan.comment_lines[i])) {
            host_diag(h, diag, HALO_MSG_HOST_MARKER_INACTIVE, file, lines, i + 1, 1,
                      "'#pragma halo declarations' is commented out, so no stage would be linked; remove the "
                      "comment around it");
            errors++;
        } else if (is_marker_line(h->scan.code_lines[i]) && l->activity == HALO_BRANCH_NOT_TAKEN) {
            const char *cfile;
            int cline;
            halo_host_scan_origin(&h->scan, file, l->condition_line, &cfile, &cline);
            host_diag(h, diag, HALO_MSG_HOST_MARKER_INACTIVE, file, lines, i + 1, 1,
                      "'#pragma halo declarations' is in a preprocessor branch not taken for target %s (the "
                      "condition at %s:%d), so no stage would be linked; move it out of the conditional",
                      halo_target_name(target), cfile, cline);
            errors++;
        }
    }
    return errors;
}

static int check_host(const char *file, const char *source, char **lines, int count, host_info *h,
                      halo_target target, halo_diagnostics *diag) {
    int errors = 0;
    h->version_line = h->marker_line = h->slices = h->volume_line = h->compositing_mip = 0;
    h->volume = h->gradient = NULL;
    halo_token_list toks;
    if (halo_lex(source, &toks)) {
        halo_diag_error(diag, OUT_OF_MEMORY, file, 0, 0, "out of memory");
        return 1;
    }
    for (int i = 0; i < count; i++) {
        if (is_version_line(lines[i]) && !h->version_line) h->version_line = i + 1;
        if (!halo_host_scan_compiled(&h->scan, i + 1)) continue;
        if (is_marker_line(h->scan.code_lines[i])) {
            if (h->marker_line) {
                const char *first_file;
                int first_line;
                halo_host_scan_origin(&h->scan, file, h->marker_line, &first_file, &first_line);
                host_diag(h, diag, HALO_MSG_HOST_MARKER_DUPLICATE, file, lines, i + 1, 1,
                          "second '#pragma halo declarations' (the first is at line %d); the host has exactly one",
                          first_line);
                errors++;
                continue;
            }
            h->marker_line = i + 1;
            /* The marker must be at global scope: no open brace before it. */
            int depth = 0;
            for (size_t t = 0; t < toks.count && toks.items[t].line <= i; t++) {
                if (halo_token_is(source, &toks.items[t], "{")) depth++;
                if (halo_token_is(source, &toks.items[t], "}")) depth--;
            }
            if (depth > 0) {
                host_diag(h, diag, HALO_MSG_HOST_MARKER_SCOPE, file, lines, i + 1, 1,
                          "'#pragma halo declarations' is inside a block; put it at global scope, before the "
                          "first function that uses halo_sample");
                errors++;
            }
        } else if (halo_annotation_start(h->scan.code_lines[i])) {
            int col = halo_annotation_start(h->scan.code_lines[i]);
            int known = host_annotation(h->scan.code_lines[i], i + 1, h);
            if (known == 1) continue;
            host_diag(h, diag, known ? HALO_MSG_ANNOTATION_SYNTAX : HALO_MSG_ANNOTATION_UNKNOWN, file, lines, i + 1,
                      col, known ? "'#pragma halo volume' and 'gradient' take one sampler name; 'slices' takes none; "
                                   "'compositing' takes 'mip'"
                                 : "a host shader takes only '#pragma halo declarations', 'volume NAME', "
                                   "'gradient NAME', 'slices' and 'compositing mip' (docs/host-contract.md)");
            errors++;
        }
    }
    int inactive = h->marker_line ? 0 : report_inactive_markers(h, file, lines, count, target, diag);
    errors += inactive;
    if (!h->marker_line && !inactive) {
        int at = h->version_line ? h->version_line : 1;
        host_diag(h, diag, HALO_MSG_HOST_MARKER_MISSING, file, lines, at, 1,
                  "host shader has no '#pragma halo declarations' line; add one at global scope after "
                  "#version (docs/host-contract.md)");
        errors++;
    }
    for (size_t t = 0; t < toks.count; t++) {
        const halo_token *k = &toks.items[t];
        if (k->kind != HALO_TOK_IDENT || k->length < 5) continue;
        const char *s = source + k->offset;
        if (strncmp(s, "halo_", 5) && strncmp(s, "HALO_", 5)) continue;
        if (t > 0 && halo_token_is(source, &toks.items[t - 1], ".")) continue; /* a field */
        int allowed = 0;
        for (int c = 0; contract_names[c]; c++) allowed |= halo_token_is(source, k, contract_names[c]);
        if (allowed) continue;
        host_diag(h, diag, HALO_MSG_HOST_RESERVED_NAME, file, lines, k->line, k->column,
                  "'%.*s' is reserved: names starting with halo_ or HALO_ belong to libhalo (the host may use "
                  "halo_sample, halo_make_sample, halo_apply, halo_finish, HALO_LINKED and HALO_CONTRACT_VERSION)",
                  (int)k->length, s);
        errors++;
    }
    halo_token_list_free(&toks);
    return errors;
}

/* ---- Stage resolution and order ---- */

typedef struct node {
    const halo_module *module;
    const halo_scene_entry *entry; /* NULL: enabled as a dependency */
    double rank;
    int indegree;
    int done;
} node;

static int provides(const halo_module *m, const char *resource) {
    for (size_t i = 0; i < m->provides_count; i++)
        if (!strcmp(m->provides[i].name, resource)) return 1;
    return 0;
}

static int hook_fits(halo_hook hook, halo_shader_kind kind) {
    if (hook == HALO_HOOK_IMAGE) return 1; /* image passes are programs of their own */
    if (kind == HALO_SHADER_VERTEX) return hook == HALO_HOOK_LINE_VERTEX;
    return hook == HALO_HOOK_SAMPLE || hook == HALO_HOOK_LINE_FRAGMENT;
}

/* Returns the ordered stages in *out (count in *out_count), or errors. */
static int resolve(const halo_library *lib, const halo_scene *scene, halo_shader_kind kind, node **out, int *out_count,
                   halo_diagnostics *diag) {
    int errors = 0, n = 0, cap = (int)(scene ? scene->count : 0) + (int)lib->count + 1;
    node *nodes = calloc((size_t)cap, sizeof *nodes);
    if (!nodes) {
        halo_diag_error(diag, OUT_OF_MEMORY, "", 0, 0, "out of memory");
        return 1;
    }
    for (size_t i = 0; scene && i < scene->count; i++) {
        if (!scene->stages[i].enabled) continue;
        /* One line scene serves both shaders of a line host: each takes its own hook. */
        halo_hook hook = scene->stages[i].module->hook;
        if ((hook == HALO_HOOK_LINE_VERTEX && kind == HALO_SHADER_FRAGMENT) ||
            (hook == HALO_HOOK_LINE_FRAGMENT && kind == HALO_SHADER_VERTEX))
            continue;
        nodes[n++] = (node){scene->stages[i].module, &scene->stages[i], (double)i, 0, 0};
    }
    /* Enable providers of what the stages need. */
    for (int i = 0; i < n; i++) {
        const halo_module *m = nodes[i].module;
        for (size_t r = 0; r < m->needs.count; r++) {
            const char *res = m->needs.items[r];
            if (halo_is_host_resource(res)) continue;
            int have = 0;
            for (int j = 0; j < n; j++) have |= provides(nodes[j].module, res);
            if (have) continue;
            const halo_module *found = NULL;
            int candidates = 0;
            for (size_t k = 0; k < lib->count; k++)
                if (provides(lib->modules[k], res)) {
                    candidates++;
                    if (!found) found = lib->modules[k];
                }
            if (candidates == 0) {
                halo_diag_add(diag, HALO_SEVERITY_ERROR, HALO_MSG_LINK_MISSING_PROVIDER, m->file, m->needs.lines[r], 1,
                              m->lines[m->needs.lines[r] - 1],
                              "stage '%s' needs '%s', which neither the host nor any module provides", m->name, res);
                errors++;
            } else if (candidates > 1) {
                halo_diag_add(diag, HALO_SEVERITY_ERROR, HALO_MSG_LINK_DUPLICATE_PROVIDER, m->file, m->needs.lines[r],
                              1, m->lines[m->needs.lines[r] - 1],
                              "stage '%s' needs '%s', which %d modules provide; enable the one to use in the scene",
                              m->name, res, candidates);
                errors++;
            } else if (n < cap) {
                nodes[n++] = (node){found, NULL, nodes[i].rank - 0.5, 0, 0};
            }
        }
    }
    /* Each resource has one provider; each stage fits the host. */
    for (int i = 0; i < n; i++) {
        const halo_module *m = nodes[i].module;
        if (!hook_fits(m->hook, kind)) {
            halo_diag_add(diag, HALO_SEVERITY_ERROR, HALO_MSG_LINK_HOOK_MISMATCH, m->file, m->hook_line, 1,
                          m->lines[m->hook_line - 1], "stage '%s' runs at a hook that a %s host cannot place", m->name,
                          kind == HALO_SHADER_VERTEX ? "vertex" : "fragment");
            errors++;
        }
        for (size_t p = 0; p < m->provides_count; p++)
            for (int j = 0; j < i; j++)
                if (provides(nodes[j].module, m->provides[p].name)) {
                    halo_diag_add(diag, HALO_SEVERITY_ERROR, HALO_MSG_LINK_DUPLICATE_PROVIDER, m->file,
                                  m->provides[p].line, 1, m->lines[m->provides[p].line - 1],
                                  "stages '%s' and '%s' both provide '%s'; enable only one", nodes[j].module->name,
                                  m->name, m->provides[p].name);
                    errors++;
                }
    }
    if (errors) {
        free(nodes);
        return errors;
    }
    /* Edges: provider → needer, and `after` between enabled stages. */
    unsigned char *edge = calloc((size_t)n * (size_t)n + 1, 1);
    node *order = calloc((size_t)n + 1, sizeof *order);
    if (!edge || !order) {
        free(edge);
        free(order);
        free(nodes);
        halo_diag_error(diag, OUT_OF_MEMORY, "", 0, 0, "out of memory");
        return 1;
    }
    for (int a = 0; a < n; a++) {
        const halo_module *m = nodes[a].module;
        for (int b = 0; b < n; b++) {
            if (a == b) continue;
            int before = 0;
            for (size_t r = 0; r < m->needs.count; r++) before |= provides(nodes[b].module, m->needs.items[r]);
            before |= halo_name_list_has(&m->after, halo_module_name(nodes[b].module));
            if (before && !edge[b * n + a]) {
                edge[b * n + a] = 1;
                nodes[a].indegree++;
            }
        }
    }
    int placed = 0;
    while (placed < n) {
        int best = -1;
        for (int i = 0; i < n; i++) {
            if (nodes[i].done || nodes[i].indegree) continue;
            if (best < 0 || nodes[i].rank < nodes[best].rank ||
                (nodes[i].rank == nodes[best].rank &&
                 strcmp(halo_module_name(nodes[i].module), halo_module_name(nodes[best].module)) < 0))
                best = i;
        }
        if (best < 0) break;
        nodes[best].done = 1;
        order[placed++] = nodes[best];
        for (int j = 0; j < n; j++)
            if (edge[best * n + j]) nodes[j].indegree--;
    }
    if (placed < n) {
        halo_strbuf names = {0};
        const halo_module *first = NULL;
        for (int i = 0; i < n; i++)
            if (!nodes[i].done) {
                halo_strbuf_printf(&names, "%s%s", first ? ", " : "", halo_module_name(nodes[i].module));
                if (!first) first = nodes[i].module;
            }
        int line = first->after.count ? first->after.lines[0] : first->needs.count ? first->needs.lines[0]
                                                                                     : first->module_line;
        halo_diag_add(diag, HALO_SEVERITY_ERROR, HALO_MSG_LINK_CYCLE, first->file, line, 1, first->lines[line - 1],
                      "the 'needs' and 'after' annotations of these stages form a cycle: %s",
                      names.data ? names.data : "");
        halo_strbuf_free(&names);
        errors++;
    }
    free(edge);
    free(nodes);
    if (errors) {
        free(order);
        return errors;
    }
    *out = order;
    *out_count = n;
    return 0;
}

/* ---- Emission ---- */

static void format_number(char *buf, size_t len, double v, halo_param_type t) {
    if (t == HALO_PARAM_INT) {
        snprintf(buf, len, "%d", (int)v);
        return;
    }
    if (t == HALO_PARAM_BOOL) {
        snprintf(buf, len, "%s", v != 0 ? "true" : "false");
        return;
    }
    snprintf(buf, len, "%.9g", v);
    if (!strpbrk(buf, ".e")) strncat(buf, ".0", len - strlen(buf) - 1);
}

static void format_element(halo_strbuf *b, const halo_param_info *info, const double *v) {
    char num[64];
    if (info->components == 1) {
        format_number(num, sizeof num, v[0], info->type);
        halo_strbuf_append(b, num);
        return;
    }
    halo_strbuf_printf(b, "%s(", halo_param_type_name(info->type));
    for (int c = 0; c < info->components; c++) {
        format_number(num, sizeof num, v[c], info->type);
        halo_strbuf_printf(b, "%s%s", c ? ", " : "", num);
    }
    halo_strbuf_append(b, ")");
}

/* Is name used (as an identifier, not a field) in the module's code? */
int halo_module_uses(const halo_module *m, const char *name) {
    for (size_t i = 0; i < m->tokens.count; i++) {
        const halo_token *t = &m->tokens.items[i];
        if (t->kind == HALO_TOK_IDENT && halo_token_is(m->source, t, name) &&
            !(i > 0 && halo_token_is(m->source, &m->tokens.items[i - 1], ".")))
            return 1;
    }
    return 0;
}

/* engine: the program's live parameters are declared by the engine (not in image passes) */
static void emit_params(emitter *e, const halo_program *p, const halo_linked_stage *st, int engine) {
    const halo_module *m = st->module;
    for (size_t i = 0; i < m->param_count; i++) {
        const halo_param_info *info = &m->params[i];
        const halo_uniform_info *u = &p->uniforms[st->first_uniform + i];
        char count_name[160];
        snprintf(count_name, sizeof count_name, "%s_count", info->name);
        int used = halo_module_uses(m, info->name), count_used = info->array_size && halo_module_uses(m, count_name);
        if (!used && !count_used) continue;
        const char *type = halo_param_type_name(info->type);
        int line = m->param_lines[i];
        const char *orig = m->lines[line - 1];
        if (u->live && engine) {
            /* declared by the engine from the reflection (halo_program_uniform_next) */
            emit(e, m->file, line, orig, "// uniform %s %s%s; (declared by the engine%s)",
                 info->type == HALO_PARAM_BOOL ? "int" : info->type == HALO_PARAM_CHANNELS ? "halo_channels" : type,
                 u->name, info->array_size && used ? "[]" : "", count_used ? ", with NAME_count" : "");
            continue;
        }
        if (u->live) {
            if (info->type == HALO_PARAM_CHANNELS) {
                emit(e, m->file, line, orig, "uniform halo_channels %s;", u->name);
            } else if (info->array_size) {
                if (used) emit(e, m->file, line, orig, "uniform %s %s[%d];", type, u->name, info->array_size);
                if (count_used) emit(e, m->file, line, orig, "uniform int %s_count;", u->name);
            } else {
                emit(e, m->file, line, orig, "uniform %s %s;", type, u->name);
            }
            continue;
        }
        halo_strbuf b = {0};
        if (info->type == HALO_PARAM_CHANNELS) {
            static const char *const ctor[] = {"float", "float", "vec2", "vec3", "vec4"};
            halo_strbuf_printf(&b, "const halo_channels %s = %s(", u->name, ctor[p->channel_count]);
            for (int k = 0; k < p->channel_count; k++) {
                char num[64];
                format_number(num, sizeof num, u->value[k < u->count ? k : u->count - 1], HALO_PARAM_FLOAT);
                halo_strbuf_printf(&b, "%s%s", k ? ", " : "", num);
            }
            halo_strbuf_append(&b, ");");
        } else if (info->array_size) {
            if (count_used) emit(e, m->file, line, orig, "const int %s_count = %d;", u->name, u->count);
            if (!used) continue;
            halo_strbuf_printf(&b, "const %s %s[%d] = %s[%d](", type, u->name, u->count, type, u->count);
            for (int k = 0; k < u->count; k++) {
                if (k) halo_strbuf_append(&b, ", ");
                format_element(&b, info, u->value + k * info->components);
            }
            halo_strbuf_append(&b, ");");
        } else {
            halo_strbuf_printf(&b, "const %s %s = ", type, u->name);
            format_element(&b, info, u->value);
            halo_strbuf_append(&b, ";");
        }
        if (b.data) emit(e, m->file, line, orig, "%s", b.data);
        else e->failed = 1;
        halo_strbuf_free(&b);
    }
}

/* Copies lines [first, last] of m, renaming its private names and parameters. engine: a
 * program whose live parameters the engine declares, a bool one as int (read as
 * (NAME != 0)). */
static void emit_module_lines(emitter *e, const halo_module *m, int first, int last, int rename,
                              const halo_program *engine) {
    size_t t = 0;
    for (int li = first; li <= last && li <= m->line_count; li++) {
        if (m->is_annotation[li - 1]) continue;
        const char *line = m->lines[li - 1];
        size_t start = (size_t)(line - m->line_storage), len = strlen(line);
        const char *p = line;
        while (*p == ' ' || *p == '\t') p++;
        if (!*p) continue;
        halo_strbuf b = {0};
        size_t pos = start;
        while (t < m->tokens.count && m->tokens.items[t].offset < start) t++;
        for (; t < m->tokens.count && m->tokens.items[t].offset < start + len; t++) {
            const halo_token *k = &m->tokens.items[t];
            if (!rename || k->kind != HALO_TOK_IDENT) continue;
            if (t > 0 && halo_token_is(m->source, &m->tokens.items[t - 1], ".")) continue;
            char name[160];
            size_t n = k->length < sizeof name - 8 ? k->length : sizeof name - 8;
            memcpy(name, m->source + k->offset, n);
            name[n] = '\0';
            const char *base = name;
            int is_count = 0;
            if (n > 6 && !strcmp(name + n - 6, "_count")) {
                char stem[160];
                memcpy(stem, name, n - 6);
                stem[n - 6] = '\0';
                const halo_param_info *pi = halo_module_find_param(m, stem);
                is_count = pi && pi->array_size;
            }
            if (!is_count && !halo_name_list_has(&m->declared, base) && !halo_module_find_param(m, base)) continue;
            halo_strbuf_append_n(&b, m->source + pos, k->offset - pos);
            const halo_param_info *pi = engine && !is_count ? halo_module_find_param(m, base) : NULL;
            const halo_uniform_info *u = pi ? halo_program_find_uniform(engine, m->name, base) : NULL;
            if (pi && pi->type == HALO_PARAM_BOOL && u && u->live)
                halo_strbuf_printf(&b, "(halo_%s_%s != 0)", m->name, name);
            else
                halo_strbuf_printf(&b, "halo_%s_%s", m->name, name);
            pos = k->offset + k->length;
        }
        halo_strbuf_append_n(&b, m->source + pos, start + len - pos);
        if (b.data) {
            /* Strip a trailing \r kept by the copy. */
            if (b.len && b.data[b.len - 1] == '\r') b.data[--b.len] = '\0';
            emit(e, m->file, li, line, "%s", b.data);
        } else {
            e->failed = 1;
        }
        halo_strbuf_free(&b);
    }
}

static void emit_helpers(emitter *e, const halo_library *lib, const halo_program *p) {
    const halo_module *h = halo_library_helpers(lib);
    if (!h || !h->chunk_count) return;
    unsigned char *need = calloc(h->chunk_count, 1);
    if (!need) { e->failed = 1; return; }
    for (size_t c = 0; c < h->chunk_count; c++)
        for (size_t s = 0; s < p->stage_count; s++)
            if (halo_name_list_has(&p->stages[s].module->calls, h->chunks[c].name)) need[c] = 1;
    for (int changed = 1; changed;) {
        changed = 0;
        for (size_t c = 0; c < h->chunk_count; c++) {
            if (!need[c]) continue;
            for (size_t d = 0; d < h->chunk_count; d++)
                if (!need[d] && halo_name_list_has(&h->chunks[c].calls, h->chunks[d].name)) need[d] = changed = 1;
        }
    }
    for (size_t c = 0; c < h->chunk_count; c++)
        if (need[c]) emit_module_lines(e, h, h->chunks[c].first_line, h->chunks[c].last_line, 0, NULL);
    free(need);
}

/* A struct is emitted when a linked stage runs at its hook or the host names it. */
static int hook_needed(const halo_program *p, const halo_hook_struct *hs, const char *host) {
    for (size_t s = 0; s < p->stage_count; s++)
        if (p->stages[s].module->hook == hs->hook) return 1;
    if (hs->hook == HALO_HOOK_SAMPLE && p->kind == HALO_SHADER_FRAGMENT && !strstr(host, "halo_line_fragment"))
        return 1; /* the classic host: halo_sample and halo_apply always exist */
    return strstr(host, hs->type) != NULL;
}

/* Does any linked stage use per-halo channels? */
static int uses_channels(const halo_program *p) {
    if (p->image_count || p->output_count || p->sampler_count) return 1;
    for (size_t s = 0; s < p->stage_count; s++) {
        const halo_module *m = p->stages[s].module;
        for (size_t i = 0; i < m->calls.count; i++)
            if (!strncmp(m->calls.items[i], "halo_channel", 12)) return 1;
        for (size_t i = 0; i < m->param_count; i++)
            if (m->params[i].type == HALO_PARAM_CHANNELS) return 1;
    }
    return 0;
}

static void emit_channel_definitions(emitter *e, int c) {
    static const char *const type[] = {"float", "float", "vec2", "vec3", "vec4"};
    static const char *const from[] = {"v.x", "v.x", "v.xy", "v.xyz", "v"};
    static const char *const to[] = {"vec4(v, 0.0, 0.0, 0.0)", "vec4(v, 0.0, 0.0, 0.0)", "vec4(v, 0.0, 0.0)",
                                     "vec4(v, 0.0)", "v"};
    GEN(e, "#define halo_channels %s\nconst int halo_channel_count = %d;", type[c], c);
    GEN(e, "float halo_channel(halo_channels v, int i) { return %s; }", c == 1 ? "v" : "v[i]");
    GEN(e, "halo_channels halo_channels_from(vec4 v) { return %s; }", from[c]);
    GEN(e, "vec4 halo_channels_to_vec4(halo_channels v) { return %s; }", to[c]);
}

/* GLSL type of an output: the program's halo_channels, or float/vecN for a fixed size. */
static const char *output_type(const halo_program *p, const halo_output_info *out) {
    static const char *const types[] = {"float", "float", "vec2", "vec3", "vec4"};
    if (out->channel < 0 && out->components == p->channel_count) return "halo_channels";
    return types[out->components < 1 ? 1 : out->components > 4 ? 4 : out->components];
}

static halo_image_info *find_image(halo_program *p, const char *name);

static void emit_declarations(emitter *e, const halo_program *p, const char *host) {
    GEN(e, "#define HALO_LINKED 1\n#define HALO_CONTRACT_VERSION %d", HALO_CONTRACT_VERSION);
    /* host contract 2: stages with extra outputs (seeds, feature buffers) read every sample
     * of a ray, hidden ones too, as the slice host gives them: the host's early ray
     * termination waits for this */
    GEN(e, "#define HALO_RAY_MAY_END %d", p->output_count == 0);
    if (uses_channels(p)) emit_channel_definitions(e, p->channel_count);
    for (size_t h = 0; h < halo_hook_struct_count; h++) {
        const halo_hook_struct *hs = &halo_hook_structs[h];
        if (!hook_needed(p, hs, host)) continue;
        GEN(e, "struct %s {", hs->type);
        for (int i = 0; i < hs->field_count; i++) GEN(e, "    %s %s;", hs->fields[i][0], hs->fields[i][1]);
        for (size_t s = 0; s < p->stage_count; s++) {
            const halo_module *m = p->stages[s].module;
            if (m->hook != hs->hook) continue;
            for (size_t r = 0; r < m->provides_count; r++)
                emit(e, m->file, m->provides[r].line, m->lines[m->provides[r].line - 1], "    %s %s;",
                     m->provides[r].type, m->provides[r].name);
        }
        GEN(e, "};");
        halo_strbuf sig = {0};
        for (int i = 0; i < hs->field_count; i++)
            halo_strbuf_printf(&sig, "%s%s %s", i ? ", " : "", hs->fields[i][0], hs->fields[i][1]);
        GEN(e, "%s %s(%s) {\n    %s %s;", hs->type, hs->make, sig.data ? sig.data : "", hs->type, hs->var);
        halo_strbuf_free(&sig);
        for (int i = 0; i < hs->field_count; i++) GEN(e, "    %s.%s = %s;", hs->var, hs->fields[i][1], hs->fields[i][1]);
        for (size_t s = 0; s < p->stage_count; s++) {
            const halo_module *m = p->stages[s].module;
            if (m->hook != hs->hook) continue;
            for (size_t r = 0; r < m->provides_count; r++) {
                const char *t = m->provides[r].type;
                char zero[32];
                if (!strncmp(t, "vec", 3) || !strncmp(t, "mat", 3) || !strcmp(t, "halo_channels"))
                    snprintf(zero, sizeof zero, "%s(0.0)", t);
                else snprintf(zero, sizeof zero, "%s", !strcmp(t, "int") ? "0" : !strcmp(t, "bool") ? "false" : "0.0");
                GEN(e, "    %s.%s = %s;", hs->var, m->provides[r].name, zero);
            }
        }
        GEN(e, "    return %s;\n}", hs->var);
    }
    for (size_t o = 0; o < p->output_count; o++) {
        const halo_output_info *out = &p->outputs[o];
        const char *type = output_type(p, out);
        char layout[48];
        GEN(e, "%sout %s %s;", halo_output_layout(p, out->location, layout, sizeof layout), type, out->name);
        GEN(e, "%s halo_accum_%s = %s(%s);", type, out->image, type, out->blend == HALO_BLEND_MIN ? "1.0" : "0.0");
    }
    for (size_t i = 0; i < p->sampler_count; i++) {
        const halo_sampler_info *sm = &p->samplers[i];
        GEN(e, "uniform highp sampler2D %s;", sm->name);
        const halo_image_info *im = find_image((halo_program *)p, sm->image);
        int scale = im ? im->scale : 1;
        if (scale > 1)
            /* a 1/scale image: bilinear between its four nearest pixel centres (clamped to
             * the image), written out so that the emulation can match it */
            GEN(e, "halo_channels halo_read_%s(vec2 fragcoord) {\n"
                   "    ivec2 size = textureSize(%s, 0);\n"
                   "    ivec2 pixel = ivec2(fragcoord);\n"
                   "    if (any(lessThan(pixel, ivec2(0))) || any(greaterThanEqual(pixel, size * %d)))\n"
                   "        return halo_channels(0.0);\n"
                   "    vec2 at = fragcoord * (1.0 / %d.0) - 0.5;\n"
                   "    vec2 corner = floor(at);\n"
                   "    vec2 t = at - corner;\n"
                   "    ivec2 p0 = clamp(ivec2(corner), ivec2(0), size - 1), p1 = clamp(ivec2(corner) + 1, ivec2(0), size - 1);\n"
                   "    vec4 bottom = mix(texelFetch(%s, p0, 0), texelFetch(%s, ivec2(p1.x, p0.y), 0), t.x);\n"
                   "    vec4 top = mix(texelFetch(%s, ivec2(p0.x, p1.y), 0), texelFetch(%s, p1, 0), t.x);\n"
                   "    return halo_channels_from(mix(bottom, top, t.y));\n}",
                sm->image, sm->name, scale, scale, sm->name, sm->name, sm->name, sm->name);
        else
            GEN(e, "halo_channels halo_read_%s(vec2 fragcoord) {\n"
                   "    ivec2 pixel = ivec2(fragcoord);\n"
                   "    if (any(lessThan(pixel, ivec2(0))) || any(greaterThanEqual(pixel, textureSize(%s, 0))))\n"
                   "        return halo_channels(0.0);\n"
                   "    return halo_channels_from(texelFetch(%s, pixel, 0));\n}",
                sm->image, sm->name, sm->name);
    }
    for (size_t i = 0; i < p->host_uniform_count; i++)
        GEN(e, "uniform %s%s %s;", strncmp(p->host_uniforms[i].type, "sampler", 7) ? "" : "highp ",
            p->host_uniforms[i].type, p->host_uniforms[i].name);
}

/* Emits generated text written by fn (nothing when it writes none). */
static void emit_text(emitter *e, const halo_program *p, void (*fn)(halo_strbuf *, const halo_program *)) {
    halo_strbuf b = {0};
    fn(&b, p);
    if (b.failed) e->failed = 1;
    else if (b.len) GEN(e, "%s", b.data);
    halo_strbuf_free(&b);
}

static int emit_program(halo_program *p, const char *host_source, char **host_lines, int host_count,
                        const host_info *h, const halo_library *lib) {
    emitter e = {0};
    const char *ver = halo_target_version_line(p->target);
    int es = p->target == HALO_TARGET_ES300;
    const char *precision = p->kind == HALO_SHADER_FRAGMENT
                                ? "precision highp float;\nprecision highp int;\nprecision highp sampler2D;\n"
                                  "precision highp sampler3D;"
                                : "precision highp float;\nprecision highp int;";
    if (!h->version_line && p->version == HALO_VERSION_TARGET) {
        GEN(&e, "%s", ver);
        if (es) GEN(&e, "%s", precision);
    }
    for (int i = 0; i < host_count; i++) {
        const char *line = host_lines[i];
        if (i + 1 == h->version_line) {
            if (p->version == HALO_VERSION_NONE) emit(&e, p->host_file, i + 1, line, "// %s (no #version: the engine adds its own)", line);
            else emit(&e, p->host_file, i + 1, line, "%s", p->version == HALO_VERSION_KEEP ? line : ver);
            if (es) emit(&e, p->host_file, i + 1, line, "%s", precision);
            continue;
        }
        if (i + 1 != h->marker_line) {
            emit(&e, p->host_file, i + 1, line, "%s", line);
            continue;
        }
        emit(&e, p->host_file, i + 1, line, "// ---- libhalo %s: %zu stage%s (contract %d) ----", PACKAGE_VERSION,
             p->stage_count, p->stage_count == 1 ? "" : "s", HALO_CONTRACT_VERSION);
        emit_declarations(&e, p, host_source);
        emit_helpers(&e, lib, p);
        for (size_t s = 0; s < p->stage_count; s++) {
            const halo_module *m = p->stages[s].module;
            if (m->hook == HALO_HOOK_IMAGE) continue;
            emit(&e, m->file, m->module_line, m->lines[m->module_line - 1], "// stage %s (%s)", m->name, m->file);
            emit_params(&e, p, &p->stages[s], p->engine_uniforms);
            emit_module_lines(&e, m, 1, m->line_count, 1, p->engine_uniforms ? p : NULL);
        }
        for (size_t h = 0; h < halo_hook_struct_count; h++) {
            const halo_hook_struct *hs = &halo_hook_structs[h];
            if (!hook_needed(p, hs, host_source)) continue;
            GEN(&e, "void halo_apply(inout %s %s) {", hs->type, hs->var);
            for (size_t s = 0; s < p->stage_count; s++)
                if (p->stages[s].module->hook == hs->hook)
                    GEN(&e, "    halo_%s_apply(%s);", p->stages[s].module->name, hs->var);
            for (size_t o = 0; o < p->output_count && hs->hook == HALO_HOOK_SAMPLE; o++) {
                const halo_output_info *out = &p->outputs[o];
                const char *img = out->image;
                char field[160];
                if (out->channel >= 0) snprintf(field, sizeof field, "s.%s[%d]", out->field, out->channel);
                else snprintf(field, sizeof field, "s.%s", out->field);
                if (out->blend == HALO_BLEND_MAX)
                    GEN(&e, "    halo_accum_%s = max(halo_accum_%s, %s);", img, img, field);
                else if (out->blend == HALO_BLEND_MIN)
                    GEN(&e, "    halo_accum_%s = min(halo_accum_%s, %s);", img, img, field);
                else if (out->blend == HALO_BLEND_FIRST) /* the first hit of the fragment wins */
                    GEN(&e, "    if (halo_accum_%s.a <= 0.0) halo_accum_%s = %s;", img, img, field);
                else
                    GEN(&e, "    halo_accum_%s += %s;", img, field);
            }
            GEN(&e, "}");
        }
        GEN(&e, "void halo_finish() {");
        for (size_t o = 0; o < p->output_count; o++)
            GEN(&e, "    %s = halo_accum_%s;", p->outputs[o].name, p->outputs[o].image);
        GEN(&e, "}");
        emit_text(&e, p, halo_segment_emit);
        emit(&e, p->host_file, i + 1, line, "// ---- end of libhalo declarations ----");
    }
    emit_text(&e, p, halo_segment_emit_tail);
    if (e.failed || e.text.failed) {
        halo_strbuf_free(&e.text);
        free(e.origins);
        return -1;
    }
    p->source = halo_strbuf_take(&e.text);
    p->origins = e.origins;
    p->origin_count = e.count;
    return p->source ? 0 : -1;
}


/* ---- Channels, images and passes (docs/image-passes.md) ---- */

static int is_per_halo(const halo_module *m, size_t i) {
    return m->params[i].type == HALO_PARAM_CHANNELS || halo_name_list_has(&m->per_halo, m->params[i].name);
}

/* The channel count is the longest per-halo list; shorter ones repeat their last element. */
static void set_channel_count(halo_program *p) {
    int c = 1;
    for (size_t s = 0; s < p->stage_count; s++)
        for (size_t i = 0; i < p->stages[s].module->param_count; i++)
            if (is_per_halo(p->stages[s].module, i) && p->stages[s].values[i].count > c)
                c = p->stages[s].values[i].count;
    if (c > 4) c = 4;
    p->channel_count = c;
    for (size_t s = 0; s < p->stage_count; s++) {
        const halo_module *m = p->stages[s].module;
        for (size_t i = 0; i < m->param_count; i++) {
            if (!is_per_halo(m, i)) continue;
            halo_param_value *v = &p->stages[s].values[i];
            int comps = m->params[i].components, max = m->params[i].array_size;
            int target = c < max ? c : max;
            for (int k = v->count; k < target; k++)
                memcpy(v->value + k * comps, v->value + (v->count - 1) * comps, (size_t)comps * sizeof(double));
            if (v->count < target) v->count = target;
            p->uniforms[p->stages[s].first_uniform + i].count = v->count;
        }
    }
}

char *halo_program_own(halo_program *p, const char *fmt, ...) {
    halo_strbuf b = {0};
    va_list ap;
    va_start(ap, fmt);
    halo_strbuf_vprintf(&b, fmt, ap);
    va_end(ap);
    char *str = halo_strbuf_take(&b);
    char **list = str ? realloc(p->strings, (p->string_count + 1) * sizeof *list) : NULL;
    if (!list) { free(str); return NULL; }
    p->strings = list;
    p->strings[p->string_count++] = str;
    return str;
}

static halo_image_info *find_image(halo_program *p, const char *name) {
    for (size_t i = 0; i < p->image_count; i++)
        if (!strcmp(p->images[i].name, name)) return &p->images[i];
    return NULL;
}

/* components 0: the program's channel count. A second declaration keeps the first's size
 * and clear value unless it is the first to give them (clear_set). */
static int add_image(halo_program *p, const char *name, halo_image_reset reset, int components, double clear,
                     int clear_set) {
    halo_image_info *im = find_image(p, name);
    if (im) {
        if (reset == HALO_RESET_GENERATION) im->reset = reset;
        if (clear_set) im->clear = clear;
        return 0;
    }
    halo_image_info *list = realloc(p->images, (p->image_count + 1) * sizeof *list);
    if (!list) return -1;
    p->images = list;
    int host = !strcmp(name, "host_color");
    list[p->image_count++] = (halo_image_info){halo_program_own(p, "%s", name), host ? 4 : components ? components : p->channel_count,
                                               reset, clear, host, 1};
    return 0;
}

/* Image names of a declaration: NAME, or NAME_0 .. NAME_{c-1} for a family. */
static int add_image_decl(halo_program *p, const halo_image_decl *d) {
    if (!d->family) return add_image(p, d->name, d->reset, d->components, d->clear, d->clear_set);
    for (int k = 0; k < p->channel_count; k++) {
        char name[160];
        snprintf(name, sizeof name, "%s_%d", d->name, k);
        if (add_image(p, name, d->reset, d->components, d->clear, d->clear_set)) return -1;
    }
    return 0;
}

/* Components of a provided field's GLSL type; 0 if it cannot be an output. */
static int field_components(const halo_program *p, const char *type, int *per_channel) {
    *per_channel = 0;
    if (!strcmp(type, "halo_channels")) return p->channel_count;
    if (!strcmp(type, "float")) return 1;
    if (!strcmp(type, "vec2")) return 2;
    if (!strcmp(type, "vec3")) return 3;
    if (!strcmp(type, "vec4")) return 4;
    if (!strcmp(type, "mat4")) { *per_channel = 1; return 4; }
    return 0;
}

/* The first fragment output location the host does not declare. */
static int first_free_location(const char *host) {
    halo_token_list t;
    int max = 0; /* location 0: the host's colour, declared or implied */
    if (halo_lex(host, &t)) return 1;
    for (size_t i = 0; i + 2 < t.count; i++)
        if (halo_token_is(host, &t.items[i], "location") && halo_token_is(host, &t.items[i + 1], "=") &&
            t.items[i + 2].kind == HALO_TOK_NUMBER) {
            int loc = atoi(host + t.items[i + 2].offset);
            if (loc > max) max = loc;
        }
    halo_token_list_free(&t);
    return max + 1;
}

static int collect_resources(halo_program *p, const char *host, halo_diagnostics *diag) {
    int errors = 0, location = p->first_location > 0 ? p->first_location : first_free_location(host);
    for (size_t s = 0; s < p->stage_count; s++) {
        const halo_module *m = p->stages[s].module;
        for (size_t i = 0; i < m->image_count && m->hook == HALO_HOOK_IMAGE; i++)
            if (add_image_decl(p, &m->images[i])) return -1;
    }
    for (size_t s = 0; s < p->stage_count; s++) {
        const halo_module *m = p->stages[s].module;
        for (size_t o = 0; o < m->output_count; o++) {
            const halo_output_decl *od = &m->outputs[o];
            const char *type = NULL;
            for (size_t r = 0; r < m->provides_count; r++)
                if (!strcmp(m->provides[r].name, od->name)) type = m->provides[r].type;
            int per_channel = 0, components = type ? field_components(p, type, &per_channel) : 0;
            if (!type || m->hook != HALO_HOOK_SAMPLE || !components ||
                (od->blend == HALO_BLEND_FIRST && components != 4)) {
                halo_diag_add(diag, HALO_SEVERITY_ERROR, HALO_MSG_PASS_INVALID, m->file, od->line, 1,
                              m->lines[od->line - 1],
                              "output '%s' must be a field the sample stage provides, of type channels, float, "
                              "vec2..vec4 or mat4 (one vec4 column per channel); a 'first' output needs vec4 or mat4",
                              od->name);
                errors++;
                continue;
            }
            int n = per_channel ? p->channel_count : 1;
            for (int k = 0; k < n; k++) {
                char *image = per_channel ? halo_program_own(p, "%s_%d", od->name, k) : halo_program_own(p, "%s", od->name);
                halo_output_info *list = realloc(p->outputs, (p->output_count + 1) * sizeof *list);
                if (!list || !image) return -1;
                p->outputs = list;
                if (add_image(p, image, HALO_RESET_FRAME, components, od->blend == HALO_BLEND_MIN ? 1.0 : 0.0,
                              !find_image(p, image)))
                    return -1;
                list[p->output_count++] = (halo_output_info){halo_program_own(p, "halo_output_%s", image), location++, components,
                                                             image, od->blend, halo_program_own(p, "%s", od->name),
                                                             per_channel ? k : -1};
            }
        }
        for (size_t i = 0; i < m->image_count && m->hook == HALO_HOOK_SAMPLE; i++) {
            const char *name = m->images[i].name;
            int known = find_image(p, name) != NULL;
            for (size_t k = 0; k < p->sampler_count; k++) known |= !strcmp(p->samplers[k].image, name) * 2;
            if (known == 0) {
                halo_diag_add(diag, HALO_SEVERITY_ERROR, HALO_MSG_LINK_MISSING_PROVIDER, m->file, m->images[i].line,
                              1, m->lines[m->images[i].line - 1],
                              "stage '%s' reads image '%s', which no linked stage produces", m->name, name);
                errors++;
                continue;
            }
            if (known >= 2) continue;
            halo_sampler_info *list = realloc(p->samplers, (p->sampler_count + 1) * sizeof *list);
            if (!list) return -1;
            p->samplers = list;
            list[p->sampler_count++] = (halo_sampler_info){halo_program_own(p, "halo_image_%s", name), halo_program_own(p, "%s", name)};
        }
        for (size_t i = 0; i < m->host_uniform_count; i++) {
            const halo_host_uniform_decl *hu = &m->host_uniforms[i];
            char *name = halo_program_own(p, "halo_host_%s", hu->name);
            int dup = 0;
            for (size_t k = 0; k < p->host_uniform_count; k++) dup |= !strcmp(p->host_uniforms[k].name, name);
            if (dup) continue;
            halo_host_uniform_info *list = realloc(p->host_uniforms, (p->host_uniform_count + 1) * sizeof *list);
            if (!list) return -1;
            p->host_uniforms = list;
            list[p->host_uniform_count++] = (halo_host_uniform_info){name, hu->type, hu->meaning};
        }
    }
    /* Pass images must be declared. */
    for (size_t s = 0; s < p->stage_count; s++) {
        const halo_module *m = p->stages[s].module;
        for (size_t i = 0; i < m->pass_count; i++) {
            const halo_pass_decl *pd = &m->passes[i];
            const char *names[HALO_MAX_PASS_INPUTS + 2] = {pd->output, pd->first};
            int n = 2;
            for (int k = 0; k < pd->input_count; k++) names[n++] = pd->inputs[k];
            for (int k = 0; k < n; k++) {
                char expanded[160];
                if (names[k] && names[k][0] && names[k][strlen(names[k]) - 1] == '*') {
                    snprintf(expanded, sizeof expanded, "%.*s_0", (int)strlen(names[k]) - 1, names[k]);
                    names[k] = expanded;
                }
                if (names[k] && strcmp(names[k], "previous") && !find_image(p, names[k])) {
                    halo_diag_add(diag, HALO_SEVERITY_ERROR, HALO_MSG_PASS_INVALID, m->file, pd->line, 1,
                                  m->lines[pd->line - 1], "pass '%s' uses image '%s', which is not declared", pd->name,
                                  names[k]);
                    errors++;
                }
            }
        }
    }
    return errors;
}

/* Pass images at 1/image_scale: every image but the outputs (fragment outputs of the
 * host's framebuffer), host_color and the images at=post passes write (end-of-frame
 * work on the frame's own pixels). */
static void set_image_scales(halo_program *p) {
    for (size_t i = 0; i < p->image_count; i++) {
        halo_image_info *im = &p->images[i];
        int full = im->host;
        for (size_t o = 0; o < p->output_count && !full; o++) full = !strcmp(p->outputs[o].image, im->name);
        for (size_t s = 0; s < p->stage_count && !full; s++) {
            const halo_module *m = p->stages[s].module;
            for (size_t k = 0; k < m->pass_count && !full; k++) {
                const halo_pass_decl *pd = &m->passes[k];
                if (!pd->post) continue;
                size_t n = strlen(pd->output);
                full = n > 1 && pd->output[n - 1] == '*' ? !strncmp(im->name, pd->output, n - 1) &&
                                                                im->name[n - 1] == '_'
                                                          : !strcmp(im->name, pd->output);
            }
        }
        im->scale = full ? 1 : p->image_scale;
    }
}

static const char pass_vertex_body[] =
    "// One full-screen triangle from gl_VertexID; no vertex attributes.\n"
    "void main() {\n"
    "    vec2 corner = vec2(float((gl_VertexID << 1) & 2), float(gl_VertexID & 2));\n"
    "    gl_Position = vec4(corner * 2.0 - 1.0, 0.0, 1.0);\n"
    "}";

static int param_int(const halo_linked_stage *st, const char *name) {
    for (size_t i = 0; i < st->module->param_count; i++)
        if (!strcmp(st->module->params[i].name, name)) return (int)st->values[i].value[0];
    return 0;
}

/* An image name of a pass with its '*' resolved: channel k of an each=channel pass. */
static char *resolve_name(halo_program *p, const char *name, int channel) {
    size_t n = strlen(name);
    if (n > 1 && name[n - 1] == '*') return halo_program_own(p, "%.*s_%d", (int)n - 1, name, channel < 0 ? 0 : channel);
    return halo_program_own(p, "%s", name);
}

static int build_pass(halo_program *p, const halo_library *lib, const halo_linked_stage *st, const halo_pass_decl *pd,
                      int channel) {
    const halo_module *m = st->module;
    emitter e = {0};
    /* The inputs: NAME* of a pass that is not each=channel expands to one input per channel. */
    const char *inputs[HALO_MAX_PASS_INPUTS];
    int input_count = 0;
    for (int k = 0; k < pd->input_count; k++) {
        size_t n = strlen(pd->inputs[k]);
        int family = n > 1 && pd->inputs[k][n - 1] == '*' && channel < 0;
        for (int c = 0; c < (family ? p->channel_count : 1); c++) {
            if (input_count == HALO_MAX_PASS_INPUTS) return -2;
            inputs[input_count++] = resolve_name(p, pd->inputs[k], family ? c : channel);
        }
    }
    const char *output = resolve_name(p, pd->output, channel);
    const halo_image_info *out_image = find_image(p, output);
    int es = p->target == HALO_TARGET_ES300;
    GEN(&e, "%s", halo_target_version_line(p->target));
    if (es) GEN(&e, "precision highp float;\nprecision highp int;\nprecision highp sampler2D;");
    emit(&e, m->file, pd->line, m->lines[pd->line - 1], "// stage %s (%s): image pass '%s'", m->name, m->file, pd->name);
    emit_channel_definitions(&e, p->channel_count);
    for (int k = 0; k < input_count; k++) GEN(&e, "uniform highp sampler2D halo_input_%d;", k);
    GEN(&e, "uniform int halo_pass_index;\nuniform int halo_pass_count;");
    GEN(&e, "const int halo_pass_channel = %d; // each=channel: this pass's channel (0 otherwise)",
        channel < 0 ? 0 : channel);
    GEN(&e, "vec4 halo_pass_vec4(float v) { return vec4(v, 0.0, 0.0, 0.0); }\n"
            "vec4 halo_pass_vec4(vec2 v) { return vec4(v, 0.0, 0.0); }\n"
            "vec4 halo_pass_vec4(vec3 v) { return vec4(v, 0.0); }\n"
            "vec4 halo_pass_vec4(vec4 v) { return v; }");
    char layout[48];
    /* GLSL 150: libhalo's own pass programs name their one output (bound at 0 by the runtime) */
    GEN(&e, "%sout vec4 halo_pass_output;",
        p->target == HALO_TARGET_GLSL150 ? "" : halo_output_layout(p, 0, layout, sizeof layout));
    /* Inputs of another size than the output (halo_link_desc.image_scale): a larger one
     * (the full-size seed read by a 1/s pass) gives the max over the s x s block of the
     * pixel, so that no seed is lost; a smaller one its pixel / s. */
    int out_scale = out_image ? out_image->scale : 1;
    GEN(&e, "const int halo_pass_scale = %d; // the output image is 1/halo_pass_scale of the frame per side",
        out_scale);
    int down[HALO_MAX_PASS_INPUTS], up[HALO_MAX_PASS_INPUTS];
    for (int k = 0; k < input_count; k++) {
        const halo_image_info *in = strcmp(inputs[k], "previous") ? find_image(p, inputs[k]) : out_image;
        int in_scale = in ? in->scale : out_scale;
        down[k] = in_scale < out_scale ? out_scale / in_scale : 1;
        up[k] = in_scale > out_scale ? in_scale / out_scale : 1;
        GEN(&e, "vec4 halo_fetch_%d(ivec2 pixel) {\n"
                "    if (any(lessThan(pixel, ivec2(0))) || any(greaterThanEqual(pixel, textureSize(halo_input_%d, 0))))\n"
                "        return vec4(0.0);\n"
                "    return texelFetch(halo_input_%d, pixel, 0);\n}", k, k, k);
    }
    GEN(&e, "// All four components of input k (images of components=N, host_color) at a pixel of the\n"
            "// output; 0 outside the image (zero padding at the borders).");
    GEN(&e, "vec4 halo_input4(int k, ivec2 pixel) {");
    for (int k = 0; k < input_count; k++) {
        if (down[k] > 1)
            GEN(&e, "    if (k == %d) {\n"
                    "        vec4 m = halo_fetch_%d(pixel * %d);\n"
                    "        for (int i = 1; i < %d; ++i)\n"
                    "            m = max(m, halo_fetch_%d(pixel * %d + ivec2(i %% %d, i / %d)));\n"
                    "        return m;\n"
                    "    }", k, k, down[k], down[k] * down[k], k, down[k], down[k], down[k]);
        else if (up[k] > 1)
            GEN(&e, "    if (k == %d) return any(lessThan(pixel, ivec2(0))) ? vec4(0.0) : halo_fetch_%d(pixel / %d);",
                k, k, up[k]);
        else
            GEN(&e, "    if (k == %d) return halo_fetch_%d(pixel);", k, k);
    }
    GEN(&e, "    return vec4(0.0);\n}");
    GEN(&e, "// Input k at a pixel: the program's channels.\n"
            "halo_channels halo_input(int k, ivec2 pixel) { return halo_channels_from(halo_input4(k, pixel)); }");
    if (input_count > 0 && (down[0] > 1 || up[0] > 1))
        GEN(&e, "// The output's size in pixels.\n"
                "ivec2 halo_image_size() { return (textureSize(halo_input_0, 0) * %d + %d) / %d; }",
            up[0], down[0] - 1, down[0]);
    else
        GEN(&e, "// The output's size in pixels (input 0 has it).\n"
                "ivec2 halo_image_size() { return textureSize(halo_input_0, 0); }");
    /* The helpers this module calls. */
    halo_program one = *p;
    halo_linked_stage only = *st;
    one.stages = &only;
    one.stage_count = 1;
    emit_helpers(&e, lib, &one);
    emit_params(&e, p, st, 0);
    emit_module_lines(&e, m, 1, m->line_count, 1, NULL);
    GEN(&e, "void main() {\n    halo_pass_output = halo_pass_vec4(halo_%s_%s(ivec2(gl_FragCoord.xy)));\n}",
        m->name, pd->entry);
    if (e.failed || e.text.failed) {
        halo_strbuf_free(&e.text);
        free(e.origins);
        return -1;
    }
    halo_pass_info *list = realloc(p->passes, (p->pass_count + 1) * sizeof *list);
    halo_line_origin **ol = realloc(p->pass_origins, (p->pass_count + 1) * sizeof *ol);
    int *oc = realloc(p->pass_origin_counts, (p->pass_count + 1) * sizeof *oc);
    if (list) p->passes = list;
    if (ol) p->pass_origins = ol;
    if (oc) p->pass_origin_counts = oc;
    char *fragment = halo_strbuf_take(&e.text);
    char *frag_owned = fragment ? halo_program_own(p, "%s", fragment) : NULL;
    free(fragment);
    if (!list || !ol || !oc || !frag_owned) {
        free(e.origins);
        return -1;
    }
    halo_pass_info *pi = &p->passes[p->pass_count];
    memset(pi, 0, sizeof *pi);
    pi->name = channel < 0 ? halo_program_own(p, "%s", pd->name) : halo_program_own(p, "%s_%d", pd->name, channel);
    pi->stage = m->name;
    pi->entry = halo_program_own(p, "%s", pd->entry);
    pi->input_count = input_count;
    for (int k = 0; k < input_count; k++) pi->inputs[k] = inputs[k];
    pi->first = pd->first ? resolve_name(p, pd->first, channel) : NULL;
    pi->output = output;
    pi->post = pd->post;
    pi->channel = channel;
    pi->repeat = pd->repeat ? param_int(st, pd->repeat) : 1;
    pi->vertex_source = halo_program_own(p, "%s\n%s\n", halo_target_version_line(p->target), pass_vertex_body);
    pi->fragment_source = frag_owned;
    p->pass_origins[p->pass_count] = e.origins;
    p->pass_origin_counts[p->pass_count] = e.count;
    p->pass_count++;
    return 0;
}

static int build_passes(halo_program *p, const halo_library *lib, halo_diagnostics *diag) {
    for (size_t s = 0; s < p->stage_count; s++) {
        const halo_linked_stage *st = &p->stages[s];
        for (size_t i = 0; i < st->module->pass_count; i++) {
            const halo_pass_decl *pd = &st->module->passes[i];
            if (pd->when && !param_int(st, pd->when)) continue;
            if (pd->repeat && param_int(st, pd->repeat) < 1) continue;
            for (int c = 0; c < (pd->each_channel ? p->channel_count : 1); c++) {
                int r = build_pass(p, lib, st, pd, pd->each_channel ? c : -1);
                if (r == -2) {
                    halo_diag_add(diag, HALO_SEVERITY_ERROR, HALO_MSG_PASS_INVALID, st->module->file, pd->line, 1,
                                  st->module->lines[pd->line - 1],
                                  "pass '%s' reads more than %d images with %d channels", pd->name,
                                  HALO_MAX_PASS_INPUTS, p->channel_count);
                    return -2;
                }
                if (r) return -1;
            }
        }
    }
    return 0;
}

/* ---- The program ---- */

static int build_uniforms(halo_program *p, int all_live) {
    size_t n = 0;
    for (size_t s = 0; s < p->stage_count; s++) n += p->stages[s].module->param_count;
    p->uniforms = calloc(n + 1, sizeof *p->uniforms);
    p->uniform_names = calloc(n + 1, sizeof *p->uniform_names);
    if (!p->uniforms || !p->uniform_names) return -1;
    for (size_t s = 0; s < p->stage_count; s++) {
        halo_linked_stage *st = &p->stages[s];
        st->first_uniform = p->uniform_count;
        for (size_t i = 0; i < st->module->param_count; i++) {
            halo_strbuf b = {0};
            halo_strbuf_printf(&b, "halo_%s_%s", st->module->name, st->module->params[i].name);
            char *name = halo_strbuf_take(&b);
            if (!name) return -1;
            p->uniform_names[p->uniform_count] = name;
            halo_param_value *v = &st->values[i];
            if (all_live) v->live = 1;
            p->uniforms[p->uniform_count++] = (halo_uniform_info){
                .name = name,
                .stage = st->module->name,
                .param = st->module->params[i].name,
                .info = &st->module->params[i],
                .live = v->live,
                .count = v->count,
                .value = v->value,
                .count_name = st->module->params[i].array_size ? halo_program_own(p, "%s_count", name) : NULL,
            };
            if (st->module->params[i].array_size && !p->uniforms[p->uniform_count - 1].count_name) return -1;
        }
    }
    return 0;
}

static int set_groups(halo_program *p);
static void load_group(halo_program *p, int g);

/* Host contract 2: does the host take segments, and does the program need them? A
 * single-pass ray caster (a sample loop, no halo_segment_begin, no `#pragma halo slices`)
 * cannot run passes between slices: refuse it rather than render without the stages
 * that need them. */
static int plan_segments(halo_program *p, const halo_link_desc *desc, const host_info *h, halo_diagnostics *diag) {
    const char *host = halo_skip_bom(desc->host_source);
    int segmenting = halo_host_uses(host, "halo_segment_begin");
    p->v2_host = segmenting || h->volume || h->gradient || halo_host_uses(host, "halo_view_at") ||
                 halo_host_uses(host, "halo_depth_at");
    int generation = halo_program_has_generation_passes(p);
    if (h->compositing_mip && p->stage_count) {
        /* a MIP host composites no samples: every stage would be silently meaningless */
        halo_strbuf names = {0};
        for (size_t s = 0; s < p->stage_count; s++)
            halo_strbuf_printf(&names, "%s%s", names.len ? ", " : "", p->stages[s].module->name);
        halo_diag_add(diag, HALO_SEVERITY_ERROR, HALO_MSG_HOST_COMPOSITING, p->host_file, h->compositing_mip, 1,
                      p->host_lines[h->compositing_mip - 1],
                      "the stages %s act on the samples a host composites, but this host declares maximum intensity "
                      "projection ('#pragma halo compositing mip'): link it with no stage, or use a compositing mode",
                      names.data ? names.data : "?");
        halo_strbuf_free(&names);
        return 1;
    }
    if (desc->force_segments && !segmenting) {
        halo_diag_add(diag, HALO_SEVERITY_ERROR, HALO_MSG_HOST_SINGLE_PASS, p->host_file, 1, 1, p->host_lines[0],
                      "force_segments: the host never calls halo_segment_begin (docs/host-contract.md, "
                      "\"Segmented ray casting\")");
        return 1;
    }
    /* a host that draws one sample per fragment (a slice host, a probe) runs the passes
     * between its draws; one that loops over samples marches whole rays */
    int marches = halo_host_uses(host, "for") || halo_host_uses(host, "while");
    if (generation && marches && !segmenting && !h->slices && p->kind == HALO_SHADER_FRAGMENT) {
        halo_strbuf names = {0};
        for (size_t s = 0; s < p->stage_count; s++) {
            const halo_module *m = p->stages[s].module;
            for (size_t k = 0; k < m->pass_count; k++)
                if (!m->passes[k].post) {
                    halo_strbuf_printf(&names, "%s%s", names.len ? ", " : "", m->name);
                    break;
                }
        }
        int at = h->marker_line ? h->marker_line : 1;
        halo_diag_add(diag, HALO_SEVERITY_ERROR, HALO_MSG_HOST_SINGLE_PASS, p->host_file, at, 1, p->host_lines[at - 1],
                      "the stages %s run image passes between slices, but this host marches each ray in one draw: "
                      "clip its ray loop with halo_segment_begin/halo_segment_end and draw it with "
                      "halo_gl_frame_draw (docs/host-contract.md, \"Segmented ray casting\"), or, for a slice or "
                      "slab host that runs the passes itself, add '#pragma halo slices'",
                      names.data ? names.data : "?");
        halo_strbuf_free(&names);
        return 1;
    }
    if (segmenting && (generation || desc->force_segments)) {
        int location = first_free_location(host);
        for (size_t o = 0; o < p->output_count; o++)
            if (p->outputs[o].location >= location) location = p->outputs[o].location + 1;
        p->segment_location = location;
    }
    return 0;
}

/* ---- The host against what the program needs ---- */

/* The host's main, where a missing call goes; line 1 when there is none. */
static halo_host_hit host_main(const host_info *h, const char *host) {
    const halo_token_list *t = &h->scan.tokens;
    for (size_t i = 0; i + 1 < t->count; i++)
        if (t->items[i].depth == 0 && halo_token_is(host, &t->items[i], "main") &&
            halo_token_is(host, &t->items[i + 1], "(") && halo_host_scan_compiled(&h->scan, t->items[i].line))
            return (halo_host_hit){t->items[i].line, t->items[i].column, 0};
    return (halo_host_hit){1, 1, 0};
}

/* A call the program needs: on a compiled line, not in a comment or a branch not taken. */
static int require_call(const halo_program *p, const host_info *h, const char *host, const char *name,
                        halo_message_id id, const char *why, halo_diagnostics *diag) {
    halo_host_hit unused;
    if (halo_host_scan_find_call(&h->scan, name, &unused)) return 0;
    if (unused.line) {
        const halo_host_line_info *l = &h->scan.lines[unused.line - 1];
        const char *cfile;
        int cline;
        halo_host_scan_origin(&h->scan, p->host_file, l->condition_line, &cfile, &cline);
        if (unused.in_comment)
            host_diag(h, diag, id, p->host_file, p->host_lines, unused.line, unused.column,
                      "this call of %s is commented out, and no other is compiled; %s", name, why);
        else
            host_diag(h, diag, id, p->host_file, p->host_lines, unused.line, unused.column,
                      "this call of %s is in a preprocessor branch not taken for target %s (the condition at "
                      "%s:%d), and no other is compiled; %s",
                      name, halo_target_name(p->target), cfile, cline, why);
        return 1;
    }
    halo_host_hit at = host_main(h, host);
    host_diag(h, diag, id, p->host_file, p->host_lines, at.line, at.column, "the host never calls %s; %s", name, why);
    return 1;
}

static int check_host_calls(const halo_program *p, const host_info *h, const char *host, halo_diagnostics *diag) {
    int errors = 0;
    halo_strbuf stages = {0}, why = {0};
    for (size_t s = 0; s < p->stage_count; s++)
        if (p->stages[s].module->hook != HALO_HOOK_IMAGE)
            halo_strbuf_printf(&stages, "%s%s", stages.len ? ", " : "", p->stages[s].module->name);
    if (stages.len) {
        halo_strbuf_printf(&why, "the scene links the stages %s, which run only inside halo_apply: call it once per "
                                 "sample (docs/host-contract.md)",
                           stages.data);
        errors += require_call(p, h, host, "halo_apply", HALO_MSG_HOST_APPLY_MISSING,
                               why.data ? why.data : "call it", diag);
    }
    if (p->output_count) {
        halo_strbuf_free(&why);
        halo_strbuf_printf(&why, "the linked stages write extra outputs (%s...), so the host must call "
                                 "halo_finish() once per fragment before it returns (docs/image-passes.md)",
                           p->outputs[0].name);
        errors += require_call(p, h, host, "halo_finish", HALO_MSG_HOST_FINISH_MISSING,
                               why.data ? why.data : "call it", diag);
    }
    halo_strbuf_free(&stages);
    halo_strbuf_free(&why);
    return errors;
}

/* The host's outputs need explicit locations when libhalo adds outputs of its own: the
 * compiler would place an output without one anywhere, possibly on libhalo's. */
static int check_host_outputs(const halo_program *p, const host_info *h, const char *host, halo_diagnostics *diag) {
    if ((!p->output_count && !p->segment_location) || p->kind != HALO_SHADER_FRAGMENT) return 0;
    if (p->unlocated_outputs) return 0; /* every output is bound by name before linking */
    halo_host_hit at[16];
    size_t n = halo_host_scan_unlocated_outputs(&h->scan, host, at, sizeof at / sizeof at[0]);
    for (size_t i = 0; i < n && i < sizeof at / sizeof at[0]; i++)
        host_diag(h, diag, HALO_MSG_HOST_OUTPUT_LOCATION, p->host_file, p->host_lines, at[i].line, at[i].column,
                  "this output has no layout(location), but the program adds outputs of its own at location %d "
                  "and up (libhalo takes the first locations after the highest the host declares); declare it "
                  "'layout(location = 0) out ...' (each host output at its own location)",
                  p->output_count ? p->outputs[0].location : p->segment_location);
    return (int)n;
}

/* A host macro defined at the marker rewrites every use of its name in the declarations
 * that replace the marker (a halo_sample field, a local of libhalo's code). */
static int check_host_macros(const halo_program *p, const host_info *h, halo_diagnostics *diag) {
    int first = 0, last = 0, errors = 0;
    for (int i = 0; i < p->origin_count; i++)
        if (p->origins[i].file == p->host_file && p->origins[i].line == h->marker_line) {
            if (!first) first = i + 1;
            last = i + 1;
        }
    halo_token_list t;
    if (!first || halo_lex(p->source, &t)) return 0;
    for (size_t m = 0; m < h->scan.marker_macro_count; m++) {
        const halo_host_macro *mac = halo_host_scan_macro(&h->scan, h->scan.marker_macros[m].name,
                                                          h->scan.marker_macros[m].length);
        for (size_t i = 0; mac && i < t.count; i++) {
            const halo_token *k = &t.items[i];
            if (k->line <= first || k->line >= last || k->length != mac->length ||
                memcmp(p->source + k->offset, mac->name, mac->length))
                continue;
            if (mac->function_like && !(i + 1 < t.count && halo_token_is(p->source, &t.items[i + 1], "(")))
                continue;
            const char *mfile;
            int mline;
            halo_host_scan_origin(&h->scan, p->host_file, h->marker_line, &mfile, &mline);
            host_diag(h, diag, HALO_MSG_HOST_MACRO_CLASH, p->host_file, p->host_lines, mac->line, mac->column,
                      "the macro '%.*s' is still defined at '#pragma halo declarations' (%s:%d), so it rewrites the "
                      "identifier '%.*s' that libhalo's declarations use; #undef it before the marker (and define "
                      "it again after), or rename it",
                      (int)mac->length, mac->name, mfile, mline, (int)mac->length, mac->name);
            errors++;
            break;
        }
    }
    halo_token_list_free(&t);
    return errors;
}

/* A host #line stays out of the compiled text (its numbering would no longer match
 * the line map); the line map applies it instead. */
static int hide_line_directives(halo_program *p, const host_info *h) {
    for (int i = 0; i < h->scan.line_count; i++) {
        if (!h->scan.lines[i].line_directive) continue;
        char *comment = halo_program_own(p, "// %s (libhalo: applied to the line map)", p->host_lines[i]);
        if (!comment) return -1;
        p->host_lines[i] = comment;
    }
    return 0;
}

/* Host lines of the program's line map at the origins the host's #line directives give. */
static int map_host_lines(halo_program *p, const host_info *h) {
    for (int i = 0; i < p->origin_count; i++) {
        halo_line_origin *o = &p->origins[i];
        if (o->file != p->host_file) continue;
        const char *file;
        halo_host_scan_origin(&h->scan, p->host_file, o->line, &file, &o->line);
        if (file == p->host_file) continue;
        o->file = NULL;
        for (size_t k = 0; k < p->string_count && !o->file; k++)
            if (!strcmp(p->strings[k], file)) o->file = p->strings[k];
        if (!o->file && !(o->file = halo_program_own(p, "%s", file))) return -1;
    }
    return 0;
}

static halo_program *link_with_host(const halo_link_desc *desc, host_info *h, halo_diagnostics *diag);

halo_program *halo_link_host(const halo_link_desc *desc, halo_diagnostics *diag) {
    host_info h = {0};
    halo_program *p = link_with_host(desc, &h, diag);
    halo_host_scan_free(&h.scan);
    return p;
}

static halo_program *link_with_host(const halo_link_desc *desc, host_info *h, halo_diagnostics *diag) {
    if (!desc || !desc->library || !desc->host_source) {
        halo_diag_error(diag, USAGE, "", 0, 0, "halo_link: library and host_source are required");
        return NULL;
    }
    if ((unsigned)desc->target >= HALO_TARGET_COUNT) {
        halo_diag_error(diag, USAGE, "", 0, 0, "halo_link: unknown target %d", (int)desc->target);
        return NULL;
    }
    if (desc->scene && desc->scene->library != desc->library) {
        /* its stages point into the other library's modules: linking would use those */
        halo_diag_error(diag, USAGE, "", 0, 0,
                        "halo_link: the scene was read against another library than desc.library; read it against "
                        "the library it is linked with");
        return NULL;
    }
    halo_program *p = calloc(1, sizeof *p);
    if (!p) goto oom;
    atomic_init(&p->refs, 1);
    p->library = desc->library;
    halo_library_retain(p->library);
    p->target = desc->target == HALO_TARGET_DEFAULT ? HALO_TARGET_GLSL330 : desc->target;
    p->kind = desc->kind;
    p->version = desc->version;
    p->engine_uniforms = desc->engine_uniforms != 0;
    p->unlocated_outputs =
        desc->unlocated_outputs || (p->target == HALO_TARGET_GLSL150 && !desc->location_extension);
    p->first_location = desc->pieces ? desc->pieces->first_output_location : 0;
    p->host_file = halo_strdup(desc->host_file ? desc->host_file : "host");
    /* a UTF-8 byte-order mark is no part of the shader */
    const char *host_source = halo_skip_bom(desc->host_source);
    p->host_storage = halo_strdup(host_source);
    if (!p->host_file || !p->host_storage) goto oom;
    int host_count = halo_split_lines(p->host_storage, &p->host_lines);
    if (host_count < 0) goto oom;

    /* 1. The host keeps the contract. */
    if (halo_host_scan_run(&(halo_host_scan_desc){host_source, p->target, p->kind, is_marker_line}, &h->scan))
        goto oom;
    int errors = check_host(p->host_file, host_source, p->host_lines, host_count, h, p->target, diag);
    p->volume_sampler = h->volume;
    p->gradient_sampler = h->gradient;
    /* 2. Stages, their dependencies and their order. */
    node *order = NULL;
    int n = 0;
    errors += resolve(desc->library, desc->scene, desc->kind, &order, &n, diag);
    if (errors) {
        free(order);
        halo_program_destroy(p);
        return NULL;
    }
    /* 3. Parameters: the scene's values, or the defaults. */
    p->stages = calloc((size_t)n + 1, sizeof *p->stages);
    if (!p->stages) { free(order); goto oom; }
    for (int i = 0; i < n; i++) {
        const halo_module *m = order[i].module;
        halo_linked_stage *st = &p->stages[p->stage_count++];
        st->module = m;
        st->values = calloc(m->param_count + 1, sizeof *st->values);
        if (!st->values) { free(order); goto oom; }
        for (size_t k = 0; k < m->param_count; k++) {
            if (order[i].entry) {
                st->values[k] = order[i].entry->values[k];
            } else {
                st->values[k].count = m->params[k].default_count;
                memcpy(st->values[k].value, m->params[k].default_value, sizeof st->values[k].value);
            }
        }
    }
    free(order);
    if (set_groups(p)) goto oom;
    if (build_uniforms(p, desc->all_live)) goto oom;
    /* 4. Channels, images, outputs, samplers, host uniforms, passes. */
    p->image_precision = desc->image_precision ? desc->image_precision : 32;
    if (p->image_precision != 32 && p->image_precision != 16 && p->image_precision != 8) {
        halo_diag_error(diag, USAGE, "", 0, 0, "image_precision must be 32, 16 or 8, not %d", desc->image_precision);
        halo_program_destroy(p);
        return NULL;
    }
    p->image_scale = desc->image_scale ? desc->image_scale : 1;
    if (p->image_scale != 1 && p->image_scale != 2 && p->image_scale != 4) {
        halo_diag_error(diag, USAGE, "", 0, 0, "image_scale must be 1, 2 or 4, not %d", desc->image_scale);
        halo_program_destroy(p);
        return NULL;
    }
    set_channel_count(p);
    int resources = collect_resources(p, host_source, diag);
    int host_errors = resources < 0 ? 0
                                    : plan_segments(p, desc, h, diag) + check_host_calls(p, h, host_source, diag) +
                                          check_host_outputs(p, h, host_source, diag);
    if (resources || host_errors) {
        halo_program_destroy(p);
        return NULL;
    }
    set_image_scales(p);
    if (p->group_count > 1) load_group(p, 0);
    /* 5. Emit. */
    if (hide_line_directives(p, h)) goto oom;
    if (emit_program(p, host_source, p->host_lines, host_count, h, desc->library)) goto oom;
    if (check_host_macros(p, h, diag)) {
        halo_program_destroy(p);
        return NULL;
    }
    if (map_host_lines(p, h)) goto oom;
    int passes = build_passes(p, desc->library, diag);
    if (passes == -2) {
        halo_program_destroy(p);
        return NULL;
    }
    if (passes) goto oom;
    return p;
oom:
    halo_diag_error(diag, OUT_OF_MEMORY, "", 0, 0, "out of memory");
    halo_program_destroy(p);
    return NULL;
}

void halo_program_retain(const halo_program *p) { atomic_fetch_add(&((halo_program *)p)->refs, 1); }

void halo_program_destroy(halo_program *p) {
    if (!p || atomic_fetch_sub(&p->refs, 1) != 1) return;
    for (int i = 0; i < HALO_PIECE_COUNT; i++) { /* pieces (compose.c) */
        free(p->pieces[i]);
        free(p->piece_origins[i]);
    }
    free(p->volume_sampler);
    free(p->gradient_sampler);
    free(p->source);
    free(p->host_file);
    free(p->host_storage);
    free(p->host_lines);
    free(p->origins);
    for (size_t s = 0; s < p->stage_count; s++) {
        free(p->stages[s].values);
        free(p->stages[s].group_values);
    }
    free(p->stages);
    for (size_t i = 0; i < p->uniform_count; i++) free(p->uniform_names[i]);
    free(p->uniform_names);
    free(p->uniforms);
    free(p->outputs);
    free(p->passes);
    for (size_t i = 0; i < p->pass_count; i++) free(p->pass_origins[i]);
    free(p->pass_origins);
    free(p->pass_origin_counts);
    free(p->images);
    free(p->samplers);
    free(p->host_uniforms);
    for (size_t i = 0; i < p->string_count; i++) free(p->strings[i]);
    free(p->strings);
    halo_library_release(p->library);
    free(p);
}

/* A reflection getter: refuses a NULL program with none_value. */
#define PROGRAM_GETTER(type, name, none_value, expression)                                                        \
    type name(const halo_program *p) {                                                                            \
        HALO_REFUSE_NULL(NULL, p, "program", none_value);                                                         \
        return expression;                                                                                        \
    }
#define PROGRAM_ITEM(type, name, count, items)                                                                    \
    const type *name(const halo_program *p, size_t i) {                                                           \
        HALO_REFUSE_NULL(NULL, p, "program", NULL);                                                               \
        return i < p->count ? &p->items[i] : NULL;                                                                \
    }
PROGRAM_GETTER(const char *, halo_program_source, NULL, p->source)
PROGRAM_GETTER(halo_target, halo_program_target, HALO_TARGET_COUNT, p->target)

int halo_program_map_line(const halo_program *p, int line, const char **file, int *origin_line) {
    HALO_REFUSE_NULL(NULL, p, "program", 0);
    if (line < 1 || line > p->origin_count) return 0;
    const halo_line_origin *o = &p->origins[line - 1];
    if (file) *file = o->file;
    if (origin_line) *origin_line = o->line;
    return o->file != halo_generated_file;
}

PROGRAM_GETTER(size_t, halo_program_stage_count, 0, p->stage_count)
const char *halo_program_stage(const halo_program *p, size_t i) {
    HALO_REFUSE_NULL(NULL, p, "program", NULL);
    return i < p->stage_count ? p->stages[i].module->name : NULL;
}
PROGRAM_GETTER(size_t, halo_program_uniform_count, 0, p->uniform_count)
PROGRAM_ITEM(halo_uniform_info, halo_program_uniform, uniform_count, uniforms)
const halo_uniform_info *halo_program_find_uniform(const halo_program *p, const char *stage, const char *param) {
    HALO_REFUSE_NULL(NULL, p, "program", NULL);
    HALO_REFUSE_NULL(NULL, stage, "stage", NULL);
    HALO_REFUSE_NULL(NULL, param, "param", NULL);
    for (size_t i = 0; i < p->uniform_count; i++)
        if (!strcmp(p->uniforms[i].stage, stage) && !strcmp(p->uniforms[i].param, param)) return &p->uniforms[i];
    return NULL;
}

halo_status halo_program_set(halo_program *p, const char *stage, const char *param, const double *values, int count,
                             halo_diagnostics *diag) {
    HALO_REFUSE_NULL(diag, p, "program", HALO_ERROR_INPUT);
    HALO_REFUSE_NULL(diag, stage, "stage", HALO_ERROR_INPUT);
    HALO_REFUSE_NULL(diag, param, "param", HALO_ERROR_INPUT);
    HALO_REFUSE_NULL(diag, values, "values", HALO_ERROR_INPUT);
    const halo_uniform_info *u = halo_program_find_uniform(p, stage, param);
    if (!u) {
        halo_diag_error(diag, SCENE_PARAM_UNKNOWN, "", 0, 0, "%s.%s: no such parameter in this program", stage, param);
        return HALO_ERROR_INPUT;
    }
    if (!u->live) {
        halo_diag_error(diag, USAGE, "", 0, 0,
                        "%s.%s is a compile-time constant in this program; mark it live in the scene to change it "
                        "at run time",
                        stage, param);
        return HALO_ERROR_INPUT;
    }
    char why[256];
    int id = halo_param_check(u->info, values, count, why, sizeof why);
    if (id >= 0) {
        halo_diag_add(diag, HALO_SEVERITY_ERROR, (halo_message_id)id, "", 0, 0, NULL, "%s.%s: %s", stage, param, why);
        return HALO_ERROR_INPUT;
    }
    /* a grouped parameter of a program with feature groups: the whole list; the current
     * group's four become the uniform's values */
    for (size_t s = 0; s < p->stage_count; s++) {
        halo_linked_stage *st = &p->stages[s];
        if (!st->group_values || strcmp(st->module->name, stage)) continue;
        size_t i = (size_t)(u->info - st->module->params);
        if (st->module->params[i].type != HALO_PARAM_CHANNELS) break;
        if (count > 4 * p->group_count) {
            halo_diag_error(diag, USAGE, "", 0, 0,
                            "%s.%s: %d features need more than the program's %d feature groups; link the scene again",
                            stage, param, count, p->group_count);
            return HALO_ERROR_INPUT;
        }
        memcpy(st->group_values[i].value, values, (size_t)count * sizeof(double));
        st->group_values[i].count = count;
        load_group(p, p->group);
        return HALO_OK;
    }
    halo_uniform_info *w = &p->uniforms[u - p->uniforms];
    memcpy((double *)w->value, values, (size_t)count * (size_t)u->info->components * sizeof(double));
    w->count = count;
    /* Keep the stage's value record in step. */
    for (size_t s = 0; s < p->stage_count; s++)
        for (size_t i = 0; i < p->stages[s].module->param_count; i++)
            if (p->stages[s].values[i].value == w->value) p->stages[s].values[i].count = count;
    return HALO_OK;
}

PROGRAM_GETTER(size_t, halo_program_output_count, 0, p->output_count)
PROGRAM_ITEM(halo_output_info, halo_program_output, output_count, outputs)
PROGRAM_GETTER(size_t, halo_program_image_count, 0, p->image_count)
PROGRAM_ITEM(halo_image_info, halo_program_image, image_count, images)
PROGRAM_GETTER(size_t, halo_program_sampler_count, 0, p->sampler_count)
PROGRAM_ITEM(halo_sampler_info, halo_program_sampler, sampler_count, samplers)
PROGRAM_GETTER(size_t, halo_program_host_uniform_count, 0, p->host_uniform_count)
PROGRAM_ITEM(halo_host_uniform_info, halo_program_host_uniform, host_uniform_count, host_uniforms)
PROGRAM_GETTER(int, halo_program_channel_count, 0, p->channel_count)
PROGRAM_GETTER(int, halo_program_image_precision, 0, p->image_precision)
PROGRAM_GETTER(int, halo_program_image_scale, 0, p->image_scale)
PROGRAM_GETTER(int, halo_program_segment_location, 0, p->segment_location)
PROGRAM_GETTER(int, halo_program_group_count, 0, p->group_count > 1 ? p->group_count : 1)

/* Group g's values of every grouped channels parameter: values 4g .. 4g + 3 of the
 * scene's list (the last value repeated where the list ends), padded to the channel
 * count by repeating the group's last. */
static void load_group(halo_program *p, int g) {
    for (size_t s = 0; s < p->stage_count; s++) {
        halo_linked_stage *st = &p->stages[s];
        if (!st->group_values) continue;
        for (size_t i = 0; i < st->module->param_count; i++) {
            if (st->module->params[i].type != HALO_PARAM_CHANNELS) continue;
            const halo_param_value *full = &st->group_values[i];
            halo_param_value *v = &st->values[i];
            int n = full->count < 1 ? 1 : full->count, c = p->channel_count < 1 ? 4 : p->channel_count;
            for (int k = 0; k < c; k++) {
                int from = 4 * g + k < n ? 4 * g + k : n - 1;
                v->value[k] = full->value[from];
            }
            v->count = c;
            p->uniforms[st->first_uniform + i].count = c;
        }
    }
    p->group = g;
}

halo_status halo_program_select_group(halo_program *p, int group) {
    HALO_REFUSE_NULL(NULL, p, "program", HALO_ERROR_INPUT);
    if (group < 0 || group >= halo_program_group_count(p)) return HALO_ERROR_INPUT;
    if (p->group_count > 1) load_group(p, group);
    return HALO_OK;
}

/* Feature groups: grouped stages whose channels lists are longer than four. Their lists
 * are kept whole (group_values), their channels parameters become uniforms (switching
 * groups is an upload), and group 0 is loaded. */
static int set_groups(halo_program *p) {
    int features = 0;
    for (size_t s = 0; s < p->stage_count; s++) {
        const halo_module *m = p->stages[s].module;
        for (size_t i = 0; m->groups && i < m->param_count; i++)
            if (m->params[i].type == HALO_PARAM_CHANNELS && p->stages[s].values[i].count > features)
                features = p->stages[s].values[i].count;
    }
    p->group_count = features > 4 ? (features + 3) / 4 : 1;
    if (p->group_count == 1) return 0;
    for (size_t s = 0; s < p->stage_count; s++) {
        halo_linked_stage *st = &p->stages[s];
        if (!st->module->groups) continue;
        st->group_values = calloc(st->module->param_count + 1, sizeof *st->group_values);
        if (!st->group_values) return -1;
        for (size_t i = 0; i < st->module->param_count; i++) {
            if (st->module->params[i].type != HALO_PARAM_CHANNELS) continue;
            st->group_values[i] = st->values[i];
            st->values[i].live = 1;
            st->values[i].count = 4; /* group 0 (set_channel_count sees four) */
        }
    }
    return 0;
}
PROGRAM_GETTER(size_t, halo_program_pass_count, 0, p->pass_count)
PROGRAM_ITEM(halo_pass_info, halo_program_pass, pass_count, passes)

static json_t *number_or_null(double v) { return isfinite(v) ? json_real(v) : json_null(); }

char *halo_program_reflect_json(const halo_program *p) {
    HALO_REFUSE_NULL(NULL, p, "program", NULL);
    json_t *root = json_object();
    json_object_set_new(root, "contract", json_integer(HALO_CONTRACT_VERSION));
    json_object_set_new(root, "target", json_string(halo_target_name(p->target)));
    json_t *stages = json_array();
    for (size_t s = 0; s < p->stage_count; s++) json_array_append_new(stages, json_string(p->stages[s].module->name));
    json_object_set_new(root, "stages", stages);
    json_t *uniforms = json_array(), *constants = json_array();
    for (size_t i = 0; i < p->uniform_count; i++) {
        const halo_uniform_info *u = &p->uniforms[i];
        json_t *o = json_object();
        json_object_set_new(o, "name", json_string(u->name));
        json_object_set_new(o, "stage", json_string(u->stage));
        json_object_set_new(o, "param", json_string(u->param));
        halo_strbuf t = {0};
        halo_strbuf_append(&t, u->info->type == HALO_PARAM_CHANNELS ? "channels" : halo_param_type_name(u->info->type));
        if (u->info->array_size && u->info->type != HALO_PARAM_CHANNELS) halo_strbuf_printf(&t, "[%d]", u->info->array_size);
        json_object_set_new(o, "type", json_string(t.data ? t.data : "?"));
        halo_strbuf_free(&t);
        json_t *val = json_array();
        for (int k = 0; k < u->count * u->info->components; k++) json_array_append_new(val, json_real(u->value[k]));
        json_object_set_new(o, "value", val);
        json_object_set_new(o, "count", json_integer(u->count));
        json_object_set_new(o, "min", number_or_null(u->info->min));
        json_object_set_new(o, "max", number_or_null(u->info->max));
        json_object_set_new(o, "meaning", json_string(u->info->meaning));
        json_array_append_new(u->live ? uniforms : constants, o);
    }
    json_object_set_new(root, "uniforms", uniforms);
    json_object_set_new(root, "constants", constants);
    json_object_set_new(root, "channels", json_integer(p->channel_count));
    json_object_set_new(root, "image_precision", json_integer(p->image_precision));
    json_object_set_new(root, "image_scale", json_integer(p->image_scale));
    /* host contract 2: drawn in depth segments (halo_gl_frame_draw), the ray state at this location */
    json_object_set_new(root, "segment_state_location",
                        p->segment_location > 0 ? json_integer(p->segment_location) : json_null());
    json_t *samplers = json_array();
    for (size_t i = 0; i < p->sampler_count; i++) {
        json_t *o = json_object();
        json_object_set_new(o, "name", json_string(p->samplers[i].name));
        json_object_set_new(o, "image", json_string(p->samplers[i].image));
        json_array_append_new(samplers, o);
    }
    json_object_set_new(root, "samplers", samplers);
    json_t *host_uniforms = json_array();
    for (size_t i = 0; i < p->host_uniform_count; i++) {
        json_t *o = json_object();
        json_object_set_new(o, "name", json_string(p->host_uniforms[i].name));
        json_object_set_new(o, "type", json_string(p->host_uniforms[i].type));
        json_object_set_new(o, "meaning", json_string(p->host_uniforms[i].meaning));
        json_array_append_new(host_uniforms, o);
    }
    json_object_set_new(root, "host_uniforms", host_uniforms);
    json_t *images = json_array();
    for (size_t i = 0; i < p->image_count; i++) {
        json_t *o = json_object();
        json_object_set_new(o, "name", json_string(p->images[i].name));
        json_object_set_new(o, "channels", json_integer(p->images[i].channels));
        if (p->images[i].clear != 0.0) json_object_set_new(o, "clear", json_real(p->images[i].clear));
        if (p->images[i].host) json_object_set_new(o, "host", json_true());
        if (p->images[i].scale > 1) json_object_set_new(o, "scale", json_integer(p->images[i].scale));
        json_object_set_new(o, "reset", json_string(p->images[i].reset == HALO_RESET_GENERATION ? "generation"
                                                                                                   : "frame"));
        json_array_append_new(images, o);
    }
    json_object_set_new(root, "images", images);
    static const char *const blends[] = {"none", "max", "add", "min", "first"};
    json_t *outputs = json_array();
    for (size_t i = 0; i < p->output_count; i++) {
        json_t *o = json_object();
        json_object_set_new(o, "name", json_string(p->outputs[i].name));
        json_object_set_new(o, "location", json_integer(p->outputs[i].location));
        json_object_set_new(o, "components", json_integer(p->outputs[i].components));
        json_object_set_new(o, "image", json_string(p->outputs[i].image));
        json_object_set_new(o, "blend", json_string(blends[p->outputs[i].blend]));
        json_array_append_new(outputs, o);
    }
    json_object_set_new(root, "outputs", outputs);
    json_t *passes = json_array();
    for (size_t i = 0; i < p->pass_count; i++) {
        const halo_pass_info *pi = &p->passes[i];
        json_t *o = json_object();
        json_object_set_new(o, "name", json_string(pi->name));
        json_object_set_new(o, "stage", json_string(pi->stage));
        json_object_set_new(o, "entry", json_string(pi->entry));
        json_t *in = json_array();
        for (int k = 0; k < pi->input_count; k++) json_array_append_new(in, json_string(pi->inputs[k]));
        json_object_set_new(o, "inputs", in);
        if (pi->first) json_object_set_new(o, "first", json_string(pi->first));
        json_object_set_new(o, "output", json_string(pi->output));
        json_object_set_new(o, "repeat", json_integer(pi->repeat));
        if (pi->post) json_object_set_new(o, "at", json_string("post"));
        if (pi->channel >= 0) json_object_set_new(o, "channel", json_integer(pi->channel));
        json_array_append_new(passes, o);
    }
    json_object_set_new(root, "passes", passes);
    char *text = json_dumps(root, JSON_INDENT(2) | JSON_PRESERVE_ORDER | JSON_REAL_PRECISION(9));
    json_decref(root);
    return text;
}
