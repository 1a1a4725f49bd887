/* The frame family of conformance rows (conform_frame.c). */
#ifndef HALO_CONFORM_FRAME_H
#define HALO_CONFORM_FRAME_H

#include "conform_harness.h"

/* A frame row's scene: JSON (NULL: the stage alone with its defaults), and whether
 * every parameter is live. */
typedef struct conform_frame_params {
    const char *scene;
    int live;
} conform_frame_params;

/* The stage of row->name (up to '@') drawn through a GL frame against the emulated
 * frame, within row's tolerance; row->params: a conform_frame_params, or NULL. */
void conform_frame_row(conform *c, const conform_row *row);
/* Every stage with outputs, images or host uniforms that has no row of its own: its
 * defaults and @live, within row's (default) tolerance. */
void conform_frame_other_rows(conform *c, const conform_row *row);

#endif
