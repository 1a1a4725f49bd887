/* The built-in procedural volume (see volume.h). */
#include "volume.h"

#include <math.h>
#include <stdlib.h>

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

/* 1 inside, 0 outside, a smooth (cubic) ramp of `width` across the edge at distance 0;
 * distance is negative inside. */
static double soft_inside(double distance, double width)
{
    double t = 0.5 - distance / width;
    if (t <= 0.0)
        return 0.0;
    if (t >= 1.0)
        return 1.0;
    return t * t * (3.0 - 2.0 * t);
}

static float maxf(float a, float b) { return a > b ? a : b; }

/* The voxels lo..hi (per axis, inclusive) of the box from (int)p - reach to
 * (int)p + reach + 1 around the point p that lie inside the border. */
static void box_inside(double px, double py, double pz, int reach, int border, int size, int lo[3], int hi[3])
{
    const double p[3] = {px, py, pz};
    for (int k = 0; k < 3; ++k) {
        lo[k] = (int)p[k] - reach > border ? (int)p[k] - reach : border;
        hi[k] = (int)p[k] + reach + 1 < size - border - 1 ? (int)p[k] + reach + 1 : size - border - 1;
    }
}

float *halo_volume_create(int size)
{
    if (size < HALO_VOLUME_MIN_SIZE || size > HALO_VOLUME_MAX_SIZE)
        return NULL;
    size_t n = (size_t)size;
    float *v = calloc(n * n * n, sizeof *v);
    if (!v)
        return NULL;
    const double scale = size / 96.0;      /* feature sizes below are in voxels at size 96 */
    const double c = 0.5 * (size - 1);     /* centre, in voxel index units */
    const double edge = 2.0 * scale + 1.0; /* width of every smooth edge */
    const int border = 2;

    /* Nested shells: radius and half thickness. The outer shell is cut open where
     * x and z both exceed the centre, with a smooth cut edge. */
    const double outer_radius = 38.0 * scale, outer_half = 1.8 * scale + 0.5;
    const double inner_radius = 17.0 * scale, inner_half = 2.2 * scale + 0.5;
    for (int z = border; z < size - border; ++z)
        for (int y = border; y < size - border; ++y)
            for (int x = border; x < size - border; ++x) {
                double dx = x - c, dy = y - c, dz = z - c;
                double r = sqrt(dx * dx + dy * dy + dz * dz);
                double outer = soft_inside(fabs(r - outer_radius) - outer_half, edge);
                double cut = soft_inside(-fmin(dx, dz) + 4.0 * scale, edge); /* 1 outside the cut */
                double inner = soft_inside(fabs(r - inner_radius) - inner_half, edge);
                float value =
                    maxf((float)(HALO_VOLUME_OUTER_SHELL * outer * cut), (float)(HALO_VOLUME_INNER_SHELL * inner));
                v[((size_t)z * n + (size_t)y) * n + (size_t)x] = value;
            }

    /* A thin tube along a trefoil knot between the shells: splat the distance to
     * densely spaced points of the curve into a small box around each point. */
    const double tube_radius = 1.6 * scale + 0.4;
    const double knot_scale = 9.0 * scale; /* the knot spans about +-27 voxels at 96 */
    const int points = (int)(1200 * scale) + 200;
    const int reach = (int)ceil(tube_radius + edge) + 1;
    for (int i = 0; i < points; ++i) {
        double t = 2.0 * M_PI * i / points;
        double px = c + knot_scale * (sin(t) + 2.0 * sin(2.0 * t));
        double py = c + knot_scale * (cos(t) - 2.0 * cos(2.0 * t));
        double pz = c - knot_scale * 1.2 * sin(3.0 * t);
        int lo[3], hi[3];
        box_inside(px, py, pz, reach, border, size, lo, hi);
        for (int z = lo[2]; z <= hi[2]; ++z)
            for (int y = lo[1]; y <= hi[1]; ++y)
                for (int x = lo[0]; x <= hi[0]; ++x) {
                    double d = sqrt((x - px) * (x - px) + (y - py) * (y - py) + (z - pz) * (z - pz));
                    float value = (float)(HALO_VOLUME_TUBE * soft_inside(d - tube_radius, edge));
                    float *dst = &v[((size_t)z * n + (size_t)y) * n + (size_t)x];
                    *dst = maxf(*dst, value);
                }
    }

    /* Small Gaussian blobs (sigma 2-4 voxels at 96): three inside the inner shell,
     * the others scattered between and outside the shells. Fixed positions, in units
     * of the half size, and sigmas. */
    static const double blobs[][4] = {
        {0.12, -0.10, 0.05, 2.5}, {-0.15, 0.08, -0.12, 3.0}, {0.02, 0.18, 0.14, 2.0},
        {0.55, 0.40, -0.20, 4.0}, {-0.50, -0.45, 0.30, 3.5}, {0.35, -0.60, -0.35, 2.5},
        {-0.30, 0.62, 0.45, 3.0}, {0.60, -0.05, 0.55, 2.0},  {0.88, 0.10, 0.10, 3.0},
    };
    for (size_t b = 0; b < sizeof blobs / sizeof blobs[0]; ++b) {
        double bx = c + blobs[b][0] * c, by = c + blobs[b][1] * c, bz = c + blobs[b][2] * c;
        double sigma = blobs[b][3] * scale;
        int blob_reach = (int)ceil(3.5 * sigma) + 1;
        int lo[3], hi[3];
        box_inside(bx, by, bz, blob_reach, border, size, lo, hi);
        for (int z = lo[2]; z <= hi[2]; ++z)
            for (int y = lo[1]; y <= hi[1]; ++y)
                for (int x = lo[0]; x <= hi[0]; ++x) {
                    double d2 = (x - bx) * (x - bx) + (y - by) * (y - by) + (z - bz) * (z - bz);
                    float value = (float)(HALO_VOLUME_BLOB * exp(-d2 / (2.0 * sigma * sigma)));
                    float *dst = &v[((size_t)z * n + (size_t)y) * n + (size_t)x];
                    *dst = maxf(*dst, value);
                }
    }
    return v;
}

void halo_volume_gradients_slab(const float *v, const int dims[3], int z_first, int z_count, float *out)
{
    size_t nx = (size_t)dims[0], ny = (size_t)dims[1], nz = (size_t)dims[2];
    size_t slice = nx * ny;
    for (size_t z = (size_t)z_first; z < (size_t)z_first + (size_t)z_count; ++z)
        for (size_t y = 0; y < ny; ++y)
            for (size_t x = 0; x < nx; ++x) {
                size_t at[3] = {x, y, z}, n[3] = {nx, ny, nz}, stride[3] = {1, nx, slice};
                size_t i = (z * ny + y) * nx + x;
                float *g = &out[(i - (size_t)z_first * slice) * 3];
                for (int k = 0; k < 3; ++k) {
                    size_t plus = at[k] + 1 < n[k] ? i + stride[k] : i;
                    size_t minus = at[k] > 0 ? i - stride[k] : i;
                    g[k] = (v[plus] - v[minus]) * 0.5f;
                }
            }
}

float halo_volume_largest_gradient(const float *v, const int dims[3])
{
    size_t nx = (size_t)dims[0], ny = (size_t)dims[1], nz = (size_t)dims[2];
    size_t n[3] = {nx, ny, nz}, stride[3] = {1, nx, nx * ny};
    float largest = 0.0f;
    for (size_t z = 0; z < nz; ++z)
        for (size_t y = 0; y < ny; ++y)
            for (size_t x = 0; x < nx; ++x) {
                size_t at[3] = {x, y, z}, i = (z * ny + y) * nx + x;
                for (int k = 0; k < 3; ++k) {
                    size_t plus = at[k] + 1 < n[k] ? i + stride[k] : i;
                    size_t minus = at[k] > 0 ? i - stride[k] : i;
                    float g = fabsf((v[plus] - v[minus]) * 0.5f);
                    largest = g > largest ? g : largest;
                }
            }
    return largest;
}

float *halo_volume_gradients(const float *v, const int dims[3])
{
    float *g = malloc((size_t)dims[0] * (size_t)dims[1] * (size_t)dims[2] * 3 * sizeof *g);
    if (g)
        halo_volume_gradients_slab(v, dims, 0, dims[2], g);
    return g;
}

/* The eight texels of GL_LINEAR with GL_CLAMP_TO_EDGE at p: their voxel indices (x
 * fastest) and weights. */
static void trilinear_taps(const int dims[3], const double p[3], size_t voxel[8], double weight[8])
{
    int i0[3], i1[3];
    double f[3];
    for (int k = 0; k < 3; ++k) {
        double u = p[k] * dims[k] - 0.5;
        double base = floor(u);
        f[k] = u - base;
        int b = (int)base;
        i0[k] = b < 0 ? 0 : b > dims[k] - 1 ? dims[k] - 1 : b;
        i1[k] = b + 1 < 0 ? 0 : b + 1 > dims[k] - 1 ? dims[k] - 1 : b + 1;
    }
    for (int corner = 0; corner < 8; ++corner) {
        int x = corner & 1 ? i1[0] : i0[0], y = corner & 2 ? i1[1] : i0[1], z = corner & 4 ? i1[2] : i0[2];
        weight[corner] =
            (corner & 1 ? f[0] : 1.0 - f[0]) * (corner & 2 ? f[1] : 1.0 - f[1]) * (corner & 4 ? f[2] : 1.0 - f[2]);
        voxel[corner] = ((size_t)z * (size_t)dims[1] + (size_t)y) * (size_t)dims[0] + (size_t)x;
    }
}

void halo_volume_trilinear3(const float *v, const int dims[3], const double p[3], double out[3])
{
    size_t voxel[8];
    double weight[8];
    trilinear_taps(dims, p, voxel, weight);
    out[0] = out[1] = out[2] = 0.0;
    for (int corner = 0; corner < 8; ++corner)
        for (int c = 0; c < 3; ++c)
            out[c] += weight[corner] * v[voxel[corner] * 3 + (size_t)c];
}

double halo_volume_trilinear(const float *v, const int dims[3], const double p[3])
{
    size_t voxel[8];
    double weight[8];
    trilinear_taps(dims, p, voxel, weight);
    double result = 0.0;
    for (int corner = 0; corner < 8; ++corner)
        result += weight[corner] * v[voxel[corner]];
    return result;
}
