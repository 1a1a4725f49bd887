/* The conformance suite: every per-sample stage rendered through OSMesa on chosen
 * inputs and compared with its C emulation; the ray caster linked with no stage
 * compared bit for bit with the unlinked one; a whole small render compared with a C
 * emulation of the ray caster. Tolerances and their reasons: the table below and
 * docs/accuracy.md. */
#include "conform.h"
#include "conform_internal.h"
#include "conform_feature.h"
#include "conform_lines.h"
#include "conform_outline.h"
#include "conform_slice.h"

#include "halo.h"
#include "diag.h"
#include "internal.h"
#include "gl/glfuncs.h"
#include "gl/headless.h"
#include "hosts/raycast.h"
#include "volume.h"

#include <errno.h>
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
 * abs and rel (per stage, below) bound the float32 evaluation of the stage's formula
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
typedef struct stage_tolerance {
    const char *stage;
    double abs, rel;
    const char *reason;
} stage_tolerance;

static const stage_tolerance stage_tolerances[] = {
    {"gradient", 0.0, 0.0, "writes only normal and |grad f|: colour and opacity pass through bit for bit"},
    {"opacity_power", 2e-6, 8e-6,
     "one pow: llvmpipe's exp2/log2 give ~1e-6 relative for exponents up to 64 (error in the argument e*log2 x)"},
    {"boundary", 2e-6, 8e-6,
     "opacity * (k_gc + k_gs |g|^k_ge): pow as above, scaled by k_gs <= 10 on an opacity <= 1, then saturated"},
    {"silhouette", 4e-6, 8e-6,
     "opacity * (k_sc + k_ss (1-|n.V|)^k_se): k_ss = 50 multiplies pow's ~1e-7 absolute error"},
    {"orientation_fade", 2e-6, 4e-6, "RGB->HSV->RGB in float: a division by chroma and max, a few ulps each"},
    {"sketch", 4e-6, 8e-6, "pow of 1-|n.V| with exponent 8 and a colour mix: a few ulps"},
    {"tone_shading", 2e-6, 4e-6, "sums of up to four lights' dot products and mixes, no pow: a few ulps"},
    {"distance_blend", 2e-6, 4e-6, "one pow of the depth and a mix: a few ulps"},
    {"distance_cue", 2e-6, 4e-6, "a piecewise linear colour map of depth and a mix: a few ulps"},
};
/* Stages added from files: a pow and a few operations. */
static const stage_tolerance default_tolerance = {NULL, 1e-5, 1e-5, "a stage not in the table"};

/* The relative input change that models the GPU's intermediate rounding (see above). */
#define INPUT_PERTURBATION (1.0 / 2097152.0) /* 2^-21 */

/* Whole-image rows. The empty scene must not change a single bit. The ray cast row:
 * llvmpipe computes texel coordinates and trilinear weights in float32, so each fetch
 * carries ~1e-7 relative error in position (size * 2^-24 texels) and weight; central
 * differences of such values have ~1e-6 absolute error on gradients of ~0.01-0.3; the
 * enhancements scale opacities by up to k_gs = 10 and the compositing of ~100 samples
 * with pow(1 - a, step) accumulates them. Measured on llvmpipe (LLVM 15): largest
 * error 8e-6 at 25x25 pixels, 1.1e-5 at 64x64, 2.2e-5 at 128x128 (more pixels, more
 * extremes); 2e-4 absolute per channel leaves a margin of about 10. Decisions on a threshold (the 0.99 early
 * termination, the last step before the exit point) are bracketed: the emulation is
 * also run with each threshold moved by 1e-5 and the spread is allowed. */
#define RAYCAST_TOLERANCE 2e-4
#define RAYCAST_THRESHOLD_MOVE 1e-5

/* ---- Statistics and rows -------------------------------------------------------------- */

/* row_stats and conform: conform_internal.h */

int row_selected(const conform *c, const char *row, const char *stage)
{
    return !c->only || strcmp(c->only, row) == 0 || (stage && strcmp(c->only, stage) == 0);
}

void print_row(conform *c, const char *row, const row_stats *s, const char *tolerance, int pass)
{
    double rmse = s->values ? sqrt(s->sum_squares / (double)s->values) : 0.0;
    printf("%-26s %10.3e %10.3e %8zu %9zu %17s %s\n", row, s->max_abs, rmse, s->over, s->nonfinite, tolerance,
           pass ? "PASS" : "FAIL");
    fflush(stdout);
    c->rows++;
    if (!pass)
        c->failures++;
}

/* A row that could not run (link or compile error): the diagnostics say why. */
void print_error_row(conform *c, const char *row)
{
    printf("%-26s %10s %10s %8s %9s %12s FAIL\n", row, "-", "-", "-", "-", "-");
    halo_diagnostics_print(c->diag, stderr);
    halo_diagnostics_clear(c->diag);
    fflush(stdout);
    c->rows++;
    c->failures++;
}

/* ---- Probe inputs ---------------------------------------------------------------------- */

static uint64_t random_state;

static double random_uniform(void) /* splitmix64, [0, 1) */
{
    uint64_t z = (random_state += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    z ^= z >> 31;
    return (double)(z >> 11) / 9007199254740992.0;
}

static void normalize3(double v[3])
{
    double n = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    if (n > 0.0)
        for (int k = 0; k < 3; ++k)
            v[k] /= n;
}

static void set3(double out[3], double x, double y, double z)
{
    out[0] = x, out[1] = y, out[2] = z;
}

/* A (gradient, view) pair of the hard cases. */
typedef struct direction_case {
    double gradient[3];
    double view[3];
} direction_case;

/* Float one ulp above and below 1 (2^-23 and 2^-24 away). */
#define ONE_ULP_UP (1.0 + 1.0 / 8388608.0)
#define ONE_ULP_DOWN (1.0 - 1.0 / 16777216.0)

static size_t direction_cases(direction_case *out)
{
    size_t n = 0;
    double oblique[3] = {1, 2, 3}, other[3] = {-0.3, 0.5, -0.8};
    normalize3(oblique);
    normalize3(other);
    /* Round the view to float first: the host's V is a float unit vector. */
    for (int k = 0; k < 3; ++k)
        oblique[k] = (float)oblique[k], other[k] = (float)other[k];
    const double *views[] = {(const double[]){0, 0, 1}, (const double[]){0, 0, -1}, (const double[]){1, 0, 0},
                             oblique, other};
    for (size_t v = 0; v < sizeof views / sizeof views[0]; ++v) {
        const double *V = views[v];
        /* no gradient, and gradients too small to have a direction (|g|^2 < 1e-20) */
        set3(out[n].gradient, 0, 0, 0), memcpy(out[n++].view, V, 3 * sizeof *V);
        set3(out[n].gradient, 1e-12, 0, 0), memcpy(out[n++].view, V, 3 * sizeof *V);
        set3(out[n].gradient, 0, -1e-12, 1e-12), memcpy(out[n++].view, V, 3 * sizeof *V);
        /* tiny but with a direction (|g|^2 = 1e-18, above the guard) */
        for (int k = 0; k < 3; ++k)
            out[n].gradient[k] = -1e-9 * V[k];
        memcpy(out[n++].view, V, 3 * sizeof *V);
        /* n.V = +1 exactly (g = -a V: the normal points to the eye), and -1 */
        for (int k = 0; k < 3; ++k)
            out[n].gradient[k] = -0.3 * V[k];
        memcpy(out[n++].view, V, 3 * sizeof *V);
        for (int k = 0; k < 3; ++k)
            out[n].gradient[k] = 0.25 * V[k];
        memcpy(out[n++].view, V, 3 * sizeof *V);
        /* parallel, but the view one ulp longer / shorter than 1: n.V rounds past +-1 */
        for (int k = 0; k < 3; ++k) {
            out[n].gradient[k] = -0.2 * V[k];
            out[n].view[k] = V[k] * ONE_ULP_UP;
        }
        n++;
        for (int k = 0; k < 3; ++k) {
            out[n].gradient[k] = 0.45 * V[k];
            out[n].view[k] = V[k] * ONE_ULP_DOWN;
        }
        n++;
        /* perpendicular: n.V = 0 (silhouette) */
        double perpendicular[3] = {V[1] - V[2], V[2] - V[0], V[0] - V[1]};
        normalize3(perpendicular);
        for (int k = 0; k < 3; ++k)
            out[n].gradient[k] = 0.4 * perpendicular[k];
        memcpy(out[n++].view, V, 3 * sizeof *V);
        /* the largest gradient the host contract allows (|each component| <= 0.5) */
        set3(out[n].gradient, 0.5, -0.5, 0.5), memcpy(out[n++].view, V, 3 * sizeof *V);
    }
    return n;
}

/* Fills count samples: first every hard case (direction pairs x depths x opacities,
 * colours cycling), then random samples (fixed seed). Inputs are rounded to the floats
 * the probe uploads. */
static void fill_samples(halo_emu_sample *samples, int width, int height)
{
    static direction_case directions[64];
    size_t direction_count = direction_cases(directions);
    static const double depths[] = {0.0, 1.0, 0.5, 1e-7, 0.9999999};
    static const double opacities[] = {0.0, 1.0, 0.5, 0.02};
    static const double colors[][3] = {{0, 0, 0}, {1, 1, 1}, {1, 0, 0}, {0.2, 0.5, 0.9},
                                       {0.5, 0.5, 0.5}, {1, 1, 0}, {0, 0.3, 0.3}};
    static const double values[] = {0.0, 1.0, 0.5};
    static const double positions[][3] = {{0.5, 0.5, 0.5}, {0, 0, 0}, {1, 1, 1}};
    const size_t depth_count = sizeof depths / sizeof depths[0];
    const size_t opacity_count = sizeof opacities / sizeof opacities[0];
    const size_t hard = direction_count * depth_count * opacity_count;
    const size_t count = (size_t)width * (size_t)height;
    random_state = 0x68616c6f2d636f6eull; /* fixed seed: every run uses the same samples */
    for (size_t i = 0; i < count; ++i) {
        halo_emu_sample *s = &samples[i];
        memset(s, 0, sizeof *s);
        if (i < hard) {
            const direction_case *d = &directions[i % direction_count];
            memcpy(s->gradient, d->gradient, sizeof s->gradient);
            memcpy(s->view, d->view, sizeof s->view);
            s->depth = depths[(i / direction_count) % depth_count];
            s->opacity = opacities[(i / (direction_count * depth_count)) % opacity_count];
            memcpy(s->color, colors[i % (sizeof colors / sizeof colors[0])], sizeof s->color);
            s->value = values[i % 3];
            memcpy(s->position, positions[(i / 3) % 3], sizeof s->position);
        } else {
            for (int k = 0; k < 3; ++k) {
                s->position[k] = random_uniform();
                s->color[k] = random_uniform();
                s->view[k] = random_uniform() * 2.0 - 1.0;
                s->gradient[k] = random_uniform() - 0.5;
            }
            normalize3(s->view);
            /* gradient magnitudes over many scales, 1e-6 .. 0.87 */
            double scale = pow(10.0, -6.0 * random_uniform() * random_uniform());
            for (int k = 0; k < 3; ++k)
                s->gradient[k] *= scale;
            s->value = random_uniform();
            s->depth = random_uniform();
            double o = random_uniform();
            s->opacity = o < 0.05 ? 0.0 : o > 0.95 ? 1.0 : o;
        }
        halo_probe_round_inputs(s, (int)(i % (size_t)width), (int)(i / (size_t)width));
    }
}

/* ---- Per-stage rows ---------------------------------------------------------------- */

static const stage_tolerance *tolerance_of(const char *stage)
{
    for (size_t i = 0; i < sizeof stage_tolerances / sizeof stage_tolerances[0]; ++i)
        if (strcmp(stage_tolerances[i].stage, stage) == 0)
            return &stage_tolerances[i];
    return &default_tolerance;
}

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
    case 0: for (int k = 0; k < 3; ++k) s.view[k] *= factor; break;
    case 1: for (int k = 0; k < 3; ++k) s.gradient[k] *= factor; break;
    case 2: s.value *= factor; break;
    case 3: s.depth = fmin(1.0, s.depth * factor); break;
    case 4: for (int k = 0; k < 3; ++k) s.color[k] = fmin(1.0, s.color[k] * factor); break;
    default: s.opacity = fmin(1.0, s.opacity * factor); break;
    }
    if (halo_emu_apply(p, &s, NULL) != HALO_OK)
        return 0;
    emulated_output(&s, out);
    return 1;
}

static void print_sample(const char *label, const halo_emu_sample *s, const float *gpu, const double *emu)
{
    fprintf(stderr,
            "  %s: position (%.9g %.9g %.9g) value %.9g gradient (%.9g %.9g %.9g) view (%.9g %.9g %.9g)\n"
            "    depth %.9g colour (%.9g %.9g %.9g) opacity %.9g fragcoord (%.1f %.1f)\n"
            "    gpu (%.9g %.9g %.9g %.9g) emulation (%.9g %.9g %.9g %.9g)\n",
            label, s->position[0], s->position[1], s->position[2], s->value, s->gradient[0], s->gradient[1],
            s->gradient[2], s->view[0], s->view[1], s->view[2], s->depth, s->color[0], s->color[1], s->color[2],
            s->opacity, s->fragcoord[0], s->fragcoord[1], gpu[0], gpu[1], gpu[2], gpu[3], emu[0], emu[1], emu[2],
            emu[3]);
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
    for (size_t i = 0; i < halo_module_param_count(m); ++i)
        if (is_exponent(halo_module_param(m, i)))
            return 1;
    return 0;
}

/* For the live variant: arrays get several elements (up to 4), including a zero
 * vector where the range allows it, so `<name>_count` and every element are used. */
static void set_live_arrays(halo_program *p, const halo_module *m, halo_diagnostics *diag)
{
    static const double elements[4][4] = {{0.6, -0.8, 0.0, 1.0}, {0.0, 0.0, 0.0, 0.0},
                                          {-0.3, 0.5, 0.8, 0.5}, {1.0, 1.0, -1.0, 0.25}};
    for (size_t i = 0; i < halo_module_param_count(m); ++i) {
        const halo_param_info *info = halo_module_param(m, i);
        if (info->array_size < 2)
            continue;
        int count = info->array_size < 4 ? info->array_size : 4;
        double values[HALO_MAX_COMPONENTS];
        for (int e = 0; e < count; ++e)
            for (int k = 0; k < info->components; ++k) {
                double v = elements[e][k];
                values[e * info->components + k] = v < info->min ? info->min : v > info->max ? info->max : v;
            }
        halo_program_set(p, halo_module_name(m), info->name, values, count, diag);
    }
}

static void run_stage_row(conform *c, const halo_module *m, enum variant variant, const char *probe_source)
{
    const char *stage = halo_module_name(m);
    char row[128];
    snprintf(row, sizeof row, "%s%s", stage, variant_suffix[variant]);
    if (!row_selected(c, row, stage))
        return;
    const stage_tolerance *tol = tolerance_of(stage);
    char tolerance_text[32];
    snprintf(tolerance_text, sizeof tolerance_text, "%.0e+%.0er+cond", tol->abs, tol->rel);

    halo_scene *scene = halo_scene_create(c->lib);
    halo_program *program = NULL;
    halo_probe *probe = NULL;
    halo_emu_sample *samples = NULL;
    float *gpu = NULL;
    if (!scene || halo_scene_enable(scene, stage, 1, c->diag) != HALO_OK)
        goto error;
    if (variant == VARIANT_EXPONENT_0 || variant == VARIANT_EXPONENT_64) {
        double exponent = variant == VARIANT_EXPONENT_0 ? 0.0 : 64.0;
        for (size_t i = 0; i < halo_module_param_count(m); ++i) {
            const halo_param_info *info = halo_module_param(m, i);
            if (is_exponent(info) && halo_scene_set(scene, stage, info->name, &exponent, 1, 0, c->diag) != HALO_OK)
                goto error;
        }
    }
    program = halo_link(&(halo_link_desc){.library = c->lib, .scene = scene, .host_source = probe_source,
                                          .host_file = "probe.frag", .all_live = variant == VARIANT_LIVE},
                        c->diag);
    if (!program)
        goto error;
    if (variant == VARIANT_LIVE)
        set_live_arrays(program, m, c->diag);
    if (halo_diagnostics_errors(c->diag) > 0)
        goto error;
    probe = halo_probe_create(&(halo_host_desc){.gl = c->gl, .runtime = c->runtime, .program = program,
                                                .width = c->size, .height = c->size},
                              c->diag);
    size_t count = (size_t)c->size * (size_t)c->size;
    samples = malloc(count * sizeof *samples);
    gpu = malloc(count * 4 * sizeof *gpu);
    if (!probe || !samples || !gpu) {
        if (!samples || !gpu)
            halo_diag_error(c->diag, OUT_OF_MEMORY, "", 0, 0, "out of memory");
        goto error;
    }
    fill_samples(samples, c->size, c->size);
    if (halo_probe_run(probe, samples, gpu, c->diag) != HALO_OK)
        goto error;

    row_stats stats = {0};
    size_t worst_over = SIZE_MAX;
    double worst_excess = 0.0, worst_ratio = 0.0;
    for (size_t i = 0; i < count; ++i) {
        halo_emu_sample s = samples[i];
        if (halo_emu_apply(program, &s, c->diag) != HALO_OK)
            goto error;
        double emu[4], condition[4] = {0, 0, 0, 0};
        emulated_output(&s, emu);
        for (int field = 0; field < 6; ++field)
            for (int sign = -1; sign <= 1; sign += 2) {
                double moved[4];
                if (perturbed_output(program, &samples[i], field, 1.0 + sign * INPUT_PERTURBATION, moved))
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
            double allowed = tol->abs + tol->rel * fabs(emu[k]) + condition[k];
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
    int pass = stats.over == 0 && stats.nonfinite == 0;
    print_row(c, row, &stats, tolerance_text, pass);
    if (c->verbose || !pass) {
        size_t shown[2] = {stats.worst, worst_over};
        const char *labels[2] = {"largest error", "furthest over tolerance"};
        for (int j = 0; j < 2; ++j) {
            if (shown[j] == SIZE_MAX || (j == 1 && shown[1] == shown[0]))
                continue;
            halo_emu_sample s = samples[shown[j]];
            halo_emu_apply(program, &s, NULL);
            double emu[4];
            emulated_output(&s, emu);
            print_sample(labels[j], &samples[shown[j]], &gpu[shown[j] * 4], emu);
        }
        if (c->verbose)
            fprintf(stderr, "  largest error / allowed: %.3g; tolerance: %s\n", worst_ratio, tol->reason);
    }
    goto done;
error:
    print_error_row(c, row);
done:
    halo_diagnostics_clear(c->diag);
    free(samples);
    free(gpu);
    halo_probe_destroy(probe);
    halo_program_destroy(program);
    halo_scene_destroy(scene);
}

/* ---- The ray caster: empty scene and emulation ------------------------------------------ */

static void compare_images(const float *gpu, const double *reference, const double *allowed, size_t pixels,
                           row_stats *stats)
{
    memset(stats, 0, sizeof *stats);
    for (size_t i = 0; i < pixels; ++i) {
        int over = 0, nonfinite = 0;
        for (int k = 0; k < 4; ++k) {
            double g = gpu[i * 4 + (size_t)k], r = reference[i * 4 + (size_t)k];
            if (!isfinite(g) || !isfinite(r)) {
                nonfinite = 1;
                continue;
            }
            double error = fabs(g - r);
            stats->sum_squares += error * error;
            stats->values++;
            if (error > stats->max_abs) {
                stats->max_abs = error;
                stats->worst = i;
            }
            if (error > allowed[i * 4 + (size_t)k])
                over = 1;
        }
        stats->over += (size_t)over;
        stats->nonfinite += (size_t)nonfinite;
    }
}

/* Renders the built-in volume with the ray caster: linked program, or raw text. */
static float *render_raycast(conform *c, const halo_program *program, const char *raw_source,
                             const halo_scene *scene, const float *volume, int volume_size,
                             halo_raycast_state *state_out, float *transfer_out)
{
    halo_raycast *r = halo_raycast_create(&(halo_host_desc){.gl = c->gl, .runtime = c->runtime, .program = program,
                                                           .fragment_source = program ? NULL : raw_source,
                                                           .fragment_file = "raycast.frag",
                                                           .width = c->size, .height = c->size},
                                          c->diag);
    if (!r)
        return NULL;
    float *image = malloc((size_t)c->size * (size_t)c->size * 4 * sizeof *image);
    const halo_render_settings *settings = halo_scene_render(scene);
    if (!image || halo_raycast_set_volume(r, volume, volume_size, volume_size, volume_size, c->diag) != HALO_OK ||
        halo_raycast_set_render(r, settings, c->diag) != HALO_OK) {
        if (!image)
            halo_diag_error(c->diag, OUT_OF_MEMORY, "", 0, 0, "out of memory");
        free(image);
        halo_raycast_destroy(r);
        return NULL;
    }
    halo_raycast_set_camera(r, settings->azimuth, settings->elevation, settings->zoom);
    if (halo_raycast_render(r, image, c->diag) != HALO_OK) {
        free(image);
        image = NULL;
    }
    if (state_out) {
        /* the state points into the ray caster: keep a copy of its transfer table */
        halo_raycast_get_state(r, state_out);
        memcpy(transfer_out, state_out->transfer, HALO_RAYCAST_TRANSFER_TEXELS * 4 * sizeof *transfer_out);
        state_out->transfer = transfer_out;
    }
    halo_raycast_destroy(r);
    return image;
}

static void run_empty_row(conform *c, const char *host_source, const float *volume, int volume_size)
{
    if (!row_selected(c, "empty", NULL))
        return;
    halo_scene *scene = halo_scene_create(c->lib);
    halo_program *program = NULL;
    float *raw = NULL, *linked = NULL;
    if (!scene)
        goto error;
    program = halo_link(&(halo_link_desc){.library = c->lib, .scene = scene, .host_source = host_source,
                                          .host_file = "raycast.frag"},
                        c->diag);
    if (!program)
        goto error;
    raw = render_raycast(c, NULL, host_source, scene, volume, volume_size, NULL, NULL);
    linked = raw ? render_raycast(c, program, NULL, scene, volume, volume_size, NULL, NULL) : NULL;
    if (!raw || !linked)
        goto error;
    size_t pixels = (size_t)c->size * (size_t)c->size;
    row_stats stats = {0};
    for (size_t i = 0; i < pixels; ++i) {
        int differs = memcmp(&raw[i * 4], &linked[i * 4], 4 * sizeof(float)) != 0, nonfinite = 0;
        for (int k = 0; k < 4; ++k) {
            double a = raw[i * 4 + (size_t)k], b = linked[i * 4 + (size_t)k];
            if (!isfinite(a) || !isfinite(b)) {
                nonfinite = 1;
                continue;
            }
            double error = fabs(a - b);
            stats.sum_squares += error * error;
            stats.values++;
            if (error > stats.max_abs)
                stats.max_abs = error;
        }
        stats.over += (size_t)differs;
        stats.nonfinite += (size_t)nonfinite;
    }
    print_row(c, "empty", &stats, "0 (bits)", stats.over == 0 && stats.nonfinite == 0);
    goto done;
error:
    print_error_row(c, "empty");
done:
    halo_diagnostics_clear(c->diag);
    free(raw);
    free(linked);
    halo_program_destroy(program);
    halo_scene_destroy(scene);
}

/* The transfer texture lookup of raycast.frag's classify(), in double. */
static void classify(const halo_raycast_state *s, double value, double rgba[4])
{
    double v = value < 0.0 ? 0.0 : value > 1.0 ? 1.0 : value;
    int n = s->transfer_texels;
    double u = v * (n - 1); /* texel coordinate: ((v (n-1) + 0.5) / n) * n - 0.5 */
    double base = floor(u);
    double f = u - base;
    int i0 = (int)base, i1 = i0 + 1 > n - 1 ? n - 1 : i0 + 1;
    for (int k = 0; k < 4; ++k)
        rgba[k] = (1.0 - f) * s->transfer[i0 * 4 + k] + f * s->transfer[i1 * 4 + k];
}

static void transform(const double m[16], const double v[4], double out[4])
{
    for (int row = 0; row < 4; ++row)
        out[row] = m[row] * v[0] + m[4 + row] * v[1] + m[8 + row] * v[2] + m[12 + row] * v[3];
}

/* One pixel of raycast.frag, in double, with halo_emu_apply per sample. The two
 * thresholds are parameters so that the decisions on them can be bracketed. */
static int emulate_pixel(const halo_raycast_state *s, const halo_program *p, int x, int y, double threshold,
                         double exit_move, double out[4])
{
    double ndc[2] = {(x + 0.5) / s->width * 2.0 - 1.0, (y + 0.5) / s->height * 2.0 - 1.0};
    double near_point[4], far_point[4];
    transform(s->inverse_view_projection, (const double[]){ndc[0], ndc[1], -1.0, 1.0}, near_point);
    transform(s->inverse_view_projection, (const double[]){ndc[0], ndc[1], 1.0, 1.0}, far_point);
    double origin[3], direction[3];
    for (int k = 0; k < 3; ++k) {
        origin[k] = near_point[k] / near_point[3];
        direction[k] = far_point[k] / far_point[3] - origin[k];
    }
    normalize3(direction);
    double t_enter = 0.0, t_exit = INFINITY;
    for (int k = 0; k < 3; ++k) {
        double inverse = 1.0 / direction[k];
        double a = (0.0 - origin[k]) * inverse, b = (1.0 - origin[k]) * inverse;
        t_enter = fmax(t_enter, fmin(a, b));
        t_exit = fmin(t_exit, fmax(a, b));
    }
    t_exit += exit_move;
    const double radius = 0.8660254037844386;
    double centre_distance = sqrt((s->eye[0] - 0.5) * (s->eye[0] - 0.5) + (s->eye[1] - 0.5) * (s->eye[1] - 0.5) +
                                  (s->eye[2] - 0.5) * (s->eye[2] - 0.5));
    double front_distance = centre_distance - radius;
    double exponent = s->step_size / s->unit_step;
    double voxel[3] = {1.0 / s->dims[0], 1.0 / s->dims[1], 1.0 / s->dims[2]};
    double accumulated[4] = {0, 0, 0, 0};
    for (int i = 0; i < 4096; ++i) {
        double t = t_enter + i * s->step_size;
        if (t > t_exit)
            break;
        double P[3] = {origin[0] + t * direction[0], origin[1] + t * direction[1], origin[2] + t * direction[2]};
        double value = halo_volume_trilinear(s->volume, s->dims, P);
        double color[4];
        classify(s, value, color);
        halo_emu_sample sample = {0};
        memcpy(sample.position, P, sizeof P);
        sample.value = value;
        for (int k = 0; k < 3; ++k) {
            double plus[3] = {P[0], P[1], P[2]}, minus[3] = {P[0], P[1], P[2]};
            plus[k] += voxel[k];
            minus[k] -= voxel[k];
            sample.gradient[k] = (halo_volume_trilinear(s->volume, s->dims, plus) -
                                  halo_volume_trilinear(s->volume, s->dims, minus)) * 0.5;
            sample.view[k] = s->eye[k] - P[k];
        }
        double distance = sqrt(sample.view[0] * sample.view[0] + sample.view[1] * sample.view[1] +
                               sample.view[2] * sample.view[2]);
        normalize3(sample.view);
        double depth = (distance - front_distance) / (2.0 * radius);
        sample.depth = depth < 0.0 ? 0.0 : depth > 1.0 ? 1.0 : depth;
        sample.fragcoord[0] = x + 0.5;
        sample.fragcoord[1] = y + 0.5;
        memcpy(sample.color, color, 3 * sizeof *color);
        sample.opacity = color[3];
        if (halo_emu_apply(p, &sample, NULL) != HALO_OK)
            return 0;
        double alpha = sample.opacity < 0.0 ? 0.0 : sample.opacity > 1.0 ? 1.0 : sample.opacity;
        if (alpha > 0.0) {
            alpha = 1.0 - pow(1.0 - alpha, exponent);
            for (int k = 0; k < 3; ++k)
                accumulated[k] += (1.0 - accumulated[3]) * alpha * sample.color[k];
            accumulated[3] += (1.0 - accumulated[3]) * alpha;
            if (accumulated[3] >= threshold)
                break;
        }
    }
    for (int k = 0; k < 3; ++k)
        out[k] = accumulated[k] + (1.0 - accumulated[3]) * s->background[k];
    out[3] = 1.0;
    return 1;
}

/* The scene of the ray cast row: several stages with well-conditioned parameters. */
static const char raycast_scene[] =
    "{\"halo_scene\": 1, \"stages\": ["
    "{\"boundary\": {}}, {\"silhouette\": {\"k_ss\": 4, \"k_se\": 1}}, {\"tone_shading\": {}},"
    " {\"distance_blend\": {}}],"
    " \"render\": {\"azimuth\": 30, \"elevation\": 20, \"zoom\": 1.3, \"step\": 0.5}}";

static void run_raycast_row(conform *c, const char *host_source)
{
    if (!row_selected(c, "raycast", NULL))
        return;
    const int volume_size = 32;
    halo_scene *scene = NULL;
    halo_program *program = NULL;
    float *volume = NULL, *gpu = NULL;
    double *reference = NULL, *allowed = NULL;
    volume = halo_volume_create(volume_size);
    if (!volume) {
        halo_diag_error(c->diag, OUT_OF_MEMORY, "", 0, 0, "out of memory");
        goto error;
    }
    scene = halo_scene_parse(raycast_scene, "(conformance ray cast scene)", c->lib, c->diag);
    if (!scene)
        goto error;
    program = halo_link(&(halo_link_desc){.library = c->lib, .scene = scene, .host_source = host_source,
                                          .host_file = "raycast.frag"},
                        c->diag);
    if (!program)
        goto error;
    halo_raycast_state state;
    float transfer[HALO_RAYCAST_TRANSFER_TEXELS * 4];
    gpu = render_raycast(c, program, NULL, scene, volume, volume_size, &state, transfer);
    if (!gpu)
        goto error;
    state.volume = volume;
    size_t pixels = (size_t)c->size * (size_t)c->size;
    reference = malloc(pixels * 4 * sizeof *reference);
    allowed = malloc(pixels * 4 * sizeof *allowed);
    if (!reference || !allowed) {
        halo_diag_error(c->diag, OUT_OF_MEMORY, "", 0, 0, "out of memory");
        goto error;
    }
    static const double moves[][2] = {{-RAYCAST_THRESHOLD_MOVE, 0.0}, {RAYCAST_THRESHOLD_MOVE, 0.0},
                                      {0.0, -RAYCAST_THRESHOLD_MOVE}, {0.0, RAYCAST_THRESHOLD_MOVE}};
    for (int y = 0; y < c->size; ++y)
        for (int x = 0; x < c->size; ++x) {
            size_t i = (size_t)y * (size_t)c->size + (size_t)x;
            double *r = &reference[i * 4];
            if (!emulate_pixel(&state, program, x, y, 0.99, 0.0, r)) {
                halo_diag_error(c->diag, EMU_MISSING, "", 0, 0, "the ray cast scene has a stage without emulation");
                goto error;
            }
            double spread[4] = {0, 0, 0, 0};
            for (size_t m = 0; m < sizeof moves / sizeof moves[0]; ++m) {
                double moved[4];
                if (emulate_pixel(&state, program, x, y, 0.99 + moves[m][0], moves[m][1], moved))
                    for (int k = 0; k < 4; ++k)
                        spread[k] = fmax(spread[k], fabs(moved[k] - r[k]));
            }
            for (int k = 0; k < 4; ++k)
                allowed[i * 4 + (size_t)k] = RAYCAST_TOLERANCE + spread[k];
        }
    row_stats stats;
    compare_images(gpu, reference, allowed, pixels, &stats);
    char tolerance_text[32];
    snprintf(tolerance_text, sizeof tolerance_text, "%.0e", RAYCAST_TOLERANCE);
    int pass = stats.over == 0 && stats.nonfinite == 0;
    print_row(c, "raycast", &stats, tolerance_text, pass);
    if (c->verbose || !pass) {
        size_t w = stats.worst;
        fprintf(stderr, "  largest error at pixel (%zu, %zu): gpu (%.9g %.9g %.9g %.9g) emulation (%.9g %.9g %.9g %.9g)\n",
                w % (size_t)c->size, w / (size_t)c->size, gpu[w * 4], gpu[w * 4 + 1], gpu[w * 4 + 2], gpu[w * 4 + 3],
                reference[w * 4], reference[w * 4 + 1], reference[w * 4 + 2], reference[w * 4 + 3]);
    }
    goto done;
error:
    print_error_row(c, "raycast");
done:
    halo_diagnostics_clear(c->diag);
    free(volume);
    free(gpu);
    free(reference);
    free(allowed);
    halo_program_destroy(program);
    halo_scene_destroy(scene);
}

/* ---- Volumetric halos: stages with images, outputs and host uniforms; image passes --------
 *
 * These rows run through the GL runtime's frame (halo_gl_frame_*: images, attached outputs,
 * bound samplers, the pass schedule) and compare with the emulation's frame
 * (halo_emu_frame_*). The probe host is drawn by conform itself (it needs the output
 * attachments and the image samplers, which halo_probe does not set up). */

/* The image-plane axes the frame rows use (oblique, so that both matter), as floats. */
void host_axes(double right[3], double up[3])
{
    const double a = 0.3, b = 0.4;
    double r[3] = {cos(a), sin(a), 0.0}, u[3] = {-sin(a) * cos(b), cos(a) * cos(b), sin(b)};
    for (int k = 0; k < 3; ++k)
        right[k] = (float)r[k], up[k] = (float)u[k];
}

/* Sampler host uniforms of the frame rows (e.g. outline_feature's "labels"): a small
 * volume of integer labels, the same in GL (unit 15) and in the emulation
 * (halo_emu_frame_set_volume); sampler2D host uniforms get a 1x1 texture on unit 14.
 * GL needs a texture of the sampler's own type on a unit of its own: the default unit 0
 * holds the probe's sampler2D inputs, and two sampler types on one unit are
 * GL_INVALID_OPERATION at draw. */
/* PROBE_VOLUME_*, PROBE_UNIT_*: conform_internal.h */

const float *probe_label_volume(void)
{
    static float labels[PROBE_VOLUME_X * PROBE_VOLUME_Y * PROBE_VOLUME_Z];
    for (int z = 0; z < PROBE_VOLUME_Z; ++z)
        for (int y = 0; y < PROBE_VOLUME_Y; ++y)
            for (int x = 0; x < PROBE_VOLUME_X; ++x)
                labels[(z * PROBE_VOLUME_Y + y) * PROBE_VOLUME_X + x] = (float)((x + 2 * y + 3 * z) % 4);
    return labels;
}

/* frame_probe: conform_internal.h */

void frame_probe_release(frame_probe *fp)
{
    const halo_glfuncs *f = fp->f;
    if (f) {
        if (fp->framebuffer)
            f->DeleteFramebuffers(1, &fp->framebuffer);
        if (fp->color)
            f->DeleteTextures(1, &fp->color);
        if (fp->inputs[0])
            f->DeleteTextures(4, fp->inputs);
        if (fp->vertex_array)
            f->DeleteVertexArrays(1, &fp->vertex_array);
        if (fp->host_textures[0])
            f->DeleteTextures(2, fp->host_textures);
        if (fp->program)
            f->DeleteProgram(fp->program);
    }
    free(fp->staging);
    memset(fp, 0, sizeof *fp);
}

int frame_probe_init(conform *c, const halo_program *p, frame_probe *fp)
{
    memset(fp, 0, sizeof *fp);
    const halo_glfuncs *f = c->gl;
    fp->f = f;
    fp->size = c->size;
    const char *vertex = halo_host_embedded("raycast.vert");
    fp->program = vertex ? halo_gl_program_build(c->runtime, p, vertex, "raycast.vert", c->diag) : 0;
    fp->staging = malloc((size_t)c->size * (size_t)c->size * 4 * sizeof *fp->staging);
    if (!fp->program || !fp->staging)
        return 0;
    f->GenVertexArrays(1, &fp->vertex_array);
    f->GenTextures(4, fp->inputs);
    f->GenTextures(1, &fp->color);
    for (int i = 0; i < 5; ++i) {
        f->BindTexture(GL_TEXTURE_2D, i < 4 ? fp->inputs[i] : fp->color);
        f->TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
        f->TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
        f->TexImage2D(GL_TEXTURE_2D, 0, GL_RGBA32F, c->size, c->size, 0, GL_RGBA, GL_FLOAT, NULL);
    }
    f->BindTexture(GL_TEXTURE_2D, 0);
    f->GenTextures(2, fp->host_textures);
    f->BindTexture(GL_TEXTURE_3D, fp->host_textures[0]);
    f->TexParameteri(GL_TEXTURE_3D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    f->TexParameteri(GL_TEXTURE_3D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    f->PixelStorei(GL_UNPACK_ALIGNMENT, 4);
    f->TexImage3D(GL_TEXTURE_3D, 0, GL_R32F, PROBE_VOLUME_X, PROBE_VOLUME_Y, PROBE_VOLUME_Z, 0, GL_RED, GL_FLOAT,
                  probe_label_volume());
    f->BindTexture(GL_TEXTURE_3D, 0);
    f->BindTexture(GL_TEXTURE_2D, fp->host_textures[1]);
    f->TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    f->TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    f->TexImage2D(GL_TEXTURE_2D, 0, GL_RGBA32F, 1, 1, 0, GL_RGBA, GL_FLOAT, (const float[]){0, 0, 0, 0});
    f->BindTexture(GL_TEXTURE_2D, 0);
    f->GenFramebuffers(1, &fp->framebuffer);
    f->BindFramebuffer(GL_FRAMEBUFFER, fp->framebuffer);
    f->FramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, fp->color, 0);
    GLenum status = f->CheckFramebufferStatus(GL_FRAMEBUFFER);
    f->BindFramebuffer(GL_FRAMEBUFFER, 0);
    if (status != GL_FRAMEBUFFER_COMPLETE) {
        halo_diag_error(c->diag, GL_LINK, "", 0, 0, "frame probe: incomplete framebuffer (0x%x)", status);
        return 0;
    }
    return 1;
}

/* Draws probe.frag once over samples (one per pixel) with the frame's outputs attached and
 * images bound; reads colour and opacity back into rgba (may be NULL). */
halo_status frame_probe_draw(conform *c, frame_probe *fp, const halo_program *p, halo_gl_frame *frame,
                                    const halo_emu_sample *samples, float *rgba)
{
    const halo_glfuncs *f = fp->f;
    size_t n = (size_t)fp->size * (size_t)fp->size;
    static const char *const names[4] = {"position_value", "gradient_depth", "view_texture", "color_opacity"};
    for (int t = 0; t < 4; ++t) {
        for (size_t i = 0; i < n; ++i) {
            const halo_emu_sample *s = &samples[i];
            float *d = &fp->staging[i * 4];
            const double *v = t == 0 ? s->position : t == 1 ? s->gradient : t == 2 ? s->view : s->color;
            double w = t == 0 ? s->value : t == 1 ? s->depth : t == 2 ? 0.0 : s->opacity;
            d[0] = (float)v[0], d[1] = (float)v[1], d[2] = (float)v[2], d[3] = (float)w;
        }
        f->BindTexture(GL_TEXTURE_2D, fp->inputs[t]);
        f->PixelStorei(GL_UNPACK_ALIGNMENT, 4);
        f->TexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, fp->size, fp->size, GL_RGBA, GL_FLOAT, fp->staging);
    }
    f->BindTexture(GL_TEXTURE_2D, 0);
    f->Disable(GL_BLEND);
    f->Disable(GL_DEPTH_TEST);
    f->Disable(GL_SCISSOR_TEST);
    f->BindFramebuffer(GL_FRAMEBUFFER, fp->framebuffer);
    halo_gl_frame_attach(frame, fp->framebuffer);
    f->Viewport(0, 0, fp->size, fp->size);
    f->UseProgram(fp->program);
    halo_gl_program_upload(c->runtime, p, fp->program);
    for (int t = 0; t < 4; ++t) {
        f->ActiveTexture(GL_TEXTURE0 + (GLenum)t);
        f->BindTexture(GL_TEXTURE_2D, fp->inputs[t]);
        f->Uniform1i(f->GetUniformLocation(fp->program, names[t]), t);
    }
    f->ActiveTexture(GL_TEXTURE0);
    halo_gl_frame_bind(frame, fp->program, 4);
    double right[3], up[3];
    host_axes(right, up);
    float fr[3] = {(float)right[0], (float)right[1], (float)right[2]}, fu[3] = {(float)up[0], (float)up[1], (float)up[2]};
    for (size_t i = 0; i < halo_program_host_uniform_count(p); ++i) {
        const char *name = halo_program_host_uniform(p, i)->name;
        if (strstr(name, "screen_right"))
            halo_gl_set_host_uniform(c->runtime, fp->program, name, fr, 3);
        else if (strstr(name, "screen_up"))
            halo_gl_set_host_uniform(c->runtime, fp->program, name, fu, 3);
        else if (!strcmp(halo_program_host_uniform(p, i)->type, "sampler3D")) {
            f->ActiveTexture(GL_TEXTURE0 + PROBE_UNIT_3D);
            f->BindTexture(GL_TEXTURE_3D, fp->host_textures[0]);
            halo_gl_set_host_uniform(c->runtime, fp->program, name, (const float[]){PROBE_UNIT_3D}, 1);
        } else if (!strncmp(halo_program_host_uniform(p, i)->type, "sampler", 7)) {
            f->ActiveTexture(GL_TEXTURE0 + PROBE_UNIT_2D);
            f->BindTexture(GL_TEXTURE_2D, fp->host_textures[1]);
            halo_gl_set_host_uniform(c->runtime, fp->program, name, (const float[]){PROBE_UNIT_2D}, 1);
        }
    }
    f->ActiveTexture(GL_TEXTURE0);
    f->BindVertexArray(fp->vertex_array);
    f->DrawArrays(GL_TRIANGLES, 0, 3);
    f->BindVertexArray(0);
    if (rgba) {
        f->ReadBuffer(GL_COLOR_ATTACHMENT0);
        f->PixelStorei(GL_PACK_ALIGNMENT, 4);
        f->ReadPixels(0, 0, fp->size, fp->size, GL_RGBA, GL_FLOAT, rgba);
    }
    f->ActiveTexture(GL_TEXTURE0 + PROBE_UNIT_3D);
    f->BindTexture(GL_TEXTURE_3D, 0);
    f->ActiveTexture(GL_TEXTURE0 + PROBE_UNIT_2D);
    f->BindTexture(GL_TEXTURE_2D, 0);
    for (int t = 3; t >= 0; --t) {
        f->ActiveTexture(GL_TEXTURE0 + (GLenum)t);
        f->BindTexture(GL_TEXTURE_2D, 0);
    }
    f->UseProgram(0);
    f->Disable(GL_BLEND);
    f->BindFramebuffer(GL_FRAMEBUFFER, 0);
    GLenum error = f->GetError();
    if (error != GL_NO_ERROR) {
        halo_diag_error(c->diag, GL_LINK, "", 0, 0, "OpenGL error 0x%x while drawing the frame probe", error);
        return HALO_ERROR_IO;
    }
    return HALO_OK;
}

void emu_set_axes(halo_emu_frame *ef)
{
    double right[3], up[3];
    host_axes(right, up);
    halo_emu_frame_set_host_uniform(ef, "screen_right", right, 3);
    halo_emu_frame_set_host_uniform(ef, "screen_up", up, 3);
}

/* One sample through the emulated frame: colour, opacity and the seed (8 values). Does
 * not fold into the frame's images (finish is separate). */
static int emulate_frame_sample(const halo_program *p, halo_emu_frame *ef, halo_emu_sample *s, double out[8])
{
    memset(s->output_accum, 0, sizeof s->output_accum);
    if (halo_emu_apply_frame(p, ef, s, NULL) != HALO_OK)
        return 0;
    out[0] = s->color[0], out[1] = s->color[1], out[2] = s->color[2], out[3] = s->opacity;
    for (int k = 0; k < 4; ++k)
        out[4 + k] = s->output_accum[k];
    return 1;
}

static int program_has_image(const halo_program *p, const char *name)
{
    for (size_t i = 0; i < halo_program_image_count(p); ++i)
        if (!strcmp(halo_program_image(p, i)->name, name))
            return 1;
    return 0;
}

void emu_set_probe_volumes(const halo_program *p, halo_emu_frame *ef)
{
    for (size_t i = 0; i < halo_program_host_uniform_count(p); ++i)
        if (!strcmp(halo_program_host_uniform(p, i)->type, "sampler3D"))
            halo_emu_frame_set_volume(ef, halo_program_host_uniform(p, i)->name + strlen("halo_host_"),
                                      probe_label_volume(), PROBE_VOLUME_X, PROBE_VOLUME_Y, PROBE_VOLUME_Z);
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
    if (halo_emu_apply_frame(p, one, &s, NULL) != HALO_OK)
        return 0;
    halo_emu_frame_finish(one, &s);
    int n = 0;
    for (size_t i = 0; i < halo_program_image_count(p); ++i) {
        const halo_image_info *info = halo_program_image(p, i);
        int written = 0;
        for (size_t o = 0; o < halo_program_output_count(p); ++o)
            written |= !strcmp(halo_program_output(p, o)->image, info->name);
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
    size_t images = halo_program_image_count(p);
    float **gl_images = calloc(images ? images : 1, sizeof *gl_images);
    halo_emu_frame *one = halo_emu_frame_create(p, 1, 1, c->diag);
    int ok = 0;
    if (!gl_images || !one)
        goto out;
    emu_set_axes(one);
    emu_set_probe_volumes(p, one);
    for (size_t i = 0; i < images; ++i) {
        const halo_image_info *info = halo_program_image(p, i);
        int written = 0;
        for (size_t o = 0; o < halo_program_output_count(p); ++o)
            written |= !strcmp(halo_program_output(p, o)->image, info->name);
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
        if (halo_emu_apply_frame(p, eframe, &s, c->diag) != HALO_OK)
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
            int ch = halo_program_image(p, m)->channels;
            const double *e = halo_emu_frame_image(eframe, halo_program_image(p, m)->name);
            for (int k = 0; k < ch && n < 4 + MAX_VALUES; ++k)
                emu[n] = e[i * (size_t)ch + (size_t)k], g[n++] = gl_images[m][i * (size_t)ch + (size_t)k];
        }
        for (int field = 0; field < 6; ++field)
            for (int sign = -1; sign <= 1; sign += 2) {
                halo_emu_sample moved = samples[i];
                double factor = 1.0 + sign * INPUT_PERTURBATION, out[8];
                switch (field) {
                case 0: for (int k = 0; k < 3; ++k) moved.view[k] *= factor; break;
                case 1: for (int k = 0; k < 3; ++k) moved.gradient[k] *= factor; break;
                case 2: moved.value *= factor; break;
                case 3: for (int k = 0; k < 3; ++k) moved.position[k] *= factor; break;
                case 4: for (int k = 0; k < 3; ++k) moved.color[k] = fmin(1.0, moved.color[k] * factor); break;
                default: moved.opacity = fmin(1.0, moved.opacity * factor); break;
                }
                halo_emu_sample copy = moved;
                if (emulate_frame_sample(p, eframe, &copy, out))
                    for (int k = 0; k < 4; ++k)
                        condition[k] = fmax(condition[k], fabs(out[k] - emu[k]));
                if (emulate_output_pixel(p, one, &moved, one_px, MAX_VALUES, &nv))
                    for (int k = 0; k < nv && 4 + k < n; ++k)
                        condition[4 + k] = fmax(condition[4 + k], fabs(one_px[k] - emu[4 + k]));
            }
        int over = 0, nonfinite = 0;
        for (int k = 0; k < n; ++k) {
            if (!isfinite(g[k]) || !isfinite(emu[k])) {
                nonfinite = 1;
                continue;
            }
            double error = fabs(g[k] - emu[k]), allowed = tol_abs + tol_rel * fabs(emu[k]) + condition[k];
            stats.sum_squares += error * error;
            stats.values++;
            if (error > stats.max_abs)
                stats.max_abs = error, stats.worst = i;
            if (error > allowed)
                over = 1, worst_over = i;
        }
        stats.over += (size_t)over;
        stats.nonfinite += (size_t)nonfinite;
    }
    int pass = stats.over == 0 && stats.nonfinite == 0;
    print_row(c, row, &stats, tolerance_text, pass);
    if (c->verbose || !pass) {
        size_t shown = worst_over != SIZE_MAX ? worst_over : stats.worst;
        halo_emu_sample s = samples[shown];
        double emu[8];
        emulate_frame_sample(p, eframe, &s, emu);
        print_sample(worst_over != SIZE_MAX ? "over tolerance" : "largest error", &samples[shown], &gpu[shown * 4],
                     emu);
        for (size_t m = 0; m < images; ++m) {
            if (!gl_images[m])
                continue;
            int ch = halo_program_image(p, m)->channels;
            const double *e = halo_emu_frame_image(eframe, halo_program_image(p, m)->name);
            fprintf(stderr, "    %-16s gpu", halo_program_image(p, m)->name);
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
        halo_diag_error(c->diag, EMU_MISSING, "", 0, 0, "row %s: an output image could not be read or emulated", row);
    for (size_t i = 0; gl_images && i < images; ++i)
        free(gl_images[i]);
    free(gl_images);
    halo_emu_frame_destroy(one);
    return ok;
}

/* Scenes of the frame rows of the volumetric-halo stages. */
typedef struct frame_variant {
    const char *suffix;
    const char *scene; /* JSON; NULL = the module's defaults */
    int live;
} frame_variant;

static const frame_variant seed_variants[] = {
    {"", NULL, 0},
    {"@halos2",
     "{\"halo_scene\": 1, \"stages\": [{\"halo_seed\": {\"alpha\": [32, 4], \"beta\": [0.125, 1],"
     " \"gradient_scale\": [2, 5], \"value_0\": [[0.2, 0], [0.5, 1], [0.8, 0]], \"value_1\": [[0, 1], [1, 0.2]],"
     " \"direction_center\": [0, 90], \"direction_width\": [360, 120], \"direction_softness\": [30, 0],"
     " \"focus\": [[0.5, 0.5, 0.5], [0.3, 0.6, 0.5]], \"focus_radius\": [10, 0.3],"
     " \"focus_transition\": [0, 0.2]}}]}",
     0},
    {"@halos4",
     "{\"halo_scene\": 1, \"stages\": [{\"halo_seed\": {\"alpha\": [1, 2, 8, 32], \"beta\": [0, 0.5, 2, 0.125],"
     " \"direction_center\": [-135, 180, 45, 0], \"direction_width\": [180, 90, 0, 359],"
     " \"direction_softness\": [30, 180, 10, 0], \"focus_radius\": [0.4, 0, 10, 0.5],"
     " \"focus_transition\": [0, 0.5, 0, 10], \"value_2\": [[0.5, 0.3]], \"value_3\": [[0.1, 0], [0.1, 1]]}}]}",
     0},
    {"@live", NULL, 1},
};

static const frame_variant map_variants[] = {
    {"",
     "{\"halo_scene\": 1, \"stages\": [{\"halo_seed\": {\"alpha\": 1, \"gradient_scale\": 20}},"
     " {\"halo_generate\": {\"delta\": 0.9}}, {\"halo_map\": {\"color_near\": [[1, 0.5, 0]],"
     " \"color_far\": [[0, 0, 1]], \"full_at\": 0.5, \"profile_exponent\": 2, \"opacity\": 0.8}}]}",
     0},
    {"@halos2",
     "{\"halo_scene\": 1, \"stages\": [{\"halo_seed\": {\"alpha\": [1, 2], \"gradient_scale\": [20, 10]}},"
     " {\"halo_generate\": {\"delta\": [0.9, 0.7]}}, {\"halo_map\": {\"mode\": [0, 1],"
     " \"color_near\": [[1, 0.5, 0], [0, 0, 0]], \"color_far\": [[0, 0, 1], [0.2, 0.2, 0.2]],"
     " \"full_at\": [0.5, 0.01], \"profile_exponent\": [2, 0], \"opacity\": [0.8, 1]}}]}",
     0},
    {"@halos4",
     "{\"halo_scene\": 1, \"stages\": [{\"halo_seed\": {\"alpha\": 1, \"gradient_scale\": [20, 10, 5, 50]}},"
     " {\"halo_generate\": {\"delta\": [0.9, 0.7, 0.5, 1], \"passes\": 3}}, {\"halo_map\": {\"mode\": [1, 0, 0.5, 0.2],"
     " \"color_near\": [[1, 0, 0], [0, 1, 0], [0, 0, 1], [1, 1, 1]], \"color_far\": [[0, 0, 0]],"
     " \"full_at\": [1, 0.2, 0.05, 0.5], \"profile_exponent\": [1, 64, 0.5, 3], \"opacity\": [1, 0.5, 0.25, 0.9]}}]}",
     0},
    {"@live", NULL, 1},
};

#define SEED_TOLERANCE_ABS 1e-5
#define SEED_TOLERANCE_REL 1e-5
#define MAP_TOLERANCE_ABS 2e-6
#define MAP_TOLERANCE_REL 4e-6

/* halo_seed and halo_map, and any stage with outputs, images or host uniforms: the probe
 * is drawn through a frame. halo_map's program also holds halo_seed and halo_generate: the
 * first draw seeds, the GPU generates, the GPU's field and occlusion images are copied
 * into the emulated frame, and the second draw is compared (so that this row measures
 * halo_map alone; the pass rows measure the images). halo_seed's rows also compare the
 * seed image (max over the one fragment of each pixel). */
static void run_frame_stage_row(conform *c, const halo_module *m, const frame_variant *v, const char *probe_source)
{
    const char *stage = halo_module_name(m);
    char row[128];
    snprintf(row, sizeof row, "%s%s", stage, v->suffix);
    if (!row_selected(c, row, stage))
        return;
    int is_map = m->image_count > 0;
    double tol_abs = is_map ? MAP_TOLERANCE_ABS : SEED_TOLERANCE_ABS;
    double tol_rel = is_map ? MAP_TOLERANCE_REL : SEED_TOLERANCE_REL;
    char tolerance_text[32];
    snprintf(tolerance_text, sizeof tolerance_text, "%.0e+%.0er+cond", tol_abs, tol_rel);
    halo_scene *scene = NULL;
    halo_program *program = NULL;
    halo_gl_frame *gframe = NULL;
    halo_emu_frame *eframe = NULL;
    frame_probe fp = {0};
    halo_emu_sample *samples = NULL;
    float *gpu = NULL, *gpu_seed = NULL, *image = NULL;
    size_t count = (size_t)c->size * (size_t)c->size;
    if (v->scene)
        scene = halo_scene_parse(v->scene, "(conformance frame scene)", c->lib, c->diag);
    else if ((scene = halo_scene_create(c->lib)) && halo_scene_enable(scene, stage, 1, c->diag) != HALO_OK)
        goto error;
    if (!scene)
        goto error;
    program = halo_link(&(halo_link_desc){.library = c->lib, .scene = scene, .host_source = probe_source,
                                          .host_file = "probe.frag", .all_live = v->live},
                        c->diag);
    if (!program)
        goto error;
    if (v->live)
        set_live_arrays(program, m, c->diag);
    if (halo_diagnostics_errors(c->diag) > 0)
        goto error;
    int channels = halo_program_channel_count(program);
    samples = malloc(count * sizeof *samples);
    gpu = malloc(count * 4 * sizeof *gpu);
    gpu_seed = malloc(count * 4 * sizeof *gpu_seed);
    image = malloc(count * 4 * sizeof *image);
    if (!samples || !gpu || !gpu_seed || !image) {
        halo_diag_error(c->diag, OUT_OF_MEMORY, "", 0, 0, "out of memory");
        goto error;
    }
    fill_samples(samples, c->size, c->size);
    gframe = halo_gl_frame_create(c->runtime, program, c->size, c->size, c->diag);
    eframe = halo_emu_frame_create(program, c->size, c->size, c->diag);
    if (!gframe || !eframe || !frame_probe_init(c, program, &fp))
        goto error;
    emu_set_axes(eframe);
    emu_set_probe_volumes(program, eframe);
    halo_gl_frame_begin(gframe);
    halo_emu_frame_begin(eframe);
    if (frame_probe_draw(c, &fp, program, gframe, samples, gpu) != HALO_OK)
        goto error;
    if (!is_map && !program_has_image(program, "seed")) {
        /* outputs other than seed (outline_feature): compare every output image */
        if (!compare_output_images(c, row, program, gframe, eframe, samples, gpu, tol_abs, tol_rel, tolerance_text))
            goto error;
        goto done;
    }
    if (is_map) {
        /* generate on the GPU; the emulation continues from the GPU's images */
        halo_gl_frame_generate(gframe);
        for (size_t i = 0; i < halo_program_image_count(program); ++i) {
            const char *name = halo_program_image(program, i)->name;
            if (halo_gl_frame_read(gframe, name, image) != HALO_OK)
                goto error;
            double *e = halo_emu_frame_image(eframe, name);
            for (size_t k = 0; k < count * (size_t)channels; ++k)
                e[k] = image[k];
        }
        if (frame_probe_draw(c, &fp, program, gframe, samples, gpu) != HALO_OK)
            goto error;
    } else if (halo_gl_frame_read(gframe, "seed", gpu_seed) != HALO_OK) {
        goto error;
    }
    row_stats stats = {0};
    size_t worst_over = SIZE_MAX;
    int values = is_map ? 4 : 4 + channels;
    for (size_t i = 0; i < count; ++i) {
        halo_emu_sample s = samples[i];
        double emu[8], condition[8] = {0};
        if (!emulate_frame_sample(program, eframe, &s, emu)) {
            halo_diag_error(c->diag, EMU_MISSING, "", 0, 0, "a stage of row %s has no emulation", row);
            goto error;
        }
        for (int field = 0; field < 6; ++field)
            for (int sign = -1; sign <= 1; sign += 2) {
                halo_emu_sample moved = samples[i];
                double factor = 1.0 + sign * INPUT_PERTURBATION, out[8];
                switch (field) {
                case 0: for (int k = 0; k < 3; ++k) moved.view[k] *= factor; break;
                case 1: for (int k = 0; k < 3; ++k) moved.gradient[k] *= factor; break;
                case 2: moved.value *= factor; break;
                case 3: for (int k = 0; k < 3; ++k) moved.position[k] *= factor; break;
                case 4: for (int k = 0; k < 3; ++k) moved.color[k] = fmin(1.0, moved.color[k] * factor); break;
                default: moved.opacity = fmin(1.0, moved.opacity * factor); break;
                }
                if (emulate_frame_sample(program, eframe, &moved, out))
                    for (int k = 0; k < 8; ++k)
                        condition[k] = fmax(condition[k], fabs(out[k] - emu[k]));
            }
        int over = 0, nonfinite = 0;
        for (int k = 0; k < values; ++k) {
            double g = k < 4 ? gpu[i * 4 + (size_t)k] : gpu_seed[i * (size_t)channels + (size_t)(k - 4)];
            if (!isfinite(g) || !isfinite(emu[k])) {
                nonfinite = 1;
                continue;
            }
            double error = fabs(g - emu[k]), allowed = tol_abs + tol_rel * fabs(emu[k]) + condition[k];
            stats.sum_squares += error * error;
            stats.values++;
            if (error > stats.max_abs)
                stats.max_abs = error, stats.worst = i;
            if (error > allowed)
                over = 1, worst_over = i;
        }
        stats.over += (size_t)over;
        stats.nonfinite += (size_t)nonfinite;
    }
    int pass = stats.over == 0 && stats.nonfinite == 0;
    print_row(c, row, &stats, tolerance_text, pass);
    if (c->verbose || !pass) {
        size_t shown = worst_over != SIZE_MAX ? worst_over : stats.worst;
        halo_emu_sample s = samples[shown];
        double emu[8];
        emulate_frame_sample(program, eframe, &s, emu);
        print_sample(worst_over != SIZE_MAX ? "over tolerance" : "largest error", &samples[shown], &gpu[shown * 4],
                     emu);
        if (!is_map)
            fprintf(stderr, "    seed gpu (%.9g %.9g %.9g %.9g) emulation (%.9g %.9g %.9g %.9g)\n",
                    gpu_seed[shown * (size_t)channels], channels > 1 ? gpu_seed[shown * (size_t)channels + 1] : 0.0,
                    channels > 2 ? gpu_seed[shown * (size_t)channels + 2] : 0.0,
                    channels > 3 ? gpu_seed[shown * (size_t)channels + 3] : 0.0, emu[4], emu[5], emu[6], emu[7]);
    }
    goto done;
error:
    print_error_row(c, row);
done:
    halo_diagnostics_clear(c->diag);
    frame_probe_release(&fp);
    halo_gl_frame_destroy(gframe);
    halo_emu_frame_destroy(eframe);
    free(samples);
    free(gpu);
    free(gpu_seed);
    free(image);
    halo_program_destroy(program);
    halo_scene_destroy(scene);
}

/* ---- Pass rows: halo_generate's passes on chosen seed images ---- */

/* A sample stage that writes its colour and opacity as the seeds: the pass rows draw any
 * seed image through the host and the frame's seed output. */
static const char conform_seed_module[] =
    "#pragma halo module conform_seed\n"
    "#pragma halo summary \"conformance: seeds = (r, g, b, opacity) of the sample\"\n"
    "#pragma halo hook sample\n"
    "#pragma halo provides seed channels\n"
    "#pragma halo output seed max\n"
    "void apply(inout halo_sample s) { s.seed = halo_channels_from(vec4(s.color, s.opacity)); }\n";

enum { SEED_EMPTY, SEED_FULL, SEED_PIXEL, SEED_BORDER, SEED_DISCS, SEED_NOISE, SEED_CASES };
static const char *const seed_case_names[SEED_CASES] = {"empty", "full", "single pixel", "border", "discs", "noise"};

/* Seed image case `which` for one channel, as floats (what the GPU's seed image holds). */
static double seed_case(int which, int x, int y, int size)
{
    int c0 = size / 2;
    switch (which) {
    case SEED_EMPTY: return 0.0;
    case SEED_FULL: return 1.0;
    case SEED_PIXEL: return x == c0 && y == c0 ? 1.0 : 0.0;
    case SEED_BORDER: {
        int last = size - 1;
        if ((x == 0 || x == last) && (y == 0 || y == last)) return 1.0;
        if (x == 0 && y % 3 == 0) return 1.0;
        if (x == last && y % 4 == 1) return 0.75;
        if (y == 0 && x % 5 == 2) return 1.0;
        if (y == last && x % 2 == 0) return 0.5;
        return 0.0;
    }
    case SEED_DISCS: {
        static const double discs[][4] = {{0.25, 0.3, 1, 0.7}, {0.6, 0.35, 3, 1.0}, {0.35, 0.7, 6, 0.35}, {0.8, 0.8, 2, 1.0}};
        for (size_t d = 0; d < sizeof discs / sizeof discs[0]; ++d) {
            double dx = x - discs[d][0] * size, dy = y - discs[d][1] * size;
            if (dx * dx + dy * dy <= discs[d][2] * discs[d][2]) return discs[d][3];
        }
        return 0.0;
    }
    default: {
        uint64_t z = (uint64_t)(y * size + x) * 0x9e3779b97f4a7c15ull + 0x1234567ull;
        z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
        z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
        z ^= z >> 31;
        double u = (double)(z >> 11) / 9007199254740992.0;
        return u < 0.3 ? 0.0 : (float)u;
    }
    }
}

typedef struct pass_row {
    const char *name;
    const char *generate;   /* halo_generate's parameters (JSON object) */
    const char *compare[3]; /* images compared after the generation(s) */
    int generations;        /* 2: a second generation on the next case, in the same frame */
    double tolerance;
    const char *reason;
    int scale;              /* halo_link_desc.image_scale: the pass images at 1/scale (0: 1) */
} pass_row;

static const pass_row pass_rows[] = {
    {"pass:median", "{\"median\": true, \"passes\": 1}", {"initial"}, 1, 3e-7,
     "the median selects an input value (exact); the gradient after it: one sqrt of a sum of squares, ~1 ulp", 1},
    {"pass:gradient", "{\"passes\": 1}", {"initial"}, 1, 3e-7,
     "differences of exact seeds, sqrt of a sum of two squares: ~1 ulp of a value <= 1", 1},
    {"pass:spread@N1", "{\"passes\": 1}", {"field"}, 1, 2e-6,
     "float32 sums of 9 taps and a mix per pass (~1e-7 each), gain <= 1 from pass to pass", 1},
    {"pass:spread@N2", "{\"passes\": 2}", {"field"}, 1, 2e-6, "as N1, over 2 passes", 1},
    {"pass:spread@N3", "{\"passes\": 3}", {"field"}, 1, 2e-6, "as N1, over 3 passes", 1},
    {"pass:spread@N4", "{\"passes\": 4}", {"field"}, 1, 2e-6, "as N1, over 4 passes", 1},
    {"pass:spread@delta0", "{\"passes\": 4, \"delta\": 0}", {"field"}, 1, 3e-7, "delta 0: H_N = H_0 exactly", 1},
    {"pass:spread@delta1", "{\"passes\": 4, \"delta\": 1}", {"field"}, 1, 2e-6, "as N4", 1},
    {"pass:occlude", "{\"passes\": 4}", {"occlusion", "field"}, 2, 2e-6,
     "max of two fields (exact) over 2 generations in one frame: the spreading's error", 1},
    {"pass:halos2", "{\"passes\": 4, \"delta\": [0.7, 0.95]}", {"initial", "field", "occlusion"}, 1, 2e-6,
     "two halos (vec2 images): as N4 per channel", 1},
    {"pass:halos4", "{\"passes\": 3, \"delta\": [0, 0.5, 0.8, 1], \"median\": true}", {"initial", "field", "occlusion"},
     2, 2e-6, "four halos (vec4 images), median on: as N4 per channel", 1},
    /* halo images at 1/2 and 1/4 of the frame (an odd frame size gives partial blocks):
     * the first pass max-downsamples the full-size seed (exact), the rest as above */
    {"pass:spread@half", "{\"passes\": 4}", {"initial", "field"}, 1, 2e-6, "as N4 on the 1/2 images", 2},
    {"pass:halos4@quarter", "{\"passes\": 3, \"delta\": [0, 0.5, 0.8, 1], \"median\": true}",
     {"initial", "field", "occlusion"}, 2, 2e-6, "as halos4 on the 1/4 images", 4},
};

static void run_pass_row(conform *c, halo_library *lib, const pass_row *r, const char *probe_source)
{
    if (!row_selected(c, r->name, NULL))
        return;
    char json[512], tolerance_text[32];
    snprintf(json, sizeof json, "{\"halo_scene\": 1, \"stages\": [\"conform_seed\", {\"halo_generate\": %s}]}",
             r->generate);
    snprintf(tolerance_text, sizeof tolerance_text, "%.0e", r->tolerance);
    halo_scene *scene = halo_scene_parse(json, "(conformance pass scene)", lib, c->diag);
    halo_program *program = NULL;
    halo_gl_frame *gframe = NULL;
    halo_emu_frame *eframe = NULL;
    frame_probe fp = {0};
    size_t count = (size_t)c->size * (size_t)c->size;
    halo_emu_sample *samples = calloc(count, sizeof *samples);
    float *image = malloc(count * 4 * sizeof *image);
    if (!scene || !samples || !image)
        goto error;
    program = halo_link(&(halo_link_desc){.library = lib, .scene = scene, .host_source = probe_source,
                                          .host_file = "probe.frag", .image_scale = r->scale},
                        c->diag);
    if (!program || halo_diagnostics_errors(c->diag) > 0)
        goto error;
    int channels = halo_program_channel_count(program);
    gframe = halo_gl_frame_create(c->runtime, program, c->size, c->size, c->diag);
    eframe = halo_emu_frame_create(program, c->size, c->size, c->diag);
    if (!gframe || !eframe || !frame_probe_init(c, program, &fp))
        goto error;
    row_stats stats = {0};
    int worst_case = -1;
    for (int which = 0; which < SEED_CASES; ++which) {
        halo_gl_frame_begin(gframe);
        halo_emu_frame_begin(eframe);
        for (int g = 0; g < r->generations; ++g) {
            int base = (which + g) % SEED_CASES;
            double *seed = halo_emu_frame_image(eframe, "seed");
            for (int y = 0; y < c->size; ++y)
                for (int x = 0; x < c->size; ++x) {
                    size_t i = (size_t)y * (size_t)c->size + (size_t)x;
                    halo_emu_sample *s = &samples[i];
                    memset(s, 0, sizeof *s);
                    double v[4] = {0, 0, 0, 0};
                    for (int h = 0; h < channels; ++h)
                        v[h] = seed_case((base + h) % SEED_CASES, x, y, c->size);
                    s->color[0] = v[0], s->color[1] = v[1], s->color[2] = v[2], s->opacity = v[3];
                    s->view[2] = 1.0;
                    for (int h = 0; h < channels; ++h)
                        seed[i * (size_t)channels + (size_t)h] = v[h];
                }
            if (frame_probe_draw(c, &fp, program, gframe, samples, NULL) != HALO_OK)
                goto error;
            halo_gl_frame_generate(gframe);
            if (halo_emu_frame_generate(eframe, c->diag) != HALO_OK)
                goto error;
        }
        for (int k = 0; k < 3 && r->compare[k]; ++k) {
            if (halo_gl_frame_read(gframe, r->compare[k], image) != HALO_OK)
                goto error;
            const double *e = halo_emu_frame_image(eframe, r->compare[k]);
            int scale = 1;
            for (size_t m = 0; m < halo_program_image_count(program); ++m)
                if (!strcmp(halo_program_image(program, m)->name, r->compare[k]))
                    scale = halo_program_image(program, m)->scale;
            size_t side = (size_t)((c->size + scale - 1) / scale), compared = side * side;
            for (size_t i = 0; i < compared; ++i) {
                int over = 0, nonfinite = 0;
                for (int h = 0; h < channels; ++h) {
                    double gv = image[i * (size_t)channels + (size_t)h], ev = e[i * (size_t)channels + (size_t)h];
                    if (!isfinite(gv)) {
                        nonfinite = 1;
                        continue;
                    }
                    double error = fabs(gv - ev);
                    stats.sum_squares += error * error;
                    stats.values++;
                    if (error > stats.max_abs)
                        stats.max_abs = error, stats.worst = i, worst_case = which;
                    if (error > r->tolerance)
                        over = 1;
                }
                stats.over += (size_t)over;
                stats.nonfinite += (size_t)nonfinite;
            }
        }
    }
    int pass = stats.over == 0 && stats.nonfinite == 0;
    print_row(c, r->name, &stats, tolerance_text, pass);
    if ((c->verbose || !pass) && worst_case >= 0)
        fprintf(stderr, "  largest error at texel %zu (row-major in its image) of seed case '%s'; tolerance: %s\n",
                stats.worst, seed_case_names[worst_case], r->reason);
    goto done;
error:
    print_error_row(c, r->name);
done:
    halo_diagnostics_clear(c->diag);
    frame_probe_release(&fp);
    halo_gl_frame_destroy(gframe);
    halo_emu_frame_destroy(eframe);
    free(samples);
    free(image);
    halo_program_destroy(program);
    halo_scene_destroy(scene);
}

static void run_pass_rows(conform *c, const char *probe_source)
{
    int any = 0;
    for (size_t i = 0; i < sizeof pass_rows / sizeof pass_rows[0]; ++i)
        any |= row_selected(c, pass_rows[i].name, NULL);
    if (!any)
        return;
    /* The test module lives in a library of its own, so that it gets no stage row. */
    halo_library *lib = halo_library_create(c->diag);
    if (!lib || halo_library_add_source(lib, "(conformance seed module)", conform_seed_module, c->diag) != HALO_OK) {
        print_error_row(c, "pass:*");
        halo_library_destroy(lib);
        return;
    }
    for (size_t i = 0; i < sizeof pass_rows / sizeof pass_rows[0]; ++i)
        run_pass_row(c, lib, &pass_rows[i], probe_source);
    halo_library_destroy(lib);
}

/* ---- Figure 3 (validate/figure3.c) ---- */

int halo_figure3_run(const halo_library *lib, FILE *out, double ratios[4], halo_diagnostics *diag);

static void run_figure3_row(conform *c)
{
    if (!row_selected(c, "figure3", NULL))
        return;
    double ratios[4];
    if (halo_figure3_run(c->lib, stdout, ratios, c->diag) != 0) {
        print_error_row(c, "figure3");
        return;
    }
    /* The paper's claim: spreading the gradient keeps small features' halos (ratio near 1)
     * where a low-pass of the seeds loses them (ratio << 1). */
    double spread_gradient = fabs(log(fmax(ratios[3], 1e-300))), lowpass = fabs(log(fmax(ratios[0], 1e-300)));
    int pass = ratios[3] > 0.0 && spread_gradient < lowpass;
    printf("%-26s %10s %10s %8s %9s %17s %s\n", "figure3", "-", "-", "-", "-", "|log f| < |log b|",
           pass ? "PASS" : "FAIL");
    printf("  (f)/(b) feature-preservation ratios: %.4f vs %.4f\n", ratios[3], ratios[0]);
    fflush(stdout);
    c->rows++;
    if (!pass)
        c->failures++;
}

/* ---- Main ------------------------------------------------------------------------------ */

static void conform_usage(FILE *out)
{
    fputs("Usage: halo-validate conform [--stage NAME] [--size N] [-v]\n"
          "Renders every per-sample stage through a headless OpenGL context (OSMesa) and\n"
          "compares it with the C emulation; one row per test:\n"
          "  empty     the ray caster linked with no stage against the unlinked one (bit for bit)\n"
          "  STAGE     the stage with its default parameters, on a probe of hard and random samples\n"
          "  STAGE@exp0, STAGE@exp64   every exponent parameter set to 0 / 64\n"
          "  STAGE@live                every parameter a uniform, arrays with several elements\n"
          "  halo_seed, halo_map (and @halos2, @halos4, @live)   drawn through a GL frame (outputs,\n"
          "            images, host uniforms) against the emulated frame\n"
          "  pass:*    halo_generate's image passes on chosen seed images (GPU frame vs emulation)\n"
          "  outline:* the outline passes (at=post) on synthetic feature buffers: flat depth, depth 1,\n"
          "            one pixel, border, sigma > image, no-hit normals, occlusion styles, depth effects\n"
          "  raycast   a small whole render against a C emulation of the ray caster\n"
          "  figure3   the paper's Fig. 3 as numbers (emulation): fails unless spreading the seed\n"
          "            gradient keeps small features' halos better than a low-pass of the seeds\n"
          "Columns: max_abs and rmse of the error over colour and opacity, over_tol the samples\n"
          "(pixels) beyond tolerance, nonfinite the NaN/Inf values, the tolerance (absolute +\n"
          "relative; the per-sample conditioning term is explained in docs/accuracy.md).\n"
          "  --stage NAME  only the rows of this stage (or one row: empty, raycast, boundary@exp64)\n"
          "  --size N      probe and image side in pixels, 25..512 (default 64)\n"
          "  -v            print the worst sample of every row and the tolerance's reason\n"
          "Exit status: 0 all pass, 1 a row failed, 2 usage or setup failure (no OpenGL context).\n",
          out);
}

int halo_conform_main(int argc, char **argv)
{
    conform c = {.size = 64};
    for (int i = 1; i < argc; ++i) {
        const char *a = argv[i];
        if (!strcmp(a, "--help") || !strcmp(a, "-h")) {
            conform_usage(stdout);
            return 0;
        } else if (!strcmp(a, "-v") || !strcmp(a, "--verbose")) {
            c.verbose = 1;
        } else if (!strcmp(a, "--stage") && i + 1 < argc) {
            c.only = argv[++i];
        } else if (!strcmp(a, "--size") && i + 1 < argc) {
            const char *text = argv[++i];
            char *end = NULL;
            errno = 0;
            long n = strtol(text, &end, 10);
            if (end == text || *end != '\0' || errno == ERANGE || n < 25 || n > 512) {
                fprintf(stderr, "halo-validate: conform: --size: '%s' is not an integer in 25..512\n", text);
                return 2;
            }
            c.size = (int)n;
        } else {
            fprintf(stderr, "halo-validate: conform: unknown or incomplete argument '%s'\n", a);
            conform_usage(stderr);
            return 2;
        }
    }

    int status = 2;
    char *raycast_source = NULL, *probe_source = NULL;
    float *volume = NULL;
    c.diag = halo_diagnostics_create();
    if (!c.diag || halo_setup(NULL) != HALO_OK) {
        fprintf(stderr, "halo-validate: conform: cannot initialize libhalo\n");
        halo_diagnostics_destroy(c.diag);
        return 2;
    }
    c.lib = halo_library_create(c.diag);
    if (!c.lib)
        goto setup_failed;
    if (c.only && strcmp(c.only, "empty") != 0 && strcmp(c.only, "raycast") != 0 && strcmp(c.only, "figure3") != 0 &&
        strncmp(c.only, "pass:", 5) != 0 && strncmp(c.only, "slice", 5) != 0 && strncmp(c.only, "slab", 4) != 0 &&
        strncmp(c.only, "line", 4) != 0 && strncmp(c.only, "outline", 7) != 0 && strncmp(c.only, "feature", 7) != 0) {
        char base[128];
        snprintf(base, sizeof base, "%s", c.only);
        char *at = strchr(base, '@');
        if (at)
            *at = '\0';
        const halo_module *m = halo_library_find(c.lib, base);
        if (!m || halo_module_hook(m) != HALO_HOOK_SAMPLE) {
            fprintf(stderr, "halo-validate: conform: --stage: no per-sample stage '%s' (rows: empty, raycast, figure3,"
                            " pass:NAME, slice, slab, line_strip, line_halo, lines, or a stage of halo-validate list)\n", c.only);
            goto setup_failed;
        }
    }
    raycast_source = halo_host_load("raycast.frag", NULL, c.diag);
    probe_source = halo_host_load("probe.frag", NULL, c.diag);
    if (!raycast_source || !probe_source)
        goto setup_failed;
    char err[512];
    c.context = halo_headless_create(c.size, c.size, err, sizeof err);
    if (!c.context) {
        fprintf(stderr, "halo-validate: conform: %s\n", err);
        goto setup_failed;
    }
    c.runtime = halo_gl_create(&(halo_gl_desc){.get_proc_address = halo_headless_get_proc_address}, c.diag);
    if (!c.runtime)
        goto setup_failed;
    c.gl = halo_gl_functions(c.runtime);
    if (c.verbose)
        fprintf(stderr, "conform: %s context, %s\n", halo_headless_backend(c.context),
                halo_headless_renderer(c.context));

    printf("%-26s %10s %10s %8s %9s %17s %s\n", "stage", "max_abs", "rmse", "over_tol", "nonfinite", "tolerance",
           "result");
    const int empty_volume_size = 32;
    volume = halo_volume_create(empty_volume_size);
    if (!volume)
        goto setup_failed;
    run_empty_row(&c, raycast_source, volume, empty_volume_size);
    for (size_t i = 0; i < halo_library_module_count(c.lib); ++i) {
        const halo_module *m = halo_library_module(c.lib, i);
        if (halo_module_hook(m) != HALO_HOOK_SAMPLE)
            continue;
        /* feature_halo reads a 3D halo buffer the generic probe cannot supply: its own
         * rows (conform_feature.c) build the buffer on the GPU and in the emulation. */
        if (!strcmp(halo_module_name(m), "feature_halo"))
            continue;
        if (!halo_module_has_emulation(m)) {
            /* helper libraries (halo_math) are modules too, but no scene can enable them */
            halo_scene *probe_scene = halo_scene_create(c.lib);
            int is_stage = probe_scene && halo_scene_enable(probe_scene, halo_module_name(m), 1, NULL) == HALO_OK;
            halo_scene_destroy(probe_scene);
            if (is_stage && row_selected(&c, halo_module_name(m), halo_module_name(m))) {
                halo_diag_error(c.diag, EMU_MISSING, halo_module_file(m), 0, 0, "stage '%s' has no C emulation",
                                halo_module_name(m));
                print_error_row(&c, halo_module_name(m));
            }
            continue;
        }
        if (m->output_count || m->image_count || m->host_uniform_count) {
            const frame_variant *variants = m->image_count ? map_variants : seed_variants;
            size_t n = m->image_count ? sizeof map_variants / sizeof *map_variants
                                      : sizeof seed_variants / sizeof *seed_variants;
            /* the named scenes are written for halo_seed and halo_map; other such stages get
             * their defaults and the live variant */
            int own = !strcmp(halo_module_name(m), m->image_count ? "halo_map" : "halo_seed");
            for (size_t v = 0; v < n; ++v)
                if (own || !variants[v].scene)
                    run_frame_stage_row(&c, m, &variants[v], probe_source);
            continue;
        }
        for (int v = 0; v < VARIANT_COUNT; ++v)
            if (v == VARIANT_DEFAULT || v == VARIANT_LIVE || has_exponent(m))
                run_stage_row(&c, m, (enum variant)v, probe_source);
    }
    run_pass_rows(&c, probe_source);
    halo_conform_outline_rows(&c, probe_source);
    if (!c.only || !strncmp(c.only, "slice", 5) || !strncmp(c.only, "slab", 4))
        c.rows += halo_conform_slice_rows(c.size, c.verbose, &c.failures);
    if (!c.only || !strncmp(c.only, "feature", 7))
        c.rows += halo_conform_feature_rows(c.verbose, &c.failures);
    if (!c.only || !strncmp(c.only, "line", 4))
        c.rows += halo_conform_line_rows_select(c.only, c.verbose, &c.failures);
    run_raycast_row(&c, raycast_source);
    run_figure3_row(&c);
    status = c.failures ? 1 : 0;
    printf("%d rows, %d failed\n", c.rows, c.failures);
    goto done;

setup_failed:
    halo_diagnostics_print(c.diag, stderr);
    status = 2;
done:
    free(volume);
    free(raycast_source);
    free(probe_source);
    halo_gl_destroy(c.runtime);
    halo_headless_destroy(c.context);
    halo_library_destroy(c.lib);
    halo_diagnostics_destroy(c.diag);
    halo_shutdown();
    return status;
}
