/* A headless OpenGL context for tools and tests (not part of the installed libhalo).
 *
 * Kept internal on purpose (issue 15): libhalo runs in the host's own context through
 * the host's loader (halo_gl_desc.get_proc_address), so an application never needs
 * this; exporting it would tie libhalo.so to libEGL and libOSMesa (which Mesa 25.1
 * dropped) for every application, and its state is process-wide (one backend choice,
 * the loader of the context created last) and parses the tools' argv, which is no
 * library interface. The tools and tests link the static libhalo-headless.la; a host
 * without a window makes an EGL surfaceless context and passes eglGetProcAddress.
 *
 * Backends, each built when configure finds it: EGL (surfaceless, or a device of
 * EGL_EXT_platform_device: the route to GPUs and to Mesa >= 25.1, which has no
 * OSMesa) and OSMesa (OpenGL 4.5 core on llvmpipe, falling back to 3.3 core).
 *
 * The backend is chosen once per process: a tool's --backend option
 * (halo_headless_backend_option), else HALO_HEADLESS in the environment, else auto.
 *   egl     EGL only
 *   osmesa  OSMesa only
 *   auto    EGL when one of its devices reports a hardware renderer (not llvmpipe,
 *           softpipe or another software rasterizer), else OSMesa, else EGL's
 *           software renderer (surfaceless, then the devices)
 *   egl-es3.0, egl-es3.2
 *           EGL with an OpenGL ES 3.0 or 3.2 context (the WebGL 2 feature set is ES
 *           3.0): the tools link their shaders for GLSL ES 3.00 (halo_headless_es)
 * The context has no default framebuffer worth drawing to: render into framebuffer
 * objects.
 *
 * One context per process: halo_headless_get_proc_address resolves against the
 * backend of the context created last. */
#ifndef HALO_HEADLESS_H
#define HALO_HEADLESS_H

#include <stddef.h>

typedef struct halo_headless halo_headless;

typedef enum halo_headless_choice {
    HALO_HEADLESS_AUTO,
    HALO_HEADLESS_EGL,
    HALO_HEADLESS_OSMESA,
    HALO_HEADLESS_EGL_ES30,
    HALO_HEADLESS_EGL_ES32
} halo_headless_choice;

/* "egl", "osmesa", "auto", "egl-es3.0" or "egl-es3.2" to *choice; 0 for any other text. */
int halo_headless_parse_choice(const char *text, halo_headless_choice *choice);

/* A tool whose hosts draw on OpenGL ES calls this with 1 before taking --backend: the
 * egl-es3.0 and egl-es3.2 choices are refused otherwise (with a message). */
void halo_headless_allow_es(int allowed);

/* The tools' --backend option, one implementation for all of them: removes every
 * "--backend B" and "--backend=B" from argv (updating *argc) and makes B the
 * process's choice. Returns 1, or 0 with a message in err (errlen bytes) when B is
 * missing or not egl, osmesa or auto, or names a backend this build does not have.
 * Call it before the tool parses its other options. */
int halo_headless_backend_option(int *argc, char **argv, char *err, size_t errlen);

/* The same for a tool's main: on failure prints "PROGRAM: error: MESSAGE" on stderr
 * and returns 0 (the tool exits 2, a usage error). */
int halo_headless_take_backend_option(int *argc, char **argv, const char *program);

/* The backends this build has: "egl, osmesa", "osmesa", ... */
const char *halo_headless_built_backends(void);

/* Creates a context of the process's choice and makes it current. Returns NULL with
 * a message in err (errlen bytes, may be 0) that starts "no headless OpenGL context"
 * when no backend allowed by the choice could create one. */
halo_headless *halo_headless_create(int width, int height, char *err, size_t errlen);
void halo_headless_destroy(halo_headless *h);
/* The loader to pass to halo_gl_create / halo_glfuncs_load. */
void *halo_headless_get_proc_address(const char *name);
/* The entry points of the current context (the public halo_gl_loader.h's table, loaded
 * through halo_headless_get_proc_address): what the tools call GL through. NULL when a
 * required one is missing. */
struct halo_glfuncs;
const struct halo_glfuncs *halo_headless_functions(void);
/* GL_RENDERER of the context ("llvmpipe (LLVM 15.0.6, 256 bits)"). */
const char *halo_headless_renderer(halo_headless *h);
/* "osmesa" or "egl". */
const char *halo_headless_backend(halo_headless *h);
/* 30 or 32 when the process's choice (--backend, HALO_HEADLESS) is an OpenGL ES 3.0 or
 * 3.2 context, else 0: what a tool needs to know before it creates the context. */
int halo_headless_choice_es(void);
/* 30 or 32 for an OpenGL ES 3.0 or 3.2 context, 0 for desktop OpenGL. */
int halo_headless_es(const halo_headless *h);

#endif
