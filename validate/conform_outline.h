/* Conformance rows of the outline passes (glsl/outline/outlines.glsl, docs/outlines.md):
 * feature buffers drawn through the frame probe, then the at=post passes on the GPU
 * (halo_gl_frame_post) against their emulation (halo_emu_frame_post). */
#ifndef HALO_CONFORM_OUTLINE_H
#define HALO_CONFORM_OUTLINE_H

#include "conform_harness.h"

/* The synthetic feature buffers of a case. */
enum conform_outline_shape {
    OUTLINE_DISCS,     /* four discs of one feature at several depths */
    OUTLINE_FLAT,      /* a constant depth */
    OUTLINE_DEPTH_ONE, /* features at depth exactly 1 (the background) */
    OUTLINE_PIXEL,     /* a one-pixel feature */
    OUTLINE_BORDER,    /* features touching the border */
    OUTLINE_FOUR,      /* four features */
    OUTLINE_SIX        /* six features in two feature groups */
};

/* An outline row's set-up: the shape, an opaque occluder band drawn second (rows
 * size/3 .. size/2 at depth 0.1), the outlines stage's parameters (JSON object members). */
typedef struct conform_outline_params {
    enum conform_outline_shape shape;
    int occluder_band;
    const char *outlines;
} conform_outline_params;

/* One row outline:CASE: the feature buffers through the frame probe, the at=post passes
 * on the GPU against their emulation (every image a post pass writes, within
 * row->tolerance_abs + row->tolerance_rel |emu|), and what the case is about (flat depth
 * gives no outline, ...). */
void conform_outline_row(conform *c, const conform_row *row);

#endif
