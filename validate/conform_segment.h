/* Conformance of segmented ray casting (host contract 2): the emulation of raycast.frag
 * drawn by halo_gl_frame_draw in depth segments (conform_segment.c). */
#ifndef HALO_CONFORM_SEGMENT_H
#define HALO_CONFORM_SEGMENT_H

#include "conform_harness.h"
#include "halo.h"
#include "internal.h"
#include "hosts/raycast.h"

/* The frame of raycast.frag drawn by the plan (halo_segment_plan_make with the state's
 * camera and step), in double: out gets width*height*4 values over the background. The
 * opacity threshold (the host's 0.99) and a shift of every ray's exit are parameters so
 * that a caller can bracket the decisions on them. Returns 0 with diagnostics (a stage
 * without emulation, out of memory). */
int halo_conform_segment_emulate(const halo_raycast_state *s, const halo_program *p, const halo_segment_plan *plan,
                                 double threshold, double exit_move, double *out, halo_diagnostics *diag);

/* A row: the ray caster (raycast.frag) with the scene; segments > 0: linked with
 * force_segments and drawn in exactly that many, against the same host in one draw;
 * 0: drawn as the program needs, against the emulation. --stage segments selects them all. */
typedef struct conform_segment_params {
    const char *scene;
    int segments, orthographic;
} conform_segment_params;
void conform_segment_row(conform *c, const conform_row *row);

#endif
