/* Scene files (docs/scene.md): which stages are enabled, their parameters, and the
 * render settings of the example renderers. Every error names the file and JSON path. */
#include "diag.h"
#include "internal.h"
#include "strbuf.h"

#include <errno.h>
#include <jansson.h>
#include <math.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>

int halo_param_from_json(const halo_param_info *info, void *json, double *values, int *count, char *why,
                         size_t why_len);

#define SCENE_FORMAT_VERSION 1

static void default_render(halo_render_settings *r)
{
    memset(r, 0, sizeof *r);
    r->azimuth = 30;
    r->elevation = 20;
    r->zoom = 1;
    r->step = 0.5;
    r->window[0] = 0;
    r->window[1] = 1;
    static const double tf[][5] = {{0.0, 0.0, 0.0, 0.0, 0.0},
                                   {0.15, 0.9, 0.75, 0.6, 0.0},
                                   {0.35, 0.9, 0.75, 0.6, 0.08},
                                   {0.6, 0.95, 0.5, 0.4, 0.3},
                                   {1.0, 1.0, 1.0, 0.9, 0.8}};
    r->transfer_count = 5;
    memcpy(r->transfer, tf, sizeof tf);
}

halo_scene *halo_scene_create(const halo_library *lib)
{
    HALO_REFUSE_NULL(NULL, lib, "library", NULL);
    halo_scene *s = calloc(1, sizeof *s);
    if (!s)
        return NULL;
    s->library = lib;
    halo_library_retain(lib);
    default_render(&s->render);
    return s;
}

void halo_scene_destroy(halo_scene *s)
{
    if (!s)
        return;
    for (size_t i = 0; i < s->count; i++)
        free(s->stages[i].values);
    free(s->stages);
    free(s->names);
    halo_library_release(s->library);
    free(s);
}

static halo_scene_entry *find_entry(halo_scene *s, const char *stage)
{
    for (size_t i = 0; i < s->count; i++)
        if (!strcmp(halo_module_name_of(s->stages[i].module), stage))
            return &s->stages[i];
    return NULL;
}

/* Adds a stage with default values, or returns the existing entry. */
static halo_scene_entry *add_entry(halo_scene *s, const halo_module *m)
{
    halo_scene_entry *e = find_entry(s, halo_module_name_of(m));
    if (e)
        return e;
    const char **names = realloc(s->names, (s->count + 1) * sizeof *names);
    if (!names)
        return NULL;
    s->names = names;
    halo_scene_entry *p = realloc(s->stages, (s->count + 1) * sizeof *p);
    if (!p)
        return NULL;
    s->stages = p;
    names[s->count] = halo_module_name_of(m);
    e = &p[s->count];
    e->module = m;
    e->enabled = 1;
    e->values = calloc(m->param_count ? m->param_count : 1, sizeof *e->values);
    if (!e->values)
        return NULL;
    for (size_t i = 0; i < m->param_count; i++) {
        e->values[i].count = m->params[i].default_count;
        memcpy(e->values[i].value, m->params[i].default_value, sizeof e->values[i].value);
    }
    s->count++;
    return e;
}

static const halo_module *stage_module(const halo_scene *s, const char *stage, const char *file, const char *path,
                                       halo_diagnostics *diag)
{
    const halo_module *m = halo_library_find(s->library, stage);
    if (!m || m->is_library) {
        halo_diag_error(diag, SCENE_STAGE_UNKNOWN, file, 0, 0, "%s: unknown stage '%s'", path, stage);
        return NULL;
    }
    return m;
}

halo_status halo_scene_enable(halo_scene *s, const char *stage, int enabled, halo_diagnostics *diag)
{
    HALO_REFUSE_NULL(diag, s, "scene", HALO_ERROR_INPUT);
    HALO_REFUSE_NULL(diag, stage, "stage", HALO_ERROR_INPUT);
    const halo_module *m = stage_module(s, stage, "", "stages", diag);
    if (!m)
        return HALO_ERROR_INPUT;
    halo_scene_entry *e = add_entry(s, m);
    if (!e) {
        halo_diag_error(diag, OUT_OF_MEMORY, "", 0, 0, "out of memory");
        return HALO_ERROR_IO;
    }
    e->enabled = enabled;
    return HALO_OK;
}

halo_status halo_scene_set(halo_scene *s, const char *stage, const char *param, const double *values, int count,
                           int live, halo_diagnostics *diag)
{
    HALO_REFUSE_NULL(diag, s, "scene", HALO_ERROR_INPUT);
    HALO_REFUSE_NULL(diag, stage, "stage", HALO_ERROR_INPUT);
    HALO_REFUSE_NULL(diag, param, "param", HALO_ERROR_INPUT);
    HALO_REFUSE_NULL(diag, values, "values", HALO_ERROR_INPUT);
    const halo_module *m = stage_module(s, stage, "", "stages", diag);
    if (!m)
        return HALO_ERROR_INPUT;
    const halo_param_info *info = halo_module_find_param(m, param);
    if (!info) {
        halo_diag_error(diag, SCENE_PARAM_UNKNOWN, "", 0, 0, "%s: unknown parameter '%s'", stage, param);
        return HALO_ERROR_INPUT;
    }
    char why[256];
    int id = halo_param_check(info, values, count, why, sizeof why);
    if (id >= 0) {
        halo_diagnostics_report(diag, HALO_SEVERITY_ERROR, (halo_message_id)id, "", 0, 0, NULL, "%s.%s: %s", stage,
                                param, why);
        return HALO_ERROR_INPUT;
    }
    halo_scene_entry *e = add_entry(s, m);
    if (!e) {
        halo_diag_error(diag, OUT_OF_MEMORY, "", 0, 0, "out of memory");
        return HALO_ERROR_IO;
    }
    halo_param_value *v = &e->values[info - m->params];
    v->set = 1;
    v->live = live;
    v->count = count;
    memcpy(v->value, values, (size_t)count * (size_t)info->components * sizeof(double));
    return HALO_OK;
}

halo_scene_info halo_scene_describe(const halo_scene *s)
{
    halo_scene_info info = {0};
    HALO_REFUSE_NULL(NULL, s, "scene", info);
    info.stage_count = s->count;
    info.stages = s->names;
    info.render = &s->render;
    return info;
}

void halo_scene_set_render(halo_scene *s, const halo_render_settings *render)
{
    HALO_REFUSE_NULL_VOID(NULL, s, "scene");
    HALO_REFUSE_NULL_VOID(NULL, render, "render");
    s->render = *render;
}

/* ---- Reading JSON ---- */

typedef struct reader {
    halo_scene *scene;
    const char *file;
    halo_diagnostics *diag;
    int errors;
    const char *text; /* the JSON text, to find where a value is */
} reader;

/* ---- Where a value is in the text: jansson keeps no positions, so the JSON path of a
 * message ("stages[1].boundary.k_gs") is followed through the text again. ---- */

static const char *skip_space(const char *p)
{
    while (*p == ' ' || *p == '\t' || *p == '\n' || *p == '\r')
        p++;
    return p;
}

static const char *skip_string(const char *p)
{ /* p at the opening quote */
    for (p++; *p && *p != '"'; p++)
        if (*p == '\\' && p[1])
            p++;
    return *p ? p + 1 : p;
}

static const char *skip_value(const char *p)
{
    p = skip_space(p);
    if (*p == '"')
        return skip_string(p);
    if (*p != '{' && *p != '[') {
        while (*p && !strchr(",}] \t\r\n", *p))
            p++;
        return p;
    }
    for (int depth = 0; *p; p++) {
        if (*p == '"')
            p = skip_string(p) - 1;
        else if (*p == '{' || *p == '[')
            depth++;
        else if ((*p == '}' || *p == ']') && --depth == 0)
            return p + 1;
    }
    return p;
}

/* The key `name` (n bytes) of the object at p: its opening quote, or NULL. */
static const char *object_key(const char *p, const char *name, size_t n)
{
    p = skip_space(p);
    if (*p++ != '{')
        return NULL;
    for (;;) {
        p = skip_space(p);
        if (*p != '"')
            return NULL;
        const char *key = p, *end = skip_string(p);
        p = skip_space(end);
        if (*p != ':')
            return NULL;
        if ((size_t)(end - key) == n + 2 && !strncmp(key + 1, name, n))
            return key;
        p = skip_space(skip_value(p + 1));
        if (*p++ != ',')
            return NULL;
    }
}

/* Item `index` of the list at p, or NULL. */
static const char *list_item(const char *p, size_t index)
{
    p = skip_space(p);
    if (*p++ != '[')
        return NULL;
    for (size_t i = 0;; i++) {
        p = skip_space(p);
        if (*p == ']' || !*p)
            return NULL;
        if (i == index)
            return p;
        p = skip_space(skip_value(p));
        if (*p++ != ',')
            return NULL;
    }
}

/* Where the value at path (n bytes: "a.b[2]") is in text, as far as the text follows the
 * path; at its key instead when the path ends with one and at_key is set. */
static const char *locate_path(const char *text, const char *path, size_t n, int at_key)
{
    const char *value = skip_space(text), *at = value;
    for (size_t i = 0; i < n;) {
        if (path[i] == '[') {
            char *end;
            unsigned long index = strtoul(path + i + 1, &end, 10);
            const char *item = list_item(value, index);
            if (!item || *end != ']')
                break;
            at = value = item;
            i = (size_t)(end - path) + 1;
        } else {
            if (path[i] == '.')
                i++;
            size_t k = i;
            while (k < n && path[k] != '.' && path[k] != '[')
                k++;
            const char *key = object_key(value, path + i, k - i);
            if (!key)
                break;
            value = skip_space(skip_space(skip_string(key)) + 1);
            at = at_key && k == n ? key : value;
            i = k;
        }
    }
    return at;
}

/* A scene error at the value its message starts with ("PATH: ..."): file:line:col and
 * the line, as the JSON syntax errors have. */
static void read_error(reader *r, halo_message_id id, const char *fmt, ...) __attribute__((format(printf, 3, 4)));
static void read_error(reader *r, halo_message_id id, const char *fmt, ...)
{
    halo_strbuf text = {0};
    va_list ap;
    va_start(ap, fmt);
    halo_strbuf_vprintf(&text, fmt, ap);
    va_end(ap);
    const char *message = text.data ? text.data : "";
    int line = 0, column = 0;
    const char *line_start = NULL, *colon = strstr(message, ": ");
    if (r->text && colon && halo_diag_kept(r->diag, HALO_SEVERITY_ERROR)) {
        int at_key = id == HALO_MSG_SCENE_KEY_UNKNOWN || id == HALO_MSG_SCENE_PARAM_UNKNOWN ||
                     id == HALO_MSG_SCENE_STAGE_DUPLICATE;
        size_t n = !strncmp(message, "(top level)", 11) ? 0 : (size_t)(colon - message);
        const char *at = locate_path(r->text, message, n, at_key);
        line = 1;
        line_start = r->text;
        for (const char *p = r->text; p < at; p++)
            if (*p == '\n')
                line++, line_start = p + 1;
        column = (int)(at - line_start) + 1;
    }
    halo_diagnostics_report(r->diag, HALO_SEVERITY_ERROR, id, r->file, line, column, line_start, "%s", message);
    halo_strbuf_free(&text);
    r->errors++;
}

#define READ_ERROR(r, id, ...) read_error((r), HALO_MSG_##id, __VA_ARGS__)

static const char *json_type_name(const json_t *v)
{
    switch (json_typeof(v)) {
    case JSON_OBJECT:
        return "an object";
    case JSON_ARRAY:
        return "a list";
    case JSON_STRING:
        return "a string";
    case JSON_INTEGER:
    case JSON_REAL:
        return "a number";
    case JSON_TRUE:
    case JSON_FALSE:
        return "a boolean";
    default:
        return "null";
    }
}

static void read_param(reader *r, halo_scene_entry *e, const char *path, const char *key, json_t *v)
{
    const halo_module *m = e->module;
    const halo_param_info *info = halo_module_find_param(m, key);
    if (!info) {
        halo_strbuf names = {0};
        for (size_t i = 0; i < m->param_count; i++)
            halo_strbuf_printf(&names, "%s%s", i ? ", " : "", m->params[i].name);
        READ_ERROR(r, SCENE_PARAM_UNKNOWN, "%s.%s: unknown parameter of stage '%s' (it has: %s%s)", path, key,
                   halo_module_name_of(m), names.data ? names.data : "none", m->param_count ? ", live, enabled" : "");
        halo_strbuf_free(&names);
        return;
    }
    double values[HALO_MAX_COMPONENTS];
    int count = 0;
    char why[256];
    int id = halo_param_from_json(info, v, values, &count, why, sizeof why);
    if (id >= 0) {
        read_error(r, (halo_message_id)id, "%s.%s: %s, got %s", path, key, why, json_type_name(v));
        return;
    }
    id = halo_param_check(info, values, count, why, sizeof why);
    if (id >= 0) {
        read_error(r, (halo_message_id)id, "%s.%s: %s", path, key, why);
        return;
    }
    halo_param_value *pv = &e->values[info - m->params];
    pv->set = 1;
    pv->count = count;
    memcpy(pv->value, values, (size_t)count * (size_t)info->components * sizeof(double));
}

static void read_stage(reader *r, size_t index, json_t *item)
{
    char path[256];
    const char *stage = NULL;
    json_t *body = NULL;
    if (json_is_string(item)) {
        stage = json_string_value(item);
    } else if (json_is_object(item) && json_object_size(item) == 1) {
        void *it = json_object_iter(item);
        stage = json_object_iter_key(it);
        body = json_object_iter_value(it);
    } else {
        READ_ERROR(r, SCENE_TYPE, "stages[%zu]: expected a stage name or an object {\"STAGE\": {...}}, got %s", index,
                   json_is_object(item) ? "an object with several keys" : json_type_name(item));
        return;
    }
    snprintf(path, sizeof path, "stages[%zu].%s", index, stage);
    const halo_module *m = halo_library_find(r->scene->library, stage);
    if (!m || m->is_library) {
        char at[64];
        snprintf(at, sizeof at, "stages[%zu]", index);
        READ_ERROR(r, SCENE_STAGE_UNKNOWN, "%s: unknown stage '%s' (halo-validate list shows the stages)", at, stage);
        return;
    }
    if (find_entry(r->scene, stage)) {
        READ_ERROR(r, SCENE_STAGE_DUPLICATE, "%s: stage '%s' is listed twice", path, stage);
        return;
    }
    halo_scene_entry *e = add_entry(r->scene, m);
    if (!e) {
        READ_ERROR(r, OUT_OF_MEMORY, "out of memory");
        return;
    }
    if (!body)
        return;
    if (!json_is_object(body)) {
        READ_ERROR(r, SCENE_TYPE, "%s: expected an object of parameters, got %s", path, json_type_name(body));
        return;
    }
    json_t *live = NULL;
    const char *key;
    json_t *v;
    json_object_foreach(body, key, v)
    {
        if (!strcmp(key, "enabled")) {
            if (!json_is_boolean(v))
                READ_ERROR(r, SCENE_TYPE, "%s.enabled: expected true or false, got %s", path, json_type_name(v));
            else
                e->enabled = json_is_true(v);
        } else if (!strcmp(key, "live")) {
            live = v;
        } else {
            read_param(r, e, path, key, v);
        }
    }
    if (live) {
        if (json_is_boolean(live)) {
            for (size_t i = 0; i < m->param_count; i++)
                e->values[i].live = json_is_true(live);
        } else if (json_is_array(live)) {
            size_t i;
            json_t *name;
            json_array_foreach(live, i, name)
            {
                const halo_param_info *info =
                    json_is_string(name) ? halo_module_find_param(m, json_string_value(name)) : NULL;
                if (!info)
                    READ_ERROR(r, SCENE_PARAM_UNKNOWN, "%s.live[%zu]: %s%s%s is not a parameter of '%s'", path, i,
                               json_is_string(name) ? "'" : "",
                               json_is_string(name) ? json_string_value(name) : "value",
                               json_is_string(name) ? "'" : "", stage);
                else
                    e->values[info - m->params].live = 1;
            }
        } else {
            READ_ERROR(r, SCENE_TYPE, "%s.live: expected true, false or a list of parameter names, got %s", path,
                       json_type_name(live));
        }
    }
}

static int read_number(reader *r, json_t *v, const char *path, double lo, double hi, double *out)
{
    if (!json_is_number(v)) {
        READ_ERROR(r, SCENE_TYPE, "%s: expected a number, got %s", path, json_type_name(v));
        return -1;
    }
    double x = json_number_value(v);
    if (!isfinite(x)) {
        READ_ERROR(r, SCENE_VALUE_NONFINITE, "%s: %g is not finite", path, x);
        return -1;
    }
    if (x < lo) {
        READ_ERROR(r, SCENE_VALUE_BELOW_MIN, "%s: %.9g is below the minimum %.9g", path, x, lo);
        return -1;
    }
    if (x > hi) {
        READ_ERROR(r, SCENE_VALUE_ABOVE_MAX, "%s: %.9g is above the maximum %.9g", path, x, hi);
        return -1;
    }
    *out = x;
    return 0;
}

static int read_numbers(reader *r, json_t *v, const char *path, size_t n, double lo, double hi, double *out)
{
    if (!json_is_array(v) || json_array_size(v) != n) {
        READ_ERROR(r, SCENE_VALUE_COUNT, "%s: expected a list of %zu numbers, got %s", path, n, json_type_name(v));
        return -1;
    }
    int bad = 0;
    for (size_t i = 0; i < n; i++) {
        char p[256];
        snprintf(p, sizeof p, "%s[%zu]", path, i);
        bad |= read_number(r, json_array_get(v, i), p, lo, hi, &out[i]);
    }
    return bad;
}

static void read_render(reader *r, json_t *obj)
{
    halo_render_settings *rs = &r->scene->render;
    if (!json_is_object(obj)) {
        READ_ERROR(r, SCENE_TYPE, "render: expected an object, got %s", json_type_name(obj));
        return;
    }
    const char *key;
    json_t *v;
    char path[256];
    json_object_foreach(obj, key, v)
    {
        snprintf(path, sizeof path, "render.%s", key);
        if (!strcmp(key, "azimuth"))
            read_number(r, v, path, -360, 360, &rs->azimuth);
        else if (!strcmp(key, "elevation"))
            read_number(r, v, path, -90, 90, &rs->elevation);
        else if (!strcmp(key, "zoom"))
            read_number(r, v, path, 0.05, 20, &rs->zoom);
        else if (!strcmp(key, "step"))
            read_number(r, v, path, 0.05, 4, &rs->step);
        else if (!strcmp(key, "background"))
            read_numbers(r, v, path, 3, 0, 1, rs->background);
        else if (!strcmp(key, "window")) {
            double w[2];
            if (!read_numbers(r, v, path, 2, -1e30, 1e30, w)) {
                if (!(w[0] < w[1]))
                    READ_ERROR(r, SCENE_VALUE_BELOW_MIN, "%s: the window's end %g is not above its start %g", path,
                               w[1], w[0]);
                else
                    memcpy(rs->window, w, sizeof w);
            }
        } else if (!strcmp(key, "transfer")) {
            if (!json_is_array(v) || json_array_size(v) < 1 || json_array_size(v) > HALO_MAX_TRANSFER_POINTS) {
                READ_ERROR(r, SCENE_VALUE_COUNT, "%s: expected a list of 1 to %d points [value, r, g, b, opacity]",
                           path, HALO_MAX_TRANSFER_POINTS);
                continue;
            }
            size_t i;
            json_t *pt;
            double tf[HALO_MAX_TRANSFER_POINTS][5];
            int bad = 0;
            json_array_foreach(v, i, pt)
            {
                char p[300];
                snprintf(p, sizeof p, "%s[%zu]", path, i);
                bad |= read_numbers(r, pt, p, 5, 0, 1, tf[i]);
                if (!bad && i > 0 && tf[i][0] < tf[i - 1][0]) {
                    READ_ERROR(r, SCENE_VALUE_BELOW_MIN, "%s[0]: %g is below the previous point's value %g", p,
                               tf[i][0], tf[i - 1][0]);
                    bad = 1;
                }
            }
            if (!bad) {
                rs->transfer_count = (int)json_array_size(v);
                memcpy(rs->transfer, tf, sizeof tf);
            }
        } else {
            READ_ERROR(r, SCENE_KEY_UNKNOWN,
                       "%s: unknown key (azimuth, elevation, zoom, step, background, window, transfer)", path);
        }
    }
}

static halo_scene *scene_parse(const char *text, const char *file, const halo_library *lib, halo_diagnostics *diag)
{
    if (!file)
        file = "scene";
    text = halo_skip_bom(text); /* editors write it; JSON has no place for it */
    json_error_t err;
    json_t *root = json_loads(text, JSON_REJECT_DUPLICATES, &err);
    if (!root) {
        halo_diagnostics_report(diag, HALO_SEVERITY_ERROR, HALO_MSG_SCENE_JSON, file, err.line > 0 ? err.line : 1,
                                err.column > 0 ? err.column : 1, NULL, "invalid JSON: %s", err.text);
        return NULL;
    }
    halo_scene *scene = halo_scene_create(lib);
    if (!scene) {
        json_decref(root);
        halo_diag_error(diag, OUT_OF_MEMORY, file, 0, 0, "out of memory");
        return NULL;
    }
    reader r = {scene, file, diag, 0, text};
    if (!json_is_object(root)) {
        READ_ERROR(&r, SCENE_TYPE, "(top level): expected an object, got %s", json_type_name(root));
    } else {
        const char *key;
        json_t *v;
        json_object_foreach(root, key, v)
        {
            if (!strcmp(key, "halo_scene")) {
                if (!json_is_integer(v) || json_integer_value(v) != SCENE_FORMAT_VERSION)
                    READ_ERROR(&r, SCENE_VERSION, "halo_scene: this libhalo reads scene version %d",
                               SCENE_FORMAT_VERSION);
            } else if (!strcmp(key, "description")) {
                if (!json_is_string(v))
                    READ_ERROR(&r, SCENE_TYPE, "description: expected a string, got %s", json_type_name(v));
            } else if (!strcmp(key, "stages")) {
                if (!json_is_array(v)) {
                    READ_ERROR(&r, SCENE_TYPE, "stages: expected a list, got %s", json_type_name(v));
                    continue;
                }
                size_t i;
                json_t *item;
                json_array_foreach(v, i, item) read_stage(&r, i, item);
            } else if (!strcmp(key, "render")) {
                read_render(&r, v);
            } else {
                READ_ERROR(&r, SCENE_KEY_UNKNOWN, "%s: unknown key (halo_scene, description, stages, render)", key);
            }
        }
    }
    json_decref(root);
    if (r.errors) {
        halo_scene_destroy(scene);
        return NULL;
    }
    return scene;
}

halo_scene *halo_scene_load(const char *file, const char *json_text, const halo_library *lib, halo_diagnostics *diag)
{
    HALO_REFUSE_NULL(diag, lib, "library", NULL);
    if (json_text)
        return scene_parse(json_text, file, lib, diag);
    HALO_REFUSE_NULL(diag, file, "file (or json_text)", NULL);
    const char *path = file;
    size_t len = 0;
    char *text = halo_read_file(path, &len);
    if (!text) {
        halo_diag_read_failed(diag, path, "scene");
        return NULL;
    }
    if (strlen(text) != len) {
        halo_diag_error(diag, SCENE_JSON, path, 0, 0, "invalid JSON: the file contains a NUL byte");
        free(text);
        return NULL;
    }
    halo_scene *s = scene_parse(text, path, lib, diag);
    free(text);
    return s;
}
