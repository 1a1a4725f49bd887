/* Emulation of glsl/sample/distance_cue.glsl: c = c mix(1, map(saturate(d)), k_cm), map
 * piecewise linear through the colours placed evenly over [0, 1]. */
#include <math.h>

#include "stages.h"

static void depth_map(const double *colors, int count, double d, double out[3])
{
    if (!colors || count < 1) {
        out[0] = out[1] = out[2] = 1.0;
        return;
    }
    if (count == 1) {
        for (int c = 0; c < 3; ++c)
            out[c] = colors[c];
        return;
    }
    double x = d * (double)(count - 1);
    int i = (int)floor(x);
    if (i > count - 2)
        i = count - 2;
    if (i < 0)
        i = 0;
    double f = x - (double)i;
    for (int c = 0; c < 3; ++c)
        out[c] = halo_emu_mix(colors[3 * i + c], colors[3 * (i + 1) + c], f);
}

HALO_EMU_STAGE(distance_cue)
{
    double k_cm = halo_emu_scalar(p, "k_cm");
    int count = 0;
    const double *colors = halo_emu_param(p, "colors", &count);
    double tint[3];
    depth_map(colors, count, halo_emu_saturate(s->depth), tint);
    for (int c = 0; c < 3; ++c)
        s->color[c] = s->color[c] * halo_emu_mix(1.0, tint[c], k_cm);
}
