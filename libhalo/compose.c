/* Link modes for shader composers (docs/composers.md).
 *
 * Engines such as VTK compose their fragment shader at run time from a template and
 * tagged replacements, so there is no host text to link into. A link from pieces
 * (halo_link_desc.pieces, host_source NULL) returns the declarations and the per-sample
 * and finish snippets as separate strings, each with its line map, for the engine to put
 * in its own tags; halo_validate (composed) checks the shader the engine composed,
 * with errors mapped back to the modules and to the composer's pieces.
 *
 * How: the linker's product is libhalo's block and its tail (emit.c: halo_program.block,
 * .tail, each line with its origin); linking into host text splices them into the host
 * at its marker and after its last line. The pieces are linked against a small host
 * written here (what the host declares and calls, and a complete shader for
 * halo_validate), and the declarations piece is that product itself. The sample snippet
 * is written twice: with this host's names for the program, with the composer's
 * expressions for the piece. */
#include "diag.h"
#include "glsl_lex.h"
#include "host_check.h"
#include "internal.h"
#include "strbuf.h"

#include <ctype.h>
#include <stdlib.h>
#include <string.h>

static const char pieces_host_file[] = "(libhalo pieces host)";

/* The names the pieces host declares: also the defaults of halo_pieces_desc. */
typedef struct sample_names {
    const char *position, *value, *gradient, *view, *depth, *fragcoord, *color;
} sample_names;

static const sample_names host_names = {"position", "value", "gradient", "view", "depth", "gl_FragCoord.xy", "color"};

/* The per-sample snippet: derived inputs where the composer gives none. */
static void write_sample(halo_strbuf *b, const sample_names *n, const halo_pieces_desc *d)
{
    halo_strbuf b_grad = {0}, b_view = {0}, b_depth = {0};
    if (d->gradient)
        halo_strbuf_append(&b_grad, n->gradient);
    else
        halo_strbuf_printf(&b_grad, "halo_gradient_at(%s)", n->position);
    if (d->view)
        halo_strbuf_append(&b_view, n->view);
    else
        halo_strbuf_printf(&b_view, "halo_view_at(%s)", n->position);
    if (d->depth)
        halo_strbuf_append(&b_depth, n->depth);
    else
        halo_strbuf_printf(&b_depth, "halo_depth_at(%s)", n->position);
    halo_strbuf_printf(b,
                       "{\n"
                       "    halo_sample libhalo_s = halo_make_sample(%s, %s, %s,\n"
                       "                                             %s, %s, %s, (%s).rgb, (%s).a);\n"
                       "    halo_apply(libhalo_s);\n"
                       "    %s = vec4(libhalo_s.color, libhalo_s.opacity);\n"
                       "}\n",
                       n->position, n->value, b_grad.data ? b_grad.data : "", b_view.data ? b_view.data : "",
                       b_depth.data ? b_depth.data : "", n->fragcoord, n->color, n->color, n->color);
    if (b_grad.failed || b_view.failed || b_depth.failed)
        b->failed = 1;
    halo_strbuf_free(&b_grad);
    halo_strbuf_free(&b_view);
    halo_strbuf_free(&b_depth);
}

/* The host the pieces are linked into. */
static char *pieces_host(const halo_pieces_desc *d, const halo_link_desc *desc)
{
    halo_strbuf b = {0};
    if (desc->target == HALO_TARGET_GLSL150 && desc->output_locations == HALO_LOCATIONS_EXTENSION)
        halo_strbuf_append(&b, "#extension GL_ARB_explicit_attrib_location : require\n");
    halo_strbuf_append(&b, "#pragma halo declarations\n");
    if (d->gradient_texture)
        halo_strbuf_append(&b, "#pragma halo gradient piece_gradient\n");
    else if (d->volume)
        halo_strbuf_append(&b, "#pragma halo volume piece_volume\n");
    if (d->gradient_texture)
        halo_strbuf_append(&b, "uniform sampler3D piece_gradient;\n");
    if (d->volume)
        halo_strbuf_append(&b, "uniform sampler3D piece_volume;\n");
    int located = desc->output_locations == HALO_LOCATIONS_EXTENSION ||
                  (desc->output_locations == HALO_LOCATIONS_AUTO && desc->target != HALO_TARGET_GLSL150);
    halo_strbuf_printf(&b, "%sout vec4 piece_output;\n", located ? "layout(location = 0) " : "");
    halo_strbuf_append(&b,
                       "void main() {\n"
                       "    vec3 position = vec3(0.5);\n"
                       "    float value = 0.5;\n"
                       "    vec3 gradient = vec3(0.0, 0.0, 0.1);\n"
                       "    vec3 view = vec3(0.0, 0.0, 1.0);\n"
                       "    float depth = 0.5;\n"
                       "    vec4 color = vec4(0.5);\n");
    if (d->segmented)
        halo_strbuf_append(&b,
                           "    int first = 0, end = 2;\n"
                           "    vec4 state = vec4(0.0);\n"
                           "    halo_segment_begin(position, view, 0.0, 0.01, first, end, state);\n"
                           "    for (int i = first; i < end; ++i)\n");
    write_sample(&b, &host_names, d);
    if (d->segmented)
        halo_strbuf_append(&b, "    halo_segment_end(state, false);\n");
    halo_strbuf_append(&b,
                       "    halo_finish();\n"
                       "    piece_output = color;\n"
                       "} // end of the pieces host\n");
    return halo_strbuf_take(&b);
}

/* Replaces the identifier from by the expression to, outside other identifiers. */
static char *replace_identifier(const char *text, const char *from, const char *to)
{
    halo_strbuf b = {0};
    size_t n = strlen(from);
    const char *p = text;
    for (const char *hit; (hit = strstr(p, from)) != NULL; p = hit + n) {
        int before = hit > text && (hit[-1] == '_' || isalnum((unsigned char)hit[-1]));
        int after = hit[n] == '_' || isalnum((unsigned char)hit[n]);
        halo_strbuf_append_n(&b, p, (size_t)(hit - p));
        halo_strbuf_append(&b, before || after ? from : to);
    }
    halo_strbuf_append(&b, p);
    return halo_strbuf_take(&b);
}

/* Lines of a text, counted: a final line without '\n' counts. */
static int count_lines(const char *text)
{
    int n = 0;
    for (const char *p = text; *p; p++)
        n += *p == '\n';
    return n + (*text && text[strlen(text) - 1] != '\n');
}

/* The declarations piece: the linker's product (libhalo's block, which replaced the pieces
 * host's marker, and its tail), its two host-origin lines (the block's opening and closing
 * comments) libhalo's own; the pieces host's sampler names become the composer's
 * expressions. */
static int set_declarations(halo_program *p, const halo_pieces_desc *d)
{
    const halo_linked_text *parts[2] = {&p->block, &p->tail};
    int n = p->block.count + p->tail.count;
    halo_line_origin *origins = calloc((size_t)n + 1, sizeof *origins);
    halo_strbuf b = {0};
    for (int k = 0, at = 0; origins && k < 2; k++) {
        halo_strbuf_append(&b, parts[k]->text ? parts[k]->text : "");
        for (int i = 0; i < parts[k]->count; i++, at++) {
            origins[at] = parts[k]->origins[i];
            if (origins[at].file == p->host_file)
                origins[at] = (halo_line_origin){halo_pieces_file, 0, NULL};
        }
    }
    char *text = b.failed ? (halo_strbuf_free(&b), NULL) : halo_strbuf_take(&b);
    char *named = text && d->volume ? replace_identifier(text, "piece_volume", d->volume) : text;
    if (named != text)
        free(text);
    char *named2 =
        named && d->gradient_texture ? replace_identifier(named, "piece_gradient", d->gradient_texture) : named;
    if (named2 != named)
        free(named);
    if (!origins || !named2) {
        free(origins);
        free(named2);
        return -1;
    }
    p->pieces[HALO_PIECE_DECLARATIONS] = named2;
    p->piece_origins[HALO_PIECE_DECLARATIONS] = origins;
    p->piece_origin_counts[HALO_PIECE_DECLARATIONS] = n;
    return 0;
}

/* A piece written here: every line is libhalo's own. */
static int set_generated_piece(halo_program *p, halo_piece piece, char *text)
{
    if (!text)
        return -1;
    int n = count_lines(text);
    halo_line_origin *origins = calloc((size_t)n + 1, sizeof *origins);
    if (!origins) {
        free(text);
        return -1;
    }
    for (int i = 0; i < n; i++)
        origins[i] = (halo_line_origin){halo_pieces_file, i + 1, NULL};
    p->pieces[piece] = text;
    p->piece_origins[piece] = origins;
    p->piece_origin_counts[piece] = n;
    return 0;
}

/* Does text declare name as a uniform: the identifier in a declaration that starts with
 * the keyword "uniform" (outside comments: the tokens), up to its ';'? (A link without the
 * parameter live has a constant of that name.) -1 when memory ran out. */
static int declares_uniform(const char *text, const char *name)
{
    halo_token_list t = {0};
    if (halo_lex(text, &t) != 0)
        return -1;
    int found = 0;
    for (size_t i = 0; i < t.count && !found; i++) {
        if (t.items[i].kind != HALO_TOK_IDENT || !halo_token_is(text, &t.items[i], "uniform"))
            continue;
        for (size_t j = i + 1; j < t.count && !halo_token_is(text, &t.items[j], ";"); j++)
            if (t.items[j].kind == HALO_TOK_IDENT && halo_token_is(text, &t.items[j], name)) {
                found = 1;
                break;
            }
    }
    halo_token_list_free(&t);
    return found;
}

/* With engine_uniforms, the pieces host declares the live parameters as the engine would
 * (from the reflection's declarations), after its #version line, so that it validates. */
static int declare_engine_uniforms(halo_program *p)
{
    halo_strbuf b = {0};
    int added = 0;
    for (size_t i = 0; i < p->declaration_count; ++i) {
        const halo_uniform_decl *u = &p->declarations[i];
        if (u->name && u->array_size)
            halo_strbuf_printf(&b, "uniform %s %s[%d];\n", u->glsl_type, u->name, u->array_size), added++;
        else if (u->name)
            halo_strbuf_printf(&b, "uniform %s %s;\n", u->glsl_type, u->name), added++;
        if (u->count_name)
            halo_strbuf_printf(&b, "uniform int %s;\n", u->count_name), added++;
    }
    if (!added)
        return 0;
    /* after the #version line and the precision statements (GLSL ES: a float uniform
     * before them has no precision) */
    const char *nl = strchr(p->source, '\n');
    size_t head = nl ? (size_t)(nl - p->source) + 1 : 0;
    int first = nl ? 1 : 0;
    while (nl && (!strncmp(p->source + head, "precision ", 10) || !strncmp(p->source + head, "#extension ", 11))) {
        nl = strchr(p->source + head, '\n');
        head = nl ? (size_t)(nl - p->source) + 1 : strlen(p->source);
        first++;
    }
    halo_strbuf text = {0};
    halo_strbuf_append_n(&text, p->source, head);
    halo_strbuf_append(&text, b.data ? b.data : "");
    halo_strbuf_append(&text, p->source + head);
    halo_strbuf_free(&b);
    halo_line_origin *origins = calloc((size_t)(p->origin_count + added), sizeof *origins);
    char *source = halo_strbuf_take(&text);
    if (!origins || !source) {
        free(origins);
        free(source);
        return -1;
    }
    memcpy(origins, p->origins, (size_t)first * sizeof *origins);
    for (int i = 0; i < added; i++)
        origins[first + i] = (halo_line_origin){halo_generated_file, 0, NULL};
    memcpy(origins + first + added, p->origins + first, (size_t)(p->origin_count - first) * sizeof *origins);
    free(p->source);
    free(p->origins);
    p->source = source;
    p->origins = origins;
    p->origin_count += added;
    return 0;
}

halo_program *halo_link_pieces(const halo_link_desc *desc, halo_diagnostics *diag)
{
    const halo_pieces_desc *d = desc->pieces;
    if (desc->kind != HALO_SHADER_FRAGMENT) {
        halo_diag_error(diag, USAGE, "", 0, 0, "halo_link: pieces are for fragment shaders (per-sample stages)");
        return NULL;
    }
    if (!d->gradient && !d->volume && !d->gradient_texture) {
        halo_diag_error(diag, USAGE, "", 0, 0,
                        "halo_link: the pieces need a gradient: an expression (halo_pieces_desc.gradient), the "
                        "volume's sampler to derive it from (volume) or a gradient texture (gradient_texture)");
        return NULL;
    }
    if (halo_pieces_check_expressions(d, desc->target, diag))
        return NULL;
    char *host = pieces_host(d, desc);
    if (!host) {
        halo_diag_error(diag, OUT_OF_MEMORY, "", 0, 0, "out of memory");
        return NULL;
    }
    halo_link_desc inner = *desc;
    inner.pieces = d;
    inner.host_source = host;
    inner.host_file = pieces_host_file;
    inner.version = HALO_VERSION_TARGET;
    halo_program *p = halo_link_host(&inner, diag);
    free(host);
    if (!p)
        return NULL;
    if (!d->segmented && !p->one_draw && halo_program_has_generation_passes(p)) {
        halo_strbuf stages = {0};
        for (size_t s = 0; s < p->stage_count; s++)
            for (size_t k = 0; k < p->stages[s].module->pass_count; k++)
                if (!p->stages[s].module->passes[k].at) {
                    halo_strbuf_printf(&stages, "%s%s", stages.len ? ", " : "", p->stages[s].module->name);
                    break;
                }
        halo_diag_error(
            diag, HOST_SINGLE_PASS, "", 0, 0,
            "the scene's stages %s run image passes between depth segments, but the pieces were "
            "linked for a single pass: link with one_draw (host contract 3: libhalo computes the halo field "
            "before the engine draws once) or set halo_pieces_desc.segmented and call halo_segment_begin "
            "/ halo_segment_end in the ray loop (docs/host-contract.md)",
            stages.data ? stages.data : "?");
        halo_strbuf_free(&stages);
        halo_program_destroy(p);
        return NULL;
    }
    sample_names names = {
        d->position ? d->position : host_names.position, d->value ? d->value : host_names.value,
        d->gradient ? d->gradient : host_names.gradient, d->view ? d->view : host_names.view,
        d->depth ? d->depth : host_names.depth,          d->fragcoord ? d->fragcoord : host_names.fragcoord,
        d->color ? d->color : host_names.color,
    };
    halo_strbuf sample = {0};
    write_sample(&sample, &names, d);
    if (sample.failed || set_declarations(p, d) || (p->engine_uniforms && declare_engine_uniforms(p)) ||
        set_generated_piece(p, HALO_PIECE_SAMPLE, halo_strbuf_take(&sample)) ||
        set_generated_piece(p, HALO_PIECE_FINISH, halo_strdup("halo_finish();\n"))) {
        halo_strbuf_free(&sample);
        halo_program_destroy(p);
        halo_diag_error(diag, OUT_OF_MEMORY, "", 0, 0, "out of memory");
        return NULL;
    }
    return p;
}

/* The line (0-based) of offset in text. */
static int line_of(const char *text, size_t offset)
{
    int n = 0;
    for (size_t i = 0; i < offset && text[i]; i++)
        n += text[i] == '\n';
    return n;
}

static halo_status validate_composed_held(const halo_program *p, const char *composed, const char *composed_file,
                                          const halo_composer_piece *pieces, size_t piece_count,
                                          halo_diagnostics *diag);

halo_status halo_validate_composed(const halo_program *p, const char *composed, const char *composed_file,
                                   const halo_composer_piece *pieces, size_t piece_count, halo_diagnostics *diag)
{
    HALO_REFUSE_NULL(diag, p, "program", HALO_ERROR_INPUT);
    HALO_REFUSE_NULL(diag, composed, "composed", HALO_ERROR_INPUT);
    if (piece_count)
        HALO_REFUSE_NULL(diag, pieces, "pieces (with a piece_count)", HALO_ERROR_INPUT);
    return HALO_WITH_GLSLANG(diag, validate_composed_held(p, composed, composed_file, pieces, piece_count, diag));
}

/* text with its CRLF line ends as LF (an engine on Windows, a file saved there): the
 * pieces are found, and lines counted, the same either way. */
static char *without_carriage_returns(const char *text)
{
    char *out = halo_strdup(text), *w = out;
    for (const char *r = text; out && *r; r++)
        if (!(r[0] == '\r' && r[1] == '\n'))
            *w++ = *r;
    if (out)
        *w = '\0';
    return out;
}

static int no_marker(const char *line)
{
    (void)line;
    return 0;
}

/* The composed shader keeps the contract as a host does: it calls halo_apply (the sample
 * piece), halo_finish (the finish piece) and the segment calls where the program needs
 * them. Returns the error count. */
static int check_composed_contract(const halo_program *p, const char *text, const char *file, char **lines,
                                   halo_diagnostics *diag)
{
    /* the engine's text alone: the declarations piece (which defines those functions) blanked */
    char *engine = halo_strdup(text);
    const char *decl = p->pieces[HALO_PIECE_DECLARATIONS];
    char *at = engine && decl && *decl ? strstr(engine, decl) : NULL;
    for (size_t i = 0; at && i < strlen(decl); i++)
        if (at[i] != '\n')
            at[i] = ' ';
    halo_host_info h = {0};
    int errors = -1;
    if (engine && !halo_host_scan_run(&(halo_host_scan_desc){engine, p->target, p->kind, no_marker}, &h.scan)) {
        halo_host_text t = {engine, file, lines, "composed shader"};
        /* not its outputs' locations: an engine binds its own (VTK: glBindFragDataLocation) */
        errors = halo_host_check_calls_in(p, &h, &t, diag);
    }
    halo_host_scan_free(&h.scan);
    free(engine);
    return errors;
}

static halo_status validate_composed_held(const halo_program *p, const char *composed, const char *composed_file,
                                          const halo_composer_piece *pieces, size_t piece_count, halo_diagnostics *diag)
{
    if (!composed_file)
        composed_file = "composed shader";
    char *text = without_carriage_returns(halo_skip_bom(composed));
    char *copy = text ? halo_strdup(text) : NULL;
    char **lines = NULL;
    int count = copy ? halo_split_lines(copy, &lines) : -1;
    halo_line_origin *origins = count >= 0 ? calloc((size_t)count + 1, sizeof *origins) : NULL;
    if (!origins) {
        free(lines);
        free(copy);
        free(text);
        halo_diag_error(diag, OUT_OF_MEMORY, "", 0, 0, "out of memory");
        return HALO_ERROR_IO;
    }
    for (int i = 0; i < count; i++)
        origins[i] = (halo_line_origin){composed_file, i + 1, lines[i]};
    /* the composer's pieces, then libhalo's (which may sit inside a composer piece) */
    for (size_t k = 0; k < piece_count; k++) {
        char *piece = pieces[k].text && *pieces[k].text ? without_carriage_returns(pieces[k].text) : NULL;
        const char *at = piece ? strstr(text, piece) : NULL;
        int first = at ? line_of(text, (size_t)(at - text)) : 0, n = at ? count_lines(piece) : 0;
        for (int i = 0; i < n && first + i < count; i++)
            origins[first + i] =
                (halo_line_origin){pieces[k].name ? pieces[k].name : "composer piece", i + 1, lines[first + i]};
        free(piece);
    }
    int missing = 0;
    for (int k = 0; k < HALO_PIECE_COUNT; k++) {
        const char *piece = p->pieces[k];
        if (!piece)
            continue;
        const char *at = strstr(text, piece);
        if (!at) {
            missing += k == HALO_PIECE_DECLARATIONS;
            continue;
        }
        /* a module's line keeps its origin; a line libhalo wrote stays the composed shader's own */
        int first = line_of(text, (size_t)(at - text));
        for (int i = 0; i < p->piece_origin_counts[k] && first + i < count; i++) {
            halo_line_origin o = p->piece_origins[k][i];
            if (o.file != halo_pieces_file && o.file != halo_generated_file && o.line)
                origins[first + i] = o;
        }
    }
    if (missing)
        halo_diagnostics_report(diag, HALO_SEVERITY_WARNING, HALO_MSG_USAGE, composed_file, 0, 0, NULL,
                                "the program's declarations piece is not in the composed shader (or was changed): its "
                                "errors are reported at the composed shader's lines");
    /* the live uniforms this link's declarations piece declares must be in the text (a
     * shader composed from another link's pieces compiles, and the values set for this
     * program reach nothing); with engine_uniforms the engine declares them itself */
    int stale = 0;
    for (size_t u = 0; u < p->uniform_count && !p->engine_uniforms; u++)
        if (p->uniforms[u].live && p->pieces[HALO_PIECE_DECLARATIONS] &&
            declares_uniform(p->pieces[HALO_PIECE_DECLARATIONS], p->uniforms[u].name) == 1 &&
            declares_uniform(text, p->uniforms[u].name) == 0) {
            halo_diagnostics_report(diag, HALO_SEVERITY_ERROR, HALO_MSG_USAGE, composed_file, 0, 0, NULL,
                                    "the composed shader has no uniform %s (%s.%s, live in this program): it was "
                                    "composed from other pieces; compose it again from this link's pieces",
                                    p->uniforms[u].name, p->uniforms[u].stage, p->uniforms[u].param);
            stale = 1;
            break;
        }
    int contract = check_composed_contract(p, text, composed_file, lines, diag);
    halo_status st = contract < 0
                         ? HALO_ERROR_IO
                         : halo_glslang_validate(text, p->kind, p->target, origins, count, composed_file, diag);
    if (contract < 0)
        halo_diag_error(diag, OUT_OF_MEMORY, "", 0, 0, "out of memory");
    else if ((contract > 0 || stale) && st == HALO_OK)
        st = HALO_ERROR_INPUT;
    free(origins);
    free(lines);
    free(copy);
    free(text);
    return st;
}
