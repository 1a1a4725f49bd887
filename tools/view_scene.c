/* halo-view's scene (view.h): the scene on screen and the last good one, its volume,
 * host and program through the render driver, the keys' changes, reloading the file
 * and saving a screenshot with the scene. */
#define _POSIX_C_SOURCE 200809L
#include "view.h"

#include "image_write.h"
#include "json_file.h"
#include "volume.h"

#include <dirent.h>
#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* ---- Small helpers ---------------------------------------------------------------------- */

static const char *base_name(const char *path)
{
    const char *slash = strrchr(path, '/');
    return slash ? slash + 1 : path;
}

static char *dup_string(const char *s) { return s ? strdup(s) : NULL; }


file_signature view_signature_of(const char *path)
{
    file_signature s = {0};
    struct stat st;
    if (path && stat(path, &st) == 0) {
        s.exists = 1;
        s.device = st.st_dev;
        s.inode = st.st_ino;
        s.size = st.st_size;
        s.mtime = st.st_mtim;
    }
    return s;
}

static int signature_equal(const file_signature *a, const file_signature *b)
{
    return a->exists == b->exists && a->device == b->device && a->inode == b->inode && a->size == b->size &&
           a->mtime.tv_sec == b->mtime.tv_sec && a->mtime.tv_nsec == b->mtime.tv_nsec;
}

/* ---- Hosts --------------------------------------------------------------------------------- */

/* The host and its program render through the render driver (examples/render_driver.h). */


/* ---- The viewer ------------------------------------------------------------------------------ */


static void set_error(viewer *v, const char *fmt, ...)
{
    v->error_printed = 0;
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(v->error, sizeof v->error, fmt, ap);
    va_end(ap);
}

/* Prints the diagnostics and keeps the first error (or the given fallback) for the title. */
void view_report_diagnostics(viewer *v, const char *fallback)
{
    halo_diagnostics_print(v->diag, stderr);
    const halo_diagnostic *first = NULL;
    for (size_t i = 0; i < halo_diagnostics_describe(v->diag).count && !first; ++i) {
        const halo_diagnostic *d = halo_diagnostics_get(v->diag, i);
        if (d->severity == HALO_SEVERITY_ERROR)
            first = d;
    }
    if (!first) {
        set_error(v, "%s", fallback);
    } else if (first->file && first->file[0] && first->line > 0) {
        set_error(v, "%s:%d:%d: error: %s", base_name(first->file), first->line, first->column, first->text);
    } else if (first->file && first->file[0]) {
        set_error(v, "%s: error: %s", base_name(first->file), first->text);
    } else {
        set_error(v, "error: %s", first->text);
    }
    v->error_printed = first != NULL;
}

static const halo_uniform_info *find_param(const viewer *v, const char *stage, const char *param)
{
    return v->program ? halo_program_find_uniform(v->program, stage, param) : NULL;
}

void view_update_title(viewer *v)
{
    char title[2048];
    size_t n = 0;
#define APPEND(...)                                                          \
    do {                                                                     \
        if (n < sizeof title)                                                \
            n += (size_t)snprintf(title + n, sizeof title - n, __VA_ARGS__); \
    } while (0)
    APPEND("halo-view: %s [%s] %.0f ms", v->watch_path ? base_name(v->watch_path) : "default.json (built in)",
           halo_driver_host_names[v->kind], v->frame_ms);
    for (size_t i = 0; i < v->toggle_count; ++i)
        APPEND("%s%zu%c%s", i ? " " : " | ", i + 1, v->toggle_on[i] ? '+' : '-', v->toggle_names[i]);
    if (v->host.slice)
        APPEND(" | M %d", halo_slice_interval(v->host.slice));
    const halo_uniform_info *selected = find_param(v, v->selected.stage, v->selected.param);
    if (selected && selected->count > 0) {
        APPEND(" | %s.%s", selected->stage, selected->param);
        for (int k = 0; k < selected->info->components && k < 4; ++k)
            APPEND("%s%g", k ? ", " : " ", selected->value[k]);
    }
    if (v->error[0])
        APPEND(" | %s (showing the last good scene)", v->error);
#undef APPEND
    if (v->window)
        glfwSetWindowTitle(v->window, title);
}

/* ---- Volume ---------------------------------------------------------------------------------- */

static int scene_sets_window(const json_t *root)
{
    const json_t *render = root ? json_object_get(root, "render") : NULL;
    return render && json_object_get(render, "window") != NULL;
}

/* The cube for this scene's window (as halo-render's prepare_volume): *cube_out is NULL
 * when v->volume already has that window, else a new cube for commit_volume. */
static int prepare_volume(viewer *v, const halo_render_settings *settings, int scene_window, float **cube_out,
                          int *size_out, double window[2])
{
    *cube_out = NULL;
    if (v->have_file && !scene_window) {
        halo_volume_percentile_window(&v->file, WINDOW_LOW_PERCENT, WINDOW_HIGH_PERCENT, window);
    } else {
        window[0] = settings->window[0];
        window[1] = settings->window[1];
    }
    if (v->volume && window[0] == v->volume_window[0] && window[1] == v->volume_window[1])
        return 0;
    float *cube;
    int size;
    if (!v->have_file) {
        size = v->o.volume_size;
        cube = halo_driver_builtin_volume(size, window);
    } else {
        size = v->o.have_volume_size ? v->o.volume_size : halo_volume_display_size(&v->file, HALO_VOLUME_MAX_SIZE);
        char why[512];
        if (halo_volume_display_check(&v->file, size, why, sizeof why) != HALO_VOLUME_OK) {
            set_error(v, "%s: %s", v->o.volume_path, why);
            fprintf(stderr, "halo-view: error: %s\n", v->error);
            return 1;
        }
        cube = halo_volume_to_display(&v->file, window, size);
        fprintf(stderr, "halo-view: %s: window %g:%g; resampled to %d^3\n", v->o.volume_path, window[0], window[1],
                size);
    }
    if (!cube) {
        set_error(v, "out of memory for a %d^3 volume", size);
        fprintf(stderr, "halo-view: error: %s\n", v->error);
        return 2;
    }
    *cube_out = cube;
    *size_out = size;
    return 0;
}

/* Makes a new cube the current volume (the hosts that referenced the old one are gone). */
static void commit_volume(viewer *v, float *cube, int size, const double window[2])
{
    if (!cube)
        return;
    free(v->volume);
    v->volume = cube;
    v->volume_size = size;
    v->volume_window[0] = window[0];
    v->volume_window[1] = window[1];
}

/* ---- Linking and hosts ------------------------------------------------------------------------------ */

static halo_program *link_program(viewer *v, const halo_scene *scene, halo_driver_host kind)
{
    return halo_driver_link(&(halo_link_desc){.library = v->lib, .scene = scene}, kind, 1, v->diag);
}

/* Builds a host for program (the GL context is current) and uploads volume and settings. */
static int build_host(viewer *v, halo_driver_host kind, const halo_program *program,
                      const halo_render_settings *settings, const float *volume, int n, halo_driver *out)
{
    const halo_host_desc desc = {
        .gl = v->f, .runtime = v->runtime, .program = program, .width = v->width, .height = v->height};
    halo_driver h;
    if (!halo_driver_create(&h, kind, &desc, v->diag) ||
        halo_driver_set_volume(&h, volume, (const int[3]){n, n, n}, settings, 0, v->diag) != HALO_OK) {
        halo_driver_destroy(&h);
        return 0;
    }
    *out = h;
    return 1;
}

void view_set_camera(viewer *v)
{
    halo_driver_set_camera(&v->host, v->azimuth, v->elevation, v->zoom);
    v->dirty = 1;
}

/* Relinks the current scene (after a key changed it) and rebuilds the host. On failure
 * the old program and host stay and the error is shown. */
static int relink(viewer *v)
{
    halo_diagnostics_clear(v->diag);
    halo_program *p = link_program(v, v->scene, v->kind);
    halo_driver h = {0};
    if (!p || !build_host(v, v->kind, p, halo_scene_describe(v->scene).render, v->volume, v->volume_size, &h)) {
        view_report_diagnostics(v, "cannot relink the scene");
        halo_program_destroy(p);
        return 0;
    }
    halo_driver_destroy(&v->host);
    halo_program_destroy(v->program);
    v->program = p;
    v->host = h;
    v->error[0] = '\0';
    view_set_camera(v);
    return 1;
}

void view_free_toggles(viewer *v)
{
    for (size_t i = 0; i < v->toggle_count; ++i)
        free(v->toggle_names[i]);
    v->toggle_count = 0;
}

/* Whether a JSON stage entry is {"name": {"enabled": false, ...}}. */
static int json_stage_disabled(const json_t *root, const char *name)
{
    const json_t *stages = json_object_get(root, "stages");
    size_t i;
    const json_t *entry;
    json_array_foreach(stages, i, entry)
    {
        const json_t *params = json_is_object(entry) ? json_object_get(entry, name) : NULL;
        const json_t *enabled = params ? json_object_get(params, "enabled") : NULL;
        if (enabled && json_is_false(enabled))
            return 1;
    }
    return 0;
}

/* Loads a scene file (path) or the built-in scene (path NULL). keep_camera: keep the
 * viewer's camera when the file's camera did not change (a reload). Returns 0, or an
 * exit status for a failure at start (the old scene stays otherwise). */
int view_load_scene(viewer *v, const char *path, int keep_camera)
{
    halo_diagnostics_clear(v->diag);
    const char *text = NULL;
    if (!path) {
        text = halo_tool_embedded_scene(DEFAULT_SCENE);
        if (!text) {
            set_error(v, "%s is not embedded", DEFAULT_SCENE);
            return 2;
        }
    }
    halo_scene *scene = path ? halo_scene_load(path, NULL, v->lib, v->diag)
                             : halo_scene_load(DEFAULT_SCENE " (built in)", text, v->lib, v->diag);
    if (!scene) {
        view_report_diagnostics(v, "cannot read the scene");
        return halo_diagnostics_has(v->diag, HALO_MSG_IO_READ) ||
                       halo_diagnostics_has(v->diag, HALO_MSG_INPUT_TOO_LARGE)
                   ? 2
                   : 1;
    }
    json_error_t json_error;
    json_t *root = path ? halo_json_load_file(path, 0, &json_error) : json_loads(text, 0, &json_error);
    if (!root) { /* changed between the two reads: the next poll reads it again */
        halo_scene_destroy(scene);
        set_error(v, "%s: %s", path ? base_name(path) : "scene", json_error.text);
        return 1;
    }
    /* halo-render's choice: the slice host when the scene has halo stages */
    halo_driver_host kind = halo_driver_choose_host(v->lib, scene);
    halo_program *p = link_program(v, scene, kind);
    const halo_render_settings *settings = halo_scene_describe(scene).render;
    int status = 1, size = v->volume_size;
    float *cube = NULL;
    double window[2] = {0.0, 1.0};
    if (p)
        status = prepare_volume(v, settings, scene_sets_window(root), &cube, &size, window);
    halo_driver h = {0};
    if (!p || status || !build_host(v, kind, p, settings, cube ? cube : v->volume, size, &h)) {
        if (!status)
            status = 1;
        free(cube);
        view_report_diagnostics(v, "cannot link the scene");
        halo_program_destroy(p);
        halo_scene_destroy(scene);
        json_decref(root);
        return status;
    }

    /* Success: the new scene replaces the old one. */
    const halo_render_settings *old = v->scene ? halo_scene_describe(v->scene).render : NULL;
    int same_camera = old && old->azimuth == settings->azimuth && old->elevation == settings->elevation &&
                      old->zoom == settings->zoom;
    if (!(keep_camera && same_camera)) {
        v->azimuth = settings->azimuth;
        v->elevation = settings->elevation;
        v->zoom = settings->zoom;
    }
    halo_driver_release(&v->host, &v->program, &v->scene);
    commit_volume(v, cube, size, window);
    json_decref(v->scene_json);
    free(v->scene_file);
    v->host = h;
    v->program = p;
    v->scene = scene;
    v->scene_json = root;
    v->scene_file = dup_string(path);
    v->kind = kind;
    v->touched_count = 0;
    view_free_toggles(v);
    size_t stages = halo_scene_describe(scene).stage_count;
    for (size_t i = 0; i < stages && v->toggle_count < MAX_TOGGLE_STAGES; ++i) {
        const char *name = halo_scene_describe(scene).stages[i];
        v->toggle_names[v->toggle_count] = strdup(name);
        v->toggle_on[v->toggle_count] = !json_stage_disabled(root, name);
        if (v->toggle_names[v->toggle_count])
            v->toggle_count++;
    }
    v->error[0] = '\0';
    view_set_camera(v);
    size_t linked = halo_program_reflection(p).stage_count;
    printf("halo-view: loaded %s (%s host, %zu stage%s%s", path ? path : DEFAULT_SCENE " (built in)",
           halo_driver_host_names[kind], linked, linked == 1 ? "" : "s", linked ? ": " : "");
    for (size_t i = 0; i < linked; ++i)
        printf("%s%s", i ? ", " : "", halo_program_reflection(p).stages[i].name);
    printf(")\n");
    return 0;
}

/* Switches to another scene file, or reloads the watched one. */
static void open_scene(viewer *v, const char *path, int keep_camera)
{
    if (path != v->watch_path) {
        char *copy = strdup(path);
        if (!copy)
            return;
        free(v->watch_path);
        v->watch_path = copy;
    }
    v->watch_signature = view_signature_of(v->watch_path);
    if (view_load_scene(v, v->watch_path, keep_camera) != 0) {
        fprintf(stderr, "halo-view: %s: keeping the last good scene\n", base_name(v->watch_path));
        printf("halo-view: the window shows: %s\n", v->error);
    }
    v->loads++;
    view_update_title(v);
}

void view_poll_scene_file(viewer *v, double now)
{
    if (!v->watch_path || now < v->next_poll)
        return;
    v->next_poll = now + POLL_SECONDS;
    file_signature s = view_signature_of(v->watch_path);
    if (signature_equal(&s, &v->watch_signature))
        return;
    if (!s.exists) { /* deleted, or between an editor's delete and write: wait */
        v->watch_signature = s;
        return;
    }
    printf("halo-view: %s changed: reloading\n", v->watch_path);
    int same = v->scene_file && !strcmp(v->scene_file, v->watch_path);
    open_scene(v, v->watch_path, same);
}

static int compare_names(const void *a, const void *b) { return strcmp(*(char *const *)a, *(char *const *)b); }

/* The next (step 1) or previous (step -1) .json file in the watched scene's folder. */
void view_cycle_scene(viewer *v, int step)
{
    if (!v->watch_path) {
        fprintf(stderr, "halo-view: the built-in scene has no folder to cycle through: use --scene\n");
        return;
    }
    const char *slash = strrchr(v->watch_path, '/');
    char *folder = slash ? strndup(v->watch_path, (size_t)(slash - v->watch_path) + 1) : strdup("");
    DIR *dir = folder ? opendir(folder[0] ? folder : ".") : NULL;
    char **names = NULL;
    size_t count = 0, cap = 0;
    struct dirent *e;
    while (dir && (e = readdir(dir))) {
        size_t len = strlen(e->d_name);
        if (len < 6 || strcmp(e->d_name + len - 5, ".json") || e->d_name[0] == '.')
            continue;
        if (count == cap) {
            cap = cap ? 2 * cap : 32;
            char **grown = realloc(names, cap * sizeof *names);
            if (!grown)
                break;
            names = grown;
        }
        if ((names[count] = strdup(e->d_name)))
            count++;
    }
    if (dir)
        closedir(dir);
    if (count) {
        qsort(names, count, sizeof *names, compare_names);
        const char *current = base_name(v->watch_path);
        size_t at = 0;
        int found = 0;
        for (size_t i = 0; i < count && !found; ++i)
            if (!strcmp(names[i], current))
                at = i, found = 1;
        size_t next = found ? (at + count + (size_t)(step > 0 ? 1 : count - 1)) % count : 0;
        size_t length = strlen(folder) + strlen(names[next]) + 1;
        char *path = malloc(length);
        if (path) {
            snprintf(path, length, "%s%s", folder, names[next]);
            open_scene(v, path, 0);
            free(path);
        }
    }
    for (size_t i = 0; i < count; ++i)
        free(names[i]);
    free(names);
    free(folder);
}

/* ---- Parameter keys --------------------------------------------------------------------------- */

static void touch(viewer *v, const char *stage, const char *param)
{
    for (int i = 0; i < v->touched_count; ++i)
        if (!strcmp(v->touched[i].stage, stage) && !strcmp(v->touched[i].param, param))
            return;
    if (v->touched_count < MAX_TOUCHED) {
        touched_param *t = &v->touched[v->touched_count++];
        snprintf(t->stage, sizeof t->stage, "%s", stage);
        snprintf(t->param, sizeof t->param, "%s", param);
    }
}

/* Applies fn to every element of stage.param and relinks; restores the old values if
 * the relink fails. */
static void change_param(viewer *v, const char *stage, const char *param, double (*fn)(double, double), double arg)
{
    const halo_uniform_info *u = find_param(v, stage, param);
    if (!u) {
        fprintf(stderr, "halo-view: the linked program has no parameter %s.%s\n", stage, param);
        return;
    }
    int n = u->count * u->info->components, live = u->live;
    double old[HALO_MAX_COMPONENTS], values[HALO_MAX_COMPONENTS];
    memcpy(old, u->value, (size_t)n * sizeof *old);
    for (int k = 0; k < n; ++k) {
        double x = fn(old[k], arg);
        values[k] = x < u->info->min ? u->info->min : x > u->info->max ? u->info->max : x;
    }
    if (!memcmp(old, values, (size_t)n * sizeof *old)) {
        printf("halo-view: %s.%s stays %g (its range is %g..%g)\n", stage, param, old[0], u->info->min, u->info->max);
        return;
    }
    int count = u->count;
    halo_diagnostics_clear(v->diag);
    if (halo_scene_set(v->scene, stage, param, values, count, live, v->diag) != HALO_OK) {
        view_report_diagnostics(v, "cannot set the parameter");
    } else if (!relink(v)) {
        halo_scene_set(v->scene, stage, param, old, count, live, NULL);
    } else {
        touch(v, stage, param);
        printf("halo-view: %s.%s = %g%s\n", stage, param, values[0], count > 1 ? " (every element)" : "");
    }
    view_update_title(v);
}

static double flip(double x, double unused)
{
    (void)unused;
    return x >= 0.5 ? 0.0 : 1.0;
}

static double add(double x, double d)
{
    /* 0.9 - 0.05 is 0.85, not 0.8500000000000001; a step finer than that is taken as it is */
    return fabs(d) >= 1e-6 ? round((x + d) * 1e6) / 1e6 : x + d;
}

static double scale_int(double x, double factor) { return round(x * factor); }

/* 10 % of the value (of 1 near 0) in the direction's sign. */
static double nudge(double x, double direction) { return add(x, direction * 0.1 * fmax(fabs(x), 1.0)); }

/* The program's index of the selected parameter, or -1. */
static long selected_index(const viewer *v)
{
    size_t n = v->program ? halo_program_reflection(v->program).uniform_count : 0;
    for (size_t i = 0; i < n; ++i) {
        const halo_uniform_info *u = &halo_program_reflection(v->program).uniforms[i];
        if (!strcmp(u->stage, v->selected.stage) && !strcmp(u->param, v->selected.param))
            return (long)i;
    }
    return -1;
}

void view_select_param(viewer *v, int step)
{
    size_t n = v->program ? halo_program_reflection(v->program).uniform_count : 0;
    if (!n) {
        fprintf(stderr, "halo-view: the linked stages have no parameters\n");
        return;
    }
    long i = selected_index(v);
    if (i < 0)
        i = step > 0 ? -1 : 0;
    i = ((i + step) % (long)n + (long)n) % (long)n;
    const halo_uniform_info *u = &halo_program_reflection(v->program).uniforms[(size_t)i];
    snprintf(v->selected.stage, sizeof v->selected.stage, "%s", u->stage);
    snprintf(v->selected.param, sizeof v->selected.param, "%s", u->param);
    printf("halo-view: selected %s.%s = %g (%g..%g): %s\n", u->stage, u->param, u->count > 0 ? u->value[0] : 0.0,
           u->info->min, u->info->max, u->info->meaning ? u->info->meaning : "");
    view_update_title(v);
}

/* A step by what the reflection says of the parameter: a bool flips; its step= when it has one; an int steps by 1,
 * or halves and doubles when it is a stage's interval (M: powers of two); a float (or
 * vector: every component) moves by a PARAM_STEPS-th of its range, or by 10 % when the
 * range is unbounded. */
void view_step_param(viewer *v, int direction)
{
    long i = selected_index(v);
    if (i < 0) {
        fprintf(stderr, "halo-view: no parameter selected (p / P select one)%s\n",
                v->selected.stage[0] ? ": the selected one is not linked now" : "");
        return;
    }
    const halo_uniform_info *u = &halo_program_reflection(v->program).uniforms[(size_t)i];
    const halo_param_info *info = u->info;
    if (info->type == HALO_PARAM_CHANNELS && halo_program_reflection(v->program).group_count > 1) {
        /* the program holds one group of four features at a time: a change here would
         * write that group back over the scene's others */
        fprintf(stderr,
                "halo-view: %s.%s has a value per feature in %d groups: edit it in the scene file (it reloads)\n",
                u->stage, u->param, halo_program_reflection(v->program).group_count);
        return;
    }
    if (info->type == HALO_PARAM_BOOL) {
        change_param(v, u->stage, u->param, flip, 0.0);
        return;
    }
    if (info->step > 0.0) {
        change_param(v, u->stage, u->param, add, direction * info->step);
        return;
    }
    if (info->type == HALO_PARAM_INT) {
        int interval = 0;
        for (size_t k = 0; k < halo_program_reflection(v->program).stage_count; ++k) {
            const halo_stage_info *s = &halo_program_reflection(v->program).stages[k];
            interval |= !strcmp(s->name, u->stage) && s->interval && !strcmp(s->interval, u->param);
        }
        if (interval)
            change_param(v, u->stage, u->param, scale_int, direction > 0 ? 2.0 : 0.5);
        else
            change_param(v, u->stage, u->param, add, direction);
        return;
    }
    double range = info->max - info->min;
    if (isfinite(range) && range > 0.0 && range <= 1e6) {
        change_param(v, u->stage, u->param, add, direction * range / PARAM_STEPS);
        return;
    }
    change_param(v, u->stage, u->param, nudge, direction);
}

void view_toggle_stage(viewer *v, size_t index)
{
    if (index >= v->toggle_count) {
        fprintf(stderr, "halo-view: the scene has no stage %zu\n", index + 1);
        return;
    }
    const char *name = v->toggle_names[index];
    int on = !v->toggle_on[index];
    halo_diagnostics_clear(v->diag);
    if (halo_scene_enable(v->scene, name, on, v->diag) != HALO_OK) {
        view_report_diagnostics(v, "cannot change the stage");
    } else if (!relink(v)) {
        halo_scene_enable(v->scene, name, !on, NULL);
    } else {
        v->toggle_on[index] = on;
        int linked = 0;
        for (size_t i = 0; i < halo_program_reflection(v->program).stage_count; ++i)
            linked |= !strcmp(halo_program_reflection(v->program).stages[i].name, name);
        printf("halo-view: %s %s%s\n", name, on ? "enabled" : "disabled",
               !on && linked ? " (still linked: an enabled stage needs it)" : "");
    }
    view_update_title(v);
}

/* ---- Saving ------------------------------------------------------------------------------------------ */

static json_t *param_json(const halo_uniform_info *u)
{
    int integer = u->info->type == HALO_PARAM_INT || u->info->type == HALO_PARAM_BOOL;
    int components = u->info->components;
#define NUMBER(x) (integer ? json_integer((json_int_t)llround(x)) : json_real(x))
    if (u->info->array_size == 0 && u->info->type != HALO_PARAM_CHANNELS) {
        if (components == 1)
            return NUMBER(u->value[0]);
        json_t *list = json_array();
        for (int c = 0; c < components; ++c)
            json_array_append_new(list, NUMBER(u->value[c]));
        return list;
    }
    if (u->info->type == HALO_PARAM_CHANNELS && u->count == 1)
        return NUMBER(u->value[0]);
    json_t *list = json_array();
    for (int e = 0; e < u->count; ++e) {
        if (components == 1) {
            json_array_append_new(list, NUMBER(u->value[e]));
            continue;
        }
        json_t *element = json_array();
        for (int c = 0; c < components; ++c)
            json_array_append_new(element, NUMBER(u->value[e * components + c]));
        json_array_append_new(list, element);
    }
    return list;
#undef NUMBER
}

/* The parameter object of a stage's entry in stages (made an object, or appended). */
static json_t *stage_params(json_t *root, const char *name)
{
    json_t *stages = json_object_get(root, "stages");
    if (!json_is_array(stages)) {
        stages = json_array();
        json_object_set_new(root, "stages", stages);
    }
    size_t i;
    json_t *entry;
    json_array_foreach(stages, i, entry)
    {
        if (json_is_string(entry) && !strcmp(json_string_value(entry), name)) {
            json_t *object = json_pack("{s:{}}", name);
            json_array_set_new(stages, i, object);
            return json_object_get(object, name);
        }
        json_t *params = json_is_object(entry) ? json_object_get(entry, name) : NULL;
        if (params)
            return params;
    }
    json_t *object = json_pack("{s:{}}", name);
    json_array_append_new(stages, object);
    return json_object_get(object, name);
}

/* The scene on screen as JSON: the file's text with the stages the keys switched, the
 * parameters they changed and the camera. */
static json_t *current_scene_json(viewer *v)
{
    json_t *root = json_deep_copy(v->scene_json);
    if (!root)
        return NULL;
    for (size_t i = 0; i < v->toggle_count; ++i) {
        const char *name = v->toggle_names[i];
        int disabled = json_stage_disabled(root, name);
        if (v->toggle_on[i] == !disabled)
            continue;
        json_t *params = stage_params(root, name);
        if (v->toggle_on[i])
            json_object_del(params, "enabled");
        else
            json_object_set_new(params, "enabled", json_false());
    }
    for (int i = 0; i < v->touched_count; ++i) {
        const halo_uniform_info *u = find_param(v, v->touched[i].stage, v->touched[i].param);
        if (u)
            json_object_set_new(stage_params(root, u->stage), u->param, param_json(u));
    }
    json_t *render = json_object_get(root, "render");
    if (!json_is_object(render)) {
        render = json_object();
        json_object_set_new(root, "render", render);
    }
    json_object_set_new(render, "azimuth", json_real(v->azimuth));
    json_object_set_new(render, "elevation", json_real(v->elevation));
    json_object_set_new(render, "zoom", json_real(v->zoom));
    return root;
}

/* Writes the last rendered image (not the window's view of it) to path; name is the
 * name reported (path may be a temporary name). */
int view_save_image(viewer *v, const char *path, const char *name)
{
    char err[512];
    if (halo_image_write(path, v->width, v->height, v->image, err, sizeof err) != 0) {
        fprintf(stderr, "halo-view: error: %s\n", err);
        return 0;
    }
    printf("halo-view: wrote %s (%dx%d)\n", name, v->width, v->height);
    return 1;
}

/* The S key: PREFIX###.png and PREFIX###.json. */
void view_save_screenshot_and_scene(viewer *v)
{
    size_t length = strlen(v->o.save_prefix) + 32;
    char *png = malloc(length), *json = malloc(length);
    json_t *root = current_scene_json(v);
    if (png && json && root) {
        ++v->save_count;
        snprintf(png, length, "%s%03d.png", v->o.save_prefix, v->save_count);
        snprintf(json, length, "%s%03d.json", v->o.save_prefix, v->save_count);
        /* the scene first: a test waiting for the image finds both */
        if (json_dump_file(root, json, JSON_INDENT(2) | JSON_REAL_PRECISION(15)) != 0)
            fprintf(stderr, "halo-view: error: cannot write %s: %s\n", json, strerror(errno));
        else
            printf("halo-view: wrote %s\n", json);
        char *partial = malloc(length + 8);
        if (partial) { /* written under another name, then renamed: never seen half-written */
            snprintf(partial, length + 8, "%s%03d.tmp.png", v->o.save_prefix, v->save_count);
            if (view_save_image(v, partial, png) && rename(partial, png) != 0)
                fprintf(stderr, "halo-view: error: cannot rename %s: %s\n", partial, strerror(errno));
            free(partial);
        }
    }
    json_decref(root);
    free(png);
    free(json);
}
