/* Internal: what the GPU halo-buffer builder (gl/feature_splat.c) shares with the CPU
 * emulation (emu/feature_halo.c). Not installed. */
#ifndef HALO_FEATURE_INTERNAL_H
#define HALO_FEATURE_INTERNAL_H

#include "halo_feature.h"

/* The values a desc runs with (halo_feature_layout.desc); desc may be NULL. */
void halo_feature_effective(const halo_feature_desc *desc, halo_feature_desc *out);
/* S of an n x n x n splat (halo_feature_layout.splat_weight_sum). */
double halo_feature_weight_sum(int splat_size);
/* The splat radius in buffer texels of an effective desc (halved, rounded up, at half
 * resolution). */
int halo_feature_splat_radius(const halo_feature_desc *effective);
/* The host contract's gradient at voxel (x, y, z), clamped at the faces. */
void halo_feature_gradient_at(const float *values, const int dims[3], int x, int y, int z, double g[3]);
/* The gradient of every buffer texel (3 doubles each): the voxel's, or the 2x2x2 mean. */
halo_status halo_feature_buffer_gradients(const float *values, const int dims[3], const halo_feature_desc *effective,
                                          double *out);
/* h_n for an outward unit normal, the unit offset e from the neighbour to the sample and
 * the unit view vector. */
double halo_feature_potential(const double normal[3], const double e[3], const double view[3], double k_hpe,
                              double k_hse);

struct halo_emu_params;
/* The registered per-sample emulation (emu/registry.c). */
void halo_emu_feature_halo(halo_emu_sample *s, const struct halo_emu_params *p);

#endif
