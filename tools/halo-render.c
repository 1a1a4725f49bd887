/* halo-render: renders a volume with a libhalo scene through one of the example GPU
 * hosts (slices, slab ray caster, ray caster), offline (headless OpenGL), to a PNG
 * or EXR image. The manual is docs/halo-render.md and halo-render(1).
 *
 * With no arguments: the built-in procedural volume, the default scene
 * (examples/scenes/default.json, embedded at build time), halo-render.png in the
 * current directory. Exit status: 0 success, 1 the input has errors (scene, shaders,
 * volume contents), 2 usage or I/O failure (bad options, missing or truncated files). */
#define _POSIX_C_SOURCE 200809L
#include "halo.h"
#include "halo_feature.h"
#include "gl/glfuncs.h"
#include "gl/headless.h"
#include "hosts/host_common.h"
#include "hosts/raycast.h"
#include "hosts/slab.h"
#include "hosts/slice.h"
#include "image_write.h"
#include "json_file.h"
#include "volume.h"
#include "volume_io.h"

#include "bench_budget.h"

#include <jansson.h>

#include <errno.h>
#include <limits.h>
#include <math.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

/* examples/scenes/default.json, embedded by build-aux/embed.sh (embedded_scenes.c). */
struct halo_embedded_file {
    const char *name;
    const char *text;
};
extern const struct halo_embedded_file halo_embedded_scenes[];

static const char *embedded_scene(const char *name)
{
    for (const struct halo_embedded_file *f = halo_embedded_scenes; f->name; ++f)
        if (!strcmp(f->name, name))
            return f->text;
    return NULL;
}


/* The stage of feature halos (libhalo/halo_feature.h): its halo buffer is built here. */
#define FEATURE_STAGE "feature_halo"
/* The texture unit the feature halo buffer is bound to: the hosts use 0..2, the slice
 * host's halo images 3 on. */
#define FEATURE_BUFFER_UNIT 15

#define DEFAULT_SCENE "examples/scenes/default.json"
/* The default window of a volume file whose scene sets none: these percentiles. */
#define WINDOW_LOW_PERCENT 1.0
#define WINDOW_HIGH_PERCENT 99.0

static void usage(FILE *out)
{
    fputs("Usage: halo-render [OPTION]...\n"
          "Renders a volume with a libhalo scene through an example GPU host (headless\n"
          "OpenGL: EGL or OSMesa) and writes an image. With no options: the built-in\n"
          "procedural volume and the default halo scene, to halo-render.png.\n"
          "\n"
          "Scene and host:\n"
          "  --scene S          scene file (JSON); default: examples/scenes/default.json (built in)\n"
          "  --host H           slice, slab or raycast; default: slice when the scene has\n"
          "                     halo stages, else raycast\n"
          "  --no-halos         switch the halo stages (image passes, images, extra outputs,\n"
          "                     feature_halo) off: the same scene and host without halos\n"
          "  --halo-scale S     halo images at 1/S of the image per side: 1 (default), 2 or 4\n"
          "                     (faster image passes; docs/performance.md)\n"
          "  --gradient-format F  the slice and slab hosts' gradient texture: float (RGB32F),\n"
          "                     half (RGB16F, the default) or snorm8 (RGB8_SNORM, scaled to the\n"
          "                     volume's largest gradient); docs/performance.md\n"
          "  --max-error E      measure a sweep of configurations (slice or slab host, M, N,\n"
          "                     halo image precision and resolution, step) of this scene,\n"
          "                     volume and image against the exact reference and render with\n"
          "                     the cheapest whose largest colour error is <= E (E >= 0). The\n"
          "                     sweep renders about 35 configurations 4 times each: about\n"
          "                     40 s at 64x64 with a\n"
          "                     48^3 volume on llvmpipe, minutes at larger sizes\n"
          "Volume (default: the built-in procedural volume):\n"
          "  --volume FILE      NIfTI volume (.nii, .nii.gz, .hdr/.img), or raw with --raw-dims\n"
          "  --raw-dims XxYxZ   raw file: voxels per axis, x fastest\n"
          "  --raw-type T       raw file: uint8, uint16, int16 or float32 (required with --raw-dims)\n"
          "  --raw-endian E     raw file: little (default) or big\n"
          "  --raw-offset N     raw file: header bytes to skip (default 0)\n"
          "  --raw-spacing XxYxZ  raw file: voxel size per axis (default 1x1x1)\n"
          "  --labels FILE      segmentation (NIfTI, integer label ids) on the grid of --volume\n"
          "                     (same dimensions and orientation), resampled nearest into the\n"
          "                     same cube: the label features of outline_feature (label >= 0)\n"
          "  --window LOW:HIGH  values mapped to [0,1]; default: the scene's render.window,\n"
          "                     else for a file the 1st..99th percentile of its values\n"
          "  --volume-size N    side of the cube the volume is resampled to (8..512); default:\n"
          "                     96 for the built-in volume, a file's own resolution up to 512\n"
          "Camera and image:\n"
          "  --azimuth A        degrees about the vertical axis (default: the scene's)\n"
          "  --elevation E      degrees, -90..90 (default: the scene's)\n"
          "  --zoom Z           1 fits the volume in view, larger is closer (default: the scene's)\n"
          "  --size WxH         image size in pixels, 1..8192 each; default 512x512\n"
          "  -o OUT             .png (8-bit, clamped) or .exr (float); default halo-render.png\n"
          "  --backend B        headless OpenGL: egl, osmesa or auto (default: EGL when it\n"
          "                     has a hardware renderer, else OSMesa)\n"
          "  --quiet            no progress or volume notes on stderr\n"
          "  --help             show this help\n"
          "\n"
          "Exit status: 0 success, 1 the scene, shaders or volume contents have errors,\n"
          "2 usage or I/O failure (bad options, missing or truncated files).\n",
          out);
}

/* ---- Option parsing ---------------------------------------------------------------- */

static int parse_number(const char *option, const char *text, double lo, double hi, double *out)
{
    char *end = NULL;
    errno = 0;
    double x = text ? strtod(text, &end) : NAN;
    if (!text || end == text || *end != '\0' || errno == ERANGE || !isfinite(x)) {
        fprintf(stderr, "halo-render: error: %s: '%s' is not a finite number\n", option, text ? text : "");
        return 0;
    }
    if (x < lo || x > hi) {
        fprintf(stderr, "halo-render: error: %s: %g is outside %g..%g\n", option, x, lo, hi);
        return 0;
    }
    *out = x;
    return 1;
}

static int parse_long(const char *option, const char *text, long lo, long hi, long *out)
{
    char *end = NULL;
    errno = 0;
    long x = text ? strtol(text, &end, 10) : 0;
    if (!text || end == text || *end != '\0' || errno == ERANGE) {
        fprintf(stderr, "halo-render: error: %s: '%s' is not an integer\n", option, text ? text : "");
        return 0;
    }
    if (x < lo || x > hi) {
        fprintf(stderr, "halo-render: error: %s: %ld is outside %ld..%ld\n", option, x, lo, hi);
        return 0;
    }
    *out = x;
    return 1;
}

static int parse_int(const char *option, const char *text, int lo, int hi, int *out)
{
    long x;
    if (!parse_long(option, text, lo, hi, &x))
        return 0;
    *out = (int)x;
    return 1;
}

/* Splits "AsepBsepC" into count parts of at most 63 characters. */
static int split(const char *option, const char *text, char separator, int count, char parts[][64])
{
    const char *p = text ? text : "";
    for (int k = 0; k < count; ++k) {
        const char *end = k + 1 < count ? strchr(p, separator) : p + strlen(p);
        if (!end || end == p || (size_t)(end - p) >= 64) {
            fprintf(stderr, "halo-render: error: %s: '%s' is not %d values separated by '%c'\n", option,
                    text ? text : "", count, separator);
            return 0;
        }
        memcpy(parts[k], p, (size_t)(end - p));
        parts[k][end - p] = '\0';
        p = end + (k + 1 < count);
    }
    return 1;
}

static int parse_size(const char *text, int *width, int *height)
{
    char parts[2][64];
    return split("--size", text, 'x', 2, parts) && parse_int("--size", parts[0], 1, 8192, width) &&
           parse_int("--size", parts[1], 1, 8192, height);
}

typedef enum host_kind { HOST_AUTO = 0, HOST_SLICE, HOST_SLAB, HOST_RAYCAST } host_kind;
static const char *const host_names[] = {"auto", "slice", "slab", "raycast"};

typedef struct options {
    const char *scene_path, *output, *volume_path, *labels_path;
    int width, height, volume_size, have_volume_size;
    int have_azimuth, have_elevation, have_zoom, have_window, no_halos, quiet, have_max_error;
    double azimuth, elevation, zoom, window[2], max_error;
    host_kind host;
    int raw, have_raw_type, have_raw_extra;
    int halo_scale, have_halo_scale;
    halo_gradient_format gradient_format;
    halo_raw_desc raw_desc;
} options;

static const char *const valued_options[] = {
    "--scene", "-o", "--output", "--size", "--azimuth", "--elevation", "--zoom", "--volume-size", "--volume",
    "--raw-dims", "--raw-type", "--raw-endian", "--raw-offset", "--raw-spacing", "--window", "--host", "--max-error",
    "--labels", "--halo-scale", "--gradient-format", NULL};

/* Returns 0 to go on, -1 to exit 0 (help), or an exit status. */
static int parse_options(int argc, char **argv, options *o)
{
    *o = (options){.output = "halo-render.png", .width = 512, .height = 512,
                   .volume_size = HALO_VOLUME_DEFAULT_SIZE};
    for (int i = 1; i < argc; ++i) {
        const char *a = argv[i];
        if (!strcmp(a, "--help") || !strcmp(a, "-h")) {
            usage(stdout);
            return -1;
        }
        if (!strcmp(a, "--no-halos")) {
            o->no_halos = 1;
            continue;
        }
        if (!strcmp(a, "--quiet") || !strcmp(a, "-q")) {
            o->quiet = 1;
            continue;
        }
        int valued = 0;
        for (const char *const *v = valued_options; *v; ++v)
            valued |= !strcmp(a, *v);
        if (!valued) {
            fprintf(stderr, "halo-render: error: unknown argument '%s'\n", a);
            usage(stderr);
            return 2;
        }
        const char *value = i + 1 < argc ? argv[++i] : NULL;
        if (!value) {
            fprintf(stderr, "halo-render: error: %s needs a value\n", a);
            usage(stderr);
            return 2;
        }
        int ok = 1;
        if (!strcmp(a, "--scene"))
            o->scene_path = value;
        else if (!strcmp(a, "-o") || !strcmp(a, "--output"))
            o->output = value;
        else if (!strcmp(a, "--volume"))
            o->volume_path = value;
        else if (!strcmp(a, "--labels"))
            o->labels_path = value;
        else if (!strcmp(a, "--gradient-format")) {
            char err[128];
            ok = halo_gradient_format_option(value, &o->gradient_format, err, sizeof err);
            if (!ok)
                fprintf(stderr, "halo-render: error: %s\n", err);
        } else if (!strcmp(a, "--halo-scale")) {
            ok = o->have_halo_scale = parse_int(a, value, 1, 4, &o->halo_scale);
            if (ok && o->halo_scale == 3) {
                fprintf(stderr, "halo-render: error: --halo-scale: 3 is not 1, 2 or 4\n");
                ok = 0;
            }
        }
        else if (!strcmp(a, "--size"))
            ok = parse_size(value, &o->width, &o->height);
        else if (!strcmp(a, "--azimuth"))
            ok = o->have_azimuth = parse_number(a, value, -3600, 3600, &o->azimuth);
        else if (!strcmp(a, "--elevation"))
            ok = o->have_elevation = parse_number(a, value, -90, 90, &o->elevation);
        else if (!strcmp(a, "--zoom"))
            ok = o->have_zoom = parse_number(a, value, 1e-3, 1e3, &o->zoom);
        else if (!strcmp(a, "--max-error"))
            ok = o->have_max_error = parse_number(a, value, 0, 1e30, &o->max_error);
        else if (!strcmp(a, "--volume-size"))
            ok = o->have_volume_size =
                parse_int(a, value, HALO_VOLUME_MIN_SIZE, HALO_VOLUME_MAX_SIZE, &o->volume_size);
        else if (!strcmp(a, "--window")) {
            char parts[2][64];
            ok = split(a, value, ':', 2, parts) && parse_number(a, parts[0], -1e30, 1e30, &o->window[0]) &&
                 parse_number(a, parts[1], -1e30, 1e30, &o->window[1]);
            if (ok && !(o->window[1] > o->window[0])) {
                fprintf(stderr, "halo-render: error: --window: HIGH %g is not above LOW %g\n", o->window[1],
                        o->window[0]);
                ok = 0;
            }
            o->have_window = ok;
        } else if (!strcmp(a, "--host")) {
            o->host = HOST_AUTO;
            for (int h = HOST_SLICE; h <= HOST_RAYCAST; ++h)
                if (!strcmp(value, host_names[h]))
                    o->host = (host_kind)h;
            if (o->host == HOST_AUTO) {
                fprintf(stderr, "halo-render: error: --host: unknown host '%s' (slice, slab or raycast)\n", value);
                ok = 0;
            }
        } else if (!strcmp(a, "--raw-dims")) {
            char parts[3][64];
            o->raw = 1;
            ok = split(a, value, 'x', 3, parts);
            for (int k = 0; ok && k < 3; ++k)
                ok = parse_long(a, parts[k], 1, LONG_MAX, &o->raw_desc.dims[k]);
        } else if (!strcmp(a, "--raw-type")) {
            o->raw_desc.type = halo_voxel_type_from_name(value);
            o->have_raw_type = 1;
            if (o->raw_desc.type == HALO_VOXEL_TYPE_COUNT) {
                fprintf(stderr, "halo-render: error: --raw-type: unknown type '%s' (uint8, uint16, int16, float32)\n",
                        value);
                ok = 0;
            }
        } else if (!strcmp(a, "--raw-endian")) {
            o->have_raw_extra = 1;
            if (!strcmp(value, "little") || !strcmp(value, "big"))
                o->raw_desc.big_endian = !strcmp(value, "big");
            else {
                fprintf(stderr, "halo-render: error: --raw-endian: '%s' is not little or big\n", value);
                ok = 0;
            }
        } else if (!strcmp(a, "--raw-offset")) {
            long offset;
            o->have_raw_extra = 1;
            ok = parse_long(a, value, 0, LONG_MAX, &offset);
            o->raw_desc.offset = offset;
        } else if (!strcmp(a, "--raw-spacing")) {
            char parts[3][64];
            o->have_raw_extra = 1;
            ok = split(a, value, 'x', 3, parts);
            for (int k = 0; ok && k < 3; ++k)
                ok = parse_number(a, parts[k], 1e-6, 1e6, &o->raw_desc.spacing[k]);
        }
        if (!ok)
            return 2;
    }
    if (!o->output[0]) {
        fprintf(stderr, "halo-render: error: -o: empty file name\n");
        return 2;
    }
    if ((o->have_raw_type || o->have_raw_extra) && !o->raw) {
        fprintf(stderr, "halo-render: error: --raw-type, --raw-endian, --raw-offset and --raw-spacing need --raw-dims\n");
        return 2;
    }
    if (o->raw && !o->have_raw_type) {
        fprintf(stderr, "halo-render: error: --raw-dims needs --raw-type (uint8, uint16, int16 or float32)\n");
        return 2;
    }
    if (o->have_max_error && o->no_halos) {
        fprintf(stderr, "halo-render: error: --max-error chooses how to render the halos: not with --no-halos\n");
        return 2;
    }
    if (o->have_max_error && o->host != HOST_AUTO) {
        fprintf(stderr, "halo-render: error: --max-error chooses the host (slice or slab): not with --host\n");
        return 2;
    }
    if (o->labels_path && !o->volume_path) {
        fprintf(stderr, "halo-render: error: --labels needs --volume FILE (the labels are on that volume's grid)\n");
        return 2;
    }
    if (o->labels_path && o->host == HOST_RAYCAST) {
        fprintf(stderr, "halo-render: error: --labels: the raycast host has no label texture; use slice or slab\n");
        return 2;
    }
    if (o->gradient_format && o->have_max_error) {
        fprintf(stderr, "halo-render: error: --max-error chooses the gradient format: not with --gradient-format\n");
        return 2;
    }
    if (o->have_halo_scale && o->have_max_error) {
        fprintf(stderr, "halo-render: error: --max-error chooses the halo image resolution: not with --halo-scale\n");
        return 2;
    }
    if (o->labels_path && o->have_max_error) {
        fprintf(stderr, "halo-render: error: --max-error sweeps halo scenes without labels: not with --labels\n");
        return 2;
    }
    if (o->raw && !o->volume_path) {
        fprintf(stderr, "halo-render: error: --raw-dims needs --volume FILE\n");
        return 2;
    }
    return 0;
}

/* ---- Progress ---------------------------------------------------------------------- */

static double seconds_now(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

/* While a render runs, a thread prints the elapsed time on stderr once a second has
 * passed (a line rewritten in place on a terminal, a line every 5 s otherwise). */
typedef struct progress {
    pthread_mutex_t lock;
    pthread_cond_t wake;
    pthread_t thread;
    int running, done, printed, tty;
    double start;
    char what[160];
} progress;

static void *progress_main(void *arg)
{
    progress *p = arg;
    pthread_mutex_lock(&p->lock);
    double next = p->start + 1.0;
    while (!p->done) {
        struct timespec until;
        until.tv_sec = (time_t)next;
        until.tv_nsec = (long)((next - (double)until.tv_sec) * 1e9);
        pthread_cond_timedwait(&p->wake, &p->lock, &until); /* the condition uses CLOCK_MONOTONIC */
        if (p->done)
            break;
        double now = seconds_now();
        if (now >= next) {
            fprintf(stderr, p->tty ? "\rhalo-render: %s: %.0f s" : "halo-render: %s: %.0f s\n", p->what,
                    now - p->start);
            fflush(stderr);
            p->printed = 1;
            next = now + (p->tty ? 1.0 : 5.0);
        }
    }
    pthread_mutex_unlock(&p->lock);
    return NULL;
}

static void progress_begin(progress *p, int quiet, const char *what)
{
    memset(p, 0, sizeof *p);
    p->start = seconds_now();
    snprintf(p->what, sizeof p->what, "%s", what);
    if (quiet)
        return;
    p->tty = isatty(fileno(stderr));
    pthread_condattr_t attributes;
    pthread_condattr_init(&attributes);
    pthread_condattr_setclock(&attributes, CLOCK_MONOTONIC);
    pthread_mutex_init(&p->lock, NULL);
    pthread_cond_init(&p->wake, &attributes);
    pthread_condattr_destroy(&attributes);
    p->running = pthread_create(&p->thread, NULL, progress_main, p) == 0;
    if (!p->running) {
        pthread_cond_destroy(&p->wake);
        pthread_mutex_destroy(&p->lock);
    }
}

/* Ends the line and, when the step took more than a second, says how long. */
static void progress_end(progress *p, int quiet, const char *done_text)
{
    double elapsed = seconds_now() - p->start;
    if (p->running) {
        pthread_mutex_lock(&p->lock);
        p->done = 1;
        pthread_cond_signal(&p->wake);
        pthread_mutex_unlock(&p->lock);
        pthread_join(p->thread, NULL);
        pthread_cond_destroy(&p->wake);
        pthread_mutex_destroy(&p->lock);
    }
    if (!quiet && elapsed > 1.0)
        fprintf(stderr, "%shalo-render: %s in %.1f s\n", p->printed && p->tty ? "\r\033[K" : "", done_text, elapsed);
}

/* The slice and slab hosts report each slice (slab) drawn (halo_slice_set_progress):
 * once a render has taken a second, "slice k of n" on stderr, rewritten in place on a
 * terminal (at most 4 times a second), a line every 5 s otherwise. */
typedef struct slice_progress {
    const halo_glfuncs *gl;
    int tty, printed;
    double start, next;
    const char *what, *unit;
} slice_progress;

static void slice_progress_report(int done, int total, void *user)
{
    slice_progress *p = user;
    double now = seconds_now();
    if (now < p->next || done >= total)
        return;
    /* llvmpipe queues draws: flushing keeps the count printed close to what has been
     * drawn. Only when printing: a flush after every slice cost 7 % of a frame, and
     * --quiet (no progress) must time the same frame (docs/halo-render.md). */
    p->gl->Flush();
    fprintf(stderr, p->tty ? "\rhalo-render: %s: %s %d of %d (%.0f s)" : "halo-render: %s: %s %d of %d (%.0f s)\n",
            p->what, p->unit, done, total, now - p->start);
    fflush(stderr);
    p->printed = 1;
    p->next = now + (p->tty ? 0.25 : 5.0);
}

/* ---- Halo stages ----------------------------------------------------------------------- */

/* A host for probing what a stage links to: calls halo_finish, as the slice host does. */
static const char probe_host[] =
    "#version 330 core\n"
    "#pragma halo declarations\n"
    "layout(location = 0) out vec4 frag_color;\n"
    "void main()\n"
    "{\n"
    "    vec4 color = vec4(0.0);\n"
    "#ifdef HALO_LINKED\n"
    "    halo_sample s = halo_make_sample(vec3(0.5), 0.5, vec3(0.0, 0.1, 0.0), vec3(0.0, 0.0, 1.0), 0.5,\n"
    "                                     gl_FragCoord.xy, vec3(1.0), 0.5);\n"
    "    halo_apply(s);\n"
    "    color = vec4(s.color, s.opacity);\n"
    "    halo_finish();\n"
    "#endif\n"
    "    frag_color = color;\n"
    "}\n";

typedef struct link_shape {
    int ok;
    size_t outputs, samplers, passes;
} link_shape;

static link_shape probe_link(const halo_library *lib, const char *const *stages, size_t count)
{
    link_shape shape = {0};
    halo_scene *scene = halo_scene_create(lib);
    int ok = scene != NULL;
    for (size_t i = 0; ok && i < count; ++i)
        ok = halo_scene_enable(scene, stages[i], 1, NULL) == HALO_OK;
    halo_program *p = ok ? halo_link(&(halo_link_desc){.library = lib, .scene = scene, .host_source = probe_host,
                                                       .host_file = "probe"},
                                     NULL)
                         : NULL;
    if (p) {
        shape.ok = 1;
        shape.outputs = halo_program_output_count(p);
        shape.samplers = halo_program_sampler_count(p);
        shape.passes = halo_program_pass_count(p);
    }
    halo_program_destroy(p);
    halo_scene_destroy(scene);
    return shape;
}

/* Marks the scene's halo stages: a stage with hook image, or one that adds extra
 * outputs, images read per sample or image passes to a program. A stage that does
 * not link alone (it needs what a halo stage provides) is judged together with the
 * halo stages found first. Returns the number found. */
static size_t find_halo_stages(const halo_library *lib, const halo_scene *scene, int *is_halo)
{
    size_t n = halo_scene_stage_count(scene), found = 0;
    const char **base = calloc(n + 1, sizeof *base);
    int *pending = calloc(n + 1, sizeof *pending);
    if (!base || !pending) {
        free(base);
        free(pending);
        return 0;
    }
    for (size_t i = 0; i < n; ++i) {
        const char *name = halo_scene_stage(scene, i);
        const halo_module *m = halo_library_find(lib, name);
        is_halo[i] = 0;
        if (m && halo_module_hook(m) == HALO_HOOK_IMAGE) {
            is_halo[i] = 1;
            continue;
        }
        link_shape alone = probe_link(lib, &name, 1);
        if (alone.ok)
            is_halo[i] = alone.outputs || alone.samplers || alone.passes;
        else
            pending[i] = 1;
    }
    size_t base_count = 0;
    for (size_t i = 0; i < n; ++i)
        if (is_halo[i])
            base[base_count++] = halo_scene_stage(scene, i);
    link_shape without = probe_link(lib, base, base_count);
    for (size_t i = 0; i < n; ++i) {
        if (!pending[i] || !without.ok)
            continue;
        base[base_count] = halo_scene_stage(scene, i);
        link_shape with = probe_link(lib, base, base_count + 1);
        is_halo[i] = with.ok && (with.outputs > without.outputs || with.samplers > without.samplers ||
                                 with.passes > without.passes);
    }
    for (size_t i = 0; i < n; ++i)
        found += is_halo[i] != 0;
    free(base);
    free(pending);
    return found;
}

/* ---- Volume --------------------------------------------------------------------------- */

/* Whether the scene text sets render.window (a file volume then uses it as it is). */
static int scene_sets_window(const char *scene_path, const char *scene_text)
{
    json_error_t error;
    json_t *root = scene_path ? halo_json_load_file(scene_path, 0, &error) : json_loads(scene_text, 0, &error);
    json_t *render = root ? json_object_get(root, "render") : NULL;
    int has = render && json_object_get(render, "window") != NULL;
    json_decref(root);
    return has;
}

/* Loads the volume (a file, or the built-in one), windows it to [0,1] and resamples
 * it into a cube. Returns an exit status; *volume_out is the cube. */
/* Whether a feature of outline_feature reads the labels (label >= 0). */
static int has_label_feature(const halo_program *program)
{
    const halo_uniform_info *u = halo_program_find_uniform(program, "outline_feature", "label");
    for (int k = 0; u && u->value && k < u->count; ++k)
        if (u->value[k] >= 0.0)
            return 1;
    return 0;
}

/* The segmentation of --labels, on the grid of the volume file vol: the same cube. */
static int prepare_labels(const options *o, const halo_volume_file *vol, int size, float **labels_out)
{
    halo_volume_file file;
    char err[512];
    halo_volume_status status = halo_volume_read_nifti(o->labels_path, &file, err, sizeof err);
    if (status != HALO_VOLUME_OK) {
        fprintf(stderr, "halo-render: error: --labels: %s\n", err);
        return (int)status;
    }
    int same = 1;
    for (int a = 0; a < 3; ++a)
        same &= file.dims[a] == vol->dims[a] && file.display_axis[a] == vol->display_axis[a] &&
                file.display_flip[a] == vol->display_flip[a] &&
                fabs(file.spacing[a] - vol->spacing[a]) <= 1e-4 * vol->spacing[a];
    if (!same) {
        fprintf(stderr,
                "halo-render: error: --labels: %s (%s) is not on the grid of %s (%s): same dimensions, spacing and "
                "orientation needed (resample it first)\n",
                o->labels_path, file.description, o->volume_path, vol->description);
        halo_volume_file_free(&file);
        return 1;
    }
    if (file.nonfinite) {
        fprintf(stderr, "halo-render: error: --labels: %s: %zu voxels are NaN or infinite: not label ids\n",
                o->labels_path, file.nonfinite);
        halo_volume_file_free(&file);
        return 1;
    }
    *labels_out = halo_volume_labels_to_display(&file, size);
    halo_volume_file_free(&file);
    if (!*labels_out) {
        fprintf(stderr, "halo-render: error: %s: out of memory for a %d^3 label volume\n", o->labels_path, size);
        return 2;
    }
    return 0;
}

static int prepare_volume(const options *o, const halo_render_settings *settings, int scene_window,
                          float **volume_out, float **labels_out, int *size_out)
{
    *volume_out = NULL;
    *labels_out = NULL;
    if (!o->volume_path) {
        float *v = halo_volume_create(o->volume_size);
        if (!v) {
            fprintf(stderr, "halo-render: error: out of memory for the built-in volume\n");
            return 2;
        }
        /* The built-in volume's values are in [0,1]: window only when asked to. */
        double lo = o->have_window ? o->window[0] : settings->window[0];
        double hi = o->have_window ? o->window[1] : settings->window[1];
        if (lo != 0.0 || hi != 1.0) {
            size_t n = (size_t)o->volume_size * (size_t)o->volume_size * (size_t)o->volume_size;
            for (size_t i = 0; i < n; ++i) {
                double x = (v[i] - lo) / (hi - lo);
                v[i] = (float)(x < 0.0 ? 0.0 : x > 1.0 ? 1.0 : x);
            }
        }
        *volume_out = v;
        *size_out = o->volume_size;
        return 0;
    }

    halo_volume_file file;
    char err[512];
    progress step;
    progress_begin(&step, o->quiet, "reading the volume");
    halo_volume_status status = o->raw ? halo_volume_read_raw(o->volume_path, &o->raw_desc, &file, err, sizeof err)
                                       : halo_volume_read_nifti(o->volume_path, &file, err, sizeof err);
    progress_end(&step, o->quiet, "read the volume");
    if (status != HALO_VOLUME_OK) {
        fprintf(stderr, "halo-render: error: %s\n", err);
        return (int)status;
    }
    if (file.nonfinite)
        fprintf(stderr, "halo-render: warning: %s: %zu voxel%s NaN or infinite: rendered as the smallest finite value\n",
                o->volume_path, file.nonfinite, file.nonfinite == 1 ? " is" : "s are");
    if (file.discarded_volumes)
        fprintf(stderr, "halo-render: warning: %s: 4-D file: rendering its first volume, %d more ignored\n",
                o->volume_path, file.discarded_volumes);
    double window[2];
    const char *window_from;
    if (o->have_window) {
        window[0] = o->window[0];
        window[1] = o->window[1];
        window_from = "--window";
    } else if (scene_window) {
        window[0] = settings->window[0];
        window[1] = settings->window[1];
        window_from = "the scene's render.window";
    } else {
        halo_volume_percentile_window(&file, WINDOW_LOW_PERCENT, WINDOW_HIGH_PERCENT, window);
        window_from = "1st..99th percentile";
    }
    int size = o->have_volume_size ? o->volume_size : halo_volume_display_size(&file, HALO_VOLUME_MAX_SIZE);
    if (halo_volume_display_check(&file, size, err, sizeof err) != HALO_VOLUME_OK) {
        fprintf(stderr, "halo-render: error: %s: %s\n", o->volume_path, err);
        halo_volume_file_free(&file);
        return HALO_VOLUME_INVALID;
    }
    if (!o->quiet)
        fprintf(stderr, "halo-render: %s: %s; window %g:%g (%s); resampled to %d^3\n", o->volume_path,
                file.description, window[0], window[1], window_from, size);
    progress_begin(&step, o->quiet, "resampling the volume");
    float *cube = halo_volume_to_display(&file, window, size);
    progress_end(&step, o->quiet, "resampled the volume");
    if (cube && o->labels_path) {
        int labelled = prepare_labels(o, &file, size, labels_out);
        if (labelled) {
            halo_volume_file_free(&file);
            free(cube);
            return labelled;
        }
    }
    halo_volume_file_free(&file);
    if (!cube) {
        fprintf(stderr, "halo-render: error: %s: out of memory for a %d^3 volume\n", o->volume_path, size);
        return 2;
    }
    *volume_out = cube;
    *size_out = size;
    return 0;
}

/* ---- Main ----------------------------------------------------------------------------- */

/* Diagnostics decide the exit status: an input error is 1, I/O or memory 2. */
static int failure_status(const halo_diagnostics *d)
{
    if (halo_diagnostics_has(d, HALO_MSG_IO_READ) || halo_diagnostics_has(d, HALO_MSG_IO_WRITE) ||
        halo_diagnostics_has(d, HALO_MSG_OUT_OF_MEMORY))
        return 2;
    return 1;
}

/* The hosts behind one interface: the slab caster shares the slice host's object. */
typedef struct render_host {
    host_kind kind;
    halo_raycast *raycast;
    halo_slice *slice;
} render_host;

static int host_create(render_host *h, host_kind kind, const halo_host_desc *desc, halo_diagnostics *diag)
{
    h->kind = kind;
    if (kind == HOST_RAYCAST)
        h->raycast = halo_raycast_create(desc, diag);
    else if (kind == HOST_SLAB)
        h->slice = halo_slab_create(desc, diag);
    else
        h->slice = halo_slice_create(desc, diag);
    return h->raycast || h->slice;
}

static void host_destroy(render_host *h)
{
    halo_raycast_destroy(h->raycast);
    halo_slice_destroy(h->slice);
}

static const char *host_fragment(host_kind kind)
{
    return kind == HOST_RAYCAST ? "raycast.frag" : kind == HOST_SLAB ? "slab.frag" : "slice.frag";
}

static int has_stage(const halo_scene *scene, const char *name)
{
    for (size_t i = 0; i < halo_scene_stage_count(scene); ++i)
        if (!strcmp(halo_scene_stage(scene, i), name))
            return 1;
    return 0;
}

/* Switches off the scene's halo stages (is_halo) and feature_halo. Returns 0 on failure. */
static int disable_halo_stages(halo_scene *scene, const int *is_halo, halo_diagnostics *diag)
{
    /* Collect the names first: disabling changes the scene's stage list. */
    size_t n = halo_scene_stage_count(scene), count = 0;
    char **names = calloc(n + 1, sizeof *names);
    int ok = names != NULL;
    for (size_t i = 0; ok && i < n; ++i)
        if (is_halo[i] || !strcmp(halo_scene_stage(scene, i), FEATURE_STAGE))
            ok = (names[count++] = strdup(halo_scene_stage(scene, i))) != NULL;
    for (size_t i = 0; ok && i < count; ++i)
        ok = halo_scene_enable(scene, names[i], 0, diag) == HALO_OK;
    for (size_t i = 0; names && i < count; ++i)
        free(names[i]);
    free(names);
    return ok;
}

/* ---- --max-error ------------------------------------------------------------------------ */

/* The scene text the sweep renders: the scene with the camera options written into its
 * render object (the sweep reads the camera from the scene). NULL: out of memory or
 * an unreadable scene (diagnosed by the scene loader before). */
static char *budget_scene_text(const options *o, const char *scene_text)
{
    json_error_t error;
    json_t *root = o->scene_path ? halo_json_load_file(o->scene_path, 0, &error) : json_loads(scene_text, 0, &error);
    if (!root || !json_is_object(root)) {
        json_decref(root);
        return NULL;
    }
    json_t *render = json_object_get(root, "render");
    if (!json_is_object(render)) {
        render = json_object();
        json_object_set_new(root, "render", render);
    }
    if (o->have_azimuth)
        json_object_set_new(render, "azimuth", json_real(o->azimuth));
    if (o->have_elevation)
        json_object_set_new(render, "elevation", json_real(o->elevation));
    if (o->have_zoom)
        json_object_set_new(render, "zoom", json_real(o->zoom));
    char *text = json_dumps(root, 0);
    json_decref(root);
    return text;
}

/* Runs the error budget (validate/bench_budget.c) on the scene, volume and image size
 * and applies its choice to the scene (N, step) and to *kind, *precision, *scale,
 * *interval, *gradient.
 * Returns an exit status. */
static int apply_budget(const options *o, const char *scene_text, halo_library *lib, halo_gl *runtime,
                        const float *volume, int size, int scene_passes, halo_scene *scene, host_kind *kind,
                        int *precision, int *scale, int *interval, halo_gradient_format *gradient,
                        halo_diagnostics *diag)
{
    char *text = budget_scene_text(o, scene_text);
    if (!text) {
        fprintf(stderr, "halo-render: error: --max-error: cannot prepare the scene for the sweep\n");
        return 2;
    }
    halo_bench_env env = {.lib = lib, .runtime = runtime, .gl = halo_gl_functions(runtime), .diag = diag,
                          .width = o->width, .height = o->height, .volume = volume, .dims = {size, size, size},
                          .repeat = 3, .scene_text = text, .progress = o->quiet ? NULL : stderr};
    char *report_text = NULL;
    size_t report_size = 0;
    FILE *report = open_memstream(&report_text, &report_size);
    halo_bench_config choice;
    double start = seconds_now();
    if (!o->quiet)
        fprintf(stderr, "halo-render: --max-error %g: measuring the configurations at %dx%d...\n", o->max_error,
                o->width, o->height);
    halo_status st = halo_bench_budget(&env, scene_passes, o->max_error, &choice, report);
    double elapsed = seconds_now() - start;
    if (report)
        fclose(report);
    free(text);
    /* "budget: max error E: slice, M = ..., (verified: within); the exact reference ..." */
    char *line = report_text;
    size_t length = line ? strcspn(line, "\n") : 0;
    if (line && length)
        printf("halo-render: %.*s (sweep %.1f s)\n", (int)length, line, elapsed);
    free(report_text);
    if (st != HALO_OK) {
        if (st == HALO_ERROR_INPUT && line && length)
            fprintf(stderr, "halo-render: error: --max-error %g: the cheapest configuration is not within it when "
                            "measured again\n", o->max_error);
        return st == HALO_ERROR_INPUT ? 1 : 2;
    }
    if (has_stage(scene, "halo_generate") && choice.passes > 0) {
        double passes = choice.passes;
        if (halo_scene_set(scene, "halo_generate", "passes", &passes, 1, 0, diag) != HALO_OK)
            return 1;
    }
    if (choice.step > 0.0)
        halo_scene_render_mutable(scene)->step = choice.step;
    *kind = choice.slab ? HOST_SLAB : HOST_SLICE;
    *precision = choice.precision;
    *scale = choice.scale;
    *interval = choice.interval;
    if (choice.gradient)
        *gradient = (halo_gradient_format)choice.gradient;
    return 0;
}

/* ---- Feature halos ------------------------------------------------------------------------ */

/* Builds the feature_halo stage's halo buffer for the host's current view (from the
 * volume's centre towards the eye) and binds it to the stage's sampler. Call again
 * after every camera change. Returns 0 on failure (diagnostics in diag). */
static int feature_update(halo_feature_buffer **buffer, halo_gl *runtime, const halo_program *program,
                          const render_host *host, const float *volume, int size, int quiet, halo_diagnostics *diag)
{
    const halo_glfuncs *f = halo_gl_functions(runtime);
    double start = seconds_now();
    if (!*buffer) {
        halo_feature_desc fd;
        if (halo_feature_desc_from_program(program, &fd) != HALO_OK)
            return 0;
        const int dims[3] = {size, size, size};
        *buffer = halo_feature_buffer_create(runtime, volume, dims, &fd, diag);
        if (!*buffer)
            return 0;
    }
    double eye[3];
    unsigned gl_program;
    if (host->raycast) {
        halo_raycast_state state;
        halo_raycast_get_state(host->raycast, &state);
        memcpy(eye, state.eye, sizeof eye);
        gl_program = halo_raycast_gl_program(host->raycast);
    } else {
        halo_slice_state state;
        halo_slice_get_state(host->slice, &state);
        memcpy(eye, state.eye, sizeof eye);
        gl_program = halo_slice_gl_program(host->slice);
    }
    /* texture space = voxel space up to the scale for the cube the hosts render */
    double view[3] = {eye[0] - 0.5, eye[1] - 0.5, eye[2] - 0.5};
    double length = sqrt(view[0] * view[0] + view[1] * view[1] + view[2] * view[2]);
    for (int k = 0; k < 3 && length > 0.0; ++k)
        view[k] /= length;
    if (halo_feature_buffer_build(*buffer, view) != HALO_OK) {
        fprintf(stderr, "halo-render: error: building the feature halo buffer failed\n");
        return 0;
    }
    f->UseProgram(gl_program);
    f->Uniform1i(f->GetUniformLocation(gl_program, "halo_host_feature_buffer"), FEATURE_BUFFER_UNIT);
    f->UseProgram(0);
    f->ActiveTexture(GL_TEXTURE0 + FEATURE_BUFFER_UNIT);
    f->BindTexture(GL_TEXTURE_3D, halo_feature_buffer_texture(*buffer));
    f->ActiveTexture(GL_TEXTURE0);
    f->Finish();
    if (!quiet)
        fprintf(stderr, "halo-render: feature halo buffer: %zu qualified voxels, built in %.2f s\n",
                halo_feature_buffer_qualified(*buffer), seconds_now() - start);
    return 1;
}

/* ---- Post passes ------------------------------------------------------------------------------ */


/* Runs the post passes on the host's image (rgba, over its background) and replaces rgba
 * with their result. Returns 0 on failure. */
static int run_post_passes(halo_gl *runtime, halo_gl_frame *frame, const halo_program *program, int width,
                           int height, float *rgba, halo_diagnostics *diag)
{
    const halo_glfuncs *f = halo_gl_functions(runtime);
    unsigned texture = 0;
    f->GenTextures(1, &texture);
    halo_host_image_texture(f, texture, GL_RGBA32F, width, height, GL_RGBA, GL_FLOAT);
    f->TexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, width, height, GL_RGBA, GL_FLOAT, rgba);
    f->BindTexture(GL_TEXTURE_2D, 0);
    halo_status status = halo_host_post_passes(frame, program, texture, width, height, rgba, diag);
    f->DeleteTextures(1, &texture);
    if (status != HALO_OK || f->GetError() != GL_NO_ERROR) {
        halo_diagnostics_print(diag, stderr);
        fprintf(stderr, "halo-render: error: the post passes failed\n");
        return 0;
    }
    return 1;
}

/* ---- Main ----------------------------------------------------------------------------- */

int main(int argc, char **argv)
{
    options o;
    if (!halo_headless_take_backend_option(&argc, argv, "halo-render"))
        return 2;
    int status = parse_options(argc, argv, &o);
    if (status)
        return status < 0 ? 0 : status;

    halo_diagnostics *diag = halo_diagnostics_create();
    if (!diag || halo_setup(NULL) != HALO_OK) {
        fprintf(stderr, "halo-render: error: cannot initialize libhalo\n");
        halo_diagnostics_destroy(diag);
        return 2;
    }
    halo_library *lib = NULL;
    halo_scene *scene = NULL;
    halo_program *program = NULL;
    halo_headless *context = NULL;
    halo_gl *runtime = NULL;
    halo_feature_buffer *feature_buffer = NULL;
    render_host host = {0};
    float *volume = NULL, *labels = NULL, *image = NULL;
    char *host_source = NULL;
    int *is_halo = NULL;
    const char *scene_text = NULL;
    status = 1;

    lib = halo_library_create(diag);
    if (!lib)
        goto done;
    if (!o.scene_path) {
        scene_text = embedded_scene(DEFAULT_SCENE);
        if (!scene_text) {
            fprintf(stderr, "halo-render: error: %s is not embedded\n", DEFAULT_SCENE);
            status = 2;
            goto done;
        }
    }
    scene = o.scene_path ? halo_scene_load(o.scene_path, lib, diag)
                         : halo_scene_parse(scene_text, DEFAULT_SCENE " (built in)", lib, diag);
    if (!scene)
        goto done;

    /* The halo stages decide the default host; --no-halos keeps that host. Feature
     * halos (a halo buffer read per sample) go with any host: the ray caster by default. */
    size_t stage_count = halo_scene_stage_count(scene);
    is_halo = calloc(stage_count + 1, sizeof *is_halo);
    if (!is_halo) {
        status = 2;
        goto done;
    }
    size_t halo_stages = find_halo_stages(lib, scene, is_halo);
    for (size_t i = 0; i < stage_count; ++i)
        if (is_halo[i] && !strcmp(halo_scene_stage(scene, i), FEATURE_STAGE)) {
            is_halo[i] = 0;
            --halo_stages;
        }
    int feature = has_stage(scene, FEATURE_STAGE);
    host_kind kind = o.host != HOST_AUTO ? o.host : halo_stages ? HOST_SLICE : HOST_RAYCAST;
    if (o.have_max_error && feature) {
        fprintf(stderr, "halo-render: error: --max-error: the sweep cannot render feature_halo (no halo buffer); "
                        "render this scene without --max-error\n");
        status = 2;
        goto done;
    }
    if (o.no_halos) {
        if (!disable_halo_stages(scene, is_halo, diag)) {
            status = 2;
            goto done;
        }
        if (!halo_stages && !feature && !o.quiet)
            fprintf(stderr, "halo-render: note: --no-halos: the scene has no halo stages\n");
        feature = 0;
    }

    host_source = halo_host_load(host_fragment(kind), NULL, diag);
    if (!host_source)
        goto done;
    program = halo_link(&(halo_link_desc){.library = lib, .scene = scene, .host_source = host_source,
                                          .host_file = host_fragment(kind), .image_scale = o.halo_scale},
                        diag);
    if (!program || halo_program_validate(program, diag) != HALO_OK)
        goto done;

    const halo_render_settings *settings = halo_scene_render(scene);
    int size = 0;
    status = prepare_volume(&o, settings, scene_sets_window(o.scene_path, scene_text), &volume, &labels, &size);
    if (status)
        goto done;
    status = 1;

    char err[512];
    context = halo_headless_create(o.width, o.height, err, sizeof err);
    if (!context) {
        fprintf(stderr, "halo-render: error: %s\n", err);
        status = 2;
        goto done;
    }
    runtime = halo_gl_create(&(halo_gl_desc){.get_proc_address = halo_headless_get_proc_address}, diag);
    if (!runtime) {
        status = 2;
        goto done;
    }
    int interval = 0;
    if (o.have_max_error) {
        /* the scene's N heads the sweep */
        const halo_uniform_info *u = halo_program_find_uniform(program, "halo_generate", "passes");
        int scene_passes = u && u->value ? (int)u->value[0] : 0;
        int precision = 32, scale = 1;
        status = apply_budget(&o, scene_text, lib, runtime, volume, size, scene_passes, scene, &kind, &precision,
                              &scale, &interval, &o.gradient_format, diag);
        if (status)
            goto done;
        status = 1;
        /* the program again, for the chosen host, N and precision */
        halo_program_destroy(program);
        free(host_source);
        program = NULL;
        host_source = halo_host_load(host_fragment(kind), NULL, diag);
        if (!host_source)
            goto done;
        program = halo_link(&(halo_link_desc){.library = lib, .scene = scene, .host_source = host_source,
                                              .host_file = host_fragment(kind), .image_precision = precision,
                                              .image_scale = scale},
                            diag);
        if (!program || halo_program_validate(program, diag) != HALO_OK)
            goto done;
        settings = halo_scene_render(scene);
    }
    const halo_host_desc desc = {.gl = halo_gl_functions(runtime), .runtime = runtime, .program = program,
                                 .width = o.width, .height = o.height};
    if (!host_create(&host, kind, &desc, diag))
        goto done;
    image = malloc((size_t)o.width * (size_t)o.height * 4 * sizeof *image);
    if (!image) {
        fprintf(stderr, "halo-render: error: out of memory for a %dx%d image\n", o.width, o.height);
        status = 2;
        goto done;
    }
    double azimuth = o.have_azimuth ? o.azimuth : settings->azimuth;
    double elevation = o.have_elevation ? o.elevation : settings->elevation;
    double zoom = o.have_zoom ? o.zoom : settings->zoom;
    halo_status rendered;
    char what[160];
    snprintf(what, sizeof what, "rendering %dx%d with the %s host", o.width, o.height, host_names[kind]);
    progress step;
    slice_progress sp = {.gl = halo_gl_functions(runtime), .tty = isatty(fileno(stderr)), .what = what,
                         .unit = kind == HOST_SLAB ? "slab" : "slice"};
    if (host.raycast) {
        if (halo_raycast_set_volume(host.raycast, volume, size, size, size, diag) != HALO_OK ||
            halo_raycast_set_render(host.raycast, settings, diag) != HALO_OK) {
            status = 2;
            goto done;
        }
        halo_raycast_set_camera(host.raycast, azimuth, elevation, zoom);
    } else {
        halo_slice_set_gradient_format(host.slice, o.gradient_format);
        if (halo_slice_set_volume(host.slice, volume, size, size, size, diag) != HALO_OK ||
            halo_slice_set_render(host.slice, settings, diag) != HALO_OK) {
            status = 2;
            goto done;
        }
        halo_slice_set_camera(host.slice, azimuth, elevation, zoom);
        halo_slice_set_interval(host.slice, interval);
        if (!o.quiet && halo_slice_reads_gradients(host.slice))
            fprintf(stderr, "halo-render: gradient texture: %s\n",
                    halo_gradient_format_name(halo_slice_gradient_format(host.slice)));
        if (!labels && has_label_feature(program))
            fprintf(stderr, "halo-render: warning: the scene's label features (outline_feature label >= 0) need "
                            "--labels FILE: without it they are empty\n");
        if (labels) {
            if (!has_label_feature(program) && !o.quiet)
                fprintf(stderr, "halo-render: note: --labels: the scene has no label feature (outline_feature label)\n");
            if (halo_slice_set_labels(host.slice, labels, size, size, size, diag) != HALO_OK) {
                status = 2;
                goto done;
            }
        }
    }
    /* the feature halo buffer, for this view (rebuilt after every camera change) */
    if (feature &&
        !feature_update(&feature_buffer, runtime, program, &host, volume, size, o.quiet, diag))
        goto done;
    /* the hosts have the volume in textures and the feature buffer has its own copy:
     * nothing reads the float copy any more (4 bytes a voxel) */
    free(volume);
    volume = NULL;
    if (host.raycast) {
        progress_begin(&step, o.quiet, what);
        rendered = halo_raycast_render(host.raycast, image, diag);
    } else {
        /* progress per slice (slab) from the host; no timer thread */
        progress_begin(&step, 1, what);
        sp.start = step.start;
        sp.next = sp.start + 1.0;
        if (!o.quiet)
            halo_slice_set_progress(host.slice, slice_progress_report, &sp);
        rendered = halo_slice_render(host.slice, image, diag);
        step.printed = sp.printed;
        step.tty = sp.tty;
    }
    /* the ray caster runs the post passes itself */
    halo_gl_frame *frame = host.slice ? halo_slice_frame(host.slice) : halo_raycast_frame(host.raycast);
    const halo_image_info *post = frame ? halo_host_post_image(program) : NULL;
    if (rendered == HALO_OK && post && host.slice &&
        !run_post_passes(runtime, frame, program, o.width, o.height, image, diag)) {
        status = 2;
        goto done;
    }
    if (host.slice)
        snprintf(what, sizeof what, "rendered %ld %s and %ld image passes%s", halo_slice_draws(host.slice),
                 kind == HOST_SLAB ? "slabs" : "slices", halo_slice_pass_draws(host.slice),
                 post ? " (and the post passes)" : "");
    else if (frame)
        snprintf(what, sizeof what, "rendered %d segment%s and %ld image passes%s", halo_gl_frame_segment_count(frame),
                 halo_gl_frame_segment_count(frame) == 1 ? "" : "s", halo_gl_frame_pass_draws(frame),
                 post ? " (and the post passes)" : "");
    else
        snprintf(what, sizeof what, "rendered");
    progress_end(&step, o.quiet || rendered != HALO_OK, what);
    if (rendered != HALO_OK) {
        status = 2;
        goto done;
    }
    if (halo_image_write(o.output, o.width, o.height, image, err, sizeof err) != 0) {
        fprintf(stderr, "halo-render: error: %s\n", err);
        status = 2;
        goto done;
    }
    size_t stages = halo_program_stage_count(program);
    printf("halo-render: wrote %s (%dx%d, %s host, %zu stage%s%s", o.output, o.width, o.height, host_names[kind],
           stages, stages == 1 ? "" : "s", stages ? ": " : "");
    for (size_t i = 0; i < stages; ++i)
        printf("%s%s", i ? ", " : "", halo_program_stage(program, i));
    if (post)
        printf("; image %s of the post passes", post->name);
    printf(")\n");
    status = 0;

done:
    if (status != 0 && halo_diagnostics_count(diag) > 0) {
        halo_diagnostics_print(diag, stderr);
        if (status == 1)
            status = failure_status(diag);
    } else if (status == 0 && halo_diagnostics_count(diag) > 0) {
        halo_diagnostics_print(diag, stderr); /* warnings */
    }
    halo_feature_buffer_destroy(feature_buffer);
    host_destroy(&host);
    halo_gl_destroy(runtime);
    halo_headless_destroy(context);
    halo_program_destroy(program);
    halo_scene_destroy(scene);
    halo_library_destroy(lib);
    free(host_source);
    free(is_halo);
    free(volume);
    free(labels);
    free(image);
    halo_diagnostics_destroy(diag);
    halo_shutdown();
    return status;
}
