/* Emulation of the line stages (glsl/lines/strip.glsl, glsl/lines/halo.glsl) in double
 * precision, with the guards and branches of the GLSL modules. Line stages run at hooks
 * of their own (line_vertex, line_fragment), so they are applied through
 * halo_emu_line_vertex_apply / halo_emu_line_fragment_apply rather than halo_emu_apply. */
#include <math.h>
#include <string.h>

#include "diag.h"
#include "emu.h"

/* The current value of stage.param (first component), or fallback when absent. */
static double param_value(const halo_program *p, const char *stage, const char *param, double fallback)
{
    const halo_uniform_info *u = halo_program_find_uniform(p, stage, param);
    return u && u->value && u->count > 0 ? u->value[0] : fallback;
}

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

static void line_strip(const halo_program *p, const double range[2], halo_emu_line_vertex *v)
{
    double strip_width = param_value(p, "line_strip", "strip_width", 0.03);
    double depth_attenuation = param_value(p, "line_strip", "depth_attenuation", 0.5);
    double taper = param_value(p, "line_strip", "taper", 0.1);
    double taper_end = param_value(p, "line_strip", "taper_end", 0.25);
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

static double displacement(double x, int profile, double core)
{
    if (profile == 1)
        return x * x * (3.0 - 2.0 * x);
    if (profile == 2)
        return x < core ? 0.0 : 1.0;
    return x;
}

static void line_halo(const halo_program *p, halo_emu_line_fragment *f)
{
    double core = param_value(p, "line_halo", "core", 0.4);
    double d_max = param_value(p, "line_halo", "d_max", 0.05);
    int profile = (int)param_value(p, "line_halo", "profile", 0.0);
    double x = halo_emu_saturate(2.0 * fabs(f->uv[1] - 0.5));
    if (!(x < core)) {
        memcpy(f->color, f->background, sizeof f->color);
        f->opacity = 1.0;
    }
    f->depth = f->depth + d_max * displacement(x, profile, core);
}

static halo_status missing(const char *stage, halo_diagnostics *diag)
{
    halo_diag_error(diag, EMU_MISSING, "", 0, 0, "line stage '%s' has no C emulation", stage);
    return HALO_ERROR_INPUT;
}

halo_status halo_emu_line_vertex_apply(const halo_program *p, const double depth_range[2], halo_emu_line_vertex *v,
                                       halo_diagnostics *diag)
{
    HALO_REFUSE_NULL(diag, p, "program", HALO_ERROR_INPUT);
    HALO_REFUSE_NULL(diag, v, "vertex", HALO_ERROR_INPUT);
    const double unset[2] = {0.0, 0.0};
    const double *range = depth_range ? depth_range : unset;
    for (size_t i = 0; i < halo_program_reflection(p).stage_count; ++i) {
        const char *stage = halo_program_reflection(p).stages[i].name;
        if (strcmp(stage, "line_strip") == 0)
            line_strip(p, range, v);
        else
            return missing(stage, diag);
    }
    return HALO_OK;
}

halo_status halo_emu_line_fragment_apply(const halo_program *p, halo_emu_line_fragment *f, halo_diagnostics *diag)
{
    HALO_REFUSE_NULL(diag, p, "program", HALO_ERROR_INPUT);
    HALO_REFUSE_NULL(diag, f, "fragment", HALO_ERROR_INPUT);
    for (size_t i = 0; i < halo_program_reflection(p).stage_count; ++i) {
        const char *stage = halo_program_reflection(p).stages[i].name;
        if (strcmp(stage, "line_halo") == 0)
            line_halo(p, f);
        else
            return missing(stage, diag);
    }
    return HALO_OK;
}
