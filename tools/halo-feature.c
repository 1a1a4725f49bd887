/* halo-feature: feature halos (docs/feature-halos.md) from the command line.
 *
 *   halo-feature render [--scene S] [--volume FILE] [--volume-size N] [--size N]
 *                       [--splat N] [--threshold T] [--half] [-o OUT]
 *   halo-feature report [--size N] [--mri PATH] [--mri-size N] [--splat N] [--repeat N]
 *   halo-feature conform [-v]
 *
 * render: a scene through the example ray caster (or, for a scene with volumetric halos,
 * the slice host), with the halo buffer of a feature_halo stage built for the camera
 * and bound to the stage's sampler; prints the buffer's preprocessing, build and render
 * times. report: the tables of docs/feature-halos.md. conform: the conformance rows. */
#include "halo.h"
#include "halo_feature.h"
#include "halo_gl_loader.h"
#include "gl/headless.h"
#include "image_write.h"
#include "render_driver.h"
#include "tool_options.h"
#include "volume.h"
#include "volume_io.h"

#include "conform_feature.h"
#include "feature_report.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>


#define DEFAULT_SCENE "examples/scenes/feature-default.json"

static double now_ms(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec * 1e3 + (double)t.tv_nsec * 1e-6;
}

static void usage(FILE *out)
{
    fputs(
        "Usage: halo-feature render [--scene S] [--volume FILE] [--volume-size N] [--size N]\n"
        "                           [--splat N] [--threshold T] [--half] [-o OUT]\n"
        "       halo-feature report [--size N] [--mri PATH] [--mri-size N] [--splat N] [--repeat N]\n"
        "       halo-feature conform [-v]\n"
        "Every command takes --backend B: headless OpenGL through egl, osmesa or auto\n"
        "(default: EGL when it has a hardware renderer, else OSMesa).\n",
        out);
}

typedef struct render_options {
    const char *scene, *volume, *output;
    int volume_size, size, splat, half;
    double threshold;
} render_options;

static float *load_volume(const render_options *o, const halo_render_settings *settings, int *size)
{
    if (!o->volume) {
        *size = o->volume_size ? o->volume_size : HALO_VOLUME_DEFAULT_SIZE;
        return halo_volume_create(*size);
    }
    halo_volume_file file = {0};
    char err[512];
    if (halo_volume_read_nifti(o->volume, &file, err, sizeof err) != HALO_VOLUME_OK) {
        fprintf(stderr, "halo-feature: %s\n", err);
        return NULL;
    }
    double window[2] = {settings->window[0], settings->window[1]};
    if (!(window[1] > window[0]) || (window[0] == 0 && window[1] == 1))
        halo_volume_percentile_window(&file, 1.0, 99.0, window);
    *size = o->volume_size ? o->volume_size : halo_volume_display_size(&file, 256);
    if (halo_volume_display_check(&file, *size, err, sizeof err) != HALO_VOLUME_OK) {
        fprintf(stderr, "halo-feature: %s: %s\n", o->volume, err);
        halo_volume_file_free(&file);
        return NULL;
    }
    float *cube = halo_volume_to_display(&file, window, *size);
    halo_volume_file_free(&file);
    return cube;
}

static int render_main(int argc, char **argv)
{
    render_options o = {.output = "halo-feature.png", .size = 512};
    int threshold_set = 0;
    enum { OPT_SCENE, OPT_VOLUME, OPT_VOLUME_SIZE, OPT_SIZE, OPT_SPLAT, OPT_THRESHOLD, OPT_HALF, OPT_OUTPUT };
    static const halo_tool_option table[] = {[OPT_SCENE] = {"--scene", NULL, 1},
                                             [OPT_VOLUME] = {"--volume", NULL, 1},
                                             [OPT_VOLUME_SIZE] = {"--volume-size", NULL, 1},
                                             [OPT_SIZE] = {"--size", NULL, 1},
                                             [OPT_SPLAT] = {"--splat", NULL, 1},
                                             [OPT_THRESHOLD] = {"--threshold", NULL, 1},
                                             [OPT_HALF] = {"--half", NULL, 0},
                                             [OPT_OUTPUT] = {"-o", NULL, 1},
                                             {NULL, NULL, 0}};
    halo_tool_args args = {.tool = "halo-feature", .usage = usage, .argc = argc, .argv = argv, .next = 0};
    for (int k; (k = halo_tool_args_next(&args, table)) != HALO_TOOL_ARGS_END;) {
        if (k == HALO_TOOL_ARGS_HELP)
            return 0;
        const char *a = args.option, *value = args.value;
        int ok = k != HALO_TOOL_ARGS_ERROR;
        switch (k) {
        case OPT_SCENE:
            o.scene = value;
            break;
        case OPT_VOLUME:
            o.volume = value;
            break;
        case OPT_VOLUME_SIZE:
            ok = halo_tool_int("halo-feature", a, value, 8, 512, &o.volume_size);
            break;
        case OPT_SIZE:
            ok = halo_tool_int("halo-feature", a, value, 16, 4096, &o.size);
            break;
        case OPT_SPLAT:
            ok = halo_tool_int("halo-feature", a, value, 3, 9, &o.splat);
            if (ok && o.splat % 2 == 0) {
                fprintf(stderr, "halo-feature: error: --splat: %d is not 3, 5, 7 or 9\n", o.splat);
                ok = 0;
            }
            break;
        case OPT_THRESHOLD:
            ok = threshold_set = halo_tool_number("halo-feature", a, value, -1e30, 1e30, &o.threshold);
            break;
        case OPT_HALF:
            o.half = 1;
            break;
        case OPT_OUTPUT:
            o.output = value;
            break;
        }
        if (!ok)
            return 2;
    }
    if (threshold_set && o.threshold == 0.0)
        o.threshold = -1.0; /* 0 asks for no cutoff */
    int status = 1;
    halo_diagnostics *diag = halo_diagnostics_create();
    halo_setup(NULL);
    halo_library *lib = halo_library_create(diag);
    halo_scene *scene = NULL;
    halo_program *program = NULL;
    halo_headless *context = NULL;
    halo_gl *runtime = NULL;
    halo_driver host = {0};
    halo_feature_buffer *buffer = NULL;
    float *volume = NULL, *image = NULL;
    if (!lib || halo_feature_ensure_module(lib, diag) != HALO_OK)
        goto done;
    const char *builtin = o.scene ? NULL : halo_tool_embedded_scene(DEFAULT_SCENE);
    if (!o.scene && !builtin) {
        fprintf(stderr, "halo-feature: error: %s is not embedded\n", DEFAULT_SCENE);
        goto done;
    }
    scene = o.scene ? halo_scene_load(o.scene, NULL, lib, diag)
                    : halo_scene_load(DEFAULT_SCENE " (built in)", builtin, lib, diag);
    if (!scene)
        goto done;
    int feature = halo_driver_has_feature_halos(lib, scene);
    const halo_render_settings *settings = halo_scene_describe(scene).render;
    int size = 0;
    volume = load_volume(&o, settings, &size);
    if (!volume)
        goto done;
    char err[512];
    context = halo_headless_create(o.size, o.size, err, sizeof err);
    if (!context) {
        fprintf(stderr, "halo-feature: %s\n", err);
        status = 77;
        goto done;
    }
    runtime = halo_gl_create(&(halo_gl_desc){.get_proc_address = halo_headless_get_proc_address}, diag);
    if (!runtime)
        goto done;
    /* feature halos through the ray caster; any other scene (volumetric halos need
     * image passes) through the slice host */
    int use_slice = !feature;
    halo_driver_host kind = use_slice ? HALO_DRIVER_SLICE : HALO_DRIVER_RAYCAST;
    program = halo_driver_link(&(halo_link_desc){.library = lib, .scene = scene}, kind, 0, diag);
    if (!program)
        goto done;
    const halo_host_desc desc = {
        .gl = halo_headless_functions(), .runtime = runtime, .program = program, .width = o.size, .height = o.size};
    const halo_glfuncs *f = halo_headless_functions();
    image = malloc((size_t)o.size * o.size * 4 * sizeof *image);
    if (!image)
        goto done;
    double create_ms = 0, build_ms = 0, render_ms[2] = {0, 0};
    if (!halo_driver_create(&host, kind, &desc, diag) ||
        halo_driver_set_volume(&host, volume, (const int[3]){size, size, size}, settings, 0, diag) != HALO_OK)
        goto done;
    halo_driver_set_camera(&host, settings->azimuth, settings->elevation, settings->zoom);
    if (feature) {
        /* the buffer with this tool's splat, threshold and resolution, timed step by step */
        int dims[3] = {size, size, size};
        halo_feature_desc fd;
        halo_feature_desc_from_program(program, &fd);
        if (o.splat)
            fd.splat_size = o.splat;
        if (threshold_set)
            fd.threshold = o.threshold;
        if (o.half)
            fd.half_resolution = 1;
        double t0 = now_ms();
        buffer = halo_feature_buffer_create(runtime, volume, dims, &fd, diag);
        create_ms = now_ms() - t0;
        if (!buffer)
            goto done;
        /* the view: from the volume's centre towards the eye (one direction for the
         * whole buffer; voxel space = texture space for the cube) */
        double eye[3];
        halo_driver_eye(&host, eye);
        double view[3] = {eye[0] - 0.5, eye[1] - 0.5, eye[2] - 0.5};
        f->Finish();
        t0 = now_ms();
        if (halo_feature_buffer_build(buffer, view) != HALO_OK)
            goto done;
        f->Finish();
        build_ms = now_ms() - t0;
        halo_driver_bind_feature(&host, buffer);
    }
    for (int k = 0; k < 2; ++k) {
        double t0 = now_ms();
        if (halo_driver_render(&host, image, diag) != HALO_OK)
            goto done;
        render_ms[k] = now_ms() - t0;
    }
    if (halo_image_write(o.output, o.size, o.size, image, err, sizeof err) != 0) {
        fprintf(stderr, "halo-feature: %s\n", err);
        status = 2;
        goto done;
    }
    printf("%s: %d^3 volume, %dx%d, %s host", o.output, size, o.size, o.size, use_slice ? "slice" : "raycast");
    if (feature)
        printf(", halo buffer: %zu qualified, preprocess %.1f ms, build %.1f ms",
               halo_feature_buffer_describe(buffer).qualified, create_ms, build_ms);
    printf(", render %.1f ms (first %.1f ms)\n", render_ms[1], render_ms[0]);
    status = 0;
done:
    if (status == 1)
        halo_diagnostics_print(diag, stderr);
    halo_feature_buffer_destroy(buffer);
    halo_driver_release(&host, &program, &scene);
    halo_gl_destroy(runtime);
    halo_headless_destroy(context);
    halo_library_destroy(lib);
    halo_diagnostics_destroy(diag);
    halo_shutdown();
    free(volume);
    free(image);
    return status;
}

int main(int argc, char **argv)
{
    if (!halo_headless_take_backend_option(&argc, argv, "halo-feature"))
        return 2;
    if (argc < 2) {
        usage(stderr);
        return 2;
    }
    if (!strcmp(argv[1], "render"))
        return render_main(argc - 2, argv + 2);
    if (!strcmp(argv[1], "report"))
        return halo_feature_report_main(argc - 2, argv + 2);
    if (!strcmp(argv[1], "conform")) {
        int verbose = argc > 2 && !strcmp(argv[2], "-v");
        int failed = 0;
        printf("%-26s %10s %10s %8s %9s %17s %s\n", "stage", "max_abs", "rmse", "over_tol", "nonfinite", "tolerance",
               "result");
        int rows = halo_conform_feature_rows(verbose, &failed);
        printf("%d rows, %d failed\n", rows, failed);
        return failed ? 1 : 0;
    }
    if (!strcmp(argv[1], "--help")) {
        usage(stdout);
        return 0;
    }
    usage(stderr);
    return 2;
}
