/* The per-sample family of conformance rows (conform_sample.c). */
#ifndef HALO_CONFORM_SAMPLE_H
#define HALO_CONFORM_SAMPLE_H

#include "conform_harness.h"

/* The stage named row->name on the probe, within row's tolerance: its default
 * parameters, STAGE@exp0 and STAGE@exp64 (every exponent at 0 and 64, when it has
 * exponents) and STAGE@live (every parameter a uniform, arrays with several elements). */
void conform_sample_rows(conform *c, const conform_row *row);
/* The same for every per-sample stage of the library without a row of its own (a
 * stage added from a file), within row's (default) tolerance; an error row for a stage
 * without emulation. */
void conform_sample_other_rows(conform *c, const conform_row *row);

#endif
