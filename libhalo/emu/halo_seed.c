/* Emulation of glsl/halo/seed.glsl: per halo h,
 * s_h = clamp(h_v h_d h_p g^alpha (1 - |n.V|)^beta, 0, 1), g = min(1, |grad f| gradient_scale);
 * s = 0 where the normal is zero. */
#include <math.h>
#include <stdio.h>

#include "stages.h"

/* 1 - smoothstep(e0, e1, x) as written in the module; a step where e1 <= e0. */
static double fall_off(double e0, double e1, double x)
{
    if (e1 <= e0)
        return x <= e0 ? 1.0 : 0.0;
    double t = halo_emu_clamp((x - e0) / (e1 - e0), 0.0, 1.0);
    return 1.0 - t * t * (3.0 - 2.0 * t);
}

static double value_influence(const halo_emu_params *p, int h, double v)
{
    char name[16];
    snprintf(name, sizeof name, "value_%d", h < 3 ? h : 3);
    int n = 0;
    const double *points = halo_emu_param(p, name, &n);
    if (!points || n < 1)
        return 1.0;
    if (v <= points[0])
        return points[1];
    for (int i = 1; i < n; ++i)
        if (v < points[2 * i]) {
            double d = points[2 * i] - points[2 * i - 2];
            return d > 0.0 ? halo_emu_mix(points[2 * i - 1], points[2 * i + 1], (v - points[2 * i - 2]) / d)
                           : points[2 * i + 1];
        }
    return points[2 * n - 1];
}

static double direction_influence(const halo_emu_params *p, int h, const double n[3])
{
    double width = halo_emu_channel(p, "direction_width", h);
    if (width >= 360.0)
        return 1.0;
    double x = halo_emu_dot(n, halo_emu_host_uniform(p, "screen_right"));
    double y = halo_emu_dot(n, halo_emu_host_uniform(p, "screen_up"));
    if (x * x + y * y < 1.0e-12)
        return 0.0;
    double theta = atan2(x, y) * (180.0 / 3.14159265358979323846);
    double distance = fabs(theta - halo_emu_channel(p, "direction_center", h));
    distance = distance - 360.0 * floor(distance / 360.0); /* GLSL mod */
    if (distance > 180.0)
        distance = 360.0 - distance;
    double softness = halo_emu_channel(p, "direction_softness", h);
    return fall_off(0.5 * width - 0.5 * softness, 0.5 * width + 0.5 * softness, distance);
}

static double position_influence(const halo_emu_params *p, int h, const double position[3])
{
    double r = halo_emu_channel(p, "focus_radius", h);
    const double *focus = halo_emu_channel_param(p, "focus", h);
    double d[3];
    for (int k = 0; k < 3; ++k)
        d[k] = position[k] - (focus ? focus[k] : 0.0);
    return fall_off(r, r + halo_emu_channel(p, "focus_transition", h), sqrt(halo_emu_dot(d, d)));
}

HALO_EMU_STAGE(halo_seed)
{
    double seed[4] = {0, 0, 0, 0};
    int channels = halo_emu_channel_count(p);
    if (!halo_emu_is_zero3(s->normal)) {
        double contour = 1.0 - fabs(halo_emu_dot_clamped(s->normal, s->view));
        for (int h = 0; h < channels; ++h) {
            double g = s->gradient_magnitude * halo_emu_channel(p, "gradient_scale", h);
            g = g < 1.0 ? g : 1.0;
            double weight = value_influence(p, h, s->value) * direction_influence(p, h, s->normal) *
                            position_influence(p, h, s->position);
            seed[h] = halo_emu_clamp(weight * halo_emu_pow(g, halo_emu_channel(p, "alpha", h)) *
                                         halo_emu_pow(contour, halo_emu_channel(p, "beta", h)),
                                     0.0, 1.0);
        }
    }
    for (int h = 0; h < 4; ++h)
        s->seed[h] = seed[h];
}
