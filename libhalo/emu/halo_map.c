/* Emulation of glsl/halo/map.glsl: the halo profile (t = clamp(H / full_at, 0, 1),
 * alpha = opacity t^exponent, colour = mix(color_far, color_near, t), H <= 0 transparent);
 * occlusive halos (occlusion image) mix into the colour, then emissive halos (field
 * image) are composited behind the sample. */
#include "stages.h"

static void profile(const halo_emu_params *p, int h, double H, double *alpha, double colour[3])
{
    double t = halo_emu_clamp(H / halo_emu_channel(p, "full_at", h), 0.0, 1.0);
    *alpha = halo_emu_channel(p, "opacity", h) * halo_emu_pow(t, halo_emu_channel(p, "profile_exponent", h));
    const double *near = halo_emu_channel_param(p, "color_near", h);
    const double *far = halo_emu_channel_param(p, "color_far", h);
    for (int k = 0; k < 3; ++k)
        colour[k] = halo_emu_mix(far ? far[k] : 0.0, near ? near[k] : 0.0, t);
}

HALO_EMU_STAGE(halo_map)
{
    double field[4], occluding[4];
    halo_emu_read_image(p, "field", s->fragcoord, field);
    halo_emu_read_image(p, "occlusion", s->fragcoord, occluding);
    int channels = halo_emu_channel_count(p);
    for (int h = 0; h < channels; ++h) {
        double H = occluding[h], a, colour[3];
        if (halo_emu_channel(p, "mode", h) < 0.5 || H <= 0.0)
            continue;
        profile(p, h, H, &a, colour);
        for (int k = 0; k < 3; ++k)
            s->color[k] = halo_emu_mix(s->color[k], colour[k], a);
    }
    for (int h = 0; h < channels; ++h) {
        double H = field[h], a, colour[3];
        if (halo_emu_channel(p, "mode", h) >= 0.5 || H <= 0.0)
            continue;
        profile(p, h, H, &a, colour);
        double behind = (1.0 - s->opacity) * a;
        double opacity = s->opacity + behind;
        if (opacity > 0.0)
            for (int k = 0; k < 3; ++k)
                s->color[k] = (s->opacity * s->color[k] + behind * colour[k]) / opacity;
        s->opacity = opacity;
    }
}
