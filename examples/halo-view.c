/* halo-view: the interactive viewer. A GLFW window (OpenGL 3.3 core or later) that
 * renders a volume with a libhalo scene through the same example hosts and GL runtime
 * as halo-render (the slice host when the scene has halo stages, else the ray caster),
 * with mouse orbit and zoom, keys that relink the scene with stages or halo parameters
 * changed, live reloading of the scene file, and screenshots. The manual is
 * docs/halo-view.md and halo-view(1).
 *
 * Every frame the host renders into its own RGBA32F framebuffer and reads the image
 * back (as for halo-render); the viewer uploads it to a texture and blits it to the
 * window. A screenshot is that read-back image, so it is what halo-render writes for
 * the same scene, volume, camera and size.
 *
 * Exit status: 0 success, 1 the scene, shaders or volume contents have errors (at
 * start; later errors are shown and the last good scene stays), 2 usage, I/O, window
 * or OpenGL failure. */
#define _POSIX_C_SOURCE 200809L
#include "halo.h"
#include "gl/glfuncs.h"
#include "hosts/raycast.h"
#include "hosts/slice.h"
#include "image_write.h"
#include "json_file.h"
#include "volume.h"
#include "volume_io.h"

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <jansson.h>

#include <dirent.h>
#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>

/* examples/scenes/default.json, embedded by build-aux/embed.sh (embedded_scenes.c). */
struct halo_embedded_file {
    const char *name;
    const char *text;
};
extern const struct halo_embedded_file halo_embedded_scenes[];

#define DEFAULT_SCENE "examples/scenes/default.json"
#define WINDOW_LOW_PERCENT 1.0 /* as halo-render: a file volume's default window */
#define WINDOW_HIGH_PERCENT 99.0
#define POLL_SECONDS 0.25      /* how often the scene file's signature is checked */
#define WAIT_TIMEOUT_SECONDS 60.0 /* --keys "@reload" gives up after this long */
#define ORBIT_DEGREES_PER_PIXEL 0.4
#define KEY_ORBIT_DEGREES 5.0
#define ZOOM_FACTOR 1.1
#define DELTA_STEP 0.05
#define MAX_TOGGLE_STAGES 9

static void usage(FILE *out)
{
    fputs("Usage: halo-view [OPTION]...\n"
          "Opens a window that renders a volume with a libhalo scene through the example\n"
          "GPU hosts (as halo-render does), with mouse orbit and zoom, keys that change the\n"
          "scene, and live reloading of the scene file. Needs an X display (or xvfb-run).\n"
          "\n"
          "  --scene S          scene file (JSON); default: examples/scenes/default.json\n"
          "                     (built in: no reloading, no scene cycling)\n"
          "  --volume FILE      NIfTI volume (.nii, .nii.gz, .hdr/.img); default: the\n"
          "                     built-in procedural volume\n"
          "  --volume-size N    side of the cube the volume is resampled to (8..512); default:\n"
          "                     96 for the built-in volume, a file's own resolution up to 512\n"
          "  --size WxH         render (and initial window) size, 1..8192 each; default 512x512\n"
          "  --save-prefix P    the S key writes P001.png and P001.json, P002...; default\n"
          "                     halo-view-\n"
          "Automation (tests):\n"
          "  --keys \"K ...\"     presses these keys, one per frame, before anything else: a\n"
          "                     character (\"1\", \"e\", \"D\" = shift+d, \"+\"), or left, right, up,\n"
          "                     down, tab, shift+tab, pageup, pagedown, f1, esc; \"@reload\"\n"
          "                     waits until the scene file was reloaded (or failed to) since\n"
          "                     the previous key\n"
          "  --frames N         render at least N frames (default 1)\n"
          "  --screenshot FILE  after N frames and the keys, save the image: .png (8-bit,\n"
          "                     clamped) or .exr (float), as halo-render -o writes it\n"
          "  --quit             exit after that\n"
          "  --help             show this help\n"
          "\n"
          "Keys: mouse left drag orbit, wheel zoom; 1-9 toggle the scene's stages; e\n"
          "emissive/occlusive; d/D delta -/+0.05; m/M interval M halve/double; n/N passes\n"
          "-/+1; arrows orbit; +/- zoom; r camera of the scene; tab/shift+tab (pagedown/\n"
          "pageup) next/previous scene in its folder; s save screenshot and scene; h or F1\n"
          "this help; q or esc quit.\n"
          "\n"
          "Exit status: 0 success, 1 the scene, shaders or volume contents have errors at\n"
          "start, 2 usage, I/O, window or OpenGL failure.\n",
          out);
}

/* ---- Options -------------------------------------------------------------------------- */

typedef struct options {
    const char *scene_path, *volume_path, *screenshot, *save_prefix, *keys;
    int width, height, volume_size, have_volume_size, frames, quit;
} options;

static int parse_int(const char *option, const char *text, int lo, int hi, int *out)
{
    char *end = NULL;
    errno = 0;
    long x = text ? strtol(text, &end, 10) : 0;
    if (!text || end == text || *end != '\0' || errno == ERANGE || x < lo || x > hi) {
        fprintf(stderr, "halo-view: error: %s: '%s' is not an integer in %d..%d\n", option, text ? text : "", lo, hi);
        return 0;
    }
    *out = (int)x;
    return 1;
}

static int parse_size(const char *text, int *width, int *height)
{
    const char *x = strchr(text, 'x');
    char first[32];
    if (!x || (size_t)(x - text) >= sizeof first || x == text) {
        fprintf(stderr, "halo-view: error: --size: '%s' is not WxH\n", text);
        return 0;
    }
    memcpy(first, text, (size_t)(x - text));
    first[x - text] = '\0';
    return parse_int("--size", first, 1, 8192, width) && parse_int("--size", x + 1, 1, 8192, height);
}

static const char *const valued_options[] = {"--scene", "--volume", "--volume-size", "--size", "--save-prefix",
                                             "--keys", "--frames", "--screenshot", NULL};

/* Returns 0 to go on, -1 to exit 0 (help), or an exit status. */
static int parse_options(int argc, char **argv, options *o)
{
    *o = (options){.width = 512, .height = 512, .volume_size = HALO_VOLUME_DEFAULT_SIZE, .frames = 1,
                   .save_prefix = "halo-view-"};
    for (int i = 1; i < argc; ++i) {
        const char *a = argv[i];
        if (!strcmp(a, "--help") || !strcmp(a, "-h")) {
            usage(stdout);
            return -1;
        }
        if (!strcmp(a, "--quit")) {
            o->quit = 1;
            continue;
        }
        int valued = 0;
        for (const char *const *v = valued_options; *v; ++v)
            valued |= !strcmp(a, *v);
        if (!valued) {
            fprintf(stderr, "halo-view: error: unknown argument '%s'\n", a);
            usage(stderr);
            return 2;
        }
        const char *value = i + 1 < argc ? argv[++i] : NULL;
        if (!value) {
            fprintf(stderr, "halo-view: error: %s needs a value\n", a);
            usage(stderr);
            return 2;
        }
        int ok = 1;
        if (!strcmp(a, "--scene"))
            o->scene_path = value;
        else if (!strcmp(a, "--volume"))
            o->volume_path = value;
        else if (!strcmp(a, "--volume-size"))
            ok = o->have_volume_size = parse_int(a, value, HALO_VOLUME_MIN_SIZE, HALO_VOLUME_MAX_SIZE, &o->volume_size);
        else if (!strcmp(a, "--size"))
            ok = parse_size(value, &o->width, &o->height);
        else if (!strcmp(a, "--save-prefix"))
            o->save_prefix = value;
        else if (!strcmp(a, "--keys"))
            o->keys = value;
        else if (!strcmp(a, "--frames"))
            ok = parse_int(a, value, 1, 1000000, &o->frames);
        else if (!strcmp(a, "--screenshot"))
            o->screenshot = value;
        if (!ok)
            return 2;
    }
    if (o->screenshot && !o->screenshot[0]) {
        fprintf(stderr, "halo-view: error: --screenshot: empty file name\n");
        return 2;
    }
    return 0;
}

/* ---- Keys ------------------------------------------------------------------------------ */

/* A key is a character (what was typed, shift included) or one of these. */
enum {
    KEY_LEFT = 0x110000,
    KEY_RIGHT,
    KEY_UP,
    KEY_DOWN,
    KEY_NEXT_SCENE,
    KEY_PREVIOUS_SCENE,
    KEY_HELP,
    KEY_QUIT,
    KEY_WAIT_RELOAD /* --keys only */
};

static const struct {
    const char *name;
    int key;
} key_names[] = {{"left", KEY_LEFT},         {"right", KEY_RIGHT},   {"up", KEY_UP},
                 {"down", KEY_DOWN},         {"tab", KEY_NEXT_SCENE}, {"pagedown", KEY_NEXT_SCENE},
                 {"shift+tab", KEY_PREVIOUS_SCENE}, {"pageup", KEY_PREVIOUS_SCENE}, {"f1", KEY_HELP},
                 {"esc", KEY_QUIT},          {"escape", KEY_QUIT},   {"@reload", KEY_WAIT_RELOAD}};

/* Parses --keys into an array of keys; returns the count, or -1 after a message. */
static int parse_keys(const char *text, int **out)
{
    size_t n = 0, cap = 16;
    int *keys = malloc(cap * sizeof *keys);
    if (!keys)
        return -1;
    const char *p = text;
    for (;;) {
        while (*p == ' ' || *p == '\t' || *p == '\n')
            ++p;
        if (!*p)
            break;
        const char *end = p;
        while (*end && *end != ' ' && *end != '\t' && *end != '\n')
            ++end;
        size_t len = (size_t)(end - p);
        int key = -1;
        if (len == 1 && (unsigned char)*p > ' ' && (unsigned char)*p < 127)
            key = (unsigned char)*p;
        for (size_t k = 0; key < 0 && k < sizeof key_names / sizeof key_names[0]; ++k)
            if (strlen(key_names[k].name) == len && !strncmp(key_names[k].name, p, len))
                key = key_names[k].key;
        if (key < 0) {
            fprintf(stderr, "halo-view: error: --keys: unknown key '%.*s'\n", (int)len, p);
            free(keys);
            return -1;
        }
        if (n == cap) {
            int *grown = realloc(keys, 2 * cap * sizeof *keys);
            if (!grown) {
                free(keys);
                return -1;
            }
            keys = grown;
            cap *= 2;
        }
        keys[n++] = key;
        p = end;
    }
    *out = keys;
    return (int)n;
}

/* ---- Small helpers ---------------------------------------------------------------------- */

static double seconds_now(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

static const char *base_name(const char *path)
{
    const char *slash = strrchr(path, '/');
    return slash ? slash + 1 : path;
}

static char *dup_string(const char *s)
{
    return s ? strdup(s) : NULL;
}

/* What identifies a version of a file: replaced (rename), rewritten or touched. */
typedef struct file_signature {
    int exists;
    dev_t device;
    ino_t inode;
    off_t size;
    struct timespec mtime;
} file_signature;

static file_signature signature_of(const char *path)
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

typedef enum host_kind { HOST_SLICE = 0, HOST_RAYCAST } host_kind;
static const char *const host_names[] = {"slice", "raycast"};
static const char *const host_fragments[] = {"slice.frag", "raycast.frag"};

typedef struct render_host {
    halo_raycast *raycast;
    halo_slice *slice;
} render_host;

static void host_destroy(render_host *h)
{
    halo_raycast_destroy(h->raycast);
    halo_slice_destroy(h->slice);
    h->raycast = NULL;
    h->slice = NULL;
}

/* One change the keys made to a parameter, written into a saved scene. */
typedef struct touched_param {
    const char *stage, *param;
} touched_param;

#define MAX_TOUCHED 8

/* ---- The viewer ------------------------------------------------------------------------------ */

typedef struct viewer {
    options o;
    halo_diagnostics *diag;
    halo_library *lib;

    /* The scene on screen (the last good one), with the keys' changes. */
    halo_scene *scene;
    json_t *scene_json;   /* its text, for saving */
    char *scene_file;     /* its path, NULL for the built-in scene */
    host_kind kind;
    halo_program *program;
    render_host host;
    size_t toggle_count;
    char *toggle_names[MAX_TOGGLE_STAGES];
    int toggle_on[MAX_TOGGLE_STAGES];
    touched_param touched[MAX_TOUCHED];
    int touched_count;

    /* The file watched for changes (the scene asked for last, good or not). */
    char *watch_path;
    file_signature watch_signature;
    double next_poll;
    long loads;           /* reload attempts of the watched file, good or not */
    char error[1024];     /* the first error of the last failed load or change, "" when none */

    /* Volume */
    halo_volume_file file;
    int have_file;
    float *volume;
    int volume_size;
    double volume_window[2];

    /* Camera */
    double azimuth, elevation, zoom;
    int dragging;
    double drag_x, drag_y;

    /* Window and GL */
    GLFWwindow *window;
    halo_gl *runtime;
    const halo_glfuncs *f;
    unsigned display_texture, display_framebuffer;
    int width, height;
    float *image, *display;
    int dirty;            /* the image is out of date: render */
    int rendered;         /* an image has been rendered */
    double frame_ms;
    long frames;
    int save_count;
    int save_requested;
    int quit;
    int error_printed; /* v->error's diagnostics are on stderr already */
} viewer;

static void set_error(viewer *v, const char *fmt, ...)
{
    v->error_printed = 0;
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(v->error, sizeof v->error, fmt, ap);
    va_end(ap);
}

/* Prints the diagnostics and keeps the first error (or the given fallback) for the title. */
static void report_diagnostics(viewer *v, const char *fallback)
{
    halo_diagnostics_print(v->diag, stderr);
    const halo_diagnostic *first = NULL;
    for (size_t i = 0; i < halo_diagnostics_count(v->diag) && !first; ++i) {
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

static void update_title(viewer *v)
{
    char title[2048];
    size_t n = 0;
#define APPEND(...)                                                                       \
    do {                                                                                  \
        if (n < sizeof title)                                                             \
            n += (size_t)snprintf(title + n, sizeof title - n, __VA_ARGS__);              \
    } while (0)
    APPEND("halo-view: %s [%s] %.0f ms", v->watch_path ? base_name(v->watch_path) : "default.json (built in)",
           host_names[v->kind], v->frame_ms);
    for (size_t i = 0; i < v->toggle_count; ++i)
        APPEND("%s%zu%c%s", i ? " " : " | ", i + 1, v->toggle_on[i] ? '+' : '-', v->toggle_names[i]);
    const halo_uniform_info *delta = find_param(v, "halo_generate", "delta");
    const halo_uniform_info *passes = find_param(v, "halo_generate", "passes");
    const halo_uniform_info *mode = find_param(v, "halo_map", "mode");
    if (delta && delta->count > 0)
        APPEND(" | delta %.2f", delta->value[0]);
    if (v->host.slice)
        APPEND(" M %d", halo_slice_interval(v->host.slice));
    if (passes && passes->count > 0)
        APPEND(" N %.0f", passes->value[0]);
    if (mode && mode->count > 0)
        APPEND(" %s", mode->value[0] >= 0.5 ? "occlusive" : "emissive");
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
        cube = halo_volume_create(size);
        if (cube && (window[0] != 0.0 || window[1] != 1.0)) {
            size_t n = (size_t)size * (size_t)size * (size_t)size;
            for (size_t i = 0; i < n; ++i) {
                double x = (cube[i] - window[0]) / (window[1] - window[0]);
                cube[i] = (float)(x < 0.0 ? 0.0 : x > 1.0 ? 1.0 : x);
            }
        }
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

static halo_program *link_program(viewer *v, const halo_scene *scene, host_kind kind)
{
    char *source = halo_host_load(host_fragments[kind], NULL, v->diag);
    if (!source)
        return NULL;
    halo_program *p = halo_link(&(halo_link_desc){.library = v->lib, .scene = scene, .host_source = source,
                                                  .host_file = host_fragments[kind]},
                                v->diag);
    free(source);
    if (p && halo_program_validate(p, v->diag) != HALO_OK) {
        halo_program_destroy(p);
        p = NULL;
    }
    return p;
}

/* halo-render's choice: the slice host when the scene has halo stages (image passes,
 * images, extra outputs or samplers), else the ray caster. */
static halo_program *link_for_scene(viewer *v, const halo_scene *scene, host_kind *kind)
{
    halo_program *p = link_program(v, scene, HOST_SLICE);
    if (!p)
        return NULL;
    if (halo_program_pass_count(p) || halo_program_image_count(p) || halo_program_output_count(p) ||
        halo_program_sampler_count(p)) {
        *kind = HOST_SLICE;
        return p;
    }
    halo_program_destroy(p);
    *kind = HOST_RAYCAST;
    return link_program(v, scene, HOST_RAYCAST);
}

/* Builds a host for program (the GL context is current) and uploads volume and settings. */
static int build_host(viewer *v, host_kind kind, const halo_program *program, const halo_render_settings *settings,
                      const float *volume, int n, render_host *out)
{
    const halo_host_desc desc = {.gl = v->f, .runtime = v->runtime, .program = program,
                                 .width = v->width, .height = v->height};
    render_host h = {0};
    if (kind == HOST_RAYCAST) {
        h.raycast = halo_raycast_create(&desc, v->diag);
        if (!h.raycast || halo_raycast_set_volume(h.raycast, volume, n, n, n, v->diag) != HALO_OK ||
            halo_raycast_set_render(h.raycast, settings, v->diag) != HALO_OK) {
            host_destroy(&h);
            return 0;
        }
    } else {
        h.slice = halo_slice_create(&desc, v->diag);
        if (!h.slice || halo_slice_set_volume(h.slice, volume, n, n, n, v->diag) != HALO_OK ||
            halo_slice_set_render(h.slice, settings, v->diag) != HALO_OK) {
            host_destroy(&h);
            return 0;
        }
    }
    *out = h;
    return 1;
}

static void set_camera(viewer *v)
{
    if (v->host.raycast)
        halo_raycast_set_camera(v->host.raycast, v->azimuth, v->elevation, v->zoom);
    if (v->host.slice)
        halo_slice_set_camera(v->host.slice, v->azimuth, v->elevation, v->zoom);
    v->dirty = 1;
}

/* Relinks the current scene (after a key changed it) and rebuilds the host. On failure
 * the old program and host stay and the error is shown. */
static int relink(viewer *v)
{
    halo_diagnostics_clear(v->diag);
    halo_program *p = link_program(v, v->scene, v->kind);
    render_host h = {0};
    if (!p || !build_host(v, v->kind, p, halo_scene_render(v->scene), v->volume, v->volume_size, &h)) {
        report_diagnostics(v, "cannot relink the scene");
        halo_program_destroy(p);
        return 0;
    }
    host_destroy(&v->host);
    halo_program_destroy(v->program);
    v->program = p;
    v->host = h;
    v->error[0] = '\0';
    set_camera(v);
    return 1;
}

static void free_toggles(viewer *v)
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
static int load_scene(viewer *v, const char *path, int keep_camera)
{
    halo_diagnostics_clear(v->diag);
    const char *text = NULL;
    if (!path) {
        for (const struct halo_embedded_file *e = halo_embedded_scenes; e->name; ++e)
            if (!strcmp(e->name, DEFAULT_SCENE))
                text = e->text;
        if (!text) {
            set_error(v, "%s is not embedded", DEFAULT_SCENE);
            return 2;
        }
    }
    halo_scene *scene = path ? halo_scene_load(path, v->lib, v->diag)
                             : halo_scene_parse(text, DEFAULT_SCENE " (built in)", v->lib, v->diag);
    if (!scene) {
        report_diagnostics(v, "cannot read the scene");
        return halo_diagnostics_has(v->diag, HALO_MSG_IO_READ) ? 2 : 1;
    }
    json_error_t json_error;
    json_t *root = path ? halo_json_load_file(path, 0, &json_error) : json_loads(text, 0, &json_error);
    if (!root) { /* changed between the two reads: the next poll reads it again */
        halo_scene_destroy(scene);
        set_error(v, "%s: %s", path ? base_name(path) : "scene", json_error.text);
        return 1;
    }
    host_kind kind = HOST_SLICE;
    halo_program *p = link_for_scene(v, scene, &kind);
    const halo_render_settings *settings = halo_scene_render(scene);
    int status = 1, size = v->volume_size;
    float *cube = NULL;
    double window[2] = {0.0, 1.0};
    if (p)
        status = prepare_volume(v, settings, scene_sets_window(root), &cube, &size, window);
    render_host h = {0};
    if (!p || status || !build_host(v, kind, p, settings, cube ? cube : v->volume, size, &h)) {
        if (!status)
            status = 1;
        free(cube);
        report_diagnostics(v, "cannot link the scene");
        halo_program_destroy(p);
        halo_scene_destroy(scene);
        json_decref(root);
        return status;
    }

    /* Success: the new scene replaces the old one. */
    int same_camera = v->scene && halo_scene_render(v->scene)->azimuth == settings->azimuth &&
                      halo_scene_render(v->scene)->elevation == settings->elevation &&
                      halo_scene_render(v->scene)->zoom == settings->zoom;
    if (!(keep_camera && same_camera)) {
        v->azimuth = settings->azimuth;
        v->elevation = settings->elevation;
        v->zoom = settings->zoom;
    }
    host_destroy(&v->host);
    commit_volume(v, cube, size, window);
    halo_program_destroy(v->program);
    halo_scene_destroy(v->scene);
    json_decref(v->scene_json);
    free(v->scene_file);
    v->host = h;
    v->program = p;
    v->scene = scene;
    v->scene_json = root;
    v->scene_file = dup_string(path);
    v->kind = kind;
    v->touched_count = 0;
    free_toggles(v);
    size_t stages = halo_scene_stage_count(scene);
    for (size_t i = 0; i < stages && v->toggle_count < MAX_TOGGLE_STAGES; ++i) {
        const char *name = halo_scene_stage(scene, i);
        v->toggle_names[v->toggle_count] = strdup(name);
        v->toggle_on[v->toggle_count] = !json_stage_disabled(root, name);
        if (v->toggle_names[v->toggle_count])
            v->toggle_count++;
    }
    v->error[0] = '\0';
    set_camera(v);
    size_t linked = halo_program_stage_count(p);
    printf("halo-view: loaded %s (%s host, %zu stage%s%s", path ? path : DEFAULT_SCENE " (built in)",
           host_names[kind], linked, linked == 1 ? "" : "s", linked ? ": " : "");
    for (size_t i = 0; i < linked; ++i)
        printf("%s%s", i ? ", " : "", halo_program_stage(p, i));
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
    v->watch_signature = signature_of(v->watch_path);
    if (load_scene(v, v->watch_path, keep_camera) != 0) {
        fprintf(stderr, "halo-view: %s: keeping the last good scene\n", base_name(v->watch_path));
        printf("halo-view: the window shows: %s\n", v->error);
    }
    v->loads++;
    update_title(v);
}

static void poll_scene_file(viewer *v, double now)
{
    if (!v->watch_path || now < v->next_poll)
        return;
    v->next_poll = now + POLL_SECONDS;
    file_signature s = signature_of(v->watch_path);
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

static int compare_names(const void *a, const void *b)
{
    return strcmp(*(char *const *)a, *(char *const *)b);
}

/* The next (step 1) or previous (step -1) .json file in the watched scene's folder. */
static void cycle_scene(viewer *v, int step)
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
    if (v->touched_count < MAX_TOUCHED)
        v->touched[v->touched_count++] = (touched_param){stage, param};
}

/* Applies fn to every element of stage.param and relinks; restores the old values if
 * the relink fails. */
static void change_param(viewer *v, const char *stage, const char *param, double (*fn)(double, double), double arg)
{
    const halo_uniform_info *u = find_param(v, stage, param);
    if (!u) {
        fprintf(stderr, "halo-view: the scene has no %s stage linked (%s)\n", stage, param);
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
        report_diagnostics(v, "cannot set the parameter");
    } else if (!relink(v)) {
        halo_scene_set(v->scene, stage, param, old, count, live, NULL);
    } else {
        touch(v, stage, param);
        printf("halo-view: %s.%s = %g%s\n", stage, param, values[0], count > 1 ? " (every halo)" : "");
    }
    update_title(v);
}

static double flip_mode(double x, double unused)
{
    (void)unused;
    return x >= 0.5 ? 0.0 : 1.0;
}

static double add(double x, double d)
{
    return round((x + d) * 1e6) / 1e6; /* 0.9 - 0.05 is 0.85, not 0.8500000000000001 */
}

static double scale_int(double x, double factor)
{
    return round(x * factor);
}

static void toggle_stage(viewer *v, size_t index)
{
    if (index >= v->toggle_count) {
        fprintf(stderr, "halo-view: the scene has no stage %zu\n", index + 1);
        return;
    }
    const char *name = v->toggle_names[index];
    int on = !v->toggle_on[index];
    halo_diagnostics_clear(v->diag);
    if (halo_scene_enable(v->scene, name, on, v->diag) != HALO_OK) {
        report_diagnostics(v, "cannot change the stage");
    } else if (!relink(v)) {
        halo_scene_enable(v->scene, name, !on, NULL);
    } else {
        v->toggle_on[index] = on;
        int linked = 0;
        for (size_t i = 0; i < halo_program_stage_count(v->program); ++i)
            linked |= !strcmp(halo_program_stage(v->program, i), name);
        printf("halo-view: %s %s%s\n", name, on ? "enabled" : "disabled",
               !on && linked ? " (still linked: an enabled stage needs it)" : "");
    }
    update_title(v);
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
static int save_image(viewer *v, const char *path, const char *name)
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
static void save_screenshot_and_scene(viewer *v)
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
            if (save_image(v, partial, png) && rename(partial, png) != 0)
                fprintf(stderr, "halo-view: error: cannot rename %s: %s\n", partial, strerror(errno));
            free(partial);
        }
    }
    json_decref(root);
    free(png);
    free(json);
}

/* ---- Input ------------------------------------------------------------------------------------------- */

static void print_keys(void)
{
    fputs("halo-view keys:\n"
          "  mouse: left drag orbit, wheel zoom; arrows orbit, + and - zoom, r the scene's camera\n"
          "  1-9    toggle the scene's stages (in scene order)\n"
          "  e      halo_map.mode: emissive <-> occlusive\n"
          "  d / D  halo_generate.delta -/+ 0.05\n"
          "  m / M  halo_generate.interval (M) halve / double\n"
          "  n / N  halo_generate.passes (N) -/+ 1\n"
          "  tab / shift+tab (pagedown / pageup)  next / previous scene in the scene's folder\n"
          "  s      save the image and the scene (--save-prefix)\n"
          "  h, F1  this help;  q, esc  quit\n",
          stdout);
}

static double wrap_degrees(double a)
{
    a = fmod(a, 360.0);
    if (a > 180.0)
        a -= 360.0;
    if (a <= -180.0)
        a += 360.0;
    return a;
}

/* Camera values are kept to 6 decimals, so that a saved scene (written with 15
 * significant digits) holds exactly the camera of the screenshot saved with it. */
static double snap(double x)
{
    return round(x * 1e6) / 1e6;
}

static void orbit(viewer *v, double d_azimuth, double d_elevation)
{
    v->azimuth = snap(wrap_degrees(v->azimuth + d_azimuth));
    v->elevation = snap(fmin(90.0, fmax(-90.0, v->elevation + d_elevation)));
    set_camera(v);
}

static void zoom_by(viewer *v, double factor)
{
    v->zoom = snap(fmin(20.0, fmax(0.05, v->zoom * factor)));
    set_camera(v);
}

static void handle_key(viewer *v, int key)
{
    if (key >= '1' && key <= '9') {
        toggle_stage(v, (size_t)(key - '1'));
        return;
    }
    switch (key) {
    case 'e': case 'E': change_param(v, "halo_map", "mode", flip_mode, 0); break;
    case 'd': change_param(v, "halo_generate", "delta", add, -DELTA_STEP); break;
    case 'D': change_param(v, "halo_generate", "delta", add, DELTA_STEP); break;
    case 'm': change_param(v, "halo_generate", "interval", scale_int, 0.5); break;
    case 'M': change_param(v, "halo_generate", "interval", scale_int, 2.0); break;
    case 'n': change_param(v, "halo_generate", "passes", add, -1); break;
    case 'N': change_param(v, "halo_generate", "passes", add, 1); break;
    case '+': case '=': zoom_by(v, ZOOM_FACTOR); break;
    case '-': case '_': zoom_by(v, 1.0 / ZOOM_FACTOR); break;
    case KEY_LEFT: orbit(v, -KEY_ORBIT_DEGREES, 0); break;
    case KEY_RIGHT: orbit(v, KEY_ORBIT_DEGREES, 0); break;
    case KEY_UP: orbit(v, 0, KEY_ORBIT_DEGREES); break;
    case KEY_DOWN: orbit(v, 0, -KEY_ORBIT_DEGREES); break;
    case 'r': case 'R': {
        const halo_render_settings *r = halo_scene_render(v->scene);
        v->azimuth = r->azimuth;
        v->elevation = r->elevation;
        v->zoom = r->zoom;
        set_camera(v);
        break;
    }
    case KEY_NEXT_SCENE: cycle_scene(v, 1); break;
    case KEY_PREVIOUS_SCENE: cycle_scene(v, -1); break;
    case 's': case 'S': v->save_requested++; break;
    case 'h': case 'H': case '?': case KEY_HELP: print_keys(); break;
    case 'q': case 'Q': case KEY_QUIT: v->quit = 1; break;
    default: break;
    }
    update_title(v);
}

static void on_char(GLFWwindow *w, unsigned int codepoint)
{
    viewer *v = glfwGetWindowUserPointer(w);
    if (codepoint < 127)
        handle_key(v, (int)codepoint);
}

static void on_key(GLFWwindow *w, int key, int scancode, int action, int mods)
{
    (void)scancode;
    viewer *v = glfwGetWindowUserPointer(w);
    if (action == GLFW_RELEASE)
        return;
    switch (key) {
    case GLFW_KEY_LEFT: handle_key(v, KEY_LEFT); break;
    case GLFW_KEY_RIGHT: handle_key(v, KEY_RIGHT); break;
    case GLFW_KEY_UP: handle_key(v, KEY_UP); break;
    case GLFW_KEY_DOWN: handle_key(v, KEY_DOWN); break;
    case GLFW_KEY_TAB: handle_key(v, mods & GLFW_MOD_SHIFT ? KEY_PREVIOUS_SCENE : KEY_NEXT_SCENE); break;
    case GLFW_KEY_PAGE_DOWN: handle_key(v, KEY_NEXT_SCENE); break;
    case GLFW_KEY_PAGE_UP: handle_key(v, KEY_PREVIOUS_SCENE); break;
    case GLFW_KEY_F1: handle_key(v, KEY_HELP); break;
    case GLFW_KEY_ESCAPE: handle_key(v, KEY_QUIT); break;
    default: break;
    }
}

static void on_mouse_button(GLFWwindow *w, int button, int action, int mods)
{
    (void)mods;
    viewer *v = glfwGetWindowUserPointer(w);
    if (button != GLFW_MOUSE_BUTTON_LEFT)
        return;
    v->dragging = action == GLFW_PRESS;
    glfwGetCursorPos(w, &v->drag_x, &v->drag_y);
}

static void on_cursor(GLFWwindow *w, double x, double y)
{
    viewer *v = glfwGetWindowUserPointer(w);
    if (!v->dragging)
        return;
    double dx = x - v->drag_x, dy = y - v->drag_y;
    v->drag_x = x;
    v->drag_y = y;
    orbit(v, -ORBIT_DEGREES_PER_PIXEL * dx, ORBIT_DEGREES_PER_PIXEL * dy);
}

static void on_scroll(GLFWwindow *w, double dx, double dy)
{
    (void)dx;
    viewer *v = glfwGetWindowUserPointer(w);
    zoom_by(v, pow(ZOOM_FACTOR, dy));
}

static void present(viewer *v);

static void on_refresh(GLFWwindow *w)
{
    viewer *v = glfwGetWindowUserPointer(w);
    if (v->rendered)
        present(v);
}

static void on_glfw_error(int code, const char *text)
{
    fprintf(stderr, "halo-view: GLFW error 0x%x: %s\n", code, text);
}

/* ---- Rendering -------------------------------------------------------------------------------------------- */

static void *get_proc_address(const char *name)
{
    GLFWglproc proc = glfwGetProcAddress(name);
    void *p;
    memcpy(&p, &proc, sizeof p);
    return p;
}

static int render(viewer *v)
{
    double start = seconds_now();
    halo_diagnostics_clear(v->diag);
    halo_status status = v->host.raycast ? halo_raycast_render(v->host.raycast, v->image, v->diag)
                                         : halo_slice_render(v->host.slice, v->image, v->diag);
    v->frame_ms = 1e3 * (seconds_now() - start);
    if (status != HALO_OK) {
        report_diagnostics(v, "rendering failed");
        return 0;
    }
    v->rendered = 1;
    v->frames++;
    v->dirty = 0;
    return 1;
}

/* Shows the last image, letterboxed in the window; a red bar along the top while the
 * scene on disk has errors (the image itself stays as rendered, for screenshots). */
static void present(viewer *v)
{
    const halo_glfuncs *f = v->f;
    size_t pixels = (size_t)v->width * (size_t)v->height;
    memcpy(v->display, v->image, pixels * 4 * sizeof *v->display);
    if (v->error[0]) {
        int bar = v->height / 40 + 2;
        for (int y = v->height - bar < 0 ? 0 : v->height - bar; y < v->height; ++y)
            for (int x = 0; x < v->width; ++x) {
                float *px = &v->display[((size_t)y * (size_t)v->width + (size_t)x) * 4];
                px[0] = 0.9f, px[1] = 0.1f, px[2] = 0.1f, px[3] = 1.0f;
            }
    }
    f->BindTexture(GL_TEXTURE_2D, v->display_texture);
    f->PixelStorei(GL_UNPACK_ALIGNMENT, 4);
    f->TexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, v->width, v->height, GL_RGBA, GL_FLOAT, v->display);
    f->BindTexture(GL_TEXTURE_2D, 0);
    int fw, fh;
    glfwGetFramebufferSize(v->window, &fw, &fh);
    f->BindFramebuffer(GL_DRAW_FRAMEBUFFER, 0);
    f->Disable(GL_SCISSOR_TEST);
    f->Viewport(0, 0, fw, fh);
    f->ClearColor(0.12f, 0.12f, 0.12f, 1.0f);
    f->Clear(GL_COLOR_BUFFER_BIT);
    double scale = fmin((double)fw / v->width, (double)fh / v->height);
    int w = (int)lround(v->width * scale), h = (int)lround(v->height * scale);
    int x0 = (fw - w) / 2, y0 = (fh - h) / 2;
    f->BindFramebuffer(GL_READ_FRAMEBUFFER, v->display_framebuffer);
    f->BlitFramebuffer(0, 0, v->width, v->height, x0, y0, x0 + w, y0 + h, GL_COLOR_BUFFER_BIT,
                       w == v->width && h == v->height ? GL_NEAREST : GL_LINEAR);
    f->BindFramebuffer(GL_READ_FRAMEBUFFER, 0);
    glfwSwapBuffers(v->window);
}

static int create_display(viewer *v)
{
    const halo_glfuncs *f = v->f;
    f->GenTextures(1, &v->display_texture);
    f->BindTexture(GL_TEXTURE_2D, v->display_texture);
    f->TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    f->TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    f->TexImage2D(GL_TEXTURE_2D, 0, GL_RGBA32F, v->width, v->height, 0, GL_RGBA, GL_FLOAT, NULL);
    f->BindTexture(GL_TEXTURE_2D, 0);
    f->GenFramebuffers(1, &v->display_framebuffer);
    f->BindFramebuffer(GL_FRAMEBUFFER, v->display_framebuffer);
    f->FramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, v->display_texture, 0);
    GLenum status = f->CheckFramebufferStatus(GL_FRAMEBUFFER);
    f->BindFramebuffer(GL_FRAMEBUFFER, 0);
    return status == GL_FRAMEBUFFER_COMPLETE && f->GetError() == GL_NO_ERROR;
}

/* ---- Main ------------------------------------------------------------------------------------------------- */

int main(int argc, char **argv)
{
    viewer view = {0}, *v = &view;
    int status = parse_options(argc, argv, &v->o);
    if (status)
        return status < 0 ? 0 : status;
    int *keys = NULL, key_count = 0, key_next = 0;
    if (v->o.keys && (key_count = parse_keys(v->o.keys, &keys)) < 0)
        return 2;
    setvbuf(stdout, NULL, _IOLBF, 0);
    v->width = v->o.width;
    v->height = v->o.height;
    status = 2;

    v->diag = halo_diagnostics_create();
    if (!v->diag || halo_setup(NULL) != HALO_OK) {
        fprintf(stderr, "halo-view: error: cannot initialize libhalo\n");
        halo_diagnostics_destroy(v->diag);
        free(keys);
        return 2;
    }
    v->lib = halo_library_create(v->diag);
    if (!v->lib) {
        halo_diagnostics_print(v->diag, stderr);
        goto done;
    }
    if (v->o.volume_path) {
        char err[512];
        halo_volume_status read = halo_volume_read_nifti(v->o.volume_path, &v->file, err, sizeof err);
        if (read != HALO_VOLUME_OK) {
            fprintf(stderr, "halo-view: error: %s\n", err);
            status = (int)read;
            goto done;
        }
        v->have_file = 1;
        fprintf(stderr, "halo-view: %s: %s\n", v->o.volume_path, v->file.description);
    }

    glfwSetErrorCallback(on_glfw_error);
    if (!glfwInit()) {
        fprintf(stderr, "halo-view: error: cannot initialize GLFW (no display? DISPLAY=%s; try xvfb-run -a)\n",
                getenv("DISPLAY") ? getenv("DISPLAY") : "");
        goto done;
    }
    glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
    glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
    glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
    glfwWindowHint(GLFW_SCALE_TO_MONITOR, GLFW_FALSE);
    v->window = glfwCreateWindow(v->width, v->height, "halo-view", NULL, NULL);
    if (!v->window) {
        fprintf(stderr, "halo-view: error: cannot open a %dx%d window with an OpenGL 3.3 core context\n", v->width,
                v->height);
        goto done;
    }
    glfwMakeContextCurrent(v->window);
    glfwSwapInterval(0);
    glfwSetWindowUserPointer(v->window, v);
    glfwSetCharCallback(v->window, on_char);
    glfwSetKeyCallback(v->window, on_key);
    glfwSetMouseButtonCallback(v->window, on_mouse_button);
    glfwSetCursorPosCallback(v->window, on_cursor);
    glfwSetScrollCallback(v->window, on_scroll);
    glfwSetWindowRefreshCallback(v->window, on_refresh);

    v->runtime = halo_gl_create(&(halo_gl_desc){.get_proc_address = get_proc_address}, v->diag);
    if (!v->runtime) {
        halo_diagnostics_print(v->diag, stderr);
        goto done;
    }
    v->f = halo_gl_functions(v->runtime);
    fprintf(stderr, "halo-view: OpenGL %s, %s\n", (const char *)v->f->GetString(GL_VERSION),
            (const char *)v->f->GetString(GL_RENDERER));
    size_t pixels = (size_t)v->width * (size_t)v->height;
    v->image = calloc(pixels * 4, sizeof *v->image);
    v->display = malloc(pixels * 4 * sizeof *v->display);
    if (!v->image || !v->display || !create_display(v)) {
        fprintf(stderr, "halo-view: error: cannot create a %dx%d image\n", v->width, v->height);
        goto done;
    }

    if (v->o.scene_path) {
        v->watch_path = strdup(v->o.scene_path);
        v->watch_signature = signature_of(v->watch_path);
    }
    status = load_scene(v, v->watch_path, 0);
    if (status) {
        if (!v->error_printed) /* each error once */
            fprintf(stderr, "halo-view: error: %s\n", v->error);
        goto done;
    }
    update_title(v);
    if (!v->o.quit)
        print_keys();

    status = 0;
    double wait_since = 0;
    long loads_before_key = v->loads;
    int screenshot_done = 0;
    double last_title = 0;
    while (!glfwWindowShouldClose(v->window) && !v->quit) {
        int waiting = key_next < key_count && keys[key_next] == KEY_WAIT_RELOAD;
        int automated = (key_next < key_count && !waiting) || (long)v->frames < v->o.frames;
        if (automated || v->dirty || v->save_requested)
            glfwPollEvents();
        else
            glfwWaitEventsTimeout(waiting ? 0.05 : POLL_SECONDS);
        double now = seconds_now();
        poll_scene_file(v, now);

        /* one injected key per frame; "@reload" holds the rest until a (re)load */
        if (key_next < key_count) {
            if (keys[key_next] == KEY_WAIT_RELOAD) {
                if (wait_since == 0)
                    wait_since = now;
                if (v->loads > loads_before_key) {
                    key_next++;
                    wait_since = 0;
                    loads_before_key = v->loads;
                } else if (now - wait_since > WAIT_TIMEOUT_SECONDS) {
                    fprintf(stderr, "halo-view: error: --keys @reload: %s did not change in %.0f s\n",
                            v->watch_path ? v->watch_path : "the built-in scene", WAIT_TIMEOUT_SECONDS);
                    status = 1;
                    break;
                }
            } else {
                handle_key(v, keys[key_next++]);
                loads_before_key = v->loads;
            }
        }

        int force = (long)v->frames < v->o.frames;
        if (v->dirty || force || !v->rendered) {
            if (!render(v)) {
                status = 2;
                break;
            }
            present(v);
            if (now - last_title > 0.25) {
                update_title(v);
                last_title = now;
            }
        } else if (v->error[0] || now - last_title > 1.0) {
            present(v); /* the error bar, or a window that was uncovered */
            update_title(v);
            last_title = now;
        }
        for (; v->save_requested > 0; v->save_requested--)
            save_screenshot_and_scene(v);

        if (key_next >= key_count && (long)v->frames >= v->o.frames && !screenshot_done) {
            screenshot_done = 1;
            if (v->o.screenshot && !save_image(v, v->o.screenshot, v->o.screenshot)) {
                status = 2;
                break;
            }
            if (v->o.quit)
                break;
        }
    }
    if (status == 0)
        printf("halo-view: %ld frame%s, last %.1f ms\n", v->frames, v->frames == 1 ? "" : "s", v->frame_ms);

done:
    if (v->window) {
        glfwMakeContextCurrent(v->window);
        host_destroy(&v->host);
        if (v->f && v->display_framebuffer)
            v->f->DeleteFramebuffers(1, &v->display_framebuffer);
        if (v->f && v->display_texture)
            v->f->DeleteTextures(1, &v->display_texture);
        halo_gl_destroy(v->runtime);
        glfwDestroyWindow(v->window);
    }
#if !defined(__SANITIZE_ADDRESS__)
    /* Under AddressSanitizer the X connection is left to the process exit: glfwTerminate
     * unloads Mesa's GLX driver, whose few process-wide allocations LeakSanitizer then
     * reports from an unknown module (no suppression can name it); loaded, they are
     * still reachable and nothing is reported. */
    glfwTerminate();
#endif
    halo_program_destroy(v->program);
    halo_scene_destroy(v->scene);
    json_decref(v->scene_json);
    free_toggles(v);
    free(v->scene_file);
    free(v->watch_path);
    halo_library_destroy(v->lib);
    if (v->have_file)
        halo_volume_file_free(&v->file);
    free(v->volume);
    free(v->image);
    free(v->display);
    free(keys);
    halo_diagnostics_destroy(v->diag);
    halo_shutdown();
    return status;
}
