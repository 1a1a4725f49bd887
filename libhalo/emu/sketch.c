/* Emulation of glsl/sample/sketch.glsl: line = (1 - |n.V|)^k_le (0 where the normal is
 * zero); c = line_color; o = clamp(o k_ls line, 0, 1). */
#include <math.h>

#include "stages.h"

HALO_EMU_STAGE(sketch)
{
    double k_ls = halo_emu_scalar(p, "k_ls");
    double k_le = halo_emu_scalar(p, "k_le");
    int count = 0;
    const double *line_color = halo_emu_param(p, "line_color", &count);
    double line = 0.0;
    if (!halo_emu_is_zero3(s->normal))
        line = halo_emu_pow(1.0 - fabs(halo_emu_dot_clamped(s->normal, s->view)), k_le);
    for (int i = 0; i < 3; ++i)
        s->color[i] = line_color && count > 0 ? line_color[i] : 0.0;
    s->opacity = halo_emu_saturate(s->opacity * k_ls * line);
}
