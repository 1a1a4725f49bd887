/* Conformance rows of the outline passes (glsl/outline/outlines.glsl, docs/outlines.md):
 * feature buffers drawn through the frame probe, then the at=post passes on the GPU
 * (halo_gl_frame_post) against their emulation (halo_emu_frame_post). */
#ifndef HALO_CONFORM_OUTLINE_H
#define HALO_CONFORM_OUTLINE_H

#include "conform_internal.h"

/* Prints the rows outline:CASE (hard cases: flat depth, depth exactly 1, one-pixel
 * feature, feature on the border, sigma beyond the image, normals of no hit, occlusion
 * styles, depth enhancements, four features) in conform's format; probe_source: the
 * probe host's fragment source. Rows and failures go to c->rows, c->failures. */
void halo_conform_outline_rows(conform *c, const char *probe_source);

#endif
