/* The figure3 family: Bruckner & Groller 2007, Fig. 3, as numbers (figure3.c). */
#ifndef HALO_FIGURE3_H
#define HALO_FIGURE3_H

#include "conform_harness.h"

#include <stdio.h>

/* Prints the table of halo intensities around features of several sizes for the four
 * strategies to out; ratios: the feature-preservation ratio of (b), (c), (e), (f).
 * Returns 0, or non-zero on failure (diagnostics in diag). */
int halo_figure3_run(const halo_library *lib, FILE *out, double ratios[4], halo_diagnostics *diag);
/* The row figure3: passes when (f) preserves small features better than (b). */
void conform_figure3_row(conform *c, const conform_row *row);

#endif
