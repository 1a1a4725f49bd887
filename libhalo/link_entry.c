/* halo_link, the linker's front door: what the desc asks for, checked once, then host text
 * (link.c's pipeline) or pieces for a shader composer (compose.c, through the same
 * pipeline). Its own file, so that neither path's file calls the other's. */
#include "diag.h"
#include "internal.h"

/* The public entry: host text (halo_link_host, link.c) or pieces (halo_link_pieces,
 * compose.c, which links them into a stand-in host through halo_link_host). */
halo_program *halo_link(const halo_link_desc *desc, halo_diagnostics *diag)
{
    HALO_REFUSE_NULL(diag, desc, "desc", NULL);
    HALO_REFUSE_NULL(diag, desc->library, "desc.library", NULL);
    if (!desc->pieces)
        HALO_REFUSE_NULL(diag, desc->host_source, "desc.host_source (or desc.pieces)", NULL);
    if ((unsigned)desc->output_locations >= HALO_LOCATIONS_COUNT) {
        halo_diag_error(diag, USAGE, "", 0, 0, "halo_link: unknown output_locations %d", (int)desc->output_locations);
        return NULL;
    }
    if (desc->pieces && !desc->host_source)
        return halo_link_pieces(desc, diag);
    if (desc->pieces) {
        halo_diag_error(diag, USAGE, "", 0, 0, "halo_link: give host_source or pieces, not both");
        return NULL;
    }
    if ((unsigned)desc->version > HALO_VERSION_NONE) {
        halo_diag_error(diag, USAGE, "", 0, 0, "halo_link: unknown version mode %d", (int)desc->version);
        return NULL;
    }
    return halo_link_host(desc, diag);
}
