/* Emulation of glsl/sample/orientation_fade.glsl: facing = |n.V|^k_fe; o *= 1 - k_fo facing;
 * HSV saturation *= 1 - k_fs facing, value *= 1 - k_fv (1 - facing); zero normal: unchanged. */
#include <math.h>

#include "stages.h"

HALO_EMU_STAGE(orientation_fade)
{
    if (halo_emu_is_zero3(s->normal))
        return;
    double k_fo = halo_emu_scalar(p, "k_fo");
    double k_fs = halo_emu_scalar(p, "k_fs");
    double k_fv = halo_emu_scalar(p, "k_fv");
    double k_fe = halo_emu_scalar(p, "k_fe");
    double facing = halo_emu_pow(fabs(halo_emu_dot_clamped(s->normal, s->view)), k_fe);
    s->opacity = s->opacity * (1.0 - k_fo * facing);
    double hsv[3];
    halo_emu_rgb_to_hsv(s->color, hsv);
    hsv[1] = hsv[1] * (1.0 - k_fs * facing);
    hsv[2] = hsv[2] * (1.0 - k_fv * (1.0 - facing));
    halo_emu_hsv_to_rgb(hsv, s->color);
}
