/* The slab ray caster: the slice host in slab mode (see slab.h, slice.c). */
#include "hosts/slab.h"

halo_slab *halo_slab_create(const halo_host_desc *desc, halo_diagnostics *diag)
{
    return halo_slice_create_mode(desc, 1, diag);
}
