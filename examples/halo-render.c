/* halo-render: renders a volume with the example GPU ray caster and a libhalo scene,
 * offline (headless OpenGL), to a PNG or EXR image.
 *
 *   halo-render [--scene S] [-o OUT] [--size WxH] [--azimuth A] [--elevation E]
 *               [--zoom Z] [--volume-size N] [--help]
 *
 * With no arguments: the built-in procedural volume, the built-in default scene,
 * halo-render.png in the current directory. Exit status: 0 success, 1 the input has
 * errors (diagnostics on stderr), 2 usage or I/O failure. */
#include "halo.h"
#include "gl/glfuncs.h"
#include "gl/headless.h"
#include "hosts/raycast.h"
#include "image_write.h"
#include "volume.h"

#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* The default scene: gradient-dependent enhancements strong enough to see at a
 * glance on the built-in volume (|grad f| there is about 0.05-0.3 per voxel). */
static const char default_scene[] =
    "{\n"
    "  \"halo_scene\": 1,\n"
    "  \"description\": \"halo-render's built-in scene: boundary and silhouette enhancement, tone shading,"
    " distance colour blending\",\n"
    "  \"stages\": [\n"
    "    {\"boundary\": {\"k_gc\": 0.4, \"k_gs\": 12, \"k_ge\": 1}},\n"
    "    {\"silhouette\": {\"k_sc\": 0.5, \"k_ss\": 3, \"k_se\": 2}},\n"
    "    {\"tone_shading\": {\"k_ty\": 0.35, \"k_tb\": 0.45, \"k_ta\": 0.6, \"k_td\": 0.5,"
    " \"lights\": [[-0.4, 0.7, 0.6]]}},\n"
    "    {\"distance_blend\": {\"background\": [0.05, 0.08, 0.25], \"k_ds\": 0.9, \"k_de\": 1.5}}\n"
    "  ],\n"
    "  \"render\": {\n"
    "    \"azimuth\": 35, \"elevation\": 25, \"zoom\": 1.5, \"step\": 0.5,\n"
    "    \"background\": [0.05, 0.08, 0.25],\n"
    "    \"transfer\": [[0, 0, 0, 0, 0], [0.18, 0.6, 0.8, 1, 0], [0.3, 0.6, 0.8, 1, 0.06],\n"
    "                   [0.42, 1, 0.85, 0.55, 0.02], [0.5, 1, 0.85, 0.55, 0.25], [0.62, 0.9, 0.35, 0.25, 0.05],\n"
    "                   [0.75, 0.95, 0.3, 0.2, 0.7], [0.9, 1, 0.95, 0.7, 0.8], [1, 1, 1, 0.8, 0.9]]\n"
    "  }\n"
    "}\n";

static void usage(FILE *out)
{
    fputs("Usage: halo-render [--scene S] [-o OUT] [--size WxH] [--azimuth A] [--elevation E]\n"
          "                   [--zoom Z] [--volume-size N] [--help]\n"
          "Renders the built-in procedural volume with libhalo's example GPU ray caster\n"
          "(OSMesa, headless) and writes an image.\n"
          "\n"
          "  --scene S        scene file (JSON); default: a built-in scene with boundary and\n"
          "                   silhouette enhancement, tone shading and distance blending\n"
          "  -o OUT           output image, .png (8-bit, values clamped) or .exr (float);\n"
          "                   default halo-render.png\n"
          "  --size WxH       image size in pixels, 1..8192 each; default 512x512\n"
          "  --azimuth A      camera azimuth in degrees (default: the scene's)\n"
          "  --elevation E    camera elevation in degrees, -90..90 (default: the scene's)\n"
          "  --zoom Z         1 fits the volume in view, larger is closer, > 0 (default: the scene's)\n"
          "  --volume-size N  size of the built-in volume, 8..512 voxels per side; default 96\n"
          "  --help           show this help\n"
          "\n"
          "Exit status: 0 success, 1 the scene or shaders have errors, 2 usage or I/O failure.\n",
          out);
}

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

static int parse_int(const char *option, const char *text, long lo, long hi, int *out)
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
    *out = (int)x;
    return 1;
}

static int parse_size(const char *text, int *width, int *height)
{
    const char *x = text ? strchr(text, 'x') : NULL;
    if (!x) {
        fprintf(stderr, "halo-render: error: --size: '%s' is not WIDTHxHEIGHT\n", text ? text : "");
        return 0;
    }
    char first[32];
    size_t n = (size_t)(x - text);
    if (n == 0 || n >= sizeof first) {
        fprintf(stderr, "halo-render: error: --size: '%s' is not WIDTHxHEIGHT\n", text);
        return 0;
    }
    memcpy(first, text, n);
    first[n] = '\0';
    return parse_int("--size", first, 1, 8192, width) && parse_int("--size", x + 1, 1, 8192, height);
}

typedef struct options {
    const char *scene_path, *output;
    int width, height, volume_size;
    int have_azimuth, have_elevation, have_zoom;
    double azimuth, elevation, zoom;
} options;

/* Returns 0 to go on, or an exit status. */
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
        const char *value = i + 1 < argc ? argv[i + 1] : NULL;
        int ok = 1;
        if (!strcmp(a, "--scene") || !strcmp(a, "-o") || !strcmp(a, "--output") || !strcmp(a, "--size") ||
            !strcmp(a, "--azimuth") || !strcmp(a, "--elevation") || !strcmp(a, "--zoom") ||
            !strcmp(a, "--volume-size")) {
            if (!value) {
                fprintf(stderr, "halo-render: error: %s needs a value\n", a);
                usage(stderr);
                return 2;
            }
            ++i;
        } else {
            fprintf(stderr, "halo-render: error: unknown argument '%s'\n", a);
            usage(stderr);
            return 2;
        }
        if (!strcmp(a, "--scene"))
            o->scene_path = value;
        else if (!strcmp(a, "-o") || !strcmp(a, "--output"))
            o->output = value;
        else if (!strcmp(a, "--size"))
            ok = parse_size(value, &o->width, &o->height);
        else if (!strcmp(a, "--azimuth"))
            ok = o->have_azimuth = parse_number(a, value, -3600, 3600, &o->azimuth);
        else if (!strcmp(a, "--elevation"))
            ok = o->have_elevation = parse_number(a, value, -90, 90, &o->elevation);
        else if (!strcmp(a, "--zoom")) {
            ok = o->have_zoom = parse_number(a, value, 1e-3, 1e3, &o->zoom);
            if (ok && o->zoom <= 0.0)
                ok = 0;
        } else if (!strcmp(a, "--volume-size"))
            ok = parse_int(a, value, HALO_VOLUME_MIN_SIZE, HALO_VOLUME_MAX_SIZE, &o->volume_size);
        if (!ok)
            return 2;
    }
    if (!o->output[0]) {
        fprintf(stderr, "halo-render: error: -o: empty file name\n");
        return 2;
    }
    return 0;
}

/* Diagnostics decide the exit status: an input error is 1, I/O or memory 2. */
static int failure_status(const halo_diagnostics *d)
{
    if (halo_diagnostics_has(d, HALO_MSG_IO_READ) || halo_diagnostics_has(d, HALO_MSG_IO_WRITE) ||
        halo_diagnostics_has(d, HALO_MSG_OUT_OF_MEMORY))
        return 2;
    return 1;
}

int main(int argc, char **argv)
{
    options o;
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
    halo_raycast *raycast = NULL;
    float *volume = NULL, *image = NULL;
    char *host = NULL;
    status = 1;

    lib = halo_library_create(diag);
    if (!lib)
        goto done;
    scene = o.scene_path ? halo_scene_load(o.scene_path, lib, diag)
                         : halo_scene_parse(default_scene, "(built-in scene)", lib, diag);
    if (!scene)
        goto done;
    host = halo_host_load("raycast.frag", NULL, diag);
    if (!host)
        goto done;
    program = halo_link(&(halo_link_desc){.library = lib, .scene = scene, .host_source = host,
                                          .host_file = "raycast.frag"},
                        diag);
    if (!program || halo_program_validate(program, diag) != HALO_OK)
        goto done;

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
    const halo_glfuncs *gl = halo_gl_functions(runtime);
    raycast = halo_raycast_create(&(halo_host_desc){.gl = gl, .runtime = runtime, .program = program,
                                                   .width = o.width, .height = o.height},
                                  diag);
    if (!raycast)
        goto done;

    const halo_render_settings *settings = halo_scene_render(scene);
    volume = halo_volume_create(o.volume_size);
    image = malloc((size_t)o.width * (size_t)o.height * 4 * sizeof *image);
    if (!volume || !image) {
        fprintf(stderr, "halo-render: error: out of memory\n");
        status = 2;
        goto done;
    }
    /* The intensity window maps the scene's value range to [0,1]. */
    double lo = settings->window[0], hi = settings->window[1];
    if (hi > lo && (lo != 0.0 || hi != 1.0)) {
        size_t n = (size_t)o.volume_size * (size_t)o.volume_size * (size_t)o.volume_size;
        for (size_t i = 0; i < n; ++i) {
            double v = (volume[i] - lo) / (hi - lo);
            volume[i] = (float)(v < 0.0 ? 0.0 : v > 1.0 ? 1.0 : v);
        }
    }
    if (halo_raycast_set_volume(raycast, volume, o.volume_size, o.volume_size, o.volume_size, diag) != HALO_OK ||
        halo_raycast_set_render(raycast, settings, diag) != HALO_OK) {
        status = 2;
        goto done;
    }
    halo_raycast_set_camera(raycast, o.have_azimuth ? o.azimuth : settings->azimuth,
                            o.have_elevation ? o.elevation : settings->elevation,
                            o.have_zoom ? o.zoom : settings->zoom);
    if (halo_raycast_render(raycast, image, diag) != HALO_OK) {
        status = 2;
        goto done;
    }
    if (halo_image_write(o.output, o.width, o.height, image, err, sizeof err) != 0) {
        fprintf(stderr, "halo-render: error: %s\n", err);
        status = 2;
        goto done;
    }
    size_t stages = halo_program_stage_count(program);
    printf("halo-render: wrote %s (%dx%d, %zu stage%s%s", o.output, o.width, o.height, stages,
           stages == 1 ? "" : "s", stages ? ": " : "");
    for (size_t i = 0; i < stages; ++i)
        printf("%s%s", i ? ", " : "", halo_program_stage(program, i));
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
    halo_raycast_destroy(raycast);
    halo_gl_destroy(runtime);
    halo_headless_destroy(context);
    halo_program_destroy(program);
    halo_scene_destroy(scene);
    halo_library_destroy(lib);
    free(host);
    free(volume);
    free(image);
    halo_diagnostics_destroy(diag);
    halo_shutdown();
    return status;
}
