/* Emulation of glsl/outline/feature.glsl (feature buffers, per sample) and of the image
 * passes of glsl/outline/outline.glsl (unsharp masks, occlusion styles, line colour,
 * depth enhancement), with the same guards, tap order and border rule: Gaussians are
 * truncated at 3 standard deviations (no further than the image) and renormalized over
 * the taps inside the image; every kernel is given by its size, the full width of 6
 * standard deviations (the paper's sigma). docs/outlines.md. */
#include <math.h>
#include <string.h>

#include "stages.h"

/* ---- Feature buffers (per sample) ---- */

static int in_feature(const halo_emu_sample *s, const halo_emu_params *p, int k)
{
    double id = halo_emu_channel(p, "label", k);
    if (id < 0.0)
        return s->value >= halo_emu_channel(p, "value_min", k) && s->value <= halo_emu_channel(p, "value_max", k);
    for (int a = 0; a < 3; ++a)
        if (s->position[a] < 0.0 || s->position[a] > 1.0)
            return 0;
    int dims[3];
    const float *labels = halo_emu_host_volume(p, "labels", dims);
    if (!labels)
        return 0;
    int v[3];
    for (int a = 0; a < 3; ++a) {
        v[a] = (int)floor(s->position[a] * dims[a]);
        v[a] = v[a] < 0 ? 0 : v[a] > dims[a] - 1 ? dims[a] - 1 : v[a];
    }
    double label = labels[((size_t)v[2] * (size_t)dims[1] + (size_t)v[1]) * (size_t)dims[0] + (size_t)v[0]];
    return fabs(label - id) < 0.5;
}

HALO_EMU_STAGE(outline_feature)
{
    int c = halo_emu_channel_count(p);
    for (int k = 0; k < 4; ++k) {
        s->feature_depth[k] = 1.0;
        memset(s->feature_normal[k], 0, sizeof s->feature_normal[k]);
    }
    if (s->opacity > 0.0)
        for (int k = 0; k < c; ++k) {
            if (!in_feature(s, p, k))
                continue;
            double mask = halo_emu_channel(p, "mask_depth", k);
            s->feature_depth[k] = mask >= 0.0 ? mask : s->depth;
            memcpy(s->feature_normal[k], s->normal, 3 * sizeof(double));
            s->feature_normal[k][3] = 1.0;
        }
    for (int k = c; k < 4; ++k) /* halo_channels_from keeps the first c components */
        s->feature_depth[k] = 1.0;
    double threshold = halo_emu_scalar(p, "occluder_opacity");
    s->occluder_depth = s->opacity >= threshold && s->opacity > 0.0 ? s->depth : 1.0;
}

/* ---- Passes ---- */

static double diagonal_pixels(const halo_emu_pass_context *c, double percent)
{
    return percent * 0.01 * sqrt((double)c->width * c->width + (double)c->height * c->height);
}

/* The standard deviation in pixels of a kernel of this size (percent of the diagonal). */
static double deviation_pixels(const halo_emu_pass_context *c, const char *kernel_size)
{
    return diagonal_pixels(c, halo_emu_scalar(c->params, kernel_size) / 6.0);
}

static int kernel_radius(const halo_emu_pass_context *c, double sigma)
{
    int reach = c->width > c->height ? c->width : c->height;
    if (reach > 1024)
        reach = 1024;
    double r = ceil(3.0 * sigma);
    return r < reach ? (int)r : reach;
}

static int inside(const halo_emu_pass_context *c, int x, int y)
{
    return x >= 0 && y >= 0 && x < c->width && y < c->height;
}

static void input4(const halo_emu_pass_context *c, int k, int x, int y, double out[4])
{
    for (int i = 0; i < 4; ++i)
        out[i] = halo_emu_input(c, k, x, y, i);
}

/* taper: weights exp(-t^2/2) - exp(-4.5) (0 at the 3 sigma cut): continuous in sigma,
 * for the per-pixel sigma of depth blurring (outlines.glsl: blur_axis_tapered). */
static void blur_axis_tapered(const halo_emu_pass_context *c, int k, int x, int y, int ax, int ay, double sigma,
                              int taper, double out[4])
{
    if (sigma < 1e-3) {
        input4(c, k, x, y, out);
        return;
    }
    int r = kernel_radius(c, sigma);
    double sum[4] = {0, 0, 0, 0}, weight = 0.0;
    for (int i = -r; i <= r; ++i) {
        int px = x + i * ax, py = y + i * ay;
        if (!inside(c, px, py))
            continue;
        double t = i / sigma, w = exp(-0.5 * t * t), v[4];
        if (taper)
            w = w - exp(-4.5) > 0.0 ? w - exp(-4.5) : 0.0;
        input4(c, k, px, py, v);
        for (int j = 0; j < 4; ++j)
            sum[j] += w * v[j];
        weight += w;
    }
    for (int j = 0; j < 4; ++j)
        out[j] = sum[j] / weight;
}

static void blur_axis(const halo_emu_pass_context *c, int k, int x, int y, int ax, int ay, double sigma, double out[4])
{
    blur_axis_tapered(c, k, x, y, ax, ay, sigma, 0, out);
}

static void min_axis(const halo_emu_pass_context *c, int k, int x, int y, int ax, int ay, double sigma, double out[4])
{
    int r = sigma < 1e-3 ? 0 : kernel_radius(c, sigma);
    input4(c, k, x, y, out);
    for (int i = -r; i <= r; ++i) {
        int px = x + i * ax, py = y + i * ay;
        if (!inside(c, px, py))
            continue;
        double v[4];
        input4(c, k, px, py, v);
        for (int j = 0; j < 4; ++j)
            out[j] = v[j] < out[j] ? v[j] : out[j];
    }
}

static void keep_channels(const halo_emu_pass_context *c, double out[4])
{
    for (int j = c->channels; j < 4; ++j)
        out[j] = 0.0;
}

/* The separable passes: one axis (ax, ay) of a blur or a minimum over the kernel of a
 * size parameter; the depth passes clear the channels beyond the features'. */
typedef void (*axis_fn)(const halo_emu_pass_context *c, int k, int x, int y, int ax, int ay, double sigma,
                        double out[4]);
static void axis_pass(const halo_emu_pass_context *c, int x, int y, axis_fn axis, int ax, int ay,
                      const char *size_parameter, int clear_unused, double out[4])
{
    axis(c, 0, x, y, ax, ay, deviation_pixels(c, size_parameter), out);
    if (clear_unused)
        keep_channels(c, out);
}

HALO_EMU_PASS(outlines, blur_x_pass) { axis_pass(c, x, y, blur_axis, 1, 0, "sigma", 1, out); }
HALO_EMU_PASS(outlines, blur_y_pass) { axis_pass(c, x, y, blur_axis, 0, 1, "sigma", 1, out); }
HALO_EMU_PASS(outlines, min_x_pass) { axis_pass(c, x, y, min_axis, 1, 0, "sigma", 1, out); }
HALO_EMU_PASS(outlines, min_y_pass) { axis_pass(c, x, y, min_axis, 0, 1, "sigma", 1, out); }
HALO_EMU_PASS(outlines, normal_blur_x_pass) { axis_pass(c, x, y, blur_axis, 1, 0, "normal_sigma", 0, out); }
HALO_EMU_PASS(outlines, normal_blur_y_pass) { axis_pass(c, x, y, blur_axis, 0, 1, "normal_sigma", 0, out); }

static double depth_gamma(const halo_emu_params *p, double d)
{
    double start = halo_emu_scalar(p, "depth_start");
    if (d < start || start >= 1.0)
        return 0.0;
    return halo_emu_clamp((d - start) / (1.0 - start), 0.0, 1.0);
}

static double normal_change(const double a[4], const double b[4])
{
    if (a[3] <= 0.0 && b[3] <= 0.0)
        return 0.0;
    double na[3], nb[3];
    halo_emu_normalize(a, na);
    halo_emu_normalize(b, nb);
    return 1.0 - halo_emu_dot(na, nb);
}

static double normal_importance(const halo_emu_params *p, int k, double dn)
{
    double lo = halo_emu_channel(p, "normal_min", k), hi = halo_emu_channel(p, "normal_max", k);
    if (dn < lo)
        return 0.0;
    if (hi <= lo || dn > hi)
        return 1.0;
    return halo_emu_pow((dn - lo) / (hi - lo), halo_emu_channel(p, "normal_power", k));
}

HALO_EMU_PASS(outlines, importance_pass)
{
    const halo_emu_params *p = c->params;
    int n = c->channels, difference = halo_emu_scalar(p, "normal_difference") != 0.0,
        unsharp = halo_emu_scalar(p, "normal_unsharp") != 0.0,
        correction = halo_emu_scalar(p, "depth_correction") != 0.0;
    double occluder = halo_emu_input(c, 3, x, y, 0);
    for (int k = 0; k < n; ++k) {
        double D = halo_emu_input(c, 0, x, y, k), B = halo_emu_input(c, 1, x, y, k),
               d_min = halo_emu_input(c, 2, x, y, k);
        double negative = D - B > 0.0 ? D - B : 0.0;
        double I = halo_emu_clamp(
            halo_emu_channel(p, "lambda", k) * halo_emu_pow(negative, halo_emu_channel(p, "depth_power", k)), 0.0, 1.0);
        double dn = 0.0;
        if (difference) {
            double a[4], b[4], e[4], f[4];
            input4(c, 4 + k, x + 1, y, a);
            input4(c, 4 + k, x - 1, y, b);
            input4(c, 4 + k, x, y + 1, e);
            input4(c, 4 + k, x, y - 1, f);
            double v = normal_change(a, b) + normal_change(e, f);
            dn = v > dn ? v : dn;
        }
        if (unsharp) {
            double nv[4], blurred[4], unit[3];
            input4(c, 4 + k, x, y, nv);
            if (nv[3] > 0.0) {
                input4(c, 4 + n + k, x, y, blurred);
                halo_emu_normalize(nv, unit);
                double v = 1.0 - halo_emu_dot(blurred, unit);
                dn = v > dn ? v : dn;
            }
        }
        if (difference || unsharp) {
            double in = normal_importance(p, k, dn);
            I = in > I ? in : I;
        }
        if (I > 0.0 && d_min < 1.0 && occluder < d_min - halo_emu_scalar(p, "occlusion_bias")) {
            double style = halo_emu_channel(p, "occluded", k);
            int dash = (int)halo_emu_scalar(p, "dash_length");
            if (style < 0.5)
                I = 0.0;
            else if (style < 1.5 && dash > 0 && ((x + y) / dash) % 2 == 1)
                I = 0.0;
        }
        if (halo_emu_scalar(p, "line_fading") != 0.0)
            I = halo_emu_mix(I, 0.0, depth_gamma(p, D >= 1.0 && correction ? d_min : D));
        out[k] = I;
    }
}

/* Border pixels (d = 1): gamma(1) and gamma(d_min) mixed by the outline I
 * (outlines.glsl: border_gamma; continuous in I, so that float and double, which
 * disagree on whether blur tails are zero, stay close). */

/* reduce_pass: inputs importance, feature_depth, depth_min, reduced (the accumulator):
 * min(accumulator, (1 - max I, min d, min d_min, 1)). */
HALO_EMU_PASS(outlines, reduce_pass)
{
    double d = 1.0, d_min = 1.0, line = 0.0;
    for (int k = 0; k < c->channels; ++k) {
        double i = halo_emu_input(c, 0, x, y, k), v = halo_emu_input(c, 1, x, y, k), m = halo_emu_input(c, 2, x, y, k);
        d = v < d ? v : d;
        d_min = m < d_min ? m : d_min;
        line = i > line ? i : line;
    }
    const double mine[4] = {1.0 - line, d, d_min, 1.0};
    for (int j = 0; j < 4; ++j) {
        double acc = halo_emu_input(c, 3, x, y, j);
        out[j] = mine[j] < acc ? mine[j] : acc;
    }
}

/* gamma of a pixel from the reduced features (input `reduced`) */
static double pixel_gamma(const halo_emu_pass_context *c, int x, int y, int reduced)
{
    double line = 1.0 - halo_emu_input(c, reduced, x, y, 0), d = halo_emu_input(c, reduced, x, y, 1),
           d_min = halo_emu_input(c, reduced, x, y, 2);
    int correction = halo_emu_scalar(c->params, "depth_correction") != 0.0;
    if (d < 1.0 || !correction)
        return depth_gamma(c->params, d);
    double t = line < 0.0 ? 0.0 : line > 1.0 ? 1.0 : line;
    return halo_emu_mix(depth_gamma(c->params, d), depth_gamma(c->params, d_min), t);
}

HALO_EMU_PASS(outlines, compose_pass)
{
    const halo_emu_params *p = c->params;
    double back[3], col[3], line[3];
    for (int j = 0; j < 3; ++j)
        back[j] = col[j] = halo_emu_input(c, 0, x, y, j);
    double I = 1.0 - halo_emu_input(c, 1, x, y, 0);
    double gamma = pixel_gamma(c, x, y, 1);
    const double *depth_color = halo_emu_param(p, "depth_color", NULL);
    double gray = halo_emu_scalar(p, "cue_gray");
    for (int j = 0; j < 3; ++j) {
        if (halo_emu_scalar(p, "depth_color_blend") != 0.0 && depth_color)
            col[j] = halo_emu_mix(col[j], depth_color[j], gamma);
        if (halo_emu_scalar(p, "depth_cue") != 0.0)
            col[j] = halo_emu_mix(col[j], gray, gamma);
    }
    int mode = (int)halo_emu_scalar(p, "line_color_mode");
    const double *user = halo_emu_param(p, "line_color", NULL);
    double phi = halo_emu_scalar(p, "background_fraction");
    double brightness = 0.2126 * back[0] + 0.7152 * back[1] + 0.0722 * back[2];
    for (int j = 0; j < 3; ++j) {
        line[j] = mode == 1 ? phi * back[j] : mode == 2 ? (brightness < 0.5 ? 1.0 : 0.0) : user ? user[j] : 0.0;
        out[j] = halo_emu_mix(col[j], line[j], I);
    }
    out[3] = 1.0;
}

static double final_sigma(const halo_emu_pass_context *c, int x, int y)
{
    double size =
        halo_emu_mix(1.0, diagonal_pixels(c, halo_emu_scalar(c->params, "blur_max")), pixel_gamma(c, x, y, 1));
    return size <= 1.0 ? 0.0 : size / 6.0;
}

HALO_EMU_PASS(outlines, final_blur_x_pass)
{
    blur_axis_tapered(c, 0, x, y, 1, 0, final_sigma(c, x, y), 1, out);
    out[3] = 1.0;
}

HALO_EMU_PASS(outlines, final_blur_y_pass)
{
    blur_axis_tapered(c, 0, x, y, 0, 1, final_sigma(c, x, y), 1, out);
    out[3] = 1.0;
}
