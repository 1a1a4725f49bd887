/* A headless OpenGL context for tools and tests (not part of the installed libhalo).
 *
 * Backends: OSMesa (OpenGL 4.5 core on llvmpipe, falling back to 3.3 core) and,
 * when built with HALO_HAVE_EGL, EGL surfaceless. The default order is OSMesa,
 * then EGL; HALO_HEADLESS=egl in the environment tries EGL first, HALO_HEADLESS=osmesa
 * uses OSMesa only. The context has no default framebuffer worth drawing to: render
 * into framebuffer objects.
 *
 * One context per process: halo_headless_get_proc_address resolves against the
 * backend of the context created last. */
#ifndef HALO_HEADLESS_H
#define HALO_HEADLESS_H

#include <stddef.h>

typedef struct halo_headless halo_headless;

/* Creates a context and makes it current. Returns NULL with a message in err
 * (errlen bytes, may be 0) when no backend could create one. */
halo_headless *halo_headless_create(int width, int height, char *err, size_t errlen);
void halo_headless_destroy(halo_headless *h);
/* The loader to pass to halo_gl_create / halo_glfuncs_load. */
void *halo_headless_get_proc_address(const char *name);
/* GL_RENDERER of the context ("llvmpipe (LLVM 15.0.6, 256 bits)"). */
const char *halo_headless_renderer(halo_headless *h);
/* "osmesa" or "egl". */
const char *halo_headless_backend(halo_headless *h);

#endif
