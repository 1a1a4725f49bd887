/* The built-in procedural volume of the examples and the conformance suite. */
#ifndef HALO_EXAMPLE_VOLUME_H
#define HALO_EXAMPLE_VOLUME_H

#define HALO_VOLUME_DEFAULT_SIZE 96
#define HALO_VOLUME_MIN_SIZE     8
#define HALO_VOLUME_MAX_SIZE     512

/* A size³ volume (x fastest, then y, then z) of values in [0,1] with features of
 * several scales that occlude each other: two nested spherical shells (the outer one
 * cut open towards +x+z), a thin tube along a trefoil knot winding through the gap
 * between the shells, and small Gaussian blobs, some inside the inner shell. Every
 * edge is smooth over about two voxels, so central-difference gradients are
 * meaningful; the outermost two voxels are zero. Feature sizes scale with size
 * (stated for the default of 96). Deterministic. Returns NULL when size is out of
 * [HALO_VOLUME_MIN_SIZE, HALO_VOLUME_MAX_SIZE] or memory runs out; free() the result. */
float *halo_volume_create(int size);

/* The values each feature peaks at, for transfer functions that separate them. */
#define HALO_VOLUME_OUTER_SHELL 0.3f
#define HALO_VOLUME_INNER_SHELL 0.5f
#define HALO_VOLUME_TUBE        0.75f
#define HALO_VOLUME_BLOB        1.0f

/* The value of GL_LINEAR with GL_CLAMP_TO_EDGE on a dims[0] x dims[1] x dims[2] 3D
 * texture of v (x fastest) at texture coordinate p, in double. */
double halo_volume_trilinear(const float *v, const int dims[3], const double p[3]);

/* Central-difference gradients at the voxels, per voxel step: g = (v[i+1] - v[i-1]) / 2
 * along each axis, indices clamped to the volume (as GL_CLAMP_TO_EDGE reads beyond the
 * edge), in float; 3 floats per voxel, x fastest. Trilinear interpolation of them is
 * the central difference of the trilinear field at +-1 voxel (exactly, away from the
 * edges), so a host can read its gradient with one RGB fetch instead of six. Returns
 * NULL when memory runs out; free() the result. */
float *halo_volume_gradients(const float *v, const int dims[3]);
/* The same for the slices z_first .. z_first + z_count - 1 only (their neighbours are
 * read from v): 3 * dims[0] * dims[1] * z_count floats into out. A host builds its
 * gradient texture slab by slab with it, without a whole-volume copy. */
void halo_volume_gradients_slab(const float *v, const int dims[3], int z_first, int z_count, float *out);
/* The largest |component| of those gradients (0 for a constant volume), without storing
 * them; NaN values are skipped. */
float halo_volume_largest_gradient(const float *v, const int dims[3]);
/* halo_volume_trilinear of a 3-component volume (out: 3 values). */
void halo_volume_trilinear3(const float *v, const int dims[3], const double p[3], double out[3]);

#endif
