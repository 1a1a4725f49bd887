/* halo-render: renders a volume with a libhalo scene through one of the example GPU
 * hosts (slices, slab ray caster, ray caster), offline (headless OpenGL), to a PNG
 * or EXR image. The manual is docs/halo-render.md and halo-render(1). The rendering
 * is examples/render_driver.c; this file has the options, the volume file and the
 * output.
 *
 * With no arguments: the built-in procedural volume, the default scene
 * (examples/scenes/default.json, embedded at build time), halo-render.png in the
 * current directory. Exit status: 0 success, 1 the input has errors (scene, shaders,
 * volume contents), 2 usage or I/O failure (bad options, missing or truncated files). */
#define _POSIX_C_SOURCE 200809L
#include "halo.h"
#include "halo_gl_loader.h"
#include "gl/headless.h"
#include "image_write.h"
#include "json_file.h"
#include "progress.h"
#include "render_driver.h"
#include "tool_options.h"
#include "volume.h"
#include "volume_io.h"

#include "bench_budget.h"

#include <jansson.h>

#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <errno.h>

#define TOOL "halo-render"

#define DEFAULT_SCENE       "examples/scenes/default.json"
/* The default window of a volume file whose scene sets none: these percentiles. */
#define WINDOW_LOW_PERCENT  1.0
#define WINDOW_HIGH_PERCENT 99.0

static void usage(FILE *out)
{
    fputs(
        "Usage: halo-render [OPTION]...\n"
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
        "  --one-draw         with --host raycast or slice: host contract 3, volumetric halos\n"
        "                     computed by libhalo before the ray caster is drawn once, or the\n"
        "                     slices all at once (docs/host-contract.md)\n"
        "  --halo-scale S     halo images at 1/S of the image per side: 1 (default), 2 or 4\n"
        "                     (faster image passes; docs/performance.md). Without it, a\n"
        "                     --one-draw field over its cap is drawn at 1/2, else 1/4, with a warning\n"
        "  --field-max-mib N  with --one-draw: the cap on the frame's halo field, in MiB\n"
        "                     (0.01..1048576; default 1024)\n"
        "  --gradient-format F  the slice and slab hosts' gradient texture: float (RGB32F),\n"
        "                     half (RGB16F, the default), snorm8 (RGB8_SNORM, scaled to the\n"
        "                     volume's largest gradient), packed16 or packed32 (RGBA16_SNORM,\n"
        "                     RGBA32F: value and gradient in one texture, one fetch);\n"
        "                     docs/performance.md\n"
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
        "                     has a hardware renderer, else OSMesa); egl-es3.0 or\n"
        "                     egl-es3.2: an OpenGL ES context, for the raycast host\n"
        "                     (halo scenes: drawn once, --one-draw, unless --host raycast)\n"
        "  --export-host DIR  with --host raycast: write what the ray caster draws with into\n"
        "                     DIR (host.json: uniforms and sizes; volume.f32, transfer.f32:\n"
        "                     its textures; image.f32: the RGBA image), for another renderer\n"
        "  --quiet            no progress or volume notes on stderr\n"
        "  --help             show this help\n"
        "\n"
        "Exit status: 0 success, 1 the scene, shaders or volume contents have errors,\n"
        "2 usage or I/O failure (bad options, missing or truncated files).\n",
        out);
}

/* ---- Options ---------------------------------------------------------------------- */

typedef struct options {
    const char *scene_path, *output, *volume_path, *labels_path;
    int width, height, volume_size, have_volume_size;
    int have_azimuth, have_elevation, have_zoom, have_window, no_halos, quiet, have_max_error;
    double azimuth, elevation, zoom, window[2], max_error;
    halo_driver_host host;
    int raw, have_raw_type, have_raw_extra;
    int halo_scale, have_halo_scale, one_draw;
    double field_max_mib; /* 0: libhalo's cap */
    const char *export_dir;
    halo_gradient_format gradient_format;
    halo_raw_desc raw_desc;
} options;

enum {
    OPT_NO_HALOS,
    OPT_QUIET,
    OPT_SCENE,
    OPT_OUTPUT,
    OPT_SIZE,
    OPT_AZIMUTH,
    OPT_ELEVATION,
    OPT_ZOOM,
    OPT_VOLUME_SIZE,
    OPT_VOLUME,
    OPT_RAW_DIMS,
    OPT_RAW_TYPE,
    OPT_RAW_ENDIAN,
    OPT_RAW_OFFSET,
    OPT_RAW_SPACING,
    OPT_WINDOW,
    OPT_HOST,
    OPT_MAX_ERROR,
    OPT_LABELS,
    OPT_HALO_SCALE,
    OPT_GRADIENT_FORMAT,
    OPT_ONE_DRAW,
    OPT_EXPORT_HOST,
    OPT_FIELD_MAX_MIB
};
static const halo_tool_option option_table[] = {[OPT_NO_HALOS] = {"--no-halos", NULL, 0},
                                                [OPT_QUIET] = {"--quiet", "-q", 0},
                                                [OPT_SCENE] = {"--scene", NULL, 1},
                                                [OPT_OUTPUT] = {"-o", "--output", 1},
                                                [OPT_SIZE] = {"--size", NULL, 1},
                                                [OPT_AZIMUTH] = {"--azimuth", NULL, 1},
                                                [OPT_ELEVATION] = {"--elevation", NULL, 1},
                                                [OPT_ZOOM] = {"--zoom", NULL, 1},
                                                [OPT_VOLUME_SIZE] = {"--volume-size", NULL, 1},
                                                [OPT_VOLUME] = {"--volume", NULL, 1},
                                                [OPT_RAW_DIMS] = {"--raw-dims", NULL, 1},
                                                [OPT_RAW_TYPE] = {"--raw-type", NULL, 1},
                                                [OPT_RAW_ENDIAN] = {"--raw-endian", NULL, 1},
                                                [OPT_RAW_OFFSET] = {"--raw-offset", NULL, 1},
                                                [OPT_RAW_SPACING] = {"--raw-spacing", NULL, 1},
                                                [OPT_WINDOW] = {"--window", NULL, 1},
                                                [OPT_HOST] = {"--host", NULL, 1},
                                                [OPT_MAX_ERROR] = {"--max-error", NULL, 1},
                                                [OPT_LABELS] = {"--labels", NULL, 1},
                                                [OPT_HALO_SCALE] = {"--halo-scale", NULL, 1},
                                                [OPT_GRADIENT_FORMAT] = {"--gradient-format", NULL, 1},
                                                [OPT_ONE_DRAW] = {"--one-draw", NULL, 0},
                                                [OPT_EXPORT_HOST] = {"--export-host", NULL, 1},
                                                [OPT_FIELD_MAX_MIB] = {"--field-max-mib", NULL, 1},
                                                {NULL, NULL, 0}};

/* One option's value into o. Returns 0 after a message. */
static int take_option(options *o, int option, const char *a, const char *value)
{
    char parts[3][64];
    long offset;
    int ok = 1, host;
    switch (option) {
    case OPT_NO_HALOS:
        o->no_halos = 1;
        break;
    case OPT_ONE_DRAW:
        o->one_draw = 1;
        break;
    case OPT_FIELD_MAX_MIB:
        ok = halo_tool_number(TOOL, a, value, 0.01, 1048576, &o->field_max_mib);
        break;
    case OPT_EXPORT_HOST:
        o->export_dir = value;
        break;
    case OPT_QUIET:
        o->quiet = 1;
        break;
    case OPT_SCENE:
        o->scene_path = value;
        break;
    case OPT_OUTPUT:
        o->output = value;
        break;
    case OPT_VOLUME:
        o->volume_path = value;
        break;
    case OPT_LABELS:
        o->labels_path = value;
        break;
    case OPT_GRADIENT_FORMAT: {
        char err[128];
        ok = halo_gradient_format_option(value, &o->gradient_format, err, sizeof err);
        if (!ok)
            fprintf(stderr, TOOL ": error: %s\n", err);
        break;
    }
    case OPT_HALO_SCALE:
        ok = o->have_halo_scale = halo_tool_int(TOOL, a, value, 1, 4, &o->halo_scale);
        if (ok && o->halo_scale == 3) {
            fprintf(stderr, TOOL ": error: --halo-scale: 3 is not 1, 2 or 4\n");
            ok = 0;
        }
        break;
    case OPT_SIZE:
        ok = halo_tool_size(TOOL, a, value, 8192, &o->width, &o->height);
        break;
    case OPT_AZIMUTH:
        ok = o->have_azimuth = halo_tool_number(TOOL, a, value, -3600, 3600, &o->azimuth);
        break;
    case OPT_ELEVATION:
        ok = o->have_elevation = halo_tool_number(TOOL, a, value, -90, 90, &o->elevation);
        break;
    case OPT_ZOOM:
        ok = o->have_zoom = halo_tool_number(TOOL, a, value, 1e-3, 1e3, &o->zoom);
        break;
    case OPT_MAX_ERROR:
        ok = o->have_max_error = halo_tool_number(TOOL, a, value, 0, 1e30, &o->max_error);
        break;
    case OPT_VOLUME_SIZE:
        ok = o->have_volume_size =
            halo_tool_int(TOOL, a, value, HALO_VOLUME_MIN_SIZE, HALO_VOLUME_MAX_SIZE, &o->volume_size);
        break;
    case OPT_WINDOW:
        ok = halo_tool_split(TOOL, a, value, ':', 2, parts) &&
             halo_tool_number(TOOL, a, parts[0], -1e30, 1e30, &o->window[0]) &&
             halo_tool_number(TOOL, a, parts[1], -1e30, 1e30, &o->window[1]);
        if (ok && !(o->window[1] > o->window[0])) {
            fprintf(stderr, TOOL ": error: --window: HIGH %g is not above LOW %g\n", o->window[1], o->window[0]);
            ok = 0;
        }
        o->have_window = ok;
        break;
    case OPT_HOST:
        o->host = HALO_DRIVER_AUTO;
        for (host = HALO_DRIVER_SLICE; host < HALO_DRIVER_HOST_COUNT; ++host)
            if (!strcmp(value, halo_driver_host_names[host]))
                o->host = (halo_driver_host)host;
        if (o->host == HALO_DRIVER_AUTO) {
            fprintf(stderr, TOOL ": error: --host: unknown host '%s' (slice, slab or raycast)\n", value);
            ok = 0;
        }
        break;
    case OPT_RAW_DIMS:
        o->raw = 1;
        ok = halo_tool_split(TOOL, a, value, 'x', 3, parts);
        for (int k = 0; ok && k < 3; ++k)
            ok = halo_tool_long(TOOL, a, parts[k], 1, LONG_MAX, &o->raw_desc.dims[k]);
        break;
    case OPT_RAW_TYPE:
        o->raw_desc.type = halo_voxel_type_from_name(value);
        o->have_raw_type = 1;
        if (o->raw_desc.type == HALO_VOXEL_TYPE_COUNT) {
            fprintf(stderr, TOOL ": error: --raw-type: unknown type '%s' (uint8, uint16, int16, float32)\n", value);
            ok = 0;
        }
        break;
    case OPT_RAW_ENDIAN:
        o->have_raw_extra = 1;
        if (!strcmp(value, "little") || !strcmp(value, "big"))
            o->raw_desc.big_endian = !strcmp(value, "big");
        else {
            fprintf(stderr, TOOL ": error: --raw-endian: '%s' is not little or big\n", value);
            ok = 0;
        }
        break;
    case OPT_RAW_OFFSET:
        o->have_raw_extra = 1;
        ok = halo_tool_long(TOOL, a, value, 0, LONG_MAX, &offset);
        o->raw_desc.offset = offset;
        break;
    case OPT_RAW_SPACING:
        o->have_raw_extra = 1;
        ok = halo_tool_split(TOOL, a, value, 'x', 3, parts);
        for (int k = 0; ok && k < 3; ++k)
            ok = halo_tool_number(TOOL, a, parts[k], 1e-6, 1e6, &o->raw_desc.spacing[k]);
        break;
    }
    return ok;
}

/* The options that exclude or need each other. Returns 0 after a message. */
static int check_options(const options *o)
{
    const char *why = NULL;
    if ((o->have_raw_type || o->have_raw_extra) && !o->raw)
        why = "--raw-type, --raw-endian, --raw-offset and --raw-spacing need --raw-dims";
    else if (o->raw && !o->have_raw_type)
        why = "--raw-dims needs --raw-type (uint8, uint16, int16 or float32)";
    else if (o->have_max_error && o->no_halos)
        why = "--max-error chooses how to render the halos: not with --no-halos";
    else if (o->have_max_error && o->host != HALO_DRIVER_AUTO)
        why = "--max-error chooses the host (slice or slab): not with --host";
    else if (o->labels_path && !o->volume_path)
        why = "--labels needs --volume FILE (the labels are on that volume's grid)";
    else if (o->export_dir && o->host != HALO_DRIVER_RAYCAST)
        why = "--export-host writes the raycast host's inputs: it needs --host raycast";
    else if (o->field_max_mib > 0.0 && !o->one_draw && !halo_headless_choice_es())
        why = "--field-max-mib caps the halo field of a frame drawn once: it needs --one-draw";
    else if (o->one_draw && o->host != HALO_DRIVER_RAYCAST && o->host != HALO_DRIVER_SLICE)
        why =
            "--one-draw draws the host once over the halo field (host contract 3): it needs --host raycast or "
            "slice";
    else if (o->labels_path && o->host == HALO_DRIVER_RAYCAST)
        why = "--labels: the raycast host has no label texture; use slice or slab";
    else if (o->one_draw &&
             (o->gradient_format == HALO_GRADIENT_PACKED16 || o->gradient_format == HALO_GRADIENT_PACKED32))
        why =
            "--one-draw: libhalo's march reads the slice host's R32F volume, which the packed gradient formats "
            "free: use float, half or snorm8";
    else if (o->gradient_format && o->have_max_error)
        why = "--max-error chooses the gradient format: not with --gradient-format";
    else if (o->have_halo_scale && o->have_max_error)
        why = "--max-error chooses the halo image resolution: not with --halo-scale";
    else if (o->labels_path && o->have_max_error)
        why = "--max-error sweeps halo scenes without labels: not with --labels";
    else if (o->raw && !o->volume_path)
        why = "--raw-dims needs --volume FILE";
    else if (halo_headless_choice_es() && (o->host == HALO_DRIVER_SLICE || o->host == HALO_DRIVER_SLAB))
        why =
            "an OpenGL ES context (--backend egl-es3.0, egl-es3.2) draws the raycast host: the slice and slab "
            "hosts are written for desktop OpenGL";
    else if (halo_headless_choice_es() && o->have_max_error)
        why =
            "--max-error sweeps the slice and slab hosts, which need desktop OpenGL: not with an OpenGL ES "
            "--backend";
    if (why)
        fprintf(stderr, TOOL ": error: %s\n", why);
    return why == NULL;
}

/* Returns 0 to go on, -1 to exit 0 (help), or an exit status. The output is checked
 * here, before anything is read or rendered (a render can take minutes). */
static int parse_options(int argc, char **argv, options *o)
{
    *o = (options){.output = "halo-render.png", .width = 512, .height = 512, .volume_size = HALO_VOLUME_DEFAULT_SIZE};
    halo_tool_args args = {.tool = TOOL, .usage = usage, .argc = argc, .argv = argv, .next = 1};
    for (int k; (k = halo_tool_args_next(&args, option_table)) != HALO_TOOL_ARGS_END;) {
        if (k == HALO_TOOL_ARGS_HELP)
            return -1;
        if (k == HALO_TOOL_ARGS_ERROR || !take_option(o, k, args.option, args.value))
            return 2;
    }
    if (!o->output[0]) {
        fprintf(stderr, TOOL ": error: -o: empty file name\n");
        return 2;
    }
    if (!check_options(o))
        return 2;
    char err[512];
    if (halo_image_check(o->output, err, sizeof err) != 0) {
        fprintf(stderr, TOOL ": error: -o: %s\n", err);
        return 2;
    }
    return 0;
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

/* The segmentation of --labels, on the grid of the volume file vol: the same cube. */
static int prepare_labels(const options *o, const halo_volume_file *vol, int size, float **labels_out)
{
    halo_volume_file file;
    char err[512];
    /* read for the same side as the volume: reduced alike (halo_volume_read_nifti_for) */
    halo_volume_status status =
        halo_volume_read_nifti_for(o->labels_path, o->have_volume_size ? o->volume_size : 0, 1, &file, err, sizeof err);
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

/* Loads the volume (a file, or the built-in one), windows it to [0,1] and resamples
 * it into a cube. Returns an exit status; *volume_out is the cube. */
static int prepare_volume(const options *o, const halo_render_settings *settings, int scene_window, float **volume_out,
                          float **labels_out, int *size_out)
{
    *volume_out = NULL;
    *labels_out = NULL;
    if (!o->volume_path) {
        /* The built-in volume's values are in [0,1]: window only when asked to. */
        float *v = halo_driver_builtin_volume(o->volume_size, o->have_window ? o->window : settings->window);
        if (!v) {
            fprintf(stderr, "halo-render: error: out of memory for the built-in volume\n");
            return 2;
        }
        *volume_out = v;
        *size_out = o->volume_size;
        return 0;
    }

    halo_volume_file file;
    char err[512];
    halo_progress step;
    halo_progress_begin(&step, o->quiet ? NULL : TOOL, "reading the volume", 1);
    halo_volume_status status =
        o->raw ? halo_volume_read_raw(o->volume_path, &o->raw_desc, &file, err, sizeof err)
               : halo_volume_read_nifti_for(o->volume_path, o->have_volume_size ? o->volume_size : 0, 0, &file, err,
                                            sizeof err);
    halo_progress_end(&step, 0, "read the volume");
    if (status != HALO_VOLUME_OK) {
        fprintf(stderr, "halo-render: error: %s\n", err);
        return (int)status;
    }
    if (file.nonfinite)
        fprintf(stderr,
                "halo-render: warning: %s: %zu voxel%s NaN or infinite: rendered as the smallest finite value\n",
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
        fprintf(stderr, "halo-render: %s: %s; window %g:%g (%s); resampled to %d^3\n", o->volume_path, file.description,
                window[0], window[1], window_from, size);
    halo_progress_begin(&step, o->quiet ? NULL : TOOL, "resampling the volume", 1);
    float *cube = halo_volume_to_display(&file, window, size);
    halo_progress_end(&step, 0, "resampled the volume");
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

/* N of the sweep: the parameter that sets the repetitions of the program's generation
 * passes (repeat=PARAM in its module: the spreading passes N), or NULL when none repeats. */
static const halo_uniform_info *repeat_uniform(const halo_program *p)
{
    for (size_t i = 0; i < halo_program_reflection(p).pass_count; ++i) {
        const halo_pass_info *pi = &halo_program_reflection(p).passes[i];
        if (pi->repeat_param && pi->at == HALO_PASS_AT_GENERATE)
            return halo_program_find_uniform(p, pi->stage, pi->repeat_param);
    }
    return NULL;
}

/* Runs the error budget (validate/bench_budget.c) on the scene, volume and image size
 * and applies its choice to the scene (N, step) and to *kind, *precision, *scale,
 * *interval, *gradient.
 * Returns an exit status. */
static int apply_budget(const options *o, const char *scene_text, halo_library *lib, halo_gl *runtime,
                        const float *volume, int size, const halo_uniform_info *n_param, halo_scene *scene,
                        halo_driver_host *kind, int *precision, int *scale, int *interval,
                        halo_gradient_format *gradient, halo_diagnostics *diag)
{
    char *text = budget_scene_text(o, scene_text);
    if (!text) {
        fprintf(stderr, "halo-render: error: --max-error: cannot prepare the scene for the sweep\n");
        return 2;
    }
    halo_bench_env env = {.lib = lib,
                          .runtime = runtime,
                          .gl = halo_headless_functions(),
                          .diag = diag,
                          .width = o->width,
                          .height = o->height,
                          .volume = volume,
                          .dims = {size, size, size},
                          .repeat = 3,
                          .scene_text = text,
                          .progress = o->quiet ? NULL : stderr};
    char *report_text = NULL;
    size_t report_size = 0;
    FILE *report = open_memstream(&report_text, &report_size);
    halo_bench_config choice;
    double start = halo_progress_now();
    if (!o->quiet)
        fprintf(stderr, "halo-render: --max-error %g: measuring the configurations at %dx%d...\n", o->max_error,
                o->width, o->height);
    int scene_passes = n_param && n_param->count > 0 ? (int)n_param->value[0] : 0;
    halo_status st = halo_bench_budget(&env, scene_passes, o->max_error, &choice, report);
    double elapsed = halo_progress_now() - start;
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
            fprintf(stderr,
                    "halo-render: error: --max-error %g: the cheapest configuration is not within it when "
                    "measured again\n",
                    o->max_error);
        return st == HALO_ERROR_INPUT ? 1 : 2;
    }
    if (n_param && choice.passes > 0) {
        double passes = choice.passes;
        if (halo_scene_set(scene, n_param->stage, n_param->param, &passes, 1, 0, diag) != HALO_OK)
            return 1;
    }
    if (choice.step > 0.0) {
        halo_render_settings render = *halo_scene_describe(scene).render;
        render.step = choice.step;
        halo_scene_set_render(scene, &render);
    }
    *kind = choice.slab ? HALO_DRIVER_SLAB : HALO_DRIVER_SLICE;
    *precision = choice.precision;
    *scale = choice.scale;
    *interval = choice.interval;
    if (choice.gradient)
        *gradient = (halo_gradient_format)choice.gradient;
    return 0;
}

/* ---- Main ----------------------------------------------------------------------------- */

/* Diagnostics decide the exit status: an input error is 1, I/O or memory 2. */
static int failure_status(const halo_diagnostics *d)
{
    if (halo_diagnostics_has(d, HALO_MSG_IO_READ) || halo_diagnostics_has(d, HALO_MSG_IO_WRITE) ||
        halo_diagnostics_has(d, HALO_MSG_OUT_OF_MEMORY) || halo_diagnostics_has(d, HALO_MSG_INPUT_TOO_LARGE))
        return 2;
    return 1;
}

/* Links the scene for the host (the program validated). */
static halo_program *link_scene(halo_library *lib, halo_scene *scene, halo_driver_host kind, int precision, int scale,
                                int one_draw, halo_target target, halo_diagnostics *diag)
{
    return halo_driver_link(&(halo_link_desc){.library = lib,
                                              .scene = scene,
                                              .image_precision = precision,
                                              .image_scale = scale,
                                              .one_draw = one_draw,
                                              .target = target},
                            kind, 1, diag);
}

/* ---- --export-host: the raycast host's inputs and image, for another renderer ---------- */

/* DIR/NAME from count floats (little-endian, as this machine writes them); 0 after a message. */
static int export_floats(const char *dir, const char *name, const float *data, size_t count)
{
    char path[4096];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    FILE *out = fopen(path, "wb");
    int ok = out && fwrite(data, sizeof *data, count, out) == count;
    if (out && fclose(out) != 0)
        ok = 0;
    if (!ok)
        fprintf(stderr, TOOL ": error: --export-host: cannot write %s: %s\n", path, strerror(errno));
    return ok;
}

static void export_vector(FILE *out, const char *name, const double *v, int n, const char *end)
{
    fprintf(out, "  \"%s\": [", name);
    for (int i = 0; i < n; ++i)
        fprintf(out, "%s%.17g", i ? ", " : "", v[i]);
    fprintf(out, "]%s\n", end);
}

/* What the raycast host draws with (docs/halo-render.md, --export-host): DIR/host.json
 * (image size, the uniforms of examples/hosts/raycast.frag, the volume's size),
 * DIR/volume.f32 and DIR/transfer.f32 (the textures' floats, x fastest; RGBA texels). */
static int export_host_inputs(const char *dir, const halo_driver *host)
{
    halo_raycast_state s;
    halo_raycast_get_state(host->raycast, &s);
    char path[4096];
    snprintf(path, sizeof path, "%s/host.json", dir);
    FILE *out = fopen(path, "w");
    if (!out) {
        fprintf(stderr, TOOL ": error: --export-host: cannot write %s: %s\n", path, strerror(errno));
        return 0;
    }
    fprintf(out, "{\n  \"width\": %d,\n  \"height\": %d,\n", s.width, s.height);
    export_vector(out, "inverse_view_projection", s.inverse_view_projection, 16, ",");
    export_vector(out, "eye", s.eye, 3, ",");
    export_vector(out, "screen_right", s.screen_right, 3, ",");
    export_vector(out, "screen_up", s.screen_up, 3, ",");
    export_vector(out, "background", s.background, 3, ",");
    fprintf(out, "  \"step_size\": %.17g,\n  \"unit_step\": %.17g,\n  \"transfer_texels\": %d,\n", s.step_size,
            s.unit_step, s.transfer_texels);
    fprintf(out, "  \"dims\": [%d, %d, %d]\n}\n", s.dims[0], s.dims[1], s.dims[2]);
    if (fclose(out) != 0) {
        fprintf(stderr, TOOL ": error: --export-host: cannot write %s\n", path);
        return 0;
    }
    size_t voxels = (size_t)s.dims[0] * (size_t)s.dims[1] * (size_t)s.dims[2];
    return export_floats(dir, "volume.f32", s.volume, voxels) &&
           export_floats(dir, "transfer.f32", s.transfer, (size_t)s.transfer_texels * 4);
}

/* The volume and labels into the host, the camera, and the notes on them. Returns an exit status. */
static int set_up_host(const options *o, halo_driver *host, const halo_render_settings *settings, const float *volume,
                       const float *labels, int size, int interval, halo_diagnostics *diag)
{
    const int dims[3] = {size, size, size};
    if (halo_driver_set_volume(host, volume, dims, settings, o->gradient_format, diag) != HALO_OK)
        return 2;
    halo_driver_set_camera(host, o->have_azimuth ? o->azimuth : settings->azimuth,
                           o->have_elevation ? o->elevation : settings->elevation,
                           o->have_zoom ? o->zoom : settings->zoom);
    if (host->raycast)
        return 0;
    halo_driver_set_interval(host, interval);
    const char *gradient = halo_driver_gradient_name(host);
    if (!o->quiet && gradient)
        fprintf(stderr, TOOL ": gradient texture: %s\n", gradient);
    if (!labels && halo_program_reflection(host->program).reads_labels)
        fprintf(stderr, TOOL
                ": warning: the scene's label features (outline_feature label >= 0) need "
                "--labels FILE: without it they are empty\n");
    if (labels) {
        if (!halo_program_reflection(host->program).reads_labels && !o->quiet)
            fprintf(stderr, TOOL ": note: --labels: the scene has no label feature (outline_feature label)\n");
        if (halo_driver_set_labels(host, labels, dims, diag) != HALO_OK)
            return 2;
    }
    return 0;
}

int main(int argc, char **argv)
{
    options o;
    halo_headless_allow_es(1); /* the raycast host runs on OpenGL ES */
    if (!halo_headless_take_backend_option(&argc, argv, TOOL))
        return 2;
    int status = parse_options(argc, argv, &o);
    if (status)
        return status < 0 ? 0 : status;

    halo_diagnostics *diag = halo_diagnostics_create();
    if (!diag || halo_setup(NULL) != HALO_OK) {
        fprintf(stderr, TOOL ": error: cannot initialize libhalo\n");
        halo_diagnostics_destroy(diag);
        return 2;
    }
    halo_library *lib = NULL;
    halo_scene *scene = NULL;
    halo_program *program = NULL;
    halo_headless *context = NULL;
    halo_gl *runtime = NULL;
    halo_driver host = {0};
    float *volume = NULL, *labels = NULL, *image = NULL;
    int *is_halo = NULL;
    const char *scene_text = NULL;
    status = 1;

    lib = halo_library_create(diag);
    if (!lib)
        goto done;
    if (!o.scene_path) {
        scene_text = halo_tool_embedded_scene(DEFAULT_SCENE);
        if (!scene_text) {
            fprintf(stderr, TOOL ": error: %s is not embedded\n", DEFAULT_SCENE);
            status = 2;
            goto done;
        }
    }
    scene = o.scene_path ? halo_scene_load(o.scene_path, NULL, lib, diag)
                         : halo_scene_load(DEFAULT_SCENE " (built in)", scene_text, lib, diag);
    if (!scene)
        goto done;

    /* The halo stages decide the default host; --no-halos keeps that host. Feature
     * halos (a halo buffer read per sample) go with any host: the ray caster by default. */
    is_halo = calloc(halo_scene_describe(scene).stage_count + 1, sizeof *is_halo);
    if (!is_halo) {
        status = 2;
        goto done;
    }
    size_t halo_stages = halo_driver_find_halo_stages(lib, scene, is_halo);
    int feature = halo_driver_has_feature_halos(lib, scene);
    halo_driver_host kind = o.host != HALO_DRIVER_AUTO                  ? o.host
                            : halo_stages && !halo_headless_choice_es() ? HALO_DRIVER_SLICE
                                                                        : HALO_DRIVER_RAYCAST;
    if (o.host == HALO_DRIVER_AUTO && halo_stages && halo_headless_choice_es() && !o.one_draw) {
        /* volumetric halos on OpenGL ES 3.0 need host contract 3 (docs/host-contract.md) */
        o.one_draw = 1;
        if (!o.quiet)
            fprintf(stderr, TOOL ": note: OpenGL ES: the raycast host, drawn once over the halo field (--one-draw)\n");
    }
    if (o.gradient_format && kind == HALO_DRIVER_RAYCAST) { /* given or chosen: an option that cannot apply */
        fprintf(stderr,
                TOOL
                ": error: --gradient-format: the raycast host%s has no gradient texture (it takes "
                "central differences); use --host slice or slab\n",
                o.host == HALO_DRIVER_AUTO ? " (this scene's, having no halo stages)" : "");
        status = 2;
        goto done;
    }
    if (o.have_max_error && feature) {
        fprintf(stderr, TOOL
                ": error: --max-error: the sweep cannot render feature_halo (no halo buffer); "
                "render this scene without --max-error\n");
        status = 2;
        goto done;
    }
    if (o.no_halos) {
        if (!halo_driver_disable_halo_stages(scene, is_halo, diag)) {
            status = 2;
            goto done;
        }
        if (!halo_stages && !feature && !o.quiet)
            fprintf(stderr, TOOL ": note: --no-halos: the scene has no halo stages\n");
        feature = 0;
    }

    program = link_scene(lib, scene, kind, 0, o.halo_scale, o.one_draw, HALO_TARGET_DEFAULT, diag);
    if (!program)
        goto done;

    const halo_render_settings *settings = halo_scene_describe(scene).render;
    int size = 0;
    status = prepare_volume(&o, settings, scene_sets_window(o.scene_path, scene_text), &volume, &labels, &size);
    if (status)
        goto done;
    status = 1;

    char err[512];
    context = halo_headless_create(o.width, o.height, err, sizeof err);
    if (!context) {
        fprintf(stderr, TOOL ": error: %s\n", err);
        status = 2;
        goto done;
    }
    runtime = halo_gl_create(&(halo_gl_desc){.get_proc_address = halo_headless_get_proc_address}, diag);
    if (!runtime) {
        status = 2;
        goto done;
    }
    /* an OpenGL ES context (--backend egl-es3.0, egl-es3.2): the shaders in GLSL ES 3.00 */
    halo_target target = halo_gl_es_version(runtime) ? HALO_TARGET_ES300 : HALO_TARGET_DEFAULT;
    if (target != HALO_TARGET_DEFAULT) {
        halo_program_destroy(program);
        program = link_scene(lib, scene, kind, 0, o.halo_scale, o.one_draw, target, diag);
        if (!program)
            goto done;
    }
    int interval = 0;
    if (o.have_max_error) {
        /* the scene's N heads the sweep */
        int precision = 32, scale = 1;
        status = apply_budget(&o, scene_text, lib, runtime, volume, size, repeat_uniform(program), scene, &kind,
                              &precision, &scale, &interval, &o.gradient_format, diag);
        if (status)
            goto done;
        status = 1;
        /* the program again, for the chosen host, N and precision */
        halo_program_destroy(program);
        program = link_scene(lib, scene, kind, precision, scale, 0, target, diag);
        if (!program)
            goto done;
        settings = halo_scene_describe(scene).render;
    }
    /* a field over its cap (--one-draw; FIELD_MEMORY names the scale that fits): without
     * --halo-scale, the halo images at 1/2, else 1/4, linked again, with a note */
    int scale = o.halo_scale > 1 ? o.halo_scale : 1;
    for (;;) {
        const halo_host_desc desc = {.gl = halo_headless_functions(),
                                     .runtime = runtime,
                                     .program = program,
                                     .width = o.width,
                                     .height = o.height};
        if (!halo_driver_create(&host, kind, &desc, diag))
            goto done;
        host.tool = TOOL;
        host.quiet = o.quiet;
        halo_driver_set_field_max_bytes(&host, (size_t)(o.field_max_mib * 1048576.0));
        if (!image)
            image = malloc((size_t)o.width * (size_t)o.height * 4 * sizeof *image);
        if (!image) {
            fprintf(stderr, TOOL ": error: out of memory for a %dx%d image\n", o.width, o.height);
            status = 2;
            goto done;
        }
        status = set_up_host(&o, &host, settings, volume, labels, size, interval, diag);
        if (status)
            goto done;
        status = 1;
        if (o.export_dir && !export_host_inputs(o.export_dir, &host)) {
            status = 2;
            goto done;
        }
        /* the feature halo buffer, for this view (rebuilt after every camera change) */
        if (feature && !halo_driver_update_feature(&host, volume, (const int[3]){size, size, size}, diag))
            goto done;
        /* the hosts have the volume in textures and the feature buffer has its own copy:
         * nothing reads the float copy any more (4 bytes a voxel) */
        free(volume);
        volume = NULL;
        if (halo_driver_render(&host, image, diag) == HALO_OK)
            break;
        if (o.have_halo_scale || o.have_max_error || scale >= 4 || !halo_diagnostics_has(diag, HALO_MSG_FIELD_MEMORY)) {
            status = 2;
            goto done;
        }
        scale *= 2;
        /* (a warning, with --quiet too: the image is not the one asked for) */
        for (size_t i = 0; i < halo_diagnostics_describe(diag).count; ++i)
            if (halo_diagnostics_get(diag, i)->id == HALO_MSG_FIELD_MEMORY)
                fprintf(stderr, TOOL ": warning: %s: drawing with halo images at 1/%d (--halo-scale %d)\n",
                        halo_diagnostics_get(diag, i)->text, scale, scale);
        halo_diagnostics_clear(diag);
        halo_driver_destroy(&host);
        halo_program_destroy(program);
        program = link_scene(lib, scene, kind, 0, scale, o.one_draw, target, diag);
        free(labels);
        labels = NULL;
        if (!program || (status = prepare_volume(&o, settings, scene_sets_window(o.scene_path, scene_text), &volume,
                                                 &labels, &size)) != 0)
            goto done;
        status = 1;
    }
    if (o.export_dir && !export_floats(o.export_dir, "image.f32", image, (size_t)o.width * (size_t)o.height * 4)) {
        status = 2;
        goto done;
    }
    if (halo_image_write(o.output, o.width, o.height, image, err, sizeof err) != 0) {
        fprintf(stderr, TOOL ": error: %s\n", err);
        status = 2;
        goto done;
    }
    const halo_image_info *post = halo_driver_frame(&host) ? halo_host_post_image(program) : NULL;
    size_t stages = halo_program_reflection(program).stage_count;
    printf(TOOL ": wrote %s (%dx%d, %s host, %zu stage%s%s", o.output, o.width, o.height, halo_driver_host_names[kind],
           stages, stages == 1 ? "" : "s", stages ? ": " : "");
    for (size_t i = 0; i < stages; ++i)
        printf("%s%s", i ? ", " : "", halo_program_reflection(program).stages[i].name);
    if (post)
        printf("; image %s of the post passes", post->name);
    printf(")\n");
    status = 0;

done:
    if (status != 0 && halo_diagnostics_describe(diag).count > 0) {
        halo_diagnostics_print(diag, stderr);
        if (status == 1)
            status = failure_status(diag);
    } else if (status == 0 && halo_diagnostics_describe(diag).count > 0) {
        halo_diagnostics_print(diag, stderr); /* warnings */
    }
    halo_driver_release(&host, &program, &scene);
    halo_gl_destroy(runtime);
    halo_headless_destroy(context);
    halo_library_destroy(lib);
    free(is_halo);
    free(volume);
    free(labels);
    free(image);
    halo_diagnostics_destroy(diag);
    halo_shutdown();
    return status;
}
