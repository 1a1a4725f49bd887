/* The per-sample family: every per-sample stage drawn once per pixel through the probe
 * host (halo_probe) on the hard and random samples, against halo_emu_apply; with its
 * default parameters, every exponent at 0 and at 64, and every parameter live. */
#include "conform_sample.h"

#include "halo.h"
#include "hosts/raycast.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* ---- Tolerances ---------------------------------------------------------------------
 *
 * A GPU result r passes against the emulation e (double precision, same guards, on the
 * very float inputs uploaded) when, for each of colour r, g, b and opacity,
 *
 *     |r - e| <= abs + rel * |e| + condition
 *
 * abs and rel (per stage, in the registry: conform_rows.c) bound the float32 evaluation of the stage's formula
 * where it is well conditioned: every operation rounds to 24 bits (2^-24 = 6e-8
 * relative), llvmpipe's pow is exp2(e * log2 x) with a few ulps of error in each, and
 * the parameters (k_gs up to 50 in the defaults) scale those errors up.
 *
 * condition is measured per sample: the largest change of the emulated result when one
 * input (view, gradient, value, depth, colour, opacity) is scaled by 1 +- 2^-21, i.e.
 * moved by the few float ulps that the GPU's own intermediate rounding (|grad f|, n,
 * n.V) amounts to. It is zero where the formula is flat and large only where the
 * formula itself is ill conditioned: (1 - |n.V|)^k with k < 1 near |n.V| = 1 has an
 * infinite derivative, so float32 cannot do better there and no fixed tolerance both
 * passes a correct float implementation and catches a wrong one. Inputs on a guard's
 * threshold (|grad f|^2 = 1e-20) are avoided: either side is correct there.
 *
 * A row also fails on any NaN or infinity in the GPU's output (nonfinite). */

static void emulated_output(const halo_emu_sample *s, double out[4])
{
    out[0] = s->color[0], out[1] = s->color[1], out[2] = s->color[2], out[3] = s->opacity;
}

/* The emulated result with one input scaled by factor: the sensitivity to rounding. */
static int perturbed_output(const halo_program *p, const halo_emu_sample *input, int field, double factor,
                            double out[4])
{
    halo_emu_sample s = *input;
    switch (field) {
    case 0:
        for (int k = 0; k < 3; ++k)
            s.view[k] *= factor;
        break;
    case 1:
        for (int k = 0; k < 3; ++k)
            s.gradient[k] *= factor;
        break;
    case 2:
        s.value *= factor;
        break;
    case 3:
        s.depth = fmin(1.0, s.depth * factor);
        break;
    case 4:
        for (int k = 0; k < 3; ++k)
            s.color[k] = fmin(1.0, s.color[k] * factor);
        break;
    default:
        s.opacity = fmin(1.0, s.opacity * factor);
        break;
    }
    if (halo_emu_apply(p, NULL, &s, NULL) != HALO_OK)
        return 0;
    emulated_output(&s, out);
    return 1;
}

/* `#pragma halo is keeps_empty` is a promise hosts act on (the slice host skips empty
 * samples outside the volume when every stage makes it): when every linked stage makes it,
 * an empty sample (value, colour, opacity and gradient 0) must come out empty. Returns 1
 * when it does or nothing promises it; 0 with the sample that came out in out. */
static int keeps_empty_kept(const halo_program *p, double out[4])
{
    size_t n = halo_program_reflection(p).stage_count;
    for (size_t i = 0; i < n; ++i)
        if (!halo_program_reflection(p).stages[i].keeps_empty)
            return 1;
    static const double views[2][3] = {{0, 0, 1}, {0.6, 0, 0.8}};
    for (int v = 0; v < 2; ++v) {
        halo_emu_sample s;
        memset(&s, 0, sizeof s);
        s.position[0] = s.position[1] = s.position[2] = 0.5;
        memcpy(s.view, views[v], sizeof s.view);
        s.depth = 0.5;
        s.fragcoord[0] = s.fragcoord[1] = 0.5;
        if (halo_emu_apply(p, NULL, &s, NULL) != HALO_OK)
            return 1; /* the row reports the emulation's failure */
        emulated_output(&s, out);
        if (out[0] != 0.0 || out[1] != 0.0 || out[2] != 0.0 || out[3] != 0.0)
            return 0;
    }
    return 1;
}

/* The parameter variants of a stage's rows. */
enum variant { VARIANT_DEFAULT, VARIANT_EXPONENT_0, VARIANT_EXPONENT_64, VARIANT_LIVE, VARIANT_COUNT };
static const char *const variant_suffix[VARIANT_COUNT] = {"", "@exp0", "@exp64", "@live"};

/* Exponents are the float parameters whose range ends at 64 (modules.md convention:
 * every exponent is declared max=64). */
static int is_exponent(const halo_param_info *info)
{
    return info->type == HALO_PARAM_FLOAT && info->array_size == 0 && info->max == 64.0;
}

static int has_exponent(const halo_module *m)
{
    for (size_t i = 0; i < halo_module_describe(m).param_count; ++i)
        if (is_exponent(&halo_module_describe(m).params[i]))
            return 1;
    return 0;
}


/* One row: the stage m with a parameter variant, within the tolerance of entry. */
static void run_stage_row(conform *c, const halo_module *m, enum variant variant, const conform_row *entry)
{
    const char *stage = halo_module_describe(m).name;
    char row[128];
    snprintf(row, sizeof row, "%s%s", stage, variant_suffix[variant]);
    if (!row_selected(c, row, stage))
        return;
    const conform_row *tol = entry;
    char tolerance_text[32];
    conform_tolerance_text(entry, tolerance_text, sizeof tolerance_text);

    halo_scene *scene = halo_scene_create(c->lib);
    halo_program *program = NULL;
    halo_probe *probe = NULL;
    halo_emu_sample *samples = NULL;
    float *gpu = NULL;
    int printed = 0; /* the row printed its line; else conform_row_end prints an error row */
    if (!scene || halo_scene_enable(scene, stage, 1, c->diag) != HALO_OK)
        goto done;
    if (variant == VARIANT_EXPONENT_0 || variant == VARIANT_EXPONENT_64) {
        double exponent = variant == VARIANT_EXPONENT_0 ? 0.0 : 64.0;
        for (size_t i = 0; i < halo_module_describe(m).param_count; ++i) {
            const halo_param_info *info = &halo_module_describe(m).params[i];
            if (is_exponent(info) && halo_scene_set(scene, stage, info->name, &exponent, 1, 0, c->diag) != HALO_OK)
                goto done;
        }
    }
    program = halo_link(&(halo_link_desc){.library = c->lib,
                                          .scene = scene,
                                          .host_source = c->probe_source,
                                          .host_file = "probe.frag",
                                          .all_live = variant == VARIANT_LIVE,
                                          .target = c->target},
                        c->diag);
    if (!program)
        goto done;
    if (variant == VARIANT_LIVE)
        conform_set_live_arrays(program, m, c->diag);
    if (halo_diagnostics_describe(c->diag).errors > 0)
        goto done;
    probe = halo_probe_create(
        &(halo_host_desc){.gl = c->gl, .runtime = c->runtime, .program = program, .width = c->size, .height = c->size},
        c->diag);
    size_t count = (size_t)c->size * (size_t)c->size;
    samples = malloc(count * sizeof *samples);
    gpu = malloc(count * 4 * sizeof *gpu);
    if (!probe || !samples || !gpu) {
        if (!samples || !gpu)
            HALO_REPORT_ERROR(c->diag, HALO_MSG_OUT_OF_MEMORY, "", 0, 0, "out of memory");
        goto done;
    }
    conform_fill_samples(samples, c->size, c->size);
    if (halo_probe_run(probe, samples, gpu, c->diag) != HALO_OK)
        goto done;

    row_stats stats = {0};
    size_t worst_over = SIZE_MAX;
    double worst_excess = 0.0, worst_ratio = 0.0;
    for (size_t i = 0; i < count; ++i) {
        halo_emu_sample s = samples[i];
        if (halo_emu_apply(program, NULL, &s, c->diag) != HALO_OK)
            goto done;
        double emu[4], condition[4] = {0, 0, 0, 0};
        emulated_output(&s, emu);
        for (int field = 0; field < 6; ++field)
            for (int sign = -1; sign <= 1; sign += 2) {
                double moved[4];
                if (perturbed_output(program, &samples[i], field, 1.0 + sign * CONFORM_INPUT_PERTURBATION, moved))
                    for (int k = 0; k < 4; ++k)
                        condition[k] = fmax(condition[k], fabs(moved[k] - emu[k]));
            }
        int over = 0, nonfinite = 0;
        for (int k = 0; k < 4; ++k) {
            double g = gpu[i * 4 + (size_t)k];
            if (!isfinite(g) || !isfinite(emu[k])) {
                nonfinite = 1;
                continue;
            }
            double error = fabs(g - emu[k]);
            double allowed = tol->tolerance_abs + tol->tolerance_rel * fabs(emu[k]) + condition[k];
            stats.sum_squares += error * error;
            stats.values++;
            if (error > stats.max_abs) {
                stats.max_abs = error;
                stats.worst = i;
            }
            if (error / allowed > worst_ratio)
                worst_ratio = error / allowed;
            if (error > allowed) {
                over = 1;
                if (error - allowed > worst_excess) {
                    worst_excess = error - allowed;
                    worst_over = i;
                }
            }
        }
        stats.over += (size_t)over;
        stats.nonfinite += (size_t)nonfinite;
    }
    double empty[4];
    int kept = keeps_empty_kept(program, empty);
    int pass = stats.over == 0 && stats.nonfinite == 0 && kept;
    print_row(c, row, &stats, tolerance_text, pass);
    if (!kept)
        fprintf(stderr,
                "  %s says `#pragma halo is keeps_empty`, but an empty sample (value, colour, opacity and gradient 0) "
                "comes out as colour (%g, %g, %g), opacity %g\n",
                stage, empty[0], empty[1], empty[2], empty[3]);
    if (c->verbose || !pass) {
        size_t shown[2] = {stats.worst, worst_over};
        const char *labels[2] = {"largest error", "furthest over tolerance"};
        for (int j = 0; j < 2; ++j) {
            if (shown[j] == SIZE_MAX || (j == 1 && shown[1] == shown[0]))
                continue;
            halo_emu_sample s = samples[shown[j]];
            halo_emu_apply(program, NULL, &s, NULL);
            double emu[4];
            emulated_output(&s, emu);
            conform_print_sample(labels[j], &samples[shown[j]], &gpu[shown[j] * 4], emu);
        }
        if (c->verbose)
            fprintf(stderr, "  largest error / allowed: %.3g; tolerance: %s\n", worst_ratio, tol->why);
    }
    printed = 1;
done:
    free(samples);
    free(gpu);
    halo_probe_destroy(probe);
    conform_row_end(c, row, printed, program, scene);
}

/* Whether the stage's module can run at all: an error row when it has no emulation
 * (helper libraries such as halo_math are modules too, but no scene enables them:
 * those get no row). */
static int has_emulation(conform *c, const halo_module *m)
{
    if (halo_module_describe(m).has_emulation)
        return 1;
    halo_scene *probe_scene = halo_scene_create(c->lib);
    int is_stage = probe_scene && halo_scene_enable(probe_scene, halo_module_describe(m).name, 1, NULL) == HALO_OK;
    halo_scene_destroy(probe_scene);
    if (is_stage && row_selected(c, halo_module_describe(m).name, halo_module_describe(m).name)) {
        HALO_REPORT_ERROR(c->diag, HALO_MSG_EMU_MISSING, halo_module_describe(m).file, 0, 0,
                          "stage '%s' has no C emulation", halo_module_describe(m).name);
        print_error_row(c, halo_module_describe(m).name);
    }
    return 0;
}

static void run_stage_rows(conform *c, const halo_module *m, const conform_row *entry)
{
    if (!has_emulation(c, m))
        return;
    for (int v = 0; v < VARIANT_COUNT; ++v)
        if (v == VARIANT_DEFAULT || v == VARIANT_LIVE || has_exponent(m))
            run_stage_row(c, m, (enum variant)v, entry);
}

void conform_sample_rows(conform *c, const conform_row *row)
{
    const halo_module *m = halo_library_find(c->lib, row->name);
    if (!m) {
        if (row_selected(c, row->name, row->name)) {
            HALO_REPORT_ERROR(c->diag, HALO_MSG_EMU_MISSING, "", 0, 0,
                              "stage '%s' of the registry is not in the library", row->name);
            print_error_row(c, row->name);
        }
        return;
    }
    run_stage_rows(c, m, row);
}

void conform_sample_other_rows(conform *c, const conform_row *row)
{
    for (size_t i = 0; i < halo_library_describe(c->lib).module_count; ++i) {
        const halo_module *m = halo_library_describe(c->lib).modules[i];
        if (halo_module_describe(m).hook != HALO_HOOK_SAMPLE || conform_has_row(c, halo_module_describe(m).name))
            continue;
        halo_module_info info = halo_module_describe(m);
        if (info.output_count || info.image_count || info.host_uniform_count) {
            has_emulation(c, m); /* the frame family's "*" row runs those */
            continue;
        }
        run_stage_rows(c, m, row);
    }
}
