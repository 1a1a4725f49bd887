/* The figure3 family: Bruckner & Groller 2007, Fig. 3, as numbers (figure3.c). */
#ifndef HALO_FIGURE3_H
#define HALO_FIGURE3_H

#include "conform_harness.h"

#include <stdio.h>

/* Prints the table of halo intensities around features of several sizes for the four
 * strategies to out; ratios: the feature-preservation ratio of (b), (c), (e), (f).
 * Returns 0, or non-zero on failure (diagnostics in diag). */
int halo_figure3_run(const halo_library *lib, FILE *out, double ratios[4], halo_diagnostics *diag);
/* The approximation wide on the halo field itself: one generation (delta 0.8) over the
 * figure's seed image, wide N = 2 against exact N = 4 (the same reach, 15 px), emulated in
 * double precision. weaker_*: 1 - (wide / exact) of the ring means 2..6 px outside each
 * feature (a single pixel to radius 32), the smallest and the largest. */
typedef struct halo_figure3_wide_error {
    int size; /* the seed image's side */
    double max_abs, rmse;
    double exact_at_max, wide_at_max; /* the two fields where they differ most */
    double weaker_min, weaker_max;
} halo_figure3_wide_error;
/* Returns 0, or -1 (diagnostics in diag). */
int halo_figure3_wide(const halo_library *lib, halo_figure3_wide_error *e, halo_diagnostics *diag);
/* The row figure3: passes when (f) preserves small features better than (b). */
void conform_figure3_row(conform *c, const conform_row *row);

#endif
