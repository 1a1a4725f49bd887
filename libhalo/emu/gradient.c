/* Emulation of glsl/sample/gradient.glsl: |grad f| and n = -grad f / |grad f| (0 where
 * |grad f| <= 1e-10). */
#include <math.h>

#include "stages.h"

HALO_EMU_STAGE(gradient)
{
    (void)p;
    s->gradient_magnitude = sqrt(halo_emu_dot(s->gradient, s->gradient));
    double n[3];
    halo_emu_normalize(s->gradient, n);
    for (int i = 0; i < 3; ++i)
        s->normal[i] = -n[i];
}
