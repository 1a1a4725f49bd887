/* Internal: the GL runtime's entry-point table (the public halo_gl_loader.h: the table
 * and its loader, which the example hosts use too), and the table of a runtime. Nothing
 * in libhalo links against libGL directly; every call goes through a halo_glfuncs table. */
#ifndef HALO_GLFUNCS_H
#define HALO_GLFUNCS_H

#include "halo_gl_loader.h"

/* The table of a GL runtime (runtime.c), for library code that issues its own calls. */
struct halo_gl;
const halo_glfuncs *halo_gl_functions(const struct halo_gl *gl);

#endif
