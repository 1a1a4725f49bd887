/* The whole-render family of conformance rows (conform_render.c). */
#ifndef HALO_CONFORM_RENDER_H
#define HALO_CONFORM_RENDER_H

#include "conform_harness.h"

/* The ray caster linked with no stage against the unlinked one: every bit equal. */
void conform_empty_row(conform *c, const conform_row *row);
/* A small whole render of the ray caster with several stages against its C emulation,
 * within row->tolerance_abs plus the spread of the threshold decisions. */
void conform_raycast_row(conform *c, const conform_row *row);

#endif
