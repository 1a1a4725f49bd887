/* Emission (emit.h): the linked program's text, line by line, each line with its
 * origin (module or host file:line, or libhalo's own): parameters as constants or
 * uniforms, module code with its private names renamed, helpers, the declarations
 * that replace the host's marker, and the whole program around the host. The
 * linker (link.c) and its image passes use it. */
#include "emit.h"
#include "diag.h"
#include "internal.h"
#include "strbuf.h"

#include <ctype.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* ---- Output with origins ---- */


void halo_emit(halo_emitter *e, const char *file, int line, const char *original, const char *fmt, ...)
{
    /* fmt may hold several lines: each gets the same origin. */
    halo_strbuf b = {0};
    va_list ap;
    va_start(ap, fmt);
    halo_strbuf_vprintf(&b, fmt, ap);
    va_end(ap);
    if (b.failed || !b.data) {
        e->failed = 1;
        halo_strbuf_free(&b);
        return;
    }
    for (char *p = b.data;;) {
        char *nl = strchr(p, '\n');
        size_t n = nl ? (size_t)(nl - p) : strlen(p);
        if (e->count == e->cap) {
            int cap = e->cap ? e->cap * 2 : 256;
            halo_line_origin *o = realloc(e->origins, (size_t)cap * sizeof *o);
            if (!o) {
                e->failed = 1;
                break;
            }
            e->origins = o;
            e->cap = cap;
        }
        e->origins[e->count++] = (halo_line_origin){file, line, original};
        halo_strbuf_append_n(&e->text, p, n);
        halo_strbuf_append(&e->text, "\n");
        if (!nl || !nl[1])
            break;
        p = nl + 1;
    }
    halo_strbuf_free(&b);
}

/* ---- The program's text ---- */

static void format_number(char *buf, size_t len, double v, halo_param_type t)
{
    if (t == HALO_PARAM_INT) {
        snprintf(buf, len, "%d", (int)v);
        return;
    }
    if (t == HALO_PARAM_BOOL) {
        snprintf(buf, len, "%s", v != 0 ? "true" : "false");
        return;
    }
    snprintf(buf, len, "%.9g", v);
    if (!strpbrk(buf, ".e"))
        strncat(buf, ".0", len - strlen(buf) - 1);
}

static void format_element(halo_strbuf *b, const halo_param_info *info, const double *v)
{
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
int halo_module_uses(const halo_module *m, const char *name)
{
    for (size_t i = 0; i < m->tokens.count; i++) {
        const halo_token *t = &m->tokens.items[i];
        if (t->kind == HALO_TOK_IDENT && halo_token_is(m->source, t, name) &&
            !(i > 0 && halo_token_is(m->source, &m->tokens.items[i - 1], ".")))
            return 1;
    }
    return 0;
}

/* engine: the program's live parameters are declared by the engine (not in image passes) */
void halo_emit_params(halo_emitter *e, const halo_program *p, const halo_linked_stage *st, int engine)
{
    const halo_module *m = st->module;
    for (size_t i = 0; i < m->param_count; i++) {
        const halo_param_info *info = &m->params[i];
        const halo_uniform_info *u = &p->uniforms[st->first_uniform + i];
        halo_strbuf count_name = {0};
        if (info->array_size)
            halo_strbuf_printf(&count_name, "%s_count", info->name);
        int used = halo_module_uses(m, info->name);
        int count_used = info->array_size && count_name.data && halo_module_uses(m, count_name.data);
        if (count_name.failed)
            e->failed = 1;
        halo_strbuf_free(&count_name);
        if (!used && !count_used)
            continue;
        const char *type = halo_param_type_name(info->type);
        int line = m->param_lines[i];
        const char *orig = m->lines[line - 1];
        if (u->live && engine) {
            /* declared by the engine from the reflection (halo_reflection.declarations) */
            halo_emit(e, m->file, line, orig, "// uniform %s %s%s; (declared by the engine%s)",
                      info->type == HALO_PARAM_BOOL       ? "int"
                      : info->type == HALO_PARAM_CHANNELS ? "halo_channels"
                                                          : type,
                      u->name, info->array_size && used && info->type != HALO_PARAM_CHANNELS ? "[]" : "",
                      count_used ? ", with NAME_count" : "");
            continue;
        }
        if (u->live) {
            if (info->type == HALO_PARAM_CHANNELS) {
                halo_emit(e, m->file, line, orig, "uniform halo_channels %s;", u->name);
            } else if (info->array_size) {
                if (used)
                    halo_emit(e, m->file, line, orig, "uniform %s %s[%d];", type, u->name, info->array_size);
                if (count_used)
                    halo_emit(e, m->file, line, orig, "uniform int %s_count;", u->name);
            } else {
                halo_emit(e, m->file, line, orig, "uniform %s %s;", type, u->name);
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
            if (count_used)
                halo_emit(e, m->file, line, orig, "const int %s_count = %d;", u->name, u->count);
            if (!used)
                continue;
            halo_strbuf_printf(&b, "const %s %s[%d] = %s[%d](", type, u->name, u->count, type, u->count);
            for (int k = 0; k < u->count; k++) {
                if (k)
                    halo_strbuf_append(&b, ", ");
                format_element(&b, info, u->value + k * info->components);
            }
            halo_strbuf_append(&b, ");");
        } else {
            halo_strbuf_printf(&b, "const %s %s = ", type, u->name);
            format_element(&b, info, u->value);
            halo_strbuf_append(&b, ";");
        }
        if (b.data)
            halo_emit(e, m->file, line, orig, "%s", b.data);
        else
            e->failed = 1;
        halo_strbuf_free(&b);
    }
}

/* Copies lines [first, last] of m, renaming its private names and parameters. engine: a
 * program whose live parameters the engine declares, a bool one as int (read as
 * (NAME != 0)). */
void halo_emit_module_lines(halo_emitter *e, const halo_module *m, int first, int last, int rename,
                            const halo_program *engine)
{
    size_t t = 0;
    halo_strbuf ident = {0};
    for (int li = first; li <= last && li <= m->line_count; li++) {
        if (m->is_annotation[li - 1])
            continue;
        const char *line = m->lines[li - 1];
        size_t start = (size_t)(line - m->line_storage), len = strlen(line);
        const char *p = line;
        while (*p == ' ' || *p == '\t')
            p++;
        if (!*p)
            continue;
        halo_strbuf b = {0};
        size_t pos = start;
        while (t < m->tokens.count && m->tokens.items[t].offset < start)
            t++;
        for (; t < m->tokens.count && m->tokens.items[t].offset < start + len; t++) {
            const halo_token *k = &m->tokens.items[t];
            if (!rename || k->kind != HALO_TOK_IDENT)
                continue;
            if (t > 0 && halo_token_is(m->source, &m->tokens.items[t - 1], "."))
                continue;
            /* the identifier whole, whatever its length (a truncated one would keep its name) */
            size_t n = k->length;
            halo_strbuf_set_n(&ident, m->source + k->offset, n);
            if (ident.failed) {
                e->failed = 1;
                break;
            }
            const char *name = ident.data, *base = name;
            int is_count = 0;
            if (n > 6 && !strcmp(name + n - 6, "_count")) {
                ident.data[n - 6] = '\0'; /* the stem, for a moment */
                const halo_param_info *pi = halo_module_find_param(m, ident.data);
                ident.data[n - 6] = '_';
                is_count = pi && pi->array_size;
            }
            if (!is_count && !halo_name_list_has(&m->declared, base) && !halo_module_find_param(m, base))
                continue;
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
            if (b.len && b.data[b.len - 1] == '\r')
                b.data[--b.len] = '\0';
            halo_emit(e, m->file, li, line, "%s", b.data);
        } else {
            e->failed = 1;
        }
        halo_strbuf_free(&b);
    }
    halo_strbuf_free(&ident);
}

void halo_emit_helpers(halo_emitter *e, const halo_library *lib, const halo_program *p)
{
    const halo_module *h = halo_library_helpers(lib);
    if (!h || !h->chunk_count)
        return;
    unsigned char *need = calloc(h->chunk_count, 1);
    if (!need) {
        e->failed = 1;
        return;
    }
    for (size_t c = 0; c < h->chunk_count; c++)
        for (size_t s = 0; s < p->stage_count; s++)
            if (halo_name_list_has(&p->stages[s].module->calls, h->chunks[c].name))
                need[c] = 1;
    for (int changed = 1; changed;) {
        changed = 0;
        for (size_t c = 0; c < h->chunk_count; c++) {
            if (!need[c])
                continue;
            for (size_t d = 0; d < h->chunk_count; d++)
                if (!need[d] && halo_name_list_has(&h->chunks[c].calls, h->chunks[d].name))
                    need[d] = changed = 1;
        }
    }
    for (size_t c = 0; c < h->chunk_count; c++)
        if (need[c])
            halo_emit_module_lines(e, h, h->chunks[c].first_line, h->chunks[c].last_line, 0, NULL);
    free(need);
}

/* A struct is emitted when a linked stage runs at its hook or the host names it. */
static int hook_needed(const halo_program *p, const halo_hook_struct *hs, const char *host)
{
    for (size_t s = 0; s < p->stage_count; s++)
        if (p->stages[s].module->hook == hs->hook)
            return 1;
    if (hs->hook == HALO_HOOK_SAMPLE && p->kind == HALO_SHADER_FRAGMENT && !strstr(host, "halo_line_fragment"))
        return 1; /* the classic host: halo_sample and halo_apply always exist */
    return strstr(host, hs->type) != NULL;
}

/* Does any linked stage use per-halo channels? */
static int uses_channels(const halo_program *p)
{
    if (p->image_count || p->output_count || p->sampler_count)
        return 1;
    for (size_t s = 0; s < p->stage_count; s++) {
        const halo_module *m = p->stages[s].module;
        for (size_t i = 0; i < m->calls.count; i++)
            if (!strncmp(m->calls.items[i], "halo_channel", 12))
                return 1;
        for (size_t i = 0; i < m->param_count; i++)
            if (m->params[i].type == HALO_PARAM_CHANNELS)
                return 1;
    }
    return 0;
}

void halo_emit_channel_definitions(halo_emitter *e, int c)
{
    static const char *const type[] = {"float", "float", "vec2", "vec3", "vec4"};
    static const char *const from[] = {"v.x", "v.x", "v.xy", "v.xyz", "v"};
    static const char *const to[] = {"vec4(v, 0.0, 0.0, 0.0)", "vec4(v, 0.0, 0.0, 0.0)", "vec4(v, 0.0, 0.0)",
                                     "vec4(v, 0.0)", "v"};
    HALO_GEN(e, "#define halo_channels %s\nconst int halo_channel_count = %d;", type[c], c);
    HALO_GEN(e, "float halo_channel(halo_channels v, int i) { return %s; }", c == 1 ? "v" : "v[i]");
    HALO_GEN(e, "halo_channels halo_channels_from(vec4 v) { return %s; }", from[c]);
    HALO_GEN(e, "vec4 halo_channels_to_vec4(halo_channels v) { return %s; }", to[c]);
}

/* GLSL type of an output: the program's halo_channels, or float/vecN for a fixed size. */
static const char *output_type(const halo_program *p, const halo_output_info *out)
{
    static const char *const types[] = {"float", "float", "vec2", "vec3", "vec4"};
    if (out->channel < 0 && out->components == p->channel_count)
        return "halo_channels";
    return types[out->components < 1 ? 1 : out->components > 4 ? 4 : out->components];
}


static void emit_declarations(halo_emitter *e, const halo_program *p, const char *host)
{
    HALO_GEN(e, "#define HALO_LINKED 1\n#define HALO_CONTRACT_VERSION %d", HALO_CONTRACT_VERSION);
    /* host contract 2: stages with extra outputs (seeds, feature buffers) read every sample
     * of a ray, hidden ones too, as the slice host gives them: the host's early ray
     * termination waits for this */
    HALO_GEN(e, "#define HALO_RAY_MAY_END %d", p->output_count == 0);
    if (uses_channels(p))
        halo_emit_channel_definitions(e, p->channel_count);
    for (size_t h = 0; h < halo_hook_struct_count; h++) {
        const halo_hook_struct *hs = &halo_hook_structs[h];
        if (!hook_needed(p, hs, host))
            continue;
        HALO_GEN(e, "struct %s {", hs->type);
        for (int i = 0; i < hs->field_count; i++)
            HALO_GEN(e, "    %s %s;", hs->fields[i][0], hs->fields[i][1]);
        for (size_t s = 0; s < p->stage_count; s++) {
            const halo_module *m = p->stages[s].module;
            if (m->hook != hs->hook)
                continue;
            for (size_t r = 0; r < m->provides_count; r++)
                halo_emit(e, m->file, m->provides[r].line, m->lines[m->provides[r].line - 1], "    %s %s;",
                          m->provides[r].type, m->provides[r].name);
        }
        HALO_GEN(e, "};");
        halo_strbuf sig = {0};
        for (int i = 0; i < hs->field_count; i++)
            halo_strbuf_printf(&sig, "%s%s %s", i ? ", " : "", hs->fields[i][0], hs->fields[i][1]);
        HALO_GEN(e, "%s %s(%s) {\n    %s %s;", hs->type, hs->make, sig.data ? sig.data : "", hs->type, hs->var);
        halo_strbuf_free(&sig);
        for (int i = 0; i < hs->field_count; i++)
            HALO_GEN(e, "    %s.%s = %s;", hs->var, hs->fields[i][1], hs->fields[i][1]);
        for (size_t s = 0; s < p->stage_count; s++) {
            const halo_module *m = p->stages[s].module;
            if (m->hook != hs->hook)
                continue;
            for (size_t r = 0; r < m->provides_count; r++) {
                const char *t = m->provides[r].type;
                char zero[32];
                if (!strncmp(t, "vec", 3) || !strncmp(t, "mat", 3) || !strcmp(t, "halo_channels"))
                    snprintf(zero, sizeof zero, "%s(0.0)", t);
                else
                    snprintf(zero, sizeof zero, "%s", !strcmp(t, "int") ? "0" : !strcmp(t, "bool") ? "false" : "0.0");
                HALO_GEN(e, "    %s.%s = %s;", hs->var, m->provides[r].name, zero);
            }
        }
        HALO_GEN(e, "    return %s;\n}", hs->var);
    }
    for (size_t o = 0; o < p->output_count; o++) {
        const halo_output_info *out = &p->outputs[o];
        const char *type = output_type(p, out);
        char layout[48];
        HALO_GEN(e, "%sout %s %s;", halo_output_layout(p, out->location, layout, sizeof layout), type, out->name);
        HALO_GEN(e, "%s halo_accum_%s = %s(%s);", type, out->image, type, out->blend == HALO_BLEND_MIN ? "1.0" : "0.0");
    }
    if (p->one_draw)
        /* host contract 3 (gl/field.c): the stack of the depth segments' images; segment j
         * reads layer j - 1, what the generation after segment j - 1 made (segment 0: zero) */
        HALO_GEN(
            e,
            "uniform vec4 halo_stack_plane;  // phi(P) = dot(xyz, P) + w: the segments' axis\n"
            "uniform vec3 halo_stack_slabs;  // x: phi where segment 0 begins, y: 1 / a segment's length, z: segments\n"
            "int halo_stack_layer = -1;      // the layer the current sample reads (halo_apply sets it)\n"
            "int halo_stack_layer_at(vec3 position) {\n"
            "    float k = floor((dot(halo_stack_plane.xyz, position) + halo_stack_plane.w - halo_stack_slabs.x) * halo_stack_slabs.y);\n"
            "    return k >= 1.0 ? int(min(k, halo_stack_slabs.z - 1.0)) - 1 : -1; // also NaN: -1\n"
            "}");
    for (size_t i = 0; i < p->sampler_count; i++) {
        const halo_sampler_info *sm = &p->samplers[i];
        int stacked = halo_prepass_image(p, sm->image);
        HALO_GEN(e, "uniform highp %s %s;", stacked ? "sampler2DArray" : "sampler2D", sm->name);
        if (halo_program_image_unread(p, sm->image)) {
            /* no pass writes it: it holds 0, read without a fetch */
            HALO_GEN(e, "halo_channels halo_read_%s(vec2 fragcoord) { return halo_channels(0.0); }", sm->image);
            continue;
        }
        /* a texel of the sampler: in the stack, of the sample's layer */
        const char *n = sm->name, *at = stacked ? "ivec3" : "", *layer = stacked ? ", halo_stack_layer" : "",
                   *xy = stacked ? ".xy" : "";
        const halo_image_info *im = halo_program_image_named((halo_program *)p, sm->image);
        int scale = im ? im->scale : 1;
        /* HALO_IMAGES_ZERO (a host's variant for pixels outside halo_gl_frame_info.read_box,
         * where every image read holds 0): no fetch, the same value */
        if (stacked)
            HALO_GEN(e,
                     "int halo_stack_%s_layer = -1;\nvec2 halo_stack_%s_at = vec2(-1.0);\n"
                     "halo_channels halo_stack_%s_value = halo_channels(0.0);\n"
                     "halo_channels halo_read_%s_texel(vec2 fragcoord) {",
                     sm->image, sm->image, sm->image, sm->image);
        else
            HALO_GEN(e,
                     "halo_channels halo_read_%s(vec2 fragcoord) {\n"
                     "#ifdef HALO_IMAGES_ZERO\n"
                     "    return halo_channels(0.0);\n"
                     "#else",
                     sm->image);
        if (scale > 1 && halo_program_image_filtered(p, im))
            /* a 1/scale image through the unit's bilinear filter (GL_LINEAR, CLAMP_TO_EDGE:
             * the runtime's textures): one fetch, the same weights as the four fetches
             * below where the filter computes them in float (llvmpipe); a GPU's filter
             * rounds them to its subtexel precision (8 bits on most) */
            HALO_GEN(e,
                     "    ivec2 size = textureSize(%s, 0)%s;\n"
                     "    if (any(greaterThanEqual(uvec2(ivec2(fragcoord)), uvec2(size * %d)))) // also pixel < 0\n"
                     "        return halo_channels(0.0);\n"
                     "    vec2 at = fragcoord / vec2(size * %d);\n"
                     "    return halo_channels_from(textureLod(%s, %s, 0.0)); // (level 0: no derivatives)",
                     n, xy, scale, scale, n, stacked ? "vec3(at, float(halo_stack_layer))" : "at");
        else if (scale > 1)
            /* a 1/scale image: bilinear between its four nearest pixel centres (clamped to
             * the image), written out so that the emulation can match it */
            HALO_GEN(
                e,
                "    ivec2 size = textureSize(%s, 0)%s;\n"
                "    ivec2 pixel = ivec2(fragcoord);\n"
                "    if (any(greaterThanEqual(uvec2(pixel), uvec2(size * %d)))) // also pixel < 0\n"
                "        return halo_channels(0.0);\n"
                "    vec2 at = fragcoord * (1.0 / %d.0) - 0.5;\n"
                "    vec2 corner = floor(at);\n"
                "    vec2 t = at - corner;\n"
                "    ivec2 p0 = clamp(ivec2(corner), ivec2(0), size - 1), p1 = clamp(ivec2(corner) + 1, ivec2(0), size - 1);\n"
                "    vec4 bottom = mix(texelFetch(%s, %s(p0%s), 0), texelFetch(%s, %s(ivec2(p1.x, p0.y)%s), 0), t.x);\n"
                "    vec4 top = mix(texelFetch(%s, %s(ivec2(p0.x, p1.y)%s), 0), texelFetch(%s, %s(p1%s), 0), t.x);\n"
                "    return halo_channels_from(mix(bottom, top, t.y));",
                n, xy, scale, scale, n, at, layer, n, at, layer, n, at, layer, n, at, layer);
        else
            HALO_GEN(e,
                     "    ivec2 pixel = ivec2(fragcoord);\n"
                     "    if (any(greaterThanEqual(uvec2(pixel), uvec2(textureSize(%s, 0)%s)))) // also pixel < 0\n"
                     "        return halo_channels(0.0);\n"
                     "    return halo_channels_from(texelFetch(%s, %s(pixel%s), 0));",
                     n, xy, n, at, layer);
        if (stacked) {
            HALO_GEN(e,
                     "}\nhalo_channels halo_read_%s(vec2 fragcoord) {\n"
                     "#ifdef HALO_IMAGES_ZERO\n"
                     "    return halo_channels(0.0);\n"
                     "#else",
                     sm->image);
            /* a ray's samples in one segment read one texel: fetched once (the samples of
             * a fragment share its fragcoord in a ray caster, but need not in every host) */
            HALO_GEN(e,
                     "    if (halo_stack_layer < 0) // the first segment: no generation before it\n"
                     "        return halo_channels(0.0);\n"
                     "    if (halo_stack_layer != halo_stack_%s_layer || fragcoord != halo_stack_%s_at) {\n"
                     "        halo_stack_%s_layer = halo_stack_layer;\n"
                     "        halo_stack_%s_at = fragcoord;\n"
                     "        halo_stack_%s_value = halo_read_%s_texel(fragcoord);\n"
                     "    }\n"
                     "    return halo_stack_%s_value;\n"
                     "#endif\n}",
                     sm->image, sm->image, sm->image, sm->image, sm->image, sm->image, sm->image);
        } else
            HALO_GEN(e, "#endif\n}");
    }
    for (size_t i = 0; i < p->host_uniform_count; i++)
        HALO_GEN(e, "uniform %s%s %s;", strncmp(p->host_uniforms[i].type, "sampler", 7) ? "" : "highp ",
                 p->host_uniforms[i].type, p->host_uniforms[i].name);
}

/* Emits generated text written by fn (nothing when it writes none). */
static void emit_text(halo_emitter *e, const halo_program *p, void (*fn)(halo_strbuf *, const halo_program *))
{
    halo_strbuf b = {0};
    fn(&b, p);
    if (b.failed)
        e->failed = 1;
    else if (b.len)
        HALO_GEN(e, "%s", b.data);
    halo_strbuf_free(&b);
}

/* Appends src's lines with their origins. */
static void emit_append(halo_emitter *e, const halo_emitter *src)
{
    const char *t = src->text.data;
    for (int i = 0; t && i < src->count; i++) {
        const char *nl = strchr(t, '\n');
        size_t n = nl ? (size_t)(nl - t) : strlen(t);
        const halo_line_origin *o = &src->origins[i];
        halo_emit(e, o->file, o->line, o->text, "%.*s", (int)n, t);
        t = nl ? nl + 1 : t + n;
    }
    if (src->failed || src->text.failed)
        e->failed = 1;
}

/* The emitter's text and origins as a halo_linked_text (the emitter is emptied). */
static int take_text(halo_emitter *e, halo_linked_text *out)
{
    if (e->failed || e->text.failed) {
        halo_strbuf_free(&e->text);
        free(e->origins);
        *e = (halo_emitter){0};
        return -1;
    }
    out->count = e->count;
    out->origins = e->origins;
    out->text = e->count ? halo_strbuf_take(&e->text) : halo_strdup("");
    *e = (halo_emitter){0};
    return out->text ? 0 : -1;
}

/* libhalo's block: what replaces the host's marker line (marker: that line's text, at
 * line marker_line of the host). */
static void emit_block(halo_emitter *e, halo_program *p, const char *host_source, const halo_library *lib,
                       int marker_line, const char *marker)
{
    halo_emit(e, p->host_file, marker_line, marker, "// ---- libhalo %s: %zu stage%s (contract %d) ----",
              PACKAGE_VERSION, p->stage_count, p->stage_count == 1 ? "" : "s", HALO_CONTRACT_VERSION);
    emit_declarations(e, p, host_source);
    halo_emit_helpers(e, lib, p);
    for (size_t s = 0; s < p->stage_count; s++) {
        const halo_module *m = p->stages[s].module;
        if (m->hook == HALO_HOOK_IMAGE)
            continue;
        halo_emit(e, m->file, m->module_line, m->lines[m->module_line - 1], "// stage %s (%s)", m->name, m->file);
        halo_emit_params(e, p, &p->stages[s], p->engine_uniforms);
        halo_emit_module_lines(e, m, 1, m->line_count, 1, p->engine_uniforms ? p : NULL);
    }
    for (size_t h = 0; h < halo_hook_struct_count; h++) {
        const halo_hook_struct *hs = &halo_hook_structs[h];
        if (!hook_needed(p, hs, host_source))
            continue;
        HALO_GEN(e, "void halo_apply(inout %s %s) {", hs->type, hs->var);
        if (p->one_draw && hs->hook == HALO_HOOK_SAMPLE)
            HALO_GEN(e, "    halo_stack_layer = halo_stack_layer_at(%s.position);", hs->var);
        for (size_t s = 0; s < p->stage_count; s++) {
            const halo_linked_stage *st = &p->stages[s];
            /* host contract 3: the seeding stages run in libhalo's march, and only they */
            if (st->module->hook == hs->hook && !(p->one_draw && st->prepass == 2) &&
                !(p->prepass_only && !st->prepass))
                HALO_GEN(e, "    halo_%s_apply(%s);", st->module->name, hs->var);
        }
        for (size_t o = 0; o < p->output_count && hs->hook == HALO_HOOK_SAMPLE; o++) {
            const halo_output_info *out = &p->outputs[o];
            const char *img = out->image;
            halo_strbuf field_text = {0};
            if (out->channel >= 0)
                halo_strbuf_printf(&field_text, "s.%s[%d]", out->field, out->channel);
            else
                halo_strbuf_printf(&field_text, "s.%s", out->field);
            const char *field = field_text.data ? field_text.data : "";
            if (field_text.failed)
                e->failed = 1;
            if (out->blend == HALO_BLEND_MAX)
                HALO_GEN(e, "    halo_accum_%s = max(halo_accum_%s, %s);", img, img, field);
            else if (out->blend == HALO_BLEND_MIN)
                HALO_GEN(e, "    halo_accum_%s = min(halo_accum_%s, %s);", img, img, field);
            else if (out->blend == HALO_BLEND_FIRST) /* the first hit of the fragment wins */
                HALO_GEN(e, "    if (halo_accum_%s.a <= 0.0) halo_accum_%s = %s;", img, img, field);
            else
                HALO_GEN(e, "    halo_accum_%s += %s;", img, field);
            halo_strbuf_free(&field_text);
        }
        HALO_GEN(e, "}");
    }
    HALO_GEN(e, "void halo_finish() {");
    for (size_t o = 0; o < p->output_count; o++)
        HALO_GEN(e, "    %s = halo_accum_%s;", p->outputs[o].name, p->outputs[o].image);
    HALO_GEN(e, "}");
    if (p->prepass_only && p->output_count == 1) {
        /* host contract 3's march of several segments a draw (prepass.c, gl/field.c): a
         * segment's seeds taken as a vec4, the accumulator reset for the next segment */
        const halo_output_info *out = &p->outputs[0];
        const char *type = output_type(p, out);
        static const char *const zeros[] = {", 0.0, 0.0, 0.0", ", 0.0, 0.0, 0.0", ", 0.0, 0.0", ", 0.0", ""};
        int n = out->components < 1 ? 1 : out->components > 4 ? 4 : out->components;
        if (!strcmp(type, "halo_channels"))
            HALO_GEN(e, "vec4 halo_march_take() {\n    vec4 v = halo_channels_to_vec4(halo_accum_%s);", out->image);
        else
            HALO_GEN(e, "vec4 halo_march_take() {\n    vec4 v = vec4(halo_accum_%s%s);", out->image, zeros[n]);
        HALO_GEN(e, "    halo_accum_%s = %s(%s);\n    return v;\n}", out->image, type,
                 out->blend == HALO_BLEND_MIN ? "1.0" : "0.0");
    }
    emit_text(e, p, halo_segment_emit);
    halo_emit(e, p->host_file, marker_line, marker, "// ---- end of libhalo declarations ----");
}

int halo_emit_program(halo_program *p, const char *host_source, char **host_lines, int host_count,
                      const halo_host_info *h, const halo_library *lib)
{
    /* the product: libhalo's block and its tail */
    halo_emitter block = {0}, tail = {0};
    if (h->marker_line >= 1 && h->marker_line <= host_count)
        emit_block(&block, p, host_source, lib, h->marker_line, host_lines[h->marker_line - 1]);
    emit_text(&tail, p, halo_segment_emit_tail);
    int failed = take_text(&block, &p->block); /* both: each frees its emitter */
    failed |= take_text(&tail, &p->tail);
    if (failed)
        return -1;
    /* spliced into the host */
    halo_emitter e = {0};
    const char *ver = halo_target_version_line(p->target);
    int es = p->target == HALO_TARGET_ES300;
    const char *precision = p->kind == HALO_SHADER_FRAGMENT
                                ? "precision highp float;\nprecision highp int;\nprecision highp sampler2D;\n"
                                  "precision highp sampler3D;"
                                : "precision highp float;\nprecision highp int;";
    if (!h->version_line) {
        /* GLSL ES needs the precisions whoever writes the #version (KEEP, NONE: the engine) */
        if (p->version == HALO_VERSION_TARGET)
            HALO_GEN(&e, "%s", ver);
        if (es)
            HALO_GEN(&e, "%s", precision);
    }
    for (int i = 0; i < host_count; i++) {
        const char *line = host_lines[i];
        if (i + 1 == h->version_line) {
            if (p->version == HALO_VERSION_NONE)
                halo_emit(&e, p->host_file, i + 1, line, "// %s (no #version: the engine adds its own)", line);
            else
                halo_emit(&e, p->host_file, i + 1, line, "%s", p->version == HALO_VERSION_KEEP ? line : ver);
            if (es)
                halo_emit(&e, p->host_file, i + 1, line, "%s", precision);
            continue;
        }
        if (i + 1 != h->marker_line) {
            halo_emit(&e, p->host_file, i + 1, line, "%s", line);
            continue;
        }
        emit_append(
            &e, &(halo_emitter){.text = {.data = p->block.text}, .origins = p->block.origins, .count = p->block.count});
    }
    emit_append(&e,
                &(halo_emitter){.text = {.data = p->tail.text}, .origins = p->tail.origins, .count = p->tail.count});
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
