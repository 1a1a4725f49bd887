/* Emulation of the image passes of glsl/halo/generate.glsl, one function per entry:
 * median_pass (3x3 median per channel), gradient_pass (H_0 = clamp(|grad S|, 0, 1),
 * central differences not halved), spread_pass (H_i = delta F_i + (1 - delta F_i) H_0,
 * F_i the 3x3 Gaussian [1 2 1; 2 4 2; 1 2 1]/16 at distance k = 2^(N - i)) and
 * occlusion_pass (O = max(H, O)). Outside the image every input reads 0. */
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

void halo_emu_halo_generate_median(const halo_emu_pass_context *c, int x, int y, double out[4])
{
    for (int ch = 0; ch < c->channels; ++ch) {
        double v[9];
        for (int i = 0; i < 9; ++i)
            v[i] = halo_emu_input(c, 0, x + i % 3 - 1, y + i / 3 - 1, ch);
        out[ch] = median9(v);
    }
}

void halo_emu_halo_generate_gradient(const halo_emu_pass_context *c, int x, int y, double out[4])
{
    for (int ch = 0; ch < c->channels; ++ch) {
        double gx = halo_emu_input(c, 0, x + 1, y, ch) - halo_emu_input(c, 0, x - 1, y, ch);
        double gy = halo_emu_input(c, 0, x, y + 1, ch) - halo_emu_input(c, 0, x, y - 1, ch);
        out[ch] = halo_emu_clamp(sqrt(gx * gx + gy * gy), 0.0, 1.0);
    }
}

void halo_emu_halo_generate_spread(const halo_emu_pass_context *c, int x, int y, double out[4])
{
    int shift = c->pass_count - c->pass_index;
    int k = shift >= 0 && shift < 30 ? (1 << shift) / (c->scale > 1 ? c->scale : 1) : 1;
    if (k < 1)
        k = 1;
    for (int ch = 0; ch < c->channels; ++ch) {
        double corners = halo_emu_input(c, 0, x - k, y - k, ch) + halo_emu_input(c, 0, x + k, y - k, ch) +
                         halo_emu_input(c, 0, x - k, y + k, ch) + halo_emu_input(c, 0, x + k, y + k, ch);
        double edges = halo_emu_input(c, 0, x, y - k, ch) + halo_emu_input(c, 0, x - k, y, ch) +
                       halo_emu_input(c, 0, x + k, y, ch) + halo_emu_input(c, 0, x, y + k, ch);
        double f = (corners + 2.0 * edges + 4.0 * halo_emu_input(c, 0, x, y, ch)) * (1.0 / 16.0);
        double spread = halo_emu_channel(c->params, "delta", ch) * f;
        out[ch] = spread + (1.0 - spread) * halo_emu_input(c, 1, x, y, ch);
    }
}

void halo_emu_halo_generate_occlusion(const halo_emu_pass_context *c, int x, int y, double out[4])
{
    for (int ch = 0; ch < c->channels; ++ch) {
        double a = halo_emu_input(c, 0, x, y, ch), b = halo_emu_input(c, 1, x, y, ch);
        out[ch] = b > a ? b : a;
    }
}
