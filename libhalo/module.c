/* Parsing a module: `#pragma halo` annotations, then the code's global declarations. */
#include "diag.h"
#include "internal.h"
#include "strbuf.h"

#include <ctype.h>
#include <float.h>
#include <jansson.h>
#include <limits.h>
#include <math.h>
#include <stdlib.h>
#include <stddef.h>
#include <string.h>

static const char *const hook_names[HALO_HOOK_COUNT] = {"sample", "image", "line_vertex", "line_fragment"};

int halo_name_list_has(const halo_name_list *l, const char *name)
{
    for (size_t i = 0; i < l->count; i++)
        if (!strcmp(l->items[i], name))
            return 1;
    return 0;
}

int halo_name_list_has_n(const halo_name_list *l, const char *name, size_t n)
{
    for (size_t i = 0; i < l->count; i++)
        if (!strncmp(l->items[i], name, n) && l->items[i][n] == '\0')
            return 1;
    return 0;
}

int halo_name_list_add(halo_name_list *l, const char *name, size_t n, int line)
{
    char **items = realloc(l->items, (l->count + 1) * sizeof *items);
    if (!items)
        return -1;
    l->items = items;
    int *lines = realloc(l->lines, (l->count + 1) * sizeof *lines);
    if (!lines)
        return -1;
    l->lines = lines;
    char *s = malloc(n + 1);
    if (!s)
        return -1;
    memcpy(s, name, n);
    s[n] = '\0';
    l->items[l->count] = s;
    l->lines[l->count] = line;
    l->count++;
    return 0;
}

void halo_name_list_free(halo_name_list *l)
{
    for (size_t i = 0; i < l->count; i++)
        free(l->items[i]);
    free(l->items);
    free(l->lines);
    memset(l, 0, sizeof *l);
}

const char *halo_param_type_name(halo_param_type t)
{
    static const char *const names[] = {"float", "vec2", "vec3", "vec4", "int", "bool", "halo_channels"};
    return (unsigned)t < 7 ? names[t] : "?";
}

static int param_components(halo_param_type t)
{
    switch (t) {
    case HALO_PARAM_VEC2:
        return 2;
    case HALO_PARAM_VEC3:
        return 3;
    case HALO_PARAM_VEC4:
        return 4;
    default:
        return 1;
    }
}

/* The range a value of this type can hold in the shader: int's for int, float's for
 * the float-based types (beyond it a float is +-inf, an int cast is undefined). */
static void type_range(halo_param_type t, double *lowest, double *highest)
{
    if (t == HALO_PARAM_INT) {
        *lowest = INT_MIN;
        *highest = INT_MAX;
    } else if (t == HALO_PARAM_BOOL) {
        *lowest = 0;
        *highest = 1;
    } else {
        *lowest = -FLT_MAX;
        *highest = FLT_MAX;
    }
}

/* Whether v fits the type; if not, why names the value and the range. */
static int fits_type(halo_param_type t, double v, char *why, size_t why_len)
{
    double lowest, highest;
    type_range(t, &lowest, &highest);
    if (v >= lowest && v <= highest)
        return 1;
    if (t == HALO_PARAM_INT || t == HALO_PARAM_BOOL)
        snprintf(why, why_len, "%.15g is outside the %s range [%.0f, %.0f]", v, halo_param_type_name(t), lowest,
                 highest);
    else
        snprintf(why, why_len, "%.15g is outside the float range [%.9g, %.9g]", v, lowest, highest);
    return 0;
}

int halo_param_check(const halo_param_info *info, const double *values, int count, char *why, size_t why_len)
{
    int max_count = info->array_size ? info->array_size : 1;
    if (count < 1 || count > max_count) {
        snprintf(why, why_len, "has %d element%s; %s takes %s%d", count, count == 1 ? "" : "s", info->name,
                 info->array_size ? "1 to " : "", max_count);
        return HALO_MSG_SCENE_VALUE_COUNT;
    }
    for (int i = 0; i < count * info->components; i++) {
        double v = values[i];
        if (!isfinite(v)) {
            snprintf(why, why_len, "%g is not finite", v);
            return HALO_MSG_SCENE_VALUE_NONFINITE;
        }
        if (!fits_type(info->type, v, why, why_len))
            return v < 0 ? HALO_MSG_SCENE_VALUE_BELOW_MIN : HALO_MSG_SCENE_VALUE_ABOVE_MAX;
        if (v < info->min) {
            snprintf(why, why_len, "%.9g is below the minimum %.9g", v, info->min);
            return HALO_MSG_SCENE_VALUE_BELOW_MIN;
        }
        if (v > info->max) {
            snprintf(why, why_len, "%.9g is above the maximum %.9g", v, info->max);
            return HALO_MSG_SCENE_VALUE_ABOVE_MAX;
        }
        if ((info->type == HALO_PARAM_INT || info->type == HALO_PARAM_BOOL) && v != floor(v)) {
            snprintf(why, why_len, "%.9g is not a whole number", v);
            return HALO_MSG_SCENE_TYPE;
        }
    }
    return -1;
}

/* Reads one element (scalar or vector) of a parameter from JSON. Returns -1, or the id. */
static int element_from_json(const halo_param_info *info, json_t *v, double *out, char *why, size_t why_len)
{
    int n = info->components;
    if (n == 1) {
        if (info->type == HALO_PARAM_BOOL && json_is_boolean(v)) {
            out[0] = json_is_true(v);
            return -1;
        }
        if (!json_is_number(v)) {
            snprintf(why, why_len, "expected a number for %s (%s)", info->name, halo_param_type_name(info->type));
            return HALO_MSG_SCENE_TYPE;
        }
        out[0] = json_number_value(v);
        return -1;
    }
    if (!json_is_array(v)) {
        snprintf(why, why_len, "expected a list of %d numbers for %s (%s)", n, info->name,
                 halo_param_type_name(info->type));
        return HALO_MSG_SCENE_TYPE;
    }
    if ((int)json_array_size(v) != n) {
        snprintf(why, why_len, "has %zu numbers; %s (%s) takes %d", json_array_size(v), info->name,
                 halo_param_type_name(info->type), n);
        return HALO_MSG_SCENE_VALUE_COUNT;
    }
    for (int i = 0; i < n; i++) {
        json_t *c = json_array_get(v, (size_t)i);
        if (!json_is_number(c)) {
            snprintf(why, why_len, "expected a list of %d numbers for %s", n, info->name);
            return HALO_MSG_SCENE_TYPE;
        }
        out[i] = json_number_value(c);
    }
    return -1;
}

/* Fills values/count from JSON in the parameter's layout. Returns -1, or a message id
 * (SCENE_TYPE, SCENE_VALUE_COUNT) with why. */
int halo_param_from_json(const halo_param_info *info, void *json, double *values, int *count, char *why,
                         size_t why_len);
int halo_param_from_json(const halo_param_info *info, void *json, double *values, int *count, char *why, size_t why_len)
{
    json_t *v = json;
    if (info->type == HALO_PARAM_CHANNELS && json_is_number(v)) {
        *count = 1;
        values[0] = json_number_value(v);
        return -1;
    }
    if (!info->array_size) {
        *count = 1;
        return element_from_json(info, v, values, why, why_len);
    }
    if (!json_is_array(v)) {
        snprintf(why, why_len, "expected a list of 1 to %d elements for %s", info->array_size, info->name);
        return HALO_MSG_SCENE_TYPE;
    }
    size_t n = json_array_size(v);
    if (n < 1 || n > (size_t)info->array_size) {
        snprintf(why, why_len, "has %zu elements; %s takes 1 to %d", n, info->name, info->array_size);
        return HALO_MSG_SCENE_VALUE_COUNT;
    }
    for (size_t i = 0; i < n; i++) {
        int id = element_from_json(info, json_array_get(v, i), values + i * (size_t)info->components, why, why_len);
        if (id >= 0)
            return id;
    }
    *count = (int)n;
    return -1;
}

/* Splits an annotation's arguments into words: "quoted text", or runs without white
 * space outside brackets (so JSON lists with spaces stay one word). */
typedef struct words {
    char *w[24]; /* MAX_WORDS */
    int col[24];
    int n;
} words;

enum { MAX_WORDS = 24 };

/* 0, or SPLIT_QUOTE (an unclosed quote) or SPLIT_MANY (more than MAX_WORDS words) with
 * *at the column of the quote or of the first word too many. */
enum { SPLIT_QUOTE = 1, SPLIT_MANY };

static int split_words(const char *s, int col0, words *out, char *storage, int *at)
{
    out->n = 0;
    size_t i = 0, k = 0;
    while (s[i]) {
        while (s[i] == ' ' || s[i] == '\t')
            i++;
        if (!s[i])
            break;
        *at = col0 + (int)i;
        if (out->n == MAX_WORDS)
            return SPLIT_MANY;
        out->col[out->n] = col0 + (int)i;
        out->w[out->n++] = storage + k;
        if (s[i] == '"') {
            storage[k++] = s[i++];
            while (s[i] && s[i] != '"')
                storage[k++] = s[i++];
            if (s[i] != '"')
                return SPLIT_QUOTE;
            storage[k++] = s[i++];
        } else {
            int depth = 0;
            while (s[i] && (depth > 0 || (s[i] != ' ' && s[i] != '\t'))) {
                if (s[i] == '[')
                    depth++;
                if (s[i] == ']')
                    depth--;
                storage[k++] = s[i++];
            }
        }
        storage[k++] = '\0';
    }
    return 0;
}

static int valid_name(const char *s)
{
    if (!islower((unsigned char)s[0]))
        return 0;
    for (; *s; s++)
        if (!islower((unsigned char)*s) && !isdigit((unsigned char)*s) && *s != '_')
            return 0;
    return 1;
}

int halo_when_next(const char **cursor, char *name, size_t cap, int *negate)
{
    const char *p = *cursor;
    if (!*p)
        return 0;
    *negate = *p == '!';
    p += *negate;
    size_t n = strcspn(p, ",");
    if (!n || n >= cap)
        return -1; /* empty, or longer than a name can be here */
    snprintf(name, cap, "%.*s", (int)n, p);
    *cursor = p[n] ? p + n + 1 : p + n;
    if (p[n] && !p[n + 1])
        return -1; /* a trailing comma */
    return valid_name(name) ? 1 : -1;
}

static char *unquote(const char *w)
{
    size_t n = strlen(w);
    if (n >= 2 && w[0] == '"' && w[n - 1] == '"') {
        char *s = malloc(n - 1);
        if (s) {
            memcpy(s, w + 1, n - 2);
            s[n - 2] = '\0';
        }
        return s;
    }
    return halo_strdup(w);
}

/* The `is KEY=PARAM` properties (halo_stage_info): which field PARAM's name goes to, and
 * the type that parameter must have (a scalar; -1: any parameter). */
static const struct {
    const char *key;
    size_t offset;
    int type;
    const char *type_name;
} is_params[] = {
    {"labels_when", offsetof(halo_stage_info, labels_when), -1, ""},
    {"interval", offsetof(halo_stage_info, interval), HALO_PARAM_INT, "int "},
    {"strip_width", offsetof(halo_stage_info, strip_width), HALO_PARAM_FLOAT, "float "},
    {"core_fraction", offsetof(halo_stage_info, core_fraction), HALO_PARAM_FLOAT, "float "},
};
#define IS_PARAM_COUNT ((int)(sizeof is_params / sizeof is_params[0]))

static const char **is_param_field(halo_stage_info *info, int k)
{
    return (const char **)((char *)info + is_params[k].offset);
}

typedef struct parse_ctx {
    halo_module *m;
    halo_diagnostics *diag;
    int errors;
    int module_tried, hook_tried; /* a 'module' or 'hook' annotation was there, malformed */
    int is_param_line[IS_PARAM_COUNT], is_param_col[IS_PARAM_COUNT]; /* where each 'is KEY=PARAM' was */
} parse_ctx;

#define ANNOT_ERROR(ctx, id, line, col, ...)                                                                    \
    do {                                                                                                        \
        halo_diagnostics_report((ctx)->diag, HALO_SEVERITY_ERROR, HALO_MSG_##id, (ctx)->m->file, (line), (col), \
                                (ctx)->m->lines[(line)-1], __VA_ARGS__);                                        \
        (ctx)->errors++;                                                                                        \
    } while (0)

static void parse_param(parse_ctx *ctx, words *w, int line)
{
    halo_module *m = ctx->m;
    if (w->n < 3) {
        ANNOT_ERROR(ctx, ANNOTATION_SYNTAX, line, w->col[0],
                    "param needs: NAME TYPE default=VALUE [min=N] [max=N] [step=N] \"meaning\"");
        return;
    }
    const char *name = w->w[1], *type = w->w[2];
    if (!valid_name(name)) {
        ANNOT_ERROR(ctx, ANNOTATION_SYNTAX, line, w->col[1], "parameter name '%s' must match [a-z][a-z0-9_]*", name);
        return;
    }
    if (halo_is_glsl_reserved(name)) {
        ANNOT_ERROR(ctx, ANNOTATION_SYNTAX, line, w->col[1],
                    "parameter name '%s' is a GLSL keyword, type name or reserved word: the module's code could "
                    "not use it; choose another name",
                    name);
        return;
    }
    for (size_t i = 0; i < m->param_count; i++)
        if (!strcmp(m->params[i].name, name)) {
            ANNOT_ERROR(ctx, PARAM_DUPLICATE, line, w->col[1], "parameter '%s' is already declared at line %d", name,
                        m->param_lines[i]);
            return;
        }
    halo_param_info info = {0};
    info.min = -HUGE_VAL;
    info.max = HUGE_VAL;
    char base[16] = {0};
    const char *bracket = strchr(type, '[');
    size_t blen = bracket ? (size_t)(bracket - type) : strlen(type);
    if (blen >= sizeof base)
        blen = sizeof base - 1;
    memcpy(base, type, blen);
    static const char *const types[] = {"float", "vec2", "vec3", "vec4", "int", "bool", "channels"};
    int t = -1;
    for (int i = 0; i < 7; i++)
        if (!strcmp(base, types[i]))
            t = i;
    if (t < 0) {
        ANNOT_ERROR(ctx, PARAM_TYPE_UNKNOWN, line, w->col[2],
                    "unknown parameter type '%s' (float, int, bool, vec2, vec3, vec4, or TYPE[N])", type);
        return;
    }
    info.type = (halo_param_type)t;
    info.components = param_components(info.type);
    if (info.type == HALO_PARAM_BOOL) {
        info.min = 0;
        info.max = 1;
    }
    if (info.type == HALO_PARAM_CHANNELS) {
        if (bracket) {
            ANNOT_ERROR(ctx, PARAM_TYPE_UNKNOWN, line, w->col[2],
                        "'channels' holds one value per halo already; "
                        "it takes no [N]");
            return;
        }
        info.array_size = 4;
    }
    if (bracket) {
        char *end;
        long n = strtol(bracket + 1, &end, 10);
        if (*end != ']' || end[1] || n < 1 || n > 16 || n * info.components > HALO_MAX_COMPONENTS) {
            ANNOT_ERROR(ctx, PARAM_TYPE_UNKNOWN, line, w->col[2],
                        "array type '%s' needs a size from 1 to 16 (at most %d numbers)", type, HALO_MAX_COMPONENTS);
            return;
        }
        info.array_size = (int)n;
    }
    const char *default_text = NULL;
    int default_col = w->col[0];
    for (int i = 3; i < w->n; i++) {
        const char *a = w->w[i];
        if (a[0] == '"') {
            free((char *)info.meaning);
            info.meaning = unquote(a);
        } else if (!strncmp(a, "default=", 8)) {
            default_text = a + 8;
            default_col = w->col[i];
        } else if (!strncmp(a, "step=", 5)) {
            char *end;
            double v = strtod(a + 5, &end);
            if (*end || end == a + 5 || !isfinite(v) || v <= 0.0 ||
                ((info.type == HALO_PARAM_INT || info.type == HALO_PARAM_BOOL) && v != floor(v))) {
                ANNOT_ERROR(ctx, ANNOTATION_SYNTAX, line, w->col[i] + 5,
                            "'%s' needs a finite number above 0 (a whole one for an int or bool)", a);
                free((char *)info.meaning);
                return;
            }
            info.step = v;
        } else if (!strncmp(a, "min=", 4) || !strncmp(a, "max=", 4)) {
            char *end;
            double v = strtod(a + 4, &end);
            if (*end || end == a + 4 || !isfinite(v)) {
                ANNOT_ERROR(ctx, ANNOTATION_SYNTAX, line, w->col[i], "'%s' needs a finite number", a);
                free((char *)info.meaning);
                return;
            }
            char why[160];
            if (!fits_type(info.type, v, why, sizeof why)) {
                ANNOT_ERROR(ctx, PARAM_DEFAULT_INVALID, line, w->col[i] + 4, "%.3s of '%s' (%s): %s", a, name,
                            halo_param_type_name(info.type), why);
                free((char *)info.meaning);
                return;
            }
            if (a[1] == 'i')
                info.min = v;
            else
                info.max = v;
        } else {
            ANNOT_ERROR(ctx, ANNOTATION_SYNTAX, line, w->col[i],
                        "unexpected '%s' in param (default=, min=, max=, step= or a \"meaning\")", a);
            free((char *)info.meaning);
            return;
        }
    }
    if (!default_text) {
        ANNOT_ERROR(ctx, ANNOTATION_MISSING, line, w->col[0], "parameter '%s' has no default=", name);
        free((char *)info.meaning);
        return;
    }
    info.name = halo_strdup(name);
    json_error_t jerr;
    json_t *v = json_loads(default_text, JSON_DECODE_ANY, &jerr);
    char why[256];
    if (!v || halo_param_from_json(&info, v, info.default_value, &info.default_count, why, sizeof why) >= 0) {
        if (!v)
            snprintf(why, sizeof why, "default '%s' is not JSON: %s", default_text, jerr.text);
        ANNOT_ERROR(ctx, PARAM_DEFAULT_INVALID, line, default_col, "%s", why);
        json_decref(v);
        free((char *)info.name);
        free((char *)info.meaning);
        return;
    }
    json_decref(v);
    if (info.min > info.max) {
        ANNOT_ERROR(ctx, ANNOTATION_SYNTAX, line, w->col[0], "min %g is above max %g", info.min, info.max);
    } else if (halo_param_check(&info, info.default_value, info.default_count, why, sizeof why) >= 0) {
        ANNOT_ERROR(ctx, PARAM_DEFAULT_INVALID, line, default_col + 8, "default of '%s' (%s): %s", name,
                    halo_param_type_name(info.type), why);
    } else {
        halo_param_info *p = realloc(m->params, (m->param_count + 1) * sizeof *p);
        int *pl = p ? realloc(m->param_lines, (m->param_count + 1) * sizeof *pl) : NULL;
        if (p)
            m->params = p;
        if (pl)
            m->param_lines = pl;
        if (p && pl) {
            if (!info.meaning)
                info.meaning = halo_strdup("");
            m->params[m->param_count] = info;
            m->param_lines[m->param_count++] = line;
            return;
        }
        ANNOT_ERROR(ctx, OUT_OF_MEMORY, line, 1, "out of memory");
    }
    free((char *)info.name);
    free((char *)info.meaning);
}

/* reach=K or reach=[M*]B^(PARAM-i)[+K], B 2 or 4 (docs/image-passes.md): fills pd->reach,
 * reach_param, reach_factor and reach_base; -1 on a syntax error. */
static int parse_reach(const char *v, halo_pass_decl *pd)
{
    const char *p = v;
    char *name = NULL, *end = NULL;
    long factor = 1;
    if (isdigit((unsigned char)*p) && (factor = strtol(p, &end, 10), *end == '*')) {
        if (factor < 1 || factor > 4096)
            return -1;
        p = end + 1;
    } else {
        factor = 1;
    }
    int base = (p[0] == '2' || p[0] == '4') && p[1] == '^' && p[2] == '(' ? p[0] - '0' : 0;
    if (!base && p != v)
        return -1; /* M* without a power */
    if (base) {
        const char *start = p + 3, *minus = strstr(start, "-i)");
        if (!minus || minus == start)
            return -1;
        name = strndup(start, (size_t)(minus - start));
        if (!name || !valid_name(name)) {
            free(name);
            return -1;
        }
        p = minus + 3;
    }
    long k = 0; /* K: the whole value, or after the power's '+' */
    end = NULL;
    if (base && *p && *p++ != '+')
        k = -1;
    else if (!base || p[-1] == '+')
        k = isdigit((unsigned char)*p) ? strtol(p, &end, 10) : -1;
    if (k < 0 || k > 4096 || (end && *end)) {
        free(name);
        return -1;
    }
    free(pd->reach_param);
    pd->reach_param = name;
    pd->reach = (int)k;
    pd->reach_factor = (int)factor;
    pd->reach_base = base ? base : 2;
    return 0;
}

static void parse_pass(parse_ctx *ctx, words *w, int line)
{
    halo_module *m = ctx->m;
    if (w->n < 3 || !valid_name(w->w[1])) {
        ANNOT_ERROR(ctx, ANNOTATION_SYNTAX, line, w->col[0],
                    "'pass' takes NAME entry=FUNC inputs=A,B output=IMAGE [repeat=PARAM first=IMAGE start=K] "
                    "[when=[!]PARAM,...] [reach=K | reach=[M*]B^(PARAM-i)[+K]]");
        return;
    }
    halo_pass_decl pd = {0};
    pd.reach = -1;
    pd.name = halo_strdup(w->w[1]);
    pd.line = line;
    for (int i = 2; i < w->n; i++) {
        const char *a = w->w[i], *eq = strchr(a, '=');
        if (!eq || !eq[1]) {
            ANNOT_ERROR(ctx, ANNOTATION_SYNTAX, line, w->col[i], "'%s': expected KEY=VALUE", a);
            continue;
        }
        size_t k = (size_t)(eq - a);
        const char *v = eq + 1;
        char **slot = NULL;
        if (k == 5 && !strncmp(a, "entry", 5))
            slot = &pd.entry;
        else if (k == 6 && !strncmp(a, "output", 6))
            slot = &pd.output;
        else if (k == 5 && !strncmp(a, "first", 5))
            slot = &pd.first;
        else if (k == 6 && !strncmp(a, "repeat", 6))
            slot = &pd.repeat;
        else if (k == 4 && !strncmp(a, "when", 4)) {
            char name[64];
            int negate, r;
            for (const char *c = v; (r = halo_when_next(&c, name, sizeof name, &negate)) > 0;) {}
            if (r < 0) {
                ANNOT_ERROR(ctx, ANNOTATION_SYNTAX, line, w->col[i],
                            "when= takes [!]PARAM,[!]PARAM...: bool parameters (or halo_full_size), all must hold");
                continue;
            }
            slot = &pd.when;
        } else if (k == 2 && !strncmp(a, "at", 2)) {
            if (!strcmp(v, "post"))
                pd.at = HALO_PASS_AT_POST;
            else if (!strcmp(v, "final"))
                pd.at = HALO_PASS_AT_FINAL;
            else if (strcmp(v, "generate"))
                ANNOT_ERROR(ctx, ANNOTATION_SYNTAX, line, w->col[i], "at= takes generate, post or final");
            continue;
        } else if (k == 5 && !strncmp(a, "start", 5)) {
            char *end = NULL;
            long start = strtol(v, &end, 10);
            if (end == v || *end || start < 1 || start > 64)
                ANNOT_ERROR(ctx, ANNOTATION_SYNTAX, line, w->col[i], "start= takes a repetition 1..64");
            else
                pd.start = (int)start;
            continue;
        } else if (k == 5 && !strncmp(a, "reach", 5)) {
            if (parse_reach(v, &pd) < 0)
                ANNOT_ERROR(
                    ctx, ANNOTATION_SYNTAX, line, w->col[i],
                    "reach= takes pixels K (0..4096) or [M*]B^(PARAM-i)[+K] (M 1..4096, B 2 or 4): how far from "
                    "the nonzero pixels "
                    "of its inputs repetition i can write a nonzero pixel");
            continue;
        } else if (k == 7 && !strncmp(a, "running", 7)) {
            if (!strcmp(v, "associative"))
                pd.running = 1;
            else
                ANNOT_ERROR(ctx, ANNOTATION_SYNTAX, line, w->col[i],
                            "running= takes associative: the pass combines input 0 with its own output of the "
                            "generation before (input 1) by an associative operation whose identity is 0");
            continue;
        } else if (k == 4 && !strncmp(a, "each", 4)) {
            if (!strcmp(v, "channel"))
                pd.each_channel = 1;
            else
                ANNOT_ERROR(ctx, ANNOTATION_SYNTAX, line, w->col[i], "each= takes channel");
            continue;
        } else if (k == 6 && !strncmp(a, "inputs", 6)) {
            char buf[256];
            snprintf(buf, sizeof buf, "%s", v);
            char *cursor = NULL; /* strtok_r: another thread may be parsing */
            for (char *tok = strtok_r(buf, ",", &cursor); tok; tok = strtok_r(NULL, ",", &cursor)) {
                if (pd.input_count == HALO_MAX_PASS_INPUTS) {
                    ANNOT_ERROR(ctx, PASS_INVALID, line, w->col[i], "a pass reads at most %d images",
                                HALO_MAX_PASS_INPUTS);
                    break;
                }
                pd.inputs[pd.input_count++] = halo_strdup(tok);
            }
            continue;
        } else {
            ANNOT_ERROR(ctx, ANNOTATION_SYNTAX, line, w->col[i],
                        "unknown pass key '%.*s' (entry, inputs, output, "
                        "repeat, first, start, when, at, each, reach, running)",
                        (int)k, a);
            continue;
        }
        free(*slot);
        *slot = halo_strdup(v);
    }
    if (!pd.entry || !pd.output || !pd.input_count)
        ANNOT_ERROR(ctx, PASS_INVALID, line, w->col[0], "pass '%s' needs entry=, inputs= and output=", pd.name);
    halo_pass_decl *p = realloc(m->passes, (m->pass_count + 1) * sizeof *p);
    if (!p)
        return;
    m->passes = p;
    p[m->pass_count++] = pd;
}

/* The annotation without its comments (the preprocessor drops them too): a copy with
 * each comment outside quotes blanked, so that columns stay. Caller frees. */
static char *without_comments(const char *rest)
{
    char *s = halo_strdup(rest);
    for (char *p = s, *quote = NULL; p && *p; p++) {
        if (*p == '"')
            quote = quote ? NULL : p;
        if (quote)
            continue;
        if (p[0] == '/' && p[1] == '/') {
            memset(p, ' ', strlen(p));
            break;
        }
        if (p[0] == '/' && p[1] == '*') {
            char *end = strstr(p + 2, "*/");
            size_t n = end ? (size_t)(end + 2 - p) : strlen(p);
            memset(p, ' ', n);
            p += n - 1;
        }
    }
    return s;
}

static void parse_annotation(parse_ctx *ctx, const char *rest, int col0, int line, char *storage)
{
    halo_module *m = ctx->m;
    words w;
    char *text = without_comments(rest);
    int at = col0, split = text ? split_words(text, col0, &w, storage, &at) : SPLIT_QUOTE;
    free(text);
    if (split == SPLIT_QUOTE) {
        ANNOT_ERROR(ctx, ANNOTATION_SYNTAX, line, at, "the quote opened here is not closed on this line");
        return;
    }
    if (split == SPLIT_MANY) {
        ANNOT_ERROR(ctx, ANNOTATION_SYNTAX, line, at,
                    "an annotation takes at most %d words; split it over several lines of the same directive "
                    "(needs, after and per_halo add to the list)",
                    MAX_WORDS);
        return;
    }
    if (w.n == 0) {
        ANNOT_ERROR(ctx, ANNOTATION_SYNTAX, line, col0, "'#pragma halo' without a directive");
        return;
    }
    const char *d = w.w[0];
    if (!strcmp(d, "module") || !strcmp(d, "library"))
        ctx->module_tried = 1;
    if (!strcmp(d, "hook"))
        ctx->hook_tried = 1;
    if (!strcmp(d, "module") || !strcmp(d, "library")) {
        int lib = d[0] == 'l';
        if (m->module_line) {
            ANNOT_ERROR(ctx, ANNOTATION_DUPLICATE, line, w.col[0], "'%s' given twice (first at line %d)", d,
                        m->module_line);
            return;
        }
        if (lib ? w.n != 1 : (w.n != 2 || !valid_name(w.w[1]))) {
            ANNOT_ERROR(ctx, ANNOTATION_SYNTAX, line, w.col[0],
                        lib ? "'library' takes no argument" : "'module' takes one name matching [a-z][a-z0-9_]*");
            return;
        }
        m->module_line = line;
        m->is_library = lib;
        if (!lib)
            m->name = halo_strdup(w.w[1]);
    } else if (!strcmp(d, "summary")) {
        if (w.n != 2 || w.w[1][0] != '"') {
            ANNOT_ERROR(ctx, ANNOTATION_SYNTAX, line, w.col[0], "'summary' takes one \"quoted\" line");
            return;
        }
        free(m->summary);
        m->summary = unquote(w.w[1]);
    } else if (!strcmp(d, "hook")) {
        if (w.n != 2) {
            ANNOT_ERROR(ctx, ANNOTATION_SYNTAX, line, w.col[0], "'hook' takes one hook name");
            return;
        }
        int h = -1;
        for (int i = 0; i < HALO_HOOK_COUNT; i++)
            if (!strcmp(w.w[1], hook_names[i]))
                h = i;
        if (h < 0) {
            ANNOT_ERROR(ctx, MODULE_HOOK_UNKNOWN, line, w.col[1],
                        "unknown hook '%s' (sample, image, line_vertex, line_fragment)", w.w[1]);
            return;
        }
        if (m->hook_line) {
            ANNOT_ERROR(ctx, ANNOTATION_DUPLICATE, line, w.col[0], "'hook' given twice (first at line %d)",
                        m->hook_line);
            return;
        }
        m->hook = (halo_hook)h;
        m->hook_line = line;
    } else if (!strcmp(d, "needs") || !strcmp(d, "after")) {
        halo_name_list *l = d[0] == 'n' ? &m->needs : &m->after;
        if (w.n < 2)
            ANNOT_ERROR(ctx, ANNOTATION_SYNTAX, line, w.col[0], "'%s' takes one or more names", d);
        for (int i = 1; i < w.n; i++) {
            if (!valid_name(w.w[i])) {
                ANNOT_ERROR(ctx, ANNOTATION_SYNTAX, line, w.col[i], "'%s' is not a valid name", w.w[i]);
                continue;
            }
            if (halo_name_list_add(l, w.w[i], strlen(w.w[i]), line))
                ANNOT_ERROR(ctx, OUT_OF_MEMORY, line, 1, "out of memory");
        }
    } else if (!strcmp(d, "provides")) {
        static const char *const ok_types[] = {"float", "vec2", "vec3",     "vec4",  "int",
                                               "bool",  "mat4", "channels", "image", NULL};
        int ok = w.n == 3 && valid_name(w.w[1]);
        int tok = 0;
        for (int i = 0; ok && ok_types[i]; i++)
            tok |= !strcmp(w.w[2], ok_types[i]);
        if (!ok || !tok) {
            ANNOT_ERROR(ctx, ANNOTATION_SYNTAX, line, w.col[0],
                        "'provides' takes a name and a type (float, vec3, ...)");
            return;
        }
        if (halo_is_glsl_reserved(w.w[1])) {
            ANNOT_ERROR(ctx, ANNOTATION_SYNTAX, line, w.col[1],
                        "'%s' is a GLSL keyword, type name or reserved word: "
                        "no name for a field of halo_sample",
                        w.w[1]);
            return;
        }
        if (halo_is_host_resource(w.w[1])) {
            ANNOT_ERROR(ctx, MODULE_RESERVED_NAME, line, w.col[1],
                        "'%s' is filled by the host; stages modify it, "
                        "they do not provide it",
                        w.w[1]);
            return;
        }
        halo_resource_decl *p = realloc(m->provides, (m->provides_count + 1) * sizeof *p);
        if (!p) {
            ANNOT_ERROR(ctx, OUT_OF_MEMORY, line, 1, "out of memory");
            return;
        }
        m->provides = p;
        p[m->provides_count++] = (halo_resource_decl){
            halo_strdup(w.w[1]), halo_strdup(!strcmp(w.w[2], "channels") ? "halo_channels" : w.w[2]), line};
    } else if (!strcmp(d, "param")) {
        parse_param(ctx, &w, line);
    } else if (!strcmp(d, "output")) {
        halo_blend blend = HALO_BLEND_NONE;
        if (w.n == 3)
            blend = !strcmp(w.w[2], "max")     ? HALO_BLEND_MAX
                    : !strcmp(w.w[2], "add")   ? HALO_BLEND_ADD
                    : !strcmp(w.w[2], "min")   ? HALO_BLEND_MIN
                    : !strcmp(w.w[2], "first") ? HALO_BLEND_FIRST
                                               : HALO_BLEND_NONE;
        if (w.n != 3 || !valid_name(w.w[1]) || blend == HALO_BLEND_NONE) {
            ANNOT_ERROR(ctx, ANNOTATION_SYNTAX, line, w.col[0],
                        "'output' takes a provided field and max, add, min or first");
            return;
        }
        halo_output_decl *o = realloc(m->outputs, (m->output_count + 1) * sizeof *o);
        if (!o)
            return;
        m->outputs = o;
        o[m->output_count++] = (halo_output_decl){halo_strdup(w.w[1]), blend, line};
    } else if (!strcmp(d, "image")) {
        halo_image_reset reset = HALO_RESET_FRAME;
        char *name = halo_strdup(w.n >= 2 ? w.w[1] : ""); /* whole: no length limit */
        if (!name)
            return;
        int family = 0, components = 0, clear_set = 0;
        double clear = 0.0;
        const char *read_when = NULL;
        size_t len = strlen(name);
        if (len > 1 && name[len - 1] == '*') {
            family = 1;
            name[len - 1] = 0;
        }
        int ok = w.n >= 2 && w.n <= 6 && valid_name(name);
        for (int i = 2; ok && i < w.n; i++) {
            char *end = NULL;
            if (!strcmp(w.w[i], "reset=generation"))
                reset = HALO_RESET_GENERATION;
            else if (!strcmp(w.w[i], "reset=frame"))
                reset = HALO_RESET_FRAME;
            else if (!strcmp(w.w[i], "reset=frame-only"))
                reset = HALO_RESET_FRAME_ONLY;
            else if (!strncmp(w.w[i], "clear=", 6)) {
                clear = strtod(w.w[i] + 6, &end);
                ok = end != w.w[i] + 6 && !*end && isfinite(clear);
                clear_set = 1;
            } else if (!strncmp(w.w[i], "components=", 11)) {
                components = (int)strtol(w.w[i] + 11, &end, 10);
                ok = end != w.w[i] + 11 && !*end && components >= 1 && components <= 4;
            } else if (!strncmp(w.w[i], "read_when=", 10)) {
                read_when = w.w[i] + 10;
                ok = valid_name(read_when);
            } else
                ok = 0;
        }
        if (!ok) {
            ANNOT_ERROR(ctx, ANNOTATION_SYNTAX, line, w.col[0],
                        "'image' takes a name (NAME* for one per channel) and "
                        "optionally reset=frame, reset=generation or reset=frame-only, clear=VALUE, components=1..4, "
                        "read_when=PARAM");
            free(name);
            return;
        }
        halo_image_decl *im = realloc(m->images, (m->image_count + 1) * sizeof *im);
        if (!im) {
            free(name);
            return;
        }
        m->images = im;
        im[m->image_count++] = (halo_image_decl){
            name, reset, line, family, components, clear, clear_set, read_when ? halo_strdup(read_when) : NULL};
    } else if (!strcmp(d, "host_uniform")) {
        static const char *const ok_types[] = {"float", "vec2",      "vec3",      "vec4", "int",
                                               "mat4",  "sampler2D", "sampler3D", NULL};
        int ok = w.n >= 3 && w.n <= 4 && valid_name(w.w[1]), tok = 0;
        for (int i = 0; ok && ok_types[i]; i++)
            tok |= !strcmp(w.w[2], ok_types[i]);
        if (!ok || !tok || (w.n == 4 && w.w[3][0] != '"')) {
            ANNOT_ERROR(ctx, ANNOTATION_SYNTAX, line, w.col[0],
                        "'host_uniform' takes a name, a type "
                        "(float, vec2, vec3, vec4, int, mat4, sampler2D, sampler3D) and a \"meaning\"");
            return;
        }
        halo_host_uniform_decl *h = realloc(m->host_uniforms, (m->host_uniform_count + 1) * sizeof *h);
        if (!h)
            return;
        m->host_uniforms = h;
        h[m->host_uniform_count++] = (halo_host_uniform_decl){halo_strdup(w.w[1]), halo_strdup(w.w[2]),
                                                              w.n == 4 ? unquote(w.w[3]) : halo_strdup(""), line};
    } else if (!strcmp(d, "pass")) {
        parse_pass(ctx, &w, line);
    } else if (!strcmp(d, "groups")) {
        /* features in groups of four: its channels parameters take up to 16 values */
        if (w.n != 1)
            ANNOT_ERROR(ctx, ANNOTATION_SYNTAX, line, w.col[0], "'groups' takes no arguments");
        m->groups = 1;
    } else if (!strcmp(d, "per_halo")) {
        if (w.n < 2)
            ANNOT_ERROR(ctx, ANNOTATION_SYNTAX, line, w.col[0], "'per_halo' takes parameter names");
        for (int i = 1; i < w.n; i++)
            halo_name_list_add(&m->per_halo, w.w[i], strlen(w.w[i]), line);
    } else if (!strcmp(d, "is")) {
        /* what the stage is, for hosts (halo_stage_info) */
        if (w.n < 2)
            ANNOT_ERROR(ctx, ANNOTATION_SYNTAX, line, w.col[0], "'is' takes one or more properties");
        for (int i = 1; i < w.n; i++) {
            if (!strcmp(w.w[i], "keeps_empty"))
                m->info.keeps_empty = 1;
            else if (!strcmp(w.w[i], "zero_generation"))
                m->info.zero_generation = 1;
            else {
                int k = 0;
                size_t n = strcspn(w.w[i], "=");
                while (k < IS_PARAM_COUNT && !(strlen(is_params[k].key) == n && !strncmp(w.w[i], is_params[k].key, n)))
                    k++;
                const char **field = k < IS_PARAM_COUNT ? is_param_field(&m->info, k) : NULL;
                if (field && w.w[i][n] == '=' && valid_name(w.w[i] + n + 1) && !*field) {
                    *field = halo_strdup(w.w[i] + n + 1);
                    ctx->is_param_line[k] = line;
                    ctx->is_param_col[k] = w.col[i];
                } else
                    ANNOT_ERROR(ctx, ANNOTATION_SYNTAX, line, w.col[i],
                                "'%s' is not a property 'is' takes (keeps_empty, zero_generation, labels_when=PARAM, "
                                "interval=PARAM, strip_width=PARAM, core_fraction=PARAM, once each)",
                                w.w[i]);
            }
        }
    } else if (!strcmp(d, "declarations")) {
        ANNOT_ERROR(ctx, ANNOTATION_UNKNOWN, line, w.col[0],
                    "'#pragma halo declarations' belongs in a host shader, not in a module");
    } else {
        ANNOT_ERROR(ctx, ANNOTATION_UNKNOWN, line, w.col[0],
                    "unknown directive '%s' (module, library, summary, hook, needs, provides, after, param, "
                    "output, image, host_uniform, pass, per_halo, groups, is)",
                    d);
    }
}

/* Returns the column (1-based) of the directive after "#pragma halo", or 0 if the line
 * is not a libhalo annotation. */
int halo_annotation_start(const char *line);
int halo_annotation_start(const char *line)
{
    const char *p = line;
    while (*p == ' ' || *p == '\t')
        p++;
    if (*p != '#')
        return 0;
    p++;
    while (*p == ' ' || *p == '\t')
        p++;
    if (strncmp(p, "pragma", 6) || (p[6] != ' ' && p[6] != '\t'))
        return 0;
    p += 6;
    while (*p == ' ' || *p == '\t')
        p++;
    if (strncmp(p, "halo", 4) || (p[4] && p[4] != ' ' && p[4] != '\t' && p[4] != '\r'))
        return 0;
    p += 4;
    while (*p == ' ' || *p == '\t')
        p++;
    return (int)(p - line) + 1;
}

/* Finds the names the code declares at global scope, and the halo_* names it uses. */
static void scan_code(parse_ctx *ctx)
{
    halo_module *m = ctx->m;
    const char *src = m->source;
    halo_token *t = m->tokens.items;
    size_t n = m->tokens.count;
    for (size_t i = 0; i < n; i++) {
        if (t[i].kind != HALO_TOK_IDENT)
            continue;
        const char *s = src + t[i].offset;
        size_t len = t[i].length;
        if (len > 5 && !strncmp(s, "halo_", 5) && !(i > 0 && halo_token_is(src, &t[i - 1], ".")) &&
            !halo_token_is(src, &t[i], "halo_sample") && !halo_name_list_has_n(&m->calls, s, len))
            halo_name_list_add(&m->calls, s, len, t[i].line);
        if (t[i].depth != 0 || halo_is_glsl_keyword(s, len))
            continue;
        int declared = 0;
        if (i > 0 && (t[i - 1].kind == HALO_TOK_IDENT || halo_token_is(src, &t[i - 1], "]")) && i + 1 < n) {
            const halo_token *nx = &t[i + 1];
            declared = halo_token_is(src, nx, "(") || halo_token_is(src, nx, "=") || halo_token_is(src, nx, ";") ||
                       halo_token_is(src, nx, "[") || halo_token_is(src, nx, ",");
            if (i > 1 && halo_token_is(src, &t[i - 2], "#"))
                declared = halo_token_is(src, &t[i - 1], "define");
        }
        if (!declared)
            continue;
        /* names of any length, compared and kept whole (a truncated one would not be renamed) */
        if (halo_name_list_has_n(&m->declared, s, len))
            continue;
        if (!m->is_library && !strncmp(s, "halo_", 5)) {
            halo_diagnostics_report(ctx->diag, HALO_SEVERITY_ERROR, HALO_MSG_MODULE_RESERVED_NAME, m->file, t[i].line,
                                    t[i].column, m->lines[t[i].line - 1],
                                    "module declares '%.*s': names starting with 'halo_' are reserved for the library",
                                    (int)len, s);
            ctx->errors++;
            continue;
        }
        if (halo_token_is(src, &t[i], "apply") && halo_token_is(src, &t[i + 1], "("))
            m->has_entry = 1;
        halo_name_list_add(&m->declared, s, len, t[i].line);
        if (m->is_library && halo_token_is(src, &t[i + 1], "(")) {
            /* A helper function: its chunk runs from after the previous chunk to its closing brace. */
            size_t j = i + 1;
            while (j < n && !(halo_token_is(src, &t[j], "{") && t[j].brace_depth == 0) &&
                   !(halo_token_is(src, &t[j], ";") && t[j].depth == 0))
                j++;
            if (j < n && halo_token_is(src, &t[j], ";"))
                continue; /* a prototype */
            while (j < n && !(halo_token_is(src, &t[j], "}") && t[j].brace_depth == 0))
                j++;
            if (j >= n)
                break;
            halo_chunk *c = realloc(m->chunks, (m->chunk_count + 1) * sizeof *c);
            if (!c)
                break;
            m->chunks = c;
            halo_chunk *ch = &c[m->chunk_count++];
            memset(ch, 0, sizeof *ch);
            ch->name = halo_strndup(s, len);
            ch->first_line = m->chunk_count > 1 ? c[m->chunk_count - 2].last_line + 1 : 1;
            ch->last_line = t[j].line;
            for (size_t q = i + 1; q < j; q++) {
                const char *qs = src + t[q].offset;
                size_t ck = t[q].length;
                if (t[q].kind == HALO_TOK_IDENT && ck > 5 && !strncmp(qs, "halo_", 5) &&
                    !(ck == len && !memcmp(qs, s, len)) && !halo_name_list_has_n(&ch->calls, qs, ck))
                    halo_name_list_add(&ch->calls, qs, ck, t[q].line);
            }
            i = j;
        }
    }
}

/* 1 (and an error at the pass's line) when key=name of a pass names no int (is_bool: bool)
 * scalar parameter of the module; 0 when it does or name is NULL. */
static int pass_param_invalid(const halo_module *m, halo_diagnostics *diag, const char *file, const halo_pass_decl *pd,
                              const char *key, const char *name, int is_bool)
{
    const halo_param_info *pi = name ? halo_module_find_param(m, name) : NULL;
    if (!name || (pi && pi->type == (is_bool ? HALO_PARAM_BOOL : HALO_PARAM_INT) && !pi->array_size))
        return 0;
    halo_diagnostics_report(diag, HALO_SEVERITY_ERROR, HALO_MSG_PASS_INVALID, file, pd->line, 1, m->lines[pd->line - 1],
                            "pass '%s': %s=%s must name an %s parameter of the module", pd->name, key, name,
                            is_bool ? "bool" : "int");
    return 1;
}

halo_module *halo_module_parse(const char *file, const char *source, halo_diagnostics *diag)
{
    halo_module *m = calloc(1, sizeof *m);
    if (!m)
        return NULL;
    parse_ctx ctx = {.m = m, .diag = diag};
    source = halo_skip_bom(source); /* a UTF-8 byte-order mark is no part of the module */
    m->file = halo_strdup(file);
    m->source = halo_strdup(source);
    m->line_storage = halo_strdup(source);
    if (!m->file || !m->source || !m->line_storage)
        goto oom;
    /* Split into lines (in place, in line_storage). */
    int cap = 64;
    m->lines = malloc((size_t)cap * sizeof *m->lines);
    if (!m->lines)
        goto oom;
    for (char *p = m->line_storage;;) {
        if (m->line_count == cap) {
            cap *= 2;
            char **l = realloc(m->lines, (size_t)cap * sizeof *l);
            if (!l)
                goto oom;
            m->lines = l;
        }
        m->lines[m->line_count++] = p;
        char *nl = strchr(p, '\n');
        if (!nl)
            break;
        *nl = '\0';
        if (nl > p && nl[-1] == '\r')
            nl[-1] = '\0';
        p = nl + 1;
    }
    m->is_annotation = calloc((size_t)m->line_count + 1, 1);
    if (!m->is_annotation)
        goto oom;
    size_t longest = 0;
    for (int i = 0; i < m->line_count; i++)
        if (strlen(m->lines[i]) > longest)
            longest = strlen(m->lines[i]);
    char *storage = malloc(longest * 2 + 64);
    if (!storage)
        goto oom;
    for (int i = 0; i < m->line_count; i++) {
        int col = halo_annotation_start(m->lines[i]);
        if (!col)
            continue;
        m->is_annotation[i] = 1;
        parse_annotation(&ctx, m->lines[i] + col - 1, col, i + 1, storage);
    }
    free(storage);
    if (!m->module_line && !ctx.module_tried) {
        halo_diagnostics_report(diag, HALO_SEVERITY_ERROR, HALO_MSG_ANNOTATION_MISSING, file, 1, 1, m->lines[0],
                                "no '#pragma halo module NAME' (or '#pragma halo library') annotation");
        ctx.errors++;
    } else if (m->module_line && !m->is_library && !m->hook_line && !ctx.hook_tried) {
        halo_diagnostics_report(diag, HALO_SEVERITY_ERROR, HALO_MSG_ANNOTATION_MISSING, file, m->module_line, 1,
                                m->lines[m->module_line - 1], "module '%s' has no '#pragma halo hook' annotation",
                                m->name);
        ctx.errors++;
    }
    m->info.name = m->name;
    m->info.hook = m->hook;
    for (int k = 0; k < IS_PARAM_COUNT; ++k) {
        const char *name = *is_param_field(&m->info, k);
        const halo_param_info *pi = name ? halo_module_find_param(m, name) : NULL;
        if (name && (!pi || (is_params[k].type >= 0 &&
                             (pi->type != (halo_param_type)is_params[k].type || pi->array_size != 0)))) {
            halo_diagnostics_report(diag, HALO_SEVERITY_ERROR, HALO_MSG_ANNOTATION_SYNTAX, file, ctx.is_param_line[k],
                                    ctx.is_param_col[k], m->lines[ctx.is_param_line[k] - 1],
                                    "'is %s=%s': the module has no %sparameter '%s'", is_params[k].key, name,
                                    is_params[k].type_name, name);
            ctx.errors++;
        }
    }
    /* Tokens of the code, annotation lines left out. */
    halo_token_list all;
    if (halo_lex(m->source, &all))
        goto oom;
    size_t k = 0;
    for (size_t i = 0; i < all.count; i++)
        if (!m->is_annotation[all.items[i].line - 1])
            all.items[k++] = all.items[i];
    all.count = k;
    m->tokens = all;
    if (ctx.errors == 0) {
        scan_code(&ctx);
        for (size_t i = 0; i < m->pass_count; i++) {
            const halo_pass_decl *pd = &m->passes[i];
            if (pd->entry && !halo_name_list_has(&m->declared, pd->entry)) {
                halo_diagnostics_report(diag, HALO_SEVERITY_ERROR, HALO_MSG_PASS_INVALID, file, pd->line, 1,
                                        m->lines[pd->line - 1], "pass '%s': the module defines no function '%s'",
                                        pd->name, pd->entry);
                ctx.errors++;
            }
            const char *need[2] = {pd->repeat, pd->reach_param};
            static const char *const key[2] = {"repeat", "reach"};
            for (int k = 0; k < 2; k++)
                ctx.errors += pass_param_invalid(m, diag, file, pd, key[k], need[k], 0);
            const halo_param_info *rp = pd->repeat ? halo_module_find_param(m, pd->repeat) : NULL;
            if (rp && rp->type == HALO_PARAM_INT && !rp->array_size && !(rp->max <= HALO_MAX_PASS_REPEAT)) {
                /* each repetition is a draw a generation: a scene may not ask for 2^31 of them */
                halo_diagnostics_report(
                    diag, HALO_SEVERITY_ERROR, HALO_MSG_PASS_INVALID, file, pd->line, 1, m->lines[pd->line - 1],
                    "pass '%s': repeat=%s: the parameter's max is %g; declare max=N with N at most %d "
                    "(HALO_MAX_PASS_REPEAT)",
                    pd->name, pd->repeat, rp->max, HALO_MAX_PASS_REPEAT);
                ctx.errors++;
            }
            /* running=associative: output = (its own output of the generation before) op (input 0),
             * computed by a runtime as a prefix over generations */
            if (pd->running && (pd->input_count != 2 || !pd->output || strcmp(pd->inputs[1], pd->output) ||
                                !strcmp(pd->inputs[0], pd->output) || !strcmp(pd->inputs[0], "previous") ||
                                pd->repeat || pd->first || pd->reach != 0 || pd->reach_param || pd->start > 1 ||
                                pd->each_channel || pd->at != HALO_PASS_AT_GENERATE)) {
                halo_diagnostics_report(diag, HALO_SEVERITY_ERROR, HALO_MSG_PASS_INVALID, file, pd->line, 1,
                                        m->lines[pd->line - 1],
                                        "pass '%s': running=associative needs inputs=IMAGE,OUTPUT (another image, "
                                        "then its own output of the generation before), reach=0, no repeat=, first=, "
                                        "start= or each=, and no at=post or final",
                                        pd->name);
                ctx.errors++;
            }
            /* when=!PARAM negates; when=halo_full_size: the halo images at the frame's size */
            char when[64];
            int negate;
            for (const char *c = pd->when ? pd->when : ""; halo_when_next(&c, when, sizeof when, &negate) > 0;)
                if (strcmp(when, HALO_WHEN_FULL_SIZE))
                    ctx.errors += pass_param_invalid(m, diag, file, pd, "when", when, 1);
        }
        for (size_t i = 0; i < m->image_count; i++) {
            const halo_image_decl *im = &m->images[i];
            const halo_param_info *pi = im->read_when ? halo_module_find_param(m, im->read_when) : NULL;
            if (im->read_when && (!pi ||
                                  (pi->type != HALO_PARAM_CHANNELS && pi->type != HALO_PARAM_INT &&
                                   pi->type != HALO_PARAM_BOOL && pi->type != HALO_PARAM_FLOAT) ||
                                  (pi->array_size && pi->type != HALO_PARAM_CHANNELS))) {
                halo_diagnostics_report(
                    diag, HALO_SEVERITY_ERROR, HALO_MSG_ANNOTATION_SYNTAX, file, im->line, 1, m->lines[im->line - 1],
                    "image '%s': read_when=%s must name a channels, float, int or bool parameter of the module",
                    im->name, im->read_when);
                ctx.errors++;
            }
        }
        for (size_t i = 0; m->groups && i < m->param_count; i++)
            if (m->params[i].type == HALO_PARAM_CHANNELS)
                m->params[i].array_size = HALO_MAX_GROUP_CHANNELS;
        for (size_t i = 0; i < m->per_halo.count; i++) {
            const halo_param_info *pi = halo_module_find_param(m, m->per_halo.items[i]);
            if (!pi || !pi->array_size || pi->type == HALO_PARAM_CHANNELS) {
                halo_diagnostics_report(diag, HALO_SEVERITY_ERROR, HALO_MSG_ANNOTATION_SYNTAX, file,
                                        m->per_halo.lines[i], 1, m->lines[m->per_halo.lines[i] - 1],
                                        "per_halo '%s' must name an array parameter (TYPE[N]) of the module",
                                        m->per_halo.items[i]);
                ctx.errors++;
            }
        }
        if (!m->is_library && m->hook == HALO_HOOK_SAMPLE && !m->has_entry) {
            halo_diagnostics_report(diag, HALO_SEVERITY_ERROR, HALO_MSG_MODULE_ENTRY_MISSING, file, m->module_line, 1,
                                    m->lines[m->module_line - 1],
                                    "sample module '%s' must define 'void apply(inout halo_sample s)'", m->name);
            ctx.errors++;
        }
    }
    if (!m->summary)
        m->summary = halo_strdup("");
    if (ctx.errors) {
        halo_module_free(m);
        return NULL;
    }
    return m;
oom:
    halo_diagnostics_report(diag, HALO_SEVERITY_ERROR, HALO_MSG_OUT_OF_MEMORY, file, 0, 0, NULL, "out of memory");
    halo_module_free(m);
    return NULL;
}

void halo_module_free(halo_module *m)
{
    if (!m)
        return;
    free(m->name);
    for (int k = 0; k < IS_PARAM_COUNT; ++k)
        free((char *)*is_param_field(&m->info, k));
    free(m->file);
    free(m->summary);
    halo_name_list_free(&m->needs);
    halo_name_list_free(&m->after);
    for (size_t i = 0; i < m->provides_count; i++) {
        free(m->provides[i].name);
        free(m->provides[i].type);
    }
    free(m->provides);
    for (size_t i = 0; i < m->param_count; i++) {
        free((char *)m->params[i].name);
        free((char *)m->params[i].meaning);
    }
    free(m->params);
    free(m->param_lines);
    free(m->source);
    free(m->lines);
    free(m->line_storage);
    free(m->is_annotation);
    halo_token_list_free(&m->tokens);
    halo_name_list_free(&m->declared);
    halo_name_list_free(&m->calls);
    halo_name_list_free(&m->per_halo);
    for (size_t i = 0; i < m->output_count; i++)
        free(m->outputs[i].name);
    free(m->outputs);
    for (size_t i = 0; i < m->image_count; i++) {
        free(m->images[i].name);
        free(m->images[i].read_when);
    }
    free(m->images);
    for (size_t i = 0; i < m->host_uniform_count; i++) {
        free(m->host_uniforms[i].name);
        free(m->host_uniforms[i].type);
        free(m->host_uniforms[i].meaning);
    }
    free(m->host_uniforms);
    for (size_t i = 0; i < m->pass_count; i++) {
        halo_pass_decl *pd = &m->passes[i];
        free(pd->name);
        free(pd->entry);
        free(pd->output);
        free(pd->first);
        free(pd->repeat);
        free(pd->when);
        free(pd->reach_param);
        for (int k = 0; k < pd->input_count; k++)
            free(pd->inputs[k]);
    }
    free(m->passes);
    for (size_t i = 0; i < m->chunk_count; i++) {
        free(m->chunks[i].name);
        halo_name_list_free(&m->chunks[i].calls);
    }
    free(m->chunks);
    free(m);
}

/* ---- Accessors ---- */
const char *halo_module_name_of(const halo_module *m) { return m->is_library ? "halo_math" : m->name; }
const halo_param_info *halo_module_find_param(const halo_module *m, const char *name)
{
    HALO_REFUSE_NULL(NULL, m, "module", NULL);
    HALO_REFUSE_NULL(NULL, name, "name", NULL);
    for (size_t i = 0; i < m->param_count; i++)
        if (!strcmp(m->params[i].name, name))
            return &m->params[i];
    return NULL;
}
