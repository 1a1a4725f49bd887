/* Emulation of the image passes of glsl/halo/generate.glsl, one function per entry:
 * median_pass (3x3 median per channel), gradient_pass (H_0 = clamp(|grad S|, 0, 1),
 * central differences not halved), spread_pass (H_i = delta F_i + (1 - delta F_i) H_0,
 * F_i the 3x3 Gaussian [1 2 1; 2 4 2; 1 2 1]/16 at distance k = 2^(N - i)) and
 * occlusion_pass (O = max(H, O)); with `fold` at the frame's size spread_seed_pass and spread_on_pass,
 * the same with H_0 taken from the seed image where it is read; spread_wide_pass (the
 * approximation `wide`: two steps' kernels convolved, 49 taps). Outside the image every
 * input reads 0. */
#include <math.h>

#include "stages.h"

static double median9(double v[9])
{
    for (int i = 1; i < 9; ++i) {
        double x = v[i];
        int j = i - 1;
        while (j >= 0 && v[j] > x) {
            v[j + 1] = v[j];
            --j;
        }
        v[j + 1] = x;
    }
    return v[4];
}

HALO_EMU_PASS(halo_generate, median_pass)
{
    for (int ch = 0; ch < c->channels; ++ch) {
        double v[9];
        for (int i = 0; i < 9; ++i)
            v[i] = halo_emu_input(c, 0, x + i % 3 - 1, y + i / 3 - 1, ch);
        out[ch] = median9(v);
    }
}

/* H_0 at (x, y) of channel ch from the seed image, input k; 0 outside the image. */
static double seed_gradient(const halo_emu_pass_context *c, int k, int x, int y, int ch)
{
    if (x < 0 || y < 0 || x >= c->width || y >= c->height)
        return 0.0;
    double gx = halo_emu_input(c, k, x + 1, y, ch) - halo_emu_input(c, k, x - 1, y, ch);
    double gy = halo_emu_input(c, k, x, y + 1, ch) - halo_emu_input(c, k, x, y - 1, ch);
    return halo_emu_clamp(sqrt(gx * gx + gy * gy), 0.0, 1.0);
}

HALO_EMU_PASS(halo_generate, gradient_pass)
{
    for (int ch = 0; ch < c->channels; ++ch)
        out[ch] = seed_gradient(c, 0, x, y, ch);
}

/* H at one tap: input k read as it is, or (from_seed) H_0 from the seed image there. */
static double tap(const halo_emu_pass_context *c, int k, int from_seed, int x, int y, int ch)
{
    return from_seed ? seed_gradient(c, k, x, y, ch) : halo_emu_input(c, k, x, y, ch);
}

/* H_i: the taps of H_{i-1} (input 0, or H_0 from the seed image in input 0), H_0 from
 * input 1 (stored, or from the seed image there) or, for the first pass at the frame's
 * size, from input 0. */
static void spread(const halo_emu_pass_context *c, int x, int y, int taps_from_seed, int initial_input,
                   int initial_from_seed, double out[4])
{
    /* pass i of N = the parameter passes (spread_seed_pass is pass 1, drawn once) */
    int index = taps_from_seed ? 1 : c->pass_index;
    int shift = (int)halo_emu_scalar(c->params, "passes") - index;
    int k = shift >= 0 && shift < 30 ? (1 << shift) / (c->scale > 1 ? c->scale : 1) : 1;
    if (k < 1)
        k = 1;
    for (int ch = 0; ch < c->channels; ++ch) {
        double corners = tap(c, 0, taps_from_seed, x - k, y - k, ch) + tap(c, 0, taps_from_seed, x + k, y - k, ch) +
                         tap(c, 0, taps_from_seed, x - k, y + k, ch) + tap(c, 0, taps_from_seed, x + k, y + k, ch);
        double edges = tap(c, 0, taps_from_seed, x, y - k, ch) + tap(c, 0, taps_from_seed, x - k, y, ch) +
                       tap(c, 0, taps_from_seed, x + k, y, ch) + tap(c, 0, taps_from_seed, x, y + k, ch);
        double f = (corners + 2.0 * edges + 4.0 * tap(c, 0, taps_from_seed, x, y, ch)) * (1.0 / 16.0);
        double amount = halo_emu_channel(c->params, "delta", ch) * f;
        out[ch] = amount + (1.0 - amount) * tap(c, initial_input, initial_from_seed, x, y, ch);
    }
}

HALO_EMU_PASS(halo_generate, spread_pass) { spread(c, x, y, 0, 1, 0, out); }

HALO_EMU_PASS(halo_generate, spread_seed_pass) { spread(c, x, y, 1, 0, 1, out); }

HALO_EMU_PASS(halo_generate, spread_on_pass) { spread(c, x, y, 0, 1, 1, out); }

/* wide: pass i of N, per axis [1 2 3 4 3 2 1]/16 at spacing s = 4^(N - i) (max(1, s / scale)
 * on images at 1/scale) over H_{i-1} (input 0), H_0 from input 1. */
HALO_EMU_PASS(halo_generate, spread_wide_pass)
{
    static const double weights[7] = {1, 2, 3, 4, 3, 2, 1};
    int shift = 2 * ((int)halo_emu_scalar(c->params, "passes") - c->pass_index);
    int s = shift >= 0 && shift < 30 ? (1 << shift) / (c->scale > 1 ? c->scale : 1) : 1;
    if (s < 1)
        s = 1;
    for (int ch = 0; ch < c->channels; ++ch) {
        double sum = 0.0;
        for (int v = 0; v < 7; ++v) {
            double row = 0.0;
            for (int u = 0; u < 7; ++u)
                row += weights[u] * halo_emu_input(c, 0, x + s * (u - 3), y + s * (v - 3), ch);
            sum += weights[v] * row;
        }
        double amount = halo_emu_channel(c->params, "delta", ch) * sum / 256.0;
        out[ch] = amount + (1.0 - amount) * halo_emu_input(c, 1, x, y, ch);
    }
}

HALO_EMU_PASS(halo_generate, occlusion_pass)
{
    for (int ch = 0; ch < c->channels; ++ch) {
        double a = halo_emu_input(c, 0, x, y, ch), b = halo_emu_input(c, 1, x, y, ch);
        out[ch] = b > a ? b : a;
    }
}
