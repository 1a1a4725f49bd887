/* The linker: scene + modules + host shader → one program, emitting only what the
 * scene needs. A straight pipeline: check the host → resolve and order the stages →
 * gather parameters → emit, each line with its origin (halo_link_host). halo_link, the
 * front door (link_entry.c), sends host text down it; pieces for a shader composer
 * (compose.c) go down it too, in a stand-in host, and are cut back out of its product. */
#include "diag.h"
#include "emit.h"
#include "host_check.h"
#include "host_scan.h"
#include "internal.h"
#include "strbuf.h"

#include <ctype.h>
#include <jansson.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

/* ---- Stage resolution and order ---- */

typedef struct node {
    const halo_module *module;
    const halo_scene_entry *entry; /* NULL: enabled as a dependency */
    double rank;
    int indegree;
    int done;
} node;

static int provides(const halo_module *m, const char *resource)
{
    for (size_t i = 0; i < m->provides_count; i++)
        if (!strcmp(m->provides[i].name, resource))
            return 1;
    return 0;
}

static int hook_fits(halo_hook hook, halo_shader_kind kind)
{
    if (hook == HALO_HOOK_IMAGE)
        return 1; /* image passes are programs of their own */
    if (kind == HALO_SHADER_VERTEX)
        return hook == HALO_HOOK_LINE_VERTEX;
    return hook == HALO_HOOK_SAMPLE || hook == HALO_HOOK_LINE_FRAGMENT;
}

/* Returns the ordered stages in *out (count in *out_count), or errors. */
static int resolve(const halo_library *lib, const halo_scene *scene, halo_shader_kind kind, node **out, int *out_count,
                   halo_diagnostics *diag)
{
    int errors = 0, n = 0, cap = (int)(scene ? scene->count : 0) + (int)lib->count + 1;
    node *nodes = calloc((size_t)cap, sizeof *nodes);
    if (!nodes) {
        halo_diag_error(diag, OUT_OF_MEMORY, "", 0, 0, "out of memory");
        return 1;
    }
    for (size_t i = 0; scene && i < scene->count; i++) {
        if (!scene->stages[i].enabled)
            continue;
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
            if (halo_is_host_resource(res))
                continue;
            int have = 0;
            for (int j = 0; j < n; j++)
                have |= provides(nodes[j].module, res);
            if (have)
                continue;
            const halo_module *found = NULL;
            int candidates = 0;
            for (size_t k = 0; k < lib->count; k++)
                if (provides(lib->modules[k], res)) {
                    candidates++;
                    if (!found)
                        found = lib->modules[k];
                }
            if (candidates == 0) {
                halo_diagnostics_report(diag, HALO_SEVERITY_ERROR, HALO_MSG_LINK_MISSING_PROVIDER, m->file,
                                        m->needs.lines[r], 1, m->lines[m->needs.lines[r] - 1],
                                        "stage '%s' needs '%s', which neither the host nor any module provides",
                                        m->name, res);
                errors++;
            } else if (candidates > 1) {
                halo_diagnostics_report(
                    diag, HALO_SEVERITY_ERROR, HALO_MSG_LINK_DUPLICATE_PROVIDER, m->file, m->needs.lines[r], 1,
                    m->lines[m->needs.lines[r] - 1],
                    "stage '%s' needs '%s', which %d modules provide; enable the one to use in the scene", m->name, res,
                    candidates);
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
            halo_diagnostics_report(diag, HALO_SEVERITY_ERROR, HALO_MSG_LINK_HOOK_MISMATCH, m->file, m->hook_line, 1,
                                    m->lines[m->hook_line - 1], "stage '%s' runs at a hook that a %s host cannot place",
                                    m->name, kind == HALO_SHADER_VERTEX ? "vertex" : "fragment");
            errors++;
        }
        for (size_t p = 0; p < m->provides_count; p++)
            for (int j = 0; j < i; j++)
                if (provides(nodes[j].module, m->provides[p].name)) {
                    halo_diagnostics_report(diag, HALO_SEVERITY_ERROR, HALO_MSG_LINK_DUPLICATE_PROVIDER, m->file,
                                            m->provides[p].line, 1, m->lines[m->provides[p].line - 1],
                                            "stages '%s' and '%s' both provide '%s'; enable only one",
                                            nodes[j].module->name, m->name, m->provides[p].name);
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
            if (a == b)
                continue;
            int before = 0;
            for (size_t r = 0; r < m->needs.count; r++)
                before |= provides(nodes[b].module, m->needs.items[r]);
            before |= halo_name_list_has(&m->after, halo_module_name_of(nodes[b].module));
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
            if (nodes[i].done || nodes[i].indegree)
                continue;
            if (best < 0 || nodes[i].rank < nodes[best].rank ||
                (nodes[i].rank == nodes[best].rank &&
                 strcmp(halo_module_name_of(nodes[i].module), halo_module_name_of(nodes[best].module)) < 0))
                best = i;
        }
        if (best < 0)
            break;
        nodes[best].done = 1;
        order[placed++] = nodes[best];
        for (int j = 0; j < n; j++)
            if (edge[best * n + j])
                nodes[j].indegree--;
    }
    if (placed < n) {
        halo_strbuf names = {0};
        const halo_module *first = NULL;
        for (int i = 0; i < n; i++)
            if (!nodes[i].done) {
                halo_strbuf_printf(&names, "%s%s", first ? ", " : "", halo_module_name_of(nodes[i].module));
                if (!first)
                    first = nodes[i].module;
            }
        int line = first->after.count   ? first->after.lines[0]
                   : first->needs.count ? first->needs.lines[0]
                                        : first->module_line;
        halo_diagnostics_report(
            diag, HALO_SEVERITY_ERROR, HALO_MSG_LINK_CYCLE, first->file, line, 1, first->lines[line - 1],
            "the 'needs' and 'after' annotations of these stages form a cycle: %s", names.data ? names.data : "");
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

/* ---- Channels, images and passes (docs/image-passes.md) ---- */

static int is_per_halo(const halo_module *m, size_t i)
{
    return m->params[i].type == HALO_PARAM_CHANNELS || halo_name_list_has(&m->per_halo, m->params[i].name);
}

/* The channel count is the longest per-halo list; shorter ones repeat their last element. */
static void set_channel_count(halo_program *p)
{
    int c = 1;
    for (size_t s = 0; s < p->stage_count; s++)
        for (size_t i = 0; i < p->stages[s].module->param_count; i++)
            if (is_per_halo(p->stages[s].module, i) && p->stages[s].values[i].count > c)
                c = p->stages[s].values[i].count;
    if (c > 4)
        c = 4;
    p->channel_count = c;
    for (size_t s = 0; s < p->stage_count; s++) {
        const halo_module *m = p->stages[s].module;
        for (size_t i = 0; i < m->param_count; i++) {
            if (!is_per_halo(m, i))
                continue;
            halo_param_value *v = &p->stages[s].values[i];
            int comps = m->params[i].components, max = m->params[i].array_size;
            int target = c < max ? c : max;
            for (int k = v->count; k < target; k++)
                memcpy(v->value + k * comps, v->value + (v->count - 1) * comps, (size_t)comps * sizeof(double));
            if (v->count < target)
                v->count = target;
            p->uniforms[p->stages[s].first_uniform + i].count = v->count;
        }
    }
}


/* components 0: the program's channel count. A second declaration keeps the first's size
 * and clear value unless it is the first to give them (clear_set). */
static int add_image(halo_program *p, const char *name, halo_image_reset reset, int components, double clear,
                     int clear_set)
{
    halo_image_info *im = halo_program_image_named(p, name);
    if (im) {
        if (reset == HALO_RESET_GENERATION)
            im->reset = reset;
        if (clear_set)
            im->clear = clear;
        return 0;
    }
    halo_image_info *list = realloc(p->images, (p->image_count + 1) * sizeof *list);
    if (!list)
        return -1;
    p->images = list;
    int host = !strcmp(name, "host_color");
    list[p->image_count++] = (halo_image_info){
        halo_program_own(p, "%s", name), host ? 4 : components ? components : p->channel_count, reset, clear, host, 1};
    return 0;
}

/* Image names of a declaration: NAME, or NAME_0 .. NAME_{c-1} for a family. */
static int add_image_decl(halo_program *p, const halo_image_decl *d)
{
    if (!d->family)
        return add_image(p, d->name, d->reset, d->components, d->clear, d->clear_set);
    for (int k = 0; k < p->channel_count; k++) {
        const char *name = halo_program_own(p, "%s_%d", d->name, k); /* any length */
        if (!name || add_image(p, name, d->reset, d->components, d->clear, d->clear_set))
            return -1;
    }
    return 0;
}

/* Components of a provided field's GLSL type; 0 if it cannot be an output. */
static int field_components(const halo_program *p, const char *type, int *per_channel)
{
    *per_channel = 0;
    if (!strcmp(type, "halo_channels"))
        return p->channel_count;
    if (!strcmp(type, "float"))
        return 1;
    if (!strcmp(type, "vec2"))
        return 2;
    if (!strcmp(type, "vec3"))
        return 3;
    if (!strcmp(type, "vec4"))
        return 4;
    if (!strcmp(type, "mat4")) {
        *per_channel = 1;
        return 4;
    }
    return 0;
}

/* The first fragment output location the host does not declare. */
static int first_free_location(const char *host)
{
    halo_token_list t;
    int max = 0; /* location 0: the host's colour, declared or implied */
    if (halo_lex(host, &t))
        return 1;
    for (size_t i = 0; i + 2 < t.count; i++)
        if (halo_token_is(host, &t.items[i], "location") && halo_token_is(host, &t.items[i + 1], "=") &&
            t.items[i + 2].kind == HALO_TOK_NUMBER) {
            long loc = strtol(host + t.items[i + 2].offset, NULL, 10);
            if (loc > max)
                max = loc > HALO_MAX_OUTPUT_LOCATION ? HALO_MAX_OUTPUT_LOCATION : (int)loc; /* no overflow */
        }
    halo_token_list_free(&t);
    return max + 1;
}

static int collect_resources(halo_program *p, const char *host, halo_diagnostics *diag)
{
    int errors = 0, location = p->first_location > 0 ? p->first_location : first_free_location(host);
    for (size_t s = 0; s < p->stage_count; s++) {
        const halo_module *m = p->stages[s].module;
        for (size_t i = 0; i < m->image_count && m->hook == HALO_HOOK_IMAGE; i++)
            if (add_image_decl(p, &m->images[i]))
                return -1;
    }
    for (size_t s = 0; s < p->stage_count; s++) {
        const halo_module *m = p->stages[s].module;
        for (size_t o = 0; o < m->output_count; o++) {
            const halo_output_decl *od = &m->outputs[o];
            const char *type = NULL;
            for (size_t r = 0; r < m->provides_count; r++)
                if (!strcmp(m->provides[r].name, od->name))
                    type = m->provides[r].type;
            int per_channel = 0, components = type ? field_components(p, type, &per_channel) : 0;
            if (!type || m->hook != HALO_HOOK_SAMPLE || !components ||
                (od->blend == HALO_BLEND_FIRST && components != 4)) {
                halo_diagnostics_report(
                    diag, HALO_SEVERITY_ERROR, HALO_MSG_PASS_INVALID, m->file, od->line, 1, m->lines[od->line - 1],
                    "output '%s' must be a field the sample stage provides, of type channels, float, "
                    "vec2..vec4 or mat4 (one vec4 column per channel); a 'first' output needs vec4 or mat4",
                    od->name);
                errors++;
                continue;
            }
            int n = per_channel ? p->channel_count : 1;
            for (int k = 0; k < n; k++) {
                char *image =
                    per_channel ? halo_program_own(p, "%s_%d", od->name, k) : halo_program_own(p, "%s", od->name);
                halo_output_info *list = realloc(p->outputs, (p->output_count + 1) * sizeof *list);
                if (!list || !image)
                    return -1;
                p->outputs = list;
                if (add_image(p, image, HALO_RESET_FRAME, components, od->blend == HALO_BLEND_MIN ? 1.0 : 0.0,
                              !halo_program_image_named(p, image)))
                    return -1;
                list[p->output_count++] = (halo_output_info){
                    halo_program_own(p, "halo_output_%s", image), location++,          components, image, od->blend,
                    halo_program_own(p, "%s", od->name),          per_channel ? k : -1};
            }
        }
        for (size_t i = 0; i < m->image_count && m->hook == HALO_HOOK_SAMPLE; i++) {
            const char *name = m->images[i].name;
            int known = halo_program_image_named(p, name) != NULL;
            for (size_t k = 0; k < p->sampler_count; k++)
                known |= !strcmp(p->samplers[k].image, name) * 2;
            if (known == 0) {
                halo_diagnostics_report(diag, HALO_SEVERITY_ERROR, HALO_MSG_LINK_MISSING_PROVIDER, m->file,
                                        m->images[i].line, 1, m->lines[m->images[i].line - 1],
                                        "stage '%s' reads image '%s', which no linked stage produces", m->name, name);
                errors++;
                continue;
            }
            if (known >= 2)
                continue;
            halo_sampler_info *list = realloc(p->samplers, (p->sampler_count + 1) * sizeof *list);
            if (!list)
                return -1;
            p->samplers = list;
            list[p->sampler_count++] =
                (halo_sampler_info){halo_program_own(p, "halo_image_%s", name), halo_program_own(p, "%s", name)};
        }
        for (size_t i = 0; i < m->host_uniform_count; i++) {
            const halo_host_uniform_decl *hu = &m->host_uniforms[i];
            char *name = halo_program_own(p, "halo_host_%s", hu->name);
            int dup = 0;
            for (size_t k = 0; k < p->host_uniform_count; k++)
                dup |= !strcmp(p->host_uniforms[k].name, name);
            if (dup)
                continue;
            halo_host_uniform_info *list = realloc(p->host_uniforms, (p->host_uniform_count + 1) * sizeof *list);
            if (!list)
                return -1;
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
            for (int k = 0; k < pd->input_count; k++)
                names[n++] = pd->inputs[k];
            for (int k = 0; k < n; k++) {
                if (names[k] && names[k][0] && names[k][strlen(names[k]) - 1] == '*') {
                    names[k] = halo_program_own(p, "%.*s_0", (int)strlen(names[k]) - 1, names[k]);
                    if (!names[k])
                        return -1;
                }
                if (names[k] && strcmp(names[k], "previous") && !halo_program_image_named(p, names[k])) {
                    halo_diagnostics_report(diag, HALO_SEVERITY_ERROR, HALO_MSG_PASS_INVALID, m->file, pd->line, 1,
                                            m->lines[pd->line - 1], "pass '%s' uses image '%s', which is not declared",
                                            pd->name, names[k]);
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
static void set_image_scales(halo_program *p)
{
    for (size_t i = 0; i < p->image_count; i++) {
        halo_image_info *im = &p->images[i];
        int full = im->host;
        for (size_t o = 0; o < p->output_count && !full; o++)
            full = !strcmp(p->outputs[o].image, im->name);
        for (size_t s = 0; s < p->stage_count && !full; s++) {
            const halo_module *m = p->stages[s].module;
            for (size_t k = 0; k < m->pass_count && !full; k++) {
                const halo_pass_decl *pd = &m->passes[k];
                if (!pd->at)
                    continue;
                size_t n = strlen(pd->output);
                full = n > 1 && pd->output[n - 1] == '*'
                           ? !strncmp(im->name, pd->output, n - 1) && im->name[n - 1] == '_'
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

static int param_int(const halo_linked_stage *st, const char *name)
{
    for (size_t i = 0; i < st->module->param_count; i++)
        if (!strcmp(st->module->params[i].name, name))
            return (int)st->values[i].value[0];
    return 0;
}

/* An image name of a pass with its '*' resolved: channel k of an each=channel pass. */
static char *resolve_name(halo_program *p, const char *name, int channel)
{
    size_t n = strlen(name);
    if (n > 1 && name[n - 1] == '*')
        return halo_program_own(p, "%.*s_%d", (int)n - 1, name, channel < 0 ? 0 : channel);
    return halo_program_own(p, "%s", name);
}

static int build_pass(halo_program *p, const halo_library *lib, const halo_linked_stage *st, const halo_pass_decl *pd,
                      int channel)
{
    const halo_module *m = st->module;
    halo_emitter e = {0};
    /* The inputs: NAME* of a pass that is not each=channel expands to one input per channel. */
    const char *inputs[HALO_MAX_PASS_INPUTS];
    int input_count = 0;
    for (int k = 0; k < pd->input_count; k++) {
        size_t n = strlen(pd->inputs[k]);
        int family = n > 1 && pd->inputs[k][n - 1] == '*' && channel < 0;
        for (int c = 0; c < (family ? p->channel_count : 1); c++) {
            if (input_count == HALO_MAX_PASS_INPUTS)
                return -2;
            inputs[input_count++] = resolve_name(p, pd->inputs[k], family ? c : channel);
        }
    }
    const char *output = resolve_name(p, pd->output, channel);
    const halo_image_info *out_image = halo_program_image_named(p, output);
    int es = p->target == HALO_TARGET_ES300;
    HALO_GEN(&e, "%s", halo_target_version_line(p->target));
    if (es)
        HALO_GEN(&e, "precision highp float;\nprecision highp int;\nprecision highp sampler2D;");
    halo_emit(&e, m->file, pd->line, m->lines[pd->line - 1], "// stage %s (%s): image pass '%s'", m->name, m->file,
              pd->name);
    halo_emit_channel_definitions(&e, p->channel_count);
    for (int k = 0; k < input_count; k++)
        HALO_GEN(&e, "uniform highp sampler2D halo_input_%d;", k);
    HALO_GEN(&e, "uniform int halo_pass_index;\nuniform int halo_pass_count;");
    HALO_GEN(&e, "const int halo_pass_channel = %d; // each=channel: this pass's channel (0 otherwise)",
             channel < 0 ? 0 : channel);
    HALO_GEN(&e,
             "vec4 halo_pass_vec4(float v) { return vec4(v, 0.0, 0.0, 0.0); }\n"
             "vec4 halo_pass_vec4(vec2 v) { return vec4(v, 0.0, 0.0); }\n"
             "vec4 halo_pass_vec4(vec3 v) { return vec4(v, 0.0); }\n"
             "vec4 halo_pass_vec4(vec4 v) { return v; }");
    char layout[48];
    /* GLSL 150: libhalo's own pass programs name their one output (bound at 0 by the runtime) */
    HALO_GEN(&e, "%sout vec4 halo_pass_output;",
             p->target == HALO_TARGET_GLSL150 ? "" : halo_output_layout(p, 0, layout, sizeof layout));
    /* Inputs of another size than the output (halo_link_desc.image_scale): a larger one
     * (the full-size seed read by a 1/s pass) gives the max over the s x s block of the
     * pixel, so that no seed is lost; a smaller one its pixel / s. */
    int out_scale = out_image ? out_image->scale : 1;
    HALO_GEN(&e, "const int halo_pass_scale = %d; // the output image is 1/halo_pass_scale of the frame per side",
             out_scale);
    int down[HALO_MAX_PASS_INPUTS], up[HALO_MAX_PASS_INPUTS], tiled = 1;
    for (int k = 0; k < input_count; k++) {
        const halo_image_info *in = strcmp(inputs[k], "previous") ? halo_program_image_named(p, inputs[k]) : out_image;
        int in_scale = in ? in->scale : out_scale;
        down[k] = in_scale < out_scale ? out_scale / in_scale : 1;
        up[k] = in_scale > out_scale ? in_scale / out_scale : 1;
        tiled &= down[k] == 1 && up[k] == 1;
    }
    /* HALO_PASS_TILES (inputs and output of one size): the images are atlases of equal
     * tiles, one a depth segment, and one draw runs the pass on every tile
     * (gl/field_atlas.c); each tile is an image of its own, 0 outside it */
    if (tiled)
        HALO_GEN(&e,
                 "#ifdef HALO_PASS_TILES\n"
                 "uniform ivec2 halo_tile_size; // a tile's pixels\n"
                 "ivec2 halo_tile_origin = ivec2(0); // the fragment's tile's first pixel in the atlas\n"
                 "#endif");
    /* a running=associative pass on an atlas is a step of a prefix scan over the tiles:
     * input 1 is the tile halo_tile_back tiles before the fragment's (0 before the first) */
    int scan = tiled && pd->running && input_count == 2;
    if (scan)
        HALO_GEN(&e,
                 "#ifdef HALO_PASS_TILES\n"
                 "uniform int halo_tile_columns; // tiles per row of the atlas\n"
                 "uniform int halo_tile_back; // the scan's step: input 1 reads this many tiles back\n"
                 "ivec2 halo_tile_before = ivec2(-1); // that tile's first pixel; -1: before the first tile\n"
                 "#endif");
    for (int k = 0; k < input_count; k++) {
        if (tiled)
            HALO_GEN(&e,
                     "#ifdef HALO_PASS_TILES\n"
                     "vec4 halo_fetch_%d(ivec2 pixel) {\n"
                     "    if (%sany(greaterThanEqual(uvec2(pixel), uvec2(halo_tile_size)))) // also pixel < 0\n"
                     "        return vec4(0.0);\n"
                     "    return texelFetch(halo_input_%d, %s + pixel, 0);\n}\n"
                     "#else",
                     k, scan && k == 1 ? "halo_tile_before.x < 0 || " : "", k,
                     scan && k == 1 ? "halo_tile_before" : "halo_tile_origin");
        HALO_GEN(
            &e,
            "vec4 halo_fetch_%d(ivec2 pixel) {\n"
            "    if (any(greaterThanEqual(uvec2(pixel), uvec2(textureSize(halo_input_%d, 0))))) // also pixel < 0\n"
            "        return vec4(0.0);\n"
            "    return texelFetch(halo_input_%d, pixel, 0);\n}",
            k, k, k);
        if (tiled)
            HALO_GEN(&e, "#endif");
    }
    HALO_GEN(&e,
             "// All four components of input k (images of components=N, host_color) at a pixel of the\n"
             "// output; 0 outside the image (zero padding at the borders).");
    HALO_GEN(&e, "vec4 halo_input4(int k, ivec2 pixel) {");
    for (int k = 0; k < input_count; k++) {
        if (down[k] > 1)
            HALO_GEN(&e,
                     "    if (k == %d) {\n"
                     "        vec4 m = halo_fetch_%d(pixel * %d);\n"
                     "        for (int i = 1; i < %d; ++i)\n"
                     "            m = max(m, halo_fetch_%d(pixel * %d + ivec2(i %% %d, i / %d)));\n"
                     "        return m;\n"
                     "    }",
                     k, k, down[k], down[k] * down[k], k, down[k], down[k], down[k]);
        else if (up[k] > 1)
            /* pixel < 0 tested first: pixel / u rounds toward 0 (-1 / 2 would read pixel 0) */
            HALO_GEN(&e,
                     "    if (k == %d) return any(lessThan(pixel, ivec2(0))) ? vec4(0.0) : halo_fetch_%d(pixel / %d);",
                     k, k, up[k]);
        else
            HALO_GEN(&e, "    if (k == %d) return halo_fetch_%d(pixel);", k, k);
    }
    HALO_GEN(&e, "    return vec4(0.0);\n}");
    HALO_GEN(&e,
             "// Input k at a pixel: the program's channels.\n"
             "halo_channels halo_input(int k, ivec2 pixel) { return halo_channels_from(halo_input4(k, pixel)); }");
    if (input_count > 0 && (down[0] > 1 || up[0] > 1))
        HALO_GEN(&e,
                 "// The output's size in pixels.\n"
                 "ivec2 halo_image_size() { return (textureSize(halo_input_0, 0) * %d + %d) / %d; }",
                 up[0], down[0] - 1, down[0]);
    else
        HALO_GEN(&e,
                 "// The output's size in pixels (input 0 has it; an atlas's: a tile's).\n"
                 "#ifdef HALO_PASS_TILES\n"
                 "ivec2 halo_image_size() { return halo_tile_size; }\n"
                 "#else\n"
                 "ivec2 halo_image_size() { return textureSize(halo_input_0, 0); }\n"
                 "#endif");
    /* The helpers this module calls. */
    halo_program one = *p;
    halo_linked_stage only = *st;
    one.stages = &only;
    one.stage_count = 1;
    halo_emit_helpers(&e, lib, &one);
    halo_emit_params(&e, p, st, 0);
    halo_emit_module_lines(&e, m, 1, m->line_count, 1, NULL);
    if (tiled)
        HALO_GEN(&e,
                 "#ifdef HALO_PASS_TILES\n"
                 "void main() {\n"
                 "    ivec2 fragment = ivec2(gl_FragCoord.xy);\n"
                 "    halo_tile_origin = fragment / halo_tile_size * halo_tile_size;%s\n"
                 "    halo_pass_output = halo_pass_vec4(halo_%s_%s(fragment - halo_tile_origin));\n"
                 "}\n"
                 "#else",
                 scan ? "\n    ivec2 tile = fragment / halo_tile_size;\n"
                        "    int before = tile.y * halo_tile_columns + tile.x - halo_tile_back;\n"
                        "    if (before >= 0)\n"
                        "        halo_tile_before = ivec2(before % halo_tile_columns, before / halo_tile_columns) * "
                        "halo_tile_size;"
                      : "",
                 m->name, pd->entry);
    HALO_GEN(&e, "void main() {\n    halo_pass_output = halo_pass_vec4(halo_%s_%s(ivec2(gl_FragCoord.xy)));\n}",
             m->name, pd->entry);
    if (tiled)
        HALO_GEN(&e, "#endif");
    if (e.failed || e.text.failed) {
        halo_strbuf_free(&e.text);
        free(e.origins);
        return -1;
    }
    halo_pass_info *list = realloc(p->passes, (p->pass_count + 1) * sizeof *list);
    halo_line_origin **ol = realloc(p->pass_origins, (p->pass_count + 1) * sizeof *ol);
    int *oc = realloc(p->pass_origin_counts, (p->pass_count + 1) * sizeof *oc);
    if (list)
        p->passes = list;
    if (ol)
        p->pass_origins = ol;
    if (oc)
        p->pass_origin_counts = oc;
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
    for (int k = 0; k < input_count; k++)
        pi->inputs[k] = inputs[k];
    pi->first = pd->first ? resolve_name(p, pd->first, channel) : NULL;
    pi->output = output;
    pi->at = pd->at;
    pi->channel = channel;
    pi->repeat = pd->repeat ? param_int(st, pd->repeat) : 1;
    pi->repeat_param = pd->repeat ? halo_program_own(p, "%s", pd->repeat) : NULL;
    pi->start = pd->start > 1 ? pd->start : 1;
    pi->reach = pd->reach;
    /* -1 is "no exponent": a negative PARAM is B^0, the same as exponent 0 */
    int exponent = pd->reach >= 0 && pd->reach_param ? param_int(st, pd->reach_param) : -1;
    pi->reach_exponent = pd->reach >= 0 && pd->reach_param ? (exponent < 0 ? 0 : exponent) : -1;
    pi->reach_factor = pd->reach_factor > 0 ? pd->reach_factor : 1;
    pi->reach_base = pd->reach_base == 4 ? 4 : 2;
    pi->running = pd->running;
    pi->vertex_source = halo_program_own(p, "%s\n%s\n", halo_target_version_line(p->target), pass_vertex_body);
    pi->fragment_source = frag_owned;
    p->pass_origins[p->pass_count] = e.origins;
    p->pass_origin_counts[p->pass_count] = e.count;
    p->pass_count++;
    return 0;
}

/* A pass's when=: a list of conditions that must all hold, each a bool parameter or
 * HALO_WHEN_FULL_SIZE, either negated by '!'. */
static int pass_condition(const halo_program *p, const halo_linked_stage *st, const char *when)
{
    char name[64];
    int negate;
    while (halo_when_next(&when, name, sizeof name, &negate) > 0) {
        int on = !strcmp(name, HALO_WHEN_FULL_SIZE) ? p->image_scale <= 1 : param_int(st, name) != 0;
        if (on == negate)
            return 0;
    }
    return 1;
}

static int build_passes(halo_program *p, const halo_library *lib, halo_diagnostics *diag)
{
    for (size_t s = 0; s < p->stage_count; s++) {
        const halo_linked_stage *st = &p->stages[s];
        for (size_t i = 0; i < st->module->pass_count; i++) {
            const halo_pass_decl *pd = &st->module->passes[i];
            if (pd->when && !pass_condition(p, st, pd->when))
                continue;
            if (pd->repeat && param_int(st, pd->repeat) < (pd->start > 1 ? pd->start : 1))
                continue;
            if (!pd->each_channel && halo_program_image_unread(p, pd->output))
                continue;
            for (int c = 0; c < (pd->each_channel ? p->channel_count : 1); c++) {
                int r = build_pass(p, lib, st, pd, pd->each_channel ? c : -1);
                if (r == -2) {
                    halo_diagnostics_report(diag, HALO_SEVERITY_ERROR, HALO_MSG_PASS_INVALID, st->module->file,
                                            pd->line, 1, st->module->lines[pd->line - 1],
                                            "pass '%s' reads more than %d images with %d channels", pd->name,
                                            HALO_MAX_PASS_INPUTS, p->channel_count);
                    return -2;
                }
                if (r)
                    return -1;
            }
        }
    }
    return 0;
}

/* ---- The program ---- */


/* Host contract 2: does the host take segments, and does the program need them? A
 * single-pass ray caster (a sample loop, no halo_segment_begin, no `#pragma halo slices`)
 * cannot run passes between slices: refuse it rather than render without the stages
 * that need them. */
static int plan_segments(halo_program *p, const halo_link_desc *desc, const halo_host_info *h, halo_diagnostics *diag)
{
    const char *host = halo_skip_bom(desc->host_source);
    int segmenting = halo_host_uses(host, "halo_segment_begin");
    p->v2_host = segmenting || h->volume || h->gradient || halo_host_uses(host, "halo_view_at") ||
                 halo_host_uses(host, "halo_depth_at");
    /* a host that draws one sample per fragment (a slice host, a probe) runs the passes
     * between its draws; one that loops over samples marches whole rays */
    int marches = halo_host_uses(host, "for") || halo_host_uses(host, "while");
    p->single_pass = !h->slices && desc->one_draw; /* and not drawn in segments (segment_location) */
    /* host contract 3: libhalo computes what the passes between slices make before the host draws */
    int generation = halo_program_has_generation_passes(p) && !desc->one_draw;
    if (h->compositing_mip && p->stage_count) {
        /* a MIP host composites no samples: every stage would be silently meaningless */
        halo_strbuf names = {0};
        for (size_t s = 0; s < p->stage_count; s++)
            halo_strbuf_printf(&names, "%s%s", names.len ? ", " : "", p->stages[s].module->name);
        halo_diagnostics_report(
            diag, HALO_SEVERITY_ERROR, HALO_MSG_HOST_COMPOSITING, p->host_file, h->compositing_mip, 1,
            p->host_lines[h->compositing_mip - 1],
            "the stages %s act on the samples a host composites, but this host declares maximum intensity "
            "projection ('#pragma halo compositing mip'): link it with no stage, or use a compositing mode",
            names.data ? names.data : "?");
        halo_strbuf_free(&names);
        return 1;
    }
    if (desc->force_segments && !segmenting) {
        halo_diagnostics_report(diag, HALO_SEVERITY_ERROR, HALO_MSG_HOST_SINGLE_PASS, p->host_file, 1, 1,
                                p->host_lines[0],
                                "force_segments: the host never calls halo_segment_begin (docs/host-contract.md, "
                                "\"Segmented ray casting\")");
        return 1;
    }
    if (generation && marches && !segmenting && !h->slices && p->kind == HALO_SHADER_FRAGMENT) {
        halo_strbuf names = {0};
        for (size_t s = 0; s < p->stage_count; s++) {
            const halo_module *m = p->stages[s].module;
            for (size_t k = 0; k < m->pass_count; k++)
                if (!m->passes[k].at) {
                    halo_strbuf_printf(&names, "%s%s", names.len ? ", " : "", m->name);
                    break;
                }
        }
        int at = h->marker_line ? h->marker_line : 1;
        halo_diagnostics_report(
            diag, HALO_SEVERITY_ERROR, HALO_MSG_HOST_SINGLE_PASS, p->host_file, at, 1, p->host_lines[at - 1],
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
            if (p->outputs[o].location >= location)
                location = p->outputs[o].location + 1;
        p->segment_location = location;
    }
    return 0;
}

static halo_program *link_with_host(const halo_link_desc *desc, halo_host_info *h, int prepass_only,
                                    halo_diagnostics *diag);

halo_program *halo_link_host(const halo_link_desc *desc, halo_diagnostics *diag)
{
    halo_host_info h = {0};
    halo_program *p = link_with_host(desc, &h, 0, diag);
    halo_host_scan_free(&h.scan);
    return p;
}

halo_program *halo_link_prepass(const halo_link_desc *desc, halo_diagnostics *diag)
{
    halo_host_info h = {0};
    halo_program *p = link_with_host(desc, &h, 1, diag);
    halo_host_scan_free(&h.scan);
    return p;
}

/* The reflection's declarations, which uniforms an engine declares (halo_link_desc.
 * engine_uniforms) and as what: the live parameters a stage reads, a bool one as int, a
 * channels one as the program's halo_channels type. Fixed at link; their values follow
 * the program's (halo_program_derive). 0 when out of memory. */
static int link_declarations(halo_program *p)
{
    static const char *const channel_types[] = {"float", "float", "vec2", "vec3", "vec4"};
    if (!(p->declarations = calloc(p->uniform_count + 1, sizeof *p->declarations)))
        return 0;
    for (size_t i = 0; i < p->uniform_count; ++i) {
        const halo_uniform_info *u = &p->uniforms[i];
        const halo_param_info *info = u->info;
        const halo_module *m = NULL;
        for (size_t s = 0; s < p->stage_count && !m; s++)
            if (!strcmp(p->stages[s].module->name, u->stage))
                m = p->stages[s].module;
        if (!u->live || !m)
            continue;
        char count_name[160];
        snprintf(count_name, sizeof count_name, "%s_count", info->name);
        int used = halo_module_uses(m, info->name), count_used = info->array_size && halo_module_uses(m, count_name);
        if (!used && !count_used)
            continue;
        halo_uniform_decl *d = &p->declarations[p->declaration_count++];
        d->name = u->name;
        d->param = u;
        d->components = info->components;
        if (info->type == HALO_PARAM_BOOL)
            d->glsl_type = "int";
        else if (info->type == HALO_PARAM_CHANNELS) {
            /* halo_channels, the type the stages read: one float or vector of the program's
             * channels (its values a list of up to 4 in the module, no array in GLSL) */
            d->glsl_type = channel_types[p->channel_count];
            d->components = p->channel_count;
            continue;
        } else
            d->glsl_type = halo_param_type_name(info->type);
        if (info->array_size) {
            d->array_size = used ? info->array_size : 0;
            d->count_name = count_used ? u->count_name : NULL;
            if (!used)
                d->name = NULL; /* only the companion is read */
        }
    }
    return 1;
}

static halo_program *link_with_host(const halo_link_desc *desc, halo_host_info *h, int prepass_only,
                                    halo_diagnostics *diag)
{
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
    if (desc->pieces &&
        (desc->pieces->first_output_location < 0 || desc->pieces->first_output_location > HALO_MAX_OUTPUT_LOCATION)) {
        halo_diag_error(diag, USAGE, "", 0, 0,
                        "halo_link: pieces.first_output_location is %d: 0 (after the engine's colour) or 1..%d",
                        desc->pieces->first_output_location, HALO_MAX_OUTPUT_LOCATION);
        return NULL;
    }
    halo_program *p = calloc(1, sizeof *p);
    if (!p)
        goto oom;
    atomic_init(&p->refs, 1);
    p->library = desc->library;
    halo_library_retain(p->library);
    p->target = desc->target == HALO_TARGET_DEFAULT ? HALO_TARGET_GLSL330 : desc->target;
    p->kind = desc->kind;
    p->version = desc->version;
    p->engine_uniforms = desc->engine_uniforms != 0;
    p->unlocated_outputs = desc->output_locations == HALO_LOCATIONS_BY_NAME ||
                           (p->target == HALO_TARGET_GLSL150 && desc->output_locations != HALO_LOCATIONS_EXTENSION);
    p->first_location = desc->pieces ? desc->pieces->first_output_location : 0;
    p->host_file = halo_strdup(desc->host_file ? desc->host_file : "host");
    /* a UTF-8 byte-order mark is no part of the shader */
    const char *host_source = halo_skip_bom(desc->host_source);
    p->host_storage = halo_strdup(host_source);
    if (!p->host_file || !p->host_storage)
        goto oom;
    int host_count = halo_split_lines(p->host_storage, &p->host_lines);
    if (host_count < 0)
        goto oom;

    /* 1. The host keeps the contract. */
    if (halo_host_scan_run(&(halo_host_scan_desc){host_source, p->target, p->kind, halo_host_is_marker_line}, &h->scan))
        goto oom;
    int errors = halo_host_check(p->host_file, host_source, p->host_lines, host_count, h, p->target, diag);
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
    p->stage_infos = calloc((size_t)n + 1, sizeof *p->stage_infos);
    if (!p->stages || !p->stage_infos) {
        free(order);
        goto oom;
    }
    for (int i = 0; i < n; i++) {
        const halo_module *m = order[i].module;
        p->stage_infos[p->stage_count] = m->info;
        halo_linked_stage *st = &p->stages[p->stage_count++];
        st->module = m;
        st->values = calloc(m->param_count + 1, sizeof *st->values);
        if (!st->values) {
            free(order);
            goto oom;
        }
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
    if (halo_program_set_groups(p))
        goto oom;
    if (halo_program_build_uniforms(p, desc->all_live))
        goto oom;
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
    int host_errors = 0;
    if (resources >= 0) { /* in this order: the checks of the calls read the plan (segment_location) */
        host_errors += plan_segments(p, desc, h, diag);
        host_errors += halo_host_check_calls(p, h, host_source, diag);
        host_errors += halo_host_check_outputs(p, h, host_source, diag);
    }
    if (resources || host_errors) {
        halo_program_destroy(p);
        return NULL;
    }
    set_image_scales(p);
    /* host contract 3: the stages that seed the generation passes run in libhalo's march */
    if (desc->one_draw && !prepass_only && halo_program_has_generation_passes(p)) {
        /* a slice host (one sample a fragment) draws all its slices over the field; a slab
         * host marches each slab's rays, with the passes between the slabs */
        int slab = h->slices && (halo_host_uses(host_source, "for") || halo_host_uses(host_source, "while"));
        const char *why = desc->force_segments ? "force_segments draws the host in segments"
                          : slab ? "a host with '#pragma halo slices' and a loop (for, while) is taken for a slab "
                                   "host, which marches its slabs' rays with the passes between them"
                          : p->kind != HALO_SHADER_FRAGMENT ? "it is for fragment shaders"
                          : !halo_prepass_mark(p)           ? "no stage seeds the passes from its samples"
                                                            : NULL;
        if (why) {
            halo_diag_error(diag, USAGE, "", 0, 0, "halo_link: one_draw (host contract 3) cannot take this program: %s",
                            why);
            halo_program_destroy(p);
            return NULL;
        }
        p->one_draw = 1;
        halo_prepass_drop_outputs(p, 1);
        /* the seeds are no longer the host's outputs: libhalo's march writes them at the
         * halo images' scale (gl/field.c), a ray a pixel of the 1/image_scale image */
        set_image_scales(p);
        /* the march and the host share the parameters' values: halo_program_set changes both */
        halo_link_desc march = halo_prepass_desc(p, desc);
        if (!(p->prepass = halo_link_prepass(&march, diag)) || !halo_prepass_host_uniforms_known(p->prepass, diag)) {
            halo_program_destroy(p);
            return NULL;
        }
    } else if (prepass_only) {
        halo_prepass_mark(p);
        /* the march writes the seeds only: the host's samples write the other outputs
         * (outline features), which the march's draws would otherwise overwrite */
        halo_prepass_drop_outputs(p, 0);
        p->prepass_only = 1;
    }
    if (p->group_count > 1)
        halo_program_load_group(p, 0);
    /* 5. Emit. */
    if (halo_host_hide_line_directives(p, h))
        goto oom;
    if (halo_emit_program(p, host_source, p->host_lines, host_count, h, desc->library))
        goto oom;
    if (halo_host_check_macros(p, h, diag)) {
        halo_program_destroy(p);
        return NULL;
    }
    if (halo_host_map_lines(p, h))
        goto oom;
    int passes = build_passes(p, desc->library, diag);
    if (passes == -2) {
        halo_program_destroy(p);
        return NULL;
    }
    if (passes)
        goto oom;
    if (!link_declarations(p))
        goto oom;
    halo_program_derive(p);
    return p;
oom:
    halo_diag_error(diag, OUT_OF_MEMORY, "", 0, 0, "out of memory");
    halo_program_destroy(p);
    return NULL;
}
