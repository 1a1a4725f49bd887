/* The linked program (halo_program): the strings it owns, its uniforms and feature
 * groups, its destruction, and the reflection a host reads (halo.h). The linker
 * (link.c) builds it. */
#include "diag.h"
#include "internal.h"
#include "strbuf.h"

#include <jansson.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

const char halo_generated_file[] = "<libhalo>";

char *halo_program_own(halo_program *p, const char *fmt, ...)
{
    halo_strbuf b = {0};
    va_list ap;
    va_start(ap, fmt);
    halo_strbuf_vprintf(&b, fmt, ap);
    va_end(ap);
    char *str = halo_strbuf_take(&b);
    char **list = str ? realloc(p->strings, (p->string_count + 1) * sizeof *list) : NULL;
    if (!list) {
        free(str);
        return NULL;
    }
    p->strings = list;
    p->strings[p->string_count++] = str;
    return str;
}

halo_image_info *halo_program_image_named(halo_program *p, const char *name)
{
    for (size_t i = 0; i < p->image_count; i++)
        if (!strcmp(p->images[i].name, name))
            return &p->images[i];
    return NULL;
}

/* Whether param `name` of a linked stage could be on: live, grouped (its values change per
 * group), or some element >= 0.5. */
static int param_may_be_on(const halo_linked_stage *st, const char *name)
{
    for (size_t i = 0; i < st->module->param_count; i++) {
        if (strcmp(st->module->params[i].name, name))
            continue;
        const halo_param_value *v = &st->values[i];
        if (v->live || st->group_values)
            return 1;
        for (int c = 0; c < (v->count > 0 ? v->count : 1) && c < HALO_MAX_COMPONENTS; c++)
            if (v->value[c] >= 0.5)
                return 1;
        return 0;
    }
    return 1;
}

/* Desktop GLSL filters every float format linearly; OpenGL ES 3.0 filters 16-bit floats and
 * 8-bit normalized images, but 32-bit floats only with OES_texture_float_linear, which the
 * linked text cannot ask for: there the four fetches stay. */
int halo_program_image_filtered(const halo_program *p, const halo_image_info *im)
{
    if (!im || im->scale <= 1)
        return 0;
    return p->target != HALO_TARGET_ES300 || p->image_precision == 16 || p->image_precision == 8;
}

/* An image that only conditional readers declare (`image NAME read_when=PARAM`), each with
 * its condition off, and that no pass of another image reads: the passes writing it are
 * dead work (e.g. the occlusion image of a scene without occlusive halos). */
int halo_program_image_unread(const halo_program *p, const char *image)
{
    int conditional = 0;
    for (size_t s = 0; s < p->stage_count; s++) {
        const halo_linked_stage *st = &p->stages[s];
        const halo_module *m = st->module;
        for (size_t i = 0; i < m->pass_count; i++)
            for (int k = 0; k < m->passes[i].input_count; k++)
                if (!strcmp(m->passes[i].inputs[k], image) && strcmp(m->passes[i].output, image))
                    return 0;
        if (m->hook != HALO_HOOK_SAMPLE)
            continue;
        for (size_t i = 0; i < m->image_count; i++) {
            const halo_image_decl *im = &m->images[i];
            if (strcmp(im->name, image))
                continue;
            if (im->family || !im->read_when || param_may_be_on(st, im->read_when))
                return 0;
            conditional = 1;
        }
    }
    return conditional;
}

int halo_program_build_uniforms(halo_program *p, int all_live)
{
    size_t n = 0;
    for (size_t s = 0; s < p->stage_count; s++)
        n += p->stages[s].module->param_count;
    p->uniforms = calloc(n + 1, sizeof *p->uniforms);
    p->uniform_names = calloc(n + 1, sizeof *p->uniform_names);
    if (!p->uniforms || !p->uniform_names)
        return -1;
    for (size_t s = 0; s < p->stage_count; s++) {
        halo_linked_stage *st = &p->stages[s];
        st->first_uniform = p->uniform_count;
        for (size_t i = 0; i < st->module->param_count; i++) {
            halo_strbuf b = {0};
            halo_strbuf_printf(&b, "halo_%s_%s", st->module->name, st->module->params[i].name);
            char *name = halo_strbuf_take(&b);
            if (!name)
                return -1;
            p->uniform_names[p->uniform_count] = name;
            halo_param_value *v = &st->values[i];
            if (all_live)
                v->live = 1;
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
            if (st->module->params[i].array_size && !p->uniforms[p->uniform_count - 1].count_name)
                return -1;
        }
    }
    return 0;
}

void halo_program_retain(const halo_program *p) { atomic_fetch_add(&((halo_program *)p)->refs, 1); }

void halo_program_destroy(halo_program *p)
{
    if (!p || atomic_fetch_sub(&p->refs, 1) != 1)
        return;
    halo_program_destroy(p->prepass);
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
    free(p->block.text);
    free(p->block.origins);
    free(p->tail.text);
    free(p->tail.origins);
    for (size_t s = 0; s < p->stage_count; s++) {
        free(p->stages[s].values);
        free(p->stages[s].group_values);
    }
    free(p->stages);
    free(p->stage_infos);
    for (size_t i = 0; i < p->uniform_count; i++)
        free(p->uniform_names[i]);
    free(p->uniform_names);
    free(p->uniforms);
    free(p->declarations);
    free(p->outputs);
    free(p->passes);
    for (size_t i = 0; i < p->pass_count; i++)
        free(p->pass_origins[i]);
    free(p->pass_origins);
    free(p->pass_origin_counts);
    free(p->images);
    free(p->samplers);
    free(p->host_uniforms);
    for (size_t i = 0; i < p->string_count; i++)
        free(p->strings[i]);
    free(p->strings);
    halo_library_release(p->library);
    free(p);
}


const char halo_pieces_file[] = "(libhalo piece)";

/* halo_program_map_line for one of its pieces (p not NULL). */
static int piece_map_line(const halo_program *p, halo_piece piece, int line, const char **file, int *origin_line)
{
    if ((unsigned)piece >= HALO_PIECE_COUNT || !p->pieces[piece] || line < 1 || line > p->piece_origin_counts[piece])
        return 0;
    const halo_line_origin *o = &p->piece_origins[piece][line - 1];
    if (o->file == halo_generated_file || o->file == halo_pieces_file || !o->line)
        return 0;
    if (file)
        *file = o->file;
    if (origin_line)
        *origin_line = o->line;
    return 1;
}

const char *halo_program_source(const halo_program *p, halo_piece piece)
{
    HALO_REFUSE_NULL(NULL, p, "program", NULL);
    if (piece == HALO_PIECE_WHOLE)
        return p->source;
    return (unsigned)piece < HALO_PIECE_COUNT ? p->pieces[piece] : NULL;
}

int halo_program_map_line(const halo_program *p, halo_piece piece, int line, const char **file, int *origin_line)
{
    HALO_REFUSE_NULL(NULL, p, "program", 0);
    if (piece != HALO_PIECE_WHOLE)
        return piece_map_line(p, piece, line, file, origin_line);
    if (line < 1 || line > p->origin_count)
        return 0;
    const halo_line_origin *o = &p->origins[line - 1];
    if (file)
        *file = o->file;
    if (origin_line)
        *origin_line = o->line;
    return o->file != halo_generated_file;
}

/* The reflection's interval and reads_labels. */
static int program_interval(const halo_program *p)
{
    for (size_t i = 0; i < p->stage_count; i++) {
        const halo_module *m = p->stages[i].module;
        const halo_uniform_info *u = m->info.interval ? halo_program_find_uniform(p, m->name, m->info.interval) : NULL;
        if (u && u->value && u->count > 0 && u->value[0] >= 1.0 && u->value[0] < 1e6)
            return (int)u->value[0];
    }
    return 0;
}

static int program_reads_labels(const halo_program *p)
{
    for (size_t i = 0; i < p->stage_count; i++) {
        const halo_module *m = p->stages[i].module;
        int declares = 0;
        for (size_t k = 0; k < m->host_uniform_count; k++)
            declares |= !strcmp(m->host_uniforms[k].name, "labels");
        if (!declares)
            continue;
        if (!m->info.labels_when)
            return 1;
        const halo_uniform_info *u = halo_program_find_uniform(p, m->name, m->info.labels_when);
        if (!u || u->live)
            return 1;
        for (int k = 0; k < u->count; k++)
            if (u->value[k] >= 0.0)
                return 1;
    }
    return 0;
}
const halo_uniform_info *halo_program_find_uniform(const halo_program *p, const char *stage, const char *param)
{
    HALO_REFUSE_NULL(NULL, p, "program", NULL);
    HALO_REFUSE_NULL(NULL, stage, "stage", NULL);
    HALO_REFUSE_NULL(NULL, param, "param", NULL);
    for (size_t i = 0; i < p->uniform_count; i++)
        if (!strcmp(p->uniforms[i].stage, stage) && !strcmp(p->uniforms[i].param, param))
            return &p->uniforms[i];
    return NULL;
}

/* Does a pass of module m take its schedule from param: its repetitions (repeat=PARAM), its
 * reach (reach=B^(PARAM-i)) or whether it runs (when=PARAM,...)? The linker fixed those at
 * the linked value. */
static const char *schedule_use(const halo_module *m, const char *param)
{
    for (size_t k = 0; k < m->pass_count; k++) {
        const halo_pass_decl *pd = &m->passes[k];
        if (pd->repeat && !strcmp(pd->repeat, param))
            return "repeat=";
        if (pd->reach_param && !strcmp(pd->reach_param, param))
            return "reach=";
        for (const char *w = pd->when; w && *w;) {
            w += *w == '!';
            size_t n = strcspn(w, ",");
            if (n == strlen(param) && !strncmp(w, param, n))
                return "when=";
            w += n + (w[n] == ',');
        }
    }
    return NULL;
}

halo_status halo_program_set(halo_program *p, const char *stage, const char *param, const double *values, int count,
                             halo_diagnostics *diag)
{
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
        halo_diagnostics_report(diag, HALO_SEVERITY_ERROR, (halo_message_id)id, "", 0, 0, NULL, "%s.%s: %s", stage,
                                param, why);
        return HALO_ERROR_INPUT;
    }
    /* a parameter that schedules image passes: the passes were planned at its linked value */
    const halo_module *m = NULL;
    for (size_t s = 0; s < p->stage_count && !m; s++)
        if (!strcmp(p->stages[s].module->name, stage))
            m = p->stages[s].module;
    const char *use = m ? schedule_use(m, param) : NULL;
    int changed = count != u->count;
    for (int i = 0; i < count * u->info->components && !changed; i++)
        changed = values[i] != u->value[i];
    if (use && changed) {
        halo_diag_error(diag, USAGE, "", 0, 0,
                        "%s.%s schedules the stage's image passes (%s): they were planned at its linked value %g; "
                        "link the scene again (halo_link) to change it",
                        stage, param, use, u->value[0]);
        return HALO_ERROR_INPUT;
    }
    /* a grouped parameter of a program with feature groups: the whole list; the current
     * group's four become the uniform's values */
    for (size_t s = 0; s < p->stage_count; s++) {
        halo_linked_stage *st = &p->stages[s];
        if (!st->group_values || strcmp(st->module->name, stage))
            continue;
        size_t i = (size_t)(u->info - st->module->params);
        if (st->module->params[i].type != HALO_PARAM_CHANNELS)
            break;
        if (count > 4 * p->group_count) {
            halo_diag_error(diag, USAGE, "", 0, 0,
                            "%s.%s: %d features need more than the program's %d feature groups; link the scene again",
                            stage, param, count, p->group_count);
            return HALO_ERROR_INPUT;
        }
        memcpy(st->group_values[i].value, values, (size_t)count * sizeof(double));
        st->group_values[i].count = count;
        halo_program_load_group(p, p->group);
        return HALO_OK;
    }
    halo_uniform_info *w = &p->uniforms[u - p->uniforms];
    memcpy((double *)w->value, values, (size_t)count * (size_t)u->info->components * sizeof(double));
    w->count = count;
    /* Keep the stage's value record in step. */
    for (size_t s = 0; s < p->stage_count; s++)
        for (size_t i = 0; i < p->stages[s].module->param_count; i++)
            if (p->stages[s].values[i].value == w->value)
                p->stages[s].values[i].count = count;
    halo_program_derive(p);
    /* host contract 3: the march, linked from the same scene, has the same live parameters */
    if (p->prepass) /* the same stages and parameters: checked above */
        halo_program_set(p->prepass, stage, param, values, count, NULL);
    return HALO_OK;
}

halo_reflection halo_program_reflection(const halo_program *p)
{
    halo_reflection r = {.target = HALO_TARGET_COUNT};
    if (!p)
        return r;
    r.stage_count = p->stage_count;
    r.stages = p->stage_infos;
    r.uniform_count = p->uniform_count;
    r.uniforms = p->uniforms;
    r.output_count = p->output_count;
    r.outputs = p->outputs;
    r.pass_count = p->pass_count;
    r.passes = p->passes;
    r.image_count = p->image_count;
    r.images = p->images;
    r.sampler_count = p->sampler_count;
    r.samplers = p->samplers;
    r.host_uniform_count = p->host_uniform_count;
    r.host_uniforms = p->host_uniforms;
    r.channel_count = p->channel_count;
    r.image_precision = p->image_precision;
    r.image_scale = p->image_scale;
    r.segment_location = p->segment_location;
    r.one_draw = p->one_draw;
    r.march = p->one_draw ? p->prepass : NULL;
    r.target = p->target;
    r.group_count = p->group_count > 1 ? p->group_count : 1;
    r.interval = p->derived_interval;
    r.reads_labels = p->derived_reads_labels;
    r.declaration_count = p->declaration_count;
    r.declarations = p->declarations;
    return r;
}

/* Group g's values of every grouped channels parameter: values 4g .. 4g + 3 of the
 * scene's list (the last value repeated where the list ends), padded to the channel
 * count by repeating the group's last. */
void halo_program_load_group(halo_program *p, int g)
{
    for (size_t s = 0; s < p->stage_count; s++) {
        halo_linked_stage *st = &p->stages[s];
        if (!st->group_values)
            continue;
        for (size_t i = 0; i < st->module->param_count; i++) {
            if (st->module->params[i].type != HALO_PARAM_CHANNELS)
                continue;
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
    halo_program_derive(p);
}

/* The values of the reflection's declarations (built at link: link.c's link_declarations):
 * a parameter's current ones, a channels one converted to the program's halo_channels. */
static void refresh_declarations(halo_program *p)
{
    for (size_t i = 0; i < p->declaration_count; ++i) {
        halo_uniform_decl *d = &p->declarations[i];
        const halo_uniform_info *u = d->param;
        if (u->info->type != HALO_PARAM_CHANNELS) {
            d->count = u->count;
            d->value = u->value;
            continue;
        }
        /* one value per channel; fewer set: the last repeats */
        for (int k = 0; k < p->channel_count && u->count > 0; k++)
            d->storage[k] = u->value[k < u->count ? k : u->count - 1];
        d->count = 1;
        d->value = d->storage;
    }
}

void halo_program_derive(halo_program *p)
{
    p->derived_interval = program_interval(p);
    p->derived_reads_labels = program_reads_labels(p);
    refresh_declarations(p);
}

halo_status halo_program_select_group(halo_program *p, int group)
{
    HALO_REFUSE_NULL(NULL, p, "program", HALO_ERROR_INPUT);
    if (group < 0 || group >= (p->group_count > 1 ? p->group_count : 1))
        return HALO_ERROR_INPUT;
    if (p->group_count > 1)
        halo_program_load_group(p, group);
    return HALO_OK;
}

/* Feature groups: grouped stages whose channels lists are longer than four. Their lists
 * are kept whole (group_values), their channels parameters become uniforms (switching
 * groups is an upload), and group 0 is loaded. */
int halo_program_set_groups(halo_program *p)
{
    int features = 0;
    for (size_t s = 0; s < p->stage_count; s++) {
        const halo_module *m = p->stages[s].module;
        for (size_t i = 0; m->groups && i < m->param_count; i++)
            if (m->params[i].type == HALO_PARAM_CHANNELS && p->stages[s].values[i].count > features)
                features = p->stages[s].values[i].count;
    }
    p->group_count = features > 4 ? (features + 3) / 4 : 1;
    if (p->group_count == 1)
        return 0;
    for (size_t s = 0; s < p->stage_count; s++) {
        halo_linked_stage *st = &p->stages[s];
        if (!st->module->groups)
            continue;
        st->group_values = calloc(st->module->param_count + 1, sizeof *st->group_values);
        if (!st->group_values)
            return -1;
        for (size_t i = 0; i < st->module->param_count; i++) {
            if (st->module->params[i].type != HALO_PARAM_CHANNELS)
                continue;
            st->group_values[i] = st->values[i];
            st->values[i].live = 1;
            st->values[i].count = 4; /* group 0 (set_channel_count sees four) */
        }
    }
    return 0;
}

int halo_pass_reach(const halo_pass_info *pass, int repetition)
{
    HALO_REFUSE_NULL(NULL, pass, "pass", -1);
    if (pass->reach < 0)
        return -1;
    if (pass->reach_exponent < 0)
        return pass->reach;
    /* in long long and clamped before shifting: no int overflow for any exponent or repetition */
    long long e = (long long)pass->reach_exponent - repetition, bits = pass->reach_base == 4 ? 2 : 1;
    long long shift = e < 0 ? 0 : e > 30 ? 30 : e * bits > 30 ? 30 : e * bits;
    long long factor = pass->reach_factor > 1 ? pass->reach_factor : 1;
    long long reach = (long long)pass->reach + (factor > (1 << 30) ? 1 << 30 : factor) * (1LL << shift);
    return reach > (1 << 30) ? 1 << 30 : (int)reach;
}

static json_t *number_or_null(double v) { return isfinite(v) ? json_real(v) : json_null(); }

char *halo_program_reflect_json(const halo_program *p)
{
    HALO_REFUSE_NULL(NULL, p, "program", NULL);
    json_t *root = json_object();
    json_object_set_new(root, "contract", json_integer(HALO_CONTRACT_VERSION));
    json_object_set_new(root, "target", json_string(halo_target_name(p->target)));
    json_t *stages = json_array();
    for (size_t s = 0; s < p->stage_count; s++)
        json_array_append_new(stages, json_string(p->stages[s].module->name));
    json_object_set_new(root, "stages", stages);
    json_t *infos = json_array();
    for (size_t s = 0; s < p->stage_count; s++) {
        const halo_stage_info *in = &p->stages[s].module->info;
        json_t *o = json_object();
        json_object_set_new(o, "name", json_string(in->name));
        json_object_set_new(o, "keeps_empty", json_boolean(in->keeps_empty));
        json_object_set_new(o, "zero_generation", json_boolean(in->zero_generation));
        json_object_set_new(o, "labels_when", in->labels_when ? json_string(in->labels_when) : json_null());
        json_object_set_new(o, "interval", in->interval ? json_string(in->interval) : json_null());
        json_object_set_new(o, "strip_width", in->strip_width ? json_string(in->strip_width) : json_null());
        json_object_set_new(o, "core_fraction", in->core_fraction ? json_string(in->core_fraction) : json_null());
        json_array_append_new(infos, o);
    }
    json_object_set_new(root, "stage_info", infos);
    json_t *uniforms = json_array(), *constants = json_array();
    for (size_t i = 0; i < p->uniform_count; i++) {
        const halo_uniform_info *u = &p->uniforms[i];
        json_t *o = json_object();
        json_object_set_new(o, "name", json_string(u->name));
        json_object_set_new(o, "stage", json_string(u->stage));
        json_object_set_new(o, "param", json_string(u->param));
        halo_strbuf t = {0};
        halo_strbuf_append(&t, u->info->type == HALO_PARAM_CHANNELS ? "channels" : halo_param_type_name(u->info->type));
        if (u->info->array_size && u->info->type != HALO_PARAM_CHANNELS)
            halo_strbuf_printf(&t, "[%d]", u->info->array_size);
        json_object_set_new(o, "type", json_string(t.data ? t.data : "?"));
        halo_strbuf_free(&t);
        json_t *val = json_array();
        for (int k = 0; k < u->count * u->info->components; k++)
            json_array_append_new(val, json_real(u->value[k]));
        json_object_set_new(o, "value", val);
        json_object_set_new(o, "count", json_integer(u->count));
        json_object_set_new(o, "min", number_or_null(u->info->min));
        json_object_set_new(o, "max", number_or_null(u->info->max));
        if (u->info->step > 0.0)
            json_object_set_new(o, "step", json_real(u->info->step));
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
    /* host contract 3: the field computed before the host is drawn once */
    json_object_set_new(root, "one_draw", json_boolean(p->one_draw));
    /* a stage reads halo_host_labels (halo_reflection.reads_labels): else the sampler is unread */
    json_object_set_new(root, "reads_labels", json_boolean(p->derived_reads_labels));
    json_t *samplers = json_array();
    for (size_t i = 0; i < p->sampler_count; i++)
        json_array_append_new(samplers,
                              json_pack("{s:s, s:s}", "name", p->samplers[i].name, "image", p->samplers[i].image));
    json_object_set_new(root, "samplers", samplers);
    json_t *host_uniforms = json_array();
    for (size_t i = 0; i < p->host_uniform_count; i++) {
        const halo_host_uniform_info *h = &p->host_uniforms[i];
        json_array_append_new(host_uniforms, json_pack("{s:s, s:s, s:s, s:s}", "name", h->name, "type", h->type,
                                                       "meaning", h->meaning, "set_by", "host"));
    }
    /* the camera and segment uniforms: a host that draws without halo_gl_frame_draw sets them */
    for (size_t i = 0; i < halo_runtime_uniform_count; i++) {
        const halo_runtime_uniform *u = &halo_runtime_uniforms[i];
        if (halo_program_declares_runtime_uniform(p, u))
            json_array_append_new(host_uniforms, json_pack("{s:s, s:s, s:s, s:s}", "name", u->name, "type", u->type,
                                                           "meaning", u->meaning, "set_by", u->set_by));
    }
    json_object_set_new(root, "host_uniforms", host_uniforms);
    json_t *images = json_array();
    for (size_t i = 0; i < p->image_count; i++) {
        json_t *o = json_object();
        json_object_set_new(o, "name", json_string(p->images[i].name));
        json_object_set_new(o, "channels", json_integer(p->images[i].channels));
        if (p->images[i].clear != 0.0)
            json_object_set_new(o, "clear", json_real(p->images[i].clear));
        if (p->images[i].host)
            json_object_set_new(o, "host", json_true());
        if (p->images[i].scale > 1)
            json_object_set_new(o, "scale", json_integer(p->images[i].scale));
        json_object_set_new(o, "reset",
                            json_string(p->images[i].reset == HALO_RESET_GENERATION ? "generation" : "frame"));
        json_array_append_new(images, o);
    }
    json_object_set_new(root, "images", images);
    static const char *const blends[] = {"none", "max", "add", "min", "first"};
    json_t *outputs = json_array();
    for (size_t i = 0; i < p->output_count; i++) {
        const halo_output_info *o = &p->outputs[i];
        json_array_append_new(outputs,
                              json_pack("{s:s, s:i, s:i, s:s, s:s}", "name", o->name, "location", o->location,
                                        "components", o->components, "image", o->image, "blend", blends[o->blend]));
    }
    json_object_set_new(root, "outputs", outputs);
    json_t *passes = json_array();
    for (size_t i = 0; i < p->pass_count; i++) {
        const halo_pass_info *pi = &p->passes[i];
        json_t *o = json_object();
        json_object_set_new(o, "name", json_string(pi->name));
        json_object_set_new(o, "stage", json_string(pi->stage));
        json_object_set_new(o, "entry", json_string(pi->entry));
        json_object_set_new(o, "start", json_integer(pi->start));
        json_t *in = json_array();
        for (int k = 0; k < pi->input_count; k++)
            json_array_append_new(in, json_string(pi->inputs[k]));
        json_object_set_new(o, "inputs", in);
        if (pi->first)
            json_object_set_new(o, "first", json_string(pi->first));
        json_object_set_new(o, "output", json_string(pi->output));
        json_object_set_new(o, "repeat", json_integer(pi->repeat));
        if (pi->repeat_param)
            json_object_set_new(o, "repeat_param", json_string(pi->repeat_param));
        if (pi->at)
            json_object_set_new(o, "at", json_string(pi->at == HALO_PASS_AT_FINAL ? "final" : "post"));
        if (pi->channel >= 0)
            json_object_set_new(o, "channel", json_integer(pi->channel));
        json_array_append_new(passes, o);
    }
    json_object_set_new(root, "passes", passes);
    char *text = json_dumps(root, JSON_INDENT(2) | JSON_PRESERVE_ORDER | JSON_REAL_PRECISION(9));
    json_decref(root);
    return text;
}
