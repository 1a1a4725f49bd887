/* Emulation of glsl/lines/strip.glsl in double precision, with the module's guards and
 * branches: the vertex moved sideways by the strip's depth-attenuated, tapered width. It
 * reads s->line_vertex (a program linked into a line vertex host). */
#include <math.h>
#include <string.h>

#include "stages.h"

static void cross3(const double a[3], const double b[3], double out[3])
{
    double r[3] = {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
    memcpy(out, r, sizeof r);
}

/* side_direction: (V x D) / |V x D|, or, where |V x D|^2 <= 1e-12, V x (the axis least
 * aligned with V), normalized. */
static void side_direction(const double view[3], const double direction[3], double out[3])
{
    double side[3];
    cross3(view, direction, side);
    double side_squared = halo_emu_dot(side, side);
    if (side_squared > 1e-12) {
        double scale = 1.0 / sqrt(side_squared);
        for (int i = 0; i < 3; ++i)
            out[i] = side[i] * scale;
        return;
    }
    double magnitude[3] = {fabs(view[0]), fabs(view[1]), fabs(view[2])};
    double axis[3] = {0.0, 0.0, 1.0};
    if (magnitude[0] <= magnitude[1] && magnitude[0] <= magnitude[2])
        axis[0] = 1.0, axis[2] = 0.0;
    else if (magnitude[1] <= magnitude[2])
        axis[1] = 1.0, axis[2] = 0.0;
    cross3(view, axis, side);
    halo_emu_normalize(side, out);
}

static void unit_direction(const double direction[3], double out[3])
{
    double largest = fmax(fabs(direction[0]), fmax(fabs(direction[1]), fabs(direction[2])));
    if (!(largest > 0.0)) {
        out[0] = out[1] = out[2] = 0.0;
        return;
    }
    double scaled[3] = {direction[0] / largest, direction[1] / largest, direction[2] / largest};
    halo_emu_normalize(scaled, out);
}

static double vertex_depth(const double position[3], const double eye[3], const double range[2])
{
    double extent = range[1] - range[0];
    if (!(extent > 0.0))
        return 0.0;
    double d[3] = {position[0] - eye[0], position[1] - eye[1], position[2] - eye[2]};
    return halo_emu_saturate((sqrt(halo_emu_dot(d, d)) - range[0]) / extent);
}

static double taper_factor(double u, double taper, double taper_end)
{
    if (!(taper > 0.0))
        return 1.0;
    return halo_emu_mix(taper_end, 1.0, halo_emu_saturate(fmin(u, 1.0 - u) / taper));
}

HALO_EMU_STAGE(line_strip)
{
    halo_emu_line_vertex *v = &s->line_vertex;
    const double *range = halo_emu_host_uniform(p, "depth_range"); /* (0, 0) when unset */
    double strip_width = halo_emu_scalar(p, "strip_width");
    double depth_attenuation = halo_emu_scalar(p, "depth_attenuation");
    double taper = halo_emu_scalar(p, "taper");
    double taper_end = halo_emu_scalar(p, "taper_end");
    double to_eye[3] = {v->eye[0] - v->position[0], v->eye[1] - v->position[1], v->eye[2] - v->position[2]};
    double view[3], direction[3], side[3];
    halo_emu_normalize(to_eye, view);
    unit_direction(v->direction, direction);
    side_direction(view, direction, side);
    double attenuation = 1.0 - depth_attenuation * vertex_depth(v->position, v->eye, range);
    double strip = strip_width * v->width * attenuation * taper_factor(v->uv[0], taper, taper_end);
    for (int i = 0; i < 3; ++i)
        v->position[i] = v->position[i] + side[i] * ((v->uv[1] - 0.5) * strip);
    v->width = strip;
}
