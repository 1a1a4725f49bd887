/* Double-precision mirrors of the helpers in glsl/halo_math.glsl, with the same
 * thresholds and branches, so that the emulation and the shaders agree wherever GLSL
 * would otherwise be undefined. */
#include <math.h>

#include "stages.h"

double halo_emu_saturate(double x) { return halo_emu_clamp(x, 0.0, 1.0); }

/* GLSL clamp: min(max(x, lo), hi). */
double halo_emu_clamp(double x, double lo, double hi)
{
    double y = x > lo ? x : lo;
    return y < hi ? y : hi;
}

double halo_emu_pow(double x, double e)
{
    if (x <= 0.0)
        return e == 0.0 ? 1.0 : 0.0;
    return pow(x, e);
}

void halo_emu_normalize(const double v[3], double out[3])
{
    double length_squared = halo_emu_dot(v, v);
    if (length_squared <= 1e-20) {
        out[0] = out[1] = out[2] = 0.0;
        return;
    }
    double scale = 1.0 / sqrt(length_squared);
    for (int i = 0; i < 3; ++i)
        out[i] = v[i] * scale;
}

/* The GLSL built-in dot. */
double halo_emu_dot(const double a[3], const double b[3]) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

double halo_emu_dot_clamped(const double a[3], const double b[3])
{
    return halo_emu_clamp(halo_emu_dot(a, b), -1.0, 1.0);
}

/* The GLSL built-in mix: a (1 - t) + b t. */
double halo_emu_mix(double a, double b, double t) { return a * (1.0 - t) + b * t; }

void halo_emu_rgb_to_hsv(const double rgb[3], double hsv[3])
{
    double r = rgb[0], g = rgb[1], b = rgb[2];
    double maximum = fmax(r, fmax(g, b));
    double minimum = fmin(r, fmin(g, b));
    double chroma = maximum - minimum;
    double hue = 0.0;
    if (chroma > 0.0) {
        if (maximum == r)
            hue = (g - b) / chroma;
        else if (maximum == g)
            hue = 2.0 + (b - r) / chroma;
        else
            hue = 4.0 + (r - g) / chroma;
        hue = hue / 6.0;
        if (hue < 0.0)
            hue = hue + 1.0;
    }
    hsv[0] = hue;
    hsv[1] = maximum > 0.0 ? chroma / maximum : 0.0;
    hsv[2] = maximum;
}

void halo_emu_hsv_to_rgb(const double hsv[3], double rgb[3])
{
    double hue = (hsv[0] - floor(hsv[0])) * 6.0;
    if (!(hue >= 0.0 && hue < 6.0)) /* rounding up to 6, or not finite: keeps (int) defined */
        hue = 0.0;
    double saturation = halo_emu_saturate(hsv[1]);
    double value = hsv[2];
    double sector = floor(hue);
    double fraction = hue - sector;
    double p = value * (1.0 - saturation);
    double q = value * (1.0 - saturation * fraction);
    double t = value * (1.0 - saturation * (1.0 - fraction));
    double out[3];
    switch ((int)sector) {
    case 0:
        out[0] = value;
        out[1] = t;
        out[2] = p;
        break;
    case 1:
        out[0] = q;
        out[1] = value;
        out[2] = p;
        break;
    case 2:
        out[0] = p;
        out[1] = value;
        out[2] = t;
        break;
    case 3:
        out[0] = p;
        out[1] = q;
        out[2] = value;
        break;
    case 4:
        out[0] = t;
        out[1] = p;
        out[2] = value;
        break;
    default:
        out[0] = value;
        out[1] = p;
        out[2] = q;
        break;
    }
    rgb[0] = out[0];
    rgb[1] = out[1];
    rgb[2] = out[2];
}
