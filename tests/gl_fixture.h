/* The set-up of the test programs that draw through a headless OpenGL context
 * (tests/examples/hosts, tests/libhalo/gl): diagnostics, libhalo's setup, the context,
 * a library, the GL runtime and, when asked, the built-in volume. Each program includes
 * it once; gl_fixture_close releases what gl_fixture_open made. */
#ifndef HALO_TEST_GL_FIXTURE_H
#define HALO_TEST_GL_FIXTURE_H

#include "halo.h"
#include "gl/glfuncs.h"
#include "gl/headless.h"
#include "volume.h"

#include <stdio.h>
#include <stdlib.h>

typedef struct gl_fixture {
    halo_diagnostics *diag;
    halo_headless *context;
    halo_library *lib;
    halo_gl *runtime;
    const halo_glfuncs *gl;
    float *volume; /* halo_volume_create(volume_size); NULL for volume_size 0 */
} gl_fixture;

/* Sets f up with a side x side context. Returns 0, else the test's exit status: 77
 * without an OpenGL context (said on stdout), 99 for a broken setup (the diagnostics on
 * stderr). */
static inline int gl_fixture_open(gl_fixture *f, int side, int volume_size)
{
    char err[512];
    *f = (gl_fixture){0};
    f->diag = halo_diagnostics_create();
    if (!f->diag || halo_setup(NULL) != HALO_OK)
        return 99;
    f->context = halo_headless_create(side, side, err, sizeof err);
    if (!f->context) {
        printf("no OpenGL context (%s): skipping\n", err);
        halo_shutdown();
        halo_diagnostics_destroy(f->diag);
        return 77;
    }
    f->lib = halo_library_create(f->diag);
    f->runtime = halo_gl_create(&(halo_gl_desc){.get_proc_address = halo_headless_get_proc_address}, f->diag);
    f->volume = volume_size ? halo_volume_create(volume_size) : NULL;
    if (!f->lib || !f->runtime || (volume_size && !f->volume)) {
        halo_diagnostics_print(f->diag, stderr);
        return 99;
    }
    f->gl = halo_gl_functions(f->runtime);
    return 0;
}

static inline void gl_fixture_close(gl_fixture *f)
{
    free(f->volume);
    halo_gl_destroy(f->runtime);
    halo_library_destroy(f->lib);
    halo_headless_destroy(f->context);
    halo_diagnostics_destroy(f->diag);
    halo_shutdown();
}

#endif
