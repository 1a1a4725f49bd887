/* Emulation of glsl/sample/tone_shading.glsl:
 * c = k_ta c_v + sum over lights of (I_t + k_td c_v max(n.L, 0)),
 * I_t = ((1 + n.L)/2) (k_ty, k_ty, 0) + (1 - (1 + n.L)/2) (0, 0, k_tb), L = normalize(light). */
#include "stages.h"

HALO_EMU_STAGE(tone_shading)
{
    double k_ty = halo_emu_scalar(p, "k_ty");
    double k_tb = halo_emu_scalar(p, "k_tb");
    double k_ta = halo_emu_scalar(p, "k_ta");
    double k_td = halo_emu_scalar(p, "k_td");
    int lights_count = 0;
    const double *lights = halo_emu_param(p, "lights", &lights_count);
    if (!lights)
        lights_count = 0;
    const double warm[3] = {k_ty, k_ty, 0.0};
    const double cool[3] = {0.0, 0.0, k_tb};
    double color[3];
    for (int c = 0; c < 3; ++c)
        color[c] = k_ta * s->color[c];
    for (int i = 0; i < lights_count; ++i) {
        double light[3];
        halo_emu_normalize(lights + 3 * i, light);
        double n_dot_l = halo_emu_dot_clamped(s->normal, light);
        double toward = (1.0 + n_dot_l) * 0.5;
        double diffuse = n_dot_l > 0.0 ? n_dot_l : 0.0;
        for (int c = 0; c < 3; ++c)
            color[c] += toward * warm[c] + (1.0 - toward) * cool[c] + k_td * s->color[c] * diffuse;
    }
    for (int c = 0; c < 3; ++c)
        s->color[c] = color[c];
}
