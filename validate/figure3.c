/* Bruckner & Groller 2007, Figure 3, as numbers: an artificial seed image with features
 * of several scales (a single pixel and discs of radius 1 .. 32 px), and the halo
 * intensity that four generation strategies leave around each feature:
 *   (b) low-pass of S, (c) spreading of S, (e) low-pass of grad S, (f) spreading of
 *   grad S (libhalo's halo_generate: N = 4, delta = 0.8).
 * The feature-preservation ratio is the mean intensity in a ring 2..6 px outside the
 * smallest feature's edge over that of the largest; the paper's claim is that (f)
 * equalizes (ratio near 1) where (b) loses small features (ratio << 1). (f) is libhalo's
 * emulation of halo_generate through its public frame (the conformance rows pass:* tie it
 * to the GPU); (b) to (e), the strategies the paper sets it against, are written out here. Printed by `halo-validate conform` (docs/volumetric-halos.md). */
#include "figure3.h"

#include "halo.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define FIG_SIZE     256
#define FIG_FEATURES 7
#define FIG_SIGMA    5.0 /* px: 3 sigma = 15 px = the reach 2^N - 1 of the spreading with N = 4 */

static const struct {
    double radius; /* 0: a single pixel */
    int x, y;
} features[FIG_FEATURES] = {
    {0, 200, 220}, {1, 140, 220}, {2, 190, 170}, {4, 140, 170}, {8, 60, 180}, {16, 180, 60}, {32, 60, 60},
};

static const char figure3_host[] =
    "#version 330 core\n"
    "#pragma halo declarations\n"
    "layout(location = 0) out vec4 color;\n"
    "void main() {\n"
    "    color = vec4(0.0);\n"
    "#ifdef HALO_LINKED\n"
    "    halo_sample s = halo_make_sample(vec3(0.5), 0.5, vec3(0.0), vec3(0.0, 0.0, 1.0),"
    " 0.5, gl_FragCoord.xy, vec3(0.0), 0.0);\n"
    "    halo_apply(s);\n"
    "    halo_finish();\n"
    "#endif\n"
    "}\n";

static void seed_image(double *s)
{
    memset(s, 0, FIG_SIZE * FIG_SIZE * sizeof *s);
    for (int f = 0; f < FIG_FEATURES; ++f) {
        double r = features[f].radius;
        for (int y = 0; y < FIG_SIZE; ++y)
            for (int x = 0; x < FIG_SIZE; ++x) {
                double dx = x - features[f].x, dy = y - features[f].y;
                if (dx * dx + dy * dy <= r * r)
                    s[y * FIG_SIZE + x] = 1.0;
            }
    }
}

/* Separable Gaussian, truncated at 3 sigma, normalized, zero padding. */
static void lowpass(const double *in, double *out, double *tmp)
{
    int reach = (int)ceil(3.0 * FIG_SIGMA);
    double w[64], sum = 0.0;
    for (int i = -reach; i <= reach; ++i)
        sum += w[i + reach] = exp(-0.5 * i * i / (FIG_SIGMA * FIG_SIGMA));
    for (int i = 0; i <= 2 * reach; ++i)
        w[i] /= sum;
    for (int y = 0; y < FIG_SIZE; ++y)
        for (int x = 0; x < FIG_SIZE; ++x) {
            double a = 0.0;
            for (int i = -reach; i <= reach; ++i)
                if (x + i >= 0 && x + i < FIG_SIZE)
                    a += w[i + reach] * in[y * FIG_SIZE + x + i];
            tmp[y * FIG_SIZE + x] = a;
        }
    for (int y = 0; y < FIG_SIZE; ++y)
        for (int x = 0; x < FIG_SIZE; ++x) {
            double a = 0.0;
            for (int i = -reach; i <= reach; ++i)
                if (y + i >= 0 && y + i < FIG_SIZE)
                    a += w[i + reach] * tmp[(y + i) * FIG_SIZE + x];
            out[y * FIG_SIZE + x] = a;
        }
}

/* The image at (x, y), 0 outside it (the passes' zero padding). */
static double at(const double *img, int x, int y)
{
    return x < 0 || y < 0 || x >= FIG_SIZE || y >= FIG_SIZE ? 0.0 : img[y * FIG_SIZE + x];
}

/* (d): |grad S| by unhalved central differences, clamped to 1, 0 outside the image:
 * halo_generate's H_0 (docs/stages/halo_generate.md), written out for the figure. */
static void gradient_magnitude(const double *s, double *out)
{
    for (int y = 0; y < FIG_SIZE; ++y)
        for (int x = 0; x < FIG_SIZE; ++x) {
            double gx = at(s, x + 1, y) - at(s, x - 1, y), gy = at(s, x, y + 1) - at(s, x, y - 1);
            out[y * FIG_SIZE + x] = fmin(fmax(sqrt(gx * gx + gy * gy), 0.0), 1.0);
        }
}

/* (c): halo_generate's spreading (docs/stages/halo_generate.md) started from S itself
 * instead of |grad S|: N passes H_i = d F_i + (1 - d F_i) H_0, F_i the 3x3 kernel
 * [1 2 1; 2 4 2; 1 2 1] / 16 over H_(i-1) with its taps 2^(N - i) pixels apart. */
static void spread(int passes, double delta, const double *initial, double *out, double *tmp)
{
    memcpy(tmp, initial, FIG_SIZE * FIG_SIZE * sizeof *tmp);
    for (int i = 1; i <= passes; ++i) {
        int k = 1 << (passes - i);
        for (int y = 0; y < FIG_SIZE; ++y)
            for (int x = 0; x < FIG_SIZE; ++x) {
                double corners =
                    at(tmp, x - k, y - k) + at(tmp, x + k, y - k) + at(tmp, x - k, y + k) + at(tmp, x + k, y + k);
                double edges = at(tmp, x, y - k) + at(tmp, x - k, y) + at(tmp, x + k, y) + at(tmp, x, y + k);
                double amount = delta * ((corners + 2.0 * edges + 4.0 * at(tmp, x, y)) * (1.0 / 16.0));
                out[y * FIG_SIZE + x] = amount + (1.0 - amount) * initial[y * FIG_SIZE + x];
            }
        memcpy(tmp, out, FIG_SIZE * FIG_SIZE * sizeof *tmp);
    }
}

/* Mean of an image in the ring 2..6 px outside feature f's edge (edge: radius + 0.5). */
static double ring_mean(const double *img, int f)
{
    double edge = features[f].radius + 0.5, sum = 0.0;
    int n = 0;
    for (int y = 0; y < FIG_SIZE; ++y)
        for (int x = 0; x < FIG_SIZE; ++x) {
            double dx = x - features[f].x, dy = y - features[f].y, d = sqrt(dx * dx + dy * dy);
            if (d >= edge + 2.0 && d <= edge + 6.0) {
                sum += img[y * FIG_SIZE + x];
                n++;
            }
        }
    return n ? sum / n : 0.0;
}

/* Computes the four strategies; prints the table to out; ratios[k] = ring(smallest) /
 * ring(largest) for (b), (c), (e), (f). Returns 0, or -1 (diagnostics) on failure. */
int halo_figure3_run(const halo_library *lib, FILE *out, double ratios[4], halo_diagnostics *diag)
{
    int status = -1;
    const size_t n = FIG_SIZE * FIG_SIZE;
    double *buffers = calloc(8 * n, sizeof *buffers);
    halo_scene *scene = halo_scene_load(
        "(figure 3 scene)", "{\"stages\": [{\"halo_generate\": {\"passes\": 4, \"delta\": 0.8}}]}", lib, diag);
    halo_program *program = NULL;
    halo_emu_frame *frame = NULL;
    if (!buffers || !scene)
        goto done;
    program = halo_link(
        &(halo_link_desc){.library = lib, .scene = scene, .host_source = figure3_host, .host_file = "(figure 3 host)"},
        diag);
    if (!program)
        goto done;
    frame = halo_emu_frame_create(program, FIG_SIZE, FIG_SIZE, diag);
    if (!frame)
        goto done;
    double *S = buffers, *grad = buffers + n, *tmp = buffers + 2 * n;
    double *results[4] = {buffers + 4 * n, buffers + 5 * n, buffers + 6 * n, buffers + 7 * n};
    seed_image(S);
    lowpass(S, results[0], tmp);        /* (b) */
    spread(4, 0.8, S, results[1], tmp); /* (c) */
    gradient_magnitude(S, grad);        /* (d) */
    lowpass(grad, results[2], tmp);     /* (e) */
    /* (f): libhalo's schedule, as a host runs it: the seed image, then one generation. */
    halo_emu_frame_begin(frame);
    memcpy(halo_emu_frame_image(frame, "seed"), S, n * sizeof *S);
    if (halo_emu_frame_generate(frame, diag) != HALO_OK)
        goto done;
    memcpy(results[3], halo_emu_frame_image(frame, "field"), n * sizeof *S);

    static const char *const names[4] = {"(b) low-pass of S", "(c) spreading of S", "(e) low-pass of grad S",
                                         "(f) spreading of grad S"};
    fprintf(out,
            "figure3: Bruckner & Groller 2007 Fig. 3, emulation, %dx%d seed image, spreading N = 4, delta = 0.8,"
            " low-pass Gaussian sigma = %.0f px\n"
            "  mean halo intensity in a ring 2..6 px outside each feature (radius in px; 0 = one pixel)\n"
            "  %-26s",
            FIG_SIZE, FIG_SIZE, FIG_SIGMA, "strategy");
    for (int f = 0; f < FIG_FEATURES; ++f)
        fprintf(out, "   r=%-4.0f", features[f].radius);
    fprintf(out, "  smallest/largest\n");
    for (int k = 0; k < 4; ++k) {
        fprintf(out, "  %-26s", names[k]);
        for (int f = 0; f < FIG_FEATURES; ++f)
            fprintf(out, " %8.4f", ring_mean(results[k], f));
        double largest = ring_mean(results[k], FIG_FEATURES - 1);
        ratios[k] = largest > 0.0 ? ring_mean(results[k], 0) / largest : 0.0;
        fprintf(out, "  %10.4f\n", ratios[k]);
    }
    fflush(out);
    status = 0;
done:
    halo_emu_frame_destroy(frame);
    halo_program_destroy(program);
    halo_scene_destroy(scene);
    free(buffers);
    return status;
}

void conform_figure3_row(conform *c, const conform_row *row)
{
    if (!row_selected(c, row->name, NULL))
        return;
    double ratios[4];
    if (halo_figure3_run(c->lib, stdout, ratios, c->diag) != 0) {
        print_error_row(c, row->name);
        return;
    }
    /* The paper's claim: spreading the gradient keeps small features' halos (ratio near 1)
     * where a low-pass of the seeds loses them (ratio << 1). */
    double spread_gradient = fabs(log(fmax(ratios[3], 1e-300))), lowpass = fabs(log(fmax(ratios[0], 1e-300)));
    int pass = ratios[3] > 0.0 && spread_gradient < lowpass;
    char tolerance_text[32];
    conform_tolerance_text(row, tolerance_text, sizeof tolerance_text);
    print_plain_row(c, row->name, tolerance_text, pass);
    printf("  (f)/(b) feature-preservation ratios: %.4f vs %.4f\n", ratios[3], ratios[0]);
    fflush(stdout);
}

/* One generation of halo_generate with the given parameters over the figure's seed
 * image, emulated: the field into out (FIG_SIZE^2). Returns 0, or -1. */
static int field_of(const halo_library *lib, const char *generate, const double *seed, double *out,
                    halo_diagnostics *diag)
{
    char json[256];
    snprintf(json, sizeof json, "{\"stages\": [{\"halo_generate\": %s}]}", generate);
    halo_scene *scene = halo_scene_load("(wide field scene)", json, lib, diag);
    halo_program *program = scene ? halo_link(&(halo_link_desc){.library = lib,
                                                                .scene = scene,
                                                                .host_source = figure3_host,
                                                                .host_file = "(figure 3 host)"},
                                              diag)
                                  : NULL;
    halo_emu_frame *frame = program ? halo_emu_frame_create(program, FIG_SIZE, FIG_SIZE, diag) : NULL;
    int status = -1;
    if (frame) {
        halo_emu_frame_begin(frame);
        memcpy(halo_emu_frame_image(frame, "seed"), seed, FIG_SIZE * FIG_SIZE * sizeof *seed);
        if (halo_emu_frame_generate(frame, diag) == HALO_OK) {
            memcpy(out, halo_emu_frame_image(frame, "field"), FIG_SIZE * FIG_SIZE * sizeof *out);
            status = 0;
        }
    }
    halo_emu_frame_destroy(frame);
    halo_program_destroy(program);
    halo_scene_destroy(scene);
    return status;
}

int halo_figure3_wide(const halo_library *lib, halo_figure3_wide_error *e, halo_diagnostics *diag)
{
    const size_t n = FIG_SIZE * FIG_SIZE;
    double *seed = calloc(3 * n, sizeof *seed), *exact = seed + n, *wide = seed + 2 * n;
    memset(e, 0, sizeof *e);
    if (!seed)
        return -1;
    e->size = FIG_SIZE;
    seed_image(seed);
    int status = field_of(lib, "{\"passes\": 4, \"delta\": 0.8}", seed, exact, diag) ||
                 field_of(lib, "{\"passes\": 2, \"delta\": 0.8, \"wide\": true}", seed, wide, diag);
    if (!status) {
        double sum = 0.0;
        for (size_t i = 0; i < n; ++i) {
            double d = fabs(wide[i] - exact[i]);
            sum += d * d;
            if (d > e->max_abs)
                e->max_abs = d, e->exact_at_max = exact[i], e->wide_at_max = wide[i];
        }
        e->rmse = sqrt(sum / (double)n);
        e->weaker_min = 1.0, e->weaker_max = -1.0;
        for (int f = 0; f < FIG_FEATURES; ++f) {
            double x = ring_mean(exact, f), w = ring_mean(wide, f);
            double weaker = x > 0.0 ? 1.0 - w / x : 0.0;
            e->weaker_min = fmin(e->weaker_min, weaker);
            e->weaker_max = fmax(e->weaker_max, weaker);
        }
    }
    free(seed);
    return status ? -1 : 0;
}
