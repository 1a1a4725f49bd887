/* The registry of conformance rows (conform_rows.c). */
#ifndef HALO_CONFORM_ROWS_H
#define HALO_CONFORM_ROWS_H

#include "conform_harness.h"

extern const conform_row conform_rows[];
extern const size_t conform_row_count;

#endif
