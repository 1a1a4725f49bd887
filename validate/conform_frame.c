/* The frame family: stages with outputs, images or host uniforms (halo_seed, halo_map,
 * outline_feature) drawn through the GL runtime's frame by the frame probe, against the
 * emulation's frame: colour and opacity, and the images the stage writes. */
#include "conform_frame.h"

#include "halo.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Input field (0 view, 1 gradient, 2 value, 3 position, 4 colour, 5 opacity) of s
 * scaled by factor: the sensitivity of a frame row's result to rounding. */
static void perturb_input(halo_emu_sample *s, int field, double factor)
{
    switch (field) {
    case 0:
        for (int k = 0; k < 3; ++k)
            s->view[k] *= factor;
        break;
    case 1:
        for (int k = 0; k < 3; ++k)
            s->gradient[k] *= factor;
        break;
    case 2:
        s->value *= factor;
        break;
    case 3:
        for (int k = 0; k < 3; ++k)
            s->position[k] *= factor;
        break;
    case 4:
        for (int k = 0; k < 3; ++k)
            s->color[k] = fmin(1.0, s->color[k] * factor);
        break;
    default:
        s->opacity = fmin(1.0, s->opacity * factor);
        break;
    }
}

/* One sample through the emulated frame: colour, opacity and the seed (8 values). Does
 * not fold into the frame's images (finish is separate). */
static int emulate_frame_sample(const halo_program *p, halo_emu_frame *ef, halo_emu_sample *s, double out[8])
{
    memset(s->output_accum, 0, sizeof s->output_accum);
    if (halo_emu_apply(p, ef, s, NULL) != HALO_OK)
        return 0;
    out[0] = s->color[0], out[1] = s->color[1], out[2] = s->color[2], out[3] = s->opacity;
    for (int k = 0; k < 4; ++k)
        out[4 + k] = s->output_accum[k];
    return 1;
}

static int program_has_image(const halo_program *p, const char *name)
{
    for (size_t i = 0; i < halo_program_reflection(p).image_count; ++i)
        if (!strcmp(halo_program_reflection(p).images[i].name, name))
            return 1;
    return 0;
}


/* `#pragma halo is keeps_empty` with a frame (as conform_sample.c checks it without one):
 * when every linked stage makes the promise, an empty sample through a 1x1 frame whose
 * images are cleared comes out with colour, opacity and every output 0. Returns 1 when
 * it does or nothing promises it; 0 with colour and opacity in out. */
static int frame_keeps_empty(const halo_program *p, double out[4])
{
    size_t n = halo_program_reflection(p).stage_count;
    for (size_t i = 0; i < n; ++i)
        if (!halo_program_reflection(p).stages[i].keeps_empty)
            return 1;
    halo_emu_frame *one = halo_emu_frame_create(p, 1, 1, NULL);
    if (!one)
        return 1; /* the row reports the emulation's failure */
    emu_set_axes(one);
    emu_set_probe_volumes(p, one);
    halo_emu_frame_begin(one);
    halo_emu_sample s;
    memset(&s, 0, sizeof s);
    s.position[0] = s.position[1] = s.position[2] = 0.5;
    s.view[2] = 1.0;
    s.depth = 0.5;
    s.fragcoord[0] = s.fragcoord[1] = 0.5;
    int kept = 1;
    if (halo_emu_apply(p, one, &s, NULL) == HALO_OK) {
        out[0] = s.color[0], out[1] = s.color[1], out[2] = s.color[2], out[3] = s.opacity;
        kept = out[0] == 0.0 && out[1] == 0.0 && out[2] == 0.0 && out[3] == 0.0;
        for (int k = 0; k < 4; ++k) {
            kept &= s.output_accum[k] == 0.0;
            for (int o = 0; o < 15; ++o)
                kept &= s.output_accum_next[o][k] == 0.0;
        }
    }
    halo_emu_frame_destroy(one);
    return kept;
}

/* Prints a frame row; with -v or when it failed, the sample over tolerance (else the one
 * of the largest error) with the GPU's and the emulation's colour. Returns that sample's
 * index, its emulated values in emu (8), or SIZE_MAX when nothing more is to be shown. */
static size_t print_frame_row(conform *c, const char *row, const row_stats *stats, const char *tolerance_text,
                              size_t worst_over, const halo_program *p, halo_emu_frame *eframe,
                              const halo_emu_sample *samples, const float *gpu, double emu[8])
{
    double empty[4];
    int kept = frame_keeps_empty(p, empty);
    int pass = stats->over == 0 && stats->nonfinite == 0 && kept;
    print_row(c, row, stats, tolerance_text, pass);
    if (!kept)
        fprintf(stderr,
                "  a stage says `#pragma halo is keeps_empty`, but an empty sample (value, colour, opacity and "
                "gradient 0) through a cleared frame comes out as colour (%g, %g, %g), opacity %g, or an output "
                "not 0\n",
                empty[0], empty[1], empty[2], empty[3]);
    if (!c->verbose && pass)
        return SIZE_MAX;
    size_t shown = worst_over != SIZE_MAX ? worst_over : stats->worst;
    halo_emu_sample s = samples[shown];
    emulate_frame_sample(p, eframe, &s, emu);
    conform_print_sample(worst_over != SIZE_MAX ? "over tolerance" : "largest error", &samples[shown], &gpu[shown * 4],
                         emu);
    return shown;
}

/* One sample through a 1x1 emulated frame (fragcoord moved to its pixel): the output
 * images' values at that pixel, nv of them (outputs in order, each image's components). */
static int emulate_output_pixel(const halo_program *p, halo_emu_frame *one, const halo_emu_sample *sample,
                                double *values, int max_values, int *nv)
{
    halo_emu_sample s = *sample;
    memset(s.output_accum, 0, sizeof s.output_accum);
    memset(s.output_accum_next, 0, sizeof s.output_accum_next);
    s.fragcoord[0] = s.fragcoord[1] = 0.5;
    halo_emu_frame_begin(one);
    if (halo_emu_apply(p, one, &s, NULL) != HALO_OK)
        return 0;
    halo_emu_frame_finish(one, &s);
    int n = 0;
    for (size_t i = 0; i < halo_program_reflection(p).image_count; ++i) {
        const halo_image_info *info = &halo_program_reflection(p).images[i];
        int written = 0;
        for (size_t o = 0; o < halo_program_reflection(p).output_count; ++o)
            written |= !strcmp(halo_program_reflection(p).outputs[o].image, info->name);
        const double *px = written ? halo_emu_frame_image(one, info->name) : NULL;
        for (int k = 0; px && k < info->channels && n < max_values; ++k)
            values[n++] = px[k];
    }
    *nv = n;
    return 1;
}

/* The output images of a frame row (one fragment per pixel) against the emulated frame,
 * with colour and opacity: each value within tol_abs + tol_rel |emu| + the change that a
 * 2^-21 relative perturbation of the sample's inputs makes (a label or value-range
 * membership that flips within float rounding of the inputs). */
static int compare_output_images(conform *c, const char *row, const halo_program *p, halo_gl_frame *gframe,
                                 halo_emu_frame *eframe, const halo_emu_sample *samples, const float *gpu,
                                 double tol_abs, double tol_rel, const char *tolerance_text)
{
    enum { MAX_VALUES = 64 };
    size_t count = (size_t)c->size * (size_t)c->size;
    size_t images = halo_program_reflection(p).image_count;
    float **gl_images = calloc(images ? images : 1, sizeof *gl_images);
    halo_emu_frame *one = halo_emu_frame_create(p, 1, 1, c->diag);
    int ok = 0;
    if (!gl_images || !one)
        goto out;
    emu_set_axes(one);
    emu_set_probe_volumes(p, one);
    for (size_t i = 0; i < images; ++i) {
        const halo_image_info *info = &halo_program_reflection(p).images[i];
        int written = 0;
        for (size_t o = 0; o < halo_program_reflection(p).output_count; ++o)
            written |= !strcmp(halo_program_reflection(p).outputs[o].image, info->name);
        if (!written)
            continue;
        gl_images[i] = malloc(count * (size_t)info->channels * sizeof **gl_images);
        if (!gl_images[i] || halo_gl_frame_read(gframe, info->name, gl_images[i]) != HALO_OK)
            goto out;
    }
    for (size_t i = 0; i < count; ++i) { /* the whole frame, as a host would fold it */
        halo_emu_sample s = samples[i];
        memset(s.output_accum, 0, sizeof s.output_accum);
        memset(s.output_accum_next, 0, sizeof s.output_accum_next);
        if (halo_emu_apply(p, eframe, &s, c->diag) != HALO_OK)
            goto out;
        halo_emu_frame_finish(eframe, &s);
    }
    row_stats stats = {0};
    size_t worst_over = SIZE_MAX;
    for (size_t i = 0; i < count; ++i) {
        double emu[4 + MAX_VALUES], g[4 + MAX_VALUES], condition[4 + MAX_VALUES] = {0}, one_px[MAX_VALUES];
        int n = 0, nv = 0;
        halo_emu_sample s = samples[i];
        double colour[8];
        if (!emulate_frame_sample(p, eframe, &s, colour))
            goto out;
        for (int k = 0; k < 4; ++k)
            emu[n] = colour[k], g[n++] = gpu[i * 4 + (size_t)k];
        for (size_t m = 0; m < images; ++m) {
            if (!gl_images[m])
                continue;
            int ch = halo_program_reflection(p).images[m].channels;
            const double *e = halo_emu_frame_image(eframe, halo_program_reflection(p).images[m].name);
            for (int k = 0; k < ch && n < 4 + MAX_VALUES; ++k)
                emu[n] = e[i * (size_t)ch + (size_t)k], g[n++] = gl_images[m][i * (size_t)ch + (size_t)k];
        }
        for (int field = 0; field < 6; ++field)
            for (int sign = -1; sign <= 1; sign += 2) {
                halo_emu_sample moved = samples[i];
                double factor = 1.0 + sign * CONFORM_INPUT_PERTURBATION, out[8];
                perturb_input(&moved, field, factor);
                halo_emu_sample copy = moved;
                if (emulate_frame_sample(p, eframe, &copy, out))
                    for (int k = 0; k < 4; ++k)
                        condition[k] = fmax(condition[k], fabs(out[k] - emu[k]));
                if (emulate_output_pixel(p, one, &moved, one_px, MAX_VALUES, &nv))
                    for (int k = 0; k < nv && 4 + k < n; ++k)
                        condition[4 + k] = fmax(condition[4 + k], fabs(one_px[k] - emu[4 + k]));
            }
        if (row_stats_add(&stats, i, g, emu, condition, n, tol_abs, tol_rel))
            worst_over = i;
    }
    double emu_shown[8];
    size_t shown = print_frame_row(c, row, &stats, tolerance_text, worst_over, p, eframe, samples, gpu, emu_shown);
    if (shown != SIZE_MAX) {
        for (size_t m = 0; m < images; ++m) {
            if (!gl_images[m])
                continue;
            int ch = halo_program_reflection(p).images[m].channels;
            const double *e = halo_emu_frame_image(eframe, halo_program_reflection(p).images[m].name);
            fprintf(stderr, "    %-16s gpu", halo_program_reflection(p).images[m].name);
            for (int k = 0; k < ch; ++k)
                fprintf(stderr, " %.9g", gl_images[m][shown * (size_t)ch + (size_t)k]);
            fprintf(stderr, "  emulation");
            for (int k = 0; k < ch; ++k)
                fprintf(stderr, " %.9g", e[shown * (size_t)ch + (size_t)k]);
            fprintf(stderr, "\n");
        }
    }
    ok = 1;
out:
    if (!ok)
        HALO_REPORT_ERROR(c->diag, HALO_MSG_EMU_MISSING, "", 0, 0,
                          "row %s: an output image could not be read or emulated", row);
    for (size_t i = 0; gl_images && i < images; ++i)
        free(gl_images[i]);
    free(gl_images);
    halo_emu_frame_destroy(one);
    return ok;
}


/* halo_seed and halo_map, and any stage with outputs, images or host uniforms: the probe
 * is drawn through a frame. halo_map's program also holds halo_seed and halo_generate: the
 * first draw seeds, the GPU generates, the GPU's field and occlusion images are copied
 * into the emulated frame, and the second draw is compared (so that this row measures
 * halo_map alone; the pass rows measure the images). halo_seed's rows also compare the
 * seed image (max over the one fragment of each pixel). row: the row's name; scene_json:
 * NULL for the module's defaults. */
static void run_frame_stage_row(conform *c, const halo_module *m, const char *row, const char *scene_json, int live,
                                const conform_row *entry)
{
    const char *stage = halo_module_describe(m).name;
    if (!row_selected(c, row, stage))
        return;
    int is_map = halo_module_describe(m).image_count > 0;
    double tol_abs = entry->tolerance_abs, tol_rel = entry->tolerance_rel;
    char tolerance_text[32];
    conform_tolerance_text(entry, tolerance_text, sizeof tolerance_text);
    halo_scene *scene = NULL;
    halo_program *program = NULL;
    halo_gl_frame *gframe = NULL;
    halo_emu_frame *eframe = NULL;
    frame_probe fp = {0};
    halo_emu_sample *samples = NULL;
    float *gpu = NULL, *gpu_seed = NULL, *image = NULL;
    size_t count = (size_t)c->size * (size_t)c->size;
    int printed = 0; /* the row printed its line; else conform_row_end prints an error row */
    if (scene_json)
        scene = halo_scene_load("(conformance frame scene)", scene_json, c->lib, c->diag);
    else if ((scene = halo_scene_create(c->lib)) && halo_scene_enable(scene, stage, 1, c->diag) != HALO_OK)
        goto done;
    if (!scene)
        goto done;
    program = halo_link(&(halo_link_desc){.library = c->lib,
                                          .scene = scene,
                                          .host_source = c->probe_source,
                                          .host_file = "probe.frag",
                                          .all_live = live,
                                          .target = c->target},
                        c->diag);
    if (!program)
        goto done;
    if (live)
        conform_set_live_arrays(program, m, c->diag);
    if (halo_diagnostics_describe(c->diag).errors > 0)
        goto done;
    int channels = halo_program_reflection(program).channel_count;
    samples = malloc(count * sizeof *samples);
    gpu = malloc(count * 4 * sizeof *gpu);
    gpu_seed = malloc(count * 4 * sizeof *gpu_seed);
    image = malloc(count * 4 * sizeof *image);
    if (!samples || !gpu || !gpu_seed || !image) {
        HALO_REPORT_ERROR(c->diag, HALO_MSG_OUT_OF_MEMORY, "", 0, 0, "out of memory");
        goto done;
    }
    conform_fill_samples(samples, c->size, c->size);
    if (!frame_probe_open(c, program, c->size, &fp))
        goto done;
    gframe = fp.gl_frame;
    eframe = fp.emu_frame;
    emu_set_axes(eframe);
    emu_set_probe_volumes(program, eframe);
    halo_gl_frame_begin(gframe);
    halo_emu_frame_begin(eframe);
    if (frame_probe_draw(c, &fp, program, gframe, samples, gpu) != HALO_OK)
        goto done;
    if (!is_map && !program_has_image(program, "seed")) {
        /* outputs other than seed (outline_feature): compare every output image */
        if (!compare_output_images(c, row, program, gframe, eframe, samples, gpu, tol_abs, tol_rel, tolerance_text))
            goto done;
        printed = 1;
        goto done;
    }
    if (is_map) {
        /* generate on the GPU; the emulation continues from the GPU's images */
        halo_gl_frame_generate(gframe);
        for (size_t i = 0; i < halo_program_reflection(program).image_count; ++i) {
            const char *name = halo_program_reflection(program).images[i].name;
            if (halo_gl_frame_read(gframe, name, image) != HALO_OK)
                goto done;
            double *e = halo_emu_frame_image(eframe, name);
            for (size_t k = 0; k < count * (size_t)channels; ++k)
                e[k] = image[k];
        }
        if (frame_probe_draw(c, &fp, program, gframe, samples, gpu) != HALO_OK)
            goto done;
    } else if (halo_gl_frame_read(gframe, "seed", gpu_seed) != HALO_OK) {
        goto done;
    }
    row_stats stats = {0};
    size_t worst_over = SIZE_MAX;
    int values = is_map ? 4 : 4 + channels;
    for (size_t i = 0; i < count; ++i) {
        halo_emu_sample s = samples[i];
        double emu[8], condition[8] = {0};
        if (!emulate_frame_sample(program, eframe, &s, emu)) {
            HALO_REPORT_ERROR(c->diag, HALO_MSG_EMU_MISSING, "", 0, 0, "a stage of row %s has no emulation", row);
            goto done;
        }
        for (int field = 0; field < 6; ++field)
            for (int sign = -1; sign <= 1; sign += 2) {
                halo_emu_sample moved = samples[i];
                double factor = 1.0 + sign * CONFORM_INPUT_PERTURBATION, out[8];
                perturb_input(&moved, field, factor);
                if (emulate_frame_sample(program, eframe, &moved, out))
                    for (int k = 0; k < 8; ++k)
                        condition[k] = fmax(condition[k], fabs(out[k] - emu[k]));
            }
        double g[8];
        for (int k = 0; k < values; ++k)
            g[k] = k < 4 ? gpu[i * 4 + (size_t)k] : gpu_seed[i * (size_t)channels + (size_t)(k - 4)];
        if (row_stats_add(&stats, i, g, emu, condition, values, tol_abs, tol_rel))
            worst_over = i;
    }
    double emu[8];
    size_t shown = print_frame_row(c, row, &stats, tolerance_text, worst_over, program, eframe, samples, gpu, emu);
    if (shown != SIZE_MAX) {
        if (!is_map)
            fprintf(stderr, "    seed gpu (%.9g %.9g %.9g %.9g) emulation (%.9g %.9g %.9g %.9g)\n",
                    gpu_seed[shown * (size_t)channels], channels > 1 ? gpu_seed[shown * (size_t)channels + 1] : 0.0,
                    channels > 2 ? gpu_seed[shown * (size_t)channels + 2] : 0.0,
                    channels > 3 ? gpu_seed[shown * (size_t)channels + 3] : 0.0, emu[4], emu[5], emu[6], emu[7]);
    }
    printed = 1;
done:
    frame_probe_release(&fp); /* and the frames */
    free(samples);
    free(gpu);
    free(gpu_seed);
    free(image);
    conform_row_end(c, row, printed, program, scene);
}

/* The stage of a row: its name up to '@'. */
static const halo_module *row_module(conform *c, const char *row)
{
    char stage[128];
    snprintf(stage, sizeof stage, "%s", row);
    char *at = strchr(stage, '@');
    if (at)
        *at = '\0';
    return halo_library_find(c->lib, stage);
}

void conform_frame_row(conform *c, const conform_row *row)
{
    const conform_frame_params *params = row->params;
    const halo_module *m = row_module(c, row->name);
    if (!m) {
        if (row_selected(c, row->name, NULL)) {
            HALO_REPORT_ERROR(c->diag, HALO_MSG_EMU_MISSING, "", 0, 0, "the stage of row '%s' is not in the library",
                              row->name);
            print_error_row(c, row->name);
        }
        return;
    }
    if (!halo_module_describe(m).has_emulation)
        return; /* the per-sample family's "*" row says so */
    run_frame_stage_row(c, m, row->name, params ? params->scene : NULL, params ? params->live : 0, row);
}

void conform_frame_other_rows(conform *c, const conform_row *row)
{
    for (size_t i = 0; i < halo_library_describe(c->lib).module_count; ++i) {
        const halo_module *m = halo_library_describe(c->lib).modules[i];
        if (halo_module_describe(m).hook != HALO_HOOK_SAMPLE || conform_has_row(c, halo_module_describe(m).name) ||
            !(halo_module_describe(m).output_count || halo_module_describe(m).image_count ||
              halo_module_describe(m).host_uniform_count) ||
            !halo_module_describe(m).has_emulation)
            continue;
        char live[128];
        snprintf(live, sizeof live, "%s@live", halo_module_describe(m).name);
        run_frame_stage_row(c, m, halo_module_describe(m).name, NULL, 0, row);
        run_frame_stage_row(c, m, live, NULL, 1, row);
    }
}
