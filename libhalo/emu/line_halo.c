/* Emulation of glsl/lines/halo.glsl in double precision, with the module's branches: the
 * line's core keeps its colour, the halo takes the background's, and the depth is pushed
 * back away from the centre. It reads s->line_fragment (a program linked into a line
 * fragment host). */
#include <math.h>
#include <string.h>

#include "stages.h"

static double displacement(double x, int profile, double core)
{
    if (profile == 1)
        return x * x * (3.0 - 2.0 * x);
    if (profile == 2)
        return x < core ? 0.0 : 1.0;
    return x;
}

HALO_EMU_STAGE(line_halo)
{
    halo_emu_line_fragment *f = &s->line_fragment;
    double core = halo_emu_scalar(p, "core");
    double d_max = halo_emu_scalar(p, "d_max");
    int profile = (int)halo_emu_scalar(p, "profile");
    double x = halo_emu_saturate(2.0 * fabs(f->uv[1] - 0.5));
    if (!(x < core)) {
        memcpy(f->color, f->background, sizeof f->color);
        f->opacity = 1.0;
    }
    f->depth = f->depth + d_max * displacement(x, profile, core);
}
