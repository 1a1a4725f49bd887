/* frame.c's accessors of a halo_gl_frame, for the segmented drawing in segments.c
 * (which draws a host through the frame's images and passes). Internal. */
#ifndef HALO_GL_FRAME_H
#define HALO_GL_FRAME_H

#include "halo.h"

halo_gl *halo_gl_frame_runtime(const halo_gl_frame *fr);
const halo_program *halo_gl_frame_program(const halo_gl_frame *fr);
void halo_gl_frame_size(const halo_gl_frame *fr, int *width, int *height);
/* The ray-state texture: next 0, the one read by this segment; 1, the one it writes. */
unsigned halo_gl_frame_state(halo_gl_frame *fr, int next);
void halo_gl_frame_state_flip(halo_gl_frame *fr);
void halo_gl_frame_segments_reset(halo_gl_frame *fr);

#endif
