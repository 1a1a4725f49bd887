/* Feature halos from the neighbourhood (Ebert & Rheingans 2000, Sec. 5.2; Svakhine &
 * Ebert 2003, Sec. 3.3-3.4) on the CPU, in double precision: the exact reference, the
 * emulation of the GPU halo buffer (libhalo/gl/feature_splat.c) and the emulation of the
 * per-sample stage glsl/feature/feature_halo.glsl. docs/feature-halos.md. */
#include "diag.h"
#include "emu.h"
#include "stages.h"
#include "halo_feature.h"
#include "internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "feature_internal.h"

void halo_feature_effective(const halo_feature_desc *desc, halo_feature_desc *out)
{
    halo_feature_desc d = desc ? *desc : (halo_feature_desc){0};
    if (d.splat_size == 0)
        d.splat_size = 5;
    if (d.splat_size < HALO_FEATURE_SPLAT_MIN)
        d.splat_size = HALO_FEATURE_SPLAT_MIN;
    if (d.splat_size > HALO_FEATURE_SPLAT_MAX)
        d.splat_size = HALO_FEATURE_SPLAT_MAX;
    if (d.splat_size % 2 == 0)
        d.splat_size += 1;
    if (d.threshold == 0.0 || !(d.threshold == d.threshold))
        d.threshold = 0.1;
    if (d.k_hpe == 0.0 || !(d.k_hpe >= 0.0))
        d.k_hpe = 1.0;
    if (d.k_hse == 0.0 || !(d.k_hse >= 0.0))
        d.k_hse = 2.0;
    d.half_resolution = d.half_resolution ? 1 : 0;
    d.gradient_weighted = d.gradient_weighted ? 1 : 0;
    *out = d;
}

/* The buffer's texels for a volume of dims voxels, for an effective desc. */
static void buffer_dims(const int dims[3], const halo_feature_desc *effective, int out[3])
{
    for (int k = 0; k < 3; ++k)
        out[k] = effective->half_resolution ? (dims[k] + 1) / 2 : dims[k];
}

int halo_feature_splat_radius(const halo_feature_desc *effective)
{
    int r = (effective->splat_size - 1) / 2;
    return effective->half_resolution ? (r + 1) / 2 : r;
}

double halo_feature_weight_sum(int splat_size)
{
    int r = (splat_size - 1) / 2;
    if (r < 1)
        r = 1;
    double sum = 0.0;
    for (int z = -r; z <= r; ++z)
        for (int y = -r; y <= r; ++y)
            for (int x = -r; x <= r; ++x)
                if (x || y || z)
                    sum += 1.0 / (double)(x * x + y * y + z * z);
    return sum;
}

halo_feature_layout halo_feature_desc_layout(const halo_feature_desc *desc, const int dims[3])
{
    halo_feature_layout layout;
    memset(&layout, 0, sizeof layout);
    halo_feature_effective(desc, &layout.desc);
    if (dims)
        buffer_dims(dims, &layout.desc, layout.buffer_dims);
    layout.splat_radius = halo_feature_splat_radius(&layout.desc);
    layout.splat_weight_sum = halo_feature_weight_sum(layout.desc.splat_size);
    return layout;
}

static int dims_ok(const int dims[3])
{
    return dims && dims[0] > 0 && dims[1] > 0 && dims[2] > 0 && dims[0] <= 8192 && dims[1] <= 8192 && dims[2] <= 8192 &&
           (size_t)dims[0] * (size_t)dims[1] * (size_t)dims[2] <= ((size_t)1 << 30);
}

static size_t voxel_count(const int dims[3]) { return (size_t)dims[0] * (size_t)dims[1] * (size_t)dims[2]; }

static float value_at(const float *v, const int dims[3], int x, int y, int z)
{
    x = x < 0 ? 0 : x >= dims[0] ? dims[0] - 1 : x;
    y = y < 0 ? 0 : y >= dims[1] ? dims[1] - 1 : y;
    z = z < 0 ? 0 : z >= dims[2] ? dims[2] - 1 : z;
    return v[((size_t)z * (size_t)dims[1] + (size_t)y) * (size_t)dims[0] + (size_t)x];
}

void halo_feature_gradient_at(const float *v, const int dims[3], int x, int y, int z, double g[3])
{
    /* the host contract: (f(+1) - f(-1)) / 2, each difference of the stored floats */
    g[0] = ((double)value_at(v, dims, x + 1, y, z) - (double)value_at(v, dims, x - 1, y, z)) * 0.5;
    g[1] = ((double)value_at(v, dims, x, y + 1, z) - (double)value_at(v, dims, x, y - 1, z)) * 0.5;
    g[2] = ((double)value_at(v, dims, x, y, z + 1) - (double)value_at(v, dims, x, y, z - 1)) * 0.5;
}

halo_status halo_feature_gradient_magnitudes(const float *values, const int dims[3], float *out)
{
    HALO_REFUSE_NULL(NULL, values, "values", HALO_ERROR_INPUT);
    HALO_REFUSE_NULL(NULL, dims, "dims", HALO_ERROR_INPUT);
    HALO_REFUSE_NULL(NULL, out, "out", HALO_ERROR_INPUT);
    if (!dims_ok(dims))
        return HALO_ERROR_INPUT;
    size_t i = 0;
    for (int z = 0; z < dims[2]; ++z)
        for (int y = 0; y < dims[1]; ++y)
            for (int x = 0; x < dims[0]; ++x) {
                double g[3];
                halo_feature_gradient_at(values, dims, x, y, z, g);
                out[i++] = (float)sqrt(g[0] * g[0] + g[1] * g[1] + g[2] * g[2]);
            }
    return HALO_OK;
}

halo_status halo_feature_buffer_gradients(const float *values, const int dims[3], const halo_feature_desc *effective,
                                          double *out)
{
    int bd[3];
    buffer_dims(dims, effective, bd);
    if (!effective->half_resolution) {
        size_t i = 0;
        for (int z = 0; z < dims[2]; ++z)
            for (int y = 0; y < dims[1]; ++y)
                for (int x = 0; x < dims[0]; ++x, ++i)
                    halo_feature_gradient_at(values, dims, x, y, z, &out[i * 3]);
        return HALO_OK;
    }
    /* IVIS Sec. 3.4: each half-resolution texel gets the mean gradient of its 2x2x2
     * block (fewer voxels at the far faces of odd sizes) */
    size_t i = 0;
    for (int z = 0; z < bd[2]; ++z)
        for (int y = 0; y < bd[1]; ++y)
            for (int x = 0; x < bd[0]; ++x, ++i) {
                double sum[3] = {0, 0, 0};
                int n = 0;
                for (int dz = 0; dz < 2; ++dz)
                    for (int dy = 0; dy < 2; ++dy)
                        for (int dx = 0; dx < 2; ++dx) {
                            int vx = 2 * x + dx, vy = 2 * y + dy, vz = 2 * z + dz;
                            if (vx >= dims[0] || vy >= dims[1] || vz >= dims[2])
                                continue;
                            double g[3];
                            halo_feature_gradient_at(values, dims, vx, vy, vz, g);
                            sum[0] += g[0], sum[1] += g[1], sum[2] += g[2];
                            ++n;
                        }
                for (int k = 0; k < 3; ++k)
                    out[i * 3 + k] = sum[k] / (double)n;
            }
    return HALO_OK;
}

double halo_feature_potential(const double normal[3], const double e[3], const double view[3], double k_hpe,
                              double k_hse)
{
    /* h_n = max(0, n.e)^k_hpe (1 - |n.V|)^k_hse. A neighbour whose outward normal points
     * away from the sample (n.e <= 0) contributes nothing: a negative base has no real
     * fractional power, and halos belong outside features. |n.V| as in IVIS Eq. 2: the
     * term is 1 for normals in the plane facing the viewer, 0 for normals along V. */
    double facing = normal[0] * e[0] + normal[1] * e[1] + normal[2] * e[2];
    if (!(facing > 0.0))
        return 0.0;
    double along = fabs(normal[0] * view[0] + normal[1] * view[1] + normal[2] * view[2]);
    /* 1 - |n.V| = |n x V|^2 / (1 + |n.V|) for unit vectors; this form has no cancellation
     * where n is nearly along V (the GPU computes the same) */
    double across[3] = {normal[1] * view[2] - normal[2] * view[1], normal[2] * view[0] - normal[0] * view[2],
                        normal[0] * view[1] - normal[1] * view[0]};
    double in_plane = (across[0] * across[0] + across[1] * across[1] + across[2] * across[2]) / (1.0 + along);
    if (in_plane > 1.0)
        in_plane = 1.0;
    return halo_emu_pow(facing > 1.0 ? 1.0 : facing, k_hpe) * halo_emu_pow(in_plane, k_hse);
}

/* The outward unit normal -g/|g| of a gradient, 0 when it has no direction. */
static int outward_normal(const double g[3], double n[3])
{
    double length_squared = g[0] * g[0] + g[1] * g[1] + g[2] * g[2];
    if (length_squared <= 1e-20) {
        n[0] = n[1] = n[2] = 0.0;
        return 0;
    }
    double inverse = 1.0 / sqrt(length_squared);
    n[0] = -g[0] * inverse, n[1] = -g[1] * inverse, n[2] = -g[2] * inverse;
    return 1;
}

static void unit_view(const double view[3], double out[3]) { halo_emu_normalize(view, out); }

/* Scatters the splats of the voxels with |g| > cutoff into out (bd texels, zeroed by
 * the caller): out[t] += weight(d) h(n_s, d/|d|); weight 1/|d|^2 times scale. */
static void scatter(const double *gradients, const int bd[3], int radius, double cutoff, const double view[3],
                    double k_hpe, double k_hse, int weighted, double scale, double *out)
{
    size_t s = 0;
    for (int z = 0; z < bd[2]; ++z)
        for (int y = 0; y < bd[1]; ++y)
            for (int x = 0; x < bd[0]; ++x, ++s) {
                const double *g = &gradients[s * 3];
                double magnitude = sqrt(g[0] * g[0] + g[1] * g[1] + g[2] * g[2]);
                double n[3];
                if (!(magnitude > cutoff) || !outward_normal(g, n))
                    continue;
                double strength = weighted ? halo_emu_pow(magnitude, k_hpe) : 1.0;
                for (int dz = -radius; dz <= radius; ++dz) {
                    int tz = z + dz;
                    if (tz < 0 || tz >= bd[2])
                        continue;
                    for (int dy = -radius; dy <= radius; ++dy) {
                        int ty = y + dy;
                        if (ty < 0 || ty >= bd[1])
                            continue;
                        for (int dx = -radius; dx <= radius; ++dx) {
                            int tx = x + dx;
                            if (tx < 0 || tx >= bd[0] || !(dx || dy || dz))
                                continue;
                            double d2 = (double)(dx * dx + dy * dy + dz * dz);
                            double length = sqrt(d2);
                            double e[3] = {dx / length, dy / length, dz / length};
                            double h = halo_feature_potential(n, e, view, k_hpe, k_hse);
                            if (h != 0.0)
                                out[((size_t)tz * (size_t)bd[1] + (size_t)ty) * (size_t)bd[0] + (size_t)tx] +=
                                    strength * h * scale / d2;
                        }
                    }
                }
            }
}

/* The two buffers share their inputs and their splatting: the reference (full
 * resolution, every splat's whole extent, scaled by 1 - |grad f| per voxel) and the
 * emulation of the GPU's buffer (its resolution, radius, threshold and weight sum). */
static halo_status feature_buffer(const float *values, const int dims[3], const halo_feature_desc *desc,
                                  const double view[3], int reference, double *out)
{
    if (!dims_ok(dims))
        return HALO_ERROR_INPUT;
    halo_feature_desc d;
    halo_feature_effective(desc, &d);
    if (reference)
        d.half_resolution = 0;
    int bd[3];
    buffer_dims(dims, &d, bd);
    size_t count = voxel_count(bd);
    double *gradients = malloc(count * 3 * sizeof *gradients);
    if (!gradients)
        return HALO_ERROR_IO;
    halo_feature_buffer_gradients(values, dims, &d, gradients);
    double v[3];
    unit_view(view, v);
    memset(out, 0, count * sizeof *out);
    if (reference) {
        scatter(gradients, bd, (d.splat_size - 1) / 2, 1e-10, v, d.k_hpe, d.k_hse, d.gradient_weighted, 1.0, out);
        for (size_t i = 0; i < count; ++i) {
            const double *g = &gradients[i * 3];
            out[i] *= halo_emu_saturate(1.0 - sqrt(g[0] * g[0] + g[1] * g[1] + g[2] * g[2]));
        }
    } else {
        int radius = halo_feature_splat_radius(&d);
        double cutoff = d.threshold < 0.0 ? 1e-10 : d.threshold;
        scatter(gradients, bd, radius, cutoff, v, d.k_hpe, d.k_hse, d.gradient_weighted,
                1.0 / halo_feature_weight_sum(2 * radius + 1), out);
    }
    free(gradients);
    return HALO_OK;
}

/* In the public function itself, so that a refusal names it. */
#define REFUSE_NULL_BUFFER_ARGUMENTS()                              \
    do {                                                            \
        HALO_REFUSE_NULL(NULL, values, "values", HALO_ERROR_INPUT); \
        HALO_REFUSE_NULL(NULL, dims, "dims", HALO_ERROR_INPUT);     \
        HALO_REFUSE_NULL(NULL, view, "view", HALO_ERROR_INPUT);     \
        HALO_REFUSE_NULL(NULL, out, "out", HALO_ERROR_INPUT);       \
    } while (0)

halo_status halo_feature_compute(halo_feature_result result, const float *values, const int dims[3],
                                 const halo_feature_desc *desc, const double view[3], double *out)
{
    REFUSE_NULL_BUFFER_ARGUMENTS();
    if (result != HALO_FEATURE_REFERENCE && result != HALO_FEATURE_EMULATED_BUFFER) {
        HALO_REPORT_ERROR(NULL, HALO_MSG_USAGE, "", 0, 0,
                          "halo_feature_compute: result %d is not a halo_feature_result", (int)result);
        return HALO_ERROR_INPUT;
    }
    return feature_buffer(values, dims, desc, view, result == HALO_FEATURE_REFERENCE, out);
}

double halo_feature_buffer_lookup(const double *buffer, const int dims[3], const double position[3])
{
    HALO_REFUSE_NULL(NULL, buffer, "buffer", 0.0);
    HALO_REFUSE_NULL(NULL, dims, "dims", 0.0);
    HALO_REFUSE_NULL(NULL, position, "position", 0.0);
    if (!dims_ok(dims))
        return 0.0;
    int i0[3], i1[3];
    double f[3];
    for (int k = 0; k < 3; ++k) {
        double u = position[k] * dims[k] - 0.5;
        if (!(u == u))
            return 0.0;
        if (u < -1.0)
            u = -1.0;
        if (u > dims[k])
            u = dims[k];
        double base = floor(u);
        f[k] = u - base;
        int b = (int)base;
        i0[k] = b < 0 ? 0 : b > dims[k] - 1 ? dims[k] - 1 : b;
        i1[k] = b + 1 < 0 ? 0 : b + 1 > dims[k] - 1 ? dims[k] - 1 : b + 1;
    }
    double result = 0.0;
    for (int corner = 0; corner < 8; ++corner) {
        int x = corner & 1 ? i1[0] : i0[0], y = corner & 2 ? i1[1] : i0[1], z = corner & 4 ? i1[2] : i0[2];
        double w =
            (corner & 1 ? f[0] : 1.0 - f[0]) * (corner & 2 ? f[1] : 1.0 - f[1]) * (corner & 4 ? f[2] : 1.0 - f[2]);
        result += w * buffer[((size_t)z * (size_t)dims[1] + (size_t)y) * (size_t)dims[0] + (size_t)x];
    }
    return result;
}

halo_status halo_feature_desc_from_program(const halo_program *p, halo_feature_desc *out)
{
    HALO_REFUSE_NULL(NULL, p, "program", HALO_ERROR_INPUT);
    HALO_REFUSE_NULL(NULL, out, "out", HALO_ERROR_INPUT);
    for (size_t i = 0; i < p->stage_count; i++) {
        const halo_linked_stage *st = &p->stages[i];
        if (strcmp(st->module->name, "feature_halo"))
            continue;
        halo_emu_params params = {p, st, NULL};
        halo_feature_desc d = {0};
        d.k_hpe = halo_emu_scalar(&params, "k_hpe");
        d.k_hse = halo_emu_scalar(&params, "k_hse");
        d.splat_size = (int)halo_emu_scalar(&params, "splat_size");
        d.threshold = halo_emu_scalar(&params, "threshold");
        if (d.threshold == 0.0)
            d.threshold = -1.0; /* 0 in a scene: every voxel with a gradient */
        d.half_resolution = halo_emu_scalar(&params, "half_resolution") != 0.0;
        d.gradient_weighted = halo_emu_scalar(&params, "gradient_weighted") != 0.0;
        halo_feature_effective(&d, out);
        return HALO_OK;
    }
    return HALO_ERROR_INPUT;
}

/* ---- The per-sample stage ----------------------------------------------------------- */

static void apply_stage(halo_emu_sample *s, const halo_emu_params *p, double buffer_value)
{
    double opacity_gain = halo_emu_scalar(p, "opacity_gain");
    double darkening = halo_emu_scalar(p, "darkening");
    double influence = buffer_value > 0.0 ? buffer_value : 0.0;
    double halo = influence * halo_emu_saturate(1.0 - s->gradient_magnitude);
    s->opacity = halo_emu_saturate(s->opacity + opacity_gain * halo);
    double factor = halo_emu_saturate(1.0 - darkening * halo);
    for (int k = 0; k < 3; ++k)
        s->color[k] *= factor;
}

/* The registered emulation (halo_emu_lookup "feature_halo"): the emulated frame cannot
 * hold a 3D texture, so its host uniform `feature_buffer` holds the buffer's value at
 * the sample, set by the caller per sample (0 without a frame, as an unbound sampler). */
HALO_EMU_STAGE(feature_halo) { apply_stage(s, p, halo_emu_host_uniform(p, "feature_buffer")[0]); }
