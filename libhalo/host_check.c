/* The host shader's side of the link (host_check.h): the host alone keeps the
 * contract (one marker at global scope, known annotations, no reserved names), and,
 * once the program is known, the host against what the program needs (calls, output
 * locations, macros at the marker) and its #line directives in the line map. Every
 * problem is a diagnostic at the host's own file:line. */
#include "host_check.h"
#include "diag.h"
#include "internal.h"
#include "strbuf.h"

#include <ctype.h>
#include <stdlib.h>
#include <string.h>

/* ---- The host alone ---- */

static const char *const contract_names[] = {"halo_sample", "halo_make_sample", "halo_apply", "halo_finish",
                                             "halo_line_vertex", "halo_make_line_vertex", "halo_line_fragment",
                                             "halo_make_line_fragment", "HALO_LINKED", "HALO_CONTRACT_VERSION",
                                             /* host contract 2 */
                                             "halo_segment_begin", "halo_segment_end", "halo_view_at", "halo_depth_at",
                                             "halo_gradient_at", "HALO_RAY_MAY_END", NULL};


/* `#pragma halo volume NAME`, `gradient NAME`, `slices` or `compositing mip`: 1 if the line is one of them
 * (stored in h), 0 if it is another annotation, -1 if it is one of them but malformed. */
static int host_annotation(const char *line, int number, halo_host_info *h)
{
    const char *d = line + halo_annotation_start(line) - 1;
    size_t word = strcspn(d, " \t");
    const char *arg = d + word;
    while (*arg == ' ' || *arg == '\t')
        arg++;
    size_t n = strcspn(arg, " \t");
    int rest = arg[n + strspn(arg + n, " \t")] != '\0';
    if (word == 6 && !strncmp(d, "slices", 6)) {
        if (*arg)
            return -1;
        h->slices = number;
        return 1;
    }
    if (word == 11 && !strncmp(d, "compositing", 11)) {
        if (n != 3 || strncmp(arg, "mip", 3) || rest)
            return -1;
        h->compositing_mip = number;
        return 1;
    }
    char **slot = word == 6 && !strncmp(d, "volume", 6)     ? &h->volume
                  : word == 8 && !strncmp(d, "gradient", 8) ? &h->gradient
                                                            : NULL;
    if (!slot)
        return 0;
    if (!n || rest || !(isalpha((unsigned char)arg[0]) || arg[0] == '_'))
        return -1;
    for (size_t k = 0; k < n; k++)
        if (!isalnum((unsigned char)arg[k]) && arg[k] != '_')
            return -1;
    free(*slot);
    *slot = malloc(n + 1);
    if (*slot) {
        memcpy(*slot, arg, n);
        (*slot)[n] = '\0';
    }
    h->volume_line = number;
    return 1;
}

/* Reports at a host line, where its #line directives say it comes from. */
static void host_diag(const halo_host_info *h, halo_diagnostics *diag, halo_message_id id, const char *host_file,
                      char **lines, int line, int column, const char *fmt, ...) __attribute__((format(printf, 8, 9)));
static void host_diag(const halo_host_info *h, halo_diagnostics *diag, halo_message_id id, const char *host_file,
                      char **lines, int line, int column, const char *fmt, ...)
{
    halo_strbuf b = {0};
    va_list ap;
    va_start(ap, fmt);
    halo_strbuf_vprintf(&b, fmt, ap);
    va_end(ap);
    const char *file;
    int origin_line;
    halo_host_scan_origin(&h->scan, host_file, line, &file, &origin_line);
    halo_diagnostics_report(diag, HALO_SEVERITY_ERROR, id, file, origin_line, column, lines[line - 1], "%s",
                            b.data ? b.data : halo_message_name(id));
    halo_strbuf_free(&b);
}

static int is_version_line(const char *l)
{
    while (*l == ' ' || *l == '\t')
        l++;
    if (*l != '#')
        return 0;
    l++;
    while (*l == ' ' || *l == '\t')
        l++;
    return !strncmp(l, "version", 7) && !isalnum((unsigned char)l[7]);
}

int halo_host_is_marker_line(const char *l)
{
    int col = halo_annotation_start(l);
    if (!col)
        return 0;
    const char *d = l + col - 1;
    if (strncmp(d, "declarations", 12))
        return 0;
    for (d += 12; *d; d++)
        if (!isspace((unsigned char)*d))
            return 0;
    return 1;
}

/* Marker lines that a compiler never sees: commented out, or in an #if branch not taken. */
static int report_inactive_markers(const halo_host_info *h, const char *file, char **lines, int count,
                                   halo_target target, halo_diagnostics *diag)
{
    int errors = 0;
    for (int i = 0; i < count; i++) {
        const halo_host_line_info *l = &h->scan.lines[i];
        if (halo_host_is_marker_line(h->scan.comment_lines[i])) {
            host_diag(h, diag, HALO_MSG_HOST_MARKER_INACTIVE, file, lines, i + 1, 1,
                      "'#pragma halo declarations' is commented out, so no stage would be linked; remove the "
                      "comment around it");
            errors++;
        } else if (halo_host_is_marker_line(h->scan.code_lines[i]) && l->activity == HALO_BRANCH_NOT_TAKEN) {
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

int halo_host_check(const char *file, const char *source, char **lines, int count, halo_host_info *h,
                    halo_target target, halo_diagnostics *diag)
{
    int errors = 0;
    h->version_line = h->marker_line = h->slices = h->volume_line = h->compositing_mip = 0;
    h->volume = h->gradient = NULL;
    halo_token_list toks;
    if (halo_lex(source, &toks)) {
        halo_diag_error(diag, OUT_OF_MEMORY, file, 0, 0, "out of memory");
        return 1;
    }
    for (int i = 0; i < count; i++) {
        if (is_version_line(lines[i]) && !h->version_line)
            h->version_line = i + 1;
        if (!halo_host_scan_compiled(&h->scan, i + 1))
            continue;
        if (halo_host_is_marker_line(h->scan.code_lines[i])) {
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
                if (halo_token_is(source, &toks.items[t], "{"))
                    depth++;
                if (halo_token_is(source, &toks.items[t], "}"))
                    depth--;
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
            if (known == 1)
                continue;
            host_diag(h, diag, known ? HALO_MSG_ANNOTATION_SYNTAX : HALO_MSG_ANNOTATION_UNKNOWN, file, lines, i + 1,
                      col,
                      known ? "'#pragma halo volume' and 'gradient' take one sampler name; 'slices' takes none; "
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
    /* the names of every contract version (contract_names), as the message lists them */
    halo_strbuf allowed_list = {0};
    for (int c = 0; contract_names[c]; c++)
        halo_strbuf_printf(&allowed_list, "%s%s", c ? (contract_names[c + 1] ? ", " : " and ") : "", contract_names[c]);
    for (size_t t = 0; t < toks.count; t++) {
        const halo_token *k = &toks.items[t];
        if (k->kind != HALO_TOK_IDENT || k->length < 5)
            continue;
        const char *s = source + k->offset;
        if (strncmp(s, "halo_", 5) && strncmp(s, "HALO_", 5))
            continue;
        if (t > 0 && halo_token_is(source, &toks.items[t - 1], "."))
            continue; /* a field */
        /* libhalo's own march (prepass.c) uses its batch's names: HALO_MARCH_BATCH, halo_march_take */
        int allowed = file && !strcmp(file, halo_march_file) &&
                      (halo_token_is(source, k, "HALO_MARCH_BATCH") || halo_token_is(source, k, "halo_march_take"));
        for (int c = 0; contract_names[c]; c++)
            allowed |= halo_token_is(source, k, contract_names[c]);
        if (allowed)
            continue;
        host_diag(h, diag, HALO_MSG_HOST_RESERVED_NAME, file, lines, k->line, k->column,
                  "'%.*s' is reserved: names starting with halo_ or HALO_ belong to libhalo (the host may use %s)",
                  (int)k->length, s, allowed_list.data ? allowed_list.data : "the contract's names");
        errors++;
    }
    halo_strbuf_free(&allowed_list);
    halo_token_list_free(&toks);
    return errors;
}

/* ---- The host against what the program needs ---- */

/* The host's main, where a missing call goes; line 1 when there is none. */
static halo_host_hit host_main(const halo_host_info *h, const char *host)
{
    const halo_token_list *t = &h->scan.tokens;
    for (size_t i = 0; i + 1 < t->count; i++)
        if (t->items[i].depth == 0 && halo_token_is(host, &t->items[i], "main") &&
            halo_token_is(host, &t->items[i + 1], "(") && halo_host_scan_compiled(&h->scan, t->items[i].line))
            return (halo_host_hit){t->items[i].line, t->items[i].column, 0};
    return (halo_host_hit){1, 1, 0};
}

/* A call the program needs: on a compiled line, not in a comment or a branch not taken. */
static int require_call(const halo_program *p, const halo_host_info *h, const halo_host_text *t, const char *name,
                        halo_message_id id, const char *why, halo_diagnostics *diag)
{
    halo_host_hit unused;
    if (halo_host_scan_find_call(&h->scan, name, &unused))
        return 0;
    if (unused.line) {
        const halo_host_line_info *l = &h->scan.lines[unused.line - 1];
        const char *cfile;
        int cline;
        halo_host_scan_origin(&h->scan, t->file, l->condition_line, &cfile, &cline);
        if (unused.in_comment)
            host_diag(h, diag, id, t->file, t->lines, unused.line, unused.column,
                      "this call of %s is commented out, and no other is compiled; %s", name, why);
        else
            host_diag(h, diag, id, t->file, t->lines, unused.line, unused.column,
                      "this call of %s is in a preprocessor branch not taken for target %s (the condition at "
                      "%s:%d), and no other is compiled; %s",
                      name, halo_target_name(p->target), cfile, cline, why);
        return 1;
    }
    halo_host_hit at = host_main(h, t->source);
    host_diag(h, diag, id, t->file, t->lines, at.line, at.column, "the %s never calls %s; %s", t->what, name, why);
    return 1;
}

/* Drawn in segments, a fragment that discards after halo_segment_begin loses the draw of
 * that segment only: its colour and ray state are not written, so the next segment starts
 * the ray again from the state before (a discard that depends on the segment). A discard
 * before halo_segment_begin (a ray that misses the box) holds in every segment. Each
 * compiled `discard` after the first compiled halo_segment_begin call, in the function
 * that makes it, is an error; one in a function called from there is not seen. */
static int segment_discards(const halo_host_info *h, const halo_host_text *t, halo_diagnostics *diag)
{
    const halo_token_list *tokens = &h->scan.tokens;
    size_t i = 0;
    for (; i + 1 < tokens->count; i++)
        if (halo_token_is(t->source, &tokens->items[i], "halo_segment_begin") &&
            halo_token_is(t->source, &tokens->items[i + 1], "(") &&
            halo_host_scan_compiled(&h->scan, tokens->items[i].line))
            break;
    int errors = 0;
    for (size_t k = i + 1; k < tokens->count && tokens->items[k].brace_depth > 0; k++) {
        const halo_token *d = &tokens->items[k];
        if (!halo_token_is(t->source, d, "discard") || !halo_host_scan_compiled(&h->scan, d->line))
            continue;
        host_diag(h, diag, HALO_MSG_HOST_SEGMENT_CALLS, t->file, t->lines, d->line, d->column,
                  "a discard after halo_segment_begin: drawn in depth segments, it drops this segment's colour and "
                  "ray state, and the next segment marches the ray again from before it; discard before "
                  "halo_segment_begin (a ray that misses the volume), or end the ray with "
                  "halo_segment_end(state, true) (docs/host-contract.md)");
        ++errors;
    }
    return errors;
}

int halo_host_check_calls(const halo_program *p, const halo_host_info *h, const char *host, halo_diagnostics *diag)
{
    halo_host_text t = {host, p->host_file, p->host_lines, "host"};
    return halo_host_check_calls_in(p, h, &t, diag);
}

int halo_host_check_calls_in(const halo_program *p, const halo_host_info *h, const halo_host_text *t,
                             halo_diagnostics *diag)
{
    int errors = 0;
    halo_strbuf stages = {0}, why = {0};
    for (size_t s = 0; s < p->stage_count; s++)
        if (p->stages[s].module->hook != HALO_HOOK_IMAGE)
            halo_strbuf_printf(&stages, "%s%s", stages.len ? ", " : "", p->stages[s].module->name);
    if (stages.len) {
        halo_strbuf_printf(&why,
                           "the scene links the stages %s, which run only inside halo_apply: call it once per "
                           "sample (docs/host-contract.md)",
                           stages.data);
        errors +=
            require_call(p, h, t, "halo_apply", HALO_MSG_HOST_APPLY_MISSING, why.data ? why.data : "call it", diag);
    }
    if (p->output_count) {
        halo_strbuf_free(&why);
        halo_strbuf_printf(&why,
                           "the linked stages write extra outputs (%s...), so the host must call "
                           "halo_finish() once per fragment before it returns (docs/image-passes.md)",
                           p->outputs[0].name);
        errors +=
            require_call(p, h, t, "halo_finish", HALO_MSG_HOST_FINISH_MISSING, why.data ? why.data : "call it", diag);
    }
    halo_host_hit unused;
    int begins = halo_host_scan_find_call(&h->scan, "halo_segment_begin", &unused),
        ends = halo_host_scan_find_call(&h->scan, "halo_segment_end", &unused);
    if (p->segment_location > 0 || begins || ends) {
        /* drawn in segments: each draw clips its rays to its segment and carries their state on */
        static const char why_segments[] =
            "a ray loop drawn in depth segments (the program's image passes run between them, or the text calls "
            "one of the two) starts with halo_segment_begin and ends with halo_segment_end, which stores the "
            "ray's state for the next segment (docs/host-contract.md, \"Segmented ray casting\")";
        errors += require_call(p, h, t, "halo_segment_begin", HALO_MSG_HOST_SEGMENT_CALLS, why_segments, diag);
        errors += require_call(p, h, t, "halo_segment_end", HALO_MSG_HOST_SEGMENT_CALLS, why_segments, diag);
        if (p->segment_location > 0)
            errors += segment_discards(h, t, diag);
    }
    halo_strbuf_free(&stages);
    halo_strbuf_free(&why);
    return errors;
}

/* The host's outputs need explicit locations when libhalo adds outputs of its own: the
 * compiler would place an output without one anywhere, possibly on libhalo's. */
int halo_host_check_outputs(const halo_program *p, const halo_host_info *h, const char *host, halo_diagnostics *diag)
{
    const halo_host_text text = {host, p->host_file, p->host_lines, "host"}, *t = &text;
    if ((!p->output_count && !p->segment_location) || p->kind != HALO_SHADER_FRAGMENT)
        return 0;
    if (p->unlocated_outputs)
        return 0; /* every output is bound by name before linking */
    halo_host_hit at[16];
    size_t n = halo_host_scan_unlocated_outputs(&h->scan, t->source, at, sizeof at / sizeof at[0]);
    for (size_t i = 0; i < n && i < sizeof at / sizeof at[0]; i++)
        host_diag(h, diag, HALO_MSG_HOST_OUTPUT_LOCATION, t->file, t->lines, at[i].line, at[i].column,
                  "this output has no layout(location), but the program adds outputs of its own at location %d "
                  "and up (libhalo takes the first locations after the highest the host declares); declare it "
                  "'layout(location = 0) out ...' (each host output at its own location)",
                  p->output_count ? p->outputs[0].location : p->segment_location);
    return (int)n;
}

/* A host macro defined at the marker rewrites every use of its name in the declarations
 * that replace the marker (a halo_sample field, a local of libhalo's code). */
int halo_host_check_macros(const halo_program *p, const halo_host_info *h, halo_diagnostics *diag)
{
    int first = 0, last = 0, errors = 0;
    for (int i = 0; i < p->origin_count; i++)
        if (p->origins[i].file == p->host_file && p->origins[i].line == h->marker_line) {
            if (!first)
                first = i + 1;
            last = i + 1;
        }
    halo_token_list t;
    if (!first || halo_lex(p->source, &t))
        return 0;
    for (size_t m = 0; m < h->scan.marker_macro_count; m++) {
        const halo_host_macro *mac =
            halo_host_scan_macro(&h->scan, h->scan.marker_macros[m].name, h->scan.marker_macros[m].length);
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
int halo_host_hide_line_directives(halo_program *p, const halo_host_info *h)
{
    for (int i = 0; i < h->scan.line_count; i++) {
        if (!h->scan.lines[i].line_directive)
            continue;
        char *comment = halo_program_own(p, "// %s (libhalo: applied to the line map)", p->host_lines[i]);
        if (!comment)
            return -1;
        p->host_lines[i] = comment;
    }
    return 0;
}

/* Host lines of the program's line map at the origins the host's #line directives give. */
int halo_host_map_lines(halo_program *p, const halo_host_info *h)
{
    for (int i = 0; i < p->origin_count; i++) {
        halo_line_origin *o = &p->origins[i];
        if (o->file != p->host_file)
            continue;
        const char *file;
        halo_host_scan_origin(&h->scan, p->host_file, o->line, &file, &o->line);
        if (file == p->host_file)
            continue;
        o->file = NULL;
        for (size_t k = 0; k < p->string_count && !o->file; k++)
            if (!strcmp(p->strings[k], file))
                o->file = p->strings[k];
        if (!o->file && !(o->file = halo_program_own(p, "%s", file)))
            return -1;
    }
    return 0;
}
