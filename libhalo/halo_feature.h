/* libhalo feature halos from the neighbourhood (Ebert & Rheingans 2000, Sec. 5.2;
 * Svakhine & Ebert 2003, Sec. 3.3-3.4): the halo buffer built on the GPU by additive
 * splatting, its double-precision emulation, and the exact reference.
 *
 * The per-sample stage `feature_halo` (glsl/feature/feature_halo.glsl) reads the buffer
 * through its host uniform `halo_host_feature_buffer` (a sampler3D): build the buffer
 * for the current view with halo_feature_buffer_build, bind halo_feature_buffer_describe(b).texture
 * to a free texture unit and set the sampler to that unit (glUniform1i). Rebuild it
 * whenever the view direction changes. docs/feature-halos.md has the formulas, the
 * conventions and the measured costs and errors.
 *
 * Volumes are float values already normalized to [0,1], x fastest, one voxel per step;
 * every position and direction is in voxel index space (for the cube the example hosts
 * render, texture space up to the scale). Gradients are the host contract's: central
 * differences over +-1 voxel divided by 2 (value per voxel step), clamped at the
 * volume's faces like a CLAMP_TO_EDGE texture sampled at voxel centres. */
#ifndef HALO_FEATURE_H
#define HALO_FEATURE_H

#include <stddef.h>

#include "halo.h"

#ifdef __cplusplus
extern "C" {
#endif

/* The host uniform (a sampler3D) through which a stage reads the halo buffer: a host
 * or driver that finds it in the program's host uniforms (halo_program_reflection) builds and binds the buffer. */
#define HALO_HOST_FEATURE_BUFFER "halo_host_feature_buffer"

#define HALO_FEATURE_SPLAT_MIN 3
#define HALO_FEATURE_SPLAT_MAX 9

/* Zero means "use the default" for every field (halo_feature_desc_layout: desc). */
typedef struct halo_feature_desc {
    int splat_size;        /* n: the neighbourhood is the n x n x n cube around a voxel, odd, 3..9; default 5 */
    double threshold;      /* low-gradient cutoff: only voxels with |grad f| > threshold splat (value per
                          * voxel step); default 0.1; negative: no cutoff (every voxel whose gradient has
                          * a direction, |grad f| > 1e-10, as the exact reference) */
    int half_resolution;   /* 1: the buffer has ceil(dims/2) texels per side; gradients are the mean over
                          * each 2x2x2 block; the splat radius is halved (rounded up) so that it covers
                          * the same neighbourhood */
    double k_hpe;          /* how directly a neighbour's normal must point at the sample; default 1 (Fig. 6) */
    double k_hse;          /* how tightly halos are kept in the plane facing the viewer; default 2 (Fig. 6) */
    int gradient_weighted; /* 1: IVIS Eq. 2, |grad f(P_n) . e|^k_hpe with the unnormalized gradient, i.e.
                            * h_n times |grad f(P_n)|^k_hpe: weak gradients add little, which is what
                            * makes the low-gradient cutoff a good approximation; 0: Ebert & Rheingans
                            * 2000 with the normalized gradient (the default) */
} halo_feature_desc;

/* What a desc makes, by value. desc may be NULL (every default); dims (a volume's voxels)
 * may be NULL (buffer_dims 0). */
typedef struct halo_feature_layout {
    halo_feature_desc desc;  /* the values it runs with: defaults patched in, splat size forced odd and
                             * into range */
    int buffer_dims[3];      /* the buffer's size in texels (ceil(dims/2) at half resolution) */
    int splat_radius;        /* in buffer texels: (n - 1)/2, halved and rounded up at half resolution */
    double splat_weight_sum; /* S: the sum of 1/|d|^2 over the offsets d != 0 of the n x n x n
                              * neighbourhood (voxel units). A splat texel's weight is (1/|d|^2)/S, so
                              * one splat's weights sum to 1 and the buffer holds the paper's neighbour
                              * sum divided by S (docs/feature-halos.md) */
} halo_feature_layout;
HALO_API halo_feature_layout halo_feature_desc_layout(const halo_feature_desc *desc, const int dims[3]);

/* The desc a linked program's feature_halo stage asks for (its parameters k_hpe, k_hse,
 * splat_size, threshold, half_resolution, gradient_weighted, current values).
 * HALO_ERROR_INPUT when the program has no feature_halo stage. */
HALO_API halo_status halo_feature_desc_from_program(const halo_program *p, halo_feature_desc *out);

/* ---- Reference and emulation (double precision, CPU) ---------------------------- */

/* |grad f| of every voxel (dims[0]*dims[1]*dims[2] floats). HALO_ERROR_INPUT on bad
 * arguments. */
HALO_API halo_status halo_feature_gradient_magnitudes(const float *values, const int dims[3], float *out);

/* What halo_feature_compute computes, in double precision:
 * HALO_FEATURE_REFERENCE: the exact reference, Ebert & Rheingans 2000, Sec. 5.2, at every
 * voxel P_i:
 *   h_i = ( sum_{n in cube, n != i} h_n / |P_i - P_n|^2 ) (1 - |grad f(P_i)|)
 *   h_n = max(0, n(P_n).e)^k_hpe (1 - |n(P_n).V|)^k_hse,  e = (P_i - P_n)/|P_i - P_n|
 * (times |grad f(P_n)|^k_hpe with desc->gradient_weighted)
 * with n = -grad f/|grad f| (points out of dense material) and V the unit view vector
 * (sample -> eye, voxel space, one direction for the whole volume). Neighbours without a
 * gradient direction (|grad f| <= 1e-10) and outside the volume contribute nothing. No
 * cutoff, full resolution, unnormalized weights. out: dims[0]*dims[1]*dims[2] doubles.
 * HALO_FEATURE_EMULATED_BUFFER: the emulation of halo_feature_buffer_build, the
 * normalized, cut-off (and optionally half-resolution) neighbour sum the GPU splats. out:
 * the buffer's texels (halo_feature_layout.buffer_dims), x fastest. */
typedef enum halo_feature_result { HALO_FEATURE_REFERENCE = 0, HALO_FEATURE_EMULATED_BUFFER } halo_feature_result;
HALO_API halo_status halo_feature_compute(halo_feature_result result, const float *values, const int dims[3],
                                          const halo_feature_desc *desc, const double view[3], double *out);

/* The buffer read as the stage reads it: GL_LINEAR with CLAMP_TO_EDGE at texture-space
 * position (in [0,1]^3) of a buffer of dims texels, in double. */
HALO_API double halo_feature_buffer_lookup(const double *buffer, const int dims[3], const double position[3]);

/* The emulation (halo_emu_apply) reads the halo buffer through an emulated frame's host
 * uniform: halo_emu_frame_set_host_uniform(frame, HALO_HOST_FEATURE_BUFFER, &value, 1) with
 * the buffer's value at the sample (e.g. from halo_feature_buffer_lookup): the emulated
 * frame has no 3D textures. Without a frame it reads 0 (an unbound sampler). */

/* ---- The GPU halo buffer ----------------------------------------------------------- */

typedef struct halo_feature_buffer halo_feature_buffer;

/* Preprocesses the volume once (gradients, the qualified voxels sorted by z, a vertex
 * buffer) and creates the R32F 3D texture (on an OpenGL ES context that cannot render,
 * blend and filter R32F: R16F, with a note), its framebuffer and the splat program in the
 * current context of gl. The volume is copied. NULL with diagnostics (USAGE,
 * OUT_OF_MEMORY, GL_COMPILE, GL_LINK, ENGINE_UNSUPPORTED) on failure. */
HALO_API halo_feature_buffer *halo_feature_buffer_create(halo_gl *gl, const float *values, const int dims[3],
                                                         const halo_feature_desc *desc, halo_diagnostics *diag);
HALO_API void halo_feature_buffer_destroy(halo_feature_buffer *b);
/* Splats the buffer for unit view vector view (sample -> eye, voxel space): per layer of
 * the buffer, the qualified voxels within reach drawn as points of the splat's size with
 * additive blending. Saves and restores the GL state it touches (framebuffer, viewport,
 * program, blending, vertex array). */
HALO_API halo_status halo_feature_buffer_build(halo_feature_buffer *b, const double view[3]);
/* What a buffer is: a copy, cheap to take. A NULL buffer: every field 0. */
typedef struct halo_feature_buffer_info {
    unsigned texture;    /* its GL texture name (GL_TEXTURE_3D, R32F or R16F, GL_LINEAR, CLAMP_TO_EDGE) */
    int dims[3];         /* its size in texels (halo_feature_layout.buffer_dims of the volume) */
    size_t qualified;    /* voxels that splat (|grad f| above the cutoff, at the buffer's resolution) */
    size_t points_drawn; /* points drawn by the last build (each qualified voxel once per layer it reaches) */
} halo_feature_buffer_info;
HALO_API halo_feature_buffer_info halo_feature_buffer_describe(const halo_feature_buffer *b);
/* Reads the buffer back: dims[0]*dims[1]*dims[2] floats, x fastest. */
HALO_API halo_status halo_feature_buffer_read(halo_feature_buffer *b, float *out);

#ifdef __cplusplus
}
#endif

#endif
