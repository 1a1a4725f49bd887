/* Emulation of glsl/sample/opacity_power.glsl: o = clamp((k_os v)^k_oe, 0, 1). */
#include "stages.h"

HALO_EMU_STAGE(opacity_power)
{
    double k_os = halo_emu_scalar(p, "k_os");
    double k_oe = halo_emu_scalar(p, "k_oe");
    s->opacity = halo_emu_saturate(halo_emu_pow(k_os * s->value, k_oe));
}
