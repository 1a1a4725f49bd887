/* The slab ray caster (slab.frag): like the slice host (slice.h), but one draw advances
 * every ray by M samples (halo_slice_set_interval), with the ray's accumulated colour
 * and opacity in ping-ponged RGBA32F textures. Sample k of every ray lies on slice k's
 * plane, so for the same M it renders what the slice host renders, with M times fewer
 * draws; the halo images are regenerated between slabs.
 *
 * It shares the slice host's object: create it here, then use halo_slice_*. */
#ifndef HALO_EXAMPLE_SLAB_H
#define HALO_EXAMPLE_SLAB_H

#include "hosts/slice.h"

typedef halo_slice halo_slab;

/* desc as for halo_slice_create; the default fragment shader is slab.frag. */
halo_slab *halo_slab_create(const halo_host_desc *desc, halo_diagnostics *diag);

#endif
