/* halo-outline: renders a scene with outline/depth-enhancement stages (docs/outlines.md)
 * through the slice host and the frame runtime: slices fill the feature buffers, then
 * halo_gl_frame_post runs the outline passes on the host's colour and the image
 * "final" (or --image NAME, e.g. importance) is written.
 *
 *   halo-outline --scene S [--size N] [--volume-size N] [--image NAME] [-o OUT.png] [--check]
 *
 * --check: copies the GL frame's inputs of the post passes (feature buffers, host colour)
 * into the C emulation, runs halo_emu_frame_post and prints the largest difference of
 * every image the post passes write (exit 1 above 1e-3). */
#include "halo_gl_loader.h"
#include "gl/headless.h"
#include "halo.h"
#include "image_write.h"
#include "render_driver.h"
#include "tool_options.h"
#include "volume.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* GL post passes against their emulation on the same inputs. */
static int check_post(const halo_program *program, halo_gl_frame *frame, int size, halo_diagnostics *diag)
{
    halo_emu_frame *emu = halo_emu_frame_create(program, size, size, diag);
    float *buffer = malloc((size_t)size * size * 4 * sizeof *buffer);
    int written[64] = {0}, written_final[64] = {0}, failed = 0;
    /* feature groups: the GL frame's per-group images hold the last group, and its
     * accumulator (written by an at=post pass) all of them: copy it too */
    int grouped = halo_program_reflection(program).group_count > 1;
    if (!emu || !buffer) {
        halo_emu_frame_destroy(emu);
        free(buffer);
        return 2;
    }
    for (size_t i = 0; i < halo_program_reflection(program).pass_count; ++i) {
        const halo_pass_info *pass = &halo_program_reflection(program).passes[i];
        for (size_t k = 0; pass->at && k < halo_program_reflection(program).image_count && k < 64; ++k)
            if (!strcmp(halo_program_reflection(program).images[k].name, pass->output)) {
                written[k] = 1;
                written_final[k] |= pass->at == HALO_PASS_AT_FINAL;
            }
    }
    for (size_t k = 0; k < halo_program_reflection(program).image_count && k < 64; ++k) {
        const halo_image_info *info = &halo_program_reflection(program).images[k];
        if ((grouped ? written_final[k] : written[k]) || halo_gl_frame_read(frame, info->name, buffer) != HALO_OK)
            continue;
        double *dst = halo_emu_frame_image(emu, info->name);
        for (size_t n = 0; n < (size_t)size * size * (size_t)info->channels; ++n)
            dst[n] = buffer[n];
    }
    /* the per-group passes ran last with the last group's values */
    int groups = halo_program_reflection(program).group_count;
    if (grouped)
        halo_program_select_group((halo_program *)program, groups - 1);
    if (halo_emu_frame_post(emu, diag) != HALO_OK)
        failed = 1;
    if (grouped)
        halo_program_select_group((halo_program *)program, 0);
    for (size_t k = 0; !failed && k < halo_program_reflection(program).image_count && k < 64; ++k) {
        const halo_image_info *info = &halo_program_reflection(program).images[k];
        if (!written[k] || halo_gl_frame_read(frame, info->name, buffer) != HALO_OK)
            continue;
        const double *e = halo_emu_frame_image(emu, info->name);
        double worst = 0.0;
        int finite = 1;
        for (size_t n = 0; n < (size_t)size * size * (size_t)info->channels; ++n) {
            finite &= isfinite(buffer[n]) && isfinite(e[n]);
            double d = fabs(buffer[n] - e[n]);
            worst = d > worst ? d : worst;
        }
        int ok = finite && worst <= 1e-3;
        printf("  %-16s max |GL - emu| %.2e  %s%s\n", info->name, worst, ok ? "PASS" : "FAIL",
               finite ? "" : " (not finite)");
        failed |= !ok;
    }
    halo_emu_frame_destroy(emu);
    free(buffer);
    return failed;
}

static void usage(FILE *out)
{
    fputs(
        "usage: halo-outline --scene S [--size N] [--volume-size N] [--image NAME] [-o OUT] [--check]\n"
        "                    [--backend egl|osmesa|auto]\n",
        out);
}

int main(int argc, char **argv)
{
    const char *scene_path = NULL, *output = "halo-outline.png", *image_name = "final";
    int size = 256, volume_size = 96, check = 0;
    if (!halo_headless_take_backend_option(&argc, argv, "halo-outline"))
        return 2;
    enum { OPT_SCENE, OPT_SIZE, OPT_VOLUME_SIZE, OPT_IMAGE, OPT_OUTPUT, OPT_CHECK };
    static const halo_tool_option table[] = {[OPT_SCENE] = {"--scene", NULL, 1},
                                             [OPT_SIZE] = {"--size", NULL, 1},
                                             [OPT_VOLUME_SIZE] = {"--volume-size", NULL, 1},
                                             [OPT_IMAGE] = {"--image", NULL, 1},
                                             [OPT_OUTPUT] = {"-o", NULL, 1},
                                             [OPT_CHECK] = {"--check", NULL, 0},
                                             {NULL, NULL, 0}};
    halo_tool_args args = {.tool = "halo-outline", .usage = usage, .argc = argc, .argv = argv, .next = 1};
    for (int k; (k = halo_tool_args_next(&args, table)) != HALO_TOOL_ARGS_END;) {
        if (k == HALO_TOOL_ARGS_HELP)
            return 0;
        int ok = k != HALO_TOOL_ARGS_ERROR;
        if (k == OPT_SCENE)
            scene_path = args.value;
        else if (k == OPT_SIZE)
            ok = halo_tool_int("halo-outline", args.option, args.value, 8, 4096, &size);
        else if (k == OPT_VOLUME_SIZE)
            ok = halo_tool_int("halo-outline", args.option, args.value, HALO_VOLUME_MIN_SIZE, HALO_VOLUME_MAX_SIZE,
                               &volume_size);
        else if (k == OPT_IMAGE)
            image_name = args.value;
        else if (k == OPT_OUTPUT)
            output = args.value;
        else if (k == OPT_CHECK)
            check = 1;
        if (!ok)
            return 2;
    }
    if (!scene_path || size < 8 || size > 4096) {
        fprintf(stderr, "halo-outline: --scene is required; --size 8..4096\n");
        return 2;
    }
    halo_diagnostics *diag = halo_diagnostics_create();
    if (!diag || halo_setup(NULL) != HALO_OK)
        return 2;
    int status = 1;
    halo_library *lib = halo_library_create(diag);
    halo_scene *scene = lib ? halo_scene_load(scene_path, NULL, lib, diag) : NULL;
    halo_program *program =
        scene ? halo_driver_link(&(halo_link_desc){.library = lib, .scene = scene}, HALO_DRIVER_SLICE, 1, diag) : NULL;
    halo_headless *context = NULL;
    halo_gl *runtime = NULL;
    halo_driver slice = {0};
    float *volume = NULL, *rgba = NULL, *out = NULL;
    if (!program)
        goto done;
    char err[512];
    if (!(context = halo_headless_create(size, size, err, sizeof err))) {
        fprintf(stderr, "halo-outline: error: %s\n", err);
        status = 77;
        goto done;
    }
    runtime = halo_gl_create(&(halo_gl_desc){.get_proc_address = halo_headless_get_proc_address}, diag);
    if (!runtime ||
        !halo_driver_create(
            &slice, HALO_DRIVER_SLICE,
            &(halo_host_desc){
                .gl = halo_headless_functions(), .runtime = runtime, .program = program, .width = size, .height = size},
            diag))
        goto done;
    volume = halo_volume_create(volume_size);
    rgba = malloc((size_t)size * size * 4 * sizeof *rgba);
    out = malloc((size_t)size * size * 4 * sizeof *out);
    if (!volume || !rgba || !out)
        goto done;
    const halo_render_settings *settings = halo_scene_describe(scene).render;
    if (halo_driver_set_volume(&slice, volume, (const int[3]){volume_size, volume_size, volume_size}, settings, 0,
                               diag) != HALO_OK)
        goto done;
    halo_driver_set_camera(&slice, settings->azimuth, settings->elevation, settings->zoom);
    /* the post passes run on the host's colour within the frame */
    if (halo_driver_render(&slice, rgba, diag) != HALO_OK)
        goto done;
    halo_gl_frame *frame = halo_driver_frame(&slice);
    int channels = 4;
    if (frame) {
        const halo_image_info *info = NULL;
        for (size_t i = 0; i < halo_program_reflection(program).image_count; ++i)
            if (!strcmp(halo_program_reflection(program).images[i].name, image_name))
                info = &halo_program_reflection(program).images[i];
        if (!info || halo_gl_frame_read(frame, image_name, out) != HALO_OK) {
            fprintf(stderr, "halo-outline: error: the program has no image '%s'\n", image_name);
            goto done;
        }
        channels = info->channels;
        if (check && (status = check_post(program, frame, size, diag)) != 0)
            goto done;
        /* a feature image (importance, depth) as grey levels of its first channel, max over channels */
        if (channels != 4) {
            for (size_t p = (size_t)size * size; p-- > 0;) {
                float v = 0.0f;
                for (int c = 0; c < channels; ++c)
                    v = out[p * channels + c] > v ? out[p * channels + c] : v;
                out[p * 4] = out[p * 4 + 1] = out[p * 4 + 2] = v;
                out[p * 4 + 3] = 1.0f;
            }
        }
    } else {
        memcpy(out, rgba, (size_t)size * size * 4 * sizeof *out);
    }
    if (halo_image_write(output, size, size, out, err, sizeof err) != 0) {
        fprintf(stderr, "halo-outline: error: %s\n", err);
        status = 2;
        goto done;
    }
    printf("halo-outline: wrote %s (%dx%d, image %s)\n", output, size, size, frame ? image_name : "host colour");
    status = 0;
done:
    if (halo_diagnostics_describe(diag).count > 0)
        halo_diagnostics_print(diag, stderr);
    halo_driver_release(&slice, &program, &scene);
    halo_gl_destroy(runtime);
    halo_headless_destroy(context);
    halo_library_destroy(lib);
    free(volume);
    free(rgba);
    free(out);
    halo_diagnostics_destroy(diag);
    halo_shutdown();
    return status;
}
