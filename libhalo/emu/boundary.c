/* Emulation of glsl/sample/boundary.glsl: o = clamp(o (k_gc + k_gs |grad f|^k_ge), 0, 1). */
#include "stages.h"

HALO_EMU_STAGE(boundary)
{
    double k_gc = halo_emu_scalar(p, "k_gc");
    double k_gs = halo_emu_scalar(p, "k_gs");
    double k_ge = halo_emu_scalar(p, "k_ge");
    double enhancement = k_gc + k_gs * halo_emu_pow(s->gradient_magnitude, k_ge);
    s->opacity = halo_emu_saturate(s->opacity * enhancement);
}
