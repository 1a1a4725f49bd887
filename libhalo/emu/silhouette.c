/* Emulation of glsl/sample/silhouette.glsl: o = clamp(o (k_sc + k_ss (1 - |n.V|)^k_se), 0, 1);
 * no silhouette term where the normal is zero. */
#include <math.h>

#include "stages.h"

HALO_EMU_STAGE(silhouette)
{
    double k_sc = halo_emu_scalar(p, "k_sc");
    double k_ss = halo_emu_scalar(p, "k_ss");
    double k_se = halo_emu_scalar(p, "k_se");
    double silhouette = 0.0;
    if (!halo_emu_is_zero3(s->normal)) {
        double facing = fabs(halo_emu_dot_clamped(s->normal, s->view));
        silhouette = k_ss * halo_emu_pow(1.0 - facing, k_se);
    }
    s->opacity = halo_emu_saturate(s->opacity * (k_sc + silhouette));
}
