/* Emulation of glsl/sample/distance_blend.glsl: t = k_ds saturate(d)^k_de;
 * c = (1 - t) c + t c_b. */
#include "stages.h"

HALO_EMU_STAGE(distance_blend)
{
    double k_ds = halo_emu_scalar(p, "k_ds");
    double k_de = halo_emu_scalar(p, "k_de");
    int count = 0;
    const double *background = halo_emu_param(p, "background", &count);
    double t = k_ds * halo_emu_pow(halo_emu_saturate(s->depth), k_de);
    for (int i = 0; i < 3; ++i) {
        double b = background && count > 0 ? background[i] : 0.0;
        s->color[i] = halo_emu_mix(s->color[i], b, t);
    }
}
