/* Conformance rows for the line stages (Everts et al. 2009, docs/lines.md): GPU against
 * the C emulation on controlled strips and fragments, degenerate inputs, and the
 * depth-gap image test. */
#ifndef HALO_CONFORM_LINES_H
#define HALO_CONFORM_LINES_H

/* Prints one row per test in halo-validate conform's format (stage max_abs rmse
 * over_tol nonfinite tolerance PASS|FAIL) to stdout, details to stderr with verbose.
 * Needs a current headless context (libhalo/gl/headless.h). Returns the number of rows
 * printed and adds the failed ones to *failed. */
int halo_conform_line_rows(int verbose, int *failed);
/* The same for the rows named `only` (a row name or a stage: "line_halo" selects every
 * line_halo row); NULL: all. */
int halo_conform_line_rows_select(const char *only, int verbose, int *failed);

#include "conform_harness.h"

/* The row row->name of the rows above when --stage selects it (a row name or its stage,
 * e.g. line_halo), in halo-validate conform's context. */
void conform_lines_row(conform *c, const conform_row *row);

#endif
