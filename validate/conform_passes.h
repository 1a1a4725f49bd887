/* The pass family of conformance rows (conform_passes.c). */
#ifndef HALO_CONFORM_PASSES_H
#define HALO_CONFORM_PASSES_H

#include "conform_harness.h"

/* A pass row's set-up. */
typedef struct conform_pass_params {
    const char *generate;   /* halo_generate's parameters (JSON object) */
    const char *compare[3]; /* images compared after the generation(s) */
    int generations;        /* 2: a second generation on the next case, in the same frame */
    int scale;              /* halo_link_desc.image_scale: the pass images at 1/scale (0: 1) */
} conform_pass_params;

/* halo_generate's passes on the seed cases (empty, full, one pixel, border, discs,
 * noise): every image of params->compare within row->tolerance_abs. */
void conform_pass_row(conform *c, const conform_row *row);

/* Every image-pass stage not in row->params (a NULL-terminated list of the stages with
 * families of their own), alone: the images no pass writes filled with noise, every image
 * its passes write against the emulation within tolerance_abs + tolerance_rel |emu|. */
void conform_image_other_rows(conform *c, const conform_row *row);

#endif
